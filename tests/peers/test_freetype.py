"""FreeType's smooth rasterizer, ported (:mod:`tests.peers.freetype`), against its original
(``tests/peers/src/freetype``: ``ftgrays.c`` 2.14.3 built standalone, with ``FT_INT64`` as
every 64-bit build has it, and without: the two line walks), and
judged by the harness against the convention it declares: no accuracy or seams failure
but FreeType's own bugs, each found and named by its cause.

The cross-check draws ``RASTERCHECK_PEER_SCENES`` random triangles (300 by default), each in
both windings, under both fill rules and through both sweeps (bitmap and direct spans).
"""

from __future__ import annotations

import ctypes
import os
from collections.abc import Callable
from functools import cache

import numpy as np
import pytest
from numpy.typing import NDArray

from cases.suites import suite
from harness import run_suite
from harness.contract.case import Case
from harness.contract.scenes import Scene
from harness.oracle.area import exact_area
from rasterizers.real._masks import LIMIT
from tests.peers.compiled import SOURCES, load
from tests.peers.freetype import LINE_WALKS, FreetypeSmooth, render_outline, to_26_6

SCENES = int(os.environ.get("RASTERCHECK_PEER_SCENES", "300"))
FOLDER = SOURCES / "freetype"
# standalone, with FALL_THROUGH (compiler-macros.h's, which a standalone build lacks)
STANDALONE = ("-DSTANDALONE_", "-DFALL_THROUGH=(void)0")
# the flags of each line walk: FT_INT64 as every 64-bit build defines it, or not at all
FLAGS = {"int64": (*STANDALONE, "-DFT_INT64=long", "-DFT_Int64=long", "-DFT_UInt64=unsigned long", "-DFT_UInt=unsigned int"),
         "scanline": STANDALONE}

Original = Callable[..., NDArray[np.uint8]]


@cache
def _original(walk: str) -> Original:
    """The compiled original with ``walk``'s flags: ``render(points 26.6 (P, 2), ends (C,),
    width, height, evenodd, direct)`` -> (height, width) uint8."""
    library = load(f"freetype-{walk}", [FOLDER / "ftgrays.c", FOLDER / "freetype_shim.c"], flags=FLAGS[walk])
    function = library.rastercheck_ftgrays_render
    function.restype = ctypes.c_int
    function.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                         ctypes.c_int, ctypes.c_int, ctypes.c_void_p]

    def render(points: NDArray[np.int64], ends: list[int], width: int, height: int, evenodd: bool = False,
               direct: bool = False) -> NDArray[np.uint8]:
        xy = np.ascontiguousarray(points, dtype=np.int64)  # FT_Pos: long, 64 bits here
        last = np.ascontiguousarray(ends, dtype=np.uint16)
        out = np.zeros((height, width), dtype=np.uint8)
        error = function(xy.ctypes.data, len(xy), last.ctypes.data, len(last), int(evenodd), int(direct), width, height,
                         out.ctypes.data)
        assert error == 0, f"ftgrays failed ({error}) on {points.tolist()}"
        return out

    return render


@pytest.fixture(scope="module")
def original() -> Original:
    """The original as every 64-bit build compiles it (``FT_INT64``): the port's default."""
    return _original("int64")


def _random_triangles(count: int, seed: int = 29) -> list[tuple[str, NDArray[np.float64], int, int]]:
    """(kind, (3, 2) vertices in px, width, height): ordinary, tiny (inside a pixel, thinner
    than the 1/64 grid), huge (to the adapter's limit), partly outside, on lattices of 1/2 to
    1/256 px, and degenerate (collinear or repeated vertices)."""
    rng = np.random.default_rng(seed)
    kinds = ("ordinary", "tiny", "huge", "outside", "lattice", "degenerate")
    out = []
    for i in range(count):
        kind = kinds[i % len(kinds)]
        width, height = (int(v) for v in rng.integers(1, 48, 2))
        if kind == "ordinary":
            p = rng.uniform(0, 1, (3, 2)) * [width, height]
        elif kind == "tiny":
            p = rng.integers(0, 8, 2) + rng.uniform(0, 1, (3, 2)) * rng.choice([1.0, 1 / 16, 1 / 128])
        elif kind == "huge":
            p = rng.uniform(-1, 1, (3, 2)) * LIMIT * rng.choice([1.0, 2.0**-6, 2.0**-12])
        elif kind == "outside":
            p = rng.uniform(-30, 30, (3, 2)) + [width / 2, height / 2]
        elif kind == "lattice":
            p = rng.integers(-4, 52, (3, 2)) / rng.choice([1, 2, 4, 64, 256])
        else:
            a, b = rng.uniform(-4, 52, (2, 2))
            p = np.array([a, b, a + (b - a) * rng.choice([0.0, 0.5, 2.0])])
        out.append((kind, p, width, height))
    return out


# (evenodd, direct): the gray bitmap under both rules, and direct spans
MODES = ((False, False), (True, False), (False, True))


@pytest.mark.parametrize("walk", list(LINE_WALKS))
def test_the_port_equals_the_original_on_random_triangles(walk: str) -> None:
    """Every alpha of every triangle, both windings, both fill rules, both sweeps: equal
    (a huge triangle, whose edges are walked over up to 2**21 cells, and the scanline walk
    in one fill rule and sweep: the walk is what they test, the sweep and the rules are
    the same code as the default walk's)."""
    original = _original(walk)
    differing: dict[str, int] = {}
    compared = 0
    for kind, p, width, height in _random_triangles(SCENES):
        for points in (to_26_6(p), to_26_6(p[::-1])):
            for evenodd, direct in ((False, False),) if kind == "huge" or walk != "int64" else MODES:
                want = original(points, [2], width, height, evenodd, direct)
                got = render_outline(points, np.array([2]), width, height, evenodd, walk)
                differing[kind] = differing.get(kind, 0) + int(np.count_nonzero(got != want))
                compared += want.size
    assert compared > 0 and not any(differing.values()), f"alphas differing by kind of triangle: {differing}, of {compared}"


def test_the_port_equals_the_original_on_polygons_of_several_contours(original: Original) -> None:
    """The port's outline walk is FreeType's for any straight contours: a polygon and a
    square with a hole, both fill rules."""
    rng = np.random.default_rng(6)
    for _ in range(12):
        points = to_26_6(np.concatenate([rng.uniform(-3, 35, (7, 2)), [[4, 4], [28, 4], [28, 28], [4, 28]],
                                         [[10, 10], [10, 20], [20, 20], [20, 10]]]))
        for evenodd in (False, True):
            want = original(points, [6, 10, 14], 32, 32, evenodd)
            assert np.array_equal(render_outline(points, np.array([6, 10, 14]), 32, 32, evenodd), want)


@cache
def _quick() -> dict[str, Case]:
    return {c.id: c for c in suite("quick") if isinstance(c, Case)}


def test_the_adapter_equals_the_original_on_every_quick_suite_scene(original: Original) -> None:
    """Each still scene of the quick suite drawn by the port's adapter and, one triangle at
    a time into the same boxes (2 px around it, clipped to the viewport), by the original:
    the same (triangle, pixel, alpha)s."""
    rasterizer = FreetypeSmooth()
    drawn = 0
    for cid, case in _quick().items():
        scene = case.scene
        if not isinstance(scene, Scene) or not np.all(np.abs(scene.positions[np.isfinite(scene.positions)]) <= LIMIT):
            continue
        fragments = []
        for k, p in enumerate(scene.positions):
            if not np.all(np.isfinite(p)):
                continue
            x0, y0 = np.clip(np.floor(p.min(axis=0)) - 2, 0, [scene.width, scene.height]).astype(int)
            x1, y1 = np.clip(np.ceil(p.max(axis=0)) + 2, 0, [scene.width, scene.height]).astype(int)
            if x0 < x1 and y0 < y1:
                value = original(to_26_6(p - [x0, y0]), [2], int(x1 - x0), int(y1 - y0))
                y, x = np.nonzero(value)
                fragments.append(np.stack([np.full(x.size, k), x + x0, y + y0, value[y, x]], axis=1))
        want = np.concatenate(fragments) if fragments else np.zeros((0, 4), dtype=np.int64)
        got = rasterizer.rasterize(scene)
        t, x, y = got.pixels()
        alpha = got.alpha if got.alpha is not None else np.zeros(0)
        got_rows = np.stack([t, x, y, np.rint(alpha * 255).astype(np.int64)], axis=1)
        assert np.array_equal(_sorted(got_rows), _sorted(want)), cid
        assert np.array_equal(alpha * 255, np.rint(alpha * 255)), cid  # value / 255 exactly
        drawn += 1
    assert drawn >= 60


def _sorted(rows: NDArray[np.int64]) -> NDArray[np.int64]:
    return rows[np.lexsort(rows.T[::-1])] if rows.size else rows.reshape(0, 4)


def test_the_original_rounds_a_half_covered_pixel_by_its_winding(original: Original) -> None:
    """``FT_FILL_RULE``: ``area >> 9`` is floor(256 A), complemented (``~coverage``) for a
    negative area: a half-covered pixel is 128 one way, 127 the other (either rule), while
    one of area 1 is 255 both ways."""
    half = to_26_6(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    for evenodd in (False, True):
        assert original(half, [2], 2, 2, evenodd)[0, 0] == 127
        assert original(half[::-1], [2], 2, 2, evenodd)[0, 0] == 128
        square = to_26_6(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]))
        assert original(square, [3], 1, 1, evenodd)[0, 0] == original(square[::-1], [3], 1, 1, evenodd)[0, 0] == 255


def test_the_originals_crossings_lose_precision_on_long_edges() -> None:
    """``FT_UDIV``'s 32-bit reciprocal: the quick suite's wedge from x = -1e6 to 1e6 errs by
    12 levels; made 100 times smaller, by under two (the quantisation's one and a little);
    built without ``FT_INT64`` (exact ``FT_DIV_MOD``), by under two at either size."""
    errors: dict[str, list[float]] = {}
    for walk in LINE_WALKS:
        for big in (1e4, 1e6):
            wedge = np.array([[-big, 6.25], [big, 9.75], [16.5, 27.0]])
            alpha = _original(walk)(to_26_6(wedge), [2], 32, 32) / 255.0
            errors.setdefault(walk, []).append(
                max(abs(float(alpha[y, x]) - float(exact_area(wedge, x, y))) * 255 for y in range(32) for x in range(32)))
    assert errors["int64"][0] < 2.0 and errors["int64"][1] >= 11.0, errors
    assert max(errors["scanline"]) < 2.0, errors


# the quick suite's failures of the port under its declared convention: FreeType's two bugs
FLIP_WINDING = "invariance|changes-under-flip-winding|none"
LARGE = "accuracy|overflow-2^12..2^24|none"
EXPECTED = {
    **{(cid, "invariance"): FLIP_WINDING for cid in (
        "lattice/bits-0", "lattice/bits-2", "lattice/bits-4", "lattice/bits-8", "lattice/first-half-pixel",
        "float/near-ties-1e-6",
        "watertight/grid-6x6-main/lattice", "watertight/grid-6x6-main/float", "watertight/grid-6x6-mixed/lattice",
        "watertight/grid-6x6-mixed/float", "watertight/fan-32/corner")},
    ("degenerate/huge/sliver-1e6", "accuracy"): LARGE,
    ("degenerate/huge/wedge-1e6", "accuracy"): LARGE,
}


def test_the_quick_suite_finds_freetypes_bugs_and_nothing_else(original: Original) -> None:
    """Accuracy, seams and invariance over the quick suite, against the declared
    convention: the failures are exactly FreeType's two bugs, named by their causes --
    alphas that change with the winding (``~coverage`` for negative areas, and crossings
    rounded down in the direction the edge is walked: two levels apart), and crossings that
    lose precision on edges of 2 x 10**6 px (errors only on the triangles beyond 2**12 px).
    Motion cases included (accuracy on every frame). Each invariance failure's first pixel
    differs by two levels or more in the original too."""
    results = run_suite([FreetypeSmooth()], cases=list(suite("quick")), isolate=False, identify=False, repros=False,
                        only={"accuracy", "seams", "invariance"}, timeout=120.0)
    checks = {r.check for r in results}
    assert {"accuracy", "seams", "invariance"} <= checks
    failing = {(r.case, r.check): r for r in results if r.status not in ("pass", "skip")}
    assert {key: r.evidence.get("signature") for key, r in failing.items()} == EXPECTED, \
        {key: r.message for key, r in failing.items()}
    for (cid, check), r in failing.items():
        if check == "accuracy":
            assert "errors only on triangles with coordinates of magnitude 1e+06 px" in r.message
            continue
        t, x, y, alpha, flipped = r.evidence["flip-winding"][0]
        scene = _quick()[cid].scene
        assert isinstance(scene, Scene)
        p = scene.positions[t]
        one = original(to_26_6(p), [2], x + 3, y + 3)[y, x]
        other = original(to_26_6(p[[0, 2, 1]]), [2], x + 3, y + 3)[y, x]
        assert (one, other) == (round(alpha * 255), round(flipped * 255)) and abs(int(one) - int(other)) >= 2, cid


def test_accuracy_names_errors_confined_to_huge_triangles_by_their_magnitude() -> None:
    """The cause added for FreeType's long edges, read from the facts: errors only on
    triangles beyond 2**12 px are that magnitude's (as conformance names them), after the
    causes of the levels (a bias stays a bias) and before a shift or drift; below 2**12, or
    with a smaller triangle erring too (``magnitude`` the smallest), not."""
    from harness.checks.area import alpha_cause

    facts = {"edge_pixels": 9, "tolerance": 7.0, "residue": [-12.0, 11.0], "between_levels": 0.9, "area_spread": 0.9,
             "bias": 0.5, "bias_share": 0.5,
             "drift_rows": {"correlation": 0.9, "first": 0.3, "last": 11.8, "steps": 20}}
    def named(**more: object) -> str | None:
        found = alpha_cause({**facts, **more})
        return None if found is None else found[0]

    assert named() == "drift"
    assert named(magnitude=1e6) == "overflow-2^12..2^24"
    assert named(magnitude=4000.0) == "drift"
    assert named(magnitude=1e6, bias=9.0, bias_share=1.0) == "alpha-bias"


def test_an_unknown_line_walk_is_refused_by_name() -> None:
    with pytest.raises(ValueError, match="'int32'"):
        FreetypeSmooth("int32")
    assert FreetypeSmooth("scanline").name == "freetype_scanline" and FreetypeSmooth().name == "freetype"


def test_the_adapter_draws_as_one_triangle_at_a_time_in_any_chunks(monkeypatch: pytest.MonkeyPatch) -> None:
    """The compiled loop over triangles gives what ``draw_each_alpha`` gives with
    ``draw_one`` (each triangle into its own box's bitmap), however the triangles are
    chunked; a NaN triangle draws nothing."""
    from harness.contract.coverage import Coverage
    from rasterizers.real._masks import draw_each_alpha
    from tests.peers import freetype

    rng = np.random.default_rng(3)
    positions = rng.uniform(-10, 70, (40, 3, 2))
    positions[5, 0, 0] = np.nan
    scene = Scene(64, 48, positions)
    rasterizer = FreetypeSmooth()

    def rows(coverage: Coverage) -> NDArray[np.int64]:
        t, x, y = coverage.pixels()
        assert coverage.alpha is not None
        return _sorted(np.stack([t, x, y, np.rint(coverage.alpha * 255).astype(np.int64)], axis=1))

    whole = rows(rasterizer.rasterize(scene))
    assert np.array_equal(whole, rows(draw_each_alpha(scene, "freetype", rasterizer.draw_one)))
    assert whole.shape[0] > 1000 and not np.any(whole[:, 0] == 5)
    monkeypatch.setattr(freetype, "CHUNK", 100)
    assert np.array_equal(rows(rasterizer.rasterize(scene)), whole)
