"""``trapezoid_fill``: the seed's trapezoid (active edge list) polygon fill under the
nonzero and even-odd rules (seed 002).

Each path is filled in one go, by the classic scanline over an edge table:

1. *Edge table.* Every edge of every closed contour (the last vertex joins the first),
   with the sample rows it crosses, sorted by its first row. An edge crosses the row
   ``ys = j + sy`` when exactly one of its ends lies below the row (greater y), so
   horizontal and zero-length edges cross nothing.
2. *Bands.* Between two consecutive event rows (where an edge enters or leaves) the
   active edge list does not change: each pair of neighbouring active edges bounds a
   trapezoid of the seed's decomposition. Within a band, each sample row takes every
   active edge's crossing column, re-sorts the list by it (insertion sort: the order
   changes only where edges intersect; edges entering the list are sorted apart and
   merged in) and sums the winding from left to right.
3. *Spans.* Between consecutive crossings the winding is constant; a span is emitted
   where the fill rule holds (``nonzero``: w != 0; ``evenodd``: w odd). Crossings are
   counted left of the sample, which negates the winding of a closed path: neither rule
   cares.

Exactness. Which rows an edge crosses is decided by float comparisons of vertex heights
with ``j + sy`` (exact). Where a row crosses an edge is computed in float with a
rigorous error bound; when a sample lies within the bound, the exact predicate
:func:`harness.geometry.exact.orient2d_sign` confirms the float guess at the two columns around
it (stepping or bisecting when the guess is off), so every decision is the exact one
for coordinates of magnitude 0 or within [2**-450, 2**450]
(:data:`harness.geometry.exact.SAFE_MIN`, :data:`~harness.geometry.exact.SAFE_MAX`); a path with a
coordinate outside that range is refused (ValueError naming it).

Ties follow the tie rule's symbolic perturbation (:mod:`harness.oracle.winding`): the sample
``p`` is decided at ``q = p + d(eps)``. A vertex exactly on a sample row lies above q
when q moves down (top rules: an edge crosses rows ``ylo <= ys < yhi``) and below it
when q moves up (``ylo < ys <= yhi``). A sample exactly on an edge's line lies right of
its crossing when q moves right first (x-first rules, and vertical edges under y-first
ones); under the y-first rules a slanted edge's crossing itself moves by
``(dx/dy)*ty*eps`` while q's x moves by O(eps**2), so q is right of it when
``dx*dy*ty < 0``. A triangle scene is filled as one single-contour path per triangle
(either rule: a triangle's winding is 0 or +/-1).

Convention: sample (0.5, 0.5), ``top-left`` ties, no snapping, no culling (a fill rule,
not an orientation, decides what a path covers). Any of the eight tie rules may be chosen:
``TrapezoidFill(tie="bottom-right")``.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import TIE_RULES, Convention, TieRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, PathScene, Scene, Unsupported
from harness.geometry.exact import SAFE_MAX, SAFE_MIN, frozen, orient2d_sign
from harness.geometry.kernel_sorts import heapsort_pairs

__all__ = ["TrapezoidFill", "outline", "trapezoid_spans", "crossing_column", "edge_table"]


# Cached on disk like every kernel. They were compiled in each process for a while: xdist
# workers crashed (segfault) inside _sweep when two processes had compiled and saved the
# same callee (harness.geometry.exact's kernels) side by side and a third loaded both builds.
# harness.geometry.numba_cache now lets one process at a time compile each cached kernel, so the
# second loads the first one's build (the crash's recipe from session 12, a side-by-side
# warm-up then the path fillers in one process: 3 crashes in 3 tries before, none in 3 after).
_CACHE = True

Spans = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]


# -- the edge table --------------------------------------------------------------------------


@numba.njit(cache=_CACHE, inline="always")
def _above(v, ys, ty):  # type: ignore[no-untyped-def]
    """Whether a vertex at height v lies above (not below) the perturbed row ys + ty*eps."""
    # The tie rule's vertical half: a vertex on the row is above a sample that moves down.
    return v < ys or (v == ys and ty > 0)


@numba.njit(cache=_CACHE)
def _first_row_under(v, sy, ty, height):  # type: ignore[no-untyped-def]
    """The first row j in [0, height] whose perturbed sample lies below height v (v above
    it), ``height`` when none: from a float estimate, then exact comparisons (j + sy is
    exact for every row of a viewport)."""
    t = v - sy
    if not t > -1.0:
        j = 0
    elif t > height:
        j = height
    else:
        j = int(math.ceil(t))
    while j > 0 and _above(v, j - 1 + sy, ty):
        j -= 1
    while j < height and not _above(v, j + sy, ty):
        j += 1
    return j


@numba.njit(cache=_CACHE)
def edge_table(ax, ay, bx, by, sy, tx, ty, y_first, height, first, last, tie_right):  # type: ignore[no-untyped-def]
    """Per edge a -> b: the first and last viewport row it crosses (``first > last`` when
    none) and whether a sample exactly on its line lies right of its crossing."""
    for e in range(ax.size):
        if ay[e] == by[e]:  # horizontal or zero-length: both ends on one side of every row
            first[e] = height
            last[e] = -1
            tie_right[e] = False
            continue
        lo = min(ay[e], by[e])
        hi = max(ay[e], by[e])
        # rows with the top end above and the bottom end below: [ylo, yhi) for top rules
        first[e] = _first_row_under(lo, sy, ty, height)
        last[e] = _first_row_under(hi, sy, ty, height) - 1
        # On the line: the perturbation's first-order x term decides (see the docstring).
        if y_first and ax[e] != bx[e]:
            tie_right[e] = ((bx[e] > ax[e]) == (by[e] > ay[e])) != (ty > 0)
        else:
            tie_right[e] = tx > 0


# -- where a row crosses an edge --------------------------------------------------------------


@numba.njit(cache=_CACHE, inline="always")
def _right_of(ax, ay, bx, by, tie_right, xs, ys):  # type: ignore[no-untyped-def]
    """Whether the perturbed sample (xs, ys) lies right of edge a-b's crossing of its row."""
    s = orient2d_sign(ax, ay, bx, by, xs, ys)
    if s == 0:
        return tie_right  # on the edge's line: the tie rule says
    # E_ab falls as x grows for an edge running down the screen: right of it is E < 0.
    return (s < 0) == (by > ay)


# |fl(x) - X| for the float crossing x = ax + (bx-ax)*((ys-ay)/(by-ay)) of the exact X:
# the quotient and product carry 5 roundings (relative 5.001 u, u = 2**-53, on |p|), the
# sum one more (u on |ax| + |p|): at most 6.01 u (|ax| + |p|). 8 u = 2**-50 also covers the
# rounding of x -/+ bound itself. Within the exact range nothing underflows (|p| >= 2**-1006);
# an overflow makes x inf or NaN, which no test below passes. The 2**-1000 keeps x_lo < x_hi.
_CROSSING_ERROR = 2.0**-50


@numba.njit(cache=_CACHE)
def crossing_column(ax, ay, bx, by, tie_right, sx, ys, width):  # type: ignore[no-untyped-def]
    """The first column c in [0, width] whose perturbed sample (c + sx, ys) lies right of
    the (non-horizontal) edge a-b's crossing of row ys; ``width`` when none does.

    Fast path: the float crossing with a rigorous error bound; when no sample lies within
    the bound, no sample is on the edge and the column follows from comparisons. Else the
    exact predicate decides: "right of" is monotone in the column, so it confirms the
    float guess at c - 1 and c, stepping once or bisecting when the guess is off (as it
    may be far out, where the float crossing overflows or loses its digits)."""
    p = (bx - ax) * ((ys - ay) / (by - ay))
    x = ax + p
    bound = _CROSSING_ERROR * (abs(ax) + abs(p)) + 2.0**-1000
    x_lo = x - bound
    x_hi = x + bound
    if x_hi < sx:  # every sample lies right of the crossing
        return 0
    if x_lo > width - 1 + sx:  # every sample lies left of it
        return width
    if x_lo > sx - 1.0 and x_hi < width + sx:  # (false for NaN)
        c = int(math.ceil(x - sx))
        if c - 1 + sx < x_lo and x_hi < c + sx:  # samples c - 1 and c lie either side of [x_lo, x_hi]
            return c
    else:
        e = x - sx
        if not e > -1.0:  # NaN too
            c = 0
        elif e > width:
            c = width
        else:
            c = int(math.ceil(e))
    c = min(max(c, 0), width)
    if c < width and not _right_of(ax, ay, bx, by, tie_right, c + sx, ys):
        if c + 1 >= width or _right_of(ax, ay, bx, by, tie_right, c + 1 + sx, ys):
            return c + 1
        lo, hi = c + 1, width  # right_of(lo) is false; hi stands for "right of all"
    else:
        if c == 0 or not _right_of(ax, ay, bx, by, tie_right, c - 1 + sx, ys):
            return c
        if c == 1 or not _right_of(ax, ay, bx, by, tie_right, c - 2 + sx, ys):
            return c - 1
        lo, hi = -1, c - 2  # right_of(hi) is true; lo stands for "left of all"
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _right_of(ax, ay, bx, by, tie_right, mid + sx, ys):
            hi = mid
        else:
            lo = mid
    return hi


# -- the sweep ---------------------------------------------------------------------------------


@numba.njit(cache=_CACHE, inline="always")
def _insertion_sort(column, active, lo, hi):  # type: ignore[no-untyped-def]
    """Sort active[lo:hi] by column[lo:hi] in place (stable; linear when nearly sorted)."""
    for k in range(lo + 1, hi):
        c = column[k]
        a = active[k]
        i = k - 1
        while i >= lo and column[i] > c:
            column[i + 1] = column[i]
            active[i + 1] = active[i]
            i -= 1
        column[i + 1] = c
        active[i + 1] = a


@numba.njit(cache=_CACHE, inline="always")
def _merge(column, active, mid, hi, spare_column, spare_active):  # type: ignore[no-untyped-def]
    """Merge the sorted runs [0, mid) and [mid, hi) of (column, active) in place."""
    for k in range(mid):  # (element by element: a slice assignment compiled numba's shape-error path, 2.5 s)
        spare_column[k] = column[k]
        spare_active[k] = active[k]
    i, k, out = 0, mid, 0
    while i < mid:
        if k < hi and column[k] < spare_column[i]:
            column[out] = column[k]
            active[out] = active[k]
            k += 1
        else:
            column[out] = spare_column[i]
            active[out] = spare_active[i]
            i += 1
        out += 1


@numba.njit(cache=_CACHE)
def _sweep(ax, ay, bx, by, winding, tie_right, first, last, order, bounds, sx, sy, evenodd, width, height,  # type: ignore[no-untyped-def]
           out_p, out_y, out_x0, out_x1):
    """Spans (path, row, x0, x1), sorted by path, row and x0, of every path.

    ``order`` lists the edges that cross a viewport row, sorted by path and first row;
    path p's are ``order[bounds[p]:bounds[p + 1]]`` (the edge table). ``winding[e]`` is
    what a crossing of edge e adds to the winding of the samples right of it. Returns
    the number of spans."""
    n = 0
    active = np.empty(order.size, dtype=np.int64)  # the active edge list
    column = np.empty(order.size, dtype=np.int64)  # each active edge's crossing column
    spare_active = np.empty(order.size, dtype=np.int64)
    spare_column = np.empty(order.size, dtype=np.int64)
    for p in range(bounds.size - 1):
        ptr = bounds[p]
        end = bounds[p + 1]
        n_active = 0
        j = 0
        while ptr < end or n_active > 0:
            if n_active == 0:
                j = max(j, first[order[ptr]])  # no edge active: skip to the next one's row
            n_before = n_active
            while ptr < end and first[order[ptr]] <= j:  # edges entering at row j
                active[n_active] = order[ptr]
                column[n_active] = 0
                n_active += 1
                ptr += 1
            # The band: rows until an edge enters or leaves. Its active edges are fixed,
            # each neighbouring pair bounding one trapezoid.
            stop = first[order[ptr]] if ptr < end else height
            for k in range(n_active):
                stop = min(stop, last[active[k]] + 1)
            for row in range(j, stop):
                ys = row + sy
                for k in range(n_active):
                    e = active[k]
                    column[k] = crossing_column(ax[e], ay[e], bx[e], by[e], tie_right[e], sx, ys, width)
                if row == j and n_before < n_active:
                    # the band's first row: the edges kept keep nearly their order, the
                    # entering ones (in contour order) are sorted apart and merged in
                    _insertion_sort(column, active, 0, n_before)
                    heapsort_pairs(column, active, n_before, n_active)  # O(k log k) whatever their order
                    _merge(column, active, n_before, n_active, spare_column, spare_active)
                else:
                    _insertion_sort(column, active, 0, n_active)  # the last row's order is nearly right
                # Winding from left to right; between crossings it is constant.
                wind = 0
                is_open = False
                start = 0
                k = 0
                while k < n_active:
                    c = column[k]
                    while k < n_active and column[k] == c:
                        wind += winding[active[k]]
                        k += 1
                    inside = (wind & 1) == 1 if evenodd else wind != 0
                    if inside and not is_open:
                        start = c
                        is_open = True
                    elif not inside and is_open:
                        out_p[n] = p
                        out_y[n] = row
                        out_x0[n] = start
                        out_x1[n] = c
                        n += 1
                        is_open = False
                # (a span still open here would have no right edge: closed contours
                # always bring the winding back to 0 after the last crossing)
            j = stop
            kept = 0
            for k in range(n_active):  # edges leaving: their last row is behind
                if last[active[k]] >= j:
                    active[kept] = active[k]
                    column[kept] = column[k]
                    kept += 1
            n_active = kept
    return n


# -- numpy at the boundaries -------------------------------------------------------------------


def outline(scene: Scene | PathScene) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Every edge a -> b of the scene's closed contours and its primitive: a path's
    contours, or a triangle as a one-contour path.

    Returns
    -------
    a, b : (E, 2) float64
    primitive : (E,) int64
    """
    if isinstance(scene, PathScene):
        return scene.edges()
    positions = scene.positions
    return (positions.reshape(-1, 2), np.roll(positions, -1, axis=1).reshape(-1, 2),
            np.repeat(np.arange(len(scene), dtype=np.int64), 3))


def trapezoid_spans(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    primitive: NDArray[np.int64],
    n_primitives: int,
    evenodd: bool,
    convention: Convention,
    width: int,
    height: int,
    winding: NDArray[np.int64] | None = None,
) -> Spans:
    """The spans of closed paths given edge by edge, under a single-sample convention.

    Parameters
    ----------
    a, b : (E, 2) float64
        Edge a -> b; finite, each coordinate 0 or of magnitude in [2**-450, 2**450].
    primitive : (E,) int64
        The path of each edge, in 0 .. n_primitives - 1.
    n_primitives : int
    evenodd : bool
        The even-odd rule; else nonzero.
    convention : Convention
        Its sample point and tie rule apply (not its snapping or culling).
    width, height : int
    winding : (E,) int64, optional
        What each edge's crossing adds to the winding; ``sign(by - ay)`` when None.

    Returns
    -------
    (primitive, y, x0, x1) : four (S,) int64 arrays
        Maximal spans, sorted by primitive, row and x0.
    """
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    ax, ay, bx, by = (frozen(c) for c in (a[:, 0], a[:, 1], b[:, 0], b[:, 1]))
    first = np.empty(ax.size, dtype=np.int64)
    last = np.empty(ax.size, dtype=np.int64)
    tie_right = np.empty(ax.size, dtype=np.bool_)
    edge_table(ax, ay, bx, by, sy, tx, ty, y_first, height, first, last, tie_right)
    if winding is None:
        winding = np.where(by > ay, 1, -1).astype(np.int64)
    crossing = np.flatnonzero(first <= last)
    order = crossing[np.lexsort((first[crossing], primitive[crossing]))]
    bounds = np.searchsorted(primitive[order], np.arange(n_primitives + 1)).astype(np.int64)
    capacity = int((last[order] - first[order] + 1).sum())  # a span per crossing at most
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    n = int(_sweep(ax, ay, bx, by, frozen(winding, np.int64), frozen(tie_right, np.bool_), frozen(first, np.int64),
                   frozen(last, np.int64), frozen(order, np.int64), bounds, sx, sy, evenodd, width, height, *out))
    return out[0][:n], out[1][:n], out[2][:n], out[3][:n]


@numba.njit(cache=_CACHE)
def _screen(a, primitive, n):  # type: ignore[no-untyped-def]
    """Per primitive whether all its vertices are finite ((n,) bool), and the first edge
    of a finite primitive with a coordinate beyond the exact range (-1 when none)."""
    finite = np.ones(n, dtype=np.bool_)
    for e in range(a.shape[0]):
        if not (np.isfinite(a[e, 0]) and np.isfinite(a[e, 1])):
            finite[primitive[e]] = False
    for e in range(a.shape[0]):
        if finite[primitive[e]]:
            for c in range(2):
                m = abs(a[e, c])
                if m != 0.0 and (m < SAFE_MIN or m > SAFE_MAX):
                    return finite, e
    return finite, -1


def screen_edges(scene: Scene | PathScene, rasterizer: str) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """:func:`outline` without the primitives that hold a NaN or infinite coordinate (they
    cover nothing); ValueError naming the first primitive with a coordinate beyond the
    exact predicates' range."""
    a, b, primitive = outline(scene)
    finite, beyond = _screen(frozen(a), frozen(primitive, np.int64), len(scene))
    if beyond >= 0:
        k = int(primitive[beyond])
        raise ValueError(f"{rasterizer}: {scene.noun} {k} has a coordinate of magnitude beyond the exact predicates' range "
                         f"(nonzero and below 2**-450 or above 2**450)")
    if finite.all():
        return a, b, primitive
    kept = finite[primitive]
    return a[kept], b[kept], primitive[kept]


class TrapezoidFill:
    """The seed's trapezoid (active edge list) fill of paths, and of triangles as paths.

    Examples
    --------
    A square with a square hole wound the same way: nonzero fills the hole, even-odd not.

    >>> from harness.contract.scenes import PathScene
    >>> outer, hole = [[0, 0], [4, 0], [4, 4], [0, 4]], [[1, 1], [3, 1], [3, 3], [1, 3]]
    >>> for rule in ("nonzero", "evenodd"):
    ...     print(rule, TrapezoidFill().rasterize(PathScene.from_paths(4, 4, [[outer, hole]], rule)).counts(4, 4)[1])
    nonzero [1 1 1 1]
    evenodd [1 0 0 1]
    """

    name = "trapezoid_fill"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")
    scene_kinds = ("triangles", "paths")
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def __init__(self, tie: TieRule = "top-left") -> None:
        if tie not in TIE_RULES:
            raise ValueError(f"trapezoid_fill: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        if tie != "top-left":
            self.name = f"trapezoid_fill_{tie}"
            self.convention = Convention(sample=(0.5, 0.5), tie=tie)

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, (Scene, PathScene)):
            raise Unsupported(f"{self.name} fills triangles and paths, not {scene.kind}")
        a, b, primitive = screen_edges(scene, self.name)
        evenodd = isinstance(scene, PathScene) and scene.fill_rule == "evenodd"
        return Coverage(*trapezoid_spans(a, b, primitive, len(scene), evenodd, self.convention, scene.width, scene.height))
