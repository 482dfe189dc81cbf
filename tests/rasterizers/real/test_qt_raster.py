"""Qt's raster paint engine (rasterizers.real.qt_raster, PyQt6): the coordinate mapping of
both modes, the fill rules, cosmetic lines, NaN input and the upstream repro."""

import math
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.protocol import takes
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from harness.oracle.area import area_coverage
from harness.oracle.coverage import exact_coverage
from rasterizers.real import qt_raster
from tests.optional import need

ROOT = Path(__file__).parents[3]
W = H = 32
# what the scan converter does (qrasterizer.cpp): centre samples, bottom-right ties,
# vertices to 26.6 with qRound (the quarter-pixel vertices below are on that grid)
QT = Convention(tie="bottom-right", subpixel_bits=6, snap_rounding="half-away")


@pytest.fixture(scope="module")
def qt():
    need("PyQt6")
    return qt_raster.QtRaster()


@pytest.fixture(scope="module")
def qt_aa():
    need("PyQt6")
    return qt_raster.QtAntialiased()


def quarter_triangles(n, seed, margin=1 / 16):
    """n triangles with vertices on integer-plus-1/4 positions (no flip, transposition or
    half-pixel shift maps them onto themselves), each with every pixel centre of the screen
    at least ``margin`` px from its edges' lines (far from ties and from the scan
    converter's slope drift), and area above 4 px."""
    rng = np.random.default_rng(seed)
    centres = np.stack(np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5), axis=-1).reshape(-1, 2)
    found: list[np.ndarray] = []
    while len(found) < n:
        p = rng.integers(0, W - 1, size=(3, 2)) + 0.25
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if abs(area) < 8:
            continue
        far = True
        for a, b in ((p[0], p[1]), (p[1], p[2]), (p[2], p[0])):
            d = b - a
            distance = np.abs(d[0] * (centres[:, 1] - a[1]) - d[1] * (centres[:, 0] - a[0])) / np.hypot(*d)
            far &= bool(distance.min() >= margin)
        if far:
            found.append(p)
    return np.array(found)


def pentagram(cx, cy, r):
    """A pentagram {5/2}: its centre has winding 2, its points winding 1."""
    a = 2 * np.pi * np.arange(5) * 2 / 5
    return np.c_[cx + r * np.sin(a), cy - r * np.cos(a)]


def test_declarations():
    assert qt_raster.QtRaster.name == "qt" and qt_raster.QtAntialiased.name == "qt_aa"
    assert qt_raster.QtRaster.library == qt_raster.QtAntialiased.library == "Qt"
    assert qt_raster.QtRaster.coverage_kind == "single" and qt_raster.QtAntialiased.coverage_kind == "area"
    assert qt_raster.QtRaster.convention is None and qt_raster.QtAntialiased.convention is None  # identified
    assert qt_raster.QtRaster.scene_kinds == ("triangles", "paths", "lines")
    assert qt_raster.QtRaster.fill_rules == ("nonzero", "evenodd") and qt_raster.QtRaster.line_widths == (1.0,)
    star = PathScene.from_paths(W, H, [[pentagram(16, 16, 12)]], "nonzero")
    assert takes(qt_raster.QtAntialiased, star)  # type: ignore[arg-type]  # AA paths too (issue 34)
    assert qt_raster.QtAntialiased.scene_kinds == ("triangles", "lines", "paths")


def test_a_missing_library_makes_the_adapters_unavailable(monkeypatch):
    monkeypatch.setitem(sys.modules, "PyQt6", None)
    for cls in (qt_raster.QtRaster, qt_raster.QtAntialiased):
        with pytest.raises(Unavailable, match="PyQt6 is not installed"):
            cls()


def test_the_mapping_is_exact(qt):
    """Triangles far from ties draw exactly the pixels whose centre they hold: no
    half-pixel shift, no flip, no transposition; each triangle on its own."""
    scene = Scene(W, H, quarter_triangles(24, seed=3))
    cov = qt.rasterize(scene)
    oracle = exact_coverage(scene, QT)
    for t in range(len(scene)):
        mine = cov.take(np.flatnonzero(cov.primitive == t)).counts(W, H)
        expected = oracle.take(np.flatnonzero(oracle.primitive == t)).counts(W, H)
        assert mine.sum() > 0 and np.array_equal(mine, expected), t
    # and the screen's far corner: a triangle off the top-left is clipped, not moved
    corner = Scene(W, H, [[[-3.25, -2.25], [6.25, -2.25], [-3.25, 7.75]]])
    assert np.array_equal(qt.rasterize(corner).counts(W, H), exact_coverage(corner, QT).counts(W, H))


def test_ties_go_bottom_right(qt):
    """A square [2, 6] x [3, 7] on pixel edges, as two triangles sharing a diagonal through
    pixel centres: every centre inside is drawn once (watertight on the diagonal), and the
    square's 4 x 4 pixels exactly; a triangle whose right edge runs through centres owns
    them, whose left edge does not."""
    square = Scene(W, H, [[[2, 3], [6, 3], [6, 7]], [[2, 3], [6, 7], [2, 7]]])
    counts = qt.rasterize(square).counts(W, H)
    expected = np.zeros((H, W), dtype=np.int32)
    expected[3:7, 2:6] = 1
    assert np.array_equal(counts, expected)
    # vertical edges through the centres of columns 4 (left edge) and 8 (right edge)
    strip = Scene(W, H, [[[4.5, 2.0], [8.5, 2.0], [8.5, 6.0]], [[4.5, 2.0], [8.5, 6.0], [4.5, 6.0]]])
    drawn = qt.rasterize(strip).counts(W, H)
    assert drawn[2:6, 4].sum() == 0 and drawn[2:6, 8].tolist() == [1, 1, 1, 1]


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_the_fill_rule_is_honoured(qt, rule):
    """A pentagram's centre (winding 2) is filled under nonzero only; its points under both;
    a ring's hole wound the same way likewise."""
    outer = np.array([[2.5, 2.5], [29.5, 2.5], [29.5, 29.5], [2.5, 29.5]])
    hole = np.array([[10.5, 10.5], [21.5, 10.5], [21.5, 21.5], [10.5, 21.5]])
    scene = PathScene.from_paths(W, H, [[pentagram(16.2, 15.9, 13.3)], [outer, hole]], rule)
    cov = qt.rasterize(scene)
    star = cov.take(np.flatnonzero(cov.primitive == 0)).counts(W, H)
    ring = cov.take(np.flatnonzero(cov.primitive == 1)).counts(W, H)
    assert star[16, 16] == (rule == "nonzero") and star[5, 16] == 1 and star[12, 5] == 1
    assert ring[16, 16] == (rule == "nonzero") and ring[5, 16] == 1 and ring[16, 5] == 1
    # every pixel is the winding oracle's under that rule (no centre is near an edge here)
    assert np.array_equal(star, exact_coverage(scene.subset([0]), QT).counts(W, H))
    assert np.array_equal(ring, exact_coverage(scene.subset([1]), QT).counts(W, H))


def test_cosmetic_lines(qt):
    """A cosmetic pen (width 0) with Qt's square caps: one pixel per column of an x-major
    line, the pixels holding both end points included; a horizontal line through pixel
    centres covers the columns of both end pixels. Wider lines are refused."""
    scene = LineScene.from_segments(16, 16, [[1.5, 1.5], [2.5, 11.5]], [[10.5, 5.5], [8.5, 11.5]])
    cov = qt.rasterize(scene)
    slanted = cov.take(np.flatnonzero(cov.primitive == 0)).counts(16, 16)
    ys, xs = np.nonzero(slanted)
    assert sorted(zip(xs.tolist(), ys.tolist())) == [(1, 1), (2, 1), (3, 2), (4, 2), (5, 3), (6, 3), (7, 4), (8, 4),
                                                     (9, 5), (10, 5)]
    flat = cov.take(np.flatnonzero(cov.primitive == 1)).counts(16, 16)
    assert flat[11, 2:9].tolist() == [1] * 7 and flat.sum() == 7
    with pytest.raises(Unsupported, match="hairlines"):
        qt.rasterize(LineScene.from_segments(16, 16, [[1, 1]], [[9, 9]], line_width=3.0))


def test_the_antialiased_mapping_is_exact(qt_aa):
    """Alphas are within 0.02 of the exact area of each triangle in each pixel (issue 32:
    max 0.018): a shifted, flipped or transposed image would be off by far more."""
    scene = Scene(W, H, quarter_triangles(12, seed=5, margin=0.0))
    cov = qt_aa.rasterize(scene)
    area = area_coverage(scene, Convention(coverage="area", subpixel_bits=6, snap_rounding="half-away"))
    for t in range(len(scene)):
        mine, exact = np.zeros((H, W)), np.zeros((H, W))
        for c, image in ((cov, mine), (area, exact)):
            k, x, y = c.pixels()
            alpha = c.alpha if c.alpha is not None else np.ones(k.size)
            image[y[k == t], x[k == t]] = alpha[k == t]
        assert np.abs(mine - exact).max() <= 0.02, t
        assert np.array_equal(mine * 255, np.round(mine * 255))  # 8-bit alpha


def test_a_nan_triangle_does_not_hang_and_is_drawn(qt, qt_aa):
    """A NaN vertex: Qt answers at once, and fills pixels (the finding the upstream repro
    reports); infinite vertices likewise answer at once."""
    scene = Scene(16, 16, [[[math.nan, 2.0], [12.0, 3.0], [5.0, 13.0]], [[-math.inf, 2.0], [12.0, 3.0], [5.0, 13.0]],
                           [[math.inf, math.inf], [12.0, 3.0], [5.0, 13.0]]])
    for adapter in (qt, qt_aa):
        start = time.perf_counter()
        cov = adapter.rasterize(scene)
        assert time.perf_counter() - start < 5
        assert np.count_nonzero(cov.primitive == 0) > 0  # the NaN triangle draws (Qt's bug)
