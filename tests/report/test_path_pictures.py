"""Pictures and the report for path scenes: a path failure's crop draws the paths under
their fill rule and writes in every pixel the winding number of its sample, exactly -- its
fill-rule verdict is the oracle's at every sample, ties on edges and vertices included --;
the repro is drawn likewise; triangle pictures are what they were; the report shows path
failures with their pictures, each rasterizer's scene kinds and fill rules, and a table of
polygon fillers."""

from __future__ import annotations

import base64
import hashlib
import math
import re
import xml.etree.ElementTree as ET
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from markupsafe import escape

from harness.checks import Result
from harness.checks.records import Drawing
from harness.contract.case import Case, case_to_json
from harness.contract.conventions import TIE_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
from harness.report import picture_paths, pictures
from harness.report.pages import capabilities, on_paths, write_report

SVG = "{http://www.w3.org/2000/svg}"


def _star(cx: float, cy: float, r: float, n: int = 5, step: int = 2) -> list[list[float]]:
    return [[cx + r * math.sin(k * step * 2 * math.pi / n), cy - r * math.cos(k * step * 2 * math.pi / n)] for k in range(n)]


# On the 1/2 px lattice: vertices on pixel centres and corners, edges through samples.
PENTAGRAM = [_star(6, 6, 5)]
LATTICE_STAR = [[[6.0, 0.5], [9.5, 11.5], [0.5, 4.5], [11.5, 4.5], [2.5, 11.5]]]
RING_SAME = [[[1.5, 1.5], [10.5, 1.5], [10.5, 10.5], [1.5, 10.5]], [[4.0, 4.0], [8.5, 4.0], [8.5, 8.5], [4.0, 8.5]]]
BOW_TIE = [[[1.0, 1.0], [11.0, 11.0], [11.0, 1.0], [1.0, 11.0]]]
TOUCHING = [[[1.5, 1.5], [6.0, 1.5], [6.0, 6.0], [1.5, 6.0]], [[6.0, 6.0], [10.5, 6.0], [10.5, 10.5], [6.0, 10.5]],
            [[6.0, 6.0], [6.0, 8.5], [3.5, 8.5]]]  # contours meeting at a vertex on a sample
SHAPES = {"pentagram": PENTAGRAM, "lattice-star": LATTICE_STAR, "ring-same": RING_SAME, "bow-tie": BOW_TIE, "touching": TOUCHING}
# every tie rule once, with sample points on and off the lattice's ties, with and without snapping
CONVENTIONS = [Convention(sample=sample, tie=tie, subpixel_bits=bits)
               for tie, sample, bits in zip(TIE_RULES, [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.5, 0.5)] * 2, [None, None, 1, None] * 2)]


def _path_mask(scene: PathScene, path: int, convention: Convention, window: tuple[int, int, int, int]) -> np.ndarray:
    """The oracle's verdict on each sample of the window for one path."""
    cov = exact_coverage(scene, convention)
    x0, y0, x1, y1 = window
    return cov.take(np.flatnonzero(cov.primitive == path)).counts(scene.width, scene.height)[y0:y1, x0:x1] > 0


def _reference_winding(scene: PathScene, path: int, convention: Convention, i: int, j: int) -> int:
    """The winding number of sample (i, j) around ``path`` by brute force in rationals:
    the sample perturbed as the tie rule says, every quantity a triple (value, eps,
    eps**2) compared lexicographically, dir summed over the crossings right of it."""
    tx, ty, y_first = convention.tie_perturbation
    dx, dy = ((0, tx), (ty, 0)) if y_first else ((tx, 0), (0, ty))
    qx = (i + Fraction(convention.sample[0]), Fraction(dx[0]), Fraction(dx[1]))
    qy = (j + Fraction(convention.sample[1]), Fraction(dy[0]), Fraction(dy[1]))

    def sign(t: tuple[Fraction, ...]) -> int:
        return next((1 if v > 0 else -1 for v in t if v), 0)

    start, end, owner = scene.edges()
    w = 0
    for a, b in zip(convention.snap(start[owner == path]), convention.snap(end[owner == path])):
        ax, ay, bx, by = (Fraction(float(v)) for v in (*a, *b))
        if (sign((ay - qy[0], -qy[1], -qy[2])) > 0) == (sign((by - qy[0], -qy[1], -qy[2])) > 0):
            continue
        e = ((bx - ax) * (qy[0] - ay) - (by - ay) * (qx[0] - ax), (bx - ax) * qy[1] - (by - ay) * qx[1],
             (bx - ax) * qy[2] - (by - ay) * qx[2])
        d = 1 if by > ay else -1
        if sign(e) * d > 0:  # the crossing lies right of the sample
            w += d
    return w


# -- the winding numbers are exact --------------------------------------------------------


@pytest.mark.parametrize("shape", list(SHAPES))
def test_the_winding_numbers_give_the_oracles_verdict_at_every_sample_under_every_tie_rule(shape: str) -> None:
    for rule in ("nonzero", "evenodd"):
        # a second path over the first: each path's numbers are its own
        scene = PathScene.from_paths(12, 12, [SHAPES[shape], [[[0, 0], [12, 0], [12, 12], [0, 12]]]], rule)
        for convention in CONVENTIONS:
            for window in ((0, 0, 12, 12), (3, 2, 9, 10)):
                w = pictures.winding_numbers(scene, 0, convention, window)
                assert w is not None and w.shape == (window[3] - window[1], window[2] - window[0])
                assert np.array_equal(pictures.rule_fills(w, rule), _path_mask(scene, 0, convention, window)), \
                    (shape, rule, convention, window)


def test_the_winding_numbers_are_the_brute_force_counts() -> None:
    for shape in ("lattice-star", "ring-same", "touching"):
        scene = PathScene.from_paths(12, 12, [SHAPES[shape]], "nonzero")
        for convention in CONVENTIONS[:4]:
            w = pictures.winding_numbers(scene, 0, convention, (0, 0, 12, 12))
            want = [[_reference_winding(scene, 0, convention, i, j) for i in range(12)] for j in range(12)]
            assert w is not None and w.tolist() == want, (shape, convention)


def test_the_numbers_say_what_each_rule_fills() -> None:
    # clockwise on screen counts +1: the pentagram's centre is 2 (nonzero fills it, even-odd
    # does not), its points 1; reversed, the signs flip and the verdicts stay
    scene = PathScene.from_paths(12, 12, [PENTAGRAM], "nonzero")
    w = pictures.winding_numbers(scene, 0, Convention(), (0, 0, 12, 12))
    assert w is not None and w[6, 6] == 2 and w[4, 1] == 1 and w[0, 0] == 0
    back = PathScene.from_paths(12, 12, [[PENTAGRAM[0][::-1]]], "nonzero")
    assert np.array_equal(pictures.winding_numbers(back, 0, Convention(), (0, 0, 12, 12)), -w)
    ring = PathScene.from_paths(12, 12, [RING_SAME], "evenodd")
    w = pictures.winding_numbers(ring, 0, Convention(), (0, 0, 12, 12))
    assert w is not None and w[6, 6] == 2 and w[2, 2] == 1  # a hole wound like its ring: 2, even-odd leaves it
    assert not pictures.rule_fills(w, "evenodd")[6, 6] and pictures.rule_fills(w, "nonzero")[6, 6]
    nan = PathScene.from_paths(4, 4, [[[[0, 0], [3, 0], [float("nan"), 3]]]], "nonzero")
    assert pictures.winding_numbers(nan, 0, Convention(), (0, 0, 4, 4)) is None  # covers nothing: no number


@settings(max_examples=25, deadline=None)
@given(st.lists(st.lists(st.tuples(st.integers(-4, 44), st.integers(-4, 40)), min_size=1, max_size=7), min_size=1, max_size=3),
       st.sampled_from(("nonzero", "evenodd")), st.sampled_from(CONVENTIONS))
def test_random_lattice_paths_number_every_sample_as_the_oracle_decides(contours: list[list[tuple[int, int]]], rule: str,
                                                                         convention: Convention) -> None:
    scene = PathScene.from_paths(10, 9, [[np.array(c, dtype=float) / 4 for c in contours]], rule)
    w = pictures.winding_numbers(scene, 0, convention, (0, 0, 10, 9))
    assert w is not None and np.array_equal(pictures.rule_fills(w, rule), _path_mask(scene, 0, convention, (0, 0, 10, 9)))


def test_a_path_of_100000_vertices_costs_a_filter_and_a_few_exact_tests(monkeypatch: pytest.MonkeyPatch) -> None:
    n = 100_000
    k = np.arange(n)
    radius = 200 + 3 * np.sin(k * 0.37)
    ring = np.stack([256 + radius * np.cos(2 * np.pi * k / n), 256 + radius * np.sin(2 * np.pi * k / n)], axis=1)
    scene = PathScene.from_paths(512, 512, [[ring]], "nonzero")
    tested = []
    real = picture_paths.orientation
    monkeypatch.setattr(picture_paths, "orientation", lambda p: (tested.append(len(p)), real(p))[1])
    window = (50, 240, 82, 272)  # across the ring's left side
    w = pictures.winding_numbers(scene, 0, Convention(), window)
    assert w is not None and np.array_equal(pictures.rule_fills(w, "nonzero"), _path_mask(scene, 0, Convention(), window))
    assert 0 < w.sum() < w.size and sum(tested) < 64  # exact tests only where a crossing falls near a sample


# -- pictures of path failures --------------------------------------------------------------


class WrongRule:
    """Fills each path exactly, under the other fill rule than the one asked."""

    name = "wrong_rule"
    convention = Convention()
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene: PathScene) -> Coverage:
        return exact_coverage(scene.with_fill_rule("evenodd" if scene.fill_rule == "nonzero" else "nonzero"), self.convention)


class DoubleEdges(WrongRule):
    """Draws the samples on shared edges into both paths (a partition's double hits)."""

    name = "double_edges"

    def rasterize(self, scene: PathScene) -> Coverage:
        return Coverage.concat([exact_coverage(scene, self.convention), exact_coverage(scene, Convention(tie="bottom-right"))]).canonical()


CELLS = [[[[x, y], [x + 4.5, y], [x + 4.5, y + 4.5], [x, y + 4.5]]] for x in (1.0, 5.5) for y in (1.0, 5.5)]
CASES = [Case("paths/pentagram/nonzero", PathScene.from_paths(12, 12, [PENTAGRAM], "nonzero")),
         Case("paths/ring-same/lattice/evenodd", PathScene.from_paths(12, 12, [RING_SAME, [[[0, 0], [3, 0], [0, 3]]]], "evenodd"),
              lattice=True)]
PARTITION = Case("path-partitions/quads-2x2/lattice/nonzero", PathScene.from_paths(12, 12, CELLS, "nonzero"), lattice=True,
                 region=np.array([[1.0, 1.0], [10.0, 1.0], [10.0, 10.0], [1.0, 10.0]]))


@pytest.fixture(scope="module")
def results() -> list[Result]:
    wrong = run_suite([WrongRule()], cases=CASES, isolate=False, identify=False, repros=False)
    double = run_suite([DoubleEdges()], cases=[PARTITION], isolate=False, identify=False, repros=False, only={"watertight"})
    return wrong + double


def _svg(uri: str) -> ET.Element:
    assert uri.startswith("data:image/svg+xml;base64,")
    return ET.fromstring(base64.b64decode(uri.split(",", 1)[1]))  # well-formed XML, or this raises


def _numbers(svg: ET.Element) -> dict[tuple[int, int], tuple[int, bool]]:
    """pixel -> (number written, bold) of a picture's winding numbers."""
    out = {}
    for text in svg.iter(SVG + "text"):
        if text.text and re.fullmatch(r"-?\d+", text.text):
            out[(math.floor(float(text.get("x"))), math.floor(float(text.get("y"))))] = (int(text.text),
                                                                                          text.get("font-weight") == "bold")
    return out


def test_a_failing_path_case_draws_the_paths_and_the_oracles_winding_numbers(results: list[Result]) -> None:
    failures = [r for r in results if r.status == "fail" and r.check == "conformance"]
    assert {r.case for r in failures} == {c.id for c in CASES}
    for failure in failures:
        scene = failure.drawing.case.scene
        drawn = pictures.draw(failure)
        assert list(drawn) == ["heatmap", "diff", "crop"]
        svg = _svg(drawn["crop"])
        paths = list(svg.iter(SVG + "path"))
        assert paths and {p.get("fill-rule") for p in paths} == {scene.fill_rule}  # one <path> per path, the scene's rule
        assert all(p.get("d").startswith("M") and float(p.get("fill-opacity")) < 0.5 for p in paths)
        assert list(svg.iter(SVG + "polygon")), "arrowheads along the edges"
        path = pictures.numbered_path(failure)
        assert path == failure.evidence["pixels"][0]["path"]
        x0, y0, w, h = (int(float(v)) for v in svg.get("viewBox").split())
        window = (x0, y0, x0 + w, y0 + h)
        numbers = _numbers(svg)
        assert len(numbers) == w * h  # one per pixel of the window
        want = _path_mask(scene, path, Convention(), window)
        winding = pictures.winding_numbers(scene, path, Convention(), window)
        for (x, y), (number, bold) in numbers.items():
            assert number == winding[y - y0, x - x0]
            assert bold == bool(want[y - y0, x - x0]) == bool(pictures.rule_fills(np.array([number]), scene.fill_rule)[0])


@pytest.mark.parametrize("convention", [Convention(samples=4, tie="bottom-right"), None])
def test_a_multisample_crop_numbers_the_first_sample_and_one_without_a_convention_the_centre(convention: Convention | None) -> None:
    scene = PathScene.from_paths(12, 12, [LATTICE_STAR], "evenodd")
    case = Case("paths/lattice-star/lattice/evenodd", scene, lattice=True)
    failure = Result("r", case.id, "conformance", "fail", "m", {}, {"pixels": [{"path": 0, "x": 6, "y": 6, "kind": "extra"}]},
                     Drawing(case, (Coverage.empty(),), convention))
    numbered = convention.at_sample(0) if convention is not None else Convention()
    svg = _svg(pictures.draw(failure)["crop"])
    x0, y0, w, h = (int(float(v)) for v in svg.get("viewBox").split())
    want = _path_mask(scene, 0, numbered, (x0, y0, x0 + w, y0 + h))
    numbers = _numbers(svg)
    assert len(numbers) == w * h and all(bold == bool(want[y - y0, x - x0]) for (x, y), (_, bold) in numbers.items())
    dots = {(float(c.get("cx")) % 1, float(c.get("cy")) % 1) for c in svg.iter(SVG + "circle") if c.get("fill") == "#333"}
    assert dots == {numbered.sample}


def test_path_colours_mean_nothing_else_in_any_picture() -> None:
    others = [pictures.HEAT_LEGEND, pictures.DIFF_LEGEND, pictures.LEGEND, pictures.ALPHA_LEGEND, pictures.CROP_LEGEND]
    used = {rgb for legend in others for rgb in legend.values()}
    assert not set(pictures.PATH_LEGEND.values()) & used
    assert len(set(pictures.PATH_LEGEND.values())) == len(pictures.PATH_LEGEND)


def test_the_crop_of_a_watertight_failure_numbers_a_path_its_blame_names(results: list[Result]) -> None:
    failure = next(r for r in results if r.check == "watertight" and r.status == "fail")
    assert "paths" in failure.evidence["blame"][0]
    assert pictures.numbered_path(failure) == failure.evidence["blame"][0]["paths"][0]
    svg = _svg(pictures.draw(failure)["crop"])
    dashed = [p for p in svg.iter(SVG + "path") if p.get("stroke-dasharray")]
    assert dashed and len(list(svg.iter(SVG + "path"))) == len(dashed) + 1  # the numbered path solid, its neighbours dashed
    assert _numbers(svg)


def test_the_evidence_of_each_path_check_names_the_path_to_number() -> None:
    def named(**evidence: Any) -> int | None:
        return pictures.focus_path(Result("r", "c", "x", "fail", "m", {}, evidence))

    assert named(pixels=[{"path": 4, "x": 1, "y": 1, "kind": "missing"}]) == 4
    assert named(blame=[{"pixel": [1, 1], "kind": "hole", "paths": [2, 5]}]) == 2
    assert named(triangles_only=[[3, 1, 2]], columns=["path", "x", "y"]) == 3
    assert named(**{"reverse-every-contour": [[6, 1, 2]]}) == 6
    assert named(pixels=[{"triangle": 1, "x": 1, "y": 1}]) is None


def test_a_path_repro_is_drawn_with_its_winding_numbers(results: list[Result]) -> None:
    failure = next(r for r in results if r.check == "conformance" and r.case == "paths/ring-same/lattice/evenodd")
    repro = Case("paths/ring-same/lattice/evenodd/repro", failure.drawing.case.scene.subset([0]), lattice=True)
    payload = case_to_json(repro, check="conformance", rasterizer="wrong_rule", message="m", original_case=failure.case,
                           original_triangles=2)
    with_repro = Result(failure.rasterizer, failure.case, failure.check, failure.status, failure.message, failure.metrics,
                        {**failure.evidence, "repro": payload}, failure.drawing)
    uri, caption = pictures.draw_repro(with_repro)
    assert uri is not None and caption.startswith("minimal repro: its 1 path (of 2) under the evenodd rule")
    assert "winding number of its sample around path 0" in caption
    svg = _svg(uri)
    numbers = _numbers(svg)
    x0, y0, w, h = (int(float(v)) for v in svg.get("viewBox").split())
    want = _path_mask(repro.scene, 0, Convention(), (x0, y0, x0 + w, y0 + h))
    assert numbers and all(bold == bool(want[y - y0, x - x0]) for (x, y), (_, bold) in numbers.items())
    covered = "#{:02x}{:02x}{:02x}".format(*pictures.CROP_LEGEND[pictures._CONVENTION])
    assert f'fill="{covered}"' in base64.b64decode(uri.split(",", 1)[1]).decode()


# -- triangle pictures are what they were -------------------------------------------------

# sha256 of the SVGs the pictures module drew for this case before paths were added
TRIANGLE_PICTURES = {
    "svg_crop": "e37a7ed09ea384ec689ec0ea8c242281b270c24e48d7b114c7c301d95917e2aa",
    "svg_window": "0e996f6231ef1e3d227f63839067d4d781ea3312cd6cede45bd213ba48d35e8c",
    "draw_crop": "151c9688f92d2de720b40e5d707c9d49b95bc8036ddb55ba3bf7070bf9604838",
    "repro": "b294875aa4065db3dd603b3b39bd6a5325833285f397c5affcdc91499a15c085",
}


def test_triangle_pictures_are_byte_for_byte_what_they_were() -> None:
    scene = Scene(16, 12, [[[1.25, 1.5], [9.75, 2.25], [3.5, 10.5]], [[9.75, 2.25], [14.5, 9.0], [3.5, 10.5]],
                           [[0.5, 0.5], [2.0, 0.5], [0.5, 2.0]]])
    convention = Convention(tie="bottom-right")
    oracle, coverage = exact_coverage(scene, Convention()), exact_coverage(scene, convention)
    case = Case("fixed/triangles", scene, lattice=True)
    pixels = [{"triangle": 0, "x": 5, "y": 6, "kind": "missing", "near_tie": False, "distance": 0.0},
              {"triangle": 1, "x": 9, "y": 3, "kind": "extra", "near_tie": True, "distance": 0.0}]
    payload = case_to_json(Case("fixed/triangles/repro", scene.subset([0, 1]), lattice=True), check="conformance",
                           rasterizer="x", message="m", original_case="fixed/triangles", original_triangles=3)
    failure = Result("x", case.id, "conformance", "fail", "2 missing", {"missing": 2.0}, {"pixels": pixels, "repro": payload},
                     Drawing(case, (coverage,), convention, (oracle,)))

    def digest(uri: str) -> str:
        return hashlib.sha256(base64.b64decode(uri.split(",", 1)[1])).hexdigest()

    uri, caption = pictures.draw_repro(failure)
    got = {"svg_crop": digest(pictures.svg_crop(scene.positions, coverage, (0.5, 0.5), (2, 1, 14, 12), [(5, 6), (9, 3)])),
           "svg_window": digest(pictures.svg_window(scene.positions, None, (230, 205, 140), None, (0, 0, 16, 12), [(5, 6)])),
           "draw_crop": digest(pictures.draw(failure)["crop"]), "repro": digest(uri)}
    assert got == TRIANGLE_PICTURES
    assert caption == ("minimal repro: its 2 triangles (of 3), the pixels the convention covers; outlined: 2 of the pixels "
                       "the failure names, next to these triangles")


# -- the report -----------------------------------------------------------------------------


def test_the_report_shows_path_failures_fill_rules_and_the_polygon_fillers(results: list[Result], tmp_path: Any) -> None:
    rasterizers = [WrongRule(), DoubleEdges()]
    conventions = {r.name: r.convention.describe() for r in rasterizers}
    fingerprints = {"wrong_rule": {"rasterizer": "wrong_rule", "convention": "sample (0.5, 0.5), top-left ties", "exact": True,
                                   "residual": 0, "pixels": 10, "runner_up": None, "facts": {}, "ambiguous": [],
                                   "fill_rules": {"nonzero": "evenodd", "evenodd": "nonzero"}, "honoured_fill_rules": [],
                                   "path_convention": {"convention": "sample (0.5, 0.5), top-left ties, no snapping",
                                                       "exact": True, "residual": 0, "pixels": 10}}}
    write_report(tmp_path, conventions, results, seed=0, fingerprints=fingerprints, **capabilities(rasterizers))
    index = (tmp_path / "index.html").read_text()
    table = index[index.index('<h2 id="polygon-fillers">'):index.index("<h2>Conventions</h2>")]
    assert "<script" not in index
    for name in ("wrong_rule", "double_edges"):
        assert f'<a href="rasterizer-{name}.html">{name}</a>' in table
    assert "nonzero → evenodd" in table and "identified on paths: sample (0.5, 0.5), top-left ties, no snapping" in table
    failing = [r for r in results if r.status == "fail" and r.rasterizer == "wrong_rule"]
    assert f"<b>conformance</b> ({sum(r.check == 'conformance' for r in failing)})" in table
    assert re.search(r'<a href="rasterizer-wrong_rule.html#failure-\d+">paths/pentagram/nonzero</a>', table)
    assert "takes paths (fill rules nonzero, evenodd)" in index
    page = (tmp_path / "rasterizer-wrong_rule.html").read_text()
    assert "Scenes: takes paths" in page and "fill rules honoured: nonzero, evenodd" in page
    assert re.search(r"<figcaption>crop: the paths over the pixel grid under the nonzero rule; in each pixel the winding number "
                     r"of its sample around path 0 \(bold where the rule fills it\)</figcaption>", page)
    for legend in (pictures.PATH_LEGEND, pictures.CROP_LEGEND):
        for name, rgb in legend.items():
            assert f'<span class="swatch" style="background: rgb({rgb[0]}, {rgb[1]}, {rgb[2]})"></span>{escape(name)}' in page
    side = (tmp_path / "fingerprints.html").read_text()
    assert "<th>fill rules asked → drawn</th>" in side and "<th>path convention</th>" in side
    # told nothing of the rasterizers, the report reads the scene kinds from the results
    write_report(tmp_path / "bare", conventions, results, seed=0)
    assert "takes paths <span class=\"count\">(seen in its results)</span>" in (tmp_path / "bare" / "rasterizer-wrong_rule.html").read_text()
    assert all(on_paths(r) for r in results)
