"""Known-bad edge-function rasterizers: a plain per-pixel test over each triangle's
bounding box, compiled, with one classic bug each (selected by the constructor)."""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import Convention, owns_edge
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen

__all__ = ["EdgeFunctionBug"]


class EdgeFunctionBug:
    """Pixel-centre edge functions, top-left rule (or any other ``tie``), with one bug.

    bug:
      "inclusive"      every edge owns its samples (tinyrenderer's `< 0` test): double hits,
                       and zero-area triangles drawn as lines
      "exclusive"      no edge owns its samples: cracks through pixel centres
      "float32"        edge functions in float32: wrong pixels on unconstrained floats
      "endpoint-order" each triangle evaluates a shared edge in its own endpoint order:
                       values not exactly opposite, cracks and double hits at near ties
      "vertex-order-ties" ties owned by the edges leaving vertex 0, not by top/left edges
      "min-area"       drops triangles of area below one pixel
      "one-winding"    draws only clockwise triangles (assumes one winding)
      "nan-to-num"     replaces non-finite coordinates by numbers and draws them
    """

    interpolates = False  # coverage only: the attribute checks skip it (else its missing rows are a second finding)

    def __init__(self, bug: str, tie: str = "top-left") -> None:
        self.bug = bug
        self.name = f"bad_{bug}" + ("" if tie == "top-left" else f"_{tie}")
        self.convention = Convention(tie=tie)  # type: ignore[arg-type]

    def rasterize(self, scene: Scene) -> Coverage:
        positions = scene.positions
        if self.bug == "nan-to-num":
            positions = np.nan_to_num(positions, nan=0.0, posinf=1e6, neginf=-1e6)
        sx, sy, y_first = self.convention.tie_perturbation
        with np.errstate(all="ignore"):
            tri, x, y = _pixels(frozen(positions), scene.width, scene.height,
                                BUGS.index(self.bug), sx, sy, y_first)
        return Coverage.from_pixels(tri, x, y)


BUGS = ("inclusive", "exclusive", "float32", "endpoint-order", "vertex-order-ties", "min-area", "one-winding", "nan-to-num")


@numba.njit(cache=True)
def _edge(ax, ay, bx, by, px, py, f32):
    if f32:
        return np.float32(np.float32(bx - ax) * np.float32(py - ay)) - np.float32(np.float32(by - ay) * np.float32(px - ax))
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax)


@numba.njit(cache=True)
def _pixels(positions, width, height, bug, sx, sy, y_first):
    """(triangle, x, y) of every pixel whose centre the buggy test puts inside: a plain
    per-pixel test over each triangle's bounding box, with the bug numbered ``bug`` in
    :data:`BUGS` (a compiled kernel: shrinking calls it thousands of times)."""
    f32 = bug == 2
    out_t, out_x, out_y = [], [], []
    for t in range(positions.shape[0]):
        p = positions[t].copy()
        finite = True
        for i in range(3):
            finite = finite and math.isfinite(p[i, 0]) and math.isfinite(p[i, 1])
        if not finite:
            continue
        if f32:
            for i in range(3):
                for j in range(2):
                    p[i, j] = np.float32(p[i, j])
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if (area == 0 and bug != 0) or (bug == 5 and abs(area) / 2 < 1.0) or (bug == 6 and area < 0):
            continue
        if area < 0:  # (scalar code throughout: numpy's reductions and fancy indexing compile slowly)
            for j in range(2):
                p[1, j], p[2, j] = p[2, j], p[1, j]
        x0 = int(max(np.floor(min(p[0, 0], p[1, 0], p[2, 0])), 0.0))
        x1 = int(min(np.ceil(max(p[0, 0], p[1, 0], p[2, 0])) + 1, width))
        y0 = int(max(np.floor(min(p[0, 1], p[1, 1], p[2, 1])), 0.0))
        y1 = int(min(np.ceil(max(p[0, 1], p[1, 1], p[2, 1])) + 1, height))
        owned = np.zeros(3, dtype=np.bool_)
        for k in range(3):
            ax, ay, bx, by = p[k, 0], p[k, 1], p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
            if bug == 0:
                owned[k] = True
            elif bug == 1:
                owned[k] = False
            elif bug == 4:
                owned[k] = k == 0
            else:
                owned[k] = owns_edge(ax, ay, bx, by, sx, sy, y_first)
        for yy in range(y0, y1):
            for xx in range(x0, x1):
                px, py = xx + 0.5, yy + 0.5
                inside = True
                for k in range(3):
                    ax, ay, bx, by = p[k, 0], p[k, 1], p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
                    sign = 1.0
                    if bug != 3 and bug != 2 and (ax > bx or (ax == bx and ay > by)):
                        ax, ay, bx, by, sign = bx, by, ax, ay, -1.0  # canonical order: shared edges get opposite values
                    e = sign * _edge(ax, ay, bx, by, px, py, f32)
                    if not (e > 0 or (e == 0 and owned[k])):
                        inside = False
                        break
                if inside:
                    out_t.append(t)
                    out_x.append(xx)
                    out_y.append(yy)
    return np.array(out_t, dtype=np.int64), np.array(out_x, dtype=np.int64), np.array(out_y, dtype=np.int64)
