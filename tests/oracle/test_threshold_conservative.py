"""The coverage rules' exact oracles (issue 33, point 2) against the brute-force rational
reference: random and lattice triangles, snapping and culling, extreme magnitudes."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.oracle.area import exact_area
from harness.oracle.coverage import exact_coverage
from harness.oracle.coverage_rules import conservative_over, conservative_under, rules_reference, threshold_coverage

RULES = [Convention(coverage="area-threshold"), Convention(coverage="area-threshold", threshold=0.25),
         Convention(coverage="area-threshold", threshold=1.0), Convention(coverage="conservative-over"),
         Convention(coverage="conservative-under")]


def _random_scene(seed: int, lattice: bool) -> Scene:
    rng = np.random.default_rng(seed)
    if lattice:  # quarter-pixel lattice: many exact ties (areas of exactly 1/2, edges through corners)
        p = rng.integers(-4, 4 * 9, size=(6, 3, 2)) / 4.0
    else:
        p = rng.uniform(-1.0, 9.0, size=(6, 3, 2))
    return Scene(8, 7, p)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("lattice", [False, True])
@pytest.mark.parametrize("index", range(len(RULES)))
def test_the_oracles_agree_with_the_rational_reference(seed, lattice, index):
    convention = RULES[index]
    scene = _random_scene(seed, lattice)
    assert exact_coverage(scene, convention) == rules_reference(scene, convention)


@pytest.mark.parametrize("index", range(len(RULES)))
def test_snapping_and_culling_come_first(index):
    scene = _random_scene(7, False)
    for extra in ({"subpixel_bits": 2}, {"subpixel_bits": 0, "snap_rounding": "floor"}, {"cull": "cw"}, {"cull": "ccw"}):
        convention = _with(RULES[index], **extra)
        assert exact_coverage(scene, convention) == rules_reference(scene, convention), extra


def _with(convention: Convention, **changes: object) -> Convention:
    from dataclasses import replace

    return replace(convention, **changes)  # type: ignore[arg-type]


def test_exact_decisions_on_ties():
    """A 2 x 2 right triangle: the hypotenuse halves pixels (0, 1) and (1, 0), touches
    (1, 1) at its corner only, and runs along the squares' corners."""
    scene = Scene(3, 3, [[[0, 0], [2, 0], [0, 2]]])
    assert threshold_coverage(scene, Convention(coverage="area-threshold")).counts(3, 3).tolist() == \
        [[1, 1, 0], [1, 0, 0], [0, 0, 0]]  # exactly 1/2 draws
    assert threshold_coverage(scene, Convention(coverage="area-threshold", threshold=0.5 + 2.0**-40)
                              ).counts(3, 3).tolist() == [[1, 0, 0], [0, 0, 0], [0, 0, 0]]
    assert conservative_over(scene, Convention(coverage="conservative-over")).counts(3, 3).tolist() == \
        [[1, 1, 1], [1, 1, 0], [1, 0, 0]]  # (1, 1) touches the hypotenuse at its corner; (2, 0) at (2, 0)
    assert conservative_under(scene, Convention(coverage="conservative-under")).counts(3, 3).tolist() == \
        [[1, 0, 0], [0, 0, 0], [0, 0, 0]]


def test_a_threshold_a_float_could_not_decide():
    """Triangles covering a pixel a few units in the last place more or less than 1/2
    (within the float oracle's error bound): decided exactly."""
    tri = np.array([[[0.0, 0.0], [2.0 + 2.0**-51, 0.0], [0.0, 2.0]]])
    area = exact_area(tri[0], 1, 0)
    assert Fraction(1, 2) < area < Fraction(1, 2) + Fraction(1, 2**48)
    got = threshold_coverage(Scene(2, 2, tri), Convention(coverage="area-threshold", threshold=0.5)).counts(2, 2)
    assert got[0, 1] == 1
    tri2 = np.array([[[0.0, 0.0], [2.0 - 2.0**-52, 0.0], [0.0, 2.0]]])
    assert exact_area(tri2[0], 1, 0) < Fraction(1, 2)
    got = threshold_coverage(Scene(2, 2, tri2), Convention(coverage="area-threshold")).counts(2, 2)
    assert got[0, 1] == 0


def test_extreme_magnitudes_take_the_rational_path():
    """Coordinates beyond the expansions' safe range (subnormal, 1e300): the same answers
    as the reference."""
    scene = Scene(4, 4, [[[1e-310, 0.0], [3.0, 1e-320], [0.0, 3.0]], [[-1e300, -1e300], [1e300, 0.5], [0.5, 1e300]],
                         [[-1e100, 0.25], [1e100, 0.5], [2.5, 1e100]], [[0.5, -1e20], [3.5, 1.0], [0.25, 1e20]]])
    for convention in RULES[3:]:
        assert exact_coverage(scene, convention) == rules_reference(scene, convention)


def test_zero_area_and_non_finite_triangles_cover_nothing():
    scene = Scene(4, 4, np.array([[[0, 0], [2, 2], [4, 4]], [[0, 0], [np.nan, 1], [1, 2]], [[1, 1], [1, 1], [1, 1]]]))
    for convention in RULES:
        assert len(exact_coverage(scene, convention)) == 0


@pytest.mark.parametrize("seed", range(4))
def test_underestimate_is_a_threshold_of_one(seed):
    """A closed triangle covers all of a square iff it contains it: conservative-under and
    area-threshold 1 draw the same pixels (two independent oracles)."""
    for lattice in (False, True):
        scene = _random_scene(seed, lattice)
        assert conservative_under(scene, Convention(coverage="conservative-under")) == \
            threshold_coverage(scene, Convention(coverage="area-threshold", threshold=1.0))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("lattice", [False, True])
def test_the_uncertainty_regions_bounds_agree_with_the_reference(seed, lattice):
    """What an overestimate may draw and an underestimate must draw under an uncertainty
    region u: the squares grown by u, decided exactly, against the rational reference."""
    from harness.oracle.coverage_rules import uncertainty_bounds

    scene = _random_scene(seed, lattice)
    for u in (2.0**-8, 2.0**-16, 0.5):
        over = Convention(coverage="conservative-over", uncertainty=u)
        must, may = uncertainty_bounds(scene, over)
        assert must == exact_coverage(scene, over) and may == rules_reference(scene, over, grown=u)
        under = Convention(coverage="conservative-under", uncertainty=u, subpixel_bits=4)
        must, may = uncertainty_bounds(scene, under)
        assert may == exact_coverage(scene, under) and must == rules_reference(scene, under, grown=u)


def test_the_uncertainty_region_on_the_rational_path():
    from harness.oracle.coverage_rules import uncertainty_bounds

    scene = Scene(5, 4, [[[1e-310, 0.0], [3.0 - 2.0**-10, 1e-320], [0.0, 3.0]], [[-1e300, -1e300], [1e300, 0.5], [0.5, 1e300]]])
    for rule in ("conservative-over", "conservative-under"):
        convention = Convention(coverage=rule, uncertainty=2.0**-8)
        must, may = uncertainty_bounds(scene, convention)
        grown = rules_reference(scene, convention, grown=2.0**-8)
        assert (may if rule == "conservative-over" else must) == grown
