"""``pineda_topleft``: edge functions at pixel centres, top-left rule, tiled traversal
(seeds 003 and 004).

Three edge functions ``E(p) = (bx-ax)*(py-ay) - (by-ay)*(px-ax)`` are evaluated in float64
at pixel centres, tile by tile (8 x 8 tiles aligned to the screen): a tile is rejected
when one edge is surely negative over it, accepted whole when all three are surely
positive, and otherwise tested pixel by pixel. "Surely" means beyond twice the float
evaluation's error bound, so a whole-tile decision always equals the per-pixel one.

Each edge is evaluated with its endpoints in one canonical (lexicographic) order and
negated for the other direction, so the two triangles sharing an edge get exactly
opposite values at every sample and the mesh is watertight on arbitrary floats.

Convention: sample (0.5, 0.5), ``top-left`` ties.
"""

from __future__ import annotations

import numba
import numpy as np

from harness.api import Coverage, Scene
from harness.conventions import Convention
from harness.exact import orientation
from rasterizers._common import build_coverage, check_coordinates, interpolate_barycentric

__all__ = ["PinedaTopLeft"]

TILE = 8
MAX_COORDINATE = 2.0**24  # float edge functions stay accurate to far below 1/1000 px
# Bound on |E_float - E_exact| relative to |dx*(py-ay)| + |dy*(px-ax)|: Shewchuk's
# 3*eps + 16*eps**2 for this expression, doubled for the bound's own rounding.
_ERROR = 8.0 * 2.0**-53


@numba.njit(cache=True)
def _setup(p, sign):  # type: ignore[no-untyped-def]
    """Per edge k (vertex k -> k+1 after orienting A > 0): canonical start point,
    canonical deltas, the sign that turns the canonical value into this triangle's, and
    whether the edge is top or left."""
    edges = np.empty((3, 6))
    for k in range(3):
        if sign > 0:
            a, b = k, (k + 1) % 3
        else:  # walk the edges backwards: same triangle, positive orientation
            a, b = (k + 1) % 3, k
        ax, ay, bx, by = p[a, 0], p[a, 1], p[b, 0], p[b, 1]
        dx, dy = bx - ax, by - ay
        # Top-left rule: a top edge is horizontal with the interior below (dx > 0);
        # a left edge has the interior to its right (dy < 0).
        top_left = (dy == 0.0 and dx > 0.0) or dy < 0.0
        # One canonical endpoint order per edge: both triangles compute the same float.
        if (ax, ay) <= (bx, by):
            edges[k] = (ax, ay, bx - ax, by - ay, 1.0, 1.0 if top_left else 0.0)
        else:
            edges[k] = (bx, by, ax - bx, ay - by, -1.0, 1.0 if top_left else 0.0)
    return edges


@numba.njit(cache=True, inline="always")
def _edge(ax, ay, dx, dy, s, px, py):  # type: ignore[no-untyped-def]
    return s * (dx * (py - ay) - dy * (px - ax))


@numba.njit(cache=True, inline="always")
def _passes(value, top_left):  # type: ignore[no-untyped-def]
    # The top-left rule: a sample exactly on an edge is inside only for top or left edges.
    return value > 0.0 or (value == 0.0 and top_left > 0.0)


@numba.njit(cache=True, inline="always")
def _tile_state(ax, ay, dx, dy, s, x_lo, x_hi, y_lo, y_hi):  # type: ignore[no-untyped-def]
    """+1 surely inside over the tile, -1 surely outside, 0 undecided."""
    x_a, x_b, y_a, y_b = x_lo + 0.5, x_hi + 0.5, y_lo + 0.5, y_hi + 0.5
    v0 = _edge(ax, ay, dx, dy, s, x_a, y_a)
    v1 = _edge(ax, ay, dx, dy, s, x_b, y_a)
    v2 = _edge(ax, ay, dx, dy, s, x_a, y_b)
    v3 = _edge(ax, ay, dx, dy, s, x_b, y_b)
    lo = min(min(v0, v1), min(v2, v3))
    hi = max(max(v0, v1), max(v2, v3))
    reach_y = max(abs(y_a - ay), abs(y_b - ay))
    reach_x = max(abs(x_a - ax), abs(x_b - ax))
    margin = 2.0 * _ERROR * (abs(dx) * reach_y + abs(dy) * reach_x)
    if lo > margin:
        return 1
    if hi < -margin:
        return -1
    return 0


@numba.njit(cache=True, inline="always")
def _extend(run_x0, run_x1, x0, x1):  # type: ignore[no-untyped-def]
    """Extend the open run [run_x0, run_x1) with [x0, x1) when they touch; otherwise the
    open run is finished. Returns (new run, finished run); scalars only, no arrays."""
    if run_x1 == x0:
        return run_x0, x1, 0, 0
    return x0, x1, run_x0, run_x1


@numba.njit(cache=True)
def _kernel(positions, sign, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    run_x0 = np.zeros(TILE, dtype=np.int64)
    run_x1 = np.zeros(TILE, dtype=np.int64)
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue
        p = positions[t]
        e = _setup(p, sign[t])
        a0x, a0y, d0x, d0y, s0, tl0 = e[0, 0], e[0, 1], e[0, 2], e[0, 3], e[0, 4], e[0, 5]
        a1x, a1y, d1x, d1y, s1, tl1 = e[1, 0], e[1, 1], e[1, 2], e[1, 3], e[1, 4], e[1, 5]
        a2x, a2y, d2x, d2y, s2, tl2 = e[2, 0], e[2, 1], e[2, 2], e[2, 3], e[2, 4], e[2, 5]
        # Bounding box of the pixel centres inside the triangle's box, clipped to the screen.
        bx0 = max(int(np.floor(min(p[0, 0], p[1, 0], p[2, 0]) - 0.5)), 0)
        bx1 = min(int(np.ceil(max(p[0, 0], p[1, 0], p[2, 0]) - 0.5)), width - 1)
        by0 = max(int(np.floor(min(p[0, 1], p[1, 1], p[2, 1]) - 0.5)), 0)
        by1 = min(int(np.ceil(max(p[0, 1], p[1, 1], p[2, 1]) - 0.5)), height - 1)
        if bx0 > bx1 or by0 > by1:
            continue
        for ty in range((by0 // TILE) * TILE, by1 + 1, TILE):
            y_lo, y_hi = max(ty, by0), min(ty + TILE - 1, by1)
            run_x0[:] = 0
            run_x1[:] = 0
            for tx in range((bx0 // TILE) * TILE, bx1 + 1, TILE):
                x_lo, x_hi = max(tx, bx0), min(tx + TILE - 1, bx1)
                state0 = _tile_state(a0x, a0y, d0x, d0y, s0, x_lo, x_hi, y_lo, y_hi)
                state1 = _tile_state(a1x, a1y, d1x, d1y, s1, x_lo, x_hi, y_lo, y_hi)
                state2 = _tile_state(a2x, a2y, d2x, d2y, s2, x_lo, x_hi, y_lo, y_hi)
                if state0 < 0 or state1 < 0 or state2 < 0:
                    continue  # trivial reject: one edge is surely negative over the tile
                accept = state0 > 0 and state1 > 0 and state2 > 0
                for y in range(y_lo, y_hi + 1):
                    row = y - ty
                    if accept:
                        run_x0[row], run_x1[row], f0, f1 = _extend(run_x0[row], run_x1[row], x_lo, x_hi + 1)
                        if f1 > f0:
                            out_t[n], out_y[n], out_x0[n], out_x1[n] = t, y, f0, f1
                            n += 1
                        continue
                    py = y + 0.5
                    start = -1
                    for x in range(x_lo, x_hi + 2):
                        px = x + 0.5
                        inside = (
                            x <= x_hi
                            and _passes(_edge(a0x, a0y, d0x, d0y, s0, px, py), tl0)
                            and _passes(_edge(a1x, a1y, d1x, d1y, s1, px, py), tl1)
                            and _passes(_edge(a2x, a2y, d2x, d2y, s2, px, py), tl2)
                        )
                        if inside and start < 0:
                            start = x
                        elif not inside and start >= 0:
                            run_x0[row], run_x1[row], f0, f1 = _extend(run_x0[row], run_x1[row], start, x)
                            if f1 > f0:
                                out_t[n], out_y[n], out_x0[n], out_x1[n] = t, y, f0, f1
                                n += 1
                            start = -1
            for row in range(TILE):
                if run_x1[row] > run_x0[row]:
                    out_t[n], out_y[n], out_x0[n], out_x1[n] = t, ty + row, run_x0[row], run_x1[row]
                    n += 1
    return n


class PinedaTopLeft:
    """Pineda edge functions with the top-left rule, 8 x 8 tiled traversal.

    Examples
    --------
    >>> PinedaTopLeft().rasterize(Scene(4, 3, [[[0.5, 0.5], [3.5, 0.5], [0.5, 2.5]]])).counts(4, 3)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    """

    name = "pineda_topleft"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")

    def rasterize(self, scene: Scene) -> Coverage:
        finite = check_coordinates(
            scene, MAX_COORDINATE, self.name, "float edge functions are not accurate that far out"
        )
        positions = np.where(finite[:, None, None], scene.positions, 0.0)
        sign = orientation(positions)  # zero-area and non-finite triangles draw nothing
        live = positions[sign != 0]
        rows = np.ceil(live[..., 1].max(axis=1)) - np.floor(live[..., 1].min(axis=1)) + 1
        # Runs per row: one, or more only where float rounding breaks a row (never seen).
        capacity = int(np.clip(rows, 0, scene.height).sum()) * 2 + 16
        spans = tuple(np.empty(capacity, dtype=np.int64) for _ in range(4))
        n = _kernel(positions, sign, scene.width, scene.height, *spans)
        attributes = interpolate_barycentric(scene, positions, spans, n, self.convention.sample)
        return build_coverage(scene, spans, n, attributes)
