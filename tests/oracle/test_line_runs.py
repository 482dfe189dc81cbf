"""The line oracles' run kernels (issue 35, point 4) against the kernels they replaced, kept as
references: :func:`harness.oracle.diamond_lines._diamond_exit_spans_reference` (one major-axis
cell at a time, each decided by the exact predicate),
:func:`harness.oracle.bresenham_lines._bresenham_spans_reference` (pixel by pixel in closed
form) and :func:`harness.oracle.rectangle_lines._rectangle_spans_reference` (every flip of a
row decided by the exact condition). The spans must be identical, array for array: random floats, lattice and tie scenes
(end points on pixel centres and diamond corners, slopes exactly 1 and 1/2, axis-aligned and
zero-length segments), far and tiny coordinates, non-finite end points, clipping, and
hypothesis scenes."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from harness.contract.conventions import BRESENHAM_ROUNDINGS, BRESENHAM_TIES, LINE_DIRECTIONS, TIE_RULES
from harness.oracle.bresenham_lines import (
    _bresenham_spans_reference,
    _end_point_pixels_numpy,
    bresenham_spans,
    end_point_pixels,
)
from harness.oracle.diamond_lines import _diamond_exit_spans_reference, diamond_exit_spans
from harness.oracle.line_spans import _beyond, _beyond_numpy, finite_rows
from harness.oracle.rectangle_lines import _rectangle_spans_reference, rectangle_spans

QUICK = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # examples: the profile's
DIAMOND_RULES = ("diamond-exit", "diamond-exit-gl")


def _same(new: Any, old: Any) -> None:
    assert [x.tolist() for x in new] == [x.tolist() for x in old]


def _diamond_same(a: np.ndarray, b: np.ndarray, width: int, height: int) -> None:
    for rule in DIAMOND_RULES:
        for last_pixel in (False, True):
            _same(diamond_exit_spans(a, b, width, height, last_pixel, rule),
                  _diamond_exit_spans_reference(a, b, width, height, last_pixel, rule))


def _bresenham_same(a: np.ndarray, b: np.ndarray, width: int, height: int) -> None:
    for rounding in BRESENHAM_ROUNDINGS:
        for ties in BRESENHAM_TIES:
            for last_pixel in (False, True):
                for direction in LINE_DIRECTIONS:
                    _same(bresenham_spans(a, b, width, height, rounding, ties, last_pixel, direction),
                          _bresenham_spans_reference(a, b, width, height, rounding, ties, last_pixel, direction))


SAMPLES = ((0.5, 0.5), (0.0, 0.0), (0.25, 0.75), (1.0, 0.5))
WIDTHS = (1.0, 0.5, 2.0, 1.5, 3.0, 0.25, 1.0 / 3, 2.0**0.5)


def _rectangle_same(a: np.ndarray, b: np.ndarray, width: int, height: int, widths: Any = 1.0,
                    ties: tuple[str, ...] = TIE_RULES, samples: tuple[tuple[float, float], ...] = SAMPLES) -> None:
    for tie in ties:
        for sample in samples:
            _same(rectangle_spans(a, b, widths, sample, tie, width=width, height=height),  # type: ignore[arg-type]
                  _rectangle_spans_reference(a, b, widths, sample, tie, width=width, height=height))  # type: ignore[arg-type]


def _scenes(seed: int) -> list[tuple[np.ndarray, np.ndarray, int, int]]:
    """Scenes of 150 segments in viewports of 0 to 40 pixels a side, of six kinds: floats,
    half-pixel lattice, pixel centres with integer steps (slopes 1, 1/2, 0, ...), quarter
    lattice with slopes of small integers, far end points with near ones, and axis-aligned
    lines nudged by tiny amounts; a few NaN end points in each."""
    rng = np.random.default_rng(seed)
    out = []
    n = 150
    for kind in range(6):
        width, height = int(rng.integers(0, 40)), int(rng.integers(0, 40))
        if kind == 0:
            a, b = rng.uniform(-20, 60, (n, 2)), rng.uniform(-20, 60, (n, 2))
        elif kind == 1:
            a, b = rng.integers(-10, 90, (n, 2)) / 2.0, rng.integers(-10, 90, (n, 2)) / 2.0
        elif kind == 2:
            a = (rng.integers(-5, 45, (n, 2)) + 0.5).astype(np.float64)
            b = a + rng.integers(-8, 9, (n, 2)) * rng.integers(1, 5, (n, 1))
        elif kind == 3:
            a = rng.integers(-20, 180, (n, 2)) / 4.0
            b = a + rng.integers(-3, 4, (n, 2)) * rng.integers(1, 12, (n, 1)) / 2.0
        elif kind == 4:
            a, b = rng.uniform(-1e9, 1e9, (n, 2)), rng.uniform(-1e9, 1e9, (n, 2))
            a[::3] = rng.uniform(0, 30, (len(a[::3]), 2))
        else:
            a = rng.uniform(0, 40, (n, 2))
            b = a.copy()
            axis = rng.integers(0, 2, n)
            b[np.arange(n), axis] += rng.uniform(-30, 30, n)
            b[::5] = a[::5]
            rows = np.arange(1, n, 7)
            b[rows, 1 - axis[rows]] += rng.choice([1e-300, -1e-300, 1e-9, 2.0**-40], len(rows))
        a[rng.random(n) < 0.03, 0] = np.nan
        out.append((a, b, width, height))
    return out


@pytest.mark.parametrize("seed", range(4))
def test_diamond_runs_match_reference_on_random_and_lattice_scenes(seed: int) -> None:
    for a, b, width, height in _scenes(seed):
        _diamond_same(a, b, width, height)


@pytest.mark.parametrize("seed", range(3))
def test_bresenham_runs_match_reference_on_random_and_lattice_scenes(seed: int) -> None:
    for a, b, width, height in _scenes(seed):
        _bresenham_same(a, b, width, height)


@pytest.mark.parametrize("seed", range(3))
def test_rectangle_runs_match_reference_on_random_and_lattice_scenes(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    for k, (a, b, width, height) in enumerate(_scenes(seed)):
        if k == 4:  # far end points: in the rectangles' range too (2**150)
            a, b = a / 2.0**20, b / 2.0**20
        a = np.where(np.abs(a) < 2.0**-140, 0.0, a)
        b = np.where(np.abs(b) < 2.0**-140, 0.0, b)
        _rectangle_same(a, b, width, height, float(rng.choice(WIDTHS)))
        _rectangle_same(a, b, width, height, rng.choice(WIDTHS, a.shape[0]), ties=("top-left", "bottom-right"))


def test_runs_match_reference_on_far_and_tiny_coordinates() -> None:
    """Coordinates near the kernels' range (2**+-450 for the diamonds; rounded end points up
    to 2**30 for Bresenham, whose walks longer than 2**30 - 1 go pixel by pixel), lines
    almost horizontal over huge spans, and tiny slopes."""
    big = 2.0**449
    a = np.array([[-big, 3.25], [1.5, -big], [-1e130, 2.5], [0.5, 0.5], [3.0, 2.0**-449], [-big, -big], [2.0**-440, 7.0],
                  [-1e6, 4.0], [4.0, -1e6]])
    b = np.array([[big, 3.75], [2.5, big], [1e130, 2.5 + 2.0**-40], [30.5, 0.5 + 2.0**-449], [9.0, 5.0], [big, big],
                  [2.0**-449, -3.0], [1e6, 5.0], [5.0, 1e6]])
    _diamond_same(a, b, 24, 20)
    far = 2.0**30 - 2.0  # rounded by any rule to within 2**30
    c = np.array([[-far, 3.0], [5.0, -far], [-1e9, -1e9], [far, far - 7.0], [0.5, 1.5]])
    d = np.array([[far, 4.0], [6.0, far], [1e9, 1e9 - 3.0], [-far, -far], [far, 2.5]])
    _bresenham_same(c, d, 20, 24)
    r = 2.0**149
    e = np.array([[-r, 3.25], [1.5, -r], [0.5, 0.5], [3.0, 2.0**-149], [2.0**-140, 7.0], [-1e6, 4.0], [4.0, -1e6]])
    f = np.array([[r, 3.75], [2.5, r], [30.5, 0.5 + 2.0**-149], [9.0, 5.0], [2.0**-149, -3.0], [1e6, 5.0], [5.0, 1e6]])
    _rectangle_same(e, f, 24, 20, 1.0)
    _rectangle_same(e, f, 24, 20, 2.0**-100, ties=("top-left",))
    _rectangle_same(e, f, 24, 20, 2.0**140, ties=("top-left",))


def test_runs_match_reference_on_bench_sized_scenes() -> None:
    """Long segments across a larger viewport, the shape of the bench's L2 (clipped too)."""
    rng = np.random.default_rng(7)
    a, b = rng.uniform(-40, 300, (200, 2)), rng.uniform(-40, 300, (200, 2))
    _diamond_same(a, b, 256, 200)
    _bresenham_same(a, b, 200, 256)
    _rectangle_same(a, b, 256, 200, 1.0, ties=("top-left",), samples=((0.5, 0.5),))


def test_end_point_pixels_match_numpy() -> None:
    values = np.array([[-2.5, -2.0], [-1.5, -1.0], [-0.5, -0.0], [0.0, 0.5], [1.0, 1.5], [2.0, 2.5], [3.0, 1e300],
                       [np.nan, np.inf], [-np.inf, 2.0**52], [4.999999999, -7.0]])
    for rounding in BRESENHAM_ROUNDINGS:
        with np.errstate(invalid="ignore"):  # inf - inf in the numpy version
            new, old = end_point_pixels(values, rounding), _end_point_pixels_numpy(values, rounding)
        assert np.array_equal(new, old, equal_nan=True)
        assert np.array_equal(np.signbit(new), np.signbit(old))
        assert end_point_pixels(values[:, 0], rounding).shape == (10,)


def test_compiled_range_and_finiteness_checks_match_numpy() -> None:
    values = np.array([[0.0, 1e-200, 3.0, 1.0], [np.nan, 1.0, 2.0, 0.0], [np.inf, 0.0, 0.0, 1.0], [2.0**500, 1.0, 1.0, 1.0],
                       [1.0, 2.0, 3.0, -0.0], [-2.0**-451, 1.0, 1.0, 1.0], [-np.inf, np.nan, 0.0, 0.0]])
    low, high = 2.0**-450, 2.0**450
    assert _beyond(values, low, high).tolist() == _beyond_numpy(values, low, high).tolist()
    assert _beyond(values[:, :2], low, high).tolist() == _beyond_numpy(values[:, :2], low, high).tolist()
    a, b = values[:, :2], values[:, 2:]
    assert finite_rows(a, b).tolist() == (np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)).tolist()


# -- hypothesis: end points on a 1/2, 1/4 or 1/8 lattice (ties on purpose) or floats -----------

def _coordinate() -> st.SearchStrategy[float]:
    lattice = st.sampled_from([2, 4, 8]).flatmap(lambda den: st.integers(-2 * den, 20 * den).map(lambda k: k / den))
    floats = st.floats(-2.0, 20.0, allow_nan=False, allow_infinity=False).map(lambda v: 0.0 if abs(v) < 2.0**-140 else v)
    return st.one_of(lattice, floats)  # (nothing so tiny that the kernels' range refuses it)


@st.composite
def _segment(draw: Any) -> tuple[tuple[float, float], tuple[float, float]]:
    a = (draw(_coordinate()), draw(_coordinate()))
    kind = draw(st.sampled_from(["any", "diagonal", "half", "axis", "zero"]))
    if kind == "any":
        b = (draw(_coordinate()), draw(_coordinate()))
    elif kind in ("diagonal", "half"):  # slopes 1 and 1/2 (x- or y-major), either direction
        t = draw(st.integers(-40, 40)) / 4
        s = t if kind == "diagonal" else t / 2
        b = (a[0] + t, a[1] + s) if draw(st.booleans()) else (a[0] + s, a[1] + t)
    elif kind == "axis":
        other = (draw(_coordinate()), draw(_coordinate()))
        b = (a[0], other[1]) if draw(st.booleans()) else (other[0], a[1])
    else:
        b = a
    return a, b


_segments = st.lists(_segment(), min_size=1, max_size=6).map(
    lambda pairs: (np.array([p[0] for p in pairs], dtype=np.float64), np.array([p[1] for p in pairs], dtype=np.float64)))


@QUICK
@given(_segments, st.integers(0, 20), st.integers(0, 20))
@example((np.array([[0.5, 0.5]]), np.array([[4.5, 2.5]])), 6, 4)  # slope 1/2 through bottom corners
@example((np.array([[1.0, 0.5]]), np.array([[4.0, 3.5]])), 6, 6)  # 45 degrees along diamond edges
@example((np.array([[9.5, 3.0]]), np.array([[0.5, 3.0]])), 8, 6)  # right to left on a row boundary
@example((np.array([[0.5, 2.0]]), np.array([[12.5, 8.0]])), 10, 6)  # GL's lower pixel at corners, clipped
def test_runs_match_reference_on_hypothesis_scenes(segs: tuple[np.ndarray, np.ndarray], width: int, height: int) -> None:
    a, b = segs
    _diamond_same(a, b, width, height)
    _diamond_same(b, a, width, height)
    _bresenham_same(a, b, width, height)
    _rectangle_same(a, b, width, height, 1.0, samples=((0.5, 0.5), (0.0, 0.0)))


@QUICK
@given(_segments, st.sampled_from(WIDTHS), st.sampled_from(SAMPLES), st.sampled_from(TIE_RULES))
@example((np.array([[0.5, 1.0]]), np.array([[3.5, 1.0]])), 1.0, (0.5, 0.5), "top-left")  # sides through samples
@example((np.array([[0.5, 0.5]]), np.array([[3.5, 4.5]])), 1.0, (0.5, 0.5), "bottom-right")  # 3-4-5: side ties
@example((np.array([[1.0, 1.0]]), np.array([[5.0, 5.0]])), 2.0**0.5, (0.5, 0.5), "top-right-y-first")  # 45 degrees
def test_rectangle_runs_match_reference_on_hypothesis_scenes(segs: tuple[np.ndarray, np.ndarray], w: float,
                                                             sample: tuple[float, float], tie: str) -> None:
    a, b = segs
    _rectangle_same(a, b, 20, 20, w, ties=(tie,), samples=(sample,))
