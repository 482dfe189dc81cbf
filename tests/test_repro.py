"""Minimal repros: shrinking keeps the failure, JSON round-trips exactly, replay works."""

import json

import numpy as np
import pytest
from hypothesis import given, strategies as st

from cases.records import Case
from cases.suites import suite
from harness import run_suite
from harness.api import Scene
from harness.repro import case_from_json, case_to_json, ddmin, load_case, replay, save_case
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.misc import WrongTieClaim


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
    back = case_from_json(json.loads(json.dumps(case_to_json(case))))
    assert np.array_equal(back.scene.positions, positions, equal_nan=True)
    assert np.array_equal(back.scene.attributes, scene.attributes) and np.array_equal(back.scene.w, scene.w)
    assert np.array_equal(back.region, case.region) and back.refusable == (1,)


def test_bad_case_files_name_the_problem(tmp_path):
    path = tmp_path / "x.json"
    path.write_text("{not json")
    with pytest.raises(ValueError, match="x.json: cannot read"):
        load_case(path)
    path.write_text(json.dumps({"schema": 1, "id": "a"}))
    with pytest.raises(ValueError, match="lacks the field 'positions'"):
        load_case(path)


@pytest.mark.parametrize("bad, case_id, check", [
    (WrongTieClaim(), "lattice/bits-0", "conformance"),
    (EdgeFunctionBug("inclusive"), "watertight/fan-32/centre", "watertight"),
])
def test_failures_shrink_to_small_replayable_cases(bad, case_id, check, tmp_path):
    case = next(c for c in suite("quick") if c.id == case_id)
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


def test_saved_case_replays_identically(tmp_path):
    case = suite("quick")[0]
    path = save_case(tmp_path / "c.json", case)
    assert np.array_equal(load_case(path).scene.positions, case.scene.positions)
    assert [r.status for r in replay(path, "fixed_point")] == [r.status for r in run_suite(["fixed_point"], cases=[case])]
