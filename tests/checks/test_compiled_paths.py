"""The checks' compiled fast paths give what the numpy code they replaced gave (kept here as
the reference): the motion masks and span-end series, the watertight corner sides, the
canonical span comparison, and invariance's span-level "nothing changed" -- on random,
lattice, overlapping, off-screen and garbage spans."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from harness.checks.fragments import _same_fragments, deviations
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orientation

motion = importlib.import_module("harness.checks.motion")
watertight = importlib.import_module("harness.checks.watertight")
invariance = importlib.import_module("harness.checks.invariance")


def _coverage(rng: np.random.Generator, n: int, width: int, height: int, garbage: bool = False) -> Coverage:
    spans = int(rng.integers(0, 40))
    t = rng.integers(-1 if garbage else 0, n + (1 if garbage else 0), spans)
    y = rng.integers(-2 if garbage else 0, height + (2 if garbage else 0), spans)
    x0 = rng.integers(-3, width + 3, spans)
    x1 = x0 + rng.integers(-1 if garbage else 1, 6, spans)
    return Coverage(t, y, x0, x1)


def _old_series(coverages: list[Coverage], n: int, height: int) -> tuple[NDArray, NDArray]:
    frames = len(coverages)
    f, t, y, x0, x1 = motion._spans(coverages)
    ok = (t >= 0) & (t < n) & (y >= 0) & (y < height) & (x1 > x0)
    where = (f[ok], t[ok], y[ok])
    lo = np.full((frames, n, height), np.inf)
    hi = np.full((frames, n, height), -np.inf)
    np.minimum.at(lo, where, x0[ok].astype(float))
    np.maximum.at(hi, where, x1[ok].astype(float))
    return np.where(np.isfinite(lo), lo, np.nan), np.where(np.isfinite(hi), hi, np.nan)


def _old_masks(coverages: list[Coverage], window: tuple[int, int, int, int]) -> NDArray:
    x0, y0, x1, y1 = window
    w, h = x1 - x0, y1 - y0
    stride = w + 1
    f, _, y, a, b = motion._spans(coverages)
    y = y - y0
    a = np.clip(a, x0, x1) - x0
    b = np.clip(b, x0, x1) - x0
    keep = (y >= 0) & (y < h) & (b > a)
    f, y, a, b = f[keep], y[keep], a[keep], b[keep]
    size = len(coverages) * h * stride
    delta = np.bincount((f * h + y) * stride + a, minlength=size) - np.bincount((f * h + y) * stride + b, minlength=size)
    out: NDArray = np.cumsum(delta.reshape(len(coverages), h, stride), axis=2)[:, :, :w] > 0
    return out


@pytest.mark.parametrize("seed", range(40))
def test_motion_masks_and_series_are_the_numpy_ones(seed: int) -> None:
    rng = np.random.default_rng(seed)
    width, height, n = int(rng.integers(1, 20)), int(rng.integers(1, 20)), int(rng.integers(1, 5))
    coverages = [_coverage(rng, n, width, height, garbage=seed % 2 == 1) for _ in range(int(rng.integers(1, 6)))]
    window = motion._window(coverages, width, height)
    assert np.array_equal(motion._masks(coverages, window), _old_masks(coverages, window))
    for got, want in zip(motion.boundary_series(coverages, n, height), _old_series(coverages, n, height), strict=True):
        assert np.array_equal(got, want, equal_nan=True)


def _old_sides(region: NDArray, width: int, height: int, area_sign: int) -> NDArray:
    m = region.shape[0]
    cy, cx = np.mgrid[0 : height + 1, 0 : width + 1]
    corners = np.stack([cx.ravel(), cy.ravel()], axis=-1).astype(float)
    n = corners.shape[0]
    triangles = np.empty((m, n, 3, 2))
    triangles[:, :, 0] = region[:, None, :]
    triangles[:, :, 1] = np.roll(region, -1, axis=0)[:, None, :]
    triangles[:, :, 2] = corners[None, :, :]
    out: NDArray = orientation(triangles.reshape(m * n, 3, 2)).reshape(m, height + 1, width + 1) * area_sign
    return out


@pytest.mark.parametrize("seed", range(30))
def test_watertight_corner_sides_are_the_exact_orientations(seed: int) -> None:
    rng = np.random.default_rng(seed)
    width, height, m = int(rng.integers(1, 24)), int(rng.integers(1, 24)), int(rng.integers(3, 8))
    region = rng.uniform(-3.0, 27.0, size=(m, 2))
    if seed % 3 == 0:
        region = np.round(region * 4) / 4  # corners exactly on edges
    if seed % 5 == 0:
        region = np.round(region)
    for sign in (1, -1):
        got = watertight._sides_kernel(frozen(region), width, height, sign)
        assert np.array_equal(got, _old_sides(region, width, height, sign))


def test_watertight_classes_beyond_the_safe_range_fall_back_to_rationals() -> None:
    region = np.array([[0.0, 0.0], [1e300, 0.0], [0.0, 8.0]])
    inside, outside = watertight._classes(region, 4, 4)
    assert inside.shape == outside.shape == (4, 4) and inside[1, 1] and not outside[1, 1] and not inside[0, 0]


def _old_same(a: Coverage, b: Coverage, width: int, height: int) -> bool:
    x, y = (Coverage(c.triangle, c.y, c.x0, c.x1).canonical() for c in (a, b))
    if len(x) != len(y) or not all(np.array_equal(getattr(x, f), getattr(y, f)) for f in ("triangle", "y", "x0", "x1")):
        return False
    return bool(((x.triangle >= 0) & (x.y >= 0) & (x.y < height) & (x.x0 >= 0) & (x.x1 <= width)).all())


@pytest.mark.parametrize("seed", range(60))
def test_span_comparison_decides_as_the_canonical_forms(seed: int) -> None:
    rng = np.random.default_rng(seed)
    width, height = 12, 10
    a = _coverage(rng, 4, width, height, garbage=seed % 3 == 0)
    canonical = Coverage(a.triangle, a.y, a.x0, a.x1).canonical()
    for b in (a, canonical, Coverage(canonical.triangle, canonical.y, canonical.x0, canonical.x1 + (seed % 2)),
              _coverage(rng, 4, width, height)):
        assert _same_fragments(a, b, width, height) == _old_same(a, b, width, height)
        assert _same_fragments(b, a, width, height) == _old_same(b, a, width, height)


def _old_changed(name: str, index: NDArray, cov: Coverage, coverage: Coverage, scene: Scene,
                 shift: tuple[int, int]) -> NDArray:
    t, x, y = cov.pixels()
    keep = (t >= 0) & (t < index.size)
    t, x, y = index[t[keep]], x[keep], y[keep]
    if name == "translate":
        x, y = x - shift[0], y - shift[1]
        window = (x >= 0) & (y >= 0) & (x < scene.width) & (y < scene.height)
        t, x, y = t[window], x[window], y[window]
    missing, extra = deviations(Coverage.from_pixels(t, x, y), coverage, scene.width, scene.height)
    out: NDArray = np.concatenate([missing, extra], axis=1)
    return out


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["rotate-vertices", "permute-triangles", "translate"]),
       st.booleans())
def test_invariance_span_fast_path_agrees_with_the_pixels(seed: int, name: str, same: bool) -> None:
    rng = np.random.default_rng(seed)
    n, width, height = 4, 12, 10
    scene = Scene(width, height, rng.uniform(0.0, 12.0, size=(n, 3, 2)))
    coverage = Coverage.from_pixels(*_coverage(rng, n, width, height).pixels())  # canonical, as answers usually are
    index = rng.permutation(n) if name == "permute-triangles" else np.arange(n)
    shift = (2, 3)
    inverse = np.argsort(index)
    t, x, y = coverage.pixels()
    if name == "translate":
        x, y = x + shift[0], y + shift[1]
    variant = Coverage.from_pixels(inverse[t], x, y)  # the variant's own answer: its triangle ids, its pixels
    if not same and len(variant):
        variant = Coverage(variant.primitive, variant.y, variant.x0, variant.x1 + 1)
    fast = invariance._unchanged_spans(name, index, variant, coverage, scene, shift)
    old = _old_changed(name, index, variant, coverage, scene, shift)
    assert invariance._changed(name, index, variant, coverage, scene, shift).shape == old.shape
    if fast:
        assert old.shape[1] == 0
    if same and bool(((coverage.x0 >= 0) & (coverage.y >= 0) & (coverage.x1 <= width) & (coverage.y < height)).all()):
        assert fast  # the usual case is decided span by span
