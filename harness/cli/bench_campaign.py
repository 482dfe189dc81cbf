"""The campaign workload of the bench (``rastercheck bench --campaign``; :func:`run_campaign_bench`):
a campaign (:func:`harness.campaign.coordinator.run_campaign`) of a fixed scene budget on a
built-in reference (``pineda_topleft``: it passes, so nothing is shrunk) over every fuzz family
it takes, first on a ``LocalCluster`` of one worker process, then of two
(:func:`harness.campaign.cluster.local_cluster`, as a campaign starts by default): end-to-end
checked primitives per second per worker, and the speed-up from one worker to two. The
workers are started and warmed (the harness imported, the kernels loaded, one scene of each
family checked) before the clock starts: the figure is a campaign's steady state.
"""

from __future__ import annotations

import os
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from harness.campaign.cluster import local_cluster
from harness.cli.bench import CampaignMeasurement, _one_line

__all__ = ["CampaignMeasurement", "run_campaign_bench", "format_campaign_table", "campaign_summary", "CAMPAIGN_REFERENCE",
           "CAMPAIGN_SCENES", "CAMPAIGN_GOAL", "per_scene_breakdown", "CAMPAIGN_SCENES_GOAL", "CAMPAIGN_PRIMITIVES_GOAL",
           "CAMPAIGN_BATCH", "CAMPAIGN_FAMILIES", "CAMPAIGN_REPEATS", "NothingMeasured"]

if TYPE_CHECKING:
    from distributed import Client


CAMPAIGN_REFERENCE = "pineda_topleft"  # a built-in that passes: no finding, nothing shrunk
# about 20 s of search on one worker here: a run long enough that its fixed costs (the first and last batches) weigh as
# little as in a campaign of minutes
CAMPAIGN_SCENES = 6000
CAMPAIGN_GOAL = 1.7  # the speed-up from one worker to two that the issue asks for
CAMPAIGN_REPEATS = 3  # rounds of 1 then 2 workers; the fastest run of each is kept
# scenes per batch, fixed: both campaigns check the very same scenes (0.2 .. 1 s a batch here; a campaign's own batches
# are sized to about a second each, coordinator.TARGET_BATCH_SECONDS)
CAMPAIGN_BATCH = 100
CAMPAIGN_FAMILIES: tuple[str, ...] | None = None  # None: every fuzz family (those the rasterizer does not take are skipped)
CAMPAIGN_SEED = 0
WARM_SEED = 1  # the warm-up's scenes: not among those measured


class NothingMeasured(RuntimeError):
    """The rasterizer under a campaign bench failed every call of its warm-up: there is no
    throughput to measure (its text is the one line that says so)."""


def _failed_call(finding: Any) -> bool:
    """A finding of a rasterize call that crashed, hung or raised (or answered no
    coverage): the ``run`` check's errors (:func:`harness.campaign.worker.run_batch`)."""
    return bool(finding.status == "error" and finding.check_name == "run")


def _warm(client: Client, spec: str, families: Sequence[str], timeout: float) -> None:
    """Every worker imports the harness, loads ``spec`` and checks one scene of each
    family (kernels loaded, trimesh imported), so that the clock measures the search.

    Raises :class:`NothingMeasured` when every one of those scenes' rasterize calls failed
    (crashed, hung, raised, answered no coverage): a campaign of failed calls would time
    failures, not checks."""
    from harness.campaign.state import Batch, CampaignTask
    from harness.campaign.worker import run_batch

    addresses = sorted(client.scheduler_info()["workers"])
    futures = [client.submit(run_batch, CampaignTask(spec, Batch(family, WARM_SEED, 0, 1), timeout=timeout),
                             workers=[address], allow_other_workers=False, pure=False)
               for address in addresses for family in families]
    batches = client.gather(futures)
    failed = [f for batch in batches for f in batch.findings if _failed_call(f)]
    if batches and all(any(_failed_call(f) for f in batch.findings) for batch in batches):
        faults = list(dict.fromkeys(_one_line(f.message, 160) for f in failed))
        raise NothingMeasured(f"{spec}: nothing measured: every rasterize call of the warm-up failed "
                              f"({len(batches)} scene{'s' if len(batches) > 1 else ''}: {'; '.join(faults[:3])})")


def _failed_calls(signatures: dict[str, dict[str, Any]]) -> int:
    """The findings of failed rasterize calls among a campaign's ``signatures``."""
    return sum(int(entry.get("count", 0)) for entry in signatures.values() if entry.get("check") == "run")


# The parts of a scene's work, as the breakdown names them: the sections a worker keeps
# (harness.engine.ledger; "check:NAME" for each check), then what only adds up.
_PARTS = {"generation": "generation", "isolation": "IPC and isolation (sending scenes, reading answers)",
          "oracle": "oracle", "signatures": "signatures (failures classified)"}
CAMPAIGN_SCENES_GOAL = 1_000_000 / 3600  # scenes per second per worker: a million per core-hour
CAMPAIGN_PRIMITIVES_GOAL = 10_000.0  # primitives per second per worker


def per_scene_breakdown(sections: dict[str, float], scenes: int) -> dict[str, float]:
    """Milliseconds per scene of each part of a campaign's work, from the sections its
    workers and coordinator kept (:attr:`harness.campaign.state.ProgressEvent.sections`):
    generation, IPC and isolation, each check (``check NAME``), the oracle, the signatures,
    the rest of the workers' batch time (``other``: the checks' glue, results made plain
    data), and apart from those, the rasterizer's own time in its process (``rasterizer
    (its process)``, drawn while the worker checks), and the coordinator's merging and
    saving of the state (``state``).

    >>> per_scene_breakdown({"generation": 0.5, "check:watertight": 1.0, "note:batch": 2.0, "note:rasterizer": 0.25,
    ...                      "state": 0.1}, 1000)
    {'check watertight': 1.0, 'generation': 0.5, 'other': 0.5, 'rasterizer (its process)': 0.25, 'state': 0.1}
    """
    if scenes <= 0:
        return {}
    ms = 1000.0 / scenes
    out: dict[str, float] = {}
    kept = 0.0
    for name, seconds in sorted(sections.items(), key=lambda kv: -kv[1]):
        if name.startswith("note:") or name == "state":
            continue
        label = f"check {name[6:]}" if name.startswith("check:") else _PARTS.get(name, name)
        out[label] = round(seconds * ms, 4)
        kept += seconds
    if "note:batch" in sections:
        out["other"] = round(max(sections["note:batch"] - kept, 0.0) * ms, 4)
    if "note:rasterizer" in sections:
        out["rasterizer (its process)"] = round(sections["note:rasterizer"] * ms, 4)
    if "state" in sections:
        out["state"] = round(sections["state"] * ms, 4)
    return out


def run_campaign_bench(spec: str = CAMPAIGN_REFERENCE, scenes: int = CAMPAIGN_SCENES, worker_counts: Sequence[int] = (1, 2),
                       families: Sequence[str] | None = None, batch_size: int = CAMPAIGN_BATCH, repeats: int = CAMPAIGN_REPEATS,
                       timeout: float = 60.0, progress: Callable[[str], None] | None = None,
                       one_core: bool = True) -> list[CampaignMeasurement]:
    """The same campaign (``scenes`` scenes of ``families``, default all, under seed 0, in
    batches of ``batch_size``: the same scenes whatever the workers) on a fresh local
    cluster of each worker count in turn, each in a state folder of its own; the whole
    round ``repeats`` times, and the fastest run of each count kept (other processes on
    the machine only ever slow a run down: the rounds interleave the counts, so a busy
    spell costs each the same).

    Parameters
    ----------
    spec : str
        The rasterizer (:func:`harness.engine.registry.load`); a built-in reference by default.
    scenes : int
        The scene budget of each campaign.
    worker_counts : sequence of int
        Worker processes of each cluster, in order; the speed-ups are against the first.
    families : sequence of str, optional
        Fuzz families (:data:`cases.fuzz.FAMILIES`); those the rasterizer does not take
        are skipped by the campaign.
    batch_size : int
        Scenes per batch (fixed, unlike a campaign's default: with sizes adapted to the
        time measured the two campaigns would check different scenes).
    repeats : int
        Rounds over the worker counts.
    progress : callable, optional
        Hears a line before and after each measurement.
    one_core : bool
        Also one worker with everything it runs on (its rasterizer's process, the
        coordinator) held to one core (``cores`` 1; Linux only): the throughput of a
        core, where the free one-worker campaign draws in its rasterizer's process on the
        other core while it checks.

    Returns
    -------
    list of CampaignMeasurement
        One per worker count, in order: its fastest run (``runs``: the seconds of each),
        then the one-core run.

    Raises
    ------
    NothingMeasured
        When every rasterize call of the warm-up failed (:func:`_warm`).
    """
    from cases.fuzz import FAMILIES
    from harness.campaign.coordinator import run_campaign
    from harness.campaign.state import ProgressEvent

    if scenes < 1:
        raise ValueError(f"the campaign bench needs at least one scene, not {scenes}")
    if not worker_counts or any(n < 1 for n in worker_counts):
        raise ValueError(f"worker counts must be at least 1, not {list(worker_counts)}")
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, not {repeats}")
    chosen = tuple(families or CAMPAIGN_FAMILIES or FAMILIES)
    # (workers, cores): every worker count free to use the machine, and one worker held to one core
    configurations = [(n, 0) for n in worker_counts] + ([(1, 1)] if one_core and _can_pin() else [])
    best: dict[tuple[int, int], CampaignMeasurement] = {}
    runs: dict[tuple[int, int], list[float]] = {c: [] for c in configurations}
    for round_ in range(repeats):
        for workers, cores in configurations:
            said = (f"campaign on {workers} worker{'s' if workers > 1 else ''}{' on one core' if cores else ''} "
                    f"(round {round_ + 1} of {repeats})")
            if progress is not None:
                progress(f"{said}: starting and warming the workers ...")
            started = time.perf_counter()
            with _on_one_core(bool(cores)), local_cluster(workers) as client, \
                    tempfile.TemporaryDirectory(prefix="rastercheck-bench-") as state_dir:
                _warm(client, spec, chosen, timeout)
                startup = time.perf_counter() - started
                events: list[ProgressEvent] = []
                state = run_campaign(spec, budget_scenes=scenes, families=chosen, seed=CAMPAIGN_SEED, state_dir=state_dir,
                                     scheduler=client, batch_size=batch_size, timeout=timeout, on_progress=events.append)
            last = events[-1] if events else None
            seconds = last.elapsed if last is not None else 0.0
            checked = last.scenes if last is not None else 0
            primitives = last.primitives if last is not None else 0
            rate = primitives / seconds if seconds > 0 else 0.0
            runs[(workers, cores)].append(round(seconds, 3))
            taken = [f for f in chosen if f not in state.skipped]
            measured = CampaignMeasurement(
                "campaign", spec, workers, checked, primitives, state.findings, seconds, startup,
                checked / seconds if seconds > 0 else 0.0, rate, rate / workers, 0.0,
                failed_calls=_failed_calls(state.signatures), cores=cores,
                breakdown=per_scene_breakdown(last.sections if last is not None else {}, checked),
                description=(f"{scenes:,} fuzz scenes of {', '.join(taken) or 'no family'} (seed {CAMPAIGN_SEED}, batches of "
                             f"{batch_size}), checked end to end; the fastest of {repeats} run{'s' if repeats > 1 else ''}"))
            if (workers, cores) not in best or measured.primitives_per_second > best[(workers, cores)].primitives_per_second:
                best[(workers, cores)] = measured
            if progress is not None:
                progress(f"{said}: {checked:,} scenes, {primitives:,} primitives in {seconds:.1f} s ({rate:,.0f} primitives/s; "
                         f"startup {startup:.1f} s)")
    base = best[(worker_counts[0], 0)].primitives_per_second
    return [replace(best[c], speedup=best[c].primitives_per_second / base if base > 0 else 0.0, runs=tuple(runs[c]))
            for c in dict.fromkeys(configurations)]


def _can_pin() -> bool:
    """Whether this system lets a process be held to one core (Linux's sched_setaffinity)."""
    return hasattr(os, "sched_setaffinity") and hasattr(os, "sched_getaffinity")


@contextmanager
def _on_one_core(pin: bool) -> Iterator[None]:
    """With ``pin``: this thread, and so every thread and process started from it while
    inside (the cluster's scheduler, its workers, their rasterizers' processes), held to
    one core (the lowest this process may use); as before on leaving."""
    if not pin or not _can_pin():
        yield
        return
    before = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(before)})
    try:
        yield
    finally:
        os.sched_setaffinity(0, before)


def _unjudged(results: Sequence[CampaignMeasurement]) -> str:
    """Why no speed-up can be judged from ``results`` ("" when one can): rasterize calls
    that failed in them."""
    failed = sum(m.failed_calls for m in results)
    if not failed:
        return ""
    return (f"{failed:,} finding{'s' if failed > 1 else ''} of failed rasterize calls (crashed, hung or raised) "
            f"in the campaigns: the figures time failures")


def _label(m: CampaignMeasurement) -> str:
    return f"{m.workers} worker{'s' if m.workers > 1 else ''}" + (" on one core" if m.cores else "")


def _per_core(results: Sequence[CampaignMeasurement]) -> tuple[float, float]:
    """Scenes and primitives per second per core: the least of each free run's per worker
    (its workers share the machine's cores) and the one-core run's own."""
    rates = [(m.scenes_per_second / max(m.workers, m.cores), m.primitives_per_second / max(m.workers, m.cores))
             for m in results if m.cores or m.workers > 1] or [(m.scenes_per_second, m.primitives_per_second) for m in results]
    return min(r[0] for r in rates), min(r[1] for r in rates)


def campaign_summary(results: Sequence[CampaignMeasurement]) -> dict[str, Any]:
    """The speed-up from the first worker count to the last (the free runs) and of the last
    over one worker on one core, the latter judged against the goal where it was measured
    (not met, and why, when rasterize calls failed in the campaigns); scenes and primitives per second per core
    (:func:`_per_core`) against a million scenes per core-hour and 10,000 primitives/s;
    and the scenes a 10-minute campaign on the most workers covers."""
    free = [m for m in results if not m.cores]
    if len(free) < 2:
        return {"goal": CAMPAIGN_GOAL}
    first, last = free[0], free[-1]
    one = next((m for m in results if m.cores), None)
    why = _unjudged(results)
    scenes, primitives = _per_core(results)
    # the speed-up judged: over one worker on one core where there is that run (a free worker's
    # rasterizer draws on another core while it checks: two workers then gain less than two cores do)
    over_core = last.scenes_per_second / one.scenes_per_second if one is not None and one.scenes_per_second > 0 else None
    judged = over_core if over_core is not None else last.speedup
    return {"from_workers": first.workers, "to_workers": last.workers, "speedup": round(last.speedup, 3),
            "goal": CAMPAIGN_GOAL, "met": not why and judged >= CAMPAIGN_GOAL, **({"not_judged": why} if why else {}),
            **({"speedup_over_one_core": round(over_core, 3)} if over_core is not None else {}),
            "scenes_per_second_per_core": round(scenes, 1), "scenes_per_core_hour": round(scenes * 3600),
            "primitives_per_second_per_core": round(primitives), "scenes_goal": round(CAMPAIGN_SCENES_GOAL, 1),
            "primitives_goal": CAMPAIGN_PRIMITIVES_GOAL,
            "throughput_met": not why and scenes >= CAMPAIGN_SCENES_GOAL and primitives >= CAMPAIGN_PRIMITIVES_GOAL,
            "ten_minute_campaign_scenes": round(last.scenes_per_second * 600)}


def format_campaign_table(results: Sequence[CampaignMeasurement]) -> str:
    """The campaign measurements, one line per configuration, the speed-up, the figures
    per core against their goals, and where a scene's time goes."""
    if not results:
        return "campaign: nothing measured"
    lines = [f"campaign: {results[0].contender}, {results[0].description}",
             f"  {'run':<22}{'scenes':>9}{'primitives':>12}{'seconds':>9}{'scenes/s':>10}{'primitives/s':>14}"
             f"{'per worker':>12}{'speed-up':>10}{'startup s':>11}"]
    for m in results:
        lines.append(f"  {_label(m):<22}{m.scenes:>9,}{m.primitives:>12,}{m.seconds:>9.1f}{m.scenes_per_second:>10.1f}"
                     f"{m.primitives_per_second:>14,.0f}{m.per_worker:>12,.0f}{m.speedup:>9.2f}x{m.startup_seconds:>11.1f}"
                     + (f"   runs: {', '.join(f'{r:.1f}' for r in m.runs)} s" if len(m.runs) > 1 else ""))
    why = _unjudged(results)
    summary = campaign_summary(results)
    if why:
        lines.append(f"speed-up not judged: {why}")
    elif "speedup_over_one_core" in summary:
        verdict = "met" if summary["met"] else "NOT met"
        lines.append(f"speed-up of {summary['to_workers']} workers over one worker on one core: "
                     f"{summary['speedup_over_one_core']:.2f}x (goal >= {CAMPAIGN_GOAL}x: {verdict}); over one free worker "
                     f"(its rasterizer drawing on another core while it checks): {summary['speedup']:.2f}x")
    elif "speedup" in summary:
        verdict = "met" if summary["met"] else "NOT met"
        lines.append(f"speed-up from {summary['from_workers']} to {summary['to_workers']} workers: {summary['speedup']:.2f}x "
                     f"(goal >= {CAMPAIGN_GOAL}x: {verdict})")
    if not why and "scenes_per_second_per_core" in summary:
        verdict = "met" if summary["throughput_met"] else "NOT met"
        lines.append(f"per core: {summary['scenes_per_second_per_core']:,.0f} scenes/s = {summary['scenes_per_core_hour']:,} "
                     f"scenes per core-hour, {summary['primitives_per_second_per_core']:,} primitives/s (goal >= "
                     f"{CAMPAIGN_SCENES_GOAL:,.0f} scenes/s and >= {CAMPAIGN_PRIMITIVES_GOAL:,.0f} primitives/s: {verdict}); "
                     f"a 10-minute campaign on {summary['to_workers']} workers covers {summary['ten_minute_campaign_scenes']:,} "
                     "scenes")
    for m in results:
        if m.breakdown:
            total = sum(v for k, v in m.breakdown.items() if k not in ("rasterizer (its process)", "state"))
            lines.append(f"where a scene's time goes, {_label(m)} (ms per scene; {total:.3f} in the workers' batches, "
                         "the rasterizer's own process and the coordinator's state apart):")
            lines += [f"  {name:<58}{ms:>8.3f}" for name, ms in m.breakdown.items()]
    return "\n".join(lines)
