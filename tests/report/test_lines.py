"""Line scenes in the report, the pictures, the JSON and the gate: a failing line case's crop
draws each strip as a polyline from end point to end point over the pixel grid, its pixels
coloured segment by segment against the oracle, the joints, the segment numbers and, under
the diamond-exit rule, the diamond test area of the offending pixel; its minimal repro is
drawn likewise; the index has a table of line drawers with a column per check that judges
lines (derived from the registry); line results round-trip through JSON and gate like any
others.

The failures come from a small broken line drawer defined here (the oracle under a wrong
line rule: the last pixel drawn, so a strip's joints are drawn by both their segments),
judged by a check registered for this module only (the real line checks live in
harness.checks and are tested with their own known-bad rasterizers)."""

from __future__ import annotations

import base64
import json
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from markupsafe import escape

from harness.checks import Check, Result, deviations, registered, result
from harness.checks.records import Drawing, Subject
from harness.contract.case import Case, case_from_json
from harness.contract.conventions import Convention, LineRule
from harness.contract.scenes import LineScene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
from harness.report import pictures
from harness.report.pages import capabilities, line_checks, on_lines, write_report
from harness.results.gate import compare_with_baseline, load_baseline, save_baseline
from harness.results.output import results_from_json, results_to_json, write_json
from tests.report.pictured import attr, drawn_case, number, repro_picture, title_text, titled

SVG = "{http://www.w3.org/2000/svg}"
CHECK = "test-line-exact"  # registered by the fixture below, for this module only

# A strip of three segments (two joints; segment 0 x-major, 1 y-major) and a lone segment
# crossing it, on the 1/4 px lattice: every decision exact, no end point on a pixel border
# but (14.5, 14.0), a joint on a row border.
STRIP = [[1.5, 1.5], [12.5, 5.5], [14.5, 14.0], [3.25, 10.75]]
LONE = [[2.0, 13.0], [20.25, 9.5]]
DIAMOND = Convention(line="diamond-exit")
LAST_PIXEL = Convention(line=LineRule("diamond-exit", last_pixel=True))


class LastPixelLines:
    """Declares diamond-exit lines (last pixel omitted) and draws the last pixel too: each
    joint is drawn by both its segments, each lone segment's end pixel is extra."""

    name = "bad_last_pixel_lines"
    convention = DIAMOND
    scene_kinds = ("lines",)

    def rasterize(self, scene: LineScene) -> Any:
        return exact_coverage(scene, LAST_PIXEL)


class ExactLines:
    """The oracle itself: passes."""

    name = "exact_lines"
    convention = DIAMOND
    scene_kinds = ("triangles", "lines")

    def rasterize(self, scene: Any) -> Any:
        return exact_coverage(scene, self.convention)


def exact_lines(subject: Subject) -> Result:
    """Every fragment (segment, x, y) against the oracle's, as conformance judges them."""
    scene = subject.case.scene
    missing, extra = deviations(subject.coverage, subject.oracle, scene.width, scene.height)
    both = np.concatenate([missing, extra], axis=1)
    kinds = ["missing"] * missing.shape[1] + ["extra"] * extra.shape[1]
    pixels = [{"segment": k, "x": x, "y": y, "kind": kind} for (k, x, y), kind in zip(both.T.tolist(), kinds)]
    return result(subject.case.id, CHECK, not pixels, f"{missing.shape[1]} missing, {extra.shape[1]} extra",
                  {"wrong": float(len(pixels))}, {"pixels": pixels} if pixels else {})


def _is_lines(case: Any) -> bool:
    return isinstance(getattr(case, "scene", None), LineScene)


CASES = [Case("lines/strip-and-lone", LineScene.from_strips(24, 16, [STRIP, LONE]), lattice=True),
         Case("lines/lone", LineScene.from_strips(24, 16, [LONE]), lattice=True)]


@pytest.fixture(scope="module")
def line_check() -> Iterator[Check]:
    with registered(Check(CHECK, exact_lines, _is_lines, needs_convention=True, shrinks=True, metrics={"wrong": (1.0, 0.0)},
                          caption="every fragment of every segment as the oracle's (this test's)")) as check:
        yield check


@pytest.fixture(scope="module")
def results(line_check: Check) -> list[Result]:
    """The broken drawer's failures on both cases (with minimal repros), the exact one's
    passes, and a joints failure built by hand from the first (as a line check reports a
    joint drawn twice; the message tries to inject markup)."""
    run = run_suite([LastPixelLines(), ExactLines()], cases=CASES, isolate=False, identify=False, only={CHECK})
    first = next(r for r in run if r.rasterizer == LastPixelLines.name and r.case == CASES[0].id)
    joints = replace(first, check="joints", message="1 joint drawn by both its segments <script>alert(1)</script>",
                     metrics={"double_hits": 1.0},
                     evidence={"double_hits": [{"segments": [0, 1], "x": 12, "y": 5}], "repro": first.evidence["repro"]})
    return [*run, joints]


def _svg(uri: str) -> ET.Element:
    assert uri.startswith("data:image/svg+xml;base64,")
    return ET.fromstring(base64.b64decode(uri.split(",", 1)[1]))


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def _pixel_fills(svg: ET.Element) -> dict[tuple[int, int], str]:
    """Each filled pixel of a picture and its colour (runs of one row as <rect height=1>)."""
    out = {}
    for rect in svg.iter(SVG + "rect"):
        if rect.get("height") == "1":
            x, y, w = int(number(rect, "x")), int(number(rect, "y")), int(number(rect, "width"))
            out.update({(x + i, y): attr(rect, "fill") for i in range(w)})
    return out


def _labels(svg: ET.Element, starting: str) -> dict[str, ET.Element]:
    """The texts whose <title> starts with ``starting``: what each shows (the title's tail) -> the element."""
    out = {}
    for t in svg.iter(SVG + "text"):
        title = t.find(SVG + "title")
        if title is not None and (title.text or "").startswith(starting):
            out[(title.tail or "").strip()] = t
    return out


def _failure(results: list[Result], case: str, check: str = CHECK) -> Result:
    return next(r for r in results if r.rasterizer == LastPixelLines.name and r.case == case and r.check == check)


# -- the pictures -------------------------------------------------------------------------


def test_the_broken_drawer_fails_at_the_joints_and_the_exact_one_passes(results: list[Result]) -> None:
    failure = _failure(results, CASES[0].id)
    # the last pixels: where segment 0 ends (the joint pixel (12, 5)), 1 ends, 2 ends, and the lone segment's
    assert failure.status == "fail" and sorted((p["segment"], p["x"], p["y"]) for p in failure.evidence["pixels"]) == [
        (0, 12, 5), (1, 14, 13), (2, 3, 10), (3, 20, 9)]
    assert all(r.status == "pass" for r in results if r.rasterizer == ExactLines.name)
    assert on_lines(failure) and on_lines(replace(failure, drawing=None))


def test_a_line_crop_draws_strips_joints_numbers_and_the_diamond_of_the_offending_pixel(results: list[Result]) -> None:
    failure = _failure(results, CASES[0].id)
    drawn = pictures.draw(failure)
    assert list(drawn) == ["heatmap", "diff", "crop"]
    svg = _svg(drawn["crop"])
    x0, y0, w, h = (int(float(v)) for v in attr(svg, "viewBox").split())
    assert (w, h) == (pictures.LINE_CROP_SIDE, pictures.LINE_CROP_SIDE) and x0 <= 12 < x0 + w and y0 <= 5 < y0 + h
    # the strip as one polyline through its vertices (all in view but the clipped start), the lone segment as another
    polylines = [[tuple(float(v) for v in pt.split(",")) for pt in attr(p, "points").split()] for p in svg.iter(SVG + "polyline")]
    assert any([tuple(v) for v in STRIP[1:]] == line[1:] for line in polylines)
    assert len(polylines) == 2
    # segment 0, named by the evidence, thick on top in its colour
    first_colour = _hex(pictures.LINE_LEGEND[list(pictures.LINE_LEGEND)[0]])
    thick = [line for line in svg.iter(SVG + "line") if line.get("stroke") == first_colour]
    assert len(thick) == 1 and (number(thick[0], "x2"), number(thick[0], "y2")) == (12.5, 5.5)
    assert pictures.numbered_segment(failure) == 0
    # every segment in view numbered, the joints dotted and named
    numbers = _labels(svg, "segment")
    assert set(numbers) == {"0", "1", "2", "3"} and numbers["0"].get("font-weight") == "bold"
    joints = {title_text(c) for c in svg.iter(SVG + "circle") if c.find(SVG + "title") is not None}
    assert joints == {"joint: segment 0 ends where segment 1 starts", "joint: segment 1 ends where segment 2 starts"}
    # the diamond test area of each offending pixel in view, segment 0 x-major: its right corner out
    diamonds = [title_text(g) for g in svg.iter(SVG + "g") if g.find(SVG + "title") is not None
                and title_text(g).startswith("diamond")]
    assert diamonds and diamonds[0].startswith("diamond test area of pixel (12, 5)")
    assert "right corner out (an x-major" in diamonds[0]
    outlined = {(int(number(r, "x")), int(number(r, "y"))) for r in svg.iter(SVG + "rect") if r.get("stroke")}
    assert (12, 5) in outlined


def test_a_line_crop_colours_each_pixel_segment_by_segment_against_the_oracle(results: list[Result]) -> None:
    failure = _failure(results, CASES[0].id)
    scene = drawn_case(failure).scene
    svg = _svg(pictures.draw(failure)["crop"])
    x0, y0, w, h = (int(float(v)) for v in attr(svg, "viewBox").split())
    fills = _pixel_fills(svg)
    got = exact_coverage(scene, LAST_PIXEL)
    want = exact_coverage(scene, DIAMOND)
    extra = {(x, y) for k, x, y in zip(*got.pixels()) if (k, x, y) not in set(zip(*want.pixels()))}
    drawn = {(x, y) for _, x, y in zip(*got.pixels())}
    expected = {(x, y): _hex(pictures.DIFF_LEGEND["extra (rasterizer only)"] if (x, y) in extra else pictures.DIFF_LEGEND["both"])
                for x, y in drawn if x0 <= x < x0 + w and y0 <= y < y0 + h}
    assert fills == expected
    # the joint pixel is drawn by the oracle too (segment 1 starts there), yet extra: segment 0 drew it
    assert fills[(12, 5)] == _hex(pictures.DIFF_LEGEND["extra (rasterizer only)"])
    # and it shows that two segments drew it
    hits = {(int(number(t, "x")), int(number(t, "y"))): titled(t).tail for t in svg.iter(SVG + "text")
            if t.get("fill") == _hex(pictures.LINE_LEGEND[list(pictures.LINE_LEGEND)[-1]])}
    counts = got.counts(scene.width, scene.height)
    assert hits == {(x, y): str(counts[y, x]) for y in range(y0, y0 + h) for x in range(x0, x0 + w) if counts[y, x] > 1}
    assert hits[(12, 5)] == "2"


@pytest.mark.parametrize("rule", ["rectangle", "bresenham", "parallelogram"])
def test_the_crop_draws_what_the_line_rule_needs(rule: str, results: list[Result]) -> None:
    failure = _failure(results, CASES[0].id)
    area = rule in ("rectangle", "parallelogram")
    convention = Convention(line=rule, sample=(0.25, 0.75)) if area else Convention(line=rule)
    original = drawn_case(failure).scene
    assert isinstance(original, LineScene) and failure.drawing is not None
    scene = original.with_line_width(3.0) if area else original
    case = Case(failure.case, scene, lattice=True)
    drawn = replace(failure, drawing=Drawing(case, failure.drawing.coverages, convention))
    svg = _svg(pictures.draw(drawn)["crop"])
    titles = [title_text(g) for g in svg.iter(SVG + "g") if g.find(SVG + "title") is not None]
    assert not [t for t in titles if t.startswith("diamond")]  # the diamond belongs to the diamond-exit rule only
    dotted = [p for p in svg.iter(SVG + "polygon") if p.get("stroke-dasharray")]
    dots = {(round(number(c, "cx") % 1, 6), round(number(c, "cy") % 1, 6)) for c in svg.iter(SVG + "circle")
            if c.get("fill") == "#333"}
    if rule == "rectangle":
        assert len(dotted) == 4 and dots == {(0.25, 0.75)}  # each segment's rectangle; the convention's sample points
        corners = [tuple(float(v) for v in pt.split(",")) for pt in attr(dotted[1], "points").split()]
        # segment 1's rectangle (wholly in view): its corners 1.5 px either side of its end points
        assert len(corners) == 4 and all(min(np.hypot(cx - ex, cy - ey) for ex, ey in STRIP[1:3]) == pytest.approx(1.5)
                                         for cx, cy in corners)
    elif rule == "parallelogram":
        assert len(dotted) == 4 and dots == {(0.25, 0.75)}  # each segment's parallelogram; the sample points
        corners = [tuple(float(v) for v in pt.split(",")) for pt in attr(dotted[1], "points").split()]
        # segment 1's parallelogram: its corners 1.5 px from its end points along one axis (the minor one)
        assert len(corners) == 4 and all(min(abs(cx - ex) + abs(cy - ey) for ex, ey in STRIP[1:3]) == pytest.approx(1.5)
                                         for cx, cy in corners)
        assert len({cx for cx, _ in corners}) == 2 or len({cy for _, cy in corners}) == 2  # ends parallel to an axis
    else:
        assert not dotted and dots == {(0.5, 0.5)}  # Bresenham steps through the pixel centres


def test_a_line_repro_is_drawn_with_its_segments_and_the_pixels_the_rule_draws(results: list[Result]) -> None:
    """What the rasterizer drew on the repro (kept in its file) on the left, what the rule
    draws on the right, the pixels the failure names on the repro outlined on both, and the
    segment drawn where it is (through the pixels the rule draws)."""
    failure = _failure(results, CASES[0].id)
    repro = case_from_json(failure.evidence["repro"])
    assert isinstance(repro, Case) and isinstance(repro.scene, LineScene) and len(repro.scene) < len(drawn_case(failure).scene)
    uri, caption = repro_picture(failure)
    n = len(repro.scene)
    assert caption.startswith(f"minimal repro: its {n} segment{'s' if n > 1 else ''} (of 4)")
    assert ("left: what the rasterizer drew, right: what the convention draws (diamond-exit lines, last pixel omitted, "
            "no snapping)") in caption
    left, right = _svg(uri).findall(SVG + "svg")
    x0, y0, w, h = (int(float(v)) for v in attr(right, "viewBox").split())
    want = exact_coverage(repro.scene, DIAMOND).counts(repro.scene.width, repro.scene.height)
    got = LastPixelLines().rasterize(repro.scene).counts(repro.scene.width, repro.scene.height)
    inside = [(x, y) for y in range(y0, y0 + h) for x in range(x0, x0 + w)]
    assert _pixel_fills(right) == {(x, y): _hex(pictures.CROP_LEGEND[pictures._CONVENTION]) for x, y in inside if want[y, x]}
    assert _pixel_fills(left) == {(x, y): _hex(pictures.CROP_LEGEND[pictures._DRAWN]) for x, y in inside if got[y, x]}
    # outlined: exactly the pixels where the two differ (the failure's own, on the repro)
    differ = {(x, y) for x, y in inside if bool(got[y, x]) != bool(want[y, x])}
    red = _hex(pictures.CROP_LEGEND["offending pixel (outlined)"])
    for panel in (left, right):
        outlined = {(int(number(r, "x")), int(number(r, "y"))) for r in panel.iter(SVG + "rect") if r.get("stroke") == red}
        assert outlined == differ and differ
    a, b = repro.scene.segments()
    line = next(e for e in right.iter(SVG + "line") if e.get("stroke-width") == "3")  # the segment, thick
    assert [number(line, k) for k in ("x1", "y1", "x2", "y2")] == [*a[0].tolist(), *b[0].tolist()]
    # read back from JSON (no drawing, no convention): what the rasterizer drew alone, and said so
    bare = results_from_json(json.loads(json.dumps(results_to_json([failure], "custom", 0, {}))))[0]
    uri, caption = repro_picture(bare)
    assert "what the rasterizer drew (no convention known, so nothing beside it)" in caption
    assert len(_svg(uri).findall(SVG + "svg")) == 1
    # a repro file from before the answer was kept: the rule's pixels alone, the whole case's marks near the segment
    old = {k: v for k, v in failure.evidence["repro"].items() if k not in ("answer", "evidence")}
    uri, caption = repro_picture(replace(failure, evidence={**failure.evidence, "repro": old}))
    assert "the pixels the convention draws (diamond-exit lines, last pixel omitted, no snapping)" in caption
    assert _pixel_fills(_svg(uri)) == {(x, y): _hex(pictures.CROP_LEGEND[pictures._CONVENTION]) for x, y in inside if want[y, x]}


def test_an_old_line_repros_marks_are_those_near_its_segments_not_in_their_box() -> None:
    """A diagonal segment's box holds pixels far from it: the whole case's offending pixels
    there are not the repro's (the issue's 25 pixels outlined away from a one-segment repro)."""
    scene = LineScene.from_strips(32, 32, [[[1.5, 1.5], [25.5, 25.5]]])
    near, far = (10, 10), (20, 3)
    assert pictures._near_segments([near, far], scene) == [near]


def test_the_failures_of_every_check_that_judges_lines_are_drawn(line_check: Check) -> None:
    """Whatever each registered line check puts in its evidence, its failures on the broken
    drawer are drawn: a heat map, a diff and a crop that parse, the crop naming a segment
    and marking pixels (those named, else where that segment departs from the oracle), and
    the minimal repro."""
    judging = set(line_checks()) - {"run"}
    found = [r for r in run_suite([LastPixelLines()], cases=CASES, isolate=False, identify=False, only=judging)
             if r.status == "fail"]
    assert {r.check for r in found} >= {CHECK}
    for failure in found:
        drawn = pictures.draw(failure)
        assert list(drawn) == ["heatmap", "diff", "crop"], failure.check
        svg = _svg(drawn["crop"])
        assert pictures.numbered_segment(failure) is not None and list(svg.iter(SVG + "polyline")), failure.check
        assert [r for r in svg.iter(SVG + "rect") if r.get("stroke")], f"{failure.check}: no pixel marked"
        if "repro" in failure.evidence:
            uri, _ = repro_picture(failure)
            assert _svg(uri).tag == SVG + "svg"


def test_line_colours_mean_nothing_else_in_any_picture() -> None:
    others = [pictures.HEAT_LEGEND, pictures.DIFF_LEGEND, pictures.LEGEND, pictures.ALPHA_LEGEND, pictures.CROP_LEGEND,
              pictures.PATH_LEGEND]
    used = {rgb for legend in others for rgb in legend.values()}
    assert not set(pictures.LINE_LEGEND.values()) & used
    assert len(set(pictures.LINE_LEGEND.values())) == len(pictures.LINE_LEGEND)


def test_the_evidence_names_the_pixels_and_the_segment_in_any_usual_form() -> None:
    def named(**evidence: Any) -> tuple[list[tuple[int, int]], int | None]:
        r = Result("r", "lines/x", "c", "fail", "m", {}, evidence)
        return pictures.line_focus(r), pictures.focus_segment(r)

    assert named(pixels=[{"segment": 2, "x": 4, "y": 5, "kind": "extra"}]) == ([(4, 5)], 2)
    assert named(total=3, gaps=[[1, 7, 8], [1, 8, 8]], columns=["segment", "x", "y"]) == ([(7, 8), (8, 8)], 1)
    assert named(double_hits=[{"segments": [4, 5], "pixel": [3, 3]}]) == ([(3, 3)], 4)
    assert named(differ=[[6, 2]]) == ([(6, 2)], None)
    assert named(series={"x": [1, 2]}, repro={"lines": []}) == ([], None)


# -- the report ---------------------------------------------------------------------------


FINGERPRINT = {"rasterizer": LastPixelLines.name, "convention": "sample (0.5, 0.5), top-left ties", "exact": True,
               "residual": 0, "pixels": 10, "runner_up": None, "facts": {"lines seen": "diamond-exit"}, "ambiguous": [],
               "line_rule": {"convention": "diamond-exit lines, last pixel drawn <b>", "exact": False, "residual": 3,
                             "pixels": 40},
               "line_rounding": "nearest-even"}


@pytest.fixture(scope="module")
def report(results: list[Result], tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("line-report")
    for r in results:
        if "repro" in r.evidence and r.check == CHECK:
            path = out / "repros" / r.rasterizer / f"{r.case.replace('/', '-')}--{r.check}.json"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(r.evidence["repro"]))
            r.evidence["repro_path"] = str(path.relative_to(out))
    rasterizers: list[LastPixelLines | ExactLines] = [LastPixelLines(), ExactLines()]
    conventions = {r.name: r.convention.describe() for r in rasterizers}
    write_report(out, conventions, results, seed=0, fingerprints={LastPixelLines.name: FINGERPRINT},
                 **capabilities(rasterizers))
    return out


def test_capabilities_say_each_line_drawers_rule() -> None:
    caps = capabilities([LastPixelLines(), ExactLines()])
    assert caps["scene_kinds"] == {LastPixelLines.name: ("lines",), ExactLines.name: ("triangles", "lines")}
    assert caps["line_rules"] == {name: "diamond-exit lines, last pixel omitted, no snapping"
                                  for name in (LastPixelLines.name, ExactLines.name)}


def test_the_columns_of_line_checks_come_from_the_registry(line_check: Check, results: list[Result]) -> None:
    judging = line_checks(results)
    assert CHECK in line_checks() and "conformance" in judging  # registered checks that apply to a line case
    assert "joints" in judging  # a check with results on line cases, registered or not
    assert "triangulation" not in judging and "jaggy" not in judging  # path and triangle-motion checks do not judge lines
    with registered(Check("test-line-late", line_check.run, _is_lines)):
        assert "test-line-late" in line_checks()
    assert "test-line-late" not in line_checks()


def test_the_index_tabulates_the_line_drawers_with_their_rule_and_failures(report: Path, results: list[Result]) -> None:
    index = (report / "index.html").read_text()
    assert "<script" not in index
    table = index[index.index('<h2 id="line-drawers">'):index.index("<h2>Conventions</h2>")]
    for name in (LastPixelLines.name, ExactLines.name):
        assert f'<a href="rasterizer-{name}.html">{name}</a>' in table
    header_row = re.search(r"<tr><th>rasterizer</th>.*?</tr>", table, re.S)
    assert header_row is not None
    header = header_row.group()
    columns = re.findall(r'<th title="[^"]*">([^<]+)</th>', header)
    assert columns == line_checks(results)
    assert "declared: diamond-exit lines, last pixel omitted, no snapping" in table
    # what identify found (escaped), and the other line_* fields as facts
    assert "diamond-exit lines, last pixel drawn &lt;b&gt; (best guess, residual 3)<br>" in table
    assert "rounding: nearest-even" in table
    row = table[table.index(f'<tr><td><a href="rasterizer-{LastPixelLines.name}.html">'):]
    row = row[:row.index("</tr>")]
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)[4:]
    by_check = dict(zip(columns, cells))
    failing = [r for r in results if r.rasterizer == LastPixelLines.name and r.status == "fail"]
    for check in (CHECK, "joints"):
        mine = [r for r in failing if r.check == check]
        assert by_check[check].startswith(f"0 / {len(mine)} / 0 / 0")
        for r in mine:
            assert re.search(rf'<a href="rasterizer-{LastPixelLines.name}.html#failure-\d+">{re.escape(r.case)}</a>',
                             by_check[check])
    assert re.search(r'\(<a href="repros/[^"]+\.json" download>repro</a>\)', by_check[CHECK])
    assert "takes lines" in index and "; lines: diamond-exit lines, last pixel omitted, no snapping" in index


def test_the_rasterizer_page_shows_line_failures_with_pictures_and_the_line_legend(report: Path) -> None:
    page = (report / f"rasterizer-{LastPixelLines.name}.html").read_text()
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in page and "<script>alert" not in page  # autoescape kept
    assert "Scenes: takes lines" in page and "lines checked against: diamond-exit lines, last pixel omitted" in page
    assert "on line cases: 0 pass, 3 fail, 0 error, 0 skip" in page
    assert re.search(r"<figcaption>crop: the segments over the pixel grid \(diamond-exit lines, last pixel omitted, no "
                     r"snapping\), each pixel coloured as against the oracle, segment by segment; segment 0 thick</figcaption>",
                     page)
    assert re.search(r'minimal repro</a> \(\d of 4 segments\)', page)
    for name, rgb in pictures.LINE_LEGEND.items():
        assert f'<span class="swatch" style="background: rgb({rgb[0]}, {rgb[1]}, {rgb[2]})"></span>{escape(name)}' in page
    assert "lines: diamond-exit lines, last pixel drawn &lt;b&gt; — best guess, residual 3 of 40 pixels" in page
    images = re.findall(r'src="(data:image/svg\+xml;base64,[^"]+)"', page)
    assert len(images) >= 4 and all(_svg(uri).tag == SVG + "svg" for uri in images)  # every SVG parses
    side = (report / "fingerprints.html").read_text()
    assert "<th>line rule</th>" in side and "<th>lines seen</th>" in side


def test_an_exact_identification_confirms_or_refutes_the_declared_line_rule(results: list[Result], tmp_path: Path) -> None:
    rasterizers: list[LastPixelLines | ExactLines] = [LastPixelLines(), ExactLines()]
    found = {LastPixelLines.name: "diamond-exit lines, last pixel drawn, no snapping",
             ExactLines.name: "diamond-exit lines, last pixel omitted, no snapping"}
    fingerprints = {name: {**FINGERPRINT, "rasterizer": name, "line_rule": None,
                           "line_convention": {"convention": text, "exact": True, "residual": 0, "pixels": 40}}
                    for name, text in found.items()}
    write_report(tmp_path, {r.name: r.convention.describe() for r in rasterizers}, results, seed=0,
                 fingerprints=fingerprints, **capabilities(rasterizers))
    index = (tmp_path / "index.html").read_text()
    assert ('<td class="fail">diamond-exit lines, last pixel drawn, no snapping (exactly): not the declared rule' in index)
    assert ('<td class="pass">diamond-exit lines, last pixel omitted, no snapping (exactly): confirms the declared rule' in index)


def test_told_nothing_the_report_reads_that_a_rasterizer_takes_lines_from_its_results(results: list[Result],
                                                                                      tmp_path: Path) -> None:
    write_report(tmp_path, {LastPixelLines.name: "x"}, [r for r in results if r.rasterizer == LastPixelLines.name], seed=0)
    page = (tmp_path / f"rasterizer-{LastPixelLines.name}.html").read_text()
    assert 'takes lines <span class="count">(seen in its results)</span>' in page
    assert "no line rule stated" in page and '<h2 id="line-drawers">' in (tmp_path / "index.html").read_text()


# -- JSON and the gate --------------------------------------------------------------------


def test_line_results_round_trip_through_json_with_the_scene_kinds_and_line_rules(results: list[Result], tmp_path: Path) -> None:
    rasterizers: list[LastPixelLines | ExactLines] = [LastPixelLines(), ExactLines()]
    path = write_json(tmp_path / "run.json", results, "custom", 0, {r.name: r.convention.describe() for r in rasterizers},
                      {LastPixelLines.name: FINGERPRINT}, **capabilities(rasterizers))
    data = json.loads(path.read_text())
    assert data["scene_kinds"] == {LastPixelLines.name: ["lines"], ExactLines.name: ["triangles", "lines"]}
    assert data["line_rules"][LastPixelLines.name] == "diamond-exit lines, last pixel omitted, no snapping"
    assert "fill_rules" in data and data["fill_rules"] == {}
    assert data["fingerprints"][LastPixelLines.name]["line_rule"]["residual"] == 3
    back = results_from_json(data)
    assert back == results  # every field but the drawing
    failure = next(r for r in back if r.check == CHECK and r.status == "fail")
    assert failure.evidence["pixels"][0].keys() >= {"segment", "x", "y"}
    repro = case_from_json(failure.evidence["repro"])
    original = case_from_json(_failure(results, failure.case).evidence["repro"])
    assert isinstance(repro, Case) and isinstance(original, Case) and isinstance(original.scene, LineScene)
    assert isinstance(repro.scene, LineScene) and np.array_equal(repro.scene.vertices, original.scene.vertices)
    assert all(on_lines(r) for r in back)  # read back, the line cases are known by their family


def test_a_new_line_failure_is_a_regression_and_a_known_one_is_not(results: list[Result], tmp_path: Path) -> None:
    good = [r for r in results if r.rasterizer == ExactLines.name]
    # the broken drawer's results under the exact one's name: it regressed on every line case
    broken = [replace(r, rasterizer=ExactLines.name) for r in results if r.rasterizer == LastPixelLines.name and r.check == CHECK]
    baseline = load_baseline(save_baseline(tmp_path / "baseline.json", good))
    assert set(baseline) == {f"{ExactLines.name}|{c.id}|{CHECK}" for c in CASES}
    verdict = compare_with_baseline(broken, baseline)
    assert not verdict.ok and len(verdict.regressions) == len(CASES)
    assert all(line.startswith(f"{ExactLines.name}|lines/") and "was pass, now fail" in line for line in verdict.regressions)
    assert any(line.startswith(f"{CHECK}: ") for line in verdict.lines())
    # a line failure not in the baseline is a regression too
    joints = [replace(r, rasterizer=ExactLines.name) for r in results if r.check == "joints"]
    assert [f.verdict for f in compare_with_baseline(good + joints, baseline).findings
            if f.key.endswith("|joints")] == ["regression"]
    # once accepted, it is known; its metric growing beyond the check's tolerance regresses again
    accepted = load_baseline(save_baseline(tmp_path / "accepted.json", broken))
    assert compare_with_baseline(broken, accepted).ok and len(compare_with_baseline(broken, accepted).known) == len(CASES)
    worse = [replace(r, metrics={**r.metrics, "wrong": r.metrics["wrong"] + 1}) for r in broken]
    assert len(compare_with_baseline(worse, accepted).regressions) == len(CASES)
