"""The rules read from libraries' sources (harness/oracle/library_rules.py): AGG's cell cover
and pygame's inclusive scanline, each against its rational reference, its known-bad
rasterizer, identify's rule probes and (where installed) the library itself."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from harness.checks import conformance
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage_models import AGG_COVER, COVERAGE_RULES, INCLUSIVE_SCANLINE, model_for
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.library_rules import (
    agg_cover_coverage,
    agg_cover_reference,
    agg_covers,
    cell_polygon,
    cover_min,
    inclusive_scanline_coverage,
    inclusive_scanline_reference,
    on_library_boundary,
)
from tests.known_bad.library_rules import ExclusiveRightScanline, Float32AggCover

AGGDRAW = Convention(coverage="agg-cover", input="fixed8-toward-zero")
MATPLOTLIB = Convention(coverage="agg-cover", input="fixed8-half-away", threshold=2.0**-8)
PYGAME = Convention(coverage="inclusive-scanline", input="integer-toward-zero")

# vertices on the 1/256 px grid, some off screen, some on the lattice of halves (ties on purpose)
_grid = st.integers(-2 * 256, 10 * 256).map(lambda k: k / 256.0)
_halves = st.integers(-4, 20).map(lambda k: k / 2.0)
_vertex = st.tuples(st.one_of(_grid, _halves), st.one_of(_grid, _halves))
_triangle = st.lists(_vertex, min_size=3, max_size=3)


def test_the_rules_are_registered_once_as_coverage_rules():
    assert COVERAGE_RULES["agg-cover"] is AGG_COVER and COVERAGE_RULES["inclusive-scanline"] is INCLUSIVE_SCANLINE
    assert model_for("agg-cover", False) is AGG_COVER and AGGDRAW.model is AGG_COVER and PYGAME.model is INCLUSIVE_SCANLINE
    for c in (AGGDRAW, MATPLOTLIB, PYGAME):
        assert c.coverage_kind == "single" and c.model.rule and not c.model.exactly_once and not c.model.sample_point
        assert eval(repr(c)) == c  # noqa: S307
    assert AGGDRAW.describe().startswith("AGG's cell cover (a pixel iff its 8-bit cover is at least 256 x 0.5), 24.8 fixed")
    assert PYGAME.describe().startswith("an inclusive scanline fill")
    # nothing changes for the existing conventions
    assert Convention().model.input_bits is None and Convention(coverage="area-threshold").model.input_bits is None


def test_the_rules_need_their_librarys_grid():
    with pytest.raises(ValueError, match=r"defined on a grid of 2\*\*-8 px: declare input='fixed8-<rounding>'"):
        Convention(coverage="agg-cover")
    with pytest.raises(ValueError, match=r"defined on a grid of 2\*\*-0 px: declare input='integer-<rounding>'"):
        Convention(coverage="inclusive-scanline", input="fixed4")
    with pytest.raises(ValueError, match="and no subpixel_bits"):
        Convention(coverage="agg-cover", input="fixed8", subpixel_bits=4)
    # a coarser grid is on the finer one
    assert Convention(coverage="agg-cover", input="fixed6-floor").input == "fixed6-floor"
    assert Convention(coverage="agg-cover", input="integer-floor").model is AGG_COVER


def test_agg_covers_round_by_orientation():
    """calculate_alpha: the shift floors the signed value, so a counter-clockwise triangle
    (on screen, y down) gets floor(256 a), a clockwise one ceil(256 a)."""
    w = 171 / 256  # area 171/512: 85.5 / 256
    ccw, cw = np.array([[0, 0], [0, 1], [w, 1]]), np.array([[0, 0], [w, 1], [0, 1]])
    assert int(agg_covers(ccw, 1, 1)[0, 0]) == 85 and int(agg_covers(cw, 1, 1)[0, 0]) == 86
    # a whole pixel is capped at 255
    assert agg_covers(np.array([[0, 0], [4, 0], [0, 4.0]]), 4, 4)[0, 0] == 255
    assert [cover_min(t) for t in (0.5, 2.0**-8, 0.75, 1.0)] == [128, 1, 192, 256]


def test_the_cell_polygon_rounds_crossings_down():
    """An edge from (0, 0) to (1.5, 3): it crosses y = 1 at x = 0.5 (exact) and y = 2 at
    x = 1 (exact); from (0, 0) to (1, 3): at x = 1/3 and 2/3, rounded down to 85/256 and
    170/256 (and the column x = 1 never crossed inside)."""
    poly = cell_polygon(np.array([[0, 0], [1, 3], [0, 3.0]]))
    assert poly[:3] == [(0, 0), (85, 256), (170, 512)]
    # the reference of a lattice triangle: exact areas, no rounding
    scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    assert agg_cover_reference(scene, AGGDRAW) == agg_cover_coverage(scene, AGGDRAW)


@settings(max_examples=60, deadline=None)
@given(_triangle, st.sampled_from([AGGDRAW, MATPLOTLIB, Convention(coverage="agg-cover", input="fixed8-floor",
                                                                    threshold=0.75, cull="cw")]))
@example([(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)], AGGDRAW)  # exact halves: cover 128
@example([(0.0, 0.0), (171 / 256, 1.0), (0.0, 1.0)], MATPLOTLIB)
@example([(-1.5, 0.25), (7.75, 3.0), (0.5, 7.5)], AGGDRAW)  # off screen to the left
def test_agg_cover_matches_its_rational_reference(vertices, convention):
    scene = Scene(8, 8, np.array([vertices], dtype=np.float64))
    assert agg_cover_coverage(scene, convention) == agg_cover_reference(scene, convention)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 10), st.integers(-3, 10)), min_size=3, max_size=3),
       st.lists(st.tuples(st.floats(0, 0.99), st.floats(0, 0.99)), min_size=3, max_size=3))
@example([(0, 0), (3, 0), (0, 3)], [(0, 0)] * 3)
@example([(1, 1), (3, 1), (2, 1)], [(0, 0)] * 3)  # flat: its row
@example([(1, 1), (5, 3), (3, 2)], [(0, 0)] * 3)  # zero area, slanted: drawn
@example([(-2, 0), (5, 7), (-1, 7)], [(0.5, 0.5)] * 3)  # left of the screen: truncated toward zero
def test_inclusive_scanline_matches_its_rational_reference(whole, fraction):
    vertices = np.array(whole, dtype=np.float64) + np.array(fraction) * np.sign(np.array(whole) + 0.5)
    scene = Scene(8, 8, vertices[None])
    assert inclusive_scanline_coverage(scene, PYGAME) == inclusive_scanline_reference(scene, PYGAME)


def test_exact_coverage_dispatches_to_the_rules():
    scene = Scene(6, 6, np.array([[[0, 0], [6, 0], [0, 6]], [[1.5, 1.5], [5.25, 2], [2, 5.5]]]))
    for convention in (AGGDRAW, MATPLOTLIB):
        assert exact_coverage(scene, convention) == agg_cover_coverage(scene, convention)
    assert exact_coverage(scene, PYGAME) == inclusive_scanline_coverage(scene, PYGAME)
    # any cover (clockwise: ceil) draws the half-covered pixel, and no pixel the triangle only touches
    assert exact_coverage(Scene(2, 2, [[[0, 0], [1, 0], [0, 1]]]), MATPLOTLIB).counts(2, 2).tolist() == [[1, 0], [0, 0]]
    # culling by the orientation after the input grid
    culled = dataclasses.replace(PYGAME, cull="cw")
    assert len(exact_coverage(Scene(4, 4, [[[0, 0], [3, 0], [0, 3]]]), culled)) == 0


def test_the_rules_boundaries():
    t = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    assert on_library_boundary(t, 1, 0, AGGDRAW) and not on_library_boundary(t, 0, 0, AGGDRAW)
    assert on_library_boundary(t, 2, 0, PYGAME) and not on_library_boundary(t, 0, 1, PYGAME)
    from harness.oracle.coverage_rules import on_rule_boundary, rules_reference

    assert on_rule_boundary(t, 1, 0, AGGDRAW)
    scene = Scene(4, 4, [t])
    assert rules_reference(scene, PYGAME) == inclusive_scanline_coverage(scene, PYGAME)


@pytest.mark.parametrize("bad", [Float32AggCover, ExclusiveRightScanline])
def test_each_known_bad_rasterizer_is_caught_by_conformance(bad):
    rasterizer = bad()
    scene = Scene(8, 8, [[[0, 0], [6, 0], [0, 6]], [[2, 2], [8, 3], [3, 8]], [[1, 7], [7, 7], [4, 4]]])
    case = Case("rules/known-bad", scene, lattice=True)
    oracle = exact_coverage(scene, rasterizer.convention)
    result = conformance(case, rasterizer.rasterize(scene), oracle, rasterizer.convention)
    assert result.status == "fail" and result.metrics["wrong"] > 0, result.message


@pytest.mark.parametrize("bad", [Float32AggCover, ExclusiveRightScanline])
def test_identify_does_not_call_a_known_bad_rasterizer_its_declared_rule(bad):
    from harness.identify.rule_probes import fit_rule

    rasterizer = bad()
    fit = fit_rule(rasterizer.rasterize)
    assert not (fit.exact and fit.convention == rasterizer.convention), fit.describe()


class _Oracular:
    def __init__(self, convention: Convention) -> None:
        self.convention = convention

    def rasterize(self, scene: Scene):  # noqa: ANN201
        return exact_coverage(scene, self.convention)


@pytest.mark.parametrize("convention", [AGGDRAW, MATPLOTLIB, PYGAME])
def test_identify_recovers_each_rule_input_rounding_included(convention):
    from harness.identify.rule_probes import fit_rule

    fit = fit_rule(_Oracular(convention).rasterize)
    assert fit.exact and fit.convention == convention, fit.describe()


def test_checks_expect_what_the_inclusive_rule_draws():
    """Zero-area triangles draw under inclusive-scanline (degenerate asks only that
    non-finite ones draw nothing), and the pixels its truncated mesh draws just outside a
    partition are the rule's own (watertight)."""
    from harness.checks import degenerate, watertight

    flat = Scene(6, 6, np.array([[[1, 1], [5, 3], [3, 2]], [[1, 4], [4, 4], [2, 4]]], dtype=np.float64))
    case = Case("degenerate/rules/inclusive", flat, lattice=True)
    drawn = exact_coverage(flat, PYGAME)
    assert len(drawn) > 0 and degenerate(case, drawn, PYGAME).status == "pass"
    assert degenerate(case, drawn, Convention()).status == "fail"  # under a sample rule they draw nothing
    # a partition whose outline the integer input moves: pixel (2, 2) lies wholly outside, yet the truncated mesh draws it
    quad = np.array([[3.5, 1.75], [8.5, 1.0], [7.5, 2.75], [1.25, 8.0]])
    scene = Scene(10, 10, np.array([[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]))
    part = Case("partitions/rules/inclusive", scene, lattice=False, region=quad)
    own = exact_coverage(scene, PYGAME)
    assert own.counts(10, 10)[2, 2] == 1
    result = watertight(part, own, PYGAME, lambda: own)
    assert result.status == "pass" and result.metrics["strays"] == 0 and result.metrics["rule_own"] > 0, result.message
    assert watertight(part, own).metrics["strays"] > 0  # convention-free, a stray
