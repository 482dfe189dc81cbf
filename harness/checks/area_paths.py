"""accuracy on path scenes: every (path, pixel) alpha within the declared tolerance of the
exact area where the fill rule holds (:mod:`harness.oracle.path_area`), or of the share of
the pattern's samples inside (a supersampled convention: exact), on the declared levels.

The float oracle is within its proven per-pixel bound of the exact area; where that bound
(and the roundings of the level's value and of the difference) leaves a verdict open, the
rational reference (:func:`harness.oracle.path_area.exact_path_area`) decides: no epsilon
decides. :func:`harness.checks.area.accuracy` hands path scenes here.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np

from harness.checks.area import _aligned, _keyed, _model_words, exact_alpha, exact_tolerance, level_values, off_level
from harness.checks.records import EVIDENCE_LIMIT, Result, result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.kinds import PATHS
from harness.oracle.path_area import exact_path_area, path_pixel_areas

__all__ = ["path_accuracy"]

# the roundings of a level's value and of the difference, per unit of magnitude (as area.py's)
_DIFFERENCE_ROUNDING = 4.0 * 2.0**-53


def path_accuracy(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention) -> Result:
    """|alpha - model| per (path, pixel) against the declared tolerance (a pixel either side
    leaves out has alpha 0); alphas off the declared levels fail too.

    Metrics: ``max_error``, ``mean_error``, ``over_tolerance``, ``pixels``, ``off_level``,
    ``exact_decisions``. Evidence on failure: ``pixels`` (worst first, ``{path, x, y,
    alpha, area, error}``) and ``off_level``.
    """
    scene = PATHS.narrow(case.scene)
    width, height, n = scene.width, scene.height, len(scene)
    keys, alpha, model = _aligned(*_keyed(coverage, width, height, n), *_keyed(oracle, width, height, n))
    present = (alpha != 0) | (model != 0)
    keys, alpha, model = keys[present], alpha[present], model[present]
    levels = convention.levels
    with np.errstate(invalid="ignore"):
        error = np.abs(level_values(alpha, levels) - model)
    error[np.isnan(error)] = np.inf
    limit = exact_tolerance(convention)
    bound = float(limit)
    path = keys // (width * height)
    x, y = keys % width, keys // width % height
    finite = np.isfinite(alpha)
    magnitude = np.maximum(1.0, np.abs(np.where(finite, alpha, 0.0)))
    oracle_bound = np.zeros(keys.size)
    analytic = convention.samples is None
    if analytic:  # the float area's proven bound per pixel (a supersampled share is exact)
        p, px, py, _, b = path_pixel_areas(scene, convention)
        where = np.searchsorted(keys, (p * height + py) * width + px)
        inside = where < keys.size
        inside[inside] = keys[where[inside]] == ((p * height + py) * width + px)[inside]
        oracle_bound[where[inside]] = b[inside]
        oracle_bound[model == 0] = np.maximum(oracle_bound[model == 0], float(b.max(initial=2.0**-53)))
    margin = oracle_bound + _DIFFERENCE_ROUNDING * magnitude + _DIFFERENCE_ROUNDING * max(1.0, bound)
    over = (error - margin > bound) | ~finite
    open_ = np.flatnonzero(~over & (error + margin > bound))
    snapped = convention.snap(scene.vertices)
    contours: dict[int, list[Any]] = {}
    for i in open_:
        if analytic:
            k = int(path[i])
            if k not in contours:
                ends = np.cumsum(scene.contour_sizes)
                contours[k] = [snapped[ends[c] - scene.contour_sizes[c]:ends[c]] for c in np.flatnonzero(scene.contour_path == k)]
            exact = exact_path_area(contours[k], scene.fill_rule, int(x[i]), int(y[i]))
        else:
            exact = Fraction(float(model[i]))  # k / n: exact as a float
        over[i] = abs(exact_alpha(float(alpha[i]), levels) - exact) > limit
    off = off_level(alpha, levels)
    count, n_off = int(over.sum()), int(off.sum())
    worst = float(error.max(initial=0.0))
    metrics = {"max_error": worst, "mean_error": float(error.mean()) if error.size else 0.0,
               "over_tolerance": float(count), "near_tie": 0.0, "near_tie_error": 0.0, "pixels": float(keys.size),
               "off_level": float(n_off), "exact_decisions": float(open_.size)}
    ok = not count and not n_off
    step = convention.level_step
    what = _model_words(convention)
    evidence: dict[str, Any] = {}
    if not ok:
        order = np.lexsort((-error, ~over))[:EVIDENCE_LIMIT]
        evidence["pixels"] = [{"path": int(path[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                               "area": float(model[i]), "error": float(error[i]), "over": bool(over[i])} for i in order]
        evidence["model"] = what
        evidence["tolerance"] = bound
        if n_off:
            evidence["off_level"] = [{"path": int(path[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                                      "level": float(alpha[i] * (levels - 1))} for i in np.flatnonzero(off)[:EVIDENCE_LIMIT]]
    if ok:
        message = (f"within {bound:.3g} of {what} at all {keys.size} pixels of the paths (largest error {worst:.3g}, "
                   f"{worst / step:.2f} levels)")
    else:
        parts = []
        if count:
            parts.append(f"{count} of {keys.size} pixels of the paths beyond {bound:.3g} of {what} "
                         f"(largest error {worst:.3g}, {worst / step:.1f} levels)")
        if n_off:
            parts.append(f"{n_off} alphas on none of the {levels} declared levels")
        message = "; ".join(parts)
    return result(case.id, "accuracy", ok, message, metrics, evidence)
