"""identify's probes for area (anti-aliased) coverage, measured from outside: the levels of edge
sweeps, a supersampler's sample grid, the quantisation (:func:`alpha_sweeps`) and the input
grid (:func:`input_grid`), on the corner probes of :mod:`harness.identify.coverage_probes`.

- :func:`alpha_sweeps`: a vertical, a horizontal and a slanted edge swept across a pixel
  in steps of 1/256 px, and two scenes of random float triangles. The distinct alphas of
  each sweep are its *levels*: an analytic anti-aliaser shows about one per step, a
  supersampler with n sample columns and m sample rows n + 1 and m + 1, stepping where
  the edge passes a sample. Those steps are bisected to 2**-20 px, and the samples found
  on each axis are paired up by corner probes between them (inclusion-exclusion gives
  how many samples lie in each cell), so that a regular grid and a sparse pattern
  (n-rooks) are both recovered. The quantisation is the coarsest 1/d of which every
  alpha seen is a multiple.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from cases.scenes import random_triangles
from harness.contract.conventions import (
    MAX_AREA_SAMPLES,
    MAX_SUBPIXEL_BITS,
    PLAIN_SNAP_ROUNDINGS,
    TIE_RULES,
    Convention,
    CullMode,
    SnapRounding,
)
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.engine.isolation import Call, Outcome, describe
from harness.geometry.keys import union
from harness.identify.coverage_probes import (
    Remembered,
    _alpha_at,
    _corner,
    _fraction_bits,
    _layout,
    _offset,
    _probe_scene,
    _slant,
    _wheels,
)
from harness.identify.triangle_probes import _half_steps, _snap_candidates, culling
from harness.oracle.coverage import exact_coverage

__all__ = ["SWEEP_STEPS", "SLACK", "quantum", "AxisSweep", "SweepFact", "InputGrid", "alpha_sweeps", "input_grid"]

# Sweeps step the edge by 1/SWEEP_STEPS px: exact (dyadic) positions on any snapping grid
# of 8 bits or finer, so snapping never moves a sweep's edge.
SWEEP_STEPS = 256
# At most this many sample columns (rows) make a sweep "stepped": a 64 x 64 supersampler
# still shows as one, an analytic anti-aliaser (a level per step) never does.
MAX_STEPPED_LEVELS = 65
# The most samples a recovered supersampling pattern may have (a 64 x 64 grid).
MAX_CELLS = 64 * 64
# Alphas are compared with their oracle up to this much beyond the promised tolerance:
# the area oracle's float error (<= 2**-24, harness.oracle.area.area_error_bound) plus an alpha
# computed in float32 (relative error 2**-24).
SLACK = 2.0**-20
# The finest quantisation looked for: alphas multiples of 1/65536 at most; finer is
# "continuous", which a convention holds as its finest levels (2**24).
FINEST_QUANTUM = 2**16
CONTINUOUS_LEVELS = 2**24


# --- quantisation ----------------------------------------------------------------------------


def quantum(alphas: NDArray[np.float64], finest: int = FINEST_QUANTUM) -> int | None:
    """The smallest d <= ``finest`` such that every alpha is a multiple of 1/d (up to its
    float32 rounding: ``|alpha * d - k| <= 1e-7 d``), or None (continuous). A random
    alpha passes for a given d with odds 2e-7 d (at most 1.3 %): a probe's hundreds of
    alphas leave no d by chance, a handful may.

    >>> quantum(np.array([0.25, 0.5, 1.0])), quantum(np.array([4 / 255, 1.0])), quantum(np.random.default_rng(0).random(50))
    (4, 255, None)
    """
    candidates = np.arange(1, finest + 1, dtype=np.float64)
    alphas = np.asarray(alphas, dtype=np.float64)
    if not np.all(np.isfinite(alphas)):
        return None
    for alpha in np.unique(alphas):
        scaled = alpha * candidates
        candidates = candidates[np.abs(scaled - np.rint(scaled)) <= 1e-7 * candidates + 1e-12]
        if not candidates.size:
            return None
    return int(candidates[0])


# --- alpha differences ---------------------------------------------------------------------------


def _keyed(coverage: Coverage, scene: Scene) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    t, x, y = coverage.pixels()
    alpha = coverage.alpha if coverage.alpha is not None and coverage.alpha.shape[0] == t.size else np.ones(t.size)
    return (t * scene.height + y) * scene.width + x, alpha


def alpha_differences(got: Coverage, want: Coverage, scene: Any) -> NDArray[np.float64]:
    """alpha - wanted alpha at every (triangle, pixel) either holds (a missing one has 0)."""
    kg, ag = _keyed(got, scene)
    kw, aw = _keyed(want, scene)
    keys = union(kg, kw)
    g = np.zeros(keys.size)
    w = np.zeros(keys.size)
    np.add.at(g, np.searchsorted(keys, kg), ag)
    np.add.at(w, np.searchsorted(keys, kw), aw)
    return g - w


@dataclass(frozen=True)
class _AlphaDrawn:
    """An area scene and the rasterizer's answer, with its differences from each
    candidate's oracle computed once."""

    scene: Scene
    outcome: Outcome
    _cache: dict[Convention, NDArray[np.float64]] = field(default_factory=dict, repr=False, compare=False)
    _still: dict[tuple[int | None, str], bool] = field(default_factory=dict, repr=False, compare=False)

    @property
    def coverage(self) -> Coverage | None:
        return self.outcome.coverage

    def differences(self, convention: Convention) -> NDArray[np.float64]:
        """alpha - the oracle's alpha of ``convention`` at every (triangle, pixel) either
        holds; a snapping that moves no vertex of the scene shares the unsnapped oracle."""
        snapping = (convention.subpixel_bits, convention.snap_rounding)
        if snapping[0] is not None:
            if snapping not in self._still:
                self._still[snapping] = bool(np.array_equal(convention.snap(self.scene.positions), self.scene.positions))
            if self._still[snapping]:
                convention = replace(convention, subpixel_bits=None, snap_rounding="nearest-even")
        if convention not in self._cache:
            self._cache[convention] = alpha_differences(self.coverage or Coverage.empty(),
                                                         exact_coverage(self.scene, convention), self.scene)
        return self._cache[convention]

    def beyond(self, convention: Convention) -> int:
        """(triangle, pixel)s whose alpha is further from the oracle's than the convention's
        tolerance allows."""
        return int(np.sum(np.abs(self.differences(convention)) > convention.alpha_tolerance + SLACK))


# --- area: sweeps, grid and levels ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class AxisSweep:
    """One sweep of an edge across a pixel in ``steps`` steps: the distinct alphas seen
    (``levels``), the largest |alpha - exact area|, and for a stepped sweep each step
    bisected (``jumps``: the interval (lo, hi) of edge offsets, one bisection step wide,
    in which the alpha drops, and by how much)."""

    axis: Literal["vertical", "horizontal", "slanted"]
    steps: int
    levels: int
    max_error: float
    jumps: tuple[tuple[float, float, float], ...] = ()

    @property
    def positions(self) -> tuple[float, ...]:
        """The jumps' offsets, each the end of its interval with fewer fraction bits."""
        return tuple(_offset(lo, hi) for lo, hi, _ in self.jumps)

    @property
    def text(self) -> str:
        said = f"{self.axis} edge: {self.levels} levels in {self.steps} steps"
        if self.jumps:
            said += " stepping at " + " ".join(f"{p:.6g}" for p in self.positions)
        return said


Model = Literal["analytic", "supersampled", "hybrid"]


@dataclass(frozen=True)
class SweepFact:
    """What the sweeps say of an anti-aliaser.

    ``model``: ``analytic`` (alpha tracks the area: a level per step), ``supersampled``
    (both axial sweeps stepped: ``pattern`` holds the recovered offsets, row by row,
    ``layout`` says their shape), or ``hybrid`` (one axis stepped, the other not: say,
    sub-scanlines with exact coverage along them); None when the rasterizer gave an
    error. ``levels``: alphas are multiples of 1/(levels - 1) (None: continuous).
    ``max_error`` and ``mean_error``: |alpha - exact area| over every pixel of the
    sweeps and the float scenes. ``convention``: the candidate (with the measured
    tolerance when the alphas stray further than half a level from its oracle);
    ``residual``: the (triangle, pixel)s, of ``pixels`` compared, whose alpha lies more
    than half a level from the candidate's oracle (a measured tolerance is reported,
    never claimed: such a rasterizer is a best guess), ``max_residual`` the largest
    |alpha - oracle|; ``runner_up``: the next supersampled candidate (another tie rule).
    ``grid``: the input grid fitted (:func:`input_grid`; the convention's snapping).
    ``calls``: the rasterizer calls made.
    """

    model: Model | None
    vertical: AxisSweep | None = None
    horizontal: AxisSweep | None = None
    slanted: AxisSweep | None = None
    levels: int | None = None
    max_error: float = 0.0
    mean_error: float = 0.0
    pattern: tuple[tuple[float, float], ...] | None = None
    layout: str = ""
    convention: Convention | None = None
    residual: int = 0
    max_residual: float = 0.0
    pixels: int = 0
    runner_up: tuple[str, int] | None = None
    calls: int = 0
    error: str = ""
    grid: InputGrid | None = None
    drawn: tuple[_AlphaDrawn, ...] = field(default=(), repr=False, compare=False)
    quantisation: QuantisationFit | None = None

    @property
    def levels_text(self) -> str:
        """The quantisation and the levels per sweep, in words."""
        quantised = ("continuous (no quantisation down to 1/65536)" if self.levels is None
                     else f"{self.levels} levels (alpha a multiple of 1/{self.levels - 1})")
        sweeps = " / ".join(f"{s.levels}" for s in (self.vertical, self.horizontal, self.slanted) if s is not None)
        return f"{quantised}; {sweeps} levels on the vertical / horizontal / slanted sweeps of {SWEEP_STEPS} steps"

    @property
    def grid_text(self) -> str:
        """The grid (or its absence), in words."""
        if self.model == "analytic":
            return "alpha tracks the exact area (about a level per sweep step), no sample grid"
        if self.model == "hybrid":
            stepped = next(s for s in (self.vertical, self.horizontal) if s is not None and s.jumps)
            axis, other = ("columns (x)", "y") if stepped.axis == "vertical" else ("rows (y)", "x")
            return (f"{len(stepped.jumps)} sample {axis} at " + " ".join(f"{p:.6g}" for p in stepped.positions)
                    + f", exact along {other}")
        if self.pattern is None:
            return "the pattern was not recovered"
        xs = sorted({x for x, _ in self.pattern})
        ys = sorted({y for _, y in self.pattern})
        if len(self.pattern) == len(xs) * len(ys):  # a full grid: its columns and rows say it all
            said = (f"{self.layout}: columns at " + " ".join(f"{x:.6g}" for x in xs) + ", rows at "
                    + " ".join(f"{y:.6g}" for y in ys))
        else:
            said = f"{self.layout}: " + " ".join(f"({x:.6g}, {y:.6g})" for x, y in self.pattern)
        if len(self.pattern) > MAX_AREA_SAMPLES:
            said += f" (more than the {MAX_AREA_SAMPLES} samples a convention holds: judged as area within a tolerance)"
        return said

    @property
    def text(self) -> str:
        if self.model is None:
            return f"not measured: {self.error}"[:160]
        return (f"{self.model}: {self.grid_text}; {self.levels_text}; |alpha - area| max {self.max_error:.3g}, "
                f"mean {self.mean_error:.3g}")

    def lines(self) -> dict[str, str]:
        """The card's lines: the model and grid, the levels, the area error, the sweeps."""
        if self.model is None:
            return {"model": self.text}
        return {"model": f"{self.model}: {self.grid_text}", "levels": self.levels_text,
                "area error": f"|alpha - exact area| max {self.max_error:.3g}, mean {self.mean_error:.3g} over {self.pixels} "
                              "(triangle, pixel)s",
                "sweeps": "; ".join(s.text for s in (self.vertical, self.horizontal, self.slanted) if s is not None)} | (
                {} if self.grid is None else {"input grid": self.grid.text}) | (
                {} if self.quantisation is None else {"quantisation": self.quantisation.text})


def _sweep_shapes() -> tuple[NDArray[np.float64], slice, slice, slice, NDArray[np.float64], NDArray[np.float64]]:
    """The three sweeps' probes in one array, where each sweep lies in it, and the offsets
    of the axial sweeps (-1/256 .. 1) and of the slanted one (-1/4 .. 5/4)."""
    axial = np.arange(-1, SWEEP_STEPS + 1) / SWEEP_STEPS
    slanted = np.arange(-SWEEP_STEPS // 4, SWEEP_STEPS * 5 // 4 + 1) / SWEEP_STEPS
    shapes = np.concatenate([[_corner(t, -2.0) for t in axial], [_corner(-2.0, t) for t in axial],
                             [_slant(t) for t in slanted]])
    n = axial.size
    return shapes, slice(0, n), slice(n, 2 * n), slice(2 * n, 2 * n + slanted.size), axial, slanted


def _refine(call: Call, cull: CullMode, jumps: list[tuple[int, float, float, float, float]],
            resolution: int, drawn: list[_AlphaDrawn], limit: int = 512) -> list[tuple[int, float, float, float, float]] | None:
    """Bisect every interval (axis, lo, hi, alpha at lo, alpha at hi) of edge offsets whose
    ends differ, all at once (one call per halving), down to 2**-resolution px; an
    interval whose middle differs from both ends splits in two. None when an answer was
    missing or the intervals multiply past ``limit`` (no monotone step function)."""
    while jumps and jumps[0][2] - jumps[0][1] > 2.0**-resolution:
        mids = [(lo + hi) / 2.0 for _, lo, hi, _, _ in jumps]  # exact: dyadic
        shapes = np.array([_corner(m, -2.0) if axis == 0 else _corner(-2.0, m) for (axis, *_), m in zip(jumps, mids)])
        probes = _probe_scene(shapes, cull)
        got = _AlphaDrawn(probes.scene, call(probes.scene))
        drawn.append(got)
        if got.coverage is None:
            return None
        values = _alpha_at(got.coverage, probes)
        halves = []
        for (axis, lo, hi, a_lo, a_hi), mid, a_mid in zip(jumps, mids, values.tolist()):
            if a_mid != a_lo:
                halves.append((axis, lo, mid, a_lo, a_mid))
            if a_mid != a_hi:
                halves.append((axis, mid, hi, a_mid, a_hi))
        if len(halves) > limit:
            return None
        jumps = halves
    return jumps


def _thresholds(jumps: Sequence[tuple[float, float, float]]) -> list[float]:
    """Corner offsets separating consecutive sample columns (rows): below all, between
    each two (halfway across the gap between their intervals: dyadic), above all."""
    ordered = sorted(jumps)
    return [-1.0] + [(ordered[i - 1][1] + ordered[i][0]) / 2.0 for i in range(1, len(ordered))] + [1.0]


def _measure_error(drawn: Sequence[_AlphaDrawn]) -> tuple[float, float, int]:
    """max and mean |alpha - exact area| over the answered scenes, and the pixels compared."""
    exact = Convention(coverage="area")
    diffs = [np.abs(d.differences(exact)) for d in drawn if d.coverage is not None]
    every = np.concatenate(diffs) if diffs else np.zeros(0)
    return (float(every.max(initial=0.0)), float(every.mean()) if every.size else 0.0, int(every.size))


def rounded_up_tolerance(error: float) -> float:
    """A tolerance covering ``error`` (plus the comparison slack), rounded up to 2**-12."""
    return min(1.0, math.ceil((error + SLACK) * 4096.0) / 4096.0)


def alpha_sweeps(call: Call, seed: int = 0, resolution: int = 20) -> SweepFact:
    """Tell an analytic anti-aliaser from a supersampler and recover the grid and levels.

    A vertical and a horizontal edge are swept across a pixel from -1/256 to 1 px in steps
    of 1/256 px, a slanted one (dx/dy = 1/4) from -1/4 to 5/4 (one call), and two scenes of
    random float triangles are drawn (their alphas show the quantisation; the exact area
    is known for every pixel). When both axial sweeps are stepped (at most 65 levels),
    each step is bisected to 2**-``resolution`` px (one call per halving, all steps at
    once), corner probes between consecutive sample columns and rows count the samples
    of each cell (one call), and a pinwheel scene around every sample fits the tie rule
    (one call): the supersampled candidate is ``Convention(coverage="area",
    samples=pattern, tie=..., levels=...)``. Otherwise, and when the pattern has more
    than :data:`~harness.contract.conventions.MAX_AREA_SAMPLES` samples, the candidate is
    ``Convention(coverage="area", levels=..., tolerance=...)`` with the largest measured
    |alpha - area| rounded up (None when it is within half a level). Either way the
    input grid -- the snapping applied to the vertices before the area or the share is
    taken -- is fitted (:func:`input_grid`; a supersampler's steps read again under each
    snapping their grid allows first, :func:`_snapped_reading`), and the tolerance is
    measured against the oracle of the snapped scene.

    Parameters
    ----------
    call : Call
    seed : int
        Seeds the float scenes.
    resolution : int
        Bisect steps down to 2**-resolution px.

    Returns
    -------
    SweepFact
    """
    calls = Remembered(call)
    found = culling(calls)
    if found.seen is None or found.seen == "both":
        return SweepFact(None, error=found.text, calls=calls.calls)
    cull = found.cull
    shapes, vertical, horizontal, slanted, axial, slant_offsets = _sweep_shapes()
    probes = _probe_scene(shapes, cull)
    sweep = _AlphaDrawn(probes.scene, calls(probes.scene))
    drawn = [sweep]
    if sweep.coverage is None:
        return SweepFact(None, error=f"the rasterizer raised {describe(sweep.outcome.error)}", calls=calls.calls)
    floats = [Scene(48, 48, random_triangles(150, 60.0, 48, seed + k)) for k in range(2)]
    drawn += [_AlphaDrawn(scene, calls(scene)) for scene in floats]
    values = _alpha_at(sweep.coverage, probes)
    area = _alpha_at(exact_coverage(probes.scene, Convention(coverage="area")), probes)

    def quantum_seen() -> int | None:
        """The quantum of every alpha drawn so far."""
        return quantum(np.concatenate([values] + [x.coverage.alpha for x in drawn
                                                  if x.coverage is not None and x.coverage.alpha is not None]))

    def sweep_of(axis: Literal["vertical", "horizontal", "slanted"], where: slice, steps: int) -> AxisSweep:
        return AxisSweep(axis, steps, len(set(values[where].tolist())), float(np.abs(values[where] - area[where]).max()))

    sweeps = [sweep_of("vertical", vertical, axial.size - 1), sweep_of("horizontal", horizontal, axial.size - 1),
              sweep_of("slanted", slanted, slant_offsets.size - 1)]
    stepped = [s.levels <= MAX_STEPPED_LEVELS for s in sweeps[:2]]
    refined: dict[int, tuple[tuple[float, float, float], ...]] = {}
    if any(stepped):
        jumps = [(axis, float(axial[k - 1]), float(axial[k]), float(values[where][k - 1]), float(values[where][k]))
                 for axis, where in ((0, vertical), (1, horizontal)) if stepped[axis]
                 for k in range(1, axial.size) if values[where][k] != values[where][k - 1]]
        bisected = _refine(calls, cull, jumps, resolution, drawn)
        if bisected is not None:
            for axis in (0, 1):
                if stepped[axis]:
                    refined[axis] = tuple((lo, hi, a_lo - a_hi) for ax, lo, hi, a_lo, a_hi in bisected if ax == axis)
    sweeps[0:2] = [AxisSweep(s.axis, s.steps, s.levels, s.max_error, refined.get(axis, ())) for axis, s in enumerate(sweeps[:2])]
    model: Model = "supersampled" if len(refined) == 2 else "hybrid" if len(refined) == 1 else "analytic"
    pattern: tuple[tuple[float, float], ...] | None = None
    layout = ""
    candidates: list[Convention] = []
    first = quantum_seen()
    if model == "supersampled":
        cells = None if first is None else _count_cells(calls, cull, refined[0], refined[1], first, drawn)
        xs = [_offset(lo, hi) for lo, hi, _ in sorted(refined[0])]
        ys = [_offset(lo, hi) for lo, hi, _ in sorted(refined[1])]
        if cells is None or not all(0.0 <= v < 1.0 for v in (*xs, *ys)):
            # the steps do not pair up into samples of equal weight, or one lies on the pixel's
            # edge (an area taken on an input grid steps there): no sample pattern
            model = "analytic"
        else:
            pattern = tuple((xs[i], ys[j]) for i, j in cells)  # row by row
            layout = _layout(pattern)
            if len(pattern) <= MAX_AREA_SAMPLES:
                # under an input grid, the steps lie where the snapped edge crosses a sample
                xs, ys, snapping = _snapped_reading(xs, ys, cells, cull, (first or CONTINUOUS_LEVELS - 1) + 1, drawn[1:3])
                pattern = tuple((xs[i], ys[j]) for i, j in cells)
                layout = _layout(pattern)
                candidates = [Convention(coverage="area", samples=pattern, tie=tie, cull=cull, subpixel_bits=snapping[0],
                                         snap_rounding=snapping[1]) for tie in TIE_RULES]
                # the tie rule: edges exactly through every sample column and row, and pinwheels around every sample
                shapes = np.concatenate([[_corner(x, -2.0) for x in xs], [_corner(-2.0, y) for y in ys], _wheels(pattern)])
                ties = _probe_scene(shapes, cull)
                drawn.append(_AlphaDrawn(ties.scene, calls(ties.scene)))
    max_error, mean_error, pixels = _measure_error(drawn)
    # the quantisation again, over every alpha seen (a corner probe may show one sample's share)
    d = quantum_seen()
    levels = None if d is None else d + 1
    candidates = [replace(c, levels=levels or CONTINUOUS_LEVELS) for c in candidates]
    answered = [x for x in drawn if x.coverage is not None]
    runner_up = None
    if candidates:
        scores = sorted((sum(x.beyond(c) for x in answered), i) for i, c in enumerate(candidates))
        convention = candidates[scores[0][1]]
        runner_up = (f"the same samples, {candidates[scores[1][1]].tie} ties", scores[1][0])  # another tie rule
    else:
        convention = Convention(coverage="area", levels=levels or CONTINUOUS_LEVELS, cull=cull)
        if model == "hybrid" and 1 in refined:
            convention = _row_sampled(convention, len(refined[1]), [x for x in drawn if x.coverage is not None])
    # the input grid: the snapping applied to the vertices before the area (or the share
    # of the samples) is taken, fitted on the sweeps and the float scenes
    grid = input_grid(calls, convention, [sweep, *drawn[1:3]], drawn)
    convention = replace(convention, subpixel_bits=grid.bits, snap_rounding=grid.rounding)
    if candidates and pattern is not None:
        # a square grid of 2**s x 2**s samples may be skia's supersampler (tiny-skia)
        convention = _skia_supersampled(convention, pattern, answered)
    if not candidates:
        # the tolerance measured against the oracle of the snapped scene
        error = max((float(np.abs(x.differences(convention)).max(initial=0.0)) for x in answered), default=0.0)
        tolerance = None if error <= convention.alpha_tolerance + SLACK else rounded_up_tolerance(error)
        convention = replace(convention, tolerance=tolerance)
    # a tolerance measured on these very probes explains them by construction: the
    # residual counts what lies beyond half a level of the oracle, which rounding to the
    # levels keeps within
    fit = None
    if not candidates and not convention.rows and levels == QUANTISED_LEVELS:
        # an analytic anti-aliaser on 8-bit levels: the library's own levels of the exact area
        fit = quantisation_fit(calls, convention, answered, drawn, cull)
        if fit.chosen is not None:
            convention = fit.chosen  # with the input grid fitted beside the levels
    residual = sum(x.beyond(replace(convention, tolerance=None)) for x in answered)
    max_residual = max((float(np.abs(x.differences(convention)).max(initial=0.0)) for x in answered), default=0.0)
    return SweepFact(model, sweeps[0], sweeps[1], sweeps[2], levels, max_error, mean_error, pattern, layout, convention,
                     residual, max_residual, pixels, runner_up, calls.calls, grid=grid, drawn=tuple(drawn), quantisation=fit)


def _row_sampled(analytic: Convention, rows: int, answered: Sequence[_AlphaDrawn]) -> Convention:
    """A hybrid whose horizontal sweep steps ``rows`` times and whose vertical one does not
    samples each pixel row on ``rows`` lines, exact along x (cairo's tor scan converter:
    :mod:`harness.oracle.aa_models`): the row-sampled candidates, all rows sampled or
    cairo's analytic full rows, against the analytic area, the one leaving the fewest
    (triangle, pixel)s beyond half a level (the analytic area on a tie)."""
    if not 1 <= rows <= 256:
        return analytic
    candidates = [analytic, replace(analytic, rows=rows), replace(analytic, rows=rows, full_rows=True)]
    scores = [sum(x.beyond(c) for x in answered) for c in candidates]
    return candidates[scores.index(min(scores))]


def _skia_supersampled(found: Convention, pattern: Sequence[tuple[float, float]],
                       answered: Sequence[_AlphaDrawn]) -> Convention:
    """A supersampler whose samples form a square grid of 2**s columns and 2**s rows (s in
    1..4) may be skia's supersampler (tiny-skia's ``scan/path_aa.rs``:
    :mod:`harness.oracle.supersample_models`), whose sub-scanlines and rounded sub-pixel
    spans look like such a grid from outside but whose 16.16 edge walk, 1/2**(s+6) px input
    grid and ``blit_h`` levels (63 on a full pixel's last sub-row) do not follow any sample
    pattern: its candidate ``Convention(coverage="area", supersample=s, input="float32")``
    against the pattern's, the one leaving fewer (triangle, pixel)s beyond half a level
    (the pattern on a tie). Never tried for an analytic, hybrid (cairo's row-sampled) or
    non-square stepped answer: none of them has such a grid."""
    xs = {x for x, _ in pattern}
    ys = {y for _, y in pattern}
    n = len(ys)
    if len(xs) != n or len(pattern) != n * n or n not in (2, 4, 8, 16):
        return found
    candidate = Convention(coverage="area", supersample=n.bit_length() - 1, input="float32", cull=found.cull)
    scores = [sum(x.beyond(replace(c, tolerance=None)) for x in answered) for c in (found, candidate)]
    return candidate if scores[1] < scores[0] else found
# --- area: the library's levels ------------------------------------------------------------------

# the quantisations make 8-bit levels
QUANTISED_LEVELS = 256
# the input grids the analytic libraries receive, tried with every quantisation (bits):
# 26.6 (FreeType, Qt) and 24.8 (AGG, Blend2D)
_LIBRARY_GRIDS = (6, 8)
# a quantisation is judged within one level: the libraries' crossings, rounded to 1/256 px,
# leave a level off at some pixels (harness.oracle.analytic_models)
ONE_LEVEL = 1.0 / 255.0


@dataclass(frozen=True, slots=True)
class QuantisationFit:
    """Which library's levels (:mod:`harness.contract.quantisations`) an analytic 8-bit
    anti-aliaser's alphas are, fitted from outside: every quantisation scored on the probes
    that part them (:func:`quantisation_fit`) and on every scene drawn before, by the
    (triangle, pixel)s off its level (``off``) and beyond one level (``beyond``), against
    ``nearest`` (the area rounded to the nearest level: ``nearest_off``). ``chosen``: the
    convention (the quantisation, within one level) when one leaves fewer pixels off its
    level than ``nearest``, else None; ``pixels`` compared; ``scores`` every candidate's
    (off, beyond); ``nearest`` the candidate before (``base``)."""

    chosen: Convention | None
    name: str
    off: int
    beyond: int
    nearest_off: int
    pixels: int
    scores: tuple[tuple[str, int, int], ...] = ()
    # the candidate before the levels: the exact area within its measured tolerance (what the
    # rasterizer's lines and paths, for which the levels are not defined, are judged by)
    nearest: Convention | None = None

    @property
    def text(self) -> str:
        others = ", ".join(f"{n} {o}" for n, o, _ in self.scores if n != self.name)
        if self.chosen is None:
            return (f"the area rounded to the nearest level ({self.nearest_off} of {self.pixels} (triangle, pixel)s off it; "
                    f"off a library's levels: {others})")
        grid = self.chosen.subpixel_bits
        on = "the vertices as given" if grid is None else f"1/{2**grid} px ({self.chosen.snap_rounding})"
        return (f"{self.name} on {on}: {self.off} of {self.pixels} (triangle, pixel)s off its level, {self.beyond} beyond "
                f"one level (the area rounded to the nearest level: {self.nearest_off} off; at best on any grid: {others})")


def _quantisation_shapes() -> NDArray[np.float64]:
    """(K, 3, 2): probes whose pixel areas are whole multiples of 1/256 -- right triangles
    with legs of 1, 2 and 4 px, at slopes 1, 1/2 and 2 (every crossing on a pixel corner or
    a 1/2 or 1/4 px point) -- in both windings: where ``floor(256 S)`` and its complement
    (FreeType's ``~k``) part, and which winding a library counts positive."""
    shapes = []
    for a, b in ((1.0, 1.0), (2.0, 2.0), (2.0, 1.0), (1.0, 2.0), (4.0, 2.0), (4.0, 4.0)):
        clockwise = np.array([[0.0, 0.0], [a, 0.0], [0.0, b]])
        shapes += [clockwise, clockwise[::-1]]
    return np.array(shapes)


def quantisation_fit(call: Call, base: Convention, answered: Sequence[_AlphaDrawn], drawn: list[_AlphaDrawn],
                     cull: CullMode, seed: int = 0) -> QuantisationFit:
    """The library's levels of an analytic anti-aliaser on 8-bit levels: one scene drawn
    (appended to ``drawn``) of right triangles whose pixel areas are whole multiples of 1/256
    in both windings (:func:`_quantisation_shapes`: FreeType's complement of a negative
    ``k`` and the winding a library counts positive show there), and random float triangles
    in both windings (the others: ``|k|``, the gray-8 blend and Blend2D's ``* 255 >> 8``
    part by a level over most of the range), and those with every vertex on a half step of
    1/64 and 1/256 px (the grids' roundings part) -- then every quantisation, on ``base``'s
    input grid and on 26.6 and 24.8 with each rounding, scored by the (triangle, pixel)s off
    its level, then beyond one level, over those and ``answered``, against ``nearest``
    (``base`` itself, half a level). The best is chosen, within one level, when it leaves
    fewer pixels off its level than ``nearest``."""
    from harness.contract.quantisations import QUANTISATIONS

    shapes = _quantisation_shapes()
    probes = _probe_scene(shapes, "none")
    floats = random_triangles(120, 20.0, 40, seed + 7)
    both = Scene(40, 40, np.concatenate([floats, floats[:, ::-1]]))
    # and the float scene with every vertex on a half step of each library grid: where rounding
    # to nearest (either tie rule) and truncation part
    halves = [_half_steps(both, bits).positions for bits in _LIBRARY_GRIDS]
    side = max(probes.scene.width, probes.scene.height, 42)
    together = Scene(side, side, np.concatenate([probes.scene.positions, both.positions, *halves]))  # one call
    scenes = [_AlphaDrawn(together, call(together))]
    drawn += scenes
    judged = [x for x in [*answered, *scenes] if x.coverage is not None]
    pixels = sum(int(x.differences(replace(base, tolerance=None)).size) for x in judged)
    nearest = sum(x.beyond(replace(base, tolerance=None)) for x in judged)
    scores: list[tuple[int, int, int, str, Convention]] = []
    # each quantisation on base's grid and on the libraries' grids (26.6 and 24.8, each rounding):
    # a level's boundary moves with the grid, so the two are fitted together
    grids = list(dict.fromkeys([(base.subpixel_bits, base.snap_rounding), (None, "nearest-even"),
                                *((bits, r) for bits in _LIBRARY_GRIDS for r in PLAIN_SNAP_ROUNDINGS)]))
    for name in QUANTISATIONS:
        for order, (bits, rounding) in enumerate(grids):
            candidate = replace(base, quantisation=name, levels=QUANTISED_LEVELS, tolerance=ONE_LEVEL, cull=cull,
                                subpixel_bits=bits, snap_rounding=rounding)
            differences = [np.abs(x.differences(candidate)) for x in judged]  # the tolerance aside: one oracle each
            off = sum(int(np.sum(d > 0.5 * ONE_LEVEL + SLACK)) for d in differences)
            beyond = sum(int(np.sum(d > ONE_LEVEL + SLACK)) for d in differences)
            scores.append((off, beyond, order, name, candidate))
    off, beyond, _, name, best = min(scores, key=lambda s: (s[0], s[1], s[2]))
    # each quantisation's best grid, for the card
    listed = tuple((n, *min((o, b) for o, b, _, m, _ in scores if m == n)) for n in QUANTISATIONS)
    chosen = best if off < nearest else None
    return QuantisationFit(chosen, name, off, beyond, nearest, pixels, listed, base)


# --- area: the input grid ------------------------------------------------------------------------

_ROUNDING_WORDS = {"nearest-even": "rounding half to even", "half-away": "rounding half away from zero",
                   "floor": "truncating (rounding down)",
                   "half-away-shifted": "rounding half away from the pixel centre (piglit's shifted frame)"}
# a snapping is taken over none only when it leaves at most this share of the (triangle,
# pixel)s beyond the tolerance that none leaves (a rasterizer whose error is not a
# snapping gains little from any, and by chance)
_GRID_GAIN = 0.5
# the grids scored on every scene: the best on part of one float scene
_GRID_SHORTLIST = 6
# a supersampler's readings under snapping: each on the first SHORT_PART triangles of a
# float scene, the best few on both float scenes
_SHORT_PART = 40
_READING_SHORTLIST = 3


@dataclass(frozen=True, slots=True)
class InputGrid:
    """The snapping an anti-aliaser applies to its vertices before it takes the area (or
    the share of its samples), fitted from outside: ``bits`` (None: none seen) and
    ``rounding``; ``beyond`` the (triangle, pixel)s beyond the tolerance against the exact
    oracle of the scenes so snapped, ``unsnapped`` against the unsnapped ones, ``error``
    the summed |alpha - oracle| of each; ``tied`` the roundings that explain the answers
    as well (on scenes whose every vertex is a half step of the grid, where they part)."""

    bits: int | None
    rounding: SnapRounding
    beyond: int
    error: float
    unsnapped: int
    unsnapped_error: float
    tied: tuple[SnapRounding, ...] = ()

    @property
    def text(self) -> str:
        against = (f"{self.beyond} (triangle, pixel)s beyond the tolerance against the snapped scenes' exact area, "
                   f"{self.unsnapped} against the unsnapped ones")
        if self.bits is None:
            return (f"none detected (the exact area of the vertices as given: {self.unsnapped} (triangle, pixel)s "
                    "beyond the tolerance)")
        rounding = _ROUNDING_WORDS[self.rounding]
        if len(self.tied) > 1:
            rounding += " (or " + ", ".join(_ROUNDING_WORDS[r] for r in self.tied if r != self.rounding) + ": as well)"
        return f"1/{2**self.bits} px ({32 - self.bits}.{self.bits}), {rounding}; {against}"


def _grid_key(scenes: Sequence[_AlphaDrawn], convention: Convention) -> tuple[int, float]:
    """(triangle, pixel)s beyond the tolerance and the summed |alpha - oracle| on ``scenes``."""
    answered = [x for x in scenes if x.coverage is not None]
    return (sum(x.beyond(convention) for x in answered),
            float(sum(np.abs(x.differences(convention)).sum() for x in answered)))


def _snapped_reading(xs: list[float], ys: list[float], cells: Sequence[tuple[int, int]], cull: CullMode, levels: int,
                     floats: Sequence[_AlphaDrawn]) -> tuple[list[float], list[float], tuple[int | None, SnapRounding]]:
    """A supersampler's sample columns ``xs`` and rows ``ys`` as read from its steps, and
    its input grid, read again with snapping: when every step lies on a grid of 2**-k px
    (k <= 16), the vertices may be snapped, rounding to 2**-(k - 1) px or truncating to
    2**-k (:func:`harness.identify.triangle_probes._snap_candidates`), and a step is then where the
    snapped edge crosses a sample: a sample on the grid lies half a grid step from its
    step when rounding (either side, as its tie rule has it), on it or one step below
    when truncating, and one off the grid acts as any point between its grid points.
    Each snapping, with every column (row) read shifted alike by each of those, is
    scored on the ``floats`` scenes with
    top-left ties (a tie is rare there); the best is kept when it leaves at most half of
    the (triangle, pixel)s beyond the tolerance that the unsnapped reading does and less
    error (as :func:`input_grid` decides), else the reading as it was, unsnapped.

    Returns
    -------
    xs, ys : list of float
    snapping : (bits or None, rounding)
    """
    k = max(_fraction_bits(v) for v in [*xs, *ys])

    def convention(px: list[float], py: list[float], bits: int | None, rounding: SnapRounding) -> Convention:
        return Convention(coverage="area", samples=[(px[i], py[j]) for i, j in cells], cull=cull, levels=levels,
                          subpixel_bits=bits, snap_rounding=rounding)

    unsnapped = _grid_key(floats, convention(xs, ys, None, "nearest-even"))
    readings: list[tuple[list[float], list[float], int, SnapRounding]] = []
    for bits, rounding in _snap_candidates(k if k <= MAX_SUBPIXEL_BITS + 1 else None):
        if bits is None:
            continue
        step = 2.0**-bits
        # a sample on the grid steps half a grid step from it when rounding (after it when its
        # edge owns it, before it when not), one step after it when truncating by an edge
        # that owns it, on it when not; one off the grid behaves as any point between its grid points
        shifts = (0.0, -step / 2.0, -step) if rounding == "floor" else (0.0, -step / 2.0, step / 2.0)
        readings += [([x + dx for x in xs], [y + dy for y in ys], bits, rounding) for dx in shifts for dy in shifts
                     if all(0.0 <= x + dx < 1.0 for x in xs) and all(0.0 <= y + dy < 1.0 for y in ys)]
    if not readings:
        return xs, ys, (None, "nearest-even")
    # every reading on a part of the first float scene, the best few on both
    part = [_alpha_part(x, _SHORT_PART) for x in floats[:1] if x.coverage is not None]
    if part:
        readings = sorted(readings, key=lambda c: _grid_key(part, convention(*c)))[:_READING_SHORTLIST]
    key, px, py, bits, rounding = min(((_grid_key(floats, convention(*c)), *c) for c in readings), key=lambda c: c[0])
    if not (key[0] < unsnapped[0] and key[0] <= _GRID_GAIN * unsnapped[0] and key[1] < unsnapped[1]):
        return xs, ys, (None, "nearest-even")
    return px, py, (bits, rounding)


def _alpha_part(drawn: _AlphaDrawn, count: int) -> _AlphaDrawn:
    """The first ``count`` triangles of an answered scene and the answer's (triangle, pixel)s of them."""
    coverage = drawn.coverage
    assert coverage is not None
    spans = np.flatnonzero(coverage.primitive < count)
    return _AlphaDrawn(drawn.scene.subset(np.arange(min(count, len(drawn.scene.positions)))), Outcome(coverage.take(spans)))


def input_grid(call: Call, base: Convention, scenes: Sequence[_AlphaDrawn], drawn: list[_AlphaDrawn]) -> InputGrid:
    """The input grid of an anti-aliaser: with ``base`` (the area or supersampled
    candidate, its tolerance half a level), every snapping of 0..16 bits x each rounding,
    and none, scored on ``scenes`` (the sweeps, whose vertices sit on 1/256 px and on
    coarser grids, and random floats) by the (triangle, pixel)s beyond the tolerance
    against the exact oracle of the snapped scene, then by the summed |alpha - oracle|
    (every grid on part of the first float scene, the best few on all); ties prefer no snapping, then the
    coarser grid, then rounding to nearest even. A snapping is kept only when it leaves at most half of the
    pixels beyond the tolerance that none does (a rasterizer whose error is something else gains little from
    any, and only by chance). With a grid found, the float scenes are drawn again with every vertex on a half
    step of it (two calls, appended to ``drawn``), where nearest-even, half-away and truncation part, and the
    rounding is fitted there too."""
    exact = replace(base, tolerance=None, subpixel_bits=None, snap_rounding="nearest-even")
    none = _grid_key(scenes, exact)
    grids = [(b, r) for b in range(MAX_SUBPIXEL_BITS + 1) for r in PLAIN_SNAP_ROUNDINGS]
    # every grid on part of the first float scene, the few best of them on every scene
    first = [_alpha_part(x, _SHORT_PART) for x in scenes[1:2] if x.coverage is not None]
    if first:
        grids = sorted(grids, key=lambda g: _grid_key(first, replace(exact, subpixel_bits=g[0],
                                                                     snap_rounding=g[1])))[:_GRID_SHORTLIST]
    ranked = sorted((_grid_key(scenes, replace(exact, subpixel_bits=b, snap_rounding=r)), b, PLAIN_SNAP_ROUNDINGS.index(r), r)
                    for b, r in grids)
    (beyond, error), bits, _, rounding = ranked[0]
    if not (beyond < none[0] and beyond <= _GRID_GAIN * none[0] and error < none[1]):
        return InputGrid(None, "nearest-even", none[0], none[1], none[0], none[1])
    floats = [x for x in scenes[1:] if x.coverage is not None]
    halves = [_AlphaDrawn(half, call(half)) for half in (_half_steps(x.scene, bits) for x in floats)]
    drawn += halves
    parted = sorted((_grid_key([*scenes, *halves], replace(exact, subpixel_bits=bits, snap_rounding=r)),
                     PLAIN_SNAP_ROUNDINGS.index(r), r)
                    for r in PLAIN_SNAP_ROUNDINGS)
    rounding = parted[0][2]
    tied = tuple(r for key, _, r in parted if key[0] == parted[0][0][0])
    final = _grid_key(scenes, replace(exact, subpixel_bits=bits, snap_rounding=rounding))
    return InputGrid(bits, rounding, final[0], final[1], none[0], none[1], tied if len(tied) > 1 else ())


def _count_cells(call: Call, cull: CullMode, columns: Sequence[tuple[float, float, float]],
                 rows: Sequence[tuple[float, float, float]], d: int, drawn: list[_AlphaDrawn]) -> list[tuple[int, int]] | None:
    """The (column, row) cells holding a sample: a corner probe at every pair of
    thresholds between sample columns and rows gives Q[i, j], the share of samples right
    of threshold i and below threshold j; each cell's share is Q[i, j] - Q[i + 1, j] -
    Q[i, j + 1] + Q[i + 1, j + 1] (one call). None unless every share is 0 or one and the
    same 1/N: within half a quantum 1/d when the shares are exact multiples of it, within
    two quanta when they are the share rounded to one (four rounded alphas make a cell)."""
    a = _thresholds(columns)
    b = _thresholds(rows)
    probes = _probe_scene(np.array([_corner(x, y) for x in a for y in b]), cull)
    got = _AlphaDrawn(probes.scene, call(probes.scene))
    drawn.append(got)
    if got.coverage is None:
        return None
    q = _alpha_at(got.coverage, probes).reshape(len(a), len(b))
    share = q[:-1, :-1] - q[1:, :-1] - q[:-1, 1:] + q[1:, 1:]
    step = 1.0 / d
    # exact shares (a multiple of 1/d each), else shares quantised to 1/d: four of them
    # rounded make a cell's share err by up to two steps
    for slack in (step / 2.0, 2.0 * step):
        held = share > slack
        count = int(held.sum())
        if 0 < count <= MAX_CELLS and np.all(np.abs(share[held] - 1.0 / count) <= slack) \
                and np.all(np.abs(share[~held]) <= slack):
            return sorted(((int(i), int(j)) for i, j in zip(*np.nonzero(held))), key=lambda c: (c[1], c[0]))
    return None
