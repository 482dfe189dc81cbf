"""Failure signatures (harness/diagnose/signatures.py): one bug on many generated scenes is one
signature, different bugs are different ones, errors classify, odd input never raises;
and the held-out rare bug (tests/known_bad/rare.py) passes the quick suite."""

import collections
import math
from dataclasses import replace

import numpy as np
import pytest

from cases.fuzz import generate
from harness import run_suite
from harness.checks import Result
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.diagnose.signatures import Signature, overflow_class, signature
from harness.diagnose.trials import with_trials
from harness.engine.isolation import InProcess, Outcome
from harness.engine.runner import _error, check_case, check_motion
from rasterizers.fixed_point import FixedPoint
from tests.known_bad.antialiasing import BiasedArea
from tests.known_bad.conventions import HalfAwayClaimsNearestEven, YFirstClaimsXFirst
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.lines import BothEndPixels, YMajorAlongX
from tests.known_bad.misc import ClipsBeforeSnapping, Float32Input, Raises
from tests.known_bad.paths import PathFillBug
from tests.known_bad.rare import RareSlopeTie, flipped_samples

_RUNS: dict[tuple[str, str, int], tuple[dict, list[Result]]] = {}


def scenes(family: str, count: int) -> dict[str, Case | MotionCase]:
    return {c.id: c for c in (generate(family, 0, index) for index in range(count))}


def failures(bad, family: str, count: int, only: set[str]) -> tuple[collections.Counter, list[Result]]:
    """Signature keys of the bug's failures on the family's first scenes (computed once per
    module), and the failing results."""
    key = (bad.name, family, count)
    if key not in _RUNS:
        cases = scenes(family, count)
        results = run_suite([bad], cases=list(cases.values()), isolate=False, identify=False, repros=False, only=only)
        _RUNS[key] = (cases, [r for r in results if r.status in ("fail", "error")])
    cases, failed = _RUNS[key]
    return collections.Counter(signature(r, cases[r.case], bad.convention).key for r in failed), failed


ONE_SIGNATURE = [
    # bug, family, scenes, the checks run, its one signature
    (EdgeFunctionBug("inclusive"), "lattice", 50, {"conformance"}, "conformance|exact-tie-slanted-edge|tie-rule"),
    (YFirstClaimsXFirst(), "lattice", 50, {"conformance"}, "conformance|exact-tie-slanted-edge|tie-rule"),
    (EdgeFunctionBug("float32"), "float", 120, {"conformance"}, "conformance|near-tie|none"),
    (ClipsBeforeSnapping(), "lattice", 50, {"conformance"}, "conformance|viewport-edge|none"),
    (EdgeFunctionBug("one-winding"), "lattice", 30, {"conformance"}, "conformance|culling|culling"),
    (PathFillBug("evenodd-for-nonzero"), "paths", 40, {"conformance"}, "conformance|fill-rule|fill-rule"),
    (PathFillBug("unsigned-crossings"), "paths", 40, {"conformance"}, "conformance|winding|fill-rule"),
    (BothEndPixels(), "lines", 16, {"length"}, "length|last-pixel|line-rule"),
    (YMajorAlongX(), "lines", 16, {"connectivity"}, "connectivity|gap|line-rule"),
]


@pytest.mark.parametrize("bad, family, count, only, expected", ONE_SIGNATURE, ids=lambda v: getattr(v, "name", None))
def test_one_bug_on_many_scenes_is_one_signature(bad, family, count, only, expected):
    found, failed = failures(bad, family, count, only)
    assert len(failed) >= 5, f"{bad.name} fails only {len(failed)} of {count} {family} scenes"
    assert set(found) == {expected}, found


def test_different_bugs_are_different_signatures():
    """An edge function owning every tie, one in float32 and a clipper snapping its new
    vertices: three causes, no signature in common; so too three path fill bugs."""
    groups = [set(failures(bad, family, count, only)[0]) for bad, family, count, only, _ in ONE_SIGNATURE
              if bad.name in ("bad_inclusive", "bad_float32", "bad_clips_before_snapping")]
    paths = [set(failures(PathFillBug(bug), "paths", 40, {"conformance"})[0])
             for bug in ("evenodd-for-nonzero", "inclusive-ends", "unsigned-crossings")]
    for sets in (groups, paths):
        assert len(sets) == 3 and all(sets)
        for i in range(3):
            for j in range(i + 1, 3):
                assert not sets[i] & sets[j], (sets[i], sets[j])


def test_a_snapping_rounding_and_huge_coordinates_are_named():
    """The quick suite's snapping case (vertices on half steps, rounded away from zero
    where the convention says to even) is ``snapping``; drawing nothing beyond 1e15 is an
    overflow in its magnitude's range."""
    from harness.contract.scenes import Scene as S

    half = Case("lattice/half-steps", S(16, 16, [[[1.03125, 1.0], [9.0, 1.0], [1.03125, 9.03125]],
                                                  [[2.0, 12.5], [14.03125, 12.53125], [13.5, 3.0]]]), lattice=True)
    bad = HalfAwayClaimsNearestEven()
    failed = [r for r in run_suite([bad], cases=[half], isolate=False, identify=False, repros=False, only={"conformance"})
              if r.status == "fail"]
    assert failed and signature(failed[0], half, bad.convention).key == "conformance|snapping|snapping"
    assert overflow_class(2.0**12) == "overflow-2^12..2^24" and overflow_class(2.0**12 - 1) is None
    assert overflow_class(float("inf")) == "overflow-2^128+" and overflow_class(float("nan")) is None


def test_probes_make_input_format_and_viewport_edge_facts():
    """A library that takes float32 (and says so) fails float scenes near ties: its
    signature is ``near-tie`` until the probe shows it passes as received; a clipper's
    failure is ``viewport-edge`` by the probe too."""
    for bad, family, count, expected in ((Float32Input(tell=True), "float", 40, "conformance|input-format|none"),
                                         (ClipsBeforeSnapping(), "lattice", 12, "conformance|viewport-edge|none")):
        cases = scenes(family, count)
        worker = InProcess(bad)

        def judge(candidate, check, bad=bad, worker=worker):
            return check_case(candidate, bad, worker.rasterize, only={check})

        failed = [r for r in run_suite([bad], cases=list(cases.values()), isolate=False, identify=False, repros=False,
                                       only={"conformance"}) if r.status == "fail"][:3]
        assert failed
        for r in failed:
            probed = with_trials(r, cases[r.case], judge, bad)
            assert signature(probed, cases[r.case], bad.convention).key == expected, probed.message
    plain = Result("r", "c", "hygiene", "fail", "x")
    assert with_trials(plain, None, None, None) is plain  # only conformance and invariance failures are probed


def test_errors_classify():
    case = Case("x/y", Scene(4, 4, np.zeros((0, 3, 2))))
    made = {
        "crash": _error(case, "r", Outcome(None, RuntimeError("the rasterizer's worker process died (exit code -11)"))),
        "hang": _error(case, "r", Outcome(None, TimeoutError("no answer within 2 s"), timed_out=True)),
        "exception-ZeroDivisionError": _error(case, "r", Outcome(None, ZeroDivisionError("division by zero"))),
    }
    for expected, r in made.items():
        assert signature(r, case, None) == Signature("run", expected, "none")
    framed = replace(made["hang"], message=f"frame 7: {made['hang'].message}")
    assert signature(framed, None, None).failure_class == "hang"
    checked = Result("r", "c", "reversal", "error", "ValueError on the reversed scene: segment 3 is huge")
    assert signature(checked, None, None).key == "reversal|exception-ValueError|none"
    assert signature(Result("r", "c", "run", "error", "not run: the run's time budget was used up"), None, None).failure_class == "not-run"
    raised = [r for r in run_suite([Raises()], cases=[generate("degenerate", 0, 1)], isolate=False, identify=False, repros=False)]
    assert [signature(r, None, None).key for r in raised] == ["run|exception-RuntimeError|none"]


class _Hostile:
    """Attributes that raise when read."""

    @property
    def check(self):
        raise RuntimeError("no")

    @property
    def status(self):
        raise RuntimeError("no")


def test_signature_never_raises_on_odd_input():
    scene = Scene(8, 8, [[[1, 1], [7, 1], [1, 7]], [[np.nan, 1], [7, 1], [1, 7]]])
    case = Case("odd/case", scene)
    odd_results = [
        None, object(), _Hostile(), 42,
        Result("r", "c", "conformance", "fail", "x", evidence=None),  # type: ignore[arg-type]
        Result("r", "c", "conformance", "fail", "x", evidence={"pixels": "garbage"}),
        Result("r", "c", "conformance", "fail", "x", evidence={"pixels": [{"triangle": 99, "x": 1, "y": 1}, {"x": 2}, 5]}),
        Result("r", "c", "conformance", "fail", "x", evidence={"pixels": [{"triangle": 1, "x": 1, "y": 1, "kind": "extra"}]}),
        Result("r", "c", "conformance", "fail", "x", evidence={"pixels": [{"triangle": 0, "x": 10**30, "y": -5}]}),
        Result("r", "c", "watertight", "fail", "x", metrics={"holes": "many"}, evidence={"blame": [{"pixel": "?"}]}),
        Result("r", "c", "jaggy", "fail", "x", metrics=None),  # type: ignore[arg-type]
        Result("r", "c", "no-such-check", "fail", "x"),
        Result("r", "c", "conformance", "pass", "pixel-exact"),
        Result("r", "c", "run", "error", ""),
    ]
    for result in odd_results:
        for odd_case in (case, None, "case", Case("odd/empty", Scene(4, 4, np.zeros((0, 3, 2))))):
            for convention in (None, Convention(subpixel_bits=4), "not a convention", Convention(samples=4)):
                got = signature(result, odd_case, convention)  # type: ignore[arg-type]
                assert isinstance(got, Signature) and got.key.count("|") == 2
    nan = signature(odd_results[7], case, None)
    assert nan.failure_class == "non-finite-input"
    assert signature(odd_results[4], case, None).failure_class == "other"


def test_describe_reads_as_a_sentence():
    assert Signature("conformance", "near-tie", "none").describe() == \
        "conformance: decided wrongly within float rounding of a tie (an edge; a line rule's boundary)"
    assert "2^53..2^63" in Signature("conformance", "overflow-2^53..2^63", "none").describe()
    assert Signature("run", "exception-KeyError", "none").describe() == "run: raised KeyError"


# -- the held-out rare bug ---------------------------------------------------------------------


def test_the_rare_bug_passes_the_quick_suite():
    """Wrong only on ties of edges of slope exactly 3/4: the quick suite's triangle cases
    (conformance and watertight) never meet one."""
    from cases.suites import suite

    triangles = [c for c in suite("quick") if isinstance(c, Case) and isinstance(c.scene, Scene)]
    assert len(triangles) > 70 and not any(flipped_samples(c.scene) for c in triangles)
    results = run_suite([RareSlopeTie()], cases=triangles, isolate=False, identify=False, repros=False,
                        only={"conformance", "watertight"})
    assert {r.check for r in results} == {"conformance", "watertight"}
    assert all(r.status in ("pass", "skip") for r in results), [r.message for r in results if r.status not in ("pass", "skip")]


def test_the_rare_bug_is_rare_in_fuzz_scenes_and_named_a_slanted_tie():
    lattice = [generate("lattice", 0, index) for index in range(300)]
    triangles = sum(len(c.scene) for c in lattice)
    hit = [c for c in lattice if flipped_samples(c.scene)]
    wrong = sum(len({t for t, _, _ in flipped_samples(c.scene)}) for c in hit)
    assert 1 <= len(hit) <= 30 and wrong / triangles < 2e-3, (len(hit), wrong, triangles)
    bad = RareSlopeTie()
    # and one signature for the one cause, probed as a campaign probes (tests/campaign/test_campaign.py
    # runs the campaign): also where the slope-3/4 edge leaves the screen (lattice 61, once
    # named a viewport edge: the probe's grown screen still fails) and where a sliver's only
    # sample lies on it (lattice 730, once a dropped primitive)
    hit += [generate("lattice", 0, index) for index in (730,)]
    failed = [r for r in run_suite([bad], cases=hit, isolate=False, identify=False, repros=False, only={"conformance"})
              if r.status == "fail"]
    assert len(failed) == len(hit) and any(c.id.endswith("/61") for c in hit)
    worker = InProcess(bad)

    def judge(candidate, check):
        return check_case(candidate, bad, worker.rasterize, only={check})

    keys = collections.Counter(signature(with_trials(r, c, judge, bad), c, bad.convention).key for r, c in zip(failed, hit))
    assert set(keys) == {"conformance|exact-tie-slanted-edge|tie-rule"}, keys


def test_a_flicker_is_named_by_the_frame_that_leaves_the_oracle():
    """The rare bug flickers in motion/0/1532 (a campaign found it there): probed, the first
    frame off the oracle fails conformance on the slope-3/4 tie, so the jaggy finding is the
    tie rule's, not a bare flicker; unprobed it is a flicker."""
    bad = RareSlopeTie()
    case = generate("motion", 0, 1532)
    failed = [r for r in run_suite([bad], cases=[case], isolate=False, identify=False, repros=False, only={"jaggy"})
              if r.status == "fail"]
    assert len(failed) == 1 and failed[0].evidence["oracle_mismatch_frames"]
    assert signature(failed[0], case, bad.convention).key == "jaggy|flicker|none"
    worker = InProcess(bad)

    def judge(candidate, check):
        return check_case(candidate, bad, worker.rasterize, only={check})

    probed = with_trials(failed[0], case, judge, bad)
    frame = probed.evidence["frame_failure"]["frame"]
    assert flipped_samples(case.frames[frame])
    assert signature(probed, case, bad.convention).key == "jaggy|exact-tie-slanted-edge|tie-rule"


def _judge_of(bad):
    """The probes' judge for ``bad`` in process: still cases and motion sequences."""
    worker = InProcess(bad)

    def judge(candidate, check):
        if isinstance(candidate, MotionCase):
            return check_motion(candidate, bad, worker.rasterize, only={check})
        return check_case(candidate, bad, worker.rasterize, only={check})
    return judge


def _one_failure(bad, family: str, index: int, check: str):
    """(case, judge, its one failing result of ``check``, that result probed)."""
    case = generate(family, 0, index)
    judge = _judge_of(bad)
    failed = [r for r in judge(case, check) if r.status == "fail"]
    assert len(failed) == 1
    return case, judge, failed[0], with_trials(failed[0], case, judge, bad)


@pytest.mark.parametrize("bad, check, index, own, probed", [
    # half-away snapping under a nearest-even claim: a frame's conformance names the snapping
    # (floor moves fewer of its half-step vertices, and is tried too); its texel and u, v
    # errors, on frames whose coverage is right, pass against half-away's exact u, v
    (HalfAwayClaimsNearestEven(), "jaggy", 51, "jaggy|flicker|none", "jaggy|snapping|snapping"),
    (HalfAwayClaimsNearestEven(), "texel", 15, "texel|texel-backward-step|none", "texel|snapping|snapping"),
    (HalfAwayClaimsNearestEven(), "perspective", 15, "perspective|perspective-error|none", "perspective|snapping|snapping"),
    # float32 positions: the whole sequence passes as the library receives it
    (Float32Input(), "perspective", 15, "perspective|perspective-error|none", "perspective|input-format|none"),
    # biased alpha: the frame's accuracy fails, the pops are its consequence
    (BiasedArea(), "popping", 0, "popping|popping|none", "popping|alpha-bias|none"),
], ids=["jaggy-snapping", "texel-snapping", "perspective-snapping", "perspective-float32", "popping-alpha"])
def test_motion_failures_are_named_by_their_cause(bad, check, index, own, probed):
    """Campaigns found each of these motion failures counted as a cause of its own beside
    the bug's (a second cause in the known-bad table); probed, each names the bug's."""
    case, _, failed, probed_result = _one_failure(bad, "motion", index, check)
    assert signature(failed, case, bad.convention).key == own
    assert signature(probed_result, case, bad.convention).key == probed


def test_a_correct_motion_answer_is_not_explained_away():
    """The probes add facts only where they hold: a perspective error of u, v that are
    simply wrong (no snapping, no input rounding, coverage right) stays a perspective error."""
    class OffUV:
        """fixed_point (snapped to 8 bits) with u, v 1% too large."""

        name = "off_uv"
        convention = FixedPoint().convention

        def rasterize(self, scene):
            cov = FixedPoint().rasterize(scene)
            return replace(cov, attributes=None if cov.attributes is None else cov.attributes * 1.01)
    bad = OffUV()
    case, _, _, probed = _one_failure(bad, "motion", 15, "perspective")
    assert "snapping_trial" not in probed.evidence and "frame_failure" not in probed.evidence
    assert signature(probed, case, bad.convention).key == "perspective|perspective-error|none"


def test_a_perspective_error_of_non_finite_attributes_is_an_attribute_failure():
    """u, v that are NaN are no perspective error: the same cause as the degenerate check's
    NaN attribute rows."""
    nan = Result("r", "c", "perspective", "fail", "x", metrics={"max_uv_error_texels": math.inf})
    off = Result("r", "c", "perspective", "fail", "x", metrics={"max_uv_error_texels": 3.0})
    assert signature(nan, None, None).key == "perspective|nan-attributes|none"
    assert signature(nan, None, None).cause == signature(Result("r", "c", "degenerate", "fail", "x", metrics={
        "nan_attribute_rows": 2.0}), None, None).cause == "attributes"
    assert signature(off, None, None).key == "perspective|perspective-error|none"


@pytest.mark.parametrize("name, family, index, expected", [
    ("bad_no-prestep", "partitions", 0, "conformance|far-from-edge|sample-point"),  # its wrong samples happen to lie on edges
    ("bad_min-area", "lattice", 4, "conformance|dropped-primitive|none"),  # a sliver whose one sample lies on its edge
    ("bad_min-area", "lattice", 43, "conformance|dropped-primitive|none"),
    ("bad_rare_slope_tie", "lattice", 61, "conformance|exact-tie-slanted-edge|tie-rule"),  # a tie rule's: shifted off, right
    ("bad_inclusive", "partitions", 57, "conformance|exact-tie-vertex|tie-rule"),
    # snapped: a shift of whole grid steps along the edges of one slope keeps their samples
    # on them (at 8 bits the unsnapped shift became (4, 2)/256: y-first ties on slope-1/2
    # edges were refuted); of two non-parallel shifts one moves them off
    ("bad_y_first_tie", "lattice", 10, "conformance|exact-tie-slanted-edge|tie-rule"),
    # 14 wrong triangles: one has an edge along the first shift (its samples stay on it),
    # another's edge meets a sample again under the second; each shift clears the other
    # (the trial once asked one shift to clear all, and named far-from-edge)
    ("bad_y_first_tie", "lattice", 247, "conformance|exact-tie-slanted-edge|tie-rule"),
    # one triangle has a (5, 3) edge, and (3, -5)/256 moves its (47, 7) edge onto the next row
    # of samples exactly: the third shift clears it
    ("bad_y_first_tie", "lattice", 1397, "conformance|exact-tie-slanted-edge|tie-rule"),
])
def test_the_tie_trial_tells_a_tie_rule_from_samples_on_edges_by_chance(name, family, index, expected):
    """Wrong only on samples exactly on edges reads as the tie rule's, until the wrong
    triangles shifted off their edges (both ways) are still wrong: then it was not the tie."""
    from tests.known_bad.catalogue import KNOWN_BAD

    bad = KNOWN_BAD[name]
    case = generate(family, 0, index)
    worker = InProcess(bad)

    def judge(candidate, check):
        return check_case(candidate, bad, worker.rasterize, only={check})

    failed = [r for r in run_suite([bad], cases=[case], isolate=False, identify=False, repros=False, only={"conformance"})
              if r.status == "fail"]
    assert len(failed) == 1
    probed = with_trials(failed[0], case, judge, bad)
    assert probed.evidence["tie_trial"]["passes"] is expected.endswith("tie-rule")
    assert signature(probed, case, bad.convention).key == expected


@pytest.mark.parametrize("name, family, index, unprobed, expected", [
    # one triangle of the culled winding alone on screen: nothing else tells culling from a
    # drop; its copies of the other winding are drawn
    ("bad_one-winding", "lattice", 88, "conformance|dropped-primitive|none", "conformance|culling|culling"),
    # small triangles whose one sample the wrong edge test misses: moved a little, drawn
    ("bad_top-edge-eval", "float", 206, "conformance|dropped-primitive|none", "conformance|far-from-edge|sample-point"),
    # missing whole with every triangle of its winding: read as culling, but neither its
    # copies nor their other winding are ever drawn -- grown thick, it is drawn, wrong
    ("bad_no-prestep", "lattice", 157, "conformance|culling|culling", "conformance|far-from-edge|sample-point"),
    # slivers narrower than a pixel: spans starting at ceil(x) miss them at every move; grown
    # thick, they are drawn without their left column (campaigns: 54 "dropped" in 10 minutes)
    ("bad_ceil-left", "float", 114, "conformance|dropped-primitive|none", "conformance|far-from-edge|sample-point"),
    # a dropper drops every copy, of either winding (unprobed, the sliver's one sample on its
    # edge reads as a tie)
    ("bad_min-area", "lattice", 43, "conformance|exact-tie-slanted-edge|tie-rule", "conformance|dropped-primitive|none"),
    # a sliver thinner than the tie trial's shift, leaving the screen: shifted either way it
    # covers no sample and "passes" the tie trial; its copies that cover samples are never drawn
    ("bad_min-area", "lattice", 1124, "conformance|viewport-edge|none", "conformance|dropped-primitive|none"),
])
def test_the_dropped_trial_tells_a_drop_from_culling_and_from_a_miss(name, family, index, unprobed, expected):
    """Triangles missing whole read as dropped (or culled, when their winding is all gone);
    the dropped trial draws them again moved by quarter pixels, in both windings, and names
    what it sees (campaigns counted these as second causes of the bugs)."""
    from tests.known_bad.catalogue import KNOWN_BAD

    bad = KNOWN_BAD[name]
    case, _, failed, probed = _one_failure(bad, family, index, "conformance")
    assert signature(failed, case, bad.convention).key == unprobed
    trial = probed.evidence["dropped_trial"]
    assert trial["copies"] > 0 and trial["flipped_copies"] > 0
    assert signature(probed, case, bad.convention).key == expected
    if expected == "conformance|dropped-primitive|none":  # a dropper draws them grown thick, right
        assert trial["grown"]["passes"] is True


@pytest.mark.parametrize("family, index, unprobed", [
    # drawn in part: the answer alone tells (campaigns read the fill rule, the sample point)
    ("paths", 0, "conformance|open-contour|none"),
    # a path missing whole: started at another vertex it is drawn (campaigns: a drop)
    ("paths", 3, "conformance|dropped-primitive|none"),
    ("degenerate", 3, "conformance|open-contour|none"),
    # missing whole: its other vertex orders are drawn
    ("degenerate", 0, "conformance|dropped-primitive|none"),
    ("degenerate", 290, "conformance|culling|culling"),  # its other winding drawn right in part
    # ... in whole (its sibling, read alone in the campaign: culling); its own winding,
    # started at another vertex, is drawn
    ("degenerate", 673, "conformance|dropped-primitive|none"),
])
def test_a_filler_that_leaves_its_contours_open_is_one_cause(family, index, unprobed):
    """A path filler that drops each contour's closing edge (a triangle's third) draws rows
    that cross it wrong or not at all, depending on which vertex comes first: read as the
    sample point, the fill rule, a drop or culling (campaigns: four causes). Its answer is
    exactly the open outline's (:func:`harness.oracle.winding.open_outline_coverage`); missing
    whole, its copies in other vertex orders are."""
    bad = PathFillBug("open-contours")
    case, _, failed, probed = _one_failure(bad, family, index, "conformance")
    assert signature(failed, case, bad.convention).key == unprobed
    assert signature(probed, case, bad.convention).key == "conformance|open-contour|none"
    if unprobed != "conformance|open-contour|none":
        assert probed.evidence["dropped_trial"]["open_contour"] is True


class _DropsFewVertexPaths:
    """Broken on purpose: the oracle's coverage without the paths of fewer than five
    vertices -- whichever vertex their contours start at."""

    convention = Convention()
    scene_kinds = ("paths",)
    fill_rules = ("nonzero", "evenodd")
    interpolates = False
    name = "drops_few_vertex_paths"

    def rasterize(self, scene):
        from harness.oracle.coverage import exact_coverage

        full = exact_coverage(scene, self.convention)
        small = np.bincount(scene.contour_path, weights=scene.contour_sizes, minlength=len(scene)) < 5
        return full.take(np.flatnonzero(~small[full.primitive]))


def test_a_path_dropper_is_not_an_open_outline():
    """The other side for paths: a path dropped whatever its start vertex stays a drop."""
    bad = _DropsFewVertexPaths()
    judge = _judge_of(bad)
    for index in range(40):
        case = generate("paths", 0, index)
        failed = [r for r in judge(case, "conformance") if r.status == "fail"]
        if failed:
            break
    probed = with_trials(failed[0], case, judge, bad)
    trial = probed.evidence["dropped_trial"]
    assert trial["rotated_copies"] > 0 and trial["rotated_drawn"] == 0 and trial["open_contour"] is False
    assert signature(probed, case, bad.convention).key == "conformance|dropped-primitive|none"


def test_a_culler_is_not_an_open_outline():
    """The other side: a culler's missing triangle draws the other winding right and its
    own from no vertex -- culling, though the open outline draws a sliver's other winding
    right too."""
    from tests.known_bad.catalogue import KNOWN_BAD

    bad = KNOWN_BAD["bad_one-winding"]
    case, _, failed, probed = _one_failure(bad, "lattice", 88, "conformance")
    trial = probed.evidence["dropped_trial"]
    assert trial["rotated_copies"] > 0 and trial["rotated_drawn"] == 0 and not trial.get("open_contour")
    assert signature(probed, case, bad.convention).key == "conformance|culling|culling"


@pytest.mark.parametrize("name, family, index, unprobed, expected", [
    # int32 edge functions of 8-bit fixed point wrap on triangles a few hundred pixels
    # long, far below 2**12: campaigns read the sample point and drops
    ("bad_int32_fixed_point", "meshes", 12, "conformance|far-from-edge|sample-point", "conformance|overflow-below-2^12|none"),
    ("bad_int32_fixed_point", "meshes", 28, "conformance|dropped-primitive|none", "conformance|overflow-below-2^12|none"),
    # a missing prestep is wrong at any size: scaled down, still wrong
    ("bad_no-prestep", "meshes", 12, "conformance|far-from-edge|sample-point", "conformance|far-from-edge|sample-point"),
    # a long sliver of small area: made thick it is drawn, in its shape still dropped
    ("bad_min-area", "float", 3920, "conformance|dropped-primitive|none", "conformance|dropped-primitive|none"),
])
def test_the_size_trial_tells_a_range_that_gives_out_early(name, family, index, unprobed, expected):
    """Large wrong triangles scaled under 64 px (in shape and made thick, moved on
    screen): right then, the failure is the arithmetic's range, not a convention part's."""
    from tests.known_bad.catalogue import KNOWN_BAD

    bad = KNOWN_BAD[name]
    case, _, failed, probed = _one_failure(bad, family, index, "conformance")
    assert signature(failed, case, bad.convention).key == unprobed
    trial = probed.evidence["size_trial"]
    assert trial["copies"] >= 16 and trial["shaped"] >= 1 and trial["passes"] is (expected != unprobed)
    assert signature(probed, case, bad.convention).key == expected


def test_a_crossing_rule_bug_is_one_cause_on_triangles_and_paths():
    """Edges crossing rows with both ends inclusive: on triangles, samples exactly on
    horizontal edges; on paths, rows through vertices counted twice. Both are how a tie is
    decided (a row meeting a vertex is a tie in y), so one cause: the tie rule."""
    bad = PathFillBug("inclusive-ends")
    on_paths, _ = failures(bad, "paths", 40, {"conformance"})
    on_triangles, _ = failures(bad, "lattice", 30, {"conformance"})
    assert "conformance|vertex-row|tie-rule" in on_paths and on_triangles
    assert {Signature(*key.split("|")).cause for key in on_paths + on_triangles} == {"tie-rule"}


def test_a_seam_of_the_edge_direction_is_one_cause_with_the_invariance_failure():
    """Coverage computed by a method chosen per edge direction: the two triangles of a
    shared edge run along it in opposite directions, so it leaves a seam there, and the
    coverage changes under flipped winding. Probed, the seam names that dependence: one
    cause (campaigns counted ``seam`` and ``changes-under-flip-winding`` apart)."""
    from tests.known_bad.antialiasing import PerEdgeMethodSwitch

    bad = PerEdgeMethodSwitch()
    case = generate("partitions", 0, 0)
    judge = _judge_of(bad)
    seams = [r for r in judge(case, "seams") if r.status == "fail"]
    flipped = [r for r in judge(generate("float", 0, 0), "invariance") if r.status == "fail"]
    assert len(seams) == 1 and len(flipped) == 1
    assert signature(seams[0], case, bad.convention).key == "seams|seam|none"
    probed = signature(with_trials(seams[0], case, judge, bad), case, bad.convention)
    assert probed.key == "seams|changes-under-flip-winding|none"
    assert probed.cause == signature(flipped[0], generate("float", 0, 0), bad.convention).cause
    # a seam of a biased alpha, whose coverage does not change under flipped winding, stays a seam
    biased = BiasedArea()
    judge = _judge_of(biased)
    seam = [r for r in judge(case, "seams") if r.status == "fail"]
    assert len(seam) == 1 and [r.status for r in judge(case, "invariance")] == ["pass"]
    assert signature(with_trials(seam[0], case, judge, biased), case, biased.convention).key == "seams|seam|none"


def test_a_triangulation_mismatch_is_named_by_the_triangles_own_failure():
    """Horizontal edges kept in the edge table: the path passes (its float scene excuses
    near ties), its triangulation drawn as triangles decides samples exactly on their flat
    edges wrongly -- the tie rule, one cause with its conformance failures. Two fillers
    that disagree, each right on its own, stay a triangulation mismatch."""
    from tests.known_bad.paths import TwoFillers

    case = generate("paths", 0, 0)
    for bad, own, probed in ((PathFillBug("horizontal-crossings"), "triangulation|triangulation-mismatch|none",
                              "triangulation|exact-tie-horizontal-edge|tie-rule"),
                             (TwoFillers(), "triangulation|triangulation-mismatch|none", None)):
        judge = _judge_of(bad)
        failed = [r for r in judge(case, "triangulation") if r.status == "fail"]
        assert len(failed) == 1, bad.name
        found = failed[0]
        assert signature(found, case, bad.convention).key == own
        assert signature(with_trials(found, case, judge, bad), case, bad.convention).key == (probed or own)


def test_a_rounding_that_moves_with_the_screen_is_snapping_not_the_viewport_edge():
    """Half away from zero rounds a half step down left of 0 and up right of it: moved into
    a grown screen (the viewport probe), an off-screen vertex rounds the other way and the
    case may pass by chance. The answer equals half-away's exact coverage: snapping (a
    campaign named 13 such findings ``viewport-edge``). The clipper's own stays the edge's."""
    bad = HalfAwayClaimsNearestEven()
    case, _, _, probed = _one_failure(bad, "lattice", 587, "conformance")
    assert "viewport_edge" in probed.evidence  # the probe passed...
    assert signature(probed, case, bad.convention).key == "conformance|snapping|snapping"  # ...by chance
    clipper = ClipsBeforeSnapping()
    found, failed = failures(clipper, "lattice", 50, {"conformance"})
    judge = _judge_of(clipper)
    cases = scenes("lattice", 50)
    assert {signature(with_trials(r, cases[r.case], judge, clipper), cases[r.case], clipper.convention).key
            for r in failed} == {"conformance|viewport-edge|none"}


def test_a_flat_triangle_drawn_on_its_own_edge_is_the_tie_rules():
    """An inclusive edge test draws a zero-area triangle's samples that lie exactly on its
    edges: the degenerate check sees the tie rule's fault. A rasterizer drawing a flat
    triangle's pixels off its edges draws something from nothing: no tie."""
    from harness.contract.coverage import Coverage

    class DrawsBesideFlat:
        name = "bad_draws_beside_flat"
        convention = Convention()

        def rasterize(self, scene):
            return Coverage(np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64),
                            np.ones(1, dtype=np.int64))

    flat = Scene(8, 8, np.array([[[0.5, 2.5], [6.5, 2.5], [3.0, 2.5]]]))  # centres (0.5..6.5, 2.5) on it
    case = Case("degenerate/flat-through-centres", flat)
    keys = {}
    for bad in (EdgeFunctionBug("inclusive"), DrawsBesideFlat()):
        failed = [r for r in _judge_of(bad)(case, "degenerate") if r.status == "fail"]
        assert len(failed) == 1
        keys[bad.name] = signature(failed[0], case, bad.convention).key
    assert keys == {"bad_inclusive": "degenerate|zero-area-drawn|tie-rule",
                    "bad_draws_beside_flat": "degenerate|zero-area-drawn|none"}


def test_non_finite_triangles_drawn_are_non_finite_input_not_zero_area():
    """A triangle with an infinite coordinate that draws fails degenerate as non-finite input
    (as conformance and accuracy name it), not as a zero-area triangle drawn."""
    bad = EdgeFunctionBug("nan-to-num")
    scene = Scene(8, 8, np.array([[[0.5, 0.5], [np.inf, 0.5], [0.5, 6.5]], [[1.0, 1.0], [7.0, 1.0], [1.0, 7.0]]]))
    case = Case("degenerate/non-finite/inf", scene)
    failed = [r for r in _judge_of(bad)(case, "degenerate") if r.status == "fail"]
    assert len(failed) == 1 and failed[0].evidence["triangles"] == [0], failed
    assert signature(failed[0], case, bad.convention).key == "degenerate|non-finite-input|none"


@pytest.mark.parametrize("family, index, check", [("meshes", 311, "conformance"), ("motion", 15, "jaggy")])
def test_a_wrong_sample_near_an_off_screen_edge_is_tried_in_a_grown_screen(family, index, check):
    """A mirrored sample pattern's wrong samples that happen to lie within a sixteenth of a
    pixel of edges leaving the screen, on floats of full precision (the exact move into a
    grown screen would round them): the move rounds, the grown scene still fails, so the
    cause is the sample point, not the viewport edge (campaigns had counted such scenes as
    a second cause)."""
    from tests.known_bad.antialiasing import MirroredPattern

    bad = MirroredPattern()
    case, judge, failed, probed = _one_failure(bad, family, index, check)
    evidence = probed.evidence.get("frame_failure", {}).get("evidence", probed.evidence)
    assert evidence["viewport_edge_refuted"]["rounded"] is True
    assert signature(probed, case, bad.convention).key == f"{check}|far-from-edge|sample-point"


@pytest.mark.parametrize("bug, index, expected, twin_fails", [
    # float32 edge functions on full-precision floats: the exact tie rounds either way; the
    # same tie on a lattice (float32 exact there) is decided right
    ("float32", 263, "watertight|near-tie|none", False),
    # an inclusive edge test double-hits the same tie on the lattice too
    ("inclusive", 53, "watertight|double-hit|tie-rule", True),
])
def test_a_tie_on_a_float_partition_is_rebuilt_on_a_lattice(bug, index, expected, twin_fails):
    """Holes and double hits exactly on shared edges of a float partition are the tie rule's
    only when the same tie fails where arithmetic is exact (campaigns had counted float32's
    rounding at exact ties as the tie rule, beside its near ties)."""
    bad = EdgeFunctionBug(bug)
    case = generate("partitions", 0, index)
    judge = _judge_of(bad)
    failed = [r for r in judge(case, "watertight") if r.status == "fail"]
    assert len(failed) == 1 and not case.lattice
    assert signature(failed[0], case, bad.convention).convention_part == "tie-rule"
    probed = with_trials(failed[0], case, judge, bad)
    assert probed.evidence["lattice_twin"]["fails"] is twin_fails
    assert signature(probed, case, bad.convention).key == expected


@pytest.mark.parametrize("index, expected", [(2, "conformance|near-tie|none"),
                                             (100, "conformance|exact-tie-slanted-segment|line-rule")])
def test_a_primitive_wholly_on_screen_is_not_the_viewport_edges(index, expected):
    """A float32 DDA rounds a moved scene otherwise: the scene passes in the grown screen,
    yet a wrong segment lies wholly inside the screen, whose edge decided nothing there
    (campaigns had counted 39 such scenes as the viewport edge's)."""
    from tests.known_bad.lines import Float32DDA

    bad = Float32DDA()
    case, judge, failed, probed = _one_failure(bad, "lines", index, "conformance")
    assert "viewport_edge" in probed.evidence  # the grown screen passed
    assert signature(probed, case, bad.convention).key == expected


@pytest.mark.parametrize("index", [415, 939])
def test_a_fill_bug_on_a_vertex_row_or_an_edge_is_the_fills(index):
    """Crossings counted without their direction fill gaps; on a scene whose only wrong
    samples lie on a row through a vertex (415) or exactly on an edge (939) that read as the
    tie rule. Shifted off those rows and edges the paths still fail: the fill's (campaigns
    had counted six such scenes as a second cause)."""
    bad = PathFillBug("unsigned-crossings")
    case, _, failed, probed = _one_failure(bad, "paths", index, "conformance")
    assert signature(failed, case, bad.convention).convention_part == "tie-rule"
    assert probed.evidence["tie_trial"]["passes"] is False
    assert signature(probed, case, bad.convention).key == "conformance|winding|fill-rule"


@pytest.mark.parametrize("name, index, expected", [
    ("BothEndPixels", 2, "conformance|end-pixel|line-rule"),  # the last pixel drawn, its end near a diamond's edge
    ("LeftmostFirst", 125, "conformance|reversal|line-rule"),  # drawn from the other end, near a tie
    ("Float32DDA", 16, "conformance|near-tie|none"),  # float32 steps: rounding indeed
])
def test_a_line_wrong_near_the_rules_boundary_is_told_from_rounding(name, index, expected):
    """Wrong pixels within rounding of the line rule's boundary: drawn exactly as the rule
    with the other last-pixel choice, or backwards, they are that choice (campaigns had
    counted them as near ties beside the bug); otherwise rounding."""
    import tests.known_bad.lines as lines

    bad = getattr(lines, name)()
    case, _, failed, probed = _one_failure(bad, "lines", index, "conformance")
    assert signature(probed, case, bad.convention).key == expected


def test_a_sliver_the_rounded_move_would_flatten_gets_no_viewport_trial():
    """A sliver a few ulps thick, reaching past the screen: moving it into a grown screen
    rounds it flat, which a scanline skips -- another scene, so no verdict on the viewport
    edge; the extra row it drew is the sample point's (campaigns had counted 15 such scenes
    as the viewport edge's)."""
    from tests.known_bad.catalogue import KNOWN_BAD

    bad = KNOWN_BAD["bad_rows-plus-one"]
    case, _, failed, probed = _one_failure(bad, "degenerate", 182, "conformance")
    assert "viewport_edge" not in probed.evidence and "viewport_edge_refuted" not in probed.evidence
    assert signature(probed, case, bad.convention).key == "conformance|far-from-edge|sample-point"


def test_dropped_contours_are_not_ignored_holes():
    """Issue 29: a filler drawing each path's first contour alone is named
    ``later-contours-dropped``; one filling each contour apart (their union)
    ``holes-ignored``; a fill that counts crossings unsigned, filling a hole within the
    first contour just as both would, neither (the two cannot be told apart there). The
    message speaks of no sample on an edge: the wrong ones lie inside the hole too."""
    from harness.contract.scenes import PathScene

    outer = [[2.25, 2.25], [20.75, 2.25], [20.75, 20.75], [2.25, 20.75]]
    hole = [[8.25, 8.25], [8.25, 14.75], [14.75, 14.75], [14.75, 8.25]]  # wound against the outer square
    beside = [[24.25, 4.25], [30.75, 4.25], [30.75, 18.75], [24.25, 18.75]]  # outside it, on the same rows
    ring = Case("paths/ring-and-beside/nonzero", PathScene.from_paths(32, 24, [[np.array(outer), np.array(hole),
                                                                                np.array(beside)]], "nonzero"), lattice=True)
    only_ring = Case("paths/ring/nonzero", PathScene.from_paths(32, 24, [[np.array(outer), np.array(hole)]], "nonzero"),
                     lattice=True)
    for bug, case, expected in (("first-contour-only", ring, "conformance|later-contours-dropped|none"),
                                ("contours-apart", ring, "conformance|holes-ignored|fill-rule"),
                                ("unsigned-crossings", only_ring, "conformance|winding|fill-rule"),
                                ("contours-apart", only_ring, "conformance|winding|fill-rule")):
        bad = PathFillBug(bug)
        judge = _judge_of(bad)
        failed = [r for r in judge(case, "conformance") if r.status == "fail"]
        assert failed, bug
        probed = with_trials(failed[0], case, judge, bad)
        assert signature(probed, case, bad.convention).key == expected, (bug, case.id, failed[0].message)
        assert "exactly on" not in failed[0].message, failed[0].message
    from rasterizers.trapezoid import TrapezoidFill

    assert all(r.status == "pass" for r in _judge_of(TrapezoidFill())(ring, "conformance"))


@pytest.mark.parametrize("family", ["lattice", "float"])
def test_samples_dropped_near_edges_are_not_a_wrong_pattern(family):
    """Issue 29: a multisample rasterizer rejecting pixels whose centre lies just outside
    an edge is named ``dropped-near-edges``; a wrong pattern (mirrored, every sample at the
    centre), which puts samples in where it leaves others out, stays the sample point's."""
    from tests.known_bad.antialiasing import CentreSamples, MirroredPattern, RejectsNearEdges

    case = generate(family, 0, 0)
    for bad, expected in ((RejectsNearEdges(), "conformance|dropped-near-edges|none"),
                          (CentreSamples(), "conformance|far-from-edge|sample-point"),
                          (MirroredPattern(), "conformance|far-from-edge|sample-point")):
        judge = _judge_of(bad)
        failed = [r for r in judge(case, "conformance") if r.status == "fail"]
        assert failed, bad.name
        assert signature(with_trials(failed[0], case, judge, bad), case, bad.convention).key == expected, bad.name


def test_line_messages_speak_of_lines():
    """Issue 29: a line drawer's wrong pixels on the rule's boundary are said to lie on the
    line rule's boundary -- no sample on an edge, no triangle -- and its signature is the
    line rule's."""
    from cases.lines import line_cases

    case = next(c for c in line_cases(0) if c.id == "lines/octants/edge-midpoints")
    bad = BothEndPixels()
    failed = [r for r in _judge_of(bad)(case, "conformance") if r.status == "fail"]
    assert failed and "exactly on the line rule's boundary" in failed[0].message, failed
    assert "sample" not in failed[0].message and "triangle" not in failed[0].message
    assert signature(failed[0], case, bad.convention).convention_part == "line-rule"
