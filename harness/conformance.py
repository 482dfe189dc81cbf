"""Oracle-versus-rasterizer comparison for the default suite: missing and extra pixels,
and double hits on meshes whose triangles tile a region."""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field

import numpy as np

from harness.api import Coverage, Rasterizer
from harness.conventions import snap
from harness.exact import orientation
from harness.oracle import exact_coverage

__all__ = ["ConformanceResult", "compare", "deviations", "edge_distance", "run_conformance", "NEAR_TIE"]

# A deviation is a near tie -- float rounding, not a wrong rule -- when the sample lies
# within NEAR_TIE * max(1, largest |coordinate| of the triangle) px of one of its edges.
# float64 evaluations of edge crossings err by a few units in the last place of the
# coordinates (about 2**-50 relative); 2**-40 leaves a wide berth and is still far below
# any sub-pixel lattice a rasterizer could mean (16 bits is 2**-16).
NEAR_TIE = 2.0**-40


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
    near_tie: int = 0
    max_tie_distance: float = 0.0
    double_hits: int = 0
    seconds: float = 0.0
    details: dict[str, object] = field(default_factory=dict)


def deviations(coverage: Coverage, oracle: Coverage, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Fragments (triangle, x, y) the oracle has and the coverage lacks (missing), and the
    reverse (extra), with multiplicity; fragments outside the viewport count as extra.

    Returns
    -------
    missing, extra : (3, M) int64
    """
    tri, x, y = coverage.pixels()
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (tri >= 0)
    got = np.stack([tri[inside], x[inside], y[inside]])
    want = np.stack(oracle.pixels())
    key_got = (got[0] * height + got[2]) * width + got[1]
    key_want = (want[0] * height + want[2]) * width + want[1]
    got_keys, got_first, got_counts = np.unique(key_got, return_index=True, return_counts=True)
    want_keys, want_first, want_counts = np.unique(key_want, return_index=True, return_counts=True)
    keys = np.union1d(got_keys, want_keys)
    delta = np.zeros(keys.size, dtype=np.int64)
    delta[np.searchsorted(keys, got_keys)] += got_counts
    delta[np.searchsorted(keys, want_keys)] -= want_counts
    tri_of = keys // (width * height)
    y_of = (keys // width) % height
    x_of = keys % width
    triples = np.stack([tri_of, x_of, y_of])
    missing = np.repeat(triples, np.clip(-delta, 0, None), axis=1)
    extra = np.repeat(triples, np.clip(delta, 0, None), axis=1)
    outside = np.stack([tri[~inside], x[~inside], y[~inside]])
    return missing, np.concatenate([extra, outside], axis=1)


def compare(coverage: Coverage, oracle: Coverage, width: int, height: int) -> tuple[int, int]:
    """(missing, extra) fragment counts; see :func:`deviations`."""
    missing, extra = deviations(coverage, oracle, width, height)
    return missing.shape[1], extra.shape[1]


def edge_distance(positions: np.ndarray, fragments: np.ndarray, sample: tuple[float, float]) -> np.ndarray:
    """Distance from each fragment's sample point to the nearest edge line of its
    triangle, relative to max(1, largest |coordinate|) of that triangle; exactly 0 when
    the sample lies exactly on an edge line (decided by the exact predicate), which makes
    the deviation a tie-rule question rather than float rounding.

    Parameters
    ----------
    positions : (N, 3, 2) float64, as the convention sees them (snapped)
    fragments : (3, M) int64 rows triangle, x, y
    """
    if fragments.shape[1] == 0:
        return np.zeros(0)
    tri = fragments[0]
    ok = (tri >= 0) & (tri < positions.shape[0])
    out = np.full(fragments.shape[1], np.inf)
    p = positions[tri[ok]]
    px = fragments[1, ok] + sample[0]
    py = fragments[2, ok] + sample[1]
    best = np.full(p.shape[0], np.inf)
    with np.errstate(all="ignore"):
        for k in range(3):
            a, b = p[:, k], p[:, (k + 1) % 3]
            d = b - a
            e = d[:, 0] * (py - a[:, 1]) - d[:, 1] * (px - a[:, 0])
            best = np.minimum(best, np.abs(e) / np.hypot(d[:, 0], d[:, 1]))
        scale = np.maximum(1.0, np.abs(p).max(axis=(1, 2)))
    relative = best / scale
    samples = np.stack([px, py], axis=-1)
    for k in range(3):
        on_line = orientation(np.stack([p[:, k], p[:, (k + 1) % 3], samples], axis=1)) == 0
        relative[on_line] = 0.0
    out[ok] = relative
    return out


def run_conformance(rasterizer: Rasterizer, cases: list, convention=None, strict: bool = False) -> list[ConformanceResult]:  # type: ignore[no-untyped-def]
    """Run every case through the rasterizer against the oracle of ``convention`` (default:
    the declared one). Default mode passes near-tie deviations; strict mode none. An
    exception becomes an error result carrying the traceback."""
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
        missing, extra = deviations(coverage, oracle, scene.width, scene.height)
        positions = snap(scene.positions, convention.subpixel_bits)
        distance = edge_distance(positions, np.concatenate([missing, extra], axis=1), convention.sample)
        # On lattice cases float arithmetic is exact: nothing is excused as rounding.
        near = (distance <= NEAR_TIE) if not getattr(case, "lattice", False) else np.zeros(distance.size, bool)
        double = int((coverage.counts(scene.width, scene.height) > 1).sum()) if case.partition else 0
        wrong = int((~near).sum())
        ok = double == 0 and (wrong == 0 if not strict else distance.size == 0)
        parts = []
        if missing.shape[1] or extra.shape[1]:
            parts.append(f"{missing.shape[1]} missing, {extra.shape[1]} extra")
            exact_ties = int((distance == 0.0).sum())
            parts.append(f"{int(near.sum())} near ties (within 2**-40 of an edge: float rounding)")
            if exact_ties:
                parts.append(f"{exact_ties} of the samples lie exactly on an edge")
        if double:
            parts.append(f"{double} double hits")
        message = ", ".join(parts) if parts else "pixel-exact"
        results.append(
            ConformanceResult(
                rasterizer.name, case.id, "pass" if ok else "fail", message,
                expected_pixels=oracle.n_pixels, missing=missing.shape[1], extra=extra.shape[1],
                near_tie=int(near.sum()),
                max_tie_distance=float(distance[near].max()) if near.any() else 0.0,
                double_hits=double, seconds=seconds,
            )
        )
    return results
