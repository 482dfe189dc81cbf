"""JSON schema, JUnit (the baseline gate: test_gate.py; the pytest plugin and assert_conforms:
test_pytest_plugin.py)."""

import json
import textwrap
import xml.etree.ElementTree as ET

from harness.cli.main import main
from harness.results.output import results_from_json

BROKEN = textwrap.dedent('''
    from harness import Convention
    from rasterizers.centre_scanline import CentreScanline

    class CentreScanline2(CentreScanline):
        """Registered under the built-in's name: a change that breaks its tie rule."""
        name = "centre_scanline"
        convention = Convention(tie="bottom-right")
''')


def run_args(tmp_path, *extra):
    # the families where the checks these tests read show, not the whole suite
    families = [a for g in ("lattice/*", "watertight/fan-*", "degenerate/zero-area/*") for a in ("--case", g)]
    return ["--suite", "quick", *families, "--no-fingerprints", "--out", str(tmp_path / "rep"), *extra]


def test_json_and_junit(tmp_path):
    code = main(["run", "--rasterizer", "fixed_point",
                 *run_args(tmp_path, "--json", str(tmp_path / "r.json"), "--junit", str(tmp_path / "r.xml"))])
    assert code == 0
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["schema"] == 1 and data["rasterizers"] == {"fixed_point": "sample (0.5, 0.5), top-left ties, snapped to 1/256 px "
                                                                          "(8 bits), no culling"}
    results = results_from_json(data)
    assert len(results) == len(data["results"]) and {r.status for r in results} <= {"pass", "skip"}
    root = ET.parse(tmp_path / "r.xml").getroot()
    suite = root.find("testsuite")
    assert suite is not None
    assert suite.get("name") == "fixed_point" and int(suite.get("tests", "")) == len(results)
    assert int(suite.get("failures", "")) == 0 and len(suite.findall("testcase")) == len(results)


def test_junit_reports_failures(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    code = main(["run", "--rasterizer", f"{bad}:CentreScanline2", *run_args(tmp_path, "--junit", str(tmp_path / "r.xml"))])
    assert code == 1
    failures = ET.parse(tmp_path / "r.xml").getroot().findall(".//failure")
    assert failures and "minimal repro" in (failures[0].text or "")


def test_list_shows_suites_and_checks(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert "quick" in out and "jaggy" in out and "centre_scanline" in out


def test_compare_names_the_convention_that_separates(tmp_path, capsys):
    assert main(["compare", "centre_scanline", "floor_scanline", "pineda_topleft", "--out", str(tmp_path), "--json",
                 str(tmp_path / "c.json")]) == 0
    out = capsys.readouterr().out
    assert "centre_scanline vs floor_scanline" in out and "half-pixel shift of the sample point by (+0.5, +0.5)" in out
    assert "mirrored tie rule (top-left vs bottom-right)" in out
    assert "centre_scanline vs pineda_topleft: 0 pixels differ" in out
    data = json.loads((tmp_path / "c.json").read_text())
    assert all(e["exact"] for e in data["explanations"])
    page = (tmp_path / "compare.html").read_text()
    assert "separated by" in page
    # each pair that differs is drawn where it first does, both sides; identical pairs are not
    assert "<h3>centre_scanline · floor_scanline</h3>" in page and "centre_scanline · pineda_topleft</h3>" not in page
    assert page.count("<figcaption>") == 4 and "data:image/svg+xml;base64," in page
    assert main(["compare", "centre_scanline"]) == 2


def test_a_broken_plugin_is_reported_and_skipped(monkeypatch, capsys):
    from importlib.metadata import EntryPoint

    import harness.engine.registry as registry

    real = registry.entry_points  # type: ignore[attr-defined]  # (its import, stood in for below)

    def with_broken(group):
        return [*real(group=group), EntryPoint("broken_plugin", "no_such_module_xyz:Thing", group)]

    monkeypatch.setattr(registry, "entry_points", with_broken)
    assert "broken_plugin" in registry.available()
    assert main(["list"]) == 0
    assert "skipped plugin: broken_plugin: plugin failed to load" in capsys.readouterr().out
    monkeypatch.setenv("RASTERCHECK_NO_PLUGINS", "1")
    assert "broken_plugin" not in registry.available()
