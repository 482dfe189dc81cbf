"""The line case families (cases.lines): stable unique ids, deterministic scenes, the three
families, honest lattice and refusable marks, and exact JSON round trips."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cases.lines import LINE_FAMILIES, REFUSABLE_FROM, fan, line_cases, spiral, zigzag
from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.scenes import LineScene


@pytest.fixture(scope="module")
def quick() -> list[Case]:
    return line_cases(0)


@pytest.fixture(scope="module")
def full() -> list[Case]:
    return line_cases(0, full=True)


def _same_scene(a: LineScene, b: LineScene) -> bool:
    """Identical floats (NaN in the same places), strips, viewport and width."""
    return (a.width, a.height, a.line_width) == (b.width, b.height, b.line_width) \
        and np.array_equal(a.strip_sizes, b.strip_sizes) and a.vertices.shape == b.vertices.shape \
        and np.array_equal(a.vertices, b.vertices, equal_nan=True)


def _on_lattice(scene: LineScene, scale: int = 16) -> bool:
    v = scene.vertices * scale
    return bool(np.isfinite(v).all() and np.all(v == np.round(v)))


def test_ids_are_unique_and_hierarchical(quick, full):
    for cases in (quick, full):
        ids = [c.id for c in cases]
        assert len(ids) == len(set(ids))
        assert all(len(i.split("/")) >= 3 for i in ids)
    assert {c.family for c in quick} == {c.family for c in full} == set(LINE_FAMILIES)
    assert all(isinstance(c.scene, LineScene) for c in full)


def test_cases_are_deterministic_and_the_quick_suite_is_part_of_the_full(quick, full):
    again = line_cases(0)
    assert [c.id for c in again] == [c.id for c in quick]
    assert all(_same_scene(u.scene, v.scene) for u, v in zip(quick, again))  # type: ignore[arg-type]
    other_seed = line_cases(1)
    assert [c.id for c in other_seed] == [c.id for c in quick]  # ids do not depend on the seed
    by_id = {c.id: c for c in full}
    for case in quick:
        assert _same_scene(case.scene, by_id[case.id].scene), case.id
    assert len(full) > len(quick)


def test_quick_suite_is_small(quick):
    assert 30 <= len(quick) <= 45
    for case in quick:
        assert max(case.scene.width, case.scene.height) <= 64 and len(case.scene) <= 400, case.id


def test_every_kind_of_case_is_there(quick):
    ids = {c.id for c in quick}
    for wanted in ("lines/octants/centres", "lines/octants/corners", "lines/ties/through-diamond-corners",
                   "lines/float/near-ties-1e-6", "lines/float/sub-pixel", "lines/float/across-viewport",
                   "lines/wide-2.5/lattice", "lines/wide-0.25/lattice", "line-strips/closed/square-and-diamond",
                   "line-strips/spiral/lattice", "line-strips/zigzag/diagonal-centres", "line-strips/star/lattice-5-2",
                   "line-degenerate/zero-length/lattice", "line-degenerate/epsilon/1e-9", "line-degenerate/huge/1e10",
                   "line-degenerate/huge/1e200-two", "line-degenerate/non-finite/mixed"):
        assert wanted in ids
    by_id = {c.id: c for c in quick}
    # closed loops: the last vertex is the first, so the closing joint exists
    loops = by_id["line-strips/closed/square-and-diamond"].scene
    assert isinstance(loops, LineScene) and len(loops.joints(closed=True)) == len(loops.joints()) + 2
    assert by_id["line-degenerate/non-finite/mixed"].non_finite


def test_wide_cases_have_their_own_ids(full):
    for case in full:
        assert isinstance(case.scene, LineScene)
        assert (case.scene.line_width != 1.0) == ("wide" in case.id), case.id


def test_lattice_marks_are_honest(full):
    for case in full:
        if case.lattice:
            assert _on_lattice(case.scene), case.id
    # the test can fail: float cases are off the lattice
    assert not _on_lattice(next(c for c in full if c.id == "lines/float/random-short").scene)
    assert sum(c.lattice for c in full) >= len(full) // 2


def test_refusable_segments_are_exactly_the_huge_ones(full):
    for case in full:
        a, b = case.scene.segments()
        ends = np.abs(np.concatenate([a, b], axis=1))
        with np.errstate(invalid="ignore"):
            huge = np.flatnonzero(np.isfinite(ends).all(axis=1) & (ends >= REFUSABLE_FROM).any(axis=1))
        assert case.refusable == tuple(huge.tolist()), case.id
    huge_cases = [c for c in full if "huge" in c.id and "1e4" not in c.id]
    assert huge_cases and all(c.refusable for c in huge_cases)
    # the anchors (segments 0 to 2) of every degenerate case are ordinary and on screen
    for case in full:
        if case.family == "line-degenerate":
            a, b = case.scene.segments()
            assert np.isfinite(a[:3]).all() and np.isfinite(b[:3]).all() and not set(case.refusable) & {0, 1, 2}


def test_every_case_round_trips_through_json(quick, full):
    # every quick case, and the full suite's others but its largest (the same helpers and
    # codec; decoding validates the schema at about half a millisecond a segment)
    quick_ids = {c.id for c in quick}
    for case in quick + [c for c in full if c.id not in quick_ids and len(c.scene) <= 150]:
        data = json.loads(json.dumps(case_to_json(case)))
        back = case_from_json(data)
        assert isinstance(back, Case) and back.id == case.id
        assert _same_scene(back.scene, case.scene), case.id  # type: ignore[arg-type]
        assert (back.lattice, back.refusable, back.non_finite) == (case.lattice, case.refusable, case.non_finite)
    # the comparison can fail: a moved vertex is another scene
    scene = full[0].scene
    assert isinstance(scene, LineScene)
    moved = scene.vertices.copy()
    moved[0, 0] = np.nextafter(moved[0, 0], np.inf)
    assert not _same_scene(scene, scene.with_coordinates(moved))


def test_geometry_helpers():
    a, b = fan((0.5, 0.5), 10, (0, 3, 5, 7))
    d = b - a
    assert np.all(np.abs(d).max(axis=1) == 10) and len(np.unique(d, axis=0)) == len(d)
    slopes = {float(y / x) for x, y in d if x != 0}
    assert {0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0} <= slopes and any(x == 0 for x, _ in d)
    assert np.all((b * 2) % 2 == 1)  # every end on a pixel centre
    points = spiral((16, 16), 3.0, 60, 14.0)
    assert points.shape == (60, 2) and np.allclose(points[0], 16) and np.isclose(np.hypot(*(points[-1] - 16)), 14)
    zig = zigzag((2.5, 10.5), (3, 3), 4)
    assert zig.tolist() == [[2.5, 10.5], [5.5, 13.5], [8.5, 10.5], [11.5, 13.5], [14.5, 10.5]]
    steep = zigzag((4.0, 1.0), (-2, 5), 2)
    assert steep.tolist() == [[4.0, 1.0], [6.0, 6.0], [4.0, 11.0]]
