"""FreeType's two outline rasterizers driven directly (freetype-py, ``freetype.raw``): the
monochrome one (``src/raster/ftraster.c``, "raster") with dropout control off
(:class:`FreeTypeMono`) and on (:class:`FreeTypeMonoDropout`), and the anti-aliasing one
(``src/smooth/ftgrays.c``, "smooth": :class:`FreeTypeSmooth`).

Each primitive becomes an ``FT_Outline`` of straight segments only (every point tagged
``FT_CURVE_TAG_ON``, one contour per closed polygon contour), rendered with
``FT_Outline_Get_Bitmap`` into an ``FT_Bitmap`` the adapter owns (a numpy buffer):
for an ``FT_PIXEL_MODE_MONO`` bitmap it asks ``FT_Outline_Render`` for a plain render,
which the monochrome rasterizer takes, for ``FT_PIXEL_MODE_GRAY`` (256 levels) one with
``FT_RASTER_FLAG_AA``, which the smooth one takes (the monochrome one refuses it).

The coordinate mapping, exact for every finite coordinate within the harness's limit:
FreeType's outline coordinates are 26.6 fixed point (``FT_Pos``, 1/64 px) with y up, and
bitmap row 0 the top row for a positive pitch, so its pixel (i, r) is the square
x in [i, i+1), y_ft in [rows - r - 1, rows - r). Our point (x, y) of a box of ``rows`` rows
is therefore sent as ``(round(64 x), 64 rows - round(64 y))``: y flipped about the box's
top edge, the rounding to nearest with halves to even (``np.rint``; the flip and the
box's whole-pixel origin are multiples of 64, so the rounding is the same where the
screen's coordinates are). :meth:`received` mirrors it exactly (every coordinate rounded
to 1/64 px, halves to even), so identify and the checks judge what FreeType was given.
"""

from __future__ import annotations

import ctypes
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need, refuse_kind

__all__ = ["FreeTypeMono", "FreeTypeMonoDropout", "FreeTypeSmooth", "to_26_6", "received_26_6"]

_PIXEL_MODE_MONO = 1  # FT_PIXEL_MODE_MONO
_PIXEL_MODE_GRAY = 2  # FT_PIXEL_MODE_GRAY
# FT_Outline's n_points, n_contours and contour ends are C shorts in FreeType 2.13
# (include/freetype/ftimage.h; FT_OUTLINE_POINTS_MAX is SHRT_MAX)
MAX_POINTS = 32767
# FT_Outline_Render (src/base/ftoutln.c) refuses an outline whose control box reaches beyond
# +/-0x1000000 in 26.6 (+/-262,144 px) with Invalid_Outline
MAX_26_6 = 0x1000000
_ERRORS = {0x14: "Invalid_Outline", 0x62: "Raster_Overflow", 0x06: "Invalid_Argument", 0x13: "Cannot_Render_Glyph"}
# the standalone repro of the monochrome rasterizer's overflow on deeply wound outlines
OVERFLOW_REPRO = "rasterizers/real/upstream/freetype_mono_raster_overflow.py"


def to_26_6(x: NDArray[np.float64]) -> NDArray[np.int64]:
    """Pixels to 26.6 fixed point: round(64 x), halves to even (``np.rint``, exact: 64 x
    is exact in float64 for |x| < 2**1017).

    >>> to_26_6(np.array([0.25, 1 / 128, 3 / 128, -1 / 128, 2.0])).tolist()
    [16, 0, 2, 0, 128]
    """
    fixed: NDArray[np.int64] = np.rint(x * 64.0).astype(np.int64)
    return fixed


def received_26_6(scene: AnyScene) -> AnyScene:
    """The scene as FreeType receives it: every finite coordinate rounded to a multiple of
    1/64 px, halves to even (:func:`to_26_6`); non-finite ones unchanged (such a primitive
    is never sent: it covers nothing)."""
    coordinates = scene.coordinates
    with np.errstate(invalid="ignore", over="ignore"):
        rounded = np.where(np.isfinite(coordinates), np.rint(coordinates * 64.0) / 64.0, coordinates)
    return scene.with_coordinates(rounded)


class _Outline:
    """Renders closed polygon contours with FreeType into a bitmap the caller's box
    (``FT_Outline_Get_Bitmap``), one call per primitive."""

    def __init__(self, pixel_mode: int, flags: int) -> None:
        freetype = need("freetype")
        from freetype import raw
        from freetype.ft_structs import FT_Bitmap, FT_Outline, FT_Vector

        self.freetype: Any = freetype
        self.raw: Any = raw
        self.Bitmap: Any = FT_Bitmap
        self.Outline: Any = FT_Outline
        self.Vector: Any = FT_Vector
        self.library: Any = freetype.get_handle()
        self.pixel_mode = pixel_mode
        self.flags = flags
        major, minor, patch = freetype.version()
        self.version = f"{major}.{minor}.{patch}"

    def render(self, contours: list[NDArray[np.float64]], w: int, h: int) -> NDArray[np.uint8]:
        """The (h, w) bitmap FreeType draws for these contours (coordinates relative to the
        box, y down): 0/1 per pixel in mono mode, 0..255 in gray mode. A contour with a NaN
        or infinite coordinate has no 26.6 value: then nothing is sent and nothing drawn."""
        kept = [c for c in contours if c.shape[0] > 0]  # an empty contour encloses nothing (FT_Outline has none)
        out = np.zeros((h, w), dtype=np.uint8)
        if not kept or w <= 0 or h <= 0:
            return out
        points = np.concatenate(kept)
        if not np.isfinite(points).all():
            return out
        n = points.shape[0]
        if n > MAX_POINTS or len(kept) > MAX_POINTS:
            raise ValueError(f"FreeType {self.version}: an FT_Outline holds at most {MAX_POINTS} points and contours "
                             f"(C shorts), not {n} points in {len(kept)} contours")
        fixed = np.empty((n, 2), dtype=np.int64)  # FT_Vector: two FT_Pos (C long, 64 bits here)
        fixed[:, 0] = to_26_6(points[:, 0])
        fixed[:, 1] = 64 * h - to_26_6(points[:, 1])  # y up, about the box's top edge
        if np.abs(fixed).max() > MAX_26_6:
            raise ValueError(f"FreeType {self.version}: FT_Outline_Render refuses outlines reaching beyond +/-{MAX_26_6:#x} "
                             f"in 26.6 (+/-{MAX_26_6 // 64:,} px from the bitmap's corner) with Invalid_Outline; this one "
                             f"reaches {np.abs(fixed).max() / 64:g} px")
        vectors = (self.Vector * n).from_buffer(fixed)
        tags = (ctypes.c_ubyte * n).from_buffer(np.ones(n, dtype=np.uint8))  # FT_CURVE_TAG_ON: straight segments
        ends = np.cumsum([c.shape[0] for c in kept]) - 1
        contour_ends = (ctypes.c_short * len(kept))(*ends.tolist())
        outline = self.Outline(len(kept), n, vectors, tags, contour_ends, self.flags)
        if self.pixel_mode == _PIXEL_MODE_MONO:
            pitch = ((w + 15) // 16) * 2  # one bit per pixel, most significant first; an even pitch as FreeType's own
        else:
            pitch = (w + 3) & ~3
        buffer = np.zeros((h, pitch), dtype=np.uint8)
        bitmap = self.Bitmap(h, w, pitch, buffer.ctypes.data_as(ctypes.POINTER(ctypes.c_ubyte)), 256,
                             self.pixel_mode, b"\0", None)
        error = self.raw.FT_Outline_Get_Bitmap(self.library, ctypes.byref(outline), ctypes.byref(bitmap))
        if error == 0x62 and self.pixel_mode == _PIXEL_MODE_MONO:
            raise RuntimeError(f"FreeType {self.version}: the monochrome rasterizer failed with Raster_Overflow (0x62) "
                               f"on a valid outline ({n} points, {len(kept)} contours, {w} x {h} bitmap): its fixed "
                               f"render pool cannot hold one scanline's profiles. Repro: {OVERFLOW_REPRO}")
        if error:
            raise RuntimeError(f"FreeType {self.version}: FT_Outline_Get_Bitmap failed with error {error:#x} "
                               f"({_ERRORS.get(error, 'see fterrdef.h')}: "
                               f"{n} points, {len(kept)} contours, {w} x {h} bitmap)")
        if self.pixel_mode == _PIXEL_MODE_MONO:
            mono: NDArray[np.uint8] = np.unpackbits(buffer, axis=1)[:, :w]
            return mono
        return buffer[:, :w].copy()


class _FreeTypeMonoBase(OneAtATime):
    """Shared by both monochrome modes: see :class:`FreeTypeMono`."""

    library = "FreeType"
    scene_kinds = ("triangles", "paths")
    fill_rules = ("nonzero",)
    line_widths = None
    FLAGS = 0

    def __init__(self) -> None:
        self._outline = _Outline(_PIXEL_MODE_MONO, self.FLAGS)
        self.library_version = self._outline.version

    # as FreeType receives the scene: every coordinate rounded to 1/64 px, halves to even
    # (26.6, :func:`to_26_6`; read by received_of)
    input = "fixed6"

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._outline.render([p], w, h) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return self._outline.render(contours, w, h) > 0

    def rasterize(self, scene: AnyScene) -> Coverage:
        if isinstance(scene, LineScene):  # FreeType's rasterizers fill outlines; its stroker is outside them
            refuse_kind(self.name, scene, self.scene_kinds)
        return super().rasterize(scene)


class FreeTypeMono(_FreeTypeMonoBase):
    """FreeType's monochrome rasterizer (``src/raster/ftraster.c``) with dropout control
    off (``FT_OUTLINE_IGNORE_DROPOUTS``): one bit per pixel, one ``FT_Outline`` per
    triangle or path (all its contours), rendered with ``FT_Outline_Get_Bitmap`` into a
    ``FT_PIXEL_MODE_MONO`` bitmap.

    Coordinates: see the module (:mod:`rasterizers.real.freetype_outline`): 26.6 fixed
    point rounded to nearest, halves to even, y flipped about the box's top edge; the
    library receives multiples of 1/64 px, and :meth:`received` mirrors that rounding
    exactly. The mapping (no half-pixel shift, no flip, no transposition) is proven by
    ``test_freetype_mono_maps_coordinates_exactly`` in
    ``tests/rasterizers/real/test_freetype_outline.py``: a triangle with vertices at
    integer-plus-0.25 draws exactly the pixels whose centres it contains.

    What the rasterizer does (ftraster.c, FreeType 2.13): coordinates are shifted by half
    a pixel (``SCALED``) so that pixel centres sit on its integer grid; a vertical sweep
    per scanline (pixel-centre row) pairs the k-th upward profile with the k-th downward
    one, sorted by x, and sets the pixels ``CEILING(x1) .. FLOOR(x2)``, both ends
    included; pairing the k-th up with the k-th down crossing covers exactly the points
    whose winding number is not zero, so the fill is the nonzero rule; a second,
    horizontal sweep (no ``FT_OUTLINE_SINGLE_PASS``) also sets the pixels whose centre
    lies exactly on a span end in x. So a sample exactly on an edge is drawn by both
    triangles sharing that edge: no tie rule.

    Fill rules: nonzero only. ``FT_OUTLINE_EVEN_ODD_FILL`` is ignored by this rasterizer
    (ftimage.h documents that flag as working with the smooth rasterizer only; ftraster.c
    never reads it): a pentagram's centre is filled with the flag set or not, so
    ``fill_rules = ("nonzero",)`` and even-odd path scenes are refused (Unsupported),
    not drawn nonzero under an even-odd name.

    Lines: none. FreeType's rasterizers fill outlines only; its stroker (``FT_Stroker``)
    turns a stroke into an outline with its own geometry, outside the rasterizer.

    Bad input: a triangle or path with a NaN or infinite coordinate has no 26.6 value, so
    it is not sent and covers nothing (the adapter's choice; FreeType cannot be handed
    such a coordinate). A path of more than 32,767 points cannot be one ``FT_Outline``
    (its counts are C shorts): ValueError naming the limit.

    Declared (issue 33): ``Convention(coverage="closed", input="fixed6",
    dropout="none-stepped6")``: the closed rule on 26.6 input, each edge's crossings
    stepped from its start as ``Line_Up`` steps them, the render pool's bands included
    (:mod:`harness.oracle.dropout`); identify's rule probes: exact, 0 of 918 pixels off
    (the closed rule with exact crossings: 8 off); the quick suite: conformance exact on
    every case, 504/510, the 6 failures FreeType's limits and its known overflow bug
    (below). Before it, identify's best guess was centre-ish samples (0.508, 0.508) with
    top-right ties, 2,899 pixels off of 143,710 (best guess only); it draws both windings, the
    nonzero rule exactly on its probes, samples on shared edges twice (3,715 double hits
    on its partitions), 17 pixels for zero-area triangles, nothing for non-finite ones.
    Its edge crossings are computed at 1/64 px by stepping along each edge from its
    start, so the rounding depends on the edge's direction: 361 of 2,000 random
    triangles on the 1/64 grid change a pixel when their winding is reversed, every such
    pixel centre within 1.5/64 px of an edge (the quick suite's invariance check sees
    it). Clipping does the same: a triangle crossing the viewport's edge is drawn into a
    bitmap that ends there (as a caller's would), its profiles start at the clip line,
    and 96 pixels of 1,000 random triangles crossing a 32 x 32 viewport differ from the
    same triangles drawn in a larger bitmap, all within 1.5/64 px of an edge. Known bug:
    ``Raster_Overflow`` on a valid contour winding about 120 times or
    more (the smooth rasterizer draws it): raised as RuntimeError naming
    :data:`OVERFLOW_REPRO`. Limit: ``FT_Outline_Render`` refuses outlines beyond
    +/-262,144 px (Invalid_Outline: ValueError naming the limit)."""

    name = "freetype_mono"
    FLAGS = 0x8  # FT_OUTLINE_IGNORE_DROPOUTS (include/freetype/ftimage.h)
    # issue 33: the closed rule on 26.6 input, crossings stepped as ftraster.c's Line_Up steps them
    # (harness.oracle.dropout); identify's rule probes: exact, 0 pixels off
    convention: Convention | None = Convention(coverage="closed", input="fixed6", dropout="none-stepped6")


class FreeTypeMonoDropout(_FreeTypeMonoBase):
    """FreeType's monochrome rasterizer with dropout control on, in the smart mode fonts
    use: ``FT_OUTLINE_SMART_DROPOUTS`` without ``FT_OUTLINE_INCLUDE_STUBS``, which ftraster.c
    runs as dropout mode 5 (TrueType's ``SCANTYPE`` 5: smart dropout control, stubs
    excluded). Everything else as :class:`FreeTypeMono` (coordinates, nonzero fill only,
    no lines, bad input); the same mapping probe covers this mode
    (``test_freetype_mono_maps_coordinates_exactly`` is parametrised over both).

    What dropout control adds (ftraster.c ``Draw_Sweep``): where a span between an up
    and a down crossing holds no pixel centre (``CEILING(x1) > FLOOR(x2)``: a feature
    thinner than a pixel between two centres), one pixel is set anyway, the one nearer
    the span's midpoint (``SMART``), unless its neighbour is already set; the same in
    the horizontal sweep per column. That is the documented TrueType scan-conversion
    rule 3 (a convention, not a bug): triangles whose area misses every pixel centre
    (slivers, even zero-area ones whose edges coincide) still draw pixels.

    Declared (issue 33): ``Convention(coverage="closed", input="fixed6",
    dropout="smart-no-stubs-stepped6")``, ftraster.c's scan conversion with SCANTYPE 5
    (:mod:`harness.oracle.dropout`): identify's rule probes exact, 0 of 1,005 pixels off
    (stubs included: 88 off; simple: 101; exact crossings: 5); the quick suite's
    conformance exact on every case, its failures FreeType's limits and overflow bug.

    Found before (FreeType 2.13.2): identify's best guess as for :class:`FreeTypeMono`, 4,103
    pixels off of 144,920 (best guess only; the dropout pixels are what no sample rule
    draws), 27 pixels for zero-area triangles; 289 of 2,000 random triangles change a
    pixel when reversed, dropout pixels up to 0.48 px from an edge among them (which of
    the two candidate pixels a dropout sets depends on the profiles' direction). At the
    bitmap's (the viewport's) edge, a dropout whose pixel would fall outside sets the
    pixel inside instead (ftraster.c: "undocumented but confirmed"): 175 pixels of 1,000
    random triangles crossing a 32 x 32 viewport differ from a larger bitmap's, 87 of
    them in its border rows and columns."""

    name = "freetype_mono_dropout"
    FLAGS = 0x10  # FT_OUTLINE_SMART_DROPOUTS (no FT_OUTLINE_INCLUDE_STUBS: stubs excluded)
    # issue 33: TrueType's smart dropout control, stubs excluded (SCANTYPE 5), as ftraster.c runs it
    convention: Convention | None = Convention(coverage="closed", input="fixed6", dropout="smart-no-stubs-stepped6")


class FreeTypeSmooth(AlphaOneTriangleAtATime):
    """FreeType's anti-aliasing rasterizer (``src/smooth/ftgrays.c``): one ``FT_Outline``
    per triangle rendered with ``FT_Outline_Get_Bitmap`` into an 8-bit
    ``FT_PIXEL_MODE_GRAY`` bitmap (256 levels); alpha = value / 255.

    Coordinates as :class:`FreeTypeMono` (the module's mapping: 26.6 fixed point rounded
    to nearest, halves to even, y flipped about the box's top edge; :meth:`received`
    mirrors the rounding). The mapping is proven by
    ``test_freetype_smooth_alphas_match_the_area`` in
    ``tests/rasterizers/real/test_freetype_outline.py``: a triangle with vertices at
    integer-plus-0.25 (multiples of 1/64: received exactly) gets every pixel's covered
    area within 1/64 + 1/255 (no shift, flip or transposition could keep that).

    What the rasterizer does: exact area coverage computed in cells of 1/256 px
    (``PIXEL_BITS`` 8: its input, 26.6, shifted up by two bits), accumulated per pixel and
    turned into 0..255. Triangles only: the harness's exact area oracle takes triangles
    (area coverage of paths and lines is issue 34). This rasterizer honours
    ``FT_OUTLINE_EVEN_ODD_FILL`` (measured: a pentagram's centre is empty with the flag,
    full without), so even-odd paths will be judgeable here once paths are.

    Bad input: a triangle with a NaN or infinite coordinate is not sent (no 26.6 value)
    and covers nothing; one beyond +/-262,144 px is refused as for :class:`FreeTypeMono`.

    Found (FreeType 2.13.2): identify says area coverage, analytic, 256 levels (alpha a
    multiple of 1/255), max |alpha - exact area| 0.0162 (mean 0.0016) over 274,241
    (triangle, pixel)s, zero-area triangles draw nothing; an edge swept across a pixel
    in 1/256 px steps takes 65 levels (the 26.6 input grid). Alphas change by a level
    on some pixels when a triangle's winding is reversed (the quick suite's invariance
    check)."""

    name = "freetype_smooth"
    library = "FreeType"
    scene_kinds = ("triangles",)

    def __init__(self) -> None:
        self._outline = _Outline(_PIXEL_MODE_GRAY, 0)
        self.library_version = self._outline.version

    # as FreeType receives the scene: every coordinate rounded to 1/64 px, halves to even
    # (26.6, :func:`to_26_6`; read by received_of)
    input = "fixed6"

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._outline.render([p], w, h) / 255.0
