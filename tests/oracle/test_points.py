"""The exact point oracle (harness.oracle.points) against its rational brute force: on
lattice points whose square sides pass through samples (every tie rule, sample point,
snapping, multisample pattern), on floats a step away from a tie, and on hostile input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from harness.contract.conventions import TIE_RULES, Convention
from harness.kinds.points import PointScene
from harness.oracle.points import point_coverage, point_coverage_rational

QUICK = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
SIZE = 8

# centres on a quarter-pixel lattice and sizes in half pixels: square sides land on pixel
# centres and corners, where only the tie rule decides
lattice = st.lists(st.tuples(st.integers(-8, 40), st.integers(-8, 40)), min_size=1, max_size=6).map(
    lambda c: np.array(c, dtype=np.float64) / 4.0)
sizes = st.integers(1, 12).map(lambda n: n / 2.0)
conventions = st.builds(
    Convention,
    sample=st.sampled_from([(0.5, 0.5), (0.0, 0.0), (0.25, 0.75)]),
    tie=st.sampled_from(TIE_RULES),
    subpixel_bits=st.sampled_from([None, 1, 4]),
    samples=st.sampled_from([None, 4]),
)


def _same(a, b) -> None:
    assert a.canonical() == b.canonical(), (a.canonical().spans_table() if hasattr(a, "spans_table") else a, b)


@QUICK
@given(lattice, sizes, conventions)
@example(np.array([[1.0, 1.0]]), 1.0, Convention())  # sides through four pixel centres
@example(np.array([[1.0, 1.0]]), 1.0, Convention(tie="bottom-right"))
@example(np.array([[-0.5, 3.0]]), 2.0, Convention())  # half outside the viewport
def test_the_oracle_matches_its_rational_brute_force(centres, size, convention) -> None:
    scene = PointScene(SIZE, SIZE, centres, point_size=size)
    _same(point_coverage(scene, convention), point_coverage_rational(scene, convention))


@QUICK
@given(lattice, sizes, st.sampled_from(TIE_RULES), st.integers(-1, 1), st.integers(-1, 1))
def test_a_float_step_from_a_tie_is_decided_by_the_step(centres, size, tie, ux, uy) -> None:
    """Centres moved one unit in the last place off the lattice: the exact oracle sees the
    step (a float evaluation of ``c - (p - s/2)`` would round it away)."""
    step = np.array([ux, uy], dtype=np.float64)
    moved = np.where(step == 0, centres, np.nextafter(centres, centres + step))
    scene = PointScene(SIZE, SIZE, moved, point_size=size)
    convention = Convention(tie=tie)
    _same(point_coverage(scene, convention), point_coverage_rational(scene, convention))


def test_unit_points_on_a_grid_tile_the_viewport_exactly_once_under_every_tie_rule() -> None:
    """Size-1 points one pixel apart, moved together by an offset that puts their sides
    through the samples: every sample covered once, by the tie rule's choice."""
    for tie in TIE_RULES:
        for offset in ((0.0, 0.0), (0.5, 0.5), (0.25, 0.5), (0.125, 0.0)):
            grid = np.stack(np.meshgrid(np.arange(-1, SIZE + 1), np.arange(-1, SIZE + 1)), axis=-1).reshape(-1, 2) + offset
            counts = point_coverage(PointScene(SIZE, SIZE, grid.astype(np.float64)), Convention(tie=tie)).counts(SIZE, SIZE)
            assert (counts == 1).all(), (tie, offset, counts)


def test_the_tie_rule_picks_the_sides() -> None:
    # a size-1 point centred on a pixel corner: its sides pass through four pixel centres
    scene = PointScene(3, 3, [[1.0, 1.0]])
    owned = {tie: np.argwhere(point_coverage(scene, Convention(tie=tie)).counts(3, 3)).tolist() for tie in TIE_RULES}
    assert owned["top-left"] == [[0, 0]] and owned["bottom-right"] == [[1, 1]]
    assert owned["top-right"] == [[0, 1]] and owned["bottom-left"] == [[1, 0]]
    assert owned["top-left-y-first"] == owned["top-left"]  # axis-aligned sides: x- and y-first agree


def test_hostile_centres_cover_nothing_and_huge_ones_do_not_overflow() -> None:
    centres = np.array([[np.nan, 1.0], [np.inf, 2.0], [1e308, 1e308], [-1e308, 3.0], [2.5, 2.5]])
    coverage = point_coverage(PointScene(SIZE, SIZE, centres, point_size=1.0), Convention())
    assert coverage.primitive.tolist() == [4] and coverage.y.tolist() == [2]
    big = point_coverage(PointScene(4, 4, [[2.0, 2.0]], point_size=float(1 << 20)), Convention())
    assert (big.counts(4, 4) == 1).all()


def test_the_scene_refuses_a_bad_size_and_area_coverage_is_refused_by_name() -> None:
    for bad in (0.0, -1.0, float("nan"), "big"):
        with pytest.raises(ValueError, match="point_size"):
            PointScene(4, 4, [[1.0, 1.0]], point_size=bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="points are defined for single-sample and multisample"):
        point_coverage(PointScene(4, 4, [[1.0, 1.0]]), Convention(coverage="area"))
