"""Exact oracle for Vulkan's rectangular lines, with its rational reference; spans as in
:mod:`harness.oracle.line_spans`.

Rectangular lines (:func:`rectangle_spans`)
    Vulkan's ``VK_LINE_RASTERIZATION_MODE_RECTANGULAR`` ("lines drawn as if they were
    rectangles extruded from the line"; ``strictLines``): sample p = (i + sx, j + sy) is
    covered when it lies inside the rectangle of width w centred on the segment, length
    |b - a|, no end caps. With d = b - a and c(p) = cross(d, p - a) =
    dx*(py - ay) - dy*(px - ax): ``dot(d, p - a) > 0``, ``dot(a - b, p - b) > 0`` and
    ``4*c(p)**2 < w**2 * |d|**2``. A sample on the boundary is decided at p + delta(eps), the
    tie rule's symbolic perturbation (:mod:`harness.contract.conventions`), exactly as for
    triangles: on a cap or side the sign of the boundary function's gradient along delta
    decides (x-first: its x part, else its y part), so collinear segments a->b, b->c share
    the samples of their common cap exactly once, and side by side strips likewise.
    Decisions: the caps by a dot-product sign (float filter, exact expansion), the sides
    by sign(c) (:func:`harness.geometry.exact.orient2d_sign`) and sign(w**2 |d|**2 - 4 c**2), a
    degree-4 polynomial: a float filter with a rigorous bound, else an exact expansion. No
    square root decides anything. Degree 4 needs a smaller range: coordinates and widths
    zero or of magnitude in [2**-150, 2**150] (every partial product of the expansion is
    then a multiple of 2**-808 and below 2**610: no underflow, no overflow); beyond,
    ValueError. A zero-length segment covers nothing.

    Runs (issue 35): each condition flips once along a row, at a crossing the kernel computes
    in float with a proven margin (``_rect_runs_segment``); the flip column is decided there
    unless a sample lies within the margin, where the exact predicates above decide. On the
    rows strictly between the caps (by a wide margin) only the two sides are computed, in a
    loop numba vectorizes. ``_rectangle_spans_reference`` keeps the exact-flip kernel for
    the tests.

:func:`rectangle_spans_rational` is the slow reference, in :class:`fractions.Fraction`
arithmetic for any finite float (small viewports and coordinates only): it decides every
sample of the viewport from the definition above.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import (
    Convention,
    TieRule,
)
from harness.geometry.exact import CCW_ERRBOUND_A, _two_product, _two_sum, frozen, orient2d_sign
from harness.oracle.line_spans import (
    Spans,
    _as_spans,
    _check_range,
    _clamp_index,
    _empty,
    _endpoints,
    _spans_from_mask,
    _viewport,
    span_buffers,
)

# Rectangles decide a degree-4 polynomial: inputs of magnitude in [2**-150, 2**150] (or 0)
# are multiples of 2**-202, so every term is a multiple of 2**-808 (no underflow) and the
# largest, (2c)**2 <= (4 * 2**151 * 2**151)**2, stays below 2**610 (no overflow; Dekker's
# split needs < 2**996).
RECT_SAFE_MIN = 2.0**-150
RECT_SAFE_MAX = 2.0**150


# margin of the rectangle's float filter: 32 ulps, well above its ~8 roundings
_FILTER_SLACK = 2.0**-48


# -- rectangles --------------------------------------------------------------------------------


@numba.njit(cache=True)
def grow_expansion(h, length, q):  # type: ignore[no-untyped-def]
    """Add float q to the nonoverlapping expansion h[:length] (Shewchuk's
    grow_expansion_zeroelim); returns the new length."""
    k = 0
    for i in range(length):
        q, err = _two_sum(q, h[i])
        if err != 0.0:
            h[k] = err
            k += 1
    if q != 0.0:
        h[k] = q
        k += 1
    return k


@numba.njit(cache=True)
def expansion_sign(h, length):  # type: ignore[no-untyped-def]
    if length == 0:
        return 0
    return 1 if h[length - 1] > 0.0 else -1


@numba.njit(cache=True)
def _dot_sign(ax, ay, bx, by, px, py):  # type: ignore[no-untyped-def]
    """Exact sign of dot(b - a, p - a) = (bx-ax)*(px-ax) + (by-ay)*(py-ay)."""
    t1 = (bx - ax) * (px - ax)
    t2 = (by - ay) * (py - ay)
    total = t1 + t2
    # Signs of differences and of their products are exact: agreeing signs need no bound.
    if (t1 >= 0.0 and t2 >= 0.0) or (t1 <= 0.0 and t2 <= 0.0):
        return 1 if total > 0.0 else (-1 if total < 0.0 else 0)
    bound = CCW_ERRBOUND_A * (abs(t1) + abs(t2))  # Shewchuk's orient2d bound: same form
    if total > bound:
        return 1
    if -total > bound:
        return -1
    h = np.empty(16)
    length = np.int64(0)  # np.int64, not the literal 0: numba compiles a callee once per literal argument
    for u, v in ((bx, px), (-bx, ax), (-ax, px), (ax, ax), (by, py), (-by, ay), (-ay, py), (ay, ay)):
        hi, lo = _two_product(u, v)
        length = grow_expansion(h, length, lo)
        length = grow_expansion(h, length, hi)
    return expansion_sign(h, length)


@numba.njit(cache=True)
def _strip_sign(ax, ay, bx, by, px, py, w):  # type: ignore[no-untyped-def]
    """Exact sign of w**2 * |b - a|**2 - 4 * c**2, c = cross(b - a, p - a): positive when
    p lies strictly between the rectangle's long sides."""
    detleft = (ax - px) * (by - py)
    detright = (ay - py) * (bx - px)
    c = detleft - detright
    c_err = CCW_ERRBOUND_A * (abs(detleft) + abs(detright))
    dx = bx - ax
    dy = by - ay
    big_h = 0.25 * w * w * (dx * dx + dy * dy)  # h**2 within ~7 roundings
    c_hi = abs(c) + c_err
    c_lo = abs(c) - c_err
    if c_hi * c_hi * (1.0 + _FILTER_SLACK) < big_h * (1.0 - _FILTER_SLACK):
        return 1
    if c_lo > 0.0 and c_lo * c_lo * (1.0 - _FILTER_SLACK) > big_h * (1.0 + _FILTER_SLACK):
        return -1
    # Exact: 2c as an expansion (orient2d's six products, doubled: exact), then
    # w**2 * (dx**2 + dy**2) - (2c)**2 summed term by term.
    cc = np.empty(16)
    nc = np.int64(0)  # np.int64, not the literal 0: numba compiles a callee once per literal argument
    for u, v in ((ax, by), (-ay, bx), (bx, py), (-by, px), (px, ay), (-py, ax)):
        hi, lo = _two_product(2.0 * u, v)
        nc = grow_expansion(cc, nc, lo)
        nc = grow_expansion(cc, nc, hi)
    dd = np.empty(32)
    nd = np.int64(0)
    dxh, dxl = _two_sum(bx, -ax)
    dyh, dyl = _two_sum(by, -ay)
    for u, v in ((dxh, dxh), (dxh, dxl), (dxh, dxl), (dxl, dxl), (dyh, dyh), (dyh, dyl), (dyh, dyl), (dyl, dyl)):
        hi, lo = _two_product(u, v)
        nd = grow_expansion(dd, nd, lo)
        nd = grow_expansion(dd, nd, hi)
    wh, wl = _two_product(w, w)
    acc = np.empty(2 * nc * nc + 4 * nd + 8)
    na = np.int64(0)
    for k in range(nd):
        for part in (wh, wl):
            if part != 0.0:
                hi, lo = _two_product(dd[k], part)
                na = grow_expansion(acc, na, lo)
                na = grow_expansion(acc, na, hi)
    for k in range(nc):
        for m in range(nc):
            hi, lo = _two_product(-cc[k], cc[m])
            na = grow_expansion(acc, na, lo)
            na = grow_expansion(acc, na, hi)
    return expansion_sign(acc, na)


@numba.njit(cache=True, inline="always")
def _owned(gx, gy, tx, ty, y_first):  # type: ignore[no-untyped-def]
    """Whether a sample exactly on a boundary whose inside function has gradient signs
    (gx, gy) is inside: the sign of the gradient along the tie rule's perturbation
    (x-first: its x part, else its y part; y-first the other way round)."""
    if y_first:
        return gy * ty > 0 if gy != 0 else gx * tx > 0
    return gx * tx > 0 if gx != 0 else gy * ty > 0


@numba.njit(cache=True)
def _rect_condition(kind, ax, ay, bx, by, w, px, py, sdx, sdy, tx, ty, y_first):  # type: ignore[no-untyped-def]
    """Condition ``kind`` of the rectangle at sample p, exactly, ties by the perturbation:
    0 dot(d, p - a) > 0, 1 dot(-d, p - b) > 0, 2 c < h, 3 c > -h (c = cross(d, p - a),
    h = w|d|/2, d = b - a with exact signs sdx, sdy)."""
    if kind == 0:
        s = _dot_sign(ax, ay, bx, by, px, py)
        return s > 0 if s != 0 else _owned(sdx, sdy, tx, ty, y_first)
    if kind == 1:
        s = _dot_sign(bx, by, ax, ay, px, py)
        return s > 0 if s != 0 else _owned(-sdx, -sdy, tx, ty, y_first)
    c = orient2d_sign(ax, ay, bx, by, px, py)
    if kind == 2:
        if c <= 0:
            return True
        s = _strip_sign(ax, ay, bx, by, px, py, w)
        return s > 0 if s != 0 else _owned(sdy, -sdx, tx, ty, y_first)  # grad(h - c) = (dy, -dx)
    if c >= 0:
        return True
    s = _strip_sign(ax, ay, bx, by, px, py, w)
    return s > 0 if s != 0 else _owned(-sdy, sdx, tx, ty, y_first)  # grad(c + h) = (-dy, dx)


@numba.njit(cache=True)
def _rect_flip(kind, rising, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first, width, estimate):  # type: ignore[no-untyped-def]
    """The first column i in [0, width] where g(i) holds, g = condition (``rising``) or
    its negation, monotone false -> true along the row; g(width) is taken as true.
    Starts from the float estimate, then steps or bisects with the exact condition."""
    c = min(max(estimate, 0), width)
    if c < width and (_rect_condition(kind, ax, ay, bx, by, w, c + sx, ys, sdx, sdy, tx, ty, y_first) != rising):
        c += 1
        if c >= width or (_rect_condition(kind, ax, ay, bx, by, w, c + sx, ys, sdx, sdy, tx, ty, y_first) == rising):
            return c
        lo, hi = c, width
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _rect_condition(kind, ax, ay, bx, by, w, mid + sx, ys, sdx, sdy, tx, ty, y_first) == rising:
                hi = mid
            else:
                lo = mid
        return hi
    if c == 0 or (_rect_condition(kind, ax, ay, bx, by, w, c - 1 + sx, ys, sdx, sdy, tx, ty, y_first) != rising):
        return c
    c -= 1
    if c == 0 or (_rect_condition(kind, ax, ay, bx, by, w, c - 1 + sx, ys, sdx, sdy, tx, ty, y_first) != rising):
        return c
    lo, hi = -1, c - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _rect_condition(kind, ax, ay, bx, by, w, mid + sx, ys, sdx, sdy, tx, ty, y_first) == rising:
            hi = mid
        else:
            lo = mid
    return hi


@numba.njit(cache=True, inline="always")
def _rect_rows(ay, by, w, sy, height):  # type: ignore[no-untyped-def]
    """Rows whose sample height may meet the rectangle (within w/2 of the segment's y
    extent), with a row to spare either side for the float bounds."""
    y_lo = min(ay, by) - 0.5 * w - sy
    y_hi = max(ay, by) + 0.5 * w - sy
    first = _clamp_index(y_lo, -1, height) - 1
    last = _clamp_index(y_hi, -1, height) + 1
    return max(first, 0), min(last, height - 1)


@numba.njit(cache=True)
def _rect_capacity(a, b, widths, keep, sy, height):  # type: ignore[no-untyped-def]
    total = 0
    for s in range(a.shape[0]):
        if keep[s]:
            first, last = _rect_rows(a[s, 1], b[s, 1], widths[s], sy, height)
            total += max(last - first + 1, 0)
    return total


@numba.njit(cache=True)
def _rect_kernel(a, b, widths, keep, sx, sy, tx, ty, y_first, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Every segment's rectangle as one span per row. Each of the four conditions is linear
    along a row (monotone in the column), so the covered samples run from the last column
    where a rising condition turns true to the first where a falling one turns false."""
    n = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by, w = a[s, 0], a[s, 1], b[s, 0], b[s, 1], widths[s]
        if ax == bx and ay == by:
            continue  # no length, no rectangle
        sdx = 1 if bx > ax else (-1 if bx < ax else 0)
        sdy = 1 if by > ay else (-1 if by < ay else 0)
        dx = bx - ax
        dy = by - ay
        half = 0.5 * w * math.sqrt(dx * dx + dy * dy)  # for the float estimates only
        first, last = _rect_rows(ay, by, w, sy, height)
        for j in range(first, last + 1):
            ys = j + sy
            lo = 0
            end = width
            for kind in range(4):
                # the condition's x gradient: d, -d, (dy, .), (-dy, .)
                gx = sdx if kind == 0 else (-sdx if kind == 1 else (sdy if kind == 2 else -sdy))
                if gx == 0:
                    # constant along the row
                    if not _rect_condition(kind, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first):
                        end = 0
                        break
                    continue
                if kind == 0:
                    x_edge = ax - dy * (ys - ay) / dx
                elif kind == 1:
                    x_edge = bx - dy * (ys - by) / dx
                elif kind == 2:
                    x_edge = ax + (dx * (ys - ay) - half) / dy
                else:
                    x_edge = ax + (dx * (ys - ay) + half) / dy
                e = x_edge - sx
                estimate = 0 if not e > -1.0 else (width if e > width else int(math.ceil(e)))
                rising = gx > 0
                c = _rect_flip(kind, rising, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first, width, estimate)
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


# -- rectangles as runs: the float filter decides each side of a row, exact near a sample --------

# Margin of the crossings' float filter (below): 2**-48 = 32 * 2**-53, twice the bound on the
# rounding of a crossing (see _rect_runs_segment), plus 2**-1000 (no term underflows in range).
_RECT_RUN_FILTER = 2.0**-48
_RECT_RUN_TINY = 2.0**-1000
# the filter only converts crossings below this magnitude to integers
_RECT_INT_SAFE = 2.0**40


@numba.njit(cache=True, inline="always")
def _first_column(x_edge, margin, sx, width):  # type: ignore[no-untyped-def]
    """The first column i in [0, width] whose sample i + sx lies past the crossing x_edge
    (known within ``margin``), or -1 when a sample may lie on it: then the crossing is
    within the margin of a sample and the exact condition decides."""
    e = x_edge - sx
    f = np.floor(e + margin)  # a float: one conversion to int, once decided
    if f < e - margin:  # no integer i with i + sx within the margin of the crossing
        return min(max(int(f) + 1, 0), width)
    return -1


@numba.njit(cache=True, inline="always")
def _rect_side(kind, rising, x_edge, margin, fast, lo, end, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first, width):  # type: ignore[no-untyped-def]
    """(lo, end) narrowed by condition ``kind`` of a row, which flips at x_edge (true after
    it when ``rising``, before it otherwise): the flip column from the float filter
    (:func:`_first_column`) or, near a sample, exactly (:func:`_rect_flip`)."""
    if lo >= end:
        return lo, end
    c = _first_column(x_edge, margin, sx, width) if fast else -1
    if c < 0:
        e = x_edge - sx
        estimate = 0 if not e > -1.0 else (width if e > width else int(math.ceil(e)))
        c = _rect_flip(kind, rising, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first, width, estimate)
    if rising:
        return max(lo, c), end
    return lo, min(end, c)


@numba.njit(cache=True)
def _rect_runs_segment(s, ax, ay, bx, by, w, sx, sy, tx, ty, y_first, width, height, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """One segment's rectangle as one span per row, as :func:`_rect_kernel` finds it: each
    condition of the rectangle flips at one crossing along a row (x_edge), and the covered
    samples lie between the last rising and the first falling flip. Here each crossing is
    computed in float with a rigorous margin, and decides the flip column when no sample
    lies within the margin (:func:`_first_column`); otherwise :func:`_rect_flip` decides
    exactly, as before.

    Crossings (d = b - a rounded, s = |d|, h = w s / 2, all rounded): caps x = ax - (y -
    ay) * dy/dx and bx - (y - by) * dy/dx; sides x = ax + ((y - ay) * dx/dy -+ h/dy). With
    P the product and Z = h/dy, the error of a cap's crossing is below 2**-53 * (|x| +
    5|P|) and a side's below 2**-53 * (|x| + 8(|P| + |Z|)) (P: three roundings in the
    quotient, one each in y - ay and the product; Z: four in h, two in the quotient; one
    per sum), and of x - sx one more 2**-53 * (|x| + 1); the margin is 2**-48 times
    bounds on |x| + 2|P| + 2|Z| + 1 over the segment's rows: twice the error and more."""
    if ax == bx and ay == by:
        return n  # no length, no rectangle
    sdx = 1 if bx > ax else (-1 if bx < ax else 0)
    sdy = 1 if by > ay else (-1 if by < ay else 0)
    dx = bx - ax
    dy = by - ay
    first, last = _rect_rows(ay, by, w, sy, height)
    if first > last:
        return n
    half = 0.5 * w * math.sqrt(dx * dx + dy * dy)
    grow = 1.0 + 2.0**-40  # bounds of |y - ay| and of the products over the rows, rounded up
    y0 = max(abs(first + sy - ay), abs(last + sy - ay)) * grow
    y1 = max(abs(first + sy - by), abs(last + sy - by)) * grow
    cap_slope = dy / dx if sdx != 0 else 0.0
    side_slope = dx / dy if sdy != 0 else 0.0
    side_shift = half / dy if sdy != 0 else 0.0
    p_cap = max(y0, y1) * abs(cap_slope) * grow
    p_side = y0 * abs(side_slope) * grow
    z_side = abs(side_shift)
    margin_cap = _RECT_RUN_FILTER * (max(abs(ax), abs(bx)) + 3.0 * p_cap + 1.0) + _RECT_RUN_TINY
    margin_side = _RECT_RUN_FILTER * (abs(ax) + 3.0 * (p_side + z_side) + 1.0) + _RECT_RUN_TINY
    fast = (max(abs(ax), abs(bx)) + p_cap + p_side + z_side < _RECT_INT_SAFE and margin_cap < 0.25
            and margin_side < 0.25)
    # Rows whose samples between the sides all lie strictly between the caps: the sides
    # cross row y at t = (y - ay -+ q) / dy along d, q = (w/2) dx/|d|, both in (0, 1) when
    # y lies in (ay + |q|, by - |q|) (dy > 0; (by + |q|, ay - |q|) when dy < 0). The margin
    # 2**-30 of the magnitudes dwarfs every rounding here: the rows found are inside.
    mid_lo, mid_hi = 1, 0
    if sdy != 0:
        q = 0.5 * w * abs(dx) / math.sqrt(dx * dx + dy * dy)
        safety = 2.0**-30 * (abs(ay) + abs(by) + q + 1.0)
        y_lo = min(ay, by) + q + safety
        y_hi = max(ay, by) - q - safety
        if y_lo < y_hi and abs(y_lo) + abs(y_hi) < _RECT_INT_SAFE:
            mid_lo = int(math.floor(y_lo - sy)) + 1  # first row with j + sy > y_lo
            mid_hi = int(math.ceil(y_hi - sy)) - 1  # last row with j + sy < y_hi
    if fast and sdy != 0 and mid_lo <= mid_hi:
        m0, m1 = max(first, mid_lo), min(last, mid_hi)
    else:
        m0, m1 = last + 1, last
    for j in range(first, min(m0, last + 1)):
        n = _rect_row(s, j, ax, ay, bx, by, w, sx, sy, tx, ty, y_first, width, sdx, sdy, cap_slope, side_slope, side_shift,
                      margin_cap, margin_side, fast, False, out_s, out_y, out_x0, out_x1, n)
    # the rows between the caps: two crossings each, decided by the filter (else the general row)
    rising_left = sdy > 0  # c < h rises along the row when dy > 0: its flip starts the run
    if m0 <= m1 and _rect_middle(s, m0, m1, ax, ay, sx, sy, side_slope, side_shift, margin_side, width, rising_left,
                                 out_s, out_y, out_x0, out_x1, n):
        n += m1 - m0 + 1
        m0 = m1 + 1  # every row decided, each a span
    for j in range(m0, m1 + 1):
        ys = j + sy
        p = (ys - ay) * side_slope
        c2 = _first_column(ax + (p - side_shift), margin_side, sx, width)
        c3 = _first_column(ax + (p + side_shift), margin_side, sx, width)
        if c2 < 0 or c3 < 0:
            n = _rect_row(s, j, ax, ay, bx, by, w, sx, sy, tx, ty, y_first, width, sdx, sdy, cap_slope, side_slope,
                          side_shift, margin_cap, margin_side, fast, True, out_s, out_y, out_x0, out_x1, n)
            continue
        lo, end = (c2, c3) if rising_left else (c3, c2)
        if lo < end:
            u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
            out_s[u] = s
            out_y[u] = j
            out_x0[u] = lo
            out_x1[u] = end
            n += 1
    for j in range(max(m1 + 1, first), last + 1):
        n = _rect_row(s, j, ax, ay, bx, by, w, sx, sy, tx, ty, y_first, width, sdx, sdy, cap_slope, side_slope, side_shift,
                      margin_cap, margin_side, fast, False, out_s, out_y, out_x0, out_x1, n)
    return n


@numba.njit(cache=True)
def _rect_middle(s, m0, m1, ax, ay, sx, sy, side_slope, side_shift, margin, width, rising_left,  # type: ignore[no-untyped-def]
                 out_s, out_y, out_x0, out_x1, n):
    """Rows m0..m1 between the caps written as spans n, n + 1, ... in one branch-free loop
    (numba stores them a vector at a time): the sides' flips as :func:`_first_column`
    finds them. True when the filter decided every row and each covers a sample; else
    False, and the caller decides the rows one by one (overwriting these spans)."""
    ok = True
    for i in range(m1 - m0 + 1):
        j = m0 + i
        p = (j + sy - ay) * side_slope
        e2 = ax + (p - side_shift) - sx
        e3 = ax + (p + side_shift) - sx
        f2 = np.floor(e2 + margin)
        f3 = np.floor(e3 + margin)
        ok &= (f2 < e2 - margin) & (f3 < e3 - margin)
        c2 = min(max(int(f2) + 1, 0), width)
        c3 = min(max(int(f3) + 1, 0), width)
        lo = c2 if rising_left else c3
        end = c3 if rising_left else c2
        ok &= lo < end
        u = np.uint64(n + i)
        out_s[u] = s
        out_y[u] = j
        out_x0[u] = lo
        out_x1[u] = end
    return ok


@numba.njit(cache=True)
def _rect_row(s, j, ax, ay, bx, by, w, sx, sy, tx, ty, y_first, width, sdx, sdy, cap_slope, side_slope, side_shift,  # type: ignore[no-untyped-def]
              margin_cap, margin_side, fast, between_caps, out_s, out_y, out_x0, out_x1, n):
    """Row j of a segment's rectangle (:func:`_rect_runs_segment`): the sides' flips, then
    the caps' unless ``between_caps`` (every sample between the sides lies between the
    caps). Returns the span count."""
    ys = j + sy
    lo = 0
    end = width
    # the sides: c < h (x gradient dy) and c > -h (x gradient -dy)
    if sdy == 0:  # constant along the row
        if not (_rect_condition(2, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first)
                and _rect_condition(3, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first)):
            return n
    else:
        p = (ys - ay) * side_slope
        lo, end = _rect_side(2, sdy > 0, ax + (p - side_shift), margin_side, fast, lo, end, ax, ay, bx, by, w, sx,
                             ys, sdx, sdy, tx, ty, y_first, width)
        lo, end = _rect_side(3, sdy < 0, ax + (p + side_shift), margin_side, fast, lo, end, ax, ay, bx, by, w, sx,
                             ys, sdx, sdy, tx, ty, y_first, width)
    if lo >= end:
        return n
    if not between_caps:
        # the caps: dot(d, p - a) > 0 (x gradient dx), dot(-d, p - b) > 0 (x gradient -dx)
        if sdx == 0:  # constant along the row
            if not (_rect_condition(0, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first)
                    and _rect_condition(1, ax, ay, bx, by, w, sx, ys, sdx, sdy, tx, ty, y_first)):
                return n
        else:
            lo, end = _rect_side(0, sdx > 0, ax - (ys - ay) * cap_slope, margin_cap, fast, lo, end, ax, ay, bx, by,
                                 w, sx, ys, sdx, sdy, tx, ty, y_first, width)
            lo, end = _rect_side(1, sdx < 0, bx - (ys - by) * cap_slope, margin_cap, fast, lo, end, ax, ay, bx, by,
                                 w, sx, ys, sdx, sdy, tx, ty, y_first, width)
    if lo < end:
        u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
        out_s[u] = s
        out_y[u] = j
        out_x0[u] = lo
        out_x1[u] = end
        n += 1
    return n


@numba.njit(cache=True)
def _rect_runs_kernel(a, b, widths, keep, sx, sy, tx, ty, y_first, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """The spans of :func:`_rect_kernel`, each row's flips decided by the float filter of
    :func:`_rect_runs_segment` and exactly only near a sample."""
    n = 0
    for s in range(a.shape[0]):
        if keep[s]:
            n = _rect_runs_segment(s, a[s, 0], a[s, 1], b[s, 0], b[s, 1], widths[s], sx, sy, tx, ty, y_first, width, height,
                                   out_s, out_y, out_x0, out_x1, n)
    return n


# -- rectangles: public ---------------------------------------------------------------------------


def _rect_prepare(a: ArrayLike, b: ArrayLike, line_width: ArrayLike, sample: tuple[float, float], tie: TieRule,
                  width: int, height: int) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                                                    NDArray[np.bool_], Convention, int, int]:
    width, height = _viewport(width, height)
    convention = Convention(sample=sample, tie=tie)  # validates the sample point and the rule
    a_arr, b_arr, keep = _endpoints(a, b)
    widths = np.broadcast_to(np.asarray(line_width, dtype=np.float64), (a_arr.shape[0],)).copy()
    bad = ~(np.isfinite(widths) & (widths > 0.0))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ValueError(f"line_width of segment {k} must be positive and finite, not {widths[k]!r}")
    return a_arr, b_arr, widths, keep, convention, width, height


def rectangle_spans(a: ArrayLike, b: ArrayLike, line_width: ArrayLike, sample: tuple[float, float] = (0.5, 0.5),
                    tie: TieRule = "top-left", *, width: int, height: int) -> Spans:
    """Exactly which samples each segment's rectangle covers (Vulkan rectangular lines).

    Parameters
    ----------
    a, b : (N, 2) float64
        Segment k runs from ``a[k]`` to ``b[k]``.
    line_width : float or (N,) float64
        The rectangle's width w > 0.
    sample : (float, float)
        The sample point's offset in each pixel (as :class:`harness.contract.conventions.Convention`).
    tie : str
        The tie rule for samples on the rectangle's boundary (:data:`harness.contract.conventions.TIE_RULES`).
    width, height : int
        The viewport.

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        One span per covered row and segment, sorted by segment and row.

    Raises
    ------
    ValueError
        On a bad argument, or a segment with a nonzero coordinate or width of magnitude below
        2**-150 or above 2**150, naming the segment.

    Examples
    --------
    A horizontal segment of width 1 along y = 1: the samples of row 0 (y = 0.5) lie on its
    upper side and those of row 1 on its lower side; top-left ties keep the upper side and
    the left cap (x = 0.5), and leave out the lower side and the right cap (x = 3.5).

    >>> s, y, x0, x1 = rectangle_spans([[0.5, 1.0]], [[3.5, 1.0]], 1.0, width=5, height=3)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 3)]
    """
    a_arr, b_arr, widths, keep, convention, width, height = _rect_prepare(a, b, line_width, sample, tie, width, height)
    values = np.concatenate([a_arr, b_arr, widths[:, None]], axis=1)
    _check_range(values, keep, RECT_SAFE_MIN, RECT_SAFE_MAX, "rectangle_spans_rational")
    return _rectangle_kept(a_arr, b_arr, widths, keep, convention, width, height)


def _rectangle_spans_reference(a: ArrayLike, b: ArrayLike, line_width: ArrayLike, sample: tuple[float, float] = (0.5, 0.5),
                               tie: TieRule = "top-left", *, width: int, height: int) -> Spans:
    """:func:`rectangle_spans` with every flip decided by the exact condition (the kernel
    before the float filter; tests compare the two)."""
    a_arr, b_arr, widths, keep, convention, width, height = _rect_prepare(a, b, line_width, sample, tie, width, height)
    values = np.concatenate([a_arr, b_arr, widths[:, None]], axis=1)
    _check_range(values, keep, RECT_SAFE_MIN, RECT_SAFE_MAX, "rectangle_spans_rational")
    return _rectangle_kept(a_arr, b_arr, widths, keep, convention, width, height, reference=True)


def _rectangle_kept(a: NDArray[np.float64], b: NDArray[np.float64], widths: NDArray[np.float64], keep: NDArray[np.bool_],
                    convention: Convention, width: int, height: int, reference: bool = False) -> Spans:
    """:func:`rectangle_spans` of the segments ``keep`` names, checked already: (N, 2)
    float64 end points and (N,) widths (finite, positive and in range where kept), a valid
    viewport, the convention's sample point and tie rule."""
    a_arr, b_arr = a, b
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    a_f, b_f, w_f, keep_f = frozen(a_arr), frozen(b_arr), frozen(widths), frozen(keep, np.bool_)
    capacity = int(_rect_capacity(a_f, b_f, w_f, keep_f, sy, height))
    out = span_buffers(capacity)
    kernel = _rect_kernel if reference else _rect_runs_kernel
    m = int(kernel(a_f, b_f, w_f, keep_f, sx, sy, tx, ty, y_first, width, height, *out))
    return out[0][:m], out[1][:m], out[2][:m], out[3][:m]


def _first_sign(coefficients: list[Fraction]) -> int:
    for value in coefficients:
        if value:
            return 1 if value > 0 else -1
    return 0


def rectangle_spans_rational(a: ArrayLike, b: ArrayLike, line_width: ArrayLike, sample: tuple[float, float] = (0.5, 0.5),
                             tie: TieRule = "top-left", *, width: int, height: int) -> Spans:
    """The same spans as :func:`rectangle_spans` by brute force in rational arithmetic:
    every sample p of the viewport moved symbolically to q = p + delta(eps) -- the tie rule's
    (tx*eps, ty*eps**2), or (tx*eps**2, ty*eps) y-first -- and tested in the open rectangle
    as polynomials in eps (sign of the lowest nonzero coefficient): dot(d, q - a) > 0,
    dot(-d, q - b) > 0 and w**2 |d|**2 / 4 - cross(d, q - a)**2 > 0. Any finite float."""
    a_arr, b_arr, widths, keep, convention, width, height = _rect_prepare(a, b, line_width, sample, tie, width, height)
    sx, sy = (Fraction(v) for v in convention.sample)
    tx, ty, y_first = convention.tie_perturbation
    ex = (Fraction(0), Fraction(tx)) if y_first else (Fraction(tx), Fraction(0))  # (eps, eps**2) parts of q - p
    ey = (Fraction(ty), Fraction(0)) if y_first else (Fraction(0), Fraction(ty))
    out: list[tuple[int, int, int, int]] = []
    for s in np.flatnonzero(keep):
        ax, ay, bx, by = (Fraction(float(v)) for v in (*a_arr[s], *b_arr[s]))
        w = Fraction(float(widths[s]))
        dx, dy = bx - ax, by - ay
        if dx == 0 and dy == 0:
            continue
        big_h = w * w * (dx * dx + dy * dy) / 4
        covered = []
        for j in range(height):
            row = []
            for i in range(width):
                px, py = i + sx, j + sy
                cap_a = [dx * (px - ax) + dy * (py - ay), dx * ex[0] + dy * ey[0], dx * ex[1] + dy * ey[1]]
                cap_b = [-dx * (px - bx) - dy * (py - by), -dx * ex[0] - dy * ey[0], -dx * ex[1] - dy * ey[1]]
                c0 = dx * (py - ay) - dy * (px - ax)
                c1 = dx * ey[0] - dy * ex[0]
                c2 = dx * ey[1] - dy * ex[1]
                side = [big_h - c0 * c0, -2 * c0 * c1, -(c1 * c1 + 2 * c0 * c2), -2 * c1 * c2, -c2 * c2]
                row.append(_first_sign(cap_a) > 0 and _first_sign(cap_b) > 0 and _first_sign(side) > 0)
            covered.append(row)
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)
