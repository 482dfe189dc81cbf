"""AGG 2.0 through aggdraw (rasterizers.real.agg): ``agg`` (aliased: a pixel iff at
least half of it is covered) and ``agg_aa`` (area coverage), compared with the exact area
of each pixel; aggdraw's 0.5 px widening of fills turned off."""

import sys
import time

import numpy as np
import pytest

from harness.contract.protocol import receive
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from rasterizers.real import agg
from tests.optional import need
from tests.rasterizers.real._agg_probe import PROBE, H, W, exact_areas, image, margin_of_probe


@pytest.fixture
def aliased():
    need("aggdraw")
    return agg.AggAliased()


@pytest.fixture
def antialiased():
    need("aggdraw")
    return agg.AggAntialiased()


@pytest.mark.parametrize("cls", ["AggAliased", "AggAntialiased"])
def test_a_missing_library_makes_the_adapter_unavailable(monkeypatch, cls):
    monkeypatch.setitem(sys.modules, "aggdraw", None)  # import raises ImportError
    with pytest.raises(Unavailable, match="aggdraw is not installed"):
        getattr(agg, cls)()


def test_names_and_modes(aliased, antialiased):
    assert (aliased.name, antialiased.name) == ("agg", "agg_aa")
    assert aliased.library == antialiased.library == "AGG (aggdraw)"
    assert aliased.library_version.startswith("aggdraw ")
    assert (aliased.coverage_kind, antialiased.coverage_kind) == ("single", "area")
    assert aliased.fill_rules == ("nonzero",) and aliased.convention is None and antialiased.convention is None


def test_agg_pixels_of_a_quarter_offset_triangle(aliased):
    """The coordinate mapping: exactly the pixels at least half covered by the probe
    triangle (none lies within 0.057 of half), so no half-pixel shift, flip or
    transposition."""
    assert margin_of_probe() > 0.05
    drawn = image(aliased.rasterize(Scene(W, H, [PROBE])))
    assert np.array_equal(drawn > 0, exact_areas([PROBE]) >= 0.5)
    assert drawn.max() == 1  # one span per pixel


def test_agg_aa_alphas_of_a_quarter_offset_triangle(antialiased):
    """The coordinate mapping in the AA mode: each alpha within 2/255 + 1/256 of the exact
    area (AGG's floor(256 area) blended by the gray-8 format, (255 cover) >> 8), nothing
    drawn elsewhere."""
    alphas = image(antialiased.rasterize(Scene(W, H, [PROBE])))
    areas = exact_areas([PROBE])
    assert np.abs(alphas - areas).max() <= 2 / 255 + 1 / 256
    assert np.array_equal(alphas > 0, areas > 0)


def test_the_default_widening_is_off(antialiased):
    """aggdraw's fill without a pen is the polygon grown by 0.25 px on every side (0.5 px
    wider and taller: ``conv_contour.width(0.5)``, which offsets by half the width): a
    4 x 4 square on whole pixels gets a ring of pixels a quarter covered (63/255) that way;
    the adapter's is the square alone."""
    aggdraw = need("aggdraw")
    draw = aggdraw.Draw("L", (W, H), 0)
    draw.polygon((4, 4, 8, 4, 8, 8, 4, 8), aggdraw.Brush(255))
    default = np.frombuffer(draw.tobytes(), np.uint8).reshape(H, W)
    assert default[4:8, 4:8].min() == 255 and default[3, 4:8].tolist() == [63] * 4 and default[3, 3] == 15
    square = np.array([[4.0, 4.0], [8.0, 4.0], [8.0, 8.0], [4.0, 8.0]])
    drawn = image(antialiased.rasterize(Scene(W, H, [square[:3], square[[0, 2, 3]]])))
    assert drawn[4:8, 4:8].min() > 0.99 and drawn.sum() == pytest.approx(16, abs=0.1)
    drawn[4:8, 4:8] = 0
    assert not drawn.any()


def test_nonzero_paths(aliased):
    """Two overlapping squares of one orientation (whole pixels: each pixel covered wholly
    or not at all) fill their union, overlap included (nonzero); a pentagram its centre."""
    a = [[2, 2], [8, 2], [8, 8], [2, 8]]
    b = [[5, 5], [11, 5], [11, 11], [5, 11]]
    drawn = image(aliased.rasterize(PathScene.from_paths(W, H, [[a, b]])))
    union = np.zeros((H, W), dtype=bool)
    union[2:8, 2:8] = union[5:11, 5:11] = True
    assert np.array_equal(drawn > 0, union)
    angles = 2 * np.pi * np.arange(5) * 2 / 5
    star = np.c_[6 + 5 * np.sin(angles), 6.2 - 5 * np.cos(angles)]
    assert image(aliased.rasterize(PathScene.from_paths(W, H, [[star]])))[6, 6] == 1


def test_even_odd_is_refused(aliased):
    """aggdraw never sets AGG's filling rule: even-odd paths are not taken."""
    with pytest.raises(Unsupported, match="nonzero"):
        aliased.rasterize(PathScene.from_paths(W, H, [[[[2, 2], [8, 2], [8, 8]]]], fill_rule="evenodd"))


def test_lines_are_half_covered_pixels_of_the_stroke_rectangle(aliased):
    """A 1 px wide butt-capped stroke is the rectangle around the segment: a horizontal
    segment at y = 2.25 from x = 1.5 to 6.5 covers rows [1.75, 2.75]; the pixels at least
    half covered are row 2, columns 2..5 (the end columns are 0.375 covered). A vertical
    one the same, transposed."""
    cov = aliased.rasterize(LineScene.from_segments(W, H, [[1.5, 2.25], [9.25, 1.5]], [[6.5, 2.25], [9.25, 6.5]]))
    t, x, y = cov.pixels()
    assert sorted(zip(t.tolist(), x.tolist(), y.tolist())) == (
        [(0, c, 2) for c in range(2, 6)] + [(1, 9, r) for r in range(2, 6)])


def test_wide_lines_are_rectangles(aliased):
    """Width 3 from (2, 5.5) to (8, 5.5): the rectangle [2, 8] x [4, 7], whole pixels."""
    cov = aliased.rasterize(LineScene.from_segments(W, H, [[2.0, 5.5]], [[8.0, 5.5]], line_width=3.0))
    drawn = image(cov)
    assert drawn[4:7, 2:8].all() and drawn.sum() == 18


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_triangle_draws_nothing_at_once(aliased, antialiased, bad):
    """AGG truncates the coordinate to an int (INT_MIN on x86) and its clipper drops the
    triangle: nothing drawn, no hang; the finite triangle beside it is drawn."""
    scene = Scene(W, H, np.array([[[bad, 1.25], [6.25, 2.25], [2.25, 6.25]], PROBE]))
    for adapter in (aliased, antialiased):
        start = time.perf_counter()
        cov = adapter.rasterize(scene)
        assert time.perf_counter() - start < 5
        assert set(cov.triangle.tolist()) == {1}


def test_received_truncates_to_24_8_toward_zero(aliased):
    scene = Scene(W, H, [[[1 / 512, -1 / 512], [3 - 1e-9, -(3 - 1e-9)], [5.5, 0.75]]])
    got = receive(aliased, scene).positions[0]
    assert got.tolist() == [[0.0, 0.0], [3 - 1 / 256, -(3 - 1 / 256)], [5.5, 0.75]]
