"""The line contract: LineScene's structure and validation, the line rule in Convention, the
oracle behind exact_coverage (snapping first, one rule per convention, exact fallbacks
beyond the compiled kernels' range) and case JSON for lines."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.protocol import scene_kinds_of, takes
from harness.contract.scenes import LineScene
from harness.kinds import SCENE_KINDS
from harness.oracle.bresenham_lines import _bresenham_far
from harness.oracle.coverage import exact_coverage
from harness.oracle.lines import bresenham_spans, diamond_exit_spans_rational, rectangle_spans_rational

QUICK = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _strips() -> LineScene:
    return LineScene.from_strips(8, 8, [[[0.5, 0.5], [6.5, 2.5], [6.5, 7.5], [0.5, 0.5]], [[0, 4], [3, 4]]])


# -- LineScene ---------------------------------------------------------------------------------


def test_segments_strips_and_joints() -> None:
    scene = _strips()
    a, b = scene.segments()
    assert len(scene) == 4 and scene.kind == "lines" and scene.noun == "segment" and "lines" in SCENE_KINDS
    assert a.tolist() == [[0.5, 0.5], [6.5, 2.5], [6.5, 7.5], [0, 4]]
    assert b.tolist() == [[6.5, 2.5], [6.5, 7.5], [0.5, 0.5], [3, 4]]
    assert scene.segment_strip.tolist() == [0, 0, 0, 1]
    assert scene.joints().tolist() == [[0, 1], [1, 2]]
    # the first strip ends where it starts: a closed polyline, its closing joint too
    assert scene.joints(closed=True).tolist() == [[0, 1], [1, 2], [2, 0]]
    assert scene.edges()[2].tolist() == [0, 1, 2, 3]


def test_subset_keeps_runs_of_a_strip_together() -> None:
    scene = _strips()
    assert scene.subset([0, 1, 3]).strip_sizes.tolist() == [3, 2]
    moved = scene.subset([2, 0, 1, 3])
    assert moved.strip_sizes.tolist() == [2, 3, 2]
    assert moved.segments()[0].tolist() == [scene.segments()[0][k].tolist() for k in (2, 0, 1, 3)]


def test_reversed_retraces_every_segment() -> None:
    scene = _strips()
    back, origin = scene.reversed()
    a, b = scene.segments()
    ra, rb = back.segments()
    assert origin.tolist() == [2, 1, 0, 3]
    assert np.array_equal(ra, b[origin]) and np.array_equal(rb, a[origin])


def test_boxes_grow_by_half_the_width_and_name_non_finite_segments() -> None:
    scene = LineScene.from_segments(8, 8, [[1.0, 1.0], [np.nan, 2.0]], [[3, 2], [4, 4]], line_width=2.0)
    lo, hi, finite = scene.primitive_boxes()
    assert lo[0].tolist() == [0, 0] and hi[0].tolist() == [4, 3] and finite.tolist() == [True, False]
    assert scene.non_finite() == (1,)


@pytest.mark.parametrize(("make", "words"), [
    (lambda: LineScene(8, 8, [[0, 0], [1, 1], [2, 2]], [2]), "add up to 2 vertices, not the 3"),
    (lambda: LineScene(8, 8, [[0, 0]], [1]), "strip 0 has fewer than 2 vertices"),
    (lambda: LineScene(8, 8, [[0, 0], [1, 1]], [2], line_width=0.0), "line_width must be positive"),
    (lambda: LineScene(8, 8, [[0, 0], [1, 1]], [2], line_width=float("nan")), "line_width must be positive"),
    (lambda: LineScene(8, 8, [["a", "b"], [1, 1]], [2]), "vertices must hold real numbers"),  # type: ignore[arg-type]
    (lambda: LineScene(8, 8, [0, 0, 1, 1], [2]), "vertices must have shape (V, 2)"),
    (lambda: LineScene(0, 8, [[0, 0], [1, 1]], [2]), "width must lie in"),
])
def test_bad_line_scenes_are_refused_by_name(make, words) -> None:
    with pytest.raises(ValueError, match=None) as error:
        make()
    assert words in str(error.value)


def test_only_rasterizers_listing_lines_are_handed_them() -> None:
    class Drawer:
        name, convention, scene_kinds = "drawer", Convention(), ("lines",)

        def rasterize(self, scene):
            return Coverage.empty()

    class Filler:
        name, convention = "filler", Convention()

        def rasterize(self, scene):
            return Coverage.empty()

    assert scene_kinds_of(Drawer()) == ("lines",)
    assert takes(Drawer(), _strips()) and not takes(Filler(), _strips())


# -- the line rule in Convention ---------------------------------------------------------------


def test_line_rule_defaults_and_validation() -> None:
    assert Convention().line == LineRule("diamond-exit", last_pixel=False)
    assert LineRule("bresenham").last_pixel is True  # seed 003 draws both end points
    assert Convention(line="rectangle").line.rule == "rectangle"
    assert "line=LineRule(rule='bresenham'" in repr(Convention(line="bresenham"))
    assert repr(Convention()) == "Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none')"
    assert Convention(subpixel_bits=4, line=LineRule("bresenham", rounding="floor", ties="stay",
                                                     last_pixel=False)).describe_lines() \
        == "Bresenham lines, end points to pixels by floor, ties stay, last pixel omitted, snapped to 1/16 px (4 bits)"
    for bad, words in ((dict(rule="dda"), "LineRule.rule must be one of"), (dict(rounding="up"), "LineRule.rounding"),
                       (dict(ties="maybe"), "LineRule.ties"), (dict(last_pixel="yes"), "LineRule.last_pixel")):
        with pytest.raises(ValueError, match=words):
            LineRule(**bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="Convention.line must be"):
        Convention(line=3)


# -- the oracle -----------------------------------------------------------------------------------


def test_snapping_comes_before_the_rule() -> None:
    # (0.49, 0.5) -> (4.51, 0.5) leaves the diamonds of pixels 0..3 and ends inside pixel 4's;
    # snapped to whole pixels it runs (0, 0) -> (5, 0) along the top corners of row 0's
    # diamonds (excluded): nothing in row 0
    scene = LineScene.from_segments(8, 2, [[0.49, 0.5]], [[4.51, 0.5]])
    plain = exact_coverage(scene, Convention()).counts(8, 2)[0].tolist()
    snapped = exact_coverage(scene, Convention(subpixel_bits=0)).counts(8, 2)[0].tolist()
    assert plain == [1, 1, 1, 1, 0, 0, 0, 0]
    assert snapped == [0] * 8
    assert snapped == exact_coverage(LineScene.from_segments(8, 2, [[0, 0]], [[5, 0]]), Convention()).counts(8, 2)[0].tolist()


def test_each_rule_draws_its_own_pixels() -> None:
    scene = LineScene.from_segments(8, 4, [[0.5, 0.5]], [[6.5, 3.5]])
    diamond = exact_coverage(scene, Convention()).counts(8, 4)
    bresenham = exact_coverage(scene, Convention(line="bresenham")).counts(8, 4)
    rectangle = exact_coverage(scene, Convention(line="rectangle")).counts(8, 4)
    assert diamond.sum() == 6 and bresenham.sum() == 7  # diamond-exit omits the end pixel
    assert bresenham[3, 6] == 1 and diamond[3, 6] == 0
    assert rectangle.sum() >= 1 and not np.array_equal(rectangle, bresenham)


def test_wide_lines_are_for_the_rectangle_rule_and_replicated_diamonds_only() -> None:
    scene = LineScene.from_segments(8, 8, [[1, 1]], [[6, 5]], line_width=2.5)
    assert exact_coverage(scene, Convention(line="rectangle")).n_pixels > 5
    with pytest.raises(ValueError, match="width 1, not 2.5"):
        exact_coverage(scene, Convention())
    with pytest.raises(ValueError, match="integer widths, not 2.5"):
        exact_coverage(scene, Convention(line=LineRule(wide="replicate")))
    # multisample lines are rectangles per sample: a width-1 rule there is refused
    with pytest.raises(ValueError, match="rectangles sampled per sample"):
        exact_coverage(LineScene.from_segments(8, 8, [[1, 1]], [[6, 5]]), Convention(samples=4))


@QUICK
@given(st.sampled_from([1e200, 2.0**460, 3e9, 1e-300]), st.floats(-3, 3), st.floats(-3, 3), st.floats(0, 12), st.floats(0, 12),
       st.booleans())
def test_far_diamond_segments_are_exact(big, dx, dy, cx, cy, last_pixel) -> None:
    """Beyond the compiled kernel's range (2**450, 2**-450) a segment is decided in
    rationals: the same pixels as the brute-force reference."""
    a = np.array([[cx + dx * big, cy + dy * big]])
    b = np.array([[cx - dx * big, cy - dy * big]]) if big > 1 else a + [[dx * big, dy * big]]
    scene = LineScene.from_segments(12, 12, a, b)
    got = exact_coverage(scene, Convention(line=LineRule(last_pixel=last_pixel))).counts(12, 12)
    want = Coverage(*diamond_exit_spans_rational(a, b, 12, 12, last_pixel)).counts(12, 12)
    assert np.array_equal(got, want)


@QUICK
@given(st.tuples(st.integers(-40, 50), st.integers(-40, 50)), st.tuples(st.integers(-40, 50), st.integers(-40, 50)),
       st.sampled_from(["step", "stay"]), st.booleans())
def test_far_bresenham_walk_matches_the_kernel(p0, p1, ties, last_pixel) -> None:
    """The closed-form walk used for end points beyond 2**30 (Python integers, clipped to
    the viewport by bisection) draws what the compiled walk draws."""
    out: list[tuple[int, int, int, int]] = []
    _bresenham_far(0, p0, p1, 13, 9, ties, last_pixel, out)
    got = np.zeros((9, 13), dtype=np.int32)
    for _, y, x, _ in out:
        got[y, x] += 1
    want = Coverage(*bresenham_spans(np.add([p0], 0.5), np.add([p1], 0.5), 13, 9, "floor", ties, last_pixel)).counts(13, 9)
    assert np.array_equal(got, want)


def test_far_segments_of_every_rule_cross_the_viewport() -> None:
    # the diagonal y = x from -1e300 to 1e300: every diagonal pixel under each rule
    scene = LineScene.from_segments(6, 6, [[-1e300, -1e300]], [[1e300, 1e300]])
    for rule in ("diamond-exit", "bresenham"):
        assert np.array_equal(exact_coverage(scene, Convention(line=rule)).counts(6, 6), np.eye(6, dtype=np.int32)), rule
    far = LineScene.from_segments(6, 6, [[-1e160, 3.0]], [[1e160, 3.0]])
    want = Coverage(*rectangle_spans_rational([[-1e160, 3.0]], [[1e160, 3.0]], 1.0, width=6, height=6)).counts(6, 6)
    assert np.array_equal(exact_coverage(far, Convention(line="rectangle")).counts(6, 6), want)
    assert want[2].tolist() == [1] * 6 and want.sum() == 6  # the upper side's samples (top-left ties)


def test_non_finite_segments_cover_nothing() -> None:
    scene = LineScene.from_segments(6, 6, [[np.nan, 1.0], [0.5, 0.5], [np.inf, 2.0]], [[3.0, 3.0], [4.5, 0.5], [1.0, 1.0]])
    for rule in ("diamond-exit", "bresenham", "rectangle"):
        assert set(exact_coverage(scene, Convention(line=rule)).primitive.tolist()) <= {1}, rule


# -- case JSON ----------------------------------------------------------------------------------


def test_line_cases_round_trip_exactly() -> None:
    scene = LineScene.from_strips(8, 8, [[[0.5, 0.1], [6.5, 2.5], [1.0, 7.0]], [[1e-300, 2.0], [np.inf, 3.0]]], line_width=1.5)
    back = case_from_json(case_to_json(Case("lines/x", scene, refusable=(2,))))
    assert isinstance(back, Case) and isinstance(back.scene, LineScene)
    assert np.array_equal(back.scene.vertices, scene.vertices) and back.scene.strip_sizes.tolist() == [3, 2]
    assert back.scene.line_width == 1.5 and back.refusable == (2,)


def test_malformed_line_case_json_names_the_fault() -> None:
    data = case_to_json(Case("lines/x", _strips()))
    with pytest.raises(ValueError, match="'positions' and 'lines'"):
        case_from_json({**data, "positions": [[[0, 0], [1, 0], [0, 1]]]})
    with pytest.raises(ValueError, match="lines"):
        case_from_json({**data, "lines": [[[0, 0]]]})


def test_toward_zero_is_the_c_cast() -> None:
    """softpipe and Pillow take an end point's pixel by C's (int) cast: pixel 0 holds
    -1 < x < 1, unlike floor."""
    from harness.oracle.lines import end_point_pixels

    values = np.array([-1.5, -1.0, -0.5, -0.0, 0.5, 1.0, 1.5])
    assert end_point_pixels(values, "toward-zero").tolist() == [-1, -1, 0, 0, 0, 1, 1]
    assert end_point_pixels(values, "floor").tolist() == [-2, -1, -1, 0, 0, 1, 1]
    scene = LineScene.from_segments(6, 3, [[-0.5, 1.5]], [[4.5, 1.5]])
    cast = exact_coverage(scene, Convention(line=LineRule("bresenham", rounding="toward-zero"))).counts(6, 3)[1]
    floor = exact_coverage(scene, Convention(line=LineRule("bresenham", rounding="floor"))).counts(6, 3)[1]
    assert cast.tolist() == [1, 1, 1, 1, 1, 0] and floor.tolist() == [1, 1, 1, 1, 1, 0]
    steep = LineScene.from_segments(6, 6, [[-0.5, 0.5]], [[1.5, 5.5]])  # starts in pixel 0 (cast) or -1 (floor)
    assert exact_coverage(steep, Convention(line=LineRule("bresenham", rounding="toward-zero"))).counts(6, 6)[0, 0] == 1
    assert exact_coverage(steep, Convention(line=LineRule("bresenham", rounding="floor"))).counts(6, 6)[0, 0] == 0
