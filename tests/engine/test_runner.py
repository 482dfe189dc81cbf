"""The runner over the built-ins: the quick suite passes; isolation keeps results."""

import collections

import numpy as np
import pytest

from cases.suites import suite
from harness import run_suite
from harness.checks import Result, checks
from harness.contract.case import MotionCase
from harness.contract.protocol import takes
from harness.engine.registry import load

BUILTINS = ["floor_scanline", "centre_scanline", "pineda_topleft", "fixed_point"]


def _quick():
    """The quick suite (built once per process by :func:`cases.suites.suite`)."""
    return tuple(suite("quick"))


@pytest.fixture(scope="module")
def quick_results():
    """The quick suite on every built-in: one through a worker process, as ``rastercheck
    run`` calls it (every kind of case, a motion case's frames sent at once, the adaptive
    time limit); the others in this process, where the verdicts are the same and the
    workers' start-up and the pickling of every answer (a third of the time) are saved."""
    isolated, *rest = BUILTINS
    return run_suite([isolated], cases=_quick(), seed=0) + run_suite(rest, cases=_quick(), seed=0, isolate=False)


def test_builtins_pass_the_quick_suite(quick_results):
    bad = [(r.rasterizer, r.case, r.check, r.message) for r in quick_results if r.status in ("fail", "error")]
    assert not bad, bad[:10]
    # skips are only refusals of huge coordinates, with their reason
    assert all(r.case.startswith("degenerate/huge/") and "declined" in r.message for r in quick_results if r.status == "skip")


def test_builtins_pass_every_motion_check(quick_results):
    from cases.motion import motion_cases

    motion = {c.id for c in motion_cases(0)}
    results = [r for r in quick_results if r.case in motion]
    assert {r.case for r in results} == motion and all(r.status == "pass" for r in results)
    assert {r.check for r in results} == {"jaggy", "texel", "perspective"}


def test_every_check_ran_on_every_builtin(quick_results):
    ran = collections.defaultdict(set)
    for r in quick_results:
        ran[r.rasterizer].add(r.check)
    for name in BUILTINS:
        rasterizer = load(name)
        assert rasterizer.convention is not None
        kind = rasterizer.convention.coverage_kind
        # every check of its coverage kind that applies to a case it is handed
        wanted = {c.name for case in suite("quick") if not hasattr(case, "scene") or takes(rasterizer, case.scene)
                  for c in checks(case, coverage_kind=kind)}
        assert wanted <= ran[name], name


def test_records_have_the_promised_fields(quick_results):
    r = quick_results[0]
    assert {"rasterizer", "case", "check", "status", "message", "metrics", "evidence"} <= set(r.__dataclass_fields__)


def test_suites_are_deterministic_and_ids_unique():
    from cases.suites import build

    for name in ("quick", "full"):
        # suite() builds once per process: a second generation from scratch must match it
        a, b = suite(name, seed=3), list(build.__wrapped__(name, 3))
        assert [c.id for c in a] == [c.id for c in b]
        assert len({c.id for c in a}) == len(a)
        for x, y in zip(a, b):
            scenes_x = x.frames if isinstance(x, MotionCase) else (x.scene,)
            scenes_y = y.frames if isinstance(y, MotionCase) else (y.scene,)
            assert all(np.array_equal(p.coordinates, q.coordinates, equal_nan=True) for p, q in zip(scenes_x, scenes_y))


def test_results_stream_as_they_come():
    seen: list[Result] = []
    results = run_suite(["centre_scanline"], cases=_quick()[:3], on_result=seen.append)
    assert seen == results


def test_strict_mode_allows_no_rounding_default_allows_near_ties():
    from harness.checks import Tolerance

    cases = [c for c in _quick() if c.id.endswith("/non-dyadic")]
    default = run_suite(["centre_scanline"], cases=cases, repros=False)
    strict = run_suite(["centre_scanline"], cases=cases, tolerance=Tolerance(mode="strict"), repros=False)
    conf_default = [r for r in default if r.check == "conformance"]
    conf_strict = [r for r in strict if r.check == "conformance"]
    assert all(r.status == "pass" for r in conf_default)
    assert any(r.metrics["near_tie"] > 0 for r in conf_default)  # there is rounding to excuse
    assert any(r.status == "fail" for r in conf_strict)


def test_a_hang_becomes_a_timeout_and_the_run_goes_on():
    from tests.known_bad.misc import HangsOnEpsilon

    cases = [c for c in _quick() if c.family == "degenerate"][:12]
    results = run_suite([HangsOnEpsilon()], cases=cases, timeout=0.5, repros=False)
    timeouts = [r for r in results if r.status == "error" and r.message.startswith("timeout")]
    assert timeouts and len({r.case for r in results}) == len(cases)  # every case has results


def test_a_case_no_selected_check_applies_to_is_not_drawn():
    """--check conformance draws no motion frame (no motion check is selected): nothing to
    judge there, so no call and no result; the static cases are drawn and judged."""
    from cases.motion import motion_cases
    from rasterizers.centre_scanline import CentreScanline

    class Counting(CentreScanline):
        calls = 0

        def rasterize(self, scene):
            Counting.calls += 1
            return super().rasterize(scene)

    motion = motion_cases(0)[:2]
    static = list(_quick()[:2])
    results = run_suite([Counting()], cases=[*motion, *static], only={"conformance"}, isolate=False, identify=False)
    assert Counting.calls == 2 and {r.case for r in results} == {c.id for c in static}
    assert run_suite([Counting()], cases=motion, only={"jaggy"}, isolate=False, identify=False)
    assert Counting.calls == 2 + sum(len(c.frames) for c in motion if checks(c, {"jaggy"}))


@pytest.mark.parametrize("name", ["area_scanline"])
def test_the_references_beyond_one_sample_pass_every_check_that_judges_them(name):
    """The anti-aliased reference passes the quick suite's still cases and one motion
    sequence of each kind (the full quick suite: ``rastercheck run``). pineda_msaa4 and
    supersample4 equal their exact oracles on every still case (tests/rasterizers/test_antialiased.py),
    and those oracles pass every check (tests/contract/test_coverage.py, test_area_checks.py)."""
    quick = _quick()
    still = [c for c in quick if not hasattr(c, "frames")]
    motion = list({c.id.split("/")[1]: c for c in quick if hasattr(c, "frames")}.values())
    results = run_suite([name], cases=still + motion, isolate=False, repros=False, identify=False)
    bad = [(r.case, r.check, r.message) for r in results if r.status in ("fail", "error")]
    assert not bad, bad[:5]
    convention = load(name).convention
    assert convention is not None
    kind = convention.coverage_kind
    assert {c.name for c in checks(coverage_kind=kind)} == {r.check for r in results}, name  # every check judged it
