"""Refusals that teach (issue 28, point 6): a plugin whose declarations contradict each other
or its answers gets one line saying what to add, not an error per case; `run_suite` and
`rastercheck run` agree; correct plugins are unaffected."""

import json
from pathlib import Path
from typing import Any

import pytest

from cases.suites import suite
from harness import Convention, Coverage, LineRule, Scene, run_suite
from harness.checks import checks
from harness.cli.main import main
from harness.contract.case import MotionCase
from harness.contract.declarations import REFUSED, answer_problem, declaration_problem
from harness.engine.registry import builtins, load
from tests.known_bad import antialiasing, declarations, lines, paths
from tests.known_bad.declarations import ANSWER_BADS, LOAD_BADS, DiamondDrawerNoLines

FILE = "tests/known_bad/declarations.py"


@pytest.fixture(scope="module")
def few_cases():
    """Three triangle scenes and a motion sequence: enough to see 'once, not per case'."""
    every = suite("quick", 0)
    still = [c for c in every if c.id in ("lattice/bits-0", "lattice/bits-8", "watertight/grid-6x6-main/lattice")]
    motion = [c for c in every if isinstance(c, MotionCase)][:1]
    return still + motion


@pytest.mark.parametrize("bad", list(LOAD_BADS), ids=lambda b: b.name)
def test_a_contradicting_declaration_is_refused_at_load_in_one_line(bad) -> None:
    text = LOAD_BADS[bad]
    spec = f"{FILE}:{bad.__name__}"
    with pytest.raises(ValueError) as loading:
        load(spec)
    with pytest.raises(ValueError) as running:  # an object handed to run_suite: the same words
        run_suite([bad()], cases=[], identify=False)
    for message, culprit in ((str(loading.value), spec), (str(running.value), bad.name)):
        assert message.startswith(f"{culprit}: {REFUSED}: ") and text in message and "\n" not in message


def test_the_command_line_refuses_it_in_one_line_exit_2(tmp_path, capsys) -> None:
    code = main(["run", "--rasterizer", f"{FILE}:LineRuleNoLines", "--no-fingerprints", "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and LOAD_BADS[declarations.LineRuleNoLines] in err[0]


@pytest.mark.parametrize("bad", list(ANSWER_BADS), ids=lambda b: b.name)
def test_a_contradicting_answer_gives_one_line_and_no_more_calls(bad, few_cases) -> None:
    calls = []

    class Counted(bad):  # type: ignore[misc]  # (a known-bad class, parametrized)
        def rasterize(self, scene):
            calls.append(scene)
            return super().rasterize(scene)

    results = run_suite([Counted()], cases=few_cases, identify=False, isolate=False, repros=False)
    assert len(results) == 1, [(r.case, r.check, r.message) for r in results]
    (only,) = results
    assert only.status == "error" and only.check == "run" and only.evidence["refused"] == "triangles"
    assert only.message.startswith(f"{REFUSED}: ") and ANSWER_BADS[bad] in only.message and "\n" not in only.message
    assert only.case == "lattice/bits-0" and "traceback" not in only.evidence
    assert len(calls) == 1  # the first answer said it all: nothing else was handed to it


def test_run_suite_and_the_command_line_agree(tmp_path, capsys) -> None:
    """`rastercheck run` on the drawer that forgot its scene kinds: the same one result,
    one line in the terminal, exit 1."""
    out = tmp_path / "r.json"
    code = main(["run", "--rasterizer", f"{FILE}:DiamondDrawerNoLines", "--case", "lattice/bits-*", "--no-fingerprints",
                 "--out", str(tmp_path / "rep"), "--json", str(out)])
    printed = capsys.readouterr().out
    from_cli = [(r["case"], r["check"], r["status"], r["message"]) for r in json.loads(out.read_text())["results"]]
    cases = [c for c in suite("quick", 0) if c.id.startswith("lattice/bits-")]
    from_library = [(r.case, r.check, r.status, r.message) for r in run_suite([DiamondDrawerNoLines()], cases=cases,
                                                                              identify=False)]
    assert code == 1 and from_cli == from_library and len(from_cli) == 1
    assert printed.count(ANSWER_BADS[DiamondDrawerNoLines]) == 1 and "Traceback" not in printed


def _rasterizers(module):
    return [value for value in vars(module).values()
            if isinstance(value, type) and callable(getattr(value, "rasterize", None))
            and isinstance(getattr(value, "name", None), str)
            and value.__module__ == module.__name__ and not value.__name__.startswith("_")]


def test_correct_declarations_are_unaffected() -> None:
    """The built-ins and the other known-bads (wrong drawing, right declaration) load and
    agree with themselves; a correct answer of each coverage kind passes."""
    for name in builtins():
        assert declaration_problem(load(name)) is None, name
    plugins = [*lines.LINE_BADS, *(paths.PathFillBug(bug) for bug in paths.BUGS), paths.TwoFillers(),
               *(cls() for cls in _rasterizers(antialiasing))]
    assert len(plugins) >= 19
    for r in plugins:
        assert declaration_problem(r) is None, r.name
    spans = Coverage([0], [0], [0], [2])
    assert answer_problem(Convention(), spans) is None
    assert answer_problem(Convention(samples=4), Coverage([0], [0], [0], [2], sample=[3])) is None
    assert answer_problem(Convention(coverage="area"), Coverage([0], [0], [0], [2], alpha=[0.5, 1.0])) is None
    assert answer_problem(Convention(coverage="area"), Coverage.empty()) is None  # nothing drawn contradicts nothing
    assert answer_problem(None, Coverage([0], [0], [0], [2], sample=[1])) is None  # undeclared: identify reads the kind


def test_line_and_area_conventions_need_what_their_scene_kinds_allow() -> None:
    class Mixed:
        name, scene_kinds = "mixed", ("triangles", "lines")
        convention = Convention(samples=4)

        def rasterize(self, scene: Scene) -> Coverage:
            return Coverage.empty()

    assert "line_convention = Convention(line=...)" in (declaration_problem(Mixed()) or "")
    Mixed.line_convention = Convention(line=LineRule("bresenham"))  # type: ignore[attr-defined]  # declared afterwards
    assert declaration_problem(Mixed()) is None


def test_pytest_items_say_it_once_too(tmp_path, capsys, monkeypatch) -> None:
    """``pytest --rasterizer``: the first case's items fail with the one line (no
    traceback), the other cases of that kind are skipped, not handed to it; a
    declaration that contradicts itself is a usage error in one line."""
    from tests.integrations.test_pytest_plugin import plugin_run_here

    spec = f"{Path(__file__).resolve().parents[2] / FILE}"
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "-q", "-rfs", "--rasterizer", f"{spec}:DiamondDrawerNoLines",
                           "-k", "lattice/bits-0 or lattice/bits-2")
    first = len(checks(next(c for c in suite("quick", 0) if c.id == "lattice/bits-0"), coverage_kind="single"))
    assert proc.returncode == 1 and f"{first} failed" in proc.stdout and f"{first} skipped" in proc.stdout, proc.stdout[-3000:]
    assert ANSWER_BADS[DiamondDrawerNoLines] in proc.stdout and "Traceback" not in proc.stdout
    assert "not handed to it: its answer on lattice/bits-0 contradicted its declaration" in proc.stdout
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "-q", "--rasterizer", f"{spec}:LineRuleNoLines")
    assert proc.returncode == 4 and LOAD_BADS[declarations.LineRuleNoLines] in proc.stderr


def test_a_kind_listed_but_drawn_as_another_is_named() -> None:
    """A triangle filler that lists paths too reads ``positions`` of a path scene: leave
    "paths" out; a member two kinds have names both."""
    from harness import PathScene
    from harness.contract.declarations import scene_kind_problem

    class Filler:
        name, convention, scene_kinds = "filler", Convention(), ("triangles", "paths")

        def rasterize(self, scene: Any) -> Coverage:  # never called: the problem is read from the error
            raise NotImplementedError

    square = PathScene.from_paths(4, 4, [[[[0, 0], [2, 0], [2, 2], [0, 2]]]])
    said = scene_kind_problem(Filler(), square, AttributeError("'PathScene' object has no attribute 'positions'"))
    assert said is not None
    assert 'lists "paths" in scene_kinds but does not draw them: leave "paths" out (scene_kinds = ("triangles",))' in said
    triangle = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    said = scene_kind_problem(Filler(), triangle, AttributeError("'Scene' object has no attribute 'strip_sizes'"))
    assert said is not None and 'lack "lines": add "lines" (scene_kinds = ("triangles", "paths", "lines"))' in said
    both = scene_kind_problem(Filler(), triangle, AttributeError("'Scene' object has no attribute 'vertices'"))
    assert both is not None and "which path and line and point scenes have" in both and 'lack "lines"' in both
    assert scene_kind_problem(Filler(), triangle, AttributeError("'Scene' object has no attribute 'frobnicate'")) is None
    assert scene_kind_problem(Filler(), triangle, KeyError("segments")) is None


@pytest.mark.parametrize(("members", "said"), [
    ({"scene_kinds": 3}, "scene_kinds = 3 is not a tuple of kinds"),
    ({"scene_kinds": ("triangle",)}, "scene_kinds names 'triangle', which is no scene kind"),
    ({"scene_kinds": ()}, "scene_kinds is empty, so no scene would reach it"),
    ({"scene_kinds": ("paths",), "fill_rules": "evenodd"},
     'fill_rules = \'evenodd\' is one string, not a tuple of rules: write fill_rules = ("evenodd",)'),
    ({"scene_kinds": ("paths",), "fill_rules": ("even-odd",)}, "fill_rules names 'even-odd', which is no fill rule"),
    ({"scene_kinds": ("paths",), "fill_rules": ()}, "fill_rules is empty, so no path scene would reach it"),
    ({"scene_kinds": ("paths",), "convention": Convention(coverage="area-threshold")},
     "a coverage rule defined for triangles only"),
])
def test_each_self_contradiction_is_named(members, said) -> None:
    plugin = type("Plugin", (), {"name": "plugin", "convention": Convention(), "rasterize": lambda self, scene: None,
                                 **members})()
    problem = declaration_problem(plugin)
    assert problem is not None and problem.startswith(f"{REFUSED}: ") and said in problem, problem


def test_a_second_copy_keeps_what_it_declares() -> None:
    """Two line drawers of one name: the second, renamed, still takes lines (and is not
    refused for a line rule without them)."""
    from harness.engine.registry import distinct_names
    from rasterizers.lines import BresenhamLines
    first, second = distinct_names([BresenhamLines(), BresenhamLines()])
    assert second.name == "bresenham_lines#2" and getattr(second, "scene_kinds", None) == ("lines",)
    assert declaration_problem(second) is None
    filler = paths.PathFillBug("open-contours")
    renamed = distinct_names([filler, filler])[1]
    assert getattr(renamed, "scene_kinds", None) == filler.scene_kinds
    assert getattr(renamed, "fill_rules", None) == getattr(filler, "fill_rules", None)


def test_every_registered_rasterizer_declares_consistently() -> None:
    """Each built-in and adapter (those whose library is here) passes the check `run` applies
    at load: mesa_llvmpipe_msaa4 inherited llvmpipe's fill rules without its paths and was
    skipped by every run ("contradicts its declaration") while its own tests, which build it
    directly, passed."""
    from harness.engine.registry import Unavailable, _entry_points

    checked = []
    for name, entry in sorted(_entry_points().items()):
        try:
            rasterizer = entry.load()()
        except Unavailable:
            continue  # its library is not installed here: `run` skips it saying so
        assert declaration_problem(rasterizer) is None, (name, declaration_problem(rasterizer))
        checked.append(name)
    assert set(builtins()) <= set(checked)
