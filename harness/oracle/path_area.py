"""Area coverage of paths: the area of {p in pixel square : rule(winding(p))}, exactly and in
fast float64, under the nonzero and even-odd fill rules.

A path is one or more closed contours (:class:`harness.contract.scenes.PathScene`); w(p) is
the winding number of the path around p. The alpha of path P at pixel (i, j) is the area of
the points of ``[i, i+1] x [j, j+1]`` where ``w != 0`` (nonzero) or w is odd (even-odd):
self-intersections, overlapping contours, holes, collinear, repeated and zero-length edges
are all allowed (the boundary has zero area, so no tie rule enters). For float input it
is a rational number.

The exact reference (:func:`exact_path_area`, :func:`exact_path_pixel_areas`)
    Per pixel row band ``j <= y <= j + 1``, in :class:`fractions.Fraction`: the band is
    split at every vertex height inside it and at every height inside it where two edges
    cross. Between consecutive splits no edge begins, ends or crosses another, so the
    non-horizontal edges spanning the piece are ordered in x (by their x at its middle)
    and the winding number is constant between neighbours: summed left to right, each
    gap where the rule holds is a trapezoid with two straight sides. Its area inside
    column i is ``integral over y of clamp(R(y), i, i+1) - clamp(L(y), i, i+1)`` of its
    right and left sides, a piecewise linear integrand (broken where a side crosses
    x = i or x = i + 1) integrated exactly. Obviously correct, slow.

The float method (:func:`path_pixel_areas`)
    The same decomposition in compiled float64 code. Per (path, band) the band is cut at
    its lines and the vertex heights inside it (floats, exact), and each piece
    S = [y0, y1] (height h) is handled alone: every edge spanning it gets its float x at
    y0 and y1 (``ax + fl(fl(y - ay) / fl(by - ay)) * fl(bx - ax)`` with the edge's top end
    first, so coincident edges compute alike; the end point itself at its height), the
    edges are sorted by their float x at the middle, and walking that order at each end:

    * a neighbour left of its predecessor by at most 2 eps (eps = 12 u X, X >= 1 the
      path's largest |x|) is moved onto it -- float noise where two edges meet or cross
      at the piece's end;
    * by more, the two cross inside the piece: it is split at their float crossing
      height (or a float next to its end) and both halves are done alike. A piece that
      cannot be split (or the 4 k + 64th split of a sweep over k edges) is left out: its area,
      at most h, is added to the bound.

    After the walk the float crossings, linear between the piece's ends, are sorted at
    both ends, hence throughout S, so the winding number is constant between neighbours
    and summed left to right gives the trapezoids (L, R) where the rule holds. Trapezoid
    T adds ``g_i(R) - g_i(L)`` to column i, with ``g_i(e) = fl(h * clamped_mean(fl(x_e(y0) - i),
    fl(x_e(y1) - i)))`` (:func:`harness.oracle.area.clamped_mean`: the mean of
    clamp(x, 0, 1) along the side); columns wholly right of L and left of R (where
    clamped_mean gives exactly 0 and 1) get h through a difference array, every other
    column of the trapezoid its term directly. The row's values are clamped to [0, 1]. A
    band whose bound exceeds :data:`LOOSE_BOUND`, and every band of a path with a
    coordinate beyond ±:data:`harness.oracle.area.GUARD_LIMIT`, is computed by the exact
    reference instead (rounded to nearest: within u).

Tiles (a band of more than :data:`TILE_EDGES` edges)
    The sweep above costs its pieces times the edges spanning them: a band crossed by
    many edges (a long outline of short edges crosses a row at hundreds of places, each
    vertex height a piece) is cut into tiles of about ``2 W / k`` columns (W its columns, k
    its edges), each swept alone over its columns ``[B, B')``. For a point (x, y) of the
    tile, ``w(x, y) = w_left(y) + (the windings of the tile's edges crossing height y left
    of x)``, where the tile's edges are those whose part in the band may reach into it
    (their float x at the band's ends, widened by 2 eps, overlap it) and w_left(y) is the
    winding added by the band's other edges lying wholly left of it (right of B' they add
    nothing): exact, an integer sum of their directions (+1 where such an edge starts
    inside the band, -1 where it ends, the ones spanning the band's top counted at once),
    merged per height -- where a contour runs on wholly left of the tile its two edges'
    changes cancel, so w_left changes only where a contour passes into the tile. The tile's
    pieces are split at its edges' vertex heights and at w_left's changes; the walk starts
    at w_left, a trapezoid open there has the tile's left side x = B, one still open at the
    end its right side x = B' (integers: exact sides), and only the tile's columns are
    written. Since the area formula sum_T clamp(R) - clamp(L) is linear in the sides, the
    left sides of a tile's trapezoids need not be in order with its edges: the formula holds
    for the rule set of the sorted float crossings with the winding w_left left of them.
    Steps 1 to 3 below hold per tile as they stand (its n_S the tile's edges spanning S);
    the band's bound is the largest of its tiles' piece sums plus step 4's term over the
    whole band (its difference array and weight shared). A tile with no edge and a constant
    w_left is filled or empty as a whole.

The error bound (u = 2**-53, round to nearest)
    With n_S the edges spanning piece S, tau_S its trapezoids, Z = X + max(W, H) + 1,
    T = sum_S h_S tau_S and N the most terms added into one pixel (its direct terms plus
    the band's difference-array entries, plus 2), at every pixel of the band::

        |alpha_float - alpha_exact| <= sum_S h_S (3 n_S eps + tau_S u (2 Z + 13))
                                       + (the heights of the pieces left out) + 1.02 N (2 T + 1) u

    1. *An edge's x.* t = (y - ay) / (by - ay) is in [0, 1]; its three roundings and
       those of ``fl(bx - ax)`` and the product give ``t d (1 + theta_5)`` with
       |t d| <= |d| <= 2X; the sum rounds once more: the float x is within
       ``2 gamma_5 X + u X <= 11.01 u X < eps`` of the true one. A value moved onto its
       predecessor takes a float x of an earlier edge within 2 eps of its own: it stays
       within 3 eps of the true crossing.
    2. *The configuration.* In the piece, let the float crossings run linearly between the
       (moved) float values at its ends: each lies within 3 eps of the true crossing at
       every height of S (both differences are linear). At a height y the rule holds on a
       set of x whose winding number changes only at the crossings, so moving each
       crossing by at most 3 eps changes that set's length inside the column by at most
       3 eps per crossing: the float configuration's area in S differs from the exact one
       by at most ``3 n_S eps h``. The float configuration is sorted throughout S, so its
       area inside column i is exactly ``sum_T integral_S clamp(R) - clamp(L)``.
    3. *One trapezoid's term.* ``fl(x - i)`` errs by at most ``u |x - i| <= u Z``;
       clamped_mean is 1/2-Lipschitz in each argument, so it moves by at most u Z; its own
       roundings add 3.51 u (:mod:`harness.oracle.area`, step 3); h = fl(y1 - y0) errs by
       at most u h, the product rounds once: ``|g - g_exact| <= h u (Z + 5.53)``; two g and
       the difference's rounding: ``h u (2 Z + 12.1)``.
    4. *Sums.* A pixel's value is a recursive float sum of at most N terms: its direct
       terms, each within h (1 + 2^-40) of 0 for its piece, and the difference array's
       prefix, entries of +-h; every partial sum is at most the sum of the magnitudes,
       below 2 T + 1, so the summation errs by at most ``1.01 N (2 T + 1) u``; clamping to
       [0, 1] only brings it closer, the exact area lying in [0, 1].

    For a glyph at 1,000 pixels the bound is about 1e-13, far under the 1/510 of half an
    8-bit level: :func:`path_pixel_areas` returns it per pixel so that a check can settle
    with :func:`exact_path_area` the rare verdict it leaves open
    (:func:`harness.checks.area_paths.path_accuracy`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import MAX_VIEWPORT, PathScene
from harness.geometry.spans import expand
from harness.oracle.area import GUARD_LIMIT, UNIT_ROUNDOFF, _trim_zeros, clamped_mean

__all__ = ["exact_path_area", "exact_path_pixel_areas", "path_pixel_areas", "path_area_coverage", "PathAreas"]

_Edge = tuple[Fraction, Fraction, Fraction, Fraction]  # a -> b: ax, ay, bx, by
# A band whose float bound exceeds this is computed exactly (far below 1/510, half an 8-bit
# level: a check's verdict is then rarely left open).
LOOSE_BOUND = 2.0**-24
# A band of more edges than this is swept in tiles of columns (the module docstring, "Tiles").
TILE_EDGES = 24


# -- the exact rational reference -----------------------------------------------------------


def _fill(winding: int, evenodd: bool) -> bool:
    return winding % 2 == 1 if evenodd else winding != 0


def _contour_edges(contours: list[NDArray[np.float64]]) -> list[_Edge]:
    """The non-horizontal edges of closed contours, exactly (horizontal and zero-length
    edges cross no horizontal line: they change no winding number)."""
    edges: list[_Edge] = []
    for contour in contours:
        points = [(Fraction(float(x)), Fraction(float(y))) for x, y in np.asarray(contour, dtype=np.float64).reshape(-1, 2)]
        for k, (ax, ay) in enumerate(points):
            bx, by = points[(k + 1) % len(points)]
            if ay != by:
                edges.append((ax, ay, bx, by))
    return edges


def _x_exact(edge: _Edge, y: Fraction) -> Fraction:
    ax, ay, bx, by = edge
    return ax + (y - ay) * (bx - ax) / (by - ay)


def _clamped_integral(f0: Fraction, f1: Fraction, lo: Fraction, hi: Fraction) -> Fraction:
    """The mean over t in [0, 1] of clamp(f0 + t (f1 - f0), lo, hi), exactly: the
    integrand is linear between the points where it crosses lo and hi."""
    cuts = [Fraction(0), Fraction(1)]
    if f0 != f1:
        for level in (lo, hi):
            t = (level - f0) / (f1 - f0)
            if 0 < t < 1:
                cuts.append(t)
    cuts.sort()
    total = Fraction(0)
    for t0, t1 in zip(cuts, cuts[1:]):
        v0 = min(max(f0 + t0 * (f1 - f0), lo), hi)
        v1 = min(max(f0 + t1 * (f1 - f0), lo), hi)
        total += (t1 - t0) * (v0 + v1) / 2
    return total


def _band_trapezoids(edges: list[_Edge], evenodd: bool, j: int) -> list[tuple[Fraction, Fraction, Fraction, Fraction,
                                                                             Fraction, Fraction]]:
    """The trapezoids of row band j where the rule holds: (y0, y1, L(y0), L(y1), R(y0),
    R(y1)), exactly (the module docstring's reference). Coincident edges are merged first,
    their windings summed (an edge running down the screen adds +1, up -1): a contour
    repeated n times is one edge of winding n, and edges whose windings cancel vanish."""
    top, bottom = Fraction(j), Fraction(j + 1)
    merged: dict[_Edge, int] = {}
    for ax, ay, bx, by in edges:
        if min(ay, by) < bottom and max(ay, by) > top:
            key = (ax, ay, bx, by) if ay < by else (bx, by, ax, ay)  # top end first
            merged[key] = merged.get(key, 0) + (1 if by > ay else -1)
    band = [(e, w) for e, w in merged.items() if w]
    splits = {top, bottom}
    for e, _ in band:
        for y in (e[1], e[3]):
            if top < y < bottom:
                splits.add(y)
    # every height inside the band where two edges cross (lines x = p + q y)
    lines = [(e, e[0] - e[1] * (e[2] - e[0]) / (e[3] - e[1]), (e[2] - e[0]) / (e[3] - e[1])) for e, _ in band]
    for k, (e, p, q) in enumerate(lines):
        for f, pf, qf in lines[k + 1:]:
            if q != qf:
                y = (pf - p) / (q - qf)
                if top < y < bottom and e[1] <= y <= e[3] and f[1] <= y <= f[3]:
                    splits.add(y)
    heights = sorted(splits)
    out = []
    for y0, y1 in zip(heights, heights[1:]):
        middle = (y0 + y1) / 2
        spanning = sorted(((e, w) for e, w in band if e[1] <= y0 and e[3] >= y1), key=lambda ew: _x_exact(ew[0], middle))
        winding = 0
        left: _Edge | None = None
        for e, w in spanning:
            before = _fill(winding, evenodd)
            winding += w
            after = _fill(winding, evenodd)
            if after and not before:
                left = e
            elif before and not after:
                assert left is not None
                out.append((y0, y1, _x_exact(left, y0), _x_exact(left, y1), _x_exact(e, y0), _x_exact(e, y1)))
    return out


def _band_areas(edges: list[_Edge], evenodd: bool, j: int, columns: range) -> dict[int, Fraction]:
    """Column -> exact area in row band j, for the columns asked (only nonzero ones)."""
    areas: dict[int, Fraction] = {}
    for y0, y1, l0, l1, r0, r1 in _band_trapezoids(edges, evenodd, j):
        first = max(math.floor(min(l0, l1)), columns.start)
        last = min(math.ceil(max(r0, r1)), columns.stop)
        for i in range(first, last):
            lo, hi = Fraction(i), Fraction(i + 1)
            area = (y1 - y0) * (_clamped_integral(r0, r1, lo, hi) - _clamped_integral(l0, l1, lo, hi))
            if area:
                areas[i] = areas.get(i, Fraction(0)) + area
    return {i: a for i, a in areas.items() if a}


def _check_pixel(x: int, y: int) -> None:
    for value in (x, y):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise ValueError(f"pixel coordinates are integers, not {value!r}")


def exact_path_area(contours: Sequence[ArrayLike], fill_rule: str, x: int, y: int) -> Fraction:
    """Exact area of {p in [x, x+1] x [y, y+1] : rule(winding(p))} for one path.

    Parameters
    ----------
    contours : list of (K, 2) float64
        The path's closed contours (the last vertex joins the first).
    fill_rule : {"nonzero", "evenodd"}
    x, y : int
        The pixel's column and row.

    Returns
    -------
    Fraction
        The area, in [0, 1].

    Examples
    --------
    Two overlapping squares: nonzero counts the overlap once, even-odd not at all.

    >>> squares = [[[0, 0], [1.5, 0], [1.5, 1], [0, 1]], [[0.5, 0], [2, 0], [2, 1], [0.5, 1]]]
    >>> exact_path_area(squares, "nonzero", 0, 0), exact_path_area(squares, "evenodd", 0, 0)
    (Fraction(1, 1), Fraction(1, 2))
    """
    _check_pixel(x, y)
    arrays = [np.asarray(c, dtype=np.float64).reshape(-1, 2) for c in contours]
    if not all(np.all(np.isfinite(c)) for c in arrays):
        raise ValueError("a contour has a coordinate that is not finite")
    return _band_areas(_contour_edges(arrays), fill_rule == "evenodd", int(y), range(int(x), int(x) + 1)).get(
        int(x), Fraction(0))


def _finite_paths(scene: PathScene, vertices: NDArray[np.float64]) -> NDArray[np.bool_]:
    finite = np.ones(len(scene), dtype=bool)
    bad = ~np.all(np.isfinite(vertices), axis=1)
    finite[np.unique(np.repeat(scene.contour_path, scene.contour_sizes)[bad])] = False
    return finite


def _path_contours(scene: PathScene, vertices: NDArray[np.float64], path: int) -> list[NDArray[np.float64]]:
    ends = np.cumsum(scene.contour_sizes)
    return [vertices[ends[c] - scene.contour_sizes[c]:ends[c]] for c in np.flatnonzero(scene.contour_path == path)]


def exact_path_pixel_areas(scene: PathScene, convention: Convention | None = None) -> dict[tuple[int, int, int], Fraction]:
    """The slow reference for :func:`path_pixel_areas`: every nonzero area, exactly.

    Parameters
    ----------
    scene : PathScene
    convention : Convention, optional
        Its snapping is applied to every vertex first.

    Returns
    -------
    dict of (path, x, y) -> Fraction
        Every viewport pixel where a finite path covers a nonzero area.

    Examples
    --------
    >>> ring = PathScene.from_paths(3, 3, [[[[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [1, 2], [2, 2], [2, 1]]]])
    >>> areas = exact_path_pixel_areas(ring)
    >>> len(areas), (0, 1, 1) in areas
    (8, False)
    """
    vertices = scene.vertices if convention is None else convention.snap(scene.vertices)
    evenodd = scene.fill_rule == "evenodd"
    out: dict[tuple[int, int, int], Fraction] = {}
    for p in np.flatnonzero(_finite_paths(scene, vertices)):
        edges = _contour_edges(_path_contours(scene, vertices, int(p)))
        if not edges:
            continue
        ys = [v for e in edges for v in (e[1], e[3])]
        for j in range(max(math.floor(min(ys)), 0), min(math.ceil(max(ys)), scene.height)):
            for i, area in sorted(_band_areas(edges, evenodd, j, range(0, scene.width)).items()):
                out[int(p), i, j] = area
    return out


# -- the compiled float path -----------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _x_at(ax, ay, bx, by, y):  # type: ignore[no-untyped-def]
    """x of the edge a-b at height y between ay and by (the end point itself at its height)."""
    if y == ay:
        return ax
    if y == by:
        return bx
    return ax + ((y - ay) / (by - ay)) * (bx - ax)


@numba.njit(cache=True, inline="always")
def _g(x0, x1, i, h):  # type: ignore[no-untyped-def]
    """h * mean of clamp(x - i, 0, 1) along a side running from x0 to x1 (0 and h exactly
    where the column lies wholly right or left of it)."""
    if max(x0, x1) <= i:
        return 0.0
    if min(x0, x1) >= i + 1.0:
        return h
    return h * clamped_mean(x0 - i, x1 - i)


@numba.njit(cache=True, inline="always")
def _rule(winding, evenodd):  # type: ignore[no-untyped-def]
    return (winding % 2 != 0) if evenodd else winding != 0


@numba.njit(cache=True)
def _emit(l0, l1, r0, r1, h, lo_col, hi_col, c0, base, out, diff, counts):  # type: ignore[no-untyped-def]
    """Trapezoid (L, R) of height h into the tile's columns lo_col .. hi_col - 1: columns
    wholly right of L and left of R get h through the difference array, every other column
    its term directly. Returns the difference-array entries added (0 or 2)."""
    lo = max(int(math.floor(min(l0, l1))), lo_col)
    hi = min(int(math.ceil(max(r0, r1))), hi_col)
    full0 = max(int(math.ceil(max(l0, l1))), lo)
    full1 = min(int(math.floor(min(r0, r1))), hi)
    added = 0
    if full1 > full0:
        diff[full0 - c0] += h
        diff[full1 - c0] -= h
        added = 2
    else:
        full0 = full1 = hi
    for i in range(lo, full0):  # the columns the sides cross: their terms directly
        fi = float(i)
        out[base + i - c0] += _g(r0, r1, fi, h) - _g(l0, l1, fi, h)
        counts[i - c0] += 1
    for i in range(max(full1, lo), hi):
        fi = float(i)
        out[base + i - c0] += _g(r0, r1, fi, h) - _g(l0, l1, fi, h)
        counts[i - c0] += 1
    return added


@numba.njit(cache=True, inline="always")
def _tile_sweep(ax, ay, bx, by, down, by_top, j, lo_col, hi_col, c0, base, wl_y, wl_d, w0, evenodd,  # type: ignore[no-untyped-def]  # noqa: C901 - a numba kernel: one sweep per tile
                eps, zterm, out, diff, counts, split_buf, stack0, stack1, xs0, xs1, keys, active, ident):
    """One tile of a band: columns lo_col .. hi_col - 1 of row band j, from the edges
    ``by_top`` (those whose part in the band may reach into the tile, sorted by their top)
    and the winding number left of the tile, ``w0`` plus the changes ``wl_d`` at heights
    ``wl_y`` (sorted, inside the band). Returns (bound, weight, entries): the pieces' part
    of the error bound, the sum of h * trapezoids and the difference-array entries."""
    k = by_top.size
    splits = split_buf
    splits[0] = j
    splits[1] = j + 1.0
    m = 2
    for s in range(k):
        e = by_top[s]
        for y in (ay[e], by[e]):
            if j < y < j + 1.0:
                splits[m] = y
                m += 1
    for q in range(wl_y.size):
        splits[m] = wl_y[q]
        m += 1
    if m > 32:
        splits = np.sort(splits[:m])
    else:  # a few heights (most tiles): an insertion sort, no allocation
        for q in range(1, m):
            y = splits[q]
            t = q
            while t > 0 and splits[t - 1] > y:
                splits[t] = splits[t - 1]
                t -= 1
            splits[t] = y
    # pieces to do, as a stack of (y0, y1): the sub-intervals between vertex heights and
    # the heights where the winding left of the tile changes, split further where two
    # float edges cross
    limit = 4 * k + 64  # (the stack holds at most limit + m - 1 pieces)
    top = 0
    for q in range(m - 2, -1, -1):
        if splits[q + 1] > splits[q]:
            stack0[top] = splits[q]
            stack1[top] = splits[q + 1]
            top += 1
    bound = 0.0
    weight = 0.0  # sum over the pieces of h * (their trapezoids): bounds every partial sum
    entries = 0  # difference-array entries
    pieces = 0
    joined = 0
    n_active = 0
    w_left = w0
    next_change = 0
    flo, fhi = float(lo_col), float(hi_col)
    # the pieces come in order of y0 (the stack pops the lower half of a split first):
    # an active edge list, edges joining by their top end, leaving below their bottom
    while top > 0:
        top -= 1
        y0, y1 = stack0[top], stack1[top]
        h = y1 - y0
        while next_change < wl_y.size and wl_y[next_change] <= y0:
            w_left += wl_d[next_change]
            next_change += 1
        while joined < k and ay[by_top[joined]] <= y0:
            active[n_active] = by_top[joined]
            n_active += 1
            joined += 1
        # the active list stays sorted from piece to piece: ended edges leave it in place,
        # joined ones are appended, and an insertion sort by x at the middle, ties by x at
        # y0, restores the order in a pass when few edges have crossed (every active edge
        # spans the piece: no edge ends inside one, every vertex height being a split)
        kept = 0
        for q in range(n_active):
            e = active[q]
            if by[e] <= y0:
                continue  # ended above this piece: and above every later one
            active[kept] = e
            kept += 1
        n_active = kept
        n = kept
        for r in range(n):
            e = active[r]
            x0_ = _x_at(ax[e], ay[e], bx[e], by[e], y0)
            x1_ = _x_at(ax[e], ay[e], bx[e], by[e], y1)
            key = 0.5 * x0_ + 0.5 * x1_
            t = r
            while t > 0 and (keys[t - 1] > key or (keys[t - 1] == key and xs0[t - 1] > x0_)):
                active[t] = active[t - 1]
                keys[t] = keys[t - 1]
                xs0[t] = xs0[t - 1]
                xs1[t] = xs1[t - 1]
                t -= 1
            active[t] = e
            keys[t] = key
            xs0[t] = x0_
            xs1[t] = x1_
        ids = active
        order = ident[:n]
        # at each end, a neighbour left of its predecessor by at most 2 eps is moved
        # onto it (float noise: it stays within 3 eps of the true crossing); by more,
        # the two cross inside the piece: split it there
        inverted = -1
        for r in range(n - 1):
            a_, b_ = order[r], order[r + 1]
            if xs0[b_] < xs0[a_]:
                if xs0[a_] - xs0[b_] <= 2.0 * eps:
                    xs0[b_] = xs0[a_]
                elif inverted < 0:
                    inverted = r
            if xs1[b_] < xs1[a_]:
                if xs1[a_] - xs1[b_] <= 2.0 * eps:
                    xs1[b_] = xs1[a_]
                elif inverted < 0:
                    inverted = r
        if inverted >= 0:
            pieces += 1
            a_, b_ = order[inverted], order[inverted + 1]
            # the gaps at the ends have opposite signs: they cross at t = g0 / (g0 - g1)
            g0 = xs0[b_] - xs0[a_]
            g1 = xs1[b_] - xs1[a_]
            yc = y0 + (g0 / (g0 - g1)) * h
            if yc <= y0:
                yc = np.nextafter(y0, y1)
            elif yc >= y1:
                yc = np.nextafter(y1, y0)
            if y0 < yc < y1 and pieces < limit and h > 2.0**-60:
                stack0[top], stack1[top] = yc, y1
                stack0[top + 1], stack1[top + 1] = y0, yc
                top += 2
            else:
                bound += h  # left out: its area, at most h, is the error
            continue
        # the float crossings, linear between the piece's ends, are sorted throughout
        # it: each gap's winding is constant (module docstring, steps 1 and 2); the
        # winding starts at the tile's left side at w_left, a side of the tile closing a
        # trapezoid open there (exact: an integer x)
        winding = w_left
        filled = _rule(winding, evenodd)
        l0 = l1 = flo
        trapezoids = 0
        r = 0
        while r < n:
            t = order[r]
            # a run of coincident crossings is one, their windings summed
            winding += down[ids[t]]
            r += 1
            while r < n and xs0[order[r]] == xs0[t] and xs1[order[r]] == xs1[t]:
                winding += down[ids[order[r]]]
                r += 1
            now = _rule(winding, evenodd)
            if now and not filled:
                l0, l1 = xs0[t], xs1[t]
            elif filled and not now:
                trapezoids += 1
                entries += _emit(l0, l1, xs0[t], xs1[t], h, lo_col, hi_col, c0, base, out, diff, counts)
            filled = now
        if filled:
            trapezoids += 1
            entries += _emit(l0, l1, fhi, fhi, h, lo_col, hi_col, c0, base, out, diff, counts)
        bound += h * (3.0 * n * eps + trapezoids * zterm)
        weight += h * trapezoids
    return bound, weight, entries




@numba.njit(cache=True)
def _bands_kernel(ax, ay, bx, by, down, group_start, group_edges, group_j, group_c0, group_n, group_off,  # type: ignore[no-untyped-def]  # noqa: C901 - a numba kernel: one sweep per band
                  group_path, evenodd, x_of_path, z_of_path, out, out_bound):
    """Per (path, band) group: the band's alphas into ``out[group_off[g]:][:group_n[g]]``
    (columns group_c0[g] ..) and its error bound (module docstring). Edge e runs from
    (ax, ay) to (bx, by) with ay < by, ``down[e]`` its winding (+1 down the screen, -1 up).

    A band of more than TILE_EDGES edges is cut into tiles of a few columns, each swept
    alone (module docstring, "Tiles"): its edges are those whose part in the band may reach
    into it, and the edges wholly left of it enter as the winding number they add left of
    it, which changes only at their vertex heights inside the band."""
    u = 2.0**-53
    # work space for the largest band, allocated once
    kmax, nmax = 1, 1
    for g in range(group_j.size):
        kmax = max(kmax, group_start[g + 1] - group_start[g])
        nmax = max(nmax, group_n[g])
    split_buf = np.empty(4 * kmax + 2)
    stack0 = np.empty(8 * kmax + 66)
    stack1 = np.empty(8 * kmax + 66)
    diff = np.empty(nmax + 1)
    counts = np.empty(nmax, dtype=np.int64)  # direct terms per column
    xs0 = np.empty(kmax)
    xs1 = np.empty(kmax)
    keys = np.empty(kmax)
    active = np.empty(kmax, dtype=np.int64)
    ident = np.arange(kmax)
    top_buf = np.empty(kmax, dtype=np.int64)
    first_tile = np.empty(kmax, dtype=np.int64)
    last_tile = np.empty(kmax, dtype=np.int64)
    left_from = np.empty(kmax, dtype=np.int64)
    tile_start = np.empty(2 * kmax + 4, dtype=np.int64)  # tiles <= k + 1
    tile_edges = np.empty(0, dtype=np.int64)
    left_start = np.empty(2 * kmax + 4, dtype=np.int64)
    left_edges = np.empty(kmax, dtype=np.int64)
    ev_y = np.empty(2 * kmax)
    ev_d = np.empty(2 * kmax, dtype=np.int64)
    no_y = np.empty(0)
    no_d = np.empty(0, dtype=np.int64)
    for g in range(group_j.size):
        s0, s1 = group_start[g], group_start[g + 1]
        k = s1 - s0
        j = float(group_j[g])
        c0 = group_c0[g]
        ncol = group_n[g]
        base = group_off[g]
        eps = 12.0 * u * x_of_path[group_path[g]]  # an edge's float x at a height: within 11.01 u X
        zterm = u * (2.0 * z_of_path[group_path[g]] + 13.0)
        band = group_edges[s0:s1]
        if k <= 32:  # a few edges (most bands): an insertion sort by their tops, no allocation
            by_top = top_buf[:k]
            for q in range(k):
                e = band[q]
                t = q
                while t > 0 and ay[by_top[t - 1]] > ay[e]:
                    by_top[t] = by_top[t - 1]
                    t -= 1
                by_top[t] = e
        else:
            by_top = band[np.argsort(ay[band])]
        diff[:ncol + 1] = 0.0
        counts[:ncol] = 0
        bound = 0.0
        weight = 0.0
        entries = 0
        if k <= TILE_EDGES or ncol <= 2:
            bound, weight, entries = _tile_sweep(ax, ay, bx, by, down, by_top, j, c0, c0 + ncol, c0, base, no_y, no_d, 0,
                                                 evenodd, eps, zterm, out, diff, counts, split_buf, stack0, stack1, xs0,
                                                 xs1, keys, active, ident)
        else:
            width = max(1, (2 * ncol) // k)  # about one edge per tile for edges spread evenly
            tiles = (ncol + width - 1) // width
            # each edge's tiles: its part in the band spans x in [lo, hi] (its float x at
            # the band's ends, within 11.01 u X of the true; widened by 2 eps), and the
            # quotients by 1e-12 (|q| + 1): tiles first..last may hold it, tiles after last
            # have it wholly left of them (B_k >= hi)
            tile_start[:tiles + 2] = 0
            left_start[:tiles + 2] = 0
            for q in range(k):
                e = by_top[q]
                yt = max(ay[e], j)
                yb = min(by[e], j + 1.0)
                xt = _x_at(ax[e], ay[e], bx[e], by[e], yt)
                xb = _x_at(ax[e], ay[e], bx[e], by[e], yb)
                lo = (min(xt, xb) - 2.0 * eps - c0) / width
                hi = (max(xt, xb) + 2.0 * eps - c0) / width
                # (the quotients' two roundings err by far less than 1e-12 (|q| + 1))
                first_tile[q] = max(int(math.floor(max(min(lo - 1e-12 * (abs(lo) + 1.0), tiles + 1.0), -1.0))), 0)
                # in tile t only if B_t < the edge's right end: t < hi; wholly left of tile t
                # if B_t >= it: t >= ceil(hi)
                la = int(math.ceil(max(min(hi + 1e-12 * (abs(hi) + 1.0), tiles + 1.0), -1.0)))
                last_tile[q] = min(la - 1, tiles - 1)
                left_from[q] = max(la, 0)
                for t in range(first_tile[q], last_tile[q] + 1):
                    tile_start[t + 1] += 1
                if left_from[q] < tiles:
                    left_start[left_from[q] + 1] += 1
            for t in range(tiles):
                tile_start[t + 1] += tile_start[t]
                left_start[t + 1] += left_start[t]
            if tile_edges.size < tile_start[tiles]:
                tile_edges = np.empty(2 * tile_start[tiles], dtype=np.int64)
            fill = tile_start[:tiles].copy()
            lfill = left_start[:tiles].copy()
            for q in range(k):  # in order of their tops: each tile's list is sorted too
                e = by_top[q]
                for t in range(first_tile[q], last_tile[q] + 1):
                    tile_edges[fill[t]] = e
                    fill[t] += 1
                if left_from[q] < tiles:
                    left_edges[lfill[left_from[q]]] = e
                    lfill[left_from[q]] += 1
            # the winding left of tile t: w0 at the band's top plus the changes at the
            # heights inside the band (+down where a left edge starts, -down where one
            # ends), kept sorted and merged: a contour running on wholly left of the tile
            # changes nothing (its two edges' changes cancel at their common vertex)
            w0 = 0
            n_ev = 0
            for t in range(tiles):
                for s in range(left_start[t], left_start[t + 1]):
                    e = left_edges[s]
                    if ay[e] <= j:
                        w0 += down[e]
                    for y, d in ((ay[e], down[e]), (by[e], -down[e])):
                        if not j < y < j + 1.0:
                            continue
                        p = n_ev
                        while p > 0 and ev_y[p - 1] > y:
                            p -= 1
                        if p > 0 and ev_y[p - 1] == y:
                            ev_d[p - 1] += d
                            if ev_d[p - 1] == 0:  # cancelled: removed
                                for r in range(p - 1, n_ev - 1):
                                    ev_y[r] = ev_y[r + 1]
                                    ev_d[r] = ev_d[r + 1]
                                n_ev -= 1
                        else:
                            for r in range(n_ev, p, -1):
                                ev_y[r] = ev_y[r - 1]
                                ev_d[r] = ev_d[r - 1]
                            ev_y[p] = y
                            ev_d[p] = d
                            n_ev += 1
                lo_col = c0 + t * width
                hi_col = min(lo_col + width, c0 + ncol)
                if tile_start[t + 1] == tile_start[t] and n_ev == 0:
                    # no edge and a constant winding: the tile's columns are all filled or all empty
                    if _rule(w0, evenodd):
                        diff[lo_col - c0] += 1.0
                        diff[hi_col - c0] -= 1.0
                        entries += 2
                        weight += 1.0
                        bound = max(bound, zterm)
                    continue
                tb, tw, te = _tile_sweep(ax, ay, bx, by, down, tile_edges[tile_start[t]:tile_start[t + 1]], j, lo_col,
                                         hi_col, c0, base, ev_y[:n_ev], ev_d[:n_ev], w0, evenodd, eps, zterm, out, diff,
                                         counts, split_buf, stack0, stack1, xs0, xs1, keys, active, ident)
                bound = max(bound, tb)
                weight += tw
                entries += te
        running = 0.0
        for c in range(ncol):
            running += diff[c]
            value = out[base + c] + running
            out[base + c] = min(max(value, 0.0), 1.0)
        most = 0
        for c in range(ncol):
            most = max(most, counts[c])
        terms = float(most + entries + 2)
        out_bound[g] = bound * (1.0 + 2.0**-40) + 1.02 * u * terms * (2.0 * weight + 1.0)


@numba.njit(cache=True)
def _edge_setup(vx, vy, sizes, contour_path, n_paths, guard):  # type: ignore[no-untyped-def]
    """Every edge (vertex v to the next of its contour) top end first: (ax, ay, bx, by),
    its direction ``down`` (+1 where it runs down the screen, else -1, the ends swapped),
    its path ``owner`` and ``use`` (its path finite and the edge not horizontal); per path
    ``near`` (no coordinate beyond ``guard``) and its largest |x| (at least 1) over the
    vertices within it."""
    n = vx.size
    owner = np.empty(n, dtype=np.int64)
    v = 0
    for c in range(sizes.size):
        for _ in range(sizes[c]):
            owner[v] = contour_path[c]
            v += 1
    finite = np.ones(n_paths, dtype=np.bool_)
    near = np.ones(n_paths, dtype=np.bool_)
    path_x = np.ones(n_paths)
    for v in range(n):
        p = owner[v]
        fx, fy = np.isfinite(vx[v]), np.isfinite(vy[v])
        if not (fx and fy):
            finite[p] = False
        sx = abs(vx[v]) if fx else 0.0  # a coordinate that is not finite counts as 0 here
        sy = abs(vy[v]) if fy else 0.0
        if sx <= guard and sy <= guard:
            if fx:
                path_x[p] = max(path_x[p], sx)
        else:
            near[p] = False
    ax = np.empty(n)
    ay = np.empty(n)
    bx = np.empty(n)
    by = np.empty(n)
    down = np.empty(n, dtype=np.int64)
    use = np.empty(n, dtype=np.bool_)
    start = 0
    for c in range(sizes.size):
        for v in range(start, start + sizes[c]):
            w = v + 1 if v + 1 < start + sizes[c] else start
            if vy[w] > vy[v]:
                down[v] = 1
                ax[v], ay[v], bx[v], by[v] = vx[v], vy[v], vx[w], vy[w]
            else:
                down[v] = -1
                ax[v], ay[v], bx[v], by[v] = vx[w], vy[w], vx[v], vy[v]
            use[v] = finite[owner[v]] and ay[v] != by[v]
        start += sizes[c]
    return ax, ay, bx, by, down, owner, use, near, path_x


@numba.njit(cache=True)
def _band_groups(ax, ay, bx, by, use, owner, n_paths, width, height):  # type: ignore[no-untyped-def]
    """The (path, row band) groups: every used edge (a -> b, ay < by) once per row band it
    crosses, sorted by path, then row, then edge (two stable counting sorts), and per group
    its first entry, row, path and columns [c0, c1) (the edges' x range, clipped to the
    viewport; np.floor, not math.floor, whose integer overflows on a far coordinate).
    Returns (edges, group_start (G + 1), group_j, group_path, c0, c1)."""
    n = ax.size
    first = np.zeros(n, dtype=np.int64)
    count = np.zeros(n, dtype=np.int64)
    total = 0
    for e in range(n):
        if use[e]:
            f = int(min(max(np.floor(ay[e]), 0.0), float(height)))
            last = int(min(max(np.ceil(by[e]), 0.0), float(height))) - 1
            first[e] = f
            count[e] = max(last - f + 1, 0)
            total += count[e]
    # by row (stable: edges in order), then by path (stable): by path, row, edge
    per_row = np.zeros(height + 1, dtype=np.int64)
    for e in range(n):
        for j in range(first[e], first[e] + count[e]):
            per_row[j + 1] += 1
    for j in range(height):
        per_row[j + 1] += per_row[j]
    row_edge = np.empty(total, dtype=np.int64)
    row_j = np.empty(total, dtype=np.int64)
    for e in range(n):
        for j in range(first[e], first[e] + count[e]):
            row_edge[per_row[j]] = e
            row_j[per_row[j]] = j
            per_row[j] += 1
    per_path = np.zeros(n_paths + 1, dtype=np.int64)
    for q in range(total):
        per_path[owner[row_edge[q]] + 1] += 1
    for p in range(n_paths):
        per_path[p + 1] += per_path[p]
    edges = np.empty(total, dtype=np.int64)
    rows = np.empty(total, dtype=np.int64)
    for q in range(total):
        p = owner[row_edge[q]]
        edges[per_path[p]] = row_edge[q]
        rows[per_path[p]] = row_j[q]
        per_path[p] += 1
    groups = 0
    for q in range(total):
        if q == 0 or rows[q] != rows[q - 1] or owner[edges[q]] != owner[edges[q - 1]]:
            groups += 1
    group_start = np.empty(groups + 1, dtype=np.int64)
    group_j = np.empty(groups, dtype=np.int64)
    group_path = np.empty(groups, dtype=np.int64)
    c0 = np.empty(groups, dtype=np.int64)
    c1 = np.empty(groups, dtype=np.int64)
    g = -1
    lo = hi = 0.0
    for q in range(total):
        e = edges[q]
        if q == 0 or rows[q] != rows[q - 1] or owner[e] != owner[edges[q - 1]]:
            if g >= 0:
                c0[g] = int(min(max(np.floor(lo), 0.0), float(width)))
                c1[g] = int(min(max(np.ceil(hi), 0.0), float(width)))
            g += 1
            group_start[g] = q
            group_j[g] = rows[q]
            group_path[g] = owner[e]
            lo, hi = min(ax[e], bx[e]), max(ax[e], bx[e])
        else:
            lo, hi = min(lo, ax[e], bx[e]), max(hi, ax[e], bx[e])
    if g >= 0:
        c0[g] = int(min(max(np.floor(lo), 0.0), float(width)))
        c1[g] = int(min(max(np.ceil(hi), 0.0), float(width)))
    group_start[groups] = total
    return edges, group_start, group_j, group_path, c0, c1


# (path, x, y, area, bound) of path_pixel_areas
PathAreas = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]


def _viewport(width: int, height: int) -> None:
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 1 <= value <= MAX_VIEWPORT:
            raise ValueError(f"{name} must be an integer in 1..{MAX_VIEWPORT}, not {value!r}")


def _area_groups(scene: PathScene, vertices: NDArray[np.float64], exact_everywhere: bool = False) -> tuple[
        NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """(path, y, x0, x1, alpha, bound): one span per (path, row band), alphas per column."""
    width, height = scene.width, scene.height
    _viewport(width, height)
    n_paths = len(scene)
    ax, ay, bx, by, down, owner, use, near, path_x = _edge_setup(
        np.ascontiguousarray(vertices[:, 0]), np.ascontiguousarray(vertices[:, 1]),
        np.ascontiguousarray(scene.contour_sizes, dtype=np.int64), np.ascontiguousarray(scene.contour_path, dtype=np.int64),
        n_paths, GUARD_LIMIT)
    rep_edge, group_start, group_j, group_path, c0, c1 = _band_groups(ax, ay, bx, by, use, owner, n_paths, width, height)
    heads = group_start[:-1]
    group_n = np.maximum(c1 - c0, 0)
    offsets = np.concatenate([[0], np.cumsum(group_n)]).astype(np.int64)
    out = np.zeros(int(offsets[-1]))
    ok = np.zeros(heads.size, dtype=bool)
    bound = np.zeros(heads.size)
    z = path_x + max(width, height) + 1.0
    fast = near[group_path] & (not exact_everywhere)
    idx = np.flatnonzero(fast)
    if idx.size:
        # the kernel sees the fast groups only (their edges all near)
        if idx.size == heads.size:  # every group (the usual case): as they are
            sub_start, sub_edges = group_start, rep_edge
        else:
            sub_start = np.concatenate([[0], np.cumsum(np.diff(group_start)[idx])]).astype(np.int64)
            sizes = np.diff(group_start)[idx]
            sub_edges = rep_edge[np.repeat(group_start[idx] - sub_start[:-1], sizes) + np.arange(int(sizes.sum()))]
        sub_off = offsets[idx]
        sub_bound = np.zeros(idx.size)
        _bands_kernel(ax, ay, bx, by, down, sub_start, sub_edges.astype(np.int64),
                      group_j[idx].astype(np.int64), c0[idx], group_n[idx], sub_off, group_path[idx].astype(np.int64),
                      scene.fill_rule == "evenodd", path_x, z, out, sub_bound)
        # a band whose bound is loose (a piece left out where float edges could not be
        # told apart) is computed by the exact reference instead
        ok[idx], bound[idx] = sub_bound <= LOOSE_BOUND, sub_bound
    # the exact reference where the float bound is loose (or the path is far)
    evenodd = scene.fill_rule == "evenodd"
    exact_edges: dict[int, list[_Edge]] = {}
    for g in np.flatnonzero(~ok):
        p = int(group_path[g])
        if p not in exact_edges:
            exact_edges[p] = _contour_edges(_path_contours(scene, vertices, p))
        lo, n = int(c0[g]), int(group_n[g])
        values = np.zeros(n)
        for i, area in _band_areas(exact_edges[p], evenodd, int(group_j[g]), range(lo, lo + n)).items():
            values[i - lo] = float(area)
        out[offsets[g]:offsets[g] + n] = values
        bound[g] = UNIT_ROUNDOFF
    return group_path, group_j, c0, c0 + group_n, out, bound


def path_pixel_areas(scene: PathScene, convention: Convention | None = None) -> PathAreas:
    """Area of {p in pixel : rule(winding(p))} for every path and viewport pixel it touches.

    Float64 in compiled code where its bound is tight (below LOOSE_BOUND), the exact
    reference elsewhere (module docstring), each pixel with its proven error bound.

    Parameters
    ----------
    scene : PathScene
    convention : Convention, optional
        Its snapping is applied to every vertex first.

    Returns
    -------
    path, x, y : (P,) int64
        Pixels with a nonzero float area, sorted by path, row and column.
    area : (P,) float64
        In (0, 1].
    bound : (P,) float64
        A proven bound on ``|area - exact_path_area|`` at each.

    Examples
    --------
    >>> star = PathScene.from_paths(2, 2, [[[[0, 0], [2, 0], [0, 2]]]])
    >>> p, x, y, area, bound = path_pixel_areas(star)
    >>> x.tolist(), y.tolist(), area.tolist(), bool(bound.max() < 2**-40)
    ([0, 1, 0], [0, 0, 1], [1.0, 0.5, 0.5], True)
    """
    path, y, x0, x1, alpha, bound = _coverage_parts(scene, convention)
    lengths = x1 - x0
    keep = alpha > 0.0
    columns = np.repeat(x0 - np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64), lengths) + np.arange(alpha.size)
    return (np.repeat(path, lengths)[keep], columns[keep], np.repeat(y, lengths)[keep], alpha[keep],
            np.repeat(bound, lengths)[keep])


def _coverage_parts(scene: PathScene, convention: Convention | None) -> tuple[
        NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    vertices = scene.vertices if convention is None else np.asarray(convention.snap(scene.vertices), dtype=np.float64)
    path, y, x0, x1, alpha, bound = _area_groups(scene, np.ascontiguousarray(vertices))
    # each span cut to its first and last nonzero alpha (area.py's kernel)
    new_x0, new_x1, first = np.empty_like(x0), np.empty_like(x1), np.empty_like(x0)
    _trim_zeros(np.ascontiguousarray(x0), np.ascontiguousarray(x1), alpha, new_x0, new_x1, first)
    keep = new_x1 > new_x0
    lengths = (new_x1 - new_x0)[keep]
    return path[keep], y[keep], new_x0[keep], new_x1[keep], alpha[expand(first[keep], lengths)], bound[keep]


def path_area_coverage(scene: PathScene, convention: Convention) -> Coverage:
    """The oracle of an analytic area convention for a path scene: every (path, pixel) with
    a nonzero area, its alpha the area where the fill rule holds inside the pixel square
    (unquantised), within the bound of :func:`path_pixel_areas` of the exact area.

    Snapping is the convention's; the tie rule, the sample point and culling mean nothing
    here. Spans sorted by path, row and column, with ``alpha``.

    >>> from harness.contract.conventions import Convention
    >>> square = PathScene.from_paths(2, 2, [[[[0.5, 0], [2, 0], [2, 2], [0.5, 2]]]])
    >>> path_area_coverage(square, Convention(coverage="area")).alpha.tolist()
    [0.5, 1.0, 0.5, 1.0]
    """
    if convention.samples is not None:
        raise ValueError("path_area_coverage is the analytic area; a supersampled convention's oracle is "
                         "harness.oracle.winding.path_coverage (the share of its samples covered)")
    path, y, x0, x1, alpha, _ = _coverage_parts(scene, convention)
    ordered = bool(np.all((path[1:] > path[:-1]) | ((path[1:] == path[:-1]) & (
        (y[1:] > y[:-1]) | ((y[1:] == y[:-1]) & (x0[1:] >= x0[:-1]))))))
    if not ordered:  # (the groups come by path and row: sorted already)
        order = np.lexsort((x0, y, path))
        lengths = x1 - x0
        starts = np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64)
        alpha = np.concatenate([alpha[starts[s]:starts[s + 1]] for s in order])
        path, y, x0, x1 = path[order], y[order], x0[order], x1[order]
    return Coverage(path, y, x0, x1, alpha=alpha)
