"""identify: fingerprint a black-box rasterizer's convention from outside, by small experiments
(probes) on triangles, coverage beyond one sample, lines and paths."""
