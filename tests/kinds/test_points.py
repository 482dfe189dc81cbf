"""Points end to end (issue 31, point 8): the reference passes every point case under
several conventions, each known-bad point drawer fails the checks its bug breaks and only
those, cases round-trip through JSON, identify fingerprints a point-taking black box, and a
point failure's crop draws the squares."""

from __future__ import annotations

import base64
import collections
import json
import urllib.parse

import numpy as np
import pytest

from cases.points import point_cases
from harness import PointScene, run_suite
from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.conventions import Convention
from harness.identify.fingerprint import Identified, identify
from harness.kinds import KINDS, SCENE_KINDS, kind_of
from harness.oracle.points import point_coverage
from harness.report.picture_svg import svg_crop
from rasterizers.points import PointSprites
from tests.known_bad.points import ClosedSquares, DropsTheLast, Float32Sides, OwnsTheOtherSides, RoundedCentres


def _point_results(rasterizer) -> list:
    results = run_suite([rasterizer], isolate=False, repros=False, identify=False)
    return [r for r in results if r.case.startswith("points/")]


def test_points_are_a_kind_like_the_others() -> None:
    assert "points" in SCENE_KINDS and KINDS["points"].scene_class is PointScene
    assert kind_of(PointScene(4, 4, [[1.0, 1.0]])).name == "points" and not KINDS["points"].missing_hooks()


@pytest.mark.parametrize("convention", [Convention(), Convention(tie="bottom-right", sample=(0.25, 0.75)),
                                        Convention(samples=4), Convention(subpixel_bits=2, tie="top-right")],
                         ids=["d3d", "bottom-right-offset", "msaa4", "snapped"])
def test_the_reference_passes_every_point_case(convention) -> None:
    results = _point_results(PointSprites(convention))
    seen = collections.Counter((r.check, r.status) for r in results)
    assert {status for _, status in seen} == {"pass"}, [(r.case, r.check, r.message) for r in results if r.status != "pass"]
    # every check that applies to points ran: conformance, hygiene, invariance on every case, watertight on the tilings
    assert seen[("conformance", "pass")] == seen[("hygiene", "pass")] == seen[("invariance", "pass")] == len(point_cases(0))
    assert seen[("watertight", "pass")] == 4


# each bug: the checks it must fail (on which cases) and the checks it must pass everywhere
BUGS = [
    (ClosedSquares, {"conformance": "points/ties/size-1", "watertight": "points/tiles/offset-0-0"}, {"invariance"}),
    (OwnsTheOtherSides, {"conformance": "points/ties/size-2"}, {"watertight", "invariance"}),
    (Float32Sides, {"conformance": "points/float/near-ties-1e-6"}, {"watertight", "invariance"}),
    # rounding halves to even: a whole-pixel move changes which way a half rounds
    (RoundedCentres, {"conformance": "points/float/size-1.3", "watertight": "points/tiles/offset-0.5-0.5",
                      "invariance": "points/tiles/offset-0.5-0.5"}, {"hygiene"}),
    # the last point of ties/size-1 covers no pixel: only listing the points in another order shows the bug there
    (DropsTheLast, {"conformance": "points/ties/size-2", "invariance": "points/ties/size-1",
                    "watertight": "points/tiles/offset-0-0"},
     {"hygiene"}),
]


@pytest.mark.parametrize("bad, fails, passes", BUGS, ids=[b[0].__name__ for b in BUGS])
def test_each_known_bad_point_drawer_fails_what_its_bug_breaks(bad, fails, passes) -> None:
    results = _point_results(bad())
    failed = {(r.check, r.case) for r in results if r.status == "fail"}
    for check, case in fails.items():
        assert (check, case) in failed, (check, case, sorted(failed))
    assert not any(r.check in passes and r.status != "pass" for r in results), [(r.case, r.check) for r in results
                                                                                 if r.check in passes and r.status != "pass"]
    assert not any(r.status == "error" for r in results)


def test_a_tie_failure_says_the_samples_lie_on_the_squares_sides() -> None:
    [result] = [r for r in _point_results(ClosedSquares()) if r.case == "points/ties/size-1" and r.check == "conformance"]
    assert "lie exactly on a side of their point's square" in result.message


def test_point_cases_round_trip_exactly_through_json_and_a_broken_one_is_named() -> None:
    for case in point_cases(0, full=True):
        back = case_from_json(json.loads(json.dumps(case_to_json(case))))
        assert isinstance(back, Case) and isinstance(case, Case) and isinstance(case.scene, PointScene)
        assert back.id == case.id and isinstance(back.scene, PointScene)
        assert np.array_equal(back.scene.vertices, case.scene.vertices, equal_nan=True)
        assert back.scene.point_size == case.scene.point_size and back.lattice == case.lattice
    data = case_to_json(point_cases(0)[0])
    broken = dict(data, points=data["points"][:3] + [["x", 1]])
    with pytest.raises(ValueError, match=r"points\[3\]"):
        case_from_json(broken)
    neither = {k: v for k, v in data.items() if k != "points"}
    with pytest.raises(ValueError, match="'points' for a point case"):
        case_from_json(neither)
    with pytest.raises(ValueError, match="one kind of scene"):
        case_from_json(dict(data, lines=[[[0, 0], [1, 1]]]))


@pytest.mark.parametrize("convention", [Convention(), Convention(tie="bottom-left"),
                                        Convention(sample=(0.0, 0.0), tie="top-right")],
                         ids=["d3d", "bottom-left", "corner-sample"])
def test_identify_recovers_a_point_drawers_convention(convention) -> None:
    fingerprint = identify(PointSprites(convention))
    assert fingerprint.exact and fingerprint.convention == convention, fingerprint.card()
    assert fingerprint.to_dict()["kind_conventions"]["points"]["exact"]


class TrianglesAndPoints(PointSprites):
    """Triangles at pixel centres with top-left ties, points owning the other sides."""

    name = "triangles_and_points"
    scene_kinds = ("triangles", "points")

    def __init__(self) -> None:
        super().__init__(Convention(tie="bottom-right"))

    def rasterize(self, scene):
        if scene.kind == "points":
            return super().rasterize(scene)
        from rasterizers.centre_scanline import CentreScanline

        return CentreScanline().rasterize(scene)


def test_a_black_box_whose_points_differ_from_its_triangles_is_judged_by_each() -> None:
    fingerprint = identify(TrianglesAndPoints())
    assert fingerprint.convention.tie == "top-left"
    assert fingerprint.kind_fits["points"].convention.tie == "bottom-right"
    assert fingerprint.to_dict()["kind_conventions"]["points"]["same_as_triangles"] is False
    judged = Identified(TrianglesAndPoints(), fingerprint)
    assert judged.point_convention.tie == "bottom-right"  # type: ignore[attr-defined]


def test_a_point_crop_draws_each_square() -> None:
    scene = PointScene(8, 8, [[2.0, 2.0], [5.5, 4.5]], point_size=2.0)
    uri = svg_crop(scene, point_coverage(scene, Convention()), (0.5, 0.5), (0, 0, 8, 8), [(1, 1)])
    data = uri.split(",", 1)[1]
    svg = base64.b64decode(data).decode() if ";base64," in uri else urllib.parse.unquote(data)
    assert svg.count('<rect x="1" y="1" width="2" height="2"') == 1
    assert svg.count('<rect x="4.5" y="3.5" width="2" height="2"') == 1
