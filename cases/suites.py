"""Suites: ``quick`` (the four built-ins in well under a minute) and ``full``.

Triangle families first, then the path families (``paths``, ``path-partitions``,
``path-degenerate``: :mod:`cases.paths`; handed only to rasterizers that take paths), the
line families (``lines``, ``line-strips``, ``line-degenerate``: :mod:`cases.lines`; handed
only to rasterizers that take lines), the point families (``points``: :mod:`cases.points`),
then motion (triangles, then anti-aliased paths and lines: :func:`cases.motion.aa_motion_cases`).
"""

from __future__ import annotations

import functools

from cases.conformance import conformance_cases
from cases.degenerate import degenerate_cases
from cases.lines import line_cases
from cases.meshes import mesh_cases
from cases.motion import aa_motion_cases, motion_cases
from cases.partitions import partition_cases
from cases.paths import path_cases
from cases.points import point_cases
from harness.contract.case import Case, MotionCase

__all__ = ["SUITES", "suite", "conformance_cases"]

SUITES = ("quick", "full")


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
        *point_cases(seed, full),
        *motion_cases(seed, full),
        *aa_motion_cases(seed, full),  # frames of paths and lines (issue 34)
    )
