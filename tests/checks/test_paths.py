"""The checks on path scenes: conformance per fill rule, triangulation equivalence,
invariance under the path variants, watertightness of path partitions, and the runner
handing each rasterizer only the scene kinds it takes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.checks.paths import simple_polygon_triangles, triangulated
from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage


def _star(cx: float, cy: float, r: float, n: int = 5, step: int = 2) -> np.ndarray:
    return np.array([[cx + r * math.sin(k * step * 2 * math.pi / n), cy - r * math.cos(k * step * 2 * math.pi / n)]
                     for k in range(n)])


RING_SAME = [[[1, 1], [11, 1], [11, 11], [1, 11]], [[4, 4], [8, 4], [8, 8], [4, 8]]]  # both clockwise on screen
ARROW = [[1.5, 1.5], [9.5, 1.5], [9.5, 9.5], [5.5, 4.5], [1.5, 9.5]]  # concave; samples on its sides


class OracleFiller:
    """Fills exactly as the oracle says, paths and triangles; knobs make it wrong."""

    scene_kinds: tuple[str, ...] = ("triangles", "paths")
    interpolates = False

    def __init__(self, name: str = "oracle_filler", convention: Convention = Convention(), triangles: Convention | None = None,
                 positive_only: bool = False, kinds: tuple[str, ...] = ("triangles", "paths"),
                 fill_rules: tuple[str, ...] = ("nonzero", "evenodd")) -> None:
        self.name, self.convention, self._triangles = name, convention, triangles or convention
        self._positive_only, self.scene_kinds = positive_only, kinds
        if "paths" in kinds:  # fill rules without path scenes contradict each other (harness.contract.declarations)
            self.fill_rules = fill_rules
        self.seen: list[str] = []

    def rasterize(self, scene: Scene | PathScene) -> Coverage:
        self.seen.append(scene.kind if not isinstance(scene, PathScene) else f"paths:{scene.fill_rule}")
        if not isinstance(scene, PathScene):
            return exact_coverage(scene, self._triangles)
        if not self._positive_only or scene.fill_rule != "nonzero":
            return exact_coverage(scene, self.convention)
        # the bug: nonzero taken as "winding > 0" -- contours wound one way fill, the other way not
        keep = []
        for p in range(len(scene)):
            contours = scene.contours_of(p)
            area = sum(float(np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1])) for c in contours)
            if area > 0:  # clockwise on screen (y down): positive winding under our count
                keep.append(p)
        cov = exact_coverage(scene, self.convention)
        return cov.take(np.flatnonzero(np.isin(cov.primitive, keep)))


def _results(rasterizer, cases, only=None):
    return run_suite([rasterizer], cases=cases, isolate=False, identify=False, repros=False, only=only)


def _status(results, check):
    return {r.case: r.status for r in results if r.check == check}


CASES = [
    Case("paths/pentagram/nonzero", PathScene.from_paths(12, 12, [[_star(6, 6, 5)]], "nonzero")),
    Case("paths/pentagram/evenodd", PathScene.from_paths(12, 12, [[_star(6, 6, 5)]], "evenodd")),
    Case("paths/ring-same/nonzero", PathScene.from_paths(12, 12, [RING_SAME], "nonzero"), lattice=True),
    Case("paths/arrow/nonzero", PathScene.from_paths(12, 12, [[ARROW]], "nonzero"), lattice=True),
]


def test_the_oracle_filler_passes_every_path_check_and_a_wrong_rule_fails_conformance() -> None:
    good = _results(OracleFiller(), CASES)
    checks = {r.check for r in good}
    assert {"hygiene", "conformance", "invariance", "triangulation"} <= checks
    assert all(r.status in ("pass", "skip") for r in good), [r for r in good if r.status not in ("pass", "skip")]
    assert _status(good, "triangulation")["paths/arrow/nonzero"] == "pass"

    class EvenOddAlways(OracleFiller):
        def rasterize(self, scene):
            return super().rasterize(scene.with_fill_rule("evenodd") if isinstance(scene, PathScene) else scene)

    bad = _status(_results(EvenOddAlways("evenodd_always"), CASES, {"conformance"}), "conformance")
    assert bad["paths/pentagram/nonzero"] == "fail" and bad["paths/ring-same/nonzero"] == "fail"
    assert bad["paths/pentagram/evenodd"] == "pass"


def test_triangulation_fails_when_paths_and_triangles_follow_different_tie_rules() -> None:
    split = OracleFiller("split_ties", Convention(), triangles=Convention(tie="bottom-right"))
    results = _results(split, CASES, {"triangulation"})
    verdict = {r.case: r for r in results}
    arrow = verdict["paths/arrow/nonzero"]
    assert arrow.status == "fail" and arrow.metrics["triangles_only"] > 0 and arrow.evidence["triangles_only"]
    # its triangle answers alone, against the triangle oracle, are exact: only the tie of the two fills differs
    assert verdict["paths/pentagram/nonzero"].status == "skip"  # a pentagram is not simple


def test_invariance_catches_a_winding_sign_bug_on_contour_reversal() -> None:
    bug = OracleFiller("positive_only", positive_only=True)
    square = [[[2, 2], [9, 2], [9, 9], [2, 9]]]
    case = Case("paths/square/nonzero", PathScene.from_paths(12, 12, [square], "nonzero"), lattice=True)
    results = {r.check: r for r in _results(bug, [case], {"invariance"})}
    assert results["invariance"].status == "fail"
    assert results["invariance"].metrics["reverse-every-contour_differences"] > 0
    assert _results(OracleFiller(), [case], {"invariance"})[0].status == "pass"


def test_path_partitions_are_judged_watertight() -> None:
    # a 2 x 2 grid of quads sharing exact vertices, each its own path
    xs, ys = [1.0, 4.25, 9.0], [1.0, 5.5, 9.0]
    cells = [[[[xs[i], ys[j]], [xs[i + 1], ys[j]], [xs[i + 1], ys[j + 1]], [xs[i], ys[j + 1]]]] for i in range(2)
             for j in range(2)]
    region = np.array([[1.0, 1.0], [9.0, 1.0], [9.0, 9.0], [1.0, 9.0]])
    case = Case("path-partitions/grid-2x2", PathScene.from_paths(10, 10, cells, "nonzero"), lattice=True, region=region)
    assert _results(OracleFiller(), [case], {"watertight"})[0].status == "pass"

    class Inclusive(OracleFiller):  # samples on shared edges drawn by both cells
        def rasterize(self, scene):
            cov = super().rasterize(scene)
            extra = exact_coverage(scene, Convention(tie="bottom-right"))
            return Coverage.concat([cov, extra]).canonical() if isinstance(scene, PathScene) else cov

    moved = Case(case.id, PathScene.from_paths(10, 10, [[[[x + 0.25, y + 0.0] for x, y in c[0]]] for c in cells], "nonzero"),
                 lattice=True, region=region + [0.25, 0.0])
    result = _results(Inclusive("inclusive"), [moved], {"watertight"})[0]
    assert result.status == "fail" and result.metrics["double_hits"] > 0
    assert "paths" in result.evidence["blame"][0]


def test_the_runner_hands_each_rasterizer_only_the_scene_kinds_and_fill_rules_it_takes() -> None:
    triangle = Case("lattice/one", Scene(8, 8, [[[0, 0], [8, 0], [0, 8]]]), lattice=True)
    only_triangles = OracleFiller("triangles_only", kinds=("triangles",))
    results = _results(only_triangles, [triangle, *CASES])
    assert {r.case for r in results} == {"lattice/one"} and only_triangles.seen and "paths:nonzero" not in only_triangles.seen
    evenodd = OracleFiller("evenodd_only", fill_rules=("evenodd",))
    results = _results(evenodd, CASES)
    assert {r.case for r in results} == {"paths/pentagram/evenodd"}


def test_ear_clipping_triangulates_exactly_and_refuses_what_is_not_simple() -> None:
    triangles = simple_polygon_triangles(np.array(ARROW, dtype=float))
    assert triangles is not None and triangles.shape == (3, 3, 2)
    area = sum(abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2 for a, b, c in triangles)
    assert area == 8 * 8 - 8 * 5 / 2  # the square less the notch
    assert simple_polygon_triangles(_star(6, 6, 5)) is None  # self-intersecting
    assert simple_polygon_triangles(np.array([[0, 0], [2, 0], [4, 0], [2, 2]], dtype=float)) is None  # collinear
    assert simple_polygon_triangles(np.array([[0, 0], [1, 0]], dtype=float)) is None
    scene = PathScene.from_paths(12, 12, [[ARROW], RING_SAME, [_star(6, 6, 5)]])
    made = triangulated(scene)
    assert made is not None and made[2].tolist() == [0]


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_path_cases_round_trip_and_the_oracle_equals_the_triangle_oracle_on_triangles(rule: str) -> None:
    triangles = np.array([[[0.5, 0.25], [7.75, 3.0], [2.0, 7.5]], [[1, 1], [6, 1], [1, 6]]])
    paths = PathScene.from_paths(8, 8, [[t] for t in triangles], rule)
    for convention in (Convention(), Convention(tie="bottom-right", sample=(0.0, 0.0)), Convention(samples=4)):
        assert exact_coverage(paths, convention) == exact_coverage(Scene(8, 8, triangles), convention)
    case = Case("paths/two", paths)
    back = case_from_json(case_to_json(case))
    assert isinstance(back, Case) and isinstance(back.scene, PathScene) and back.scene.fill_rule == rule
    assert np.array_equal(back.scene.vertices, paths.vertices) and np.array_equal(back.scene.contour_path, paths.contour_path)


def test_path_scenes_refuse_malformed_input_naming_the_fault() -> None:
    with pytest.raises(ValueError, match="fill_rule"):
        PathScene.from_paths(4, 4, [[[[0, 0], [1, 0], [0, 1]]]], "winding")
    with pytest.raises(ValueError, match="add up"):
        PathScene(4, 4, np.zeros((3, 2)), [2], [0])
    with pytest.raises(ValueError, match="number the paths"):
        PathScene(4, 4, np.zeros((3, 2)), [3], [1])
    with pytest.raises(ValueError, match="no vertex"):
        PathScene(4, 4, np.zeros((3, 2)), [3, 0], [0, 0])


def test_a_scene_a_rasterizer_cannot_draw_as_given_is_a_skip_saying_why() -> None:
    from harness.contract.scenes import Unsupported

    class OneContour(OracleFiller):
        def rasterize(self, scene):
            if isinstance(scene, PathScene) and np.bincount(scene.contour_path).max() > 1:
                raise Unsupported(f"{self.name}: path 0 has {len(scene.contour_sizes)} contours; one per call")
            return super().rasterize(scene)

    results = _results(OneContour("one_contour"), CASES)
    ring = [r for r in results if r.case == "paths/ring-same/nonzero"]
    assert [(r.check, r.status) for r in ring] == [("run", "skip")] and "2 contours" in ring[0].message
    assert all(r.status in ("pass", "skip") for r in results)
