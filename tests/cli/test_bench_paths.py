"""The bench's path workloads at a tiny size: their structure, the oracle's answer on the
stars (pinned: checked once against the rational brute force, path_spans_rational, star
by star), and the library peers drawing the same fill rule; and its anti-aliased stroke
workloads. No timing assertion."""

import json

import numpy as np
import pytest

from harness.cli.bench import (
    STROKE_ORACLE,
    _contenders,
    format_table,
    missing_peers,
    path_workloads,
    run_bench,
    stars,
    stroke_workloads,
    write_json,
)
from harness.cli.bench_peers import _path_peers, _stroke_peers, _Surface
from harness.contract.conventions import Convention
from harness.contract.scenes import LineScene, PathScene
from harness.oracle.coverage import exact_coverage
from tests.narrow import paths

SCALE = 0.01  # 10 stars; an outline of 1,000 vertices

# The oracle's fragments on the 10 stars, per fill rule (with overlaps between stars
# counted once per star); confirmed by path_spans_rational on each star in its own box.
STAR_PIXELS = {"nonzero": 13_981, "evenodd": 12_315}


def test_the_path_workloads_are_stars_and_an_outline_under_both_rules():
    works = path_workloads(SCALE)
    assert [w.name for w in works] == ["P1-nonzero", "P1-evenodd", "P2-nonzero", "P2-evenodd", "P3-nonzero", "P3-evenodd"]
    for w in works:
        assert isinstance(w.scene, PathScene) and (w.scene.width, w.scene.height) == (512, 512)
        assert w.scene.fill_rule == w.name.split("-")[1] and w.name.split("-")[1] in w.description
    star, outline = paths(works[0].scene), paths(works[2].scene)
    assert len(star) == 10 and star.contour_sizes.tolist() == [10] * 10
    assert len(outline) == 1 and outline.contour_sizes.tolist() == [1000]
    assert len(path_workloads(1.0)[0].scene) == 1000 and paths(path_workloads(1.0)[2].scene).vertices.shape == (100_000, 2)


def test_a_star_is_a_ten_three_star_polygon():
    # one contour joining every third of ten points on a circle: winding number 3 at the centre
    scene = stars(1, 512, 5)
    v = scene.vertices
    centre = v.mean(axis=0)
    angles = np.unwrap(np.arctan2(v[:, 1] - centre[1], v[:, 0] - centre[0]))
    assert np.allclose(np.diff(angles), 2 * np.pi * 3 / 10) and np.allclose(np.hypot(*(v - centre).T),
                                                                            np.hypot(*(v - centre).T)[0])


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_the_oracle_on_the_stars_equals_the_reference_count(rule):
    scene = paths(path_workloads(SCALE)[0].scene).with_fill_rule(rule)
    assert exact_coverage(scene, Convention()).n_pixels == STAR_PIXELS[rule]


def test_run_bench_measures_the_path_workloads_against_pillow():
    results = [m for m in run_bench(["centre_scanline"], scale=SCALE, budget=0.0) if m.workload.startswith("P")]
    by_work: dict[str, list] = {}
    for m in results:
        by_work.setdefault(m.workload, []).append(m)
    assert list(by_work) == ["P1-nonzero", "P1-evenodd", "P2-nonzero", "P2-evenodd", "P3-nonzero", "P3-evenodd"]
    peers = [label for label, _ in _path_peers()]
    for work, ms in by_work.items():
        labels = [m.contender for m in ms]
        assert labels[:3] == ["pillow", "oracle", "oracle_area"] and ms[0].ratio_to_pillow == 1.0
        # scikit-image's polygon is too slow for the 1,000-vertex outline (each box pixel x each edge)
        assert labels[3:] == [p for p in peers if not work.startswith("P2") or p != "skimage_polygon"]
        assert "centre_scanline" not in labels  # it takes no paths
        assert all(m.unit == "paths" and m.description and m.seconds > 0 and m.pixels > 0 for m in ms)
        assert all(m.ratio_to_pillow == pytest.approx(ms[0].seconds / m.seconds) for m in ms)
    oracle = {m.workload: m.pixels for m in results if m.contender == "oracle"}
    assert oracle["P1-nonzero"] == STAR_PIXELS["nonzero"] and oracle["P1-evenodd"] == STAR_PIXELS["evenodd"]
    table = format_table(results, {})
    assert "P1-nonzero: 10 {10/3} stars of 10 vertices, nonzero, 512 x 512" in table and "paths/s" in table


def test_the_json_carries_the_unit_and_the_description(tmp_path):
    results = [m for m in run_bench([], scale=SCALE, budget=0.0) if m.workload in ("W2", "P2-evenodd")]
    write_json(results, tmp_path / "b.json")
    rows = json.loads((tmp_path / "b.json").read_text())["results"]
    assert {(r["workload"], r["unit"]) for r in rows} == {("W2", "triangles"), ("P2-evenodd", "paths")}
    assert all(r["description"] for r in rows)


class TakesEvenOdd:
    name = "evenodd-only"
    convention = Convention()
    scene_kinds = ("triangles", "paths")
    fill_rules = ("evenodd",)

    def rasterize(self, scene):
        return exact_coverage(scene, self.convention)


def test_a_rasterizer_is_measured_on_the_path_workloads_it_takes():
    nonzero, evenodd = path_workloads(SCALE)[:2]
    assert "evenodd-only" not in [label for label, _ in _contenders(nonzero, [TakesEvenOdd()])]
    assert "evenodd-only" in [label for label, _ in _contenders(evenodd, [TakesEvenOdd()])]


@pytest.mark.parametrize("peer", ["cairo_fill", "skia_fill"])
@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_the_library_peers_fill_under_the_rule_asked(peer, rule):
    """cairo and skia, aliased, draw the oracle's union of the stars under the rule asked,
    up to their own sampling along edges and at the stars' self-intersections (cairo's
    even-odd takes about 2 more pixels at each): far closer to it than to the other rule's."""
    fills = dict(_path_peers())
    if peer not in fills:
        pytest.skip(f"{peer}: {missing_peers().get(peer, 'its library is not installed')}")
    scene = paths(path_workloads(SCALE)[0].scene).with_fill_rule(rule)
    surface = fills[peer](scene)
    assert isinstance(surface, _Surface)
    drawn = surface.read() > 0
    union = exact_coverage(scene, Convention()).counts(512, 512) > 0
    other = exact_coverage(scene.with_fill_rule("evenodd" if rule == "nonzero" else "nonzero"), Convention()).counts(512, 512) > 0
    assert (drawn != union).sum() < 0.15 * (other != union).sum()


# -- the anti-aliased stroke workloads (S1, S2) --------------------------------------------


def test_the_stroke_workloads_are_wide_segments_inside_the_screen():
    works = stroke_workloads(SCALE)
    assert [w.name for w in works] == ["S1", "S2"] and all(w.anti_aliased for w in works)
    for w, width in zip(works, (1.5, 4.0)):
        scene = w.scene
        assert isinstance(scene, LineScene) and scene.line_width == width and len(scene) == 10
        a, b = scene.segments()
        ends = np.concatenate([a, b])
        assert ends.min() >= width and ends.max() <= 512 - width
        assert (np.hypot(*(b - a).T) >= 4).all() and f"width {width:g}, butt caps" in w.description
    assert len(stroke_workloads(1.0)[0].scene) == 1000


def test_run_bench_measures_the_strokes_against_the_stroke_area_oracle():
    results = run_bench([], scale=SCALE, budget=0.0, paths=False, lines=False, triangles=False, strokes=True)
    peers = [label for label, _ in _stroke_peers()]
    by_work: dict[str, list] = {}
    for m in results:
        by_work.setdefault(m.workload, []).append(m)
    assert list(by_work) == ["S1", "S2"]
    for ms in by_work.values():
        assert [m.contender for m in ms] == ["pillow", "oracle_area", *peers]
        assert all(m.unit == "segments" and m.seconds > 0 and m.pixels > 0 and not m.fault for m in ms)
    assert run_bench([], scale=SCALE, budget=0.0, paths=False, lines=False, triangles=False) == []  # off by default


@pytest.mark.parametrize("peer", ["cairo_aa_stroke", "skia_aa_stroke"])
def test_the_stroke_peers_draw_about_the_oracles_area(peer):
    """cairo's and skia's anti-aliased strokes of the 10 segments: their alphas sum to the
    strokes' exact area within a few percent (their own AA models; overlaps saturate)."""
    draws = dict(_stroke_peers())
    if peer not in draws:
        pytest.skip(f"{peer}: {missing_peers().get(peer, 'its library is not installed')}")
    for work in stroke_workloads(SCALE):
        assert isinstance(work.scene, LineScene)
        surface = draws[peer](work.scene)
        assert isinstance(surface, _Surface)
        drawn = float(surface.read().astype(np.float64).sum() / 255)
        oracle = exact_coverage(work.scene, STROKE_ORACLE)
        assert oracle.alpha is not None
        total = float(oracle.alpha.sum())
        assert abs(drawn - total) < 0.05 * total, (work.name, drawn, total)


class AliasedLines:
    name = "aliased-lines"
    convention = Convention(line="bresenham")
    scene_kinds = ("lines",)

    def rasterize(self, scene):
        return exact_coverage(scene, self.convention)


class AntiAliasedLines(AliasedLines):
    name = "aa-lines"
    convention = STROKE_ORACLE


def test_only_anti_aliasing_line_rasterizers_are_measured_on_the_strokes():
    labels = [label for label, _ in _contenders(stroke_workloads(SCALE)[0], [AliasedLines(), AntiAliasedLines()])]
    assert "aa-lines" in labels and "aliased-lines" not in labels
