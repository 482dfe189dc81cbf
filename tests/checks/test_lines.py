"""The checks on line scenes (issue 16): connectivity, joints, reversal, length and
line-motion each fail on their known-bad line drawer (naming the segment) and pass on the
exact oracle of every rule; the existing checks behave on line cases (conformance with the
line oracle and its near-tie distances, invariance under the line variants, and the
checks that mean nothing for lines not applied)."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest

from harness.checks import checks, conformance, line_motion
from harness.checks.invariance import invariance_variants
from harness.checks.lines import motion_frames, motion_oracles
from harness.checks.near_ties import _diamond_margins, line_edge_distance, near_ties_of
from harness.checks.records import Tolerance
from harness.contract.case import Case
from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
from tests.known_bad.hairlines import LlvmpipeUnshiftedSnap, QtFlatCaps, SkiaCentredStart
from tests.known_bad.lines import (
    BackwardPrestep,
    BothEndPixels,
    Float32DDA,
    FullWidthOffset,
    LeftmostFirst,
    OffByOneLast,
    RoundingDDA,
    YMajorAlongX,
)

LINE_CHECKS = {"connectivity", "joints", "reversal", "length", "line-motion"}


class OracleLines:
    """Draws exactly what the rule of its convention says (a correct line drawer)."""

    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, convention: Convention, name: str = "oracle_lines") -> None:
        self.convention, self.name = convention, name

    def rasterize(self, scene: LineScene) -> Coverage:
        return exact_coverage(scene, self.convention)


class Nudged(OracleLines):
    """The oracle of the scene with every coordinate moved up by one ulp: float rounding."""

    def rasterize(self, scene: LineScene) -> Coverage:
        return exact_coverage(scene.with_coordinates(np.nextafter(scene.vertices, np.inf)), self.convention)


class StripAware(OracleLines):
    """Draws the last pixel of a strip's last segment only (as a polyline drawer that
    closes its strip): a segment's pixels depend on whether another follows it."""

    def rasterize(self, scene: LineScene) -> Coverage:
        with_last = exact_coverage(scene, Convention(line=LineRule("diamond-exit", last_pixel=True)))
        without = exact_coverage(scene, self.convention)
        last = np.cumsum(scene.strip_sizes - 1) - 1
        return Coverage(*(np.concatenate([getattr(without, f)[~np.isin(without.primitive, last)],
                                          getattr(with_last, f)[np.isin(with_last.primitive, last)]])
                          for f in ("primitive", "y", "x0", "x1")))


STAR: list[list[float]] = [[2.5, 1.25], [13.75, 6.5], [3.0, 14.5], [8.5, 0.5], [14.25, 13.0], [2.5, 1.25]]  # closed
HAIRPIN: list[list[float]] = [[1.0, 9.0], [7.5, 11.5], [1.5, 9.25]]  # a sharp turn: both segments cross the same diamonds
FLOATS: list[list[list[float]]] = [[[0.37, 0.81], [8.93, 4.12], [11.28, 13.66], [2.04, 10.51], [6.77, 6.13]],
          [[15.4, 0.9], [9.1, 2.35], [14.6, 15.2]]]
CASES = [
    Case("lines/star/lattice",
         LineScene.from_strips(16, 16, [STAR, HAIRPIN, [[1.0, 8.0], [15.0, 9.5]], [[7.5, 15.5], [6.25, 2.0]]]), lattice=True),
    Case("lines/strips/float", LineScene.from_strips(16, 16, FLOATS)),
    # 45 degrees, ties of the Bresenham decision variable, beyond the viewport
    Case("lines/ties/lattice", LineScene.from_segments(12, 12, [[0.5, 0.5], [11.0, 1.0], [-2.0, 5.5], [6.0, 11.5]],
                                                      [[4.5, 2.5], [3.0, 9.0], [14.0, 6.5], [6.0, 3.5]]), lattice=True),
]
WIDE = Case("lines/wide/lattice", LineScene.from_strips(16, 16, [STAR, [[1.0, 8.0], [15.0, 9.5]]], line_width=2.5), lattice=True)
# end points on ties of the 1/256 grid (odd multiples of 1/512): where llvmpipe's line snapping parts from its triangles'
TIES_512 = Case("lines/ties-512/float", LineScene.from_segments(16, 16, [[2 + 1 / 512, 3 + 1 / 512], [13 - 1 / 512, 2 + 3 / 512]],
                                                             [[13 + 3 / 512, 3 - 1 / 512], [12 + 1 / 512, 14 - 1 / 512]]))
LONG = Case("lines/long/float", LineScene.from_segments(4096, 64, [[0.3, 3.7], [4090.6, 60.2]], [[4095.1, 57.3], [5.3, 1.1]]))

RULES = {
    "diamond-exit": Convention(),
    "diamond-exit-last": Convention(line=LineRule("diamond-exit", last_pixel=True), subpixel_bits=4),
    "bresenham": Convention(line="bresenham"),
    "bresenham-floor-stay": Convention(line=LineRule("bresenham", rounding="floor", ties="stay", last_pixel=False)),
    # textbook plotLine: the direction of travel normalised (issue 28)
    "bresenham-smaller-x": Convention(line=LineRule("bresenham", ties="stay", last_pixel=False, direction="smaller-x"),
                                      subpixel_bits=4),
    "bresenham-smaller-major": Convention(line=LineRule("bresenham", rounding="floor", direction="smaller-major")),
    "rectangle": Convention(line="rectangle"),
    "rectangle-bottom-right": Convention(line="rectangle", tie="bottom-right", sample=(0.25, 0.75), subpixel_bits=4),
    # Vulkan's non-strict lines; line ends snapped half away where the triangles snap to even (lavapipe)
    "parallelogram": Convention(line="parallelogram"),
    "parallelogram-half-away": Convention(line=LineRule("parallelogram", snap_rounding="half-away"), tie="bottom-right",
                                          subpixel_bits=4),
    # libraries' fixed-point one-pixel lines read from their sources (issue 33)
    "skia-hairline": Convention(line="skia-hairline", input="fixed6-toward-zero"),
    "qt-cosmetic": Convention(line="qt-cosmetic"),
    "llvmpipe-rectangle": Convention(line="llvmpipe-rectangle", input="float32", subpixel_bits=8),
}


def _run(rasterizer, cases, only=None):
    return run_suite([rasterizer], cases=cases, isolate=False, identify=False, repros=False, only=only)


@pytest.mark.parametrize("label", list(RULES))
def test_the_exact_oracle_passes_every_check_on_lines(label: str) -> None:
    convention = RULES[label]
    cases = CASES + ([WIDE] if convention.line.rule in ("rectangle", "llvmpipe-rectangle") else [])
    results = _run(OracleLines(convention), cases)
    bad = [r for r in results if r.status not in ("pass", "skip")]
    assert not bad, [(r.case, r.check, r.message) for r in bad]
    ran = {r.check for r in results}
    assert {"hygiene", "conformance", "invariance"} | LINE_CHECKS <= ran
    assert not ran & {"watertight", "closed", "degenerate", "triangulation", "overdraw", "jaggy", "accuracy"}
    by = {(r.case, r.check): r for r in results}
    if convention.line.rule in ("rectangle", "llvmpipe-rectangle"):
        assert by["lines/star/lattice", "connectivity"].status == "skip"
        assert "rectangular" in by["lines/star/lattice", "connectivity"].message
        assert by["lines/star/lattice", "reversal"].metrics["reversal_pixels"] == 0  # a rectangle has no direction
        assert by["lines/wide/lattice", "joints"].metrics["joint_overlap_predicted"] > 0  # wedges overlap: a fact
    else:
        assert by["lines/star/lattice", "connectivity"].status == "pass"
    assert by["lines/ties/lattice", "joints"].status == "skip"  # lone segments: no joints
    joints = by["lines/star/lattice", "joints"]
    assert joints.metrics["joints"] == 6  # 4 in the star, its closing joint, 1 in the hairpin
    if convention.line.rule == "diamond-exit" and convention.line.last_pixel:
        # where the shared vertex lies in a diamond, both segments draw that pixel: reported, no failure
        assert joints.metrics["joint_vertex_double_predicted"] > 0 and "drawn twice" in joints.message
    elif convention.line.rule == "diamond-exit":
        assert joints.metrics["joint_vertex_double_predicted"] == 0 and "drawn once" in joints.message
        assert joints.metrics["joint_overlap_predicted"] > 0  # the hairpin's two segments share diamonds
        assert by["lines/star/lattice", "reversal"].metrics["reversal_pixels"] > 0  # the other end pixel omitted
    if label == "bresenham":
        assert by["lines/ties/lattice", "reversal"].metrics["reversal_pixels"] > 0  # ties step towards the end point
    if convention.line.direction != "as-given":
        # a normalised walk draws backwards as forwards, ties and end pixel alike (no vertical segment in the star:
        # walking from the smaller x, those keep their given order, and their omitted end pixel)
        assert by["lines/star/lattice", "reversal"].metrics["reversal_pixels"] == 0
        ties = by["lines/ties/lattice", "reversal"].metrics["reversal_pixels"]
        # the vertical (6, 11.5) -> (6, 3.5) keeps its given order from the smaller x: each way omits its own end
        assert ties == 0 if convention.line.direction == "smaller-major" else ties == 2


# known-bad -> (the check it fails, the case it shows on)
KNOWN_BAD: list[tuple[Any, str, Case]] = [
    (RoundingDDA(), "conformance", CASES[0]),
    (BothEndPixels(), "joints", CASES[0]),
    (YMajorAlongX(), "connectivity", CASES[1]),
    (OffByOneLast(), "length", CASES[1]),
    (Float32DDA(), "conformance", LONG),
    (LeftmostFirst(), "reversal", CASES[0]),
    (BackwardPrestep(), "line-motion", CASES[1]),
    (FullWidthOffset(), "conformance", CASES[1]),
    (SkiaCentredStart(), "conformance", CASES[2]),
    (QtFlatCaps(), "conformance", CASES[0]),
    (LlvmpipeUnshiftedSnap(), "conformance", TIES_512),
]


@pytest.mark.parametrize(("bad", "check", "case"), KNOWN_BAD, ids=[b.name for b, _, _ in KNOWN_BAD])
def test_each_known_bad_fails_its_check_naming_the_segment(bad, check: str, case: Case) -> None:
    (verdict,) = [r for r in _run(bad, [case], only={check}) if r.check == check]
    assert verdict.status == "fail", verdict.message
    assert '"segment' in json.dumps(verdict.evidence), verdict.evidence
    if check != "conformance":  # conformance's message counts pixels; its evidence names them
        assert "segment" in verdict.message, verdict.message
    if check == "conformance":
        assert verdict.metrics["wrong"] > 0 and verdict.metrics["near_tie"] == 0  # nothing passes for rounding


def test_the_known_bads_show_what_they_should() -> None:
    """The evidence says what went wrong: a gap in a steep segment, the shared vertex
    drawn twice, a missing last pixel, a segment drawn the same both ways; and float32
    accumulation stays invisible on short lines, showing on long ones only."""
    (gaps,) = [r for r in _run(YMajorAlongX(), [CASES[1]], only={"connectivity"}) if r.check == "connectivity"]
    assert gaps.metrics["line_gaps"] > 0 and gaps.evidence["problems"][0]["kind"] == "gap"
    (twice,) = [r for r in _run(BothEndPixels(), [CASES[0]], only={"joints"}) if r.check == "joints"]
    row = twice.evidence["joints"][0]
    assert row["drawn"] == 2 and row["rule"] == 1 and len(row["segments"]) == 2
    (short,) = [r for r in _run(OffByOneLast(), [CASES[1]], only={"length"}) if r.check == "length"]
    assert short.metrics["length_deficit"] == 1 and short.metrics["length_excess"] == 0
    (same,) = [r for r in _run(LeftmostFirst(), [CASES[0]], only={"reversal"}) if r.check == "reversal"]
    assert same.metrics["reversal_mismatches"] > 0 and same.metrics["reversal_pixels"] > same.metrics["reversal_differences"]
    short_lines = [r for r in _run(Float32DDA(), CASES[:2], only={"conformance"}) if r.check == "conformance"]
    assert {r.status for r in short_lines} == {"pass"}
    (back,) = [r for r in _run(BackwardPrestep(), [CASES[1]], only={"line-motion"}) if r.check == "line-motion"]
    assert back.metrics["line_backward_steps"] > 0 and back.evidence["backward_steps"][0]["motion"] in ("x", "y")


def test_line_motion_holds_for_the_exact_pixels_of_every_rule() -> None:
    """The claim behind line-motion's geometric directions: under each rule (snapped or
    not) the exact pixels of segments of every slope -- 45 degrees, near it, axis-aligned,
    short, leaving the viewport -- never move against the line."""
    rng = np.random.default_rng(3)
    a = rng.uniform(-2.0, 14.0, (48, 2))
    a[::3] = np.round(a[::3] * 4) / 4
    d = rng.normal(0.0, 4.0, (48, 2))
    d[0:8, 1] = d[0:8, 0] * np.where(np.arange(8) % 2, 1, -1)  # 45 degrees
    d[8:16, 1] = d[8:16, 0] + 1 / 16  # near it
    d[16:20, 1] = 0.0
    d[20:24, 0] = 0.0
    d[24:32] = np.round(d[24:32])
    d[32:36] /= 8  # short
    scene = LineScene.from_segments(12, 12, a, a + d)
    case = Case("lines/motion/float", scene)
    for convention in [*RULES.values(), Convention(line=LineRule("bresenham", rounding="half-away"), subpixel_bits=3)]:
        sequences = []
        for axis, frames in motion_frames(scene):
            exact = [exact_coverage(frame, convention) for frame in frames]
            sequences.append((axis, frames, exact, exact))
        together = motion_oracles(frames, convention)  # the check's one call of the oracle for every frame
        assert all(np.array_equal(p.canonical().pixels(), q.canonical().pixels()) for p, q in zip(together, exact))
        verdict = line_motion(case, sequences, convention)
        assert verdict.status == "pass", (convention.line.describe(), verdict.message, verdict.evidence)


@pytest.mark.parametrize("rule", ["diamond-exit", "bresenham", "rectangle"])
def test_conformance_excuses_only_near_ties_on_lines(rule: str) -> None:
    """End points one ulp off exact ties (a line through a diamond's corner, an end point on
    a pixel boundary, a sample on a rectangle's side) flip pixels: near ties off the lattice
    in default mode, never on the lattice or in strict mode; a quarter pixel is never one."""
    convention = Convention(line=rule)
    scene = LineScene.from_segments(12, 8, [[0.5, 0.5], [2.0, 4.5], [1.0, 6.5]], [[4.5, 2.5], [9.0, 4.5], [10.0, 6.5]])
    nudged = Nudged(convention).rasterize(scene)
    oracle = exact_coverage(scene, convention)
    off = Case("lines/ties/float", scene)
    verdict = conformance(off, nudged, oracle, convention)
    assert verdict.metrics["near_tie"] > 0 and verdict.metrics["wrong"] == 0 and verdict.status == "pass", verdict.message
    assert verdict.metrics["exact_ties"] > 0  # the oracle's own decisions sit on the boundary
    assert conformance(off, nudged, oracle, convention, Tolerance(mode="strict")).status == "fail"
    assert conformance(Case("lines/ties/lattice", scene, lattice=True), nudged, oracle, convention).status == "fail"
    far = exact_coverage(scene.with_coordinates(scene.vertices + [0.0, 0.625]), convention)
    assert conformance(off, far, oracle, convention).metrics["wrong"] > 0
    # a pixel no near rounding of its end points moves is no near tie, whatever the segment's ties
    distance = line_edge_distance(scene, convention, np.array([[1], [5], [4]]))
    assert distance[0] > 0.05


def test_line_near_tie_distances_are_upper_bounds_and_zero_only_at_ties() -> None:
    """The diamond-exit margin is never below the true distance of the decision from
    flipping (the segment's penetration depth into the closed diamond, or its distance
    from it, computed independently), is at most sqrt(2) times it, and is exactly 0 where
    the segment touches the diamond without entering it or ends on its boundary."""
    rng = np.random.default_rng(11)
    corners = np.array([[0.5, 0.0], [-0.5, 0.0], [0.0, 0.5], [0.0, -0.5]])

    def to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
        d = b - a
        t = 0.0 if not d.any() else float(np.clip((p - a) @ d / (d @ d), 0.0, 1.0))
        return float(np.hypot(*(a + t * d - p)))

    def truth(a: np.ndarray, b: np.ndarray) -> float:
        # in the diamond's frame: meets the closed diamond when every separating function >= 0
        normals = [np.array(s) / math.sqrt(2) for s in ((1, 1), (1, -1), (-1, 1), (-1, -1))]
        depth = [0.5 / math.sqrt(2) - min(n @ a, n @ b) for n in normals]
        d = b - a
        if d.any():
            n = np.array([-d[1], d[0]]) / np.hypot(*d)
            depth.append(max(abs(n[0]), abs(n[1])) / 2 - abs(n @ a))
        if min(depth) >= 0:
            return float(min(depth))
        edges = [(corners[0], corners[2]), (corners[2], corners[1]), (corners[1], corners[3]), (corners[3], corners[0])]
        outside = [min(to_segment(p, *e) for e in edges) for p in (a, b)]
        return min(*outside, *(to_segment(c, a, b) for c in corners))

    a = rng.uniform(-2, 2, (300, 2))
    b = a + rng.normal(0, 1.5, (300, 2))
    centre = rng.integers(0, 4, (300, 2)) + 0.5
    margin = _diamond_margins(a + centre, b + centre, centre[:, 0], centre[:, 1], True)
    want = np.array([truth(p, q) for p, q in zip(a, b)])
    assert (margin >= want * (1 - 1e-12)).all()
    assert (margin <= math.sqrt(2) * want * (1 + 1e-9) + 1e-15).all()
    # exact ties: along a lower edge, through a corner only, ending on the boundary
    tie = LineScene.from_segments(8, 8, [[0.0, 0.5], [1.0, 0.0], [1.5, 0.0]], [[0.5, 1.0], [1.0, 2.0], [1.5, 1.0]])
    fragments = np.array([[0, 1, 2], [0, 1, 1], [0, 0, 0]])
    assert line_edge_distance(tie, Convention(), fragments).tolist() == [0.0, 0.0, 0.0]
    assert (line_edge_distance(tie, Convention(line=LineRule("diamond-exit", last_pixel=True)), fragments)[2] > 0.3)
    near, _ = near_ties_of(tie, None, fragments, Tolerance())  # no convention: the least under any rule
    assert near.all()


def test_invariance_on_lines_splits_and_reorders_strips() -> None:
    """Each rule decides every segment alone: splitting the strips or listing them in
    another order changes no segment's pixels; a drawer that treats a strip's last segment
    otherwise fails. Translation is by an even shift, and only of positive coordinates."""
    case = CASES[0]
    names = [name for name, _, _ in invariance_variants(case)]
    assert names == ["reorder-strips", "split-strips", "translate"]
    at_zero = Case("lines/x/lattice", LineScene.from_segments(8, 8, [[0.0, 1.5]], [[6.0, 2.5]]), lattice=True)
    assert "translate" not in [name for name, _, _ in invariance_variants(at_zero)]
    (verdict,) = [r for r in _run(StripAware(Convention()), [case], only={"invariance"}) if r.check == "invariance"]
    assert verdict.status == "fail" and verdict.metrics["split-strips_differences"] > 0, verdict.message


def test_a_width_one_rule_on_wide_lines_is_no_verdict() -> None:
    """A drawer claiming diamond-exit handed lines 2.5 px wide: the rule defines no answer,
    so the convention-bound checks skip with the reason (it should raise Unsupported)."""
    results = _run(OracleLines(Convention(line="rectangle")), [WIDE])
    assert all(r.status == "pass" for r in results if r.check == "conformance")

    class Claims(OracleLines):
        convention = Convention()

        def __init__(self) -> None:
            self.name = "claims_diamond"

        def rasterize(self, scene: LineScene) -> Coverage:
            return exact_coverage(scene, Convention(line="rectangle"))

    by = {r.check: r for r in _run(Claims(), [WIDE])}
    assert {by[c].status for c in {"conformance"} | LINE_CHECKS} == {"skip"}
    assert "width 1" in by["conformance"].message and by["hygiene"].status == "pass"


def test_checks_that_mean_nothing_for_lines_do_not_apply() -> None:
    scene = LineScene.from_segments(8, 8, [[0.5, 0.5], [2.0, 2.0]], [[0.5, 0.5], [np.nan, 3.0]])
    case = Case("degenerate/lines/zero-length", scene, region=None)
    names = {c.name for c in checks(case, only={"overdraw", "watertight", "degenerate", "closed", "triangulation"})}
    assert not names
    assert {c.name for c in checks(case)} >= LINE_CHECKS
    results = _run(OracleLines(Convention()), [case])
    assert all(r.status in ("pass", "skip") for r in results), [(r.check, r.message) for r in results]
