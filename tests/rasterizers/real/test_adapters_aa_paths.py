"""The anti-aliasing adapters on path scenes (issue 34): each path filled in one call under
the scene's fill rule with the library's own path fill (rasterizers.real._aa_paths), alphas
judged against the exact area where the rule holds (harness.oracle.path_area). Each test
skips without its library, naming the install."""

import importlib

import numpy as np
import pytest

from cases.paths import triangles_as_paths
from cases.scenes import random_triangles
from harness.checks.area import accuracy
from harness.contract.case import Case
from harness.contract.conventions import Convention, LineRule
from harness.contract.protocol import takes
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.oracle.coverage import exact_coverage
from rasterizers.real._aa_paths import AlphaPaths, draw_each_path_alpha
from tests.optional import need

W = H = 48
# judged with no tolerance to speak of, to measure max |alpha - area|
MEASURE = Convention(coverage="area", tolerance=1.0)
MEASURE_LINES = Convention(coverage="area", line=LineRule("rectangle"), tolerance=1.0)

# name -> (module, class, the module to install, the fill rules it declares, whether it strokes lines)
ADAPTERS = {
    "cairo_aa": ("adapters", "CairoAntialiased", "cairo", ("nonzero", "evenodd"), True),
    "skia_aa": ("adapters", "SkiaAntialiased", "skia", ("nonzero", "evenodd"), True),
    "freetype_smooth": ("freetype_outline", "FreeTypeSmooth", "freetype", ("nonzero", "evenodd"), False),
    "blend2d": ("blend2d_context", "Blend2DContext", "blend2d", ("nonzero", "evenodd"), True),
    "agg_aa": ("agg", "AggAntialiased", "aggdraw", ("nonzero",), True),
    "matplotlib_agg_aa": ("matplotlib_agg", "MatplotlibAggAntialiased", "matplotlib", ("nonzero",), True),
    "qt_aa": ("qt_raster", "QtAntialiased", "PyQt6", ("nonzero", "evenodd"), True),
    "tiny_skia_aa": ("tiny_skia", "TinySkiaAntialiased", "resvg_py", ("nonzero", "evenodd"), False),
}
# the libraries that apply the fill rule to each pixel's summed signed area (analytic
# accumulation: FreeType's gray_sweep, AGG's calculate_alpha, Qt's qgrayraster, Blend2D),
# not to the area where the winding satisfies it: a pixel half covered by a doubly wound
# region gets alpha 1 under both rules
SUMMED = {"freetype_smooth", "blend2d", "agg_aa", "matplotlib_agg_aa", "qt_aa"}
# max |alpha - exact area| on paths whose pixels each see one nonzero winding (measured,
# Debian 12: cairo 1.16 0.048, skia-python 144.1 0.119, FreeType 2.13.2 0.013, Blend2D 0.8.0
# 0.0072, aggdraw 1.4.1 0.013, matplotlib 3.11.2 0.011, Qt 6.11.0 0.013, resvg 0.48.1 0.114);
# cairo: its declared tolerance
SIMPLE_PATHS_ERROR = {"cairo_aa": 1 / 15 + 1 / 256 + 1 / 510, "skia_aa": 0.15, "freetype_smooth": 0.02, "blend2d": 0.01,
                      "agg_aa": 0.02, "matplotlib_agg_aa": 0.015, "qt_aa": 0.02, "tiny_skia_aa": 0.15}


def make(name):
    module, cls, install, _, _ = ADAPTERS[name]
    need(install)
    return getattr(importlib.import_module(f"rasterizers.real.{module}"), cls)()


@pytest.fixture(params=sorted(ADAPTERS))
def adapter(request):
    return make(request.param)


def polygon(cx, cy, r, points, step=1, turn=0.0):
    """A regular polygon (step 1) or star polygon {points/step}: (points, 2), clockwise on
    screen (y down)."""
    a = 2 * np.pi * np.arange(points) * step / points + turn
    return np.c_[cx + r * np.sin(a), cy - r * np.cos(a)]


def image(cov, width=W, height=H):
    """(H, W) sum of every primitive's alpha at each pixel."""
    _, x, y = cov.pixels()
    out = np.zeros((height, width))
    np.add.at(out, (y, x), cov.alpha)
    return out


def test_the_kinds_and_rules_each_declares(adapter):
    _, _, _, rules, lines = ADAPTERS[adapter.name]
    assert "paths" in adapter.scene_kinds and "paths" not in adapter.kinds_not_taken
    assert adapter.fill_rules == rules and adapter.coverage_kind == "area"
    assert ("lines" in adapter.scene_kinds) == lines
    # the atlas's texts stay true: a kind taken is never said not to be, one not taken says why
    assert set(adapter.kinds_not_taken) == {"lines"} - set(adapter.scene_kinds)
    for rule in ("nonzero", "evenodd"):
        scene = PathScene.from_paths(8, 8, [[[[1, 1], [6, 1], [1, 6]]]], rule)
        assert takes(adapter, scene) == (rule in rules)
        if rule not in rules:
            with pytest.raises(Unsupported, match=f"fills nonzero only, not '{rule}'"):
                adapter.rasterize(scene)


def test_a_one_triangle_path_is_the_triangle(adapter):
    """Every triangle drawn as a path of one contour gets the triangle's own alphas, pixel
    for pixel, whatever its orientation: each library's triangle draw and path fill are the
    same call but for the fill rule (a triangle covers each point once)."""
    positions = np.concatenate([random_triangles(30, 20.0, W, 34), random_triangles(10, 4.0, W, 35),
                                [[[-5.0, 10.0], [20.0, 12.5], [3.0, 60.0]]]])
    positions[::2] = positions[::2, ::-1]  # both orientations
    scene = Scene(W, H, positions)
    triangles = adapter.rasterize(scene)
    for rule in adapter.fill_rules:
        paths = adapter.rasterize(triangles_as_paths(scene, rule))
        for field in ("primitive", "y", "x0", "x1", "alpha"):
            assert np.array_equal(getattr(paths, field), getattr(triangles, field)), (rule, field)


def test_the_alphas_are_eight_bit_and_nonzero(adapter):
    scene = PathScene.from_paths(W, H, [[polygon(24, 24, 20, 5, 2)], [polygon(10.3, 12.7, 7, 7, 3, 0.3)]],
                                 adapter.fill_rules[-1])
    cov = adapter.rasterize(scene)
    assert cov.sample is None and cov.alpha is not None and cov.alpha.size == cov.n_pixels
    assert np.all((cov.alpha > 0) & (cov.alpha <= 1))
    assert np.array_equal(cov.alpha * 255, np.round(cov.alpha * 255))
    assert set(cov.primitive.tolist()) == {0, 1}


def test_simple_paths_near_their_exact_area(adapter):
    """Paths whose every pixel sees one nonzero winding (a ring with its hole wound the
    other way, a concave polygon, a convex one crossing the screen's edge) under each rule
    the adapter declares: max |alpha - exact area| as measured (the coordinate mapping of
    paths is the triangles')."""
    ring = [polygon(24, 24, 18, 12, 1, 0.1), polygon(24, 24, 9, 9, 1, 0.2)[::-1]]
    arrow = np.array([[3.3, 30.2], [20.1, 30.7], [20.6, 26.1], [30.2, 37.9], [19.7, 46.2], [20.3, 41.4], [3.8, 41.9]])
    edge = polygon(44.5, 6.3, 9.0, 6, 1, 0.4)
    for rule in adapter.fill_rules:
        scene = PathScene.from_paths(W, H, [ring, [arrow], [edge]], rule)
        result = accuracy(Case(f"simple/{rule}", scene), adapter.rasterize(scene), exact_coverage(scene, MEASURE), MEASURE)
        assert result.metrics["max_error"] <= SIMPLE_PATHS_ERROR[adapter.name], (rule, result.message)


def test_the_fill_rules_drawn_as_declared(adapter):
    """A bow tie (one contour crossing itself: windings +1 and -1) fills both lobes under
    either rule; a doubly wound square (the same contour twice) is full inside under
    nonzero, empty under even-odd; a pentagram's centre (winding 2) likewise."""
    bow = np.array([[2.0, 2.0], [22.0, 22.0], [22.0, 2.0], [2.0, 22.0]])  # lobes left and right of x = 12
    square = np.array([[26.5, 26.5], [40.5, 26.5], [40.5, 40.5], [26.5, 40.5]])
    star = polygon(12, 36, 11, 5, 2)
    for rule in adapter.fill_rules:
        out = image(adapter.rasterize(PathScene.from_paths(W, H, [[bow], [square, square], [star]], rule)))
        assert out[11, 4] == 1.0 and out[11, 19] == 1.0, rule  # both lobes of the bow tie
        inside = 1.0 if rule == "nonzero" else 0.0
        assert np.all(out[28:39, 28:39] == inside), rule  # the doubly wound square's inside
        assert out[36, 12] == inside, rule  # the pentagram's centre


def test_overlapping_contours_at_their_edges(adapter):
    """Where a doubly wound region's edge halves a pixel, the exact alpha is 1/2 under
    nonzero and 0 under even-odd. Libraries that sum each pixel's signed area first
    (:data:`SUMMED`) give 1 under both rules: overlapping contours, as variable fonts'
    glyphs have, get dark fringes; the supersamplers (cairo, skia, tiny-skia) judge each
    sample's winding and are right."""
    square = np.array([[6.5, 6.5], [20.5, 6.5], [20.5, 20.5], [6.5, 20.5]])  # edges through pixel centres
    for rule in adapter.fill_rules:
        out = image(adapter.rasterize(PathScene.from_paths(W, H, [[square, square]], rule)))
        edges = np.array([out[12, 6], out[12, 20], out[6, 12], out[20, 12]])
        if adapter.name in SUMMED:
            assert np.all(edges == 1.0), (rule, edges)
        else:
            exact = 0.5 if rule == "nonzero" else 0.0
            assert np.all(np.abs(edges - exact) <= 1 / 255), (rule, edges)


def test_a_library_failure_names_the_path(adapter, monkeypatch):
    """A library raising on the third path: RuntimeError naming path 2 (tiny-skia fills
    from resvg's rendered documents, so there resvg itself is made to fail)."""
    scene = PathScene.from_paths(W, H, [[polygon(8 + 12 * k, 24, 5, 6)] for k in range(4)], adapter.fill_rules[0])
    if adapter.name == "tiny_skia_aa":
        rgba = adapter._resvg.rgba

        def failing_resvg(elements, x0, y0, w, h):
            if "M 32.0 19.0" in elements:  # path 2's first vertex (it fails alone and in a shared document)
                raise OSError("resvg failed")
            return rgba(elements, x0, y0, w, h)

        monkeypatch.setattr(adapter._resvg, "rgba", failing_resvg)
    else:
        fill = adapter._fill_path
        calls = []

        def failing(contours, rule, w, h, origin):
            calls.append(origin)
            if len(calls) == 3:
                raise OSError("the library failed")
            return fill(contours, rule, w, h, origin)

        monkeypatch.setattr(adapter, "_fill_path", failing)
    with pytest.raises(RuntimeError, match=rf"{adapter.name}: the library failed on path 2 \(1 contours, 6 vertices\)"):
        adapter.rasterize(scene)


def test_freetype_names_the_path_it_cannot_hold():
    """A real library limit: an FT_Outline holds at most 32,767 points (C shorts)."""
    smooth = make("freetype_smooth")
    big = polygon(24, 24, 20, 40000)
    scene = PathScene.from_paths(W, H, [[polygon(10, 10, 5, 6)], [big]], "nonzero")
    with pytest.raises(RuntimeError, match=r"freetype_smooth: the library failed on path 1 \(1 contours, 40000 vertices\)"):
        smooth.rasterize(scene)


def test_the_agg_libraries_fill_nonzero_whatever_is_asked():
    """aggdraw and matplotlib never set AGG's filling rule: a doubly wound square is full
    inside (so ``fill_rules`` leaves even-odd out)."""
    square = np.array([[2.0, 2.0], [10.0, 2.0], [10.0, 10.0], [2.0, 10.0]])
    agg, mpl = need("aggdraw"), make("matplotlib_agg_aa")
    from rasterizers.real.agg import _fill

    assert np.all(_fill(agg, [square, square], 12, 12, True)[3:9, 3:9] == 255)
    assert np.all(mpl._mpl.fill([square, square], 12, 12, True)[3:9, 3:9] == 255)


@pytest.mark.parametrize(("name", "thin", "wide"), [
    ("matplotlib_agg_aa", 0.015, 0.015),  # AGG's conv_stroke outline, analytic coverage: 0.0108 measured
])
def test_the_new_aa_strokes_measured(name, thin, wide):
    rasterizer = make(name)
    assert "lines" in rasterizer.scene_kinds and "lines" not in rasterizer.kinds_not_taken
    rng = np.random.default_rng(34)
    for width in (1.0, 2.5):
        case = Case(f"aa-lines/random-w{width:g}",
                    LineScene.from_segments(W, H, rng.uniform(2, 46, (40, 2)), rng.uniform(2, 46, (40, 2)), width))
        result = accuracy(case, rasterizer.rasterize(case.scene), exact_coverage(case.scene, MEASURE_LINES), MEASURE_LINES)
        assert result.metrics["max_error"] < (thin if width <= 1.0 else wide), (width, result.message)


def test_the_mixin_adds_paths_after_lines():
    """AlphaPaths before AlphaLines: the class takes triangles, lines and paths, and the
    base's texts for both kinds are dropped; alone, triangles and paths."""
    from rasterizers.real._aa_lines import AlphaLines
    from rasterizers.real._bases import AlphaOneTriangleAtATime

    class Both(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
        pass

    class PathsOnly(AlphaPaths, AlphaOneTriangleAtATime):
        pass

    assert Both.scene_kinds == ("triangles", "lines", "paths") and Both.kinds_not_taken == {}
    assert PathsOnly.scene_kinds == ("triangles", "paths") and set(PathsOnly.kinds_not_taken) == {"lines"}


def test_draw_each_path_alpha_boxes_and_non_finite_paths():
    """Each path's box is its bounding box and the margin, clipped to the screen; a path
    with a NaN vertex is handed the whole screen unchanged; alphas of 0 are left out."""
    seen = []

    def library(contours, w, h, origin):
        seen.append((len(contours), w, h, origin, bool(np.isfinite(np.concatenate(contours)).all())))
        alpha = np.zeros((h, w))
        alpha[0, 0] = 0.25
        return alpha

    paths: list[list[list[list[float]]]] = [[[[3, 2], [5, 2], [5, 4]], [[6, 2], [6, 3], [7, 3]]],
                                            [[[1, 1], [np.nan, 1], [2, 2]]], [[[-9, -9], [-8, -9], [-8, -8]]]]
    scene = PathScene.from_paths(16, 8, paths)
    cov = draw_each_path_alpha(scene, "lib", library, margin=1)
    assert seen == [(2, 6, 4, (2, 1), True), (1, 16, 8, (0, 0), False)]
    assert cov.primitive.tolist() == [0, 1] and cov.x0.tolist() == [2, 0] and cov.y.tolist() == [1, 0]
    assert cov.alpha is not None and cov.alpha.tolist() == [0.25, 0.25]
