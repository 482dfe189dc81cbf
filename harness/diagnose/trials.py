"""Trials: the experiments that re-run the rasterizer on a failure to tell its cause
(:func:`with_trials`), their findings added to the failing result's evidence for its
signature (:mod:`harness.diagnose.signatures`) to read: the tie trial (wrong samples only
exactly on edges: do the wrong primitives pass shifted off them?), the dropped trial
(primitives missing whole: are moved copies, the other winding, other vertex orders
drawn?), the size trial, the lattice twin, the order dependence, a motion failure's frame
judged alone, and the snapping of a sequence. Each primitive kind names its own tie and
dropped trials (:mod:`harness.kinds`).

(identify's experiments on a rasterizer with no failure yet are its *probes*,
:mod:`harness.identify`; the experiments here are *trials*.)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.records import OVERFLOW_EDGES, frame_checks, motion_checks
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import SNAP_ROUNDINGS, Convention
from harness.contract.coverage import Coverage
from harness.contract.protocol import convention_for
from harness.contract.scenes import PathScene, Scene
from harness.diagnose.facts import answer_of, judged_convention, open_outline
from harness.diagnose.signatures import classify_invariance, classify_watertight, metric_of, signature
from harness.kinds import PATHS, TRIANGLES, kind_of

__all__ = ["with_trials", "tie_trial", "dropped_trial", "triangle_tie_trial", "vertex_row_trial", "triangle_dropped_trial",
           "path_orders_trial", "no_trial", "frame_case", "named_frames", "TIE_SHIFT", "DROPPED_SHIFTS"]

def with_trials(result: Any, case: Case | MotionCase, judge: Callable[[Case | MotionCase, str], list[Any]], rasterizer: Any) -> Any:
    """The failing ``result`` with the trials' evidence added when they apply: for
    conformance and invariance, ``viewport_edge`` (:func:`harness.diagnose.repro.grown_screen_passes`:
    the case passes moved into a grown screen; ``viewport_edge_refuted`` when it still
    fails) and ``input_precision`` (:func:`harness.diagnose.repro.input_precision_trial`: it passes
    rounded as the library receives it), ``size_trial`` (:func:`_size_trial`: large wrong
    triangles scaled down), ``tie_trial`` (wrong only exactly on edges: do the
    wrong triangles pass shifted off them? :func:`tie_trial`); for the motion checks
    (jaggy, texel, perspective, popping), ``input_precision`` as above for the whole
    sequence, else ``frame_failure`` (a frame the failure names, judged alone, fails
    conformance -- or accuracy, for anti-aliased coverage: that failure, tried and
    classified; :func:`_with_frame_failure`), else for texel and perspective
    ``snapping_trial`` (:func:`_snapping_trial`). Each costs a call or two of the
    rasterizer and the check; :func:`signature`
    then reads them as facts instead of guessing. Any other result comes back as it is.
    Never raises."""
    from harness.diagnose.repro import input_precision_trial, viewport_edge_trial

    try:
        if getattr(result, "status", None) == "fail" and result.check in motion_checks() and isinstance(case, MotionCase):
            return _with_frame_failure(result, case, judge, rasterizer)
        if getattr(result, "status", None) == "fail" and result.check == "seams" and isinstance(case, Case):
            return _with_order_dependence(result, case, judge)
        if getattr(result, "status", None) == "fail" and result.check == "triangulation" and isinstance(case, Case):
            return _with_triangles_failure(result, case, judge, rasterizer)
        if getattr(result, "status", None) == "fail" and result.check == "watertight" and isinstance(case, Case):
            return _with_lattice_twin(result, case, judge, convention_for(rasterizer, case.scene))
        if getattr(result, "status", None) != "fail" or result.check not in ("conformance", "invariance") or not isinstance(case, Case):
            return result
        evidence = dict(result.evidence)
        if "input_precision" not in evidence:
            found = input_precision_trial(case, result.check, judge, rasterizer)
            if found is not None:
                evidence["input_precision"] = found
        if "viewport_edge" not in evidence and "input_precision" not in evidence:
            trial = viewport_edge_trial(case, result.check, judge)
            if trial is not None:
                # it passes on a grown screen: the edge's fault; it still fails: not the edge's
                evidence["viewport_edge" if trial.pop("passes") else "viewport_edge_refuted"] = trial
        if "tie_trial" not in evidence and "input_precision" not in evidence:
            tie = tie_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if tie is not None:
                evidence["tie_trial"] = tie
        if "size_trial" not in evidence and "input_precision" not in evidence:
            size = _size_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if size is not None:
                evidence["size_trial"] = size
        if "dropped_trial" not in evidence and "input_precision" not in evidence \
                and not evidence.get("size_trial", {}).get("passes"):
            dropped = dropped_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if dropped is not None:
                evidence["dropped_trial"] = dropped
        return replace(result, evidence=evidence)
    except Exception:
        return result


# the tie trial's shift: dyadic, well beyond float rounding, and off every line of small
# denominator through a sample (a shifted edge holding a sample again is as rare as a generic one)
TIE_SHIFT = (1 / 64 + 1 / 4096, 1 / 128 + 1 / 65536)


# under snapping to 1/2**bits px, three shifts of whole grid steps, no two parallel: a
# snapped shift runs along the edges of its own slope and keeps their samples on them, or
# moves an edge by exactly one row of samples (a (47, 7) edge under (3, -5)/256), so the
# tie stands when each wrong triangle passes both ways under one of them
TIE_GRID_SHIFTS = ((5, 3), (-3, 5), (7, -2))


def _tie_shifts(convention: Convention) -> list[tuple[float, float]]:
    """The shifts the tie trial tries (:data:`TIE_SHIFT`, or :data:`TIE_GRID_SHIFTS` in
    steps of the convention's snapping grid)."""
    if convention.subpixel_bits is None:
        return [TIE_SHIFT]
    step = 2.0 ** -convention.subpixel_bits
    return [(a * step, b * step) for a, b in TIE_GRID_SHIFTS]


def tie_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]], convention: Convention | None
               ) -> dict[str, Any] | None:
    """Whether a conformance failure whose wrong samples all lie exactly on edges is the
    tie rule's: the wrong triangles alone, shifted one way and the other (every such
    sample then strictly inside or outside), pass strictly both times -- each triangle
    under one of :func:`_tie_shifts` at least (a shift parallel to one triangle's edge
    keeps its samples on it). A missing prestep or a dropped sliver that merely put its wrong
    samples on edges still fails. Two calls per shift; None when it does not apply
    (triangles only)."""
    if result.check != "conformance" or convention is None:
        return None
    trial: dict[str, Any] | None = kind_of(case.scene).hook("tie_trial")(result, case, judge, convention)
    return trial


def triangle_tie_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]], convention: Convention
                       ) -> dict[str, Any] | None:
    """:func:`tie_trial` of a triangle scene (the kind's ``tie_trial`` hook)."""
    scene = TRIANGLES.narrow(case.scene)
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    if not wrong or any(p.get("distance") != 0.0 or not isinstance(p.get("triangle"), int) for p in wrong):
        return None
    subset = scene.subset(np.array(sorted({int(p["triangle"]) for p in wrong}), dtype=np.int64))
    if not np.isfinite(subset.coordinates).all():
        return None
    tried = []
    unexplained = set(range(len(subset)))  # wrong triangles no shift has yet cleared
    for shift in _tie_shifts(convention):
        failing: set[int] = set()
        for sign in (1.0, -1.0):
            shifted = subset.with_coordinates(subset.coordinates + sign * np.array(shift))
            results = judge(Case(f"{case.id}/tie-shift/{'+' if sign > 0 else '-'}", shifted, lattice=True), "conformance")
            failing |= _failing_triangles(results, len(subset))
        tried.append(list(shift))
        if not failing:
            return {"shift": list(shift), "tried": tried, "passes": True}
        # a shift runs along the edges of its own slope: each triangle needs one that clears it
        unexplained &= failing
        if not unexplained:
            return {"shift": list(shift), "tried": tried, "passes": True}
    return {"shift": tried[-1], "tried": tried, "passes": False}


def vertex_row_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                      convention: Convention) -> dict[str, Any] | None:
    """The tie trial for paths whose wrong samples all lie exactly on their edges or on rows
    through one of their path's vertices (where the crossings' count is the tie rule's):
    the wrong paths alone, shifted one way and the other by :data:`TIE_SHIFT` (no sample
    then lies on an edge or meets a vertex's row), pass both times -- else those samples
    were wrong there by chance and the fill is. Two calls; None when it does not apply
    (under snapping the shift would snap away)."""
    scene = PATHS.narrow(case.scene)
    if convention.subpixel_bits is not None:
        return None
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    if not wrong or any(not isinstance(p.get("path"), int) or not 0 <= p["path"] < len(scene) for p in wrong):
        return None
    sy = convention.sample[1]
    if not all(p.get("distance") == 0.0 or any(np.any(c[:, 1] == p["y"] + sy) for c in scene.contours_of(int(p["path"])))
               for p in wrong):
        return None  # some wrong sample neither on an edge nor on a vertex's row: no tie
    subset = scene.subset(np.array(sorted({int(p["path"]) for p in wrong}), dtype=np.int64))
    if not np.isfinite(subset.coordinates).all():
        return None
    shift = np.array(TIE_SHIFT)
    for sign in (1.0, -1.0):
        shifted = subset.with_coordinates(subset.coordinates + sign * shift)
        verdicts = judge(Case(f"{case.id}/tie-shift/{'+' if sign > 0 else '-'}", shifted, lattice=True), "conformance")
        if not verdicts or any(r.status == "fail" for r in verdicts):
            return {"shift": list(TIE_SHIFT), "tried": [list(TIE_SHIFT)], "passes": False, "vertex_rows": True}
    return {"shift": list(TIE_SHIFT), "tried": [list(TIE_SHIFT)], "passes": True, "vertex_rows": True}


def _failing_triangles(results: list[Any], n: int) -> set[int]:
    """The triangles (of n) a conformance verdict finds wrong: all n when there is no pass
    and the evidence does not list every wrong sample (or names none)."""
    if results and all(r.status in ("pass", "skip") for r in results):
        return set()
    failed = [r for r in results if r.status == "fail"]
    if len(failed) != 1:
        return set(range(n))
    pixels = [p for p in failed[0].evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    named = {int(p["triangle"]) for p in pixels if isinstance(p.get("triangle"), int)}
    if not named or metric_of(failed[0], "wrong") > len(pixels):
        return set(range(n))
    return named


# the dropped trial's copies: each missing triangle moved by (i/4, j/4) px, i, j in 0..3
# (plus the tie trial's first shift)
DROPPED_SHIFTS = tuple((i / 4, j / 4) for j in range(4) for i in range(4))


def dropped_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                   convention: Convention | None) -> dict[str, Any] | None:
    """Whether triangles missing whole are dropped as such, culled, or missed by another
    bug: the missing triangles, each in 16 copies moved by quarter pixels
    (:data:`DROPPED_SHIFTS`), 16 more of the other winding (two vertices swapped) and 32
    of the same winding started at its other vertices, drawn in one call. A dropper (too
    small) draws none of the copies the oracle covers; a culler draws the other winding's
    only, right; a wrong sample point or edge test that missed a sliver's only sample draws
    some of the same winding; an open outline draws some orders. Returns ``{"copies": n,
    "drawn": k, "flipped_copies": m, "flipped_drawn": j, "flipped_right": r,
    "rotated_copies": q, "rotated_drawn": i}`` (copies the oracle covers, of them those the
    rasterizer drew something of, and of the other winding's those it drew exactly right:
    a culler's), ``open_contour`` (another order drawn: all drawn exactly as with each
    triangle's closing edge left out, :func:`open_outline`), and ``grown``
    (:func:`_grown_trial`) when none is drawn, the triangles are not culled and not so
    explained; None when it does not apply (triangles missing whole, near ties aside, finite)."""

    answer = answer_of(result)
    if result.check != "conformance" or convention is None or answer is None:
        return None
    trial: dict[str, Any] | None = kind_of(case.scene).hook("dropped_trial")(result, case, judge, convention, answer)
    return trial


def triangle_dropped_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                           convention: Convention, answer: Coverage) -> dict[str, Any] | None:
    """:func:`dropped_trial` of a triangle scene (the kind's ``dropped_trial`` hook)."""
    from harness.oracle.coverage import exact_coverage

    scene = TRIANGLES.narrow(case.scene)
    prims = _missing_whole(result, answer, "triangle")
    if prims is None:
        return None
    subset = scene.subset(prims)
    if not np.isfinite(subset.positions).all():
        return None
    # the same triangle as given, of the other winding, and of its winding started at its
    # second and third vertex: 16 copies each
    orders = ([0, 1, 2], [0, 2, 1], [1, 2, 0], [2, 0, 1])
    copies_of = len(DROPPED_SHIFTS) * len(subset)
    # off the quarter-pixel grid by the tie trial's shift: a sliver whose samples all lie on its
    # edges (a horizontal edge on a sample row) covers samples strictly inside in some copy
    shifts = np.repeat(np.array(DROPPED_SHIFTS) + np.array(_tie_shifts(convention)[0]), len(subset), axis=0)[:, None, :]

    def tiled(a: NDArray | None) -> NDArray | None:
        return None if a is None else np.concatenate([np.concatenate([a[:, order]] * len(DROPPED_SHIFTS)) for order in orders])
    positions = tiled(subset.positions) + np.concatenate([shifts] * len(orders))
    copies = Scene(scene.width, scene.height, positions, tiled(subset.attributes), tiled(subset.w))
    n = len(copies)
    oracle = exact_coverage(copies, convention)
    want = np.bincount(oracle.pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/dropped-copies", copies, lattice=True), "conformance")
                if r.check == "conformance"]
    if not verdicts:
        return None
    if verdicts[0].status == "pass":
        got, right = want, want
    elif (drawn := answer_of(verdicts[0])) is not None:
        pixels = drawn.pixels()[0]
        got = np.bincount(pixels[(pixels >= 0) & (pixels < n)], minlength=n)[:n] > 0
        right = want & _drawn_exactly(drawn, oracle, n, scene.width, scene.height)
    else:
        return None
    same, flipped, rotated = slice(0, copies_of), slice(copies_of, 2 * copies_of), slice(2 * copies_of, n)
    found: dict[str, Any] = {"copies": int(want[same].sum()), "drawn": int((want & got)[same].sum()),
                             "flipped_copies": int(want[flipped].sum()), "flipped_drawn": int((want & got)[flipped].sum()),
                             "flipped_right": int(right[flipped].sum()),
                             "rotated_copies": int(want[rotated].sum()), "rotated_drawn": int((want & got)[rotated].sum())}
    # a culler draws the other winding right, and its own from no vertex
    culled = found["flipped_drawn"] > 0 and found["flipped_right"] == found["flipped_drawn"] and not found["rotated_drawn"]
    if (found["flipped_drawn"] or found["rotated_drawn"]) and verdicts[0].status == "fail" and drawn is not None:
        # another order drawn: as with each triangle's closing edge left out (it runs
        # between two other vertices now), and not as a culler draws it (the other winding right)?
        found["open_contour"] = open_outline(drawn, copies, np.arange(n), convention,
                                              lambda right: {f for f in right if copies_of <= f[0] < 2 * copies_of})
    if found["copies"] and not found["drawn"] and not culled and not found.get("open_contour"):
        grown = _grown_trial(subset, case, judge, convention)
        if grown is not None:
            found["grown"] = grown
    return found


# the size trial: wrong triangles at least this long (px, their bounding box's longer
# side) and below the overflow classes (2**12) are tried scaled down under it
SIZE_TRIAL_EXTENT = 64.0


def _size_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                convention: Convention | None) -> dict[str, Any] | None:
    """Whether triangles wrong at their size are right made smaller: a range that gives out
    early -- int32 edge functions of 8-bit fixed point wrap from about 181 px, long before
    any coordinate reaches the overflow classes' 2**12 -- rather than a convention part's
    error, which shows at any size. Each wrong triangle (near ties aside) at least
    :data:`SIZE_TRIAL_EXTENT` px long and under 2**12 px from the origin is scaled by the
    power of two bringing it under that length, moved by whole pixels to the screen's
    centre, in 16 copies moved by quarter pixels (:data:`DROPPED_SHIFTS`) and 16 more made
    :data:`GROWN_THICKNESS` px thick (:func:`_thickened`: a sliver scaled down covers
    few samples), judged in one call. Returns ``{"scales": [...], "shaped": m,
    "shaped_right": j, "copies": n, "right": k, "passes": bool}`` (copies the oracle
    covers, of them those drawn exactly right, in shape and thick; passes when every one
    is right, one in shape and four thick at least -- a dropper of small areas drops the
    ones in shape); None when it does not apply."""
    from harness.oracle.coverage import exact_coverage

    scene = case.scene
    # triangles only: a scaled-down copy of a path or line is another trial's
    if result.check != "conformance" or convention is None or not TRIANGLES.owns(scene):
        return None
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and isinstance(p.get("triangle"), int)
             and not p.get("near_tie")]
    if not wrong:
        return None
    prims = np.array(sorted({int(p["triangle"]) for p in wrong}), dtype=np.int64)
    subset = scene.subset(prims)
    positions = subset.positions
    if not np.isfinite(positions).all() or np.abs(positions).max(initial=0.0) >= 2.0**OVERFLOW_EDGES[0]:
        return None
    extent = (positions.max(axis=1) - positions.min(axis=1)).max(axis=1)
    if not (extent >= SIZE_TRIAL_EXTENT).all():
        return None  # a small one wrong too: not (only) its size
    scales = 2.0 ** -(np.floor(np.log2(extent / SIZE_TRIAL_EXTENT)) + 1)  # under it, by a power of two
    # about its centroid's pixel, moved by whole pixels to the screen's centre, made thick
    # as a grown copy (a sliver scaled down covers no sample)
    centroid = np.floor(positions.mean(axis=1, keepdims=True))
    centre = np.array([scene.width // 2, scene.height // 2], dtype=np.float64)
    smaller = centre + (positions - centroid) * scales[:, None, None]
    # each in its shape and made thick: a dropper of small areas drops the first, and a
    # sliver's first may cover no sample
    shifts = np.repeat(np.array(DROPPED_SHIFTS), len(subset), axis=0)[:, None, :]
    tile = lambda a: None if a is None else np.concatenate([a] * len(DROPPED_SHIFTS) * 2)  # noqa: E731
    both = np.concatenate([np.concatenate([smaller] * len(DROPPED_SHIFTS)) + shifts,
                           np.concatenate([_thickened(smaller, GROWN_THICKNESS)] * len(DROPPED_SHIFTS)) + shifts])
    copies = Scene(scene.width, scene.height, both, tile(subset.attributes), tile(subset.w))
    n = len(copies)
    oracle = exact_coverage(copies, convention)
    want = np.bincount(oracle.pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/smaller", copies, lattice=True), "conformance") if r.check == "conformance"]
    if not verdicts:
        return None
    if verdicts[0].status == "pass":
        right = want
    elif (drawn := answer_of(verdicts[0])) is not None:
        right = want & _drawn_exactly(drawn, oracle, n, scene.width, scene.height)
    else:
        return None
    shaped, thick = slice(0, n // 2), slice(n // 2, n)
    found: dict[str, Any] = {"scales": scales.tolist(), "shaped": int(want[shaped].sum()), "shaped_right": int(right[shaped].sum()),
                             "copies": int(want[thick].sum()), "right": int(right[thick].sum())}
    found["passes"] = found["copies"] >= 4 and found["right"] == found["copies"] \
        and found["shaped"] >= 1 and found["shaped_right"] == found["shaped"]
    return found


def _missing_whole(result: Any, answer: Coverage, noun: str) -> NDArray[np.int64] | None:
    """The primitives (``noun``: triangle or path) a conformance failure finds wrong, when
    every wrong deviation -- near ties excused, as the classes read them -- is a missing
    fragment of a primitive the answer draws nothing of; else None."""
    listed = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict)]
    wrong = [p for p in listed if not p.get("near_tie")] or listed
    if not wrong or any(p.get("kind") != "missing" or not isinstance(p.get(noun), int) for p in wrong):
        return None
    prims = np.array(sorted({int(p[noun]) for p in wrong}), dtype=np.int64)
    return None if np.isin(answer.pixels()[0], prims).any() else prims  # drawn in part: not missing whole


def path_orders_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                       convention: Convention, answer: Coverage) -> dict[str, Any] | None:
    """The dropped trial of paths missing whole (near ties aside): the same paths with
    every contour started at its second and at its third vertex, drawn in one call with
    the paths as given. A dropper draws none; an open outline (:func:`open_outline`) draws
    some, all exactly as it predicts. Returns ``{"rotated_copies": n, "rotated_drawn": k, "open_contour": bool}``
    (copies the oracle covers, those drawn something of), None when it does not apply."""
    from harness.oracle.coverage import exact_coverage

    scene = PATHS.narrow(case.scene)
    prims = _missing_whole(result, answer, "path")
    if prims is None:
        return None
    subset = scene.subset(prims)
    if not np.isfinite(subset.vertices).all():
        return None
    starts = np.concatenate([[0], np.cumsum(subset.contour_sizes)])
    contours = [subset.vertices[a:b] for a, b in zip(starts[:-1], starts[1:])]
    rotations = (0, 1, 2)  # with the paths as given: missing, as the hypothesis must predict too
    vertices = np.concatenate([np.roll(c, -r, axis=0) for r in rotations for c in contours])
    owner = np.concatenate([subset.contour_path + k * len(subset) for k in range(len(rotations))])
    copies = PathScene(scene.width, scene.height, vertices, np.tile(subset.contour_sizes, len(rotations)), owner,
                       subset.fill_rule)
    n = len(copies)
    want = np.bincount(exact_coverage(copies, convention).pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/other-orders", copies, lattice=True), "conformance")
                if r.check == "conformance"]
    if not verdicts:
        return None
    got = None if verdicts[0].status == "pass" else answer_of(verdicts[0])
    if got is None and verdicts[0].status != "pass":
        return None
    pixels = got.pixels()[0] if got is not None else np.zeros(0, dtype=np.int64)
    drawn = want if got is None else np.bincount(pixels[(pixels >= 0) & (pixels < n)], minlength=n)[:n] > 0
    rotated = slice(len(subset), n)
    found: dict[str, Any] = {"rotated_copies": int(want[rotated].sum()), "rotated_drawn": int((want & drawn)[rotated].sum())}
    found["open_contour"] = got is not None and bool(found["rotated_drawn"]) and open_outline(got, copies, np.arange(n), convention)
    return found


def _drawn_exactly(answer: Coverage, oracle: Coverage, n: int, width: int, height: int) -> NDArray[np.bool_]:
    """(n,) bool: the primitives whose fragments in the viewport are exactly the oracle's."""
    def keys(coverage: Coverage) -> NDArray[np.int64]:
        t, x, y = coverage.pixels()
        keep = (t >= 0) & (t < n) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
        return np.unique((t[keep] * height + y[keep]) * width + x[keep])
    differ = np.setxor1d(keys(answer), keys(oracle), assume_unique=True) // (width * height)
    return np.bincount(differ, minlength=n)[:n] == 0


def _thickened(p: NDArray[np.float64], thickness: float) -> NDArray[np.float64]:
    """(N, 3, 2) triangles with each far vertex moved away from its longest edge until
    the triangle is at least ``thickness`` px thick there (its winding kept; a flat one's
    far vertex goes to the edge's left)."""
    p = p.copy()
    with np.errstate(all="ignore"):
        sides = p[:, [1, 2, 0]] - p
        rows = np.arange(len(p))
        k = np.hypot(sides[..., 0], sides[..., 1]).argmax(axis=1)
        a, b, c = p[rows, k], p[rows, (k + 1) % 3], p[rows, (k + 2) % 3]
        d = b - a
        length = np.hypot(d[:, 0], d[:, 1])
        cross = d[:, 0] * (c[:, 1] - a[:, 1]) - d[:, 1] * (c[:, 0] - a[:, 0])
        side = np.where(cross < 0, -1.0, 1.0)
        normal = np.stack([-d[:, 1], d[:, 0]], axis=-1) / length[:, None] * side[:, None]
        p[rows, (k + 2) % 3] = c + normal * np.maximum(thickness - np.abs(cross) / length, 0.0)[:, None]
    return p


# the grown trial: each never-drawn triangle made this many pixels thick and long
GROWN_THICKNESS = 3.0


def _grown_trial(subset: Scene, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                 convention: Convention) -> dict[str, Any] | None:
    """Whether triangles never drawn at any small move (the dropped trial) are dropped for
    their size or missed by the bug seen elsewhere: each grown -- scaled about its centroid
    by a power of two until its longest edge is :data:`GROWN_THICKNESS` pixels long, then
    its far vertex moved away from that edge until it is as thick -- in the same screen,
    judged once. A dropper (too small) draws the grown copies right; an edge test that
    starts spans a column late, or samples off the pixel, draws them wrong -- that failure,
    classified here, names the cause. Returns ``{"scales": [...], "drawn": k, "passes":
    bool, "signature": key}`` (the signature when it fails), None when it does not apply."""
    p = subset.positions
    if not np.isfinite(p).all() or np.abs(p).max(initial=0.0) > 2.0**20:
        return None
    with np.errstate(all="ignore"):
        sides = p[:, [1, 2, 0]] - p
        longest = np.hypot(sides[..., 0], sides[..., 1]).max(axis=1)
        if not (longest > 0).all():
            return None
        scales = 2.0 ** np.ceil(np.log2(np.maximum(GROWN_THICKNESS / longest, 1.0)))
        centroid = p.mean(axis=1, keepdims=True)
        grown = _thickened(centroid + (p - centroid) * scales[:, None, None], GROWN_THICKNESS)
    if not np.isfinite(grown).all():
        return None
    grown_case = Case(f"{case.id}/grown", subset.with_coordinates(grown))
    verdicts = [r for r in judge(grown_case, "conformance") if r.check == "conformance"]
    if not verdicts:
        return None
    found: dict[str, Any] = {"scales": scales.tolist(), "passes": verdicts[0].status == "pass"}
    answer = answer_of(verdicts[0])
    drawn = answer.pixels()[0] if answer is not None else np.zeros(0, dtype=np.int64)
    found["drawn"] = len(grown) if found["passes"] else int(np.unique(drawn[(drawn >= 0) & (drawn < len(grown))]).size)
    if verdicts[0].status == "fail":
        found["signature"] = signature(verdicts[0], grown_case, convention).key
    return found


# the invariance variants that reverse the direction in which a triangle runs along its
# edges: a coverage that changes under them differs on the two sides of a shared edge
EDGE_DIRECTION_VARIANTS = ("flip-winding", "rotate-vertices")


def _with_order_dependence(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]]) -> Any:
    """A failing seams result with ``order_dependence`` added when the same case fails
    invariance under a variant of :data:`EDGE_DIRECTION_VARIANTS`: two triangles run along
    their shared edge in opposite directions, so a coverage that depends on the direction
    leaves a seam there -- the seam is that dependence, one cause with the invariance
    failure. One call."""
    evidence = dict(result.evidence)
    if "order_dependence" in evidence:
        return result
    for verdict in judge(case, "invariance"):
        if verdict.status == "fail" and verdict.check == "invariance":
            found, _ = classify_invariance(verdict, case, None)
            if found.removeprefix("changes-under-") in EDGE_DIRECTION_VARIANTS:
                evidence["order_dependence"] = found
                return replace(result, evidence=evidence)
    return result


# the lattice twin's edge: the shared edge's direction as a ratio of integers up to this
LATTICE_TWIN_DENOMINATOR = 16


def _with_lattice_twin(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                       convention: Convention | None) -> Any:
    """A failing watertight result of a float partition whose holes and double hits all lie
    exactly on shared edges, with ``lattice_twin`` added: whether the same tie, rebuilt on a
    lattice (two triangles sharing an edge of the same direction -- as a ratio of small
    integers -- through a sample, in each vertex rotation and both windings: float
    arithmetic exact there), fails too. It does: the tie rule's fault. It never does: the
    float case's rounding decided the tie (float32 edge functions), a near tie that merely
    fell exactly on the edge. Up to six calls of the rasterizer and the check."""
    evidence = dict(result.evidence)
    if case.lattice or "lattice_twin" in evidence or classify_watertight(result, case, convention)[1] != "tie-rule":
        return result
    judged = judged_convention(result, convention)
    edges: list[Any] = [b["edge"] for b in evidence.get("blame", []) if isinstance(b, dict) and b.get("edge")]
    if not edges or PATHS.owns(case.scene):  # a twin moves a triangle's edge: a path's crossings are the vertex-row trial's
        return result
    a, b = (judged.snap(np.asarray(v, dtype=np.float64)) for v in edges[0])
    step, twins = _lattice_twins(b - a, judged)
    if not twins:
        return result
    fails = False
    for twin in twins:
        verdicts = [r for r in judge(twin, "watertight") if r.check == "watertight"]
        if verdicts and verdicts[0].status == "fail":
            fails = True
            break
    evidence["lattice_twin"] = {"direction": step.tolist(), "fails": fails}
    return replace(result, evidence=evidence)


def _lattice_twins(direction: NDArray, judged: Convention) -> tuple[NDArray, list[Case]]:
    """Two triangles sharing an edge of ``direction`` (its slope as a ratio of integers up
    to :data:`LATTICE_TWIN_DENOMINATOR`, its signs kept) whose midpoint is a sample, in a
    48-pixel screen: one case per vertex rotation and winding, each a planar partition (its
    region the rhombus they make), and the edge's lattice direction. No case when the
    direction is not finite or zero, or the snapping grid cannot hold the twin."""
    from fractions import Fraction

    dx, dy = float(direction[0]), float(direction[1])
    if not (math.isfinite(dx) and math.isfinite(dy)) or dx == dy == 0.0:
        return np.zeros(2), []
    if dx == 0.0 or dy == 0.0:
        step = np.array([math.copysign(2.0, dx) if dx else 0.0, math.copysign(2.0, dy) if dy else 0.0])
    else:
        slope = Fraction(abs(dy) / abs(dx)).limit_denominator(LATTICE_TWIN_DENOMINATOR)
        if slope == 0 or slope.numerator > LATTICE_TWIN_DENOMINATOR:
            slope = Fraction(1, LATTICE_TWIN_DENOMINATOR) if slope == 0 else Fraction(LATTICE_TWIN_DENOMINATOR, 1)
        step = np.array([math.copysign(slope.denominator, dx), math.copysign(slope.numerator, dy)])
    sample = np.array([24.0 + judged.sample[0], 24.0 + judged.sample[1]])
    normal = np.array([-step[1], step[0]])
    a, b, left, right = sample - step, sample + step, sample + normal, sample - normal
    if not np.array_equal(judged.snap(np.stack([a, b, left, right])), np.stack([a, b, left, right])):
        return step, []  # the snapping grid is coarser than the sample's offset: no exact twin
    region = np.stack([a, left, b, right])
    cases = []
    for flip in (False, True):
        pair = np.array([[a, b, left], [b, a, right]])
        if flip:
            pair = pair[:, [0, 2, 1]]
        for turn in range(3):
            rotated = np.roll(pair, turn, axis=1)
            cases.append(Case(f"lattice-twin/{'flipped' if flip else 'kept'}/{turn}", Scene(48, 48, rotated),
                              lattice=True, region=region))
    return step, cases


def _with_triangles_failure(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                            rasterizer: Any) -> Any:
    """A failing triangulation result with ``triangles_failure`` added when the paths'
    triangulation, drawn as triangles, fails conformance itself: the mismatch is that
    failure's (a tie rule wrong on the triangles' flat edges), tried and classified. One
    call (more for that failure's trials)."""
    from harness.checks.paths import triangulated

    evidence = dict(result.evidence)
    made = triangulated(case.scene) if PATHS.owns(case.scene) and "triangles_failure" not in evidence else None
    if made is None:
        return result
    triangles = Case(f"{case.id}/triangulated", made[0], lattice=True)  # strict: the check excuses no near tie
    failed = [r for r in judge(triangles, "conformance") if r.status == "fail" and r.check == "conformance"]
    if not failed:
        return result
    tried = with_trials(failed[0], triangles, judge, rasterizer)
    named = signature(tried, triangles, convention_for(rasterizer, triangles.scene))
    evidence["triangles_failure"] = {"message": tried.message, "signature": named.key}
    return replace(result, evidence=evidence)


def frame_case(case: MotionCase, frame: int) -> Case:
    """Frame ``frame`` (0-based) of a motion sequence as a still case, judged as the jaggy
    check judges frames: every deviation from the oracle counts, none excused as a near
    tie (``lattice``: conformance's strict reading)."""
    return Case(f"{case.id}/frame/{frame}", case.frames[frame], lattice=True)


# the motion checks whose failures are read through a frame's still verdict, and those
# verdicts (conformance for aliased coverage, accuracy for anti-aliased: one applies) are
# the registry's: :func:`harness.checks.records.motion_checks`, :func:`~harness.checks.records.frame_checks`
# frames judged alone per failing motion result, at most
FRAMES_TRIED = 3


def named_frames(result: Any) -> list[int]:
    """The frames (0-based) a failing motion result names, in its evidence's order: the
    frames off the oracle (jaggy), of texel mismatches and backward steps (texel; a step
    names its frame and the one before), of the worst u, v error (perspective), of the
    worst alpha steps (popping); at most :data:`FRAMES_TRIED`."""
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    frames: list[int] = []
    if result.check == "jaggy":
        frames += [int(f) for f in evidence.get("oracle_mismatch_frames") or []][:1]
    for key, step in (("mismatches", False), ("backward_steps", True), ("steps", True)):
        for row in evidence.get(key) or []:
            if isinstance(row, dict) and isinstance(row.get("frame"), int):
                frames += [row["frame"], row["frame"] - 1] if step else [row["frame"]]
    worst = evidence.get("worst")
    if isinstance(worst, dict) and isinstance(worst.get("frame"), int):
        frames.append(worst["frame"])
    return list(dict.fromkeys(f for f in frames if f >= 0))[:FRAMES_TRIED]


def _with_frame_failure(result: Any, case: MotionCase, judge: Callable[[Case | MotionCase, str], list[Any]], rasterizer: Any) -> Any:
    """A failing motion result with ``frame_failure`` added: the first of its named frames
    (:func:`named_frames`) that fails conformance (or accuracy) judged alone, that failure
    tried -- so a flicker, a swimming texel or a pop caused by a wrong tie rule, snapping
    or alpha is named by that cause. A call per frame tried."""
    from harness.diagnose.repro import input_precision_trial

    evidence = dict(result.evidence)
    if "frame_failure" in evidence or "input_precision" in evidence or "snapping_trial" in evidence:
        return result
    found = input_precision_trial(case, result.check, judge, rasterizer)
    if found is not None:  # the whole sequence passes as the library receives it
        evidence["input_precision"] = found
        return replace(result, evidence=evidence)
    for frame in named_frames(result):
        if frame >= len(case.frames):
            continue
        still = frame_case(case, frame)
        for check in frame_checks():
            verdicts = judge(still, check)
            failed = [r for r in verdicts if r.status == "fail"]
            if failed:
                tried = with_trials(failed[0], still, judge, rasterizer)
                # classified here, where the frame's answer is at hand (the snapping and
                # fill-rule hypotheses compare it)
                named = signature(tried, still, convention_for(rasterizer, still.scene))
                evidence["frame_failure"] = {"frame": frame, "check": check, "message": tried.message,
                                             "signature": named.key, "metrics": dict(tried.metrics),
                                             "evidence": dict(tried.evidence)}
                return replace(result, evidence=evidence)
            if any(r.status == "pass" for r in verdicts):
                break  # this frame passes its verdict: try the next
    trial = _snapping_trial(result, case, convention_for(rasterizer, case.frames[0]))
    if trial is not None:
        evidence["snapping_trial"] = trial
        return replace(result, evidence=evidence)
    return result


def _snapping_trial(result: Any, case: MotionCase, convention: Convention | None) -> dict[str, Any] | None:
    """For a texel or perspective failure whose frames all pass conformance, under a
    snapping convention: the other roundings that move a vertex (fewest moved first), the
    check run again on the same answers against that rounding's exact oracles. The first
    under which it passes (``{"rounding": ..., "passes": True}``): the u, v came from vertices
    snapped that way -- the snapping's fault, which the coverage did not show. None when
    none passes or it does not apply. No rasterizer call: an oracle per frame per rounding."""
    from harness.checks.motion import perspective, texel_swimming
    from harness.oracle.coverage import exact_coverage

    if result.check not in ("texel", "perspective") or convention is None or convention.subpixel_bits is None:
        return None
    coverages = list(getattr(getattr(result, "drawing", None), "coverages", None) or [])
    frames = list(case.frames)
    if len(coverages) != len(frames) or not all(TRIANGLES.owns(f) and np.isfinite(f.positions).all() for f in frames):
        return None
    positions = np.concatenate([f.positions for f in frames])
    declared = convention.snap(positions)
    others = []
    for rounding in SNAP_ROUNDINGS:
        moved = int(np.sum(replace(convention, snap_rounding=rounding).snap(positions) != declared))
        if rounding != convention.snap_rounding and moved:
            others.append((moved, rounding))
    for _, rounding in sorted(others):
        other = replace(convention, snap_rounding=rounding)
        oracles = [exact_coverage(f, other) for f in frames]
        again = (texel_swimming(case.id, coverages, oracles, case.texels or 1) if result.check == "texel"
                 else perspective(case.id, coverages, oracles, case.texels or 1))
        if again.status == "pass":
            return {"rounding": rounding, "passes": True}
    return None


def no_trial(*args: Any) -> None:
    """A kind's ``tie_trial`` or ``dropped_trial`` hook when it has none (lines: the line
    checks' own distances say where the rule's decision sits)."""
    return None
