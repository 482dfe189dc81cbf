"""Known-bad edge-function rasterizers: a plain per-pixel test over each triangle's
bounding box, in numpy, with one classic bug each (selected by the constructor)."""

from __future__ import annotations

import numpy as np

from harness.api import Coverage, Scene
from tests.known_bad import coverage_from_parts
from harness.conventions import Convention, owns_edge

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

    def __init__(self, bug: str, tie: str = "top-left") -> None:
        self.bug = bug
        self.name = f"bad_{bug}" + ("" if tie == "top-left" else f"_{tie}")
        self.convention = Convention(tie=tie)  # type: ignore[arg-type]

    def rasterize(self, scene: Scene) -> Coverage:
        with np.errstate(all="ignore"):
            return self._rasterize(scene)

    def _rasterize(self, scene: Scene) -> Coverage:
        dtype = np.float32 if self.bug == "float32" else np.float64
        positions = scene.positions
        if self.bug == "nan-to-num":
            positions = np.nan_to_num(positions, nan=0.0, posinf=1e6, neginf=-1e6)
        tris, xs, ys = [], [], []
        for t, p in enumerate(positions):
            if not np.all(np.isfinite(p)):
                continue
            area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
            if (area == 0 and self.bug != "inclusive") or (self.bug == "min-area" and abs(area) / 2 < 1.0) or (self.bug == "one-winding" and area < 0):
                continue
            if area < 0:
                p = p[[0, 2, 1]]
            x0 = int(max(np.floor(p[:, 0].min()), 0))
            x1 = int(min(np.ceil(p[:, 0].max()) + 1, scene.width))
            y0 = int(max(np.floor(p[:, 1].min()), 0))
            y1 = int(min(np.ceil(p[:, 1].max()) + 1, scene.height))
            if x0 >= x1 or y0 >= y1:
                continue
            py, px = (np.mgrid[y0:y1, x0:x1] + 0.5).astype(dtype)
            inside = np.ones(px.shape, dtype=bool)
            q = p.astype(dtype)
            for k in range(3):
                a, b = q[k], q[(k + 1) % 3]
                sign = 1
                if self.bug not in ("endpoint-order", "float32") and tuple(a) > tuple(b):
                    a, b, sign = b, a, -1  # canonical order: shared edges get opposite values
                e = sign * ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]))
                (ax, ay), (bx, by) = q[k], q[(k + 1) % 3]
                owned = owns_edge(ax, ay, bx, by, *self.convention.tie_perturbation)
                if self.bug == "inclusive":
                    owned = True
                elif self.bug == "exclusive":
                    owned = False
                elif self.bug == "vertex-order-ties":
                    owned = k == 0
                inside &= (e > 0) | ((e == 0) & owned)
            y, x = np.nonzero(inside)
            tris.append(np.full(x.size, t))
            xs.append(x + x0)
            ys.append(y + y0)
        return coverage_from_parts(tris, xs, ys)
