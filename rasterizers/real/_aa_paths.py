"""Anti-aliased path fills from a 2D library, one whole path at a time (issue 34): the
:class:`AlphaPaths` mixin gives an area-coverage adapter path scenes, each path filled in
one call under the scene's fill rule with the library's own path fill, judged against the
exact area where the rule holds (:mod:`harness.oracle.path_area`, the accuracy check
:mod:`harness.checks.area_paths`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Unsupported
from rasterizers.real._masks import path_boxes

__all__ = ["AlphaPaths", "draw_each_path_alpha"]


def draw_each_path_alpha(scene: PathScene, name: str,
                         draw: Callable[[list[NDArray[np.float64]], int, int, tuple[int, int]], NDArray[np.float64]],
                         margin: int = 2) -> Coverage:
    """:func:`rasterizers.real._masks.draw_each_path` for an anti-aliasing library:
    ``draw(contours relative to the box origin, box width, box height, origin)`` is called
    once per path, every contour of the path in that one call (the library fills them
    together under the scene's fill rule), and returns the box's (h, w) alphas in [0, 1];
    every pixel with a nonzero alpha keeps it (Coverage ``alpha``), in screen coordinates.

    The boxes are :func:`~rasterizers.real._masks.path_boxes`' (the path's bounding box
    over all its contours widened by ``margin`` px and clipped to the viewport; the whole
    screen for a path with a NaN or infinite vertex, handed over unchanged; ValueError
    naming a path beyond :data:`~rasterizers.real._masks.LIMIT`); the origin is a whole
    pixel, so shifting by it is exact. A library failure is raised as RuntimeError naming
    the path.

    Examples
    --------
    >>> def half(contours, w, h, origin):  # a "library" that gives every box pixel alpha 0.5
    ...     return np.full((h, w), 0.5)
    >>> scene = PathScene.from_paths(6, 3, [[[[1, 0], [2, 0], [2, 1]], [[3, 0], [3, 1], [4, 1]]]])
    >>> cov = draw_each_path_alpha(scene, "half", half, margin=0)
    >>> cov.primitive.tolist(), cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist(), cov.alpha.tolist()
    ([0], [0], [1], [4], [0.5, 0.5, 0.5])
    """
    parts = []
    for k, contours, x0, y0, x1, y1 in path_boxes(scene, name, margin):
        origin = np.array([x0, y0], dtype=np.float64)
        try:
            alpha = np.asarray(draw([c - origin for c in contours], x1 - x0, y1 - y0, (x0, y0)), dtype=np.float64)
        except Exception as exc:  # name the path the library failed on
            raise RuntimeError(f"{name}: the library failed on path {k} ({len(contours)} contours, "
                               f"{sum(c.shape[0] for c in contours)} vertices): {type(exc).__name__}: {exc}") from exc
        covered = alpha > 0.0
        if covered.any():
            cov = Coverage.from_mask(k, covered, alpha=alpha)
            parts.append(Coverage(cov.primitive, cov.y + y0, cov.x0 + x0, cov.x1 + x0, alpha=cov.alpha))
    return Coverage.concat(parts) if parts else Coverage.empty()


def _kinds_after(cls: type, attribute: str, default: Any) -> Any:
    """``attribute`` as the classes after :class:`AlphaPaths` in ``cls``'s MRO give it, or as
    a mixin after it (:class:`~rasterizers.real._aa_lines.AlphaLines`) has just set it on
    ``cls`` itself."""
    if attribute in cls.__dict__:
        return cls.__dict__[attribute]
    after = cls.__mro__[cls.__mro__.index(AlphaPaths) + 1:]
    return next((c.__dict__[attribute] for c in after if attribute in c.__dict__), default)


class AlphaPaths:
    """Mixin for an area-coverage adapter whose library fills anti-aliased paths
    (``_fill_path(contours, fill_rule, w, h, origin)`` -> (h, w) alphas in [0, 1]): path
    scenes are drawn one path at a time, all its contours in one fill under the scene's
    fill rule (:func:`draw_each_path_alpha`); a rule not in :attr:`fill_rules` is refused
    (Unsupported; the runner hands the adapter none: :func:`harness.contract.protocol.takes`);
    every other scene goes to the next class (``super().rasterize``).

    Adds ``"paths"`` to the next classes' ``scene_kinds`` and drops it from their
    ``kinds_not_taken`` (on each adapter class, unless the class sets them itself). Put
    it first among the mixins, before :class:`~rasterizers.real._aa_lines.AlphaLines`
    (``class X(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime)``): AlphaLines sets the
    class's kinds only when nothing has, so after it this mixin adds to what it set."""

    scene_kinds: tuple[str, ...] = ("triangles", "paths")
    kinds_not_taken: dict[str, str] = {}  # noqa: RUF012  # replaced per adapter class (__init_subclass__)
    # the fill rules the library honours; an adapter whose library cannot honour one leaves it out (and says why)
    fill_rules: tuple[str, ...] = ("nonzero", "evenodd")

    def __init_subclass__(cls, **kwargs: Any) -> None:
        own = {attribute for attribute in ("scene_kinds", "kinds_not_taken") if attribute in cls.__dict__}
        super().__init_subclass__(**kwargs)  # AlphaLines, when it follows, sets the class's kinds first
        if "scene_kinds" not in own:
            kinds: tuple[str, ...] = _kinds_after(cls, "scene_kinds", ("triangles",))
            cls.scene_kinds = kinds if "paths" in kinds else (*kinds, "paths")
        if "kinds_not_taken" not in own:
            not_taken: dict[str, str] = _kinds_after(cls, "kinds_not_taken", {})
            cls.kinds_not_taken = {k: v for k, v in not_taken.items() if k != "paths"}

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def rasterize(self, scene: Any) -> Coverage:
        if isinstance(scene, PathScene):
            name = str(getattr(self, "name", ""))
            rule = scene.fill_rule
            if rule not in self.fill_rules:
                raise Unsupported(f"{name}: fills {' and '.join(self.fill_rules)} only, not {rule!r}")
            return draw_each_path_alpha(scene, name, lambda contours, w, h, origin: self._fill_path(contours, rule, w, h, origin))
        coverage: Coverage = super().rasterize(scene)  # type: ignore[misc]
        return coverage
