"""Qt: ``QPainter::drawPolygon`` fills pixels for a polygon with a NaN vertex (raster paint engine).

Library: Qt 6.11 through PyQt6 6.11, the raster paint engine (a ``QImage``), offscreen.

Input: the triangle (NaN, 2), (12, 3), (5, 13) filled with ``drawPolygon`` (no pen, a
solid brush, anti-aliasing off, then on) on a 16 x 16 ``QImage.Format_Alpha8``.

Expected: nothing drawn. A vertex that is not a number defines no polygon, and Qt's own
policy for such points is to refuse them: ``QPainterPath::moveTo``/``lineTo`` drop a
point with a NaN or infinite coordinate ("Adding point with invalid coordinates, ignoring
call", qtbase ``src/gui/painting/qpainterpath.cpp``); dropping it here leaves two
vertices, which enclose nothing.

What happens: ``QRasterPaintEngine::drawPolygon`` passes the points unchecked to
``QOutlineMapper``, whose ``qRound(x * 64)`` of NaN is undefined behaviour (``INT_MIN``
on x86-64): the NaN vertex lands far to the left, and every pixel left of the edge
between the two finite vertices, in the rows between them, is filled (85 px aliased, 105
anti-aliased, with Qt 6.11).

Exit status: the script prints the counts and exits 1 while the polygon draws pixels, 0
once it draws none.
"""

import math
import os
import sys

import numpy as np

TRIANGLE = [(math.nan, 2.0), (12.0, 3.0), (5.0, 13.0)]


def drawn(antialias: bool) -> int:
    """How many pixels the triangle covers (nonzero alpha)."""
    from PyQt6.QtCore import QPointF, Qt
    from PyQt6.QtGui import QColor, QImage, QPainter, QPolygonF

    image = QImage(16, 16, QImage.Format.Format_Alpha8)
    image.fill(0)
    painter = QPainter(image)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing, antialias)
    painter.setPen(Qt.PenStyle.NoPen)
    painter.setBrush(QColor(0, 0, 0, 255))
    painter.drawPolygon(QPolygonF([QPointF(x, y) for x, y in TRIANGLE]))
    painter.end()
    data = image.constBits().asstring(image.sizeInBytes())
    alpha = np.frombuffer(data, dtype=np.uint8).reshape(16, image.bytesPerLine())[:, :16]
    return int(np.count_nonzero(alpha))


def main() -> int:
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")  # no display needed
    from PyQt6.QtCore import QT_VERSION_STR
    from PyQt6.QtGui import QGuiApplication

    app = QGuiApplication(sys.argv[:1])  # noqa: F841 - kept alive while drawing
    print(f"Qt {QT_VERSION_STR}: triangle {TRIANGLE}")
    bad = 0
    for antialias in (False, True):
        polygon = drawn(antialias)
        print(f"{'anti-aliased' if antialias else 'aliased'}: drawPolygon covers {polygon} px")
        bad += polygon > 0
    if bad:
        print("BUG: a polygon with a NaN vertex is filled")
        return 1
    print("fixed: a polygon with a NaN vertex draws nothing")
    return 0


if __name__ == "__main__":
    sys.exit(main())
