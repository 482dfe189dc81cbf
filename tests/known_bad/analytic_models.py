"""Known-bad analytic anti-aliasers (issue 34): each declares a library's levels of the exact
area (``Convention(coverage="area", quantisation=...)``, :mod:`harness.contract.quantisations`)
and breaks them the way a port of the library's arithmetic could."""

from __future__ import annotations

import math

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.area import area_coverage

__all__ = ["RoundsWhereFreeTypeFloors", "ComplementsWhereQtNegates", "FloorsWhereBlend2DScales"]


def _answer(scene: Scene, convention: Convention, level: object) -> Coverage:
    """The exact area of the received triangles, each pixel's level made by ``level(area,
    clockwise)``, as alphas."""
    plain = area_coverage(scene, convention)
    assert plain.alpha is not None
    t, _, _ = plain.pixels()
    a = convention.snap(scene.positions)
    clockwise = ((a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1]) > (a[:, 1, 1] - a[:, 0, 1]) * (a[:, 2, 0] - a[:, 0, 0]))
    levels = np.array([level(float(area), bool(clockwise[k])) for area, k in zip(plain.alpha, t)], dtype=np.float64)  # type: ignore[operator]
    return Coverage(plain.primitive, plain.y, plain.x0, plain.x1, alpha=levels / 255.0)


class RoundsWhereFreeTypeFloors:
    """Declares FreeType's levels (``ftgrays``: ``floor(256 S)``) on its 26.6 input; rounds
    the area to the nearest of 256 levels instead (``round(255 a)``): a level off wherever
    the fractions part."""

    name = "bad_rounds_where_freetype_floors"
    convention = Convention(coverage="area", quantisation="ftgrays", input="fixed6")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return _answer(scene, self.convention, lambda area, clockwise: round(255 * area))


class ComplementsWhereQtNegates:
    """Declares Qt's levels (``cells-abs``: ``|floor(256 S)|``); takes a negative k's
    complement as newer ftgrays does (``~k``): one level low on every partly covered pixel
    of a clockwise triangle (which Qt accumulates negative)."""

    name = "bad_complements_where_qt_negates"
    convention = Convention(coverage="area", quantisation="cells-abs", input="fixed6")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        def level(area: float, clockwise: bool) -> int:
            k = math.floor(256 * area * (-1 if clockwise else 1))
            return min(~k if k < 0 else k, 255)

        return _answer(scene, self.convention, level)


class FloorsWhereBlend2DScales:
    """Declares Blend2D's levels (``min(|k|, 256) * 255 >> 8``); leaves out the global
    alpha's scaling (``min(|k|, 255)``): one level high on most partly covered pixels."""

    name = "bad_floors_where_blend2d_scales"
    convention = Convention(coverage="area", quantisation="blend2d", input="fixed8-toward-zero")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        def level(area: float, clockwise: bool) -> int:
            k = math.floor(256 * area * (-1 if clockwise else 1))
            return min(abs(k), 255)

        return _answer(scene, self.convention, level)
