"""Scene generators shared by the case families and the benchmark.

Every generator is deterministic for its seed. Ids are hierarchical and stable.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["random_triangles", "lattice_triangles", "grid_mesh", "fan_mesh", "tall_triangles", "TALL_SCREEN", "TALL_TRIANGLES"]

# Tall triangles far right on a tall screen: over 2,048 rows down each long edge, at x past
# 1,024 px, where a float32 x holds 2**-13 px: a rasterizer stepping its edges' x from row
# to row in float32 drifts by up to 2**-14 px a row, a tenth of a pixel by the bottom.
TALL_SCREEN = (1152, 2112)
TALL_TRIANGLES = np.array([
    [[1030.25, 0.75], [1062.5, 2087.25], [1041.75, 2095.5]],  # a sliver leaning right
    [[1120.5, 4.25], [1100.25, 1.5], [1088.75, 2100.5]],  # and one leaning left
    [[1026.5, 10.5], [1080.0, 2090.75], [1031.0, 2105.25]],  # a wider one
])


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
    positions: NDArray[np.float64] = centre + offsets
    return positions


def lattice_triangles(count: int, size: int, bits: int, seed: int) -> NDArray[np.float64]:
    """(count, 3, 2) float64 on the 2**-bits lattice, some vertices on pixel centres,
    corners and edges through samples on purpose."""
    rng = np.random.default_rng(seed)
    scale = 2**bits
    ints = rng.integers(-2 * scale, (size + 2) * scale, size=(count, 3, 2))
    positions: NDArray[np.float64] = ints / scale
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


def tall_triangles(count: int, width: int, height: int, rng: np.random.Generator) -> NDArray[np.float64]:
    """(count, 3, 2) float64: triangles at least ``height - 16`` px tall (a vertex in the
    first 8 rows, one in the last 8, the third anywhere between), at x from 1,024 px to
    the screen's right edge (where float32 steps are 2**-13 px; ``width`` > 1,100),
    leaning either way by up to 60 px, slivers 1 px wide to wedges 40 px wide; on the 1/4
    px lattice or not."""
    top = np.stack([rng.uniform(1024, width - 4, count), rng.uniform(0, 8, count)], axis=-1)
    bottom = np.stack([np.clip(top[:, 0] + rng.uniform(-60, 60, count), 1024, width - 1), rng.uniform(height - 8, height, count)],
                      axis=-1)
    along = rng.uniform(0, 1, (count, 1))
    side = rng.choice([-1.0, 1.0], count) * np.exp(rng.uniform(0, np.log(40), count))
    third = top + along * (bottom - top) + np.stack([side, np.zeros(count)], axis=-1)
    third[:, 0] = np.clip(third[:, 0], 1024, width - 1)
    tris = np.stack([top, bottom, third], axis=1)
    return np.round(tris * 4) / 4 if rng.random() < 0.5 else tris
