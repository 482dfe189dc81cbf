"""Scene generators for the default conformance suite and the benchmark.

Every generator is deterministic for its seed. Ids are hierarchical and stable.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from harness.api import Scene

__all__ = ["Case", "random_triangles", "lattice_triangles", "grid_mesh", "fan_mesh", "default_cases"]


@dataclass(frozen=True, slots=True, eq=False)
class Case:
    """A named scene. ``partition`` is True when the triangles tile a region without
    overlapping (shared edges), so every pixel may be hit at most once. ``lattice`` is True
    when every coordinate lies on a coarse dyadic lattice, where float arithmetic is exact
    and no deviation from the oracle can be excused as rounding."""

    id: str
    scene: Scene
    partition: bool = False
    lattice: bool = False


def random_triangles(count: int, mean_area: float, size: int, seed: int) -> NDArray[np.float64]:
    """(count, 3, 2) float64: near-equilateral triangles of about ``mean_area`` px,
    random orientation and jitter, centred uniformly so that they stay on a size x size
    screen."""
    rng = np.random.default_rng(seed)
    radius = np.sqrt(mean_area / (3.0 * np.sqrt(3.0) / 4.0))
    centre = rng.uniform(radius, size - radius, size=(count, 1, 2))
    angle = rng.uniform(0, 2 * np.pi, size=(count, 1)) + np.array([0.0, 2.0, 4.0]) * np.pi / 3.0
    angle = angle + rng.uniform(-0.3, 0.3, size=(count, 3))
    r = radius * rng.uniform(0.8, 1.2, size=(count, 3))
    offsets = np.stack([r * np.cos(angle), r * np.sin(angle)], axis=-1)
    return centre + offsets


def lattice_triangles(count: int, size: int, bits: int, seed: int) -> NDArray[np.float64]:
    """(count, 3, 2) float64 on the 2**-bits lattice, some vertices on pixel centres,
    corners and edges through samples on purpose."""
    rng = np.random.default_rng(seed)
    scale = 2**bits
    ints = rng.integers(-2 * scale, (size + 2) * scale, size=(count, 3, 2))
    positions = ints / scale
    on_centre = rng.random((count, 3)) < 0.3
    positions[on_centre] = np.floor(positions[on_centre]) + 0.5
    on_corner = rng.random((count, 3)) < 0.2
    positions[on_corner] = np.floor(positions[on_corner])
    return positions


def grid_mesh(cells: int, size: int, jitter: float, seed: int, diagonal: str = "main") -> NDArray[np.float64]:
    """A cells x cells grid over [1, size-1]^2 split on a diagonal; interior vertices moved
    by up to ``jitter`` px (unconstrained floats). Returns (2 * cells**2, 3, 2)."""
    rng = np.random.default_rng(seed)
    lines = np.linspace(1.0, size - 1.0, cells + 1)
    gx, gy = np.meshgrid(lines, lines, indexing="xy")
    vertices = np.stack([gx, gy], axis=-1)
    inner = (slice(1, -1), slice(1, -1))
    vertices[inner] += rng.uniform(-jitter, jitter, size=vertices[inner].shape)
    tris = []
    for j in range(cells):
        for i in range(cells):
            a, b = vertices[j, i], vertices[j, i + 1]
            c, d = vertices[j + 1, i], vertices[j + 1, i + 1]
            if diagonal == "main":
                tris += [(a, b, d), (a, d, c)]
            else:
                tris += [(a, b, c), (b, d, c)]
    return np.array(tris, dtype=np.float64)


def fan_mesh(count: int, centre: tuple[float, float], radius: float, seed: int) -> NDArray[np.float64]:
    """(count, 3, 2): a closed fan of triangles around ``centre``, alternate windings."""
    rng = np.random.default_rng(seed)
    angles = np.sort(rng.uniform(0, 2 * np.pi, size=count))
    rim = np.stack([centre[0] + radius * np.cos(angles), centre[1] + radius * np.sin(angles)], axis=-1)
    c = np.array(centre, dtype=np.float64)
    tris = [(c, rim[k], rim[(k + 1) % count]) if k % 2 else (c, rim[(k + 1) % count], rim[k]) for k in range(count)]
    return np.array(tris, dtype=np.float64)


def default_cases(seed: int = 0) -> list[Case]:
    """The default suite's scenes: lattice triangles with ties, unconstrained floats,
    and meshes with shared edges."""
    cases = []
    for bits in (0, 2, 4, 8):
        cases.append(Case(f"lattice/bits-{bits}", Scene(64, 64, lattice_triangles(200, 64, bits, seed + bits)), lattice=True))
    rng = np.random.default_rng(seed + 5)
    centres = np.floor(rng.uniform(1, 31, size=(300, 1, 2))) + 0.5
    small = centres + rng.integers(-12, 13, size=(300, 3, 2)) / 16  # areas below a pixel
    cases.append(Case("lattice/sub-pixel-triangles", Scene(32, 32, small), lattice=True))
    cases.append(Case("float/random-50px", Scene(128, 128, random_triangles(400, 50.0, 128, seed))))
    cases.append(Case("float/random-2000px", Scene(128, 128, random_triangles(40, 2000.0, 128, seed + 1))))
    for jitter, label in ((0.0, "no-jitter"), (0.37, "float-jitter")):
        for diagonal in ("main", "anti"):
            positions = grid_mesh(12, 96, jitter, seed + 2, diagonal)
            cases.append(Case(f"mesh/grid-12x12-{diagonal}/{label}", Scene(96, 96, positions), partition=True))
    for diagonal in ("main", "anti"):
        lattice_grid = grid_mesh(12, 98, 0.0, seed, diagonal)  # lines at 1 + 8k: exact
        cases.append(Case(f"mesh/grid-12x12-{diagonal}/lattice", Scene(98, 98, lattice_grid), partition=True, lattice=True))
    for where, centre in (("centre", (48.5, 48.5)), ("corner", (48.0, 48.0)), ("random", (47.3141, 48.7183))):
        cases.append(Case(f"mesh/fan-32/{where}", Scene(96, 96, fan_mesh(32, centre, 40.0, seed + 3)), partition=True))
    return cases
