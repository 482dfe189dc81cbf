"""Row-sampled area coverage of paths (issue 34): the plain model's compiled oracle against
its rational reference, cairo's hybrid on paths against the triangle oracle and against
cairo itself, and accuracy judging a row-sampled path filler."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from harness.checks.area_paths import path_accuracy
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.oracle.aa_models import cairo_alpha_levels, row_sampled_coverage
from harness.oracle.coverage import exact_coverage
from harness.oracle.row_sampled_paths import (
    HYBRID_LIMIT,
    exact_row_sampled_path_alpha,
    row_sampled_path_bound,
    row_sampled_path_coverage,
)
from tests.accuracy_runs import dense_alphas

W = H = 6
HYBRID = Convention(coverage="area", rows=15, full_rows=True, input="fixed8")


def _dense(coverage: Coverage, width: int = W, height: int = H) -> np.ndarray:
    return dense_alphas(coverage, width, height)  # type: ignore[no-any-return]


# vertices on 1/32 px (pixel edges often) and 1/30 px (the 15 rows' centres and boundaries)
_coordinate = st.one_of(st.integers(-8, 7 * 32).map(lambda v: v / 32), st.integers(0, 6 * 30).map(lambda v: v / 30))
_contour = st.lists(st.tuples(_coordinate, _coordinate), min_size=3, max_size=7)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_contour, min_size=1, max_size=2), st.sampled_from(["nonzero", "evenodd"]), st.sampled_from([1, 4, 15]))
@example([[(0, 0), (6, 6), (6, 0), (0, 6)]], "nonzero", 4)  # a bow tie through the centre
@example([[(0, 0), (5, 0), (5, 5), (0, 5)], [(1, 1), (4, 1), (4, 4), (1, 4)]], "nonzero", 15)  # doubly wound
def test_the_plain_model_on_paths_is_its_rational_reference_within_its_bound(contours, rule, rows):
    """Self-intersecting, overlapping, collinear and zero-length edges: each pixel's compiled
    alpha within the proven bound of the exact mean of the cross-sections."""
    rings = [np.array(c, dtype=np.float64) for c in contours]
    scene = PathScene.from_paths(W, H, [rings], fill_rule=rule)
    image = _dense(row_sampled_path_coverage(scene, Convention(coverage="area", rows=rows)))
    edges = np.concatenate([np.concatenate([c, np.roll(c, -1, axis=0)], axis=1) for c in rings])
    bound = row_sampled_path_bound(edges, W, H, rows)
    assert bound < 1e-12
    for y in range(H):
        for x in range(W):
            exact = exact_row_sampled_path_alpha(rings, rule, x, y, rows)
            assert abs(Fraction(float(image[y, x])) - exact) <= Fraction(bound), (x, y, image[y, x], exact)


def test_a_doubly_wound_square_is_filled_under_nonzero_and_emptied_under_evenodd():
    outer = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], dtype=np.float64)
    inner = np.array([[1, 1], [3, 1], [3, 3], [1, 3]], dtype=np.float64)
    for convention in (Convention(coverage="area", rows=4), HYBRID):
        nonzero = _dense(row_sampled_path_coverage(PathScene.from_paths(W, H, [[outer, inner]], "nonzero"), convention))
        evenodd = _dense(row_sampled_path_coverage(PathScene.from_paths(W, H, [[outer, inner]], "evenodd"), convention))
        assert nonzero[2, 2] == 1.0 and evenodd[2, 2] == 0.0 and evenodd[0, 0] == 1.0


@pytest.mark.parametrize("convention", [Convention(coverage="area", rows=5), HYBRID], ids=["rows5", "cairo"])
def test_a_one_triangle_path_gives_the_triangle_oracles_alphas(convention):
    rng = np.random.default_rng(3)
    for t in range(60):
        triangle = rng.uniform(-1, 13, (3, 2))
        if t % 3 == 0:
            triangle = np.round(triangle * 4) / 4  # shared cells, ties in the edge list
        as_path = _dense(row_sampled_path_coverage(PathScene.from_paths(12, 12, [[triangle]]), convention), 12, 12)
        as_triangle = _dense(row_sampled_coverage(Scene(12, 12, triangle[None]), convention), 12, 12)
        assert np.array_equal(as_path, as_triangle), triangle.tolist()


def test_the_hybrid_reference_reads_the_cells_exactly():
    square = [np.array([[0.5, 0.5], [2.5, 0.5], [2.5, 2.5], [0.5, 2.5]])]
    assert exact_row_sampled_path_alpha(square, "nonzero", 1, 1, 15, full_rows=True) == 1
    # the top edge at y = 1/2 starts at sub-row floor(15/2 + 1/2) = 8: 7 of 15 rows, half the width
    assert exact_row_sampled_path_alpha(square, "nonzero", 0, 0, 15, full_rows=True) == Fraction(7, 30)
    far = [np.array([[0.0, 0.0], [HYBRID_LIMIT, 0.0], [0.0, 2.0]])]  # beyond cairo's 24.8 in 32 bits
    # the surface cairo clips to is part of the model: clipped at x = 2, the right edge's
    # stand-in at the surface's side starts and ends mid-row
    wide = [np.array([[0.25, 0.0], [6.0, 1.0], [0.5, 3.0]])]
    assert exact_row_sampled_path_alpha(wide, "nonzero", 1, 0, 15, True, surface=(2, 3)) != \
        exact_row_sampled_path_alpha(wide, "nonzero", 1, 0, 15, True)
    assert exact_row_sampled_path_alpha(far, "nonzero", 0, 0, 15, full_rows=True) == 0  # beyond the model's range


def _star(rng: np.random.Generator, centre: tuple[float, float], points: int) -> np.ndarray:
    angles = np.arange(points) * (2 * np.pi * (points // 2 - (points % 2 == 0)) / points) + rng.uniform(0, 1)
    radius = rng.uniform(3, 9)
    return np.stack([centre[0] + radius * np.cos(angles), centre[1] + radius * np.sin(angles)], axis=1)


def test_cairo_fills_paths_exactly_as_its_hybrid_model():
    """The model against cairo itself (pycairo, A8, ANTIALIAS_DEFAULT) on stars, bow ties and
    ring pairs inside the surface under both rules: every level equal (cairo's
    GRID_AREA_TO_ALPHA of the model's cell areas)."""
    pytest.importorskip("cairo")
    import cairo

    from rasterizers.real.adapters import _cairo_fill

    rng = np.random.default_rng(11)
    off = 0
    for t in range(40):
        rule = "evenodd" if t % 2 else "nonzero"
        contours = [_star(rng, (12.0 + rng.uniform(-1, 1), 12.0 + rng.uniform(-1, 1)), int(rng.integers(5, 9)))]
        if t % 4 == 3:  # a second contour overlapping the first
            contours.append(_star(rng, (13.0, 11.0), 7))
        if t % 5 == 0:
            contours = [np.round(c * 8) / 8 for c in contours]  # vertices sharing sub-rows and cells
        got = _cairo_fill(cairo, contours, 24, 24, cairo.ANTIALIAS_DEFAULT, rule).astype(np.int64)
        model = _dense(exact_coverage(PathScene.from_paths(24, 24, [contours], rule), HYBRID), 24, 24)
        off += int(np.sum(cairo_alpha_levels(np.clip(model, 0.0, 1.0)) != got))
    assert off == 0


@pytest.mark.parametrize("magnitude", [1e3, 1e6, 4e6])
def test_cairo_fills_huge_triangles_as_its_model_overflow_included(magnitude):
    """cairo clips a huge polygon to the surface, then its int64 products overflow (beyond
    ~2**15 px); the model does the same arithmetic and matches every byte."""
    pytest.importorskip("cairo")
    import warnings

    import cairo

    from rasterizers.real.adapters import _cairo_fill

    rng = np.random.default_rng(5)
    off = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numpy's overflow warnings: the wrap is cairo's
        for _ in range(12):
            triangle = rng.uniform(-magnitude, magnitude, (3, 2)) + 8
            got = _cairo_fill(cairo, [triangle], 16, 16, cairo.ANTIALIAS_DEFAULT).astype(np.int64)
            model = _dense(exact_coverage(PathScene.from_paths(16, 16, [[triangle]]), HYBRID), 16, 16)
            off += int(np.sum(cairo_alpha_levels(np.clip(model, 0.0, 1.0)) != got))
    assert off == 0


def test_cairo_fills_rectilinear_paths_as_boxes_within_a_level_of_their_area():
    pytest.importorskip("cairo")
    import cairo

    from rasterizers.real.adapters import _cairo_fill

    rng = np.random.default_rng(4)
    worst = 0.0
    for t in range(30):
        xs, ys = np.sort(rng.uniform(-3, 19, 4)), np.sort(rng.uniform(-3, 19, 4))
        stairs = np.array([[xs[0], ys[0]], [xs[3], ys[0]], [xs[3], ys[2]], [xs[2], ys[2]], [xs[2], ys[3]], [xs[0], ys[3]]])
        rule = "evenodd" if t % 2 else "nonzero"
        got = _cairo_fill(cairo, [stairs], 16, 16, cairo.ANTIALIAS_DEFAULT, rule)
        model = _dense(exact_coverage(PathScene.from_paths(16, 16, [[stairs]], rule), HYBRID), 16, 16)
        worst = max(worst, float(np.abs(np.clip(model, 0, 1) * 255 - got).max()))
    assert 0.5 < worst <= 1.0  # box compositing: not the tor's rounding, within one level


def test_accuracy_judges_cairos_model_on_paths_and_catches_the_plain_rows():
    """A path filler drawing the hybrid passes against it at a tolerance of one level; one
    sampling every row (no full rows) fails (shallow edges differ by several levels)."""
    star = np.array([[2.0, 10.3], [21.7, 8.1], [5.2, 21.9], [12.6, 1.2], [19.4, 20.8]])
    scene = PathScene.from_paths(24, 24, [[star]], "nonzero")
    case = Case("paths/star/test", scene)
    declared = Convention(coverage="area", rows=15, full_rows=True, input="fixed8", levels=256, tolerance=1 / 255)
    hybrid = exact_coverage(scene, HYBRID)
    assert hybrid.alpha is not None
    quantised = Coverage(hybrid.triangle, hybrid.y, hybrid.x0, hybrid.x1,
                         alpha=cairo_alpha_levels(np.clip(hybrid.alpha, 0, 1)) / 255.0)
    assert path_accuracy(case, quantised, hybrid, declared).status == "pass"
    sampled = exact_coverage(scene, Convention(coverage="area", rows=15, input="fixed8"))
    assert sampled.alpha is not None
    worse = Coverage(sampled.triangle, sampled.y, sampled.x0, sampled.x1,
                     alpha=cairo_alpha_levels(np.clip(sampled.alpha, 0, 1)) / 255.0)
    assert path_accuracy(case, worse, hybrid, declared).status == "fail"
