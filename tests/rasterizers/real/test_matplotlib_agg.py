"""matplotlib's Agg backend (rasterizers.real.matplotlib_agg): ``matplotlib_agg``
(aliased: every pixel any of which is covered) and ``matplotlib_agg_aa`` (area
coverage), compared with the exact area of each pixel."""

import sys
import time

import numpy as np
import pytest

from harness.contract.protocol import receive
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from rasterizers.real import matplotlib_agg
from tests.optional import need
from tests.rasterizers.real._agg_probe import PROBE, H, W, exact_areas, image, margin_of_probe


@pytest.fixture
def aliased():
    need("matplotlib")
    return matplotlib_agg.MatplotlibAgg()


@pytest.fixture
def antialiased():
    need("matplotlib")
    return matplotlib_agg.MatplotlibAggAntialiased()


@pytest.mark.parametrize("cls", ["MatplotlibAgg", "MatplotlibAggAntialiased"])
def test_a_missing_library_makes_the_adapter_unavailable(monkeypatch, cls):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import raises ImportError
    with pytest.raises(Unavailable, match="matplotlib is not installed"):
        getattr(matplotlib_agg, cls)()


def test_names_and_modes(aliased, antialiased):
    assert (aliased.name, antialiased.name) == ("matplotlib_agg", "matplotlib_agg_aa")
    assert aliased.library == antialiased.library == "AGG (matplotlib)"
    assert aliased.library_version.startswith("matplotlib ")
    assert (aliased.coverage_kind, antialiased.coverage_kind) == ("single", "area")
    assert aliased.fill_rules == ("nonzero",) and aliased.convention is None and antialiased.convention is None


def test_matplotlib_agg_pixels_of_a_quarter_offset_triangle(aliased):
    """The coordinate mapping (matplotlib's y flip cancelled): exactly the pixels the
    probe triangle touches (each at least 0.057 covered), so no half-pixel shift, flip or
    transposition."""
    assert margin_of_probe() > 0.05
    drawn = image(aliased.rasterize(Scene(W, H, [PROBE])))
    assert np.array_equal(drawn > 0, exact_areas([PROBE]) > 0)
    assert drawn.max() == 1


def test_matplotlib_agg_aa_alphas_of_a_quarter_offset_triangle(antialiased):
    """The mapping in the AA mode: each alpha within 1/255 + 1/256 of the exact area
    (AGG's floor(256 area), capped at 255, read as value / 255), nothing elsewhere."""
    alphas = image(antialiased.rasterize(Scene(W, H, [PROBE])))
    areas = exact_areas([PROBE])
    assert np.abs(alphas - areas).max() <= 1 / 255 + 1 / 256
    assert np.array_equal(alphas > 0, areas > 0)


def test_nonzero_paths(aliased):
    """Two overlapping squares of one orientation on whole pixels fill their union (the
    overlap too: nonzero); a pentagram its centre; even-odd is not taken."""
    a = [[2, 2], [8, 2], [8, 8], [2, 8]]
    b = [[5, 5], [11, 5], [11, 11], [5, 11]]
    drawn = image(aliased.rasterize(PathScene.from_paths(W, H, [[a, b]])))
    union = np.zeros((H, W), dtype=bool)
    union[2:8, 2:8] = union[5:11, 5:11] = True
    assert np.array_equal(drawn > 0, union)
    angles = 2 * np.pi * np.arange(5) * 2 / 5
    star = np.c_[6 + 5 * np.sin(angles), 6.2 - 5 * np.cos(angles)]
    assert image(aliased.rasterize(PathScene.from_paths(W, H, [[star]])))[6, 6] == 1
    with pytest.raises(Unsupported, match="nonzero"):
        aliased.rasterize(PathScene.from_paths(W, H, [[a]], fill_rule="evenodd"))


def test_lines_are_the_touched_pixels_of_the_stroke_rectangle(aliased):
    """A 1 pt (1 px at 72 dpi) butt-capped stroke is the rectangle around the segment: a
    horizontal segment at y = 2.25 from x = 1.5 to 6.5 covers [1.5, 6.5] x [1.75, 2.75]:
    rows 1 and 2, columns 1..6, every one touched; a vertical one the same, transposed."""
    cov = aliased.rasterize(LineScene.from_segments(W, H, [[1.5, 2.25], [9.25, 1.5]], [[6.5, 2.25], [9.25, 6.5]]))
    t, x, y = cov.pixels()
    assert sorted(zip(t.tolist(), x.tolist(), y.tolist())) == sorted(
        [(0, c, r) for c in range(1, 7) for r in (1, 2)] + [(1, c, r) for c in (8, 9) for r in range(1, 7)])


def test_wide_lines_are_rectangles(aliased):
    """Width 3 from (2, 5.5) to (8, 5.5): the rectangle [2, 8] x [4, 7], whole pixels."""
    drawn = image(aliased.rasterize(LineScene.from_segments(W, H, [[2.0, 5.5]], [[8.0, 5.5]], line_width=3.0)))
    assert drawn[4:7, 2:8].all() and drawn.sum() == 18


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_triangle_draws_nothing_at_once(aliased, antialiased, bad):
    """matplotlib removes non-finite vertices (PathNanRemover): the two finite ones left
    enclose nothing; no hang; the finite triangle beside it is drawn."""
    scene = Scene(W, H, np.array([[[bad, 1.25], [6.25, 2.25], [2.25, 6.25]], PROBE]))
    for adapter in (aliased, antialiased):
        start = time.perf_counter()
        cov = adapter.rasterize(scene)
        assert time.perf_counter() - start < 5
        assert set(cov.triangle.tolist()) == {1}


def test_received_rounds_to_24_8_half_away_from_zero(aliased):
    scene = Scene(W, H, [[[1 / 512, -1 / 512], [3 / 512, -3 / 512], [5.5, 0.75 + 1 / 1024]]])
    got = receive(aliased, scene).positions[0]
    assert got.tolist() == [[1 / 256, -1 / 256], [2 / 256, -2 / 256], [5.5, 0.75]]
