"""A campaign on a worker: run one batch (:func:`run_batch`) and shrink a finding to its repro
(:func:`shrink_finding`).

A Dask worker loads the rasterizer spec itself (once per process), checks each scene with
every call isolated in a forked process (a crash or a hang is a finding, never a dead
campaign) and classifies each failure by its cause
(:func:`harness.diagnose.signatures.signature`); what it sends back is plain data
(:func:`plain_data`). A representative of each new signature is shrunk to a minimal repro by
the existing shrinker of :mod:`harness.diagnose.repro`.

Dask worker processes are daemonic, and a daemonic process may start no children: a worker
lifts that for itself before it forks the rasterizer's process, and each process it forks
ends when the worker is gone (:func:`_prepare_process`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import multiprocessing
import os
import pickle
import threading
import time
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from harness.campaign.state import BatchResult, CampaignError, CampaignTask, SceneFinding
from harness.checks import Result
from harness.contract.case import Case, MotionCase, case_to_json
from harness.diagnose.causes import attributed
from harness.engine import ledger
from harness.engine.session import Session

if TYPE_CHECKING:
    from harness.diagnose.signatures import Signature


SHRINK_SECONDS = 10.0  # the shrinker's own time budget, per representative


_PREPARED = False


def _prepare_process() -> None:
    """Let this process (a Dask worker's) start the rasterizer's isolated processes, and
    make sure none of them outlives it.

    A Dask worker process is daemonic by default (``distributed.worker.daemon``), and
    multiprocessing lets no daemonic process start children: the flag is cleared for this
    process only (its nanny still ends it). Forking a Dask worker, which runs a few
    threads, is safe here: the child only reads scenes from its pipe and calls the
    rasterizer. A child whose parent is killed (a lost worker) would wait on its pipe
    forever, as its siblings hold copies of that pipe's other end: each isolated child
    watches its parent and ends when it is gone (:func:`harness.engine.isolation._exit_with_parent`).
    """
    global _PREPARED
    if _PREPARED:
        return
    process = multiprocessing.current_process()
    if process.daemon:
        try:
            process.daemon = False
        except AssertionError as exc:  # pragma: no cover - multiprocessing's own guard
            raise CampaignError("this Dask worker process is daemonic and cannot start the rasterizer's isolated process; "
                                "start the workers with DASK_DISTRIBUTED__WORKER__DAEMON=False") from exc
    _PREPARED = True


def _session(spec: str, fingerprint: Any | None, timeout: float) -> Session:
    """The session of the rasterizer of ``spec``, loaded in this process (wrapped by the
    coordinator's fingerprint when it declares no convention), its calls in an isolated
    worker process. Every scene is handed to it: a campaign's scene is a finding of its
    own, even after an answer contradicted the rasterizer's declaration."""
    from harness.engine.isolation import TimeLimit
    from harness.engine.registry import load
    from harness.identify.fingerprint import Identified

    _prepare_process()
    rasterizer = load(spec, import_timeout=timeout)
    if fingerprint is not None and rasterizer.convention is None:
        rasterizer = Identified(rasterizer, fingerprint)
    # run's policy: the first call of a scene kind (a JIT compiling its kernels) gets the
    # cap, --timeout, as every call may; no allowance beyond what the user asked
    return Session(rasterizer, TimeLimit.of(timeout), remembers_refusals=False)


_LOADED: dict[tuple[str, bytes, float, int], Session] = {}
_LOADED_LOCK = threading.Lock()
KEEP_LOADED = 4  # rasterizers kept loaded per worker process (a long-lived cluster serves many campaigns)


def _loaded(spec: str, fingerprint: Any | None, timeout: float) -> Session:
    """The rasterizer of ``spec`` in this process, loaded once per process (and thread:
    a worker running several tasks at once gives each its own isolated process); each
    thread's least recently used beyond :data:`KEEP_LOADED` are closed."""
    token = hashlib.sha1(pickle.dumps(fingerprint)).digest()
    key = (spec, token, timeout, threading.get_ident())
    with _LOADED_LOCK:
        found = _LOADED.pop(key, None)
    if found is None:
        found = _session(spec, fingerprint, timeout)
    with _LOADED_LOCK:
        _LOADED[key] = found  # the most recently used last
        mine = [k for k in _LOADED if k[3] == key[3]]  # only this thread's: another's may be in use
        closing = [_LOADED.pop(k) for k in mine[:-KEEP_LOADED]]
    for old in closing:
        old.close()
    return found


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return str(get_worker().address)
    except (ImportError, ValueError):
        return f"local:{os.getpid()}"


def _classified(result: Result, case: Case | MotionCase, loaded: Session) -> tuple[Result, Signature]:
    """A failing or erroring result with its signature (a failing conformance or invariance
    check probed first: does it pass on a grown screen, or as the library receives its
    input? a flicker: does the frame that leaves the oracle fail conformance, and why?
    :func:`harness.diagnose.trials.with_trials`)."""
    from harness.diagnose.signatures import signature
    from harness.diagnose.trials import with_trials

    with ledger.section("signatures"):
        if result.status == "fail":
            result = with_trials(result, case, loaded.judge, loaded.rasterizer)
        return result, signature(result, case, loaded.convention(case))


def _finding(result: Result, case: Case | MotionCase, loaded: Session, family: str, seed: int, index: int) -> SceneFinding:
    result, found = _classified(result, case, loaded)
    return SceneFinding(family, seed, index, result.check, result.status, result.message, found.key, found.failure_class,
                   found.convention_part, found.check)


def attribute_causes(findings: list[SceneFinding]) -> list[SceneFinding]:
    """One scene's findings, each with its cause (:func:`harness.diagnose.causes.attributed`, the
    rule a run's results are grouped by too): when the scene fails conformance (or accuracy
    for anti-aliased coverage), the failures of the consequent checks (watertight, closed,
    ...: :attr:`harness.checks.records.Check.cause_role`) on it are counted under that
    failure's cause (the exact oracle says what is wrong; the others see its effects); any
    other finding keeps its own signature's cause.
    A finding already counted under a cause keeps it.

    >>> f = SceneFinding("lattice", 0, 1, "conformance", "fail", "", "", "culling", "culling", "conformance")
    >>> g = SceneFinding("lattice", 0, 1, "watertight", "fail", "", "", "hole", "none", "watertight")
    >>> [x.cause for x in attribute_causes([f, g])]
    ['culling', 'culling']
    """
    counted = attributed([(f.status, f.signature) for f in findings])  # the rule: harness.diagnose.causes
    return [replace(f, cause=cause) if not f.cause else f for f, cause in zip(findings, counted)]


def _harness_fault(exc: BaseException, family: str, seed: int, index: int) -> SceneFinding:
    """A scene the harness itself could not generate or check: a finding of its own kind
    (check ``harness``), so that the campaign goes on and the fault is seen."""
    kind = type(exc).__name__
    return SceneFinding(family, seed, index, "harness", "error", f"{kind}: {exc}", f"harness|harness-fault-{kind}|none",
                   f"harness-fault-{kind}", "none", "harness")


def plain_data(value: Any, where: str = "the answer") -> Any:
    """``value`` rebuilt of exact builtin types only (None, bool, int, float, str, and lists,
    tuples and str-keyed dicts of them): what a Dask worker sends the coordinator, by
    pickle. A str, int or float of a subclass (a plugin's name, a message's text) becomes
    a plain copy, read through the builtin's own slot (none of the subclass's methods run,
    here or where it is unpickled); anything else is refused.

    >>> class Sly(str):
    ...     def __reduce__(self):
    ...         raise AssertionError("pickled")
    >>> back = plain_data({"rasterizer": Sly("mine"), "scene": ("lattice", 0, 3)})
    >>> back, type(back["rasterizer"]) is str
    ({'rasterizer': 'mine', 'scene': ('lattice', 0, 3)}, True)

    Raises
    ------
    TypeError
        Naming where in ``value`` a value of another type is.
    """
    kind = type(value)
    if value is None or kind in (bool, int, float, str):
        return value
    if isinstance(value, str):
        return str.__str__(value)
    if isinstance(value, int) and not isinstance(value, bool):
        return int.__index__(value)
    if isinstance(value, float):
        return float.__float__(value)
    if kind in (list, tuple):
        return kind(plain_data(item, f"{where}[{k}]") for k, item in enumerate(value))
    if kind is dict:
        if not all(isinstance(key, str) for key in value):
            raise TypeError(f"{where}: a dict keyed by other than text")
        return {str.__str__(key): plain_data(item, f"{where}.{str.__str__(key)}") for key, item in value.items()}
    raise TypeError(f"{where}: a {kind.__name__} is not plain data")


def _plain_finding(finding: SceneFinding) -> SceneFinding:
    """``finding`` with every field plain (:func:`plain_data`; read field by field, not by
    ``asdict``, which would deep-copy, and so pickle, what it holds)."""
    return SceneFinding(**{f.name: plain_data(getattr(finding, f.name), f"finding.{f.name}")
                           for f in dataclasses.fields(SceneFinding)})


def run_batch(task: CampaignTask) -> BatchResult:
    """Run one batch (on a Dask worker, or anywhere): generate each scene, run the checks
    with every rasterize call isolated, and classify each failing or erroring result.

    The rasterizer is loaded once per worker process; a crash or hang of it is an error
    result (a ``crash`` or ``hang`` finding), and the batch goes on. Every scene of the
    batch the checks will hand the rasterizer is sent to its process at once, before the
    first is checked (:meth:`harness.engine.session.Session.prefetch`): it draws them while
    this process checks. Where the worker's time went is kept (``sections``).
    """
    from cases.fuzz import generate, primitives

    start = time.perf_counter()
    loaded = _loaded(task.spec, task.fingerprint, task.timeout)
    setup = time.perf_counter() - start
    only = set(task.only) if task.only is not None else None
    family, seed = task.batch.family, task.batch.seed
    findings: list[SceneFinding] = []
    scenes = counted = 0
    with ledger.keeping() as kept:
        cases: list[tuple[int, Case | MotionCase | Exception]] = []
        with ledger.section("generation"):
            for index in task.batch.indices():
                try:
                    cases.append((index, generate(family, seed, index)))
                except Exception as exc:
                    cases.append((index, exc))
        loaded.prefetch([case for _, case in cases if not isinstance(case, Exception)], only)
        for index, case in cases:
            scenes += 1
            try:
                if isinstance(case, Exception):
                    raise case
                results = loaded.check(case, only)
                if any(r.status != "skip" for r in results):  # checked, not only handed over
                    counted += primitives(case)
                findings += attribute_causes([_finding(r, case, loaded, family, seed, index) for r in results
                                              if r.status in ("fail", "error")])
            except Exception as exc:
                findings.append(_harness_fault(exc, family, seed, index))
        loaded.forget_prefetched()
    seconds = time.perf_counter() - start
    sections = {**kept.seconds, **{f"note:{k}": v for k, v in kept.notes.items()}, "note:batch": seconds - setup}
    # plain data only goes back to the coordinator: nothing of the plugin's is unpickled there
    return BatchResult(task.batch, scenes, int(counted), seconds,
                       tuple(_plain_finding(f) for f in findings), str.__str__(_worker_name()), setup,
                       {str(k): float(v) for k, v in sections.items()})


def shrink_finding(spec: str, fingerprint: Any | None, finding: SceneFinding, timeout: float = 60.0,
                   seconds: float = SHRINK_SECONDS) -> dict[str, Any]:
    """A minimal repro of a finding, as case JSON naming its check, rasterizer, message and
    signature (a Dask task, or called anywhere).

    The scene is regenerated from ``(family, seed, index)`` and checked again; a failing
    check is shrunk by :func:`harness.diagnose.repro.attach_repro` (ddmin over the triangles, then
    coarsening, and the input-format and viewport-edge probes; a partition's hole cut down
    to the pieces around it, :func:`harness.diagnose.repro.hole_repro`; the file keeps what the
    rasterizer drew on the repro, for its picture), a crash or exception by
    ddmin keeping the same signature; a hang or a motion case is kept whole, as is a
    finding that no longer shows (said in ``note``).

    The repro is plain data (:func:`plain_data`): nothing of the plugin's (its name, a
    message's text) is unpickled where it is sent.
    """
    return plain_data(_shrunk(spec, fingerprint, finding, timeout, seconds), "the repro")  # type: ignore[no-any-return]


def _shrunk(spec: str, fingerprint: Any | None, finding: SceneFinding, timeout: float, seconds: float) -> dict[str, Any]:
    """The repro of :func:`shrink_finding`, before it is made plain data."""
    from cases.fuzz import generate
    from harness.checks import checks
    from harness.diagnose import repro

    loaded = _loaded(spec, fingerprint, timeout)
    name = loaded.rasterizer.name
    case = generate(finding.family, finding.seed, finding.index)
    extra: dict[str, Any] = {"signature": finding.signature_key, "scene": list(finding.point)}
    whole = {"check": finding.check, "rasterizer": name, "message": finding.message, "original_case": case.id, **extra}
    if not isinstance(case, Case):
        return case_to_json(case, **whole, note="a motion sequence is kept whole")
    if finding.status == "error" and finding.failure_class == "hang":
        return case_to_json(case, **whole, note="not shrunk: each try of a hang costs its time limit")
    registered = checks(only={finding.check})
    only = {finding.check} if registered else {"hygiene"}  # an error of the call itself: the cheapest check calls it

    def same_cause(candidate: Case) -> list[Result]:
        """The candidate's results that fail (or err) as the finding did, for the same cause."""
        out = []
        for r in loaded.check(candidate, only):
            if r.check == finding.check and r.status == finding.status:
                probed, found = _classified(r, candidate, loaded)
                if found.key == finding.signature_key:
                    out.append(probed)
        return out

    # ddmin over the primitives and coarsening, keeping the signature (a subset that fails
    # the same check for another cause is no repro of this one); closed meshes need the
    # whole case, and a partition's hole is cut down to the pieces around it by attach_repro
    shrinks = not registered or any(c.shrinks for c in registered)
    minimal = repro.shrink(case, lambda candidate: bool(same_cause(candidate)), budget=60, seconds=seconds) if shrinks else case
    shown = same_cause(minimal)
    if not shown and minimal is not case:
        minimal, shown = case, same_cause(case)
    if not shown:
        return case_to_json(case, **whole, note="not shrunk: the failure did not show again")
    if finding.status == "error":
        return case_to_json(minimal, check=finding.check, rasterizer=name, message=shown[0].message, original_case=case.id,
                            original_triangles=len(case.scene), **extra)
    # the repro file as the runner writes it: the check's message on the minimal case, the probes' notes
    attached = repro.attach_repro(shown[0], minimal, loaded.judge, loaded.rasterizer, seconds=seconds)
    return {**attached.evidence["repro"], "original_case": case.id, "original_triangles": len(case.scene), **extra}
