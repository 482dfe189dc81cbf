"""dEQP's reference renderer rasterizing triangles at 2, 4, 8 or 16 samples per pixel, ported.

Ported from ``framework/referencerenderer/rrRasterizer.cpp`` of KhronosGroup/VK-GL-CTS
(commit c57d29f97dbd51e6ff57e9eb1a98808e66afa0d3, the file last changed in 60a706c4),
``TriangleRasterizer::init`` and ``TriangleRasterizer::rasterizeMultiSample<N>`` with the
default ``RasterizationState`` (counter-clockwise winding, ``FILL_LEFT``, ``FILL_BOTTOM``)
and 8 subpixel bits, as dEQP's GLES and Vulkan tests drive it. The original, compiled from
``tests/peers/src/deqp`` (:mod:`tests.test_peer_deqp`), decides every sample alike.

What the original does, and the port with it:

- Vertices are ``tcu::Vec4`` floats: a float64 coordinate becomes the nearest float32
  (as a caller's ``(float)`` does), then ``toSubpixelCoord`` computes
  ``(int64_t)(v * 256.0f + (v < 0 ? -0.5f : 0.5f))`` in float32 arithmetic: rounding half
  away from zero to 1/256 px, except where the float32 sum itself rounds (for
  32,768 <= |v| < 65,536 px an odd multiple of 1/256 gains 1/256; the float32 just below
  1/512 becomes 1/256).
- The sample offsets are the float tables ``s_samplePts2/4/8/16`` put through the same
  ``toSubpixelCoord``: 2x at 0.3 and 0.7 becomes 77/256 and 179/256, 4x is (1/4 + k/2)
  on a grid, 8x is in sixteenths, 16x is the 4x4 grid at (1/8 + k/4).
- ``initEdgeCCW`` makes each edge ``a*x + b*y + c`` in int64, inclusive when horizontal
  and running in +x (``FILL_BOTTOM``: the interior lies at larger y) or running in -y
  otherwise (``FILL_LEFT``); a triangle whose edge 01 is not positive at v2 has all three
  edges reversed (sign and inclusiveness). A sample is covered when every edge is
  ``>= 0`` (inclusive) or ``> 0``. In the harness's screen (y down) that is the
  top-left tie rule.
- The pixels tested are those of the 2x2 packets walked from the bounding box
  (``floorSubpixelToPixelCoord`` / ``ceilSubpixelToPixelCoord``) clamped to the
  viewport; a packet's second column or row is dropped at the viewport's edge.

Where the original is undefined the port refuses or draws nothing: a finite coordinate
beyond 2**21 px (its int64 edge products overflow, its float-to-int64 conversion
saturates) raises ValueError naming the triangle; a triangle with a non-finite coordinate
(converted to an undefined int64 by the original) covers nothing.

Cross-check against the compiled original: see :mod:`tests.test_peer_deqp` (the numbers
of the long run are in its docstring).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.api import Coverage, Scene
from harness.exact import frozen
from rasterizers._common import check_range

__all__ = ["SAMPLE_POINTS", "SUBPIXEL_BITS", "DeqpMultisample", "to_subpixel", "sample_offsets"]

SUBPIXEL_BITS = 8
"""dEQP's GLES and Vulkan tests build the rasterizer with 8 subpixel bits."""

SAMPLE_POINTS: dict[int, tuple[tuple[float, float], ...]] = {
    2: ((0.3, 0.3), (0.7, 0.7)),
    4: ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)),
    8: ((7 / 16, 9 / 16), (9 / 16, 13 / 16), (11 / 16, 3 / 16), (13 / 16, 11 / 16),
        (1 / 16, 7 / 16), (5 / 16, 1 / 16), (15 / 16, 5 / 16), (3 / 16, 15 / 16)),
    16: tuple(((2 * i + 1) / 8, (2 * j + 1) / 8) for j in range(4) for i in range(4)),
}
"""``s_samplePts2``, ``s_samplePts4``, ``s_samplePts8``, ``s_samplePts16``: (x, y) per
sample, in sample order, as written in the source (float literals)."""


def to_subpixel(values: NDArray[np.floating], bits: int) -> NDArray[np.int64]:
    """``toSubpixelCoord(float v, int bits)`` elementwise: ``v`` rounded to float32, then
    ``(int64_t)(v * (float)(1 << bits) + (v < 0.f ? -0.5f : 0.5f))`` in float32.

    Parameters
    ----------
    values : (...) float
        Finite, of magnitude below 2**62 / 2**bits (else the original is undefined).
    bits : int

    Returns
    -------
    (...) int64

    Examples
    --------
    >>> to_subpixel(np.array([0.3, 0.7, -1.5 / 256, 32768 + 1 / 256]), 8).tolist()
    [77, 179, -2, 8388610]
    """
    v = np.asarray(values, dtype=np.float64).astype(np.float32)
    half = np.where(v < np.float32(0.0), np.float32(-0.5), np.float32(0.5)).astype(np.float32)
    scaled = (v * np.float32(1 << bits)).astype(np.float32) + half  # float32 + float32: float32
    assert scaled.dtype == np.float32
    return np.trunc(scaled).astype(np.int64)


def sample_offsets(samples: int, bits: int = SUBPIXEL_BITS) -> NDArray[np.int64]:
    """``samplePos`` of ``rasterizeMultiSample``: each sample's offset in 1/2**bits px.

    Returns
    -------
    (samples, 2) int64
    """
    return to_subpixel(np.array(SAMPLE_POINTS[samples], dtype=np.float64), bits)


@numba.njit(cache=True, inline="always")
def _floor_pixel(coord, bits, fill_edge):  # type: ignore[no-untyped-def]
    """floorSubpixelToPixelCoord (arithmetic shifts round toward -inf, as in C on int64)."""
    if coord >= 0:
        return (coord - (1 if fill_edge else 0)) >> bits
    return (coord - ((1 << bits) - (0 if fill_edge else 1))) >> bits


@numba.njit(cache=True, inline="always")
def _ceil_pixel(coord, bits, fill_edge):  # type: ignore[no-untyped-def]
    """ceilSubpixelToPixelCoord."""
    if coord >= 0:
        return (coord + ((1 << bits) - (0 if fill_edge else 1))) >> bits
    return (coord + (1 if fill_edge else 0)) >> bits


@numba.njit(cache=True, inline="always")
def _init_edge_ccw(edges, k, x0, y0, x1, y1):  # type: ignore[no-untyped-def]
    """initEdgeCCW with FILL_LEFT and FILL_BOTTOM: row k of ``edges`` = a, b, c, inclusive."""
    xd, yd = x1 - x0, y1 - y0
    if yd == 0:
        inclusive = xd >= 0  # verticalFill == FILL_BOTTOM
    else:
        inclusive = yd <= 0  # horizontalFill == FILL_LEFT
    edges[k, 0] = y0 - y1
    edges[k, 1] = x1 - x0
    edges[k, 2] = x0 * y1 - y0 * x1
    edges[k, 3] = 1 if inclusive else 0


@numba.njit(cache=True)
def _multisample_kernel(v, drawn, offsets, bits, width, height):  # type: ignore[no-untyped-def]
    """Runs ``(triangle, sample, y, x0, x1)`` of covered samples, sorted by triangle,
    sample and row; ``v`` (T, 3, 2) int64 subpixel vertices, ``drawn`` (T,) bool."""
    out = []
    edges = np.empty((3, 4), dtype=np.int64)
    n_samples = offsets.shape[0]
    for t in range(v.shape[0]):
        if not drawn[t]:
            continue
        x0, y0, x1, y1, x2, y2 = v[t, 0, 0], v[t, 0, 1], v[t, 1, 0], v[t, 1, 1], v[t, 2, 0], v[t, 2, 1]
        # TriangleRasterizer::init, m_winding == WINDING_CCW
        _init_edge_ccw(edges, 0, x0, y0, x1, y1)
        _init_edge_ccw(edges, 1, x1, y1, x2, y2)
        _init_edge_ccw(edges, 2, x2, y2, x0, y0)
        s = edges[0, 0] * x2 + edges[0, 1] * y2 + edges[0, 2]
        if not s > 0:  # reverseEdge on all three
            for k in range(3):
                edges[k, 0], edges[k, 1], edges[k, 2] = -edges[k, 0], -edges[k, 1], -edges[k, 2]
                edges[k, 3] = 1 - edges[k, 3]
        x_min, x_max = min(min(x0, x1), x2), max(max(x0, x1), x2)
        y_min, y_max = min(min(y0, y1), y2), max(max(y0, y1), y2)
        bx0 = min(max(_floor_pixel(x_min, bits, True), 0), width - 1)  # FILL_LEFT
        by0 = min(max(_floor_pixel(y_min, bits, True), 0), height - 1)  # FILL_BOTTOM
        bx1 = min(max(_ceil_pixel(x_max, bits, False), 0), width - 1)  # not FILL_RIGHT
        by1 = min(max(_ceil_pixel(y_max, bits, False), 0), height - 1)  # not FILL_TOP
        # the 2x2 packets start at bx0, bx0 + 2, ... <= bx1; a packet's second column (row)
        # is out at the viewport's edge
        x_end = min(bx0 + ((bx1 - bx0) // 2) * 2 + 2, width)
        y_end = min(by0 + ((by1 - by0) // 2) * 2 + 2, height)
        for sample in range(n_samples):
            ox, oy = offsets[sample, 0], offsets[sample, 1]
            for y in range(by0, y_end):
                py = (y << bits) + oy
                run = -1
                for x in range(bx0, x_end):
                    px = (x << bits) + ox
                    inside = True
                    for k in range(3):  # isInsideCCW
                        value = edges[k, 0] * px + edges[k, 1] * py + edges[k, 2]
                        if not (value >= 0 if edges[k, 3] else value > 0):
                            inside = False
                            break
                    if inside and run < 0:
                        run = x
                    elif not inside and run >= 0:
                        out.append((t, sample, y, run, x))
                        run = -1
                if run >= 0:
                    out.append((t, sample, y, run, x_end))
    result = np.empty((len(out), 5), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2], result[i, 3], result[i, 4] = out[i]
    return result


class DeqpMultisample:
    """dEQP's ``TriangleRasterizer`` at 2, 4, 8 or 16 samples per pixel (8 subpixel bits).

    Declares no convention: ``identify`` reads it from outside.

    Parameters
    ----------
    samples : {2, 4, 8, 16}

    Examples
    --------
    dEQP's 4x samples sit at (1/4 + k/2): under the edge x + y = 4 (not owned: it is the
    triangle's bottom-right side) pixel (3, 0) keeps only sample 0, at (3.25, 0.25).

    >>> cov = DeqpMultisample(4).rasterize(Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]]))
    >>> [cov.layer(s).counts(4, 1)[0].tolist() for s in range(4)]
    [[1, 1, 1, 1], [1, 1, 1, 0], [1, 1, 1, 0], [1, 1, 1, 0]]
    """

    convention = None
    interpolates = False  # coverage only, as dEQP's tests compare coverage

    def __init__(self, samples: int = 4) -> None:
        if samples not in SAMPLE_POINTS:
            raise ValueError(f"deqp_msaa: samples must be one of {sorted(SAMPLE_POINTS)}, not {samples!r}")
        self.samples = samples
        self.bits = SUBPIXEL_BITS
        self.offsets = sample_offsets(samples, self.bits)
        self.name = f"deqp_msaa{samples}"

    def snap(self, positions: NDArray[np.float64]) -> NDArray[np.int64]:
        """The vertices in 1/256 px as ``init`` computes them (:func:`to_subpixel`)."""
        return to_subpixel(positions, self.bits)

    def rasterize(self, scene: Scene) -> Coverage:
        limit = 2.0 ** (29 - self.bits)
        check_range(scene, limit, self.name, "its int64 edge functions overflow beyond that")
        drawn = np.all(np.isfinite(scene.positions), axis=(1, 2))
        fixed = self.snap(np.where(drawn[:, None, None], scene.positions, 0.0))
        runs = _multisample_kernel(frozen(fixed, np.int64), frozen(drawn, np.bool_), frozen(self.offsets, np.int64),
                                   self.bits, scene.width, scene.height)
        return Coverage(runs[:, 0], runs[:, 2], runs[:, 3], runs[:, 4], sample=runs[:, 1])
