"""tiny-skia through resvg (``resvg-py``): each primitive is written as a one-element SVG
document, rendered by resvg (whose raster back end is tiny-skia, a Rust port of skia's
raster pipeline) to PNG bytes, and decoded with Pillow (resvg-py 0.5 returns PNG bytes
only: ``svg_to_bytes``; 0.2 ms per call for a small box, the decoding 0.03 ms).

Two modes: :class:`TinySkia` (``tiny_skia``, ``shape-rendering="crispEdges"``: anti-aliasing
off; triangles, paths under both fill rules, lines) and :class:`TinySkiaAntialiased`
(``tiny_skia_aa``, resvg's default ``geometricPrecision``: triangles).

The mapping: the document is ``<svg width="w" height="h" viewBox="0 0 w h">`` for a w x h
box, so one user unit is one pixel and resvg's transform is the identity; SVG's pixel
(i, j) is the square [i, i+1) x [j, j+1), y down, as ours, so coordinates pass unchanged.
They are written with ``repr()`` (the shortest decimal that reads back as the same
float64); resvg parses path data as f64 (``svgtypes``) and usvg/tiny-skia keep path points
as f32: tiny-skia receives each coordinate rounded to float32 (:meth:`received`).

Non-finite input: SVG text cannot carry it. ``repr`` writes ``nan``/``inf``, which
``svgtypes`` rejects; per SVG's error handling the path is rendered up to the error, so a
triangle with a NaN or infinite coordinate draws nothing (nor does one whose coordinate
overflows float32). Coordinates beyond 2**20 are refused before (``finite_within_limit``)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import AnyScene
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need

__all__ = ["TinySkia", "TinySkiaAntialiased"]


def _contour_data(contour: NDArray) -> str:
    """SVG path data of one closed polygon contour: ``M x y L x y ... Z`` (repr decimals)."""
    coordinates = [repr(v) for v in contour.ravel().tolist()]
    if not coordinates:
        return ""
    return f"M {coordinates[0]} {coordinates[1]} L {' '.join(coordinates[2:])} Z" if len(coordinates) > 2 \
        else f"M {coordinates[0]} {coordinates[1]} Z"


class _Resvg:
    """resvg-py and Pillow: an SVG element rendered into a w x h box, its alpha read back."""

    def __init__(self) -> None:
        self.resvg: Any = need("resvg_py")
        need("PIL")
        from PIL import Image

        self._image: Any = Image
        self.version = f"resvg {self.resvg.__resvg_version__} (resvg-py {self.resvg.__version__})"

    def alpha(self, element: str, w: int, h: int) -> NDArray[np.uint8]:
        """The (h, w) alpha bytes of ``element`` rendered alone on a transparent w x h canvas."""
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">'
               f"{element}</svg>")
        png = self.resvg.svg_to_bytes(svg_string=svg, skip_system_fonts=True)
        with self._image.open(io.BytesIO(png)) as image:
            rgba = np.asarray(image.convert("RGBA"))
        if rgba.shape[:2] != (h, w):
            raise RuntimeError(f"resvg rendered {rgba.shape[1]} x {rgba.shape[0]} px, not {w} x {h}")
        alpha: NDArray[np.uint8] = rgba[:, :, 3]
        return alpha

    def fill(self, contours: list[NDArray], w: int, h: int, crisp: bool, fill_rule: str = "nonzero") -> NDArray[np.uint8]:
        """Closed contours filled as one black ``<path>`` under the fill rule: alpha bytes."""
        data = " ".join(_contour_data(c) for c in contours if c.shape[0])
        rendering = ' shape-rendering="crispEdges"' if crisp else ""
        return self.alpha(f'<path d="{data}" fill="#000" fill-rule="{fill_rule}"{rendering}/>', w, h)


def _float32(scene: AnyScene) -> AnyScene:
    """The scene as tiny-skia receives it: each coordinate rounded to float32."""
    with np.errstate(invalid="ignore", over="ignore"):
        window = scene.coordinates.astype(np.float32).astype(np.float64)
    return scene.with_coordinates(window)


class TinySkia(OneAtATime):
    """tiny-skia (through resvg) with anti-aliasing off (``shape-rendering="crispEdges"``);
    the mapping is the identity (module docstring), proved by ``test_the_mapping_is_exact``
    (tests/rasterizers/real/test_tiny_skia.py: integer-plus-1/4 triangles, the exact set of
    pixels of the oracle). Input: float32 (:meth:`received`).

    Triangles and paths: one ``<path>`` per primitive, every contour of a path in it
    (``M``, ``L``..., ``Z`` each), ``fill-rule="nonzero"`` or ``"evenodd"``: both rules are
    tiny-skia's own. What tiny-skia does (``scan/path.rs``, ``edge.rs``, ported from skia's
    ``SkScan_Path.cpp``): each f32 end point is scaled by 64 and cast to i32
    (``(p.x * 64.0) as i32``: truncation toward zero, 26.6 fixed point), an edge covers the
    rows whose centre it spans (rounded 26.6 ends), its x stepped in 16.16 per row, spans
    from the rounded crossings: centre samples. Issue 32's measurement: the same pixels as
    skia's (:class:`~rasterizers.real.adapters.SkiaPath`: ``compare`` found 0 px
    different), 732 px residual against its best-fitting convention (the 16.16 stepping).
    No declared convention: ``identify`` fingerprints it.

    Lines: a ``<path d="M a L b">`` stroked black ``line_width`` px wide, SVG's default
    butt caps, no fill, one call per segment, any width. resvg has no hairlines: SVG's
    ``stroke-width="0"`` means no stroke (usvg drops it), and tiny-skia draws a stroke as
    a hairline only when its width is 0 or, anti-aliased, when it is at most 1 px
    (``treat_as_hairline`` in ``painter.rs``); crisp, a 1-px stroke is outlined by the
    stroker (the rectangle of that width around the segment, no caps) and filled as a path
    -- ``LineRule("rectangle")`` under the fill's rules, as cairo 1.16's strokes."""

    name = "tiny_skia"
    library = "tiny-skia (resvg)"
    line_widths = None  # any width: a stroke is outlined and filled

    def __init__(self) -> None:
        self._resvg = _Resvg()
        self.library_version = self._resvg.version

    def received(self, scene: AnyScene) -> AnyScene:
        """The scene as tiny-skia receives it: each coordinate rounded to float32 (usvg's and
        tiny-skia's path points are f32)."""
        return _float32(scene)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._resvg.fill([p], w, h, crisp=True) > 0

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        return self._resvg.fill(contours, w, h, crisp=True, fill_rule=fill_rule) > 0

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        ax, ay, bx, by = (repr(v) for v in (float(a[0]), float(a[1]), float(b[0]), float(b[1])))
        element = (f'<path d="M {ax} {ay} L {bx} {by}" fill="none" stroke="#000" stroke-width="{line_width!r}" '
                   'shape-rendering="crispEdges"/>')
        return self._resvg.alpha(element, w, h) > 0


class TinySkiaAntialiased(AlphaOneTriangleAtATime):
    """tiny-skia (through resvg) anti-aliased (resvg's default ``shape-rendering``,
    ``geometricPrecision``), one triangle per document; the mapping is the identity (module
    docstring), proved by ``test_the_antialiased_mapping_is_exact``
    (tests/rasterizers/real/test_tiny_skia.py). Alpha is the PNG's alpha byte / 255.
    Triangles only (exact area coverage of paths and lines is issue 34). Input: float32
    (:meth:`received`).

    What tiny-skia does (``scan/path_aa.rs``, skia's ``SkScan_AntiPath.cpp`` supersampler;
    tiny-skia has no analytic AA): ``SUPERSAMPLE_SHIFT`` 2, each pixel sampled on 4
    sub-scanlines with x in 1/4 px, the coverage accumulated to 8 bits -- a 4 x 4
    supersampler where skia-python's is 16 x 4. Issue 32's measurement: max |alpha - area|
    0.24 (thin slivers). No declared convention: ``identify`` fingerprints it."""

    name = "tiny_skia_aa"
    library = "tiny-skia (resvg)"

    def __init__(self) -> None:
        self._resvg = _Resvg()
        self.library_version = self._resvg.version

    def received(self, scene: AnyScene) -> AnyScene:
        """The scene as tiny-skia receives it: each coordinate rounded to float32."""
        return _float32(scene)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._resvg.fill([p], w, h, crisp=False) / 255.0
