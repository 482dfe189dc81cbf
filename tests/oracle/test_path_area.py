"""The area oracle of paths: the rational reference on hand cases, the float method within
its proven bound of it, and a one-triangle path giving the triangle oracle's alphas."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.scenes import PathScene
from harness.oracle.area import exact_pixel_areas
from harness.oracle.path_area import exact_path_area, exact_path_pixel_areas, path_area_coverage, path_pixel_areas

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


def _star(cx: float, cy: float, r: float, points: int = 5, step: int = 2) -> list[list[float]]:
    return [[cx + r * math.sin(2 * math.pi * k * step / points), cy - r * math.cos(2 * math.pi * k * step / points)]
            for k in range(points)]


def _float_vs_exact(scene: PathScene) -> None:
    exact = exact_path_pixel_areas(scene)
    p, x, y, area, bound = path_pixel_areas(scene)
    got = {(int(a), int(b), int(c)): (float(v), float(e)) for a, b, c, v, e in zip(p, x, y, area, bound)}
    for key in set(exact) | set(got):
        value, err = got.get(key, (0.0, 0.0))
        want = exact.get(key, Fraction(0))
        if key not in got:  # a pixel left out holds at most the bound of its band
            assert want <= Fraction(max([e for k, (_, e) in got.items() if k[0] == key[0] and k[2] == key[2]],
                                        default=2.0**-30)), key
            continue
        assert abs(Fraction(value) - want) <= Fraction(err), (key, value, want, err)


def test_overlapping_squares_nonzero_once_evenodd_not_at_all() -> None:
    squares: list[list[list[float]]] = [[[0, 0], [1.5, 0], [1.5, 1], [0, 1]], [[0.5, 0], [2, 0], [2, 1], [0.5, 1]]]
    assert exact_path_area(squares, "nonzero", 0, 0) == 1
    assert exact_path_area(squares, "evenodd", 0, 0) == Fraction(1, 2)
    assert exact_path_area(squares, "evenodd", 1, 0) == Fraction(1, 2)
    # the same squares, one reversed: winding 0 in the overlap under nonzero too
    reversed_ = [squares[0], squares[1][::-1]]
    assert exact_path_area(reversed_, "nonzero", 0, 0) == Fraction(1, 2)


def test_pentagram_centre_nonzero_filled_evenodd_hollow() -> None:
    star = [_star(5, 5, 5)]
    # the centre pentagon contains the pixel (4.5.., 5.5..)? the pentagon's inradius is
    # r cos(72) cos(36)/cos(36)... about 1.55: the pixel [4, 5] x [4, 5] lies inside it
    assert exact_path_area(star, "nonzero", 4, 4) == 1
    assert exact_path_area(star, "evenodd", 4, 4) == 0
    _float_vs_exact(PathScene.from_paths(10, 10, [star], "nonzero"))
    _float_vs_exact(PathScene.from_paths(10, 10, [star], "evenodd"))


def test_ring_has_a_hole_under_both_rules() -> None:
    outer = [[0, 0], [4, 0], [4, 4], [0, 4]]
    inner = [[1, 1], [1, 3], [3, 3], [3, 1]]  # reversed: winding 0 inside under nonzero
    for rule in ("nonzero", "evenodd"):
        assert exact_path_area([outer, inner], rule, 1, 1) == 0
        assert exact_path_area([outer, inner], rule, 0, 1) == 1
    same_way = [outer, inner[::-1]]  # winding 2 inside: nonzero fills, even-odd does not
    assert exact_path_area(same_way, "nonzero", 1, 1) == 1
    assert exact_path_area(same_way, "evenodd", 1, 1) == 0


def test_collinear_repeated_and_zero_length_edges_change_nothing() -> None:
    plain = [[[0.25, 0.25], [1.75, 0.25], [1.75, 1.5], [0.25, 1.5]]]
    busy = [[[0.25, 0.25], [0.25, 0.25], [1.0, 0.25], [1.75, 0.25], [1.75, 0.75], [1.75, 1.5], [1.75, 1.5],
             [0.25, 1.5]]]
    for i in range(2):
        for j in range(2):
            for rule in ("nonzero", "evenodd"):
                assert exact_path_area(plain, rule, i, j) == exact_path_area(busy, rule, i, j)
    assert exact_path_area(plain, "nonzero", 0, 0) == Fraction(9, 16)
    # a contour doubling back on itself encloses nothing
    assert exact_path_area([[[0, 0], [2, 2], [0, 0]]], "nonzero", 0, 0) == 0
    _float_vs_exact(PathScene.from_paths(3, 3, [busy]))


def test_reversed_winding_changes_nothing() -> None:
    star = [_star(4.3, 4.1, 3.7, 7, 3)]
    for rule in ("nonzero", "evenodd"):
        a = exact_path_pixel_areas(PathScene.from_paths(9, 9, [star], rule))
        b = exact_path_pixel_areas(PathScene.from_paths(9, 9, [[c[::-1] for c in star]], rule))
        assert a == b


triangles = st.lists(st.tuples(st.integers(-8, 72), st.integers(-8, 72)), min_size=3, max_size=3)


@settings(max_examples=40, deadline=None)
@given(triangles)
@example([(0, 0), (64, 0), (0, 64)])
@example([(0, 0), (8, 8), (16, 16)])
def test_one_triangle_path_gives_the_triangle_oracles_alphas(points: list[tuple[int, int]]) -> None:
    tri = np.array(points, dtype=np.float64) / 16
    scene = PathScene.from_paths(4, 4, [[tri]])
    want = {(i, x, y): a for (i, x, y), a in exact_pixel_areas(tri[None], 4, 4).items()}
    for rule in ("nonzero", "evenodd"):
        assert exact_path_pixel_areas(PathScene.from_paths(4, 4, [[tri]], rule)) == want
    _float_vs_exact(scene)


contours = st.lists(st.lists(st.tuples(st.integers(-4, 52), st.integers(-4, 52)), min_size=1, max_size=7),
                    min_size=1, max_size=3)


@settings(max_examples=60, deadline=None)
@given(contours, st.sampled_from(["nonzero", "evenodd"]))
@example([[(0, 0), (32, 0), (0, 32)], [(0, 0), (32, 0), (0, 32)]], "nonzero")
@example([[(0, 0), (16, 0), (16, 16), (0, 16)], [(8, 8), (24, 8), (24, 24), (8, 24)]], "evenodd")
def test_float_method_within_its_bound_of_the_exact_one(points: list[list[tuple[int, int]]], rule: str) -> None:
    paths = [[np.array(c, dtype=np.float64) / 16 for c in points]]
    _float_vs_exact(PathScene.from_paths(3, 3, paths, rule))


def test_many_paths_and_far_coordinates() -> None:
    paths: list[list[list[list[float]]]] = [[_star(3 + k, 3.5, 2.5)] for k in range(3)]
    paths.append([[[-1e30, -1e30], [1e30, 0.5], [-1e30, 3]]])
    for rule in ("nonzero", "evenodd"):
        _float_vs_exact(PathScene.from_paths(7, 7, paths, rule))


def test_non_finite_paths_cover_nothing_and_snapping_applies() -> None:
    bad: list[list[float]] = [[0, 0], [math.nan, 0], [0, 2]]
    scene = PathScene.from_paths(2, 2, [[bad], [SQUARE]])
    p, x, y, area, _ = path_pixel_areas(scene)
    assert p.tolist() == [1] and area.tolist() == [1.0]
    shifted = PathScene.from_paths(2, 2, [[[[0.01, 0], [1.01, 0], [1.01, 1], [0.01, 1]]]])
    snapped = path_area_coverage(shifted, Convention(coverage="area", subpixel_bits=2))
    assert snapped.alpha is not None and snapped.alpha.tolist() == [1.0]


def test_glyph_like_outline_float_agrees() -> None:
    # an "o": two flattened circles, the inner one reversed, plus an overlapping bar
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    outer = np.stack([6 + 5 * np.cos(t), 6 + 5.5 * np.sin(t)], axis=1)
    inner = np.stack([6 + 3 * np.cos(t), 6 + 3.2 * np.sin(t)], axis=1)[::-1]
    bar = np.array([[1.3, 5.1], [10.7, 5.1], [10.7, 6.9], [1.3, 6.9]])
    for rule in ("nonzero", "evenodd"):
        _float_vs_exact(PathScene.from_paths(12, 12, [[outer, inner, bar]], rule))


def test_crossings_and_repeated_contours_stay_in_float(monkeypatch: pytest.MonkeyPatch) -> None:
    import harness.oracle.path_area as module

    def refuse(*args: object) -> None:
        raise AssertionError("the exact reference was used")

    star = PathScene.from_paths(10, 10, [[_star(5, 5, 4.5)], [_star(4.3, 4.1, 3.7, 7, 3)]], "nonzero")
    repeated = PathScene.from_paths(8, 8, [[np.array([[1, 1], [1, 7], [7, 1]] * 500, dtype=np.float64),
                                            [[3, 7], [7, 7], [7, 3], [3, 3]]]], "evenodd")
    wanted = [exact_path_pixel_areas(star), exact_path_pixel_areas(repeated)]
    monkeypatch.setattr(module, "_band_areas", refuse)
    for scene, want in zip((star, repeated), wanted):
        p, x, y, area, bound = path_pixel_areas(scene)
        assert bound.max() < 2**-30
        for k in range(p.size):
            assert abs(Fraction(float(area[k])) - want.get((int(p[k]), int(x[k]), int(y[k])), Fraction(0))) <= bound[k]


def test_the_glyph_and_hairline_cases_within_the_bound() -> None:
    from cases.paths import shape_cases

    cases = [c for c in shape_cases(0, True) if "/glyph/" in c.id or "/hairline/" in c.id]
    assert len(cases) == 16  # the "o" with its bar, the hairline ring, the "D" glyphs (sizes, a line of text), both rules
    for case in cases:
        assert isinstance(case.scene, PathScene)
        _float_vs_exact(case.scene)


# -- bands of many edges: swept in tiles of columns (path_area._bands_kernel) -----------------

busy_contours = st.lists(st.lists(st.tuples(st.integers(-8, 104), st.integers(-8, 104)), min_size=20, max_size=44),
                         min_size=1, max_size=2)


def _with_extras(contour: list[tuple[int, int]], extras: int) -> NDArray[np.float64]:
    """The contour with a repeated vertex (a zero-length edge) and a midpoint (two collinear
    edges) put in every ``extras``-th edge."""
    out: list[tuple[float, float]] = []
    for k, (x, y) in enumerate(contour):
        out.append((x, y))
        if extras and k % extras == 0:
            nx, ny = contour[(k + 1) % len(contour)]
            out += [(x, y), ((x + nx) / 2, (y + ny) / 2)]
    return np.array(out, dtype=np.float64) / 16


@settings(max_examples=25, deadline=None)
@given(busy_contours, st.sampled_from(["nonzero", "evenodd"]), st.integers(0, 5))
@example([[(8 * k % 97, 5 * k * k % 101) for k in range(44)]], "evenodd", 3)
@example([[(k % 2 * 96, 4 * k) for k in range(24)] + [(0, 100)]], "nonzero", 0)
def test_tiled_bands_within_the_bound_of_the_exact_one(points: list[list[tuple[int, int]]], rule: str,
                                                        extras: int) -> None:
    """Random self-intersecting contours of 20 to 44 vertices (and collinear and zero-length
    edges) in 6 x 6 pixels: most bands hold more than TILE_EDGES edges and are swept in
    tiles, their left edges entering as a winding number."""
    paths = [[_with_extras(c, extras) for c in points]]
    _float_vs_exact(PathScene.from_paths(6, 6, paths, rule))


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_tiles_with_edges_on_their_sides_and_huge_edges(rule: str) -> None:
    # a comb: 30 vertical edges on integer columns (a tile's side) and half-columns, a
    # zigzag crossing it, and a huge triangle whose edges cross every tile of the band
    comb = [[float(k) / 4, 0.0 if k % 2 else 5.5] for k in range(30)] + [[7.5, 6.0], [0.0, 6.0]]
    zigzag = [[0.1 + 0.23 * k, 1.0 + (k % 3) * 1.7] for k in range(28)] + [[6.5, 5.9]]
    huge = [[-4e4, -3e4], [5e4, 2.5], [-3e4, 3.1e4]]
    _float_vs_exact(PathScene.from_paths(8, 7, [[np.array(comb), np.array(zigzag), np.array(huge)]], rule))


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_the_bench_outline_small_within_the_bound(rule: str) -> None:
    from harness.cli.bench_workloads import wiggly_outline

    scene = wiggly_outline(600, 12).with_fill_rule(rule)  # about 60 edges a band, crossing itself
    _float_vs_exact(scene)
