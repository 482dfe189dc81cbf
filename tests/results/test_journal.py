"""The run journal: a run killed half-way keeps what it checked, and ``run --resume``
finishes it (issue 30, point 2)."""

import contextlib
import json
import os
import signal
import subprocess
import sys

import pytest

from harness.cli.main import main
from harness.results.journal import JOURNAL_NAME, read_journal

LATTICE = ["--case", "lattice/bits-*", "--check", "conformance", "--no-fingerprints"]
CASES = ["lattice/bits-0", "lattice/bits-2", "lattice/bits-4", "lattice/bits-8"]


def _killer(tmp_path):
    """A correct rasterizer (pineda_topleft's answers) that, while the file ``armed``
    exists, kills the whole ``rastercheck run`` process from its isolated worker on its
    third call (disarming itself first); it logs each call it answers to ``calls``."""
    plugin = tmp_path / "killer.py"
    plugin.write_text(
        "import os, signal\n"
        "from rasterizers.pineda_topleft import PinedaTopLeft\n"
        "class Killer(PinedaTopLeft):\n"
        "    name = 'killer'\n"
        "    seen = 0\n"
        "    def rasterize(self, scene):\n"
        "        Killer.seen += 1\n"
        f"        if Killer.seen == 3 and os.path.exists({str(tmp_path / 'armed')!r}):\n"
        f"            os.remove({str(tmp_path / 'armed')!r})\n"
        "            os.kill(os.getppid(), signal.SIGKILL)  # the run, not this worker: as the OOM killer would\n"
        "            os._exit(0)\n"
        f"        with open({str(tmp_path / 'calls')!r}, 'a') as log:\n"
        "            log.write('call\\n')\n"
        "        return super().rasterize(scene)\n"
    )
    (tmp_path / "armed").touch()
    return f"{plugin}:Killer"


def _cli(args, cwd):
    """``python -m harness.cli.main`` in a session of its own (killed whole if it outlives the test)."""
    proc = subprocess.Popen([sys.executable, "-m", "harness.cli.main", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=cwd, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=120)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)  # an orphaned worker of a killed run
    return proc.returncode, out, err


def _statuses(path):
    return [(r["rasterizer"], r["case"], r["check"], r["status"]) for r in json.loads(path.read_text())["results"]]


def test_a_killed_run_keeps_its_results_and_resume_finishes_it(tmp_path):
    killer = _killer(tmp_path)
    out = tmp_path / "rep"
    args = ["run", "--rasterizer", "centre_scanline", "--rasterizer", killer, *LATTICE, "--out", str(out),
            "--json", str(out / "r.json")]
    code, _, err = _cli(args, os.getcwd())
    assert code == -signal.SIGKILL, err
    assert not (out / "r.json").exists()  # killed before the end: only the journal holds what was checked
    recorded = read_journal(out / JOURNAL_NAME)
    assert {("centre_scanline", c) for c in CASES} | {("killer", c) for c in CASES[:2]} == recorded.complete
    assert {(r.rasterizer, r.case) for r in recorded.results} == recorded.complete
    assert recorded.parameters["specs"] == ["centre_scanline", killer] and recorded.parameters["checks"] == ["conformance"]
    assert (tmp_path / "calls").read_text().count("call") == 2

    code, _, err = _cli([*args, "--resume"], os.getcwd())
    assert code == 0, err
    assert (tmp_path / "calls").read_text().count("call") == 4  # only the killer's two cases left were run again

    clean = tmp_path / "clean.json"
    assert main(["run", "--rasterizer", "centre_scanline", "--rasterizer", killer, *LATTICE, "--out", str(tmp_path / "clean"),
                 "--json", str(clean)]) == 0
    assert _statuses(out / "r.json") == _statuses(clean) and len(_statuses(clean)) == 8
    assert len(read_journal(out / JOURNAL_NAME).complete) == 8


def test_resume_refuses_a_journal_of_other_parameters_and_a_new_run_replaces_it(tmp_path, capsys):
    out = tmp_path / "rep"

    def run(*extra, case="lattice/bits-0", check="hygiene"):
        return main(["run", "--rasterizer", "centre_scanline", "--no-fingerprints", "--case", case, "--check", check,
                     "--out", str(out), *extra])

    assert run() == 0
    assert run("--resume") == 0  # a finished run resumed: nothing left to run, the same pairs
    assert read_journal(out / JOURNAL_NAME).complete == {("centre_scanline", "lattice/bits-0")}
    capsys.readouterr()
    for resumed, named in ((lambda: run("--seed", "1", "--resume"), "--seed was 0, is now 1"),
                           (lambda: run("--resume", case="lattice/bits-2"), "--case was lattice/bits-0, is now lattice/bits-2"),
                           (lambda: run("--resume", check="conformance"), "--check was hygiene, is now conformance")):
        refused = resumed()
        err = capsys.readouterr().err
        assert refused == 2 and len(err.strip().splitlines()) == 1, err
        assert named in err and JOURNAL_NAME in err and "Traceback" not in err, err
    # without --resume the journal is a new one: the old run's pairs are gone
    assert run(case="lattice/bits-2") == 0
    assert read_journal(out / JOURNAL_NAME).complete == {("centre_scanline", "lattice/bits-2")}


HEADER = json.dumps({"header": {"journal": 1, "parameters": {}}})
RESULT = json.dumps({"result": {"rasterizer": "r", "case": "a", "check": "hygiene", "status": "pass", "message": "ok",
                                "metrics": {}, "evidence": {}}})


@pytest.mark.parametrize("text, said", [
    ("", "empty"),
    ('{"result": {}}\n', "line 1: not a run journal header"),
    (f"{HEADER}\nnot json\n{RESULT}\n", "line 2: not JSON"),
    (f"{HEADER}\n{RESULT.replace('pass', 'great')}\n", "line 2: a result of status 'great'"),
    (f'{HEADER}\n{{"complete": {{"case": "a"}}}}\n', "line 2: a complete line names no rasterizer"),
    (f'{HEADER}\n{{"verdict": 1}}\n', "line 2: a line of kind 'verdict'"),
])
def test_a_malformed_journal_is_refused_in_one_line(tmp_path, capsys, text, said):
    out = tmp_path / "rep"
    out.mkdir()
    (out / JOURNAL_NAME).write_text(text)
    assert main(["run", "--rasterizer", "centre_scanline", "--no-fingerprints", "--out", str(out), "--resume"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and said in err and str(out / JOURNAL_NAME) in err and "Traceback" not in err, err


def test_resume_without_a_journal_is_a_usage_error(tmp_path, capsys):
    assert main(["run", "--rasterizer", "centre_scanline", "--out", str(tmp_path), "--resume"]) == 2
    assert "no run journal" in capsys.readouterr().err


def test_a_torn_last_line_and_an_unfinished_case_are_dropped(tmp_path):
    """A pair without its complete line is run again: its results are not kept, nor is a
    line the kill tore in half."""
    other = RESULT.replace('"case":"a"', '"case":"b"').replace('"case": "a"', '"case": "b"')
    path = tmp_path / JOURNAL_NAME
    path.write_text(f'{HEADER}\n{RESULT}\n{{"complete": {{"rasterizer": "r", "case": "a"}}}}\n{other}\n{other[:30]}')
    recorded = read_journal(path)
    assert recorded.complete == {("r", "a")}
    assert [(r.case, r.status) for r in recorded.results] == [("a", "pass")]
