"""matplotlib's Agg backend (``RendererAgg.draw_path``, AGG 2.4 as vendored by
matplotlib), aliased (``matplotlib_agg``) and anti-aliased (``matplotlib_agg_aa``).

What ``RendererAgg::draw_path`` does (``src/_backend_agg.h``, matplotlib 3.x): the
given transform is multiplied by AGG's y flip, ``trans *= scaling(1, -1); trans *=
translation(0, height)`` (matplotlib's display space has y up, AGG's buffer row 0 at the
top); non-finite vertices are removed (``PathNanRemover``); clipping to the figure and
simplification only apply to unfilled hatched paths; snapping follows the graphics
context (``set_snap(False)``: off); the path is added to a
``rasterizer_scanline_aa<rasterizer_sl_clip_dbl>``, clipped to the image in float64
and converted to 24.8 fixed point by ``iround(v * 256)`` (to nearest, half away from
zero); ``draw_path`` never calls ``filling_rule``, so every fill is nonzero (AGG's
default). Anti-aliased, each cell's cover (``floor(256 * area)``, 8 bits, capped at 255)
is blended as alpha; aliased (``gc.isaa`` false), the same scanlines are drawn by
``renderer_scanline_bin_solid``, which draws every cell the sweep keeps: every pixel
whose cover is nonzero. The cover is the signed area shifted right, then made positive
(``calculate_alpha``), so it is ``floor(256 * area)`` for a triangle counter-clockwise
on screen (y down) and ``ceil(256 * area)`` for a clockwise one: aliased, a clockwise
triangle draws every pixel it touches at all, a counter-clockwise one those at least
1/256 covered (the vertex order changes the pixels: a bug, repro
``rasterizers/real/upstream/matplotlib_agg_orientation.py``). The area is that of AGG's
cell polygon (each edge split at the pixel rows and columns, the crossings rounded down to
1/256 px), not quite the triangle's: the coverage rule ``agg-cover`` with a threshold of
1/256 (cover >= 1), :data:`FOUND`, is exact (:mod:`harness.oracle.library_rules`).

The mapping: vertices are passed unchanged with the transform ``scale(1, -1)`` then
``translate(0, h)``; composed with draw_path's own flip the matrix is the identity
exactly (``ty = -h + h = 0``, ``sy = (-1)(-1)``), so AGG receives our float64
coordinates unchanged, y down, AGG's pixel (i, j) being our [i, i+1) x [j, j+1) and
buffer row 0 the top row.
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

__all__ = ["MatplotlibAgg", "MatplotlibAggAntialiased", "FOUND"]

# The aliased mode's rule, found from outside and read in the source (issue 33): every
# nonzero AGG 8-bit cell cover on 24.8 input rounded half away (``iround``). Not the declared
# ``convention``: a coverage rule is defined for triangles, and the adapter draws paths and lines too.
FOUND = Convention(coverage="agg-cover", input="fixed8-half-away", threshold=2.0**-8)


class _Renderer:
    """matplotlib's Agg renderer, imported once: a fill of closed contours or a stroke of
    a segment into a cleared w x h RGBA buffer, read back as the (h, w) alpha channel.
    Renderers (one per size), graphics contexts and transforms are made once and reused
    (the gc's settings are read afresh by every ``draw_path``)."""

    def __init__(self) -> None:
        self.matplotlib = need("matplotlib")
        from matplotlib.backends.backend_agg import RendererAgg
        from matplotlib.path import Path
        from matplotlib.transforms import Affine2D

        self._renderer: Any = RendererAgg
        self._path: Any = Path
        self._affine: Any = Affine2D
        self.version = f"matplotlib {self.matplotlib.__version__}"
        self._renderers: dict[tuple[int, int], Any] = {}
        self._contexts: dict[tuple[bool, float], Any] = {}
        self._flips: dict[int, Any] = {}

    def _begin(self, w: int, h: int, antialias: bool, linewidth: float) -> tuple[Any, Any, Any]:
        """A cleared w x h renderer (one per size, reused: ``clear`` costs 1/100 of making
        one), its graphics context and the transform that cancels draw_path's y flip."""
        renderer = self._renderers.get((w, h))
        if renderer is None:
            if len(self._renderers) >= 256:
                self._renderers.clear()
            renderer = self._renderers[w, h] = self._renderer(w, h, 72)  # 72 dpi: 1 pt = 1 px
        else:
            renderer.clear()  # to (1, 1, 1, 0): alpha 0
        gc = self._contexts.get((antialias, linewidth))
        if gc is None:
            gc = self._contexts[antialias, linewidth] = renderer.new_gc()
            gc.set_antialiased(antialias)
            gc.set_snap(False)
            gc.set_linewidth(linewidth)
            gc.set_capstyle("butt")
            gc.set_foreground((0.0, 0.0, 0.0, 1.0))
        transform = self._flips.get(h)
        if transform is None:
            # with draw_path's own flip (scale(1, -1), translate(0, h)) the identity, exactly
            transform = self._flips[h] = self._affine().scale(1.0, -1.0).translate(0.0, float(h))
        return renderer, gc, transform

    @staticmethod
    def _alpha(renderer: Any) -> NDArray:
        return np.asarray(renderer.buffer_rgba())[..., 3].copy()

    def fill(self, contours: list[NDArray], w: int, h: int, antialias: bool) -> NDArray:
        """The contours filled (one path, matplotlib's fill rule: nonzero) in black, no
        stroke: the (h, w) uint8 alpha."""
        renderer, gc, transform = self._begin(w, h, antialias, 0.0)
        Path = self._path
        vertices, codes = [], []
        for contour in contours:
            if contour.shape[0] == 0:
                continue
            vertices.append(contour)
            vertices.append(contour[:1])  # CLOSEPOLY's vertex (ignored)
            codes.append(np.concatenate([[Path.MOVETO], np.full(contour.shape[0] - 1, Path.LINETO), [Path.CLOSEPOLY]]))
        if vertices:
            path = Path(np.concatenate(vertices), np.concatenate(codes).astype(Path.code_type))
            path.should_simplify = False
            renderer.draw_path(gc, path, transform, (0.0, 0.0, 0.0, 1.0))
        return self._alpha(renderer)

    def stroke(self, a: NDArray, b: NDArray, w: int, h: int, antialias: bool, width: float) -> NDArray:
        """The segment a -> b stroked ``width`` pt (= px at 72 dpi) wide, butt caps: the
        (h, w) uint8 alpha."""
        renderer, gc, transform = self._begin(w, h, antialias, width)
        path = self._path(np.array([a, b], dtype=np.float64))
        path.should_simplify = False
        renderer.draw_path(gc, path, transform, None)
        return self._alpha(renderer)


def _received(scene: AnyScene) -> AnyScene:
    """The scene as AGG 2.4's rasterizer receives it: each coordinate to 24.8 fixed point,
    ``iround(v * 256)``: to nearest, half away from zero. The adapters hand the library
    coordinates relative to a whole-pixel box origin, which moves no rounding boundary."""
    with np.errstate(invalid="ignore", over="ignore"):
        v = scene.coordinates * 256.0
        snapped = np.where(v < 0, np.ceil(v - 0.5), np.floor(v + 0.5)) / 256.0
    return scene.with_coordinates(snapped)


class MatplotlibAgg(OneAtATime):
    """matplotlib's ``RendererAgg.draw_path`` with ``antialiased=False`` and snapping
    off, at 72 dpi: a pixel is drawn iff any of it is covered (any area for a triangle
    clockwise on screen, at least 1/256 of the pixel for a counter-clockwise one; module
    docstring). Coordinates pass unchanged (the module docstring shows the transform
    that cancels matplotlib's y flip exactly); the probe
    ``test_matplotlib_agg_pixels_of_a_quarter_offset_triangle`` compares an asymmetric
    triangle with vertices at whole + 0.25 px with the pixels it touches (no half-pixel
    shift, no flip, no transposition).

    Each triangle and each path is one ``matplotlib.path.Path`` (MOVETO, LINETO...,
    CLOSEPOLY per contour; ``should_simplify`` off), float64, which AGG rounds to 24.8
    fixed point, nearest, half away from zero (:meth:`received`); filled black with no
    stroke (line width 0) into a fresh RGBA buffer around its box, read back as alpha.

    Paths: nonzero only. ``draw_path`` never sets AGG's filling rule, so a path is filled
    nonzero whatever one wants (matplotlib's even-odd-looking results come from
    contours of opposite orientation): ``fill_rules = ("nonzero",)``.

    Lines: one path of the two end points per segment stroked with ``linewidth`` w pt
    (w px at 72 dpi), butt caps (``conv_stroke``: the w x length rectangle around it),
    drawn by the same any-coverage rule, any width (``line_widths = None``; without
    dashes ``draw_path`` strokes the width as given, aliased too); a zero-length segment
    draws nothing.

    Found (issue 33): triangles follow the coverage rule ``agg-cover`` exactly,
    :data:`FOUND` (every nonzero AGG cell cover, 24.8 input rounded half away):
    ``python -m harness.identify.rule_probes rasterizers.real.matplotlib_agg:MatplotlibAgg``
    says exact, 0 of 2,064 pixels off (the best area threshold, 0.00085 on a 1/16 grid, 26
    off: clockwise and counter-clockwise triangles disagree on any plain threshold), and 0
    of 14,083 on 400 further triangles. Not declared as ``convention`` (paths and lines
    have no rule yet); triangles crossing the screen's edge may differ (AGG clips in
    float64 and rounds the new vertices, which the rule does not model). Before
    (matplotlib 3.11.2, no declared convention): best guess only, sample (0, 0.5), top-left ties (y first), 5
    sub-pixel bits, 39,902 of 180,834 pixels off (every pixel a triangle touches is drawn,
    so shared edges are drawn twice: watertight fails with 0 holes and 20,716 double
    hits on 24 partitions); paths the same as triangles, under nonzero; lines best guess
    rectangular, sample (0.5, 0), 2 bits, 15,637 of 26,685 pixels off (width 3: 508 of
    1,237); 9 of 190,725 on-screen pixels change when a triangle crosses the screen's
    edge (AGG clips in float64, then rounds the new vertices to 24.8).

    Bad input: matplotlib removes non-finite vertices before AGG sees them
    (``PathNanRemover``), so a NaN or infinite triangle keeps its two finite vertices,
    which enclose nothing: nothing drawn, at once (tested)."""

    name = "matplotlib_agg"
    library = "AGG (matplotlib)"
    fill_rules = ("nonzero",)
    line_widths = None  # a stroke is the rectangle of any width

    def __init__(self) -> None:
        self._mpl = _Renderer()
        self.library_version = self._mpl.version

    input = "fixed8-half-away"  # 24.8 by iround(c * 256), as :func:`_received` says (read by received_of)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._mpl.fill([p], w, h, False) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return self._mpl.fill(contours, w, h, False) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._mpl.stroke(a, b, w, h, False, line_width) > 0


class MatplotlibAggAntialiased(AlphaPaths, AlphaLines, AlphaOneTriangleAtATime):
    """matplotlib's ``RendererAgg.draw_path`` with ``antialiased=True``, snapping off, one
    triangle, path or segment at a time, drawn as for :class:`MatplotlibAgg` (coordinates
    unchanged, float64, rounded by AGG to 24.8 fixed point, nearest, half away); probe
    ``test_matplotlib_agg_aa_alphas_of_a_quarter_offset_triangle``. Alpha is the RGBA
    buffer's alpha / 255: AGG's cover ``floor(256 * area)``, capped at 255, blended over
    a transparent buffer (``pixfmt_rgba32_plain``). No declared convention.

    Paths: each path one ``matplotlib.path.Path`` of all its contours filled once;
    nonzero only, as :class:`MatplotlibAgg` (``RendererAgg::_draw_path`` in
    ``src/_backend_agg.h`` never calls ``filling_rule``: AGG's default ``fill_non_zero``),
    so ``fill_rules = ("nonzero",)``. AGG applies the rule to each cell's summed signed
    area (capped at 255), not to the area where the winding is nonzero: a pixel half
    covered by a doubly wound region gets alpha 1 where the exact area is 1/2.

    Lines: each segment a two-point path stroked ``linewidth`` px wide (72 dpi) with butt
    caps (``conv_stroke`` in ``_draw_path``: anti-aliased, the width as given), judged
    against the exact rectangle (:mod:`harness.oracle.area_lines`).

    Identified (matplotlib 3.11.2): area coverage, analytic, 256 levels, max |alpha - area|
    0.0111 (mean 0.00173) on identify's scenes, 0.0118 on the quick suite's; NaN and
    infinite vertices are removed (nothing drawn). Found on the quick suite's path cases
    (issue 34): where each pixel sees one winding, within 0.0117 of the exact area; with
    overlapping contours up to 0.966 off (the summed area); reversed contours change no
    alpha by more than a level; the inside of a contour wound 65,536 times is filled
    with alpha 0 (the summed cover overflows; winding 256 still fills it)."""

    name = "matplotlib_agg_aa"
    library = "AGG (matplotlib)"
    convention = None
    fill_rules = ("nonzero",)  # draw_path never sets AGG's filling rule: fill_non_zero (class docstring)

    def __init__(self) -> None:
        self._mpl = _Renderer()
        self.library_version = self._mpl.version

    input = "fixed8-half-away"  # 24.8 by iround(c * 256), as :func:`_received` says (read by received_of)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._mpl.fill([p], w, h, True) / 255.0

    def _fill_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._mpl.fill(contours, w, h, True) / 255.0

    def _draw_stroke(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._mpl.stroke(a, b, w, h, True, line_width) / 255.0
