"""Blend2D: a nonzero fill leaves the inside of a contour wound 128 times empty.

Blend2D's analytic rasterizer fills the inside of a triangle traced 128 times over (one
contour, winding number 128 inside) with alpha 0 under the nonzero rule, where 127 or 129
times fill it (a bug report's repro; uses blend2d-python and numpy only).

Library: Blend2D (seen with Blend2D 0.8.0 through blend2d-python 1.0.0).

Input: one closed contour listing the triangle (1, 1), (1, 7), (7, 1) k times in a row (the
same vertices, the same direction: winding number k inside the triangle), as one
``BLPath`` (``move_to``, ``line_to``..., ``close``), filled opaque white with
``BLFillRule.NON_ZERO`` on a cleared 10 x 10 A8 image, for k = 127, 128 and 129.

Expected: pixel (3, 3), entirely inside the triangle, gets 255 for every k: under the
nonzero rule every point whose winding number is not 0 is inside.

What happens: the pixel gets 255 for k = 127 and 129 but 0 for k = 128 (and the edge pixel
(4, 3), 1/2 covered, gets 0 for k = 256): each pixel's coverage is accumulated as one
signed sum of every edge's area and cover in fixed point and the nonzero rule applied to
the sum (``calc_masks_from_cells`` in ``blend2d/pipeline/jit/fillpart.cpp``,
``calc_mask`` in ``blend2d/pipeline/reference/fillgeneric_p.h``), and that sum wraps:
128 full pixels read as none, as do 256 half pixels, so a deeply wound region reads as
uncovered.

Exit status: 1 while the bug reproduces, 0 once fixed.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np


def fill(times: int) -> Any:
    """The (10, 10) A8 values of the triangle traced ``times`` times in one contour."""
    import blend2d  # here, so that collecting this file (pytest --doctest-modules) needs no blend2d

    image = blend2d.BLImage(10, 10, blend2d.BLFormat.A8)
    ctx = blend2d.BLContext(image)
    ctx.clear_all()
    ctx.fill_rule = blend2d.BLFillRule.NON_ZERO
    ctx.set_fill_style((1.0, 1.0, 1.0, 1.0))
    path = blend2d.BLPath()
    path.move_to(1.0, 1.0)
    for _ in range(times):
        for x, y in ((1.0, 7.0), (7.0, 1.0), (1.0, 1.0)):
            path.line_to(x, y)
    path.close()
    ctx.fill_path(path)
    ctx.flush()
    return np.array(image.getDataAsNumPy(), dtype=np.uint8).reshape(10, 10)


def main() -> int:
    wrong = False
    for times in (127, 128, 129):
        value = int(fill(times)[3, 3])
        print(f"winding {times}: pixel (3, 3), fully inside, = {value}")
        wrong |= value != 255
    print("BUG: a deeply wound inside is filled empty" if wrong else "fixed: every winding fills the inside")
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
