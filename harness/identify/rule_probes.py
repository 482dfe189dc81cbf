"""identify's probes for the coverage rules (issue 33): which of ``area-threshold``,
``conservative-over`` and ``conservative-under`` (and at which snapping and threshold) a
rasterizer's aliased answers follow, measured from outside.

The probes are single triangles in a 16 x 16 viewport: on the quarter-pixel lattice (exact
halves and edges through pixel corners: where the rules and thresholds disagree), on whole
pixels (squares touching edges and corners only) and at random float positions, each in
both orientations (a rasterizer whose rule depends on the winding shows it).

The three rules tell themselves apart on these at once: conservative-over draws every
square an edge touches, under none that an edge crosses, a threshold half of those. The
threshold is read from the answers, not guessed: under snapping s, a threshold rasterizer
draws every pixel covered at least t and no other, so t lies in ``(largest area left
undrawn, smallest area drawn]`` (the areas of the snapped triangles); the simplest dyadic
number in that interval (fewest bits) is the candidate, and the exact oracle then counts
its residual. Snapping candidates: none, and 4, 6 or 8 bits under each rounding.

:func:`fit_rule` gives the best convention, its residual (pixels off over the probes), the
runner-up, and the fit on each orientation alone when they differ
(:class:`RuleFit`). Run on a rasterizer: ``python -m harness.identify.rule_probes
module:Class``.
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

from harness.contract.conventions import PLAIN_SNAP_ROUNDINGS, Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import COVERAGE_RULES
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.oracle.area import pixel_areas
from harness.oracle.coverage import exact_coverage

__all__ = ["RuleFit", "probe_scenes", "rule_candidates", "fit_rule", "simplest_dyadic"]

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


def rule_candidates(scenes: Sequence[Scene], answers: Sequence[Coverage]) -> list[Convention]:
    """Every rule at every snapping of :data:`SNAPPINGS`, the threshold read from the
    answers (module docstring: the best split of the areas drawn and left undrawn)."""
    out = []
    for bits, rounding in SNAPPINGS:
        base = Convention(subpixel_bits=bits, snap_rounding=rounding)  # type: ignore[arg-type]
        areas, drawn = [], []
        for scene, answer in zip(scenes, answers):
            _, x, y, area = pixel_areas(base.snap(scene.positions), SIZE, SIZE)
            areas.append(area)
            drawn.append(_drawn(answer)[y, x])
        t = best_threshold(np.concatenate(areas), np.concatenate(drawn)) if areas else None
        for name in COVERAGE_RULES:
            if name == "area-threshold":
                if t is not None and 2.0**-20 <= t < 1.0:  # a threshold of 1 is conservative-under
                    out.append(Convention(coverage="area-threshold", threshold=t, subpixel_bits=bits,
                                         snap_rounding=rounding))  # type: ignore[arg-type]
            else:
                out.append(Convention(coverage=name, subpixel_bits=bits, snap_rounding=rounding))  # type: ignore[arg-type]
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
