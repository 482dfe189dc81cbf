"""The runner: every rasterizer on every case of a suite, each call isolated.

Each rasterizer runs in a worker process of its own. An exception becomes an ``error``
result carrying the traceback; a call cut off by its time limit
(:class:`harness.isolation.TimeLimit`) is asked again once with a longer one, and one cut
off twice becomes a ``timeout`` error, the worker is replaced, and the run goes on. Results already computed
are never lost: ``on_result`` sees each one as soon as it exists.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import replace
from pathlib import Path



from cases.suites import suite as suite_cases
from harness.case import Case, MotionCase, read_case_file
from harness import checks, repro
from harness.api import (AnyScene, Coverage, LineScene, Rasterizer, Scene, Unsupported, convention_for, fingerprint_of,
                         interpolates_of, scene_kinds_of, takes)
from harness.causes import signed
from harness.declarations import answer_problem, declaration_problem, scene_kind_problem
from harness.checks import Drawing, Result, Tolerance

from harness.isolation import AnyCall, InProcess, Outcome, TimeLimit, Worker, describe, each_until_error
from harness.registry import distinct_names, load

__all__ = ["run_suite", "check_case", "check_motion", "replay", "nothing_checked"]


def _error(case: Case, rasterizer: str, outcome: Outcome, check: str = "run") -> Result:
    kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
    text = describe(outcome.error, kind=False)
    return Result(rasterizer, case.id, check, "error", f"{kind}: {text}",
                  {"seconds": outcome.seconds}, {"traceback": outcome.traceback})


def _refusal(case: Case | MotionCase, rasterizer: Rasterizer, scene: AnyScene, outcome: Outcome,
             refused: dict[str, str] | None, frame: int | None = None) -> Result | None:
    """The one error result of an answer (or error) that contradicts what the rasterizer
    declares (:mod:`harness.declarations`), recorded in ``refused`` under the scene kind so
    that no more scenes of that kind are handed to it; None when nothing contradicts."""
    if outcome.coverage is not None:
        problem = answer_problem(convention_for(rasterizer, scene) if fingerprint_of(rasterizer) is None else None,
                                 outcome.received if outcome.received is not None else outcome.coverage)
    else:
        problem = scene_kind_problem(rasterizer, scene, outcome.error)
    if problem is None:
        return None
    where = "" if frame is None else f" (frame {frame})"
    message = f"{problem}; its answer on {case.id}{where} was its last: no more {scene.kind} were handed to it"
    if refused is not None:
        refused[scene.kind] = message
    return Result(rasterizer.name, case.id, "run", "error", message, {"seconds": outcome.seconds},
                  {"refused": scene.kind})


def check_case(case: Case, rasterizer: Rasterizer, call: AnyCall,
               tolerance: Tolerance = Tolerance(), invariance: bool = True,
               only: set[str] | None = None, refused: dict[str, str] | None = None) -> list[Result]:
    """All applicable checks of one rasterizer on one case (or those named in ``only``;
    when none of them applies, the rasterizer is not called and there is no result).

    ``refused`` (scene kind -> message) holds the scene kinds whose answers contradicted
    the rasterizer's declaration: such a scene is not handed to it (no result), and an
    answer that contradicts it adds its kind and gives the one error result saying so."""
    name = rasterizer.name
    if not takes(rasterizer, case.scene):
        return []  # a scene kind (or fill rule) it does not take: not handed to it
    if refused is not None and case.scene.kind in refused:
        return []  # its answers contradicted its declaration already: said once, not per case
    convention = convention_for(rasterizer, case.scene)
    kind = convention.kind if convention is not None else "single"
    applicable = [check for check in checks.checks(case, only, kind) if invariance or check.name != "invariance"]
    if not applicable:
        return []
    outcome = call(case.scene)
    contradiction = _refusal(case, rasterizer, case.scene, outcome, refused)
    if contradiction is not None:
        return [contradiction]
    if outcome.coverage is None:
        if isinstance(outcome.error, Unsupported):  # cannot draw this scene as given: it says so
            return [Result(name, case.id, "run", "skip", f"unsupported: {outcome.error}", {"seconds": outcome.seconds})]
        declined = checks.refusal(case, outcome.error) if outcome.error is not None else None
        if declined is not None:
            return [replace(declined, rasterizer=name)]
        return [_error(case, name, outcome)]
    coverage = outcome.coverage
    subject = checks.Subject(case, name, convention, [coverage], call, tolerance, interpolates_of(rasterizer), outcome.seconds,
                             received=[outcome.received if outcome.received is not None else coverage],
                             scene_kinds=scene_kinds_of(rasterizer))
    results = [check.verdict(subject) for check in applicable]
    drawing = Drawing.of(subject)  # references only (and the oracle if a check computed it): the report draws
    return [_retried(replace(r, rasterizer=name, metrics={**r.metrics, "seconds": outcome.seconds},
                             drawing=(r.drawing or drawing) if r.status == "fail" else None), [outcome]) for r in results]


def _retried(result: Result, outcomes: Sequence[Outcome]) -> Result:
    """``result``, its evidence saying which of the calls behind it were cut off by their time
    limit and answered only when asked again (``retried``), when any were."""
    said = [o.retry_text if len(outcomes) == 1 else f"frame {f}: {o.retry_text}"
            for f, o in enumerate(outcomes) if o.retried is not None]
    return replace(result, evidence={**result.evidence, "retried": "; ".join(said)}) if said else result


def check_motion(case: MotionCase, rasterizer: Rasterizer, call: Callable[[Scene], Outcome],
                 tolerance: Tolerance = Tolerance(), only: set[str] | None = None,
                 call_all: Callable[[list[Scene]], list[Outcome]] | None = None,
                 refused: dict[str, str] | None = None) -> list[Result]:
    """The motion checks of one rasterizer on one frame sequence (or those named in
    ``only``; when none of them applies, no frame is drawn and there is no result).
    ``refused`` as for :func:`check_case`."""
    name = rasterizer.name
    if not case.frames or not takes(rasterizer, case.frames[0]):
        return []  # triangles it does not take (a line drawer): not handed to it
    if refused is not None and case.frames[0].kind in refused:
        return []
    convention = rasterizer.convention
    applicable = checks.checks(case, only, convention.kind if convention is not None else "single")
    if not applicable:
        return []
    coverages = []
    seconds = 0.0
    frames = list(case.frames)
    # every frame in one go when the caller can (a worker draws the next frame while this
    # process reads the last), else one call each; either way up to the first error
    outcomes = call_all(frames) if call_all is not None else each_until_error(call, frames)
    for f, outcome in enumerate(outcomes):
        scene = frames[f]
        contradiction = _refusal(case, rasterizer, scene, outcome, refused, frame=f)
        if contradiction is not None:
            return [contradiction]
        if outcome.coverage is None:
            failed = _error(Case(case.id, scene), name, outcome)
            return [replace(failed, message=f"frame {f}: {failed.message}")]
        coverages.append(outcome.coverage)
        seconds += outcome.seconds
    subject = checks.Subject(case, name, convention, coverages, call, tolerance, interpolates_of(rasterizer), seconds)
    results = [check.verdict(subject) for check in applicable]
    drawing = Drawing.of(subject)
    return [_retried(replace(r, rasterizer=name, metrics={**r.metrics, "seconds": seconds},
                             drawing=(r.drawing or drawing) if r.status == "fail" else None), outcomes) for r in results]


def _qualified(result: Result, rasterizer: Rasterizer, case: Case | MotionCase) -> Result:
    """A convention-bound failure of a rasterizer checked against a convention that was
    only guessed (identified with a residual, never declared) says so: it shows where the
    rasterizer departs from the nearest convention, not a rule it broke. A line case is
    judged by the line fit (its own residual), any other by the triangle (path) one."""
    fingerprint = fingerprint_of(rasterizer)
    bound = {c.name for c in checks.checks() if c.needs_convention}
    if fingerprint is None or result.check not in bound or result.status != "fail":
        return result
    line_fit = getattr(fingerprint, "line_fit", None)
    if isinstance(case, Case) and isinstance(case.scene, LineScene) and line_fit is not None:
        exact, residual, what = line_fit.exact, line_fit.residual, "line convention"
    else:
        exact, residual, what = fingerprint.exact, fingerprint.residual, "convention"
    if exact:
        return result
    unanswered = getattr(fingerprint, "unanswered", 0)
    why = (f"; {unanswered} of its fit scenes went unanswered: calls failed" if unanswered and what == "convention" else "")
    return replace(result, message=(f"against the best-guess {what} (declared by nobody; identify's residual "
                                    f"{residual} px{why}): {result.message}"))


def run_suite(
    rasterizers: Iterable[Rasterizer | str],
    suite: str = "quick",
    seed: int = 0,
    *,
    cases: Sequence[Case | MotionCase] | None = None,
    tolerance: Tolerance = Tolerance(),
    timeout: float | TimeLimit = 60.0,
    isolate: bool = True,
    repros: bool = True,
    repro_seconds: float = 120.0,
    on_result: Callable[[Result], None] | None = None,
    identify: bool = True,
    only: set[str] | None = None,
    rerun: int = 0,
    stop: threading.Event | None = None,
    deadline: float | None = None,
    on_case: Callable[[str, str], None] | None = None,
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
    timeout : float or TimeLimit
        The time-limit policy of one rasterize call (:class:`harness.isolation.TimeLimit`;
        a number is its cap, in seconds): a call cut off by its limit is asked again once
        with a longer one, and only then is it a ``timeout`` error.
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
    only : set of str, optional
        Run only the checks of these names (see :func:`harness.checks.check_names`).
    rerun : int
        Rerun each failing or erroring check this many times; one whose status changes
        is marked flaky (``evidence["flaky"]``) and not shrunk.
    stop : threading.Event, optional
        Set from another thread (Ctrl-C) to end the run after the case in progress; the
        results of that case are dropped (a killed worker's answers are no verdicts).
    deadline : float, optional
        A ``time.monotonic()`` after which no case starts; each case left is an error
        result ("not run"), so that a capped run never passes.
    on_case : callable, optional
        Called with the rasterizer's name and the case's id once every result of that
        case is given to ``on_result`` (also when it gave none; never for a case cut
        short or not run): what the run journal (:mod:`harness.journal`) marks complete.

    Returns
    -------
    list of Result
        Records with ``rasterizer``, ``case``, ``check``, ``status``, ``message``,
        ``metrics`` and ``evidence``; a failing or erroring one's evidence names its
        ``signature`` (:func:`harness.causes.signed`), which
        :func:`harness.causes.by_cause` groups by. A rasterizer whose answers on a scene
        kind contradict its declared convention (:func:`harness.declarations.answer_problem`)
        has one error result for that kind, ``evidence["refused"]`` naming it, and is
        handed no more scenes of the kind.

    Raises
    ------
    ValueError
        In one line naming it, for a rasterizer that cannot be loaded or whose
        declarations contradict each other (:func:`harness.declarations.declaration_problem`).
    """
    selected = list(cases) if cases is not None else suite_cases(suite, seed)
    results: list[Result] = []
    loaded = distinct_names([load(spec) if isinstance(spec, str) else _declared(spec) for spec in rasterizers])
    if identify:
        from harness.identify import identify_all

        loaded, _ = identify_all(loaded, seed, call_timeout=timeout)
    for rasterizer in loaded:
        worker: Worker | InProcess = Worker(rasterizer, timeout) if isolate else InProcess(rasterizer)
        call = worker.rasterize
        refused: dict[str, str] = {}  # scene kinds whose answers contradicted its declaration

        def one_case(case: Case | MotionCase, only: set[str] | None, rasterizer: Rasterizer = rasterizer, call: AnyCall = call,
                     call_all: Callable[[list[Scene]], list[Outcome]] = worker.rasterize_all,
                     refused: dict[str, str] = refused) -> list[Result]:
            if isinstance(case, MotionCase):
                return check_motion(case, rasterizer, call, tolerance, only, call_all, refused)
            return check_case(case, rasterizer, call, tolerance, only=only, refused=refused)

        def judge(candidate: Case | MotionCase, check: str, one_case: Callable[..., list[Result]] = one_case) -> list[Result]:
            return one_case(candidate, {check})

        def answered(still: Case, drawn: Coverage, check: str, rasterizer: Rasterizer = rasterizer) -> list[Result]:
            """The one check on ``still``, judged on ``drawn`` (an answer the run has): no call."""
            return check_case(still, rasterizer, lambda scene: Outcome(drawn), tolerance, only={check})

        shrink_until = time.monotonic() + repro_seconds
        try:
            for k, case in enumerate(selected):
                if stop is not None and stop.is_set():
                    break
                if deadline is not None and time.monotonic() > deadline:
                    results += _not_run(selected[k:], rasterizer.name, "the run's time budget was used up", on_result)
                    break
                found = one_case(case, only)
                if rerun:
                    found = [_rerun(r, case, one_case, rerun) if r.status in ("fail", "error") and "refused" not in r.evidence
                             else r for r in found]
                if stop is not None and stop.is_set():
                    break  # the case was cut short by the stop: its results are not to be trusted
                for result in found:
                    if repros and result.status == "fail" and isinstance(case, Case) and "flaky" not in result.evidence:
                        if time.monotonic() < shrink_until:
                            result = repro.attach_repro(result, case, judge, rasterizer)
                        else:  # budget used up: the whole case is the repro
                            result = repro.whole_case_repro(result, case, rasterizer.name,
                                                            "not shrunk: the shrinking time budget was used up")
                    result = signed(_qualified(result, rasterizer, case), case, rasterizer, judge, answered)
                    results.append(result)
                    if on_result is not None:
                        on_result(result)
                if on_case is not None:
                    on_case(rasterizer.name, case.id)
        finally:
            worker.close()
    return results


def _declared(rasterizer: Rasterizer) -> Rasterizer:
    """A rasterizer object whose declarations agree, as :func:`harness.registry.load`
    checks a spec's; ValueError naming it in one line otherwise."""
    problem = declaration_problem(rasterizer)
    if problem is not None:
        raise ValueError(f"{getattr(rasterizer, 'name', rasterizer)!s}: {problem}")
    return rasterizer


def _not_run(cases: Sequence[Case | MotionCase], rasterizer: str, why: str,
             on_result: Callable[[Result], None] | None) -> list[Result]:
    """An error result for each case that was not run, saying why: a run cut short never
    passes silently."""
    out = [Result(rasterizer, c.id, "run", "error", f"not run: {why}") for c in cases]
    for result in out:
        if on_result is not None:
            on_result(result)
    return out


def _rerun(result: Result, case: Case | MotionCase, one_case: Callable[[Case | MotionCase, set[str] | None], list[Result]],
           times: int) -> Result:
    """Rerun the check behind an unexpected result ``times`` times; when the status
    changes, the result is marked flaky (``evidence["flaky"]``: the statuses seen, first
    the original) and its message says so: a flake is not a regression."""
    statuses: list[str] = [result.status]
    only = None if result.check == "run" else {result.check}
    for _ in range(times):
        again = [r for r in one_case(case, only) if r.check == result.check]
        statuses.append(again[0].status if again else "missing")
    if len(set(statuses)) == 1:
        return replace(result, evidence={**result.evidence, "reruns": statuses})
    return replace(result, message=f"flaky ({' / '.join(statuses)} over {times + 1} runs): {result.message}",
                   evidence={**result.evidence, "flaky": statuses})


def replay(path: Path | str, rasterizer: Rasterizer | str, isolate: bool = False, identify: bool = True,
           timeout: float | TimeLimit = 60.0) -> list[Result]:
    """Replay a saved case (:func:`harness.case.save_case`, or a repro from a run): the
    check it names (plus hygiene), or, when it names none, every check that applies."""
    case, extra = read_case_file(path)
    named = extra.get("check")
    known = isinstance(named, str) and bool(checks.checks(only={named}))  # on-request ones (overdraw) too
    only = {str(named), "hygiene"} if known else None
    return run_suite([rasterizer], cases=[case], isolate=isolate, identify=identify, repros=False, only=only,
                     timeout=timeout)


def _first_scene(case: Case | MotionCase) -> AnyScene | None:
    if isinstance(case, MotionCase):
        return case.frames[0] if case.frames else None
    return case.scene


def nothing_checked(rasterizer: Rasterizer, results: Sequence[Result], cases: Sequence[Case | MotionCase]) -> str | None:
    """Why no check judged ``rasterizer`` on ``cases``, in one line naming it, or None when
    at least one check passed or failed on an answer of its: a run, a replay or a gate
    that checked nothing must never pass.

    The reasons: none of the cases is of a scene kind it takes (nor, for paths, under a
    fill rule it honours); no selected check applies to them; every call failed (an
    error, a crash, a time-out: no answer to judge); its time budget ran out first; every
    case was skipped (``Unsupported`` for each, or a skip list); else a mixture of these.

    Examples
    --------
    >>> from harness.api import Scene
    >>> from harness.case import Case
    >>> class Lines:
    ...     name, convention, scene_kinds = "lines_only", None, ("lines",)
    >>> print(nothing_checked(Lines(), [], [Case("lattice/one", Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]))]))
    lines_only: nothing checked: none of the 1 selected cases is of a scene kind it takes (scene_kinds=('lines',))
    """
    name = rasterizer.name
    mine = [r for r in results if r.rasterizer == name]
    if any(r.status in ("pass", "fail") for r in mine):
        return None
    head = f"{name}: nothing checked"
    if not mine:
        handed = [c for c in cases if (scene := _first_scene(c)) is not None and takes(rasterizer, scene)]
        if not handed:
            kinds = scene_kinds_of(rasterizer)
            rules = getattr(rasterizer, "fill_rules", None)
            said = f"scene_kinds={kinds!r}" + (f", fill_rules={tuple(rules)!r}" if "paths" in kinds and rules is not None else "")
            if not cases:
                return f"{head}: no case was selected"
            return f"{head}: none of the {len(cases)} selected cases is of a scene kind it takes ({said})"
        return f"{head}: no selected check applies to the {len(handed)} cases of the kinds it takes"
    errors = [r for r in mine if r.status == "error"]
    skips = [r for r in mine if r.status == "skip"]
    refused = [r for r in errors if "refused" in r.evidence]
    if refused:
        return f"{head}: {refused[0].message}"[:400]
    if errors and not skips:
        not_run = [r for r in errors if r.message.startswith("not run")]
        if len(not_run) == len(errors):
            return f"{head}: {not_run[0].message.removeprefix('not run: ')} before any of its {len(errors)} cases started"
        calls = len({r.case for r in errors})
        return f"{head}: every one of its {calls} calls failed: {errors[0].message}"[:400]
    if skips and not errors:
        return f"{head}: every one of its {len(skips)} cases was skipped, e.g. {skips[0].case}: {skips[0].message}"[:400]
    return (f"{head}: of its {len({r.case for r in mine})} cases, {len(skips)} were skipped and {len(errors)} gave no answer "
            f"(e.g. {errors[0].case}: {errors[0].message})")[:400]
