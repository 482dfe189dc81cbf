"""Point cases: squares of a given size around each point (:mod:`harness.kinds.points`),
handed only to rasterizers that take points.

``points/<family>/<detail>``:

- ``tiles``: size-1 points one pixel apart, moved together by a sub-pixel offset -- a
  planar partition of their block (``region``): every sample inside covered exactly once,
  the offsets putting the squares' sides through the samples where the tie rule decides.
- ``ties``: centres on a quarter-pixel lattice and sizes in half pixels, so that sides
  pass through pixel centres.
- ``float``: random centres and sizes that are not dyadic-friendly; ``near-ties`` moves
  lattice points by about a micro-pixel.
- ``viewport``: points across the viewport's sides and corners.
- ``sub-pixel``: points smaller than a pixel (a sample inside or none).
- ``degenerate``: NaN and infinite centres among good points (they cover nothing), and
  centres far beyond the viewport (refusable).
"""

from __future__ import annotations

import zlib

import numpy as np
from numpy.typing import NDArray

from harness.contract.case import Case
from harness.kinds.points import PointScene

__all__ = ["point_cases"]

SIZE = 16


def _rng(seed: int, name: str) -> np.random.Generator:
    """A generator for one family, independent of the others (adding one changes no other)."""
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def _tiles(offset: tuple[float, float], first: int = 2, last: int = 13) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Size-1 points at ``(i + ox, j + oy)`` for i, j in first..last, and the outline of
    their squares' union (a rectangle, clockwise on screen)."""
    ox, oy = offset
    steps = np.arange(first, last + 1, dtype=np.float64)
    centres = np.stack(np.meshgrid(steps + ox, steps + oy), axis=-1).reshape(-1, 2)
    lo_x, hi_x, lo_y, hi_y = first + ox - 0.5, last + ox + 0.5, first + oy - 0.5, last + oy + 0.5
    return centres, np.array([[lo_x, lo_y], [hi_x, lo_y], [hi_x, hi_y], [lo_x, hi_y]])


def point_cases(seed: int, full: bool = False) -> list[Case]:
    """The point cases of the quick suite (``full``: more of each family)."""
    cases: list[Case] = []
    for ox, oy in ((0.0, 0.0), (0.5, 0.5), (0.25, 0.5), (0.375, 0.125)) + (((0.5, 0.0), (0.0, 0.75)) if full else ()):
        centres, region = _tiles((ox, oy))
        cases.append(Case(f"points/tiles/offset-{ox:g}-{oy:g}", PointScene(SIZE, SIZE, centres), lattice=True, region=region))
    for size in (1.0, 2.0, 3.0, 0.5) + ((1.5, 4.0, 7.0) if full else ()):
        rng = _rng(seed, f"ties-{size:g}")
        centres = rng.integers(-4, 4 * SIZE + 4, size=(120, 2)) / 4.0
        cases.append(Case(f"points/ties/size-{size:g}", PointScene(SIZE, SIZE, centres, point_size=size), lattice=True))
    for size in (1.0, 1.3, 2.75, 5.1):
        rng = _rng(seed, f"float-{size:g}")
        centres = rng.uniform(-2.0, SIZE + 2.0, size=(200 if full else 80, 2))
        cases.append(Case(f"points/float/size-{size:g}", PointScene(SIZE, SIZE, centres, point_size=size)))
    rng = _rng(seed, "near-ties")
    lattice = rng.integers(0, 4 * SIZE, size=(120, 2)) / 4.0
    nudged = lattice + rng.uniform(-1e-6, 1e-6, size=lattice.shape)
    cases.append(Case("points/float/near-ties-1e-6", PointScene(SIZE, SIZE, nudged, point_size=2.0)))
    border = np.array([[x, y] for x in (-0.5, 0.0, 0.25, SIZE - 0.25, SIZE, SIZE + 0.5)
                       for y in (-0.5, 0.0, 7.5, SIZE, SIZE + 0.5)])
    cases.append(Case("points/viewport/sides-and-corners", PointScene(SIZE, SIZE, border, point_size=2.0), lattice=True))
    rng = _rng(seed, "sub-pixel")
    cases.append(Case("points/sub-pixel/size-0.25", PointScene(SIZE, SIZE, rng.integers(0, 8 * SIZE, size=(100, 2)) / 8.0,
                                                                point_size=0.25), lattice=True))
    good = np.array([[2.5, 2.5], [6.0, 6.0], [11.25, 3.75]])
    bad = np.array([[np.nan, 4.0], [5.0, np.inf], [-np.inf, -np.inf]])
    cases.append(Case("points/degenerate/non-finite", PointScene(SIZE, SIZE, np.concatenate([good, bad]), point_size=2.0),
                      lattice=True))
    far = np.array([[4.5, 4.5], [1e300, 4.0], [-3e200, 1e250], [8.0, 8.0]])
    cases.append(Case("points/degenerate/far-beyond", PointScene(SIZE, SIZE, far, point_size=3.0), lattice=True,
                      refusable=(1, 2)))
    return cases
