"""popping: area coverage under sub-pixel motion -- no alpha changes beyond what the
declared tolerance allows; pops against the exact area reported. The shared parts of the
area checks are :mod:`harness.checks.area`'s."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.area import (
    _DIFFERENCE_ROUNDING,
    DISPLAY_LEVELS,
    scene_exact_model,
    scene_model_bound,
)
from harness.checks.area_levels import (
    AREA_COVERAGE_KINDS,
    _fragments,
    _model_words,
    exact_alpha,
    exact_tolerance,
    level_values,
)
from harness.checks.records import (
    EVIDENCE_LIMIT,
    Check,
    Figure,
    Result,
    Subject,
    register,
    result,
)
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.kinds import LINES
from harness.oracle.area import area_coverage
from harness.oracle.area_lines import step_exceeds

# -- popping ----------------------------------------------------------------------------------


def _exact_areas(scenes: list[Scene], convention: Convention) -> list[Coverage]:
    """The exact area (the float oracle) of each frame under ``convention``'s snapping
    and culling, ignoring any sample pattern: what a viewer's eye integrates."""
    analytic = replace(convention, samples=None, coverage="area")
    return [area_coverage(scene, analytic) for scene in scenes]


def _window(parts: list[tuple[NDArray, NDArray, NDArray, NDArray]]) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1): the smallest rectangle holding every fragment of ``parts``."""
    xs = [p[1] for p in parts if p[1].size]
    ys = [p[2] for p in parts if p[2].size]
    if not xs:
        return 0, 0, 1, 1
    return (min(int(a.min()) for a in xs), min(int(a.min()) for a in ys),
            max(int(a.max()) for a in xs) + 1, max(int(a.max()) for a in ys) + 1)


# dense per-frame arrays of (triangles in a chunk) x (window pixels) stay below this many entries
_CHUNK_ENTRIES = 1 << 21


def _pixel_series(parts: dict[str, tuple[list[Any], list[NDArray[np.int64]]]], pixel: int) -> dict[str, list[float]]:
    """Per name, one pixel's value summed over the triangles in each frame: ``parts`` maps
    a name to its fragments per frame (``(triangle, x, y, value)``) and their window-local
    pixel indices per frame."""
    return {name: [float(frame[3][local == pixel].sum()) for frame, local in zip(frames, where)]
            for name, (frames, where) in parts.items()}


def _step_beyond(before: Any, after: Any, convention: Convention, primitive: int, x: int, y: int,
                 shares: tuple[float, float], step_alpha: Any, limit: Any) -> bool:
    """Whether the alpha's step ``step_alpha`` is beyond ``limit`` of the exact model's step
    at one (primitive, pixel), decided exactly (two strokes' exact areas lie in different
    fields: enclosed, :func:`harness.oracle.area_lines.step_exceeds`)."""
    earlier = scene_exact_model(before, convention, primitive, x, y, shares[0])
    later = scene_exact_model(after, convention, primitive, x, y, shares[1])
    if LINES.owns(after):
        return step_exceeds(step_alpha, later, earlier, limit)
    return bool(abs(step_alpha - (later - earlier)) > limit)


def popping(case_id: str, scenes: list[Scene], coverages: list[Coverage], oracles: list[Coverage],
            convention: Convention, areas: list[Coverage] | None = None) -> Result:
    """Per (triangle, pixel) and frame step, the alpha change against the declared
    model's (the oracle of each frame): beyond twice the declared tolerance (what the
    declared accuracy allows at the two frames; :func:`exact_tolerance`, each alpha the
    level it stands for, :func:`exact_alpha`) the alpha jumped on its own -- a failure,
    decided exactly where the oracle's bound leaves it open. Per pixel, the change of the summed
    alpha against the exact area's (``areas``, computed when None) is the popping
    artifact, in 8-bit levels (:data:`DISPLAY_LEVELS`).

    The verdict is per triangle: at a pixel that k triangles share, each may err by the
    tolerance, so their summed alpha may step by up to 2 k times it against the model's
    with every promise kept.

    Metrics: ``alpha_jumps`` ((triangle, pixel, step)s beyond the bound), ``max_step_error``
    (largest |d alpha - d model|), ``max_pop_levels``, ``pops`` (pixel-steps beyond one
    8-bit level), ``frames``, ``exact_decisions``. Evidence: ``series``, the worst pixel's
    per-frame ``alpha``, ``area`` (exact) and ``oracle`` (each summed over triangles;
    ready to plot); ``pixel``, that pixel ``{x, y}``; and (on failure) ``steps``, worst
    first, ``{frame, triangle, x, y, d_alpha, d_oracle}`` (frame: the later frame of the
    step).
    """
    frames = len(scenes)
    width, height, n = scenes[0].width, scenes[0].height, len(scenes[0])
    if areas is None:
        areas = oracles if convention.samples is None else _exact_areas(scenes, convention)
    levels = convention.levels
    # each alpha as the level it stands for (exact_alpha), in float
    got = [(t, x, y, level_values(a, levels)) for t, x, y, a in (_fragments(c, width, height, n) for c in coverages)]
    want = [_fragments(c, width, height, n) for c in oracles]
    true = want if areas is oracles else [_fragments(c, width, height, n) for c in areas]
    x0, y0, x1, y1 = _window(got + want + true)
    span = x1 - x0
    win = span * (y1 - y0)
    # window-local pixel index of every fragment, per frame
    where = {name: [(part[2] - y0) * span + (part[1] - x0) for part in parts] for name, parts in (("got", got), ("want", want))}
    where["true"] = where["want"] if true is want else [(part[2] - y0) * span + (part[1] - x0) for part in true]
    limit = 2 * exact_tolerance(convention)
    tolerance = float(limit)
    unit = 1.0 / DISPLAY_LEVELS
    bounds: dict[int, NDArray] = {}

    def bound(f: int) -> NDArray:
        """:func:`model_bound` of frame ``f`` (computed when a step comes near the limit)."""
        if f not in bounds:
            bounds[f] = scene_model_bound(scenes[f], convention)
        return bounds[f]

    # anti-aliased strokes (harness.oracle.area_lines): their oracle's bound may exceed 2**-24
    oracle_slack = 2.0**-23 if not LINES.owns(scenes[0]) else max(
        2.0**-23, 2 * max(float(bound(f).max(initial=0.0)) for f in range(frames)))

    chunk = max(1, _CHUNK_ENTRIES // max(win, 1))
    whole = chunk >= n  # one chunk: the per-pixel sums come from the per-triangle arrays

    pop_max, pops, pop_at = 0.0, 0, 0
    summed_before: tuple[NDArray, NDArray] | None = None

    def pixel_step(summed: tuple[NDArray, NDArray]) -> None:
        """The summed alpha's step against the exact area's, per pixel."""
        nonlocal pop_max, pops, pop_at, summed_before
        if summed_before is not None:
            with np.errstate(invalid="ignore"):
                # float even when no frame covers anything (empty sums come out integer)
                pop = np.abs((summed[0] - summed_before[0]) - (summed[1] - summed_before[1])).astype(np.float64)
            pop[np.isnan(pop)] = np.inf
            pops += int((pop > unit).sum())
            k = int(np.argmax(pop))
            if pop[k] > pop_max:
                pop_max, pop_at = float(pop[k]), k
        summed_before = summed

    found: list[tuple[float, int, int, int, float, float, float, float]] = []  # |step error|, frame, t, pixel, a0, a1, o0, o1
    jumps, worst_step, open_count = 0, 0.0, 0
    for t0 in range(0, n, chunk):
        t1 = min(n, t0 + chunk)
        size = (t1 - t0) * win
        before: tuple[NDArray, NDArray] | None = None
        for f in range(frames):
            dense = []
            for part, local in ((got[f], where["got"][f]), (want[f], where["want"][f])):
                if whole:
                    dense.append(np.bincount(part[0] * win + local, weights=part[3], minlength=size))
                else:
                    mine = (part[0] >= t0) & (part[0] < t1)
                    dense.append(np.bincount((part[0][mine] - t0) * win + local[mine], weights=part[3][mine], minlength=size))
            now = (dense[0], dense[1])
            if whole:
                alpha_sum = now[0].reshape(n, win).sum(axis=0)
                area_sum = (now[1].reshape(n, win).sum(axis=0) if true is want
                            else np.bincount(where["true"][f], weights=true[f][3], minlength=win))
                pixel_step((alpha_sum, area_sum))
            if before is not None:
                with np.errstate(invalid="ignore"):
                    diff = np.abs((now[0] - before[0]) - (now[1] - before[1])).astype(np.float64)
                diff[np.isnan(diff)] = np.inf
                worst_step = max(worst_step, float(diff.max(initial=0.0)))
                # the exact step error lies within the two frames' oracle bounds (each below
                # 2**-24: harness.oracle.area) and the rounding of the differences of diff: beyond
                # the limit for sure, or open; only the steps near or beyond it are looked at
                with np.errstate(invalid="ignore"):
                    largest = np.nanmax(np.abs(now[0]), initial=0.0) + np.nanmax(np.abs(before[0]), initial=0.0)
                candidates = np.flatnonzero(diff > tolerance - oracle_slack - _DIFFERENCE_ROUNDING * max(1.0, largest))
                if candidates.size:
                    t = t0 + candidates // win
                    a0, a1, o0, o1 = before[0][candidates], now[0][candidates], before[1][candidates], now[1][candidates]
                    finite = np.isfinite(a0) & np.isfinite(a1)
                    magnitude = np.maximum(1.0, np.abs(np.where(finite, a0, 0.0)) + np.abs(np.where(finite, a1, 0.0)))
                    slack = bound(f - 1)[t] + bound(f)[t] + _DIFFERENCE_ROUNDING * (magnitude + max(1.0, tolerance))
                    d = diff[candidates]
                    sure = (d - slack > tolerance) | ~finite  # a NaN or infinite alpha jumps beyond any limit
                    for k in np.flatnonzero(~sure & (d + slack > tolerance)):  # open: the rationals decide
                        open_count += 1
                        p = int(candidates[k]) % win
                        x, y = x0 + p % span, y0 + p // span
                        step_alpha = exact_alpha(float(a1[k]), levels) - exact_alpha(float(a0[k]), levels)
                        sure[k] = _step_beyond(scenes[f - 1], scenes[f], convention, int(t[k]), x, y,
                                               (float(o0[k]), float(o1[k])), step_alpha, limit)
                    hits = np.flatnonzero(sure)
                    jumps += hits.size
                    for k in hits[np.argsort(-d[hits], kind="stable")][:EVIDENCE_LIMIT]:
                        found.append((float(d[k]), f, int(t[k]), int(candidates[k]) % win,
                                      float(a0[k]), float(a1[k]), float(o0[k]), float(o1[k])))
            before = now
    if not whole:
        for f in range(frames):
            pixel_step((np.bincount(where["got"][f], weights=got[f][3], minlength=win),
                        np.bincount(where["true"][f], weights=true[f][3], minlength=win)))
    found.sort(key=lambda item: (-item[0], item[1], item[2], item[3]))  # worst first; ties by frame, triangle, pixel
    found = found[:EVIDENCE_LIMIT]

    # the worst pixel's series: the worst failing step's pixel, else the deepest pop's
    focus = found[0][3] if found else pop_at
    series = _pixel_series({"alpha": (got, where["got"]), "area": (true, where["true"]), "oracle": (want, where["want"])},
                           focus)
    metrics = {"alpha_jumps": float(jumps), "max_step_error": worst_step, "max_pop_levels": pop_max / unit,
               "pops": float(pops), "frames": float(frames), "exact_decisions": float(open_count)}
    evidence: dict[str, Any] = {"series": series, "pixel": {"x": int(x0 + focus % span), "y": int(y0 + focus // span)}}
    if found:
        evidence["steps"] = [{"frame": f, "triangle": t, "x": int(x0 + p % span), "y": int(y0 + p // span),
                              "d_alpha": a1 - a0, "d_oracle": o1 - o0} for _, f, t, p, a0, a1, o0, o1 in found]
    what = _model_words(convention)
    artifact = (f"against the exact area the summed alpha pops by up to {pop_max / unit:.1f} 8-bit levels in a step "
                f"({pops} pixel-steps beyond one level)")
    if not jumps:
        message = f"every alpha change within {tolerance:.3g} of {what}'s; {artifact}"
    else:
        message = (f"{jumps} alpha changes beyond {tolerance:.3g} (twice the tolerance) of {what}'s, by up to "
                   f"{worst_step:.3g}; {artifact}")
    return result(case_id, "popping", not jumps, message, metrics, evidence)




def _popping(s: Subject) -> Result:
    assert s.convention is not None
    return popping(s.case.id, list(s.case.frames), s.coverages, s.oracles, s.convention)


register(Check(
    "popping", _popping, lambda case: hasattr(case, "frames"), needs_convention=True, coverage_kinds=AREA_COVERAGE_KINDS,
    per_sample=False, metrics={"alpha_jumps": (1.0, 0.0)},
    caption="area coverage under sub-pixel motion: no alpha changes beyond what the declared tolerance allows; "
            "pops against the exact area reported",
    classifier="harness.diagnose.signatures:classify_popping", cause_role="own", motion_role="through-frames",
    figures=(Figure("max_pop_levels", "max", "largest pop against the exact area (in 1/255 levels)"),
             Figure("pops", "sum", "pops of more than 1/255 (pixel-steps)"),
             Figure("alpha_jumps", "sum", "alpha jumps beyond the declared tolerance")),
))
