"""Checked by mypy in tests/test_typing.py: every built-in (and the known-bad ones) is
assignable to the Rasterizer protocol."""

from harness import Rasterizer
from rasterizers.centre_scanline import CentreScanline
from rasterizers.fixed_point import FixedPoint
from rasterizers.floor_scanline import FloorScanline
from rasterizers.pineda_topleft import PinedaTopLeft

floor: Rasterizer = FloorScanline()
centre: Rasterizer = CentreScanline()
pineda: Rasterizer = PinedaTopLeft()
fixed: Rasterizer = FixedPoint()
fixed16: Rasterizer = FixedPoint(16)
