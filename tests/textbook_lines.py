"""Textbook Bresenham line drawers, written as a new user writes them from a textbook
(issue 28, point 7): each swaps its end points before it walks, so the direction of travel
is normalised, and each declares what it does with
:class:`~harness.contract.conventions.LineRule`'s ``direction``.

- :class:`TextbookPlotLine`: Hearn & Baker's ``lineBres`` made general, the usual
  "if x0 > x1: swap" ``plotLine``: end points to the pixels holding them (``floor``), then
  always walk towards +x -- along x for |dy| <= |dx| (decision ``p = 2dy - dx``, the minor
  step when ``p >= 0``: ties step), along y up or down the screen otherwise. Both end pixels
  drawn. ``LineRule("bresenham", rounding="floor", ties="step", direction="smaller-x")``.
- :class:`WikipediaPlotLine`: Wikipedia's ``plotLine`` with ``plotLineLow`` (|dy| < |dx|,
  swapped so that x0 <= x1) and ``plotLineHigh`` (swapped so that y0 <= y1); its test
  ``D > 0`` keeps the minor coordinate on a tie. End points to the pixel whose centre is
  nearest (``floor(x)``, and the even one of x - 1, x when x is an integer). A diagonal (|dy| = |dx|) goes to
  ``plotLineHigh`` where ours counts it x-major: it steps both coordinates every step, so
  the two draw it alike. ``LineRule("bresenham", ties="stay", direction="smaller-major")``.

A known-bad drawer that normalises inconsistently is in :mod:`tests.known_bad.lines`
(:class:`~tests.known_bad.lines.SwapsShallowOnly`, built on this module's kernel).

Per-pixel work in one compiled kernel; the end point rounding in numpy.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Unsupported
from harness.geometry.exact import frozen

__all__ = ["TextbookPlotLine", "WikipediaPlotLine", "plot_lines", "LIMIT"]

# end points within +-2**30 px: every decision variable fits int64
LIMIT = 2.0**30


@numba.njit(cache=True)
def _plot_line_kernel(p, finite, swap_steep, width, height):
    """Hearn & Baker's plotLine for every segment (p: (N, 4) int64 x0, y0, x1, y1): swap so
    that x0 <= x1 (the steep branch too unless ``swap_steep`` is False), then walk with the
    decision variable, ties stepping. (M, 3) int64 rows (segment, x, y) in the viewport."""
    out = []
    for s in range(p.shape[0]):
        if not finite[s]:
            continue
        x0, y0, x1, y1 = p[s, 0], p[s, 1], p[s, 2], p[s, 3]
        steep = abs(y1 - y0) > abs(x1 - x0)
        if x0 > x1 and (swap_steep or not steep):
            x0, y0, x1, y1 = x1, y1, x0, y0
        dx = abs(x1 - x0)
        dy = abs(y1 - y0)
        sx = 1 if x1 >= x0 else -1
        sy = 1 if y1 >= y0 else -1
        if not steep:
            pk = 2 * dy - dx
            y = y0
            for x in range(x0, x1 + 1):
                if 0 <= x < width and 0 <= y < height:
                    out.append((s, x, y))
                if pk >= 0:
                    y += sy
                    pk -= 2 * dx
                pk += 2 * dy
        else:
            pk = 2 * dx - dy
            x = x0
            y = y0
            for _ in range(dy + 1):
                if 0 <= x < width and 0 <= y < height:
                    out.append((s, x, y))
                if pk >= 0:
                    x += sx
                    pk -= 2 * dy
                pk += 2 * dx
                y += sy
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


@numba.njit(cache=True)
def _wikipedia_kernel(p, finite, width, height):
    """Wikipedia's plotLine (plotLineLow / plotLineHigh, ``D > 0``) for every segment."""
    out = []
    for s in range(p.shape[0]):
        if not finite[s]:
            continue
        x0, y0, x1, y1 = p[s, 0], p[s, 1], p[s, 2], p[s, 3]
        if abs(y1 - y0) < abs(x1 - x0):  # plotLineLow
            if x0 > x1:
                x0, y0, x1, y1 = x1, y1, x0, y0
            dx = x1 - x0
            dy = y1 - y0
            yi = 1
            if dy < 0:
                yi = -1
                dy = -dy
            d = 2 * dy - dx
            y = y0
            for x in range(x0, x1 + 1):
                if 0 <= x < width and 0 <= y < height:
                    out.append((s, x, y))
                if d > 0:
                    y += yi
                    d += 2 * (dy - dx)
                else:
                    d += 2 * dy
        else:  # plotLineHigh
            if y0 > y1:
                x0, y0, x1, y1 = x1, y1, x0, y0
            dx = x1 - x0
            dy = y1 - y0
            xi = 1
            if dx < 0:
                xi = -1
                dx = -dx
            d = 2 * dx - dy
            x = x0
            for y in range(y0, y1 + 1):
                if 0 <= x < width and 0 <= y < height:
                    out.append((s, x, y))
                if d > 0:
                    x += xi
                    d += 2 * (dx - dy)
                else:
                    d += 2 * dx
    result = np.empty((len(out), 3), dtype=np.int64)
    for i in range(len(out)):
        result[i, 0], result[i, 1], result[i, 2] = out[i]
    return result


def _end_pixels(scene: LineScene, rounding: str, name: str) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """(N, 4) int64 end point pixels x0, y0, x1, y1 (``floor``, or the nearest centre with
    halves to even) and which segments are finite; a width other than 1 is Unsupported,
    a coordinate beyond +-2**30 px a ValueError naming the segment."""
    if not isinstance(scene, LineScene):
        raise Unsupported(f"{name} draws line scenes only, not {scene.kind}")
    if scene.line_width != 1.0:
        raise Unsupported(f"{name} draws lines 1 px wide only, not {scene.line_width:g}")
    a, b = scene.segments()
    ends = np.concatenate([a, b], axis=1)
    finite = np.isfinite(ends).all(axis=1)
    ends = np.where(finite[:, None], ends, 0.0)
    if (np.abs(ends) > LIMIT).any():
        k = int(np.flatnonzero((np.abs(ends) > LIMIT).any(axis=1))[0])
        raise ValueError(f"{name}: segment {k} has a coordinate beyond +-2**30 px")
    pixels = np.floor(ends)
    if rounding == "nearest-even":  # the centre nearest: floor, but an integer v lies between two: the even one
        pixels = np.where((ends == pixels) & (np.fmod(pixels, 2.0) != 0.0), pixels - 1.0, pixels)
    return frozen(pixels, np.int64), frozen(finite, np.bool_)


def plot_lines(scene: LineScene, swap_steep: bool = True, name: str = "plot_line") -> Coverage:
    """:class:`TextbookPlotLine`'s drawing of ``scene`` (``swap_steep=False``: the
    known-bad that swaps shallow segments only)."""
    p, finite = _end_pixels(scene, "floor", name)
    out = _plot_line_kernel(p, finite, swap_steep, scene.width, scene.height)
    return Coverage.from_pixels(out[:, 0], out[:, 1], out[:, 2])


class TextbookPlotLine:
    """The textbook plotLine: floor end points, walk towards +x, ties step, both ends."""

    name = "textbook_plot_line"
    convention = Convention(line=LineRule("bresenham", rounding="floor", ties="step", direction="smaller-x"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return plot_lines(scene, True, self.name)


class WikipediaPlotLine:
    """Wikipedia's plotLine: nearest centres, walk along the major axis upwards, ties stay."""

    name = "wikipedia_plot_line"
    convention = Convention(line=LineRule("bresenham", rounding="nearest-even", ties="stay", direction="smaller-major"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        p, finite = _end_pixels(scene, "nearest-even", self.name)
        out = _wikipedia_kernel(p, finite, scene.width, scene.height)
        return Coverage.from_pixels(out[:, 0], out[:, 1], out[:, 2])
