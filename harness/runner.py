"""The runner: every rasterizer on every case of a suite, each call isolated.

Each rasterizer runs in a worker process of its own. An exception becomes an ``error``
result carrying the traceback; a call that outlives the per-case time limit becomes a
``timeout`` error, the worker is replaced, and the run goes on. Results already computed
are never lost: ``on_result`` sees each one as soon as it exists.
"""

from __future__ import annotations

import multiprocessing
import time
import traceback
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from cases.records import Case
from cases.suites import suite as suite_cases
from cases.motion import MotionCase
from harness import checks, pictures, repro
from harness.api import Coverage, Rasterizer, Scene
from harness.checks import Result, Tolerance
from harness.oracle import exact_coverage
from harness.registry import distinct_names, load

__all__ = ["run_suite", "Worker", "Outcome"]


@dataclass(frozen=True, slots=True)
class Outcome:
    """What one rasterize call gave: a coverage, or an error (with its traceback)."""

    coverage: Coverage | None
    error: BaseException | None = None
    traceback: str = ""
    seconds: float = 0.0
    timed_out: bool = False


def _call(rasterizer: Rasterizer, scene: Scene) -> Outcome:
    start = time.perf_counter()
    try:
        coverage = rasterizer.rasterize(scene)
        if not isinstance(coverage, Coverage):
            raise TypeError(f"rasterize returned {type(coverage).__name__}, not a harness.Coverage")
    except Exception as exc:
        return Outcome(None, exc, traceback.format_exc(), time.perf_counter() - start)
    return Outcome(coverage, seconds=time.perf_counter() - start)


def _serve(rasterizer: Rasterizer, conn: Any) -> None:  # pragma: no cover - runs in the child
    while True:
        try:
            scene = conn.recv()
        except EOFError:
            return
        outcome = _call(rasterizer, scene)
        try:
            conn.send(outcome)
        except Exception as exc:  # an unpicklable exception: send its text instead
            conn.send(Outcome(None, RuntimeError(f"{type(outcome.error).__name__}: {outcome.error}"), outcome.traceback, outcome.seconds))
            del exc


class Worker:
    """A rasterizer in a forked process of its own, called with a time limit."""

    def __init__(self, rasterizer: Rasterizer) -> None:
        self.rasterizer = rasterizer
        self._context = multiprocessing.get_context("fork")
        self._start()

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._process = self._context.Process(target=_serve, args=(self.rasterizer, child), daemon=True)
        self._process.start()
        child.close()

    def rasterize(self, scene: Scene, timeout: float) -> Outcome:
        start = time.perf_counter()
        try:
            self._conn.send(scene)
            if self._conn.poll(timeout):
                return self._conn.recv()
        except (EOFError, BrokenPipeError, ConnectionResetError):
            self._process.join(1)
            code = self._process.exitcode
            self._start()
            return Outcome(None, RuntimeError(f"the rasterizer's worker process died (exit code {code})"), "", time.perf_counter() - start)
        self.close()
        self._start()
        return Outcome(None, TimeoutError(f"no answer within {timeout:g} s"), "", timeout, timed_out=True)

    def close(self) -> None:
        if self._process.is_alive():
            self._process.kill()
        self._process.join(5)
        self._conn.close()


def interpolates(rasterizer: Rasterizer) -> bool:
    """Whether the rasterizer interpolates attributes: an optional member, True unless it
    says ``interpolates = False`` (coverage-only libraries such as cairo or skia)."""
    return bool(getattr(rasterizer, "interpolates", True))


def _error(case: Case, rasterizer: str, outcome: Outcome, check: str = "run") -> Result:
    kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
    return Result(rasterizer, case.id, check, "error", f"{kind}: {outcome.error}",
                  {"seconds": outcome.seconds}, {"traceback": outcome.traceback})


def check_case(case: Case, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
               tolerance: Tolerance = Tolerance(), invariance: bool = True,
               only: set[str] | None = None) -> list[Result]:
    """All applicable checks of one rasterizer on one case (or those named in ``only``)."""
    name = rasterizer.name
    convention = rasterizer.convention
    outcome = call(case.scene)
    if outcome.coverage is None:
        refused = checks.refusal(case, outcome.error) if outcome.error is not None else None
        if refused is not None:
            return [replace(refused, rasterizer=name)]
        return [_error(case, name, outcome)]
    coverage = outcome.coverage
    subject = checks.Subject(case, name, convention, [coverage], call, tolerance, interpolates(rasterizer), outcome.seconds)
    results = [check.verdict(subject) for check in checks.checks(case, only)
               if invariance or check.name != "invariance"]
    for i, r in enumerate(results):
        evidence = r.evidence
        if r.status == "fail" and only is None:
            evidence = {**evidence, "images": _pictures(case, coverage, convention, r)}
        results[i] = replace(r, rasterizer=name, evidence=evidence, metrics={**r.metrics, "seconds": outcome.seconds})
    return results


def _focus(result: Result) -> list[tuple[int, int]]:
    """The offending pixels a failure names, first the most telling."""
    e = result.evidence
    if "pixels" in e and e["pixels"] and isinstance(e["pixels"][0], dict):
        return [(p["x"], p["y"]) for p in e["pixels"]]
    if "blame" in e:
        return [tuple(b["pixel"]) for b in e["blame"]]
    for key in ("strays", "pixels"):
        if e.get(key):
            return [(int(p[0]), int(p[1])) for p in e[key]]
    for key in ("rotate-vertices", "flip-winding", "permute-triangles", "translate"):
        if e.get(key):
            return [(int(p[1]), int(p[2])) for p in e[key]]
    return []


def _pictures(case: Case, coverage: Coverage, convention: Any, result: Result) -> dict[str, str]:
    """Heat map, oracle diff and an SVG crop around the first offending pixel."""
    scene = case.scene
    marks = _focus(result)
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    window = pictures.window_around(int(fx), int(fy), scene.width, scene.height, 64)
    counts = coverage.counts(scene.width, scene.height)
    holes = strays = None
    if case.region is not None:
        inside, outside = checks.pixel_classes(case.region, scene.width, scene.height)
        holes, strays = inside & (counts == 0), outside & (counts > 0)
    images = {"heatmap": pictures.heatmap(counts, holes, strays, window)}
    if convention is not None:
        oracle = exact_coverage(scene, convention)
        images["diff"] = pictures.oracle_diff(scene.width, scene.height, counts > 0, oracle.counts(scene.width, scene.height) > 0,
                                              result.evidence.get("pixels", []) if result.check == "conformance" else [], window)
    crop = pictures.window_around(int(fx), int(fy), scene.width, scene.height, 12)
    sample = convention.sample if convention is not None else (0.5, 0.5)
    images["crop"] = pictures.svg_crop(scene.positions, coverage, sample, crop, [(int(x), int(y)) for x, y in marks[:20]])
    return images


def check_motion(case: MotionCase, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
                 tolerance: Tolerance = Tolerance()) -> list[Result]:
    """The motion checks of one rasterizer on one frame sequence."""
    name = rasterizer.name
    convention = rasterizer.convention
    coverages = []
    seconds = 0.0
    for f, scene in enumerate(case.frames):
        outcome = call(scene)
        if outcome.coverage is None:
            failed = _error(Case(case.id, scene), name, outcome)
            return [replace(failed, message=f"frame {f}: {failed.message}")]
        coverages.append(outcome.coverage)
        seconds += outcome.seconds
    subject = checks.Subject(case, name, convention, coverages, call, tolerance, interpolates(rasterizer), seconds)
    results = [check.verdict(subject) for check in checks.checks(case)]
    oracles = subject.oracles if convention is not None else []
    first = case.frames[0]
    out = []
    for r in results:
        evidence = r.evidence
        if r.status == "fail":
            marks = [*evidence.get("backward_jumps", []), *evidence.get("mismatches", []), *evidence.get("backward_steps", [])]
            evidence = {**evidence, "animation": pictures.motion_animation(coverages, oracles, first.width, first.height, marks, case.texels)}
            if "series" in evidence:
                evidence["plot"] = pictures.series_plot(evidence["series"])
        out.append(replace(r, rasterizer=name, evidence=evidence, metrics={**r.metrics, "seconds": seconds}))
    return out


def attach_repro(result: Result, case: Case, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
                 tolerance: Tolerance, budget: int = 60, seconds: float = 10.0) -> Result:
    """Shrink the case to a minimal one that still fails the same check and attach it, as
    replayable JSON, to the result's evidence."""
    check = result.check
    if check == "watertight" and result.metrics.get("double_hits", 0) > 0:
        check = "overdraw"  # double hits stay double hits in any subset of the triangles
    if check not in {c.name for c in checks.checks(only={check}) if c.shrinks}:
        minimal = case  # holes and closed meshes need the whole case: no smaller one is valid
    else:
        def fails(candidate: Case) -> bool:
            found = check_case(candidate, rasterizer, call, tolerance, only={check})
            return any(r.check == check and r.status == "fail" for r in found)

        minimal = repro.shrink(case, fails, budget=budget, seconds=seconds)
    evidence = dict(result.evidence)
    message = result.message
    if check in ("conformance", "invariance"):
        as_received = input_precision_probe(minimal, check, rasterizer, call, tolerance)
        if as_received is not None:
            evidence["input_precision"] = as_received
            message += ("; with its coordinates rounded the way the library receives them (rasterizer.received), the "
                        f"same triangles pass: the deviation comes from the input format ({as_received['moved']} "
                        "coordinates move), not from the fill rule")
        inside = viewport_edge_probe(minimal, check, rasterizer, call, tolerance)
        if inside is not None:
            evidence["viewport_edge"] = inside
            message += (f"; moved {inside['margin']} px into a screen {inside['margin']} px larger on each side, the same "
                        "triangles pass: the deviation appears only where triangles cross the viewport edge")
    payload = repro.case_to_json(minimal, check=check, rasterizer=rasterizer.name, message=message,
                                 original_case=case.id, original_triangles=len(case.scene))
    return replace(result, message=message, evidence={**evidence, "repro": payload})


def input_precision_probe(case: Case, check: str, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
                          tolerance: Tolerance) -> dict[str, Any] | None:
    """Whether a failing case passes once its coordinates are rounded the way the library
    receives them, for a rasterizer that says how (an optional ``received(scene) -> Scene``
    member, e.g. float32 positions at the GL API). Returns ``{"moved": n}`` (how many
    coordinates the rounding changed) when it then passes, else None."""
    received = getattr(rasterizer, "received", None)
    if received is None:
        return None
    try:
        scene = received(case.scene)
    except Exception:
        return None
    before, after = case.scene.positions, scene.positions
    moved = int(np.sum((before != after) & ~(np.isnan(before) & np.isnan(after))))
    if moved == 0:
        return None
    return {"moved": moved} if _passes(replace(case, id=f"{case.id}/as-received", scene=scene), check, rasterizer, call, tolerance) else None


def viewport_edge_probe(case: Case, check: str, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
                        tolerance: Tolerance, largest: int = 8192) -> dict[str, Any] | None:
    """Whether a failing case with vertices off-screen passes once the screen is grown by a
    whole-pixel margin on every side and its triangles moved by that margin (an exact
    translation), so that nothing crosses the viewport edge any more.

    Returns ``{"margin": m, "screen": [w, h]}`` when the grown case passes ``check``, None
    when no vertex is off-screen, the case has a region, the grown screen would exceed
    ``largest`` pixels a side, or it still fails (the deviation is not the edge's).
    """
    scene = case.scene
    p = scene.positions
    finite = np.isfinite(p).all(axis=(1, 2))
    if case.region is not None or not finite.any():
        return None
    q = p[finite]
    over = max(0.0, float(-q[..., 0].min()), float(-q[..., 1].min()),
               float(q[..., 0].max() - scene.width), float(q[..., 1].max() - scene.height))
    if over == 0.0:
        return None
    if over > largest:
        return None
    margin = int(np.ceil(over)) + 8  # the invariance check's translation stays inside too
    width, height = scene.width + 2 * margin, scene.height + 2 * margin
    if max(width, height) > largest:
        return None
    moved = p + float(margin)
    with np.errstate(invalid="ignore", over="ignore"):
        if not np.array_equal(moved - float(margin), p, equal_nan=True):
            return None
    grown = replace(case, id=f"{case.id}/inside", scene=Scene(width, height, moved, scene.attributes, scene.w))
    return {"margin": margin, "screen": [width, height]} if _passes(grown, check, rasterizer, call, tolerance) else None


def _passes(case: Case, check: str, rasterizer: Rasterizer, call: Callable[[Scene], Outcome], tolerance: Tolerance) -> bool:
    found = [r for r in check_case(case, rasterizer, call, tolerance, only={check}) if r.check == check]
    return bool(found) and all(r.status == "pass" for r in found)


def _qualified(result: Result, rasterizer: Rasterizer) -> Result:
    """A convention-bound failure of a rasterizer checked against a convention that was
    only guessed (identified with a residual, never declared) says so: it shows where the
    rasterizer departs from the nearest convention, not a rule it broke."""
    fingerprint = getattr(rasterizer, "fingerprint", None)
    bound = {c.name for c in checks.checks() if c.needs_convention}
    if fingerprint is None or fingerprint.exact or result.check not in bound or result.status != "fail":
        return result
    return replace(result, message=(f"against the best-guess convention (declared by nobody; identify's residual "
                                    f"{fingerprint.residual} px): {result.message}"))


def run_suite(
    rasterizers: Iterable[Rasterizer | str],
    suite: str = "quick",
    seed: int = 0,
    *,
    cases: list[Case | MotionCase] | None = None,
    tolerance: Tolerance = Tolerance(),
    timeout: float = 60.0,
    isolate: bool = True,
    repros: bool = True,
    repro_seconds: float = 120.0,
    on_result: Callable[[Result], None] | None = None,
    identify: bool = True,
) -> list[Result]:
    """Run a suite's checks on each rasterizer.

    Parameters
    ----------
    rasterizers : rasterizer objects or specs (see :func:`harness.registry.load`)
    suite : {"quick", "full"}
    seed : int
    cases : list of Case, optional
        Run these instead of the suite's.
    tolerance : Tolerance
    timeout : float
        Seconds one rasterize call may take before it counts as hung.
    isolate : bool
        Run each rasterizer in a worker process (default); False calls it in-process
        (no time limit), for debugging.
    repros : bool
        Shrink each failing case to a minimal replayable one (evidence ``repro``).
    repro_seconds : float
        Time budget for shrinking, per rasterizer; failures past it keep their whole case
        as the repro, and say so.
    on_result : callable, optional
        Called with each result as soon as it exists.
    identify : bool
        Identify each rasterizer that declares no convention first (as ``rastercheck
        run`` does) and check it against the convention identified for it; False runs it
        without one (its convention-bound checks skip).

    Returns
    -------
    list of Result
        Records with ``rasterizer``, ``case``, ``check``, ``status``, ``message``,
        ``metrics`` and ``evidence``.
    """
    selected = cases if cases is not None else suite_cases(suite, seed)
    results: list[Result] = []
    loaded = distinct_names([load(spec) if isinstance(spec, str) else spec for spec in rasterizers])
    if identify:
        from harness.identify import identify_all

        loaded, _ = identify_all(loaded, seed, call_timeout=timeout)
    for rasterizer in loaded:
        worker = Worker(rasterizer) if isolate else None
        call = (lambda scene, w=worker: w.rasterize(scene, timeout)) if worker else (lambda scene, r=rasterizer: _call(r, scene))
        shrink_until = time.monotonic() + repro_seconds
        try:
            for case in selected:
                if isinstance(case, MotionCase):
                    for result in check_motion(case, rasterizer, call, tolerance):
                        result = _qualified(result, rasterizer)
                        results.append(result)
                        if on_result is not None:
                            on_result(result)
                    continue
                for result in check_case(case, rasterizer, call, tolerance):
                    if repros and result.status == "fail":
                        if time.monotonic() < shrink_until:
                            result = attach_repro(result, case, rasterizer, call, tolerance)
                        else:  # budget used up: the whole case is the repro
                            payload = repro.case_to_json(case, check=result.check, rasterizer=rasterizer.name, message=result.message,
                                                         original_case=case.id, original_triangles=len(case.scene),
                                                         note="not shrunk: the shrinking time budget was used up")
                            result = replace(result, evidence={**result.evidence, "repro": payload})
                    result = _qualified(result, rasterizer)
                    results.append(result)
                    if on_result is not None:
                        on_result(result)
        finally:
            if worker is not None:
                worker.close()
    return results
