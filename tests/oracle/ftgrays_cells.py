"""FreeType's cell accumulation, ported for one test: ``gray_render_line`` (the 64-bit
branch of ``src/smooth/ftgrays.c``, FreeType 2.13) and ``gray_sweep``'s ``FT_FILL_RULE``,
on integers as FreeType holds them. It shows where :mod:`harness.oracle.analytic_models`'s
model of FreeType (the exact area's ``ftgrays`` level) and FreeType part: each edge's
crossing of a cell boundary is ``FT_UDIV(a, b) = (a * (0xFFFFFFFF / b)) >> 32``, truncated to
1/256 px (and one unit lower still where the truncated reciprocal falls short), so a
pixel's area is that of a polygon whose crossings moved down by up to 1/128 px."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

ONE_PIXEL = 256  # PIXEL_BITS 8


def _udiv(a: int, b: int) -> int:
    """FT_UDIVPREP then FT_UDIV: a / b by the truncated reciprocal, on 64-bit unsigned."""
    return (a * (0xFFFFFFFF // b)) >> 32


def cells(points: list[tuple[int, int]]) -> dict[tuple[int, int], list[int]]:
    """The cells (ex, ey) -> [cover, area] of one closed contour of points in 1/256 px
    (26.6 upscaled by 4), FreeType's axes (y up): ``gray_render_line`` edge by edge."""
    out: dict[tuple[int, int], list[int]] = {}

    def integrate(ex: int, ey: int, a: int, b: int) -> None:  # FT_INTEGRATE
        cell = out.setdefault((ex, ey), [0, 0])
        cell[0] += a
        cell[1] += a * b

    x, y = points[-1]
    for tx, ty in points:
        ex1, ey1, ex2, ey2 = x >> 8, y >> 8, tx >> 8, ty >> 8
        fx1, fy1 = x & 255, y & 255
        dx, dy = tx - x, ty - y
        if (ex1, ey1) != (ex2, ey2):
            if dy == 0:  # a horizontal line changes no cover
                x, y = tx, ty
                continue
            if dx == 0:  # vertical: whole cells up or down
                step = 1 if dy > 0 else -1
                while ey1 != ey2:
                    integrate(ex1, ey1, (ONE_PIXEL if step > 0 else 0) - fy1, fx1 * 2)
                    fy1 = 0 if step > 0 else ONE_PIXEL
                    ey1 += step
            else:
                prod = dx * fy1 - dy * fx1
                while (ex1, ey1) != (ex2, ey2):
                    if prod - dx * ONE_PIXEL > 0 >= prod:  # left
                        fx2, fy2 = 0, _udiv(-prod, -dx)
                        prod -= dy * ONE_PIXEL
                        integrate(ex1, ey1, fy2 - fy1, fx1 + fx2)
                        fx1, fy1, ex1 = ONE_PIXEL, fy2, ex1 - 1
                    elif prod - dx * ONE_PIXEL + dy * ONE_PIXEL > 0 >= prod - dx * ONE_PIXEL:  # up
                        prod -= dx * ONE_PIXEL
                        fx2, fy2 = _udiv(-prod, dy), ONE_PIXEL
                        integrate(ex1, ey1, fy2 - fy1, fx1 + fx2)
                        fx1, fy1, ey1 = fx2, 0, ey1 + 1
                    elif prod + dy * ONE_PIXEL >= 0 >= prod - dx * ONE_PIXEL + dy * ONE_PIXEL:  # right
                        prod += dy * ONE_PIXEL
                        fx2, fy2 = ONE_PIXEL, _udiv(prod, dx)
                        integrate(ex1, ey1, fy2 - fy1, fx1 + fx2)
                        fx1, fy1, ex1 = 0, fy2, ex1 + 1
                    else:  # down
                        fx2, fy2 = _udiv(prod, -dy), 0
                        prod += dx * ONE_PIXEL
                        integrate(ex1, ey1, fy2 - fy1, fx1 + fx2)
                        fx1, fy1, ey1 = fx2, ONE_PIXEL, ey1 - 1
        integrate(ex1, ey1, (ty & 255) - fy1, fx1 + (tx & 255))
        x, y = tx, ty
    return out


def level(triangle: NDArray[np.float64], x: int, y: int, height: int = 4096) -> tuple[int, int]:
    """(FreeType's level, its accumulated area in 1/131072 px) of pixel (x, y) for a
    triangle on the 26.6 grid (screen coordinates, y down; flipped about ``height`` as the
    adapter flips about its box: whole pixels, so the same fractions): ``gray_sweep``'s
    running cover, then ``FT_FILL_RULE`` (nonzero)."""
    points = [(round(float(px) * 256), round((height - float(py)) * 256)) for px, py in triangle]
    found = cells(points)
    ey = height - 1 - y
    cover = 0
    area = 0
    for (cx, cy), (c, a) in sorted(found.items()):
        if cy == ey and cx <= x:
            cover += c * ONE_PIXEL * 2
            area = cover - a if cx == x else cover
    k = area >> 9
    return min(~k if k < 0 else k, 255), area
