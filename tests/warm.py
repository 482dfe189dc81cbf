"""Compile every numba kernel the tests use, once, into numba's on-disk cache.

``make test`` runs its two parts beside mypy (three processes on the machine's cores)
before pytest starts its workers: on a fresh clone each worker would otherwise compile the
same kernels again (tens of seconds each). It asserts nothing; the tests do.

Run: ``python -m tests.warm engine`` (the checks', oracle's and area kernels) and
``python -m tests.warm rasterizers`` (the built-in, known-bad and ported rasterizers'),
or both in turn without an argument.
"""

from __future__ import annotations

import contextlib
import sys
import time

import numpy as np

from harness.geometry.numba_cache import safe_numba_cache as safe_numba_cache  # the tests import it from here too

# attributes, affine and perspective-correct: the interpolation kernels
POSITIONS = np.array([[[0.5, 0.5], [7.0, 1.0], [2.0, 6.5]]])
VALUES = np.arange(6, dtype=np.float64).reshape(1, 3, 2)


def _first_of_each_family() -> list:
    from cases.suites import suite

    cases, families = [], set()
    for case in suite("quick"):  # the first case of each family: every check, every kernel
        if case.family not in families:
            families.add(case.family)
            cases.append(case)
    return cases


class _Oracle:
    """The exact oracle as a rasterizer: the checks' kernels without a rasterizer's. The
    single-sample one takes path scenes too (the winding oracle's and the path checks'
    kernels)."""

    def __init__(self, **convention: object) -> None:
        from harness.contract.conventions import Convention

        self.convention = Convention(**convention)  # type: ignore[arg-type]
        shares = self.convention.samples and self.convention.coverage_kind == "area"
        self.name = f"oracle_{self.convention.coverage_kind}{'_shares' if shares else ''}"
        self.interpolates = self.convention.coverage_kind != "area"
        # single-sample: paths and points too (the winding oracle's, the path checks' and the points' kernels)
        self.scene_kinds = ("triangles", "paths", "points") if self.convention.coverage_kind == "single" else ("triangles",)

    def rasterize(self, scene):
        from harness.oracle.coverage import exact_coverage

        return exact_coverage(scene, self.convention)


def engine() -> None:
    """Every check on the first case of each family; areas; identify's counts."""
    from harness import run_suite
    from harness.checks import FragmentCounter
    from harness.contract.case import Case
    from harness.contract.conventions import Convention
    from harness.contract.coverage import Coverage
    from harness.contract.scenes import Scene
    from harness.oracle.area import area_error_bound, pixel_areas
    from harness.oracle.coverage import exact_coverage

    cases = _first_of_each_family()
    # every coverage kind: the oracles' and the area checks' kernels
    oracles = [_Oracle(), _Oracle(samples=4), _Oracle(coverage="area"), _Oracle(coverage="area", samples=4)]
    run_suite(oracles, cases=cases, identify=False, isolate=False, repros=False)
    scene = next(c.scene for c in cases if isinstance(c, Case) and isinstance(c.scene, Scene))
    pixel_areas(scene.positions, scene.width, scene.height)
    area_error_bound(np.asarray(scene.positions))
    for w in (None, np.array([[1.0, 2.0, 4.0]])):
        exact_coverage(Scene(8, 8, POSITIONS, attributes=VALUES, w=w), Convention())
    # identify's and compare's mismatch counts, span by span and fragment by fragment
    counter = FragmentCounter(Coverage([0], [1], [0], [3]), 8, 8)
    counter.mismatches(Coverage([0], [1], [1], [4]))
    counter.mismatches(Coverage([0, 0], [1, 1], [1, 2], [4, 5]))
    # the near-tie distance of deviations on a path (conformance off the lattice)
    from harness.checks.conformance import path_edge_distance
    from harness.contract.scenes import PathScene

    star = PathScene.from_paths(8, 8, [[[[1.0, 1.0], [7.0, 2.0], [2.0, 7.0]]]])
    path_edge_distance(star, Convention(), np.array([[0, 0], [2, 3], [2, 3]]))
    # the line checks' own kernels (major axis, the pixel holding a joint)
    from harness.checks.lines import vertex_pixels, x_major_of
    from harness.contract.scenes import LineScene

    strip = LineScene.from_strips(8, 8, [[[0.5, 0.5], [6.0, 2.5], [2.0, 7.0]]])
    x_major_of(strip, Convention())
    vertex_pixels(strip, Convention(), strip.joints())
    # an untidy answer: tidied span by span
    Coverage([0, 0], [1, 1], [1, 0], [3, 2]).tidy(Scene(8, 8, POSITIONS))
    # the anti-aliased reference (here, to balance the two parts; the multisample ones and
    # the supersampler are drawn by one test module only, which compiles them itself)
    from rasterizers.area_scanline import AreaScanline

    _draw_each_family([AreaScanline()])
    # the exact line oracles (here, to balance the two parts; no kernel of the other part's
    # calls them, so neither part waits on the other's compile: harness.geometry.numba_cache)
    from harness.oracle.lines import bresenham_spans, diamond_exit_spans, rectangle_spans

    a, b = np.array([[0.5, 0.5], [1.0, 7.0]]), np.array([[7.5, 3.25], [6.0, 0.5]])
    diamond_exit_spans(a, b, 8, 8)
    rectangle_spans(a, b, 1.0, width=8, height=8)
    bresenham_spans(a, b, 8, 8)


def rasterizers() -> None:
    """Each built-in, known-bad and ported rasterizer on one scene of each family, and on
    scenes with attributes (affine and perspective-correct)."""
    from harness.engine.registry import builtins, load
    from rasterizers.area_scanline import AreaScanline
    from rasterizers.multisample import PinedaMSAA4, PinedaMSAA8
    from rasterizers.supersample import Supersampler4
    from tests.known_bad.edge_functions import EdgeFunctionBug
    from tests.known_bad.scanlines import ScanlineBug
    from tests.ports import DeqpReference, PiglitReference

    beyond_one_sample = {r.name for r in (PinedaMSAA4(), PinedaMSAA8(), AreaScanline(), Supersampler4())}
    everyone = [load(name) for name in builtins() if name not in beyond_one_sample]  # those: the engine part's
    everyone += [EdgeFunctionBug("inclusive"), ScanlineBug("no-prestep"), DeqpReference(), PiglitReference()]
    from tests.known_bad.paths import BUGS, PathFillBug, TwoFillers

    everyone += [PathFillBug(bug) for bug in BUGS] + [TwoFillers()]  # the trapezoid fill's kernels, as the built-in's
    _draw_each_family(everyone)
    # the Mesa path adapter's layering kernel
    from rasterizers.real._stencil import layers

    layers(np.array([[0, 0, 1, 1]]))


def _draw_each_family(everyone: list) -> None:
    from harness.contract.case import Case
    from harness.contract.protocol import takes
    from harness.contract.scenes import AnyScene, PathScene, Scene

    scenes: list[AnyScene] = [Scene(8, 8, POSITIONS, attributes=VALUES, w=w) for w in (None, np.array([[1.0, 2.0, 4.0]]))]
    for case in _first_of_each_family():
        scenes += case.frames[:1] if not isinstance(case, Case) else [case.scene]
    # paths under both rules (each rule a specialisation of some kernels)
    scenes += [s.with_fill_rule(rule) for s in scenes if isinstance(s, PathScene) for rule in ("nonzero", "evenodd")]
    for scene in scenes:
        for rasterizer in everyone:
            if not takes(rasterizer, scene):  # a path scene, to a triangle rasterizer: never handed one
                continue
            with contextlib.suppress(ValueError):  # a refusal (coordinates out of its range): compiled all the same
                rasterizer.rasterize(scene)


PARTS = {"engine": engine, "rasterizers": rasterizers}

if __name__ == "__main__":
    safe_numba_cache()
    for name in sys.argv[1:] or list(PARTS):
        start = time.monotonic()
        PARTS[name]()
        print(f"numba kernels ({name}) compiled and cached in {time.monotonic() - start:.1f} s")
