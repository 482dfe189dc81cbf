"""Known-bad attribute interpolation and edge stepping (seeds 000 and 002), for the motion
checks: correct spans from the centre scanline, wrong values or drifting edges."""

from __future__ import annotations

import math

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers._scanline import scanline
from tests.known_bad import coverage_from_spans

__all__ = ["InterpolationBug", "Float32DDA"]


class InterpolationBug:
    """Centre-sampled spans; (u, v, ...) interpolated with one bug.

    bug:
      "no-subtexel"        values start at the left edge's x, not the first sample's
                           (seed 000's second bug): texels drift against their edges
      "subtexel-wrong-sign" the x correction applied backwards
      "pixel-corner"       values taken at the pixel's corner, not its sample point
      "affine"             screen-linear interpolation even when w is given
    """

    convention = Convention()

    def __init__(self, bug: str) -> None:
        self.bug = bug
        self.name = f"bad_{bug}"

    def rasterize(self, scene: Scene) -> Coverage:
        spans, n, edge_x = scanline(scene, centre=True, name=self.name)
        t, y, x0, x1 = (a[:n] for a in spans)
        if scene.attributes is None:
            return Coverage(t, y, x0, x1)
        lengths = x1 - x0
        tri = np.repeat(t, lengths)
        row = np.repeat(y, lengths)
        start = np.repeat(x0, lengths)
        xl = np.repeat(edge_x[:n], lengths)
        x = start + (np.arange(tri.size) - np.repeat(np.cumsum(lengths) - lengths, lengths))
        p = scene.positions[tri]
        perspective = scene.w is not None and self.bug != "affine"
        inv_w = 1.0 / scene.w[tri] if perspective and scene.w is not None else np.ones((tri.size, 3))
        values = scene.attributes[tri] * inv_w[:, :, None]
        quantities = np.concatenate([values, inv_w[:, :, None]], axis=2)
        e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        area = e1[:, 0] * e2[:, 1] - e2[:, 0] * e1[:, 1]
        dq1, dq2 = quantities[:, 1] - quantities[:, 0], quantities[:, 2] - quantities[:, 0]
        dqdx = (dq1 * e2[:, 1, None] - dq2 * e1[:, 1, None]) / area[:, None]
        dqdy = (dq2 * e1[:, 0, None] - dq1 * e2[:, 0, None]) / area[:, None]
        ys = row + 0.5
        xs = x + 0.5
        if self.bug == "pixel-corner":
            xs, ys = x.astype(float), row.astype(float)
        at_edge = quantities[:, 0] + dqdx * (xl - p[:, 0, 0])[:, None] + dqdy * (ys - p[:, 0, 1])[:, None]
        if self.bug == "no-subtexel":
            q = at_edge + dqdx * (x - start)[:, None]
        elif self.bug == "subtexel-wrong-sign":
            q = at_edge - dqdx * (start + 0.5 - xl)[:, None] + dqdx * (x - start)[:, None]
        else:
            q = at_edge + dqdx * (xs - xl)[:, None]
        out = q[:, :-1] / q[:, -1:] if perspective else q[:, :-1]
        return Coverage(t, y, x0, x1, out)


class Float32DDA:
    """A centre scanline that steps each edge down the rows in single precision,
    ``x += dxdy`` from the first row: the error grows down tall edges, and the drifting
    boundary flickers as the triangle slides."""

    name = "bad_float32_dda"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        from harness.geometry.exact import orientation

        sign = orientation(scene.positions)
        spans = []
        f32 = np.float32
        for t in np.flatnonzero(sign != 0):
            p = scene.positions[t]
            top, mid, bot = sorted(range(3), key=lambda v: (p[v, 1], p[v, 0]))
            long_left = orientation(np.array([[p[top], p[mid], p[bot]]]))[0] > 0
            edges = {}
            for a, b in ((top, bot), (top, mid), (mid, bot)):
                (xa, ya), (xb, yb) = p[a], p[b]
                if yb == ya:
                    continue
                first = math.ceil(ya - 0.5)
                slope = f32((xb - xa) / (yb - ya))
                x = f32(xa + (xb - xa) * (first + 0.5 - ya) / (yb - ya))
                column = {}
                for j in range(first, math.ceil(yb - 0.5)):
                    column[j] = float(x)
                    x = f32(x + slope)  # single-precision accumulation
                edges[(a, b)] = column
            for j in range(max(math.ceil(p[top, 1] - 0.5), 0), min(math.ceil(p[bot, 1] - 0.5), scene.height)):
                x_long = edges.get((top, bot), {}).get(j)
                x_short = edges.get((top, mid), {}).get(j, edges.get((mid, bot), {}).get(j))
                if x_long is None or x_short is None:
                    continue
                xl, xr = (x_long, x_short) if long_left else (x_short, x_long)
                a, b = max(math.ceil(xl - 0.5), 0), min(math.ceil(xr - 0.5), scene.width)
                if a < b:
                    spans.append((t, j, a, b))
        return coverage_from_spans(spans)
