"""How an analytic anti-aliaser turns a pixel's accumulated area into an 8-bit level:
one object per library family, read from its source (issue 34).

FreeType's ``ftgrays.c``, Qt's ``qgrayraster.c`` (a copy of an older ``ftgrays.c``), AGG's
``agg_rasterizer_scanline_aa.h`` and Blend2D's analytic pipeline all accumulate, per pixel,
the *signed* area ``S`` of the outline inside it (the integral of the winding number over
the pixel, in cells of 1/256 px: a full pixel is ``2 * 256 * 256`` units) and shift it down
to ``k = floor(256 S)`` (``area >> (PIXEL_BITS * 2 + 1 - 8)``, an arithmetic shift). What
they do with ``k`` differs, and that is a :class:`Quantisation`:

==================  ==================================================================
name                level of ``k`` (nonzero; even-odd: see each object)
==================  ==================================================================
``nearest``         (no object: the default) the exact area rounded to the nearest of the
                    convention's ``levels``, within its ``tolerance`` -- what every area
                    convention meant before
``ftgrays``         ``k`` if ``k >= 0`` else ``~k`` (``-k - 1``), capped at 255: FreeType
                    (``src/smooth/ftgrays.c``, ``FT_FILL_RULE`` in ``gray_sweep``)
``cells-abs``       ``|k|`` capped at 255: Qt (``src/gui/painting/qgrayraster.c``,
                    ``gray_hline``) and AGG (``agg_rasterizer_scanline_aa.h``,
                    ``calculate_alpha`` with the linear gamma) -- matplotlib's Agg
``cells-abs-gray8`` ``cells-abs``'s ``c``, then AGG 2's ``pixfmt_gray8`` blend of opaque 255
                    over 0 (``agg_pixfmt_gray8.h``, ``blend_hline``: ``(255 * 255 c) >> 16``,
                    255 for ``c = 255``): aggdraw's ``"L"`` images
``blend2d``         ``min(|k|, 256) * 255 >> 8``: Blend2D (``blend2d/pipeline/reference/
                    fillgeneric_p.h``, ``FillAnalytic_Base::calc_mask``, opaque global alpha
                    255; the JIT's ``FillAnalyticPart::calc_masks_from_cells`` alike)
==================  ==================================================================

The sign of ``S`` is the library's: its cells add a contour's area with the sign of the
contour's orientation in the library's own axes. Qt, AGG and Blend2D are y down, as the
screen: a contour running clockwise on screen (signed area ``A > 0``, see
:mod:`harness.contract.conventions`) accumulates ``S < 0``. FreeType's outlines are y up,
so the same contour accumulates ``S > 0`` there (``cw_positive``). The sign matters: ``k``
and ``~k`` differ where ``256 S`` is a whole number, ``|k|`` and ``k`` by one level wherever
it is not (``floor`` of a negative area is its ceiling, negated).

This module imports nothing of the harness: :mod:`harness.contract.conventions` checks a
convention's ``quantisation`` against :data:`QUANTISATIONS`, and the oracle
(:mod:`harness.oracle.analytic_models`) asks the object for its levels.

>>> [q.level(128, "nonzero") for q in QUANTISATIONS.values()]
[128, 128, 127, 127]
>>> [q.level(-128, "nonzero") for q in QUANTISATIONS.values()]
[127, 128, 127, 127]
>>> [q.level(256, "nonzero") for q in QUANTISATIONS.values()], [q.level(384, "evenodd") for q in QUANTISATIONS.values()]
([255, 255, 255, 255], [127, 128, 127, 127])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["Quantisation", "QUANTISATIONS", "QUANTISATION_NAMES", "NEAREST", "FTGRAYS", "CELLS_ABS", "CELLS_ABS_GRAY8",
           "BLEND2D", "quantisation_named"]

# the default: the exact area rounded to the nearest level, within the declared tolerance
NEAREST = "nearest"


@dataclass(frozen=True, eq=False)
class Quantisation:
    """A library's mapping of ``k = floor(256 S)`` (S: the pixel's signed accumulated area,
    in the library's sign) to an 8-bit level.

    Parameters
    ----------
    name : str
        Its key in :data:`QUANTISATIONS` (what ``Convention.quantisation`` says).
    words : str
        A few words for people.
    source : str
        Where it is read: file and function.
    negative : {"abs", "not"}
        A negative ``k`` becomes ``-k`` (``abs``) or ``~k = -k - 1`` (``not``: ftgrays'
        ``coverage = ~coverage``).
    evenodd : {"bit8", "fold"}
        Even-odd: ``bit8`` (ftgrays): ``~k`` when bit 8 of ``k`` is set, then its low byte;
        ``fold``: ``c = |k| mod 512``, ``512 - c`` above 256 (a triangle wave of period 512).
    scale : {"clamp", "gray8", "times255"}
        The last step: ``min(c, 255)``; ``gray8``: that, blended as AGG 2's
        ``pixfmt_gray8`` blends opaque 255 over 0 (``(255 * 255 c) >> 16``, 255 kept);
        ``times255``: ``min(c, 256) * 255 >> 8`` (Blend2D's mask times its global alpha).
    cw_positive : bool
        A contour running clockwise on screen (A > 0) accumulates a positive S (the
        library's axes are y up: FreeType).
    """

    name: str
    words: str
    source: str
    negative: Literal["abs", "not"] = "abs"
    evenodd: Literal["bit8", "fold"] = "fold"
    scale: Literal["clamp", "gray8", "times255"] = "clamp"
    cw_positive: bool = False

    def __repr__(self) -> str:
        return f"Quantisation({self.name!r})"

    def __reduce__(self) -> tuple[object, tuple[str]]:
        return quantisation_named, (self.name,)

    def level(self, k: int, fill_rule: str = "nonzero") -> int:
        """The 8-bit level of ``k = floor(256 S)`` under ``fill_rule`` (``nonzero`` or
        ``evenodd``): the library's integer steps, as Python integers (two's complement
        for ``&`` and ``~``, as C's on the library's ``long``).

        >>> FTGRAYS.level(-1), CELLS_ABS.level(-1), BLEND2D.level(1), CELLS_ABS_GRAY8.level(200)
        (0, 1, 0, 198)
        """
        k = int(k)
        if fill_rule == "evenodd":
            if self.evenodd == "bit8":  # FT_FILL_RULE with fill = 0x100, then (unsigned char)
                return (~k if k & 0x100 else k) & 0xFF
            c = (-k if k < 0 else k) if self.negative == "abs" else (~k if k < 0 else k)
            c &= 511
            c = 512 - c if c > 256 else c
        else:
            c = k if k >= 0 else (-k if self.negative == "abs" else ~k)
        if self.scale == "times255":
            return min(c, 256) * 255 >> 8
        c = min(c, 255)
        if self.scale == "gray8" and c != 255:
            return (255 * 255 * c) >> 16  # *p = ((c.v - v) * alpha + (v << 16)) >> 16, v = 0, alpha = 255 c
        return c

    def signed(self, clockwise: bool) -> int:
        """The sign of the area the library accumulates for a contour running clockwise on
        screen (``clockwise``: A > 0) or counter-clockwise."""
        return 1 if clockwise == self.cw_positive else -1


FTGRAYS = Quantisation(
    "ftgrays", "FreeType's: floor(256 S), ~k below zero, capped at 255 (y up)",
    "freetype src/smooth/ftgrays.c: FT_FILL_RULE in gray_sweep", negative="not", evenodd="bit8", cw_positive=True)
CELLS_ABS = Quantisation(
    "cells-abs", "floor(256 S), its absolute value, capped at 255 (Qt, AGG)",
    "qtbase src/gui/painting/qgrayraster.c: gray_hline; AGG agg_rasterizer_scanline_aa.h: calculate_alpha")
CELLS_ABS_GRAY8 = Quantisation(
    "cells-abs-gray8", "AGG's cover blended by pixfmt_gray8 over black: floor(65025 c / 65536) (aggdraw)",
    "aggdraw agg2/include/agg_rasterizer_scanline_aa.h: calculate_alpha; agg2/include/agg_pixfmt_gray8.h: blend_hline",
    scale="gray8")
BLEND2D = Quantisation(
    "blend2d", "Blend2D's: min(|floor(256 S)|, 256) * 255 >> 8",
    "blend2d blend2d/pipeline/reference/fillgeneric_p.h: FillAnalytic_Base::calc_mask", scale="times255")

QUANTISATIONS: dict[str, Quantisation] = {q.name: q for q in (FTGRAYS, CELLS_ABS, CELLS_ABS_GRAY8, BLEND2D)}
# what Convention.quantisation may say
QUANTISATION_NAMES: tuple[str, ...] = (NEAREST, *QUANTISATIONS)


def quantisation_named(name: str) -> Quantisation:
    """The quantisation called ``name``; a ValueError naming them otherwise (``nearest``
    is no object: the convention's own levels and tolerance)."""
    found = QUANTISATIONS.get(name)
    if found is None:
        raise ValueError(f"no quantisation is named {name!r}: {', '.join(QUANTISATIONS)}")
    return found
