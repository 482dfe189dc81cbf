"""The contract every rasterizer implements: Scene in, Coverage out.

A rasterizer is any object with ``name``, ``convention`` and ``rasterize(scene)`` (see
:class:`Rasterizer`); there is no base class to inherit. Screen space, conventions and
tie rules are defined in :mod:`harness.conventions`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.conventions import FILL_RULES, Convention
from harness.exact import frozen
from harness.keys import composite, lexsort
from harness.spans import already_tidy, expand, pixel_offsets, run_tails, span_buffers, tidy

__all__ = ["Scene", "PathScene", "LineScene", "AnyScene", "SCENE_KINDS", "Coverage", "Convention", "Rasterizer", "span_buffers", "interpolates_of", "received_of", "fingerprint_of",
           "scene_kinds_of", "fill_rules_of", "takes", "convention_for", "Unsupported"]

# Sample points i + sx must be exact floats (sx has up to 32 fractional bits).
MAX_VIEWPORT = 1 << 20


def _real_array(value: ArrayLike, field: str, owner: str) -> NDArray[np.float64]:
    array = np.asarray(value)
    if array.dtype.kind not in "biuf":
        raise ValueError(f"{owner}.{field} must hold real numbers, not dtype {array.dtype}")
    if array.dtype.kind in "iu" and bool(np.any(array > 2**53) or np.any(array < -(2**53))):
        # float64 holds every integer up to 2**53 exactly and rounds past it: refuse rather
        # than test a scene other than the one given
        raise ValueError(f"{owner}.{field} holds integers beyond 2**53, which float64 cannot hold exactly; "
                         "give them as floats if the rounding is meant")
    array = np.array(array, dtype=np.float64, copy=True, order="C")
    array.setflags(write=False)
    return array


def _set_viewport(scene: Any) -> None:
    """Check and set a scene's ``width`` and ``height`` (integers in 1 .. MAX_VIEWPORT)."""
    owner = type(scene).__name__
    for field in ("width", "height"):
        value = getattr(scene, field)
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"{owner}.{field} must be an integer, not {value!r}")
        if not 1 <= value <= MAX_VIEWPORT:
            raise ValueError(f"{owner}.{field} must lie in 1..{MAX_VIEWPORT}, not {value}")
        object.__setattr__(scene, field, int(value))


def _vertex_array(value: ArrayLike, owner: str) -> NDArray[np.float64]:
    """A scene's (V, 2) vertices, checked (an empty one reshaped to (0, 2))."""
    vertices = _real_array(value, "vertices", owner)
    if vertices.size == 0:
        vertices = vertices.reshape(0, 2)
    if vertices.ndim != 2 or vertices.shape[1] != 2:
        raise ValueError(f"{owner}.vertices must have shape (V, 2), not {vertices.shape}")
    return vertices


@dataclass(frozen=True, slots=True, eq=False)
class Scene:
    """Triangles to rasterize into a ``width`` x ``height`` viewport.

    Parameters
    ----------
    width, height : int
        Viewport size in pixels, 1 .. 2**20.
    positions : (N, 3, 2) float64
        Vertex positions in pixels, x right, y down. Non-finite values are allowed: they
        let bad-input cases be expressed; such triangles cover nothing in the oracle.
    attributes : (N, 3, K) float64 or None
        Per-vertex values to interpolate at each covered pixel.
    w : (N, 3) float64 or None
        Clip-space w of each vertex for perspective-correct interpolation; None means
        screen-linear. Finite values must be positive (clip before projecting).

    Examples
    --------
    >>> scene = Scene(4, 3, [[[0, 0], [4, 0], [0, 3]]])
    >>> scene.positions.shape, scene.positions.dtype, len(scene)
    ((1, 3, 2), dtype('float64'), 1)
    >>> Scene(4, 3, [[0, 0], [4, 0], [0, 3]])
    Traceback (most recent call last):
    ...
    ValueError: Scene.positions must have shape (N, 3, 2), not (3, 2)
    """

    width: int
    height: int
    positions: NDArray[np.float64]
    attributes: NDArray[np.float64] | None = None
    w: NDArray[np.float64] | None = None
    kind: ClassVar[str] = "triangles"
    noun: ClassVar[str] = "triangle"  # what a primitive is called in messages and evidence

    def __post_init__(self) -> None:
        _set_viewport(self)
        positions = _real_array(self.positions, "positions", "Scene")
        if positions.ndim != 3 or positions.shape[1:] != (3, 2):
            raise ValueError(f"Scene.positions must have shape (N, 3, 2), not {positions.shape}")
        object.__setattr__(self, "positions", positions)
        n = positions.shape[0]
        if self.attributes is not None:
            attributes = _real_array(self.attributes, "attributes", "Scene")
            if attributes.ndim != 3 or attributes.shape[:2] != (n, 3):
                raise ValueError(
                    f"Scene.attributes must have shape ({n}, 3, K), not {attributes.shape}"
                )
            object.__setattr__(self, "attributes", attributes)
        if self.w is not None:
            w = _real_array(self.w, "w", "Scene")
            if w.shape != (n, 3):
                raise ValueError(f"Scene.w must have shape ({n}, 3), not {w.shape}")
            bad = np.isfinite(w) & (w <= 0.0)
            if bad.any():
                t = int(np.flatnonzero(bad.any(axis=1))[0])
                raise ValueError(
                    f"Scene.w must be positive (clip against the near plane first): "
                    f"triangle {t} has w = {w[t].tolist()}"
                )
            object.__setattr__(self, "w", w)

    def __reduce__(self) -> tuple[type, tuple]:  # type: ignore[type-arg]
        # through the constructor: an unpickled scene (a worker's) is checked and frozen as
        # the original was, so kernels see one array type (see harness.exact.frozen)
        return Scene, (self.width, self.height, self.positions, self.attributes, self.w)

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    @property
    def n_attributes(self) -> int:
        """K, the number of interpolated values per vertex (0 without attributes)."""
        return 0 if self.attributes is None else int(self.attributes.shape[2])

    def primitive_boxes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """Per triangle its bounding box ``lo, hi`` ((N, 2) each) and whether all its
        coordinates are finite ((N,) bool; the box is meaningless where not)."""
        p = np.where(np.isfinite(self.positions), self.positions, 0.0)
        finite: NDArray[np.bool_] = np.asarray(np.isfinite(self.positions).all(axis=(1, 2)))
        return p.min(axis=1), p.max(axis=1), finite

    def non_finite(self) -> tuple[int, ...]:
        """Triangles with a NaN or infinite coordinate."""
        return tuple(int(t) for t in np.flatnonzero(~np.isfinite(self.positions).all(axis=(1, 2))))

    # The operations every scene kind has, so that shrinking, moving and drawing a scene
    # need not ask which kind it is.
    def edges(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
        """Every edge ``a -> b`` ((3N, 2) each: v0 -> v1, v1 -> v2, v2 -> v0 of each
        triangle) and its triangle ((3N,) int64)."""
        return (self.positions.reshape(-1, 2), self.positions[:, [1, 2, 0]].reshape(-1, 2),
                np.repeat(np.arange(len(self), dtype=np.int64), 3))

    @property
    def coordinates(self) -> NDArray[np.float64]:
        """Every vertex coordinate: ``positions``, (N, 3, 2)."""
        return self.positions

    def with_coordinates(self, coordinates: ArrayLike) -> Scene:
        """The same triangles (attributes, w) with these (N, 3, 2) positions."""
        return Scene(self.width, self.height, np.asarray(coordinates, dtype=np.float64), self.attributes, self.w)

    def subset(self, keep: ArrayLike) -> Scene:
        """Triangles ``keep``, in that order (triangle k of the result is ``keep[k]``)."""
        index = np.asarray(keep, dtype=np.int64)
        return Scene(self.width, self.height, self.positions[index], None if self.attributes is None else self.attributes[index],
                     None if self.w is None else self.w[index])


@dataclass(frozen=True, slots=True, eq=False)
class PathScene:
    """Paths to fill into a ``width`` x ``height`` viewport under one fill rule.

    A path is one or more closed contours (the last vertex joins the first); sample
    ``p`` is covered by path k when the winding number of ``p`` around path k's contours
    satisfies the fill rule (``nonzero``: w != 0; ``evenodd``: w odd), samples exactly on
    an edge or a vertex being decided by the convention's tie rule as for triangles
    (:mod:`harness.winding`). Paths are filled independently, each in one call of a 2D
    library, so coverage names the path (:attr:`Coverage.primitive`). A rasterizer takes
    path scenes when it lists ``"paths"`` in its ``scene_kinds`` (:func:`scene_kinds_of`).

    Parameters
    ----------
    width, height : int
        Viewport size in pixels, 1 .. 2**20.
    vertices : (V, 2) float64
        Every contour's vertices, one contour after the other. Non-finite values are
        allowed (bad-input cases); a path holding one covers nothing in the oracle.
    contour_sizes : (C,) int64
        The number of vertices of each contour, each at least 1 (a contour of one or two
        vertices encloses nothing).
    contour_path : (C,) int64
        The path each contour belongs to; paths are numbered 0 .. P - 1, each has a
        contour at least, and a path's contours need not be adjacent.
    fill_rule : {"nonzero", "evenodd"}

    Examples
    --------
    A square with a square hole (the hole wound the other way), and a triangle:

    >>> scene = PathScene.from_paths(8, 8, [[[[1, 1], [7, 1], [7, 7], [1, 7]], [[3, 3], [3, 5], [5, 5], [5, 3]]],
    ...                                     [[[0, 0], [2, 0], [0, 2]]]], "evenodd")
    >>> len(scene), scene.contour_sizes, scene.contour_path, scene.kind
    (2, array([4, 4, 3]), array([0, 0, 1]), 'paths')
    >>> [c.shape for c in scene.contours_of(0)]
    [(4, 2), (4, 2)]
    """

    width: int
    height: int
    vertices: NDArray[np.float64]
    contour_sizes: NDArray[np.int64]
    contour_path: NDArray[np.int64]
    fill_rule: str = "nonzero"
    kind: ClassVar[str] = "paths"
    noun: ClassVar[str] = "path"
    # paths carry no per-vertex values
    attributes: ClassVar[None] = None
    w: ClassVar[None] = None

    def __post_init__(self) -> None:
        _set_viewport(self)
        vertices = _vertex_array(self.vertices, "PathScene")
        object.__setattr__(self, "vertices", vertices)
        sizes, paths = (_counts_array(getattr(self, f), f) for f in ("contour_sizes", "contour_path"))
        if sizes.size != paths.size:
            raise ValueError(f"PathScene has {sizes.size} contour sizes but {paths.size} contour paths")
        if np.any(sizes < 1):
            raise ValueError(f"PathScene contour {int(np.flatnonzero(sizes < 1)[0])} has no vertex")
        if int(sizes.sum()) != vertices.shape[0]:
            raise ValueError(f"PathScene contour sizes add up to {int(sizes.sum())} vertices, not the {vertices.shape[0]} given")
        n_paths = int(paths.max(initial=-1)) + 1
        if np.any(paths < 0) or np.unique(paths).size != n_paths:
            raise ValueError(f"PathScene.contour_path must number the paths 0 .. P - 1, each with a contour, "
                             f"not {paths[:12].tolist()}{' ...' if paths.size > 12 else ''}")
        if self.fill_rule not in FILL_RULES:
            raise ValueError(f"PathScene.fill_rule must be one of {', '.join(FILL_RULES)}, not {self.fill_rule!r}")
        for field, array in (("contour_sizes", sizes), ("contour_path", paths)):
            array.setflags(write=False)
            object.__setattr__(self, field, array)

    @classmethod
    def from_paths(cls, width: int, height: int, paths: Iterable[Iterable[ArrayLike]], fill_rule: str = "nonzero") -> PathScene:
        """A scene from nested lists: ``paths[k]`` is path k's contours, each a (K, 2)
        array-like of vertices."""
        contours: list[NDArray[np.float64]] = []
        owner: list[int] = []
        for k, path in enumerate(paths):
            for contour in path:
                contours.append(np.asarray(contour, dtype=np.float64).reshape(-1, 2))
                owner.append(k)
        vertices = np.concatenate(contours) if contours else np.zeros((0, 2))
        return cls(width, height, vertices, np.array([c.shape[0] for c in contours], dtype=np.int64),
                   np.array(owner, dtype=np.int64), fill_rule)

    def __reduce__(self) -> tuple[type, tuple]:  # type: ignore[type-arg]
        return PathScene, (self.width, self.height, self.vertices, self.contour_sizes, self.contour_path, self.fill_rule)

    def __len__(self) -> int:
        """P, the number of paths."""
        return int(self.contour_path.max(initial=-1)) + 1

    @property
    def n_attributes(self) -> int:
        """0: paths carry no attributes."""
        return 0

    @property
    def contour_starts(self) -> NDArray[np.int64]:
        """(C,) int64: the index of each contour's first vertex."""
        return np.cumsum(self.contour_sizes) - self.contour_sizes

    def contours(self) -> list[NDArray[np.float64]]:
        """Every contour's (K, 2) vertices (views), in order."""
        ends = np.cumsum(self.contour_sizes).tolist()
        return [self.vertices[end - size:end] for end, size in zip(ends, self.contour_sizes.tolist())]

    def contours_of(self, path: int) -> list[NDArray[np.float64]]:
        """Path ``path``'s contours (views), in order: only its own are sliced, so that a
        scene's paths taken one by one cost the scene's size, not its square."""
        ends = np.cumsum(self.contour_sizes)
        return [self.vertices[ends[c] - self.contour_sizes[c]:ends[c]] for c in np.flatnonzero(self.contour_path == path)]

    def edges(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
        """Every edge ``a -> b`` ((E, 2) each; E = V, the last vertex of each contour
        joining its first) and its path ((E,) int64)."""
        following = np.arange(1, self.vertices.shape[0] + 1)
        ends = np.cumsum(self.contour_sizes)
        following[ends - 1] = ends - self.contour_sizes
        return self.vertices, self.vertices[following], np.repeat(self.contour_path, self.contour_sizes)

    def primitive_boxes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """Per path its bounding box ``lo, hi`` ((P, 2) each) and whether all its
        coordinates are finite ((P,) bool)."""
        n = len(self)
        lo = np.full((n, 2), np.inf)
        hi = np.full((n, 2), -np.inf)
        finite = np.ones(n, dtype=bool)
        if not n:
            return lo, hi, finite
        # per contour by reduceat over its run of vertices, then per path over its contours
        starts = self.contour_starts
        ok = np.isfinite(self.vertices)
        v = np.where(ok, self.vertices, 0.0)
        np.minimum.at(lo, self.contour_path, np.minimum.reduceat(v, starts, axis=0))
        np.maximum.at(hi, self.contour_path, np.maximum.reduceat(v, starts, axis=0))
        finite[self.contour_path[~np.logical_and.reduceat(ok.all(axis=1), starts)]] = False
        return lo, hi, finite

    def non_finite(self) -> tuple[int, ...]:
        """Paths with a NaN or infinite coordinate."""
        return tuple(int(p) for p in np.flatnonzero(~self.primitive_boxes()[2]))

    @property
    def coordinates(self) -> NDArray[np.float64]:
        """Every vertex coordinate: ``vertices``, (V, 2)."""
        return self.vertices

    def with_coordinates(self, coordinates: ArrayLike) -> PathScene:
        """The same contours, paths and fill rule with these (V, 2) vertices."""
        return PathScene(self.width, self.height, np.asarray(coordinates, dtype=np.float64), self.contour_sizes, self.contour_path,
                         self.fill_rule)

    def subset(self, keep: ArrayLike) -> PathScene:
        """Paths ``keep``, in that order (path k of the result is ``keep[k]``)."""
        index = np.asarray(keep, dtype=np.int64).reshape(-1)
        every = self.contours()
        chosen = [c for p in index for c in np.flatnonzero(self.contour_path == p)]
        rank = {int(p): k for k, p in enumerate(index)}
        vertices = np.concatenate([every[c] for c in chosen]) if chosen else np.zeros((0, 2))
        return PathScene(self.width, self.height, vertices, self.contour_sizes[chosen] if chosen else np.zeros(0, np.int64),
                         np.array([rank[int(self.contour_path[c])] for c in chosen], dtype=np.int64), self.fill_rule)

    def with_fill_rule(self, fill_rule: str) -> PathScene:
        """The same paths under another fill rule."""
        return PathScene(self.width, self.height, self.vertices, self.contour_sizes, self.contour_path, fill_rule)


@dataclass(frozen=True, slots=True, eq=False)
class LineScene:
    """Aliased lines to draw into a ``width`` x ``height`` viewport: segments, and
    polylines (strips) whose consecutive segments share their end points.

    The primitive is the *segment* (as ``gl_PrimitiveID`` counts the segments of a
    ``GL_LINE_STRIP``): coverage names segment k (:attr:`Coverage.primitive`), so a pixel a
    polyline draws at a joint from both of its segments is a double hit. Strip s holds
    ``strip_sizes[s]`` vertices and ``strip_sizes[s] - 1`` segments; segments are numbered
    strip by strip. How a rasterizer must draw them is its convention's
    :class:`harness.conventions.LineRule` (:mod:`harness.lines`). A rasterizer takes line
    scenes when it lists ``"lines"`` in its ``scene_kinds`` (:func:`scene_kinds_of`).

    Parameters
    ----------
    width, height : int
        Viewport size in pixels, 1 .. 2**20.
    vertices : (V, 2) float64
        Every strip's vertices, one strip after the other. Non-finite values are allowed
        (bad-input cases); a segment with one covers nothing in the oracle.
    strip_sizes : (S,) int64
        The number of vertices of each strip, each at least 2.
    line_width : float
        Width in pixels, finite and positive: the rectangle's width for rectangular
        lines; the diamond rules draw width 1, or integer widths by GL's replication
        (``LineRule(wide="replicate")``); Bresenham width 1 only.

    Examples
    --------
    A polyline of three segments and a lone segment:

    >>> scene = LineScene.from_strips(8, 8, [[[0.5, 0.5], [6.5, 2.5], [6.5, 7.5], [1.5, 7.5]], [[0, 4], [3, 4]]])
    >>> len(scene), scene.strip_sizes, scene.kind, scene.noun
    (4, array([4, 2]), 'lines', 'segment')
    >>> scene.joints().tolist()  # segment k ends where segment k + 1 starts
    [[0, 1], [1, 2]]
    """

    width: int
    height: int
    vertices: NDArray[np.float64]
    strip_sizes: NDArray[np.int64]
    line_width: float = 1.0
    kind: ClassVar[str] = "lines"
    noun: ClassVar[str] = "segment"
    # lines carry no per-vertex values
    attributes: ClassVar[None] = None
    w: ClassVar[None] = None

    def __post_init__(self) -> None:
        _set_viewport(self)
        vertices = _vertex_array(self.vertices, "LineScene")
        object.__setattr__(self, "vertices", vertices)
        sizes = _counts_array(self.strip_sizes, "strip_sizes", "LineScene")
        if np.any(sizes < 2):
            raise ValueError(f"LineScene strip {int(np.flatnonzero(sizes < 2)[0])} has fewer than 2 vertices")
        if int(sizes.sum()) != vertices.shape[0]:
            raise ValueError(f"LineScene strip sizes add up to {int(sizes.sum())} vertices, not the {vertices.shape[0]} given")
        sizes.setflags(write=False)
        object.__setattr__(self, "strip_sizes", sizes)
        try:
            line_width = float(self.line_width)
        except (TypeError, ValueError):
            raise ValueError(f"LineScene.line_width must be a number, not {self.line_width!r}") from None
        if not (math.isfinite(line_width) and 0.0 < line_width <= MAX_VIEWPORT):
            raise ValueError(f"LineScene.line_width must be positive, finite and at most {MAX_VIEWPORT}, not {self.line_width!r}")
        object.__setattr__(self, "line_width", line_width)

    @classmethod
    def from_strips(cls, width: int, height: int, strips: Iterable[ArrayLike], line_width: float = 1.0) -> LineScene:
        """A scene from nested lists: each strip a (K, 2) array-like of K >= 2 vertices."""
        arrays = [np.asarray(strip, dtype=np.float64).reshape(-1, 2) for strip in strips]
        vertices = np.concatenate(arrays) if arrays else np.zeros((0, 2))
        return cls(width, height, vertices, np.array([a.shape[0] for a in arrays], dtype=np.int64), line_width)

    @classmethod
    def from_segments(cls, width: int, height: int, a: ArrayLike, b: ArrayLike, line_width: float = 1.0) -> LineScene:
        """Separate segments ``a[k] -> b[k]`` ((N, 2) each), each a strip of its own."""
        a_arr = np.asarray(a, dtype=np.float64).reshape(-1, 2)
        b_arr = np.asarray(b, dtype=np.float64).reshape(-1, 2)
        if a_arr.shape != b_arr.shape:
            raise ValueError(f"LineScene.from_segments needs end points of one shape, not {a_arr.shape} and {b_arr.shape}")
        return cls(width, height, np.stack([a_arr, b_arr], axis=1).reshape(-1, 2), np.full(a_arr.shape[0], 2, dtype=np.int64),
                   line_width)

    def __reduce__(self) -> tuple[type, tuple]:  # type: ignore[type-arg]
        return LineScene, (self.width, self.height, self.vertices, self.strip_sizes, self.line_width)

    def __len__(self) -> int:
        """N, the number of segments."""
        return int(self.vertices.shape[0] - self.strip_sizes.size)

    @property
    def n_attributes(self) -> int:
        """0: lines carry no attributes."""
        return 0

    @property
    def strip_starts(self) -> NDArray[np.int64]:
        """(S,) int64: the index of each strip's first vertex."""
        return np.cumsum(self.strip_sizes) - self.strip_sizes

    @property
    def segment_start(self) -> NDArray[np.int64]:
        """(N,) int64: the vertex each segment starts at (it ends at the next vertex)."""
        last = np.zeros(self.vertices.shape[0], dtype=bool)
        last[np.cumsum(self.strip_sizes) - 1] = True
        return np.flatnonzero(~last)

    @property
    def segment_strip(self) -> NDArray[np.int64]:
        """(N,) int64: the strip each segment belongs to."""
        return np.repeat(np.arange(self.strip_sizes.size, dtype=np.int64), self.strip_sizes - 1)

    def segments(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Every segment's end points ``a -> b``, (N, 2) each."""
        start = self.segment_start
        return self.vertices[start], self.vertices[start + 1]

    def strips(self) -> list[NDArray[np.float64]]:
        """Every strip's (K, 2) vertices (views), in order."""
        ends = np.cumsum(self.strip_sizes).tolist()
        return [self.vertices[end - size:end] for end, size in zip(ends, self.strip_sizes.tolist())]

    def joints(self, closed: bool = False) -> NDArray[np.int64]:
        """(J, 2) int64: pairs (k, m) of segments where k ends at the vertex m starts at --
        consecutive segments of a strip (m = k + 1). With ``closed``, also (last, first) of
        each strip of three or more segments whose last vertex equals its first exactly (a
        closed polyline; its first vertex is drawn by its first segment only)."""
        start = self.segment_start
        strip = self.segment_strip
        inner = np.flatnonzero(strip[:-1] == strip[1:]) if start.size else np.zeros(0, dtype=np.int64)
        pairs = np.stack([inner, inner + 1], axis=1)
        if not closed:
            return pairs.astype(np.int64)
        first_vertex, last_vertex = self.strip_starts, np.cumsum(self.strip_sizes) - 1
        with np.errstate(invalid="ignore"):
            loops = (self.strip_sizes >= 4) & np.all(self.vertices[first_vertex] == self.vertices[last_vertex], axis=1)
        first_segment = first_vertex - np.arange(self.strip_sizes.size)
        last_segment = first_segment + self.strip_sizes - 2
        closing = np.stack([last_segment[loops], first_segment[loops]], axis=1)
        return np.concatenate([pairs, closing]).astype(np.int64)

    def edges(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
        """Every segment ``a -> b`` ((N, 2) each) and its index ((N,) int64): a line's
        one edge."""
        a, b = self.segments()
        return a, b, np.arange(len(self), dtype=np.int64)

    def primitive_boxes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """Per segment its bounding box ``lo, hi`` ((N, 2) each) grown by half the line width,
        and whether its coordinates are all finite ((N,) bool)."""
        a, b = self.segments()
        finite = np.asarray(np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1), dtype=np.bool_)
        half = 0.5 * self.line_width
        with np.errstate(invalid="ignore"):
            lo = np.where(finite[:, None], np.minimum(a, b) - half, np.inf)
            hi = np.where(finite[:, None], np.maximum(a, b) + half, -np.inf)
        return lo, hi, finite

    def non_finite(self) -> tuple[int, ...]:
        """Segments with a NaN or infinite coordinate."""
        return tuple(int(k) for k in np.flatnonzero(~self.primitive_boxes()[2]))

    @property
    def coordinates(self) -> NDArray[np.float64]:
        """Every vertex coordinate: ``vertices``, (V, 2)."""
        return self.vertices

    def with_coordinates(self, coordinates: ArrayLike) -> LineScene:
        """The same strips and width with these (V, 2) vertices."""
        return LineScene(self.width, self.height, np.asarray(coordinates, dtype=np.float64), self.strip_sizes, self.line_width)

    def with_line_width(self, line_width: float) -> LineScene:
        """The same lines at another width."""
        return LineScene(self.width, self.height, self.vertices, self.strip_sizes, line_width)

    def subset(self, keep: ArrayLike) -> LineScene:
        """Segments ``keep``, in that order (segment k of the result is ``keep[k]``): a run
        of kept segments that follow each other in one strip stays a strip (its joints are
        kept); every other segment becomes a strip of its own."""
        index = np.asarray(keep, dtype=np.int64).reshape(-1)
        start = self.segment_start
        strip = self.segment_strip
        runs: list[list[int]] = []
        for k in index.tolist():
            if runs and runs[-1][-1] + 1 == k and strip[k] == strip[runs[-1][-1]]:
                runs[-1].append(k)
            else:
                runs.append([k])
        pieces = [self.vertices[np.append(start[run], start[run[-1]] + 1)] for run in runs]
        vertices = np.concatenate(pieces) if pieces else np.zeros((0, 2))
        return LineScene(self.width, self.height, vertices, np.array([len(r) + 1 for r in runs], dtype=np.int64), self.line_width)

    def reversed(self) -> tuple[LineScene, NDArray[np.int64]]:
        """Every strip drawn backwards (its vertices in reverse order, strips in the same
        order), and for each segment of the result the segment of this scene it retraces
        ((N,) int64)."""
        pieces = [s[::-1] for s in self.strips()]
        vertices = np.concatenate(pieces) if pieces else np.zeros((0, 2))
        first_segment = self.strip_starts - np.arange(self.strip_sizes.size)
        origin = np.concatenate([first_segment[s] + np.arange(n - 2, -1, -1) for s, n in enumerate(self.strip_sizes.tolist())]) \
            if self.strip_sizes.size else np.zeros(0, dtype=np.int64)
        return LineScene(self.width, self.height, vertices, self.strip_sizes, self.line_width), origin.astype(np.int64)


class Unsupported(ValueError):
    """Raised by a rasterizer for a scene it cannot draw as given (say, a library that
    fills one contour per call handed a path of three): the runner reports a skip with the
    message, naming what it cannot do, instead of an error."""


# A scene of any kind: each has ``width``, ``height``, ``kind``, ``len()`` (its number of
# primitives), ``primitive_boxes()``, ``non_finite()``, ``coordinates``,
# ``with_coordinates(c)`` and ``subset(keep)``.
AnyScene = Scene | PathScene | LineScene
SCENE_KINDS = ("triangles", "paths", "lines")


def _counts_array(value: ArrayLike, field: str, owner: str = "PathScene") -> NDArray[np.int64]:
    array = np.asarray(value)
    if array.size == 0:
        return np.zeros(0, dtype=np.int64)
    if array.ndim != 1 or array.dtype.kind not in "iu":
        raise ValueError(f"{owner}.{field} must be a 1-D integer array, not {array.dtype} of shape {array.shape}")
    return np.array(array, dtype=np.int64)


def _int_array(value: ArrayLike, field: str) -> NDArray[np.int64]:
    array = np.asarray(value)
    if array.ndim != 1:
        raise ValueError(f"Coverage.{field} must be one-dimensional, not shape {array.shape}")
    if array.dtype == np.int64:
        # Taken as given, without a copy: kernels hand over arrays they no longer use.
        # The read-only flag below is set on this view, not on the caller's array.
        return array.view()
    if array.dtype.kind in "biu":
        return array.astype(np.int64)
    if array.dtype.kind == "f":
        if not np.all(np.isfinite(array)) or np.any(array != np.floor(array)):
            raise ValueError(f"Coverage.{field} must hold integers")
        if np.any(np.abs(array) >= 2.0**62):
            raise ValueError(f"Coverage.{field} holds values too large for int64")
        return array.astype(np.int64)
    if array.size == 0:
        return np.zeros(0, dtype=np.int64)
    raise ValueError(f"Coverage.{field} must hold integers, not dtype {array.dtype}")


@dataclass(frozen=True, slots=True, eq=False)
class Coverage:
    """What a rasterizer covered: horizontal spans, plus interpolated attributes.

    Span k covers pixels ``x0[k] <= x < x1[k]`` of row ``y[k]`` for primitive
    ``primitive[k]``: the scene's triangle k of a triangle scene, its path k of a path
    scene (:attr:`triangle` is the same array under its triangle-scene name). A triangle
    covers one run per row, so cost grows with rows, not pixels. ``attributes`` has one row per covered pixel: the spans' pixels in span
    order, left to right within a span.

    The same spans carry the two other kinds of coverage (:attr:`Convention.kind`):

    * multisample: ``sample[k]`` says which sample of the pattern span k covers in each of
      its pixels (one run per primitive, sample and row); a fragment is then a (primitive,
      sample, pixel) and ``attributes`` has one row per fragment, in span order.
    * area (anti-aliased): ``alpha`` has one value per pixel in span order, the share of
      the pixel the primitive covers; a pixel left out has alpha 0.

    The constructor checks structure only (1-D integer arrays of one length, a 2-D
    float attribute array); whether spans are sensible is for the hygiene checks to say.
    int64 span arrays are kept without a copy (as read-only views): do not modify them
    afterwards through another reference.

    Parameters
    ----------
    primitive, y, x0, x1 : (S,) int64
    attributes : (P, K) float64 or None
    sample : (S,) int64 or None
        Multisample coverage: the sample index of each span; None for one sample per pixel.
    alpha : (P,) float64 or None
        Area coverage: the alpha of each pixel, in span order; None otherwise.

    Examples
    --------
    >>> cov = Coverage.from_pixels([0, 0, 0, 1], [2, 3, 1, 0], [5, 5, 6, 5])
    >>> cov.primitive, cov.y, cov.x0, cov.x1
    (array([0, 0, 1]), array([5, 6, 5]), array([2, 1, 0]), array([4, 2, 1]))
    >>> cov.counts(4, 7)[5:]
    array([[1, 0, 1, 1],
           [0, 1, 0, 0]], dtype=int32)
    """

    primitive: NDArray[np.int64]
    y: NDArray[np.int64]
    x0: NDArray[np.int64]
    x1: NDArray[np.int64]
    attributes: NDArray[np.float64] | None = None
    sample: NDArray[np.int64] | None = None
    alpha: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        fields = ("primitive", "y", "x0", "x1") + (("sample",) if self.sample is not None else ())
        arrays = {f: _int_array(getattr(self, f), f) for f in fields}
        sizes = {f: a.size for f, a in arrays.items()}
        if len(set(sizes.values())) != 1:
            raise ValueError(f"Coverage span arrays must have equal lengths, not {sizes}")
        for field, array in arrays.items():
            array.setflags(write=False)
            object.__setattr__(self, field, array)
        if self.attributes is not None:
            attributes = np.asarray(self.attributes)
            if attributes.dtype.kind not in "biuf":
                raise ValueError(
                    f"Coverage.attributes must hold real numbers, not dtype {attributes.dtype}"
                )
            if attributes.ndim != 2:
                raise ValueError(
                    f"Coverage.attributes must have shape (P, K), not {attributes.shape}"
                )
            attributes = np.array(attributes, dtype=np.float64, copy=True)
            attributes.setflags(write=False)
            object.__setattr__(self, "attributes", attributes)
        if self.alpha is not None:
            alpha = np.asarray(self.alpha)
            if alpha.dtype.kind not in "biuf":
                raise ValueError(f"Coverage.alpha must hold real numbers, not dtype {alpha.dtype}")
            if alpha.ndim != 1:
                raise ValueError(f"Coverage.alpha must have shape (P,), not {alpha.shape}")
            alpha = np.array(alpha, dtype=np.float64, copy=True)
            alpha.setflags(write=False)
            object.__setattr__(self, "alpha", alpha)

    # -- constructors ------------------------------------------------------------------

    @classmethod
    def empty(cls, n_attributes: int | None = None) -> Coverage:
        """No spans; with ``n_attributes`` an empty (0, K) attribute array."""
        zero = np.zeros(0, dtype=np.int64)
        attributes = None if n_attributes is None else np.zeros((0, n_attributes))
        return cls(zero, zero, zero, zero, attributes)

    @classmethod
    def from_pixels(
        cls,
        primitive: ArrayLike,
        x: ArrayLike,
        y: ArrayLike,
        attributes: ArrayLike | None = None,
        *,
        sample: ArrayLike | None = None,
        alpha: ArrayLike | None = None,
    ) -> Coverage:
        """Build spans from individual fragments, in any order.

        Fragments are sorted by (primitive, sample, y, x) and runs of consecutive x become
        spans. A fragment repeated for the same primitive (and sample) stays a separate
        span, so the duplicate remains visible to the checks.

        Parameters
        ----------
        primitive, x, y : (P,) int
        attributes : (P, K) float64 or None, one row per fragment in the given order
        sample : (P,) int or None
            Multisample coverage: each fragment's sample index.
        alpha : (P,) float64 or None
            Area coverage: each fragment's alpha.

        Examples
        --------
        >>> cov = Coverage.from_pixels([0, 0, 0], [1, 2, 1], [0, 0, 0], sample=[3, 3, 1])
        >>> cov.sample, cov.x0, cov.x1
        (array([1, 3]), array([1, 1]), array([2, 3]))
        """
        tri = _int_array(primitive, "primitive")
        xs = _int_array(x, "x")
        ys = _int_array(y, "y")
        if not tri.size == xs.size == ys.size:
            raise ValueError("Coverage.from_pixels needs primitive, x and y of equal lengths")
        samples = None if sample is None else _int_array(sample, "sample")
        if samples is not None and samples.size != tri.size:
            raise ValueError("Coverage.from_pixels needs one sample index per fragment")
        keys = (xs, ys, tri) if samples is None else (xs, ys, samples, tri)
        order = lexsort(keys)
        tri, xs, ys = tri[order], xs[order], ys[order]
        if samples is not None:
            samples = samples[order]
        rows: dict[str, NDArray[np.float64] | None] = {}
        for field, values, shape in (("attributes", attributes, "K"), ("alpha", alpha, None)):
            if values is None:
                rows[field] = None
                continue
            array = np.asarray(values, dtype=np.float64)
            if array.ndim != (2 if shape else 1) or array.shape[0] != order.size:
                raise ValueError(f"Coverage.from_pixels {field} must have shape ({order.size}{', K' if shape else ','}), "
                                 f"not {array.shape}")
            rows[field] = array[order]
        new_span = np.ones(tri.size, dtype=bool)
        new_span[1:] = (tri[1:] != tri[:-1]) | (ys[1:] != ys[:-1]) | (xs[1:] != xs[:-1] + 1)
        if samples is not None:
            new_span[1:] |= samples[1:] != samples[:-1]
        heads = np.flatnonzero(new_span)
        tails = run_tails(heads, tri.size)
        return cls(tri[heads], ys[heads], xs[heads], xs[tails] + 1, rows["attributes"],
                   None if samples is None else samples[heads], rows["alpha"])

    @classmethod
    def from_mask(cls, primitive: int, mask: ArrayLike, attributes: ArrayLike | None = None, *,
                  sample: int | None = None, alpha: ArrayLike | None = None) -> Coverage:
        """Build the spans of one primitive (and one sample) from an (H, W) boolean mask.

        Parameters
        ----------
        primitive : int
        mask : (H, W) bool
        attributes : (H, W, K) float64 or None, values at every pixel (only covered ones kept)
        sample : int or None
            Multisample coverage: the sample the mask is of.
        alpha : (H, W) float64 or None
            Area coverage: the alpha at every pixel (only the mask's pixels kept).

        Examples
        --------
        >>> Coverage.from_mask(3, [[0, 1, 1, 0, 1], [0, 0, 0, 0, 0]]).x0
        array([1, 4])
        >>> alpha = [[0.0, 0.25, 1.0]]
        >>> Coverage.from_mask(0, np.asarray(alpha) > 0, alpha=alpha).alpha
        array([0.25, 1.  ])
        """
        mask = np.asarray(mask).astype(bool)
        if mask.ndim != 2:
            raise ValueError(f"Coverage.from_mask needs an (H, W) mask, not shape {mask.shape}")
        padded = np.zeros((mask.shape[0], mask.shape[1] + 2), dtype=np.int8)
        padded[:, 1:-1] = mask
        edges = np.diff(padded, axis=1)
        rows, starts = np.nonzero(edges == 1)
        _, ends = np.nonzero(edges == -1)
        values = None
        if attributes is not None:
            attributes = np.asarray(attributes, dtype=np.float64)
            if attributes.ndim != 3 or attributes.shape[:2] != mask.shape:
                raise ValueError(
                    f"Coverage.from_mask attributes must have shape {mask.shape + ('K',)}, "
                    f"not {attributes.shape}"
                )
            values = attributes[mask]
        alphas = None
        if alpha is not None:
            alpha = np.asarray(alpha, dtype=np.float64)
            if alpha.shape != mask.shape:
                raise ValueError(f"Coverage.from_mask alpha must have shape {mask.shape}, not {alpha.shape}")
            alphas = alpha[mask]
        samples = None if sample is None else np.full(rows.size, sample)
        return cls(np.full(rows.size, primitive), rows, starts, ends, values, samples, alphas)

    @classmethod
    def concat(cls, parts: Iterable[Coverage]) -> Coverage:
        """One coverage from several, spans (and attribute and alpha rows) in the order
        given. All parts carry attributes (sample indices, alphas), or none does.

        Examples
        --------
        >>> both = Coverage.concat([Coverage.from_mask(0, [[1, 1, 0]]), Coverage.from_mask(1, [[0, 1, 1]])])
        >>> both.primitive, both.x0, both.x1
        (array([0, 1]), array([0, 1]), array([2, 3]))
        """
        parts = list(parts)
        if not parts:
            return cls.empty()
        joined: dict[str, Any] = {}
        for field in ("attributes", "sample", "alpha"):
            present = [getattr(p, field) is not None for p in parts]
            if any(present) and not all(present):
                raise ValueError(f"Coverage.concat: some parts carry {field} and some do not")
            joined[field] = np.concatenate([getattr(p, field) for p in parts]) if all(present) else None
        primitive, y, x0, x1 = (np.concatenate([getattr(p, f) for p in parts]) for f in ("primitive", "y", "x0", "x1"))
        return cls(primitive, y, x0, x1, joined["attributes"], joined["sample"], joined["alpha"])

    # -- views -----------------------------------------------------------------------

    def __len__(self) -> int:
        return int(self.primitive.size)

    @property
    def triangle(self) -> NDArray[np.int64]:
        """:attr:`primitive` by its triangle-scene name (the same array)."""
        return self.primitive

    @property
    def n_pixels(self) -> int:
        """Number of fragments: the sum of positive span lengths."""
        return int(np.maximum(self.x1 - self.x0, 0).sum())

    def pixels(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
        """Every fragment as (primitive, x, y), in span order, left to right.

        >>> Coverage([2], [1], [3], [5]).pixels()
        (array([2, 2]), array([3, 4]), array([1, 1]))
        """
        lengths = np.maximum(self.x1 - self.x0, 0)
        x = expand(self.x0, lengths)
        return np.repeat(self.primitive, lengths), x, np.repeat(self.y, lengths)

    def fragment_samples(self) -> NDArray[np.int64]:
        """The sample index of every fragment, in the order of :meth:`pixels` (all 0 for
        single-sample or area coverage)."""
        lengths = np.maximum(self.x1 - self.x0, 0)
        if self.sample is None:
            return np.zeros(int(lengths.sum()), dtype=np.int64)
        return np.repeat(self.sample, lengths)

    def take(self, spans: NDArray[np.int64], start: NDArray[np.int64] | None = None,
             end: NDArray[np.int64] | None = None) -> Coverage:
        """The spans of index ``spans``, in that order, optionally cut to ``start <= x <
        end`` (within each span); attribute and alpha rows go with their pixels (dropped
        when their number does not match the spans' pixels).

        Examples
        --------
        >>> cov = Coverage([0, 1], [0, 0], [0, 4], [3, 6], alpha=[0.1, 0.2, 0.3, 0.4, 0.5])
        >>> cut = cov.take(np.array([1, 0]), np.array([5, 1]), np.array([6, 3]))
        >>> cut.x0, cut.x1, cut.alpha
        (array([5, 1]), array([6, 3]), array([0.5, 0.2, 0.3]))
        """
        x0 = self.x0[spans] if start is None else start
        x1 = self.x1[spans] if end is None else end
        kept: list[NDArray[np.float64] | None] = [None, None]
        if self.attributes is not None or self.alpha is not None:  # pixel rows only when there are any
            offsets = pixel_offsets(self.x0, self.x1)
            rows = expand(offsets[spans] + (x0 - self.x0[spans]), np.maximum(x1 - x0, 0))
            kept = [values[rows] if values is not None and values.shape[0] == offsets[-1] else None
                    for values in (self.attributes, self.alpha)]
        sample = None if self.sample is None else self.sample[spans]
        return Coverage(self.primitive[spans], self.y[spans], x0, x1, kept[0], sample, kept[1])

    def layer(self, index: int) -> Coverage:
        """The single-sample coverage of sample ``index`` of a multisample coverage (the
        whole coverage, without sample indices, when it has none and ``index`` is 0).

        >>> Coverage([0, 0], [2, 2], [1, 5], [4, 6], sample=[0, 3]).layer(3).x0
        array([5])
        """
        if self.sample is None:
            return self if index == 0 else Coverage.empty(None if self.attributes is None else self.attributes.shape[1])
        spans = np.flatnonzero(self.sample == index)
        taken = self.take(spans)
        return Coverage(taken.primitive, taken.y, taken.x0, taken.x1, taken.attributes)

    def counts(self, width: int, height: int) -> NDArray[np.int32]:
        """Hits per pixel, (height, width) int32, from difference arrays (no fragments);
        a multisample coverage counts each covered sample.

        Spans are clipped to the viewport; rows outside it are ignored.
        """
        keep = (self.y >= 0) & (self.y < height) & (self.x1 > self.x0)
        y = self.y[keep]
        x0 = np.clip(self.x0[keep], 0, width)
        x1 = np.clip(self.x1[keep], 0, width)
        stride = width + 1
        size = height * stride
        delta = np.bincount(y * stride + x0, minlength=size) - np.bincount(
            y * stride + x1, minlength=size
        )
        return np.cumsum(delta.reshape(height, stride), axis=1)[:, :width].astype(np.int32)

    def tidy(self, scene: AnyScene) -> tuple[Coverage, dict[str, NDArray[np.int64]]]:
        """What the checks may safely use of this coverage, and what was wrong with it.

        Works span by span, never pixel by pixel, so that a garbage answer (a span of
        10**8 pixels, a million copies of one span, spans far off-screen) costs time and
        memory in proportion to its number of spans, not to the pixels it claims. Keeps
        the pixels that can belong to their primitive: inside the viewport and within the
        primitive's bounding box grown by 2 px (the reach of any sample point in the pixel
        plus any snapping of a vertex by up to 1 px), each emitted once per primitive (and
        sample, for multisample coverage: a sample index outside 0 .. MAX_SAMPLES - 1 is
        a ``bad_sample``).

        Returns
        -------
        usable : Coverage
            ``self`` when nothing was wrong; else the kept spans, with the attribute (and
            alpha) rows of the kept pixels when there was one row per pixel (else none).
        flaws : dict of str -> (n,) int64
            Indices of offending spans: ``bad_primitive_id``, ``bad_sample``,
            ``empty_or_reversed``, ``outside_viewport``, ``outside_primitive``, ``repeated``
            (see :func:`harness.spans.tidy`), all empty when ``usable is self``; and
            ``repeated_pixels``, one number: the pixels emitted a second time.
        """
        from harness.conventions import MAX_SAMPLES

        n = len(scene)
        ids, layers = self.primitive, 1
        bounds = _pixel_bounds(scene)
        bad_sample = np.zeros(0, dtype=np.int64)
        if self.sample is not None:
            # one virtual primitive per (primitive, sample): the single-sample rules apply to each
            valid = (self.sample >= 0) & (self.sample < MAX_SAMPLES)
            bad_sample = np.flatnonzero(~valid)
            layers = int(self.sample[valid].max(initial=0)) + 1
            known = (self.primitive >= 0) & (self.primitive < n)
            ids = np.where(known & valid, np.where(known, self.primitive, 0) * layers + np.where(valid, self.sample, 0), -1)
            bounds = np.repeat(bounds, layers, axis=0)
        spans = (frozen(a, np.int64) for a in (ids, self.y, self.x0, self.x1))
        kinds = ("bad_primitive_id", "bad_sample", "empty_or_reversed", "outside_primitive", "repeated", "outside_viewport")
        if not bad_sample.size and already_tidy(frozen(bounds, np.int64), *spans):
            none = np.zeros(0, dtype=np.int64)
            return self, {**{kind: none for kind in kinds}, "repeated_pixels": np.zeros(1, dtype=np.int64)}
        keep, start, end, flaws, repeated_pixels = tidy(ids, self.y, self.x0, self.x1, n * layers, bounds)
        y, x0, x1 = self.y, self.x0, self.x1
        outside = (y < 0) | (y >= scene.height) | (x0 < 0) | (x1 > scene.width)
        flaws["bad_sample"] = bad_sample
        flaws["bad_primitive_id"] = np.setdiff1d(flaws["bad_primitive_id"], bad_sample[(self.primitive[bad_sample] >= 0) & (self.primitive[bad_sample] < n)])
        off_screen = outside & (x0 < x1)
        flaws["outside_viewport"] = np.flatnonzero(off_screen)
        beyond = flaws["outside_primitive"]
        flaws["outside_primitive"] = beyond[~off_screen[beyond]]
        flaws["repeated_pixels"] = np.array([repeated_pixels], dtype=np.int64)
        if not any(v.size for k, v in flaws.items() if k != "repeated_pixels"):
            return self, flaws
        return self.take(keep, start, end), flaws

    def canonical(self) -> Coverage:
        """The same fragments in canonical form: spans sorted by (primitive, sample, y, x0),
        empty spans dropped, touching spans of one primitive, sample and row merged.
        Overlapping spans are kept apart, so a fragment emitted twice is still counted
        twice."""
        length = self.x1 - self.x0
        if (length > 0).all():  # canonical already (the usual answer of a rasterizer): itself
            whole = composite((self.x1, self.x0, self.y, *([] if self.sample is None else [self.sample]), self.primitive))
            if whole is not None and (whole[1:] >= whole[:-1]).all():
                joins = (self.primitive[1:] == self.primitive[:-1]) & (self.y[1:] == self.y[:-1]) & (self.x0[1:] == self.x1[:-1])
                if self.sample is not None:
                    joins &= self.sample[1:] == self.sample[:-1]
                if not joins.any():
                    return self
        keep = np.flatnonzero(length > 0)
        keys = [self.x1[keep], self.x0[keep], self.y[keep]] + ([] if self.sample is None else [self.sample[keep]])
        order = keep[lexsort((*keys, self.primitive[keep]))]
        sorted_ = self.take(order)
        tri, y, x0, x1 = sorted_.primitive, sorted_.y, sorted_.x0, sorted_.x1
        joins = np.zeros(tri.size, dtype=bool)
        joins[1:] = (tri[1:] == tri[:-1]) & (y[1:] == y[:-1]) & (x0[1:] == x1[:-1])
        if sorted_.sample is not None:
            joins[1:] &= sorted_.sample[1:] == sorted_.sample[:-1]
        heads = np.flatnonzero(~joins)
        sample = None if sorted_.sample is None else sorted_.sample[heads]
        # rows not matching the pixels stay as they came (hygiene reports them)
        attributes = sorted_.attributes if sorted_.attributes is not None or self.attributes is None else self.attributes
        alpha = sorted_.alpha if sorted_.alpha is not None or self.alpha is None else self.alpha
        return Coverage(tri[heads], y[heads], x0[heads], x1[run_tails(heads, tri.size)], attributes, sample, alpha)

    def __eq__(self, other: object) -> bool:
        """Exact equality of canonical forms (sample indices, attributes and alphas too;
        NaN equals NaN)."""
        if not isinstance(other, Coverage):
            return NotImplemented
        a, b = self.canonical(), other.canonical()
        same_spans = all(
            np.array_equal(getattr(a, f), getattr(b, f)) for f in ("primitive", "y", "x0", "x1")
        )
        if not same_spans:
            return False
        for field in ("sample", "attributes", "alpha"):
            u, v = getattr(a, field), getattr(b, field)
            if u is None or v is None:
                if not (u is None and v is None):
                    return False
            elif u.shape != v.shape or not np.array_equal(u, v, equal_nan=True):
                return False
        return True

    __hash__ = None  # type: ignore[assignment]


@runtime_checkable
class Rasterizer(Protocol):
    """Anything that turns a Scene into a Coverage.

    Attributes
    ----------
    name : str
        Short identifier, shown in reports.
    convention : Convention or None
        The fill convention it claims to follow; None when it declares none.

    Optional members, read only through :func:`interpolates_of`, :func:`received_of` and
    :func:`fingerprint_of` (a plugin that lacks them is still a Rasterizer):

    interpolates : bool
        False for a coverage-only rasterizer (True when absent): its hygiene check then
        accepts missing attribute rows, and the texel and perspective checks are skipped
        with that reason instead of failing.
    received : callable, ``received(scene) -> Scene``
        The scene as the library really receives it (e.g. positions rounded to float32 at
        the GL API): a failure that passes on it is blamed on the input format.
    fingerprint : harness.identify.Fingerprint
        Set by rastercheck on a rasterizer that declares no convention: what identify
        found, so that verdicts against a best guess say so.
    scene_kinds : tuple of str
        The scene kinds it takes, of :data:`SCENE_KINDS` (``("triangles",)`` when absent):
        one listing ``"paths"`` is handed :class:`PathScene` too, and fills each path in
        one go under the scene's fill rule; one listing ``"lines"`` is handed
        :class:`LineScene` and draws each segment by its convention's ``line`` rule
        (:class:`harness.conventions.LineRule`). Read by :func:`scene_kinds_of`.
    fill_rules : tuple of str
        The fill rules a path-taking rasterizer honours (both when absent): it is handed
        only path scenes of these rules. Read by :func:`fill_rules_of`.
    path_convention : Convention
        The convention its path fills follow when not ``convention`` (set by identify on a
        black box whose paths and triangles differ). Read by :func:`convention_for`.
    line_convention : Convention
        The convention its lines follow when not ``convention`` (set by identify on a
        black box whose lines are snapped otherwise than its triangles, or drawn as
        rectangles at another sample point or tie rule). Read by :func:`convention_for`.
    """

    # Read-only members: a plain class attribute or instance attribute of a narrower
    # type (say ``convention = Convention()``) satisfies them.
    @property
    def name(self) -> str: ...

    @property
    def convention(self) -> Convention | None: ...

    def rasterize(self, scene: Scene) -> Coverage:
        """Cover the scene's triangles; attributes interpolated when the scene has them."""
        ...


def _pixel_bounds(scene: AnyScene) -> NDArray[np.int64]:
    """(N, 4) int64: per primitive the pixels ``xmin, ymin, xmax, ymax`` (inclusive) any of
    its fragments may lie in under any convention: its bounding box grown by 2 px, clipped
    to the viewport (the whole viewport for a primitive with a NaN or infinite coordinate)."""
    lo, hi, finite = scene.primitive_boxes()
    out = np.empty((len(scene), 4), dtype=np.int64)
    limit = [scene.width + 4.0, scene.height + 4.0]
    out[:, 0:2] = np.where(finite[:, None], np.floor(np.clip(lo, -4.0, limit)) - 2, 0)
    out[:, 2:4] = np.where(finite[:, None], np.ceil(np.clip(hi, -4.0, limit)) + 2, [scene.width - 1, scene.height - 1])
    out[:, 0:2] = np.maximum(out[:, 0:2], 0)
    out[:, 2] = np.minimum(out[:, 2], scene.width - 1)
    out[:, 3] = np.minimum(out[:, 3], scene.height - 1)
    return out


# The optional members of a Rasterizer, each read in one place.
def scene_kinds_of(rasterizer: Rasterizer) -> tuple[str, ...]:
    """The scene kinds a rasterizer takes (``scene_kinds``; triangles only when absent)."""
    kinds = getattr(rasterizer, "scene_kinds", None)
    return ("triangles",) if kinds is None else tuple(str(k) for k in kinds)


def convention_for(rasterizer: Rasterizer, scene: AnyScene) -> Convention | None:
    """The convention a rasterizer's answer on ``scene`` is judged by: its
    ``path_convention`` for a path scene when it has one (a black box whose path fills
    identify found to follow another convention than its triangles), its
    ``line_convention`` for a line scene when it has one (likewise for lines), else its
    ``convention``."""
    if isinstance(scene, PathScene):
        path = getattr(rasterizer, "path_convention", None)
        if isinstance(path, Convention):
            return path
    if isinstance(scene, LineScene):
        line = getattr(rasterizer, "line_convention", None)
        if isinstance(line, Convention):
            return line
    return rasterizer.convention


def fill_rules_of(rasterizer: Rasterizer) -> tuple[str, ...]:
    """The fill rules a path-taking rasterizer honours (``fill_rules``; both when absent)."""
    rules = getattr(rasterizer, "fill_rules", None)
    return tuple(FILL_RULES) if rules is None else tuple(str(r) for r in rules)


def takes(rasterizer: Rasterizer, scene: AnyScene) -> bool:
    """Whether the rasterizer is handed ``scene``: a kind it takes (and, for paths, a fill
    rule it honours). The runner gives each rasterizer only such scenes."""
    if scene.kind not in scene_kinds_of(rasterizer):
        return False
    return not isinstance(scene, PathScene) or scene.fill_rule in fill_rules_of(rasterizer)


def interpolates_of(rasterizer: Rasterizer) -> bool:
    """Whether the rasterizer interpolates attributes (``interpolates``, True when absent)."""
    return bool(getattr(rasterizer, "interpolates", True))


def received_of(rasterizer: Rasterizer) -> Callable[[Scene], Scene] | None:
    """The rasterizer's ``received(scene) -> Scene``, or None when it has none."""
    received = getattr(rasterizer, "received", None)
    return received if callable(received) else None


def fingerprint_of(rasterizer: Rasterizer) -> Any:
    """What identify found for a rasterizer that declared no convention, or None."""
    return getattr(rasterizer, "fingerprint", None)
