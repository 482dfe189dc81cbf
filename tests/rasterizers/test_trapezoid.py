"""The trapezoid (active edge list) fill against the exact winding oracle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from harness.contract.conventions import TIE_RULES, Convention
from harness.contract.protocol import Rasterizer, scene_kinds_of, takes
from harness.contract.scenes import PathScene, Scene
from harness.geometry.exact import orient2d_fraction
from harness.oracle.coverage import exact_coverage
from rasterizers.trapezoid import TrapezoidFill, crossing_column

SIZE = 8
FILL_RULES = ("nonzero", "evenodd")
QUICK = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _agrees(scene: PathScene | Scene, tie: str = "top-left") -> None:
    """The reference equals the oracle of its convention, under each fill rule."""
    fill = TrapezoidFill(tie)  # type: ignore[arg-type]
    scenes = [scene.with_fill_rule(rule) for rule in FILL_RULES] if isinstance(scene, PathScene) else [scene]
    for s in scenes:
        got, want = fill.rasterize(s), exact_coverage(s, fill.convention)
        assert got == want, f"{getattr(s, 'fill_rule', 'triangles')}, {tie}: {got.n_pixels} pixels, oracle {want.n_pixels}"


# -- strategies: vertices on a 1/4 or 1/8 lattice, so samples land on edges and vertices ---------


@st.composite
def lattice_contour(draw, denominator):
    """A polygon of 1-8 lattice vertices (1 and 2 enclose nothing), with repeated vertices
    (zero-length edges), horizontal edges, collinear midpoints and vertices exactly on a
    sample row mixed in."""
    coordinate = st.integers(-2 * denominator, (SIZE + 2) * denominator)
    pts = [[draw(coordinate), draw(coordinate)] for _ in range(draw(st.integers(1, 8)))]
    extras = draw(st.lists(st.tuples(st.sampled_from(["repeat", "horizontal", "midpoint", "on-row"]), st.integers(0, 99)),
                           max_size=3))
    for kind, at in extras:
        k = at % len(pts)
        a, b = pts[k], pts[(k + 1) % len(pts)]
        if kind == "repeat":
            new = list(a)
        elif kind == "horizontal":
            new = [draw(coordinate), a[1]]
        elif kind == "midpoint":  # collinear: exactly halfway (on the 2x finer lattice below)
            new = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2]
        else:
            new = [a[0], (at % SIZE) * denominator + denominator // 2]  # y = j + 0.5
        pts.insert(k + 1, new)
    return np.array(pts, dtype=np.float64) / denominator


@st.composite
def star(draw, denominator):
    """A self-intersecting star polygon {n/k}, its vertices rounded to the lattice (or not)."""
    n = draw(st.integers(5, 10))
    k = draw(st.integers(2, (n - 1) // 2))
    cx, cy = (draw(st.integers(0, SIZE * denominator)) / denominator for _ in range(2))
    r = draw(st.integers(denominator, 5 * denominator)) / denominator
    phase = draw(st.integers(0, 7)) * math.pi / 4
    pts = np.array([[cx + r * math.cos(phase + 2 * math.pi * k * i / n), cy + r * math.sin(phase + 2 * math.pi * k * i / n)]
                    for i in range(n)])
    return np.round(pts * denominator) / denominator if draw(st.booleans()) else pts


def ring(contour: np.ndarray, reverse: bool) -> list[np.ndarray]:
    """The contour and a copy half its size about a lattice point inside its box (exact
    on the lattice), wound the same way or the opposite."""
    centre = np.round(contour.mean(axis=0) * 4) / 4
    hole = centre + (contour - centre) / 2
    return [contour, hole[::-1].copy() if reverse else hole]


@st.composite
def path_scenes(draw):
    """1-3 paths of 1-3 contours each; some rings with a hole of either orientation."""
    denominator = draw(st.sampled_from([4, 8]))
    contour = st.one_of(lattice_contour(denominator), star(denominator))
    paths = []
    for _ in range(draw(st.integers(1, 3))):
        cs = draw(st.lists(contour, min_size=1, max_size=3))
        if draw(st.booleans()):
            cs = ring(cs[0], draw(st.booleans())) + cs[1:]
        paths.append(cs)
    return PathScene.from_paths(SIZE, SIZE, paths, draw(st.sampled_from(FILL_RULES)))


_SQUARE = [[1, 1], [7, 1], [7, 7], [1, 7]]
_PENTAGRAM = [[4, 0.25], [6.25, 7.5], [0.25, 2.75], [7.75, 2.75], [1.75, 7.5]]


@QUICK
@given(scene=path_scenes(), tie=st.sampled_from(TIE_RULES))
@example(scene=PathScene.from_paths(SIZE, SIZE, [[_PENTAGRAM]]), tie="top-left")
@example(scene=PathScene.from_paths(SIZE, SIZE, [ring(np.array(_SQUARE, dtype=np.float64), False)]), tie="top-left")
@example(scene=PathScene.from_paths(SIZE, SIZE, [ring(np.array(_SQUARE, dtype=np.float64), True)]), tie="bottom-right")
# vertices on rows and columns
@example(scene=PathScene.from_paths(SIZE, SIZE, [[[[4, 0.5], [7.5, 3.5], [4, 6.5], [0.5, 3.5]]]]), tie="top-left")
@example(scene=PathScene.from_paths(SIZE, SIZE, [[[[4, 0.5], [7.5, 3.5], [4, 6.5], [0.5, 3.5]]]]), tie="bottom-left-y-first")
def test_paths_match_the_oracle(scene: PathScene, tie: str) -> None:
    _agrees(scene, tie)


@settings(max_examples=40, deadline=None)
@given(coordinates=st.lists(st.integers(-8, 4 * SIZE + 8), min_size=6, max_size=36).map(lambda c: c[: len(c) // 6 * 6]),
       flat=st.booleans(), tie=st.sampled_from(TIE_RULES))
def test_triangles_are_one_contour_paths(coordinates: list[int], flat: bool, tie: str) -> None:
    """A triangle scene fills each triangle as a path of one contour: the triangle oracle
    (no culling), zero-area triangles (here: the last, flattened) drawing nothing."""
    positions = np.array(coordinates, dtype=np.float64).reshape(-1, 3, 2) / 4
    if flat:
        positions[-1, 2] = (positions[-1, 0] + positions[-1, 1]) / 2
    _agrees(Scene(SIZE, SIZE, positions), tie)


# -- float input, far and near ------------------------------------------------------------------


def test_float_paths_match_the_oracle() -> None:
    rng = np.random.default_rng(15)
    for tie in TIE_RULES:
        paths = [[rng.normal(SIZE / 2, SIZE / 2, size=(int(rng.integers(3, 12)), 2)) for _ in range(int(rng.integers(1, 3)))]
                 for _ in range(6)]
        _agrees(PathScene.from_paths(SIZE, SIZE, paths), tie)
        _agrees(Scene(SIZE, SIZE, rng.normal(SIZE / 2, SIZE, size=(12, 3, 2))), tie)


def test_many_stars_in_one_viewport() -> None:
    """Bands of many active edges, edges crossing between events (the insertion sort)."""
    rng = np.random.default_rng(3)
    stars = []
    for _ in range(40):
        cx, cy, r, phase = *rng.uniform(0, 64, 2), rng.uniform(2, 20), rng.uniform(0, 2 * math.pi)
        stars.append([np.array([[cx + r * math.cos(phase + 2 * math.pi * 3 * i / 10),
                                 cy + r * math.sin(phase + 2 * math.pi * 3 * i / 10)]
                                for i in range(10)])])
    _agrees(PathScene.from_paths(64, 48, stars + [[np.concatenate([s[0] for s in stars])]]))


@pytest.mark.parametrize("tie", ["top-left", "bottom-right-y-first"])
def test_near_ties_and_extreme_magnitudes(tie: str) -> None:
    """Vertices a hair off a sample row or column, edges from far outside the viewport
    (where the float crossing has no digits left), and tiny coordinates: all exact."""
    hair = 2.0**-45
    near = [[0.5 + hair, 0.5], [6.5, 0.5 - hair], [3.5, 6.5 + hair], [2.5 - hair, 3.5]]
    far = [[-1e130, -3e129], [1e130, 4.0], [3.25, 1e130]]
    thin = [[-1e120, 3.5], [1e120, 3.5 + 1e-100], [1e120, 3.5 + 2e-100]]  # a sliver along row 3
    tiny = [[1e-130, 1e-130], [7.5, 2e-130], [3e-130, 7.5]]
    for contours in ([near], [far], [thin], [tiny], [near, far, tiny]):
        _agrees(PathScene.from_paths(SIZE, SIZE, [contours]), tie)


def test_refuses_coordinates_beyond_the_exact_range_and_skips_non_finite_paths() -> None:
    fill = TrapezoidFill()
    square = np.array(_SQUARE, dtype=np.float64)
    with pytest.raises(ValueError, match="path 1 "):
        fill.rasterize(PathScene.from_paths(SIZE, SIZE, [[square], [square * 2.0**460]]))
    with pytest.raises(ValueError, match="path 0 "):
        fill.rasterize(PathScene.from_paths(SIZE, SIZE, [[np.array([[0, 0], [4, 2.0**-460], [0, 4]])]]))
    with pytest.raises(ValueError, match="triangle 1 "):
        fill.rasterize(Scene(SIZE, SIZE, np.array([[[0, 0], [4, 0], [0, 4]], [[0, 0], [2.0**-470, 0], [0, 4]]])))
    # a NaN in a path (even next to a huge coordinate) makes the path cover nothing
    spans = fill.rasterize(PathScene.from_paths(SIZE, SIZE, [[square], [square, np.array([[np.nan, 0], [1e300, 0], [0, 1]])],
                                                             [square]]))
    assert sorted(set(spans.primitive.tolist())) == [0, 2]
    assert spans.n_pixels == 2 * 36


def test_declares_a_path_taking_reference() -> None:
    fill = TrapezoidFill()
    assert isinstance(fill, Rasterizer)
    assert fill.name == "trapezoid_fill" and fill.convention == Convention(sample=(0.5, 0.5), tie="top-left")
    assert scene_kinds_of(fill) == ("triangles", "paths")
    assert takes(fill, PathScene.from_paths(4, 4, [[_SQUARE]], "evenodd")) and takes(fill, Scene(4, 4, np.zeros((0, 3, 2))))
    assert TrapezoidFill("bottom-right").name == "trapezoid_fill_bottom-right"
    with pytest.raises(ValueError, match="tie"):
        TrapezoidFill("nearest")  # type: ignore[arg-type]
    empty = fill.rasterize(Scene(4, 4, np.zeros((0, 3, 2))))
    assert len(empty) == 0


def test_crossing_column_is_exact_where_the_float_crossing_is_off() -> None:
    """Edges of length about 2**50..2**58 through the viewport: the float crossing errs by
    up to several columns either way; the confirmed column is the exact one (brute force
    over every column in rational arithmetic)."""
    rng = np.random.default_rng(7)
    width, sx = 16, 0.5
    for _ in range(1500):
        px, py = rng.uniform(0, width), float(rng.integers(0, 4)) + 0.5
        angle = rng.uniform(0, math.pi)
        scale = 2.0 ** rng.integers(50, 59)
        ax, ay = px - scale * math.cos(angle), py - scale * math.sin(angle)
        bx, by = px + scale * math.cos(angle), py + scale * math.sin(angle)
        if rng.integers(2):
            ax, ay, bx, by = bx, by, ax, ay
        if ay == by:
            continue
        tie_right = bool(rng.integers(2))
        ys = py
        want = width
        for k in range(width + 1):
            s = orient2d_fraction(ax, ay, bx, by, k + sx, ys)
            if (tie_right if s == 0 else (s < 0) == (by > ay)):
                want = k
                break
        assert crossing_column(ax, ay, bx, by, tie_right, sx, ys, width) == want, (ax, ay, bx, by, ys)
