"""``area_scanline``: the font renderers' signed-area accumulation anti-aliaser (issue 14).

The method of libart, FreeType's "gray" rasterizer, stb_truetype (v2) and font-rs: each
triangle is drawn row by row into a row of cells. Every edge is cut into its pieces
within the row's band [j, j+1], and each piece is walked across the columns it crosses;
a sub-piece of signed height h (+ going down the edge in the triangle's order, - going
up) whose mean x inside cell i lies at xm in [0, 1] adds ``h * (1 - xm)`` to cell i (the
part of the cell to its right, the "area") and ``h * xm`` to cell i + 1, so that h in
all is carried to every cell further right (the "cover"). A prefix sum across the row
then gives each cell the signed area of the triangle inside it; its absolute value,
clamped to [0, 1] and rounded to 256 levels, is the alpha. Rows are independent.

Left and right of the viewport. A piece's part at x < 0 acts on the cells of the screen
exactly as a vertical piece at x = 0 (it carries its whole height into cell 0 and on),
and its part at x > W on none: pieces are cut there, so each row costs its on-screen
width, however far the triangle reaches.

Consistency. Each edge is taken with its end points ordered by y, whichever triangle it
belongs to, so two triangles sharing an edge cut it at the same float crossings: their
pieces coincide and their areas sum to the union's (the seam property on planar
partitions, up to each alpha's rounding).

The error bound (u = 2**-53, round to nearest, L = 2**24 the largest accepted |coordinate|)
    1. *Band crossings.* The x where an edge crosses the line y = j,
       ``xa + fl(j - ya) * fl(fl(xb - xa) / fl(yb - ya))`` (ya < yb), errs by at most
       ``gamma_5 |xb - xa| + u |x| <= 5.01 u * 2L + u L < 11.1 u L`` (clamped to the edge's
       x range, which only brings it closer). Local heights ``y - j`` inside the band are
       exact (Sterbenz; j >= 0). Moving a piece's end by delta along x changes the area in
       the band by at most delta * h / 2 <= delta / 2; a triangle's section of a band has
       at most four ends on the band's lines: at most ``2 delta < 22.2 u L`` at any cell.
    2. *Column crossings.* Within a piece (heights in [0, 1]), the height where it meets
       x = i, ``yl + fl(i - xl) * fl(fl(yr - yl) / fl(xr - xl))``, errs by at most
       ``gamma_5 + u < 6.02 u`` (and is clamped to the piece's height range, so the
       sub-pieces' heights stay monotone and telescope to the piece's height). Moving
       such a point by e changes cell i - 1 and cell i by at most e each and no other
       cell; with two such points per cell and at most three pieces per band (one per
       edge): at most ``36.2 u``.
    3. *Cell arithmetic.* Local x inside a cell is exact (Sterbenz again, i >= 0); xm has
       one rounding, h one, ``1 - xm`` one more, each product one: the two contributions
       of a sub-piece err by at most ``4 u |h|`` and ``3 u |h|``, ``7 u`` per piece over a
       whole row since its heights sum to at most 1: ``21 u``. Adding them into cells
       (at most nine additions into a cell, whose contributions total at most 3 in
       absolute value over the row): ``27 u``.
    4. *Prefix sum.* Each partial sum is a cell's value, within [-1 - 1e-6, 1 + 1e-6]; the
       row has at most ``W <= 2**20`` cells: ``2**20 * 1.01 u``. Taking |.| and clamping to
       [0, 1] only brings it closer to the exact area, which lies in [0, 1].
    5. *Quantisation.* ``alpha = rint(fl(255 a)) / 255`` is within half a level
       (1/510) plus ``2 u`` of a.

    In all, |alpha - exact area| <= 1/510 + 22.2 u L + (86.2 + 2**20 * 1.01) u
    < 1/510 + 4.14e-8 < 1/510 + 2**-24. The convention declares
    ``tolerance = 1/510 + 2**-23`` (:data:`TOLERANCE`): the proven bound with a factor of
    two to spare on the float part. Triangles with a coordinate beyond +/-L are refused
    (ValueError naming the first), triangles of exactly zero area (exact orientation) and
    non-finite ones draw nothing.

Convention: area coverage, 256 levels, within :data:`TOLERANCE` of the exact area, no
snapping, no culling. No attributes (``interpolates = False``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from rasterizers._common import screen_triangles

__all__ = ["AreaScanline", "MAX_COORDINATE", "TOLERANCE", "LEVELS", "emit_row", "first_capacity"]

MAX_COORDINATE = 2.0**24  # L: band crossings err by < 11.1 u L = 2.1e-8 px (module docstring)
LEVELS = 256
# Half a level plus the float error (< 4.14e-8 < 2**-24, module docstring), doubled.
TOLERANCE = 0.5 / (LEVELS - 1) + 2.0**-23


@numba.njit(cache=True, inline="always")
def _crossing(xa, ya, xb, yb, y):  # type: ignore[no-untyped-def]
    """x of the edge (ya < yb) at height y in [ya, yb], within its x range."""
    if y == ya:
        return xa
    if y == yb:
        return xb
    x = xa + (y - ya) * ((xb - xa) / (yb - ya))
    return min(max(x, min(xa, xb)), max(xa, xb))


@numba.njit(cache=True, inline="always")
def _height_at(xl, yl, xr, yr, x):  # type: ignore[no-untyped-def]
    """Local height of the piece (xl, yl) - (xr, yr), xl < xr, at x in [xl, xr], kept
    within the piece's height range (monotone along the piece)."""
    y = yl + (x - xl) * ((yr - yl) / (xr - xl))
    return min(max(y, min(yl, yr)), max(yl, yr))


@numba.njit(cache=True)
def _accumulate_piece(cells, x0, y0, x1, y1, d, width):  # type: ignore[no-untyped-def]
    """Add the piece from (x0, y0) to (x1, y1) (local heights y0 < y1 in the band, global
    x) of signed direction d into ``cells`` (W + 2,): per cell i it crosses, the area
    ``h (1 - xm)`` into cell i and ``h xm`` into cell i + 1 (h its signed height there,
    xm its mean x inside the cell). Parts left of x = 0 count as a vertical piece at 0,
    parts right of x = W are dropped (they reach no cell of the screen)."""
    if x0 <= x1:
        xl, yl, xr, yr = x0, y0, x1, y1
    else:
        xl, yl, xr, yr = x1, y1, x0, y0
    if xr <= 0.0:  # wholly left of the screen: its height carries into cell 0 and on
        cells[0] += d * (y1 - y0)
        return
    if xl >= width:
        return
    if xl == xr:  # vertical: one cell
        i = int(math.floor(xl))
        xm = xl - i
        h = d * (y1 - y0)
        cells[i] += h * (1.0 - xm)
        cells[i + 1] += h * xm
        return
    x_in, y_in = xl, yl
    if xl < 0.0:  # the part left of x = 0 acts as a vertical piece at x = 0
        y_in = _height_at(xl, yl, xr, yr, 0.0)
        cells[0] += d * abs(y_in - yl)
        x_in = 0.0
    i = int(math.floor(x_in))
    while True:
        if xr <= i + 1.0:
            x_out, y_out = xr, yr
        else:
            x_out = i + 1.0
            y_out = _height_at(xl, yl, xr, yr, x_out)
        h = d * abs(y_out - y_in)
        # local x in cell i is exact: x_in, x_out lie in [i, i + 1] and i >= 0 (Sterbenz)
        xm = 0.5 * ((x_in - i) + (x_out - i))
        cells[i] += h * (1.0 - xm)  # the cell's part right of the edge
        cells[i + 1] += h * xm  # the rest of h: carried to every cell further right
        if x_out >= xr or i + 1 >= width:
            return
        i += 1
        x_in, y_in = x_out, y_out


@numba.njit(cache=True)
def _grow(block, alpha, n, m, spans, pixels):  # type: ignore[no-untyped-def]
    """The output buffers with room for ``spans`` more spans and ``pixels`` more alphas."""
    if n + spans > block.shape[1]:
        bigger = np.empty((4, max(2 * block.shape[1], n + spans)), dtype=np.int64)
        for k in range(n):  # loops, not slices: numba compiles them in a fraction of the time
            bigger[0, k], bigger[1, k], bigger[2, k], bigger[3, k] = block[0, k], block[1, k], block[2, k], block[3, k]
        block = bigger
    if m + pixels > alpha.size:
        wider = np.empty(max(2 * alpha.size, m + pixels))
        for k in range(m):
            wider[k] = alpha[k]
        alpha = wider
    return block, alpha


@numba.njit(cache=True)
def emit_row(t, j, values, c0, c1, block, alpha, n, m):  # type: ignore[no-untyped-def]
    """Append the runs of nonzero ``values[c0 .. c1]`` of row j of triangle t as spans
    with their alphas; returns the grown buffers and the new counts."""
    block, alpha = _grow(block, alpha, n, m, (c1 - c0 + 2) // 2, c1 - c0 + 1)
    c = c0
    while c <= c1:
        if values[c] == 0.0:
            c += 1
            continue
        start = c
        while c <= c1 and values[c] != 0.0:
            alpha[m] = values[c]
            m += 1
            c += 1
        block[0, n], block[1, n], block[2, n], block[3, n] = t, j, start, c
        n += 1
    return block, alpha, n, m


def first_capacity(positions: NDArray[np.float64], sign: NDArray[np.int8], width: int, height: int) -> tuple[int, int]:
    """A first guess at the spans and pixels of a scene (the kernels grow their buffers
    past it when needed): per drawn triangle its rows on screen, and its area plus two
    pixels per row, clamped to the screen, in floats before any integer."""
    drawn = sign != 0
    p = np.where(drawn[:, None, None], positions, 0.0)
    ys = p[:, :, 1]
    rows = np.clip(np.ceil(ys.max(axis=1)) - np.floor(ys.min(axis=1)) + 1.0, 0.0, float(height))
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    with np.errstate(over="ignore", invalid="ignore"):
        area = np.nan_to_num(0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]), nan=0.0, posinf=0.0)
    pixels = np.minimum(area + 2.0 * rows, float(width) * height)
    return int(rows[drawn].sum()) + 16, int(pixels[drawn].sum()) + 16


@numba.njit(cache=True, error_model="numpy")
def _kernel(positions, sign, width, height, steps, block, alpha):  # type: ignore[no-untyped-def]
    cells = np.zeros(width + 2)
    values = np.zeros(width)
    edges = np.empty((3, 5))
    n = np.int64(0)  # np.int64, not the literal 0: numba compiles a callee once per literal argument
    m = np.int64(0)
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue  # zero area or non-finite: nothing
        p = positions[t]
        count = 0
        for k in range(3):
            ax, ay, bx, by = p[k, 0], p[k, 1], p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
            if ay == by:
                continue  # horizontal: no height, no area
            # Each edge with its ends ordered by y, whichever triangle it belongs to, so
            # that neighbours cut it at the same crossings; d: down (+1) or up (-1).
            if ay < by:
                edges[count, 0], edges[count, 1], edges[count, 2], edges[count, 3], edges[count, 4] = ax, ay, bx, by, 1.0
            else:
                edges[count, 0], edges[count, 1], edges[count, 2], edges[count, 3], edges[count, 4] = bx, by, ax, ay, -1.0
            count += 1
        ymin = min(p[0, 1], p[1, 1], p[2, 1])
        ymax = max(p[0, 1], p[1, 1], p[2, 1])
        # Rows whose band [j, j + 1] meets (ymin, ymax), clamped as floats first.
        if ymax <= 0.0 or ymin >= height:
            continue
        r0 = int(math.floor(max(ymin, 0.0)))
        r1 = int(math.ceil(min(ymax, float(height)))) - 1
        for j in range(r0, r1 + 1):
            top = float(j)
            lo = math.inf
            hi = -math.inf
            for k in range(count):
                xa, ya, xb, yb, d = edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3], edges[k, 4]
                if yb <= top or ya >= top + 1.0:
                    continue
                # The piece inside the band; local heights y - j are exact (Sterbenz).
                if ya >= top:
                    x0, y0 = xa, ya - top
                else:
                    x0, y0 = _crossing(xa, ya, xb, yb, top), 0.0
                if yb <= top + 1.0:
                    x1, y1 = xb, yb - top
                else:
                    x1, y1 = _crossing(xa, ya, xb, yb, top + 1.0), 1.0
                _accumulate_piece(cells, x0, y0, x1, y1, d, width)
                lo = min(lo, x0, x1)
                hi = max(hi, x0, x1)
            if lo > hi:
                continue
            # Cells the pieces touched: floor(lo) .. floor(hi), on screen.
            c0 = int(math.floor(min(max(lo, 0.0), width - 1.0)))
            c1 = int(math.floor(min(max(hi, 0.0), width - 1.0)))
            acc = 0.0
            for i in range(c0, c1 + 1):
                acc += cells[i]  # the prefix sum: area in the cell plus the cover carried
                # |signed area| (the winding's sign), clamped, rounded to the nearest level
                values[i] = np.rint(min(abs(acc), 1.0) * steps) / steps
            for i in range(c0, c1 + 2):
                cells[i] = 0.0
            block, alpha, n, m = emit_row(t, j, values, c0, c1, block, alpha, n, m)
    return block, alpha, n, m


class AreaScanline:
    """Signed-area accumulation per row (FreeType "gray", stb_truetype v2, font-rs).

    Examples
    --------
    >>> cov = AreaScanline().rasterize(Scene(3, 2, [[[0, 0], [2, 0], [0, 2]]]))
    >>> cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist(), cov.alpha.tolist()
    ([0, 1], [0, 0], [2, 1], [1.0, 0.5019607843137255, 0.5019607843137255])
    >>> AreaScanline().rasterize(Scene(4, 4, [[[0, 0], [1e30, 0], [0, 1]]]))  # doctest: +NORMALIZE_WHITESPACE
    Traceback (most recent call last):
    ...
    ValueError: area_scanline: triangle 0 has a coordinate beyond +/-1.67772e+07 px ([[0.0, 0.0], [1e+30, 0.0], [0.0, 1.0]]); band
    crossings are within 2**-24 of a pixel only that far
    """

    name = "area_scanline"
    convention = Convention(coverage="area", levels=LEVELS, tolerance=TOLERANCE)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        sign = screen_triangles(  # zero-area and non-finite triangles draw nothing
            scene, MAX_COORDINATE, self.name, "band crossings are within 2**-24 of a pixel only that far"
        )
        positions = frozen(scene.positions)
        spans, pixels = first_capacity(positions, sign, scene.width, scene.height)
        block, alpha = np.empty((4, spans), dtype=np.int64), np.empty(pixels)
        block, alpha, n, m = _kernel(positions, sign, scene.width, scene.height, float(LEVELS - 1), block, alpha)
        return Coverage(block[0, :n], block[1, :n], block[2, :n], block[3, :n], alpha=alpha[:m])
