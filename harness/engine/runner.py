"""The runner: every rasterizer on every case of a suite, each call isolated.

Each rasterizer runs in a worker process of its own, through a
:class:`harness.engine.session.Session` (which also holds the checks of one case,
:func:`check_case` and :func:`check_motion`, named here too). An exception becomes an
``error`` result carrying the traceback; a call cut off by its time limit
(:class:`harness.engine.isolation.TimeLimit`) is asked again once with a longer one, and one cut
off twice becomes a ``timeout`` error, the worker is replaced, and the run goes on. Results
already computed are never lost: ``on_result`` sees each one as soon as it exists.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import replace
from pathlib import Path

from cases.suites import suite as suite_cases
from harness import checks
from harness.checks import Result, Tolerance
from harness.contract.case import Case, MotionCase, read_case_file
from harness.contract.declarations import declaration_problem
from harness.contract.protocol import Rasterizer, fingerprint_of, scene_kinds_of, takes
from harness.contract.scenes import AnyScene
from harness.diagnose import repro
from harness.diagnose.causes import signed
from harness.engine.isolation import TimeLimit
from harness.engine.registry import distinct_names, load
from harness.engine.session import Session, _error, check_case, check_motion  # noqa: F401 (check_case, _error: this module's names too)
from harness.kinds import kind_of

__all__ = ["run_suite", "run_session", "declared", "check_case", "check_motion", "replay", "nothing_checked"]


def _qualified(result: Result, rasterizer: Rasterizer, case: Case | MotionCase) -> Result:
    """A convention-bound failure of a rasterizer checked against a convention that was
    only guessed (identified with a residual, never declared) says so: it shows where the
    rasterizer departs from the nearest convention, not a rule it broke. A line case is
    judged by the line fit (its own residual), any other by the triangle (path) one."""
    fingerprint = fingerprint_of(rasterizer)
    bound = {c.name for c in checks.checks() if c.needs_convention}
    if fingerprint is None or result.check not in bound or result.status != "fail":
        return result
    own_fit = kind_of(case.scene).own_fit if isinstance(case, Case) else None
    fit = getattr(fingerprint, own_fit[0], None) if own_fit is not None else None
    if own_fit is not None and fit is not None:
        exact, residual, what = fit.exact, fit.residual, own_fit[1]
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
    rasterizers : rasterizer objects or specs (see :func:`harness.engine.registry.load`)
    suite : {"quick", "full"}
    seed : int
    cases : list of Case, optional
        Run these instead of the suite's.
    tolerance : Tolerance
    timeout : float or TimeLimit
        The time-limit policy of one rasterize call (:class:`harness.engine.isolation.TimeLimit`;
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
        short or not run): what the run journal (:mod:`harness.results.journal`) marks complete.

    Returns
    -------
    list of Result
        Records with ``rasterizer``, ``case``, ``check``, ``status``, ``message``,
        ``metrics`` and ``evidence``; a failing or erroring one's evidence names its
        ``signature`` (:func:`harness.diagnose.causes.signed`), which
        :func:`harness.diagnose.causes.by_cause` groups by. A rasterizer whose answers on a scene
        kind contradict its declared convention (:func:`harness.contract.declarations.answer_problem`)
        has one error result for that kind, ``evidence["refused"]`` naming it, and is
        handed no more scenes of the kind.

    Raises
    ------
    ValueError
        In one line naming it, for a rasterizer that cannot be loaded or whose
        declarations contradict each other (:func:`harness.contract.declarations.declaration_problem`).
    """
    selected = list(cases) if cases is not None else suite_cases(suite, seed)
    results: list[Result] = []
    loaded = distinct_names([load(spec) if isinstance(spec, str) else declared(spec) for spec in rasterizers])
    if identify:
        from harness.identify.fingerprint import identify_all

        loaded, _ = identify_all(loaded, seed, call_timeout=timeout)
    for rasterizer in loaded:
        with Session(rasterizer, timeout, isolate=isolate, tolerance=tolerance) as session:
            results += run_session(session, selected, repros=repros, repro_seconds=repro_seconds, on_result=on_result,
                                   only=only, rerun=rerun, stop=stop, deadline=deadline, on_case=on_case)
    return results


def run_session(
    session: Session,
    cases: Sequence[Case | MotionCase],
    *,
    repros: bool = True,
    repro_seconds: float = 120.0,
    on_result: Callable[[Result], None] | None = None,
    only: set[str] | None = None,
    rerun: int = 0,
    stop: threading.Event | None = None,
    deadline: float | None = None,
    on_case: Callable[[str, str], None] | None = None,
) -> list[Result]:
    """The cases on one session's rasterizer, one after another: each case's checks, its
    reruns, its failures shrunk and signed (:func:`run_suite` runs this for each of its
    rasterizers; the pytest plugin for each case, on the session it keeps per rasterizer).
    The parameters are :func:`run_suite`'s; the session is left open."""
    rasterizer = session.rasterizer
    results: list[Result] = []
    shrink_until = time.monotonic() + repro_seconds
    for k, case in enumerate(cases):
        if stop is not None and stop.is_set():
            break
        if deadline is not None and time.monotonic() > deadline:
            results += _not_run(cases[k:], rasterizer.name, "the run's time budget was used up", on_result)
            break
        found = session.check(case, only)
        if rerun:
            found = [_rerun(r, case, session.check, rerun) if r.status in ("fail", "error") and "refused" not in r.evidence
                     else r for r in found]
        if stop is not None and stop.is_set():
            break  # the case was cut short by the stop: its results are not to be trusted
        for result in found:
            if repros and result.status == "fail" and isinstance(case, Case) and "flaky" not in result.evidence:
                if time.monotonic() < shrink_until:
                    result = repro.attach_repro(result, case, session.judge, rasterizer)
                else:  # budget used up: the whole case is the repro
                    result = repro.whole_case_repro(result, case, rasterizer.name,
                                                    "not shrunk: the shrinking time budget was used up")
            result = signed(_qualified(result, rasterizer, case), case, rasterizer, session.judge, session.answered)
            results.append(result)
            if on_result is not None:
                on_result(result)
        if on_case is not None:
            on_case(rasterizer.name, case.id)
    return results


def declared(rasterizer: Rasterizer) -> Rasterizer:
    """A rasterizer object whose declarations agree, as :func:`harness.engine.registry.load`
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


def _rerun(result: Result, case: Case | MotionCase, check: Callable[[Case | MotionCase, set[str] | None], list[Result]],
           times: int) -> Result:
    """Rerun the check behind an unexpected result ``times`` times; when the status
    changes, the result is marked flaky (``evidence["flaky"]``: the statuses seen, first
    the original) and its message says so: a flake is not a regression."""
    statuses: list[str] = [result.status]
    only = None if result.check == "run" else {result.check}
    for _ in range(times):
        again = [r for r in check(case, only) if r.check == result.check]
        statuses.append(again[0].status if again else "missing")
    if len(set(statuses)) == 1:
        return replace(result, evidence={**result.evidence, "reruns": statuses})
    return replace(result, message=f"flaky ({' / '.join(statuses)} over {times + 1} runs): {result.message}",
                   evidence={**result.evidence, "flaky": statuses})


def replay(path: Path | str, rasterizer: Rasterizer | str, isolate: bool = False, identify: bool = True,
           timeout: float | TimeLimit = 60.0) -> list[Result]:
    """Replay a saved case (:func:`harness.contract.case.save_case`, or a repro from a run): the
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
    >>> from harness.contract.scenes import Scene
    >>> from harness.contract.case import Case
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
