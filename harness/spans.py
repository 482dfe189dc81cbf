"""Span helpers: the arithmetic that turns spans into pixels and back, without a Python loop.

A coverage is a list of spans (triangle, y, x0, x1) covering pixels x0 <= x < x1 of row
y. Kernels fill :func:`span_buffers`; :class:`harness.api.Coverage` and the oracle use
the rest to expand spans into pixels and to merge runs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["pixel_offsets", "run_tails", "span_buffers", "expand"]


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
