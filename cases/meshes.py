"""Closed meshes through trimesh, seen by a perspective camera, and user mesh files.

A closed mesh wholly in front of the camera covers every pixel as often with clockwise
triangles as with counter-clockwise ones (front minus back is zero). A camera that cuts
the mesh clips it against the near plane (Sutherland-Hodgman in clip space); the clipped
mesh is open, so only the convention-bound checks apply to it.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from harness.contract.case import Case
from harness.contract.scenes import Scene

if TYPE_CHECKING:  # imported where a mesh is made or read: a second and more, that most
    import trimesh  # processes importing the suites (every command, every test worker) never need

__all__ = ["MeshFileError", "load_mesh_file", "project", "clip_near", "mesh_cases", "mesh_file_case"]

SIZE = 96
NEAR = 0.1


class MeshFileError(ValueError):
    """A mesh file that cannot be used: unreadable, empty or not watertight."""


def _rotation(rng: np.random.Generator) -> NDArray[np.float64]:
    import trimesh

    q = rng.normal(size=4)
    rotation: NDArray[np.float64] = trimesh.transformations.quaternion_matrix(q / np.linalg.norm(q))
    return rotation


def _perspective(fov_y: float, aspect: float, near: float, far: float) -> NDArray[np.float64]:
    """OpenGL's projection matrix: the camera looks down -z; clip-space near plane z = -w."""
    f = 1.0 / np.tan(fov_y / 2)
    return np.array([
        [f / aspect, 0, 0, 0],
        [0, f, 0, 0],
        [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
        [0, 0, -1, 0],
    ])


def clip_near(triangles: NDArray[np.float64]) -> NDArray[np.float64]:
    """Clip clip-space triangles (N, 3, 4) against the near plane z >= -w
    (Sutherland-Hodgman), fanning each clipped polygon back into triangles."""
    out = []
    for tri in triangles:
        d = tri[:, 2] + tri[:, 3]  # signed distance to the plane z + w = 0
        if np.all(d >= 0):
            out.append(tri)
            continue
        if np.all(d < 0):
            continue
        polygon = []
        for k in range(3):
            a, b = tri[k], tri[(k + 1) % 3]
            da, db = d[k], d[(k + 1) % 3]
            if da >= 0:
                polygon.append(a)
            if (da >= 0) != (db >= 0):
                polygon.append(a + (b - a) * (da / (da - db)))
        out.extend(np.array([polygon[0], polygon[i], polygon[i + 1]]) for i in range(1, len(polygon) - 1))
    return np.array(out).reshape(-1, 3, 4)


def project(mesh: trimesh.Trimesh, rotation: NDArray, distance: float, size: int = SIZE) -> tuple[NDArray, NDArray, bool]:
    """Screen positions (N, 3, 2) and clip w (N, 3) of a mesh rotated, centred and
    moved ``distance`` in front of the camera; also whether the near plane cut it."""
    vertices = mesh.vertices - mesh.bounds.mean(axis=0)
    vertices = vertices / np.abs(vertices).max()
    homogeneous = np.c_[vertices, np.ones(len(vertices))] @ rotation.T
    homogeneous[:, 2] -= distance
    clip = homogeneous @ _perspective(np.radians(50), 1.0, NEAR, 100.0).T
    triangles = clip[mesh.faces]
    clipped = bool(np.any(triangles[..., 2] + triangles[..., 3] < 0))
    triangles = clip_near(triangles)
    w = triangles[..., 3]
    ndc = triangles[..., :2] / w[..., None]
    screen = np.stack([(ndc[..., 0] + 1) / 2 * size, (1 - ndc[..., 1]) / 2 * size], axis=-1)
    return screen, w, clipped


def load_mesh_file(path: str | Path) -> trimesh.Trimesh:
    """Load an OBJ, PLY, STL or GLB file as one mesh, with a clear error naming the file."""
    import trimesh

    path = Path(path)
    if not path.is_file():
        raise MeshFileError(f"{path}: no such file")
    try:
        loaded = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many kinds for a bad file
        raise MeshFileError(f"{path}: unreadable mesh file ({type(exc).__name__}: {exc})") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshFileError(f"{path}: the file holds no triangles")
    if not loaded.is_watertight:
        raise MeshFileError(f"{path}: the mesh is not watertight (closed), so front minus back coverage is not zero")
    return loaded


def mesh_file_case(path: str | Path, seed: int = 0) -> Case:
    """A user's closed mesh, at a random orientation in front of the camera."""
    mesh = load_mesh_file(path)
    rng = np.random.default_rng(seed)
    screen, _, _ = project(mesh, _rotation(rng), 3.0)
    return Case(f"mesh/file-{Path(path).stem}/seed-{seed}", Scene(SIZE, SIZE, screen), closed=True)


def _shapes() -> dict[str, trimesh.Trimesh]:
    import trimesh.creation

    return {
        "icosphere": trimesh.creation.icosphere(subdivisions=2),
        "box": trimesh.creation.box(),
        "cylinder": trimesh.creation.cylinder(radius=0.5, height=1.5, sections=24),
        "capsule": trimesh.creation.capsule(height=1.0, radius=0.4, count=[12, 12]),
        "torus": trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=24, minor_sections=12),
    }


def mesh_cases(seed: int, full: bool = False) -> list[Case]:
    """``mesh/<shape>/<view>``: closed meshes in front of the camera, and near-clipped ones."""
    rng = np.random.default_rng(seed)
    cases = []
    for name, mesh in _shapes().items():
        for view in range(2 if full else 1):
            screen, _, _ = project(mesh, _rotation(rng), 3.0)
            cases.append(Case(f"mesh/{name}/view-{view}", Scene(SIZE, SIZE, screen), closed=True))
        screen, w, clipped = project(mesh, _rotation(rng), 0.2)
        assert clipped, "the camera should cut the mesh"
        cases.append(Case(f"mesh/{name}/near-clipped", Scene(SIZE, SIZE, screen, attributes=w[..., None], w=w)))
    return cases
