"""The library adapters. Each docstring says how the library's coordinates map onto ours:
pixel (i, j) is the square [i, i+1) x [j, j+1), y down."""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from rasterizers.real._aa_lines import AlphaLines
from rasterizers.real._aa_paths import AlphaPaths
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need, refuse_kind, refuse_several_contours
from rasterizers.real._lines import MesaLines
from rasterizers.real._masks import (
    budget_batches,
    coverage_from_sample_masks,
    draw_each,
    finite_within_limit,
)
from rasterizers.real._stencil import StencilPaths

__all__ = ["PillowPolygon", "SkimagePolygon", "SkiaPath", "CairoFill", "MesaLlvmpipe", "MesaSoftpipe",
           "CairoAntialiased", "SkiaAntialiased", "MesaMultisample"]


def _skia_path(skia: Any, contours: list[NDArray], fill_rule: str = "nonzero") -> Any:
    """A skia path of closed polygon contours (move, lines, close per contour) under the
    fill rule. skia keeps points as float32 (``SkScalar``), which ``moveTo``/``lineTo``
    round to as well; the path is built from its serialized form (``readFromMemory``:
    the points as float32, the verbs as bytes) in one call, and, should this skia not
    read that form back, with a ``moveTo``/``lineTo`` per vertex (the same path)."""
    fill_type = skia.PathFillType.kEvenOdd if fill_rule == "evenodd" else skia.PathFillType.kWinding
    path = skia.Path()
    sizes = [c.shape[0] for c in contours]
    if sizes and min(sizes) > 0:
        # SkPath::writeToMemory, version 5: (version | fill type << 8), points, conics, verbs;
        # the float32 points; the verbs (move, line..., close per contour), padded to 4 bytes
        lengths = np.array(sizes) + 1  # K verbs and a close per contour
        ends = np.cumsum(lengths)
        verbs = np.ones(int(ends[-1]), dtype=np.uint8)  # kLine_Verb
        verbs[ends - lengths] = 0  # kMove_Verb
        verbs[ends - 1] = 5  # kClose_Verb
        with np.errstate(over="ignore", invalid="ignore"):
            points = np.concatenate(contours).astype(np.float32)
        header = np.array([5 | (1 if fill_rule == "evenodd" else 0) << 8, points.shape[0], 0, verbs.size], dtype=np.int32)
        data = header.tobytes() + points.tobytes() + verbs.tobytes() + bytes(-verbs.size % 4)
        if path.readFromMemory(data) == len(data):
            return path
        path = skia.Path()
    path.setFillType(fill_type)
    for contour in contours:
        if contour.shape[0] == 0:
            continue
        path.moveTo(float(contour[0, 0]), float(contour[0, 1]))
        for x, y in contour[1:].tolist():
            path.lineTo(x, y)
        path.close()
    return path


def _skia_fill(skia: Any, contours: list[NDArray], w: int, h: int, antialias: bool, fill_rule: str = "nonzero") -> NDArray:
    """Closed contours (a triangle is one) filled by skia under the fill rule, as one path
    with black paint, into a w x h alpha-8 surface: the (h, w) uint8 alpha."""
    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(w, h))
    canvas = surface.getCanvas()
    canvas.clear(skia.ColorTRANSPARENT)
    canvas.drawPath(_skia_path(skia, contours, fill_rule), skia.Paint(AntiAlias=antialias, Color=skia.ColorBLACK))
    alpha = np.empty((h, w), dtype=np.uint8)
    if not surface.readPixels(skia.ImageInfo.MakeA8(w, h), alpha, w, 0, 0):
        raise RuntimeError(f"skia could not read back its {w} x {h} surface")
    return alpha


def _skia_stroke(skia: Any, a: NDArray, b: NDArray, line_width: float, w: int, h: int) -> NDArray:
    """The segment a-b stroked by skia with anti-aliasing, ``line_width`` wide, butt caps
    (``kStroke_Style``, ``kButt_Cap``), into a w x h alpha-8 surface: the (h, w) uint8 alpha."""
    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(w, h))
    canvas = surface.getCanvas()
    canvas.clear(skia.ColorTRANSPARENT)
    paint = skia.Paint(AntiAlias=True, Color=skia.ColorBLACK)
    paint.setStyle(skia.Paint.kStroke_Style)
    paint.setStrokeWidth(float(line_width))
    paint.setStrokeCap(skia.Paint.kButt_Cap)
    path = skia.Path()
    path.moveTo(float(a[0]), float(a[1]))
    path.lineTo(float(b[0]), float(b[1]))
    canvas.drawPath(path, paint)
    alpha = np.empty((h, w), dtype=np.uint8)
    if not surface.readPixels(skia.ImageInfo.MakeA8(w, h), alpha, w, 0, 0):
        raise RuntimeError(f"skia could not read back its {w} x {h} surface")
    return alpha


def _cairo_stroke(cairo: Any, a: NDArray, b: NDArray, line_width: float, w: int, h: int) -> NDArray:
    """The segment a-b stroked by cairo with ``ANTIALIAS_DEFAULT``, ``line_width`` wide, butt
    caps (``LINE_CAP_BUTT``), into a w x h A8 surface: the (h, w) uint8 alpha."""
    surface = cairo.ImageSurface(cairo.FORMAT_A8, w, h)
    ctx = cairo.Context(surface)
    ctx.set_antialias(cairo.ANTIALIAS_DEFAULT)
    ctx.set_line_width(float(line_width))
    ctx.set_line_cap(cairo.LINE_CAP_BUTT)
    ctx.move_to(float(a[0]), float(a[1]))
    ctx.line_to(float(b[0]), float(b[1]))
    ctx.stroke()
    surface.flush()
    return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(h, surface.get_stride())[:, :w].copy()


def _cairo_fill(cairo: Any, contours: list[NDArray], w: int, h: int, antialias: Any, fill_rule: str = "nonzero") -> NDArray:
    """Closed contours (a triangle is one) filled by cairo under the fill rule, as one
    path, into a w x h A8 surface: the (h, w) uint8 alpha."""
    surface = cairo.ImageSurface(cairo.FORMAT_A8, w, h)
    ctx = cairo.Context(surface)
    ctx.set_antialias(antialias)
    ctx.set_fill_rule(cairo.FILL_RULE_EVEN_ODD if fill_rule == "evenodd" else cairo.FILL_RULE_WINDING)
    for contour in contours:
        if contour.shape[0] == 0:
            continue
        ctx.move_to(float(contour[0, 0]), float(contour[0, 1]))
        for x, y in contour[1:].tolist():
            ctx.line_to(x, y)
        ctx.close_path()
    ctx.fill()
    surface.flush()
    stride = surface.get_stride()
    return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(h, stride)[:, :w]


class PillowPolygon(OneAtATime):
    """Pillow's ``ImageDraw.polygon``. Pillow puts pixel centres at integer coordinates,
    so our (x, y) is Pillow's (x - 0.5, y - 0.5).

    Paths: even-odd, one contour per path. What Pillow does (``_draw_polygon`` in
    ``src/_imaging.c``, ``ImagingDrawPolygon`` and ``polygon_generic`` in
    ``src/libImaging/Draw.c``): every vertex is truncated to an integer (``(int)x``, toward
    zero: whole-pixel vertices); each horizontal edge is drawn as a line; on each row
    (Pillow's integer y, our pixel centre) the crossings of the other edges (an edge's two
    end rows included, its lower end row counted twice; corners nudged by a heuristic) are
    sorted and taken in pairs, each pair filling the pixels ``ceil(a) .. floor(b)``, ends
    included. Pairing sorted crossings is the even-odd rule (``polygon_generic``'s
    ``eofill`` argument is unused), so ``fill_rules = ("evenodd",)``: a self-intersecting
    contour (a pentagram) is filled even-odd, its centre left empty. ``ImageDraw.polygon``
    takes one vertex sequence, one contour: a path of several contours is refused with a
    ValueError naming it, not drawn otherwise (two calls would OR the contours, which is
    no fill rule, and a zero-width bridge joining them into one polygon would have its
    own pixels filled, Pillow filling edges inclusively).

    Lines: ``ImageDraw.line([a, b], width=1)``, one call per segment, coordinates
    unchanged: for lines Pillow follows its documented coordinate system ("the
    coordinates refer to the implied pixel corners": pixel (i, j) is the square [i, i+1) x
    [j, j+1), as ours). What Pillow does (``_draw_lines`` in ``src/_imaging.c``,
    ``line8``/``line32`` in ``src/libImaging/Draw.c``): each coordinate is cast to ``int``
    (truncation toward zero: the pixel holding the point, ``floor``, for coordinates >= 0;
    a coordinate in (-1, 0) goes to pixel 0, not -1), then integer Bresenham from the start
    pixel, the minor coordinate stepping when the decision variable is >= 0 (a tie steps),
    and the polyline's last point drawn too: one segment per call draws both end pixels.
    So Pillow's lines are ``LineRule("bresenham", rounding="floor", ties="step",
    last_pixel=True)`` applied to the coordinates truncated toward zero (measured, Pillow
    13: not one pixel differs on float, lattice and below-zero polylines), and a
    polyline's joints are drawn by both segments. Wide lines are polygons with their own
    rounding: widths other than 1 are refused (Unsupported)."""

    name = "pillow"
    library = "Pillow"
    fill_rules = ("evenodd",)

    def __init__(self) -> None:
        self._pil = need("PIL")
        self.library_version = str(self._pil.__version__)
        from PIL import Image, ImageDraw

        self._Image, self._Draw = Image, ImageDraw

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        image = self._Image.new("L", (w, h), 0)
        self._Draw.Draw(image).polygon([(float(x) - 0.5, float(y) - 0.5) for x, y in p], fill=255)
        return np.asarray(image) > 0

    def _refuse(self, scene: PathScene) -> None:
        super()._refuse(scene)
        refuse_several_contours(self.name, scene, "ImageDraw.polygon")

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        image = self._Image.new("L", (w, h), 0)
        self._Draw.Draw(image).line([(float(a[0]), float(a[1])), (float(b[0]), float(b[1]))], fill=255, width=1)
        return np.asarray(image) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        (contour,) = contours
        image = self._Image.new("L", (w, h), 0)
        if contour.shape[0] > 1:  # Pillow raises TypeError below two vertices; one vertex encloses nothing
            self._Draw.Draw(image).polygon((contour - 0.5).ravel().tolist(), fill=255)
        return np.asarray(image) > 0


class SkimagePolygon(OneAtATime):
    """scikit-image's ``draw.polygon(rows, cols)``: pixel centres at integers, so rows are
    y - 0.5 and columns x - 0.5.

    Paths: even-odd, every contour of a path in one call. What scikit-image does
    (``_polygon`` in ``draw/_draw.pyx``, ``point_in_polygon`` in
    ``_shared/geometry.pyx``): every pixel centre of the polygon's box is tested on its own
    by the parity of the polygon's crossings of a ray to its right (an edge crosses when
    its ends lie strictly on opposite sides of the ray, ``(y0 > 0) != (y1 > 0)``, at x =
    ``(x0*y1 - x1*y0) / (y1 - y0)`` in float64); a centre within 1e-12 of a vertex in both
    coordinates, or on an edge (left and right crossing parities differ), is inside. So
    ``fill_rules = ("evenodd",)``. ``draw.polygon`` takes one polygon: a path's contours
    are joined into one by zero-width bridges, C0, C0[0], C1, C1[0], C0[0], C2, C2[0],
    C0[0], ... (C0 is walked and closed, then the bridge C0[0] -> C1[0], C1 walked and
    closed, the bridge back C1[0] -> C0[0], and so on). This is exact, not an
    approximation: the two edges of a bridge are the same segment walked both ways, and
    the test above gives them the same straddle decision and the same float crossing (the
    numerator and the denominator both change sign exactly, rounding to nearest being
    symmetric), so each bridge adds 0 or 2 crossings and never changes a parity; the
    repeated vertices are vertices already, and the closing edge C0[0] -> C0[0] has zero
    length (it crosses nothing). The bridged polygon is therefore filled exactly as
    scikit-image's test would fill all the path's edges at once.

    Lines: ``draw.line(r0, c0, r1, c1)`` takes integer end points, so the adapter rounds
    each end point first, as a caller would in scikit-image's frame (pixel centres at
    integers): to the nearest pixel centre, halves to even, ``np.rint(x - 0.5)``
    (:func:`nearest_pixel`, computed exactly: the pixel holding the point, ``floor(x)``,
    but for x an integer, on the border of pixels x - 1 and x, where the even one is
    taken). What scikit-image does (``_line`` in ``draw/_draw.pyx``): integer Bresenham
    from (r0, c0), the minor coordinate stepping while the decision variable is >= 0 (a
    tie steps), both end pixels drawn; x-major unless |dr| > |dc|. So its lines are
    ``LineRule("bresenham", rounding="nearest-even", ties="step", last_pixel=True)``
    (measured, scikit-image 0.26: not one pixel differs on float, lattice and below-zero
    polylines). Widths other than 1 are refused (Unsupported)."""

    name = "skimage"
    library = "scikit-image"
    fill_rules = ("evenodd",)

    def __init__(self) -> None:
        self.library_version = str(need("skimage").__version__)
        from skimage.draw import line, polygon

        # (skimage.draw is not annotated: both give (rows, cols) index arrays)
        self._polygon: Callable[..., tuple[NDArray, NDArray]] = polygon
        self._line: Callable[..., tuple[NDArray, NDArray]] = line

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        rows, cols = self._polygon(p[:, 1] - 0.5, p[:, 0] - 0.5, shape=(h, w))
        mask = np.zeros((h, w), dtype=bool)
        mask[rows, cols] = True
        return mask

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return self._draw(bridged(contours), w, h, (0, 0))

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        # rounded where the screen's coordinates are (halves to even depend on the parity)
        shift = np.array(origin)
        (c0, r0), (c1, r1) = (nearest_pixel(a + shift) - shift).tolist(), (nearest_pixel(b + shift) - shift).tolist()
        rows, cols = self._line(r0, c0, r1, c1)
        inside = (rows >= 0) & (rows < h) & (cols >= 0) & (cols < w)
        mask = np.zeros((h, w), dtype=bool)
        mask[rows[inside], cols[inside]] = True
        return mask


def nearest_pixel(p: NDArray) -> NDArray[np.int64]:
    """The pixel whose centre is nearest to each finite coordinate, halves to even: the
    integer nearest to x - 1/2 (``np.rint(x - 0.5)``), computed without rounding x - 0.5.
    That is floor(x), but for an integer x (x - 1/2 halfway between x - 1 and x), where
    the even one of the two is taken.

    >>> nearest_pixel(np.array([3.2, 3.0, 4.0, 2.5, -1e-300, -1.0])).tolist()
    [3, 2, 4, 2, -1, -2]
    """
    below = np.floor(p)
    odd_integer = (p == below) & (np.mod(below, 2.0) == 1.0)
    nearest: NDArray[np.int64] = (below - odd_integer).astype(np.int64)
    return nearest


def bridged(contours: list[NDArray]) -> NDArray:
    """One polygon walking every contour, joined by zero-width bridges from the first
    contour's first vertex (see :class:`SkimagePolygon`): (V + 2 (C - 1) + 1, 2) for C > 1
    contours of V vertices in all, the single contour itself for C = 1.

    >>> bridged([np.array([[0, 0], [4, 0], [0, 4]]), np.array([[1, 1], [1, 2], [2, 1]])]).tolist()
    [[0, 0], [4, 0], [0, 4], [0, 0], [1, 1], [1, 2], [2, 1], [1, 1], [0, 0]]
    """
    if len(contours) == 1:
        return contours[0]
    home = contours[0][:1]
    pieces = [contours[0], home]
    for contour in contours[1:]:
        pieces += [contour, contour[:1], home]
    return np.concatenate(pieces)


class SkiaPath(OneAtATime):
    """skia-python, anti-aliasing off: skia's pixel (i, j) is our [i, i+1) x [j, j+1), so
    coordinates pass unchanged.

    Paths: each path is one ``skia.Path`` holding all its contours (move, lines, close
    each), with fill type ``kWinding`` (nonzero) or ``kEvenOdd``, drawn with one
    ``drawPath``; both rules are skia's own. Measured (skia-python 144.1): centre samples
    and bottom-right ties fit best, every departure within 1/64 px of an edge (its
    vertices in 26.6 fixed point).

    Lines: hairlines, ``canvas.drawLine(a, b)`` with a stroke paint of width 0,
    anti-aliasing off, one call per segment, coordinates unchanged (float32 in skia).
    What skia does (``SkScan::HairLineRgn`` in ``src/core/SkScan_Hairline.cpp``): end
    points to 26.6 fixed point toward zero (``SkScalarToFDot6``); an x-major line
    (``|dx| > |dy|``) is drawn left to right whatever its direction, one pixel in each
    column from round(min x) to round(max x) - 1 (round: add 1/2, floor), in the row
    holding the line's y at the column centre (16.16 fixed point); a y-major one likewise
    by rows. So a column is drawn when its centre lies in (min x, max x]: the left end's
    pixel is left out when the line starts right of its centre, the right end's drawn, in
    both directions. The DDA starts at the first column centre at or past the end point,
    so a line whose left end lies exactly on a column centre is drawn one slope step off.
    That is ``LineRule("skia-hairline")`` (:mod:`harness.oracle.hairlines`), exact on every
    segment inside the canvas (measured, skia-python 144.1: identify's line probes, 0
    mismatches on segments that stay on the canvas). A segment leaving the canvas is first
    clipped to it in float32 (``SkLineClipper::IntersectLine``), which moves its end and
    so its DDA: identify's residual (113 of 7,721 px) lies on such segments only. Widths
    other than 1 are refused (Unsupported: skia's wide strokes are another rule)."""

    name = "skia"
    library = "skia"

    def __init__(self) -> None:
        self._skia = need("skia")
        self.library_version = f"skia-python {self._skia.__version__}"

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _skia_fill(self._skia, [p], w, h, antialias=False) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return _skia_fill(self._skia, contours, w, h, False, fill_rule) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        skia = self._skia
        surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(w, h))
        canvas = surface.getCanvas()
        canvas.clear(skia.ColorTRANSPARENT)
        hairline = skia.Paint(AntiAlias=False, Color=skia.ColorBLACK, Style=skia.Paint.kStroke_Style, StrokeWidth=0)
        canvas.drawLine(float(a[0]), float(a[1]), float(b[0]), float(b[1]), hairline)
        alpha = np.empty((h, w), dtype=np.uint8)
        if not surface.readPixels(skia.ImageInfo.MakeA8(w, h), alpha, w, 0, 0):
            raise RuntimeError(f"skia could not read back its {w} x {h} surface")
        return alpha > 0


class CairoFill(OneAtATime):
    """pycairo, ``ANTIALIAS_NONE`` fill: cairo's pixel (i, j) is our [i, i+1) x [j, j+1), so
    coordinates pass unchanged.

    Paths: each path is one cairo path holding all its contours (``move_to``,
    ``line_to``, ``close_path`` each), filled once with ``FILL_RULE_WINDING`` (nonzero)
    or ``FILL_RULE_EVEN_ODD``; both rules are cairo's own. Measured (cairo 1.16): centre
    samples and top-left ties fit best, but the aliased scan converter
    (``cairo-mono-scan-converter.c``, ``row``) ends a span where the winding returns to
    zero only when the next edge lies more than one pixel further (``I(next->x.quo) >
    xend + 1``), so a one-pixel gap between two slanted edges of a row is filled (a
    triangle has none, which is why triangles fit); and a self-intersecting path leaving
    the surface on the left may fill pixels of column 0 that it leaves empty on a larger
    surface.

    Lines: one ``stroke`` per segment (``move_to(a)``, ``line_to(b)``), ``ANTIALIAS_NONE``.
    Where cairo has hairlines (``set_hairline``, cairo 1.18), a hairline, width 1 only
    (other widths Unsupported). cairo 1.16 has none: the segment is stroked
    ``line_width`` px wide with butt caps (``LINE_CAP_BUTT``, cairo's default), any width:
    the stroker outlines the rectangle of that width around the segment (no caps) and
    fills it like a path, at pixel centres, vertices in 24.8 fixed point -- Vulkan's
    rectangular lines, ``LineRule("rectangle")`` under cairo's fill convention (see
    above); a zero-length segment draws nothing. Measured (cairo 1.16): against
    ``Convention(subpixel_bits=8, line="rectangle")`` 14 of 2,465 pixels differ on float
    polylines, each within 0.005 px of the rectangle's boundary; on lattices the ties of
    vertical and horizontal sides and caps are top-left, those of slanted ones are not
    (a 45-degree segment from pixel centre to centre takes the end pixel, not the start
    one), and a rectangle corner lying on a row of pixel centres may draw a pixel beyond a
    cap (seen: 0.26 px beyond; the aliased scan converter's rounding of spans)."""

    name = "cairo"
    library = "cairo"

    def __init__(self) -> None:
        self._cairo = need("cairo")
        self.library_version = str(self._cairo.cairo_version_string())
        major, minor = (int(v) for v in self._cairo.cairo_version_string().split(".")[:2])
        self.hairlines = hasattr(self._cairo.Context, "set_hairline") and (major, minor) >= (1, 18)
        # a hairline is one pixel wide; cairo 1.16's rectangular strokes take any width
        self.line_widths = (1.0,) if self.hairlines else None

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_fill(self._cairo, [p], w, h, self._cairo.ANTIALIAS_NONE) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return _cairo_fill(self._cairo, contours, w, h, self._cairo.ANTIALIAS_NONE, fill_rule) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        cairo = self._cairo
        surface = cairo.ImageSurface(cairo.FORMAT_A8, w, h)
        ctx = cairo.Context(surface)
        ctx.set_antialias(cairo.ANTIALIAS_NONE)
        if self.hairlines:
            ctx.set_hairline(True)
        else:
            ctx.set_line_width(line_width)
        ctx.set_line_cap(cairo.LINE_CAP_BUTT)
        ctx.move_to(float(a[0]), float(a[1]))
        ctx.line_to(float(b[0]), float(b[1]))
        ctx.stroke()
        surface.flush()
        return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(h, surface.get_stride())[:, :w] > 0


class CairoAntialiased(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """pycairo, ``ANTIALIAS_DEFAULT`` fill into an A8 image surface, one triangle at a
    time; cairo's pixel (i, j) is our [i, i+1) x [j, j+1), so coordinates pass unchanged.
    Alpha is the A8 value / 255. (``GRAY``, ``GOOD``, ``BEST`` and ``SUBPIXEL`` draw the
    same bytes here; ``FAST`` is a 4 x 4 supersampler, tor22, not adapted.)

    Declared convention: cairo's own anti-aliasing model, ``Convention(coverage="area",
    rows=15, full_rows=True, input="fixed8", tolerance=1/255)``. The image backend fills
    with the tor scan converter (``cairo-tor-scan-converter.c``, ``GRID_X`` = 256,
    ``GRID_Y`` = 15) after clipping the polygon to the surface (``cairo-polygon.c``):
    transcribed whole in :mod:`harness.oracle.row_sampled_paths` (15 sampled sub-rows per
    pixel row, analytic full rows where no edge starts, ends or changes order, its edge
    list's tie order, its 24.8 input and its clipping). Its ``GRID_AREA_TO_ALPHA`` rounds
    the cell area half up, within half a level of the model; a rectilinear path goes to
    box compositing instead, within one level of its exact area. Measured (Debian 12,
    cairo 1.16): every byte equal to the model's level on 300 random triangles and 200
    random polygons crossing the surface's sides under both rules
    (tests/oracle/test_row_sampled_paths.py); against the exact area it is up to 17
    levels off (an edge swept across a pixel in 1/256 px steps takes 256 alphas when
    vertical, 16 when horizontal). Real failures it keeps: a NaN triangle draws, and a
    sliver's coverage of -5/255 wraps to 251/255 (its 16-bit cells).

    Paths (issue 34): each path one cairo path of all its contours (``_cairo_fill``,
    ``move_to``, ``line_to``..., ``close_path`` each) filled once under ``ANTIALIAS_DEFAULT``
    with ``FILL_RULE_WINDING`` (nonzero) or ``FILL_RULE_EVEN_ODD``: both rules are cairo's
    own, applied to each sub-row's winding (``apply_nonzero_fill_rule_for_subrow`` and
    ``apply_evenodd_fill_rule_for_subrow`` in ``cairo-tor-scan-converter.c``), so
    overlapping contours are judged by their winding (tested: a doubly wound square's
    edge pixels get 1/2 and 0). The same model judges them
    (:func:`harness.oracle.row_sampled_paths.row_sampled_path_coverage`)."""

    name = "cairo_aa"
    library = "cairo"
    # the tor scan converter's own model (harness.oracle.aa_models, row_sampled_paths): 15
    # sub-rows, full rows analytic, on 24.8 input, within one level (its GRID_AREA_TO_ALPHA
    # rounds half up; rectilinear paths go to box compositing, within a level of their area)
    convention = Convention(coverage="area", rows=15, full_rows=True, input="fixed8", levels=256, tolerance=1 / 255)
    # lines: each segment stroked with butt caps, the exact rectangle's area (harness.oracle.area_lines);
    # the stroker's outline goes through the same tor scan converter: its bound against the exact
    # area (15 sub-rows: 1/30 per boundary, two per column; x ends to 1/256; 8-bit rounding)
    line_convention = Convention(coverage="area", levels=256, subpixel_bits=8, tolerance=1 / 15 + 1 / 256 + 1 / 510,
                                 line=LineRule("rectangle"))

    def __init__(self) -> None:
        self._cairo = need("cairo")
        self.library_version = str(self._cairo.cairo_version_string())

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_fill(self._cairo, [p], w, h, self._cairo.ANTIALIAS_DEFAULT) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_stroke(self._cairo, a, b, line_width, w, h) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_fill(self._cairo, contours, w, h, self._cairo.ANTIALIAS_DEFAULT, fill_rule) / 255.0


class SkiaAntialiased(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """skia-python, a path per triangle filled with anti-aliasing on into an alpha-8
    surface; skia's pixel (i, j) is our [i, i+1) x [j, j+1), so coordinates pass unchanged.
    Alpha is the alpha-8 value / 255.

    No declared convention (``identify`` fingerprints it): skia has no model within a level
    (:data:`harness.oracle.supersample_models.SKIA_AAA_NOTE`). ``SkScan::AntiFillPath``
    calls the analytic ``SkScan::AAAFillPath`` for every path (``SkScan_AntiPath.cpp``):
    fixed-point trapezoid areas, vertex y snapped to 1/4 px, approximate intersections,
    alphas above 247 or below 8 snapped to 255 or 0, and it picks between two methods by
    the path's shape: measured on skia-python 144.1 with an edge swept across a pixel in
    1/256 px steps, a rectangle or 4-point quad takes 256 levels, a triangle or pentagon 17
    (multiples of 16: x on a 1/16 px grid, 4 sub-scanlines, which is why identify's best
    guess is a 16 x 4 grid). Nothing tried comes within a level (tiny-skia's supersampler:
    2,268 of 4,444 px off, up to 79 levels; a 16 x 4 grid: up to 44; the area with y
    snapped to 1/4 px: up to 65). On the quick suite's static cases the alphas are within
    0.32 of the exact area (thin tips and shallow edges of small mesh triangles), 0.0071 on
    average.

    Paths (issue 34): each path one ``skia.Path`` of all its contours (``_skia_path``) with
    fill type ``kWinding`` or ``kEvenOdd``, drawn once with anti-aliasing on: both rules are
    skia's own, applied to each sample's winding (tested: a doubly wound square's edge
    pixels get 1/2 and 0). Measured on the quick suite's path cases (max |alpha - exact
    area|): 0.31 on paths whose pixels see one winding (the triangles' shallow-edge and
    clipped-edge pattern), 0.32 with overlapping contours, 0.0066 on average."""

    name = "skia_aa"
    library = "skia"
    convention = None

    def __init__(self) -> None:
        self._skia = need("skia")
        self.library_version = f"skia-python {self._skia.__version__}"

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _skia_fill(self._skia, [p], w, h, antialias=True) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _skia_stroke(self._skia, a, b, line_width, w, h) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _skia_fill(self._skia, contours, w, h, True, fill_rule) / 255.0


_VERTEX = """#version 330
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }"""
_FRAGMENT = """#version 330
out float coverage;
void main() { coverage = 1.0; }"""
# GL >= 4.3: every fragment appends (primitive id, x, y) to a storage buffer, so one draw
# keeps each triangle's identity through overlaps (helper invocations store nothing).
_FRAGMENT_LIST = """#version 430
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
out float coverage;
void main() {
    uint i = atomicAdd(count, 1u);
    if (i < capacity) items[i] = uvec4(uint(gl_PrimitiveID), uint(gl_FragCoord.x), uint(gl_FragCoord.y), 0u);
    coverage = 1.0;
}"""


def _fragment_list(ctx: Any, moderngl: Any, program: Any, fbo: Any, positions: NDArray, side: int,
                   scissor: tuple[int, int, int, int], capacity: int) -> NDArray[np.int64]:
    """One draw of ``positions`` (n, 3, 2) float64 (pixels, the viewport mapping of
    :class:`_Mesa`) with ``program``, whose fragment shader appends one uvec4 per fragment
    (primitive id, x, y, ...) to storage buffer 0 (header: count, capacity); returns the
    (K, 4) int64 items of the fragments inside ``scissor`` (x, y, width, height).
    ``capacity`` bounds the fragments; should more arrive, the draw is redone with room
    for them (never truncated)."""
    n = len(positions)
    vertices = ctx.buffer((positions / side).astype(np.float32).tobytes())  # dividing by a power of two: exact
    vao = ctx.vertex_array(program, [(vertices, "2f", "position")])
    try:
        while True:
            storage = ctx.buffer(reserve=16 * (capacity + 1))
            storage.write(np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
            storage.bind_to_storage_buffer(0)
            fbo.use()
            ctx.viewport = (-side, -side, 2 * side, 2 * side)
            fbo.scissor = scissor
            ctx.disable(moderngl.CULL_FACE | moderngl.BLEND | moderngl.DEPTH_TEST)
            vao.render(moderngl.TRIANGLES, vertices=3 * n)
            ctx.finish()
            data = np.frombuffer(storage.read(), dtype=np.uint32)
            storage.release()
            count = int(data[0])
            if count <= capacity:
                break
            capacity = count + 1024  # cannot happen (fragments fit their boxes), but never truncate
        items = data[4:].reshape(-1, 4)[:count].astype(np.int64)
        # the scissor is not trusted as a filter: llvmpipe (22.3) with 4x multisampling runs
        # the shader for the row above and the column left of the rectangle, with the
        # samples past the pixel's centre
        x, y, w, h = scissor
        inside = (items[:, 1] >= x) & (items[:, 1] < x + w) & (items[:, 2] >= y) & (items[:, 2] < y + h)
        return items[inside]
    finally:
        vao.release()
        vertices.release()


class _Mesa:
    """Mesa's OpenGL through moderngl's EGL backend (no display). Where the context offers
    GL 4.3 (llvmpipe), the small triangles are one draw whose fragment shader appends
    (gl_PrimitiveID, x, y) to a storage buffer; large ones, and all of them without GL 4.3
    (softpipe: GL 3.3), one draw per triangle into a cleared, scissored box, read back
    each time.

    The framebuffer is a power-of-two square P >= W, H; GL window row y is memory row y,
    so the read-back image is indexed [y, x] exactly as ours (flipped relative to GL's
    bottom-up display, which also flips the winding; culling is off). GL takes float32
    positions: pixel x goes to NDC as float32(x / P) and the viewport is (-P, -P, 2P, 2P),
    whose transform ndc * P + 0 brings it back exactly, so every coordinate that float32
    holds reaches Mesa unchanged (a mapping like 2x/P - 1 would lose up to 2**-19 px to
    cancellation). The clip volume is therefore [-P, P]^2, wider than the screen: a
    triangle reaching up to P px off-screen reaches the rasterizer unclipped, as with a
    hardware guard band, and Mesa's viewport clipping (which moves vertices before
    snapping) only acts beyond that. Mesa snaps vertices to its own sub-pixel grid.

    Paths (both fill rules), each filled in one go by stencil-then-cover
    (:mod:`rasterizers.real._stencil`). Per path: a triangle fan per contour from its
    first vertex, (v0, vi, vi+1) (beyond 32 vertices a fan of fans, the same count with
    short triangles: :func:`~rasterizers.real._stencil.fan_indices`), drawn into an 8-bit
    stencil buffer with colour writes and culling off, two-sided: ``GL_INCR_WRAP`` under
    front-facing triangles and ``GL_DECR_WRAP`` under back-facing ones (nonzero),
    ``GL_INVERT`` under every one (even-odd); then a cover quad over the path's box (its bounding box widened to whole
    pixels plus one, clipped to the screen) drawn with the stencil test ``!= 0`` (nonzero:
    mask 0xFF; even-odd: bit 0), which records the path's pixels and resets the stencil to
    0 as it passes, so the next path starts from a clear stencil. With GL 4.3 (llvmpipe)
    the cover pass appends (path, x, y) to a storage buffer (``early_fragment_tests``: only
    fragments that pass the stencil test run the shader), paths whose boxes share no pixel
    go in one fan draw and one cover draw, and each batch is read back once; without
    (softpipe) the cover writes colour, read back path by path.

    Which samples, and why this is the fill rule: each fan triangle is rasterized like
    any triangle, at pixel centres, and the stencil at a sample ends as the number of
    front-facing minus back-facing fan triangles covering it (mod 256). The signed
    indicator of a triangle is the winding number of its boundary, and the fans'
    boundaries add up to the path's contours (each diagonal v0 -> vi, or chord, is
    walked once each way), so at a sample on no fan edge the count is the path's winding
    number w: the cover passes where w != 0 (mod 256), or where w is odd. On edges: llvmpipe's
    triangle rule (identified exactly: top-left ties at pixel centres, vertices snapped to
    1/256 px, half to even) decides every triangle at one perturbed point q = p + (eps,
    eps**2), eps -> 0+ (:mod:`harness.contract.conventions`), and q lies on no line through two
    vertices, so the count at p is exactly the winding number at q. A sample on a
    diagonal shared by two fan triangles is thus counted once when they lie on opposite
    sides of it, and by both or neither (with opposite signs: they cancel) when they
    overlap; a sample on the path's own edge or vertex is decided at q, which is the
    oracle's tie rule for paths (:mod:`harness.oracle.winding`); a fan triangle of zero area
    after snapping is culled and holds no q. Facing comes from the snapped area (the
    window y flip reverses every facing, which negates all counts: neither rule cares).
    So llvmpipe's paths follow ``Convention(tie="top-left", subpixel_bits=8)`` exactly
    under both rules, on the float32-rounded scene (:meth:`received`), but for a winding
    that is a nonzero multiple of 256 (reads as 0 under nonzero) and paths reaching past
    the guard band. The guard band: for a path scene P is widened (powers of two, up to
    :attr:`LARGEST`) until [-P, P]^2 holds every finite vertex, so fan triangles reaching
    off-screen are not clipped (Mesa clips in float, before snapping). A path with a NaN
    or infinite vertex goes to Mesa unchanged, its cover spanning the whole screen.

    No declared convention (it would bind the triangles too, which ``identify``
    fingerprints). Measured (Mesa 22.3.6): llvmpipe equals the exact oracle of
    ``Convention(subpixel_bits=8)`` on 400 random path scenes (1-4 paths of 1-3 contours
    of 1-13 vertices, on 1/2, 1/4, 1/512 and 1 px lattices and in float, repeated and
    collinear vertices, both rules) and on the hand-made scenes of
    ``tests/rasterizers/real/test_adapters_paths.py``: 0 pixels differ. softpipe (the same passes, colour
    read-back) fits centre samples, top-right ties, no snapping, as its triangles do:
    15 of 100 such scenes differ from it, by 21 px in all.

    Lines (:mod:`rasterizers.real._lines`): width 1 only (core-profile GL has no wider
    aliased lines: Unsupported), ``GL_LINE_SMOOTH`` off, single-sample, mapped as
    triangles are (float32 ``x / P``, P widened as for paths so that no segment is
    clipped). Separate segments (strips of two vertices) are one ``GL_LINES`` draw,
    polylines one ``GL_LINE_STRIP`` draw, strips separated by primitive restart. With
    GL 4.3 (llvmpipe) every fragment appends (gl_PrimitiveID, x, y) to a storage buffer
    (gl_PrimitiveID counts a strip draw's segments across restarts), so a pixel two
    segments draw comes back twice; without (softpipe) each segment is a draw of its own
    (a strip's as a two-vertex ``GL_LINE_STRIP``: Mesa's draw module hands the driver a
    strip one vertex pair at a time), read back by colour. A segment with a NaN or
    infinite end point is not drawn (a strip is cut around it) and covers nothing.

    What they do (Mesa 22.3.6): llvmpipe (``lp_setup_line.c``) decides whether to draw
    the start and end pixels by the diamond-exit test, in float on the unsnapped end
    points, then rasterizes a one-pixel-high parallelogram (wide, for y-major lines)
    trimmed to match, as a triangle (8-bit snapping, its triangles' tie rule). On float
    scenes that is the diamond-exit rule after snapping to 1/256 px
    (``Convention(subpixel_bits=8)``'s line rule): 0 of 2,096 (segment, pixel) pairs
    differ on ``tests/rasterizers/real/test_adapters_lines.py``'s float polylines, 11 of 15,275 on 1,500
    random segments (lines within a rounding of a diamond corner). Where lines pass
    through diamond corners (lattice end points) the parallelogram's ties decide
    instead: a line through a column's bottom corner draws the lower pixel when it runs
    down-right (the corner on the parallelogram's upper edge, a right edge) where the
    diamond rule draws the upper one, and a y-major segment running up the screen from a
    pixel centre leaves out its start pixel (54 of 2,412 pairs differ on a 1/4 px
    lattice). softpipe (``sp_setup.c``, ``sp_setup_line``) casts the window coordinates
    to ``int`` (truncation toward zero) and runs integer Bresenham without the last
    pixel, a tie stepping: exactly ``LineRule("bresenham", rounding="floor",
    last_pixel=False)`` on the truncated float32 coordinates."""

    name = ""
    driver = ""
    library = ""
    library_version = ""  # GL_VERSION, once a context is made
    coverage_kind = "single"
    convention: Convention | None = None
    interpolates = False  # coverage only: this adapter reads back no varyings (yet)
    scene_kinds: tuple[str, ...] = ("triangles", "paths", "lines")
    fill_rules: tuple[str, ...] = ("nonzero", "evenodd")
    # GL_MAX_VIEWPORT_DIMS is 16384 in llvmpipe and softpipe: the 2P viewport must fit
    LARGEST = 8192
    batch = True  # one draw with a fragment list where GL >= 4.3
    LISTED_BOX = 2048  # px: larger boxes are drawn one at a time

    def __init__(self) -> None:
        self._moderngl = need("moderngl")
        self._ctx: Any = None
        self._pid = -1
        self._paths: StencilPaths | None = None
        self._lines: MesaLines | None = None

    def _context(self) -> Any:
        if self._ctx is not None and self._pid == os.getpid():
            return self._ctx
        os.environ["GALLIUM_DRIVER"] = self.driver  # read when the EGL display is first made
        os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
        self._list_program = None
        try:
            ctx = self._moderngl.create_standalone_context(backend="egl", require=430)
        except Exception:
            try:
                ctx = self._moderngl.create_standalone_context(backend="egl")
            except Exception as exc:
                raise Unavailable(f"no EGL context ({exc}): apt-get install libegl1 libgl1-mesa-dri") from None
        renderer = ctx.info["GL_RENDERER"]
        if self.driver not in renderer:
            raise RuntimeError(f"{self.name}: asked Mesa for {self.driver} but got {renderer!r} "
                               "(this process already made an EGL display; run each Mesa adapter in its own worker)")
        self._ctx, self._pid = ctx, os.getpid()
        self.library_version = str(ctx.info["GL_VERSION"])
        self._program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
        if ctx.version_code >= 430 and self.batch:
            self._list_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT_LIST)
        return ctx

    def _side(self, scene: AnyScene) -> int:
        side = 1 << max(scene.width - 1, scene.height - 1, 1).bit_length()
        if side > self.LARGEST:
            raise ValueError(f"{self.name}: a {scene.width} x {scene.height} screen needs a {2 * side} px viewport; "
                             f"Mesa allows 16384 (screens up to {self.LARGEST} px a side)")
        return side

    def _guard_band(self, scene: PathScene | LineScene, side: int) -> int:
        """P for a path or line scene: the screen's, widened (by powers of two, up to
        :attr:`LARGEST`) until the clip volume [-P, P]^2 holds every finite vertex, so that
        no fan triangle (segment) reaching off-screen is clipped (Mesa clips in float,
        before snapping, and moves the samples near the new edges, or a segment's end
        point). The mapping stays exact: x / P in float32, P a power of two."""
        reach = float(np.max(np.abs(scene.vertices), where=np.isfinite(scene.vertices), initial=0.0))
        while side < reach and side < self.LARGEST:
            side *= 2
        return side

    # as Mesa receives the scene: each coordinate rounded to float32 (GL's vertex format),
    # which the exact mapping then carries unchanged (read by received_of)
    input = "float32"

    def _stencil_paths(self, ctx: Any) -> StencilPaths:
        """The stencil-then-cover drawer of this context (made once per context)."""
        if self._paths is None or self._paths.ctx is not ctx:
            self._paths = StencilPaths(ctx, self._moderngl, self._program, listed=self._list_program is not None)
        return self._paths

    def _line_drawer(self, ctx: Any) -> MesaLines:
        """The line drawer of this context (made once per context)."""
        if self._lines is None or self._lines.ctx is not ctx:
            self._lines = MesaLines(ctx, self._moderngl, self._program, listed=self._list_program is not None)
        return self._lines

    def rasterize(self, scene: AnyScene) -> Coverage:
        if isinstance(scene, LineScene) and scene.line_width != 1.0:
            # core-profile GL refuses wide lines (glLineWidth > 1: GL_INVALID_VALUE)
            raise Unsupported(f"{self.name}: draws lines 1 px wide only, not {scene.line_width:g}")
        ctx = self._context()
        side = self._side(scene)
        if isinstance(scene, LineScene):
            return self._line_drawer(ctx).rasterize(scene, self._guard_band(scene, side), self.name)
        if isinstance(scene, PathScene):
            return self._stencil_paths(ctx).rasterize(scene, self._guard_band(scene, side), self.name)
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        if self._list_program is not None:
            return self._rasterize_listed(ctx, scene, side)
        return self._rasterize_each(ctx, scene, side)

    def _rasterize_listed(self, ctx: Any, scene: Scene, side: int) -> Coverage:
        """Small triangles in one draw, the fragment list saying which triangle made each
        fragment; triangles whose box exceeds ``LISTED_BOX`` px one draw each (a fragment
        list pays an atomic per fragment: 20x faster on many small triangles, 12x slower
        on large ones, by ``rastercheck bench``'s workloads)."""
        positions = scene.positions
        n = len(scene)
        finite = finite_within_limit(scene, self.name)
        if n == 0:
            return Coverage.empty()
        safe = np.where(finite[:, None, None], positions, 0.0)  # non-finite ones get the whole screen below
        lo = np.clip(np.floor(safe.min(axis=1)), 0, [scene.width, scene.height])
        hi = np.clip(np.ceil(safe.max(axis=1)) + 1, 0, [scene.width, scene.height])
        boxes = np.where(finite[:, None], np.maximum(hi - lo, 0), [scene.width, scene.height])
        area = boxes[:, 0] * boxes[:, 1]
        large = np.flatnonzero(finite & (area > self.LISTED_BOX))
        parts = []
        if large.size:
            each = self._rasterize_each(ctx, Scene(scene.width, scene.height, positions[large]), side)
            parts.append(Coverage(large[each.triangle], each.y, each.x0, each.x1))
            positions = positions.copy()
            positions[large] = 0.0  # a point: draws nothing, and keeps the primitive ids in step
            area[large] = 0
        parts.append(self._draw_listed(ctx, scene, positions, side, int(np.sum(area)) + 1024))
        return Coverage(*(np.concatenate([getattr(c, f) for c in parts]) for f in ("triangle", "y", "x0", "x1")))

    def _draw_listed(self, ctx: Any, scene: Scene, positions: NDArray, side: int, capacity: int) -> Coverage:
        """One draw of every triangle; ``capacity`` bounds the fragments (no triangle covers
        more than its box)."""
        fbo = ctx.simple_framebuffer((side, side), components=1, dtype="f1")
        try:
            items = _fragment_list(ctx, self._moderngl, self._list_program, fbo, positions, side,
                                   (0, 0, scene.width, scene.height), capacity)
        finally:
            fbo.release()
        keep = (items[:, 1] < scene.width) & (items[:, 2] < scene.height)
        return Coverage.from_pixels(items[keep, 0], items[keep, 1], items[keep, 2])

    def _rasterize_each(self, ctx: Any, scene: Scene, side: int) -> Coverage:
        fbo = ctx.simple_framebuffer((side, side), components=1, dtype="f1")
        fbo.use()
        ctx.viewport = (-side, -side, 2 * side, 2 * side)
        ctx.disable(self._moderngl.CULL_FACE | self._moderngl.BLEND | self._moderngl.DEPTH_TEST)
        buffer = ctx.buffer(reserve=3 * 2 * 4)
        vao = ctx.vertex_array(self._program, [(buffer, "2f", "position")])

        def draw(p: NDArray, bw: int, bh: int, origin: tuple[int, int]) -> NDArray:
            x0, y0 = origin
            ndc = np.empty((3, 2), dtype=np.float32)
            ndc[:, 0] = (p[:, 0] + x0) / side  # dividing by a power of two: exact
            ndc[:, 1] = (p[:, 1] + y0) / side
            buffer.write(ndc.tobytes())
            fbo.scissor = (x0, y0, bw, bh)
            fbo.clear(0.0)
            vao.render(self._moderngl.TRIANGLES, vertices=3)
            data = np.frombuffer(fbo.read(viewport=(x0, y0, bw, bh), components=1, alignment=1), dtype=np.uint8)
            return data.reshape(bh, bw) > 0

        try:
            return draw_each(scene, self.name, draw)
        finally:
            vao.release()
            buffer.release()
            fbo.release()


class MesaLlvmpipe(_Mesa):
    __doc__ = _Mesa.__doc__
    name = "mesa_llvmpipe"
    driver = "llvmpipe"
    library = "Mesa llvmpipe (OpenGL)"


class MesaSoftpipe(_Mesa):
    __doc__ = _Mesa.__doc__
    name = "mesa_softpipe"
    driver = "softpipe"
    library = "Mesa softpipe (OpenGL)"


# GL >= 4.3 with multisampling: every fragment appends (primitive id, x, y, the samples of
# the pixel the primitive covers) to a storage buffer. gl_SampleMaskIn holds every covered
# sample of the fragment (the shader reads no per-sample input, so it runs once per pixel);
# a fragment with no sample covered (a helper) stores nothing.
_FRAGMENT_SAMPLES = """#version 430
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
out float coverage;
void main() {
    uint mask = uint(gl_SampleMaskIn[0]);
    if (mask != 0u) {
        uint i = atomicAdd(count, 1u);
        if (i < capacity) items[i] = uvec4(uint(gl_PrimitiveID), uint(gl_FragCoord.x), uint(gl_FragCoord.y), mask);
    }
    coverage = 1.0;
}"""
_GL_SAMPLE_POSITION = 0x8E50
# llvmpipe's 4x sample positions: lp_sample_pos_4x in Mesa's src/gallium/drivers/llvmpipe/lp_rast.c,
# which llvmpipe_get_sample_position reports (GL_SAMPLE_POSITION) and lp_scene.c turns into the
# rasterizer's fixed-point offsets (iround(pos * FIXED_ONE), exact: multiples of 1/8): D3D11's
# standard 4x pattern.
_LLVMPIPE_4X = ((0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875))


class MesaMultisample(_Mesa):
    """Mesa's llvmpipe with a 4x multisample framebuffer, through moderngl's EGL backend:
    which samples of each pixel each triangle covers, read from the fragment shader input
    ``gl_SampleMaskIn`` (bit s: sample s) with ``gl_PrimitiveID`` naming the triangle,
    appended to a storage buffer (GL 4.3), in one draw per batch of triangles.

    Coordinates are mapped as in :class:`MesaLlvmpipe` (float32 NDC ``x / P``, viewport
    (-P, -P, 2P, 2P); GL window row y is our row y, unflipped). GL gives each sample's
    position (``glGetMultisamplefv(GL_SAMPLE_POSITION)``) as an offset from the pixel's
    corner at window (i, j), x right and window y up; window y is our y, so that corner is
    our pixel's top-left corner and GL's offsets are our y-down offsets unchanged.
    llvmpipe reports D3D11's standard 4x pattern, in GL's sample order; the first draw
    checks that the driver reports the declared positions (:meth:`sample_positions`).

    Declared convention: each sample follows llvmpipe's single-sample rule, identified
    exactly for ``mesa_llvmpipe`` (top-left ties with window row y as row y, vertices
    snapped to 1/256 px rounding half to even); a test compares every sample with the
    exact multisample oracle on lattice scenes built to put edges and vertices on samples
    (every other tie rule differs there). On the quick suite's static cases, 36 of
    1,827,799 fragments differ from the oracle, all of triangles reaching beyond the clip
    volume [-P, P]^2, which Mesa clips in float before snapping (as for
    ``mesa_llvmpipe``).

    Triangles whose boxes would overflow the storage budget (:attr:`BUDGET` fragments)
    together are drawn in several batches, and a triangle that alone would is drawn in
    horizontal bands by scissor. The scissor does not filter alone: llvmpipe 22.3 with 4x
    multisampling runs the fragment shader for the row above and the column left of the
    scissor rectangle, with the samples past the pixel's centre (masks 0b1100 and 0b1010),
    so fragments outside it are dropped after the draw."""

    name = "mesa_llvmpipe_msaa4"
    driver = "llvmpipe"
    library = "Mesa llvmpipe (OpenGL)"
    coverage_kind = "multisample"
    scene_kinds = ("triangles",)  # paths and lines: single-sample only (MesaLlvmpipe)
    kinds_not_taken = {"paths": "multisampled paths are not adapted: mesa_llvmpipe fills them single-sample",
                       "lines": "multisampled lines are not adapted: mesa_llvmpipe draws them single-sample"}
    fill_rules = None  # type: ignore[assignment]  # (no paths: the base class's rules would contradict scene_kinds)
    SAMPLES = 4
    convention = Convention(samples=_LLVMPIPE_4X, tie="top-left", subpixel_bits=8)
    # fragments per draw: 16 bytes each, so 64 MiB of storage at most
    BUDGET = 1 << 22

    def __init__(self) -> None:
        super().__init__()
        self._mask_program: Any = None
        self._positions: tuple[tuple[float, float], ...] | None = None

    def _context(self) -> Any:
        fresh = self._ctx is None or self._pid != os.getpid()
        ctx = super()._context()
        if fresh or self._mask_program is None:
            if ctx.version_code < 430:
                raise Unavailable(f"{self.name}: needs GL 4.3 (storage buffers, gl_SampleMaskIn); "
                                  f"{ctx.info['GL_RENDERER']} offers {ctx.info['GL_VERSION']}")
            self._mask_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT_SAMPLES)
            self._positions = None
        return ctx

    def _framebuffer(self, ctx: Any, side: int) -> tuple[Any, Any]:
        """A side x side 4x multisample framebuffer and its colour renderbuffer."""
        colour = ctx.renderbuffer((side, side), components=1, samples=self.SAMPLES, dtype="f1")
        fbo = ctx.framebuffer(color_attachments=[colour])
        if fbo.samples != self.SAMPLES:
            fbo.release()
            colour.release()
            raise Unavailable(f"{self.name}: {ctx.info['GL_RENDERER']} gave {fbo.samples} samples, not {self.SAMPLES}")
        return fbo, colour

    def sample_positions(self) -> tuple[tuple[float, float], ...]:
        """The sample positions the driver reports for a 4x framebuffer
        (``glGetMultisamplefv(GL_SAMPLE_POSITION, s)``, which moderngl does not expose:
        resolved with ``eglGetProcAddress`` in the EGL library its context runs on), as our
        y-down offsets within the pixel, in GL's sample order."""
        if self._positions is not None and self._pid == os.getpid():
            return self._positions
        import ctypes

        ctx = self._context()
        egl = ctypes.CDLL("libEGL.so.1")
        egl.eglGetProcAddress.restype = ctypes.c_void_p
        egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
        address = egl.eglGetProcAddress(b"glGetMultisamplefv")
        if not address:
            raise Unavailable(f"{self.name}: EGL does not resolve glGetMultisamplefv")
        get = ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_uint, ctypes.POINTER(ctypes.c_float))(address)
        fbo, colour = self._framebuffer(ctx, 16)
        try:
            fbo.use()
            positions = []
            for s in range(self.SAMPLES):
                value = (ctypes.c_float * 2)()
                get(_GL_SAMPLE_POSITION, s, value)
                # window y is our y (unflipped): GL's offset up from the pixel's window corner (i, j)
                # is our offset down from its top-left corner
                positions.append((float(value[0]), float(value[1])))
        finally:
            fbo.release()
            colour.release()
        self._positions = tuple(positions)
        return self._positions

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, Scene):
            raise ValueError(f"{self.name}: takes triangles only (scene_kinds); paths and lines: mesa_llvmpipe")
        ctx = self._context()
        side = self._side(scene)
        reported = self.sample_positions()
        declared = _LLVMPIPE_4X
        if reported != declared:
            raise RuntimeError(f"{self.name}: the driver reports sample positions {reported}, "
                               f"not the declared {declared}")
        n = len(scene)
        finite = finite_within_limit(scene, self.name)
        if n == 0:
            return Coverage.empty()
        positions = scene.positions
        safe = np.where(finite[:, None, None], positions, 0.0)  # non-finite ones get the whole screen below
        lo = np.clip(np.floor(safe.min(axis=1)), 0, [scene.width, scene.height]).astype(np.int64)
        hi = np.clip(np.ceil(safe.max(axis=1)) + 1, 0, [scene.width, scene.height]).astype(np.int64)
        lo[~finite] = 0
        hi[~finite] = [scene.width, scene.height]
        boxes = np.maximum(hi - lo, 0)
        area = boxes[:, 0] * boxes[:, 1]
        fbo, colour = self._framebuffer(ctx, side)
        parts = []
        try:
            large = np.flatnonzero(area > self.BUDGET)
            for t in large:  # alone, in bands of rows that fit the budget
                rows = max(1, self.BUDGET // int(boxes[t, 0]))
                for y0 in range(int(lo[t, 1]), int(hi[t, 1]), rows):
                    band = (int(lo[t, 0]), y0, int(boxes[t, 0]), min(rows, int(hi[t, 1]) - y0))
                    items = _fragment_list(ctx, self._moderngl, self._mask_program, fbo, positions[t:t + 1], side,
                                           band, band[2] * band[3] + 1024)
                    items[:, 0] = t
                    parts.append(items)
            small = np.where(area > self.BUDGET, 0, area)
            # batches of consecutive triangles whose boxes fit the budget together
            for start, end in budget_batches(small, self.BUDGET):
                batch = positions[start:end].copy()
                batch[area[start:end] > self.BUDGET] = 0.0  # drawn above; a point draws nothing and keeps the ids in step
                items = _fragment_list(ctx, self._moderngl, self._mask_program, fbo, batch, side,
                                       (0, 0, scene.width, scene.height), int(small[start:end].sum()) + 1024)
                items[:, 0] += start
                parts.append(items)
        finally:
            fbo.release()
            colour.release()
        items = np.concatenate(parts)
        items = items[(items[:, 1] < scene.width) & (items[:, 2] < scene.height)]
        # bit s of gl_SampleMaskIn is sample s, in GL's sample order (that of the declared pattern)
        return coverage_from_sample_masks(items[:, 0], items[:, 1], items[:, 2], items[:, 3], scene.width, self.SAMPLES)
