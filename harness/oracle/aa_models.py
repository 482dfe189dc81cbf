"""Row-sampled area coverage: the anti-aliasing model of cairo's scan converter.

cairo (``src/cairo-tor-scan-converter.c``, the "tor" converter its image backend fills
with) computes a pixel's alpha neither as the exact area nor from point samples:

* ``GRID_Y 15`` sub-rows per pixel row, each sampled on its centre line: an edge's x is
  first evaluated at ``(2 * ytop + 1) / (2 * GRID_Y)`` (``polygon_add_edge``: ``tmp = (2 *
  ytop + 1) << GLITTER_INPUT_BITS``) and stepped by ``dxdy`` per sub-row (``step``), its
  ``cell`` the x rounded half up to ``GRID_X = 256`` (``GRID_X_BITS =
  CAIRO_FIXED_FRAC_BITS``); ``sub_row`` adds, for every sub-row, the covered span
  ``[xstart, xend)`` to the cells (``cell_list_add_subspan``): exact along x but for that
  rounding. An edge is active on the sub-rows ``[ytop, ybot)`` with ``ytop = floor(15 y +
  1/2)`` (``INPUT_TO_GRID_general``): the centre lines ``y_top < y_k <= y_bottom``.
* a pixel row in which no edge starts or ends and the edges keep their order
  (``can_do_full_row``) is not sampled: ``full_row`` / ``cell_list_render_edge`` add the
  area between the edges, each from its x at the row's top to its x at the bottom (stepped
  back half a sub-row from the sample positions, ``x1.quo -= edge->dxdy.quo / 2``: C's
  truncating halves), with its crossings of the pixel column boundaries at heights rounded
  down to 1/15 of the row (``y.quo = tmp / dx``).
* the cell area ``c`` in ``[0, GRID_XY]``, ``GRID_XY = 2 * 256 * 15 = 7680``, becomes an
  8-bit alpha by ``GRID_AREA_TO_ALPHA(c) = (c + (c << 4) + 256) >> 9 = floor(255 c / 7680 +
  1/2)``: the coverage rounded half up to 256 levels (``blit_a8``).

As conventions (:class:`harness.contract.conventions.Convention`):

* ``Convention(coverage="area", rows=n)``: *row-sampled* area coverage, the alpha of a
  triangle T at pixel (i, j) the mean of its n cross-sections with the pixel on the sub-row
  centre lines, exact along x::

      alpha = (1/n) * sum_{k=0}^{n-1} length(T ∩ {y = j + (k + 1/2)/n} ∩ [i, i+1] x R)

  (an edge active where ``y_top < y_k <= y_bottom``; rational for float input; decided
  exactly: each vertex is compared with each line by an exact product, :func:`_side`).
* ``Convention(coverage="area", rows=15, full_rows=True, input="fixed8")``: cairo's hybrid
  exactly, its integer procedure (full rows and sub-rows, the x rounding and the truncated
  half-steps) on its 24.8 input (the oracle rounds to 1/256 px, ties to even, as
  ``_cairo_fixed_from_double``; declare ``input="fixed8"`` to say so). Unquantised: the
  convention's ``levels`` (256) and tolerance judge the quantisation.

:func:`row_sampled_coverage` is the compiled oracle; :func:`exact_row_sampled_alpha` the
reference (rationals for the row-sampled model, cairo's integer procedure run uncompiled
for the hybrid), compared in tests/oracle/test_aa_models.py.

Measured (pycairo, cairo 1.16, A8, ``ANTIALIAS_DEFAULT``): on 400 random float triangles
inside a 24 x 24 surface every alpha is within one level of the hybrid (the analytic area:
up to 17 levels off; all 15 rows sampled: 17). On the quick suite's static cases, at a
tolerance of one level, 2,747 pixels fail (against the analytic area at one level:
90,529): triangles crossing the surface's left or right side, which cairo clips first
(``cairo-polygon.c``: the clipped edges start and end mid-row, so those rows are sampled;
not modelled), the NaN triangles cairo draws and the sliver whose coverage of -5/255 wraps
to 251.

The model is defined by coverage of a primitive along sample lines, so it extends to paths
as the winding oracle extends point samples: the cross-section of a path on a line is the
set of x where the fill rule holds (not implemented: triangles only).

The other libraries, measured the same way (max |alpha - model| in levels over 90 random
triangles): FreeType smooth 2 against the analytic area on ``input="fixed6"`` (4 on the
float input), Qt 3 on ``fixed6`` (4); tiny-skia 17 against a 4 x 4 point grid at (k + 1/2)/4
on float32 input (``scan/path_aa.rs``: ``SUPERSAMPLE_SHIFT`` 2; ``coverage_to_partial_alpha``
``aa << (8 - 2 * SHIFT)`` and the full-row ``max_value`` 64 or 63 make the level ``16 N -
[last sub-row full]``, within one level of 255 N / 16; the 17 are whole samples decided by
skia's fixed-point edge walking of the 4x-scaled path, not modelled).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.oracle.area import exact_area  # noqa: F401 (doctests)

__all__ = ["CAIRO_ROWS", "row_sampled_coverage", "exact_row_sampled_alpha", "cairo_alpha_levels"]

# cairo-tor-scan-converter.c: #define GRID_Y 15
CAIRO_ROWS = 15


def cairo_alpha_levels(coverage: ArrayLike) -> NDArray[np.int64]:
    """cairo's ``GRID_AREA_TO_ALPHA`` for ``GRID_XY = 2*256*15``: the coverage in [0, 1]
    (as the cell area ``c = 7680 * coverage``) to an 8-bit level, ``(c + (c << 4) + 256) >> 9``.

    >>> cairo_alpha_levels([0.0, 0.5, 1.0, 1 / 7680]).tolist()
    [0, 128, 255, 0]
    """
    c = np.floor(np.asarray(coverage, dtype=np.float64) * 7680.0 + 0.5).astype(np.int64)
    return (c + (c << 4) + 256) >> 9


# -- the rational reference ------------------------------------------------------------------


def _cross_section(vertices: list[tuple[Fraction, Fraction]], y: Fraction) -> tuple[Fraction, Fraction] | None:
    """[xl, xr] of the triangle at height y, its edges active where y_top < y <= y_bottom,
    or None when the line misses it."""
    xs: list[Fraction] = []
    for k in range(3):
        (ax, ay), (bx, by) = vertices[k], vertices[(k + 1) % 3]
        if ay != by and min(ay, by) < y <= max(ay, by):  # cairo's sub-rows [ytop, ybot): half open
            xs.append(ax + (y - ay) * (bx - ax) / (by - ay))
    return (min(xs), max(xs)) if xs else None


def _cairo_alpha(points: NDArray[np.float64], x: int, y: int, rows: int) -> Fraction:
    """cairo's hybrid alpha of pixel (x, y), as the rational its cells hold: the same
    integer procedure as the compiled oracle, run uncompiled."""
    fixed = np.rint(points * 256.0).astype(np.int64)
    width = x + 2
    cover = np.zeros(width + 2, dtype=np.int64)
    uncovered = np.zeros(width + 2, dtype=np.int64)
    _cairo_row.py_func(fixed, y, rows, width, np.zeros(width + 1), cover, uncovered)  # type: ignore[no-untyped-call]
    area = int(cover[: x + 2].sum()) * 512 - int(uncovered[x + 1])
    return Fraction(area, 512 * rows)


def exact_row_sampled_alpha(triangle: ArrayLike, x: int, y: int, rows: int, full_rows: bool = False) -> Fraction:
    """The row-sampled alpha of ``triangle`` at pixel (x, y), exactly (the reference).

    >>> exact_row_sampled_alpha([[0, 0], [1, 0], [0, 1]], 0, 0, 2)
    Fraction(1, 2)
    >>> exact_row_sampled_alpha([[0, 0], [1, 0], [0, 1]], 0, 0, 3)
    Fraction(1, 2)
    >>> exact_row_sampled_alpha([[0, 0], [4, 0], [0, 1]], 1, 0, 2)  # lengths 1 and 0 on y = 1/4, 3/4
    Fraction(1, 2)
    >>> exact_area(np.array([[0, 0], [4, 0], [0, 1.0]]), 1, 0)
    Fraction(5, 8)
    """
    points = np.asarray(triangle, dtype=np.float64)
    vertices = [(Fraction(float(px)), Fraction(float(py))) for px, py in points]
    if (vertices[1][0] - vertices[0][0]) * (vertices[2][1] - vertices[0][1]) == \
            (vertices[1][1] - vertices[0][1]) * (vertices[2][0] - vertices[0][0]):
        return Fraction(0)
    if full_rows:
        return _cairo_alpha(points, x, y, rows)
    total = Fraction(0)
    for k in range(rows):
        section = _cross_section(vertices, y + Fraction(2 * k + 1, 2 * rows))
        if section is not None:
            total += max(Fraction(0), min(section[1], Fraction(x + 1)) - max(section[0], Fraction(x)))
    return total / rows


# -- the compiled oracle ----------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _side(v, num, den):  # type: ignore[no-untyped-def]
    """The sign of v - num / den exactly (num, den integers below 2**52, den > 0): v * den
    split into p + e exactly (Dekker's product), then p - num is exact (Sterbenz) where it
    matters."""
    p = v * den
    # Dekker: split v and den in halves of 26 bits
    c = 134217729.0 * v
    vh = c - (c - v)
    vl = v - vh
    c = 134217729.0 * den
    dh = c - (c - den)
    dl = den - dh
    e = ((vh * dh - p) + vh * dl + vl * dh) + vl * dl
    s = p - num
    if s != 0.0:
        return 1 if s > 0.0 else -1
    return 1 if e > 0.0 else (-1 if e < 0.0 else 0)


@numba.njit(cache=True)
def _section(tri, line, rows):  # type: ignore[no-untyped-def]
    """(xl, xr) of the triangle on the sample line y = (2 line + 1) / (2 rows), the edges
    active where y_top < y <= y_bottom, decided exactly; xl > xr when the line misses it."""
    lo = np.inf
    hi = -np.inf
    num = 2.0 * line + 1.0
    den = 2.0 * rows
    y = num / den
    for e in range(3):
        f = (e + 1) % 3
        ax, ay, bx, by = tri[e, 0], tri[e, 1], tri[f, 0], tri[f, 1]
        if ay == by:
            continue
        top = min(ay, by)
        bottom = max(ay, by)
        if _side(top, num, den) < 0 and _side(bottom, num, den) >= 0:
            x = ax + ((y - ay) / (by - ay)) * (bx - ax)
            # the line lies within the edge's y-range: keep x within its x-range
            x = min(max(x, min(ax, bx)), max(ax, bx))
            lo = min(lo, x)
            hi = max(hi, x)
    return lo, hi


@numba.njit(cache=True)
def _row_alphas(tri, j, rows, width, acc):  # type: ignore[no-untyped-def]
    """The row's alphas (its rows sample lines) into acc[i0:i1]; returns (i0, i1)."""
    lo = np.inf
    hi = -np.inf
    for k in range(rows):
        a, b = _section(tri, j * rows + k, rows)
        lo = min(lo, a)
        hi = max(hi, b)
    if not lo <= hi:
        return 0, 0
    i0 = max(int(math.floor(lo)), 0)
    i1 = min(int(math.floor(hi)) + 1, width)
    for i in range(i0, i1):
        acc[i] = 0.0
    for k in range(rows):
        a, b = _section(tri, j * rows + k, rows)
        if not a <= b:
            continue
        for i in range(max(int(math.floor(a)), i0), min(int(math.floor(b)) + 1, i1)):
            acc[i] += max(0.0, min(b, i + 1.0) - max(a, float(i))) / rows
    return i0, i1


# -- cairo's arithmetic, on its 24.8 input grid (full_rows) ------------------------------------


@numba.njit(cache=True, inline="always")
def _tdiv(a, b):  # type: ignore[no-untyped-def]
    """C's integer division (truncating toward zero) and remainder."""
    q = abs(a) // abs(b)
    if (a < 0) != (b < 0):
        q = -q
    return q, a - q * b


@numba.njit(cache=True)
def _edge_x(px1, py1, ex, ey, k):  # type: ignore[no-untyped-def]
    """An edge's x at sub-row k's centre as cairo holds it: (quo, rem), x = quo + rem/ey in
    1/256 px, rem in [0, ey) (``polygon_add_edge``, then ``step`` k times: exact)."""
    tmp = ((2 * k + 1) * 256 - py1 * 30) * ex
    quo = tmp // ey
    return quo + px1, tmp - quo * ey


@numba.njit(cache=True)
def _cairo_edge(pf, e, rows):  # type: ignore[no-untyped-def]
    """Edge e of the fixed-point triangle pf as cairo's polygon_add_edge makes it:
    (px1, py1, ex, ey, ytop, ybot, dir), ey = 0 for an edge cairo drops."""
    f = (e + 1) % 3
    ax, ay, bx, by = pf[e, 0], pf[e, 1], pf[f, 0], pf[f, 1]
    direction = 1
    if by < ay:
        ax, ay, bx, by = bx, by, ax, ay
        direction = -1
    ytop = (rows * ay + 128) >> 8  # INPUT_TO_GRID_general
    ybot = (rows * by + 128) >> 8
    if ybot <= ytop:
        return ax, ay, 0, 0, ytop, ybot, direction
    return ax, ay, (bx - ax) * 256, (by - ay) * rows * 512, ytop, ybot, direction


@numba.njit(cache=True)
def _is_full_row(edges, top, rows, now):  # type: ignore[no-untyped-def]
    """can_do_full_row for the pixel row starting at sub-row ``top``: no edge starts or
    ends inside it, two edges span it, and one full step on their cells keep their order.
    ``now`` gets the two edges' x at the row's first sub-row (their order)."""
    n_full = 0
    for e in range(3):
        if edges[e, 3] == 0:
            continue
        if top < edges[e, 4] < top + rows or top < edges[e, 5] < top + rows:
            return False
        if edges[e, 4] <= top and edges[e, 5] >= top + rows:
            n_full += 1
    if n_full != 2:
        return False
    cells = np.zeros(2, dtype=np.int64)
    m = 0
    for e in range(3):
        if edges[e, 3] == 0 or not (edges[e, 4] <= top and edges[e, 5] >= top + rows):
            continue
        q, r = _edge_x(edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3], top + rows)
        cells[m] = q + (1 if r >= edges[e, 3] // 2 else 0)
        q0, r0 = _edge_x(edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3], top)
        now[m] = q0 + r0 / edges[e, 3]
        m += 1
    return not ((cells[0] > cells[1]) if now[0] <= now[1] else (cells[1] > cells[0]))


@numba.njit(cache=True)
def _cairo_row(pf, j, rows, width, acc, cover, uncovered):  # type: ignore[no-untyped-def]
    """cairo's alphas of pixel row j of one triangle (fixed 24.8 vertices pf) into acc[0:width]:
    a full row (``full_row``, ``cell_list_render_edge``) or ``rows`` sub-rows (``sub_row``,
    ``cell_list_add_subspan``), in cairo's integers; cells accumulated as ``blit_a8`` reads them."""
    for i in range(width + 2):
        cover[i] = 0
        uncovered[i] = 0
    edges = np.zeros((3, 7), dtype=np.int64)
    for e in range(3):
        r = _cairo_edge(pf, e, rows)
        for m in range(7):
            edges[e, m] = r[m]
    top = rows * j
    now = np.zeros(2)
    full = _is_full_row(edges, top, rows, now)
    if full:
        # full_row: the left edge adds, the right one takes away
        m = 0
        for e in range(3):
            if edges[e, 3] == 0 or not (edges[e, 4] <= top and edges[e, 5] >= top + rows):
                continue
            left = now[m] <= now[1 - m] if m == 0 else now[1] < now[0]
            _render_edge(edges[e], 1 if left else -1, top, rows, width, cover, uncovered)
            m += 1
    else:
        xs = np.zeros(3, dtype=np.int64)
        ds = np.zeros(3, dtype=np.int64)
        for k in range(top, top + rows):
            n = 0
            for e in range(3):
                if edges[e, 3] != 0 and edges[e, 4] <= k < edges[e, 5]:
                    q, r = _edge_x(edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3], k)
                    xs[n] = q + (1 if r >= edges[e, 3] // 2 else 0)  # edge->cell
                    ds[n] = edges[e, 6]
                    n += 1
            if n == 2:
                _add_subspan(min(xs[0], xs[1]), max(xs[0], xs[1]), width, cover, uncovered)
    # blit_a8: cover accumulates the covered heights, area = cover * 2 GRID_X - uncovered
    total = cover[0]  # what lies left of the viewport
    for i in range(width):
        total += cover[i + 1]
        area = total * 512 - uncovered[i + 1]
        acc[i] = area / (512.0 * rows)


@numba.njit(cache=True)
def _cell(i, width):  # type: ignore[no-untyped-def]
    """Cells -1 .. width (index + 1): left of the viewport gathers into -1, right is dropped."""
    return min(max(i, -1), width) + 1


@numba.njit(cache=True)
def _add_subspan(x1, x2, width, cover, uncovered):  # type: ignore[no-untyped-def]
    """cell_list_add_subspan: [x1, x2) in 1/256 px on one sub-row."""
    if x1 == x2:
        return
    ix1, fx1 = x1 >> 8, x1 & 255
    ix2, fx2 = x2 >> 8, x2 & 255
    if ix1 != ix2:
        uncovered[_cell(ix1, width)] += 2 * fx1
        cover[_cell(ix1, width)] += 1
        uncovered[_cell(ix2, width)] -= 2 * fx2
        cover[_cell(ix2, width)] -= 1
    else:
        uncovered[_cell(ix1, width)] += 2 * (fx1 - fx2)


@numba.njit(cache=True)
def _render_edge(edge, sign, top, rows, width, cover, uncovered):  # type: ignore[no-untyped-def]
    """cell_list_render_edge: one edge over a full pixel row, in cairo's integers."""
    px1, py1, ex, ey = edge[0], edge[1], edge[2], edge[3]
    if ex == 0:  # vertical (dy == 0 in cairo's words): x = cell, no stepping
        ix, fx = px1 >> 8, px1 & 255
        cover[_cell(ix, width)] += sign * rows
        uncovered[_cell(ix, width)] += sign * 2 * fx * rows
        return
    hq = _tdiv(_tdiv(ex * 512, ey)[0], 2)[0]
    hr = _tdiv(_tdiv(ex * 512, ey)[1], 2)[0]
    x1q, x1r = _edge_x(px1, py1, ex, ey, top)
    x2q, x2r = _edge_x(px1, py1, ex, ey, top + rows)
    # step back from the sample location (half a sub-row) to the pixel row's edge
    x1q, x1r = x1q - hq, x1r - hr
    if x1r < 0:
        x1q, x1r = x1q - 1, x1r + ey
    elif x1r >= ey:
        x1q, x1r = x1q + 1, x1r - ey
    x2q, x2r = x2q - hq, x2r - hr
    if x2r < 0:
        x2q, x2r = x2q - 1, x2r + ey
    elif x2r >= ey:
        x2q, x2r = x2q + 1, x2r - ey
    ix1, fx1 = x1q >> 8, x1q & 255
    ix2, fx2 = x2q >> 8, x2q & 255
    if ix1 == ix2:
        cover[_cell(ix1, width)] += sign * rows
        uncovered[_cell(ix1, width)] += sign * (fx1 + fx2) * rows
        return
    if ix2 < ix1:
        ix1, ix2, fx1, fx2 = ix2, ix1, fx2, fx1
        x1q, x1r, x2q, x2r = x2q, x2r, x1q, x1r
    dx = (x2q - x1q) * ey + (x2r - x1r)
    tmp = ((ix1 + 1) * 256 * ey - (x1q * ey + x1r)) * rows
    y = tmp // dx
    uncovered[_cell(ix1, width)] += sign * y * (256 + fx1)
    cover[_cell(ix1, width)] += sign * y
    y_last = y
    step = rows * 256 * ey
    for c in range(ix1 + 1, ix2):
        y = (tmp + (c - ix1) * step) // dx
        uncovered[_cell(c, width)] += sign * (y - y_last) * 256
        cover[_cell(c, width)] += sign * (y - y_last)
        y_last = y
    uncovered[_cell(ix2, width)] += sign * (rows - y_last) * fx2
    cover[_cell(ix2, width)] += sign * (rows - y_last)


@numba.njit(cache=True)
def _row_kernel(positions, fixed, active, width, height, rows, full_rows, write,  # type: ignore[no-untyped-def]
                out_t, out_y, out_x0, out_x1, out_alpha):
    """Spans and alphas (write) or only their counts (not write): (spans, pixels)."""
    acc = np.zeros(width + 1)
    cover = np.zeros(width + 2, dtype=np.int64)
    uncovered = np.zeros(width + 2, dtype=np.int64)
    spans = 0
    pixels = 0
    for t in range(positions.shape[0]):
        if not active[t]:
            continue
        tri = positions[t]
        j0 = max(int(math.floor(min(tri[0, 1], tri[1, 1], tri[2, 1]))), 0)
        j1 = min(int(math.ceil(max(tri[0, 1], tri[1, 1], tri[2, 1]))), height)
        for j in range(j0, j1):
            if full_rows:
                _cairo_row(fixed[t], j, rows, width, acc, cover, uncovered)
                i0, i1 = 0, width
            else:
                i0, i1 = _row_alphas(tri, j, rows, width, acc)
            while i0 < i1 and acc[i0] <= 0.0:  # trim the zeros at both ends
                i0 += 1
            while i1 > i0 and acc[i1 - 1] <= 0.0:
                i1 -= 1
            if i0 >= i1:
                continue
            if write:
                out_t[spans] = t
                out_y[spans] = j
                out_x0[spans] = i0
                out_x1[spans] = i1
                for i in range(i0, i1):
                    out_alpha[pixels + i - i0] = min(acc[i], 1.0)
            pixels += i1 - i0
            spans += 1
    return spans, pixels


def row_sampled_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The oracle of a row-sampled area convention (``Convention(coverage="area", rows=n)``):
    per (triangle, pixel), the mean of its n cross-sections at the sub-row centre lines
    (with ``full_rows``: cairo's analytic full rows, module docstring), unquantised.

    Input precision, snapping and culling are the convention's; zero-area and non-finite
    triangles cover nothing.

    >>> c = row_sampled_coverage(Scene(4, 1, [[[0, 0], [4, 0], [0, 1]]]), Convention(coverage="area", rows=2))
    >>> c.x0.tolist(), c.x1.tolist(), c.alpha.tolist()
    ([0], [3], [1.0, 0.5, 0.5])
    """
    rows = convention.rows
    if rows <= 0:
        raise ValueError("row_sampled_coverage needs a convention with rows > 0")
    positions = np.ascontiguousarray(convention.snap(scene.positions), dtype=np.float64)
    sign = orientation(positions)
    active = sign != 0
    if convention.cull != "none":
        active &= sign != (1 if convention.cull == "cw" else -1)
    # cairo's hybrid is defined on its 24.8 input (_cairo_fixed_from_double: to nearest, ties to even)
    fixed = np.zeros(positions.shape, dtype=np.int64)
    if convention.full_rows:
        finite = np.all(np.isfinite(positions), axis=(1, 2)) & np.all(np.abs(positions) < 2.0**20, axis=(1, 2))
        active &= finite
        fixed[finite] = np.rint(positions[finite] * 256.0).astype(np.int64)
    args = (positions, fixed, active, int(scene.width), int(scene.height), int(rows), bool(convention.full_rows))
    empty_i, empty_f = np.empty(0, dtype=np.int64), np.empty(0)
    spans, pixels = _row_kernel(*args, False, empty_i, empty_i, empty_i, empty_i, empty_f)
    out = [np.empty(spans, dtype=np.int64) for _ in range(4)]
    alpha = np.empty(pixels)
    spans, pixels = _row_kernel(*args, True, *out, alpha)  # type: ignore[call-arg]
    triangle, y, x0, x1 = (o[:spans] for o in out)
    return Coverage(triangle, y, x0, x1, alpha=alpha[:pixels])
