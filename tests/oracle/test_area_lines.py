"""Anti-aliased lines: the exact areas in Q(sqrt(d)) (and the round caps' enclosures), and the
float kernel within its proven bound (harness.oracle.area_lines)."""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from harness.contract.conventions import Convention, LineRule
from harness.contract.scenes import LineScene
from harness.oracle.area import exact_area
from harness.oracle.area_lines import (
    QSqrt,
    exact_line_area,
    exact_line_pixel_areas,
    line_area_bound,
    line_pixel_areas,
)
from harness.oracle.coverage import exact_coverage

SIZE = 8


def _float_areas(segments, w, cap, width=SIZE, height=SIZE):
    s, x, y, a = line_pixel_areas(np.asarray(segments, float), w, cap, width, height)
    got = {(int(si), int(xi), int(yi)): float(ai) for si, xi, yi, ai in zip(s, x, y, a)}
    assert len(got) == s.size, "a pixel reported twice"
    return got


def within_bound(segments, w, cap, width=SIZE, height=SIZE):
    """Every pixel of every segment: |float - exact| <= the segment's bound, decided exactly;
    pixels left out hold an exact area within it too."""
    segments = np.asarray(segments, float).reshape(-1, 2, 2)
    got = _float_areas(segments, w, cap, width, height)
    bound = line_area_bound(segments, w, cap, width, height)
    exact = exact_line_pixel_areas(segments, w, cap, width, height)
    for key in set(got) | set(exact):
        value = Fraction(got.get(key, 0.0))
        area = exact.get(key)
        if area is None:
            area = exact_line_area(segments[key[0]], w, cap, key[1], key[2])
        limit = Fraction(float(bound[key[0]]))
        assert not abs(value - area) > limit, (key, float(value), float(area), float(limit))


coordinate = st.integers(-8, 72).map(lambda k: k / 8)  # on a 1/8 lattice, around an 8 x 8 viewport
widths = st.sampled_from([0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 2.0 / 3.0])


@settings(max_examples=40, deadline=None)
@given(ax=coordinate, ay=coordinate, bx=coordinate, by=coordinate, w=widths, cap=st.sampled_from(["butt", "square"]))
@example(ax=1.0, ay=1.0, bx=6.0, by=1.0, w=1.0, cap="butt")  # axis-aligned: d a square
@example(ax=1.0, ay=1.0, bx=1.0, by=1.0, w=2.0, cap="square")  # zero length
@example(ax=0.5, ay=0.5, bx=7.5, by=3.5, w=1.0, cap="butt")  # sqrt(58): irrational
def test_float_within_bound_butt_square(ax, ay, bx, by, w, cap):
    within_bound([[[ax, ay], [bx, by]]], w, cap)


@settings(max_examples=2, deadline=None)
@given(ax=coordinate, ay=coordinate, bx=coordinate, by=coordinate, w=st.sampled_from([1.0, 2.0]))
@example(ax=2.0, ay=2.0, bx=2.0, by=2.0, w=2.0)  # a disc
def test_float_within_bound_round(ax, ay, bx, by, w):
    within_bound([[[ax, ay], [bx, by]]], w, "round")


def test_qsqrt_sign_is_exact():
    d = Fraction(2)
    root = QSqrt(Fraction(0), Fraction(1), d)
    # 665857/470832 is a convergent of sqrt(2), above it by about 1.6e-12
    assert (root - Fraction(665857, 470832)).sign() == -1
    assert (root - Fraction(470832, 332929)).sign() == 1
    assert (root * root - 2).sign() == 0


def test_axis_aligned_line_is_the_rectangle():
    # a horizontal butt line is a rectangle: its areas are the triangle oracle's of its halves
    a, b, w = (0.25, 3.3), (6.75, 3.3), 1.5
    tris = [[[0.25, 2.55], [6.75, 2.55], [6.75, 4.05]], [[0.25, 2.55], [6.75, 4.05], [0.25, 4.05]]]
    for y in range(2, 5):
        for x in range(0, 7):
            want = exact_area(tris[0], x, y) + exact_area(tris[1], x, y)
            assert exact_line_area([a, b], w, "butt", x, y) == want


def test_square_caps_add_half_a_width_each_end():
    seg = [[2.0, 2.5], [5.0, 2.5]]
    assert exact_line_area(seg, 1.0, "square", 1, 2) == Fraction(1, 2)
    assert exact_line_area(seg, 1.0, "butt", 1, 2) == 0
    assert exact_line_area(seg, 1.0, "square", 5, 2) == Fraction(1, 2)


def test_rotated_square_total_area():
    # the sum over all pixels of a diagonal butt stroke is its length times its width, exactly
    seg = np.array([[1.0, 1.0], [6.0, 5.0]])
    rects = [exact_line_area(seg, 1.0, "butt", x, y).rect for x in range(SIZE) for y in range(SIZE)]
    acc = QSqrt(Fraction(0), Fraction(0), Fraction(41))
    for r in rects:
        acc = acc + r
    assert (acc - QSqrt(Fraction(0), Fraction(1), Fraction(41))).sign() == 0  # sqrt(41) * 1


def test_round_cap_disc_total():
    # a zero-length round stroke is a disc: its areas sum to pi h**2, enclosed
    w = 3.0
    found = exact_line_pixel_areas([[[4.0, 4.0], [4.0, 4.0]]], w, "round", SIZE, SIZE)
    lo = sum(v._caps(256)[0] for v in found.values())
    hi = sum(v._caps(256)[1] for v in found.values())
    assert lo <= Fraction(math.pi * 2.25) <= hi
    assert hi - lo < Fraction(1, 10**2)


def test_far_segment_within_bound():
    seg = [[[-1e12, 3.25], [1e12, 4.75]]]
    got = _float_areas(seg, 1.0, "butt")
    assert got
    bound = line_area_bound(np.array(seg), 1.0, "butt", SIZE, SIZE)[0]
    for (_s, x, y), value in got.items():
        exact = exact_line_area(seg[0], 1.0, "butt", x, y)
        assert not abs(Fraction(value) - exact) > Fraction(float(bound))


def test_oracle_dispatches_area_lines():
    scene = LineScene.from_strips(8, 8, [[[1, 1], [7, 6], [2, 7]]], line_width=1.25)
    for cap in ("butt", "square", "round"):
        cov = exact_coverage(scene, Convention(coverage="area", line=LineRule("rectangle", cap=cap)))
        assert cov.alpha is not None and cov.alpha.size == cov.n_pixels
        assert np.all((cov.alpha > 0) & (cov.alpha <= 1))


def test_caps_refused_off_area():
    with pytest.raises(ValueError, match="rectangle option"):
        LineRule("diamond-exit", cap="square")
    scene = LineScene.from_strips(8, 8, [[[1, 1], [7, 6]]], line_width=1.0)
    with pytest.raises(ValueError, match="area-coverage option"):
        exact_coverage(scene, Convention(line=LineRule("rectangle", cap="round")))
    with pytest.raises(ValueError, match="rectangles"):
        exact_coverage(scene, Convention(coverage="area", line=LineRule("diamond-exit")))


def test_line_rule_cap_round_trips_and_describes():
    for cap in ("butt", "square", "round"):
        rule = LineRule("rectangle", cap=cap)
        assert eval(repr(rule), {"LineRule": LineRule}) == rule  # noqa: S307 - our own repr
        assert (cap in rule.describe()) == (cap != "butt")
    with pytest.raises(ValueError, match="LineRule.cap must be one of"):
        LineRule("rectangle", cap="triangle")  # type: ignore[arg-type]
