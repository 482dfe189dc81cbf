"""Known-bad supersamplers of skia's model (issue 34): each declares tiny-skia's supersampler
(``Convention(coverage="area", supersample=2, input="float32")``) and breaks it the way a port
of ``scan/path_aa.rs`` (skia's ``SkScan_AntiPath.cpp``) could."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.supersample_models import skia_supersampled_coverage

__all__ = ["EightSubScanlines", "FlooredSubPixels", "SampleCountLevels"]

TINY = Convention(coverage="area", supersample=2, input="float32")


def _answer(coverage: Coverage, alpha: np.ndarray) -> Coverage:
    return Coverage(coverage.triangle, coverage.y, coverage.x0, coverage.x1, alpha=alpha)


class EightSubScanlines:
    """Declares SUPERSAMPLE_SHIFT 2; runs with 3 (``SHIFT`` taken from the wrong constant): 8
    sub-scanlines per pixel and x in 1/8 px, the levels summed the same way."""

    name = "bad_eight_sub_scanlines"
    convention = TINY
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return skia_supersampled_coverage(Scene(scene.width, scene.height, scene.positions), replace(TINY, supersample=3))


class FlooredSubPixels:
    """Declares tiny-skia's supersampler; takes a span's ends as ``x >> 16`` (floor) instead of
    ``fdot16::round_to_i32`` (``(x + 0x8000) >> 16``): every span half a sub-pixel (1/8 px)
    to the left, as the model of the path moved so."""

    name = "bad_floored_sub_pixels"
    convention = TINY
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        moved = scene.positions.astype(np.float32).astype(np.float64) - np.array([0.125, 0.0])
        return skia_supersampled_coverage(Scene(scene.width, scene.height, moved), TINY)


class SampleCountLevels:
    """Declares tiny-skia's supersampler; adds 16 per sub-sample on every sub-row and clamps
    at the end, forgetting ``blit_h``'s ``max_value`` of 63 on a full pixel's last sub-row:
    one level high on every pixel whose last sub-row is covered whole but not all of it."""

    name = "bad_sample_count_levels"
    convention = TINY
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = skia_supersampled_coverage(Scene(scene.width, scene.height, scene.positions), TINY)
        assert exact.alpha is not None
        level = np.rint(exact.alpha * 255.0).astype(np.int64)
        count = (level + 15) // 16  # 16 N - (0 or 1): N sub-samples
        return _answer(exact, np.minimum(16 * count, 255) / 255.0)
