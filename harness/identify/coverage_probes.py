"""identify's probes for coverage beyond one sample: the kind, an anti-aliaser's grid and
quantisation, a multisample pattern, each measured from outside.

Like :mod:`harness.identify.triangle_probes`, each probe calls the rasterizer only through a
:data:`~harness.engine.isolation.Call` and returns a frozen record (``text`` is its line on the
convention card); an answer with an error is reported, never raised.

One probe shape serves every measurement here: a *corner*, a right triangle whose right
angle sits at ``(X + a, Y + b)`` with legs 7 px long going right and down, read at pixel
(X, Y) only. Within that pixel it covers exactly the quadrant ``x > X + a, y > Y + b``:
with ``b = -2`` its left edge is a vertical edge at offset ``a`` (a *vertical sweep* moves
it across the pixel), with ``a = -2`` its top edge a horizontal one at offset ``b``.
Probes sit in cells of 12 px, so one scene holds hundreds of them and a whole sweep, or
one step of many bisections at once, costs one call.

- :func:`coverage_kind`: one scene; the answer carries ``alpha`` (area), ``sample``
  indices (multisample, with how many appear in a pixel the triangle covers whole), or
  neither (single).
- :func:`alpha_sweeps`: a vertical, a horizontal and a slanted edge swept across a pixel
  in steps of 1/256 px, and two scenes of random float triangles. The distinct alphas of
  each sweep are its *levels*: an analytic anti-aliaser shows about one per step, a
  supersampler with n sample columns and m sample rows n + 1 and m + 1, stepping where
  the edge passes a sample. Those steps are bisected to 2**-20 px, and the samples found
  on each axis are paired up by corner probes between them (inclusion-exclusion gives
  how many samples lie in each cell), so that a regular grid and a sparse pattern
  (n-rooks) are both recovered. The quantisation is the coarsest 1/d of which every
  alpha seen is a multiple.
- :func:`sample_positions`: for each sample index of a multisample rasterizer, its x and
  y offsets by bisecting where that sample flips as a vertical (horizontal) edge sweeps
  the pixel; the tie rule (and snapping, when the vertex sweep sees some) fitted on
  lattice scenes, pinwheels around every sample and float scenes, sample by sample with
  the single-sample oracle at each offset.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from cases.scenes import lattice_triangles, random_triangles
from harness.contract.conventions import (
    MAX_AREA_SAMPLES,
    MAX_SUBPIXEL_BITS,
    SNAP_ROUNDINGS,
    TIE_RULES,
    Convention,
    CoverageKind,
    CullMode,
    SnapRounding,
)
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import AREA, MULTISAMPLE, SINGLE, CoverageModel, model_named
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import Scene
from harness.engine.isolation import Call, Outcome, describe, layer_of
from harness.geometry.keys import union
from harness.identify.triangle_probes import Culling, Drawn, VertexSweep, _half_steps, _snap_candidates, culling, vertex_sweep
from harness.oracle.coverage import exact_coverage

__all__ = [
    "SWEEP_STEPS", "SLACK", "Remembered", "layered", "quantum",
    "CoverageKindFact", "AxisSweep", "SweepFact", "PatternFact",
    "coverage_kind", "alpha_sweeps", "sample_positions",
]

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

_CELL = 12  # px per probe cell
_LEG = 7.0  # a corner's legs: its hypotenuse stays clear of the probe pixel for a, b >= -2
_COLUMNS = 32  # probe cells per row of a probe scene


# --- calls -------------------------------------------------------------------------------


class Remembered:
    """A :data:`Call` that asks the rasterizer once per distinct scene (the probes of
    different samples share their scenes) and counts the calls it made.

    >>> calls = Remembered(lambda scene: Outcome(Coverage.empty()))
    >>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    >>> _ = calls(scene), calls(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]))
    >>> calls.calls
    1
    """

    def __init__(self, call: Call) -> None:
        self.call = call
        self.calls = 0
        self._seen: dict[tuple[int, int, bytes, bytes | None, bytes | None], Outcome] = {}

    def __call__(self, scene: Scene) -> Outcome:
        key = (scene.width, scene.height, scene.positions.tobytes(),
               None if scene.attributes is None else scene.attributes.tobytes(), None if scene.w is None else scene.w.tobytes())
        if key not in self._seen:
            self.calls += 1
            self._seen[key] = self.call(scene)
        return self._seen[key]


def layered(call: Call, index: int) -> Call:
    """The single-sample rasterizer that sample ``index`` of a multisample one is."""
    return lambda scene: layer_of(call(scene), index)


# --- probe scenes --------------------------------------------------------------------------


def _corner(a: float, b: float) -> NDArray[np.float64]:
    """(3, 2): the corner probe of offsets (a, b) relative to its pixel's top-left corner;
    clockwise on screen. Inside the pixel it covers exactly x > a, y > b (a, b >= -2)."""
    return np.array([[a, b], [a + _LEG, b], [a, b + _LEG]])


def _slant(a: float) -> NDArray[np.float64]:
    """(3, 2): a triangle whose left edge (dx/dy = 1/4) crosses the pixel's middle row at
    offset ``a``; its other edges stay clear of the pixel for a >= -0.25. Clockwise."""
    return np.array([[a - 0.625, -2.0], [a + 7.0, -2.0], [a + 0.875, 4.0]])


_RIM = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], dtype=np.float64)


def _wheel(offset: tuple[float, float], size: float) -> NDArray[np.float64]:
    """(8, 3, 2): piglit's pinwheel, eight triangles around the point ``offset`` of the
    pixel, split by the axes and diagonals: each tie rule gives that point to exactly
    one of them. Clockwise."""
    centre = np.array(offset)
    return np.array([[centre + size * _RIM[i], centre + size * _RIM[i + 1], centre] for i in range(8)])


@dataclass(frozen=True)
class _Probes:
    """A scene of probe triangles, ``per_cell`` to a 12 px cell, each read at its cell's
    pixel (x, y)."""

    scene: Scene
    x: NDArray[np.int64]
    y: NDArray[np.int64]


def _probe_scene(shapes: NDArray[np.float64], cull: CullMode, per_cell: int = 1) -> _Probes:
    """``shapes`` (K, 3, 2), relative to their probe pixel's corner, each moved into its
    cell (by whole pixels: exact); reversed when the rasterizer culls clockwise ones."""
    k = len(shapes)
    cells = -(-k // per_cell)
    columns = max(1, min(cells, _COLUMNS))
    cell = np.arange(k) // per_cell
    x = (cell % columns) * _CELL + 3
    y = (cell // columns) * _CELL + 3
    triangles = shapes + np.stack([x, y], axis=-1)[:, None, :].astype(np.float64)
    if cull == "cw":  # the clockwise winding is culled: draw the other one
        triangles = triangles[:, ::-1]
    return _Probes(Scene(columns * _CELL, -(-cells // columns) * _CELL, triangles), x, y)


def _at_probe(coverage: Coverage, probes: _Probes) -> tuple[NDArray[np.bool_], NDArray[np.int64]]:
    """Which fragments of ``coverage`` lie at their own probe's pixel, and their triangle."""
    t, x, y = coverage.pixels()
    k = len(probes.x)
    known = (t >= 0) & (t < k)
    at = np.where(known, t, 0)
    return known & (x == probes.x[at]) & (y == probes.y[at]), t


def _alpha_at(coverage: Coverage, probes: _Probes) -> NDArray[np.float64]:
    """(K,) the alpha each probe has at its pixel (0 when absent; 1 per fragment when the
    answer carries no alpha)."""
    hit, t = _at_probe(coverage, probes)
    alpha = coverage.alpha if coverage.alpha is not None and coverage.alpha.shape[0] == t.size else np.ones(t.size)
    out = np.zeros(len(probes.x))
    np.add.at(out, t[hit], alpha[hit])
    return out


def _samples_at(coverage: Coverage, probes: _Probes, n: int) -> NDArray[np.bool_]:
    """(K, n) which samples of its pixel each probe covers."""
    hit, t = _at_probe(coverage, probes)
    s = coverage.fragment_samples()
    hit &= (s >= 0) & (s < n)
    out = np.zeros((len(probes.x), n), dtype=bool)
    out[t[hit], s[hit]] = True
    return out


def _fraction_bits(value: float) -> int:
    """Binary fraction digits of a float: 3 for 0.375."""
    return max(0, value.as_integer_ratio()[1].bit_length() - 1)


# --- the kind of coverage --------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class CoverageKindFact:
    """What an answer carries: ``alpha`` (area), ``sample`` indices (multisample: the
    indices seen in pixels a triangle covers whole, and how many there are per pixel), or
    neither (single); ``kind`` None when the rasterizer gave an error."""

    kind: CoverageKind | None
    indices: tuple[int, ...] = ()
    per_pixel: tuple[int, ...] = ()
    error: str = ""

    @property
    def samples(self) -> int:
        """Distinct sample indices seen in whole pixels."""
        return len(self.indices)

    @property
    def model(self) -> CoverageModel | None:
        """The coverage model of the kind seen (analytic area for alphas: the sweeps tell
        a supersampler apart); None when the rasterizer gave an error."""
        return None if self.kind is None else model_named(self.kind)

    @property
    def text(self) -> str:
        model = self.model
        if model is None:
            return f"not measured: the rasterizer raised {self.error}"[:120]
        if not model.sample_ids:
            return f"{model.kind}: {model.seen}"
        said = f"{model.kind}: {self.samples} {model.seen} (indices {', '.join(map(str, self.indices))})"
        if len(set(self.per_pixel)) > 1:
            said += f"; whole pixels hold {min(self.per_pixel)} to {max(self.per_pixel)} of them"
        return said


def coverage_kind(call: Call) -> CoverageKindFact:
    """Draw a 28 px right triangle (both windings) and a small slanted one, and read the
    kind of the answer: area when it carries alphas, multisample when it carries sample
    indices -- how many distinct ones appear in the 7 x 7 pixels the big triangle covers
    whole -- else single."""
    big = np.array([[2.0, 2.0], [30.0, 2.0], [2.0, 30.0]])
    scene = Scene(32, 32, np.array([big, big[::-1], [[20.3, 20.1], [29.7, 24.9], [22.2, 29.6]]]))
    outcome = call(scene)
    cov = outcome.coverage
    if cov is None:
        return CoverageKindFact(None, error=describe(outcome.error))
    if cov.alpha is not None:
        return CoverageKindFact(AREA.kind)
    if cov.sample is None:
        return CoverageKindFact(SINGLE.kind)
    t, x, y = cov.pixels()
    s = cov.fragment_samples()
    whole = (t <= 1) & (x >= 4) & (x <= 10) & (y >= 4) & (y <= 10)  # inside either winding's 28 px triangle
    whole &= t == (t[whole].min() if whole.any() else 0)  # one winding: the first drawn
    key = y[whole] * 32 + x[whole]
    per_pixel = [len(set(s[whole][key == k].tolist())) for k in np.unique(key)]
    return CoverageKindFact(MULTISAMPLE.kind, tuple(sorted(set(s[whole].tolist()))), tuple(sorted(set(per_pixel))))


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


def _alpha_differences(got: Coverage, want: Coverage, scene: Scene) -> NDArray[np.float64]:
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
            self._cache[convention] = _alpha_differences(self.coverage or Coverage.empty(),
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
                {} if self.grid is None else {"input grid": self.grid.text})


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


def _layout(pattern: Sequence[tuple[float, float]]) -> str:
    """The shape of a pattern, in words: a regular (uniformly spaced) or irregular full
    n x m grid, n-rooks (every column and row once), or neither.

    >>> _layout([(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)])
    'regular 2 x 2 grid (4 samples)'
    >>> _layout(STANDARD_PATTERNS[4])
    '4-rooks (every sample in a column and row of its own)'
    """
    xs = sorted({x for x, _ in pattern})
    ys = sorted({y for _, y in pattern})
    n = len(pattern)
    if n == len(xs) * len(ys):
        uniform = all(len(set(np.diff(v).tolist())) <= 1 for v in (xs, ys))
        return f"{'regular' if uniform else 'irregular'} {len(xs)} x {len(ys)} grid ({n} samples)"
    if n == len(xs) == len(ys):
        return f"{n}-rooks (every sample in a column and row of its own)"
    return f"{n} samples on {len(xs)} columns and {len(ys)} rows"


def _offset(lo: float, hi: float) -> float:
    """A sample's offset from the interval (lo, hi] of edge offsets, one bisection step
    wide, over which it stops being covered: the end that is not an odd multiple of the
    step (the one with fewer fraction bits).

    A sample at lo under a rule whose left (top) edges own their samples and one at hi
    under a rule whose edges do not are told apart by no edge on the bisection's grid: the
    finer end would be a tie rule in disguise, so a pattern is read to one bit less than
    the bisection's resolution, and the tie rule is fitted separately.

    >>> _offset(0.375, 0.375 + 2**-20), _offset(0.375 - 2**-20, 0.375)
    (0.375, 0.375)
    """
    return lo if _fraction_bits(lo) <= _fraction_bits(hi) else hi


def _part(drawn: Drawn, keep: range) -> Drawn:
    """The triangles ``keep`` of a drawn scene, with the answer's fragments of them (renumbered)."""
    scene = drawn.scene.subset(np.arange(keep.start, keep.stop))
    coverage = drawn.coverage
    if coverage is None:
        return Drawn(scene, drawn.outcome)
    spans = np.flatnonzero((coverage.primitive >= keep.start) & (coverage.primitive < keep.stop))
    taken = coverage.take(spans)
    return Drawn(scene, Outcome(Coverage(taken.primitive - keep.start, taken.y, taken.x0, taken.x1)))


def _readings(lo: float, hi: float, grid: int | None) -> tuple[float, ...]:
    """The offsets a sample may have, under snapping to 2**-``grid`` px, when an edge
    swept across it stops covering it somewhere in (lo, hi]: either end (a sample at lo
    under a rule whose left (top) edges own their samples, at hi under one whose edges do
    not: the bisection stopped at the snapping step, and the snapped edges of other
    scenes tell the two apart), the end with fewer fraction bits first (:func:`_offset`),
    then the multiples of 2**-``grid`` px strictly inside (a grid finer than the bisection
    stopped at: truncation to 2**-g shows as the vertex sweep's grid g, as rounding to
    2**-(g - 1) does). Only offsets within the pixel, [0, 1), are kept. Without snapping (``grid`` None) the bisection went to 2**-20 px and
    the two ends are a tie rule apart on any scene of coarser vertices: the end with
    fewer fraction bits only.

    >>> _readings(77 / 256, 78 / 256, 8)  # 78/256 first, then 77/256
    (0.3046875, 0.30078125)
    >>> _readings(0.25, 0.5, 3), _readings(0.375 - 2**-20, 0.375, None)
    ((0.5, 0.25, 0.375), (0.375,))
    """
    first = _offset(lo, hi)
    if grid is None:
        return (first,) if 0.0 <= first < 1.0 else ()
    inside: list[float] = []
    if hi - lo > 2.0**-grid:
        step = 2.0**-grid
        k = math.floor(lo / step) + 1
        while k * step < hi and len(inside) < 3:
            inside.append(k * step)
            k += 1
    return tuple(v for v in dict.fromkeys([first, hi if first == lo else lo, *inside]) if 0.0 <= v < 1.0)


def _wheels(pattern: Sequence[tuple[float, float]]) -> NDArray[np.float64]:
    """(16 K, 3, 2): pinwheels of 1 and 2 px around every offset of ``pattern``, one to a cell."""
    return np.concatenate([_wheel(offset, size) for offset in pattern for size in (1.0, 2.0)])


def _measure_error(drawn: Sequence[_AlphaDrawn]) -> tuple[float, float, int]:
    """max and mean |alpha - exact area| over the answered scenes, and the pixels compared."""
    exact = Convention(coverage="area")
    diffs = [np.abs(d.differences(exact)) for d in drawn if d.coverage is not None]
    every = np.concatenate(diffs) if diffs else np.zeros(0)
    return (float(every.max(initial=0.0)), float(every.mean()) if every.size else 0.0, int(every.size))


def _rounded_up(error: float) -> float:
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
        if cells is None:
            model = "analytic"  # the steps do not pair up into samples of equal weight
        else:
            xs = [_offset(lo, hi) for lo, hi, _ in sorted(refined[0])]
            ys = [_offset(lo, hi) for lo, hi, _ in sorted(refined[1])]
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
    # the input grid: the snapping applied to the vertices before the area (or the share
    # of the samples) is taken, fitted on the sweeps and the float scenes
    grid = input_grid(calls, convention, [sweep, *drawn[1:3]], drawn)
    convention = replace(convention, subpixel_bits=grid.bits, snap_rounding=grid.rounding)
    if not candidates:
        # the tolerance measured against the oracle of the snapped scene
        error = max((float(np.abs(x.differences(convention)).max(initial=0.0)) for x in answered), default=0.0)
        tolerance = None if error <= convention.alpha_tolerance + SLACK else _rounded_up(error)
        convention = replace(convention, tolerance=tolerance)
    # a tolerance measured on these very probes explains them by construction: the
    # residual counts what lies beyond half a level of the oracle, which rounding to the
    # levels keeps within
    residual = sum(x.beyond(replace(convention, tolerance=None)) for x in answered)
    max_residual = max((float(np.abs(x.differences(convention)).max(initial=0.0)) for x in answered), default=0.0)
    return SweepFact(model, sweeps[0], sweeps[1], sweeps[2], levels, max_error, mean_error, pattern, layout, convention,
                     residual, max_residual, pixels, runner_up, calls.calls, grid=grid, drawn=tuple(drawn))


# --- area: the input grid ------------------------------------------------------------------------

_ROUNDING_WORDS = {"nearest-even": "rounding half to even", "half-away": "rounding half away from zero",
                   "floor": "truncating (rounding down)"}
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
            return f"none detected (the exact area of the vertices as given: {self.unsnapped} (triangle, pixel)s beyond the tolerance)"
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
    (every grid on part of the first float scene, the best few on all); ties prefer no snapping, then the coarser grid, then rounding to nearest even. A
    snapping is kept only when it leaves at most half of the pixels beyond the tolerance
    that none does (a rasterizer whose error is something else gains little from any, and
    only by chance). With a grid found, the float scenes are drawn again with every vertex
    on a half step of it (two calls, appended to ``drawn``), where nearest-even,
    half-away and truncation part, and the rounding is fitted there too."""
    exact = replace(base, tolerance=None, subpixel_bits=None, snap_rounding="nearest-even")
    none = _grid_key(scenes, exact)
    grids = [(b, r) for b in range(MAX_SUBPIXEL_BITS + 1) for r in SNAP_ROUNDINGS]
    # every grid on part of the first float scene, the few best of them on every scene
    first = [_alpha_part(x, _SHORT_PART) for x in scenes[1:2] if x.coverage is not None]
    if first:
        grids = sorted(grids, key=lambda g: _grid_key(first, replace(exact, subpixel_bits=g[0], snap_rounding=g[1])))[:_GRID_SHORTLIST]
    ranked = sorted((_grid_key(scenes, replace(exact, subpixel_bits=b, snap_rounding=r)), b, SNAP_ROUNDINGS.index(r), r)
                    for b, r in grids)
    (beyond, error), bits, _, rounding = ranked[0]
    if not (beyond < none[0] and beyond <= _GRID_GAIN * none[0] and error < none[1]):
        return InputGrid(None, "nearest-even", none[0], none[1], none[0], none[1])
    floats = [x for x in scenes[1:] if x.coverage is not None]
    halves = [_AlphaDrawn(half, call(half)) for half in (_half_steps(x.scene, bits) for x in floats)]
    drawn += halves
    parted = sorted((_grid_key([*scenes, *halves], replace(exact, subpixel_bits=bits, snap_rounding=r)), SNAP_ROUNDINGS.index(r), r)
                    for r in SNAP_ROUNDINGS)
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
        if 0 < count <= MAX_CELLS and np.all(np.abs(share[held] - 1.0 / count) <= slack) and np.all(np.abs(share[~held]) <= slack):
            return sorted(((int(i), int(j)) for i, j in zip(*np.nonzero(held))), key=lambda c: (c[1], c[0]))
    return None


# --- multisample: the pattern -------------------------------------------------------------------


@dataclass(frozen=True)
class PatternFact:
    """A multisample pattern measured from outside.

    ``offsets``: sample s's offset as first read (the end of its bisection interval with
    fewer fraction bits), in the rasterizer's sample order (None for a sample that never
    flipped). ``convention``: the best candidate (each sample at the reading of its
    interval that explains it best, with a tie rule and the snapping the vertex sweep
    allows), None when a sample was not found or two share an offset; ``residual`` its mismatching fragments of ``fragments`` over the fit
    scenes (every sample judged with the single-sample oracle at its offset);
    ``runner_up`` the best candidate with another tie rule. ``resolution``:
    the bisection stopped at 2**-resolution px (a snapping grid's spacing, when the
    vertex sweep saw one). ``calls``: the rasterizer calls made.
    """

    offsets: tuple[tuple[float, float] | None, ...]
    convention: Convention | None
    residual: int
    fragments: int
    runner_up: tuple[str, int] | None
    resolution: int
    vertex: VertexSweep | None = None
    culling: Culling | None = None
    calls: int = 0
    drawn: tuple[tuple[Drawn, ...], ...] = field(default=(), repr=False, compare=False)
    error: str = ""  # why the bisection stopped: a call gave no answer

    @property
    def unanswered(self) -> int:
        """Fit scenes it gave no answer for (left out of the fit and the residual)."""
        return sum(1 for layers in self.drawn if layers and layers[0].coverage is None)

    @property
    def pattern(self) -> tuple[tuple[float, float], ...] | None:
        """The offsets as the convention has them, or None."""
        return None if self.convention is None else self.convention.samples

    @property
    def text(self) -> str:
        if self.convention is None or self.pattern is None:
            if not self.offsets:
                return "not recovered: no sample index seen in a pixel a triangle covers whole"
            if self.error:
                return f"not recovered: a bisection call gave no answer ({self.error})"[:200]
            missing = [str(s) for s, o in enumerate(self.offsets) if o is None]
            if missing:
                return f"not recovered: sample {', '.join(missing)} never flipped under a sweeping edge"
            groups: dict[tuple[float, float], list[str]] = {}
            for s, o in enumerate(self.offsets):
                if o is not None:
                    groups.setdefault(o, []).append(str(s))
            shared = "; ".join(f"samples {', '.join(who)} all at ({o[0]:g}, {o[1]:g})" for o, who in groups.items() if len(who) > 1)
            return f"not recovered: {shared} -- samples sharing an offset make no pattern"
        pattern = self.pattern
        said = f"{len(pattern)} samples, in the rasterizer's order: " + " ".join(f"({x:g}, {y:g})" for x, y in pattern)
        standard = STANDARD_PATTERNS.get(len(pattern))
        if standard is not None:
            if pattern == standard:
                said += f" -- the standard {len(pattern)}x pattern (D3D11 / Vulkan)"
            elif set(pattern) == set(standard):
                said += f" -- the standard {len(pattern)}x offsets in ANOTHER ORDER (sample indices permuted)"
            elif set(pattern) == {(1.0 - x, y) for x, y in standard}:
                said += f" -- the standard {len(pattern)}x pattern MIRRORED in x"
            elif set(pattern) == {(x, 1.0 - y) for x, y in standard}:
                said += f" -- the standard {len(pattern)}x pattern MIRRORED in y"
            else:
                said += f" -- not the standard {len(pattern)}x pattern"
        return said + f"; {_layout(pattern)}; bisected to 2^-{self.resolution} px"


# the sides check's step past a sample, at least (a coarser bisection's step when the
# pattern was read on a snapping grid: past one grid step, a snapped edge stays past it)
SIDE_STEP = 1.0 / 16.0


@dataclass(frozen=True)
class SampleSides:
    """Whether each sample found under left and top edges (:class:`PatternFact`'s offsets)
    is where right and bottom edges find it too: an edge a step (``step``) to its other
    side, the sample inside, must cover it. ``dropped``: (sample, axis, offset) of those
    not covered -- a sample's coverage that depends on which side the edge comes from is
    no pattern at all: samples dropped near edges (a pixel rejected whole when its centre
    lies outside an edge, by too small a margin), not a wrong pattern. ``calls``: 1 (0
    when no offset was measured)."""

    dropped: tuple[tuple[int, str, float], ...] = ()
    checked: int = 0
    calls: int = 0
    error: str = ""
    step: float = SIDE_STEP

    @property
    def text(self) -> str:
        if self.error:
            return f"not measured: {self.error}"
        if not self.checked:
            return "not measured: no sample offset recovered"
        if not self.dropped:
            return f"each of {self.checked} samples covered by edges from either side at its offset"
        shown = ", ".join(f"sample {s} (at {o:g} in {axis} under a {'left' if axis == 'x' else 'top'} edge)"
                          for s, axis, o in self.dropped[:4])
        return (f"SAMPLES DROPPED NEAR EDGES: {shown} not covered by an edge {self.step:g} px past it on the other "
                "side (a right edge for x, a bottom one for y) -- whether a sample counts depends on the side its edge "
                "comes from, so no pattern explains it (not a wrong pattern)")


def sample_sides(call: Call, offsets: Sequence[tuple[float, float] | None], cull: CullMode,
                 resolution: int = 20) -> SampleSides:
    """:class:`SampleSides` of the offsets measured under left and top edges (bisected to
    2**-``resolution`` px): for every sample and axis, one mirrored corner probe (covering
    x < offset + step within the pixel, or y < ...; the step :data:`SIDE_STEP`, or the
    bisection's when coarser: the pattern was read on a snapping grid, and an edge one
    step past the sample snaps past it still), all in one call."""
    step = max(SIDE_STEP, 2.0 ** -resolution)
    found = [(s, o) for s, o in enumerate(offsets) if o is not None]
    if not found:
        return SampleSides(step=step)
    shapes = []
    for _, (x, y) in found:
        for a, b in ((x + step, 3.0), (3.0, y + step)):  # a right edge past it, a bottom one
            shapes.append(np.array([[a, b], [a - _LEG, b], [a, b - _LEG]]))  # the corner turned half round
    probes = _probe_scene(np.array(shapes), cull)
    outcome = call(probes.scene)
    if outcome.coverage is None:
        return SampleSides(error=describe(outcome.error), calls=1, step=step)
    seen = _samples_at(outcome.coverage, probes, len(offsets))
    dropped = []
    for k, (s, (x, y)) in enumerate(found):
        for j, (axis, o) in enumerate((("x", x), ("y", y))):
            if not seen[2 * k + j, s]:
                dropped.append((s, axis, o))
    return SampleSides(tuple(dropped), len(found), 1, step=step)


def _bisect_samples(call: Call, n: int, cull: CullMode, resolution: int) -> tuple[
        NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], str]:
    """For every sample s and axis, the offsets (lo, hi], 2**-resolution px apart, between
    which a left (top) edge sweeping the pixel stops covering sample s: every sample at
    once, one call per halving, probe 2 s + axis reading sample s.

    Returns
    -------
    lo, hi : (n, 2) float64
    found : (n, 2) bool
        False where sample s is not covered with the edge 1 px before the pixel or still
        covered with it 1 px past it (or an answer was missing).
    error : str
        The error of the call that gave no answer ("" when all answered).
    """
    lo = np.full((n, 2), -1.0)
    hi = np.full((n, 2), 1.0)
    errors: list[str] = []

    def covered(offsets: NDArray[np.float64]) -> NDArray[np.bool_] | None:
        shapes = np.array([_corner(offsets[s, 0], -2.0) if axis == 0 else _corner(-2.0, offsets[s, 1])
                           for s in range(n) for axis in (0, 1)])
        probes = _probe_scene(shapes, cull)
        outcome = call(probes.scene)
        cov = outcome.coverage
        if cov is None:
            errors.append(describe(outcome.error))
            return None
        seen = _samples_at(cov, probes, n)
        return seen[np.arange(2 * n), np.repeat(np.arange(n), 2)].reshape(n, 2)

    at_lo, at_hi = covered(lo), covered(hi)
    if at_lo is None or at_hi is None:
        return lo, hi, np.zeros((n, 2), dtype=bool), errors[0]
    found = at_lo & ~at_hi
    while np.any(hi - lo > 2.0**-resolution):
        mid = (lo + hi) / 2.0  # exact: dyadic
        at_mid = covered(mid)
        if at_mid is None:
            return lo, hi, np.zeros((n, 2), dtype=bool), errors[0]
        lo = np.where(at_mid, mid, lo)
        hi = np.where(at_mid, hi, mid)
    return lo, hi, found, ""


def sample_positions(call: Call, n: int, seed: int = 0, resolution: int = 20) -> PatternFact:
    """The offsets of the ``n`` samples of a multisample rasterizer, in its sample order,
    and the tie rule (and snapping) they follow.

    Culling (one call) picks the probes' winding; the vertex sweep on sample 0
    (:func:`harness.identify.triangle_probes.vertex_sweep`, about 300 calls) sees snapping, and the bisection
    then stops at the snapping grid's spacing (positions on it are never moved), else at
    2**-``resolution`` px. Each sample's flip under a sweeping left (top) edge is bisected,
    every sample and both axes at once (``resolution + 3`` calls), to an interval (lo, hi]
    one step wide. With snapping the true offset may be either end (the coverage changes
    when the *snapped* edge crosses the sample: dEQP's 2x samples at 77/256 under 8-bit
    snapping end intervals at 77/256 and at 78/256 alike), so each axis of each sample
    is read at both ends, and at the points of a finer snapping grid inside
    (:func:`_readings`). The candidates -- each tie rule x the snappings the vertex
    sweep allows, every sample at its best reading for them -- are scored sample by
    sample (:meth:`Convention.at_sample`; the score is a sum over samples, so each
    sample's reading is chosen on its own) on four lattice scenes, one scene of edges
    exactly through every reading's column and row and pinwheels around every reading
    (every tie rule draws a different triangle there, and a sample off its wheel's centre
    sits inside one of its triangles) and, with snapping, two float scenes and their
    half-step versions, where the roundings part. Ties in the score go to the earlier
    candidate (no snapping first) and the earlier reading (the end with fewer fraction
    bits, :func:`_offset`).

    Parameters
    ----------
    call : Call
    n : int
        Samples per pixel (:func:`coverage_kind`).
    seed : int
        Seeds the lattice and float scenes.
    resolution : int

    Returns
    -------
    PatternFact
    """
    calls = Remembered(call)
    if n < 1:
        return PatternFact((), None, 0, 0, None, resolution)
    found = culling(calls)
    cull = found.cull
    vertex = vertex_sweep(layered(calls, 0))
    # positions on the snapping grid are not moved by it (a grid of 2**-g seen means
    # rounding to nearest on 2**-(g-1) or truncating on 2**-g: both keep 2**-(g-1))
    bits = resolution if vertex.grid is None else max(0, vertex.grid - 1)
    lo, hi, flips, error = _bisect_samples(calls, n, cull, bits)
    offsets = tuple((_offset(lo[s, 0], hi[s, 0]), _offset(lo[s, 1], hi[s, 1])) if flips[s].all() else None
                    for s in range(n))
    if not flips.all():
        return PatternFact(offsets, None, 0, 0, None, bits, vertex, found, calls.calls, error=error)
    snaps = _snap_candidates(vertex.grid)
    # each axis of each sample read at either end of its interval (and, under a snapping
    # finer than the bisection stopped at, at that grid's points inside it)
    readings = {snap: [[_readings(lo[s, axis], hi[s, axis], snap[0]) for axis in (0, 1)] for s in range(n)]
                for snap in snaps}
    scenes = [Scene(56, 56, lattice_triangles(120, 48, b, seed + b) + 4.0) for b in (0, 1, 2, 4)]
    # the tie rule and the reading: for each sample, edges exactly through every reading's
    # column and row and pinwheels around every reading; sample s is scored on its own part
    parts: list[NDArray[np.float64]] = []
    for s in range(n):
        points = sorted({(x, y) for per_sample in readings.values() for x in per_sample[s][0] for y in per_sample[s][1]})
        parts.append(np.concatenate([[_corner(x, -2.0) for x in sorted({x for x, _ in points})],
                                     [_corner(-2.0, y) for y in sorted({y for _, y in points})], _wheels(points)]))
    scenes.append(_probe_scene(np.concatenate(parts), cull).scene)
    if any(b is not None for b, _ in snaps):
        floats = [Scene(48, 48, random_triangles(150, 60.0, 48, seed + k)) for k in range(2)]
        scenes += floats + [_half_steps(f, b) for f in floats for b in sorted({b for b, _ in snaps if b is not None})]
    drawn = [tuple(Drawn(scene, layer_of(outcome, s)) for s in range(n)) for scene, outcome in ((sc, calls(sc)) for sc in scenes)]
    tied_scene = 4  # the scene of edges and pinwheels through the readings: where wrong readings show first
    starts = np.cumsum([0] + [len(p) for p in parts])
    scored = [list(layers) for layers in drawn]
    scored[tied_scene] = [_part(drawn[tied_scene][s], range(int(starts[s]), int(starts[s + 1]))) for s in range(n)]
    order = [tied_scene] + [k for k in range(len(drawn)) if k != tied_scene]

    def best_reading(s: int, base: Convention, xs: tuple[float, ...], ys: tuple[float, ...],
                     cap: float) -> tuple[int, tuple[float, float] | None]:
        """Sample ``s``'s reading with the fewest mismatches under ``base`` (ties to the
        earlier reading), and that score; (more than ``cap``, None) when every reading
        has more. A reading is dropped once its partial sum, the tie scene first, cannot
        win (scores only grow)."""
        answered = [k for k in order if scored[k][s].coverage is not None]
        options = [(x, y) for x in xs for y in ys]
        if not options:
            return 0, None
        best: tuple[int, int] | None = None  # (score, reading index)
        over = 0
        for i, option in enumerate(options):
            single = replace(base, sample=option)
            total = 0
            for k in answered:
                total += scored[k][s].mismatches(single)
                if total > cap or (best is not None and (total, i) > best):
                    break
            else:
                best = (total, i) if best is None else min(best, (total, i))
            over = max(over, total)
        if best is None:
            return over, None
        return best[0], options[best[1]]

    # each (snapping, tie rule) scored with every sample at its best reading; the totals are
    # exact for the best candidate and the best of another tie rule (all that is kept):
    # one is given up once it exceeds the second best per tie rule so far, cheap guesses first
    plan = [(b, r, tie) for b, r in snaps for tie in TIE_RULES]
    guess = [scored[tied_scene][0].mismatches(Convention(sample=(xs[0], ys[0]), tie=tie, cull=cull, subpixel_bits=b,
                                                         snap_rounding=r)) if xs and ys else 0
             for b, r, tie in plan for xs, ys in readings[b, r][:1]]
    per_tie: dict[str, int] = {}
    candidates: list[tuple[int, int, Convention]] = []  # (score, order, convention)
    for index in sorted(range(len(plan)), key=lambda i: (guess[i], i)):
        b, r, tie = plan[index]
        base = Convention(sample=(0.5, 0.5), tie=tie, cull=cull, subpixel_bits=b, snap_rounding=r)
        leaders = sorted(per_tie.values())
        cap = leaders[1] if len(leaders) >= 2 else math.inf
        total, chosen = 0, []
        for s in range(n):
            # ties in the score go to the earlier reading: the end with fewer fraction bits first
            xs, ys = readings[b, r][s]
            score, reading = best_reading(s, base, xs, ys, cap - total)
            total += score
            if reading is None or total > cap:
                break
            chosen.append(reading)
        else:
            if len(set(chosen)) == n:
                candidates.append((total, index, replace(base, samples=chosen)))
                per_tie[tie] = min(per_tie.get(tie, total), total)
    if not candidates:
        return PatternFact(offsets, None, 0, 0, None, bits, vertex, found, calls.calls)
    candidates.sort(key=lambda c: c[:2])
    best = candidates[0][2]
    runner = next((c for _, _, c in candidates if c.tie != best.tie), None)  # another tie rule
    fragments = sum(d.pixels for layers in drawn for d in layers)

    def residual_of(convention: Convention) -> int:
        return sum(d.mismatches(convention.at_sample(s)) for layers in drawn for s, d in enumerate(layers))

    residual = residual_of(best)
    said = None
    if runner is not None:
        other = runner
        snapping = "" if (other.subpixel_bits, other.snap_rounding) == (best.subpixel_bits, best.snap_rounding) else (
            ", no snapping" if other.subpixel_bits is None else f", {other.subpixel_bits} sub-pixel bits {other.snap_rounding}")
        moved = "" if other.samples == best.samples else " (the samples read at other ends of their intervals)"
        said = (f"the same samples{moved}, {other.tie} ties{snapping}", residual_of(other))
    return PatternFact(offsets, best, residual, fragments, said, bits, vertex, found, calls.calls, tuple(drawn))
