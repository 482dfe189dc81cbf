"""dEQP's reference rasterizer, ported: triangles at 2, 4, 8 or 16 samples per pixel
(:class:`DeqpMultisample`), aliased lines by its diamond-exit test (:class:`DeqpLines`) and
multisample lines as two triangles each (:class:`DeqpMultisampleLines`).

Ported from ``framework/referencerenderer/rrRasterizer.cpp`` of KhronosGroup/VK-GL-CTS
(commit c57d29f97dbd51e6ff57e9eb1a98808e66afa0d3, the file last changed in 60a706c4):
``TriangleRasterizer::init`` and ``rasterizeMultiSample<N>``, ``SingleSampleLineRasterizer``
with ``LineRasterUtil::doesLineSegmentExitDiamond``, and ``MultiSampleLineRasterizer``,
with the default ``RasterizationState`` (counter-clockwise winding, ``FILL_LEFT``,
``FILL_BOTTOM``) and 8 subpixel bits, as dEQP's GLES and Vulkan tests drive it. The
original, compiled from ``tests/peers/src/deqp``, decides every sample and pixel alike
(:mod:`tests.peers.test_deqp`; long run: triangles 80,000 random scenes at 2x to 16x,
83,930,017 covered samples; aliased lines 20,000 scenes, 935,023 pixels; multisample lines
20,000 scenes, 7,707,418 samples: 0 differing).

What the original does with triangles, and the port with it:

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

What identify and the quick suite find (:mod:`tests.peers.test_deqp`): the triangles'
2x, 4x, 8x and 16x conventions are recovered exactly (float32 input included) and pass (the float32 snapping
beyond 32,768 px, which no quick-suite case reaches, fails conformance where a sample
lies on an edge through such a vertex); the aliased lines part from
GL's rule at exact ties, dEQP's bugs: a segment through a diamond corner counts as leaving
it even when it ends inside (the end pixel drawn right to left through the right corner,
upwards through the bottom one, along a diamond edge), the end rule of the top corner takes
the mirrored quarter, and the bottom corner's misses horizontal lines; the multisample
lines are GL's rectangles only where float32 computes their corners exactly.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, Scene, Unsupported
from harness.geometry.exact import frozen
from rasterizers._common import check_range

__all__ = ["SAMPLE_POINTS", "SUBPIXEL_BITS", "DeqpMultisample", "DeqpLines", "DeqpMultisampleLines", "line_quads",
           "exits_diamond", "to_subpixel", "sample_offsets"]

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
    subpixels: NDArray[np.int64] = np.trunc(scaled).astype(np.int64)
    return subpixels


def sample_offsets(samples: int, bits: int = SUBPIXEL_BITS) -> NDArray[np.int64]:
    """``samplePos`` of ``rasterizeMultiSample``: each sample's offset in 1/2**bits px.

    Returns
    -------
    (samples, 2) int64
    """
    return to_subpixel(np.array(SAMPLE_POINTS[samples], dtype=np.float64), bits)


@numba.njit(cache=True, inline="always")
def _floor_pixel(coord, bits, fill_edge):
    """floorSubpixelToPixelCoord (arithmetic shifts round toward -inf, as in C on int64)."""
    if coord >= 0:
        return (coord - (1 if fill_edge else 0)) >> bits
    return (coord - ((1 << bits) - (0 if fill_edge else 1))) >> bits


@numba.njit(cache=True, inline="always")
def _ceil_pixel(coord, bits, fill_edge):
    """ceilSubpixelToPixelCoord."""
    if coord >= 0:
        return (coord + ((1 << bits) - (0 if fill_edge else 1))) >> bits
    return (coord + (1 if fill_edge else 0)) >> bits


@numba.njit(cache=True, inline="always")
def _init_edge_ccw(edges, k, x0, y0, x1, y1):
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
def _multisample_kernel(v, drawn, offsets, bits, width, height):
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

    convention: Convention | None = None
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


# -- aliased lines: SingleSampleLineRasterizer and LineRasterUtil::doesLineSegmentExitDiamond ---

LINE_LIMIT = 2.0**14
"""Beyond +-2**14 px the original's ``2 * dotProduct * dotProduct`` (a segment's direction
times a corner's normal, squared) may overflow int64: undefined, so the port refuses."""

_FLOOR_SQRT_MAX_INT64 = 3037000499
# the four corners of the diamond, in the original's order: offset (in half pixels),
# pointInclusive, lineBehavior (0 NONE, 1 HIT, 2 HIT_FIRST_QUARTER, 3 HIT_SECOND_QUARTER),
# startBehavior (0 NONE, 1 OUTSIDE, 2 POSITIVE_Y_45, 3 NEGATIVE_Y_45), endBehavior
# (0 NONE, 1 DIRECTION, 2 DIRECTION_AND_FIRST_QUARTER, 3 DIRECTION_AND_SECOND_QUARTER)
_CORNERS = frozen(np.array([[0, -1, 0, 3, 2, 3], [-1, 0, 0, 0, 0, 1], [0, 1, 0, 2, 3, 2], [1, 0, 1, 1, 1, 0]]), np.int64)
# the four bounds p0 -> p1 (in half pixels) and edgeInclusive
_BOUNDS = frozen(np.array([[0, -1, -1, 0, 0], [-1, 0, 0, 1, 0], [0, 1, 1, 0, 1], [1, 0, 0, -1, 1]]), np.int64)


@numba.njit(cache=True, inline="always")
def _bit_length(value):
    """64 - deClz64(value) for value >= 0."""
    n = 0
    while value > 0:
        value >>= 1
        n += 1
    return n


@numba.njit(cache=True, inline="always")
def _cross(ux, uy, vx, vy):
    return ux * vy - uy * vx


@numba.njit(cache=True, inline="always")
def _in_corner_angle(dx, dy, nx, ny):
    """lineInCornerAngleRange."""
    dot = dx * nx + dy * ny
    if dot < 0:
        return False
    return 2 * dot * dot > (dx * dx + dy * dy) * (nx * nx + ny * ny)


@numba.njit(cache=True, inline="always")
def _in_corner_outside_angle(dx, dy, nx, ny):
    """lineInCornerOutsideAngleRange."""
    dot = dx * nx + dy * ny
    if dot >= 0:
        return True
    return 2 * (-dot) * (-dot) < (dx * dx + dy * dy) * (nx * nx + ny * ny)


@numba.njit(cache=True, inline="always")
def _side(px, py, ax, ay, dx, dy):
    """getVertexSide: 1 left (cross < 0), 2 right (cross > 0), 0 on the line."""
    cross = _cross(dx, dy, px - ax, py - ay)
    return 1 if cross < 0 else (2 if cross > 0 else 0)


@numba.njit(cache=True)
def exits_diamond(ax, ay, bx, by, cx, cy, half, corners, bounds):
    """doesLineSegmentExitDiamond: the segment a -> b (subpixel units) and the diamond
    centred at c of half-diagonal ``half``."""
    dx, dy = bx - ax, by - ay
    # Reject distant diamonds early (with the original's overflow guards)
    cross = _cross(dx, dy, cx - ax, cy - ay)
    reject_squared = (2 * half) * (2 * half)
    cross_overflows = cross > _FLOOR_SQRT_MAX_INT64 or cross < -_FLOOR_SQRT_MAX_INT64
    cross_squared = 0 if cross_overflows else cross * cross
    length_squared = dx * dx + dy * dy
    limit_overflows = _bit_length(length_squared) + _bit_length(reject_squared) > 63
    limit = 0 if limit_overflows else length_squared * reject_squared
    if cross_overflows and not limit_overflows:
        return False
    if not cross_overflows and not limit_overflows and cross_squared > limit:
        return False
    # Corner cases at the corners
    for k in range(4):
        nx, ny = corners[k, 0] * half, corners[k, 1] * half
        px, py = cx + nx, cy + ny
        inclusive, line_case, start_case, end_case = corners[k, 2], corners[k, 3], corners[k, 4], corners[k, 5]
        # vertexOnLineSegment
        if _cross(dx, dy, px - ax, py - ay) != 0 or (dx == 0 and dy == 0):
            continue
        if not (dx * (px - ax) + dy * (py - ay) >= 0 and -dx * (px - bx) - dy * (py - by) >= 0):
            continue
        at_start = px == ax and py == ay
        at_end = px == bx and py == by
        if not at_start and not at_end:
            if line_case == 1:
                return True
            if line_case == 2 and dx * dy <= 0:
                return True
            if line_case == 3 and dx * dy > 0:
                return True
        if _in_corner_angle(dx, dy, nx, ny):
            start_inside = inclusive == 1 or not at_start
            end_outside = inclusive == 0 or not at_end
            if start_inside and end_outside:
                return True
        if at_end:
            if end_case != 0 and _in_corner_angle(dx, dy, nx, ny):
                return True
            if end_case == 2 and dx < 0 and dy > 0:
                return True
            if end_case == 3 and dx > 0 and dy > 0:
                return True
        if at_start:
            if start_case == 1 and _in_corner_outside_angle(dx, dy, nx, ny):
                return True
            if start_case == 2 and dx > 0 and dy > 0 and dy <= dx:
                return True
            if start_case == 3 and dx > 0 and dy <= 0 and -dy <= dx:
                return True
    # Does the line intersect a boundary at its left: it exits the diamond
    for k in range(4):
        p0x, p0y = cx + bounds[k, 0] * half, cy + bounds[k, 1] * half
        p1x, p1y = cx + bounds[k, 2] * half, cy + bounds[k, 3] * half
        ux, uy = p1x - p0x, p1y - p0y
        start_cross = _cross(ux, uy, ax - p0x, ay - p0y)
        end_cross = _cross(ux, uy, bx - p0x, by - p0y)
        start_inside = start_cross < 0 or (bounds[k, 4] == 1 and start_cross == 0)
        end_inside = end_cross < 0 or (bounds[k, 4] == 1 and end_cross == 0)
        if not start_inside or end_inside:
            continue
        side0 = _side(p0x, p0y, ax, ay, dx, dy)
        side1 = _side(p1x, p1y, ax, ay, dx, dy)
        if side0 != 0 and side1 != 0 and side0 != side1:
            return True
    return False


@numba.njit(cache=True)
def _line_kernel(a, b, drawn, x_major, widths, bits, width, height, corners, bounds):
    """(segment, x, y) of every fragment: SingleSampleLineRasterizer::init and rasterize,
    no stipple; ``a``, ``b`` (N, 2) int64 subpixel end points, ``widths`` (N,) the
    replication count ``lineWidthPixels``."""
    out = []
    one = 1 << bits
    half = 1 << (bits - 1)
    for n in range(a.shape[0]):
        if not drawn[n]:
            continue
        w = widths[n]
        shift = ((w - 1) << bits) // 2  # toSubpixelCoord(lineWidthPixels - 1) / 2, exact: even
        mx, my = (0, 1) if x_major[n] else (1, 0)  # minorDirection
        x0, y0 = a[n, 0] - mx * shift, a[n, 1] - my * shift
        x1, y1 = b[n, 0] - mx * shift, b[n, 1] - my * shift
        bx0 = _floor_pixel(min(x0, x1) - one, bits, True)
        bx1 = _ceil_pixel(max(x0, x1) + one, bits, True)
        by0 = _floor_pixel(min(y0, y1) - one, bits, True)
        by1 = _ceil_pixel(max(y0, y1) + one, bits, True)
        if x_major[n]:  # the major axis clamped to the viewport, the minor one padded by w
            bx0, bx1 = min(max(bx0, 0), width - 1), min(max(bx1, 0), width - 1)
            by0, by1 = min(max(by0, -w), height - 1), min(max(by1, -w), height - 1)
            lo, hi = 0, height
        else:
            by0, by1 = min(max(by0, 0), height - 1), min(max(by1, 0), height - 1)
            bx0, bx1 = min(max(bx0, -w), width - 1), min(max(bx1, -w), width - 1)
            lo, hi = 0, width
        for y in range(by0, by1 + 1):
            for x in range(bx0, bx1 + 1):
                if not exits_diamond(x0, y0, x1, y1, (x << bits) + half, (y << bits) + half, half, corners, bounds):
                    continue
                location = y if x_major[n] else x
                for r in range(max(0, lo - location), min(hi - location, w)):
                    out.append((n, x + mx * r, y + my * r))
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


class DeqpLines:
    """dEQP's ``SingleSampleLineRasterizer``: aliased lines by its diamond-exit test
    (``LineRasterUtil::doesLineSegmentExitDiamond``), 8 subpixel bits, wide lines
    replicated along the minor axis, no stipple.

    Ported from the same file and commit as :class:`DeqpMultisample`. End points are
    ``tcu::Vec4`` floats snapped by ``toSubpixelCoord`` (:func:`to_subpixel`); the major
    axis is ``|dx| >= |dy|`` in float32; a line of width w > 1 is drawn as
    ``floor(w + 0.5)`` copies, the segment first moved by ``-(copies - 1) / 2`` px along
    the minor axis. Each segment of a strip is drawn on its own, as dEQP draws
    ``GL_LINE_STRIP``. Declares no convention.

    Examples
    --------
    >>> from harness.contract.scenes import LineScene
    >>> DeqpLines().rasterize(LineScene.from_strips(4, 2, [[[0.5, 0.5], [3.5, 0.5]]])).counts(4, 2).tolist()
    [[1, 1, 1, 0], [0, 0, 0, 0]]
    """

    convention: Convention | None = None
    scene_kinds = ("lines",)
    interpolates = False
    name = "deqp_lines"

    def __init__(self) -> None:
        self.bits = SUBPIXEL_BITS

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene):
            raise Unsupported(f"{self.name} draws line scenes only, not {scene.kind}")
        a, b = scene.segments()
        ends = np.concatenate([a, b], axis=1)
        drawn = np.isfinite(ends).all(axis=1)
        beyond = drawn & (np.abs(np.where(drawn[:, None], ends, 0.0)) > LINE_LIMIT).any(axis=1)
        if beyond.any():
            raise ValueError(f"{self.name}: segment {int(np.flatnonzero(beyond)[0])} has a coordinate beyond "
                             f"+-2**14 px; the original's int64 products may overflow beyond that")
        a, b = (np.where(drawn[:, None], p, 0.0) for p in (a, b))
        delta = b.astype(np.float32) - a.astype(np.float32)  # (m_v1 - m_v0) in float32
        x_major = np.abs(delta[:, 0]) >= np.abs(delta[:, 1])
        w = np.float32(scene.line_width)
        copies = int(np.floor(w + np.float32(0.5))) if w > np.float32(1.0) else 1
        out = _line_kernel(frozen(self.snap(a), np.int64), frozen(self.snap(b), np.int64), frozen(drawn, np.bool_),
                           frozen(x_major, np.bool_), frozen(np.full(len(a), copies), np.int64), self.bits,
                           scene.width, scene.height, _CORNERS, _BOUNDS)
        return Coverage.from_pixels(out[:, 0], out[:, 1], out[:, 2])

    def snap(self, positions: NDArray[np.float64]) -> NDArray[np.int64]:
        """The end points in 1/256 px (:func:`to_subpixel`)."""
        return to_subpixel(positions, self.bits)


# -- multisample lines: MultiSampleLineRasterizer ---------------------------------------------------


def line_quads(a: NDArray[np.float64], b: NDArray[np.float64], line_width: float) -> NDArray[np.float32]:
    """``MultiSampleLineRasterizer::init`` in float32: the corners p0, p1, p2, p3 of the
    rectangle around each segment (p0, p3 at ``a`` and ``b`` plus the unit normal times
    ``width / 2``, p1, p2 minus it), the normal ``normalize((-dy, dx))`` as tcu computes it
    (``1.0f / sqrtf(x*x + y*y)`` times each part).

    Returns
    -------
    (N, 4, 2) float32
    """
    a32, b32 = a.astype(np.float32), b.astype(np.float32)
    line = b32 - a32
    raw = np.stack([-line[:, 1], line[:, 0]], axis=1)
    squared = (np.float32(0.0) + raw[:, 0] * raw[:, 0]) + raw[:, 1] * raw[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        normal = (np.float32(1.0) / np.sqrt(squared))[:, None] * raw
    offset = np.float32(line_width) / np.float32(2.0)
    step = normal * offset
    out = np.stack([a32 + step, a32 - step, b32 - step, b32 + step], axis=1)
    assert out.dtype == np.float32
    return out


class DeqpMultisampleLines:
    """dEQP's ``MultiSampleLineRasterizer`` at 2, 4, 8 or 16 samples: each segment a
    rectangle of the line's width, its corners computed in float32 (:func:`line_quads`),
    drawn as the triangles (p0, p3, p2) and (p2, p1, p0) by :class:`DeqpMultisample`'s
    rasterizer (default state: the shared diagonal's samples go to one of them).

    Ported from the same file and commit as :class:`DeqpMultisample`. A zero-length
    segment (whose normal the original divides by zero for) draws nothing. Declares no
    convention.
    """

    convention: Convention | None = None
    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, samples: int = 4) -> None:
        self.triangles = DeqpMultisample(samples)
        self.samples = samples
        self.name = f"deqp_msaa{samples}_lines"

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene):
            raise Unsupported(f"{self.name} draws line scenes only, not {scene.kind}")
        a, b = scene.segments()
        ends = np.concatenate([a, b], axis=1)
        drawn = np.isfinite(ends).all(axis=1) & np.any(a.astype(np.float32) != b.astype(np.float32), axis=1)
        limit = 2.0 ** (29 - SUBPIXEL_BITS) - scene.line_width
        beyond = drawn & (np.abs(np.where(drawn[:, None], ends, 0.0)) > limit).any(axis=1)
        if beyond.any():
            raise ValueError(f"{self.name}: segment {int(np.flatnonzero(beyond)[0])} has a coordinate beyond "
                             f"+-{limit:g} px; the original's int64 edge functions overflow beyond that")
        a, b = np.where(drawn[:, None], a, 0.0), np.where(drawn[:, None], b, 1.0)  # a stand-in where not drawn
        p = line_quads(a, b, scene.line_width).astype(np.float64)  # float32 values, exactly
        triangles = np.stack([p[:, [0, 3, 2]], p[:, [2, 1, 0]]], axis=1).reshape(-1, 3, 2)
        fixed = to_subpixel(triangles, SUBPIXEL_BITS)
        runs = _multisample_kernel(frozen(fixed, np.int64), frozen(np.repeat(drawn, 2), np.bool_),
                                   frozen(self.triangles.offsets, np.int64), SUBPIXEL_BITS, scene.width, scene.height)
        lengths = runs[:, 4] - runs[:, 3]
        which = np.repeat(np.arange(len(runs)), lengths)
        x = runs[which, 3] + (np.arange(which.size) - np.repeat(np.cumsum(lengths) - lengths, lengths))
        return Coverage.from_pixels(runs[which, 0] // 2, x, runs[which, 2], sample=runs[which, 1])
