"""aggdraw: a filled triangle's pixels change when its vertices are listed in the other order (AGG's cover rounding).

aggdraw (AGG 2.0) fills a triangle differently when its vertices are listed in the
other order (a bug report's repro; uses aggdraw and numpy only).

Library: aggdraw (seen with 1.4.1, which vendors AGG 2.0 in ``agg2/``).

Input: the right triangle (1, 1), (1 + 255/256, 1), (1, 2) in pixel coordinates (every
vertex exact in AGG's 24.8 fixed point), filled with a ``Brush`` on an "L" image, once in
each vertex order, anti-aliased and aliased (``setantialias(False)``). A pen of width 0
and opacity 0 is passed so that aggdraw does not grow the polygon (without a pen it
offsets every fill outward by 0.25 px; with one, by a quarter of the pen's width).

Expected: the same pixels in both orders. A filled polygon is a region of the plane;
reversing its vertices does not change it under the nonzero rule (aggdraw's), and AGG
computes each pixel's coverage from the region's area inside it.

What happens: AGG's ``rasterizer_scanline_aa::calculate_alpha``
(``agg2/include/agg_rasterizer_scanline_aa.h``) turns the signed cell area into a cover
by an arithmetic shift and then an absolute value (``int cover = area >>
(poly_base_shift*2 + 1 - aa_shift); if (cover < 0) cover = -cover;``): the shift floors,
so one orientation is rounded down and the other up. Pixel (1, 1), 0.498 covered, gets
cover 128 in one order and 127 in the other: aliased, where aggdraw draws a pixel iff
its cover is at least 128 (``gamma_threshold(0.5)``), it is drawn in one order only.

Exit status: 1 while the bug reproduces, 0 once fixed.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np


def fill(vertices: list[tuple[float, float]], antialias: bool) -> Any:
    """The (4, 4) gray values of the triangle filled white on a 4 x 4 black image."""
    import aggdraw  # here, so that collecting this file (pytest --doctest-modules) needs no aggdraw

    draw = aggdraw.Draw("L", (4, 4), 0)
    draw.setantialias(antialias)
    path = aggdraw.Path()
    path.moveto(*vertices[0])
    for x, y in vertices[1:]:
        path.lineto(x, y)
    path.close()
    draw.polygon(path, aggdraw.Pen(0, 0, 0), aggdraw.Brush(255))  # the pen: no 0.25 px growth
    return np.frombuffer(draw.tobytes(), dtype=np.uint8).reshape(4, 4)


def main() -> int:
    triangle = [(1.0, 1.0), (1 + 255 / 256, 1.0), (1.0, 2.0)]
    differs = False
    for antialias in (True, False):
        one, other = fill(triangle, antialias), fill(triangle[::-1], antialias)
        print(f"setantialias({antialias}): pixel (1, 1) = {int(one[1, 1])} in one vertex order, "
              f"{int(other[1, 1])} in the other")
        differs |= not np.array_equal(one, other)
    print("BUG: the fill depends on the vertex order" if differs else "fixed: both orders fill the same")
    return 1 if differs else 0


if __name__ == "__main__":
    sys.exit(main())
