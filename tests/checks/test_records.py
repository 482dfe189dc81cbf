"""The check contract: one registration, every list derived from it; the import graph
stays acyclic."""

import ast
import json
from dataclasses import replace
from pathlib import Path

from cases.suites import conformance_cases
from harness import run_suite
from harness.checks import Check, Figure, check_names, checks, every_check, metric_tolerance, registered, result


def _few_pixels(subject):
    """A trivial check: a scene may draw at most 500 pixels."""
    drawn = subject.coverage.n_pixels
    return result(subject.case.id, "few_pixels", drawn <= 500, f"{drawn} pixels drawn", {"drawn_pixels": float(drawn)})


def _few_pixels_class(result, case, convention):
    """Its classifier: every failure is too many pixels."""
    return "too-many-pixels", "none"


FEW_PIXELS = Check("few_pixels", _few_pixels, lambda case: not hasattr(case, "frames"), shrinks=True,
                   metrics={"drawn_pixels": (1.0, 0.0)}, caption="at most 500 pixels per scene",
                   classifier=_few_pixels_class, cause_role="consequent", motion_role="none",
                   figures=(Figure("drawn_pixels", "max", "most pixels drawn in a scene"),))


def test_a_check_registered_in_a_test_reaches_run_json_gate_report_and_shrinker(tmp_path):
    from harness.campaign.state import SceneFinding
    from harness.campaign.worker import attribute_causes
    from harness.diagnose.causes import by_cause, signature_of
    from harness.report.pages import coverage_figures, write_report
    from harness.results.gate import compare_with_baseline, load_baseline, save_baseline
    from harness.results.output import write_json

    case = [c for c in conformance_cases(0) if c.id == "lattice/bits-0"]
    with registered(FEW_PIXELS):
        assert "few_pixels" in check_names() and metric_tolerance()["drawn_pixels"] == (1.0, 0.0)
        results = run_suite(["centre_scanline"], cases=case)
        mine = [r for r in results if r.check == "few_pixels"]
        assert len(mine) == 1 and mine[0].status == "fail"
        repro = mine[0].evidence["repro"]  # the shrinker found a smaller case that still fails
        assert repro["check"] == "few_pixels" and len(repro["positions"]) < len(case[0].scene)
        write_json(tmp_path / "r.json", results, "custom", 0, {"centre_scanline": "declared"})
        assert any(r["check"] == "few_pixels" for r in json.loads((tmp_path / "r.json").read_text())["results"])
        save_baseline(tmp_path / "base.json", results)
        baseline = load_baseline(tmp_path / "base.json")
        assert baseline["centre_scanline|lattice/bits-0|few_pixels"]["metrics"]["drawn_pixels"] == mine[0].metrics["drawn_pixels"]
        worse = [replace(r, metrics={**r.metrics, "drawn_pixels": r.metrics["drawn_pixels"] + 1}) if r.check == "few_pixels"
                 else r
                 for r in results]
        assert any("drawn_pixels worsened" in line for line in compare_with_baseline(worse, baseline).regressions)
        write_report(tmp_path / "rep", {"centre_scanline": "declared"}, results, 0)
        pages = "".join(p.read_text() for p in (tmp_path / "rep").glob("*.html"))
        assert "few_pixels" in pages
        # ... and what it declares of its failures reaches the signatures, the causes, the
        # campaign and the report's figures with no other edit
        assert mine[0].evidence["signature"] == "few_pixels|too-many-pixels|none"  # the run signed it with its classifier
        unsigned = replace(mine[0], evidence={k: v for k, v in mine[0].evidence.items() if k != "signature"})
        assert signature_of(unsigned).key == "few_pixels|too-many-pixels|none"  # classified from its drawing, not read back
        assert [g.cause for g in by_cause(mine)] == ["too-many-pixels"]
        conformance = SceneFinding("lattice", 0, 1, "conformance", "fail", "", "conformance|culling|culling", "culling",
                                   "culling",
                              "conformance")
        few = SceneFinding("lattice", 0, 1, "few_pixels", "fail", "", "few_pixels|too-many-pixels|none", "too-many-pixels",
                           "none",
                      "few_pixels")
        assert [f.cause for f in attribute_causes([conformance, few])] == ["culling", "culling"]  # a consequent of conformance
        assert ("few_pixels: most pixels drawn in a scene", f"{mine[0].metrics['drawn_pixels']:.4g}") in coverage_figures(results)
        assert "few_pixels: most pixels drawn in a scene" in pages
    assert "few_pixels" not in check_names()
    assert signature_of(unsigned).key == "few_pixels|other|none"  # unregistered: an unknown check's failure


def test_registry_answers_what_the_lists_used_to_say():
    lines = ("connectivity", "joints", "reversal", "length", "line-motion")
    assert check_names() == ("hygiene", "conformance", "watertight", "closed", "degenerate", "invariance", "jaggy", "texel",
                             "perspective", "accuracy", "seams", "popping", "triangulation", *lines)
    assert {c.name for c in checks() if c.needs_convention} == {"conformance", "jaggy", "texel", "perspective", "accuracy",
                                                                "seams",
                                                                 "popping", *lines}
    # each coverage kind gets the checks that judge it; lines are single-sample, or
    # multisample rectangles judged sample by sample
    area = {"hygiene", "degenerate", "invariance", "accuracy", "seams", "popping"}
    assert {c.name for c in checks(coverage_kind="area")} == area
    sampled = {"hygiene", "conformance", "watertight", "closed", "degenerate", "invariance", "jaggy", "texel", "perspective",
               "triangulation"}
    assert {c.name for c in checks(coverage_kind="multisample")} == sampled | set(lines)
    assert {c.name for c in checks(coverage_kind="single")} == sampled | set(lines)
    assert {c.name for c in checks(only={"overdraw", "hygiene", "conformance", "degenerate", "invariance"}) if c.shrinks} == {
        "hygiene", "conformance", "degenerate", "invariance", "overdraw"}


def _undeclared() -> dict[str, tuple[str, ...]]:
    """Each registered check that leaves some of its classifier, campaign role, motion
    role and report figures undeclared, with those it leaves."""
    return {c.name: c.undeclared() for c in every_check() if c.undeclared()}


def test_every_registered_check_says_how_its_failures_are_read():
    """A check is one registration: its classifier, campaign role, motion role and report
    figures are declared where it is registered, none left to a list kept elsewhere."""
    assert not _undeclared(), _undeclared()
    for check in every_check():
        assert callable(check.classifier_function()), check.name  # a dotted name resolves
        assert check.cause_role in ("root", "consequent", "own") and check.motion_role in ("frame", "through-frames", "none")
        assert check.figures is not None, check.name
        assert all(isinstance(f, Figure) and f.how in ("max", "sum", "mean") for f in check.figures), check.name
    # the detector itself: a check registered without them is named, with what it lacks
    bare = Check("bare", _few_pixels, lambda case: True)
    with registered(bare):
        assert _undeclared() == {"bare": ("classifier", "cause_role", "motion_role", "figures")}
    with registered(replace(bare, classifier=_few_pixels_class, cause_role="own", motion_role="none")):
        assert _undeclared() == {"bare": ("figures",)}
    assert not _undeclared()


def test_the_roles_say_what_the_hand_kept_lists_said():
    """The lists that signatures, causes, campaign and report kept by hand, now read from
    the registry, say what they said."""
    from harness.checks.records import check_named, figures, frame_checks, is_consequent, motion_checks, root_checks

    assert root_checks() == ("conformance", "accuracy")
    assert {c.name for c in every_check() if is_consequent(c.name, "any")} == {
        "watertight", "closed", "invariance", "degenerate", "overdraw", "seams", "triangulation", "connectivity", "joints",
        "reversal", "length"}
    assert is_consequent("hygiene", "outside-primitive") and not is_consequent("hygiene", "nan-attributes")
    assert not is_consequent("run", "hang") and check_named("run") is None
    assert motion_checks() == ("jaggy", "texel", "perspective", "popping")
    assert frame_checks() == ("conformance", "accuracy")
    assert {(check, f.metric, f.how, f.label) for check, f in figures()} == {
        ("accuracy", "max_error", "max", "largest |alpha - area|"),
        ("accuracy", "mean_error", "mean", "mean |alpha - area|"),
        ("accuracy", "over_tolerance", "sum", "pixels beyond the declared tolerance"),
        ("seams", "seam_pixels", "sum", "seam pixels (alphas not summing to 1)"),
        ("seams", "max_sum_error", "max", "largest seam (levels of its quantisation)"),
        ("seams", "max_over_gap", "max", "deepest seam after compositing with over"),
        ("popping", "max_pop_levels", "max", "largest pop against the exact area (in 1/255 levels)"),
        ("popping", "pops", "sum", "pops of more than 1/255 (pixel-steps)"),
        ("popping", "alpha_jumps", "sum", "alpha jumps beyond the declared tolerance"),
        ("conformance", "failing_samples", "sum", "samples failing conformance (summed over cases)")}


def test_a_motion_check_registered_in_a_test_is_read_through_its_frames():
    """A check registered with motion role ``through-frames`` is a motion check for the
    probes, and its signature is its frame verdict's when there is one, else its own."""
    from harness.checks import Result
    from harness.checks.records import motion_checks
    from harness.diagnose.signatures import signature

    frame_failure = {"frame_failure": {"frame": 2, "check": "conformance", "signature": "conformance|culling|culling"}}
    with registered(replace(FEW_PIXELS, name="few_pixels_moving", motion_role="through-frames",
                            applies=lambda case: hasattr(case, "frames"))):
        assert motion_checks()[-1] == "few_pixels_moving"
        assert signature(Result("r", "c", "few_pixels_moving", "fail", "", {}, frame_failure), None, None).key == \
            "few_pixels_moving|culling|culling"
        assert signature(Result("r", "c", "few_pixels_moving", "fail", "", {}, {}), None, None).key == \
            "few_pixels_moving|too-many-pixels|none"
    assert "few_pixels_moving" not in motion_checks()


def test_a_classifier_named_by_a_dotted_path_resolves_on_first_use():
    import pytest

    from harness.checks import Result
    from harness.diagnose.signatures import signature

    with registered(replace(FEW_PIXELS, name="few_pixels_dotted", classifier="harness.diagnose.signatures:classify_overdraw")):
        assert signature(Result("r", "c", "few_pixels_dotted", "fail", ""), None, None).key == "few_pixels_dotted|double-hit|none"
    with pytest.raises(ValueError, match="few_pixels_dotted.*module:function"):
        replace(FEW_PIXELS, name="few_pixels_dotted", classifier="harness.diagnose.signatures.classify_overdraw")
    with pytest.raises(ValueError, match="cause_role"):
        replace(FEW_PIXELS, cause_role="cause")  # type: ignore[arg-type]  # no such role: refused


def test_a_name_registers_once():
    import pytest

    from harness.checks import register

    with pytest.raises(ValueError, match="registered already"):
        register(Check("hygiene", _few_pixels, lambda case: True))


def _imports(path: Path, package: str) -> set[str]:
    tree = ast.parse(path.read_text())
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out.update(f"{node.module}.{a.name}" for a in node.names)
    return {m for m in out if m.split(".")[0] in ("harness", "cases", "rasterizers")}


def test_the_check_modules_import_no_runner_and_no_presentation():
    """Checks are pure: no runner, report, pictures or command line behind them."""
    root = Path(__file__).resolve().parents[2]
    for path in (root / "harness" / "checks").glob("*.py"):
        bad = {m for m in _imports(path, "harness")
               if _under(m, ("harness.engine.runner", "harness.engine.session", "harness.report", "harness.cli",
                             "harness.campaign", "harness.results.output", "harness.results.gate"))}
        assert not bad, (path.name, bad)


def _module_graph() -> dict[str, set[str]]:
    """Every module of harness, cases and rasterizers -> the project modules it imports
    (at the top or inside a function: a lazy import is an import too)."""
    root = Path(__file__).resolve().parents[2]
    modules = {}
    for package in ("harness", "cases", "rasterizers"):
        for path in (root / package).rglob("*.py"):
            parts = path.relative_to(root).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            modules[name] = path
    graph = {}
    for name, path in modules.items():
        found = set()
        for imported in _imports(path, "harness"):
            # "harness.checks.Result" names a module only as far as it is one
            while imported and imported not in modules:
                imported = imported.rpartition(".")[0]
            if imported and imported != name:
                found.add(imported)
        graph[name] = found
    return graph


def test_the_import_graph_has_no_cycle():
    """Packages aside (a package's __init__ gathers its own modules), no module reaches
    itself through imports."""
    graph = _module_graph()

    def edges(name):
        # a package importing its own submodules is aggregation, not a cycle
        return {m for m in graph[name] if not m.startswith(name + ".")}

    state: dict[str, int] = {}
    path: list[str] = []

    def visit(name):
        state[name] = 1
        path.append(name)
        for nxt in edges(name):
            if state.get(nxt) == 1:
                raise AssertionError("import cycle: " + " -> ".join(path[path.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt)
        path.pop()
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name)


# the layers, by folder: presentation (report pages and pictures, the command line, output
# formats, the gate, the pytest plugin) sits on the engine, never under it
PRESENTATION_PACKAGES = ("harness.report", "harness.cli.main", "harness.cli.common", "harness.cli.run", "harness.cli.gate",
                         "harness.cli.compare", "harness.cli.identify", "harness.cli.replay", "harness.cli.bench_command",
                         "harness.cli.fuzz", "harness.cli.diff", "harness.cli.listing", "harness.results.output",
                         "harness.results.gate", "harness.integrations.pytest_plugin",
                         "harness.results.atlas", "harness.cli.atlas")
ENGINE_PACKAGES = ("harness.geometry", "harness.contract", "harness.kinds", "harness.oracle", "harness.checks",
                   "harness.diagnose", "harness.identify", "harness.engine", "harness.results.files", "harness.cli.bench",
                   "harness.cli.bench_workloads", "harness.cli.bench_peers", "harness.cli.bench_campaign", "cases", "rasterizers")


def _under(name: str, packages: tuple[str, ...]) -> bool:
    return any(name == p or name.startswith(p + ".") for p in packages)


def test_the_engine_imports_no_presentation_module():
    """Presentation (report, pictures, command line, output formats) sits on the engine,
    never under it: no engine module reaches one, however indirectly."""
    graph = _module_graph()
    engine = {m for m in graph if _under(m, ENGINE_PACKAGES)}
    presentation = {m for m in graph if _under(m, PRESENTATION_PACKAGES)}
    assert len(engine) > 60 and len(presentation) >= 6, (len(engine), sorted(presentation))
    for start in sorted(engine):
        seen, todo = set(), [start]
        while todo:
            name = todo.pop()
            for nxt in graph.get(name, ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        assert not seen & presentation, (start, sorted(seen & presentation))
