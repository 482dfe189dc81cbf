"""The fuzz families (cases/fuzz.py): each scene regenerable alone from (family, seed,
index), valid, exact where it says so, JSON round-trips; trimesh only on first use."""

import json
import pickle
import subprocess
import sys

import numpy as np
import pytest

from cases.fuzz import FAMILIES, FAMILY_CODE, SUITE_FAMILY, generate, primitives, scene_point
from harness.checks import closed_balance, watertight
from harness.contract.case import Case, MotionCase, case_from_json, case_to_json
from harness.contract.conventions import Convention
from harness.contract.scenes import LineScene, PathScene, Scene
from harness.oracle.coverage import exact_coverage

SAMPLE = 24  # scenes per family in the validity tests


def dumped(case: Case | MotionCase) -> str:
    return json.dumps(case_to_json(case), sort_keys=True)


@pytest.fixture(scope="module")
def scenes() -> dict[str, list[Case | MotionCase]]:
    return {family: [generate(family, 5, index) for index in range(SAMPLE)] for family in FAMILIES}


def test_the_families_are_the_contract():
    assert FAMILIES == ("lattice", "float", "partitions", "meshes", "degenerate", "motion", "paths", "lines", "tall", "winding")
    assert set(FAMILY_CODE) == set(FAMILIES) and len(set(FAMILY_CODE.values())) == len(FAMILIES)


@pytest.mark.parametrize("family", FAMILIES)
def test_a_scene_is_decided_by_family_seed_and_index_alone(family, scenes):
    # drawn again out of order, after other families' scenes: byte for byte the same
    # (pickled: every array's bytes, and cheap for the deep-winding paths' 262,000 vertices)
    again = [generate(family, 5, index) for index in reversed(range(6))][::-1]
    assert [pickle.dumps(c) for c in again] == [pickle.dumps(c) for c in scenes[family][:6]]
    texts = [pickle.dumps(c) for c in scenes[family]]
    assert len(set(texts)) == len(texts), "two indices gave the same scene"
    assert pickle.dumps(generate(family, 6, 0)) != texts[0], "another seed gave the same scene"


@pytest.mark.parametrize("family", FAMILIES)
def test_every_family_generates_valid_cases(family, scenes):
    for index, case in enumerate(scenes[family]):
        assert case.id == f"{SUITE_FAMILY[family]}/fuzz/{family}/5/{index}" and scene_point(case.id) == (family, 5, index)
        if family == "motion":
            assert isinstance(case, MotionCase) and 2 <= len(case.frames) <= 40
            assert len({len(f) for f in case.frames}) == 1 and primitives(case) == len(case.frames) * len(case.frames[0])
            continue
        assert isinstance(case, Case)
        kind = {"paths": PathScene, "lines": LineScene, "winding": PathScene}.get(family, Scene)
        assert isinstance(case.scene, kind)
        assert primitives(case) == len(case.scene) >= 1
        if family == "tall":  # over 2,048 px tall, far right on a tall screen
            assert isinstance(case.scene, Scene)
            tall = case.scene.positions
            assert case.scene.width == 1152 and 2064 <= case.scene.height <= 2560 and len(case.scene) <= 3
            assert np.ptp(tall[..., 1], axis=1).min() >= max(2048, case.scene.height - 16)
            assert tall[..., 0].min() >= 1024 and tall[..., 0].max() <= case.scene.width
            assert tall[..., 1].max() <= case.scene.height
        elif family == "winding":  # one path, a small screen, one contour traced over and over
            assert isinstance(case.scene, PathScene)
            assert len(case.scene) == 1 and case.scene.width in (8, 16) and case.scene.vertices.shape[0] <= 4 * 65537 + 36
        else:
            assert max(case.scene.width, case.scene.height) <= 64 and len(case.scene) <= 130
        assert all(0 <= t < len(case.scene) for t in case.refusable)
        if case.lattice:  # exact in any arithmetic: coordinates on the 1/256 px lattice
            c = case.scene.coordinates
            assert np.isfinite(c).all() and np.array_equal(np.round(c * 256), c * 256)
    if family == "lattice":
        assert all(c.lattice for c in scenes[family])
    marked = {"partitions": lambda c: c.region is not None, "meshes": lambda c: c.closed,
              "degenerate": lambda c: bool(c.refusable), "paths": lambda c: c.region is not None}.get(family)
    if marked is not None:
        assert any(marked(c) for c in scenes[family]), \
            f"no partition, closed mesh or refusable case among {SAMPLE} {family} scenes"
    if family == "partitions":
        assert all(c.region is not None for c in scenes[family])


@pytest.mark.parametrize("family", ["partitions", "meshes", "degenerate", "paths"])
def test_partitions_and_closed_meshes_hold_exactly(family, scenes):
    """The exact oracle passes watertight on every partition and closed on every closed
    mesh: a region or a ``closed`` flag is a fact, not a hope."""
    convention = Convention()
    for case in scenes[family]:
        if case.region is None and not case.closed:
            continue
        answer = exact_coverage(case.scene, convention)
        if case.region is not None:
            verdict = watertight(case, answer)
            assert verdict.status == "pass", (case.id, verdict.message)
        if case.closed:
            verdict = closed_balance(case, answer, convention)
            assert verdict.status == "pass", (case.id, verdict.message)


@pytest.mark.parametrize("family", FAMILIES)
def test_a_sample_round_trips_through_json_exactly(family, scenes):
    # a deep-winding path of 262,000 vertices takes seconds to read back: the small ones
    small = [c for c in scenes[family] if isinstance(c, MotionCase) or c.scene.coordinates.size <= 20_000]
    for case in small[:4]:
        back = case_from_json(json.loads(dumped(case)))
        assert type(back) is type(case) and dumped(back) == dumped(case)


def test_unknown_family_and_bad_numbers_are_refused_by_name():
    with pytest.raises(ValueError, match="unknown fuzz family 'cubes'.*lattice, float"):
        generate("cubes", 0, 0)
    with pytest.raises(ValueError, match="unknown fuzz family"):
        generate(None, 0, 0)  # type: ignore[arg-type]
    for seed, index, name in ((-1, 0, "seed"), (0, -3, "index"), (0.5, 0, "seed"), (0, True, "index")):
        with pytest.raises(ValueError, match=f"fuzz scene {name} must be a non-negative integer"):
            generate("lattice", seed, index)  # type: ignore[arg-type]
    # numpy integers are taken too (a seed drawn from an array)
    drawn = generate("lattice", np.int64(2), np.uint32(3))  # type: ignore[arg-type]
    assert drawn.id == "lattice/fuzz/lattice/2/3"


def _still(case: Case | MotionCase) -> Case:
    assert isinstance(case, Case), case.id
    return case


def _moving(case: Case | MotionCase) -> MotionCase:
    assert isinstance(case, MotionCase), case.id
    return case


def test_the_families_draw_what_their_checks_need(scenes):
    """Ties on purpose in every lattice scene (pixel centres exactly on horizontal,
    vertical and slanted edges), huge and non-finite triangles among the degenerate ones,
    both fill rules, textured and perspective motion somewhere in the first hundred."""
    from tests.known_bad.rare import flipped_samples  # noqa: F401 - the rare bug's module imports cleanly

    for case in scenes["lattice"]:
        probes = case.scene.positions[:4]
        midpoints = (probes + probes[:, [1, 2, 0]]) / 2
        assert np.array_equal(midpoints % 1, np.full(midpoints.shape, 0.5))
    degenerate = [_still(generate("degenerate", 0, i)) for i in range(60)]
    assert any(c.non_finite for c in degenerate) and any(c.refusable for c in degenerate)
    assert {c.scene.fill_rule for c in scenes["paths"]} == {"nonzero", "evenodd"}
    # deep windings either side of 2**7, 2**8 and 2**16 turns (a contour of 3 or 4 vertices a turn)
    turns = [c.scene.contour_sizes.max() / 4 for c in scenes["winding"]]
    assert min(turns) < 128 and any(t >= 256 for t in turns) and max(turns) >= 65536 / 4 * 3
    assert {c.scene.fill_rule for c in scenes["winding"]} == {"nonzero", "evenodd"}
    motion = [_moving(generate("motion", 0, i)) for i in range(100)]
    assert any(c.texels for c in motion) and any(c.perspective for c in motion)
    assert any(c.frames[0].width > 1000 for c in motion)  # the tall sliver on a large screen


def test_trimesh_is_imported_on_first_use_only():
    code = "import sys, cases.fuzz; print('trimesh' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"

