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

Both round exactly on float64 input by default and refuse coordinates whose fixed-point
values would not fit their int64 arithmetic, as the built-in ``fixed_point`` does. With
``arithmetic="float32"`` they compute as their sources do: the vertex arrives as a C
``float`` (rounded to nearest-even), and the rounding to fixed point is float32 arithmetic
(dEQP ``v * (float)(1 << bits) + (v < 0.f ? -0.5f : 0.5f)``; piglit ``FIXED_ONE * (v +
center_offset)``, then ``iround``'s ``v += 0.5f``), truncated by the ``(int64_t)`` cast. Those
float32 sums are exact where the suites draw, so the float32 ports draw float32 input
snapped by their named roundings exactly, but for two artifacts of the arithmetic (no
rule): beyond 2**(22 - bits) px ``v + 0.5f`` rounds to even, where the float32 ports
refuse the coordinates (as beyond the int64 limit); and near the origin a float32 carrying
bits below 2**-25 px is rounded once more -- dEQP's ``v * 2**bits + 0.5f`` at ``v * 2**bits``
within 2**-25 below 1/2 (``0.49999997f + 0.5f`` is ``1.0f``), piglit's ``v - 0.5f`` for v in
(-1/2, 1/4) (onto a tie, which ``iround`` then takes away from zero).
``tests/identify/test_ports_float32.py`` shows both.
"""

from __future__ import annotations

import numba
import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from rasterizers._common import check_range

__all__ = ["DeqpReference", "PiglitReference", "PIGLIT_CONVENTIONS", "ARITHMETICS"]

# how the ports compute the fixed-point vertices: exactly on float64 input, or as the sources do
ARITHMETICS = ("float64", "float32")


def _float32_limit(bits: int) -> float:
    """Where a float32 port's sums stop being exact: |v * 2**bits| >= 2**22 (an ulp of 1/2
    and more: ``v + 0.5f`` rounds to even)."""
    return 2.0 ** (22 - bits)


def _received32(positions: np.ndarray, finite: np.ndarray) -> np.ndarray:
    """The coordinates as C ``float``s (round to nearest-even), non-finite triangles zeroed."""
    with np.errstate(over="ignore"):
        received: np.ndarray = np.where(finite[:, None, None], positions, 0.0).astype(np.float32)
    return received


def _truncated32(v: np.ndarray) -> np.ndarray:
    """``(int64_t)v`` of float32 values: toward zero (exact: a float32's integer part is one)."""
    out: np.ndarray = np.trunc(v).astype(np.int64)
    return out


def _half_away(scaled: np.ndarray) -> np.ndarray:
    """(int64)(v + 0.5) for v >= 0, (int64)(v - 0.5) below, exactly."""
    whole = np.trunc(scaled)
    rounded: np.ndarray = (whole + np.sign(scaled) * (np.abs(scaled - whole) >= 0.5)).astype(np.int64)
    return rounded


class DeqpReference:
    """dEQP's triangle rasterizer: half-away snapping, inclusive edges by fill direction."""

    convention = None
    interpolates = False  # coverage only, as the suites compare coverage

    def __init__(self, bits: int = 8, horizontal_fill: str = "left", vertical_fill: str = "bottom",
                 arithmetic: str = "float64") -> None:
        if arithmetic not in ARITHMETICS:
            raise ValueError(f"arithmetic must be one of {ARITHMETICS}, not {arithmetic!r}")
        self.bits, self.arithmetic = bits, arithmetic
        self.horizontal_fill, self.vertical_fill = horizontal_fill, vertical_fill
        self.name = f"deqp_reference_{bits}" + ("_float32" if arithmetic == "float32" else "")

    def rasterize(self, scene: Scene) -> Coverage:
        bits = self.bits
        limit = 2.0 ** (29 - bits)  # products of 2**31-sized fixed-point values stay in int64
        check_range(scene, limit, self.name, "its int64 edge functions overflow beyond that")
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        if self.arithmetic == "float32":
            check_range(scene, _float32_limit(bits), self.name, "its float32 sum v * 2**bits + 0.5f rounds beyond that")
            v = _received32(scene.positions, finite)
            # toSubpixelCoord: (int64_t)(v * (float)(1 << bits) + (v < 0.f ? -0.5f : 0.5f)), all float32
            fixed = _truncated32(v * np.float32(1 << bits) + np.where(v < 0, np.float32(-0.5), np.float32(0.5)))
        else:
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

    def __init__(self, filling: str = "top_left", bits: int = 8, arithmetic: str = "float64") -> None:
        if arithmetic not in ARITHMETICS:
            raise ValueError(f"arithmetic must be one of {ARITHMETICS}, not {arithmetic!r}")
        self.code = np.array(PIGLIT_CONVENTIONS[filling], dtype=np.int64)
        self.shift, self.arithmetic = bits, arithmetic
        self.name = f"piglit_reference_{filling}_{bits}" + ("_float32" if arithmetic == "float32" else "")

    def rasterize(self, scene: Scene) -> Coverage:
        shift = self.shift
        one = 1 << shift
        check_range(scene, 2.0 ** (29 - shift), self.name, "its int64 edge functions overflow beyond that")
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        if self.arithmetic == "float32":
            check_range(scene, _float32_limit(shift), self.name, "its float32 sum v + 0.5f rounds beyond that")
            # iround(FIXED_ONE * (tri[i].x + center_offset)), all float32: the sum, the
            # product (a power of two: exact), then iround's v += 0.5f (v -= 0.5f below 0)
            v = np.float32(one) * (_received32(scene.positions, finite) + np.float32(-0.5))
            fixed = _truncated32(np.where(v > 0, v + np.float32(0.5), np.where(v < 0, v - np.float32(0.5), v)))
        else:
            # iround(FIXED_ONE * (v + center_offset)) in float64: v * 2**shift is exact, the
            # difference rounds only for |v| < 1/2 carrying bits below 2**-53
            fixed = _half_away(np.where(finite[:, None, None], scene.positions, 0.0) * float(one) - float(one // 2))
        return _fragments(_piglit_kernel(frozen(fixed, np.int64), finite, shift, self.code, scene.width, scene.height))

