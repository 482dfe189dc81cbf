"""The area checks on anti-aliased paths and lines beyond accuracy (issue 34, point 4):
popping under sub-pixel motion of path and line frames, invariance under reversal judged
exactly, seams on path partitions, and the fill rule drawn as asked -- each passing the
exact area rounded to 8 bits and failing its known-bad filler or drawer."""

from __future__ import annotations

import functools
from dataclasses import replace
from fractions import Fraction
from typing import Any

import numpy as np
import pytest

from cases.motion import aa_motion_cases
from cases.paths import glyph_d, path_cases, star
from harness.checks.area import accuracy
from harness.checks.area_popping import path_motion_bound, popping
from harness.checks.area_seams import seams
from harness.checks.invariance import ORIENTATION_VARIANTS, area_invariance, invariance_variants, near_level_boundary
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, PathScene
from harness.oracle.coverage import exact_coverage
from harness.oracle.path_area import exact_path_area, path_area_coverage
from tests.known_bad.aa_lines import DirectionalAALines, ExactAALines
from tests.known_bad.aa_paths import (
    BiasedPartialFiller,
    EvenOddForNonzeroArea,
    ExactAreaPathFiller,
    OrientationRoundedFiller,
    QuarterPixelPathFiller,
)

AREA = Convention(coverage="area")


@functools.cache
def _quick_paths() -> tuple[Case, ...]:
    return tuple(path_cases(0))


def _motion(kind: type) -> list[MotionCase]:
    return [c for c in aa_motion_cases(0) if isinstance(c.frames[0], kind)]


def _pops(rasterizer: Any, case: MotionCase) -> Any:
    conv = rasterizer.convention
    return popping(case.id, list(case.frames), [rasterizer.rasterize(f) for f in case.frames],
                   [exact_coverage(f, conv) for f in case.frames], conv)


# -- popping ----------------------------------------------------------------------------------


def test_the_motion_suite_holds_path_and_line_frames() -> None:
    paths, lines = _motion(PathScene), _motion(LineScene)
    assert {c.id for c in paths} == {"motion/path-glyph-d/translate-diagonal-1/64/nonzero",
                                     "motion/path-star-5-2/rotate-0.05deg/nonzero"}
    assert [c.id for c in lines] == ["motion/aa-lines/slide-x-1/64/w1"]
    full = aa_motion_cases(0, full=True)
    assert len(full) > 20 and {c.id for c in paths + lines} <= {c.id for c in full}


def test_popping_passes_the_exact_area_on_path_and_line_frames() -> None:
    for case in _motion(PathScene):
        verdict = _pops(ExactAreaPathFiller(), case)
        assert verdict.status == "pass", verdict.message
        assert verdict.metrics["alpha_jumps"] == 0 and verdict.metrics["beyond_motion"] == 0
    for case in _motion(LineScene):
        verdict = _pops(ExactAALines(), case)
        assert verdict.status == "pass", verdict.message


def test_popping_catches_a_filler_that_snaps_to_quarter_pixels() -> None:
    """Its alphas stand still, then jump: beyond twice the tolerance of the exact area's
    step, and beyond what a motion of 1/64 px allows any area at all."""
    for case in _motion(PathScene):
        verdict = _pops(QuarterPixelPathFiller(), case)
        assert verdict.status == "fail", verdict.message
        assert verdict.metrics["alpha_jumps"] > 0 and verdict.metrics["beyond_motion"] > 0
        assert "beyond what the motion allows any area" in verdict.message
        worst = verdict.evidence["beyond_motion"][0]
        assert abs(worst["d_alpha"]) > worst["bound"] + 2 / 255 and worst["bound"] < 0.1


def test_popping_judges_a_declared_snapping_against_its_own_model() -> None:
    """The same snapping declared (2 sub-pixel bits) is the model's own step: no alpha
    jumps, and none beyond the motion of the snapped vertices (a quarter pixel at a time)."""
    declared = Convention(coverage="area", subpixel_bits=2)

    class Snapping:
        convention = declared

        def rasterize(self, scene: PathScene) -> Coverage:
            cov = path_area_coverage(scene, declared)
            assert cov.alpha is not None
            return Coverage(cov.primitive, cov.y, cov.x0, cov.x1, alpha=np.rint(cov.alpha * 255) / 255)

    case = _motion(PathScene)[0]
    verdict = _pops(Snapping(), case)
    assert verdict.status == "pass", verdict.message
    assert verdict.metrics["alpha_jumps"] == 0 and verdict.metrics["beyond_motion"] == 0


@pytest.mark.parametrize("seed", range(6))
def test_the_motion_bound_holds_exactly(seed: int) -> None:
    """path_motion_bound against the rational areas of both frames: a random path moved by
    a random step of at most 1/8 px (every vertex its own way) changes its exact area in
    every pixel by no more than the bound."""
    rng = np.random.default_rng(seed)
    contours = [rng.uniform(0.5, 7.5, (int(rng.integers(3, 7)), 2)) for _ in range(2)]
    if seed % 2:
        contours = glyph_d(rng.uniform(0.5, 1.0, 2), 6.5, 3)
    before = PathScene.from_paths(8, 8, [contours], "evenodd" if seed % 3 == 0 else "nonzero")
    after = before.with_coordinates(before.vertices + rng.uniform(-1 / 16, 1 / 16, before.vertices.shape))
    for x in range(8):
        for y in range(8):
            change = abs(exact_path_area(after.contours_of(0), after.fill_rule, x, y)
                         - exact_path_area(before.contours_of(0), before.fill_rule, x, y))
            bound = path_motion_bound(before, after, AREA, 0, x, y)
            assert change <= Fraction(bound), (x, y, float(change), bound)


# -- invariance: the same scene up to orientation gives the same alphas ------------------------


def _invariance(rasterizer: Any, case: Case, exact: frozenset[str] = ORIENTATION_VARIANTS) -> Any:
    variants = invariance_variants(case)
    if isinstance(case.scene, LineScene):
        from harness.checks.invariance import area_line_variants

        variants += area_line_variants(case.scene)
    answers = [(name, index, rasterizer.rasterize(scene)) for name, scene, index in variants]
    near = near_level_boundary(case, exact_coverage(case.scene, rasterizer.convention), rasterizer.convention)
    return area_invariance(case, rasterizer.rasterize(case.scene), answers, rasterizer.convention.level_step,
                           exact=exact, near=near)


def _glyph_cases() -> list[Case]:
    return [c for c in _quick_paths() if c.id.startswith(("paths/glyph/", "paths/star-", "paths/ring/"))]


def test_reversal_leaves_the_exact_area_unchanged() -> None:
    cases = _glyph_cases()
    assert len(cases) >= 6
    for case in cases:
        verdict = _invariance(ExactAreaPathFiller(), case)
        assert verdict.status == "pass", (case.id, verdict.message)
        assert "exactly under reverse-every-contour" in verdict.message


def test_a_rounding_that_follows_the_winding_is_caught_exactly() -> None:
    """AGG's floor for one winding and ceiling for the other: within its declared one-level
    tolerance everywhere (accuracy passes), and within one level of itself reversed (the
    one-level rule of the other variants would pass it), but not the same alphas."""
    bad: Any = OrientationRoundedFiller()
    for case in _glyph_cases():
        assert accuracy(case, bad.rasterize(case.scene), exact_coverage(case.scene, bad.convention),
                        bad.convention).status == "pass", case.id
        verdict = _invariance(bad, case)
        assert _invariance(bad, case, exact=frozenset()).status == "pass", case.id
        levels = path_area_coverage(case.scene, AREA).alpha * 255  # type: ignore[arg-type, operator]
        if np.any(levels != np.rint(levels)):  # a pixel between levels: floor and ceiling differ
            assert verdict.status == "fail" and verdict.metrics["reverse-every-contour_differences"] > 0, case.id
        else:  # whole pixels and exact levels only (a lattice ring filled whole)
            assert verdict.status == "pass", case.id


def _line_cases() -> list[Case]:
    rng = np.random.default_rng(34)
    a, b = rng.uniform(2, 30, (16, 2)), rng.uniform(2, 30, (16, 2))
    strip = np.array([[2.2, 3.1], [29.3, 9.5], [4.25, 28.7], [30.1, 30.4]])
    return [Case("aa-lines/random-w1", LineScene.from_segments(32, 32, a, b, 1.0)),
            Case("aa-lines/strip-w2.5", LineScene.from_strips(32, 32, [strip, strip[::-1] + 0.3], 2.5))]


def test_reversed_strokes_are_the_same_strokes() -> None:
    for case in _line_cases():
        good = _invariance(ExactAALines(), case)
        assert good.status == "pass" and "exactly under reverse-segments" in good.message, good.message
        bad: Any = DirectionalAALines()
        assert accuracy(case, bad.rasterize(case.scene), exact_coverage(case.scene, bad.convention),
                        bad.convention).status == "pass"
        verdict = _invariance(bad, case)
        assert verdict.status == "fail" and verdict.metrics["reverse-segments_differences"] > 0, verdict.message


def test_a_one_level_difference_at_a_rounding_boundary_is_a_near_tie() -> None:
    """An area within float rounding of a level's midpoint may round either way: a
    rasterizer rounding it up one way and down reversed is excused there, and not
    elsewhere; on a lattice case only an area exactly on the midpoint (accuracy lets it
    round either way), no geometry moved by rounding."""
    # pixel (1, 1) half covered: 127.5 levels, a midpoint; pixel (2, 1) a quarter: 63.75
    square = PathScene.from_paths(4, 4, [[np.array([[1.5, 1.0], [2.25, 1.0], [2.25, 2.0], [1.5, 2.0]])]])
    case = Case("aa-paths/midpoint", square)
    oracle = exact_coverage(square, AREA)
    near = near_level_boundary(case, oracle, AREA)
    key = (0 * 4 + 1) * 4 + 1  # path 0, pixel (1, 1)
    assert near(np.array([key])).tolist() == [True]
    assert near(np.array([(0 * 4 + 1) * 4 + 2])).tolist() == [False]  # a quarter of a level from the nearest
    on_lattice = near_level_boundary(replace(case, lattice=True), oracle, AREA)
    assert on_lattice(np.array([key, (0 * 4 + 1) * 4 + 2])).tolist() == [True, False]


# -- seams on path partitions -----------------------------------------------------------------


def _partitions() -> list[Case]:
    return [c for c in _quick_paths() if c.family == "path-partitions"]


def test_the_path_partitions_reach_area_rasterizers_and_the_exact_area_has_no_seam() -> None:
    cases = _partitions()
    assert {"path-partitions/pie-8/float/nonzero", "path-partitions/voronoi-12/float/evenodd"} <= {c.id for c in cases}
    good = ExactAreaPathFiller()
    for case in cases:
        verdict = seams(case, good.rasterize(case.scene), AREA, exact_coverage(case.scene, AREA))
        assert verdict.status == "pass", (case.id, verdict.message)
        assert verdict.metrics["inside_pixels"] > 100


def test_seams_catch_a_filler_biased_on_partial_pixels() -> None:
    bad: Any = BiasedPartialFiller()
    for case in _partitions():
        verdict = seams(case, bad.rasterize(case.scene), bad.convention, exact_coverage(case.scene, AREA))
        assert verdict.status == "fail" and verdict.metrics["seam_pixels"] > 0, case.id


# -- the fill rule drawn as asked -------------------------------------------------------------


def test_the_other_fill_rule_fails_accuracy_and_is_exactly_that_rule() -> None:
    """EvenOddForNonzeroArea fails accuracy on every quick path case whose rules differ
    under area coverage (and only there: its answer is the even-odd area to the level),
    and judged against the other rule's area it passes -- what names the fill rule."""
    bad = EvenOddForNonzeroArea()
    failed = 0
    for case in _quick_paths():
        if case.family != "paths" or not case.id.endswith("/nonzero") or case.refusable:
            continue
        scene = case.scene
        assert isinstance(scene, PathScene)
        answer = bad.rasterize(scene)
        verdict = accuracy(case, answer, exact_coverage(scene, AREA), AREA)
        flipped = scene.with_fill_rule("evenodd")
        mine, other = path_area_coverage(scene, AREA), path_area_coverage(flipped, AREA)
        rules_differ = mine.x0.size != other.x0.size or not np.array_equal(np.asarray(mine.alpha), np.asarray(other.alpha))
        if rules_differ:
            failed += verdict.status == "fail"
        else:
            assert verdict.status == "pass", case.id
        assert accuracy(Case(case.id, flipped), answer, exact_coverage(flipped, AREA), AREA).status == "pass", case.id
    assert failed >= 5


def test_a_star_outline_is_filled_under_both_rules_by_the_exact_filler() -> None:
    """The control for the fill rule: the exact filler passes accuracy under both rules on
    the glyph and the pentagram, which differ between the rules."""
    good = ExactAreaPathFiller()
    for rule in ("nonzero", "evenodd"):
        scene = PathScene.from_paths(32, 32, [glyph_d((4.3, 4.1), 23.0, 10), [star(5, 2, (16.2, 15.7), 12.5, 0.3)]], rule)
        verdict = accuracy(Case("aa-paths/rules", scene), good.rasterize(scene), exact_coverage(scene, AREA), AREA)
        assert verdict.status == "pass", verdict.message


# -- through the runner: each known-bad caught by its check on the suite's own cases ----------

# known-bad -> (the checks that must flag it, the quick suite's case ids where it shows)
AA_TABLE: dict[str, tuple[set[str], tuple[str, ...]]] = {
    "bad_quarter_pixel_path_filler": ({"popping", "accuracy"}, ("motion/path-glyph-d/translate-diagonal-1/64/nonzero",)),
    "bad_orientation_rounded_filler": ({"invariance"}, ("paths/glyph/d-curves/float/nonzero",
                                                         "paths/glyph/d-curves/float/evenodd")),
    "bad_biased_partial_filler": ({"seams", "accuracy"}, ("path-partitions/pie-8/float/nonzero",)),
    "bad_aa_lines_directional": ({"invariance"}, ("lines/octants/centres",)),
    "bad_evenodd_for_nonzero_area": ({"accuracy"}, ("paths/glyph/d-curves/float/nonzero",)),
}


@pytest.mark.parametrize("name", list(AA_TABLE))
def test_each_known_bad_is_caught_by_its_check_through_the_runner(name: str) -> None:
    from cases.suites import suite
    from harness import run_suite
    from tests.known_bad.catalogue import KNOWN_BAD

    wanted, ids = AA_TABLE[name]
    cases = [c for c in suite("quick") if c.id in ids]
    assert len(cases) == len(ids)
    results = run_suite([KNOWN_BAD[name]], cases=cases, identify=False, repros=False, isolate=False, only=wanted)
    failed = {r.check for r in results if r.status == "fail"}
    assert wanted <= failed, [(r.case, r.check, r.status, r.message) for r in results]


def test_the_exact_references_pass_every_check_on_the_aa_cases_through_the_runner() -> None:
    """The exact area rounded to 8 bits (paths) and the exact strokes (lines) pass every
    check that judges them on the quick suite's glyph, stroke, partition and motion cases."""
    from cases.suites import suite
    from harness import run_suite

    picked = [c for c in suite("quick") if c.id.startswith(("paths/glyph/", "paths/stroke/", "paths/sliver/",
                                                            "path-partitions/", "motion/path-", "motion/aa-lines/",
                                                            "lines/octants/"))]
    assert len(picked) >= 10
    results = run_suite([ExactAreaPathFiller(), ExactAALines()], cases=picked, identify=False, repros=False, isolate=False)
    bad = [(r.rasterizer, r.case, r.check, r.message) for r in results if r.status in ("fail", "error")]
    assert not bad, bad[:5]
    assert {"accuracy", "invariance", "popping", "seams"} <= {r.check for r in results}


def test_a_half_level_tie_rounded_either_way_by_direction_is_no_change_even_on_a_lattice():
    """Mesa's smooth lines round an area of exactly 1/2 to 127 one way and 128 the other:
    accuracy lets an area exactly halfway between two levels round to either, so the exact
    reversal does too, on lattice cases and in strict mode; rounding that differs by
    direction anywhere else is still a change (DirectionalAALines)."""
    import numpy as np

    from cases.suites import suite
    from harness import run_suite
    from harness.contract.conventions import Convention, LineRule
    from harness.contract.coverage import Coverage
    from harness.oracle.area_lines import line_pixel_areas
    from tests.known_bad.aa_lines import DirectionalAALines

    class TiesByDirection:
        name = "ties_by_direction"
        convention = Convention(coverage="area", line=LineRule("rectangle"))
        scene_kinds = ("lines",)
        interpolates = False

        def rasterize(self, scene: LineScene) -> Coverage:
            a, b = scene.segments()
            s, x, y, area = line_pixel_areas(np.stack([a, b], axis=1), scene.line_width, "butt", scene.width,
                                             scene.height)
            forward = (b - a)[:, 0] > 0
            scaled = np.clip(area, 0.0, 1.0) * 255.0
            level = np.where(forward[s], np.floor(scaled + 0.5), np.ceil(scaled - 0.5)) if s.size else scaled
            keep = level > 0
            return Coverage.from_pixels(s[keep], x[keep], y[keep], alpha=level[keep] / 255.0)

    cases = [c for c in suite("quick") if c.id == "lines/octants/centres" and isinstance(c, Case)]
    assert cases and cases[0].lattice
    tied = run_suite([TiesByDirection()], cases=cases, isolate=False, identify=False, repros=False, only={"invariance"})
    assert [r.status for r in tied] == ["pass"], [r.message for r in tied]
    bad = run_suite([DirectionalAALines()], cases=cases, isolate=False, identify=False, repros=False, only={"invariance"})
    assert [r.status for r in bad] == ["fail"]
