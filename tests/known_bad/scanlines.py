"""Known-bad scanline rasterizers, one classic bug each (seeds 000-002), in one numba kernel."""

from __future__ import annotations

import numba
import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orientation

__all__ = ["ScanlineBug"]


class ScanlineBug:
    """A scanline rasterizer (floor convention unless noted) with one bug.

    bug:
      "no-prestep"      centre sampling, span x taken from the edge's top vertex and stepped
                        per row without the sub-pixel prestep (seed 000's first bug)
      "rows-plus-one"   floor convention drawing Y2 - Y1 + 1 rows
      "ceil-left"       floor convention starting spans at ceil(x_left) (seed 002's warning)
      "round-ends"      centre sampling with round-to-nearest span ends
      "top-edge-eval"   floor row counts with the span evaluated at the row's top edge
      "no-clip"         centre sampling without clipping spans to the viewport
    """

    interpolates = False  # coverage only: the attribute checks skip it (else its missing rows are a second finding)

    def __init__(self, bug: str) -> None:
        self.bug = bug
        self.name = f"bad_{bug}"
        centre = bug in ("no-prestep", "round-ends", "no-clip")
        self.centre = centre
        self.convention = Convention() if centre else Convention(sample=(1.0, 1.0), tie="bottom-right")

    def rasterize(self, scene: Scene) -> Coverage:
        sign = orientation(scene.positions)
        with np.errstate(all="ignore"):
            t, y, x0, x1 = _spans(frozen(scene.positions), sign.astype(np.int64),
                                  BUGS.index(self.bug), self.centre, scene.width, scene.height)
        return Coverage(t, y, x0, x1)


BUGS = ("none", "no-prestep", "rows-plus-one", "ceil-left", "round-ends", "top-edge-eval", "no-clip")
NO_PRESTEP, ROWS_PLUS_ONE, CEIL_LEFT, ROUND_ENDS, TOP_EDGE_EVAL, NO_CLIP = range(1, 7)


@numba.njit(cache=True, inline="always")
def _edge_x(ax, ay, bx, by, j, sample, bug):
    if by == ay:
        return ax
    if bug == NO_PRESTEP:  # x from the top vertex, stepped per row
        return ax + (bx - ax) / (by - ay) * (j - np.ceil(ay - 0.5))
    return ax + (bx - ax) * (sample - ay) / (by - ay)


@numba.njit(cache=True, inline="always")
def _column(x, centre, bug):
    if bug == ROUND_ENDS:
        return np.rint(x)  # half to even, as Python's round
    if centre:
        return np.ceil(x - 0.5)
    return np.floor(x)


@numba.njit(cache=True)
def _spans(positions, sign, bug, centre, width, height):
    """Spans (triangle, y, x0, x1) row by row. Coordinates are clamped to a few pixels
    around the viewport before rounding (the same rows and columns survive the clipping);
    a NaN crossing (overflow) draws nothing on its row."""
    n = positions.shape[0]
    tops = np.zeros(n, dtype=np.int64)
    ends = np.zeros(n, dtype=np.int64)
    orders = np.zeros((n, 3), dtype=np.int64)
    capacity = 0
    for t in range(n):
        if sign[t] == 0:
            continue
        p = positions[t]
        order = orders[t]
        order[0], order[1], order[2] = 0, 1, 2
        for a in range(2):  # sorted by y, then x: top, mid, bottom
            for b in range(2 - a):
                i, k = order[b], order[b + 1]
                if p[i, 1] > p[k, 1] or (p[i, 1] == p[k, 1] and p[i, 0] > p[k, 0]):
                    order[b], order[b + 1] = k, i
        yt = min(max(p[order[0], 1], -8.0), height + 8.0)
        yb = min(max(p[order[2], 1], -8.0), height + 8.0)
        if centre:
            first, last = np.ceil(yt - 0.5), np.ceil(yb - 0.5)
        else:
            first, last = np.floor(yt), np.floor(yb) + (1 if bug == ROWS_PLUS_ONE else 0)
        tops[t] = max(int(first), -4)
        ends[t] = min(int(last), height + 4)
        capacity += max(ends[t] - tops[t], 0)
    out_t = np.empty(capacity, dtype=np.int64)
    out_y = np.empty(capacity, dtype=np.int64)
    out_x0 = np.empty(capacity, dtype=np.int64)
    out_x1 = np.empty(capacity, dtype=np.int64)
    count = 0
    for t in range(n):
        if sign[t] == 0:
            continue
        p = positions[t]
        top, mid, bot = orders[t, 0], orders[t, 1], orders[t, 2]
        xt, yt = p[top, 0], p[top, 1]
        xm, ym = p[mid, 0], p[mid, 1]
        xb, yb = p[bot, 0], p[bot, 1]
        parity = 1  # the sorted order's orientation is the triangle's times the permutation's sign
        if top > mid:
            parity = -parity
        if top > bot:
            parity = -parity
        if mid > bot:
            parity = -parity
        long_left = sign[t] * parity > 0
        for j in range(tops[t], ends[t]):
            if bug != NO_CLIP and not (0 <= j < height):
                continue
            sample = j + (0.5 if centre else 1.0)
            if bug == TOP_EDGE_EVAL:
                sample = float(j)
            x_long = _edge_x(xt, yt, xb, yb, j, sample, bug)
            x_short = _edge_x(xt, yt, xm, ym, j, sample, bug) if sample < ym else _edge_x(xm, ym, xb, yb, j, sample, bug)
            xl, xr = (x_long, x_short) if long_left else (x_short, x_long)
            if xl != xl or xr != xr:
                continue
            xl = min(max(xl, -8.0), width + 8.0)
            xr = min(max(xr, -8.0), width + 8.0)
            a, b = int(_column(xl, centre, bug)), int(_column(xr, centre, bug))
            if bug == CEIL_LEFT:
                a = int(np.ceil(xl))
            if bug != NO_CLIP:
                a, b = max(a, 0), min(b, width)
            else:  # no clipping to the viewport, but keep the numbers in range
                a, b = max(a, -4), min(b, width + 4)
            if a < b:
                out_t[count], out_y[count], out_x0[count], out_x1[count] = t, j, a, b
                count += 1
    return out_t[:count], out_y[:count], out_x0[:count], out_x1[:count]
