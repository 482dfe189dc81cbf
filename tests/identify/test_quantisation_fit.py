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


def test_lines_of_an_anti_aliaser_at_a_librarys_levels_are_judged_by_the_exact_area():
    """The levels are defined for triangles: identify's lines (and paths) of such an
    anti-aliaser are judged against the exact area within the tolerance measured before the
    levels were fitted (the atlas once raised on every line case)."""
    import numpy as np

    from harness.contract.conventions import LineRule
    from harness.contract.coverage import Coverage
    from harness.contract.protocol import convention_for
    from harness.contract.scenes import LineScene
    from harness.identify.fingerprint import Identified, identify
    from harness.oracle.coverage import exact_coverage

    levels = Convention(coverage="area", quantisation="blend2d", subpixel_bits=8, snap_rounding="floor")

    class LevelsWithLines:
        name = "levels_with_lines"
        convention = None
        scene_kinds = ("triangles", "lines")

        def rasterize(self, scene):
            if isinstance(scene, LineScene):
                cov = exact_coverage(scene, Convention(coverage="area", line=LineRule("rectangle")))
                assert cov.alpha is not None
                return Coverage(cov.primitive, cov.y, cov.x0, cov.x1, alpha=np.rint(cov.alpha * 255) / 255)
            return exact_coverage(scene, levels)

    rasterizer = LevelsWithLines()
    fingerprint = identify(rasterizer)
    assert fingerprint.convention.quantisation == "blend2d", fingerprint.card()
    assert fingerprint.line_convention is not None and fingerprint.line_convention.quantisation == "nearest"
    segment = LineScene.from_segments(8, 8, [[1.0, 1.5]], [[6.0, 4.0]])
    judged = convention_for(Identified(rasterizer, fingerprint), segment)
    assert judged is not None and exact_coverage(segment, judged).alpha is not None  # judged, not refused
