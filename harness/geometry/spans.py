"""Span helpers: the arithmetic that turns spans into pixels and back, without a Python loop.

A coverage is a list of spans (triangle, y, x0, x1) covering pixels x0 <= x < x1 of row
y. Kernels fill :func:`span_buffers`; :class:`harness.contract.coverage.Coverage` and the oracle use
the rest to expand spans into pixels and to merge runs.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["pixel_offsets", "run_tails", "span_buffers", "expand", "tidy"]


def pixel_offsets(x0: NDArray[np.int64], x1: NDArray[np.int64]) -> NDArray[np.int64]:
    """Index of each span's first pixel in the span-ordered pixel list."""
    lengths = np.maximum(x1 - x0, 0)
    offsets = np.zeros(lengths.size + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    return offsets


def run_tails(heads: NDArray[np.int64], size: int) -> NDArray[np.int64]:
    """Index of the last element of each run, given the index of each run's first."""
    tails = np.empty(heads.size, dtype=np.int64)
    tails[:-1] = heads[1:] - 1
    if heads.size:
        tails[-1] = size - 1
    return tails


def span_buffers(capacity: int) -> tuple[NDArray[np.int64], ...]:
    """Four int64 arrays (triangle, y, x0, x1) of ``capacity`` for a span kernel to fill.

    They are rows of one block: a single large allocation is much cheaper than four
    (one mapping, and huge pages where the system offers them), and the spans a kernel
    writes end up side by side in memory."""
    block = np.empty((4, capacity), dtype=np.int64)
    return block[0], block[1], block[2], block[3]


def expand(starts: NDArray[np.int64], lengths: NDArray[np.int64]) -> NDArray[np.int64]:
    """Concatenate ``arange(s, s + n)`` for each (s, n), without a Python loop.

    >>> expand(np.array([3, 10]), np.array([2, 3])).tolist()
    [3, 4, 10, 11, 12]
    """
    total = int(lengths.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    keep = lengths > 0
    starts, lengths = starts[keep], lengths[keep]
    steps = np.ones(total, dtype=np.int64)
    heads = np.zeros(lengths.size, dtype=np.int64)
    np.cumsum(lengths[:-1], out=heads[1:])
    steps[heads] = starts
    steps[heads[1:]] -= starts[:-1] + lengths[:-1] - 1
    return np.cumsum(steps)


def tidy(triangle: NDArray[np.int64], y: NDArray[np.int64], x0: NDArray[np.int64], x1: NDArray[np.int64],
         n_triangles: int, bounds: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64],
                                                               dict[str, NDArray[np.int64]], int]:
    """What can be kept of a list of spans, found span by span (never pixel by pixel, so
    that the cost is bounded by the number of spans whatever their lengths).

    Parameters
    ----------
    triangle, y, x0, x1 : (S,) int64
        The spans as a rasterizer returned them.
    n_triangles : int
        Valid triangle ids are 0 .. n_triangles - 1.
    bounds : (n_triangles, 4) int64
        Per triangle, the pixel rectangle ``xmin, ymin, xmax, ymax`` (inclusive) a pixel of
        it may lie in: its bounding box grown by the reach of any sample point and
        snapping, clipped to the viewport.

    Returns
    -------
    keep : (P,) int64
        For each kept piece, the index of the span it comes from; pieces sorted by
        triangle, y and start. A pixel that several spans of one triangle emit belongs to
        the first of them in the rasterizer's order (so a kept pixel's attribute row is
        the one it was first given with); a span may thus keep several pieces, or none.
    start, end : (P,) int64
        Each piece's pixels [start, end), inside its triangle's bounds.
    flaws : dict of str -> (n,) int64
        Indices of offending spans per kind: ``bad_primitive_id``, ``empty_or_reversed``,
        ``outside_primitive`` (reaching past its triangle's bounds), ``repeated``
        (emitting a pixel that an earlier span of the same triangle emitted).
    repeated_pixels : int
        How many pixels (within the bounds) the repeated spans emit a second time.

    >>> t, y = np.array([0, 0, 0, 0]), np.array([1, 1, 1, 1])
    >>> x0, x1 = np.array([2, 4, 9, 1]), np.array([6, 8, 9, 3])
    >>> keep, start, end, flaws, again = tidy(t, y, x0, x1, 1, np.array([[0, 0, 9, 9]]))
    >>> keep.tolist(), start.tolist(), end.tolist(), again
    ([3, 0, 1], [1, 2, 6], [2, 6, 8], 3)
    >>> flaws["repeated"].tolist(), flaws["empty_or_reversed"].tolist()
    ([1, 3], [2])
    """
    size = triangle.size
    valid_id = (triangle >= 0) & (triangle < n_triangles)
    if n_triangles == 0:
        bounds = np.zeros((1, 4), dtype=np.int64)
    flaws = {"bad_primitive_id": np.flatnonzero(~valid_id), "empty_or_reversed": np.flatnonzero(x0 >= x1)}
    tri = np.where(valid_id, triangle, 0)
    box = bounds[tri] if size else np.zeros((0, 4), dtype=np.int64)
    lo = np.maximum(x0, box[:, 0])
    hi = np.minimum(x1, box[:, 2] + 1)
    row_in = (y >= box[:, 1]) & (y <= box[:, 3])
    flaws["outside_primitive"] = np.flatnonzero(valid_id & (x0 < x1) & ((lo > x0) | (hi < x1) | ~row_in))
    usable = valid_id & row_in & (lo < hi)
    order = np.lexsort((np.arange(size), lo, y, triangle))
    order = order[usable[order]]
    keep, start, end = _first_emissions(triangle[order], y[order], lo[order], hi[order], order)
    kept = np.bincount(keep, weights=end - start, minlength=size).astype(np.int64)
    wanted = np.where(usable, hi - lo, 0)
    flaws["repeated"] = np.flatnonzero(kept < wanted)
    return keep, start, end, flaws, int((wanted - kept).sum())


@numba.njit(cache=True)
def _first_emissions(triangle, y, x0, x1, index):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """Spans sorted by (triangle, y, x0): the pieces of each (triangle, row) group, each
    pixel owned by the span of smallest ``index`` that covers it. A sweep along the row
    with a heap of the spans open at each point (keyed by index, closed ones dropped
    lazily): O(k log k) for a group of k spans, at most 2k pieces, whatever their lengths."""
    n = x0.size
    out_keep = np.empty(2 * n, dtype=np.int64)
    out_start = np.empty(2 * n, dtype=np.int64)
    out_end = np.empty(2 * n, dtype=np.int64)
    heap_key = np.empty(n, dtype=np.int64)
    heap_end = np.empty(n, dtype=np.int64)
    pieces = 0
    g0 = 0
    while g0 < n:
        g1 = g0 + 1
        while g1 < n and triangle[g1] == triangle[g0] and y[g1] == y[g0]:
            g1 += 1
        size = 0
        i = g0
        p = x0[g0]
        while True:
            while i < g1 and x0[i] <= p:  # open the spans starting here
                c = size
                size += 1
                while c > 0 and heap_key[(c - 1) // 2] > index[i]:
                    heap_key[c], heap_end[c] = heap_key[(c - 1) // 2], heap_end[(c - 1) // 2]
                    c = (c - 1) // 2
                heap_key[c], heap_end[c] = index[i], x1[i]
                i += 1
            while size > 0 and heap_end[0] <= p:  # drop the spans closed by now
                size -= 1
                key, end = heap_key[size], heap_end[size]
                c = 0
                while 2 * c + 1 < size:
                    child = 2 * c + 1
                    if child + 1 < size and heap_key[child + 1] < heap_key[child]:
                        child += 1
                    if heap_key[child] >= key:
                        break
                    heap_key[c], heap_end[c] = heap_key[child], heap_end[child]
                    c = child
                heap_key[c], heap_end[c] = key, end
            if size == 0:
                if i == g1:
                    break
                p = x0[i]
                continue
            q = heap_end[0]
            if i < g1 and x0[i] < q:
                q = x0[i]
            if pieces > 0 and out_keep[pieces - 1] == heap_key[0] and out_end[pieces - 1] == p:
                out_end[pieces - 1] = q
            else:
                out_keep[pieces], out_start[pieces], out_end[pieces] = heap_key[0], p, q
                pieces += 1
            p = q
        g0 = g1
    return out_keep[:pieces], out_start[:pieces], out_end[:pieces]


@numba.njit(cache=True)
def already_tidy(bounds, primitive, y, x0, x1):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """True when :func:`tidy` would keep every span whole: each names a primitive of
    ``bounds`` ((N, 4) int64 ``xmin, ymin, xmax, ymax`` inclusive, from
    :func:`harness.contract.scenes._pixel_bounds`), is non-empty, lies within its primitive's pixel
    bounds, and the (primitive, y) pairs strictly increase, so no pixel can be emitted
    twice. What rasterizers return is usually so; one pass, no allocation. False says only
    "look closer"."""
    n = bounds.shape[0]
    for s in range(primitive.size):
        t = primitive[s]
        if t < 0 or t >= n or x0[s] >= x1[s]:
            return False
        if s > 0 and (t < primitive[s - 1] or (t == primitive[s - 1] and y[s] <= y[s - 1])):
            return False
        if y[s] < bounds[t, 1] or y[s] > bounds[t, 3] or x0[s] < bounds[t, 0] or x1[s] > bounds[t, 2] + 1:
            return False
    return True

