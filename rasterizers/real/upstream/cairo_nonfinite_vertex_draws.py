"""cairo: a path with a NaN or infinite coordinate fills pixels (aliased and anti-aliased).

Library: cairo 1.16 (Debian 12; pycairo), image backend, an A8 surface.

Input: the triangle (2, 2), (x, 3), (10, 12) with x = NaN, and again with x = +inf, filled
on a 16 x 16 A8 surface with ANTIALIAS_NONE and with ANTIALIAS_DEFAULT.

Expected: nothing drawn -- a shape with a NaN vertex has no defined area, and cairo's own
API treats non-finite matrices as errors (CAIRO_STATUS_INVALID_MATRIX); at the least, the
context should enter an error status (cairo_status) rather than draw some pixels. skia
draws nothing for the same path (SkPath::isFinite: a non-finite path is not drawn).

What happens: pixels are filled (14 aliased, 25-32 anti-aliased here), and the context's
status stays CAIRO_STATUS_SUCCESS (pycairo raises on any other): _cairo_fixed_from_double turns the non-finite value
into an arbitrary fixed-point number, which then bounds a real polygon.

Exit status: 1 while the bug reproduces, 0 once fixed.
"""

import sys

import cairo
import numpy as np


def filled(x: float, antialias: "cairo.Antialias") -> int:
    surface = cairo.ImageSurface(cairo.FORMAT_A8, 16, 16)
    ctx = cairo.Context(surface)
    ctx.set_antialias(antialias)
    ctx.move_to(2, 2)
    ctx.line_to(x, 3)
    ctx.line_to(10, 12)
    ctx.close_path()
    ctx.fill()
    surface.flush()
    alpha = np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(16, surface.get_stride())[:, :16]
    return int(np.count_nonzero(alpha))


def main() -> int:
    drawn = 0
    for x in (float("nan"), float("inf")):
        for name, mode in (("ANTIALIAS_NONE", cairo.ANTIALIAS_NONE), ("ANTIALIAS_DEFAULT", cairo.ANTIALIAS_DEFAULT)):
            pixels = filled(x, mode)  # pycairo raises should the context enter an error status
            print(f"cairo {cairo.cairo_version_string()}: vertex x = {x}, {name}: {pixels} pixels filled, no error")
            drawn += pixels
    return 1 if drawn else 0


if __name__ == "__main__":
    sys.exit(main())
