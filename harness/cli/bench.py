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

The exact winding oracle (``oracle``, :func:`harness.oracle.coverage.exact_coverage` on the path
scene) against the aliased path fills of the libraries, each path filled in one call into
one 8-bit surface, no read-back: Pillow's ``ImageDraw.polygon`` (the yardstick again;
even-odd, whatever the rule asked), cairo (``cairo_fill``: ``ANTIALIAS_NONE``, the scene's
fill rule), skia (``skia_fill``: ``drawPath`` without anti-aliasing, the scene's fill type)
and scikit-image (``skimage_polygon``: ``draw.polygon``, even-odd); and each rasterizer
that takes the scene (:func:`harness.contract.protocol.takes`). A library's time includes handing it the
vertices through its Python binding, as for the triangle peers.

Line workloads (fixed seeds, 1024 x 1024; :func:`line_workloads`), width 1:

- L1: 100,000 short segments (lengths 2 to 16 px, random directions);
- L2: 1,000 long segments (end points anywhere on the screen, at least 256 px apart).

Every segment stays inside the viewport (no peer clips). The exact line oracles, one per
rule (``oracle_diamond_exit``, ``oracle_bresenham``, ``oracle_rectangle``:
:func:`harness.oracle.coverage.exact_coverage` under ``Convention(line=...)``), against the aliased
line drawers of the libraries, each segment one call into one 8-bit image, no read-back:
Pillow's ``ImageDraw.line`` (the yardstick: integer Bresenham between the end points
truncated to pixels), scikit-image's ``draw.line`` (``skimage_line``: Bresenham between the
pixels whose centres are nearest the end points, the pixels set by a fancy index) -- on
these workloads both draw exactly the Bresenham oracle's pixels --, cairo's hairline
(``cairo_line``: width 1, ``ANTIALIAS_NONE``, each segment stroked: nearly the rectangle
oracle's) and skia's (``skia_hairline``: ``drawLine`` with stroke width 0, no
anti-aliasing: nearest the diamond-exit oracle's), when installed; and each rasterizer
that takes lines. Rates are in segments per second.

Every contender is measured in a forked process of its own, each call within a time limit
(``--timeout``; see the section on isolation below): a crash, a hang, a raise or an answer
that is no coverage is that contender's row (:attr:`Measurement.fault`), and the others go
on. The clock times the drawing call alone, in that process, as it did in one.

The campaign workload (``rastercheck bench --campaign``; :func:`run_campaign_bench`): a
campaign (:func:`harness.campaign.campaign.run_campaign`) of a fixed scene budget on a built-in
reference (``pineda_topleft``: it passes, so nothing is shrunk) over every fuzz family it
takes, first on a ``LocalCluster`` of one worker process, then of two
(:func:`harness.campaign.campaign.local_cluster`, as a campaign starts by default): end-to-end checked
primitives per second (generation, the isolated rasterize calls, every check against the
exact oracle, the coordinator merging and saving the state) per worker, and the speed-up
from one worker to two. The workers are started and warmed (the harness imported, the
kernels loaded, one scene of each family checked) before the clock starts: the figure is
a campaign's steady state, which is what a long one runs in.
"""

from __future__ import annotations

import json
import math
import multiprocessing
import os
import platform
import signal
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from cases.scenes import random_triangles
from harness.campaign.campaign import local_cluster
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.protocol import takes
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.engine.isolation import _exit_with_parent, describe, span_limit
from harness.engine.optional import missing
from harness.engine.registry import builtins, load
from harness.kinds import PATHS
from harness.oracle.coverage import RECENT_ANSWERS, exact_coverage

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["Workload", "workloads", "path_workloads", "line_workloads", "short_segments", "long_segments", "stars",
           "wiggly_outline", "run_bench", "format_table", "LINE_ORACLES", "CampaignMeasurement", "run_campaign_bench",
           "format_campaign_table", "campaign_summary", "CAMPAIGN_REFERENCE", "CAMPAIGN_SCENES", "CAMPAIGN_GOAL",
           "CAMPAIGN_BATCH", "CAMPAIGN_FAMILIES", "CAMPAIGN_REPEATS", "DEFAULT_TIMEOUT", "NothingMeasured", "failures_by_contender"]

SIZE = 1024
PATH_SIZE = 512
LINE_SIZE = 1024
DEFAULT_TIMEOUT = 60.0  # seconds one call of a contender may take (``--timeout``; as ``run``'s)


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
    paths for a path workload, segments for a line workload (``unit``).

    ``fault`` says why nothing was measured ("crashed (signal 11, SIGSEGV)", "timed out
    after 60 s", "raised ValueError: ...", "no coverage ..."; the figures are then NaN);
    ``note`` what was not counted of a measured answer (malformed spans)."""

    workload: str
    contender: str
    cold_seconds: float
    seconds: float
    triangles_per_second: float
    ratio_to_pillow: float
    pixels: int
    unit: str = "triangles"
    description: str = ""
    fault: str = ""
    note: str = ""


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
    return _installed(_LINE_PEERS)


def _path_peers() -> list[tuple[str, Callable[[PathScene], object]]]:
    """The aliased library path fills that are installed here."""
    return _installed(_PATH_PEERS)


# Every library peer, once: its label, the module it needs, and how it draws a workload.
_AA_PEERS = (("cairo_aa_fill", "cairo", _cairo_aa), ("skia_aa_fill", "skia", _skia_aa))
_LINE_PEERS = (("skimage_line", "skimage", _skimage_lines), ("cairo_line", "cairo", _cairo_lines),
               ("skia_hairline", "skia", _skia_lines))
_PATH_PEERS = (("cairo_fill", "cairo", _cairo_paths), ("skia_fill", "skia", _skia_paths),
               ("skimage_polygon", "skimage", _skimage_paths))


def missing_peers() -> dict[str, str]:
    """Each library peer not measured here because its module is missing, with the
    sentence naming the module and its install (:func:`harness.engine.optional.missing`).

    Returns
    -------
    dict of str to str
        ``{label: why}``, empty when every peer is installed.
    """
    peers = (*_AA_PEERS, *_LINE_PEERS, *_PATH_PEERS)
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


def _time(fn: Callable[[], object], budget: float, count: Callable[[object], int] = _pixels,
          heard: Callable[[float, object], None] | None = None) -> tuple[float, float, int, int]:
    """(cold seconds, best seconds, pixels, warm runs): only the drawing call is timed.

    Warm repeats run while the next one fits in the ``budget`` (at least one -- the cold
    call pays for compilation and is no throughput -- at most 50): the budget caps the
    time of the repeats, not only their count. ``count`` turns the cold call's answer into
    its pixels; ``heard`` hears each call's seconds and answer (outside the clock) as soon
    as it is made: the isolated contender's heartbeat (:func:`_serve_contender`)."""
    start = time.perf_counter()
    result = fn()
    cold = time.perf_counter() - start
    pixels = count(result)
    if heard is not None:
        heard(cold, result)
    best = float("inf")
    runs = 0
    deadline = time.perf_counter() + budget
    while runs < 50:
        left = deadline - time.perf_counter()
        if runs >= 1 and best > left:
            break  # the next repeat would overrun the budget
        start = time.perf_counter()
        again = fn()
        seconds = time.perf_counter() - start
        best = min(best, seconds)
        runs += 1
        if heard is not None:
            heard(seconds, again)
    return cold, best, pixels, runs


def _line_contenders(scene: LineScene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_lines, scene))]
    contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in LINE_ORACLES.items()]
    contenders += [(label, partial(draw, scene)) for label, draw in _line_peers()]
    return contenders


def _path_contenders(scene: PathScene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_paths, scene)),
                                                          ("oracle", partial(exact_coverage, scene, ORACLES["oracle"]))]
    contenders += [(label, partial(fill, scene)) for label, fill in _path_peers() if not _unmeasured(label, scene)]
    return contenders


def _triangle_contenders(scene: Scene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow, scene))]
    contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in ORACLES.items()]
    contenders += [(label, partial(fill, scene)) for label, fill in _library_peers()]
    return contenders


# The bench's contenders per scene kind: Pillow, the oracles, the kind's library peers.
_CONTENDERS: dict[str, Callable[[Any], list[tuple[str, Callable[[], object]]]]] = {
    "triangles": _triangle_contenders, "paths": _path_contenders, "lines": _line_contenders}


def _fixed_contenders(work: Workload) -> list[tuple[str, Callable[[], object]]]:
    """Pillow first (the yardstick), the oracles, then the library peers of the workload's
    scene kind."""
    return _CONTENDERS[work.scene.kind](work.scene)


def _contenders(work: Workload, rasterizers: list[Any]) -> list[tuple[str, Callable[[], object]]]:
    """Pillow first (the yardstick), the oracles, the library peers, then each rasterizer
    that takes the workload's scene."""
    scene = work.scene
    return _fixed_contenders(work) + [(r.name, partial(r.rasterize, scene)) for r in rasterizers if takes(r, scene)]


# -- isolation: every contender measured in a process of its own -------------------------------
#
# A rasterizer under bench is a plugin: it may raise, answer garbage, segfault, end its
# process or never answer. Every contender -- Pillow, the oracles, the library peers and the
# rasterizers alike -- is therefore measured in a forked process of its own (one per
# contender, kept from workload to workload so that kernels compiled or loaded by its first
# call stay loaded, as they did in one process; replaced after a crash or a timeout), each of
# its calls within the time limit (``--timeout``). The child runs the very timing loop the
# bench ran in its own process (:func:`_time`: the clock around the drawing call alone, a
# cold call first, then the warm repeats within the budget) and reports each call as it
# ends, so the figures and their ratios to Pillow are measured as before: the process's
# start-up, the pipe and the checks of an answer are outside the clock, and the parent
# waits idle while a child measures.
#
# Not :class:`harness.engine.isolation.Worker` itself: a Worker sends each scene and gets each
# answer back as a Coverage, while the library peers draw into surfaces that cannot cross
# a pipe (cairo's, skia's) and are counted where they were drawn. A rasterizer's answer is
# checked as a Worker's is (a Coverage, within :func:`harness.engine.isolation.span_limit` spans,
# tidied: :meth:`harness.contract.coverage.Coverage.tidy`), outside the clock, and its exceptions are
# described as the Worker's (:func:`harness.engine.isolation.describe`).


class _Unusable(Exception):
    """A contender's answer that is no measurement (its text is the row's fault)."""


def _one_line(text: str, most: int = 200) -> str:
    """``text`` on one line, at most ``most`` characters."""
    flat = " ".join(text.split())
    return flat if len(flat) <= most else flat[: most - 3] + "..."


def _counted(answer: object, scene: AnyScene) -> tuple[int, str]:
    """A rasterizer's first answer on ``scene``: its fragments once tidied (malformed spans
    not counted) and what was not counted, in words ("" when nothing); :class:`_Unusable`
    when it is no Coverage or holds more than :func:`span_limit` spans."""
    if not isinstance(answer, Coverage):
        raise _Unusable(f"no coverage (rasterize returned {type(answer).__name__}, not a harness.Coverage)")
    if len(answer) > span_limit(scene):
        raise _Unusable(f"garbage: an answer of {len(answer):,} spans ({len(scene):,} {scene.noun}s on "
                        f"{scene.height:,} rows need at most {span_limit(scene):,})")
    usable, flaws = answer.tidy(scene)
    if usable is answer:
        return int(usable.n_pixels), ""
    kinds = {kind: len(spans) for kind, spans in flaws.items() if kind != "repeated_pixels" and len(spans)}
    return int(usable.n_pixels), "not counted: " + ", ".join(f"{n:,} span{'s' if n > 1 else ''} {kind.replace('_', ' ')}"
                                                             for kind, n in kinds.items())


def _measure_here(fn: Callable[[], object], scene: AnyScene, budget: float, plugin: bool,
                  send: Callable[[tuple[Any, ...]], None]) -> tuple[Any, ...]:
    """In the contender's process: :func:`_time` on ``fn``, ``("call", seconds)`` sent
    after each call; ``("done", cold, best, pixels, runs, note)`` or ``("fault", text)``.
    A rasterizer's answers (``plugin``) must be Coverages, the first within the span limit."""
    notes: list[str] = []

    def count(answer: object) -> int:
        if not plugin:
            return _pixels(answer)
        pixels, note = _counted(answer, scene)
        notes.append(note)
        return pixels

    def heard(seconds: float, answer: object) -> None:
        if plugin and not isinstance(answer, Coverage):
            raise _Unusable(f"no coverage on a warm run (rasterize returned {type(answer).__name__}, not a harness.Coverage)")
        send(("call", seconds))

    try:
        with RECENT_ANSWERS.off():  # the oracles' repeats are timed computing, not looked up
            cold, best, pixels, runs = _time(fn, budget, count, heard)
    except _Unusable as exc:
        return ("fault", str(exc))
    except BaseException as exc:  # noqa: B036 - a plugin's KeyboardInterrupt or SystemExit is its failure
        return ("fault", f"raised {describe(exc)}")
    return ("done", cold, best, pixels, runs, notes[0] if notes else "")


def _serve_contender(calls: dict[str, tuple[Callable[[], object], AnyScene]], plugin: bool, conn: Any) -> None:  # pragma: no cover - runs in the child
    """The child of :class:`_Isolated`: for each workload asked (its name and the budget),
    :func:`_measure_here` on the call of that workload."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _exit_with_parent()
    while True:
        try:
            work, budget = conn.recv()
        except (EOFError, OSError):
            return
        fn, scene = calls[work]
        conn.send(_measure_here(fn, scene, budget, plugin, conn.send))


def _exit_fault(code: int | None) -> str:
    """A contender's process that ended without answering, in words.

    >>> _exit_fault(-11), _exit_fault(0)
    ('crashed (signal 11, SIGSEGV)', 'its process exited with code 0 without answering')
    """
    if code is not None and code < 0:
        try:
            name = f", {signal.Signals(-code).name}"
        except ValueError:
            name = ""
        return f"crashed (signal {-code}{name})"
    return f"its process exited with code {code} without answering"


class _Isolated:
    """One contender in a forked process of its own (started at its first workload,
    replaced after a crash or a timeout), each call within ``timeout`` seconds.

    Parameters
    ----------
    calls : dict
        ``{workload name: (the call, its scene)}``, inherited by the child (nothing is sent
        but the workload's name).
    plugin : bool
        The contender is a rasterizer: its answer must be a Coverage within the span limit.
    timeout : float
        The most seconds one call may take.
    """

    def __init__(self, calls: dict[str, tuple[Callable[[], object], AnyScene]], plugin: bool, timeout: float) -> None:
        self.calls = calls
        self.plugin = plugin
        self.timeout = timeout
        self._context = multiprocessing.get_context("fork")
        self._process: Any = None
        self._conn: Any = None

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._process = self._context.Process(target=_serve_contender, args=(self.calls, self.plugin, child), daemon=True)
        self._process.start()
        child.close()

    def measure(self, work: str, budget: float) -> tuple[Any, ...]:
        """``("done", cold, best, pixels, runs, note)`` or ``("fault", text)`` of the
        contender on ``work``."""
        if self._process is None:
            self._start()
        try:
            self._conn.send((work, budget))
        except OSError:
            return self._died()
        while True:
            try:
                if not self._conn.poll(self.timeout):
                    self.close()
                    return ("fault", f"timed out after {self.timeout:g} s")
                message = self._conn.recv()
            except (EOFError, OSError):
                return self._died()
            if message[0] != "call":
                return tuple(message)

    def _died(self) -> tuple[str, str]:
        self._process.join(5)
        code = self._process.exitcode
        self.close()
        return ("fault", _exit_fault(code))

    def close(self) -> None:
        """End the contender's process (a new one starts at the next workload)."""
        if self._process is None:
            return
        if self._process.is_alive():
            self._process.kill()
        self._process.join(5)
        self._conn.close()
        self._process = self._conn = None


def run_bench(names: list[str] | None = None, scale: float = 1.0, budget: float = 1.0,
              progress: Callable[[str], None] | None = None, paths: bool = True, lines: bool = True,
              triangles: bool = True, timeout: float = DEFAULT_TIMEOUT) -> list[Measurement]:
    """Measure Pillow, the oracle and each rasterizer on W1 and W2 (with ``triangles``),
    then (with ``paths``) Pillow, the winding oracle, the library path fills and each
    path-taking rasterizer on the path workloads, then (with ``lines``) Pillow, the three
    line oracles, the library line drawers and each line-taking rasterizer on the line
    workloads, each contender in a process of its own, each call within ``timeout``
    seconds; ``progress`` hears a line before and after each contender.

    A contender that crashes, hangs, raises or answers garbage on a workload is that
    workload's row (:attr:`Measurement.fault`) and the others go on; a workload whose
    Pillow failed has no ratios (NaN)."""
    from harness.engine.registry import distinct_names

    names = names if names is not None else builtins()
    rasterizers: list[Any] = distinct_names([load(n) for n in names])  # a path or line scene only to those that take it
    chosen = ((workloads(scale) if triangles else []) + (path_workloads(scale) if paths else [])
              + (line_workloads(scale) if lines else []))
    # each contender's calls, by workload: the key of a rasterizer is its place (a name of its
    # own may be any, "pillow" or "oracle" too)
    lineup: list[list[tuple[str, str, bool]]] = []  # per workload: (key, label, plugin)
    calls: dict[str, dict[str, tuple[Callable[[], object], AnyScene]]] = {}
    for work in chosen:
        entries = [(label, label, False, fn) for label, fn in _fixed_contenders(work)]
        entries += [(f"rasterizer {k}", r.name, True, partial(r.rasterize, work.scene)) for k, r in enumerate(rasterizers)
                    if takes(r, work.scene)]
        lineup.append([(key, label, plugin) for key, label, plugin, _ in entries])
        for key, _, _, fn in entries:
            calls.setdefault(key, {})[work.name] = (fn, work.scene)
    last = {key: k for k, row in enumerate(lineup) for key, _, _ in row}
    isolated: dict[str, _Isolated] = {}
    results = []
    nan = float("nan")
    try:
        for k, (work, row) in enumerate(zip(chosen, lineup)):
            unit = f"{work.scene.noun}s"  # triangles, paths, segments
            if progress is not None and PATHS.owns(work.scene):
                for label, _ in _path_peers():
                    if _unmeasured(label, work.scene):
                        progress(f"{work.name} {label}: {_unmeasured(label, work.scene)}")
            pillow_rate = nan
            for place, (key, label, plugin) in enumerate(row):
                if progress is not None:
                    progress(f"{work.name} {label}: measuring ...")
                if key not in isolated:
                    isolated[key] = _Isolated(calls[key], plugin, timeout)
                contender = isolated[key]
                answer = contender.measure(work.name, budget)
                if last[key] == k:
                    contender.close()
                if answer[0] == "fault":
                    fault = _one_line(answer[1])
                    if progress is not None:
                        progress(f"{work.name} {label}: {fault}")
                    results.append(Measurement(work.name, label, nan, nan, nan, nan, 0, unit, work.description, fault=fault))
                    continue
                _, cold, seconds, pixels, runs, note = answer
                if progress is not None:
                    progress(f"{work.name} {label}: best {seconds * 1e3:.1f} ms of {runs} warm runs (cold {cold:.2f} s)")
                rate = len(work.scene) / seconds
                if place == 0:
                    pillow_rate = rate
                results.append(Measurement(work.name, label, cold, seconds, rate, rate / pillow_rate, pixels, unit,
                                           work.description, note=note))
    finally:
        for contender in isolated.values():
            contender.close()
    return results


def failures_by_contender(results: Sequence[Measurement]) -> dict[str, str]:
    """One line per contender that failed on some workload: its faults and where, and
    whether anything of it was measured.

    >>> bad = Measurement("W1", "mine", 0, 0, 0, 0, 0, fault="raised ValueError: no")
    >>> failures_by_contender([bad, replace(bad, workload="W2")])
    {'mine': 'nothing measured: raised ValueError: no (W1, W2)'}
    """
    out = {}
    for contender in dict.fromkeys(m.contender for m in results if m.fault):
        mine = [m for m in results if m.contender == contender]
        by_fault: dict[str, list[str]] = {}
        for m in mine:
            if m.fault:
                by_fault.setdefault(m.fault, []).append(m.workload)
        said = "; ".join(f"{fault} ({', '.join(works)})" for fault, works in by_fault.items())
        measured = [m.workload for m in mine if not m.fault]
        out[contender] = (f"{said}; measured on {', '.join(measured)}" if measured else f"nothing measured: {said}")
    return out


def _figure(value: float, spec: str) -> str:
    """``value`` formatted by ``spec``, or ``-`` when it is not a number."""
    return format(value, spec) if math.isfinite(value) else "-"


def format_table(results: list[Measurement], descriptions: dict[str, str]) -> str:
    """One block per workload: each contender's rate, ratio to Pillow, best and cold time
    and pixels, or why it has none; a workload missing from ``descriptions`` is described
    by its measurements."""
    lines = []
    for work in dict.fromkeys(m.workload for m in results):
        mine = [m for m in results if m.workload == work]
        lines.append(f"{work}: {descriptions.get(work) or mine[0].description}")
        lines.append(f"  {'contender':<18}{mine[0].unit + '/s':>14}{'x Pillow':>10}{'best ms':>10}{'cold s':>9}{'pixels':>11}")
        for m in mine:
            if m.fault:
                lines.append(f"  {m.contender:<18}  {m.fault}")
                continue
            lines.append(
                f"  {m.contender:<18}{m.triangles_per_second:>14,.0f}{_figure(m.ratio_to_pillow, '>10.2f'):>10}"
                f"{m.seconds * 1e3:>10.2f}{m.cold_seconds:>9.2f}{m.pixels:>11,}" + (f"   ({m.note})" if m.note else "")
            )
    return "\n".join(lines)


def _finite(row: dict[str, Any]) -> dict[str, Any]:
    """``row`` with every non-finite float as None (JSON has no NaN)."""
    return {k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in row.items()}


def write_json(results: Sequence[Measurement | CampaignMeasurement], path: Path, summary: dict[str, Any] | None = None,
               not_measured: dict[str, str] | None = None) -> None:
    """The measurements as JSON (schema 1), with the machine and the date; ``summary``
    (e.g. the campaign's speed-up, :func:`campaign_summary`) goes in as ``"summary"``,
    the peers not measured, with why (:func:`missing_peers`), as ``"not_measured"``, and
    the rows of contenders that failed (their ``fault``) as ``"failed"``, not among the
    ``"results"``."""
    from harness.results.files import atomic_write_text

    payload: dict[str, Any] = {
        "schema": 1,
        "machine": {"platform": platform.platform(), "python": platform.python_version(), "cpus": os.cpu_count()},
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "results": [_finite(asdict(m)) for m in results if not getattr(m, "fault", "")],
    }
    failed = [{"workload": m.workload, "contender": m.contender, "fault": m.fault} for m in results
              if isinstance(m, Measurement) and m.fault]
    if failed:
        payload["failed"] = failed
    if summary is not None:
        payload["summary"] = summary
    if not_measured:
        payload["not_measured"] = not_measured
    atomic_write_text(path, json.dumps(payload, indent=2))



# -- campaigns: end-to-end checked primitives per second, one worker against two ---------------

CAMPAIGN_REFERENCE = "pineda_topleft"  # a built-in that passes: no finding, nothing shrunk
CAMPAIGN_SCENES = 3000  # about 20 s of search on one worker here: a run long enough that its fixed costs (the first and last batches) weigh as little as in a campaign of minutes
CAMPAIGN_GOAL = 1.7  # the speed-up from one worker to two that the issue asks for
CAMPAIGN_REPEATS = 3  # rounds of 1 then 2 workers; the fastest run of each is kept
CAMPAIGN_BATCH = 25  # scenes per batch, fixed: both campaigns check the very same scenes (0.1 .. 0.7 s a batch here)
CAMPAIGN_FAMILIES: tuple[str, ...] | None = None  # None: every fuzz family (those the rasterizer does not take are skipped)
CAMPAIGN_SEED = 0
WARM_SEED = 1  # the warm-up's scenes: not among those measured


@dataclass(frozen=True, slots=True)
class CampaignMeasurement:
    """One campaign of the fixed scene budget on ``workers`` local worker processes.

    ``seconds`` runs from the first batch sent to the last one merged (the coordinator's
    own clock, :class:`harness.campaign.campaign.ProgressEvent`); ``startup_seconds`` is what
    starting and warming the workers took before it. ``primitives`` are those checked
    (triangles, and every frame's of a motion sequence); ``per_worker`` is
    ``primitives_per_second / workers``; ``speedup`` the primitives per second against
    the first measurement's (one worker); ``runs`` the seconds of every run of this
    count (the measurement is the fastest)."""

    workload: str
    contender: str
    workers: int
    scenes: int
    primitives: int
    findings: int
    seconds: float
    startup_seconds: float
    scenes_per_second: float
    primitives_per_second: float
    per_worker: float
    speedup: float
    unit: str = "primitives"
    description: str = ""
    runs: tuple[float, ...] = ()
    failed_calls: int = 0


class NothingMeasured(RuntimeError):
    """The rasterizer under a campaign bench failed every call of its warm-up: there is no
    throughput to measure (its text is the one line that says so)."""


def _failed_call(finding: Any) -> bool:
    """A finding of a rasterize call that crashed, hung or raised (or answered no
    coverage): the ``run`` check's errors (:func:`harness.campaign.campaign.run_batch`)."""
    return bool(finding.status == "error" and finding.check_name == "run")


def _warm(client: Client, spec: str, families: Sequence[str], timeout: float) -> None:
    """Every worker imports the harness, loads ``spec`` and checks one scene of each
    family (kernels loaded, trimesh imported), so that the clock measures the search.

    Raises :class:`NothingMeasured` when every one of those scenes' rasterize calls failed
    (crashed, hung, raised, answered no coverage): a campaign of failed calls would time
    failures, not checks."""
    from harness.campaign.campaign import Batch, CampaignTask, run_batch

    addresses = sorted(client.scheduler_info()["workers"])
    futures = [client.submit(run_batch, CampaignTask(spec, Batch(family, WARM_SEED, 0, 1), timeout=timeout),
                             workers=[address], allow_other_workers=False, pure=False)
               for address in addresses for family in families]
    batches = client.gather(futures)
    failed = [f for batch in batches for f in batch.findings if _failed_call(f)]
    if batches and all(any(_failed_call(f) for f in batch.findings) for batch in batches):
        faults = list(dict.fromkeys(_one_line(f.message, 160) for f in failed))
        raise NothingMeasured(f"{spec}: nothing measured: every rasterize call of the warm-up failed "
                              f"({len(batches)} scene{'s' if len(batches) > 1 else ''}: {'; '.join(faults[:3])})")


def _failed_calls(signatures: dict[str, dict[str, Any]]) -> int:
    """The findings of failed rasterize calls among a campaign's ``signatures``."""
    return sum(int(entry.get("count", 0)) for entry in signatures.values() if entry.get("check") == "run")


def run_campaign_bench(spec: str = CAMPAIGN_REFERENCE, scenes: int = CAMPAIGN_SCENES, worker_counts: Sequence[int] = (1, 2),
                       families: Sequence[str] | None = None, batch_size: int = CAMPAIGN_BATCH, repeats: int = CAMPAIGN_REPEATS,
                       timeout: float = 60.0, progress: Callable[[str], None] | None = None) -> list[CampaignMeasurement]:
    """The same campaign (``scenes`` scenes of ``families``, default all, under seed 0, in
    batches of ``batch_size``: the same scenes whatever the workers) on a fresh local
    cluster of each worker count in turn, each in a state folder of its own; the whole
    round ``repeats`` times, and the fastest run of each count kept (other processes on
    the machine only ever slow a run down: the rounds interleave the counts, so a busy
    spell costs each the same).

    Parameters
    ----------
    spec : str
        The rasterizer (:func:`harness.engine.registry.load`); a built-in reference by default.
    scenes : int
        The scene budget of each campaign.
    worker_counts : sequence of int
        Worker processes of each cluster, in order; the speed-ups are against the first.
    families : sequence of str, optional
        Fuzz families (:data:`cases.fuzz.FAMILIES`); those the rasterizer does not take
        are skipped by the campaign.
    batch_size : int
        Scenes per batch (fixed, unlike a campaign's default: with sizes adapted to the
        time measured the two campaigns would check different scenes).
    repeats : int
        Rounds over the worker counts.
    progress : callable, optional
        Hears a line before and after each measurement.

    Returns
    -------
    list of CampaignMeasurement
        One per worker count, in order: its fastest run (``runs``: the seconds of each).

    Raises
    ------
    NothingMeasured
        When every rasterize call of the warm-up failed (:func:`_warm`).
    """
    from cases.fuzz import FAMILIES
    from harness.campaign.campaign import ProgressEvent, run_campaign

    if scenes < 1:
        raise ValueError(f"the campaign bench needs at least one scene, not {scenes}")
    if not worker_counts or any(n < 1 for n in worker_counts):
        raise ValueError(f"worker counts must be at least 1, not {list(worker_counts)}")
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, not {repeats}")
    chosen = tuple(families or CAMPAIGN_FAMILIES or FAMILIES)
    best: dict[int, CampaignMeasurement] = {}
    runs: dict[int, list[float]] = {n: [] for n in worker_counts}
    for round_ in range(repeats):
        for workers in worker_counts:
            said = f"campaign on {workers} worker{'s' if workers > 1 else ''} (round {round_ + 1} of {repeats})"
            if progress is not None:
                progress(f"{said}: starting and warming the workers ...")
            started = time.perf_counter()
            with local_cluster(workers) as client, tempfile.TemporaryDirectory(prefix="rastercheck-bench-") as state_dir:
                _warm(client, spec, chosen, timeout)
                startup = time.perf_counter() - started
                events: list[ProgressEvent] = []
                state = run_campaign(spec, budget_scenes=scenes, families=chosen, seed=CAMPAIGN_SEED, state_dir=state_dir,
                                     scheduler=client, batch_size=batch_size, timeout=timeout, on_progress=events.append)
            last = events[-1] if events else None
            seconds = last.elapsed if last is not None else 0.0
            checked = last.scenes if last is not None else 0
            primitives = last.primitives if last is not None else 0
            rate = primitives / seconds if seconds > 0 else 0.0
            runs[workers].append(round(seconds, 3))
            taken = [f for f in chosen if f not in state.skipped]
            measured = CampaignMeasurement(
                "campaign", spec, workers, checked, primitives, state.findings, seconds, startup,
                checked / seconds if seconds > 0 else 0.0, rate, rate / workers, 0.0, failed_calls=_failed_calls(state.signatures),
                description=(f"{scenes:,} fuzz scenes of {', '.join(taken) or 'no family'} (seed {CAMPAIGN_SEED}, batches of "
                             f"{batch_size}), checked end to end; the fastest of {repeats} run{'s' if repeats > 1 else ''}"))
            if workers not in best or measured.primitives_per_second > best[workers].primitives_per_second:
                best[workers] = measured
            if progress is not None:
                progress(f"{said}: {checked:,} scenes, {primitives:,} primitives in {seconds:.1f} s ({rate:,.0f} primitives/s; "
                         f"startup {startup:.1f} s)")
    base = best[worker_counts[0]].primitives_per_second
    return [replace(best[n], speedup=best[n].primitives_per_second / base if base > 0 else 0.0, runs=tuple(runs[n]))
            for n in dict.fromkeys(worker_counts)]


def _unjudged(results: Sequence[CampaignMeasurement]) -> str:
    """Why no speed-up can be judged from ``results`` ("" when one can): rasterize calls
    that failed in them."""
    failed = sum(m.failed_calls for m in results)
    if not failed:
        return ""
    return (f"{failed:,} finding{'s' if failed > 1 else ''} of failed rasterize calls (crashed, hung or raised) "
            f"in the campaigns: the figures time failures")


def campaign_summary(results: Sequence[CampaignMeasurement]) -> dict[str, Any]:
    """The speed-up from the first worker count to the last, against the goal (not met,
    and why, when rasterize calls failed in the campaigns)."""
    if len(results) < 2:
        return {"goal": CAMPAIGN_GOAL}
    first, last = results[0], results[-1]
    why = _unjudged(results)
    return {"from_workers": first.workers, "to_workers": last.workers, "speedup": round(last.speedup, 3),
            "goal": CAMPAIGN_GOAL, "met": not why and last.speedup >= CAMPAIGN_GOAL, **({"not_judged": why} if why else {})}


def format_campaign_table(results: Sequence[CampaignMeasurement]) -> str:
    """The campaign measurements, one line per worker count, and the speed-up."""
    if not results:
        return "campaign: nothing measured"
    lines = [f"campaign: {results[0].contender}, {results[0].description}",
             f"  {'workers':>7}{'scenes':>9}{'primitives':>12}{'seconds':>9}{'scenes/s':>10}{'primitives/s':>14}"
             f"{'per worker':>12}{'speed-up':>10}{'startup s':>11}"]
    for m in results:
        lines.append(f"  {m.workers:>7}{m.scenes:>9,}{m.primitives:>12,}{m.seconds:>9.1f}{m.scenes_per_second:>10.1f}"
                     f"{m.primitives_per_second:>14,.0f}{m.per_worker:>12,.0f}{m.speedup:>9.2f}x{m.startup_seconds:>11.1f}"
                     + (f"   runs: {', '.join(f'{r:.1f}' for r in m.runs)} s" if len(m.runs) > 1 else ""))
    why = _unjudged(results)
    if why:
        lines.append(f"speed-up not judged: {why}")
    elif len(results) > 1:
        last = results[-1]
        verdict = "met" if last.speedup >= CAMPAIGN_GOAL else "NOT met"
        lines.append(f"speed-up from {results[0].workers} to {last.workers} workers: {last.speedup:.2f}x "
                     f"(goal >= {CAMPAIGN_GOAL}x: {verdict})")
    return "\n".join(lines)
