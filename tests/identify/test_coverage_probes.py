"""identify tells the kind of coverage from outside: an analytic anti-aliaser from a
supersampler (recovering its grid and levels) and a multisample rasterizer's pattern, in
its sample order, with its tie rule. The test rasterizers are the exact oracle of a
hidden convention, declaring none."""

from dataclasses import replace

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import Scene
from harness.engine.isolation import InProcess
from harness.identify.area_probes import CONTINUOUS_LEVELS, SweepFact, alpha_sweeps
from harness.identify.coverage_probes import coverage_kind
from harness.identify.fingerprint import identify
from harness.identify.sample_probes import SampleSides, sample_positions
from harness.oracle.coverage import exact_coverage


class Hidden:
    """The exact oracle of a convention it does not declare; ``levels`` rounds its alphas
    to multiples of 1/(levels - 1), as an 8-bit alpha buffer does."""

    convention = None

    def __init__(self, convention: Convention, levels: int | None = None) -> None:
        self.hidden, self.levels = convention, levels
        self.name = f"hidden-{convention.coverage_kind}"

    def rasterize(self, scene: Scene) -> Coverage:
        cov = exact_coverage(scene, self.hidden)
        if self.levels is None:
            return cov
        step = self.levels - 1
        assert cov.alpha is not None
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, alpha=np.round(cov.alpha * step) / step)


class Supersampler:
    """An n x n box-filter supersampler (alpha = share of the grid's samples covered, top-left
    ties): more samples than a convention holds, so it is summed from patterns of 32."""

    convention = None

    def __init__(self, n: int) -> None:
        self.name = f"supersampler-{n}x{n}"
        grid = [((i + 0.5) / n, (j + 0.5) / n) for j in range(n) for i in range(n)]
        self.grid = grid
        self.parts = [Convention(samples=grid[k:k + 32]) for k in range(0, len(grid), 32)]

    def rasterize(self, scene: Scene) -> Coverage:
        w, h = scene.width, scene.height
        keys = []
        for part in self.parts:
            t, x, y = exact_coverage(scene, part).pixels()
            keys.append((t * h + y) * w + x)
        key, count = np.unique(np.concatenate(keys), return_counts=True)
        t, rest = np.divmod(key, w * h)
        return Coverage.from_pixels(t, rest % w, rest // w, alpha=count / len(self.grid))


class SnappedArea:
    """An anti-aliaser that rounds its input to 1/2**bits px (half to even, as FreeType's
    26.6 outline from a caller's lrint) and returns the exact area of the rounded scene
    (:mod:`harness.oracle.area`, through the exact oracle of that scene), in 256 levels."""

    convention = None

    def __init__(self, bits: int = 6) -> None:
        self.bits = bits
        self.name = f"area-input-grid-{bits}"

    def rasterize(self, scene: Scene) -> Coverage:
        scale = 2.0**self.bits
        rounded = Scene(scene.width, scene.height, np.rint(scene.positions * scale) / scale)
        cov = exact_coverage(rounded, Convention(coverage="area"))
        assert cov.alpha is not None
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, alpha=np.round(cov.alpha * 255) / 255)


GRID4 = tuple(((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4))
MIRRORED = tuple((1.0 - x, y) for x, y in STANDARD_PATTERNS[4])  # the known-bad "mirrored sample pattern"
SWAPPED = tuple(STANDARD_PATTERNS[4][k] for k in (1, 0, 3, 2))  # the standard offsets, sample bits swapped
# dEQP's 2x pattern (rrRasterizer.cpp: samples at 0.3 and 0.7, snapped to its 8 sub-pixel
# bits: 77/256 and 179/256, odd multiples of the snapping step)
DEQP2 = ((77 / 256, 77 / 256), (179 / 256, 179 / 256))


def test_coverage_kind_reads_what_the_answer_carries():
    assert coverage_kind(InProcess(Hidden(Convention()))).coverage_kind == "single"
    eight = coverage_kind(InProcess(Hidden(Convention(samples=8))))
    assert (eight.coverage_kind, eight.samples, eight.indices, eight.per_pixel) == ("multisample", 8, tuple(range(8)), (8,))
    assert coverage_kind(InProcess(Hidden(Convention(coverage="area")))).coverage_kind == "area"
    assert coverage_kind(InProcess(Hidden(Convention(samples=4, cull="cw")))).samples == 4  # the other winding is read

    class Raises:
        name, convention = "raises", None

        def rasterize(self, scene):
            raise RuntimeError("no")

    raised = coverage_kind(InProcess(Raises()))
    assert raised.coverage_kind is None and "RuntimeError" in raised.text


@pytest.mark.parametrize("hidden, said", [
    (Convention(samples=4), "the standard 4x pattern (D3D11"),
    (Convention(samples=MIRRORED), "the standard 4x pattern MIRRORED in x"),
    (Convention(samples=SWAPPED), "the standard 4x offsets in ANOTHER ORDER"),
    (Convention(samples=8, tie="bottom-right-y-first"), "the standard 8x pattern"),
    (Convention(samples=4, subpixel_bits=8), "bisected to 2^-8 px"),  # the snapping grid's spacing
    # each sample read at the end of its bisection interval that explains it (not the coarser one)
    (Convention(samples=DEQP2, subpixel_bits=8, snap_rounding="half-away"), "2 samples"),
    # truncation to 1/8 px shows as the vertex sweep's grid of 1/8, as rounding to 1/4 would: the
    # bisection stops at 1/4 and the samples at odd eighths lie inside their intervals
    (Convention(samples=4, subpixel_bits=3, snap_rounding="floor"), "the standard 4x pattern"),
    (Convention(samples=[(0.25, 0.5), (0.75, 0.25), (0.5, 0.875)], tie="top-right", cull="cw"), "3 samples"),
], ids=lambda c: c.describe() if isinstance(c, Convention) else "")
def test_identify_recovers_a_multisample_pattern_exactly_in_its_order(hidden, said):
    fingerprint = identify(Hidden(hidden))
    assert fingerprint.coverage_kind == "multisample"
    assert fingerprint.convention == hidden and fingerprint.exact, fingerprint.card()
    assert said in fingerprint.facts["pattern"]
    if hidden.cull == "none":  # culling leaves half a partition out
        assert fingerprint.facts["watertight"].startswith("every sample: yes")
    assert fingerprint.to_dict()["samples"] == [list(o) for o in hidden.samples]
    sides = fingerprint.probes["sample sides"]
    assert isinstance(sides, SampleSides)
    assert not sides.dropped  # a pattern, mirrored or not, is seen alike from both sides


def _undeclared(bad):
    """The known-bad with its declaration taken away: identify reads it from outside."""
    bad.convention = None
    return bad


def test_samples_dropped_near_edges_are_no_wrong_pattern():
    """Issue 29: a multisample rasterizer rejecting pixels whose centre lies just outside an
    edge (a margin too small for its samples' reach) drops samples next to edges; read
    under left and top edges its offsets look like another pattern, but right and bottom
    edges find them elsewhere: the card says samples are dropped near edges, not that the
    pattern is not the standard one."""
    from tests.known_bad.antialiasing import RejectsNearEdges

    fingerprint = identify(_undeclared(RejectsNearEdges()))
    said = fingerprint.facts["pattern"]
    assert said.startswith("SAMPLES DROPPED NEAR EDGES") and "not the standard" not in said, said
    sides = fingerprint.probes["sample sides"]
    assert isinstance(sides, SampleSides)
    assert sides.dropped and not fingerprint.exact


def test_a_card_with_samples_sharing_an_offset_never_claims_a_pattern():
    """Issue 29: all four samples at the pixel centre: the pattern is not recovered, and
    the card says so everywhere -- no standard pattern identified, no residual scored, the
    convention checked against named a stand-in."""
    from tests.known_bad.antialiasing import CentreSamples

    fingerprint = identify(_undeclared(CentreSamples()))
    card = fingerprint.card()
    assert fingerprint.pattern_missing and not fingerprint.exact
    assert "samples 0, 1, 2, 3 all at (0.5, 0.5)" in fingerprint.facts["pattern"], card
    assert "NOT RECOVERED" in card and "a stand-in" in card and "not scored" in card, card
    assert "identified" not in card and "best guess" not in card and "standard 4x pattern" not in card, card
    from harness.cli.run import _convention_text
    from harness.identify.fingerprint import Identified

    said = _convention_text(Identified(CentreSamples(), fingerprint))  # what run prints for it
    assert "no multisample pattern recovered" in said and "a stand-in" in said and "identified" not in said, said


def test_sample_positions_bisects_every_sample_at_once():
    fact = sample_positions(InProcess(Hidden(Convention(samples=4))), 4)
    assert fact.offsets == STANDARD_PATTERNS[4] and fact.resolution == 20 and fact.residual == 0
    # the vertex sweep on sample 0 is most of it; the bisection costs resolution + 2 calls
    assert fact.calls < 400, fact.calls


@pytest.mark.parametrize("levels", [None, 256])
def test_identify_recovers_analytic_area_and_its_levels(levels):
    fingerprint = identify(Hidden(Convention(coverage="area"), levels))
    sweeps = fingerprint.probes["sweeps"]
    assert isinstance(sweeps, SweepFact)
    assert fingerprint.coverage_kind == "area" and sweeps.model == "analytic", fingerprint.card()
    assert fingerprint.convention == Convention(coverage="area", levels=levels or CONTINUOUS_LEVELS)
    assert fingerprint.exact and sweeps.levels == levels
    assert sweeps.vertical is not None and sweeps.horizontal is not None
    assert sweeps.vertical.levels >= 256 and sweeps.horizontal.levels >= 256  # about a level per 1/256 px step
    assert sweeps.max_error <= (0.5 / 255 if levels else 2.0**-24)
    assert fingerprint.to_dict()["levels"] == (levels or CONTINUOUS_LEVELS)
    assert fingerprint.facts["input grid"].startswith("none detected")  # no snapping read into rounding noise


def test_identify_finds_an_anti_aliasers_input_grid():
    # FreeType's 26.6 input: the sweeps step in 64ths, at odd multiples of 1/128 px; against the
    # exact area of the vertices as given many alphas lie beyond half a level, against that of
    # the scene rounded to 1/64 px none
    fingerprint = identify(SnappedArea(6))
    swept = fingerprint.probes["sweeps"]
    assert isinstance(swept, SweepFact)
    grid = swept.grid
    assert grid is not None
    assert fingerprint.convention == Convention(coverage="area", levels=256, subpixel_bits=6), fingerprint.card()
    assert fingerprint.exact and (grid.bits, grid.rounding, grid.beyond) == (6, "nearest-even", 0) and grid.unsnapped > 0
    assert fingerprint.facts["input grid"].startswith("1/64 px (26.6), rounding half to even;")
    assert "snapped to 1/64 px (6 bits)" in fingerprint.card()


@pytest.mark.parametrize("hidden, levels, layout, sweep_levels", [
    (Convention(coverage="area", samples=GRID4), 17, "regular 4 x 4 grid (16 samples)", (5, 5)),
    (Convention(coverage="area", samples=4), 5, "4-rooks (every sample in a column and row of its own)", (5, 5)),
    # an input grid of 1/256 px: the steps lie half a grid step from the samples (issue 29)
    (Convention(coverage="area", samples=GRID4, subpixel_bits=8), 17, "regular 4 x 4 grid (16 samples)", (5, 5)),
], ids=["4x4 grid", "4-rooks", "4x4 grid, 8 bits"])
def test_identify_recovers_a_supersampling_grid(hidden, levels, layout, sweep_levels):
    fingerprint = identify(Hidden(hidden))
    sweeps = fingerprint.probes["sweeps"]
    assert isinstance(sweeps, SweepFact)
    assert sweeps.model == "supersampled" and sweeps.layout == layout, fingerprint.card()
    assert sweeps.vertical is not None and sweeps.horizontal is not None and sweeps.pattern is not None
    assert (sweeps.vertical.levels, sweeps.horizontal.levels) == sweep_levels  # n + 1 and m + 1
    assert set(sweeps.pattern) == set(hidden.samples)
    # the shares of 16 (4) samples are multiples of 1/16 (1/4): that is their quantisation
    assert sweeps.levels == levels and fingerprint.convention == replace(hidden, levels=levels)
    assert fingerprint.exact, fingerprint.card()


def test_a_supersampler_quantised_to_8_bits_keeps_its_grid():
    fingerprint = identify(Hidden(Convention(coverage="area", samples=GRID4), 256))
    sweeps = fingerprint.probes["sweeps"]
    assert isinstance(sweeps, SweepFact) and sweeps.pattern is not None
    assert sweeps.model == "supersampled" and set(sweeps.pattern) == set(GRID4), fingerprint.card()
    assert fingerprint.convention == Convention(coverage="area", samples=GRID4) and fingerprint.exact


def test_analytic_area_is_told_from_4x4_and_8x8_supersampling():
    analytic = alpha_sweeps(InProcess(Hidden(Convention(coverage="area"), 256)))
    coarse = alpha_sweeps(InProcess(Supersampler(4)))
    fine = alpha_sweeps(InProcess(Supersampler(8)))
    assert analytic.model == "analytic" and coarse.model == fine.model == "supersampled"
    assert (coarse.layout, fine.layout) == ("regular 4 x 4 grid (16 samples)", "regular 8 x 8 grid (64 samples)")
    assert fine.pattern is not None and fine.vertical is not None and fine.horizontal is not None
    assert fine.convention is not None
    assert set(fine.pattern) == set(Supersampler(8).grid) and fine.levels == 65
    assert (fine.vertical.levels, fine.horizontal.levels) == (9, 9)
    # 64 samples, more than a multisample convention holds: a supersampled area convention
    # holds them (MAX_AREA_SAMPLES), identified exactly
    assert set(fine.convention.samples) == set(Supersampler(8).grid) and fine.residual == 0
    assert analytic.max_error < 1 / 256 < fine.max_error < coarse.max_error
    assert analytic.calls <= 5 and coarse.calls <= 30 and fine.calls <= 30  # one call per sweep or bisection step


def test_single_sample_identify_is_unchanged():
    fingerprint = identify(Hidden(Convention()))
    assert fingerprint.coverage_kind == "single" and "coverage" not in fingerprint.facts and "kind" not in fingerprint.to_dict()
    assert fingerprint.exact and fingerprint.convention == Convention()


def test_an_anti_aliaser_that_raises_on_the_sweeps_is_never_claimed():
    class RaisesOnBigScenes(Hidden):
        def rasterize(self, scene):
            if len(scene) > 100:
                raise MemoryError("too many triangles")
            return super().rasterize(scene)

    fingerprint = identify(RaisesOnBigScenes(Convention(coverage="area")))
    assert fingerprint.coverage_kind == "area" and not fingerprint.exact
    assert "MemoryError" in fingerprint.facts["model"]


def test_an_anti_aliaser_taking_lines_is_judged_against_the_area_of_its_strokes():
    """identify cannot fit aliased line rules to alphas; the identified area convention then
    judges lines by the one anti-aliased line model, the butt-capped rectangle's exact area
    (a diamond-exit line rule under area coverage has no oracle: the atlas once stopped on it)."""
    from harness.contract.conventions import Convention, LineRule
    from harness.contract.scenes import LineScene
    from harness.identify.fingerprint import identify
    from harness.oracle.coverage import exact_coverage

    class AreaWithLines:
        name = "area_with_lines"
        convention = None
        scene_kinds = ("triangles", "lines")

        def rasterize(self, scene):
            line = LineRule("rectangle") if isinstance(scene, LineScene) else LineRule()
            return exact_coverage(scene, Convention(coverage="area", line=line))

    fingerprint = identify(AreaWithLines())
    assert fingerprint.convention.model.alphas and fingerprint.convention.line.rule == "rectangle", fingerprint.card()
    assert "butt-capped rectangle" in fingerprint.facts["line model"]
    segment = LineScene.from_segments(8, 8, [[1.0, 1.5]], [[6.0, 4.0]])
    assert exact_coverage(segment, fingerprint.convention).alpha is not None  # judged, not refused


def test_a_supersampler_taking_lines_has_its_lines_judged_against_the_exact_stroke_area():
    """A supersampler's grid defines no lines (skia's AA mode once errored on every line
    case: "lines are defined for single-sample and multisample conventions, not area
    coverage"); identify gives its lines the analytic line model within the triangles'
    measured error, and the Identified wrapper judges line scenes by it. A line convention
    the plugin declares beats the identified one."""
    from dataclasses import replace

    from harness.contract.conventions import Convention, LineRule
    from harness.contract.protocol import convention_for
    from harness.contract.scenes import LineScene
    from harness.identify.fingerprint import Identified, identify
    from harness.oracle.coverage import exact_coverage

    grid = [((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4)]
    supersampled = Convention(coverage="area", samples=grid)

    class SupersamplerWithLines:
        name = "supersampler_with_lines"
        convention = None
        scene_kinds = ("triangles", "lines")

        def rasterize(self, scene):
            if isinstance(scene, LineScene):
                return exact_coverage(scene, Convention(coverage="area", line=LineRule("rectangle")))
            return exact_coverage(scene, supersampled)

    inner = SupersamplerWithLines()
    fingerprint = identify(inner)
    assert fingerprint.convention.model.name == "supersampled area", fingerprint.card()
    lines = fingerprint.line_convention
    assert lines is not None and lines.model.name == "area" and lines.line.rule == "rectangle", fingerprint.card()
    assert "defines no lines" in fingerprint.facts["line model"]
    assert lines.alpha_tolerance >= getattr(fingerprint.probes["sweeps"], "max_error")  # noqa: B009
    segment = LineScene.from_segments(8, 8, [[1.0, 1.5]], [[6.0, 4.0]])
    judged = convention_for(Identified(inner, fingerprint), segment)
    assert judged is not None and exact_coverage(segment, judged).alpha is not None  # judged, not refused

    declared = replace(lines, tolerance=1 / 255)
    inner.line_convention = declared  # type: ignore[attr-defined]
    assert convention_for(Identified(inner, fingerprint), segment) == declared.for_lines()


def test_an_area_on_a_quarter_pixel_grid_is_read_as_snapping_not_as_samples_on_the_pixel_edge():
    """An analytic filler snapping to 1/4 px steps at 0.25, 0.5, 0.75 and 1: identify once
    built a sample pattern of those steps and raised ("sample offset (1.0, 0.25) lies
    outside the pixel"); a step on the pixel's edge is no sample, and the area on its input
    grid is identified exactly."""
    from harness.identify.fingerprint import identify
    from tests.known_bad.aa_paths import QuarterPixelPathFiller

    class BlackBox:
        name = "quarter_pixel_black_box"
        convention = None
        scene_kinds = QuarterPixelPathFiller.scene_kinds

        def rasterize(self, scene):
            return QuarterPixelPathFiller().rasterize(scene)

    fingerprint = identify(BlackBox())
    assert fingerprint.exact and fingerprint.convention.samples is None, fingerprint.card()
    assert (fingerprint.convention.subpixel_bits, fingerprint.convention.snap_rounding) == (2, "floor")
