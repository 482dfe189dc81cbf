"""Known-bad anti-aliasers of the row-sampled model (issue 34): each declares cairo's
row-sampled area coverage (``Convention(coverage="area", rows=15)``) and breaks it the way
a port of ``cairo-tor-scan-converter.c`` could."""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.aa_models import row_sampled_coverage

__all__ = ["RowsAtTopEdges", "RowsTruncatedLevels", "HybridSamplesEveryRow"]


def _eight_bit(alpha: np.ndarray, rounding: str = "nearest") -> np.ndarray:
    scaled = np.clip(alpha, 0.0, 1.0) * 255.0
    out: np.ndarray = (np.floor(scaled) if rounding == "floor" else np.rint(scaled)) / 255.0
    return out


def _answer(coverage: Coverage, alpha: np.ndarray) -> Coverage:
    return Coverage(coverage.triangle, coverage.y, coverage.x0, coverage.x1, alpha=alpha)


class RowsAtTopEdges:
    """Declares 15 sample rows per pixel at the sub-row centres; samples each sub-row on its
    top line, y = j + k/15 (``(2 * ytop + 1)`` written ``2 * ytop``): every edge's coverage
    moves down by half a sub-row, 1/30 px."""

    name = "bad_rows_at_top_edges"
    convention = Convention(coverage="area", rows=15)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        moved = Scene(scene.width, scene.height, scene.positions + np.array([0.0, 0.5 / 15]))
        exact = row_sampled_coverage(moved, self.convention)
        assert exact.alpha is not None
        return _answer(exact, _eight_bit(exact.alpha))


class RowsTruncatedLevels:
    """Declares 15 sample rows per pixel on 256 levels (cairo rounds the cell area half up,
    ``GRID_AREA_TO_ALPHA``); converts with ``(c * 255) / GRID_XY``: truncates."""

    name = "bad_rows_truncated_levels"
    convention = Convention(coverage="area", rows=15)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = row_sampled_coverage(scene, self.convention)
        assert exact.alpha is not None
        return _answer(exact, _eight_bit(exact.alpha, "floor"))


class HybridSamplesEveryRow:
    """Declares cairo's hybrid (15 rows, analytic full rows on the 24.8 grid); samples every
    pixel row on its 15 lines, the full rows too (``can_do_full_row`` always false): shallow
    edges in full rows are off by up to a sub-row's share."""

    name = "bad_hybrid_samples_every_row"
    convention = Convention(coverage="area", rows=15, full_rows=True, input="fixed8")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        sampled = Convention(coverage="area", rows=15, input="fixed8")
        exact = row_sampled_coverage(scene, sampled)
        assert exact.alpha is not None
        return _answer(exact, _eight_bit(exact.alpha))
