"""identify's area probes recover skia's supersampler (tiny-skia's model,
harness.oracle.supersample_models) from outside, and leave the other anti-aliasers' models alone."""

from __future__ import annotations

import pytest

from harness.contract.conventions import Convention
from harness.engine.isolation import InProcess
from harness.identify.area_probes import alpha_sweeps
from tests.identify.test_coverage_probes import Hidden, Supersampler


@pytest.mark.parametrize("shift", [2, 3])
def test_the_supersampler_is_recovered_exactly(shift: int) -> None:
    found = alpha_sweeps(InProcess(Hidden(Convention(coverage="area", supersample=shift, input="float32"))))
    assert found.model == "supersampled" and found.convention is not None
    assert found.convention.supersample == shift and found.convention.input == "float32"
    assert found.residual == 0 and found.max_residual == 0.0


@pytest.mark.parametrize("other", [Supersampler(4), Hidden(Convention(coverage="area", rows=15), 256),
                                   Hidden(Convention(coverage="area"), 256)], ids=["4x4-pattern", "row-sampled", "analytic"])
def test_other_models_are_not_taken_for_it(other: object) -> None:
    found = alpha_sweeps(InProcess(other))  # type: ignore[arg-type]
    assert found.convention is not None and found.convention.supersample == 0 and found.residual == 0
