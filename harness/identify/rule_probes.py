"""identify's probes for the coverage rules (issue 33): which of ``area-threshold``,
``conservative-over`` and ``conservative-under`` (and at which snapping and threshold) a
rasterizer's aliased answers follow, measured from outside.

The probes are single triangles in a 16 x 16 viewport: on the quarter-pixel lattice (exact
halves and edges through pixel corners: where the rules and thresholds disagree), on whole
pixels (squares touching edges and corners only) and at random float positions, each in
both orientations (a rasterizer whose rule depends on the winding shows it).

The closed rule (``closed``: samples on an edge inside) is tried at each snapping too, and
on 26.6 input with TrueType's dropout control as ftraster.c runs it (:data:`CLOSED_SCANS`):
the probes' slivers between pixel centres and their edges near centres tell the modes and
the crossings' arithmetic apart.

The three square rules tell themselves apart on these at once: conservative-over draws every
square an edge touches, under none that an edge crosses, a threshold half of those. The
threshold is read from the answers, not guessed: under snapping s, a threshold rasterizer
draws every pixel covered at least t and no other, so t lies in ``(largest area left
undrawn, smallest area drawn]`` (the areas of the snapped triangles); the simplest dyadic
number in that interval (fewest bits) is the candidate, and the exact oracle then counts
its residual. Snapping candidates: none, and 4, 6 or 8 bits under each rounding.

The rules read from libraries' sources (``agg-cover``, ``inclusive-scanline``: a model with
``input_bits``) are tried on their own grid under each input rounding; ``agg-cover``'s
threshold is read the same way from AGG's 8-bit covers of the probe pixels (the split of the
covers drawn and left undrawn, as a share of 256). When such a rule ties for best with
another candidate on the probes (an input rounding, or a threshold on the exact area),
:func:`separating_scenes` (vertices halfway between grid points, some off screen to the
left and above, kept where the tied candidates disagree) tell them apart: their pixels off
there are added to the tied candidates' residuals (the best's ``pixels`` count its own);
on screen first, then, for those still tied, with vertices off screen too (only there do
floor and toward-zero differ; there the libraries also clip, which the rules do not model).

:func:`fit_rule` gives the best convention, its residual (pixels off over the probes), the
runner-up, and the fit on each orientation alone when they differ
(:class:`RuleFit`). Run on a rasterizer: ``python -m harness.identify.rule_probes
module:Class``.

identify asks these probes when the sample-point fit leaves a residual
(:func:`fit_rule_beside`): the best rule is then scored on every scene drawn so far (the tie,
snapping and input fits' and these), beside the sample-point convention on the same
scenes, and it replaces that convention only when it explains the rasterizer strictly
better there (:class:`RuleFact`, the card's "coverage rule" line).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import (
    INPUT_ROUNDINGS,
    PLAIN_SNAP_ROUNDINGS,
    Convention,
    Dropout,
    dropout_control,
)
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import AGG_COVER, COVERAGE_RULES
from harness.contract.scenes import Scene
from harness.engine.isolation import Call
from harness.geometry.exact import orientation
from harness.identify.triangle_probes import Drawn, draw
from harness.oracle.area import pixel_areas
from harness.oracle.coverage import exact_coverage

__all__ = ["RuleFit", "RuleFact", "fit_rule_beside", "probe_scenes", "separating_scenes", "rule_candidates",
           "library_candidates", "fit_rule", "simplest_dyadic"]

SIZE = 16
# above the float areas' error (harness.oracle.area.area_error_bound < 2**-24), below any probe's gap between areas
_AREA_SLACK = 2.0**-30
# the snappings tried: none, then 4, 6 and 8 bits under each rounding
SNAPPINGS: tuple[tuple[int | None, str], ...] = ((None, "nearest-even"),
                                                 *((b, r) for b in (4, 6, 8) for r in PLAIN_SNAP_ROUNDINGS))


def probe_scenes(seed: int = 0, count: int = 36) -> list[Scene]:
    """``count`` one-triangle scenes in each orientation (lattice, whole-pixel, random
    float vertices in turn), clockwise ones first."""
    rng = np.random.default_rng(seed)
    triangles: list[NDArray[np.float64]] = []
    while len(triangles) < count:
        k = len(triangles) % 3
        if k == 0:
            p = rng.integers(0, 4 * 12, size=(3, 2)) / 4.0 + 1.0
        elif k == 1:
            p = rng.integers(0, 12, size=(3, 2)).astype(np.float64) + 1.0
        else:
            p = rng.uniform(1.0, 13.0, size=(3, 2))
        if orientation(p[None])[0] != 0:
            triangles.append(p if orientation(p[None])[0] > 0 else p[::-1].copy())
    return [Scene(SIZE, SIZE, p[None]) for p in triangles] + [Scene(SIZE, SIZE, p[None, ::-1].copy()) for p in triangles]


def simplest_dyadic(low: float, high: float) -> float | None:
    """The dyadic number with the fewest fraction bits in ``(low, high]`` (None when the
    interval is empty or holds none with at most 30 bits).

    >>> simplest_dyadic(0.49, 0.5), simplest_dyadic(0.0, 2.0**-17), simplest_dyadic(0.5, 0.5)
    (0.5, 7.62939453125e-06, None)
    """
    if not low < high:
        return None
    for bits in range(31):
        scale = 2.0**bits
        k = math.floor(high * scale)  # the largest multiple of 2**-bits at most high
        if k / scale > low and k > 0:
            return float(k / scale)
    return None


def _drawn(answer: Coverage) -> NDArray[np.bool_]:
    return np.asarray(answer.counts(SIZE, SIZE) > 0)


def best_threshold(areas: NDArray[np.float64], drawn: NDArray[np.bool_]) -> float | None:
    """The simplest dyadic threshold t that misclassifies the fewest (area, drawn) pairs
    (drawn with area < t, or undrawn with area >= t): the pairs swept in order of area, t
    then the simplest dyadic number between the best split's neighbours.

    >>> best_threshold(np.array([0.25, 0.49, 0.5, 0.75]), np.array([False, False, True, True]))
    0.5
    >>> best_threshold(np.array([0.25, 0.49, 0.5, 0.75]), np.array([False, True, False, True]))  # one off: the first best
    0.375
    """
    if not areas.size:
        return None
    order = np.argsort(areas, kind="stable")
    a, d = areas[order], drawn[order]
    values, first = np.unique(a, return_index=True)
    # t just above values[k - 1] and at most values[k]: undrawn at or above, drawn below
    undrawn_at_or_above = np.concatenate([np.cumsum((~d)[::-1])[::-1], [0]])[np.append(first, a.size)]
    drawn_below = np.concatenate([[0], np.cumsum(d)])[np.append(first, a.size)]
    errors = undrawn_at_or_above + drawn_below
    k = int(np.argmin(errors))
    low = 0.0 if k == 0 else float(values[k - 1])
    high = 1.0 if k == values.size else float(values[k])
    # the areas are float (within 2**-24 of the exact ones): a threshold the exact areas meet may lie just above
    return simplest_dyadic(low, min(high + _AREA_SLACK, 1.0))


# the closed rule's scan conversions tried on 26.6 input (FreeType's monochrome rasterizer): no dropout
# control, simple and smart, stubs included or excluded, crossings exact or stepped as ftraster.c steps them
CLOSED_SCANS: tuple[Dropout, ...] = tuple(
    dropout_control(f"{mode}{stubs}{step}") for step in ("-stepped6", "") for mode, stubs in
    (("none", ""), ("simple", ""), ("simple", "-no-stubs"), ("smart", ""), ("smart", "-no-stubs")))


def closed_candidates() -> list[Convention]:
    """The closed rule on 26.6 input with each scan conversion of :data:`CLOSED_SCANS`."""
    return [Convention(coverage="closed", input="fixed6", dropout=d.name) for d in CLOSED_SCANS]


def rule_candidates(scenes: Sequence[Scene], answers: Sequence[Coverage]) -> list[Convention]:
    """Every rule at every snapping of :data:`SNAPPINGS`, the threshold read from the
    answers (module docstring: the best split of the areas drawn and left undrawn); then
    the closed rule's scan conversions (:func:`closed_candidates`)."""
    out = []
    for bits, rounding in SNAPPINGS:
        base = Convention(subpixel_bits=bits, snap_rounding=rounding)  # type: ignore[arg-type]
        areas, drawn = [], []
        for scene, answer in zip(scenes, answers):
            _, x, y, area = pixel_areas(base.snap(scene.positions), SIZE, SIZE)
            areas.append(area)
            drawn.append(_drawn(answer)[y, x])
        t = best_threshold(np.concatenate(areas), np.concatenate(drawn)) if areas else None
        for name, model in COVERAGE_RULES.items():
            if model.input_bits is not None:
                continue  # on their own grid, below
            if name == "area-threshold":
                if t is not None and 2.0**-20 <= t < 1.0:  # a threshold of 1 is conservative-under
                    out.append(Convention(coverage="area-threshold", threshold=t, subpixel_bits=bits,
                                         snap_rounding=rounding))  # type: ignore[arg-type]
            else:
                out.append(Convention(coverage=name, subpixel_bits=bits, snap_rounding=rounding))  # type: ignore[arg-type]
    return out + library_candidates(scenes, answers) + closed_candidates()


def library_candidates(scenes: Sequence[Scene], answers: Sequence[Coverage]) -> list[Convention]:
    """The rules defined on a library's integer grid (``input_bits``), under each input
    rounding; ``agg-cover``'s threshold the best split of AGG's covers of the probe pixels
    (as a share of 256; none when the covers draw no pixel)."""
    from harness.oracle.library_rules import agg_covers

    out = []
    for name, model in COVERAGE_RULES.items():
        if model.input_bits is None:
            continue
        for rounding in INPUT_ROUNDINGS:
            received = f"integer-{rounding}" if model.input_bits == 0 else f"fixed{model.input_bits}-{rounding}"
            if model is not AGG_COVER:
                out.append(Convention(coverage=name, input=received))  # type: ignore[arg-type]
                continue
            base = Convention(coverage=name, input=received)  # type: ignore[arg-type]
            covers, drawn = [], []
            for scene, answer in zip(scenes, answers):
                positions = base.snap(scene.positions)
                if not np.all(np.isfinite(positions)):
                    continue
                covers.append(agg_covers(positions[0], SIZE, SIZE).ravel() / 256.0)
                drawn.append(_drawn(answer).ravel())
            t = best_threshold(np.concatenate(covers), np.concatenate(drawn)) if covers else None
            if t is not None:
                out.append(Convention(coverage=name, input=received, threshold=max(t, 2.0**-8)))  # type: ignore[arg-type]
    return out


def _residual(convention: Convention, scenes: Sequence[Scene], answers: Sequence[Coverage]) -> tuple[int, int]:
    """(pixels off, pixels drawn by either) over the scenes."""
    off = pixels = 0
    for scene, answer in zip(scenes, answers):
        got, want = _drawn(answer), _drawn(exact_coverage(scene, convention))
        off += int((got != want).sum())
        pixels += int((got | want).sum())
    return off, pixels


@dataclass(frozen=True)
class RuleFit:
    """What the rule probes found: the best convention, its residual over ``pixels``
    pixels, the runner-up (convention, residual), the other conventions as good as the
    best (the probes cannot tell them apart), and the fit on each orientation alone
    ("cw", "ccw": convention and residual) when it differs from the whole's."""

    convention: Convention
    residual: int
    pixels: int
    runner_up: tuple[Convention, int] | None
    ambiguous: tuple[Convention, ...] = ()
    by_orientation: dict[str, tuple[Convention, int]] = field(default_factory=dict)

    @property
    def exact(self) -> bool:
        return self.residual == 0

    def describe(self) -> str:
        said = (f"{'exact' if self.exact else 'best guess'}: {self.convention.describe()}, {self.residual} of "
                f"{self.pixels} pixels off")
        if self.runner_up is not None:
            said += f"; runner-up {self.runner_up[0].describe()}, {self.runner_up[1]} off"
        for side, (convention, residual) in self.by_orientation.items():
            said += f"; {side} triangles alone: {convention.describe()}, {residual} off"
        return said


def _rank(scenes: Sequence[Scene], answers: Sequence[Coverage]) -> list[tuple[int, int, Convention]]:
    scored = []
    for convention in rule_candidates(scenes, answers):
        off, pixels = _residual(convention, scenes, answers)
        scored.append((off, pixels, convention))
    # fewest pixels off; then the simplest threshold; then no snapping before snapping, fewer bits first
    # (the candidates' order)
    return sorted(scored, key=lambda s: (s[0], Fraction(s[2].threshold).denominator if s[2].coverage_uses_threshold else 1))


def fit_rule(rasterize: Callable[[Scene], Any], seed: int = 0) -> RuleFit:
    """The coverage rule ``rasterize`` (a rasterizer's ``rasterize``) follows on
    :func:`probe_scenes`, read as the module docstring says."""
    scenes = probe_scenes(seed)
    answers = [rasterize(scene) for scene in scenes]
    ranked = _rank(scenes, answers)
    # told apart on screen first; off screen (where libraries clip) only what is still tied
    ranked = _separate(rasterize, _separate(rasterize, ranked), offscreen=True)
    best_off, pixels, best = ranked[0]
    ambiguous = tuple(c for off, _, c in ranked[1:] if off == best_off and c.coverage != best.coverage)
    runner = next(((c, off) for off, _, c in ranked[1:] if c.coverage != best.coverage), None)
    sides: dict[str, tuple[Convention, int]] = {}
    if best_off:
        half = len(scenes) // 2
        for side, part in (("cw", slice(0, half)), ("ccw", slice(half, None))):
            off, _, convention = _rank(scenes[part], answers[part])[0]
            sides[side] = (convention, off)
    return RuleFit(best, best_off, pixels, runner, ambiguous, sides)


def separating_scenes(candidates: Sequence[Convention], seed: int = 0, count: int = 12, tries: int = 600,
                      offscreen: bool = False) -> list[Scene]:
    """Up to ``count`` one-triangle scenes on which ``candidates`` (conventions the probes
    could not tell apart) do not all agree: vertices exactly halfway between points of the
    finest input grid among them (1/512 px when none has one: where nearest-even and
    half-away disagree, where an area just over a threshold is rounded under it), on
    screen, or also left of and above it when ``offscreen`` (where floor and toward-zero
    disagree; where a library clips), drawn at random and kept when two candidates' exact
    answers differ (``tries`` drawn at most)."""
    rng = np.random.default_rng(seed)
    bits = max((c.input_precision.bits for c in candidates if c.input_precision.kind in ("fixed", "integer")), default=8)
    scale = 2.0**bits
    scenes: list[Scene] = []
    for _ in range(tries):
        if len(scenes) >= count:
            break
        p = np.asarray((rng.integers(int((-3 if offscreen else 1) * scale), int(13 * scale), size=(3, 2)) + 0.5) / scale,
                       dtype=np.float64)
        if orientation(p[None])[0] == 0:
            continue
        scene = Scene(SIZE, SIZE, p[None])
        drawn = [_drawn(exact_coverage(scene, c)) for c in candidates]
        if any(not np.array_equal(drawn[0], d) for d in drawn[1:]):
            scenes.append(scene)
    return scenes


def _separate(rasterize: Callable[[Scene], Any], ranked: list[tuple[int, int, Convention]],
              offscreen: bool = False) -> list[tuple[int, int, Convention]]:
    """The ranking with the candidates tied for best (the probes cannot tell them apart: a
    rule read from a library's source and a threshold, or input roundings) told apart on
    :func:`separating_scenes` (``offscreen`` or not): their pixels off there added to their residual, re-sorted
    (stable: the probes' order on a tie), their pixels drawn there added to their pixels."""
    best_off = ranked[0][0]
    tied = [c for off, _, c in ranked if off == best_off]
    if len(tied) < 2 or not any(c.model.input_bits is not None for c in tied):
        return ranked
    scenes = separating_scenes(tied, offscreen=offscreen)
    if not scenes:
        return ranked
    answers = [rasterize(scene) for scene in scenes]
    extra = {id(c): _residual(c, scenes, answers) for c in tied}
    rescored = [(off + extra[id(c)][0], pixels + extra[id(c)][1], c) if id(c) in extra else (off, pixels, c)
                for off, pixels, c in ranked]
    rescored.sort(key=lambda s: s[0])
    return rescored


@dataclass(frozen=True)
class RuleFact:
    """identify's coverage-rule probe: the best coverage rule on the rule probes
    (``fit``), and the convention chosen between it and the sample-point convention
    ``before`` by their mismatches on every scene drawn (``drawn``: the sample fits' and
    the rule probes'): the rule only when strictly fewer."""

    fit: RuleFit
    before: Convention
    before_mismatches: int
    rule_mismatches: int
    drawn: tuple[Drawn, ...] = field(repr=False)

    @property
    def chosen(self) -> bool:
        """Whether the rule replaced the sample-point convention."""
        return self.rule_mismatches < self.before_mismatches

    @property
    def convention(self) -> Convention:
        return self.fit.convention if self.chosen else self.before

    @property
    def mismatches(self) -> int:
        return min(self.rule_mismatches, self.before_mismatches)

    @property
    def text(self) -> str:
        verdict = ("explains it better than any sample point" if self.chosen
                   else "explains it no better than the sample point")
        return (f"{self.fit.convention.describe()}: {self.rule_mismatches} pixels off on every fit scene against "
                f"{self.before_mismatches} for the sample point; {verdict}")


def _answered_coverage(drawn: Drawn) -> Coverage:
    return Coverage.empty() if drawn.coverage is None else drawn.coverage


def fit_rule_beside(call: Call, seed: int, before: Convention, drawn_before: Sequence[Drawn]) -> RuleFact:
    """:func:`fit_rule` through a :data:`~harness.engine.isolation.Call`, scored beside the
    sample-point convention ``before`` on the scenes ``drawn_before`` and the rule probes
    (an unanswered probe scene says nothing of any rule: left out)."""
    probes = [draw(call, scene) for scene in probe_scenes(seed)]
    answered = [d for d in probes if d.coverage is not None]
    if not answered:
        fit = RuleFit(before, 0, 0, None)
        return RuleFact(fit, before, 0, 0, tuple(probes))
    separating: list[Drawn] = []

    def rasterize(scene: Scene) -> Coverage:
        separating.append(draw(call, scene))
        return _answered_coverage(separating[-1])

    ranked = _rank([d.scene for d in answered], [_answered_coverage(d) for d in answered])
    # told apart on screen first; off screen (where libraries clip) only what is still tied (as fit_rule does)
    ranked = _separate(rasterize, _separate(rasterize, ranked), offscreen=True)
    best_off, pixels, best = ranked[0]
    runner = next(((c, off) for off, _, c in ranked[1:] if c.coverage != best.coverage), None)
    fit = RuleFit(best, best_off, pixels, runner)
    everything = [*drawn_before, *probes, *separating]
    # the probes are small: the snapping (and threshold) of the best rule is chosen again on every scene
    # drawn, among the candidates of its rule (in the probes' order on a tie)
    scored = [(sum(d.mismatches(c) for d in everything), k, c)
              for k, (_, _, c) in enumerate(ranked) if c.model is best.model]
    rule_off, _, chosen = min(scored, key=lambda s: (s[0], s[1]))
    # others of its rule as good on every scene drawn, that see some scene otherwise: not told apart
    ambiguous = tuple(c for off, _, c in scored if off == rule_off and c is not chosen and (
        c.threshold != chosen.threshold or c.model is not chosen.model
        or any(not np.array_equal(c.snap(d.scene.positions), chosen.snap(d.scene.positions), equal_nan=True)
               for d in everything)))
    if chosen is not best or ambiguous:
        fit = RuleFit(chosen, sum(d.mismatches(chosen) for d in answered), pixels, runner, ambiguous)
    return RuleFact(fit, before, sum(d.mismatches(before) for d in everything), rule_off, tuple(everything))


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m harness.identify.rule_probes module:Class``: the fit, in one line."""
    from harness.engine.registry import load

    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1:
        print("usage: python -m harness.identify.rule_probes module:Class", file=sys.stderr)
        return 2
    rasterizer = load(args[0])
    print(f"{rasterizer.name}: {fit_rule(rasterizer.rasterize).describe()}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
