"""What a rasterizer receives: the scene records (triangles, paths, lines), checked on
construction, and the refusal a rasterizer may raise for one it cannot draw.

Screen space, conventions and tie rules are defined in :mod:`harness.contract.conventions`.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, cast

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import FILL_RULES

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

    # the constructor takes array-likes (lists too), which __post_init__ makes arrays
    if TYPE_CHECKING:
        def __init__(self, width: int, height: int, positions: ArrayLike, attributes: ArrayLike | None = None,
                     w: ArrayLike | None = None) -> None: ...

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

    def __reduce__(self) -> tuple[type, tuple]:
        # through the constructor: an unpickled scene (a worker's) is checked and frozen as
        # the original was, so kernels see one array type (see harness.geometry.exact.frozen)
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
        return _triangle_boxes(self.positions)  # type: ignore[no-any-return]

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

    def with_viewport(self, width: int, height: int) -> Scene:
        """The same primitives on a ``width`` x ``height`` viewport."""
        return replace(self, width=width, height=height)
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
    (:mod:`harness.oracle.winding`). Paths are filled independently, each in one call of a 2D
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

    # the constructor takes array-likes (lists too), which __post_init__ makes arrays
    if TYPE_CHECKING:
        def __init__(self, width: int, height: int, vertices: ArrayLike, contour_sizes: ArrayLike,
                     contour_path: ArrayLike, fill_rule: str = "nonzero") -> None: ...

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

    def __reduce__(self) -> tuple[type, tuple]:
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
        return PathScene(self.width, self.height, np.asarray(coordinates, dtype=np.float64), self.contour_sizes,
                         self.contour_path, self.fill_rule)

    def with_viewport(self, width: int, height: int) -> PathScene:
        """The same primitives on a ``width`` x ``height`` viewport."""
        return replace(self, width=width, height=height)
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
    :class:`harness.contract.conventions.LineRule` (:mod:`harness.oracle.lines`). A rasterizer takes line
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

    # the constructor takes array-likes (lists too), which __post_init__ makes arrays
    if TYPE_CHECKING:
        def __init__(self, width: int, height: int, vertices: ArrayLike, strip_sizes: ArrayLike,
                     line_width: float = 1.0) -> None: ...

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

    def __reduce__(self) -> tuple[type, tuple]:
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

    def with_viewport(self, width: int, height: int) -> LineScene:
        """The same primitives on a ``width`` x ``height`` viewport."""
        return replace(self, width=width, height=height)
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


class AnyScene(Protocol):
    """A scene of any kind (:data:`harness.kinds.SCENE_KINDS`; :mod:`harness.kinds` holds what differs
    between them): what every scene class has, so that shrinking, moving, hashing and
    drawing a scene need not ask which kind it is."""

    @property
    def width(self) -> int: ...

    @property
    def height(self) -> int: ...

    @property
    def kind(self) -> str:
        """Its kind's name, the key of :data:`harness.kinds.KINDS`."""
        ...

    @property
    def noun(self) -> str:
        """What one primitive is called in messages and evidence."""
        ...

    def __len__(self) -> int:
        """Its number of primitives."""
        ...

    @property
    def n_attributes(self) -> int: ...

    def primitive_boxes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]: ...

    def non_finite(self) -> tuple[int, ...]: ...

    def edges(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]: ...

    @property
    def coordinates(self) -> NDArray[np.float64]: ...

    @property
    def attributes(self) -> NDArray[np.float64] | None:
        """Per-vertex values to interpolate (triangles only; None for the other kinds)."""
        ...

    def with_coordinates(self, coordinates: ArrayLike) -> AnyScene: ...

    def with_viewport(self, width: int, height: int) -> AnyScene: ...

    def subset(self, keep: ArrayLike) -> AnyScene: ...




def _counts_array(value: ArrayLike, field: str, owner: str = "PathScene") -> NDArray[np.int64]:
    array = np.asarray(value)
    if array.size == 0:
        return np.zeros(0, dtype=np.int64)
    if array.ndim != 1 or array.dtype.kind not in "iu":
        raise ValueError(f"{owner}.{field} must be a 1-D integer array, not {array.dtype} of shape {array.shape}")
    return np.array(array, dtype=np.int64)




@numba.njit(cache=True)
def _triangle_boxes(positions):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """:meth:`Scene.primitive_boxes` of (N, 3, 2) ``positions``: a non-finite coordinate
    counts as 0 in the box (meaningless there: ``finite`` says so)."""
    n = positions.shape[0]
    lo = np.empty((n, 2))
    hi = np.empty((n, 2))
    finite = np.ones(n, dtype=np.bool_)
    for t in range(n):
        for axis in range(2):
            low, high = np.inf, -np.inf
            for k in range(3):
                value = positions[t, k, axis]
                if not np.isfinite(value):
                    finite[t] = False
                    value = 0.0
                low = min(low, value)
                high = max(high, value)
            lo[t, axis] = low
            hi[t, axis] = high
    return lo, hi, finite


def _pixel_bounds(scene: AnyScene) -> NDArray[np.int64]:
    """(N, 4) int64: per primitive the pixels ``xmin, ymin, xmax, ymax`` (inclusive) any of
    its fragments may lie in under any convention: its bounding box grown by 2 px, clipped
    to the viewport (the whole viewport for a primitive with a NaN or infinite coordinate)."""
    lo, hi, finite = scene.primitive_boxes()
    bounds: NDArray[np.int64] = _bounds_kernel(np.ascontiguousarray(lo, dtype=np.float64),
                                               np.ascontiguousarray(hi, dtype=np.float64),
                                               np.ascontiguousarray(finite, dtype=np.bool_), int(scene.width), int(scene.height))
    return bounds


@numba.njit(cache=True)
def _bounds_kernel(lo, hi, finite, width, height):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """:func:`_pixel_bounds` of the boxes ``lo``, ``hi`` ((N, 2)) and ``finite`` ((N,))."""
    n = lo.shape[0]
    out = np.empty((n, 4), dtype=np.int64)
    limit = (width + 4.0, height + 4.0)
    most = (width - 1, height - 1)
    for t in range(n):
        for axis in range(2):
            if finite[t]:
                low = math.floor(min(max(lo[t, axis], -4.0), limit[axis])) - 2
                high = math.ceil(min(max(hi[t, axis], -4.0), limit[axis])) + 2
                out[t, axis] = max(int(low), 0)
                out[t, 2 + axis] = min(int(high), most[axis])
            else:
                out[t, axis] = 0
                out[t, 2 + axis] = most[axis]
    return out


def scene_digest(scene: AnyScene) -> bytes:
    """A digest of everything a scene holds (its kind, sizes, arrays and options): two
    scenes with equal digests are the same scene (to the oracle's answers kept, and to the
    answers drawn ahead by an isolated worker, :meth:`harness.engine.isolation.Worker.prefetch`).

    >>> a = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
    >>> same = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
    >>> scene_digest(a) == scene_digest(same), scene_digest(a) == scene_digest(a.with_viewport(9, 8))
    (True, False)
    """
    digest = hashlib.blake2b(type(scene).__name__.encode(), digest_size=20)
    for name in _field_names(type(scene)):
        value = getattr(scene, name)
        if isinstance(value, np.ndarray):
            digest.update(f"|{name}:{value.dtype.str}{value.shape}:".encode())
            digest.update(value.data if value.flags.c_contiguous else np.ascontiguousarray(value).data)
        else:
            digest.update(f"|{name}={value!r}".encode())
    return digest.digest()


@functools.cache
def _field_names(kind: type) -> tuple[str, ...]:
    """The dataclass fields of a scene type, in order (read once per type)."""
    return tuple(field.name for field in dataclasses.fields(cast(Any, kind)))


# The optional members of a Rasterizer, each read in one place.
