"""Known-bad drawers of the line rules read from libraries' sources (issue 33): each claims
skia's hairlines or Qt's cosmetic lines (:mod:`harness.oracle.hairlines`), or llvmpipe's
rectangular lines (:mod:`harness.oracle.llvmpipe_lines`), and differs from the source in one
plausible way. Test doubles: Python integers per segment, not fast."""

from __future__ import annotations

import math

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Unsupported

__all__ = ["SkiaCentredStart", "QtFlatCaps", "LlvmpipeUnshiftedSnap", "HAIRLINE_BADS"]


def _cdiv(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def _walk(scene: LineScene, qt: bool, centred_start: bool = False, caps: bool = True) -> Coverage:
    """The two rules' DDA, written again with the bug's switch (module docstring)."""
    if scene.line_width != 1.0:
        raise Unsupported(f"draws lines 1 px wide only, not {scene.line_width:g}")
    a, b = scene.segments()
    seg: list[int] = []
    xs: list[int] = []
    ys: list[int] = []
    for k in range(a.shape[0]):
        if not (np.isfinite(a[k]).all() and np.isfinite(b[k]).all()):
            continue
        if qt and (a[k] == b[k]).all():
            seg.append(k)
            xs.append(math.floor(a[k, 0]))
            ys.append(math.floor(a[k, 1]))
            continue
        x0, y0, x1, y1 = (math.trunc(float(c) * 64) for c in (*a[k], *b[k]))
        x_major = abs(x1 - x0) >= abs(y1 - y0) if qt else abs(x1 - x0) > abs(y1 - y0)
        if not x_major:
            x0, y0, x1, y1 = y0, x0, y1, x1
        if x0 == x1:
            continue
        if x0 > x1:
            x0, y0, x1, y1 = x1, y1, x0, y0
        slope = _cdiv((y1 - y0) << 16, x1 - x0)
        if qt:
            v = y0 << 10
            if caps:
                x0, x1, v = x0 - 32, x1 + 32, v - (slope >> 1)
            first, last = (x0 + 32) >> 6, (x1 + 32) >> 6
            start = v + ((((first << 6) + (32 if slope > 0 else 0) - x0) * slope) >> 6)
        else:
            first, last = (x0 + 32) >> 6, (x1 + 32) >> 6
            # the bug: the DDA starts at the first drawn pixel's centre (skia: at the first
            # centre at or past x0, one column earlier when x0 lies exactly on a centre)
            offset = (first << 6) + 32 - x0 if centred_start else (32 - x0) & 63
            start = (y0 << 10) + ((slope * offset) >> 6)
        for i in range(first, last):
            j = (start + (i - first) * slope) >> 16
            seg.append(k)
            xs.append(i if x_major else j)
            ys.append(j if x_major else i)
    s, x, y = (np.array(v, dtype=np.int64) for v in (seg, xs, ys))
    inside = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
    return Coverage.from_pixels(s[inside], x[inside], y[inside])


class SkiaCentredStart:
    """skia's hairlines with the DDA started at the first drawn pixel's centre -- the
    "obvious fix" of ``(32 - x0) & 63`` -- while claiming skia's rule: a segment whose end
    lies exactly on a pixel centre is drawn one slope step off skia's."""

    name = "bad_skia_centred_start"
    convention = Convention(line="skia-hairline")
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return _walk(scene, qt=False, centred_start=True)


class QtFlatCaps:
    """Qt's cosmetic lines drawn without the square caps (a ``Qt.FlatCap`` pen's) while
    claiming the default pen's: the pixels whose centres lie between the ends instead of
    both end pixels, so an end pixel is left out wherever its end lies on the far side of
    the pixel's centre."""

    name = "bad_qt_flat_caps"
    convention = Convention(line="qt-cosmetic")
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return _walk(scene, qt=True, caps=False)




class LlvmpipeUnshiftedSnap:
    """llvmpipe's rectangular lines with the end points snapped as its triangles' vertices
    are (to 1/256 px, nearest-even, unshifted) while claiming llvmpipe's line rule, whose
    ends snap half away from zero in the frame shifted by half a pixel: an end on a tie of
    the grid (a multiple of 1/512 px) lands a grid step off."""

    name = "bad_llvmpipe_unshifted_snap"
    convention = Convention(line="llvmpipe-rectangle", input="float32", subpixel_bits=8)
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        from harness.contract.scenes import Scene
        from harness.oracle.coverage import exact_coverage
        from harness.oracle.llvmpipe_lines import llvmpipe_rectangle_corners

        a, b = scene.segments()
        rule = self.convention
        corners = llvmpipe_rectangle_corners(a, b, scene.line_width, rule)
        # move the ends to the triangles' snapping: the quad shifts by the difference
        ends = (rule.snap(a), rule.snap(b))
        llvm = (corners[:, 0] + corners[:, 3]) / 2, (corners[:, 1] + corners[:, 2]) / 2
        for k, (end, got) in enumerate(zip(ends, llvm)):
            shift = end - got
            for c in ((0, 3), (1, 2))[k]:
                corners[:, c] += shift
        triangles = np.stack([corners[:, [0, 1, 2]], corners[:, [0, 2, 3]]], axis=1).reshape(-1, 3, 2)
        p, x, y = exact_coverage(Scene(scene.width, scene.height, triangles), Convention()).pixels()
        return Coverage.from_pixels(p // 2, x, y)


HAIRLINE_BADS = [SkiaCentredStart(), QtFlatCaps(), LlvmpipeUnshiftedSnap()]
