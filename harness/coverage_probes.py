"""identify's probes for coverage beyond one sample: the kind, an anti-aliaser's grid and
quantisation, a multisample pattern, each measured from outside.

Like :mod:`harness.probes`, each probe calls the rasterizer only through a
:data:`~harness.isolation.Call` and returns a frozen record (``text`` is its line on the
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
from harness.api import Coverage, Scene
from harness.conventions import MAX_AREA_SAMPLES, TIE_RULES, Convention, CoverageKind, CullMode
from harness.isolation import Call, Outcome, describe, layer_of
from harness.oracle import exact_coverage
from harness.probes import Culling, Drawn, VertexSweep, _half_steps, _snap_candidates, culling, vertex_sweep
from harness.samples import STANDARD_PATTERNS

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
# the area oracle's float error (<= 2**-24, harness.area.area_error_bound) plus an alpha
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
    def text(self) -> str:
        if self.kind is None:
            return f"not measured: the rasterizer raised {self.error}"[:120]
        if self.kind == "area":
            return "area: an alpha per pixel and triangle (anti-aliased)"
        if self.kind == "single":
            return "single: one sample per pixel"
        said = f"multisample: {self.samples} samples per pixel (indices {', '.join(map(str, self.indices))})"
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
        return CoverageKindFact("area")
    if cov.sample is None:
        return CoverageKindFact("single")
    t, x, y = cov.pixels()
    s = cov.fragment_samples()
    whole = (t <= 1) & (x >= 4) & (x <= 10) & (y >= 4) & (y <= 10)  # inside either winding's 28 px triangle
    whole &= t == (t[whole].min() if whole.any() else 0)  # one winding: the first drawn
    key = y[whole] * 32 + x[whole]
    per_pixel = [len(set(s[whole][key == k].tolist())) for k in np.unique(key)]
    return CoverageKindFact("multisample", tuple(sorted(set(s[whole].tolist()))), tuple(sorted(set(per_pixel))))


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
    keys = np.union1d(kg, kw)
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

    @property
    def coverage(self) -> Coverage | None:
        return self.outcome.coverage

    def differences(self, convention: Convention) -> NDArray[np.float64]:
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
                "sweeps": "; ".join(s.text for s in (self.vertical, self.horizontal, self.slanted) if s is not None)}


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
    than :data:`~harness.conventions.MAX_AREA_SAMPLES` samples, the candidate is
    ``Convention(coverage="area", levels=..., tolerance=...)`` with the largest measured
    |alpha - area| rounded up (None when it is within half a level).

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
                candidates = [Convention(coverage="area", samples=pattern, tie=tie, cull=cull) for tie in TIE_RULES]
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
        half = 0.5 / (levels - 1) if levels is not None else 0.5 / (CONTINUOUS_LEVELS - 1)
        tolerance = None if max_error <= half + SLACK else _rounded_up(max_error)
        convention = Convention(coverage="area", levels=levels or CONTINUOUS_LEVELS, tolerance=tolerance, cull=cull)
    # a tolerance measured on these very probes explains them by construction: the
    # residual counts what lies beyond half a level of the oracle, which rounding to the
    # levels keeps within
    residual = sum(x.beyond(replace(convention, tolerance=None)) for x in answered)
    max_residual = max((float(np.abs(x.differences(convention)).max(initial=0.0)) for x in answered), default=0.0)
    return SweepFact(model, sweeps[0], sweeps[1], sweeps[2], levels, max_error, mean_error, pattern, layout, convention,
                     residual, max_residual, pixels, runner_up, calls.calls, drawn=tuple(drawn))


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

    ``offsets``: sample s's offset, in the rasterizer's sample order (None for a sample
    that never flipped). ``convention``: the best candidate (the offsets as its tie rule
    reads the bisection, with the snapping the vertex sweep allows), None when a sample
    was not found; ``residual`` its mismatching fragments of ``fragments`` over the fit
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

    @property
    def pattern(self) -> tuple[tuple[float, float], ...] | None:
        """The offsets as the convention has them, or None."""
        return None if self.convention is None else self.convention.samples

    @property
    def text(self) -> str:
        if self.convention is None or self.pattern is None:
            if not self.offsets:
                return "not recovered: no sample index seen in a pixel a triangle covers whole"
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


# the sides check's step past a sample: beyond any snapping grid of 4 bits or finer (which
# moves an edge by 1/32 px at most), far below a pattern's spacing
SIDE_STEP = 1.0 / 16.0


@dataclass(frozen=True)
class SampleSides:
    """Whether each sample found under left and top edges (:class:`PatternFact`'s offsets)
    is where right and bottom edges find it too: an edge :data:`SIDE_STEP` px to its other
    side, the sample inside, must cover it. ``dropped``: (sample, axis, offset) of those
    not covered -- a sample's coverage that depends on which side the edge comes from is
    no pattern at all: samples dropped near edges (a pixel rejected whole when its centre
    lies outside an edge, by too small a margin), not a wrong pattern. ``calls``: 1 (0
    when no offset was measured)."""

    dropped: tuple[tuple[int, str, float], ...] = ()
    checked: int = 0
    calls: int = 0
    error: str = ""

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
        return (f"SAMPLES DROPPED NEAR EDGES: {shown} not covered by an edge {SIDE_STEP:g} px past it on the other "
                "side (a right edge for x, a bottom one for y) -- whether a sample counts depends on the side its edge "
                "comes from, so no pattern explains it (not a wrong pattern)")


def sample_sides(call: Call, offsets: Sequence[tuple[float, float] | None], cull: CullMode) -> SampleSides:
    """:class:`SampleSides` of the offsets measured under left and top edges: for every
    sample and axis, one mirrored corner probe (covering x < offset + :data:`SIDE_STEP`
    within the pixel, or y < ...), all in one call."""
    found = [(s, o) for s, o in enumerate(offsets) if o is not None]
    if not found:
        return SampleSides()
    shapes = []
    for _, (x, y) in found:
        for a, b in ((x + SIDE_STEP, 3.0), (3.0, y + SIDE_STEP)):  # a right edge past it, a bottom one
            shapes.append(np.array([[a, b], [a - _LEG, b], [a, b - _LEG]]))  # the corner turned half round
    probes = _probe_scene(np.array(shapes), cull)
    outcome = call(probes.scene)
    if outcome.coverage is None:
        return SampleSides(error=describe(outcome.error), calls=1)
    seen = _samples_at(outcome.coverage, probes, len(offsets))
    dropped = []
    for k, (s, (x, y)) in enumerate(found):
        for j, (axis, o) in enumerate((("x", x), ("y", y))):
            if not seen[2 * k + j, s]:
                dropped.append((s, axis, o))
    return SampleSides(tuple(dropped), len(found), 1)


def _bisect_samples(call: Call, n: int, cull: CullMode, resolution: int) -> tuple[
        NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """For every sample s and axis, the offsets (lo, hi], 2**-resolution px apart, between
    which a left (top) edge sweeping the pixel stops covering sample s: every sample at
    once, one call per halving, probe 2 s + axis reading sample s.

    Returns
    -------
    lo, hi : (n, 2) float64
    found : (n, 2) bool
        False where sample s is not covered with the edge 1 px before the pixel or still
        covered with it 1 px past it (or an answer was missing).
    """
    lo = np.full((n, 2), -1.0)
    hi = np.full((n, 2), 1.0)

    def covered(offsets: NDArray[np.float64]) -> NDArray[np.bool_] | None:
        shapes = np.array([_corner(offsets[s, 0], -2.0) if axis == 0 else _corner(-2.0, offsets[s, 1])
                           for s in range(n) for axis in (0, 1)])
        probes = _probe_scene(shapes, cull)
        cov = call(probes.scene).coverage
        if cov is None:
            return None
        seen = _samples_at(cov, probes, n)
        return seen[np.arange(2 * n), np.repeat(np.arange(n), 2)].reshape(n, 2)

    at_lo, at_hi = covered(lo), covered(hi)
    if at_lo is None or at_hi is None:
        return lo, hi, np.zeros((n, 2), dtype=bool)
    found = at_lo & ~at_hi
    while np.any(hi - lo > 2.0**-resolution):
        mid = (lo + hi) / 2.0  # exact: dyadic
        at_mid = covered(mid)
        if at_mid is None:
            return lo, hi, np.zeros((n, 2), dtype=bool)
        lo = np.where(at_mid, mid, lo)
        hi = np.where(at_mid, hi, mid)
    return lo, hi, found


def sample_positions(call: Call, n: int, seed: int = 0, resolution: int = 20) -> PatternFact:
    """The offsets of the ``n`` samples of a multisample rasterizer, in its sample order,
    and the tie rule (and snapping) they follow.

    Culling (one call) picks the probes' winding; the vertex sweep on sample 0
    (:func:`harness.probes.vertex_sweep`, about 300 calls) sees snapping, and the bisection
    then stops at the snapping grid's spacing (positions on it are never moved), else at
    2**-``resolution`` px. Each sample's flip under a sweeping left (top) edge is bisected,
    every sample and both axes at once (``resolution + 3`` calls), and read as the end of
    its last interval with fewer fraction bits (:func:`_offset`). The candidates -- those
    offsets under each tie rule, x the snappings the vertex sweep allows -- are scored
    sample by sample (:meth:`Convention.at_sample`) on four lattice scenes, one scene of
    edges exactly through every sample's column and row and pinwheels around every
    sample (every tie rule draws a different triangle there) and, with snapping, two
    float scenes and their half-step versions, where the roundings part. Ties in the
    score go to the earlier candidate (no snapping first).

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
    lo, hi, flips = _bisect_samples(calls, n, cull, bits)
    offsets = tuple((_offset(lo[s, 0], hi[s, 0]), _offset(lo[s, 1], hi[s, 1])) if flips[s].all() else None
                    for s in range(n))
    if not flips.all():
        return PatternFact(offsets, None, 0, 0, None, bits, vertex, found, calls.calls)
    pattern = [o for o in offsets if o is not None]
    if len(set(pattern)) < n:
        return PatternFact(offsets, None, 0, 0, None, bits, vertex, found, calls.calls)
    snaps = _snap_candidates(vertex.grid)
    candidates = [Convention(samples=pattern, tie=tie, cull=cull, subpixel_bits=b, snap_rounding=r)
                  for b, r in snaps for tie in TIE_RULES]
    scenes = [Scene(56, 56, lattice_triangles(120, 48, b, seed + b) + 4.0) for b in (0, 1, 2, 4)]
    # the tie rule: edges exactly through every sample's column and row, pinwheels around every sample
    ties = np.concatenate([[_corner(x, -2.0) for x, _ in pattern], [_corner(-2.0, y) for _, y in pattern], _wheels(pattern)])
    scenes.append(_probe_scene(ties, cull).scene)
    if any(b is not None for b, _ in snaps):
        floats = [Scene(48, 48, random_triangles(150, 60.0, 48, seed + k)) for k in range(2)]
        scenes += floats + [_half_steps(f, b) for f in floats for b in sorted({b for b, _ in snaps if b is not None})]
    drawn = [tuple(Drawn(scene, layer_of(outcome, s)) for s in range(n)) for scene, outcome in ((sc, calls(sc)) for sc in scenes)]

    def score(convention: Convention) -> int:
        return sum(d.mismatches(convention.at_sample(s)) for layers in drawn for s, d in enumerate(layers)
                   if d.coverage is not None)

    scores = sorted((score(c), i) for i, c in enumerate(candidates))
    best = candidates[scores[0][1]]
    runner = next(((s, candidates[i]) for s, i in scores if candidates[i].tie != best.tie), None)  # another tie rule
    fragments = sum(d.pixels for layers in drawn for d in layers)
    residual = sum(d.mismatches(best.at_sample(s)) for layers in drawn for s, d in enumerate(layers))
    said = None
    if runner is not None:
        other = runner[1]
        snapping = "" if (other.subpixel_bits, other.snap_rounding) == (best.subpixel_bits, best.snap_rounding) else (
            ", no snapping" if other.subpixel_bits is None else f", {other.subpixel_bits} sub-pixel bits {other.snap_rounding}")
        said = (f"the same samples, {other.tie} ties{snapping}", runner[0])
    return PatternFact(offsets, best, residual, fragments, said, bits, vertex, found, calls.calls, tuple(drawn))
