"""pygame: draw.polygon draws pixels for a polygon with a NaN (or infinite) x coordinate.

Library: pygame 2.6.1 (SDL 2.28.4), Python 3.11, x86-64 Linux; found by rastercheck.

Input: an 8-bit 16 x 16 surface, cleared to 0, and the triangle (1, 1), (nan, 3), (3, 10):

    pygame.draw.polygon(surface, 255, [(1, 1), (float("nan"), 3), (3, 10)])

Expected: no pixel drawn, or the point refused (``draw.polygon`` already refuses fewer
than three points with ValueError): a point with a NaN coordinate is nowhere, so the
polygon encloses nothing. (An infinite x makes the polygon unbounded; what it should draw
is debatable, so only NaN is asserted here.)

What happens: 22 pixels are drawn, a wedge along the surface's left edge, as if the point
were far to the left. ``polygon`` in ``src_c/draw.c`` casts each coordinate to ``int``; the
cast of a NaN double is undefined behaviour in C and gives INT_MIN on x86-64, so the point
becomes (-2147483648, 3), and ``draw_fillpoly`` fills that polygon, clipped to the surface.
(A NaN or infinite *y* instead stalls the call: see ``pygame_polygon_inf_stall.py``.)

Exit status: prints the evidence; exits 1 while the bug reproduces (pixels drawn), 0 once fixed.
"""

import os
import sys

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")


def main() -> int:
    import numpy as np
    import pygame

    print(f"pygame {pygame.version.ver}, SDL {'.'.join(map(str, pygame.get_sdl_version()))}")
    surface = pygame.Surface((16, 16), depth=8)
    surface.fill(0)
    try:
        pygame.draw.polygon(surface, 255, [(1, 1), (float("nan"), 3), (3, 10)])
    except (ValueError, TypeError) as exc:
        print(f"fixed: the NaN point is refused ({type(exc).__name__}: {exc})")
        return 0
    pixels = np.frombuffer(surface.get_buffer().raw, dtype=np.uint8).reshape(16, surface.get_pitch())[:, :16] > 0
    drawn = int(pixels.sum())
    print(f"pixels drawn for a triangle with a NaN vertex: {drawn}")
    print("\n".join("".join("#" if p else "." for p in row) for row in pixels))
    if drawn:
        print("BUG: a polygon with a NaN coordinate draws pixels")
        return 1
    print("fixed: nothing drawn")
    return 0


if __name__ == "__main__":
    sys.exit(main())
