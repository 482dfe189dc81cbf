"""A slow, obviously correct reference for the oracle: every pixel, rational arithmetic.

For each triangle and each pixel of its bounding box (clipped to the viewport) the sample
point is tested against the three edges in exact rational arithmetic (the dyadic
coordinates scaled by their common denominator to Python integers). Ties are decided
straight from the definition in :mod:`harness.contract.conventions` -- the sample moved by the tie
rule's symbolic perturbation, E(p + d(eps)) expanded as a polynomial in eps whose first
nonzero coefficient gives the sign -- independently of how the oracle classifies edges.
Use it on small scenes.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene

__all__ = ["brute_force_coverage"]


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
    # input precision, then snapping: Convention.snap applies both, first, exactly
    positions = convention.snap(scene.positions)
    sx, sy = (Fraction(s) for s in convention.sample)
    tie_x, tie_y, y_first = convention.tie_perturbation
    # d(eps) = (tie_x*eps, tie_y*eps**2), or (tie_x*eps**2, tie_y*eps) when y_first
    move_x, move_y = ((0, tie_x, 0), (0, 0, tie_y)) if not y_first else ((0, 0, tie_x), (0, tie_y, 0))
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
        sign = 1 if area > 0 else -1
        # every number here is dyadic: scaled by the common denominator, the same tests in integers
        scale = math.lcm(sx.denominator, sy.denominator, *(c.denominator for q in v for c in q))
        w = [(int(q[0] * scale), int(q[1] * scale)) for q in v]
        edges = []
        for k in range(3):
            a, b = w[k], w[(k + 1) % 3]
            # E(p + d) = E(p) + dE/dx * d_x + dE/dy * d_y, as coefficients of 1, eps, eps**2: the
            # coefficients of eps and eps**2 do not depend on p; the first nonzero one decides E(p) = 0
            gx, gy = -(b[1] - a[1]), b[0] - a[0]
            ties = [sign * (gx * move_x[power] + gy * move_y[power]) for power in (1, 2)]
            edges.append((a, b, next((c for c in ties if c != 0), 0) > 0))
        x_lo = max(0, math.floor(min(q[0] for q in v) - sx))
        x_hi = min(scene.width - 1, math.ceil(max(q[0] for q in v) - sx))
        y_lo = max(0, math.floor(min(q[1] for q in v) - sy))
        y_hi = min(scene.height - 1, math.ceil(max(q[1] for q in v) - sy))
        for j in range(y_lo, y_hi + 1):
            py = j * scale + int(sy * scale)
            for i in range(x_lo, x_hi + 1):
                px = i * scale + int(sx * scale)
                inside = True
                for a, b, tie_owned in edges:
                    e = sign * ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]))
                    if e < 0 or e == 0 and not tie_owned:
                        inside = False
                        break
                if inside:
                    tri.append(t)
                    xs.append(i)
                    ys.append(j)
    return Coverage.from_pixels(np.array(tri, dtype=np.int64), np.array(xs, dtype=np.int64), np.array(ys, dtype=np.int64))
