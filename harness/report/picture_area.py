"""Pictures of anti-aliased (area) coverage: alpha per pixel, its error against the
oracle, and the alpha maps of a failure."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.report.picture_kit import ALPHA_LEGEND, _png

__all__ = ["alpha_map"]


def _alpha_per_pixel(coverage: Coverage, width: int, height: int) -> NDArray:
    """(H, W) float64: the alphas of every triangle summed per pixel (viewport only)."""
    t, x, y = coverage.pixels()
    alpha = coverage.alpha if coverage.alpha is not None and coverage.alpha.size == t.size else np.zeros(t.size)
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
    out = np.zeros(height * width)
    np.add.at(out, y[inside] * width + x[inside], alpha[inside])
    return out.reshape(height, width)


def _alpha_errors(coverage: Coverage, oracle: Coverage, width: int, height: int) -> NDArray:
    """(H, W) float64: per pixel, the signed alpha error (rasterizer minus oracle) of the
    triangle that errs most there."""
    def keyed(cov: Coverage) -> tuple[NDArray, NDArray]:
        t, x, y = cov.pixels()
        alpha = cov.alpha if cov.alpha is not None and cov.alpha.size == t.size else np.zeros(t.size)
        ok = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (t >= 0)
        keys, where = np.unique((t[ok] * height + y[ok]) * width + x[ok], return_inverse=True)
        return keys, np.bincount(where, weights=alpha[ok], minlength=keys.size)

    got_keys, got = keyed(coverage)
    want_keys, want = keyed(oracle)
    keys = np.union1d(got_keys, want_keys)
    error = np.zeros(keys.size)
    error[np.searchsorted(keys, got_keys)] += got
    error[np.searchsorted(keys, want_keys)] -= want
    pixel = keys % (width * height)
    worst = np.zeros(width * height)
    order = np.argsort(np.abs(error), kind="stable")  # the largest |error| written last wins
    worst[pixel[order]] = error[order]
    return worst.reshape(height, width)


def alpha_map(values: NDArray, scale: float, window: tuple[int, int, int, int] | None = None,
              marks: NDArray | None = None) -> str:
    """A signed per-pixel quantity as a PNG data URI on a diverging scale: white 0, red
    positive (too much alpha), blue negative (too little), full colour at ``scale`` and
    beyond; ``marks`` (H, W) bool pixels in black (ALPHA_LEGEND)."""
    level = np.clip(np.nan_to_num(values, nan=scale) / max(scale, 1e-300), -1.0, 1.0)
    rgb = np.full(values.shape + (3,), 255.0)
    for sign, colour in ((1.0, ALPHA_LEGEND["too much alpha (full red: the scale)"]),
                         (-1.0, ALPHA_LEGEND["too little alpha (full blue: the scale)"])):
        weight = np.where(level * sign > 0, np.abs(level), 0.0)[..., None]
        rgb = np.where(weight > 0, 255.0 * (1 - weight) + np.asarray(colour, dtype=float) * weight, rgb)
    rgb = rgb.astype(np.uint8)
    if marks is not None:
        rgb[marks] = ALPHA_LEGEND["stray (outside the region, alpha > 0)"]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))
