"""The API a plugin author needs (issue 28, point 3): every name a plugin uses is exported by
`harness` with its real signature, and every plugin of the README's section "What
`rasterize` receives and returns" runs, as written there, and passes cases of its kind."""

import inspect
import re
from pathlib import Path

import pytest

import harness
from cases.suites import suite
from harness import run_suite

README = Path(__file__).resolve().parents[2] / "README.md"
SECTION = "## What `rasterize` receives and returns"

# each plugin of the section -> its class and a few quick cases of its kind
PLUGINS = {
    "centre_triangles": ("CentreTriangles", ["lattice/bits-8", "watertight/grid-6x6-main/lattice",
                                             "degenerate/non-finite/mixed"]),
    "msaa_triangles": ("MsaaTriangles", ["lattice/bits-2", "degenerate/non-finite/mixed"]),
    "supersampled_triangles": ("SupersampledTriangles", ["watertight/fan-8/centre", "degenerate/zero-area/collinear"]),
    "winding_paths": ("WindingPaths", ["paths/star-5-2/lattice/evenodd", "paths/ring/hole-opposite/lattice/nonzero",
                                       "path-partitions/quads-5x5/lattice/nonzero", "path-degenerate/non-finite/mixed/nonzero"]),
    "floor_bresenham": ("FloorBresenham", ["lines/octants/centres", "line-strips/joints/centres", "lines/wide-2.5/lattice",
                                           "line-degenerate/non-finite/mixed", "line-degenerate/huge/1e10"]),
}

# what the line drawer declines, and the skip saying why
DECLINED = {"lines/wide-2.5/lattice": "unsupported: draws lines of width 1 only, not 2.5",
            "line-degenerate/huge/1e10": "declined huge segment 3: segment 3 reaches beyond 1e6 px"}


def _section() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index(SECTION)
    end = text.find("\n## ", start + len(SECTION))
    return text[start:end if end >= 0 else len(text)]


@pytest.fixture(scope="module")
def plugins(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The section's python blocks that start with ``# name.py``, written side by side (a
    later one imports an earlier one, as a user's files would)."""
    folder = tmp_path_factory.mktemp("readme_plugins")
    for block in re.findall(r"```python\n(.*?)```", _section(), flags=re.S):
        named = re.match(r"# (\w+)\.py\b", block)
        if named:
            (folder / f"{named.group(1)}.py").write_text(block, encoding="utf-8")
    return folder


def test_the_section_holds_the_plugins_tested_here(plugins: Path) -> None:
    assert sorted(p.stem for p in plugins.glob("*.py")) == sorted(PLUGINS)
    section = _section()
    for kind in ("triangles", "paths", "lines", "single", "multisample", "area"):
        assert kind in section
    assert "[Lines](#lines)" in section  # the direction of travel: where it is explained


@pytest.mark.parametrize("name", list(PLUGINS))
def test_each_readme_plugin_passes_cases_of_its_kind(name: str, plugins: Path) -> None:
    cls, ids = PLUGINS[name]
    by_id = {c.id: c for c in suite("quick", 0)}
    results = run_suite([f"{plugins / name}.py:{cls}"], cases=[by_id[i] for i in ids], identify=False, repros=False)
    bad = [(r.case, r.check, r.status, r.message) for r in results if r.status not in ("pass", "skip")]
    assert not bad
    passed = {r.case for r in results if r.status == "pass"}
    declined = {r.case: r.message for r in results if r.status == "skip" and r.check in ("run", "degenerate")}
    assert passed | set(declined) == set(ids) and not passed & set(declined)
    assert declined == {k: v for k, v in DECLINED.items() if k in ids}  # each refusal a skip, saying why


def test_a_broken_copy_of_a_readme_plugin_fails(plugins: Path, tmp_path: Path) -> None:
    """The plugins' runs can fail: the same triangles plugin with the tie rule turned
    (a sample on an edge counted as left of it) fails conformance."""
    text = (plugins / "centre_triangles.py").read_text(encoding="utf-8")
    broken = text.replace("(cross > 0)", "(cross >= 0)").replace("(cross < 0)", "(cross <= 0)")
    assert broken != text
    (tmp_path / "centre_triangles.py").write_text(broken, encoding="utf-8")
    case = next(c for c in suite("quick", 0) if c.id == "watertight/grid-6x6-main/lattice")
    results = run_suite([f"{tmp_path}/centre_triangles.py:CentreTriangles"], cases=[case], identify=False, repros=False)
    assert "conformance" in {r.check for r in results if r.status == "fail"}


def test_harness_exports_what_a_plugin_uses() -> None:
    for name in ("Scene", "PathScene", "LineScene", "AnyScene", "SCENE_KINDS", "Coverage", "Unsupported", "Rasterizer",
                 "Convention", "LineRule", "STANDARD_PATTERNS", "pattern", "run_suite", "replay", "Result", "Tolerance",
                 "assert_conforms", "span_buffers", "by_cause"):
        assert name in harness.__all__ and getattr(harness, name) is not None, name
    from harness.contract.conventions import LineRule
    from harness.contract.scenes import LineScene, Unsupported
    from harness.integrations.testing import assert_conforms

    assert (harness.LineScene, harness.Unsupported, harness.LineRule) == (LineScene, Unsupported, LineRule)
    assert harness.assert_conforms is assert_conforms
    from harness.diagnose.causes import by_cause

    assert harness.by_cause is by_cause
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        harness.nothing_here  # noqa: B018


@pytest.mark.parametrize("name", ["run_suite", "replay"])
def test_the_exported_runners_have_the_runners_signatures(name: str) -> None:
    """No ``*args: Any``: the same parameters, kinds and defaults as :mod:`harness.engine.runner`'s
    (``tolerance`` None standing for the default Tolerance, so that importing harness
    does not import the checks)."""
    from harness.checks import Tolerance
    from harness.engine import runner

    ours = inspect.signature(getattr(harness, name)).parameters
    theirs = inspect.signature(getattr(runner, name)).parameters
    assert list(ours) == list(theirs)
    for key, p in ours.items():
        q = theirs[key]
        assert p.kind == q.kind, key
        assert p.default == q.default or (key == "tolerance" and p.default is None and q.default == Tolerance()), key
        assert p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
