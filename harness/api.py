"""The contract every rasterizer implements: Scene in, Coverage out.

A rasterizer is any object with ``name``, ``convention`` and ``rasterize(scene)`` (see
:class:`Rasterizer`); there is no base class to inherit. Screen space, conventions and
tie rules are defined in :mod:`harness.conventions`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.conventions import Convention
from harness.exact import frozen
from harness.spans import already_tidy, expand, pixel_offsets, run_tails, span_buffers, tidy

__all__ = ["Scene", "Coverage", "Convention", "Rasterizer", "span_buffers", "interpolates_of", "received_of", "fingerprint_of"]

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

    def __post_init__(self) -> None:
        for field in ("width", "height"):
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise ValueError(f"Scene.{field} must be an integer, not {value!r}")
            if not 1 <= value <= MAX_VIEWPORT:
                raise ValueError(f"Scene.{field} must lie in 1..{MAX_VIEWPORT}, not {value}")
            object.__setattr__(self, field, int(value))
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

    Span k covers pixels ``x0[k] <= x < x1[k]`` of row ``y[k]`` for triangle
    ``triangle[k]``. A triangle covers one run per row, so cost grows with rows, not
    pixels. ``attributes`` has one row per covered pixel: the spans' pixels in span
    order, left to right within a span.

    The constructor checks structure only (1-D integer arrays of one length, a 2-D
    float attribute array); whether spans are sensible is for the hygiene checks to say.
    int64 span arrays are kept without a copy (as read-only views): do not modify them
    afterwards through another reference.

    Parameters
    ----------
    triangle, y, x0, x1 : (S,) int64
    attributes : (P, K) float64 or None

    Examples
    --------
    >>> cov = Coverage.from_pixels([0, 0, 0, 1], [2, 3, 1, 0], [5, 5, 6, 5])
    >>> cov.triangle, cov.y, cov.x0, cov.x1
    (array([0, 0, 1]), array([5, 6, 5]), array([2, 1, 0]), array([4, 2, 1]))
    >>> cov.counts(4, 7)[5:]
    array([[1, 0, 1, 1],
           [0, 1, 0, 0]], dtype=int32)
    """

    triangle: NDArray[np.int64]
    y: NDArray[np.int64]
    x0: NDArray[np.int64]
    x1: NDArray[np.int64]
    attributes: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        arrays = {f: _int_array(getattr(self, f), f) for f in ("triangle", "y", "x0", "x1")}
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
        triangle: ArrayLike,
        x: ArrayLike,
        y: ArrayLike,
        attributes: ArrayLike | None = None,
    ) -> Coverage:
        """Build spans from individual fragments, in any order.

        Fragments are sorted by (triangle, y, x) and runs of consecutive x become spans. A
        fragment repeated for the same triangle stays a separate span, so the duplicate
        remains visible to the checks.

        Parameters
        ----------
        triangle, x, y : (P,) int
        attributes : (P, K) float64 or None, one row per fragment in the given order
        """
        tri = _int_array(triangle, "triangle")
        xs = _int_array(x, "x")
        ys = _int_array(y, "y")
        if not tri.size == xs.size == ys.size:
            raise ValueError("Coverage.from_pixels needs triangle, x and y of equal lengths")
        order = np.lexsort((xs, ys, tri))
        tri, xs, ys = tri[order], xs[order], ys[order]
        if attributes is not None:
            attributes = np.asarray(attributes, dtype=np.float64)
            if attributes.ndim != 2 or attributes.shape[0] != order.size:
                raise ValueError(
                    f"Coverage.from_pixels attributes must have shape ({order.size}, K), "
                    f"not {attributes.shape}"
                )
            attributes = attributes[order]
        new_span = np.ones(tri.size, dtype=bool)
        new_span[1:] = (tri[1:] != tri[:-1]) | (ys[1:] != ys[:-1]) | (xs[1:] != xs[:-1] + 1)
        heads = np.flatnonzero(new_span)
        tails = run_tails(heads, tri.size)
        return cls(tri[heads], ys[heads], xs[heads], xs[tails] + 1, attributes)

    @classmethod
    def from_mask(cls, triangle: int, mask: ArrayLike, attributes: ArrayLike | None = None) -> Coverage:
        """Build the spans of one triangle from an (H, W) boolean mask.

        Parameters
        ----------
        triangle : int
        mask : (H, W) bool
        attributes : (H, W, K) float64 or None, values at every pixel (only covered ones kept)

        Examples
        --------
        >>> Coverage.from_mask(3, [[0, 1, 1, 0, 1], [0, 0, 0, 0, 0]]).x0
        array([1, 4])
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
        return cls(np.full(rows.size, triangle), rows, starts, ends, values)

    @classmethod
    def concat(cls, parts: Iterable[Coverage]) -> Coverage:
        """One coverage from several, spans (and attribute rows) in the order given. All
        parts carry attributes, or none does.

        Examples
        --------
        >>> both = Coverage.concat([Coverage.from_mask(0, [[1, 1, 0]]), Coverage.from_mask(1, [[0, 1, 1]])])
        >>> both.triangle, both.x0, both.x1
        (array([0, 1]), array([0, 1]), array([2, 3]))
        """
        parts = list(parts)
        if not parts:
            return cls.empty()
        with_values = [p.attributes is not None for p in parts]
        if any(with_values) and not all(with_values):
            raise ValueError("Coverage.concat: some parts carry attributes and some do not")
        values = np.concatenate([p.attributes for p in parts if p.attributes is not None]) if all(with_values) else None
        triangle, y, x0, x1 = (np.concatenate([getattr(p, f) for p in parts]) for f in ("triangle", "y", "x0", "x1"))
        return cls(triangle, y, x0, x1, values)

    # -- views -----------------------------------------------------------------------

    def __len__(self) -> int:
        return int(self.triangle.size)

    @property
    def n_pixels(self) -> int:
        """Number of fragments: the sum of positive span lengths."""
        return int(np.maximum(self.x1 - self.x0, 0).sum())

    def pixels(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
        """Every fragment as (triangle, x, y), in span order, left to right.

        >>> Coverage([2], [1], [3], [5]).pixels()
        (array([2, 2]), array([3, 4]), array([1, 1]))
        """
        lengths = np.maximum(self.x1 - self.x0, 0)
        x = expand(self.x0, lengths)
        return np.repeat(self.triangle, lengths), x, np.repeat(self.y, lengths)

    def counts(self, width: int, height: int) -> NDArray[np.int32]:
        """Hits per pixel, (height, width) int32, from difference arrays (no fragments).

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

    def tidy(self, scene: Scene) -> tuple[Coverage, dict[str, NDArray[np.int64]]]:
        """What the checks may safely use of this coverage, and what was wrong with it.

        Works span by span, never pixel by pixel, so that a garbage answer (a span of
        10**8 pixels, a million copies of one span, spans far off-screen) costs time and
        memory in proportion to its number of spans, not to the pixels it claims. Keeps
        the pixels that can belong to their triangle: inside the viewport and within the
        triangle's bounding box grown by 2 px (the reach of any sample point in the pixel
        plus any snapping of a vertex by up to 1 px), each emitted once per triangle.

        Returns
        -------
        usable : Coverage
            ``self`` when nothing was wrong; else the kept spans, with the attribute rows
            of the kept pixels when there was one row per pixel (else none).
        flaws : dict of str -> (n,) int64
            Indices of offending spans: ``bad_triangle_id``, ``empty_or_reversed``,
            ``outside_viewport``, ``outside_triangle``, ``repeated``
            (see :func:`harness.spans.tidy`), all empty when ``usable is self``; and
            ``repeated_pixels``, one number: the pixels emitted a second time.
        """
        spans = (frozen(a, np.int64) for a in (self.triangle, self.y, self.x0, self.x1))
        if already_tidy(frozen(scene.positions), scene.width, scene.height, *spans):
            none = np.zeros(0, dtype=np.int64)
            kinds = ("bad_triangle_id", "empty_or_reversed", "outside_triangle", "repeated", "outside_viewport")
            return self, {**{kind: none for kind in kinds}, "repeated_pixels": np.zeros(1, dtype=np.int64)}
        bounds = _pixel_bounds(scene)
        keep, start, end, flaws, repeated_pixels = tidy(self.triangle, self.y, self.x0, self.x1, len(scene), bounds)
        t, y, x0, x1 = self.triangle, self.y, self.x0, self.x1
        outside = (y < 0) | (y >= scene.height) | (x0 < 0) | (x1 > scene.width)
        flaws["outside_viewport"] = np.flatnonzero(outside & (x0 < x1))
        flaws["outside_triangle"] = np.setdiff1d(flaws["outside_triangle"], flaws["outside_viewport"])
        flaws["repeated_pixels"] = np.array([repeated_pixels], dtype=np.int64)
        if not any(v.size for k, v in flaws.items() if k != "repeated_pixels"):
            return self, flaws
        attributes = None
        if self.attributes is not None and self.attributes.shape[0] == self.n_pixels:
            first = pixel_offsets(x0, x1)[keep] + (start - x0[keep])
            attributes = self.attributes[expand(first, end - start)]
        return Coverage(t[keep], y[keep], start, end, attributes), flaws

    def canonical(self) -> Coverage:
        """The same fragments in canonical form: spans sorted by (triangle, y, x0), empty
        spans dropped, touching spans of one triangle and row merged. Overlapping spans
        are kept apart, so a fragment emitted twice is still counted twice."""
        length = self.x1 - self.x0
        keep = np.flatnonzero(length > 0)
        order = keep[np.lexsort((self.x1[keep], self.x0[keep], self.y[keep], self.triangle[keep]))]
        tri, y, x0, x1 = self.triangle[order], self.y[order], self.x0[order], self.x1[order]
        attributes = self.attributes
        if attributes is not None:
            offsets = pixel_offsets(self.x0, self.x1)
            if attributes.shape[0] == offsets[-1]:
                attributes = attributes[expand(offsets[order], length[order])]
        joins = np.zeros(tri.size, dtype=bool)
        joins[1:] = (tri[1:] == tri[:-1]) & (y[1:] == y[:-1]) & (x0[1:] == x1[:-1])
        heads = np.flatnonzero(~joins)
        return Coverage(tri[heads], y[heads], x0[heads], x1[run_tails(heads, tri.size)], attributes)

    def __eq__(self, other: object) -> bool:
        """Exact equality of canonical forms (attributes too; NaN equals NaN)."""
        if not isinstance(other, Coverage):
            return NotImplemented
        a, b = self.canonical(), other.canonical()
        same_spans = all(
            np.array_equal(getattr(a, f), getattr(b, f)) for f in ("triangle", "y", "x0", "x1")
        )
        if not same_spans:
            return False
        if a.attributes is None or b.attributes is None:
            return a.attributes is None and b.attributes is None
        return a.attributes.shape == b.attributes.shape and bool(
            np.array_equal(a.attributes, b.attributes, equal_nan=True)
        )

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


def _pixel_bounds(scene: Scene) -> NDArray[np.int64]:
    """(N, 4) int64: per triangle the pixels ``xmin, ymin, xmax, ymax`` (inclusive) any of
    its fragments may lie in under any convention: its bounding box grown by 2 px, clipped
    to the viewport (the whole viewport for a triangle with a NaN or infinite coordinate)."""
    p = scene.positions
    out = np.empty((len(scene), 4), dtype=np.int64)
    finite: NDArray[np.bool_] = np.asarray(np.isfinite(p).all(axis=(1, 2)))
    q = np.where(np.isfinite(p), p, 0.0)
    lo = np.clip(q.min(axis=1, initial=np.inf), -4.0, [scene.width + 4.0, scene.height + 4.0])
    hi = np.clip(q.max(axis=1, initial=-np.inf), -4.0, [scene.width + 4.0, scene.height + 4.0])
    out[:, 0:2] = np.where(finite[:, None], np.floor(lo) - 2, 0)
    out[:, 2:4] = np.where(finite[:, None], np.ceil(hi) + 2, [scene.width - 1, scene.height - 1])
    out[:, 0:2] = np.maximum(out[:, 0:2], 0)
    out[:, 2] = np.minimum(out[:, 2], scene.width - 1)
    out[:, 3] = np.minimum(out[:, 3], scene.height - 1)
    return out


# The optional members of a Rasterizer, each read in one place.
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
