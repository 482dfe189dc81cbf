"""identify's probes for coverage beyond one sample, the part every such probe shares: the
corner probe scenes, the calls remembered and layered, and the kind of coverage
(:func:`coverage_kind`). An anti-aliaser's grid, levels and input grid are measured by
:mod:`harness.identify.area_probes`, a multisample pattern by
:mod:`harness.identify.sample_probes`.

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
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import (
    CoverageKind,
    CullMode,
)
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import AREA, MULTISAMPLE, SINGLE, CoverageModel, model_named
from harness.contract.scenes import Scene
from harness.engine.isolation import Call, Outcome, describe, layer_of
from harness.identify.triangle_probes import Drawn

__all__ = ["Remembered", "layered", "CoverageKindFact", "coverage_kind"]

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

    coverage_kind: CoverageKind | None
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
        return None if self.coverage_kind is None else model_named(self.coverage_kind)

    @property
    def text(self) -> str:
        model = self.model
        if model is None:
            return f"not measured: the rasterizer raised {self.error}"[:120]
        if not model.sample_ids:
            return f"{model.coverage_kind}: {model.seen}"
        said = f"{model.coverage_kind}: {self.samples} {model.seen} (indices {', '.join(map(str, self.indices))})"
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
        return CoverageKindFact(AREA.coverage_kind)
    if cov.sample is None:
        return CoverageKindFact(SINGLE.coverage_kind)
    t, x, y = cov.pixels()
    s = cov.fragment_samples()
    whole = (t <= 1) & (x >= 4) & (x <= 10) & (y >= 4) & (y <= 10)  # inside either winding's 28 px triangle
    whole &= t == (t[whole].min() if whole.any() else 0)  # one winding: the first drawn
    key = y[whole] * 32 + x[whole]
    per_pixel = [len(set(s[whole][key == k].tolist())) for k in np.unique(key)]
    return CoverageKindFact(MULTISAMPLE.coverage_kind, tuple(sorted(set(s[whole].tolist()))), tuple(sorted(set(per_pixel))))


def _layout(pattern: Sequence[tuple[float, float]]) -> str:
    """The shape of a pattern, in words: a regular (uniformly spaced) or irregular full
    n x m grid, n-rooks (every column and row once), or neither.

    >>> _layout([(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)])
    'regular 2 x 2 grid (4 samples)'
    >>> from harness.contract.samples import STANDARD_PATTERNS
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
    2**-(g - 1) does). Only offsets within the pixel, [0, 1), are kept. Without snapping
    (``grid`` None) the bisection went to 2**-20 px and the two ends are a tie rule apart
    on any scene of coarser vertices: the end with fewer fraction bits only.

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
