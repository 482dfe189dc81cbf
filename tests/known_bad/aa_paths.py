"""Known-bad anti-aliased path fillers (issue 34): each computes an area coverage of paths
with one classic mistake, and the accuracy check must catch it on path scenes.

* :class:`SignedAreaPathFiller`: the font renderers' accumulation (font-rs, stb_truetype's
  v2 rasterizer): per pixel the signed integral of the winding number, |.| clamped to 1.
  Right where the winding is 0 or +/-1 everywhere (a glyph of non-overlapping contours);
  wrong where contours overlap (a pixel half at winding 2 reads 1) and under even-odd.
* :class:`EvenOddForNonzeroArea`: draws the even-odd area whatever rule is asked.
* :class:`QuarterPixelPathFiller`: the exact area of the path snapped (floored) to a 1/4 px
  grid, while claiming float input: under sub-pixel motion its alphas stand still, then
  jump by up to a quarter of a pixel's edge length -- popping catches it (beyond even what
  the motion allows any area: the jump is its own, not a model's).
* :class:`OrientationRoundedFiller`: the exact area, floored to a level where the path
  winds one way and ceiled where it winds the other (AGG's ``calculate_alpha``,
  ``agg_rasterizer_scanline_aa.h``: ``cover = area >> shift`` is an arithmetic shift, a
  floor of the signed area, then ``if (cover < 0) cover = -cover``: a ceiling of the
  magnitude for the negative winding). It declares a tolerance of one level, which both
  roundings keep (accuracy passes); reversing the contours changes every partial alpha by
  one level, which invariance must catch exactly.
* :class:`BiasedPartialFiller`: the exact area rounded, then one level more on every
  partially covered pixel: pieces of a planar partition drawn as separate paths sum to 1
  plus a level per piece -- seams catch it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.oracle.area import pixel_areas
from harness.oracle.path_area import path_area_coverage

__all__ = ["SignedAreaPathFiller", "EvenOddForNonzeroArea", "ExactAreaPathFiller", "QuarterPixelPathFiller",
           "OrientationRoundedFiller", "BiasedPartialFiller", "AA_PATH_BADS"]


def _eight_bit(alpha: np.ndarray) -> np.ndarray:
    rounded: np.ndarray = np.rint(np.clip(alpha, 0.0, 1.0) * 255.0) / 255.0
    return rounded


def _signed_integral(scene: PathScene) -> np.ndarray:
    """(paths, H, W): the signed integral of the winding number over each pixel, each contour
    fanned from its first vertex into triangles whose areas inside the pixel are added with
    the sign of their orientation (Green's theorem)."""
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
    return total


def _exact(scene: PathScene) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(path, x, y, area) of the exact area where the fill rule holds, one entry a pixel."""
    cov = path_area_coverage(scene, Convention(coverage="area"))
    assert cov.alpha is not None
    p, x, y = cov.pixels()
    return p, x, y, cov.alpha


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
        total = _signed_integral(scene)
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


class QuarterPixelPathFiller:
    """Claims the exact area on float input; floors every vertex to the 1/4 px grid first."""

    name = "bad_quarter_pixel_path_filler"
    convention = Convention(coverage="area")
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        snapped = scene.with_coordinates(np.floor(scene.vertices * 4.0) / 4.0)
        p, x, y, area = _exact(snapped)
        alpha = _eight_bit(area)
        keep = alpha > 0
        return Coverage.from_pixels(p[keep], x[keep], y[keep], alpha=alpha[keep])


class OrientationRoundedFiller:
    """The exact area on 256 levels, floored where the signed winding integral over the
    pixel is positive (the path winds clockwise there, y down) and ceiled where it is
    negative, as AGG's arithmetic shift does; declares a tolerance of one level."""

    name = "bad_orientation_rounded_filler"
    convention = Convention(coverage="area", tolerance=1 / 255)
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        p, x, y, area = _exact(scene)
        signed = _signed_integral(scene)[p, y, x] if p.size else np.zeros(0)
        scaled = np.clip(area, 0.0, 1.0) * 255.0
        level = np.where(signed < 0, np.ceil(scaled), np.floor(scaled))
        keep = level > 0
        return Coverage.from_pixels(p[keep], x[keep], y[keep], alpha=level[keep] / 255.0)


class BiasedPartialFiller:
    """The exact area on 256 levels, one level more on every partially covered pixel."""

    name = "bad_biased_partial_filler"
    convention = Convention(coverage="area")
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        p, x, y, area = _exact(scene)
        level = np.rint(np.clip(area, 0.0, 1.0) * 255.0)
        level = np.where((area > 0) & (area < 1), np.minimum(level + 1, 255.0), level)
        keep = level > 0
        return Coverage.from_pixels(p[keep], x[keep], y[keep], alpha=level[keep] / 255.0)


AA_PATH_BADS = (SignedAreaPathFiller(), EvenOddForNonzeroArea(), QuarterPixelPathFiller(), OrientationRoundedFiller(),
                BiasedPartialFiller())
