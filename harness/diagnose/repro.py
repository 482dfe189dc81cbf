"""Minimal repros: shrink a failing case to the smallest one that still fails the same
check, and try what the failure depends on (trials: the rasterizer called again on a
changed case).

Shrinking is delta debugging over the triangles (Zeller's ddmin), then coarsening every
coordinate to the simplest dyadic lattice on which the check still fails. The repro is
stored as case JSON (:mod:`harness.contract.case`, every float as ``float.hex``) naming the check;
:func:`harness.engine.runner.replay` runs it. The checks are reached through a ``judge``
(``judge(case, check) -> results``) so that this module needs nothing of the runner's.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness import checks
from harness.checks import Result
from harness.contract.case import Case, MotionCase, case_to_json
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer, received_of
from harness.contract.scenes import AnyScene
from harness.geometry.exact import orientation
from harness.kinds import TRIANGLES, kind_of

__all__ = ["ddmin", "shrink", "attach_repro", "hole_repro", "whole_case_repro", "answer_json", "answer_from_json", "MAX_ANSWER_FRAGMENTS", "input_precision_trial", "grown_screen_passes", "viewport_edge_trial",
           "grown_screen", "Judge"]

# The checks of one rasterizer on a case, restricted to one check by name.
Judge = Callable[[Case | MotionCase, str], list[Result]]


def ddmin(items: list[int], fails: Callable[[list[int]], bool], budget: int) -> list[int]:
    """Zeller's ddmin: a 1-minimal sublist of ``items`` on which ``fails`` still holds,
    within ``budget`` calls of ``fails`` (the best found so far when it runs out).

    >>> ddmin(list(range(10)), lambda s: 3 in s and 7 in s, 100)
    [3, 7]
    """
    n = 2
    calls = 0
    while len(items) >= 2 and calls < budget:
        size = -(-len(items) // n)
        chunks = [items[i : i + size] for i in range(0, len(items), size)]
        reduced = False
        for chunk in chunks:
            calls += 1
            if calls > budget:
                break
            if fails(chunk):
                items, n, reduced = chunk, 2, True
                break
        if not reduced and n > 2 and calls < budget:
            for chunk in chunks:
                rest = [i for i in items if i not in set(chunk)]
                calls += 1
                if calls > budget:
                    break
                if fails(rest):
                    items, n, reduced = rest, max(n - 1, 2), True
                    break
        if not reduced:
            if n >= len(items):
                break
            n = min(2 * n, len(items))
    return items


def _subcase(case: Case, keep: list[int], coordinates: NDArray | None = None, lattice: bool | None = None) -> Case:
    scene = case.scene.subset(keep)
    if coordinates is not None:
        scene = scene.with_coordinates(coordinates)
    remap = {int(t): k for k, t in enumerate(keep)}
    return Case(
        f"{case.id}/repro",
        scene,
        lattice=case.lattice if lattice is None else lattice,
        refusable=tuple(remap[t] for t in case.refusable if t in remap),
    )


def shrink(case: Case, fails: Callable[[Case], bool], budget: int = 200, seconds: float = 20.0) -> Case:
    """The smallest and simplest case on which ``fails`` still holds.

    First ddmin over triangles, then coarsening all coordinates to multiples of 2**-b for
    the smallest b (0..24) that still fails. ``budget`` bounds the calls of ``fails`` and
    ``seconds`` the time; the best case found so far is returned when either runs out.
    """
    deadline = time.monotonic() + seconds
    calls = 0

    def guarded(candidate: Case) -> bool:
        nonlocal calls
        if calls >= budget or time.monotonic() > deadline:
            return False
        calls += 1
        return fails(candidate)

    keep = ddmin(list(range(len(case.scene))), lambda sub: guarded(_subcase(case, sub)), budget)
    best = _subcase(case, keep)
    with np.errstate(all="ignore"):
        for bits in range(0, 25):
            p = best.scene.coordinates
            coarse = np.where(np.isfinite(p) & (np.abs(p) < 2.0**40), np.round(p * 2.0**bits) / 2.0**bits, p)
            if np.array_equal(coarse, p, equal_nan=True):
                break
            candidate = _subcase(best, list(range(len(best.scene))), coarse, lattice=best.lattice or bits <= 8)
            if guarded(candidate):
                best = Case(best.id, candidate.scene, lattice=candidate.lattice, refusable=best.refusable)
                break
    return best


def attach_repro(result: Result, case: Case, judge: Judge, rasterizer: Rasterizer,
                 budget: int = 60, seconds: float = 10.0) -> Result:
    """Shrink the case to a minimal one that still fails the same check and attach it, as
    replayable JSON naming that check, to the result's evidence. The result keeps the
    whole case's message; the repro file carries the check's own on the shrunk case, its
    evidence there (``evidence``) and what the rasterizer drew there (``answer``,
    :func:`answer_json`: a multisample answer whole), for its picture.

    Watertight's double hits shrink as ``overdraw``; its holes are cut down to the pieces
    around one of them as ``holes`` (:func:`hole_repro`), the whole case kept when that
    fails."""
    check = result.check
    start = case  # what is shrunk
    if check == "watertight" and result.metrics.get("double_hits", 0) > 0:
        check = "overdraw"  # double hits stay double hits in any subset of the triangles
    elif check == "watertight" and result.metrics.get("holes", 0) > 0:
        around = hole_repro(case, result, judge)  # the pieces around one hole, and a region as small
        if around is not None:
            check, start = "holes", around

    def failed(candidate: Case) -> Result | None:
        return next((r for r in judge(candidate, check) if r.check == check and r.status == "fail"), None)

    if check not in {c.name for c in checks.checks(only={check}) if c.shrinks}:
        minimal = start  # closed meshes need the whole case, a partition the pieces around its hole: no smaller one is valid
    else:
        minimal = shrink(start, lambda candidate: failed(candidate) is not None, budget=budget, seconds=seconds)
    evidence = dict(result.evidence)
    message = result.message  # the whole case's, for the result
    said = result.message  # the shrunk case's, for the repro file
    seen: Result | None = result  # the failure on the repro itself: what its picture shows
    if minimal is not case:
        seen = again = failed(minimal)
        if again is not None:
            said = again.message
    if check in ("conformance", "invariance"):
        as_received = input_precision_trial(minimal, check, judge, rasterizer)
        if as_received is not None:
            evidence["input_precision"] = as_received
            noun = f"{minimal.scene.noun}s"
            note = ("; with its coordinates rounded the way the library receives them (rasterizer.received), the "
                    f"same {noun} pass: the deviation comes from the input format ({as_received['moved']} "
                    "coordinates move), not from the convention")
            message, said = message + note, said + note
        inside = grown_screen_passes(minimal, check, judge)
        if inside is not None:
            evidence["viewport_edge"] = inside
            noun = f"{minimal.scene.noun}s"
            note = (f"; moved {inside['margin']} px into a screen {inside['margin']} px larger on each side, the same "
                    f"{noun} pass: the deviation appears only where {noun} cross the viewport edge")
            message, said = message + note, said + note
    payload = case_to_json(minimal, check=check, rasterizer=rasterizer.name, message=said,
                           original_case=case.id, original_triangles=len(case.scene), **_seen(seen))
    return replace(result, message=message, evidence={**evidence, "repro": payload})


def hole_repro(case: Case, result: Result, judge: Judge, tries: int = 4) -> Case | None:
    """A watertight failure's hole cut down to the partition's pieces around it: for one
    of the first holes it blames, the region becomes pixel (x, y) grown by a dyadic margin
    (1/4 px, halved until it lies wholly inside the partition's open region: exact), and
    the pieces those whose box meets it grown by a pixel -- every piece that covers part of
    it, snapped or not, so their union covers it and its pixel must be hit under any tie
    rule. Returned when the
    ``holes`` check (:func:`harness.checks.watertight.holes`) fails there; None when no
    blamed hole does (a rasterizer whose pieces' answers depend on each other).
    """
    if case.region is None:
        return None
    region = case.region
    m = region.shape[0]
    turns = orientation(np.stack([region, np.roll(region, -1, axis=0), np.roll(region, -2, axis=0)], axis=1))
    if not turns.any():
        return None
    area_sign = int(turns[np.flatnonzero(turns)[0]])

    def strictly_inside(points: NDArray[np.float64]) -> bool:
        for k in range(m):
            a = np.broadcast_to(region[k], points.shape)
            b = np.broadcast_to(region[(k + 1) % m], points.shape)
            if not np.all(orientation(np.stack([a, b, points], axis=1)) * area_sign > 0):
                return False
        return True

    blamed = [e["pixel"] for e in result.evidence.get("blame", []) if isinstance(e, dict) and e.get("kind") == "hole"]
    lo, hi, finite = case.scene.primitive_boxes()
    for x, y in blamed[:tries]:
        for bits in range(2, 21):
            margin = 2.0**-bits
            square = np.array([[x - margin, y - margin], [x + 1 + margin, y - margin], [x + 1 + margin, y + 1 + margin],
                               [x - margin, y + 1 + margin]], dtype=np.float64)
            if strictly_inside(square):
                break
        else:
            continue
        box_lo, box_hi = square[0] - 1.0, square[2] + 1.0  # a pixel more: snapping moves a vertex by at most half of one
        meets = finite & np.all(lo <= box_hi, axis=1) & np.all(hi >= box_lo, axis=1)
        keep = np.flatnonzero(meets).tolist()
        if not keep or len(keep) == len(case.scene):
            continue
        around = replace(_subcase(case, keep), id=f"{case.id}/repro", region=square)
        if any(r.check == "holes" and r.status == "fail" for r in judge(around, "holes")):
            return around
    return None


def whole_case_repro(result: Result, case: Case, rasterizer: str, note: str) -> Result:
    """The whole case attached as the repro, unshrunk, with the reason."""
    payload = case_to_json(case, check=result.check, rasterizer=rasterizer, message=result.message,
                           original_case=case.id, original_triangles=len(case.scene), note=note, **_seen(result))
    return replace(result, evidence={**result.evidence, "repro": payload})


MAX_ANSWER_FRAGMENTS = 20_000  # a repro file keeps the rasterizer's answer up to this many fragments


def answer_json(coverage: Coverage) -> dict[str, Any] | None:
    """A rasterizer's answer on a repro as JSON, to draw beside the convention's: its spans
    (``primitive``, ``y``, ``x0``, ``x1``), each span's ``sample`` index (multisample) and
    each pixel's ``alpha`` (area coverage), attributes left out; None beyond
    :data:`MAX_ANSWER_FRAGMENTS` fragments (or samples).

    >>> answer_json(Coverage([0], [2], [1], [3], alpha=[0.25, 1.0]))
    {'primitive': [0], 'y': [2], 'x0': [1], 'x1': [3], 'alpha': [0.25, 1.0]}
    """
    if int(np.maximum(coverage.x1 - coverage.x0, 0).sum()) > MAX_ANSWER_FRAGMENTS:
        return None
    out: dict[str, Any] = {name: getattr(coverage, name).tolist() for name in ("primitive", "y", "x0", "x1")}
    if coverage.sample is not None:
        out["sample"] = coverage.sample.tolist()
    if coverage.alpha is not None:
        out["alpha"] = [float(a) if np.isfinite(a) else str(a) for a in coverage.alpha.tolist()]
    return out


def answer_from_json(data: Any) -> Coverage | None:
    """The coverage :func:`answer_json` wrote; None for anything else (a file from
    elsewhere: a picture, not a verdict, depends on it).

    >>> answer_from_json(answer_json(Coverage([0, 1], [2, 2], [1, 4], [3, 5], sample=[0, 3]))).pixels()
    (array([0, 0, 1]), array([1, 2, 4]), array([2, 2, 2]))
    >>> answer_from_json({"primitive": [0]}) is None
    True
    """
    if not isinstance(data, dict):
        return None
    try:
        primitive, y, x0, x1 = (np.asarray(data[k], dtype=np.int64).reshape(-1) for k in ("primitive", "y", "x0", "x1"))
        alpha = data.get("alpha")
        return Coverage(primitive, y, x0, x1, sample=None if data.get("sample") is None else np.asarray(data["sample"], dtype=np.int64),
                        alpha=None if alpha is None else np.asarray(alpha, dtype=np.float64))
    except (KeyError, TypeError, ValueError):
        return None


def _json_safe(value: Any) -> Any:
    """Evidence as the results file writes it: non-finite floats as strings ("inf", "nan").

    >>> _json_safe({"d": [1.5, float("inf")]})
    {'d': [1.5, 'inf']}
    """
    if isinstance(value, float) and not np.isfinite(value):
        return str(value)
    if isinstance(value, dict):
        return {str(k): _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def _seen(result: Result | None) -> dict[str, Any]:
    """What a repro file keeps of the failure on the repro itself, for its picture: the
    rasterizer's answer (``answer``, :func:`answer_json`) and the check's evidence
    (``evidence``: the offending pixels, on the repro's own coordinates)."""
    if result is None:
        return {}
    out: dict[str, Any] = {"evidence": _json_safe({k: v for k, v in result.evidence.items()
                                                   if k not in ("repro", "repro_path", "traceback")})}
    drawing = result.drawing
    if drawing is not None and drawing.whole is not None:  # one sample's layer: the whole multisample answer
        drawing = drawing.whole
    if drawing is not None and drawing.coverages:
        answer = answer_json(drawing.coverages[0])
        if answer is not None:
            out["answer"] = answer
    return out


def _passes(case: Case, check: str, judge: Judge) -> bool:
    found = [r for r in judge(case, check) if r.check == check]
    return bool(found) and all(r.status == "pass" for r in found)


def input_precision_trial(case: Case | MotionCase, check: str, judge: Judge, rasterizer: Rasterizer) -> dict[str, Any] | None:
    """Whether a failing case (still, or a motion sequence: every frame) passes once its
    coordinates are rounded the way the library receives them, for a rasterizer that says
    how (an optional ``received(scene) -> Scene`` member, e.g. float32 positions at the GL
    API). Returns ``{"moved": n}`` (how many coordinates the rounding changed) when it
    then passes, else None."""
    received = received_of(rasterizer)
    scenes = [s for s in (case.frames if isinstance(case, MotionCase) else [case.scene]) if TRIANGLES.owns(s)]  # received() reads triangle scenes
    if received is None or not scenes or len(scenes) != (len(case.frames) if isinstance(case, MotionCase) else 1):
        return None
    try:
        rounded = [received(s) for s in scenes]
    except Exception:
        return None
    moved = sum(int(np.sum((s.coordinates != r.coordinates) & ~(np.isnan(s.coordinates) & np.isnan(r.coordinates))))
                for s, r in zip(scenes, rounded))
    if moved == 0:
        return None
    again = (replace(case, id=f"{case.id}/as-received", frames=tuple(rounded)) if isinstance(case, MotionCase)
             else replace(case, id=f"{case.id}/as-received", scene=rounded[0]))
    return {"moved": moved} if _passes(again, check, judge) else None  # type: ignore[arg-type]


def grown_screen(scene: AnyScene, margin: int, largest: int = 8192, rounding: bool = False) -> AnyScene | None:
    """The scene moved ``margin`` whole pixels right and down into a screen ``margin``
    pixels larger on every side -- an exact translation, so the same triangles cover the
    same samples, none of them crossing the viewport edge any more. None when the grown
    screen would exceed ``largest`` pixels a side or (unless ``rounding``) the move would
    round a coordinate; with ``rounding``, each moved coordinate is the float nearest
    (within half an ulp: only samples within float rounding of an edge can change)."""
    width, height = scene.width + 2 * margin, scene.height + 2 * margin
    if max(width, height) > largest:
        return None
    p = scene.coordinates
    moved = p + float(margin)
    with np.errstate(invalid="ignore", over="ignore"):
        if not rounding and not np.array_equal(moved - float(margin), p, equal_nan=True):
            return None
    return scene.with_coordinates(moved).with_viewport(width, height)


def grown_screen_passes(case: Case, check: str, judge: Judge, largest: int = 8192) -> dict[str, Any] | None:
    """Whether a failing case with vertices off-screen passes once the screen is grown
    (:func:`grown_screen`) so that nothing crosses the viewport edge.

    Returns ``{"margin": m, "screen": [w, h]}`` when the grown case passes ``check``, None
    when no vertex is off-screen, the case has a region, the grown screen would exceed
    ``largest`` pixels a side, or it still fails (the deviation is not the edge's).
    """
    trial = viewport_edge_trial(case, check, judge, largest)
    if trial is None or not trial.pop("passes"):
        return None
    return trial


def _same_shapes(scene: AnyScene, moved: AnyScene) -> bool:
    """Whether a rounded move kept every triangle's orientation (a sliver within rounding
    of flat may collapse or flip) and every segment's being a point or not. Exact."""
    kind = kind_of(scene)
    return moved.kind != kind.name or kind.keeps_shapes(scene, moved)


def viewport_edge_trial(case: Case, check: str, judge: Judge, largest: int = 8192) -> dict[str, Any] | None:
    """:func:`grown_screen_passes`'s trial, told either way: ``{"margin", "screen",
    "passes", "rounded"}`` when the grown case was checked (``passes`` False: it still
    fails, so the viewport edge is not the cause), None when the trial does not apply.
    Where the exact move would round a coordinate (floats of full precision, a screen or
    so off-screen), the move rounds (``rounded``): it changes only samples within float
    rounding of an edge, which the check's default tolerance excuses (both cases are judged
    so; a strictly read case that passes so has nothing to tell), so the verdict still
    tells the viewport edge's part from the rest -- without the trial a wrong sample near
    an off-screen edge could only be guessed at."""
    scene = case.scene
    lo, hi, finite = scene.primitive_boxes()
    if case.region is not None or not finite.any():
        return None
    over = max(0.0, float(-lo[finite, 0].min()), float(-lo[finite, 1].min()),
               float(hi[finite, 0].max() - scene.width), float(hi[finite, 1].max() - scene.height))
    if over == 0.0 or over > largest:
        return None
    margin = int(np.ceil(over)) + 8  # the invariance check's translation stays inside too
    grown = grown_screen(scene, margin, largest)
    rounded = grown is None
    if rounded:
        grown = grown_screen(scene, margin, largest, rounding=True)
        if grown is not None and not _same_shapes(scene, grown):
            return None  # a sliver within rounding of flat collapsed (or flipped): another scene
        if grown is not None and case.lattice and _passes(replace(case, lattice=False), check, judge):
            return None  # wrong only within rounding (a strict reading): the rounded move cannot tell
        case = replace(case, lattice=False)  # its roundings excused, as the original's were
    if grown is None:
        return None
    passes = _passes(replace(case, id=f"{case.id}/inside", scene=grown), check, judge)
    return {"margin": margin, "screen": [grown.width, grown.height], "passes": passes, "rounded": rounded}
