"""tiny-skia through resvg (``resvg-py``): primitives are written as SVG ``<path>``
elements, rendered by resvg (whose raster back end is tiny-skia, a Rust port of skia's
raster pipeline) to PNG bytes, and decoded with Pillow (resvg-py 0.5 returns PNG bytes
only, ``svg_to_bytes``: about 0.15 ms a call plus 0.07 us a pixel, encoding and decoding).

Two modes: :class:`TinySkia` (``tiny_skia``, ``shape-rendering="crispEdges"``: anti-aliasing
off; triangles, paths under both fill rules, lines) and :class:`TinySkiaAntialiased`
(``tiny_skia_aa``, resvg's default ``geometricPrecision``: triangles, paths under both fill
rules, lines).

One primitive per ``<path>``, each drawn alone as far as its pixels go: every primitive
has the box :func:`~rasterizers.real._masks.draw_each` gives it (its bounding box and 2 px,
clipped to the screen), and primitives whose boxes do not overlap share one document
(:func:`pack`), its canvas the union of their boxes, each box's pixels read back as its
primitive's; crisp documents stack three such sets, one per colour channel
(:func:`stack`). A fill or stroke draws nothing outside its box, so each pixel of a box
holds its own primitive's coverage alone. A primitive whose box reaches the screen's
edge (which may clip it: tiny-skia clips in float32, after the viewBox's translation) is
drawn alone on its box's canvas, as ``draw_each`` draws for every library
(``test_shared_documents_draw_as_the_whole_screen_does`` checks both). This makes one
resvg call per 2 to 10 primitives instead of one each.

The mapping: a document showing the screen's pixels [x0, x0 + w) x [y0, y0 + h) is
``<svg width="w" height="h" viewBox="x0 y0 w h">``: one user unit is one pixel, resvg's
transform a translation by whole pixels (exact in float32: x - x0 of a float32 x >= x0 is
a float32); SVG's pixel (i, j) is the square [i, i+1) x [j, j+1), y down, as ours, so the
screen's coordinates pass unchanged. They are written with ``repr()`` (the shortest
decimal that reads back as the same float64); resvg parses path data as f64
(``svgtypes``) and usvg/tiny-skia keep path points as f32: tiny-skia receives each screen
coordinate rounded to float32 (:meth:`TinySkia.received`).

Non-finite input: SVG text cannot carry it. ``repr`` writes ``nan``/``inf``, which
``svgtypes`` rejects; per SVG's error handling the path is rendered up to the error, so a
triangle with a NaN or infinite coordinate draws nothing (nor does one whose coordinate
overflows float32), and a path draws its contours before the bad number. Coordinates
beyond 2**20 are refused before (``finite_within_limit``)."""

from __future__ import annotations

import io
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene, Unsupported
from rasterizers.real._aa_paths import AlphaPaths, draw_each_path_alpha
from rasterizers.real._bases import AlphaOneTriangleAtATime, OneAtATime, need, refuse_kind
from rasterizers.real._masks import (
    _boxes,
    draw_each,
    draw_each_alpha,
    draw_each_path,
    draw_each_segment,
    path_boxes,
    segment_boxes,
)

__all__ = ["TinySkia", "TinySkiaAntialiased"]


MARGIN = 2  # px around each primitive's box: draw_each's, so the boxes are the same
# a document's canvas may exceed this many pixels only if its boxes fill half of it
# (measured, resvg-py 0.5: 0.15 ms a call plus 0.07 us a pixel, encoding and decoding)
CANVAS = 64 * 64
LAYER = 64  # primitives in one document at most
OPEN = 8  # documents still open to a primitive (the last ones)


def _number(v: float) -> str:
    """A coordinate as SVG text: ``repr`` (the shortest decimal reading back as the same
    float64; ``nan``/``inf`` for non-finite ones, which SVG's number syntax rejects)."""
    return repr(float(v))


def _contour_data(contour: NDArray) -> str:
    """SVG path data of one closed polygon contour: ``M x y L x y ... Z``."""
    coordinates = [_number(v) for v in contour.ravel().tolist()]
    if not coordinates:
        return ""
    return f"M {coordinates[0]} {coordinates[1]} L {' '.join(coordinates[2:])} Z" if len(coordinates) > 2 \
        else f"M {coordinates[0]} {coordinates[1]} Z"


def pack(boxes: list[tuple[int, int, int, int]]) -> list[list[int]]:
    """Documents of primitives whose boxes (x0, y0, x1, y1) do not overlap, in order: each
    box goes into the first of the last :data:`OPEN` documents it overlaps no box of,
    holding fewer than :data:`LAYER`, whose canvas (the union of its boxes) stays within
    :data:`CANVAS` pixels or twice their area; else into a new one.

    >>> pack([(0, 0, 4, 4), (2, 2, 6, 6), (5, 0, 9, 4), (0, 5, 4, 9)])
    [[0, 2, 3], [1]]
    """
    layers: list[list[int]] = []
    members: list[list[tuple[int, int, int, int]]] = []
    unions: list[tuple[int, int, int, int]] = []
    areas: list[int] = []
    for i, box in enumerate(boxes):
        x0, y0, x1, y1 = box
        area = (x1 - x0) * (y1 - y0)
        for j in range(max(0, len(layers) - OPEN), len(layers)):
            if len(layers[j]) >= LAYER:
                continue
            u0, v0, u1, v1 = unions[j]
            ux0, uy0, ux1, uy1 = min(u0, x0), min(v0, y0), max(u1, x1), max(v1, y1)
            if (ux1 - ux0) * (uy1 - uy0) > max(CANVAS, 2 * (areas[j] + area)):
                continue
            if u0 < x1 and x0 < u1 and v0 < y1 and y0 < v1 and any(
                    b0 < x1 and x0 < b1 and c0 < y1 and y0 < c1 for b0, c0, b1, c1 in members[j]):
                continue
            layers[j].append(i)
            members[j].append(box)
            unions[j] = (ux0, uy0, ux1, uy1)
            areas[j] += area
            break
        else:
            layers.append([i])
            members.append([box])
            unions.append(box)
            areas.append(area)
    return layers


def stack(layers: list[list[int]], boxes: list[tuple[int, int, int, int]]) -> list[list[list[int]]]:
    """Documents of up to three consecutive :func:`pack` layers (one per colour channel),
    as long as the document's canvas (the union of their boxes) stays within
    :data:`CANVAS` pixels or twice their area.

    >>> stack([[0], [1], [2], [3]], [(0, 0, 4, 4), (2, 2, 6, 6), (1, 1, 5, 5), (0, 0, 3, 3)])
    [[[0], [1], [2]], [[3]]]
    """
    documents: list[list[list[int]]] = []
    unions: list[tuple[int, int, int, int]] = []
    areas: list[int] = []
    for layer in layers:
        x0, y0 = min(boxes[i][0] for i in layer), min(boxes[i][1] for i in layer)
        x1, y1 = max(boxes[i][2] for i in layer), max(boxes[i][3] for i in layer)
        area = sum((boxes[i][2] - boxes[i][0]) * (boxes[i][3] - boxes[i][1]) for i in layer)
        if documents and len(documents[-1]) < 3:
            u0, v0, u1, v1 = unions[-1]
            ux0, uy0, ux1, uy1 = min(u0, x0), min(v0, y0), max(u1, x1), max(v1, y1)
            if (ux1 - ux0) * (uy1 - uy0) <= max(CANVAS, 2 * (areas[-1] + area)):
                documents[-1].append(layer)
                unions[-1] = (ux0, uy0, ux1, uy1)
                areas[-1] += area
                continue
        documents.append([layer])
        unions.append((x0, y0, x1, y1))
        areas.append(area)
    return documents


Take = Callable[[int, int, tuple[int, int]], NDArray[np.uint8]]  # (w, h, origin) -> a box's alpha bytes


class _Resvg:
    """resvg-py and Pillow: SVG elements rendered on a transparent canvas, alphas read back."""

    def __init__(self) -> None:
        self.resvg: Any = need("resvg_py")
        need("PIL")
        from PIL import Image

        self._image: Any = Image
        self.version = f"resvg {self.resvg.__resvg_version__} (resvg-py {self.resvg.__version__})"

    def rgba(self, elements: str, x0: int, y0: int, w: int, h: int) -> NDArray[np.uint8]:
        """The (h, w, 4) RGBA bytes (not premultiplied) of the screen's pixels [x0, x0 + w) x
        [y0, y0 + h) with ``elements`` (in screen coordinates) drawn: ``viewBox="x0 y0 w h"``
        on a w x h canvas, a translation by whole pixels, exact in tiny-skia's float32
        (x - x0 of a float32 x >= x0 is a float32)."""
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="{x0} {y0} {w} {h}">'
               f"{elements}</svg>")
        png = self.resvg.svg_to_bytes(svg_string=svg, skip_system_fonts=True)
        with self._image.open(io.BytesIO(png)) as image:
            rgba: NDArray[np.uint8] = np.asarray(image if image.mode == "RGBA" else image.convert("RGBA"))
        if rgba.shape[:2] != (h, w):
            raise RuntimeError(f"resvg rendered {rgba.shape[1]} x {rgba.shape[0]} px, not {w} x {h}")
        return rgba

    def replay(self, group: str, elements: list[str], boxes: list[tuple[int, int, int, int]], screen: tuple[int, int],
               channels: bool = False) -> Take:
        """Render the elements (each inside its box, in screen coordinates) a document at a
        time; returns a function answering, call after call in the boxes' order,
        ``(w, h, origin)`` with that box's coverage bytes.

        ``group`` is an opening ``<g ...>`` giving the elements' paint, ``{paint}`` where its
        colour goes. A document holds box-disjoint elements (:func:`pack`), black, read from
        the alpha channel; each pixel of a box then holds its own element's coverage alone.
        With ``channels`` (crisp drawing only: every coverage is 0 or 255), a document holds
        up to three such sets of box-disjoint elements (:func:`stack`), red, green and blue,
        the second and third composited with ``mix-blend-mode: screen`` (per channel
        1 - (1 - a)(1 - b), which leaves each channel its own set's coverage): each box is
        read from its set's channel. A document resvg fails on is not used: its elements
        are then rendered one by one when asked (so a failure names its primitive).

        A box reaching an edge of the ``screen`` (width, height) holds an element that may
        be clipped there, which tiny-skia does in float32 on the coordinates it draws with
        (after the viewBox's translation, and a blended group's move to its own corner), so
        the canvas's origin matters to it: such an element is drawn alone on the canvas of
        its box, as :func:`~rasterizers.real._masks.draw_each` draws for every library.
        Anywhere else the translation changes nothing (x - x0 is exact)."""
        width, height = screen
        clipped = [x0 == 0 or y0 == 0 or x1 == width or y1 == height for x0, y0, x1, y1 in boxes]
        crops: list[NDArray[np.uint8] | None] = [None] * len(boxes)
        free = [i for i in range(len(boxes)) if not clipped[i]]
        placed = [boxes[i] for i in free]
        layers = [[free[k] for k in layer] for layer in pack(placed)]
        for document in (stack(layers, boxes) if channels else [[layer] for layer in layers]):
            members = [i for layer in document for i in layer]
            ux0 = min(boxes[i][0] for i in members)
            uy0 = min(boxes[i][1] for i in members)
            ux1 = max(boxes[i][2] for i in members)
            uy1 = max(boxes[i][3] for i in members)
            parts = []
            for c, layer in enumerate(document):
                opening = group.format(paint=("#f00", "#0f0", "#00f")[c] if channels else "#000")
                if c:
                    opening = opening[:-1] + ' style="mix-blend-mode:screen">'
                parts.append(opening + "".join(elements[i] for i in layer) + "</g>")
            try:
                rgba = self.rgba("".join(parts), ux0, uy0, ux1 - ux0, uy1 - uy0)
            except Exception:  # noqa: BLE001 - rendered alone below, where the failure names the primitive
                continue
            for c, layer in enumerate(document):
                plane = rgba[:, :, c if channels else 3]
                for i in layer:
                    x0, y0, x1, y1 = boxes[i]
                    crops[i] = plane[y0 - uy0:y1 - uy0, x0 - ux0:x1 - ux0]
        order: Iterator[int] = iter(range(len(boxes)))

        def take(w: int, h: int, origin: tuple[int, int]) -> NDArray[np.uint8]:
            i = next(order)
            x0, y0, x1, y1 = boxes[i]
            if (x0, y0, x1 - x0, y1 - y0) != (origin[0], origin[1], w, h):
                raise RuntimeError(f"box {(x0, y0, x1, y1)} asked as {origin} + {w} x {h}: the boxes are out of order")
            crop = crops[i]
            if crop is None:
                crop = self.rgba(group.format(paint="#000") + elements[i] + "</g>", x0, y0, w, h)[:, :, 3]
            return crop

        return take


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
    from the rounded crossings: centre samples. No declared convention: ``identify``
    fingerprints it. Measured (resvg 0.48.1, resvg-py 0.5.0): best guess centre samples,
    bottom-right ties, vertices snapped to 1/64 px rounding down, residual 732 of 140,855
    px (236 exactly at vertices, 330 exactly on edges of non-dyadic slope, 64 off every
    edge: the 16.16 stepping); paths the same, both fill rules honoured; not watertight at
    vertices lying on pixel centres (4 double hits on 24 partitions); NaN and infinite
    triangles draw nothing. ``compare`` with skia-python 144.1's aliased fill
    (:class:`~rasterizers.real.adapters.SkiaPath`): 0 pixels differ.

    Lines: a ``<path d="M a L b">`` stroked black ``line_width`` px wide, SVG's default
    butt caps, no fill, one path per segment, any width. resvg has no hairlines: SVG's
    ``stroke-width="0"`` means no stroke (usvg drops it), and tiny-skia draws a stroke as
    a hairline only when its width is 0 or, anti-aliased, when it is at most 1 px
    (``treat_as_hairline`` in ``painter.rs``); crisp, a 1-px stroke is outlined by the
    stroker (the rectangle of that width around the segment, no caps) and filled as a path
    -- ``LineRule("rectangle")`` under the fill's rules, as cairo 1.16's strokes.
    Measured: best guess rectangular lines, bottom-right ties, end points snapped to 1/128
    px rounding down, 307 of 10,815 pixels mismatching (width 3: 19 of 734)."""

    name = "tiny_skia"
    library = "tiny-skia (resvg)"
    line_widths = None  # any width: a stroke is outlined and filled

    def __init__(self) -> None:
        self._resvg = _Resvg()
        self.library_version = self._resvg.version

    # as tiny-skia receives the scene: each coordinate rounded to float32 (usvg's and
    # tiny-skia's path points are f32; read by received_of)
    input = "float32"

    def rasterize(self, scene: AnyScene) -> Coverage:
        resvg = self._resvg
        screen = (scene.width, scene.height)
        if isinstance(scene, LineScene):
            self._refuse_lines(scene)
            boxes, drawn = segment_boxes(scene, self.name, MARGIN)
            a, b = scene.segments()
            chosen = drawn.tolist()
            elements = [f'<path d="M {_number(float(a[k, 0]))} {_number(float(a[k, 1]))} '
                        f'L {_number(float(b[k, 0]))} {_number(float(b[k, 1]))}"/>' for k in chosen]
            box_list = [(x0, y0, x1, y1) for x0, y0, x1, y1 in boxes[chosen].tolist()]
            group = ('<g fill="none" stroke="{paint}" stroke-width="' + _number(scene.line_width)
                     + '" shape-rendering="crispEdges">')
            take = resvg.replay(group, elements, box_list, screen, channels=True)
            return draw_each_segment(scene, self.name, lambda a, b, w, h, origin: take(w, h, origin) > 0, margin=MARGIN)
        if isinstance(scene, PathScene):
            self._refuse(scene)
            items = list(path_boxes(scene, self.name, MARGIN))
            elements = [f'<path d="{" ".join(_contour_data(c) for c in contours if c.shape[0])}"/>'
                        for _, contours, *_box in items]
            group = '<g fill="{paint}" fill-rule="' + scene.fill_rule + '" shape-rendering="crispEdges">'
            take = resvg.replay(group, elements, [(x0, y0, x1, y1) for _, _, x0, y0, x1, y1 in items], screen, channels=True)
            return draw_each_path(scene, self.name, lambda contours, w, h, origin: take(w, h, origin) > 0, margin=MARGIN)
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        triangles = list(_boxes(scene, self.name, MARGIN))
        take = resvg.replay('<g fill="{paint}" shape-rendering="crispEdges">',
                            [f'<path d="{_contour_data(p)}"/>' for _, p, *_box in triangles],
                            [(x0, y0, x1, y1) for _, _, x0, y0, x1, y1 in triangles], screen, channels=True)
        return draw_each(scene, self.name, lambda p, w, h, origin: take(w, h, origin) > 0, margin=MARGIN)


class TinySkiaAntialiased(AlphaPaths, AlphaOneTriangleAtATime):
    """tiny-skia (through resvg) anti-aliased (resvg's default ``shape-rendering``,
    ``geometricPrecision``); the mapping is the identity (module docstring), proved by
    ``test_the_antialiased_mapping_is_exact`` (tests/rasterizers/real/test_tiny_skia.py).
    Alpha is the PNG's alpha byte / 255. Input: float32 (:meth:`received`). Each
    primitive is drawn alone as far as its pixels go, box-disjoint ones sharing a document
    (module docstring; black, read from the alpha channel).

    Triangles: one ``<path>`` each. Paths: one ``<path>`` per path, every contour in it
    (``M``, ``L``..., ``Z`` each), ``fill-rule="nonzero"`` or ``"evenodd"``: both rules are
    tiny-skia's own (as for :class:`TinySkia`). Lines are not taken (``kinds_not_taken``):
    tiny-skia draws a stroke at most 1 px wide as an anti-aliased hairline with its alpha
    scaled by the width (``treat_as_hairline`` in ``painter.rs``), as skia does, and neither
    that nor its wider strokes have a model here.

    What tiny-skia does (``scan/path_aa.rs``, skia's ``SkScan_AntiPath.cpp`` supersampler;
    tiny-skia has no analytic AA): ``SUPERSAMPLE_SHIFT`` 2, each pixel sampled on 4
    sub-scanlines with x in 1/4 px, the coverage accumulated to 8 bits -- a 4 x 4
    supersampler where skia-python's is 16 x 4. Declared: that supersampler exactly
    (``Convention(coverage="area", supersample=2, input="float32")``,
    :mod:`harness.oracle.supersample_models`: its f32 points truncated to 1/256 px, 16.16 edge
    walk, ``blit_h``'s levels, the edge clipper at the screen's sides); identify recovers it
    (residual 0 of 60,824 px) and accuracy passes on every quick case. As a sample grid
    (resvg 0.48.1): 4 x 4 at 1/8 + k/4, |alpha - exact area| at most 0.241 (thin slivers),
    mean 0.019; the sweep finds the last two columns at 0.624998 and 0.874998, not 5/8 and
    7/8, because the sweep's coordinates reach tiny-skia rounded to float32 (:meth:`received`).
    The fill rule is applied per sub-scanline span (the winding of each span between
    crossings), so overlapping contours are judged by their winding, not by a sum of areas;
    paths are judged by the same model (:func:`harness.oracle.supersample_models.skia_supersampled_paths`)."""

    name = "tiny_skia_aa"
    library = "tiny-skia (resvg)"
    # skia's supersampler as tiny-skia runs it, SUPERSAMPLE_SHIFT 2, on its f32 points
    # (harness.oracle.supersample_models): the library's 8-bit levels exactly
    convention = Convention(coverage="area", supersample=2, input="float32")
    # what the atlas says of the kind it is not handed
    kinds_not_taken = {"lines": "tiny-skia strokes a line at most 1 px wide as an anti-aliased hairline scaled by "
                                "its width (painter.rs treat_as_hairline; up to 1.0 from the stroke's area on the "
                                "quick suite's 1 px lines), wider ones through the supersampler: neither has a model "
                                "here yet"}

    def __init__(self) -> None:
        self._resvg = _Resvg()
        self.library_version = self._resvg.version

    input = "float32"  # as tiny-skia receives the scene (read by received_of)

    def rasterize(self, scene: AnyScene) -> Coverage:
        resvg = self._resvg
        screen = (scene.width, scene.height)
        if isinstance(scene, PathScene):
            if scene.fill_rule not in self.fill_rules:
                raise Unsupported(f"{self.name}: fills {' and '.join(self.fill_rules)} only, not {scene.fill_rule!r}")
            items = list(path_boxes(scene, self.name, MARGIN))
            elements = [f'<path d="{" ".join(_contour_data(c) for c in contours if c.shape[0])}"/>'
                        for _, contours, *_box in items]
            group = '<g fill="{paint}" fill-rule="' + scene.fill_rule + '">'
            take = resvg.replay(group, elements, [(x0, y0, x1, y1) for _, _, x0, y0, x1, y1 in items], screen)
            return draw_each_path_alpha(scene, self.name, lambda contours, w, h, origin: take(w, h, origin) / 255.0,
                                        margin=MARGIN)
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        triangles = list(_boxes(scene, self.name, MARGIN))
        take = resvg.replay('<g fill="{paint}">', [f'<path d="{_contour_data(p)}"/>' for _, p, *_box in triangles],
                            [(x0, y0, x1, y1) for _, _, x0, y0, x1, y1 in triangles], screen)
        return draw_each_alpha(scene, self.name, lambda p, w, h, origin: take(w, h, origin) / 255.0, margin=MARGIN)
