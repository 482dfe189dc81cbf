import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from harness.contract.conventions import Convention, snap


@pytest.mark.parametrize(
    "kwargs, text",
    [
        (dict(sample=(0.5, 1.5)), "sample y must lie in"),
        (dict(sample=(1 / 3, 0.5)), "multiple of 2"),
        (dict(tie="left"), "tie must be one of"),
        (dict(subpixel_bits=17), "subpixel_bits"),
        (dict(subpixel_bits=True), "subpixel_bits"),
        (dict(cull="front"), "cull must be one of"),
    ],
)
def test_invalid_conventions(kwargs, text):
    with pytest.raises(ValueError, match=text):
        Convention(**kwargs)


def test_snap_rounds_half_to_even():
    values = np.array([0.5, 1.5, 2.5, -0.5, -1.5, 0.49999999999999994]) / 4
    assert snap(values, 2).tolist() == (np.array([0, 2, 2, -0, -2, 0]) / 4).tolist()


@given(st.floats(allow_nan=False, allow_infinity=False), st.integers(0, 16))
def test_snap_is_exact_and_nearest(value, bits):
    from fractions import Fraction

    snapped = float(snap(np.array([value]), bits)[0])
    scaled = Fraction(snapped) * 2**bits
    assert scaled.denominator == 1  # on the grid
    assert abs(Fraction(value) * 2**bits - scaled) <= Fraction(1, 2)


@given(st.floats(allow_nan=False, allow_infinity=False), st.integers(0, 16))
def test_half_away_and_floor_snapping_are_exact(value, bits):
    """Each rounding against its definition in rationals: half away from zero is
    sign(v) * floor(|v| + 1/2), floor is floor(v), both on v = value * 2**bits."""
    import math
    from fractions import Fraction

    scaled = Fraction(value) * 2**bits
    away = float(snap(np.array([value]), bits, "half-away")[0])
    assert Fraction(away) * 2**bits == (1 if scaled >= 0 else -1) * math.floor(abs(scaled) + Fraction(1, 2))
    down = float(snap(np.array([value]), bits, "floor")[0])
    assert Fraction(down) * 2**bits == math.floor(scaled)


def test_the_three_roundings_part_only_at_half_steps_or_below():
    half_steps = np.array([0.5, 1.5, 2.5, -0.5, -1.5, -2.5]) / 4
    assert snap(half_steps, 2, "nearest-even").tolist() == (np.array([0, 2, 2, 0, -2, -2]) / 4).tolist()
    assert snap(half_steps, 2, "half-away").tolist() == (np.array([1, 2, 3, -1, -2, -3]) / 4).tolist()
    assert snap(half_steps, 2, "floor").tolist() == (np.array([0, 1, 2, -1, -2, -3]) / 4).tolist()


def test_tie_rules_are_the_eight_perturbations():
    from harness.contract.conventions import TIE_PERTURBATION, TIE_RULES

    assert len(TIE_RULES) == 8 and len(set(TIE_PERTURBATION.values())) == 8
    assert TIE_PERTURBATION["top-left"] == (1, 1, False)  # right, then down: the D3D rule
    assert Convention(tie="bottom-right-y-first").describe().startswith("sample (0.5, 0.5), bottom-right ties (y first)")


def test_piglit_names_map_onto_the_rule_that_fills_its_probe():
    """piglit's get_filling_convention: eight sub-pixel triangles around a pixel centre
    (window coordinates taken as ours); the rule named ``PIGLIT_NAMES[name]`` must give the
    centre to piglit's triangle number ``name`` and to no other."""
    from harness.contract.conventions import PIGLIT_NAMES
    from harness.contract.scenes import Scene
    from harness.oracle.coverage import exact_coverage

    order = ["bottom_left", "left_bottom", "right_bottom", "bottom_right", "top_right", "right_top", "left_top", "top_left"]
    mid, size = 0.5, 3.0 / 256
    v = [(mid + size, mid), (mid + size, mid + size), (mid, mid + size), (mid - size, mid + size),
         (mid - size, mid), (mid - size, mid - size), (mid, mid - size), (mid + size, mid - size), (mid + size, mid)]
    probe = Scene(1, 1, [[v[i], v[i + 1], (mid, mid)] for i in range(8)])
    for index, name in enumerate(order):
        drawn = exact_coverage(probe, Convention(tie=PIGLIT_NAMES[name])).triangle
        assert drawn.tolist() == [index], (name, drawn)
