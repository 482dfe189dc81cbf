"""pygame: draw.polygon stalls (tens of seconds to minutes) on a NaN or infinite y coordinate.

Library: pygame 2.6.1 (SDL 2.28.4), Python 3.11, x86-64 Linux; found by rastercheck.

Input: an 8-bit 16 x 16 surface and the triangle (1, 1), (5, -inf), (3, 10):

    pygame.draw.polygon(surface, 255, [(1, 1), (5, float("-inf")), (3, 10)])

Expected: an immediate return, either refusing the point (as ``draw.polygon`` refuses
fewer than three points with ValueError) or drawing nothing / something bounded by the
16 x 16 surface; ``draw.line`` with the same infinite end point returns in microseconds.

What happens: the call does not return for a long time (88 s measured for one triangle;
it returns eventually, with whatever it drew). ``polygon`` in ``src_c/draw.c`` casts each
coordinate to ``int``; the cast of an infinite or NaN double is undefined behaviour in C
and gives INT_MIN on x86-64. ``draw_fillpoly`` then loops ``for (y = miny; y <= maxy;
y++)`` over every row between the lowest and highest vertex, never clipped to the
surface: about 2**31 rows, each testing every edge. An infinite or NaN x does not stall
(the row range stays small). Finite but huge y coordinates are slow for the same reason
(the loop is not clipped to the surface).

Exit status: the script runs the call in a child process with a timeout; it prints the
evidence and exits 1 while the bug reproduces (the call is still running after the timeout), 0 once
the call returns promptly.
"""

import contextlib
import multiprocessing
import os
import sys
import time

TIMEOUT = 3.0  # seconds from the call (pygame imported); a fixed pygame returns in microseconds


def draw(bad_y: float, ready: "multiprocessing.synchronize.Event") -> None:
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    surface = pygame.Surface((16, 16), depth=8)
    ready.set()
    with contextlib.suppress(ValueError, TypeError, OverflowError):  # refusing the point is a fix too
        pygame.draw.polygon(surface, 255, [(1, 1), (5, bad_y), (3, 10)])


def main() -> int:
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    print(f"pygame {pygame.version.ver}, SDL {'.'.join(map(str, pygame.get_sdl_version()))}")
    stalled = []
    context = multiprocessing.get_context("spawn")
    children = []
    for bad_y in (float("-inf"), float("inf"), float("nan")):  # one child each, side by side
        ready = context.Event()
        child = context.Process(target=draw, args=(bad_y, ready))
        child.start()
        children.append((bad_y, child, ready))
    for bad_y, child, ready in children:
        if not ready.wait(60.0):
            child.kill()
            print(f"y = {bad_y}: the child could not import pygame")
            return 2
    start = time.monotonic()  # every call has begun by now
    for bad_y, child, _ready in children:
        child.join(max(0.0, start + TIMEOUT - time.monotonic()))
        elapsed = time.monotonic() - start
        if child.is_alive():
            child.kill()
            child.join()
            stalled.append(bad_y)
            print(f"y = {bad_y}: draw.polygon still running {elapsed:.1f} s or more after the call (killed)")
        else:
            print(f"y = {bad_y}: draw.polygon returned after {elapsed:.2f} s (exit code {child.exitcode})")
    if stalled:
        print(f"BUG: draw.polygon stalls on a non-finite y coordinate ({', '.join(map(str, stalled))})")
        return 1
    print("fixed: draw.polygon returns promptly on non-finite y coordinates")
    return 0


if __name__ == "__main__":
    sys.exit(main())
