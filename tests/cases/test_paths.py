"""The path case families (cases.paths): valid scenes that round-trip exactly through JSON,
stable ids, partitions that tile their region exactly, fill rules that differ exactly where
they should, and the path strategy."""

from __future__ import annotations

import fnmatch
import json
import re
from decimal import Decimal
from functools import cache

import numpy as np
from hypothesis import given, settings
from numpy.typing import NDArray

from cases.partitions import partition_cases
from cases.paths import PATH_FAMILIES, partition_flaws, path_cases, quad_grid, rectangle, star
from cases.strategies import path_scenes
from cases.suites import suite
from harness.checks import pixel_classes
from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.conventions import Convention
from harness.contract.scenes import AnyScene, PathScene, Scene
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage
from harness.oracle.winding import FILL_RULES

# the tie rules' four corners and a y-first one, at the centre; and the corner sample
CONVENTIONS = [Convention(), Convention(tie="bottom-right"), Convention(tie="top-right-y-first"), Convention(sample=(0.0, 0.0))]


@cache
def full() -> tuple[Case, ...]:
    return tuple(path_cases(0, full=True))


def by_id() -> dict[str, Case]:
    return {c.id: c for c in full()}


def matching(*patterns: str) -> list[Case]:
    return [c for c in full() if any(fnmatch.fnmatchcase(c.id, p) for p in patterns)]


def masks(scene: AnyScene, convention: Convention = CONVENTIONS[0]) -> NDArray[np.bool_]:
    """(P, H, W) bool: the pixels each path covers, exactly."""
    out = np.zeros((len(scene), scene.height, scene.width), dtype=bool)
    path, x, y = exact_coverage(scene, convention).pixels()
    out[path, y, x] = True
    return out


def alone(contours: list, like: PathScene) -> NDArray[np.bool_]:
    """(H, W): what one path of these contours covers in a scene like ``like``."""
    covered: NDArray[np.bool_] = masks(PathScene.from_paths(like.width, like.height, [contours], like.fill_rule))[0]
    return covered


def bits(scene: PathScene) -> tuple:
    """Everything that makes a path scene, bit for bit (NaN payloads and signed zeros too)."""
    return (scene.width, scene.height, scene.fill_rule, scene.vertices.shape, scene.vertices.view(np.int64).tobytes(),
            scene.contour_sizes.tolist(), scene.contour_path.tolist())


def same_case(a: Case, b: Case) -> bool:
    regions = (a.region is None and b.region is None) or (
        a.region is not None and b.region is not None and a.region.tobytes() == b.region.tobytes())
    return (a.id, a.lattice, a.closed, a.refusable) == (b.id, b.lattice, b.closed, b.refusable) and regions and \
        isinstance(a.scene, PathScene) and isinstance(b.scene, PathScene) and bits(a.scene) == bits(b.scene)


# -- every case ------------------------------------------------------------------------------


def test_every_case_is_a_small_valid_path_scene_that_round_trips_exactly():
    for case in full():
        scene = case.scene
        assert isinstance(scene, PathScene) and case.family in PATH_FAMILIES, case.id
        assert 16 <= scene.width <= 64 and 16 <= scene.height <= 64, case.id
        assert len(case.id.split("/")) >= 4 and case.id.split("/")[-1] == scene.fill_rule, case.id
        # through the constructor again: every field valid
        PathScene(scene.width, scene.height, scene.vertices, scene.contour_sizes, scene.contour_path, scene.fill_rule)
        assert all(0 <= p < len(scene) for p in case.refusable), case.id
        if case.lattice:  # small multiples of 1/8 (1/16: the triangle partitions'): float arithmetic on them is exact
            # (the triangle scenes as paths: the triangle suite's lattices, 1/16 px, reaching 2 px beyond the screen)
            v, scale, reach = (scene.vertices, 16, 66) if "/triangles/" in case.id else (scene.vertices, 8, 64)
            assert np.isfinite(v).all() and np.all(v * scale == np.round(v * scale)) and np.abs(v).max() <= reach, case.id
        back = case_from_json(json.loads(json.dumps(case_to_json(case)), parse_float=Decimal))
        assert isinstance(back, Case) and same_case(case, back), case.id
        exact_coverage(scene, Convention())  # the oracle takes it (no coordinate beyond its fast range)


def test_ids_are_unique_stable_and_free_of_the_seed():
    ids = [c.id for c in full()]
    assert len(ids) == len(set(ids))
    # plain names: --case globs and report paths take them as they are
    assert all(re.fullmatch(r"[a-z0-9.-]+(/[a-z0-9.-]+)+", i) for i in ids)
    assert all(same_case(a, b) for a, b in zip(full(), path_cases(0, full=True), strict=True))  # deterministic
    other = path_cases(7, full=True)
    assert [c.id for c in other] == ids  # the ids do not depend on the seed; the draws do
    assert not same_case(by_id()["paths/star-7-3/float/nonzero"],
                         next(c for c in other if c.id == "paths/star-7-3/float/nonzero"))
    # a quick case is its full namesake, bit for bit, in the full suite's order
    quick = path_cases(0)
    assert [c.id for c in quick] == [i for i in ids if i in {c.id for c in quick}]
    # (the triangle partitions as paths follow the triangle suite's watertight/ family, drawn
    # from one generator in turn: a quick one is its quick namesake, tested below)
    assert all(same_case(c, by_id()[c.id]) for c in quick if not c.id.startswith("path-partitions/triangles/"))
    assert {c.family for c in quick} == set(PATH_FAMILIES)


def test_every_case_comes_under_both_rules_in_the_full_suite():
    """The same geometry under nonzero and evenodd, ids differing in the last part only."""
    cases = by_id()
    for case in full():
        stem, rule = case.id.rsplit("/", 1)
        twin = cases[f"{stem}/{'evenodd' if rule == 'nonzero' else 'nonzero'}"]
        assert bits(twin.scene)[3:] == bits(case.scene)[3:], case.id  # type: ignore[arg-type]
        assert (twin.lattice, twin.refusable) == (case.lattice, case.refusable)


def test_the_suites_hold_the_path_families_between_the_triangles_and_the_lines():
    for name, count in (("quick", (95, 125)), ("full", (200, 270))):  # with the triangle scenes as paths
        cases = suite(name)
        ids = [c.id for c in cases]
        assert len(ids) == len(set(ids)), name
        families = [c.family for c in cases]
        where = [k for k, f in enumerate(families) if f in PATH_FAMILIES]
        assert where == list(range(where[0], where[-1] + 1)), name  # one block
        assert families[where[-1] + 1] == "lines" and families[where[0] - 1] == "degenerate", name
        assert count[0] <= len(where) <= count[1], (name, len(where))
        assert ids[where[0]: where[-1] + 1] == [c.id for c in path_cases(0, name == "full")]


# -- partitions ------------------------------------------------------------------------------


def sample_classes(region: NDArray[np.float64], width: int, height: int, sample: tuple[float, float]) -> tuple[NDArray, NDArray]:
    """(inside, outside), (H, W) bool: pixels whose sample point lies strictly inside the
    convex region, and strictly outside it; decided exactly."""
    y, x = np.mgrid[0:height, 0:width]
    p = np.stack([x.ravel() + sample[0], y.ravel() + sample[1]], axis=-1).astype(np.float64)
    m = region.shape[0]
    side = np.array([orientation(np.stack([np.broadcast_to(region[k], p.shape),
                                           np.broadcast_to(region[(k + 1) % m], p.shape), p], axis=1))
                     for k in range(m)])
    sign = orientation(region[None, :3])[0]  # a convex region's corners all turn its way
    return np.all(side == sign, axis=0).reshape(height, width), np.any(side == -sign, axis=0).reshape(height, width)


def tiling_errors(scene: PathScene, region: NDArray[np.float64], convention: Convention) -> dict[str, int]:
    """Pixels hit twice; samples strictly inside the region not hit once; samples strictly
    outside hit; pixels that differ from the region's own coverage (the samples on its
    outline too); and the watertight check's pixel classes (squares wholly inside / outside)."""
    counts = exact_coverage(scene, convention).counts(scene.width, scene.height)
    inside, outside = sample_classes(region, scene.width, scene.height, convention.sample)
    whole = masks(PathScene.from_paths(scene.width, scene.height, [[region]], scene.fill_rule), convention)[0]
    square_in, square_out = pixel_classes(region, scene.width, scene.height)
    return {"doubles": int((counts > 1).sum()), "holes": int((inside & (counts != 1)).sum()),
            "strays": int((outside & (counts > 0)).sum()),
            "unlike_region": int((counts != whole).sum()), "square_holes": int((square_in & (counts != 1)).sum()),
            "square_strays": int((square_out & (counts > 0)).sum())}


def test_partitions_tile_their_region_exactly():
    partitions = [c for c in matching("path-partitions/*") if not c.id.startswith("path-partitions/triangles/")]
    assert len(partitions) == 22  # with the pies (issue 34: glyph-like pieces for the AA seams)
    for case in partitions:
        scene, region = case.scene, case.region
        assert isinstance(scene, PathScene) and region is not None
        # each cell its own path of one contour
        assert scene.contour_path.tolist() == list(range(len(scene))), case.id
        assert partition_flaws(scene.contours(), region) is None, case.id
        inside_pixels = 0
        for convention in CONVENTIONS:
            errors = tiling_errors(scene, region, convention)
            assert not any(errors.values()), (case.id, convention.tie, convention.sample, errors)
            inside_pixels += int(sample_classes(region, scene.width, scene.height, convention.sample)[0].sum())
        assert inside_pixels > 4 * 900, case.id  # most of the 48 x 48 viewport: the check has teeth


def test_the_triangle_partitions_come_as_paths_the_way_identify_sends_them():
    """Every triangle partition of the suite, each triangle a one-contour path under each
    rule: the scenes identify's watertight probe sends a paths-only rasterizer."""
    from harness.identify.path_probes import triangle_paths

    for complete in (False, True):
        triangles = partition_cases(0, complete)
        as_paths = {c.id: c for c in path_cases(0, complete) if c.id.startswith("path-partitions/triangles/")}
        assert len(as_paths) == 2 * len(triangles)
        for case in triangles:
            for rule in ("nonzero", "evenodd"):
                twin = as_paths[f"path-partitions/triangles/{case.id.split('/', 1)[1]}/{rule}"]
                assert isinstance(twin.scene, PathScene) and isinstance(case.scene, Scene)
                assert twin.region is not None and case.region is not None
                assert bits(twin.scene) == bits(triangle_paths(case.scene, rule))
                assert twin.lattice == case.lattice and np.array_equal(twin.region, case.region)


def test_the_tiling_checks_fail_on_broken_partitions():
    """Both the exact proof and the oracle's pixel count catch a missing cell, a doubled
    cell and one cell's copy of a shared vertex moved; the proof also refuses a
    T-junction and a cell that crosses itself."""
    cells, region = quad_grid(5, 4.0, 44.0, "lattice", np.random.default_rng(3))
    assert partition_flaws(cells, region) is None

    def scene(parts: list) -> PathScene:
        return PathScene.from_paths(48, 48, [[c] for c in parts], "nonzero")

    moved = [c.copy() for c in cells]
    moved[6][0, 0] += 1.0  # grid point (1, 1), shared by cells 0, 1, 5 and 6: in cell 6 only
    for broken, kind in ((cells[:12] + cells[13:], "holes"), (cells + [cells[12]], "doubles"), (moved, None)):
        assert partition_flaws(broken, region) is not None
        errors = tiling_errors(scene(broken), region, Convention())
        assert errors[kind] > 0 if kind else errors["holes"] + errors["doubles"] > 0, errors
    # a rectangle's right half split in two: an exact tiling, but with a T-junction at (1, 1)
    t_junction = [rectangle(0, 0, 1, 2), rectangle(1, 0, 2, 1), rectangle(1, 1, 2, 2)]
    assert partition_flaws(t_junction, rectangle(0, 0, 2, 2)) is not None
    assert partition_flaws([np.array([[0, 0], [2, 0], [0, 2], [2, 2]])],
                           rectangle(0, 0, 2, 2)) == "cell 0 is not a simple polygon"


# -- fill rules ------------------------------------------------------------------------------

# the pixels the two rules cover differ (some winding is even and nonzero) ...
DIFFER = ["paths/star-*", "paths/ring/*hole-same/*", "paths/overlap/squares-same/*", "paths/zero-length-edges/doubled-vertices/*",
          "paths/huge/ring-*", "paths/huge/star-*", "paths/epsilon/star-*", "paths/epsilon/hole-*", "paths/several/*",
          "path-degenerate/duplicate-contours/same/*", "paths/deep-winding/*", "paths/glyph/o-with-bar/*",
          "paths/glyph/o-with-bar-6px/*", "paths/glyph/d-curves/*", "paths/glyph/d-curves-9px/*", "paths/glyph/text-line/*",
          "paths/sub-pixel/star-*"]
# ... or they agree (windings 0 and +-1 only)
AGREE = ["paths/simple/*", "paths/bow-tie/*", "paths/ring/*hole-opposite/*", "paths/overlap/squares-opposite/*",
         "paths/collinear/*", "paths/zero-length-edges/closed-*", "paths/spike/*", "paths/tiny-contours/*", "paths/huge/wedge-*",
         "paths/epsilon/triangles-*", "path-partitions/*", "path-degenerate/*", "paths/triangles/*",
         "paths/glyph/o-with-bar-sub-pixel/*", "paths/ring/hairline/*", "paths/glyph/d-curves-sub-pixel/*", "paths/stroke/*",
         "paths/sliver/*", "paths/sub-pixel/ring-*", "paths/huge/band-*", "paths/huge/glyph-*"]


def test_evenodd_covers_a_subset_of_nonzero_and_they_differ_exactly_where_they_should():
    cases = by_id()
    for case in matching("*/nonzero"):
        nonzero = masks(case.scene)
        evenodd = masks(cases[case.id.rsplit("/", 1)[0] + "/evenodd"].scene)
        assert not (evenodd & ~nonzero).any(), case.id  # an odd winding is nonzero
        differ = any(fnmatch.fnmatchcase(case.id, p) for p in DIFFER)
        agree = not differ and any(fnmatch.fnmatchcase(case.id, p) for p in AGREE)
        assert (differ or agree) == (not case.id.startswith(("paths/random/", "paths/overlap/three-"))), case.id
        if differ:
            assert (nonzero & ~evenodd).any(), case.id
        elif agree:
            assert (nonzero == evenodd).all(), case.id


def test_the_pentagram_centre_is_nonzero_only():
    for case in matching("paths/star-5-2/*/nonzero", "paths/epsilon/star-*/nonzero"):
        assert isinstance(case.scene, PathScene)
        (centre,) = case.scene.contours()
        x, y = np.floor(centre.mean(axis=0)).astype(int)
        twin = by_id()[case.id.replace("/nonzero", "/evenodd")]
        assert masks(case.scene)[0, y, x] and not masks(twin.scene)[0, y, x], case.id
    # the 1e-9 px pentagram around the sample of pixel (10, 12): that pixel, only under nonzero
    tiny = by_id()["paths/epsilon/star-1e-9-on-sample/nonzero"]
    assert np.argwhere(masks(tiny.scene)[0]).tolist() == [[12, 10]]
    assert not masks(by_id()["paths/epsilon/star-1e-9-on-sample/evenodd"].scene).any()
    # the square with a 1e-9 px hole wound its way: the hole's pixel under nonzero only
    hole = [masks(by_id()[f"paths/epsilon/hole-1e-9/{rule}"].scene)[0] for rule in FILL_RULES]
    assert np.argwhere(hole[0] & ~hole[1]).tolist() == [[15, 15]]


def test_degenerate_contours_change_nothing():
    """Spikes, collinear and doubled vertices, one- and two-vertex contours: the same
    pixels as the plain contour, under every tie rule; the degenerate catalogue's bad paths
    cover nothing, its anchors what they cover alone."""
    ids = by_id()
    plain = {"paths/spike/out-and-in/lattice": [rectangle(6, 6, 26, 26)],
             "paths/collinear/square-extra-vertices/lattice": [rectangle(4, 4, 28, 28)],
             "paths/tiny-contours/one-and-two-vertices/lattice": [rectangle(4, 4, 20, 20)],
             "paths/zero-length-edges/doubled-vertices/lattice": [np.round(star(7, 2, (16, 16), 12.0) * 4) / 4]}
    for stem, contours in plain.items():
        for rule in FILL_RULES:
            scene = ids[f"{stem}/{rule}"].scene
            assert isinstance(scene, PathScene)
            for convention in CONVENTIONS:
                got = masks(scene, convention)
                same = masks(PathScene.from_paths(scene.width, scene.height, [contours], rule), convention)[0]
                assert (got[0] == same).all() and not got[1:].any(), (stem, rule, convention.tie)
    anchors = PathScene.from_paths(32, 32, [[rectangle(1.5, 1.5, 8.0, 6.0)], [[[23.0, 24.0], [30.5, 26.5], [25.25, 31.0]]]])
    expected = masks(anchors)
    assert expected.any(axis=(1, 2)).all()
    for case in matching("path-degenerate/*"):
        if case.id.startswith("path-degenerate/triangles/"):
            continue  # identify's triangle probes as paths: no anchors (the triangle suite's degenerate/.../probe*)
        assert isinstance(case.scene, PathScene)
        got = masks(case.scene)
        assert (got[:2] == expected).all(), case.id
        covering = [p for p in range(2, len(case.scene)) if got[p].any()]
        if "/figure-8/" in case.id:
            assert covering == [2], case.id
        elif case.id.endswith("/duplicate-contours/same/nonzero"):  # winding 2: what one copy covers
            assert covering == [2] and (got[2] == alone(case.scene.contours_of(2)[:1], case.scene)).all()
        elif "/non-finite/" in case.id:
            assert covering == [len(case.scene) - 1], case.id  # only the last path, all finite
        else:
            assert covering == [], case.id


# -- the strategy ----------------------------------------------------------------------------


@settings(max_examples=30, deadline=None)
@given(path_scenes())
def test_path_scenes_draw_lattice_paths_that_round_trip(scene):
    assert isinstance(scene, PathScene) and scene.fill_rule in FILL_RULES
    assert 1 <= len(scene) <= 3 and scene.contour_sizes.min() >= 1 and scene.contour_sizes.max() <= 8
    assert np.bincount(scene.contour_path).max() <= 3
    v = scene.vertices
    assert np.all(v * 4 == np.round(v * 4)) and v.min() >= -2 and v.max() <= 14
    case = Case("paths/strategy/" + scene.fill_rule, scene, lattice=True)
    back = case_from_json(json.loads(json.dumps(case_to_json(case)), parse_float=Decimal))
    assert isinstance(back, Case) and same_case(case, back)
    other = scene.with_fill_rule("evenodd" if scene.fill_rule == "nonzero" else "nonzero")
    nonzero, evenodd = (masks(s) for s in ((scene, other) if scene.fill_rule == "nonzero" else (other, scene)))
    assert not (evenodd & ~nonzero).any()


# -- the anti-aliased cases of issue 34: the exact area is defined on each ---------------------

AA_CASES = ["paths/glyph/*", "paths/stroke/*", "paths/sliver/*", "paths/sub-pixel/*", "paths/huge/band-*",
            "paths/huge/glyph-*", "paths/ring/hairline/*", "path-partitions/pie-*"]


def test_the_exact_area_is_defined_on_the_anti_aliased_cases():
    """Every glyph-like, stroke, sliver, sub-pixel, huge and pie case: the float area oracle
    takes it, each pixel's area within its proven bound (below 2**-24) of the rational
    reference at a spread of pixels, and a pie's pieces sum to exactly 1 inside."""
    from fractions import Fraction

    from harness.oracle.path_area import LOOSE_BOUND, exact_path_area, path_pixel_areas

    cases = matching(*AA_CASES)
    assert len(cases) >= 30
    for case in cases:
        scene = case.scene
        assert isinstance(scene, PathScene)
        p, x, y, area, bound = path_pixel_areas(scene)
        assert area.size and np.all((area > 0) & (area <= 1)) and float(bound.max()) < LOOSE_BOUND, case.id
        for i in np.unique(np.linspace(0, area.size - 1, 6).astype(int)):
            exact = exact_path_area(scene.contours_of(int(p[i])), scene.fill_rule, int(x[i]), int(y[i]))
            assert abs(Fraction(float(area[i])) - exact) <= Fraction(float(bound[i])), (case.id, int(x[i]), int(y[i]))
        if case.region is not None:  # a pie: the wedges of a pixel wholly inside sum to 1
            inside, _ = pixel_classes(case.region, scene.width, scene.height)
            cy, cx = (int(v) for v in np.argwhere(inside)[len(np.argwhere(inside)) // 2])
            total = sum((exact_path_area(scene.contours_of(k), scene.fill_rule, cx, cy) for k in range(len(scene))),
                        Fraction(0))
            assert total == 1, case.id


def test_the_glyph_d_is_wound_as_a_font_winds_it():
    """The "D": outline clockwise, counter against it, the overlapping stem like the
    outline -- winding 2 in the overlap (nonzero fills it, even-odd leaves a hole), 0 in
    the counter, 1 in the stem beside the counter."""
    from cases.paths import glyph_d, polygon_sign
    from harness.oracle.path_area import exact_path_area

    contours = glyph_d((0, 0), 100.0)
    assert [polygon_sign(c) for c in contours] == [1, -1, 1]
    # pixels in the overlap, the counter, the stem beside the counter, the outline's stem alone
    pixels = [(10, 50), (40, 50), (20, 50), (2, 50)]
    assert [exact_path_area(contours, "nonzero", x, y) for x, y in pixels] == [1, 0, 1, 1]
    assert [exact_path_area(contours, "evenodd", x, y) for x, y in pixels] == [0, 0, 1, 1]
