"""Two coverage rules read from libraries' sources (issue 33): AGG's cell cover and pygame's
inclusive scanline fill, each an exact oracle on the integer grid its library receives.

``agg-cover`` (:func:`agg_cover_coverage`; aggdraw's and matplotlib's aliased fills)
    AGG's scanline rasterizer (``agg_rasterizer_scanline_aa.h``, ``outline_aa::render_line``
    and ``render_hline`` in 2.0, ``rasterizer_cells_aa`` in 2.4) receives 24.8 fixed point
    (the convention's ``input``: ``fixed8-toward-zero`` for aggdraw's ``int(c * 256)``,
    ``fixed8-half-away`` for AGG 2.4's ``iround(c * 256)``). It replaces each edge by a
    polyline through the points where it crosses the pixel rows, x rounded *down* to 1/256
    px (``delta = p / dy`` with the remainder carried: the floor of the exact crossing,
    whichever way the edge runs), and, within a row, through the points where that
    piece crosses the pixel columns, y rounded down likewise: the *cell polygon*. Each
    pixel gets the exact doubled signed area of the cell polygon inside it, V (an integer
    in units of 2**-17 px²), and its 8-bit cover is ``|V >> 9|`` capped at 255
    (``calculate_alpha``: the shift floors before the absolute value, so a polygon
    counter-clockwise on screen gets ``floor(256 a)`` and a clockwise one ``ceil(256 a)``).
    A pixel is drawn iff ``cover >= 256 t`` (t the convention's ``threshold``):
    aggdraw's ``gamma_threshold(0.5)`` maps cover c to 255 iff ``c / 255 >= 0.5``, i.e.
    ``c >= 128`` (t = 1/2); matplotlib's ``renderer_scanline_bin_solid`` draws every
    nonzero cover (t = 1/256). The integers are AGG's own, so the oracle is AGG's
    arithmetic, ported (:func:`_agg_cells`, compiled, int64: no overflow in the harness's
    coordinate range); :func:`agg_cover_reference` builds the cell polygon from its
    definition above and clips it to each pixel in :class:`fractions.Fraction`.
    Not modelled: AGG's clipping at the image's edge (its new vertices are rounded to
    1/256 px) and AGG 2.4's subdivision of edges longer than 16384 px.

``inclusive-scanline`` (:func:`inclusive_scanline_coverage`; pygame's ``draw.polygon``)
    pygame casts every coordinate to a C ``int`` (``input="integer-toward-zero"``), then
    ``draw_fillpoly`` (``src_c/draw.c``) visits every integer row y from the lowest vertex
    to the highest, takes each edge's x at y (``(int)((y - y1) * (x2 - x1) / (y2 - y1) +
    x1)``: truncation toward zero of the exact crossing; the double arithmetic is exact
    enough below 2**21 px) and draws both ends and everything between. For a triangle T
    that is: pixel (i, y) is drawn iff ``ymin <= y <= ymax`` and ``trunc(xl(y)) <= i <=
    trunc(xr(y))``, where [xl(y), xr(y)] is the closed triangle's cross-section at height y
    (a horizontal triangle draws its x extent on its one row). Zero-area triangles draw
    (a segment's pixels), so shared edges and vertices are drawn by both sides.
    :func:`inclusive_scanline_reference` decides each pixel from that definition in
    rationals.

Culling (``cull``) removes the triangles of the culled orientation (their exact area after
the input grid); non-finite triangles draw nothing (aggdraw and matplotlib draw nothing;
pygame's adapter refuses a non-finite y).
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
from harness.geometry.exact import orient2d_fraction

__all__ = ["agg_cover_coverage", "agg_covers", "agg_cover_reference", "cell_polygon", "inclusive_scanline_coverage",
           "inclusive_scanline_reference", "cover_min", "on_library_boundary"]

SUBPIXEL_SHIFT = 8  # AGG's poly_base_shift: 24.8 fixed point
SUBPIXEL_ONE = 1 << SUBPIXEL_SHIFT
SUBPIXEL_MASK = SUBPIXEL_ONE - 1
# calculate_alpha: cover = V >> (2 * 8 + 1 - 8), to 8 bits
_ALPHA_SHIFT = 2 * SUBPIXEL_SHIFT + 1 - 8
_COVER_MAX = 255


def cover_min(threshold: float) -> int:
    """The least 8-bit cover a threshold t draws: ``ceil(256 t)`` (cover >= 256 t, cover an integer).

    >>> cover_min(0.5), cover_min(2.0**-8), cover_min(2.0**-20)
    (128, 1, 1)
    """
    return max(1, math.ceil(Fraction(threshold) * 256))


def _culled(sign: int, cull: str) -> bool:
    return (cull == "cw" and sign > 0) or (cull == "ccw" and sign < 0)


def _received(scene: Scene, convention: Convention) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The positions the rule sees (the convention's input grid and snapping) and which
    triangles are drawn (finite, not culled)."""
    positions = np.ascontiguousarray(convention.snap(scene.positions))
    use = np.all(np.isfinite(positions), axis=(1, 2))
    if convention.cull != "none":
        for t in np.flatnonzero(use):
            if _culled(orient2d_fraction(*(float(v) for v in positions[t].ravel())), convention.cull):
                use[t] = False
    return positions, use


def _runs(triangle: list[int], y: list[int], x: list[int]) -> Coverage:
    """(triangle, row, column) pixels, sorted, as spans."""
    if not triangle:
        return Coverage.empty()
    e = np.array(sorted(zip(triangle, y, x)), dtype=np.int64)
    t, yy, xx = e[:, 0], e[:, 1], e[:, 2]
    new = np.ones(t.size, dtype=bool)
    new[1:] = (t[1:] != t[:-1]) | (yy[1:] != yy[:-1]) | (xx[1:] != xx[:-1] + 1)
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], t.size)
    return Coverage(t[starts], yy[starts], xx[starts], xx[ends - 1] + 1)


# --- agg-cover --------------------------------------------------------------------------------

@numba.njit(cache=True)
def _add(cover, area, ex, ey, dc, da, width, height):  # type: ignore[no-untyped-def]
    """Add (dc, da) to cell (ex, ey): rows off screen dropped, columns left of it summed in
    column 0 (only their cover reaches the screen), right of it dropped."""
    if ey < 0 or ey >= height or ex >= width:
        return
    col = ex + 1 if ex >= 0 else 0
    cover[ey, col] += dc
    area[ey, col] += da


@numba.njit(cache=True)
def _hline(cover, area, ey, x1, y1, x2, y2, width, height):  # type: ignore[no-untyped-def]
    """AGG's ``render_hline``: the piece (x1, y1) -> (x2, y2) of row ey (y1, y2 in
    0 .. 256 within the row), split at the columns, y rounded down (floor division)."""
    ex1 = x1 >> SUBPIXEL_SHIFT
    ex2 = x2 >> SUBPIXEL_SHIFT
    fx1 = x1 & SUBPIXEL_MASK
    fx2 = x2 & SUBPIXEL_MASK
    if y1 == y2:
        return
    if ex1 == ex2:
        delta = y2 - y1
        _add(cover, area, ex1, ey, delta, (fx1 + fx2) * delta, width, height)
        return
    p = (SUBPIXEL_ONE - fx1) * (y2 - y1)
    first = SUBPIXEL_ONE
    incr = 1
    dx = x2 - x1
    if dx < 0:
        p = fx1 * (y2 - y1)
        first = 0
        incr = -1
        dx = -dx
    delta = p // dx  # floor, as AGG's quotient corrected by a negative remainder
    mod = p - delta * dx
    _add(cover, area, ex1, ey, delta, (fx1 + first) * delta, width, height)
    ex1 += incr
    y1 += delta
    if ex1 != ex2:
        p = SUBPIXEL_ONE * (y2 - y1 + delta)
        lift = p // dx
        rem = p - lift * dx
        mod -= dx
        while ex1 != ex2:
            delta = lift
            mod += rem
            if mod >= 0:
                mod -= dx
                delta += 1
            _add(cover, area, ex1, ey, delta, SUBPIXEL_ONE * delta, width, height)
            y1 += delta
            ex1 += incr
    delta = y2 - y1
    _add(cover, area, ex1, ey, delta, (fx2 + SUBPIXEL_ONE - first) * delta, width, height)


@numba.njit(cache=True)
def _line(cover, area, x1, y1, x2, y2, width, height):  # type: ignore[no-untyped-def]
    """AGG's ``render_line``: the edge split at the rows, x rounded down (floor division)."""
    ey1 = y1 >> SUBPIXEL_SHIFT
    ey2 = y2 >> SUBPIXEL_SHIFT
    fy1 = y1 & SUBPIXEL_MASK
    fy2 = y2 & SUBPIXEL_MASK
    dx = x2 - x1
    dy = y2 - y1
    if ey1 == ey2:
        _hline(cover, area, ey1, x1, fy1, x2, fy2, width, height)
        return
    incr = 1
    if dx == 0:  # vertical: one cell per row, the same area in each
        ex = x1 >> SUBPIXEL_SHIFT
        two_fx = (x1 - (ex << SUBPIXEL_SHIFT)) << 1
        first = SUBPIXEL_ONE
        if dy < 0:
            first = 0
            incr = -1
        delta = first - fy1
        _add(cover, area, ex, ey1, delta, two_fx * delta, width, height)
        ey1 += incr
        delta = first + first - SUBPIXEL_ONE
        while ey1 != ey2:
            _add(cover, area, ex, ey1, delta, two_fx * delta, width, height)
            ey1 += incr
        delta = fy2 - SUBPIXEL_ONE + first
        _add(cover, area, ex, ey1, delta, two_fx * delta, width, height)
        return
    p = (SUBPIXEL_ONE - fy1) * dx
    first = SUBPIXEL_ONE
    if dy < 0:
        p = fy1 * dx
        first = 0
        incr = -1
        dy = -dy
    delta = p // dy
    mod = p - delta * dy
    x_from = x1 + delta
    _hline(cover, area, ey1, x1, fy1, x_from, first, width, height)
    ey1 += incr
    if ey1 != ey2:
        p = SUBPIXEL_ONE * dx
        lift = p // dy
        rem = p - lift * dy
        mod -= dy
        while ey1 != ey2:
            delta = lift
            mod += rem
            if mod >= 0:
                mod -= dy
                delta += 1
            x_to = x_from + delta
            _hline(cover, area, ey1, x_from, SUBPIXEL_ONE - first, x_to, first, width, height)
            x_from = x_to
            ey1 += incr
    _hline(cover, area, ey1, x_from, SUBPIXEL_ONE - first, x2, fy2, width, height)


@numba.njit(cache=True)
def _agg_cells(fixed, width, height):  # type: ignore[no-untyped-def]
    """The signed 8-bit cover ``V >> 9`` of every pixel of the viewport for one polygon
    of 24.8 vertices ``fixed`` ((N, 2) int64), as AGG's sweep sums its cells: V = 512 x
    (the covers of the row's cells up to and including this one) - this cell's area."""
    cover = np.zeros((height, width + 1), dtype=np.int64)
    area = np.zeros((height, width + 1), dtype=np.int64)
    n = fixed.shape[0]
    for k in range(n):
        a = fixed[k]
        b = fixed[(k + 1) % n]
        _line(cover, area, a[0], a[1], b[0], b[1], width, height)
    out = np.zeros((height, width), dtype=np.int64)
    for j in range(height):
        run = cover[j, 0]
        for i in range(width):
            run += cover[j, i + 1]
            out[j, i] = ((run << (SUBPIXEL_SHIFT + 1)) - area[j, i + 1]) >> _ALPHA_SHIFT
    return out


def _fixed(triangle: NDArray[np.float64]) -> NDArray[np.int64]:
    """The vertices in 1/256 px units: ValueError unless on that grid (the convention's input)."""
    scaled = triangle * SUBPIXEL_ONE
    if not np.all(scaled == np.round(scaled)):
        raise ValueError("agg-cover needs vertices on the 1/256 px grid: declare input='fixed8-...' (24.8 fixed point)")
    return np.ascontiguousarray(scaled.astype(np.int64))


def agg_covers(triangle: NDArray[np.float64], width: int, height: int) -> NDArray[np.int64]:
    """AGG's 8-bit cover (``|V >> 9|`` capped at 255: module docstring) of every pixel of a
    width x height viewport for one triangle already on the 1/256 px grid: (height, width) int64.

    A counter-clockwise half pixel is cover 128; its mirror image, clockwise, too (exact
    halves have no rounding); 171/512 of a pixel (85.5 / 256) is 85 counter-clockwise, 86 clockwise.

    >>> ccw, cw = np.array([[0, 0], [0, 1], [1, 1.0]]), np.array([[0, 0], [1, 1], [0, 1.0]])
    >>> agg_covers(ccw, 1, 1).tolist(), agg_covers(cw, 1, 1).tolist()
    ([[128]], [[128]])
    >>> w = 171 / 256
    >>> [int(agg_covers(t, 1, 1)[0, 0]) for t in (np.array([[0, 0], [0, 1], [w, 1]]), np.array([[0, 0], [w, 1], [0, 1]]))]
    [85, 86]
    """
    signed = _agg_cells(_fixed(np.asarray(triangle, dtype=np.float64)), width, height)
    result: NDArray[np.int64] = np.minimum(np.abs(signed), _COVER_MAX)
    return result


def agg_cover_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="agg-cover"``: the pixels
    whose AGG cover is at least ``256 * convention.threshold`` (module docstring).

    >>> scene = Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]])
    >>> agg_cover_coverage(scene, Convention(coverage="agg-cover", input="fixed8-toward-zero")).counts(2, 2).tolist()
    [[1, 1], [1, 0]]
    >>> agg_cover_coverage(scene, Convention(coverage="agg-cover", input="fixed8-toward-zero", threshold=2**-8)
    ...                    ).counts(2, 2).tolist()  # any cover: the corner pixel only touched
    [[1, 1], [1, 0]]
    """
    positions, use = _received(scene, convention)
    k = cover_min(convention.threshold)
    ts: list[int] = []
    ys: list[int] = []
    xs: list[int] = []
    for t in np.flatnonzero(use):
        drawn = np.argwhere(agg_covers(positions[t], scene.width, scene.height) >= k)
        ts += [int(t)] * len(drawn)
        ys += drawn[:, 0].tolist()
        xs += drawn[:, 1].tolist()
    return _runs(ts, ys, xs)


def cell_polygon(triangle: NDArray[np.float64]) -> list[tuple[int, int]]:
    """The cell polygon of a triangle on the 1/256 px grid, in 1/256 px units, from its
    definition (module docstring): each edge through its row crossings, x the floor of the
    exact crossing, and each row's piece through its column crossings, y the floor of the
    exact crossing of that piece. Pure Python integers (the reference)."""
    v = [(int(x), int(y)) for x, y in (np.asarray(triangle, dtype=np.float64) * SUBPIXEL_ONE).tolist()]
    points: list[tuple[int, int]] = []
    for k in range(3):
        (x1, y1), (x2, y2) = v[k], v[(k + 1) % 3]
        rows = [(x1, y1)]
        if y1 != y2:
            lo, hi = sorted((y1, y2))
            crossings = [r * SUBPIXEL_ONE for r in range(-(-lo // SUBPIXEL_ONE), hi // SUBPIXEL_ONE + 1)
                         if lo < r * SUBPIXEL_ONE < hi]
            crossings.sort(reverse=y2 < y1)
            rows += [(x1 + (yc - y1) * (x2 - x1) // (y2 - y1), yc) for yc in crossings]
        rows.append((x2, y2))
        for (ax, ay), (bx, by) in zip(rows, rows[1:]):
            points.append((ax, ay))
            if ax != bx and ay != by:
                lo, hi = sorted((ax, bx))
                columns = [c * SUBPIXEL_ONE for c in range(-(-lo // SUBPIXEL_ONE), hi // SUBPIXEL_ONE + 1)
                           if lo < c * SUBPIXEL_ONE < hi]
                columns.sort(reverse=bx < ax)
                # the floor of the exact crossing (Python's // floors whatever the signs)
                points += [(xc, ay + (xc - ax) * (by - ay) // (bx - ax)) for xc in columns]
    return points


def _clipped_area(polygon: list[tuple[Fraction, Fraction]], i: int, j: int) -> Fraction:
    """The signed area of a polygon clipped to the square [i, i+1] x [j, j+1] (Sutherland-Hodgman:
    right for any polygon against a convex window, its degenerate edges cancelling)."""
    poly = polygon
    for axis, bound, keep_low in ((0, i, False), (0, i + 1, True), (1, j, False), (1, j + 1, True)):
        out: list[tuple[Fraction, Fraction]] = []
        for n, q in enumerate(poly):
            p = poly[n - 1]
            p_in = p[axis] <= bound if keep_low else p[axis] >= bound
            q_in = q[axis] <= bound if keep_low else q[axis] >= bound
            if p_in != q_in:
                s = (bound - p[axis]) / (q[axis] - p[axis])
                out.append((p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])))
            if q_in:
                out.append(q)
        poly = out
        if not poly:
            return Fraction(0)
    return sum((a[0] * b[1] - b[0] * a[1] for a, b in zip(poly, poly[1:] + poly[:1])), Fraction(0)) / 2


def agg_cover_reference(scene: Scene, convention: Convention) -> Coverage:
    """``agg-cover`` from its definition: the cell polygon (:func:`cell_polygon`) clipped to
    every pixel in rationals, its signed area a, cover ``|floor(256 a')|`` with a' the area
    signed as AGG signs it (positive for counter-clockwise on screen), capped at 255, drawn
    iff at least ``256 t``. Slow; for tests."""
    positions, use = _received(scene, convention)
    k = cover_min(convention.threshold)
    ts: list[int] = []
    ys: list[int] = []
    xs: list[int] = []
    for t in np.flatnonzero(use):
        _fixed(positions[t])
        polygon = [(Fraction(x, SUBPIXEL_ONE), Fraction(y, SUBPIXEL_ONE)) for x, y in cell_polygon(positions[t])]
        for j in range(scene.height):
            for i in range(scene.width):
                a = -_clipped_area(polygon, i, j)  # the shoelace sum is positive for clockwise on screen (y down)
                if min(abs(math.floor(256 * a)), _COVER_MAX) >= k:
                    ts.append(int(t))
                    ys.append(j)
                    xs.append(i)
    return _runs(ts, ys, xs)


# --- inclusive-scanline -----------------------------------------------------------------------

@numba.njit(cache=True)
def _trunc_div(num, den):  # type: ignore[no-untyped-def]
    """num / den truncated toward zero (den > 0), as C's cast of the quotient."""
    q = num // den
    if q < 0 and q * den != num:
        q += 1
    return q


@numba.njit(cache=True)
def _scanline_kernel(v, use, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """pygame's draw_fillpoly for each used triangle of integer vertices ``v`` ((T, 3, 2)
    int64): one span per row, both crossings included, clipped to the viewport."""
    n = 0
    for t in range(v.shape[0]):
        if not use[t]:
            continue
        ymin = min(v[t, 0, 1], v[t, 1, 1], v[t, 2, 1])
        ymax = max(v[t, 0, 1], v[t, 1, 1], v[t, 2, 1])
        for y in range(max(ymin, 0), min(ymax, height - 1) + 1):
            lo = 1 << 62
            hi = -(1 << 62)
            if ymin == ymax:  # one row: the x extent
                for k in range(3):
                    lo = min(lo, v[t, k, 0])
                    hi = max(hi, v[t, k, 0])
            else:
                for k in range(3):
                    x1, y1 = v[t, (k + 2) % 3, 0], v[t, (k + 2) % 3, 1]
                    x2, y2 = v[t, k, 0], v[t, k, 1]
                    if y1 > y2:
                        x1, y1, x2, y2 = x2, y2, x1, y1
                    elif y1 == y2:
                        continue
                    if (y1 <= y < y2) or (y == ymax and y2 == ymax):
                        x = _trunc_div((y - y1) * (x2 - x1) + x1 * (y2 - y1), y2 - y1)
                        lo = min(lo, x)
                        hi = max(hi, x)
            x0 = max(lo, 0)
            x1_ = min(hi, width - 1)
            if x0 <= x1_:
                out_t[n] = t
                out_y[n] = y
                out_x0[n] = x0
                out_x1[n] = x1_ + 1
                n += 1
    return n


def _integers(positions: NDArray[np.float64], use: NDArray[np.bool_]) -> NDArray[np.int64]:
    """The used triangles' vertices as int64 (ValueError unless whole: the convention's input)."""
    whole = np.where(use[:, None, None], positions, 0.0)
    if not np.all(whole == np.round(whole)):
        raise ValueError("inclusive-scanline needs whole-pixel vertices: declare input='integer-...'")
    return np.ascontiguousarray(whole.astype(np.int64))


def inclusive_scanline_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="inclusive-scanline"``
    (module docstring): every row from the lowest vertex to the highest, from the
    truncated left crossing to the truncated right one, both included.

    >>> scene = Scene(4, 4, [[[0, 0], [3, 0], [0, 3]], [[1, 1], [3, 1], [2, 1]]])
    >>> inclusive_scanline_coverage(scene, Convention(coverage="inclusive-scanline", input="integer-toward-zero")
    ...                             ).counts(4, 4).tolist()  # both ends drawn; a flat triangle draws its row
    [[1, 1, 1, 1], [1, 2, 2, 1], [1, 1, 0, 0], [1, 0, 0, 0]]
    """
    positions, use = _received(scene, convention)
    v = _integers(positions, use)
    # a triangle spans at most height rows on screen: one span each
    capacity = int(use.sum()) * scene.height
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    n = int(_scanline_kernel(v, use, scene.width, scene.height, *out))
    return Coverage(*(a[:n] for a in out))


def inclusive_scanline_reference(scene: Scene, convention: Convention) -> Coverage:
    """``inclusive-scanline`` from its definition, in rationals: the closed triangle's
    cross-section [xl, xr] at each integer row between its lowest and highest vertex (the
    x extent for a horizontal one), pixels trunc(xl) .. trunc(xr). Slow; for tests."""
    positions, use = _received(scene, convention)
    ts: list[int] = []
    ys: list[int] = []
    xs: list[int] = []
    for t in np.flatnonzero(use):
        p = [(Fraction(float(x)), Fraction(float(y))) for x, y in positions[t]]
        for y in range(scene.height):
            section = [x for x, yy in p if yy == y]
            for a, b in ((p[0], p[1]), (p[1], p[2]), (p[2], p[0])):
                if min(a[1], b[1]) < y < max(a[1], b[1]):
                    section.append(a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
            if not section:
                continue
            for i in range(max(int(min(section)), 0), min(int(max(section)), scene.width - 1) + 1):  # int(): toward zero
                ts.append(int(t))
                ys.append(y)
                xs.append(i)
    return _runs(ts, ys, xs)


def on_library_boundary(triangle: NDArray[np.float64], i: int, j: int, convention: Convention) -> bool:
    """Whether pixel (i, j) (i, j >= 0) lies exactly on the rule's decision boundary for the
    ``triangle`` as the convention receives it: its AGG cover exactly ``256 t`` rounded up
    (``agg-cover``: where a ``>`` for ``>=`` goes wrong), or the right end of row j's span
    an exact integer crossing at i, or j the bottom row (``inclusive-scanline``: drawn only
    because both ends are).

    >>> t = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    >>> on_library_boundary(t, 1, 0, Convention(coverage="agg-cover", input="fixed8-toward-zero"))  # half covered
    True
    >>> on_library_boundary(t, 2, 0, Convention(coverage="inclusive-scanline", input="integer-toward-zero"))
    True
    """
    p = convention.snap(np.asarray(triangle, dtype=np.float64).reshape(3, 2))
    if not np.all(np.isfinite(p)) or i < 0 or j < 0:
        return False
    if convention.model.thresholded:
        return bool(agg_covers(p, i + 1, j + 1)[j, i] == cover_min(convention.threshold))
    ys = p[:, 1]
    if not ys.min() <= j <= ys.max():
        return False
    section = [Fraction(float(x)) for x, y in p if y == j]
    for a, b in ((p[0], p[1]), (p[1], p[2]), (p[2], p[0])):
        if min(a[1], b[1]) < j < max(a[1], b[1]):
            section.append(Fraction(float(a[0])) + (j - Fraction(float(a[1]))) * Fraction(float(b[0] - a[0]))
                           / Fraction(float(b[1] - a[1])))
    return j == ys.max() or max(section) == i
