"""Correct rasterizers written from the public test suites' own reference rasterizers, as
a new user would port them: they declare no convention, so ``identify`` must find theirs.

- :class:`DeqpReference`: dEQP's reference renderer (``rrRasterizer.cpp``):
  ``toSubpixelCoord`` rounds ``v * 2**bits`` half away from zero, edges are int64
  ``a*x + b*y + c`` in counter-clockwise form, ``inclusive`` by the horizontal and
  vertical fill (default left and bottom in its window y, i.e. top-left with its y taken
  as ours), samples at pixel centres.
- :class:`PiglitReference`: piglit's ``triangle-rasterization`` ``rast_triangle``:
  ``iround(FIXED_ONE * (v - 0.5))`` (half away from zero in the frame of the pixel
  centre), a +1 bias on the edges its filling convention owns, ``E > 0`` per pixel.

Both round exactly on float64 input (dEQP and piglit round float32 input; that is the
input format, not the rule) and refuse coordinates whose fixed-point values would not
fit their int64 arithmetic, as the built-in ``fixed_point`` does.
"""

from __future__ import annotations

import numba
import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from rasterizers._common import check_range

__all__ = ["DeqpReference", "PiglitReference", "PIGLIT_CONVENTIONS"]


def _half_away(scaled: np.ndarray) -> np.ndarray:
    """(int64)(v + 0.5) for v >= 0, (int64)(v - 0.5) below, exactly."""
    whole = np.trunc(scaled)
    rounded: np.ndarray = (whole + np.sign(scaled) * (np.abs(scaled - whole) >= 0.5)).astype(np.int64)
    return rounded


class DeqpReference:
    """dEQP's triangle rasterizer: half-away snapping, inclusive edges by fill direction."""

    convention = None
    interpolates = False  # coverage only, as the suites compare coverage

    def __init__(self, bits: int = 8, horizontal_fill: str = "left", vertical_fill: str = "bottom") -> None:
        self.bits = bits
        self.horizontal_fill, self.vertical_fill = horizontal_fill, vertical_fill
        self.name = f"deqp_reference_{bits}"

    def rasterize(self, scene: Scene) -> Coverage:
        bits = self.bits
        limit = 2.0 ** (29 - bits)  # products of 2**31-sized fixed-point values stay in int64
        check_range(scene, limit, self.name, "its int64 edge functions overflow beyond that")
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        fixed = _half_away(np.where(finite[:, None, None], scene.positions, 0.0) * float(1 << bits))
        left, bottom = self.horizontal_fill == "left", self.vertical_fill == "bottom"
        out = _deqp_kernel(frozen(fixed, np.int64), finite, bits, left, bottom, scene.width, scene.height)
        return _fragments(out)


def _fragments(out: np.ndarray) -> Coverage:
    if not out.size:
        return Coverage.empty()
    return Coverage.from_pixels(out[:, 0], out[:, 1], out[:, 2])


@numba.njit(cache=True)
def _deqp_kernel(v, finite, bits, left, bottom, width, height):
    half, one = 1 << (bits - 1), 1 << bits
    out = []
    edges = np.empty((3, 4), dtype=np.int64)
    for t in range(v.shape[0]):
        if not finite[t]:
            continue
        area = (v[t, 1, 0] - v[t, 0, 0]) * (v[t, 2, 1] - v[t, 0, 1]) - (v[t, 1, 1] - v[t, 0, 1]) * (v[t, 2, 0] - v[t, 0, 0])
        if area == 0:
            continue
        for k in range(3):  # initEdgeCCW for v_k -> v_k+1, reverseEdge when clockwise
            x0, y0 = v[t, k, 0], v[t, k, 1]
            x1, y1 = v[t, (k + 1) % 3, 0], v[t, (k + 1) % 3, 1]
            xd, yd = x1 - x0, y1 - y0
            if yd == 0:
                inclusive = xd >= 0 if bottom else xd <= 0
            else:
                inclusive = yd <= 0 if left else yd >= 0
            s = 1 if area > 0 else -1
            edges[k, 0], edges[k, 1], edges[k, 2] = s * (y0 - y1), s * (x1 - x0), s * (x0 * y1 - y0 * x1)
            edges[k, 3] = 1 if (inclusive if area > 0 else not inclusive) else 0
        x_lo = max(min(v[t, 0, 0], v[t, 1, 0], v[t, 2, 0]) // one - 1, 0)
        x_hi = min(max(v[t, 0, 0], v[t, 1, 0], v[t, 2, 0]) // one + 1, width - 1)
        y_lo = max(min(v[t, 0, 1], v[t, 1, 1], v[t, 2, 1]) // one - 1, 0)
        y_hi = min(max(v[t, 0, 1], v[t, 1, 1], v[t, 2, 1]) // one + 1, height - 1)
        for y in range(y_lo, y_hi + 1):
            py = y * one + half
            for x in range(x_lo, x_hi + 1):
                px = x * one + half
                inside = True
                for k in range(3):
                    value = edges[k, 0] * px + edges[k, 1] * py + edges[k, 2]
                    if not (value >= 0 if edges[k, 3] else value > 0):
                        inside = False
                if inside:
                    out.append((t, x, y))
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


# piglit's filling conventions, its own biases: edge 12 owns when the test holds for
# (dx12, dy12) = v1 - v2 after the triangle is made clockwise in its y-up sense:
# (main axis, its sign, other axis's sign): "bottom_right" is dy > 0 or (dy == 0 and dx > 0).
PIGLIT_CONVENTIONS = {
    "bottom_right": (1, 1, 1), "right_bottom": (0, -1, -1), "left_bottom": (0, -1, 1), "bottom_left": (1, -1, 1),
    "top_left": (1, -1, -1), "left_top": (0, 1, 1), "right_top": (0, 1, -1), "top_right": (1, 1, -1),
}


@numba.njit(cache=True, inline="always")
def _piglit_owns(dx, dy, code):
    main, other = (dy, dx) if code[0] == 1 else (dx, dy)
    return main * code[1] > 0 or (main == 0 and other * code[2] > 0)


@numba.njit(cache=True)
def _piglit_kernel(v, finite, shift, code, width, height):
    out = []
    deltas = np.empty((3, 3), dtype=np.int64)
    for t in range(v.shape[0]):
        if not finite[t]:
            continue
        x1, y1, x2, y2, x3, y3 = v[t, 0, 0], v[t, 0, 1], v[t, 1, 0], v[t, 1, 1], v[t, 2, 0], v[t, 2, 1]
        cross = (x2 - x1) * (y3 - y2) - (y2 - y1) * (x3 - x2)
        if cross > 0:  # force its vertex order
            x1, y1, x3, y3 = x3, y3, x1, y1
        for k, (ax, ay, bx, by) in enumerate(((x1, y1, x2, y2), (x2, y2, x3, y3), (x3, y3, x1, y1))):
            dx, dy = ax - bx, ay - by
            deltas[k, 0], deltas[k, 1] = dx, dy
            deltas[k, 2] = dy * ax - dx * ay + (1 if _piglit_owns(dx, dy, code) else 0)
        minx = max(min(x1, x2, x3) >> shift, 0)
        maxx = min(max(x1, x2, x3) >> shift, width - 1)
        miny = max(min(y1, y2, y3) >> shift, 0)
        maxy = min(max(y1, y2, y3) >> shift, height - 1)
        for y in range(miny, maxy + 1):
            py = y << shift
            for x in range(minx, maxx + 1):
                px = x << shift
                if (deltas[0, 2] + deltas[0, 0] * py - deltas[0, 1] * px > 0
                        and deltas[1, 2] + deltas[1, 0] * py - deltas[1, 1] * px > 0
                        and deltas[2, 2] + deltas[2, 0] * py - deltas[2, 1] * px > 0):
                    out.append((t, x, y))
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


class PiglitReference:
    """piglit's ``rast_triangle`` with one of its eight filling conventions."""

    convention = None
    interpolates = False  # coverage only, as the suites compare coverage

    def __init__(self, filling: str = "top_left", bits: int = 8) -> None:
        self.code = np.array(PIGLIT_CONVENTIONS[filling], dtype=np.int64)
        self.shift = bits
        self.name = f"piglit_reference_{filling}_{bits}"

    def rasterize(self, scene: Scene) -> Coverage:
        shift = self.shift
        one = 1 << shift
        check_range(scene, 2.0 ** (29 - shift), self.name, "its int64 edge functions overflow beyond that")
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        # iround(FIXED_ONE * (v + center_offset)): exact, since v * 2**shift - 2**(shift-1) is
        fixed = _half_away(np.where(finite[:, None, None], scene.positions, 0.0) * float(one) - float(one // 2))
        return _fragments(_piglit_kernel(frozen(fixed, np.int64), finite, shift, self.code, scene.width, scene.height))

