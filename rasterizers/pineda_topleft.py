"""``pineda_topleft``: edge functions at pixel centres with the top-left rule (seeds 003, 004).

Coverage is the per-pixel Pineda test: pixel (i, j) is inside when all three edge
functions ``E(p) = (bx-ax)*(py-ay) - (by-ay)*(px-ax)``, evaluated in float64 at its centre,
are positive, or zero on a top or left edge.

Traversal walks the edges instead of testing every pixel of the bounding box (or of
8 x 8 tiles). Along a row the float value ``fl(dx*fl(py-ay) - fl(dy*fl(px-ax)))`` is
monotone in px -- each rounding is monotone -- so the pixels passing one edge form a prefix
or a suffix of the row. Each edge's sign change is found from its float crossing and
confirmed with the same float edge function (stepping, or bisecting when the estimate is
off), which gives exactly the per-pixel decisions at a few evaluations per edge and row.
Tests compare it with a per-pixel evaluation of the whole bounding box.

Each edge is evaluated with its endpoints in one canonical (lexicographic) order and
negated for the other direction, so the two triangles sharing an edge get exactly
opposite values at every sample and the mesh is watertight on arbitrary floats.

Convention: sample (0.5, 0.5), ``top-left`` ties (any of the eight rules may be chosen:
``PinedaTopLeft(tie="bottom-right-y-first")``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import TIE_RULES, Convention, TieRule, owns_edge
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from harness.geometry.spans import span_buffers
from rasterizers._common import build_coverage, interpolate_barycentric, row_capacity, screen_triangles

__all__ = ["PinedaTopLeft", "edge_setup"]

MAX_COORDINATE = 2.0**24  # float edge functions stay accurate to far below 1/1000 px


@numba.njit(cache=True)
def edge_setup(p, sign, edges, tie_x=1, tie_y=1, y_first=False):  # type: ignore[no-untyped-def]
    """Fill ``edges`` (3, 6) for edge k (vertex k -> k+1 once oriented A > 0): canonical
    start point, canonical deltas, the sign turning the canonical value into this
    triangle's, and 1 when the tie rule (default top-left) owns the edge."""
    for k in range(3):
        if sign > 0:
            a, b = k, (k + 1) % 3
        else:  # walk the edges backwards: same triangle, positive orientation
            a, b = (k + 1) % 3, k
        ax, ay, bx, by = p[a, 0], p[a, 1], p[b, 0], p[b, 1]
        # The tie rule: top-left owns top edges (horizontal, interior below: dx > 0) and
        # left ones (interior to the right: dy < 0); any other rule by its perturbation.
        top_left = 1.0 if owns_edge(ax, ay, bx, by, tie_x, tie_y, y_first) else 0.0
        # One canonical endpoint order per edge: both triangles compute the same float.
        if (ax, ay) <= (bx, by):
            edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3], edges[k, 4] = ax, ay, bx - ax, by - ay, 1.0
        else:
            edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3], edges[k, 4] = bx, by, ax - bx, ay - by, -1.0
        edges[k, 5] = top_left


@numba.njit(cache=True, inline="always")
def _passes(ax, ay, dx, dy, s, top_left, px, py):  # type: ignore[no-untyped-def]
    value = s * (dx * (py - ay) - dy * (px - ax))
    # The top-left rule: a sample exactly on an edge is inside only for top or left edges.
    return value > 0.0 or (value == 0.0 and top_left > 0.0)


@numba.njit(cache=True, inline="always")
def _walk(ax, ay, dx, dy, s, top_left, py, lo, hi, estimate, rising):  # type: ignore[no-untyped-def]
    """First column c in [lo, hi] where g(c) holds, g monotone false -> true and g(hi)
    taken as true: g = passes for an edge whose value rises with x, not passes for one
    whose value falls. Starts at the estimate; steps, then bisects if it is far off."""
    c = min(max(estimate, lo), hi)
    if c < hi and (_passes(ax, ay, dx, dy, s, top_left, c + 0.5, py) != rising):
        c += 1
        if c >= hi or (_passes(ax, ay, dx, dy, s, top_left, c + 0.5, py) == rising):
            return c
        low, high = c, hi
    else:
        if c == lo or (_passes(ax, ay, dx, dy, s, top_left, c - 0.5, py) != rising):
            return c
        c -= 1
        if c == lo or (_passes(ax, ay, dx, dy, s, top_left, c - 0.5, py) != rising):
            return c
        low, high = lo - 1, c - 1
    while high - low > 1:
        mid = (low + high) // 2
        if _passes(ax, ay, dx, dy, s, top_left, mid + 0.5, py) == rising:
            high = mid
        else:
            low = mid
    return high


@numba.njit(cache=True, error_model="numpy")
def _kernel(positions, sign, tie_x, tie_y, y_first, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    e = np.empty((3, 6))
    slope = np.empty(3)
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue
        p = positions[t]
        edge_setup(p, sign[t], e, tie_x, tie_y, y_first)
        for k in range(3):  # dx/dy, for the crossing estimate only
            slope[k] = e[k, 2] / e[k, 3] if e[k, 3] != 0.0 else 0.0
        # Columns and rows whose pixel centres lie in the triangle's box, on screen.
        bx0 = max(math.floor(min(p[0, 0], p[1, 0], p[2, 0]) - 0.5), 0)
        bx1 = min(math.ceil(max(p[0, 0], p[1, 0], p[2, 0]) - 0.5), width - 1)
        by0 = max(math.floor(min(p[0, 1], p[1, 1], p[2, 1]) - 0.5), 0)
        by1 = min(math.ceil(max(p[0, 1], p[1, 1], p[2, 1]) - 0.5), height - 1)
        for y in range(by0, by1 + 1):
            py = y + 0.5
            left = bx0
            right = bx1 + 1
            for k in range(3):
                ax, ay, dx, dy, s, tl = e[k, 0], e[k, 1], e[k, 2], e[k, 3], e[k, 4], e[k, 5]
                if dy == 0.0:  # constant along the row: all or nothing
                    if not _passes(ax, ay, dx, dy, s, tl, 0.5, py):
                        right = left
                    continue
                # Float crossing of the edge line with this row, as a column estimate.
                cross = ax + slope[k] * (py - ay) - 0.5
                estimate = bx0 if not cross > bx0 else (right if cross > right else int(math.ceil(cross)))
                if s * dy < 0.0:  # the value rises with x: the pass set is a suffix
                    left = max(left, _walk(ax, ay, dx, dy, s, tl, py, left, right, estimate, True))
                else:  # falls with x: the pass set is a prefix
                    right = min(right, _walk(ax, ay, dx, dy, s, tl, py, left, right, estimate, False))
                if left >= right:
                    break
            if left < right:
                out_t[n] = t
                out_y[n] = y
                out_x0[n] = left
                out_x1[n] = right
                n += 1
    return n


class PinedaTopLeft:
    """Pineda edge functions with the top-left rule, edge-walking traversal.

    Examples
    --------
    >>> PinedaTopLeft().rasterize(Scene(4, 3, [[[0.5, 0.5], [3.5, 0.5], [0.5, 2.5]]])).counts(4, 3)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    """

    name = "pineda_topleft"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")

    def __init__(self, tie: TieRule = "top-left") -> None:
        if tie not in TIE_RULES:
            raise ValueError(f"pineda_topleft: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        if tie != "top-left":
            self.name = f"pineda_{tie}"
            self.convention = Convention(sample=(0.5, 0.5), tie=tie)

    def rasterize(self, scene: Scene) -> Coverage:
        sign = screen_triangles(  # zero-area and non-finite triangles draw nothing
            scene, MAX_COORDINATE, self.name, "float edge functions are not accurate that far out"
        )
        positions = frozen(scene.positions)
        capacity = row_capacity(positions, sign, scene.height)  # one run per row at most
        spans = span_buffers(capacity)
        n = _kernel(positions, sign, *self.convention.tie_perturbation, scene.width, scene.height, *spans)
        attributes = interpolate_barycentric(scene, scene.positions, spans, n, self.convention.sample)
        return build_coverage(scene, spans, n, attributes)
