"""The oracle against the brute-force rational reference and its own rational path."""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cases.strategies import conventions, float_scenes, lattice_scenes, thin_scenes
from harness.contract.conventions import SNAP_ROUNDINGS, TIE_RULES, Convention
from harness.contract.scenes import Scene
from harness.geometry.exact import in_safe_range, orient2d_fraction, orient2d_sign, orientation
from harness.oracle.coverage import exact_coverage, exact_coverage_python
from harness.oracle.reference import brute_force_coverage


def agree(scene, convention):
    fast = exact_coverage(scene, convention)
    assert fast == brute_force_coverage(scene, convention)
    assert fast == exact_coverage_python(scene, convention)
    return fast


@given(lattice_scenes(), conventions())
@example(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]), Convention())
@example(Scene(6, 6, [[[0.5, 0.5], [4.5, 0.5], [0.5, 4.5]], [[4.5, 0.5], [4.5, 4.5], [0.5, 4.5]]]), Convention())
def test_lattice_scenes(scene, convention):
    agree(scene, convention)


@pytest.mark.parametrize("rounding", SNAP_ROUNDINGS)
@pytest.mark.parametrize("tie", TIE_RULES)
@given(scene=lattice_scenes(max_bits=5), sample=st.tuples(*[st.integers(0, 4).map(lambda k: k / 4)] * 2),
       bits=st.one_of(st.none(), st.integers(0, 4)))
@settings(max_examples=30)
def test_every_tie_rule_and_rounding(tie, rounding, scene, sample, bits):
    """All 8 x 3 combinations against the brute-force reference, on lattices finer than
    the snapping grid: vertices land on half steps, samples on vertices and edges."""
    agree(scene, Convention(sample=sample, tie=tie, subpixel_bits=bits, snap_rounding=rounding))


@given(float_scenes(), conventions())
def test_unconstrained_floats(scene, convention):
    agree(scene, convention)


@given(thin_scenes(), conventions(snapping=False))
def test_near_zero_heights_and_widths(scene, convention):
    agree(scene, convention)


@given(lattice_scenes(max_bits=2), st.sampled_from(TIE_RULES))
def test_both_windings_cover_the_same(scene, tie):
    convention = Convention(tie=tie)
    flipped = Scene(scene.width, scene.height, scene.positions[:, ::-1])
    assert exact_coverage(scene, convention) == exact_coverage(flipped, convention)


@pytest.mark.parametrize("tie", TIE_RULES)
def test_vertex_on_sample_and_shared_edges_partition(tie):
    # a fan of 8 triangles around a pixel centre, all vertices on pixel centres
    c = np.array([4.5, 4.5])
    rim = np.array([[0.5, 0.5], [4.5, 0.5], [8.5, 0.5], [8.5, 4.5], [8.5, 8.5], [4.5, 8.5], [0.5, 8.5], [0.5, 4.5]])
    tris = np.array([[c, rim[k], rim[(k + 1) % 8]] for k in range(8)])
    for sample in [(0.5, 0.5), (0, 0), (1, 1)]:
        convention = Convention(sample=sample, tie=tie)
        counts = agree(Scene(10, 10, tris), convention).counts(10, 10)
        assert counts.max() == 1  # no double hit, whatever the tie rule
        assert counts.sum() == 64  # the 8x8 square's samples, each exactly once


def test_huge_coordinates_neither_overflow_nor_lose_pixels():
    big = np.finfo(np.float64).max
    for scale in (1e6, 1e9, 1e30, big):
        # a screen-covering pair of triangles with far-away vertices
        tris = np.array([[[-scale, -scale], [scale, -scale], [-scale, scale]],
                         [[scale, -scale], [scale, scale], [-scale, scale]]])
        counts = exact_coverage(Scene(16, 16, tris), Convention()).counts(16, 16)
        assert (counts == 1).all(), scale
    sliver = np.array([[[-big, 3.25], [big, 3.75], [5.5, 3.5]]])
    agree(Scene(16, 16, sliver), Convention())


def test_non_finite_zero_area_and_culling():
    tris = np.array([
        [[0, 0], [8, 0], [0, 8]],            # clockwise on screen (A > 0)
        [[0, 0], [0, 8], [8, 0]],            # counter-clockwise
        [[np.nan, 0], [8, 0], [0, 8]],
        [[0, 0], [np.inf, 0], [0, 8]],
        [[0, 0], [4, 4], [8, 8]],            # collinear
        [[1, 1], [1, 1], [1, 1]],
    ], dtype=float)
    scene = Scene(8, 8, tris)
    tri = lambda cov: sorted(set(cov.triangle.tolist()))  # noqa: E731
    assert tri(exact_coverage(scene, Convention())) == [0, 1]
    assert tri(exact_coverage(scene, Convention(cull="cw"))) == [1]
    assert tri(exact_coverage(scene, Convention(cull="ccw"))) == [0]


def test_snapping_can_collapse_a_triangle():
    scene = Scene(8, 8, [[[0.0, 0.0], [8.0, 0.001], [0.0, 0.002]]])
    assert exact_coverage(scene, Convention(subpixel_bits=4)).n_pixels == 0
    assert exact_coverage(scene, Convention()).n_pixels == 0  # and it covers no sample anyway


def test_cases_kept_outside_the_project():
    """Hand-worked cases: each expected picture derived on paper from CONVENTIONS.md."""
    # Right triangle, hypotenuse through 4 centres: a right edge (not owned by top-left).
    scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    assert exact_coverage(scene, Convention()).n_pixels == 6
    assert exact_coverage(scene, Convention(tie="bottom-right")).n_pixels == 10
    # The floor convention: rows floor(yt)..floor(yb)-1, columns floor(xl)..floor(xr)-1.
    square = Scene(8, 8, [[[1.2, 1.7], [5.9, 1.7], [5.9, 4.1]], [[1.2, 1.7], [5.9, 4.1], [1.2, 4.1]]])
    counts = exact_coverage(square, Convention(sample=(1, 1), tie="bottom-right")).counts(8, 8)
    expected = np.zeros((8, 8), dtype=np.int32)
    expected[1:4, 1:5] = 1
    assert np.array_equal(counts, expected)


@given(st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=6, max_size=6), st.integers(0, 2))
def test_orient2d_matches_rationals(values, collinear):
    ax, ay, bx, by, cx, cy = values
    if collinear:  # put c on the line through a and b as nearly as floats allow
        t = [0.5, 1 / 3][collinear - 1]
        cx, cy = ax + t * (bx - ax), ay + t * (by - ay)
    exact = orient2d_fraction(ax, ay, bx, by, cx, cy)
    assert orientation(np.array([[[ax, ay], [bx, by], [cx, cy]]]))[0] == exact
    if in_safe_range(np.array(values)):
        assert orient2d_sign(ax, ay, bx, by, cx, cy) == exact


def test_orientation_extremes():
    tiny = 5e-324
    tris = np.array([[[0, 0], [tiny, 0], [0, tiny]], [[0, 0], [1e300, 1e-300], [-1e300, -1e-300]]])
    assert orientation(tris).tolist() == [1, 0]


def test_reference_attributes_affine_and_perspective():
    positions = np.array([[[0.25, 0.5], [11.0, 1.0], [2.0, 10.5]]])
    values = np.array([[[1.0, 0.0], [5.0, 3.0], [-2.0, 7.0]]])
    w = np.array([[1.0, 4.0, 0.5]])
    for scene_w in (None, w):
        scene = Scene(12, 12, positions, attributes=values, w=scene_w)
        cov = exact_coverage(scene, Convention())
        tri, x, y = cov.pixels()
        p = [(Fraction(v[0]), Fraction(v[1])) for v in positions[0]]
        for k in range(0, tri.size, 7):
            sx, sy = Fraction(int(x[k])) + Fraction(1, 2), Fraction(int(y[k])) + Fraction(1, 2)
            e = []
            for i in range(3):
                a, b = p[(i + 1) % 3], p[(i + 2) % 3]
                e.append((b[0] - a[0]) * (sy - a[1]) - (b[1] - a[1]) * (sx - a[0]))
            if scene_w is not None:
                e = [e[i] / Fraction(w[0, i]) for i in range(3)]
            for c in range(2):
                exact = sum(e[i] * Fraction(values[0, i, c]) for i in range(3)) / sum(e)
                assert cov.attributes is not None
                assert abs(cov.attributes[k, c] - float(exact)) <= 1e-12 * max(1.0, abs(float(exact)))
