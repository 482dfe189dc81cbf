"""``rastercheck bench`` against hostile rasterizers (tests/known_bad/bench_hostile.py): a
raise, a ``None`` answer, a segfault, ``os._exit(0)``, a hang, a crash on a warm run, an
exit in a path workload. Each is that contender's row and one line naming it and its
fault; Pillow, the oracles and a well-behaved rasterizer beside it are still measured;
the exit code is 1. Bad ``--json`` paths are refused before any work, and the campaign
bench of a rasterizer whose every call fails measures nothing and judges no speed-up.

The workloads are the smallest (``--scale 0.01 --budget 0``, one kind); no timing assertion."""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path
from typing import Any

import pytest

from harness.cli.bench import Measurement, failures_by_contender, format_table, write_json
from harness.cli.bench_campaign import CAMPAIGN_GOAL, CampaignMeasurement, campaign_summary, format_campaign_table
from harness.cli.main import main

HOSTILE = "tests/known_bad/bench_hostile.py"
SMALL = ["--scale", "0.01", "--budget", "0"]
GOOD = "pineda_topleft"  # a well-behaved rasterizer beside the hostile one
TRIANGLE_ROWS = {"pillow", "oracle", "oracle_area", "oracle_msaa4", "oracle_msaa8"}
PATH_ROWS = {"pillow", "oracle"}


def _bench(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(["bench", *SMALL, *argv])
    said = capsys.readouterr()
    return code, said.out, said.err


def _rows(out: str) -> dict[str, dict[str, str]]:
    """``{workload: {contender: the rest of its row}}`` of the printed table."""
    rows: dict[str, dict[str, str]] = {}
    work = ""
    for line in out.splitlines():
        if not line.startswith(" ") and ": " in line and not line.startswith(("failed:", "not measured:", "json:")):
            work = line.split(":")[0]
            rows[work] = {}
        elif line.startswith("  ") and work and not line.strip().startswith("contender"):
            label, _, rest = line.strip().partition(" ")
            rows[work][label] = rest.strip()
    return rows


FAULTS = {
    "BenchRaises": "raised ValueError: refuses",
    "BenchAnswersNone": "no coverage (rasterize returned NoneType, not a harness.Coverage)",
    "BenchSegfaults": "crashed (signal 11, SIGSEGV)",
    "BenchExits": "its process exited with code 0 without answering",
    "BenchCrashesWhenWarm": "crashed (signal 11, SIGSEGV)",
}


@pytest.fixture(scope="module")
def failing_bench(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One bench of every failing contender of FAULTS beside a well-behaved one (each is
    forked on its own: one's fault cannot touch another's row)."""
    import contextlib
    import io

    out_json = tmp_path_factory.mktemp("bench") / "bench.json"
    argv = ["--kinds", "triangles", "--timeout", "30", "--json", str(out_json), "--rasterizer", GOOD]
    for name in FAULTS:
        argv += ["--rasterizer", f"{HOSTILE}:{name}"]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["bench", *SMALL, *argv])
    return {"code": code, "out": out.getvalue(), "err": err.getvalue(), "json": json.loads(out_json.read_text())}


@pytest.mark.parametrize("name, fault", FAULTS.items())
def test_a_failing_rasterizer_is_its_own_row_and_the_others_are_measured(name: str, fault: str,
                                                                         failing_bench: dict[str, Any]) -> None:
    code, out, err = failing_bench["code"], failing_bench["out"], failing_bench["err"]
    assert code == 1, (out, err)
    assert "Traceback" not in out + err
    rows = _rows(out)
    assert list(rows) == ["W1", "W2"]
    for work, row in rows.items():
        assert row[name].startswith(fault), (work, row[name])
        assert set(row) >= TRIANGLE_ROWS | {GOOD}
        for label in TRIANGLE_ROWS | {GOOD}:  # measured: a rate, a ratio, times and pixels
            figures = row[label].replace(",", "").split()
            assert len(figures) == 5 and all(math.isfinite(float(f)) for f in figures), (work, label, row[label])
    said = [line for line in out.splitlines() if line.startswith(f"failed: {name}:")]
    assert said == [f"failed: {name}: nothing measured: {said[0].split('nothing measured: ', 1)[1]}"]
    assert fault in said[0] and "W1" in said[0] and "W2" in said[0]
    data = failing_bench["json"]
    assert {(r["workload"], r["contender"]) for r in data["failed"] if r["contender"] == name} == {("W1", name), ("W2", name)}
    assert {r["contender"] for r in data["failed"]} == set(FAULTS)  # and no other
    measured = {r["contender"] for r in data["results"]}
    assert measured >= TRIANGLE_ROWS | {GOOD} and name not in measured
    assert all(r["fault"] == "" and r["seconds"] > 0 for r in data["results"])


def test_a_hang_times_out_at_the_limit_and_the_others_are_measured(capsys: pytest.CaptureFixture[str]) -> None:
    started = time.monotonic()
    code, out, err = _bench(capsys, "--kinds", "triangles", "--timeout", "1", "--rasterizer", f"{HOSTILE}:BenchHangs",
                            "--rasterizer", GOOD)
    assert code == 1 and "Traceback" not in out + err
    rows = _rows(out)
    assert [row["BenchHangs"] for row in rows.values()] == ["timed out after 1 s"] * 2
    assert all(set(row) >= TRIANGLE_ROWS | {GOOD} and "timed out" not in row[GOOD] for row in rows.values())
    assert "failed: BenchHangs: nothing measured: timed out after 1 s (W1, W2)" in out
    assert time.monotonic() - started < 25  # two calls of 1 s cut off, not an hour's sleep


def test_a_rasterizer_that_exits_in_a_path_workload_does_not_pass_silently(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _bench(capsys, "--kinds", "paths", "--timeout", "30", "--rasterizer", f"{HOSTILE}:BenchExitsOnPaths")
    assert code == 1 and "Traceback" not in out + err
    rows = _rows(out)
    assert list(rows) == ["P1-nonzero", "P1-evenodd", "P2-nonzero", "P2-evenodd", "P3-nonzero", "P3-evenodd"]
    for row in rows.values():
        assert row["BenchExitsOnPaths"] == "its process exited with code 0 without answering"
        assert set(row) >= PATH_ROWS
    assert out.count("failed: BenchExitsOnPaths: nothing measured:") == 1


def test_well_behaved_contenders_exit_0(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _bench(capsys, "--kinds", "lines", "--timeout", "30")
    assert code == 0, (out, err)
    assert "failed:" not in out and set(_rows(out)) == {"L1", "L2"}


# -- output paths: refused in one line, before any work ---------------------------------------


def _refused(capsys: pytest.CaptureFixture[str], argv: list[str], monkeypatch: pytest.MonkeyPatch) -> str:
    import harness.cli.bench
    import harness.cli.bench_campaign

    def no_work(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("the bench started before its output path was checked")

    monkeypatch.setattr(harness.cli.bench, "run_bench", no_work)
    monkeypatch.setattr(harness.cli.bench_campaign, "run_campaign_bench", no_work)
    assert main(["bench", *argv]) == 2
    said = capsys.readouterr()
    assert said.out == "" and len(said.err.strip().splitlines()) == 1 and "Traceback" not in said.err
    return said.err


@pytest.mark.parametrize("campaign", [[], ["--campaign"]])
def test_a_folder_as_json_is_refused_before_any_work(campaign: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    err = _refused(capsys, [*campaign, "--json", str(tmp_path)], monkeypatch)
    assert f"--json {tmp_path} is a folder, not a file" in err


def test_a_json_in_a_missing_folder_is_refused_and_the_folder_not_made(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "no-such-folder" / "bench.json"
    err = _refused(capsys, ["--json", str(path)], monkeypatch)
    assert f"--json {path}: its folder {path.parent} does not exist" in err and not path.parent.exists()


def test_a_json_under_a_file_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "a-file").write_text("")
    path = tmp_path / "a-file" / "bench.json"
    assert f"its folder {path.parent} is a file" in _refused(capsys, ["--json", str(path)], monkeypatch)


def test_a_json_in_an_unwritable_folder_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        if os.access(folder, os.W_OK):  # root writes anywhere: a read-only file system's folder instead
            folder = Path("/proc/self")
        err = _refused(capsys, ["--json", str(folder / "bench.json")], monkeypatch)
    finally:
        (tmp_path / "locked").chmod(0o700)
    assert f"{folder}" in err and "cannot be written" in err


# -- the table, the summary lines and the JSON of failed rows -----------------------------------


def test_failed_rows_print_their_fault_and_the_json_keeps_them_apart(tmp_path: Path) -> None:
    nan = float("nan")
    rows = [Measurement("W1", "pillow", nan, nan, nan, nan, 0, fault="crashed (signal 11, SIGSEGV)"),
            Measurement("W1", "mine", 0.1, 0.01, 100.0, nan, 50),
            Measurement("W2", "pillow", 0.0, 0.02, 50.0, 1.0, 40),
            Measurement("W2", "mine", nan, nan, nan, nan, 0, fault="timed out after 60 s")]
    table = format_table(rows, {})
    assert "pillow              crashed (signal 11, SIGSEGV)" in table and "mine                timed out after 60 s" in table
    assert "         -" in table  # no yardstick on W1: no ratio
    assert failures_by_contender(rows) == {"pillow": "crashed (signal 11, SIGSEGV) (W1); measured on W2",
                                           "mine": "timed out after 60 s (W2); measured on W1"}
    write_json(rows, tmp_path / "b.json")
    data = json.loads((tmp_path / "b.json").read_text())  # strict JSON: no NaN
    assert [(r["workload"], r["contender"], r["ratio_to_pillow"]) for r in data["results"]] == [("W1", "mine", None),
                                                                                                ("W2", "pillow", 1.0)]
    assert data["failed"] == [{"workload": "W1", "contender": "pillow", "fault": "crashed (signal 11, SIGSEGV)"},
                              {"workload": "W2", "contender": "mine", "fault": "timed out after 60 s"}]


def test_no_speed_up_is_judged_from_failed_calls() -> None:
    """A campaign whose calls failed (some of them: the warm-up passed) reports no goal met,
    however fast the failures were."""
    one = CampaignMeasurement("campaign", "flaky", 1, 100, 1000, 40, 1.0, 1.0, 100.0, 1000.0, 1000.0, 1.0, failed_calls=40)
    two = CampaignMeasurement("campaign", "flaky", 2, 100, 1000, 40, 0.25, 1.0, 400.0, 4000.0, 2000.0, 4.0, failed_calls=40)
    summary = campaign_summary([one, two])
    assert summary["met"] is False and "80 findings of failed rasterize calls" in summary["not_judged"]
    table = format_campaign_table([one, two])
    assert "goal met" not in table and "met)" not in table and "speed-up not judged: 80 findings" in table
    clean = [CampaignMeasurement(**{**{f: getattr(m, f) for f in m.__dataclass_fields__}, "failed_calls": 0}) for m in (one, two)]
    assert campaign_summary(clean)["met"] is (CAMPAIGN_GOAL <= 4.0) and "goal >= 1.7x: met" in format_campaign_table(clean)


def test_the_speed_up_is_judged_over_one_worker_on_one_core_and_the_figures_per_core() -> None:
    """Where one worker was also held to one core, the speed-up judged is two workers' over
    it (a free worker draws in its rasterizer's process on the other core while it checks);
    the figures per core are the least of two workers' per worker and the one-core run's."""
    def run(workers: int, cores: int, seconds: float) -> CampaignMeasurement:
        rate = 6000 / seconds
        return CampaignMeasurement("campaign", "ref", workers, 6000, 175_000, 0, seconds, 1.0, rate, rate * 29.2,
                                   rate * 29.2 / workers, 0.0, cores=cores)

    free, two, core = run(1, 0, 12.0), run(2, 0, 8.4), run(1, 1, 16.3)
    two = CampaignMeasurement(**{**{f: getattr(two, f) for f in two.__dataclass_fields__}, "speedup": 12.0 / 8.4})
    summary = campaign_summary([free, two, core])
    assert summary["met"] is True and summary["speedup_over_one_core"] == pytest.approx(16.3 / 8.4, abs=1e-3)
    assert summary["speedup"] == pytest.approx(12.0 / 8.4, abs=1e-3)  # said, not judged
    assert summary["scenes_per_second_per_core"] == pytest.approx(3000 / 8.4, abs=0.1) and summary["throughput_met"]
    slow_core = run(1, 1, 9.0)  # two workers barely beat one core: not met, however the free run compares
    assert campaign_summary([free, two, slow_core])["met"] is False
    table = format_campaign_table([free, two, core])
    assert "over one worker on one core: 1.94x (goal >= 1.7x: met)" in table and "1 worker on one core" in table
    assert "scenes per core-hour" in table


def test_the_campaign_bench_of_a_rasterizer_raising_on_every_call_measures_nothing(monkeypatch: pytest.MonkeyPatch,
                                                                                   tmp_path: Path,
                                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("distributed")
    import harness.cli.bench_campaign

    monkeypatch.setattr(harness.cli.bench_campaign, "CAMPAIGN_FAMILIES", ("lattice",))
    out_json = tmp_path / "campaign.json"
    code = main(["bench", "--campaign", "--rasterizer", f"{HOSTILE}:BenchRaises", "--scenes", "4", "--repeats", "1",
                 "--timeout", "30", "--json", str(out_json)])
    said = capsys.readouterr()
    assert code == 1, said
    assert "goal" not in said.out and "speed-up" not in said.out and "Traceback" not in said.err
    lines = [line for line in said.err.splitlines() if line.startswith("rastercheck:")]
    assert len(lines) == 1 and f"{HOSTILE}:BenchRaises: nothing measured" in lines[0] and "ValueError: refuses" in lines[0]
    assert not out_json.exists()


def test_a_garbage_answer_is_refused_or_counted_without_its_malformed_spans(capsys: pytest.CaptureFixture[str]) -> None:
    """A million copies of one span: beyond the span limit of W2's one triangle (refused, its
    row the fault), within W1's (measured, the copies not counted, and said)."""
    code, out, err = _bench(capsys, "--kinds", "triangles", "--timeout", "30",
                            "--rasterizer", "tests.known_bad.hostile:MillionCopies", "--rasterizer", GOOD)
    assert code == 1 and "Traceback" not in out + err
    rows = _rows(out)
    assert rows["W2"]["MillionCopies"].startswith("garbage: an answer of 1,000,")
    assert "not counted: 1,000,000 spans repeated" in rows["W1"]["MillionCopies"]
    assert rows["W1"]["MillionCopies"].split()[4] == rows["W1"][GOOD].split()[4]  # the same pixels: the copies left out
    assert "failed: MillionCopies: garbage: an answer of" in out and "(W2); measured on W1" in out
