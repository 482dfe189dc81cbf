"""Exact oracles for the diamond-exit rules of aliased lines (Direct3D's and GL's), width 1 and
GL's wide lines, with their rational references; spans as in :mod:`harness.oracle.line_spans`.

Diamond exit (:func:`diamond_exit_spans`)
    Sources: the Direct3D 11.3 functional specification, section 3.4.3 "Aliased Line
    Rasterization Rules" (microsoft/DirectX-Specs, ``d3d/archive/D3D11_3_FunctionalSpec.htm``,
    whose rules are the text of its figure ``images/d3d11/D3D11_3_LineRast.png``; the same
    words are in the Direct3D 10 "Rasterization Rules" page), and the OpenGL specification,
    section 3.4.1 "Basic Line Segment Rasterization" (1.1 to 1.5; 14.5.1 in 4.6).

    * The diamond of pixel (i, j) is |x - xc| + |y - yc| < 1/2 around its centre
      (xc, yc) = (i + 1/2, j + 1/2). A segment is *x-major* when -1 <= slope <= 1, i.e.
      |by - ay| <= |bx - ax| (decided exactly; a zero-length segment counts as x-major),
      and *y-major* otherwise. For an x-major segment the diamond's *test area* D (D3D11
      3.4.3; +y is down on the render target) includes the diamond's lower-left and
      lower-right edges and its bottom corner (xc, j + 1), and excludes its upper-left and
      upper-right edges and its top, left and right corners. For a y-major segment D also
      includes the right corner (i + 1, yc). With the diamond's edge functions oriented
      clockwise on screen (top -> right -> bottom -> left corner, positive inside):
      ``D = {E_ul > 0, E_ur > 0, E_lr >= 0, E_ll >= 0}`` (plus the right corner, y-major).
      Diamonds touch only at corners, and each shared corner belongs to at most one of the
      two (a bottom corner to the upper pixel; a right corner, y-major, to the left pixel):
      a point lies in at most one test area. So a line through a bottom corner draws the
      upper pixel, and a y-major line through a right corner the left one.
    * "A line covers a pixel if the line *exits* the pixel's diamond test area, when
      traveling along the line from the start towards the end" (D3D11 3.4.3). D is convex,
      so the segment meets it in an interval, and it exits D exactly when it meets D and its
      end point b is not in D: pixel f is drawn when ``segment & D_f != {}`` and
      ``b not in D_f``. That is GL's wording ("produces those fragments f for which the
      segment intersects R_f, except if p_b is contained in R_f"): the start pixel is drawn
      when the segment leaves it, the end pixel is not, so a strip's shared vertex is drawn
      once (by the segment that starts there). A zero-length segment draws nothing.
      ``last_pixel=True`` draws every pixel whose test area the segment meets (the end
      pixel too; then a zero-length segment draws the pixel whose D holds it).
    * GL's rule (``rule="diamond-exit-gl"``; OpenGL 4.6 core, section 14.5.1 "Basic Line
      Segment Rasterization"; 3.4.1 in 1.1 to 1.5) asks the same two questions of the open
      diamond ``R_f = {|x - x_f| + |y - y_f| < 1/2}``, but first perturbs both end points
      to ``p - (eps, eps**2)`` ("eps is chosen to be so small that rasterizing the line
      segment produces the same fragments when delta is substituted for eps for any
      0 < delta <= eps"). Window y is taken as rastercheck's y (row y = window row y, as
      the GL adapters and the triangle tie rules read it). Decided symbolically, as the
      triangle tie rules are: a point's test ``|dx| + |dy| < 1/2`` at p - (eps, eps**2)
      holds on the diamond's *right* edges and right corner (their x gradient is
      negative: the move by -eps brings the point inside) and nowhere else on the
      boundary -- GL's point test area, the same for x- and y-major lines. The segment
      moved meets the open diamond of pixel (i, j) exactly when the unmoved one meets the
      diamond moved by +(eps, eps**2): its vertical diagonal x = xc + eps is tiled by the
      column's open diamonds (j + eps**2, j + 1 + eps**2), and an x-major line crosses it
      at y(xc) + slope*eps, never on a corner: row floor(y(xc)), or, when y(xc) is an
      integer n, row n where y grows with x (slope > 0) and n - 1 otherwise (a horizontal
      line on a row boundary draws the row above, as D3D's). A y-major line crosses the
      horizontal diagonal y = yc + eps**2 at x(yc) + eps**2 * dx/dy, left of the corner
      i + eps: column ceil(x(yc)) - 1, D3D's. The segment reaches the moved diagonal when
      ``r_u <= u_c < q_u`` (not when it ends on it). So GL parts from D3D on segments along
      a diamond's edges (45-degree lines half a pixel off the centres: D3D owns the lower
      edges, GL the right ones), through the corner two diamonds of a column share, on an
      x-major line whose y grows with x (GL: the lower pixel, D3D: the upper), and with
      end points on a diamond's boundary (a right corner is in GL's test area for every
      line, D3D's for y-major ones only; a bottom corner and the lower-left edge are in
      D3D's, not GL's). Mesa's llvmpipe (below) reads ``< 0.5f`` as GL's open diamond but
      does not perturb.
    * Implementations: Mesa's llvmpipe (``src/gallium/drivers/llvmpipe/lp_setup_line.c``)
      asks the same two questions in float -- ``draw_start`` when the start lies inside
      the open diamond (``fabsf(x1diff) + fabsf(y1diff) < 0.5f``) or the segment crosses
      the diamond's diagonal after it, ``draw_end`` false when the end lies inside -- and
      trims a one-pixel-wide parallelogram to match; softpipe (``sp_setup.c``,
      ``sp_setup_line``) runs integer Bresenham on truncated end points and omits the last
      pixel.

    Method (why one pixel per major step and O(length) per segment). For an x-major line
    (|slope| <= 1) and a column i, the line meets D(i, j) only for the one row j with
    ``j < y(xc) <= j + 1``, y(xc) the line's height at the column centre xc = i + 1/2:
    along the diamond's vertical diagonal the test areas of a column tile the line x = xc
    with half-open pieces (j, j + 1] (top corners out, bottom corners in), and
    ``|t + m*u| + |u| >= |t|`` for |m| <= 1 shows that a line missing the diagonal misses
    the diamond (a line along a lower edge meets that edge; along an upper edge, nothing).
    y-major lines likewise meet one D per row, the horizontal diagonal tiled by (i, i + 1]
    (left corners out, right corners in). So the kernel walks the major axis: at each
    column (row) centre it finds the one candidate minor cell exactly (a float estimate
    settled by :func:`harness.geometry.exact.orient2d_sign` against the cell's grid points). The
    line meets that D in an interval containing the diagonal point P, so the *segment*
    meets it when P lies on the segment (the column centre lies between the end points'
    x: a float comparison), and otherwise exactly when the end point nearer to P lies in
    D -- four orient2d signs against the diamond's edges, no intersection points. The end
    point b is tested once. Coordinates must be zero or of magnitude in [2**-450, 2**450]
    (:data:`harness.geometry.exact.SAFE_MIN`/:data:`~harness.geometry.exact.SAFE_MAX`); beyond, ValueError
    names the segment (:func:`diamond_exit_spans_rational` takes any finite float).

    Runs (issue 35). The kernel decides whole runs, not cells: every major-axis cell whose
    centre the segment reaches meets it, so there an x-major line's pixels of one row are
    the columns between the line's crossings of the row's top and bottom, and a y-major
    line's one pixel per row is the cell of its height at the row centre. Both come from
    a float filter with a proven margin (:data:`_DIAMOND_FILTER`): a crossing or height
    strictly between two integers decides; within the margin of one (a tie: a line
    through a corner or a cell centre), the exact predicate above decides. The one or two
    cells at each end, and the end pixel, are tested exactly as before. Rows are written
    by branch-free loops (numba vectorizes them), the cell-by-cell walk where the filter
    hesitates. ``_diamond_exit_spans_reference`` keeps the cell-by-cell kernel; the tests
    compare the two span for span.

Wide diamond lines (:func:`diamond_wide_spans`)
    ``LineRule(wide="replicate")``: GL's wide lines (OpenGL 4.6, 14.5.2 "Other Line Segment
    Features"; Direct3D 10+ has no wide aliased lines): an integer width w, the segment
    moved by -(w - 1)/2 along its minor axis drawn by the width-1 diamond rule, each
    fragment replicated w times along that axis, the width-1 one first (rows y .. y + w - 1
    of an x-major segment; window y taken as rows). GL rounds a width to the nearest
    integer first; here a non-integer width is undefined (a rasterizer refuses it).

:func:`diamond_exit_spans_rational` and :func:`diamond_wide_spans_rational` are the slow
references, in :class:`fractions.Fraction` arithmetic for any finite float (small viewports
and coordinates only): they decide every pixel of the viewport from the definitions above.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import (
    DIAMOND_RULES,
)
from harness.contract.scenes import MAX_VIEWPORT
from harness.geometry.exact import SAFE_MAX, SAFE_MIN, _two_sum, frozen, orient2d_sign
from harness.geometry.spans import expand
from harness.oracle.line_spans import (
    Spans,
    _as_spans,
    _beyond,
    _check_range,
    _clamp_index,
    _empty,
    _endpoints,
    _spans_from_mask,
    _viewport,
    emit_pixel,
    span_buffers,
)

# -- diamond exit ------------------------------------------------------------------------------


@numba.njit(cache=True)
def is_x_major(ax, ay, bx, by):  # type: ignore[no-untyped-def]
    """|bx - ax| >= |by - ay|, exactly (a zero-length segment is x-major)."""
    dx, ex = _two_sum(bx, -ax)
    dy, ey = _two_sum(by, -ay)
    # Rounding is monotone: a strict order of the rounded magnitudes is the exact order.
    if abs(dx) != abs(dy):
        return abs(dx) > abs(dy)
    if dx == 0.0:
        return True
    # Equal rounded magnitudes: |d| = |hi| + sign(hi)*lo exactly, so compare the tails.
    tail_x = ex if dx > 0.0 else -ex
    tail_y = ey if dy > 0.0 else -ey
    return tail_x >= tail_y


@numba.njit(cache=True)
def _in_test_area(px, py, i, j, y_major):  # type: ignore[no-untyped-def]
    """Whether point p lies in the diamond test area D of pixel (i, j) (D3D11 3.4.3)."""
    fi = float(i)
    fj = float(j)
    xc = fi + 0.5
    yc = fj + 0.5
    # y-major lines: the right corner belongs to D as well.
    if y_major and px == fi + 1.0 and py == yc:
        return True
    # Corners top (xc, j), right (i+1, yc), bottom (xc, j+1), left (i, yc), clockwise on
    # screen: each edge function is positive inside. Upper edges and their corners are out
    # (strict), lower edges and the bottom corner in.
    if orient2d_sign(fi, yc, xc, fj, px, py) <= 0:  # upper-left
        return False
    if orient2d_sign(xc, fj, fi + 1.0, yc, px, py) <= 0:  # upper-right
        return False
    if orient2d_sign(fi + 1.0, yc, xc, fj + 1.0, px, py) < 0:  # lower-right
        return False
    return orient2d_sign(xc, fj + 1.0, fi, yc, px, py) >= 0  # lower-left


@numba.njit(cache=True)
def _in_gl_area(px, py, i, j):  # type: ignore[no-untyped-def]
    """Whether point p lies in GL's diamond of pixel (i, j) once moved by -(eps, eps**2)
    (OpenGL 4.6, 14.5.1): the open diamond with its right edges and right corner, which the
    move brings inside; its left edges and its top, bottom and left corners stay out."""
    fi = float(i)
    fj = float(j)
    xc = fi + 0.5
    yc = fj + 0.5
    # the edge functions of _in_test_area (positive inside); an edge whose x gradient is
    # negative (a right edge) grows under the move by -eps in x: it owns its points
    if orient2d_sign(fi, yc, xc, fj, px, py) <= 0:  # upper-left
        return False
    if orient2d_sign(xc, fj + 1.0, fi, yc, px, py) <= 0:  # lower-left
        return False
    if orient2d_sign(xc, fj, fi + 1.0, yc, px, py) < 0:  # upper-right
        return False
    return orient2d_sign(fi + 1.0, yc, xc, fj + 1.0, px, py) >= 0  # lower-right


@numba.njit(cache=True, inline="always")
def _in_area(px, py, i, j, y_major, gl):  # type: ignore[no-untyped-def]
    """The test area of the diamond rule: GL's (``gl``) or D3D11's."""
    if gl:
        return _in_gl_area(px, py, i, j)
    return _in_test_area(px, py, i, j, y_major)


@numba.njit(cache=True)
def area_holding(px, py, y_major, gl, width, height):  # type: ignore[no-untyped-def]
    """The viewport pixel whose test area under the diamond rule (GL's when ``gl``, else
    D3D11's: :func:`diamond_holding`) holds p, as (i, j, found). GL's moved diamond of
    (i, j) lies in i < x <= i + 1 and j < y <= j + 1."""
    if not gl:
        return diamond_holding(px, py, y_major, width, height)
    if not (-1.0 < px < width + 1.0 and -1.0 < py < height + 1.0):
        return -1, -1, False
    i = int(math.ceil(px)) - 1
    j = int(math.ceil(py)) - 1
    if i < 0 or i >= width or j < 0 or j >= height:
        return -1, -1, False
    return i, j, _in_gl_area(px, py, i, j)


@numba.njit(cache=True)
def diamond_holding(px, py, y_major, width, height):  # type: ignore[no-untyped-def]
    """The viewport pixel whose test area holds p, as (i, j, found). D(i, j) lies in
    i < x < i + 1 (x-major) or i < x <= i + 1 (y-major), and j < y <= j + 1."""
    if not (-1.0 < px < width + 1.0 and -1.0 < py < height + 1.0):
        return -1, -1, False
    if y_major:
        i = int(math.ceil(px)) - 1
    else:
        if px == math.floor(px):
            return -1, -1, False
        i = int(math.floor(px))
    j = int(math.ceil(py)) - 1
    if i < 0 or i >= width or j < 0 or j >= height:
        return -1, -1, False
    return i, j, _in_test_area(px, py, i, j, y_major)


@numba.njit(cache=True, inline="always")
def _at_or_below(rx, ry, qx, qy, uc, n, x_major):  # type: ignore[no-untyped-def]
    """Whether the line r -> q (q after r along the major axis) crosses the major coordinate
    uc at minor coordinate <= n, exactly."""
    if x_major:
        # orient2d(r, q, (uc, n)) = (qx - rx) * (n - y(uc)), qx > rx
        return orient2d_sign(rx, ry, qx, qy, uc, float(n)) >= 0
    # orient2d(r, q, (n, uc)) = (qy - ry) * (x(uc) - n), qy > ry
    return orient2d_sign(rx, ry, qx, qy, float(n), uc) <= 0


@numba.njit(cache=True)
def _minor_cell(rx, ry, qx, qy, uc, x_major, limit, estimate):  # type: ignore[no-untyped-def]
    """ceil(v(uc)) - 1, the minor cell m with m < v(uc) <= m + 1, clamped to [-1, limit]:
    the smallest n in [0, limit + 1] with v(uc) <= n, minus one (n = limit + 1 when none).
    Starts from the float estimate, then steps or bisects with the exact predicate."""
    n = min(max(estimate, 0), limit + 1)
    if n <= limit and not _at_or_below(rx, ry, qx, qy, uc, n, x_major):
        n += 1
        if n > limit or _at_or_below(rx, ry, qx, qy, uc, n, x_major):
            return n - 1
        lo, hi = n, limit + 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _at_or_below(rx, ry, qx, qy, uc, mid, x_major):
                hi = mid
            else:
                lo = mid
        return hi - 1
    if n == 0 or not _at_or_below(rx, ry, qx, qy, uc, n - 1, x_major):
        return n - 1
    n -= 1
    if n == 0 or not _at_or_below(rx, ry, qx, qy, uc, n - 1, x_major):
        return n - 1
    lo, hi = -1, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _at_or_below(rx, ry, qx, qy, uc, mid, x_major):
            hi = mid
        else:
            lo = mid
    return hi - 1


@numba.njit(cache=True)
def _diamond_walk(ax, ay, bx, by, width, height):  # type: ignore[no-untyped-def]
    """The major-axis cells a segment's walk visits: (x_major, r, q, lo, hi) with r, q its
    end points ordered along the major axis and lo..hi the cells (clamped to the
    viewport) whose test areas it may meet: x-major D(i, .) lies in i < x < i + 1, y-major
    D(., j) in j < y <= j + 1, so floor(min) - 1 .. floor(max) covers both."""
    x_major = is_x_major(ax, ay, bx, by)
    if x_major:
        if ax <= bx:
            rx, ry, qx, qy = ax, ay, bx, by
        else:
            rx, ry, qx, qy = bx, by, ax, ay
        ru, qu, extent = rx, qx, width
    else:
        if ay <= by:
            rx, ry, qx, qy = ax, ay, bx, by
        else:
            rx, ry, qx, qy = bx, by, ax, ay
        ru, qu, extent = ry, qy, height
    lo = _clamp_index(ru, 0, extent) - 1
    lo = max(lo, 0)
    hi = _clamp_index(qu, -1, extent - 1)
    return x_major, rx, ry, qx, qy, lo, hi


@numba.njit(cache=True)
def _diamond_capacity(a, b, keep, width, height):  # type: ignore[no-untyped-def]
    """An upper bound on the spans each segment writes: the cells its walk visits."""
    total = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        if a[s, 0] == b[s, 0] and a[s, 1] == b[s, 1]:
            total += 1
            continue
        _, _, _, _, _, lo, hi = _diamond_walk(a[s, 0], a[s, 1], b[s, 0], b[s, 1], width, height)
        total += max(hi - lo + 1, 0)
    return total


@numba.njit(cache=True)
def _diamond_kernel(a, b, keep, width, height, last_pixel, gl, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Every segment's diamond-exit pixels as spans, segment by segment, rows ascending,
    under D3D11's test area or (``gl``) GL's perturbed end points. Returns the number of
    spans written."""
    n = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        first = n
        if ax == bx and ay == by:
            # Zero length: it never exits; with the last pixel drawn, the pixel holding it.
            if last_pixel:
                # np.bool_, not the literal False: numba compiles a callee once per literal argument
                i, j, found = area_holding(ax, ay, np.bool_(False), gl, width, height)
                if found:
                    n = emit_pixel(s, j, i, out_s, out_y, out_x0, out_x1, n, first)
            continue
        x_major, rx, ry, qx, qy, lo, hi = _diamond_walk(ax, ay, bx, by, width, height)
        if lo > hi:
            continue
        y_major = not x_major
        # The exit rule: the pixel whose test area holds the end point b is not left.
        bi, bj, b_inside = area_holding(bx, by, y_major, gl, width, height)
        skip_end = b_inside and not last_pixel
        if x_major:
            ru, rv, qu, qv, limit = rx, ry, qx, qy, height
        else:
            ru, rv, qu, qv, limit = ry, rx, qy, qx, width
        slope = (qv - rv) / (qu - ru)
        # Walk so that rows come out ascending: x-major lines going up walk right to left.
        step = -1 if (x_major and qv < rv) else 1
        k = lo if step == 1 else hi
        for _ in range(hi - lo + 1):
            uc = k + 0.5
            k_now = k
            k += step
            v_est = rv + (uc - ru) * slope
            estimate = 0 if not v_est > -1.0 else (limit + 1 if v_est > limit + 1.0 else int(math.ceil(v_est)))
            m = _minor_cell(rx, ry, qx, qy, uc, x_major, limit, estimate)
            if gl and x_major and qv > rv and m + 1 <= limit and orient2d_sign(rx, ry, qx, qy, uc, float(m + 1)) == 0:
                # GL, x-major, y growing with x, through the corner at height m + 1: the
                # moved diagonal x = uc + eps is crossed at m + 1 + slope*eps, below the
                # corner m + 1 + eps**2: the lower pixel's
                m += 1
            if m < 0 or m >= limit:
                continue
            i, j = (k_now, m) if x_major else (m, k_now)
            # The segment meets D when it reaches the diagonal point at the cell centre
            # (GL: the diagonal moved by +eps, so not when the segment ends at it);
            # short of it, only through the end point nearer to it.
            if uc < ru:
                meets = _in_area(rx, ry, i, j, y_major, gl)
            elif uc > qu or (gl and uc == qu):
                meets = _in_area(qx, qy, i, j, y_major, gl)
            else:
                meets = True
            if not meets or (skip_end and i == bi and j == bj):
                continue
            n = emit_pixel(s, j, i, out_s, out_y, out_x0, out_x1, n, first)
    return n


# -- diamond exit as runs: a float filter decides, the exact predicate settles near ties ---------

# The float filters' margins. A cell's height v(uc) = rv + (uc - ru) * slope takes five
# roundings (uc - ru, the two differences and the quotient of the slope, the product) and a
# sixth for the sum: |error| <= 2**-53 * (|v| + 5.01 |product|) to first order; a boundary's
# column t* = ru + (n - rv) * (du / dv) - c takes six: <= 6 * 2**-53 * (|ucs| + |t| + |P|).
# The margin is 2**-49 = 16 * 2**-53 times the same magnitudes, above twice either bound (the
# margin's own rounding and that of v +- margin stay inside the slack), plus 2**-1000 for a
# product that underflows (coordinates >= 2**-450 keep every other term normal).
_DIAMOND_FILTER = 2.0**-49
_DIAMOND_TINY = 2.0**-1000
# the filters only convert floats below this magnitude to integers
_DIAMOND_INT_SAFE = 2.0**40


@numba.njit(cache=True)
def _in_area_fast(px, py, i, j, y_major, gl):  # type: ignore[no-untyped-def]
    """:func:`_in_area`, a float filter first: d = |px - xc| + |py - yc| is computed with a
    relative error below 3 * 2**-53, so d < 1/2 - 2**-48 puts p in the open diamond (in
    every test area) and d > 1/2 + 2**-48 outside the closed one (in none); between, the
    exact edge tests."""
    d = abs(px - (i + 0.5)) + abs(py - (j + 0.5))
    if d < 0.5 - 2.0**-48:
        return True
    if d > 0.5 + 2.0**-48:
        return False
    return _in_area(px, py, i, j, y_major, gl)


@numba.njit(cache=True)
def _area_holding_fast(px, py, y_major, gl, width, height):  # type: ignore[no-untyped-def]
    """:func:`area_holding` with the point test of :func:`_in_area_fast`."""
    if not (-1.0 < px < width + 1.0 and -1.0 < py < height + 1.0):
        return -1, -1, False
    if gl or y_major:  # GL's moved diamond and D3D's y-major test area: i < x <= i + 1
        i = int(math.ceil(px)) - 1
    else:  # D3D's x-major test area: i < x < i + 1
        if px == math.floor(px):
            return -1, -1, False
        i = int(math.floor(px))
    j = int(math.ceil(py)) - 1
    if i < 0 or i >= width or j < 0 or j >= height:
        return -1, -1, False
    return i, j, _in_area_fast(px, py, i, j, y_major, gl)


@numba.njit(cache=True)
def _exact_cell(rx, ry, qx, qy, uc, x_major, limit, v_est, gl_rising):  # type: ignore[no-untyped-def]
    """The minor cell of the major coordinate uc, exactly, clamped to [-1, limit] (the
    reference kernel's steps: :func:`_minor_cell` from the float estimate, and GL's
    lower pixel on a corner when ``gl_rising``)."""
    estimate = 0 if not v_est > -1.0 else (limit + 1 if v_est > limit + 1.0 else int(math.ceil(v_est)))
    m = _minor_cell(rx, ry, qx, qy, uc, x_major, limit, estimate)
    if gl_rising and m + 1 <= limit and orient2d_sign(rx, ry, qx, qy, uc, float(m + 1)) == 0:
        # GL, x-major, y growing with x, through the corner at height m + 1: the moved
        # diagonal x = uc + eps is crossed at m + 1 + slope*eps, below the corner
        # m + 1 + eps**2: the lower pixel's
        m += 1
    return m


@numba.njit(cache=True, inline="always")
def _cell(rx, ry, qx, qy, ru, rv, slope, uc, x_major, limit, gl_rising):  # type: ignore[no-untyped-def]
    """The minor cell at major coordinate uc (as :func:`_exact_cell`, unclamped when the
    filter decides): v(uc) strictly between two integers f and f + 1 is cell f under
    every rule (the rules part only on an integer v); otherwise the exact steps."""
    prod = (uc - ru) * slope
    v_est = rv + prod
    margin = _DIAMOND_FILTER * (abs(v_est) + abs(prod)) + _DIAMOND_TINY
    low = v_est - margin
    high = v_est + margin
    if abs(v_est) < _DIAMOND_INT_SAFE and margin < 0.25:
        f = math.floor(low)
        if low > f and high < f + 1.0:
            return int(f)
    elif low > limit + 1.0:  # far past the last row (or column)
        return limit
    elif high < -1.0:  # far before the first
        return -1
    return _exact_cell(rx, ry, qx, qy, uc, x_major, limit, v_est, gl_rising)


@numba.njit(cache=True, inline="always")
def _beyond_boundary(rx, ry, qx, qy, uc, n, gl_rising):  # type: ignore[no-untyped-def]
    """Whether an x-major line's cell at column centre uc is n or more, exactly: v(uc) > n
    (D3D's cells and GL's on a falling line: ceil(v) - 1), v(uc) >= n (GL's on a rising
    line: floor(v)). orient2d(r, q, (uc, n)) = (qx - rx) * (n - v(uc)), qx > rx."""
    o = orient2d_sign(rx, ry, qx, qy, uc, float(n))
    return o <= 0 if gl_rising else o < 0


@numba.njit(cache=True)
def _first_beyond(rx, ry, qx, qy, ru, rv, inv, n, c, step, t0, count, gl_rising):  # type: ignore[no-untyped-def]
    """The first walk index t in [t0, count) whose column k = c - 1/2 + step*t has cell >= n
    (``count`` when none), on an x-major line whose v grows along the walk (every cell
    before t0 is below n). The float filter places the line's crossing of height n,
    t* = (ru + (n - rv) * inv - c) * step, strictly between two integers, else the exact
    predicate (:func:`_beyond_boundary`) decides near the estimate or by bisection."""
    a = n - rv
    big_p = a * inv
    ucs = ru + big_p
    t_est = (ucs - c) * step
    margin = _DIAMOND_FILTER * (abs(ucs) + abs(t_est) + abs(big_p)) + _DIAMOND_TINY
    if t_est - margin > count:  # beyond the walk (also an infinite estimate)
        return count
    if abs(t_est) < _DIAMOND_INT_SAFE and margin < 0.25:
        f = math.floor(t_est - margin)
        if t_est - margin > f and t_est + margin < f + 1.0:
            # t* in (f, f + 1): cells from f + 1 on are n or more, strictly or not
            return min(max(int(f) + 1, t0), count)
        guess = int(math.floor(t_est))
        for g in (guess, guess + 1, guess + 2):
            if t0 <= g <= count:
                here = g == count or _beyond_boundary(rx, ry, qx, qy, c + step * g, n, gl_rising)
                if here and (g == t0 or not _beyond_boundary(rx, ry, qx, qy, c + step * (g - 1), n, gl_rising)):
                    return g
    lo, hi = t0, count  # the answer lies in [lo, hi]
    while lo < hi:
        mid = (lo + hi) // 2
        if _beyond_boundary(rx, ry, qx, qy, c + step * mid, n, gl_rising):
            hi = mid
        else:
            lo = mid + 1
    return lo


@numba.njit(cache=True, inline="always")
def _put(s, y, x0, x1, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """Write span n (an unsigned index: no wraparound test, stores 3x faster). Returns n + 1."""
    u = np.uint64(n)
    out_s[u] = s
    out_y[u] = y
    out_x0[u] = x0
    out_x1[u] = x1
    return n + 1


@numba.njit(cache=True, inline="always")
def _emit_run(s, y, x0, x1, out_s, out_y, out_x0, out_x1, n, first):  # type: ignore[no-untyped-def]
    """Add pixels x0 <= x < x1 of row y (x1 > x0), merged into the last span when adjacent
    on its row, as :func:`emit_pixel` one pixel at a time. Returns the span count."""
    if n > first:
        last = np.uint64(n - 1)
        if out_y[last] == y:
            if out_x1[last] == x0:
                out_x1[last] = x1
                return n
            if out_x0[last] == x1:
                out_x0[last] = x0
                return n
    u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
    out_s[u] = s
    out_y[u] = y
    out_x0[u] = x0
    out_x1[u] = x1
    return n + 1


@numba.njit(cache=True)
def _diamond_column(s, k, rx, ry, qx, qy, ru, rv, qu, slope, x_major, limit, gl, gl_rising, skip_end, bi, bj,  # type: ignore[no-untyped-def]
                    out_s, out_y, out_x0, out_x1, n, first):
    """One major-axis cell k near an end of the segment, as the reference kernel decides it:
    the segment meets the test area there when it reaches the diagonal point at the cell
    centre (GL: the diagonal moved by +eps, so not when the segment ends at it); short of
    it, only through the end point nearer to it."""
    uc = k + 0.5
    m = _cell(rx, ry, qx, qy, ru, rv, slope, uc, x_major, limit, gl_rising)
    if m < 0 or m >= limit:
        return n
    i, j = (k, m) if x_major else (m, k)
    y_major = not x_major
    if uc < ru:
        meets = _in_area_fast(rx, ry, i, j, y_major, gl)
    elif uc > qu or (gl and uc == qu):
        meets = _in_area_fast(qx, qy, i, j, y_major, gl)
    else:
        meets = True
    if not meets or (skip_end and i == bi and j == bj):
        return n
    return _emit_run(s, j, i, i + 1, out_s, out_y, out_x0, out_x1, n, first)


@numba.njit(cache=True)
def _y_major_vector(s, ka, kb, ru, rv, slope, margin, limit, skip_end, bi, bj, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """Rows ka..kb of a y-major segment written as spans n, n + 1, ... in one branch-free
    loop (numba stores them a vector at a time), each cell from the float filter of
    :func:`_y_major_cells`. True when the filter decided every row, each cell lies in the
    viewport and none is the end pixel left out; else False, and the caller decides the
    rows one by one (overwriting these spans)."""
    ok = True
    for i in range(kb - ka + 1):
        k = ka + i
        v_est = rv + (k + 0.5 - ru) * slope
        low = v_est - margin
        f = np.floor(low)
        ok &= (low > f) & (v_est + margin < f + 1.0)
        m = int(f)
        ok &= (m >= 0) & (m < limit) & ((m != bi) | (k != bj) | (not skip_end))
        u = np.uint64(n + i)
        out_s[u] = s
        out_y[u] = k
        out_x0[u] = m
        out_x1[u] = m + 1
    return ok


@numba.njit(cache=True)
def _y_major_cells(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, limit, gl_rising, skip_end, bi, bj,  # type: ignore[no-untyped-def]
                   out_s, out_y, out_x0, out_x1, n):
    """The pixels of a y-major segment in the rows ka..kb whose centre it reaches (all meet
    it), one per row, rows ascending: the cell from the float filter of :func:`_cell`
    with one margin for the segment, else exactly. The end pixel (bi, bj) is left out when
    ``skip_end``. Returns the span count."""
    x_major = np.bool_(False)
    # One margin for every row: |prod| <= p_max, |v| <= |rv| + p_max (the filter of
    # :func:`_cell` with the row's magnitudes bounded by the segment's).
    p_max = max(abs(ka + 0.5 - ru), abs(kb + 0.5 - ru)) * abs(slope) * (1.0 + 2.0**-40)
    margin = _DIAMOND_FILTER * (abs(rv) + 2.0 * p_max) + _DIAMOND_TINY
    fast = abs(rv) + p_max < _DIAMOND_INT_SAFE and margin < 0.25
    if not fast:
        for k in range(ka, kb + 1):
            m = _cell(rx, ry, qx, qy, ru, rv, slope, k + 0.5, x_major, limit, gl_rising)
            if 0 <= m < limit and not (skip_end and m == bi and k == bj):
                n = _put(s, k, m, m + 1, out_s, out_y, out_x0, out_x1, n)
        return n
    if skip_end and ka <= bj <= kb:  # the end pixel's row on its own, the rows either side by vectors
        n = _y_major_fast(s, ka, bj - 1, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, out_s, out_y, out_x0,
                          out_x1, n)
        n = _y_major_rows(s, bj, bj, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, skip_end, bi, bj,
                          out_s, out_y, out_x0, out_x1, n)
        return _y_major_fast(s, bj + 1, kb, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, out_s, out_y, out_x0,
                             out_x1, n)
    return _y_major_fast(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, out_s, out_y, out_x0, out_x1, n)


@numba.njit(cache=True)
def _y_major_fast(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """Rows ka..kb (none holding a pixel left out) by :func:`_y_major_vector`, else one by
    one (:func:`_y_major_rows`). Returns the span count."""
    no = np.bool_(False)  # np.bool_, not the literal False: numba compiles a callee once per literal argument
    if ka > kb or _y_major_vector(s, ka, kb, ru, rv, slope, margin, limit, no, -1, -1, out_s, out_y, out_x0, out_x1, n):
        return n + max(kb - ka + 1, 0)
    return _y_major_rows(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, no, -1, -1,
                         out_s, out_y, out_x0, out_x1, n)


@numba.njit(cache=True)
def _y_major_rows(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, margin, limit, gl_rising, skip_end, bi, bj,  # type: ignore[no-untyped-def]
                  out_s, out_y, out_x0, out_x1, n):
    """Rows ka..kb one by one: the float filter of :func:`_y_major_cells`, else exactly.
    Returns the span count."""
    x_major = np.bool_(False)
    uc = ka + 0.5
    for k in range(ka, kb + 1):
        v_est = rv + (uc - ru) * slope
        low = v_est - margin
        f = np.floor(low)  # a float: one conversion to int, once decided
        if low > f and v_est + margin < f + 1.0:
            m = int(f)  # v strictly between f and f + 1: cell f
        else:
            m = _exact_cell(rx, ry, qx, qy, uc, x_major, limit, v_est, gl_rising)
        if 0 <= m < limit and not (skip_end and m == bi and k == bj):
            # a row of its own: no span to merge with
            n = _put(s, k, m, m + 1, out_s, out_y, out_x0, out_x1, n)
        uc += 1.0  # exact: k + 1/2 below 2**52
    return n


@numba.njit(cache=True, inline="always")
def _crossing(ru, rv, inv, margin, c, step, count, n):  # type: ignore[no-untyped-def]
    """The first walk index whose cell is n or more, from the float filter of
    :func:`_x_major_runs` (clamped to [1, count - 1], where such an index lies when the
    cells run from below n to n or more), and whether the filter placed it."""
    t_est = (ru + (n - rv) * inv - c) * step
    f = np.floor(t_est - margin)
    placed = (t_est - margin > f) & (t_est + margin < f + 1.0) & (abs(t_est) <= count + 1.0)
    return min(max(int(f) + 1, 1), count - 1), placed


@numba.njit(cache=True)
def _x_major_vector(s, k_first, step, count, c, ru, rv, inv, margin, m_first, m_last, r0, r1,  # type: ignore[no-untyped-def]
                    out_s, out_y, out_x0, out_x1, n):
    """Rows r0..r1 of an x-major segment's reached columns (walk indices 0 .. count - 1,
    cells m_first at the first and m_last at the last) as spans n, n + 1, ... in
    branch-free loops numba stores a vector at a time: row m runs from the crossing of
    its top (walk index 0 for the first row) to that of its bottom (count for the last),
    each placed by the float filter of :func:`_x_major_runs` (:func:`_crossing`); the
    crossings go to ``out_x0`` first, the spans next. True when the filter placed every
    crossing used; else False, and the caller walks the rows one by one (overwriting
    these spans)."""
    rows = r1 - r0 + 1
    ok = True
    # the tops of rows r0..r1: walk indices of the first column of each
    for i in range(rows):
        t, placed = _crossing(ru, rv, inv, margin, c, step, count, r0 + i)
        top = (i == 0) & (r0 == m_first)  # the first row starts at the first column
        ok &= placed | top
        out_x0[np.uint64(n + i)] = t * (not top)
    bottom, placed = _crossing(ru, rv, inv, margin, c, step, count, r1 + 1)
    if r1 == m_last:
        bottom = count
    elif not placed:
        return False
    for i in range(rows):
        u = np.uint64(n + i)
        t_start = out_x0[u]
        t_end = out_x0[u + np.uint64(1)] if i + 1 < rows else bottom
        ok &= t_start < t_end
        a = k_first + step * t_start
        b = k_first + step * (t_end - 1)
        out_s[u] = s
        out_y[u] = r0 + i
        out_x0[u] = min(a, b)
        out_x1[u] = max(a, b) + 1
    return ok


@numba.njit(cache=True, inline="always")
def _left_out(bi, u, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Leave column bi out of span u: True when done (bi outside it, or at an end of a
    span of two pixels or more: trimmed), False when the span would split or vanish."""
    if not out_x0[u] <= bi < out_x1[u]:
        return True
    if out_x1[u] - out_x0[u] < 2:
        return False
    if out_x0[u] == bi:
        out_x0[u] = bi + 1
        return True
    if out_x1[u] == bi + 1:
        out_x1[u] = bi
        return True
    return False


@numba.njit(cache=True)
def _x_major_runs(s, ka, kb, step, rx, ry, qx, qy, ru, rv, du, dv, slope, limit, gl_rising, skip_end, bi, bj,  # type: ignore[no-untyped-def]
                  out_s, out_y, out_x0, out_x1, n, first):
    """The runs of an x-major segment over the columns ka..kb whose centre it reaches (all
    meet it), walked in the direction ``step`` (rows ascending): per row, the column where
    the line crosses the row's bottom (:func:`_first_beyond`) ends the run. The end pixel
    (bi, bj) is left out when ``skip_end``. Returns the span count."""
    count = kb - ka + 1
    k_first = ka if step == 1 else kb
    c = k_first + 0.5  # walk index t is column centre c + step*t
    inv = du / dv if dv != 0.0 else math.inf  # a horizontal line never crosses a row boundary
    # One margin for the crossings within the walk (|t| <= count + 1): there
    # |ucs| <= big_u and |P| <= big_u + |ru| (the filter of :func:`_first_beyond`).
    big_u = abs(c) + count + 2.0
    margin = _DIAMOND_FILTER * (2.0 * big_u + abs(ru) + count + 2.0) + _DIAMOND_TINY
    fast = big_u < _DIAMOND_INT_SAFE and margin < 0.25 and dv != 0.0
    t = 0
    # np.bool_, not the literal True: numba compiles a callee once per literal argument
    m = _cell(rx, ry, qx, qy, ru, rv, slope, c, np.bool_(True), limit, gl_rising)
    if fast:
        m_last = _cell(rx, ry, qx, qy, ru, rv, slope, c + step * (count - 1), np.bool_(True), limit, gl_rising)
        r0, r1 = max(m, 0), min(m_last, limit - 1)
        if r0 > r1:
            return n  # every reached cell above or below the viewport
        simple = not (n > first and out_y[np.uint64(n - 1)] == r0)  # a span the first run may extend
        # the rows by vectors; then the end pixel, if left out, trimmed off its run (else the rows one by one)
        if (simple and _x_major_vector(s, k_first, step, count, c, ru, rv, inv, margin, m, m_last, r0, r1,
                                       out_s, out_y, out_x0, out_x1, n)
                and (not (skip_end and r0 <= bj <= r1) or _left_out(bi, np.uint64(n + bj - r0), out_x0, out_x1))):
            return n + r1 - r0 + 1
    while t < count and m < limit:
        if m < 0:  # above the viewport: on to the first cell of row 0
            t = count if dv == 0.0 else _first_beyond(rx, ry, qx, qy, ru, rv, inv, 0, c, step, t, count, gl_rising)
            m = 0  # |slope| <= 1: the cell grows by at most one per column
            continue
        t_end = -1
        if fast:
            t_est = (ru + (m + 1 - rv) * inv - c) * step
            if abs(t_est) <= count + 1.0:
                f = math.floor(t_est - margin)
                if t_est - margin > f and t_est + margin < f + 1.0:
                    # the crossing t* in (f, f + 1): cells from f + 1 on are m + 1 or more
                    t_end = min(max(f + 1, t + 1), count)
        if t_end < 0:
            t_end = count if dv == 0.0 else _first_beyond(rx, ry, qx, qy, ru, rv, inv, m + 1, c, step, t + 1,
                                                            count, gl_rising)
        # columns of walk indices t .. t_end - 1, in walk order
        if step == 1:
            x_lo, x_hi = k_first + t, k_first + t_end  # [x_lo, x_hi)
        else:
            x_lo, x_hi = k_first - t_end + 1, k_first - t + 1
        if skip_end and m == bj and x_lo <= bi < x_hi:
            if step == 1:
                if x_lo < bi:
                    n = _emit_run(s, m, x_lo, bi, out_s, out_y, out_x0, out_x1, n, first)
                if bi + 1 < x_hi:
                    n = _emit_run(s, m, bi + 1, x_hi, out_s, out_y, out_x0, out_x1, n, first)
            else:
                if bi + 1 < x_hi:
                    n = _emit_run(s, m, bi + 1, x_hi, out_s, out_y, out_x0, out_x1, n, first)
                if x_lo < bi:
                    n = _emit_run(s, m, x_lo, bi, out_s, out_y, out_x0, out_x1, n, first)
        else:
            n = _emit_run(s, m, x_lo, x_hi, out_s, out_y, out_x0, out_x1, n, first)
        t = t_end
        m += 1
    return n


@numba.njit(cache=True)
def _diamond_runs_kernel(a, b, keep, width, height, last_pixel, gl, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """The spans of :func:`_diamond_kernel`, found a run at a time. The major-axis cells
    whose diagonal point the segment reaches (every cell but one or two at each end) all
    meet the segment: there an x-major line's cells form one run per row, from the column
    where the line crosses the row's top to where it crosses its bottom
    (:func:`_first_beyond`), and a y-major line's one cell per row comes from the float
    filter (:func:`_cell`); the cells at the ends go through the reference kernel's test
    (:func:`_diamond_column`), in the same walk order, merged alike. Returns the span count."""
    n = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        first = n
        if ax == bx and ay == by:
            # Zero length: it never exits; with the last pixel drawn, the pixel holding it.
            if last_pixel:
                # np.bool_, not the literal False: numba compiles a callee once per literal argument
                i, j, found = _area_holding_fast(ax, ay, np.bool_(False), gl, width, height)
                if found:
                    n = _emit_run(s, j, i, i + 1, out_s, out_y, out_x0, out_x1, n, first)
            continue
        x_major, rx, ry, qx, qy, lo, hi = _diamond_walk(ax, ay, bx, by, width, height)
        if lo > hi:
            continue
        y_major = not x_major
        # The exit rule: the pixel whose test area holds the end point b is not left.
        bi, bj, b_inside = _area_holding_fast(bx, by, y_major, gl, width, height)
        skip_end = b_inside and not last_pixel
        if x_major:
            ru, rv, qu, qv, limit = rx, ry, qx, qy, height
        else:
            ru, rv, qu, qv, limit = ry, rx, qy, qx, width
        du = qu - ru
        dv = qv - rv
        slope = dv / du
        gl_rising = gl and x_major and qv > rv
        # Walk so that rows come out ascending: x-major lines going up walk right to left.
        step = -1 if (x_major and qv < rv) else 1
        # the cells whose centre the segment reaches: ru <= uc <= qu (GL: uc < qu)
        ka = lo
        while ka <= hi and ka + 0.5 < ru:
            ka += 1
        kb = hi
        while kb >= ka and (kb + 0.5 > qu or (gl and kb + 0.5 == qu)):
            kb -= 1
        # the cells walked before the run of reached ones
        if step == 1:
            for k in range(lo, ka):
                n = _diamond_column(s, k, rx, ry, qx, qy, ru, rv, qu, slope, x_major, limit, gl, gl_rising, skip_end,
                                    bi, bj, out_s, out_y, out_x0, out_x1, n, first)
        else:
            for k in range(hi, kb, -1):
                n = _diamond_column(s, k, rx, ry, qx, qy, ru, rv, qu, slope, x_major, limit, gl, gl_rising, skip_end,
                                    bi, bj, out_s, out_y, out_x0, out_x1, n, first)
        count = kb - ka + 1
        if count > 0 and y_major:
            n = _y_major_cells(s, ka, kb, rx, ry, qx, qy, ru, rv, slope, limit, gl_rising, skip_end, bi, bj,
                               out_s, out_y, out_x0, out_x1, n)
        elif count > 0:
            n = _x_major_runs(s, ka, kb, step, rx, ry, qx, qy, ru, rv, du, dv, slope, limit, gl_rising, skip_end, bi, bj,
                              out_s, out_y, out_x0, out_x1, n, first)
        # the cells walked after it
        if step == 1:
            for k in range(max(kb + 1, ka), hi + 1):
                n = _diamond_column(s, k, rx, ry, qx, qy, ru, rv, qu, slope, x_major, limit, gl, gl_rising, skip_end,
                                    bi, bj, out_s, out_y, out_x0, out_x1, n, first)
        else:
            for k in range(ka - 1, lo - 1, -1):
                n = _diamond_column(s, k, rx, ry, qx, qy, ru, rv, qu, slope, x_major, limit, gl, gl_rising, skip_end,
                                    bi, bj, out_s, out_y, out_x0, out_x1, n, first)
    return n


# -- diamond exit: public ----------------------------------------------------------------------


def _gl_flag(rule: str) -> bool:
    """Whether a diamond rule's name is GL's (ValueError for a rule that is no diamond rule)."""
    if rule not in DIAMOND_RULES:
        raise ValueError(f"rule must be one of {', '.join(DIAMOND_RULES)}, not {rule!r}")
    return rule == "diamond-exit-gl"


def diamond_exit_spans(a: ArrayLike, b: ArrayLike, width: int, height: int, last_pixel: bool = False,
                       rule: str = "diamond-exit") -> Spans:
    """Exactly which pixels each segment draws under the diamond-exit rule (D3D11 aliased
    lines), or GL's (``rule="diamond-exit-gl"``: open diamonds, end points moved by
    -(eps, eps**2)).

    Parameters
    ----------
    a, b : (N, 2) float64
        Segment k runs from ``a[k]`` to ``b[k]``.
    width, height : int
        The viewport.
    last_pixel : bool
        False: the rule itself (a pixel whose test area holds the end point is not
        drawn). True: every pixel whose test area the segment meets, the end pixel too.
    rule : {"diamond-exit", "diamond-exit-gl"}
        D3D11's test areas, or GL's perturbed end points (the module docstring).

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        Spans [x0, x1), sorted by segment, row and x0 (one span per row and segment).

    Raises
    ------
    ValueError
        On a bad argument, or a segment with a nonzero coordinate of magnitude below
        2**-450 or above 2**450, naming the segment.

    Examples
    --------
    From pixel centre to pixel centre: the start pixel is drawn, the end pixel is not; a
    tie (the line through the bottom corner of (1, 0)) goes to the upper pixel.

    >>> s, y, x0, x1 = diamond_exit_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4)]
    >>> s, y, x0, x1 = diamond_exit_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4, last_pixel=True)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]

    The two rules part on a 45-degree line half a pixel off the centres: it runs along the
    lower-left edges of one diagonal of diamonds (D3D's) and the upper-right edges of the
    next (GL's); and on an x-major segment ending on a right corner (GL's, not D3D's):

    >>> for rule in ("diamond-exit", "diamond-exit-gl"):
    ...     s, y, x0, x1 = diamond_exit_spans([[0.5, 0.0], [0.5, 2.5]], [[3.5, 3.0], [3.0, 2.5]], 5, 4, rule=rule)
    ...     print(rule, [(int(k), int(r), int(u), int(v)) for k, r, u, v in zip(s, y, x0, x1)])
    diamond-exit [(0, 0, 1, 2), (0, 1, 2, 3), (1, 2, 0, 3)]
    diamond-exit-gl [(0, 0, 0, 1), (0, 1, 1, 2), (0, 2, 2, 3), (1, 2, 0, 2)]
    """
    return _diamond_exit(a, b, width, height, last_pixel, rule, _diamond_runs_kernel)


def _diamond_exit_spans_reference(a: ArrayLike, b: ArrayLike, width: int, height: int, last_pixel: bool = False,
                                  rule: str = "diamond-exit") -> Spans:
    """:func:`diamond_exit_spans` one major-axis cell at a time, each decided by the exact
    predicate (the kernel before runs; tests compare the two)."""
    return _diamond_exit(a, b, width, height, last_pixel, rule, _diamond_kernel)


def _diamond_exit(a: ArrayLike, b: ArrayLike, width: int, height: int, last_pixel: bool, rule: str, kernel: Any) -> Spans:
    _gl_flag(rule)
    width, height = _viewport(width, height)
    a_arr, b_arr, keep = _endpoints(a, b)
    _check_range(np.concatenate([a_arr, b_arr], axis=1), keep, SAFE_MIN, SAFE_MAX, "diamond_exit_spans_rational")
    return _diamond_exit_kept(a_arr, b_arr, keep, width, height, last_pixel, rule, kernel)


def _diamond_exit_kept(a: NDArray[np.float64], b: NDArray[np.float64], keep: NDArray[np.bool_], width: int, height: int,
                       last_pixel: bool, rule: str, kernel: Any = None) -> Spans:
    """:func:`diamond_exit_spans` of the segments ``keep`` names, checked already: (N, 2)
    float64 end points (finite and in range where kept), a valid viewport and rule."""
    gl = _gl_flag(rule)
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    a_arr, b_arr, keep_f = frozen(a), frozen(b), frozen(keep, np.bool_)
    capacity = int(_diamond_capacity(a_arr, b_arr, keep_f, width, height))
    out = span_buffers(capacity)
    m = int((kernel or _diamond_runs_kernel)(a_arr, b_arr, keep_f, width, height, bool(last_pixel), gl, *out))
    return out[0][:m], out[1][:m], out[2][:m], out[3][:m]


def _in_test_area_rational(px: Fraction, py: Fraction, xc: Fraction, yc: Fraction, y_major: bool) -> bool:
    """The D3D11 test area, written from the spec's words: lower edges (``<=``) and the
    bottom corner in, upper edges and the top, left and right corners out; the right corner
    in for y-major lines."""
    dx, dy = px - xc, py - yc
    half = Fraction(1, 2)
    if y_major and dx == half and dy == 0:
        return True
    return dx + dy <= half and -dx + dy <= half and dx - dy < half and -dx - dy < half


def _in_diamond_rational(px: Fraction, py: Fraction, xc: Fraction, yc: Fraction, y_major: bool, gl: bool) -> bool:
    return _in_gl_area_rational(px, py, xc, yc) if gl else _in_test_area_rational(px, py, xc, yc, y_major)


def _meets_diamond_rational(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], xc: Fraction, yc: Fraction,
                            y_major: bool, gl: bool) -> bool:
    return _meets_gl_rational(a, b, xc, yc) if gl else _meets_rational(a, b, xc, yc, y_major)


def _meets_rational(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], xc: Fraction, yc: Fraction,
                    y_major: bool) -> bool:
    """Whether the segment a-b meets the test area around (xc, yc): the points
    a + t(b - a), 0 <= t <= 1, satisfying its four linear conditions form an interval."""
    half = Fraction(1, 2)
    ex, ey = a[0] - xc, a[1] - yc
    fx, fy = b[0] - a[0], b[1] - a[1]
    # each condition: g0 + g1*t > 0 (strict) or >= 0
    conditions = [
        (half - ex - ey, -fx - fy, False),  # dx + dy <= 1/2: lower-right edge
        (half + ex - ey, fx - fy, False),  # -dx + dy <= 1/2: lower-left edge
        (half - ex + ey, -fx + fy, True),  # dx - dy < 1/2: upper-right edge
        (half + ex + ey, fx + fy, True),  # -dx - dy < 1/2: upper-left edge
    ]
    lo, lo_strict, hi, hi_strict = Fraction(0), False, Fraction(1), False
    feasible = True
    for g0, g1, strict in conditions:
        if g1 == 0:
            if g0 < 0 or (g0 == 0 and strict):
                feasible = False
            continue
        root = -g0 / g1
        if g1 > 0:  # t > root
            if root > lo:
                lo, lo_strict = root, strict
            elif root == lo:
                lo_strict = lo_strict or strict
        else:  # t < root
            if root < hi:
                hi, hi_strict = root, strict
            elif root == hi:
                hi_strict = hi_strict or strict
    if feasible and (lo < hi or (lo == hi and not lo_strict and not hi_strict)):
        return True
    if not y_major:
        return False
    # the right corner (xc + 1/2, yc): on the segment?
    rx, ry = xc + half - a[0], yc - a[1]
    if fx == 0 and fy == 0:
        return rx == 0 and ry == 0
    if fx * ry - fy * rx != 0:
        return False
    t = (rx * fx + ry * fy) / (fx * fx + fy * fy)
    return 0 <= t <= 1


# GL's end points move by -(eps, eps**2): a quantity q0 + q1*eps + q2*eps**2 is the tuple
# (q0, q1, q2), compared lexicographically (its sign as eps -> 0+).
_Poly = tuple[Fraction, Fraction, Fraction]
_GL_DIAGONALS = ((1, 1), (1, -1), (-1, 1), (-1, -1))


def _in_gl_area_rational(px: Fraction, py: Fraction, xc: Fraction, yc: Fraction) -> bool:
    """GL's R_f = {|x - xc| + |y - yc| < 1/2} holds p - (eps, eps**2), from the spec's
    words: for each diagonal s, 1/2 - s.(p - (eps, eps**2) - c) > 0 as a polynomial in eps."""
    half = Fraction(1, 2)
    zero = (Fraction(0), Fraction(0), Fraction(0))
    return all((half - sx * (px - xc) - sy * (py - yc), Fraction(sx), Fraction(sy)) > zero for sx, sy in _GL_DIAGONALS)


def _meets_gl_rational(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], xc: Fraction, yc: Fraction) -> bool:
    """Whether GL's moved segment a' b' (a' = a - (eps, eps**2), likewise b') meets the open
    diamond R_f around (xc, yc): the t in [0, 1] with 1/2 - s.(a' + t(b - a) - c) > 0 for the
    four diagonals s form an interval whose ends are polynomials in eps; it is not empty
    when its lower end is below its upper one (lexicographically: ends never coincide
    with 0 or 1, as a condition's root has a nonzero eps term)."""
    half = Fraction(1, 2)
    fx, fy = b[0] - a[0], b[1] - a[1]
    lower: _Poly = (Fraction(0), Fraction(0), Fraction(0))
    upper: _Poly = (Fraction(1), Fraction(0), Fraction(0))
    for sx, sy in _GL_DIAGONALS:
        # g(t) = g0 + g1*t + sx*eps + sy*eps**2 > 0
        g0 = half - sx * (a[0] - xc) - sy * (a[1] - yc)
        g1 = -sx * fx - sy * fy
        if g1 == 0:
            if not (g0, Fraction(sx), Fraction(sy)) > (Fraction(0), Fraction(0), Fraction(0)):
                return False
            continue
        root: _Poly = (-g0 / g1, Fraction(-sx) / g1, Fraction(-sy) / g1)
        if g1 > 0:  # t > root
            lower = max(lower, root)
        else:  # t < root
            upper = min(upper, root)
    return lower < upper


def diamond_exit_spans_rational(a: ArrayLike, b: ArrayLike, width: int, height: int, last_pixel: bool = False,
                                rule: str = "diamond-exit") -> Spans:
    """The same spans as :func:`diamond_exit_spans` by brute force in rational arithmetic:
    every pixel of the viewport tested from the definition (the segment meets the pixel's
    test area, and the end point is not in it; GL's: the moved segment meets the open
    diamond, and the moved end point is not in it). Any finite float; small viewports only."""
    gl = _gl_flag(rule)
    width, height = _viewport(width, height)
    a_arr, b_arr, keep = _endpoints(a, b)
    out: list[tuple[int, int, int, int]] = []
    half = Fraction(1, 2)
    for s in np.flatnonzero(keep):
        pa = (Fraction(float(a_arr[s, 0])), Fraction(float(a_arr[s, 1])))
        pb = (Fraction(float(b_arr[s, 0])), Fraction(float(b_arr[s, 1])))
        y_major = abs(pb[1] - pa[1]) > abs(pb[0] - pa[0])
        covered = []
        for j in range(height):
            row = []
            for i in range(width):
                xc, yc = i + half, j + half
                hit = _meets_diamond_rational(pa, pb, xc, yc, y_major, gl) and (
                    bool(last_pixel) or not _in_diamond_rational(pb[0], pb[1], xc, yc, y_major, gl))
                row.append(hit)
            covered.append(row)
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)


def _diamond_far(segment: int, a: NDArray[np.float64], b: NDArray[np.float64], width: int, height: int, last_pixel: bool,
                 out: list[tuple[int, int, int, int]], gl: bool = False) -> None:
    """One diamond-exit segment of any finite coordinates, in rational arithmetic: per
    major-axis cell of the viewport the one minor cell whose test area the line can meet
    (the module docstring's method), and its neighbours, tested from the definition."""
    pa = (Fraction(float(a[0])), Fraction(float(a[1])))
    pb = (Fraction(float(b[0])), Fraction(float(b[1])))
    _diamond_far_exact(segment, pa, pb, width, height, last_pixel, out, gl)


def _diamond_far_exact(segment: int, pa: tuple[Fraction, Fraction], pb: tuple[Fraction, Fraction], width: int, height: int,
                       last_pixel: bool, out: list[tuple[int, int, int, int]], gl: bool) -> None:
    """:func:`_diamond_far` on rational end points."""
    fx, fy = pb[0] - pa[0], pb[1] - pa[1]
    if fx == 0 and fy == 0:
        if last_pixel:  # the pixel whose test area holds the point, if any
            i, j = math.floor(pa[0]), math.floor(pa[1])
            for u in (i - 1, i, i + 1):
                for v in (j - 1, j, j + 1):
                    if 0 <= u < width and 0 <= v < height and _in_diamond_rational(pa[0], pa[1], u + Fraction(1, 2),
                                                                                   v + Fraction(1, 2), False, gl):
                        out.append((segment, v, u, u + 1))
        return
    y_major = abs(fy) > abs(fx)
    half = Fraction(1, 2)
    hits: list[tuple[int, int]] = []
    for c in range(height if y_major else width):
        centre = c + half
        if y_major:
            across = pa[0] + (centre - pa[1]) * fx / fy
            candidates = [(m, c) for m in range(math.ceil(across) - 2, math.ceil(across) + 1)]
        else:
            across = pa[1] + (centre - pa[0]) * fy / fx
            candidates = [(c, m) for m in range(math.ceil(across) - 2, math.ceil(across) + 1)]
        for i, j in candidates:
            if not (0 <= i < width and 0 <= j < height):
                continue
            xc, yc = i + half, j + half
            if _meets_diamond_rational(pa, pb, xc, yc, y_major, gl) and (
                    last_pixel or not _in_diamond_rational(pb[0], pb[1], xc, yc, y_major, gl)):
                hits.append((j, i))
    out.extend((segment, j, i, i + 1) for j, i in sorted(hits))


# -- wide diamond lines: GL's replication ------------------------------------------------------


@numba.njit(cache=True)
def _x_major_all(a, b, out):  # type: ignore[no-untyped-def]
    for k in range(a.shape[0]):
        out[k] = is_x_major(a[k, 0], a[k, 1], b[k, 0], b[k, 1])


def _line_width_of(line_width: float) -> int:
    w = float(line_width)
    if not (math.isfinite(w) and w == math.floor(w) and 1.0 <= w <= MAX_VIEWPORT):
        raise ValueError(f"replicated lines have an integer width in 1..{MAX_VIEWPORT}, not {line_width!r}")
    return int(w)


def diamond_wide_spans(a: ArrayLike, b: ArrayLike, line_width: float, width: int, height: int, last_pixel: bool = False,
                       rule: str = "diamond-exit") -> Spans:
    """Exactly which pixels each segment draws as a wide line of integer width w under a
    diamond rule, by GL's replication (OpenGL 4.6, 14.5.2, wide lines): the segment moved by
    -(w - 1)/2 along its minor axis (y for an x-major segment) is drawn by the width-1 rule,
    and each of its fragments becomes w, along the minor axis from it (rows y .. y + w - 1,
    or columns x .. x + w - 1). The major axis is the segment's (the move keeps it).

    Method: moving the segment by +(w - 1)/2 instead is the same drawing w - 1 pixels
    further along the minor axis (the pixel lattice is invariant under whole-pixel moves),
    so the moved segment runs through :func:`diamond_exit_spans` in a viewport w - 1 pixels
    longer on that axis, and each fragment at minor coordinate m stands for m - (w - 1) ..
    m. The move is exact in float64 for most inputs (checked: Knuth's two-sum error is
    zero) and the segment stays in the kernel's range; any other segment (the move rounds,
    or coordinates beyond 2**+-450) is drawn in rational arithmetic. Any finite float64.

    Parameters
    ----------
    a, b : (N, 2) float64
    line_width : float
        An integer w >= 1 (w = 1: :func:`diamond_exit_spans`).
    width, height : int
    last_pixel : bool
    rule : {"diamond-exit", "diamond-exit-gl"}

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        Spans sorted by segment, row and x0.

    Examples
    --------
    A horizontal segment through the centres of row 2, width 3: rows 1 to 3 (moved up by one,
    then replicated down); width 2: the segment moved by -1/2 runs on the row boundary y = 2,
    whose bottom corners are row 1's, replicated to rows 1 and 2.

    >>> for w in (3, 2):
    ...     s, y, x0, x1 = diamond_wide_spans([[0.5, 2.5]], [[3.5, 2.5]], w, 5, 5)
    ...     print(w, [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)])
    3 [(1, 0, 3), (2, 0, 3), (3, 0, 3)]
    2 [(1, 0, 3), (2, 0, 3)]
    """
    from harness.contract.coverage import Coverage

    gl = _gl_flag(rule)
    w = _line_width_of(line_width)
    width, height = _viewport(width, height)
    a_arr, b_arr, keep = _endpoints(a, b)
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    n = a_arr.shape[0]
    x_major = np.ones(n, dtype=np.bool_)
    chosen = np.zeros(int(keep.sum()), dtype=np.bool_)
    _x_major_all(np.ascontiguousarray(a_arr[keep]), np.ascontiguousarray(b_arr[keep]), chosen)
    x_major[keep] = chosen
    half = (w - 1) / 2.0
    minor = np.where(x_major, 1, 0)
    moved_a, moved_b = a_arr.copy(), b_arr.copy()
    exact = keep.copy()
    rows = np.arange(n)
    for moved in (moved_a, moved_b):
        with np.errstate(invalid="ignore", over="ignore"):
            v = moved[rows, minor]
            total = v + half  # Knuth's two-sum: the rounding error of v + half, exactly
            back = total - v
            error = (v - (total - back)) + (half - back)
            exact &= np.isfinite(total) & (error == 0.0)
            moved[rows, minor] = np.where(keep, total, 0.0)
    exact &= ~_beyond(np.concatenate([moved_a, moved_b], axis=1), SAFE_MIN, SAFE_MAX)
    pixels: list[tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]] = []
    for major in (True, False):
        group = exact & (x_major == major)
        w_ext, h_ext = (width, height + w - 1) if major else (width + w - 1, height)
        if group.any():
            nan = np.full((n, 2), np.nan)
            spans = diamond_exit_spans(np.where(group[:, None], moved_a, nan), np.where(group[:, None], moved_b, nan),
                                       w_ext, h_ext, last_pixel, rule)
            pixels.append(_replicate(spans, w, major))
        extra: list[tuple[int, int, int, int]] = []
        for k in np.flatnonzero(keep & ~exact & (x_major == major)):
            shift = Fraction(w - 1, 2)
            pa = [Fraction(float(v)) for v in a_arr[k]]
            pb = [Fraction(float(v)) for v in b_arr[k]]
            pa[1 if major else 0] += shift
            pb[1 if major else 0] += shift
            _diamond_far_exact(int(k), (pa[0], pa[1]), (pb[0], pb[1]), w_ext, h_ext, last_pixel, extra, gl)
        if extra:
            pixels.append(_replicate(_as_spans(extra), w, major))
    if not pixels:
        return _empty()
    seg, x, y = (np.concatenate(parts) for parts in zip(*pixels))
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
    cov = Coverage.from_pixels(seg[inside], x[inside], y[inside])
    return cov.primitive, cov.y, cov.x0, cov.x1


def _replicate(spans: Spans, w: int, x_major: bool) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """(segment, x, y) of the w pixels each base fragment (drawn w - 1 pixels further along
    the minor axis) stands for: minor coordinates m - (w - 1) .. m."""
    s, y, x0, x1 = spans
    lengths = x1 - x0
    seg, x, yy = np.repeat(s, lengths), expand(x0, lengths), np.repeat(y, lengths)
    k = np.arange(w)
    seg = np.repeat(seg, w)
    if x_major:
        return seg, np.repeat(x, w), (yy[:, None] - k[None, :]).ravel()
    return seg, (x[:, None] - k[None, :]).ravel(), np.repeat(yy, w)


def diamond_wide_spans_rational(a: ArrayLike, b: ArrayLike, line_width: float, width: int, height: int,
                                last_pixel: bool = False, rule: str = "diamond-exit") -> Spans:
    """The same spans as :func:`diamond_wide_spans` from GL's words, by brute force in
    rational arithmetic: pixel (i, j) is covered when one of (i, j - k) (x-major; (i - k, j)
    y-major), 0 <= k < w, is drawn by the width-1 rule (:func:`diamond_exit_spans_rational`'s
    tests) on the segment moved by -(w - 1)/2 along its minor axis. Small viewports only."""
    gl = _gl_flag(rule)
    w = _line_width_of(line_width)
    width, height = _viewport(width, height)
    a_arr, b_arr, keep = _endpoints(a, b)
    out: list[tuple[int, int, int, int]] = []
    half = Fraction(1, 2)
    shift = Fraction(w - 1, 2)
    for s in np.flatnonzero(keep):
        pa = [Fraction(float(v)) for v in a_arr[s]]
        pb = [Fraction(float(v)) for v in b_arr[s]]
        y_major = abs(pb[1] - pa[1]) > abs(pb[0] - pa[0])
        axis = 0 if y_major else 1
        pa[axis] -= shift
        pb[axis] -= shift
        ta, tb = (pa[0], pa[1]), (pb[0], pb[1])

        def base(i: int, j: int, ta: tuple[Fraction, Fraction] = ta, tb: tuple[Fraction, Fraction] = tb,
                 y_major: bool = y_major) -> bool:
            xc, yc = i + half, j + half
            return _meets_diamond_rational(ta, tb, xc, yc, y_major, gl) and (
                bool(last_pixel) or not _in_diamond_rational(tb[0], tb[1], xc, yc, y_major, gl))

        covered = [[any(base(i - k, j) if y_major else base(i, j - k) for k in range(w)) for i in range(width)]
                   for j in range(height)]
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)
