"""cairo: an anti-aliased sliver gets alpha 251/255 in a pixel it covers by 0.1% (8-bit coverage wraps).

Library: cairo 1.16 (Debian 12; pycairo), image backend, ANTIALIAS_DEFAULT (the tor scan
converter, cairo-tor-scan-converter.c), an A8 surface.

Input: one filled triangle (a sliver 0.02 px wide at its base, 23.5 px tall),
(35.02531253054519, 43.75), (35.047223827580794, 43.75), (48.46737173529964, 20.25), into a
64 x 64 A8 surface, cleared to 0, operator OVER, source opaque.

Expected: each pixel's alpha is the share of the pixel the triangle covers, rounded to
8 bits (within the scan converter's grid error, a few 1/255): pixel (47, 21) is covered by
about 0.0011 of its area (the exact value is printed), so alpha 0 or 1.

What happens: alpha 251 there. The tor converter sums the cells' coverage of a row in a
signed accumulator and writes it as a byte; for this pixel the sum is -5/255 (rounding of
the sub-row x positions makes the sliver's two edges cross within the pixel), which wraps
to 251 instead of being clamped to 0.

Exit status: 1 while the bug reproduces, 0 once fixed.
"""

import sys
from collections.abc import Callable

import cairo
import numpy as np

Point = tuple[float, float]
TRIANGLE = [(35.02531253054519, 43.75), (35.047223827580794, 43.75), (48.46737173529964, 20.25)]
PIXEL = (47, 21)


def covered_area(polygon: list[tuple[float, float]], x: int, y: int) -> float:
    """The area of the polygon within pixel [x, x+1) x [y, y+1) (Sutherland-Hodgman, float64)."""
    def clip(points: list[Point], inside: Callable[[Point], bool], cut: Callable[[Point, Point], Point]) -> list[Point]:
        out = []
        for k, p in enumerate(points):
            q = points[(k + 1) % len(points)]
            if inside(p):
                out.append(p)
            if inside(p) != inside(q):
                out.append(cut(p, q))
        return out

    def at_x(c: float) -> Callable[[Point, Point], Point]:
        return lambda p, q: (c, p[1] + (q[1] - p[1]) * (c - p[0]) / (q[0] - p[0]))

    def at_y(c: float) -> Callable[[Point, Point], Point]:
        return lambda p, q: (p[0] + (q[0] - p[0]) * (c - p[1]) / (q[1] - p[1]), c)

    pts = list(polygon)
    sides: list[tuple[Callable[[Point], bool], Callable[[Point, Point], Point]]] = [
        (lambda p: p[0] >= x, at_x(x)), (lambda p: p[0] <= x + 1, at_x(x + 1)),
        (lambda p: p[1] >= y, at_y(y)), (lambda p: p[1] <= y + 1, at_y(y + 1))]
    for inside, cut in sides:
        pts = clip(pts, inside, cut)
        if not pts:
            return 0.0
    return float(abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(pts, pts[1:] + pts[:1]))) / 2)


def main() -> int:
    surface = cairo.ImageSurface(cairo.FORMAT_A8, 64, 64)
    ctx = cairo.Context(surface)
    ctx.set_antialias(cairo.ANTIALIAS_DEFAULT)
    ctx.move_to(*TRIANGLE[0])
    for p in TRIANGLE[1:]:
        ctx.line_to(*p)
    ctx.close_path()
    ctx.fill()
    surface.flush()
    alpha = np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(64, surface.get_stride())[:, :64]
    x, y = PIXEL
    area = covered_area(TRIANGLE, x, y)
    got = int(alpha[y, x])
    print(f"cairo {cairo.cairo_version_string()}: pixel {PIXEL} alpha {got}/255, covered area {area:.6f} "
          f"(expected about {round(255 * area)}/255)")
    return 1 if abs(got / 255 - area) > 0.1 else 0


if __name__ == "__main__":
    sys.exit(main())
