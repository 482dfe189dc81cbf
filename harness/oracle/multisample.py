"""The exact multisample oracle in one pass: every sample of a pattern decided per triangle
from one setup (issue 35).

The standard multisample rule (D3D11, Vulkan, GL) decides each sample of a pattern as the
single-sample oracle decides its one sample, at the sample's own offset, under the same tie
rule, snapping and culling. Everything but the sample rows is the same for every sample:
the snapped vertices, the exact orientation, culling and which edges own their ties
(:class:`harness.oracle.coverage.PreparedTriangles`), and each edge's slope and error
bound. So the triangle is prepared once, and each sample row's crossings are decided from
the same prepared edges with the single-sample oracle's own pieces
(:func:`harness.oracle.kernels._bound`: the float filter with its proven error bound, the
exact predicate where a column boundary lies within it). A sample row strictly between
the vertices' heights meets two edges, the long one and a short one, and only those two
are evaluated there; on a triangle well inside the viewport no crossing is clamped and
the filter is the same arithmetic without the clamping. Those rows' loop runs the float
filters alone, with no call in it (the exact fallback inline, or a call to it, kept the
loop's values out of registers: 6.5 ms for the 8x pattern on W1, 4.5 without): a row the
filter is unsure of (a column boundary within the crossing's bound, rare) is written with
a -1 column and settled exactly after the whole pass (:func:`_settle_spans`, which also
drops the rows it leaves empty). The spans are written in the
order :func:`harness.oracle.coverage.exact_multisample` returns them (triangle, sample,
row): no sort, no concatenation. The supersampled area oracle counts, per pixel row, the
samples of all the pattern's sample rows on that row together.

The former path -- the single-sample oracle once per offset, then concatenated and sorted
-- stays as the reference (:func:`harness.oracle.coverage.exact_multisample_layers`,
:func:`harness.oracle.coverage.sample_shares_layers`); the tests compare the two bit for
bit. Triangles beyond the expansions' safe range take that path (exact rationals).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.samples import FRACTION_BITS
from harness.contract.scenes import Scene
from harness.oracle.kernels import _apply_edge, _bound, _edge_setup, _filtered_bound, _row_range, interpolate_at

__all__ = ["multisample_spans", "fused_samples", "fused_shares", "Prepared"]


# sample offsets are multiples of 2**-FRACTION_BITS, so are the sample rows j + sy
_LATTICE = 2.0**FRACTION_BITS


class Prepared(Protocol):
    """What the kernels read of a scene's prepared triangles
    (:class:`harness.oracle.coverage.PreparedTriangles`: snapped, oriented, culled, their
    edges' owners classified under the convention -- the same for every sample)."""

    @property
    def snapped(self) -> NDArray[np.float64]: ...
    @property
    def sign(self) -> NDArray[np.int8]: ...
    @property
    def owned(self) -> NDArray[np.bool_]: ...
    @property
    def active(self) -> NDArray[np.bool_]: ...
    @property
    def safe(self) -> NDArray[np.bool_]: ...
    @property
    def positions(self) -> NDArray[np.float64]: ...


@numba.njit(cache=True, inline="always")
def _oriented(positions, sign, t):  # type: ignore[no-untyped-def]
    # Vertices in oriented order (A > 0): swap the last two when A < 0.
    v1, v2 = (1, 2) if sign[t] > 0 else (2, 1)
    return (positions[t, 0, 0], positions[t, 0, 1], positions[t, v1, 0], positions[t, v1, 1],
            positions[t, v2, 0], positions[t, v2, 1])


@numba.njit(cache=True, inline="always")
def _exact_rows(y_lo, y_hi, sy, first, last):  # type: ignore[no-untyped-def]
    """The rows j of [first, last] with y_lo <= j + sy <= y_hi (j + sy is exact): the
    conservative range of _row_range may overshoot by a row at either end."""
    while first <= last and first + sy < y_lo:
        first += 1
    while first <= last and last + sy > y_hi:
        last -= 1
    return first, last


@numba.njit(cache=True)
def _sample_rows(positions, use, offsets, height):  # type: ignore[no-untyped-def]
    """How many (triangle, sample, row) the used triangles' sample rows make: rows j of
    the viewport with ymin <= j + sy <= ymax, for each sample -- the spans the kernel may
    write (it writes at most one per such row)."""
    total = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        ymin = min(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        ymax = max(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        for s in range(offsets.shape[0]):
            sy = offsets[s, 1]
            first, last = _row_range(ymin, ymax, sy, height)
            first, last = _exact_rows(ymin, ymax, sy, first, last)
            total += max(last - first + 1, 0)
    return total


@numba.njit(cache=True, inline="always")
def _edge_between(p, q):  # type: ignore[no-untyped-def]
    """Which edge (k: vertex k to vertex k + 1, oriented order) joins vertices p and q."""
    return p if (p + 1) % 3 == q else q


@numba.njit(cache=True, inline="always")
def _edge_record(xs, ys, es, os, k, width):  # type: ignore[no-untyped-def]
    """Edge k (vertex k to k + 1) as (ax, ay, bx, by, slope, bound, owned, lower, inner).

    lower: E grows with x, so the edge bounds the run from the left. inner: both ends at
    least 2 + 2 * bound columns inside the viewport, so every crossing on the edge's rows
    (between its ends' x) is too, filter error and sample offset included: none is
    clamped, and :func:`harness.oracle.kernels._bound`'s filter is :func:`_inner_bound`'s
    (the same arithmetic)."""
    a, b = k, (k + 1) % 3
    margin = 2.0 + 2.0 * es[k][3]
    inner = min(xs[a], xs[b]) >= margin and max(xs[a], xs[b]) <= width - margin
    return (xs[a], ys[a], xs[b], ys[b], es[k][2], es[k][3], os[k], ys[b] < ys[a], inner)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _triangle(positions, sign, owned, t, offsets, width, height):  # type: ignore[no-untyped-def]
    """Everything the samples of triangle ``t`` share, set up once: its vertices in
    oriented order, y extent, edges and their owners (as the single-sample kernel has
    them) and, for the rows strictly between the vertices' heights, the long edge (top
    to bottom vertex) and the two short ones.

    Each edge's error bound is taken over every row the samples may have, the triangle's
    height within the viewport: a larger reach only widens the bound, which never changes
    an answer (it only tells when the float crossing is already certain). Returns (any
    row, ymin, ymax, ymid, vertices, edge constants, owners, long, upper short,
    lower short edge)."""
    x0, y0, x1, y1, x2, y2 = _oriented(positions, sign, t)
    ymin = min(y0, y1, y2)
    ymax = max(y0, y1, y2)
    # every sample row j + sy decided lies in [ymin, ymax] and in [0, height]
    some = ymax >= 0.0 and ymin <= height
    y_first = max(ymin, 0.0) if some else 0.0
    y_last = min(ymax, float(height)) if some else 0.0
    e0 = _edge_setup(x0, y0, x1, y1, y_first, y_last)
    e1 = _edge_setup(x1, y1, x2, y2, y_first, y_last)
    e2 = _edge_setup(x2, y2, x0, y0, y_first, y_last)
    o0, o1, o2 = owned[t, 0], owned[t, 1], owned[t, 2]
    # vertices by height: top, middle, bottom (ties in any order: a row at a tied height
    # goes through a vertex and takes all three edges)
    xs = (x0, x1, x2)
    ys = (y0, y1, y2)
    es = (e0, e1, e2)
    os = (o0, o1, o2)
    top, mid, bottom = 0, 1, 2
    if ys[mid] < ys[top]:
        top, mid = mid, top
    if ys[bottom] < ys[mid]:
        mid, bottom = bottom, mid
        if ys[mid] < ys[top]:
            top, mid = mid, top
    long = _edge_record(xs, ys, es, os, _edge_between(top, bottom), width)
    upper = _edge_record(xs, ys, es, os, _edge_between(top, mid), width)
    lower = _edge_record(xs, ys, es, os, _edge_between(mid, bottom), width)
    return (some, ymin, ymax, ys[mid], (x0, y0, x1, y1, x2, y2), (e0, e1, e2), (o0, o1, o2),
            long, upper, lower)


@numba.njit(cache=True, inline="always")
def _inner_bound(ax, ay, slope, delta, sx, ys):  # type: ignore[no-untyped-def]
    """:func:`harness.oracle.kernels._bound`'s float filter on an edge whose crossings all lie
    well inside the viewport (no clamping): the first column past the crossing when the
    filter is certain of it, else -1 (the caller settles it exactly)."""
    xc = ax + slope * (ys - ay)
    lo = xc - delta - sx
    hi = xc + delta - sx
    f = np.floor(lo)
    if hi < f + 1.0:
        return int(f) + 1
    return -1


@numba.njit(cache=True, inline="always")
def _filtered_crossing(edge, sx, ys, width):  # type: ignore[no-untyped-def]
    """:func:`_crossing`'s float filter alone: the column, or -1 where the exact predicate
    must settle it (:func:`_settle_segment`)."""
    ax, ay, bx, by, slope, delta, owned, lower, inner = edge
    if inner:
        return _inner_bound(ax, ay, slope, delta, sx, ys)
    return _filtered_bound(ax, ay, slope, delta, sx, ys, width)


@numba.njit(cache=True, inline="always")
def _crossing(edge, sx, ys, width):  # type: ignore[no-untyped-def]
    """The column where ``edge``'s test flips on sample row ys (:func:`_bound`)."""
    ax, ay, bx, by, slope, delta, owned, lower, inner = edge
    if inner:
        column = _inner_bound(ax, ay, slope, delta, sx, ys)
        if column >= 0:
            return column
    return _bound(ax, ay, bx, by, slope, delta, owned, sx, ys, width, lower)


@numba.njit(cache=True, inline="always")
def _decide(tri, sx, ys, width):  # type: ignore[no-untyped-def]
    """The run [left, right) of sample columns a triangle (:func:`_triangle`) covers on
    the sample row ys, which lies within its height.

    A row strictly between the vertices' heights meets exactly two edges: the long one,
    bounding one side, and the short one of its half, the other; only those two are
    evaluated. A row through a vertex takes all three edges, as the single-sample kernel
    does (a horizontal edge's tie; the two edges meeting at the middle vertex)."""
    _, _, _, ymid, v, e, o, long, upper, lower = tri
    x0, y0, x1, y1, x2, y2 = v
    if ys == y0 or ys == y1 or ys == y2:  # noqa: SIM109 (three compares, no tuple, in compiled code)
        left, right = _apply_edge(x0, y0, x1, y1, e[0][0], e[0][1], e[0][2], e[0][3], o[0], sx, ys, width, 0, width)
        left, right = _apply_edge(x1, y1, x2, y2, e[1][0], e[1][1], e[1][2], e[1][3], o[1], sx, ys, width, left, right)
        return _apply_edge(x2, y2, x0, y0, e[2][0], e[2][1], e[2][2], e[2][3], o[2], sx, ys, width, left, right)
    c_long = _crossing(long, sx, ys, width)
    if ys < ymid:
        c_short = _crossing(upper, sx, ys, width)
    else:
        c_short = _crossing(lower, sx, ys, width)
    # the columns are clamped to [0, width]: the run is [lower bound, upper bound)
    return (c_long, c_short) if long[7] else (c_short, c_long)


@numba.njit(cache=True, inline="always")
def _on_lattice(y):  # type: ignore[no-untyped-def]
    scaled = y * _LATTICE
    return scaled == np.floor(scaled)


@numba.njit(cache=True, inline="always")
def _through_vertex(v, sy, first, last):  # type: ignore[no-untyped-def]
    """Whether a sample row j + sy, first <= j <= last, passes through a vertex: if
    y - sy is an integer j it is exact, so fl(y - sy) is j; any other candidate fails the
    exact test j + sy == y."""
    for y in (v[1], v[3], v[5]):
        r = np.floor(y - sy)
        if first <= r <= last and int(r) + sy == y:
            return True
    return False


@numba.njit(cache=True, inline="always")
def _first_row_below(ymid, sy, first, last):  # type: ignore[no-untyped-def]
    """The first row j of [first, last + 1] with j + sy > ymid (no row lies on ymid):
    the float estimate, then stepped until the exact test agrees."""
    split = min(max(np.floor(ymid - sy) + 1.0, float(first)), float(last + 1))
    j = int(split)
    while j > first and (j - 1) + sy > ymid:
        j -= 1
    while j <= last and j + sy < ymid:
        j += 1
    return j


@numba.njit(cache=True, inline="always")
def _segment(long, short, t, s, sx, sy, start, stop, width, n, out_t, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Spans of rows start <= j < stop of sample s, each row strictly between two
    vertices' heights and bounded by the ``long`` and ``short`` edge records; returns
    (the spans written so far, how many of this segment's are unsure).

    The rows' loop runs the float filters alone: a row whose filter is unsure (a column
    boundary within a crossing's error bound, rare) is written with a -1 column, settled
    exactly afterwards by :func:`_settle_spans`. No call may stand in this loop, not even
    one never made: the compiler then keeps the loop's values in memory (the 8x pattern
    took 40% longer with the exact fallback inline, twice as long with it a call)."""
    l_lower = long[7]
    unsure = 0
    for j in range(start, stop):
        ys = j + sy
        c_long = _filtered_crossing(long, sx, ys, width)
        c_short = _filtered_crossing(short, sx, ys, width)
        left, right = (c_long, c_short) if l_lower else (c_short, c_long)
        row_unsure = (c_long < 0) | (c_short < 0)
        if left < right or row_unsure:
            out_t[n] = t
            out_s[n] = s
            out_y[n] = j
            out_x0[n] = left
            out_x1[n] = right
            n += 1
            unsure += row_unsure
    return n, unsure


@numba.njit(cache=True, error_model="numpy")
def _settle_spans(positions, sign, owned, offsets, width, height, n, out_t, out_s, out_y, out_x0,  # type: ignore[no-untyped-def]
                  out_x1):
    """The first n spans of :func:`_multisample_kernel`, its unsure rows (a -1 column,
    from :func:`_segment`) settled by :func:`_crossing` (the exact predicate where the
    filter is unsure) and the rows left empty dropped, in order; returns the new n."""
    kept = 0
    t_record = -1
    tri = _triangle(positions, sign, owned, 0, offsets, width, height)
    for k in range(n):
        left, right = out_x0[k], out_x1[k]
        if left < 0 or right < 0:
            t = out_t[k]
            if t != t_record:
                tri = _triangle(positions, sign, owned, t, offsets, width, height)
                t_record = t
            sx, ys = offsets[out_s[k], 0], out_y[k] + offsets[out_s[k], 1]
            # a segment's row lies strictly between two vertices' heights
            long = tri[7]
            c_long = _crossing(long, sx, ys, width)
            c_short = _crossing(tri[8] if ys < tri[3] else tri[9], sx, ys, width)
            left, right = (c_long, c_short) if long[7] else (c_short, c_long)
        if left < right:
            out_t[kept] = out_t[k]
            out_s[kept] = out_s[k]
            out_y[kept] = out_y[k]
            out_x0[kept] = left
            out_x1[kept] = right
            kept += 1
    return kept


@numba.njit(cache=True, error_model="numpy")
def _multisample_kernel(positions, sign, owned, use, offsets, width, height,  # type: ignore[no-untyped-def]
                        out_t, out_s, out_y, out_x0, out_x1):
    """Spans of every sample of every used triangle, in (triangle, sample, row) order;
    returns (how many, how many of them are unsure: :func:`_settle_spans` settles them)."""
    n = 0
    unsure = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        tri = _triangle(positions, sign, owned, t, offsets, width, height)
        some, ymin, ymax = tri[0], tri[1], tri[2]
        if not some:
            continue
        # A sample row j + sy is a multiple of 2**-FRACTION_BITS (harness.contract.samples):
        # it can pass through a vertex only if the vertex's y is one too (scaling by a
        # power of two is exact).
        on_lattice = _on_lattice(tri[4][1]) or _on_lattice(tri[4][3]) or _on_lattice(tri[4][5])
        for s in range(offsets.shape[0]):
            sx, sy = offsets[s, 0], offsets[s, 1]
            first, last = _row_range(ymin, ymax, sy, height)
            first, last = _exact_rows(ymin, ymax, sy, first, last)
            if first > last:
                continue
            ymid, v, long = tri[3], tri[4], tri[7]
            if not (on_lattice and _through_vertex(v, sy, first, last)):
                # no row through a vertex: the rows above the middle vertex meet the long
                # edge and the upper short one, the rows below it the long and the lower
                split = _first_row_below(ymid, sy, first, last)
                n, more = _segment(long, tri[8], t, s, sx, sy, first, split, width, n, out_t, out_s, out_y, out_x0, out_x1)
                unsure += more
                n, more = _segment(long, tri[9], t, s, sx, sy, split, last + 1, width, n, out_t, out_s, out_y, out_x0,
                                   out_x1)
                unsure += more
                continue
            for j in range(first, last + 1):
                left, right = _decide(tri, sx, j + sy, width)
                if left < right:
                    out_t[n] = t
                    out_s[n] = s
                    out_y[n] = j
                    out_x0[n] = left
                    out_x1[n] = right
                    n += 1
    return n, unsure


@numba.njit(cache=True)
def _interpolate_samples(positions, values, inv_w, perspective, span_t, span_s, span_y, span_x0,  # type: ignore[no-untyped-def]
                         span_x1, offsets, out):
    """Barycentric interpolation at each covered sample, l_i = E_i / (E_0 + E_1 + E_2):
    :func:`harness.oracle.coverage.interpolate_kernel` with each span's own sample offset
    (the same arithmetic, so the same bits)."""
    row = 0
    for s in range(span_t.size):
        t = span_t[s]
        p = positions[t]
        sx = offsets[span_s[s], 0]
        ys = span_y[s] + offsets[span_s[s], 1]
        for i in range(span_x0[s], span_x1[s]):
            interpolate_at(p, values, inv_w, t, perspective, i + sx, ys, out, row)
            row += 1


def _offsets(samples: Sequence[Sequence[float]]) -> NDArray[np.float64]:
    offsets = np.ascontiguousarray(np.asarray(samples, dtype=np.float64).reshape(-1, 2))
    return offsets


def multisample_spans(scene: Scene, prepared: Prepared, samples: Sequence[Sequence[float]],
                      vertex_values: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None) -> Coverage | None:
    """Exactly which samples of the pattern ``samples`` each triangle covers, as one
    Coverage with sample ids, spans in (triangle, sample, row) order (attributes at each
    sample); ``None`` when some triangle lies beyond the expansions' safe range (the
    caller takes the per-sample path, whose rational fallback decides it).

    Parameters
    ----------
    scene : Scene
    prepared : Prepared
        The scene's triangles prepared under a single-sample convention (its ``sample``
        is not used).
    samples : sequence of (x, y)
        The pattern's offsets, in pattern order.
    vertex_values : ((N, 3, K) float64, (N, 3) float64), optional
        Attributes and 1/w at each vertex in oriented order, when the scene has
        attributes (:func:`harness.oracle.coverage.exact_multisample` passes them).

    Returns
    -------
    Coverage or None

    Examples
    --------
    >>> from harness.contract.conventions import Convention
    >>> from harness.oracle.coverage import prepare_triangles
    >>> scene = Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]])
    >>> cov = multisample_spans(scene, prepare_triangles(scene, Convention()), [(0.25, 0.25), (0.75, 0.75)])
    >>> cov.sample.tolist(), cov.y.tolist(), cov.x1.tolist()
    ([0, 0, 1], [0, 1, 0], [2, 1, 1])
    """
    if (prepared.active & ~prepared.safe).any():
        return None
    offsets = _offsets(samples)
    # Room for exactly the sample rows, not more: the spans are 40 bytes each, and a block
    # under 32 MiB stays with the allocator between calls (glibc's dynamic mmap
    # threshold), so a repeat does not pay the page faults of fresh memory again.
    capacity = int(_sample_rows(prepared.snapped, prepared.active, offsets, scene.height))
    block = np.empty((5, capacity), dtype=np.int64)
    n, unsure = _multisample_kernel(prepared.snapped, prepared.sign, prepared.owned, prepared.active, offsets,
                                    scene.width, scene.height, *block)
    if unsure:
        n = _settle_spans(prepared.snapped, prepared.sign, prepared.owned, offsets, scene.width, scene.height, n, *block)
    n = int(n)
    triangle, sample, y, x0, x1 = (a[:n] for a in block)
    attributes = None
    if vertex_values is not None:
        values, inv_w = vertex_values
        attributes = np.empty((int((x1 - x0).sum()), values.shape[2]))
        _interpolate_samples(prepared.positions, values, inv_w, scene.w is not None, triangle, sample, y, x0, x1,
                             offsets, attributes)
    return Coverage(triangle, y, x0, x1, attributes, sample)


@numba.njit(cache=True)
def _layer_order(sample, starts, order):  # type: ignore[no-untyped-def]
    """A stable counting sort of the spans by sample into ``order`` (P,): spans of sample
    0 first (in their order), then sample 1's, ...; ``starts`` (S + 1,) zeros on entry,
    where each sample's spans start on return."""
    for k in range(sample.size):
        starts[sample[k] + 1] += 1
    for s in range(starts.size - 1):
        starts[s + 1] += starts[s]
    fill = starts[:-1].copy()
    for k in range(sample.size):
        s = sample[k]
        order[fill[s]] = k
        fill[s] += 1


def fused_samples(scene: Scene, prepared: Prepared, samples: Sequence[Sequence[float]],
                  vertex_values: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None) -> list[Coverage] | None:
    """:func:`multisample_spans` as one single-sample Coverage per sample, in pattern
    order, each sorted by triangle then row (what
    :func:`harness.oracle.coverage.exact_samples` returns); ``None`` as there."""
    joined = multisample_spans(scene, prepared, samples, vertex_values)
    if joined is None:
        return None
    assert joined.sample is not None
    starts = np.zeros(len(samples) + 1, dtype=np.int64)
    order = np.empty(joined.sample.size, dtype=np.int64)  # numpy's allocation, not numba's (far cheaper)
    _layer_order(joined.sample, starts, order)
    if joined.attributes is None:
        return [Coverage(*(getattr(joined, f)[order[a:b]] for f in ("triangle", "y", "x0", "x1")))
                for a, b in zip(starts[:-1], starts[1:], strict=True)]
    layers = []
    for a, b in zip(starts[:-1], starts[1:], strict=True):
        layer = joined.take(order[a:b])
        layers.append(Coverage(layer.triangle, layer.y, layer.x0, layer.x1, layer.attributes))
    return layers


@numba.njit(cache=True)
def _shares_capacity(positions, use, offsets, width, height):  # type: ignore[no-untyped-def]
    """Room for the shares of the used triangles: per triangle, its pixel rows times the
    columns of its bounding box (a run's pixels lie in it) -- pixels -- and times at most
    one run per sample -- spans. Returns (spans, pixels)."""
    spans = 0
    pixels = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        ymin = min(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        ymax = max(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        first, last = height, -1
        for s in range(offsets.shape[0]):
            a, b = _row_range(ymin, ymax, offsets[s, 1], height)
            if a <= b:
                first = min(first, a)
                last = max(last, b)
        if first > last:
            continue
        # columns floor(xmin) - 1 .. floor(xmax) hold every sample column of the triangle,
        # clamped as floats first (np.floor, not math.floor: a coordinate may lie far
        # beyond any int)
        xmin = min(positions[t, 0, 0], positions[t, 1, 0], positions[t, 2, 0])
        xmax = max(positions[t, 0, 0], positions[t, 1, 0], positions[t, 2, 0])
        columns = int(min(max(np.floor(xmax) + 1.0, 0.0), float(width)) - min(max(np.floor(xmin) - 1.0, 0.0), float(width)))
        columns = max(columns, 0)
        pixels += (last - first + 1) * columns
        spans += (last - first + 1) * min(columns, offsets.shape[0])
    return spans, pixels


# The most pixels the supersampled shares make room for at first (128 MiB of alphas,
# only touched where written); more when the answer needs it.
FIRST_ROOM = 1 << 24


@numba.njit(cache=True, error_model="numpy")
def _shares_kernel(positions, sign, owned, use, offsets, width, height, share, spans, alpha, start, n, m):  # type: ignore[no-untyped-def]
    """Per (triangle, pixel row), the samples of every sample row of that pixel row
    counted per pixel together: spans over the pixels some sample covers, with the count
    over ``share`` per pixel, in (triangle, row) order, written to ``spans`` (4, room) and
    ``alpha`` (room,) from triangle ``start`` on, after ``n`` spans and ``m`` pixels
    already written.

    Returns (triangle, spans, pixels): the triangle it stopped at (all of them: N), and
    how many spans and pixels are written before it. It stops before a triangle whose
    answer would not fit (nothing of that triangle kept): the caller grows the buffers and
    calls again from there."""
    n_samples = offsets.shape[0]
    lefts = np.empty(n_samples, dtype=np.int64)
    rights = np.empty(n_samples, dtype=np.int64)
    delta = np.zeros(width + 1, dtype=np.int64)
    for t in range(start, positions.shape[0]):
        if not use[t]:
            continue
        tri = _triangle(positions, sign, owned, t, offsets, width, height)
        some, ymin, ymax = tri[0], tri[1], tri[2]
        if not some:
            continue
        n_triangle, m_triangle = n, m
        # the pixel rows any sample row of the triangle falls on
        j_first = height
        j_last = -1
        for s in range(n_samples):
            first, last = _row_range(ymin, ymax, offsets[s, 1], height)
            if first <= last:
                j_first = min(j_first, first)
                j_last = max(j_last, last)
        for j in range(j_first, j_last + 1):
            lo = width
            hi = 0
            for s in range(n_samples):
                sx, sy = offsets[s, 0], offsets[s, 1]
                ys = j + sy
                left, right = 0, 0
                if ys >= ymin and ys <= ymax:
                    left, right = _decide(tri, sx, ys, width)
                lefts[s] = left
                rights[s] = right
                if left < right:
                    lo = min(lo, left)
                    hi = max(hi, right)
            if lo >= hi:
                continue
            # at most one run per sample, at most one pixel per column of [lo, hi)
            if n + min(n_samples, hi - lo) > spans.shape[1] or m + (hi - lo) > alpha.size:
                return t, n_triangle, m_triangle
            for s in range(n_samples):
                if lefts[s] < rights[s]:
                    delta[lefts[s]] += 1
                    delta[rights[s]] -= 1
            running = 0
            open_run = False
            for x in range(lo, hi):
                running += delta[x]
                delta[x] = 0
                if running > 0:
                    if not open_run:
                        spans[0, n] = t
                        spans[1, n] = j
                        spans[2, n] = x
                        open_run = True
                    alpha[m] = running / share  # the count over the pattern's size, as numpy divides
                    m += 1
                elif open_run:
                    spans[3, n] = x
                    n += 1
                    open_run = False
            delta[hi] = 0
            if open_run:
                spans[3, n] = hi
                n += 1
    return positions.shape[0], n, m


def fused_shares(scene: Scene, prepared: Prepared, samples: Sequence[Sequence[float]], n_samples: int) -> Coverage | None:
    """Per (triangle, pixel) the share of the pattern's ``n_samples`` samples the triangle
    covers, as alpha, all samples of a pixel row counted together (what
    :func:`harness.oracle.coverage.sample_shares` returns); ``None`` when some triangle
    lies beyond the expansions' safe range.

    >>> from harness.contract.conventions import Convention
    >>> from harness.oracle.coverage import prepare_triangles
    >>> scene = Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]])
    >>> fused_shares(scene, prepare_triangles(scene, Convention()), [(0.25, 0.25), (0.75, 0.75)], 2).alpha.tolist()
    [1.0, 0.5, 0.5]
    """
    if (prepared.active & ~prepared.safe).any():
        return None
    offsets = _offsets(samples)
    span_room, pixel_room = _shares_capacity(prepared.snapped, prepared.active, offsets, scene.width, scene.height)
    # The bounding boxes' room, up to FIRST_ROOM pixels at first (a long diagonal sliver's box
    # is far larger than its answer), grown by doubling when a triangle's answer does not
    # fit. Allocated here, not in the kernel: numba's own allocation of a large array
    # costs several times numpy's (fresh pages are only touched where written).
    spans = np.empty((4, max(min(span_room, FIRST_ROOM // 4), 1)), dtype=np.int64)
    alpha = np.empty(max(min(pixel_room, FIRST_ROOM), 1), dtype=np.float64)
    t, n, m = 0, 0, 0
    while True:
        t, n, m = _shares_kernel(prepared.snapped, prepared.sign, prepared.owned, prepared.active, offsets,
                                 scene.width, scene.height, n_samples, spans, alpha, t, n, m)
        if t == len(scene):
            break
        grown = np.empty((4, 2 * spans.shape[1]), dtype=np.int64)
        grown[:, :n] = spans[:, :n]
        more = np.empty(2 * alpha.size, dtype=np.float64)
        more[:m] = alpha[:m]
        spans, alpha = grown, more
    return Coverage(spans[0, :n], spans[1, :n], spans[2, :n], spans[3, :n], alpha=alpha[:m])
