"""hygiene: the answer is well-formed, whatever the convention."""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.checks.records import ALL_COVERAGE_KINDS, EVIDENCE_LIMIT, Check, Result, first, register, result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import SINGLE

__all__ = ["hygiene"]


def hygiene(case: Case, coverage: Coverage, interpolates: bool = True, convention: Convention | None = None) -> Result:
    """Spans inside the viewport and within their triangle's reach, valid triangle ids,
    ``x0 < x1``, no pixel emitted twice by one triangle, one finite attribute row per
    pixel (when the scene has attributes and the rasterizer interpolates; one that
    declares ``interpolates = False`` may return none). Under a multisample convention,
    every span names a sample of the pattern, and a pixel's sample is emitted once per
    triangle; under area coverage, one alpha per pixel, in [0, 1].

    Judged span by span (:meth:`Coverage.tidy`), so a garbage answer costs time in
    proportion to its spans, not to the pixels it claims."""
    scene = case.scene
    _, flaws = coverage.tidy(scene)
    t, y, x0, x1 = coverage.triangle, coverage.y, coverage.x0, coverage.x1
    kinds = ("outside_viewport", "outside_primitive", "bad_primitive_id", "empty_or_reversed", "bad_sample")
    if convention is not None and convention.model.sample_ids and coverage.sample is not None:
        # a sample index of no sample of the declared pattern
        beyond = np.flatnonzero((coverage.sample >= convention.n_samples) & (coverage.sample >= 0))
        flaws["bad_sample"] = np.union1d(flaws["bad_sample"], beyond)
    metrics = {k: float(flaws[k].size) for k in kinds}
    metrics["repeated_pixels"] = float(flaws["repeated_pixels"][0])
    evidence: dict[str, Any] = {k: first(flaws[k]) for k in kinds if flaws[k].size}
    if flaws["repeated"].size:
        shown = flaws["repeated"][:EVIDENCE_LIMIT]
        evidence["repeated_spans"] = np.stack([t[shown], y[shown], x0[shown], x1[shown]], axis=1).tolist()
    kind_problem = _kind_problem(coverage, convention)
    attribute_problem = ""
    if scene.attributes is not None and (interpolates or coverage.attributes is not None):
        if coverage.attributes is None:
            if coverage.n_pixels:  # no pixel needs no row
                attribute_problem = (f"no attribute rows for {coverage.n_pixels} pixels "
                                     f"(the scene has {scene.n_attributes} per vertex)")
        elif coverage.attributes.shape[0] != coverage.n_pixels:
            attribute_problem = f"{coverage.attributes.shape[0]} attribute rows for {coverage.n_pixels} pixels"
        elif coverage.attributes.shape[1] != scene.n_attributes:
            attribute_problem = f"{coverage.attributes.shape[1]} attributes per pixel, the scene has {scene.n_attributes}"
        elif not np.isfinite(coverage.attributes).all() and np.isfinite(scene.attributes).all():
            bad = int((~np.isfinite(coverage.attributes)).any(axis=1).sum())
            attribute_problem = f"{bad} pixels with NaN or infinite attributes, from finite vertex attributes"
    parts = [f"{int(v)} {k.replace('_', ' ').replace('primitive', scene.noun)}" for k, v in metrics.items() if v]
    if kind_problem:
        parts.append(kind_problem)
        evidence["coverage"] = kind_problem
    if attribute_problem:
        parts.append(attribute_problem)
        evidence["attributes"] = attribute_problem
    quiet = "well-formed" if interpolates or scene.attributes is None \
        else "well-formed (interpolates no attributes, as it declares)"
    return result(case.id, "hygiene", not parts, "; ".join(parts) or quiet, metrics, evidence)


def _kind_problem(coverage: Coverage, convention: Convention | None) -> str:
    """What is wrong with the answer's form for the declared coverage kind ("" if nothing)."""
    model = SINGLE if convention is None else convention.model
    if model.sample_ids and coverage.sample is None and len(coverage):
        return "no sample indices, but the convention declares a multisample pattern"
    if model.alphas:
        if coverage.alpha is None:
            return "no alphas, but the convention declares area coverage" if coverage.n_pixels else ""
        if coverage.alpha.shape[0] != coverage.n_pixels:
            return f"{coverage.alpha.shape[0]} alphas for {coverage.n_pixels} pixels"
        bad = int((~((coverage.alpha >= 0.0) & (coverage.alpha <= 1.0))).sum())  # NaN fails both
        if bad:
            return f"{bad} alphas outside [0, 1] or NaN"
    return ""


def _is_static(case: Any) -> bool:
    return not hasattr(case, "frames")


register(Check(
    "hygiene", lambda s: hygiene(s.case, s.received[0], s.interpolates, s.convention), _is_static, shrinks=True,
    coverage_kinds=ALL_COVERAGE_KINDS, per_sample=False,
    caption="spans inside the viewport and their triangle's reach, valid triangle ids, x0 < x1, no pixel twice per triangle, "
            "one finite attribute row per pixel (per sample: valid sample ids; area: one alpha in [0, 1] per pixel)",
    # its own cause, but for pixels drawn outside their primitive: coverage's fault too (its
    # attribute failures, say, are not)
    classifier="harness.diagnose.signatures:classify_hygiene", cause_role="own",
    consequent_classes=frozenset({"outside-primitive"}), motion_role="none", figures=(),
))
