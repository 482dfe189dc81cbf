"""Reference line rasterizers: integer Bresenham (seed 003), a fixed-point DDA under the
diamond-exit rule, and Vulkan's rectangular lines.

Each draws a :class:`~harness.contract.scenes.LineScene` exactly as its convention's
:class:`~harness.contract.conventions.LineRule` says (the definitions are in :mod:`harness.oracle.lines`),
with its own arithmetic: none calls the oracle's kernels, so a test comparing the two
compares two implementations. The primitive is the segment; a segment with a NaN or
infinite end point covers nothing; a segment with a coordinate beyond a rasterizer's
range is refused (ValueError naming it), never drawn wrong. A scene a rasterizer cannot
draw as given (another line width, another kind of scene) raises
:class:`harness.contract.scenes.Unsupported`.

``bresenham_lines`` (:class:`BresenhamLines`)
    Seed 003's integer algorithm. End points go to pixels by the declared rounding (the
    pixel whose centre is nearest, halves to even or away from zero; or ``floor``), then
    the classic decision variable ``p = 2M - K`` (K, M the major and minor pixel deltas) is
    walked one pixel per major step in the segment's octant: the minor coordinate steps
    when ``p >= 0`` (``ties="step"``) or ``p > 0`` (``"stay"``), and ``p`` grows by ``2M``,
    less ``2K`` after a minor step. Only the steps inside the viewport are walked: the
    walk starts at the first such step k with the variable it would have there,
    ``p_k = 2M(k + 1) - K - 2K*offset_k``. Width 1. Range: end points within +-2**30 px
    (every ``k*M`` then fits int64).

``diamond_exit_dda`` (:class:`DiamondExitDDA`)
    End points snapped to 1/256 px (8 sub-pixel bits, D3D's 16.8), so every quantity is an
    integer in units of 1/256 px (x-major when ``|dx| >= |dy|`` on those integers; a
    zero-length segment counts as x-major). The diamond test area D of a pixel is
    ``-u - v < 128, u - v < 128, u + v <= 128, v - u <= 128`` around its centre (u, v the
    offsets), plus the right corner ``(128, 0)`` for y-major lines (D3D11 3.4.3). A line
    with |slope| <= 1 meets at most one D per column -- the one whose row holds its height
    at the column centre, ``256j < y(xc) <= 256j + 256`` -- and a y-major line one per row
    (:mod:`harness.oracle.lines` proves it), so the DDA walks the major axis one cell at a time
    and carries that height as an exact quotient and remainder (``N = Q*256*du + R``,
    stepped by the constant ``divmod(256*dv, 256*du)``): the candidate cell is
    ``ceil(N / (256*du)) - 1`` with no division in the loop. The segment meets the
    candidate's D when the column centre lies between its end points' x (the diagonal
    point is on it), else exactly when its nearer end point lies in D; the pixel is drawn
    unless the end point b lies in D (the exit rule; ``last_pixel=True`` draws it too).
    Overflow bound: fixed-point coordinates within +-2**30 (+-2**22 px, 4,194,304) keep
    ``rv*du + (uc - ru)*dv`` below 2.3 * 2**61 < 2**63. Width 1.

``rectangle_lines`` (:class:`RectangleLines`)
    Vulkan's rectangular lines: the sample (pixel centre) lies in the ``line_width``-wide
    rectangle around the segment (no caps beyond the end points), ties by the tie rule's
    symbolic perturbation (top-left by default), end points snapped to 8 bits. With
    d = b - a and c = cross(d, p - a) in units of 1/256 px, the caps are the integer
    tests ``dot(d, p - a) > 0`` and ``dot(-d, p - b) > 0``, solved per row for the first
    and last column by floor division (a tie owned by the rule is a bias of 0, else -1,
    as in :mod:`rasterizers.fixed_point`), and the sides are ``4c**2 < W**2 |d|**2`` with
    W = 256 w: c and |d|**2 are exact int64 integers (below 2**62), W a float; each side is
    decided by a float filter and, near a tie, an exact sum of error-free products
    (:func:`harness.geometry.exact._two_product`) of c and |d|**2 split into two floats each. The
    sides' columns on a row start from a float estimate (a square root) that the exact
    test then corrects a column at a time: no square root decides anything. Range:
    coordinates within +-2**21 px (2,097,152), any line width: ``|c|``, the caps' dot
    products and ``|d|**2`` then stay below 2**62 at every sample of the largest viewport
    (2**20 px).

Conventions: ``bresenham_lines`` -- ``LineRule("bresenham")`` (nearest-even end points,
ties step, both end points drawn), no snapping; ``diamond_exit_dda`` -- ``LineRule()``
(diamond exit, last pixel omitted), snapped to 8 bits; ``rectangle_lines`` --
``LineRule("rectangle")``, sample (0.5, 0.5), top-left ties, snapped to 8 bits.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import (
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    TIE_RULES,
    BresenhamRounding,
    BresenhamTies,
    Convention,
    LineRule,
    TieRule,
)
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, Unsupported
from harness.geometry.exact import _two_product, frozen
from harness.geometry.spans import span_buffers
from harness.oracle.line_spans import emit_pixel
from harness.oracle.rectangle_lines import expansion_sign, grow_expansion

__all__ = ["BresenhamLines", "DiamondExitDDA", "RectangleLines", "BRESENHAM_LIMIT", "DDA_LIMIT", "RECTANGLE_LIMIT"]

# Bresenham: end points within +-2**30 px, so K, M <= 2**31 and k*M <= 2**62 fits int64.
BRESENHAM_LIMIT = 2.0**30
# DDA: 8 sub-pixel bits; |fixed| <= 2**30 keeps rv*du + (uc - ru)*dv below 2.3 * 2**61.
SUBPIXEL_BITS = 8
SUBPIXEL_ONE = 1 << SUBPIXEL_BITS
SUBPIXEL_HALF = SUBPIXEL_ONE // 2
DDA_LIMIT = 2.0**22
# Rectangles: |x|, |y| <= 2**21 px (2**29 fixed) and samples within MAX_VIEWPORT = 2**20 px
# (2**28 fixed) keep |d| components <= 2**30 and |p - a| components < 2**29.6, so every
# cross and dot product at a sample is below 2**60.6, 2|c| < 2**61.6 and |d|**2 <= 2**61.
RECTANGLE_LIMIT = 2.0**21
# Below W = 2**-31, W**2 |d|**2 < 2**-62 * 2**61 < 4 <= 4c**2 whenever c != 0.
_TINY_W = 2.0**-31
# Float filter margin for 4c**2 against W**2 |d|**2: each side errs by at most 4 roundings.
_FILTER = 2.0**-48

_ROUNDING_CODES = {"floor": 0, "nearest-even": 1, "half-away": 2, "toward-zero": 3}


# -- shared pieces -----------------------------------------------------------------------------


def _line_scene(scene: AnyScene, rasterizer: str) -> LineScene:
    if not isinstance(scene, LineScene):
        raise Unsupported(f"{rasterizer} draws line scenes only, not {scene.kind}")
    return scene


def _segments(scene: LineScene, limit: float, rasterizer: str, why: str) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                                                    NDArray[np.bool_]]:
    """The segments' end points (N, 2) each, and which segments are finite; ValueError
    naming the first finite segment with a coordinate beyond +-limit px."""
    a, b = scene.segments()
    ends = np.concatenate([a, b], axis=1)
    finite = np.isfinite(ends).all(axis=1)
    beyond = finite & (np.abs(np.where(finite[:, None], ends, 0.0)) > limit).any(axis=1)
    if beyond.any():
        k = int(np.flatnonzero(beyond)[0])
        raise ValueError(f"{rasterizer}: segment {k} has a coordinate beyond +/-{limit:g} px "
                         f"({a[k].tolist()} -> {b[k].tolist()}); {why}")
    return a, b, frozen(finite, np.bool_)


def _fixed(points: NDArray[np.float64], convention: Convention, finite: NDArray[np.bool_]) -> NDArray[np.int64]:
    """(N, 2) int64: snapped end points in units of 1/256 px (exact: snapped values lie
    on the grid and within range); non-finite segments become 0."""
    snapped = convention.snap(np.where(finite[:, None], points, 0.0))
    return frozen(snapped * float(SUBPIXEL_ONE), np.int64)


@numba.njit(cache=True, inline="always")
def _reverse(first, n, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Reverse spans first..n-1 (one segment's, all of it): a walk up the screen wrote its
    rows descending."""
    lo = first
    hi = n - 1
    while lo < hi:
        out_y[lo], out_y[hi] = out_y[hi], out_y[lo]
        out_x0[lo], out_x0[hi] = out_x0[hi], out_x0[lo]
        out_x1[lo], out_x1[hi] = out_x1[hi], out_x1[lo]
        lo += 1
        hi -= 1


def _coverage(spans: tuple[NDArray[np.int64], ...], n: int) -> Coverage:
    s, y, x0, x1 = (a[:n] for a in spans)
    return Coverage(s, y, x0, x1)


def _suffixed(base: str, parts: list[str]) -> str:
    return "_".join([base, *parts]) if parts else base


# -- Bresenham -----------------------------------------------------------------------------------


@numba.njit(cache=True)
def _pixel_of(v, rounding):  # type: ignore[no-untyped-def]
    """The pixel index of coordinate v: floor(v) (``floor``, 0), else the pixel whose
    centre i + 1/2 is nearest to v. That is floor(v) too, except when v is an integer:
    then pixels v - 1 and v are equally near, and the tie goes to the even one (1) or the
    one away from zero, i.e. v when v - 1/2 > 0 (2); or trunc(v) (``toward-zero``, 3)."""
    if rounding == 3:  # toward zero: C's (int) cast
        return int(math.trunc(v))
    f = math.floor(v)
    i = int(f)
    if rounding == 0 or v != f:
        return i
    if rounding == 1:
        return i if i % 2 == 0 else i - 1
    return i if i >= 1 else i - 1


@numba.njit(cache=True)
def _bresenham_pixels(a, b, keep, rounding, p0, p1):  # type: ignore[no-untyped-def]
    for s in range(a.shape[0]):
        if keep[s]:
            for c in range(2):
                p0[s, c] = _pixel_of(a[s, c], rounding)
                p1[s, c] = _pixel_of(b[s, c], rounding)


@numba.njit(cache=True)
def _bresenham_kernel(p0, p1, keep, step_ties, last_pixel, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Walk every segment's decision variable through the viewport; spans per segment with
    rows ascending. Returns the span count."""
    n = 0
    for s in range(p0.shape[0]):
        if not keep[s]:
            continue
        dx = p1[s, 0] - p0[s, 0]
        dy = p1[s, 1] - p0[s, 1]
        # The octant: u the major axis (x when |dx| >= |dy|), v the minor; su, sv the steps.
        x_major = abs(dx) >= abs(dy)
        if x_major:
            u0, v0, du, dv, extent = p0[s, 0], p0[s, 1], dx, dy, width
        else:
            u0, v0, du, dv, extent = p0[s, 1], p0[s, 0], dy, dx, height
        su = 1 if du >= 0 else -1
        sv = 1 if dv >= 0 else -1
        big_k = abs(du)
        big_m = abs(dv)
        last = big_k if last_pixel else big_k - 1
        if last < 0:
            continue
        # only the steps k in [0, last] whose major coordinate u0 + su*k lies in the viewport
        if su > 0:
            k_lo, k_hi = max(0, -u0), min(last, extent - 1 - u0)
        else:
            k_lo, k_hi = max(0, u0 - (extent - 1)), min(last, u0)
        if k_lo > k_hi:
            continue
        # The decision variable before step k is p_k = 2M(k + 1) - K - 2K*offset_k; at k = 0
        # the classic 2M - K. Starting later (the segment begins off screen), offset_k is
        # k*M/K rounded as the walk rounds it -- halves up when ties step, down when they
        # stay -- and p_k follows from the remainder r of k*M = q*K + r.
        offset = 0
        p = 2 * big_m - big_k
        if k_lo > 0:
            q, r = divmod(k_lo * big_m, big_k)
            carry = 1 if (2 * r > big_k or (step_ties and 2 * r == big_k)) else 0
            offset = q + carry
            p = 2 * r + 2 * big_m - big_k - 2 * big_k * carry
        u = u0 + su * k_lo
        v = v0 + sv * offset
        first = n
        for _ in range(k_hi - k_lo + 1):
            x, y = (u, v) if x_major else (v, u)
            if 0 <= x < width and 0 <= y < height:
                n = emit_pixel(s, y, x, out_s, out_y, out_x0, out_x1, n, first)
            # seed 003's test: p >= 0 steps the minor coordinate (a tie, p = 0, steps
            # towards the end point); "stay" keeps it on a tie
            if p > 0 or (step_ties and p == 0):
                v += sv
                p -= 2 * big_k
            p += 2 * big_m
            u += su
        if (sv < 0) if x_major else (su < 0):
            _reverse(first, n, out_y, out_x0, out_x1)
    return n


class BresenhamLines:
    """Seed 003's integer Bresenham: end points to pixels, one pixel per major step.

    Parameters
    ----------
    rounding : {"nearest-even", "half-away", "floor", "toward-zero"}
        How an end point picks its pixel (:class:`harness.contract.conventions.LineRule`).
    ties : {"step", "stay"}
        The minor coordinate when the decision variable is 0.
    last_pixel : bool
        Draw the end point's pixel (seed 003: yes) or stop one step short.

    Examples
    --------
    >>> scene = LineScene.from_segments(6, 4, [[0.5, 0.5]], [[4.5, 2.5]])
    >>> BresenhamLines().rasterize(scene).counts(6, 4)
    array([[1, 0, 0, 0, 0, 0],
           [0, 1, 1, 0, 0, 0],
           [0, 0, 0, 1, 1, 0],
           [0, 0, 0, 0, 0, 0]], dtype=int32)
    >>> BresenhamLines(ties="stay", last_pixel=False).rasterize(scene).counts(6, 4)[2]
    array([0, 0, 0, 0, 0, 0], dtype=int32)
    """

    name = "bresenham_lines"
    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, rounding: BresenhamRounding = "nearest-even", ties: BresenhamTies = "step", last_pixel: bool = True) -> None:
        if rounding not in BRESENHAM_ROUNDINGS:
            raise ValueError(f"bresenham_lines: rounding must be one of {', '.join(BRESENHAM_ROUNDINGS)}, not {rounding!r}")
        if ties not in BRESENHAM_TIES:
            raise ValueError(f"bresenham_lines: ties must be one of {', '.join(BRESENHAM_TIES)}, not {ties!r}")
        self.rounding = rounding
        self.ties = ties
        self.last_pixel = bool(last_pixel)
        self.convention = Convention(line=LineRule("bresenham", last_pixel=self.last_pixel, rounding=rounding, ties=ties))
        parts: list[str] = [rounding] if rounding != "nearest-even" else []
        parts += [ties] if ties != "step" else []
        parts += [] if self.last_pixel else ["no_last"]
        self.name = _suffixed("bresenham_lines", parts)

    def rasterize(self, scene: AnyScene) -> Coverage:
        lines = _line_scene(scene, self.name)
        if lines.line_width != 1.0:
            raise Unsupported(f"{self.name} draws lines of width 1 only, not {lines.line_width:g}")
        a, b, keep = _segments(lines, BRESENHAM_LIMIT, self.name, "end points beyond +-2**30 px would overflow int64")
        n = a.shape[0]
        p0 = np.zeros((n, 2), dtype=np.int64)
        p1 = np.zeros((n, 2), dtype=np.int64)
        _bresenham_pixels(frozen(a), frozen(b), keep, _ROUNDING_CODES[self.rounding], p0, p1)
        p0, p1 = frozen(p0, np.int64), frozen(p1, np.int64)
        # one pixel per major step, at most the viewport's extent along the major axis
        delta = np.abs(p1 - p0)
        x_major = delta[:, 0] >= delta[:, 1]
        steps = np.minimum(delta.max(axis=1) + 1, np.where(x_major, lines.width, lines.height))
        spans = span_buffers(int(np.where(keep, steps, 0).sum()))
        count = _bresenham_kernel(p0, p1, keep, self.ties == "step", self.last_pixel, lines.width, lines.height, *spans)
        return _coverage(spans, count)


# -- diamond exit, fixed-point DDA -------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _in_test_area(px, py, i, j, y_major):  # type: ignore[no-untyped-def]
    """Whether fixed-point p lies in the diamond test area of pixel (i, j)."""
    u = px - (i * SUBPIXEL_ONE + SUBPIXEL_HALF)
    v = py - (j * SUBPIXEL_ONE + SUBPIXEL_HALF)
    # y-major lines own the right corner too (D3D11 3.4.3)
    if y_major and u == SUBPIXEL_HALF and v == 0:
        return True
    # y down: upper-left and upper-right edges (and the top, left and right corners) are
    # out -- strict; lower edges and the bottom corner are in
    return -u - v < SUBPIXEL_HALF and u - v < SUBPIXEL_HALF and u + v <= SUBPIXEL_HALF and v - u <= SUBPIXEL_HALF


@numba.njit(cache=True)
def _dda_kernel(a, b, keep, last_pixel, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """The diamond-exit pixels of every segment (fixed point, 1/256 px), spans per segment
    with rows ascending. Returns the span count."""
    n = 0
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        first = n
        if ax == bx and ay == by:
            # No length, no exit; drawn with the last pixel: the pixel whose test area
            # (x-major) holds the point -- (i, j) with 256i < x < 256i + 256, 256j < y <= 256j + 256.
            if last_pixel and ax % SUBPIXEL_ONE != 0:
                i = ax // SUBPIXEL_ONE
                j = -((-ay) // SUBPIXEL_ONE) - 1
                if 0 <= i < width and 0 <= j < height and _in_test_area(ax, ay, i, j, np.bool_(False)):
                    n = emit_pixel(s, j, i, out_s, out_y, out_x0, out_x1, n, first)
            continue
        x_major = abs(bx - ax) >= abs(by - ay)
        y_major = not x_major
        # u the major axis, v the minor; r before q along u
        if x_major:
            if ax <= bx:
                ru, rv, qu, qv = ax, ay, bx, by
            else:
                ru, rv, qu, qv = bx, by, ax, ay
            extent, across = width, height
        else:
            if ay <= by:
                ru, rv, qu, qv = ay, ax, by, bx
            else:
                ru, rv, qu, qv = by, bx, ay, ax
            extent, across = height, width
        du = qu - ru  # > 0
        dv = qv - rv
        # Major cells whose test areas may meet [ru, qu]: D spans 256c < u < 256c + 256
        # (x-major; its left and right corners are out) or 256c < u <= 256c + 256 (y-major,
        # the bottom corner in), so c runs from floor(ru/256) (x-major) or ceil(ru/256) - 1
        # to ceil(qu/256) - 1.
        c_lo = ru // SUBPIXEL_ONE if x_major else -((-ru) // SUBPIXEL_ONE) - 1
        c_hi = -((-qu) // SUBPIXEL_ONE) - 1
        c_lo = max(c_lo, 0)
        c_hi = min(c_hi, extent - 1)
        if c_lo > c_hi:
            continue
        # The line's minor coordinate at the cell centre uc is N / du with
        # N = rv*du + (uc - ru)*dv; the candidate minor cell m satisfies
        # 256m < N/du <= 256m + 256, i.e. m = ceil(N / (256 du)) - 1. Carry N as
        # Q * (256 du) + R, 0 <= R < 256 du, stepped per cell by divmod(256 dv, 256 du).
        denominator = SUBPIXEL_ONE * du
        uc = c_lo * SUBPIXEL_ONE + SUBPIXEL_HALF
        big_q, big_r = divmod(rv * du + (uc - ru) * dv, denominator)
        step_q, step_r = divmod(SUBPIXEL_ONE * dv, denominator)
        for c in range(c_lo, c_hi + 1):
            m = big_q - 1 if big_r == 0 else big_q
            if 0 <= m < across:
                i, j = (c, m) if x_major else (m, c)
                px, py = (ru, rv) if x_major else (rv, ru)
                qx, qy = (qu, qv) if x_major else (qv, qu)
                # The line meets this D in an interval around the diagonal point at uc: the
                # segment reaches it when uc lies between its ends, else through the nearer end.
                if uc < ru:
                    meets = _in_test_area(px, py, i, j, y_major)
                elif uc > qu:
                    meets = _in_test_area(qx, qy, i, j, y_major)
                else:
                    meets = True
                # the exit rule: a pixel whose test area holds the end point b is not left
                if meets and (last_pixel or not _in_test_area(bx, by, i, j, y_major)):
                    n = emit_pixel(s, j, i, out_s, out_y, out_x0, out_x1, n, first)
            uc += SUBPIXEL_ONE
            big_q += step_q
            big_r += step_r
            if big_r >= denominator:
                big_r -= denominator
                big_q += 1
        if x_major and dv < 0:
            _reverse(first, n, out_y, out_x0, out_x1)
    return n


class DiamondExitDDA:
    """A sub-pixel DDA under the diamond-exit rule, in 24.8 fixed point.

    Parameters
    ----------
    last_pixel : bool
        False (the rule): a pixel whose test area holds the end point is not drawn, so a
        polyline's shared vertex is drawn once. True: that pixel is drawn too.

    Examples
    --------
    From pixel centre to pixel centre: the start pixel is drawn, the end pixel is not.

    >>> scene = LineScene.from_strips(6, 4, [[[0.5, 0.5], [4.5, 2.5], [0.5, 3.5]]])
    >>> DiamondExitDDA().rasterize(scene).counts(6, 4)
    array([[1, 1, 0, 0, 0, 0],
           [0, 0, 1, 1, 0, 0],
           [0, 0, 1, 1, 1, 0],
           [0, 1, 0, 0, 0, 0]], dtype=int32)
    """

    name = "diamond_exit_dda"
    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, last_pixel: bool = False) -> None:
        self.last_pixel = bool(last_pixel)
        self.convention = Convention(subpixel_bits=SUBPIXEL_BITS, line=LineRule("diamond-exit", last_pixel=self.last_pixel))
        self.name = _suffixed("diamond_exit_dda", ["last_pixel"] if self.last_pixel else [])

    def rasterize(self, scene: AnyScene) -> Coverage:
        lines = _line_scene(scene, self.name)
        if lines.line_width != 1.0:
            raise Unsupported(f"{self.name} draws lines of width 1 only, not {lines.line_width:g}")
        a, b, keep = _segments(lines, DDA_LIMIT, self.name,
                               "24.8 fixed point keeps the DDA's int64 products exact only within +/-2**22 px")
        fa, fb = _fixed(a, self.convention, keep), _fixed(b, self.convention, keep)
        # one pixel per major cell at most, plus the cell before the first
        delta = np.abs(fb - fa)
        x_major = delta[:, 0] >= delta[:, 1]
        cells = np.minimum(delta.max(axis=1) // SUBPIXEL_ONE + 2, np.where(x_major, lines.width, lines.height))
        spans = span_buffers(int(np.where(keep, cells, 0).sum()))
        count = _dda_kernel(fa, fb, keep, self.last_pixel, lines.width, lines.height, *spans)
        return _coverage(spans, count)


# -- rectangles -------------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _sign(v):  # type: ignore[no-untyped-def]
    return 1 if v > 0 else (-1 if v < 0 else 0)


@numba.njit(cache=True, inline="always")
def _owned(gx, gy, tx, ty, y_first):  # type: ignore[no-untyped-def]
    """Whether a sample exactly on a boundary is inside, the inside function there having
    gradient signs (gx, gy): the sign of that gradient along the tie rule's perturbation
    (tx*eps, ty*eps**2) -- or (tx*eps**2, ty*eps) y-first."""
    if y_first:
        return gy * ty > 0 if gy != 0 else gx * tx > 0
    return gx * tx > 0 if gx != 0 else gy * ty > 0


@numba.njit(cache=True, inline="always")
def _split_int(v):  # type: ignore[no-untyped-def]
    """An int64 v (|v| < 2**63) as floats hi + lo exactly: hi = float(v), lo = v - hi
    (|lo| <= 2**9)."""
    hi = float(v)
    return hi, float(v - np.int64(hi))


@numba.njit(cache=True)
def _sides_sign(q, big_s, w2_hi, w2_lo, scratch):  # type: ignore[no-untyped-def]
    """Exact sign of W**2 * S - q**2 (q, S int64 below 2**62, W**2 = w2_hi + w2_lo
    exactly): a float filter, then the seven error-free products of the split factors
    summed as a nonoverlapping expansion (its largest component carries the sign)."""
    q_hi, q_lo = _split_int(q)
    s_hi, s_lo = _split_int(big_s)
    lhs = w2_hi * s_hi
    rhs = q_hi * q_hi
    if lhs * (1.0 - _FILTER) > rhs * (1.0 + _FILTER):
        return 1
    if rhs * (1.0 - _FILTER) > lhs * (1.0 + _FILTER):
        return -1
    # W**2 S - q**2 = (w2_hi + w2_lo)(s_hi + s_lo) - (q_hi**2 + 2 q_hi q_lo + q_lo**2)
    scratch[0], scratch[1] = _two_product(w2_hi, s_hi)
    scratch[2], scratch[3] = _two_product(w2_hi, s_lo)
    scratch[4], scratch[5] = _two_product(w2_lo, s_hi)
    scratch[6], scratch[7] = _two_product(w2_lo, s_lo)
    scratch[8], scratch[9] = _two_product(-q_hi, q_hi)
    scratch[10], scratch[11] = _two_product(-2.0 * q_hi, q_lo)
    scratch[12], scratch[13] = _two_product(-q_lo, q_lo)
    length = np.int64(0)  # np.int64, not the literal 0: numba compiles a callee once per literal argument
    h = scratch[14:]
    for t in range(14):
        length = grow_expansion(h, length, scratch[t])
    return expansion_sign(h, length)


@numba.njit(cache=True)
def _between_sides(c, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty, y_first, scratch):  # type: ignore[no-untyped-def]
    """Whether a sample with cross product c = cross(d, p - a) lies between the long sides,
    4c**2 < W**2 |d|**2, a sample on a side decided by the tie rule."""
    if c == 0:
        return True  # on the segment's line: W > 0 and |d| > 0
    if w_fixed < _TINY_W:
        return False  # W**2 |d|**2 < 4 <= 4c**2
    sign = _sides_sign(2 * abs(c), big_s, w2_hi, w2_lo, scratch)
    if sign != 0:
        return sign > 0
    # on a side: c = h, inside function h - c (gradient (dy, -dx)); or c = -h, c + h (-dy, dx)
    if c > 0:
        return _owned(_sign(dy), -_sign(dx), tx, ty, y_first)
    return _owned(-_sign(dy), _sign(dx), tx, ty, y_first)


@numba.njit(cache=True, inline="always")
def _cap_columns(gx, gy, ex, ey, ys, bias, lo, hi):  # type: ignore[no-untyped-def]
    """Narrow columns [lo, hi] to those whose sample satisfies the cap
    f(i) = gx*(256 i + 128 - ex) + gy*(ys - ey) >= -bias, i.e. f > 0, or f = 0 owned
    (bias 0) -- for integers, f > 0 and f - 1 >= 0 are the same test (bias -1)."""
    k = gx * (SUBPIXEL_HALF - ex) + gy * (ys - ey) + bias  # f(i) + bias = 256*gx*i + k
    if gx > 0:
        lo = max(lo, -(k // (SUBPIXEL_ONE * gx)))
    elif gx < 0:
        hi = min(hi, k // (-SUBPIXEL_ONE * gx))
    elif k < 0:
        hi = lo - 1
    return lo, hi


@numba.njit(cache=True)
def _rect_bounds(u0, u1, half_w, size):  # type: ignore[no-untyped-def]
    """Pixel indices (clamped to [0, size - 1]) whose sample coordinate 256k + 128 may lie
    within half_w of [min, max] of the fixed coordinates u0, u1 (the rectangle's extent
    along that axis); one to spare either side."""
    lo = (min(u0, u1) - half_w - SUBPIXEL_HALF) / SUBPIXEL_ONE
    hi = (max(u0, u1) + half_w - SUBPIXEL_HALF) / SUBPIXEL_ONE
    first = max(int(math.floor(lo)) - 1, 0)
    last = min(int(math.ceil(hi)) + 1, size - 1)
    return first, last


@numba.njit(cache=True)
def _rect_capacity(a, b, keep, w_fixed, height):  # type: ignore[no-untyped-def]
    total = 0
    for s in range(a.shape[0]):
        if keep[s]:
            first, last = _rect_bounds(a[s, 1], b[s, 1], 0.5 * w_fixed, height)
            total += max(last - first + 1, 0)
    return total


@numba.njit(cache=True)
def _rect_kernel(a, b, keep, w_fixed, tx, ty, y_first, width, height, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Every segment's rectangle, one span per row (fixed point, 1/256 px). Returns the
    span count."""
    n = 0
    w2_hi, w2_lo = _two_product(w_fixed, w_fixed)  # W**2 exactly (W >= 2**-31: no underflow)
    scratch = np.empty(14 + 14)
    half_w = 0.5 * w_fixed
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        dx = bx - ax
        dy = by - ay
        if dx == 0 and dy == 0:
            continue  # no length, no rectangle
        big_s = dx * dx + dy * dy  # |d|**2 <= 2**61: exact in int64
        # the caps' inside functions have gradients d (at a) and -d (at b)
        bias_a = 0 if _owned(_sign(dx), _sign(dy), tx, ty, y_first) else -1
        bias_b = 0 if _owned(-_sign(dx), -_sign(dy), tx, ty, y_first) else -1
        row_first, row_last = _rect_bounds(ay, by, half_w, height)
        col_first, col_last = _rect_bounds(ax, bx, half_w, width)
        if col_first > col_last:
            continue
        # float estimates of where a row crosses the sides (exactly corrected below)
        half_span = w_fixed * math.sqrt(float(big_s)) / (2.0 * SUBPIXEL_ONE * abs(dy)) if dy != 0 else 0.0
        for j in range(row_first, row_last + 1):
            ys = j * SUBPIXEL_ONE + SUBPIXEL_HALF
            lo, hi = _cap_columns(dx, dy, ax, ay, ys, bias_a, col_first, col_last)
            lo, hi = _cap_columns(-dx, -dy, bx, by, ys, bias_b, lo, hi)
            if lo > hi:
                continue
            # c(i) = cross(d, p - a) = c0 - 256*dy*i at column i
            c0 = dx * (ys - ay) - dy * (SUBPIXEL_HALF - ax)
            step = SUBPIXEL_ONE * dy
            if dy == 0:
                if not _between_sides(c0, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty, y_first, scratch):
                    continue
            else:
                # c vanishes at x0 = c0 / (256 dy); the inside columns are an interval around
                # it, so the columns of [lo, hi] nearest to x0 are inside when any is
                zero = c0 // step
                near = min(max(zero, lo), hi)
                after = min(max(zero + 1, lo), hi)
                if _between_sides(c0 - step * near, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty, y_first, scratch):
                    inside = near
                elif _between_sides(c0 - step * after, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty, y_first, scratch):
                    inside = after
                else:
                    continue
                centre = c0 / step
                left = int(math.ceil(min(max(centre - half_span, float(lo)), float(inside))))
                while left < inside and not _between_sides(c0 - step * left, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty,
                                                            y_first, scratch):
                    left += 1
                while left > lo and _between_sides(c0 - step * (left - 1), dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty,
                                                   y_first, scratch):
                    left -= 1
                right = int(math.floor(max(min(centre + half_span, float(hi)), float(inside))))
                while right > inside and not _between_sides(c0 - step * right, dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty,
                                                             y_first, scratch):
                    right -= 1
                while right < hi and _between_sides(c0 - step * (right + 1), dx, dy, big_s, w_fixed, w2_hi, w2_lo, tx, ty,
                                                    y_first, scratch):
                    right += 1
                lo, hi = left, right
            out_s[n] = s
            out_y[n] = j
            out_x0[n] = lo
            out_x1[n] = hi + 1
            n += 1
    return n


class RectangleLines:
    """Vulkan's rectangular lines (``strictLines``): the samples inside the
    ``line_width``-wide rectangle around each segment, in 24.8 fixed point.

    Parameters
    ----------
    tie : str
        The tie rule for samples on the rectangle's boundary (:data:`harness.contract.conventions.TIE_RULES`,
        top-left by default, as Vulkan's triangles).

    Examples
    --------
    A horizontal segment of width 1 along y = 1: row 0's samples lie on its upper side
    and row 1's on its lower side; top-left ties keep the upper side and the left cap.

    >>> RectangleLines().rasterize(LineScene.from_segments(5, 3, [[0.5, 1.0]], [[3.5, 1.0]])).counts(5, 3)
    array([[1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]], dtype=int32)
    """

    name = "rectangle_lines"
    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, tie: TieRule = "top-left") -> None:
        if tie not in TIE_RULES:
            raise ValueError(f"rectangle_lines: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        self.convention = Convention(tie=tie, subpixel_bits=SUBPIXEL_BITS, line=LineRule("rectangle"))
        self.name = _suffixed("rectangle_lines", [tie] if tie != "top-left" else [])

    def rasterize(self, scene: AnyScene) -> Coverage:
        lines = _line_scene(scene, self.name)
        a, b, keep = _segments(lines, RECTANGLE_LIMIT, self.name,
                               "exact squared distances in 24.8 fixed point need coordinates within +/-2**21 px")
        fa, fb = _fixed(a, self.convention, keep), _fixed(b, self.convention, keep)
        w_fixed = lines.line_width * SUBPIXEL_ONE
        capacity = int(_rect_capacity(fa, fb, keep, w_fixed, lines.height))
        spans = span_buffers(capacity)
        tx, ty, y_first = self.convention.tie_perturbation
        count = _rect_kernel(fa, fb, keep, w_fixed, tx, ty, y_first, lines.width, lines.height, *spans)
        return _coverage(spans, count)
