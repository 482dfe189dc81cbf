"""``floor_scanline``: the 1998 floor convention with subpixel and subtexel correction (seed 000).

Rows ``floor(y_top) .. floor(y_bottom) - 1`` and columns ``floor(x_left) .. floor(x_right) - 1``,
never ``+ 1``, so shared vertices and edges are drawn once and a flat triangle draws nothing.
Each row's span is evaluated at ``y = j + 1``, the only height consistent with that row
count; the start x is the edge's x corrected for the y error (``x_top + Ey * dxdy``, here
evaluated afresh per row rather than accumulated), and each interpolant at the span start
is corrected for the x error (``+ Ex * du/dx``) before stepping by ``du/dx``.

Convention: sample (1, 1), ``bottom-right`` ties -- intervals ``(a, b]`` on both axes.
"""

from __future__ import annotations

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers._common import build_coverage, interpolate_planes
from rasterizers._scanline import scanline

__all__ = ["FloorScanline"]


class FloorScanline:
    """Seed 000's floor scanline rasterizer.

    Examples
    --------
    >>> FloorScanline().rasterize(Scene(4, 3, [[[0.5, 0.5], [3.5, 0.5], [0.5, 2.5]]])).counts(4, 3)
    array([[1, 1, 0, 0],
           [1, 0, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    """

    name = "floor_scanline"
    convention = Convention(sample=(1.0, 1.0), tie="bottom-right")

    def rasterize(self, scene: Scene) -> Coverage:
        spans, n, edge_x = scanline(scene, centre=False, name=self.name)
        attributes = interpolate_planes(scene, spans, n, edge_x, self.convention.sample)
        return build_coverage(scene, spans, n, attributes)
