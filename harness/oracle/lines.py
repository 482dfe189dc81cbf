"""Exact oracles for aliased lines: the diamond-exit rules (Direct3D's and GL's), integer
Bresenham (seed 003) and Vulkan's rectangular lines.

A segment k runs from ``a[k]`` to ``b[k]`` (float64, pixels, x right, y down: the screen
space of :mod:`harness.contract.conventions`). Pixel (i, j) is the square [i, i+1) x [j, j+1) with
centre (i + 1/2, j + 1/2). Every oracle returns the covered pixels as spans
``(segment, y, x0, x1)`` -- pixels x0 <= x < x1 of row y -- sorted by segment, row and x0,
like :func:`harness.oracle.winding.path_spans`. A segment with a NaN or infinite endpoint covers
nothing. Every decision is exact on the float64 input; no epsilon appears anywhere.

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

Bresenham (:func:`bresenham_spans`)
    Seed 003: integer end points, one pixel per step of the major axis, octants centred on
    the first point (the walk starts at ``a`` and goes towards ``b``).

    * End point p -> pixel (i, j), exactly, by the declared ``rounding``: the pixel holding
      p. ``floor``: i = floor(px) (seed 000's floor). ``toward-zero``: i = trunc(px), C's
      ``(int)`` cast of the window coordinate (softpipe's ``sp_setup_line``, Pillow's
      ``ImageDraw.line``): floor for px >= 0, but pixel 0 for -1 < px < 0. ``nearest-even``/``half-away``: i is the integer nearest to
      px - 1/2, i.e. the pixel whose centre i + 1/2 is nearest to px; that is floor(px)
      except when px is an integer (p on the boundary of pixels px - 1 and px), where
      ``nearest-even`` takes the even one and ``half-away`` the one away from zero (px when
      px - 1/2 > 0, px - 1 when px - 1/2 < 0). Likewise j from py.
    * x-major when |x1 - x0| >= |y1 - y0| (integers), else y-major. With K = |major delta|,
      M = |minor delta|: the classic decision variable ``p = 2M - K``; after each pixel the
      major coordinate steps, and the minor one steps when ``p >= 0`` (then ``p += 2M - 2K``,
      else ``p += 2M``) -- Hearn & Baker's and GeeksforGeeks' decision parameter (the
      seed's first reference), softpipe's ``if (error < 0) ... else y0 += ystep``. A tie
      (p = 0: the ideal line exactly halfway between two pixel centres) steps towards the
      end point (``ties="step"``); ``ties="stay"`` keeps the minor coordinate on a tie
      (Foley & van Dam's midpoint test ``d <= 0``; Wikipedia's ``D > 0``). Closed form: the
      minor offset at major step k is ``round(k*M/K)`` with halves rounded up (``step``) or
      down (``stay``). Both end points are drawn (K + 1 pixels); ``last_pixel=False``
      drops the last (K pixels, none for a zero-length segment).
    * Direction of travel (``direction``). The walk above starts at ``a`` (``as-given``), and
      its ties and its last pixel belong to the walk: drawn backwards, a tie steps the other
      way (``step`` from b is ``stay`` from a) and the other end pixel is the last. Textbook
      drawers normalise the direction first, on the end points' *pixels*: ``smaller-x``
      walks from the end point whose pixel has the smaller x (Hearn & Baker's ``lineBres``,
      the usual "if x0 > x1: swap" ``plotLine``; the given order when the x are equal),
      ``smaller-major`` from the one whose pixel has the smaller major coordinate (Wikipedia's
      ``plotLine`` with ``plotLineLow``/``plotLineHigh``, tinyrenderer's ``line``). Then the
      same walk runs from that end point, with the same ``ties`` and ``last_pixel`` (the
      end walked to is the one omitted): such a drawer draws a segment and its reverse
      alike (but for the omitted end of a vertical one walked from the smaller x, kept in
      its given order), and only differs from ``as-given`` on segments it reverses, at a tie
      or at the omitted end. :func:`walks_backwards` says which it reverses.
    * Rounded end points must lie within +-2**30 (every product k*M then fits int64).

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

Wide diamond lines (:func:`diamond_wide_spans`)
    ``LineRule(wide="replicate")``: GL's wide lines (OpenGL 4.6, 14.5.2 "Other Line Segment
    Features"; Direct3D 10+ has no wide aliased lines): an integer width w, the segment
    moved by -(w - 1)/2 along its minor axis drawn by the width-1 diamond rule, each
    fragment replicated w times along that axis, the width-1 one first (rows y .. y + w - 1
    of an x-major segment; window y taken as rows). GL rounds a width to the nearest
    integer first; here a non-integer width is undefined (a rasterizer refuses it).

Multisample lines (:func:`line_coverage` under a multisample convention)
    OpenGL 4.6, 14.5.4 "Line Multisample Rasterization" (dEQP's ``MultiSampleLineRasterizer``
    likewise): the samples inside the rectangle of the line's width centred on the segment
    (two edges parallel to it at half the width, two through the end points), i.e. the
    rectangle rule at every sample of the pattern, each decided exactly at its own offset
    under the tie rule and snapping (:meth:`harness.contract.conventions.Convention.at_sample`).
    The only line rule defined under a multisample convention.

The ``*_rational`` functions are the slow references, in :class:`fractions.Fraction`
arithmetic for any finite float (small viewports and coordinates only): the diamond and
rectangle ones decide every pixel (sample) of the viewport from the definitions above; the
Bresenham one rounds the end points exactly and walks the incremental decision variable
literally, pixel by pixel.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import (
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    DIAMOND_RULES,
    LINE_DIRECTIONS,
    BresenhamRounding,
    BresenhamTies,
    Convention,
    LineDirection,
    TieRule,
)
from harness.contract.scenes import MAX_VIEWPORT
from harness.geometry.exact import CCW_ERRBOUND_A, SAFE_MAX, SAFE_MIN, _two_product, _two_sum, frozen, orient2d_sign
from harness.geometry.spans import expand

__all__ = [
    "diamond_exit_spans",
    "diamond_exit_spans_rational",
    "bresenham_spans",
    "bresenham_spans_rational",
    "bresenham_pixels",
    "rectangle_spans",
    "rectangle_spans_rational",
    "line_coverage",
    "is_x_major",
    "diamond_holding",
    "area_holding",
    "diamond_wide_spans",
    "diamond_wide_spans_rational",
    "end_point_pixels",
    "walks_backwards",
    "BRESENHAM_ROUNDINGS",
    "BRESENHAM_TIES",
    "RECT_SAFE_MIN",
    "RECT_SAFE_MAX",
    "BRESENHAM_MAX",
    "BresenhamRounding",
    "BresenhamTies",
]

Spans = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]
# Rectangles decide a degree-4 polynomial: inputs of magnitude in [2**-150, 2**150] (or 0)
# are multiples of 2**-202, so every term is a multiple of 2**-808 (no underflow) and the
# largest, (2c)**2 <= (4 * 2**151 * 2**151)**2, stays below 2**610 (no overflow; Dekker's
# split needs < 2**996).
RECT_SAFE_MIN = 2.0**-150
RECT_SAFE_MAX = 2.0**150
# Rounded Bresenham end points: |k*M| <= 2**31 * 2**31 = 2**62 fits int64.
BRESENHAM_MAX = 2**30
# margin of the rectangle's float filter: 32 ulps, well above its ~8 roundings
_FILTER_SLACK = 2.0**-48


# -- shared compiled pieces -------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def emit_pixel(s, y, x, out_s, out_y, out_x0, out_x1, n, first):  # type: ignore[no-untyped-def]
    """Add pixel (x, y) of segment s, merged into the last span when adjacent on its row.
    ``first`` is the index of the segment's first span. Returns the span count."""
    if n > first and out_y[n - 1] == y:
        if out_x1[n - 1] == x:
            out_x1[n - 1] = x + 1
            return n
        if out_x0[n - 1] == x + 1:
            out_x0[n - 1] = x
            return n
    out_s[n] = s
    out_y[n] = y
    out_x0[n] = x
    out_x1[n] = x + 1
    return n + 1


@numba.njit(cache=True, inline="always")
def _clamp_index(value, low, high):  # type: ignore[no-untyped-def]
    """floor(value) clamped to [low, high] without converting a huge float (NaN -> low)."""
    if not value >= low:
        return low
    if value >= high:
        return high
    return int(math.floor(value))


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


# -- Bresenham -------------------------------------------------------------------------------


@numba.njit(cache=True)
def _bresenham_capacity(p0, p1, keep, width, height):  # type: ignore[no-untyped-def]
    total = 0
    for s in range(p0.shape[0]):
        if keep[s]:
            total += min(max(abs(p1[s, 0] - p0[s, 0]), abs(p1[s, 1] - p0[s, 1])) + 1, max(width, height))
    return total


@numba.njit(cache=True)
def _bresenham_kernel(p0, p1, keep, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Integer Bresenham from p0 to p1 (int64 pixel coordinates), in closed form and only
    within the viewport. Returns the number of spans written."""
    n = 0
    for s in range(p0.shape[0]):
        if not keep[s]:
            continue
        first = n
        x0, y0, x1, y1 = p0[s, 0], p0[s, 1], p1[s, 0], p1[s, 1]
        x_major = abs(x1 - x0) >= abs(y1 - y0)
        if x_major:
            u0, v0, du, dv, extent = x0, y0, x1 - x0, y1 - y0, width
        else:
            u0, v0, du, dv, extent = y0, x0, y1 - y0, x1 - x0, height
        su = 1 if du >= 0 else -1
        sv = 1 if dv >= 0 else -1
        big_k = abs(du)
        big_m = abs(dv)
        last = big_k if last_pixel else big_k - 1
        if last < 0:
            continue
        # the steps k in [0, last] whose major coordinate u0 + su*k lies in [0, extent)
        if su > 0:
            k_lo, k_hi = max(0, -u0), min(last, extent - 1 - u0)
        else:
            k_lo, k_hi = max(0, u0 - (extent - 1)), min(last, u0)
        if k_lo > k_hi:
            continue
        # rows ascending: walk backwards when the rows run up the screen
        rows_down = (sv > 0) if x_major else (su > 0)
        k = k_lo if rows_down else k_hi
        step = 1 if rows_down else -1
        for _ in range(k_hi - k_lo + 1):
            k_now = k
            k += step
            if big_k == 0:
                offset = 0
            else:
                # The decision variable in closed form: the minor offset is k*M/K rounded
                # to nearest, a half (p = 0) stepping ("step") or staying ("stay").
                q, r = divmod(k_now * big_m, big_k)
                twice = 2 * r
                offset = q + (1 if (twice > big_k or (step_ties and twice == big_k)) else 0)
            u = u0 + su * k_now
            v = v0 + sv * offset
            x, y = (u, v) if x_major else (v, u)
            if y < 0 or y >= height or x < 0 or x >= width:
                continue
            n = emit_pixel(s, y, x, out_s, out_y, out_x0, out_x1, n, first)
    return n


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


# -- input handling ------------------------------------------------------------------------------


def _empty() -> Spans:
    return tuple(np.empty(0, dtype=np.int64) for _ in range(4))  # type: ignore[return-value]


def _viewport(width: int, height: int) -> tuple[int, int]:
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= MAX_VIEWPORT:
            raise ValueError(f"{name} must be an integer in 0..{MAX_VIEWPORT}, not {value!r}")
    return int(width), int(height)


def _endpoints(a: ArrayLike, b: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """The end points as (N, 2) float64 arrays, and which segments are finite."""
    a_arr = np.asarray(a, dtype=np.float64)
    b_arr = np.asarray(b, dtype=np.float64)
    if a_arr.ndim != 2 or a_arr.shape[1:] != (2,) or a_arr.shape != b_arr.shape:
        raise ValueError(f"a and b must be (N, 2) arrays of one shape, not {a_arr.shape} and {b_arr.shape}")
    finite = np.isfinite(np.concatenate([a_arr, b_arr], axis=1)).all(axis=1)
    return a_arr, b_arr, np.asarray(finite, dtype=np.bool_)


def _check_range(values: NDArray[np.float64], keep: NDArray[np.bool_], low: float, high: float, use: str) -> None:
    """ValueError naming the first kept segment with a nonzero coordinate beyond [low, high]."""
    magnitude = np.abs(values.reshape(values.shape[0], -1))
    beyond = ((magnitude != 0.0) & ((magnitude < low) | (magnitude > high))).any(axis=1) & keep
    if beyond.any():
        k = int(np.flatnonzero(beyond)[0])
        raise ValueError(
            f"segment {k} has coordinates beyond the exact predicates' range (nonzero magnitude below "
            f"2**{int(math.log2(low))} or above 2**{int(math.log2(high))}); use {use}"
        )


def _spans_from_mask(segment: int, covered: list[list[bool]], out: list[tuple[int, int, int, int]]) -> None:
    """Maximal runs of each row of ``covered`` ([y][x]) as spans of ``segment``."""
    for j, row in enumerate(covered):
        i = 0
        while i < len(row):
            if row[i]:
                k = i
                while k < len(row) and row[k]:
                    k += 1
                out.append((segment, j, i, k))
                i = k
            else:
                i += 1


def _as_spans(rows: list[tuple[int, int, int, int]]) -> Spans:
    if not rows:
        return _empty()
    arr = np.array(rows, dtype=np.int64).T
    return arr[0], arr[1], arr[2], arr[3]


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
    gl = _gl_flag(rule)
    width, height = _viewport(width, height)
    a_arr, b_arr, keep = _endpoints(a, b)
    _check_range(np.concatenate([a_arr, b_arr], axis=1), keep, SAFE_MIN, SAFE_MAX, "diamond_exit_spans_rational")
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    a_arr, b_arr, keep_f = frozen(a_arr), frozen(b_arr), frozen(keep, np.bool_)
    capacity = int(_diamond_capacity(a_arr, b_arr, keep_f, width, height))
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    m = int(_diamond_kernel(a_arr, b_arr, keep_f, width, height, bool(last_pixel), gl, *out))
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


# -- Bresenham: public --------------------------------------------------------------------------


def end_point_pixels(p: NDArray[np.float64], rounding: str) -> NDArray[np.float64]:
    """Pixel coordinates of points, exactly (see the module docstring): floor(p) and
    trunc(p) are exact, and so is p - floor(p)."""
    if rounding == "toward-zero":
        return np.trunc(p) + 0.0  # (int)p; + 0.0 turns -0.0 into 0.0
    f = np.floor(p)
    if rounding == "floor":
        return f
    on_boundary = (p - f) == 0.0  # p - 1/2 is a half: the tie
    if rounding == "nearest-even":
        tie = np.where(np.fmod(f, 2.0) == 0.0, f, f - 1.0)
    else:  # half-away: p - 1/2 > 0 rounds up to f, < 0 down to f - 1
        tie = np.where(f >= 1.0, f, f - 1.0)
    return np.where(on_boundary, tie, f)


def walks_backwards(p0: NDArray[Any], p1: NDArray[Any], direction: str) -> NDArray[np.bool_]:
    """(N,) bool: which Bresenham walks between end point pixels ``p0`` -> ``p1`` ((N, 2)
    integers: int64, or Python integers in an object array) run from ``p1`` to ``p0`` under ``direction`` (see the
    module docstring): never (``as-given``); where x0 > x1 (``smaller-x``); where the major
    coordinate of p0 exceeds p1's (``smaller-major``; x-major when |x1 - x0| >= |y1 - y0|).

    >>> p0, p1 = np.array([[5, 0], [0, 5], [3, 9]]), np.array([[0, 2], [2, 0], [3, 1]])
    >>> [walks_backwards(p0, p1, d).tolist() for d in ("as-given", "smaller-x", "smaller-major")]
    [[False, False, False], [True, False, False], [True, True, True]]
    """
    if direction not in LINE_DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(LINE_DIRECTIONS)}, not {direction!r}")
    p0, p1 = np.asarray(p0), np.asarray(p1)
    if direction == "as-given":
        return np.zeros(p0.shape[0], dtype=np.bool_)
    if direction == "smaller-x":
        return np.asarray(p0[:, 0] > p1[:, 0], dtype=np.bool_)
    x_major = np.abs(p1[:, 0] - p0[:, 0]) >= np.abs(p1[:, 1] - p0[:, 1])
    return np.asarray(np.where(x_major, p0[:, 0] > p1[:, 0], p0[:, 1] > p1[:, 1]), dtype=np.bool_)


def _walk_ends(p0: NDArray[Any], p1: NDArray[Any], direction: str) -> tuple[NDArray[Any], NDArray[Any]]:
    """The walks' (start, end) pixels: ``p0, p1`` swapped where :func:`walks_backwards`."""
    back = walks_backwards(p0, p1, direction)[:, None]
    return np.where(back, p1, p0), np.where(back, p0, p1)


def _bresenham_prepare(a: ArrayLike, b: ArrayLike, width: int, height: int, rounding: str, ties: str,
                       direction: str) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_], int, int]:
    """The walks' start and end pixels (int64, (N, 2) each: the rounded end points, in
    the order ``direction`` walks them), which segments are finite, and the viewport."""
    width, height = _viewport(width, height)
    if rounding not in BRESENHAM_ROUNDINGS:
        raise ValueError(f"rounding must be one of {', '.join(BRESENHAM_ROUNDINGS)}, not {rounding!r}")
    if ties not in BRESENHAM_TIES:
        raise ValueError(f"ties must be one of {', '.join(BRESENHAM_TIES)}, not {ties!r}")
    if direction not in LINE_DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(LINE_DIRECTIONS)}, not {direction!r}")
    a_arr, b_arr, keep = _endpoints(a, b)
    with np.errstate(invalid="ignore"):
        p0 = np.where(keep[:, None], end_point_pixels(a_arr, rounding), 0.0)
        p1 = np.where(keep[:, None], end_point_pixels(b_arr, rounding), 0.0)
    beyond = (np.abs(np.concatenate([p0, p1], axis=1)) > BRESENHAM_MAX).any(axis=1)
    if beyond.any():
        k = int(np.flatnonzero(beyond)[0])
        raise ValueError(f"segment {k} has a rounded end point beyond +-2**30 pixels")
    p0, p1 = _walk_ends(p0, p1, direction)
    return p0.astype(np.int64), p1.astype(np.int64), keep, width, height


def bresenham_spans(a: ArrayLike, b: ArrayLike, width: int, height: int, rounding: BresenhamRounding = "nearest-even",
                    ties: BresenhamTies = "step", last_pixel: bool = True, direction: LineDirection = "as-given") -> Spans:
    """The pixels integer Bresenham draws from ``a[k]`` to ``b[k]`` (seed 003).

    Parameters
    ----------
    a, b : (N, 2) float64
        End points, rounded to pixels by ``rounding`` (see the module docstring).
    width, height : int
        The viewport.
    rounding : {"nearest-even", "half-away", "floor", "toward-zero"}
    ties : {"step", "stay"}
        Decision variable zero: step the minor coordinate (``p >= 0``) or keep it (``p > 0``).
    last_pixel : bool
        Draw the pixel the walk ends in (True) or stop one step short.
    direction : {"as-given", "smaller-x", "smaller-major"}
        Where the walk starts (:func:`walks_backwards`): at ``a[k]``, or at the end point
        whose pixel has the smaller x, or the smaller major coordinate (textbook plotLine).

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        Spans sorted by segment, row and x0.

    Examples
    --------
    >>> s, y, x0, x1 = bresenham_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 1), (1, 1, 3), (2, 3, 5)]
    >>> s, y, x0, x1 = bresenham_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4, ties="stay")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]

    Drawn right to left, the ties step the other way; a drawer walking from the smaller x
    draws it as left to right:

    >>> s, y, x0, x1 = bresenham_spans([[4.5, 2.5]], [[0.5, 0.5]], 6, 4)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]
    >>> s, y, x0, x1 = bresenham_spans([[4.5, 2.5]], [[0.5, 0.5]], 6, 4, direction="smaller-x")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 1), (1, 1, 3), (2, 3, 5)]
    """
    p0, p1, keep, width, height = _bresenham_prepare(a, b, width, height, rounding, ties, direction)
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    p0, p1, keep_f = frozen(p0, np.int64), frozen(p1, np.int64), frozen(keep, np.bool_)
    capacity = int(_bresenham_capacity(p0, p1, keep_f, width, height))
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    m = int(_bresenham_kernel(p0, p1, keep_f, width, height, ties == "step", bool(last_pixel), *out))
    return out[0][:m], out[1][:m], out[2][:m], out[3][:m]


bresenham_pixels = bresenham_spans  # the name for it


def _round_pixel_rational(v: Fraction, rounding: str) -> int:
    if rounding == "toward-zero":
        return math.trunc(v)
    if rounding == "floor":
        return math.floor(v)
    c = v - Fraction(1, 2)
    f = math.floor(c)
    r = c - f
    if r != Fraction(1, 2):
        return f if r < Fraction(1, 2) else f + 1
    if rounding == "nearest-even":
        return f if f % 2 == 0 else f + 1
    return f + 1 if c > 0 else f


def bresenham_spans_rational(a: ArrayLike, b: ArrayLike, width: int, height: int,
                             rounding: BresenhamRounding = "nearest-even", ties: BresenhamTies = "step",
                             last_pixel: bool = True, direction: LineDirection = "as-given") -> Spans:
    """The same pixels as :func:`bresenham_spans` by the literal algorithm: end points
    rounded in rational arithmetic, swapped as a textbook plotLine swaps them
    (``direction``), then the incremental decision variable walked pixel by pixel from
    the first (small coordinates only)."""
    width, height = _viewport(width, height)
    if rounding not in BRESENHAM_ROUNDINGS or ties not in BRESENHAM_TIES or direction not in LINE_DIRECTIONS:
        raise ValueError(f"bad rounding {rounding!r}, ties {ties!r} or direction {direction!r}")
    a_arr, b_arr, keep = _endpoints(a, b)
    out: list[tuple[int, int, int, int]] = []
    for s in np.flatnonzero(keep):
        x0, y0 = (_round_pixel_rational(Fraction(float(v)), rounding) for v in a_arr[s])
        x1, y1 = (_round_pixel_rational(Fraction(float(v)), rounding) for v in b_arr[s])
        x_major = abs(x1 - x0) >= abs(y1 - y0)
        if direction == "smaller-x" and x0 > x1:
            x0, y0, x1, y1 = x1, y1, x0, y0
        if direction == "smaller-major" and ((x_major and x0 > x1) or (not x_major and y0 > y1)):
            x0, y0, x1, y1 = x1, y1, x0, y0
        u, v, du, dv = (x0, y0, x1 - x0, y1 - y0) if x_major else (y0, x0, y1 - y0, x1 - x0)
        su, sv = (1 if du >= 0 else -1), (1 if dv >= 0 else -1)
        big_k, big_m = abs(du), abs(dv)
        p = 2 * big_m - big_k
        covered = [[False] * width for _ in range(height)]
        for k in range(big_k + 1):
            if k < big_k or last_pixel:
                x, y = (u, v) if x_major else (v, u)
                if 0 <= x < width and 0 <= y < height:
                    covered[y][x] = True
            if k == big_k:
                break
            if p > 0 or (p == 0 and ties == "step"):
                v += sv
                p -= 2 * big_k
            p += 2 * big_m
            u += su
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)


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
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    a_f, b_f, w_f, keep_f = frozen(a_arr), frozen(b_arr), frozen(widths), frozen(keep, np.bool_)
    capacity = int(_rect_capacity(a_f, b_f, w_f, keep_f, sy, height))
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    m = int(_rect_kernel(a_f, b_f, w_f, keep_f, sx, sy, tx, ty, y_first, width, height, *out))
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


# -- line scenes: the oracle ------------------------------------------------------------------------


def _beyond(values: NDArray[np.float64], low: float, high: float) -> NDArray[np.bool_]:
    """(N,) bool: rows holding a nonzero finite magnitude outside [low, high]."""
    magnitude = np.abs(values.reshape(values.shape[0], -1))
    with np.errstate(invalid="ignore"):
        return np.asarray(((magnitude != 0.0) & ((magnitude < low) | (magnitude > high))).any(axis=1), dtype=np.bool_)


def _bresenham_far(segment: int, p0: tuple[int, int], p1: tuple[int, int], width: int, height: int, ties: str,
                   last_pixel: bool, out: list[tuple[int, int, int, int]]) -> None:
    """One Bresenham segment with end-point pixels of any size (Python integers): the
    closed form ``minor = round(k*M/K)`` (halves up for ``step``, down for ``stay``) on the
    steps k whose pixel lies in the viewport, found by bisection (the walk is monotone)."""
    x_major = abs(p1[0] - p0[0]) >= abs(p1[1] - p0[1])
    u0, v0, du, dv = (p0[0], p0[1], p1[0] - p0[0], p1[1] - p0[1]) if x_major else (p0[1], p0[0], p1[1] - p0[1], p1[0] - p0[0])
    su, sv = (1 if du >= 0 else -1), (1 if dv >= 0 else -1)
    big_k, big_m = abs(du), abs(dv)
    u_size, v_size = (width, height) if x_major else (height, width)
    last = big_k if last_pixel else big_k - 1
    if last < 0:
        return

    def minor(k: int) -> int:
        if big_k == 0:
            return v0
        # round(k*M/K): halves up (step) = floor((2kM + K) / 2K); halves down (stay) = ceil((2kM - K) / 2K)
        offset = (2 * k * big_m + big_k) // (2 * big_k) if ties == "step" else -((big_k - 2 * k * big_m) // (2 * big_k))
        return v0 + sv * offset

    # steps whose major coordinate lies in [0, u_size)
    lo_u, hi_u = (0 - u0, u_size - 1 - u0) if su > 0 else (u0 - (u_size - 1), u0)
    k_lo, k_hi = max(0, lo_u), min(last, hi_u)
    if k_lo > k_hi:
        return

    def inside_or_before(k: int) -> bool:  # minor not yet past the viewport's far side
        v = minor(k)
        return v <= v_size - 1 if sv > 0 else v >= 0

    def reached(k: int) -> bool:  # minor already at or past the viewport's near side
        v = minor(k)
        return v >= 0 if sv > 0 else v <= v_size - 1

    def first_true(lo: int, hi: int, test: Any) -> int:
        while lo < hi:
            mid = (lo + hi) // 2
            if test(mid):
                hi = mid
            else:
                lo = mid + 1
        return lo

    start = first_true(k_lo, k_hi + 1, reached)
    stop = first_true(start, k_hi + 1, lambda k: not inside_or_before(k))
    for k in range(start, stop):
        u, v = u0 + su * k, minor(k)
        x, y = (u, v) if x_major else (v, u)
        out.append((segment, y, x, x + 1))


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


def _multisample_lines(scene: Any, convention: Convention) -> Any:
    """Multisample lines (OpenGL 4.6, 14.5.4 "Line Multisample Rasterization"; dEQP's
    ``MultiSampleLineRasterizer``): the samples of the convention's pattern inside the
    ``line_width``-wide rectangle around each segment, each sample decided exactly at its
    own offset under the tie rule and snapping (:meth:`Convention.at_sample`), as the
    rectangle rule decides a pixel centre. Spans carry their sample index, sorted by
    segment, sample and row (as :func:`harness.oracle.coverage.exact_multisample`)."""
    from harness.contract.coverage import Coverage

    if convention.line.rule != "rectangle":
        raise ValueError(f"multisample lines are rectangles sampled per sample (GL 14.5.4), not {convention.line.describe()}: "
                         "declare Convention(samples=..., line=LineRule('rectangle'))")
    layers = [line_coverage(scene, convention.at_sample(k)) for k in range(convention.n_samples)]
    joined = Coverage.concat([Coverage(c.primitive, c.y, c.x0, c.x1, sample=np.full(len(c), k, dtype=np.int64))
                              for k, c in enumerate(layers)])
    return joined.take(np.argsort(joined.primitive, kind="stable"))


def line_coverage(scene: Any, convention: Convention) -> Any:
    """The exact coverage of a line scene (:func:`harness.oracle.coverage.exact_coverage` for lines).

    The end points are snapped by the convention first; then each segment is drawn by the
    convention's :class:`~harness.contract.conventions.LineRule`: :func:`diamond_exit_spans`,
    :func:`bresenham_spans` (walked in the rule's ``direction``) or :func:`rectangle_spans` (the scene's ``line_width``, the
    convention's sample point and tie rule). Segments beyond the compiled kernels' range
    are decided by the rational references (Bresenham's by its closed form in Python
    integers, clipped to the viewport): exact for every finite float64.

    Parameters
    ----------
    scene : harness.contract.scenes.LineScene
    convention : harness.contract.conventions.Convention
        Single-sample, or multisample with the rectangle rule (each sample of the pattern
        at its own offset: :func:`_multisample_lines`); an area convention, or a width-1
        rule under a multisample one: ValueError.

    Returns
    -------
    harness.contract.coverage.Coverage
        Spans of segment (``primitive``), row, x0, x1 sorted by segment, row and x0; no
        attributes. Segments with a NaN or infinite end point cover nothing.

    Examples
    --------
    >>> from harness.contract.scenes import LineScene
    >>> scene = LineScene.from_strips(6, 4, [[[0.5, 0.5], [4.5, 2.5], [0.5, 3.5]]])
    >>> line_coverage(scene, Convention()).counts(6, 4)
    array([[1, 1, 0, 0, 0, 0],
           [0, 0, 1, 1, 0, 0],
           [0, 0, 1, 1, 1, 0],
           [0, 1, 0, 0, 0, 0]], dtype=int32)
    """
    from harness.contract.coverage import Coverage

    if not convention.model.lines:
        raise ValueError(f"lines are defined for single-sample and multisample conventions, not {convention.kind} coverage")
    if convention.model.layered:
        return _multisample_lines(scene, convention)
    rule = convention.line
    a, b = scene.segments()
    a, b = convention.snap(a), convention.snap(b)
    n = a.shape[0]
    width, height = scene.width, scene.height
    finite = np.asarray(np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1), dtype=np.bool_)
    ends = np.concatenate([a, b], axis=1)
    why = rule.undefined_width(scene.line_width)
    if why:
        raise ValueError(why + ("" if not rule.diamond or rule.wide == "replicate" else
                                " (LineRule(wide='replicate') draws integer widths as GL does; the rectangle rule any width)"))
    extra: list[tuple[int, int, int, int]] = []
    if rule.diamond and scene.line_width != 1.0:
        return Coverage(*diamond_wide_spans(a, b, scene.line_width, width, height, rule.last_pixel, rule.rule))
    if rule.diamond:
        far = _beyond(ends, SAFE_MIN, SAFE_MAX) & finite
        near = finite & ~far
        spans = diamond_exit_spans(np.where(near[:, None], a, np.nan), np.where(near[:, None], b, np.nan), width, height,
                                   rule.last_pixel, rule.rule)
        for k in np.flatnonzero(far):
            _diamond_far(int(k), a[k], b[k], width, height, rule.last_pixel, extra, _gl_flag(rule.rule))
    elif rule.rule == "bresenham":
        with np.errstate(invalid="ignore"):
            p0 = np.where(finite[:, None], end_point_pixels(np.where(finite[:, None], a, 0.0), rule.rounding), 0.0)
            p1 = np.where(finite[:, None], end_point_pixels(np.where(finite[:, None], b, 0.0), rule.rounding), 0.0)
        far = (np.abs(np.concatenate([p0, p1], axis=1)) > BRESENHAM_MAX).any(axis=1) & finite
        near = finite & ~far
        spans = bresenham_spans(np.where(near[:, None], a, np.nan), np.where(near[:, None], b, np.nan), width, height,
                                rule.rounding, rule.ties, rule.last_pixel, rule.direction)
        for k in np.flatnonzero(far):
            # the end pixels as Python integers: the walk's direction decided exactly
            start, end = (np.array([[int(p[k, 0]), int(p[k, 1])]], dtype=object) for p in (p0, p1))
            start, end = _walk_ends(start, end, rule.direction)
            _bresenham_far(int(k), (start[0, 0], start[0, 1]), (end[0, 0], end[0, 1]), width, height, rule.ties,
                           rule.last_pixel, extra)
    else:
        values = np.concatenate([ends, np.full((n, 1), scene.line_width)], axis=1)
        far = _beyond(values, RECT_SAFE_MIN, RECT_SAFE_MAX) & finite
        near = finite & ~far
        kw = dict(width=width, height=height)
        spans = rectangle_spans(np.where(near[:, None], a, np.nan), np.where(near[:, None], b, np.nan), scene.line_width,
                                convention.sample, convention.tie, **kw)
        for k in np.flatnonzero(far):
            s, y, x0, x1 = rectangle_spans_rational(a[k:k + 1], b[k:k + 1], scene.line_width, convention.sample, convention.tie, **kw)
            extra.extend((int(k), int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1))
    p, y, x0, x1 = spans
    if extra:
        more = np.array(extra, dtype=np.int64).T
        p, y, x0, x1 = (np.concatenate([u, v]) for u, v in zip((p, y, x0, x1), more))
        order = np.lexsort((x0, y, p))
        p, y, x0, x1 = p[order], y[order], x0[order], x1[order]
        if rule.rule != "rectangle":  # far pixels come one by one: merge them into runs
            lengths = x1 - x0
            return Coverage.from_pixels(np.repeat(p, lengths), expand(x0, lengths), np.repeat(y, lengths))
    return Coverage(p, y, x0, x1)

