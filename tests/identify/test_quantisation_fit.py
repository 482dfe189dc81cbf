"""identify recovers an analytic anti-aliaser's levels (issue 34,
:func:`harness.identify.area_probes.quantisation_fit`): the quantisation and the input grid
of a hidden convention, and the nearest level kept for one that rounds."""

from __future__ import annotations

import pytest

from harness.contract.conventions import Convention
from harness.engine.isolation import InProcess
from harness.identify.area_probes import alpha_sweeps
from tests.identify.test_coverage_probes import Hidden


@pytest.mark.parametrize("hidden", [Convention(coverage="area", quantisation="ftgrays", input="fixed6"),
                                    Convention(coverage="area", quantisation="cells-abs-gray8", subpixel_bits=8,
                                               snap_rounding="floor")],
                         ids=["ftgrays-26.6", "aggdraw-24.8-truncated"])
def test_identify_recovers_the_levels_and_the_grid(hidden):
    fact = alpha_sweeps(InProcess(Hidden(hidden, 256)))
    assert fact.model == "analytic" and fact.convention is not None and fact.quantisation is not None
    found = fact.convention
    assert found.quantisation == hidden.quantisation, fact.quantisation.text
    bits = hidden.input_precision.bits if hidden.input != "float64" else hidden.subpixel_bits
    assert found.subpixel_bits == bits, found
    assert found.tolerance == pytest.approx(1 / 255)  # judged within one level
    assert fact.residual == 0 and fact.quantisation.off == 0, fact.quantisation.text


def test_identify_keeps_the_nearest_level_for_an_anti_aliaser_that_rounds():
    fact = alpha_sweeps(InProcess(Hidden(Convention(coverage="area"), 256)))
    assert fact.convention is not None and fact.convention.quantisation == "nearest"
    assert fact.quantisation is not None and fact.quantisation.chosen is None and fact.quantisation.nearest_off == 0
