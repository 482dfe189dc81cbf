"""Known-bad rasterizers of the coverage rules (issue 33): each breaks its declared rule
where the rule is decided exactly (a threshold met exactly, a square touching an edge)."""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.oracle.area import pixel_areas
from tests.known_bad import coverage_from_parts

__all__ = ["StrictThreshold", "BoxOverestimate", "OpenUnderestimate"]


class StrictThreshold:
    """Declares an area threshold of 1/2 (a pixel covered exactly half is drawn) but tests
    the float area with ``>``: every pixel a triangle covers exactly half is missing."""

    name = "bad_strict_threshold"
    convention = Convention(coverage="area-threshold")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        t, x, y, area = pixel_areas(scene.positions, scene.width, scene.height)
        keep = area > 0.5
        return coverage_from_parts([t[keep]], [x[keep]], [y[keep]])


class BoxOverestimate:
    """Declares conservative overestimate but draws every pixel of the triangle's bounding
    box: the corners beyond a slanted edge are extra."""

    name = "bad_box_overestimate"
    convention = Convention(coverage="conservative-over")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        tris, xs, ys = [], [], []
        for k, p in enumerate(scene.positions):
            if not np.all(np.isfinite(p)) or orientation(p[None])[0] == 0:
                continue
            i0, i1 = max(int(np.ceil(p[:, 0].min())) - 1, 0), min(int(np.floor(p[:, 0].max())), scene.width - 1)
            j0, j1 = max(int(np.ceil(p[:, 1].min())) - 1, 0), min(int(np.floor(p[:, 1].max())), scene.height - 1)
            if i0 > i1 or j0 > j1:
                continue
            yy, xx = np.mgrid[j0:j1 + 1, i0:i1 + 1]
            tris.append(np.full(xx.size, k))
            xs.append(xx.ravel())
            ys.append(yy.ravel())
        return coverage_from_parts(tris, xs, ys)


class OpenUnderestimate:
    """Declares conservative underestimate (a square with a side on an edge is inside) but
    asks for corners strictly inside: squares along axis-aligned edges are missing."""

    name = "bad_open_underestimate"
    convention = Convention(coverage="conservative-under")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        tris, xs, ys = [], [], []
        for k, p in enumerate(scene.positions):
            s = orientation(p[None])[0]
            if not np.all(np.isfinite(p)) or s == 0:
                continue
            yy, xx = np.mgrid[0:scene.height, 0:scene.width]
            inside = np.ones(xx.shape, dtype=bool)
            for dx in (0, 1):
                for dy in (0, 1):
                    cx, cy = xx + dx, yy + dy
                    for e in range(3):
                        (ax, ay), (bx, by) = p[e], p[(e + 1) % 3]
                        inside &= s * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) > 0
            tris.append(np.full(int(inside.sum()), k))
            xs.append(xx[inside])
            ys.append(yy[inside])
        return coverage_from_parts(tris, xs, ys)
