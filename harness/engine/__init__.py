"""The engine: finding rasterizers, running each call in an isolated worker, one Session per
loaded rasterizer, and the runner over a suite."""
