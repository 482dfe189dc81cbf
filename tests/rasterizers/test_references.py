"""The four reference rasterizers against the oracle of their declared conventions."""

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cases.scenes import fan_mesh, grid_mesh, random_triangles
from cases.strategies import float_scenes, lattice_scenes
from harness.checks import NEAR_TIE, FragmentCounter, deviations, edge_distance
from harness.contract.conventions import SNAP_ROUNDINGS, TIE_RULES, Convention, snap
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from rasterizers.centre_scanline import CentreScanline
from rasterizers.fixed_point import MAX_FIXED, FixedPoint
from rasterizers.floor_scanline import FloorScanline
from rasterizers.pineda_topleft import PinedaTopLeft

BUILTINS: list[FloorScanline | CentreScanline | PinedaTopLeft | FixedPoint] = [FloorScanline(), CentreScanline(), PinedaTopLeft(),
                                                                             FixedPoint()]
ids = [r.name for r in BUILTINS]


def test_each_builtin_satisfies_the_protocol():
    for r in BUILTINS + [FixedPoint(4), FixedPoint(16)]:
        typed: Rasterizer = r  # the static assignment a type checker verifies
        assert isinstance(typed, Rasterizer)


@pytest.mark.parametrize("rasterizer", BUILTINS + [FixedPoint(4), FixedPoint(16)], ids=ids + ["fixed4", "fixed16"])
@given(scene=lattice_scenes(max_bits=4, size=24, max_triangles=6))
def test_pixel_exact_on_lattice_scenes(rasterizer, scene):
    assert rasterizer.rasterize(scene) == exact_coverage(scene, rasterizer.convention)


@pytest.mark.parametrize("rasterizer", [FixedPoint(4), FixedPoint(), FixedPoint(16)], ids=["4", "8", "16"])
@given(scene=float_scenes(size=24, max_triangles=6))
def test_fixed_point_is_exact_on_any_float(rasterizer, scene):
    assert rasterizer.rasterize(scene) == exact_coverage(scene, rasterizer.convention)


@pytest.mark.parametrize("rasterizer", BUILTINS, ids=ids)
def test_float_deviations_are_near_ties_only(rasterizer):
    rng = np.random.default_rng(7)
    worst = 0.0
    for seed in range(20):
        positions = random_triangles(300, 40.0, 200, seed)
        # make edges pass within float rounding of samples: grids of non-dyadic spacing
        positions = np.concatenate([positions, grid_mesh(10, 200, 0.0, seed)])
        positions = positions + rng.uniform(-1, 1) * 1e-3
        scene = Scene(200, 200, positions)
        cov = rasterizer.rasterize(scene)
        missing, extra = deviations(cov, exact_coverage(scene, rasterizer.convention), 200, 200)
        frags = np.concatenate([missing, extra], axis=1)
        d = edge_distance(snap(scene.positions, rasterizer.convention.subpixel_bits), frags, rasterizer.convention.sample)
        if d.size:
            worst = max(worst, float(d.max()))
    assert worst <= NEAR_TIE, worst
    print(f"{rasterizer.name}: largest relative distance of a deviating sample {worst:.3g}")


MESHES = {
    "grid-lattice": grid_mesh(8, 64, 0.0, 1),
    "grid-float": grid_mesh(8, 64, 0.4, 2, "anti"),
    "fan-centre": fan_mesh(32, (32.5, 32.5), 28.0, 3),
    "fan-corner": fan_mesh(16, (32.0, 32.0), 28.0, 4),
    "fan-random": fan_mesh(64, (31.37, 30.91), 28.0, 5),
}


@pytest.mark.parametrize("rasterizer", BUILTINS, ids=ids)
@pytest.mark.parametrize("mesh", MESHES, ids=list(MESHES))
def test_meshes_have_no_cracks_or_double_hits(rasterizer, mesh):
    scene = Scene(64, 64, MESHES[mesh])
    counts = rasterizer.rasterize(scene).counts(64, 64)
    assert counts.max() <= 1
    # the oracle of the same convention fills the same region: pixels whose sample lies
    # inside the union; on a partition its hole count is the rasterizer's
    oracle_counts = exact_coverage(scene, rasterizer.convention).counts(64, 64)
    assert (counts == 0).sum() == (oracle_counts == 0).sum()


@pytest.mark.parametrize("rasterizer", BUILTINS, ids=ids)
def test_non_finite_triangles_cover_nothing_and_the_rest_is_right(rasterizer):
    tris = np.array([[[1, 1], [9, 1], [1, 9]], [[np.nan, 1], [9, 1], [1, 9]], [[2, 2], [np.inf, 3], [2, 9]]], dtype=float)
    scene = Scene(12, 12, tris)
    cov = rasterizer.rasterize(scene)
    assert set(cov.triangle.tolist()) == {0}
    assert cov == exact_coverage(Scene(12, 12, tris[:1]), rasterizer.convention)


@pytest.mark.parametrize("rasterizer", BUILTINS, ids=ids)
def test_out_of_range_coordinates_raise_naming_the_triangle(rasterizer):
    tris = np.array([[[1, 1], [9, 1], [1, 9]], [[1, 1], [1e30, 1], [1, 9]]])
    with pytest.raises(ValueError, match=f"{rasterizer.name}: triangle 1 "):
        rasterizer.rasterize(Scene(12, 12, tris))


def test_fixed_point_overflow_bound():
    # the bound: 8 * MAX_FIXED**2 fits int64 while 8 * (MAX_FIXED + 1)**2 does not
    assert 8 * MAX_FIXED**2 < 2**63 <= 8 * (MAX_FIXED + 1) ** 2
    for bits in (4, 8, 16):
        r = FixedPoint(bits)
        edge = r.max_coordinate - 2.0**-bits
        tris = np.array([[[-edge, -edge], [edge, -edge], [-edge, edge]], [[edge, -edge], [edge, edge], [-edge, edge]]])
        scene = Scene(16, 16, tris)
        counts = r.rasterize(scene).counts(16, 16)
        assert (counts == 1).all()
        assert r.rasterize(scene) == exact_coverage(scene, r.convention)
    with pytest.raises(ValueError, match="subpixel_bits"):
        FixedPoint(3)


@pytest.mark.parametrize("rasterizer", BUILTINS, ids=ids)
@pytest.mark.parametrize("perspective", [False, True])
def test_attributes_match_the_oracle(rasterizer, perspective):
    rng = np.random.default_rng(3)
    positions = random_triangles(20, 300.0, 64, 11)
    values = rng.uniform(-5, 5, size=(20, 3, 2))
    w = rng.uniform(0.5, 4.0, size=(20, 3)) if perspective else None
    scene = Scene(64, 64, positions, attributes=values, w=w)
    cov = rasterizer.rasterize(scene).canonical()
    ref = exact_coverage(scene, rasterizer.convention).canonical()
    assert cov.attributes.shape == (cov.n_pixels, 2)
    assert np.array_equal(np.stack(cov.pixels()), np.stack(ref.pixels()))
    # both interpolate at the same samples from the same (snapped) vertices
    assert np.max(np.abs(cov.attributes - ref.attributes)) <= 1e-9


def pineda_per_pixel(scene, tie="top-left"):
    """The Pineda test at every pixel of the screen, in numpy: the reference the edge
    walk must reproduce exactly (same float expression, same canonical edges)."""
    from harness.geometry.exact import frozen, orientation
    from rasterizers.pineda_topleft import edge_setup
    from tests.known_bad import coverage_from_parts

    ys, xs = np.mgrid[0 : scene.height, 0 : scene.width] + 0.5
    finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
    positions = frozen(np.where(finite[:, None, None], scene.positions, 0.0))  # as the kernel sees them
    sign = orientation(positions)
    tri, px, py = [], [], []
    e = np.empty((3, 6))
    for t in np.flatnonzero(sign):
        edge_setup(positions[t], sign[t], e, *Convention(tie=tie).tie_perturbation)
        inside = np.ones(xs.shape, dtype=bool)
        for ax, ay, dx, dy, s, tl in e:
            value = s * (dx * (ys - ay) - dy * (xs - ax))
            inside &= (value > 0) | ((value == 0) & (tl > 0))
        y, x = np.nonzero(inside)
        tri.append(np.full(x.size, t))
        px.append(x)
        py.append(y)
    return coverage_from_parts(tri, px, py)


@given(scene=float_scenes(size=24, max_triangles=6))
def test_pineda_edge_walk_equals_per_pixel_tests_on_floats(scene):
    assert PinedaTopLeft().rasterize(scene) == pineda_per_pixel(scene)


@given(scene=lattice_scenes(max_bits=4, size=24, max_triangles=6))
def test_pineda_edge_walk_equals_per_pixel_tests_on_lattices(scene):
    assert PinedaTopLeft().rasterize(scene) == pineda_per_pixel(scene)


def test_pineda_edge_walk_equals_per_pixel_tests_on_slivers_and_near_ties():
    rng = np.random.default_rng(5)
    for seed in range(10):
        positions = np.concatenate([grid_mesh(6, 48, 0.0, seed), random_triangles(30, 20.0, 48, seed)])
        slivers = rng.uniform(0, 48, size=(20, 3, 2))
        slivers[:, 2] = slivers[:, 0] + (slivers[:, 1] - slivers[:, 0]) * 0.37 + rng.choice([1e-9, 1e-13, 1e-15], size=(20, 1))
        scene = Scene(48, 48, np.concatenate([positions, slivers]))
        assert PinedaTopLeft().rasterize(scene) == pineda_per_pixel(scene)


@pytest.mark.parametrize("tie", TIE_RULES)
@given(scene=lattice_scenes(max_bits=4, size=24, max_triangles=6))
@settings(max_examples=25)
def test_pineda_and_fixed_point_take_every_tie_rule(tie, scene):
    assert PinedaTopLeft(tie=tie).rasterize(scene) == exact_coverage(scene, Convention(tie=tie))
    assert PinedaTopLeft(tie=tie).rasterize(scene) == pineda_per_pixel(scene, tie)
    fixed = FixedPoint(4, tie=tie)
    assert fixed.rasterize(scene) == exact_coverage(scene, fixed.convention)


@pytest.mark.parametrize("rounding", SNAP_ROUNDINGS)
@given(scene=lattice_scenes(max_bits=8, size=24, max_triangles=6))
@settings(max_examples=25)
def test_fixed_point_takes_every_rounding(rounding, scene):
    for bits in (4, 6):
        fixed = FixedPoint(bits, tie="bottom-left-y-first", snap_rounding=rounding)
        assert fixed.rasterize(scene) == exact_coverage(scene, fixed.convention)


def test_known_bad_edge_functions_take_every_tie_rule():
    from tests.known_bad.edge_functions import EdgeFunctionBug

    scene = Scene(24, 24, np.concatenate([grid_mesh(4, 24, 0.0, 1), fan_mesh(8, (12.5, 12.5), 10.0, 1)]))
    for tie in TIE_RULES:
        bad = EdgeFunctionBug("exclusive", tie=tie)
        assert bad.convention.tie == tie and bad.rasterize(scene) != exact_coverage(scene, bad.convention)


SPANS = st.lists(st.tuples(st.integers(-1, 3), st.integers(-1, 5), st.integers(-2, 7), st.integers(-2, 7)), max_size=12)


@given(SPANS, SPANS)
@settings(max_examples=300)
@example([(0, 1, 0, 3)], [(0, 1, 0, 2), (0, 1, 2, 3)])  # the same fragments: deviations' span-level shortcut
@example([(0, 1, 4, 8)], [(0, 1, 4, 8)])  # the same, partly off-screen: extra, and missing
def test_counting_mismatches_span_by_span_equals_the_deviations(got, want):
    """FragmentCounter (identify's and compare's fast count, which merges an oracle's spans
    without expanding them) agrees with deviations fragment by fragment: any spans,
    off-screen, overlapping and empty ones included."""
    def coverage(spans):
        return Coverage(*(np.array(column, dtype=np.int64) for column in zip(*spans))) if spans else Coverage.empty()

    got_coverage, want_coverage = coverage(got), coverage(want)
    missing, extra = deviations(got_coverage, want_coverage, 6, 5)
    assert FragmentCounter(got_coverage, 6, 5).mismatches(want_coverage) == missing.shape[1] + extra.shape[1]


def test_edge_distance_past_a_vertex_is_from_the_edge_it_lies_outside():
    """A sample exactly on an edge's line but beyond its ends lies clearly outside another
    edge: rounding that edge function would not take it in, so it is that far from a tie
    (a scanline drawing one row too many puts its extra samples there). Outside two edges,
    the farther decides; on the boundary, 0."""
    positions = np.array([[[0.0, 0.0], [4.0, 0.0], [0.5, 4.0]]])
    at = lambda x, y, sample: edge_distance(positions, np.array([[0], [x], [y]]), sample)[0]  # noqa: E731
    slanted = np.hypot(3.5, 4.0)  # the edge (4, 0) -> (0.5, 4)
    assert at(5, -1, (0.5, 1.0)) == pytest.approx(6.0 / slanted / 4)  # (5.5, 0): on y = 0, past (4, 0)
    assert at(2, -1, (0.5, 1.0)) == 0.0  # (2.5, 0): on the edge
    assert at(5, -1, (0.5, 0.5)) == pytest.approx(4.25 / slanted / 4)  # (5.5, -0.5): outside both
    assert at(1, 0, (0.5, 0.5)) == pytest.approx(0.5 / 4)  # (1.5, 0.5): inside, the nearest edge y = 0


def test_a_sliver_within_rounding_of_a_sample_past_its_vertex_is_a_near_tie():
    """A sliver whose third vertex lies within float rounding of its long edge: a sample on
    that edge's extension lies outside the short edges only by rounding -- a float edge
    function may take it in (an inclusive test on the degenerate family's slivers)."""
    positions = np.array([[[0.5, -6.5], [22.5, 15.5], [11.500000000000002, 4.499999999999998]]])
    assert edge_distance(positions, np.array([[0], [23], [16]]), (0.5, 0.5))[0] <= NEAR_TIE


def test_an_extra_pixel_on_an_edge_line_past_its_vertex_fails_conformance():
    """Default tolerance excuses near ties on float cases: a fragment exactly on the line of
    an edge, two pixels past its vertex, is not one."""
    from harness.checks import conformance
    from harness.contract.case import Case

    third = 1.0 / 3.0  # non-dyadic: a float case
    scene = Scene(8, 8, np.array([[[0.5, 0.5], [4.5, 4.5], [0.5 + third, 4.5]]]))
    convention = Convention()
    oracle = exact_coverage(scene, convention)
    t, x, y = oracle.pixels()
    # centre (6.5, 6.5): on the edge's line y = x, past the vertex (4.5, 4.5)
    extra = Coverage(np.append(t, 0), np.append(y, 6), np.append(x, 6), np.append(x, 6) + 1)
    case = Case("float/past-vertex", scene)
    result = conformance(case, extra, oracle, convention)
    assert result.status == "fail"
    assert [(p["x"], p["y"], p["near_tie"]) for p in result.evidence["pixels"]] == [(6, 6, False)]
    assert conformance(case, oracle, oracle, convention).status == "pass"


def test_a_path_sample_on_a_horizontal_edges_row_past_its_end_is_no_tie():
    """Path distances take the edges whose y-range holds the sample: a horizontal edge on
    the sample's row is measured along it -- exactly 0 on it, not on its line past its
    ends (a filler counting horizontal edges as crossings had its wrong samples there read
    as ties)."""
    from harness.checks.conformance import path_edge_distance
    from harness.contract.scenes import PathScene

    path = PathScene(8, 8, np.array([[2.0, 2.5], [6.0, 2.5], [4.0, 6.5]]), np.array([3]), np.array([0]), "nonzero")
    at = lambda x, y: path_edge_distance(path, Convention(), np.array([[0], [x], [y]]))[0]  # noqa: E731
    assert at(4, 2) == 0.0  # (4.5, 2.5): on the horizontal edge
    assert at(7, 2) == pytest.approx(6.0 / np.hypot(2.0, 4.0) / 6.5)  # (7.5, 2.5): the slanted edge is nearer than its end
