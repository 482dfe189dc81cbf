"""What every library adapter shares: importing the library (:func:`need`), refusing a
scene kind it does not take (:func:`refuse_kind`), and the two ways of driving a 2D library
one primitive at a time: :class:`OneAtATime` (a bool mask per triangle, path or segment)
and :class:`AlphaOneTriangleAtATime` (8-bit alphas per triangle).

Each adapter also says which library it drives, for the atlas: ``library`` (its name, the
same for every mode of one library) and ``library_version`` (set when it is made), and
the kind of coverage it returns, ``coverage_kind`` (``single``, ``multisample`` or
``area``: :data:`harness.contract.coverage_models.CoverageKind`)."""

from __future__ import annotations

from typing import Any, NoReturn

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene, Unsupported
from harness.engine.optional import missing
from harness.engine.registry import Unavailable
from rasterizers.real._masks import draw_each, draw_each_alpha, draw_each_path, draw_each_segment

__all__ = ["need", "refuse_kind", "refuse_several_contours", "OneAtATime", "AlphaOneTriangleAtATime"]


def need(module: str) -> Any:
    """The module, imported; :class:`Unavailable` naming the install when it is missing."""
    why = missing(module)
    if why is not None:
        raise Unavailable(why)
    return __import__(module)


def refuse_kind(name: str, scene: object, kinds: tuple[str, ...]) -> NoReturn:
    """Raise ValueError for a scene of a kind the rasterizer does not take."""
    raise ValueError(f"{name}: takes {', '.join(kinds)} scenes, not {type(scene).__name__}")


def refuse_several_contours(name: str, scene: PathScene, call: str) -> None:
    """Raise Unsupported naming the first path of several contours, for a library whose
    ``call`` fills one contour per call: two calls would OR the contours, which is no
    fill rule."""
    several = np.flatnonzero(np.bincount(scene.contour_path, minlength=len(scene)) > 1)
    if several.size:
        k = int(several[0])
        raise Unsupported(f"{name}: path {k} has {int(np.sum(scene.contour_path == k))} contours; "
                          f"{call} fills one contour per call")


class OneAtATime:
    """A 2D library drawing one triangle, one whole path (all its contours in one fill,
    under the scene's fill rule) or one line segment at a time into a mask (``_draw``,
    ``_draw_path``, ``_draw_segment``): coverage only, no declared convention.

    Line scenes: each segment in its own call into an image around its box
    (:func:`~rasterizers.real._masks.draw_each_segment`), so a pixel two segments of a
    polyline draw is seen twice; a segment with a NaN or infinite end point covers
    nothing (the library is not asked); one with a coordinate beyond
    :data:`~rasterizers.real._masks.LIMIT` is refused (ValueError naming it). Libraries
    that draw hairlines only (:attr:`line_widths` ``(1.0,)``) raise Unsupported for any
    other ``line_width``."""

    name = ""
    library = ""  # the library driven, the same for each of its modes (the atlas's row)
    library_version = ""  # set when the adapter is made
    coverage_kind = "single"
    convention: Convention | None = None
    interpolates = False  # coverage only: the library draws no varyings
    scene_kinds: tuple[str, ...] = ("triangles", "paths", "lines")
    fill_rules: tuple[str, ...] = ("nonzero", "evenodd")
    # the line widths the library draws; None: any
    line_widths: tuple[float, ...] | None = (1.0,)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        raise NotImplementedError

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def _refuse_lines(self, scene: LineScene) -> None:
        """Raise Unsupported for a line width the library does not draw."""
        if self.line_widths is not None and scene.line_width not in self.line_widths:
            raise Unsupported(f"{self.name}: draws hairlines (one pixel wide) only, not lines {scene.line_width:g} px wide")

    def _refuse(self, scene: PathScene) -> None:
        """Raise Unsupported for a path scene the library cannot fill (by default, a fill
        rule it does not honour)."""
        if scene.fill_rule not in self.fill_rules:
            raise Unsupported(f"{self.name}: fills {' and '.join(self.fill_rules)} only, not {scene.fill_rule!r}")

    def rasterize(self, scene: AnyScene) -> Coverage:
        if isinstance(scene, LineScene):
            self._refuse_lines(scene)
            width = scene.line_width
            return draw_each_segment(scene, self.name, lambda a, b, w, h, origin: self._draw_segment(a, b, width, w, h, origin))
        if isinstance(scene, PathScene):
            self._refuse(scene)
            rule = scene.fill_rule
            return draw_each_path(scene, self.name, lambda contours, w, h, origin: self._draw_path(contours, rule, w, h))
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        return draw_each(scene, self.name, self._draw)


class AlphaOneTriangleAtATime:
    """An anti-aliasing 2D library drawing one triangle at a time into an 8-bit alpha
    image (``_draw``): area coverage, alpha = pixel value / 255 per (triangle, pixel)."""

    name = ""
    library = ""
    library_version = ""
    coverage_kind = "area"
    # what the atlas says of the kinds it is not handed
    # (an adapter whose library fills paths or strokes lines mixes in AlphaPaths / AlphaLines,
    # which drop these)
    kinds_not_taken = {"paths": "not adapted: this adapter draws one triangle at a time, no paths",
                       "lines": "not adapted: this adapter draws one triangle at a time, no lines"}
    convention: Convention | None = None
    interpolates = False  # coverage only: the library draws no varyings

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def rasterize(self, scene: Scene) -> Coverage:
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, ("triangles",))
        return draw_each_alpha(scene, self.name, self._draw)


