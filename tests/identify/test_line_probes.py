"""identify on line-taking black boxes: the line rule (diamond-exit, Bresenham with its end
point rounding, tie direction and last pixel, rectangle with its sample point and tie rule)
and the snapping in front of it, recovered from outside; a box that takes only lines is sent
nothing else; a line drawer that follows no rule gets a best guess with a residual.

The black boxes are the exact oracles, declaring no convention."""

import json
from dataclasses import replace

import numpy as np
import pytest

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.protocol import convention_for
from harness.contract.scenes import LineScene, Unsupported
from harness.engine.isolation import InProcess
from harness.identify.fingerprint import Fingerprint, Identified, _with_lines, identify
from harness.identify.line_probes import crafted_lines, line_candidates, nudged_lines
from harness.oracle.coverage import exact_coverage


class LineBox:
    """Lines by the exact oracle of ``lines`` (width 1 only unless rectangular: a wider
    scene is refused, as a real width-1 drawer does); triangles, when given a convention
    for them, by ``triangles``."""

    convention = None

    def __init__(self, lines, triangles=None, name="linebox"):
        self.lines, self.triangles, self.name = lines, triangles, name
        self.scene_kinds = ("lines",) if triangles is None else ("triangles", "lines")
        self.kinds_seen = set()

    def rasterize(self, scene):
        self.kinds_seen.add(scene.kind)
        if scene.kind != "lines":
            return exact_coverage(scene, self.triangles)
        if self.lines.line.rule not in ("rectangle", "parallelogram", "llvmpipe-rectangle") and scene.line_width != 1.0:
            raise Unsupported(f"width 1 only, not {scene.line_width:g}")
        return exact_coverage(scene, self.lines)


class RoundingDDA(LineBox):
    """Broken: a float DDA stepping max(|dx|, |dy|) + 1 points along the segment and taking
    the pixel each lies in -- no rule's end points, ties or last pixel."""

    def __init__(self):
        super().__init__(Convention(line="bresenham"), name="rounding-dda")

    def rasterize(self, scene):
        self.kinds_seen.add(scene.kind)
        a, b = scene.segments()
        steps = np.ceil(np.abs(b - a).max(axis=1)).astype(np.int64)
        prim = np.repeat(np.arange(len(scene)), steps + 1)
        t = (np.arange(prim.size) - np.repeat(np.cumsum(steps + 1) - steps - 1, steps + 1)) / np.maximum(steps[prim], 1)
        x, y = np.floor(a[prim] + t[:, None] * (b - a)[prim]).astype(np.int64).T
        inside = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
        key = np.unique((prim[inside] * scene.height + y[inside]) * scene.width + x[inside])
        return Coverage.from_pixels(key // (scene.width * scene.height), key % scene.width, key // scene.width % scene.height)


class Refuses(LineBox):
    def rasterize(self, scene):
        raise Unsupported("no lines today")


# each rule; Bresenham's roundings, two tie directions, two last-pixel rules and three directions
# of travel in eight boxes (every value of each at least once, in different company); snapping
# in front of each rule
DECLARED = [
    Convention(line=LineRule("diamond-exit")),
    Convention(line=LineRule("diamond-exit", last_pixel=True), subpixel_bits=8),
    Convention(line=LineRule("bresenham", last_pixel=True, rounding="nearest-even", ties="step")),
    Convention(line=LineRule("bresenham", last_pixel=False, rounding="nearest-even", ties="stay"), subpixel_bits=8),
    Convention(line=LineRule("bresenham", last_pixel=False, rounding="half-away", ties="step")),
    Convention(line=LineRule("bresenham", last_pixel=True, rounding="half-away", ties="stay")),
    Convention(line=LineRule("bresenham", last_pixel=True, rounding="floor", ties="step")),
    Convention(line=LineRule("bresenham", last_pixel=False, rounding="floor", ties="stay")),
    # textbook plotLine: the direction of travel normalised (issue 28)
    Convention(line=LineRule("bresenham", last_pixel=False, rounding="toward-zero", ties="step", direction="smaller-x")),
    Convention(line=LineRule("bresenham", last_pixel=True, rounding="half-away", ties="stay", direction="smaller-major"),
               subpixel_bits=4),
    Convention(line="rectangle"),
    Convention(sample=(0.0, 0.0), tie="bottom-right-y-first", line="rectangle", subpixel_bits=4, snap_rounding="half-away"),
    # off the 9 usual sample points: measured by a segment's end swept across a pixel (issue 29)
    Convention(sample=(0.25, 0.75), line="rectangle"),
    Convention(sample=(0.375, 0.125), tie="top-right", line="rectangle", subpixel_bits=8, snap_rounding="half-away"),
    # odd multiples of the snapping step: the swept end flips half a step off them (76.5/256)
    Convention(sample=(77 / 256, 179 / 256), line="rectangle", subpixel_bits=8, snap_rounding="half-away"),
    # Vulkan's non-strict lines (issue 33)
    Convention(line="parallelogram"),
    Convention(tie="bottom-right", line="parallelogram", subpixel_bits=8, snap_rounding="half-away"),
    # skia's hairlines and Qt's cosmetic lines, read from their sources (issue 33)
    Convention(line="skia-hairline"),
    Convention(line="qt-cosmetic"),
    # llvmpipe's (lavapipe's) rectangular lines: its own snapping (issue 33)
    Convention(line="llvmpipe-rectangle"),
    Convention(tie="bottom-right", line="llvmpipe-rectangle"),
]


@pytest.mark.parametrize("declared", DECLARED, ids=[c.describe_lines() for c in DECLARED])
def test_identify_recovers_the_declared_line_convention_exactly(declared):
    box = LineBox(declared)
    fp = identify(box)
    assert fp.line_convention == declared and fp.line_rule == declared.line, fp.card()
    assert fp.line_fit is not None and fp.runner_up is not None
    assert fp.exact and fp.line_fit.exact and fp.residual == 0 and fp.runner_up[1] > 0, fp.card()
    assert fp.convention == declared and fp.lines_only
    assert box.kinds_seen == {"lines"}  # a lines-only box is sent nothing else
    said = fp.to_dict()
    json.dumps(said)
    assert said["line_rule"] == declared.line.describe() and said["convention"] == declared.describe_lines()
    line = said["line_convention"]
    assert line["rule"] == declared.line.rule and line["exact"] and line["subpixel_bits"] == declared.subpixel_bits
    assert dict(fp.line_fit.rule_scores)[declared.line.rule] == 0
    assert "(identified exactly)" in fp.card() and fp.card().splitlines()[1].endswith(declared.describe_lines())
    wide = fp.line_fit.wide  # width 3: drawn as rectangles, refused by a width-1 rule
    assert wide is not None
    if declared.line.rule in ("rectangle", "parallelogram", "llvmpipe-rectangle"):
        assert wide.error == "" and wide.mismatches == 0 and wide.pixels > 0, wide.text
    else:
        assert wide.text.startswith("width 3: refused (Unsupported: width 1 only"), wide.text


def test_the_probe_scenes_part_every_pair_of_candidate_rules():
    """No two unsnapped candidates draw the crafted scene alike: the rule fit can tell each
    from every other whatever the random lattice scenes hold."""
    scene = crafted_lines()
    seen: dict[bytes, list[Convention]] = {}
    for candidate in line_candidates():
        prim, x, y = exact_coverage(scene, candidate).pixels()
        key = (prim * scene.height + y) * scene.width + x
        seen.setdefault(np.sort(key).tobytes(), []).append(candidate)
    alike = [group for group in seen.values() if len(group) > 1]
    # llvmpipe's rectangles differ from the exact ones by their snapped normal only, which no
    # quarter-pixel lattice shows: the nudged and float scenes part them (below)
    twins = [group for group in alike if len(group) == 2 and {c.line.rule for c in group} == {"rectangle", "llvmpipe-rectangle"}
             and group[0].sample == group[1].sample and group[0].tie == group[1].tie]
    alike = [group for group in alike if group not in twins]
    assert not alike, [[c.describe_lines() + f" {c.sample} {c.tie}" for c in group] for group in alike]
    nudged = nudged_lines(0)
    for rectangle, llvmpipe in twins:
        one, other = (exact_coverage(nudged, replace(c, subpixel_bits=8)).pixels() for c in (rectangle, llvmpipe))
        assert set(zip(*(v.tolist() for v in one))) != set(zip(*(v.tolist() for v in other)))


def test_a_dda_that_follows_no_rule_gets_a_best_guess_with_a_residual():
    box = RoundingDDA()
    fp = identify(box)
    assert not fp.exact and fp.residual > 0 and fp.line_rule is not None, fp.card()
    assert "best guess only" in fp.card() and "best guess only" in fp.facts["lines"]
    assert not fp.to_dict()["line_convention"]["exact"]


def test_a_box_that_refuses_every_line_is_never_claimed():
    fp = identify(Refuses(Convention()))
    assert fp.line_rule is None and fp.line_convention is None and not fp.exact and fp.residual > 0
    assert fp.facts["lines"].startswith("not fitted: unanswered: Unsupported: no lines today")
    assert fp.to_dict()["line_convention"] is None


def test_triangles_and_lines_each_by_their_own_convention():
    """A box that takes both: the triangle fingerprint as before, the line rule put in its
    convention, and the line convention (its own snapping) kept apart and used to judge
    lines."""
    triangles = Convention(subpixel_bits=8)
    lines = Convention(line=LineRule("bresenham", ties="stay"))
    box = LineBox(lines, triangles)
    fp = identify(box)
    assert box.kinds_seen == {"triangles", "lines"}
    assert fp.exact and fp.convention == Convention(subpixel_bits=8, line=lines.line), fp.card()
    assert fp.line_fit is not None
    assert fp.line_convention == lines and fp.line_fit.exact and not fp.lines_only
    assert fp.line_fit.differences == ("snapping bits None (triangles: 8)",)
    assert fp.to_dict()["line_convention"]["same_as_triangles"] is False
    judged = Identified(box, fp)
    assert judged.line_convention == lines and not hasattr(judged, "path_convention")
    assert convention_for(judged, LineScene.from_segments(4, 4, [[0, 0]], [[3, 1]])) == lines


def test_a_snapping_no_line_shows_is_taken_to_be_the_triangles():
    """Floor snapping in front of Bresenham's floor rounding changes no pixel: the line fit
    then keeps the triangles' snapping, and the line convention is the triangle one with
    its line rule (nothing apart to judge lines by)."""
    triangles = Convention(subpixel_bits=8, snap_rounding="floor", cull="cw")
    lines = Convention(line=LineRule("bresenham", rounding="floor"), subpixel_bits=8, snap_rounding="floor", cull="cw")
    fp = Fingerprint("box", triangles, 0, 1, ("another", 3))
    _with_lines(fp, InProcess(LineBox(lines, triangles)), 0)
    assert fp.line_fit is not None
    assert fp.line_convention == lines and fp.convention == lines and fp.line_fit.same_as_triangles, fp.card()
    assert not hasattr(Identified(LineBox(lines, triangles), fp), "line_convention")


def test_lines_rounding_otherwise_than_the_triangles_say_so_in_their_rule():
    """lavapipe: triangles snap to 1/256 px to nearest-even, line ends half away. The line
    fit puts the rounding in its rule, so the triangle convention with that rule draws the
    lines exactly (one convention for both)."""
    triangles = Convention(subpixel_bits=8)
    lines = Convention(line="parallelogram", subpixel_bits=8, snap_rounding="half-away")
    box = LineBox(lines, triangles)
    fp = identify(box)
    assert fp.exact and fp.line_fit is not None and fp.line_fit.exact, fp.card()
    assert fp.line_rule == LineRule("parallelogram", snap_rounding="half-away"), fp.card()
    assert fp.convention == Convention(subpixel_bits=8, line=LineRule("parallelogram", snap_rounding="half-away"))
    assert fp.line_fit.differences == ("snap rounding half-away (triangles: nearest-even)",)
    scene = LineScene.from_strips(16, 16, [[[0.5 + 1 / 512, 1.5 - 1 / 512], [13.5 + 3 / 512, 7.5 + 1 / 512]]])
    assert (exact_coverage(scene, fp.convention).counts(16, 16) == exact_coverage(scene, lines).counts(16, 16)).all()
    judged = convention_for(Identified(box, fp), scene)
    assert judged is not None and judged.snap_rounding == "half-away"


def test_a_lines_only_anti_aliaser_is_fingerprinted_by_the_exact_stroke_area():
    """A rasterizer taking only lines whose answers carry alphas (GL smooth lines,
    mesa_llvmpipe_smooth) was once fingerprinted as an aliased diamond-exit best guess,
    "residual 1 of 0"; it is judged by the one anti-aliased line model: the exact strokes
    are exact, a minor-axis box is a best guess within its measured error."""
    from dataclasses import replace

    from harness.identify.fingerprint import identify
    from tests.known_bad.aa_lines import ExactAALines, MajorAxisBoxLines

    exact = ExactAALines()
    exact.convention = None  # type: ignore[assignment]  # a black box: identify must find it
    fingerprint = identify(exact)
    assert fingerprint.coverage_kind == "area" and fingerprint.convention.line.rule == "rectangle", fingerprint.card()
    assert fingerprint.exact and fingerprint.pixels > 0 and fingerprint.convention.tolerance is None
    assert "butt-capped rectangle" in fingerprint.facts["line model"]

    boxed = MajorAxisBoxLines()
    boxed.convention = None  # type: ignore[assignment]
    guess = identify(boxed)
    assert not guess.exact and guess.residual > 0, guess.card()
    assert guess.convention.alpha_tolerance > replace(guess.convention, tolerance=None).alpha_tolerance
