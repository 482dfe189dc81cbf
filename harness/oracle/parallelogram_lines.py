"""Exact oracle for Vulkan's non-strict (parallelogram) lines, with its rational reference;
spans as in :mod:`harness.oracle.line_spans`.

Parallelogram lines (:func:`parallelogram_spans`)
    Vulkan 1.4, 28.8.1 "Basic Line Segment Rasterization": when ``strictLines`` is false
    (``VK_LINE_RASTERIZATION_MODE_DEFAULT`` on such a device), lines "may be rasterized as
    parallelograms" instead of rectangles: the segment from a to b is classed x-major when
    |dy| <= |dx| (slope in [-1, 1]), else y-major, and covers the samples inside the
    parallelogram whose vertices are a -+ (w/2) e and b -+ (w/2) e, e the unit vector of the
    *minor* axis (y for x-major, x for y-major): its long sides are the segment moved by
    +-w/2 along the minor axis, its ends are parallel to the minor axis through a and b.
    With d = b - a, c(p) = cross(d, p - a) = dx*(py - ay) - dy*(px - ax) and h = w/2, an
    x-major sample p is inside when ``sdx*(px - ax) > 0``, ``sdx*(bx - px) > 0`` and
    ``|c(p)| < |dx| * h`` (``sdx*(dx*h - c) > 0`` and ``sdx*(dx*h + c) > 0``); a y-major
    one likewise with the axes exchanged (``sdy*(py - ay) > 0``, ``sdy*(by - py) > 0``,
    ``|c(p)| < |dy| * h``). A sample on the boundary is decided at p + delta(eps), the tie
    rule's symbolic perturbation, as for triangles and rectangles
    (:mod:`harness.oracle.rectangle_lines`): the sign of the boundary function's gradient along
    delta decides. The sides decide sign(m*h -+ c), m = dx or dy: eight products, a float
    filter with a rigorous bound, else an exact expansion; the ends a float comparison. No
    division decides anything. Coordinates and widths zero or of magnitude in
    [2**-150, 2**150] (as rectangles); beyond, ValueError (:func:`harness.oracle.lines.line_coverage`
    sends such segments to the rational reference). A zero-length segment covers nothing.

    This is the body llvmpipe draws for GL lines (Mesa, src/gallium/drivers/llvmpipe/
    lp_setup_line.c, ``try_setup_line``: four planes x[0..3], y[0..3] at the end points,
    +-``fixed_width/2`` along the minor axis, decided with the triangles' fill rule), but
    llvmpipe first moves each end along the segment to a pixel edge when its own diamond
    test (``draw_start``/``draw_end``, computed in float) disagrees with what the
    parallelogram would draw there (``will_draw_start``/``will_draw_end``): its lines are
    this rule only where no end is moved. A float32 port of that branch
    (``tests/llvmpipe_lines.py``) reproduces llvmpipe's lines on every identify probe (0 of
    9,584 px, Mesa 22.3.6), where this rule misses the ends it moves: they are a procedure, not
    a rule. With ``rectangular_lines`` set (lavapipe's rectangular mode) it draws the
    rectangle instead.

:func:`parallelogram_spans_rational` is the slow reference in :class:`fractions.Fraction`
arithmetic for any finite float (small viewports only): the four vertices as fractions, and
each sample of the viewport tested against the four edges of the parallelogram as a
polygon, perturbed symbolically -- written from the vertices, not from the conditions above.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike

from harness.contract.conventions import TieRule
from harness.geometry.exact import _two_product, frozen
from harness.oracle.diamond_lines import is_x_major
from harness.oracle.line_spans import Spans, _as_spans, _check_range, _empty, _spans_from_mask
from harness.oracle.rectangle_lines import (
    RECT_SAFE_MAX,
    RECT_SAFE_MIN,
    _owned,
    _rect_capacity,
    _rect_prepare,
    _rect_rows,
    expansion_sign,
    grow_expansion,
)

__all__ = ["parallelogram_spans", "parallelogram_spans_rational", "PARA_SAFE_MIN", "PARA_SAFE_MAX"]

# The sides decide a degree-2 polynomial in the inputs; the rectangles' range keeps every
# partial product of its expansion a normal float far from overflow.
PARA_SAFE_MIN = RECT_SAFE_MIN
PARA_SAFE_MAX = RECT_SAFE_MAX

# margin of the float filter over 8 products summed: 8 roundings are below 2**-50 of the
# sum of magnitudes; 2**-48 leaves room
_FILTER = 2.0**-48


@numba.njit(cache=True)
def _side_sign(ax, ay, bx, by, px, py, h, x_major, sc):  # type: ignore[no-untyped-def]
    """Exact sign of m*h + sc*c(p), m = bx - ax (x-major) or by - ay, c(p) = cross(b - a,
    p - a) = bx*py - bx*ay - ax*py - by*px + by*ax + ay*px, sc = +-1."""
    mb = bx if x_major else by
    ma = ax if x_major else ay
    us = np.empty(8)
    vs = np.empty(8)
    us[0], vs[0] = mb, h
    us[1], vs[1] = -ma, h
    us[2], vs[2] = sc * bx, py
    us[3], vs[3] = -sc * bx, ay
    us[4], vs[4] = -sc * ax, py
    us[5], vs[5] = -sc * by, px
    us[6], vs[6] = sc * by, ax
    us[7], vs[7] = sc * ay, px
    total = 0.0
    magnitude = 0.0
    for k in range(8):
        t = us[k] * vs[k]
        total += t
        magnitude += abs(t)
    bound = _FILTER * magnitude
    if total > bound:
        return 1
    if -total > bound:
        return -1
    acc = np.empty(16)
    n = np.int64(0)  # np.int64, not the literal 0: numba compiles a callee once per literal argument
    for k in range(8):
        hi, lo = _two_product(us[k], vs[k])
        n = grow_expansion(acc, n, lo)
        n = grow_expansion(acc, n, hi)
    return expansion_sign(acc, n)


@numba.njit(cache=True, inline="always")
def _cmp(u, v):  # type: ignore[no-untyped-def]
    return 1 if u > v else (-1 if u < v else 0)


@numba.njit(cache=True)
def _para_condition(kind, ax, ay, bx, by, h, px, py, x_major, sdx, sdy, tx, ty, y_first):  # type: ignore[no-untyped-def]
    """Condition ``kind`` of the parallelogram at sample p, exactly, ties by the
    perturbation: 0 past the first end, 1 before the second, 2 and 3 the two sides."""
    if x_major:
        if kind == 0:
            s = sdx * _cmp(px, ax)
            return s > 0 if s != 0 else _owned(sdx, 0, tx, ty, y_first)
        if kind == 1:
            s = sdx * _cmp(bx, px)
            return s > 0 if s != 0 else _owned(-sdx, 0, tx, ty, y_first)
        if kind == 2:  # sdx*(dx*h - c) > 0, gradient sdx*(dy, -dx)
            s = sdx * _side_sign(ax, ay, bx, by, px, py, h, True, -1.0)
            return s > 0 if s != 0 else _owned(sdx * sdy, -1, tx, ty, y_first)
        s = sdx * _side_sign(ax, ay, bx, by, px, py, h, True, 1.0)  # sdx*(dx*h + c) > 0, gradient sdx*(-dy, dx)
        return s > 0 if s != 0 else _owned(-sdx * sdy, 1, tx, ty, y_first)
    if kind == 0:
        s = sdy * _cmp(py, ay)
        return s > 0 if s != 0 else _owned(0, sdy, tx, ty, y_first)
    if kind == 1:
        s = sdy * _cmp(by, py)
        return s > 0 if s != 0 else _owned(0, -sdy, tx, ty, y_first)
    if kind == 2:  # sdy*(dy*h + c) > 0, gradient sdy*(-dy, dx)
        s = sdy * _side_sign(ax, ay, bx, by, px, py, h, False, 1.0)
        return s > 0 if s != 0 else _owned(-1, sdx * sdy, tx, ty, y_first)
    s = sdy * _side_sign(ax, ay, bx, by, px, py, h, False, -1.0)  # sdy*(dy*h - c) > 0, gradient sdy*(dy, -dx)
    return s > 0 if s != 0 else _owned(1, -sdx * sdy, tx, ty, y_first)


@numba.njit(cache=True)
def _para_flip(kind, rising, ax, ay, bx, by, h, sx, ys, x_major, sdx, sdy, tx, ty, y_first, width, estimate):  # type: ignore[no-untyped-def]
    """The first column i in [0, width] where g(i) holds, g = condition (``rising``) or its
    negation, monotone false -> true along the row; g(width) is taken as true. Starts from
    the float estimate, then steps or bisects with the exact condition."""
    c = min(max(estimate, 0), width)
    if c < width and (_para_condition(kind, ax, ay, bx, by, h, c + sx, ys, x_major, sdx, sdy, tx, ty, y_first) != rising):
        c += 1
        if c >= width or (_para_condition(kind, ax, ay, bx, by, h, c + sx, ys, x_major, sdx, sdy, tx, ty, y_first)
                          == rising):
            return c
        lo, hi = c, width
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _para_condition(kind, ax, ay, bx, by, h, mid + sx, ys, x_major, sdx, sdy, tx, ty, y_first) == rising:
                hi = mid
            else:
                lo = mid
        return hi
    if c == 0 or (_para_condition(kind, ax, ay, bx, by, h, c - 1 + sx, ys, x_major, sdx, sdy, tx, ty, y_first) != rising):
        return c
    c -= 1
    if c == 0 or (_para_condition(kind, ax, ay, bx, by, h, c - 1 + sx, ys, x_major, sdx, sdy, tx, ty, y_first) != rising):
        return c
    lo, hi = -1, c - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _para_condition(kind, ax, ay, bx, by, h, mid + sx, ys, x_major, sdx, sdy, tx, ty, y_first) == rising:
            hi = mid
        else:
            lo = mid
    return hi


@numba.njit(cache=True)
def _para_kernel(a, b, widths, keep, majors, sx, sy, tx, ty, y_first, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Every segment's parallelogram as one span per row: each of the four conditions is
    linear along a row, so the covered samples run from the last column where a rising
    condition turns true to the first where a falling one turns false."""
    n = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        h = 0.5 * widths[s]
        if ax == bx and ay == by:
            continue  # no length, no parallelogram
        x_major = majors[s]
        sdx = 1 if bx > ax else (-1 if bx < ax else 0)
        sdy = 1 if by > ay else (-1 if by < ay else 0)
        dx = bx - ax
        dy = by - ay
        m = dx if x_major else dy
        first, last = _rect_rows(ay, by, widths[s], sy, height)
        for j in range(first, last + 1):
            ys = j + sy
            lo = 0
            end = width
            for kind in range(4):
                # the condition's x gradient
                if x_major:
                    gx = sdx if kind == 0 else (-sdx if kind == 1 else (sdx * sdy if kind == 2 else -sdx * sdy))
                else:
                    gx = 0 if kind < 2 else (-1 if kind == 2 else 1)
                if gx == 0:  # constant along the row
                    if not _para_condition(kind, ax, ay, bx, by, h, sx, ys, x_major, sdx, sdy, tx, ty, y_first):
                        end = 0
                        break
                    continue
                if kind == 0:
                    x_edge = ax
                elif kind == 1:
                    x_edge = bx
                else:
                    sc = (-1.0 if kind == 2 else 1.0) if x_major else (1.0 if kind == 2 else -1.0)
                    x_edge = ax + (dx * (ys - ay) + sc * m * h) / dy  # m*h + sc*c = 0
                e = x_edge - sx
                estimate = 0 if not e > -1.0 else (width if e > width else int(math.ceil(e)))
                rising = gx > 0
                c = _para_flip(kind, rising, ax, ay, bx, by, h, sx, ys, x_major, sdx, sdy, tx, ty, y_first, width, estimate)
                if rising:
                    lo = max(lo, c)
                else:
                    end = min(end, c)
                if lo >= end:
                    break
            if lo < end:
                out_s[n] = s
                out_y[n] = j
                out_x0[n] = lo
                out_x1[n] = end
                n += 1
    return n


def parallelogram_spans(a: ArrayLike, b: ArrayLike, line_width: ArrayLike = 1.0, sample: tuple[float, float] = (0.5, 0.5),
                        tie: TieRule = "top-left", *, width: int, height: int) -> Spans:
    """Exactly which samples each segment's parallelogram covers (Vulkan non-strict lines).

    Parameters
    ----------
    a, b : (N, 2) float64
        Segment k runs from ``a[k]`` to ``b[k]``.
    line_width : float or (N,) float64
        w > 0: the sides lie w/2 either side of the segment along its minor axis.
    sample : (float, float)
        The sample point's offset in each pixel (as :class:`harness.contract.conventions.Convention`).
    tie : str
        The tie rule for samples on the boundary (:data:`harness.contract.conventions.TIE_RULES`).
    width, height : int
        The viewport.

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        One span per covered row and segment, sorted by segment and row.

    Raises
    ------
    ValueError
        On a bad argument, or a nonzero coordinate or width of magnitude below 2**-150 or
        above 2**150, naming the segment.

    Examples
    --------
    A segment of slope 1/2 from pixel centre (0.5, 0.5) to (6.5, 3.5): x-major, so each
    column's centre is drawn where the segment, widened by 1/2 up and down, covers it. At
    x = 1.5, 3.5 and 5.5 the segment runs through a row boundary, and both centres there
    lie on a side: top-left ties (x first) keep the lower side, whose inside lies up and
    to its right (a left edge), and leave the upper one (a right edge); the left end
    (x = 0.5) is kept, the right end (x = 6.5) is not.

    >>> s, y, x0, x1 = parallelogram_spans([[0.5, 0.5]], [[6.5, 3.5]], width=8, height=5)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 1), (1, 1, 3), (2, 3, 5), (3, 5, 6)]
    """
    a_arr, b_arr, widths, keep, convention, width, height = _rect_prepare(a, b, line_width, sample, tie, width, height)
    values = np.concatenate([a_arr, b_arr, widths[:, None]], axis=1)
    _check_range(values, keep, PARA_SAFE_MIN, PARA_SAFE_MAX, "parallelogram_spans_rational")
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    majors = np.array([bool(is_x_major(*a_arr[k], *b_arr[k])) if keep[k] else True for k in range(a_arr.shape[0])],
                      dtype=np.bool_)
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    a_f, b_f, w_f = frozen(a_arr), frozen(b_arr), frozen(widths)
    keep_f, majors_f = frozen(keep, np.bool_), frozen(majors, np.bool_)
    capacity = int(_rect_capacity(a_f, b_f, w_f, keep_f, sy, height))
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    m = int(_para_kernel(a_f, b_f, w_f, keep_f, majors_f, sx, sy, tx, ty, y_first, width, height, *out))
    return out[0][:m], out[1][:m], out[2][:m], out[3][:m]


def _first_sign(coefficients: list[Fraction]) -> int:
    for value in coefficients:
        if value:
            return 1 if value > 0 else -1
    return 0


def parallelogram_spans_rational(a: ArrayLike, b: ArrayLike, line_width: ArrayLike = 1.0,
                                 sample: tuple[float, float] = (0.5, 0.5), tie: TieRule = "top-left", *,
                                 width: int, height: int) -> Spans:
    """The same spans as :func:`parallelogram_spans` by brute force in rational arithmetic,
    from the parallelogram's four vertices: every sample p moved symbolically to
    q = p + delta(eps) (the tie rule's (tx*eps, ty*eps**2), or (tx*eps**2, ty*eps) y-first)
    and tested strictly inside each of the four edges, as polynomials in eps. Any finite float."""
    a_arr, b_arr, widths, keep, convention, width, height = _rect_prepare(a, b, line_width, sample, tie, width, height)
    sx, sy = (Fraction(v) for v in convention.sample)
    tx, ty, y_first = convention.tie_perturbation
    ex = (Fraction(0), Fraction(tx)) if y_first else (Fraction(tx), Fraction(0))  # (eps, eps**2) parts of q - p
    ey = (Fraction(ty), Fraction(0)) if y_first else (Fraction(0), Fraction(ty))
    out: list[tuple[int, int, int, int]] = []
    for s in np.flatnonzero(keep):
        ax, ay, bx, by = (Fraction(float(v)) for v in (*a_arr[s], *b_arr[s]))
        h = Fraction(float(widths[s])) / 2
        if ax == bx and ay == by:
            continue
        ox, oy = (Fraction(0), h) if abs(bx - ax) >= abs(by - ay) else (h, Fraction(0))
        quad = [(ax - ox, ay - oy), (bx - ox, by - oy), (bx + ox, by + oy), (ax + ox, ay + oy)]
        twice_area = sum(u[0] * v[1] - v[0] * u[1] for u, v in zip(quad, quad[1:] + quad[:1]))
        turn = 1 if twice_area > 0 else -1
        covered = []
        for j in range(height):
            row = []
            for i in range(width):
                px, py = i + sx, j + sy
                inside = True
                for (ux, uy), (vx, vy) in zip(quad, quad[1:] + quad[:1]):
                    fx, fy = vx - ux, vy - uy
                    poly = [fx * (py - uy) - fy * (px - ux), fx * ey[0] - fy * ex[0], fx * ey[1] - fy * ex[1]]
                    if _first_sign([turn * c for c in poly]) <= 0:
                        inside = False
                        break
                row.append(inside)
            covered.append(row)
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)
