"""Compile every numba kernel the tests use, once, into numba's on-disk cache.

``make test`` runs this beside mypy (one core each), before pytest starts its workers: on
a fresh clone each worker would otherwise compile the same kernels again (tens of seconds
each). It asserts nothing; the tests do. Run: ``python -m tests.warm``.
"""

from __future__ import annotations

import time

import numpy as np


def warm() -> float:
    """Run every kernel on a few small scenes; return the seconds it took."""
    start = time.monotonic()
    from cases.suites import suite
    from harness import run_suite
    from harness.api import Coverage, Scene
    from harness.area import area_error_bound, pixel_areas
    from harness.checks import FragmentCounter
    from harness.conventions import Convention
    from harness.oracle import exact_coverage
    from harness.case import Case
    from harness.registry import builtins, load
    from tests.known_bad.edge_functions import EdgeFunctionBug
    from tests.known_bad.scanlines import ScanlineBug
    from tests.ports import DeqpReference, PiglitReference

    rasterizers = [load(name) for name in builtins()]
    rasterizers += [EdgeFunctionBug("inclusive"), ScanlineBug("no-prestep"), DeqpReference(), PiglitReference()]
    cases, families = [], set()
    for case in suite("quick"):  # the first case of each family: every check, every kernel
        if case.family not in families:
            families.add(case.family)
            cases.append(case)
    run_suite(rasterizers, cases=cases, identify=False, isolate=False, repros=False)
    scene = next(c for c in cases if isinstance(c, Case)).scene
    pixel_areas(scene.positions, scene.width, scene.height)
    area_error_bound(np.asarray(scene.positions))
    # attributes, affine and perspective-correct: the interpolation kernels
    positions = np.array([[[0.5, 0.5], [7.0, 1.0], [2.0, 6.5]]])
    values = np.arange(6, dtype=np.float64).reshape(1, 3, 2)
    for w in (None, np.array([[1.0, 2.0, 4.0]])):
        with_values = Scene(8, 8, positions, attributes=values, w=w)
        exact_coverage(with_values, Convention())
        for rasterizer in rasterizers:
            rasterizer.rasterize(with_values)
    # identify's and compare's mismatch counts, span by span and fragment by fragment
    counter = FragmentCounter(Coverage([0], [1], [0], [3]), 8, 8)
    counter.mismatches(Coverage([0], [1], [1], [4]))
    counter.mismatches(Coverage([0, 0], [1, 1], [1, 2], [4, 5]))
    return time.monotonic() - start


if __name__ == "__main__":
    print(f"numba kernels compiled and cached in {warm():.1f} s")
