"""The pytest plugin (``pytest --rasterizer SPEC``) and ``harness.integrations.testing.assert_conforms``.

The plugin runs in a pytest of its own, in a folder whose pytest.ini is as strict as ours:
xfail_strict, --strict-markers, warnings as errors. Once in a subprocess, as a CI user
runs it (the plugin found through its entry point by a fresh interpreter); the other runs
are the same pytest session started in this process (``pytest.main``), which loads the
plugin through the same entry point without starting an interpreter and importing
everything again.
"""

import functools
import os
import subprocess
import sys
import textwrap
import time
import xml.etree.ElementTree as ET
from pathlib import Path
from types import SimpleNamespace

import pytest

from cases.suites import suite
from harness.checks import checks
from harness.contract.case import Case
from harness.engine.runner import run_suite
from harness.integrations.testing import assert_conforms
from harness.results.files import safe_name
from harness.results.gate import key, save_baseline
from tests.known_bad.misc import WrongTieClaim

REPO = Path(__file__).resolve().parents[2]
INI = "[pytest]\nxfail_strict = true\nfilterwarnings = error\naddopts = --strict-markers\n"
COUNTING = textwrap.dedent('''
    """centre_scanline, writing the triangle count of every scene it is called on to calls.log."""
    import os

    from rasterizers.centre_scanline import CentreScanline

    LOG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "calls.log")


    class Counting(CentreScanline):
        name = "counting"

        def rasterize(self, scene):
            with open(LOG, "a") as log:
                log.write(f"{len(scene)}\\n")
            return super().rasterize(scene)


    class Undeclared:
        """centre_scanline declaring no convention: identified (dozens of calls) when its
        first item is set up."""

        name = "undeclared"
        convention = None

        def rasterize(self, scene):
            return CentreScanline().rasterize(scene)
''')
KNOWN_BAD = ["--rasterizer", "tests.known_bad.misc:WrongTieClaim", "--rasterizer", "tests.known_bad.misc:Raises"]


def plugin_run(tmp_path: Path, *args: str) -> tuple[subprocess.CompletedProcess[str], float]:
    """``pytest ARGS`` in ``tmp_path`` (the repository importable, as an installed plugin
    would be), and how long it took."""
    (tmp_path / "pytest.ini").write_text(INI)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST_", "COV_"))}
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), *filter(None, [os.environ.get("PYTHONPATH")])])
    env["COLUMNS"] = "100"  # the summary lines are cut to the terminal's width: one width everywhere
    start = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-p", "no:hypothesispytest",
                           "--rastercheck-repros",
                           str(tmp_path / "repros"), *args], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600)
    return proc, time.monotonic() - start


def plugin_run_here(tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
                    *args: str) -> SimpleNamespace:
    """``pytest ARGS`` as :func:`plugin_run` runs it, in ``tmp_path``, but in this process:
    its exit code (``returncode``) and what it printed (``stdout``, ``stderr``).

    ``pytest.main`` itself, not pytester's inline run: that one forgets the modules the
    run imported when it ends, and numba cannot import its own again in one process."""
    (tmp_path / "pytest.ini").write_text(INI)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "100")
    for name in [k for k in os.environ if k.startswith(("PYTEST_", "COV_")) and k != "PYTEST_CURRENT_TEST"]:
        monkeypatch.delenv(name)
    capsys.readouterr()
    # (without the unraisable-exception plugin: its cleanup collects garbage five times over
    # this process's whole heap at the end of every inner run, a third of a second each)
    code = pytest.main(["-p", "no:cacheprovider", "-p", "no:hypothesispytest", "-p", "no:unraisableexception",
                        "--rastercheck-repros", str(tmp_path / "repros"), *args])
    out, err = capsys.readouterr()
    return SimpleNamespace(returncode=int(code), stdout=out, stderr=err)


def calls(tmp_path: Path) -> list[int]:
    log = tmp_path / "calls.log"
    return [int(line) for line in log.read_text().split()] if log.exists() else []


def test_collection_builds_every_item_and_rasterizes_nothing(tmp_path, capsys, monkeypatch):
    (tmp_path / "counting.py").write_text(COUNTING)
    plugin = tmp_path / "counting.py"
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "--collect-only", "-q", "--rasterizer", f"{plugin}:Counting",
                           "--rasterizer", f"{plugin}:Undeclared")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    ids = [line for line in proc.stdout.splitlines() if "::" in line]
    cases = suite("quick")
    # a single-sample rasterizer's checks, on the scenes it takes (triangles)
    assert len(ids) == 2 * sum(len(checks(case, coverage_kind="single")) for case in cases
                               if not isinstance(case, Case) or case.scene.kind == "triangles")
    assert ids[:3] == ["rastercheck::counting::lattice/bits-0::hygiene", "rastercheck::counting::lattice/bits-0::conformance",
                       "rastercheck::counting::lattice/bits-0::invariance"]
    assert f"rastercheck::undeclared::{cases[-1].id}::" in proc.stdout
    assert not calls(tmp_path)  # no rasterizing, no identifying
    # -k leaves one item a case: each runs its own case and nothing else; the undeclared
    # rasterizer is identified once, before its first item
    lattice = [case for case in cases if isinstance(case, Case) and case.id.startswith("lattice/bits-")]
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "-q", "--rasterizer", f"{plugin}:Counting", "--rasterizer",
                           f"{plugin}:Undeclared", "-k", "lattice/bits- and conformance")
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert f"{2 * len(lattice)} passed" in proc.stdout
    assert len(calls(tmp_path)) >= len(lattice) and set(calls(tmp_path)) == {len(case.scene) for case in lattice}
    identified = [line for line in proc.stdout.splitlines() if line.startswith("undeclared: ")]
    assert identified == ["undeclared: checked against the convention identified for it: sample (0.5, 0.5), top-left ties, "
                          "no snapping, no culling"]


def test_a_one_case_selection_runs_one_item_in_seconds(tmp_path):
    proc, _ = plugin_run(tmp_path, "--rasterizer", "centre_scanline", "-k", "lattice/bits-0 and conformance",
                               "--junitxml", str(tmp_path / "r.xml"))
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert " 1 passed, " in proc.stdout and " deselected" in proc.stdout
    cases = ET.parse(tmp_path / "r.xml").getroot().findall(".//testcase")
    assert [(c.get("classname"), c.get("name")) for c in cases] == [("rastercheck.centre_scanline.lattice/bits-0", "conformance")]
    assert float(cases[0].get("time", "0")) > 0.01  # the item's own run, not done at collection
    # (how long it takes is measured, not asserted: about 5 s here, interpreter and imports included)


def test_with_no_path_named_only_the_suite_is_collected(tmp_path, capsys, monkeypatch):
    """``pytest --rasterizer X`` collects the suite's items, not the project's own tests
    (seconds of imports before one case runs); naming a path collects its tests too."""
    (tmp_path / "test_mine.py").write_text("def test_mine():\n    pass\n")
    only = plugin_run_here(tmp_path, capsys, monkeypatch, "--collect-only", "-q", "--rasterizer", "centre_scanline",
                           "-k", "lattice/bits-0")
    assert only.returncode == 0 and "test_mine" not in only.stdout and "rastercheck::centre_scanline" in only.stdout
    both = plugin_run_here(tmp_path, capsys, monkeypatch, "--collect-only", "-q", "test_mine.py", "--rasterizer",
                           "centre_scanline")
    assert both.returncode == 0 and "test_mine.py::test_mine" in both.stdout and "rastercheck::centre_scanline" in both.stdout
    mine = plugin_run_here(tmp_path, capsys, monkeypatch, "--collect-only", "-q")  # no --rasterizer: as ever
    assert "test_mine.py::test_mine" in mine.stdout and "rastercheck::" not in mine.stdout


def test_failures_read_well_with_their_repro_and_traceback(tmp_path, capsys, monkeypatch):
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, *KNOWN_BAD, "-k", "lattice/bits-0")
    assert proc.returncode == 1
    out = proc.stdout
    assert "4 failed, 2 passed" in out
    assert "_ bad_wrong_tie_claim lattice/bits-0 [conformance] _" in out
    assert "bad_wrong_tie_claim lattice/bits-0 [conformance] fail: " in out
    repro = tmp_path / "repros" / "bad_wrong_tie_claim" / f"{safe_name('lattice/bits-0')}--conformance.json"
    assert f"minimal repro: {repro} (rastercheck replay {repro} --rasterizer tests.known_bad.misc:WrongTieClaim)" in out
    assert repro.is_file()
    # a rasterizer that raises: each check of the case shows the run's error and its traceback
    failures = out.split("short test summary info")[0]
    assert failures.count("bad_raises lattice/bits-0 [run] error: RuntimeError: rasterizer exploded") == 3
    assert "the rasterizer's traceback:" in out and 'raise RuntimeError("rasterizer exploded")' in out


def test_a_baseline_makes_known_failures_xfail(tmp_path, capsys, monkeypatch):
    baseline = tmp_path / "baseline.json"
    from harness.checks import Result

    known = [Result("bad_wrong_tie_claim", "lattice/bits-0", "conformance", "fail", ""),
             Result("bad_wrong_tie_claim", "lattice/bits-0", "hygiene", "fail", ""),  # passes now: XPASS
             Result("bad_raises", "lattice/bits-0", "run", "error", "")]  # the whole case: each check xfails
    save_baseline(baseline, known, {key(known[0]): {"reason": "claims bottom-right, draws top-left"}})
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, *KNOWN_BAD, "-k", "lattice/bits-0", "--rastercheck-baseline",
                           str(baseline), "-rxX")
    assert proc.returncode == 0, proc.stdout[-3000:]
    out = proc.stdout
    # 618: with identify's four degenerate probe cases and the six deep-winding paths; 630 with
    # issue 34's motion of anti-aliased paths and lines (three cases, jaggy, two rasterizers)
    assert "1 passed, 630 deselected, 4 xfailed, 1 xpassed" in out
    assert "XFAIL rastercheck::bad_wrong_tie_claim::lattice/bits-0::conformance - claims bottom-right, draws top-left" in out
    assert "XPASS rastercheck::bad_wrong_tie_claim::lattice/bits-0::hygiene" in out
    assert "XFAIL rastercheck::bad_raises::lattice/bits-0::invariance - the case's run: " in out


@pytest.mark.parametrize("args, said", [
    (["--rasterizer", "nope"], "nope: not a registered rasterizer"),
    (["--rasterizer", "centre_scanline", "--rastercheck-baseline", "none.json"],
     "--rastercheck-baseline: none.json: no such baseline"),
    (["--rasterizer", "centre_scanline", "--rastercheck-suite", "huge"], "--rastercheck-suite: unknown suite 'huge'"),
])
def test_usage_errors(tmp_path, capsys, monkeypatch, args, said):
    # in this process as plugin_run_here runs it (pytester's inline run forgot the modules
    # it imported, and the next test to compile a kernel in this worker failed on numba's own)
    result = plugin_run_here(tmp_path, capsys, monkeypatch, *args)
    assert result.returncode == pytest.ExitCode.USAGE_ERROR and said in result.stderr, result.stderr


@functools.cache
def lattice_cases():
    """The quick suite's lattice cases (built once, when a test needs them, not at
    collection: every test worker collects every module)."""
    return tuple(case for case in suite("quick") if case.id.startswith("lattice/"))


def test_assert_conforms():
    assert assert_conforms("fixed_point", cases=lattice_cases(), isolate=False)
    with pytest.raises(AssertionError, match=r"checks failed:(.|\n)*minimal repro: "):
        assert_conforms(WrongTieClaim(), cases=lattice_cases(), isolate=False)


def test_assert_conforms_lets_a_baselines_known_failures_through(tmp_path):
    failing = [r for r in run_suite([WrongTieClaim()], cases=lattice_cases(), isolate=False, repros=False) if r.status == "fail"]
    assert len(failing) > 1
    baseline = tmp_path / "baseline.json"
    save_baseline(baseline, failing)
    results = assert_conforms(WrongTieClaim(), cases=lattice_cases(), isolate=False, repros=False, baseline=baseline)
    assert [key(r) for r in results if r.status == "fail"] == [key(r) for r in failing]
    save_baseline(baseline, failing[1:])  # one known failure fewer: that one fails the assertion, alone
    with pytest.raises(AssertionError) as raised:
        assert_conforms(WrongTieClaim(), cases=lattice_cases(), isolate=False, repros=False, baseline=baseline)
    text = str(raised.value)
    assert text.startswith(f"1 of {len(results)} checks failed ({len(failing) - 1} known failures of the baseline let through):")
    assert f"{failing[0].rasterizer} {failing[0].case} [{failing[0].check}] fail" in text
    with pytest.raises(ValueError, match="no such baseline"):
        assert_conforms(WrongTieClaim(), cases=lattice_cases(), baseline=tmp_path / "none.json")


def test_the_time_limit_is_an_option(tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """A rasterizer that hangs took 63 s an item (the fixed 60 s cap): --rastercheck-timeout
    sets it, as `rastercheck run --timeout` does; a cap of 0 is refused."""
    plugin = tmp_path / "hangs.py"
    plugin.write_text("import time\nfrom rasterizers.centre_scanline import CentreScanline\n"
                      "class Hangs(CentreScanline):\n    name = 'hangs'\n"
                      "    def rasterize(self, scene):\n        time.sleep(600)\n")
    start = time.monotonic()
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "--rasterizer", f"{plugin}:Hangs", "--rastercheck-timeout", "1",
                           "-k", "lattice/bits-0 and conformance")
    assert proc.returncode == 1 and time.monotonic() - start < 30, proc.stdout[-2000:]
    assert "no answer within 1 s" in proc.stdout, proc.stdout[-2000:]
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "--rasterizer", "centre_scanline", "--rastercheck-timeout", "0")
    assert proc.returncode == 4 and "expected a finite number > 0, not '0'" in proc.stderr, proc.stderr
