"""identify's probes for multisample coverage, measured from outside: the sample pattern and its
tie rule (:func:`sample_positions`) and which side of each sample an edge through it covers
(:func:`sample_sides`), on the corner probes of :mod:`harness.identify.coverage_probes`.

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

import numpy as np
from numpy.typing import NDArray

from cases.scenes import lattice_triangles, random_triangles
from harness.contract.conventions import (
    TIE_RULES,
    Convention,
    CullMode,
)
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import Scene
from harness.engine.isolation import Call, describe, layer_of
from harness.identify.coverage_probes import (
    _LEG,
    Remembered,
    _corner,
    _layout,
    _offset,
    _part,
    _probe_scene,
    _readings,
    _samples_at,
    _wheels,
    layered,
)
from harness.identify.triangle_probes import Culling, Drawn, VertexSweep, _half_steps, _snap_candidates, culling, vertex_sweep

__all__ = ["PatternFact", "SampleSides", "sample_positions", "sample_sides"]

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
