"""skia's supersampler: the anti-aliasing model of tiny-skia (and of skia's own ``SkScan_AntiPath``
before it gave way to analytic AA), as its sources define it, in integers.

tiny-skia (``src/scan/path_aa.rs``, a port of skia's ``SkScan_AntiPath.cpp``; ``src/scan/path.rs``,
``src/edge.rs``, ``src/edge_builder.rs``, ``src/fixed_point.rs``, ``src/alpha_runs.rs``) fills an
anti-aliased path by running its aliased scan converter on the path scaled by
``SCALE = 2**SUPERSAMPLE_SHIFT`` (``SUPERSAMPLE_SHIFT = 2``) and accumulating the spans of the
``SCALE`` sub-scanlines of each pixel row into 8-bit alphas:

* **input** (``LineEdge::new``): every path point is an f32 (usvg's and tiny-skia's ``Point``),
  scaled by ``1 << (shift + 6)`` (exact: a power of two) and cast to i32 -- truncation toward
  zero, saturating (``(p.x * scale) as i32``): a 2**-(shift+6) px grid (1/256 px), 26.6 fixed
  point in sub-pixel units.
* **edges**: an edge (y0 < y1 after swapping, ``winding`` -1 if swapped) covers the sub-scanlines
  ``first_y = fdot6::round(y0) = (y0 + 32) >> 6`` to ``last_y = fdot6::round(y1) - 1``: sub-row
  k's centre line ``k + 1/2`` in ``(y0, y1]`` (half open); none when they are equal. Its slope
  ``dx = fdot6::div(x1 - x0, y1 - y0)``, 16.16 truncated toward zero; its x at ``first_y``'s
  centre ``(x0 + fdot16::mul(dx, (first_y << 6) + 32 - y0)) << 10`` (``compute_dy``;
  ``fdot16::mul`` floors), then ``x += dx`` per sub-row: a 16.16 DDA.
  ``BasicEdgeBuilder::push_line`` merges a vertical edge into the previous one when they share
  x and abut or overlap (``combine_vertical``).
* **walk** (``walk_edges``): the edges sorted by (``first_y``, x), stable; per sub-row the active
  edges in x order (a linked list kept sorted by ``backward_insert_edge_based_on_x`` and
  ``insert_new_edges``: equal x keep their order, a new edge goes before the equal ones), each
  edge's x rounded, ``fdot16::round_to_i32`` = ``(x + 0x8000) >> 16``, the winding summed
  (even-odd: its low bit); a span ``[left, x)`` of sub-pixels (1/SCALE px) is blitted where the
  rule stops holding, unless empty.
* **accumulation** (``SuperBlitter::blit_h``, ``AlphaRuns::add``): a span's first pixel, when only
  partly covered, gets ``coverage_to_partial_alpha(fb) = fb << (8 - 2 shift)`` (16 per covered
  sub-pixel for shift 2), its last likewise, the pixels between ``max_value = (1 << (8 - shift))
  - (((y & MASK) + 1) >> shift)``: 64, but 63 on a pixel's last sub-row, so four full sub-rows
  give 255; the first pixel's and the middle's sums are clamped 256 -> 255 (``tmp - (tmp >>
  8)``), the last pixel's added as a u8. The pixel's alpha is the sum (the raster pipeline
  draws an opaque paint at that coverage; resvg's PNG keeps the alpha byte).

So a pixel's level is ``16 N`` for N covered sub-samples (sub-row k, sub-column q: the
sub-pixel ``4 i + q`` lies in one of sub-row ``4 j + k``'s spans) but for the full-pixel runs'
63 on the last sub-row and the clamps: within one level of ``255 N / 16``.

As a convention (:class:`harness.contract.conventions.Convention`):
``Convention(coverage="area", supersample=2, input="float32")`` -- the model object
:data:`harness.contract.coverage_models.SKIA_SUPERSAMPLED_AREA`; ``supersample`` is the
``SUPERSAMPLE_SHIFT`` (1 .. 4: 2, 4, 8 or 16 sub-scanlines per pixel, x on the same
sub-pixel grid). The oracle's alphas are the library's 8-bit levels / 255 exactly (quantised
by the model: the convention's tolerance judges the library against them).

Scope (what the model leaves out, each named where the code stands):

* a path whose pixel box reaches outside the screen has its lines clipped to the screen in
  f32 first (``edge_clipper.rs``, ``line_clipper.rs``: the intersections in f64, rounded to f32;
  parts left or right of it moved onto its side as vertical lines), as the oracle does; an
  adapter drawing on a canvas translated by whole pixels clips in translated coordinates,
  whose f64 intersections may round to another f32 (not seen);
* paths whose clipped bounds overflow a short when shifted (coordinates beyond 8191 px) are
  filled aliased by tiny-skia (``rect_overflows_short_shift``): not modelled (the oracle keeps
  supersampling);
* quadratic and cubic segments: not reached (our paths are polygons);
* a path whose f32 bounds have a width or height of at most 2**-12 draws nothing
  (``PixmapMut::fill_path``, ``is_nearly_zero``), nor one with a non-finite coordinate.

skia-python 144 (skia m144) no longer supersamples: ``SkScan::AntiFillPath`` calls
``SkScan::AAAFillPath`` for every path (``src/core/SkScan_AntiPath.cpp``), and no model
explains its alphas within a level: :data:`SKIA_AAA_NOTE` says why, with the numbers.

:func:`skia_supersampled_coverage` (triangles) and :func:`skia_supersampled_paths` (paths) are
the compiled oracles; :func:`reference_levels` the uncompiled reference, written from the
sources a second time (Python integers, a Python list for the active edges), compared in
tests/oracle/test_supersample_models.py.

>>> from harness.contract.scenes import PathScene
>>> square = PathScene.from_paths(3, 2, [[[[0.5, 0], [2.25, 0], [2.25, 2], [0.5, 2]]]])
>>> c = skia_supersampled_paths(square, Convention(coverage="area", supersample=2, input="float32"))
>>> (c.alpha * 255).round().astype(int).tolist()  # 2 sub-columns (32 levels); full (255); 1 sub-column (64 - 1 + ...)
[128, 255, 64, 128, 255, 64]
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.geometry.exact import orientation

__all__ = ["TINY_SKIA_SHIFT", "SKIA_AAA_NOTE", "skia_supersampled_coverage", "skia_supersampled_paths",
           "path_levels", "reference_levels"]

# tiny-skia src/scan/path_aa.rs: const SUPERSAMPLE_SHIFT: u32 = 2 (skia's SK_SUPERSAMPLE_SHIFT)
TINY_SKIA_SHIFT = 2
# i32's range (Rust's `as i32` saturates; NaN gives 0)
_I32_MIN = -(2**31)
_I32_MAX = 2**31 - 1
# tiny-skia-path scalar.rs: SCALAR_NEARLY_ZERO = 1 / (1 << 12)
_NEARLY_ZERO = 1.0 / 4096.0  # tiny-skia-path scalar.rs: SCALAR_NEARLY_ZERO

SKIA_AAA_NOTE = (
    "skia-python 144 has no supersampler model: SkScan::AntiFillPath (src/core/SkScan_AntiPath.cpp, "
    "the stored m14x source) calls SkScan::AAAFillPath for every path -- analytic AA whose alphas come "
    "from fixed-point trapezoid areas (SkScan_AAAPath.cpp: trapezoid_to_alpha, partial_triangle_to_alpha "
    "on a >> 11, approximate_intersection where edges cross, rows merged by is_smooth_enough, vertex y "
    "snapped to 1/4 px by SkAnalyticEdge::setLine, the RLE blitter's snapAlpha sending alphas above 247 "
    "to 255 and below 8 to 0). Measured (skia-python 144.1): a vertical edge swept across a pixel in "
    "1/256 px steps gives 256 levels on a rectangle or a 4-point quad but 17 (multiples of 16) on a "
    "triangle or pentagon -- two methods, chosen by the path; on random triangles all 255 levels occur; "
    "against tiny-skia's supersampler (this module) 2,268 of 4,444 pixels differ (up to 79 levels), "
    "against a 16 x 4 supersampler 759 of 1,193 (up to 44), against the exact area of the triangle with "
    "y snapped to 1/4 px median 0.9 levels but up to 65 (e.g. triangle (2.3, 1.7), (13.6, 4.2), "
    "(5.1, 12.9), pixel (5, 12): skia 155, exact area 118.75, supersampler 96): no model within one "
    "level; identify keeps its fitted 16 x 4 pattern and a measured tolerance."
)


# -- the compiled procedure -------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _to_i32(v):  # type: ignore[no-untyped-def]
    """Rust's ``v as i32`` for a float: truncation toward zero, saturating, NaN -> 0."""
    if v != v:
        return 0
    if v >= 2147483647.0:
        return 2147483647
    if v <= -2147483648.0:
        return -2147483648
    return int(v)


@numba.njit(cache=True, inline="always")
def _tdiv(a, b):  # type: ignore[no-untyped-def]
    """C's (and Rust's) integer division: truncation toward zero."""
    q = abs(a) // abs(b)
    return -q if (a < 0) != (b < 0) else q


@numba.njit(cache=True)
def _push_line(ax, ay, bx, by, scale, ex, edx, efirst, elast, ewind, n):  # type: ignore[no-untyped-def]
    """``BasicEdgeBuilder::push_line``: ``LineEdge::new`` of the f32 points a -> b on the
    ``scale``-d grid, merged into the previous edge when both are vertical at one x and they
    abut or overlap (``combine_vertical``); returns the new number of edges."""
    x0 = _to_i32(ax * scale)
    y0 = _to_i32(ay * scale)
    x1 = _to_i32(bx * scale)
    y1 = _to_i32(by * scale)
    winding = 1
    if y0 > y1:
        x0, y0, x1, y1 = x1, y1, x0, y0
        winding = -1
    top = (y0 + 32) >> 6  # fdot6::round
    bottom = (y1 + 32) >> 6
    if top == bottom:
        return n  # a zero-height line
    slope = _tdiv((x1 - x0) * 65536, y1 - y0)  # fdot6::div (fdot16::div clamps)
    slope = min(max(slope, -2147483648), 2147483647)
    dy = (top << 6) + 32 - y0  # compute_dy
    x = (x0 + ((slope * dy) >> 16)) << 10  # fdot16::mul floors; fdot6::to_fdot16
    first, last = top, bottom - 1
    if slope == 0 and n > 0 and edx[n - 1] == 0 and ex[n - 1] == x:
        j = n - 1
        if winding == ewind[j]:
            if last + 1 == efirst[j]:
                efirst[j] = first
                return n
            if first == elast[j] + 1:
                elast[j] = last
                return n
        elif first == efirst[j]:
            if last == elast[j]:
                return n - 1  # Combine::Total
            if last < elast[j]:
                efirst[j] = last + 1
                return n
            efirst[j] = elast[j] + 1
            elast[j] = last
            ewind[j] = winding
            return n
        elif last == elast[j]:
            if first > efirst[j]:
                elast[j] = first - 1
            else:
                elast[j] = efirst[j] - 1
                efirst[j] = first
                ewind[j] = winding
            return n
    ex[n] = x
    edx[n] = slope
    efirst[n] = first
    elast[n] = last
    ewind[n] = winding
    return n + 1


@numba.njit(cache=True, inline="always")
def _f32(v):  # type: ignore[no-untyped-def]
    """A float64 rounded to f32 (Rust's ``as f32``), as a float64."""
    return float(np.float32(v))


@numba.njit(cache=True)
def _sect_horizontal(x0, y0, x1, y1, y):  # type: ignore[no-untyped-def]
    """line_clipper.rs ``sect_with_horizontal``: the x where the line meets height y, in
    f64, pinned to its x range, as f32 (the f32 average of its ends when it is nearly flat)."""
    if abs(_f32(y1 - y0)) <= _NEARLY_ZERO:
        return _f32(_f32(x0 + x1) * 0.5)
    r = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    return _f32(min(max(r, min(x0, x1)), max(x0, x1)))


@numba.njit(cache=True)
def _sect_vertical(x0, y0, x1, y1, x):  # type: ignore[no-untyped-def]
    """line_clipper.rs ``sect_clamp_with_vertical``: the y where the line meets x = x, in
    f64, as f32, pinned to its y range (the f32 average of its ends when it is nearly upright)."""
    if abs(_f32(x1 - x0)) <= _NEARLY_ZERO:
        r = _f32(_f32(y0 + y1) * 0.5)
    else:
        r = _f32(y0 + (x - x0) * (y1 - y0) / (x1 - x0))
    return min(max(r, min(y0, y1)), max(y0, y1))


@numba.njit(cache=True)
def _clip_line(ax, ay, bx, by, left, top, right, bottom, out):  # type: ignore[no-untyped-def]
    """line_clipper.rs ``clip`` (``can_cull_to_the_right`` false): the line a -> b cut to
    the clip rectangle in f32, its parts left (right) of it moved onto its left (right)
    side as vertical lines; the points, in a -> b order, into ``out`` (4, 2); returns how
    many (0: the line lies wholly above or below)."""
    sx = (ax, bx)
    sy = (ay, by)
    i0, i1 = (0, 1) if ay < by else (1, 0)
    if sy[i1] <= top or sy[i0] >= bottom:
        return 0
    tx = [ax, bx]
    ty = [ay, by]
    if sy[i0] < top:
        tx[i0], ty[i0] = _sect_horizontal(ax, ay, bx, by, top), top
    if ty[i1] > bottom:
        tx[i1], ty[i1] = _sect_horizontal(ax, ay, bx, by, bottom), bottom
    if sx[0] < sx[1]:
        i0, i1, reverse = 0, 1, False
    else:
        i0, i1, reverse = 1, 0, True
    rx = np.empty(4)
    ry = np.empty(4)
    count = 1
    if tx[i1] <= left or tx[i0] >= right:
        side = left if tx[i1] <= left else right
        rx[0], ry[0], rx[1], ry[1] = side, ty[0], side, ty[1]
        reverse = False
    else:
        k = 0
        if tx[i0] < left:
            rx[0], ry[0] = left, ty[i0]
            k = 1
            rx[1], ry[1] = left, _sect_vertical(tx[0], ty[0], tx[1], ty[1], left)
        else:
            rx[0], ry[0] = tx[i0], ty[i0]
        k += 1
        if tx[i1] > right:
            rx[k], ry[k] = right, _sect_vertical(tx[0], ty[0], tx[1], ty[1], right)
            k += 1
            rx[k], ry[k] = right, ty[i1]
        else:
            rx[k], ry[k] = tx[i1], ty[i1]
        count = k
    for i in range(count + 1):
        j = count - i if reverse else i
        out[i, 0] = rx[j]
        out[i, 1] = ry[j]
    return count + 1


@numba.njit(cache=True)
def _build_edges(vx, vy, starts, sizes, scale, clip, rect, ex, edx, efirst, elast, ewind):  # type: ignore[no-untyped-def]
    """``BasicEdgeBuilder::build`` of the contours (``starts``/``sizes`` into ``vx``/``vy``,
    each closed), every line through the edge clipper (:func:`_clip_line`, to ``rect`` =
    (left, top, right, bottom)) when ``clip`` (the path's box is not inside the screen);
    returns the number of edges written."""
    n = 0
    points = np.empty((4, 2))
    for c in range(starts.size):
        s, m = starts[c], sizes[c]
        for k in range(m):
            p = s + k
            q = s + (k + 1) % m
            if not clip:
                n = _push_line(vx[p], vy[p], vx[q], vy[q], scale, ex, edx, efirst, elast, ewind, n)
                continue
            count = _clip_line(vx[p], vy[p], vx[q], vy[q], rect[0], rect[1], rect[2], rect[3], points)
            for i in range(count - 1):
                n = _push_line(points[i, 0], points[i, 1], points[i + 1, 0], points[i + 1, 1], scale,
                               ex, edx, efirst, elast, ewind, n)
    return n


@numba.njit(cache=True)
def _blit_h(acc, x, y, width, shift, super_left, top, left, right):  # type: ignore[no-untyped-def]
    """``SuperBlitter::blit_h`` + ``AlphaRuns::add``: the span [x, x + width) of sub-row y
    (sub-pixel units) into acc[row - top, column - left] (columns in [left, right) kept)."""
    mask = (1 << shift) - 1
    # the span cut to the screen's columns: tiny-skia clips the edges to the screen first
    # (edge_clipper.rs), so no span reaches past it
    stop = min(x + width, right << shift) - super_left
    start = max(x - super_left, 0)
    if stop <= start:
        return
    fb = start & mask
    fe = stop & mask
    n = (stop >> shift) - (start >> shift) - 1
    if n < 0:
        fb = fe - fb
        n = 0
        fe = 0
    elif fb == 0:
        n += 1
    else:
        fb = (1 << shift) - fb
    max_value = (1 << (8 - shift)) - (((y & mask) + 1) >> shift)
    row = (y >> shift) - top
    px = (start >> shift) + (super_left >> shift)
    if fb != 0:
        if left <= px < right:
            t = acc[row, px - left] + (fb << (8 - 2 * shift))
            acc[row, px - left] = t - (t >> 8)  # clamp 256 -> 255
        px += 1
    for _ in range(n):
        if left <= px < right:
            t = acc[row, px - left] + max_value
            acc[row, px - left] = t - (t >> 8)  # catch_overflow
        px += 1
    if fe != 0 and left <= px < right:
        acc[row, px - left] = (acc[row, px - left] + (fe << (8 - 2 * shift))) & 255  # a u8 add


@numba.njit(cache=True, inline="always")
def _unlink(i, prev, nxt):  # type: ignore[no-untyped-def]
    """remove_edge: take edge i out of the linked list."""
    a, b = prev[i], nxt[i]
    nxt[a] = b
    prev[b] = a


@numba.njit(cache=True, inline="always")
def _link_after(i, after, prev, nxt):  # type: ignore[no-untyped-def]
    """insert_edge_after: put edge i right after edge ``after``."""
    prev[i] = after
    nxt[i] = nxt[after]
    prev[nxt[after]] = i
    nxt[after] = i


@numba.njit(cache=True)
def _backward_insert(curr, x, prev, nxt):  # type: ignore[no-untyped-def]
    """backward_insert_edge_based_on_x: ripple edge ``curr`` back until the list is x-sorted."""
    p = prev[curr]
    while p != 0 and x[p] > x[curr]:
        p = prev[p]
    if nxt[p] != curr:
        _unlink(curr, prev, nxt)
        _link_after(curr, p, prev, nxt)


@numba.njit(cache=True)
def _insert_new_edges(new, curr_y, x, first, prev, nxt):  # type: ignore[no-untyped-def]
    """insert_new_edges: the edges starting on sub-row ``curr_y`` (``new`` the first of
    them) moved into x order among the active ones, each before the equal ones it meets."""
    if first[new] != curr_y:
        return
    p = prev[new]
    if x[p] <= x[new]:
        return
    start = p  # backward_insert_start
    while prev[start] >= 0:
        start = prev[start]
        if x[start] <= x[new]:
            break
    while True:
        following = nxt[new]
        keep = False
        while True:
            after = nxt[start]
            if after == new:
                keep = True
                break
            if x[after] >= x[new]:
                break
            start = after
        if not keep:
            _unlink(new, prev, nxt)
            _link_after(new, start, prev, nxt)
        start = new
        new = following
        if first[new] != curr_y:
            return


@numba.njit(cache=True)
def _sorted_list(ex, edx, efirst, elast, ewind, n, start_y):  # type: ignore[no-untyped-def]
    """The edges sorted by (first_y, x), stable (Rust's sort_by), with a head (index 0, x =
    i32::MIN) and a tail (n + 1) around them, linked in that order: (x, dx, first, last,
    winding, prev, next). An edge starting above the walk (the screen's top) enters at its
    first row, its x stepped there."""
    key = np.empty(n, dtype=np.int64)
    for i in range(n):
        key[i] = efirst[i] * (np.int64(1) << 34) + (ex[i] + (np.int64(1) << 33))
    order = np.argsort(key, kind="mergesort")
    size = n + 2
    x = np.zeros(size, dtype=np.int64)
    dx = np.zeros(size, dtype=np.int64)
    first = np.zeros(size, dtype=np.int64)
    last = np.zeros(size, dtype=np.int64)
    wind = np.zeros(size, dtype=np.int64)
    x[0] = -2147483648
    first[0] = -(np.int64(1) << 62)
    first[n + 1] = np.int64(1) << 62
    for i in range(n):
        e = order[i]
        x[i + 1], dx[i + 1], first[i + 1], last[i + 1], wind[i + 1] = ex[e], edx[e], efirst[e], elast[e], ewind[e]
        if first[i + 1] < start_y:
            x[i + 1] += (start_y - first[i + 1]) * dx[i + 1]
            first[i + 1] = start_y
    prev = np.arange(-1, size - 1)
    nxt = np.arange(1, size + 1)
    return x, dx, first, last, wind, prev, nxt


@numba.njit(cache=True)
def _walk(ex, edx, efirst, elast, ewind, n, evenodd, start_y, stop_y, shift, super_left,  # type: ignore[no-untyped-def]
          top, left, right, acc):
    """``walk_edges`` over sub-rows [start_y, stop_y), on the linked list tiny-skia keeps
    (:func:`_sorted_list`): each sub-row's spans blitted (:func:`_blit_h`), the edges
    stepped and kept x-sorted, the next sub-row's new edges inserted."""
    x, dx, first, last, wind, prev, nxt = _sorted_list(ex, edx, efirst, elast, ewind, n, start_y)
    mask = 1 if evenodd else -1
    curr_y = start_y
    while curr_y < stop_y:
        w = 0
        lft = 0
        prev_x = x[0]
        curr = nxt[0]
        while first[curr] <= curr_y:
            if last[curr] >= curr_y:  # (an edge ending above the screen is never drawn)
                xr = (x[curr] + 0x8000) >> 16  # fdot16::round_to_i32
                if (w & mask) == 0:
                    lft = xr  # an interval starts
                w += wind[curr]
                if (w & mask) == 0 and xr - lft > 0:
                    _blit_h(acc, lft, curr_y, xr - lft, shift, super_left, top, left, right)
            following = nxt[curr]
            if last[curr] <= curr_y:
                _unlink(curr, prev, nxt)  # done with this edge
            else:
                x[curr] += dx[curr]
                if x[curr] < prev_x:
                    _backward_insert(curr, x, prev, nxt)
                else:
                    prev_x = x[curr]
            curr = following
        curr_y += 1
        if curr_y < stop_y:
            _insert_new_edges(curr, curr_y, x, first, prev, nxt)


@numba.njit(cache=True)
def _path_box(vx, vy, width, height):  # type: ignore[no-untyped-def]
    """The path's pixel box (floor/ceil of its f32 bounds) clipped to the screen, and
    whether it draws at all, and whether its edges are clipped: (draws, left, top, right,
    bottom, clip)."""
    lo_x = np.inf
    lo_y = np.inf
    hi_x = -np.inf
    hi_y = -np.inf
    for k in range(vx.size):
        if not (math.isfinite(vx[k]) and math.isfinite(vy[k])):
            return False, 0, 0, 0, 0, False
        lo_x = min(lo_x, vx[k])
        hi_x = max(hi_x, vx[k])
        lo_y = min(lo_y, vy[k])
        hi_y = max(hi_y, vy[k])
    if vx.size == 0:
        return False, 0, 0, 0, 0, False
    # PixmapMut::fill_path: empty paths and horizontal or vertical lines are skipped (f32 widths)
    if abs(np.float32(np.float32(hi_x) - np.float32(lo_x))) <= 1.0 / 4096.0 or \
            abs(np.float32(np.float32(hi_y) - np.float32(lo_y))) <= 1.0 / 4096.0:
        return False, 0, 0, 0, 0, False
    if max(abs(lo_x), abs(hi_x), abs(lo_y), abs(hi_y)) > 2.0**30:
        return False, 0, 0, 0, 0, False  # beyond the i32 grid (the adapters refuse beyond 2**20)
    left = int(math.floor(lo_x))
    top = int(math.floor(lo_y))
    right = int(math.ceil(hi_x))
    bottom = int(math.ceil(hi_y))
    cl, ct, cr, cb = max(left, 0), max(top, 0), min(right, width), min(bottom, height)
    if cl >= cr or ct >= cb:
        return False, 0, 0, 0, 0, False
    # fill_path_impl's path_contained_in_clip: the box inside the screen, else the edges are clipped
    return True, cl, ct, cr, cb, not (left >= 0 and top >= 0 and right <= width and bottom <= height)


@numba.njit(cache=True)
def _levels(vx, vy, starts, sizes, evenodd, shift, width, height):  # type: ignore[no-untyped-def]
    """One path's 8-bit levels on its pixel box cut to the screen: (left, top, acc), acc
    (rows, columns) int64; an empty acc when it draws nothing."""
    draws, left, top, right, bottom, clip = _path_box(vx, vy, width, height)
    if not draws:
        return 0, 0, np.zeros((0, 0), dtype=np.int64)
    m = 3 * vx.size  # a clipped line gives up to three edges
    ex = np.empty(m, dtype=np.int64)
    edx = np.empty(m, dtype=np.int64)
    efirst = np.empty(m, dtype=np.int64)
    elast = np.empty(m, dtype=np.int64)
    ewind = np.empty(m, dtype=np.int64)
    rect = np.array([0.0, 0.0, float(width), float(height)])
    n = _build_edges(vx, vy, starts, sizes, float(1 << (shift + 6)), clip, rect, ex, edx, efirst, elast, ewind)
    acc = np.zeros((bottom - top, right - left), dtype=np.int64)
    if n < 2:
        return left, top, acc  # build_edges: fewer than two edges draw nothing
    # the walk's sub-rows: the path's box cut to the screen's (fill_path_impl's start_y, stop_y);
    # the super blitter's left: that box's left
    _walk(ex, edx, efirst, elast, ewind, n, evenodd, top << shift, bottom << shift, shift, left << shift,
          top, left, right, acc)
    return left, top, acc


@numba.njit(cache=True)
def _scene_kernel(vx, vy, starts, sizes, path_first, path_count, active, evenodd, shift, width, height,  # type: ignore[no-untyped-def]
                  write, out_p, out_y, out_x0, out_x1, out_alpha):
    """Spans and alphas (write) or only their counts: (spans, pixels). Path k's contours
    are ``path_first[k] .. path_first[k] + path_count[k]`` of ``starts``/``sizes``."""
    spans = 0
    pixels = 0
    for k in range(path_first.size):
        if not active[k]:
            continue
        c0, c1 = path_first[k], path_first[k] + path_count[k]
        lo = starts[c0] if c1 > c0 else 0
        hi = starts[c1 - 1] + sizes[c1 - 1] if c1 > c0 else 0
        left, top, acc = _levels(vx[lo:hi], vy[lo:hi], starts[c0:c1] - lo, sizes[c0:c1], evenodd, shift, width, height)
        for r in range(acc.shape[0]):
            i0 = 0
            i1 = acc.shape[1]
            while i0 < i1 and acc[r, i0] == 0:
                i0 += 1
            while i1 > i0 and acc[r, i1 - 1] == 0:
                i1 -= 1
            if i0 >= i1:
                continue
            if write:
                out_p[spans] = k
                out_y[spans] = top + r
                out_x0[spans] = left + i0
                out_x1[spans] = left + i1
                for i in range(i0, i1):
                    out_alpha[pixels + i - i0] = acc[r, i] / 255.0
            spans += 1
            pixels += i1 - i0
    return spans, pixels


def _received(coordinates: NDArray[np.float64], convention: Convention) -> NDArray[np.float64]:
    """The coordinates as the supersampler holds them: the convention's input (and snapping),
    then f32 (skia's and tiny-skia's points are f32; an overflow is infinite, drawing nothing)."""
    with np.errstate(invalid="ignore", over="ignore"):
        return convention.snap(np.asarray(coordinates, dtype=np.float64)).astype(np.float32).astype(np.float64)


def _run(vertices: NDArray[np.float64], starts: NDArray[np.int64], sizes: NDArray[np.int64], path_first: NDArray[np.int64],
         path_count: NDArray[np.int64], active: NDArray[np.bool_], evenodd: bool, convention: Convention,
         width: int, height: int) -> Coverage:
    shift = convention.supersample
    if not 1 <= shift <= 4:
        raise ValueError(f"the supersampler's shift must lie in 1..4, not {shift!r}")
    vx = np.ascontiguousarray(vertices[:, 0])
    vy = np.ascontiguousarray(vertices[:, 1])
    args = (vx, vy, starts, sizes, path_first, path_count, active, bool(evenodd), int(shift), int(width), int(height))
    empty_i, empty_f = np.empty(0, dtype=np.int64), np.empty(0)
    spans, pixels = _scene_kernel(*args, False, empty_i, empty_i, empty_i, empty_i, empty_f)
    out = [np.empty(spans, dtype=np.int64) for _ in range(4)]
    alpha = np.empty(pixels)
    _scene_kernel(*args, True, *out, alpha)  # type: ignore[call-arg]
    return Coverage(out[0], out[1], out[2], out[3], alpha=alpha)


def skia_supersampled_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The oracle of ``Convention(coverage="area", supersample=shift)`` on triangles: each
    triangle filled alone as a one-contour path (nonzero), its alphas the supersampler's
    8-bit levels / 255 (module docstring). Culling is the convention's (on the received
    triangle); a zero-area triangle is filled as the library fills it (its three edges'
    DDAs may leave a sliver).

    >>> c = skia_supersampled_coverage(Scene(2, 1, [[[0, 0], [2, 0], [0, 1]]]), Convention(coverage="area", supersample=2))
    >>> (c.alpha * 255).round().astype(int).tolist()  # 12 and 4 of the 16 sub-samples
    [192, 64]
    """
    positions = _received(scene.positions, convention).reshape(-1, 3, 2)
    n = positions.shape[0]
    active = np.ones(n, dtype=bool)
    if convention.cull != "none":
        with np.errstate(invalid="ignore"):
            sign = orientation(np.where(np.isfinite(positions), positions, 0.0))
        active &= sign != (1 if convention.cull == "cw" else -1)
    vertices = positions.reshape(-1, 2)
    starts = np.arange(n, dtype=np.int64) * 3
    return _run(vertices, starts, np.full(n, 3, dtype=np.int64), np.arange(n, dtype=np.int64), np.ones(n, dtype=np.int64),
                active, False, convention, scene.width, scene.height)


def skia_supersampled_paths(scene: PathScene, convention: Convention) -> Coverage:
    """The oracle of ``Convention(coverage="area", supersample=shift)`` on paths: each path
    filled alone under the scene's fill rule (module docstring), alphas the 8-bit levels /
    255. Culling does not apply to paths."""
    vertices = _received(scene.vertices, convention)
    order = np.argsort(scene.contour_path, kind="stable")
    ends = np.cumsum(scene.contour_sizes)
    starts_all = ends - scene.contour_sizes
    # contours gathered path by path (a path's contours need not be adjacent in the scene)
    pieces = [vertices[starts_all[c]:ends[c]] for c in order]
    gathered = np.concatenate(pieces) if pieces else np.zeros((0, 2))
    sizes = scene.contour_sizes[order].astype(np.int64)
    starts = (np.cumsum(sizes) - sizes).astype(np.int64)
    n = len(scene)
    path_count = np.bincount(scene.contour_path, minlength=n).astype(np.int64)
    path_first = (np.cumsum(path_count) - path_count).astype(np.int64)
    return _run(np.ascontiguousarray(gathered), starts, sizes, path_first, path_count, np.ones(n, dtype=bool),
                scene.fill_rule == "evenodd", convention, scene.width, scene.height)


def path_levels(contours: Sequence[ArrayLike], width: int, height: int, fill_rule: str = "nonzero",
                shift: int = TINY_SKIA_SHIFT) -> NDArray[np.int64]:
    """The (height, width) 8-bit levels of one path (contours of (K, 2) float coordinates,
    taken as f32) on a width x height screen, by the compiled procedure.

    >>> path_levels([[[0, 0], [1, 0], [1, 1], [0, 1]]], 2, 1).tolist()
    [[255, 0]]
    """
    scene = PathScene.from_paths(width, height, [contours], fill_rule)
    cov = skia_supersampled_paths(scene, Convention(coverage="area", supersample=shift, input="float32"))
    out = np.zeros((height, width), dtype=np.int64)
    _, x, y = cov.pixels()
    out[y, x] = np.rint(np.asarray(cov.alpha) * 255.0).astype(np.int64)
    return out


# -- the reference: the same procedure written again, in Python integers ------------------------


def _reference_edges(pts: list[NDArray[np.float32]], scale: float, rect: tuple[float, float, float, float] | None
                     ) -> list[list[int]]:
    """``LineEdge::new`` and ``combine_vertical`` in Python integers: [x, dx, first, last,
    winding]; each line clipped to ``rect`` first when given (the compiled clipper, run
    uncompiled: :func:`_clip_line`)."""

    def as_i32(v: float) -> int:
        return max(_I32_MIN, min(_I32_MAX, math.trunc(v)))

    edges: list[list[int]] = []
    lines = []
    points = np.empty((4, 2))
    for c in pts:
        for k in range(len(c)):
            (ax, ay), (bx, by) = (float(v) for v in c[k]), (float(v) for v in c[(k + 1) % len(c)])
            if rect is None:
                lines.append((ax, ay, bx, by))
                continue
            count = _clip_line.py_func(ax, ay, bx, by, *rect, points)  # type: ignore[no-untyped-call]
            lines += [(points[i, 0], points[i, 1], points[i + 1, 0], points[i + 1, 1]) for i in range(count - 1)]
    for ax, ay, bx, by in lines:
        x0, y0, x1, y1 = (as_i32(float(v) * scale) for v in (ax, ay, bx, by))
        winding = 1
        if y0 > y1:
            x0, y0, x1, y1, winding = x1, y1, x0, y0, -1
        top, bottom = (y0 + 32) // 64, (y1 + 32) // 64
        if top == bottom:
            continue
        num, den = (x1 - x0) * 65536, y1 - y0
        slope = max(_I32_MIN, min(_I32_MAX, abs(num) // den * (1 if num >= 0 else -1)))
        edge = [(x0 + (slope * ((top * 64) + 32 - y0)) // 65536) * 1024, slope, top, bottom - 1, winding]
        if not (slope == 0 and edges and edges[-1][1] == 0 and edges[-1][0] == edge[0] and _combined(edge, edges)):
            edges.append(edge)
    return edges


def _combined(edge: list[int], edges: list[list[int]]) -> bool:
    """combine_vertical of ``edge`` into the last of ``edges`` (both vertical, same x):
    whether it was absorbed (the last edge changed or dropped)."""
    last = edges[-1]
    if edge[4] == last[4]:
        if edge[3] + 1 == last[2]:
            last[2] = edge[2]
            return True
        if edge[2] == last[3] + 1:
            last[3] = edge[3]
            return True
        return False
    if edge[2] == last[2]:
        if edge[3] == last[3]:
            edges.pop()
        elif edge[3] < last[3]:
            last[2] = edge[3] + 1
        else:
            last[2], last[3], last[4] = last[3] + 1, edge[3], edge[4]
        return True
    if edge[3] == last[3]:
        if edge[2] > last[2]:
            last[3] = edge[2] - 1
        else:
            last[3], last[2], last[4] = last[2] - 1, edge[2], edge[4]
        return True
    return False


def _reference_row(lst: list[list[int]], y: int, rule: int) -> list[tuple[int, int]]:
    """One sub-row of ``walk_edges`` on the list (active edges first): its spans; the list
    stepped, x-sorted again and the next sub-row's new edges inserted."""
    w, left, prev_x, i = 0, 0, _I32_MIN, 0
    spans = []
    while i < len(lst) and lst[i][2] <= y:
        e = lst[i]
        xr = (e[0] + 0x8000) >> 16
        if w & rule == 0:
            left = xr
        w += e[4]
        if w & rule == 0 and xr > left:
            spans.append((left, xr))
        if e[3] == y:
            lst.pop(i)  # done with this edge
            continue
        e[0] += e[1]
        if e[0] < prev_x:  # ripple it back until x-sorted
            p = i - 1
            while p >= 0 and lst[p][0] > e[0]:
                p -= 1
            lst.insert(p + 1, lst.pop(i))
        else:
            prev_x = e[0]
        i += 1

    def x_of(k: int) -> int:  # the list's head (index -1) holds i32::MIN
        return lst[k][0] if k >= 0 else _I32_MIN

    # insert_new_edges: the edges starting on the next sub-row, now at i
    if i < len(lst) and lst[i][2] == y + 1 and x_of(i - 1) > lst[i][0]:
        s = i - 1
        while s >= 0:  # backward_insert_start
            s -= 1
            if x_of(s) <= lst[i][0]:
                break
        j = i
        while j < len(lst) and lst[j][2] == y + 1:
            while s + 1 != j and lst[s + 1][0] < lst[j][0]:
                s += 1
            if s + 1 != j:
                lst.insert(s + 1, lst.pop(j))
            s += 1
            j += 1
    return spans


def _reference_blit(out: NDArray[np.int64], spans: list[tuple[int, int]], y: int, shift: int, left_px: int) -> None:
    """The sub-row's spans summed into ``out`` pixel by pixel, as blit_h and AlphaRuns::add do."""
    width = out.shape[1]
    full = (1 << (8 - shift)) - (((y & ((1 << shift) - 1)) + 1) >> shift)
    row = y >> shift
    for start, stop in spans:
        start, stop = max(start, left_px << shift), min(stop, width << shift)
        first_px = start >> shift
        for px in range(first_px, ((stop - 1) >> shift) + 1):
            count = min(stop, (px + 1) << shift) - max(start, px << shift)
            if count <= 0:
                continue
            if count == 1 << shift:
                total = out[row, px] + full
                out[row, px] = total - (total >> 8)  # a full pixel: catch_overflow
            elif px == first_px:
                total = out[row, px] + (count << (8 - 2 * shift))
                out[row, px] = total - (total >> 8)  # the first pixel: clamped 256 -> 255
            else:
                out[row, px] = (out[row, px] + (count << (8 - 2 * shift))) & 255  # the last: a u8 add


def reference_levels(contours: Sequence[ArrayLike], width: int, height: int, fill_rule: str = "nonzero",
                     shift: int = TINY_SKIA_SHIFT) -> NDArray[np.int64]:
    """The (height, width) 8-bit levels of one path as tiny-skia computes them, uncompiled:
    Python integers, the edges a Python list kept as ``walk_edges`` keeps its linked list,
    every sub-row's spans accumulated pixel by pixel (slow; the reference of the compiled
    oracle).

    >>> reference_levels([[[0, 0], [2, 0], [0, 1]]], 2, 1).tolist()
    [[192, 64]]
    """
    pts = [np.asarray(c, dtype=np.float64).astype(np.float32) for c in contours]
    out = np.zeros((height, width), dtype=np.int64)
    flat = np.concatenate(pts) if pts else np.zeros((0, 2), np.float32)
    if flat.size == 0 or not np.all(np.isfinite(flat)):
        return out
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    if abs(np.float32(hi[0] - lo[0])) <= _NEARLY_ZERO or abs(np.float32(hi[1] - lo[1])) <= _NEARLY_ZERO:
        return out
    box = (math.floor(float(lo[0])), math.floor(float(lo[1])), math.ceil(float(hi[0])), math.ceil(float(hi[1])))
    inside = box[0] >= 0 and box[1] >= 0 and box[2] <= width and box[3] <= height
    edges = _reference_edges(pts, float(1 << (shift + 6)), None if inside else (0.0, 0.0, float(width), float(height)))
    if len(edges) < 2:
        return out
    start_y = max(math.floor(float(lo[1])), 0) << shift
    stop_y = min(math.ceil(float(hi[1])), height) << shift
    # stable, as Rust's sort_by; the edges ending above the screen are never walked, those
    # starting above it enter at its top row
    lst = [e for e in sorted(edges, key=lambda e: (e[2], e[0])) if e[3] >= start_y]
    for e in lst:
        if e[2] < start_y:
            e[0] += (start_y - e[2]) * e[1]
            e[2] = start_y
    rule = 1 if fill_rule == "evenodd" else -1
    for y in range(start_y, stop_y):
        _reference_blit(out, _reference_row(lst, y, rule), y, shift, max(math.floor(float(lo[0])), 0))
    return out
