"""The ``closed`` coverage rule's exact oracle: a sample exactly on an edge is inside, for
every triangle sharing that edge (FreeType's monochrome rasterizer, ``ftraster.c``: its
spans run ``CEILING(x1) .. FLOOR(x2)``, both ends included).

A (triangle, pixel) is covered iff the pixel's sample point (i + sx, j + sy) lies in the
closed (snapped) triangle: on the inner side of every edge or on it, by exact orientation
signs (:func:`harness.geometry.exact.orient2d_sign`; rational beyond its safe range).

Zero-area triangles: the closed triangle is then the segment (or point) its vertices span,
and it covers the samples lying exactly on that segment (a triangle collapsed to one point
has no edge and covers nothing, as in ftraster.c, where it makes no profile). That is the closed rule read
literally, and it is what ``ftraster.c`` does with dropout control off
(``FT_OUTLINE_IGNORE_DROPOUTS``, mode 2): a zero-area outline's up and down profiles cross
each scanline at the same x, and ``Vertical_Sweep_Span`` draws ``CEILING(x) .. FLOOR(x)``,
one pixel when x is a pixel centre and none otherwise; mode 2 never reaches
``Vertical_Sweep_Drop``. So FreeType's pixels for zero-area triangles with dropouts off
are the closed rule's, not dropouts (with dropout control on, the dropout pixels come on
top: :mod:`harness.oracle.dropout`). Culling removes a triangle of the culled orientation;
a zero-area triangle has none and is never culled. Non-finite triangles cover nothing.

The per-pixel work is compiled (numba, cached); triangles beyond the expansions' safe
range take the same steps in rationals. :func:`closed_reference` is the slow reference in
:class:`fractions.Fraction` for tests.

>>> from harness.contract.conventions import Convention
>>> from harness.contract.scenes import Scene
>>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]], [[4, 0], [4, 4], [0, 4]]])
>>> closed_coverage(scene, Convention(coverage="closed")).counts(4, 4).tolist()  # the shared diagonal's 4 centres twice
[[1, 1, 1, 2], [1, 1, 2, 1], [1, 2, 1, 1], [2, 1, 1, 1]]
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orient2d_sign, orientation

__all__ = ["closed_coverage", "closed_reference", "closed_positions"]


def closed_positions(scene: Scene, convention: Convention) -> tuple[NDArray[np.float64], NDArray[np.int8],
                                                                      NDArray[np.bool_], NDArray[np.bool_]]:
    """(snapped positions, exact orientation sign, drawn, within the safe range): drawn
    is finite and not culled (zero-area triangles are drawn: they have no facing)."""
    positions = np.ascontiguousarray(convention.snap(scene.positions))
    safe = np.empty(positions.shape[0], dtype=np.bool_)
    sign = orientation(positions, safe).copy()
    with np.errstate(invalid="ignore"):
        drawn = np.asarray(np.isfinite(positions).all(axis=(1, 2)), dtype=np.bool_)
    if convention.cull != "none":
        drawn &= sign != (1 if convention.cull == "cw" else -1)
    return positions, sign, drawn, safe


@numba.njit(cache=True)
def _inside_closed(p, s, x, y):  # type: ignore[no-untyped-def]
    """Whether (x, y) lies in the closed triangle p of orientation s (0: the segment or
    point the collinear vertices span)."""
    if s != 0:
        for k in range(3):  # noqa: SIM110 (numba: no all() over a generator)
            if orient2d_sign(p[k, 0], p[k, 1], p[(k + 1) % 3, 0], p[(k + 1) % 3, 1], x, y) * s < 0:
                return False
        return True
    if x < min(p[0, 0], p[1, 0], p[2, 0]) or x > max(p[0, 0], p[1, 0], p[2, 0]):
        return False
    if y < min(p[0, 1], p[1, 1], p[2, 1]) or y > max(p[0, 1], p[1, 1], p[2, 1]):
        return False
    # collinear vertices: on their hull iff in its box and on the line through two distinct ones
    for k in range(3):
        a, b = k, (k + 1) % 3
        if p[a, 0] != p[b, 0] or p[a, 1] != p[b, 1]:
            return orient2d_sign(p[a, 0], p[a, 1], p[b, 0], p[b, 1], x, y) == 0
    return False  # all three vertices one point: no edge, nothing drawn (as ftraster.c: no profile)


@numba.njit(cache=True)
def _closed_kernel(positions, sign, use, sx, sy, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """One span per row of each triangle marked ``use`` (a closed convex set meets a row of
    samples in one run)."""
    n = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        p = positions[t]
        s = sign[t]
        xmin, xmax = min(p[0, 0], p[1, 0], p[2, 0]), max(p[0, 0], p[1, 0], p[2, 0])
        ymin, ymax = min(p[0, 1], p[1, 1], p[2, 1]), max(p[0, 1], p[1, 1], p[2, 1])
        # samples i + sx in [xmin, xmax]; the bounds clamped before converting (no overflow)
        i0 = max(int(math.ceil(max(xmin - sx, -2.0))), 0)
        i1 = min(int(math.floor(min(xmax - sx, width + 2.0))), width - 1)
        j0 = max(int(math.ceil(max(ymin - sy, -2.0))), 0)
        j1 = min(int(math.floor(min(ymax - sy, height + 2.0))), height - 1)
        for j in range(j0, j1 + 1):
            first = -1
            last = -1
            for i in range(i0, i1 + 1):
                if _inside_closed(p, s, i + sx, j + sy):
                    if first < 0:
                        first = i
                    last = i
            if first >= 0:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = first
                out_x1[n] = last + 1
                n += 1
    return n


def _fraction_inside(p: list[tuple[Fraction, Fraction]], x: Fraction, y: Fraction) -> bool:
    """The definition in rationals: (x, y) in the convex hull of the three points."""
    def e(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction]) -> Fraction:
        return (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])

    s = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])
    if s != 0:
        return all(e(p[k], p[(k + 1) % 3]) * s >= 0 for k in range(3))
    xs, ys = [v[0] for v in p], [v[1] for v in p]
    if not (min(xs) <= x <= max(xs) and min(ys) <= y <= max(ys)):
        return False
    distinct = [(a, b) for a, b in ((p[0], p[1]), (p[1], p[2]), (p[2], p[0])) if a != b]
    return bool(distinct) and e(*distinct[0]) == 0


def _rows(triangles: NDArray[np.int64], pixels: list[tuple[int, int, int]]) -> Coverage:
    if not pixels:
        return Coverage.empty()
    e = np.array(sorted(pixels), dtype=np.int64)
    t, y, x = e[:, 0], e[:, 1], e[:, 2]
    new = np.ones(t.size, dtype=bool)
    new[1:] = (t[1:] != t[:-1]) | (y[1:] != y[:-1]) | (x[1:] != x[:-1] + 1)
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], t.size)
    return Coverage(t[starts], y[starts], x[starts], x[ends - 1] + 1)


def _rational_pixels(triangle: NDArray[np.float64], scene: Scene, sx: float, sy: float) -> list[tuple[int, int]]:
    p = [(Fraction(float(x)), Fraction(float(y))) for x, y in triangle]
    xs, ys = [v[0] for v in p], [v[1] for v in p]
    fx, fy = Fraction(sx), Fraction(sy)
    i0, i1 = max(math.ceil(min(xs) - fx), 0), min(math.floor(max(xs) - fx), scene.width - 1)
    j0, j1 = max(math.ceil(min(ys) - fy), 0), min(math.floor(max(ys) - fy), scene.height - 1)
    return [(j, i) for j in range(j0, j1 + 1) for i in range(i0, i1 + 1) if _fraction_inside(p, i + fx, j + fy)]


def closed_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="closed"`` (module docstring):
    every pixel whose sample point lies in the closed (snapped) triangle."""
    positions, sign, drawn, safe = closed_positions(scene, convention)
    use = drawn & safe
    sx, sy = convention.sample
    with np.errstate(invalid="ignore"):
        ys = positions[:, :, 1]
        lo = np.clip(np.floor(np.where(use, ys.min(axis=1), 0.0)) - 1, 0, scene.height)
        hi = np.clip(np.ceil(np.where(use, ys.max(axis=1), 0.0)) + 1, 0, scene.height)
    capacity = int(np.where(use, hi - lo, 0).sum())
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    n = int(_closed_kernel(frozen(positions), frozen(sign.astype(np.int64), np.int64), frozen(use, np.bool_),
                           float(sx), float(sy), scene.width, scene.height, *out))
    spans = [a[:n] for a in out]
    slow = np.flatnonzero(drawn & ~safe)
    if slow.size:
        extra = [(int(t), j, i) for t in slow for j, i in _rational_pixels(positions[t], scene, sx, sy)]
        if extra:
            more = _rows(np.empty(0, np.int64), extra)
            spans = [np.concatenate([a, getattr(more, f)]) for a, f in zip(spans, ("triangle", "y", "x0", "x1"))]
            order = np.argsort(spans[0], kind="stable")
            spans = [a[order] for a in spans]
    return Coverage(*spans)


def closed_reference(scene: Scene, convention: Convention) -> Coverage:
    """Every pixel of the viewport and every triangle decided in :class:`fractions.Fraction`
    from the definition alone (the sample in the convex hull of the snapped vertices).
    Slow; for tests."""
    positions = convention.snap(scene.positions)
    sx, sy = (Fraction(v) for v in convention.sample)
    pixels: list[tuple[int, int, int]] = []
    for t, triangle in enumerate(positions):
        if not np.all(np.isfinite(triangle)):
            continue
        p = [(Fraction(float(x)), Fraction(float(y))) for x, y in triangle]
        s = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])
        if (convention.cull == "cw" and s > 0) or (convention.cull == "ccw" and s < 0):
            continue
        pixels += [(t, j, i) for j in range(scene.height) for i in range(scene.width)
                   if _fraction_inside(p, i + sx, j + sy)]
    return _rows(np.empty(0, np.int64), pixels)
