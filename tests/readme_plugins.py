"""Plugins written as a new user writes them from the README alone (issue 28): plain Python,
float arithmetic, nothing of the harness beyond its public contract.

- :class:`EvenOddScanline`: an even-odd scanline path filler. For each pixel row it
  intersects the sample row ``y + 0.5`` with every edge whose y range holds it (half-open,
  top inclusive), the crossing's x computed in floating point as textbooks do
  (``x0 + (y - y0) * (x1 - x0) / (y1 - y0)``), sorts the crossings and fills between pairs
  the pixels whose centre lies in ``[left, right)``. It declares pixel centres and top-left
  ties, which it follows exactly whenever the crossings are exact; a crossing rounded the
  other way of a pixel centre makes the two sides of a shared edge disagree (a hole or a
  double hit): what ``identify`` and ``run`` must both find on the same scenes.
- :class:`InclusiveSupersampler`: a 4 x 4 supersampled anti-aliased triangle rasterizer,
  alpha = the share of the grid's 16 samples covered, that declares top-left ties but
  makes every edge inclusive (``E >= 0`` on all three edges): a sample on an edge shared
  by two triangles counts for both (seams), and a sample an edge passes through counts
  where top-left leaves it out (accuracy, popping). ``identify`` must not call it
  consistent with what it declares.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene

__all__ = ["EvenOddScanline", "InclusiveSupersampler", "GRID_4X4"]

GRID_4X4 = tuple(((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4))


class EvenOddScanline:
    """An even-odd scanline path filler, as written from the README."""

    name = "user_evenodd_scanline"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")
    scene_kinds = ("paths",)
    fill_rules = ("evenodd",)
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        a, b, path = scene.edges()
        primitive: list[int] = []
        rows: list[int] = []
        starts: list[int] = []
        ends: list[int] = []
        for p in range(len(scene)):
            mine = path == p
            pa, pb = a[mine], b[mine]
            if not (np.isfinite(pa).all() and np.isfinite(pb).all()) or not len(pa):
                continue
            top = max(0, math.floor(min(pa[:, 1].min(), pb[:, 1].min())))
            bottom = min(scene.height, math.ceil(max(pa[:, 1].max(), pb[:, 1].max())) + 1)
            for y in range(top, bottom):
                sy = y + 0.5
                xs = []
                for (x0, y0), (x1, y1) in zip(pa.tolist(), pb.tolist()):
                    if y0 == y1 or not (min(y0, y1) <= sy < max(y0, y1)):
                        continue
                    xs.append(x0 + (sy - y0) * (x1 - x0) / (y1 - y0))
                xs.sort()
                for left, right in zip(xs[0::2], xs[1::2]):
                    x0i = max(0, math.ceil(left - 0.5))  # centre x + 0.5 >= left
                    x1i = min(scene.width, math.ceil(right - 0.5))  # centre x + 0.5 < right
                    if x1i > x0i:
                        primitive.append(p)
                        rows.append(y)
                        starts.append(x0i)
                        ends.append(x1i)
        return Coverage(np.array(primitive, dtype=np.int64), np.array(rows, dtype=np.int64),
                        np.array(starts, dtype=np.int64), np.array(ends, dtype=np.int64))


class InclusiveSupersampler:
    """4 x 4 supersampling, every edge inclusive, declared with top-left ties."""

    name = "user_inclusive_supersampler"
    convention = Convention(coverage="area", samples=GRID_4X4, tie="top-left", levels=17)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        offsets = np.array(GRID_4X4)
        triangle: list[NDArray[np.int64]] = []
        rows: list[NDArray[np.int64]] = []
        starts: list[NDArray[np.int64]] = []
        alphas: list[NDArray[np.float64]] = []
        for t, corners in enumerate(scene.positions):
            if not np.isfinite(corners).all():
                continue
            (ax, ay), (bx, by), (cx, cy) = corners.tolist()
            area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            if area == 0:
                continue
            sign = 1.0 if area > 0 else -1.0
            x_lo, x_hi = max(0, math.floor(corners[:, 0].min())), min(scene.width, math.ceil(corners[:, 0].max()) + 1)
            y_lo, y_hi = max(0, math.floor(corners[:, 1].min())), min(scene.height, math.ceil(corners[:, 1].max()) + 1)
            if x_hi <= x_lo or y_hi <= y_lo:
                continue
            y, x = np.mgrid[y_lo:y_hi, x_lo:x_hi]
            px = x[..., None] + offsets[:, 0]  # (rows, columns, 16) sample points
            py = y[..., None] + offsets[:, 1]
            inside = np.ones(px.shape, dtype=bool)
            for (x0, y0), (x1, y1) in (((ax, ay), (bx, by)), ((bx, by), (cx, cy)), ((cx, cy), (ax, ay))):
                inside &= sign * ((x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)) >= 0  # every edge inclusive
            count = inside.sum(axis=-1)
            hit = count > 0
            triangle.append(np.full(int(hit.sum()), t, dtype=np.int64))
            rows.append(y[hit].astype(np.int64))
            starts.append(x[hit].astype(np.int64))
            alphas.append(count[hit] / len(offsets))
        if not triangle:
            none = np.zeros(0, dtype=np.int64)
            return Coverage(none, none, none, none, alpha=np.zeros(0))
        xs = np.concatenate(starts)
        return Coverage(np.concatenate(triangle), np.concatenate(rows), xs, xs + 1, alpha=np.concatenate(alphas))
