"""FreeType's outline rasterizers (rasterizers.real.freetype_outline): the coordinate
mapping of each mode, the fill rule the monochrome one honours, dropout control, and bad
input."""

import sys
from pathlib import Path

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.protocol import receive
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from harness.oracle.area import area_coverage
from harness.oracle.coverage import exact_coverage
from rasterizers.real import freetype_outline
from tests.optional import need

ROOT = Path(__file__).parents[3]
MONO = {"freetype_mono": "FreeTypeMono", "freetype_mono_dropout": "FreeTypeMonoDropout"}
CENTRE = Convention(sample=(0.5, 0.5), tie="top-left")


@pytest.fixture(params=sorted(MONO))
def mono(request):
    need("freetype")
    return getattr(freetype_outline, MONO[request.param])()


@pytest.fixture
def smooth():
    need("freetype")
    return freetype_outline.FreeTypeSmooth()


def pixel_set(cov, primitive=None):
    t, x, y = cov.pixels()
    keep = np.ones(t.size, dtype=bool) if primitive is None else t == primitive
    return set(zip(x[keep].tolist(), y[keep].tolist()))


def alpha_image(cov, width, height):
    _, x, y = cov.pixels()
    image = np.zeros((height, width))
    np.add.at(image, (y, x), cov.alpha)
    return image


def star(cx, cy, r):
    a = 4 * np.pi * np.arange(5) / 5
    return np.c_[cx + r * np.sin(a), cy - r * np.cos(a)]


def square(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def test_freetype_mono_maps_coordinates_exactly(mono):
    """Triangles with vertices at integer-plus-0.25 (multiples of 1/64, received exactly;
    no pixel centre on an edge) draw exactly the pixels whose centres they hold: no
    half-pixel shift, no flip (y is flipped twice, by the adapter and back by the bitmap's
    row order), no transposition. Off-screen parts are clipped, not folded back."""
    triangles = [[[1.25, 1.25], [9.25, 3.25], [3.25, 10.25]], [[12.25, 2.25], [18.25, 2.25], [18.25, 5.25]],
                 [[-3.25, 14.25], [6.25, 17.25], [2.25, 23.25]]]
    scene = Scene(20, 20, triangles)
    cov, exact = mono.rasterize(scene), exact_coverage(scene, CENTRE)
    for t in range(len(triangles)):
        assert pixel_set(cov, t) == pixel_set(exact, t), t
    assert len(pixel_set(cov, 0)) > 25


def test_freetype_smooth_alphas_match_the_area(smooth):
    """The same triangles anti-aliased: every pixel's alpha is the covered area within
    1/64 + 1/255 (an area coverage shifted by half a pixel, flipped or transposed would be
    off by up to 1 on the edges)."""
    scene = Scene(20, 20, [[[1.25, 1.25], [9.25, 3.25], [3.25, 10.25]], [[12.25, 2.25], [18.25, 2.25], [18.25, 5.25]]])
    got = alpha_image(smooth.rasterize(scene), 20, 20)
    area = alpha_image(area_coverage(scene, Convention(coverage="area")), 20, 20)
    assert np.abs(got - area).max() <= 1 / 64 + 1 / 255
    assert np.count_nonzero((area > 0) & (area < 1)) > 20  # the edges are there to be judged
    cov = smooth.rasterize(scene)
    assert np.array_equal(cov.alpha * 255, np.round(cov.alpha * 255))  # 8-bit gray: value / 255


def test_coordinates_are_received_as_26_6_rounded_half_to_even(mono):
    scene = Scene(8, 8, [[[1 / 128, 3 / 128], [5.0 + 1 / 256, 1.0], [np.nan, 2.0]]])
    got = receive(mono, scene).positions[0]
    assert got[0].tolist() == [0.0, 2 / 64] and got[1].tolist() == [5.0, 1.0] and np.isnan(got[2, 0])
    paths = PathScene.from_paths(8, 8, [[[[0.5 + 1 / 128, 1.0], [3.0, 3 / 128], [1.0, 4.0]]]])
    assert receive(mono, paths).vertices[:2].tolist() == [[0.5, 1.0], [3.0, 2 / 64]]
    # what the library draws depends on the rounded coordinates only
    near = Scene(12, 12, [[[1.0 + 1 / 200, 1.5], [10.0, 1.5 + 1 / 300], [3.0, 9.7]]])
    assert pixel_set(mono.rasterize(near)) == pixel_set(mono.rasterize(receive(mono, near)))


def test_mono_fills_nonzero_and_refuses_evenodd(mono):
    """Nonzero: a pentagram's centre (winding 2) is filled; a hole wound opposite to its
    ring is empty, one wound alike is filled. Even-odd scenes are refused, since the
    monochrome rasterizer ignores FT_OUTLINE_EVEN_ODD_FILL."""
    assert mono.fill_rules == ("nonzero",)
    ring, hole = square(2, 2, 30, 30), square(10, 10, 20, 20)
    scene = PathScene.from_paths(32, 32, [[star(16, 16, 14)], [ring, hole[::-1]], [ring, hole]], "nonzero")
    cov = mono.rasterize(scene)
    assert (16, 16) in pixel_set(cov, 0)
    assert (15, 15) not in pixel_set(cov, 1) and (5, 5) in pixel_set(cov, 1)
    assert (15, 15) in pixel_set(cov, 2)
    with pytest.raises(Unsupported, match="nonzero only"):
        mono.rasterize(PathScene.from_paths(32, 32, [[star(16, 16, 14)]], "evenodd"))


def test_the_even_odd_flag_works_in_the_smooth_rasterizer_only():
    """The finding behind ``fill_rules``: FreeType's monochrome rasterizer fills a
    pentagram's centre with FT_OUTLINE_EVEN_ODD_FILL set or not; the smooth one leaves it
    empty with the flag."""
    freetype = need("freetype")
    even_odd = freetype.FT_OUTLINE_EVEN_ODD_FILL
    contour = [star(10, 10, 8)]
    centre = {}
    for mode, name in ((1, "mono"), (2, "smooth")):
        for flags, rule in ((0, "nonzero"), (even_odd, "evenodd")):
            outline = freetype_outline._Outline(mode, flags | (freetype.FT_OUTLINE_IGNORE_DROPOUTS if mode == 1 else 0))
            centre[name, rule] = int(outline.render(contour, 20, 20)[10, 10])
    assert centre["mono", "nonzero"] == centre["mono", "evenodd"] == 1
    assert centre["smooth", "nonzero"] == 255 and centre["smooth", "evenodd"] == 0


def test_dropout_control_draws_slivers_between_pixel_centres():
    """A strip 0.5 px wide between two rows of pixel centres (y in [3.6, 4.1]): no centre
    inside, so no pixel without dropout control; with it (smart mode, stubs excluded) one
    pixel per column, the one nearer the strip."""
    need("freetype")
    strip = PathScene.from_paths(16, 8, [[square(2.0, 3.6, 12.0, 4.1)]])
    assert not freetype_outline.FreeTypeMono().rasterize(strip).n_pixels
    got = pixel_set(freetype_outline.FreeTypeMonoDropout().rasterize(strip))
    assert got == {(x, 3) for x in range(2, 12)}


def test_non_finite_triangles_cover_nothing(mono, smooth):
    """A NaN or infinite coordinate has no 26.6 value: such a triangle is not sent and
    covers nothing; the others are drawn. Quick: nothing hangs."""
    scene = Scene(16, 16, [[[1.25, 1.25], [9.25, 3.25], [3.25, 10.25]], [[np.nan, 1.0], [5.0, 5.0], [1.0, 9.0]],
                           [[1.0, 1.0], [np.inf, 5.0], [1.0, 9.0]], [[-np.inf, 1.0], [5.0, -np.inf], [9.0, 9.0]]])
    for adapter in (mono, smooth):
        cov = adapter.rasterize(scene)
        assert set(np.unique(cov.pixels()[0]).tolist()) == {0}
    paths = PathScene.from_paths(16, 16, [[square(1, 1, 6, 6), np.array([[2.0, 2.0], [np.nan, 3.0], [4.0, 4.0]])]])
    assert not mono.rasterize(paths).n_pixels


def test_outlines_beyond_freetypes_limit_are_refused_by_name(mono, smooth):
    """FT_Outline_Render refuses control boxes beyond +/-0x1000000 in 26.6 (262,144 px)
    with Invalid_Outline: the adapter names that limit; a triangle within it is drawn."""
    far = Scene(32, 32, [[[-300000.0, 1.0], [20.0, 1.0], [20.0, 20.0]]])
    for adapter in (mono, smooth):
        with pytest.raises(RuntimeError, match="refuses outlines reaching beyond"):
            adapter.rasterize(far)
    near = Scene(32, 32, [[[-200000.0, 1.0], [20.0, 1.0], [20.0, 20.0]]])
    assert mono.rasterize(near).n_pixels > 10


def test_kinds_versions_and_refusals(mono, smooth):
    assert mono.library == smooth.library == "FreeType"
    assert mono.library_version.count(".") == 2 and mono.library_version == smooth.library_version
    assert mono.scene_kinds == smooth.scene_kinds == ("triangles", "paths")  # AA paths: issue 34
    assert mono.fill_rules == ("nonzero",) and smooth.fill_rules == ("nonzero", "evenodd")
    assert "lines" in smooth.kinds_not_taken and "paths" not in smooth.kinds_not_taken
    assert mono.coverage_kind == "single" and smooth.coverage_kind == "area" and smooth.convention is None
    # issue 33: the monochrome modes declare the closed rule with ftraster.c's scan conversion
    assert mono.convention is not None and mono.convention.coverage == "closed" and mono.convention.input == "fixed6"
    with pytest.raises(ValueError, match="takes triangles, paths"):
        mono.rasterize(LineScene.from_segments(8, 8, [[1.0, 1.0]], [[5.0, 5.0]]))


def test_a_missing_library_makes_the_adapters_unavailable(monkeypatch):
    monkeypatch.setitem(sys.modules, "freetype", None)
    for cls in ("FreeTypeMono", "FreeTypeMonoDropout", "FreeTypeSmooth"):
        with pytest.raises(Unavailable, match="freetype"):
            getattr(freetype_outline, cls)()


def test_a_deeply_wound_outline_overflows_the_monochrome_rasterizer_naming_the_repro(mono, smooth):
    """A contour tracing a triangle 128 times: Raster_Overflow in both monochrome modes
    (a RuntimeError naming the repro); the smooth rasterizer draws it."""
    triangle = np.array([[2.0, 2.0], [14.0, 2.0], [8.0, 14.0]])
    contour = np.tile(triangle, (128, 1))
    with pytest.raises(RuntimeError, match="freetype_mono_raster_overflow.py"):
        mono.rasterize(PathScene.from_paths(16, 16, [[contour]]))
    assert smooth._outline.render([contour], 16, 16).any()
