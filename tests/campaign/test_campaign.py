"""Campaigns on a real Dask LocalCluster of two worker processes: a known bug found and
grouped, a worker killed mid-campaign losing no finding, a resumed campaign repeating no
scene, two campaigns merged, crashes and hangs as findings, the held-out rare bug found."""

from __future__ import annotations

import json
import os
import pickle
import signal
import time
from pathlib import Path
from typing import Any

import pytest

from harness.campaign.cluster import local_cluster
from harness.campaign.coordinator import run_campaign
from harness.campaign.state import Batch, BatchResult, CampaignState, CampaignTask, ProgressEvent, SceneFinding, add_interval
from harness.campaign.worker import run_batch
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.engine.runner import replay
from harness.identify.fingerprint import Fingerprint
from harness.oracle.coverage import exact_coverage
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.warm import safe_numba_cache

distributed = pytest.importorskip("distributed")

INCLUSIVE = "tests.campaign.test_campaign:inclusive"
RARE = "tests.known_bad.rare:RareSlopeTie"


def inclusive() -> EdgeFunctionBug:
    """The edge-function rasterizer whose every edge owns its ties, as a zero-argument spec."""
    return EdgeFunctionBug("inclusive")


class Explosive:
    """Exact (the default convention), but once it has answered in a Dask worker it dies on
    scenes of 5k triangles and hangs on scenes of 5k + 1, when asked again too: a marker
    file named after the worker (the parent of every process its isolation forks) says it
    has answered."""

    name = "bad_explosive"
    convention = Convention()
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        import tempfile

        answered = Path(tempfile.gettempdir()) / f"rastercheck-explosive-{os.getppid()}"
        if answered.exists() and len(scene) % 5 == 0:
            os._exit(3)
        if answered.exists() and len(scene) % 5 == 1:
            while True:
                time.sleep(0.05)
        answered.touch()
        return exact_coverage(scene, self.convention)


class BottomRightBox:
    """Draws bottom-right ties and declares no convention (a black box)."""

    name = "bottom_right_box"
    convention = None
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(scene, Convention(tie="bottom-right"))


class SafeNumbaCache(distributed.WorkerPlugin):
    """Numba's cache made safe for processes compiling side by side (as in every test
    worker: :func:`tests.warm.safe_numba_cache`), in each Dask worker as it starts."""

    def setup(self, worker: Any) -> None:
        safe_numba_cache()


@pytest.fixture(scope="module")
def cluster():  # type: ignore[no-untyped-def]
    """One LocalCluster of two single-threaded worker processes for the module, as a
    campaign makes its own (:func:`harness.campaign.cluster.local_cluster`)."""
    with local_cluster(2) as client:
        client.register_plugin(SafeNumbaCache())  # every worker, as every test worker, shares the numba cache safely
        # each worker imports the harness and loads the kernels once, before any test's clock runs
        warm = [client.submit(run_batch, CampaignTask("pineda_topleft", Batch("lattice", 0, 0, 1)), workers=[address], pure=False)
                for address in client.run(os.getpid)]
        client.gather(warm)
        yield client.cluster, client


def _merged(events: list[ProgressEvent]) -> list[Batch]:
    return [e.batch for e in events if e.batch is not None]


def _points(batches: list[Batch]) -> list[tuple[str, int, int]]:
    return [(b.family, b.seed, i) for b in batches for i in b.indices()]


def _ranges(points: list[tuple[str, int, int]]) -> dict[tuple[str, int], list[tuple[int, int]]]:
    done: dict[tuple[str, int], list[tuple[int, int]]] = {}
    for family, seed, index in points:
        done[(family, seed)] = add_interval(done.get((family, seed), []), index, index + 1)
    return done


def _findings(findings: Any) -> list[tuple[Any, ...]]:
    return sorted((f.family, f.seed, f.index, f.check, f.status, f.signature_key) for f in findings)


def test_a_resumed_campaign_repeats_no_scene_and_a_correct_rasterizer_has_no_finding(cluster, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    local, _ = cluster
    first: list[ProgressEvent] = []
    second: list[ProgressEvent] = []
    families = ["lattice", "float", "degenerate", "partitions"]
    # stopped by time: batches in flight at the deadline are cancelled, not done
    run_campaign("pineda_topleft", budget_seconds=1.0, families=families, state_dir=tmp_path,
                 scheduler=local.scheduler_address, on_progress=first.append)
    before = CampaignState.load(tmp_path)
    state = run_campaign("pineda_topleft", budget_scenes=60, families=families, state_dir=tmp_path,
                         scheduler=local.scheduler_address, on_progress=second.append)
    runs = [_points(_merged(first)), _points(_merged(second))]
    assert runs[0] and len(runs[1]) == 60
    assert before.done == _ranges(runs[0])  # only the batches merged are done, none cancelled at the deadline
    every = runs[0] + runs[1]
    assert len(every) == len(set(every))  # no scene twice
    assert state.scenes == before.scenes + 60 == len(every)
    assert state.done == _ranges(every)
    assert state.signatures == {} and second[-1].findings == 0
    assert second[-1].finished and second[-1].scenes_per_second > 0 and second[-1].primitives_per_second > 0


def test_crashes_and_hangs_are_findings_and_the_campaign_finishes(cluster, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    local, _ = cluster
    state = run_campaign("tests.campaign.test_campaign:Explosive", budget_scenes=12, families=["lattice"], state_dir=tmp_path,
                         scheduler=local.scheduler_address, batch_size=6, timeout=1.0, only=["conformance"])
    assert state.scenes == 12 and state.done == {("lattice", 0): [(0, 12)]}
    assert {"run|crash|none", "run|hang|none"} <= set(state.signatures)
    crash = state.signatures["run|crash|none"]
    assert "died" in crash["message"] and (tmp_path / crash["repro"]).is_file()


def test_the_held_out_rare_bug_is_found_within_a_modest_budget(cluster, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    local, _ = cluster
    state = run_campaign(RARE, budget_scenes=60, families=["lattice", "float", "degenerate", "paths"], state_dir=tmp_path,
                         scheduler=local.scheduler_address)
    assert set(state.skipped) == {"paths"} and state.scenes == 60  # it takes triangles only
    assert list(state.signatures) == ["conformance|exact-tie-slanted-edge|tie-rule"]
    repro = tmp_path / state.signatures["conformance|exact-tie-slanted-edge|tie-rule"]["repro"]
    assert len(json.loads(repro.read_text())["positions"]) == 1
    assert any(r.check == "conformance" and r.status == "fail" for r in replay(repro, RARE, identify=False))
    # a signature left without its repro (a run stopped while shrinking) is shrunk by the next run
    repro.unlink()
    state.signatures["conformance|exact-tie-slanted-edge|tie-rule"]["repro"] = None
    state.save()
    again = run_campaign(RARE, budget_scenes=1, families=["float"], state_dir=tmp_path, scheduler=local.scheduler_address)
    assert again.signatures["conformance|exact-tie-slanted-edge|tie-rule"]["repro"] == repro.relative_to(tmp_path).as_posix()
    assert repro.is_file() and again.scenes == 61


# -- without a cluster ------------------------------------------------------------------------


def _result(batch: Batch, keys: dict[int, str]) -> BatchResult:
    findings = tuple(SceneFinding(batch.family, batch.seed, i, "conformance", "fail", f"wrong at {i}", key, key.split("|")[1],
                             key.split("|")[2], "conformance") for i, key in sorted(keys.items()))
    return BatchResult(batch, batch.count, 10 * batch.count, 0.5, findings, "here")


def test_a_batch_is_merged_once_and_the_state_survives_a_reload(tmp_path: Path) -> None:
    state = CampaignState(tmp_path, "spec", "name")
    assert state.record(_result(Batch("lattice", 0, 0, 8), {3: "c|a|tie-rule", 5: "c|a|tie-rule"}), 1.0) == ["c|a|tie-rule"]
    assert state.record(_result(Batch("lattice", 0, 0, 8), {3: "c|a|tie-rule"}), 2.0) is None  # a duplicate completion
    assert state.record(_result(Batch("lattice", 0, 8, 4), {9: "c|b|none"}), 3.0) == ["c|b|none"]
    with pytest.raises(ValueError, match=r"lattice/0/10..13 overlaps scenes already done \(10..11\)"):
        state.record(_result(Batch("lattice", 0, 10, 4), {}), 4.0)
    assert state.scenes == 12 and state.findings == 3 and state.done == {("lattice", 0): [(0, 12)]}
    assert state.signatures["c|a|tie-rule"]["examples"] == [["lattice", 0, 3], ["lattice", 0, 5]]
    state.save()
    again = CampaignState.load(tmp_path)
    assert again.to_json() == state.to_json()
    assert [str(b) for b, _ in zip(again.next_batches(["lattice"], 5), range(2))] == ["lattice/0/12..16", "lattice/0/17..21"]
    (tmp_path / "campaign.json").write_text("{\"schema\": 1}")
    with pytest.raises(ValueError, match="campaign.json: malformed campaign state"):
        CampaignState.load(tmp_path)
    with pytest.raises(ValueError, match="no campaign state here"):
        CampaignState.load(tmp_path / "elsewhere")
    assert pickle.loads(pickle.dumps(CampaignTask("s", Batch("a", 1, 2, 3)))) == CampaignTask("s", Batch("a", 1, 2, 3))


def test_two_campaigns_merge_when_disjoint_and_refuse_an_overlap(tmp_path: Path) -> None:
    a = CampaignState(tmp_path / "a", "spec", "name")
    a.record(_result(Batch("lattice", 0, 0, 10), {2: "c|a|tie-rule"}), 1.0)
    b = CampaignState(tmp_path / "b", "spec", "name", seed=1)
    b.record(_result(Batch("lattice", 1, 0, 10), {4: "c|a|tie-rule", 6: "c|b|none"}), 1.0)
    b.record(_result(Batch("float", 1, 0, 5), {}), 2.0)
    (tmp_path / "b" / "repros").mkdir(parents=True)
    (tmp_path / "b" / "repros" / "x.json").write_text("{}")
    b.signatures["c|b|none"]["repro"] = "repros/x.json"
    a.merge(b)
    assert a.scenes == 25 and a.primitives == 250 and a.findings == 3
    assert a.done == {("lattice", 0): [(0, 10)], ("lattice", 1): [(0, 10)], ("float", 1): [(0, 5)]}
    assert a.signatures["c|a|tie-rule"]["count"] == 2
    assert a.signatures["c|a|tie-rule"]["examples"] == [["lattice", 0, 2], ["lattice", 1, 4]]
    assert (tmp_path / "a" / a.signatures["c|b|none"]["repro"]).read_text() == "{}"
    assert a.history[-1][1:] == [25, 3]
    c = CampaignState(tmp_path / "c", "spec", "name")
    c.record(_result(Batch("lattice", 1, 5, 10), {}), 1.0)
    with pytest.raises(ValueError, match=r"both checked lattice/1 scenes 5..9"):
        a.merge(c)
    with pytest.raises(ValueError, match="on 'other'"):
        a.merge(CampaignState(tmp_path / "d", "spec", "other"))


def test_a_worker_judges_a_black_box_by_the_coordinators_fingerprint() -> None:
    fingerprint = Fingerprint("bottom_right_box", Convention(), residual=0, pixels=1)
    spec = "tests.campaign.test_campaign:BottomRightBox"
    judged = run_batch(CampaignTask(spec, Batch("lattice", 0, 0, 6), fingerprint, frozenset({"conformance"})))
    assert judged.findings and {f.signature_key.split("|")[0] for f in judged.findings} == {"conformance"}
    unjudged = run_batch(CampaignTask(spec, Batch("lattice", 0, 0, 6), None, frozenset({"conformance"})))
    assert unjudged.findings == () and unjudged.primitives == 0  # no convention: conformance skips


def test_bad_arguments_are_refused_naming_them(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="needs a budget"):
        run_campaign("pineda_topleft", state_dir=tmp_path)
    with pytest.raises(ValueError, match="unknown case family 'cubes'"):
        run_campaign("pineda_topleft", budget_scenes=1, families=["cubes"], state_dir=tmp_path)
    with pytest.raises(ValueError, match="unknown check conformity"):
        run_campaign("pineda_topleft", budget_scenes=1, only=["conformity"], state_dir=tmp_path)
    with pytest.raises(ValueError, match="no_such_thing"):
        run_campaign("no_such_thing", budget_scenes=1, state_dir=tmp_path)
    CampaignState(tmp_path, "centre_scanline", "centre_scanline").save()
    with pytest.raises(ValueError, match="of a campaign on 'centre_scanline'"):
        run_campaign("pineda_topleft", budget_scenes=1, state_dir=tmp_path)
    with pytest.raises(ValueError, match="this campaign runs every check, not only conformance"):
        run_campaign("centre_scanline", budget_scenes=1, only=["conformance"], state_dir=tmp_path)


# last: the cluster has one worker left after it


def test_two_workers_find_the_bug_and_a_killed_worker_loses_no_finding(cluster, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    local, client = cluster
    pids = client.run(os.getpid)
    killed: dict[str, Any] = {}
    events: list[ProgressEvent] = []

    def kill_a_busy_worker(event: ProgressEvent) -> None:
        events.append(event)
        if killed or event.batch is None:
            return
        busy = {address: keys for address, keys in client.processing().items()
                if any(str(k).startswith("rastercheck-batch-") for k in keys)}
        if not busy:
            return  # every batch in flight ended this instant: at the next one
        address, keys = sorted(busy.items())[0]
        killed.update(address=address, keys=[str(k) for k in keys if str(k).startswith("rastercheck-batch-")])
        nanny = next(n for n in local.workers.values() if n.worker_address == address)
        nanny.close_gracefully()  # lost for good (a machine gone): not restarted
        os.kill(pids[address], signal.SIGKILL)

    state = run_campaign(INCLUSIVE, budget_scenes=60, families=["lattice"], state_dir=tmp_path, scheduler=local.scheduler_address,
                         batch_size=6, timeout=30.0, on_progress=kill_a_busy_worker)

    # every batch merged exactly once, all 60 scenes done once
    assert killed, "no worker was busy to be killed"
    batches = _merged(events)
    assert len(batches) == len(set(batches)) == 10
    assert sorted(_points(batches)) == [("lattice", 0, i) for i in range(60)]
    assert state.done == {("lattice", 0): [(0, 60)]} and state.scenes == 60
    # the batches given to the killed worker (running or waiting there) were redone by the other;
    # one that ended in the instant before the kill counts once
    lost = {b for b in batches if any(k.endswith(f"-lattice-0-{b.start}-{b.count}") for k in killed["keys"])}
    redone = {e.batch for e in events if e.batch in lost and e.worker != killed["address"]}
    assert len(lost) == len(killed["keys"]) and redone
    # the same findings as the same scenes checked in one process, one after another
    serial = run_batch(CampaignTask(INCLUSIVE, Batch("lattice", 0, 0, 60), timeout=30.0))
    found = [f for e in events for f in e.batch_findings]
    assert _findings(found) == _findings(serial.findings)
    counts: dict[str, int] = {}
    for f in serial.findings:
        counts[f.signature_key] = counts.get(f.signature_key, 0) + 1
    assert {k: s["count"] for k, s in state.signatures.items()} == counts
    assert events[-1].finished and events[-1].signatures == counts
    # its bug is found (ties owned by every edge), grouped, and each group shrunk to a repro that replays
    ties = [k for k in state.signatures if k.startswith("conformance|exact-tie-") and k.endswith("|tie-rule")]
    assert ties
    saved = CampaignState.load(tmp_path)
    assert saved.signatures == state.signatures
    for key in ties:
        repro = tmp_path / state.signatures[key]["repro"]
        data = json.loads(repro.read_text())
        assert data["signature"] == key and data["check"] == "conformance" and data["rasterizer"] == "bad_inclusive"
        assert len(data["positions"]) <= 2
        assert any(r.check == "conformance" and r.status == "fail" for r in replay(repro, inclusive(), identify=False))


def test_ctrl_c_stops_a_campaign_in_seconds_quietly_keeping_its_batches(tmp_path):
    """Ctrl-C in a terminal reaches the whole process group: every Dask worker and nanny
    printed a KeyboardInterrupt traceback of its own (four on two workers). Now: exit 130
    within seconds, one line, the merged batches kept, no process left."""
    import contextlib
    import os
    import signal
    import subprocess
    import sys
    import time

    token = f"fuzz-ctrlc-{os.getpid()}"
    state = tmp_path / token
    # Ctrl-C raising KeyboardInterrupt, as in a terminal, even where this test runs with SIGINT
    # ignored (a background job of a shell: the child would inherit that)
    cli = ("import runpy, signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
           "runpy.run_module('harness.cli.main', run_name='__main__', alter_sys=True)")
    proc = subprocess.Popen([sys.executable, "-c", cli, "fuzz", "--rasterizer", "pineda_topleft", "--budget", "10m",
                             "--families", "lattice", "--workers", "2", "--batch", "4", "--state", str(state),
                             "--out", str(tmp_path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        waited = time.monotonic()
        while not (state / "campaign.json").exists() or not CampaignState.load(state).scenes:
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() - waited < 120, "no batch merged in 120 s"
            time.sleep(0.1)
        os.killpg(proc.pid, signal.SIGINT)  # as the terminal does: to the whole group
        stopped = time.monotonic()
        _, err = proc.communicate(timeout=30)
        took = time.monotonic() - stopped
    finally:
        if proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == 130 and took < 10, (proc.returncode, took, err[-3000:])
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err[-3000:]
    assert "interrupted; the state in" in err and CampaignState.load(state).scenes >= 4, err[-3000:]
    time.sleep(1)
    left = [p for p in subprocess.run(["pgrep", "-g", str(proc.pid)], capture_output=True, text=True).stdout.split()
            if subprocess.run(["ps", "-o", "stat=", "-p", p], capture_output=True, text=True).stdout.strip()[:1] not in ("Z", "")]
    assert not left, f"processes left behind: {subprocess.run(['ps', '-o', 'pid,etime,cmd', *left], capture_output=True, text=True).stdout}"


def test_a_state_with_three_disjoint_done_ranges_loads_again(tmp_path):
    """Batches finished out of order leave several disjoint ranges: the check on load
    compared every range with every other, the middle one with itself, and refused the
    state ("not sorted disjoint"): a resumed or interrupted campaign lost it."""
    state = CampaignState(tmp_path, "spec", "name")
    for start in (0, 8, 16):
        state.record(BatchResult(Batch("lattice", 0, start, 4), 4, 40, 0.1, (), "w"), 1.0)
    state.save()
    assert CampaignState.load(tmp_path).done == {("lattice", 0): [(0, 4), (8, 12), (16, 20)]}
    data = json.loads(state.path.read_text())
    data["done"][0]["intervals"] = [[0, 4], [3, 12]]  # overlapping: still refused
    state.path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="not sorted disjoint"):
        CampaignState.load(tmp_path)


@pytest.mark.parametrize("hostile", ["ArraysDetonate", "CoverageDetonates", "RaisesDetonating", "RaisesUnprintableDetonating",
                                     "NamedDetonating"])
def test_nothing_a_plugin_returns_is_unpickled_in_the_coordinator_or_a_dask_worker(cluster, tmp_path: Path,
                                                                                  hostile: str) -> None:  # type: ignore[no-untyped-def]
    """A campaign's Dask workers send the coordinator batches and repros, by pickle: only
    plain data may be in them. Hostile answers (tests/known_bad/hostile_pickles.py: a
    coverage, its arrays, an exception or its text, the rasterizer's name, whose
    ``__reduce__`` writes the unpickling process's pid to a marker) run nowhere: not in the
    coordinator (this process), not in a Dask worker, and the campaign's findings are the
    plugin's (a correct answer none, a raise one signature with a repro)."""
    local, client = cluster
    marker = tmp_path / "detonated"
    plugin = tmp_path / f"hostile_{hostile.lower()}.py"
    plugin.write_text(f"from tests.known_bad.hostile_pickles import {hostile}\n\n\n"
                      f"def make():\n    return {hostile}({str(marker)!r})\n")
    state = run_campaign(f"{plugin}:make", budget_scenes=4, families=["lattice"], state_dir=tmp_path / "state",
                         scheduler=local.scheduler_address, batch_size=2, only=["conformance"])
    ran = marker.read_text().split() if marker.exists() else []
    homes = {str(os.getpid()): "the coordinator", **{str(pid): f"Dask worker {where}" for where, pid in client.run(os.getpid).items()}}
    assert not ran, f"hostile code ran in {[homes.get(pid, f'process {pid}') for pid in ran]}"
    assert state.scenes == 4
    if hostile in ("ArraysDetonate", "CoverageDetonates"):
        assert state.signatures == {}
    else:
        assert len(state.signatures) == 1
        (entry,) = state.signatures.values()
        assert (tmp_path / "state" / entry["repro"]).is_file()
