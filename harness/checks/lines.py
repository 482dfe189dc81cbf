"""Line checks (seed 003, issue 16): connectivity, joints, reversal, length and line-motion --
the artifacts of aliased lines, each judged against what the declared
:class:`~harness.contract.conventions.LineRule` promises (:mod:`harness.oracle.lines` defines the rules).

* **connectivity** (diamond-exit, Bresenham): each segment's pixels are one per step of its
  major axis from its first to its last, 8-connected: no gap, no doubled step.
* **joints**: at each polyline joint (:meth:`LineScene.joints`, closed polylines too) the
  shared vertex's pixel is drawn as often as the rule says (once when the last pixel is
  omitted, twice when drawn: a fact), and the pixels both segments draw are the rule's.
* **reversal**: every strip drawn backwards differs from the forward drawing exactly as the
  rule predicts (the diamond-exit rule omits the other end pixel, Bresenham breaks ties
  towards the other end, unless it normalises its direction of travel); the predicted
  difference is reported as a fact, and a Bresenham drawer whose two drawings are exactly
  its rule's under another ``direction`` is told to declare that one.
* **length**: each segment draws as many pixels as the rule, strictly (an off-by-one last
  pixel shows even where conformance excuses a near tie).
* **line-motion**: under sub-pixel translation (16 steps of 1/16 px along x, then along y)
  each segment's minor-axis pixel in each major-axis cell moves only the way the line moves,
  and its end cells never move against a motion along its major axis.

Each applies to still line cases only and needs the declared convention; a rule a check
does not define (rectangular lines for connectivity) is a skip with the reason. Evidence
names the segments (``scene.noun``). Pixel work is numpy over the pixel lists, no Python
loop per pixel.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.checks.conformance import near_ties_of, undefined_width
from harness.checks.motion import filled_direction
from harness.checks.records import EVIDENCE_LIMIT, Check, Result, Subject, Tolerance, register, result, skip
from harness.contract.case import Case
from harness.contract.conventions import AREA_LINE_RULES, LINE_DIRECTIONS, Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import COVERAGE_MODELS
from harness.contract.scenes import LineScene, Unsupported
from harness.kinds import LINES
from harness.oracle.coverage import exact_coverage
from harness.oracle.hairlines import HAIRLINE_MAX, HAIRLINE_RULES, hairline_x_major, to_fdot6
from harness.oracle.lines import area_holding, end_point_pixels, is_x_major

__all__ = [
    "x_major_of", "vertex_pixels", "connectivity", "joints", "reversal", "length", "line_motion", "motion_frames",
    "motion_oracles", "MOTION_STEPS",
]

# line-motion: 16 steps of 1/16 px (exact for any coordinate on a 1/16 lattice, and a
# monotone motion for any other: float rounding is monotone)
MOTION_STEPS = 16


# -- shared pieces -------------------------------------------------------------------------------


def _is_line_case(case: Any) -> bool:
    return not hasattr(case, "frames") and LINES.owns(getattr(case, "scene", None))


def _pixels(coverage: Coverage, n: int) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Each (segment, x, y) drawn, once, sorted by segment, y, x; unknown segments dropped."""
    seg, x, y = coverage.pixels()
    keep = (seg >= 0) & (seg < n)
    if not keep.any():
        none = np.zeros(0, dtype=np.int64)
        return none, none.copy(), none.copy()
    seg, x, y = seg[keep], x[keep], y[keep]
    x0, y0 = int(x.min()), int(y.min())
    width, height = int(x.max()) - x0 + 1, int(y.max()) - y0 + 1
    key = (seg * height + (y - y0)) * width + (x - x0)
    if key.size > 1 and not bool((key[1:] > key[:-1]).all()):  # sorted and once each already: the usual answer
        key = np.unique(key)
    return key // (width * height), key % width + x0, key // width % height + y0


def _keys(seg: NDArray, x: NDArray, y: NDArray, width: int, height: int) -> NDArray[np.int64]:
    """One int64 per (segment, x, y): (segment * height + y) * width + x."""
    keys: NDArray[np.int64] = (seg.astype(np.int64) * height + y) * width + x
    return keys


def _unkey(keys: NDArray, width: int, height: int) -> tuple[NDArray, NDArray, NDArray]:
    return keys // (width * height), keys % width, keys // width % height


@numba.njit(cache=True)
def _x_major_kernel(a, b, out):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    for k in range(a.shape[0]):
        out[k] = is_x_major(a[k, 0], a[k, 1], b[k, 0], b[k, 1])


def x_major_of(scene: LineScene, convention: Convention) -> NDArray[np.bool_]:
    """(N,) bool: whether each segment is x-major under the convention's rule: Bresenham
    by its rounded end points (``|x1 - x0| >= |y1 - y0|``), the others by the snapped end
    points, exactly (``|dy| <= |dx|``; a zero-length segment is x-major).

    >>> scene = LineScene.from_segments(8, 8, [[0.5, 0.5], [0.5, 0.5], [0.9, 0.1]], [[4.5, 4.5], [2.5, 5.5], [3.05, 2.95]])
    >>> x_major_of(scene, Convention()).tolist(), x_major_of(scene, Convention(line="bresenham")).tolist()
    ([True, False, False], [True, False, True])
    """
    a, b = scene.segments()
    return _x_major_of_ends(convention.snap(a), convention.snap(b), convention)


def _x_major_of_ends(a: NDArray, b: NDArray, convention: Convention) -> NDArray[np.bool_]:
    """:func:`x_major_of` for snapped end points ``a, b`` (M, 2)."""
    out = np.ones(a.shape[0], dtype=np.bool_)
    finite = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
    if convention.line.rule == "bresenham":
        p0, p1 = end_point_pixels(a[finite], convention.line.rounding), end_point_pixels(b[finite], convention.line.rounding)
        d = np.abs(p1 - p0)
        out[finite] = d[:, 0] >= d[:, 1]
        return out
    if convention.line.rule in HAIRLINE_RULES:  # by the 26.6 end points, each rule's own tie
        out[finite] = hairline_x_major(a[finite], b[finite], convention.line.rule)
        return out
    chosen = np.zeros(int(finite.sum()), dtype=np.bool_)
    if chosen.size:
        _x_major_kernel(np.ascontiguousarray(a[finite]), np.ascontiguousarray(b[finite]), chosen)
    out[finite] = chosen
    return out


def _rule(convention: Convention) -> str:
    """The declared line rule, for messages: ``the rule (diamond-exit lines, last pixel omitted)``."""
    return f"the rule ({convention.line.describe()})"


def _diagnosis(case: Case, name: str, outcome: Any, what: str) -> Result | None:
    """The skip or error result of a call on a variant scene that gave no coverage."""
    if outcome.coverage is not None:
        return None
    if isinstance(outcome.error, Unsupported):
        return skip(case, name, f"unsupported on {what}: {outcome.error}")
    kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
    return Result("", case.id, name, "error", f"{kind} on {what}: {outcome.error}", {"seconds": outcome.seconds},
                  {"traceback": outcome.traceback})


def _excused(case: Case, convention: Convention, tolerance: Tolerance, fragments: NDArray,
             scene: LineScene | None = None) -> NDArray[np.bool_]:
    """(M,) bool: fragments (3, M) (segment, x, y) that are near ties under the tolerance,
    on a non-lattice case in default mode (never otherwise)."""
    if tolerance.mode != "default" or case.lattice or not fragments.shape[1]:
        return np.zeros(fragments.shape[1], dtype=np.bool_)
    near, _ = near_ties_of(scene if scene is not None else case.scene, convention, fragments, tolerance)
    return near


# -- connectivity --------------------------------------------------------------------------------


def connectivity(case: Case, coverage: Coverage, convention: Convention) -> Result:
    """Each segment's pixels, one per step of its major axis (x-major: one per column,
    y-major: one per row; :func:`x_major_of`) from its first to its last, 8-connected.

    A *gap* is a major step with no pixel between the first and the last, a *double* a
    step with two or more, a *break* two neighbouring steps whose minor coordinates differ
    by more than one (not 8-connected). Segments are judged on what they draw inside the
    viewport; a segment drawing nothing is judged by conformance and length, not here.
    """
    scene = case.scene
    scene = LINES.narrow(scene)
    seg, x, y = _pixels(coverage, len(scene))
    major = x_major_of(scene, convention)
    along = major[seg]
    u = np.where(along, x, y)
    v = np.where(along, y, x)
    # cells (segment, major step), with their pixel count and minor range
    order = np.lexsort((v, u, seg))
    seg, u, v, x, y = seg[order], u[order], v[order], x[order], y[order]
    new_cell = np.ones(seg.size, dtype=bool)
    new_cell[1:] = (seg[1:] != seg[:-1]) | (u[1:] != u[:-1])
    start = np.flatnonzero(new_cell)
    count = np.diff(np.append(start, seg.size))
    cell_seg, cell_u = seg[start], u[start]
    low = np.minimum.reduceat(v, start) if start.size else v[:0]
    high = np.maximum.reduceat(v, start) if start.size else v[:0]
    same = cell_seg[1:] == cell_seg[:-1]
    step = np.diff(cell_u)
    gap = same & (step > 1)
    broken = same & (step == 1) & ((low[1:] > high[:-1] + 1) | (high[1:] < low[:-1] - 1))
    double = count > 1
    noun = scene.noun

    def pixel(index: int) -> list[int]:
        return [int(x[index]), int(y[index])]

    problems: list[dict[str, Any]] = []
    for c in np.flatnonzero(double)[:EVIDENCE_LIMIT]:
        axis = "column" if major[cell_seg[c]] else "row"
        pixels = [pixel(i) for i in range(start[c], start[c] + count[c])]
        problems.append({noun: int(cell_seg[c]), "kind": "double", axis: int(cell_u[c]), "pixels": pixels})
    for kind, found in (("gap", gap), ("break", broken)):
        for c in np.flatnonzero(found)[:EVIDENCE_LIMIT]:
            axis = "columns" if major[cell_seg[c]] else "rows"
            last_of_cell = start[c] + count[c] - 1
            problems.append({noun: int(cell_seg[c]), "kind": kind, axis: [int(cell_u[c]), int(cell_u[c + 1])],
                             "pixels": [pixel(last_of_cell), pixel(start[c + 1])]})
    problems.sort(key=lambda p: p[noun])
    missing = int((step[gap] - 1).sum())
    metrics = {"line_gaps": float(missing), "line_doubles": float(double.sum()), "line_breaks": float(broken.sum()),
               "segments_judged": float(np.unique(cell_seg).size)}
    ok = not problems
    if ok:
        message = f"each of {int(metrics['segments_judged'])} {noun}s: one pixel per major step, 8-connected"
    else:
        bad = np.unique(np.concatenate([cell_seg[double], cell_seg[:-1][gap | broken]]))
        first = problems[0]
        message = (f"{missing} missing steps, {int(double.sum())} doubled steps, {int(broken.sum())} breaks in "
                   f"{bad.size} {noun}s (first: {noun} {first[noun]}, {first['kind']} at {first['pixels']})")
    return result(case.id, "connectivity", ok, message, metrics, {"problems": problems[:EVIDENCE_LIMIT]} if problems else {})


def _guarded(name: str, run: Callable[[Subject], Result]) -> Callable[[Subject], Result]:
    """``run(subject)``, or a skip when the declared rule does not define the scene (a
    width-1 rule handed a wide line)."""

    def guarded(s: Subject) -> Result:
        assert s.convention is not None
        why = undefined_width(s.case.scene, s.convention)
        return skip(s.case, name, why) if why else run(s)

    return guarded


def _run_connectivity(s: Subject) -> Result:
    assert s.convention is not None
    if s.convention.line.rule in ("rectangle", "llvmpipe-rectangle"):
        return skip(s.case, "connectivity", "rectangular lines are filled rectangles: no rule of one pixel per major step")
    if s.case.scene.line_width != 1.0:
        return skip(s.case, "connectivity", "wide lines draw w pixels per major step: no rule of one")
    return connectivity(s.case, s.coverage, s.convention)


# -- joints --------------------------------------------------------------------------------------


@numba.njit(cache=True)
def _diamond_vertex_kernel(v, y_major, gl, width, height, out):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    for k in range(v.shape[0]):
        i, j, found = area_holding(v[k, 0], v[k, 1], y_major[k], gl, width, height)
        if found:
            out[k, 0] = i
            out[k, 1] = j


def vertex_pixels(scene: LineScene, convention: Convention, pairs: NDArray[np.int64]) -> NDArray[np.int64]:
    """(J, 2) int64: per joint (k, m) the pixel the rule ties to its shared vertex v, or
    (-1, -1) when none (inside the viewport).

    diamond-exit (D3D's or GL's): the pixel whose test area holds v, for the major axis of m (the segment
    starting there, which draws it; the one ending there omits it); Bresenham: the pixel v
    rounds to (both segments start or end there); skia's hairlines and Qt's cosmetic lines:
    the pixel holding v's 26.6 point; rectangles and parallelograms: none.
    """
    out = np.full((pairs.shape[0], 2), -1, dtype=np.int64)
    if not pairs.shape[0] or convention.line.rule in AREA_LINE_RULES:
        return out
    _, b = scene.segments()
    v = convention.snap(b[pairs[:, 0]])
    finite = np.asarray(np.isfinite(v).all(axis=1), dtype=np.bool_)
    if convention.line.rule in HAIRLINE_RULES:
        # the pixel holding the vertex's 26.6 point (both segments' DDAs end or start there)
        near = finite & (np.abs(np.where(finite[:, None], v, 0.0)) <= HAIRLINE_MAX).all(axis=1)
        held = to_fdot6(np.where(near[:, None], v, -1.0)) >> 6
        inside = near & (held[:, 0] >= 0) & (held[:, 0] < scene.width) & (held[:, 1] >= 0) & (held[:, 1] < scene.height)
        out[inside] = held[inside]
        return out
    if convention.line.rule == "bresenham":
        p = end_point_pixels(np.where(finite[:, None], v, -1.0), convention.line.rounding)
        inside = finite & (p[:, 0] >= 0) & (p[:, 0] < scene.width) & (p[:, 1] >= 0) & (p[:, 1] < scene.height)
        out[inside] = p[inside].astype(np.int64)
        return out
    y_major = ~x_major_of(scene, convention)[pairs[:, 1]]
    _diamond_vertex_kernel(np.ascontiguousarray(np.where(finite[:, None], v, -2.0)), y_major.astype(np.bool_),
                           convention.line.gl, scene.width, scene.height, out)
    return out


def _joint_counts(coverage: Coverage, scene: LineScene, pairs: NDArray, vertex: NDArray) -> tuple[NDArray, NDArray]:
    """Per joint, how often its two segments draw its vertex pixel ((J,) int, 0 where
    none), and the sorted keys (joint * height + y) * width + x of the pixels both draw."""
    w, h = scene.width, scene.height
    seg, x, y = _pixels(coverage, len(scene))
    drawn = _keys(seg, x, y, w, h)  # sorted: _pixels sorts by segment, y, x
    counts = np.zeros(pairs.shape[0], dtype=np.int64)
    has = vertex[:, 0] >= 0
    for side in (0, 1):
        counts[has] += np.isin(_keys(pairs[has, side], vertex[has, 0], vertex[has, 1], w, h), drawn)
    sides = []
    for side in (0, 1):
        joint_of = np.full(len(scene), -1, dtype=np.int64)
        joint_of[pairs[:, side]] = np.arange(pairs.shape[0])
        j = joint_of[seg]
        sides.append(_keys(j[j >= 0], x[j >= 0], y[j >= 0], w, h))
    return counts, np.intersect1d(sides[0], sides[1])


def joints(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention,
           tolerance: Tolerance = Tolerance()) -> Result:
    """At each joint (k, m) of a polyline (closed ones too: :meth:`LineScene.joints`), the
    vertex pixel (:func:`vertex_pixels`) is drawn by k and m together as often as the rule
    says -- once when it omits the last pixel, twice (a fact, not a failure) when it draws
    it -- and the pixels both k and m draw (a sharp turn's, or every joint's with the last
    pixel drawn; for rectangles their overlap) are exactly the oracle's. Differences at near
    ties are excused on non-lattice cases in default mode."""
    scene = case.scene
    scene = LINES.narrow(scene)
    pairs = scene.joints(closed=True)
    w, h = scene.width, scene.height
    noun = scene.noun
    vertex = vertex_pixels(scene, convention, pairs)
    got_count, got_overlap = _joint_counts(coverage, scene, pairs, vertex)
    want_count, want_overlap = _joint_counts(oracle, scene, pairs, vertex)
    # the differing (joint, pixel)s: overlap pixels one side has and the other lacks, and
    # vertex pixels drawn a different number of times
    odd = np.setxor1d(got_overlap, want_overlap)
    at_vertex = np.flatnonzero(got_count != want_count)
    keys = np.union1d(odd, _keys(at_vertex, vertex[at_vertex, 0], vertex[at_vertex, 1], w, h))
    joint, px, py = _unkey(keys, w, h)
    excused = np.zeros(keys.size, dtype=np.bool_)
    for side in (0, 1):
        excused |= _excused(case, convention, tolerance, np.stack([pairs[joint, side], px, py]))
    bad_joints = np.unique(joint[~excused])
    overlap_want = np.bincount(_unkey(want_overlap, w, h)[0], minlength=pairs.shape[0])
    overlap_got = np.bincount(_unkey(got_overlap, w, h)[0], minlength=pairs.shape[0])
    metrics = {"joints": float(pairs.shape[0]), "joint_overlap_predicted": float(want_overlap.size),
               "joint_overlap": float(got_overlap.size), "joint_vertex_double_predicted": float((want_count == 2).sum()),
               "joint_mismatches": float(bad_joints.size)}
    evidence: dict[str, Any] = {}
    if bad_joints.size:
        rows = []
        for j in bad_joints[:EVIDENCE_LIMIT]:
            mine = joint == j
            row: dict[str, Any] = {f"{noun}s": [int(pairs[j, 0]), int(pairs[j, 1])],
                                   "pixels": [[int(a), int(b)] for a, b in zip(px[mine], py[mine])]}
            if vertex[j, 0] >= 0:
                row.update({"vertex_pixel": [int(vertex[j, 0]), int(vertex[j, 1])], "drawn": int(got_count[j]),
                            "rule": int(want_count[j])})
            row.update({"overlap": int(overlap_got[j]), "rule_overlap": int(overlap_want[j])})
            rows.append(row)
        evidence["joints"] = rows
    if not pairs.shape[0]:
        message = "no polyline joints"
    elif bad_joints.size:
        first = evidence["joints"][0]
        said = (f"vertex pixel {first['vertex_pixel']} drawn {first['drawn']} times, the rule {first['rule']}; "
                if "vertex_pixel" in first and first["drawn"] != first["rule"] else "")
        message = (f"{bad_joints.size} of {pairs.shape[0]} joints differ from {_rule(convention)} (first: "
                   f"{noun}s {first[f'{noun}s'][0]} and {first[f'{noun}s'][1]}: {said}{first['overlap']} pixels drawn by both, "
                   f"the rule {first['rule_overlap']})")
    else:
        message = f"each of {pairs.shape[0]} joints as {_rule(convention)} predicts"
        doubled = int((want_count == 2).sum())
        if doubled:
            message += f": the vertex pixel drawn twice at {doubled} (the last pixel is drawn)"
        elif (vertex[:, 0] >= 0).any():
            message += ": the vertex pixel drawn once"
        if want_overlap.size:
            message += f"; {want_overlap.size} pixels drawn by both segments of a joint, as predicted"
    return result(case.id, "joints", not bad_joints.size, message, metrics, evidence)


def _run_joints(s: Subject) -> Result:
    assert s.convention is not None
    if not LINES.narrow(s.case.scene).joints(closed=True).shape[0]:
        return skip(s.case, "joints", "no polyline joints (every segment a strip of its own)")
    return joints(s.case, s.coverage, s.oracle, s.convention, s.tolerance)


# -- reversal ------------------------------------------------------------------------------------


def _mapped_keys(coverage: Coverage, index: NDArray | None, scene: LineScene) -> NDArray[np.int64]:
    """Sorted unique keys of a coverage's pixels, segment ids mapped through ``index``."""
    seg, x, y = _pixels(coverage, len(scene))
    if index is not None:
        seg = index[seg]
    return np.unique(_keys(seg, x, y, scene.width, scene.height))


def reversal(case: Case, coverage: Coverage, backward: Coverage, origin: NDArray[np.int64], oracle: Coverage,
             backward_oracle: Coverage, convention: Convention, tolerance: Tolerance = Tolerance()) -> Result:
    """The pixels each segment draws forwards but not backwards, and backwards but not
    forwards, are exactly the rule's (the oracle's on the scene and on
    :meth:`LineScene.reversed`); the predicted difference is a fact (``reversal_pixels``).
    Differences at near ties (forwards or backwards) are excused on non-lattice cases in
    default mode.

    Parameters
    ----------
    backward, backward_oracle : Coverage
        Of the reversed scene, whose segment k retraces segment ``origin[k]``.
    """
    scene = case.scene
    scene = LINES.narrow(scene)
    w, h = scene.width, scene.height
    forward, back = _mapped_keys(coverage, None, scene), _mapped_keys(backward, origin, scene)
    rule_forward, rule_back = _mapped_keys(oracle, None, scene), _mapped_keys(backward_oracle, origin, scene)
    everything = np.union1d(np.union1d(forward, back), np.union1d(rule_forward, rule_back))

    def pattern(f: NDArray, b: NDArray) -> NDArray:
        """0: the same both ways; 1: forwards only; 2: backwards only."""
        in_f, in_b = np.isin(everything, f, assume_unique=True), np.isin(everything, b, assume_unique=True)
        return np.where(in_f & ~in_b, 1, np.where(in_b & ~in_f, 2, 0))

    got, want = pattern(forward, back), pattern(rule_forward, rule_back)
    differ = np.flatnonzero(got != want)
    seg, px, py = _unkey(everything[differ], w, h)
    fragments = np.stack([seg, px, py])
    excused = _excused(case, convention, tolerance, fragments)
    reversed_scene, _ = scene.reversed()
    inverse = np.empty_like(origin)
    inverse[origin] = np.arange(origin.size)
    excused |= _excused(case, convention, tolerance, np.stack([inverse[seg], px, py]), reversed_scene)
    wrong = differ[~excused]
    names = np.array(["the same both ways", "forwards only", "backwards only"])
    noun = scene.noun
    metrics = {"reversal_pixels": float((want != 0).sum()), "reversal_differences": float((got != 0).sum()),
               "reversal_mismatches": float(wrong.size)}
    evidence: dict[str, Any] = {}
    if wrong.size:
        s, x, y = _unkey(everything[wrong], w, h)
        evidence["pixels"] = [{noun: int(s[i]), "x": int(x[i]), "y": int(y[i]), "drawn": str(names[got[wrong[i]]]),
                               "rule": str(names[want[wrong[i]]])} for i in range(min(wrong.size, EVIDENCE_LIMIT))]
        first = evidence["pixels"][0]
        message = (f"{wrong.size} pixels differ between forwards and backwards otherwise than {_rule(convention)} "
                   f"predicts, in {np.unique(s).size} {noun}s (first: {noun} {first[noun]} pixel ({first['x']}, {first['y']}) "
                   f"drawn {first['drawn']}, the rule {first['rule']})")
        direction = _direction_drawn(scene, reversed_scene, origin, forward, back, convention)
        if direction is not None:
            evidence["direction"] = direction
            walk = replace(convention.line, direction=direction).walk or "walked as given"
            message += f"; both ways it draws exactly the rule {walk}: declare LineRule(..., direction={direction!r})"
    elif metrics["reversal_pixels"]:
        message = (f"reversed, {int(metrics['reversal_pixels'])} pixels differ, as {_rule(convention)} predicts "
                   f"(in {np.unique(_unkey(everything[want != 0], w, h)[0]).size} {noun}s)")
    else:
        message = f"reversed, the same pixels, as {_rule(convention)} predicts"
    return result(case.id, "reversal", not wrong.size, message, metrics, evidence)


def _direction_drawn(scene: LineScene, reversed_scene: LineScene, origin: NDArray[np.int64], forward: NDArray,
                     back: NDArray, convention: Convention) -> str | None:
    """The other direction of travel (:data:`~harness.contract.conventions.LINE_DIRECTIONS`) under
    which the declared Bresenham rule draws exactly ``forward`` and ``back`` (keys of the
    scene and of its reversal, as :func:`reversal` has them): a drawer that normalises its
    direction (textbook plotLine) declared as walking as given, or the other way round.
    None when no other direction explains both (or the rule is not Bresenham)."""
    line = convention.line
    if line.rule != "bresenham":
        return None
    for direction in LINE_DIRECTIONS:
        if direction == line.direction:
            continue
        other = replace(convention, line=replace(line, direction=direction))
        if (np.array_equal(_mapped_keys(exact_coverage(scene, other), None, scene), forward)
                and np.array_equal(_mapped_keys(exact_coverage(reversed_scene, other), origin, scene), back)):
            return direction
    return None


def _run_reversal(s: Subject) -> Result:
    assert s.convention is not None
    backward_scene, origin = LINES.narrow(s.case.scene).reversed()
    outcome = s.call(backward_scene)
    failed = _diagnosis(s.case, "reversal", outcome, "the reversed scene")
    if failed is not None:
        return failed
    return reversal(s.case, s.coverage, outcome.coverage, origin, s.oracle, exact_coverage(backward_scene, s.convention),
                    s.convention, s.tolerance)


# -- length --------------------------------------------------------------------------------------


def length(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention) -> Result:
    """Each segment draws as many pixels as the rule (the oracle) does -- strictly, no near
    tie excused: an off-by-one last pixel shows even where conformance would excuse it.
    ``length_excess`` and ``length_deficit`` are the worst segment's."""
    scene = case.scene
    n = len(scene)
    got = np.bincount(_pixels(coverage, n)[0], minlength=n)
    want = np.bincount(_pixels(oracle, n)[0], minlength=n)
    diff = got - want
    wrong = np.flatnonzero(diff)
    noun = scene.noun
    metrics = {"length_mismatches": float(wrong.size), "length_excess": float(max(int(diff.max(initial=0)), 0)),
               "length_deficit": float(max(-int(diff.min(initial=0)), 0)), "oracle_pixels": float(want.sum())}
    evidence: dict[str, Any] = {}
    if wrong.size:
        evidence[f"{noun}s"] = [{noun: int(k), "drawn": int(got[k]), "rule": int(want[k])} for k in wrong[:EVIDENCE_LIMIT]]
        k = int(wrong[0])
        message = (f"{wrong.size} of {n} {noun}s draw another number of pixels than {_rule(convention)} "
                   f"(first: {noun} {k}, {int(got[k])} pixels, the rule {int(want[k])}); worst excess "
                   f"{int(metrics['length_excess'])}, deficit {int(metrics['length_deficit'])}")
    else:
        message = f"each of {n} {noun}s draws as many pixels as the rule ({int(want.sum())} in all)"
    return result(case.id, "length", not wrong.size, message, metrics, evidence)


# -- line-motion ---------------------------------------------------------------------------------


def motion_frames(scene: LineScene, steps: int = MOTION_STEPS) -> list[tuple[str, list[LineScene]]]:
    """The scene moved by ``k / steps`` px, k = 0 .. steps, along x and then along y, each
    frame in the viewport grown by one pixel both ways (so nothing leaves it)."""
    out = []
    for axis, name in ((0, "x"), (1, "y")):
        frames = []
        for k in range(steps + 1):
            offset = np.zeros(2)
            offset[axis] = k / steps
            moved = scene.vertices + offset
            frames.append(LineScene(scene.width + 1, scene.height + 1, moved, scene.strip_sizes, scene.line_width))
        out.append((name, frames))
    return out


def _geometry(frames: list[LineScene], convention: Convention) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Per frame and segment ((F, N) each), whether it is x-major under the rule
    (:func:`x_major_of`) and the sign of dx * dy (the slope's): of the rounded end points
    for Bresenham, else of the snapped ones (exact: a float difference has the sign of the
    exact one); 0 when non-finite. The frames share their strips (:func:`motion_frames`)."""
    start = frames[0].segment_start
    vertices = np.stack([frame.vertices for frame in frames])  # (F, V, 2)
    a = convention.snap(vertices[:, start].reshape(-1, 2))
    b = convention.snap(vertices[:, start + 1].reshape(-1, 2))
    x_major = _x_major_of_ends(a, b, convention)
    with np.errstate(invalid="ignore"):
        if convention.line.rule == "bresenham":
            a, b = end_point_pixels(a, convention.line.rounding), end_point_pixels(b, convention.line.rounding)
        slope = np.nan_to_num(np.sign(b[:, 0] - a[:, 0]) * np.sign(b[:, 1] - a[:, 1]))
    return x_major.reshape(len(frames), -1), slope.reshape(len(frames), -1)


def motion_oracles(frames: list[LineScene], convention: Convention) -> list[Coverage]:
    """The exact coverage of each frame, in one call of the oracle: every rule decides each
    segment alone, so the frames side by side in one scene give each frame's segments."""
    n = len(frames[0])
    together = LineScene(frames[0].width, frames[0].height, np.concatenate([f.vertices for f in frames]),
                         np.tile(frames[0].strip_sizes, len(frames)), frames[0].line_width)
    cov = exact_coverage(together, convention)
    bounds = np.searchsorted(cov.primitive, np.arange(len(frames) + 1) * n)  # spans sorted by segment
    return [Coverage(cov.primitive[lo:hi] - f * n, cov.y[lo:hi], cov.x0[lo:hi], cov.x1[lo:hi])
            for f, (lo, hi) in enumerate(zip(bounds[:-1], bounds[1:]))]


def _frame_cells(coverage: Coverage, n: int, x_major: NDArray, extent: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """A frame's pixels as cells: per pixel its cell key ``(2 * segment + y_major) * extent + u``
    (u its major coordinate, y_major whether the segment is y-major in this frame), its minor
    coordinate v, its end key ``2 * segment + y_major`` and u."""
    seg, x, y = _pixels(coverage, n)
    y_major = (~x_major[seg]).astype(np.int64)
    u, v = np.where(y_major == 0, x, y), np.where(y_major == 0, y, x)
    end = 2 * seg + y_major
    return end * extent + u, v.astype(np.float64), end, u.astype(np.float64)


def _series(cells: list[tuple[NDArray, NDArray, NDArray, NDArray]], universe: NDArray, n: int
            ) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Per frame the least and greatest minor coordinate in each cell of ``universe``
    ((F, K) each), and the first and last major cell of each end key ((F, 2N) each); NaN
    where there is none."""
    frames = len(cells)
    low = np.full((frames, universe.size), np.inf)
    high = np.full((frames, universe.size), -np.inf)
    first = np.full((frames, 2 * n), np.inf)
    last = np.full((frames, 2 * n), -np.inf)
    for f, (key, v, end, u) in enumerate(cells):
        where = np.searchsorted(universe, key)
        np.minimum.at(low[f], where, v)
        np.maximum.at(high[f], where, v)
        np.minimum.at(first[f], end, u)
        np.maximum.at(last[f], end, u)
    return tuple(np.where(np.isfinite(s), s, np.nan) for s in (low, high, first, last))  # type: ignore[return-value]


def _against(series: NDArray, direction: NDArray, judged: NDArray, strict_zero: bool) -> NDArray:
    """(F-1, K) bool: the judged steps of ``series`` (F, K) that go against ``direction``
    ((F-1, K)): the opposite sign, or with ``strict_zero`` any move where it is 0."""
    step = np.diff(series, axis=0)
    moved = np.isfinite(step) & (step != 0) & judged
    against: NDArray = moved & (np.sign(step) == -direction) & (direction != 0)
    if strict_zero:
        against |= moved & (direction == 0)
    return against


def line_motion(case: Case, sequences: list[tuple[str, list[LineScene], list[Coverage], list[Coverage]]],
                convention: Convention) -> Result:
    """Under each sub-pixel motion (:func:`motion_frames`), per segment and major cell, the
    least and the greatest minor pixel drawn never step against the line's motion, and --
    when the motion runs along the segment's major axis -- neither do its first and last
    cells.

    The major axis and the slope are the rule's in each frame (:func:`_geometry`; snapping
    or Bresenham's rounding may turn a segment near 45 degrees from x-major to y-major
    between two frames: its cells are then not compared across that step).

    Width-1 rules (diamond-exit, Bresenham) are judged against the geometry: a line moved
    along x by t has height y(u - t) at column u, so an x-major cell's row moves by
    -sign(dx*dy) (a horizontal line's not at all: any move is wrong) and a y-major cell's
    column by +1; likewise along y. The exact pixels do so: a cell's minor coordinate is
    a monotone function of the line's position (diamond-exit: the row holding the line at
    the cell's centre; Bresenham: the rounded end points move monotonically, and with them
    round(k*M/K)), and the extent along the motion only grows at its front and shrinks at
    its back. skia's hairlines are not monotone (an end crossing a pixel centre moves the
    DDA's start by a slope step: :mod:`harness.oracle.hairlines`) and are judged as the
    area rules are. Rectangular (and parallelogram) lines are thin regions whose ends may legitimately move a
    cell's pixels either way: they are judged against the exact answer's own direction at
    each step (its most recent move where it does not move, as
    :func:`harness.checks.motion.filled_direction`).

    Parameters
    ----------
    sequences : list of (axis name "x" or "y", frames, coverages per frame, oracle coverages per frame)
    """
    scene = case.scene
    scene = LINES.narrow(scene)
    n = len(scene)
    noun = scene.noun
    geometric = convention.line.rule not in AREA_LINE_RULES and (
        convention.line.rule not in HAIRLINE_RULES or HAIRLINE_RULES[convention.line.rule].monotone)
    jumps: list[dict[str, Any]] = []
    totals = {"cells": 0, "ends": 0}
    for axis, frames, coverages, oracles in sequences:
        extent = max(frames[0].width, frames[0].height) + 2
        x_major, slope = _geometry(frames, convention)  # (F, N) each
        got = [_frame_cells(c, n, x_major[f], extent) for f, c in enumerate(coverages)]
        want = [_frame_cells(c, n, x_major[f], extent) for f, c in enumerate(oracles)]
        universe = np.unique(np.concatenate([g[0] for g in got + want]))
        low, high, first, last = _series(got, universe, n)
        end_y_major = np.arange(2 * n) % 2 == 1
        along_end = end_y_major == (axis == "y")  # the motion runs along the major axis
        cell_end = universe // extent
        cell_seg, cell_along = cell_end // 2, along_end[cell_end]
        if geometric:
            # the geometric direction, judged where the slope's sign is the same in both frames
            direction = np.where(cell_along[None, :], -slope[:-1, cell_seg], 1.0)
            judged = slope[:-1, cell_seg] == slope[1:, cell_seg]
            minor = [(low, direction, judged), (high, direction, judged)]
            forward = np.broadcast_to(np.where(along_end, 1.0, 0.0), (len(frames) - 1, 2 * n))
            ends = [(first, forward), (last, forward)]
        else:
            o_low, o_high, o_first, o_last = _series(want, universe, n)
            judged = np.ones((len(frames) - 1, universe.size), dtype=bool)
            minor = [(low, filled_direction(np.diff(o_low, axis=0)), judged),
                     (high, filled_direction(np.diff(o_high, axis=0)), judged)]
            ends = [(first, np.where(along_end, filled_direction(np.diff(o_first, axis=0)), 0.0)),
                    (last, np.where(along_end, filled_direction(np.diff(o_last, axis=0)), 0.0))]
        for side, (series, direction, judged) in zip(("least", "greatest"), minor):
            back = _against(series, direction, judged, geometric)
            totals["cells"] += int(back.sum())
            for f, c in np.argwhere(back)[:EVIDENCE_LIMIT]:
                k, name = int(cell_seg[c]), "row" if cell_end[c] % 2 else "column"
                jumps.append({noun: k, "motion": axis, "frame": int(f + 1), "kind": f"{side} minor pixel",
                              name: int(universe[c] % extent), "from": int(series[f, c]), "to": int(series[f + 1, c])})
        for side, (series, direction) in zip(("first", "last"), ends):
            back = _against(series, direction, np.ones(direction.shape, dtype=bool), False)
            totals["ends"] += int(back.sum())
            for f, e in np.argwhere(back)[:EVIDENCE_LIMIT]:
                jumps.append({noun: int(e // 2), "motion": axis, "frame": int(f + 1), "kind": f"{side} cell",
                              "rows" if e % 2 else "columns": [int(series[f, e]), int(series[f + 1, e])]})
    jumps.sort(key=lambda j: (j[noun], j["motion"], j["frame"]))
    metrics = {"line_backward_steps": float(totals["cells"]), "line_end_backward_steps": float(totals["ends"]),
               "frames": float(sum(len(frames) for _, frames, _, _ in sequences))}
    ok = not jumps
    judge = "the line's motion" if geometric else "the exact pixels' motion"
    if ok:
        message = f"under sub-pixel motion along x and y every {noun}'s pixels move monotonically with {judge}"
    else:
        j = jumps[0]
        message = (f"{totals['cells']} steps of a minor pixel and {totals['ends']} of an end cell against {judge} "
                   f"(first: {noun} {j[noun]}, motion along {j['motion']}, frame {j['frame']}, {j['kind']})")
    return result(case.id, "line-motion", ok, message, metrics, {"backward_steps": jumps[:EVIDENCE_LIMIT]} if jumps else {})


def _run_line_motion(s: Subject) -> Result:
    assert s.convention is not None
    sequences = []
    for axis, frames in motion_frames(LINES.narrow(s.case.scene)):
        coverages = []
        for k, frame in enumerate(frames):
            outcome = s.call(frame)
            failed = _diagnosis(s.case, "line-motion", outcome, f"frame {k} of the motion along {axis}")
            if failed is not None:
                return failed
            coverages.append(outcome.coverage)
        sequences.append((axis, frames, coverages, motion_oracles(frames, s.convention)))
    return line_motion(s.case, sequences, s.convention)


# -- registration --------------------------------------------------------------------------------

# lines are single-sample, or multisample rectangles (harness.oracle.lines): a multisample answer is
# judged sample by sample (each layer a single-sample rectangle rule at its offset); an area
# answer gets none of these
_SINGLE = frozenset(model.coverage_kind for model in COVERAGE_MODELS.values() if model.lines and not model.alphas)

register(Check(
    "connectivity", _guarded("connectivity", _run_connectivity), _is_line_case, needs_convention=True, shrinks=True,
    coverage_kinds=_SINGLE, metrics={"line_gaps": (1.0, 0.0), "line_doubles": (1.0, 0.0), "line_breaks": (1.0, 0.0)},
    caption="each segment: one pixel per major-axis step from its first to its last, 8-connected (diamond-exit, Bresenham)",
    classifier="harness.diagnose.signatures:classify_connectivity", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "joints", _guarded("joints", _run_joints), _is_line_case, needs_convention=True, shrinks=True, coverage_kinds=_SINGLE,
    metrics={"joint_mismatches": (1.0, 0.0)},
    caption="at each polyline joint the vertex pixel is drawn as often as the rule says (once without the last pixel) "
            "and both segments draw the same pixels as the rule's",
    classifier="harness.diagnose.signatures:classify_joints", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "reversal", _guarded("reversal", _run_reversal), _is_line_case, needs_convention=True, shrinks=True, coverage_kinds=_SINGLE,
    metrics={"reversal_mismatches": (1.0, 0.0)},
    caption="drawn backwards, each segment differs from forwards exactly as the rule predicts (the difference a fact)",
    classifier="harness.diagnose.signatures:classify_reversal", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "length", _guarded("length", lambda s: length(s.case, s.coverage, s.oracle, s.convention)),  # type: ignore[arg-type]
    _is_line_case, needs_convention=True, shrinks=True, coverage_kinds=_SINGLE,
    metrics={"length_mismatches": (1.0, 0.0), "length_excess": (1.0, 0.0), "length_deficit": (1.0, 0.0)},
    caption="each segment draws exactly as many pixels as the rule, no near tie excused",
    classifier="harness.diagnose.signatures:classify_length", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "line-motion", _guarded("line-motion", _run_line_motion), _is_line_case, needs_convention=True, shrinks=True,
    coverage_kinds=_SINGLE,
    metrics={"line_backward_steps": (1.0, 0.0), "line_end_backward_steps": (1.0, 0.0)},
    caption="under sub-pixel motion along x and y each segment's pixels, per major-axis cell, and its end cells never "
            "move against the motion",
    classifier="harness.diagnose.signatures:classify_line_motion", cause_role="own", motion_role="none", figures=(),
))
