"""Minimal repros: shrinking keeps the failure, JSON round-trips exactly, replay works."""

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cases.fuzz import generate
from cases.suites import suite
from harness import run_suite
from harness.contract.case import Case, case_from_json, case_to_json, load_case, save_case
from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.diagnose.repro import answer_from_json, ddmin
from harness.engine.runner import replay
from harness.oracle.coverage import exact_coverage
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.misc import WrongTieClaim
from tests.known_bad.paths import PathFillBug
from tests.narrow import moving, still, triangles


@given(st.sets(st.integers(0, 40), min_size=1, max_size=4), st.integers(1, 60))
def test_ddmin_finds_the_culprits(culprits, n):
    items = list(range(max(n, max(culprits) + 1)))
    found = ddmin(items, lambda s: culprits <= set(s), budget=10_000)
    assert set(found) == culprits


def test_json_round_trip_is_exact():
    rng = np.random.default_rng(1)
    positions = rng.uniform(-5, 40, size=(7, 3, 2))
    positions[2, 1, 0] = np.nan
    positions[3, 0, 1] = -np.inf
    scene = Scene(40, 30, positions, attributes=rng.normal(size=(7, 3, 2)), w=rng.uniform(0.5, 2, size=(7, 3)))
    case = Case("x/y", scene, lattice=False, region=np.array([[0.1, 0.2], [3, 4], [5, 0]]), refusable=(1,))
    back = still(case_from_json(json.loads(json.dumps(case_to_json(case)))))
    back_scene = triangles(back.scene)
    assert back_scene.attributes is not None and back_scene.w is not None and back.region is not None
    assert scene.attributes is not None and scene.w is not None and case.region is not None
    assert np.array_equal(back_scene.positions, positions, equal_nan=True)
    assert np.array_equal(back_scene.attributes, scene.attributes) and np.array_equal(back_scene.w, scene.w)
    assert np.array_equal(back.region, case.region) and back.refusable == (1,)


def test_bad_case_files_name_the_problem(tmp_path):
    path = tmp_path / "x.json"
    path.write_text("{not json")
    with pytest.raises(ValueError, match="x.json: cannot read"):
        load_case(path)
    path.write_text(json.dumps({"schema": 1, "id": "a"}))
    with pytest.raises(ValueError, match="lacks the fields 'width', 'height', 'positions'"):
        load_case(path)


def _good(**changes):
    data = case_to_json(Case("x/y", Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]]), region=np.array([[0, 0], [4, 0], [0, 4.0]])))
    data.update(changes)
    return data


@pytest.mark.parametrize("changes, problem", [
    ({"width": 1e999}, r"at width: inf is not of type 'integer'"),
    ({"width": "8"}, r"at width: '8' is not of type 'integer'"),
    ({"width": 1 << 20, "height": 1 << 20}, r"1048576 x 1048576 viewport is more than"),
    ({"positions": [[[0, 0], [4, 0]]]}, r"at positions\[0\]"),
    ({"positions": [[["0x1p+0", "zz"], [4, 0], [0, 4]]]}, r"at positions\[0\]\[0\]\[1\]"),
    ({"region": [[0, 0, 1], [4, 0, 1], [0, 4, 1]]}, r"at region\[\d\]: \[\d, \d, 1\] is not valid"),
    ({"region": {"a": 1}}, r"at region"),
    ({"refusable": [5]}, r"refusable: names triangles past the last"),
    ({"attributes": [[[1.0], [2.0, 3.0], [4.0]]]}, r"attributes"),
    ({"id": ""}, r"at id"),
    ({"kind": "motion"}, r"lacks the field 'frames'"),
])
def test_malformed_case_files_are_refused_by_the_schema_naming_the_field(changes, problem):
    with pytest.raises(ValueError, match=problem):
        case_from_json(_good(**changes))


def test_case_files_nested_too_deep_or_not_utf8_are_refused(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match="deep.json: cannot read the case"):
        load_case(path)
    path.write_bytes(b'{"schema": 1, "id": "\xff\xfe"}' + bytes([0xff]))
    with pytest.raises(ValueError, match="cannot read the case"):
        load_case(path)


def test_motion_cases_round_trip_exactly(tmp_path):
    from cases.motion import motion_cases

    case = motion_cases(0)[0]
    back = moving(load_case(save_case(tmp_path / "m.json", case, check="jaggy")))
    assert back.id == case.id and back.texels == case.texels and len(back.frames) == len(case.frames)
    assert all(np.array_equal(a.positions, b.positions) for a, b in zip(back.frames, case.frames))


@pytest.mark.parametrize("bad, case_id, check", [
    (WrongTieClaim(), "lattice/bits-0", "conformance"),
    (EdgeFunctionBug("inclusive"), "watertight/fan-32/centre", "watertight"),
])
def test_failures_shrink_to_small_replayable_cases(bad, case_id, check, tmp_path):
    case = still(next(c for c in suite("quick") if c.id == case_id))
    failing = [r for r in run_suite([bad], cases=[case]) if r.check == check and r.status == "fail"]
    assert failing
    payload = failing[0].evidence["repro"]
    assert payload["original_triangles"] == len(case.scene)
    assert len(payload["positions"]) <= 2 < len(case.scene)
    path = tmp_path / "repro.json"
    path.write_text(json.dumps(payload))
    replayed = replay(path, bad)
    shrunk_check = payload["check"]
    assert any(r.status == "fail" for r in replayed if r.check in (shrunk_check, "conformance", "watertight"))
    assert all(r.status in ("pass", "skip") for r in replay(path, "centre_scanline") if r.check != "conformance")


class _ExactPaths:
    """The oracle itself, for triangles and paths: every hole check passes on it."""

    name = "exact_paths"
    convention = Convention()
    scene_kinds = ("triangles", "paths")
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def rasterize(self, scene):
        return exact_coverage(scene, self.convention)


@pytest.mark.parametrize("bad, case", [
    (EdgeFunctionBug("exclusive"), next(c for c in suite("quick") if c.id == "watertight/grid-6x6-on-centres/lattice")),
    (PathFillBug("horizontal-crossings"), generate("paths", 0, 77)),  # a 4 x 4 quad grid of paths, a campaign's scene
])
def test_a_hole_is_cut_down_to_the_pieces_around_it(bad, case, tmp_path):
    """A partition's hole is no subset's hole -- but the pieces that meet a region one pixel
    wide around it still cover that region: the repro keeps those, the region, and the
    failure (the on-request holes check), which the exact answer passes."""
    failing = [r for r in run_suite([bad], cases=[case], isolate=False, identify=False, only={"watertight"})
               if r.status == "fail"]
    assert failing and failing[0].metrics["holes"] > 0
    payload = failing[0].evidence["repro"]
    cut = still(case_from_json(payload))
    assert cut.region is not None
    assert payload["check"] == "holes" and payload["original_triangles"] == len(case.scene) > len(cut.scene) >= 1
    x, y = payload["evidence"]["pixels"][0]  # the hole on the repro, one of those the whole case's blames
    assert [x, y] in [e["pixel"] for e in failing[0].evidence["blame"] if e["kind"] == "hole"]
    low, high = cut.region.min(axis=0), cut.region.max(axis=0)
    assert cut.region.shape == (4, 2) and low.tolist() > [x - 1, y - 1] and high.tolist() < [x + 2, y + 2]
    path = tmp_path / "repro.json"
    path.write_text(json.dumps(payload))
    assert [r.status for r in replay(path, bad, identify=False) if r.check == "holes"] == ["fail"]
    assert [r.status for r in replay(path, _ExactPaths(), identify=False) if r.check == "holes"] == ["pass"]
    # the repro file keeps what the rasterizer drew on it, for its picture
    answer = answer_from_json(payload["answer"])
    assert answer is not None
    assert np.array_equal(answer.counts(cut.scene.width, cut.scene.height),
                          bad.rasterize(cut.scene).counts(cut.scene.width, cut.scene.height))


def test_saved_case_replays_identically(tmp_path):
    case = still(suite("quick")[0])
    path = save_case(tmp_path / "c.json", case)
    assert np.array_equal(triangles(still(load_case(path)).scene).positions, triangles(case.scene).positions)
    assert [r.status for r in replay(path, "fixed_point")] == [r.status for r in run_suite(["fixed_point"], cases=[case])]


def test_coordinates_are_written_as_short_decimals_where_exact_and_read_back_exactly(tmp_path):
    scene = Scene(16, 16, [[[0.375, 1.5], [12.0, 0.1], [1e-300, 2**60]]])
    data = case_to_json(Case("x/y", scene))
    assert data["positions"][0][0] == ["0.375", "1.5"] and data["positions"][0][1][0] == "12"
    assert data["positions"][0][1][1] == float.hex(0.1) and data["positions"][0][2][0] == float.hex(1e-300)
    back = load_case(save_case(tmp_path / "c.json", Case("x/y", scene)))
    assert np.array_equal(triangles(still(back).scene).positions, scene.positions)
    data["positions"][0][0] = ["10", 1.5]  # "10" is ten (not hex sixteen); numbers are read exactly
    assert triangles(still(case_from_json(data)).scene).positions[0, 0].tolist() == [10.0, 1.5]
