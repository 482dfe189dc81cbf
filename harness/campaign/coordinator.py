"""The campaign's coordinator: :func:`run_campaign`.

It identifies a rasterizer that declares no convention once (its workers wrap it in that
fingerprint), keeps about two batches per worker in flight (each sized to about a second of
work once its family's cost is known), merges each completed batch exactly once into the
:class:`~harness.campaign.state.CampaignState` and writes it atomically (at most twice a
second, at once for a new signature); for each new signature one representative is shrunk to a
minimal repro (:func:`harness.campaign.worker.shrink_finding`) and saved beside the state.

A batch on a worker that dies is redone elsewhere by Dask; at the budget the batches in flight
are cancelled and not marked done.
"""

from __future__ import annotations

import contextlib
import math
import pickle
import time
import uuid
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from harness.campaign.cluster import SCHEDULER_TIMEOUT, _dask, scheduler_address
from harness.campaign.state import (
    IDENTIFIED_FILE,
    Batch,
    BatchResult,
    CampaignError,
    CampaignState,
    CampaignTask,
    ProgressEvent,
    SceneFinding,
    state_lock,
)
from harness.campaign.worker import run_batch, shrink_finding
from harness.contract.case import MotionCase
from harness.contract.protocol import Rasterizer, takes
from harness.results.files import atomic_write_bytes, safe_name

if TYPE_CHECKING:
    from distributed import Client, Future

TARGET_BATCH_SECONDS = 1.0  # a batch long enough to amortise Dask's few ms per task, short enough to stop promptly
FIRST_BATCH = 4  # scenes in a family's first batch, before its cost is known
MAX_BATCH = 4096
IN_FLIGHT_PER_WORKER = 2
SAVE_EVERY = 0.5  # seconds between writes of the state (a new signature or repro is written at once)
SHRINK_GRACE = 60.0  # after the search stops, how long the representatives still being shrunk are waited for
IDENTIFY_SEED = 0  # every campaign of a rasterizer is judged by the same identified convention: their findings merge


def _portable_spec(spec: str) -> str:
    """A ``path/file.py:attr`` spec with the path made absolute (workers may run elsewhere)."""
    where, sep, attr = spec.rpartition(":")
    if sep and where.endswith(".py") and Path(where).is_file():
        return f"{Path(where).resolve()}:{attr}"
    return spec


def _identify(rasterizer: Rasterizer, timeout: float) -> tuple[Any | None, dict[str, Any] | None]:
    """The fingerprint workers wrap a rasterizer that declares no convention with
    (identified once, here; its probes' raw data left out: only the conventions travel),
    and its summary for the state."""
    if rasterizer.convention is not None:
        return None, None
    from harness.identify.fingerprint import Identified, identify_all

    wrapped, cards = identify_all([rasterizer], IDENTIFY_SEED, call_timeout=timeout)
    card = cards.get(rasterizer.name, {})
    if not isinstance(wrapped[0], Identified):
        return None, {"error": card.get("error", "not identified")}
    fingerprint = wrapped[0].fingerprint
    summary = {"convention": card.get("convention"), "exact": card.get("exact"), "residual": card.get("residual")}
    return replace(fingerprint, probes={}, calls=None), summary  # (the call tally holds the local call: not picklable)


def _taken_families(rasterizer: Rasterizer, families: Sequence[str], seed: int) -> tuple[list[str], dict[str, str]]:
    """The families whose scenes the rasterizer takes (judged on their first scenes), and
    the others with why."""
    from cases.fuzz import generate

    kept, skipped = [], {}
    for family in families:
        scenes = [c.frames[0] if isinstance(c, MotionCase) else c.scene for c in (generate(family, seed, i) for i in range(4))]
        if any(takes(rasterizer, scene) for scene in scenes):
            kept.append(family)
        else:
            skipped[family] = f"{rasterizer.name} takes none of its scene kinds ({', '.join(sorted({s.noun for s in scenes}))})"
    return kept, skipped


class _Coordinator:
    """The loop of :func:`run_campaign`: batches out, results merged, representatives shrunk."""

    def __init__(self, client: Client, state: CampaignState, spec: str, fingerprint: Any | None, families: list[str],
                 budget_seconds: float | None, budget_scenes: int | None, batch_size: int | None,
                 only: frozenset[str] | None, timeout: float, on_progress: Callable[[ProgressEvent], None] | None) -> None:
        from distributed import as_completed

        self.client, self.state, self.spec, self.fingerprint = client, state, spec, fingerprint
        self.budget_seconds, self.budget_scenes = budget_seconds, budget_scenes
        self.fixed_size, self.only, self.timeout, self.on_progress = batch_size, only, timeout, on_progress
        self.token = uuid.uuid4().hex[:12]
        self.completed = as_completed(loop=client.loop)
        self.batches: dict[Future, Batch] = {}
        self.shrinks: dict[Future, str] = {}
        self.merged: set[Batch] = set()
        self.seconds_per_scene: dict[str, float] = {}
        self.sections: dict[str, float] = {}  # this run's seconds per section (BatchResult.sections, and "state")
        self.cursor = state.next_batches(families, self._size)
        self.scenes = self.primitives = self.submitted = 0
        self.wall_before = state.wall_seconds
        self.start = time.monotonic()
        self.deadline = None if budget_seconds is None else self.start + budget_seconds
        self.grace_end = math.inf
        self.searching = True
        self.slots = 1
        self.slots_asked = -math.inf
        self.saved = -math.inf

    # -- sizes

    def _workers(self) -> int:
        """Worker threads in the cluster (asked at most once a second; at least one)."""
        if time.monotonic() - self.slots_asked >= 1.0:
            self.slots_asked = time.monotonic()
            with contextlib.suppress(Exception):  # a scheduler between workers: keep going with what was known
                self.slots = max(1, sum(self.client.nthreads().values()))
        return self.slots

    def _size(self, family: str) -> int:
        if self.fixed_size is not None:
            size = self.fixed_size
        elif family not in self.seconds_per_scene:
            size = FIRST_BATCH
        else:
            size = round(TARGET_BATCH_SECONDS / max(self.seconds_per_scene[family], 1e-6))
            if self.deadline is not None:  # the last batches should not outlast the budget by much
                size = min(size, round(max(self.deadline - time.monotonic(), 0.0) / 2
                                       / max(self.seconds_per_scene[family], 1e-6)))
            if self.budget_scenes is not None:  # keep every worker busy to the end
                left = self.budget_scenes - self.submitted
                size = min(size, math.ceil(left / (2 * self.slots)))
        return int(min(max(size, 1), MAX_BATCH))

    # -- submitting

    def top_up(self) -> None:
        self.slots = self._workers()
        while self.searching and len(self.batches) < IN_FLIGHT_PER_WORKER * self.slots:
            if self.budget_scenes is not None and self.submitted >= self.budget_scenes:
                return
            batch = next(self.cursor)
            if self.budget_scenes is not None and self.submitted + batch.count > self.budget_scenes:
                batch = replace(batch, count=self.budget_scenes - self.submitted)  # the rest is left for a later run
            self.submitted += batch.count
            task = CampaignTask(self.spec, batch, self.fingerprint, self.only, self.timeout)
            key = f"rastercheck-batch-{self.token}-{batch.family}-{batch.seed}-{batch.start}-{batch.count}"
            future = self.client.submit(run_batch, task, key=key, retries=2)
            self.batches[future] = batch
            self.completed.add(future)

    def shrink(self, finding: SceneFinding) -> None:
        """Shrink one representative of a new signature, in a task of its own (ahead of
        the batches waiting)."""
        key = finding.signature_key
        future = self.client.submit(shrink_finding, self.spec, self.fingerprint, finding, self.timeout, priority=10,
                                    key=f"rastercheck-shrink-{self.token}-{safe_name(key)}-{finding.index}")
        self.shrinks[future] = key
        self.completed.add(future)

    # -- the loop

    def save(self, now: bool = False) -> None:
        """Write the state: at once with ``now``, else at most every :data:`SAVE_EVERY`
        seconds (a batch merged but not yet written is not done for a resumed campaign:
        it is run again then, never counted twice)."""
        if now or time.monotonic() - self.saved >= SAVE_EVERY:
            self.state.wall_seconds = self.wall_before + self.elapsed()
            self.state.save()
            self.saved = time.monotonic()

    def run(self) -> None:
        self._workers()
        self._reshrink()
        try:
            self.top_up()
            while self.batches or self.shrinks:
                now = time.monotonic()
                if self.searching and self.deadline is not None and now >= self.deadline:
                    self.stop_search()
                if not self.searching and self.shrinks and now >= self.grace_end:
                    self.client.cancel(list(self.shrinks))  # their signatures keep repro None: the next run shrinks them
                    self.shrinks.clear()
                    break
                if not self.completed.has_ready():
                    with self.completed.thread_condition:
                        self.completed.thread_condition.wait(timeout=0.05)
                    continue
                for future in self.completed.next_batch(block=False):
                    self.handle(future)
                spent = self.budget_scenes is not None and self.submitted >= self.budget_scenes
                if self.searching and not self.batches and spent:
                    self.stop_search()
                self.top_up()
        except BaseException:
            self.client.cancel(list(self.batches) + list(self.shrinks))
            raise
        finally:
            self.save(now=True)
        self.emit(None, "", (), (), finished=True)

    def stop_search(self) -> None:
        """No more batches: those in flight are cancelled (their scenes are not done: a
        resumed campaign runs them); representatives being shrunk get a grace period."""
        self.searching = False
        if self.batches:
            self.client.cancel(list(self.batches))
            self.batches.clear()
        self.grace_end = time.monotonic() + SHRINK_GRACE

    def elapsed(self) -> float:
        return time.monotonic() - self.start

    def handle(self, future: Future) -> None:
        if future in self.shrinks:
            key = self.shrinks.pop(future)
            if future.status == "finished":
                self.state.save_repro(key, future.result())
            elif future.status == "error":
                self.state.signatures[key]["repro_error"] = f"{type(future.exception()).__name__}: {future.exception()}"
            self.save(now=True)
            return
        batch = self.batches.pop(future, None)
        if batch is None:
            return  # cancelled at the budget
        if future.status != "finished":
            error = future.exception() if future.status == "error" else None
            why = f"{type(error).__name__}: {error}" if error is not None else future.status
            raise CampaignError(f"batch {batch} failed on the cluster ({why}); the state in {self.state.directory} "
                                "keeps the batches done so far: rerun to resume")
        result: BatchResult = future.result()
        if batch in self.merged:
            return  # a duplicate completion: merged once already
        self.merged.add(batch)
        started = time.perf_counter()
        new = self.state.record(result, self.wall_before + self.elapsed())
        if new is None:
            return
        for name, seconds in result.sections.items():
            self.sections[name] = self.sections.get(name, 0.0) + seconds
        self.scenes += result.scenes
        self.primitives += result.primitives
        if result.scenes:
            per_scene = max(result.seconds - result.setup_seconds, 0.0) / result.scenes
            before = self.seconds_per_scene.get(result.batch.family)
            self.seconds_per_scene[result.batch.family] = per_scene if before is None else (before + per_scene) / 2
        self.save(now=bool(new))
        self.sections["state"] = self.sections.get("state", 0.0) + time.perf_counter() - started
        for key in new:
            representative = next(f for f in result.findings if f.signature_key == key)
            if not key.startswith("harness|"):
                self.shrink(representative)
        self.emit(batch, result.worker, result.findings, tuple(new))

    def _reshrink(self) -> None:
        """Signatures of an earlier run left without a repro are shrunk now (from their
        first finding, regenerated)."""
        for key, entry in self.state.signatures.items():
            if entry.get("repro") is None and not key.startswith("harness|"):
                first = entry["first"]
                self.shrink(SceneFinding(first["family"], first["seed"], first["index"],
                                         entry.get("result_check", entry["check"]),
                                    entry.get("status", "fail"), entry["message"], key, entry["failure_class"],
                                    entry["convention_part"], entry["check"]))

    def emit(self, batch: Batch | None, worker: str, findings: tuple[SceneFinding, ...], new: tuple[str, ...],
             finished: bool = False) -> None:
        if self.on_progress is None:
            return
        elapsed = self.elapsed()
        rate = self.scenes / elapsed if elapsed > 0 else 0.0
        eta: float | None = None
        if self.deadline is not None:
            eta = max(self.deadline - time.monotonic(), 0.0)
        if self.budget_scenes is not None and rate > 0:
            left = max(self.budget_scenes - self.scenes, 0) / rate
            eta = left if eta is None else min(eta, left)
        self.on_progress(ProgressEvent(
            self.scenes, self.primitives, elapsed, rate, self.primitives / elapsed if elapsed > 0 else 0.0,
            self.state.scenes, self.state.findings, {k: int(s["count"]) for k, s in self.state.signatures.items()},
            0.0 if finished else eta, self.slots, batch, worker, findings, new, finished, dict(self.sections)))


def run_campaign(spec: str, *, budget_seconds: float | None = None, budget_scenes: int | None = None,
                 families: Sequence[str] | None = None, seed: int = 0, state_dir: Path | str,
                 scheduler: str | Client | None = None, workers: int | None = None, batch_size: int | None = None,
                 only: Sequence[str] | None = None, timeout: float = 60.0,
                 on_progress: Callable[[ProgressEvent], None] | None = None,
                 scheduler_timeout: float = SCHEDULER_TIMEOUT) -> CampaignState:
    """Search generated scenes for failures of one rasterizer until the budget, on Dask.

    Parameters
    ----------
    spec : str
        The rasterizer (:func:`harness.engine.registry.load`); each worker loads it itself.
    budget_seconds, budget_scenes : float, int
        Stop after this many seconds of search (counted once the workers are ready) or
        scenes checked in this run, whichever comes first; at least one is required.
    families : sequence of str
        Case families of :data:`cases.fuzz.FAMILIES` (default all); those whose scenes the
        rasterizer does not take are skipped (``state.skipped`` says why).
    seed : int
    state_dir : path
        The campaign's state (:class:`CampaignState`): rerunning with the same folder
        continues, repeating no scene.
    scheduler : str or distributed.Client, optional
        A Dask scheduler's address (or a client); default a ``LocalCluster`` of ``workers``
        processes (one per core) of one thread each.
    batch_size : int, optional
        Scenes per batch; default sized per family to about a second of work.
    only : sequence of str, optional
        Run only these checks.
    timeout : float
        Seconds one rasterize call may take before it counts as hung.
    on_progress : callable, optional
        Called with a :class:`ProgressEvent` after each merged batch and at the end.
    scheduler_timeout : float
        Seconds the connection to ``scheduler`` (an address) may take.

    Returns
    -------
    CampaignState
        Saved in ``state_dir``.
    """
    from cases.fuzz import FAMILIES
    from harness.engine.registry import load

    families = tuple(FAMILIES if families is None else families)
    unknown = [f for f in families if f not in FAMILIES]
    if unknown or not families:
        raise ValueError(f"unknown case famil{'ies' if len(unknown) > 1 else 'y'} {', '.join(map(repr, unknown))} "
                         f"(known: {', '.join(FAMILIES)})" if unknown else "no case family given")
    if budget_seconds is None and budget_scenes is None:
        raise ValueError("a campaign needs a budget: budget_seconds or budget_scenes")
    if (budget_seconds is not None and not budget_seconds > 0) or (budget_scenes is not None and budget_scenes < 1):
        raise ValueError(f"a budget must be positive (budget_seconds={budget_seconds}, budget_scenes={budget_scenes})")
    if batch_size is not None and batch_size < 1:
        raise ValueError(f"batch_size must be at least 1, not {batch_size}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be at least 1, not {workers}")
    if only is not None:
        from harness.checks import checks

        known = {c.name for c in checks(only=set(only))}
        if set(only) - known:
            raise ValueError(f"unknown check{'s' if len(set(only) - known) > 1 else ''} {', '.join(sorted(set(only) - known))} "
                             f"(known: {', '.join(c.name for c in checks())})")
    if isinstance(scheduler, str):
        scheduler = scheduler_address(scheduler)  # (before any work)
    spec = _portable_spec(spec)
    rasterizer = load(spec, import_timeout=timeout)
    with state_lock(state_dir):
        return _run_locked(spec, rasterizer, budget_seconds, budget_scenes, families, seed, state_dir, scheduler, workers,
                           batch_size, only, timeout, on_progress, scheduler_timeout)


def _run_locked(spec: str, rasterizer: Rasterizer, budget_seconds: float | None, budget_scenes: int | None,
                families: tuple[str, ...], seed: int, state_dir: Path | str, scheduler: str | Client | None,
                workers: int | None, batch_size: int | None, only: Sequence[str] | None, timeout: float,
                on_progress: Callable[[ProgressEvent], None] | None, scheduler_timeout: float) -> CampaignState:
    """:func:`run_campaign` once its arguments are checked and its state is locked."""
    state = CampaignState.open(state_dir, spec, rasterizer.name, seed, only)
    fingerprint, identified = _identify(rasterizer, timeout)
    if identified is not None:
        state.identified = identified
    if fingerprint is not None:
        atomic_write_bytes(Path(state.directory) / IDENTIFIED_FILE, pickle.dumps(fingerprint))
    kept, skipped = _taken_families(rasterizer, families, seed)
    state.families = tuple(dict.fromkeys(state.families + families))
    state.skipped.update(skipped)
    state.batch_size = batch_size
    state.save()
    if not kept:
        return state
    with _dask(scheduler, workers, scheduler_timeout) as client:
        _Coordinator(client, state, spec, fingerprint, kept, budget_seconds, budget_scenes, batch_size,
                     None if only is None else frozenset(only), timeout, on_progress).run()
    return state
