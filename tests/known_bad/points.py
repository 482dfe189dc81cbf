"""Known-bad point drawers: point sprites with one classic bug each.

Each takes point scenes only and claims D3D11's convention (pixel centres, top-left ties,
no snapping), and is :class:`rasterizers.points.PointSprites` but for its bug. Test doubles:
numpy per point, not fast.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.kinds.points import PointScene
from rasterizers.points import PointSprites

__all__ = ["ClosedSquares", "OwnsTheOtherSides", "Float32Sides", "RoundedCentres", "DropsTheLast", "POINT_BADS"]


def _spans(scene: PointScene, x0: np.ndarray, x1: np.ndarray, y0: np.ndarray, y1: np.ndarray) -> Coverage:
    """Per point the pixels ``x0 <= x < x1``, ``y0 <= y < y1`` (clipped): one span per row."""
    x0, x1 = np.clip(x0, 0, scene.width), np.clip(x1, 0, scene.width)
    y0, y1 = np.clip(y0, 0, scene.height), np.clip(y1, 0, scene.height)
    return Coverage.from_boxes(x0, x1, y0, y1)


def _finite(scene: PointScene) -> np.ndarray:
    """The points these doubles draw: finite and within 2**24 px (the rest cover nothing)."""
    with np.errstate(invalid="ignore"):
        finite = cast(np.ndarray, np.isfinite(scene.vertices).all(axis=1) & (np.abs(scene.vertices) < 2.0**24).all(axis=1))
    return finite


class ClosedSquares(PointSprites):
    """Owns all four sides (``<=`` on both): size-1 points tiling a block double-hit every
    sample their sides pass through."""

    name = "bad_points_closed_squares"

    def rasterize(self, scene: PointScene) -> Coverage:
        keep = _finite(scene)
        c = np.where(keep[:, None], scene.vertices, -1e9)
        half = scene.point_size / 2
        # first index with i + 0.5 >= p - s/2, last with i + 0.5 <= p + s/2 (exact on the lattice cases)
        low, high = np.ceil(c - half - 0.5), np.floor(c + half - 0.5) + 1
        low, high = low.astype(np.int64), high.astype(np.int64)
        return _spans(scene, low[:, 0], high[:, 0], low[:, 1], high[:, 1])


class OwnsTheOtherSides(PointSprites):
    """Claims top-left but owns the right and bottom sides (a y-up framebuffer's rule read in
    y-down, and x flipped): still a partition (watertight passes), not the declared one."""

    name = "bad_points_other_sides"

    def rasterize(self, scene: PointScene) -> Coverage:
        return PointSprites(Convention(tie="bottom-right")).rasterize(scene)


class Float32Sides(PointSprites):
    """Computes the square's sides in float32 (a GPU's vertex arithmetic) and decides there:
    right on the lattice, wrong a micro-pixel from a tie."""

    name = "bad_points_float32_sides"

    def rasterize(self, scene: PointScene) -> Coverage:
        keep = _finite(scene)
        c = np.where(keep[:, None], scene.vertices, -1e9).astype(np.float32)
        half = np.float32(scene.point_size / 2)
        low = np.ceil((c - half) - np.float32(0.5)).astype(np.int64)  # i + 0.5 >= p - s/2
        high = np.ceil((c + half) - np.float32(0.5)).astype(np.int64)  # i + 0.5 < p + s/2
        return _spans(scene, low[:, 0], high[:, 0], low[:, 1], high[:, 1])


class RoundedCentres(PointSprites):
    """Rounds each centre to the nearest pixel corner first (fixed-point without a
    fraction): right for centres on corners, wrong elsewhere."""

    name = "bad_points_rounded_centres"

    def rasterize(self, scene: PointScene) -> Coverage:
        return super().rasterize(scene.with_coordinates(np.round(scene.vertices)))


POINT_BADS: tuple[type, ...] = (ClosedSquares, OwnsTheOtherSides, Float32Sides, RoundedCentres)


class DropsTheLast(PointSprites):
    """Stops one point short (``range(n - 1)``): the last point listed is never drawn, so
    listing the points in another order drops another one."""

    name = "bad_points_drops_the_last"

    def rasterize(self, scene: PointScene) -> Coverage:
        drawn = super().rasterize(scene)
        return drawn.take(np.flatnonzero(drawn.primitive != len(scene) - 1))


POINT_BADS = (*POINT_BADS, DropsTheLast)
