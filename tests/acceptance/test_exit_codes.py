"""Exit codes never lie (issue 30, point 3): ``run``, ``identify``, ``compare`` and
``replay`` exit 0 only when something was checked and passed. Nothing checked, every call
failed, no answers to fit: 1, with one line naming the rasterizer and why; a declaration
that leaves no scene to hand it, two rasterizers of one name, no case selected: 2, in one
line. The hostile plugins are in tests/known_bad/nothing_checked.py."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from harness.cli.main import main
from harness.engine.registry import load
from tests.known_bad import nothing_checked as bad

PLUGINS = Path(bad.__file__)


def spec(name: str) -> str:
    return f"{PLUGINS}:{name}"


def run_args(tmp_path: Path, *rasterizers: str, cases: tuple[str, ...] = ("lattice/bits-0",)) -> list[str]:
    selected = [a for r in rasterizers for a in ("--rasterizer", r)]
    globs = [a for c in cases for a in ("--case", c)]
    return ["run", *selected, *globs, "--no-fingerprints", "--out", str(tmp_path / "rep")]


def said(err: str, name: str) -> list[str]:
    """The lines of ``err`` that name ``name`` after rastercheck's prefix."""
    return [line for line in err.splitlines() if line.startswith("rastercheck:") and name in line]


# -- 2: declarations that leave no scene, duplicate names, no case --------------------------


@pytest.mark.parametrize("plugin", sorted(bad.REFUSED_AT_LOAD))
def test_a_declaration_that_leaves_no_scene_is_refused_in_one_line(tmp_path, capsys, plugin):
    assert main(run_args(tmp_path, spec(plugin))) == 2
    err = capsys.readouterr().err
    lines = said(err, plugin)
    assert len(lines) == 1 and bad.REFUSED_AT_LOAD[plugin] in lines[0], err
    assert "Traceback" not in err


def test_identify_refuses_such_a_declaration_too(capsys):
    assert main(["identify", spec("KindsAsNumber")]) == 2
    err = capsys.readouterr().err
    assert len(said(err, "KindsAsNumber")) == 1 and "Traceback" not in err


def test_two_rasterizers_of_one_name_are_a_usage_error(tmp_path, capsys):
    assert main(run_args(tmp_path, "centre_scanline", spec("Impostor"))) == 2
    err = capsys.readouterr().err
    assert "two rasterizers are named 'centre_scanline'" in err and spec("Impostor") in err
    assert main(run_args(tmp_path, "centre_scanline", "centre_scanline")) == 2
    assert "(centre_scanline twice)" in capsys.readouterr().err
    assert main(["compare", "centre_scanline", spec("Impostor"), "--out", str(tmp_path)]) == 2
    assert "two rasterizers are named 'centre_scanline'" in capsys.readouterr().err


def test_a_name_registered_twice_is_refused_not_chosen(tmp_path, monkeypatch, capsys):
    """A plugin that registers a built-in's name: neither is run under it silently."""
    from importlib.metadata import EntryPoint

    import harness.engine.registry as registry

    real = registry.entry_points  # type: ignore[attr-defined]  # (its import, stood in for below)

    def with_impostor(group):
        return [*real(group=group), EntryPoint("centre_scanline", "tests.known_bad.nothing_checked:Impostor", group)]

    monkeypatch.setattr(registry, "entry_points", with_impostor)
    assert registry.registered_twice("centre_scanline") == ["rasterizers.centre_scanline:CentreScanline",
                                                            "tests.known_bad.nothing_checked:Impostor"]
    with pytest.raises(ValueError, match="registered twice"):
        load("centre_scanline")
    assert main(run_args(tmp_path, "centre_scanline")) == 2
    err = capsys.readouterr().err
    assert len(said(err, "registered twice")) == 1 and "Traceback" not in err


@pytest.mark.parametrize("selection", [["--case", "no-such-case*"], ["--case", "lattice/bits-0", "--shard", "2/2"]])
def test_no_case_selected_is_a_usage_error(tmp_path, capsys, selection):
    assert main(["run", "--rasterizer", "centre_scanline", *selection, "--out", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "no case" in err, err


def test_a_broken_registered_plugin_fails_the_run_after_the_others_are_written(tmp_path, monkeypatch, capsys):
    from importlib.metadata import EntryPoint

    import harness.engine.registry as registry

    real = registry.entry_points  # type: ignore[attr-defined]  # (its import, stood in for below)
    monkeypatch.setattr(registry, "entry_points",
                        lambda group: [*real(group=group), EntryPoint("broken_plugin", "no_such_module_xyz:Thing", group)])
    monkeypatch.setattr(registry, "available", lambda: ["centre_scanline", "broken_plugin"])
    out = tmp_path / "r.json"
    assert main(run_args(tmp_path) + ["--json", str(out)]) == 2
    assert {r["rasterizer"] for r in json.loads(out.read_text())["results"]} == {"centre_scanline"}
    assert len(said(capsys.readouterr().err, "broken_plugin")) == 1


# -- 1: nothing checked ---------------------------------------------------------------------


@pytest.mark.parametrize(("plugin", "why"), [
    ("UnsupportedEverything", "nothing checked: every one of its 1 cases was skipped, e.g. lattice/bits-0: unsupported: "
                              "it draws nothing as given"),
    ("LinesOnly", "nothing checked: none of the 1 selected cases is of a scene kind it takes (scene_kinds=('lines',))"),
    ("CrashesAlways", "nothing checked: every one of its 1 calls failed: RuntimeError: the engine is not initialised"),
])
def test_nothing_checked_is_a_verdict_and_the_others_are_written(tmp_path, capsys, plugin, why):
    out = tmp_path / "r.json"
    assert main(run_args(tmp_path, "centre_scanline", spec(plugin)) + ["--json", str(out)]) == 1
    name = getattr(bad, plugin).name
    captured = capsys.readouterr()
    assert said(captured.err, name) == [f"rastercheck: {name}: {why}"]
    assert f"{name:<22} nothing checked: " in captured.out and f"{name:<22} 1/1 pass or skip" not in captured.out
    results = json.loads(out.read_text())["results"]
    assert any(r["rasterizer"] == "centre_scanline" and r["status"] == "pass" for r in results)
    assert (tmp_path / "rep" / "index.html").is_file()


def test_a_check_that_applies_to_no_case_checks_nothing(tmp_path, capsys):
    assert main(run_args(tmp_path, "centre_scanline") + ["--check", "seams"]) == 1
    assert said(capsys.readouterr().err, "centre_scanline") == [
        "rastercheck: centre_scanline: nothing checked: no selected check applies to the 1 cases of the kinds it takes"]


def test_a_run_whose_budget_ran_out_is_a_verdict(tmp_path, capsys):
    """--max-seconds: the cases not started are errors ("not run"), never a pass."""
    assert main(run_args(tmp_path, "centre_scanline", cases=("lattice/*",)) + ["--max-seconds", "0.001"]) == 1
    captured = capsys.readouterr()
    assert "not run" in captured.out + captured.err


def test_a_budget_used_up_before_any_case_is_said_so():
    from harness.checks import Result
    from harness.contract.case import Case
    from harness.engine.runner import nothing_checked

    cases = [Case(f"c/{k}", None) for k in range(3)]  # type: ignore[arg-type]
    results = [Result("centre_scanline", c.id, "run", "error", "not run: the run's time budget was used up") for c in cases]
    assert nothing_checked(load("centre_scanline"), results, cases) == (
        "centre_scanline: nothing checked: the run's time budget was used up before any of its 3 cases started")
    results[0] = Result("centre_scanline", "c/0", "conformance", "pass", "")
    assert nothing_checked(load("centre_scanline"), results, cases) is None


# -- identify: no answers, no convention ------------------------------------------------------


@pytest.mark.parametrize(("plugin", "first"), [
    ("CrashesAlways", "RuntimeError: the engine is not initialised"),
    ("SegfaultsAlways", "worker process died"),
    ("ExitsAlways", "SystemExit: 0"),
    ("UnsupportedEverything", "Unsupported: it draws nothing as given"),
])
def test_identify_says_there_were_no_answers(tmp_path, capsys, plugin, first):
    out = tmp_path / "f.json"
    assert main(["identify", spec(plugin), "--json", str(out)]) == 1
    captured = capsys.readouterr()
    name = getattr(bad, plugin).name
    lines = said(captured.err, name)
    assert len(lines) == 1 and "no answers, nothing identified: every one of its" in lines[0] and first in lines[0], lines
    assert "convention   none identified: no answers" in captured.out
    assert "mismatching pixels" not in captured.out and "next best" not in captured.out and "declared " not in captured.out
    data = json.loads(out.read_text())
    assert data["no_answers"] and data["fingerprint"]["convention"].startswith("none identified")


def test_a_fingerprint_of_calls_that_all_timed_out_claims_nothing():
    from harness.contract.scenes import Scene
    from harness.engine.isolation import Outcome
    from harness.identify.fingerprint import identify

    def hangs(scene: Scene) -> Outcome:
        return Outcome(None, TimeoutError("no answer within 2 s, nor within 8 s when asked again"), timed_out=True)

    fingerprint = identify(bad.CrashesAlways(), call=hangs)
    assert fingerprint.no_answers is not None and "calls timed out (each asked twice)" in fingerprint.no_answers
    assert not fingerprint.exact and "mismatching pixels" not in fingerprint.card()
    assert fingerprint.to_dict()["no_answers"] == fingerprint.no_answers


def test_identify_contradicts_area_coverage_drawn_as_samples(capsys):
    assert main(["identify", spec("AreaDrawsSamples")]) == 1
    captured = capsys.readouterr()
    assert "NOT what it does" in captured.out and "carries no alphas" in captured.out
    assert said(captured.err, "area_draws_samples") == [
        "rastercheck: identify area_draws_samples: its declared convention is contradicted by what it does "
        "(the 'declared' line above)"]


# -- compare: never ranks a rasterizer that answered nothing ----------------------------------


def test_compare_does_not_rank_a_rasterizer_without_answers(tmp_path, capsys):
    out = tmp_path / "c.json"
    assert main(["compare", "centre_scanline", spec("SegfaultsAlways"), "--out", str(tmp_path), "--json", str(out)]) == 1
    captured = capsys.readouterr()
    assert "segfaults_always       no answers, not ranked: every one of its 6 fit calls failed" in captured.out
    assert "best, with" not in captured.out and " vs " not in captured.out
    assert len(said(captured.err, "segfaults_always")) == 1
    data = json.loads(out.read_text())
    silent = next(e for e in data["explanations"] if e["rasterizer"] == "segfaults_always")
    assert silent["answered"] is False and silent["convention"] is None and not silent["exact"]
    assert data["comparisons"] == []
    page = (tmp_path / "compare.html").read_text()
    assert "no answers, not ranked: every one of its 6 fit calls failed" in page


# -- replay ----------------------------------------------------------------------------------


def _saved(tmp_path: Path, kind: str) -> Path:
    from cases.suites import suite
    from harness.contract.case import Case, save_case

    case = next(c for c in suite("quick") if isinstance(c, Case) and c.scene.kind == kind)
    return save_case(tmp_path / f"{kind}.json", case)


def test_replay_of_a_case_it_does_not_take_is_a_usage_error(tmp_path, capsys):
    assert main(["replay", str(_saved(tmp_path, "paths")), "--rasterizer", "centre_scanline"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "a case of paths, which centre_scanline does not take" in err


def test_replay_that_checks_nothing_is_a_verdict(tmp_path, capsys):
    assert main(["replay", str(_saved(tmp_path, "triangles")), "--rasterizer", spec("UnsupportedEverything")]) == 1
    lines = said(capsys.readouterr().err, "unsupported_everything")
    assert len(lines) == 1 and "nothing checked: every one of its 1 cases was skipped" in lines[0]
