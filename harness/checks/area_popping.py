"""popping: area coverage under sub-pixel motion -- no alpha changes beyond what the
declared tolerance allows; pops against the exact area reported. The shared parts of the
area checks are :mod:`harness.checks.area`'s.

Frames may be triangle, line or path scenes (issue 34): a path's model is the area where its
fill rule holds (:mod:`harness.oracle.path_area`, the float oracle within its proven bound
per pixel, the rational reference where that leaves a step open). For paths the check also
counts the steps no motion of that size could make (:func:`path_motion_bound`): whatever the
model, a path whose vertices move by at most r changes its area inside a pixel by at most
the displaced-path bound of the edges within r of that pixel, so an alpha stepping by more
than that plus twice the tolerance jumped on its own -- a pop no declared model excuses.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction
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
    _aligned,
    _fragments,
    _keyed,
    _model_words,
    exact_alpha,
    exact_tolerance,
    level_values,
)
from harness.checks.area_paths import displaced_path_bound
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
from harness.contract.scenes import PathScene, Scene
from harness.kinds import LINES, PATHS
from harness.oracle.area import area_coverage
from harness.oracle.area_lines import step_exceeds
from harness.oracle.path_area import exact_path_area, path_area_coverage, path_pixel_areas
from harness.oracle.row_sampled_paths import exact_row_sampled_path_alpha, row_sampled_path_bound

__all__ = ["popping", "path_motion_bound"]

# -- popping ----------------------------------------------------------------------------------


def _exact_areas(scenes: list[Scene], convention: Convention) -> list[Coverage]:
    """The exact area (the float oracle) of each frame under ``convention``'s snapping
    and culling, ignoring any sample pattern: what a viewer's eye integrates."""
    analytic = replace(convention, samples=None, coverage="area", rows=0, full_rows=False)
    return [path_area_coverage(PATHS.narrow(scene), analytic) if PATHS.owns(scene) else area_coverage(scene, analytic)
            for scene in scenes]


def _model_bound(scene: Any, convention: Convention) -> NDArray:
    """Per primitive, a proven bound on |oracle - model| at every pixel: a path scene's
    the largest of :func:`harness.oracle.path_area.path_pixel_areas`' per-pixel bounds
    (a pixel the float leaves at 0 is within it too), a share of samples' 2**-53; other
    scenes :func:`harness.checks.area.scene_model_bound`."""
    if not PATHS.owns(scene):
        return scene_model_bound(scene, convention)
    paths = PATHS.narrow(scene)
    if convention.samples is not None:
        return np.full(len(paths), 2.0**-53)
    if convention.rows:  # the hybrid's integers over 2 * 256 * rows; the plain model's crossings
        bounds = np.full(len(paths), 2.0**-52)
        if not convention.full_rows:
            vertices = convention.snap(paths.vertices)
            ends = np.cumsum(paths.contour_sizes)
            for k in range(len(paths)):
                rings = [vertices[ends[c] - paths.contour_sizes[c]:ends[c]] for c in np.flatnonzero(paths.contour_path == k)]
                rings = [r for r in rings if r.shape[0] >= 2]
                if rings:
                    edges = np.concatenate([np.concatenate([r, np.roll(r, -1, axis=0)], axis=1) for r in rings])
                    bounds[k] = row_sampled_path_bound(edges, paths.width, paths.height, convention.rows)
        return bounds
    bound = path_pixel_areas(paths, convention)[4]
    return np.full(len(paths), float(bound.max(initial=2.0**-53)))


def _path_contours(scene: PathScene, convention: Convention, path: int) -> list[NDArray]:
    """The path's contours as the convention sees them (snapped)."""
    return [convention.snap(c) for c in scene.contours_of(path)]


def _exact_model(scene: Any, convention: Convention, primitive: int, x: int, y: int, share: float) -> Any:
    """The model at one (primitive, pixel), exactly: a path's exact area where its rule
    holds (0 for a path with a coordinate that is not finite: it draws nothing), or its
    share of samples as count/n; other scenes :func:`harness.checks.area.scene_exact_model`."""
    if not PATHS.owns(scene):
        return scene_exact_model(scene, convention, primitive, x, y, share)
    if convention.samples is not None:
        n = convention.n_samples
        return Fraction(int(round(share * n)), n)
    paths = PATHS.narrow(scene)
    contours = _path_contours(paths, convention, primitive)
    if not all(np.all(np.isfinite(c)) for c in contours):
        return Fraction(0)
    if convention.rows:  # the row-sampled model's reference (cairo's hybrid clips to the viewport)
        return exact_row_sampled_path_alpha(contours, paths.fill_rule, x, y, convention.rows, convention.full_rows,
                                            surface=(paths.width, paths.height))
    return exact_path_area(contours, paths.fill_rule, x, y)


def _edges_near(p: NDArray, q: NDArray, x: int, y: int, reach: float) -> int:
    """How many of the edges ``p -> q`` ((E, 2) each) meet the pixel (x, y) grown by
    ``reach`` on every side (clipped exactly as Liang and Barsky; the box grown further by
    the float rounding of the clip, so the count never falls short)."""
    if not p.size:
        return 0
    slack = reach + 2.0**-40 * max(1.0, float(np.abs(p).max(initial=0.0)), float(np.abs(q).max(initial=0.0)))
    lo, hi = np.array([x - slack, y - slack]), np.array([x + 1 + slack, y + 1 + slack])
    d = q - p
    t0, t1 = np.zeros(p.shape[0]), np.ones(p.shape[0])
    meets = np.ones(p.shape[0], dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis in (0, 1):
            flat = d[:, axis] == 0
            meets &= ~(flat & ((p[:, axis] < lo[axis]) | (p[:, axis] > hi[axis])))
            ta, tb = (lo[axis] - p[:, axis]) / d[:, axis], (hi[axis] - p[:, axis]) / d[:, axis]
            t0 = np.where(flat, t0, np.maximum(t0, np.minimum(ta, tb)))
            t1 = np.where(flat, t1, np.minimum(t1, np.maximum(ta, tb)))
    return int((meets & (t0 <= t1 + 2.0**-40)).sum())


def path_motion_bound(before: PathScene, after: PathScene, convention: Convention, path: int, x: int, y: int) -> float:
    """How much the area where ``path``'s rule holds can change inside pixel (x, y) from
    frame ``before`` to frame ``after``, whatever happens in between, proven: with r the
    largest distance a vertex (snapped as the convention snaps) moves, every point whose
    winding changes lies within r of an edge of ``before`` (:func:`displaced_path_bound`'s
    proof: the vertices moved along straight lines), so only the m edges within r of the
    pixel count: ``displaced_path_bound(m, r)``, at most 1. A path with a coordinate that is
    not finite may change by anything (1).

    >>> square = PathScene.from_paths(8, 8, [[[[1, 1], [5, 1], [5, 5], [1, 5]]]])
    >>> moved = square.with_coordinates(square.coordinates + [1 / 64, 0])
    >>> round(path_motion_bound(square, moved, Convention(coverage="area"), 0, 4, 2), 4)
    0.0463
    >>> path_motion_bound(square, moved, Convention(coverage="area"), 0, 2, 2)
    0.0
    """
    return _bound_at(_motion_edges(before, after, convention, path), x, y)


_Edges = tuple[NDArray, NDArray, float] | None


def _motion_edges(before: PathScene, after: PathScene, convention: Convention, path: int) -> _Edges:
    """(p, q, r): the path's edges ``p -> q`` in ``before`` (snapped) and the largest
    distance a vertex moves (rounded up); None when a coordinate is not finite or the
    contours differ in shape (anything may change)."""
    a, b = _path_contours(before, convention, path), _path_contours(after, convention, path)
    if not all(np.all(np.isfinite(c)) for c in a + b) or [c.shape for c in a] != [c.shape for c in b]:
        return None
    if not a:
        return np.zeros((0, 2)), np.zeros((0, 2)), 0.0
    moves = np.concatenate([np.hypot(*(v - u).T) for u, v in zip(a, b)])
    reach = float(moves.max(initial=0.0)) * (1.0 + 2.0**-50)
    return np.concatenate(a), np.concatenate([np.roll(c, -1, axis=0) for c in a]), reach


def _bound_at(edges: _Edges, x: int, y: int) -> float:
    """:func:`path_motion_bound` at one pixel from :func:`_motion_edges`."""
    if edges is None:
        return 1.0
    p, q, reach = edges
    if reach == 0.0:
        return 0.0
    near = _edges_near(p, q, x, y, reach)
    return float(displaced_path_bound(np.array([near]), np.array([reach]))[0])



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
    earlier = _exact_model(before, convention, primitive, x, y, shares[0])
    later = _exact_model(after, convention, primitive, x, y, shares[1])
    if LINES.owns(after):
        return step_exceeds(step_alpha, later, earlier, limit)
    return bool(abs(step_alpha - (later - earlier)) > limit)


def _beyond_motion(scenes: list[Scene], coverages: list[Coverage], convention: Convention,
                   limit: float) -> tuple[int, list[dict[str, Any]]]:
    """Path frames: the (path, pixel, step)s whose alpha steps by more than ``limit``
    (twice the tolerance) beyond :func:`path_motion_bound` -- what no area within the
    tolerance at both frames can do, whatever the model -- and the worst few, ``{frame,
    path, x, y, d_alpha, bound, excess}`` (frame: the later of the step). Only steps beyond
    ``limit`` are looked at; a NaN or infinite alpha is beyond any bound."""
    first = PATHS.narrow(scenes[0])
    width, height, n = first.width, first.height, len(first)
    levels = convention.levels
    keyed = [_keyed(c, width, height, n) for c in coverages]
    count, worst = 0, []
    for f in range(1, len(scenes)):
        keys, a0, a1 = _aligned(*keyed[f - 1], *keyed[f])
        with np.errstate(invalid="ignore"):
            step = np.abs(level_values(a1, levels) - level_values(a0, levels))
        step[np.isnan(step)] = np.inf
        before, after = PATHS.narrow(scenes[f - 1]), PATHS.narrow(scenes[f])
        edges: dict[int, _Edges] = {}
        for i in np.flatnonzero(step > limit):
            key = int(keys[i])
            path, x, y = key // (width * height), key % width, key // width % height
            if path not in edges:
                edges[path] = _motion_edges(before, after, convention, path)
            bound = _bound_at(edges[path], x, y)
            excess = float(step[i]) - limit - bound
            if excess > 2.0**-40:  # beyond the bound's and the steps' roundings
                count += 1
                worst.append({"frame": f, "path": path, "x": x, "y": y, "d_alpha": float(a1[i] - a0[i]),
                              "bound": bound, "excess": excess})
    worst.sort(key=lambda item: -item["excess"])
    return count, worst[:EVIDENCE_LIMIT]


def _motion_verdict(scenes: list[Scene], coverages: list[Coverage], convention: Convention, limit: float,
                    metrics: dict[str, float], evidence: dict[str, Any]) -> str:
    """On path frames under an analytic area: :func:`_beyond_motion` into ``metrics`` and
    ``evidence`` (in place), and the words the failure message adds; '' elsewhere."""
    if not PATHS.owns(scenes[0]) or convention.samples is not None or convention.rows:
        return ""
    beyond, shown = _beyond_motion(scenes, coverages, convention, limit)
    metrics["beyond_motion"] = float(beyond)
    if shown:
        evidence["beyond_motion"] = shown
        return f"; {beyond} of them beyond what the motion allows any area (by up to {shown[0]['excess']:.3g})"
    return "; none beyond what the motion allows any area"


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
    8-bit level), ``frames``, ``exact_decisions``; on path frames under an analytic area,
    ``beyond_motion`` ((path, pixel, step)s stepping beyond what the motion allows any
    area, :func:`_beyond_motion`; evidence ``beyond_motion``). Evidence: ``series``, the worst pixel's
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
            bounds[f] = _model_bound(scenes[f], convention)
        return bounds[f]

    # anti-aliased strokes (harness.oracle.area_lines) and paths (harness.oracle.path_area):
    # their oracle's bound may exceed 2**-24
    oracle_slack = 2.0**-23 if not (LINES.owns(scenes[0]) or PATHS.owns(scenes[0])) else max(
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
    beyond_words = _motion_verdict(scenes, coverages, convention, float(limit), metrics, evidence)
    what = _model_words(convention)
    artifact = (f"against the exact area the summed alpha pops by up to {pop_max / unit:.1f} 8-bit levels in a step "
                f"({pops} pixel-steps beyond one level)")
    if not jumps:
        message = f"every alpha change within {tolerance:.3g} of {what}'s; {artifact}"
    else:
        message = (f"{jumps} alpha changes beyond {tolerance:.3g} (twice the tolerance) of {what}'s, by up to "
                   f"{worst_step:.3g}{beyond_words}; {artifact}")
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
