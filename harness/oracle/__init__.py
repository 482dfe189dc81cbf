"""The exact oracles: what a declared convention says a scene must cover, for triangles, paths
(winding numbers), aliased lines and area coverage, with a slow rational reference to check
them against."""
