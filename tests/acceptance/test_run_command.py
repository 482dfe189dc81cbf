"""The run command a CI user leans on: filters, shards, skip lists, reruns, budgets,
output paths checked first, Ctrl-C (issues 12 and 13; Ctrl-C on identify: issue 30)."""

import contextlib
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from harness.cli.main import main

LATTICE = ["--case", "lattice/bits-*", "--no-fingerprints"]


def _json(path):
    return json.loads(path.read_text())["results"]


def test_case_and_check_filters_select_exactly(tmp_path):
    out = tmp_path / "r.json"
    code = main(["run", "--rasterizer", "centre_scanline", *LATTICE, "--check", "conformance", "--out", str(tmp_path / "rep"),
                 "--json", str(out)])
    results = _json(out)
    assert code == 0 and results and {r["check"] for r in results} == {"conformance"}
    assert all(r["case"].startswith("lattice/bits-") for r in results)


def test_shards_partition_the_run(tmp_path):
    """The union of the shards is the whole run, and no case runs in two shards."""
    def cases(*extra):
        out = tmp_path / f"{'-'.join(extra) or 'all'}.json".replace("/", "of")
        main(["run", "--rasterizer", "centre_scanline", "--no-fingerprints", "--check", "hygiene", "--out", str(tmp_path / "rep"),
              "--json", str(out), *extra])
        return [r["case"] for r in _json(out)]

    whole = cases()
    shards = [cases("--shard", f"{k}/3") for k in (1, 2, 3)]
    assert sorted(whole) == sorted(c for s in shards for c in s) and len(whole) > 50
    assert all(set(a).isdisjoint(b) for i, a in enumerate(shards) for b in shards[i + 1:])


def test_a_skip_list_skips_with_its_reasons(tmp_path):
    skips = tmp_path / "skip.txt"
    skips.write_text("# known slow\nlattice/bits-0   # upstream bug 123\ncentre_scanline:lattice/bits-2\n")
    out = tmp_path / "r.json"
    main(["run", "--rasterizer", "centre_scanline", *LATTICE, "--skip", str(skips), "--out", str(tmp_path / "rep"), "--json", str(out)])
    by_case = {}
    for r in _json(out):
        by_case.setdefault(r["case"], []).append(r)
    assert [r["message"] for r in by_case["lattice/bits-0"]] == ["skipped: upstream bug 123"]
    assert by_case["lattice/bits-2"][0]["status"] == "skip" and len(by_case["lattice/bits-2"]) == 1
    assert any(r["check"] == "conformance" for r in by_case["lattice/bits-4"])


def test_rerun_tells_a_flake_from_a_failure(tmp_path):
    from cases.suites import suite
    from harness import run_suite
    from tests.known_bad.misc import Flaky, WrongTieClaim

    cases = [c for c in suite("quick") if c.id == "lattice/bits-0"]
    flaky = [r for r in run_suite([Flaky()], cases=cases, rerun=2, isolate=False) if r.check == "conformance"]
    assert flaky and all("flaky" in r.evidence and r.message.startswith("flaky (fail / pass") for r in flaky)
    assert all("repro" not in r.evidence for r in flaky)
    steady = [r for r in run_suite([WrongTieClaim()], cases=cases, rerun=2) if r.status == "fail"]
    assert steady and all("flaky" not in r.evidence and r.evidence["reruns"] == ["fail"] * 3 for r in steady)


def test_a_run_budget_makes_the_rest_errors_not_passes(tmp_path):
    from cases.suites import suite
    from harness import run_suite

    cases = suite("quick")[:30]
    results = run_suite(["centre_scanline"], cases=cases, deadline=time.monotonic() - 1)
    assert len(results) == 30 and all(r.status == "error" and "time budget" in r.message for r in results)
    assert main(["run", "--rasterizer", "centre_scanline", *LATTICE, "--max-seconds", "0.001", "--out", str(tmp_path)]) == 1


@pytest.mark.parametrize("option, kind", [("--out", "file"), ("--json", "dir"), ("--junit", "dir"), ("--out", "unwritable")])
def test_bad_output_paths_are_usage_errors_before_any_work(tmp_path, capsys, monkeypatch, option, kind):
    target = tmp_path / "x"
    if kind == "file":
        target.write_text("")
    elif kind == "dir":
        target.mkdir()
    else:
        target = "/proc/rastercheck-out"
    def no_work(*args, **kwargs):
        raise AssertionError("work started before the output paths were checked")

    monkeypatch.setattr("harness.cli.run._load_all", no_work)
    code = main(["run", "--rasterizer", "centre_scanline", "--no-fingerprints", option, str(target)]
                + ([] if option == "--out" else ["--out", str(tmp_path / "rep")]))
    err = capsys.readouterr().err
    assert code == 2 and option in err and "Traceback" not in err


def test_unknown_check_or_case_glob_is_a_usage_error(capsys):
    assert main(["run", "--rasterizer", "centre_scanline", "--check", "nope"]) == 2
    assert main(["run", "--rasterizer", "centre_scanline", "--case", "nothing/*"]) == 2
    with pytest.raises(SystemExit):
        main(["run", "--shard", "4/3"])


def test_stale_temp_files_of_killed_writes_are_swept(tmp_path):
    from harness.results.files import prepare_folder

    stale = tmp_path / ".index.html.999999.abcdefgh.partial"
    stale.write_text("half")
    mine = tmp_path / f".index.html.{os.getpid()}.abcdefgh.partial"
    mine.write_text("being written")
    prepare_folder(tmp_path, "--out")
    assert not stale.exists() and mine.exists()


def test_ctrl_c_stops_a_parallel_run_within_seconds_and_keeps_what_finished(tmp_path):
    """Ctrl-C while two rasterizers run side by side: exit 130 within seconds, the finished
    results written, no worker left. The interrupt comes once the slow one has finished a
    case (it marks its second call: with conformance alone, one call a case), not after a
    fixed time, which under load could fall before the run even started."""
    token = f"ctrlc-{os.getpid()}"
    marker = tmp_path / "second-call"
    plugin = tmp_path / "slow.py"
    plugin.write_text(
        "import time\n"
        "from rasterizers.centre_scanline import CentreScanline\n"
        "class Slow(CentreScanline):\n"
        "    name = 'slow'\n"
        "    calls = 0\n"
        "    def rasterize(self, scene):\n"
        "        Slow.calls += 1\n"
        "        if Slow.calls == 2:  # its first case is judged and kept\n"
        f"            open({str(marker)!r}, 'w').close()\n"
        "        time.sleep(0.3)\n"
        "        return super().rasterize(scene)\n"
    )
    out = tmp_path / token
    # `python -m harness.cli.main` with Ctrl-C raising KeyboardInterrupt, as in a terminal, even
    # where this test runs with SIGINT ignored (a background job of a shell: the child would
    # inherit that, and never see the interrupt)
    cli = ("import runpy, signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
           "runpy.run_module('harness.cli.main', run_name='__main__', alter_sys=True)")
    proc = subprocess.Popen([sys.executable, "-c", cli, "run", "--rasterizer", f"{plugin}:Slow", "--rasterizer",
                             "centre_scanline", "--check", "conformance", "--no-fingerprints", "--jobs", "2", "--out", str(out),
                             "--json", str(out / "r.json")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=os.getcwd(), start_new_session=True,
                            env={**os.environ, "PYTHONFAULTHANDLER": "1"})  # SIGABRT dumps every thread's stack
    try:
        waited = time.monotonic()
        while not marker.exists():  # the slow one needs 0.3 s a case, dozens of cases: the run is still going
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() - waited < 120, "the slow rasterizer was not called twice in 120 s"
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        try:
            _, err = proc.communicate(timeout=10)  # stopped at once: a run that went on would time out here
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGABRT)
            proc.wait(30)
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)  # its workers hold the pipes open
            raise AssertionError(f"still running 10 s after Ctrl-C; where it was:\n{proc.communicate()[1][-8000:]}") from None
    finally:
        if proc.poll() is None:  # a failure above: leave nothing running
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    results = _json(out / "r.json")  # the partial results were written: the slow one's first case at least
    assert "slow" in {r["rasterizer"] for r in results}, results
    left = subprocess.run(["pgrep", "-f", token], capture_output=True, text=True).stdout.split()
    assert not left, f"worker processes left behind: {left}"


def test_ctrl_c_stops_identify_within_seconds_leaving_no_process(tmp_path):
    """Ctrl-C while ``identify`` probes a slow rasterizer (in its forked worker): exit
    non-zero within 5 s, one line and no traceback, no worker left. The interrupt comes once
    the worker has answered a call (a marker file), not after a fixed time."""
    token = f"ctrlc-identify-{os.getpid()}"
    marker = tmp_path / "answered"
    plugin = tmp_path / f"{token}.py"
    plugin.write_text(
        "import time\n"
        "from rasterizers.centre_scanline import CentreScanline\n"
        "class Slow(CentreScanline):\n"
        "    name = 'slow'\n"
        "    convention = None\n"
        "    def rasterize(self, scene):\n"
        f"        open({str(marker)!r}, 'w').close()\n"
        "        time.sleep(0.3)\n"
        "        return super().rasterize(scene)\n"
    )
    cli = ("import runpy, signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
           "runpy.run_module('harness.cli.main', run_name='__main__', alter_sys=True)")
    proc = subprocess.Popen([sys.executable, "-c", cli, "identify", f"{plugin}:Slow"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=os.getcwd(), start_new_session=True)
    try:
        waited = time.monotonic()
        while not marker.exists():  # hundreds of probe calls of 0.3 s: identify is still going
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() - waited < 120, "the slow rasterizer was not called in 120 s"
            time.sleep(0.05)
        time.sleep(0.5)  # in the middle of a call or between two
        proc.send_signal(signal.SIGINT)
        sent = time.monotonic()
        try:
            _, err = proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            raise AssertionError("identify still running 30 s after Ctrl-C") from None
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:  # a failure above: leave nothing running
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert took < 5, f"identify took {took:.1f} s to stop"
    assert proc.returncode == 130, err
    assert "Traceback" not in err and err.strip().count("\n") == 0 and "interrupted" in err, err
    time.sleep(0.5)  # a worker watching for its parent's end polls every second at most
    left = subprocess.run(["pgrep", "-f", token], capture_output=True, text=True).stdout.split()
    assert not left, f"worker processes left behind: {left}"


def test_diff_classifies_every_change_and_writes_a_page(tmp_path, capsys):
    from harness.checks import Result
    from harness.results.output import write_json

    def run(path, rows):
        write_json(path, [Result(*row) for row in rows], "custom", 0, {"r": "declared"})
        return str(path)

    a = run(tmp_path / "a.json", [
        ("r", "c1", "conformance", "pass", "ok", {"missing": 0.0, "seconds": 0.1}, {}),
        ("r", "c2", "conformance", "fail", "bad", {"missing": 3.0}, {}),
        ("r", "c3", "watertight", "pass", "ok", {"holes": 0.0}, {}),
        ("r", "c4", "hygiene", "fail", "bad", {}, {}),
        ("r", "gone", "hygiene", "pass", "ok", {}, {}),
    ])
    b = run(tmp_path / "b.json", [
        ("r", "c1", "conformance", "fail", "now bad", {"missing": 2.0, "seconds": 0.3}, {}),
        ("r", "c2", "conformance", "pass", "ok", {"missing": 0.0}, {}),
        ("r", "c3", "watertight", "pass", "ok", {"holes": 0.0}, {}),
        ("r", "c4", "hygiene", "error", "crashed", {}, {}),
        ("r", "born", "hygiene", "pass", "ok", {}, {}),
    ])
    assert main(["diff", a, b, "--out", str(tmp_path / "d")]) == 1
    out = capsys.readouterr().out
    assert "regression: 1, fix: 1, status change: 1, new: 1, removed: 1" in out and "unchanged: 1" in out
    assert "REGRESSION     r c1 conformance: pass -> fail" in out and "seconds" not in out
    page = (tmp_path / "d" / "diff.html").read_text()
    assert "c1" in page and "now bad" in page and "Metric changes (2)" in page
    assert main(["diff", b, b, "--out", str(tmp_path / "d")]) == 0
    (tmp_path / "x.json").write_text("{")
    assert main(["diff", a, str(tmp_path / "x.json")]) == 2


def test_identify_writes_json_and_exits_1_when_the_declared_convention_is_contradicted(tmp_path, capsys):
    out = tmp_path / "f.json"
    assert main(["identify", "centre_scanline", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["fingerprint"]["exact"] and data["contradicted"] is False and data["verdict"] == "confirmed"
    code = main(["identify", "tests/known_bad/misc.py:WrongTieClaim", "--json", str(out)])
    said = capsys.readouterr().out
    assert code == 1 and "NOT what it does" in said
    assert json.loads(out.read_text())["contradicted"] is True
    assert main(["identify", "centre_scanline", "--json", str(tmp_path)]) == 2
