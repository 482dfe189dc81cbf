"""The real adapters on line scenes (rasterizers.real.adapters): each segment drawn so that
its pixels are named by it, compared with the exact line oracles (harness.oracle.lines).

Pillow and scikit-image draw integer Bresenham with both end pixels (Pillow truncating
coordinates toward zero, scikit-image's end points rounded by the adapter to the nearest
pixel, halves to even); cairo 1.16 strokes rectangles (butt caps) under its fill rule;
skia draws hairlines of its own; llvmpipe follows the diamond-exit rule after 8-bit
snapping but for ties; softpipe draws Bresenham between truncated end points without the
last pixel. Mesa picks its driver once per process, so each Mesa adapter is exercised in
one fresh Python per module, whose findings the tests below read."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.protocol import takes
from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from harness.oracle.coverage import exact_coverage
from rasterizers.real import adapters
from rasterizers.real._lines import RESTART, draw_lists
from rasterizers.real._masks import LIMIT, draw_each_segment, segment_boxes
from tests.optional import need

ROOT = Path(__file__).parents[3]
W = H = 48
TWO_D = {"pillow": "PillowPolygon", "skimage": "SkimagePolygon", "cairo": "CairoFill", "skia": "SkiaPath"}

# the candidate rules (each after the snapping the library's rule implies)
RULES = {
    "diamond-exit": Convention(line="diamond-exit"),
    "diamond-exit/8 bits": Convention(subpixel_bits=8, line="diamond-exit"),
    "bresenham/floor": Convention(line=LineRule("bresenham", rounding="floor")),
    "bresenham/floor/no last": Convention(line=LineRule("bresenham", rounding="floor", last_pixel=False)),
    "bresenham/nearest-even": Convention(line=LineRule("bresenham", rounding="nearest-even")),
    "rectangle/top-left": Convention(line="rectangle"),
    "rectangle/top-left/8 bits": Convention(subpixel_bits=8, line="rectangle"),
}


# -- the scenes -----------------------------------------------------------------------------

# a polyline whose joint (10.5, 2.5) is a pixel centre: a horizontal run then a vertical one
ELBOW = LineScene.from_strips(W, H, [[[2.5, 2.5], [10.5, 2.5], [10.5, 9.5]]])
JOINT = (10, 2)
# axis-aligned and diagonal segments from pixel centre to pixel centre, each also reversed
STRAIGHT = {
    "horizontal": ((2.5, 4.5), (9.5, 4.5)),
    "vertical": ((4.5, 12.5), (4.5, 18.5)),
    "diagonal": ((20.5, 20.5), (26.5, 26.5)),
}


def straight_scene():
    """Each STRAIGHT segment forwards, then each backwards: 6 segments."""
    a = [p for p, q in STRAIGHT.values()] + [q for p, q in STRAIGHT.values()]
    b = [q for p, q in STRAIGHT.values()] + [p for p, q in STRAIGHT.values()]
    return LineScene.from_segments(W, H, a, b)


def random_scene(seed, grid=None, low=2.0, high=46.0, strips=40):
    """Polylines of 2-5 vertices within [low, high]^2, on a ``grid`` (or floats)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(strips):
        v = rng.uniform(low, high, (int(rng.integers(2, 6)), 2))
        out.append(v if grid is None else np.round(v / grid) * grid)
    return LineScene.from_strips(W, H, out)


def far_scene(seed=1, n=40):
    """Segments from up to 6,000 px off-screen into it (Mesa must not clip them)."""
    rng = np.random.default_rng(seed)
    return LineScene.from_segments(W, H, rng.uniform(-6000, 6000, (n, 2)), rng.uniform(0, W, (n, 2)))


def truncated(scene):
    """The scene with every coordinate truncated toward zero (C's ``(int)`` cast)."""
    return scene.with_coordinates(np.trunc(scene.vertices))


def pixel_set(cov):
    """{(segment, x, y)}."""
    primitive, x, y = cov.pixels()
    return set(zip(primitive.tolist(), x.tolist(), y.tolist()))


def residual(cov, scene, convention):
    """(segment, pixel) pairs drawn by one of the rasterizer and the oracle only."""
    return len(pixel_set(cov) ^ pixel_set(exact_coverage(scene, convention)))


def segment_pixels(cov, k):
    """Segment k's pixels as sorted [x, y] lists."""
    primitive, x, y = cov.pixels()
    return sorted([int(i), int(j)] for i, j in zip(x[primitive == k], y[primitive == k]))


def hits(cov, x, y):
    """The segments that drew pixel (x, y), with repeats."""
    primitive, px, py = cov.pixels()
    return sorted(primitive[(px == x) & (py == y)].tolist())


# -- pieces, without a library --------------------------------------------------------------


def test_draw_each_segment_attributes_every_pixel_to_its_segment():
    """A fake library drawing each segment's box border: every pixel comes back under the
    segment drawn, once per segment (double hits visible), clipped to the screen; non-finite
    segments are never drawn; a failure names the segment; far coordinates are refused."""
    seen = []

    def border(a, b, w, h, origin):
        seen.append((a.tolist(), b.tolist(), w, h, origin))
        mask = np.zeros((h, w), dtype=bool)
        mask[0, :] = True
        return mask

    scene = LineScene.from_strips(8, 6, [[[1.0, 1.0], [3.0, 1.0], [3.0, 4.0]], [[np.nan, 1.0], [2.0, 2.0]],
                                         [[6.0, 5.0], [9.0, 9.0]]])
    cov = draw_each_segment(scene, "border", border, margin=1)
    assert [s[4] for s in seen] == [(0, 0), (1, 0), (4, 3)]  # the NaN segment (2) never reaches the library
    assert seen[0] == ([1.0, 1.0], [3.0, 1.0], 5, 3, (0, 0))  # box [0.5, 3.5] x [0.5, 1.5] grown by 1 px
    assert cov.primitive.tolist() == [0, 1, 3] and cov.x1.tolist() == [5, 5, 8]  # segment 3 clipped at x = 8
    assert hits(cov, 2, 0) == [0, 1]  # both segments of the strip drew pixel (2, 0)
    boxes, drawn = segment_boxes(scene, "border", margin=1)
    assert drawn.tolist() == [0, 1, 3] and boxes[3].tolist() == [4, 3, 8, 6]

    def broken(a, b, w, h, origin):
        raise ZeroDivisionError("no")

    with pytest.raises(RuntimeError, match=r"border: the library failed on segment 0 \[1.0, 1.0\] -> \[3.0, 1.0\]"):
        draw_each_segment(scene, "border", broken)
    far = LineScene.from_segments(8, 6, [[1.0, 1.0], [0.0, 0.0]], [[2.0, 2.0], [2 * LIMIT, 0.0]])
    with pytest.raises(ValueError, match="border: segment 1 has a coordinate beyond"):
        draw_each_segment(far, "border", border)


def test_draw_lists_split_strips_at_left_out_segments():
    """GL_LINES for separate segments, GL_LINE_STRIP runs for polylines, a run cut where a
    segment is left out (a NaN vertex), restarts between runs."""
    scene = LineScene.from_strips(9, 9, [[[0, 0], [1, 1], [2, 2], [3, 3], [4, 4]], [[5, 5], [6, 6]], [[7, 7], [8, 8], [1, 8]]])
    lines, line_segments, strip, strip_segments = draw_lists(scene, np.array([0, 2, 3, 4, 5, 6]))
    assert lines.tolist() == [5, 6] and line_segments.tolist() == [4]
    assert [-1 if i == RESTART else i for i in strip.tolist()] == [0, 1, -1, 2, 3, 4, -1, 7, 8, 9, -1]
    assert strip_segments.tolist() == [0, 2, 3, 5, 6]


def test_nearest_pixel_is_the_oracles_nearest_even_rounding():
    from harness.oracle.lines import end_point_pixels

    rng = np.random.default_rng(2)
    values = np.concatenate([rng.uniform(-40, 40, 500), np.arange(-9.0, 10.0), np.arange(-9.0, 10.0) + 0.5, [-1e-300, 1e-300]])
    assert np.array_equal(adapters.nearest_pixel(values), end_point_pixels(values, "nearest-even").astype(np.int64))


def test_declared_kinds():
    for cls in ("PillowPolygon", "SkimagePolygon", "CairoFill", "SkiaPath", "MesaLlvmpipe", "MesaSoftpipe"):
        assert getattr(adapters, cls).scene_kinds == ("triangles", "paths", "lines")
        assert getattr(adapters, cls).convention is None  # black boxes: identify fingerprints them
    for cls, taken in (("MesaMultisample", False), ("CairoAntialiased", True), ("SkiaAntialiased", True)):
        assert takes(getattr(adapters, cls), ELBOW) == taken  # anti-aliased strokes (issue 34)


def test_antialiased_adapters_stroke_lines():
    # issue 34: the AA modes take lines, one anti-aliased butt stroke per segment
    for cls, module in (("CairoAntialiased", "cairo"), ("SkiaAntialiased", "skia")):
        need(module)
        cov = getattr(adapters, cls)().rasterize(ELBOW)
        assert cov.alpha is not None and set(cov.primitive.tolist()) == {0, 1}


# -- the 2D libraries -----------------------------------------------------------------------


@pytest.fixture(scope="module", params=sorted(TWO_D))
def two_d(request):
    """Each 2D adapter, skipped with its install hint where its library is missing."""
    try:
        return getattr(adapters, TWO_D[request.param])()
    except Unavailable as exc:
        pytest.skip(str(exc))


# joint (10, 2) of ELBOW: which segments draw it
JOINT_HITS = {"pillow": [0, 1], "skimage": [0, 1],  # both end pixels of every segment
              "cairo": [1],  # the horizontal rectangle's right cap passes through the centre (right: out)
              "skia": [0]}  # columns (2.5, 10.5], rows (2.5, 9.5]: the left and upper ends left out


def test_joints_and_attribution(two_d):
    cov = two_d.rasterize(ELBOW)
    assert hits(cov, *JOINT) == JOINT_HITS[two_d.name]
    assert set(cov.primitive.tolist()) == {0, 1}
    vertical = segment_pixels(cov, 1)
    assert all(x == 10 for x, y in vertical)  # every pixel of the vertical segment is its own
    assert cov.take(np.flatnonzero(cov.primitive == 0)) == two_d.rasterize(ELBOW.subset([0]))  # drawn alone, the same


def run(name, lo, hi, shift=0):
    """The pixels lo .. hi (inclusive) of the STRAIGHT segment ``name``; the diagonal's at
    (i + shift, i)."""
    return {"horizontal": [[x, 4] for x in range(lo, hi + 1)], "vertical": [[4, y] for y in range(lo, hi + 1)],
            "diagonal": [[i + shift, i] for i in range(lo, hi + 1)]}[name]


# each STRAIGHT segment's pixels, forwards and backwards
STRAIGHT_ANSWERS = {
    # both end pixels, both directions (Pillow: ImageDraw.line((2, 4, 9, 4)) colours x = 2 .. 9)
    "pillow": {"horizontal": (run("horizontal", 2, 9),) * 2, "vertical": (run("vertical", 12, 18),) * 2,
               "diagonal": (run("diagonal", 20, 26),) * 2},
    # scikit-image's documented example: line(1, 1, 8, 8) is the diagonal 1 .. 8, both ends
    "skimage": {"horizontal": (run("horizontal", 2, 9),) * 2, "vertical": (run("vertical", 12, 18),) * 2,
                "diagonal": (run("diagonal", 20, 26),) * 2},
    # a rectangle from centre to centre, the same both ways: the start cap's centre in (a left
    # or top edge), the end cap's out. The diagonal's caps pass through centres too (its
    # corners, rounded to 24.8, stay symmetric), and there cairo takes the lower-right one:
    # its ties on slanted edges are not top-left (measured, cairo 1.16)
    "cairo": {"horizontal": (run("horizontal", 2, 8),) * 2, "vertical": (run("vertical", 12, 17),) * 2,
              "diagonal": (run("diagonal", 21, 26),) * 2},
    # centre in (min, max] along the major axis, whatever the direction; the diagonal is
    # y-major (|dx| > |dy| fails) and, its upper end on a row centre, each row's x is taken
    # at the previous row's centre (skia starts its 16.16 DDA at the end point, not at the
    # first row drawn): x = y - 1 (measured, skia-python 144.1)
    "skia": {"horizontal": (run("horizontal", 3, 9),) * 2, "vertical": (run("vertical", 13, 18),) * 2,
             "diagonal": (run("diagonal", 21, 26, shift=-1),) * 2},
}


def test_straight_lines_known_answers(two_d):
    """Horizontal, vertical and diagonal segments from pixel centre to pixel centre, and
    each reversed: the pixels each library is documented (or, for skia and cairo, measured)
    to draw."""
    scene = straight_scene()
    cov = two_d.rasterize(scene)
    for k, name in enumerate(STRAIGHT):
        for direction, segment in ((0, k), (1, k + 3)):
            assert segment_pixels(cov, segment) == STRAIGHT_ANSWERS[two_d.name][name][direction], (name, direction)


def test_non_finite_segments_cover_nothing_and_far_ones_are_refused(two_d):
    good = random_scene(3, strips=4)
    bad = LineScene.from_strips(W, H, [*good.strips(), [[1.0, 1.0], [np.nan, 5.0], [9.0, 9.0]], [[np.inf, 2.0], [3.0, 3.0]]])
    cov = two_d.rasterize(bad)
    n = len(good)
    assert not np.isin(cov.primitive, [n, n + 1, n + 2]).any()  # the NaN vertex's two segments, the infinite one
    assert cov.take(np.flatnonzero(cov.primitive < n)) == two_d.rasterize(good)
    far = LineScene.from_segments(W, H, [[1.0, 1.0], [2.0, 2.0]], [[5.0, 5.0], [3e6, 2.0]])
    with pytest.raises(ValueError, match=f"{two_d.name}: segment 1 has a coordinate beyond"):
        two_d.rasterize(far)


def test_line_widths(two_d):
    """Hairline libraries refuse other widths (a skip); cairo 1.16 strokes any width as a
    rectangle."""
    wide = random_scene(4, strips=6).with_line_width(2.5)
    if two_d.name == "cairo" and not two_d.hairlines:
        cov = two_d.rasterize(wide)
        pixels = cov.n_pixels
        assert residual(cov, wide, RULES["rectangle/top-left/8 bits"]) <= 0.02 * pixels, pixels
    else:
        with pytest.raises(Unsupported, match="only"):
            two_d.rasterize(wide)


def test_pillow_is_bresenham_between_truncated_end_points():
    """Pillow: Bresenham from the pixel of each end point cast to int (toward zero), ties
    stepping, both end pixels: exactly, on floats, lattices, coordinates below zero
    (where truncation is not floor: the floor oracle differs) and segments from thousands
    of pixels off-screen (each drawn into an image of its visible box only)."""
    need("PIL")
    pillow = adapters.PillowPolygon()
    rule = RULES["bresenham/floor"]
    for scene in (random_scene(5), random_scene(6, grid=0.5), random_scene(7, low=-6.0, high=30.0), far_scene()):
        assert residual(pillow.rasterize(scene), truncated(scene), rule) == 0
    below = random_scene(7, low=-6.0, high=30.0)
    assert residual(pillow.rasterize(below), below, rule) > 0
    tie = LineScene.from_segments(W, H, [[0.5, 0.5]], [[2.5, 1.5]])  # K = 2, M = 1: the decision variable starts at 0
    assert segment_pixels(pillow.rasterize(tie), 0) == [[0, 0], [1, 1], [2, 1]]  # a tie steps


def test_skimage_is_bresenham_between_nearest_pixels():
    """scikit-image after the adapter's rounding to the nearest pixel centre (halves to
    even): Bresenham with both end pixels, exactly; on a half-pixel lattice end points lie
    on pixel borders, where floor differs."""
    need("skimage")
    skimage = adapters.SkimagePolygon()
    rule = RULES["bresenham/nearest-even"]
    for scene in (random_scene(5), random_scene(6, grid=0.5), random_scene(7, low=-6.0, high=30.0), far_scene()):
        assert residual(skimage.rasterize(scene), scene, rule) == 0
    lattice = random_scene(6, grid=0.5)
    assert residual(skimage.rasterize(lattice), lattice, RULES["bresenham/floor"]) > 0


def test_cairo_strokes_rectangles_under_its_fill_rule():
    """cairo 1.16 (no hairlines): a 1 px wide butt-capped stroke is the rectangle rule
    under cairo's fill convention (centre samples, left ties, 24.8 fixed point): on float
    scenes every departure lies within 1/64 px of the rectangle's boundary (measured with
    cairo 1.16.0: 14 of 2,465 (segment, pixel) pairs, all within 0.005 px); on an integer
    lattice (end points, caps and sides through pixel centres) top-left ties fit best of
    the four x-first rules (measured: 18 of 4,913 pairs differ; right ties 234 and more,
    bottom-left 146: cairo's ties on slanted edges are not a clean rule)."""
    cairo = need("cairo")
    r = adapters.CairoFill()
    if r.hairlines:
        pytest.skip(f"cairo {cairo.cairo_version_string()} draws hairlines")
    scene = random_scene(8)
    cov = r.rasterize(scene)
    rule = RULES["rectangle/top-left/8 bits"]
    exact = pixel_set(exact_coverage(scene, rule))
    a, b = scene.segments()
    departures = pixel_set(cov) ^ exact
    assert 0 < len(departures) <= 0.03 * len(exact), len(departures)
    for k, x, y in departures:
        d, p = b[k] - a[k], np.array([x + 0.5, y + 0.5]) - a[k]
        length = float(np.hypot(*d))
        side = abs(d[0] * p[1] - d[1] * p[0]) / length - 0.5  # signed distance to the sides
        along = float(d @ p) / length
        outside = float(np.hypot(max(side, 0.0), max(-along, along - length, 0.0)))
        inside = min(-side, along, length - along)
        assert (outside if outside > 0 else inside) < 1 / 64, (k, x, y)
    lattice = random_scene(19, grid=1.0, strips=80)
    cov = r.rasterize(lattice)
    fits = {tie: residual(cov, lattice, Convention(subpixel_bits=8, tie=tie, line="rectangle"))
            for tie in ("top-left", "top-right", "bottom-left", "bottom-right")}
    assert min(fits, key=fits.__getitem__) == "top-left" and fits["top-left"] <= 0.01 * cov.n_pixels, fits
    assert min(fits["top-right"], fits["bottom-right"]) > 5 * fits["top-left"], fits


def test_skia_hairlines_are_their_own_rule():
    """skia's hairlines follow none of the three rules: the diamond-exit rule is the
    nearest (measured, skia-python 144.1, float polylines: 101 (segment, pixel) pairs for
    2,163 pixels; the rectangle rule 275, Bresenham 948 and more), and skia draws every
    segment the same in both directions."""
    need("skia")
    r = adapters.SkiaPath()
    scene = random_scene(10)
    cov = r.rasterize(scene)
    fits = {name: residual(cov, scene, rule) for name, rule in RULES.items()}
    assert min(fits, key=fits.__getitem__).startswith("diamond-exit"), fits
    assert 0 < fits["diamond-exit"] <= 0.1 * cov.n_pixels, fits
    assert min(fits[name] for name in fits if not name.startswith("diamond")) > 2 * fits["diamond-exit"], fits
    backwards, origin = scene.reversed()
    again = r.rasterize(backwards)
    assert pixel_set(Coverage(origin[again.primitive], again.y, again.x0, again.x1)) == pixel_set(cov)
    # their own rule, read from SkScan::HairLineRgn (issue 33): exact
    assert residual(cov, scene, Convention(line="skia-hairline")) == 0


def test_qt_cosmetic_lines_are_their_own_rule():
    """Qt's cosmetic lines (QCosmeticStroker::drawLine, square caps) are LineRule("qt-cosmetic")
    exactly on segments inside the canvas (issue 33)."""
    from rasterizers.real import qt_raster

    need("PyQt6")
    r = qt_raster.QtRaster()
    for seed in (3, 10):
        scene = random_scene(seed)
        assert residual(r.rasterize(scene), scene, Convention(line="qt-cosmetic")) == 0


# -- Mesa, in a fresh process per driver ----------------------------------------------------

MESA = """
import json, sys
import numpy as np
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Unsupported
from harness.contract.conventions import Convention
from harness.contract.protocol import receive
from harness.oracle.coverage import exact_coverage
from harness.engine.registry import Unavailable, load
from tests.rasterizers.real.test_adapters_lines import (ELBOW, JOINT, RULES, W, H, far_scene, hits, pixel_set, random_scene,
                                      residual, segment_pixels, straight_scene, truncated)
try:
    r = load(sys.argv[1])
    r._context()
except Unavailable as exc:
    print("UNAVAILABLE", exc)
    raise SystemExit(0)
out = {"renderer": r._ctx.info["GL_RENDERER"], "listed": r._list_program is not None}

cov = r.rasterize(ELBOW)
out["joint"] = hits(cov, *JOINT)
scene = straight_scene()
cov = r.rasterize(scene)
out["straight"] = [segment_pixels(cov, k) for k in range(len(scene))]

# the fit of each rule, on what Mesa receives (float32 coordinates); softpipe's (int) cast too
fits = {}
for label, scene in (("float", random_scene(11)), ("quarter", random_scene(12, grid=0.25)),
                     ("below zero", random_scene(13, low=-6.0, high=30.0)), ("far", far_scene())):
    received = receive(r, scene)
    cov = r.rasterize(scene)
    fits[label] = {name: residual(cov, received, rule) for name, rule in RULES.items()}
    fits[label]["truncated bresenham/floor/no last"] = residual(cov, truncated(received), RULES["bresenham/floor/no last"])
    fits[label]["pixels"] = int(cov.n_pixels)
out["fits"] = fits
# a tie inside the line: at x = 7.5 the line (12, 7) -> (6, 3) passes at y = 4, the corner of
# the diamonds of rows 3 and 4
out["tie"] = segment_pixels(r.rasterize(LineScene.from_segments(16, 16, [[12.0, 7.0]], [[6.0, 3.0]])), 0)

# one draw per segment == the fragment list; many batches == one
scene = random_scene(14)
drawer = r._line_drawer(r._ctx)
whole = r.rasterize(scene)
if drawer.list_program is not None:
    program, drawer.list_program = drawer.list_program, None
    out["listed_equals_each"] = r.rasterize(scene) == whole
    drawer.list_program = program
    budget, type(drawer).BUDGET = type(drawer).BUDGET, 40
    out["batched_equals_one_batch"] = r.rasterize(scene) == whole
    type(drawer).BUDGET = budget
# every strip drawn whole, in one GL_LINE_STRIP draw per strip, colour read back: the union
side = r._side(scene)
fbo = r._ctx.simple_framebuffer((side, side), components=1, dtype="f1")
fbo.use()
r._ctx.viewport = (-side, -side, 2 * side, 2 * side)
fbo.clear(0.0)
buffer = r._ctx.buffer((scene.vertices / side).astype(np.float32).tobytes())
vao = r._ctx.vertex_array(r._program, [(buffer, "2f", "position")])
for start, size in zip(scene.strip_starts.tolist(), scene.strip_sizes.tolist()):
    vao.render(r._moderngl.LINE_STRIP, vertices=size, first=start)
image = np.frombuffer(fbo.read(viewport=(0, 0, W, H), components=1, alignment=1), dtype=np.uint8).reshape(H, W) > 0
out["union_equals_whole_strips"] = bool(np.array_equal(image, whole.counts(W, H) > 0))

# bad input
good = random_scene(3, strips=4)
bad = LineScene.from_strips(W, H, [*good.strips(), [[1.0, 1.0], [np.nan, 5.0], [9.0, 9.0]], [[np.inf, 2.0], [3.0, 3.0]]])
cov = r.rasterize(bad)
out["non_finite_cover_nothing"] = not np.isin(cov.primitive, [len(good), len(good) + 1, len(good) + 2]).any()
out["others_unchanged"] = cov.take(np.flatnonzero(cov.primitive < len(good))) == r.rasterize(good)
try:
    r.rasterize(LineScene.from_segments(W, H, [[1.0, 1.0], [2.0, 2.0]], [[5.0, 5.0], [3e6, 2.0]]))
    out["refused"] = ""
except ValueError as exc:
    out["refused"] = str(exc)
try:
    r.rasterize(good.with_line_width(2.0))
    out["wide"] = ""
except Unsupported as exc:
    out["wide"] = str(exc)
print(json.dumps(out))
"""


def _mesa(driver: str) -> dict:
    done = subprocess.run([sys.executable, "-c", MESA, driver], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    if done.stdout.startswith("UNAVAILABLE"):
        pytest.skip(done.stdout.strip())
    measured: dict = json.loads(done.stdout.strip().splitlines()[-1])
    return measured


@pytest.fixture(scope="module")
def llvmpipe():
    return _mesa("mesa_llvmpipe")


@pytest.fixture(scope="module")
def softpipe():
    return _mesa("mesa_softpipe")


def test_llvmpipe_is_diamond_exit_after_snapping_but_for_ties(llvmpipe):
    """llvmpipe (lp_setup_line.c): the GL rule's start and end pixels decided in float,
    the body a one-pixel-high (wide, y-major) parallelogram rasterized like a triangle
    (8-bit snapping, top-left ties). On float scenes it is the diamond-exit oracle after
    8-bit snapping but for a few pixels (measured, Mesa 22.3.6: 0 of 2,096 (segment,
    pixel) pairs here; 11 of 15,275 on 1,500 random segments, lines within a rounding of
    a diamond corner, where llvmpipe's parallelogram, trimmed in float and snapped, leans
    by a rounding); on a 1/4-pixel lattice lines pass through diamond corners and
    llvmpipe's ties differ (measured: 54 of 2,412)."""
    assert "llvmpipe" in llvmpipe["renderer"] and llvmpipe["listed"]
    assert llvmpipe["joint"] == [1]  # GL: the shared vertex is drawn once, by the segment leaving it
    # from pixel centre to centre the diamond-exit rule draws the start pixel, not the end
    # one; llvmpipe does, but for a y-major segment running up the screen from a centre,
    # whose start pixel it leaves out (lp_setup_line.c decides the start in float, then
    # trims the parallelogram on the assumption that the plane's edge rule would draw it)
    straight = dict(zip([f"{name}/{way}" for way in ("forwards", "backwards") for name in STRAIGHT], llvmpipe["straight"]))
    assert straight == {"horizontal/forwards": run("horizontal", 2, 8), "vertical/forwards": run("vertical", 12, 17),
                        "diagonal/forwards": run("diagonal", 20, 25), "horizontal/backwards": run("horizontal", 3, 9),
                        "vertical/backwards": run("vertical", 13, 17), "diagonal/backwards": run("diagonal", 21, 26)}
    diamond = exact_coverage(straight_scene(), RULES["diamond-exit/8 bits"])
    assert segment_pixels(diamond, 4) == run("vertical", 13, 18)
    fits = llvmpipe["fits"]
    for label in fits:
        best = min((v, k) for k, v in fits[label].items() if k != "pixels")
        assert best[1].startswith("diamond-exit"), fits[label]
    assert fits["float"]["diamond-exit/8 bits"] <= 0.005 * fits["float"]["pixels"], fits["float"]
    assert fits["far"]["diamond-exit/8 bits"] <= 0.005 * fits["far"]["pixels"], fits["far"]  # not clipped: P widened
    assert 0 < fits["quarter"]["diamond-exit/8 bits"] <= 0.05 * fits["quarter"]["pixels"], fits["quarter"]
    # the tie: the diamond-exit rule gives the bottom corner (4) to the upper pixel, row 3;
    # llvmpipe's parallelogram (slope +2/3, y down) has that centre on its upper edge, a
    # right edge under the top-left rule: row 4
    assert [7, 4] in llvmpipe["tie"] and [7, 3] not in llvmpipe["tie"]
    exact = exact_coverage(LineScene.from_segments(16, 16, [[12.0, 7.0]], [[6.0, 3.0]]), RULES["diamond-exit/8 bits"])
    assert [7, 3] in segment_pixels(exact, 0)


def test_llvmpipe_draws_strips_and_batches_alike(llvmpipe):
    """One read-back through the fragment list (gl_PrimitiveID through primitive restarts)
    is one draw per segment read back by colour, in one batch or many; the strips drawn
    whole cover the union."""
    assert llvmpipe["listed_equals_each"] and llvmpipe["batched_equals_one_batch"]
    assert llvmpipe["union_equals_whole_strips"]


def test_softpipe_is_bresenham_between_truncated_end_points(softpipe):
    """softpipe (sp_setup.c, sp_setup_line): integer Bresenham from the (int)-cast window
    coordinates, ties stepping, the last pixel left out: exactly, on floats, lattices and
    coordinates below zero, and on segments from thousands of pixels off-screen (not
    clipped: the clip volume is widened to hold them)."""
    assert "softpipe" in softpipe["renderer"] and not softpipe["listed"]
    assert softpipe["joint"] == [1]
    for label, fit in softpipe["fits"].items():
        assert fit["truncated bresenham/floor/no last"] == 0, (label, fit)
    assert softpipe["fits"]["below zero"]["bresenham/floor/no last"] > 0  # truncation is not floor there
    assert softpipe["union_equals_whole_strips"]


def test_mesa_bad_input(llvmpipe, softpipe):
    for found, name in ((llvmpipe, "mesa_llvmpipe"), (softpipe, "mesa_softpipe")):
        assert found["non_finite_cover_nothing"] and found["others_unchanged"]
        assert f"{name}: segment 1 has a coordinate beyond" in found["refused"]
        assert "1 px wide only" in found["wide"]


def test_triangles_and_paths_are_unchanged(two_d):
    """The line path leaves triangles and paths as they were: a triangle scene and a path
    scene still go to draw_each and draw_each_path."""
    triangles = Scene(16, 16, [[[1.0, 1.0], [12.0, 2.0], [4.0, 13.0]]])
    cov = two_d.rasterize(triangles)
    assert cov.primitive.tolist() and set(cov.primitive.tolist()) == {0}
    path = PathScene.from_paths(16, 16, [[[[1.0, 1.0], [12.0, 2.0], [4.0, 13.0]]]], "evenodd")
    assert two_d.rasterize(path) == cov


LLVMPIPE_PORT = """
import json, sys
from harness.engine.registry import Unavailable, load
from harness.identify.line_probe_scenes import crafted_lines, float_lines, half_step_lines, lattice_lines, nudged_lines
from tests.llvmpipe_lines import llvmpipe_lines
try:
    r = load("mesa_llvmpipe")
    r._context()
except Unavailable as exc:
    print("UNAVAILABLE", exc)
    raise SystemExit(0)
off = pixels = 0
for scene in (crafted_lines(), lattice_lines(0), lattice_lines(0, 60, strips=True), nudged_lines(0), float_lines(0),
              half_step_lines(0, 8)):
    got, port = (set(zip(*(v.tolist() for v in c.pixels()))) for c in (r.rasterize(scene), llvmpipe_lines(scene)))
    off += len(got ^ port)
    pixels += len(got)
print(json.dumps({"off": int(off), "pixels": int(pixels), "version": r._ctx.info["GL_VERSION"]}))
"""


def test_llvmpipe_lines_are_its_float32_procedure_not_a_rule():
    """identify's line probes (crafted, lattice, strips, nudged, float and half-step
    scenes) drawn by llvmpipe are exactly the float32 port of lp_setup_line.c
    (tests/llvmpipe_lines.py): the diamond test in float, the quad's ends moved to pixel
    edges, 1/256 px half-away snapping, inside-out quads dropped. No line rule is: GL
    diamond-exit is the nearest (399 px off), Vulkan's parallelogram, the body alone, is
    farther (measured: Mesa 22.3.6)."""
    done = subprocess.run([sys.executable, "-c", LLVMPIPE_PORT], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    if done.stdout.startswith("UNAVAILABLE"):
        pytest.skip(done.stdout.strip())
    measured = json.loads(done.stdout.strip().splitlines()[-1])
    assert measured["pixels"] > 9000 and measured["off"] == 0, measured
