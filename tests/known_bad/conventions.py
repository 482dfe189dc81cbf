"""Known-bad rasterizers that are right about some convention, but not the one they
declare (a y-first tie rule, half-away snapping), or that give up on huge coordinates."""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from rasterizers.fixed_point import FixedPoint

__all__ = ["YFirstClaimsXFirst", "HalfAwayClaimsNearestEven", "DropsHuge"]


class YFirstClaimsXFirst:
    """Fixed point with the y-first top-left rule (piglit's "left_bottom" as written in
    its own reference rasterizer) declared as the x-first top-left rule: the two part
    only on samples exactly on slanted edges."""

    name = "bad_y_first_tie"
    convention = Convention(tie="top-left", subpixel_bits=8)

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(8, tie="top-left-y-first").rasterize(scene)


class HalfAwayClaimsNearestEven:
    """Fixed point at 4 bits rounding half away from zero (dEQP's ``toSubpixelCoord``)
    declared as rounding half to even: the two part only on vertices exactly on a half
    step of the 1/16 px grid."""

    name = "bad_half_away_snapping"
    convention = Convention(subpixel_bits=4)

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(4, snap_rounding="half-away").rasterize(scene)


class DropsHuge:
    """Exact, but silently draws nothing for a triangle with a coordinate beyond 1e15
    (where a float rasterizer gives up) instead of refusing it."""

    name = "bad_drops_huge"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        with np.errstate(invalid="ignore"):
            huge = np.any(np.abs(scene.positions) > 1e15, axis=(1, 2))
        kept = np.where(huge[:, None, None], np.nan, scene.positions)
        return exact_coverage(Scene(scene.width, scene.height, kept, scene.attributes, scene.w), self.convention)
