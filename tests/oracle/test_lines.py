"""Exact oracles for aliased lines (harness.oracle.lines): each fast oracle against its brute-force
rational reference, and the properties the rules promise."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from harness.contract.conventions import BRESENHAM_ROUNDINGS, BRESENHAM_TIES, TIE_RULES, BresenhamTies, Convention
from harness.contract.scenes import Scene
from harness.oracle.bresenham_lines import _round_pixel_rational, bresenham_spans, bresenham_spans_rational, end_point_pixels
from harness.oracle.coverage import exact_coverage
from harness.oracle.diamond_lines import _in_test_area_rational, diamond_exit_spans, diamond_exit_spans_rational
from harness.oracle.rectangle_lines import RECT_SAFE_MIN, rectangle_spans, rectangle_spans_rational

SIZE = 8
QUICK = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
HALF = Fraction(1, 2)


def _same(a, b) -> None:  # type: ignore[no-untyped-def]
    assert [x.tolist() for x in a] == [x.tolist() for x in b]


def _pixels(spans) -> set[tuple[int, int, int]]:  # type: ignore[no-untyped-def]
    """(segment, x, y) of every covered pixel."""
    return {(int(s), x, int(y)) for s, y, x0, x1 in zip(*spans) for x in range(int(x0), int(x1))}


def _sorted(spans) -> None:  # type: ignore[no-untyped-def]
    s, y, x0, x1 = (v.tolist() for v in spans)
    keys = list(zip(s, y, x0))
    assert keys == sorted(keys) and all(u < v for u, v in zip(x0, x1))


# -- strategies: end points on a 1/2, 1/4 or 1/8 lattice (ties on purpose), or floats -----------

def _lattice(den: int):  # type: ignore[no-untyped-def]
    return st.integers(-den, (SIZE + 1) * den).map(lambda k: k / den)


@st.composite
def lattice_point(draw):  # type: ignore[no-untyped-def]
    den = draw(st.sampled_from([2, 4, 8]))
    return draw(_lattice(den)), draw(_lattice(den))


@st.composite
def segment(draw):  # type: ignore[no-untyped-def]
    """One segment, of a kind chosen to hit the rules' ties: end points anywhere on the
    lattice, 45-degree lines (along diamond edges), horizontal and vertical lines (through
    diamond corners), zero length, end points on diamond corners or pixel centres, floats."""
    kind = draw(st.sampled_from(["lattice", "diagonal", "axis", "zero", "corner", "centre", "float"]))
    a = draw(lattice_point())
    if kind == "lattice":
        b = draw(lattice_point())
    elif kind == "diagonal":
        t = draw(st.integers(-4 * SIZE, 4 * SIZE)) / 4
        b = (a[0] + t, a[1] + draw(st.sampled_from([-1, 1])) * t)
    elif kind == "axis":
        other = draw(lattice_point())
        b = (a[0], other[1]) if draw(st.booleans()) else (other[0], a[1])
    elif kind == "zero":
        b = a
    elif kind in ("corner", "centre"):
        cell = st.integers(-1, SIZE)

        def place(i: int, j: int, which: int) -> tuple[float, float]:
            if kind == "centre":
                return i + 0.5, j + 0.5
            return ((i + 0.5, j), (i + 1.0, j + 0.5), (i + 0.5, j + 1.0), (i, j + 0.5))[which]

        a = place(draw(cell), draw(cell), draw(st.integers(0, 3)))
        b = place(draw(cell), draw(cell), draw(st.integers(0, 3)))
    else:
        # any float, but none so tiny that the rectangles' range (2**-150) refuses it
        coordinate = st.floats(-1.0, SIZE + 1.0, allow_nan=False, allow_infinity=False).map(
            lambda v: 0.0 if abs(v) < RECT_SAFE_MIN else v)
        a = (draw(coordinate), draw(coordinate))
        b = (draw(coordinate), draw(coordinate))
    return a, b


segments = st.lists(segment(), min_size=1, max_size=3).map(
    lambda pairs: (np.array([p[0] for p in pairs], dtype=np.float64), np.array([p[1] for p in pairs], dtype=np.float64)))


def is_x_major(a: tuple[float, float], b: tuple[float, float]) -> bool:
    return abs(Fraction(b[1]) - Fraction(a[1])) <= abs(Fraction(b[0]) - Fraction(a[0]))


def _holder(p: tuple[float, float], y_major: bool, width: int, height: int) -> tuple[int, int] | None:
    """The pixel whose test area holds p, from the spec-written definition."""
    px, py = Fraction(p[0]), Fraction(p[1])
    found = [(i, j) for j in range(height) for i in range(width)
             if _in_test_area_rational(px, py, i + HALF, j + HALF, y_major)]
    assert len(found) <= 1  # test areas are disjoint
    return found[0] if found else None


def _inside(seg):  # type: ignore[no-untyped-def]
    """The segment moved by whole pixels (ties kept) two pixels inside a square viewport
    that holds all of it: (a, b, size)."""
    (ax, ay), (bx, by) = seg
    dx, dy = 2 - np.floor(min(ax, bx)), 2 - np.floor(min(ay, by))
    a, b = (ax + dx, ay + dy), (bx + dx, by + dy)
    return a, b, int(np.ceil(max(a + b))) + 3


# -- diamond exit ------------------------------------------------------------------------------


@QUICK
@given(segments, st.booleans())
@example((np.array([[0.5, 0.5]]), np.array([[4.5, 2.5]])), False)  # a tie at a bottom corner
@example((np.array([[0.5, 1.0]]), np.array([[5.5, 1.0]])), False)  # along the bottom corners of row 0
@example((np.array([[1.0, 0.5]]), np.array([[4.0, 3.5]])), True)  # 45 degrees along lower-right edges
@example((np.array([[2.0, 0.5]]), np.array([[2.0, 5.5]])), False)  # y-major through right corners
@example((np.array([[3.0, 2.5]]), np.array([[3.25, 5.0]])), False)  # y-major, starting on a right corner
def test_diamond_exit_matches_rational(segs, last_pixel) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    fast = diamond_exit_spans(a, b, SIZE, SIZE, last_pixel)
    _same(fast, diamond_exit_spans_rational(a, b, SIZE, SIZE, last_pixel))
    _sorted(fast)


@QUICK
@given(segment())
def test_diamond_exit_one_pixel_per_major_step(seg) -> None:  # type: ignore[no-untyped-def]
    """With the end pixel drawn, an x-major segment draws exactly one pixel in every column
    whose centre it reaches, at most one anywhere, in a contiguous run of columns (y-major:
    rows); the exit rule removes at most that end pixel -- the one whose test area holds b."""
    a, b, size = _inside(seg)
    x_major = is_x_major(a, b)
    every = {(x, y) for _, x, y in _pixels(diamond_exit_spans([a], [b], size, size, last_pixel=True))}
    drawn = {(x, y) for _, x, y in _pixels(diamond_exit_spans([a], [b], size, size))}
    major = [p[0] if x_major else p[1] for p in every]
    lo, hi = sorted((a[0], b[0]) if x_major else (a[1], b[1]))
    crossed = [k for k in range(size) if lo <= k + 0.5 <= hi]
    assert len(major) == len(set(major))  # one pixel per major step
    assert set(crossed) <= set(major)  # every step the segment spans has one
    assert not major or sorted(major) == list(range(min(major), max(major) + 1))
    assert len(crossed) <= len(major) <= len(crossed) + 2  # plus the end cells it starts or ends in
    end = _holder(b, not x_major, size, size)
    assert every - drawn == ({end} if end in every else set())


@QUICK
@given(lattice_point(), lattice_point(), lattice_point())
@example((1.0, 1.0), (3.5, 2.5), (6.0, 2.0))  # the shared vertex at a pixel centre
@example((1.0, 1.0), (3.5, 2.0), (6.0, 5.0))  # at a bottom corner
def test_diamond_exit_strip_draws_shared_vertex_once(a, b, c) -> None:  # type: ignore[no-untyped-def]
    """A polyline a -> b -> c: the first segment never draws the pixel whose test area holds
    b; the second draws it exactly when it leaves it, i.e. unless c is inside too."""
    first = {(x, y) for _, x, y in _pixels(diamond_exit_spans([a], [b], SIZE, SIZE))}
    second = {(x, y) for _, x, y in _pixels(diamond_exit_spans([b], [c], SIZE, SIZE))}
    f1 = _holder(b, not is_x_major(a, b), SIZE, SIZE)
    f2 = _holder(b, not is_x_major(b, c), SIZE, SIZE)
    assert f1 is None or f1 not in first
    if f2 is not None:
        inside = _in_test_area_rational(Fraction(c[0]), Fraction(c[1]), f2[0] + HALF, f2[1] + HALF, not is_x_major(b, c))
        assert (f2 in second) == (not inside)
        if f1 == f2 and not inside:  # same test area for both: drawn exactly once
            assert (f2 in first) + (f2 in second) == 1


@QUICK
@given(segment())
def test_diamond_exit_reversal_changes_only_end_pixels(seg) -> None:  # type: ignore[no-untyped-def]
    """The rule predicts forward = M - {f_b} and reversed = M - {f_a}, M the pixels whose test
    areas the segment meets and f_p the pixel whose test area holds p: reversal swaps which
    end pixel is left out, and with the end pixel drawn it changes nothing."""
    a, b = seg
    y_major = not is_x_major(a, b)
    met = _pixels(diamond_exit_spans([a], [b], SIZE, SIZE, last_pixel=True))
    assert _pixels(diamond_exit_spans([b], [a], SIZE, SIZE, last_pixel=True)) == met
    f_a, f_b = (_holder(p, y_major, SIZE, SIZE) for p in (a, b))
    forward = _pixels(diamond_exit_spans([a], [b], SIZE, SIZE))
    backward = _pixels(diamond_exit_spans([b], [a], SIZE, SIZE))
    assert forward == met - ({(0, *f_b)} if f_b else set())
    assert backward == met - ({(0, *f_a)} if f_a else set())


@QUICK
@given(st.tuples(st.integers(-1, SIZE), st.integers(-1, SIZE)), st.tuples(st.integers(-1, SIZE), st.integers(-1, SIZE)),
       st.booleans())
def test_diamond_exit_between_pixel_centres_is_half_open_bresenham(p, q, last_pixel) -> None:  # type: ignore[no-untyped-def]
    """GL: "When pa and pb lie on fragment centers, this characterization of fragments
    reduces to Bresenham's algorithm with one modification: lines produced in this
    description are half-open". The D3D11 test area breaks ties towards the smaller minor
    coordinate (bottom corners in, x-major; right corners in, y-major): Bresenham's ties
    "stay" when the minor coordinate grows, "step" when it shrinks."""
    a, b = (p[0] + 0.5, p[1] + 0.5), (q[0] + 0.5, q[1] + 0.5)
    x_major = abs(q[0] - p[0]) >= abs(q[1] - p[1])
    minor = (q[1] - p[1]) if x_major else (q[0] - p[0])
    ties: BresenhamTies = "stay" if minor > 0 else "step"
    _same(diamond_exit_spans([a], [b], SIZE, SIZE, last_pixel),
          bresenham_spans([a], [b], SIZE, SIZE, ties=ties, last_pixel=last_pixel))


def test_diamond_exit_zero_length_and_non_finite() -> None:
    a = np.array([[2.5, 2.5], [np.nan, 1.0], [1.0, 1.0]])
    b = np.array([[2.5, 2.5], [3.0, 3.0], [np.inf, 1.0]])
    assert diamond_exit_spans(a, b, SIZE, SIZE)[0].size == 0  # never exits; NaN/inf: nothing
    s, y, x0, x1 = diamond_exit_spans(a, b, SIZE, SIZE, last_pixel=True)
    assert (s.tolist(), y.tolist(), x0.tolist(), x1.tolist()) == ([0], [2], [2], [3])


def test_diamond_exit_range_is_checked() -> None:
    a = np.array([[0.5, 0.5], [0.5, 0.5]])
    for bad in (1e300, 1e-300):
        b = np.array([[3.0, 3.0], [bad, 3.0]])
        with pytest.raises(ValueError, match="segment 1"):
            diamond_exit_spans(a, b, SIZE, SIZE)
        diamond_exit_spans_rational(a, b, SIZE, SIZE)  # the reference takes any finite float
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        diamond_exit_spans(np.zeros((2, 3)), np.zeros((2, 3)), SIZE, SIZE)


def test_diamond_exit_far_end_points_and_near_ties() -> None:
    """Far-away end points (the float estimate of the minor cell is useless there, the
    exact search is not) and end points a hair off a corner."""
    a = np.array([[-1e120, 0.5], [0.5 - 2.0**-60, 1.0], [2.5, 0.0]])
    b = np.array([[1e120, 3.75], [6.5, 1.0 + 2.0**-60], [2.5 + 2.0**-52, 1e100]])
    _same(diamond_exit_spans(a, b, SIZE, SIZE), diamond_exit_spans_rational(a, b, SIZE, SIZE))


# -- Bresenham ---------------------------------------------------------------------------------


@QUICK
@given(segments, st.sampled_from(BRESENHAM_ROUNDINGS), st.sampled_from(BRESENHAM_TIES), st.booleans())
def test_bresenham_matches_rational(segs, rounding, ties, last_pixel) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    fast = bresenham_spans(a, b, SIZE, SIZE, rounding, ties, last_pixel)
    _same(fast, bresenham_spans_rational(a, b, SIZE, SIZE, rounding, ties, last_pixel))
    _sorted(fast)


@QUICK
@given(segment(), st.sampled_from(BRESENHAM_ROUNDINGS), st.sampled_from(BRESENHAM_TIES))
def test_bresenham_is_eight_connected_one_pixel_per_step(seg, rounding, ties) -> None:  # type: ignore[no-untyped-def]
    a, b, size = _inside(seg)
    s, y, x0, x1 = bresenham_spans([a], [b], size, size, rounding, ties)
    pts = sorted((x, int(r)) for r, u, v in zip(y, x0, x1) for x in range(int(u), int(v)))
    (p0,), (p1,) = (sorted(_pixels(bresenham_spans([p], [p], size, size, rounding))) for p in (a, b))
    ends = (p0[1:], p1[1:])
    k = max(abs(ends[1][0] - ends[0][0]), abs(ends[1][1] - ends[0][1]))
    assert len(pts) == k + 1 and ends[0] in pts and ends[1] in pts
    x_major = abs(ends[1][0] - ends[0][0]) >= abs(ends[1][1] - ends[0][1])
    walk = sorted(pts, key=lambda p: p[0] if x_major else p[1])
    for u, v in zip(walk, walk[1:]):  # 8-connected, one step of the major axis each
        major, minor = (v[0] - u[0], v[1] - u[1]) if x_major else (v[1] - u[1], v[0] - u[0])
        assert major == 1 and abs(minor) <= 1
    # reversing the walk turns its ties round
    other: BresenhamTies = "stay" if ties == "step" else "step"
    _same(bresenham_spans([b], [a], size, size, rounding, other), (s, y, x0, x1))


def test_bresenham_rounding_of_end_points() -> None:
    """p - 1/2 rounded to nearest (ties to even, or away from zero), or p floored: the
    pixel holding p, ties where p is on a pixel boundary; the same in both references."""
    p = [2.0, 3.0, -0.0, 0.7, -1.0, 5.999, 1.0]
    expect = {"nearest-even": [2, 2, 0, 0, -2, 5, 0], "half-away": [2, 3, -1, 0, -2, 5, 1],
              "floor": [2, 3, 0, 0, -1, 5, 1]}
    for rounding, pixels in expect.items():
        assert end_point_pixels(np.array(p), rounding).astype(int).tolist() == pixels, rounding
        assert [_round_pixel_rational(Fraction(v), rounding) for v in p] == pixels, rounding
    with pytest.raises(ValueError, match="segment 0"):
        bresenham_spans([[0.0, 0.0]], [[2.0**31, 0.0]], 4, 4)


# -- rectangles --------------------------------------------------------------------------------

widths = st.sampled_from([0.25, 0.5, 1.0, 1.5, 2.0, 0.4, 1.2, 3.0]) | st.floats(0.05, 4.0)
samples = st.tuples(st.integers(0, 8).map(lambda k: k / 8), st.integers(0, 8).map(lambda k: k / 8))


@QUICK
@given(segments, widths, samples, st.sampled_from(TIE_RULES))
@example((np.array([[0.5, 1.0]]), np.array([[3.5, 1.0]])), 1.0, (0.5, 0.5), "top-left")
@example((np.array([[0.5, 0.5]]), np.array([[3.5, 4.5]])), 1.0, (0.5, 0.5), "bottom-right")  # 3-4-5: side ties
@example((np.array([[1.0, 1.0]]), np.array([[5.0, 5.0]])), 1.0, (0.5, 0.5), "top-right-y-first")
def test_rectangle_matches_rational(segs, w, sample, tie) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    fast = rectangle_spans(a, b, w, sample, tie, width=SIZE, height=SIZE)
    _same(fast, rectangle_spans_rational(a, b, w, sample, tie, width=SIZE, height=SIZE))
    _sorted(fast)


@QUICK
@given(lattice_point(), st.integers(-3 * SIZE, 3 * SIZE), st.booleans(), st.sampled_from([0.5, 1.0, 1.5]),
       samples, st.sampled_from(TIE_RULES))
def test_rectangle_of_axis_aligned_segment_is_two_triangles(a, length, horizontal, w, sample, tie) -> None:  # type: ignore[no-untyped-def]
    """Width w along an axis-aligned segment: the rectangle's corners are floats, and the
    triangle oracle on its two triangles (sharing a diagonal: each sample once) under the
    same sample point and tie rule covers the same samples."""
    d = (length / 4, 0.0) if horizontal else (0.0, length / 4)
    b = (a[0] + d[0], a[1] + d[1])
    h = w / 2
    if horizontal:
        corners = [(a[0], a[1] - h), (b[0], b[1] - h), (b[0], b[1] + h), (a[0], a[1] + h)]
    else:
        corners = [(a[0] + h, a[1]), (b[0] + h, b[1]), (b[0] - h, b[1]), (a[0] - h, a[1])]
    scene = Scene(SIZE, SIZE, np.array([[corners[0], corners[1], corners[2]], [corners[0], corners[2], corners[3]]]))
    counts = exact_coverage(scene, Convention(sample=sample, tie=tie)).counts(SIZE, SIZE)
    assert counts.max(initial=0) <= 1
    mask = np.zeros((SIZE, SIZE), dtype=np.int32)
    for _, x, y in _pixels(rectangle_spans([a], [b], w, sample, tie, width=SIZE, height=SIZE)):
        mask[y, x] = 1
    assert (mask == counts).all()


@QUICK
@given(lattice_point(), st.sampled_from([(1, 0), (0, 1), (3, 4), (-4, 3), (1, 1), (2, -1), (-1, -3)]),
       st.integers(1, 4), st.integers(1, 4), widths, samples, st.sampled_from(TIE_RULES))
def test_rectangle_collinear_pieces_partition(a, direction, k, m, w, sample, tie) -> None:  # type: ignore[no-untyped-def]
    """a -> b and b -> c on one line cover exactly the samples of a -> c, each once: the
    shared cap's samples go to one side by the tie rule."""
    d = (direction[0] / 4, direction[1] / 4)
    b = (a[0] + k * d[0], a[1] + k * d[1])
    c = (b[0] + m * d[0], b[1] + m * d[1])
    pieces = rectangle_spans([a, b], [b, c], w, sample, tie, width=SIZE, height=SIZE)
    counts = np.zeros((SIZE, SIZE), dtype=np.int32)
    for _, x, y in _pixels(pieces):
        counts[y, x] += 1
    whole = {(x, y) for _, x, y in _pixels(rectangle_spans([a], [c], w, sample, tie, width=SIZE, height=SIZE))}
    assert counts.max(initial=0) <= 1
    assert {(int(x), int(y)) for y, x in zip(*np.nonzero(counts))} == whole


@QUICK
@given(lattice_point(), st.integers(-3 * SIZE, 3 * SIZE), st.booleans(), st.sampled_from([0.5, 1.0, 2.0]),
       samples, st.sampled_from(TIE_RULES))
def test_rectangle_side_by_side_strips_partition(a, length, horizontal, w, sample, tie) -> None:  # type: ignore[no-untyped-def]
    """Two strips of width w/2 either side of an axis-aligned segment cover its width-w
    rectangle, each sample once: the shared side's samples go to one strip."""
    d = (length / 4, 0.0) if horizontal else (0.0, length / 4)
    n = (0.0, w / 4) if horizontal else (w / 4, 0.0)
    b = (a[0] + d[0], a[1] + d[1])
    starts = [(a[0] - n[0], a[1] - n[1]), (a[0] + n[0], a[1] + n[1])]
    ends = [(b[0] - n[0], b[1] - n[1]), (b[0] + n[0], b[1] + n[1])]
    halves = _pixels(rectangle_spans(starts, ends, w / 2, sample, tie, width=SIZE, height=SIZE))
    whole = {(x, y) for _, x, y in _pixels(rectangle_spans([a], [b], w, sample, tie, width=SIZE, height=SIZE))}
    assert len({(x, y) for _, x, y in halves}) == len(halves)  # no sample in both
    assert {(x, y) for _, x, y in halves} == whole


def test_rectangle_arguments_and_range() -> None:
    a, b = np.array([[1.0, 1.0], [2.0, 2.0]]), np.array([[4.0, 1.0], [2.0, 2.0]])
    assert rectangle_spans(a[1:], b[1:], 1.0, width=SIZE, height=SIZE)[0].size == 0  # no length, no rectangle
    with pytest.raises(ValueError, match="line_width of segment 1"):
        rectangle_spans(a, b, [1.0, 0.0], width=SIZE, height=SIZE)
    with pytest.raises(ValueError, match="segment 0"):
        rectangle_spans(a, b, [2.0**151, 1.0], width=SIZE, height=SIZE)
    tiny = b.copy()
    tiny[1, 0] = 1e-60
    with pytest.raises(ValueError, match="segment 1"):
        rectangle_spans(a, tiny, 1.0, width=SIZE, height=SIZE)
    with pytest.raises(ValueError, match="tie"):
        rectangle_spans(a, b, 1.0, tie="middle", width=SIZE, height=SIZE)  # type: ignore[arg-type]
