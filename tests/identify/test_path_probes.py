"""identify on path-taking black boxes: first the fill rule drawn for each rule asked (with
the pixel counts as evidence), then the convention for paths through the path interface,
compared with the triangle convention; a triangle-only rasterizer is never sent a path.

The black boxes are the exact oracles, declaring no convention."""

import json

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.protocol import takes
from harness.contract.scenes import PathScene, Scene
from harness.engine.isolation import InProcess
from harness.identify.fingerprint import Identified, identify
from harness.identify.path_probes import _hull, fill_rule_scene, fill_rules, lattice_paths, triangle_paths
from harness.oracle.coverage import exact_coverage


class PathBox:
    """Paths and triangles by the exact oracle: triangles under ``triangles``, paths under
    ``paths`` (the same by default), drawing fill rule ``draws`` whatever it is asked (the
    rule asked when None)."""

    convention = None
    scene_kinds: tuple[str, ...] = ("triangles", "paths")
    fill_rules: tuple[str, ...]  # (none unless set: then only these rules are asked)

    def __init__(self, triangles=Convention(), paths=None, draws=None, name="pathbox"):
        self.triangles, self.paths, self.draws, self.name = triangles, paths or triangles, draws, name
        self.kinds_seen = set()

    def rasterize(self, scene):
        self.kinds_seen.add(scene.kind)
        if isinstance(scene, PathScene):
            return exact_coverage(scene.with_fill_rule(self.draws) if self.draws else scene, self.paths)
        return exact_coverage(scene, self.triangles)


def _union_per_path(cov, owner, n, width, height):
    """The union of coverage ``cov`` whose primitive k belongs to path ``owner[k]``."""
    prim, x, y = cov.pixels()
    mask = np.zeros((n, height, width), dtype=bool)
    mask[owner[prim], y, x] = True
    return Coverage.concat([Coverage.from_mask(p, mask[p]) for p in range(n)])


class HullBox(PathBox):
    """Fills each path's convex hull."""

    def rasterize(self, scene):
        if not isinstance(scene, PathScene):
            return super().rasterize(scene)
        hulls = [[_hull(np.concatenate(scene.contours_of(p)))] for p in range(len(scene))]
        return exact_coverage(PathScene.from_paths(scene.width, scene.height, hulls), self.paths)


class HolesIgnored(PathBox):
    """Fills each contour on its own and takes the union: holes vanish."""

    def rasterize(self, scene):
        if not isinstance(scene, PathScene):
            return super().rasterize(scene)
        each = PathScene(scene.width, scene.height, scene.vertices, scene.contour_sizes, np.arange(scene.contour_sizes.size))
        return _union_per_path(exact_coverage(each, self.paths), scene.contour_path, len(scene), scene.width, scene.height)


class NoEvenOdd(PathBox):
    """Raises when asked for even-odd."""

    def rasterize(self, scene):
        if isinstance(scene, PathScene) and scene.fill_rule == "evenodd":
            raise NotImplementedError("even-odd fill")
        return super().rasterize(scene)


def test_an_honest_rasterizer_is_seen_to_honour_both_rules_and_one_convention():
    box = PathBox()
    fp = identify(box)
    assert fp.fill_rules == {"nonzero": "nonzero", "evenodd": "evenodd"}, fp.card()
    assert fp.path_fit is not None
    assert fp.path_convention == Convention() and fp.path_fit.exact and fp.path_fit.same_as_triangles, fp.card()
    assert fp.exact and fp.convention == Convention()
    # the evidence: every rule's mismatches on the sure pixels, on the card and in the JSON
    assert "asked nonzero: draws nonzero (nonzero: 0 off, evenodd: " in fp.card()
    assert "the same as for triangles" in fp.facts["paths"] and "0 mismatches" in fp.facts["real paths"]
    data = json.loads(json.dumps(fp.to_dict()))
    assert data["fill_rules"] == {"nonzero": "nonzero", "evenodd": "evenodd"}
    assert data["honoured_fill_rules"] == ["nonzero", "evenodd"]
    assert data["path_convention"]["tie"] == "top-left" and data["path_convention"]["same_as_triangles"] is True
    assert [g["fill_rule"] for g in data["path_convention"]["genuine_paths"]] == ["nonzero", "evenodd"]
    wrapped = Identified(box, fp)
    assert wrapped.scene_kinds == ("triangles", "paths") and wrapped.fill_rules == ("nonzero", "evenodd")


def test_always_even_odd_is_seen_and_the_runner_is_handed_only_even_odd():
    box = PathBox(draws="evenodd")
    fp = identify(box)
    assert fp.fill_rules == {"nonzero": "evenodd", "evenodd": "evenodd"}, fp.card()
    assert fp.honoured_fill_rules == ("evenodd",)
    assert "asked nonzero: draws EVENODD, not the rule asked" in fp.facts["fill rules"]
    # the path convention is fitted, and tried on genuine paths, under the honoured rule only
    assert fp.path_fit is not None and fp.path_fit.lattice is not None
    assert fp.path_fit.rule == "evenodd" and [s[0] for s in fp.path_fit.lattice.scores] == ["evenodd"]
    assert fp.path_convention == Convention() and fp.path_fit.exact
    wrapped = Identified(box, fp)
    assert wrapped.fill_rules == ("evenodd",)
    scene = fill_rule_scene("nonzero")
    assert not takes(wrapped, scene) and takes(wrapped, scene.with_fill_rule("evenodd"))
    assert takes(wrapped, Scene(4, 4, np.zeros((0, 3, 2))))


def test_a_path_convention_unlike_the_triangle_one_is_a_finding():
    triangles, paths = Convention(), Convention(tie="top-right", sample=(0.0, 0.0), subpixel_bits=4)
    fp = identify(PathBox(triangles, paths))
    assert fp.convention == triangles and fp.exact, fp.card()
    assert fp.path_fit is not None
    assert fp.path_convention == paths and fp.path_fit.exact and fp.path_fit.same_as_triangles is False, fp.card()
    assert "DIFFERS from triangles" in fp.facts["paths"]
    assert set(fp.to_dict()["path_convention"]["differences"]) == {
        "sample (0.0, 0.0) (triangles: (0.5, 0.5))", "ties top-right (triangles: top-left)", "snapping bits 4 (triangles: None)"}


@pytest.mark.parametrize("box, drawn", [
    (HullBox(), "neither: fills the outline's hull (each path's convex hull)"),
    (HolesIgnored(), "neither: ignores holes (fills each contour on its own, the union)"),
], ids=["hull", "holes"])
def test_fills_that_are_neither_rule_are_named(box, drawn):
    rules = fill_rules(InProcess(box))
    assert rules.drawn == {"nonzero": drawn, "evenodd": drawn} and rules.honoured == ()
    assert "draws NEITHER" in rules.text


def test_dropping_later_contours_is_not_ignoring_holes():
    """Issue 29: a filler that drops every contour after a path's first is named so, not
    "ignores holes" (the overlapping squares tell them apart: the second square is drawn
    by the one, not by the other); one that fills each contour apart, its union, still
    ignores holes (asked nonzero: the model fills each contour by its winding)."""
    from tests.known_bad.paths import PathFillBug

    first = fill_rules(InProcess(PathFillBug("first-contour-only")))
    words = "neither: drops the contours after each path's first (fills the first alone, under the rule asked)"
    assert first.drawn == {"nonzero": words, "evenodd": words}, first.text
    apart = fill_rules(InProcess(PathFillBug("contours-apart")))
    assert apart.drawn["nonzero"] == "neither: ignores holes (fills each contour on its own, the union)", apart.text


def test_the_fill_rule_probe_does_not_depend_on_the_convention():
    # the sure pixels are the same under any sample point, tie rule and snapping
    odd = Convention(sample=(1.0, 1.0), tie="bottom-right", subpixel_bits=0, snap_rounding="floor")
    assert fill_rules(InProcess(PathBox(odd))).honoured == ("nonzero", "evenodd")
    seen = fill_rules(InProcess(PathBox(odd, draws="nonzero"))).seen
    assert [s.label for s in seen] == ["nonzero", "nonzero"]
    assert dict(seen[1].mismatches)["nonzero"] == 0 < dict(seen[1].mismatches)["evenodd"]


class OneContourEach(PathBox):
    """Refuses a scene holding a path of several contours (as Pillow's polygon must)."""

    def rasterize(self, scene):
        if isinstance(scene, PathScene) and np.bincount(scene.contour_path).max(initial=0) > 1:
            raise ValueError("one contour per path")
        return super().rasterize(scene)


def test_a_rasterizer_that_fills_one_contour_per_path_is_judged_on_the_paths_it_takes():
    call = InProcess(OneContourEach(draws="evenodd"))
    rules = fill_rules(call)
    # the pentagrams alone still part the rules; the three two-contour probes are named
    assert rules.drawn == {"nonzero": "evenodd", "evenodd": "evenodd"} and rules.honoured == ("evenodd",)
    assert [label for label, _ in rules.seen[0].unanswered] == [
        "overlapping squares", "ring with a hole wound alike", "ring with a hole wound opposite"]
    assert "refused the overlapping squares" in rules.text and "one contour per path" in rules.text
    genuine = lattice_paths(call, Convention(), ["evenodd"], 0)
    assert genuine.mismatches == 0 and genuine.refused and "one-contour paths per rule" in genuine.text
    assert genuine.scores[0][2] > 0


class OppositeHolesOnly(PathBox):
    """Takes only rings whose hole is wound the other way: where every rule agrees."""

    def rasterize(self, scene):
        if isinstance(scene, PathScene):
            for p in range(len(scene)):
                contours = scene.contours_of(p)
                areas = [float(np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1])) for c in contours]
                if len(contours) != 2 or areas[0] * areas[1] >= 0:
                    raise ValueError("rings with opposite holes only")
        return super().rasterize(scene)


def test_nothing_is_claimed_when_the_paths_answered_cannot_tell_the_rules_apart():
    rules = fill_rules(InProcess(OppositeHolesOnly()))
    assert rules.honoured == ()
    assert rules.drawn["nonzero"] == "unanswered: the paths it answered cannot tell the rules apart"


def test_a_rule_that_raises_is_not_honoured():
    rules = fill_rules(InProcess(NoEvenOdd()))
    assert rules.honoured == ("nonzero",) and rules.drawn["evenodd"].startswith("unanswered: NotImplementedError")
    assert rules.fit_rule == "nonzero"


class TriangleBox:
    convention = None
    name = "triangles-only"

    def __init__(self):
        self.kinds_seen = set()

    def rasterize(self, scene):
        self.kinds_seen.add(scene.kind)
        return exact_coverage(scene, Convention(tie="bottom-left"))


def test_a_triangle_only_rasterizer_is_identified_as_before():
    box = TriangleBox()
    fp = identify(box)
    assert box.kinds_seen == {"triangles"}
    assert fp.fill_rules is None and fp.path_convention is None and fp.honoured_fill_rules is None
    assert not {"fill rules", "paths", "real paths"} & set(fp.facts)
    assert not {"fill_rules", "path_convention", "honoured_fill_rules"} & set(fp.to_dict())
    assert fp.convention == Convention(tie="bottom-left") and fp.exact
    wrapped = Identified(box, fp)
    assert not hasattr(wrapped, "fill_rules") and not takes(wrapped, fill_rule_scene("nonzero"))


class PathsOnly(PathBox):
    scene_kinds = ("paths",)

    def rasterize(self, scene):
        if not isinstance(scene, PathScene):
            raise TypeError("paths only")
        return super().rasterize(scene)


def test_a_paths_only_rasterizer_with_another_tie_rule_is_identified_through_one_contour_paths():
    # a tie rule other than top-left, a corner sample and snapping, recovered through paths
    # alone; only the rule it declares is asked
    hidden = Convention(tie="bottom-right-y-first", sample=(0.0, 1.0), subpixel_bits=8)
    box = PathsOnly(hidden)
    box.fill_rules = ("evenodd",)
    fp = identify(box)
    assert box.kinds_seen == {"paths"}
    assert fp.path_fit is not None
    assert fp.convention == hidden and fp.exact and fp.path_convention == hidden and fp.path_fit.exact, fp.card()
    assert fp.path_fit.same_as_triangles is None and "it takes no triangles" in fp.facts["paths"]
    assert fp.facts["watertight"].startswith("yes")
    assert fp.fill_rules == {"evenodd": "evenodd"} and Identified(box, fp).fill_rules == ("evenodd",)


def test_triangle_paths_cover_what_the_triangles_do():
    positions = np.array([[[1.5, 1.5], [9.0, 2.5], [3.0, 8.5]], [[9.0, 9.0], [2.0, 9.0], [9.0, 2.0]]])
    scene = Scene(12, 12, positions)
    for rule in ("nonzero", "evenodd"):
        assert exact_coverage(triangle_paths(scene, rule), Convention()) == exact_coverage(scene, Convention())


def test_an_identified_black_box_is_judged_on_paths_by_its_path_convention():
    from harness.contract.case import Case
    from harness.contract.protocol import convention_for
    from harness.engine.runner import run_suite

    triangles, paths = Convention(), Convention(tie="top-right", sample=(0.0, 0.0), subpixel_bits=4)
    box = PathBox(triangles, paths, name="split_box")
    wrapped = Identified(box, identify(box))
    square = PathScene.from_paths(8, 8, [[[[1, 1], [6, 1], [6, 6], [1, 6]]]])
    assert convention_for(wrapped, square) == paths and convention_for(wrapped, Scene(8, 8, np.zeros((0, 3, 2)))) == triangles
    cases = [Case("paths/square", square, lattice=True),
             Case("lattice/one", Scene(8, 8, [[[1, 1], [6, 1], [1, 6]]]), lattice=True)]
    verdicts = {r.case: r.status for r in run_suite([wrapped], cases=cases, isolate=False, identify=False, repros=False,
                                                     only={"conformance"})}
    assert verdicts == {"paths/square": "pass", "lattice/one": "pass"}
    # judged by its triangle convention instead, the same path answer fails: the difference is real
    del wrapped.path_convention
    again = run_suite([wrapped], cases=cases[:1], isolate=False, identify=False, repros=False, only={"conformance"})
    assert again[0].status == "fail"
