"""The analytic libraries' models (issue 34): the quantisations read from their sources, the
compiled oracle against the rational reference, the convention's declaration, and the
known-bad ports caught by accuracy."""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from cases.suites import suite
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import AREA, QUANTISED_AREA, model_for
from harness.contract.quantisations import QUANTISATIONS, quantisation_named
from harness.contract.scenes import Scene
from harness.oracle.analytic_models import exact_level, levels_of, quantised_area_coverage
from harness.oracle.area import exact_area
from harness.oracle.coverage import exact_coverage
from tests.accuracy_runs import assert_judged_by_accuracy, dense_alphas
from tests.known_bad.analytic_models import ComplementsWhereQtNegates, FloorsWhereBlend2DScales, RoundsWhereFreeTypeFloors

W = H = 6
NAMES = list(QUANTISATIONS)


def _dense(coverage: Coverage, width: int = W, height: int = H) -> np.ndarray:
    return dense_alphas(coverage, width, height)  # type: ignore[no-any-return]


# -- the quantisations, as their C reads ------------------------------------------------------------


def _ftgrays(k: int, evenodd: bool) -> int:
    """ftgrays.c FT_FILL_RULE then the (unsigned char) store, on a 64-bit two's complement."""
    fill = 0x100 if evenodd else -(2**31)
    coverage = k
    if coverage & fill:
        coverage = ~coverage
    if coverage > 255 and fill & -(2**31):
        coverage = 255
    return coverage & 0xFF


def _qt(k: int, evenodd: bool) -> int:
    """qgrayraster.c gray_hline."""
    coverage = -k if k < 0 else k
    if evenodd:
        coverage &= 511
        if coverage > 256:
            coverage = 512 - coverage
        elif coverage == 256:
            coverage = 255
    elif coverage >= 256:
        coverage = 255
    return coverage


def _aggdraw(k: int, evenodd: bool) -> int:
    """AGG 2 calculate_alpha (linear gamma), then pixfmt_gray8's blend of 255 over 0."""
    cover = -k if k < 0 else k
    if evenodd:
        cover &= 511
        if cover > 256:
            cover = 512 - cover
    cover = min(cover, 255)
    alpha = cover * 255
    return 255 if alpha == 255 * 255 else (255 * alpha) >> 16


def _blend2d(k: int, evenodd: bool) -> int:
    """fillgeneric_p.h calc_mask: cov biased by 256 << 9, global alpha 255 (32-bit wrap)."""
    mask = 0x1FF if evenodd else 0xFFFFFFFF
    m = (((256 + k) & mask) - 256) & 0xFFFFFFFF
    signed = m - 2**32 if m >= 2**31 else m
    return min(abs(signed), 256) * 255 >> 8


@pytest.mark.parametrize("name, port", [("ftgrays", _ftgrays), ("cells-abs", _qt), ("cells-abs-gray8", _aggdraw),
                                        ("blend2d", _blend2d)])
def test_each_quantisation_is_its_librarys_integer_steps(name, port):
    q = quantisation_named(name)
    k = np.arange(-1100, 1101)
    for evenodd in (False, True):
        rule = "evenodd" if evenodd else "nonzero"
        want = [port(int(v), evenodd) for v in k]
        assert [q.level(int(v), rule) for v in k] == want
        assert levels_of(q, k, rule).tolist() == want


def test_the_quantisations_differ_where_identify_parts_them():
    # floor(256 S) = 128, both signs: FreeType complements a negative k, the others negate it
    assert [q.level(128) for q in QUANTISATIONS.values()] == [128, 128, 127, 127]
    assert [q.level(-128) for q in QUANTISATIONS.values()] == [127, 128, 127, 127]
    # between: the gray-8 blend loses two levels above 128, Blend2D one
    assert [q.level(200) for q in QUANTISATIONS.values()] == [200, 200, 198, 199]


# -- the oracle against the rational reference ---------------------------------------------------

# vertices on 1/64 px (areas k/256 hit on purpose: crossings at pixel corners) and on 1/10 px
_coordinate = st.one_of(st.integers(0, 6 * 64).map(lambda v: v / 64), st.integers(0, 60).map(lambda v: v / 10),
                        st.integers(0, 6).map(float))
_triangle = st.lists(st.tuples(_coordinate, _coordinate), min_size=3, max_size=3)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_triangle, st.sampled_from(NAMES))
@example([(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)], "ftgrays")
@example([(0.0, 0.0), (0.0, 2.0), (2.0, 0.0)], "ftgrays")
@example([(0.0, 0.0), (4.0, 0.0), (0.0, 2.0)], "cells-abs")
@example([(0.0, 0.0), (0.0, 2.0), (4.0, 0.0)], "blend2d")
def test_the_compiled_oracle_is_the_rational_reference(vertices, name):
    triangle = np.array(vertices, dtype=np.float64)
    convention = Convention(coverage="area", quantisation=name)
    image = _dense(quantised_area_coverage(Scene(W, H, triangle[None]), convention))
    q = quantisation_named(name)
    for y in range(H):
        for x in range(W):
            level = exact_level(triangle, x, y, name)
            assert image[y, x] == level / 255, (x, y, image[y, x] * 255, level)
            # the reference is the definition: floor(256 S) of the rational signed area, then the level
            area = exact_area(triangle, x, y)
            if area:
                clockwise = (triangle[1, 0] - triangle[0, 0]) * (triangle[2, 1] - triangle[0, 1]) > \
                    (triangle[1, 1] - triangle[0, 1]) * (triangle[2, 0] - triangle[0, 0])
                assert level == q.level(math.floor(256 * area * q.signed(bool(clockwise))))


def test_levels_are_decided_exactly_where_the_area_is_a_whole_number_of_256ths():
    # a sliver of area exactly 1/256 in pixel (0, 0), clockwise and counter-clockwise on screen
    sliver = np.array([[0.0, 0.0], [1 / 128, 0.0], [0.0, 1.0]])
    want = {"ftgrays": (1, 0), "cells-abs": (1, 1), "cells-abs-gray8": (0, 0), "blend2d": (0, 0)}
    for name in NAMES:
        convention = Convention(coverage="area", quantisation=name)
        got = tuple(int(_dense(quantised_area_coverage(Scene(2, 2, tri[None]), convention), 2, 2)[0, 0] * 255)
                    for tri in (sliver, sliver[::-1]))
        assert got == want[name] == (exact_level(sliver, 0, 0, name), exact_level(sliver[::-1], 0, 0, name)), name


def test_the_oracle_applies_the_input_grid_and_culling():
    scene = Scene(W, H, [[[0.3, 0.2], [5.7, 1.4], [1.1, 5.9]]])
    fixed = Convention(coverage="area", quantisation="ftgrays", input="fixed6")
    snapped = Scene(W, H, np.rint(scene.positions * 64) / 64)
    assert np.array_equal(_dense(exact_coverage(scene, fixed)),
                          _dense(exact_coverage(snapped, Convention(coverage="area", quantisation="ftgrays"))))
    culled = Convention(coverage="area", quantisation="blend2d", cull="cw")
    assert _dense(exact_coverage(scene, culled)).sum() == 0


def test_zero_area_and_non_finite_triangles_cover_nothing():
    scene = Scene(W, H, np.array([[[0, 0], [3, 3], [6, 6]], [[np.nan, 0], [3, 3], [1, 6]]]))
    alpha = quantised_area_coverage(scene, Convention(coverage="area", quantisation="cells-abs")).alpha
    assert alpha is not None and alpha.size == 0


def test_a_quantised_convention_is_declared_once_and_described():
    convention = Convention(coverage="area", quantisation="ftgrays", input="fixed6", tolerance=1 / 255)
    assert convention.model is QUANTISED_AREA and model_for("area", False, quantisation="ftgrays") is QUANTISED_AREA
    assert Convention(coverage="area").model is AREA  # the default changes nothing
    assert Convention(coverage="area").quantisation == "nearest"
    assert "ftgrays level" in convention.describe() and "quantisation='ftgrays'" in repr(convention)
    bads: list[dict[str, Any]] = [dict(coverage="sample", quantisation="ftgrays"), dict(coverage="area", quantisation="x"),
                                  dict(coverage="area", samples=4, quantisation="blend2d"),
                                  dict(coverage="area", rows=15, quantisation="blend2d"),
                                  dict(coverage="area", levels=17, quantisation="blend2d")]
    for bad in bads:
        with pytest.raises(ValueError):
            Convention(**bad)


# -- accuracy against the declared model, and the known-bads -----------------------------------------


@functools.cache
def _cases() -> list[Any]:
    return [c for c in suite("quick") if c.id.startswith(("float/random", "lattice/bits-2"))][:3]


class _ExactPort:
    """A port of ftgrays' levels that is right: the oracle's own answer."""

    name = "exact_ftgrays"
    convention = Convention(coverage="area", quantisation="ftgrays", input="fixed6")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return quantised_area_coverage(scene, self.convention)


@pytest.mark.parametrize("rasterizer, passes", [(_ExactPort(), True), (RoundsWhereFreeTypeFloors(), False),
                                                (ComplementsWhereQtNegates(), False), (FloorsWhereBlend2DScales(), False)],
                         ids=["exact", "rounds-where-freetype-floors", "complements-where-qt-negates",
                              "floors-where-blend2d-scales"])
def test_accuracy_judges_the_declared_levels_and_catches_the_known_bads(rasterizer, passes):
    assert_judged_by_accuracy(rasterizer, _cases(), passes)


def test_the_analytic_area_rounded_is_not_a_librarys_levels():
    """The models are told apart: FreeType's levels are not the nearest level of the area."""
    scene = Scene(W, H, [[[0.3, 0.2], [5.7, 1.4], [1.1, 5.9]]])
    nearest = np.rint(_dense(exact_coverage(scene, Convention(coverage="area"))) * 255)
    for name in NAMES:
        levels = np.rint(_dense(exact_coverage(scene, Convention(coverage="area", quantisation=name))) * 255)
        assert (levels != nearest).any(), name


_wide = st.one_of(_coordinate, st.floats(-1e6, 1e6, allow_nan=False), st.floats(-1e-300, 1e-300, allow_nan=False))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(_wide, _wide), min_size=3, max_size=3), st.integers(-2, 6), st.integers(-2, 6))
@example([(0.0, 0.0), (1e-300, 0.0), (0.0, 1e6)], 0, 0)
def test_the_integer_area_is_the_rational_area(vertices, x, y):
    from harness.oracle.analytic_models import _integer_area

    triangle = np.array(vertices, dtype=np.float64)
    assert _integer_area(triangle, x, y) == exact_area(triangle, x, y)


# -- where FreeType leaves its model: the crossings' truncation ---------------------------------------


def test_freetypes_two_level_pixels_are_its_truncated_crossings():
    """The quick suite's lattice/bits-0 pixels FreeType 2.13.2 draws two levels off its model
    (the exact area's ftgrays level on the 26.6 input: integer vertices, received exactly):
    FreeType's cell arithmetic, ported (tests/oracle/ftgrays_cells.py), gives FreeType's
    levels (measured: 130, 80, 129), each crossing truncated to 1/256 px by FT_UDIV."""
    from tests.oracle import ftgrays_cells

    for triangle, x, y, model, measured in (([[48.0, 64.0], [33.0, 38.0], [63.0, 19.0]], 62, 19, 132, 130),
                                            ([[25.5, 55.5], [-2.0, 53.0], [51.0, 24.0]], 50, 24, 82, 80),
                                            ([[52.0, 10.0], [22.0, 43.0], [37.0, 11.0]], 51, 10, 131, 129)):
        t = np.array(triangle)
        assert exact_level(t, x, y, "ftgrays") == model
        assert ftgrays_cells.level(t, x, y)[0] == measured


def test_the_ftgrays_port_draws_what_freetype_draws():
    """The port against the library: every pixel of random 26.6 triangles in both windings
    (FreeType smooth; skipped without it)."""
    from tests.optional import need

    need("freetype")
    from rasterizers.real.freetype_outline import FreeTypeSmooth
    from tests.oracle import ftgrays_cells

    rng = np.random.default_rng(3)
    triangles = np.rint(rng.uniform(1, 15, (12, 3, 2)) * 64) / 64
    triangles[6:] = triangles[6:, ::-1]
    scene = Scene(16, 16, triangles)
    got = FreeTypeSmooth().rasterize(scene)
    t, x, y = got.pixels()
    assert got.alpha is not None
    for k in range(t.size):
        assert round(float(got.alpha[k]) * 255) == ftgrays_cells.level(triangles[t[k]], int(x[k]), int(y[k]))[0]


# -- pixels wholly inside: decided by exact corner signs, the rationals' answer ------------------

# vertices on 1/4 px and whole pixels (corners on edges on purpose) and on 1/10 px, both windings
_wide_coordinate = st.one_of(st.integers(-8, 10 * 4).map(lambda v: v / 4), st.integers(-2, 10).map(float),
                             st.integers(-10, 100).map(lambda v: v / 10))


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(_wide_coordinate, _wide_coordinate), min_size=3, max_size=3))
@example([(0.0, 0.0), (8.0, 0.0), (0.0, 8.0)])  # pixels with a corner on the hypotenuse
@example([(0.0, 0.0), (0.0, 8.0), (8.0, 0.0)])
@example([(-2.0, -2.0), (10.0, -2.0), (-2.0, 10.0)])  # beyond the viewport: every pixel in view whole
@example([(0.0, 0.0), (1e300, 0.0), (0.0, 8.0)])  # beyond the exact signs' safe range: the rationals decide
def test_a_pixel_wholly_inside_is_told_by_corner_signs_as_the_rationals_tell_it(vertices):
    from harness.geometry.exact import orientation
    from harness.oracle.analytic_models import _integer_area, _whole_pixels

    triangle = np.array(vertices, dtype=np.float64)
    safe = np.empty(1, dtype=np.bool_)
    sign = orientation(triangle[None], safe)
    ys, xs = np.mgrid[0:8, 0:8]
    x, y = xs.ravel().astype(np.int64), ys.ravel().astype(np.int64)
    inside = np.empty(x.size, dtype=np.bool_)
    _whole_pixels(triangle[None], sign, safe, np.zeros(x.size, dtype=np.int64), x, y, np.arange(x.size), inside)
    for i in range(x.size):
        whole = _integer_area(triangle, int(x[i]), int(y[i])) == 1
        # said whole only when it is; every whole pixel of a triangle within the safe range is said so
        assert inside[i] == (whole and bool(safe[0]) and sign[0] != 0), (x[i], y[i], inside[i], whole)
    # and the oracle's levels are the rational reference's there
    for name in NAMES:
        image = _dense(quantised_area_coverage(Scene(8, 8, triangle[None]), Convention(coverage="area", quantisation=name)),
                       8, 8)
        for j in np.flatnonzero(inside).tolist():
            assert image[y[j], x[j]] == exact_level(triangle, int(x[j]), int(y[j]), name) / 255
