"""The area-coverage checks (issue 14): accuracy, seams and popping pass on correct
anti-aliasers -- the exact area rounded to 8 bits, and the exact share of a 4 x 4 grid's
samples declared as supersampled -- and fail on the known-bad ones for the reason each
stands for (asserted on the metrics, not only the status); the multisample known-bads
fail the per-sample checks the same way."""

from __future__ import annotations

import fnmatch
from dataclasses import replace
from fractions import Fraction
from functools import cache
from typing import Any

import numpy as np
import pytest

from cases.suites import suite
from harness import run_suite
from harness.checks import Result, accuracy, checks, popping, seams
from harness.checks.records import Tolerance
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import Scene
from harness.oracle.area import area_coverage, exact_area
from harness.oracle.coverage import exact_coverage, sample_shares
from tests.known_bad.antialiasing import (
    GRID_4X4,
    BiasedArea,
    CoarseSupersampleClaimsAnalytic,
    DriftingStepArea,
    Float32EdgeStepping,
    FourBitArea,
    GammaEncodedArea,
    HalfPixelShiftedArea,
    InclusiveSampleTies,
    MirroredPattern,
    PerEdgeMethodSwitch,
    SwappedSampleBits,
    TruncatedArea,
)
from tests.narrow import triangles

AREA_CHECKS = {"accuracy", "seams", "popping"}


class Quantised8Bit:
    """The exact area rounded to the nearest of 256 levels: within half a level (and the
    oracle's float error, below 2**-24) of the exact area."""

    name = "area_8bit"
    convention = Convention(coverage="area", tolerance=0.5 / 255 + 2.0**-24)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = area_coverage(scene, self.convention)
        assert exact.alpha is not None
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=np.rint(exact.alpha * 255) / 255)


class Shares4x4:
    """The exact share of a 4 x 4 grid's samples covered (top-left ties), declared as
    what it is: supersampled area on 17 levels."""

    name = "shares_4x4"
    convention = Convention(coverage="area", samples=GRID_4X4, levels=17)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return sample_shares(scene, self.convention)


class FloatSupersampler:
    """A correct 4 x 4 supersampler computing in float64, as a plugin author writes one:
    each sample tested against the three edge functions (evaluated from the edge's
    smaller end point, so that a shared edge is evaluated alike from both sides), top-left
    ties, alpha the share of its 16 samples. Where a sample lies within rounding of an
    edge the float sign may differ from the exact one: near ties, not errors. Sampling at
    other offsets than it declares (``offsets``) makes it a known-bad."""

    name = "float_supersampler"
    convention = Convention(coverage="area", samples=GRID_4X4, levels=17)
    interpolates = False

    def __init__(self, offsets: tuple[tuple[float, float], ...] = GRID_4X4) -> None:
        self.offsets = np.array(offsets, dtype=np.float64)

    def rasterize(self, scene: Scene) -> Coverage:
        parts: list[tuple[int, np.ndarray, np.ndarray, np.ndarray]] = []
        for t, p in enumerate(scene.positions):
            if not np.all(np.isfinite(p)):
                continue
            area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
            if area == 0:
                continue
            if area < 0:  # the interior to the left of every edge (y down)
                p = p[[0, 2, 1]]
            x0, x1 = max(int(np.floor(p[:, 0].min())), 0), min(int(np.ceil(p[:, 0].max())), scene.width)
            y0, y1 = max(int(np.floor(p[:, 1].min())), 0), min(int(np.ceil(p[:, 1].max())), scene.height)
            if x0 >= x1 or y0 >= y1:
                continue
            xs, ys = np.meshgrid(np.arange(x0, x1), np.arange(y0, y1))
            px, py = xs[..., None] + self.offsets[:, 0], ys[..., None] + self.offsets[:, 1]
            inside = np.ones(px.shape, dtype=bool)
            for k in range(3):
                a, b = p[k], p[(k + 1) % 3]
                lo, hi, sign = (a, b, 1.0) if tuple(a) <= tuple(b) else (b, a, -1.0)
                e = sign * ((hi[0] - lo[0]) * (py - lo[1]) - (hi[1] - lo[1]) * (px - lo[0]))
                top_left = b[1] < a[1] or (b[1] == a[1] and b[0] > a[0])
                inside &= (e > 0) | ((e == 0) & top_left)
            count = inside.sum(axis=-1)
            hit = count > 0
            parts.append((t, xs[hit], ys[hit], count[hit] / len(self.offsets)))
        if not parts:
            return Coverage.empty()
        primitive = np.concatenate([np.full(x.size, k) for k, x, _, _ in parts])
        return Coverage.from_pixels(primitive, np.concatenate([x for _, x, _, _ in parts]),
                                    np.concatenate([y for _, _, y, _ in parts]),
                                    alpha=np.concatenate([a for _, _, _, a in parts]))


@cache
def quick() -> dict[str, Case | MotionCase]:
    return {c.id: c for c in suite("quick")}


def cases(*patterns: str) -> list[Case | MotionCase]:
    return [c for cid, c in quick().items() if any(fnmatch.fnmatchcase(cid, p) for p in patterns)]


def judged(rasterizer: Any, selected: list[Case | MotionCase], only: set[str]) -> dict[str, dict[str, Result]]:
    """check -> case id -> result, in-process."""
    out: dict[str, dict[str, Result]] = {}
    for r in run_suite([rasterizer], cases=selected, isolate=False, identify=False, repros=False, only=set(only),
                       timeout=60.0):
        out.setdefault(r.check, {})[r.case] = r
    return out


# -- correct rasterizers pass ----------------------------------------------------------------


def test_the_exact_area_in_8_bits_passes_every_area_check_on_the_quick_suite():
    results = judged(Quantised8Bit(), list(quick().values()), AREA_CHECKS)
    assert set(results) >= AREA_CHECKS
    for check in AREA_CHECKS:
        bad = {cid: r.message for cid, r in results[check].items() if r.status != "pass"}
        assert not bad, (check, bad)
    tolerance = Quantised8Bit.convention.alpha_tolerance
    assert max(r.metrics["max_error"] for r in results["accuracy"].values()) <= tolerance
    assert len(results["seams"]) >= 24 and len(results["popping"]) >= 25
    # conflation: the pieces of an exact partition composited with over still leave a seam
    assert max(r.metrics["max_over_gap"] for r in results["seams"].values()) > 0.2
    # single triangles: each step of a rounded area is within one level of the area's
    single = [r for cid, r in results["popping"].items() if cid.startswith("motion/triangle/")]
    assert single and all(r.metrics["max_pop_levels"] <= 1.0 and r.metrics["pops"] == 0 for r in single)


def test_the_exact_share_of_a_4x4_grid_passes_and_its_popping_shows_as_an_artifact():
    selected = [c for c in quick().values() if not isinstance(c, MotionCase)] + cases("motion/*/translate-*-1/16")
    results = judged(Shares4x4(), selected, AREA_CHECKS)
    for check in AREA_CHECKS:
        bad = {cid: r.message for cid, r in results[check].items() if r.status != "pass"}
        assert not bad, (check, bad)
    assert all(r.metrics["max_error"] == 0 for r in results["accuracy"].values())
    # judged against the exact area, a sixteenth of a pixel at a time is a pop
    pops = [r.metrics["max_pop_levels"] for r in results["popping"].values()]
    assert max(pops) >= 8 and sum(r.metrics["pops"] for r in results["popping"].values()) > 0


# -- accuracy ---------------------------------------------------------------------------------


def _alone(scene: Scene, convention: Convention, x: int, y: int, alpha: float) -> Coverage:
    """The oracle's answer with the alpha of triangle 0 at pixel (x, y) replaced."""
    oracle = exact_coverage(scene, convention)
    t, xs, ys = oracle.pixels()
    assert oracle.alpha is not None
    values = oracle.alpha.copy()
    values[(t == 0) & (xs == x) & (ys == y)] = alpha
    return Coverage.from_pixels(t, xs, ys, alpha=values)


def test_accuracy_passes_an_alpha_exactly_at_the_tolerance():
    """Pixel (0, 0) holds exactly half of the triangle's area: alpha = 1/2 + 1/128 is at
    the tolerance 1/128, within it; on 129 levels it is a level. The float oracle's bound
    leaves the verdict open: the rationals decide."""
    scene = Scene(2, 2, [[[0, 0], [1, 1], [0, 1]]])
    convention = Convention(coverage="area", tolerance=2.0**-7, levels=129)
    assert exact_area(scene.positions[0], 0, 0) == Fraction(1, 2)
    case = Case("exact/at-tolerance", scene)
    oracle = exact_coverage(scene, convention)
    at = accuracy(case, _alone(scene, convention, 0, 0, 0.5 + 2.0**-7), oracle, convention)
    assert at.status == "pass" and at.metrics["exact_decisions"] == 1 and at.metrics["max_error"] == 2.0**-7, at.message
    beyond = accuracy(case, _alone(scene, convention, 0, 0, 0.5 + 2 * 2.0**-7), oracle, convention)
    assert beyond.status == "fail" and beyond.metrics["over_tolerance"] == 1
    assert beyond.evidence["pixels"][0] == {"triangle": 0, "x": 0, "y": 0, "alpha": 0.5 + 2**-6, "area": 0.5,
                                            "error": 2**-6, "over": True, "near_tie": False}


def test_accuracy_decides_at_the_last_bit_where_the_float_oracle_cannot():
    """Pixel (0, 0) holds 5/6 of a pixel, which no float is; the float oracle errs by
    1/2**54.6 or so. The floats on either side of 5/6 + 1/128 are judged by the rationals:
    the one above is beyond the tolerance although its float error equals it exactly (on
    the integer lattice, where no float rounding excuses it; off a lattice the last bit is
    a near tie)."""
    scene = Scene(2, 4, [[[0, 0], [1, 0], [0, 3]]])
    convention = Convention(coverage="area", tolerance=2.0**-7)
    limit = exact_area(scene.positions[0], 0, 0) + Fraction(2.0**-7)
    assert limit.denominator % 3 == 0
    below = float(limit) if Fraction(float(limit)) <= limit else float(np.nextafter(float(limit), 0.0))
    above = float(np.nextafter(below, 2.0))
    assert Fraction(below) < limit < Fraction(above)
    case = Case("exact/last-bit", scene, lattice=True)
    oracle = exact_coverage(scene, convention)
    assert oracle.alpha is not None and not abs(above - oracle.alpha[0]) > 2.0**-7  # the float difference says "within"
    for alpha, over in ((below, 0), (above, 1)):
        verdict = accuracy(case, _alone(scene, convention, 0, 0, alpha), oracle, convention)
        assert verdict.metrics["over_tolerance"] == over and verdict.metrics["exact_decisions"] == 1, (alpha, verdict.message)
        assert verdict.metrics["near_tie"] == 0
    off_lattice = accuracy(replace(case, lattice=False), _alone(scene, convention, 0, 0, above), oracle, convention)
    assert off_lattice.metrics["over_tolerance"] == 0 and off_lattice.metrics["near_tie"] == 1


def test_accuracy_fails_alphas_off_the_declared_levels_and_nothing_else():
    """The unquantised float area declared as 256 levels: within the tolerance everywhere,
    yet on none of the levels it declares."""
    case = quick()["lattice/bits-2"]
    convention = Convention(coverage="area")
    assert isinstance(case, Case)
    oracle = exact_coverage(case.scene, convention)
    verdict = accuracy(case, oracle, oracle, convention)
    assert verdict.status == "fail" and verdict.metrics["over_tolerance"] == 0 and verdict.metrics["off_level"] > 100
    assert "declared levels" in verdict.message and verdict.evidence["off_level"][0].keys() >= {"x", "y", "alpha", "level"}


def test_biased_area_fails_accuracy_by_two_levels():
    verdict = judged(BiasedArea(), cases("lattice/bits-2"), {"accuracy"})["accuracy"]["lattice/bits-2"]
    assert verdict.status == "fail"
    metrics, worst = verdict.metrics, verdict.evidence["pixels"][0]
    assert 1.5 / 255 < metrics["max_error"] <= 2.5 / 255 + 1e-12
    assert metrics["over_tolerance"] > 1000 and metrics["off_level"] == 0
    assert worst["over"] and worst["alpha"] > worst["area"]  # too much alpha: the bias


def test_an_answer_without_alphas_fails_every_area_check():
    """Spans but no alphas (NaN throughout): beyond every tolerance, never a crash in the
    exact fallback."""
    convention = Quantised8Bit.convention
    case = quick()["watertight/fan-8/centre"]
    assert isinstance(case, Case)
    oracle = exact_coverage(case.scene, convention)
    bare = Coverage(oracle.triangle, oracle.y, oracle.x0, oracle.x1)
    verdict = accuracy(case, bare, oracle, convention)
    assert verdict.status == "fail" and verdict.metrics["over_tolerance"] == oracle.n_pixels
    assert seams(case, bare, convention, oracle).metrics["seam_pixels"] > 0
    motion = quick()["motion/triangle/translate-x-1/16"]
    assert isinstance(motion, MotionCase)
    frames = list(motion.frames)[:3]
    oracles = [exact_coverage(s, convention) for s in frames]
    bares = [Coverage(o.triangle, o.y, o.x0, o.x1) for o in oracles]
    assert popping(motion.id, frames, bares, oracles, convention).metrics["alpha_jumps"] > 0


def test_an_area_exactly_halfway_between_levels_may_round_to_either():
    """Issue 29: the triangle's area at pixel (22, 23) is 19/34 = 142.5/255 exactly. Level
    142 and level 143 are each exactly half a level from it: within the default tolerance,
    exactly at it, whichever way a rasterizer rounds (the decision is on the numbers the
    floats 142/255 and 0.5/255 stand for, not on the floats); a level further is not. On
    its half-pixel lattice, with no near tie to hide behind."""
    scene = Scene(40, 40, [[[22.0, 22.0], [30.0, 23.5], [24.5, 30.5]]])
    assert exact_area(scene.positions[0], 22, 23) == Fraction(285, 510)
    convention = Convention(coverage="area")
    case = Case("exact/halfway", scene, lattice=True)
    oracle = exact_coverage(scene, convention)
    assert oracle.alpha is not None
    level = oracle.alpha * 255
    for rounded in (np.floor(level + 0.5), np.ceil(level - 0.5), np.rint(level)):  # halves up, down, to even
        verdict = accuracy(case, Coverage(oracle.triangle, oracle.y, oracle.x0, oracle.x1, alpha=rounded / 255),
                           oracle, convention)
        assert verdict.status == "pass" and verdict.metrics["near_tie"] == 0, verdict.message
        assert verdict.metrics["max_error"] == pytest.approx(0.5 / 255) and verdict.metrics["exact_decisions"] >= 1
    for beyond in (141 / 255, 144 / 255):
        verdict = accuracy(case, _alone(scene, convention, 22, 23, beyond), oracle, convention)
        assert verdict.status == "fail" and verdict.metrics["over_tolerance"] == 1, verdict.message


class Truncated8Bit:
    """The area truncated to 8 bits (a converter that floors), declared as what it is:
    within one level of the area."""

    name = "area_8bit_truncated"
    convention = Convention(coverage="area", tolerance=1 / 255)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = area_coverage(scene, self.convention)
        assert exact.alpha is not None
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=np.floor(exact.alpha * 255) / 255)


def test_seams_allow_each_piece_the_declared_tolerance():
    """Issue 29: a truncating converter loses up to a level per piece, which it declares;
    where many pieces meet (a fan's centre, a grid's corners) the sum falls short by more
    than half a level per piece. Declared one level, no seam; declared half a level, seams
    (the same answer); a piece missing is a seam under either."""
    rasterizer = Truncated8Bit()
    for case in cases("watertight/fan-8/centre", "watertight/grid-6x6-main/float"):
        assert isinstance(case, Case) and case.region is not None
        answer = rasterizer.rasterize(triangles(case.scene))
        one_level = rasterizer.convention
        oracle = exact_coverage(case.scene, one_level)
        verdict = seams(case, answer, one_level, oracle)
        assert verdict.status == "pass" and "(1 levels per piece)" in verdict.message, (case.id, verdict.message)
        assert accuracy(case, answer, oracle, one_level).metrics["over_tolerance"] == 0
        half_level = replace(one_level, tolerance=None)
        strict = seams(case, answer, half_level, oracle)
        assert strict.status == "fail" and strict.metrics["seam_pixels"] >= 1, case.id
        worst = strict.evidence["pixels"][0]
        assert worst["pieces"] / 2 < -worst["levels_off"] <= worst["pieces"]  # short by more than half a level each
        dropped = answer.take(np.flatnonzero(answer.triangle != 3))
        assert seams(case, dropped, one_level, oracle).metrics["seam_pixels"] > 0, case.id


# -- near ties (float rounding) ----------------------------------------------------------------


NON_DYADIC = "watertight/grid-12x12-main/non-dyadic"  # lines at non-dyadic spacing: samples within rounding of edges


def test_a_float_supersampler_passes_with_its_samples_within_rounding_of_an_edge_as_near_ties():
    """Issue 28: a correct float supersampler counts some samples lying ~1e-15 px from an
    edge the other way. Each such pixel is reached by flipping samples within rounding of
    an edge of its triangle: a near tie (float rounding), not a failure; strict mode
    allows none."""
    case = quick()[NON_DYADIC]
    assert isinstance(case, Case) and not case.lattice
    rasterizer = FloatSupersampler()
    convention = rasterizer.convention
    answer, oracle = rasterizer.rasterize(triangles(case.scene)), exact_coverage(case.scene, convention)
    verdict = accuracy(case, answer, oracle, convention)
    metrics = verdict.metrics
    assert verdict.status == "pass" and metrics["over_tolerance"] == 0 and metrics["max_error"] == 0, verdict.message
    assert metrics["near_tie"] >= 10 and metrics["near_tie_error"] >= 2 / 16, metrics
    assert f"{int(metrics['near_tie'])} near ties (float rounding: samples within rounding of an edge" in verdict.message
    listed = verdict.evidence["pixels"]  # near ties first, then the rest, each worst first
    ties = listed[: int(metrics["near_tie"])]
    assert all(p["near_tie"] and not p["over"] for p in ties) and not any(p["near_tie"] for p in listed[len(ties):])
    assert all(abs(p["alpha"] - p["area"]) > convention.alpha_tolerance for p in ties)  # beyond the tolerance, each
    strict = accuracy(case, answer, oracle, convention, Tolerance(mode="strict"))
    assert strict.status == "fail" and strict.metrics["near_tie"] == metrics["near_tie"] and "strict" in strict.message
    # through the runner, which hands the check its tolerance: the same near ties
    through = judged(rasterizer, [case], {"accuracy"})["accuracy"][case.id]
    assert through.status == "pass" and through.metrics["near_tie"] == metrics["near_tie"]


def test_a_supersampler_sampling_elsewhere_still_fails_by_real_error():
    """The same float supersampler at the D3D11 16x offsets while it declares the 4 x 4
    grid: samples a sixteenth of a pixel from where they should be are no rounding."""
    case = quick()[NON_DYADIC]
    assert isinstance(case, Case)
    verdict = judged(FloatSupersampler(STANDARD_PATTERNS[16]), [case], {"accuracy"})["accuracy"][case.id]
    assert verdict.status == "fail" and verdict.metrics["over_tolerance"] > 1000
    # pixels with a declared sample on (or within rounding of) an edge may count it either way, as in conformance
    assert verdict.metrics["over_tolerance"] > 4 * verdict.metrics["near_tie"]
    worst = verdict.evidence["pixels"][0]
    assert worst["over"] and not worst["near_tie"] and worst["error"] >= 2 / 16


def _vertical_edge(a: float) -> Scene:
    """Pixels (0, 0) and (0, 1) covered left of x = a: the exact area of each is ``a``."""
    return Scene(2, 2, [[[a, -5], [a, 5], [a - 20, 0]]])


def test_an_area_within_rounding_of_a_rounding_boundary_is_a_near_tie():
    """The float nearest 65.5/255 lies 2.7e-17 below it, so level 65 is the exact
    rounding; the float product a * 255 is exactly 65.5 and rounds (to even) to 66, half a
    level and 2.7e-17 away: beyond the exact half-level tolerance by far less than the area
    moves when the triangle moves by a rounding. A near tie, not an error; one level off an
    area no rounding brings to a boundary is an error."""
    convention = Convention(coverage="area")  # the tolerance: exactly half a level
    a = float(Fraction(131, 510))
    scene = _vertical_edge(a)
    assert exact_area(scene.positions[0], 0, 0) == Fraction(a) < Fraction(131, 510) and a * 255 == 65.5
    oracle = exact_coverage(scene, convention)
    answer = Coverage.from_pixels([0, 0], [0, 0], [0, 1], alpha=np.rint(oracle.alpha * 255) / 255)  # type: ignore[operator]
    case = Case("near-tie/half-level", scene)
    verdict = accuracy(case, answer, oracle, convention)
    assert verdict.status == "pass" and verdict.metrics["near_tie"] == 2 and verdict.metrics["over_tolerance"] == 0
    assert verdict.evidence["pixels"] == [{"triangle": 0, "x": 0, "y": y, "alpha": 66 / 255, "area": a,
                                           "error": 66 / 255 - a, "over": False, "near_tie": True} for y in (0, 1)]
    assert "2 near ties (float rounding: the area within rounding of a level's boundary" in verdict.message
    assert accuracy(case, answer, oracle, convention, Tolerance(mode="strict")).status == "fail"
    assert accuracy(replace(case, lattice=True), answer, oracle, convention).metrics["over_tolerance"] == 2
    far = _vertical_edge(65.4 / 255)
    wrong = Coverage.from_pixels([0, 0], [0, 0], [0, 1], alpha=[66 / 255, 65 / 255])
    verdict = accuracy(Case("near-tie/far", far), wrong, exact_coverage(far, convention), convention)
    assert verdict.status == "fail" and verdict.metrics["over_tolerance"] == 1 and verdict.metrics["near_tie"] == 0
    assert verdict.evidence["pixels"][0]["over"] and (verdict.evidence["pixels"][0]["x"],
                                                      verdict.evidence["pixels"][0]["y"]) == (0, 0)


def test_known_bad_anti_aliasers_fail_accuracy_by_real_error_off_the_lattice():
    """Off the lattice, where near ties are allowed, the known-bads' errors are no rounding
    (the coarse supersampler's half-covered pixels on a diagonal within rounding of the
    pixel's own, 8/16 written as 128/255 where the area is 127.5/255 - 1e-32, are)."""
    case = quick()[NON_DYADIC]
    for bad in (BiasedArea(), CoarseSupersampleClaimsAnalytic()):
        verdict = judged(bad, [case], {"accuracy"})["accuracy"][case.id]
        metrics = verdict.metrics
        assert verdict.status == "fail" and metrics["over_tolerance"] > 1000, (bad.name, verdict.message)
        assert metrics["near_tie"] <= metrics["over_tolerance"] / 100 and metrics["near_tie_error"] <= 0.5 / 255 + 1e-9
        assert metrics["max_error"] > 1.5 / 255 and verdict.evidence["pixels"][0]["over"], bad.name


# the cause each area known-bad's accuracy failure names, and words its message says
AREA_CAUSES: list[tuple[Any, str, str]] = [  # (known-bad anti-aliasers of many classes)
    (BiasedArea(), "alpha-bias", "2.0 levels high on average"),
    (GammaEncodedArea(), "gamma", "(gamma 2.2"),
    (HalfPixelShiftedArea(), "sub-pixel-shift", "moved by (+0.5, +0.5) px"),
    (TruncatedArea(), "truncated-levels", "truncated to the levels"),
    (FourBitArea(), "coarse-levels", "on 16 levels only"),
    (DriftingStepArea(), "drift", "error growing down the triangle"),
    (CoarseSupersampleClaimsAnalytic(), "alpha-error", ""),  # none of those: the error alone
]


@pytest.mark.parametrize("bad, cause, words", AREA_CAUSES, ids=[b.name for b, _, _ in AREA_CAUSES])
def test_an_accuracy_failure_names_its_cause_from_facts(bad, cause, words):
    """Issue 29: each classic anti-aliasing bug's accuracy failure names its cause -- a
    bias, gamma, a sub-pixel shift, truncation, coarse levels, drift down the triangle --
    in its message and its signature, on a lattice and a float scene; an error none of
    them explains (a 4 x 4 supersampler claiming the exact area) is named by none."""
    from harness.diagnose.signatures import signature

    selected = cases("lattice/bits-2", "float/random-50px")
    verdicts = judged(bad, selected, {"accuracy"})["accuracy"]
    for case in selected:
        verdict = verdicts[case.id]
        assert verdict.status == "fail", (bad.name, case.id)
        assert signature(verdict, case, bad.convention).key == f"accuracy|{cause}|none", (case.id, verdict.message)
        assert words in verdict.message, verdict.message
        named = [text for other, _, text in AREA_CAUSES if text and other is not bad and text in verdict.message]
        assert not named, (verdict.message, named)


def test_errors_no_fact_explains_name_no_cause():
    """Alphas a sample or two off (inclusive ties of a 4 x 4 supersampler), or a coarse
    supersampler's, are on levels and may happen to sit on a coarser grid: no truncation,
    coarse levels or other cause is named for them."""
    from tests.known_bad.antialiasing import InclusiveSupersampledTies

    selected = cases("lattice/*", "watertight/grid-6x6-*")
    for bad in (InclusiveSupersampledTies(), CoarseSupersampleClaimsAnalytic()):
        failed = [r for r in judged(bad, selected, {"accuracy"})["accuracy"].values() if r.status == "fail"]
        assert len(failed) >= 4, bad.name
        assert all("alpha_cause" not in r.evidence for r in failed), [(r.case, r.message) for r in failed]


def test_accuracy_names_no_cause_where_it_passes():
    """The correct anti-aliasers pass accuracy with no cause in the message (the facts are
    taken on failure only)."""
    selected = cases("lattice/bits-2", "float/random-50px")
    for rasterizer in (Quantised8Bit(), Shares4x4()):
        for verdict in judged(rasterizer, selected, {"accuracy"})["accuracy"].values():
            assert verdict.status == "pass" and "alpha_facts" not in verdict.evidence, verdict.message


# -- seams ------------------------------------------------------------------------------------


def test_seams_counts_a_missing_piece_and_a_stray():
    case = quick()["watertight/grid-6x6-main/none"]
    assert isinstance(case, Case) and case.region is not None
    rasterizer = Quantised8Bit()
    convention = rasterizer.convention
    answer = rasterizer.rasterize(triangles(case.scene))
    oracle = exact_coverage(case.scene, convention)
    assert seams(case, answer, convention, oracle).status == "pass"
    dropped = answer.take(np.flatnonzero(answer.triangle != 7))
    verdict = seams(case, dropped, convention, oracle)
    assert verdict.status == "fail" and verdict.metrics["seam_pixels"] > 10 and verdict.metrics["strays"] == 0
    assert verdict.evidence["pixels"][0]["levels_off"] == -255  # a pixel wholly inside piece 7
    stray = Coverage.concat([answer, Coverage([0], [0], [0], [1], alpha=[3 / 255])])  # pixel (0, 0): outside
    verdict = seams(case, stray, convention, oracle)
    assert verdict.status == "fail" and verdict.metrics["strays"] == 1 and verdict.evidence["strays"] == [[0, 0]]


def test_per_edge_method_switch_keeps_its_tolerance_but_opens_seams_and_changes_under_flips():
    """cairo's 2010 seam: each alpha within the (generous) tolerance it declares; the
    pieces of a partition do not sum to one pixel where a shared edge is integrated one
    way on one side and another on the other; flipping a winding swaps the methods."""
    selected = cases("watertight/grid-6x6-main/none", "watertight/fan-8/centre")
    results = judged(PerEdgeMethodSwitch(), selected, {"accuracy", "seams", "invariance"})
    for case in selected:
        assert results["accuracy"][case.id].status == "pass"
        seam = results["seams"][case.id]
        assert seam.status == "fail" and seam.metrics["seam_pixels"] > 10 and seam.metrics["max_sum_error"] >= 2
        worst = seam.evidence["pixels"][0]
        assert abs(worst["levels_off"]) > worst["pieces"] / 2 and len(worst["triangles"]) >= 2
        flips = results["invariance"][case.id]
        assert flips.status == "fail" and flips.metrics["flip-winding_differences"] > 0
        assert flips.metrics["rotate-vertices_differences"] == 0 == flips.metrics["permute-triangles_differences"]


# -- popping ----------------------------------------------------------------------------------


def test_coarse_supersampling_claimed_as_analytic_fails_accuracy_and_pops():
    results = judged(CoarseSupersampleClaimsAnalytic(), cases("lattice/bits-0", "motion/triangle/translate-x-1/64"),
                     {"accuracy", "popping"})
    coarse = results["accuracy"]["lattice/bits-0"]
    assert coarse.status == "fail" and coarse.metrics["max_error"] > 8 / 255 and coarse.metrics["off_level"] == 0
    pop = results["popping"]["motion/triangle/translate-x-1/64"]
    assert pop.status == "fail" and pop.metrics["alpha_jumps"] > 10 and pop.metrics["max_pop_levels"] >= 8
    evidence = pop.evidence
    series = evidence["series"]
    assert {len(v) for v in series.values()} == {pop.metrics["frames"]} == {129}
    # the alpha moves in sixteenths, the area continuously
    assert len(set(series["alpha"])) <= 17 < len(set(series["area"]))
    assert series["oracle"] == series["area"]  # analytic: the declared model is the area
    step = evidence["steps"][0]
    assert step.keys() == {"frame", "triangle", "x", "y", "d_alpha", "d_oracle"}
    assert abs(step["d_alpha"] - step["d_oracle"]) > 2 * CoarseSupersampleClaimsAnalytic.convention.alpha_tolerance
    assert evidence["pixel"].keys() == {"x", "y"}


def test_popping_allows_each_triangle_its_own_tolerance():
    """Two triangles over pixel (0, 0), each covering its left part up to x = a, moving
    right by 0.02 levels' worth: each area crosses a half level in the same step, so each
    rounded alpha steps by one level while the area steps by 0.02 -- each keeps its
    promise, the summed alpha pops by two levels. The verdict is per triangle; the
    summed pop is the artifact."""
    a = 100.49 / 255
    frames = [Scene(2, 2, [[[a + d, -5], [a + d, 5], [a + d - 20, 0]]] * 2) for d in (0.0, 0.02 / 255)]
    convention = Quantised8Bit.convention
    answers = [Quantised8Bit().rasterize(s) for s in frames]
    oracles = [exact_coverage(s, convention) for s in frames]
    verdict = popping("two-pieces", frames, answers, oracles, convention)
    assert verdict.status == "pass" and verdict.metrics["alpha_jumps"] == 0, verdict.message
    assert verdict.metrics["max_step_error"] <= 2 * convention.alpha_tolerance
    assert 1.9 < verdict.metrics["max_pop_levels"] < 2 and verdict.metrics["pops"] == 2  # rows 0 and 1 alike
    assert verdict.evidence["pixel"] == {"x": 0, "y": 0} and verdict.evidence["series"]["alpha"] == [200 / 255, 202 / 255]


def test_popping_in_triangle_chunks_agrees_with_popping_at_once(monkeypatch):
    """Large scenes are judged a few triangles at a time (bounded memory): same verdict,
    same metrics, same evidence."""
    import harness.checks.area_popping as area_popping

    motion = quick()["motion/fan-8/translate-x-1/16"]
    assert isinstance(motion, MotionCase)
    frames = list(motion.frames)
    bad = CoarseSupersampleClaimsAnalytic()
    answers = [bad.rasterize(s) for s in frames]
    oracles = [exact_coverage(s, bad.convention) for s in frames]
    at_once = popping(motion.id, frames, answers, oracles, bad.convention)
    monkeypatch.setattr(area_popping, "_CHUNK_ENTRIES", 1)  # one triangle per chunk
    chunked = popping(motion.id, frames, answers, oracles, bad.convention)
    assert at_once.status == chunked.status == "fail" and at_once.metrics == chunked.metrics
    assert at_once.evidence == chunked.evidence


# -- multisample known-bads, judged sample by sample -------------------------------------------


def test_multisample_known_bads_fail_per_sample_for_their_reason():
    lattice = cases("lattice/bits-0")
    mirrored = judged(MirroredPattern(), lattice, {"conformance"})["conformance"]["lattice/bits-0"]
    assert mirrored.status == "fail" and mirrored.metrics["failing_samples"] == 4
    swapped = judged(SwappedSampleBits(), lattice, {"conformance"})["conformance"]["lattice/bits-0"]
    assert swapped.status == "fail" and swapped.metrics["failing_samples"] == 2
    assert [s["sample"] for s in swapped.evidence["samples"]] == [1, 2]
    # the anti-diagonals of this grid run through samples 0 and 3 of the 4x pattern
    ties = cases("watertight/grid-6x6-on-samples-0.25/lattice")
    inclusive = judged(InclusiveSampleTies(), ties, {"watertight", "conformance"})
    double = inclusive["watertight"][ties[0].id]
    assert double.status == "fail" and double.metrics["double_hits"] > 100 and double.metrics["holes"] == 0
    assert [s["sample"] for s in double.evidence["samples"]] == [0, 3]
    extra = inclusive["conformance"][ties[0].id]
    assert extra.status == "fail" and extra.metrics["missing"] == 0
    assert extra.metrics["extra"] == extra.metrics["exact_ties"] > 0  # every extra sample lies on an edge


def test_the_area_checks_judge_area_coverage_only():
    for check in checks(only=AREA_CHECKS):
        assert check.coverage_kinds == frozenset({"area"}) and check.needs_convention
    judged_kinds = {check.name for check in checks(coverage_kind="multisample")}
    assert not AREA_CHECKS & judged_kinds


@pytest.mark.parametrize("rasterizer", [MirroredPattern(), SwappedSampleBits(), InclusiveSampleTies()], ids=lambda r: r.name)
def test_the_multisample_known_bads_are_well_formed(rasterizer):
    case = quick()["watertight/fan-8/centre"]
    results = judged(rasterizer, [case], {"hygiene"})
    assert results["hygiene"][case.id].status == "pass"


# -- accuracy on every motion frame, and on triangles over 2,048 px tall (issue 29) ------------

TALL = "float/tall-triangles-2048px"
TALL_MOTION = "motion/tall-triangle/translate-x-1/64"


def _errors_by_row(rasterizer: Any, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """(y, |alpha - exact area| in levels) of every (triangle, pixel) either side covers."""
    width, height = scene.width, scene.height
    got, want = rasterizer.rasterize(scene), exact_coverage(scene, rasterizer.convention)
    keys, values = [], []
    for cov in (got, want):
        t, x, y = cov.pixels()
        keys.append((t * height + y) * width + x)
        values.append(cov.alpha)
    union = np.union1d(*keys)
    alpha, area = np.zeros(union.size), np.zeros(union.size)
    alpha[np.searchsorted(union, keys[0])] = values[0]
    area[np.searchsorted(union, keys[1])] = values[1]
    return union // width % height, np.abs(alpha - area) * 255


def test_an_edge_stepped_in_float32_drifts_down_the_tall_triangles_and_fails_accuracy():
    """Far right, each row's float32 step rounds the same way: the error is about a
    level (a rounding) near the top and tens of levels near the bottom, where accuracy finds it (no
    near tie); the built-in anti-aliasers pass the same case."""
    case = quick()[TALL]
    assert isinstance(case, Case) and np.ptp(triangles(case.scene).positions[..., 1], axis=1).min() >= 2048
    bad = Float32EdgeStepping()
    verdict = judged(bad, [case], {"accuracy"})["accuracy"][TALL]
    assert verdict.status == "fail" and verdict.metrics["max_error"] * 255 >= 10 and verdict.metrics["near_tie"] == 0
    assert all(p["y"] > 1024 for p in verdict.evidence["pixels"][:10])
    from harness.diagnose.signatures import signature

    # issue 29: the cause named from the facts, drift down the triangle
    assert signature(verdict, case, bad.convention).key == "accuracy|drift|none", verdict.message
    assert "error growing down the triangle" in verdict.message
    y, error = _errors_by_row(bad, triangles(case.scene))
    assert error[y < 64].max() < 1.5 and error[y > 2000].max() >= 10
    from rasterizers.area_scanline import AreaScanline
    from rasterizers.supersample import Supersampler4

    for good in (AreaScanline(), Supersampler4()):
        assert judged(good, [case], {"accuracy"})["accuracy"][TALL].status == "pass", good.name


def test_accuracy_judges_every_frame_of_a_motion_case_and_names_the_failing_ones():
    """The tall sliver's drift fails accuracy in its frames (popping alone saw only pops);
    a bias of two levels fails every frame of a small triangle's; the exact area in 8
    bits passes every frame. Frames are named, counted and plotted."""
    full = quick()[TALL_MOTION]
    assert isinstance(full, MotionCase)
    tall = MotionCase(full.id, full.frames[:6])  # six of its 129 frames: the drift is in each
    verdict = judged(Float32EdgeStepping(), [tall], {"accuracy"})["accuracy"][tall.id]
    assert verdict.status == "fail" and verdict.metrics["frames"] == 6 and verdict.metrics["failing_frames"] == 6
    assert verdict.metrics["max_error"] * 255 >= 10 and verdict.message.startswith("6 of 6 frames fail (first: frame 0)")
    worst = verdict.evidence["frame"]
    assert f"frame {worst}:" in verdict.message and all(p["frame"] == worst for p in verdict.evidence["pixels"])
    assert len(verdict.evidence["series"]["max_error_levels"]) == 6 and verdict.evidence["failing_frames"] == list(range(6))
    small = cases("motion/triangle/translate-x-1/16")
    biased = judged(BiasedArea(), small, {"accuracy"})["accuracy"]["motion/triangle/translate-x-1/16"]
    frames = len(small[0].frames)  # type: ignore[union-attr]
    assert biased.status == "fail" and biased.metrics["failing_frames"] == frames
    assert 2.0 <= biased.metrics["max_error"] * 255 <= 2.5 + 1e-9  # two levels over, and the rounding
    exact = judged(Quantised8Bit(), [tall, *small], {"accuracy"})["accuracy"]
    assert {r.status for r in exact.values()} == {"pass"} and exact[tall.id].metrics["frames"] == 6
    assert exact[tall.id].message.startswith("all 6 frames within the tolerance")


def test_the_tall_fuzz_family_catches_float32_stepping() -> None:
    """On the first tall fuzz scenes the float32 stepper fails accuracy every time, and
    the reference passes."""
    from cases.fuzz import generate
    from rasterizers.area_scanline import AreaScanline

    tall: list[Case | MotionCase] = [generate("tall", 5, index) for index in range(3)]
    assert {r.status for r in judged(AreaScanline(), tall, {"accuracy"})["accuracy"].values()} == {"pass"}
    assert {r.status for r in judged(Float32EdgeStepping(), tall, {"accuracy"})["accuracy"].values()} == {"fail"}
