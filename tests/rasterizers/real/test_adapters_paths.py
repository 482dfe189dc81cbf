"""The real adapters on path scenes (rasterizers.real.adapters): each path filled in one
call under the scene's fill rule, compared with the exact winding oracle.

cairo and skia honour both rules, Pillow and scikit-image even-odd only (Pillow one contour
per path); llvmpipe draws paths by stencil-then-cover and equals the oracle of its
triangles' convention exactly. Mesa picks its driver once per process, so each Mesa
adapter is exercised in one fresh Python per module (one GL context each), whose findings
the tests below read."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from harness.contract.conventions import TIE_RULES, Convention, SnapRounding
from harness.contract.coverage import Coverage
from harness.contract.protocol import takes
from harness.contract.scenes import PathScene, Scene
from harness.engine.registry import Unavailable
from harness.oracle.coverage import exact_coverage
from rasterizers.real import adapters
from rasterizers.real._masks import coverage_from_fragments, draw_each_path, path_extents
from rasterizers.real._stencil import cover_boxes, fan_indices, fans, layers
from tests.optional import need

ROOT = Path(__file__).parents[3]
W = H = 32
# class, module, the snapping its triangles were identified with (README), how far from the
# path's edges (px) a pixel where it departs from its best-fitting convention may lie
# (measured, Debian 12: cairo 1.16, skia-python 144.1, scikit-image 0.26, Pillow 13)
TWO_D: dict[str, tuple[str, str, tuple[int | None, SnapRounding], float]] = {
    "cairo": ("CairoFill", "cairo", (8, "nearest-even"), 1 / 16),  # 24.8 fixed point
    "skia": ("SkiaPath", "skia", (6, "floor"), 1 / 16),  # 26.6 fixed point, truncated
    "skimage": ("SkimagePolygon", "skimage", (None, "nearest-even"), 1 / 16),
    "pillow": ("PillowPolygon", "PIL", (None, "nearest-even"), 2.0),  # vertices truncated to whole pixels
}


# -- the hand-made scenes -------------------------------------------------------------------


def star(cx, cy, r, points=5, step=2, turn=0.0, grid=None):
    """A star polygon {points/step} (a pentagram by default): (points, 2), on a ``grid``."""
    a = 2 * np.pi * np.arange(points) * step / points + turn
    v = np.c_[cx + r * np.sin(a), cy - r * np.cos(a)]
    return v if grid is None else np.round(v / grid) * grid


# vertices on a half-pixel lattice: on sample points, edges through them
OCTAGON = np.array([[9.5, 2.5], [22.5, 2.5], [29.5, 9.5], [29.5, 22.5], [22.5, 29.5], [9.5, 29.5], [2.5, 22.5], [2.5, 9.5]])
HOLE = np.array([[11.5, 8.5], [21.5, 11.5], [23.5, 21.5], [10.5, 23.5]])  # the octagon's orientation
QUAD = np.array([[8.5, 10.0], [30.0, 14.5], [24.5, 30.5], [6.0, 26.5]])


def scenes(rule):
    """The hand-made path scenes under ``rule``, by name."""
    return {
        "pentagram": PathScene.from_paths(W, H, [[star(16, 16, 14, grid=0.5)]], rule),
        "pentagram-float": PathScene.from_paths(W, H, [[star(16.3, 15.7, 13.1, turn=0.1)]], rule),
        "ring-same": PathScene.from_paths(W, H, [[OCTAGON, HOLE]], rule),
        "ring-opposite": PathScene.from_paths(W, H, [[OCTAGON, HOLE[::-1]]], rule),
        "overlap": PathScene.from_paths(W, H, [[star(13, 13, 11, grid=0.5)], [QUAD]], rule),
        "offscreen": PathScene.from_paths(W, H, [[star(3.5, 29, 24, 7, 3, grid=0.5)]], rule),  # a {7/3} star, half off
    }


def path_counts(cov, k, width=W, height=H):
    """(H, W) hits of path k."""
    return cov.take(np.flatnonzero(cov.primitive == k)).counts(width, height)


def mismatch(cov, scene, convention):
    """Pixels where each path's coverage differs from the oracle's: [(path, x, y), ...]."""
    found = []
    for k in range(len(scene)):
        ys, xs = np.nonzero(path_counts(cov, k, scene.width, scene.height)
                            != path_counts(exact_coverage(scene, convention), k, scene.width, scene.height))
        found += [(k, x, y) for x, y in zip(xs.tolist(), ys.tolist())]
    return found


def distance_to_edges(scene, k, x, y):
    """Distance from pixel (x, y)'s centre to the nearest edge of path k."""
    a, b, path = scene.edges()
    a, b = a[path == k], b[path == k]
    d = b - a
    length = np.where((d**2).sum(axis=1) == 0, 1.0, (d**2).sum(axis=1))
    p = np.array([x + 0.5, y + 0.5])
    t = np.clip(((p - a) * d).sum(axis=1) / length, 0.0, 1.0)
    return float(np.sqrt(((a + t[:, None] * d - p) ** 2).sum(axis=1)).min())


def best_fit(drawn, snapping: tuple[int | None, SnapRounding]):
    """The convention among centre samples x the eight tie rules x (no snapping, the
    library's) with the fewest mismatching pixels over ``drawn`` ({(rule, name): (scene,
    coverage)}), and those mismatches."""
    candidates = [Convention(tie=t, subpixel_bits=bits, snap_rounding=rounding) for t in TIE_RULES
                  for bits, rounding in ((None, "nearest-even"), snapping)]
    fits = {c: {key: mismatch(cov, scene, c) for key, (scene, cov) in drawn.items()} for c in candidates}
    best = min(candidates, key=lambda c: sum(len(m) for m in fits[c].values()))
    return best, fits[best]


@pytest.fixture(scope="module", params=sorted(TWO_D))
def two_d(request):
    """Each 2D adapter, skipped with its install hint where its library is missing."""
    try:
        return getattr(adapters, TWO_D[request.param][0])()
    except Unavailable as exc:
        pytest.skip(str(exc))


@pytest.fixture(scope="module")
def drawn(two_d):
    """{(rule, name): (scene, coverage)} of the hand-made scenes the adapter takes."""
    out = {}
    for rule in two_d.fill_rules:
        for name, scene in scenes(rule).items():
            if two_d.name == "pillow" and len(scene.contours_of(0)) > 1:
                continue  # refused (see test_pillow_refuses_what_it_cannot_fill)
            out[rule, name] = (scene, two_d.rasterize(scene))
    return out


# -- what each adapter declares -------------------------------------------------------------


def test_declared_kinds_and_rules():
    for cls in ("CairoFill", "SkiaPath", "MesaLlvmpipe", "MesaSoftpipe"):
        r = getattr(adapters, cls)
        assert r.scene_kinds == ("triangles", "paths", "lines") and r.fill_rules == ("nonzero", "evenodd")
    for cls in ("PillowPolygon", "SkimagePolygon"):
        r = getattr(adapters, cls)
        assert r.scene_kinds == ("triangles", "paths", "lines") and r.fill_rules == ("evenodd",)
        assert takes(r, scenes("evenodd")["pentagram"]) and not takes(r, scenes("nonzero")["pentagram"])
    assert adapters.MesaMultisample.scene_kinds == ("triangles",)
    # the class itself (its declarations are class attributes; the library may be missing)
    assert not takes(adapters.MesaMultisample, scenes("nonzero")["pentagram"])  # type: ignore[arg-type]
    for cls in ("CairoAntialiased", "SkiaAntialiased"):  # area coverage of paths (issue 34): both rules
        assert all(takes(getattr(adapters, cls), scenes(rule)["pentagram"]) for rule in ("nonzero", "evenodd"))


# -- the fill rules, on what decides them ----------------------------------------------------


def test_the_pentagram_centre_follows_the_rule(drawn):
    """The centre of a pentagram has winding 2: filled under nonzero, empty under
    even-odd; the five points (winding 1) are filled under both."""
    for (rule, name), (_scene, cov) in drawn.items():
        if name != "pentagram":
            continue
        counts = cov.counts(W, H)
        assert counts[16, 16] == (rule == "nonzero"), rule
        assert counts[5, 15] == 1 and counts[12, 6] == 1, rule  # the top point, the left point


def test_ring_holes_follow_the_rule(drawn, two_d):
    """A hole wound like the outline has winding 2 (filled under nonzero), one wound the
    other way 0; under even-odd both are empty. The ring itself is filled."""
    rings = {key: value for key, value in drawn.items() if key[1].startswith("ring")}
    if two_d.name == "pillow":
        assert not rings  # one contour per call: refused
        return
    for (rule, name), (_, cov) in rings.items():
        counts = cov.counts(W, H)
        assert counts[16, 16] == (rule == "nonzero" and name == "ring-same"), (rule, name)
        assert counts[5, 16] == 1 and counts[16, 5] == 1, (rule, name)


def test_paths_are_filled_independently(drawn, two_d):
    """Overlapping paths each cover the overlap (each is its own primitive), and each
    path's coverage is what it covers alone."""
    for (rule, name), (scene, cov) in drawn.items():
        if name != "overlap":
            continue
        assert cov.counts(W, H)[18, 9] == 2
        for k in range(2):
            assert np.array_equal(path_counts(cov, k), two_d.rasterize(scene.subset([k])).counts(W, H)), (rule, k)


def test_departures_from_the_best_convention_lie_on_edges(drawn, two_d):
    """Against its best-fitting convention (centre samples, any of the eight tie rules,
    unsnapped or snapped as its triangles are), every pixel where the adapter differs
    lies near one of the path's edges: the winding rule itself is followed, only the
    boundary is drawn otherwise. skia and scikit-image: within 1/16 px (ties, and skia's
    snapping to 1/64 px). Pillow: within 2 px (vertices truncated to whole pixels, corners
    nudged). cairo: within 1/16 px, but for two habits of its scan converter shown below:
    it fills a one-pixel gap between two edges of a row, and a few pixels of column 0
    where a self-intersecting path leaves the surface on the left."""
    _, _, snapping, reach = TWO_D[two_d.name]
    convention, found = best_fit(drawn, snapping)
    for (rule, name), pixels in found.items():
        scene, cov = drawn[rule, name]
        for k, x, y in pixels:
            if two_d.name == "cairo":
                exact = path_counts(exact_coverage(scene, convention), k)
                gap_filled = path_counts(cov, k)[y, x] == 1 and exact[y, x - 1: x + 2].tolist() == [1, 0, 1]
                if gap_filled or (x == 0 and name == "offscreen"):
                    continue
            assert distance_to_edges(scene, k, x, y) <= reach, (rule, name, k, x, y, convention)


def test_cairo_fills_a_one_pixel_gap():
    """cairo's aliased fills (cairo-mono-scan-converter.c, ``row``) close a span where the
    winding returns to zero only if the next edge lies more than one pixel further
    (``I(next->x.quo) > xend + 1``): a one-pixel gap between two slanted edges is filled,
    a two-pixel one is not (rectilinear paths go elsewhere and keep the gap)."""
    cairo = need("cairo")
    if cairo.cairo_version_string() != "1.16.0":
        pytest.skip(f"measured with cairo 1.16.0, not {cairo.cairo_version_string()}")
    for gap, filled in ((1.0, True), (2.0, False)):
        left = np.array([[2.0, 2.0], [10.0, 2.0], [10.01, 6.0], [2.0, 6.0]])
        right = np.array([[10.0 + gap, 2.0], [20.0, 2.0], [20.0, 6.0], [10.01 + gap, 6.0]])
        scene = PathScene.from_paths(24, 8, [[left, right]], "nonzero")
        row = adapters.CairoFill().rasterize(scene).counts(24, 8)[3]
        exact = exact_coverage(scene, Convention()).counts(24, 8)[3]
        assert exact[10] == 0 and exact[11] == (gap == 1.0)
        assert row[10] == filled and np.array_equal(np.delete(row, 10), np.delete(exact, 10)), gap


def test_cairo_fills_column_0_where_a_crossing_path_leaves_the_surface():
    cairo = need("cairo")
    if cairo.cairo_version_string() != "1.16.0":
        pytest.skip(f"measured with cairo 1.16.0, not {cairo.cairo_version_string()}")
    scene = scenes("nonzero")["offscreen"]
    small = adapters.CairoFill().rasterize(scene).counts(W, H)
    moved = scene.with_coordinates(scene.vertices + 64)
    big = adapters.CairoFill().rasterize(PathScene(160, 160, moved.vertices, moved.contour_sizes, moved.contour_path,
                                                   "nonzero")).counts(160, 160)[64:96, 64:96]
    exact = exact_coverage(scene, Convention()).counts(W, H)
    assert np.array_equal(big, exact)
    assert np.argwhere(small != big).tolist() == [[14, 0], [15, 0], [16, 0], [17, 0]]


def test_a_path_of_one_triangle_is_the_triangle(two_d):
    """Under either rule, a path holding one triangle covers what the adapter's triangle
    covers (the same library call but for the fill rule)."""
    rng = np.random.default_rng(5)
    triangles = rng.uniform(-4, 36, (20, 3, 2))
    triangle_cov = two_d.rasterize(Scene(W, H, triangles))
    for rule in two_d.fill_rules:
        paths = two_d.rasterize(PathScene.from_paths(W, H, [[t] for t in triangles], rule))
        assert paths == triangle_cov, rule


# -- what each library can and cannot do ------------------------------------------------------


def test_pillow_refuses_what_it_cannot_fill():
    need("PIL")
    pillow = adapters.PillowPolygon()
    with pytest.raises(ValueError, match="pillow: path 1 has 2 contours"):
        pillow.rasterize(PathScene.from_paths(W, H, [[star(8, 8, 6)], [OCTAGON, HOLE]], "evenodd"))
    with pytest.raises(ValueError, match="evenodd only"):
        pillow.rasterize(scenes("nonzero")["pentagram"])


def test_skimage_bridges_add_no_crossing():
    """scikit-image fills one polygon: the path's contours joined by bridges walked both
    ways. Away from the edges that is exactly the parity of the contours: the XOR of each
    contour filled alone."""
    need("skimage")
    skimage = adapters.SkimagePolygon()
    rng = np.random.default_rng(3)
    for _ in range(5):
        contours = [rng.uniform(-3, 35, (int(rng.integers(3, 9)), 2)) for _ in range(3)]
        together = skimage.rasterize(PathScene.from_paths(W, H, [contours], "evenodd")).counts(W, H)
        each = skimage.rasterize(PathScene.from_paths(W, H, [[c] for c in contours], "evenodd"))
        xor = np.bitwise_xor.reduce([path_counts(each, k) for k in range(3)])
        assert np.array_equal(together, xor)


def test_a_bridge_is_exact_for_skimage_not_for_pillow():
    """Two squares apart, joined into one polygon by a bridge walked both ways
    (:func:`rasterizers.real.adapters.bridged`): scikit-image fills exactly the two
    squares, Pillow also the pixels along the bridge (it fills edges inclusively), which
    is why the Pillow adapter refuses paths of several contours rather than bridge them."""
    need("PIL")
    need("skimage")
    from PIL import Image, ImageDraw

    left = np.array([[2.0, 2.0], [8.0, 3.0], [7.0, 9.0], [3.0, 8.0]])
    right = np.array([[20.0, 2.0], [28.0, 4.0], [26.0, 9.0], [21.0, 8.0]])

    def pillow(polygon):
        image = Image.new("L", (W, 12), 0)
        ImageDraw.Draw(image).polygon((polygon - 0.5).ravel().tolist(), fill=255)
        return np.asarray(image) > 0

    extra = pillow(adapters.bridged([left, right])) & ~(pillow(left) | pillow(right))
    assert np.argwhere(extra).tolist() == [[1, x] for x in range(2, 19)]  # row 1, along the bridge
    skimage = adapters.SkimagePolygon()
    apart = skimage.rasterize(PathScene.from_paths(W, 12, [[left], [right]], "evenodd")).counts(W, 12)
    assert np.array_equal(skimage.rasterize(PathScene.from_paths(W, 12, [[left, right]], "evenodd")).counts(W, 12), apart)


def test_skia_builds_the_path_it_would_build_vertex_by_vertex():
    """The serialized path read in one call is byte for byte the path of moveTo, lineTo
    and close per contour (a NaN vertex too)."""
    skia = need("skia")
    contours = [star(16, 16, 14), np.array([[1.0, 2.0], [np.nan, 3.0], [5.0, 1e6]]), np.array([[4.0, 4.0]])]
    for rule, fill_type in (("nonzero", skia.PathFillType.kWinding), ("evenodd", skia.PathFillType.kEvenOdd)):
        path = skia.Path()
        path.setFillType(fill_type)
        for c in contours:
            path.moveTo(*c[0])
            for x, y in c[1:]:
                path.lineTo(x, y)
            path.close()
        built = adapters._skia_path(skia, contours, rule)
        assert bytes(built.serialize()) == bytes(path.serialize()), rule


def test_non_finite_and_far_paths(two_d):
    """A path with a NaN vertex is the library's business (drawn or refused, naming the
    path) but never takes the others with it; a path far away covers nothing; one that
    holds the screen covers all of it."""
    rule = two_d.fill_rules[0]
    good = star(16, 16, 12)
    scene = PathScene.from_paths(W, H, [[good], [np.array([[2.0, 2.0], [np.nan, 9.0], [9.0, 2.0]])]], rule)
    try:
        cov = two_d.rasterize(scene)
    except (ValueError, RuntimeError) as exc:
        assert "path 1" in str(exc)
    else:
        assert np.array_equal(path_counts(cov, 0), two_d.rasterize(scene.subset([0])).counts(W, H))
    far = np.array([[1e5, 1e5], [1e5 + 9, 1e5], [1e5, 1e5 + 9]])
    huge = np.array([[-1e5, -1e5], [1e5, -1e5], [1e5, 1e5], [-1e5, 1e5]])
    cov = two_d.rasterize(PathScene.from_paths(W, H, [[far], [huge]], rule))
    assert path_counts(cov, 0).sum() == 0 and (path_counts(cov, 1) == 1).all()


def test_each_path_is_drawn_in_its_box_within_the_screen():
    """draw_each_path hands the library every contour of a path at once, shifted to its
    box (the bounding box plus the margin, cut to the screen), never more than the
    screen; a path wholly off-screen is not drawn; a NaN path gets the screen."""
    calls = []

    def library(contours, w, h, origin):
        calls.append(([c.copy() for c in contours], w, h, origin))
        return np.ones((h, w), dtype=bool)

    ring = [OCTAGON, HOLE]
    huge = [np.array([[-1e5, 3.0], [1e5, 3.0], [0.0, 1e5]])]
    away = [np.array([[500.0, 500.0], [509.0, 500.0], [500.0, 509.0]])]
    nan = [np.array([[1.0, 1.0], [np.nan, 2.0], [3.0, 4.0]])]
    cov = draw_each_path(PathScene.from_paths(W, H, [ring, huge, away, nan]), "lib", library)
    (contours, w, h, origin), (_, w1, h1, origin1), (nan_contours, w3, h3, origin3) = calls
    assert origin == (0, 0) and (w, h) == (W, H) and len(contours) == 2  # 2.5 - 2 floors to 0; 29.5 + 2 ceils to 32
    assert np.array_equal(contours[1], HOLE)
    assert origin1 == (0, 1) and (w1, h1) == (W, H - 1)
    assert origin3 == (0, 0) and (w3, h3) == (W, H) and np.isnan(nan_contours[0][1, 0])
    assert sorted(set(cov.primitive.tolist())) == [0, 1, 3]
    small = [np.array([[10.25, 12.5], [14.0, 12.5], [10.25, 17.0]])]
    calls.clear()
    draw_each_path(PathScene.from_paths(W, H, [small]), "lib", library)
    (contours, w, h, origin), = calls
    assert origin == (8, 10) and (w, h) == (16 - 8, 19 - 10)
    assert contours[0].tolist() == [[2.25, 2.5], [6.0, 2.5], [2.25, 7.0]]


def test_a_fan_of_fans_counts_the_winding_number():
    """The signed count of the chunked fan's triangles at each sample (each triangle
    decided by the oracle's top-left rule, as llvmpipe decides it) is the contour's
    winding number there: nonzero and odd exactly where the path oracle says, ties
    included (vertices on a quarter-pixel lattice)."""
    rng = np.random.default_rng(8)
    contour = np.round(rng.uniform(-2, 34, (150, 2)) * 4) / 4
    scene = PathScene.from_paths(W, H, [[contour]])
    index = fan_indices(np.arange(150), 8)
    assert index.shape == (148, 3) and set(np.unique(index)) == set(range(150))
    triangles = contour[index]
    area = (triangles[:, 1, 0] - triangles[:, 0, 0]) * (triangles[:, 2, 1] - triangles[:, 0, 1]) \
        - (triangles[:, 1, 1] - triangles[:, 0, 1]) * (triangles[:, 2, 0] - triangles[:, 0, 0])
    cov = exact_coverage(Scene(W, H, triangles), Convention())
    t, x, y = cov.pixels()
    count = np.zeros((H, W), dtype=np.int64)
    np.add.at(count, (y, x), np.sign(area[t]).astype(np.int64))
    for rule, inside in (("nonzero", count != 0), ("evenodd", count % 2 == 1)):
        assert np.array_equal(exact_coverage(scene.with_fill_rule(rule), Convention()).counts(W, H) == 1, inside), rule


def test_path_extents_are_the_scenes_boxes():
    """The adapters' per-contour reduction gives PathScene.primitive_boxes exactly (NaN
    vertices, paths of several contours, contours of one vertex)."""
    rng = np.random.default_rng(6)
    for _ in range(40):
        paths = [[rng.uniform(-5, 5, (int(rng.integers(1, 6)), 2)) for _ in range(int(rng.integers(1, 4)))]
                 for _ in range(int(rng.integers(1, 5)))]
        scene = PathScene.from_paths(9, 9, paths)
        vertices = scene.vertices.copy()
        vertices[rng.random(vertices.shape) < 0.05] = np.nan
        scene = scene.with_coordinates(vertices)
        for mine, theirs in zip(path_extents(scene), scene.primitive_boxes()):
            assert np.array_equal(mine, theirs)


def test_pieces_of_the_stencil_adapter():
    """The fans (per contour from its first vertex), the cover boxes (bounding box plus a
    pixel, on screen; the screen for a NaN path), the layers (boxes of one layer share no
    pixel), and the fragment read-back's spans, without a GL context."""
    scene = PathScene.from_paths(W, H, [[OCTAGON, HOLE], [np.array([[0.0, 0.0], [1.0, 0.0]])],
                                        [np.array([[np.nan, 1.0], [4.0, 4.0], [1.0, 4.0]])], [star(40, 40, 3)]])
    triangles, first, count = fans(scene)
    assert count.tolist() == [6 + 2, 0, 1, 3] and first.tolist() == [0, 8, 8, 9]
    assert np.array_equal(triangles[6], [HOLE[0], HOLE[1], HOLE[2]])
    boxes = cover_boxes(scene, np.isfinite(scene.primitive_boxes()[0]).all(axis=1) & np.array([1, 1, 0, 1], dtype=bool))
    assert boxes.tolist() == [[1, 1, 31, 31], [0, 0, 2, 1], [0, 0, W, H], [W, H, W, H]]
    rng = np.random.default_rng(0)
    lo = rng.integers(0, 200, (300, 2))
    many = np.c_[lo, lo + rng.integers(1, 40, (300, 2))]
    layer = layers(many)
    for a in range(300):
        same = np.flatnonzero(layer == layer[a])
        same = same[same != a]
        apart = (many[same, 2] <= many[a, 0]) | (many[a, 2] <= many[same, 0]) \
            | (many[same, 3] <= many[a, 1]) | (many[a, 3] <= many[same, 1])
        assert apart.all()
    assert layer.max() < 40  # far fewer draws than paths
    path, x, y = rng.integers(0, 5, 400), rng.integers(0, 9, 400), rng.integers(0, 7, 400)  # repeats too
    assert coverage_from_fragments(path, x, y, 9, 7) == Coverage.from_pixels(path, x, y)


# -- Mesa, in a fresh process per driver ----------------------------------------------------

MESA = """
import json, sys
import numpy as np
from harness.contract.scenes import PathScene, Scene
from harness.contract.conventions import Convention, TIE_RULES
from harness.contract.protocol import receive
from harness.oracle.coverage import exact_coverage
from harness.engine.registry import Unavailable, load
from tests.rasterizers.real.test_adapters_paths import scenes, star, W, H
try:
    r = load(sys.argv[1])
    r._context()
except Unavailable as exc:
    print("UNAVAILABLE", exc)
    raise SystemExit(0)
out = {"renderer": r._ctx.info["GL_RENDERER"], "listed": r._list_program is not None}
conventions = [Convention(tie=t, subpixel_bits=b) for t in TIE_RULES for b in (None, 8)]

def differing(scene, cov, convention):
    exact = exact_coverage(receive(r, scene), convention)
    return sum(int((cov.take(np.flatnonzero(cov.primitive == k)).counts(W, H)
                    != exact.take(np.flatnonzero(exact.primitive == k)).counts(W, H)).sum()) for k in range(len(scene)))

# the hand-made scenes: pixels differing from each candidate convention, and the truths;
# "snap": a right edge at x = 10.5 + 1/512, on column 10's samples once snapped to 1/256
# (half to even), right of them unsnapped
hand = {}
for rule in ("nonzero", "evenodd"):
    snap = PathScene.from_paths(W, H, [[np.array([[2.0, 2.0], [10.5 + 1 / 512, 2.0], [10.5 + 1 / 512, 8.0], [2.0, 8.0]])]], rule)
    # a fan of fans
    long = PathScene.from_paths(W, H, [[np.round(np.random.default_rng(4).uniform(-2, 34, (300, 2)) * 4) / 4]], rule)
    for name, scene in {**scenes(rule), "snap": snap, "long": long}.items():
        cov = r.rasterize(scene)
        hand[f"{rule}/{name}"] = {"same": cov == exact_coverage(receive(r, scene), Convention(subpixel_bits=8)),
                                  "centre": int(cov.counts(W, H)[16, 16])}
        for c in conventions:
            out.setdefault("fit", {}).setdefault(repr(c), 0)
            out["fit"][repr(c)] += differing(scene, cov, c)
out["hand"] = hand

# random lattice and float scenes, both rules: paths of 1-3 contours of 1-12 vertices
rng = np.random.default_rng(11)
random, agree = 0, 0
n = int(sys.argv[2])
for trial in range(n):
    rule = ("nonzero", "evenodd")[trial % 2]
    grid = (0.5, 0.25, 1 / 512, None)[trial % 4]
    paths = []
    for _ in range(int(rng.integers(1, 5))):
        contours = []
        for _ in range(int(rng.integers(1, 4))):
            v = rng.uniform(-12, 52, (int(rng.integers(1, 13)), 2))
            contours.append(v if grid is None else np.round(v / grid) * grid)
        paths.append(contours)
    scene = PathScene.from_paths(40, 40, paths, rule)
    random += 1
    agree += r.rasterize(scene) == exact_coverage(receive(r, scene), Convention(subpixel_bits=8))
out["random"], out["agree"] = random, agree

# one draw per layer with the fragment list == one colour read-back per path
if r._list_program is not None:
    scene = PathScene.from_paths(64, 64, [[star(*rng.uniform(0, 64, 2), rng.uniform(3, 20), turn=rng.uniform(0, 6))]
                                          for _ in range(60)], "nonzero")
    listed = r.rasterize(scene)
    program, r._paths.cover_program = r._paths.cover_program, None
    out["listed_equals_each"] = listed == r.rasterize(scene)
    r._paths.cover_program = program
    BUDGET = type(r._paths).BUDGET
    type(r._paths).BUDGET = 300  # batches of a few paths, and paths alone
    out["batched_equals_one_batch"] = r.rasterize(scene) == listed
    type(r._paths).BUDGET = BUDGET

# a path of one triangle is the triangle
triangles = rng.uniform(-4, 36, (20, 3, 2))
tri = r.rasterize(Scene(W, H, triangles))
out["one_triangle"] = all(r.rasterize(PathScene.from_paths(W, H, [[t] for t in triangles], rule)) == tri
                          for rule in ("nonzero", "evenodd"))

# the 8-bit stencil: a square wound 256 times reads as winding 0 under nonzero
square = np.array([[4.0, 4.0], [12.0, 4.0], [12.0, 12.0], [4.0, 12.0]])
wound = PathScene.from_paths(16, 16, [[np.tile(square, (256, 1))], [np.tile(square, (255, 1))]], "nonzero")
cov = r.rasterize(wound)
out["wound_256"] = int(cov.take(np.flatnonzero(cov.primitive == 0)).n_pixels)
out["wound_255"] = int(cov.take(np.flatnonzero(cov.primitive == 1)).n_pixels)

# a NaN path and a path far away alongside a good one
good = star(16, 16, 12)
scene = PathScene.from_paths(W, H, [[good], [np.array([[2.0, 2.0], [np.nan, 9.0], [9.0, 2.0]])],
                                    [np.array([[5e3, 5e3], [5e3 + 9, 5e3], [5e3, 5e3 + 9]])]], "evenodd")
cov = r.rasterize(scene)
out["nan_keeps_others"] = cov.take(np.flatnonzero(cov.primitive == 0)) == r.rasterize(scene.subset([0]))
out["far_covers_nothing"] = int(cov.take(np.flatnonzero(cov.primitive == 2)).n_pixels) == 0
try:
    r.rasterize(PathScene.from_paths(W, H, [[good], [np.array([[0.0, 0.0], [1e30, 0.0], [0.0, 5.0]])]], "nonzero"))
    out["refused"] = ""
except ValueError as exc:
    out["refused"] = str(exc)
print(json.dumps(out))
"""


def _mesa(driver: str, random_scenes: int) -> dict:
    done = subprocess.run([sys.executable, "-c", MESA, driver, str(random_scenes)], capture_output=True, text=True,
                          timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    if done.stdout.startswith("UNAVAILABLE"):
        pytest.skip(done.stdout.strip())
    measured: dict = json.loads(done.stdout.strip().splitlines()[-1])
    return measured


@pytest.fixture(scope="module")
def llvmpipe():
    return _mesa("mesa_llvmpipe", 60)


@pytest.fixture(scope="module")
def softpipe():
    return _mesa("mesa_softpipe", 0)


def test_llvmpipe_is_the_exact_oracle_of_its_triangles_convention(llvmpipe):
    """Stencil-then-cover inherits llvmpipe's triangle rule (centre, top-left, 8 bits):
    every hand-made scene and 60 random ones (lattices of 1/2, 1/4 and 1/512 px, where
    edges and vertices sit on samples, and floats), both rules, pixel for pixel; every
    other tie rule and the unsnapped convention differ somewhere."""
    assert "llvmpipe" in llvmpipe["renderer"] and llvmpipe["listed"]
    assert all(v["same"] for v in llvmpipe["hand"].values()), llvmpipe["hand"]
    assert llvmpipe["agree"] == llvmpipe["random"] == 60
    fit = llvmpipe["fit"]
    assert fit[repr(Convention(subpixel_bits=8))] == 0
    assert min(v for k, v in fit.items() if k != repr(Convention(subpixel_bits=8))) > 0, fit


def test_llvmpipe_fill_rules_and_their_limits(llvmpipe):
    hand = llvmpipe["hand"]
    assert hand["nonzero/pentagram"]["centre"] == 1 and hand["evenodd/pentagram"]["centre"] == 0
    assert hand["nonzero/ring-same"]["centre"] == 1 and hand["nonzero/ring-opposite"]["centre"] == 0
    assert hand["evenodd/ring-same"]["centre"] == 0
    assert llvmpipe["one_triangle"]
    assert llvmpipe["wound_256"] == 0 and llvmpipe["wound_255"] == 64  # 8-bit stencil: 256 turns read as none
    assert llvmpipe["nan_keeps_others"] and llvmpipe["far_covers_nothing"]
    assert "mesa_llvmpipe: path 1 has a coordinate beyond" in llvmpipe["refused"]


def test_llvmpipe_layers_and_batches_change_nothing(llvmpipe):
    """Paths drawn a layer per draw through the fragment list, in one batch or in many,
    cover what one path at a time read back by colour covers."""
    assert llvmpipe["listed_equals_each"] and llvmpipe["batched_equals_one_batch"]


def test_softpipe_follows_the_rules(softpipe):
    """softpipe (GL 3.3: a colour read-back per path) fills by the same passes; its tie
    rule is its own (its triangles fit top-right ties, unsnapped)."""
    assert "softpipe" in softpipe["renderer"] and not softpipe["listed"]
    hand = softpipe["hand"]
    assert hand["nonzero/pentagram"]["centre"] == 1 and hand["evenodd/pentagram"]["centre"] == 0
    assert hand["nonzero/ring-same"]["centre"] == 1 and hand["evenodd/ring-same"]["centre"] == 0
    assert softpipe["one_triangle"] and softpipe["wound_256"] == 0 and softpipe["wound_255"] == 64
    fit = softpipe["fit"]
    assert fit[repr(Convention(tie="top-right"))] == 0, fit  # on these scenes; see MesaLlvmpipe's docstring
