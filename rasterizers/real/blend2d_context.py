"""Blend2D's raster context (``BLContext``) through blend2d-python: ``blend2d``, area
coverage (anti-aliased): triangles, paths and lines.

Blend2D has no aliased mode: its rendering context exposes no anti-aliasing switch (the
C++ API neither: ``BLContext`` fills are always analytic coverage), so there is one
adapter, in its native mode."""

from __future__ import annotations

import importlib.metadata
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rasterizers.real._aa_lines import AlphaLines
from rasterizers.real._aa_paths import AlphaPaths
from rasterizers.real._bases import AlphaOneTriangleAtATime, need

__all__ = ["Blend2DContext", "fill", "stroke"]


def fill(blend2d: Any, contours: list[NDArray], w: int, h: int, fill_rule: str = "nonzero") -> NDArray:
    """Closed contours filled by Blend2D as one ``BLPath`` (``move_to``, ``line_to``...,
    ``close`` per contour, float64) under the fill rule (``BLFillRule.NON_ZERO`` or
    ``EVEN_ODD``), opaque white over a cleared w x h A8 image: the (h, w) uint8 alpha."""
    image = blend2d.BLImage(w, h, blend2d.BLFormat.A8)
    ctx = blend2d.BLContext(image)
    ctx.clear_all()
    ctx.fill_rule = blend2d.BLFillRule.EVEN_ODD if fill_rule == "evenodd" else blend2d.BLFillRule.NON_ZERO
    ctx.set_fill_style((1.0, 1.0, 1.0, 1.0))
    path = blend2d.BLPath()
    for contour in contours:
        if contour.shape[0] == 0:
            continue
        path.move_to(float(contour[0, 0]), float(contour[0, 1]))
        for x, y in contour[1:].tolist():
            path.line_to(x, y)
        path.close()
    ctx.fill_path(path)
    ctx.flush()
    return np.array(image.getDataAsNumPy(), dtype=np.uint8).reshape(h, w)


def stroke(blend2d: Any, a: NDArray, b: NDArray, line_width: float, w: int, h: int, cap: str = "butt") -> NDArray:
    """The segment a-b stroked by Blend2D (``stroke_path``, ``stroke_width``, both caps
    ``BLStrokeCap.CAP_BUTT``, ``CAP_SQUARE`` or ``CAP_ROUND``), opaque white over a cleared
    w x h A8 image: the (h, w) uint8 alpha."""
    image = blend2d.BLImage(w, h, blend2d.BLFormat.A8)
    ctx = blend2d.BLContext(image)
    ctx.clear_all()
    ctx.set_stroke_style((1.0, 1.0, 1.0, 1.0))
    ctx.stroke_width = float(line_width)
    ctx.set_stroke_caps(getattr(blend2d.BLStrokeCap, "CAP_" + cap.upper()))
    path = blend2d.BLPath()
    path.move_to(float(a[0]), float(a[1]))
    path.line_to(float(b[0]), float(b[1]))
    ctx.stroke_path(path)
    ctx.flush()
    return np.array(image.getDataAsNumPy(), dtype=np.uint8).reshape(h, w)


class Blend2DContext(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """Blend2D (``BLContext.fill_path``), one triangle at a time into an A8 image around
    its box: area coverage, alpha = A8 value / 255. Blend2D's pixel (i, j) is our [i, i+1)
    x [j, j+1), y down, so coordinates pass unchanged (float64 to ``BLPath``); the probe
    ``test_blend2d_alphas_of_a_quarter_offset_triangle`` compares an asymmetric triangle
    with vertices at whole + 0.25 px with its exact area per pixel (no half-pixel shift,
    no flip, no transposition).

    Blend2D has no aliased mode (module docstring). Paths: each path one ``BLPath`` of all
    its contours filled once (:func:`fill`) under ``BLContext.fill_rule``, nonzero or
    even-odd: both rules are Blend2D's own (tested on a bow tie and a doubly wound
    square), judged against the exact area where the rule holds
    (:mod:`harness.oracle.path_area`). Lines: one butt-capped stroke per segment
    (:func:`stroke`), judged against the exact rectangle (:mod:`harness.oracle.area_lines`).

    No declared convention (Blend2D documents no error bound). Identified (Blend2D 0.8.0,
    blend2d-python 1.0.0): area coverage, analytic (every one of 256 sweep steps of an
    edge across a pixel gives its own level), 256 levels, max |alpha - area| 0.00884
    (mean 0.000998) on identify's scenes, 0.0142 on the quick suite's. A NaN vertex: nothing drawn. An infinite
    vertex: Blend2D draws the triangle's limit as the vertex goes to infinity (the same
    alphas, within 0.01, as the vertex at 2**20: tested), which identify counts as
    drawing a non-finite triangle (257 pixels); a geometric limit, not garbage, so not
    reported upstream.

    Found on the quick suite's path cases (issue 34): where each pixel sees one winding,
    within 0.0142 of the exact area (as triangles). Both rules are applied to each pixel's
    summed signed area (``calc_masks_from_cells`` in
    ``blend2d/pipeline/jit/fillpart.cpp``), not to the area where the winding satisfies
    them, so with overlapping contours a pixel half covered by a doubly wound region gets
    alpha 1 under both rules (up to 0.966 off: tested). And the sum wraps: the inside of
    a contour wound 128 times (or 65,536) is filled with alpha 0 under nonzero, where 127
    and 129 fill it (``rasterizers/real/upstream/blend2d_deep_winding.py``)."""

    name = "blend2d"
    library = "Blend2D"
    convention = None

    def __init__(self) -> None:
        self._b2d = need("blend2d")
        try:
            binding = importlib.metadata.version("blend2d-python")
        except importlib.metadata.PackageNotFoundError:
            binding = "?"
        self.library_version = f"Blend2D {'.'.join(str(v) for v in self._b2d.BL_VERSION)} (blend2d-python {binding})"

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return fill(self._b2d, [p], w, h) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return stroke(self._b2d, a, b, line_width, w, h) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return fill(self._b2d, contours, w, h, fill_rule) / 255.0
