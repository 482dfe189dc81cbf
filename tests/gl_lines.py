"""A line drawer under GL's aliased-line rule, written from the OpenGL 4.6 specification
(section 14.5.1, "Basic Line Segment Rasterization") with its own arithmetic -- not the
oracle's walk -- and a known-bad one that perturbs the end points the wrong way.

GL: "a line segment starting at p_a and ending at p_b produces those fragments f for which
the segment intersects R_f, except if p_b is contained in R_f", with the open diamond
``R_f = {(x, y) | |x - x_f| + |y - y_f| < 1/2}`` and both end points first perturbed to
``p - (eps, eps**2)``, eps so small that any smaller one gives the same fragments.
Window y is taken as rastercheck's y (row y = window row y), as the GL adapters do.

:class:`GLDiamondLines` snaps the end points to 1/256 px (24.8 fixed point) and decides
each candidate pixel (three per major-axis cell around the line's height at the cell
centre) by the separating axis theorem in int64: the moved segment S' and the open
diamond R meet unless some axis n -- a diamond normal (+-1, +-1) or the segment's normal
(-dy, dx) -- has ``max over S' of n.x <= min over R of n.x``. Each side is a polynomial
``q0 + q1*eps + q2*eps**2`` in the perturbation, compared as the tuple (q0, q1, q2)
lexicographically (its sign as eps -> 0+): no epsilon value, no float decision. The end
point test is ``s.(b' - c) < 1/2`` for the four diagonals s, likewise.

With ``wide=True`` it draws integer widths w as GL's wide lines (OpenGL 4.6, 14.5.2): the
end points moved by -(w - 1)/2 along the minor axis (in fixed point: exact), each
fragment replicated w times along it, the width-1 one first.

:class:`PerturbedUpwards` (known bad) moves the end points by +(eps, eps**2) instead: the
diamonds then own their left edges and left corners, not their right ones -- it agrees
with GL everywhere but at exact ties (lines along diamond edges, through corners, end
points on a diamond's boundary), and claims GL's rule.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, Unsupported
from harness.geometry.exact import frozen

__all__ = ["GLDiamondLines", "PerturbedUpwards", "WideNotMoved", "LIMIT"]

ONE = 256
HALF = 128
# |x|, |y| <= 2**21 px: |a - c| < 2**30 units and |d| <= 2**30, so n.(a - c) < 2**61.
LIMIT = 2.0**21


@numba.njit(cache=True, inline="always")
def _below(q0, q1, q2):
    """q0 + q1*eps + q2*eps**2 < 0 as eps -> 0+."""
    if q0 != 0:
        return q0 < 0
    if q1 != 0:
        return q1 < 0
    return q2 < 0


@numba.njit(cache=True)
def _meets(ax, ay, bx, by, cx, cy, sign):
    """Whether the segment a-b moved by -sign*(eps, eps**2) meets the open diamond of
    centre c (fixed point), by the separating axis theorem."""
    for sx in (-1, 1):
        for sy in (-1, 1):
            # separated along s when max over S' of s.(x - c) <= -1/2 (the diamond's least)
            top = max(sx * (ax - cx) + sy * (ay - cy), sx * (bx - cx) + sy * (by - cy))
            if not _below(-HALF - top, sign * sx, sign * sy):  # -1/2 - (top - sign*(sx eps + sy eps^2)) >= 0
                return False
    dx = bx - ax
    dy = by - ay
    if dx == 0 and dy == 0:
        return True
    nx = -dy
    ny = dx
    reach = HALF * max(abs(nx), abs(ny))  # the diamond's extent along n
    p0 = nx * (ax - cx) + ny * (ay - cy)
    p1 = -sign * nx
    p2 = -sign * ny
    # |n.(a' - c)| < reach, both ways
    return _below(p0 - reach, p1, p2) and _below(-p0 - reach, -p1, -p2)


@numba.njit(cache=True)
def _holds(px, py, cx, cy, sign):
    """Whether p moved by -sign*(eps, eps**2) lies in the open diamond of centre c."""
    for sx in (-1, 1):
        for sy in (-1, 1):
            if not _below(sx * (px - cx) + sy * (py - cy) - HALF, -sign * sx, -sign * sy):
                return False
    return True


@numba.njit(cache=True)
def _gl_kernel(a, b, keep, sign, last_pixel, width, height, line_width, shift):
    """(M, 3) int64 rows (segment, x, y) of every segment's fragments (fixed point ends),
    wide lines (integer ``line_width`` w) by GL's replication: the segment moved by
    ``-shift`` units along its minor axis, each fragment then w along it."""
    out = []
    for s in range(a.shape[0]):
        if not keep[s]:
            continue
        ax, ay, bx, by = a[s, 0], a[s, 1], b[s, 0], b[s, 1]
        x_major = abs(bx - ax) >= abs(by - ay)
        if x_major:
            ay -= shift
            by -= shift
        else:
            ax -= shift
            bx -= shift
        au, av, bu, bv = (ax, ay, bx, by) if x_major else (ay, ax, by, bx)
        extent, across = (width, height) if x_major else (height, width)
        lo = max(min(au, bu) // ONE - 1, 0)
        hi = min(max(au, bu) // ONE + 1, extent - 1)
        for c in range(lo, hi + 1):
            uc = c * ONE + HALF
            if bu == au:
                v = float(av)
            else:
                v = av + (uc - au) * ((bv - av) / (bu - au))
            m = int(math.floor(v / ONE))
            for k in range(m - 1, m + 2):
                if k < 1 - line_width or k >= across:
                    continue
                x, y = (c, k) if x_major else (k, c)
                cx, cy = x * ONE + HALF, y * ONE + HALF
                if _meets(ax, ay, bx, by, cx, cy, sign) and (last_pixel or not _holds(bx, by, cx, cy, sign)):
                    for r in range(line_width):  # the width-1 fragment first, then along the minor axis
                        u, v = (x, y + r) if x_major else (x + r, y)
                        if 0 <= u < width and 0 <= v < height:
                            out.append((s, u, v))
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


class GLDiamondLines:
    """GL's aliased lines (diamond exit, end points perturbed by -(eps, eps**2)), 8 bits.

    >>> scene = LineScene.from_strips(6, 4, [[[0.5, 0.0], [3.5, 3.0]]])
    >>> GLDiamondLines().rasterize(scene).counts(6, 4)[:3, :4]
    array([[1, 0, 0, 0],
           [0, 1, 0, 0],
           [0, 0, 1, 0]], dtype=int32)
    """

    name = "gl_diamond_lines"
    scene_kinds = ("lines",)
    interpolates = False
    sign = 1
    shift_error = 0  # whole pixels the known-bad wide drawer adds to GL's move

    def __init__(self, last_pixel: bool = False, wide: bool = False) -> None:
        self.last_pixel = bool(last_pixel)
        self.wide = bool(wide)
        self.convention = Convention(subpixel_bits=8, line=LineRule("diamond-exit-gl", last_pixel=self.last_pixel,
                                                                    wide="replicate" if wide else "none"))
        if self.last_pixel:
            self.name += "_last_pixel"
        if self.wide:
            self.name += "_wide"

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene):
            raise Unsupported(f"{self.name} draws line scenes only, not {scene.kind}")
        w = scene.line_width
        if w != 1.0 and not (self.wide and w == math.floor(w) and 1.0 <= w <= 64.0):
            raise Unsupported(f"{self.name} draws lines {'of integer width' if self.wide else '1 px wide'} only, not {w:g}")
        a, b = scene.segments()
        ends = np.concatenate([a, b], axis=1)
        finite = np.isfinite(ends).all(axis=1)
        beyond = finite & (np.abs(np.where(finite[:, None], ends, 0.0)) > LIMIT).any(axis=1)
        if beyond.any():
            raise ValueError(f"{self.name}: segment {int(np.flatnonzero(beyond)[0])} has a coordinate beyond +-2**21 px")
        fixed = [frozen(self.convention.snap(np.where(finite[:, None], p, 0.0)) * ONE, np.int64) for p in (a, b)]
        w = int(w)
        out = _gl_kernel(fixed[0], fixed[1], frozen(finite, np.bool_), self.sign, self.last_pixel, scene.width, scene.height,
                         w, (w - 1) * HALF + self.shift_error * ONE)
        return Coverage.from_pixels(out[:, 0], out[:, 1], out[:, 2])


class PerturbedUpwards(GLDiamondLines):
    """Known bad: GL's rule with the end points moved by +(eps, eps**2), claiming GL's."""

    name = "bad_gl_perturbed_upwards"
    sign = -1


class WideNotMoved(GLDiamondLines):
    """Known bad: GL's wide lines replicated from the segment not moved by the whole
    pixels of -(w - 1)/2 (one pixel for w = 3 or 4; none for w = 2), so the line is drawn
    off centre, claiming GL's replication."""

    name = "bad_gl_wide_not_moved"

    def __init__(self) -> None:
        super().__init__(wide=True)
        self.name = "bad_gl_wide_not_moved"

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene) or scene.line_width == 1.0:
            return super().rasterize(scene)
        w = int(scene.line_width)
        self.shift_error = -((w - 1) // 2)  # cancel GL's move (whole pixels of it)
        try:
            return super().rasterize(scene)
        finally:
            self.shift_error = 0
