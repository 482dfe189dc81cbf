"""stb_truetype's version-2 anti-aliased rasterizer (issue 29, point 6): the port
(:mod:`tests.peers.stb`) draws every alpha the compiled original draws, and the quick
suite, judging it against the convention it declares, finds stb's own bugs only -- each
named by its cause: row 0 of a bitmap at the screen's top (``viewport-edge``), a triangle
with an infinite coordinate (``non-finite-input``), and, drawn into screen-wide bitmaps,
the x stepped down 2,000 rows in float32 (``drift``).

The cross-check against the original draws ``RASTERCHECK_PEER_SCENES`` random triangles
(300 by default; 100,000 measured: 0 differing alphas of 2,720,261,330)."""

from __future__ import annotations

import ctypes
import os
from functools import cache

import numpy as np
import pytest

from cases.scenes import TALL_SCREEN, TALL_TRIANGLES
from cases.suites import suite
from harness import run_suite
from harness.checks import Result
from harness.checks.area import alpha_cause
from harness.contract.case import Case, MotionCase
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.diagnose.causes import by_cause
from harness.oracle.area import area_coverage
from rasterizers.real._masks import draw_each_alpha
from tests.peers import compiled
from tests.peers.stb import MARGIN, StbTruetype, rasterize_polygon

SCENES = int(os.environ.get("RASTERCHECK_PEER_SCENES", "300"))

# what the quick suite finds, judged on accuracy and seams: (case, check) -> signature
STB_BUGS = {
    ("mesh/box/view-0", "accuracy"): "accuracy|viewport-edge|none",
    ("mesh/cylinder/near-clipped", "accuracy"): "accuracy|viewport-edge|none",
    ("mesh/capsule/near-clipped", "accuracy"): "accuracy|viewport-edge|none",
    ("mesh/torus/near-clipped", "accuracy"): "accuracy|viewport-edge|none",
    ("degenerate/sliver/random-12", "accuracy"): "accuracy|viewport-edge|none",
    ("degenerate/offscreen/fully", "accuracy"): "accuracy|viewport-edge|none",
    ("degenerate/non-finite/mixed", "accuracy"): "accuracy|non-finite-input|none",
}


@cache
def original() -> ctypes.CDLL:
    """The compiled stb_truetype.h with its shim (skips without a compiler)."""
    lib = compiled.load("stb", [compiled.SOURCES / "stb" / "shim.c"])
    lib.stb_rasterize_polygon.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                                          ctypes.c_int, ctypes.c_void_p]
    lib.stb_rasterize_polygon.restype = None
    return lib


def original_draws(points: np.ndarray, width: int, height: int, off_x: int, off_y: int) -> np.ndarray:
    """The original's (height, width) uint8 bitmap of one polygon of float32 points."""
    xy = np.ascontiguousarray(points, dtype=np.float32).ravel()
    out = np.zeros((height, width), dtype=np.uint8)
    original().stb_rasterize_polygon(xy.ctypes.data, xy.size // 2, width, height, off_x, off_y, out.ctypes.data)
    return out


class CompiledStb(StbTruetype):
    """The plugin with the compiled original in place of the port: the same boxes, offsets
    and float32 vertices."""

    def rasterize(self, scene: Scene) -> Coverage:  # draw_each_alpha's loop, a triangle per call
        return draw_each_alpha(scene, self.name, self._draw, MARGIN)

    def _draw(self, p: np.ndarray, w: int, h: int, origin: tuple[int, int]) -> np.ndarray:
        points = (p + np.array(origin, dtype=np.float64)).astype(np.float32)
        if self.bitmap == "screen":
            return original_draws(points, origin[0] + w, h, 0, origin[1])[:, origin[0]:] / 255.0
        return original_draws(points, w, h, origin[0], origin[1]) / 255.0


def random_draws(count: int, seed: int) -> list[tuple[np.ndarray, int, int, int, int]]:
    """(float32 triangle, width, height, off_x, off_y): random triangles in and around
    small bitmaps, with edges above and left of the bitmap (off 0 and not), slivers, tiny
    ones, vertical and horizontal edges, points on the 1/4 px lattice, vertices far off,
    tall ones (2,048 rows, x past 1,024 px, from x = 960 px)."""
    rng = np.random.default_rng(seed)
    draws = []
    for k in range(count):
        kind = k % 16
        width, height = int(rng.integers(1, 80)), int(rng.integers(1, 80))
        off_x, off_y = (0, 0) if k % 3 == 0 else (int(rng.integers(-4, 40)), int(rng.integers(-4, 40)))
        base = np.array([off_x, off_y], dtype=np.float64)
        if kind == 0:  # anywhere around the bitmap: edges above, left, right and below it
            p = base + rng.uniform(-12, 90, (3, 2))
        elif kind == 1:  # tall and thin, leaving the bitmap at the top and the bottom
            p = base + rng.uniform(0, 1, (3, 2)) * np.array([6.0, 160.0]) - np.array([0.0, 40.0])
        elif kind == 2:  # tiny
            p = base + rng.uniform(5, 7, (1, 2)) + rng.uniform(0, 0.2, (3, 2))
        elif kind == 3:  # on the 1/4 px lattice: vertical and horizontal edges, vertices on pixel corners
            p = base + np.round(rng.uniform(-8, 60, (3, 2)) * 4) / 4
        elif kind == 4:  # a vertical edge
            p = base + rng.uniform(-5, 60, (3, 2))
            p[1, 0] = p[0, 0]
        elif kind == 5:  # a sliver
            p = base + rng.uniform(-5, 60, (3, 2))
            p[2] = p[0] + rng.uniform(0.9, 1.1) * (p[1] - p[0]) + rng.uniform(-0.05, 0.05, 2)
        elif kind == 6:  # vertices far off
            p = base + rng.uniform(-3000, 3000, (3, 2))
        elif kind == 7:  # 2,048 rows tall at x past 1,024 px, in a bitmap from x = 960
            top = [rng.uniform(1024, 1100), rng.uniform(0, 8)]
            p = np.array([top, [top[0] + rng.uniform(-40, 40), rng.uniform(2040, 2048)],
                          [top[0] + rng.uniform(-20, 20), rng.uniform(0, 2048)]])
            width, height, off_x, off_y = 200, 2056, 960, 0
        else:  # in and around the bitmap, smaller
            p = base + rng.uniform(-6, 50, (3, 2))
        draws.append((p.astype(np.float32), width, height, off_x, off_y))
    return draws


def test_the_port_draws_every_alpha_the_original_draws():
    """Random triangles (RASTERCHECK_PEER_SCENES, 300 by default): 0 differing alphas."""
    differing = total = 0
    for points, width, height, off_x, off_y in random_draws(SCENES, 29):
        want = original_draws(points, width, height, off_x, off_y)
        got = rasterize_polygon(points, width, height, off_x, off_y)
        differing += int(np.count_nonzero(got != want))
        total += want.size
    assert total > 1_000_000 and differing == 0


def test_the_port_draws_what_the_original_draws_on_non_finite_and_huge_vertices():
    """What stb does with NaN, infinite and huge coordinates (garbage, C's (int) of a NaN
    included) is drawn alike."""
    rng = np.random.default_rng(7)
    for k in range(24):
        p = rng.uniform(-2, 30, (3, 2))
        if k < 18:
            p[k % 3, k // 3 % 2] = (np.nan, np.inf, -np.inf)[k // 6]
        else:
            p[k % 3] = rng.uniform(-1e30, 1e30, 2)
        with np.errstate(invalid="ignore", over="ignore"):
            points = p.astype(np.float32)
        assert np.array_equal(rasterize_polygon(points, 24, 20, 0, k % 2), original_draws(points, 24, 20, 0, k % 2)), p


def test_the_original_fills_row_0_right_of_an_edge_above_the_bitmap():
    """An edge ending above a bitmap at row 0 (off_y 0) whose line crosses row 0 inside it
    adds its whole signed height to the row: 255 right of that line, where the triangle
    covers only pixels 5 to 7. One row lower (off_y 1, the edge's end clamped) it is right."""
    triangle = np.array([[5, -6], [5.5, -2], [9, 6]], dtype=np.float32)
    row = original_draws(triangle, 12, 8, 0, 0)[0]
    assert row[6:].tolist() == [255] * 6
    moved = triangle + np.float32(1)
    exact = area_coverage(Scene(12, 8, moved.astype(np.float64)[None]), StbTruetype.convention)
    _, x, y = exact.pixels()
    first = np.zeros(12)
    assert exact.alpha is not None
    first[x[y == 1]] = exact.alpha[y == 1]
    assert np.abs(original_draws(moved, 12, 7, 0, 1)[0] / 255 - first).max() <= StbTruetype.convention.alpha_tolerance


@cache
def quick() -> list[Case | MotionCase]:
    return list(suite("quick"))


@cache
def judged() -> tuple[Result, ...]:
    """The port judged on the quick suite's accuracy and seams, in-process."""
    return tuple(run_suite([StbTruetype()], cases=quick(), isolate=False, identify=False, repros=False,
                           only={"accuracy", "seams"}))


def test_the_quick_suite_finds_stbs_bugs_only_each_named_by_its_cause():
    """Judged against the convention it declares, the port fails accuracy on the 7 cases
    of stb's two bugs and nowhere else (seams: none), each failure's signature and message
    naming the cause, grouped as a run's report groups them."""
    results = judged()
    assert {r.check for r in results if r.status != "skip"} == {"accuracy", "seams"}
    failing = {(r.case, r.check): r.evidence.get("signature") for r in results if r.status in ("fail", "error")}
    assert failing == STB_BUGS
    for r in results:
        if (r.case, r.check) in STB_BUGS:
            facts = r.evidence["alpha_facts"]
            if "viewport-edge" in STB_BUGS[r.case, r.check]:  # stb's row 0: every error there, under a triangle above
                assert facts["over_border"] == {"top": facts["over_pixels"]}, (r.case, facts)
                assert all(p["y"] == 0 for p in r.evidence["pixels"] if p["over"])
            assert "on triangles reaching past" in r.message or "NaN or infinite" in r.message, r.message
    assert {group.cause: group.count for group in by_cause(results)} == {"viewport-edge": 6, "non-finite-input": 1}
    # away from its bugs stb keeps the tolerance derived from its float32 arithmetic, and needs it: its
    # worst alpha is more than half a level off
    worst = max(r.metrics["max_error"] for r in results if r.check == "accuracy" and (r.case, r.check) not in STB_BUGS)
    assert 0.5 / 255 < worst <= StbTruetype.convention.alpha_tolerance


def test_the_bugs_the_suite_finds_are_the_originals():
    """The failing cases drawn by the compiled original in the plugin's place: the same
    alphas, so the bugs are stb's and not the port's."""
    cases = {c.id: c for c in quick()}
    for case_id, _ in STB_BUGS:
        case = cases[case_id]
        assert isinstance(case, Case) and isinstance(case.scene, Scene)
        scene = case.scene
        assert CompiledStb().rasterize(scene) == StbTruetype().rasterize(scene), case_id


def tall_cases() -> list[Case]:
    """The quick suite's tall triangles, and frame 40 of its tall sliver in motion (x near
    1,500 px), as still cases."""
    motion = next(c for c in quick() if c.id == "motion/tall-triangle/translate-x-1/64")
    assert isinstance(motion, MotionCase)
    return [Case("float/tall-triangles-2048px", Scene(*TALL_SCREEN, TALL_TRIANGLES)), Case(f"{motion.id}#40", motion.frames[40])]


def test_stepping_drifts_down_tall_triangles_drawn_from_the_screens_left_edge():
    """Drawn into bitmaps from the screen's left edge (x past 1,024 px: a float32 step of
    2**-13 px or coarser) the tall triangles drift down their 2,000 rows, by 26 levels and,
    on the tall sliver at x 1,500, by 32; accuracy names it drift. The original draws the
    same alphas. In their own boxes (x near 0) they do not drift beyond the tolerance (the
    quick suite passes both cases)."""
    screen, boxed = StbTruetype("screen"), StbTruetype()
    for case, levels in zip(tall_cases(), (26, 32)):
        scene = case.scene
        assert isinstance(scene, Scene)
        assert screen.rasterize(scene) == CompiledStb("screen").rasterize(scene), case.id
        [verdict] = run_suite([screen], cases=[case], isolate=False, identify=False, repros=False, only={"accuracy"})
        assert verdict.status == "fail" and verdict.evidence["signature"] == "accuracy|drift|none", verdict.message
        assert levels - 1 < verdict.metrics["max_error"] * 255 < levels + 0.5, (case.id, verdict.message)
        [kept] = run_suite([boxed], cases=[case], isolate=False, identify=False, repros=False, only={"accuracy"})
        assert kept.status == "pass" and kept.metrics["max_error"] * 255 < 1, kept.message


def test_where_the_errors_lie_names_the_cause_before_what_they_are():
    """The facts of :func:`harness.checks.area.alpha_cause` about where the pixels beyond the
    tolerance are: all on non-finite triangles, all in a border row of a side their
    triangles cross; one elsewhere and neither is named."""
    border = {"edge_pixels": 9, "tolerance": 0.5, "over_pixels": 3, "over_non_finite": 0.0, "over_border": {"top": 3},
              "over_border_share": 1.0}
    assert alpha_cause(border) == ("viewport-edge", "every alpha beyond the tolerance (3) in the screen's top row, "
                                   "on triangles reaching past that edge of the screen")
    non_finite = alpha_cause({**border, "over_non_finite": 1.0})
    assert non_finite is not None and non_finite[0] == "non-finite-input"
    assert alpha_cause({**border, "over_border_share": 2 / 3}) is None


def test_the_declared_convention():
    convention = StbTruetype.convention
    assert convention.coverage_kind == "area" and convention.levels == 256 and convention.subpixel_bits is None
    assert convention.alpha_tolerance == pytest.approx(1 / 510 + 55 * 2.0**-13)
    with pytest.raises(ValueError, match="bitmap must be 'box' or 'screen'"):
        StbTruetype("glyph")
    empty = StbTruetype().rasterize(Scene(8, 8, np.zeros((0, 3, 2))))
    assert isinstance(empty, Coverage) and len(empty) == 0
