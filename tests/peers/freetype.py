"""A faithful port of FreeType's smooth ("gray") anti-aliased rasterizer, for straight
outlines: ``src/smooth/ftgrays.c`` of FreeType 2.14.3 (tag ``VER-2-14-3``, commit
0a0221a1347e2f1e07c395263540026e9a0aa7c7). ``ftgrays.c`` holds two line renderers, chosen
when it is compiled: by default the port follows the one compiled where ``FT_INT64`` is
defined (every 64-bit build: ``include/freetype/config/integer-types.h``), and
``FreetypeSmooth(walk="scanline")`` the other (:data:`LINE_WALKS`), which a standalone
build without ``FT_INT64`` compiles.

What is ported, function by function (names are the original's):

- ``gray_move_to`` / ``gray_line_to``: 26.6 points scaled to ``PIXEL_BITS`` = 8 (1/256 px,
  ``UPSCALE``), the current cell set to the point's (``gray_set_cell``).
- ``gray_set_cell``: cells outside the band's rows or right of it go to the null cell (their
  sums are lost); cells left of the band are clamped into column ``min_ex - 1``, which only
  carries its cover into the row.
- ``gray_render_line`` (the ``FT_INT64`` branch): the line walked cell by cell, the exit side
  decided by the exact 64-bit ``prod``, the exit coordinate by ``FT_UDIV`` (a multiply by the
  truncated reciprocal ``0xFFFFFFFF / d`` and a shift by 32, never above the exact quotient);
  each piece adds ``FT_INTEGRATE``: ``cover += dy``, ``area += dy * (fx1 + fx2)``, both in
  wrapping 32-bit ints (``ADD_INT``); vertical clipping skips lines wholly above or below.
- ``gray_render_line`` and ``gray_render_scanline`` (without ``FT_INT64``): the line cut at
  each row, the row's crossing x the floor of the exact one (``FT_DIV_MOD``, quotient and
  remainder cast to ``int``, the remainder carried from row to row), then each row's piece
  cut at each column the same way.
- ``gray_sweep``: per row, the running cover (``cover * 2 * ONE_PIXEL``) and each cell's
  ``cover - area``; ``FT_FILL_RULE``: ``coverage = area >> 9``, complemented (``~coverage``)
  when the fill bit is set (the sign bit for nonzero, bit 8 for even-odd), clamped to 255 for
  nonzero, kept to its low byte.

Cells are kept in a dense (rows, width + 1) array, column 0 standing for ``min_ex - 1``:
a cell the original never created holds cover 0 and area 0, and the sweep then writes the
running cover's value exactly where the original's span (``FT_GRAY_SET``) does, so the bitmap
is the same. Banding (``gray_convert_glyph`` splitting the bitmap when the cell pool
overflows) changes no pixel: each band renders the same lines and keeps the cells within it,
and the clamped column carries the cover of everything left of it; so the port renders one
band, the whole bitmap. Conic and cubic arcs, the direct-span sweep and the pool are not
ported (a polygon draws no arc; the direct sweep writes the same values, checked against the
original in ``tests/peers/test_freetype.py``).

The caller's part: vertices to 26.6 fixed point by rounding to nearest, ties to even
(``np.rint(64 x)``, exact in float64), FreeType's input grid; our y grows downwards and is
passed unchanged (the bitmap's pitch negative, so that its row y is FreeType's row y).

Checked against the original (``tests/peers/src/freetype``, built standalone with and
without ``FT_INT64``; ``tests/peers/test_freetype.py``), ``RASTERCHECK_PEER_SCENES=12000``
random triangles (ordinary, tiny, huge to 2**20 px, partly outside, lattice and degenerate
ones, each in both windings; 300 by default): with ``FT_INT64``, 0 differing alphas of
36,378,010 (both fill rules, both sweeps; huge ones in one), and of 40,995,822 in an
earlier run with every mode for the huge ones too; without, 0 of 13,665,274 (the bitmap,
nonzero). Also equal on polygons of several contours and on every still scene of the
quick suite drawn through the adapter.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.real._masks import finite_within_limit

__all__ = ["FreetypeSmooth", "LINE_WALKS", "to_26_6", "render_outline"]

PIXEL_BITS = 8
ONE_PIXEL = 1 << PIXEL_BITS
_RECIPROCAL = 0xFFFFFFFF  # FT_UDIVPREP's dividend
_INT_MIN = -(1 << 31)


@numba.njit(cache=True, inline="always")
def _i32(v: int) -> int:
    """A C ``int`` of the low 32 bits (the wrap of ``ADD_INT`` and of a cast to ``TCoord``)."""
    return ((v + (1 << 31)) & 0xFFFFFFFF) - (1 << 31)


@numba.njit(cache=True, inline="always")
def _trunc_div(a: int, b: int) -> int:
    """C's ``a / b`` on integers: the quotient truncated toward zero."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


@numba.njit(cache=True, inline="always")
def _udiv(a: int, reciprocal: int) -> int:
    """``FT_UDIV``: ``(TCoord)(((FT_UInt64)a * (FT_UInt64)reciprocal) >> 32)``."""
    product = np.uint64(a) * np.uint64(reciprocal)
    return _i32(np.int64(product >> np.uint64(32)))  # type: ignore[arg-type]  # (numba: an int64 is an int)


@numba.njit(cache=True)
def _set_cell(state: NDArray[np.int64], ex: int, ey: int, width: int, height: int) -> None:
    """``gray_set_cell`` for the band [0, width) x [0, height): state[0] the current cell's
    row, state[1] its column + 1 (column 0: ``min_ex - 1``), state[0] = -1: the null cell."""
    if ey < 0 or ey >= height or ex >= width:
        state[0] = -1
    else:
        state[0] = ey
        state[1] = max(ex, -1) + 1


@numba.njit(cache=True)
def _integrate(state: NDArray[np.int64], cover: NDArray[np.int64], area: NDArray[np.int64], a: int, b: int) -> None:
    """``FT_INTEGRATE``: the current cell's cover += a, area += a * b (32-bit wrapping)."""
    if state[0] >= 0:
        r, c = state[0], state[1]
        cover[r, c] = _i32(cover[r, c] + a)
        area[r, c] = _i32(area[r, c] + _i32(a * b))


@numba.njit(cache=True)
def _render_line(state: NDArray[np.int64], cover: NDArray[np.int64], area: NDArray[np.int64],
                 to_x: int, to_y: int, width: int, height: int) -> None:
    """``gray_render_line`` (``FT_INT64``): from (state[2], state[3]) to (to_x, to_y),
    coordinates in 1/256 px."""
    x, y = state[2], state[3]
    ey1 = _i32(y >> PIXEL_BITS)
    ey2 = _i32(to_y >> PIXEL_BITS)
    if not ((ey1 >= height and ey2 >= height) or (ey1 < 0 and ey2 < 0)):  # vertical clipping
        ex1 = _i32(x >> PIXEL_BITS)
        ex2 = _i32(to_x >> PIXEL_BITS)
        fx1 = x & (ONE_PIXEL - 1)
        fy1 = y & (ONE_PIXEL - 1)
        dx = to_x - x
        dy = to_y - y
        horizontal = False
        if ex1 == ex2 and ey1 == ey2:  # inside one cell
            pass
        elif dy == 0:  # any horizontal line
            _set_cell(state, ex2, ey2, width, height)
            horizontal = True
        elif dx == 0:
            if dy > 0:  # vertical line up
                while True:
                    fy2 = ONE_PIXEL
                    _integrate(state, cover, area, fy2 - fy1, fx1 * 2)
                    fy1 = 0
                    ey1 += 1
                    _set_cell(state, ex1, ey1, width, height)
                    if ey1 == ey2:
                        break
            else:  # vertical line down
                while True:
                    fy2 = 0
                    _integrate(state, cover, area, fy2 - fy1, fx1 * 2)
                    fy1 = ONE_PIXEL
                    ey1 -= 1
                    _set_cell(state, ex1, ey1, width, height)
                    if ey1 == ey2:
                        break
        else:  # any other line
            prod = dx * fy1 - dy * fx1
            dx_r = _trunc_div(_RECIPROCAL, dx) if ex1 != ex2 else 0
            dy_r = _trunc_div(_RECIPROCAL, dy) if ey1 != ey2 else 0
            while True:
                if prod - dx * ONE_PIXEL > 0 and prod <= 0:  # left
                    fx2 = 0
                    fy2 = _udiv(-prod, -dx_r)
                    prod -= dy * ONE_PIXEL
                    _integrate(state, cover, area, fy2 - fy1, fx1 + fx2)
                    fx1 = ONE_PIXEL
                    fy1 = fy2
                    ex1 -= 1
                elif prod - dx * ONE_PIXEL + dy * ONE_PIXEL > 0 and prod - dx * ONE_PIXEL <= 0:  # up
                    prod -= dx * ONE_PIXEL
                    fx2 = _udiv(-prod, dy_r)
                    fy2 = ONE_PIXEL
                    _integrate(state, cover, area, fy2 - fy1, fx1 + fx2)
                    fx1 = fx2
                    fy1 = 0
                    ey1 += 1
                elif prod + dy * ONE_PIXEL >= 0 and prod - dx * ONE_PIXEL + dy * ONE_PIXEL <= 0:  # right
                    prod += dy * ONE_PIXEL
                    fx2 = ONE_PIXEL
                    fy2 = _udiv(prod, dx_r)
                    _integrate(state, cover, area, fy2 - fy1, fx1 + fx2)
                    fx1 = 0
                    fy1 = fy2
                    ex1 += 1
                else:  # down
                    fx2 = _udiv(prod, -dy_r)
                    fy2 = 0
                    prod += dx * ONE_PIXEL
                    _integrate(state, cover, area, fy2 - fy1, fx1 + fx2)
                    fx1 = fx2
                    fy1 = ONE_PIXEL
                    ey1 -= 1
                _set_cell(state, ex1, ey1, width, height)
                if ex1 == ex2 and ey1 == ey2:
                    break
        if not horizontal:
            fx2 = to_x & (ONE_PIXEL - 1)
            fy2 = to_y & (ONE_PIXEL - 1)
            _integrate(state, cover, area, fy2 - fy1, fx1 + fx2)
    state[2] = to_x
    state[3] = to_y


@numba.njit(cache=True)
def _div_mod(dividend: int, divisor: int) -> tuple[int, int]:
    """``FT_DIV_MOD( TCoord, ... )``: C's quotient and remainder, each cast to ``int``, the
    remainder made non-negative (the quotient lowered)."""
    quotient = _i32(_trunc_div(dividend, divisor))
    remainder = _i32(dividend - _trunc_div(dividend, divisor) * divisor)
    if remainder < 0:
        quotient -= 1
        remainder = _i32(remainder + _i32(divisor))
    return quotient, remainder


@numba.njit(cache=True)
def _render_scanline(state: NDArray[np.int64], cover: NDArray[np.int64], area: NDArray[np.int64], ey: int,
                     x1: int, y1: int, x2: int, y2: int, width: int, height: int) -> None:
    """``gray_render_scanline`` (without ``FT_INT64``): the piece of a line within row ey,
    from (x1, y1) to (x2, y2), y1 and y2 within the row (0 .. ONE_PIXEL)."""
    ex1 = _i32(x1 >> PIXEL_BITS)
    ex2 = _i32(x2 >> PIXEL_BITS)
    if y1 == y2:  # trivial case
        _set_cell(state, ex2, ey, width, height)
        return
    fx1 = x1 & (ONE_PIXEL - 1)
    fx2 = x2 & (ONE_PIXEL - 1)
    if ex1 != ex2:  # a run of adjacent cells on the same scanline
        dx = x2 - x1
        dy = y2 - y1
        if dx > 0:
            p = (ONE_PIXEL - fx1) * dy
            first = ONE_PIXEL
            incr = 1
        else:
            p = fx1 * dy
            first = 0
            incr = -1
            dx = -dx
        delta, mod = _div_mod(p, dx)
        _integrate(state, cover, area, delta, fx1 + first)
        y1 += delta
        ex1 += incr
        _set_cell(state, ex1, ey, width, height)
        if ex1 != ex2:
            lift, rem = _div_mod(ONE_PIXEL * dy, dx)
            while True:
                delta = lift
                mod += rem
                if mod >= _i32(dx):
                    mod -= _i32(dx)
                    delta += 1
                _integrate(state, cover, area, delta, ONE_PIXEL)
                y1 += delta
                ex1 += incr
                _set_cell(state, ex1, ey, width, height)
                if ex1 == ex2:
                    break
        fx1 = ONE_PIXEL - first
    _integrate(state, cover, area, y2 - y1, fx1 + fx2)


@numba.njit(cache=True)
def _render_line_scanlines(state: NDArray[np.int64], cover: NDArray[np.int64], area: NDArray[np.int64],
                           to_x: int, to_y: int, width: int, height: int) -> None:
    """``gray_render_line`` without ``FT_INT64``: the line cut into scanlines, each row's
    crossing x the floor of the exact one (``FT_DIV_MOD``, its remainder carried), each
    scanline rendered by :func:`_render_scanline`."""
    x, y = state[2], state[3]
    ey1 = _i32(y >> PIXEL_BITS)
    ey2 = _i32(to_y >> PIXEL_BITS)
    if not ((ey1 >= height and ey2 >= height) or (ey1 < 0 and ey2 < 0)):  # vertical clipping
        fy1 = y & (ONE_PIXEL - 1)
        fy2 = to_y & (ONE_PIXEL - 1)
        dx = to_x - x
        dy = to_y - y
        if ey1 == ey2:  # everything on a single scanline
            _render_scanline(state, cover, area, ey1, x, fy1, to_x, fy2, width, height)
        elif dx == 0:  # vertical line
            ex = _i32(x >> PIXEL_BITS)
            two_fx = (x & (ONE_PIXEL - 1)) << 1
            if dy > 0:
                first = ONE_PIXEL
                incr = 1
            else:
                first = 0
                incr = -1
            _integrate(state, cover, area, first - fy1, two_fx)
            ey1 += incr
            _set_cell(state, ex, ey1, width, height)
            delta = first + first - ONE_PIXEL
            while ey1 != ey2:
                _integrate(state, cover, area, delta, two_fx)
                ey1 += incr
                _set_cell(state, ex, ey1, width, height)
            _integrate(state, cover, area, fy2 - ONE_PIXEL + first, two_fx)
        else:  # several scanlines
            if dy > 0:
                p = (ONE_PIXEL - fy1) * dx
                first = ONE_PIXEL
                incr = 1
            else:
                p = fy1 * dx
                first = 0
                incr = -1
                dy = -dy
            delta, mod = _div_mod(p, dy)
            cx = x + delta
            _render_scanline(state, cover, area, ey1, x, fy1, cx, first, width, height)
            ey1 += incr
            _set_cell(state, _i32(cx >> PIXEL_BITS), ey1, width, height)
            if ey1 != ey2:
                lift, rem = _div_mod(ONE_PIXEL * dx, dy)
                while True:
                    delta = lift
                    mod += rem
                    if mod >= _i32(dy):
                        mod -= _i32(dy)
                        delta += 1
                    x2 = cx + delta
                    _render_scanline(state, cover, area, ey1, cx, ONE_PIXEL - first, x2, first, width, height)
                    cx = x2
                    ey1 += incr
                    _set_cell(state, _i32(cx >> PIXEL_BITS), ey1, width, height)
                    if ey1 == ey2:
                        break
            _render_scanline(state, cover, area, ey1, cx, ONE_PIXEL - first, to_x, fy2, width, height)
    state[2] = to_x
    state[3] = to_y


@numba.njit(cache=True, inline="always")
def _fill_rule(value: int, fill: int) -> int:
    """``FT_FILL_RULE`` and the cast to ``unsigned char``."""
    coverage = _i32(value >> (PIXEL_BITS * 2 + 1 - 8))
    if coverage & fill:
        coverage = ~coverage
    if coverage > 255 and fill == _INT_MIN:
        coverage = 255
    return coverage & 0xFF


@numba.njit(cache=True)
def _render(points: NDArray[np.int64], ends: NDArray[np.int64], evenodd: bool | np.bool_, out: NDArray[np.uint8],
            scanlines: bool) -> None:
    """``FT_Outline_Decompose`` of straight contours (move to the first point, a line to each
    next, a line back to the first), ``gray_render_line`` for each (``scanlines``: the one
    compiled without ``FT_INT64``), ``gray_sweep`` into ``out`` ((height, width) uint8,
    overwritten)."""
    height, width = out.shape
    cover = np.zeros((height, width + 1), dtype=np.int64)
    area = np.zeros((height, width + 1), dtype=np.int64)
    state = np.full(4, -1, dtype=np.int64)
    first = 0
    for last in ends:
        x0 = points[first, 0] * (ONE_PIXEL >> 6)
        y0 = points[first, 1] * (ONE_PIXEL >> 6)
        _set_cell(state, _i32(x0 >> PIXEL_BITS), _i32(y0 >> PIXEL_BITS), width, height)  # gray_move_to
        state[2] = x0
        state[3] = y0
        for k in range(first + 1, last + 2):
            x1 = points[k, 0] * (ONE_PIXEL >> 6) if k <= last else x0  # the last: close the contour
            y1 = points[k, 1] * (ONE_PIXEL >> 6) if k <= last else y0
            if scanlines:
                _render_line_scanlines(state, cover, area, x1, y1, width, height)
            else:
                _render_line(state, cover, area, x1, y1, width, height)
        first = last + 1
    fill = 0x100 if evenodd else _INT_MIN
    for row in range(height):
        running = 0
        for column in range(width + 1):  # column 0: the cell left of the bitmap, never drawn
            running = _i32(running + _i32(cover[row, column] * (ONE_PIXEL * 2)))
            if column >= 1:
                value = _i32(running - area[row, column])
                out[row, column - 1] = _fill_rule(value, fill) if value != 0 else 0


@numba.njit(cache=True)
def _render_triangles(points: NDArray[np.int64], boxes: NDArray[np.int64], drawn: NDArray[np.int64], room: int,
                      scanlines: bool) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.uint8]]:
    """Each drawn triangle alone into a bitmap of its box (:func:`_render`, its 26.6 points
    moved to the box's origin: whole pixels, exact), its nonzero values kept: (triangle, x,
    y, value) with x, y on the screen, at most ``room`` of them."""
    t_out = np.empty(room, dtype=np.int64)
    x_out = np.empty(room, dtype=np.int64)
    y_out = np.empty(room, dtype=np.int64)
    v_out = np.empty(room, dtype=np.uint8)
    ends = np.array([2], dtype=np.int64)
    local = np.empty((3, 2), dtype=np.int64)
    n = 0
    for t in drawn:
        x0, y0, x1, y1 = boxes[t, 0], boxes[t, 1], boxes[t, 2], boxes[t, 3]
        for k in range(3):
            local[k, 0] = points[t, k, 0] - 64 * x0
            local[k, 1] = points[t, k, 1] - 64 * y0
        out = np.zeros((y1 - y0, x1 - x0), dtype=np.uint8)
        _render(local, ends, np.bool_(False), out, scanlines)  # (np.bool_: no recompile for the literal False)
        for row in range(y1 - y0):
            for column in range(x1 - x0):
                if out[row, column] != 0:
                    t_out[n] = t
                    x_out[n] = x0 + column
                    y_out[n] = y0 + row
                    v_out[n] = out[row, column]
                    n += 1
    return t_out[:n], x_out[:n], y_out[:n], v_out[:n]


def to_26_6(points: NDArray[np.float64]) -> NDArray[np.int64]:
    """Float pixel coordinates to FreeType's 26.6 fixed point: round(64 x), ties to even
    (64 x is exact in float64, so this is the nearest multiple of 1/64 px)."""
    return np.rint(np.asarray(points, dtype=np.float64) * 64.0).astype(np.int64)


def render_outline(points: NDArray[np.int64], ends: NDArray[np.int64], width: int, height: int,
                   evenodd: bool = False, walk: str = "int64") -> NDArray[np.uint8]:
    """FreeType's gray bitmap of straight contours.

    Parameters
    ----------
    points : (P, 2) int64
        26.6 fixed-point points, x right, y as given (row y of the result is y's row).
    ends : (C,) int64
        Each contour's last point index, ascending (``FT_Outline.contours``).
    width, height : int
    evenodd : bool
        ``FT_OUTLINE_EVEN_ODD_FILL``.
    walk : {"int64", "scanline"}
        The line renderer (:data:`LINE_WALKS`).

    Returns
    -------
    (height, width) uint8
    """
    out = np.zeros((height, width), dtype=np.uint8)
    _render(np.ascontiguousarray(points, dtype=np.int64), np.ascontiguousarray(ends, dtype=np.int64), bool(evenodd), out,
            _scanlines(walk))
    return out


_ONE_TRIANGLE = np.array([2], dtype=np.int64)
CHUNK = 1 << 22  # the box pixels one compiled call draws at most (the fragments it may keep)
LINE_WALKS = {"int64": "gray_render_line with FT_INT64 (every 64-bit build): exit side by prod, crossings by FT_UDIV",
              "scanline": "gray_render_line and gray_render_scanline without FT_INT64: crossings by FT_DIV_MOD"}
"""The two line renderers ``ftgrays.c`` compiles, by whether ``FT_INT64`` is defined."""


def _scanlines(walk: str) -> bool:
    """Whether ``walk`` is the scanline renderer; ValueError for neither of :data:`LINE_WALKS`."""
    if walk not in LINE_WALKS:
        raise ValueError(f"FreeType's line walk must be one of {', '.join(LINE_WALKS)}, not {walk!r}")
    return walk == "scanline"


class FreetypeSmooth:
    """FreeType's smooth rasterizer (the port above), one triangle at a time into an 8-bit
    gray bitmap around its box, as :class:`rasterizers.real.adapters.CairoAntialiased`
    draws with cairo: alpha = value / 255 per (triangle, pixel). A triangle with a NaN or
    infinite coordinate draws nothing (it has no 26.6 value to give FreeType).

    Declared convention: area coverage, 256 levels, vertices snapped to 26.6 fixed point
    (round to nearest, ties to even: the caller's conversion), within ``7/256`` (0.0273)
    of the snapped triangle's area, for edges shorter than 2**16 px. Why:

    - Quantisation: ``coverage = area >> 9`` is floor(256 A) for a cell of area A winding
      positively and ``~coverage`` = ceil(256 A) - 1 for one winding negatively (then 256 is
      clamped to 255), read as value / 255. With 256 A = k + f, the error k/255 - (k + f)/256
      = k/65280 - f/256 lies in [-1/256, 1/256] for k <= 255: at most 1/256 (0.996 of a
      level), either winding. The two windings of one triangle differ by a level wherever
      256 A is an integer: a half-covered pixel is 128 one way and 127 the other.
    - Crossings: the vertices are exact (26.6 is a multiple of 1/256 px), and each cell's
      area is the exact area of straight pieces between the points where the edge crosses
      cell borders; a crossing is ``FT_UDIV(a, d)``, at most the exact quotient and less by
      under 1 + q d / 2**32 units of 1/256 px (q <= 256 the quotient, d the edge's extent in
      1/256 px): under 2/256 px when d < 2**24 (edges shorter than 2**16 px). Moving one
      crossing by delta along a pixel's side changes that pixel's area by at most delta/2
      (a triangle with base delta on the side and its apex within the pixel), and a triangle
      crosses a pixel's border at most 6 times (3 edges, 2 each): 6 x (2/256)/2 = 6/256.
      The scanline walk (``walk="scanline"``) keeps the same bound another way: each row's
      crossing is the floor of the exact one (``FT_DIV_MOD``: under 1/256 px), so each
      row's piece lies within 1/256 px horizontally of the edge (at most 1/256 of a pixel's
      area between them), and its column crossings are floors again (under 1/256 px, 1/512
      each): 2/256 per edge, 6/256 for three; its ``int`` quotients wrap only on edges
      flatter than 1 in 2**23.

    Measured on the quick suite: within 1.97 levels (0.0077) wherever it passes, motion
    frames included (the scanline walk: 2.2 levels, and no check fails). Longer edges lose
    precision in ``FT_UDIV`` (the reciprocal has 32 bits, and the comment in ``ftgrays.c``
    asks for the divisor to be ``PIXEL_BITS`` narrower than the shift): beyond 2**16 px a crossing may be off by 1 + 256 d / 2**32
    units, up to 17/256 px at d = 2**28. The quick suite's sliver and wedge from x = -1e6 to
    1e6 err by 12 levels there (the same wedge 100 times smaller: one level; ``ftgrays.c``
    built without ``FT_INT64``, whose ``gray_render_scanline`` divides exactly: one level
    at 1e6 too), which accuracy names by the triangles' magnitude (``overflow-2^12..2^24``).
    The other bug the quick suite finds: the alphas depend on the winding (invariance,
    ``changes-under-flip-winding``), by the quantisation's level and by ``FT_UDIV``
    rounding each crossing down in the direction the edge is walked, two levels apart
    where both add (lattice/bits-0, triangle 13, pixel (42, 35): 96 one way, 94 the
    other, the exact area 95.625/255)."""

    name = "freetype"
    # floor(256 A) read as /255 (1/256), 6 crossings per pixel each within 2/256 px (6/256)
    convention = Convention(coverage="area", levels=256, subpixel_bits=6, snap_rounding="nearest-even", tolerance=7 / 256)
    interpolates = False  # coverage only: FreeType draws no varyings
    scene_kinds = ("triangles",)

    def __init__(self, walk: str = "int64") -> None:
        _scanlines(walk)  # a clear error for an unknown walk
        self.walk = walk
        if walk != "int64":
            self.name = f"freetype_{walk}"

    def rasterize(self, scene: Scene) -> Coverage:
        """What :func:`~rasterizers.real._masks.draw_each_alpha` with :meth:`draw_one` gives
        (each triangle alone into a bitmap of its box widened by 2 px and clipped to the
        viewport; a coordinate beyond :data:`~rasterizers.real._masks.LIMIT` refused with a
        ValueError naming the triangle), in one compiled loop over the triangles."""
        if not isinstance(scene, Scene):
            raise ValueError(f"{self.name}: takes triangles scenes, not {type(scene).__name__}")
        finite = finite_within_limit(scene, self.name)
        positions = np.where(finite[:, None, None], scene.positions, 0.0)
        size = np.array([scene.width, scene.height])
        first = np.clip(np.floor(positions.min(axis=1)) - 2, 0, size).astype(np.int64)
        last = np.clip(np.ceil(positions.max(axis=1)) + 2, 0, size).astype(np.int64)
        drawn = np.flatnonzero(finite & np.all(first < last, axis=1))
        rooms = np.prod(last[drawn] - first[drawn], axis=1)
        points, boxes = to_26_6(positions), np.concatenate([first, last], axis=1)
        parts = []
        start = 0
        while start < drawn.size:  # triangles in chunks of boxes up to CHUNK pixels (one at least)
            stop = start + max(1, int(np.searchsorted(np.cumsum(rooms[start:]), CHUNK, side="right")))
            parts.append(_render_triangles(points, boxes, drawn[start:stop], int(rooms[start:stop].sum()),
                                           self.walk == "scanline"))
            start = stop
        if not parts or not sum(part[0].size for part in parts):
            return Coverage.empty()
        t, x, y, value = (np.concatenate([part[i] for part in parts]) for i in range(4))
        return Coverage.from_pixels(t, x, y, alpha=value / 255.0)

    def draw_one(self, p: NDArray[np.float64], w: int, h: int, origin: tuple[int, int]) -> NDArray[np.float64]:
        """One triangle (vertices relative to the box's origin) into a w x h bitmap: the
        (h, w) alphas, value / 255; nothing for a NaN or infinite coordinate (it has no 26.6
        value to give FreeType)."""
        if not np.all(np.isfinite(p)):
            return np.zeros((h, w))
        return render_outline(to_26_6(p), _ONE_TRIANGLE, w, h, walk=self.walk) / 255.0
