"""Row-sampled area coverage of paths: cairo's anti-aliasing model beyond triangles.

:mod:`harness.oracle.aa_models` defines the model on triangles; a path is where cairo's
scan converter (``src/cairo-tor-scan-converter.c``) really works, on every edge of the
polygon at once under the fill rule's winding mask (``glitter_scan_converter_render``:
``winding_mask`` ~0 for nonzero, 1 for even-odd). Two conventions:

* ``Convention(coverage="area", rows=n)``: the alpha of a path at pixel (i, j) is the mean
  over the n sub-row centre lines ``y_k = j + (k + 1/2)/n`` of the length of
  ``{x in [i, i+1] : rule(winding(x, y_k))}`` -- the path's cross-section on each line,
  exact along x. An edge counts on the line where ``y_top < y_k <= y_bottom`` (as
  :func:`harness.oracle.aa_models.exact_row_sampled_alpha`), so a line through a vertex
  sees each crossing once. :func:`exact_row_sampled_path_alpha` is the rational reference;
  the compiled oracle computes crossings in float within :func:`row_sampled_path_bound`
  of it, and the checks decide what the bound leaves open by the reference.
* ``Convention(coverage="area", rows=15, full_rows=True, input="fixed8")``: cairo's hybrid
  on its 24.8 input, its integer procedure transcribed whole (the compiled kernel run
  uncompiled is the reference, exact in Python's integers):

  - ``polygon_add_edge``: edges rounded to sub-rows (``INPUT_TO_GRID_Y``: ``ytop =
    floor(15 y + 1/2)`` in 1/256 units), clamped to the surface rows, horizontal ones
    dropped; x as a quotient and remainder at the first sub-row's centre, its step per
    sub-row (``dxdy``) and per pixel row (``dxdy_full``, only for edges at least a row
    tall), ``cell`` = x rounded half up to 1/256 px;
  - ``glitter_scan_converter_render``: per pixel row the edges starting in it bucketed by
    sub-row (each bucket in the order the edges were added), merged into the active list
    by cairo's ``sort_edges`` / ``merge_sorted_edges`` (their tie order is theirs, and it
    decides ``can_do_full_row`` when two edges share a cell);
  - a full row (``full_row``, ``cell_list_render_edge``) where no edge starts after the
    row's first sub-row, none ends inside it and one full step keeps the list in order;
    otherwise 15 ``sub_row`` passes, each stepping every edge, re-sorting by insertion and
    adding the spans where ``winding & mask`` is nonzero (``cell_list_add_subspan``);
  - ``blit_a8``'s cells: the row's coverage is the running ``covered_height`` times 512
    less the ``uncovered_area``, out of ``2 * 256 * 15``.

  Not modelled, as for triangles: cairo clips the polygon to the surface's sides first
  (``cairo-polygon.c``; a path leaving the viewport sideways), its cells are 16-bit (a
  sliver's negative coverage wraps) and its 8-bit rounding is the convention's levels'.
  The arithmetic is cairo's int64 arithmetic, overflow included: beyond about 2**15 px
  its intermediate products (``tmp *= Ex`` in ``polygon_add_edge``, ``dx`` in
  ``cell_list_render_edge``) wrap, and so do ours, which is how cairo is matched byte for
  byte on triangles of 4e6 px (tests). The hybrid is defined within cairo's own range,
  |coordinates| < 2**23 px (its 24.8 fixed point in 32 bits); a path reaching further
  covers nothing under it.

A one-triangle path gives exactly :func:`harness.oracle.aa_models.row_sampled_coverage`'s
alphas for that triangle (tests/oracle/test_row_sampled_paths.py).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene

__all__ = ["row_sampled_path_coverage", "exact_row_sampled_path_alpha", "row_sampled_path_bound", "HYBRID_LIMIT"]

# the hybrid's coordinates: cairo's 24.8 fixed point in 32 bits (its int64 products wrap
# beyond 2**15 px as cairo's do)
HYBRID_LIMIT = 2.0**23
_BIG = np.int64(2**62)  # the active list's tail sentinel (cairo: INT_MAX)
_SMALL = np.int64(-(2**62))  # its head sentinel and "no span started" (INT_MIN)


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



# -- the paths' edges ----------------------------------------------------------------------------


def _path_edges(scene: PathScene, vertices: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Per path, its closed contours' edges as an (E, 4) array of (ax, ay, bx, by) in the
    order the contours and their vertices are given (cairo adds them in path order)."""
    ends = np.cumsum(scene.contour_sizes)
    starts = ends - scene.contour_sizes
    per_path: list[list[NDArray[np.float64]]] = [[] for _ in range(len(scene))]
    for c in range(scene.contour_sizes.size):
        ring = vertices[starts[c]:ends[c]]
        if ring.shape[0] < 2:
            continue
        per_path[int(scene.contour_path[c])].append(np.concatenate([ring, np.roll(ring, -1, axis=0)], axis=1))
    return [np.concatenate(e) if e else np.zeros((0, 4)) for e in per_path]


def _sample_line(j: int, k: int, rows: int) -> Fraction:
    return Fraction(2 * (j * rows + k) + 1, 2 * rows)


# -- the plain row-sampled model: reference ------------------------------------------------------


def _fill(winding: int, evenodd: bool) -> bool:
    return (winding & 1) == 1 if evenodd else winding != 0


def exact_row_sampled_path_alpha(contours: Sequence[ArrayLike], fill_rule: str, x: int, y: int, rows: int,
                                 full_rows: bool = False, surface: tuple[int, int] | None = None) -> Fraction:
    """The row-sampled alpha of one path at pixel (x, y), exactly (the reference).

    Parameters
    ----------
    contours : list of (V, 2) array_like
        The path's closed contours, as the convention's snapping leaves them.
    fill_rule : {"nonzero", "evenodd"}
    x, y : int
        The pixel.
    rows : int
        Sample lines per pixel row.
    full_rows : bool
        cairo's hybrid (the module docstring): its integer procedure's cell area.
    surface : (int, int), optional
        The hybrid's surface (width, height), which cairo clips the polygon to: the
        scene's viewport, as the oracle has it; None: unclipped.

    Returns
    -------
    Fraction

    >>> square = [[[0, 0], [2, 0], [2, 2], [0, 2]]]
    >>> exact_row_sampled_path_alpha(square, "nonzero", 0, 0, 4)
    Fraction(1, 1)
    >>> bow = [[[0, 0], [1, 1], [1, 0], [0, 1]]]  # a bow tie: each half covers half the rows' length
    >>> exact_row_sampled_path_alpha(bow, "nonzero", 0, 0, 2)
    Fraction(1, 2)
    """
    arrays = [np.asarray(c, dtype=np.float64).reshape(-1, 2) for c in contours]
    if full_rows:
        return _cairo_path_alpha(arrays, fill_rule, x, y, rows, surface)
    edges = [(Fraction(float(a[0])), Fraction(float(a[1])), Fraction(float(b[0])), Fraction(float(b[1])))
             for ring in arrays if ring.shape[0] >= 2 for a, b in zip(ring, np.roll(ring, -1, axis=0), strict=True)]
    evenodd = fill_rule == "evenodd"
    total = Fraction(0)
    left, right = Fraction(x), Fraction(x + 1)
    for k in range(rows):
        line = _sample_line(y, k, rows)
        crossings: list[tuple[Fraction, int]] = []
        for ax, ay, bx, by in edges:
            if ay != by and min(ay, by) < line <= max(ay, by):  # the sub-rows [ytop, ybot): half open
                crossings.append((ax + (line - ay) * (bx - ax) / (by - ay), 1 if by > ay else -1))
        crossings.sort()
        winding = 0
        for (x0, d), (x1, _) in zip(crossings, crossings[1:], strict=False):
            winding += d
            if _fill(winding, evenodd):
                total += max(Fraction(0), min(x1, right) - max(x0, left))
    return total / rows


# -- the plain row-sampled model: compiled -------------------------------------------------------


@numba.njit(cache=True)
def _plain_rows(edges, j0, j1, width, rows, evenodd, acc, spans_y, spans_x0, spans_x1, alpha, n_spans,  # type: ignore[no-untyped-def]
                n_pixels, write):
    """The path's rows j0 .. j1-1: per row the n sample lines' cross-sections summed into
    acc, then spans of nonzero alphas (written when ``write``); returns the new counts."""
    m = edges.shape[0]
    xs = np.empty(m)
    ds = np.empty(m, dtype=np.int64)
    den = 2.0 * rows
    for j in range(j0, j1):
        lo = width
        hi = 0
        for k in range(rows):
            num = 2.0 * (j * rows + k) + 1.0
            line = num / den
            n = 0
            for e in range(m):
                ax, ay, bx, by = edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3]
                if ay == by:
                    continue
                top = min(ay, by)
                bottom = max(ay, by)
                if _side(top, num, den) < 0 and _side(bottom, num, den) >= 0:
                    x = ax + ((line - ay) / (by - ay)) * (bx - ax)
                    xs[n] = min(max(x, min(ax, bx)), max(ax, bx))
                    ds[n] = 1 if by > ay else -1
                    n += 1
            if n < 2:
                continue
            order = np.argsort(xs[:n], kind="mergesort")
            winding = 0
            for q in range(n - 1):
                winding += ds[order[q]]
                inside = (winding & 1) == 1 if evenodd else winding != 0
                if not inside:
                    continue
                a = max(xs[order[q]], 0.0)
                b = min(xs[order[q + 1]], float(width))
                if not a < b:
                    continue
                i0 = int(math.floor(a))
                i1 = min(int(math.floor(b)) + 1, width)
                lo = min(lo, i0)
                hi = max(hi, i1)
                for i in range(i0, i1):
                    acc[i] += (min(b, i + 1.0) - max(a, float(i))) / rows
        while lo < hi and acc[lo] <= 0.0:  # trim the pixels a crossing only touched
            lo += 1
        while hi > lo and acc[hi - 1] <= 0.0:
            hi -= 1
        if lo >= hi:  # (the trimmed pixels hold exactly 0: acc is clean for the next row)
            continue
        if write:
            spans_y[n_spans] = j
            spans_x0[n_spans] = lo
            spans_x1[n_spans] = hi
            for i in range(lo, hi):
                alpha[n_pixels + i - lo] = min(acc[i], 1.0)
        for i in range(lo, hi):  # acc is all zeros again for the next row
            acc[i] = 0.0
        n_spans += 1
        n_pixels += hi - lo
    return n_spans, n_pixels


def row_sampled_path_bound(edges: NDArray[np.float64], width: int, height: int, rows: int) -> float:
    """A proven bound on |compiled alpha - exact alpha| of the plain row-sampled model at
    any pixel of a path with these edges.

    Each crossing ``x = ax + ((y - ay) / (by - ay)) (bx - ax)`` is within 4 ulps of
    ``M = max(|coordinates|, width, height) + 1`` of its exact value (the quotient and the
    product within an ulp each of values at most 1 and |bx - ax| <= 2M, the sum within
    one of M; the clamp into the edge's x range only moves it toward the exact value);
    clipping to [i, i + 1] and the subtraction add 2 more ulps of M per end. A line's
    cross-section in a pixel has at most E ends (E edges), so each line's length is within
    ``E 6 ulp(M) <= 6 E M 2**-52``; the mean of ``rows`` such lengths with its ``rows``
    float additions of values at most 1 adds ``rows 2**-53``.

    >>> row_sampled_path_bound(np.array([[0, 0, 1, 1.0]]), 4, 4, 15) < 1e-13
    True
    """
    finite = edges[np.all(np.isfinite(edges), axis=1)]
    magnitude = float(np.abs(finite).max(initial=0.0)) + max(width, height) + 1.0
    return float(min(1.0, (6.0 * edges.shape[0] * magnitude * 2.0**-52 + rows * 2.0**-53) * (1.0 + 2.0**-40)))


# -- cairo's hybrid: the transcribed procedure ---------------------------------------------------


def _clip_one(p1x: int, p1y: int, p2x: int, p2y: int, top: int, bottom: int,  # noqa: C901 - cairo's branches, one by one
              direction: int, xmax: int, ymax: int) -> list[tuple[int, ...]]:
    """``_add_clipped_edge`` (cairo-polygon.c) for one edge and the surface box [0, xmax] x
    [0, ymax] (24.8): the edges cairo adds, in order -- (p1x, p1y, p2x, p2y, top, bottom,
    dir), the sides of the box standing in for the parts beyond them."""
    if top >= ymax or bottom <= 0:
        return []
    left_side = (0, 0, 0, ymax)  # limits->p1 to bot_left
    right_side = (xmax, 0, xmax, ymax)  # top_right to limits->p2
    top_y, bot_y = max(top, 0), min(bottom, ymax)
    pleft, pright = min(p1x, p2x), max(p1x, p2x)
    if pleft >= 0 and pright <= xmax:
        return [(p1x, p1y, p2x, p2y, top_y, bot_y, direction)]
    if pright <= 0:
        return [(*left_side, top_y, bot_y, direction)]
    if xmax <= pleft:
        return [(*right_side, top_y, bot_y, direction)]

    def y_for_x(x: int) -> int:  # _cairo_edge_compute_intersection_y_for_x: C's truncating division
        if x == p1x:
            return p1y
        if x == p2x:
            return p2y
        return p1y + _c_quotient((x - p1x) * (p2y - p1y), p2x - p1x)

    def x_for_y(y: int) -> int:
        if y == p1y:
            return p1x
        if y == p2y:
            return p2x
        return p1x + _c_quotient((y - p1y) * (p2x - p1x), p2y - p1y)

    out: list[tuple[int, ...]] = []
    if (p1x <= p2x) == (p1y <= p2y):  # top left to bottom right
        left_y = top_y
        if pleft < 0:
            left_y = y_for_x(0)
            if x_for_y(left_y) < 0:
                left_y += 1
        left_y = min(left_y, bot_y)
        if top_y < left_y:
            out.append((*left_side, top_y, left_y, direction))
            top_y = left_y
        right_y = bot_y
        if pright > xmax:
            right_y = y_for_x(xmax)
            if x_for_y(right_y) > xmax:
                right_y -= 1
        right_y = max(right_y, top_y)
        if bot_y > right_y:
            out.append((*right_side, right_y, bot_y, direction))
            bot_y = right_y
    else:
        right_y = top_y
        if pright > xmax:
            right_y = y_for_x(xmax)
            if x_for_y(right_y) > xmax:
                right_y += 1
        right_y = min(right_y, bot_y)
        if top_y < right_y:
            out.append((*right_side, top_y, right_y, direction))
            top_y = right_y
        left_y = bot_y
        if pleft < 0:
            left_y = y_for_x(0)
            if x_for_y(left_y) < 0:
                left_y -= 1
        left_y = max(left_y, top_y)
        if bot_y > left_y:
            out.append((*left_side, left_y, bot_y, direction))
            bot_y = left_y
    if top_y != bot_y:
        out.append((p1x, p1y, p2x, p2y, top_y, bot_y, direction))
    return out


def _c_quotient(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return -q if (a < 0) != (b < 0) else q


def cairo_polygon(edges: NDArray[np.float64], width: int, height: int, clip: bool = True) -> NDArray[np.int64]:
    """The polygon cairo's scan converter receives for a path's edges (E, 4) on a width x
    height surface: each edge in 24.8 (``_cairo_fixed_from_double``: to nearest, ties to
    even), horizontal ones dropped, running downward with ``dir`` saying which way the
    path went, and (``clip``) clipped to the surface box where it leaves it
    (``_add_clipped_edge``: the box's sides stand in for the parts beyond, at heights
    cairo's truncating intersections give). An (E', 8) int64 table (p1x, p1y, p2x, p2y, top, bottom, dir,
    edge index), in the order added.

    >>> cairo_polygon(np.array([[-1.0, 0.0, 1.0, 2.0]]), 4, 4).tolist()  # crosses the left side at y = 1
    [[0, 0, 0, 1024, 0, 256, 1, 0], [-256, 0, 256, 512, 256, 512, 1, 0]]
    """
    fixed = np.rint(edges * 256.0).astype(np.int64)
    xmax, ymax = width * 256, height * 256
    rows: list[tuple[int, ...]] = []
    for index, (ax, ay, bx, by) in enumerate(fixed.tolist()):
        if ay == by:
            continue
        direction = 1
        if ay > by:  # _cairo_polygon_add_edge: the edge runs downward, dir says which way the path went
            ax, ay, bx, by, direction = bx, by, ax, ay, -1
        if not clip:
            rows.append((ax, ay, bx, by, ay, by, direction, index))
            continue
        rows.extend((*clipped, index) for clipped in _clip_one(ax, ay, bx, by, ay, by, direction, xmax, ymax))
    return np.array(rows, dtype=np.int64).reshape(-1, 8)


def _cairo_edges(polygon: NDArray[np.int64], height: int, rows: int) -> NDArray[np.int64]:
    """polygon_add_edge (cairo-tor-scan-converter.c) for every edge of :func:`cairo_polygon`'s
    table: an (E', 12) int64 table of the edges the scan converter keeps, in the order
    added -- (ytop, height_left, dir, cell, x.quo, x.rem, dxdy.quo, dxdy.rem,
    dxdy_full.quo, dxdy_full.rem, dy, edge index) -- with C's truncating / and % where
    cairo uses them, in int64 as cairo's C (wrapping where cairo's products overflow).

    >>> polygon = cairo_polygon(np.array([[0.0, 0.0, 1.0, 1.0], [1.0, 1.0, 1.0, 0.0]]), 2, 1)
    >>> _cairo_edges(polygon, 1, 15)[:, :4].tolist()
    [[0, 15, 1, 9], [0, 15, -1, 256]]
    """
    p1x, p1y, p2x, p2y, top, bottom, direction, index = (polygon[:, c] for c in range(8))
    ytop = np.maximum((rows * top + 128) >> 8, 0)  # INPUT_TO_GRID_Y, clamped to the surface's rows
    ybot = np.minimum((rows * bottom + 128) >> 8, height * rows)
    keep = np.flatnonzero(ybot > ytop)  # sub-row-thin edges are dropped
    p1x, p1y, p2x, p2y, ytop, ybot, direction, index = (v[keep] for v in (p1x, p1y, p2x, p2y, ytop, ybot, direction,
                                                                          index))
    height_left = ybot - ytop
    vertical = p1x == p2x
    ex = (p2x - p1x) * 256  # GRID_X
    ey = np.where(vertical, 1, (p2y - p1y) * rows * 512)  # GRID_Y * (2 << GLITTER_INPUT_BITS)
    dq, dr = _c_divmod(ex * 512, ey)
    quo, rem = np.divmod((((2 * ytop + 1) << 8) - p1y * rows * 2) * ex, ey)  # C's quotient, then normalised: floor
    quo = quo + p1x
    fq, fr = _c_divmod(ex * (2 * rows << 8), ey)
    tall = height_left >= rows  # dxdy_full only for edges at least a row tall
    fq, fr = np.where(tall, fq, 0), np.where(tall, fr, 0)
    cell = quo + (rem >= ey // 2)
    zero = np.zeros_like(quo)
    columns = [ytop, height_left, direction,
               np.where(vertical, p1x, cell), np.where(vertical, p1x, quo), np.where(vertical, zero, rem),
               np.where(vertical, zero, dq), np.where(vertical, zero, dr), np.where(vertical, zero, fq),
               np.where(vertical, zero, fr), np.where(vertical, zero, ey), index]
    return np.ascontiguousarray(np.stack(columns, axis=1).astype(np.int64))


def _c_divmod(a: NDArray[Any], b: NDArray[Any]) -> tuple[NDArray[Any], NDArray[Any]]:
    """C's integer division: the quotient truncated toward zero, the remainder a - q b."""
    q = np.abs(a) // np.abs(b)
    q = np.where((a < 0) != (b < 0), -q, q)
    return q, a - q * b


@numba.njit(cache=True, inline="always")
def _take(src, i, limit, cell, out, n):  # type: ignore[no-untyped-def]
    """Copy src[i:] to out[n:] while its cells are at most ``limit``: (i, n) after."""
    while i < src.size and cell[src[i]] <= limit:
        out[n] = src[i]
        n += 1
        i += 1
    return i, n


@numba.njit(cache=True)
def _merge(a, b, cell):  # type: ignore[no-untyped-def]
    """cairo's merge_sorted_edges of two sorted id lists (b not empty): its tie order."""
    out = np.empty(a.size + b.size, dtype=np.int64)
    ia = 0
    ib = 0
    n = 0
    from_a = a.size > 0 and cell[a[0]] <= cell[b[0]]
    while True:
        if from_a:  # a's run up to b's head (ties taken from the list being walked)
            ia, n = _take(a, ia, cell[b[ib]], cell, out, n)
            if ia == a.size:
                ib, n = _take(b, ib, _BIG, cell, out, n)
                return out
        else:
            ib, n = _take(b, ib, cell[a[ia]] if ia < a.size else _BIG, cell, out, n)
            if ib == b.size:
                ia, n = _take(a, ia, _BIG, cell, out, n)
                return out
        from_a = not from_a


@numba.njit(cache=True)
def _sort_edges(ids, cell):  # type: ignore[no-untyped-def]
    """cairo's sort_edges: a bottom-up merge sort (pairs, then runs doubling, aligned on
    the list's start) with merge_sorted_edges' tie order."""
    runs = ids.copy()
    width = 1
    n = ids.size
    while width < n:
        for start in range(0, n - width, 2 * width):
            stop = min(start + 2 * width, n)
            merged = _merge(runs[start:start + width].copy(), runs[start + width:stop].copy(), cell)
            runs[start:stop] = merged
        width *= 2
    return runs


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
def _normalised(quo, rem, dy):  # type: ignore[no-untyped-def]
    if rem < 0:
        return quo - 1, rem + dy
    if rem >= dy:
        return quo + 1, rem - dy
    return quo, rem


@numba.njit(cache=True)
def _step(t, e, full):  # type: ignore[no-untyped-def]
    """step (a sub-row) or full_step (a pixel row) of edge e in table t."""
    dy = t[e, 10]
    if dy == 0:
        return
    if full:
        quo, rem = _normalised(t[e, 4] + t[e, 8], t[e, 5] + t[e, 9], dy)
    else:
        quo, rem = _normalised(t[e, 4] + t[e, 6], t[e, 5] + t[e, 7], dy)
    t[e, 4] = quo
    t[e, 5] = rem
    t[e, 3] = quo + (1 if rem >= dy // 2 else 0)


@numba.njit(cache=True)
def _tdiv(a, b):  # type: ignore[no-untyped-def]
    q = abs(a) // abs(b)
    if (a < 0) != (b < 0):
        q = -q
    return q


@numba.njit(cache=True)
def _render_edge(t, e, sign, rows, width, cover, uncovered):  # type: ignore[no-untyped-def]
    """cell_list_render_edge: edge e over a full pixel row (and its full_step)."""
    dy = t[e, 10]
    x1q, x1r = t[e, 4], t[e, 5]
    _step(t, e, True)
    x2q, x2r = t[e, 4], t[e, 5]
    if dy != 0:  # step back from the sample location (half a sub-row) to the pixel row's edge
        hq = _tdiv(t[e, 6], 2)
        hr = _tdiv(t[e, 7], 2)
        x1q, x1r = _normalised(x1q - hq, x1r - hr, dy)
        x2q, x2r = _normalised(x2q - hq, x2r - hr, dy)
    ix1, fx1 = x1q >> 8, x1q & 255
    ix2, fx2 = x2q >> 8, x2q & 255
    if ix1 == ix2:
        cover[_cell(ix1, width)] += sign * rows
        uncovered[_cell(ix1, width)] += sign * (fx1 + fx2) * rows
        return
    if ix2 < ix1:
        ix1, ix2, fx1, fx2 = ix2, ix1, fx2, fx1
        x1q, x1r, x2q, x2r = x2q, x2r, x1q, x1r
    dx = (x2q - x1q) * dy + (x2r - x1r)
    # ((ix1 + 1) GRID_X dy - (x1.quo dy + x1.rem)) GRID_Y, grouped to stay within 64 bits
    tmp = (((ix1 + 1) * 256 - x1q) * dy - x1r) * rows
    yq = tmp // dx  # tmp, dx > 0: C's quotient
    yr = tmp - yq * dx
    uncovered[_cell(ix1, width)] += sign * yq * (256 + fx1)
    cover[_cell(ix1, width)] += sign * yq
    y_last = yq
    if ix1 + 1 < ix2:
        fq = rows * 256 * dy // dx
        fr = rows * 256 * dy - fq * dx
        for c in range(ix1 + 1, ix2):
            yq += fq
            yr += fr
            if yr >= dx:
                yq += 1
                yr -= dx
            uncovered[_cell(c, width)] += sign * (yq - y_last) * 256
            cover[_cell(c, width)] += sign * (yq - y_last)
            y_last = yq
    uncovered[_cell(ix2, width)] += sign * (rows - y_last) * fx2
    cover[_cell(ix2, width)] += sign * (rows - y_last)


@numba.njit(cache=True)
def _can_do_full_row(t, active, n, rows):  # type: ignore[no-untyped-def]
    """can_do_full_row: every active edge at least a row tall still, and one full step
    keeps the list in order (cells compared in list order)."""
    for q in range(n):
        if t[active[q], 1] < rows:
            return False
    prev = _SMALL
    for q in range(n):
        e = active[q]
        dy = t[e, 10]
        if dy != 0:
            quo, rem = _normalised(t[e, 4] + t[e, 8], t[e, 5] + t[e, 9], dy)
            cell = quo + (1 if rem >= dy // 2 else 0)
        else:
            cell = t[e, 3]
        if cell < prev:
            return False
        prev = cell
    return True


@numba.njit(cache=True)
def _full_row(t, active, n, mask, rows, width, cover, uncovered):  # type: ignore[no-untyped-def]
    """full_row: each run of edges from a left edge to where the masked winding returns to
    zero rendered analytically (left +1, right -1), the edges between full-stepped;
    returns the active list without the edges that end (dec)."""
    q = 0
    while q < n:
        left = active[q]
        t[left, 1] -= rows
        winding = t[left, 2]
        r = q + 1
        while r < n:
            right = active[r]
            t[right, 1] -= rows
            winding += t[right, 2]
            following = t[active[r + 1], 3] if r + 1 < n else _BIG
            if (winding & mask) == 0 and following != t[right, 3]:
                break
            _step(t, right, True)
            r += 1
        if r >= n:  # an unclosed winding (not a closed polygon): nothing more to pair
            break
        _render_edge(t, left, 1, rows, width, cover, uncovered)
        _render_edge(t, active[r], -1, rows, width, cover, uncovered)
        q = r + 1
    kept = 0
    for q in range(n):
        if t[active[q], 1] > 0:
            active[kept] = active[q]
            kept += 1
    return kept


@numba.njit(cache=True)
def _sub_row(t, active, n, mask, width, cover, uncovered):  # type: ignore[no-untyped-def]
    """sub_row: the spans where the masked winding is nonzero added at the edges' cells,
    every edge stepped one sub-row (dropped when it ends) and moved back by insertion where
    it now lies left of the last kept edge; returns the new list's length."""
    out = np.empty(n, dtype=np.int64)
    m = 0
    xstart = _SMALL
    prev_x = _SMALL
    winding = 0
    for q in range(n):
        e = active[q]
        following = t[active[q + 1], 3] if q + 1 < n else _BIG
        xend = t[e, 3]
        t[e, 1] -= 1
        if t[e, 1] > 0:
            _step(t, e, False)
            if t[e, 3] < prev_x:
                # pos = edge->prev, then back while edge->cell < pos->cell: insert after pos
                p = m - 2
                while p >= 0 and t[e, 3] < t[out[p], 3]:
                    p -= 1
                for s in range(m, p + 1, -1):
                    out[s] = out[s - 1]
                out[p + 1] = e
                m += 1
            else:
                prev_x = t[e, 3]
                out[m] = e
                m += 1
        winding += t[e, 2]
        if (winding & mask) == 0:
            if following != xend:
                _add_subspan(xstart, xend, width, cover, uncovered)
                xstart = _SMALL
        elif xstart == _SMALL:
            xstart = xend
    for q in range(m):
        active[q] = out[q]
    return m


@numba.njit(cache=True)
def _cairo_rows(t, mask, rows, width, height, cells, cover, uncovered, spans_p, primitive,  # type: ignore[no-untyped-def]  # noqa: C901 - cairo's render loop
                spans_y, spans_x0, spans_x1, alpha, numer, n_spans, n_pixels, write):
    """glitter_scan_converter_render over the viewport's pixel rows for one path's edge
    table t (in the order added): the row's alphas (unquantised: blit_a8's cell areas out
    of 2 * 256 * rows) as spans, and the cell areas themselves (``numer``: cairo's
    integers); returns the new counts."""
    count = t.shape[0]
    if count == 0:
        return n_spans, n_pixels
    order = np.argsort(t[:, 0], kind="mergesort")  # by first sub-row, in the order added
    active = np.empty(count, dtype=np.int64)
    n = 0
    nxt = 0
    last = 0
    for e in range(count):
        last = max(last, t[e, 0] + t[e, 1])
    for j in range(t[order[0], 0] // rows, min(height, (last + rows - 1) // rows)):
        first = j * rows
        begin = nxt
        while nxt < count and t[order[nxt], 0] < first + rows:
            nxt += 1
        max_sub = 0
        for q in range(begin, nxt):
            max_sub = max(max_sub, t[order[q], 0] - first)
        for c in range(width + 2):
            cover[c] = 0
            uncovered[c] = 0
        full = False
        if max_sub == 0:
            if nxt > begin:
                merged = _merge(active[:n].copy(), _sort_edges(order[begin:nxt].copy(), t[:, 3]), t[:, 3])
                n = merged.size
                active[:n] = merged
            if n == 0:
                continue
            full = _can_do_full_row(t, active, n, rows)
        if full:
            n = _full_row(t, active, n, mask, rows, width, cover, uncovered)
        else:
            for sub in range(rows):
                if max_sub > 0:
                    b = 0
                    bucket = np.empty(nxt - begin, dtype=np.int64)
                    for q in range(begin, nxt):
                        if t[order[q], 0] == first + sub:
                            bucket[b] = order[q]
                            b += 1
                    if b > 0:
                        merged = _merge(active[:n].copy(), _sort_edges(bucket[:b].copy(), t[:, 3]), t[:, 3])
                        n = merged.size
                        active[:n] = merged
                n = _sub_row(t, active, n, mask, width, cover, uncovered)
        # blit_a8: cover accumulates the covered heights, area = cover * 2 GRID_X - uncovered
        total = cover[0]  # what lies left of the viewport
        lo = width
        hi = 0
        for i in range(width):
            total += cover[i + 1]
            cells[i] = total * 512 - uncovered[i + 1]
            if cells[i] != 0:
                lo = min(lo, i)
                hi = i + 1
        if lo >= hi:
            continue
        if write:
            spans_p[n_spans] = primitive
            spans_y[n_spans] = j
            spans_x0[n_spans] = lo
            spans_x1[n_spans] = hi
            for i in range(lo, hi):
                alpha[n_pixels + i - lo] = min(cells[i] / (512.0 * rows), 1.0)
                numer[n_pixels + i - lo] = cells[i]
        n_spans += 1
        n_pixels += hi - lo
    return n_spans, n_pixels


def _cairo_path_alpha(contours: list[NDArray[np.float64]], fill_rule: str, x: int, y: int, rows: int,
                      surface: tuple[int, int] | None) -> Fraction:
    """cairo's hybrid alpha of one path at pixel (x, y), as the rational its cells hold
    (the integer procedure's cell area out of ``2 * 256 * rows``), on ``surface``."""
    rings = [c for c in contours if c.shape[0] >= 2]
    if not rings:
        return Fraction(0)
    edges = np.concatenate([np.concatenate([c, np.roll(c, -1, axis=0)], axis=1) for c in rings])
    if not (np.all(np.isfinite(edges)) and np.all(np.abs(edges) < HYBRID_LIMIT)):
        return Fraction(0)
    if surface is None:  # unclipped: the surface only needs to hold the pixel
        width, height, clip = x + 2, y + 1, False
    else:
        (width, height), clip = surface, True
    _, rows_y, x0, x1, _, numer = _cairo_spans(edges, np.zeros(edges.shape[0], dtype=np.int64), fill_rule, width,
                                               height, rows, clip)
    offsets = np.concatenate([[0], np.cumsum(x1 - x0)])
    for s in np.flatnonzero(rows_y == y):
        if x0[s] <= x < x1[s]:
            return Fraction(int(numer[offsets[s] + x - x0[s]]), 512 * rows)
    return Fraction(0)


def _cairo_spans(edges: NDArray[np.float64], owner: NDArray[np.int64], fill_rule: str, width: int, height: int,
                 rows: int, clip: bool = True) -> tuple[NDArray[np.int64], ...]:
    """The hybrid's spans of every primitive: ``edges`` (E, 4) grouped by ``owner`` (E,),
    ascending, clipped to the surface (``clip``); returns (primitive, y, x0, x1, alpha,
    cell areas)."""
    table = _cairo_edges(cairo_polygon(edges, width, height, clip), height, rows)
    owners = owner[table[:, 11]]
    starts = np.searchsorted(owners, np.unique(owners))
    bounds = np.append(starts, owners.size).astype(np.int64)
    ids = owners[starts] if owners.size else np.zeros(0, dtype=np.int64)
    mask = 1 if fill_rule == "evenodd" else -1
    empty_i, empty_f = np.empty(0, dtype=np.int64), np.empty(0)
    spans, pixels = _cairo_all(table.copy(), bounds, ids, mask, rows, width, height,
                               empty_i, empty_i, empty_i, empty_i, empty_f, empty_i, False)
    out = [np.empty(spans, dtype=np.int64) for _ in range(4)]
    alpha, numer = np.empty(pixels), np.empty(pixels, dtype=np.int64)
    _cairo_all(table, bounds, ids, mask, rows, width, height, *out, alpha, numer, True)  # type: ignore[call-arg]
    return (*out, alpha, numer)


@numba.njit(cache=True)
def _cairo_all(table, bounds, ids, mask, rows, width, height, spans_p, spans_y, spans_x0, spans_x1,  # type: ignore[no-untyped-def]
               alpha, numer, write):
    """:func:`_cairo_rows` for each primitive's rows of the edge table (bounds[k] ..
    bounds[k + 1]); returns (spans, pixels)."""
    cells = np.zeros(width, dtype=np.int64)
    cover = np.zeros(width + 2, dtype=np.int64)
    uncovered = np.zeros(width + 2, dtype=np.int64)
    n_spans = 0
    n_pixels = 0
    for k in range(ids.size):
        n_spans, n_pixels = _cairo_rows(table[bounds[k]:bounds[k + 1]], mask, rows, width, height, cells, cover,
                                        uncovered, spans_p, ids[k], spans_y, spans_x0, spans_x1, alpha, numer,
                                        n_spans, n_pixels, write)
    return n_spans, n_pixels


def _box_areas(scene: PathScene, vertices: NDArray[np.float64], boxes: list[int]) -> Coverage:
    """The exact area of the rectilinear paths ``boxes`` on cairo's 24.8 grid, as cairo's
    box compositing fills them."""
    from harness.oracle.path_area import path_area_coverage

    on_grid = PathScene(scene.width, scene.height, np.rint(vertices * 256.0) / 256.0, scene.contour_sizes,
                        scene.contour_path, scene.fill_rule).subset(boxes)
    areas = path_area_coverage(on_grid, Convention(coverage="area"))
    return Coverage(np.asarray(boxes, dtype=np.int64)[areas.triangle], areas.y, areas.x0, areas.x1, alpha=areas.alpha)


def _plain_spans(edges: NDArray[np.float64], fill_rule: str, width: int, height: int, rows: int) -> tuple[
        NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    """One path's plain row-sampled spans: (y, x0, x1, alpha, unused)."""
    j0 = max(int(math.floor(float(np.min(edges[:, [1, 3]])))), 0)
    j1 = min(int(math.ceil(float(np.max(edges[:, [1, 3]])))), height)
    evenodd = fill_rule == "evenodd"
    acc = np.zeros(width + 1)
    empty_i, empty_f = np.empty(0, dtype=np.int64), np.empty(0)
    spans, pixels = _plain_rows(edges, j0, j1, width, rows, evenodd, acc, empty_i, empty_i, empty_i, empty_f, 0, 0, False)
    y, x0, x1 = (np.empty(spans, dtype=np.int64) for _ in range(3))
    alpha = np.empty(pixels)
    _plain_rows(edges, j0, j1, width, rows, evenodd, acc, y, x0, x1, alpha, 0, 0, True)
    return y, x0, x1, alpha, np.empty(0, dtype=np.int64)


def row_sampled_path_coverage(scene: PathScene, convention: Convention) -> Coverage:
    """The oracle of a row-sampled area convention on a path scene
    (``Convention(coverage="area", rows=n[, full_rows=True])``): per (path, pixel), the mean
    of the path's n cross-sections where its fill rule holds, or cairo's hybrid
    (module docstring); unquantised.

    Input precision and snapping are the convention's; a path with a non-finite vertex
    covers nothing, and under the hybrid so does one reaching beyond
    :data:`HYBRID_LIMIT` px.

    Parameters
    ----------
    scene : PathScene
    convention : Convention
        With ``rows`` > 0.

    Returns
    -------
    Coverage
        ``triangle`` is the path index; ``alpha`` per pixel.

    >>> square = PathScene.from_paths(4, 1, [[[[0, 0], [4, 0], [0, 1]]]])
    >>> c = row_sampled_path_coverage(square, Convention(coverage="area", rows=2))
    >>> c.x0.tolist(), c.x1.tolist(), c.alpha.tolist()
    ([0], [3], [1.0, 0.5, 0.5])
    """
    rows = convention.rows
    if rows <= 0:
        raise ValueError("row_sampled_path_coverage needs a convention with rows > 0")
    vertices = np.asarray(convention.snap(scene.vertices), dtype=np.float64)
    width, height = int(scene.width), int(scene.height)
    per_path = _path_edges(scene, vertices)
    usable = [p for p, edges in enumerate(per_path) if edges.shape[0] and np.all(np.isfinite(edges))
              and (not convention.full_rows or np.all(np.abs(edges) < HYBRID_LIMIT))]
    if not usable:
        return Coverage.empty()
    if convention.full_rows:
        # cairo fills a rectilinear path as boxes (cairo-spans-compositor.c,
        # _cairo_path_fixed_fill_rectilinear_to_boxes): the exact area of its 24.8 outline
        fixed = [np.rint(per_path[p] * 256.0) for p in usable]
        boxes = [p for p, f in zip(usable, fixed, strict=True) if np.all((f[:, 0] == f[:, 2]) | (f[:, 1] == f[:, 3]))]
        usable = [p for p in usable if p not in boxes]
        filled = [_box_areas(scene, vertices, boxes)] if boxes else []
        if usable:
            owner = np.concatenate([np.full(per_path[p].shape[0], p, dtype=np.int64) for p in usable])
            path, y, x0, x1, alpha, _ = _cairo_spans(np.concatenate([per_path[p] for p in usable]), owner,
                                                     scene.fill_rule, width, height, rows)
            filled.append(Coverage(path, y, x0, x1, alpha=alpha))
        return Coverage.concat(filled).canonical() if filled else Coverage.empty()
    parts: list[tuple[Any, ...]] = []
    for p in usable:
        y, x0, x1, alphas, _ = _plain_spans(per_path[p], scene.fill_rule, width, height, rows)
        if y.size:
            parts.append((np.full(y.size, p, dtype=np.int64), y, x0, x1, alphas))
    if not parts:
        return Coverage.empty()
    path, y, x0, x1, alpha = (np.concatenate(column) for column in zip(*parts, strict=True))
    return Coverage(path, y, x0, x1, alpha=alpha)
