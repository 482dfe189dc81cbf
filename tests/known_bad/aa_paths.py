"""Known-bad anti-aliased path fillers (issue 34): each computes an area coverage of paths
with one classic mistake, and the accuracy check must catch it on path scenes.

* :class:`SignedAreaPathFiller`: the font renderers' accumulation (font-rs, stb_truetype's
  v2 rasterizer): per pixel the signed integral of the winding number, |.| clamped to 1.
  Right where the winding is 0 or +/-1 everywhere (a glyph of non-overlapping contours);
  wrong where contours overlap (a pixel half at winding 2 reads 1) and under even-odd.
* :class:`EvenOddForNonzeroArea`: draws the even-odd area whatever rule is asked.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.oracle.area import pixel_areas
from harness.oracle.path_area import path_area_coverage

__all__ = ["SignedAreaPathFiller", "EvenOddForNonzeroArea", "ExactAreaPathFiller"]


def _eight_bit(alpha: np.ndarray) -> np.ndarray:
    rounded: np.ndarray = np.rint(np.clip(alpha, 0.0, 1.0) * 255.0) / 255.0
    return rounded


class SignedAreaPathFiller:
    """|signed winding integral| per pixel, clamped to [0, 1], on 256 levels: each contour
    fanned from its first vertex into triangles whose areas inside the pixel are added with
    the sign of their orientation (Green's theorem: the integral of w over the pixel)."""

    name = "bad_signed_area_path_filler"
    convention = Convention(coverage="area")
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        width, height = scene.width, scene.height
        ends = np.cumsum(scene.contour_sizes)
        fans, owner = [], []
        for c, size in enumerate(scene.contour_sizes):
            v = scene.vertices[ends[c] - size:ends[c]]
            for k in range(1, size - 1):
                fans.append([v[0], v[k], v[k + 1]])
                owner.append(scene.contour_path[c])
        total = np.zeros((len(scene), height, width))
        if fans:
            tris = np.array(fans, dtype=np.float64)
            tris[~np.all(np.isfinite(tris), axis=(1, 2))] = 0.0  # a non-finite path draws nothing here
            sign = np.sign((tris[:, 1, 0] - tris[:, 0, 0]) * (tris[:, 2, 1] - tris[:, 0, 1])
                           - (tris[:, 1, 1] - tris[:, 0, 1]) * (tris[:, 2, 0] - tris[:, 0, 0]))
            t, x, y, area = pixel_areas(tris, width, height)
            np.add.at(total, (np.asarray(owner)[t], y, x), sign[t] * area)
        alpha = _eight_bit(np.abs(total))
        p, y, x = np.nonzero(alpha)
        return Coverage(p, y, x, x + 1, alpha=alpha[p, y, x])


class EvenOddForNonzeroArea:
    """The exact area, 256 levels, but of the even-odd rule whatever the scene asks."""

    name = "bad_evenodd_for_nonzero_area"
    convention = Convention(coverage="area")
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        cov = path_area_coverage(scene.with_fill_rule("evenodd"), self.convention)
        assert cov.alpha is not None
        return Coverage(cov.primitive, cov.y, cov.x0, cov.x1, alpha=_eight_bit(cov.alpha))


class ExactAreaPathFiller:
    """The control (not bad): the exact area of paths and triangles, rounded to 256 levels;
    every area check must pass it."""

    name = "exact_area_path_filler"
    convention = Convention(coverage="area")
    scene_kinds = ("triangles", "paths")
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: Any) -> Coverage:
        from harness.oracle.coverage import exact_coverage

        geometry = scene if isinstance(scene, PathScene) else Scene(scene.width, scene.height, scene.positions)
        cov = exact_coverage(geometry, self.convention)
        assert cov.alpha is not None
        return Coverage(cov.primitive, cov.y, cov.x0, cov.x1, alpha=_eight_bit(cov.alpha))
