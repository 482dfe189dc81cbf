"""What the exact line oracles share (:mod:`harness.oracle.diamond_lines`,
:mod:`~harness.oracle.bresenham_lines`, :mod:`~harness.oracle.rectangle_lines`): their spans
(:data:`Spans`), the compiled emitter of one pixel, and the end points and viewport checked
before any rule runs.

A segment k runs from ``a[k]`` to ``b[k]`` (float64, pixels, x right, y down: the screen
space of :mod:`harness.contract.conventions`). Pixel (i, j) is the square [i, i+1) x [j, j+1) with
centre (i + 1/2, j + 1/2). Every oracle returns the covered pixels as spans
``(segment, y, x0, x1)`` -- pixels x0 <= x < x1 of row y -- sorted by segment, row and x0,
like :func:`harness.oracle.winding.path_spans`. A segment with a NaN or infinite endpoint covers
nothing. Every decision is exact on the float64 input; no epsilon appears anywhere.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.scenes import MAX_VIEWPORT
from harness.geometry.exact import frozen

Spans = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]


# -- shared compiled pieces -------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def emit_pixel(s, y, x, out_s, out_y, out_x0, out_x1, n, first):  # type: ignore[no-untyped-def]
    """Add pixel (x, y) of segment s, merged into the last span when adjacent on its row.
    ``first`` is the index of the segment's first span. Returns the span count."""
    if n > first and out_y[n - 1] == y:
        if out_x1[n - 1] == x:
            out_x1[n - 1] = x + 1
            return n
        if out_x0[n - 1] == x + 1:
            out_x0[n - 1] = x
            return n
    out_s[n] = s
    out_y[n] = y
    out_x0[n] = x
    out_x1[n] = x + 1
    return n + 1


@numba.njit(cache=True, inline="always")
def _clamp_index(value, low, high):  # type: ignore[no-untyped-def]
    """floor(value) clamped to [low, high] without converting a huge float (NaN -> low)."""
    if not value >= low:
        return low
    if value >= high:
        return high
    return int(math.floor(value))


def span_buffers(capacity: int) -> list[NDArray[np.int64]]:
    """Four (capacity,) int64 arrays for a kernel's segment, y, x0 and x1: rows of one
    block. One allocation, not four: glibc serves four multi-megabyte arrays by fresh
    ``mmap`` calls whose pages the kernel zeroes on first touch on every call (about
    1 ms for L2's 12 MB of spans), while one block of the same size is reused."""
    block = np.empty((4, capacity), dtype=np.int64)
    return [block[0], block[1], block[2], block[3]]


# -- input handling ------------------------------------------------------------------------------


def _empty() -> Spans:
    return tuple(np.empty(0, dtype=np.int64) for _ in range(4))  # type: ignore[return-value]


def _viewport(width: int, height: int) -> tuple[int, int]:
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= MAX_VIEWPORT:
            raise ValueError(f"{name} must be an integer in 0..{MAX_VIEWPORT}, not {value!r}")
    return int(width), int(height)


def _endpoints(a: ArrayLike, b: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """The end points as (N, 2) float64 arrays, and which segments are finite."""
    a_arr = np.asarray(a, dtype=np.float64)
    b_arr = np.asarray(b, dtype=np.float64)
    if a_arr.ndim != 2 or a_arr.shape[1:] != (2,) or a_arr.shape != b_arr.shape:
        raise ValueError(f"a and b must be (N, 2) arrays of one shape, not {a_arr.shape} and {b_arr.shape}")
    finite = np.isfinite(np.concatenate([a_arr, b_arr], axis=1)).all(axis=1)
    return a_arr, b_arr, np.asarray(finite, dtype=np.bool_)


def _check_range(values: NDArray[np.float64], keep: NDArray[np.bool_], low: float, high: float, use: str) -> None:
    """ValueError naming the first kept segment with a nonzero coordinate beyond [low, high]."""
    beyond = _beyond(values, low, high) & keep
    if beyond.any():
        k = int(np.flatnonzero(beyond)[0])
        raise ValueError(
            f"segment {k} has coordinates beyond the exact predicates' range (nonzero magnitude below "
            f"2**{int(math.log2(low))} or above 2**{int(math.log2(high))}); use {use}"
        )


def _spans_from_mask(segment: int, covered: list[list[bool]], out: list[tuple[int, int, int, int]]) -> None:
    """Maximal runs of each row of ``covered`` ([y][x]) as spans of ``segment``."""
    for j, row in enumerate(covered):
        i = 0
        while i < len(row):
            if row[i]:
                k = i
                while k < len(row) and row[k]:
                    k += 1
                out.append((segment, j, i, k))
                i = k
            else:
                i += 1


def _as_spans(rows: list[tuple[int, int, int, int]]) -> Spans:
    if not rows:
        return _empty()
    arr = np.array(rows, dtype=np.int64).T
    return arr[0], arr[1], arr[2], arr[3]


@numba.njit(cache=True)
def _beyond_kernel(values, low, high, out):  # type: ignore[no-untyped-def]
    for k in range(values.shape[0]):
        hit = False
        for c in range(values.shape[1]):
            magnitude = abs(values[k, c])
            if magnitude != 0.0 and (magnitude < low or magnitude > high):
                hit = True
        out[k] = hit


def _beyond(values: NDArray[np.float64], low: float, high: float) -> NDArray[np.bool_]:
    """(N,) bool: rows holding a nonzero magnitude outside [low, high] (an infinite one
    too; NaN never)."""
    flat = np.asarray(values, dtype=np.float64).reshape(values.shape[0], -1)
    out = np.empty(flat.shape[0], dtype=np.bool_)
    _beyond_kernel(frozen(flat), float(low), float(high), out)
    return out


@numba.njit(cache=True)
def _finite_kernel(a, b, out):  # type: ignore[no-untyped-def]
    for k in range(a.shape[0]):
        out[k] = math.isfinite(a[k, 0]) and math.isfinite(a[k, 1]) and math.isfinite(b[k, 0]) and math.isfinite(b[k, 1])


def finite_rows(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(N,) bool: segments whose four coordinates are finite ((N, 2) float64 end points)."""
    out = np.empty(a.shape[0], dtype=np.bool_)
    _finite_kernel(frozen(a), frozen(b), out)
    return out


def _beyond_numpy(values: NDArray[np.float64], low: float, high: float) -> NDArray[np.bool_]:
    """:func:`_beyond` in numpy operations (its reference in tests)."""
    magnitude = np.abs(values.reshape(values.shape[0], -1))
    with np.errstate(invalid="ignore"):
        return np.asarray(((magnitude != 0.0) & ((magnitude < low) | (magnitude > high))).any(axis=1), dtype=np.bool_)
