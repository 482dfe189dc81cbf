"""A multisample line drawer, as GL's 14.5.4 "Line Multisample Rasterization" and dEQP's
``MultiSampleLineRasterizer`` draw lines: each sample of the pattern inside the w-wide
rectangle around the segment -- written with its own arithmetic (int64 over a pixel box in
a compiled kernel, Python integers where a float filter cannot settle a side), not the
oracle's kernels -- and a known-bad one.

:class:`MultisampleRectangleLines` snaps the end points to 1/256 px; the pattern's offsets
and the width must be multiples of 1/256 too (the standard 2, 4, 8 and 16 sample patterns
are), so that with d = b - a, for a sample p: the caps ``dot(d, p - a) > 0`` and
``dot(-d, p - b) > 0`` and the sides ``4 cross(d, p - a)**2 < W**2 |d|**2`` are integer
comparisons. A sample exactly on the boundary is decided by the tie rule's symbolic
perturbation (:data:`harness.contract.conventions.TIE_PERTURBATION`): the sign of the boundary
function's gradient along it (x-first: its x part, else its y part).

:class:`ClosedRectangles` (known bad) takes every boundary sample in, whatever the tie
rule says, claiming the same convention.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import TIE_PERTURBATION, Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, Unsupported
from harness.geometry.exact import frozen

__all__ = ["MultisampleRectangleLines", "ClosedRectangles", "LIMIT"]

ONE = 256
# |x|, |y| <= 2**21 px (2**29 units) and samples within the viewport: every dot and cross
# product below 2**62
LIMIT = 2.0**21


@numba.njit(cache=True)
def _owned(gx, gy, tx, ty, y_first):
    """A boundary sample is inside when the boundary function's gradient (gx, gy) points
    along the tie rule's perturbation: x-first its x part decides, else its y part."""
    if y_first:
        return gy * ty > 0 if gy != 0 else gx * tx > 0
    return gx * tx > 0 if gx != 0 else gy * ty > 0


@numba.njit(cache=True)
def _sign(v):
    return (v > 0) - (v < 0)


@numba.njit(cache=True)
def _msaa_kernel(a, b, keep, big_w, offsets, tx, ty, y_first, closed, width, height):
    """Every segment's samples that pass the caps and may pass the sides, as rows (segment,
    sample, x, y, status) in int64: status 1 inside, 2 a sample whose side test the float
    filter cannot settle (ties among them), with its cross product in the second array."""
    rows = []
    crosses = []
    for k in range(a.shape[0]):
        if not keep[k]:
            continue
        ax, ay, bx, by = a[k, 0], a[k, 1], b[k, 0], b[k, 1]
        dx = bx - ax
        dy = by - ay
        if dx == 0 and dy == 0:
            continue
        reach = big_w // 2 + 2 * ONE
        x_lo = max(0, (min(ax, bx) - reach) // ONE)
        x_hi = min(width - 1, (max(ax, bx) + reach) // ONE)
        y_lo = max(0, (min(ay, by) - reach) // ONE)
        y_hi = min(height - 1, (max(ay, by) + reach) // ONE)
        bound = float(big_w) * float(big_w) * (float(dx) * float(dx) + float(dy) * float(dy))
        own_a = _owned(_sign(dx), _sign(dy), tx, ty, y_first)
        own_b = _owned(-_sign(dx), -_sign(dy), tx, ty, y_first)
        for s in range(offsets.shape[0]):
            for j in range(y_lo, y_hi + 1):
                py = j * ONE + offsets[s, 1]
                for i in range(x_lo, x_hi + 1):
                    px = i * ONE + offsets[s, 0]
                    cap_a = dx * (px - ax) + dy * (py - ay)
                    cap_b = -dx * (px - bx) - dy * (py - by)
                    if closed:
                        if cap_a < 0 or cap_b < 0:
                            continue
                    elif not ((cap_a > 0 or (cap_a == 0 and own_a)) and (cap_b > 0 or (cap_b == 0 and own_b))):
                        continue
                    cross = dx * (py - ay) - dy * (px - ax)
                    cf = float(cross)
                    side = bound - 4.0 * cf * cf
                    if abs(side) <= 2.0**-40 * (bound + 4.0 * cf * cf):
                        rows.append((k, s, i, j, 2))
                        crosses.append(cross)
                    elif side > 0:
                        rows.append((k, s, i, j, 1))
    out = np.empty((len(rows), 5), dtype=np.int64)
    for r in range(len(rows)):
        for c in range(5):
            out[r, c] = rows[r][c]
    cr = np.empty(len(crosses), dtype=np.int64)
    for r in range(len(crosses)):
        cr[r] = crosses[r]
    return out, cr


class MultisampleRectangleLines:
    """Rectangles sampled at each sample of a pattern, ties by the tie rule, 8 bits.

    >>> scene = LineScene.from_segments(6, 3, [[0.5, 1.0]], [[4.5, 1.0]])
    >>> cov = MultisampleRectangleLines().rasterize(scene)
    >>> [(int(s), int(y), int(x0), int(x1)) for s, y, x0, x1 in zip(cov.sample, cov.y, cov.x0, cov.x1)]
    [(0, 1, 1, 5), (1, 1, 0, 4), (2, 0, 1, 5), (3, 0, 0, 4)]
    """

    name = "msaa_rectangle_lines"
    scene_kinds = ("lines",)
    interpolates = False
    closed = False

    def __init__(self, samples: int = 4, tie: str = "top-left") -> None:
        self.convention = Convention(samples=samples, tie=tie, subpixel_bits=8, line=LineRule("rectangle"))  # type: ignore[arg-type]
        self.offsets = np.array([(int(x * ONE), int(y * ONE)) for x, y in self.convention.samples], dtype=np.int64)
        if any(x / ONE != ox or y / ONE != oy for (x, y), (ox, oy) in zip(self.offsets.tolist(), self.convention.samples)):
            raise ValueError("the pattern's offsets must be multiples of 1/256")

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene):
            raise Unsupported(f"{self.name} draws line scenes only, not {scene.kind}")
        big_w = scene.line_width * ONE
        if big_w != math.floor(big_w) or big_w > 2**16:
            raise Unsupported(f"{self.name} draws widths up to 256 px, multiples of 1/256 only, not {scene.line_width!r}")
        a, b = scene.segments()
        ends = np.concatenate([a, b], axis=1)
        finite = np.isfinite(ends).all(axis=1)
        beyond = finite & (np.abs(np.where(finite[:, None], ends, 0.0)) > LIMIT).any(axis=1)
        if beyond.any():
            raise ValueError(f"{self.name}: segment {int(np.flatnonzero(beyond)[0])} has a coordinate beyond +-2**21 px")
        fa = frozen(self.convention.snap(np.where(finite[:, None], a, 0.0)) * ONE, np.int64)
        fb = frozen(self.convention.snap(np.where(finite[:, None], b, 0.0)) * ONE, np.int64)
        tx, ty, y_first = TIE_PERTURBATION[self.convention.tie]
        rows, crosses = _msaa_kernel(fa, fb, frozen(finite, np.bool_), int(big_w), self.offsets, tx, ty, y_first, self.closed,
                                     scene.width, scene.height)
        inside = rows[:, 4] == 1
        doubtful = np.flatnonzero(rows[:, 4] == 2)
        for r, cross in zip(doubtful, crosses.tolist()):
            # the side test in Python integers: sign(W**2 |d|**2 - 4 cross**2), a tie by the rule
            k = int(rows[r, 0])
            dx, dy = int(fb[k, 0] - fa[k, 0]), int(fb[k, 1] - fa[k, 1])
            side = int(big_w) ** 2 * (dx * dx + dy * dy) - 4 * cross * cross
            if side == 0 and not self.closed:
                # on a side: cross = +h has grad(h - cross) = (dy, -dx), cross = -h grad(cross + h) = (-dy, dx)
                grad = (dy, -dx) if cross > 0 else (-dy, dx)
                inside[r] = bool(_owned(int(np.sign(grad[0])), int(np.sign(grad[1])), tx, ty, y_first))
            else:
                inside[r] = side >= 0 if self.closed else side > 0
        seg, sample, x, y = (rows[inside, c] for c in range(4))
        layers = []
        for s in range(self.offsets.shape[0]):
            mine = sample == s
            c = Coverage.from_pixels(seg[mine], x[mine], y[mine])
            layers.append(Coverage(c.primitive, c.y, c.x0, c.x1, sample=np.full(len(c), s, dtype=np.int64)))
        joined = Coverage.concat(layers)
        return joined.take(np.argsort(joined.primitive, kind="stable"))


class ClosedRectangles(MultisampleRectangleLines):
    """Known bad: every sample on the rectangle's boundary taken in (closed rectangles),
    claiming the tie rule."""

    name = "bad_msaa_closed_rectangles"
    closed = True
