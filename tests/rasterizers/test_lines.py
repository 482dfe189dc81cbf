"""The reference line rasterizers (rasterizers.lines) against the exact line oracle: on every
quick line case each takes, on hypothesis segments (lattice and float), and on their error
paths (Unsupported, refusals naming the segment, non-finite segments)."""

from __future__ import annotations

from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from cases.lines import line_cases
from harness.contract.case import Case
from harness.contract.conventions import Convention, LineRule
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import MAX_VIEWPORT, LineScene, Scene, Unsupported
from harness.oracle.coverage import exact_coverage
from rasterizers.lines import BRESENHAM_LIMIT, DDA_LIMIT, RECTANGLE_LIMIT, BresenhamLines, DiamondExitDDA, RectangleLines

SIZE = 8
QUICK = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])

LineReference = BresenhamLines | DiamondExitDDA | RectangleLines
REFERENCES: list[LineReference] = [BresenhamLines(), DiamondExitDDA(), RectangleLines()]
VARIANTS: list[LineReference] = [BresenhamLines("floor", "stay", last_pixel=False), BresenhamLines("half-away"),
                                 DiamondExitDDA(last_pixel=True),
            RectangleLines("bottom-right"), RectangleLines("top-left-y-first")]


@pytest.fixture(scope="module")
def quick_cases() -> list[Case]:
    return line_cases(0)


def _deviations(rasterizer: Any, cases: list[Case], convention: Convention | None = None) -> list[str]:
    """The ids of the cases where the rasterizer differs from the oracle of ``convention``
    (its own by default), refuses a segment the case does not call refusable, or fails."""
    convention = convention or rasterizer.convention
    wrong = []
    for case in cases:
        try:
            coverage = rasterizer.rasterize(case.scene)
        except Unsupported:
            continue
        except ValueError as error:
            if not any(f"segment {k}" in str(error) for k in case.refusable):
                wrong.append(f"{case.id}: {error}")
            continue
        if coverage != exact_coverage(case.scene, convention):
            wrong.append(case.id)
    return wrong


# -- the quick cases ---------------------------------------------------------------------------


@pytest.mark.parametrize("rasterizer", REFERENCES, ids=lambda r: r.name)
def test_reference_equals_the_oracle_on_every_quick_line_case(rasterizer, quick_cases):
    assert _deviations(rasterizer, quick_cases) == []


@pytest.mark.parametrize("rasterizer", VARIANTS, ids=lambda r: r.name)
def test_variants_equal_the_oracle_of_their_convention(rasterizer, quick_cases):
    lattice = [c for c in quick_cases if c.lattice or c.family == "line-degenerate"]
    assert _deviations(rasterizer, lattice) == []


@pytest.mark.parametrize("wrong, convention", [
    (BresenhamLines(ties="stay"), BresenhamLines().convention),  # ties the other way
    (BresenhamLines(last_pixel=False), BresenhamLines().convention),  # off by one at the end
    (BresenhamLines(rounding="floor"), BresenhamLines().convention),  # end points truncated
    (DiamondExitDDA(last_pixel=True), DiamondExitDDA().convention),  # the end pixel drawn
    (RectangleLines("bottom-right"), RectangleLines().convention),  # the other tie rule
], ids=["ties", "last-pixel", "rounding", "diamond-last-pixel", "rectangle-ties"])
def test_the_comparison_catches_another_rule(wrong, convention, quick_cases):
    # the comparison above is not vacuous: a drawer of a neighbouring rule fails it
    lattice = [c for c in quick_cases if c.lattice]
    assert _deviations(wrong, lattice, convention)


def test_references_take_lines_only_and_declare_their_rule():
    for rasterizer in REFERENCES + VARIANTS:
        assert isinstance(rasterizer, Rasterizer)
        assert rasterizer.scene_kinds == ("lines",) and rasterizer.interpolates is False
    assert [r.name for r in REFERENCES] == ["bresenham_lines", "diamond_exit_dda", "rectangle_lines"]
    assert BresenhamLines().convention == Convention(line=LineRule("bresenham"))
    assert DiamondExitDDA().convention == Convention(subpixel_bits=8, line=LineRule())
    assert RectangleLines().convention == Convention(subpixel_bits=8, line=LineRule("rectangle"))
    assert len({r.name for r in REFERENCES + VARIANTS}) == len(REFERENCES + VARIANTS)


# -- hypothesis: lattice end points (ties on purpose) and floats ----------------------------------


@st.composite
def lattice_segments(draw):
    """Up to 4 segments with end points on the 1/2, 1/4, 1/8 or 1/256 lattice, in and around
    an 8 x 8 viewport."""
    den = draw(st.sampled_from([2, 4, 8, 256]))
    coordinate = st.integers(-2 * den, (SIZE + 2) * den).map(lambda k: k / den)
    n = draw(st.integers(1, 4))
    ends = draw(st.lists(st.tuples(coordinate, coordinate, coordinate, coordinate), min_size=n, max_size=n))
    array = np.array(ends, dtype=np.float64)
    return array[:, :2], array[:, 2:]


@st.composite
def float_segments(draw):
    """Up to 4 float segments, some short (within a pixel), some long."""
    coordinate = st.floats(-3.0, SIZE + 3.0, allow_nan=False)
    n = draw(st.integers(1, 4))
    a = np.array(draw(st.lists(st.tuples(coordinate, coordinate), min_size=n, max_size=n)))
    offset = st.floats(-1.0, 1.0, allow_nan=False) if draw(st.booleans()) else st.floats(-12.0, 12.0, allow_nan=False)
    d = np.array(draw(st.lists(st.tuples(offset, offset), min_size=n, max_size=n)))
    return a, a + d


def _agree(a, b, line_width: float = 1.0) -> None:
    scene = LineScene.from_segments(SIZE, SIZE, a, b)
    width_1: list[BresenhamLines | DiamondExitDDA] = [BresenhamLines(), BresenhamLines("half-away", "stay"), DiamondExitDDA(),
                                                      DiamondExitDDA(True)]
    for rasterizer in width_1:
        assert rasterizer.rasterize(scene) == exact_coverage(scene, rasterizer.convention), rasterizer.name
    wide = scene.with_line_width(line_width)
    for rectangles in [RectangleLines(), RectangleLines("bottom-left-y-first")]:
        assert rectangles.rasterize(wide) == exact_coverage(wide, rectangles.convention), rectangles.name


@QUICK
@given(lattice_segments(), st.sampled_from([1.0, 2.5, 0.25, 2.0, 1.5]))
# a tie of Bresenham's decision variable; lines through diamond corners; a zero-length segment
@example((np.array([[0.5, 0.5]]), np.array([[4.5, 2.5]])), 1.0)
@example((np.array([[0.0, 2.0], [1.5, 0.0]]), np.array([[7.0, 2.0], [5.5, 4.0]])), 1.0)
@example((np.array([[3.5, 3.0]]), np.array([[3.5, 3.0]])), 1.0)
# samples on the rectangle's sides (3-4-5 directions), on its caps and corners
@example((np.array([[0.5, 0.5], [1.5, 2.0]]), np.array([[3.5, 4.5], [5.5, 5.0]])), 2.0)
@example((np.array([[0.5, 1.0]]), np.array([[3.5, 1.0]])), 1.0)
def test_references_equal_the_oracle_on_lattice_segments(segments, line_width):
    _agree(segments[0], segments[1], line_width)


@QUICK
@given(float_segments(), st.floats(0.05, 4.0))
def test_references_equal_the_oracle_on_float_segments(segments, line_width):
    _agree(segments[0], segments[1], line_width)


# -- errors, refusals and bad input ---------------------------------------------------------------


def test_width_1_rules_do_not_draw_wide_lines_and_nobody_draws_triangles():
    wide = LineScene.from_segments(8, 8, [[1, 1]], [[6, 3]], line_width=2.5)
    for width_1 in (BresenhamLines(), DiamondExitDDA()):
        with pytest.raises(Unsupported, match="width 1 only"):
            width_1.rasterize(wide)
    assert RectangleLines().rasterize(wide).counts(8, 8).sum() > 0
    triangles = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
    for rasterizer in REFERENCES:
        with pytest.raises(Unsupported, match="line scenes only"):
            rasterizer.rasterize(triangles)


@pytest.mark.parametrize("rasterizer, limit", [(BresenhamLines(), BRESENHAM_LIMIT), (DiamondExitDDA(), DDA_LIMIT),
                                               (RectangleLines(), RECTANGLE_LIMIT)], ids=lambda v: getattr(v, "name", ""))
def test_coordinates_beyond_the_range_are_refused_naming_the_segment(rasterizer, limit):
    within = LineScene.from_segments(16, 16, [[-limit, 3.5], [1.0, 1.0]], [[limit, 12.5], [5.0, 9.0]])
    assert rasterizer.rasterize(within) == exact_coverage(within, rasterizer.convention)  # the limit itself is drawn
    beyond = LineScene.from_segments(16, 16, [[1.0, 1.0], [0.5, 0.5], [2.0, 2.0]], [[5.0, 9.0], [2 * limit, 3.0], [1e200, 1.0]])
    with pytest.raises(ValueError, match=r"segment 1 has a coordinate beyond"):
        rasterizer.rasterize(beyond)


def test_rectangles_draw_every_width_exactly():
    scene = LineScene.from_segments(8, 8, [[1, 1]], [[6, 3]], line_width=float(MAX_VIEWPORT))  # the widest a scene takes
    assert RectangleLines().rasterize(scene) == exact_coverage(scene, RectangleLines().convention)
    i, j = np.meshgrid(np.arange(8), np.arange(8))  # so wide every sample between the caps (no ties on them)
    assert RectangleLines().rasterize(scene).counts(8, 8).tolist() == ((5 * i + 2 * j > 3.5)
                                                                       & (5 * i + 2 * j < 32.5)).astype(int).tolist()
    tiny = scene.with_line_width(1e-300)  # a hair: only samples exactly on the segment
    hair = LineScene.from_segments(8, 8, [[0.5, 0.5]], [[6.5, 6.5]], line_width=1e-300)
    assert RectangleLines().rasterize(tiny) == exact_coverage(tiny, RectangleLines().convention)
    assert RectangleLines().rasterize(hair).counts(8, 8).sum() == 6


# Pythagorean directions: a sample at distance 5s (or 13s, 17s) from the segment's line lies
# exactly on a side of width 10s (26s, 34s), with dyadic end points far off screen.
_TRIPLES = [(3, 4, 5), (5, 12, 13), (8, 15, 17)]


@st.composite
def far_tie_segments(draw):
    """(a, b, width): one segment with end points up to ~2**21 px away whose side passes
    exactly through a pixel centre of the 8x8 viewport."""
    u, v, h = draw(st.sampled_from(_TRIPLES))
    if draw(st.booleans()):
        u, v = v, u
    u, v = u * draw(st.sampled_from([1, -1])), v * draw(st.sampled_from([1, -1]))
    s = draw(st.sampled_from([0.25, 0.5, 1.0, 2.0**-6]))
    side = draw(st.sampled_from([1, -1]))
    q = np.array([draw(st.integers(0, SIZE - 1)) + 0.5, draw(st.integers(0, SIZE - 1)) + 0.5])
    foot = q - side * s * np.array([v, -u])  # the normal (v, -u) has length h
    reach = int(RECTANGLE_LIMIT) // (2 * max(abs(u), abs(v)))
    t0, t1 = draw(st.integers(1, reach)), draw(st.integers(0, reach))
    return (foot - t0 * np.array([u, v]))[None], (foot + t1 * np.array([u, v]))[None], 2.0 * h * s


@QUICK
@given(far_tie_segments())
def test_rectangles_equal_the_oracle_on_far_segments_through_ties(segment):
    a, b, width = segment
    scene = LineScene.from_segments(SIZE, SIZE, a, b, line_width=width)
    for rasterizer in [RectangleLines(), RectangleLines("bottom-left-y-first")]:
        assert rasterizer.rasterize(scene) == exact_coverage(scene, rasterizer.convention), rasterizer.name


@QUICK
@given(st.integers(-2**29 + 2**12, 2**29 - 2**12), st.integers(-2**29 + 2**12, 2**29 - 2**12), st.integers(0, SIZE - 1),
       st.integers(0, SIZE - 1), st.integers(-2, 2))
def test_rectangles_decide_samples_within_an_ulp_of_a_side(ax, ay, i, j, ulps):
    # a far end point a (1/256 px grid), b = a's mirror through the viewport's centre; the
    # width is the float nearest twice the distance of the sample (i, j) from the line,
    # moved by a few ulps: the two sides of the inequality agree to ~2**-53, past any float test
    a = np.array([[ax / 256.0, ay / 256.0]])
    b = np.array([[SIZE - ax / 256.0, SIZE - ay / 256.0 + 1.0]])
    (dx, dy), (px, py) = (b - a)[0], (np.array([i + 0.5, j + 0.5]) - a[0])
    cross, length = Fraction(dx) * Fraction(py) - Fraction(dy) * Fraction(px), Fraction(dx) ** 2 + Fraction(dy) ** 2
    assume(length > 0)
    with localcontext() as context:
        context.prec = 60
        width = float(2 * abs(Decimal(cross.numerator) / Decimal(cross.denominator)) / (Decimal(length.numerator).sqrt()
                                                                                            / Decimal(length.denominator).sqrt()))
    for _ in range(abs(ulps)):
        width = np.nextafter(width, np.inf if ulps > 0 else 0.0)
    assume(0.0 < width <= MAX_VIEWPORT)
    scene = LineScene.from_segments(SIZE, SIZE, a, b, line_width=float(width))
    for rasterizer in [RectangleLines(), RectangleLines("bottom-right")]:
        assert rasterizer.rasterize(scene) == exact_coverage(scene, rasterizer.convention), rasterizer.name


@QUICK
@given(st.tuples(st.floats(-2.0**21, 2.0**21), st.floats(-2.0**21, 2.0**21)), st.floats(0.5, SIZE - 0.5),
       st.floats(0.5, SIZE - 0.5), st.floats(0.0, 1.0), st.floats(0.01, 4.0))
def test_rectangles_equal_the_oracle_on_far_float_segments(far, x, y, along, width):
    # a segment from far away through (x, y) on screen, ending beyond it or short of it
    a = np.array([far])
    b = np.clip(a + (np.array([[x, y]]) - a) * (1.0 + along), -2.0**21, 2.0**21)
    scene = LineScene.from_segments(SIZE, SIZE, a, b, line_width=width)
    assert RectangleLines().rasterize(scene) == exact_coverage(scene, RectangleLines().convention)


def test_non_finite_segments_cover_nothing_and_the_others_are_drawn():
    nan, inf = np.nan, np.inf
    scene = LineScene.from_strips(8, 8, [[[0.5, 0.5], [6.5, 2.5]], [[nan, 1.0], [3.0, 3.0], [6.5, 6.5]],
                                         [[1.0, 7.0], [inf, -inf]]])
    for rasterizer in REFERENCES + VARIANTS:
        coverage = rasterizer.rasterize(scene)
        assert set(coverage.primitive.tolist()) == {0, 2}, rasterizer.name
        assert coverage == exact_coverage(scene, rasterizer.convention)


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="rounding"):
        BresenhamLines(rounding="up")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="ties"):
        BresenhamLines(ties="random")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="tie"):
        RectangleLines("middle")  # type: ignore[arg-type]


def test_spans_come_sorted_one_per_row():
    # rows ascending per segment, whichever way the segment runs, one span per row
    a = np.array([[12.5, 1.5], [1.5, 12.5], [14.0, 14.0], [2.0, 1.0], [13.7, 0.3]])
    b = np.array([[1.5, 12.5], [12.5, 1.5], [0.0, 0.0], [14.0, 3.0], [0.2, 14.1]])
    scene = LineScene.from_segments(16, 16, a, b)
    for rasterizer in REFERENCES:
        coverage = rasterizer.rasterize(scene)
        keys = list(zip(coverage.primitive.tolist(), coverage.y.tolist()))
        assert keys == sorted(set(keys)), rasterizer.name
