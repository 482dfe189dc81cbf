"""Exact geometric predicates on float64 input.

Floats are dyadic rationals, so the sign of an edge function is computable exactly. Two
tiers run in compiled code:

1. a float filter (Shewchuk's ``orient2d`` error bound ``ccwerrboundA``): the float
   determinant's sign is certain whenever its magnitude exceeds the bound;
2. otherwise the determinant is summed exactly as a floating-point expansion
   (error-free products and sums, Shewchuk 1997), whose largest component has its sign.

Expansions are exact while no product overflows or underflows. :data:`SAFE_MAX` and
:data:`SAFE_MIN` bound the magnitudes for which that holds; :func:`in_safe_range` tells
callers when to take the third tier, exact rational arithmetic in Python
(:func:`orient2d_fraction`), which works for every finite float.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "SAFE_MAX",
    "SAFE_MIN",
    "orient2d_sign",
    "orient2d_fraction",
    "in_safe_range",
    "frozen",
    "orientation",
]

# Shewchuk's error bound for the float orient2d: |det - exact| <= CCW_ERRBOUND_A * detsum.
_EPSILON = 2.0**-53
CCW_ERRBOUND_A = (3.0 + 16.0 * _EPSILON) * _EPSILON
# Dekker's splitter for 53-bit mantissas: 2**27 + 1.
_SPLITTER = 134217729.0
# Bounds for exact expansions: products of two coordinates stay below 2**900 (no overflow,
# splitting needs |a| < 2**996), and the smallest nonzero partial product stays above
# 2**(-450-450-104) = 2**-1004, a normal float (no underflow).
SAFE_MAX = 2.0**450
SAFE_MIN = 2.0**-450


@numba.njit(cache=True, inline="always")
def _two_sum(a: float, b: float) -> tuple[float, float]:
    x = a + b
    bv = x - a
    av = x - bv
    return x, (a - av) + (b - bv)


@numba.njit(cache=True, inline="always")
def _split(a: float) -> tuple[float, float]:
    c = _SPLITTER * a
    big = c - a
    hi = c - big
    return hi, a - hi


@numba.njit(cache=True, inline="always")
def _two_product(a: float, b: float) -> tuple[float, float]:
    x = a * b
    ahi, alo = _split(a)
    bhi, blo = _split(b)
    err = x - ahi * bhi
    err = err - alo * bhi
    err = err - ahi * blo
    return x, alo * blo - err


@numba.njit(cache=True)
def _orient2d_exact_sign(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> int:
    # det = ax*by - ay*bx + bx*cy - by*cx + cx*ay - cy*ax, summed as an exact expansion.
    terms = np.empty(12)
    terms[0], terms[1] = _two_product(ax, by)
    terms[2], terms[3] = _two_product(-ay, bx)
    terms[4], terms[5] = _two_product(bx, cy)
    terms[6], terms[7] = _two_product(-by, cx)
    terms[8], terms[9] = _two_product(cx, ay)
    terms[10], terms[11] = _two_product(-cy, ax)
    h = np.empty(12)
    length = 0
    for t in range(12):
        # grow_expansion_zeroelim: h stays nonoverlapping, increasing in magnitude.
        q = terms[t]
        k = 0
        for i in range(length):
            q, err = _two_sum(q, h[i])
            if err != 0.0:
                h[k] = err
                k += 1
        if q != 0.0:
            h[k] = q
            k += 1
        length = k
    if length == 0:
        return 0
    return 1 if h[length - 1] > 0.0 else -1


@numba.njit(cache=True)
def orient2d_sign(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> int:
    """Exact sign of ``E_ab(c) = (bx-ax)*(cy-ay) - (by-ay)*(cx-ax)``: -1, 0 or +1.

    Valid when every coordinate is zero or has magnitude in [SAFE_MIN, SAFE_MAX].
    """
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    # Signs of differences and of their products are exact: a certain sign needs no bound.
    if detleft > 0.0:
        if detright <= 0.0:
            return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
        detsum = detleft + detright
    elif detleft < 0.0:
        if detright >= 0.0:
            return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
        detsum = -detleft - detright
    else:
        return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
    bound = CCW_ERRBOUND_A * detsum
    if det > bound:
        return 1
    if -det > bound:
        return -1
    return _orient2d_exact_sign(ax, ay, bx, by, cx, cy)


def orient2d_fraction(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> int:
    """Exact sign of the same determinant in rational arithmetic: any finite floats.

    >>> orient2d_fraction(0.0, 0.0, 1e308, 1e308, -1e308, -1e308)
    0
    >>> orient2d_fraction(0.0, 0.0, 1.0, 0.0, 0.5, 1e-320)
    1
    """
    def units(v: float) -> int:
        # v as an integer count of 2**-1074 (every finite float is one): the same scale
        # for all six, so the determinant's sign is kept, in exact integer arithmetic
        m, d = v.as_integer_ratio()  # d = 2**k, k <= 1074
        return m << (1075 - d.bit_length())

    iax, iay, ibx, iby, icx, icy = map(units, (ax, ay, bx, by, cx, cy))
    det = (ibx - iax) * (icy - iay) - (iby - iay) * (icx - iax)
    return (det > 0) - (det < 0)


def frozen(array: ArrayLike, dtype: type = np.float64) -> NDArray:
    """``array`` as every numba kernel takes it: C-contiguous, read-only, of ``dtype``
    (a read-only view when it was writable; no copy when it already is).

    Numba compiles a kernel once per layout and writeability of its array arguments
    (seconds each), so every call site hands kernels this one type: a scene's own arrays
    (which :class:`harness.contract.scenes.Scene` keeps C-contiguous and read-only) and the arrays
    computed from them alike.

    >>> a = frozen(np.zeros((2, 3)).T)
    >>> a.flags.c_contiguous, a.flags.writeable
    (True, False)
    """
    out: NDArray = np.ascontiguousarray(array, dtype=dtype)
    if out.flags.writeable:
        out = out.view()
        out.flags.writeable = False
    return out


def in_safe_range(values: NDArray[np.float64], axis: int | tuple[int, ...] = -1) -> NDArray[np.bool_]:
    """True where every value along ``axis`` is zero or of magnitude in [SAFE_MIN, SAFE_MAX]."""
    magnitude = np.abs(values)
    ok = (magnitude == 0.0) | ((magnitude >= SAFE_MIN) & (magnitude <= SAFE_MAX))
    safe: NDArray[np.bool_] = np.all(ok, axis=axis)
    return safe


@numba.njit(cache=True)
def sign_kernel(positions, sign, safe):  # type: ignore[no-untyped-def]
    """Exact area sign of every finite triangle whose coordinates are within the
    expansions' safe range; 0 for non-finite ones; 2 marks finite ones outside the range
    (for :func:`orient2d_fraction`). ``safe`` records which are within it."""
    for t in range(positions.shape[0]):
        p = positions[t]
        finite = True
        in_range = True
        for v in range(3):
            for c in range(2):
                value = p[v, c]
                if not np.isfinite(value):
                    finite = False
                magnitude = abs(value)
                if magnitude != 0.0 and (magnitude < SAFE_MIN or magnitude > SAFE_MAX):
                    in_range = False
        safe[t] = finite and in_range
        if not finite:
            sign[t] = 0
        elif not in_range:
            sign[t] = 2
        else:
            sign[t] = orient2d_sign(p[0, 0], p[0, 1], p[1, 0], p[1, 1], p[2, 0], p[2, 1])


def orientation(
    positions: NDArray[np.float64], safe: NDArray[np.bool_] | None = None
) -> NDArray[np.int8]:
    """Exact sign of each triangle's signed area A; 0 for non-finite triangles.

    Parameters
    ----------
    positions : (N, 3, 2) float64
    safe : (N,) bool, optional
        Filled with whether each triangle lies within the expansions' safe range.

    Returns
    -------
    (N,) int8
        +1 clockwise on screen (y down), -1 counter-clockwise, 0 degenerate or non-finite.

    Examples
    --------
    >>> orientation(np.array([[[0, 0], [4, 0], [0, 4]], [[0, 0], [0, 4], [4, 0]],
    ...                       [[0, 0], [1, 1], [1e300, 1e300]]], dtype=float))
    array([ 1, -1,  0], dtype=int8)
    """
    positions = frozen(positions).reshape(-1, 3, 2)
    sign = np.empty(positions.shape[0], dtype=np.int8)
    if safe is None:
        safe = np.empty(positions.shape[0], dtype=np.bool_)
    sign_kernel(positions, sign, safe)
    for t in np.flatnonzero(sign == 2):  # beyond the expansions: exact rationals
        p = positions[t]
        sign[t] = orient2d_fraction(p[0, 0], p[0, 1], p[1, 0], p[1, 1], p[2, 0], p[2, 1])
    return sign
