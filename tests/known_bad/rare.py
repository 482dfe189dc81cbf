"""A held-out rare bug: a rasterizer right everywhere but on one slope.

:class:`RareSlopeTie` is the exact oracle of the D3D convention (pixel centres, top-left
ties, no snapping) with one bug: an edge whose slope is exactly 3/4 (dy/dx, y down -- the
hypotenuse of a 3-4-5 triangle) owns the samples lying exactly on it the wrong way round
(as if a table of edge steppers for small rational slopes had that one entry's tie bias
flipped). Only samples strictly inside such an edge change: a triangle must have an edge
of that exact slope *and* a pixel centre exactly on it.

Over the fuzz families' triangles (:mod:`cases.fuzz`) that is about 1 triangle in 3400
(34 of 114 661 triangles in the first 800 scenes of each triangle family, all but two in
the ``lattice`` family); the quick suite's 5449 triangles hold none
(tests/diagnose/test_signatures.py proves that the quick suite passes it, and a campaign finds it).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage

__all__ = ["RareSlopeTie", "SLOPE", "flipped_samples"]

# the slope dy/dx whose ties are owned the wrong way round
SLOPE = Fraction(3, 4)


def flipped_samples(scene: Scene) -> list[tuple[int, int, int]]:
    """(triangle, x, y) of every pixel centre lying exactly inside (not at an end of) an
    edge of slope exactly :data:`SLOPE` of a finite triangle of nonzero area, inside the
    viewport -- decided in rational arithmetic."""
    p = scene.positions
    with np.errstate(all="ignore"):
        b = p[:, [1, 2, 0]]
        dx, dy = b[..., 0] - p[..., 0], b[..., 1] - p[..., 1]
        # a float screen (differences may round): the rationals below decide
        candidates = np.isfinite(dx) & np.isfinite(dy) & (dx != 0) & (dy * SLOPE.denominator == dx * SLOPE.numerator)
    candidates &= (orientation(p) != 0)[:, None]
    out = []
    for t, k in zip(*np.nonzero(candidates)):
        ax, ay = Fraction(float(p[t, k, 0])), Fraction(float(p[t, k, 1]))
        bx, by = Fraction(float(b[t, k, 0])), Fraction(float(b[t, k, 1]))
        if by == ay or (by - ay) / (bx - ax) != SLOPE:
            continue
        low, high = min(ay, by), max(ay, by)
        for j in range(max(0, math.floor(low)), min(scene.height - 1, math.ceil(high)) + 1):
            y = j + Fraction(1, 2)
            if not low < y < high:
                continue
            i = ax + (y - ay) / SLOPE - Fraction(1, 2)  # the column whose centre the edge crosses on this row
            if i.denominator == 1 and 0 <= i < scene.width:
                out.append((int(t), int(i), j))
    return out


class RareSlopeTie:
    """Exact (pixel centres, top-left ties), but for samples exactly on an edge of slope
    exactly 3/4, whose ownership is flipped: drawn where the rule leaves them, left where it
    draws them. Coverage only."""

    name = "bad_rare_slope_tie"
    convention = Convention()
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        right = exact_coverage(Scene(scene.width, scene.height, scene.positions), self.convention)
        flips = flipped_samples(scene)
        if not flips:
            return Coverage(right.triangle, right.y, right.x0, right.x1)
        tri, x, y = right.pixels()
        keys = set(zip(tri.tolist(), x.tolist(), y.tolist()))
        keys ^= set(flips)  # each flipped sample: added when the rule leaves it, removed when it draws it
        if not keys:
            return Coverage.empty()
        t, xs, ys = (np.array(v, dtype=np.int64) for v in zip(*sorted(keys)))
        return Coverage.from_pixels(t, xs, ys)
