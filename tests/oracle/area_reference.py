"""The exact area oracle's float path as it was before runs (rastercheck session 21):
one alpha per pixel, interior pixels written one by one, zeros trimmed in a second pass.
Kept as the reference the new path (:func:`harness.oracle.area._area_spans`) is compared
with: the same rows and inner runs, every alpha within both their proven bounds (the
edge integrals in rows holding a vertex give the same bits; the band path elsewhere does
not)."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from harness.geometry.spans import expand, pixel_offsets
from harness.oracle.area import (
    _MARGIN_SCALE,
    _band_area,
    _edge_kinds,
    _pixel_area_of,
    _polygons,
    _slope,
    _sorted_triangle,
    _span_kernel,
    _sub_band_area,
    _sub_bands,
    _trim_lead,
    _viewport,
)


@numba.njit(cache=True, inline="always")
def clamped_mean(y0, y1):
    """Mean of clamp(h, 0, 1) as h runs linearly from y0 to y1. Each case is a quotient of
    differences of like-signed numbers: no cancellation, at most five roundings."""
    lo = min(y0, y1)
    hi = max(y0, y1)
    if hi <= 0.0:
        return 0.0
    if lo >= 1.0:
        return 1.0
    if lo >= 0.0:
        if hi <= 1.0:
            return (lo + hi) * 0.5
        # crosses the band's far side at t1 = (1 - lo) / (hi - lo)
        r = 1.0 - lo
        return 1.0 - (r / (hi - lo)) * r * 0.5
    if hi <= 1.0:
        # crosses the near side at t0 = -lo / (hi - lo), then rises to hi
        return (hi / (hi - lo)) * hi * 0.5
    # crosses both sides: a ramp of width 1 / (hi - lo), then full height
    return (hi - 0.5) / (hi - lo)


@numba.njit(cache=True, inline="always")
def edge_integral(ax, ay, bx, by):
    """s_e * C_e for the edge a -> b in pixel-local coordinates (see the module docstring)."""
    if ax == bx:
        return 0.0  # vertical: crosses no vertical line
    sign = 1.0
    if bx < ax:
        ax, ay, bx, by = bx, by, ax, ay
        sign = -1.0
    xl = max(ax, 0.0)
    xr = min(bx, 1.0)
    if xl >= xr:
        return 0.0
    dx = bx - ax
    dy = by - ay
    # fl(xl - ax) <= fl(dx) by monotone rounding, so the fraction stays in [0, 1]: no
    # overflow however steep the edge.
    yl = ay if xl == ax else ay + ((xl - ax) / dx) * dy
    yr = by if xr == bx else ay + ((xr - ax) / dx) * dy
    return sign * ((xr - xl) * clamped_mean(yl, yr))


@numba.njit(cache=True, inline="always")
def _x_at(ax, ay, bx, by, y):
    """x of the edge a-b (ay < by) at height y in [ay, by]."""
    if y == ay:
        return ax
    if y == by:
        return bx
    return ax + ((y - ay) / (by - ay)) * (bx - ax)


@numba.njit(cache=True)
def old_span_kernel(polys, counts, width, height, out_p, out_y, out_x0, out_x1, out_i0, out_i1):
    """Per polygon and row, the columns [x0, x1) that may hold area: the row band's
    x-extent (reached on the edges' parts inside the band), widened by the crossings'
    error bound, within the bounding box and the viewport; and the columns [i0, i1)
    whose pixel lies wholly inside the polygon (area exactly 1): when the polygon spans
    the whole band, its cross-sections at the band's top and bottom, intersected and
    narrowed by the same bound (a convex polygon's left boundary is convex in y, the
    right one concave: their extremes over the band are at its sides)."""
    n = 0
    for p in range(polys.shape[0]):
        k = counts[p]
        xmin = xmax = polys[p, 0, 0]
        ymin = ymax = polys[p, 0, 1]
        biggest = 0.0
        for v in range(k):
            x, y = polys[p, v, 0], polys[p, v, 1]
            xmin, xmax = min(xmin, x), max(xmax, x)
            ymin, ymax = min(ymin, y), max(ymax, y)
            biggest = max(biggest, abs(x), abs(y))
        margin = _MARGIN_SCALE * (max(xmax - xmin, ymax - ymin) + biggest + 1.0)
        # A pixel holds area only if i < xmax and i + 1 > xmin: columns floor(xmin) ..
        # ceil(xmax) - 1 (the same for rows). This also bounds M in the error bound.
        col_lo = max(int(math.floor(xmin)), 0)
        col_hi = min(int(math.ceil(xmax)) - 1, width - 1)
        row_lo = max(int(math.floor(ymin)), 0)
        row_hi = min(int(math.ceil(ymax)) - 1, height - 1)
        for j in range(row_lo, row_hi + 1):
            top = float(j)
            bottom = top + 1.0
            lo = math.inf
            hi = -math.inf
            for e in range(k):
                f = e + 1 if e + 1 < k else 0
                ax, ay, bx, by = polys[p, e, 0], polys[p, e, 1], polys[p, f, 0], polys[p, f, 1]
                if by < ay:
                    ax, ay, bx, by = bx, by, ax, ay
                if by < top or ay > bottom:
                    continue
                if ay == by:
                    xa, xb = ax, bx
                else:
                    xa = _x_at(ax, ay, bx, by, max(ay, top))
                    xb = _x_at(ax, ay, bx, by, min(by, bottom))
                lo = min(lo, xa, xb)
                hi = max(hi, xa, xb)
            if lo > hi:
                continue
            first = max(int(math.floor(lo - margin)), col_lo)
            last = min(int(math.ceil(hi + margin)) - 1, col_hi)
            inner_lo = 0
            inner_hi = 0
            if ymin <= top and ymax >= bottom:
                # cross-sections at y = top and y = bottom: [left, right] of each
                left = -math.inf
                right = math.inf
                for side in (top, bottom):
                    at_lo = math.inf
                    at_hi = -math.inf
                    for e in range(k):
                        f = e + 1 if e + 1 < k else 0
                        ax, ay, bx, by = polys[p, e, 0], polys[p, e, 1], polys[p, f, 0], polys[p, f, 1]
                        if by < ay:
                            ax, ay, bx, by = bx, by, ax, ay
                        if ay == by or side < ay or side > by:
                            continue
                        x = _x_at(ax, ay, bx, by, side)
                        at_lo = min(at_lo, x)
                        at_hi = max(at_hi, x)
                    left = max(left, at_lo)
                    right = min(right, at_hi)
                # columns i with left + margin <= i and i + 1 <= right - margin
                inner_lo = max(int(math.ceil(left + margin)), first)
                inner_hi = min(int(math.floor(right - margin)), last + 1)
                if inner_hi < inner_lo:
                    inner_lo = inner_hi = 0
            if first <= last:
                out_p[n] = p
                out_y[n] = j
                out_x0[n] = first
                out_x1[n] = last + 1
                out_i0[n] = inner_lo
                out_i1[n] = inner_hi
                n += 1
    return n


@numba.njit(cache=True)
def old_area_kernel(polys, counts, span_p, span_y, span_x0, span_x1, span_i0, span_i1, out):
    """|sum of the edge integrals| of each span's pixels, clamped to [0, 1], in span order
    (exactly 1 on the pixels [i0, i1) wholly inside)."""
    local_x = np.empty(polys.shape[1])
    local_y = np.empty(polys.shape[1])
    m = 0
    for s in range(span_p.size):
        p = span_p[s]
        k = counts[p]
        j = span_y[s]
        for v in range(k):
            # pixel-local coordinates: every later quantity is at most 1 (or M)
            local_y[v] = polys[p, v, 1] - j
        for i in range(span_x0[s], span_x1[s]):
            if span_i0[s] <= i < span_i1[s]:
                out[m] = 1.0  # the whole pixel lies inside: exactly 1
                m += 1
                continue
            for v in range(k):
                local_x[v] = polys[p, v, 0] - i
            total = 0.0
            for e in range(k):
                f = e + 1 if e + 1 < k else 0
                total += edge_integral(local_x[e], local_y[e], local_x[f], local_y[f])
            # Green's theorem gives the area up to the orientation's sign; the exact area is
            # in [0, 1], so clamping only brings the float one closer.
            out[m] = min(abs(total), 1.0)
            m += 1


@numba.njit(cache=True)
def old_trim_zeros(x0, x1, area, out_x0, out_x1, out_first):
    """Each span cut to its first and last pixel of nonzero area (empty when none):
    the new [x0, x1) and the index of its first area in ``area``."""
    m = 0
    for s in range(x0.size):
        a = m
        b = m + (x1[s] - x0[s])
        m = b
        while a < b and area[a] == 0.0:
            a += 1
        while b > a and area[b - 1] == 0.0:
            b -= 1
        out_first[s] = a
        out_x0[s] = x0[s] + (a - (m - (x1[s] - x0[s])))
        out_x1[s] = out_x0[s] + (b - a)


def old_area_spans(array: NDArray[np.float64], width: int, height: int) -> tuple[
        NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """(triangle, y, x0, x1, area): spans sorted by triangle and row, cut to their first
    and last pixel of nonzero float area, with one area per pixel (zero only inside a
    span, where a float area vanished)."""
    _viewport(width, height)
    polys, counts, source = _polygons(array, int(width), int(height))
    # Rows a polygon can touch: floor(ymin) .. ceil(ymax) - 1 within the viewport.
    ys = polys[:, :, 1]
    rows = np.minimum(np.ceil(ys.max(axis=1)), height) - np.maximum(np.floor(ys.min(axis=1)), 0)
    capacity = int(np.maximum(rows, 0).sum())
    block = np.empty((6, capacity), dtype=np.int64)
    spans = old_span_kernel(polys, counts, int(width), int(height), *block)
    span_p, span_y, span_x0, span_x1, span_i0, span_i1 = (np.ascontiguousarray(b[:spans]) for b in block)
    area = np.empty(int(pixel_offsets(span_x0, span_x1)[-1]))
    old_area_kernel(polys, counts, span_p, span_y, span_x0, span_x1, span_i0, span_i1, area)
    x0, x1, first = np.empty_like(span_x0), np.empty_like(span_x1), np.empty_like(span_x0)
    old_trim_zeros(span_x0, span_x1, area, x0, x1, first)
    keep = x1 > x0
    lengths = (x1 - x0)[keep]
    return source[span_p[keep]], span_y[keep], x0[keep], x1[keep], area[expand(first[keep], lengths)]


# -- the two-pass runs kernel of session 21 (span kernel, then edge kernel), the reference
# of the one-pass harness.oracle.area._area_runs: the same spans, inner runs and bits (its
# band path's crossings as the one-pass kernel computes them since session 22: the slope
# once per edge, band_edge)


@numba.njit(cache=True, inline="always", error_model="numpy")
def band_edge(xa, ya, xb, yb, top):
    """(x, d0, d1) of an edge crossing the whole row band [top, top + 1] (global
    coordinates): its local x at the band's top and bottom lines are ``fl(fl(x - i) + d0)``
    and ``fl(fl(x - i) + d1)`` at column i, x its upper end point's,
    ``d = fl(fl(y - ya) * slope)`` (harness.oracle.area's band path)."""
    if yb < ya:
        xa, ya, xb, yb = xb, yb, xa, ya
    slope = _slope(xa, ya, xb, yb)
    return xa, (top - ya) * slope, (top + 1.0 - ya) * slope


@numba.njit(cache=True, inline="always", error_model="numpy")
def pixel_area(band, triangle, crossings, tri, bands, polys, p, k, local_y, kinds, i):
    """The area at column i of a span's row: the band path's (``crossings``: xa, d0, d1, xc,
    e0, e1), a triangle's sub-bands' in a row holding a vertex, or a polygon's edge integrals."""
    if band:
        xa, d0, d1, xc, e0, e1 = crossings
        return _band_area(xa, d0, d1, xc, e0, e1, i)
    if triangle:
        return _sub_band_area(tri[0], tri[2], bands, i)
    return _pixel_area_of(polys, p, k, i, local_y, kinds)


@numba.njit(cache=True, error_model="numpy")  # no division by zero (see _edge_term)
def edge_kernel(polys, counts, span_p, span_y, span_x0, span_x1, span_i0, span_i1, out):
    """The area of each span's edge pixels, the inner run [i0, i1) left alone (exactly 1,
    written as a run, not pixel by pixel: the span fill of a scan converter).

    In place, each span is cut to its first and last pixel of nonzero float area (x1 ==
    x0 when it has none) and a span without inner run gets ``i0 == i1 == x1``; ``out``
    receives the areas of the pixels outside the inner runs, span after span, left to
    right (zero only inside a span). Returns how many it received."""
    local_y = np.empty(polys.shape[1])
    kinds = np.empty(polys.shape[1], dtype=np.int64)
    m = 0
    for s in range(span_p.size):
        p = span_p[s]
        k = counts[p]
        j = span_y[s]
        x0 = span_x0[s]
        x1 = span_x1[s]
        i0 = span_i0[s]
        i1 = span_i1[s]
        if i1 <= i0:
            i0 = i1 = x1  # no inner run: every pixel is an edge pixel
        for v in range(k):
            # pixel-local coordinates: every later quantity is at most 1 (or M)
            local_y[v] = polys[p, v, 1] - j
        triangle = k == 3
        ax, bx, cx = polys[p, 0, 0], polys[p, 1, 0], polys[p, 2, 0]
        ay, by, cy = local_y[0], local_y[1], local_y[2]
        # a band the triangle crosses with no vertex strictly inside (every row but those
        # of its vertices): two edges cross it from top to bottom, the third is wholly
        # above or below (or on a band line), and each pixel's area is the difference of
        # two clamped means of band crossings (module docstring, "Rows without a vertex")
        band = (triangle and min(ay, by, cy) <= 0.0 and max(ay, by, cy) >= 1.0
                and not 0.0 < ay < 1.0 and not 0.0 < by < 1.0 and not 0.0 < cy < 1.0)
        xa = d0 = d1 = xc = e0 = e1 = 0.0
        if band:
            # the edges' crossings as the one-pass kernel computes them, in global y
            ga, gb, gc, top = polys[p, 0, 1], polys[p, 1, 1], polys[p, 2, 1], float(j)
            if min(ay, by) <= 0.0 and max(ay, by) >= 1.0:
                xa, d0, d1 = band_edge(ax, ga, bx, gb, top)
                if min(by, cy) <= 0.0 and max(by, cy) >= 1.0:
                    xc, e0, e1 = band_edge(bx, gb, cx, gc, top)
                else:
                    xc, e0, e1 = band_edge(cx, gc, ax, ga, top)
            else:
                xa, d0, d1 = band_edge(bx, gb, cx, gc, top)
                xc, e0, e1 = band_edge(cx, gc, ax, ga, top)
        elif not triangle:
            _edge_kinds(polys, p, k, float(x0), float(x1), local_y, kinds)
        # a triangle's row holding a vertex: its sub-bands (since session 22)
        tri = _sorted_triangle(polys, p) if triangle else (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        bands = _sub_bands(tri, float(j))
        start = m
        for i in range(x0, i0):
            out[m] = pixel_area(band, triangle, (xa, d0, d1, xc, e0, e1), tri, bands, polys, p, k, local_y, kinds, i)
            m += 1
        # the span begins at its first pixel of nonzero area (the inner run's first, if need be)
        m, x0 = _trim_lead(out, start, m, x0)
        right = m
        for i in range(i1, x1):
            out[m] = pixel_area(band, triangle, (xa, d0, d1, xc, e0, e1), tri, bands, polys, p, k, local_y, kinds, i)
            m += 1
        # and ends at its last (the inner run's last, if need be)
        floor = right if i1 > i0 else start
        while m > floor and out[m - 1] == 0.0:
            m -= 1
        if i1 > i0:
            x1 = i1 + (m - right)
        else:
            x1 = x0 + (m - start)
            i0 = i1 = x1
        span_x0[s] = x0
        span_x1[s] = x1
        span_i0[s] = i0
        span_i1[s] = i1
    return m



@numba.njit(cache=True)
def two_pass_area_runs(polys, counts, source, width, height):
    """:func:`harness.oracle.area._span_kernel`, then :func:`edge_kernel`, then the empty spans dropped and
    each span's polygon replaced by its triangle (``source``): one call, no temporaries
    but the spans' block and the edge areas."""
    capacity = 0
    for p in range(polys.shape[0]):
        ymin = ymax = polys[p, 0, 1]
        for v in range(counts[p]):
            ymin = min(ymin, polys[p, v, 1])
            ymax = max(ymax, polys[p, v, 1])
        # rows a polygon can touch: floor(ymin) .. ceil(ymax) - 1 within the viewport
        capacity += max(min(int(math.ceil(ymax)), height) - max(int(math.floor(ymin)), 0), 0)
    block = np.empty((6, capacity), dtype=np.int64)
    span_p, span_y, span_x0, span_x1, span_i0, span_i1 = block[0], block[1], block[2], block[3], block[4], block[5]
    spans = _span_kernel(polys, counts, width, height, span_p, span_y, span_x0, span_x1, span_i0, span_i1)
    edges = 0
    for s in range(spans):
        edges += span_x1[s] - span_x0[s] - max(span_i1[s] - span_i0[s], 0)
    alpha = np.empty(edges)
    m = edge_kernel(polys, counts, span_p[:spans], span_y, span_x0, span_x1, span_i0, span_i1, alpha)
    w = 0
    for s in range(spans):
        if span_x1[s] > span_x0[s]:
            span_p[w] = source[span_p[s]]
            span_y[w] = span_y[s]
            span_x0[w] = span_x0[s]
            span_x1[w] = span_x1[s]
            span_i0[w] = span_i0[s]
            span_i1[w] = span_i1[s]
            w += 1
    return span_p[:w], span_y[:w], span_x0[:w], span_x1[:w], span_i0[:w], span_i1[:w], alpha[:m]
