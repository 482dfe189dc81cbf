"""matplotlib (Agg): a filled triangle's pixels change when its vertices are listed in the other order (AGG's cover rounding).

matplotlib's Agg backend fills a triangle differently when its vertices are listed in the
other order (a bug report's repro; uses matplotlib and numpy only).

Library: matplotlib (seen with 3.11.2; AGG 2.4 as vendored in ``extern/agg24-svn``).

Input: the right triangle (1, 1), (1 + 255/256, 1), (1, 2) in pixel coordinates (every
vertex exact in AGG's 24.8 fixed point), drawn with ``RendererAgg.draw_path`` at 72 dpi,
snapping off, as a filled path, once in each vertex order; and a sliver 1 px long and
1/256 px high, likewise.

Expected: the same pixels and alphas in both orders. A filled polygon is a region of the
plane; under the nonzero rule (AGG's default, which ``draw_path`` keeps) reversing its
vertices does not change the region, and AGG computes each pixel's coverage from the
region's area inside it.

What happens: AGG's ``rasterizer_scanline_aa::calculate_alpha`` turns the signed area
accumulated in a cell into a cover with an arithmetic shift, then takes the absolute
value (``int cover = area >> (poly_subpixel_shift*2 + 1 - aa_shift); if (cover < 0) cover
= -cover;``): the shift floors, so an area of one sign is rounded down and the other up
(``|floor(-x)| = ceil(x)``). The triangle's pixel (1, 1), 0.498 covered, gets alpha 128
in one order and 127 in the other; aliased (``antialiased=False``: every cell with a
nonzero cover is drawn), the sliver, 1/512 of a pixel, is drawn in one order and not in
the other, so whether a thin shape shows depends on the order of its vertices.

Exit status: 1 while the bug reproduces, 0 once fixed.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np


def fill(vertices: list[tuple[float, float]], antialiased: bool) -> Any:
    """The (4, 4) alpha channel of the triangle filled black on a 4 x 4 canvas, y down."""
    # imported here, so that collecting this file (pytest --doctest-modules) needs no matplotlib
    from matplotlib.backends import backend_agg
    from matplotlib.path import Path
    from matplotlib.transforms import Affine2D

    RendererAgg: Any = backend_agg.RendererAgg
    renderer = RendererAgg(4, 4, 72)
    gc = renderer.new_gc()
    gc.set_antialiased(antialiased)
    gc.set_snap(False)
    gc.set_linewidth(0)
    codes = [Path.MOVETO, Path.LINETO, Path.LINETO, Path.CLOSEPOLY]
    path = Path(np.array([*vertices, vertices[0]], dtype=float), codes)
    flip: Any = Affine2D().scale(1, -1).translate(0, 4)  # cancels draw_path's own y flip: pixel rows y down
    renderer.draw_path(gc, path, flip, (0, 0, 0, 1))
    return np.asarray(renderer.buffer_rgba())[..., 3].copy()


def main() -> int:
    differs = False
    shapes: list[tuple[str, list[tuple[float, float]], bool]] = [
        ("triangle 0.498 px^2, anti-aliased", [(1.0, 1.0), (1 + 255 / 256, 1.0), (1.0, 2.0)], True),
        ("sliver 1/512 px^2, aliased", [(1.0, 1.0), (2.0, 1.0), (1.0, 1 + 1 / 256)], False),
    ]
    for what, triangle, antialiased in shapes:
        one = fill(triangle, antialiased)
        other = fill(triangle[::-1], antialiased)
        print(f"{what}: pixel (1, 1) alpha {int(one[1, 1])} in one vertex order, {int(other[1, 1])} in the other")
        differs |= not np.array_equal(one, other)
    print("BUG: the fill depends on the vertex order" if differs else "fixed: both orders fill the same")
    return 1 if differs else 0


if __name__ == "__main__":
    sys.exit(main())
