"""Row-sampled area coverage (issue 34, cairo's tor scan converter): the compiled oracle
against the rational reference, the convention's declaration, and the known-bad ports of
the model caught by accuracy."""

from __future__ import annotations

import functools
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from cases.suites import suite
from harness.contract.conventions import Convention
from harness.contract.coverage_models import ROW_SAMPLED_AREA, model_for
from harness.contract.scenes import Scene
from harness.oracle.aa_models import cairo_alpha_levels, exact_row_sampled_alpha, row_sampled_coverage
from harness.oracle.area import exact_area
from harness.oracle.coverage import exact_coverage
from tests.accuracy_runs import assert_judged_by_accuracy, dense_alphas
from tests.known_bad.aa_models import HybridSamplesEveryRow, RowsAtTopEdges, RowsTruncatedLevels

W = H = 6


def _dense(coverage, width=W, height=H):
    return dense_alphas(coverage, width, height)


# vertices on a lattice of 1/32 px (ties with the 1/15 rows never, with pixel edges often)
# and on 1/30 (sub-row centres and boundaries hit on purpose)
_coordinate = st.one_of(st.integers(0, 6 * 32).map(lambda v: v / 32), st.integers(0, 6 * 30).map(lambda v: v / 30))
_triangle = st.lists(st.tuples(_coordinate, _coordinate), min_size=3, max_size=3)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_triangle, st.sampled_from([1, 4, 15]), st.booleans())
@example([(0.5, 0.5), (5.5, 1.5), (1.25, 5.25)], 15, True)
@example([(0.0, 0.0), (6.0, 0.0), (0.0, 6.0)], 15, True)
def test_the_compiled_oracle_is_the_rational_reference(vertices, rows, full_rows):
    triangle = np.array(vertices, dtype=np.float64)
    convention = Convention(coverage="area", rows=rows, full_rows=full_rows)
    image = _dense(row_sampled_coverage(Scene(W, H, triangle[None]), convention))
    for y in range(H):
        for x in range(W):
            exact = exact_row_sampled_alpha(triangle, x, y, rows, full_rows, surface=(W, H))
            assert abs(image[y, x] - float(exact)) < 1e-9, (x, y)


def test_the_mean_of_one_row_is_a_point_sample_in_y_and_many_rows_tend_to_the_area():
    triangle = np.array([[0.3, 0.2], [5.7, 1.4], [1.1, 5.9]])
    for x, y in [(1, 1), (3, 1), (0, 4)]:
        area = exact_area(triangle, x, y)
        coarse = exact_row_sampled_alpha(triangle, x, y, 4)
        fine = exact_row_sampled_alpha(triangle, x, y, 256)
        assert abs(fine - area) <= abs(coarse - area) + Fraction(1, 1000)
        assert abs(fine - area) < Fraction(1, 200)


def test_a_row_sampled_convention_is_declared_once_and_described():
    convention = Convention(coverage="area", rows=15, full_rows=True, input="fixed8")
    assert convention.model is ROW_SAMPLED_AREA and model_for("area", False, 15) is ROW_SAMPLED_AREA
    assert convention.coverage_kind == "area" if hasattr(convention, "coverage_kind") else True
    assert "15 cross-sections per pixel row" in convention.describe()
    assert "rows=15, full_rows=True" in repr(convention)
    assert Convention(coverage="area").model is not ROW_SAMPLED_AREA  # rows=0 changes nothing
    bads: list[dict[str, Any]] = [dict(coverage="sample", rows=15), dict(coverage="area", rows=15, samples=4),
                                  dict(coverage="area", full_rows=True), dict(coverage="area", rows=-1),
                                  dict(coverage="area", rows=300)]
    for bad in bads:
        with pytest.raises(ValueError):
            Convention(**bad)


def test_the_oracle_applies_the_input_grid_and_culling():
    scene = Scene(W, H, [[[0.3, 0.2], [5.7, 1.4], [1.1, 5.9]]])
    fixed = Convention(coverage="area", rows=15, input="fixed2")
    snapped = Scene(W, H, np.round(scene.positions * 4) / 4)
    assert np.array_equal(_dense(exact_coverage(scene, fixed)),
                          _dense(exact_coverage(snapped, Convention(coverage="area", rows=15))))
    culled = Convention(coverage="area", rows=15, cull="cw")
    assert _dense(exact_coverage(scene, culled)).sum() == 0


def test_cairo_alpha_levels_round_the_grid_area_half_up():
    c = np.arange(7681)
    assert np.array_equal(cairo_alpha_levels(c / 7680), (c * 255 + 3840) // 7680)


def test_zero_area_and_non_finite_triangles_cover_nothing():
    scene = Scene(W, H, np.array([[[0, 0], [3, 3], [6, 6]], [[np.nan, 0], [3, 3], [1, 6]]]))
    alpha = row_sampled_coverage(scene, Convention(coverage="area", rows=15)).alpha
    assert alpha is not None and alpha.size == 0


@functools.cache
def _cases() -> list[Any]:
    return [c for c in suite("quick") if c.id.startswith(("float/random", "lattice/bits-2"))][:3]


class _Exact:
    name = "exact_rows15"
    convention = Convention(coverage="area", rows=15)
    interpolates = False

    def rasterize(self, scene: Scene) -> Any:
        exact = row_sampled_coverage(scene, self.convention)
        assert exact.alpha is not None
        return type(exact)(exact.triangle, exact.y, exact.x0, exact.x1, alpha=np.rint(exact.alpha * 255) / 255)


@pytest.mark.parametrize("rasterizer, passes", [(_Exact(), True), (RowsAtTopEdges(), False), (RowsTruncatedLevels(), False),
                                                (HybridSamplesEveryRow(), False)],
                         ids=["exact", "rows-at-top-edges", "truncated-levels", "hybrid-samples-every-row"])
def test_accuracy_judges_the_row_sampled_model_and_catches_its_known_bads(rasterizer, passes):
    assert_judged_by_accuracy(rasterizer, _cases(), passes)


def test_accuracy_of_a_row_sampled_answer_against_the_analytic_area_fails():
    """The models are told apart: an exact row sampler is off the analytic area on shallow edges."""
    scene = Scene(64, 4, [[[0.0, 0.3], [64.0, 1.2], [0.0, 3.7]]])
    rows = _dense(row_sampled_coverage(scene, Convention(coverage="area", rows=15)), 64, 4)
    area = _dense(exact_coverage(scene, Convention(coverage="area")), 64, 4)
    assert np.abs(rows - area).max() > 4 / 255


# -- identify tells the models apart from outside ------------------------------------------------


@pytest.mark.parametrize("hidden", [Convention(coverage="area", rows=15), Convention(coverage="area", rows=15, full_rows=True),
                                    Convention(coverage="area", rows=5)], ids=["rows15", "cairo-hybrid15", "rows5"])
def test_identify_recovers_a_row_sampled_model_and_its_rows(hidden):
    from harness.engine.isolation import InProcess
    from harness.identify.area_probes import alpha_sweeps
    from tests.identify.test_coverage_probes import Hidden

    fact = alpha_sweeps(InProcess(Hidden(hidden, 256)))
    assert fact.model == "hybrid" and fact.convention is not None
    assert fact.convention.rows == hidden.rows and fact.convention.full_rows == hidden.full_rows, fact.convention
    assert fact.residual == 0, fact.residual


def test_identify_keeps_the_analytic_area_for_an_analytic_anti_aliaser():
    from harness.engine.isolation import InProcess
    from harness.identify.area_probes import alpha_sweeps
    from tests.identify.test_coverage_probes import Hidden

    fact = alpha_sweeps(InProcess(Hidden(Convention(coverage="area"), 256)))
    assert fact.convention is not None and fact.convention.rows == 0


def test_cairo_draws_its_hybrid_model_within_one_level():
    """The model against the library itself (pycairo, A8 surface, ANTIALIAS_DEFAULT): every
    alpha within one level of cairo's hybrid on random float triangles, shallow ones included
    (the analytic area is up to 17 levels off, all rows sampled 17 too)."""
    pytest.importorskip("cairo")
    from rasterizers.real.adapters import CairoAntialiased

    cairo = CairoAntialiased()
    convention = Convention(coverage="area", rows=15, full_rows=True, input="fixed8")
    rng = np.random.default_rng(7)
    worst = 0.0
    for t in range(40):
        triangle = rng.uniform(2, 22, (1, 3, 2))
        if t % 2:
            triangle[0, :, 1] = rng.uniform(5, 9, 3)  # shallow edges: full rows differ most
        scene = Scene(24, 24, triangle)
        got = _dense(cairo.rasterize(scene), 24, 24)
        want = _dense(exact_coverage(scene, convention), 24, 24)
        worst = max(worst, float(np.abs(got - np.floor(want * 255 + 0.5) / 255).max()))
    assert worst <= 1 / 255 + 1e-12, worst * 255


def test_identify_tells_a_hybrid_that_samples_every_row_from_the_one_it_claims():
    from harness.engine.isolation import InProcess
    from harness.identify.area_probes import alpha_sweeps

    fact = alpha_sweeps(InProcess(HybridSamplesEveryRow()))
    assert fact.convention is not None and fact.convention.rows == 15 and not fact.convention.full_rows


def test_identify_recovers_cairos_hybrid_exactly():
    """Issue 34: cairo's alphas are its hybrid's, every probe pixel (analytic area: 20,610
    of 61,287 beyond half a level, at best within 0.0664)."""
    pytest.importorskip("cairo")
    from harness.engine.isolation import InProcess
    from harness.identify.area_probes import alpha_sweeps
    from rasterizers.real.adapters import CairoAntialiased

    fact = alpha_sweeps(InProcess(CairoAntialiased()))
    assert fact.convention is not None and (fact.convention.rows, fact.convention.full_rows) == (15, True)
    assert fact.residual == 0 and fact.max_residual <= 0.5 / 255 + 1e-9


@pytest.mark.parametrize("bits", [6, 8])
def test_identify_recovers_an_input_grid_before_the_analytic_area(bits):
    """FreeType's and Qt's 26.6 input: Convention(coverage="area", input="fixed6") -- the area
    oracle applies the input (Convention.snap) and identify reads the grid back, as the
    equivalent snapping to 2**-bits px, ties to even."""
    from harness.engine.isolation import InProcess
    from harness.identify.area_probes import alpha_sweeps
    from tests.identify.test_coverage_probes import Hidden

    hidden = Convention(coverage="area", input=f"fixed{bits}")
    fact = alpha_sweeps(InProcess(Hidden(hidden, 256)))
    assert fact.convention is not None and fact.residual == 0
    assert (fact.convention.subpixel_bits, fact.convention.snap_rounding) == (bits, "nearest-even")
