"""Suites: ``quick`` (the four built-ins in well under a minute) and ``full``.

Triangle families first, then the path families (``paths``, ``path-partitions``,
``path-degenerate``: :mod:`cases.paths`; handed only to rasterizers that take paths), the
line families (``lines``, ``line-strips``, ``line-degenerate``: :mod:`cases.lines`; handed
only to rasterizers that take lines), then motion.
"""

from __future__ import annotations

import functools

import numpy as np

from cases.degenerate import degenerate_cases
from cases.lines import line_cases
from cases.meshes import mesh_cases
from cases.motion import motion_cases
from cases.partitions import partition_cases
from cases.paths import path_cases
from harness.case import Case, MotionCase
from cases.scenes import TALL_SCREEN, TALL_TRIANGLES, lattice_triangles, random_triangles
from harness.api import Scene

__all__ = ["SUITES", "suite", "conformance_cases"]

SUITES = ("quick", "full")


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
    # lattice triangles nudged by about a micro-pixel: samples just off the edges, where
    # single precision or a sloppy epsilon decides wrongly
    nudged = lattice_triangles(count, 64, 2, seed + 9) + rng.uniform(-2e-6, 2e-6, size=(count, 3, 2))
    cases.append(Case("float/near-ties-1e-6", Scene(64, 64, nudged)))
    cases.append(Case("float/random-50px", Scene(128, 128, random_triangles(count * 2, 50.0, 128, seed))))
    cases.append(Case("float/random-2000px", Scene(128, 128, random_triangles(count // 10, 2000.0, 128, seed + 1))))
    # over 2,048 rows tall, far right: where an edge stepped down the rows in float32 drifts
    cases.append(Case("float/tall-triangles-2048px", Scene(*TALL_SCREEN, TALL_TRIANGLES)))
    return cases


def suite(name: str, seed: int = 0) -> list[Case | MotionCase]:
    """Every case of a suite, deterministic for the seed.

    Built once per process for each (name, seed) (the quick suite takes a quarter of a
    second): each call returns a new list of the same cases, which are immutable.

    >>> ids = [c.id for c in suite("quick")]
    >>> len(ids) == len(set(ids)), ids[0]
    (True, 'lattice/bits-0')
    """
    if name not in SUITES:
        raise ValueError(f"unknown suite {name!r}: choose one of {', '.join(SUITES)}")
    return list(build(name, seed))


@functools.lru_cache(maxsize=8)
def build(name: str, seed: int) -> tuple[Case | MotionCase, ...]:
    """The cases of a suite, generated afresh (``build.__wrapped__``) or as built before."""
    full = name == "full"
    return (
        *conformance_cases(seed, full),
        *partition_cases(seed, full),
        *mesh_cases(seed, full),
        *degenerate_cases(seed, full),
        *path_cases(seed, full),
        *line_cases(seed, full),
        *motion_cases(seed, full),
    )
