import numpy as np
import pytest
from hypothesis import given, strategies as st

from harness.conventions import Convention, snap


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
