"""``rastercheck identify``: fingerprint a black-box rasterizer's convention from outside.

- Sample point and tie rule: the candidate (9 sample points and the measured one x the 8
  tie rules) whose exact oracle best matches the rasterizer on lattice scenes built to
  hit ties (vertices on sample points, edges through them, and piglit's pinwheels of
  eight triangles around a sample, of which each rule draws exactly one).
- Snapping: with that sample point and tie rule, the number of sub-pixel bits (or none)
  and the rounding (nearest-even, half-away, floor) that best explain it on
  unconstrained-float scenes, where snapping shows, and on scenes whose vertices sit
  exactly on half steps of the fitted grid, where the roundings part.
- Culling, zero-area and non-finite handling, the viewport edge (the rasterizer against
  itself inside a larger screen), and watertightness on every planar partition family.

It prints a convention card and the :class:`Convention` that best explains the rasterizer
with the residual mismatch; it says "identified" only when the residual is zero.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cases.partitions import partition_cases
from cases.scenes import lattice_triangles, random_triangles
from harness.api import Coverage, Rasterizer, Scene, interpolates_of, received_of
from harness.checks import FragmentCounter, deviations, watertight
from harness.compare import CANDIDATES
from harness.conventions import SNAP_ROUNDINGS, TIE_RULES, Convention, CullMode, SnapRounding
from harness.oracle import exact_coverage

__all__ = ["Fingerprint", "identify", "identify_isolated", "identify_all", "Identified"]

SNAP_BITS = (None, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16)


@dataclass
class Fingerprint:
    rasterizer: str
    convention: Convention
    residual: int
    pixels: int
    runner_up: tuple[str, int] | None = None
    facts: dict[str, Any] = field(default_factory=dict)
    ambiguous: tuple[str, ...] = ()

    @property
    def exact(self) -> bool:
        """No mismatch, the runner-up (another sample point or tie rule) has some, and no
        other snap rounding explains it as well: a candidate that only ties with another
        is never claimed."""
        return (self.residual == 0 and not (self.runner_up is not None and self.runner_up[1] == 0)
                and not self.ambiguous)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON and the report."""
        return {"rasterizer": self.rasterizer, "convention": self.convention.describe(),
                "sample": list(self.convention.sample), "tie": self.convention.tie,
                "subpixel_bits": self.convention.subpixel_bits, "snap_rounding": self.convention.snap_rounding,
                "cull": self.convention.cull,
                "exact": self.exact, "residual": self.residual, "pixels": self.pixels,
                "runner_up": list(self.runner_up) if self.runner_up else None, "facts": dict(self.facts),
                "ambiguous": list(self.ambiguous)}

    def card(self) -> str:
        lines = [f"rasterizer   {self.rasterizer}",
                 f"convention   {self.convention.describe()}",
                 f"             {self.convention!r}",
                 f"residual     {self.residual} mismatching pixels of {self.pixels}"
                 + ("  (identified exactly)" if self.exact
                    else f"  (ambiguous between {' and '.join(self.ambiguous)})" if self.residual == 0 and self.ambiguous
                    else "  (ambiguous: the next best explains it as well)" if self.residual == 0
                    else "  (best guess only: no candidate explains it exactly)")]
        if self.runner_up:
            lines.append(f"next best    {self.runner_up[0]} ({self.runner_up[1]} mismatches on the tie scenes)")
        for k, v in self.facts.items():
            lines.append(f"{k:<12} {v}")
        return "\n".join(lines)


_COUNTERS: dict[int, tuple[Coverage, FragmentCounter]] = {}


def _mismatch(coverage: Coverage, scene: Scene, convention: Convention) -> int:
    """Missing plus extra pixels of ``coverage`` against the oracle of ``convention``
    (the rasterizer's fragments sorted once per coverage, then merged with each oracle)."""
    held = _COUNTERS.get(id(coverage))
    if held is None or held[0] is not coverage:
        if len(_COUNTERS) > 64:
            _COUNTERS.clear()
        held = _COUNTERS[id(coverage)] = (coverage, FragmentCounter(coverage, scene.width, scene.height))
    return held[1].mismatches(exact_coverage(scene, convention))


def _safe(rasterizer: Rasterizer, scene: Scene) -> Coverage | BaseException:
    try:
        return rasterizer.rasterize(scene)
    except Exception as exc:
        return exc


def _viewport_edge(rasterizer: Rasterizer, seed: int, margin: int = 8) -> str:
    """Whether triangles crossing the viewport edge cover the same on-screen pixels as when
    the screen is grown so that nothing crosses it: convention-free, the rasterizer against
    itself (a clipper that moves vertices before snapping shows up here)."""
    changed = total = 0
    size = 64  # a power of two, as framebuffers, tiles and guard bands often are
    for bits in (0, 2, 4):
        crossing = Scene(size, size, lattice_triangles(120, size, bits, seed + 7 + bits))
        grown = Scene(size + 2 * margin, size + 2 * margin, crossing.positions + float(margin))
        a, b = _safe(rasterizer, crossing), _safe(rasterizer, grown)
        if not isinstance(a, Coverage) or not isinstance(b, Coverage):
            return "not measured: the rasterizer raised"
        ta, xa, ya = a.pixels()
        tb, xb, yb = b.pixels()
        xb, yb = xb - margin, yb - margin
        keep = (xb >= 0) & (xb < size) & (yb >= 0) & (yb < size)
        mine = set(zip(ta.tolist(), xa.tolist(), ya.tolist()))
        inside = set(zip(tb[keep].tolist(), xb[keep].tolist(), yb[keep].tolist()))
        changed += len(mine ^ inside)
        total += len(inside)
    if changed == 0:
        return f"exact ({total} on-screen pixels compared)"
    return (f"{changed} of {total} on-screen pixels change when triangles cross it: "
            "it treats them differently (e.g. clips them before snapping)")


def _fraction_bits(value: float) -> int:
    """The number of binary fraction digits of a float: 0 for an integer, 3 for 0.375."""
    return max(0, value.as_integer_ratio()[1].bit_length() - 1)


# Triangles whose moving vertex (index 0) drags two edges across many sample points; the
# fixed vertices are off every coarse lattice, so without snapping the coverage changes at
# non-dyadic offsets.
_SWEEP_TRIANGLES = (
    ([10.0, 10.0], [41.7, 30.1], [12.2, 50.9]),
    ([30.0, 8.0], [9.3, 40.3], [50.1, 52.7]),
    ([52.0, 40.0], [8.9, 12.6], [20.4, 55.3]),
)


def _vertex_sweep(rasterizer: Rasterizer, changes: int = 6, resolution: int = 16, coarsest: int = 12) -> tuple[int | None, int]:
    """Move one vertex along x (and, for the last triangle, y) and find, by bisection to
    2**-resolution px, the offsets where the coverage changes. Returns (m, count): every
    change happens at a multiple of 2**-m px (None when some change needs more than
    ``coarsest`` fraction bits: no snapping seen), and how many changes were located.

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
            got = _safe(rasterizer, Scene(64, 64, p[None]))
            return got if isinstance(got, Coverage) else None

        lo, start = 0.0, cover(0.0)
        if start is None:
            return None, located
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
                return None, located
    return (finest if finest <= coarsest else None), located


def _residual_kinds(coverages: list[Coverage], scenes: list[Scene], convention: Convention, limit: int = 5000) -> str:
    """Where the lattice residual lies: samples exactly at a vertex (the vertex rule),
    exactly on an edge whose slope dx/dy is not a dyadic fraction (an exact edge function decides those like any other; stepping x by
    dx/dy in floating point rounds there), exactly on a dyadic-slope edge, or off every
    edge (a different rule, not a tie)."""
    from fractions import Fraction

    from harness.exact import orientation

    at_vertex = non_dyadic = dyadic = off = 0
    for cov, scene in zip(coverages, scenes):
        missing, extra = deviations(cov, exact_coverage(scene, convention), scene.width, scene.height)
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
    return (f"{at_vertex} exactly at a vertex, {non_dyadic} exactly on edges of non-dyadic slope dx/dy, "
            f"{dyadic} exactly on dyadic-slope edges, {off} off every edge (lattice scenes)")


def _sample_sweep(rasterizer: Rasterizer, resolution: int = 20) -> tuple[float, float] | None:
    """Sweep a vertical edge, then a horizontal one, across pixel (8, 30) / (30, 8) and find
    by bisection (to 2**-resolution px) the offset inside the pixel where its coverage
    flips: the sample point, measured directly (up to the snapping grid). None when the
    pixel never flips (the rasterizer raised, or draws nothing there)."""
    found = []
    for axis in (0, 1):
        def covered(t: float, axis: int = axis) -> bool | None:
            edge = 8.0 + t
            tri = [[edge, 2.0], [edge, 60.0], [40.0, 31.0]] if axis == 0 else [[2.0, edge], [60.0, edge], [31.0, 40.0]]
            got = _safe(rasterizer, Scene(64, 64, np.array([tri])))
            if not isinstance(got, Coverage):
                return None
            t_, x, y = got.pixels()
            px, py = (8, 30) if axis == 0 else (30, 8)
            return bool(np.any((x == px) & (y == py)))

        lo, hi = -0.5, 1.5  # the pixel is inside at lo (edge left of it), outside at hi
        if covered(lo) is not True or covered(hi) is not False:
            return None
        while hi - lo > 2.0**-resolution:
            mid = (lo + hi) / 2.0
            answer = covered(mid)
            if answer is None:
                return None
            lo, hi = (mid, hi) if answer else (lo, mid)
        found.append(lo if _fraction_bits(lo) <= _fraction_bits(hi) else hi)
    return found[0], found[1]


def _tie_triangles(sample: tuple[float, float], seed: int, count: int = 200) -> NDArray[np.float64]:
    """(count, 3, 2): triangles whose vertices all sit on sample points (i + sx, j + sy) of a
    48 px square (moved 4 px in), each with a horizontal or a vertical edge, both windings:
    every tie rule is exercised at this sample point."""
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
    return np.stack([base, second, third], axis=1) + np.array(sample) + 4.0


def _pinwheels(sample: tuple[float, float], sizes: tuple[int, ...] = (1, 2, 3)) -> NDArray[np.float64]:
    """(8 * 30 * len(sizes), 3, 2): piglit's probe, eight triangles around a sample point
    (split by the axes and diagonals, sizes in whole pixels), at 30 sample points of a 48
    px square moved 4 px in. The sample is every triangle's vertex and lies on two edges of
    each; each of the eight tie rules gives it to exactly one triangle, a different one."""
    wheels = []
    rim = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], dtype=np.float64)
    for k in range(30):
        centre = np.array([6.0 + (k % 6) * 7.0, 6.0 + (k // 6) * 8.0]) + np.array(sample) + 4.0
        size = sizes[k % len(sizes)]
        for i in range(8):
            wheels.append([centre + size * rim[i], centre + size * rim[i + 1], centre])
    return np.array(wheels)


def _half_steps(scene: Scene, bits: int) -> Scene:
    """The scene with every coordinate moved onto an odd multiple of 2**-(bits+1) -- a half
    step of the 2**-bits grid, where rounding to nearest must break a tie -- and kept at
    least 1 px from the origin (a frame's rounding sign plays no part there)."""
    scale = 2.0**bits
    moved = (np.floor(np.abs(scene.positions) * scale) + 0.5) / scale + 1.0
    return Scene(scene.width, scene.height, moved)


def _sample_candidates(measured: tuple[float, float] | None) -> list[tuple[float, float]]:
    """The 9 standard sample points, plus the measured one at a few dyadic precisions."""
    samples = list(dict.fromkeys(c.sample for c in CANDIDATES))
    if measured is not None:
        for bits in (1, 2, 3, 4, 6, 8, 12):
            sx, sy = (min(1.0, max(0.0, round(v * 2**bits) / 2**bits)) for v in measured)
            if (sx, sy) not in samples:
                samples.append((sx, sy))
    return samples


def _epsilon(rasterizer: Rasterizer, convention: Convention) -> str:
    """Tiny triangles (1e-3 down to 1e-9 px across) around sample points, half of them
    holding their sample strictly inside and half just missing it, against the exact
    answer of ``convention``."""
    sx, sy = convention.sample
    triangles = []
    for k, size in enumerate(np.repeat(10.0 ** -np.arange(3, 10), 8)):
        x, y = 4.0 + (k % 12) * 4.0 + sx, 4.0 + (k // 12) * 4.0 + sy
        shift = 0.0 if k % 2 == 0 else 2.0 * size  # odd ones sit just to the right of the sample
        triangles.append([[x - size + shift, y - size], [x + size + shift, y - size], [x + shift, y + size]])
    scene = Scene(56, 32, np.array(triangles))
    got = _safe(rasterizer, scene)
    if not isinstance(got, Coverage):
        return f"raises {type(got).__name__}: {got}"[:120]
    wrong = _mismatch(got, scene, convention)
    want = exact_coverage(scene, convention).n_pixels
    if wrong == 0:
        return f"exact: {want} of {len(triangles)} tiny triangles (1e-3..1e-9 px) drawn, as the convention says"
    said = f"{wrong} of {len(triangles)} tiny triangles (1e-3..1e-9 px) decided unlike the convention ({want} should draw)"
    received = received_of(rasterizer)
    if received is not None:
        rounded = received(scene)
        if _mismatch(got, rounded, convention) == 0:
            said += "; exact for the coordinates as the library receives them (its input format rounds them)"
    return said


def identify(rasterizer: Rasterizer, seed: int = 0) -> Fingerprint:
    """The convention that best explains ``rasterizer``, its residual, and other facts."""
    facts: dict[str, Any] = {}
    # culling: one large clockwise and one counter-clockwise triangle
    cw = np.array([[[4.25, 4.5], [40.5, 6.25], [8.75, 40.5]]])
    cull_scene = Scene(48, 48, np.concatenate([cw, cw[:, ::-1] + np.array([2.0, 0.0])]))
    drawn = _safe(rasterizer, cull_scene)
    cull = "none"
    if isinstance(drawn, Coverage):
        which = set(drawn.triangle[drawn.x1 > drawn.x0].tolist())
        cull = "none" if which == {0, 1} else "cw" if which == {1} else "ccw" if which == {0} else "both"
        facts["culling"] = {"none": "draws both windings", "cw": "culls clockwise", "ccw": "culls counter-clockwise", "both": "draws neither winding"}[cull]
    cull_mode: CullMode = "cw" if cull == "cw" else "ccw" if cull == "ccw" else "none"
    # lattice triangles reach 2 px past a 48 px square; moved 4 px into a 56 px screen
    # (exactly) nothing crosses the viewport edge, so clipping cannot blur the convention
    # an edge swept across a pixel measures the sample point directly, even off the 9 usual ones
    measured = _sample_sweep(rasterizer)
    facts["sample sweep"] = ("no flip found (the pixel never changed)" if measured is None else
                             f"an edge swept across a pixel flips it at offset ({measured[0]:.6g}, {measured[1]:.6g}) "
                             "(bisected to 2^-20 px; snapping moves it by up to one grid step)")
    lattice = [Scene(56, 56, lattice_triangles(120, 48, bits, seed + bits) + 4.0) for bits in (0, 1, 2, 4)]
    # ties at the measured sample point: vertices on samples, axis-aligned edges through rows of them
    floats = [Scene(48, 48, random_triangles(150, 60.0, 48, seed + k)) for k in range(2)]
    lattice_cov = [rasterizer.rasterize(s) for s in lattice]
    # a vertex sweep that sees a snapping grid lets the sample and tie be fitted under it
    grid, located = _vertex_sweep(rasterizer)
    snaps: list[tuple[int | None, SnapRounding]] = [(None, "nearest-even")]
    if grid is not None:
        snaps += [(grid - 1, "nearest-even"), (grid - 1, "half-away"), (grid, "floor")]
        snaps = [(b, r) for b, r in snaps if b is None or 0 <= b <= 16]
    candidates = [Convention(sample=sample, tie=tie, cull=cull_mode, subpixel_bits=b, snap_rounding=r)
                  for b, r in snaps for sample in _sample_candidates(measured) for tie in TIE_RULES]
    scores = sorted(((sum(_mismatch(c, s, cand) for c, s in zip(lattice_cov, lattice)), i) for i, cand in enumerate(candidates)))
    # then ties at the best sample point: vertices on samples, axis-aligned edges through
    # rows of them, so that every tie rule shows there
    for ties in (_tie_triangles(candidates[scores[0][1]].sample, seed), _pinwheels(candidates[scores[0][1]].sample)):
        lattice.append(Scene(56, 56, ties))
        lattice_cov.append(rasterizer.rasterize(lattice[-1]))
        scores = sorted((score + _mismatch(lattice_cov[-1], lattice[-1], candidates[i]), i) for score, i in scores)
    best = candidates[scores[0][1]]
    # the runner-up differs in sample point or tie rule (snapping cannot show on lattices)
    runner_score, runner_index = next((sc, i) for sc, i in scores
                                      if (candidates[i].sample, candidates[i].tie) != (best.sample, best.tie))
    runner = candidates[runner_index]
    float_cov = [rasterizer.rasterize(s) for s in floats]

    def fitted(bits: int | None, rounding: SnapRounding) -> Convention:
        return Convention(sample=best.sample, tie=best.tie, subpixel_bits=bits, cull=cull_mode, snap_rounding=rounding)

    snap_scores: list[tuple[int, int, int | None, SnapRounding]] = []
    for bits in SNAP_BITS:
        for rounding in SNAP_ROUNDINGS if bits is not None else ("nearest-even",):
            score = sum(_mismatch(c, s, fitted(bits, rounding)) for c, s in zip(float_cov, floats))
            # ties prefer no snapping, then rounding to nearest even
            snap_scores.append((score, 0 if bits is None else 1 + SNAP_ROUNDINGS.index(rounding), bits, rounding))
    snap_scores.sort(key=lambda s: (s[0], s[1]))
    bits, rounding = snap_scores[0][2], snap_scores[0][3]
    ambiguous: tuple[str, ...] = ()
    if bits is not None:
        # floats almost never sit on a half step, where nearest-even and half-away part:
        # put every vertex on one, and fit the rounding there
        halves = [_half_steps(s, bits) for s in floats]
        floats += halves
        float_cov += [rasterizer.rasterize(s) for s in halves]
        rounding_scores = sorted(
            (sum(_mismatch(c, s, fitted(bits, r)) for c, s in zip(float_cov, floats)), SNAP_ROUNDINGS.index(r), r)
            for r in SNAP_ROUNDINGS
        )
        rounding = rounding_scores[0][2]
        tied = [r for score, _, r in rounding_scores if score == rounding_scores[0][0]]
        if len(tied) > 1:
            ambiguous = tuple(f"{bits} bits {r}" for r in tied)
        facts["rounding"] = "; ".join(f"{r}: {score} mismatches" for score, _, r in rounding_scores) + (
            f" (with every vertex on a half step of the 2^-{bits} grid)")
    convention = fitted(bits, rounding)
    residual = sum(_mismatch(c, s, convention) for c, s in zip([*lattice_cov, *float_cov], [*lattice, *floats]))
    pixels = sum(c.n_pixels for c in [*lattice_cov, *float_cov])
    if residual:
        facts["residual lies"] = _residual_kinds(lattice_cov, lattice, convention)
    facts["viewport edge"] = _viewport_edge(rasterizer, seed)
    facts["epsilon"] = _epsilon(rasterizer, convention)
    # degenerate and non-finite handling
    zero = Scene(32, 32, np.array([[[4.5, 4.5], [12.5, 12.5], [20.5, 20.5]], [[8, 8], [8, 8], [20, 14]]], dtype=np.float64))
    flat = _safe(rasterizer, zero)
    facts["zero area"] = (f"raises {type(flat).__name__}" if isinstance(flat, BaseException)
                          else "draws nothing" if flat.n_pixels == 0 else f"draws {flat.n_pixels} pixels")
    answers = []
    for label, value in (("NaN", np.nan), ("inf", np.inf)):
        bad = Scene(32, 32, np.array([[[value, 4], [10, 10], [4, 20]], [[4.5, 4.5], [20.5, 4.5], [4.5, 20.5]]]))
        answer = _safe(rasterizer, bad)
        if isinstance(answer, BaseException):
            answers.append(f"{label}: raises {type(answer).__name__}: {answer}"[:120])
        else:
            covered = int(np.sum((answer.triangle == 0) * (answer.x1 - answer.x0)))
            rest = "the rest drawn" if 1 in set(answer.triangle.tolist()) else "the finite triangle lost too"
            answers.append(f"{label}: {'covers nothing' if covered == 0 else f'DRAWS {covered} pixels'}, {rest}")
    facts["non-finite"] = "; ".join(answers)
    # watertight on planar partitions
    holes = doubles = 0
    partitions = partition_cases(seed)
    for case in partitions:
        cov = _safe(rasterizer, case.scene)
        if isinstance(cov, Coverage):
            r = watertight(case, cov)
            holes += int(r.metrics.get("holes", 0))
            doubles += int(r.metrics.get("double_hits", 0))
    n = len(partitions)
    facts["watertight"] = (f"yes (no hole, no double hit on {n} partitions)" if holes == doubles == 0
                           else f"no: {holes} holes, {doubles} double hits on {n} partitions")
    facts["snapping"] = ((f"{bits} sub-pixel bits, " + {"nearest-even": "half to even", "half-away": "half away from zero",
                                                         "floor": "rounding down"}[rounding]) if bits is not None
                         else "none detected") + f" ({snap_scores[0][0]} float mismatches)"
    if located == 0:
        facts["vertex sweep"] = "no coverage change located (the rasterizer raised or drew nothing)"
    elif grid is None:
        facts["vertex sweep"] = (f"{located} coverage changes at arbitrary offsets (bisected to 2^-16 px): "
                                 "no vertex snapping down to 2^-12 px" + (" (agrees)" if bits is None else f" (the fit's {bits} bits are NOT confirmed)"))
    else:
        nearest = grid - 1  # a grid rounded to nearest changes halfway between its points
        fits = (bits, rounding) in ((nearest, "nearest-even"), (nearest, "half-away"), (grid, "floor"))
        agree = " (agrees with the fit)" if fits else f" (the fit says {bits if bits is not None else 'none'}, {rounding}: not confirmed)"
        facts["vertex sweep"] = (f"{located} coverage changes, all at multiples of 2^-{grid} px: vertices snap to 2^-{nearest} px "
                                 f"rounding to nearest, or 2^-{grid} px truncating" + agree)
    _COUNTERS.clear()  # the sorted fragments were for this rasterizer's scenes only
    return Fingerprint(rasterizer.name, convention, residual, pixels, (runner.describe(), runner_score), facts, ambiguous)


class _TimeLimited:
    """The rasterizer with each call cut off after ``seconds`` by SIGALRM (a TimeoutError,
    which the probes record like any other exception). Only for a child process."""

    def __init__(self, inner: Rasterizer, seconds: float) -> None:
        self.inner, self.seconds = inner, seconds
        self.name, self.convention = inner.name, inner.convention
        for optional in ("interpolates", "received"):
            if hasattr(inner, optional):
                setattr(self, optional, getattr(inner, optional))

    def rasterize(self, scene: Scene) -> Coverage:
        import signal

        def expire(signum: int, frame: Any) -> None:
            raise TimeoutError(f"no answer within {self.seconds:g} s")

        previous = signal.signal(signal.SIGALRM, expire)
        signal.setitimer(signal.ITIMER_REAL, self.seconds)
        try:
            return self.inner.rasterize(scene)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)


def _child(rasterizer: Rasterizer, seed: int, conn: Any, call_timeout: float | None) -> None:  # pragma: no cover - runs in the child
    try:
        if call_timeout:
            rasterizer = _TimeLimited(rasterizer, call_timeout)
        conn.send(identify(rasterizer, seed))
    except Exception as exc:
        conn.send(RuntimeError(f"identify failed: {type(exc).__name__}: {exc}"))


def identify_isolated(rasterizer: Rasterizer, seed: int = 0, timeout: float = 600.0,
                      call_timeout: float | None = None) -> Fingerprint:
    """:func:`identify` in a forked process of its own, so that a library's process-wide
    state (an EGL display, a crash, a hang) stays out of the caller. ``timeout`` bounds the
    whole; ``call_timeout`` each rasterize call (a call that hangs in Python then counts
    as raising TimeoutError, and identification goes on)."""
    import multiprocessing

    context = multiprocessing.get_context("fork")
    parent, child = context.Pipe()
    process = context.Process(target=_child, args=(rasterizer, seed, child, call_timeout), daemon=True)
    process.start()
    child.close()
    try:
        if not parent.poll(timeout):
            raise TimeoutError(f"identify {rasterizer.name}: no answer within {timeout:g} s")
        answer = parent.recv()
    except EOFError:
        raise RuntimeError(f"identify {rasterizer.name}: the process died (exit code {process.exitcode})") from None
    finally:
        if process.is_alive():
            process.kill()
        process.join(5)
    if isinstance(answer, BaseException):
        raise answer
    return answer


class Identified:
    """A rasterizer that declares no convention, checked against the one identified for it."""

    def __init__(self, inner: Rasterizer, fingerprint: Fingerprint) -> None:
        self.inner = inner
        self.name = inner.name
        self.convention = fingerprint.convention
        self.interpolates = interpolates_of(inner)
        if hasattr(inner, "received"):
            self.received = inner.received
        self.fingerprint = fingerprint

    def rasterize(self, scene: Scene) -> Coverage:
        return self.inner.rasterize(scene)


def identify_all(rasterizers: list[Rasterizer], seed: int = 0, *, everyone: bool = False, call_timeout: float = 60.0,
                 report: Callable[[str], None] | None = None) -> tuple[list[Rasterizer], dict[str, dict[str, Any]]]:
    """Identify the rasterizers that declare no convention (all of them with
    ``everyone``), each in a process of its own; one that declares none is then checked
    against the one identified for it (:class:`Identified`). A failure to identify is kept
    as an error entry, and that rasterizer runs without a convention.

    Returns
    -------
    rasterizers : the same, undeclared ones wrapped
    fingerprints : name -> :meth:`Fingerprint.to_dict` or ``{"error": ...}``
    """
    out: list[Rasterizer] = []
    fingerprints: dict[str, dict[str, Any]] = {}
    for r in rasterizers:
        if r.convention is not None and (not everyone or isinstance(r, Identified)):
            out.append(r)
            continue
        try:
            fingerprint = identify_isolated(r, seed, timeout=max(300.0, 10 * call_timeout), call_timeout=call_timeout)
        except Exception as exc:
            fingerprints[r.name] = {"error": f"{type(exc).__name__}: {exc}"}
            if report is not None:
                report(f"identify {r.name}: {type(exc).__name__}: {exc}")
            out.append(r)
            continue
        fingerprints[r.name] = fingerprint.to_dict()
        # a rasterizer that declares no convention is checked against the one identified for it
        out.append(Identified(r, fingerprint) if r.convention is None else r)
    return out, fingerprints
