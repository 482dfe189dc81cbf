"""The library peers the bench measures against (:mod:`harness.cli.bench`): Pillow (the yardstick),
cairo, skia and scikit-image, each drawing a workload's triangles, paths or segments into one
8-bit surface with no read-back, when installed (:func:`missing_peers` says which are not);
and what a peer cannot draw in reasonable time (:func:`_unmeasured`).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.engine.optional import missing
from harness.kinds import PATHS

__all__ = ["missing_peers", "SKIMAGE_WORK_LIMIT"]

if TYPE_CHECKING:
    pass


def _pillow(scene: Scene) -> Image.Image:
    image = Image.new("L", (scene.width, scene.height), 0)
    draw = ImageDraw.Draw(image)
    # Pillow puts pixel centres at integers: shift by half a pixel to draw the same triangles.
    for tri in (scene.positions - 0.5).tolist():
        draw.polygon([tuple(v) for v in tri], fill=255)
    return image


def _cairo_aa(scene: Scene) -> np.ndarray:
    """cairo's anti-aliased fill (``ANTIALIAS_DEFAULT``) of each triangle into one A8 surface."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
    for (ax, ay), (bx, by), (cx, cy) in scene.positions.tolist():
        context.move_to(ax, ay)
        context.line_to(bx, by)
        context.line_to(cx, cy)
        context.close_path()
        context.fill()
    surface.flush()
    return np.frombuffer(surface.get_data(), dtype=np.uint8)


def _skia_aa(scene: Scene) -> np.ndarray:
    """skia's anti-aliased path fill of each triangle into one 8-bit alpha surface."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=True)
    for (ax, ay), (bx, by), (cx, cy) in scene.positions.tolist():
        path = skia.Path()
        path.moveTo(ax, ay)
        path.lineTo(bx, by)
        path.lineTo(cx, cy)
        path.close()
        canvas.drawPath(path, paint)
    return np.asarray(surface.makeImageSnapshot().toarray())


def _installed(candidates: tuple[tuple[str, str, Callable[[Any], object]], ...]) -> list[tuple[str, Callable[[Any], object]]]:
    """The (label, fill) of ``candidates`` whose module imports here (the others:
    :func:`missing_peers`)."""
    return [(label, fill) for label, module, fill in candidates if missing(module) is None]


def _library_peers() -> list[tuple[str, Callable[[Scene], object]]]:
    """The anti-aliased library fills that are installed here."""
    return _installed(_AA_PEERS)


# -- the path peers: each path filled in one call into one 8-bit surface ------------------------


class _Surface:
    """A library's surface, drawn and not read back: :func:`_pixels` reads it, outside the
    timed call."""

    def __init__(self, read: Callable[[], NDArray[np.uint8]]) -> None:
        self.read = read


def _contours_by_path(scene: PathScene, shift: float = 0.0) -> list[list[list[float]]]:
    """Each path's contours, as flat ``[x0, y0, x1, y1, ...]`` lists moved by ``shift`` px,
    paths in order."""
    flat = (scene.vertices + shift).ravel().tolist()
    starts = (2 * scene.contour_starts).tolist()
    ends = (2 * np.cumsum(scene.contour_sizes)).tolist()
    by_path: list[list[list[float]]] = [[] for _ in range(len(scene))]
    for path, start, end in zip(scene.contour_path.tolist(), starts, ends):
        by_path[path].append(flat[start:end])
    return by_path


def _pillow_paths(scene: PathScene) -> Image.Image:
    """Pillow's polygon fill of each contour (even-odd within a contour, whatever the rule)."""
    image = Image.new("L", (scene.width, scene.height), 0)
    draw = ImageDraw.Draw(image)
    for path in _contours_by_path(scene, -0.5):  # Pillow's pixel centres are at integers
        for contour in path:
            draw.polygon(contour, fill=255)
    return image


def _cairo_paths(scene: PathScene, antialias: bool = False) -> _Surface:
    """cairo's aliased fill (``ANTIALIAS_NONE``; anti-aliased: its default) of each path
    under the scene's fill rule."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
    context.set_antialias(cairo.ANTIALIAS_DEFAULT if antialias else cairo.ANTIALIAS_NONE)
    context.set_fill_rule(cairo.FILL_RULE_WINDING if scene.fill_rule == "nonzero" else cairo.FILL_RULE_EVEN_ODD)
    for path in _contours_by_path(scene):
        for contour in path:
            context.move_to(contour[0], contour[1])
            for k in range(2, len(contour), 2):
                context.line_to(contour[k], contour[k + 1])
            context.close_path()
        context.fill()

    def read() -> NDArray[np.uint8]:
        surface.flush()
        stride = surface.get_stride()
        return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(scene.height, stride)[:, :scene.width]

    return _Surface(read)


def _skia_paths(scene: PathScene, antialias: bool = False) -> _Surface:
    """skia's ``drawPath`` without anti-aliasing (or with) of each path under the scene's
    fill type."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=antialias)
    fill_type = skia.PathFillType.kWinding if scene.fill_rule == "nonzero" else skia.PathFillType.kEvenOdd
    for contours in _contours_by_path(scene):
        path = skia.Path()
        path.setFillType(fill_type)
        for contour in contours:
            path.moveTo(contour[0], contour[1])
            for k in range(2, len(contour), 2):
                path.lineTo(contour[k], contour[k + 1])
            path.close()
        canvas.drawPath(path, paint)
    return _Surface(lambda: np.asarray(surface.makeImageSnapshot().toarray()))


def _skimage_paths(scene: PathScene) -> NDArray[np.uint8]:
    """scikit-image's ``draw.polygon`` of each contour (even-odd within a contour) into one
    array."""
    from skimage.draw import polygon

    image = np.zeros((scene.height, scene.width), dtype=np.uint8)
    shape = image.shape
    shifted = scene.vertices - 0.5  # scikit-image's pixel centres are at integers
    for start, size in zip(scene.contour_starts.tolist(), scene.contour_sizes.tolist()):
        contour = shifted[start:start + size]
        rows, columns = polygon(contour[:, 1], contour[:, 0], shape)
        image[rows, columns] = 255
    return image


# -- the line peers: each segment drawn in one call into one 8-bit image -----------------------


def _pillow_lines(scene: LineScene) -> Image.Image:
    """Pillow's ``ImageDraw.line`` of each segment, width 1: integer Bresenham between the
    end points truncated to integers (for coordinates >= 0 the pixel holding each: the
    Bresenham oracle's end pixels, given no end point on a pixel border)."""
    image = Image.new("L", (scene.width, scene.height), 0)
    draw = ImageDraw.Draw(image)
    a, b = scene.segments()
    # no half-pixel shift, unlike the polygons: Pillow truncates, so x in [i, i + 1) is pixel i
    for segment in np.concatenate([a, b], axis=1).tolist():
        draw.line(segment, fill=255, width=1)
    return image


def _skimage_lines(scene: LineScene) -> NDArray[np.uint8]:
    """scikit-image's ``draw.line`` (integer Bresenham) between the pixels nearest each
    segment's end points."""
    from skimage.draw import line

    image = np.zeros((scene.height, scene.width), dtype=np.uint8)
    a, b = scene.segments()
    # scikit-image's pixel centres are at integers: (row, column) of the nearest one
    ends = np.rint(np.concatenate([a[:, ::-1], b[:, ::-1]], axis=1) - 0.5).astype(np.int64).tolist()
    for r0, c0, r1, c1 in ends:
        rows, columns = line(r0, c0, r1, c1)
        image[rows, columns] = 255
    return image


def _cairo_segments(scene: LineScene, antialiased: bool) -> _Surface:
    """cairo stroking each segment of ``scene`` into an A8 surface: aliased hairlines
    (width 1, ``ANTIALIAS_NONE``) or its default anti-aliasing at the scene's width with
    butt caps."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
    if antialiased:
        context.set_line_width(scene.line_width)
        context.set_line_cap(cairo.LINE_CAP_BUTT)
    else:
        context.set_antialias(cairo.ANTIALIAS_NONE)
        context.set_line_width(1.0)
    a, b = scene.segments()
    for ax, ay, bx, by in np.concatenate([a, b], axis=1).tolist():
        context.move_to(ax, ay)
        context.line_to(bx, by)
        context.stroke()

    def read() -> NDArray[np.uint8]:
        surface.flush()
        stride = surface.get_stride()
        return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(scene.height, stride)[:, :scene.width]

    return _Surface(read)


def _cairo_lines(scene: LineScene) -> _Surface:
    """cairo's aliased hairline (width 1, ``ANTIALIAS_NONE``) of each segment, stroked."""
    return _cairo_segments(scene, antialiased=False)


def _skia_lines(scene: LineScene) -> _Surface:
    """skia's aliased hairline (``drawLine``, stroke width 0, no anti-aliasing) of each segment."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=False, StrokeWidth=0.0, Style=skia.Paint.kStroke_Style)
    a, b = scene.segments()
    for ax, ay, bx, by in np.concatenate([a, b], axis=1).tolist():
        canvas.drawLine(ax, ay, bx, by, paint)
    return _Surface(lambda: np.asarray(surface.makeImageSnapshot().toarray()))


def _pillow_strokes(scene: LineScene) -> Image.Image:
    """Pillow's ``ImageDraw.line`` of each segment at the scene's width rounded to an
    integer (aliased: Pillow has no anti-aliasing; the yardstick of the stroke workloads)."""
    image = Image.new("L", (scene.width, scene.height), 0)
    draw = ImageDraw.Draw(image)
    a, b = scene.segments()
    width = max(1, round(scene.line_width))
    for segment in np.concatenate([a, b], axis=1).tolist():
        draw.line(segment, fill=255, width=width)
    return image


def _cairo_strokes(scene: LineScene) -> _Surface:
    """cairo's anti-aliased stroke (its default anti-aliasing, the scene's width, butt
    caps) of each segment."""
    return _cairo_segments(scene, antialiased=True)


def _skia_strokes(scene: LineScene) -> _Surface:
    """skia's anti-aliased stroke (``drawLine``, ``AntiAlias=True``, the scene's width,
    butt caps) of each segment."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=True, StrokeWidth=scene.line_width, Style=skia.Paint.kStroke_Style,
                       StrokeCap=skia.Paint.kButt_Cap)
    a, b = scene.segments()
    for ax, ay, bx, by in np.concatenate([a, b], axis=1).tolist():
        canvas.drawLine(ax, ay, bx, by, paint)
    return _Surface(lambda: np.asarray(surface.makeImageSnapshot().toarray()))


def _stroke_peers() -> list[tuple[str, Callable[[LineScene], object]]]:
    """The anti-aliased library strokes that are installed here."""
    return _installed(_STROKE_PEERS)


def _line_peers() -> list[tuple[str, Callable[[LineScene], object]]]:
    """The aliased library line drawers that are installed here."""
    return _installed(_LINE_PEERS)


def _path_peers() -> list[tuple[str, Callable[[PathScene], object]]]:
    """The aliased library path fills that are installed here."""
    return _installed(_PATH_PEERS)


# Every library peer, once: its label, the module it needs, and how it draws a workload.
_AA_PEERS = (("cairo_aa_fill", "cairo", _cairo_aa), ("skia_aa_fill", "skia", _skia_aa))
_LINE_PEERS = (("skimage_line", "skimage", _skimage_lines), ("cairo_line", "cairo", _cairo_lines),
               ("skia_hairline", "skia", _skia_lines))
_PATH_PEERS = (("cairo_fill", "cairo", _cairo_paths), ("skia_fill", "skia", _skia_paths),
               ("skimage_polygon", "skimage", _skimage_paths),
               # anti-aliased: the peers of the exact area oracle (oracle_area)
               ("cairo_aa_path", "cairo", partial(_cairo_paths, antialias=True)),
               ("skia_aa_path", "skia", partial(_skia_paths, antialias=True)))
_STROKE_PEERS = (("cairo_aa_stroke", "cairo", _cairo_strokes), ("skia_aa_stroke", "skia", _skia_strokes))


def missing_peers() -> dict[str, str]:
    """Each library peer not measured here because its module is missing, with the
    sentence naming the module and its install (:func:`harness.engine.optional.missing`).

    Returns
    -------
    dict of str to str
        ``{label: why}``, empty when every peer is installed.
    """
    peers = (*_AA_PEERS, *_LINE_PEERS, *_PATH_PEERS, *_STROKE_PEERS)
    return {label: why for label, module, _ in peers if (why := missing(module)) is not None}


# scikit-image's polygon tests every pixel of a contour's bounding box against each of its
# edges: above this many (box pixels x vertices) summed over the contours it is not
# measured. The 1,000 stars are 2.4e7 tests (0.8 s a call here); the 100,000-vertex
# outline is 1.7e10 (100 s a call).
SKIMAGE_WORK_LIMIT = 5e7


def _unmeasured(label: str, scene: AnyScene) -> str:
    """Why a peer is not measured on ``scene`` ("" when it is)."""
    if label != "skimage_polygon" or not PATHS.owns(scene):
        return ""
    lo = np.minimum.reduceat(scene.vertices, scene.contour_starts, axis=0)
    hi = np.maximum.reduceat(scene.vertices, scene.contour_starts, axis=0)
    box = np.prod(np.clip(np.ceil(hi) - np.floor(lo) + 1, 0, [scene.width, scene.height]), axis=1)
    work = float((box * scene.contour_sizes).sum())
    if work <= SKIMAGE_WORK_LIMIT:
        return ""
    return f"not measured: draw.polygon tests each box pixel against each edge ({work:.2g} tests, limit {SKIMAGE_WORK_LIMIT:.0e})"
