"""Case families: exact regions, closed meshes, mesh files with clear errors, strategies."""

import numpy as np
import pytest
from hypothesis import given

from cases.meshes import MeshFileError, clip_near, load_mesh_file, mesh_file_case
from cases.partitions import partition_cases
from cases.strategies import fan_scenes, grid_scenes
from harness.checks import pixel_classes as _pixel_classes
from harness.contract.conventions import Convention
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage


def test_partition_regions_are_exactly_the_union():
    """Every oracle sample inside a region pixel is covered once; none outside."""
    for case in partition_cases(0):
        counts = exact_coverage(case.scene, Convention()).counts(64, 64)
        assert case.region is not None
        inside, outside = _pixel_classes(case.region, 64, 64)
        assert (counts[inside] == 1).all(), case.id
        assert (counts[outside] == 0).all(), case.id
        assert counts.max() == 1, case.id


def test_pixel_classes_of_a_square():
    region = np.array([[2.0, 2.0], [6.0, 2.0], [6.0, 6.0], [2.0, 6.0]])
    inside, outside = _pixel_classes(region, 8, 8)
    assert inside.sum() == 4 * 4 - 12  # the ring touching the boundary is neither
    assert inside[3:5, 3:5].all() and not inside[2, 2]
    assert outside[0, 0] and not outside[1, 1] and not outside[2, 2]


def test_near_plane_clipping_keeps_what_is_in_front():
    tri = np.array([[[0, 0, -2, 1], [1, 0, 1, 1], [0, 1, 1, 1]]], dtype=float)  # one vertex behind
    out = clip_near(tri)
    assert out.shape == (2, 3, 4)
    assert np.all(out[..., 2] + out[..., 3] >= -1e-12)


def test_mesh_files_load_and_fail_clearly(tmp_path):
    import trimesh  # here, not at collection: every test worker collects every module

    good = tmp_path / "box.stl"
    trimesh.creation.box().export(good)
    case = mesh_file_case(good, seed=1)
    assert case.closed and len(case.scene) == 12
    with pytest.raises(MeshFileError, match="nope.obj: no such file"):
        load_mesh_file(tmp_path / "nope.obj")
    broken = tmp_path / "broken.ply"
    broken.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n")
    with pytest.raises(MeshFileError, match="broken.ply"):
        load_mesh_file(broken)
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing\n")
    with pytest.raises(MeshFileError, match="empty.obj"):
        load_mesh_file(empty)
    open_mesh = tmp_path / "open.obj"
    trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]]).export(open_mesh)
    with pytest.raises(MeshFileError, match="open.obj: the mesh is not watertight"):
        load_mesh_file(open_mesh)


@given(grid_scenes())
def test_grid_strategy_tiles_its_square(case):
    counts = exact_coverage(case.scene, Convention()).counts(case.scene.width, case.scene.height)
    inside, _ = _pixel_classes(case.region, case.scene.width, case.scene.height)
    assert counts.max() <= 1 and (counts[inside] == 1).all()


@given(fan_scenes())
def test_fan_strategy_is_a_partition(case):
    assert (orientation(case.scene.positions) != 0).any()
    counts = exact_coverage(case.scene, Convention()).counts(case.scene.width, case.scene.height)
    assert counts.max() <= 1


def test_a_fault_deep_in_a_long_contour_is_named_where_it_is():
    """Long runs of valid points are checked by the schema's own test of a point and cut
    short for the validator; a run with a fault is left whole, so the fault is still
    named exactly where it is (and a long valid path reads back exactly)."""
    import pytest

    from harness.contract.case import Case, case_from_json, case_to_json
    from harness.contract.scenes import PathScene

    ring = [[float(k % 7), float(k % 5)] for k in range(1000)]
    data = case_to_json(Case("paths/long", PathScene.from_paths(8, 8, [[ring]], "nonzero")))
    back = case_from_json(data)
    assert isinstance(back, Case) and isinstance(back.scene, PathScene)
    assert back.scene.vertices.tolist() == ring
    data["paths"][0][0][700][1] = "0.1x"
    with pytest.raises(ValueError, match=r"malformed at paths\[0\]\[0\]\[700\]\[1\]: '0.1x'"):
        case_from_json(data)
    data["paths"][0][0][700] = ["1", "2", "3"]
    with pytest.raises(ValueError, match=r"malformed at paths\[0\]\[0\]\[700\]"):
        case_from_json(data)
