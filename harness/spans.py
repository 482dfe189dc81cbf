"""Span helpers: the arithmetic that turns spans into pixels and back, without a Python loop.

A coverage is a list of spans (triangle, y, x0, x1) covering pixels x0 <= x < x1 of row
y. Kernels fill :func:`span_buffers`; :class:`harness.api.Coverage` and the oracle use
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
         n_triangles: int, bounds: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64], dict[str, NDArray[np.int64]], int]:
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
    keep : (S,) int64
        Indices of the spans kept, in their order (sorted by triangle, y, x0).
    start : (S2,) int64, paired with ``keep``
        Each kept span's first kept pixel (``x0`` moved right past pixels already
        emitted by an earlier span of the same triangle and row, and into the bounds);
        its end is ``min(x1, xmax + 1)``.
    flaws : dict of str -> (n,) int64
        Indices of offending spans per kind: ``bad_triangle_id``, ``empty_or_reversed``,
        ``outside_triangle`` (reaching past its triangle's bounds), ``repeated``
        (overlapping an earlier span of the same triangle and row).
    repeated_pixels : int
        How many pixels (within the bounds) the repeated spans emit a second time.

    >>> t, y = np.array([0, 0, 0]), np.array([1, 1, 1])
    >>> keep, start, flaws, again = tidy(t, y, np.array([2, 4, 9]), np.array([6, 8, 9]), 1, np.array([[0, 0, 9, 9]]))
    >>> keep.tolist(), start.tolist(), flaws["repeated"].tolist(), flaws["empty_or_reversed"].tolist(), again
    ([0, 1], [2, 6], [1], [2], 2)
    """
    size = triangle.size
    valid_id = (triangle >= 0) & (triangle < n_triangles)
    if n_triangles == 0:
        bounds = np.zeros((1, 4), dtype=np.int64)
    flaws = {"bad_triangle_id": np.flatnonzero(~valid_id), "empty_or_reversed": np.flatnonzero(x0 >= x1)}
    tri = np.where(valid_id, triangle, 0)
    box = bounds[tri] if size else np.zeros((0, 4), dtype=np.int64)
    lo = np.maximum(x0, box[:, 0])
    hi = np.minimum(x1, box[:, 2] + 1)
    row_in = (y >= box[:, 1]) & (y <= box[:, 3])
    flaws["outside_triangle"] = np.flatnonzero(valid_id & (x0 < x1) & ((lo > x0) | (hi < x1) | ~row_in))
    usable = valid_id & row_in & (lo < hi)
    order = np.lexsort((lo, y, triangle))
    order = order[usable[order]]
    start = _past_earlier_spans(triangle[order], y[order], lo[order], hi[order])
    flaws["repeated"] = np.sort(order[start > lo[order]])
    repeated_pixels = int((np.minimum(start, hi[order]) - lo[order]).sum())
    kept = start < hi[order]
    return order[kept], start[kept], flaws, repeated_pixels


@numba.njit(cache=True)
def _past_earlier_spans(triangle: NDArray[np.int64], y: NDArray[np.int64], x0: NDArray[np.int64],
                        x1: NDArray[np.int64]) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """Spans sorted by (triangle, y, x0): each one's start moved past the furthest end of
    the spans before it in its (triangle, row) group, so that no pixel is kept twice."""
    start = x0.copy()
    furthest = 0
    for i in range(x0.size):
        if i == 0 or triangle[i] != triangle[i - 1] or y[i] != y[i - 1]:
            furthest = x1[i]
            continue
        if x0[i] < furthest:
            start[i] = furthest
        if x1[i] > furthest:
            furthest = x1[i]
    return start
