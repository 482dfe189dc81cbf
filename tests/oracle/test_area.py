"""Area coverage: the exact rational areas, and the float kernel within its proven bound."""

import itertools
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from cases.partitions import fan, grid
from cases.strategies import float_scenes, lattice_scenes, thin_scenes
from harness.contract.scenes import MAX_VIEWPORT
from harness.geometry.exact import orientation
from harness.oracle.area import (
    GUARD_LIMIT,
    UNIT_ROUNDOFF,
    _clip_to_box,
    _fraction_vertices,
    _shoelace,
    area_error_bound,
    exact_area,
    exact_pixel_areas,
    pixel_areas,
)

SIZE = 8
BIG = float(np.finfo(np.float64).max)


def float_areas(positions, width, height):
    t, x, y, a = pixel_areas(positions, width, height)
    got = {(int(ti), int(xi), int(yi)): float(ai) for ti, xi, yi, ai in zip(t, x, y, a)}
    assert len(got) == t.size, "a pixel reported twice"
    return got


def within_bound(positions, width=SIZE, height=SIZE):
    """Every pixel of every triangle: |float - exact| <= the triangle's bound, exactly
    compared (as rationals); pixels left out must have an exact area within it too."""
    positions = np.asarray(positions, dtype=np.float64)
    got = float_areas(positions, width, height)
    exact = exact_pixel_areas(positions, width, height)
    bound = area_error_bound(positions, width, height)
    for key in got.keys() | exact.keys():
        t, i, j = key
        assert 0 <= i < width and 0 <= j < height
        value = got.get(key, 0.0)
        assert 0.0 < value <= 1.0 or key not in got
        error = abs(Fraction(value) - exact.get(key, Fraction(0)))
        assert error <= Fraction(float(bound[t])), (key, value, exact.get(key), float(bound[t]))
    return got, exact, bound


def clipped_area(polygon, width, height):
    """Exact area of a convex polygon inside the viewport."""
    return _shoelace(_clip_to_box(polygon, Fraction(0), Fraction(0), Fraction(width), Fraction(height)))


# -- strategies: vertices on lattices, floats, slivers, pixel corners, far away ----------


@st.composite
def corner_triangles(draw):
    """Vertices on pixel corners, on pixel edges (one coordinate an integer) or centres."""
    def coordinate():
        return st.integers(-2, 2 * SIZE + 4).map(lambda k: k / 2)
    tri = [(draw(coordinate()), draw(coordinate())) for _ in range(3)]
    return np.array([tri], dtype=np.float64)


@st.composite
def far_triangles(draw):
    """One or two vertices far away (up to the largest float), the rest near the
    viewport: a small on-screen part of a huge triangle."""
    near = st.floats(-2.0, SIZE + 2.0, allow_nan=False, allow_infinity=False)
    far = st.one_of(
        st.integers(21, 1023).flatmap(lambda e: st.sampled_from([2.0**e, -(2.0**e), 1.5 * 2.0**e])),
        st.floats(allow_nan=False, allow_infinity=False),
        st.floats(-2.0**20, 2.0**20, allow_nan=False, allow_infinity=False),
    )
    count = draw(st.integers(1, 2))
    tri = [[draw(far), draw(far)] if k < count else [draw(near), draw(near)] for k in range(3)]
    if draw(st.booleans()):  # a far vertex straight across the viewport: long slivers
        tri[0][draw(st.integers(0, 1))] = draw(near)
    order = draw(st.permutations(range(3)))
    return np.array([[tri[k] for k in order]], dtype=np.float64)


@st.composite
def sliver_triangles(draw):
    """An edge across the viewport and a third vertex a tiny step off it, at any angle."""
    a = np.array([draw(st.floats(-2, SIZE + 2)) for _ in range(2)])
    b = np.array([draw(st.floats(-2, SIZE + 2)) for _ in range(2)])
    t = draw(st.floats(-0.5, 1.5))
    off = draw(st.sampled_from([1e-3, 1e-9, 2.0**-40, 2.0**-52, 5e-324, -1e-12]))
    c = a + t * (b - a) + off * np.array([draw(st.sampled_from([-1, 0, 1])), 1.0])
    return np.array([[a, b, c]])


# -- the exact path -------------------------------------------------------------------------


def test_exact_area_by_hand():
    assert exact_area([[0, 0], [1, 0], [0, 1]], 0, 0) == Fraction(1, 2)
    assert exact_area([[-1, -1], [3, -1], [-1, 3]], 0, 0) == 1
    assert exact_area([[0, 0], [2, 0], [0, 2]], 1, 1) == 0  # touches the corner only
    assert exact_area([[0, 0], [2, 0], [0, 2]], 5, 0) == 0
    assert exact_area([[0, 0], [2, 2], [4, 4]], 1, 1) == 0  # degenerate
    assert exact_area([[0.5, 0.5], [0.5, 0.5], [0.5, 0.5]], 0, 0) == 0
    # a triangle inside one pixel: its own area
    assert exact_area([[0.25, 0.25], [0.75, 0.25], [0.25, 0.5]], 0, 0) == Fraction(1, 16)
    # a huge triangle's edge along pixel (0, 0)'s diagonal: half of it
    assert exact_area([[-1e300, -1e300], [1e300, 1e300], [1e300, -1e300]], 0, 0) == Fraction(1, 2)


@given(lattice_scenes(max_bits=3, size=SIZE, max_triangles=1), st.integers(-1, SIZE), st.integers(-1, SIZE))
def test_exact_area_is_invariant_under_vertex_order_and_whole_pixel_shifts(scene, i, j):
    tri = scene.positions[0]
    area = exact_area(tri, i, j)
    assert 0 <= area <= 1
    for order in itertools.permutations(range(3)):
        assert exact_area(tri[list(order)], i, j) == area
    assert exact_area(tri + [3, -2], i + 3, j - 2) == area


def test_exact_area_refuses_what_it_cannot_measure():
    with pytest.raises(ValueError, match="not finite"):
        exact_area([[0.0, 0.0], [1.0, np.nan], [0.0, 1.0]], 0, 0)
    with pytest.raises(ValueError, match="not finite"):
        exact_area([[0.0, 0.0], [np.inf, 0.0], [0.0, 1.0]], 0, 0)
    with pytest.raises(ValueError, match="3 x 2"):
        exact_area([[0, 0], [1, 0]], 0, 0)
    with pytest.raises(ValueError, match="integers"):
        exact_area([[0, 0], [1, 0], [0, 1]], 0.5, 0)  # type: ignore[arg-type]  # a float pixel, refused


@given(lattice_scenes(max_bits=4, size=SIZE, max_triangles=2))
@settings(max_examples=40)
def test_pixel_areas_of_a_triangle_sum_to_its_area_in_the_viewport(scene):
    exact = exact_pixel_areas(scene.positions, SIZE, SIZE)
    got = float_areas(scene.positions, SIZE, SIZE)
    bound = area_error_bound(scene.positions, SIZE, SIZE)
    for t, tri in enumerate(scene.positions):
        whole = clipped_area(_fraction_vertices(tri), SIZE, SIZE)
        pieces = [a for (u, _, _), a in exact.items() if u == t]
        assert sum(pieces, Fraction(0)) == whole  # exactly
        if np.all((tri >= 0) & (tri <= SIZE)):  # inside: the shoelace of the triangle itself
            (x0, y0), (x1, y1), (x2, y2) = map(lambda v: map(Fraction, v), tri)
            assert whole == abs((x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)) / 2
        floats = [a for (u, _, _), a in got.items() if u == t]
        touched = len({(i, j) for (u, i, j) in exact.keys() | got.keys() if u == t})
        # the float areas, summed exactly: within the bound at every pixel touched
        assert abs(sum(map(Fraction, floats), Fraction(0)) - whole) <= touched * Fraction(float(bound[t]))


# -- the proven bound: float vs exact at every pixel ------------------------------------


@given(lattice_scenes(max_bits=5, size=SIZE, max_triangles=2))
@settings(max_examples=100)
def test_bound_holds_on_dyadic_lattices(scene):
    within_bound(scene.positions)


@given(float_scenes(size=SIZE, max_triangles=2))
@settings(max_examples=100)
def test_bound_holds_on_random_floats(scene):
    within_bound(scene.positions)


@given(st.one_of(thin_scenes(size=SIZE).map(lambda s: s.positions), sliver_triangles()))
@settings(max_examples=100)
@example(np.array([[[0.5, -1e6], [0.5 + 2.0**-40, 1e6], [0.5, 3.0]]]))  # near-vertical, crossing every row
@example(np.array([[[-1e6, 2.5], [1e6, 2.5 + 2.0**-40], [3.0, 2.5]]]))  # near-horizontal
@example(np.array([[[1.0, 1.0], [7.0, 7.0], [4.0, 4.0 + 5e-324]]]))  # diagonal through corners, one subnormal step off
def test_bound_holds_on_slivers(positions):
    within_bound(positions)


@given(corner_triangles())
@settings(max_examples=100)
@example(np.array([[[0, 0], [8, 0], [0, 8]]], dtype=float))
@example(np.array([[[1, 1], [3, 1], [1, 3]]], dtype=float))  # vertices on corners, hypotenuse through them
@example(np.array([[[2, 0.5], [2, 6], [5, 0.5]]], dtype=float))  # a vertical edge on a pixel boundary
def test_bound_holds_with_vertices_on_pixel_corners_and_edges(positions):
    within_bound(positions)


@given(far_triangles())
@settings(max_examples=100)
@example(np.array([[[-BIG, 3.25], [BIG, 3.75], [5.5, 3.5]]]))
@example(np.array([[[-BIG, -BIG], [BIG, -BIG], [-BIG, BIG]]]))  # covers the whole viewport
@example(np.array([[[2.0**1023, 1.0], [1.0, 2.0**1023], [0.5, 0.5]]]))
@example(np.array([[[4.0, -1e300], [4.0 + 2.0**-30, 1e300], [3.5, 0.0]]]))  # a far, steep sliver
@example(np.array([[[-(2.0**21), 0.5], [2.0**21, 7.5], [3.0, 3.0]]]))  # just inside the guard limit
@example(np.array([[[-(2.0**21) - 1, 0.5], [2.0**21, 7.5], [3.0, 3.0]]]))  # just beyond it
def test_bound_holds_far_off_screen(positions):
    within_bound(positions)


@given(st.lists(st.floats(-(2.0**20), 2.0**20, allow_nan=False), min_size=6, max_size=6))
@example([-(2.0**20), -(2.0**20), 2.0**20, -(2.0**20), -(2.0**20), 2.0**20])
def test_bound_is_far_below_an_8_bit_step_within_2_to_the_20(values):
    positions = np.array(values).reshape(1, 3, 2)
    bound = area_error_bound(positions)  # the default viewport: valid for every viewport
    assert bound[0] <= 2.0**-24 < 1 / 256 / 2**15
    assert area_error_bound(positions, SIZE, SIZE)[0] <= bound[0]


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=6, max_size=6))
def test_bound_stays_small_for_any_finite_triangle(values):
    # far triangles are clipped exactly before the float path, so no finite input escapes
    assert area_error_bound(np.array(values).reshape(1, 3, 2))[0] <= 2.0**-24


def test_bound_formula():
    tri = np.array([[[0, 0], [4, 0], [0, 4]], [[0, 0], [1, 1], [2, 2]], [[0, 0], [np.nan, 0], [0, 1]],
                    [[0, 0], [GUARD_LIMIT * 2, 0], [0, 1]]])
    bound = area_error_bound(tri, 10, 20) / UNIT_ROUNDOFF
    assert bound.tolist() == [3 * (22 * 5 + 7) + 9, 0, 0, 7 * (22 * 20 + 11 * 20 + 7) + 49]
    assert area_error_bound(np.zeros((0, 3, 2))).shape == (0,)


# -- seams: planar partitions sum to the union's area, exactly ---------------------------


def union_check(tris, union_area, width, height, interior=None):
    """Per pixel, the exact pieces sum to the union's area there (1 inside); the float
    ones within the sum of the pieces' bounds."""
    got, exact, bound = within_bound(tris, width, height)
    exact_sum: dict[tuple[int, int], Fraction] = {}
    float_sum: dict[tuple[int, int], Fraction] = {}  # the float areas, summed exactly
    slack: dict[tuple[int, int], Fraction] = {}
    for (_, i, j), a in exact.items():
        exact_sum[i, j] = exact_sum.get((i, j), Fraction(0)) + a
    for (_, i, j), a in got.items():
        float_sum[i, j] = float_sum.get((i, j), Fraction(0)) + Fraction(a)
    for t, i, j in got.keys() | exact.keys():
        slack[i, j] = slack.get((i, j), Fraction(0)) + Fraction(float(bound[t]))
    for j in range(height):
        for i in range(width):
            want = union_area(i, j)
            assert exact_sum.get((i, j), Fraction(0)) == want, (i, j)
            assert abs(float_sum.get((i, j), Fraction(0)) - want) <= slack.get((i, j), Fraction(0)), (i, j)
            if interior is not None and interior(i, j):
                assert want == 1 and exact_sum[i, j] == 1
    return exact_sum


def test_huge_screen_covering_pair_sums_to_one_everywhere():
    for scale in (1e6, 2.0**21, 1e30, BIG):
        tris = np.array([[[-scale, -scale], [scale, -scale], [-scale, scale]],
                         [[scale, -scale], [scale, scale], [-scale, scale]]])
        exact_sum = union_check(tris, lambda i, j: 1, SIZE, SIZE)
        assert len(exact_sum) == SIZE * SIZE, scale


def square_overlap(lo, hi):
    def area(i, j):
        w = max(min(Fraction(hi), i + 1) - max(Fraction(lo), i), 0)
        h = max(min(Fraction(hi), j + 1) - max(Fraction(lo), j), 0)
        return w * h
    return area


@given(st.integers(0, 4 * 16), st.integers(1, 6 * 16), st.booleans(), st.booleans())
@settings(max_examples=50)
@example(16, 6 * 16, False, False)
def test_square_split_on_a_diagonal_has_no_seam(lo16, size16, anti, flip):
    lo, hi = lo16 / 16, (lo16 + size16) / 16
    a, b, c, d = (lo, lo), (hi, lo), (lo, hi), (hi, hi)
    tris = np.array([(a, b, c), (b, d, c)] if anti else [(a, b, d), (a, d, c)], dtype=np.float64)
    if flip:
        tris[0] = tris[0][::-1]
    union_check(tris, square_overlap(lo, hi), SIZE + 2, SIZE + 2,
                interior=lambda i, j: lo <= i and i + 1 <= hi and lo <= j and j + 1 <= hi)


@given(st.integers(1, 3), st.integers(0, 2**16), st.sampled_from(["none", "lattice", "float"]),
       st.sampled_from(["main", "anti", "mixed"]), st.integers(0, 16), st.integers(16, 32))
@settings(max_examples=15)
def test_jittered_grid_has_no_seam(cells, seed, jitter, diagonal, lo16, step16):
    rng = np.random.default_rng(seed)
    lo, hi = lo16 / 16, (lo16 + cells * step16) / 16
    tris = grid(cells, lo, hi, jitter, diagonal, rng)
    # a partition only while no triangle folds over: jitter up to 3/8 px can fold a cell
    # under 2.7 px (seed 2408: three jittered corners of a 1 px cell turned a triangle over)
    assume(bool(np.all(orientation(tris) == orientation(tris[:1]))))  # exact signs
    flip = rng.random(len(tris)) < 0.5
    tris[flip] = tris[flip][:, ::-1]
    union_check(tris, square_overlap(lo, hi), SIZE, SIZE)


@given(st.integers(3, 10), st.integers(0, 2**16), st.integers(24, 40), st.integers(24, 40))
@settings(max_examples=12)
@example(8, 1, 32, 32)
def test_fan_around_an_interior_point_has_no_seam(count, seed, cx8, cy8):
    rng = np.random.default_rng(seed)
    centre = np.array([cx8, cy8]) / 8
    tris, rim = fan(count, centre, 3.0, rng)  # rim points on a circle: unconstrained floats
    rim_polygon = _fraction_vertices(rim)

    def area(i, j):
        return _shoelace(_clip_to_box(rim_polygon, Fraction(i), Fraction(j), Fraction(i + 1), Fraction(j + 1)))

    union_check(tris, area, SIZE, SIZE)


# -- the float path's contract ------------------------------------------------------------


def test_pixel_areas_skips_what_covers_nothing_and_sorts_the_rest():
    tris = np.array([
        [[0, 0], [np.nan, 0], [0, 4]],       # non-finite
        [[0, 0], [np.inf, 0], [0, 4]],       # non-finite
        [[1, 1], [3, 3], [5, 5]],            # zero area
        [[0, 0], [4, 0], [0, 4]],
        [[9, 9], [12, 9], [9, 12]],          # off-screen
        [[4, 4], [0, 4], [4, 0]],            # counter-clockwise: drawn the same
    ])
    t, x, y, area = pixel_areas(tris, SIZE, SIZE)
    assert t.dtype == x.dtype == y.dtype == np.int64 and area.dtype == np.float64
    assert set(t.tolist()) == {3, 5}
    assert np.all(np.diff(t * SIZE * SIZE + y * SIZE + x) > 0)
    assert np.all((area > 0) & (area <= 1))
    assert area_error_bound(tris).tolist()[:3] == [0.0, 0.0, 0.0]
    empty = pixel_areas(np.zeros((0, 3, 2)), SIZE, SIZE)
    assert [a.size for a in empty] == [0, 0, 0, 0]


def test_pixel_areas_refuses_bad_input():
    with pytest.raises(ValueError, match="shape"):
        pixel_areas(np.zeros((2, 3)), SIZE, SIZE)
    with pytest.raises(ValueError, match="width"):
        pixel_areas(np.zeros((1, 3, 2)), 0, SIZE)
    with pytest.raises(ValueError, match="height"):
        pixel_areas(np.zeros((1, 3, 2)), SIZE, MAX_VIEWPORT + 1)


def test_a_large_viewport_costs_only_the_pixels_touched():
    # a long thin diagonal across a big viewport: spans per row, not the bounding box
    w = h = 4096
    tris = np.array([[[0.25, 0.5], [w - 0.5, h - 0.25], [w - 0.5, h - 2.0]]])
    t, x, y, area = pixel_areas(tris, w, h)
    assert t.size < 6 * h
    (x0, y0), (x1, y1), (x2, y2) = map(lambda v: map(Fraction, v), tris[0])
    exact_total = abs((x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)) / 2
    float_total = sum(map(Fraction, area.tolist()), Fraction(0))
    assert abs(float_total - exact_total) <= t.size * Fraction(area_error_bound(tris, w, h)[0])


def test_the_tallest_viewport_costs_only_the_rows_touched():
    """A small triangle on a screen 2**20 rows tall: the band segments' decisions take room
    for the triangle's rows, not the viewport's, and the areas are those of a small screen."""
    tris = np.array([[[3.25, 1000.5], [40.0, 1010.0], [9.5, 1037.75]]])
    tall = pixel_areas(tris, 64, MAX_VIEWPORT)
    small = pixel_areas(tris, 64, 1100)
    for a, b in zip(tall, small, strict=True):
        assert np.array_equal(a, b)
    assert tall[0].size > 0


# -- rows without a vertex: the band path (two crossing edges per row) ----------------------


@pytest.mark.parametrize("seed", range(6))
def test_bound_holds_on_large_triangles_rows_without_a_vertex(seed):
    """Most rows of a large triangle hold no vertex: their edge pixels take the band path
    (the difference of two clamped means of band crossings); within the bound everywhere."""
    rng = np.random.default_rng(seed)
    size = 24
    positions = rng.uniform(-6.0, size + 6.0, (4, 3, 2))
    if seed % 2:  # vertices on band lines and pixel corners, shallow and steep edges
        positions = np.round(positions)
        positions[0] = [[-3.0, 2.0], [size + 3.0, 3.0], [5.0, size - 1.0]]  # a shallow edge across the screen
        positions[1] = [[4.0, -2.0], [4.0 + 2.0**-30, size + 2.0], [2.0, 7.0]]  # a steep sliver
    within_bound(positions, size, size)


@given(st.lists(st.floats(-4.0, SIZE + 4.0, allow_nan=False), min_size=6, max_size=6),
       st.sampled_from([1.0, 2.0**-1, 2.0**-8, 2.0**-30, 1e5]))
@settings(max_examples=100)
@example([-3.0, 0.0, 11.0, 1.0, 2.0, 8.0], 1.0)  # a vertex on every band line it meets
@example([0.5, -1e5, 0.5, 1e5, 3.0, 2.0], 1.0)
def test_bound_holds_on_stretched_triangles(values, scale):
    """Triangles stretched in y (many vertex-free rows, steep edges) or squashed (shallow)."""
    tri = np.array(values).reshape(1, 3, 2) * np.array([1.0, scale])
    within_bound(tri)
