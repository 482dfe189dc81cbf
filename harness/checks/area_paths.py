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
from numpy.typing import NDArray

from harness.checks.area_levels import (
    _aligned,
    _keyed,
    _model_words,
    accuracy_message,
    exact_alpha,
    exact_tolerance,
    level_values,
    off_level,
)
from harness.checks.records import EVIDENCE_LIMIT, Result, Tolerance, result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.kinds import PATHS
from harness.oracle.path_area import exact_path_area, path_pixel_areas
from harness.oracle.row_sampled_paths import exact_row_sampled_path_alpha, row_sampled_path_bound

__all__ = ["path_accuracy", "displaced_path_bound"]

# the roundings of a level's value and of the difference, per unit of magnitude (as area.py's)
_DIFFERENCE_ROUNDING = 4.0 * 2.0**-53


def displaced_path_bound(edges: NDArray[np.int64], reach: NDArray[np.float64]) -> NDArray[np.float64]:
    """How much the area where a path's fill rule holds can change inside a pixel when every
    vertex moves by at most ``reach``: at most ``K (2 sqrt(2) (1 + 2 r) r + pi r**2)`` for
    a path of K edges, and never more than 1.

    Proof. Move the vertices along straight lines; every point of every edge moves by at
    most r. A point's winding number changes only when an edge passes over it, so every
    point whose rule changes lies within r of an edge. Inside the pixel those are the
    points within r of the edges' parts in the pixel grown by r, each no longer than its
    diagonal ``sqrt(2) (1 + 2 r)``: ``2 r L + pi r**2`` per edge.

    >>> float(displaced_path_bound(np.array([4]), np.array([0.0]))[0])
    0.0
    """
    r = np.asarray(reach, dtype=np.float64)
    bound = edges * (2.0 * np.sqrt(2.0) * (1.0 + 2.0 * r) * r + np.pi * r * r) * (1.0 + 2.0**-50)
    return np.asarray(np.minimum(bound, 1.0), dtype=np.float64)


def path_accuracy(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention,
                  tolerance: Tolerance = Tolerance()) -> Result:
    """|alpha - model| per (path, pixel) against the declared tolerance (a pixel either side
    leaves out has alpha 0); alphas off the declared levels fail too.

    A pixel beyond the tolerance that float rounding explains is a near tie, as for
    triangles (:func:`harness.checks.area.accuracy`): with every vertex moved by at most the
    rounding reach (``tolerance.near_tie`` relative to max(1, the path's largest
    |coordinate|), capped at ``tolerance.near_tie_pixels``) the area moves by at most
    :func:`displaced_path_bound`, and the pixel is a near tie when the alpha is within the
    tolerance plus that of the exact area (analytic area only; never on a lattice case).

    Metrics: ``max_error``, ``mean_error``, ``over_tolerance``, ``near_tie``,
    ``near_tie_error``, ``pixels``, ``off_level``, ``exact_decisions``. Evidence on failure
    or with near ties: ``pixels`` (failures, then near ties, worst first, ``{path, x, y,
    alpha, area, error, over, near_tie}``) and ``off_level``.
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
    rows = convention.rows  # a row-sampled model (harness.oracle.row_sampled_paths): its own bound and reference
    analytic = convention.samples is None and not rows and not convention.model.quantum  # a model's own levels are exact too
    snapped = convention.snap(scene.vertices)
    contours: dict[int, list[Any]] = {}

    def contours_of(k: int) -> list[Any]:
        """Path k's contours as the convention snaps them; none for a path with a
        non-finite vertex (which covers nothing)."""
        if k not in contours:
            ends = np.cumsum(scene.contour_sizes)
            rings = [snapped[ends[c] - scene.contour_sizes[c]:ends[c]] for c in np.flatnonzero(scene.contour_path == k)]
            contours[k] = rings if all(np.all(np.isfinite(r)) for r in rings) else []
        return contours[k]

    if rows:
        # the hybrid's alphas are integers over 2 * 256 * rows (one rounding); the plain
        # model's crossings are within row_sampled_path_bound of the exact ones
        per_path = np.full(n, 2.0**-52)
        if not convention.full_rows:
            for k in np.unique(path):
                rings = [c for c in contours_of(int(k)) if c.shape[0] >= 2]
                if rings:
                    edges = np.concatenate([np.concatenate([c, np.roll(c, -1, axis=0)], axis=1) for c in rings])
                    per_path[k] = row_sampled_path_bound(edges, width, height, rows)
        oracle_bound = per_path[path]
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
    for i in open_:
        if analytic:
            exact = exact_path_area(contours_of(int(path[i])), scene.fill_rule, int(x[i]), int(y[i]))
        elif rows:
            exact = exact_row_sampled_path_alpha(contours_of(int(path[i])), scene.fill_rule, int(x[i]), int(y[i]), rows,
                                                 convention.full_rows, surface=(width, height))
        elif convention.model.quantum:  # the model's level k / quantum
            exact = Fraction(int(round(float(model[i]) * convention.model.quantum)), convention.model.quantum)
        else:
            exact = Fraction(float(model[i]))  # k / n: exact as a float
        over[i] = abs(exact_alpha(float(alpha[i]), levels) - exact) > limit
    near = np.zeros(keys.size, dtype=bool)
    if analytic and not case.lattice:
        finite_v = np.all(np.isfinite(snapped), axis=1)
        owner = np.repeat(scene.contour_path, scene.contour_sizes)
        magnitude_p = np.ones(n)
        np.maximum.at(magnitude_p, owner, np.where(finite_v, np.abs(np.where(finite_v[:, None], snapped, 0.0)).max(axis=1), 0.0))
        reach = np.minimum(tolerance.near_tie * magnitude_p, tolerance.near_tie_pixels)
        shift = displaced_path_bound(np.bincount(owner, minlength=n), reach)
        for i in np.flatnonzero(over & finite):
            k = int(path[i])
            if error[i] - margin[i] > bound + float(shift[k]):
                continue
            exact = exact_path_area(contours_of(k), scene.fill_rule, int(x[i]), int(y[i]))
            near[i] = abs(exact_alpha(float(alpha[i]), levels) - exact) <= limit + Fraction(float(shift[k]))
    over &= ~near
    off = off_level(alpha, levels)
    count, n_off, n_near = int(over.sum()), int(off.sum()), int(near.sum())
    plain = error[~near]
    worst = float(plain.max(initial=0.0))
    metrics = {"max_error": worst, "mean_error": float(plain.mean()) if plain.size else 0.0,
               "over_tolerance": float(count), "near_tie": float(n_near), "near_tie_error": float(error[near].max(initial=0.0)),
               "pixels": float(keys.size), "off_level": float(n_off), "exact_decisions": float(open_.size)}
    ok = not count and not n_off and not (n_near and tolerance.mode == "strict")
    step = convention.level_step
    what = _model_words(convention)
    evidence: dict[str, Any] = {}
    if not ok or n_near:
        order = np.lexsort((-error, ~over, ~(over | near)))[:EVIDENCE_LIMIT]
        evidence["pixels"] = [{"path": int(path[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                               "area": float(model[i]), "error": float(error[i]), "over": bool(over[i]),
                               "near_tie": bool(near[i])} for i in order]
        evidence["model"] = what
        evidence["tolerance"] = bound
        if n_off:
            evidence["off_level"] = [{"path": int(path[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                                      "level": float(alpha[i] * (levels - 1))} for i in np.flatnonzero(off)[:EVIDENCE_LIMIT]]
    ties = (f"{n_near} near ties (float rounding: the area within rounding of a level's boundary)" if n_near else "")
    cause = None
    if count and _drawn_under_the_other_rule(scene, coverage, convention, float(bound)):
        other = "even-odd" if scene.fill_rule == "nonzero" else "nonzero"
        cause = f"every alpha within the tolerance of the {other} fill's: the fill rule drawn is not the one asked"
        evidence["alpha_facts"] = {"other_fill_rule": True}
        evidence["alpha_cause"] = "fill-rule"
    message = accuracy_message(total=keys.size, count=count, n_off=n_off, n_near=n_near, ties=ties, bound=bound, what=what,
                               worst=worst, step=step, levels=levels, strict=tolerance.mode == "strict",
                               where=" of the paths", cause=cause)
    return result(case.id, "accuracy", ok, message, metrics, evidence)


def _drawn_under_the_other_rule(scene: Any, coverage: Coverage, convention: Convention, bound: float) -> bool:
    """Whether a failing answer's alphas are all within the tolerance of the model under the
    other fill rule (a diagnosis, not a verdict: the float model within the comparison's
    rounding slack), for a scene where the two rules differ."""
    from harness.oracle.coverage import exact_coverage

    other = scene.with_fill_rule("evenodd" if scene.fill_rule == "nonzero" else "nonzero")
    flipped = exact_coverage(other, convention)
    width, height, n = scene.width, scene.height, len(scene)
    keys, alpha, model = _aligned(*_keyed(coverage, width, height, n), *_keyed(flipped, width, height, n))
    with np.errstate(invalid="ignore"):
        error = np.abs(level_values(alpha, convention.levels) - model)
    return bool(keys.size) and bool(np.all(error <= bound + 2.0**-30))
