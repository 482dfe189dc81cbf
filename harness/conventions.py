"""What "correct" means: screen space, sample points, tie rules, snapping and culling.

This module states the definitions of ``CONVENTIONS.md`` once; everything else in
rastercheck (the oracle, the reference rasterizers, the checks) applies them.

Screen space
    x grows right, y grows down, units are pixels, row 0 is the top row. Pixel (i, j)
    -- column i, row j -- is the unit square [i, i+1) x [j, j+1). Images are numpy
    arrays indexed ``[y, x]`` with shape ``(height, width)``.

Signed area
    ``A = (x1-x0)*(y2-y0) - (y1-y0)*(x2-x0)``. With y down, A > 0 means the vertices run
    clockwise as seen on screen. Both windings draw the same unless culling asks otherwise;
    a triangle whose (snapped) area is exactly zero covers nothing, always.

Edge function
    For the edge from a to b, ``E_ab(p) = (bx-ax)*(py-ay) - (by-ay)*(px-ax)``. For a
    triangle with A > 0 the interior is where all three of E_01, E_12, E_20 are positive.

A convention is sample point + tie rule + snapping (+ culling)
    1. Sample point ``(sx, sy)``: pixel (i, j) is covered when the point (i+sx, j+sy) is
       inside the triangle. GL, D3D10+ and Vulkan use the centre (0.5, 0.5).
    2. Tie rule: who owns a sample lying exactly on an edge. An edge is *top* if it is
       horizontal with the interior below it, *bottom* if horizontal with the interior
       above, *left* if not horizontal with the interior to its right, *right* otherwise.
       ``top-left`` owns top and left edges (D3D, llvmpipe); ``bottom-right``,
       ``top-right`` and ``bottom-left`` likewise. A sample on a vertex is inside only if it
       passes all three edge tests. A shared edge's samples thus belong to exactly one of
       its two triangles: no cracks, no double hits.
    3. Snapping ``subpixel_bits = n``: every coordinate c becomes
       ``round_half_to_even(c * 2**n) / 2**n`` before anything else. ``None``: no snapping,
       decisions are exact on the float64 input.
    4. Culling ``none | cw | ccw``: ``cw`` removes triangles with snapped A > 0 (clockwise
       on screen), ``ccw`` those with A < 0.

Every decision is exact: the sign of an edge function is the sign of the exact real
number (floats are dyadic rationals). No epsilon appears in any coverage decision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "TIE_RULES",
    "CULL_MODES",
    "MAX_SUBPIXEL_BITS",
    "SAMPLE_FRACTION_BITS",
    "Convention",
    "snap",
]

TieRule = Literal["top-left", "top-right", "bottom-left", "bottom-right"]
CullMode = Literal["none", "cw", "ccw"]
SnapRounding = Literal["nearest-even", "floor"]

TIE_RULES: tuple[str, ...] = ("top-left", "top-right", "bottom-left", "bottom-right")
CULL_MODES: tuple[str, ...] = ("none", "cw", "ccw")
SNAP_ROUNDINGS: tuple[str, ...] = ("nearest-even", "floor")
MAX_SUBPIXEL_BITS = 16
# A sample offset must be a multiple of 2**-32 so that i + sx is exact for every pixel
# column i of any viewport up to 2**20 pixels wide.
SAMPLE_FRACTION_BITS = 32
# At or above 2**52 every float64 is an integer, so snapping leaves it alone; below it,
# c * 2**16 < 2**68 cannot overflow and the product is exact (a power-of-two scale).
_SNAP_IDENTITY_ABOVE = 2.0**52


@dataclass(frozen=True, slots=True, repr=False)
class Convention:
    """A fill convention: sample point, tie rule, vertex snapping and culling.

    Parameters
    ----------
    sample : (float, float)
        Offset of the sample point inside each pixel, each in [0, 1] and a multiple of
        2**-32. (0.5, 0.5) is the centre; (1, 1) is the floor scanline's bottom-right corner.
    tie : {"top-left", "top-right", "bottom-left", "bottom-right"}
        Which edges own the samples lying exactly on them.
    subpixel_bits : int or None
        Snap vertices to multiples of 2**-n, 0 <= n <= 16, or None.
    cull : {"none", "cw", "ccw"}
        Remove triangles running clockwise (A > 0) or counter-clockwise on screen.
    snap_rounding : {"nearest-even", "floor"}
        How snapping rounds: to nearest, ties to even (D3D, GL drivers), or down
        (truncating fixed-point conversion, as skia's ``int(x * 64)``).

    Examples
    --------
    >>> Convention()
    Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none')
    >>> Convention(sample=(1, 1), tie="bottom-right").describe()
    'sample (1, 1), bottom-right ties, no snapping, no culling'
    >>> Convention(tie="top-middle")
    Traceback (most recent call last):
    ...
    ValueError: Convention.tie must be one of top-left, top-right, bottom-left, bottom-right, not 'top-middle'
    """

    sample: tuple[float, float] = (0.5, 0.5)
    tie: TieRule = "top-left"
    subpixel_bits: int | None = None
    cull: CullMode = "none"
    snap_rounding: SnapRounding = "nearest-even"

    def __repr__(self) -> str:
        extra = "" if self.snap_rounding == "nearest-even" else f", snap_rounding={self.snap_rounding!r}"
        return (f"Convention(sample={self.sample!r}, tie={self.tie!r}, subpixel_bits={self.subpixel_bits!r}, "
                f"cull={self.cull!r}{extra})")

    def snap(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """The positions as this convention sees them: snapped (see :func:`snap`)."""
        return snap(positions, self.subpixel_bits, self.snap_rounding)

    def __post_init__(self) -> None:
        try:
            sx, sy = (float(v) for v in self.sample)
        except (TypeError, ValueError):
            raise ValueError(
                f"Convention.sample must be a pair of numbers, not {self.sample!r}"
            ) from None
        for name, value in (("x", sx), ("y", sy)):
            if not (0.0 <= value <= 1.0) or not math.isfinite(value):
                raise ValueError(f"Convention.sample {name} must lie in [0, 1], not {value!r}")
            if (value * 2.0**SAMPLE_FRACTION_BITS) % 1.0 != 0.0:
                raise ValueError(
                    f"Convention.sample {name} must be a multiple of 2**-{SAMPLE_FRACTION_BITS}, "
                    f"not {value!r}"
                )
        object.__setattr__(self, "sample", (sx, sy))
        if self.tie not in TIE_RULES:
            raise ValueError(
                f"Convention.tie must be one of {', '.join(TIE_RULES)}, not {self.tie!r}"
            )
        bits = self.subpixel_bits
        if bits is not None and (
            isinstance(bits, bool)
            or not isinstance(bits, (int, np.integer))
            or not 0 <= bits <= MAX_SUBPIXEL_BITS
        ):
            raise ValueError(
                f"Convention.subpixel_bits must be None or an integer in 0..{MAX_SUBPIXEL_BITS}, "
                f"not {bits!r}"
            )
        if bits is not None:
            object.__setattr__(self, "subpixel_bits", int(bits))
        if self.snap_rounding not in SNAP_ROUNDINGS:
            raise ValueError(
                f"Convention.snap_rounding must be one of {', '.join(SNAP_ROUNDINGS)}, not {self.snap_rounding!r}"
            )
        if self.cull not in CULL_MODES:
            raise ValueError(
                f"Convention.cull must be one of {', '.join(CULL_MODES)}, not {self.cull!r}"
            )

    @property
    def owns_top(self) -> bool:
        """True when horizontal edges with the interior below them own their samples."""
        return self.tie.startswith("top")

    @property
    def owns_left(self) -> bool:
        """True when non-horizontal edges with the interior to their right own their samples."""
        return self.tie.endswith("left")

    def describe(self) -> str:
        """One line for people: sample point, ties, snapping, culling."""
        sx, sy = (f"{v:g}" for v in self.sample)
        snapping = (
            "no snapping"
            if self.subpixel_bits is None
            else f"snapped to 1/{2**self.subpixel_bits} px ({self.subpixel_bits} bits"
            + (", rounding down)" if self.snap_rounding == "floor" else ")")
        )
        culling = "no culling" if self.cull == "none" else f"culls {self.cull}"
        return f"sample ({sx}, {sy}), {self.tie} ties, {snapping}, {culling}"


def snap(positions: NDArray[np.float64], subpixel_bits: int | None, rounding: str = "nearest-even") -> NDArray[np.float64]:
    """Snap coordinates to multiples of ``2**-subpixel_bits``, rounding half to even (or
    down, with ``rounding="floor"``).

    Exact for every float64: scaling by a power of two is exact, ``np.rint`` rounds half
    to even, ``np.floor`` is exact, and values of magnitude 2**52 or more (already
    integers) are left alone. Non-finite values pass through unchanged.

    Parameters
    ----------
    positions : (..., 2) float64
    subpixel_bits : int or None
    rounding : {"nearest-even", "floor"}

    Returns
    -------
    (..., 2) float64

    Examples
    --------
    >>> snap(np.array([0.125, 0.375, 1.0 / 3.0, -0.375]), 2)
    array([ 0.  ,  0.5 ,  0.25, -0.5 ])
    """
    positions = np.asarray(positions, dtype=np.float64)
    if subpixel_bits is None:
        return positions
    scale = 2.0**subpixel_bits
    with np.errstate(invalid="ignore"):
        small = np.abs(positions) < _SNAP_IDENTITY_ABOVE
    snapped = positions.copy()
    round_ = np.floor if rounding == "floor" else np.rint
    snapped[small] = round_(positions[small] * scale) / scale
    return snapped
