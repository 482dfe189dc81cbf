"""Oracle-versus-rasterizer comparison for the default suite: missing and extra pixels,
and double hits on meshes whose triangles tile a region."""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field

import numpy as np

from harness.api import Coverage, Rasterizer
from harness.oracle import exact_coverage

__all__ = ["ConformanceResult", "compare", "run_conformance"]


@dataclass(frozen=True, slots=True)
class ConformanceResult:
    """One rasterizer on one case, against the oracle of its declared convention."""

    rasterizer: str
    case: str
    status: str  # "pass", "fail", "error" or "skip"
    message: str
    expected_pixels: int = 0
    missing: int = 0
    extra: int = 0
    double_hits: int = 0
    seconds: float = 0.0
    details: dict[str, object] = field(default_factory=dict)


def compare(coverage: Coverage, oracle: Coverage, width: int, height: int) -> tuple[int, int]:
    """(missing, extra): fragments the oracle has and the coverage lacks, and the reverse,
    per triangle and pixel (multiplicity counts)."""
    tri, x, y = coverage.pixels()
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (tri >= 0)
    key_got = (tri[inside] * height + y[inside]) * width + x[inside]
    o_tri, o_x, o_y = oracle.pixels()
    key_want = (o_tri * height + o_y) * width + o_x
    got_keys, got_counts = np.unique(key_got, return_counts=True)
    want_keys, want_counts = np.unique(key_want, return_counts=True)
    keys = np.union1d(got_keys, want_keys)
    delta = np.zeros(keys.size, dtype=np.int64)
    delta[np.searchsorted(keys, got_keys)] += got_counts
    delta[np.searchsorted(keys, want_keys)] -= want_counts
    outside = int((~inside).sum())
    return int(np.clip(-delta, 0, None).sum()), int(np.clip(delta, 0, None).sum()) + outside


def run_conformance(rasterizer: Rasterizer, cases: list, convention=None) -> list[ConformanceResult]:  # type: ignore[no-untyped-def]
    """Run every case through the rasterizer; an exception becomes an error result."""
    convention = convention or rasterizer.convention
    results = []
    for case in cases:
        scene = case.scene
        if convention is None:
            results.append(ConformanceResult(rasterizer.name, case.id, "skip", "declares no convention"))
            continue
        start = time.perf_counter()
        try:
            coverage = rasterizer.rasterize(scene)
            if not isinstance(coverage, Coverage):
                raise TypeError(f"rasterize returned {type(coverage).__name__}, not Coverage")
        except Exception as exc:
            results.append(
                ConformanceResult(
                    rasterizer.name, case.id, "error", f"{type(exc).__name__}: {exc}",
                    details={"traceback": traceback.format_exc()},
                )
            )
            continue
        seconds = time.perf_counter() - start
        oracle = exact_coverage(scene, convention)
        missing, extra = compare(coverage, oracle, scene.width, scene.height)
        double = int((coverage.counts(scene.width, scene.height) > 1).sum()) if case.partition else 0
        ok = missing == 0 and extra == 0 and double == 0
        message = (
            "pixel-exact"
            if ok
            else f"{missing} missing, {extra} extra" + (f", {double} double hits" if double else "")
        )
        results.append(
            ConformanceResult(
                rasterizer.name, case.id, "pass" if ok else "fail", message,
                expected_pixels=oracle.n_pixels, missing=missing, extra=extra,
                double_hits=double, seconds=seconds,
            )
        )
    return results
