"""Known-bad anti-aliased line drawers (issue 34): each claims exact-area strokes
(``Convention(coverage="area", line=LineRule("rectangle", cap=...))``, 8-bit alphas) and gets
one classic thing wrong, which accuracy must catch:

* :class:`MajorAxisBoxLines`: the w-wide box along the minor axis (the segment moved by
  +-w/2 in y for an x-major segment, ends parallel to that axis: a parallelogram, as
  non-strict GPU lines) instead of the true rectangle -- right for axis-aligned lines, too
  thin on diagonals (by 1/sqrt(2) at 45 degrees).
* :class:`ForgetsCaps`: claims square caps, draws butt ends: the caps' area is missing.
* :class:`QuarterPixelLines`: truncates the end points to a 1/4 px grid while claiming float
  input: under sub-pixel motion its alphas stand still, then jump (popping).
* :class:`DirectionalAALines`: floors the exact area to a level for a segment drawn
  rightwards (or straight down) and ceils it for one drawn the other way (a span
  accumulator whose rounding follows the stepping direction); it declares a tolerance of
  one level, which both keep (accuracy passes): reversing a segment changes every partial
  alpha by one level, which invariance must catch exactly.
* :class:`ExactAALines`: the oracle itself rounded to 8 bits (not bad: the control).
"""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.oracle.area_lines import _Pieces, _polygon_areas, line_pixel_areas

__all__ = ["MajorAxisBoxLines", "ForgetsCaps", "QuarterPixelLines", "DirectionalAALines", "ExactAALines", "AA_LINE_BADS"]


def _eight_bit(alpha: np.ndarray) -> np.ndarray:
    rounded: np.ndarray = np.rint(np.clip(alpha, 0.0, 1.0) * 255.0) / 255.0
    return rounded


def _strokes(scene: LineScene, cap: str, grid: float = 0.0) -> Coverage:
    a, b = scene.segments()
    if grid:
        a, b = np.floor(a / grid) * grid, np.floor(b / grid) * grid
    s, x, y, area = line_pixel_areas(np.stack([a, b], axis=1), scene.line_width, cap, scene.width, scene.height)
    alpha = _eight_bit(area)
    keep = alpha > 0
    return Coverage.from_pixels(s[keep], x[keep], y[keep], alpha=alpha[keep])


class ExactAALines:
    """The exact stroke areas rounded to the nearest 8-bit level: what accuracy accepts."""

    name = "exact_aa_lines"
    scene_kinds = ("lines",)
    interpolates = False

    def __init__(self, cap: str = "butt") -> None:
        self.cap = cap
        self.convention = Convention(coverage="area", line=LineRule("rectangle", cap=cap))  # type: ignore[arg-type]

    def rasterize(self, scene: LineScene) -> Coverage:
        return _strokes(scene, self.cap)


class ForgetsCaps:
    """Claims square caps, draws butt ends (the caps' w/2 beyond each end point left out)."""

    name = "bad_aa_lines_forget_caps"
    convention = Convention(coverage="area", line=LineRule("rectangle", cap="square"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return _strokes(scene, "butt")


class MajorAxisBoxLines:
    """Claims exact butt rectangles; draws the w-wide box along the minor axis: the
    parallelogram between the segment moved by -w/2 and +w/2 along its minor axis, its ends
    parallel to that axis through the end points."""

    name = "bad_aa_lines_major_axis_box"
    convention = Convention(coverage="area", line=LineRule("rectangle"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        a, b = scene.segments()
        h = scene.line_width / 2
        pieces = _Pieces()
        far = []
        for k in range(a.shape[0]):
            pa, pb = a[k], b[k]
            if not (np.all(np.isfinite(pa)) and np.all(np.isfinite(pb))) or np.array_equal(pa, pb):
                continue
            if max(np.abs(pa).max(), np.abs(pb).max()) > 2.0**21:
                far.append(k)  # beyond float kernels' reach: drawn right (the bug is the box, not this)
                continue
            d = pb - pa
            off = np.array([0.0, h]) if abs(d[0]) >= abs(d[1]) else np.array([h, 0.0])
            pieces.add(np.stack([pa - off, pb - off, pb + off, pa + off]), k)
        piece, x, y, area = _polygon_areas(pieces, scene.width, scene.height)
        owner = np.asarray(pieces.owner, dtype=np.int64)[piece] if piece.size else piece
        if far:
            s, fx, fy, farea = line_pixel_areas(np.stack([a[far], b[far]], axis=1), scene.line_width, "butt",
                                                scene.width, scene.height)
            owner = np.concatenate([owner, np.asarray(far, dtype=np.int64)[s]])
            x, y, area = np.concatenate([x, fx]), np.concatenate([y, fy]), np.concatenate([area, farea])
        alpha = _eight_bit(area)
        keep = alpha > 0
        return Coverage.from_pixels(owner[keep], x[keep], y[keep], alpha=alpha[keep])


class QuarterPixelLines:
    """Claims exact butt rectangles on float input; truncates the end points to 1/4 px first."""

    name = "bad_aa_lines_quarter_pixel"
    convention = Convention(coverage="area", line=LineRule("rectangle"))
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        return _strokes(scene, "butt", grid=0.25)


class DirectionalAALines:
    """Claims exact butt rectangles within one level; floors a rightward (or straight
    down) segment's areas to levels and ceils the others'."""

    name = "bad_aa_lines_directional"
    convention = Convention(coverage="area", line=LineRule("rectangle"), tolerance=1 / 255)
    scene_kinds = ("lines",)
    interpolates = False

    def rasterize(self, scene: LineScene) -> Coverage:
        a, b = scene.segments()
        s, x, y, area = line_pixel_areas(np.stack([a, b], axis=1), scene.line_width, "butt", scene.width, scene.height)
        d = b - a
        forward = (d[:, 0] > 0) | ((d[:, 0] == 0) & (d[:, 1] > 0))
        scaled = np.clip(area, 0.0, 1.0) * 255.0
        level = np.where(forward[s], np.floor(scaled), np.ceil(scaled)) if s.size else scaled
        keep = level > 0
        return Coverage.from_pixels(s[keep], x[keep], y[keep], alpha=level[keep] / 255.0)


AA_LINE_BADS = (MajorAxisBoxLines(), ForgetsCaps(), QuarterPixelLines(), DirectionalAALines())
