"""Rasterizers that receive their coordinates at another precision than float64: test doubles
for identify's input-precision probe (:mod:`harness.identify.input_probes`), and known-bad
ones that declare float64 input while they round what they receive."""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.fixed_point import FixedPoint

__all__ = ["Float32Fed", "TruncatingInput", "TruncatesClaimsFloat64", "Float32ClaimsFloat64", "UnshiftedClaimsPiglit"]


def _as_float32(scene: Scene) -> Scene:
    with np.errstate(over="ignore"):
        return Scene(scene.width, scene.height, scene.positions.astype(np.float32).astype(np.float64))


def _truncated(scene: Scene) -> Scene:
    with np.errstate(invalid="ignore"):
        return Scene(scene.width, scene.height, np.trunc(scene.positions))


class Float32Fed:
    """``inner`` fed every coordinate rounded to float32 (ties to even), as a GPU API or
    the piglit and dEQP reference rasterizers (which compute in float32) receive them."""

    convention = None
    interpolates = False

    def __init__(self, inner: Any) -> None:
        self.inner = inner
        self.name = f"float32_{inner.name}"

    def rasterize(self, scene: Scene) -> Coverage:
        coverage: Coverage = self.inner.rasterize(_as_float32(scene))
        return coverage


class TruncatingInput:
    """Whole-pixel input by C's ``(int)`` cast (toward zero), as pygame's polygon drawing,
    then the top-left rule at pixel centres (integers need no snapping)."""

    convention = None
    interpolates = False
    name = "truncating_input"

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(8).rasterize(_truncated(scene))


class TruncatesClaimsFloat64:
    """Truncates its input to whole pixels, and declares float64 input: conformance catches it."""

    name = "bad_truncates_claims_float64"
    convention = Convention(subpixel_bits=8)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(8).rasterize(_truncated(scene))


class Float32ClaimsFloat64:
    """Rounds its input to float32 and declares float64 input (with 8-bit snapping): the
    two part only where float32 rounding moves a vertex across a half step of the grid."""

    name = "bad_float32_claims_float64"
    convention = Convention(subpixel_bits=8)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(8).rasterize(_as_float32(scene))


class UnshiftedClaimsPiglit:
    """Float32 input snapped to 1/16 px half away from zero in the unshifted frame
    (``iround(v * 2**n)``, dEQP's rounding), declared as piglit's rounding in the frame shifted
    by half a pixel (``iround(2**n * (v - 0.5))``): the two part only on vertices exactly on
    a half step of the grid in the first half pixel, 0 < c < 1/2 (half-away rounds those up,
    piglit down)."""

    name = "bad_unshifted_claims_piglit"
    convention = Convention(subpixel_bits=4, snap_rounding="half-away-shifted", input="float32")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return FixedPoint(4, snap_rounding="half-away").rasterize(_as_float32(scene))
