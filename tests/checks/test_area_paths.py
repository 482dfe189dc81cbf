"""accuracy judges path scenes under area conventions: the exact area quantised to 8 bits
passes, the known-bad AA path fillers fail, for the reason they carry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.checks.area import accuracy
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene
from harness.oracle.coverage import exact_coverage
from tests.known_bad.aa_paths import EvenOddForNonzeroArea, SignedAreaPathFiller

AREA = Convention(coverage="area")


def _star(cx: float, cy: float, r: float) -> list[list[float]]:
    return [[cx + r * math.sin(4 * math.pi * k / 5), cy - r * math.cos(4 * math.pi * k / 5)] for k in range(5)]


def _scenes(rule: str) -> list[PathScene]:
    squares = [[[0.375, 0.25], [4.625, 0.25], [4.625, 3.75], [0.375, 3.75]],
               [[2.125, 1.3125], [7.4375, 1.3125], [7.4375, 6.625], [2.125, 6.625]]]
    t = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    ring = [np.stack([4 + 3.5 * np.cos(t), 4 + 3.5 * np.sin(t)], 1), np.stack([4 + 2 * np.cos(t), 4 + 2 * np.sin(t)], 1)]
    return [PathScene.from_paths(8, 8, [squares], rule), PathScene.from_paths(10, 10, [[_star(5, 5, 4.7)]], rule),
            PathScene.from_paths(8, 8, [ring], rule)]


def _quantised(scene: PathScene) -> Coverage:
    cov = exact_coverage(scene, AREA)
    assert cov.alpha is not None
    return Coverage(cov.primitive, cov.y, cov.x0, cov.x1, alpha=np.rint(cov.alpha * 255) / 255)


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_exact_area_on_levels_passes(rule: str) -> None:
    for k, scene in enumerate(_scenes(rule)):
        case = Case(f"aa-paths/{k}", scene)
        verdict = accuracy(case, _quantised(scene), exact_coverage(scene, AREA), AREA)
        assert verdict.status == "pass", verdict.message
        assert verdict.metrics["max_error"] <= 0.5 / 255


def test_signed_area_filler_fails_on_overlaps_and_evenodd() -> None:
    bad = SignedAreaPathFiller()
    for rule in ("nonzero", "evenodd"):
        scene = _scenes(rule)[1]  # the pentagram: winding 2 in the centre, its edges crossing pixels
        verdict = accuracy(Case("aa-paths/star", scene), bad.rasterize(scene), exact_coverage(scene, AREA), AREA)
        assert verdict.status == "fail", verdict.message
        assert "beyond" in verdict.message
    # right where the winding is 0 or 1 (the ring's hole wound against it)
    ring = _scenes("nonzero")[2]
    ring = PathScene(ring.width, ring.height, ring.vertices[np.r_[0:48, 95:47:-1]], ring.contour_sizes, ring.contour_path)
    verdict = accuracy(Case("aa-paths/ring", ring), bad.rasterize(ring), exact_coverage(ring, AREA), AREA)
    assert verdict.status == "pass", verdict.message


def test_evenodd_for_nonzero_fails_on_nonzero_overlaps_only() -> None:
    bad = EvenOddForNonzeroArea()
    scene = _scenes("nonzero")[0]
    verdict = accuracy(Case("aa-paths/squares", scene), bad.rasterize(scene), exact_coverage(scene, AREA), AREA)
    assert verdict.status == "fail" and verdict.metrics["max_error"] >= 0.99
    scene = _scenes("evenodd")[0]
    verdict = accuracy(Case("aa-paths/squares", scene), bad.rasterize(scene), exact_coverage(scene, AREA), AREA)
    assert verdict.status == "pass", verdict.message


def test_a_float_rounding_at_a_level_boundary_is_a_near_tie() -> None:
    from harness.checks.records import Tolerance

    # 1 - 0.3 is 178.5 levels in float: rounding the float area may take either level
    squares = [[[0.3, 0.2], [4.6, 0.2], [4.6, 3.7], [0.3, 3.7]], [[2.1, 1.3], [7.4, 1.3], [7.4, 6.6], [2.1, 6.6]]]
    scene = PathScene.from_paths(8, 8, [squares])
    oracle = exact_coverage(scene, AREA)
    verdict = accuracy(Case("aa-paths/near", scene), _quantised(scene), oracle, AREA)
    assert verdict.status == "pass" and verdict.metrics["near_tie"] > 0, verdict.message
    strict = accuracy(Case("aa-paths/near", scene), _quantised(scene), oracle, AREA, Tolerance(mode="strict"))
    assert strict.status == "fail" and "near ties" in strict.message
    # on a lattice case no rounding excuses it
    lattice = accuracy(Case("aa-paths/near", scene, lattice=True), _quantised(scene), oracle, AREA)
    assert lattice.status == "fail"


def test_a_non_finite_path_left_open_by_the_float_verdict_is_decided_as_covering_nothing() -> None:
    """A NaN path covers nothing: a rasterizer's alpha exactly at the tolerance from 0 is
    left open by the float verdict, and the exact decision must not raise on the NaN."""
    nan_square = np.array([[1.0, 1.0], [3.0, 1.0], [3.0, math.nan], [1.0, 3.0]])
    scene = PathScene.from_paths(4, 4, [[nan_square]])
    drawn = Coverage(np.array([0]), np.array([1]), np.array([1]), np.array([3]), alpha=np.array([0.0, 0.0]) + 128 / 255)
    result = accuracy(Case("paths/nan", scene), drawn, exact_coverage(scene, Convention(coverage="area")),
                      Convention(coverage="area", tolerance=128 / 255))
    assert result.status == "pass", result.message
    beyond = Coverage(np.array([0]), np.array([1]), np.array([1]), np.array([3]), alpha=np.array([192.0, 128.0]) / 255)
    assert accuracy(Case("paths/nan", scene), beyond, exact_coverage(scene, Convention(coverage="area")),
                    Convention(coverage="area", tolerance=128 / 255)).status == "fail"


def test_a_fill_rule_drawn_other_than_asked_is_named_as_such() -> None:
    """Issue 34 point 4: an AA path filler drawing even-odd where nonzero is asked fails
    accuracy with the cause "fill-rule" (the convention's part), not a vague alpha error;
    one whose alphas are wrong in another way is not called a fill-rule error."""
    from harness.diagnose.signatures import classify_accuracy

    bad = EvenOddForNonzeroArea()
    scene = _scenes("nonzero")[0]
    case = Case("aa-paths/squares", scene)
    verdict = accuracy(case, bad.rasterize(scene), exact_coverage(scene, AREA), AREA)
    assert verdict.status == "fail" and verdict.evidence["alpha_cause"] == "fill-rule", verdict.message
    assert "fill rule drawn is not the one asked" in verdict.message
    assert classify_accuracy(verdict, case, AREA) == ("fill-rule", "fill-rule")
    signed = SignedAreaPathFiller()  # wrong where contours overlap, under either rule
    other = accuracy(case, signed.rasterize(scene), exact_coverage(scene, AREA), AREA)
    assert other.status == "fail" and other.evidence.get("alpha_cause") != "fill-rule"
