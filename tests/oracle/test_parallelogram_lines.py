"""Vulkan's non-strict (parallelogram) lines (harness.oracle.parallelogram_lines): the compiled
oracle against its rational reference written from the four vertices, the parallelogram as
two triangles under the triangle oracle, partitions, and the rule's place in the convention
(LineRule("parallelogram"), a line rule's own snap rounding)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from harness.contract.conventions import SNAP_ROUNDINGS, TIE_RULES, Convention, LineRule
from harness.contract.scenes import LineScene, Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.lines import line_coverage
from harness.oracle.parallelogram_lines import parallelogram_spans, parallelogram_spans_rational
from harness.oracle.rectangle_lines import rectangle_spans
from tests.oracle.test_lines import QUICK, SIZE, _pixels, _same, _sorted, lattice_point, samples, segments, widths


def _mask(spans, size: int = SIZE) -> np.ndarray:
    counts = np.zeros((size, size), dtype=np.int32)
    for _, x, y in _pixels(spans):
        counts[y, x] += 1
    return counts


@QUICK
@given(segments, widths, samples, st.sampled_from(TIE_RULES))
@example((np.array([[0.5, 0.5]]), np.array([[6.5, 3.5]])), 1.0, (0.5, 0.5), "top-left")  # sides through centres
@example((np.array([[1.0, 1.0]]), np.array([[5.0, 5.0]])), 1.0, (0.5, 0.5), "bottom-right")  # slope 1: x-major
@example((np.array([[1.0, 5.0]]), np.array([[5.0, 1.0]])), 1.0, (0.5, 0.5), "top-right-y-first")
@example((np.array([[2.5, 0.5]]), np.array([[3.5, 6.5]])), 1.0, (0.5, 0.5), "top-left")  # y-major, ends on centres
@example((np.array([[0.5, 1.0]]), np.array([[0.5, 1.0]])), 1.0, (0.5, 0.5), "top-left")  # zero length
def test_parallelogram_matches_rational(segs, w, sample, tie) -> None:
    a, b = segs
    fast = parallelogram_spans(a, b, w, sample, tie, width=SIZE, height=SIZE)
    _same(fast, parallelogram_spans_rational(a, b, w, sample, tie, width=SIZE, height=SIZE))
    _sorted(fast)


@QUICK
@given(lattice_point(), lattice_point(), st.sampled_from([0.5, 1.0, 2.0]), samples, st.sampled_from(TIE_RULES))
def test_parallelogram_is_two_triangles(a, b, w, sample, tie) -> None:
    """On a lattice the parallelogram's vertices are floats: the triangle oracle on its two
    triangles (sharing a diagonal: each sample once) under the same sample point and tie
    rule covers the same samples -- the body llvmpipe draws with its triangles' planes."""
    if a == b:
        return
    h = w / 2
    off = (0.0, h) if abs(b[0] - a[0]) >= abs(b[1] - a[1]) else (h, 0.0)
    corners = [(a[0] - off[0], a[1] - off[1]), (b[0] - off[0], b[1] - off[1]),
               (b[0] + off[0], b[1] + off[1]), (a[0] + off[0], a[1] + off[1])]
    scene = Scene(SIZE, SIZE, np.array([[corners[0], corners[1], corners[2]], [corners[0], corners[2], corners[3]]]))
    counts = exact_coverage(scene, Convention(sample=sample, tie=tie)).counts(SIZE, SIZE)
    assert counts.max(initial=0) <= 1
    assert (_mask(parallelogram_spans([a], [b], w, sample, tie, width=SIZE, height=SIZE)) == counts).all()


@QUICK
@given(lattice_point(), st.sampled_from([(1, 0), (0, 1), (3, 1), (-4, 3), (1, 1), (2, -1), (-1, -3), (-1, 1)]),
       st.integers(1, 4), st.integers(1, 4), widths, samples, st.sampled_from(TIE_RULES))
def test_parallelogram_collinear_pieces_partition(a, direction, k, m, w, sample, tie) -> None:
    """a -> b and b -> c on one line cover exactly the samples of a -> c, each once: the
    shared end (parallel to the minor axis) gives its samples to one piece by the tie rule."""
    d = (direction[0] / 4, direction[1] / 4)
    b = (a[0] + k * d[0], a[1] + k * d[1])
    c = (b[0] + m * d[0], b[1] + m * d[1])
    counts = _mask(parallelogram_spans([a, b], [b, c], w, sample, tie, width=SIZE, height=SIZE))
    whole = _mask(parallelogram_spans([a], [c], w, sample, tie, width=SIZE, height=SIZE))
    assert counts.max(initial=0) <= 1
    assert (counts == whole).all()


@QUICK
@given(lattice_point(), st.integers(-3 * SIZE, 3 * SIZE), st.booleans(), widths, samples, st.sampled_from(TIE_RULES))
def test_axis_aligned_parallelogram_is_the_rectangle(a, length, horizontal, w, sample, tie) -> None:
    """Along an axis the minor axis is the segment's normal: the parallelogram is the rectangle."""
    b = (a[0] + length / 4, a[1]) if horizontal else (a[0], a[1] + length / 4)
    _same(parallelogram_spans([a], [b], w, sample, tie, width=SIZE, height=SIZE),
          rectangle_spans([a], [b], w, sample, tie, width=SIZE, height=SIZE))


def test_slope_one_is_x_major_and_taller_rectangles_part_the_rules() -> None:
    """|dy| = |dx| is x-major (slope in [-1, 1]): the ends are vertical, and each column is
    cut 1 px tall, where the rectangle of width 1 is sqrt(2) tall: the centres 0.6 px
    below the line are the rectangle's, not the parallelogram's."""
    a, b = [[1.0, 1.6]], [[6.0, 6.6]]
    para = {(x, y) for _, x, y in _pixels(parallelogram_spans(a, b, 1.0, width=SIZE, height=SIZE))}
    assert sorted(para) == [(x, x + 1) for x in range(1, 6)]
    rect = {(x, y) for _, x, y in _pixels(rectangle_spans(a, b, 1.0, width=SIZE, height=SIZE))}
    assert para < rect and (1, 1) in rect


@QUICK
@given(st.integers(8, 40), st.integers(-40, 40), st.integers(0, 31), st.integers(0, 31), samples, st.sampled_from(TIE_RULES))
def test_width_one_draws_one_sample_per_column(run, rise, fx, fy, sample, tie) -> None:
    """Width 1, x-major: each column's sample whose x lies strictly between the ends is
    drawn exactly once (the column is cut exactly 1 px tall, half open by the tie rule),
    as a Bresenham line draws one pixel per step; none beyond the ends."""
    if abs(rise) > run:
        return
    a = (4.0 + fx / 32, 20.0 + fy / 32)
    b = (a[0] + run / 2, a[1] + rise / 2)
    size = 48
    got = _mask(parallelogram_spans([a], [b], 1.0, sample, tie, width=size, height=size), size)
    for i in range(size):
        x = i + sample[0]
        if a[0] < x < b[0]:
            assert got[:, i].sum() == 1
        elif x < a[0] or x > b[0]:
            assert got[:, i].sum() == 0


def test_far_segments_go_to_the_reference_through_line_coverage() -> None:
    scene = LineScene.from_strips(SIZE, SIZE, [[[0.5, 0.5], [1e200, 3.5]], [[0.5, 2.5], [6.5, 5.5]]])
    got = line_coverage(scene, Convention(line="parallelogram"))
    near = parallelogram_spans([[0.5, 2.5]], [[6.5, 5.5]], width=SIZE, height=SIZE)
    far = parallelogram_spans_rational([[0.5, 0.5]], [[1e200, 3.5]], width=SIZE, height=SIZE)
    expected = {(0, x, y) for _, x, y in _pixels(far)} | {(1, x, y) for _, x, y in _pixels(near)}
    assert _pixels((got.primitive, got.y, got.x0, got.x1)) == expected


def test_parallelogram_arguments_and_range() -> None:
    a, b = np.array([[1.0, 1.0], [2.0, 2.0]]), np.array([[4.0, 1.0], [2.0, 2.0]])
    assert parallelogram_spans(a[1:], b[1:], 1.0, width=SIZE, height=SIZE)[0].size == 0  # no length
    with pytest.raises(ValueError, match="line_width of segment 1"):
        parallelogram_spans(a, b, [1.0, 0.0], width=SIZE, height=SIZE)
    with pytest.raises(ValueError, match="segment 0"):
        parallelogram_spans(a, b, [2.0**151, 1.0], width=SIZE, height=SIZE)
    with pytest.raises(ValueError, match="tie"):
        parallelogram_spans(a, b, 1.0, tie="middle", width=SIZE, height=SIZE)  # type: ignore[arg-type]


# -- the rule in the convention, and a line rule's own snap rounding -------------------------------


def test_line_rule_parallelogram_and_snap_rounding() -> None:
    rule = LineRule("parallelogram", snap_rounding="half-away")
    assert rule.last_pixel is False and rule.undefined_width(3.0) == "" and rule.undefined_width(0.5) == ""
    assert repr(LineRule()) == ("LineRule(rule='diamond-exit', last_pixel=False, rounding='nearest-even', ties='step', "
                                "direction='as-given', wide='none')")
    assert eval(repr(rule)) == rule  # noqa: S307 - the repr is the constructor call
    with pytest.raises(ValueError, match="snap_rounding"):
        LineRule(snap_rounding="up")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="diamond-exit option"):
        LineRule("parallelogram", wide="replicate")
    for rounding in SNAP_ROUNDINGS:
        c = Convention(subpixel_bits=2, line=LineRule("parallelogram", snap_rounding=rounding))
        assert c.for_lines().snap_rounding == rounding and c.for_lines().line == LineRule("parallelogram")
        assert c.for_lines().for_lines() == c.for_lines()
    plain = Convention(line="parallelogram")
    assert plain.for_lines() is plain


@pytest.mark.parametrize("rule", ["parallelogram", "diamond-exit", "bresenham", "rectangle"])
def test_line_snap_rounding_overrides_the_triangles(rule) -> None:
    """End points half a step of the 2**-2 grid off it: the line rule's own rounding snaps
    them, not the convention's (the triangles')."""
    ends = [[[0.375, 1.625], [6.625, 4.375]], [[1.125, 0.875], [2.875, 6.625]], [[4.625, 6.125], [0.125, 2.375]]]
    scene = LineScene.from_strips(SIZE, SIZE, ends)
    for line_rounding in SNAP_ROUNDINGS:
        for triangle_rounding in SNAP_ROUNDINGS:
            mixed = Convention(subpixel_bits=2, snap_rounding=triangle_rounding,
                               line=LineRule(rule, snap_rounding=line_rounding))
            same = Convention(subpixel_bits=2, snap_rounding=line_rounding, line=LineRule(rule))
            assert line_coverage(scene, mixed).counts(SIZE, SIZE).tolist() == \
                line_coverage(scene, same).counts(SIZE, SIZE).tolist()


def test_identify_sees_the_full_width_known_bad_is_no_parallelogram() -> None:
    """The known-bad drawer that puts the sides a whole width (not half) off the segment:
    no candidate explains it, the parallelogram's residual is its second pixel per column."""
    from harness.identify.fingerprint import identify
    from tests.known_bad.lines import FullWidthOffset

    fp = identify(FullWidthOffset())
    assert not fp.exact and fp.residual > 0 and fp.line_fit is not None, fp.card()
    assert "best guess only" in fp.facts["lines"]
    assert dict(fp.line_fit.rule_scores)["parallelogram"] > 0
