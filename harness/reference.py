"""A slow, obviously correct reference for the oracle: every pixel, rational arithmetic.

For each triangle and each pixel of its bounding box (clipped to the viewport) the sample
point is tested against the three edges with :class:`fractions.Fraction`. Edges are
classified straight from the definitions in :mod:`harness.conventions` -- where the third
vertex lies -- independently of how the oracle classifies them. Use it on small scenes.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from harness.api import Coverage, Scene
from harness.conventions import Convention

__all__ = ["brute_force_coverage"]


def _edge_kind(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], c: tuple[Fraction, Fraction]) -> str:
    """'top', 'bottom', 'left' or 'right' for edge a-b of triangle abc."""
    if a[1] == b[1]:
        return "top" if c[1] > a[1] else "bottom"
    # The edge's x at the third vertex's height; the interior is on the third vertex's side.
    x_on_edge = a[0] + (b[0] - a[0]) * (c[1] - a[1]) / (b[1] - a[1])
    return "left" if c[0] > x_on_edge else "right"


def _side(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], p: tuple[Fraction, Fraction]) -> Fraction:
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])


def brute_force_coverage(scene: Scene, convention: Convention) -> Coverage:
    """Coverage by testing every pixel of every triangle's bounding box exactly.

    Parameters
    ----------
    scene : Scene
        Keep it small: the cost is one rational test per pixel of each bounding box.
    convention : Convention

    Returns
    -------
    Coverage
        Without attributes.
    """
    positions = convention.snap(scene.positions)
    sx, sy = (Fraction(s) for s in convention.sample)
    vertical_owner = "top" if convention.owns_top else "bottom"
    side_owner = "left" if convention.owns_left else "right"
    tri, xs, ys = [], [], []
    for t in range(len(scene)):
        p = positions[t]
        if not np.all(np.isfinite(p)):
            continue
        v = [(Fraction(p[k, 0]), Fraction(p[k, 1])) for k in range(3)]
        area = _side(v[0], v[1], v[2])
        if area == 0:
            continue
        if convention.cull == "cw" and area > 0 or convention.cull == "ccw" and area < 0:
            continue
        edges = [(v[k], v[(k + 1) % 3], v[(k + 2) % 3]) for k in range(3)]
        owned = [_edge_kind(a, b, c) in (vertical_owner, side_owner) for a, b, c in edges]
        sign = 1 if area > 0 else -1
        x_lo = max(0, math.floor(min(q[0] for q in v) - sx))
        x_hi = min(scene.width - 1, math.ceil(max(q[0] for q in v) - sx))
        y_lo = max(0, math.floor(min(q[1] for q in v) - sy))
        y_hi = min(scene.height - 1, math.ceil(max(q[1] for q in v) - sy))
        for j in range(y_lo, y_hi + 1):
            for i in range(x_lo, x_hi + 1):
                sample = (i + sx, j + sy)
                inside = True
                for (a, b, _), own in zip(edges, owned):
                    e = sign * _side(a, b, sample)
                    if e < 0 or (e == 0 and not own):
                        inside = False
                        break
                if inside:
                    tri.append(t)
                    xs.append(i)
                    ys.append(j)
    return Coverage.from_pixels(np.array(tri, dtype=np.int64), np.array(xs, dtype=np.int64), np.array(ys, dtype=np.int64))
