"""AGG (Anti-Grain Geometry 2.0) through aggdraw: its scanline rasterizer
(``agg::rasterizer_scanline_aa``), aliased (``agg``) and anti-aliased (``agg_aa``).

What aggdraw does with a fill (``draw_adaptor::draw`` in ``aggdraw/_aggdraw.cxx``,
aggdraw 1.4.1): the path goes through ``agg::conv_contour`` with
``auto_detect_orientation(true)`` and a width of half the pen's width, or 0.5 px when no
pen is given ("expand polygons by 0.5 pixels by default (experimental)", its 2005-08-30
change log); ``vcgen_contour::width(w)`` offsets by ``w / 2``, so a fill without a pen is
the polygon offset outward by 0.25 px on every side (0.5 px wider and taller: a 4 x 4
square gets a ring of pixels a quarter covered), which no convention describes (it
would fail every coverage check by design, and a user filling adjacent polygons gets
overlaps). The adapters pass a pen of width 0 and opacity 0
(``Pen(0, 0, 0)``): the contour is offset by 0 (``vcgen_contour::calc_miter`` with width
0 returns the vertex itself, exactly: the miter limit 0 clips the join back onto it),
and the outline the pen strokes afterwards is drawn with alpha 0, which the gray-8 pixel
format skips (``if (c.a)``), so it changes no pixel.

The rasterizer (``agg2/include/agg_rasterizer_scanline_aa.h``): vertices to 24.8 fixed
point by ``poly_coord(c) = int(c * 256)`` (truncation toward zero, not rounding); cells
accumulate the exact area of the fixed-point polygon per pixel; a pixel's coverage is
``cover = |area >> 9|`` to 8 bits, capped at 255: the shift floors the signed area
before its absolute value is taken, so the cover is ``floor(256 * area)`` for a polygon
counter-clockwise on screen (y down) and ``ceil(256 * area)`` for a clockwise one (the
vertex order changes the pixels: a bug, repro
``rasterizers/real/upstream/aggdraw_orientation.py``), under the nonzero rule
(``fill_non_zero``, which aggdraw never changes: the even-odd rule is not reachable).
``setantialias(True)`` maps the cover through ``gamma_linear`` (unchanged);
``setantialias(False)`` through ``gamma_threshold(0.5)``: drawn iff ``cover / 255 >=
0.5``, i.e. cover >= 128: a pixel is drawn iff at least half of it is covered (in 1/256
of a pixel, rounded as above). The "area" is not quite the triangle's: ``render_line``
splits each edge at the pixel rows and ``render_hline`` each piece at the columns, the
crossings rounded down to 1/256 px (``delta = p / dy`` with the remainder carried), and
the cells sum the exact area of that polygon. All of it is the coverage rule
``agg-cover`` (:mod:`harness.oracle.library_rules`), exact: :data:`FOUND`. The image's clip box (the drawn box, see below) is
applied in 24.8 integers by Liang-Barsky clipping, whose new vertices on the screen's
edge are rounded to 1/256 px: the on-screen part of a clipped edge moves by up to that
much (measured: a cover 1 level off along clipped edges, so an aliased pixel near half
coverage may flip).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.scenes import AnyScene
from rasterizers.real._aa_lines import AlphaLines
from rasterizers.real._aa_paths import AlphaPaths
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need

__all__ = ["AggAliased", "AggAntialiased", "FOUND"]

# The aliased mode's rule, found from outside and read in the source (issue 33): AGG's 8-bit
# cell cover >= 128 on 24.8 input truncated toward zero. Not the declared ``convention``: a
# coverage rule is defined for triangles, and the adapter draws paths and lines too.
FOUND = Convention(coverage="agg-cover", input="fixed8-toward-zero")


def _path(aggdraw: Any, contours: list[NDArray]) -> Any:
    """An aggdraw Path of closed polygon contours: ``moveto``/``lineto`` take float64
    (``"dd"``), unlike the polygon's coordinate sequence (``getpoints``: float32)."""
    path = aggdraw.Path()
    for contour in contours:
        if contour.shape[0] == 0:
            continue
        path.moveto(float(contour[0, 0]), float(contour[0, 1]))
        for x, y in contour[1:].tolist():
            path.lineto(x, y)
        path.close()
    return path


def _fill(aggdraw: Any, contours: list[NDArray], w: int, h: int, antialias: bool) -> NDArray:
    """The contours filled (nonzero) by aggdraw into a w x h gray-8 image, with the 0.5 px
    widening off (a transparent pen of width 0): the (h, w) uint8 values."""
    draw = aggdraw.Draw("L", (w, h), 0)
    draw.setantialias(antialias)
    draw.polygon(_path(aggdraw, contours), aggdraw.Pen(0, 0, 0), aggdraw.Brush(255))
    return np.frombuffer(draw.tobytes(), dtype=np.uint8).reshape(h, w)


def _stroke(aggdraw: Any, a: NDArray, b: NDArray, line_width: float, w: int, h: int) -> NDArray:
    """The segment a-b drawn by aggdraw's ``line`` with a pen ``line_width`` wide (AGG's
    stroker, butt caps: measured, the stroke ends at the end points) into a w x h gray-8
    image, anti-aliased: the (h, w) uint8 values."""
    draw = aggdraw.Draw("L", (w, h), 0)
    draw.setantialias(True)
    draw.line((float(a[0]), float(a[1]), float(b[0]), float(b[1])), aggdraw.Pen(255, float(line_width)))
    return np.frombuffer(draw.tobytes(), dtype=np.uint8).reshape(h, w)


def _received(scene: AnyScene) -> AnyScene:
    """The scene as AGG's rasterizer receives it: each coordinate to 24.8 fixed point by
    truncation toward zero (``int(c * 256)``). The adapters hand the library coordinates
    relative to a whole-pixel box origin that is >= 2 px below the primitive, or 0 (the
    box clipped at the screen's edge), so truncating the relative coordinate is
    truncating the screen's (toward zero: floor for x >= 0, ceil below 0)."""
    with np.errstate(invalid="ignore", over="ignore"):
        snapped = np.trunc(scene.coordinates * 256.0) / 256.0
    return scene.with_coordinates(snapped)


class AggAliased(OneAtATime):
    """AGG 2.0's scanline rasterizer through aggdraw, ``setantialias(False)``: a pixel is
    drawn iff at least half of it is covered (module docstring). aggdraw's pixel (i, j)
    is our [i, i+1) x [j, j+1), y down, so coordinates pass unchanged; the probe
    ``test_agg_pixels_of_a_quarter_offset_triangle`` compares a triangle with vertices at
    whole + 0.25 px with the pixels at least half covered by it (no half-pixel shift, no
    flip, no transposition).

    Each triangle and each path is an ``aggdraw.Path`` (``moveto``, ``lineto``,
    ``close`` per contour: float64 to aggdraw, which AGG truncates toward zero to 24.8
    fixed point: :meth:`received`), filled once with a ``Brush`` into a gray-8 image around
    its box, with aggdraw's default 0.5 px widening of fills turned off (module
    docstring: without a pen, every fill is the polygon grown by 0.25 px on every side).

    Paths: nonzero only. aggdraw never sets AGG's filling rule (``fill_non_zero``), so an
    even-odd path would be filled nonzero: ``fill_rules = ("nonzero",)``.

    Lines: ``Draw.line(path, Pen(255, w))``, one segment per call (the end points float64,
    the width float32, as ``Pen`` takes it): AGG strokes the segment (``conv_stroke``,
    butt caps: the w x length rectangle around it) and fills that rectangle by the same
    half-covered rule, any width (``line_widths = None``); a zero-length segment draws
    nothing.

    Found (issue 33): triangles follow the coverage rule ``agg-cover`` exactly,
    :data:`FOUND` (AGG's 8-bit cell cover >= 128, 24.8 input truncated toward zero):
    ``python -m harness.identify.rule_probes rasterizers.real.agg:AggAliased`` says exact,
    0 of 964 pixels off (the best area threshold, 1/2 on a 1/64 grid rounding down, 2 off),
    and 0 of 7,411 on 400 further triangles; the input rounding is told apart on vertices
    halfway between 1/256 px steps, off screen too. Not declared as ``convention``: the
    rule covers triangles, and paths and lines have no rule yet (the lead's identify
    wiring picks it up). Before (aggdraw 1.4.1; no point-sample rule): best guess
    only, sample (0.504, 0.504), top-right ties, 8 sub-pixel bits, 1,941 of 140,130
    pixels off (an area threshold leaves pixels of a shared edge to neither or both
    triangles: watertight fails with 472 holes and 3,126 double hits on 24 partitions;
    sub-pixel triangles are dropped); paths the same as triangles, under nonzero; lines
    best guess rectangular, sample (0.5, 0.5), 8 bits, 1,379 of 10,819 pixels off (width
    3: 30 of 730); 8 of 162,022 on-screen pixels change when a triangle crosses the
    screen's edge (the integer clipping above).

    Bad input: a triangle with a NaN or infinite coordinate draws nothing (``int(NaN *
    256)`` is INT_MIN on x86; the clipper discards it) and returns at once."""

    name = "agg"
    library = "AGG (aggdraw)"
    fill_rules = ("nonzero",)
    line_widths = None  # a stroke is the rectangle of any width

    def __init__(self) -> None:
        self._agg = need("aggdraw")
        self.library_version = f"aggdraw {self._agg.VERSION}"

    input = "fixed8-toward-zero"  # 24.8 by int(c * 256), as :func:`_received` says (read by received_of)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _fill(self._agg, [p], w, h, False) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return _fill(self._agg, contours, w, h, False) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        aggdraw = self._agg
        draw = aggdraw.Draw("L", (w, h), 0)
        draw.setantialias(False)
        path = aggdraw.Path()
        path.moveto(float(a[0]), float(a[1]))
        path.lineto(float(b[0]), float(b[1]))
        draw.line(path, aggdraw.Pen(255, float(line_width)))
        return np.frombuffer(draw.tobytes(), dtype=np.uint8).reshape(h, w) > 0


class AggAntialiased(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """AGG 2.0's scanline rasterizer through aggdraw, ``setantialias(True)`` (the
    default), one triangle at a time, drawn as for :class:`AggAliased` (an
    ``aggdraw.Path``, float64 to aggdraw, truncated to 24.8 fixed point by AGG; the 0.5 px
    widening off); aggdraw's pixel (i, j) is our [i, i+1) x [j, j+1), coordinates
    unchanged (probe ``test_agg_aa_alphas_of_a_quarter_offset_triangle``). Alpha is the
    gray-8 value / 255.

    What AGG computes: the exact area of the fixed-point triangle in each pixel, as
    ``cover = floor(256 * area)`` capped at 255 (module docstring); the gray-8 pixel format
    then blends the brush (255) over 0 with that cover: value = ``(255 * cover) >> 8``
    (cover - 1 for 1 <= cover <= 254; 255 stays 255), so the value is below 256 * area by
    up to 2 levels and 1/255 against 1/256 scaling. Triangles; lines: each segment
    aggdraw's ``line`` with a pen of the scene's width (butt ends), against the exact
    rectangle (:mod:`harness.oracle.area_lines`): measured within 0.0151 at widths 0.5 to 4;
    and paths: each path one ``aggdraw.Path`` of all its contours filled once, as
    :class:`AggAliased` fills it.

    Paths: nonzero only, as :class:`AggAliased`: aggdraw never calls AGG's
    ``rasterizer_scanline_aa::filling_rule`` (``draw_adaptor`` in ``aggdraw/_aggdraw.cxx``
    keeps the default ``fill_non_zero``), so an even-odd path would be drawn nonzero:
    ``fill_rules = ("nonzero",)``. AGG applies the rule to each cell's summed signed area
    (``calculate_alpha``: ``|area >> 9|``, capped at 255 under nonzero), not to the area
    where the winding is nonzero, so a pixel half covered by a doubly wound region (two
    overlapping contours) gets alpha 1 where the exact area is 1/2.
    No declared convention. Identified (aggdraw
    1.4.1): area coverage, analytic, 256 levels (254 reached: the blend never gives 254),
    max |alpha - area| 0.0159 (mean 0.00167) on identify's scenes, 0.0183 on the quick
    suite's; the vertex order changes alphas by a level (the orientation bug above: the
    invariance check's flip-winding failures); NaN and infinite triangles draw nothing.

    Found on the quick suite's path cases (issue 34): where each pixel sees one winding,
    within 0.0181 of the exact area (as triangles); with overlapping contours up to 0.966
    off (the summed area above); reversing every contour changes alphas by up to 3
    levels (25 of 47 cases, 1,284 pixels: the orientation bug); and the inside of a
    contour wound 65,536 times is filled with alpha 0 (the summed cover overflows;
    winding 256 still fills it)."""

    name = "agg_aa"
    library = "AGG (aggdraw)"
    convention = None
    fill_rules = ("nonzero",)  # aggdraw never sets AGG's filling rule: fill_non_zero (class docstring)

    def __init__(self) -> None:
        self._agg = need("aggdraw")
        self.library_version = f"aggdraw {self._agg.VERSION}"

    input = "fixed8-toward-zero"  # 24.8 by int(c * 256), as :func:`_received` says (read by received_of)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _fill(self._agg, [p], w, h, True) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _stroke(self._agg, a, b, line_width, w, h) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _fill(self._agg, contours, w, h, True) / 255.0
