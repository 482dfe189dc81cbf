"""degenerate: zero-area and non-finite triangles draw nothing, no NaN attribute, and the
work stays bounded against plain triangles of the same size; convention-free."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from harness.checks.records import ALL_COVERAGE_KINDS, Check, Result, Subject, Tolerance, first, register, result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.kinds import TRIANGLES

__all__ = ["control_scene", "degenerate", "refusal", "measure_work"]


def control_scene(case: Case) -> Scene:
    """The work yardstick for a degenerate case: each finite triangle replaced by a plain
    right triangle over its bounding box, each side at least one pixel long."""
    scene = TRIANGLES.narrow(case.scene)  # degenerate cases are triangle scenes
    p = scene.positions
    finite = np.all(np.isfinite(p), axis=(1, 2))
    lo = p[finite].min(axis=1)
    hi = np.maximum(p[finite].max(axis=1), lo + 1.0)
    tris = np.stack([lo, np.stack([hi[:, 0], lo[:, 1]], axis=-1), np.stack([lo[:, 0], hi[:, 1]], axis=-1)], axis=1)
    return Scene(case.scene.width, case.scene.height, tris)


def degenerate(case: Case, coverage: Coverage, convention: Convention | None,
               work: tuple[float, float] | None = None, tolerance: Tolerance = Tolerance()) -> Result:
    """Zero-area triangles (after the declared snapping) draw nothing (unless the declared
    coverage rule draws them: ``zero_area``), non-finite ones draw nothing, no
    attribute is NaN, and the work stays bounded: ``work`` is (seconds for the case,
    seconds for :func:`control_scene`), whose ratio may not exceed
    ``tolerance.work_ratio``."""
    scene = case.scene
    scene = TRIANGLES.narrow(scene)  # degenerate cases are triangle scenes
    sign = orientation(convention.snap(scene.positions) if convention is not None else scene.positions)
    nothing = sign == 0  # zero area or non-finite
    if convention is not None and convention.model.zero_area:
        # the rule draws them (closed, inclusive-scanline): only non-finite ones must draw nothing; conformance judges the rest
        nothing &= ~np.isfinite(scene.positions).all(axis=(1, 2))
    tri = coverage.triangle
    valid = (tri >= 0) & (tri < len(scene))
    drew = np.zeros(len(scene), dtype=bool)
    if coverage.alpha is not None and coverage.alpha.shape[0] == coverage.n_pixels:
        # area coverage: a pixel listed with alpha 0 draws nothing
        pixel_tri = coverage.pixels()[0]
        hit = pixel_tri[(coverage.alpha > 0) & (pixel_tri >= 0) & (pixel_tri < len(scene))]
        drew[hit] = True
    else:
        drew[tri[valid][coverage.x1[valid] > coverage.x0[valid]]] = True
    offenders = np.flatnonzero(nothing & drew)
    nan_rows = 0
    if coverage.attributes is not None:
        nan_rows = int(np.isnan(coverage.attributes).any(axis=1).sum())
    metrics = {"degenerate_triangles_drawn": float(offenders.size), "nan_attribute_rows": float(nan_rows)}
    parts = []
    if offenders.size:
        parts.append(f"triangles {first(offenders, 10)} have zero area or non-finite coordinates but drew pixels")
    if nan_rows:
        parts.append(f"{nan_rows} pixels with NaN attributes")
    if work is not None:
        ratio = work[0] / max(work[1], 1e-9)
        metrics["work_ratio"] = ratio
        if ratio > tolerance.work_ratio:
            parts.append(f"took {ratio:.0f}x the time of plain triangles with the same bounding boxes (limit "
                         f"{tolerance.work_ratio:g}x)")
    evidence = {"triangles": first(offenders)} if offenders.size else {}
    return result(case.id, "degenerate", not parts, "; ".join(parts) or "degenerate triangles draw nothing", metrics, evidence)


def refusal(case: Case, error: BaseException) -> Result | None:
    """A ValueError that names a triangle (path) of the case the rasterizer may refuse: a
    non-finite one (a pass, as the contract allows) or a huge one (a skip, with its
    reason). None when the error is not such a refusal."""
    if not isinstance(error, ValueError):
        return None
    text = str(error)
    noun = case.scene.noun  # "triangle" or "path"
    for t in case.non_finite:
        if f"{noun} {t}" in text:
            return Result("", case.id, "degenerate", "pass", f"refused non-finite {noun} {t}: {text}")
    for t in case.refusable:
        if f"{noun} {t}" in text:
            return Result("", case.id, "degenerate", "skip", f"declined huge {noun} {t}: {text}")
    return None


def measure_work(case: Case, call: Callable[[Any], Any], first_seconds: float, repeats: int = 3) -> tuple[float, float] | None:
    """Best-of seconds for the case and for its control scene (None if the control fails)."""
    control = control_scene(case)
    if len(control) == 0:
        return None
    times = [first_seconds]
    control_times = []
    for _ in range(repeats):
        again, plain = call(case.scene), call(control)
        if again.coverage is None or plain.coverage is None:
            return None
        times.append(again.seconds)
        control_times.append(plain.seconds)
    return min(times), min(control_times)


def _timed_scenes(case: Case, repeats: int = 3) -> list[Any]:
    """The scenes :func:`measure_work` hands the rasterizer: the case's and its control
    scene, ``repeats`` times each (none without a control)."""
    control = control_scene(case)
    return [case.scene, control] * repeats if len(control) else []


def _run(s: Subject) -> Result:
    return degenerate(s.case, s.coverage, s.convention, measure_work(s.case, s.call, s.seconds), s.tolerance)


register(Check(
    "degenerate", _run,
    # triangle scenes only: a zero-length or non-finite segment's pixels are the line oracle's (conformance)
    lambda case: getattr(case, "family", "") == "degenerate" and TRIANGLES.owns(getattr(case, "scene", None)),
    # any sample drawn is drawn; times are the whole call's
    # a ratio of times: judged by its own limit, never across runs
    shrinks=True, timings=("work_ratio",), coverage_kinds=ALL_COVERAGE_KINDS, per_sample=False,
    caption="zero-area and non-finite triangles draw nothing, no NaN attribute, bounded work",
    classifier="harness.diagnose.signatures:classify_degenerate", cause_role="consequent", motion_role="none", figures=(),
    plans=lambda case, convention: _timed_scenes(case),
))
