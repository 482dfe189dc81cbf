"""stb_truetype's version-2 anti-aliased rasterizer, ported to numba in float32.

Ported from nothings/stb, ``stb_truetype.h`` v1.26 (commit 31c1ad37456438565541f4919958214b6e762fb4),
``STBTT_RASTERIZER_VERSION == 2``: ``stbtt__rasterize`` (edge building, each edge from
its upper to its lower end point, horizontal ones skipped, ``invert`` set on the edges
running down), ``stbtt__sort_edges`` (by upper y; a triangle's three edges take the
insertion sort only, the quicksort's loop runs for more than 12 edges),
``stbtt__rasterize_sorted_edges`` (the active list, new edges inserted at its front, the
scanline accumulation and ``(int)(STBTT_fabs(k)*255+0.5)`` clamped at 255),
``stbtt__new_active``, ``stbtt__fill_active_edges_new`` (the one-pixel, the multi-pixel
and the brute-force clipped cases) and ``stbtt__handle_clipped_edge``. Every operation is
done in float32, in the C source's order, so that every rounding is the original's; C's
``(int)`` of a float is x86-64's (``cvttss2si``: truncation, and -2**31 for NaN or out
of range, which ``(unsigned char)`` then stores as 0). The original is compiled from
``tests/peers/src/stb`` and the port equals it (``tests/peers/test_stb.py``): measured,
100,000 random triangles (:func:`tests.peers.test_stb.random_draws`: edges above and left
of the bitmap, tall, tiny, slivers, far-off vertices; 2,720,261,330 alphas) and every
triangle scene of the quick suite, motion frames included, in both bitmap placements
(4,706 scenes, 8,774,682 nonzero alphas), 0 differing alphas.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.real._bases import AlphaOneTriangleAtATime
from rasterizers.real._masks import finite_within_limit

__all__ = ["StbTruetype", "rasterize_polygon"]

_INT_MIN = -2147483648
# The box around each triangle is widened by this many pixels (draw_each_alpha's margin).
MARGIN = 2


@numba.njit(cache=True, inline="always", error_model="numpy")
def _c_int(v: np.float32) -> int:
    """C's ``(int)`` of a float on x86-64 (cvttss2si): truncation toward zero, and
    INT_MIN for NaN and values out of the int range."""
    if not (v > np.float32(-2147483648.0) and v < np.float32(2147483648.0)):
        return _INT_MIN  # -2**31 itself converts to INT_MIN too
    return int(v)


@numba.njit(cache=True, error_model="numpy")
def _handle_clipped_edge(buf: NDArray, base: int | np.int64, x: int | np.int64, sy: np.float32, ey: np.float32,
                         direction: np.float32, x0: np.float32, y0: np.float32, x1: np.float32, y1: np.float32) -> None:
    """stbtt__handle_clipped_edge: the edge piece (x0, y0)-(x1, y1), which does not cross
    x or x + 1, clipped to the edge's [sy, ey], added to ``buf[base + x]``."""
    if y0 == y1:
        return
    if y0 > ey:
        return
    if y1 < sy:
        return
    if y0 < sy:
        x0 += (x1 - x0) * (sy - y0) / (y1 - y0)
        y0 = sy
    if y1 > ey:
        x1 += (x1 - x0) * (ey - y1) / (y1 - y0)
        y1 = ey
    fx = np.float32(x)
    fx1 = np.float32(x + 1)
    if x0 <= fx and x1 <= fx:
        buf[base + x] += direction * (y1 - y0)
    elif x0 >= fx1 and x1 >= fx1:
        pass
    else:
        buf[base + x] += direction * (y1 - y0) * (np.float32(1.0) - ((x0 - fx) + (x1 - fx)) / np.float32(2.0))


@numba.njit(cache=True, inline="always", error_model="numpy")
def _trapezoid(height: np.float32, tx0: np.float32, tx1: np.float32, bx0: np.float32, bx1: np.float32) -> np.float32:
    """stbtt__position_trapezoid_area (stbtt__sized_trapezoid_area of the widths)."""
    top_width = tx1 - tx0
    bottom_width = bx1 - bx0
    return (top_width + bottom_width) / np.float32(2.0) * height


@numba.njit(cache=True, error_model="numpy")
def _fill_active_edges(buf: NDArray, length: int, active: NDArray, n_active: int, fx: NDArray, fdx: NDArray,
                       fdy: NDArray, direction: NDArray, sy: NDArray, ey: NDArray, y_top: np.float32) -> None:
    """stbtt__fill_active_edges_new: ``buf`` holds ``scanline`` (``[0, length)``) then
    ``scanline2`` (``[length, 2 length + 1)``; ``scanline_fill`` is ``scanline2 + 1``)."""
    fill = length + 1
    y_bottom = y_top + np.float32(1.0)
    one = np.float32(1.0)
    zero = np.int64(0)  # the C's 0 as a runtime value: numba compiles a callee once per literal argument
    for a in range(n_active):
        e = active[a]
        if fdx[e] == np.float32(0.0):
            x0 = fx[e]
            if x0 < np.float32(length):
                if x0 >= np.float32(0.0):
                    _handle_clipped_edge(buf, zero, _c_int(x0), sy[e], ey[e], direction[e], x0, y_top, x0, y_bottom)
                    _handle_clipped_edge(buf, fill - 1, _c_int(x0) + 1, sy[e], ey[e], direction[e], x0, y_top, x0, y_bottom)
                else:
                    _handle_clipped_edge(buf, fill - 1, zero, sy[e], ey[e], direction[e], x0, y_top, x0, y_bottom)
            continue
        x0 = fx[e]
        dx = fdx[e]
        xb = x0 + dx
        dy = fdy[e]
        if sy[e] > y_top:
            x_top = x0 + dx * (sy[e] - y_top)
            sy0 = sy[e]
        else:
            x_top = x0
            sy0 = y_top
        if ey[e] < y_bottom:
            x_bottom = x0 + dx * (ey[e] - y_top)
            sy1 = ey[e]
        else:
            x_bottom = xb
            sy1 = y_bottom
        flen = np.float32(length)
        if x_top >= np.float32(0.0) and x_bottom >= np.float32(0.0) and x_top < flen and x_bottom < flen:
            if _c_int(x_top) == _c_int(x_bottom):
                x = _c_int(x_top)
                height = (sy1 - sy0) * direction[e]
                buf[x] += _trapezoid(height, x_top, np.float32(x) + one, x_bottom, np.float32(x) + one)
                buf[fill + x] += height
            else:
                if x_top > x_bottom:
                    sy0 = y_bottom - (sy0 - y_top)
                    sy1 = y_bottom - (sy1 - y_top)
                    sy0, sy1 = sy1, sy0
                    x_bottom, x_top = x_top, x_bottom
                    dx = -dx
                    dy = -dy
                    x0, xb = xb, x0
                x1 = _c_int(x_top)
                x2 = _c_int(x_bottom)
                y_crossing = y_top + dy * (np.float32(x1 + 1) - x0)
                y_final = y_top + dy * (np.float32(x2) - x0)
                if y_crossing > y_bottom:
                    y_crossing = y_bottom
                sign = direction[e]
                area = sign * (y_crossing - sy0)
                buf[x1] += area * (np.float32(x1 + 1) - x_top) / np.float32(2.0)  # stbtt__sized_triangle_area
                if y_final > y_bottom:
                    y_final = y_bottom
                    dy = (y_final - y_crossing) / np.float32(x2 - (x1 + 1))
                step = sign * dy * one
                for x in range(x1 + 1, x2):
                    buf[x] += area + step / np.float32(2.0)
                    area += step
                buf[x2] += area + sign * _trapezoid(sy1 - y_final, np.float32(x2), np.float32(x2) + one, x_bottom,
                                                    np.float32(x2) + one)
                buf[fill + x2] += sign * (sy1 - sy0)
        else:
            # the brute-force clipping of an edge leaving the bitmap, pixel by pixel
            for x in range(length):
                y0 = y_top
                px1 = np.float32(x)
                px2 = np.float32(x + 1)
                x3 = xb
                y3 = y_bottom
                y1 = (np.float32(x) - x0) / dx + y_top
                y2 = (np.float32(x + 1) - x0) / dx + y_top
                s, t, d = sy[e], ey[e], direction[e]
                if x0 < px1 and x3 > px2:
                    _handle_clipped_edge(buf, zero, x, s, t, d, x0, y0, px1, y1)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px1, y1, px2, y2)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px2, y2, x3, y3)
                elif x3 < px1 and x0 > px2:
                    _handle_clipped_edge(buf, zero, x, s, t, d, x0, y0, px2, y2)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px2, y2, px1, y1)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px1, y1, x3, y3)
                elif x0 < px1 and x3 > px1 or x3 < px1 and x0 > px1:
                    _handle_clipped_edge(buf, zero, x, s, t, d, x0, y0, px1, y1)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px1, y1, x3, y3)
                elif x0 < px2 and x3 > px2 or x3 < px2 and x0 > px2:
                    _handle_clipped_edge(buf, zero, x, s, t, d, x0, y0, px2, y2)
                    _handle_clipped_edge(buf, zero, x, s, t, d, px2, y2, x3, y3)
                else:
                    _handle_clipped_edge(buf, zero, x, s, t, d, x0, y0, x3, y3)


@numba.njit(cache=True, error_model="numpy")
def rasterize_polygon(points: NDArray[np.float32], width: int, height: int, off_x: int | np.int64,
                      off_y: int) -> NDArray[np.uint8]:
    """One polygon (one winding) drawn as ``stbtt__rasterize`` draws it with scale 1,
    shift 0, ``invert`` 0 (y down as given) and vsubsample 1: the (height, width) uint8
    bitmap whose pixel (0, 0) is pixel (off_x, off_y) of the points' space.

    Parameters
    ----------
    points : (K, 2) float32
        The polygon's vertices, K <= 12 (the edges then take the insertion sort only).
    width, height : int
    off_x, off_y : int

    Returns
    -------
    (height, width) uint8
    """
    count = points.shape[0]
    one = np.float32(1.0)
    zero = np.float32(0.0)
    # stbtt__rasterize: the edges, each from its upper end point (a) to its lower one (b)
    ex0 = np.empty(count + 1, dtype=np.float32)
    ey0 = np.empty(count + 1, dtype=np.float32)
    ex1 = np.empty(count + 1, dtype=np.float32)
    ey1 = np.empty(count + 1, dtype=np.float32)
    einv = np.empty(count + 1, dtype=np.int64)
    n = 0
    j = count - 1
    for k in range(count):
        if points[j, 1] == points[k, 1]:  # skip the edge if horizontal
            j = k
            continue
        inv, a, b = 0, k, j
        if points[j, 1] < points[k, 1]:
            inv, a, b = 1, j, k
        einv[n] = inv
        ex0[n] = points[a, 0] * one + zero
        ey0[n] = (points[a, 1] * one + zero) * one  # (y * y_scale_inv + shift_y) * vsubsample
        ex1[n] = points[b, 0] * one + zero
        ey1[n] = (points[b, 1] * one + zero) * one
        n += 1
        j = k
    # stbtt__sort_edges_ins_sort (the quicksort runs for n > 12 only): by y0, stable
    for i in range(1, n):
        tx0, ty0, tx1, ty1, tinv = ex0[i], ey0[i], ex1[i], ey1[i], einv[i]
        j = i
        while j > 0:
            if not (ty0 < ey0[j - 1]):
                break
            ex0[j], ey0[j], ex1[j], ey1[j], einv[j] = ex0[j - 1], ey0[j - 1], ex1[j - 1], ey1[j - 1], einv[j - 1]
            j -= 1
        if i != j:
            ex0[j], ey0[j], ex1[j], ey1[j], einv[j] = tx0, ty0, tx1, ty1, tinv
    # stbtt__rasterize_sorted_edges
    out = np.zeros((height, width), dtype=np.uint8)
    fx = np.zeros(n, dtype=np.float32)
    fdx = np.zeros(n, dtype=np.float32)
    fdy = np.zeros(n, dtype=np.float32)
    direction = np.zeros(n, dtype=np.float32)
    sy = np.zeros(n, dtype=np.float32)
    ey = np.zeros(n, dtype=np.float32)
    active = np.empty(n + 1, dtype=np.int64)  # the active list, front first
    n_active = 0
    buf = np.zeros(2 * width + 1, dtype=np.float32)
    ey0[n] = np.float32(off_y + height) + one  # the sentinel
    e = 0
    y = off_y
    for j in range(height):
        scan_y_top = np.float32(y) + zero
        scan_y_bottom = np.float32(y) + one
        buf[:] = zero
        kept = 0  # remove the edges ending at or above this row's top
        for a in range(n_active):
            if not (ey[active[a]] <= scan_y_top):
                active[kept] = active[a]
                kept += 1
        n_active = kept
        while e <= n and ey0[e] <= scan_y_bottom:  # insert the edges starting above its bottom
            if e == n:  # past the sentinel: C reads beyond the edges (off_y + height beyond float32's integers)
                break
            if ey0[e] != ey1[e]:
                dxdy = (ex1[e] - ex0[e]) / (ey1[e] - ey0[e])  # stbtt__new_active
                fdx[e] = dxdy
                fdy[e] = one / dxdy if dxdy != zero else zero
                fx[e] = ex0[e] + dxdy * (scan_y_top - ey0[e])
                fx[e] -= np.float32(off_x)
                direction[e] = one if einv[e] else -one
                sy[e] = ey0[e]
                ey[e] = ey1[e]
                if j == 0 and off_y != 0:
                    if ey[e] < scan_y_top:
                        ey[e] = scan_y_top
                for a in range(n_active, 0, -1):  # insert at front
                    active[a] = active[a - 1]
                active[0] = e
                n_active += 1
            e += 1
        if n_active:
            _fill_active_edges(buf, width, active, n_active, fx, fdx, fdy, direction, sy, ey, scan_y_top)
        total = zero
        for i in range(width):
            total += buf[width + i]
            coverage = buf[i] + total
            scaled = np.float32(abs(coverage)) * np.float32(255.0) + np.float32(0.5)  # (float) STBTT_fabs(k)*255 + 0.5f
            m = _c_int(scaled)
            if m > 255:
                m = 255
            out[j, i] = m & 255  # (unsigned char)
        for a in range(n_active):
            fx[active[a]] += fdx[active[a]]
        y += 1
    return out


@numba.njit(cache=True, error_model="numpy")
def _draw_all(points: NDArray[np.float32], boxes: NDArray[np.int64], from_left: bool
              ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.uint8]]:
    """Every triangle of ``points`` ((N, 3, 2) float32) drawn by :func:`rasterize_polygon`
    into the bitmap of its box (``boxes`` (N, 4): x0, y0, x1, y1, screen pixels; an empty
    one skipped), or into the same rows from column 0 (``from_left``): the (P,) triangle,
    x, y and value of every nonzero pixel in the box."""
    capacity = 1024
    t_out = np.empty(capacity, dtype=np.int64)
    x_out = np.empty(capacity, dtype=np.int64)
    y_out = np.empty(capacity, dtype=np.int64)
    v_out = np.empty(capacity, dtype=np.uint8)
    count = 0
    for t in range(points.shape[0]):
        x0, y0, x1, y1 = boxes[t, 0], boxes[t, 1], boxes[t, 2], boxes[t, 3]
        if x0 >= x1 or y0 >= y1:
            continue
        if from_left:
            bitmap = rasterize_polygon(points[t], x1, y1 - y0, np.int64(0), y0)[:, x0:]  # (np.int64: no literal recompile)
        else:
            bitmap = rasterize_polygon(points[t], x1 - x0, y1 - y0, x0, y0)
        for j in range(y1 - y0):
            for i in range(x1 - x0):
                if bitmap[j, i] == 0:
                    continue
                if count == capacity:
                    capacity *= 2
                    t_out, x_out, y_out, v_out = (np.resize(t_out, capacity), np.resize(x_out, capacity),
                                                  np.resize(y_out, capacity), np.resize(v_out, capacity))
                t_out[count], x_out[count], y_out[count], v_out[count] = t, x0 + i, y0 + j, bitmap[j, i]
                count += 1
    return t_out[:count], x_out[:count], y_out[:count], v_out[:count]


# Half a float32 ulp of a coordinate below 4,096 px (the quick suite's screens reach 2,112 px).
HALF_ULP = 2.0**-13
# The half-ulps by which an edge's x in a row may be off before any stepping (2 for its end
# points rounded to float32, 10 for its slope's 5 roundings, 1 + 1 for its x at the first
# row and the bitmap's offset, 3 for its ends within the row), and the row's own sums.
EDGE_HALF_ULPS = 17
ROW_HALF_ULPS = 4


class StbTruetype(AlphaOneTriangleAtATime):
    """stb_truetype's anti-aliased rasterizer (version 2), a faithful port
    (:func:`rasterize_polygon`): each triangle drawn on its own, as ``stbtt__rasterize``
    draws a glyph's flattened outline (``stbtt_Rasterize``), into an 8-bit bitmap whose
    pixel (0, 0) is passed as stb's ``off_x``, ``off_y``; the vertices are the scene's
    coordinates rounded to float32 (stb's ``stbtt__point``), scale 1, shift 0, y down
    (``invert`` 0), so stb's pixel (i, j) is our [i, i+1) x [j, j+1). Alpha is the
    bitmap's value / 255. The bitmap covers the triangle's box widened by 2 px and clipped
    to the screen, as stb draws a glyph into its own box (``bitmap="box"``), or the same
    rows from the screen's left edge on (``bitmap="screen"``, off_x = 0: the x positions
    stb steps down the rows are then the screen's, not the box's).

    Declared convention: area coverage, 256 levels, no snapping, within
    ``1/510 + (3 * 17 + 4) * 2**-13`` (0.00867, 2.2 levels) of the exact area, derived from
    stb's method for coordinates and edges below 4,096 px (the quick suite's screens reach
    2,112 px), where half a float32 ulp is ``h = 2**-13`` px. stb computes each pixel's
    signed area analytically -- per row, each edge's part as trapezoids
    (``stbtt__fill_active_edges_new``) -- and stores ``(int)(|area| * 255 + 0.5)``: half a
    level, 1/510, from rounding the area it computed. That area is computed in float32.
    An edge's x in the row where it becomes active is off by at most 17 h
    (:data:`EDGE_HALF_ULPS`): 2 h for its end points rounded to float32 (each moved by h in
    x and in y), 10 h for ``dxdy * (start_point - e->y0)`` (five roundings of relative
    error 2**-24 -- two differences, the quotient, the row's offset, the product -- of a
    run along the edge, which moves a pixel's area by at most the edge's width, below
    2**12 px, times that error), h for adding ``e->x0``, h for subtracting ``off_x``, 3 h
    for its ends within the row (``x_top``, ``x_bottom``). Moving an edge by d within a row
    changes a pixel's area by at most d (the row is 1 px tall), and a pixel meets at most 3
    edges of a triangle: 51 h; the row's running sums (the fills along the row, ``area +=
    step``: a few thousand additions of values below 1) add at most 4 h
    (:data:`ROW_HALF_ULPS`). A bound, not a fit: measured, the quick suite's cases away
    from the bugs below stay within 0.73 levels (0.00287) of the area -- more than half a
    level, so a tolerance of half a level would fail 31 of them (motion cases included)
    on float32 rounding alone. Not included: the rows stepped (``z->fx += z->fdx`` every row), each adding up
    to half an ulp of the stepped x -- an error growing with the triangle's height and the
    x's distance from ``off_x`` (random 1,024-px triangles: 1.6 levels), which the
    accuracy check names ``drift`` where it shows.

    Its bugs, found by the quick suite (``tests/peers/test_stb.py``), the original's too:
    row 0 of a bitmap starting at row 0 (``off_y`` == 0, so stb's ``if (j == 0 && off_y
    != 0)`` clamp of an edge's end is skipped) takes the signed height of any edge ending
    above it whose line crosses the row inside the bitmap -- the row is raised to 255 (or
    lowered) right of that line wherever a triangle reaches past the screen's top: 6
    cases, named ``viewport-edge``; a triangle with an infinite coordinate draws garbage
    (``non-finite-input``). Drawn into bitmaps from the screen's left edge
    (``bitmap="screen"``), the tall triangles of ``float/tall-triangles-2048px`` (x past
    1,024 px) drift by up to 26 levels down their 2,000 rows, and frame 40 of
    ``motion/tall-triangle/translate-x-1/64`` (x near 1,500 px) by 32 (named ``drift``);
    drawn into their own boxes (x within 60 px of the offset) they stay within 0.73 levels
    of the area, within the tolerance.
    """

    name = "stb_truetype"
    convention = Convention(coverage="area", levels=256, tolerance=1 / 510 + (3 * EDGE_HALF_ULPS + ROW_HALF_ULPS) * HALF_ULP)

    def __init__(self, bitmap: str = "box") -> None:
        if bitmap not in ("box", "screen"):
            raise ValueError(f"StbTruetype: bitmap must be 'box' or 'screen', not {bitmap!r}")
        self.bitmap = bitmap
        if bitmap == "screen":
            self.name = "stb_truetype_screen"

    def rasterize(self, scene: Scene) -> Coverage:
        """:func:`rasterizers.real._masks.draw_each_alpha`'s boxes, margin and refusals (a
        coordinate beyond its limit; not a triangle scene), every triangle drawn in one
        compiled call (:func:`_draw_all`)."""
        if not isinstance(scene, Scene):
            return super().rasterize(scene)  # refused, naming the kinds taken
        finite = finite_within_limit(scene, self.name)
        positions = scene.positions
        boxes = np.zeros((len(scene), 4), dtype=np.int64)
        boxes[:, 2:] = scene.width, scene.height  # a non-finite triangle: the whole screen
        if finite.any():
            p = positions[finite]
            lo, hi = np.floor(p.min(axis=1)) - MARGIN, np.ceil(p.max(axis=1)) + MARGIN
            size = np.array([scene.width, scene.height])
            boxes[finite] = np.concatenate([np.clip(lo, 0, size), np.clip(hi, 0, size)], axis=1).astype(np.int64)
        with np.errstate(invalid="ignore", over="ignore"):
            points = positions.astype(np.float32)
        t, x, y, value = _draw_all(points, boxes, self.bitmap == "screen")
        if not t.size:
            return Coverage.empty()
        return Coverage.from_pixels(t, x, y, alpha=value / 255.0)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        # the box's origin is an integer no greater than the finite coordinates (or 0): p + origin is
        # exactly the scene's coordinates
        points = (p + np.array(origin, dtype=np.float64)).astype(np.float32)
        if self.bitmap == "screen":
            return rasterize_polygon(points, origin[0] + w, h, 0, origin[1])[:, origin[0]:] / 255.0
        return rasterize_polygon(points, w, h, origin[0], origin[1]) / 255.0
