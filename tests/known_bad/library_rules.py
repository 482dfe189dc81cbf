"""Known-bad rasterizers of the rules read from libraries' sources (issue 33): each breaks
its declared rule exactly where the rule decides (a cover met exactly, a crossing's end)."""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.library_rules import agg_covers, cover_min, inclusive_scanline_coverage
from tests.known_bad import coverage_from_parts

__all__ = ["Float32AggCover", "ExclusiveRightScanline"]


class Float32AggCover:
    """Declares AGG's aliased rule (cover >= 128 of 256, aggdraw) but decides it as a float32
    alpha against the threshold, ``float32(cover / 256) > float32(0.5)``: the exact tie, cover
    128 (a pixel covered exactly half, as on every lattice half pixel), is left out."""

    name = "bad_float32_agg_cover"
    convention = Convention(coverage="agg-cover", input="fixed8-toward-zero")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        positions = self.convention.snap(scene.positions)
        threshold = np.float32(cover_min(self.convention.threshold) / 256)
        tris, xs, ys = [], [], []
        for k, p in enumerate(positions):
            if not np.all(np.isfinite(p)):
                continue
            alpha = (agg_covers(p, scene.width, scene.height) / 256).astype(np.float32)
            yy, xx = np.nonzero(alpha > threshold)
            tris.append(np.full(xx.size, k))
            xs.append(xx)
            ys.append(yy)
        return coverage_from_parts(tris, xs, ys)


class ExclusiveRightScanline:
    """Declares pygame's inclusive scanline fill but leaves each row's right end out (the
    half-open span of a sampling rasterizer): every row one pixel short on the right."""

    name = "bad_exclusive_right_scanline"
    convention = Convention(coverage="inclusive-scanline", input="integer-toward-zero")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        spans = inclusive_scanline_coverage(scene, self.convention)
        keep = spans.x1 - 1 > spans.x0
        return Coverage(spans.triangle[keep], spans.y[keep], spans.x0[keep], spans.x1[keep] - 1)
