"""Sorts for use inside numba kernels.

Written out rather than ``np.sort`` / ``np.argsort`` in a kernel: numba compiles its generic
quicksort or merge sort into every process that compiles such a kernel, 1-2 s each on a
fresh clone (the trapezoid fill's sweep, the winding oracle and a known-bad filler each
paid it: about 5 s of ``make test``'s kernel warm-up), while these compile in a tenth of
that. Both are O(n log n) whatever the input's order.
"""

from __future__ import annotations

import numba

__all__ = ["heapsort", "heapsort_pairs", "stable_argsort"]


@numba.njit(cache=True, inline="always")
def _sift_down(keys, payload, lo, root, n, with_payload):  # type: ignore[no-untyped-def]
    """Restore the max-heap keys[lo:lo + n] below ``root`` (payload moved alike)."""
    while True:
        child = 2 * root + 1
        if child >= n:
            return
        if child + 1 < n and keys[lo + child] < keys[lo + child + 1]:
            child += 1
        if not keys[lo + root] < keys[lo + child]:
            return
        keys[lo + root], keys[lo + child] = keys[lo + child], keys[lo + root]
        if with_payload:
            payload[lo + root], payload[lo + child] = payload[lo + child], payload[lo + root]
        root = child


@numba.njit(cache=True)
def _heapsort(keys, payload, lo, hi, with_payload):  # type: ignore[no-untyped-def]
    n = hi - lo
    for root in range(n // 2 - 1, -1, -1):
        _sift_down(keys, payload, lo, root, n, with_payload)
    for end in range(n - 1, 0, -1):
        keys[lo], keys[lo + end] = keys[lo + end], keys[lo]
        if with_payload:
            payload[lo], payload[lo + end] = payload[lo + end], payload[lo]
        _sift_down(keys, payload, lo, 0, end, with_payload)


@numba.njit(cache=True)
def heapsort(keys, lo, hi):  # type: ignore[no-untyped-def]
    """Sort ``keys[lo:hi]`` ascending in place (not stable: for plain values).

    >>> import numpy as np
    >>> keys = np.array([9, 5, 3, 8, 1, 7])
    >>> heapsort(keys, 1, 5); keys.tolist()
    [9, 1, 3, 5, 8, 7]
    """
    _heapsort(keys, keys, lo, hi, False)


@numba.njit(cache=True)
def heapsort_pairs(keys, payload, lo, hi):  # type: ignore[no-untyped-def]
    """Sort ``keys[lo:hi]`` ascending in place, moving ``payload[lo:hi]`` alike (the order
    of equal keys is unspecified).

    >>> import numpy as np
    >>> keys, payload = np.array([3, 1, 2]), np.array([30, 10, 20])
    >>> heapsort_pairs(keys, payload, 0, 3); payload.tolist()
    [10, 20, 30]
    """
    _heapsort(keys, payload, lo, hi, True)


@numba.njit(cache=True)
def stable_argsort(keys, n, order, spare):  # type: ignore[no-untyped-def]
    """``order[:n]``: the indices that sort ``keys[:n]`` ascending, equal keys in index
    order (a bottom-up merge sort; ``spare`` holds at least ``n`` int64 of scratch).

    >>> import numpy as np
    >>> order, spare = np.empty(5, np.int64), np.empty(5, np.int64)
    >>> stable_argsort(np.array([2, 1, 2, 0, 1]), 5, order, spare); order.tolist()
    [3, 1, 4, 0, 2]
    """
    for i in range(n):
        order[i] = i
    width = 1
    in_order = True  # the sorted runs are in ``order`` (else in ``spare``)
    while width < n:
        src, dst = (order, spare) if in_order else (spare, order)
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i, j, k = lo, mid, lo
            while i < mid and j < hi:
                if keys[src[j]] < keys[src[i]]:  # strictly less: equal keys keep their order
                    dst[k] = src[j]
                    j += 1
                else:
                    dst[k] = src[i]
                    i += 1
                k += 1
            while i < mid:
                dst[k] = src[i]
                i += 1
                k += 1
            while j < hi:
                dst[k] = src[j]
                j += 1
                k += 1
        in_order = not in_order
        width *= 2
    if not in_order:
        for i in range(n):
            order[i] = spare[i]
