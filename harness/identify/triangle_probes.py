"""identify's probes: small experiments on a black-box rasterizer, each giving one typed fact;
here the triangle convention's: culling, the sample point, the snapping grid, the fit of
sample point and tie rule and where its residual lies. The robustness probes (viewport edge,
tiny, degenerate and non-finite triangles, watertightness) are
:mod:`harness.identify.triangle_defects`.

A probe calls the rasterizer only through a :data:`~harness.engine.isolation.Call` (a scene in,
an :class:`~harness.engine.isolation.Outcome` out: in this process, or in a worker process with
a time limit) and returns a frozen record of what it measured; the record's ``text`` is
the line the convention card prints. An outcome with an error -- the rasterizer raised,
returned something that is not a coverage, timed out or died -- is something the probe
saw and reports, never an exception of the probe's own. A garbage answer (spans of 10**8
pixels, far off-screen, naming triangles the scene lacks) is used tidied
(:meth:`harness.contract.coverage.Coverage.tidy`, see :class:`Drawn`), so that it costs time and memory
in proportion to its spans, not to the pixels it claims.

:func:`fit_ties` is the one fitting engine of sample point and tie rule: ``identify``
and ``compare`` both explain a rasterizer with it, so they cannot disagree.
"""

from __future__ import annotations

import hashlib
import heapq
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields, replace
from fractions import Fraction
from functools import cached_property
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import NDArray

from cases.scenes import lattice_triangles, random_triangles
from harness.checks import FragmentCounter, deviations
from harness.contract.conventions import (
    MAX_SUBPIXEL_BITS,
    SNAP_ROUNDING_WORDS,
    SNAP_ROUNDINGS,
    TIE_RULES,
    Convention,
    CullMode,
    SnapRounding,
)
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import SINGLE
from harness.contract.scenes import AnyScene, Scene
from harness.engine.isolation import Call, Outcome, describe
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage, scene_digest

__all__ = [
    "SAMPLES", "CANDIDATES", "SNAP_BITS", "RAW_PIXELS", "Fact", "Drawn", "draw",
    "Culling", "SampleSweep", "VertexSweep", "TieFit", "RoundingFit", "SnapFit", "ResidualLies",
    "culling", "sample_sweep", "vertex_sweep", "fit_ties", "fit_snapping", "residual_lies",
]

# The nine usual sample points: the centre, the four corners and the four edge midpoints.
SAMPLES: tuple[tuple[float, float], ...] = (
    (0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 1.0), (1.0, 0.5))
CANDIDATES = tuple(Convention(sample=s, tie=t) for s in SAMPLES for t in TIE_RULES)
SNAP_BITS = (None, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16)


class Fact(Protocol):
    """What a probe found; ``text`` is its line on the convention card."""

    @property
    def text(self) -> str: ...


# An answer is seen as it came -- off-screen, out-of-reach and repeated pixels included,
# as the hygiene check sees it -- when expanding it into pixels costs at most this many
# (24 MB); a larger one, or one naming triangles the scene lacks, is seen tidied.
RAW_PIXELS = 2**20


def _claimed(coverage: Coverage) -> float:
    """The pixels a coverage claims, in float64 (a garbage span's length may overflow an int64)."""
    return float(np.maximum(coverage.x1.astype(np.float64) - coverage.x0.astype(np.float64), 0.0).sum())


@dataclass(frozen=True)
class Drawn:
    """A scene and the rasterizer's answer to it.

    The probes see the answer as it came when that is affordable (:data:`RAW_PIXELS`), else
    tidied (:meth:`harness.contract.coverage.Coverage.tidy`) with the pixels the tidying dropped --
    off-screen, beyond a triangle's reach, or emitted twice -- counted (``dropped``):
    against any oracle they are extra, so the mismatches are the same either way. An
    unanswered scene (an error, a crash, a timeout) says nothing of the convention: it has
    no pixels and no mismatches, and is left out of every fit and residual.
    """

    scene: Scene
    outcome: Outcome

    @cached_property
    def coverage(self) -> Coverage | None:
        """The coverage the probes use, or None when the call gave an error."""
        raw, kept = self.outcome.received, self.outcome.coverage
        if raw is None or kept is None:
            return kept
        flaws = self.outcome.flaws or {}
        if _claimed(raw) <= RAW_PIXELS and not len(flaws.get("bad_primitive_id", ())):
            return raw
        return kept

    @property
    def error(self) -> BaseException | None:
        return self.outcome.error if self.outcome.coverage is None else None

    @cached_property
    def dropped(self) -> int:
        """Pixels of the answer as it came that :attr:`coverage` lacks."""
        raw, seen = self.outcome.received, self.coverage
        if raw is None or seen is None or seen is raw:
            return 0
        return max(0, int(_claimed(raw)) - seen.n_pixels)

    @property
    def pixels(self) -> int:
        """The pixels the rasterizer claimed (0 when unanswered)."""
        return 0 if self.coverage is None else self.coverage.n_pixels + self.dropped

    @cached_property
    def _counter(self) -> FragmentCounter:
        # the fragments are sorted once, then merged with each candidate's oracle
        return FragmentCounter(self.coverage or Coverage.empty(), self.scene.width, self.scene.height)

    @cached_property
    def _shared(self) -> tuple[dict[Convention, int], dict[tuple[Any, ...], int]]:
        """The scores of this answer to this scene: shared by every Drawn of the same scene
        answered alike (the path fit draws the triangle probes' scenes again, a multisample
        rasterizer's samples often answer alike), as the mismatches depend on nothing else."""
        coverage = self.coverage
        if coverage is None:
            return {}, {}
        answer = hashlib.blake2b(digest_size=20)
        for a in (coverage.primitive, coverage.y, coverage.x0, coverage.x1):
            answer.update(np.ascontiguousarray(a, dtype=np.int64).data)
            answer.update(b"|")
        key = (scene_digest(self.scene), answer.digest(), self.dropped)
        found = _SHARED_SCORES.get(key)
        if found is None:
            if len(_SHARED_SCORES) >= _SHARED_LIMIT:
                _SHARED_SCORES.clear()
            found = _SHARED_SCORES[key] = ({}, {})
        return found

    @property
    def _scores(self) -> dict[Convention, int]:
        return self._shared[0]

    @property
    def _by_vertices(self) -> dict[tuple[Any, ...], int]:
        return self._shared[1]

    @cached_property
    def _still(self) -> dict[tuple[int, str], bool]:
        return {}

    def _seen_as(self, convention: Convention) -> Convention:
        """``convention``, without its snapping when that moves no vertex of the scene (then
        the oracle is the same: identify's candidates differing only there share one)."""
        bits, rounding = convention.subpixel_bits, convention.snap_rounding
        if bits is None:
            return convention
        if (bits, rounding) not in self._still:
            positions = self.scene.positions
            self._still[bits, rounding] = bool(np.array_equal(convention.snap(positions), positions, equal_nan=True))
        if not self._still[bits, rounding]:
            return convention
        return replace(convention, subpixel_bits=None, snap_rounding="nearest-even")

    @cached_property
    def _vertices(self) -> dict[tuple[str, int | None, str], bytes]:
        return {}

    def _vertices_key(self, convention: Convention) -> tuple[Any, ...] | None:
        """For a single-sample convention: the vertices it sees (input precision and snapping
        applied) and the convention without either. The single-sample oracle reads the input
        and the snapping only through :meth:`Convention.snap` (the vertices it decides on),
        so two conventions with the same key have the same oracle on this scene: identify's
        candidates differing only in an input grid or a rounding that lands the vertices on
        the same points share one. None where that does not hold (other coverage models,
        attributes)."""
        if convention.model is not SINGLE or self.scene.attributes is not None:
            return None
        grid = (convention.input, convention.subpixel_bits, convention.snap_rounding)
        if grid not in self._vertices:
            seen = np.ascontiguousarray(convention.snap(self.scene.positions))
            self._vertices[grid] = hashlib.blake2b(seen.data, digest_size=20).digest()
        # every field but the three the vertices hold
        return (self._vertices[grid], *(getattr(convention, name) for name in _BARE_FIELDS))

    def mismatches(self, convention: Convention) -> int:
        """Missing plus extra pixels against the exact oracle of ``convention`` (0 when
        unanswered: no answer is not an answer of nothing)."""
        if self.coverage is None:
            return 0
        seen = self._seen_as(convention)
        if seen not in self._scores:
            key = self._vertices_key(seen)
            score = None if key is None else self._by_vertices.get(key)
            if score is None:
                score = self._counter.mismatches(exact_coverage(self.scene, seen)) + self.dropped
                if key is not None:
                    self._by_vertices[key] = score
            self._scores[seen] = score
        return self._scores[seen]


# (scene digest, answer digest, dropped) -> the scores of that answer (:attr:`Drawn._shared`), a
# bounded memory of this process's identifications
_SHARED_SCORES: dict[tuple[bytes, bytes, int], tuple[dict[Convention, int], dict[tuple[Any, ...], int]]] = {}
_SHARED_LIMIT = 4096

# the fields of a Convention besides its input precision and snapping (:meth:`Drawn._vertices_key`)
_BARE_FIELDS = tuple(f.name for f in fields(Convention) if f.name not in ("input", "subpixel_bits", "snap_rounding"))


def draw(call: Call, scene: Scene) -> Drawn:
    """``scene`` and the rasterizer's answer to it."""
    return Drawn(scene, call(scene))


def send(call: Call, scene: AnyScene) -> Outcome:
    """``call`` on a scene of any kind (a path-taking rasterizer's call takes path scenes)."""
    return call(scene)  # type: ignore[arg-type]


def _fit_score(drawn: list[Drawn], convention: Convention) -> int:
    """Mismatches on the answered scenes: an unanswered one says nothing of the convention,
    so it never steers a fit (nor counts in a residual)."""
    return sum(d.mismatches(convention) for d in drawn if d.coverage is not None)


def _fraction_bits(value: float) -> int:
    """The number of binary fraction digits of a float: 0 for an integer, 3 for 0.375.

    >>> _fraction_bits(0.375), _fraction_bits(2.0)
    (3, 0)
    """
    return max(0, value.as_integer_ratio()[1].bit_length() - 1)


# --- culling ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Culling:
    """Which windings a large clockwise and counter-clockwise triangle draw.

    ``seen`` is ``none`` (both drawn), ``cw`` or ``ccw`` (that one culled), ``both`` (neither
    drawn), or None when the rasterizer gave an error (``error``).
    """

    seen: Literal["none", "cw", "ccw", "both"] | None
    error: str = ""

    @property
    def cull(self) -> CullMode:
        """The culling the fit assumes (none unless exactly one winding is culled)."""
        return "cw" if self.seen == "cw" else "ccw" if self.seen == "ccw" else "none"

    @property
    def text(self) -> str:
        if self.seen is None:
            return f"not measured: the rasterizer raised {self.error}"[:120]
        return {"none": "draws both windings", "cw": "culls clockwise", "ccw": "culls counter-clockwise",
                "both": "draws neither winding"}[self.seen]


def culling(call: Call) -> Culling:
    """One large clockwise and one counter-clockwise triangle: which are drawn."""
    cw = np.array([[[4.25, 4.5], [40.5, 6.25], [8.75, 40.5]]])
    drawn = draw(call, Scene(48, 48, np.concatenate([cw, cw[:, ::-1] + np.array([2.0, 0.0])])))
    cov = drawn.coverage
    if cov is None:
        return Culling(None, describe(drawn.error))
    which = set(cov.triangle[cov.x1 > cov.x0].tolist())
    return Culling("none" if which == {0, 1} else "cw" if which == {1} else "ccw" if which == {0} else "both")


# --- the sample point, measured directly -------------------------------------------------


@dataclass(frozen=True, slots=True)
class SampleSweep:
    """Where an edge swept across a pixel flips it: the sample point, up to the snapping
    grid; None when the pixel never flips (the rasterizer raised, or draws nothing there)."""

    offset: tuple[float, float] | None
    resolution: int = 20

    @property
    def text(self) -> str:
        if self.offset is None:
            return "no flip found (the pixel never changed)"
        return (f"an edge swept across a pixel flips it at offset ({self.offset[0]:.6g}, {self.offset[1]:.6g}) "
                f"(bisected to 2^-{self.resolution} px; snapping moves it by up to one grid step)")


def sample_sweep(call: Call, resolution: int = 20) -> SampleSweep:
    """Sweep a vertical edge, then a horizontal one, across pixel (8, 30) / (30, 8) and find
    by bisection (to 2**-resolution px) the offset inside the pixel where its coverage
    flips: the sample point, measured directly, even off the nine usual ones."""
    found = []
    for axis in (0, 1):
        def covered(t: float, axis: int = axis) -> bool | None:
            edge = 8.0 + t
            tri = [[edge, 2.0], [edge, 60.0], [40.0, 31.0]] if axis == 0 else [[2.0, edge], [60.0, edge], [31.0, 40.0]]
            got = draw(call, Scene(64, 64, np.array([tri]))).coverage
            if got is None:
                return None
            _, x, y = got.pixels()
            px, py = (8, 30) if axis == 0 else (30, 8)
            return bool(np.any((x == px) & (y == py)))

        lo, hi = -0.5, 1.5  # the pixel is inside at lo (edge left of it), outside at hi
        if covered(lo) is not True or covered(hi) is not False:
            return SampleSweep(None, resolution)
        while hi - lo > 2.0**-resolution:
            mid = (lo + hi) / 2.0
            answer = covered(mid)
            if answer is None:
                return SampleSweep(None, resolution)
            lo, hi = (mid, hi) if answer else (lo, mid)
        found.append(lo if _fraction_bits(lo) <= _fraction_bits(hi) else hi)
    return SampleSweep((found[0], found[1]), resolution)


# --- the snapping grid, seen directly -------------------------------------------------------


@dataclass(frozen=True, slots=True)
class VertexSweep:
    """Where the coverage changes as one vertex moves: every change at a multiple of
    2**-grid px (``grid`` None when some change needs more than ``coarsest`` fraction bits:
    no snapping seen), ``located`` changes found; judged against the snapping fitted on
    float scenes once ``fitted`` is set (:meth:`judged`)."""

    grid: int | None
    located: int
    fitted: tuple[int | None, SnapRounding] | None = None
    resolution: int = 16
    coarsest: int = 12

    def judged(self, bits: int | None, rounding: SnapRounding) -> VertexSweep:
        """The same sweep, judged against the fitted snapping."""
        return replace(self, fitted=(bits, rounding))

    @property
    def text(self) -> str:
        if self.located == 0:
            return "no coverage change located (the rasterizer raised or drew nothing)"
        if self.grid is None:
            said = (f"{self.located} coverage changes at arbitrary offsets (bisected to 2^-{self.resolution} px): "
                    f"no vertex snapping down to 2^-{self.coarsest} px")
            if self.fitted is None:
                return said
            bits = self.fitted[0]
            return said + (" (agrees)" if bits is None else f" (the fit's {bits} bits are NOT confirmed)")
        nearest = self.grid - 1  # a grid rounded to nearest changes halfway between its points
        said = f"{self.located} coverage changes, all at multiples of 2^-{self.grid} px: vertices snap to " + (
            f"2^-{nearest} px rounding to nearest, or " if nearest >= 0 else "") + f"2^-{self.grid} px truncating"
        if self.fitted is None:
            return said
        bits, rounding = self.fitted
        fits = self.fitted in ((nearest, "nearest-even"), (nearest, "half-away"), (self.grid, "floor"),
                               (nearest, "half-away-shifted"))
        return said + (" (agrees with the fit)" if fits else
                       f" (the fit says {bits if bits is not None else 'none'}, {rounding}: not confirmed)")


# Triangles whose moving vertex (index 0) drags two edges across many sample points; the
# fixed vertices are off every coarse lattice, so without snapping the coverage changes at
# non-dyadic offsets.
_SWEEP_TRIANGLES = (
    ([10.0, 10.0], [41.7, 30.1], [12.2, 50.9]),
    ([30.0, 8.0], [9.3, 40.3], [50.1, 52.7]),
    ([52.0, 40.0], [8.9, 12.6], [20.4, 55.3]),
)


def vertex_sweep(call: Call, changes: int = 6, resolution: int = 16, coarsest: int = 12) -> VertexSweep:
    """Move one vertex along x (and, for the last triangle, y) and find, by bisection to
    2**-resolution px, the offsets where the coverage changes.

    The resolution stays coarser than float32's spacing at these coordinates (2**-18 below
    64 px), so a library that rounds its input to float32 moves a change by less than one
    step; unsnapped, a change lands within ``coarsest`` bits only by chance (1 in 8 each),
    and 18 of them all do with odds below 1e-16."""
    finest = 0
    located = 0
    for k, triangle in enumerate(_SWEEP_TRIANGLES):
        base = np.array(triangle, dtype=np.float64)
        axis = 1 if k == len(_SWEEP_TRIANGLES) - 1 else 0

        def cover(t: float, base: NDArray[np.float64] = base, axis: int = axis) -> Coverage | None:
            p = base.copy()
            p[0, axis] += t
            return draw(call, Scene(64, 64, p[None])).coverage

        lo, start = 0.0, cover(0.0)
        if start is None:
            return VertexSweep(None, located, resolution=resolution, coarsest=coarsest)
        for _ in range(changes):
            hi = lo + 1.0
            if cover(hi) == start:
                break
            while hi - lo > 2.0**-resolution:  # cover(lo) == start, cover(hi) differs
                mid = (lo + hi) / 2.0
                if cover(mid) == start:
                    lo = mid
                else:
                    hi = mid
            located += 1
            finest = max(finest, min(_fraction_bits(lo), _fraction_bits(hi)))
            lo, start = hi, cover(hi)
            if start is None:
                return VertexSweep(None, located, resolution=resolution, coarsest=coarsest)
    return VertexSweep(finest if finest <= coarsest else None, located, resolution=resolution, coarsest=coarsest)


# --- the fit of sample point and tie rule: the one fitting engine ---------------------------


def _tie_triangles(sample: tuple[float, float], seed: int, count: int = 200) -> NDArray[np.float64]:
    """Triangles whose vertices all sit on sample points (i + sx, j + sy) of a 48 px square
    (moved 4 px in), each with a horizontal or a vertical edge, both windings: every tie
    rule is exercised at this sample point.

    Returns
    -------
    (count, 3, 2) float64
    """
    rng = np.random.default_rng(seed + 11)
    base = rng.integers(6, 42, size=(count, 2)).astype(np.float64)
    a = rng.integers(1, 7, size=count) * rng.choice([-1, 1], size=count)
    c = rng.integers(-6, 7, size=(count, 2))
    c[:, 1] = np.where(c[:, 1] == 0, 1, c[:, 1])
    second = base.copy()
    horizontal = rng.random(count) < 0.5
    second[horizontal, 0] += a[horizontal]
    second[~horizontal, 1] += a[~horizontal]
    third = base + c
    triangles: NDArray[np.float64] = np.stack([base, second, third], axis=1) + np.array(sample) + 4.0
    return triangles


def _pinwheels(sample: tuple[float, float], sizes: tuple[int, ...] = (1, 2, 3)) -> NDArray[np.float64]:
    """piglit's probe: eight triangles around a sample point (split by the axes and
    diagonals, sizes in whole pixels), at 30 sample points of a 48 px square moved 4 px
    in. The sample is every triangle's vertex and lies on two edges of each; each of the
    eight tie rules gives it to exactly one triangle, a different one.

    Returns
    -------
    (240, 3, 2) float64
    """
    wheels = []
    rim = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], dtype=np.float64)
    for k in range(30):
        centre = np.array([6.0 + (k % 6) * 7.0, 6.0 + (k // 6) * 8.0]) + np.array(sample) + 4.0
        size = sizes[k % len(sizes)]
        for i in range(8):
            wheels.append([centre + size * rim[i], centre + size * rim[i + 1], centre])
    return np.array(wheels)


def _sample_candidates(measured: tuple[float, float] | None, grid: int | None = None) -> list[tuple[float, float]]:
    """The 9 usual sample points, plus the measured one at a few dyadic precisions (each
    clipped to [0, 1] and a multiple of 2**-12: a valid :class:`Convention` sample); with
    a vertex-sweep ``grid`` (snapping to 2**-(grid - 1) px rounding, or 2**-grid
    truncating), also the points of those grids on either side of it in each axis: a
    flip is where the *snapped* edge crosses the sample, up to a grid step from it, and
    rounding the measured point may pick the wrong side (dEQP's 77/256 under 8-bit
    snapping flips at 76.5/256).

    >>> _sample_candidates((0.2988, 0.5), 9)[9:]  # 77/256 under 8-bit snapping is the last
    [(0.25, 0.5), (0.3125, 0.5), (0.296875, 0.5), (0.298828125, 0.5), (0.30078125, 0.5)]
    """
    samples = list(SAMPLES)
    if measured is None:
        return samples
    for bits in (1, 2, 3, 4, 6, 8, 12):
        sx, sy = (min(1.0, max(0.0, round(v * 2**bits) / 2**bits)) for v in measured)
        if (sx, sy) not in samples:
            samples.append((sx, sy))
    if grid is not None:
        samples += [s for s in grid_sides(measured, (grid - 1, grid)) if s not in samples]
    return samples


def grid_sides(measured: tuple[float, float], grids: Sequence[int]) -> list[tuple[float, float]]:
    """The points of each 2**-b px grid (b in ``grids``, 0..12 only: a valid
    :class:`Convention` sample) on either side of a measured sample point in each axis,
    clipped to [0, 1]: where a sample lies whose flip, measured with snapped edges, is
    up to a grid step off.

    >>> grid_sides((0.3027, 0.5), [8])
    [(0.30078125, 0.5), (0.3046875, 0.5)]
    """
    out: list[tuple[float, float]] = []
    for bits in grids:
        if not 0 <= bits <= 12:
            continue
        scale = 2.0**bits
        sides = [sorted({min(1.0, max(0.0, math.floor(v * scale) / scale)), min(1.0, max(0.0, math.ceil(v * scale) / scale))})
                 for v in measured]
        out += [(sx, sy) for sx in sides[0] for sy in sides[1] if (sx, sy) not in out]
    return out


def _snap_candidates(grid: int | None) -> list[tuple[int | None, SnapRounding]]:
    """No snapping, and the snappings a vertex-sweep grid of 2**-grid px allows: rounding
    to nearest on the grid one bit coarser, or truncating on it; only those a
    :class:`Convention` can hold (0..16 bits: a garbage sweep may suggest others)."""
    snaps: list[tuple[int | None, SnapRounding]] = [(None, "nearest-even")]
    if grid is not None:
        snaps += [(grid - 1, "nearest-even"), (grid - 1, "half-away"), (grid, "floor"), (grid - 1, "half-away-shifted")]
    return [(b, r) for b, r in snaps if b is None or 0 <= b <= MAX_SUBPIXEL_BITS]


@dataclass(frozen=True)
class TieFit:
    """The candidate convention (sample point x tie rule x the snappings the vertex sweep
    allows, with the measured culling) that best explains the rasterizer on the tie scenes,
    and the runner-up that differs from it in sample point or tie rule.

    ``drawn`` holds the scenes and answers: four lattice scenes, then tie triangles and
    pinwheels at the best sample point; ``culling``, ``sweep`` and ``vertex`` the probes
    that chose the candidates.
    """

    best: Convention
    mismatches: int
    runner_up: Convention
    runner_up_mismatches: int
    candidates: int
    drawn: tuple[Drawn, ...] = field(repr=False)
    culling: Culling
    sweep: SampleSweep
    vertex: VertexSweep

    @property
    def pixels(self) -> int:
        return sum(d.pixels for d in self.drawn)

    @property
    def text(self) -> str:
        """The runner-up, as the card's "next best" line says it."""
        return f"{self.runner_up.describe()} ({self.runner_up_mismatches} mismatches on the tie scenes)"


def fit_ties(call: Call, seed: int = 0) -> TieFit:
    """Fit sample point and tie rule: the one fitting engine (identify and compare).

    Culling, the sample sweep and the vertex sweep choose the candidates: the 9 usual
    sample points plus the measured one, x the 8 tie rules, x no snapping and the
    snappings the sweep's grid allows. Each is scored by its mismatches on four lattice
    scenes, then on tie triangles and pinwheels at the best sample point so far; ties in
    the score go to the earlier candidate. Only answered scenes steer the fit and count in
    the mismatches reported.

    Parameters
    ----------
    call : Call
        The rasterizer, as a function of a scene.
    seed : int
        Seeds the lattice scenes and the tie triangles.

    Returns
    -------
    TieFit
    """
    found = culling(call)
    sweep = sample_sweep(call)
    vertex = vertex_sweep(call)
    candidates = [Convention(sample=sample, tie=tie, cull=found.cull, subpixel_bits=b, snap_rounding=r)
                  for b, r in _snap_candidates(vertex.grid) for sample in _sample_candidates(sweep.offset, vertex.grid)
                  for tie in TIE_RULES]
    # lattice triangles reach 2 px past a 48 px square; moved 4 px into a 56 px screen
    # (exactly) nothing crosses the viewport edge, so clipping cannot blur the convention
    drawn = [draw(call, Scene(56, 56, lattice_triangles(120, 48, bits, seed + bits) + 4.0)) for bits in (0, 1, 2, 4)]
    least = LeastMismatches(drawn, candidates)
    # then ties at the best sample point: vertices on samples, axis-aligned edges through
    # rows of them, and pinwheels, so that every tie rule shows there
    sample = least.first()[0].sample
    for ties in (_tie_triangles(sample, seed), _pinwheels(sample)):
        drawn.append(draw(call, Scene(56, 56, ties)))  # scored on them too (least holds drawn)
    best = least.first()[0]
    # the runner-up differs in sample point or tie rule (snapping cannot show on lattices)
    runner = least.first(lambda c: (c.sample, c.tie) != (best.sample, best.tie))[0]
    return TieFit(best, sum(d.mismatches(best) for d in drawn), runner, sum(d.mismatches(runner) for d in drawn),
                  len(candidates), tuple(drawn), found, sweep, vertex)


class LeastMismatches:
    """The candidate with least mismatches on the answered scenes of ``drawn`` (a list the
    caller may extend: later scenes count from then on), ties to the first listed, found
    without summing every candidate on every scene: best first by partial sums, a
    candidate summed on one scene more only while its partial sum (a lower bound of its
    total) is the least. The answer is that of summing them all and sorting by (total,
    index).

    >>> from harness.contract.coverage import Coverage
    >>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    >>> drawn = [Drawn(scene, Outcome(Coverage([0, 0, 0], [0, 1, 2], [0, 0, 0], [3, 2, 1])))]  # the top-left rule's
    >>> least = LeastMismatches(drawn, [Convention(tie=t) for t in ("bottom-right", "top-left", "top-right")])
    >>> [(c.tie, total) for c, total in (least.first(), least.first(lambda c: c.tie != "top-left"))]
    [('top-left', 0), ('bottom-right', 4)]
    """

    def __init__(self, drawn: list[Drawn], candidates: Sequence[Convention]) -> None:
        self.drawn = drawn
        self.candidates = list(candidates)
        # index -> (partial sum, scenes summed)
        self.partial = [(0, 0)] * len(self.candidates)

    def first(self, eligible: Callable[[Convention], bool] | None = None) -> tuple[Convention, int]:
        """The eligible candidate (every one when None) with least mismatches over every scene
        of ``drawn``, first listed among equals, and its total; IndexError when none is eligible."""
        heap = [(self.partial[i][0], i) for i, c in enumerate(self.candidates) if eligible is None or eligible(c)]
        heapq.heapify(heap)
        while heap:
            total, i = heap[0]
            done = self.partial[i][1]
            if done == len(self.drawn):
                # every other's partial sum, a lower bound of its total, is at least this (ties: a later index)
                return self.candidates[i], total
            d = self.drawn[done]
            total += d.mismatches(self.candidates[i]) if d.coverage is not None else 0
            self.partial[i] = (total, done + 1)
            heapq.heapreplace(heap, (total, i))
        raise IndexError("no candidate is eligible")


# --- snapping, fitted on floats ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class RoundingFit:
    """Mismatches of each rounding with every vertex on a half step of the 2**-bits grid
    (where the roundings part), best first; ``tied``, the roundings that explain it as well
    as the best."""

    bits: int
    scores: tuple[tuple[SnapRounding, int], ...]
    tied: tuple[SnapRounding, ...]

    @property
    def text(self) -> str:
        return ("; ".join(f"{r}: {score} mismatches" for r, score in self.scores)
                + f" (with every vertex on a half step of the 2^-{self.bits} grid)")


@dataclass(frozen=True)
class SnapFit:
    """The sub-pixel bits and rounding that best explain the rasterizer on unconstrained
    floats (with the fitted sample point and tie rule), and the final convention."""

    convention: Convention
    mismatches: int
    rounding_fit: RoundingFit | None
    drawn: tuple[Drawn, ...] = field(repr=False)

    @property
    def bits(self) -> int | None:
        return self.convention.subpixel_bits

    @property
    def rounding(self) -> SnapRounding:
        return self.convention.snap_rounding

    @property
    def ambiguous(self) -> tuple[str, ...]:
        """The roundings that explain it equally well, when more than one does."""
        tied = self.rounding_fit.tied if self.rounding_fit is not None else ()
        return tuple(f"{self.bits} bits {r}" for r in tied) if len(tied) > 1 else ()

    @property
    def text(self) -> str:
        said = "none detected" if self.bits is None else f"{self.bits} sub-pixel bits, " + SNAP_ROUNDING_WORDS[self.rounding]
        return said + f" ({self.mismatches} float mismatches)"


def _half_steps(scene: Scene, bits: int) -> Scene:
    """The scene with every coordinate moved onto an odd multiple of 2**-(bits+1) -- a half
    step of the 2**-bits grid, where rounding to nearest must break a tie -- and kept at
    least 1 px from the origin (a frame's rounding sign plays no part there)."""
    scale = 2.0**bits
    moved = (np.floor(np.abs(scene.positions) * scale) + 0.5) / scale + 1.0
    return Scene(scene.width, scene.height, moved)


def _half_steps_near_origin(scene: Scene, bits: int) -> Scene:
    """:func:`_half_steps`, with each triangle's first vertex moved onto a half step in
    (0, 1/2) on both axes: there rounding half away from zero (up) and piglit's rounding half
    away from the pixel centre line c = 1/2 (down) part, and nowhere else."""
    moved = _half_steps(scene, bits).positions.copy()
    steps = 2.0 ** (bits - 1)  # half steps in (0, 1/2): (k + 1/2) / 2**bits, k < 2**(bits-1)
    k = np.floor((np.abs(scene.positions[:, 0]) % 1.0) * steps)
    moved[:, 0] = (k + 0.5) / 2.0**bits
    # only triangles inside the viewport: one crossing its edge near the origin would show how the
    # rasterizer treats the edge (the viewport-edge probe's business), not how it rounds
    inside = ((moved >= 0.0) & (moved <= np.array([scene.width, scene.height], dtype=np.float64))).all(axis=(1, 2))
    return Scene(scene.width, scene.height, moved[inside])


def fit_snapping(call: Call, seed: int, ties: TieFit) -> SnapFit:
    """With the fitted sample point and tie rule, the number of sub-pixel bits (or none)
    and the rounding that best explain two scenes of unconstrained floats, where snapping
    shows; then, with every vertex on a half step of that grid, where the roundings part,
    the rounding again.

    Parameters
    ----------
    call : Call
    seed : int
        Seeds the float scenes.
    ties : TieFit
        The fitted sample point, tie rule and culling (:func:`fit_ties`).

    Returns
    -------
    SnapFit
        Its ``convention`` is the one identify reports.
    """
    best = ties.best

    def fitted(bits: int | None, rounding: SnapRounding) -> Convention:
        return Convention(sample=best.sample, tie=best.tie, subpixel_bits=bits, cull=best.cull, snap_rounding=rounding)

    floats = [draw(call, Scene(48, 48, random_triangles(150, 60.0, 48, seed + k))) for k in range(2)]
    scores: list[tuple[int, int, int | None, SnapRounding]] = []
    for bits in SNAP_BITS:
        for rounding in SNAP_ROUNDINGS if bits is not None else ("nearest-even",):
            score = _fit_score(floats, fitted(bits, rounding))
            # ties prefer no snapping, then rounding to nearest even
            scores.append((score, 0 if bits is None else 1 + SNAP_ROUNDINGS.index(rounding), bits, rounding))
    scores.sort(key=lambda s: (s[0], s[1]))
    _, _, bits, rounding = scores[0]
    mismatches = sum(d.mismatches(fitted(bits, rounding)) for d in floats)
    rounding_fit = None
    if bits is not None:
        # floats almost never sit on a half step, where nearest-even and half-away part:
        # put every vertex on one, and fit the rounding there
        floats += [draw(call, _half_steps(d.scene, bits)) for d in floats]
        if bits >= 1:  # and half steps in the first half pixel, where piglit's shifted frame parts from half-away
            floats.append(draw(call, _half_steps_near_origin(floats[0].scene, bits)))
        ranked = sorted((_fit_score(floats, fitted(bits, r)), SNAP_ROUNDINGS.index(r), r) for r in SNAP_ROUNDINGS)
        rounding = ranked[0][2]
        rounding_fit = RoundingFit(bits, tuple((r, sum(d.mismatches(fitted(bits, r)) for d in floats)) for _, _, r in ranked),
                                   tuple(r for score, _, r in ranked if score == ranked[0][0]))
    return SnapFit(fitted(bits, rounding), mismatches, rounding_fit, tuple(floats))


# --- where the residual lies ------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ResidualLies:
    """Where the lattice residual lies: samples exactly at a vertex, exactly on an edge of
    non-dyadic or of dyadic slope, or off every edge; and pixels that cannot be their
    triangles' at all (off-screen, out of reach, repeated)."""

    at_vertex: int
    non_dyadic: int
    dyadic: int
    off: int
    dropped: int = 0

    @property
    def text(self) -> str:
        said = (f"{self.at_vertex} exactly at a vertex, {self.non_dyadic} exactly on edges of non-dyadic slope dx/dy, "
                f"{self.dyadic} exactly on dyadic-slope edges, {self.off} off every edge")
        if self.dropped:
            said += f", {self.dropped} where they cannot belong (off-screen, out of reach or repeated)"
        return said + " (lattice scenes)"


def residual_lies(drawn: tuple[Drawn, ...], convention: Convention, limit: int = 5000) -> ResidualLies:
    """Classify up to ``limit`` deviating pixels per scene against ``convention``: exactly
    at a vertex (the vertex rule), exactly on an edge whose slope dx/dy is not a dyadic
    fraction (an exact edge function decides those like any other; stepping x by dx/dy in
    floating point rounds there), exactly on a dyadic-slope edge, or off every edge (a
    different rule, not a tie). An unanswered scene deviates by all its oracle's pixels."""
    at_vertex = non_dyadic = dyadic = off = 0
    for d in drawn:
        scene = d.scene
        missing, extra = deviations(d.coverage or Coverage.empty(), exact_coverage(scene, convention),
                                    scene.width, scene.height)
        both = np.concatenate([missing, extra], axis=1)[:, :limit]
        if not both.shape[1]:
            continue
        p = convention.snap(scene.positions)[both[0]]
        samples = np.stack([both[1] + convention.sample[0], both[2] + convention.sample[1]], axis=-1)
        kinds = np.zeros(both.shape[1], dtype=np.int8)  # 0 off, 1 dyadic slope, 2 non-dyadic
        for k in range(3):
            a, b = p[:, k], p[:, (k + 1) % 3]
            on = orientation(np.stack([a, b, samples], axis=1)) == 0
            for i in np.flatnonzero(on):
                dx, dy = Fraction(float(b[i, 0] - a[i, 0])), Fraction(float(b[i, 1] - a[i, 1]))
                slope_dyadic = dy == 0 or ((dx / dy).denominator & ((dx / dy).denominator - 1)) == 0
                kinds[i] = max(kinds[i], 1 if slope_dyadic else 2)
        vertex = np.any(np.all(p == samples[:, None, :], axis=2), axis=1)  # the sample is a vertex
        at_vertex += int(vertex.sum())
        non_dyadic += int(((kinds == 2) & ~vertex).sum())
        dyadic += int(((kinds == 1) & ~vertex).sum())
        off += int((kinds == 0).sum())
    return ResidualLies(at_vertex, non_dyadic, dyadic, off, sum(d.dropped for d in drawn))
