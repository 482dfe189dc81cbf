"""Multisample patterns: the standard tables and the validation of custom ones."""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from harness.contract.samples import FRACTION_BITS, STANDARD_PATTERNS, pattern
from harness.contract.scenes import MAX_VIEWPORT

# Within the pixel, y down, as in the design notes (CONVENTIONS.md), Mesa's Intel table
# (src/intel/common/gen_sample_positions.c) and the Vulkan standard sample locations.
LITERAL = {
    1: [(0.5, 0.5)],
    2: [(0.75, 0.75), (0.25, 0.25)],
    4: [(0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875)],
    8: [(0.5625, 0.3125), (0.4375, 0.6875), (0.8125, 0.5625), (0.3125, 0.1875),
        (0.1875, 0.8125), (0.0625, 0.4375), (0.6875, 0.9375), (0.9375, 0.0625)],
    16: [(0.5625, 0.5625), (0.4375, 0.3125), (0.3125, 0.625), (0.75, 0.4375),
         (0.1875, 0.375), (0.625, 0.8125), (0.8125, 0.6875), (0.6875, 0.1875),
         (0.375, 0.875), (0.5, 0.0625), (0.25, 0.125), (0.125, 0.75),
         (0.0, 0.5), (0.9375, 0.25), (0.875, 0.9375), (0.0625, 0.0)],
}


def test_standard_tables_match_the_published_ones():
    assert {k: list(v) for k, v in STANDARD_PATTERNS.items()} == LITERAL


@pytest.mark.parametrize("count", sorted(LITERAL))
def test_standard_patterns_are_valid_sixteenths(count):
    offsets = pattern(count)
    assert offsets is STANDARD_PATTERNS[count]
    assert len(offsets) == count == len(set(offsets))
    assert pattern(offsets) == offsets  # a standard pattern passes its own validation
    for sx, sy in offsets:
        assert type(sx) is float and type(sy) is float
        assert (sx * 16).is_integer() and (sy * 16).is_integer()
        assert 0 <= sx < 1 and 0 <= sy < 1
    # n-rooks: no two samples share a row or a column of the 1/16 grid (D3D11's design)
    assert len({sx for sx, _ in offsets}) == count == len({sy for _, sy in offsets})


def test_custom_patterns_accept_exact_reals():
    got = pattern(np.array([[0.5, 0.25], [0, 0.75]]))
    assert got == ((0.5, 0.25), (0.0, 0.75))
    assert pattern([(Fraction(3, 8), np.float32(0.5)), (-0.0, 2**-32)]) == ((0.375, 0.5), (0.0, 2**-32))
    assert pattern(((np.int64(0), 0.5),)) == ((0.0, 0.5),)


@pytest.mark.parametrize("spec, message", [
    (3, "no standard pattern has 3 samples"),
    (0, "no standard pattern has 0 samples"),
    (True, "not True"),
    ([], "at least one sample"),
    ([(0.5,)], r"\(0.5,\) is not an \(x, y\) pair"),
    ([(0.5, 0.5, 0.5)], "is not an"),
    (["ab"], "'ab' is not an"),
    ([0.5], "0.5 is not an"),
    ([(1.0, 0.0)], r"\(1.0, 0.0\) lies outside the pixel"),
    ([(0.5, -0.25)], "lies outside the pixel"),
    ([(float("nan"), 0.5)], r"\(nan, 0.5\): nan is not finite"),
    ([(0.5, float("inf"))], "inf is not finite"),
    ([(0.1, 0.5)], r"\(0.1, 0.5\) is not a multiple of 2\*\*-32"),
    ([(2.0**-33, 0.5)], "not a multiple of 2"),
    ([(Fraction(1, 3), 0.5)], "not a multiple of 2"),
    ([("0.5", 0.5)], "'0.5' is not a real number"),
    ([(True, 0.5)], "True is not a real number"),
    ([(0.5, 0.5), (0.25, 0.25), (0.5, 0.5)], r"\(0.5, 0.5\) \(sample 2\) repeats sample 0"),
])
def test_invalid_patterns_are_refused_naming_the_offset(spec, message):
    with pytest.raises(ValueError, match=message):
        pattern(spec)


@given(st.lists(st.tuples(*[st.integers(0, 2**FRACTION_BITS - 1)] * 2), min_size=1, max_size=16, unique=True))
def test_every_sample_point_of_any_valid_pattern_is_an_exact_float(ticks):
    offsets = pattern([(a / 2**FRACTION_BITS, b / 2**FRACTION_BITS) for a, b in ticks])
    assert len(offsets) == len(ticks)
    for sx, sy in offsets:
        for i in (0, 1, MAX_VIEWPORT - 1):
            # i + s rounds to nothing: the exact sample point is the float one
            assert Fraction(i + sx) == i + Fraction(sx)
            assert Fraction(i + sy) == i + Fraction(sy)


@pytest.mark.parametrize("count, tie", [(4, "top-left"), (8, "bottom-right-y-first")])
def test_per_sample_oracle_is_watertight_on_a_partition_with_ties_at_samples(count, tie):
    """On a planar partition whose vertices lie on the 1/16 grid -- edges through many of
    the standard samples -- every sample of every pixel inside it is covered exactly once,
    for each sample of the pattern; and each sample's coverage is the brute-force rational
    one at its offset."""
    from dataclasses import replace

    from cases.scenes import grid_mesh
    from harness.contract.conventions import Convention
    from harness.contract.scenes import Scene
    from harness.oracle.coverage import exact_samples
    from harness.oracle.reference import brute_force_coverage

    rng = np.random.default_rng(count)
    # interior vertices moved by random 1/16 steps; a shared vertex moves with all its triangles
    moved = {tuple(v): v + rng.integers(-6, 7, 2) / 16 for v in grid_mesh(4, 10, 0.0, 0).reshape(-1, 2)
             if ((v > 1) & (v < 9)).all()}
    mesh = np.array([[moved.get(tuple(v), v) for v in tri] for tri in grid_mesh(4, 10, 0.0, 0)])
    scene = Scene(10, 10, mesh)
    convention = Convention(tie=tie)
    per_sample = exact_samples(scene, convention, count)
    for k, coverage in enumerate(per_sample):
        hits = coverage.counts(10, 10)
        assert (hits[1:9, 1:9] == 1).all(), (k, hits)  # the pixels wholly inside [1, 9]^2
        assert coverage == brute_force_coverage(scene, replace(convention, sample=STANDARD_PATTERNS[count][k]))
