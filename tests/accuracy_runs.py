"""One accuracy run of a model's reference port or known-bad over chosen cases: what the
model tests (cairo's rows, skia's supersampler, the analytic libraries' levels) share."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from harness import run_suite


def assert_judged_by_accuracy(rasterizer: Any, cases: Sequence[Any], passes: bool) -> None:
    """Run accuracy alone on ``cases``: every result passes for a correct port (``passes``),
    at least one fails for a known-bad."""
    assert cases
    statuses = [r.status for r in run_suite([rasterizer], cases=list(cases), isolate=False, identify=False, repros=False,
                                            only={"accuracy"}, timeout=60.0)]
    assert statuses
    if passes:
        assert set(statuses) == {"pass"}, statuses
    else:
        assert "fail" in statuses, statuses


def dense_alphas(coverage: Any, width: int, height: int) -> Any:
    """(height, width) float64: each pixel's alphas summed over the primitives covering it
    (none: zeros)."""
    import numpy as np

    image = np.zeros((height, width))
    if coverage.alpha is None:
        return image
    _, x, y = coverage.pixels()
    np.add.at(image, (y, x), coverage.alpha)
    return image
