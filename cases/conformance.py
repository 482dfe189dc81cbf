"""The conformance cases: ``lattice/...`` triangles (ties on purpose, exact arithmetic) and
``float/...`` ones, the suite's first family (:mod:`cases.suites`). Their own module, so
that the path cases built from them (:func:`cases.paths.viewport_cases`) import them
without importing the suites, which import the path cases."""

from __future__ import annotations

import numpy as np

from cases.scenes import TALL_SCREEN, TALL_TRIANGLES, lattice_triangles, random_triangles
from harness.contract.case import Case
from harness.contract.scenes import Scene

__all__ = ["conformance_cases", "first_half_pixel"]


def first_half_pixel(count: int, size: int, seed: int) -> np.ndarray:
    """(count, 3, 2) lattice triangles (1/256 px) whose first vertex sits on a half step
    (k + 1/2) / 2**b, b in 1..8, in (0, 1/2) on both axes: where rounding half away from
    zero (up) and piglit's rounding half away from the pixel centre (down) part, and
    where nearest-even parts from both by k's parity.

    >>> p = first_half_pixel(4, 16, 0)
    >>> bool(((p[:, 0] > 0) & (p[:, 0] < 0.5)).all()), p.shape
    (True, (4, 3, 2))
    """
    rng = np.random.default_rng(seed)
    positions = lattice_triangles(count, size, 8, seed)
    bits = rng.integers(1, 9, size=(count, 2))
    k = np.floor(rng.random((count, 2)) * 2.0 ** (bits - 1))
    positions[:, 0] = (k + 0.5) / 2.0**bits
    # no edge of slope dy/dx exactly 3/4: the held-out rare bug (tests/known_bad/rare.py) is
    # for the fuzzer to find, not this suite (dyadic coordinates: the products are exact)
    for attempt in range(100):
        d = positions[:, [1, 2, 0]] - positions
        rare = np.any(4.0 * d[..., 1] == 3.0 * d[..., 0], axis=1)
        if not rare.any():
            break
        positions[rare, 1:] = lattice_triangles(int(rare.sum()), size, 8, seed + 1 + attempt)[:, 1:]
    return positions


def conformance_cases(seed: int, full: bool = False) -> list[Case]:
    """``lattice/...`` (ties on purpose, exact arithmetic) and ``float/...`` scenes (the
    last, ``float/tall-triangles-2048px``, three triangles over 2,048 px tall)."""
    count = 400 if full else 150
    cases = [
        Case(f"lattice/bits-{bits}", Scene(64, 64, lattice_triangles(count, 64, bits, seed + bits)), lattice=True)
        for bits in (0, 2, 4, 8)
    ]
    rng = np.random.default_rng(seed + 5)
    centres = np.floor(rng.uniform(1, 31, size=(300, 1, 2))) + 0.5
    small = centres + rng.integers(-12, 13, size=(300, 3, 2)) / 16  # areas below a pixel
    cases.append(Case("lattice/sub-pixel-triangles", Scene(32, 32, small), lattice=True))
    cases.append(Case("lattice/first-half-pixel", Scene(64, 64, first_half_pixel(count, 64, seed + 11)), lattice=True))
    # lattice triangles nudged by about a micro-pixel: samples just off the edges, where
    # single precision or a sloppy epsilon decides wrongly
    nudged = lattice_triangles(count, 64, 2, seed + 9) + rng.uniform(-2e-6, 2e-6, size=(count, 3, 2))
    cases.append(Case("float/near-ties-1e-6", Scene(64, 64, nudged)))
    cases.append(Case("float/random-50px", Scene(128, 128, random_triangles(count * 2, 50.0, 128, seed))))
    cases.append(Case("float/random-2000px", Scene(128, 128, random_triangles(count // 10, 2000.0, 128, seed + 1))))
    # over 2,048 rows tall, far right: where an edge stepped down the rows in float32 drifts
    cases.append(Case("float/tall-triangles-2048px", Scene(*TALL_SCREEN, TALL_TRIANGLES)))
    return cases
