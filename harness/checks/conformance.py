"""conformance: pixel-exact against the exact oracle; deviations at near ties (float
rounding, by a rigorous bound) excused off the lattice in default mode.

The check is here; the fragment diffing it rests on is :mod:`harness.checks.fragments`, the
near-tie distances per scene kind :mod:`harness.checks.near_ties` (their names are kept
importable from here).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.checks.fragments import FragmentCounter, deviations
from harness.checks.near_ties import edge_distance, line_edge_distance, near_ties, near_ties_of, path_edge_distance
from harness.checks.records import EVIDENCE_LIMIT, Check, Figure, Result, Subject, Tolerance, register, result, skip
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene
from harness.kinds import kind_of

__all__ = ["deviations", "FragmentCounter", "edge_distance", "path_edge_distance", "line_edge_distance", "near_ties",
           "near_ties_of", "undefined_width", "conformance"]


def conformance(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention,
                tolerance: Tolerance = Tolerance()) -> Result:
    """Missing and extra pixels against the exact oracle of the declared convention.

    Deviations are near ties (float rounding: the sample within ``tolerance.near_tie`` of
    an edge, on a non-lattice case) or wrong. Strict mode allows none; default near ties.
    """
    scene = case.scene
    missing, extra = deviations(coverage, oracle, scene.width, scene.height)
    both = np.concatenate([missing, extra], axis=1)
    near, distance = near_ties_of(scene, convention, both, tolerance)
    if case.lattice:
        near[:] = False
    # a conservative rule's uncertainty region: deviations the convention itself allows, in every mode
    uncertain = _uncertain(scene, convention, missing, extra)
    near &= ~uncertain
    wrong = ~near & ~uncertain
    allowed = not (~uncertain).any() if tolerance.mode == "strict" else not wrong.any()
    metrics = {
        "oracle_pixels": float(oracle.n_pixels),
        "missing": float(missing.shape[1]),
        "extra": float(extra.shape[1]),
        "near_tie": float(near.sum()),
        "wrong": float(wrong.sum()),
        "exact_ties": float((distance == 0.0).sum()),
    }
    if uncertain.any():
        metrics["uncertain"] = float(uncertain.sum())
    evidence: dict[str, Any] = {}
    if both.shape[1]:
        kind = np.array(["missing"] * missing.shape[1] + ["extra"] * extra.shape[1])
        order = np.argsort(near, kind="stable")  # wrong ones first
        evidence["pixels"] = [
            {scene.noun: int(both[0, i]), "x": int(both[1, i]), "y": int(both[2, i]), "kind": str(kind[i]),
             "near_tie": bool(near[i]), "distance": float(distance[i])}
            for i in order[:EVIDENCE_LIMIT]
        ]
    if not both.shape[1]:
        message = "pixel-exact"
    else:
        message = (f"{missing.shape[1]} missing, {extra.shape[1]} extra; {int(near.sum())} near ties (float rounding), "
                   f"{int(wrong.sum())} wrong")
        if uncertain.any():
            message += f"; {int(uncertain.sum())} within the rule's uncertainty region ({convention.uncertainty:g} px)"
        ties = int((distance[wrong] == 0.0).sum())
        if ties and ties == int(wrong.sum()):
            # every wrong one a tie: where the rule decides, said in the primitive's words
            # (a missing hole's or a dropped contour's samples lie away from every edge too)
            what, where = kind_of(scene).exact_tie_words
            where = where.format(noun=scene.noun)
            message += f"; all {ties} wrong {what} lie exactly on {where}"
    return result(case.id, "conformance", allowed, message, metrics, evidence)


def _uncertain(scene: AnyScene, convention: Convention, missing: np.ndarray, extra: np.ndarray) -> np.ndarray:
    """(M,) bool over the missing then the extra fragments: those a conservative rule's
    declared uncertainty region allows (an extra one the rule may draw, a missing one it
    need not; :func:`harness.oracle.coverage_rules.uncertainty_bounds`). All False for every
    other convention."""
    out = np.zeros(missing.shape[1] + extra.shape[1], dtype=bool)
    if not convention.model.uncertain or not convention.uncertainty or not out.size:
        return out
    from harness.oracle.coverage_rules import uncertainty_bounds

    must, may = uncertainty_bounds(kind_of(scene).narrow(scene), convention)

    def keys(coverage: Coverage) -> set[tuple[int, int, int]]:
        prim, x, y = coverage.pixels()
        return set(zip(prim.tolist(), x.tolist(), y.tolist()))

    required, allowed = keys(must), keys(may)
    out[:missing.shape[1]] = [(k, x, y) not in required for k, x, y in missing.T.tolist()]
    out[missing.shape[1]:] = [(k, x, y) in allowed for k, x, y in extra.T.tolist()]
    return out


def undefined_width(scene: AnyScene, convention: Convention) -> str:
    """Why the convention defines no answer on ``scene`` ("" when it does): its line rule
    draws width 1 only and the lines are wider (a rasterizer should refuse such a scene,
    raising :class:`harness.contract.scenes.Unsupported`)."""
    return kind_of(scene).undefined(scene, convention)


def _run(s: Subject) -> Result:
    assert s.convention is not None
    why = undefined_width(s.case.scene, s.convention)
    if why:
        return skip(s.case, "conformance", why)
    return conformance(s.case, s.coverage, s.oracle, s.convention, s.tolerance)


register(Check(
    "conformance", _run,
    lambda case: not hasattr(case, "frames"), needs_convention=True, shrinks=True, metrics={"wrong": (1.0, 0.0)},
    caption="pixel-exact against the exact oracle of the convention",
    # root: against the exact oracle, its failure names the scene's cause; the frame verdict of jaggy, texel, perspective
    classifier="harness.diagnose.signatures:classify_conformance", cause_role="root", motion_role="frame",
    figures=(Figure("failing_samples", "sum", "samples failing conformance (summed over cases)"),),
))
