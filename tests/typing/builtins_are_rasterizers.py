"""Checked by mypy in tests/acceptance/test_typing.py: every built-in (and the known-bad ones) is
assignable to the Rasterizer protocol."""

from harness import Rasterizer
from rasterizers.area_scanline import AreaScanline
from rasterizers.centre_scanline import CentreScanline
from rasterizers.fixed_point import FixedPoint
from rasterizers.floor_scanline import FloorScanline
from rasterizers.lines import BresenhamLines, DiamondExitDDA, RectangleLines
from rasterizers.multisample import MultisamplePineda, PinedaMSAA4, PinedaMSAA8
from rasterizers.pineda_topleft import PinedaTopLeft
from rasterizers.supersample import Supersampler, Supersampler4
from rasterizers.trapezoid import TrapezoidFill

floor: Rasterizer = FloorScanline()
centre: Rasterizer = CentreScanline()
pineda: Rasterizer = PinedaTopLeft()
fixed: Rasterizer = FixedPoint()
fixed16: Rasterizer = FixedPoint(16)
msaa4: Rasterizer = PinedaMSAA4()
msaa8: Rasterizer = PinedaMSAA8()
msaa_custom: Rasterizer = MultisamplePineda([(0.25, 0.25), (0.75, 0.75)], tie="bottom-right")
area: Rasterizer = AreaScanline()
supersample: Rasterizer = Supersampler4()
supersample2: Rasterizer = Supersampler(2)
trapezoid: Rasterizer = TrapezoidFill()
bresenham_lines: Rasterizer = BresenhamLines()
dda: Rasterizer = DiamondExitDDA()
rectangle_lines: Rasterizer = RectangleLines()
