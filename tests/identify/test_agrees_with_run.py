"""identify and run agree (issue 28, points 5 and 10): every defect identify reports is
a case of the suite for that scene kind, carries its evidence and a minimal repro on the
card, in --json and on the fingerprint page, and ``run`` fails that case; a declared
convention is never called confirmed or consistent while a check of its coverage kind
fails on identify's probe scenes; sample patterns are described in a few words.

The plugins are the ones a new user wrote from the README (:mod:`tests.readme_plugins`)."""

from __future__ import annotations

import contextlib
import functools
import io
import json

import pytest

from cases.degenerate import degenerate_cases
from cases.paths import path_cases
from cases.suites import suite as quick_suite
from harness.cli.main import main
from harness.contract.case import Case, case_from_json
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import PathScene
from harness.engine.isolation import InProcess
from harness.engine.registry import load
from harness.engine.runner import replay, run_suite
from harness.identify.fingerprint import Fingerprint, identify
from harness.identify.triangle_defects import NON_FINITE_CASES, ZERO_AREA_CASE, non_finite, suite_defects
from harness.report.pages import write_report
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.readme_plugins import GRID_4X4, EvenOddScanline

IRREGULAR = ((0.25, 0.5), (0.75, 0.25), (0.5, 0.875))


class ExactEvenOdd:
    """A correct paths-only even-odd filler: the reference trapezoid fill behind the same
    interface as :class:`tests.readme_plugins.EvenOddScanline`."""

    name = "exact_evenodd"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")
    scene_kinds = ("paths",)
    fill_rules = ("evenodd",)
    interpolates = False

    def __init__(self) -> None:
        self.inner = load("trapezoid_fill")

    def rasterize(self, scene: PathScene) -> Coverage:
        return self.inner.rasterize(scene)


@functools.cache
def scanline() -> Fingerprint:
    return identify(EvenOddScanline())


@functools.cache
def identify_cli(*args: str) -> tuple[int, str]:
    """``rastercheck identify ARGS``: the exit code and what it printed (once per module)."""
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["identify", *args])
    return code, printed.getvalue()


def test_identify_and_run_agree_on_a_scanline_path_filler(tmp_path):
    fingerprint = scanline()
    assert fingerprint.facts["watertight"].startswith("no:"), fingerprint.card()
    leaks = fingerprint.defects["watertight"]
    assert leaks and all(d.check == "watertight" and d.evidence["blame"] for d in leaks)
    # each leaking scene is a case of the path suite, and run fails watertight there, as identify says
    suite = {c.id: c for c in path_cases(0)}
    cases = [suite[d.case] for d in leaks]
    results = run_suite([EvenOddScanline()], cases=cases, only={"watertight"}, isolate=False, repros=False, identify=False)
    assert [r.status for r in results if r.check == "watertight"] == ["fail"] * len(cases)
    # a correct filler through the same interface passes the same cases, and identify sees nothing
    assert all(r.status == "pass" for r in run_suite([ExactEvenOdd()], cases=cases, only={"watertight"}, isolate=False,
                                                     repros=False, identify=False))
    # the minimal repro: a few paths of the partition, and it fails again when replayed
    repro = leaks[0].repro
    assert repro is not None and len(repro["paths"]) < len(cases[0].scene) and repro["original_case"] == leaks[0].case
    path = tmp_path / "repro.json"
    path.write_text(json.dumps(repro))
    replayed = case_from_json(repro)
    assert isinstance(replayed, Case) and isinstance(replayed.scene, PathScene)
    assert any(r.status == "fail" and r.check == repro["check"] for r in replay(str(path), EvenOddScanline(), isolate=False))
    card = fingerprint.card()
    assert f"rastercheck run --case '{leaks[0].case}' fails watertight" in card and "minimal repro" in card
    assert fingerprint.to_dict()["defects"]["watertight"][0]["repro"] == repro


def test_the_fingerprint_page_shows_each_defect_with_its_repro(tmp_path):
    fingerprint = scanline()
    name = fingerprint.rasterizer
    declared = EvenOddScanline.convention.describe()
    write_report(tmp_path, {name: declared}, [], 0, fingerprints={name: fingerprint.to_dict()}, declared={name: declared})
    page = (tmp_path / "fingerprints.html").read_text()
    leaks = fingerprint.defects["watertight"]
    assert "Evidence for each defect identify saw" in page
    for k, d in enumerate(leaks):
        assert d.case in page
        if d.repro is not None:
            saved = tmp_path / "repros" / name / f"identify--watertight--{k}.json"
            assert f'href="repros/{name}/identify--watertight--{k}.json"' in page
            assert json.loads(saved.read_text()) == d.repro
    hole = next(b for d in leaks for b in d.evidence["blame"])
    assert f"{hole['kind']} at ({hole['pixel'][0]}, {hole['pixel'][1]})" in page


def test_a_correct_paths_only_filler_has_no_defect():
    fingerprint = identify(ExactEvenOdd())
    assert fingerprint.exact and not fingerprint.defects, fingerprint.card()
    assert fingerprint.facts["watertight"].startswith("yes") and "defects" not in fingerprint.to_dict()


def test_every_defect_identify_reports_is_a_suite_case_that_run_fails():
    """Inclusive edges (undeclared, so identify fits a convention) leak on partitions and draw
    zero-area triangles; each scene identify blames is a case of the triangle suite, and
    run fails the same check there against what the rasterizer declares."""
    from tests.identify.test_triangle_probes import _inclusive

    fingerprint = _inclusive()
    assert {"watertight", "zero area"} <= set(fingerprint.defects), fingerprint.card()
    suite = {c.id: c for c in quick_suite("quick") if isinstance(c, Case)}
    for label, found in fingerprint.defects.items():
        for d in found:
            results = run_suite([EdgeFunctionBug("inclusive")], cases=[suite[d.case]], only={d.check}, isolate=False,
                                repros=False, identify=False)
            assert [r.status for r in results if r.check == d.check] == ["fail"], (label, d.case)
    assert fingerprint.defects["zero area"][0].case == ZERO_AREA_CASE


def test_non_finite_triangles_drawn_are_suite_cases_that_fail():
    bad, good = EdgeFunctionBug("nan-to-num"), load("floor_scanline")
    cases = [c for c in degenerate_cases(0) if c.id in NON_FINITE_CASES.values()]
    assert len(cases) == 2 and non_finite(InProcess(bad)).wrong and not non_finite(InProcess(good)).wrong
    found = suite_defects(InProcess(bad), cases, {"conformance"}, bad.convention, bad.name)
    assert [d.case for d in found] == [c.id for c in cases] and all(d.repro is not None for d in found)
    assert not suite_defects(InProcess(good), cases, {"conformance"}, good.convention, good.name)


def test_identify_does_not_call_an_inclusive_anti_aliaser_consistent(tmp_path):
    out = tmp_path / "f.json"
    code, said = identify_cli("tests/readme_plugins.py:InclusiveSupersampler", "--json", str(out))
    assert code == 1
    declared = next(line for line in said.splitlines() if line.startswith("declared"))
    assert "NOT what it does" in declared and "consistent" not in declared and "confirmed" not in declared
    for check in ("accuracy", "seams", "popping"):
        assert f"{check} fails on" in declared, declared
    assert json.loads(out.read_text())["contradicted"] is True
    # the same grid with top-left ties per sample, as declared: confirmed, the checks named
    code, said = identify_cli("supersample4")
    assert code == 0 and "(confirmed (accuracy and seams and popping pass against it on" in said


def test_a_supersampling_grid_prints_in_a_few_words():
    grid = Convention(coverage="area", samples=GRID_4X4, levels=17)
    assert "(4x4 grid at (1/8 + k/4))" in grid.describe() and "0.125" not in grid.describe()
    code, said = identify_cli("supersample4")
    assert code == 0
    lines = {line[:12].strip(): line for line in said.splitlines() if line[:12].strip()}
    for label in ("convention", "declared"):
        assert "4x4 grid at (1/8 + k/4)" in lines[label] and "0.125" not in lines[label] and len(lines[label]) < 250
    assert "samples=<4x4 grid at (1/8 + k/4)>" in said  # the Convention(...) line too


def test_a_standard_pattern_prints_by_its_name_and_anything_else_as_a_count():
    assert Convention(samples=4).describe().startswith("D3D11 4x, top-left ties")
    assert Convention(samples=16).describe().startswith("D3D11 16x,")
    said = Convention(samples=IRREGULAR, tie="top-right").describe()
    assert said.startswith("3 samples at irregular offsets (listed in --json and the report)") and "0.875" not in said
    # the standard offsets in another order are no standard pattern (their sample ids differ)
    assert not Convention(samples=tuple(reversed(STANDARD_PATTERNS[4]))).describe().startswith("D3D11")
    column_by_column = tuple((x, y) for x, _ in GRID_4X4[:4] for _, y in GRID_4X4[::4])
    assert "4x4 grid at (1/8 + k/4), samples in another order" in Convention(samples=column_by_column).describe()
    wide = tuple(((i + 0.5) / 16, (j + 0.5) / 4) for j in range(4) for i in range(16))
    assert Convention(coverage="area", samples=wide).describe().count("16x4 grid at (1/32 + i/16, 1/8 + j/4)") == 1


@pytest.mark.parametrize("samples, linked", [(IRREGULAR, True), (STANDARD_PATTERNS[8], False)], ids=["irregular", "standard"])
def test_the_fingerprint_page_links_the_offsets_words_do_not_spell(tmp_path, samples, linked):
    convention = Convention(samples=samples)
    fingerprint = Fingerprint("ms", convention, 0, 100, runner_up=("another tie rule", 3), coverage_kind="multisample").to_dict()
    assert fingerprint["samples"] == [list(o) for o in samples]  # the JSON keeps the offsets in full
    write_report(tmp_path, {"ms": convention.describe()}, [], 0, fingerprints={"ms": fingerprint},
                 declared={"ms": convention.describe()}, patterns={"ms": convention.samples})
    page = (tmp_path / "fingerprints.html").read_text()
    assert ('href="#offsets-0"' in page) == linked and ("(0.25, 0.5) (0.75, 0.25) (0.5, 0.875)" in page) == linked
    assert '<td class="pass">confirmed</td>' in page
    # the same words with other offsets are not confirmed
    other = tuple(reversed(samples))
    write_report(tmp_path, {"ms": convention.describe()}, [], 0, fingerprints={"ms": fingerprint},
                 declared={"ms": convention.describe()}, patterns={"ms": other})
    assert '<td class="fail">not confirmed</td>' in (tmp_path / "fingerprints.html").read_text()
