"""The scanline traversal shared by ``floor_scanline`` (seed 000) and ``centre_scanline``
(seed 001). Both sort the vertices by y, walk the long edge against the two short ones,
and evaluate each edge's x at the row's sample height from the edge's own endpoints, so a
shared edge yields the same float in both of its triangles: spans meet, no cracks."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from harness.geometry.exact import frozen

# Float scanline arithmetic is accurate (errors far below 1/1000 px) up to 2**24 px;
# beyond that a crossing's rounding error grows with the coordinates, so such triangles
# are refused with a clear error rather than drawn wrong.
MAX_COORDINATE = 2.0**24


@numba.njit(cache=True, inline="always")
def _edge_x(ax, ay, bx, by, y):  # type: ignore[no-untyped-def]
    """x of edge a-b (ay < by) at height y; exactly ax or bx at the endpoints' heights."""
    if y == ay:
        return ax
    if y == by:
        return bx
    # The seed's x_top + Ey * dxdy, with the gradient applied as dx * Ey / dy: multiplying
    # before dividing keeps lattice input exact, so only one rounding meets the tie test.
    return ax + (bx - ax) * (y - ay) / (by - ay)


@numba.njit(cache=True)
def _first_row(y, centre):  # type: ignore[no-untyped-def]
    # floor convention: row j is drawn when y_top < j + 1 (sample at the row's bottom);
    # centre convention: when y_top <= j + 0.5 (sample at the row's centre).
    return math.ceil(y - 0.5) if centre else math.floor(y)


@numba.njit(cache=True)
def _column(x, centre):  # type: ignore[no-untyped-def]
    # floor: column i is covered when x_left < i + 1 <= x_right -> [floor(xl), floor(xr));
    # centre: when x_left <= i + 0.5 < x_right -> [ceil(xl - 0.5), ceil(xr - 0.5)).
    return math.ceil(x - 0.5) if centre else math.floor(x)


@numba.njit(cache=True)
def scanline_kernel(positions, orient, active, centre, width, height, out_t, out_y, out_x0, out_x1, out_edge):  # type: ignore[no-untyped-def]
    sample = 0.5 if centre else 1.0
    n = 0
    order = np.empty(3, dtype=np.int64)
    for t in range(positions.shape[0]):
        if not active[t]:
            continue
        p = positions[t]
        # Sort by y, then x: top, mid, bottom.
        order[0], order[1], order[2] = 0, 1, 2
        for a in range(2):
            for b in range(2 - a):
                i, j = order[b], order[b + 1]
                if p[i, 1] > p[j, 1] or (p[i, 1] == p[j, 1] and p[i, 0] > p[j, 0]):
                    order[b], order[b + 1] = j, i
        parity = 1
        if order[0] > order[1]:
            parity = -parity
        if order[0] > order[2]:
            parity = -parity
        if order[1] > order[2]:
            parity = -parity
        top, mid, bot = order[0], order[1], order[2]
        xt, yt = p[top, 0], p[top, 1]
        xm, ym = p[mid, 0], p[mid, 1]
        xb, yb = p[bot, 0], p[bot, 1]
        # The exact signed area of (top, mid, bot): positive puts mid right of the long edge.
        long_is_left = orient[t] * parity > 0
        first = max(_first_row(yt, centre), 0)
        last = min(_first_row(yb, centre) - 1, height - 1)
        for j in range(first, last + 1):
            y = j + sample
            x_long = _edge_x(xt, yt, xb, yb, y)
            if y < ym:
                x_short = _edge_x(xt, yt, xm, ym, y)
            else:
                x_short = _edge_x(xm, ym, xb, yb, y)
            xl, xr = (x_long, x_short) if long_is_left else (x_short, x_long)
            x0 = max(_column(xl, centre), 0)
            x1 = min(_column(xr, centre), width)
            if x0 < x1:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = x0
                out_x1[n] = x1
                out_edge[n] = xl
                n += 1
    return n


def scanline(scene, centre: bool, name: str):  # type: ignore[no-untyped-def]
    """Run the kernel over a scene: spans, the left edge x of each, and span count."""
    from harness.geometry.spans import span_buffers
    from rasterizers._common import row_capacity, screen_triangles

    sign = screen_triangles(  # zero-area and non-finite triangles draw nothing
        scene, MAX_COORDINATE, name, "float scanline arithmetic is not accurate that far out"
    )
    positions = frozen(scene.positions)
    capacity = row_capacity(positions, sign, scene.height)
    spans = span_buffers(capacity)
    edge_x: NDArray[np.float64] = np.empty(capacity)
    out_t, out_y, out_x0, out_x1 = spans
    n = scanline_kernel(positions, sign, sign != 0, centre, scene.width, scene.height, out_t, out_y, out_x0, out_x1, edge_x)
    return spans, n, edge_x
