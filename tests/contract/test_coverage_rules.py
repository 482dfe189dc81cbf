"""The coverage rules as conventions (issue 33, point 2): declared through Convention,
validated, described, round-tripped; the checks expect their own holes and double hits;
known-bad rasterizers of each rule are caught; paths and lines refuse cleanly."""

from __future__ import annotations

import dataclasses
import functools
import json
import pickle

import numpy as np
import pytest

from harness.checks import closed_balance, conformance, overdraw, watertight
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import AREA_THRESHOLD, CLOSED, CONSERVATIVE_OVER, CONSERVATIVE_UNDER, COVERAGE_RULES
from harness.contract.scenes import LineScene, PathScene, Scene
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage
from tests.known_bad.coverage_rules import BoxOverestimate, OpenUnderestimate, StrictThreshold

RULES = {"area-threshold": Convention(coverage="area-threshold"),
         "conservative-over": Convention(coverage="conservative-over", subpixel_bits=8),
         "conservative-under": Convention(coverage="conservative-under", cull="cw")}


def test_each_rule_is_declared_by_its_name_and_gets_its_model():
    assert {n: m for n, m in COVERAGE_RULES.items() if m.input_bits is None} == {
        "area-threshold": AREA_THRESHOLD, "conservative-over": CONSERVATIVE_OVER, "conservative-under": CONSERVATIVE_UNDER,
        "closed": CLOSED}
    for name, convention in RULES.items():
        assert convention.model is COVERAGE_RULES[name] and convention.coverage_kind == "single"
        model = convention.model
        assert model.rule and not model.sample_point and not model.exactly_once
        assert not (model.single_sample or model.sample_ids or model.alphas or model.interpolates or model.paths
                    or model.lines)
    # nothing changes for the existing conventions
    assert Convention().threshold == 0.5 and repr(Convention()) == \
        "Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none')"
    assert not Convention().model.rule and Convention().model.exactly_once and Convention().model.sample_point


def test_declarations_are_validated_in_one_line():
    with pytest.raises(ValueError, match=r"^Convention.threshold must be a number in \[2\*\*-20, 1\], not 0$"):
        Convention(coverage="area-threshold", threshold=0)
    with pytest.raises(ValueError, match=r"^Convention.threshold must be a number in \[2\*\*-20, 1\], not 1.5$"):
        Convention(coverage="area-threshold", threshold=1.5)
    with pytest.raises(ValueError, match=r"coverage rule of one answer per pixel: it takes no samples"):
        Convention(coverage="conservative-over", samples=4)
    with pytest.raises(ValueError, match=r"^Convention.coverage must be one of sample, area, area-threshold"):
        Convention(coverage="conservative")  # type: ignore[arg-type]


def test_described_and_round_tripped():
    assert Convention(coverage="area-threshold", threshold=0.25, subpixel_bits=4).describe() == \
        "an area threshold (a pixel iff at least 0.25 of it is covered), snapped to 1/16 px (4 bits), no culling"
    assert RULES["conservative-under"].describe() == \
        "conservative underestimate (a pixel iff its square lies in the triangle), no snapping, culls cw"
    assert repr(RULES["conservative-over"]).endswith("subpixel_bits=8, cull='none', coverage='conservative-over')")
    for convention in [*RULES.values(), Convention(coverage="area-threshold", threshold=0.375)]:
        fields = {f.name: getattr(convention, f.name) for f in dataclasses.fields(convention) if f.name != "line"}
        again = Convention(**json.loads(json.dumps(fields)))
        assert again == convention and again.model is convention.model
        assert pickle.loads(pickle.dumps(convention)) == convention
        assert eval(repr(convention)) == convention  # noqa: S307 - the repr is the declaration


# a planar partition: a 4 x 4 square cut along its diagonal and then its halves again
_SCENE = Scene(6, 6, [[[1, 1], [5, 1], [3, 3]], [[5, 1], [5, 5], [3, 3]],
[[5, 5], [1, 5], [3, 3]], [[1, 5], [1, 1], [3, 3]]])
_PARTITION = Case("partitions/rules/fan", _SCENE, lattice=True, region=np.array([[1.0, 1.0], [5.0, 1.0], [5.0, 5.0], [1.0, 5.0]]))


@pytest.mark.parametrize("name", list(RULES))
def test_watertight_and_overdraw_expect_the_rules_own_holes_and_double_hits(name):
    convention = RULES[name] if name != "conservative-under" else Convention(coverage="conservative-under")
    own = exact_coverage(_PARTITION.scene, convention)
    counts = own.counts(6, 6)
    if name == "conservative-over":
        assert counts.max() == 4  # the centre pixels touch all four triangles
    if name == "conservative-under":
        assert (counts[1:5, 1:5] == 0).any()  # the squares the diagonals cross are in no triangle
    result = watertight(_PARTITION, own, convention, lambda: own)
    assert result.status == "pass" and result.metrics.get("rule_own", 0) > 0, result.message
    assert "the rule's own" in result.message
    assert overdraw(_PARTITION, own, convention, lambda: own).status == "pass"
    # a hole or a double hit the rule does not have is still one
    twice = Coverage.concat([own, own])
    assert watertight(_PARTITION, twice, convention, lambda: own).status == "fail"
    assert overdraw(_PARTITION, twice, convention, lambda: own).status == "fail"
    # and single-sample conventions are judged as before: no excuse without snapping
    assert watertight(_PARTITION, own, Convention(), lambda: own).status == ("pass" if counts[1:5, 1:5].min() == 1
                                                                             and counts.max() == 1 else "fail")


def test_closed_expects_the_rules_own_imbalance():
    """A closed "mesh": the four-triangle fan in front, the square as two triangles behind.
    Under a rule, front and back hits differ where the triangulations do: the rule's own."""
    back = np.array([[[1.0, 1.0], [5.0, 5.0], [5.0, 1.0]], [[1.0, 1.0], [1.0, 5.0], [5.0, 5.0]]])
    scene = Scene(6, 6, np.concatenate([_SCENE.positions, back]))
    case = Case("meshes/rules/sandwich", scene, lattice=True, closed=True)
    for convention in RULES.values():
        convention = dataclasses.replace(convention, cull="none")
        own = exact_coverage(scene, convention)
        assert closed_balance(case, own, convention).status == "fail"  # unexcused, the rule's own imbalance fails
        assert closed_balance(case, own, convention, functools.partial(exact_coverage, scene, convention)).status == "pass"
    assert closed_balance(case, exact_coverage(scene, Convention()), Convention()).status == "pass"


@pytest.mark.parametrize("bad", [StrictThreshold, BoxOverestimate, OpenUnderestimate])
def test_each_known_bad_rasterizer_is_caught_by_conformance(bad):
    rasterizer = bad()
    scene = Scene(8, 8, [[[0, 0], [6, 0], [0, 6]], [[2, 2], [8, 3], [3, 8]], [[1, 7], [7, 7], [4, 4]]])
    case = Case("rules/known-bad", scene, lattice=True)
    oracle = exact_coverage(scene, rasterizer.convention)
    result = conformance(case, rasterizer.rasterize(scene), oracle, rasterizer.convention)
    assert result.status == "fail" and result.metrics["wrong"] > 0, result.message
    # the default tolerance excuses nothing as a near tie under a coverage rule, off the lattice too
    off = Case("rules/known-bad-off-lattice", scene, lattice=False)
    assert conformance(off, rasterizer.rasterize(scene), oracle, rasterizer.convention).metrics["near_tie"] == 0


def test_paths_and_lines_refuse_cleanly():
    from harness.oracle.lines import line_coverage
    from harness.oracle.winding import path_coverage

    square = PathScene.from_paths(4, 4, [[[[0, 0], [4, 0], [4, 4], [0, 4]]]])
    line = LineScene.from_strips(6, 4, [[[0.5, 0.5], [4.5, 2.5]]])
    for convention in RULES.values():
        with pytest.raises(ValueError, match=r"coverage of paths is not defined yet \(triangles only\)$"):
            path_coverage(square, convention)
        with pytest.raises(ValueError, match="lines are defined for single-sample and multisample conventions"):
            line_coverage(line, convention)


# --- identify's rule probes ---------------------------------------------------------------


class _Oracular:
    """A rasterizer that is its convention's exact oracle."""

    def __init__(self, convention: Convention) -> None:
        self.convention = convention

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(scene, self.convention)


@pytest.mark.parametrize("convention", [
    Convention(coverage="area-threshold"), Convention(coverage="area-threshold", threshold=0.25, subpixel_bits=8),
    Convention(coverage="conservative-over"), Convention(coverage="conservative-under", subpixel_bits=4,
                                                           snap_rounding="floor")])
def test_identify_tells_the_rules_apart(convention):
    from harness.identify.rule_probes import fit_rule

    fit = fit_rule(_Oracular(convention).rasterize)
    assert fit.exact and fit.convention.model is convention.model, fit.describe()
    if convention.coverage_uses_threshold:
        assert fit.convention.threshold == convention.threshold
    # the other rules are off (but a threshold just below 1: on snapped input no area lies between it and 1, and
    # a threshold of 1 is the underestimate)
    assert fit.runner_up is not None
    assert fit.runner_up[1] > 0 or (convention.model is CONSERVATIVE_UNDER and fit.runner_up[0].threshold > 0.99)


def test_identify_separates_the_orientations_of_a_winding_dependent_rule():
    """A rasterizer drawing clockwise triangles by one threshold and counter-clockwise ones
    by another (as matplotlib's aliased Agg does: any area against 1/256)."""
    from harness.identify.rule_probes import fit_rule

    cw, ccw = Convention(coverage="area-threshold", threshold=2.0**-10), Convention(coverage="area-threshold")

    def rasterize(scene: Scene) -> Coverage:
        clockwise = orientation(scene.positions)[0] > 0
        return exact_coverage(scene, cw if clockwise else ccw)

    fit = fit_rule(rasterize)
    assert not fit.exact
    assert {side: (c.threshold, off) for side, (c, off) in fit.by_orientation.items()} == {"cw": (2.0**-10, 0),
                                                                                          "ccw": (0.5, 0)}


def test_identify_does_not_call_a_known_bad_rasterizer_exact():
    from harness.identify.rule_probes import fit_rule

    for bad in (BoxOverestimate(), OpenUnderestimate()):
        fit = fit_rule(bad.rasterize)
        assert not (fit.exact and fit.convention == bad.convention), fit.describe()


def test_a_plugin_declaring_a_rule_for_paths_or_lines_is_refused_in_its_words():
    from harness.contract.declarations import declaration_problem

    class Drawer:
        name = "rule_drawer"
        convention = Convention(coverage="conservative-over")
        scene_kinds: tuple[str, ...] = ("triangles", "paths")
        fill_rules: tuple[str, ...] | None = ("nonzero",)

        def rasterize(self, scene: Scene) -> Coverage:
            return Coverage.empty()

    said = declaration_problem(Drawer())
    assert said is not None and "conservative overestimate" in said and "triangles only" in said, said
    Drawer.scene_kinds, Drawer.fill_rules = ("triangles", "lines"), None
    said = declaration_problem(Drawer())
    assert said is not None and "declares an area threshold" not in said and "conservative overestimate" in said, said
    Drawer.scene_kinds = ("triangles",)
    assert declaration_problem(Drawer()) is None


def test_a_stray_the_snapped_overestimate_has_is_its_own():
    """A partition's outline 1/1024 px right of x = 1, snapped to 1/256: the snapped mesh
    touches column 0, which lies wholly outside the (unsnapped) region."""
    x0 = 1.0 + 2.0**-10
    scene = Scene(6, 4, [[[x0, 1.0], [5.0, 1.0], [x0, 3.0]], [[5.0, 1.0], [5.0, 3.0], [x0, 3.0]]])
    case = Case("partitions/rules/snapped-out", scene, lattice=False,
                region=np.array([[x0, 1.0], [5.0, 1.0], [5.0, 3.0], [x0, 3.0]]))
    convention = Convention(coverage="conservative-over", subpixel_bits=8)
    own = exact_coverage(scene, convention)
    assert own.counts(6, 4)[:, 0].any()  # column 0 touched
    result = watertight(case, own, convention, lambda: own)
    assert result.status == "pass" and result.metrics["strays"] == 0 and result.metrics["rule_own"] > 0, result.message
    # unsnapped, column 0 is not touched, and drawing it is a stray
    exact = Convention(coverage="conservative-over")
    drawn = Coverage.concat([exact_coverage(scene, exact), Coverage(np.array([0]), np.array([1]), np.array([0]), np.array([1]))])
    assert watertight(case, drawn, exact, lambda: exact_coverage(scene, exact)).metrics["strays"] == 1


@pytest.mark.parametrize("bad, cause", [(StrictThreshold, "rule-boundary"), (OpenUnderestimate, "rule-boundary"),
                                        (BoxOverestimate, "coverage-rule")])
def test_the_diagnosis_names_the_rules_boundary(bad, cause):
    """A known-bad rasterizer's conformance failure is classified against its rule: exactly
    on the rule's boundary (a threshold met exactly, corners on an edge) or away from it."""
    from harness.diagnose.signatures import signature

    rasterizer = bad()
    scene = Scene(8, 8, [[[0, 0], [6, 0], [0, 6]], [[2, 2], [8, 3], [3, 8]], [[1, 7], [7, 7], [4, 4]]])
    case = Case("rules/known-bad", scene, lattice=True)
    result = conformance(case, rasterizer.rasterize(scene), exact_coverage(scene, rasterizer.convention),
                         rasterizer.convention)
    assert signature(result, case, rasterizer.convention).failure_class == cause


# --- the conservative rules' uncertainty region -------------------------------------------


def test_the_uncertainty_region_is_declared_validated_and_described():
    c = Convention(coverage="conservative-over", uncertainty=2.0**-8, subpixel_bits=8)
    assert c.describe() == ("conservative overestimate (a pixel iff its square meets the triangle), uncertainty 0.00390625 "
                            "px, snapped to 1/256 px (8 bits), no culling")
    assert eval(repr(c)) == c and "uncertainty=0.00390625" in repr(c)  # noqa: S307
    assert Convention(coverage="conservative-over").uncertainty == 0.0
    with pytest.raises(ValueError, match=r"^Convention.uncertainty is a conservative rule's"):
        Convention(coverage="area-threshold", uncertainty=2.0**-8)
    with pytest.raises(ValueError, match=r"^Convention.uncertainty must be a multiple of 2\*\*-16 in \[0, 1/2\], not 0.001$"):
        Convention(coverage="conservative-under", uncertainty=0.001)


class _Drawing:
    """A rasterizer drawing a fixed answer per scene: what the rule must or may draw."""

    def __init__(self, convention: Convention, which: int, grow: float | None = None) -> None:
        self.convention, self.which, self.grow = convention, which, grow

    def rasterize(self, scene: Scene) -> Coverage:
        from harness.oracle.coverage_rules import uncertainty_bounds

        drawn = self.convention if self.grow is None else dataclasses.replace(self.convention, uncertainty=self.grow)
        return uncertainty_bounds(scene, drawn)[self.which]


# vertices 1/512 px and 3/512 px short of whole pixels (squares in the 1/256 band and beyond it, outside), and an
# edge 3/512 px past one (a square inside by that margin)
_NEAR = Scene(8, 6, [[[0.5, 0.5], [3.0 - 2.0**-9, 0.5], [0.5, 2.5]], [[4.0, 1.0], [7.0 - 3 * 2.0**-9, 1.0], [4.0, 5.0]],
                     [[-4.0, 1.0], [3.0 + 3 * 2.0**-9, 1.0], [3.0 + 3 * 2.0**-9, 9.0]]])


@pytest.mark.parametrize("rule", ["conservative-over", "conservative-under"])
def test_conformance_judges_between_what_the_rule_must_and_may_draw(rule):
    declared = Convention(coverage=rule, uncertainty=2.0**-8)
    exact = Convention(coverage=rule)
    case = Case("rules/uncertain", _NEAR, lattice=True)
    # drawing the other bound of the region: allowed under the region, wrong without it
    other = 1 if rule == "conservative-over" else 0
    answer = _Drawing(declared, other).rasterize(_NEAR)
    assert answer != exact_coverage(_NEAR, exact)
    ok = conformance(case, answer, exact_coverage(_NEAR, declared), declared)
    assert ok.status == "pass" and ok.metrics["uncertain"] > 0 and "uncertainty region" in ok.message, ok.message
    assert conformance(case, answer, exact_coverage(_NEAR, exact), exact).status == "fail"
    # a region twice as wide as declared: the squares beyond 1/256 are wrong
    beyond = _Drawing(declared, other, grow=2.0**-7).rasterize(_NEAR)
    bad = conformance(case, beyond, exact_coverage(_NEAR, declared), declared)
    assert bad.status == "fail" and bad.metrics["wrong"] > 0, bad.message


def test_watertight_allows_the_regions_double_hits_and_strays():
    declared = Convention(coverage="conservative-over", uncertainty=2.0**-8)
    x0 = 1.0 + 2.0**-10  # the outline 1/1024 px right of column 0: reached by the region
    scene = Scene(6, 4, [[[x0, 1.0], [5.0, 1.0], [x0, 3.0]], [[5.0, 1.0], [5.0, 3.0], [x0, 3.0]]])
    case = Case("partitions/rules/uncertain", scene, lattice=False,
                region=np.array([[x0, 1.0], [5.0, 1.0], [5.0, 3.0], [x0, 3.0]]))
    may = _Drawing(declared, 1).rasterize(scene)
    assert may.counts(6, 4)[:, 0].any()
    oracle = exact_coverage(scene, declared)
    result = watertight(case, may, declared, lambda: oracle)
    assert result.status == "pass" and result.metrics["strays"] == 0, result.message
    assert watertight(case, may, Convention(coverage="conservative-over"), lambda: oracle).status == "fail"
    assert overdraw(case, may, declared, lambda: oracle).status == "pass"


def test_closed_allows_the_regions_imbalance():
    back = np.array([[[1.0, 1.0], [5.0, 5.0], [5.0, 1.0]], [[1.0, 1.0], [1.0, 5.0], [5.0, 5.0]]])
    fan = _SCENE.positions + np.array([2.0**-9, 0.0])  # 1/512 px right: the region reaches column 0's neighbours
    scene = Scene(7, 6, np.concatenate([fan, back]))
    case = Case("meshes/rules/uncertain", scene, lattice=True, closed=True)
    declared = Convention(coverage="conservative-over", uncertainty=2.0**-8)
    may = _Drawing(declared, 1).rasterize(scene)
    oracle = functools.partial(exact_coverage, scene, declared)
    assert closed_balance(case, may, declared, oracle).status == "pass"
    exact = Convention(coverage="conservative-over")
    assert closed_balance(case, may, exact, functools.partial(exact_coverage, scene, exact)).status == "fail"


class _Named(_Oracular):
    name = "oracular_rule"


@pytest.mark.parametrize("convention", [Convention(coverage="area-threshold", threshold=0.25),
                                        Convention(coverage="conservative-over", subpixel_bits=8)])
def test_identify_calls_a_rule_following_rasterizer_exact_by_its_rule(convention):
    """identify itself (not only the probes): the sample-point fit leaves a residual, the
    rule probes replace it, the card says so and the sample point is the runner-up."""
    from harness.identify.fingerprint import identify

    fingerprint = identify(_Named(convention))
    assert fingerprint.exact, fingerprint.card()
    assert fingerprint.convention.model is convention.model
    assert fingerprint.runner_up is not None and fingerprint.runner_up[1] > 0
    assert "explains it better than any sample point" in fingerprint.facts["coverage rule"]


def test_identify_keeps_the_sample_point_when_no_rule_explains_it_better():
    """A sample-point rasterizer with one fault: the rule probes are asked, and lose."""
    from harness.identify.fingerprint import identify

    class OnePixelOff(_Oracular):
        name = "one_pixel_off"

        def rasterize(self, scene: Scene) -> Coverage:
            good = exact_coverage(scene, self.convention)
            if not len(good):  # one more pixel at the end of the first span
                return good
            return Coverage(good.primitive, good.y, good.x0, good.x1 + (np.arange(len(good)) == 0))

    fingerprint = identify(OnePixelOff(Convention()))
    assert not fingerprint.exact
    assert fingerprint.convention.model.sample_point
    assert "no better than the sample point" in fingerprint.facts["coverage rule"]


def test_identify_fits_the_lines_of_a_rasterizer_whose_triangles_follow_a_rule():
    """A coverage rule defines no lines: the line fit starts from the sample point, input and
    snapping beside the rule (it once raised), and finds the lines' own rule."""
    from harness.identify.fingerprint import identify

    class ClosedTrianglesDiamondLines:
        name = "closed_with_lines"
        convention = None
        scene_kinds = ("triangles", "lines")

        def rasterize(self, scene):
            if isinstance(scene, LineScene):
                return exact_coverage(scene, Convention())
            return exact_coverage(scene, Convention(coverage="closed"))

    fingerprint = identify(ClosedTrianglesDiamondLines())
    assert fingerprint.convention.coverage == "closed" and fingerprint.exact, fingerprint.card()
    assert fingerprint.line_convention is not None and fingerprint.line_convention.line.rule == "diamond-exit"
    assert fingerprint.line_fit is not None and fingerprint.line_fit.residual == 0
