"""``rastercheck bench``: throughput of the oracle and the built-ins against Pillow, side by side.

Workloads (fixed seeds, 1024 x 1024):

- W1: 10,000 random triangles of mean area about 50 px;
- W2: 100 triangles of about 100,000 px each.

Pillow's ``ImageDraw.polygon``, one call per triangle, is the in-run yardstick: every
figure is reported as a ratio to it, measured in the same process, so the numbers compare
across machines. Cold start (numba compilation or cache load) is timed separately.

Beside the single-sample oracle, the oracles of the other coverage kinds: the exact area
(``oracle_area``) and the exact 4x and 8x multisample coverage (``oracle_msaa4``,
``oracle_msaa8``), with the anti-aliased fills of cairo and skia as their peers
(``cairo_aa_fill``, ``skia_aa_fill``: the libraries alone, each triangle filled into one
8-bit surface, no read-back -- the least they can cost), when installed.

Path workloads (fixed seeds, 512 x 512; :func:`path_workloads`), each under both fill rules:

- P1-nonzero, P1-evenodd: 1,000 {10/3} stars (10 vertices, one self-intersecting contour
  each; random centres, radii 4 to 40 px and rotations);
- P2-nonzero, P2-evenodd: one closed wiggly curve of 100,000 vertices that winds twice
  around the centre (self-intersecting: where the two turns overlap nonzero and even-odd
  part).

The exact winding oracle (``oracle``, :func:`harness.oracle.exact_coverage` on the path
scene) against the aliased path fills of the libraries, each path filled in one call into
one 8-bit surface, no read-back: Pillow's ``ImageDraw.polygon`` (the yardstick again;
even-odd, whatever the rule asked), cairo (``cairo_fill``: ``ANTIALIAS_NONE``, the scene's
fill rule), skia (``skia_fill``: ``drawPath`` without anti-aliasing, the scene's fill type)
and scikit-image (``skimage_polygon``: ``draw.polygon``, even-odd); and each rasterizer
that takes the scene (:func:`harness.api.takes`). A library's time includes handing it the
vertices through its Python binding, as for the triangle peers.

Line workloads (fixed seeds, 1024 x 1024; :func:`line_workloads`), width 1:

- L1: 100,000 short segments (lengths 2 to 16 px, random directions);
- L2: 1,000 long segments (end points anywhere on the screen, at least 256 px apart).

Every segment stays inside the viewport (no peer clips). The exact line oracles, one per
rule (``oracle_diamond_exit``, ``oracle_bresenham``, ``oracle_rectangle``:
:func:`harness.oracle.exact_coverage` under ``Convention(line=...)``), against the aliased
line drawers of the libraries, each segment one call into one 8-bit image, no read-back:
Pillow's ``ImageDraw.line`` (the yardstick: integer Bresenham between the end points
truncated to pixels), scikit-image's ``draw.line`` (``skimage_line``: Bresenham between the
pixels whose centres are nearest the end points, the pixels set by a fancy index) -- on
these workloads both draw exactly the Bresenham oracle's pixels --, cairo's hairline
(``cairo_line``: width 1, ``ANTIALIAS_NONE``, each segment stroked: nearly the rectangle
oracle's) and skia's (``skia_hairline``: ``drawLine`` with stroke width 0, no
anti-aliasing: nearest the diamond-exit oracle's), when installed; and each rasterizer
that takes lines. Rates are in segments per second.
"""

from __future__ import annotations

from functools import partial

import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from harness.api import AnyScene, LineScene, PathScene, Scene, takes
from harness.conventions import Convention
from harness.oracle import exact_coverage
from harness.registry import builtins, load
from cases.scenes import random_triangles

__all__ = ["Workload", "workloads", "path_workloads", "line_workloads", "short_segments", "long_segments", "stars",
           "wiggly_outline", "run_bench", "format_table", "LINE_ORACLES"]

SIZE = 1024
PATH_SIZE = 512
LINE_SIZE = 1024


@dataclass(frozen=True, slots=True)
class Workload:
    """A scene to time; ``mean_area`` is per primitive (for a path, the magnitude of its
    signed area: the integral of its winding number; for a segment, its length in px)."""

    name: str
    description: str
    scene: AnyScene
    mean_area: float


@dataclass(frozen=True, slots=True)
class Measurement:
    """One contender on one workload. ``triangles_per_second`` is primitives per second:
    paths for a path workload, segments for a line workload (``unit``)."""

    workload: str
    contender: str
    cold_seconds: float
    seconds: float
    triangles_per_second: float
    ratio_to_pillow: float
    pixels: int
    unit: str = "triangles"
    description: str = ""


def workloads(scale: float = 1.0) -> list[Workload]:
    """W1 and W2; ``scale`` < 1 shrinks the triangle counts (for smoke tests)."""
    out = []
    for name, count, area, seed in (("W1", 10_000, 50.0, 1), ("W2", 100, 100_000.0, 2)):
        n = max(1, int(count * scale))
        positions = random_triangles(n, area, SIZE, seed)
        p = positions
        areas = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
        out.append(Workload(name, f"{n} triangles, mean area {areas.mean():,.0f} px", Scene(SIZE, SIZE, positions), float(areas.mean())))
    return out


def stars(count: int, size: int, seed: int) -> PathScene:
    """``count`` {10/3} star polygons (10 vertices, one contour, each vertex joined to the
    third next: the winding number reaches 3 at the centre) with random centres on the
    ``size`` x ``size`` screen, radii 4 to 40 px and rotations; fill rule nonzero.

    >>> scene = stars(3, 64, 0)
    >>> len(scene), scene.contour_sizes.tolist()
    (3, [10, 10, 10])
    """
    rng = np.random.default_rng(seed)
    centre = rng.uniform(0.0, size, size=(count, 1, 2))
    radius = rng.uniform(4.0, 40.0, size=(count, 1))
    angle = rng.uniform(0.0, 2.0 * np.pi, size=(count, 1)) + 2.0 * np.pi * 3.0 * np.arange(10) / 10.0
    vertices = centre + radius[..., None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    return PathScene(size, size, vertices.reshape(-1, 2), np.full(count, 10, dtype=np.int64), np.arange(count, dtype=np.int64))


def wiggly_outline(vertices: int, size: int) -> PathScene:
    """One closed curve of ``vertices`` vertices that winds twice around the screen's centre
    with wiggles of two frequencies: it crosses itself, and where its two turns overlap the
    winding number is 2 (filled by nonzero, not by even-odd); fill rule nonzero.

    >>> wiggly_outline(1000, 512).vertices.shape
    (1000, 2)
    """
    t = np.arange(vertices) * (4.0 * np.pi / vertices)  # two turns; every term below closes after them
    r = 0.42 * size * (0.62 + 0.25 * np.sin(3.5 * t) + 0.08 * np.sin(61.0 * t) + 0.03 * np.sin(997.0 * t))
    points = size / 2.0 + np.stack([r * np.cos(t), r * np.sin(t)], axis=-1)
    return PathScene(size, size, points, np.array([vertices], dtype=np.int64), np.array([0], dtype=np.int64))


def _signed_areas(scene: PathScene) -> NDArray[np.float64]:
    """(P,) each path's signed area (shoelace over its contours)."""
    a, b, path = scene.edges()
    return np.asarray(np.bincount(path, weights=(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]) / 2.0, minlength=len(scene)), dtype=np.float64)


def path_workloads(scale: float = 1.0) -> list[Workload]:
    """P1 (stars) and P2 (the 100,000-vertex outline), each under nonzero then even-odd;
    ``scale`` < 1 shrinks the star count and the outline's vertices (for smoke tests)."""
    n = max(1, int(1000 * scale))
    v = max(64, int(100_000 * scale))
    out = []
    for name, scene, what in (("P1", stars(n, PATH_SIZE, 3), f"{n} {{10/3}} stars of 10 vertices"),
                              ("P2", wiggly_outline(v, PATH_SIZE), f"one self-intersecting outline of {v:,} vertices")):
        area = float(np.abs(_signed_areas(scene)).mean())
        for rule in ("nonzero", "evenodd"):
            out.append(Workload(f"{name}-{rule}", f"{what}, {rule}, {PATH_SIZE} x {PATH_SIZE}", scene.with_fill_rule(rule), area))
    return out


def short_segments(count: int, size: int, seed: int) -> LineScene:
    """``count`` segments of lengths 2 to 16 px in random directions, each a strip of its
    own, their start points random and every end point inside the ``size`` x ``size``
    screen (at least half a pixel from its border).

    >>> scene = short_segments(4, 64, 0)
    >>> len(scene), scene.strip_sizes.tolist()
    (4, [2, 2, 2, 2])
    """
    rng = np.random.default_rng(seed)
    angle = rng.uniform(0.0, 2.0 * np.pi, size=count)
    length = rng.uniform(2.0, 16.0, size=count)
    step = length[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
    # the start far enough from each border that the end lands inside it
    low, high = 0.5 - np.minimum(step, 0.0), size - 0.5 - np.maximum(step, 0.0)
    start = low + rng.uniform(0.0, 1.0, size=(count, 2)) * (high - low)
    return LineScene.from_segments(size, size, start, start + step)


def long_segments(count: int, size: int, seed: int) -> LineScene:
    """``count`` segments whose end points lie anywhere on the ``size`` x ``size`` screen
    (at least half a pixel from its border) and at least ``size / 4`` px apart, each a
    strip of its own.

    >>> scene = long_segments(3, 512, 0)
    >>> a, b = scene.segments()
    >>> len(scene), bool((np.hypot(*(b - a).T) >= 128).all())
    (3, True)
    """
    rng = np.random.default_rng(seed)
    found: list[NDArray[np.float64]] = []
    kept = 0
    while kept < count:  # about 3 in 4 pairs are far enough apart: a few rounds at most
        ends = rng.uniform(0.5, size - 0.5, size=(2 * count, 2, 2))
        far = np.hypot(*(ends[:, 1] - ends[:, 0]).T) >= size / 4
        found.append(ends[far][: count - kept])
        kept += found[-1].shape[0]
    ends = np.concatenate(found)
    return LineScene.from_segments(size, size, ends[:, 0], ends[:, 1])


def line_workloads(scale: float = 1.0) -> list[Workload]:
    """L1 (100,000 short segments) and L2 (1,000 long ones); ``scale`` < 1 shrinks the
    counts (for smoke tests)."""
    out = []
    for name, count, make, seed, what in (("L1", 100_000, short_segments, 4, "short segments"),
                                          ("L2", 1_000, long_segments, 5, "long segments")):
        n = max(1, int(count * scale))
        scene = make(n, LINE_SIZE, seed)
        a, b = scene.segments()
        length = float(np.hypot(*(b - a).T).mean())
        out.append(Workload(name, f"{n:,} {what}, mean length {length:,.1f} px, width 1, {LINE_SIZE} x {LINE_SIZE}", scene, length))
    return out


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
    """The (label, fill) of ``candidates`` whose module imports here."""
    peers: list[tuple[str, Callable[[Any], object]]] = []
    for label, module, fill in candidates:
        try:
            __import__(module)
        except Exception:  # noqa: BLE001 - not installed (or broken): no peer, the table says which ran
            continue
        peers.append((label, fill))
    return peers


def _library_peers() -> list[tuple[str, Callable[[Scene], object]]]:
    """The anti-aliased library fills that are installed here."""
    return _installed((("cairo_aa_fill", "cairo", _cairo_aa), ("skia_aa_fill", "skia", _skia_aa)))


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


def _cairo_paths(scene: PathScene) -> _Surface:
    """cairo's aliased fill (``ANTIALIAS_NONE``) of each path under the scene's fill rule."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
    context.set_antialias(cairo.ANTIALIAS_NONE)
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


def _skia_paths(scene: PathScene) -> _Surface:
    """skia's ``drawPath`` without anti-aliasing of each path under the scene's fill type."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=False)
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


def _cairo_lines(scene: LineScene) -> _Surface:
    """cairo's aliased hairline (width 1, ``ANTIALIAS_NONE``) of each segment, stroked."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
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


def _line_peers() -> list[tuple[str, Callable[[LineScene], object]]]:
    """The aliased library line drawers that are installed here."""
    return _installed((("skimage_line", "skimage", _skimage_lines), ("cairo_line", "cairo", _cairo_lines),
                       ("skia_hairline", "skia", _skia_lines)))


def _path_peers() -> list[tuple[str, Callable[[PathScene], object]]]:
    """The aliased library path fills that are installed here."""
    return _installed((("cairo_fill", "cairo", _cairo_paths), ("skia_fill", "skia", _skia_paths),
                       ("skimage_polygon", "skimage", _skimage_paths)))


# scikit-image's polygon tests every pixel of a contour's bounding box against each of its
# edges: above this many (box pixels x vertices) summed over the contours it is not
# measured. The 1,000 stars are 2.4e7 tests (0.8 s a call here); the 100,000-vertex
# outline is 1.7e10 (100 s a call).
SKIMAGE_WORK_LIMIT = 5e7


def _unmeasured(label: str, scene: AnyScene) -> str:
    """Why a peer is not measured on ``scene`` ("" when it is)."""
    if label != "skimage_polygon" or not isinstance(scene, PathScene):
        return ""
    lo = np.minimum.reduceat(scene.vertices, scene.contour_starts, axis=0)
    hi = np.maximum.reduceat(scene.vertices, scene.contour_starts, axis=0)
    box = np.prod(np.clip(np.ceil(hi) - np.floor(lo) + 1, 0, [scene.width, scene.height]), axis=1)
    work = float((box * scene.contour_sizes).sum())
    if work <= SKIMAGE_WORK_LIMIT:
        return ""
    return f"not measured: draw.polygon tests each box pixel against each edge ({work:.2g} tests, limit {SKIMAGE_WORK_LIMIT:.0e})"


# The oracles of each coverage kind the bench measures.
ORACLES: dict[str, Convention] = {
    "oracle": Convention(),
    "oracle_area": Convention(coverage="area"),
    "oracle_msaa4": Convention(samples=4),
    "oracle_msaa8": Convention(samples=8),
}


# The line oracles the bench measures: one per rule, width 1.
LINE_ORACLES: dict[str, Convention] = {
    "oracle_diamond_exit": Convention(line="diamond-exit"),
    "oracle_bresenham": Convention(line="bresenham"),
    "oracle_rectangle": Convention(line="rectangle"),
}


def _pixels(result: object) -> int:
    """Pixels drawn (Pillow and the library fills: pixels set; rasterizers: fragments,
    one per sample for multisample coverage)."""
    if isinstance(result, Image.Image):
        return int(np.count_nonzero(np.asarray(result)))
    if isinstance(result, np.ndarray):
        return int(np.count_nonzero(result))
    if isinstance(result, _Surface):
        return int(np.count_nonzero(result.read()))
    return int(result.n_pixels)  # type: ignore[attr-defined]


def _time(fn: Callable[[], object], budget: float) -> tuple[float, float, int, int]:
    """(cold seconds, best seconds, pixels, warm runs): only the drawing call is timed.

    Warm repeats run while the next one fits in the ``budget`` (at least one -- the cold
    call pays for compilation and is no throughput -- at most 50): the budget caps the
    time of the repeats, not only their count."""
    start = time.perf_counter()
    result = fn()
    cold = time.perf_counter() - start
    pixels = _pixels(result)
    best = float("inf")
    runs = 0
    deadline = time.perf_counter() + budget
    while runs < 50:
        left = deadline - time.perf_counter()
        if runs >= 1 and best > left:
            break  # the next repeat would overrun the budget
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
        runs += 1
    return cold, best, pixels, runs


def _contenders(work: Workload, rasterizers: list[Any]) -> list[tuple[str, Callable[[], object]]]:
    """Pillow first (the yardstick), the oracles, the library peers, then each rasterizer
    that takes the workload's scene."""
    scene = work.scene
    if isinstance(scene, LineScene):
        contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_lines, scene))]
        contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in LINE_ORACLES.items()]
        contenders += [(label, partial(draw, scene)) for label, draw in _line_peers()]
    elif isinstance(scene, PathScene):
        contenders = [("pillow", partial(_pillow_paths, scene)), ("oracle", partial(exact_coverage, scene, ORACLES["oracle"]))]
        contenders += [(label, partial(fill, scene)) for label, fill in _path_peers() if not _unmeasured(label, scene)]
    else:
        contenders = [("pillow", partial(_pillow, scene))]
        contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in ORACLES.items()]
        contenders += [(label, partial(fill, scene)) for label, fill in _library_peers()]
    contenders += [(r.name, partial(r.rasterize, scene)) for r in rasterizers if takes(r, scene)]
    return contenders


def run_bench(names: list[str] | None = None, scale: float = 1.0, budget: float = 1.0,
              progress: Callable[[str], None] | None = None, paths: bool = True, lines: bool = True,
              triangles: bool = True) -> list[Measurement]:
    """Measure Pillow, the oracle and each rasterizer on W1 and W2 (with ``triangles``),
    then (with ``paths``) Pillow, the winding oracle, the library path fills and each
    path-taking rasterizer on the path workloads, then (with ``lines``) Pillow, the three
    line oracles, the library line drawers and each line-taking rasterizer on the line
    workloads, in this process; ``progress`` hears a line before and after each contender."""
    names = names if names is not None else builtins()
    rasterizers = [load(n) for n in names]
    results = []
    chosen = ((workloads(scale) if triangles else []) + (path_workloads(scale) if paths else [])
              + (line_workloads(scale) if lines else []))
    for work in chosen:
        contenders = _contenders(work, rasterizers)
        unit = {"paths": "paths", "lines": "segments"}.get(work.scene.kind, "triangles")
        if progress is not None and isinstance(work.scene, PathScene):
            for label, _ in _path_peers():
                if _unmeasured(label, work.scene):
                    progress(f"{work.name} {label}: {_unmeasured(label, work.scene)}")
        pillow_rate = None
        for label, fn in contenders:
            if progress is not None:
                progress(f"{work.name} {label}: measuring ...")
            cold, seconds, pixels, runs = _time(fn, budget)
            if progress is not None:
                progress(f"{work.name} {label}: best {seconds * 1e3:.1f} ms of {runs} warm runs (cold {cold:.2f} s)")
            rate = len(work.scene) / seconds
            if pillow_rate is None:
                pillow_rate = rate
            results.append(Measurement(work.name, label, cold, seconds, rate, rate / pillow_rate, pixels, unit, work.description))
    return results


def format_table(results: list[Measurement], descriptions: dict[str, str]) -> str:
    """One block per workload: each contender's rate, ratio to Pillow, best and cold time
    and pixels; a workload missing from ``descriptions`` is described by its measurements."""
    lines = []
    for work in dict.fromkeys(m.workload for m in results):
        mine = [m for m in results if m.workload == work]
        lines.append(f"{work}: {descriptions.get(work) or mine[0].description}")
        lines.append(f"  {'contender':<18}{mine[0].unit + '/s':>14}{'x Pillow':>10}{'best ms':>10}{'cold s':>9}{'pixels':>11}")
        for m in mine:
            lines.append(
                f"  {m.contender:<18}{m.triangles_per_second:>14,.0f}{m.ratio_to_pillow:>10.2f}"
                f"{m.seconds * 1e3:>10.2f}{m.cold_seconds:>9.2f}{m.pixels:>11,}"
            )
    return "\n".join(lines)


def write_json(results: list[Measurement], path: Path) -> None:
    from harness.files import atomic_write_text

    payload = {
        "schema": 1,
        "machine": {"platform": platform.platform(), "python": platform.python_version(), "cpus": os.cpu_count()},
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "results": [asdict(m) for m in results],
    }
    atomic_write_text(path, json.dumps(payload, indent=2))
