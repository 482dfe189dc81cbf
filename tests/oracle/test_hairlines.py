"""skia's hairlines and Qt's cosmetic lines (harness.oracle.hairlines): the compiled oracle
against its rational reference (the closed form of each rule, in Fractions), the far
segments' Python-integer walk, the quirks the sources have (skia's start on a pixel centre,
Qt's caps and points), the rules' place in the convention and the line oracle, and -- where
the libraries are installed -- the libraries themselves against the rules."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from harness.contract.conventions import FIXED_POINT_LINE_RULES, LINE_RULES, Convention, LineRule
from harness.contract.scenes import LineScene
from harness.oracle.hairlines import HAIRLINE_MAX, HAIRLINE_RULES, hairline_spans, hairline_spans_rational
from harness.oracle.lines import line_coverage
from tests.optional import need
from tests.oracle.test_lines import QUICK, SIZE, _pixels, _same, _sorted, segments

RULES = st.sampled_from(FIXED_POINT_LINE_RULES)


def _cells(spans) -> list[tuple[int, int]]:
    return sorted((x, y) for _, x, y in _pixels(spans))


@QUICK
@given(segments, RULES)
@example((np.array([[0.5, 0.5]]), np.array([[4.5, 4.5]])), "skia-hairline")  # 45 degrees: y-major, from a centre
@example((np.array([[0.5, 0.5]]), np.array([[4.5, 4.5]])), "qt-cosmetic")  # 45 degrees: x-major
@example((np.array([[2.25, 3.0]]), np.array([[2.25, 3.0]])), "qt-cosmetic")  # a point
@example((np.array([[2.25, 3.0]]), np.array([[2.25, 3.0]])), "skia-hairline")
@example((np.array([[-1.5, 2.75], [7.0, -0.25]]), np.array([[6.25, -1.0], [1.5, 9.5]])), "skia-hairline")  # below 0
@example((np.array([[-1.5, 2.75], [7.0, -0.25]]), np.array([[6.25, -1.0], [1.5, 9.5]])), "qt-cosmetic")
@example((np.array([[1.0, 1.0]]), np.array([[1.0 + 2**-7, 5.0]])), "qt-cosmetic")  # same 26.6 x: vertical
def test_hairlines_match_rational(segs, rule: str) -> None:
    a, b = segs
    fast = hairline_spans(a, b, SIZE, SIZE, rule)
    _same(fast, hairline_spans_rational(a, b, SIZE, SIZE, rule))
    _sorted(fast)


@QUICK
@given(st.integers(-2**20, 2**20), st.integers(-2**20, 2**20), st.integers(1, 6), st.integers(-6, 6), RULES)
def test_far_segments_walk_in_python_integers(shift_x: int, shift_y: int, run: int, rise: int, rule: str) -> None:
    """A segment beyond the compiled range is walked in Python integers: the same pixels
    as the rational reference, through the viewport."""
    scale = HAIRLINE_MAX * 4
    a = np.array([[-scale + shift_x / 64, 3.25 + rise / 4]])
    b = np.array([[scale + shift_y / 64, 4.75 - run / 4]])
    fast = hairline_spans(a, b, SIZE, SIZE, rule)
    _same(fast, hairline_spans_rational(a, b, SIZE, SIZE, rule))
    assert len(_pixels(fast)) == SIZE  # x-major: one pixel in every column


def test_skia_starts_on_a_centre_one_step_off() -> None:
    """skia's DDA starts at the first pixel centre at or past the end point
    (``(32 - x0) & 63``), but the first column drawn is ``(x0 + 32) >> 6``: for an end
    exactly on a centre that is the next column, drawn with the previous one's y."""
    on = hairline_spans([[0.5, 0.5]], [[5.5, 2.5]], SIZE, SIZE, "skia-hairline")
    off = hairline_spans([[0.5 + 2**-6, 0.5]], [[5.5, 2.5]], SIZE, SIZE, "skia-hairline")
    assert _cells(on) == [(1, 0), (2, 0), (3, 1), (4, 1), (5, 2)]  # columns 1..5 at the y of x = 0.5..4.5
    assert _cells(off) == [(1, 0), (2, 1), (3, 1), (4, 2), (5, 2)]  # y at each column's own centre


def test_skia_end_pixels_are_the_centres_in_the_half_open_range() -> None:
    """The left (upper) end's pixel only when the end lies left of (above) its centre, the
    right (lower) end's when at or past it; both directions alike."""
    for a, b in (([1.25, 2.5], [4.75, 2.5]), ([4.75, 2.5], [1.25, 2.5])):
        assert _cells(hairline_spans([a], [b], SIZE, SIZE, "skia-hairline")) == [(1, 2), (2, 2), (3, 2), (4, 2)]
    assert _cells(hairline_spans([[1.75, 2.5]], [[4.25, 2.5]], SIZE, SIZE, "skia-hairline")) == [(2, 2), (3, 2)]
    assert _cells(hairline_spans([[1.5, 2.5]], [[1.5 + 2**-6, 2.5]], SIZE, SIZE, "skia-hairline")) == []  # too short


def test_qt_draws_both_end_pixels_and_points() -> None:
    """Square caps reach half a pixel past each end: both end pixels, whichever way; a
    segment whose ends are equal is its point's pixel; one whose 26.6 ends coincide but
    whose ends differ draws nothing."""
    for a, b in (([1.75, 2.5], [4.25, 2.5]), ([4.25, 2.5], [1.75, 2.5])):
        assert _cells(hairline_spans([a], [b], SIZE, SIZE, "qt-cosmetic")) == [(1, 2), (2, 2), (3, 2), (4, 2)]
    assert _cells(hairline_spans([[3.5, 4.5]], [[3.5, 4.5]], SIZE, SIZE, "qt-cosmetic")) == [(3, 4)]
    assert _cells(hairline_spans([[0.999, 3.5]], [[0.999, 3.5]], SIZE, SIZE, "qt-cosmetic")) == [(0, 3)]  # floor
    assert _cells(hairline_spans([[3.3, 4.4]], [[3.305, 4.4]], SIZE, SIZE, "qt-cosmetic")) == []
    assert _cells(hairline_spans([[-0.5, 3.5]], [[-0.5, 3.5]], SIZE, SIZE, "qt-cosmetic")) == []  # pixel -1


def test_the_rules_are_truncated_to_26_6_toward_zero() -> None:
    """An end point moves only when it crosses a multiple of 1/64 (toward zero: -1/128
    truncates to 0, as 1/128 does)."""
    for rule in FIXED_POINT_LINE_RULES:
        base = _cells(hairline_spans([[0.0, 0.0]], [[6.0, 3.0]], SIZE, SIZE, rule))
        for d in (2**-7, -(2**-7), 2**-20):
            assert _cells(hairline_spans([[d, d]], [[6.0 + abs(d), 3.0]], SIZE, SIZE, rule)) == base, (rule, d)


def test_the_rules_in_the_convention_and_the_line_oracle() -> None:
    assert set(FIXED_POINT_LINE_RULES) <= set(LINE_RULES) and set(FIXED_POINT_LINE_RULES) == set(HAIRLINE_RULES)
    scene = LineScene.from_strips(12, 10, [[[0.5, 0.5], [9.25, 4.75], [2.0, 8.5]], [[11.5, 9.5], [11.5, 0.5]]])
    a, b = scene.segments()
    for rule in FIXED_POINT_LINE_RULES:
        convention = Convention(line=rule)
        assert convention.line == LineRule(rule) and not convention.line.last_pixel
        coverage = line_coverage(scene, convention)
        s, y, x0, x1 = hairline_spans(a, b, 12, 10, rule)
        assert (coverage.primitive.tolist(), coverage.y.tolist(), coverage.x0.tolist(), coverage.x1.tolist()) == (
            s.tolist(), y.tolist(), x0.tolist(), x1.tolist())
        # the convention's input precision applies first: 26.6 toward zero changes nothing
        truncated = line_coverage(scene, Convention(line=rule, input="fixed6-toward-zero"))
        assert truncated.pixels()[0].size == coverage.pixels()[0].size
        with pytest.raises(ValueError, match="width 1"):
            line_coverage(LineScene.from_strips(12, 10, [[[0.5, 0.5], [9.25, 4.75]]], line_width=2.0), convention)
    assert "skia hairlines" in LineRule("skia-hairline").describe()
    assert "Qt cosmetic lines" in LineRule("qt-cosmetic").describe()


def test_non_finite_segments_cover_nothing() -> None:
    a = np.array([[np.nan, 1.0], [1.0, 1.0], [np.inf, 2.0]])
    b = np.array([[3.0, 1.0], [5.5, 1.5], [3.0, 2.0]])
    for rule in FIXED_POINT_LINE_RULES:
        s, *_ = hairline_spans(a, b, SIZE, SIZE, rule)
        assert set(s.tolist()) == {1}


# -- the libraries themselves (where installed) ---------------------------------------------------


def _library(rule: str):
    if rule == "skia-hairline":
        need("skia")
        from rasterizers.real.adapters import SkiaPath

        return SkiaPath()
    need("PyQt6")
    from rasterizers.real.qt_raster import QtRaster

    return QtRaster()


@pytest.mark.parametrize("rule", FIXED_POINT_LINE_RULES)
def test_the_library_draws_the_rule(rule: str) -> None:
    """skia-python and PyQt6 draw exactly the rule's pixels for segments inside the canvas
    (floats, and ends on a 1/2, 1/4 and 1/64 lattice: centres, corners, ties), each segment
    alone, both directions; a segment crossing the canvas edge is clipped by the library
    in floating point first (SkLineClipper::IntersectLine, QCosmeticStroker::clipLine),
    which no rule of the segment says."""
    library = _library(rule)
    rng = np.random.default_rng(33)
    n = 240
    ends = np.concatenate([rng.uniform(1.0, 23.0, (n // 4, 4)), rng.integers(2, 46, (n // 4, 4)) / 2.0,
                           rng.integers(4, 92, (n // 4, 4)) / 4.0, rng.integers(64, 23 * 64, (n // 4, 4)) / 64.0])
    ends[::29, 2:] = ends[::29, :2]  # points
    a, b = np.concatenate([ends[:, :2], ends[:, 2:]]), np.concatenate([ends[:, 2:], ends[:, :2]])
    scene = LineScene.from_segments(24, 24, a, b)
    drawn = library.rasterize(scene)
    exact = line_coverage(scene, Convention(line=rule))
    assert set(zip(*(v.tolist() for v in drawn.pixels()))) == set(zip(*(v.tolist() for v in exact.pixels())))


# -- the known-bad doubles: their walk without the bug is the rule --------------------------------


def test_the_known_bad_doubles_differ_from_the_rule_by_their_bug_only() -> None:
    from tests.known_bad.hairlines import QtFlatCaps, SkiaCentredStart, _walk

    rng = np.random.default_rng(7)
    ends = np.concatenate([rng.integers(-8, 56, (80, 4)) / 2.0, rng.uniform(-2.0, 26.0, (80, 4))])
    ends[::13, 2:] = ends[::13, :2]
    scene = LineScene.from_segments(24, 24, ends[:, :2], ends[:, 2:])

    def pixels(coverage):
        return set(zip(*(v.tolist() for v in coverage.pixels())))

    for rule, qt, bad in (("skia-hairline", False, SkiaCentredStart()), ("qt-cosmetic", True, QtFlatCaps())):
        exact = pixels(line_coverage(scene, Convention(line=rule)))
        assert pixels(_walk(scene, qt)) == exact
        assert pixels(bad.rasterize(scene)) != exact
