"""Known-bad GL smooth-line drawers (issue 34): each declares Mesa's smooth-line convention
(:attr:`rasterizers.real.mesa_smooth.MesaSmoothLines.convention`: the butt rectangle's exact
area within :data:`~rasterizers.real.mesa_smooth.SMOOTH_TOLERANCE`) and draws Mesa's
distance ramps with one classic slip, which accuracy must catch under that tolerance (so
the tolerance is not vacuous):

* :class:`UnwidenedRampLines`: the quad not widened by half a pixel (ramp ``sat(w/2 -
  |d|)`` in place of ``sat(w/2 + 1/2 - |d|)``): a 1 px line's centre gets 1/2, its edges 0.
* :class:`EndlessRampLines`: the along factor left out (no caps: the ramp across runs on
  past the end points, over the segment's box).
* :class:`MesaModelLines`: Mesa's alphas as :func:`~rasterizers.real.mesa_smooth.smooth_line_alpha`
  computes them, rounded to 8 bits (not bad: the control, what accuracy accepts).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from rasterizers.real._aa_lines import draw_each_segment_alpha
from rasterizers.real.mesa_smooth import MesaSmoothLines, smooth_line_alpha

__all__ = ["UnwidenedRampLines", "EndlessRampLines", "MesaModelLines", "GL_SMOOTH_BADS"]


class _RampLines:
    """Draws each segment into its box with ``_alpha(a, b, width, x, y)`` at the pixel
    centres, rounded to 8 bits."""

    name = ""
    convention = MesaSmoothLines.convention
    scene_kinds = ("lines",)
    interpolates = False

    def _alpha(self, a: NDArray[np.float64], b: NDArray[np.float64], width: float,
               x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        return smooth_line_alpha(a, b, width, x, y)

    def rasterize(self, scene: LineScene) -> Coverage:
        width = float(scene.line_width)

        def draw(a: NDArray, b: NDArray, bw: int, bh: int, origin: tuple[int, int]) -> NDArray:
            y, x = np.mgrid[0:bh, 0:bw] + 0.5
            if np.array_equal(a, b):
                return np.zeros((bh, bw))
            alpha = self._alpha(a, b, width, x, y)
            rounded: NDArray = np.rint(np.clip(alpha, 0.0, 1.0) * 255.0) / 255.0
            return rounded

        return draw_each_segment_alpha(scene, self.name, draw, margin=2)


class MesaModelLines(_RampLines):
    """Mesa's smooth-line alphas (measured model), 8 bits: the control."""

    name = "mesa_model_smooth_lines"


class UnwidenedRampLines(_RampLines):
    """The ramp across centred on the rectangle's edge minus half a pixel: too thin by 1 px."""

    name = "bad_smooth_lines_unwidened"

    def _alpha(self, a: NDArray[np.float64], b: NDArray[np.float64], width: float,
               x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = np.clip(0.5 * width - _across(a, b, x, y), 0.0, 1.0) * _along(a, b, x, y)
        return out


class EndlessRampLines(_RampLines):
    """Only the ramp across: no factor along the segment, so no ends."""

    name = "bad_smooth_lines_endless"

    def _alpha(self, a: NDArray[np.float64], b: NDArray[np.float64], width: float,
               x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = np.clip(0.5 * max(width, 1.0) + 0.5 - _across(a, b, x, y), 0.0, 1.0)
        return out


def _along(a: NDArray[np.float64], b: NDArray[np.float64], x: NDArray[np.float64],
           y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Mesa's factor along the segment (:func:`smooth_line_alpha` across a 1 px line's axis)."""
    length = float(np.hypot(*(b - a)))
    ux, uy = (b - a) / length
    s = np.abs(ux * (x - (a[0] + b[0]) / 2) + uy * (y - (a[1] + b[1]) / 2))
    hl = 0.5 * length + 0.5
    out: NDArray[np.float64] = np.clip(hl - s, 0.0, 1.0) * min(1.0, length / hl)
    return out


def _across(a: NDArray[np.float64], b: NDArray[np.float64], x: NDArray[np.float64],
            y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance of (x, y) from the line through a and b."""
    ux, uy = (b - a) / float(np.hypot(*(b - a)))
    out: NDArray[np.float64] = np.abs(ux * (y - a[1]) - uy * (x - a[0]))
    return out


GL_SMOOTH_BADS = (UnwidenedRampLines(), EndlessRampLines())
