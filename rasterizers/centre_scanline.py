"""``centre_scanline``: centre sampling with prestep (seed 001).

The first row is ``ceil(y_top - 0.5)``; the start x and every interpolant are prestepped
to that row's sample, ``x = x_a + dxdy * (row + 0.5 - y_a)``; spans run
``ceil(x_left - 0.5) .. ceil(x_right - 0.5) - 1``. Half-open ``[a, b)`` on both axes is
exactly the top-left rule.

Convention: sample (0.5, 0.5), ``top-left`` ties.
"""

from __future__ import annotations

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers._common import build_coverage, interpolate_planes
from rasterizers._scanline import scanline

__all__ = ["CentreScanline"]


class CentreScanline:
    """Seed 001's centre-sampled scanline rasterizer with prestep.

    Examples
    --------
    >>> CentreScanline().rasterize(Scene(4, 3, [[[0.5, 0.5], [3.5, 0.5], [0.5, 2.5]]])).counts(4, 3)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    """

    name = "centre_scanline"
    convention = Convention(sample=(0.5, 0.5), tie="top-left")

    def rasterize(self, scene: Scene) -> Coverage:
        spans, n, edge_x = scanline(scene, centre=True, name=self.name)
        attributes = interpolate_planes(scene, spans, n, edge_x, self.convention.sample)
        return build_coverage(scene, spans, n, attributes)
