"""Qt's raster paint engine (PyQt6): a ``QPainter`` on an 8-bit alpha ``QImage``, offscreen.

Two modes: :class:`QtRaster` (``qt``, aliased: triangles, paths under both fill rules,
cosmetic lines) and :class:`QtAntialiased` (``qt_aa``, ``QPainter.RenderHint.Antialiasing``:
triangles, paths under both fill rules, lines of any width). Qt's pixel (i, j) is the
square [i, i+1) x [j, j+1), y down, as ours ("the pixel ... is centered at (x + 0.5,
y + 0.5)" in the QPainter coordinate-system docs, "Qt 5 ... no longer ... shifted half a
pixel"), so coordinates pass unchanged, as float64 ``QPointF`` (Qt's ``qreal`` is
``double``).

PyQt6 only: PySide6 6.12 aborts Python 3.11 after a few thousand calls returning void.
Qt wants a ``QGuiApplication``: one is made per process on the first draw in Qt's main
thread (``QThread.isMainThread``), never before (so never before a fork), with
``QT_QPA_PLATFORM=offscreen`` unless the environment already names a platform. Drawing
on a ``QImage`` needs none (the raster engine runs in any thread), so draws from another
thread go on without one."""

from __future__ import annotations

import os
import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rasterizers.real._aa_lines import AlphaLines
from rasterizers.real._aa_paths import AlphaPaths
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need

__all__ = ["QtRaster", "QtAntialiased"]


class _Qt:
    """PyQt6's modules, and the one ``QGuiApplication`` of this process (made lazily)."""

    def __init__(self) -> None:
        need("PyQt6")
        from PyQt6 import QtCore, QtGui

        self.core: Any = QtCore
        self.gui: Any = QtGui
        self.version = f"Qt {QtCore.QT_VERSION_STR} (PyQt6 {QtCore.PYQT_VERSION_STR})"
        self._pid = -1
        self._app: Any = None

    def application(self) -> None:
        """Make this process's ``QGuiApplication`` unless one exists (the first draw in the
        main thread: Qt wants it made there; painting on a ``QImage`` needs none, so a draw
        from another thread goes on without it)."""
        if self._pid == os.getpid():
            return
        gui = self.gui
        if gui.QGuiApplication.instance() is None:
            main = getattr(self.core.QThread, "isMainThread", None)  # Qt 6.8: the thread Qt calls main
            if not (main() if main is not None else threading.current_thread() is threading.main_thread()):
                return
            os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
            self._app = gui.QGuiApplication(["rastercheck"])
        self._pid = os.getpid()

    def image(self, w: int, h: int) -> Any:
        """A w x h 8-bit alpha image, transparent."""
        self.application()
        image = self.gui.QImage(w, h, self.gui.QImage.Format.Format_Alpha8)
        image.fill(0)
        return image

    def painter(self, image: Any, antialias: bool) -> Any:
        """A painter on ``image``: black solid brush, no pen, anti-aliasing on or off."""
        gui = self.gui
        painter = gui.QPainter(image)
        painter.setRenderHint(gui.QPainter.RenderHint.Antialiasing, antialias)
        painter.setPen(self.core.Qt.PenStyle.NoPen)
        painter.setBrush(gui.QColor(0, 0, 0, 255))
        return painter

    @staticmethod
    def alpha(image: Any, w: int, h: int) -> NDArray[np.uint8]:
        """The (h, w) alpha bytes of ``image`` (a copy; rows are 32-bit aligned in Qt)."""
        bits = image.constBits()
        bits.setsize(image.sizeInBytes())
        return np.frombuffer(bits, dtype=np.uint8).reshape(h, image.bytesPerLine())[:, :w].copy()

    def stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int) -> NDArray[np.uint8]:
        """The segment a-b drawn with ``drawLine`` and an anti-aliased solid pen ``line_width``
        wide with flat caps (``Qt.PenCapStyle.FlatCap``: butt): the (h, w) alpha bytes."""
        gui, core = self.gui, self.core
        image = self.image(w, h)
        painter = self.painter(image, True)
        try:
            pen = gui.QPen(gui.QColor(0, 0, 0, 255))
            pen.setWidthF(float(line_width))
            pen.setCapStyle(core.Qt.PenCapStyle.FlatCap)
            painter.setPen(pen)
            painter.drawLine(core.QPointF(float(a[0]), float(a[1])), core.QPointF(float(b[0]), float(b[1])))
        finally:
            painter.end()
        return self.alpha(image, w, h)

    def path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, antialias: bool) -> NDArray[np.uint8]:
        """Closed contours filled as one ``QPainterPath`` (``moveTo``, ``lineTo``...,
        ``closeSubpath`` per contour) with ``Qt.FillRule.WindingFill`` (nonzero) or
        ``OddEvenFill``, drawn once with ``drawPath``: the (h, w) alpha bytes."""
        path = self.gui.QPainterPath()
        fill = self.core.Qt.FillRule
        path.setFillRule(fill.OddEvenFill if fill_rule == "evenodd" else fill.WindingFill)
        for contour in contours:
            if contour.shape[0] == 0:
                continue
            (x0, y0), *rest = contour.tolist()
            path.moveTo(x0, y0)
            for x, y in rest:
                path.lineTo(x, y)
            path.closeSubpath()
        image = self.image(w, h)
        painter = self.painter(image, antialias)
        try:
            painter.drawPath(path)
        finally:
            painter.end()
        return self.alpha(image, w, h)

    def polygon(self, p: NDArray, w: int, h: int, antialias: bool) -> NDArray[np.uint8]:
        """One polygon (a triangle) filled with ``drawPolygon``: the (h, w) alpha bytes."""
        point = self.core.QPointF
        image = self.image(w, h)
        painter = self.painter(image, antialias)
        try:
            painter.drawPolygon(self.gui.QPolygonF([point(x, y) for x, y in p.tolist()]))
        finally:
            painter.end()
        return self.alpha(image, w, h)


class QtRaster(OneAtATime):
    """Qt's raster paint engine, anti-aliasing off, into a ``QImage.Format_Alpha8``; the
    mapping is the identity (module docstring), proved by ``test_the_mapping_is_exact``
    (tests/rasterizers/real/test_qt_raster.py: integer-plus-1/4 triangles, the exact set of
    pixels of the oracle).

    Triangles: ``QPainter.drawPolygon`` of three ``QPointF``, no pen, a solid brush. Paths:
    one ``QPainterPath`` per path (``moveTo``, ``lineTo``, ``closeSubpath`` per contour)
    with ``Qt.FillRule.WindingFill`` (nonzero) or ``OddEvenFill``, drawn once with
    ``drawPath``; both rules are Qt's own.

    What Qt receives and does (qtbase ``src/gui/painting``): ``QOutlineMapper`` converts
    every vertex to 26.6 fixed point with ``qRound(x * 64)`` (half away from zero) --
    float64 in, 6 fraction bits; an outline whose box reaches beyond
    ``QT_RASTER_COORD_LIMIT`` is first clipped in float by ``QPainterPath::intersected``.
    Aliased fills then go to ``QScanConverter`` (``qrasterizer.cpp``, ``mergeLine``), a
    scanline converter sampling pixel centres: an edge covers the rows whose centre lies in
    (top, bottom] (``iTop = (a.y + 32) >> 6``, ``iBottom = (b.y - 32) >> 6``), its x at
    the first centre row in 16.16 fixed point, stepped by a slope truncated to 16.16
    (``FloatToQScFixed``) row after row; a span covers the pixels whose centre c has
    left < c <= right. So: centre samples, bottom-right ties, 6-bit snapping half away
    from zero -- but the x of a long slanted edge drifts by the slope's truncation
    (< 2**-16 px per row), so pixels whose centre lies within that drift of an edge may
    differ: not exactly a convention, and no declared one (``identify`` fingerprints it).
    Measured (Qt 6.11.0, PyQt6 6.11.0): best guess centre samples, bottom-right ties,
    vertices snapped to 1/64 px half away from zero (the vertex sweep and the rounding
    probe agree: half-away 0 mismatches, nearest-even 95, floor 238), residual 326 of
    140,819 px, every one exactly on a vertex (159) or on an edge of non-dyadic slope (167);
    paths the same, both fill rules honoured (0 pixels off the asked rule); watertight;
    zero-area and tiny triangles draw nothing.

    Lines: ``QPainter.drawLine(QPointF, QPointF)`` with a cosmetic pen (``QPen`` of width
    0, ``Qt``'s default ``SquareCap``), aliased: ``QCosmeticStroker::drawLine`` (one pixel
    per column, or per row for a y-major line). It truncates the end points to 26.6
    (``toF26Dot6``: ``(int)(x * 64)``, toward zero), widens the major extent by half a
    pixel at both ends (the square cap), draws the columns whose centre lies in
    [x1 - 1/2, x2 + 1/2), i.e. the pixels holding both end points, in the row of its
    16.16 DDA; two equal end points draw the pixel holding them. A polyline's joint is
    drawn by both of its segments (each segment is its own call). That is
    ``LineRule("qt-cosmetic")`` (:mod:`harness.oracle.hairlines`), exact on every segment
    inside the canvas (measured, Qt 6.11.0: identify's line probes); a segment leaving the
    canvas grown by 1 px left and top, 2 px right and bottom is first clipped to it in
    float64 (``QCosmeticStroker::clipLine``): identify's residual (2 of 9,238 px) lies on
    such a segment only. Qt compares the end points fuzzily (``QPointF ==``, relative
    1e-12): ends that close but unequal draw one point, which the rule does not say.
    Hairlines only: other widths are refused (Unsupported).

    Bad input: a triangle with a NaN vertex is drawn (``drawPolygon`` does not check its
    points; ``qRound`` of NaN gives ``INT_MIN``): it covers pixels
    (``rasterizers/real/upstream/qt_nan_polygon.py``). An infinite vertex is clipped to the
    coordinate limit first and draws the (infinite) triangle's part on the screen.
    ``QPainterPath`` drops a NaN or infinite point with a warning ("Adding point with
    invalid coordinates, ignoring call"), so such a path is drawn without it, its contour
    going on from the path's current point ((0, 0) before the first ``moveTo``)."""

    name = "qt"
    library = "Qt"
    line_widths = (1.0,)

    def __init__(self) -> None:
        self._qt = _Qt()
        self.library_version = self._qt.version

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._qt.polygon(p, w, h, antialias=False) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return self._qt.path(contours, fill_rule, w, h, antialias=False) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        qt = self._qt
        image = qt.image(w, h)
        painter = qt.painter(image, antialias=False)
        try:
            pen = qt.gui.QPen(qt.gui.QColor(0, 0, 0, 255))
            pen.setWidthF(0.0)  # cosmetic: one pixel wide whatever the transform
            painter.setPen(pen)
            painter.drawLine(qt.core.QPointF(float(a[0]), float(a[1])), qt.core.QPointF(float(b[0]), float(b[1])))
        finally:
            painter.end()
        return qt.alpha(image, w, h) > 0


class QtAntialiased(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """Qt's raster paint engine with ``QPainter.RenderHint.Antialiasing``, one triangle at a
    time (``drawPolygon``, no pen) into a ``QImage.Format_Alpha8``; the mapping is the
    identity (module docstring), proved by ``test_the_antialiased_mapping_is_exact``
    (tests/rasterizers/real/test_qt_raster.py: alphas within 0.02 of the exact area of
    integer-plus-1/4 triangles). Alpha is the byte / 255. Triangles, and lines: each
    segment a ``drawLine`` with an anti-aliased pen of the scene's width and flat caps,
    against the exact rectangle (:mod:`harness.oracle.area_lines`). Measured (Qt 6.11.0,
    100 random segments): widths above 1 within 0.027 of the exact area; widths up to 1
    are drawn another way (a thin-line path: errors up to 0.30, mean 0.056). Paths: one
    ``QPainterPath`` per path, all its contours, filled with ``drawPath`` under
    ``WindingFill`` (nonzero) or ``OddEvenFill``, as :class:`QtRaster` but anti-aliased;
    both rules are Qt's own (``QOutlineMapper`` sets ``QT_FT_OUTLINE_EVEN_ODD_FILL`` for
    ``OddEvenFill``, ``qoutlinemapper_p.h``; ``gray_hline`` in ``qgrayraster.c`` reads it).
    As in FreeType, the rule is applied to each pixel's summed signed area
    (``|area >> 9|``; nonzero capped at 255, even-odd folded: ``& 511``, above 256
    ``512 - c``), not to the area where the winding satisfies it, so a pixel half covered
    by a doubly wound region gets alpha 1 under both rules (exact: 1/2 nonzero, 0
    even-odd; tested). Found on the quick suite's path cases: where each pixel sees one
    winding, within 0.0175 of the exact area (as triangles); with overlapping contours up
    to 0.966 off; reversing one contour of an even-odd path changes alphas by up to 190
    levels (the summed area), reversing every contour by no more than a level.

    What Qt receives and does: vertices to 26.6 fixed point by ``QOutlineMapper``
    (``qRound(x * 64)``, half away from zero), filled by ``qgrayraster.c`` (FreeType's
    "smooth" rasterizer, ``gray_raster_render``): the exact area of the snapped polygon in
    each pixel, computed in cells of 1/256 px (``PIXEL_BITS`` 8) and written as 8 bits.
    No declared convention (``identify`` fingerprints it): no bound is documented.
    Measured (Qt 6.11.0): analytic area coverage, 256 levels, |alpha - exact area| at most
    0.0177 (mean 0.0021) over 274,247 (triangle, pixel)s; an edge swept across a pixel in
    1/256 px steps changes the alpha at odd multiples of 1/128 px, 65 levels: the 26.6
    snapping, to nearest.

    Bad input: as :class:`QtRaster`, a NaN vertex is drawn (pixels get alpha)."""

    name = "qt_aa"
    library = "Qt"

    def __init__(self) -> None:
        self._qt = _Qt()
        self.library_version = self._qt.version

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._qt.polygon(p, w, h, antialias=True) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._qt.stroke(a, b, line_width, w, h) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._qt.path(contours, fill_rule, w, h, antialias=True) / 255.0
