"""The exact winding-number oracle for paths under the nonzero and even-odd fill rules.

A path is one or more closed contours (the last vertex joins the first). Sample
``p = (i + sx, j + sy)`` of pixel (i, j) is covered by a path when the winding number of
the *perturbed* sample ``q = p + d(eps)``, eps -> 0+, around the path's contours satisfies
the fill rule (``nonzero``: w != 0; ``evenodd``: w odd). ``d`` is the tie rule's
perturbation (:mod:`harness.contract.conventions`): ``(tx*eps, ty*eps**2)`` for the x-first rules,
``(tx*eps**2, ty*eps)`` for the y-first ones, ``(tx, ty)`` from
:data:`harness.contract.conventions.TIE_PERTURBATION`. For small eps, q lies on no edge line (an
edge of nonzero length has a nonzero gradient, so the lowest-order term of its edge
function at q is nonzero) and on no horizontal line through a vertex, so the winding number
is well defined everywhere: on vertices, horizontal edges, collinear or repeated vertices,
zero-length edges and overlapping edges. For a path of one triangle it is exactly the
triangle oracle (:func:`harness.oracle.coverage.exact_coverage`), with either fill rule.

Method, per sample row ``ys = j + sy`` (every decision exact, no epsilon):

1. *Which edges cross q's horizontal line.* q's y is ``ys + ty*eps**k`` (k = 2 for
   x-first, 1 for y-first: only the sign ``ty`` matters). A vertex ``v`` lies below it
   (greater y) when ``vy > ys``, or ``vy == ys`` and ``ty < 0`` -- float comparisons,
   exact. Edge a -> b crosses when exactly one of a, b is below. A horizontal edge has
   both ends on the same side: never crossed; a zero-length edge likewise.
2. *Where.* For a crossing edge (never horizontal), let ``s = sign E_ab(p)`` with
   ``E_ab(p) = (bx-ax)*(py-ay) - (by-ay)*(px-ax)`` (:func:`harness.geometry.exact.orient2d_sign`)
   and ``dir = sign(by - ay)``. E decreases in x when dir > 0, so q lies right of the
   edge's crossing exactly when ``sign E_ab(q) * dir < 0``. When ``s != 0`` that is
   ``s * dir < 0``. When p is on the edge's line (``s == 0``) the perturbation decides,
   from ``E(q) = E(p) + dE/dx*d_x + dE/dy*d_y`` with dE/dx = -(by-ay) != 0 and
   dE/dy = bx-ax:

   * x-first rules (d_x = tx*eps is first order): sign E(q) = -dir*tx, so q is right of
     the crossing exactly when ``tx > 0``;
   * y-first rules (d_y = ty*eps first order), a slanted edge (bx != ax): sign E(q) =
     sign((bx-ax)*ty), so q is right exactly when ``(bx-ax)*(by-ay)*ty < 0`` -- the
     crossing itself moves by (dx/dy)*ty*eps while q's x moves by only O(eps**2);
   * y-first rules, a vertical edge: dE/dy = 0 and the x-term decides as for x-first:
     right exactly when ``tx > 0``.

   "Right of the crossing" is monotone in the column, so the first column ``c`` in
   [0, width] whose sample is right of it is found from the float crossing with a rigorous
   error bound and, when a column boundary lies within it, settled exactly with
   ``orient2d_sign`` (the triangle oracle's ``_bound``/``_settle``).
3. *Winding.* Every crossing contributes ``dir`` (+1 for an edge running down the screen,
   -1 up) to the winding of every sample at column >= c (the crossings left of the
   sample). One path at a time, its crossings are bucketed by row (each row's room the
   number of its edges spanning the row, one pass over them, no global sort), each
   row's (c, dir) events sorted by c and prefix-summed; the runs where the fill rule
   holds are the spans. (Counting
   crossings left of the sample rather than right negates the winding number of a closed
   path: neither rule cares.)

Snapping (``convention.snap``) is applied to every vertex first. Culling is ignored for
paths: a fill rule, not a triangle's orientation, decides what a path covers. A path with
a NaN or infinite vertex (after snapping) covers nothing. Coordinates beyond the exact
expansions' safe range (nonzero magnitude below 2**-450 or above 2**450,
:data:`harness.geometry.exact.SAFE_MIN`/:data:`~harness.geometry.exact.SAFE_MAX`) raise ValueError naming
the contour; :func:`path_spans_rational` handles any finite float.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import FILL_RULES, Convention, FillRule  # the fill rules are defined beside the tie rules
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, PathScene
from harness.geometry.exact import SAFE_MAX, SAFE_MIN, frozen
from harness.geometry.kernel_sorts import heapsort  # (numba's own sort compiles slowly)
from harness.kinds import PATHS, TRIANGLES
from harness.oracle.kernels import _bound, _edge_setup, _row_range, shares_of_layers

__all__ = ["FILL_RULES", "FillRule", "UNBALANCED_ROWS", "path_spans", "path_spans_rational", "path_coverage",
           "open_outline_coverage"]


Spans = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]


# -- the compiled kernels ------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _below(vy, ys, ty):  # type: ignore[no-untyped-def]
    """Whether a vertex at height vy lies below (greater y than) the perturbed line
    ys + ty*eps**k, eps -> 0+."""
    return vy > ys or (vy == ys and ty < 0)


@numba.njit(cache=True, inline="always")
def _tie_right(ax, ay, bx, by, tx, ty, y_first):  # type: ignore[no-untyped-def]
    """Whether a sample exactly on the (non-horizontal) edge line a-b, perturbed by the tie
    rule, lies right of the edge's crossing of its row (see the module docstring)."""
    if y_first and ax != bx:
        return ((bx > ax) == (by > ay)) != (ty > 0)  # (bx-ax)*(by-ay)*ty < 0
    return tx > 0


@numba.njit(cache=True, error_model="numpy")
def _paths_kernel(a, b, first_edge, sx, sy, tx, ty, y_first, evenodd, to_edge, width, height,  # type: ignore[no-untyped-def]  # noqa: C901 - a numba kernel: the sweep is one loop
                  keys, row_start, row_end, out_p, out_y, out_x0, out_x1):
    """Every path's spans, one path at a time, with no global sort: the path's crossings
    bucketed by row (each row's bucket as large as the number of the path's edges whose y
    extent spans it -- an upper bound, from a difference array: no counting pass), each
    row's bucket sorted by column in place, then scanned with the winding summed. Edge k
    runs from ``a[k]`` to ``b[k]`` ((E, 2) each); edges are grouped by path: path p owns
    edges ``first_edge[p] .. first_edge[p + 1] - 1``. ``keys`` holds one path's crossings
    (as ``2 * column + (dir > 0)``), ``row_start`` and ``row_end`` height + 2 ints each.
    A row whose winding is still inside after its last crossing (only when the edges do
    not close: :func:`open_outline_coverage`) is filled to the viewport's edge when
    ``to_edge``, else up to that last crossing. Returns the number of spans written."""
    n = 0
    for p in range(first_edge.size - 1):
        e0, e1 = first_edge[p], first_edge[p + 1]
        lo, hi = height, -1
        for e in range(e0, e1):
            if a[e, 1] != b[e, 1]:
                first, last = _row_range(min(a[e, 1], b[e, 1]), max(a[e, 1], b[e, 1]), sy, height)
                if first <= last:
                    lo, hi = min(lo, first), max(hi, last)
        if hi < lo:
            continue
        rows = hi - lo + 1
        for r in range(rows + 2):
            row_start[r] = 0
        # each row's room: the edges whose rows include it (differences, summed twice:
        # once into counts per row, once into where each row starts)
        for e in range(e0, e1):
            if a[e, 1] != b[e, 1]:
                first, last = _row_range(min(a[e, 1], b[e, 1]), max(a[e, 1], b[e, 1]), sy, height)
                if first <= last:
                    row_start[first - lo + 1] += 1
                    row_start[last - lo + 2] -= 1
        for r in range(rows):
            row_start[r + 1] += row_start[r]
        for r in range(rows):
            row_start[r + 1] += row_start[r]
        for r in range(rows):
            row_end[r] = row_start[r]
        # where each crossing lies. _bound/_settle look for the first column where g holds:
        # g = inside(owned) when `lower`, else not inside(owned), with inside = s > 0 or
        # (s == 0 and owned). With dir < 0 (lower) "right of the crossing" is s > 0 or
        # (s == 0 and tie_right); with dir > 0 it is s < 0 or (s == 0 and tie_right) =
        # not (s > 0 or (s == 0 and not tie_right)).
        for e in range(e0, e1):
            x0, y0, x1, y1 = a[e, 0], a[e, 1], b[e, 0], b[e, 1]
            if y0 == y1:
                continue  # horizontal or zero-length: never crosses a perturbed row
            first, last = _row_range(min(y0, y1), max(y0, y1), sy, height)
            if first > last:
                continue
            up = 1 if y1 > y0 else 0
            lower = y1 < y0
            tie_right = _tie_right(x0, y0, x1, y1, tx, ty, y_first)
            owned = tie_right if lower else not tie_right
            y_lo, y_hi, slope, delta = _edge_setup(x0, y0, x1, y1, first + sy, last + sy)
            for j in range(first, last + 1):
                ys = j + sy
                if _below(y0, ys, ty) == _below(y1, ys, ty):
                    continue
                c = _bound(x0, y0, x1, y1, slope, delta, owned, sx, ys, width, lower)
                keys[row_end[j - lo]] = 2 * c + up
                row_end[j - lo] += 1
        for r in range(rows):
            s0, s1 = row_start[r], row_end[r]
            if s0 == s1:
                continue
            if s1 - s0 <= 24:  # a few crossings, as most rows have: insertion sort
                for i in range(s0 + 1, s1):
                    k = keys[i]
                    m = i - 1
                    while m >= s0 and keys[m] > k:
                        keys[m + 1] = keys[m]
                        m -= 1
                    keys[m + 1] = k
            else:
                heapsort(keys, s0, s1)
            wind = 0
            is_open = False
            start = 0
            end = width
            i = s0
            while i < s1:
                c = keys[i] >> 1
                if c >= width:
                    break  # right of every sample
                while i < s1 and (keys[i] >> 1) == c:
                    wind += 1 if (keys[i] & 1) == 1 else -1
                    i += 1
                if i == s1 and not to_edge:
                    end = c  # the row's last crossing
                inside = (wind & 1) == 1 if evenodd else wind != 0
                if inside and not is_open:
                    start = c
                    is_open = True
                elif not inside and is_open:
                    out_p[n] = p
                    out_y[n] = lo + r
                    out_x0[n] = start
                    out_x1[n] = c
                    n += 1
                    is_open = False
            if is_open and end > start:
                out_p[n] = p
                out_y[n] = lo + r
                out_x0[n] = start
                out_x1[n] = end
                n += 1
    return n


@numba.njit(cache=True)
def _event_counts(a, b, sy, height):  # type: ignore[no-untyped-def]
    """Per edge, an upper bound on its row crossings: the rows its y extent spans."""
    out = np.zeros(a.shape[0], dtype=np.int64)
    for e in range(a.shape[0]):
        if a[e, 1] == b[e, 1]:
            continue
        first, last = _row_range(min(a[e, 1], b[e, 1]), max(a[e, 1], b[e, 1]), sy, height)
        out[e] = max(last - first + 1, 0)
    return out


# -- input handling ------------------------------------------------------------------------


def _empty() -> Spans:
    return tuple(np.empty(0, dtype=np.int64) for _ in range(4))  # type: ignore[return-value]


def _flat(
    contours: Sequence[ArrayLike], path_of_contour: ArrayLike, fill_rule: str, convention: Convention,
    width: int, height: int, check_range: bool,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """The contours validated and snapped, as flat arrays (no per-contour array work).

    Returns
    -------
    vertices : (V, 2) float64
        Every contour's vertices, snapped, one contour after the other.
    lengths : (C,) int64
        Each contour's vertex count.
    paths : (C,) int64
        The path of each contour.
    keep : (C,) bool
        False for the contours of paths with a non-finite vertex (they cover nothing).
    """
    if fill_rule not in FILL_RULES:
        raise ValueError(f"fill_rule must be one of {', '.join(FILL_RULES)}, not {fill_rule!r}")
    if not convention.model.single_sample:
        raise ValueError(f"path_spans takes a single-sample convention, not kind {convention.coverage_kind!r}")
    if width < 0 or height < 0:
        raise ValueError(f"viewport must be non-negative, not {width} x {height}")
    paths = np.asarray(path_of_contour, dtype=np.int64).reshape(-1)
    if paths.size != len(contours):
        raise ValueError(f"path_of_contour has {paths.size} entries for {len(contours)} contours")
    arrays = [np.asarray(contour, dtype=np.float64) for contour in contours]
    for k, v in enumerate(arrays):
        if v.ndim != 2 or v.shape[1] != 2:
            raise ValueError(f"contour {k} must be a (K, 2) array, not of shape {v.shape}")
    lengths = np.array([v.shape[0] for v in arrays], dtype=np.int64)
    return _snapped(np.concatenate(arrays) if arrays else np.empty((0, 2)), lengths, paths, convention, check_range)


def _snapped(
    vertices: NDArray[np.float64], lengths: NDArray[np.int64], paths: NDArray[np.int64], convention: Convention,
    check_range: bool,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """Flat contours snapped, with the contours to keep (see :func:`_flat`)."""
    # input precision, then snapping: Convention.snap applies both, first, exactly
    vertices = convention.snap(vertices)
    finite_xy = np.isfinite(vertices)
    finite_vertex = finite_xy[:, 0] & finite_xy[:, 1]  # two columns, not an axis-1 reduction (10x slower)
    if finite_vertex.all():
        keep = np.ones(lengths.size, dtype=bool)
    else:
        contour_of_vertex = np.repeat(np.arange(lengths.size), lengths)
        finite = np.ones(lengths.size, dtype=bool)
        finite[contour_of_vertex[~finite_vertex]] = False
        keep = ~np.isin(paths, paths[~finite])
    if check_range:
        beyond = _beyond(vertices) & np.repeat(keep, lengths)
        if beyond.any():
            contour_of_vertex = np.repeat(np.arange(lengths.size), lengths)
            k = int(contour_of_vertex[np.flatnonzero(beyond)[0]])
            raise ValueError(
                f"contour {k} has coordinates beyond the exact predicates' range "
                f"(nonzero magnitude below 2**-450 or above 2**450); use path_spans_rational"
            )
    return vertices, lengths, paths, keep


def _beyond(vertices: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(V,) bool: vertices with a finite nonzero coordinate beyond the float filter's range
    (NaN is never beyond; an infinite one is, but its path is dropped anyway)."""
    magnitude = np.abs(vertices)
    out = (magnitude != 0.0) & ((magnitude < SAFE_MIN) | (magnitude > SAFE_MAX))
    beyond: NDArray[np.bool_] = out[:, 0] | out[:, 1]
    return beyond


def _prepare(
    contours: Sequence[ArrayLike], path_of_contour: ArrayLike, fill_rule: str, convention: Convention,
    width: int, height: int, check_range: bool,
) -> tuple[list[NDArray[np.float64]], NDArray[np.int64]]:
    """Validated, snapped contours (those of paths with a non-finite vertex dropped), one
    array each (for the rational reference)."""
    vertices, lengths, paths, keep = _flat(contours, path_of_contour, fill_rule, convention, width, height, check_range)
    split = np.split(vertices, np.cumsum(lengths)[:-1]) if lengths.size else []
    return [split[k] for k in np.flatnonzero(keep)], paths[keep]


# -- public entry points -------------------------------------------------------------------


def path_spans(
    contours: Sequence[ArrayLike],
    path_of_contour: ArrayLike,
    fill_rule: str,
    convention: Convention,
    width: int,
    height: int,
) -> Spans:
    """Exactly which samples each path covers under ``fill_rule`` and ``convention``.

    Parameters
    ----------
    contours : list of (K_i, 2) float64 arrays
        Closed contours: the last vertex joins the first.
    path_of_contour : (C,) int
        The path each contour belongs to; paths are filled independently.
    fill_rule : {"nonzero", "evenodd"}
    convention : Convention
        Of kind ``single``: its sample point, tie rule and snapping apply (snapping to
        every vertex first); its culling is ignored (paths have no culling).
    width, height : int
        The viewport.

    Returns
    -------
    (path, y, x0, x1) : four (S,) int64 arrays
        Maximal spans [x0, x1) of covered samples, sorted by path, row, x0. A path with a
        NaN or infinite vertex covers nothing.

    Raises
    ------
    ValueError
        On a bad argument, or a contour with coordinates beyond the exact predicates'
        range (nonzero |c| < 2**-450 or |c| > 2**450), naming the contour.

    Examples
    --------
    A pentagram: even-odd leaves the centre pentagon out, nonzero fills it.

    >>> import math
    >>> star = np.array([[4 + 3.6 * math.sin(k * 4 * math.pi / 5), 4 - 3.6 * math.cos(k * 4 * math.pi / 5)]
    ...                  for k in range(5)])
    >>> for rule in ("nonzero", "evenodd"):
    ...     p, y, x0, x1 = path_spans([star], [0], rule, Convention(), 8, 8)
    ...     print(rule, [(int(a), int(b), int(c)) for a, b, c in zip(y, x0, x1)])
    nonzero [(2, 3, 5), (3, 1, 7), (4, 3, 5), (5, 2, 6)]
    evenodd [(2, 3, 5), (3, 1, 3), (3, 5, 7), (5, 2, 6)]
    """
    return _spans(*_flat(contours, path_of_contour, fill_rule, convention, width, height, True), fill_rule, convention,
                  width, height)


def _spans(vertices: NDArray[np.float64], lengths: NDArray[np.int64], paths: NDArray[np.int64], keep: NDArray[np.bool_],
           fill_rule: str, convention: Convention, width: int, height: int, unbalanced: str | None = None) -> Spans:
    """:func:`path_spans` on flat, snapped contours; with ``unbalanced`` (``"to-edge"`` or
    ``"last-crossing"``), :func:`open_outline_coverage`'s spans instead: the contours left
    open, rows that stay inside after their last crossing filled as it says."""
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    # edge k runs from vertex k to the next of its contour (the last back to the first)
    ends = np.cumsum(lengths)
    following = np.arange(1, vertices.shape[0] + 1)
    closing = lengths > 0
    following[ends[closing] - 1] = (ends - lengths)[closing]
    kept = np.repeat(keep, lengths)
    if unbalanced is not None:
        kept[ends[closing] - 1] = False  # left open: no edge from a contour's last vertex back to its first
    if kept.all():
        a, b = vertices, np.take(vertices, following, axis=0)  # take: 2-D fancy indexing is 15x slower
    else:
        used = np.flatnonzero(kept)
        a, b = np.take(vertices, used, axis=0), np.take(vertices, following[used], axis=0)
    # paths by rank (0 .. P - 1) in the kernel, their own ids on the way out; the kernel
    # takes each path's edges together. A PathScene's contours name 0 .. P - 1, most often
    # in order: then the ranks are the ids and the edges already grouped.
    step = np.diff(paths)
    in_order = paths.size > 0 and paths[0] == 0 and bool(np.all((step == 0) | (step == 1)))
    if in_order:
        n_paths = int(paths[-1]) + 1
        edge_path = np.repeat(paths, lengths) if kept.all() else np.repeat(paths, lengths)[used]
    else:
        names, rank = np.unique(paths, return_inverse=True)
        n_paths = names.size
        edge_path = np.repeat(rank.reshape(-1), lengths) if kept.all() else np.repeat(rank.reshape(-1), lengths)[used]
        if edge_path.size and np.any(edge_path[1:] < edge_path[:-1]):
            order = np.argsort(edge_path, kind="stable")
            a, b, edge_path = np.take(a, order, axis=0), np.take(b, order, axis=0), edge_path[order]
    first_edge = frozen(np.searchsorted(edge_path, np.arange(n_paths + 1)), np.int64)
    a, b = frozen(a), frozen(b)
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    # each path's room: its edges' row counts summed (a path may have no edge left: one
    # with a non-finite vertex is dropped, so no reduceat, which reads past the end then)
    summed = np.concatenate([[0], np.cumsum(_event_counts(a, b, sy, height))])
    per_path = summed[first_edge[1:]] - summed[first_edge[:-1]]
    keys = np.empty(int(per_path.max(initial=0)), dtype=np.int64)
    capacity = int(per_path.sum())  # a row's spans are at most half its crossings
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    m = int(_paths_kernel(a, b, first_edge, sx, sy, tx, ty, y_first, fill_rule == "evenodd", unbalanced != "last-crossing",
                          width, height,
                          keys, np.empty(height + 2, dtype=np.int64), np.empty(height + 2, dtype=np.int64), *out))
    p = out[0][:m] if in_order else names[out[0][:m]]
    return p, out[1][:m], out[2][:m], out[3][:m]


UNBALANCED_ROWS = ("last-crossing", "to-edge")


def open_outline_coverage(scene: AnyScene, convention: Convention, unbalanced: str) -> Coverage:
    """What a filler draws that builds its edges from consecutive vertex pairs only and so
    leaves every contour (every triangle: its edge from the third vertex back to the first)
    open -- the classic "forgot to close the path" bug, as the oracle of a hypothesis.

    Without its closing edge a contour's crossings need not balance: a row may stay inside
    after its last crossing. ``unbalanced`` says what is drawn there: ``"last-crossing"``
    (nothing right of a row's last crossing, as a trapezoid or active-edge filler emits
    spans between crossings) or ``"to-edge"`` (a span left open runs to the viewport's
    right edge, as a scanline filler that fills until the winding returns to zero).
    Everything else is :func:`path_coverage`'s: the same crossings, ties, snapping and
    fill rule (triangles: one path each, nonzero; culling ignored), for any finite float.
    Single-sample only.

    >>> from harness.contract.scenes import Scene
    >>> tri = Scene(4, 4, np.array([[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]]))  # closing edge: (0, 4) -> (0, 0)
    >>> [len(open_outline_coverage(tri, Convention(), rule)) for rule in UNBALANCED_ROWS]  # 4 rows, each crossing once
    [0, 4]
    """
    if unbalanced not in UNBALANCED_ROWS:
        raise ValueError(f"unbalanced must be one of {', '.join(UNBALANCED_ROWS)}, not {unbalanced!r}")
    if not convention.model.single_sample:
        raise ValueError(f"open_outline_coverage takes a single-sample convention, not kind {convention.coverage_kind!r}")
    if PATHS.owns(scene):
        vertices, sizes, paths, fill_rule = scene.vertices, scene.contour_sizes, scene.contour_path, scene.fill_rule
    else:  # each triangle a one-contour path (ValueError for lines: no outline to leave open)
        n = len(scene)
        vertices, sizes, paths = TRIANGLES.narrow(scene).positions.reshape(-1, 2), np.full(n, 3), np.arange(n)
        fill_rule = "nonzero"
    vertices, lengths, paths, keep = _snapped(vertices, sizes, paths, convention, False)
    beyond = _beyond(vertices) & np.repeat(keep, lengths)
    unsafe = np.unique(np.repeat(paths, lengths)[beyond])
    p, y, x0, x1 = _spans(vertices, lengths, paths, keep & ~np.isin(paths, unsafe), fill_rule, convention,
                          scene.width, scene.height, unbalanced)
    if unsafe.size:  # beyond the float filter: row by row in rational arithmetic, as path_coverage
        ends = np.cumsum(lengths)
        extra = [(int(path), j, a, b) for path in unsafe
                 for j, a, b in _rows_rational([(float(u[0]), float(u[1]), float(v[0]), float(v[1]))
                                                for c in np.flatnonzero(paths == path)
                                                for u, v in zip(vertices[ends[c] - lengths[c]:ends[c] - 1],
                                                                vertices[ends[c] - lengths[c] + 1:ends[c]])],
                                               fill_rule, convention, scene.width, scene.height, unbalanced)]
        if extra:
            more = np.array(extra, dtype=np.int64).T
            p, y, x0, x1 = (np.concatenate([u, w]) for u, w in zip((p, y, x0, x1), more))
        order = np.lexsort((x0, y, p))
        p, y, x0, x1 = p[order], y[order], x0[order], x1[order]
    return Coverage(p, y, x0, x1)


def path_spans_rational(
    contours: Sequence[ArrayLike],
    path_of_contour: ArrayLike,
    fill_rule: str,
    convention: Convention,
    width: int,
    height: int,
) -> Spans:
    """The same spans as :func:`path_spans` by brute force in rational arithmetic: for
    every sample, the winding number of the symbolically perturbed sample point by an
    exact crossing count. Any finite float; slow (small viewports only).

    Every quantity is a triple (value, eps coefficient, eps**2 coefficient) compared in
    lexicographic order: the sample is ``(xs, ys) + (tx*eps, ty*eps**2)`` (x-first) or
    ``+ (tx*eps**2, ty*eps)`` (y-first). Edge a -> b crosses the sample's horizontal
    line when exactly one end lies below it; the crossing lies left of the sample when
    the edge function E_ab at the sample, a linear function of the triple, has the sign
    of -(by - ay); each such crossing adds sign(by - ay).
    """
    kept, paths = _prepare(contours, path_of_contour, fill_rule, convention, width, height, False)
    sx, sy = (Fraction(v) for v in convention.sample)
    tx, ty, y_first = convention.tie_perturbation
    dx = (0, tx) if y_first else (tx, 0)  # (eps, eps**2) coefficients of the x offset
    dy = (ty, 0) if y_first else (0, ty)
    by_path: dict[int, list[tuple[Fraction, Fraction, Fraction, Fraction]]] = {}
    for v, p in zip(kept, paths):
        fv = [(Fraction(float(x)), Fraction(float(y))) for x, y in v]
        edges = by_path.setdefault(int(p), [])
        for k in range(len(fv)):
            (ax, ay), (bx, by) = fv[k], fv[(k + 1) % len(fv)]
            edges.append((ax, ay, bx, by))
    spans: list[tuple[int, int, int, int]] = []

    def sign3(t: tuple[Fraction, Fraction, Fraction]) -> int:
        for value in t:
            if value:
                return 1 if value > 0 else -1
        return 0

    for p in sorted(by_path):
        edges = by_path[p]
        for j in range(height):
            ys = j + sy
            qy = (ys, Fraction(dy[0]), Fraction(dy[1]))
            covered = []
            for i in range(width):
                xs = i + sx
                qx = (xs, Fraction(dx[0]), Fraction(dx[1]))
                wind = 0
                for ax, ay, bx, by in edges:
                    below_a = sign3((ay - qy[0], -qy[1], -qy[2])) > 0
                    below_b = sign3((by - qy[0], -qy[1], -qy[2])) > 0
                    if below_a == below_b:
                        continue
                    e = ((bx - ax) * (qy[0] - ay) - (by - ay) * (qx[0] - ax),
                         (bx - ax) * qy[1] - (by - ay) * qx[1],
                         (bx - ax) * qy[2] - (by - ay) * qx[2])
                    d = 1 if by > ay else -1
                    if sign3(e) * d < 0:  # the sample is right of the crossing
                        wind += d
                covered.append(wind % 2 == 1 if fill_rule == "evenodd" else wind != 0)
            i = 0
            while i < width:
                if covered[i]:
                    k = i
                    while k < width and covered[k]:
                        k += 1
                    spans.append((p, j, i, k))
                    i = k
                else:
                    i += 1
    if not spans:
        return _empty()
    arr = np.array(spans, dtype=np.int64).T
    return arr[0], arr[1], arr[2], arr[3]




def _rows_rational(edges: list[tuple[float, float, float, float]], fill_rule: str, convention: Convention,
                   width: int, height: int, unbalanced: str | None = None) -> list[tuple[int, int, int]]:
    """One path's spans (row, x0, x1) row by row in exact rational arithmetic: the same
    method as the kernels (crossings per sample row, placed exactly), for any finite
    float -- the oracle's way for paths whose coordinates the float filter cannot take.
    A row still inside after its last crossing (edges that do not close) ends at that
    crossing when ``unbalanced`` is ``"last-crossing"``, else at the viewport's edge."""
    sx, sy = (Fraction(v) for v in convention.sample)
    tx, ty, y_first = convention.tie_perturbation
    exact = [tuple(Fraction(c) for c in e) for e in edges if e[1] != e[3]]  # horizontal edges never cross
    out: list[tuple[int, int, int]] = []
    for j in range(height):
        ys = j + sy
        events: list[tuple[int, int]] = []
        for ax, ay, bx, by in exact:
            # below: greater y, or on the row and perturbed upwards (ty < 0)
            if ((ay > ys) or (ay == ys and ty < 0)) == ((by > ys) or (by == ys and ty < 0)):
                continue
            direction = 1 if by > ay else -1
            crossing = ax + (ys - ay) * (bx - ax) / (by - ay)
            # the first column whose sample lies right of the crossing; on it, the tie rule
            # says (see the module docstring)
            column = math.floor(crossing - sx)
            on = column + sx == crossing
            if not on or not (tx > 0 if (not y_first or ax == bx) else (bx - ax) * (by - ay) * ty < 0):
                column += 1
            events.append((min(max(column, 0), width), direction))
        events.sort()
        wind, start = 0, None
        for k, (column, direction) in enumerate(events):
            wind += direction
            if k + 1 < len(events) and events[k + 1][0] == column:
                continue
            inside = wind % 2 == 1 if fill_rule == "evenodd" else wind != 0
            if inside and start is None:
                start = column
            elif not inside and start is not None:
                if column > start:
                    out.append((j, start, column))
                start = None
        end = events[-1][0] if unbalanced == "last-crossing" and events else width
        if start is not None and end > start:
            out.append((j, start, end))
    return out


def path_coverage(scene: PathScene, convention: Convention) -> Coverage:
    """The exact coverage of a path scene (:func:`harness.oracle.coverage.exact_coverage` for paths).

    Single-sample: :func:`path_spans`; multisample: the same at each sample offset, spans
    carrying their sample index, sorted by path, sample and row; supersampled area: the
    share of the pattern's samples per pixel as alpha; analytic area: the area where the
    fill rule holds (:func:`harness.oracle.path_area.path_area_coverage`). Paths whose
    coordinates lie beyond the float filter's range are decided row by row in rational
    arithmetic (exact for any finite float).

    >>> from harness.contract.scenes import PathScene
    >>> square = PathScene.from_paths(2, 2, [[[[0, 0], [2, 0], [2, 2], [0, 2]]]])
    >>> path_coverage(square, Convention(samples=4)).sample.tolist()  # one span per row and sample
    [0, 0, 1, 1, 2, 2, 3, 3]
    """
    if convention.model.path_oracle:  # a model deciding paths its own way (the closed rule: ftraster.c's scan)
        own: Coverage = convention.model.exact_paths(scene, convention)
        return own
    if not convention.model.paths:
        if not convention.model.alphas:
            raise ValueError(f"{convention.model.declared_as(convention)} coverage of paths is not defined yet (triangles only)")
        raise ValueError("analytic area coverage of paths is not defined yet: give the area convention a sample pattern")
    if convention.model.alphas and convention.samples is None:
        from harness.oracle.path_area import path_area_coverage  # the analytic area of a path (issue 34)
        return path_area_coverage(scene, convention)
    offsets = convention.samples if convention.samples is not None else (convention.sample,)
    layers = [_path_layer(scene, replace(convention.at_sample(s) if convention.samples is not None else convention,
                                         sample=offset))
              for s, offset in enumerate(offsets)]
    if convention.model.single_sample:
        return layers[0]
    if convention.model.alphas:
        return shares_of_layers(layers, scene.height, convention.n_samples)
    marked = [Coverage(c.primitive, c.y, c.x0, c.x1, None, np.full(len(c), s)) for s, c in enumerate(layers)]
    joined = Coverage.concat(marked)
    return joined.take(np.argsort(joined.primitive, kind="stable"))


def _path_layer(scene: PathScene, convention: Convention) -> Coverage:
    """One sample's exact coverage of a path scene."""
    vertices, lengths, paths, keep = _snapped(scene.vertices, scene.contour_sizes, scene.contour_path, convention, False)
    beyond_vertex = _beyond(vertices)
    if beyond_vertex.any():
        unsafe_paths = np.unique(np.repeat(paths, lengths)[beyond_vertex & np.repeat(keep, lengths)])
        keep = keep & ~np.isin(paths, unsafe_paths)
    else:
        unsafe_paths = np.zeros(0, dtype=np.int64)
    p, y, x0, x1 = _spans(vertices, lengths, paths, keep, scene.fill_rule, convention, scene.width, scene.height)
    if not unsafe_paths.size:
        return Coverage(p, y, x0, x1)
    a, b, owner = scene.edges()
    # input precision, then snapping: Convention.snap applies both, first, exactly
    a, b = convention.snap(a), convention.snap(b)
    extra = [(int(path), j, s, e) for path in unsafe_paths
             for j, s, e in _rows_rational([(float(a[k, 0]), float(a[k, 1]), float(b[k, 0]), float(b[k, 1]))
                                            for k in np.flatnonzero(owner == path)],
                                           scene.fill_rule, convention, scene.width, scene.height)]
    if extra:
        more = np.array(extra, dtype=np.int64).T
        p, y, x0, x1 = (np.concatenate([u, v]) for u, v in zip((p, y, x0, x1), more))
    order = np.lexsort((x0, y, p))
    return Coverage(p[order], y[order], x0[order], x1[order])
