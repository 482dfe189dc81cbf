"""Every check fails on at least one deliberately broken rasterizer, for the reason the
table says, and passes on all four built-ins (tests/engine/test_runner.py); and repros reproduce:
a failure of each check and case family, saved as its repro file and replayed, fails the
same check."""

import functools
import json
from typing import Any

import pytest

from cases.suites import suite
from harness import run_suite
from harness.checks import CHECKS, Result
from harness.contract.case import Case
from tests.known_bad.aa_lines import DirectionalAALines
from tests.known_bad.aa_paths import BiasedPartialFiller, EvenOddForNonzeroArea, OrientationRoundedFiller, SignedAreaPathFiller
from tests.known_bad.antialiasing import (
    BiasedArea,
    CoarseSupersampleClaimsAnalytic,
    Float32EdgeStepping,
    InclusiveSampleTies,
    MirroredPattern,
    PerEdgeMethodSwitch,
    SwappedSampleBits,
)
from tests.known_bad.conventions import DropsHuge, HalfAwayClaimsNearestEven, YFirstClaimsXFirst
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.lines import (
    BackwardPrestep,
    BothEndPixels,
    Float32DDA,
    LeftmostFirst,
    OffByOneLast,
    RoundingDDA,
    YMajorAlongX,
)
from tests.known_bad.misc import (
    HangsOnEpsilon,
    Int32FixedPoint,
    NaNAttributes,
    Raises,
    ReturnsGarbage,
    SlowOnEpsilon,
    WrongTieClaim,
)
from tests.known_bad.paths import BUGS as PATH_BUGS
from tests.known_bad.paths import PathFillBug, TwoFillers
from tests.known_bad.scanlines import ScanlineBug


@functools.cache
def static():
    """The quick suite's still cases (built when first needed, not when the module is
    collected: every test worker collects every module)."""
    return tuple(c for c in suite("quick") if isinstance(c, Case))


# known-bad rasterizer -> the checks that must flag it ("run": an error or timeout result)
TABLE: dict[Any, set[str]] = {  # (keys: known-bad rasterizers of many classes)
    **{PathFillBug(bug): {"conformance"} for bug in PATH_BUGS},
    TwoFillers(): {"triangulation"},
    SignedAreaPathFiller(): {"accuracy", "invariance"},  # issue 34: AA paths
    EvenOddForNonzeroArea(): {"accuracy"},
    OrientationRoundedFiller(): {"invariance"},  # a reversed winding must not change a nonzero fill
    BiasedPartialFiller(): {"seams", "accuracy"},
    DirectionalAALines(): {"invariance"},  # AA lines: a reversed segment draws the same
    EdgeFunctionBug("inclusive"): {"conformance", "watertight", "degenerate"},
    EdgeFunctionBug("exclusive"): {"conformance", "watertight"},
    EdgeFunctionBug("float32"): {"conformance", "watertight"},
    EdgeFunctionBug("endpoint-order"): {"watertight"},
    EdgeFunctionBug("vertex-order-ties"): {"conformance", "invariance", "watertight"},
    EdgeFunctionBug("min-area"): {"conformance", "watertight", "closed"},
    EdgeFunctionBug("one-winding"): {"conformance", "invariance", "watertight", "closed"},
    EdgeFunctionBug("nan-to-num"): {"degenerate"},
    ScanlineBug("no-prestep"): {"conformance"},
    ScanlineBug("rows-plus-one"): {"conformance", "watertight"},
    ScanlineBug("ceil-left"): {"conformance", "watertight"},
    ScanlineBug("round-ends"): {"conformance", "invariance"},
    ScanlineBug("top-edge-eval"): {"conformance"},
    ScanlineBug("no-clip"): {"hygiene"},
    WrongTieClaim(): {"conformance"},
    YFirstClaimsXFirst(): {"conformance"},
    HalfAwayClaimsNearestEven(): {"conformance"},
    DropsHuge(): {"conformance", "watertight"},
    Int32FixedPoint(): {"conformance"},
    NaNAttributes(): {"degenerate"},
    SlowOnEpsilon(): {"degenerate"},
    Raises(): {"run"},
    ReturnsGarbage(): {"run"},
    HangsOnEpsilon(): {"run"},
    # multisample (judged sample by sample) and area coverage (issue 14)
    MirroredPattern(): {"conformance"},
    SwappedSampleBits(): {"conformance"},
    InclusiveSampleTies(): {"conformance", "watertight"},  # the quick suite's lattice partitions have ties at the 4x samples
    BiasedArea(): {"accuracy"},
    PerEdgeMethodSwitch(): {"seams", "invariance"},  # cairo's 2010 seam
    CoarseSupersampleClaimsAnalytic(): {"accuracy"},  # and popping: tests/checks/test_area.py
    Float32EdgeStepping(): {"accuracy"},  # drifting tens of levels down the tall triangles (tests/checks/test_area.py)
    # lines (issue 16): each on the check it was broken for (and the cheap, certain extras)
    RoundingDDA(): {"conformance"},
    BothEndPixels(): {"joints", "length"},
    YMajorAlongX(): {"connectivity"},
    OffByOneLast(): {"length"},
    Float32DDA(): {"conformance"},  # on the long lines only
    LeftmostFirst(): {"reversal"},
    BackwardPrestep(): {"line-motion"},
}


# the case families where a multisample or area bug shows (every still case flags them
# too, at several times the cost: each sample of each case is judged)
WHERE_IT_SHOWS = {"bad_mirrored_pattern": ("lattice", "float"), "bad_swapped_sample_bits": ("lattice", "float"),
                  "bad_inclusive_sample_ties": ("watertight",), "bad_biased_area": ("lattice", "float"),
                  "bad_per_edge_method_switch": ("watertight",), "bad_coarse_supersample": ("lattice", "float"),
                  "bad_float32_edge_stepping": ("float",),
                  **{f"bad_{bug}": ("paths",) for bug in PATH_BUGS}, "bad_two_fillers": ("paths", "path-partitions"),
                  # joints need polylines; float32 drift needs the long lines
                  "bad_both_end_pixels": ("line-strips",), "bad_float32_dda": ("lines",)}


# a timing check's failure (slow_on_epsilon's) is no repro to replay exactly; a 16-bit
# winding counter fails only on a path of 196,000 vertices, whose case file takes tens of
# seconds to read back (the 8-bit one replays the same failure on 770)
SHRINKING = [bad for bad, wanted in TABLE.items()
             if "run" not in wanted and bad.name not in ("bad_slow_on_epsilon", "bad_int16-winding")]


# whose failures are read case by case (every huge case), not only the first of each
# check in each family
EVERY_FAILURE = {"bad_drops_huge"}


@pytest.fixture(scope="module")
def flagged():
    """known-bad name -> {check: [failing or erroring results]} over the quick suite.

    A family's cases run in order until each check the table names for that known-bad has
    failed there (every case of it when some check never does): the rest would only repeat
    failures already seen. The first failure of each check in each family -- what the repro
    test replays, and what the evidence tests read -- is the same as over every case."""
    import threading

    from harness.checks import checks

    out: dict[str, dict[str, list[Result]]] = {}
    for bad, wanted in TABLE.items():
        # only the cases and checks the table names (for "run", the degenerate cases, where
        # the raising, lying and hanging ones all show): what must flag it
        if "run" in wanted:
            left, stop = set(wanted), threading.Event()

            def seen_all(r, left=left, stop=stop, every=bad.name in EVERY_FAILURE):
                if r.status in ("fail", "error"):
                    left.discard(r.check)
                    if not left and not every:
                        stop.set()  # each check it must fail has failed: the rest would only repeat it (a hang, 1 s each)

            results = run_suite([bad], cases=[c for c in static() if c.family == "degenerate"], timeout=0.5, identify=False,
                                repros=False, isolate=True, on_result=seen_all, stop=stop)
        else:
            kind = bad.convention.coverage_kind if bad.convention is not None else None
            mine = [c for c in static() if any(check.name in wanted for check in checks(c))
                    and c.family in WHERE_IT_SHOWS.get(bad.name, (c.family,))]
            results = []
            for family in dict.fromkeys(c.family for c in mine):  # in suite order
                cases = [c for c in mine if c.family == family]
                left = {check.name for c in cases for check in checks(c, wanted, kind)}
                stop = threading.Event()

                def seen(r, left=left, stop=stop, every=bad.name in EVERY_FAILURE):
                    if r.status in ("fail", "error"):
                        left.discard(r.check)
                        if not left and not every:
                            stop.set()  # after this case: its results are all kept

                results += run_suite([bad], cases=cases, timeout=0.5, identify=False, repros=False, isolate=False,
                                     only=set(wanted), on_result=seen, stop=stop)
        out[bad.name] = {}
        for r in results:
            if r.status in ("fail", "error"):
                out[bad.name].setdefault(r.check, []).append(r)
    return out


@pytest.mark.parametrize("bad", list(TABLE), ids=lambda b: b.name)
def test_known_bad_is_flagged_by_its_checks(bad, flagged):
    missing = TABLE[bad] - set(flagged[bad.name])
    assert not missing, f"{bad.name} was not flagged by {sorted(missing)}"


def test_every_check_fails_on_some_known_bad():
    from tests.checks.test_motion import MOTION_TABLE

    caught = set().union(*TABLE.values(), *MOTION_TABLE.values())
    assert set(CHECKS) | {"run"} <= caught


def test_failures_carry_evidence(flagged):
    watertight = flagged["bad_inclusive"]["watertight"][0]
    blame = watertight.evidence["blame"][0]
    assert blame["kind"] == "double" and len(blame["triangles"]) == 2 and blame["edge"] is not None
    conformance = flagged["bad_wrong_tie_claim"]["conformance"][0]
    assert conformance.evidence["pixels"][0]["near_tie"] is False
    timeout = flagged["bad_hangs_on_epsilon"]["run"][0]
    assert timeout.message.startswith("timeout")
    slow = flagged["bad_slow_on_epsilon"]["degenerate"][0]
    assert slow.metrics["work_ratio"] > 50 and "the time of plain triangles" in slow.message
    crash = flagged["bad_raises"]["run"][0]
    assert "RuntimeError: rasterizer exploded" in crash.message and "Traceback" in crash.evidence["traceback"]


def test_huge_cases_are_never_excused_as_near_ties(flagged):
    """A rasterizer that draws nothing beyond 1e15 fails every huge case beyond it, with no
    pixel excused as float rounding (the exact distance is whole pixels)."""
    failed = {r.case: r for r in flagged["bad_drops_huge"]["conformance"]}
    for label in ("1e30", "max-float"):
        for kind in ("cover", "wedge"):
            result = failed[f"degenerate/huge/{kind}-{label}"]
            assert result.metrics["near_tie"] == 0 and result.metrics["exact_ties"] == 0, result.message
    holes = {r.case for r in flagged["bad_drops_huge"]["watertight"]}
    assert {"degenerate/huge/cover-1e30", "degenerate/huge/cover-max-float"} <= holes


def test_drawing_nothing_fails_every_huge_case():
    """Nothing drawn is never excused as float rounding, however far away the vertices:
    every huge case fails conformance, and the covering pairs fail watertight too."""
    from cases.degenerate import degenerate_cases
    from harness.checks import conformance, watertight
    from harness.contract.conventions import Convention
    from harness.contract.coverage import Coverage
    from harness.oracle.coverage import exact_coverage

    huge = [c for c in degenerate_cases(0) if c.id.startswith("degenerate/huge/")]
    assert len(huge) == 12
    for case in huge:
        verdict = conformance(case, Coverage.empty(), exact_coverage(case.scene, Convention()), Convention())
        assert verdict.status == "fail" and verdict.metrics["near_tie"] == 0, (case.id, verdict.message)
        if case.region is not None:
            assert watertight(case, Coverage.empty()).status == "fail", case.id



@pytest.mark.parametrize("bad", SHRINKING, ids=lambda b: b.name)
def test_every_failure_replays_as_the_same_check_from_its_repro(bad, flagged, tmp_path):
    """The repro file of a failure (shrunk, or the whole case once the shrinking budget is
    spent) fails again on replay -- the same check, which replay runs alone with hygiene --
    and a shrunk repro's message is the check's own on the shrunk case. For each check and
    case family a known-bad fails, its first failure there is run again with repros, as a
    user's run makes them (shrinking all ~700 failures would prove the same at 15 s more)."""
    from harness.engine.runner import replay

    first: dict[tuple[str, str], Result] = {}
    for found in flagged[bad.name].values():
        for r in found:
            if r.status == "fail":
                first.setdefault((r.check, r.case.split("/")[0]), r)
    assert first
    cases = {c.id: c for c in static()}
    for k, ((check, _), failure) in enumerate(sorted(first.items())):
        again_with_repro = run_suite([bad], cases=[cases[failure.case]], timeout=0.5, repro_seconds=4.0, identify=False,
                                     isolate=False, only={check})
        failure = next(r for r in again_with_repro if r.check == check and r.status == "fail")
        payload = failure.evidence["repro"]
        path = tmp_path / f"{k}.json"
        path.write_text(json.dumps(payload))
        named = payload["check"]
        again = replay(path, bad, identify=False)
        assert {r.check for r in again} <= {named, "hygiene"}
        mine = [r for r in again if r.check == named]
        assert mine and any(r.status == "fail" for r in mine), (failure.case, named, [r.message for r in again])
        # triangles, paths, or the segments of line strips
        primitives = len(payload["positions"]) if "positions" in payload else len(payload["paths"]) if "paths" in payload \
            else sum(len(strip) - 1 for strip in payload["lines"])
        shrunk = payload.get("note") is None and primitives < payload["original_triangles"]
        if shrunk and named != "watertight":
            assert payload["message"].split(";")[0] == mine[0].message.split(";")[0], (payload["message"], mine[0].message)

def test_the_catalogue_holds_the_table():
    """The campaigns run on tests/known_bad/catalogue.py's rasterizers: the table's are there."""
    from tests.known_bad.catalogue import KNOWN_BAD

    assert {bad.name for bad in TABLE} <= set(KNOWN_BAD)
    assert all(type(KNOWN_BAD[bad.name]) is type(bad) for bad in TABLE)
