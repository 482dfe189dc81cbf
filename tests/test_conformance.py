"""The default suite's conformance check: it passes every built-in and fails each
known-bad rasterizer, for the right reason."""

import numpy as np
import pytest

from cases.scenes import default_cases
from harness.api import Coverage
from harness.conformance import deviations, edge_distance, run_conformance
from harness.registry import load
from tests.known_bad.simple import (
    DropsSmallTriangles,
    EveryEdgeExclusive,
    EveryEdgeInclusive,
    Raises,
    ReturnsGarbage,
    WrongTieClaim,
)

BUILTINS = ["floor_scanline", "centre_scanline", "pineda_topleft", "fixed_point"]


def small_cases():
    # the per-pixel known-bad loops are slow: the lattice and mesh cases suffice
    return [c for c in default_cases(0) if c.lattice or c.partition]


@pytest.mark.parametrize("name", BUILTINS)
def test_builtins_pass_the_default_suite(name):
    results = run_conformance(load(name), default_cases(0))
    assert [r.status for r in results] == ["pass"] * len(results), [r.message for r in results if r.status != "pass"]


@pytest.mark.parametrize(
    "bad, expect",
    [
        (EveryEdgeInclusive(), "double hits"),
        (EveryEdgeExclusive(), "missing"),
        (WrongTieClaim(), "exactly on an edge"),
        (DropsSmallTriangles(), "missing"),
    ],
    ids=lambda v: getattr(v, "name", v),
)
def test_known_bad_rasterizers_fail(bad, expect):
    results = run_conformance(bad, small_cases())
    failed = [r for r in results if r.status == "fail"]
    assert failed, "a known-bad rasterizer passed every case"
    assert any(expect in r.message for r in failed), [r.message for r in failed]


@pytest.mark.parametrize("bad, text", [(Raises(), "RuntimeError: rasterizer exploded"), (ReturnsGarbage(), "not Coverage")])
def test_broken_plugins_become_error_results_and_the_run_goes_on(bad, text):
    cases = small_cases()[:3]
    results = run_conformance(bad, cases)
    assert [r.status for r in results] == ["error"] * 3
    assert all(text in r.message and r.case == c.id for r, c in zip(results, cases))
    assert "Traceback" in results[0].details["traceback"]


def test_deviations_and_distances():
    oracle = Coverage.from_pixels([0, 0, 1], [1, 2, 5], [0, 0, 0])
    got = Coverage.from_pixels([0, 0, 0, 1], [1, 1, 3, 7], [0, 0, 0, 9])  # dup, extra, out of view
    missing, extra = deviations(got, oracle, 8, 8)
    assert missing.T.tolist() == [[0, 2, 0], [1, 5, 0]]
    assert sorted(extra.T.tolist()) == [[0, 1, 0], [0, 3, 0], [1, 7, 9]]
    positions = np.array([[[0.5, 0.5], [4.5, 0.5], [0.5, 4.5]]])
    d = edge_distance(positions, np.array([[0, 0], [0, 1], [0, 1]]), (0.5, 0.5))
    assert d[0] == 0.0  # the sample is exactly a vertex
    assert d[1] == pytest.approx(1.0 / 4.5)  # one pixel from two edges, relative to 4.5
