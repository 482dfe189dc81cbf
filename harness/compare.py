"""Comparing rasterizers: pixel differences on the same scenes, and the convention that
separates them.

Each rasterizer is matched against the exact oracle of every candidate convention
(sample at the centre, a corner or an edge midpoint; four tie rules) on lattice scenes
with ties on purpose; the candidate with the fewest mismatches explains it (exactly when
the count is 0). Two rasterizers then agree up to a half- or whole-pixel shift of the
sample point and a mirrored tie rule when their explanations differ only there.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

import numpy as np

from harness.case import Case
from cases.suites import conformance_cases
from harness.api import Coverage, Rasterizer
from harness.checks import FragmentCounter
from harness.conventions import TIE_RULES, Convention
from harness.oracle import exact_coverage

__all__ = ["CANDIDATES", "Explanation", "Comparison", "explain", "compare"]

SAMPLES = ((0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 1.0), (1.0, 0.5))
CANDIDATES = tuple(Convention(sample=s, tie=t) for s in SAMPLES for t in TIE_RULES)


@dataclass(frozen=True)
class Explanation:
    """The candidate convention that best explains a rasterizer, and how well."""

    rasterizer: str
    convention: Convention
    mismatches: int
    pixels: int
    runner_up: tuple[Convention, int] | None = None

    @property
    def exact(self) -> bool:
        return self.mismatches == 0


@dataclass
class Comparison:
    a: str
    b: str
    differing_pixels: int
    total_pixels: int
    per_case: dict[str, int] = field(default_factory=dict)
    separation: str = ""


def _cases(seed: int) -> list[Case]:
    return [c for c in conformance_cases(seed) if c.lattice]


def explain(rasterizer: Rasterizer, coverages: dict[str, Coverage], cases: list[Case]) -> Explanation:
    scores = []
    counters = {c.id: FragmentCounter(coverages[c.id], c.scene.width, c.scene.height) for c in cases}
    for candidate in CANDIDATES:
        total = sum(counters[c.id].mismatches(exact_coverage(c.scene, candidate)) for c in cases)
        scores.append((total, candidate))
    scores.sort(key=lambda s: s[0])
    pixels = sum(coverages[c.id].n_pixels for c in cases)
    return Explanation(rasterizer.name, scores[0][1], scores[0][0], pixels, (scores[1][1], scores[1][0]))


def _separation(a: Explanation, b: Explanation) -> str:
    if not (a.exact and b.exact):
        return (f"no candidate convention explains {'both' if not (a.exact or b.exact) else (a.rasterizer if not a.exact else b.rasterizer)} "
                f"exactly; best guesses differ: {a.convention.describe()} vs {b.convention.describe()}")
    ca, cb = a.convention, b.convention
    if ca == cb:
        return "the same convention: they agree pixel for pixel wherever both are exact"
    parts = []
    if ca.sample != cb.sample:
        dx, dy = (cb.sample[0] - ca.sample[0], cb.sample[1] - ca.sample[1])
        kind = "half-pixel" if {abs(dx), abs(dy)} <= {0.0, 0.5} else "whole-pixel" if {abs(dx), abs(dy)} <= {0.0, 1.0} else "sub-pixel"
        parts.append(f"a {kind} shift of the sample point by ({dx:+g}, {dy:+g})")
    if ca.tie != cb.tie:
        (ax, ay, a_first), (bx, by, b_first) = ca.tie_perturbation, cb.tie_perturbation
        kind = ("a mirrored" if (ax, ay, a_first) == (-bx, -by, b_first)
                else "an x-first vs y-first" if (ax, ay) == (bx, by) else "a different")
        parts.append(f"{kind} tie rule ({ca.tie} vs {cb.tie})")
    return "separated by " + " and ".join(parts)


def compare(rasterizers: list[Rasterizer], seed: int = 0) -> tuple[list[Explanation], list[Comparison]]:
    """Explain each rasterizer and compare every pair on the same lattice scenes."""
    cases = _cases(seed)
    coverages = {r.name: {c.id: r.rasterize(c.scene) for c in cases} for r in rasterizers}
    explanations = [explain(r, coverages[r.name], cases) for r in rasterizers]
    by_name = {e.rasterizer: e for e in explanations}
    comparisons = []
    for ra, rb in combinations(rasterizers, 2):
        per_case = {}
        total = 0
        for c in cases:
            a, b = coverages[ra.name][c.id], coverages[rb.name][c.id]
            differing = int(np.sum(a.counts(c.scene.width, c.scene.height) != b.counts(c.scene.width, c.scene.height)))
            per_case[c.id] = differing
            total += a.n_pixels
        comparisons.append(Comparison(ra.name, rb.name, sum(per_case.values()), total, per_case,
                                      _separation(by_name[ra.name], by_name[rb.name])))
    return explanations, comparisons


def as_dict(explanations: list[Explanation], comparisons: list[Comparison]) -> dict[str, Any]:
    return {
        "explanations": [{"rasterizer": e.rasterizer, "convention": e.convention.describe(), "mismatches": e.mismatches,
                          "pixels": e.pixels, "exact": e.exact} for e in explanations],
        "comparisons": [{"a": c.a, "b": c.b, "differing_pixels": c.differing_pixels, "total_pixels": c.total_pixels,
                         "per_case": c.per_case, "separation": c.separation} for c in comparisons],
    }
