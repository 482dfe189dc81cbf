"""Exact oracle for integer Bresenham lines (seed 003), with its rational reference; spans as
in :mod:`harness.oracle.line_spans`.

Bresenham (:func:`bresenham_spans`)
    Seed 003: integer end points, one pixel per step of the major axis, octants centred on
    the first point (the walk starts at ``a`` and goes towards ``b``).

    * End point p -> pixel (i, j), exactly, by the declared ``rounding``: the pixel holding
      p. ``floor``: i = floor(px) (seed 000's floor). ``toward-zero``: i = trunc(px), C's
      ``(int)`` cast of the window coordinate (softpipe's ``sp_setup_line``, Pillow's
      ``ImageDraw.line``): floor for px >= 0, but pixel 0 for -1 < px < 0.
      ``nearest-even``/``half-away``: i is the integer nearest to px - 1/2, i.e. the pixel
      whose centre i + 1/2 is nearest to px; that is floor(px) except when px is an integer
      (p on the boundary of pixels px - 1 and px), where ``nearest-even`` takes the even
      one and ``half-away`` the one away from zero (px when px - 1/2 > 0, px - 1 when px -
      1/2 < 0). Likewise j from py.
    * x-major when |x1 - x0| >= |y1 - y0| (integers), else y-major. With K = |major delta|,
      M = |minor delta|: the classic decision variable ``p = 2M - K``; after each pixel the
      major coordinate steps, and the minor one steps when ``p >= 0`` (then ``p += 2M - 2K``,
      else ``p += 2M``) -- Hearn & Baker's and GeeksforGeeks' decision parameter (the
      seed's first reference), softpipe's ``if (error < 0) ... else y0 += ystep``. A tie
      (p = 0: the ideal line exactly halfway between two pixel centres) steps towards the
      end point (``ties="step"``); ``ties="stay"`` keeps the minor coordinate on a tie
      (Foley & van Dam's midpoint test ``d <= 0``; Wikipedia's ``D > 0``). Closed form: the
      minor offset at major step k is ``round(k*M/K)`` with halves rounded up (``step``) or
      down (``stay``). Both end points are drawn (K + 1 pixels); ``last_pixel=False``
      drops the last (K pixels, none for a zero-length segment).
    * Direction of travel (``direction``). The walk above starts at ``a`` (``as-given``), and
      its ties and its last pixel belong to the walk: drawn backwards, a tie steps the other
      way (``step`` from b is ``stay`` from a) and the other end pixel is the last. Textbook
      drawers normalise the direction first, on the end points' *pixels*: ``smaller-x``
      walks from the end point whose pixel has the smaller x (Hearn & Baker's ``lineBres``,
      the usual "if x0 > x1: swap" ``plotLine``; the given order when the x are equal),
      ``smaller-major`` from the one whose pixel has the smaller major coordinate (Wikipedia's
      ``plotLine`` with ``plotLineLow``/``plotLineHigh``, tinyrenderer's ``line``). Then the
      same walk runs from that end point, with the same ``ties`` and ``last_pixel`` (the
      end walked to is the one omitted): such a drawer draws a segment and its reverse
      alike (but for the omitted end of a vertical one walked from the smaller x, kept in
      its given order), and only differs from ``as-given`` on segments it reverses, at a tie
      or at the omitted end. :func:`walks_backwards` says which it reverses.
    * Rounded end points must lie within +-2**30 (every product k*M then fits int64).
    * Runs (issue 35): the kernel clips the steps to the viewport first (the steps of offset
      o are k_min(o) .. k_min(o + 1) - 1, k_min in closed form), then writes one span per
      row: a y-major walk's offsets and an x-major walk's row boundaries as float
      quotients of integers below 2**53 (exact), in loops numba vectorizes; longer walks
      step the quotient and remainder, and walks beyond 2**30 - 1 steps go pixel by pixel.
      ``_bresenham_spans_reference`` keeps the pixel-by-pixel kernel for the tests.

:func:`bresenham_spans_rational` is the slow reference: it rounds the end points exactly (in
:class:`fractions.Fraction` arithmetic) and walks the incremental decision variable
literally, pixel by pixel.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import (
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    LINE_DIRECTIONS,
    BresenhamRounding,
    BresenhamTies,
    LineDirection,
)
from harness.geometry.exact import frozen
from harness.oracle.line_spans import Spans, _as_spans, _empty, _endpoints, _spans_from_mask, _viewport, emit_pixel, span_buffers

# Rounded Bresenham end points: |k*M| <= 2**31 * 2**31 = 2**62 fits int64.
BRESENHAM_MAX = 2**30


# -- Bresenham -------------------------------------------------------------------------------


@numba.njit(cache=True)
def _bresenham_capacity(p0, p1, keep, width, height):  # type: ignore[no-untyped-def]
    total = 0
    for s in range(p0.shape[0]):
        if keep[s]:
            total += min(max(abs(p1[s, 0] - p0[s, 0]), abs(p1[s, 1] - p0[s, 1])) + 1, max(width, height))
    return total


# Runs need the row boundaries (2o - 1) * K in int64: K (and M <= K) below 2**30 keeps them
# under 2**32 * 2**30 = 2**62. Longer walks (end points up to 2**30 apart) go step by step.
_RUNS_MAX = 2**30 - 1


@numba.njit(cache=True)
def _bresenham_stepwise(s, x0, y0, x1, y1, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """One segment's walk, pixel by pixel in closed form (the reference of
    :func:`_bresenham_runs`, and its path for walks longer than ``_RUNS_MAX``). Returns
    the span count."""
    first = n
    x_major = abs(x1 - x0) >= abs(y1 - y0)
    if x_major:
        u0, v0, du, dv, extent = x0, y0, x1 - x0, y1 - y0, width
    else:
        u0, v0, du, dv, extent = y0, x0, y1 - y0, x1 - x0, height
    su = 1 if du >= 0 else -1
    sv = 1 if dv >= 0 else -1
    big_k = abs(du)
    big_m = abs(dv)
    last = big_k if last_pixel else big_k - 1
    if last < 0:
        return n
    # the steps k in [0, last] whose major coordinate u0 + su*k lies in [0, extent)
    if su > 0:
        k_lo, k_hi = max(0, -u0), min(last, extent - 1 - u0)
    else:
        k_lo, k_hi = max(0, u0 - (extent - 1)), min(last, u0)
    if k_lo > k_hi:
        return n
    # rows ascending: walk backwards when the rows run up the screen
    rows_down = (sv > 0) if x_major else (su > 0)
    k = k_lo if rows_down else k_hi
    step = 1 if rows_down else -1
    for _ in range(k_hi - k_lo + 1):
        k_now = k
        k += step
        if big_k == 0:
            offset = 0
        else:
            # The decision variable in closed form: the minor offset is k*M/K rounded
            # to nearest, a half (p = 0) stepping ("step") or staying ("stay").
            q, r = divmod(k_now * big_m, big_k)
            twice = 2 * r
            offset = q + (1 if (twice > big_k or (step_ties and twice == big_k)) else 0)
        u = u0 + su * k_now
        v = v0 + sv * offset
        x, y = (u, v) if x_major else (v, u)
        if y < 0 or y >= height or x < 0 or x >= width:
            continue
        n = emit_pixel(s, y, x, out_s, out_y, out_x0, out_x1, n, first)
    return n


@numba.njit(cache=True)
def _bresenham_kernel(p0, p1, keep, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Integer Bresenham from p0 to p1 (int64 pixel coordinates), in closed form, pixel by
    pixel and only within the viewport: the reference of :func:`_bresenham_runs_kernel`.
    Returns the number of spans written."""
    n = 0
    for s in range(p0.shape[0]):
        if keep[s]:
            n = _bresenham_stepwise(s, p0[s, 0], p0[s, 1], p1[s, 0], p1[s, 1], width, height, step_ties, last_pixel,
                                    out_s, out_y, out_x0, out_x1, n)
    return n


@numba.njit(cache=True, inline="always")
def _offset_at(k, big_m, big_k, step_ties):  # type: ignore[no-untyped-def]
    """round(k*M/K), halves up (``step``) or down (``stay``): the minor offset at step k."""
    q, r = divmod(k * big_m, big_k)
    twice = 2 * r
    return q + (1 if (twice > big_k or (step_ties and twice == big_k)) else 0)


@numba.njit(cache=True, inline="always")
def _k_min(o, big_m, big_k, step_ties):  # type: ignore[no-untyped-def]
    """The first step k with round(k*M/K) >= o (M > 0; halves up under ``step``, down under
    ``stay``): ceil((2o - 1)K / 2M), or floor((2o - 1)K / 2M) + 1. |2o - 1| <= 2**31 + 1
    and K < 2**30: the product fits int64."""
    q, r = divmod((2 * o - 1) * big_k, 2 * big_m)
    return q + ((r > 0) | (not step_ties))


# y-major walks shorter than this take the offsets in float: (2kM + K)/(2K) has a numerator
# below 2**52 (k, M < K < 2**25), and then floor(fl(N / D)) = floor(N / D) for integers with
# N + D < 2**53 (the quotient rounds up to the next integer only within half an ulp of it).
_VECTOR_MAX = 2**25


@numba.njit(cache=True)
def _y_major_vector(s, u0, su, v0, sv, k0, step, count, big_m, big_k, step_ties, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """``count`` pixels of a y-major walk from step k0 in direction ``step`` (rows ascending)
    as spans n, n + 1, ...: offset round(k*M/K) = floor((2kM + c) / 2K) with c = K (halves
    up, ``step``) or K - 1 (down), divided in float, exactly (``_VECTOR_MAX``), in one
    branch-free loop numba stores a vector at a time. Returns the span count."""
    c = big_k if step_ties else big_k - 1
    den = 2.0 * big_k
    y_first = u0 + su * k0
    for i in range(count):
        k = k0 + step * i
        x = v0 + sv * int(float(2 * k * big_m + c) / den)
        u = np.uint64(n + i)
        out_s[u] = s
        out_y[u] = y_first + i
        out_x0[u] = x
        out_x1[u] = x + 1
    return n + count


@numba.njit(cache=True)
def _x_major_vector(s, u0, su, v0, sv, o0, count, k_lo, k_hi, big_m, big_k, step_ties, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """``count`` rows of an x-major walk from offset o0 (rows ascending: offsets up when
    ``sv`` > 0) as spans n, n + 1, ...: row o holds the steps k_min(o) .. k_min(o + 1) - 1
    clipped to [k_lo, k_hi], k_min(o) = floor(((2o - 1)K + c) / 2M) with c = 2M - 1 (the
    ceiling, ``step``) or 2M (``stay``), divided in float, exactly (``_VECTOR_MAX``; a
    negative numerator is a step before k_lo >= 0, taken as 0), in one branch-free loop
    numba stores a vector at a time. Returns the span count."""
    den = 2 * big_m
    c = den - 1 if step_ties else den
    fden = float(den)
    y_first = v0 + sv * o0
    for i in range(count):
        o = o0 + sv * i
        k_first = max(int(float(max((2 * o - 1) * big_k + c, 0)) / fden), k_lo)
        k_last = min(int(float(max((2 * o + 1) * big_k + c, 0)) / fden) - 1, k_hi)
        a_u = u0 + su * k_first
        b_u = u0 + su * k_last
        u = np.uint64(n + i)
        out_s[u] = s
        out_y[u] = y_first + i
        out_x0[u] = min(a_u, b_u)
        out_x1[u] = max(a_u, b_u) + 1
    return n + count


@numba.njit(cache=True)
def _bresenham_runs(s, x0, y0, x1, y1, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1, n):  # type: ignore[no-untyped-def]
    """One segment's walk as runs: the spans :func:`_bresenham_stepwise` writes, one per
    row, without a division per pixel. Returns the span count.

    The offset of step k is round(k*M/K); the steps of offset o are those from k_min(o) to
    k_min(o + 1) - 1 (:func:`_k_min`), so the viewport's rows and columns clip the steps
    before the walk, which then writes every row it visits (consecutive rows). y-major: one pixel per
    step, the offset k*M/K kept as quotient and remainder and stepped by M. x-major: one
    run per offset, the quotient and remainder of (2o - 1)K by 2M stepped by 2K."""
    x_major = abs(x1 - x0) >= abs(y1 - y0)
    if x_major:
        u0, v0, du, dv, extent, v_extent = x0, y0, x1 - x0, y1 - y0, width, height
    else:
        u0, v0, du, dv, extent, v_extent = y0, x0, y1 - y0, x1 - x0, height, width
    big_k = abs(du)
    big_m = abs(dv)
    if big_k > _RUNS_MAX:
        return _bresenham_stepwise(s, x0, y0, x1, y1, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1, n)
    su = 1 if du >= 0 else -1
    sv = 1 if dv >= 0 else -1
    last = big_k if last_pixel else big_k - 1
    if last < 0:
        return n
    # the steps k in [0, last] whose major coordinate u0 + su*k lies in [0, extent)
    if su > 0:
        k_lo, k_hi = max(0, -u0), min(last, extent - 1 - u0)
    else:
        k_lo, k_hi = max(0, u0 - (extent - 1)), min(last, u0)
    # the offsets whose minor coordinate v0 + sv*o lies in [0, v_extent)
    if sv > 0:
        o_lo, o_hi = -v0, v_extent - 1 - v0
    else:
        o_lo, o_hi = v0 - (v_extent - 1), v0
    if big_m == 0:  # offset 0 throughout: one row (x-major) or one column
        if not o_lo <= 0 <= o_hi:
            return n
    else:  # the steps whose offset lies in [o_lo, o_hi] (offsets grow with k)
        k_lo = max(k_lo, _k_min(o_lo, big_m, big_k, step_ties))
        k_hi = min(k_hi, _k_min(o_hi + 1, big_m, big_k, step_ties) - 1)
    if k_lo > k_hi:
        return n
    if not x_major:
        # one pixel per row; rows ascending = k ascending when the walk goes down the screen
        step = 1 if su > 0 else -1
        k = k_lo if step > 0 else k_hi
        if big_k < _VECTOR_MAX:
            return _y_major_vector(s, u0, su, v0, sv, k, step, k_hi - k_lo + 1, big_m, big_k, step_ties,
                                   out_s, out_y, out_x0, out_x1, n)
        q, r = divmod(k * big_m, big_k)
        # a tie rounds up under "step": 2r > K - 1 instead of 2r > K
        bar = big_k - 1 if step_ties else big_k
        y = u0 + su * k
        for _ in range(k_hi - k_lo + 1):
            x = v0 + sv * (q + (2 * r > bar))
            u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
            out_s[u] = s
            out_y[u] = y
            out_x0[u] = x
            out_x1[u] = x + 1
            n += 1
            y += 1
            if step > 0:
                r += big_m
                carry = r >= big_k
                r = r - big_k if carry else r  # a select, not a branch or a product: 3 cycles a pixel
                q += carry
            else:
                r -= big_m
                borrow = r < 0
                r = r + big_k if borrow else r
                q -= borrow
        return n
    if big_m == 0:  # one row
        a_u, b_u = u0 + su * k_lo, u0 + su * k_hi
        u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
        out_s[u] = s
        out_y[u] = v0
        out_x0[u] = min(a_u, b_u)
        out_x1[u] = max(a_u, b_u) + 1
        return n + 1
    # x-major: every offset of the clipped steps is a row of the viewport with a run
    o_lo = _offset_at(k_lo, big_m, big_k, step_ties)
    o_hi = _offset_at(k_hi, big_m, big_k, step_ties)
    den = 2 * big_m
    dq, dr = divmod(2 * big_k, den)
    # rows ascending: offsets ascending when the walk goes down the screen
    o = o_lo if sv > 0 else o_hi
    if big_k < _VECTOR_MAX:
        return _x_major_vector(s, u0, su, v0, sv, o, o_hi - o_lo + 1, k_lo, k_hi, big_m, big_k, step_ties,
                               out_s, out_y, out_x0, out_x1, n)
    # (2o - 1)K = q*2M + r: the row's first step is k_min(o), its last k_min(o + 1) - 1
    q, r = divmod((2 * o - 1) * big_k, den)
    late = not step_ties
    y = v0 + sv * o
    for _ in range(o_hi - o_lo + 1):
        r1 = r + dr
        carry = r1 >= den
        r1 = r1 - den if carry else r1
        q1 = q + dq + carry
        k_first = max(q + ((r > 0) | late), k_lo)
        k_last = min(q1 + ((r1 > 0) | late) - 1, k_hi)
        a_u, b_u = u0 + su * k_first, u0 + su * k_last
        u = np.uint64(n)  # an unsigned index: no wraparound test, stores 3x faster
        out_s[u] = s
        out_y[u] = y
        out_x0[u] = min(a_u, b_u)
        out_x1[u] = max(a_u, b_u) + 1
        n += 1
        y += 1
        if sv > 0:
            q, r = q1, r1
        else:
            r -= dr
            borrow = r < 0
            r = r + den if borrow else r
            q -= dq + borrow
    return n


@numba.njit(cache=True)
def _bresenham_runs_kernel(p0, p1, keep, width, height, step_ties, last_pixel, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Integer Bresenham from p0 to p1 (int64 pixel coordinates) as runs, only within the
    viewport (:func:`_bresenham_runs`). Returns the number of spans written."""
    n = 0
    for s in range(p0.shape[0]):
        if keep[s]:
            n = _bresenham_runs(s, p0[s, 0], p0[s, 1], p1[s, 0], p1[s, 1], width, height, step_ties, last_pixel,
                                out_s, out_y, out_x0, out_x1, n)
    return n


# -- Bresenham: public --------------------------------------------------------------------------


_ROUNDING_CODES = {"toward-zero": 0, "floor": 1, "nearest-even": 2, "half-away": 3}


@numba.njit(cache=True)
def _end_point_pixels_kernel(p, code, out):  # type: ignore[no-untyped-def]
    """:func:`end_point_pixels` on a flat array, the same float operations per value."""
    for k in range(p.shape[0]):
        v = p[k]
        if code == 0:
            out[k] = np.trunc(v) + 0.0  # (int)p; + 0.0 turns -0.0 into 0.0
            continue
        f = np.floor(v)
        if code == 1 or v - f != 0.0:  # p - 1/2 not a half (NaN neither): no tie
            out[k] = f
        elif code == 2:
            out[k] = f if np.fmod(f, 2.0) == 0.0 else f - 1.0
        else:  # half-away: p - 1/2 > 0 rounds up to f, < 0 down to f - 1
            out[k] = f if f >= 1.0 else f - 1.0


def end_point_pixels(p: NDArray[np.float64], rounding: str) -> NDArray[np.float64]:
    """Pixel coordinates of points, exactly (see the module docstring): floor(p) and
    trunc(p) are exact, and so is p - floor(p). Any shape; NaN stays NaN."""
    values = np.asarray(p, dtype=np.float64)
    flat = np.ascontiguousarray(values).reshape(-1)
    out = np.empty(flat.shape[0], dtype=np.float64)
    _end_point_pixels_kernel(frozen(flat), _ROUNDING_CODES.get(rounding, 3), out)  # else: half-away, as before
    return out.reshape(values.shape)


def _end_point_pixels_numpy(p: NDArray[np.float64], rounding: str) -> NDArray[np.float64]:
    """:func:`end_point_pixels` in numpy operations (its reference in tests)."""
    if rounding == "toward-zero":
        return np.trunc(p) + 0.0  # (int)p; + 0.0 turns -0.0 into 0.0
    f = np.floor(p)
    if rounding == "floor":
        return f
    on_boundary = (p - f) == 0.0  # p - 1/2 is a half: the tie
    if rounding == "nearest-even":
        tie = np.where(np.fmod(f, 2.0) == 0.0, f, f - 1.0)
    else:  # half-away: p - 1/2 > 0 rounds up to f, < 0 down to f - 1
        tie = np.where(f >= 1.0, f, f - 1.0)
    return np.where(on_boundary, tie, f)


def walks_backwards(p0: NDArray[Any], p1: NDArray[Any], direction: str) -> NDArray[np.bool_]:
    """(N,) bool: which Bresenham walks between end point pixels ``p0`` -> ``p1`` ((N, 2)
    integers: int64, or Python integers in an object array) run from ``p1`` to ``p0`` under ``direction`` (see the
    module docstring): never (``as-given``); where x0 > x1 (``smaller-x``); where the major
    coordinate of p0 exceeds p1's (``smaller-major``; x-major when |x1 - x0| >= |y1 - y0|).

    >>> p0, p1 = np.array([[5, 0], [0, 5], [3, 9]]), np.array([[0, 2], [2, 0], [3, 1]])
    >>> [walks_backwards(p0, p1, d).tolist() for d in ("as-given", "smaller-x", "smaller-major")]
    [[False, False, False], [True, False, False], [True, True, True]]
    """
    if direction not in LINE_DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(LINE_DIRECTIONS)}, not {direction!r}")
    p0, p1 = np.asarray(p0), np.asarray(p1)
    if direction == "as-given":
        return np.zeros(p0.shape[0], dtype=np.bool_)
    if direction == "smaller-x":
        return np.asarray(p0[:, 0] > p1[:, 0], dtype=np.bool_)
    x_major = np.abs(p1[:, 0] - p0[:, 0]) >= np.abs(p1[:, 1] - p0[:, 1])
    return np.asarray(np.where(x_major, p0[:, 0] > p1[:, 0], p0[:, 1] > p1[:, 1]), dtype=np.bool_)


def _walk_ends(p0: NDArray[Any], p1: NDArray[Any], direction: str) -> tuple[NDArray[Any], NDArray[Any]]:
    """The walks' (start, end) pixels: ``p0, p1`` swapped where :func:`walks_backwards`."""
    back = walks_backwards(p0, p1, direction)[:, None]
    return np.where(back, p1, p0), np.where(back, p0, p1)


def _bresenham_prepare(a: ArrayLike, b: ArrayLike, width: int, height: int, rounding: str, ties: str,
                       direction: str) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_], int, int]:
    """The walks' start and end pixels (int64, (N, 2) each: the rounded end points, in
    the order ``direction`` walks them), which segments are finite, and the viewport."""
    width, height = _viewport(width, height)
    if rounding not in BRESENHAM_ROUNDINGS:
        raise ValueError(f"rounding must be one of {', '.join(BRESENHAM_ROUNDINGS)}, not {rounding!r}")
    if ties not in BRESENHAM_TIES:
        raise ValueError(f"ties must be one of {', '.join(BRESENHAM_TIES)}, not {ties!r}")
    if direction not in LINE_DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(LINE_DIRECTIONS)}, not {direction!r}")
    a_arr, b_arr, keep = _endpoints(a, b)
    with np.errstate(invalid="ignore"):
        p0 = np.where(keep[:, None], end_point_pixels(a_arr, rounding), 0.0)
        p1 = np.where(keep[:, None], end_point_pixels(b_arr, rounding), 0.0)
    beyond = (np.abs(np.concatenate([p0, p1], axis=1)) > BRESENHAM_MAX).any(axis=1)
    if beyond.any():
        k = int(np.flatnonzero(beyond)[0])
        raise ValueError(f"segment {k} has a rounded end point beyond +-2**30 pixels")
    p0, p1 = _walk_ends(p0, p1, direction)
    return p0.astype(np.int64), p1.astype(np.int64), keep, width, height


def bresenham_spans(a: ArrayLike, b: ArrayLike, width: int, height: int, rounding: BresenhamRounding = "nearest-even",
                    ties: BresenhamTies = "step", last_pixel: bool = True, direction: LineDirection = "as-given") -> Spans:
    """The pixels integer Bresenham draws from ``a[k]`` to ``b[k]`` (seed 003).

    Parameters
    ----------
    a, b : (N, 2) float64
        End points, rounded to pixels by ``rounding`` (see the module docstring).
    width, height : int
        The viewport.
    rounding : {"nearest-even", "half-away", "floor", "toward-zero"}
    ties : {"step", "stay"}
        Decision variable zero: step the minor coordinate (``p >= 0``) or keep it (``p > 0``).
    last_pixel : bool
        Draw the pixel the walk ends in (True) or stop one step short.
    direction : {"as-given", "smaller-x", "smaller-major"}
        Where the walk starts (:func:`walks_backwards`): at ``a[k]``, or at the end point
        whose pixel has the smaller x, or the smaller major coordinate (textbook plotLine).

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        Spans sorted by segment, row and x0.

    Examples
    --------
    >>> s, y, x0, x1 = bresenham_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 1), (1, 1, 3), (2, 3, 5)]
    >>> s, y, x0, x1 = bresenham_spans([[0.5, 0.5]], [[4.5, 2.5]], 6, 4, ties="stay")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]

    Drawn right to left, the ties step the other way; a drawer walking from the smaller x
    draws it as left to right:

    >>> s, y, x0, x1 = bresenham_spans([[4.5, 2.5]], [[0.5, 0.5]], 6, 4)
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]
    >>> s, y, x0, x1 = bresenham_spans([[4.5, 2.5]], [[0.5, 0.5]], 6, 4, direction="smaller-x")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 1), (1, 1, 3), (2, 3, 5)]
    """
    p0, p1, keep, width, height = _bresenham_prepare(a, b, width, height, rounding, ties, direction)
    return _bresenham_walks(p0, p1, keep, width, height, ties, last_pixel)


def _bresenham_walks(p0: NDArray[np.int64], p1: NDArray[np.int64], keep: NDArray[np.bool_], width: int, height: int,
                     ties: str, last_pixel: bool, reference: bool = False) -> Spans:
    """The spans of the walks from pixel ``p0[k]`` to ``p1[k]`` ((N, 2) int64, within
    +-2**30) of the kept segments: by runs (:func:`_bresenham_runs`), or pixel by pixel
    (``reference``: :func:`_bresenham_stepwise`, the same spans)."""
    if not keep.any() or width == 0 or height == 0:
        return _empty()
    p0, p1, keep_f = frozen(p0, np.int64), frozen(p1, np.int64), frozen(keep, np.bool_)
    capacity = int(_bresenham_capacity(p0, p1, keep_f, width, height))
    out = span_buffers(capacity)
    kernel = _bresenham_kernel if reference else _bresenham_runs_kernel
    m = int(kernel(p0, p1, keep_f, width, height, ties == "step", bool(last_pixel), *out))
    return out[0][:m], out[1][:m], out[2][:m], out[3][:m]


def _bresenham_spans_reference(a: ArrayLike, b: ArrayLike, width: int, height: int,
                               rounding: BresenhamRounding = "nearest-even", ties: BresenhamTies = "step",
                               last_pixel: bool = True, direction: LineDirection = "as-given") -> Spans:
    """:func:`bresenham_spans` pixel by pixel (the kernel before runs; tests compare the two)."""
    p0, p1, keep, width, height = _bresenham_prepare(a, b, width, height, rounding, ties, direction)
    return _bresenham_walks(p0, p1, keep, width, height, ties, last_pixel, reference=True)


bresenham_pixels = bresenham_spans  # the name for it


def _round_pixel_rational(v: Fraction, rounding: str) -> int:
    if rounding == "toward-zero":
        return math.trunc(v)
    if rounding == "floor":
        return math.floor(v)
    c = v - Fraction(1, 2)
    f = math.floor(c)
    r = c - f
    if r != Fraction(1, 2):
        return f if r < Fraction(1, 2) else f + 1
    if rounding == "nearest-even":
        return f if f % 2 == 0 else f + 1
    return f + 1 if c > 0 else f


def bresenham_spans_rational(a: ArrayLike, b: ArrayLike, width: int, height: int,
                             rounding: BresenhamRounding = "nearest-even", ties: BresenhamTies = "step",
                             last_pixel: bool = True, direction: LineDirection = "as-given") -> Spans:
    """The same pixels as :func:`bresenham_spans` by the literal algorithm: end points
    rounded in rational arithmetic, swapped as a textbook plotLine swaps them
    (``direction``), then the incremental decision variable walked pixel by pixel from
    the first (small coordinates only)."""
    width, height = _viewport(width, height)
    if rounding not in BRESENHAM_ROUNDINGS or ties not in BRESENHAM_TIES or direction not in LINE_DIRECTIONS:
        raise ValueError(f"bad rounding {rounding!r}, ties {ties!r} or direction {direction!r}")
    a_arr, b_arr, keep = _endpoints(a, b)
    out: list[tuple[int, int, int, int]] = []
    for s in np.flatnonzero(keep):
        x0, y0 = (_round_pixel_rational(Fraction(float(v)), rounding) for v in a_arr[s])
        x1, y1 = (_round_pixel_rational(Fraction(float(v)), rounding) for v in b_arr[s])
        x_major = abs(x1 - x0) >= abs(y1 - y0)
        if direction == "smaller-x" and x0 > x1:
            x0, y0, x1, y1 = x1, y1, x0, y0
        if direction == "smaller-major" and ((x_major and x0 > x1) or (not x_major and y0 > y1)):
            x0, y0, x1, y1 = x1, y1, x0, y0
        u, v, du, dv = (x0, y0, x1 - x0, y1 - y0) if x_major else (y0, x0, y1 - y0, x1 - x0)
        su, sv = (1 if du >= 0 else -1), (1 if dv >= 0 else -1)
        big_k, big_m = abs(du), abs(dv)
        p = 2 * big_m - big_k
        covered = [[False] * width for _ in range(height)]
        for k in range(big_k + 1):
            if k < big_k or last_pixel:
                x, y = (u, v) if x_major else (v, u)
                if 0 <= x < width and 0 <= y < height:
                    covered[y][x] = True
            if k == big_k:
                break
            if p > 0 or (p == 0 and ties == "step"):
                v += sv
                p -= 2 * big_k
            p += 2 * big_m
            u += su
        _spans_from_mask(int(s), covered, out)
    return _as_spans(out)


def _bresenham_far(segment: int, p0: tuple[int, int], p1: tuple[int, int], width: int, height: int, ties: str,
                   last_pixel: bool, out: list[tuple[int, int, int, int]]) -> None:
    """One Bresenham segment with end-point pixels of any size (Python integers): the
    closed form ``minor = round(k*M/K)`` (halves up for ``step``, down for ``stay``) on the
    steps k whose pixel lies in the viewport, found by bisection (the walk is monotone)."""
    x_major = abs(p1[0] - p0[0]) >= abs(p1[1] - p0[1])
    u0, v0, du, dv = (p0[0], p0[1], p1[0] - p0[0], p1[1] - p0[1]) if x_major else (p0[1], p0[0], p1[1] - p0[1], p1[0] - p0[0])
    su, sv = (1 if du >= 0 else -1), (1 if dv >= 0 else -1)
    big_k, big_m = abs(du), abs(dv)
    u_size, v_size = (width, height) if x_major else (height, width)
    last = big_k if last_pixel else big_k - 1
    if last < 0:
        return

    def minor(k: int) -> int:
        if big_k == 0:
            return v0
        # round(k*M/K): halves up (step) = floor((2kM + K) / 2K); halves down (stay) = ceil((2kM - K) / 2K)
        offset = (2 * k * big_m + big_k) // (2 * big_k) if ties == "step" else -((big_k - 2 * k * big_m) // (2 * big_k))
        return v0 + sv * offset

    # steps whose major coordinate lies in [0, u_size)
    lo_u, hi_u = (0 - u0, u_size - 1 - u0) if su > 0 else (u0 - (u_size - 1), u0)
    k_lo, k_hi = max(0, lo_u), min(last, hi_u)
    if k_lo > k_hi:
        return

    def inside_or_before(k: int) -> bool:  # minor not yet past the viewport's far side
        v = minor(k)
        return v <= v_size - 1 if sv > 0 else v >= 0

    def reached(k: int) -> bool:  # minor already at or past the viewport's near side
        v = minor(k)
        return v >= 0 if sv > 0 else v <= v_size - 1

    def first_true(lo: int, hi: int, test: Any) -> int:
        while lo < hi:
            mid = (lo + hi) // 2
            if test(mid):
                hi = mid
            else:
                lo = mid + 1
        return lo

    start = first_true(k_lo, k_hi + 1, reached)
    stop = first_true(start, k_hi + 1, lambda k: not inside_or_before(k))
    for k in range(start, stop):
        u, v = u0 + su * k, minor(k)
        x, y = (u, v) if x_major else (v, u)
        out.append((segment, y, x, x + 1))
