"""The contract: what a rasterizer receives (scenes), returns (coverage) and declares
(conventions, sample patterns, coverage models), and the case records that carry scenes to
the checks."""
