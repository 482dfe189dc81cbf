"""Exact oracles of two libraries' one-pixel lines read from their sources -- skia's hairlines
and Qt's cosmetic lines -- with their rational references; spans as in
:mod:`harness.oracle.line_spans`.

Both are fixed-point DDAs: the end points go to 26.6 fixed point, the slope to 16.16, and
one pixel is drawn per step along the major axis, in the row (column) holding the
fixed-point minor coordinate. Everything after the conversion is integer arithmetic, so the
rules are exact by nature; the conversion ``trunc(c * 64)`` is exact on float64 (a power of
two times a float is a float; truncation of a float is exact). Each rule is one
:class:`HairlineRule` object in :data:`HAIRLINE_RULES`, registered once; the line oracle
(:func:`harness.oracle.lines.line_coverage`) and identify's line fit read that registry.

skia hairlines (``skia-hairline``)
    skia, ``src/core/SkScan_Hairline.cpp``, ``SkScan::HairLineRgn`` (what an aliased stroke
    of width 0 draws: ``SkDraw::drawPoints``' ``bw_line_hair_proc``, and ``SkScan::HairPath``
    with butt caps). End points ``x0 = SkScalarToFDot6(x) = (int)(x * 64)`` (toward zero;
    skia receives float32: declare ``Convention(input="float32")`` or the 26.6 grid in
    front of it). With ``dx = x1 - x0``, ``dy = y1 - y0``: when ``|dx| > |dy|`` (x-major;
    ``|dx| == |dy|`` is y-major) the segment is taken left to right (end points swapped
    when ``x0 > x1``), columns ``ix0 = (x0 + 32) >> 6`` up to ``ix1 = (x1 + 32) >> 6``
    exclusive (none when equal: "too short to draw"), the slope
    ``SkFixedDiv(dy, dx) = (dy << 16) / dx`` (C division, toward zero), the start
    ``(y0 << 10) + ((slope * ((32 - x0) & 63)) >> 6)`` (y at the first pixel centre at or
    right of x0), column ``ix0 + k`` in row ``(start + k * slope) >> 16``
    (``horiline``); y-major likewise with the axes exchanged (``vertline``), top to bottom.
    So the end with the smaller major coordinate draws its pixel only when it lies left of
    (above) the pixel's centre, the other only when at or right of it; and an end exactly
    on a pixel centre starts the DDA at that centre but draws from the next pixel, one slope
    step off. A segment whose 26.6 ends coincide draws nothing.

Qt cosmetic lines (``qt-cosmetic``)
    qtbase, ``src/gui/painting/qcosmeticstroker.cpp``, ``QCosmeticStroker::drawLine`` and the
    aliased ``drawLine<drawPixel, NoDasher>`` (a ``QPen`` of width 0, Qt's default
    ``SquareCap``: ``CapBegin | CapEnd``; ``legacyRounding`` off), one segment per call
    (no dropout control between segments: ``lastPixel`` starts at -1). End points
    ``toF26Dot6(x) = (int)(x * 64.)`` (toward zero; Qt receives float64). With
    ``dx = |x2 - x1|``, ``dy = |y2 - y1|``: when ``dx < dy`` y-major, else x-major (ties
    x-major). x-major: taken left to right, ``yinc = (dy << 16) / dx`` (C division), ``y =
    y1 << 10``; the caps (``capAdjust``) move ``x1`` by -32, ``y`` by ``-(yinc >> 1)`` and
    ``x2`` by +32; columns ``x = (x1 + 32) >> 6`` up to ``xs = (x2 + 32) >> 6`` exclusive,
    ``y += (((x << 6) + round - x1) * yinc) >> 6`` with ``round = 32`` when ``yinc > 0``
    else 0, column ``x + k`` in row ``(y + k * yinc) >> 16``. y-major likewise, top to
    bottom. So both end pixels are drawn (the caps reach half a pixel past each end). A
    segment whose two end points are equal draws the pixel holding them (floor, floor);
    one whose 26.6 ends coincide but whose points differ draws nothing. Qt compares the end
    points with ``qFuzzyCompare`` (relative 1e-12), not exactly: two points that close but
    not equal are drawn as one point by Qt -- an epsilon, not part of this rule.

Both libraries clip a segment to a rectangle around the viewport first, in floating point
(skia: ``SkLineClipper::IntersectLine`` to the clip bounds, in float32; Qt:
``QCosmeticStroker::clipLine`` to the device rectangle grown by 1 px left and top, 2 px
right and bottom): a segment leaving that rectangle is drawn from a moved end point, by the
viewport, not by the rule. The rules here are the unclipped ones, in unbounded integers.

:func:`hairline_spans_rational` is the slow reference: every pixel of the viewport tested
against the closed form of each rule (the k-th step's row from ``start + k * slope``),
written in :class:`fractions.Fraction` and Python integers from the definitions above,
without the DDA's accumulation or its viewport clipping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.oracle.line_spans import Spans, _as_spans, _empty, _endpoints, _viewport

__all__ = ["HairlineRule", "HAIRLINE_RULES", "HAIRLINE_MAX", "hairline_spans", "hairline_spans_rational",
           "hairline_pixels_int", "hairline_x_major", "to_fdot6"]

HairlineName = Literal["skia-hairline", "qt-cosmetic"]

# The compiled kernel's range: |c| <= 2**33, so a 26.6 coordinate is below 2**39, y << 10
# below 2**49, (d << 16) below 2**56 and k * slope (k < 2**40, |slope| <= 2**16) below
# 2**56: nothing overflows int64. Beyond, the same walk in Python integers.
HAIRLINE_MAX = 2.0**33

_SKIA, _QT = 0, 1


@dataclass(frozen=True, slots=True)
class HairlineRule:
    """One fixed-point line rule read from a library's source: its name (the
    :class:`~harness.contract.conventions.LineRule` ``rule``), its source, its kernel's
    code, and whether a cell's minor pixel moves monotonically with the line (skia's
    does not: as an end point crosses a pixel centre the DDA's start jumps by a slope
    step, so the line-motion check judges it against the exact answer's own moves)."""

    name: HairlineName
    source: str
    code: int
    monotone: bool


HAIRLINE_RULES: dict[str, HairlineRule] = {
    rule.name: rule for rule in (
        HairlineRule("skia-hairline", "skia src/core/SkScan_Hairline.cpp, SkScan::HairLineRgn", _SKIA, False),
        HairlineRule("qt-cosmetic", "qtbase src/gui/painting/qcosmeticstroker.cpp, QCosmeticStroker::drawLine", _QT,
                     True),
    )
}


def to_fdot6(c: NDArray[np.float64]) -> NDArray[np.int64]:
    """``(int)(c * 64)``: 26.6 fixed point, toward zero, exact (|c| <= :data:`HAIRLINE_MAX`)."""
    return np.trunc(c * 64.0).astype(np.int64)


def hairline_x_major(a: NDArray[np.float64], b: NDArray[np.float64], rule: str) -> NDArray[np.bool_]:
    """(N,) bool: whether the rule walks each (finite) segment along x -- by its 26.6 end
    points, ``|dx| > |dy|`` for skia (a 45-degree segment is y-major), ``|dx| >= |dy|`` for
    Qt -- exactly (Python integers beyond :data:`HAIRLINE_MAX`).

    >>> a, b = np.array([[0.5, 0.5]]), np.array([[4.5, 4.5]])
    >>> hairline_x_major(a, b, "skia-hairline").tolist(), hairline_x_major(a, b, "qt-cosmetic").tolist()
    ([False], [True])
    """
    qt = HAIRLINE_RULES[rule].code == _QT
    ends = np.concatenate([a, b], axis=1)
    with np.errstate(invalid="ignore"):
        near = (np.abs(ends) <= HAIRLINE_MAX).all(axis=1)
    f = to_fdot6(np.where(near[:, None], ends, 0.0))
    dx, dy = np.abs(f[:, 2] - f[:, 0]), np.abs(f[:, 3] - f[:, 1])
    out = np.asarray(dx >= dy if qt else dx > dy, dtype=np.bool_)
    for k in np.flatnonzero(~near):
        x0, y0, x1, y1 = (math.trunc(Fraction(float(c)) * 64) if math.isfinite(c) else 0 for c in ends[k])
        out[k] = abs(x1 - x0) >= abs(y1 - y0) if qt else abs(x1 - x0) > abs(y1 - y0)
    return out


# -- the compiled kernel -------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _cdiv(a, b):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """C's integer division (toward zero); numba's // floors."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


@numba.njit(cache=True)
def _walk(code, u0, v0, u1, v1, major_size, minor_size, out_major, out_minor, n):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """One segment in (major, minor) 26.6 coordinates, u0 <= u1 already: append the visible
    pixels (major index, minor index) from ``n``; returns the new count."""
    du = u1 - u0
    dv = v1 - v0
    slope = _cdiv(dv << 16, du)
    if code == 0:
        i0 = (u0 + 32) >> 6
        i1 = (u1 + 32) >> 6
        start = (v0 << 10) + ((slope * ((32 - u0) & 63)) >> 6)
    else:
        v = (v0 << 10) - (slope >> 1)  # the begin cap: half a step back
        u0 -= 32
        u1 += 32
        i0 = (u0 + 32) >> 6
        i1 = (u1 + 32) >> 6
        rnd = 32 if slope > 0 else 0
        start = v + ((((i0 << 6) + rnd - u0) * slope) >> 6)
    lo = max(i0, 0)
    hi = min(i1, major_size)
    for i in range(lo, hi):
        row = (start + (i - i0) * slope) >> 16
        if 0 <= row < minor_size:
            out_major[n] = i
            out_minor[n] = row
            n += 1
    return n


@numba.njit(cache=True)
def _hairline_kernel(code, f, same, floor_px, width, height, out_s, out_x, out_y):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    n = 0
    for k in range(f.shape[0]):
        x0, y0, x1, y1 = f[k, 0], f[k, 1], f[k, 2], f[k, 3]
        start = n
        if code == 1 and same[k]:
            # QCosmeticStroker::drawLine: p1 == p2 draws the one pixel holding it
            if 0 <= floor_px[k, 0] < width and 0 <= floor_px[k, 1] < height:
                out_x[n] = floor_px[k, 0]
                out_y[n] = floor_px[k, 1]
                n += 1
        else:
            dx = x1 - x0
            dy = y1 - y0
            x_major = abs(dx) > abs(dy) if code == 0 else abs(dx) >= abs(dy)
            if x_major:
                if dx != 0:
                    if x0 > x1:
                        x0, y0, x1, y1 = x1, y1, x0, y0
                    n = _walk(code, x0, y0, x1, y1, width, height, out_x, out_y, n)
            elif dy != 0:
                if y0 > y1:
                    x0, y0, x1, y1 = x1, y1, x0, y0
                n = _walk(code, y0, x0, y1, x1, height, width, out_y, out_x, n)
        for m in range(start, n):
            out_s[m] = k
    return n


def _spans_of_pixels(s: NDArray[np.int64], x: NDArray[np.int64], y: NDArray[np.int64]) -> Spans:
    """Pixels (each once per segment) as spans sorted by segment, row and x0."""
    if not s.size:
        return _empty()
    order = np.lexsort((x, y, s))
    s, x, y = s[order], x[order], y[order]
    new = np.ones(s.size, dtype=np.bool_)
    new[1:] = (s[1:] != s[:-1]) | (y[1:] != y[:-1]) | (x[1:] != x[:-1] + 1)
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], s.size)
    return s[starts], y[starts], x[starts], x[ends - 1] + 1


def hairline_pixels_int(rule: str, x0: int, y0: int, x1: int, y1: int, same: bool, floor_px: tuple[int, int],
                        width: int, height: int) -> list[tuple[int, int]]:
    """The kernel's walk in Python integers, for 26.6 ends of any size: the visible pixels
    (x, y) of one segment."""
    code = HAIRLINE_RULES[rule].code
    if code == _QT and same:
        i, j = floor_px
        return [(i, j)] if 0 <= i < width and 0 <= j < height else []
    dx, dy = x1 - x0, y1 - y0
    x_major = abs(dx) > abs(dy) if code == _SKIA else abs(dx) >= abs(dy)
    if x_major:
        if dx == 0:
            return []
        if x0 > x1:
            x0, y0, x1, y1 = x1, y1, x0, y0
        u0, v0, u1, v1, size, other = x0, y0, x1, y1, width, height
    else:
        if dy == 0:
            return []
        if y0 > y1:
            x0, y0, x1, y1 = x1, y1, x0, y0
        u0, v0, u1, v1, size, other = y0, x0, y1, x1, height, width
    slope = _cdiv_int(v1 - v0 << 16, u1 - u0)
    if code == _SKIA:
        i0, i1 = (u0 + 32) >> 6, (u1 + 32) >> 6
        start = (v0 << 10) + ((slope * ((32 - u0) & 63)) >> 6)
    else:
        v = (v0 << 10) - (slope >> 1)
        u0, u1 = u0 - 32, u1 + 32
        i0, i1 = (u0 + 32) >> 6, (u1 + 32) >> 6
        start = v + ((((i0 << 6) + (32 if slope > 0 else 0) - u0) * slope) >> 6)
    out = []
    for i in range(max(i0, 0), min(i1, size)):
        row = (start + (i - i0) * slope) >> 16
        if 0 <= row < other:
            out.append((i, row) if x_major else (row, i))
    return out


def _cdiv_int(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def hairline_spans(a: ArrayLike, b: ArrayLike, width: int, height: int, rule: str) -> Spans:
    """The pixels the fixed-point line rule ``rule`` (a key of :data:`HAIRLINE_RULES`) draws
    from ``a[k]`` to ``b[k]`` (see the module docstring).

    Parameters
    ----------
    a, b : (N, 2) float64
        End points; each coordinate goes to 26.6 fixed point toward zero.
    width, height : int
        The viewport.
    rule : {"skia-hairline", "qt-cosmetic"}

    Returns
    -------
    (segment, y, x0, x1) : four (S,) int64 arrays
        Spans sorted by segment, row and x0.

    Examples
    --------
    skia leaves out the left end's pixel when the end lies right of its centre, and draws
    the right end's; Qt draws both:

    >>> s, y, x0, x1 = hairline_spans([[0.75, 0.5]], [[4.75, 2.5]], 6, 4, "skia-hairline")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 1, 2), (1, 2, 4), (2, 4, 5)]
    >>> s, y, x0, x1 = hairline_spans([[0.75, 0.5]], [[4.75, 2.5]], 6, 4, "qt-cosmetic")
    >>> [(int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1)]
    [(0, 0, 2), (1, 2, 4), (2, 4, 5)]
    """
    width, height = _viewport(width, height)
    code = HAIRLINE_RULES[rule].code
    a_arr, b_arr, finite = _endpoints(a, b)
    n = a_arr.shape[0]
    if n == 0 or width == 0 or height == 0:
        return _empty()
    ends = np.concatenate([a_arr, b_arr], axis=1)
    with np.errstate(invalid="ignore"):
        near = finite & (np.abs(ends) <= HAIRLINE_MAX).all(axis=1)
    f = to_fdot6(np.where(near[:, None], ends, 0.0))
    same = np.asarray(near & (a_arr == b_arr).all(axis=1), dtype=np.bool_)
    floor_px = np.floor(np.where(near[:, None], a_arr, 0.0)).astype(np.int64)
    # segments not drawn: zero ends (draw nothing under both rules)
    f[~near] = 0
    same[~near] = False
    cap = n * (max(width, height) + 1)
    out_s, out_x, out_y = (np.empty(cap, dtype=np.int64) for _ in range(3))
    m = _hairline_kernel(code, np.ascontiguousarray(f), same, np.ascontiguousarray(floor_px), width, height,
                         out_s, out_x, out_y)
    s, x, y = out_s[:m], out_x[:m], out_y[:m]
    far = np.flatnonzero(finite & ~near)
    if far.size:
        extra = []
        for k in far:
            x0, y0, x1, y1 = (math.trunc(Fraction(float(c)) * 64) for c in ends[k])
            floor_k = (math.floor(a_arr[k, 0]), math.floor(a_arr[k, 1]))
            same_k = bool((a_arr[k] == b_arr[k]).all())
            extra += [(int(k), i, j) for i, j in hairline_pixels_int(rule, x0, y0, x1, y1, same_k, floor_k, width, height)]
        more = np.array(extra, dtype=np.int64).reshape(-1, 3).T
        s, x, y = np.concatenate([s, more[0]]), np.concatenate([x, more[1]]), np.concatenate([y, more[2]])
    return _spans_of_pixels(s, x, y)


# -- the rational reference ---------------------------------------------------------------------


def _reference_pixel(rule: str, a: tuple[float, float], b: tuple[float, float], i: int, j: int) -> bool:
    """Whether the rule draws pixel (i, j) for the segment a -> b: the closed form, in
    Fractions and Python integers, straight from the definitions (module docstring)."""
    qt = rule == "qt-cosmetic"
    if qt and a == b:
        return (i, j) == (math.floor(Fraction(a[0])), math.floor(Fraction(a[1])))
    x0, y0, x1, y1 = (math.trunc(Fraction(c) * 64) for c in (*a, *b))
    dx, dy = x1 - x0, y1 - y0
    x_major = abs(dx) >= abs(dy) if qt else abs(dx) > abs(dy)
    if x_major and dx == 0 or not x_major and dy == 0:
        return False
    if not x_major:  # exchange the axes: the y-major walk is the x-major one transposed
        x0, y0, x1, y1, i, j = y0, x0, y1, x1, j, i
    if x0 > x1:
        x0, y0, x1, y1 = x1, y1, x0, y0
    slope = math.trunc(Fraction((y1 - y0) * 65536, x1 - x0))  # C division: toward zero
    if qt:
        first = math.floor(Fraction(x0 - 32 + 32, 64))       # the begin cap
        last = math.floor(Fraction(x1 + 32 + 32, 64))        # the end cap (exclusive)
        offset = first * 64 + (32 if slope > 0 else 0) - (x0 - 32)
        start = y0 * 1024 - math.floor(Fraction(slope, 2)) + math.floor(Fraction(offset * slope, 64))
    else:
        first = math.floor(Fraction(x0 + 32, 64))
        last = math.floor(Fraction(x1 + 32, 64))
        start = y0 * 1024 + math.floor(Fraction(slope * ((32 - x0) % 64), 64))
    if not first <= i < last:
        return False
    return math.floor(Fraction(start + (i - first) * slope, 65536)) == j


def hairline_spans_rational(a: ArrayLike, b: ArrayLike, width: int, height: int, rule: str) -> Spans:
    """The slow reference of :func:`hairline_spans`: every pixel of the viewport tested with
    the closed form of the rule (small viewports only)."""
    width, height = _viewport(width, height)
    a_arr, b_arr, finite = _endpoints(a, b)
    rows: list[tuple[int, int, int, int]] = []
    for k in range(a_arr.shape[0]):
        if not finite[k]:
            continue
        pa = (float(a_arr[k, 0]), float(a_arr[k, 1]))
        pb = (float(b_arr[k, 0]), float(b_arr[k, 1]))
        for j in range(height):
            i = 0
            while i < width:
                if _reference_pixel(rule, pa, pb, i, j):
                    e = i
                    while e < width and _reference_pixel(rule, pa, pb, e, j):
                        e += 1
                    rows.append((k, j, i, e))
                    i = e
                else:
                    i += 1
    return _as_spans(rows)
