"""The area oracle's runs (interior pixels as runs, edge pixels one by one) against the
kernel they replaced (:mod:`tests.oracle.area_reference`): the same rows and inner runs, every
alpha within the proven bounds of the old one and of the exact area, on random, lattice, far,
degenerate and hypothesis scenes; and :class:`AlphaRuns` as a form of the one
:class:`Coverage` contract."""

import pickle

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cases.strategies import float_scenes, lattice_scenes, thin_scenes
from harness.contract.conventions import Convention
from harness.contract.coverage import AlphaRuns, Coverage
from harness.contract.scenes import Scene
from harness.engine.outcomes import Outcome, decode_outcome, encode_outcome
from harness.geometry.spans import expand
from harness.oracle.area import _area_runs, _area_spans, _polygons, area_coverage, area_error_bound
from harness.oracle.coverage import exact_coverage
from tests.oracle.area_reference import old_area_spans, two_pass_area_runs
from tests.oracle.test_area import SIZE, corner_triangles, far_triangles, sliver_triangles, within_bound

BIG = float(np.finfo(np.float64).max)
AREA = Convention(coverage="area")


def dense(triangle, y, x0, x1, alpha):
    """{(triangle, x, y): alpha} of every pixel of nonzero alpha."""
    lengths = x1 - x0
    keys = zip(np.repeat(triangle, lengths).tolist(), expand(x0, lengths).tolist(), np.repeat(y, lengths).tolist())
    return {key: a for key, a in zip(keys, alpha.tolist()) if a != 0.0}


def same_as_before(positions, width=SIZE, height=SIZE, exact=False):
    """The new path against the old kernel: the same triangles, rows and inner runs (the
    span kernel is the same), every alpha within both their proven bounds of each other
    (each is within ``area_error_bound`` of the exact area); with ``exact``, also within
    the bound of :func:`exact_pixel_areas` itself."""
    positions = np.ascontiguousarray(positions, dtype=np.float64)
    triangle, y, x0, x1, alpha = old_area_spans(positions, width, height)
    t, yy, a0, a1, runs = _area_spans(positions, width, height)
    inner = runs.inner_x1 - runs.inner_x0
    assert np.all((a0 <= runs.inner_x0) & (inner >= 0) & (runs.inner_x1 <= a1))
    derived = Coverage(t, yy, a0, a1, runs=runs).alpha
    assert derived is not None
    assert np.all(runs.edge_alpha <= 1.0) and np.all(runs.edge_alpha >= 0.0)
    bound = area_error_bound(positions, width, height)
    old, new = dense(triangle, y, x0, x1, alpha), dense(t, yy, a0, a1, derived)
    for key in old.keys() | new.keys():
        assert abs(old.get(key, 0.0) - new.get(key, 0.0)) <= 2.0 * bound[key[0]], key
    # the inner runs are pixels the old kernel wrote as exactly 1 too
    for s in range(t.size):
        for i in range(int(runs.inner_x0[s]), int(runs.inner_x1[s])):
            assert old[int(t[s]), i, int(yy[s])] == 1.0
    if exact:
        within_bound(positions, width, height)
    same_as_two_pass(positions, width, height)
    return derived


def same_as_two_pass(positions, width=SIZE, height=SIZE):
    """The one-pass kernel against the two passes it fused (span kernel, then edge
    kernel): the same spans, inner runs and alphas, bit for bit."""
    polys, counts, source = _polygons(np.ascontiguousarray(positions, dtype=np.float64), width, height)
    one = _area_runs(polys, counts, source, width, height)
    two = two_pass_area_runs(polys, counts, source, width, height)
    for a, b in zip(one, two, strict=True):
        assert a.dtype == b.dtype and a.shape == b.shape
        assert np.array_equal(a.view(np.int64), b.view(np.int64))  # the same bits (and -0.0 is not 0.0)


@pytest.mark.parametrize("seed", range(20))
def test_random_scenes_agree_with_the_old_kernel(seed):
    rng = np.random.default_rng(seed)
    size = int(rng.integers(4, 80))
    n = int(rng.integers(1, 60))
    scale = rng.choice([0.5, 3.0, 20.0, 100.0])
    centres = rng.uniform(-2, size + 2, (n, 1, 2))
    same_as_before(centres + rng.normal(0.0, scale, (n, 3, 2)), size, size)


def test_large_triangles_agree_with_the_old_kernel():
    rng = np.random.default_rng(7)
    same_as_before(rng.uniform(-50, 350, (30, 3, 2)), 300, 200)


@pytest.mark.parametrize("seed", range(6))
def test_the_one_pass_kernel_is_the_two_passes_bit_for_bit(seed):
    """Large triangles (the band path), tiny and far ones, and near-horizontal slivers whose
    rows hold hundreds of edge pixels (the edge areas' array grows while it is written)."""
    rng = np.random.default_rng(100 + seed)
    big = rng.uniform(-40, 440, (20, 3, 2))
    tiny = rng.uniform(0, 400, (40, 1, 2)) + rng.normal(0, 0.7, (40, 3, 2))
    flat = rng.uniform(-20, 420, (10, 3, 2))
    flat[:, :, 1] = rng.uniform(0, 400, (10, 1)) + rng.uniform(0, 3, (10, 3))
    far = np.array([[[-1e9, 5.5], [1e9, 9.25], [200.0, 300.0]]])
    same_as_two_pass(np.concatenate([big, tiny, flat, far]), 400, 400)
    same_as_two_pass(flat[:1], 400, 400)


@pytest.mark.parametrize("positions", [
    [[[0.0, 0.0], [40.0, 20.0], [5.0, 40.0]]],  # every vertex on a row line
    [[[0.0, 3.0], [40.0, 3.0], [20.0, 30.0]], [[0.0, 3.0], [20.0, 30.0], [-10.0, 30.0]]],  # flat top and bottom
    [[[3.5, 0.25], [30.0, 10.0], [9.0, 35.75]]],  # the middle vertex on a row line
    [[[0.0, 0.5], [390.0, 0.0], [200.0, 3.0]]],  # shallow edges: hundreds of edge pixels in a band row
    [[[-30.0, -50.0], [430.0, 120.0], [60.0, 470.0]]],  # beyond the viewport on every side
    [[[10.0, 1.0], [10.0 + 2.0**-30, 390.0], [10.0 - 2.0**-30, 200.0]]],  # a near-vertical sliver
])
def test_band_segments_are_the_two_passes_and_within_the_bound(positions):
    """The band path's special rows: vertices and horizontal edges on a row's lines (the
    crossings there are end points), segments cut by the viewport, rows whose edge pixels
    outgrow the edge areas' array inside a segment (it grows and the segment resumes), and
    edges so steep their rows hold no inner run."""
    same_as_two_pass(positions, 400, 400)
    same_as_before(positions, 400, 400)


@given(st.integers(0, 40), st.integers(0, 40), st.lists(st.tuples(st.integers(-8, 48), st.integers(-8, 48)),
                                                     min_size=3, max_size=3), st.integers(0, 3))
@settings(max_examples=200)
def test_band_rows_agree_with_the_exact_area(dx, dy, vertices, bits):
    """Triangles on a lattice of step 2**-bits (vertices on row lines or between them), each
    pixel of the band path within the bound of the exact area."""
    positions = (np.array([vertices], dtype=float) + [dx, dy]) * 2.0**-bits
    same_as_before(positions, 48, 48, exact=True)


@pytest.mark.parametrize("bits", [0, 1, 2, 4])
def test_lattice_meshes_with_shared_edges_agree_with_the_old_kernel(bits):
    """Vertices on pixel corners, edges through corners, shared edges and diagonals."""
    step = 2.0**-bits
    grid = np.arange(0, 9) * 1.5 + step
    xs, ys = np.meshgrid(grid, grid)
    a = np.stack([xs[:-1, :-1], ys[:-1, :-1]], -1).reshape(-1, 2)
    b = np.stack([xs[:-1, 1:], ys[:-1, 1:]], -1).reshape(-1, 2)
    c = np.stack([xs[1:, :-1], ys[1:, :-1]], -1).reshape(-1, 2)
    d = np.stack([xs[1:, 1:], ys[1:, 1:]], -1).reshape(-1, 2)
    same_as_before(np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]), 14, 14, exact=True)


@pytest.mark.parametrize("positions", [
    [[[0, 0], [0, 0], [0, 0]]],  # a point
    [[[1, 1], [5, 5], [3, 3]]],  # a segment
    [[[np.nan, 0], [4, 0], [0, 4]]],  # not finite
    [[[-BIG, -BIG], [BIG, -BIG], [-BIG, BIG]]],  # the whole viewport and beyond: one inner run per row
    [[[-(2.0**21) - 1, 0.5], [2.0**21, 7.5], [3.0, 3.0]]],  # just beyond the guard limit
    [[[-1e300, 3.25], [1e300, 3.75], [5.5, 3.5]]],  # far and thin
    [[[0, 0], [8, 0], [0, 8]], [[8, 0], [8, 8], [0, 8]]],  # a square split on its diagonal
    [[[0.5, -1e6], [0.5 + 2.0**-40, 1e6], [0.5, 3.0]]],  # a near-vertical sliver crossing every row
    [[[1.0, 1.0], [7.0, 7.0], [4.0, 4.0 + 5e-324]]],  # one subnormal step off a diagonal
])
def test_degenerate_and_far_triangles_agree_with_the_old_kernel(positions):
    same_as_before(positions, exact=True)


@given(st.one_of(lattice_scenes(max_bits=5, size=SIZE, max_triangles=4).map(lambda s: s.positions),
                 float_scenes(size=SIZE, max_triangles=4).map(lambda s: s.positions),
                 thin_scenes(size=SIZE).map(lambda s: s.positions),
                 sliver_triangles(), corner_triangles(), far_triangles()))
@settings(max_examples=300)
@example(np.array([[[0, 0], [8, 0], [0, 8]]], dtype=float))
@example(np.array([[[2, 0.5], [2, 6], [5, 0.5]]], dtype=float))
def test_hypothesis_scenes_agree_with_the_old_kernel(positions):
    same_as_before(positions, exact=True)


# -- the contract: runs are one more form of the same coverage -----------------------------


def runs_and_alpha(scene=None):
    scene = scene or Scene(12, 10, np.array([[[0.5, 0.25], [11.5, 1.0], [2.0, 9.75]], [[3, 3], [9, 4], [6, 9]]]))
    runs = area_coverage(scene, AREA)
    assert runs.runs is not None
    plain = Coverage(runs.primitive, runs.y, runs.x0, runs.x1, alpha=np.array(runs.alpha))
    return scene, runs, plain


def test_runs_derive_the_alphas_once_and_keep_them():
    _, runs, plain = runs_and_alpha()
    fresh = Coverage(runs.primitive, runs.y, runs.x0, runs.x1, runs=runs.runs)
    first = fresh.alpha
    assert first is fresh.alpha and first is not None and not first.flags.writeable
    assert np.array_equal(first, plain.alpha)
    assert fresh.nbytes < plain.nbytes or len(fresh) == 0


def test_runs_and_alphas_are_the_same_coverage():
    scene, runs, plain = runs_and_alpha()
    assert runs == plain and plain == runs
    assert runs.canonical() is runs  # already canonical: the runs stay
    assert runs.canonical() == plain.canonical()
    usable, flaws = runs.tidy(scene)
    assert usable is runs and not any(v.any() for k, v in flaws.items() if k != "repeated_pixels")
    cut = runs.take(np.array([1, 0]), runs.x0[[1, 0]] + 1, runs.x1[[1, 0]])
    assert cut == plain.take(np.array([1, 0]), plain.x0[[1, 0]] + 1, plain.x1[[1, 0]])
    assert Coverage.concat([runs, plain]) == Coverage.concat([plain, plain])
    changed = np.array(plain.alpha)
    changed[-1] = 0.5
    assert runs != Coverage(plain.primitive, plain.y, plain.x0, plain.x1, alpha=changed)


def test_runs_cross_the_wire_and_pickle_as_alphas():
    _, runs, plain = runs_and_alpha()
    back = decode_outcome(encode_outcome(Outcome(runs, seconds=0.0))).coverage
    assert back is not None and back.runs is None and back == plain
    again = pickle.loads(pickle.dumps(runs))
    assert again == plain and np.array_equal(again.alpha, plain.alpha)


def test_exact_coverage_answers_with_runs():
    scene = Scene(64, 64, [[[1.5, 2.25], [60.0, 5.0], [10.0, 61.5]]])
    got = exact_coverage(scene, AREA)
    assert got.runs is not None
    assert int((got.runs.inner_x1 - got.runs.inner_x0).sum()) > got.runs.edge_alpha.size  # mostly inner
    assert got == runs_and_alpha(scene)[2]


def test_runs_are_checked_against_their_spans():
    spans = ([0, 0], [0, 1], [0, 2], [3, 5])
    good = AlphaRuns(np.array([1, 2]), np.array([2, 5]), np.array([0.5, 0.25]))
    alpha = Coverage(*spans, runs=good).alpha
    assert alpha is not None and alpha.tolist() == [0.5, 1.0, 0.25, 1.0, 1.0, 1.0]
    for bad in (AlphaRuns(np.array([1]), np.array([2]), np.array([0.5, 0.25])),  # not one per span
                AlphaRuns(np.array([1, 2]), np.array([4, 5]), np.array([0.5])),  # inner run beyond its span
                AlphaRuns(np.array([2, 2]), np.array([1, 5]), np.array([0.5, 0.25, 0.0])),  # reversed
                AlphaRuns(np.array([1, 2]), np.array([2, 5]), np.array([0.5]))):  # too few edge alphas
        with pytest.raises(ValueError):
            Coverage(*spans, runs=bad)
    with pytest.raises(ValueError, match="not both"):
        Coverage(*spans, alpha=np.zeros(6), runs=good)
    with pytest.raises(ValueError, match="AlphaRuns"):
        Coverage(*spans, runs=(1, 2, 3))  # type: ignore[arg-type]


def test_dataclasses_replace_keeps_working_on_both_forms() -> None:
    """Plugins and tests change one field with dataclasses.replace (attributes scaled, spans
    cut): per-pixel alphas are carried over, runs are kept and their alphas derived anew."""
    from dataclasses import replace

    plain = Coverage([0], [1], [2], [5], alpha=[0.25, 1.0, 0.5])
    kept = replace(plain, attributes=np.zeros((3, 2))).alpha
    assert kept is not None and kept.tolist() == [0.25, 1.0, 0.5]
    runs = Coverage([0], [1], [2], [5], runs=AlphaRuns(np.array([3]), np.array([4]), np.array([0.25, 0.5])))
    assert runs.alpha is not None and runs.alpha.tolist() == [0.25, 1.0, 0.5]  # derived (and kept) first
    again = replace(runs, primitive=np.array([1]))
    assert again.runs is not None and again.alpha is not None and again.alpha.tolist() == [0.25, 1.0, 0.5]
    assert again.primitive.tolist() == [1]
