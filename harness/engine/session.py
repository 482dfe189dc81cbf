"""One way to run a rasterizer: a :class:`Session` is a loaded rasterizer with the process
that runs it, its convention, and the checks of a case on it.

Every caller that hands a rasterizer scenes goes through one: the runner
(:func:`harness.engine.runner.run_suite`, and the command line's ``--jobs`` path through it),
campaigns (a Dask worker keeps one per rasterizer it serves), identification in a process
of its own (:func:`harness.identify.fingerprint.identify_isolated`) and the pytest plugin (one per
rasterizer and pytest session). A session's calls run in an isolated
:class:`harness.engine.isolation.Worker` (each within its :class:`harness.engine.isolation.TimeLimit`;
a call cut off twice, or a worker that dies, leaves a fresh worker behind for the next
call), or in this process (:class:`harness.engine.isolation.InProcess`, for debugging).

The checks of one case (:func:`check_case`, :func:`check_motion`) live here too, below
the runner: the session asks them, and the runner asks the session.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from harness import checks
from harness.checks import Drawing, Result, Tolerance
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.declarations import answer_problem, scene_kind_problem
from harness.contract.protocol import Rasterizer, convention_for, fingerprint_of, interpolates_of, scene_kinds_of, takes
from harness.contract.scenes import AnyScene, Scene, Unsupported
from harness.engine import ledger
from harness.engine.isolation import AnyCall, InProcess, Outcome, TimeLimit, Worker, describe, each_until_error

__all__ = ["Session", "check_case", "check_motion", "planned_scenes"]


class Session:
    """A rasterizer loaded in this process and the worker that runs its calls.

    Parameters
    ----------
    rasterizer : Rasterizer
        As loaded (:func:`harness.engine.registry.load`), or wrapped with the convention
        identified for it (:class:`harness.identify.fingerprint.Identified`).
    timeout : float or TimeLimit
        The time-limit policy of one call (a number is its cap, in seconds).
    isolate : bool
        Run the calls in a worker process of their own (default); False calls the
        rasterizer in this process, with no time limit.
    tolerance : Tolerance
        Of the checks (:meth:`check`).
    remembers_refusals : bool
        Keep :attr:`refused`: once an answer on a scene kind contradicts what the
        rasterizer declares, no more scenes of that kind are handed to it (as a run does);
        False hands it every scene (a campaign, each of whose scenes is a finding of its own).
    deadline : float, optional
        A ``time.monotonic()`` no call runs past (a bound on a whole job: identify's).

    Examples
    --------
    >>> from harness.contract.scenes import Scene
    >>> from rasterizers.centre_scanline import CentreScanline
    >>> with Session(CentreScanline(), isolate=False) as session:
    ...     outcome = session.call(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]))
    >>> outcome.error is None and len(outcome.coverage) > 0
    True
    """

    def __init__(self, rasterizer: Rasterizer, timeout: float | TimeLimit = 60.0, *, isolate: bool = True,
                 tolerance: Tolerance = Tolerance(), remembers_refusals: bool = True, deadline: float | None = None) -> None:
        self.rasterizer = rasterizer
        self.tolerance = tolerance
        self.worker: Worker | InProcess = Worker(rasterizer, timeout, deadline=deadline) if isolate else InProcess(rasterizer)
        # scene kind -> the one-line message of the answer that contradicted the declaration
        self.refused: dict[str, str] | None = {} if remembers_refusals else None

    @property
    def name(self) -> str:
        return str(self.rasterizer.name)

    def call(self, scene: AnyScene) -> Outcome:
        """One rasterize call (isolated: within its time limit, asked again once when cut off)."""
        with ledger.section("isolation"):
            outcome = self.worker.rasterize(scene)
        ledger.note("rasterizer", outcome.seconds)
        return outcome

    def call_all(self, scenes: list[Scene]) -> list[Outcome]:
        """One call per scene, in order, up to and including the first that gives no coverage."""
        with ledger.section("isolation"):
            outcomes = self.worker.rasterize_all(scenes)
        ledger.note("rasterizer", sum(o.seconds for o in outcomes))
        return outcomes

    def prefetch(self, cases: Sequence[Case | MotionCase], only: set[str] | None = None) -> int:
        """Send the worker every scene :meth:`check` will hand it for ``cases`` (each case's
        scene or frames, and the scenes its applicable checks plan to ask for:
        :attr:`harness.checks.Check.plans`), to be drawn while this process checks the
        cases one by one (:meth:`harness.engine.isolation.Worker.prefetch`); how many were
        sent. A scene sent ahead and never asked for costs only the worker's time
        (:meth:`forget_prefetched`)."""
        scenes: list[AnyScene] = []
        for case in cases:
            scenes += planned_scenes(case, self.rasterizer, only, self.refused)
        with ledger.section("isolation"):
            return self.worker.prefetch(scenes)

    def forget_prefetched(self) -> None:
        """Drop the answers drawn ahead and not asked for (the worker's pipe back in step)."""
        with ledger.section("isolation"):
            self.worker.forget_prefetched()

    def check(self, case: Case | MotionCase, only: set[str] | None = None) -> list[Result]:
        """Every applicable check of the rasterizer on ``case`` (those named in ``only``);
        [] for a case whose scenes it does not take, or of a kind it was refused."""
        if isinstance(case, MotionCase):
            return check_motion(case, self.rasterizer, self.call, self.tolerance, only, self.call_all, self.refused)
        return check_case(case, self.rasterizer, self.call, self.tolerance, only=only, refused=self.refused)

    def judge(self, case: Case | MotionCase, check: str) -> list[Result]:
        """The one check on a (changed) case: the shrinker's and the signature trials' question."""
        return self.check(case, {check})

    def answered(self, still: Case, drawn: Coverage, check: str) -> list[Result]:
        """The one check on ``still``, judged on ``drawn`` (an answer already in hand): no call."""
        return check_case(still, self.rasterizer, lambda scene: Outcome(drawn), self.tolerance, only={check})

    def convention(self, case: Case | MotionCase) -> Convention | None:
        """The convention the rasterizer is judged by on ``case``."""
        if isinstance(case, MotionCase):  # its frames' kind's (a line drawer's line convention)
            return convention_for(self.rasterizer, case.frames[0]) if case.frames else self.rasterizer.convention
        return convention_for(self.rasterizer, case.scene)

    def close(self) -> None:
        """End the worker process (a session closed twice is closed once)."""
        self.worker.close()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def planned_scenes(case: Case | MotionCase, rasterizer: Rasterizer, only: set[str] | None = None,
                   refused: dict[str, str] | None = None) -> list[AnyScene]:
    """The scenes :func:`check_case` (:func:`check_motion`) will hand ``rasterizer`` for
    ``case`` when its answers are sound: its scene (frames) and those its applicable checks
    plan to ask for (:attr:`harness.checks.Check.plans`); none when no check applies or it
    takes no scene of the case's kind (or that kind was refused)."""
    first = case.frames[0] if isinstance(case, MotionCase) and case.frames else getattr(case, "scene", None)
    if first is None or not takes(rasterizer, first) or (refused is not None and first.kind in refused):
        return []
    convention = convention_for(rasterizer, first)
    applicable = checks.checks(case, only, convention.coverage_kind if convention is not None else "single")
    if isinstance(case, MotionCase):
        return list(case.frames) if applicable else []
    planned: list[AnyScene] = [case.scene] if applicable else []
    for check in applicable:
        if check.plans is not None:
            planned += check.plans(case, convention)
    return planned


def _error(case: Case, rasterizer: str, outcome: Outcome, check: str = "run") -> Result:
    kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
    text = describe(outcome.error, with_type=False)
    return Result(rasterizer, case.id, check, "error", f"{kind}: {text}",
                  {"seconds": outcome.seconds}, {"traceback": outcome.traceback})


def _refusal(case: Case | MotionCase, rasterizer: Rasterizer, scene: AnyScene, outcome: Outcome,
             refused: dict[str, str] | None, frame: int | None = None) -> Result | None:
    """The one error result of an answer (or error) that contradicts what the rasterizer
    declares (:mod:`harness.contract.declarations`), recorded in ``refused`` under the scene kind so
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
    kind = convention.coverage_kind if convention is not None else "single"
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
    results = [_judged(check, subject) for check in applicable]
    drawing = Drawing.of(subject)  # references only (and the oracle if a check computed it): the report draws
    return [_retried(replace(r, rasterizer=name, metrics={**r.metrics, "seconds": outcome.seconds},
                             drawing=(r.drawing or drawing) if r.status == "fail" else None), [outcome]) for r in results]


def _judged(check: checks.Check, subject: checks.Subject) -> Result:
    """``check``'s verdict on ``subject``; an exception the check or its oracle raises (a
    convention it cannot judge the scene under) is an error result naming the check and the
    exception, and the run goes on."""
    try:
        verdict: Result = check.verdict(subject)
        return verdict
    except Exception as exc:  # noqa: BLE001 -- any failure of the harness's own judging, said, never lost
        return Result("", subject.case.id, check.name, "error",
                      f"the harness could not judge this case: {type(exc).__name__}: {exc}"[:500])


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
    convention = convention_for(rasterizer, case.frames[0])  # the frames' kind's (lines: the line convention)
    applicable = checks.checks(case, only, convention.coverage_kind if convention is not None else "single")
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
    results = [_judged(check, subject) for check in applicable]
    drawing = Drawing.of(subject)
    return [_retried(replace(r, rasterizer=name, metrics={**r.metrics, "seconds": seconds},
                             drawing=(r.drawing or drawing) if r.status == "fail" else None), outcomes) for r in results]
