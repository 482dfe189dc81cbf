"""The exact winding-number oracle for paths (harness.oracle.winding)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cases.strategies import conventions
from harness.contract.case import Case
from harness.contract.conventions import TIE_RULES, Convention
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.winding import FILL_RULES, path_spans, path_spans_rational

SIZE = 6
QUICK = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _same(a, b) -> None:
    assert [x.tolist() for x in a] == [x.tolist() for x in b]


def _counts(spans, width: int, height: int) -> np.ndarray:
    out = np.zeros((height, width), dtype=np.int64)
    for _, y, x0, x1 in zip(*spans):
        out[y, x0:x1] += 1
    return out


# -- strategies ------------------------------------------------------------------------------

lattice = st.integers(-4, 4 * SIZE + 4)  # 1/4 lattice, a little beyond the viewport


@st.composite
def lattice_contour(draw):
    """A random polygon on the 1/4 lattice, with repeated vertices (zero-length edges),
    horizontal edges and collinear runs mixed in."""
    n = draw(st.integers(1, 7))
    pts = [[draw(lattice), draw(lattice)] for _ in range(n)]
    extras = draw(st.lists(st.tuples(st.sampled_from(["repeat", "horizontal", "midpoint"]),
                                     st.integers(0, 100)), max_size=3))
    for kind, at in extras:
        k = at % len(pts)
        a, b = pts[k], pts[(k + 1) % len(pts)]
        if kind == "repeat":
            new = list(a)
        elif kind == "horizontal":
            new = [draw(lattice), a[1]]
        else:
            even = (a[0] + b[0]) % 2 == 0 and (a[1] + b[1]) % 2 == 0  # exact lattice midpoint
            new = [(a[0] + b[0]) // 2, (a[1] + b[1]) // 2] if even else list(b)
        pts.insert(k + 1, new)
    return np.array(pts, dtype=np.float64) / 4


@st.composite
def stars(draw):
    """A star polygon {n/k} (pentagrams, heptagrams, ...) with float vertices."""
    n = draw(st.integers(5, 9))
    k = draw(st.integers(2, (n - 1) // 2))
    cx, cy = draw(lattice) / 4, draw(lattice) / 4
    r = draw(st.integers(4, 16)) / 4
    phase = draw(st.integers(0, 7)) * math.pi / 4
    return np.array([[cx + r * math.cos(phase + 2 * math.pi * k * i / n),
                      cy + r * math.sin(phase + 2 * math.pi * k * i / n)] for i in range(n)])


@st.composite
def bow_ties(draw):
    x0, x1 = sorted((draw(lattice), draw(lattice)))
    y0, y1 = sorted((draw(lattice), draw(lattice)))
    return np.array([[x0, y0], [x1, y1], [x1, y0], [x0, y1]], dtype=np.float64) / 4


contour = st.one_of(lattice_contour(), stars(), bow_ties())


@st.composite
def paths(draw):
    """1-4 contours in 1-2 paths; sometimes a second contour is a scaled copy of the first,
    with the same or the opposite orientation (rings, overlaps)."""
    cs = draw(st.lists(contour, min_size=1, max_size=3))
    if draw(st.booleans()):
        c = cs[0]
        centre = np.round(c.mean(axis=0) * 4) / 4
        inner = centre + (c - centre) / 2
        cs.append(inner[::-1].copy() if draw(st.booleans()) else inner)
    owner = draw(st.lists(st.integers(0, 1), min_size=len(cs), max_size=len(cs)))
    return cs, owner


# -- the oracle against the rational brute force ------------------------------------------------


@pytest.mark.parametrize("tie", TIE_RULES)
@pytest.mark.parametrize("fill_rule", FILL_RULES)
@QUICK
@given(data=paths(), convention=conventions())
def test_matches_rational(tie, fill_rule, data, convention) -> None:
    cs, owner = data
    conv = replace(convention, tie=tie)
    _same(path_spans(cs, owner, fill_rule, conv, SIZE, SIZE),
          path_spans_rational(cs, owner, fill_rule, conv, SIZE, SIZE))


@pytest.mark.parametrize("tie", TIE_RULES)
@settings(max_examples=40, deadline=None)
@given(tri=st.lists(lattice, min_size=6, max_size=6), convention=conventions(),
       fill_rule=st.sampled_from(FILL_RULES))
def test_one_triangle_is_the_triangle_oracle(tie, tri, convention, fill_rule) -> None:
    positions = np.array(tri, dtype=np.float64).reshape(1, 3, 2) / 4
    conv = replace(convention, tie=tie, cull="none")
    cov = exact_coverage(Scene(SIZE, SIZE, positions), conv)
    _same(path_spans([positions[0]], [0], fill_rule, conv, SIZE, SIZE),
          (cov.triangle, cov.y, cov.x0, cov.x1))


@settings(max_examples=60, deadline=None)
@given(jitter=st.lists(st.integers(-3, 3), min_size=32, max_size=32),
       flips=st.lists(st.booleans(), min_size=9, max_size=9),
       starts=st.lists(st.integers(0, 3), min_size=9, max_size=9),
       convention=conventions(), fill_rule=st.sampled_from(FILL_RULES), tie=st.sampled_from(TIE_RULES))
def test_quad_grid_is_watertight(jitter, flips, starts, convention, fill_rule, tie) -> None:
    """A 3 x 3 grid of irregular quads (interior vertices jittered on the 1/4 lattice),
    each its own path with a random orientation and start vertex, covers each sample of
    the outer square exactly once, whatever the tie rule, snapping and fill rule."""
    conv = replace(convention, tie=tie)
    n, cell = 3, 2.0
    grid = np.zeros((n + 1, n + 1, 2))
    it = iter(jitter)
    for gy in range(n + 1):
        for gx in range(n + 1):
            x, y = gx * cell, gy * cell
            if 0 < gx < n and 0 < gy < n:
                x, y = x + next(it) / 4, y + next(it) / 4
            grid[gy, gx] = (x, y)
    quads, owner = [], []
    for q in range(n * n):
        gy, gx = divmod(q, n)
        quad = np.array([grid[gy, gx], grid[gy, gx + 1], grid[gy + 1, gx + 1], grid[gy + 1, gx]])
        quad = np.roll(quad, starts[q], axis=0)
        quads.append(quad[::-1].copy() if flips[q] else quad)
        owner.append(q)
    counts = _counts(path_spans(quads, owner, fill_rule, conv, SIZE, SIZE), SIZE, SIZE)
    square = np.array([grid[0, 0], grid[0, n], grid[n, n], grid[n, 0]])
    whole = _counts(path_spans([square], [0], fill_rule, conv, SIZE, SIZE), SIZE, SIZE)
    assert counts.max() <= 1
    assert (counts == whole).all()


# -- fill rules, degenerate and extreme input --------------------------------------------------


def _square(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)


@pytest.mark.parametrize("reverse_hole", [False, True])
def test_ring_with_hole(reverse_hole: bool) -> None:
    outer, hole = _square(0, 0, 6, 6), _square(2, 2, 4, 4)
    if reverse_hole:
        hole = hole[::-1].copy()
    nonzero = _counts(path_spans([outer, hole], [0, 0], "nonzero", Convention(), 6, 6), 6, 6)
    evenodd = _counts(path_spans([outer, hole], [0, 0], "evenodd", Convention(), 6, 6), 6, 6)
    assert evenodd[2:4, 2:4].sum() == 0 and evenodd.sum() == 32
    assert nonzero.sum() == (32 if reverse_hole else 36)


def test_separate_paths_are_independent() -> None:
    a, b = _square(0, 0, 4, 4), _square(2, 2, 6, 6)
    p, y, x0, x1 = path_spans([a, b], [7, 3], "evenodd", Convention(), 6, 6)
    assert p.tolist() == [3] * 4 + [7] * 4
    assert (x1 - x0).sum() == 32


def test_non_finite_path_covers_nothing_and_range_is_checked() -> None:
    good, bad = _square(0, 0, 4, 4), _square(0, 0, np.nan, 4)
    p, *_ = path_spans([good, bad, good], [0, 1, 2], "nonzero", Convention(), 6, 6)
    assert sorted(set(p.tolist())) == [0, 2]
    huge = _square(0, 0, 2.0**500, 4)
    with pytest.raises(ValueError, match="contour 1"):
        path_spans([good, huge], [0, 1], "nonzero", Convention(), 6, 6)
    _, y, x0, x1 = path_spans_rational([huge], [0], "nonzero", Convention(), 6, 6)
    assert (x1 - x0).sum() == 24


def test_degenerate_contours_cover_nothing() -> None:
    point = np.array([[1.5, 1.5]])
    segment = np.array([[0.5, 0.5], [5.5, 5.5]])
    flat = np.array([[0, 0.5], [3, 0.5], [6, 0.5], [3, 0.5]], dtype=np.float64)
    for conv in (Convention(tie=t) for t in TIE_RULES):
        p, *_ = path_spans([point, segment, flat], [0, 1, 2], "nonzero", conv, 6, 6)
        assert p.size == 0


def test_bad_arguments() -> None:
    sq = _square(0, 0, 4, 4)
    with pytest.raises(ValueError, match="fill_rule"):
        path_spans([sq], [0], "winding", Convention(), 6, 6)
    with pytest.raises(ValueError, match="single-sample"):
        path_spans([sq], [0], "nonzero", Convention(samples=4), 6, 6)
    with pytest.raises(ValueError, match="path_of_contour"):
        path_spans([sq], [0, 1], "nonzero", Convention(), 6, 6)


@pytest.mark.parametrize("bad", [np.nan, np.inf, 1e300])
def test_a_last_path_with_a_non_finite_or_out_of_range_vertex_leaves_the_others_alone(bad: float) -> None:
    """Regression: the per-path room was read past the end when the last path had no
    usable edge (IndexError)."""
    from harness.contract.scenes import PathScene

    scene = PathScene.from_paths(8, 8, [[[[1.0, 1.0], [6.0, 1.0], [1.0, 6.0]]], [[[bad, 1.0], [6.0, 1.0], [1.0, 6.0]]]])
    got = exact_coverage(scene, Convention())
    first = exact_coverage(scene.subset([0]), Convention())
    if bad == 1e300:  # finite: decided exactly, by the rational rows
        assert got.take(np.flatnonzero(got.primitive == 0)) == first
    else:
        assert got == first


def test_an_open_outline_is_what_a_filler_that_forgets_the_closing_edge_draws():
    """:func:`open_outline_coverage` is the hypothesis the signatures test an answer
    against: on triangles and paths of the fuzz families, exactly the known-bad trapezoid
    filler that builds its edges from consecutive vertex pairs (rows left inside end at
    their last crossing), and never the oracle's on all of them (the open outline differs)."""
    from cases.fuzz import generate
    from harness.contract.scenes import PathScene
    from harness.oracle.winding import UNBALANCED_ROWS, open_outline_coverage
    from tests.known_bad.paths import PathFillBug

    bad = PathFillBug("open-contours")

    def fragments(coverage, scene):
        t, x, y = coverage.pixels()
        inside = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
        return set(zip(t[inside].tolist(), x[inside].tolist(), y[inside].tolist()))
    differs = 0
    for family in ("lattice", "float", "paths"):
        for index in range(12):
            case = generate(family, 0, index)
            assert isinstance(case, Case)
            scene = case.scene
            assert isinstance(scene, (Scene, PathScene))
            predicted = fragments(open_outline_coverage(scene, bad.convention, "last-crossing"), scene)
            assert predicted == fragments(bad.rasterize(scene), scene), (family, index)
            differs += predicted != fragments(exact_coverage(scene, bad.convention), scene)
    assert differs >= 30
    # the other rule fills a row left inside to the screen's edge
    tri = Scene(8, 4, np.array([[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]]))
    spans = {rule: open_outline_coverage(tri, Convention(), rule) for rule in UNBALANCED_ROWS}
    assert len(spans["last-crossing"]) == 0
    assert spans["to-edge"].x1.tolist() == [8, 8, 8, 8] and spans["to-edge"].x0.tolist() == [3, 2, 1, 0]
    with pytest.raises(ValueError, match="unbalanced"):
        open_outline_coverage(tri, Convention(), "both")


def test_an_open_outline_beyond_the_float_filter_is_decided_in_rationals():
    """A vertex beyond 2**450 takes the rational row-by-row way, with the same rule for
    rows left inside: the same spans as a vertex at 2**40, whose edge is as steep here."""
    from harness.oracle.winding import UNBALANCED_ROWS, open_outline_coverage

    for rule in UNBALANCED_ROWS:
        spans = [open_outline_coverage(Scene(12, 4, np.array([[[0.0, 0.0], [8.0, 0.0], [0.0, 2.0**k]]])), Convention(), rule)
                 for k in (40, 500)]
        assert [(c.y.tolist(), c.x0.tolist(), c.x1.tolist()) for c in spans] == \
            [([], [], []) if rule == "last-crossing" else ([0, 1, 2, 3], [8] * 4, [12] * 4)] * 2
