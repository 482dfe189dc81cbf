"""What a rasterizer returns: :class:`Coverage`, horizontal spans per primitive plus
interpolated attributes, per-sample layers or area alphas, and its canonical form.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.scenes import AnyScene, _pixel_bounds
from harness.geometry.exact import frozen
from harness.geometry.keys import composite, lexsort
from harness.geometry.spans import already_tidy, expand, pixel_offsets, run_tails, tidy


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


@dataclass(frozen=True, slots=True)
class AlphaRuns:
    """Area coverage held as runs: per span, one run of pixels of alpha exactly 1 and the
    alphas of the other pixels (the span's edge pixels) one by one.

    Span k of the coverage is cut in three: its left edge pixels ``x0[k] <= x <
    inner_x0[k]``, its inner run ``inner_x0[k] <= x < inner_x1[k]`` (alpha 1 each, held
    as two numbers) and its right edge pixels ``inner_x1[k] <= x < x1[k]``; a span with
    no inner run has ``inner_x0[k] == inner_x1[k]`` (anywhere in [x0, x1]).
    ``edge_alpha`` holds the alphas of the edge pixels in span order, left to right
    (left pixels, then right ones, span after span). This is how a span fill draws
    (cairo's and Pillow's scan converters: an anti-aliased edge cell by cell, the run
    between two edges as one span of full coverage), and what the exact area oracle
    (:func:`harness.oracle.area.area_coverage`) returns: its cost grows with the edge
    pixels, not with the area.

    Parameters
    ----------
    inner_x0, inner_x1 : (S,) int64
    edge_alpha : (E,) float64
    """

    inner_x0: NDArray[np.int64]
    inner_x1: NDArray[np.int64]
    edge_alpha: NDArray[np.float64]

    @property
    def nbytes(self) -> int:
        return int(self.inner_x0.nbytes + self.inner_x1.nbytes + self.edge_alpha.nbytes)


@numba.njit(cache=True)
def _spread_runs(x0, x1, inner_x0, inner_x1, edge_alpha, out):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """One alpha per pixel in span order from :class:`AlphaRuns` (1.0 on inner runs)."""
    m = 0
    e = 0
    for s in range(x0.size):
        for x in range(x0[s], x1[s]):
            if inner_x0[s] <= x < inner_x1[s]:
                out[m] = 1.0
            else:
                out[m] = edge_alpha[e]
                e += 1
            m += 1


@numba.njit(cache=True)
def _edge_pixels(x0, x1, inner_x0, inner_x1):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """The number of pixels outside the inner runs; -1 if an inner run leaves its span."""
    edges = 0
    outside = 0
    for s in range(x0.size):
        # without a branch, so that the loop runs on vectors
        outside += (x0[s] > inner_x0[s]) | (inner_x0[s] > inner_x1[s]) | (inner_x1[s] > x1[s])
        edges += (x1[s] - x0[s]) - (inner_x1[s] - inner_x0[s])
    return -1 if outside else edges


def _alpha_runs(runs: AlphaRuns, x0: NDArray[np.int64], x1: NDArray[np.int64]) -> AlphaRuns:
    """``runs`` checked against the spans (x0, x1) and made read-only int64 / float64 arrays."""
    if not isinstance(runs, AlphaRuns):
        raise ValueError(f"Coverage.runs must be an AlphaRuns, not {type(runs).__name__}")
    inner_x0, inner_x1 = _int_array(runs.inner_x0, "runs.inner_x0"), _int_array(runs.inner_x1, "runs.inner_x1")
    edge = np.asarray(runs.edge_alpha)
    if edge.ndim != 1 or edge.dtype.kind not in "biuf":
        raise ValueError(f"Coverage.runs.edge_alpha must be (E,) real numbers, not {edge.dtype} of shape {edge.shape}")
    edge = edge.view() if edge.dtype == np.float64 else edge.astype(np.float64)
    if not inner_x0.size == inner_x1.size == x0.size:
        raise ValueError("Coverage.runs needs one inner run per span")
    edges = _edge_pixels(x0, x1, inner_x0, inner_x1)
    if edges < 0:
        raise ValueError("Coverage.runs: each inner run must lie within its span (x0 <= inner_x0 <= inner_x1 <= x1)")
    if edge.size != edges:
        raise ValueError("Coverage.runs.edge_alpha must hold one alpha per pixel outside the inner runs")
    for array in (inner_x0, inner_x1, edge):
        array.setflags(write=False)
    return AlphaRuns(inner_x0, inner_x1, edge)


@dataclass(frozen=True, slots=True, eq=False, init=False)
class Coverage:
    """What a rasterizer covered: horizontal spans, plus interpolated attributes.

    Span k covers pixels ``x0[k] <= x < x1[k]`` of row ``y[k]`` for primitive
    ``primitive[k]``: the scene's triangle k of a triangle scene, its path k of a path
    scene (:attr:`triangle` is the same array under its triangle-scene name). A triangle
    covers one run per row, so cost grows with rows, not pixels. ``attributes`` has one row
    per covered pixel: the spans' pixels in span order, left to right within a span.

    The same spans carry the two other kinds of coverage (:attr:`Convention.coverage_kind`):

    * multisample: ``sample[k]`` says which sample of the pattern span k covers in each of
      its pixels (one run per primitive, sample and row); a fragment is then a (primitive,
      sample, pixel) and ``attributes`` has one row per fragment, in span order.
    * area (anti-aliased): ``alpha`` has one value per pixel in span order, the share of
      the pixel the primitive covers; a pixel left out has alpha 0. It may be given as
      ``runs`` instead (:class:`AlphaRuns`: each span's run of alpha 1 as two numbers, its
      edge pixels one by one): ``alpha`` is then derived from them when first read, and
      kept. Either way it is the same coverage (equality, canonical form, hygiene and the
      wire read ``alpha``); ``runs`` is None when alphas were given one per pixel.

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
    runs : AlphaRuns or None, keyword only
        Area coverage as runs, instead of ``alpha`` (not with it); its arrays are kept
        without a copy, like int64 span arrays.

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
    attributes: NDArray[np.float64] | None
    sample: NDArray[np.int64] | None
    runs: AlphaRuns | None
    # the alphas one per pixel: as given, or derived from ``runs`` when first read (``alpha``)
    _alpha: NDArray[np.float64] | None = dataclass_field(repr=False)

    def __init__(self, primitive: ArrayLike, y: ArrayLike, x0: ArrayLike, x1: ArrayLike,
                 attributes: ArrayLike | None = None, sample: ArrayLike | None = None,
                 alpha: ArrayLike | None = None, *, runs: AlphaRuns | None = None, _alpha: ArrayLike | None = None) -> None:
        # the constructor takes array-likes (lists too), which _check makes arrays. ``_alpha`` is
        # what dataclasses.replace hands over: the alphas as given, or (with runs) those derived
        # from the runs, dropped here (derived again when read)
        if _alpha is not None and runs is None and alpha is None:
            alpha = _alpha
        for name, value in (("primitive", primitive), ("y", y), ("x0", x0), ("x1", x1), ("attributes", attributes),
                            ("sample", sample), ("runs", runs), ("_alpha", alpha)):
            object.__setattr__(self, name, value)
        self._check()

    @property
    def alpha(self) -> NDArray[np.float64] | None:
        """Area coverage: the alpha of each pixel, in span order, (P,) float64; None for
        other coverage. Derived from :attr:`runs` on first read when given as runs."""
        if self._alpha is None and self.runs is not None:
            alpha = np.empty(self.n_pixels)
            _spread_runs(self.x0, self.x1, self.runs.inner_x0, self.runs.inner_x1, self.runs.edge_alpha, alpha)
            alpha.setflags(write=False)
            object.__setattr__(self, "_alpha", alpha)
        return self._alpha

    @property
    def nbytes(self) -> int:
        """Bytes of the arrays held (runs, not the alphas derived from them)."""
        held = (self.primitive, self.y, self.x0, self.x1, self.attributes, self.sample,
                self._alpha if self.runs is None else self.runs)
        return sum(int(a.nbytes) for a in held if a is not None)

    def _check(self) -> None:
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
        if self.runs is not None:
            if self._alpha is not None:
                raise ValueError("Coverage takes alpha or runs, not both")
            object.__setattr__(self, "runs", _alpha_runs(self.runs, self.x0, self.x1))
        if self._alpha is not None:
            alpha = np.asarray(self._alpha)
            if alpha.dtype.kind not in "biuf":
                raise ValueError(f"Coverage.alpha must hold real numbers, not dtype {alpha.dtype}")
            if alpha.ndim != 1:
                raise ValueError(f"Coverage.alpha must have shape (P,), not {alpha.shape}")
            alpha = np.array(alpha, dtype=np.float64, copy=True)
            alpha.setflags(write=False)
            object.__setattr__(self, "_alpha", alpha)

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

    @classmethod
    def from_boxes(cls, x0: ArrayLike, x1: ArrayLike, y0: ArrayLike, y1: ArrayLike) -> Coverage:
        """Primitive k covering the pixels ``x0[k] <= x < x1[k]`` of rows ``y0[k] <= y <
        y1[k]`` ((N,) int64 each; an empty box covers nothing): one span per row, sorted by
        primitive and row.

        >>> c = Coverage.from_boxes([1, 0], [3, 0], [0, 2], [2, 3])
        >>> c.primitive, c.y, c.x0, c.x1
        (array([0, 0]), array([0, 1]), array([1, 1]), array([3, 3]))
        """
        x0, x1, y0, y1 = (np.asarray(v, dtype=np.int64) for v in (x0, x1, y0, y1))
        rows = np.where(x1 > x0, np.maximum(y1 - y0, 0), 0)
        primitive = np.repeat(np.arange(rows.size, dtype=np.int64), rows)
        return cls(primitive, expand(y0, rows), np.repeat(x0, rows), np.repeat(x1, rows))

    @classmethod
    def from_layers(cls, layers: Sequence[Coverage]) -> Coverage:
        """One multisample answer from single-sample ones, layer k the answer at sample k
        of the pattern: each span carries its layer's index, sorted by primitive (stably:
        then by sample, then as each layer gave them).

        >>> both = Coverage.from_layers([Coverage([1, 0], [0, 0], [0, 2], [1, 3]), Coverage([0], [0], [1], [2])])
        >>> both.primitive, both.sample, both.x0
        (array([0, 0, 1]), array([0, 1, 0]), array([2, 1, 0]))
        """
        joined = cls.concat([cls(c.primitive, c.y, c.x0, c.x1, sample=np.full(len(c), k, dtype=np.int64))
                             for k, c in enumerate(layers)])
        return joined.take(np.argsort(joined.primitive, kind="stable"))

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
            (see :func:`harness.geometry.spans.tidy`), all empty when ``usable is self``; and
            ``repeated_pixels``, one number: the pixels emitted a second time.
        """
        from harness.contract.conventions import MAX_SAMPLES

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
        flaws["bad_primitive_id"] = np.setdiff1d(flaws["bad_primitive_id"],
                                                 bad_sample[(self.primitive[bad_sample] >= 0) & (self.primitive[bad_sample] < n)])
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


