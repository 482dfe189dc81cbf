"""The campaign's front end: ``rastercheck fuzz`` (budgets, progress, state, page, JSON,
exit codes, merging), the campaign page, ``gate --known-campaign`` and ``bench
--campaign``. The campaigns run on one Dask LocalCluster of one worker process shared by
the module (``--scheduler``; a second worker would double the cost of starting them:
tests/campaign/test_campaign.py runs two, and kills one); the known-bad campaign runs once and its
result is read by every test that needs one."""

from __future__ import annotations

import contextlib
import io
import json
import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest

from harness.campaign.cluster import local_cluster
from harness.campaign.state import Batch, BatchResult, CampaignState, ProgressEvent, SceneFinding
from harness.checks import Result
from harness.cli.fuzz import _budget, _FuzzProgress
from harness.cli.main import main
from harness.report.campaign_page import write_campaign_page
from harness.results.gate import CampaignFindings, campaign_known, compare_with_baseline
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.warm import safe_numba_cache

distributed = pytest.importorskip("distributed")

SPEC = "tests.acceptance.test_fuzz_command:inclusive"
TIE = "conformance|exact-tie-slanted-edge|tie-rule"


def inclusive() -> EdgeFunctionBug:
    """Every edge owns its ties (tinyrenderer's ``< 0``): a zero-argument spec."""
    return EdgeFunctionBug("inclusive")


VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


class _Balance(HTMLParser):
    """Every element opened is closed, in order (void elements aside)."""

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[str] = []
        self.faults: list[str] = []

    def handle_starttag(self, tag: str, attrs: Any) -> None:
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag: str) -> None:
        if not self.stack or self.stack[-1] != tag:
            self.faults.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'}")
        else:
            self.stack.pop()


def _well_formed(html: str) -> None:
    parser = _Balance()
    parser.feed(html)
    parser.close()
    assert html.startswith("<!doctype html>") and not parser.faults and not parser.stack, (parser.faults, parser.stack)


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """One LocalCluster of one single-threaded worker process for the module: its address."""
    with local_cluster(1) as client:  # as a campaign makes its own: no port of its own fixed (8787 may be held)
        client.run(safe_numba_cache)
        assert client.scheduler is not None
        yield str(client.scheduler.address)


@pytest.fixture(scope="module")
def campaign(scheduler: str, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The known-bad campaign, run once through the command: its exit code, output and files."""
    root = tmp_path_factory.mktemp("campaign")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["fuzz", "--rasterizer", SPEC, "--budget", "16", "--families", "lattice,float", "--scheduler", scheduler,
                     "--state", str(root / "state"), "--out", str(root / "out"), "--json", str(root / "campaign.json")])
    return {"code": code, "stdout": out.getvalue(), "root": root, "state": root / "state"}


# -- usage ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("argv, culprit", [
    (["--rasterizer", "pineda_topleft", "--budget", "10x"], "'10x'"),
    (["--rasterizer", "pineda_topleft", "--budget", "0"], "'0'"),
    (["--rasterizer", "pineda_topleft", "--budget", "0s"], "'0s'"),
    (["--rasterizer", "pineda_topleft", "--budget", "m"], "'m'"),
    (["--rasterizer", "pineda_topleft", "--budget", "5", "--families", "lattice,cubes"], "'cubes'"),
    (["--rasterizer", "pineda_topleft", "--budget", "5", "--seed", "-1"], "'-1'"),
    (["--rasterizer", "pineda_topleft", "--budget", "5", "--workers", "0"], "'0'"),
])
def test_a_bad_argument_is_a_usage_error_naming_it(argv: list[str], culprit: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as info:
        main(["fuzz", *argv])
    assert info.value.code == 2 and culprit in capsys.readouterr().err


def test_a_missing_or_conflicting_option_is_a_usage_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fuzz", "--rasterizer", "pineda_topleft"]) == 2
    assert "--budget" in capsys.readouterr().err
    assert main(["fuzz", "--merge", str(tmp_path), "--rasterizer", "pineda_topleft"]) == 2
    assert "--merge" in capsys.readouterr().err
    (tmp_path / "file").write_text("")
    assert main(["fuzz", "--rasterizer", "pineda_topleft", "--budget", "5", "--out", str(tmp_path / "file")]) == 2
    assert "is a file" in capsys.readouterr().err
    assert main(["fuzz", "--rasterizer", "no_such_rasterizer", "--budget", "5", "--state", str(tmp_path / "s"),
                 "--out", str(tmp_path)]) == 2
    assert "no_such_rasterizer" in capsys.readouterr().err
    assert main(["bench", "--scenes", "5"]) == 2
    assert "--campaign" in capsys.readouterr().err


def test_budgets_read_as_durations_or_scenes() -> None:
    assert _budget("90s")[:2] == (90.0, None) and _budget("10m")[:2] == (600.0, None) and _budget("1h")[:2] == (3600.0, None)
    assert _budget("1h30m")[:2] == (5400.0, None) and _budget("2.5m")[:2] == (150.0, None)
    assert _budget("5000") == (None, 5000, "5,000 scenes")


def test_progress_in_ci_is_a_plain_line_every_few_seconds_and_new_signatures_at_once(capsys: pytest.CaptureFixture[str]) -> None:
    finding = SceneFinding("lattice", 0, 7, "conformance", "fail", "wrong", TIE, "exact-tie-slanted-edge", "tie-rule",
                           "conformance")
    event = ProgressEvent(120, 3400, 10.0, 12.0, 340.0, 150, 3, {TIE: 3}, 50.0, 2, Batch("lattice", 0, 0, 8), "w",
                          (finding,), (TIE,))
    with _FuzzProgress("1 min", quiet=True, every=0.05) as progress:
        progress(event)
        time.sleep(0.2)
    err = capsys.readouterr().err
    assert f"fuzz: new signature {TIE} on scene lattice/0/7" in err
    assert ("fuzz: 120 scenes, 3,400 primitives in 10 s (12.0 scenes/s, 340 primitives/s, 2 workers); "
            "3 findings in 1 signature") in err
    assert "budget 1 min, ETA 0:50" in err
    from rich.console import Console

    console = Console(record=True, width=100)
    console.print(progress)
    shown = console.export_text()
    assert "120 scenes this run (150 in the campaign)" in shown and "ETA 0:50" in shown and TIE in shown


# -- a campaign through the command --------------------------------------------------------------


def test_a_campaign_on_a_known_bad_rasterizer_writes_state_page_and_json_and_exits_1(campaign: dict[str, Any]) -> None:
    assert campaign["code"] == 1
    state = CampaignState.load(campaign["state"])
    assert state.scenes == 16 and state.rasterizer == "bad_inclusive" and TIE in state.signatures
    repro = campaign["state"] / state.signatures[TIE]["repro"]
    assert repro.is_file()
    # the summary: each signature with its count and repro
    assert TIE in campaign["stdout"] and str(repro) in campaign["stdout"]
    page = (campaign["root"] / "out" / "campaign.html").read_text()
    _well_formed(page)
    assert "<svg" in page and "findings (cumulative" in page and TIE in page
    assert 'src="data:image/' in page  # the repro drawn
    assert "rastercheck replay" in page and "generate(&#39;lattice&#39;, 0," in page
    href = os.path.relpath(repro, campaign["root"] / "out")
    assert f'href="{href}"' in page
    data = json.loads((campaign["root"] / "campaign.json").read_text())
    assert data["schema"] == 1 and data["rasterizer"] == "bad_inclusive" and data["totals"]["scenes"] == 16
    assert data["signatures"][TIE]["count"] == state.signatures[TIE]["count"] and data["run"]["scenes"] == 16
    assert data["described"][TIE]["replay"].startswith("rastercheck replay")


def test_a_correct_built_in_exits_0_and_a_rerun_continues(scheduler: str, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    args = ["fuzz", "--rasterizer", "pineda_topleft", "--budget", "6", "--families", "lattice", "--scheduler", scheduler,
            "--state", str(tmp_path / "state"), "--out", str(tmp_path), "--batch", "3"]
    assert main(args) == 0
    assert main(args) == 0  # resumed: the next six scenes
    state = CampaignState.load(tmp_path / "state")
    assert state.done == {("lattice", 0): [(0, 12)]} and not state.signatures
    assert "no findings" in capsys.readouterr().out
    _well_formed((tmp_path / "campaign.html").read_text())


def test_a_second_campaign_on_a_state_in_use_refuses_naming_the_holder(tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """Two campaigns on one state each saved their own copy over the other's (the second's
    12 scenes were lost): the second refuses, a merge into it too, before any work; the
    lock is the kernel's, so a holder killed with SIGKILL leaves the state free."""
    import signal
    import subprocess
    import sys

    from harness.campaign.state import state_lock

    state = tmp_path / "state"
    args = ["fuzz", "--rasterizer", "pineda_topleft", "--budget", "6", "--families", "lattice", "--state", str(state),
            "--out", str(tmp_path)]
    with state_lock(state):  # a campaign running on it
        assert main(args) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and f"another campaign is running on this state (pid {os.getpid()}, since " in err
        assert main(["fuzz", "--merge", str(tmp_path / "other"), "--state", str(state), "--out", str(tmp_path)]) == 2
        assert "another campaign is running on this state" in capsys.readouterr().err
    assert not (state / "campaign.json").exists()  # nothing was started
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom harness.campaign.state import state_lock\n"
                               f"with state_lock({str(state)!r}):\n    print('held', flush=True)\n    time.sleep(120)"],
                              stdout=subprocess.PIPE, text=True, cwd=Path(__file__).resolve().parents[2])
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        assert main(args) == 2 and f"(pid {holder.pid}, since " in capsys.readouterr().err
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait(30)
        if holder.stdout is not None:
            holder.stdout.close()
    with state_lock(state):  # free again
        pass


class _RefusesEverything:
    """Raises Unsupported for every scene: handed scenes, it has none judged."""

    name = "refuses_everything"
    convention = None

    def rasterize(self, scene: Any) -> Any:
        from harness.contract.scenes import Unsupported

        raise Unsupported("draws nothing at all")


def refuses_everything() -> _RefusesEverything:
    return _RefusesEverything()


@pytest.mark.parametrize("spec, families, why", [
    ("pineda_topleft", "lines", "pineda_topleft takes no scene of the families asked: lines ("),
    ("tests.acceptance.test_fuzz_command:refuses_everything", "lattice", "refuses_everything was handed 4 scenes but every check "
                                                                 "skipped them"),
])
def test_a_campaign_that_judges_nothing_exits_1_saying_why(scheduler: str, tmp_path: Path, spec: str, families: str,
                                                          why: str, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["fuzz", "--rasterizer", spec, "--budget", "4", "--families", families, "--scheduler", scheduler,
                 "--state", str(tmp_path / "state"), "--out", str(tmp_path), "--batch", "4"])
    err = capsys.readouterr().err
    assert code == 1 and f"rastercheck: nothing checked: {why}" in err, err


class _HangsAlways:
    """Declares the exact convention and never answers: every call, the first included, hangs."""

    name = "hangs_always"
    interpolates = False

    def __init__(self) -> None:
        from harness.contract.conventions import Convention

        self.convention = Convention()

    def rasterize(self, scene: Any) -> Any:
        while True:
            time.sleep(0.05)


def hangs_always() -> _HangsAlways:
    return _HangsAlways()


def test_a_campaign_workers_first_call_honours_timeout(scheduler: str, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    """The first call in a campaign's worker got 120 s whatever --timeout said (asked twice:
    4 minutes a hanging scene): it follows run's policy, the cap, so a scene that hangs takes
    about 2 + 2 s (asked again once)."""
    start = time.monotonic()
    code = main(["fuzz", "--rasterizer", "tests.acceptance.test_fuzz_command:hangs_always", "--budget", "1", "--families",
                 "lattice", "--scheduler", scheduler, "--state", str(tmp_path / "state"), "--out", str(tmp_path), "--batch", "1",
                 "--check", "conformance", "--timeout", "2"])
    took = time.monotonic() - start
    assert code == 1, capsys.readouterr().err
    assert took < 60, f"the campaign took {took:.0f} s"
    state = CampaignState.load(tmp_path / "state")
    assert state.scenes == 1 and "run|hang|none" in state.signatures
    assert "no answer within 2 s" in state.signatures["run|hang|none"]["message"]


def _fake(directory: Path, seed: int, keys: dict[int, str], rasterizer: str = "bad_inclusive") -> CampaignState:
    state = CampaignState(directory, SPEC, rasterizer, seed=seed)
    batch = Batch("lattice", seed, 0, 10)
    findings = tuple(SceneFinding("lattice", seed, i, "conformance", "fail", f"<b>wrong</b> at {i}", k, k.split("|")[1],
                             k.split("|")[2], "conformance") for i, k in keys.items())
    state.record(BatchResult(batch, 10, 100, 1.0, findings, "here"), 1.0)
    state.save()
    return state


def test_campaigns_merge_and_an_overlap_is_a_usage_error(campaign: dict[str, Any], tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    other = _fake(tmp_path / "other", 1, {3: TIE, 4: "conformance|near-tie|none"})
    merged = tmp_path / "merged"
    code = main(["fuzz", "--merge", str(campaign["state"]), str(other.directory), "--state", str(merged), "--out", str(tmp_path)])
    assert code == 1
    state = CampaignState.load(merged)
    first = CampaignState.load(campaign["state"])
    assert state.scenes == first.scenes + 10
    assert state.signatures[TIE]["count"] == first.signatures[TIE]["count"] + 1
    assert (merged / state.signatures[TIE]["repro"]).is_file()  # the repro came along
    assert "conformance|near-tie|none" in capsys.readouterr().out
    assert main(["fuzz", "--merge", str(other.directory), "--state", str(merged), "--out", str(tmp_path)]) == 2
    assert "both checked lattice/1 scenes 0..9" in capsys.readouterr().err
    _fake(tmp_path / "theirs", 2, {}, rasterizer="someone_else")
    assert main(["fuzz", "--merge", str(tmp_path / "theirs"), "--state", str(merged), "--out", str(tmp_path)]) == 2
    assert "someone_else" in capsys.readouterr().err


@pytest.mark.parametrize("field, value, said", [
    (("signatures", TIE), "a string",
     'at signatures["conformance|exact-tie-slanted-edge|tie-rule"]: \'a string\' is not of type \'object\''),
    (("signatures", TIE, "count"), "3", '"].count: \'3\' is not of type \'integer\''),
    (("signatures", TIE, "first"), None, '"]: lacks \'first\''),
    (("signatures", TIE, "repro"), "../../../etc/passwd", '"].repro: \'../../../etc/passwd\' is not valid (pattern'),
    (("history",), {"a": 1}, "at history: {'a': 1} is not of type 'array'"),
    (("history", 0), [1.0, "x", 0], "at history[0][1]: 'x' is not of type 'integer'"),
    (("totals", "scenes"), -4, "at totals.scenes: -4 is not valid (minimum 0)"),
    (("done",), None, "at done: None is not of type 'array'"),
])
def test_a_malformed_state_is_refused_in_one_line_naming_file_and_field(tmp_path: Path, field: tuple[Any, ...], value: Any,
                                                                       said: str, capsys: pytest.CaptureFixture[str]) -> None:
    """A state whose entries are of the wrong type or lack a key was a traceback when
    resumed or merged: it is refused before use, by schema, with the file and the field."""
    state = _fake(tmp_path / "bad", 1, {3: TIE})
    data = json.loads(state.path.read_text())
    where = data
    for key in field[:-1]:
        where = where[key]
    if field[-1] == "first" and value is None:
        del where["first"]
    else:
        where[field[-1]] = value
    state.path.write_text(json.dumps(data))
    for argv in (["fuzz", "--merge", str(state.directory), "--state", str(tmp_path / "merged"), "--out", str(tmp_path)],
                 ["fuzz", "--rasterizer", "pineda_topleft", "--budget", "2", "--state", str(state.directory), "--out",
                  str(tmp_path)]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and f"{state.path}: malformed campaign state at " in err and said in err, err


def test_a_file_where_the_repros_folder_belongs_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "state").mkdir()
    (tmp_path / "state" / "repros").write_text("not a folder")
    assert main(["fuzz", "--rasterizer", "pineda_topleft", "--budget", "2", "--state", str(tmp_path / "state"), "--out",
                 str(tmp_path)]) == 2
    assert "a file where the campaign keeps its repros (a folder)" in capsys.readouterr().err


def test_the_page_escapes_what_the_state_says(tmp_path: Path) -> None:
    state = _fake(tmp_path / "state", 0, {1: "conformance|<i>odd</i>|none"})
    state.signatures["conformance|<i>odd</i>|none"]["repro"] = "repros/missing.json"
    page = write_campaign_page(tmp_path / "out", state).read_text()
    _well_formed(page)
    assert "<b>wrong" not in page and "&lt;b&gt;wrong" in page and "<i>odd" not in page
    assert "the repro cannot be read" in page


# -- gate ----------------------------------------------------------------------------------------


def test_the_gate_takes_a_campaigns_findings_as_known_failures(campaign: dict[str, Any], tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    baseline = tmp_path / "baseline.json"
    baseline.write_text(json.dumps({"schema": 1, "entries": {}}))
    args = ["gate", "--rasterizer", SPEC, "--case", "lattice/bits-0", "--check", "conformance", "--no-fingerprints",
            "--baseline", str(baseline), "--out", str(tmp_path / "out")]
    assert main([*args, "--known-campaign", str(campaign["state"])]) == 0  # the same cause: known (without it: new, failing)
    said = capsys.readouterr().out
    assert "0 regressions" in said and "known failures (1 known from campaigns)" in said
    assert main([*args, "--known-campaign", str(tmp_path / "nowhere")]) == 2
    assert "no campaign state here" in capsys.readouterr().err
    _fake(tmp_path / "theirs", 0, {1: TIE}, rasterizer="someone_else")
    assert main([*args, "--known-campaign", str(tmp_path / "theirs")]) == 2
    assert "someone_else" in capsys.readouterr().err


def test_known_failures_match_by_case_and_check_or_by_signature(tmp_path: Path) -> None:
    _fake(tmp_path / "c", 0, {3: TIE})
    found = CampaignFindings.load(tmp_path / "c")
    assert found.cases[("conformance", "lattice/fuzz/lattice/0/3")] == TIE
    known = campaign_known([found], lambda r: {"a": TIE, "c": TIE}.get(r.case, "conformance|other|none"))
    run = [Result("bad_inclusive", "lattice/fuzz/lattice/0/3", "conformance", "fail", "x"),  # its scene
           Result("bad_inclusive", "a", "conformance", "fail", "x"),  # its signature
           Result("bad_inclusive", "b", "conformance", "fail", "x"),  # another cause: a regression
           Result("bad_inclusive", "c", "conformance", "fail", "x"),  # passed before: known now
           Result("someone_else", "a", "conformance", "fail", "x")]  # another rasterizer's
    verdict = compare_with_baseline(run, {"bad_inclusive|c|conformance": {"status": "pass"}}, known_failure=known)
    verdicts = {f.key: f.verdict for f in verdict.findings}
    assert verdicts == {"bad_inclusive|lattice/fuzz/lattice/0/3|conformance": "known", "bad_inclusive|a|conformance": "known",
                     "bad_inclusive|b|conformance": "regression", "bad_inclusive|c|conformance": "known",
                     "someone_else|a|conformance": "regression"}
    assert all("known from the campaign" in f.reason for f in verdict.of("known"))


# -- bench ---------------------------------------------------------------------------------------


def test_bench_campaign_reports_both_worker_counts_as_json(scheduler: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    """On the module's cluster for both counts (no cluster started here): the plumbing, not the timings."""
    import harness.cli.bench_campaign

    @contextmanager
    def shared(workers: int) -> Iterator[Any]:
        with distributed.Client(scheduler) as client:
            yield client

    monkeypatch.setattr(harness.cli.bench_campaign, "local_cluster", shared)
    monkeypatch.setattr(harness.cli.bench_campaign, "CAMPAIGN_FAMILIES", ("lattice",))
    out = tmp_path / "bench.json"
    assert main(["bench", "--campaign", "--scenes", "4", "--repeats", "1", "--json", str(out)]) == 0
    said = capsys.readouterr().out
    # both worker counts free, then one worker held to one core (where the system can pin processes)
    pinned = [(1, 1)] if hasattr(os, "sched_setaffinity") else []
    assert ("speed-up of 2 workers over one worker on one core" in said if pinned else "speed-up from 1 to 2 workers" in said)
    assert "primitives/s" in said
    data = json.loads(out.read_text())
    assert data["schema"] == 1 and [(r["workers"], r["cores"]) for r in data["results"]] == [(1, 0), (2, 0), *pinned]
    assert all(r["scenes"] == 4 and r["primitives"] > 0 and r["unit"] == "primitives" and len(r["runs"]) == 1
               for r in data["results"])
    assert data["summary"]["goal"] == 1.7 and "speedup" in data["summary"] and "scenes_per_core_hour" in data["summary"]
    assert "where a scene's time goes" in said and "IPC and isolation" in said and "per core:" in said


def test_findings_of_one_cause_seen_by_several_checks_are_one_cause(tmp_path: Path) -> None:
    """A scene failing conformance for culling: its watertight hole and invariance change
    are counted under culling; a hygiene attribute failure on it is its own cause; a hole
    on a scene where conformance passes stays a hole. Merged states add the counts up."""
    from harness.campaign.worker import attribute_causes

    def finding(index: int, check: str, failure_class: str, part: str = "none") -> SceneFinding:
        return SceneFinding("lattice", 0, index, check, "fail", "m", f"{check}|{failure_class}|{part}", failure_class, part,
                            check)

    scene = attribute_causes([finding(0, "conformance", "culling", "culling"), finding(0, "watertight", "hole"),
                              finding(0, "invariance", "changes-under-flip-winding"), finding(0, "hygiene", "bad-attributes")])
    assert [f.cause for f in scene] == ["culling", "culling", "culling", "attributes"]
    alone = attribute_causes([finding(1, "watertight", "hole")])
    assert [f.cause for f in alone] == ["hole"]
    states = []
    for k in range(2):
        state = CampaignState.open(tmp_path / f"s{k}", "spec", "r")
        state.record(BatchResult(Batch("lattice", 0, 10 * k, 10 * k + 2), 2, 20, 1.0, tuple(scene + alone), "here"), 1.0)
        states.append(state)
    causes = {g["cause"]: g for g in states[0].causes()}
    # the watertight hole signature, counted once under culling and once under its own, is
    # listed under the cause most of its findings had (a tie: the first by name)
    assert set(causes) == {"culling", "attributes"}
    assert set(causes["culling"]["checks"]) == {"conformance", "watertight", "invariance"} and causes["culling"]["findings"] == 4
    states[0].merge(states[1])
    assert states[0].signatures["watertight|hole|none"]["causes"] == {"culling": 2, "hole": 2}


def test_the_identified_convention_is_read_back_and_nothing_else(tmp_path: Path) -> None:
    """A black box's identified convention, kept beside the state, wraps it again for the
    page; a file naming any other global (a crafted pickle calling a function) is refused
    and the rasterizer comes back as it is."""
    import pickle

    from harness.campaign.state import IDENTIFIED_FILE
    from harness.contract.conventions import Convention
    from harness.identify.fingerprint import Fingerprint

    class BlackBox:
        name = "black_box"
        convention = None

        def rasterize(self, scene: Any) -> Any:
            raise NotImplementedError

    state = CampaignState.open(tmp_path, "spec", "black_box")
    box = BlackBox()
    assert state.judged(box) is box  # nothing identified yet
    (tmp_path / IDENTIFIED_FILE).write_bytes(pickle.dumps(Fingerprint("black_box", Convention(sample=(1.0, 1.0)), 0, 10)))
    judged = state.judged(box)
    assert judged is not box and judged.convention == Convention(sample=(1.0, 1.0))

    class Crafted:
        def __reduce__(self) -> tuple[Any, ...]:
            return (os.remove, (str(tmp_path / "victim"),))

    (tmp_path / "victim").write_text("still here")
    (tmp_path / IDENTIFIED_FILE).write_bytes(pickle.dumps(Crafted()))
    assert state.judged(box) is box and (tmp_path / "victim").read_text() == "still here"


def test_the_docs_table_row_reads_a_campaigns_state(campaign: dict[str, Any]) -> None:
    """docs/campaign_table.py (the tables of docs/campaigns.md): the known-bad's scenes,
    findings and causes as its state holds them, and whether its table's checks saw it."""
    import runpy

    table = runpy.run_path(str(Path(__file__).parents[2] / "docs" / "campaign_table.py"))
    state = CampaignState.load(campaign["state"])
    line = table["row"]("bad_inclusive", state, {"bad_inclusive": {"conformance", "degenerate"}})
    cells = [c.strip() for c in line.strip("|").split("|")]
    assert cells[:4] == ["`bad_inclusive`", "16", f"{state.findings:,}", str(len(state.signatures))]
    assert cells[5] == "yes: conformance (not degenerate)"  # lattice and float only: no degenerate scene
    assert cells[7].startswith(f"tie-rule {state.causes()[0]['findings']:,} (conformance")
    assert table["row"]("other", state, {}).split("|")[6].strip() == "-"
