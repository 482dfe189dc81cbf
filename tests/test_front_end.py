"""JSON schema, JUnit, the baseline gate, the pytest plugin and assert_conforms."""

import json
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET

import pytest

from harness.cli import main
from harness.output import results_from_json
from harness.testing import assert_conforms

BROKEN = textwrap.dedent('''
    from harness import Convention
    from rasterizers.centre_scanline import CentreScanline

    class CentreScanline2(CentreScanline):
        """Registered under the built-in's name: a change that breaks its tie rule."""
        name = "centre_scanline"
        convention = Convention(tie="bottom-right")
''')


def run_args(tmp_path, *extra):
    return ["--suite", "quick", "--out", str(tmp_path / "rep"), *extra]


def test_json_and_junit(tmp_path):
    code = main(["run", "--rasterizer", "fixed_point", *run_args(tmp_path, "--json", str(tmp_path / "r.json"), "--junit", str(tmp_path / "r.xml"))])
    assert code == 0
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["schema"] == 1 and data["rasterizers"] == {"fixed_point": "sample (0.5, 0.5), top-left ties, snapped to 1/256 px (8 bits), no culling"}
    results = results_from_json(data)
    assert len(results) == len(data["results"]) and {r.status for r in results} <= {"pass", "skip"}
    root = ET.parse(tmp_path / "r.xml").getroot()
    suite = root.find("testsuite")
    assert suite.get("name") == "fixed_point" and int(suite.get("tests")) == len(results)
    assert int(suite.get("failures")) == 0 and len(suite.findall("testcase")) == len(results)


def test_junit_reports_failures(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    code = main(["run", "--rasterizer", f"{bad}:CentreScanline2", *run_args(tmp_path, "--junit", str(tmp_path / "r.xml"))])
    assert code == 1
    failures = ET.parse(tmp_path / "r.xml").getroot().findall(".//failure")
    assert failures and "minimal repro" in failures[0].text


def test_gate_flags_a_regression_and_reports_a_fix(tmp_path, capsys):
    baseline = tmp_path / "baseline.json"
    assert main(["gate", "--rasterizer", "centre_scanline", "--baseline", str(baseline), "--update-baseline", *run_args(tmp_path)]) == 0
    assert main(["gate", "--rasterizer", "centre_scanline", "--baseline", str(baseline), *run_args(tmp_path)]) == 0
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    capsys.readouterr()
    assert main(["gate", "--rasterizer", f"{bad}:CentreScanline2", "--baseline", str(baseline), *run_args(tmp_path)]) == 1
    assert "REGRESSION centre_scanline|lattice/bits-0|conformance" in capsys.readouterr().out
    # the broken one becomes the baseline, with reasons; the fix then shows up
    assert main(["gate", "--rasterizer", f"{bad}:CentreScanline2", "--baseline", str(baseline), "--update-baseline", *run_args(tmp_path)]) == 0
    entries = json.loads(baseline.read_text())["entries"]
    assert entries["centre_scanline|lattice/bits-0|conformance"]["reason"].startswith("known failure")
    capsys.readouterr()
    assert main(["gate", "--rasterizer", "centre_scanline", "--baseline", str(baseline), *run_args(tmp_path)]) == 0
    assert "UNEXPECTEDLY PASSING centre_scanline|lattice/bits-0|conformance" in capsys.readouterr().out


def test_gate_needs_a_baseline(tmp_path, capsys):
    assert main(["gate", "--rasterizer", "centre_scanline", "--baseline", str(tmp_path / "none.json"), *run_args(tmp_path)]) == 2
    assert "no such baseline" in capsys.readouterr().err


def test_list_shows_suites_and_checks(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert "quick" in out and "jaggy" in out and "centre_scanline" in out


def test_assert_conforms():
    assert assert_conforms("fixed_point", isolate=False)
    from tests.known_bad.misc import WrongTieClaim

    with pytest.raises(AssertionError, match=r"checks failed:(.|\n)*minimal repro: "):
        assert_conforms(WrongTieClaim(), isolate=False)


def test_pytest_plugin_runs_the_suite_as_items(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    run = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-o", "addopts=", "--rootdir", str(tmp_path),
           "--rastercheck-repros", str(tmp_path / "repros")]
    good = subprocess.run([*run, "--rasterizer", "fixed_point"], capture_output=True, text=True, cwd=tmp_path)
    assert good.returncode == 0, good.stdout[-2000:]
    assert " passed" in good.stdout
    failing = subprocess.run([*run, "--rasterizer", f"{bad}:CentreScanline2"], capture_output=True, text=True, cwd=tmp_path)
    assert failing.returncode == 1
    assert "centre_scanline lattice/bits-0 [conformance] fail" in failing.stdout
    assert "minimal repro: " in failing.stdout


def test_compare_names_the_convention_that_separates(tmp_path, capsys):
    assert main(["compare", "centre_scanline", "floor_scanline", "fixed_point", "--out", str(tmp_path), "--json", str(tmp_path / "c.json")]) == 0
    out = capsys.readouterr().out
    assert "centre_scanline vs floor_scanline" in out and "half-pixel shift of the sample point by (+0.5, +0.5)" in out
    assert "mirrored tie rule (top-left vs bottom-right)" in out
    assert "centre_scanline vs fixed_point: 0 pixels differ" in out
    data = json.loads((tmp_path / "c.json").read_text())
    assert all(e["exact"] for e in data["explanations"])
    assert "separated by" in (tmp_path / "compare.html").read_text()
    assert main(["compare", "centre_scanline"]) == 2


def test_a_broken_plugin_is_reported_and_skipped(monkeypatch, capsys):
    from importlib.metadata import EntryPoint

    import harness.registry as registry

    real = registry.entry_points

    def with_broken(group):
        return [*real(group=group), EntryPoint("broken_plugin", "no_such_module_xyz:Thing", group)]

    monkeypatch.setattr(registry, "entry_points", with_broken)
    assert "broken_plugin" in registry.available()
    assert main(["list"]) == 0
    assert "skipped plugin: broken_plugin: plugin failed to load" in capsys.readouterr().out
    monkeypatch.setenv("RASTERCHECK_NO_PLUGINS", "1")
    assert "broken_plugin" not in registry.available()
