"""Comparing rasterizers: pixel differences on the same scenes, and the convention that
separates them.

Each rasterizer is explained by the fit identify makes (:func:`harness.identify.triangle_probes.fit_ties`:
the 9 usual sample points and the measured one, x the 8 tie rules, on lattice scenes,
tie triangles and piglit's pinwheels, built to hit ties), so that compare and identify
never disagree on a rasterizer's sample point and tie rule; the best candidate explains
it (exactly when it has no mismatch). Every pair is then compared pixel for pixel on the
lattice conformance cases, and two rasterizers agree up to a half- or whole-pixel shift
of the sample point and a mirrored tie rule when their explanations differ only there.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

import numpy as np

from cases.suites import conformance_cases
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import Scene
from harness.engine.isolation import Call, InProcess, TimeLimit, Worker
from harness.identify.triangle_probes import CANDIDATES, fit_ties
from harness.kinds import TRIANGLES

__all__ = ["CANDIDATES", "Explanation", "Comparison", "explain", "compare", "as_dict"]


@dataclass(frozen=True)
class Explanation:
    """The candidate convention that best explains a rasterizer, its mismatches over the
    ``pixels`` it drew on the fit's scenes, and the runner-up (another sample point or tie
    rule) with its mismatches."""

    rasterizer: str
    convention: Convention
    mismatches: int
    pixels: int
    runner_up: tuple[Convention, int] | None = None
    candidates: int = 0
    scenes: int = 0
    unanswered: int = 0
    silence: str = ""

    @property
    def answered(self) -> bool:
        """Whether any fit scene was answered: one that none was has no explanation (its
        convention is the first candidate, chosen by nothing) and is never ranked."""
        return self.unanswered < self.scenes or not self.scenes

    @property
    def exact(self) -> bool:
        """No mismatch on the fit's scenes, every one of them answered."""
        return self.mismatches == 0 and not self.unanswered


@dataclass
class Comparison:
    """Two rasterizers on the same lattice cases: pixels whose hit count differs (per case
    id), of the first one's pixels, and what separates their explanations."""

    a: str
    b: str
    differing_pixels: int
    total_pixels: int
    per_case: dict[str, int] = field(default_factory=dict)
    separation: str = ""
    # where they first differ, for the page's crops (references, not drawn here): the
    # scene, each side's coverage, and the pixels (x, y) that differ there
    where: tuple[Scene, Coverage, Coverage, list[tuple[int, int]]] | None = field(default=None, compare=False, repr=False)


def _cases(seed: int) -> list[Case]:
    return [c for c in conformance_cases(seed) if c.lattice]


def explain(rasterizer: Rasterizer, seed: int = 0, call: Call | None = None) -> Explanation:
    """The fit identify makes of ``rasterizer`` (called through ``call``; in this process
    when None), as an explanation."""
    fit = fit_ties(InProcess(rasterizer) if call is None else call, seed)
    errors = [d.error for d in fit.drawn if d.coverage is None]
    silence = ""
    if errors:
        from harness.engine.isolation import describe

        silence = (f"every one of its {len(fit.drawn)} fit calls failed" if len(errors) == len(fit.drawn)
                   else f"{len(errors)} of its {len(fit.drawn)} fit calls failed") + f", first: {describe(errors[0])}"
    return Explanation(rasterizer.name, fit.best, fit.mismatches, fit.pixels, (fit.runner_up, fit.runner_up_mismatches),
                       fit.candidates, len(fit.drawn), len(errors), silence[:300])


def _snapping(c: Convention) -> str:
    return "none" if c.subpixel_bits is None else f"{c.subpixel_bits} bits {c.snap_rounding}"


def _separation(a: Explanation, b: Explanation) -> str:
    """What tells the two explanations apart, in words."""
    ca, cb = a.convention, b.convention
    if not (a.exact and b.exact):
        inexact = [e for e in (a, b) if not e.exact]
        who = "either" if len(inexact) == 2 else inexact[0].rasterizer
        if ca == cb:
            return (f"no candidate convention explains {who} exactly; both are best explained by {ca.describe()}, "
                    + ("neither exactly" if len(inexact) == 2 else f"{who} with {inexact[0].mismatches} mismatches"))
        return (f"no candidate convention explains {'both' if len(inexact) == 2 else who} exactly; "
                f"best guesses differ: {ca.describe()} vs {cb.describe()}")
    if ca == cb:
        return "the same convention: they agree pixel for pixel wherever both are exact"
    parts = []
    if ca.sample != cb.sample:
        dx, dy = (cb.sample[0] - ca.sample[0], cb.sample[1] - ca.sample[1])
        steps = {abs(dx), abs(dy)}
        kind = "half-pixel" if steps <= {0.0, 0.5} else "whole-pixel" if steps <= {0.0, 1.0} else "sub-pixel"
        parts.append(f"a {kind} shift of the sample point by ({dx:+g}, {dy:+g})")
    if ca.tie != cb.tie:
        (ax, ay, a_first), (bx, by, b_first) = ca.tie_perturbation, cb.tie_perturbation
        kind = ("a mirrored" if (ax, ay, a_first) == (-bx, -by, b_first)
                else "an x-first vs y-first" if (ax, ay) == (bx, by) else "a different")
        parts.append(f"{kind} tie rule ({ca.tie} vs {cb.tie})")
    if (ca.subpixel_bits, ca.snap_rounding) != (cb.subpixel_bits, cb.snap_rounding):
        parts.append(f"snapping ({_snapping(ca)} vs {_snapping(cb)})")
    if ca.cull != cb.cull:
        parts.append(f"culling ({ca.cull} vs {cb.cull})")
    if ca.input != cb.input:
        parts.append(f"input precision ({ca.input} vs {cb.input})")
    return "separated by " + " and ".join(parts)


def compare(rasterizers: list[Rasterizer], seed: int = 0, isolate: bool = True,
            timeout: float | TimeLimit = 60.0) -> tuple[list[Explanation], list[Comparison]]:
    """Explain each rasterizer as identify does and compare every pair on the same lattice
    cases (a case a rasterizer gives an error for counts as drawing nothing). Each
    rasterizer is called in a worker process of its own (``isolate``), as in a run. One
    that answered none of the fit's scenes (:attr:`Explanation.answered`) is in no pair."""
    cases = _cases(seed)
    coverages: dict[str, dict[str, Coverage]] = {}
    explanations = []
    for r in rasterizers:
        with Worker(r, timeout) if isolate else InProcess(r) as call:
            explanations.append(explain(r, seed, call))
            coverages[r.name] = {c.id: call(c.scene).coverage or Coverage.empty() for c in cases}
    by_name = {e.rasterizer: e for e in explanations}
    comparisons = []
    # a rasterizer that answered no fit scene is compared with nothing: its "pixels" are none it drew
    for ra, rb in combinations([r for r in rasterizers if by_name[r.name].answered], 2):
        per_case = {}
        total = 0
        where = None
        for c in cases:
            a, b = coverages[ra.name][c.id], coverages[rb.name][c.id]
            differs = a.counts(c.scene.width, c.scene.height) != b.counts(c.scene.width, c.scene.height)
            per_case[c.id] = int(differs.sum())
            total += a.n_pixels
            if where is None and per_case[c.id] and TRIANGLES.owns(c.scene):  # the pictured difference: triangles
                ys, xs = np.nonzero(differs)
                where = (c.scene, a, b, [(int(x), int(y)) for x, y in zip(xs[:20], ys[:20])])
        comparisons.append(Comparison(ra.name, rb.name, sum(per_case.values()), total, per_case,
                                      _separation(by_name[ra.name], by_name[rb.name]), where))
    return explanations, comparisons


def as_dict(explanations: list[Explanation], comparisons: list[Comparison]) -> dict[str, Any]:
    """Plain data for JSON and the comparison page."""
    return {
        "explanations": [{"rasterizer": e.rasterizer, "convention": e.convention.describe() if e.answered else None,
                          "mismatches": e.mismatches if e.answered else None, "pixels": e.pixels, "exact": e.exact,
                          "answered": e.answered, "unanswered": e.unanswered, "scenes": e.scenes,
                          **({"no_answers": e.silence} if not e.answered else {})} for e in explanations],
        "comparisons": [{"a": c.a, "b": c.b, "differing_pixels": c.differing_pixels, "total_pixels": c.total_pixels,
                         "per_case": c.per_case, "separation": c.separation} for c in comparisons],
    }
