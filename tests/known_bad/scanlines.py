"""Known-bad scanline rasterizers in plain Python, one classic bug each (seeds 000-002)."""

from __future__ import annotations

import math

import numpy as np

from tests.known_bad import coverage_from_spans
from harness.api import Coverage, Scene
from harness.conventions import Convention
from harness.exact import orientation

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

    def __init__(self, bug: str) -> None:
        self.bug = bug
        self.name = f"bad_{bug}"
        centre = bug in ("no-prestep", "round-ends", "no-clip")
        self.centre = centre
        self.convention = Convention() if centre else Convention(sample=(1.0, 1.0), tie="bottom-right")

    def _rows(self, yt: float, yb: float, height: int) -> range:
        if self.centre:
            first, last = math.ceil(yt - 0.5), math.ceil(yb - 0.5)
        else:
            first, last = math.floor(yt), math.floor(yb) + (1 if self.bug == "rows-plus-one" else 0)
        return range(max(first, -4), min(last, height + 4))

    def _column(self, x: float) -> int:
        if self.bug == "round-ends":
            return round(x)
        if self.centre:
            return math.ceil(x - 0.5)
        return math.floor(x)

    def rasterize(self, scene: Scene) -> Coverage:
        with np.errstate(all="ignore"):
            return self._rasterize(scene)

    def _rasterize(self, scene: Scene) -> Coverage:
        sign = orientation(scene.positions)
        spans = []
        for t in np.flatnonzero(sign != 0):
            p = scene.positions[t]
            top, mid, bot = sorted(range(3), key=lambda v: (p[v, 1], p[v, 0]))
            (xt, yt), (xm, ym), (xb, yb) = p[top], p[mid], p[bot]
            long_left = orientation(np.array([[p[top], p[mid], p[bot]]]))[0] > 0
            first_row = None
            for j in self._rows(yt, yb, scene.height):
                if not self.bug == "no-clip" and not 0 <= j < scene.height:
                    continue
                sample = j + (0.5 if self.centre else 1.0)
                if self.bug == "top-edge-eval":
                    sample = float(j)
                if first_row is None:
                    first_row = j

                def edge_x(ax: float, ay: float, bx: float, by: float, j: int = j, sample: float = sample) -> float:
                    if by == ay:
                        return ax
                    if self.bug == "no-prestep":  # x from the top vertex, stepped per row
                        return ax + (bx - ax) / (by - ay) * (j - math.ceil(ay - 0.5))
                    return ax + (bx - ax) * (sample - ay) / (by - ay)

                x_long = edge_x(xt, yt, xb, yb)
                x_short = edge_x(xt, yt, xm, ym) if sample < ym else edge_x(xm, ym, xb, yb)
                xl, xr = (x_long, x_short) if long_left else (x_short, x_long)
                a, b = self._column(xl), self._column(xr)
                if self.bug == "ceil-left":
                    a = math.ceil(xl)
                if self.bug != "no-clip":
                    a, b = max(a, 0), min(b, scene.width)
                else:  # no clipping to the viewport, but keep the numbers in range
                    a, b = max(a, -4), min(b, scene.width + 4)
                if a < b:
                    spans.append((t, j, a, b))
        return coverage_from_spans(spans)
