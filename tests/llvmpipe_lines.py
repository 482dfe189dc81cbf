"""llvmpipe's GL lines as a procedure, not a rule: a float32 port of the non-rectangular
branch of ``try_setup_line`` (Mesa, src/gallium/drivers/llvmpipe/lp_setup_line.c), the
quad it bins then decided by the exact triangle oracle under llvmpipe's triangle
convention (pixel centres, top-left ties).

What it does, per segment (window coordinates, which the adapter makes ours exactly):

* the segment is x-major when ``fabsf(dx) >= fabsf(dy)`` (dx = v1 - v2 in float32);
* ``draw_start``/``draw_end``: the GL diamond-exit decision for the end pixels, computed in
  float32 from ``x1diff = v1.x - floorf(v1.x) - 0.5`` and the like, with its own shortcuts
  (``sign(x) = x >= 0``, the intersection ``fracf(v1.y) + x1diff * dydx`` in (0, 1));
* ``will_draw_start``/``will_draw_end``: whether the quad's end edge, through the end point,
  already holds the end pixel's centre; where the two disagree the end is moved along
  the segment (``x_offset = -x1diff +- 0.5``, ``y_offset = x_offset * dydx``) to the pixel's
  far (or near) edge -- which adds a start pixel the quad lacked but never removes one it
  held, and can turn a very short quad inside out;
* the four corners, each end +- ``fixed_width/2`` (1/2 px) along the minor axis, snapped to
  1/256 px by ``subpixel_snap`` = ``util_iround(256 * v)``: on x86-64 ``(int)(f + 0.5f)``
  for f >= 0, ``(int)(f - 0.5f)`` below -- half away from zero, after a float32 add (the
  triangles snap to nearest-even through SSE: hence "lines half away" in identify);
* the quad is binned as four planes with the triangles' fill rule; one wound the other
  way (its ends swapped by the moves above) has every plane negative and draws nothing.

Mesa 22.3.6 (the version measured) decides the y-major start differently from the source
the docstring of :mod:`harness.oracle.parallelogram_lines` cites (newer, with
``bottom_edge_rule``): for a segment running up the screen (dy = v1.y - v2.y > 0) it takes
``will_draw_start = y1diff >= 0`` -- a segment starting on a centre is assumed to draw its
start pixel, which the bottom edge then leaves out. With that, the port reproduces
llvmpipe on every probe scene identify draws (0 of 9,584 pixels, where the nearest rule,
GL diamond-exit after 8-bit half-away snapping, is 399 px off and Vulkan's parallelogram
rule, the body alone, more): llvmpipe's lines are this procedure, not a rule.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Scene
from harness.oracle.coverage import exact_coverage

__all__ = ["llvmpipe_quad", "llvmpipe_lines", "LLVMPIPE_TRIANGLES"]

F = np.float32
FIXED_ONE = 256
# llvmpipe's triangles as identify found them; "cw" drops quads turned inside out (a
# well-formed quad of this port is wound counter-clockwise in y-down coordinates)
LLVMPIPE_TRIANGLES = Convention(cull="cw")


def _iround(f: np.float32) -> int:
    """Mesa's ``util_iround`` on x86-64: half away from zero after a float32 add."""
    return int(F(f + F(0.5))) if f >= 0 else int(F(f - F(0.5)))  # C's cast truncates


def _snap(v: np.float32) -> int:
    return _iround(F(F(FIXED_ONE) * v))


def _fracf(f: np.float32) -> np.float32:
    return F(f - F(math.floor(f)))


def _sign(x: np.float32) -> bool:
    return bool(x >= 0)


def llvmpipe_quad(a: NDArray[np.float64], b: NDArray[np.float64]) -> list[list[tuple[float, float]]] | None:  # noqa: C901 - the C function's shape, line for line
    """The two triangles of the quad llvmpipe bins for the segment a -> b (v1 = a, v2 = b),
    in pixel coordinates; None when it draws nothing (zero length)."""
    v1 = [F(a[0]), F(a[1])]
    v2 = [F(b[0]), F(b[1])]
    dx, dy = F(v1[0] - v2[0]), F(v1[1] - v2[1])
    if F(dx * dx + dy * dy) == 0:
        return None
    half, pixel_offset = F(0.5), F(0.5)
    x_off = y_off = x_off_end = y_off_end = F(0)
    x1diff = F(F(v1[0] - F(math.floor(v1[0]))) - half)
    y1diff = F(F(v1[1] - F(math.floor(v1[1]))) - half)
    x2diff = F(F(v2[0] - F(math.floor(v2[0]))) - half)
    y2diff = F(F(v2[1] - F(math.floor(v2[1]))) - half)
    if abs(dx) >= abs(dy):  # x-major
        dydx = F(dy / dx)
        if y2diff == -half and dy < 0:
            y2diff = half
        if F(abs(x1diff) + abs(y1diff)) < half:
            draw_start = True
        elif _sign(x1diff) == _sign(-dx):
            draw_start = False
        elif _sign(-y1diff) != _sign(dy):
            draw_start = True
        else:
            t = F(_fracf(v1[1]) + F(x1diff * dydx))
            draw_start = bool(0 < t < 1)
        if F(abs(x2diff) + abs(y2diff)) < half or _sign(x2diff) != _sign(-dx):
            draw_end = False
        elif _sign(-y2diff) == _sign(dy):
            draw_end = True
        else:
            t = F(_fracf(v2[1]) + F(x2diff * dydx))
            draw_end = bool(0 < t < 1)
        if dx < 0:
            v1, v2 = v2, v1
            if (x1diff <= 0) != draw_start:
                x_off_end = F(-x1diff - half)
                y_off_end = F(x_off_end * dydx)
            if (x2diff > 0) != draw_end:
                x_off = F(-x2diff - half)
                y_off = F(x_off * dydx)
        else:
            if (x1diff > 0) != draw_start:
                x_off = F(-x1diff + half)
                y_off = F(x_off * dydx)
            if (x2diff <= 0) != draw_end:
                x_off_end = F(-x2diff + half)
                y_off_end = F(x_off_end * dydx)
        x0, x1 = _snap(F(F(v1[0] + x_off) - pixel_offset)), _snap(F(F(v2[0] + x_off_end) - pixel_offset))
        y0, y1 = _snap(F(F(v1[1] + y_off) - pixel_offset)), _snap(F(F(v2[1] + y_off_end) - pixel_offset))
        xs = [x0, x1, x1, x0]
        ys = [y0 - FIXED_ONE // 2, y1 - FIXED_ONE // 2, y1 + FIXED_ONE // 2, y0 + FIXED_ONE // 2]
    else:  # y-major
        dxdy = F(dx / dy)
        if x2diff == -half and dx < 0:
            x2diff = half
        if F(abs(x1diff) + abs(y1diff)) < half:
            draw_start = True
        elif _sign(-y1diff) == _sign(dy):
            draw_start = False
        elif _sign(x1diff) != _sign(-dx):
            draw_start = True
        else:
            t = F(_fracf(v1[0]) + F(y1diff * dxdy))
            draw_start = bool(0 < t < 1)
        if F(abs(x2diff) + abs(y2diff)) < half or _sign(-y2diff) != _sign(dy):
            draw_end = False
        elif _sign(x2diff) == _sign(-dx):
            draw_end = True
        else:
            t = F(_fracf(v2[0]) + F(y2diff * dxdy))
            draw_end = bool(0 <= t < 1)
        if dy > 0:
            v1, v2 = v2, v1
            # Mesa 22.3.6: ">= 0" for the start (newer Mesa: "> 0" without bottom_edge_rule)
            if (y1diff >= 0) != draw_start:
                y_off_end = F(-y1diff + half)
                x_off_end = F(y_off_end * dxdy)
            if (y2diff <= 0) != draw_end:
                y_off = F(-y2diff + half)
                x_off = F(y_off * dxdy)
        else:
            if (y1diff <= 0) != draw_start:
                y_off = F(-y1diff - half)
                x_off = F(y_off * dxdy)
            if (y2diff > 0) != draw_end:
                y_off_end = F(-y2diff - half)
                x_off_end = F(y_off_end * dxdy)
        x0, x1 = _snap(F(F(v1[0] + x_off) - pixel_offset)), _snap(F(F(v2[0] + x_off_end) - pixel_offset))
        y0, y1 = _snap(F(F(v1[1] + y_off) - pixel_offset)), _snap(F(F(v2[1] + y_off_end) - pixel_offset))
        xs = [x0 - FIXED_ONE // 2, x1 - FIXED_ONE // 2, x1 + FIXED_ONE // 2, x0 + FIXED_ONE // 2]
        ys = [y0, y1, y1, y0]
    # back from the rasterizer's frame (samples on integers) to pixel centres
    c = [(xs[k] / FIXED_ONE + 0.5, ys[k] / FIXED_ONE + 0.5) for k in range(4)]
    return [[c[0], c[1], c[2]], [c[0], c[2], c[3]]]


def llvmpipe_lines(scene: LineScene) -> Coverage:
    """Every finite segment's pixels as llvmpipe draws them (width 1), by :func:`llvmpipe_quad`."""
    a, b = scene.segments()
    triangles: list[list[tuple[float, float]]] = []
    owner: list[int] = []
    for s in range(len(a)):
        if not (np.isfinite(a[s]).all() and np.isfinite(b[s]).all()):
            continue
        quad = llvmpipe_quad(a[s], b[s])
        if quad is not None:
            triangles += quad
            owner += [s, s]
    if not triangles:
        return Coverage.empty()
    drawn = exact_coverage(Scene(scene.width, scene.height, np.array(triangles, dtype=np.float64)), LLVMPIPE_TRIANGLES)
    primitive, x, y = drawn.pixels()
    return Coverage.from_pixels(np.asarray(owner, dtype=np.int64)[primitive], x, y)
