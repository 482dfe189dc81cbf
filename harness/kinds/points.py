"""Points: D3D and GL point sprites, squares of a given size around each point.

A point of size ``s`` at ``(px, py)`` covers the samples inside the axis-aligned square
``[px - s/2, px + s/2] x [py - s/2, py + s/2]`` (OpenGL 4.6, 14.4 "Points": the square
"of side equal to the point size, centred at the point"; Direct3D 11 draws it as a quad of
two triangles). A sample on the square's boundary is decided by the convention's tie rule
exactly as for the quad's two triangles: the tie perturbation ``(tx, ty)`` moves it by
``(tx * eps, ty * eps)``, so the square owns its left side when ``tx > 0`` and its right
side when ``tx < 0``, its top side when ``ty > 0`` and its bottom side when ``ty < 0``
(x-first and y-first rules agree: the sides are axis-aligned). The centre is snapped by
the convention first; the size is not (it is a state of the draw, not a coordinate).
Every decision is exact (:mod:`harness.oracle.points`).

Size-1 points at the centres of a pixel grid, moved together by any offset, tile the plane:
every sample is covered exactly once -- the points' watertightness.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.scenes import MAX_VIEWPORT, _set_viewport, _vertex_array
from harness.kinds.base import JSON_NUMBER, JSON_POINT, PrimitiveKind

__all__ = ["PointScene", "POINTS"]


@dataclass(frozen=True, slots=True, eq=False)
class PointScene:
    """Points to draw into a ``width`` x ``height`` viewport, each a square of side
    ``point_size`` centred on it.

    The primitive is the point: coverage names point k (:attr:`Coverage.primitive`). A
    rasterizer takes point scenes when it lists ``"points"`` in its ``scene_kinds``.

    Parameters
    ----------
    width, height : int
        Viewport size in pixels, 1 .. 2**20.
    vertices : (N, 2) float64
        The points' centres. Non-finite values are allowed (bad-input cases); such a point
        covers nothing.
    point_size : float
        The squares' side in pixels, finite and positive (at most 2**20).

    Examples
    --------
    >>> scene = PointScene(4, 4, [[1.0, 1.0], [3.5, 2.5]], point_size=2.0)
    >>> len(scene), scene.kind, scene.noun
    (2, 'points', 'point')
    >>> lo, hi, finite = scene.primitive_boxes()
    >>> lo.tolist(), hi.tolist()
    ([[0.0, 0.0], [2.5, 1.5]], [[2.0, 2.0], [4.5, 3.5]])
    """

    width: int
    height: int
    vertices: NDArray[np.float64]
    point_size: float = 1.0
    kind: ClassVar[str] = "points"
    noun: ClassVar[str] = "point"
    # points carry no per-vertex values
    attributes: ClassVar[None] = None
    w: ClassVar[None] = None

    # the constructor takes array-likes (lists too), which __post_init__ makes arrays
    if TYPE_CHECKING:
        def __init__(self, width: int, height: int, vertices: ArrayLike, point_size: float = 1.0) -> None: ...

    def __post_init__(self) -> None:
        _set_viewport(self)
        object.__setattr__(self, "vertices", _vertex_array(self.vertices, "PointScene"))
        try:
            size = float(self.point_size)
        except (TypeError, ValueError):
            raise ValueError(f"PointScene.point_size must be a number, not {self.point_size!r}") from None
        if not (math.isfinite(size) and 0.0 < size <= MAX_VIEWPORT):
            raise ValueError(f"PointScene.point_size must be positive, finite and at most {MAX_VIEWPORT}, "
                             f"not {self.point_size!r}")
        object.__setattr__(self, "point_size", size)

    def __reduce__(self) -> tuple[type, tuple]:
        return PointScene, (self.width, self.height, self.vertices, self.point_size)

    def __len__(self) -> int:
        """N, the number of points."""
        return int(self.vertices.shape[0])

    @property
    def n_attributes(self) -> int:
        """0: points carry no attributes."""
        return 0

    def edges(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
        """Every side of every square ``a -> b`` ((4N, 2) each, clockwise on screen from the
        top left corner) and its point ((4N,) int64)."""
        half = 0.5 * self.point_size
        corners = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
        with np.errstate(invalid="ignore", over="ignore"):
            a = (self.vertices[:, None, :] + corners[None]).reshape(-1, 2)
            b = (self.vertices[:, None, :] + np.roll(corners, -1, axis=0)[None]).reshape(-1, 2)
        return a, b, np.repeat(np.arange(len(self), dtype=np.int64), 4)

    def primitive_boxes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """Per point its square ``lo, hi`` ((N, 2) each), and whether its centre is finite
        ((N,) bool)."""
        finite = np.asarray(np.isfinite(self.vertices).all(axis=1), dtype=np.bool_)
        half = 0.5 * self.point_size
        with np.errstate(invalid="ignore"):
            lo = np.where(finite[:, None], self.vertices - half, np.inf)
            hi = np.where(finite[:, None], self.vertices + half, -np.inf)
        return lo, hi, finite

    def non_finite(self) -> tuple[int, ...]:
        """Points with a NaN or infinite coordinate."""
        return tuple(int(k) for k in np.flatnonzero(~self.primitive_boxes()[2]))

    @property
    def coordinates(self) -> NDArray[np.float64]:
        """Every coordinate: ``vertices``, (N, 2)."""
        return self.vertices

    def with_coordinates(self, coordinates: ArrayLike) -> PointScene:
        """The same points' size with these (N, 2) centres."""
        return PointScene(self.width, self.height, np.asarray(coordinates, dtype=np.float64), self.point_size)

    def with_point_size(self, point_size: float) -> PointScene:
        """The same points at another size."""
        return PointScene(self.width, self.height, self.vertices, point_size)

    def with_viewport(self, width: int, height: int) -> PointScene:
        """The same points on a ``width`` x ``height`` viewport."""
        return PointScene(width, height, self.vertices, self.point_size)

    def subset(self, keep: ArrayLike) -> PointScene:
        """Points ``keep``, in that order (point k of the result is ``keep[k]``)."""
        index = np.asarray(keep, dtype=np.int64).reshape(-1)
        return PointScene(self.width, self.height, self.vertices[index].reshape(-1, 2), self.point_size)


# -- the kind: what the harness does differently for point scenes ----------------------------

# its case-file fields: the centres, and the squares' side
JSON_FIELDS = {"points": {"type": "array", "items": JSON_POINT}, "point_size": {"anyOf": [JSON_NUMBER]}}


def _coordinates_of(scene: PointScene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    return [scene.vertices[k][None, :] for k in prims]


POINTS: PrimitiveKind[PointScene] = PrimitiveKind(
    name="points", scene_class=PointScene, json_key="points", convention_attribute="point_convention",
    own_fit=None, translate_shift=(3, 2), translate_needs_positive=False, near_ties_by_own_rule=False,
    coordinates_of=_coordinates_of,
    degenerate=lambda scene, snapped: set(),  # a finite point's square always has its area
    work_size=len, keeps_shapes=lambda scene, moved: True, undefined=lambda scene, convention: "",
    exact_tie_words=("samples", "a side of their {noun}'s square"),
    case_word="point", may_overlap=True, json_fields=JSON_FIELDS, json_required=("points",),
    size_limits={"points": 1 << 20}, caption_words=lambda scene: f" of size {scene.point_size:g}",
    invariance_families=None,
    to_json="harness.contract.case:points_to_json", from_json="harness.contract.case:points_from_json",
    json_sizes="harness.contract.case:point_sizes",
    oracle="harness.oracle.points:point_coverage",
    near_ties="harness.checks.points:point_near_ties",
    invariance_variants="harness.checks.points:point_variants",
    probes="harness.identify.point_probes:fit_points",
    verdict_cases="harness.identify.point_probes:point_verdict_cases",
    still_pictures="harness.report.pictures:fill_pictures",
    repro_picture="harness.report.picture_repro:fill_repro",
    conformance_class="harness.diagnose.signatures:fill_conformance",
    hypotheses="harness.diagnose.facts:no_hypothesis",
    tie_trial="harness.diagnose.trials:no_trial",
    dropped_trial="harness.diagnose.trials:no_trial",
    vectors="harness.report.picture_points:point_vectors",
)
