"""The compiled pieces the triangle oracle (:mod:`harness.oracle.coverage`) and the path oracle
(:mod:`harness.oracle.winding`) share: where an edge's exact crossing column lies on a sample row
(a float estimate with a rigorous error bound, settled by the exact predicate where a
column boundary lies within it), and counting per pixel the samples a set of sample layers
covers (supersampled area coverage)."""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.coverage import Coverage
from harness.geometry.exact import frozen, orient2d_sign
from harness.geometry.spans import span_buffers

__all__ = ["shares_of_layers", "interpolate_at"]


@numba.njit(cache=True, inline="always")
def interpolate_at(p, values, inv_w, t, perspective, xs, ys, out, row):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """Barycentric interpolation of triangle ``t`` (vertices ``p``) at the sample (xs, ys)
    into ``out[row]``: l_i = E_i / (E_0 + E_1 + E_2), each E_i weighted by 1/w_i when
    ``perspective`` (the single-sample and the multisample oracle's one arithmetic)."""
    e0 = (p[2, 0] - p[1, 0]) * (ys - p[1, 1]) - (p[2, 1] - p[1, 1]) * (xs - p[1, 0])
    e1 = (p[0, 0] - p[2, 0]) * (ys - p[2, 1]) - (p[0, 1] - p[2, 1]) * (xs - p[2, 0])
    e2 = (p[1, 0] - p[0, 0]) * (ys - p[0, 1]) - (p[1, 1] - p[0, 1]) * (xs - p[0, 0])
    if perspective:
        e0 *= inv_w[t, 0]
        e1 *= inv_w[t, 1]
        e2 *= inv_w[t, 2]
    total = e0 + e1 + e2
    for k in range(values.shape[2]):
        out[row, k] = (e0 * values[t, 0, k] + e1 * values[t, 1, k] + e2 * values[t, 2, k]) / total


@numba.njit(cache=True, inline="always")
def _inside(ax, ay, bx, by, px, py, owned):  # type: ignore[no-untyped-def]
    s = orient2d_sign(ax, ay, bx, by, px, py)
    # A sample exactly on the edge belongs to it only when the tie rule owns the edge.
    return s > 0 or (s == 0 and owned)


@numba.njit(cache=True)
def _settle(ax, ay, bx, by, owned, sx, ys, width, estimate, lower):  # type: ignore[no-untyped-def]
    """Smallest column i in [0, width] where g(i) holds, g monotone false -> true, with
    g(i) = inside(i) for a lower bound (dy < 0) and not inside(i) for an upper bound;
    g(width) is taken as true. Starts from the float estimate, then steps or bisects."""
    c = min(max(estimate, 0), width)
    if c < width and (_inside(ax, ay, bx, by, c + sx, ys, owned) != lower):
        # g(c) is false: the answer lies right of c.
        c += 1
        if c >= width or (_inside(ax, ay, bx, by, c + sx, ys, owned) == lower):
            return c
        lo, hi = c, width
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _inside(ax, ay, bx, by, mid + sx, ys, owned) == lower:
                hi = mid
            else:
                lo = mid
        return hi
    # g(c) is true (or c == width): the answer is c or lies left of it.
    if c == 0 or (_inside(ax, ay, bx, by, c - 1 + sx, ys, owned) != lower):
        return c
    c -= 1
    if c == 0 or (_inside(ax, ay, bx, by, c - 1 + sx, ys, owned) != lower):
        return c
    lo, hi = -1, c - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _inside(ax, ay, bx, by, mid + sx, ys, owned) == lower:
            hi = mid
        else:
            lo = mid
    return hi


@numba.njit(cache=True, inline="always")
def _estimate_column(ax, ay, bx, by, sx, ys, width):  # type: ignore[no-untyped-def]
    xc = ax + (bx - ax) * ((ys - ay) / (by - ay))
    e = xc - sx
    if not e > -1.0:  # also catches NaN
        return 0
    if e > width:
        return width
    return int(math.ceil(e))


@numba.njit(cache=True)
def _row_range(ymin, ymax, sy, height):  # type: ignore[no-untyped-def]
    # Rows j with ymin <= j + sy <= ymax. ceil(fl(ymin - sy)) <= ceil(ymin - sy) and
    # floor(fl(ymax - sy)) >= floor(ymax - sy): rounding is monotone and integers are
    # representable, so no row is lost; a rare extra one is skipped by the caller.
    lo = ymin - sy
    hi = ymax - sy
    if hi < 0.0 or lo > height - 1:
        return 0, -1
    first = 0 if lo < 0.0 else int(math.ceil(lo))
    last = height - 1 if hi > height - 1 else int(math.floor(hi))
    return first, last


# Bound on |fl(ax + fl(slope * fl(ys - ay))) - exact crossing|, with the roundings of the
# filter's own interval ends: about 9 roundings of relative size 2**-53 each on
# |ax| + |slope * (ys - ay)| + |sx|; 2**-48 (32 units) leaves room to spare, and the "+ 1"
# in the scale keeps the bound above any underflow. It is taken over a triangle's rows
# once, with the largest |ys - ay| among them.
_CROSSING_ERROR = 2.0**-48


@numba.njit(cache=True, inline="always")
def _bound(ax, ay, bx, by, slope, delta, owned, sx, ys, width, lower):  # type: ignore[no-untyped-def]
    """The column where edge a-b's test flips on row ys, clamped to [0, width]: the first
    inside column for a lower bound, the first outside one for an upper bound.

    Fast path: the float crossing with its error bound ``delta`` (:func:`_filtered_bound`).
    Otherwise the exact predicate settles it."""
    column = _filtered_bound(ax, ay, slope, delta, sx, ys, width)
    if column >= 0:
        return column
    est = _estimate_column(ax, ay, bx, by, sx, ys, width)
    return _settle(ax, ay, bx, by, owned, sx, ys, width, est, lower)


@numba.njit(cache=True, inline="always")
def _filtered_bound(ax, ay, slope, delta, sx, ys, width):  # type: ignore[no-untyped-def]
    """:func:`_bound`'s float filter alone: the column, clamped to [0, width], when no
    column boundary lies within the crossing's error bound ``delta`` (then the crossing is
    not a tie and both rules give floor(lo) + 1), else -1 (the exact predicate must settle
    it). No call: a loop of these keeps its values in registers."""
    xc = ax + slope * (ys - ay)
    lo = xc - delta - sx
    hi = xc + delta - sx
    if lo >= width:
        return width
    if hi < 0.0:
        return 0
    if lo > -1.0 and hi < width + 1.0:
        f = math.floor(lo)
        if hi < f + 1.0:
            return min(int(f) + 1, width)
    return -1


@numba.njit(cache=True, inline="always")
def _edge_setup(ax, ay, bx, by, y_first, y_last):  # type: ignore[no-untyped-def]
    """Per-edge constants: y extent, slope dx/dy (for the float estimate only; 0 when
    horizontal) and the crossing's error bound over rows y_first..y_last."""
    slope = (bx - ax) / (by - ay) if by != ay else 0.0
    reach = max(abs(y_first - ay), abs(y_last - ay))
    delta = _CROSSING_ERROR * (abs(ax) + abs(slope) * reach + 1.0)
    return min(ay, by), max(ay, by), slope, delta


@numba.njit(cache=True, inline="always")
def _apply_edge(ax, ay, bx, by, y_lo, y_hi, slope, delta, owned, sx, ys, width, left, right):  # type: ignore[no-untyped-def]
    """Narrow the row's run [left, right) by edge a-b, if its segment reaches height ys.

    An edge whose segment lies wholly above or below the row is skipped: on a row within
    the triangle's height the two edges that reach it bound the section exactly (their
    wedge meets the row inside the triangle), so the third line adds nothing."""
    if ys < y_lo or ys > y_hi:
        return left, right
    if ay == by:
        # Horizontal edge on this very row: its samples are inside only if it owns them.
        if not owned:
            return left, 0
        return left, right
    # one runtime flag, not the constants True and False: numba compiles _settle once for
    # each literal it is called with (three copies of it, a second each, with the path oracle's)
    lower = by < ay
    column = _bound(ax, ay, bx, by, slope, delta, owned, sx, ys, width, lower)
    if lower:  # E grows with x: this edge bounds the run from the left
        return max(left, column), right
    return left, min(right, column)


def shares_of_layers(single: list[Coverage], height: int, n_samples: int) -> Coverage:
    """Per (primitive, pixel) the share of ``n_samples`` sample layers that cover it, as
    alpha (``single``: one single-sample coverage per sample, in a viewport ``height``
    rows high)."""
    layers = Coverage.concat(single)
    # spans grouped by (triangle, row); within a group, samples counted per pixel
    order = np.argsort(layers.primitive * height + layers.y, kind="stable")
    t, y, x0, x1 = (frozen(a[order], np.int64) for a in (layers.triangle, layers.y, layers.x0, layers.x1))
    out_t, out_y, out_x0, out_x1 = span_buffers(t.size)
    counts = np.empty(layers.n_pixels, dtype=np.int64)
    spans, pixels = _count_samples(t, y, x0, x1, out_t, out_y, out_x0, out_x1, counts)
    return Coverage(out_t[:spans], out_y[:spans], out_x0[:spans], out_x1[:spans],
                    alpha=counts[:pixels] / n_samples)


@numba.njit(cache=True)
def _count_samples(t, y, x0, x1, out_t, out_y, out_x0, out_x1, out_counts):  # type: ignore[no-untyped-def]
    """Per run of spans of one (triangle, row), the number of spans covering each pixel,
    as spans over the pixels some span covers (a sliver can pass between a pixel's
    samples: such a pixel is left out) with a count per pixel. Each output span and pixel
    comes from at least one input span and pixel, so buffers of the inputs' sizes hold
    them. Returns (spans, pixels) written."""
    n = 0
    m = 0
    i = 0
    while i < t.size:
        j = i
        lo = x0[i]
        hi = x1[i]
        while j < t.size and t[j] == t[i] and y[j] == y[i]:
            lo = min(lo, x0[j])
            hi = max(hi, x1[j])
            j += 1
        delta = np.zeros(hi - lo + 1, dtype=np.int64)
        for k in range(i, j):
            if x1[k] > x0[k]:
                delta[x0[k] - lo] += 1
                delta[x1[k] - lo] -= 1
        running = 0
        open_run = False
        for x in range(hi - lo):
            running += delta[x]
            if running > 0:
                if not open_run:
                    out_t[n] = t[i]
                    out_y[n] = y[i]
                    out_x0[n] = lo + x
                    open_run = True
                out_counts[m] = running
                m += 1
            elif open_run:
                out_x1[n] = lo + x
                n += 1
                open_run = False
        if open_run:
            out_x1[n] = hi
            n += 1
        i = j
    return n, m
