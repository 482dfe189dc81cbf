"""The exact oracle: what any declared convention says a scene must cover.

For each triangle and each row, the edges that reach the row bound the covered sample
columns from either side (a triangle is the intersection of three half-planes, so a
row's covered samples form one run). Each bound comes from the edge's float crossing
with a rigorous error bound: when no column boundary lies within that bound, the crossing
is certainly not a tie and the column follows. Otherwise it is settled exactly at the
boundary pixel with :func:`harness.geometry.exact.orient2d_sign` -- a float filter with an exact
expansion fallback -- stepping or bisecting until the exact predicate agrees. The error
bound only tells when the float answer is already certain; it never changes an answer.
Triangles with coordinates beyond the expansions' safe range (|c| > 2**450, or nonzero
|c| < 2**-450) take an exact rational path in Python.

Attributes are interpolated at each covered pixel's sample point from the snapped
positions: affine, or perspective-correct ``sum(l_i a_i / w_i) / sum(l_i / w_i)`` when
the scene has ``w``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import math
import os
import threading
from collections import OrderedDict
from collections.abc import Iterator, Sequence
from dataclasses import replace
from fractions import Fraction
from typing import Any, cast

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention, owns_edge
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import SINGLE
from harness.contract.samples import pattern
from harness.contract.scenes import AnyScene, Scene, scene_digest
from harness.engine import ledger
from harness.geometry.exact import frozen, orientation
from harness.geometry.spans import expand, pixel_offsets, span_buffers
from harness.kinds import kind_of
from harness.oracle.kernels import _apply_edge, _edge_setup, _row_range, interpolate_at, shares_of_layers
from harness.oracle.multisample import fused_samples, fused_shares, multisample_spans

__all__ = ["exact_coverage", "exact_single", "exact_samples", "exact_multisample", "sample_shares", "exact_coverage_python",
           "prepare_triangles", "PreparedTriangles", "scene_digest", "exact_samples_layers", "exact_multisample_layers",
           "sample_shares_layers"]


_CULL_CODES = {"none": 0, "cw": 1, "ccw": -1}


@numba.njit(cache=True)
def _orient_kernel(positions, sign, cull, tie_x, tie_y, y_first, sy, height, out_owned, out_active):  # type: ignore[no-untyped-def]
    """Activity and edge ownership of each triangle, taken with its vertices in oriented
    order (0, 1, 2) when A > 0 and (0, 2, 1) when A < 0; returns an upper bound on the
    rows the active ones span (the span buffers' capacity)."""
    rows = 0
    for t in range(positions.shape[0]):
        s = sign[t]
        # Zero-area and non-finite triangles cover nothing; cull 1 removes A > 0 (cw).
        active = s != 0 and s != cull
        out_active[t] = active
        if not active:
            continue
        # Orient every triangle clockwise on screen (A > 0): the interior is where all
        # three edge functions are positive.
        order = (0, 2, 1) if s < 0 else (0, 1, 2)
        for k in range(3):
            a, b = order[k], order[(k + 1) % 3]
            ax, ay = positions[t, a, 0], positions[t, a, 1]
            bx, by = positions[t, b, 0], positions[t, b, 1]
            # The tie rule: with A > 0 the interior is where E_ab > 0, and the edge owns
            # its samples when E is positive at the sample moved by the rule's
            # perturbation (harness.contract.conventions).
            out_owned[t, k] = owns_edge(ax, ay, bx, by, tie_x, tie_y, y_first)
        first, last = _row_range(
            min(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1]),
            max(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1]),
            sy,
            height,
        )
        rows += max(last - first + 1, 0)
    return rows


class PreparedTriangles:
    """A scene's triangles after snapping, culling and orienting, ready for a kernel.

    Every array has one row per scene triangle.

    Attributes
    ----------
    snapped : (N, 3, 2) float64
        Snapped vertices, in scene order.
    sign : (N,) int8
        Exact sign of the snapped signed area (0: non-finite or degenerate).
    owned : (N, 3) bool
        Whether edge k (vertex k to vertex k+1) owns samples lying exactly on it.
    active : (N,) bool
        Finite, nonzero area, not culled: the triangles that may cover anything.
    safe : (N,) bool
        Coordinates within the range of exact expansion arithmetic (else rationals).
    rows : int
        An upper bound on the rows the active triangles span.
    """

    __slots__ = ("snapped", "sign", "owned", "active", "safe", "rows", "_oriented")

    def __init__(self, scene: Scene, convention: Convention) -> None:
        # input precision, then snapping: Convention.snap applies both, first, exactly
        self.snapped = frozen(convention.snap(scene.positions))
        n = self.snapped.shape[0]
        self.safe = np.empty(n, dtype=np.bool_)
        self.sign = orientation(self.snapped, self.safe)
        self.owned = np.empty((n, 3), dtype=np.bool_)
        self.active = np.empty(n, dtype=np.bool_)
        self.rows = int(
            _orient_kernel(
                self.snapped, self.sign, _CULL_CODES[convention.cull], *convention.tie_perturbation,
                convention.sample[1], scene.height, self.owned, self.active,
            )
        )
        self._oriented: NDArray[np.float64] | None = None

    @property
    def positions(self) -> NDArray[np.float64]:
        """(N, 3, 2) float64: snapped vertices, reordered so that the signed area is positive."""
        if self._oriented is None:
            self._oriented = frozen(np.take_along_axis(self.snapped, self.vertex_order[:, :, None], axis=1))
        return self._oriented

    @property
    def vertex_order(self) -> NDArray[np.int64]:
        """(N, 3) int64: which scene vertex each row of ``positions`` came from."""
        return np.where((self.sign < 0)[:, None], np.array([0, 2, 1]), np.array([0, 1, 2]))

    @property
    def index(self) -> NDArray[np.int64]:
        """Scene indices of the active triangles."""
        return np.flatnonzero(self.active)


def prepare_triangles(scene: Scene, convention: Convention) -> PreparedTriangles:
    """Snap, cull, orient and classify the edges of a scene's triangles."""
    return PreparedTriangles(scene, convention)


# -- the compiled span kernel -------------------------------------------------------------


@numba.njit(cache=True, error_model="numpy")
def _span_kernel(positions, sign, owned, use, sx, sy, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        # Vertices in oriented order (A > 0): swap the last two when A < 0.
        v1, v2 = (1, 2) if sign[t] > 0 else (2, 1)
        x0, y0 = positions[t, 0, 0], positions[t, 0, 1]
        x1, y1 = positions[t, v1, 0], positions[t, v1, 1]
        x2, y2 = positions[t, v2, 0], positions[t, v2, 1]
        o0, o1, o2 = owned[t, 0], owned[t, 1], owned[t, 2]
        ymin = min(y0, y1, y2)
        ymax = max(y0, y1, y2)
        first, last = _row_range(ymin, ymax, sy, height)
        if first > last:
            continue
        y_first, y_last = first + sy, last + sy
        lo0, hi0, s0, d0 = _edge_setup(x0, y0, x1, y1, y_first, y_last)
        lo1, hi1, s1, d1 = _edge_setup(x1, y1, x2, y2, y_first, y_last)
        lo2, hi2, s2, d2 = _edge_setup(x2, y2, x0, y0, y_first, y_last)
        for j in range(first, last + 1):
            ys = j + sy
            if ys < ymin or ys > ymax:
                continue  # the conservative row range may overshoot by a row
            left, right = _apply_edge(x0, y0, x1, y1, lo0, hi0, s0, d0, o0, sx, ys, width, 0, width)
            left, right = _apply_edge(x1, y1, x2, y2, lo1, hi1, s1, d1, o1, sx, ys, width, left, right)
            left, right = _apply_edge(x2, y2, x0, y0, lo2, hi2, s2, d2, o2, sx, ys, width, left, right)
            if left < right:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = left
                out_x1[n] = right
                n += 1
    return n


@numba.njit(cache=True)
def interpolate_kernel(positions, values, inv_w, perspective, span_t, span_y, span_x0, span_x1, sx, sy, out):  # type: ignore[no-untyped-def]
    """Barycentric interpolation at each sample: l_i = E_i / (E_0 + E_1 + E_2)."""
    row = 0
    for s in range(span_t.size):
        t = span_t[s]
        p = positions[t]
        ys = span_y[s] + sy
        for i in range(span_x0[s], span_x1[s]):
            interpolate_at(p, values, inv_w, t, perspective, i + sx, ys, out, row)
            row += 1


# -- the exact rational path (extreme magnitudes, and a cross-check in tests) ------------


def _rows_python(
    p: NDArray[np.float64], owned: NDArray[np.bool_], sx: float, sy: float, width: int, height: int
) -> list[tuple[int, int, int]]:
    """Exact (row, x0, x1) runs of one oriented triangle, in rational arithmetic."""
    v = [(Fraction(p[k, 0]), Fraction(p[k, 1])) for k in range(3)]
    fsx, fsy = Fraction(sx), Fraction(sy)
    ys_all = [q[1] for q in v]
    first = max(0, math.ceil(min(ys_all) - fsy))
    last = min(height - 1, math.floor(max(ys_all) - fsy))
    runs = []
    for j in range(first, last + 1):
        ys = j + fsy
        left, right = 0, width
        for k in range(3):
            (ax, ay), (bx, by) = v[k], v[(k + 1) % 3]
            if ay == by:
                inside = bool(owned[k]) if ys == ay else (bx > ax) == (ys > ay)
                if not inside:
                    right = 0
                continue
            xc = ax + (bx - ax) * (ys - ay) / (by - ay) - fsx  # crossing, in column units
            if by < ay:  # inside when i > xc (i >= xc if owned)
                left = max(left, math.ceil(xc) if owned[k] else math.floor(xc) + 1)
            else:  # inside when i < xc (i <= xc if owned)
                right = min(right, math.floor(xc) + 1 if owned[k] else math.ceil(xc))
        if left < right:
            runs.append((j, left, right))
    return runs


def _barycentric_planes(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """(3, 3) float64: l_i(x, y) = c[i,0] + c[i,1]*x + c[i,2]*y, coefficients rounded once
    from their exact rational values (no cancellation, whatever the magnitudes)."""
    v = [(Fraction(p[k, 0]), Fraction(p[k, 1])) for k in range(3)]
    area = (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[1][1] - v[0][1]) * (v[2][0] - v[0][0])
    planes = np.empty((3, 3))
    for i in range(3):
        (ax, ay), (bx, by) = v[(i + 1) % 3], v[(i + 2) % 3]
        # E_ab(x, y) = (bx-ax)*(y-ay) - (by-ay)*(x-ax), split into constant, x and y parts.
        planes[i] = [
            float((-(bx - ax) * ay + (by - ay) * ax) / area),
            float(-(by - ay) / area),
            float((bx - ax) / area),
        ]
    return planes


def _interpolate_python(
    planes: NDArray[np.float64],
    values: NDArray[np.float64],
    inv_w: NDArray[np.float64] | None,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
) -> NDArray[np.float64]:
    weights = planes[:, 0][None, :] + x[:, None] * planes[:, 1] + y[:, None] * planes[:, 2]
    if inv_w is not None:
        weights = weights * inv_w[None, :]
    interpolated: NDArray[np.float64] = (weights @ values) / weights.sum(axis=1, keepdims=True)
    return interpolated


# -- public entry points ------------------------------------------------------------------


def _vertex_values(scene: Scene, prepared: PreparedTriangles) -> tuple[NDArray, NDArray]:
    """Per-vertex values and 1/w in each triangle's oriented vertex order (1/w = 1 affine)."""
    assert scene.attributes is not None
    values = np.take_along_axis(scene.attributes, prepared.vertex_order[:, :, None], axis=1)
    if scene.w is None:
        return frozen(values), frozen(np.ones((len(scene), 3)))
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_w = 1.0 / np.take_along_axis(scene.w, prepared.vertex_order, axis=1)
    return frozen(values), frozen(inv_w)


class _RecentAnswers:
    """The oracle's recent answers, keyed by the scene's contents and the convention, within
    a budget of bytes (least recently used out first); safe across threads.

    A scene is judged by several checks, candidates and rasterizers with one convention
    (identify scores about 80 candidate conventions on the same probe scenes for every
    rasterizer it fingerprints; a suite's cases meet every rasterizer that declares the same
    convention), so the same answer was computed again and again. An answer is the same
    object each time: a :class:`Coverage` is frozen and its arrays read-only.
    """

    def __init__(self, budget: int) -> None:
        self.budget = budget
        self._answers: OrderedDict[tuple[bytes, Convention], Coverage] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()

    def get(self, key: tuple[bytes, Convention]) -> Coverage | None:
        with self._lock:
            answer = self._answers.get(key)
            if answer is not None:
                self._answers.move_to_end(key)
            return answer

    def put(self, key: tuple[bytes, Convention], answer: Coverage) -> None:
        size = _footprint(answer)
        if size > self.budget // 8:  # a huge answer would push out everything else
            return
        with self._lock:
            if key in self._answers:
                return
            self._answers[key] = answer
            self._bytes += size
            while self._bytes > self.budget:
                _, old = self._answers.popitem(last=False)
                self._bytes -= _footprint(old)

    def clear(self) -> None:
        with self._lock:
            self._answers.clear()
            self._bytes = 0

    @contextlib.contextmanager
    def off(self) -> Iterator[None]:
        """Nothing kept or reused inside (and what was kept, dropped): every answer computed
        -- what a benchmark must time (its repeats would otherwise time a lookup)."""
        budget, self.budget = self.budget, 0
        self.clear()
        try:
            yield
        finally:
            self.budget = budget


def _footprint(coverage: Coverage) -> int:
    # Coverage.nbytes: an area answer's runs, not the alphas derived from them (reading
    # them here would derive them)
    return coverage.nbytes + 200


# Only scenes this small are kept: the digest reads every byte of a scene (half a
# millisecond for 10,000 triangles, a third of the oracle's own time on them), and the
# scenes met again and again -- identify's probes, the suites' cases -- are small.
KEPT_SCENE_BYTES = 1 << 16


def _scene_bytes(scene: AnyScene) -> int:
    return sum(getattr(scene, field.name).nbytes for field in dataclasses.fields(cast(Any, scene))
               if isinstance(getattr(scene, field.name), np.ndarray))


RECENT_ANSWERS = _RecentAnswers(int(os.environ.get("RASTERCHECK_ORACLE_CACHE_MB", "64")) << 20)


def exact_coverage(scene: AnyScene, convention: Convention) -> Coverage:
    """Exactly what ``convention`` says ``scene`` covers, with reference attributes.

    Parameters
    ----------
    scene : Scene, PathScene or LineScene
    convention : Convention

    Returns
    -------
    Coverage
        Spans sorted by primitive then row (a path scene's:
        :func:`harness.oracle.winding.path_coverage`), clipped to the viewport.
        Non-finite, zero-area and culled triangles cover nothing. ``attributes`` is (P,
        K) when the scene has attributes, interpolated at each covered sample
        (perspective-correct when the scene has ``w``). For a multisample convention,
        spans carry their sample index (:func:`exact_multisample`); for area coverage,
        alphas (:func:`harness.oracle.area.area_coverage`).

    Examples
    --------
    A right triangle whose hypotenuse runs through four pixel centres. The hypotenuse is
    a right edge (the interior lies to its left), so the top-left rule leaves those
    samples out and the bottom-right rule takes them in.

    >>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    >>> exact_coverage(scene, Convention()).counts(4, 4)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [1, 0, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    >>> exact_coverage(scene, Convention(tie="bottom-right")).counts(4, 4)
    array([[1, 1, 1, 1],
           [1, 1, 1, 0],
           [1, 1, 0, 0],
           [1, 0, 0, 0]], dtype=int32)
    """
    if not RECENT_ANSWERS.budget or _scene_bytes(scene) > KEPT_SCENE_BYTES:
        return _exact_coverage(scene, convention)
    key = (scene_digest(scene), convention)
    answer = RECENT_ANSWERS.get(key)
    if answer is None:
        answer = _exact_coverage(scene, convention)
        RECENT_ANSWERS.put(key, answer)
    return answer


def _exact_coverage(scene: AnyScene, convention: Convention) -> Coverage:
    with ledger.section("oracle"):
        coverage: Coverage = kind_of(scene).hook("oracle")(scene, convention)
    return coverage


def exact_triangles(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene (the oracle of :data:`harness.kinds.TRIANGLES`):
    the convention's coverage model names its oracle (exact_single, exact_multisample,
    sample_shares or harness.oracle.area.area_coverage)."""
    coverage: Coverage = convention.model.exact_triangles(scene, convention)
    return coverage


def exact_single(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under a single-sample convention (the
    oracle of :data:`harness.contract.coverage_models.SINGLE`; :func:`exact_coverage` caches it):
    spans sorted by triangle then row, with attributes interpolated at the sample point.

    >>> exact_single(Scene(3, 3, [[[0, 0], [3, 0], [0, 3]]]), Convention()).counts(3, 3).tolist()  # top-left: no hypotenuse
    [[1, 1, 0], [1, 0, 0], [0, 0, 0]]
    """
    prepared = PreparedTriangles(scene, convention)
    sx, sy = convention.sample
    fast = prepared.active & prepared.safe
    out = span_buffers(prepared.rows)
    n = int(_span_kernel(prepared.snapped, prepared.sign, prepared.owned, fast, sx, sy, scene.width, scene.height, *out))
    triangle, y, x0, x1 = (a[:n] for a in out)

    attributes = None
    if scene.attributes is not None:
        values, inv_w = _vertex_values(scene, prepared)
        attributes = np.empty((int((x1 - x0).sum()), scene.n_attributes))
        interpolate_kernel(
            prepared.positions, values, inv_w, scene.w is not None, triangle, y, x0, x1, sx, sy, attributes
        )

    slow = np.flatnonzero(prepared.active & ~prepared.safe)
    extra: list[tuple[int, int, int, int]] = []
    extra_values = []
    for m in slow:
        runs = _rows_python(prepared.positions[m], prepared.owned[m], sx, sy, scene.width, scene.height)
        extra.extend((int(m), j, a, b) for j, a, b in runs)
        if attributes is not None and runs:
            cols = np.concatenate([np.arange(a, b) for _, a, b in runs]) + sx
            rows = np.concatenate([np.full(b - a, j) for j, a, b in runs]) + sy
            planes = _barycentric_planes(prepared.positions[m])
            inv = inv_w[m] if scene.w is not None else None
            extra_values.append(_interpolate_python(planes, values[m], inv, cols, rows))
    if extra:
        e = np.array(extra, dtype=np.int64)
        triangle = np.concatenate([triangle, e[:, 0]])
        y = np.concatenate([y, e[:, 1]])
        x0 = np.concatenate([x0, e[:, 2]])
        x1 = np.concatenate([x1, e[:, 3]])
        order = np.argsort(triangle, kind="stable")  # back into triangle order
        if attributes is not None:
            attributes = np.concatenate([attributes, *extra_values])
            attributes = attributes[expand(pixel_offsets(x0, x1)[order], (x1 - x0)[order])]
        triangle, y, x0, x1 = triangle[order], y[order], x0[order], x1[order]
    return Coverage(triangle, y, x0, x1, attributes)


def exact_coverage_python(scene: Scene, convention: Convention) -> Coverage:
    """The oracle's spans from the rational path alone, for every triangle (no attributes).

    Slow; a second, independent implementation of the same rows for tests.
    """
    prepared = PreparedTriangles(scene, convention)
    sx, sy = convention.sample
    spans = [
        (int(m), j, a, b)
        for m in prepared.index
        for j, a, b in _rows_python(
            prepared.positions[m], prepared.owned[m], sx, sy, scene.width, scene.height
        )
    ]
    if not spans:
        return Coverage.empty()
    t, y, x0, x1 = np.array(spans, dtype=np.int64).T
    return Coverage(t, y, x0, x1)


def exact_samples(scene: Scene, convention: Convention, samples: int | Sequence[Sequence[float]]) -> list[Coverage]:
    """Exactly which samples of a multisample pattern each triangle covers.

    Each sample obeys the convention's tie rule, snapping and culling at its own offset
    (the standard multisample rule: D3D11, Vulkan, GL), so the exact single-sample oracle
    at each offset is the exact multisample oracle.

    Parameters
    ----------
    scene : Scene
    convention : Convention
        Its ``sample`` is not used: the pattern's offsets stand in its place.
    samples : int or sequence of (x, y)
        A standard pattern's count (1, 2, 4, 8, 16) or the offsets themselves
        (:func:`harness.contract.samples.pattern`).

    Returns
    -------
    list of Coverage
        One per sample, in pattern order: the pixels whose sample k the triangle covers.

    Examples
    --------
    The standard 4x pattern under the hypotenuse x + y = 2: in the pixels beside it,
    samples 0 and 2 lie inside, samples 1 and 3 outside.

    >>> scene = Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]])
    >>> [cov.counts(2, 2).tolist() for cov in exact_samples(scene, Convention(), 4)]
    [[[1, 1], [1, 0]], [[1, 0], [0, 0]], [[1, 1], [1, 0]], [[1, 0], [0, 0]]]
    """
    offsets = pattern(samples)
    if convention.model is SINGLE:
        # every sample from one setup per triangle (harness.oracle.multisample)
        prepared = PreparedTriangles(scene, convention)
        values = None if scene.attributes is None else _vertex_values(scene, prepared)
        layers = fused_samples(scene, prepared, offsets, values)
        if layers is not None:
            return layers
    return exact_samples_layers(scene, convention, offsets)


def exact_samples_layers(scene: Scene, convention: Convention,
                         samples: int | Sequence[Sequence[float]]) -> list[Coverage]:
    """:func:`exact_samples` the former way, the single-sample oracle once per offset: the
    reference the fused kernel (:mod:`harness.oracle.multisample`) is tested against, and
    the path of triangles beyond the expansions' safe range."""
    return [exact_coverage(scene, at_offset) for at_offset in _at_each_offset(convention, pattern(samples))]


@functools.lru_cache(maxsize=512)
def _at_each_offset(convention: Convention, offsets: tuple[tuple[float, float], ...]) -> tuple[Convention, ...]:
    """``convention`` sampled at each offset (built once: identify asks for the same few
    patterns thousands of times)."""
    return tuple(replace(convention, sample=offset) for offset in offsets)



def exact_multisample(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a multisample convention as one Coverage: the spans of
    :func:`exact_samples` with their sample index, sorted by triangle, sample and row
    (attributes interpolated at each sample).

    >>> cov = exact_multisample(Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]]), Convention(samples=4))
    >>> cov.sample.tolist(), cov.y.tolist(), cov.x1.tolist()
    ([0, 0, 1, 2, 2, 3], [0, 1, 0, 0, 1, 0], [2, 1, 1, 2, 1, 1])
    """
    offsets = convention.samples if convention.samples is not None else (convention.sample,)
    # the samples of each triangle decided together, written in (triangle, sample, row)
    # order (harness.oracle.multisample); beyond the safe range, sample by sample
    prepared = PreparedTriangles(scene, _single(convention))
    values = None if scene.attributes is None else _vertex_values(scene, prepared)
    fused = multisample_spans(scene, prepared, offsets, values)
    return fused if fused is not None else exact_multisample_layers(scene, convention)


@functools.lru_cache(maxsize=512)
def _single(convention: Convention) -> Convention:
    """``convention`` without its pattern (built once: identify asks for the same few
    conventions thousands of times)."""
    return replace(convention, samples=None)


def exact_multisample_layers(scene: Scene, convention: Convention) -> Coverage:
    """:func:`exact_multisample` the former way: the single-sample oracle at each offset
    (:func:`exact_samples_layers`), concatenated and sorted; the reference of the fused
    kernel in tests and the path beyond the expansions' safe range."""
    offsets = convention.samples if convention.samples is not None else (convention.sample,)
    layers = exact_samples_layers(scene, replace(convention, samples=None), offsets)
    sample = np.repeat(np.arange(len(layers), dtype=np.int64), [len(c) for c in layers])
    spans = [np.concatenate([getattr(c, f) for c in layers]) for f in ("triangle", "y", "x0", "x1")]
    attributes = None if scene.attributes is None else np.concatenate([c.attributes for c in layers])
    joined = Coverage(spans[0], spans[1], spans[2], spans[3], attributes, sample)
    # each layer is sorted by (triangle, row) and the layers follow in sample order: a
    # stable sort on the triangle gives (triangle, sample, row)
    order = np.argsort(joined.triangle, kind="stable")
    return joined.take(order)


def sample_shares(scene: Scene, convention: Convention) -> Coverage:
    """The oracle of a supersampled area convention: per (triangle, pixel), the share of
    the pattern's samples it covers (each sample under the tie rule, snapping and
    culling), as ``alpha``; exact (a count over the number of samples).

    >>> sample_shares(Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]]), Convention(coverage="area", samples=4)).alpha.tolist()
    [1.0, 0.5, 0.5]
    """
    # the samples of one pixel row counted together (harness.oracle.multisample)
    prepared = PreparedTriangles(scene, convention.point_sampled())
    fused = fused_shares(scene, prepared, convention.samples, convention.n_samples)
    return fused if fused is not None else sample_shares_layers(scene, convention)


def sample_shares_layers(scene: Scene, convention: Convention) -> Coverage:
    """:func:`sample_shares` the former way, from the layers of
    :func:`exact_samples_layers`: the fused kernel's reference in tests and the path
    beyond the expansions' safe range."""
    single = convention.point_sampled()
    return shares_of_layers(exact_samples_layers(scene, single, convention.samples), scene.height, convention.n_samples)
