"""The bench's workloads (:mod:`harness.cli.bench`), fixed seeds: triangles (W1, W2;
:func:`workloads`), paths ({10/3} stars, a wiggly outline and glyph-like outlines, P1, P2
and P3; :func:`path_workloads`)
lines (short and long segments, L1 and L2; :func:`line_workloads`) and anti-aliased
strokes (S1 and S2; :func:`stroke_workloads`), each a :class:`Workload` with its mean
primitive size.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from cases.scenes import random_triangles
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene

__all__ = ["Workload", "workloads", "path_workloads", "line_workloads", "short_segments", "long_segments", "stars",
           "wiggly_outline", "glyphs", "stroke_workloads", "wide_segments", "SIZE", "PATH_SIZE", "LINE_SIZE",
           "STROKE_SIZE"]

if TYPE_CHECKING:
    pass


SIZE = 1024
PATH_SIZE = 512
LINE_SIZE = 1024
STROKE_SIZE = 512


@dataclass(frozen=True, slots=True)
class Workload:
    """A scene to time; ``mean_area`` is per primitive (for a path, the magnitude of its
    signed area: the integral of its winding number; for a segment, its length in px)."""

    name: str
    description: str
    scene: AnyScene
    mean_area: float
    anti_aliased: bool = False  # a line workload of anti-aliased strokes (its own contenders)


def workloads(scale: float = 1.0) -> list[Workload]:
    """W1 and W2; ``scale`` < 1 shrinks the triangle counts (for smoke tests)."""
    out = []
    for name, count, area, seed in (("W1", 10_000, 50.0, 1), ("W2", 100, 100_000.0, 2)):
        n = max(1, int(count * scale))
        positions = random_triangles(n, area, SIZE, seed)
        p = positions
        areas = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1])
                             * (p[:, 2, 0] - p[:, 0, 0]))
        out.append(Workload(name, f"{n} triangles, mean area {areas.mean():,.0f} px", Scene(SIZE, SIZE, positions),
                            float(areas.mean())))
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


def glyphs(count: int, size: int, seed: int) -> PathScene:
    """``count`` glyph-like outlines, as a font renderer fills them: an "o" (an outer
    ellipse and its counter, wound against it, each flattened to 24 short edges) crossed by
    a bar (4 edges) overlapping both, as variable fonts' overlapping contours do, with
    random centres on the ``size`` x ``size`` screen and heights 6 to 30 px; fill rule
    nonzero (under even-odd the bar's overlap with the ring is a hole).

    >>> scene = glyphs(2, 64, 0)
    >>> len(scene), scene.contour_sizes.tolist()
    (2, [24, 24, 4, 24, 24, 4])
    """
    rng = np.random.default_rng(seed)
    t = np.arange(24) * (2.0 * np.pi / 24)
    ring = np.stack([np.cos(t), np.sin(t)], axis=-1)
    contours, sizes = [], []
    for cx, cy, s in zip(rng.uniform(16.0, size - 16.0, count), rng.uniform(16.0, size - 16.0, count),
                         rng.uniform(3.0, 15.0, count)):
        outer = np.array([cx, cy]) + ring * [0.9 * s, s]
        inner = (np.array([cx, cy]) + ring * [0.55 * s, 0.6 * s])[::-1]
        bar = np.array([[cx - 1.05 * s, cy - 0.12 * s], [cx + 1.05 * s, cy - 0.12 * s],
                        [cx + 1.05 * s, cy + 0.12 * s], [cx - 1.05 * s, cy + 0.12 * s]])
        contours += [outer, inner, bar]
        sizes += [24, 24, 4]
    return PathScene(size, size, np.concatenate(contours) if contours else np.zeros((0, 2)), np.array(sizes, dtype=np.int64),
                     np.repeat(np.arange(count, dtype=np.int64), 3))


def _signed_areas(scene: PathScene) -> NDArray[np.float64]:
    """(P,) each path's signed area (shoelace over its contours)."""
    a, b, path = scene.edges()
    return np.asarray(np.bincount(path, weights=(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]) / 2.0, minlength=len(scene)),
                      dtype=np.float64)


def path_workloads(scale: float = 1.0) -> list[Workload]:
    """P1 (stars), P2 (the 100,000-vertex outline) and P3 (1,000 glyph-like outlines), each
    under nonzero then even-odd; ``scale`` < 1 shrinks the star and glyph counts and the
    outline's vertices (for smoke tests)."""
    n = max(1, int(1000 * scale))
    v = max(64, int(100_000 * scale))
    out = []
    for name, scene, what in (("P1", stars(n, PATH_SIZE, 3), f"{n} {{10/3}} stars of 10 vertices"),
                              ("P2", wiggly_outline(v, PATH_SIZE), f"one self-intersecting outline of {v:,} vertices"),
                              ("P3", glyphs(n, PATH_SIZE, 4), f"{n} glyph-like outlines (a ring, its counter and an overlapping "
                                                              f"bar: 52 edges each)")):
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
        out.append(Workload(name, f"{n:,} {what}, mean length {length:,.1f} px, width 1, {LINE_SIZE} x {LINE_SIZE}", scene,
                            length))
    return out


def wide_segments(count: int, size: int, seed: int, line_width: float) -> LineScene:
    """``count`` segments of lengths 4 to 64 px in random directions, each a strip of its
    own, stroked ``line_width`` wide: every end point at least ``line_width`` from the
    ``size`` x ``size`` screen's border (no peer clips).

    >>> scene = wide_segments(3, 128, 0, 2.5)
    >>> len(scene), scene.line_width
    (3, 2.5)
    """
    rng = np.random.default_rng(seed)
    angle = rng.uniform(0.0, 2.0 * np.pi, size=count)
    length = rng.uniform(4.0, 64.0, size=count)
    step = length[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
    low, high = line_width - np.minimum(step, 0.0), size - line_width - np.maximum(step, 0.0)
    start = low + rng.uniform(0.0, 1.0, size=(count, 2)) * (high - low)
    return LineScene.from_segments(size, size, start, start + step, line_width=line_width)


def stroke_workloads(scale: float = 1.0) -> list[Workload]:
    """S1 and S2: 1,000 anti-aliased segments of widths 1.5 and 4 (butt caps), for the
    exact stroke-area oracle against the libraries' anti-aliased strokes; ``scale`` < 1
    shrinks the counts (for smoke tests)."""
    out = []
    n = max(1, int(1000 * scale))
    for name, w, seed in (("S1", 1.5, 6), ("S2", 4.0, 7)):
        scene = wide_segments(n, STROKE_SIZE, seed, w)
        a, b = scene.segments()
        length = float(np.hypot(*(b - a).T).mean())
        out.append(Workload(name, f"{n:,} anti-aliased segments, mean length {length:,.1f} px, width {w:g}, butt caps, "
                                  f"{STROKE_SIZE} x {STROKE_SIZE}", scene, length, anti_aliased=True))
    return out
