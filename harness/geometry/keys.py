"""Sorted unique integer keys, by sorting.

The checks key fragments as ``(t * H + y) * W + x`` (int64) and compare key sets tens of
thousands of times a run. numpy 2's ``np.unique`` hashes before it sorts: on int64
arrays it took 41 us for 10 keys and 16.7 ms for 100,000, where a sort and a comparison
of neighbours take 3 us and 4.0 ms. The sort is numpy's stable one (timsort, radix for
small integers): the keys of a tidy coverage come in order already, and a union joins two
sorted runs, where it takes linear time -- 34 us for 50,000 sorted keys, 1.8 ms with the
default quicksort (4.4 ms against 5.4 ms on random keys). These give the same results as
``np.unique`` (and ``np.union1d``) on 1-D integer arrays.

>>> unique_counts(np.array([5, 3, 5, 9]))
(array([3, 5, 9]), array([1, 2, 1]))
>>> keys, inverse = unique_inverse(np.array([5, 3, 5, 9]))
>>> keys[inverse].tolist()
[5, 3, 5, 9]
>>> union(np.array([1, 4]), np.array([4, 2])).tolist()
[1, 2, 4]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["unique", "unique_counts", "unique_inverse", "union", "composite", "lexsort"]


def _starts(ordered: NDArray) -> NDArray[np.bool_]:
    """(K,) True where a sorted array's run of equal keys starts."""
    starts = np.empty(ordered.size, dtype=bool)
    starts[:1] = True
    np.not_equal(ordered[1:], ordered[:-1], out=starts[1:])
    return starts


def unique(keys: NDArray) -> NDArray:
    """(U,) the distinct keys of a 1-D integer array, ascending (``np.unique(keys)``)."""
    ordered = np.sort(keys.ravel(), kind="stable")
    return ordered[_starts(ordered)]


def unique_counts(keys: NDArray) -> tuple[NDArray, NDArray[np.int64]]:
    """(U,) the distinct keys ascending and (U,) how often each occurs
    (``np.unique(keys, return_counts=True)``)."""
    ordered = np.sort(keys.ravel(), kind="stable")
    first = np.flatnonzero(_starts(ordered))
    return ordered[first], np.diff(np.append(first, ordered.size)).astype(np.int64)


def unique_inverse(keys: NDArray) -> tuple[NDArray, NDArray[np.int64]]:
    """(U,) the distinct keys ascending and (K,) the index of each key among them
    (``np.unique(keys, return_inverse=True)``)."""
    flat = keys.ravel()
    order = np.argsort(flat, kind="stable")
    ordered = flat[order]
    starts = _starts(ordered)
    inverse = np.empty(flat.size, dtype=np.int64)
    inverse[order] = np.cumsum(starts) - 1
    return ordered[starts], inverse


def union(a: NDArray, b: NDArray) -> NDArray:
    """(U,) the keys in either of two integer arrays, ascending (``np.union1d(a, b)``)."""
    return unique(np.concatenate([a.ravel(), b.ravel()]))


def composite(keys: tuple[NDArray, ...]) -> NDArray[np.int64] | None:
    """(K,) one int64 key ordered as the integer keys of equal length are ordered
    lexicographically (the last key primary, as for ``np.lexsort``), or None when their
    ranges' product does not fit in 62 bits."""
    out = np.zeros(keys[0].size if keys else 0, dtype=np.int64)
    if not out.size:
        return out
    room = 1
    for key in reversed(keys):  # the primary key first
        lo, hi = int(key.min()), int(key.max())
        room *= hi - lo + 1
        if room >= 1 << 62:
            return None
        out = out * (hi - lo + 1) + (key - lo)
    return out


def lexsort(keys: tuple[NDArray, ...]) -> NDArray[np.int64]:
    """``np.lexsort(keys)`` (the last key primary, stable) for integer keys of equal length:
    by one :func:`composite` key where there is one (one stable sort, linear on keys in
    order already, where lexsort makes a pass per key), else lexsort.

    >>> lexsort((np.array([2, 1, 0]), np.array([1, 1, 0]))).tolist()
    [2, 1, 0]
    """
    whole = composite(keys)
    return np.lexsort(keys) if whole is None else np.argsort(whole, kind="stable")
