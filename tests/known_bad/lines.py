"""Known-bad line drawers (issue 16): aliased lines with one classic bug each.

Each takes line scenes only and declares the rule it claims to follow. Most are built on
the exact oracle of that rule (:mod:`harness.oracle.lines`, through
:func:`harness.oracle.coverage.exact_coverage`): they draw the rule's own major-axis cells -- one
per column of an x-major segment, one per row of a y-major one -- and differ from it only
through their bug, which decides the minor coordinate in each cell (or the cells, or the
end points) another way. Test doubles: numpy per segment, not fast.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Unsupported
from harness.oracle.coverage import exact_coverage
from tests.textbook_lines import plot_lines

__all__ = [
    "RoundingDDA", "BothEndPixels", "YMajorAlongX", "OffByOneLast", "Float32DDA", "LeftmostFirst", "BackwardPrestep",
    "SwapsShallowOnly", "FullWidthOffset", "LINE_BADS",
]

DIAMOND = Convention()  # diamond-exit, last pixel omitted (D3D11, GL)
BRESENHAM = Convention(line="bresenham")  # seed 003: both end points drawn


def _cells(scene: LineScene, convention: Convention) -> tuple[NDArray, NDArray, NDArray]:
    """The oracle's pixels as (segment, major cell u, x_major of the segment), one per
    cell (every width-1 rule draws one pixel per major step)."""
    seg, x, y = exact_coverage(scene, convention).pixels()
    a, b = scene.segments()
    x_major = np.abs(b[:, 0] - a[:, 0]) >= np.abs(b[:, 1] - a[:, 1])
    major = x_major[seg]
    return seg, np.where(major, x, y), major


def _width_one(scene: LineScene) -> None:
    """Refuse lines the claimed width-1 rule does not define, as the references do."""
    if scene.line_width != 1.0:
        raise Unsupported(f"draws lines 1 px wide only, not {scene.line_width:g}")


def _from_cells(scene: LineScene, seg: NDArray, u: NDArray, major: NDArray, v: NDArray) -> Coverage:
    """Pixels from cells and (float or integer) minor coordinates, inside the viewport."""
    v = np.asarray(v, dtype=np.float64)
    x, y = np.where(major, u, v), np.where(major, v, u)
    with np.errstate(invalid="ignore"):
        inside = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)  # NaN: outside
    return Coverage.from_pixels(seg[inside], x[inside].astype(np.int64), y[inside].astype(np.int64))


def _line_at(scene: LineScene, seg: NDArray, uc: NDArray, major: NDArray, shift: NDArray | None = None) -> NDArray:
    """The minor coordinate of each segment's line at major coordinate ``uc`` (float64),
    its start point moved by ``shift`` along the major axis."""
    a, b = scene.segments()
    a, b = a[seg], b[seg]
    au, av = np.where(major, a[:, 0], a[:, 1]), np.where(major, a[:, 1], a[:, 0])
    bu, bv = np.where(major, b[:, 0], b[:, 1]), np.where(major, b[:, 1], b[:, 0])
    if shift is not None:
        au = au + shift
    with np.errstate(all="ignore"):
        return av + (uc - au) * (bv - av) / (bu - au)  # type: ignore[no-any-return]


class RoundingDDA:
    """A DDA that takes the line's height at each column centre and rounds it to the
    nearest integer -- ``putpixel(x, round(y))``, as if pixel centres lay on the integers --
    instead of the diamond rule's row holding it (``ceil(y) - 1``): every cell where the
    line crosses the lower half of a pixel lands one row too low. Claims diamond-exit."""

    name = "bad_rounding_dda"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        seg, u, major = _cells(scene, DIAMOND)
        return _from_cells(scene, seg, u, major, np.floor(_line_at(scene, seg, u + 0.5, major) + 0.5))


class BothEndPixels:
    """Draws the last pixel of every segment (the diamond-exit rule with ``last_pixel``)
    while claiming the rule without it: a polyline's shared vertex is drawn by both
    segments."""

    name = "bad_both_end_pixels"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        return exact_coverage(scene, Convention(line=LineRule("diamond-exit", last_pixel=True)))


class YMajorAlongX:
    """Steps every segment along x, one pixel per column (the row holding the line at the
    column centre), steep ones too: a y-major segment gets one pixel per column and gaps
    between its rows. x-major segments are drawn by the rule. Claims diamond-exit."""

    name = "bad_y_major_along_x"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        seg, x, y = exact_coverage(scene, DIAMOND).pixels()
        a, b = scene.segments()
        finite = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
        steep = finite & (np.abs(b[:, 1] - a[:, 1]) > np.abs(b[:, 0] - a[:, 0]))
        keep = ~steep[seg]  # x-major segments: the rule's pixels
        k = np.flatnonzero(steep)
        # a steep segment's columns: those whose centre lies on it, centres in [min x, max x)
        first = np.ceil(np.minimum(a[k, 0], b[k, 0]) - 0.5).astype(np.int64)
        last = np.ceil(np.maximum(a[k, 0], b[k, 0]) - 0.5).astype(np.int64)
        count = np.maximum(last - first, 0)
        s = np.repeat(k, count)
        column = np.repeat(first, count) + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        row = np.ceil(_line_at(scene, s, column + 0.5, np.ones(s.size, dtype=bool))) - 1
        with np.errstate(invalid="ignore"):
            inside = (column >= 0) & (column < scene.width) & (row >= 0) & (row < scene.height)
        return Coverage.from_pixels(np.concatenate([seg[keep], s[inside]]), np.concatenate([x[keep], column[inside]]),
                                    np.concatenate([y[keep], row[inside].astype(np.int64)]))


class OffByOneLast:
    """Seed 003's Bresenham looping ``for k in range(K)`` instead of ``K + 1``: the last
    pixel of every segment is missing, while it claims both end points drawn."""

    name = "bad_off_by_one_last"
    convention = BRESENHAM
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        return exact_coverage(scene, Convention(line=LineRule("bresenham", last_pixel=False)))


class Float32DDA:
    """A diamond-exit DDA in float32: the minor coordinate at the first cell centre, then
    ``y += slope`` per step in float32 -- the rounding of every step accumulates, and on a
    long line the row drifts off the exact one wherever the line passes near a pixel
    boundary. The cells are the rule's. Claims diamond-exit."""

    name = "bad_float32_dda"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        seg, u, major = _cells(scene, DIAMOND)
        a, b = scene.segments()
        pieces = []
        with np.errstate(all="ignore"):  # huge coordinates overflow float32: what this drawer does with them
            for k in np.unique(seg):
                pieces.append(self._walk(k, u[seg == k], bool(major[seg == k][0]), a, b))
        if not pieces:
            return Coverage.empty()
        s, w, m, v = (np.concatenate(p) for p in zip(*pieces))
        return _from_cells(scene, s, w, m, v)

    @staticmethod
    def _walk(k: int, cells: NDArray, along: bool, a: NDArray, b: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Segment k's cells walked from a towards b, its minor coordinate accumulated in float32."""
        cells = np.sort(cells)
        au, av = (a[k, 0], a[k, 1]) if along else (a[k, 1], a[k, 0])
        bu, bv = (b[k, 0], b[k, 1]) if along else (b[k, 1], b[k, 0])
        forward = bu >= au
        walk = cells if forward else cells[::-1]  # from a towards b
        slope = (bv - av) / (bu - au)
        steps = np.full(walk.size, np.float32(slope if forward else -slope), dtype=np.float32)
        steps[0] = np.float32(av + (walk[0] + 0.5 - au) * slope)
        minor = np.cumsum(steps, dtype=np.float32)  # y += slope in float32: one rounding per step
        return np.full(walk.size, k), walk, np.full(walk.size, along), np.ceil(minor.astype(np.float64)) - 1


class LeftmostFirst:
    """Draws every segment from its leftmost end point (the upper one of a vertical
    segment), as a scanline-minded DDA that sorts its end points does: right-to-left
    segments omit their start pixel instead of their end pixel, and a reversed scene draws
    the same pixels. Claims diamond-exit."""

    name = "bad_leftmost_first"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        a, b = scene.segments()
        swap = (b[:, 0] < a[:, 0]) | ((b[:, 0] == a[:, 0]) & (b[:, 1] < a[:, 1]))
        first, second = np.where(swap[:, None], b, a), np.where(swap[:, None], a, b)
        return exact_coverage(LineScene.from_segments(scene.width, scene.height, first, second, scene.line_width), DIAMOND)


class BackwardPrestep:
    """A DDA whose sub-pixel prestep has the wrong sign: the line's height at a cell centre
    uc is taken as ``av + slope * (uc - floor(au) + frac(au))`` instead of ``... - frac(au)``
    (u the major coordinate of the start point): the drawn line sits 2 * frac(au) behind
    the true one, so as the line moves forward within a pixel its rows (columns) move
    backwards, and jump ahead when au crosses an integer. The cells are the rule's.
    Claims diamond-exit."""

    name = "bad_backward_prestep"
    convention = DIAMOND
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        _width_one(scene)
        seg, u, major = _cells(scene, DIAMOND)
        a, b = scene.segments()
        au = np.where(major, a[seg, 0], a[seg, 1])
        v = np.ceil(_line_at(scene, seg, u + 0.5, major, shift=-2.0 * (au - np.floor(au)))) - 1
        # kept within a pixel of the segment's minor extent (its pixels stay within its reach)
        av, bv = np.where(major, a[seg, 1], a[seg, 0]), np.where(major, b[seg, 1], b[seg, 0])
        v = np.clip(v, np.floor(np.minimum(av, bv)) - 1, np.floor(np.maximum(av, bv)) + 1)
        return _from_cells(scene, seg, u, major, v)


class SwapsShallowOnly:
    """A textbook plotLine that normalises its direction inconsistently: it swaps the end
    points to walk towards +x in its shallow branch (|dy| <= |dx|) only, as Hearn & Baker's
    ``lineBres`` (written for 0 < slope < 1) extended to steep lines by a copy of the loop
    without the swap; steep segments are walked as given. Claims
    ``LineRule("bresenham", rounding="floor", direction="smaller-x")`` (ties step, both ends
    drawn), which it follows for every shallow segment and every steep one given from its
    smaller x: steep segments given from the larger x break their ties the other way."""

    name = "bad_swaps_shallow_only"
    convention = Convention(line=LineRule("bresenham", rounding="floor", ties="step", direction="smaller-x"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return plot_lines(scene, swap_steep=False, name=self.name)


class FullWidthOffset:
    """Vulkan's non-strict lines with the classic half-width slip: the parallelogram's sides
    are put ``line_width`` (not half of it) either side of the segment along the minor axis,
    so a width-1 line is drawn 2 px thick -- two pixels per column of an x-major segment.
    Ends and ties are the rule's. Claims ``LineRule("parallelogram")``."""

    name = "bad_parallelogram_full_width"
    convention = Convention(line="parallelogram")
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return exact_coverage(scene.with_line_width(2.0 * scene.line_width), self.convention)


LINE_BADS = (RoundingDDA(), BothEndPixels(), YMajorAlongX(), OffByOneLast(), Float32DDA(), LeftmostFirst(), BackwardPrestep(),
             SwapsShallowOnly(), FullWidthOffset())
