"""Anti-aliased strokes from a 2D library, one segment at a time (issue 34): the
:class:`AlphaLines` mixin gives an area-coverage adapter line scenes, judged against the
exact stroke areas of :mod:`harness.oracle.area_lines` under its ``line_convention``
(``Convention(coverage="area", line=LineRule("rectangle", cap=...))``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from rasterizers.real._masks import segment_boxes

__all__ = ["AlphaLines", "draw_each_segment_alpha"]


def draw_each_segment_alpha(scene: LineScene, name: str,
                            draw: Callable[[NDArray[np.float64], NDArray[np.float64], int, int, tuple[int, int]],
                                           NDArray[np.float64]],
                            margin: int = 2) -> Coverage:
    """:func:`rasterizers.real._masks.draw_each_segment` for an anti-aliasing library:
    ``draw(a, b, box width, box height, origin)`` returns the box's (h, w) alphas in [0, 1];
    every pixel with a nonzero alpha keeps it (Coverage ``alpha``). The box is grown by
    ``margin`` px beyond half the line width (a square cap's corner reaches h sqrt(2)
    beyond its end point: :class:`AlphaLines` passes a margin that holds it).

    >>> def half(a, b, w, h, origin):
    ...     return np.full((h, w), 0.5)
    >>> cov = draw_each_segment_alpha(LineScene.from_strips(4, 2, [[[1, 1], [2, 1]]]), "half", half, margin=0)
    >>> cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist(), cov.alpha.tolist()
    ([0, 1], [0, 0], [3, 3], [0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
    """
    boxes, drawn = segment_boxes(scene, name, margin)
    a, b = scene.segments()
    box_list = boxes.tolist()
    segments, xs, ys, alphas = [], [], [], []
    for k in drawn.tolist():
        x0, y0, x1, y1 = box_list[k]
        origin = np.array([x0, y0], dtype=np.float64)
        try:
            alpha = np.asarray(draw(a[k] - origin, b[k] - origin, x1 - x0, y1 - y0, (x0, y0)), dtype=np.float64)
        except Exception as exc:  # name the segment the library failed on
            raise RuntimeError(f"{name}: the library failed on segment {k} {a[k].tolist()} -> {b[k].tolist()}: "
                               f"{type(exc).__name__}: {exc}") from exc
        y, x = np.nonzero(alpha > 0.0)
        if y.size:
            segments.append(np.full(y.size, k))
            xs.append(x + x0)
            ys.append(y + y0)
            alphas.append(alpha[y, x])
    if not segments:
        return Coverage.empty()
    return Coverage.from_pixels(np.concatenate(segments), np.concatenate(xs), np.concatenate(ys),
                                alpha=np.concatenate(alphas))


class AlphaLines:
    """Mixin for an area-coverage adapter whose library strokes anti-aliased segments
    (``_draw_stroke(a, b, line_width, w, h, origin)`` -> (h, w) alphas): line scenes are
    drawn one segment at a time (:func:`draw_each_segment_alpha`); every other scene goes
    to the next class (``super().rasterize``). Adds ``"lines"`` to the next class's
    ``scene_kinds`` and drops it from ``kinds_not_taken`` (set on each adapter class)."""

    scene_kinds: tuple[str, ...] = ("triangles", "lines")
    kinds_not_taken: dict[str, str] = {}  # noqa: RUF012  # replaced per adapter class (__init_subclass__)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        # the kinds of the class after this mixin in the adapter's MRO, with lines
        super().__init_subclass__(**kwargs)
        after = cls.__mro__[cls.__mro__.index(AlphaLines) + 1:]
        kinds: tuple[str, ...] = next((c.__dict__["scene_kinds"] for c in after if "scene_kinds" in c.__dict__), ("triangles",))
        not_taken: dict[str, str] = next((c.__dict__["kinds_not_taken"] for c in after if "kinds_not_taken" in c.__dict__), {})
        if "scene_kinds" not in cls.__dict__:
            cls.scene_kinds = kinds if "lines" in kinds else (*kinds, "lines")
        if "kinds_not_taken" not in cls.__dict__:
            cls.kinds_not_taken = {k: v for k, v in not_taken.items() if k != "lines"}

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int,
                     origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def rasterize(self, scene: Any) -> Coverage:
        if isinstance(scene, LineScene):
            width = scene.line_width
            margin = int(math.ceil(width * 0.25)) + 2  # h (sqrt(2) - 1) more for a square cap's corner
            name = str(getattr(self, "name", ""))
            return draw_each_segment_alpha(
                scene, name, lambda a, b, w, h, origin: self._draw_stroke(a, b, width, w, h, origin), margin)
        coverage: Coverage = super().rasterize(scene)  # type: ignore[misc]
        return coverage
