"""Per-primitive masks drawn by a library into a small image around the primitive's box:
one triangle (:func:`draw_each`), one whole path, all its contours in one fill
(:func:`draw_each_path`), or one line segment (:func:`draw_each_segment`)."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene

__all__ = ["LIMIT", "draw_each", "draw_each_alpha", "draw_each_path", "draw_each_segment", "segment_boxes", "path_contours",
           "path_extents", "coverage_from_fragments", "coverage_from_sample_masks", "finite_within_limit"]

# Libraries keep coordinates in float32 or fixed point: beyond this they are refused with a
# ValueError naming the triangle (a guard band), never drawn wrong.
LIMIT = 2.0**20


def finite_within_limit(scene: AnyScene, name: str) -> NDArray[np.bool_]:
    """(N,) bool: which primitives (triangles, paths or segments) are finite.
    Raises ValueError naming the first finite triangle (path, segment) with a coordinate beyond
    :data:`LIMIT` (refused, never drawn wrong)."""
    if not isinstance(scene, Scene):
        lo, hi, finite = path_extents(scene) if isinstance(scene, PathScene) else scene.primitive_boxes()
        beyond = finite & (np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, initial=0.0) > LIMIT)
        if beyond.any():
            k = int(np.flatnonzero(beyond)[0])
            raise ValueError(f"{name}: {scene.noun} {k} has a coordinate beyond +/-{LIMIT:g} px (box {lo[k].tolist()} .. "
                             f"{hi[k].tolist()}); the library's coordinates would lose precision or overflow")
        return finite
    positions = scene.positions
    finite_triangles: NDArray[np.bool_] = np.all(np.isfinite(positions), axis=(1, 2))
    too_big = finite_triangles & np.any(np.abs(positions) > LIMIT, axis=(1, 2))
    if too_big.any():
        t = int(np.flatnonzero(too_big)[0])
        raise ValueError(f"{name}: triangle {t} has a coordinate beyond +/-{LIMIT:g} px ({positions[t].tolist()}); "
                         "the library's coordinates would lose precision or overflow")
    return finite_triangles


def _boxes(scene: Scene, name: str, margin: int) -> Iterator[tuple[int, NDArray[np.float64], int, int, int, int]]:
    """(t, vertices, x0, y0, x1, y1) for every triangle whose box within the viewport is
    not empty: its bounding box widened by ``margin`` px, or the whole screen for a
    non-finite triangle (raises as :func:`finite_within_limit` does)."""
    positions = scene.positions
    finite = finite_within_limit(scene, name)
    for t in range(len(scene)):
        p = positions[t]
        if not finite[t]:
            x0, y0, x1, y1 = 0, 0, scene.width, scene.height
        else:
            x0 = int(np.clip(np.floor(p[:, 0].min()) - margin, 0, scene.width))
            y0 = int(np.clip(np.floor(p[:, 1].min()) - margin, 0, scene.height))
            x1 = int(np.clip(np.ceil(p[:, 0].max()) + margin, 0, scene.width))
            y1 = int(np.clip(np.ceil(p[:, 1].max()) + margin, 0, scene.height))
        if x0 >= x1 or y0 >= y1:
            continue
        yield t, p, x0, y0, x1, y1


def draw_each(scene: Scene, name: str, draw: Callable[[NDArray[np.float64], int, int, tuple[int, int]], NDArray[np.bool_]],
              margin: int = 2) -> Coverage:
    """Call ``draw(vertices relative to the box origin, box width, box height, origin)`` for
    each triangle; it returns the box's (h, w) bool mask. Spans come back in screen
    coordinates, clipped to the viewport. A triangle with a NaN or infinite coordinate is
    handed to the library unchanged, with the whole screen as its box, so that what the
    library does with it (draws nothing, raises, or draws garbage) is what the checks see."""
    parts = []
    for t, p, x0, y0, x1, y1 in _boxes(scene, name, margin):
        try:
            mask = draw(p - np.array([x0, y0], dtype=np.float64), x1 - x0, y1 - y0, (x0, y0))
        except Exception as exc:  # name the triangle the library failed on
            raise RuntimeError(f"{name}: the library failed on triangle {int(t)} {p.tolist()}: "
                               f"{type(exc).__name__}: {exc}") from exc
        if mask.any():
            cov = Coverage.from_mask(int(t), mask)
            parts.append((cov.triangle, cov.y + y0, cov.x0 + x0, cov.x1 + x0))
    if not parts:
        return Coverage.empty()
    return Coverage(*(np.concatenate([part[i] for part in parts]) for i in range(4)))


def path_extents(scene: PathScene) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """:meth:`PathScene.primitive_boxes` (per path ``lo, hi`` (P, 2) over its finite
    coordinates, and whether all are finite (P,)), reduced per contour first
    (``reduceat`` over contiguous vertices: 100,000 vertices in 2 ms, not 60).

    >>> scene = PathScene.from_paths(9, 9, [[[[1, 5], [3, 2]], [[np.nan, 7], [0, 6]]], [[[4, 4]]]])
    >>> lo, hi, finite = path_extents(scene)
    >>> lo.tolist(), hi.tolist(), finite.tolist()
    ([[0.0, 2.0], [4.0, 4.0]], [[3.0, 7.0], [4.0, 4.0]], [False, True])
    """
    n = len(scene)
    vertices = scene.vertices
    finite_coordinate = np.isfinite(vertices)
    safe = np.where(finite_coordinate, vertices, 0.0)  # as primitive_boxes: a non-finite coordinate counts as 0
    starts = scene.contour_starts
    lo, hi = np.full((n, 2), np.inf), np.full((n, 2), -np.inf)
    finite = np.ones(n, dtype=bool)
    if starts.size:
        np.minimum.at(lo, scene.contour_path, np.minimum.reduceat(safe, starts, axis=0))
        np.maximum.at(hi, scene.contour_path, np.maximum.reduceat(safe, starts, axis=0))
        whole = np.logical_and.reduceat(finite_coordinate.all(axis=1), starts)
        np.logical_and.at(finite, scene.contour_path, whole)
    return lo, hi, finite


def path_contours(scene: PathScene) -> list[list[NDArray[np.float64]]]:
    """Each path's contours ((K, 2) views), in the scene's order, grouped in one pass.

    >>> scene = PathScene.from_paths(4, 4, [[[[0, 0], [1, 0], [0, 1]]], [[[2, 2], [3, 2], [2, 3]], [[0, 0]]]])
    >>> [[c.shape[0] for c in path] for path in path_contours(scene)]
    [[3], [3, 1]]
    """
    every = scene.contours()
    grouped: list[list[NDArray[np.float64]]] = [[] for _ in range(len(scene))]
    for c, k in enumerate(scene.contour_path.tolist()):
        grouped[k].append(every[c])
    return grouped


def path_boxes(scene: PathScene, name: str, margin: int) -> Iterator[tuple[int, list[NDArray[np.float64]], int, int, int, int]]:
    """(k, contours, x0, y0, x1, y1) for every path whose box within the viewport is not
    empty: as :func:`_boxes` for triangles (the path's bounding box over all its contours
    widened by ``margin`` px and clipped to the viewport; the whole screen for a path with
    a non-finite vertex; ValueError naming a path beyond :data:`LIMIT`)."""
    finite = finite_within_limit(scene, name)
    lo, hi, _ = path_extents(scene)
    size = np.array([scene.width, scene.height])
    with np.errstate(invalid="ignore"):
        first = np.where(finite[:, None], np.clip(np.floor(np.where(finite[:, None], lo, 0.0)) - margin, 0, size), 0)
        last = np.where(finite[:, None], np.clip(np.ceil(np.where(finite[:, None], hi, 0.0)) + margin, 0, size), size)
    contours = path_contours(scene)
    for k in np.flatnonzero(np.all(first < last, axis=1)).tolist():
        yield k, contours[k], int(first[k, 0]), int(first[k, 1]), int(last[k, 0]), int(last[k, 1])


def draw_each_path(scene: PathScene, name: str,
                   draw: Callable[[list[NDArray[np.float64]], int, int, tuple[int, int]], NDArray[np.bool_]],
                   margin: int = 2) -> Coverage:
    """Call ``draw(contours relative to the box origin, box width, box height, origin)``
    once per path, every contour of the path in that one call (the library fills them
    together under the scene's fill rule); it returns the box's (h, w) bool mask. As
    :func:`draw_each` for triangles: the box is the path's bounding box (all its contours)
    widened by ``margin`` px and clipped to the viewport, so a huge path mostly off-screen
    costs only its visible part; the origin is a whole pixel, so shifting by it is exact
    (x - x0 with x0 an integer and |x| <= :data:`LIMIT` is a float); a path with a NaN or
    infinite vertex is handed over unchanged with the whole screen as its box; a library
    failure is raised as RuntimeError naming the path.

    Examples
    --------
    >>> def box(contours, w, h, origin):  # a "library" that fills its whole box
    ...     return np.ones((h, w), dtype=bool)
    >>> scene = PathScene.from_paths(6, 3, [[[[1, 0], [2, 0], [2, 1]], [[3, 0], [3, 1], [4, 1]]]])
    >>> cov = draw_each_path(scene, "box", box, margin=0)
    >>> cov.primitive.tolist(), cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist()
    ([0], [0], [1], [4])
    """
    parts = []
    for k, contours, x0, y0, x1, y1 in path_boxes(scene, name, margin):
        origin = np.array([x0, y0], dtype=np.float64)
        try:
            mask = draw([c - origin for c in contours], x1 - x0, y1 - y0, (x0, y0))
        except Exception as exc:  # name the path the library failed on
            raise RuntimeError(f"{name}: the library failed on path {k} ({len(contours)} contours, "
                               f"{sum(c.shape[0] for c in contours)} vertices): {type(exc).__name__}: {exc}") from exc
        if mask.any():
            cov = Coverage.from_mask(k, mask)
            parts.append((cov.primitive, cov.y + y0, cov.x0 + x0, cov.x1 + x0))
    if not parts:
        return Coverage.empty()
    return Coverage(*(np.concatenate([part[i] for part in parts]) for i in range(4)))


def segment_boxes(scene: LineScene, name: str, margin: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Each segment's box within the viewport and which segments to draw.

    The box is the segment's bounding box grown by half the line width
    (:meth:`LineScene.primitive_boxes`), widened to whole pixels plus ``margin`` px and
    clipped to the viewport. Raises ValueError naming the first finite segment with a
    coordinate beyond :data:`LIMIT` (:func:`finite_within_limit`).

    Returns
    -------
    boxes : (N, 4) int64
        ``x0, y0, x1, y1`` per segment (garbage where not drawn).
    drawn : (D,) int64
        The segments to draw, ascending: finite ones whose box is not empty. A segment with
        a NaN or infinite coordinate is never handed to the library and covers nothing.

    Examples
    --------
    >>> scene = LineScene.from_segments(8, 8, [[1.5, 1.5], [np.nan, 0], [-9, 2]], [[3.5, 2.5], [1, 1], [-5, 3]])
    >>> boxes, drawn = segment_boxes(scene, "lib", margin=1)
    >>> boxes[0].tolist(), drawn.tolist()
    ([0, 0, 5, 4], [0])
    """
    finite = finite_within_limit(scene, name)
    lo, hi, _ = scene.primitive_boxes()
    size = np.array([scene.width, scene.height])
    with np.errstate(invalid="ignore"):
        first = np.clip(np.floor(np.where(finite[:, None], lo, 0.0)) - margin, 0, size).astype(np.int64)
        last = np.clip(np.ceil(np.where(finite[:, None], hi, 0.0)) + margin, 0, size).astype(np.int64)
    drawn = np.flatnonzero(finite & np.all(first < last, axis=1))
    return np.concatenate([first, last], axis=1), drawn


def draw_each_segment(scene: LineScene, name: str,
                      draw: Callable[[NDArray[np.float64], NDArray[np.float64], int, int, tuple[int, int]], NDArray[np.bool_]],
                      margin: int = 2) -> Coverage:
    """Call ``draw(a, b, box width, box height, origin)`` once per segment, its end points
    ``a -> b`` ((2,) float64 each) relative to the box origin; it returns the box's (h, w)
    bool mask. Each segment is drawn alone into its own image, so a pixel two segments
    draw (a polyline's joint) comes back once per segment: a double hit stays visible.

    The box (:func:`segment_boxes`) is the segment's bounding box grown by half the line
    width and ``margin`` px, clipped to the viewport; its origin is a whole pixel, so
    shifting by it is exact (x - x0, x0 an integer and |x| <= :data:`LIMIT`), and is 0 on
    an axis where the segment reaches below 0 (relative coordinates are negative only where
    the screen's are). A segment with a NaN or infinite end point covers nothing (the
    library is not asked); a library failure is raised as RuntimeError naming the segment.

    Examples
    --------
    >>> def ends(a, b, w, h, origin):  # a "library" that draws the pixels holding the end points
    ...     mask = np.zeros((h, w), dtype=bool)
    ...     for p in (a, b):
    ...         mask[int(p[1]), int(p[0])] = True
    ...     return mask
    >>> scene = LineScene.from_strips(8, 4, [[[1.5, 0.5], [4.5, 2.5], [6.5, 2.5]]])
    >>> cov = draw_each_segment(scene, "ends", ends)
    >>> cov.primitive.tolist(), cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist()
    ([0, 0, 1, 1], [0, 2, 2, 2], [1, 4, 4, 6], [2, 5, 5, 7])
    """
    boxes, drawn = segment_boxes(scene, name, margin)
    a, b = scene.segments()
    box_list = boxes.tolist()
    segments, xs, ys = [], [], []
    for k in drawn.tolist():
        x0, y0, x1, y1 = box_list[k]
        origin = np.array([x0, y0], dtype=np.float64)
        try:
            mask = draw(a[k] - origin, b[k] - origin, x1 - x0, y1 - y0, (x0, y0))
        except Exception as exc:  # name the segment the library failed on
            raise RuntimeError(f"{name}: the library failed on segment {k} {a[k].tolist()} -> {b[k].tolist()}: "
                               f"{type(exc).__name__}: {exc}") from exc
        y, x = np.nonzero(mask)
        if y.size:
            segments.append(np.full(y.size, k))
            xs.append(x + x0)
            ys.append(y + y0)
    if not segments:
        return Coverage.empty()
    # one sort of every segment's pixels, not a Coverage per segment (5x faster on short ones)
    return coverage_from_fragments(np.concatenate(segments), np.concatenate(xs), np.concatenate(ys), scene.width, scene.height)


def draw_each_alpha(scene: Scene, name: str,
                    draw: Callable[[NDArray[np.float64], int, int, tuple[int, int]], NDArray[np.float64]],
                    margin: int = 2) -> Coverage:
    """Area coverage, one triangle at a time: :func:`draw_each` for an anti-aliasing
    library. ``draw(vertices relative to the box origin, box width, box height, origin)``
    returns the box's (h, w) float64 alphas in [0, 1]; every pixel with a nonzero alpha
    becomes part of a span and keeps its alpha (Coverage ``alpha``), in screen coordinates,
    clipped to the viewport. Boxes, non-finite triangles and library failures are treated
    as in :func:`draw_each`.

    Examples
    --------
    >>> from harness.contract.scenes import Scene
    >>> def half(p, w, h, origin):  # a "library" that gives every box pixel alpha 0.5
    ...     return np.full((h, w), 0.5)
    >>> cov = draw_each_alpha(Scene(4, 1, [[[1, 0], [2, 0], [1, 1]]]), "half", half, margin=0)
    >>> cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist(), cov.alpha.tolist()
    ([0], [1], [2], [0.5])
    """
    parts = []
    for t, p, x0, y0, x1, y1 in _boxes(scene, name, margin):
        try:
            alpha = np.asarray(draw(p - np.array([x0, y0], dtype=np.float64), x1 - x0, y1 - y0, (x0, y0)), dtype=np.float64)
        except Exception as exc:  # name the triangle the library failed on
            raise RuntimeError(f"{name}: the library failed on triangle {int(t)} {p.tolist()}: "
                               f"{type(exc).__name__}: {exc}") from exc
        covered = alpha > 0.0
        if covered.any():
            cov = Coverage.from_mask(int(t), covered, alpha=alpha)
            parts.append(Coverage(cov.triangle, cov.y + y0, cov.x0 + x0, cov.x1 + x0, alpha=cov.alpha))
    return Coverage.concat(parts) if parts else Coverage.empty()


def budget_batches(sizes: NDArray[np.int64], budget: int) -> list[tuple[int, int]]:
    """Consecutive runs ``[start, end)`` of primitives whose ``sizes`` (fragments at most,
    (N,)) add up to no more than ``budget`` together, in order; a primitive that alone
    exceeds it is a run of its own.

    >>> budget_batches(np.array([3, 4, 9, 2, 2, 2]), 8)
    [(0, 2), (2, 3), (3, 6)]
    >>> budget_batches(np.zeros(0, dtype=np.int64), 8)
    []
    """
    total = np.cumsum(sizes)
    runs = []
    start = 0
    while start < total.size:
        before = int(total[start - 1]) if start else 0
        end = max(start + 1, int(np.searchsorted(total, before + budget, side="right")))
        runs.append((start, end))
        start = end
    return runs


def coverage_from_fragments(primitive: NDArray[np.int64], x: NDArray[np.int64], y: NDArray[np.int64],
                            width: int, height: int) -> Coverage:
    """Single-sample coverage from fragments in any order: ``Coverage.from_pixels`` (spans
    by primitive, row and column; a repeated fragment kept as its own span), but sorting
    one integer key instead of three (a read-back of 300,000 fragments: 8 ms, not 180).

    Parameters
    ----------
    primitive, x, y : (P,) int64
        Fragments, 0 <= x < width, 0 <= y < height, primitive >= 0.
    width, height : int

    Examples
    --------
    >>> cov = coverage_from_fragments(np.array([1, 0, 0, 0]), np.array([0, 3, 1, 2]), np.array([0, 2, 2, 2]), 4, 3)
    >>> cov.primitive.tolist(), cov.y.tolist(), cov.x0.tolist(), cov.x1.tolist()
    ([0, 1], [2, 0], [1, 0], [4, 1])
    """
    key = np.sort((np.asarray(primitive, dtype=np.int64) * height + y) * width + x)
    if not key.size:
        return Coverage.empty()
    head = np.ones(key.size, dtype=bool)  # a span starts where the key is not the last plus one, or a row begins
    head[1:] = (key[1:] != key[:-1] + 1) | (key[1:] % width == 0)
    starts = np.flatnonzero(head)
    ends = np.append(starts[1:], key.size) - 1
    first, rows = key[starts], key[starts] // width
    return Coverage(rows // height, rows % height, first % width, key[ends] % width + 1)


def coverage_from_sample_masks(triangle: NDArray[np.int64], x: NDArray[np.int64], y: NDArray[np.int64],
                               mask: NDArray[np.int64], width: int, samples: int) -> Coverage:
    """Multisample coverage from fragments in any order, each with the bit mask of the
    samples it covers (bit s: sample s).

    Equal to ``Coverage.from_pixels`` of one fragment per set bit (sorted by triangle,
    sample, row and column, a repeated fragment kept as its own span), but sorting the
    fragments once by one integer key instead of every (fragment, sample) by four.

    Parameters
    ----------
    triangle, x, y : (P,) int64
        Fragments, 0 <= x < width.
    mask : (P,) int64
        Covered samples of each fragment, bits 0 .. samples - 1.
    width : int
    samples : int

    Returns
    -------
    Coverage
        With ``sample``: one span per run of consecutive pixels of one triangle, sample
        and row.

    Examples
    --------
    >>> cov = coverage_from_sample_masks(np.array([0, 0, 0]), np.array([2, 1, 3]), np.array([0, 0, 0]),
    ...                                  np.array([0b01, 0b11, 0b10]), 4, 2)
    >>> cov.sample.tolist(), cov.x0.tolist(), cov.x1.tolist()
    ([0, 1, 1], [1, 1, 3], [3, 2, 4])

    A sample no fragment covers (a thin triangle between samples), or no fragment at all:

    >>> coverage_from_sample_masks(np.array([0]), np.array([1]), np.array([0]), np.array([0b10]), 4, 4).sample.tolist()
    [1]
    >>> empty = np.zeros(0, dtype=np.int64)
    >>> coverage_from_sample_masks(empty, empty, empty, empty, 4, 4).n_pixels
    0
    """
    triangle, x, y, mask = (np.asarray(a, dtype=np.int64) for a in (triangle, x, y, mask))
    height = int(y.max()) + 1 if y.size else 1
    key = (triangle * height + y) * width + x  # by triangle, row, column
    order = np.argsort(key, kind="stable")  # fragments arrive nearly in raster order: merge sort is fast
    key, mask = key[order], mask[order]
    parts = []
    for s in range(samples):
        covered = ((mask >> s) & 1).astype(bool)
        k = key[covered]
        # a new span where the key is not the previous one plus one, or a row begins
        head = np.ones(k.size, dtype=bool)
        head[1:] = (k[1:] != k[:-1] + 1) | (k[1:] % width == 0)
        starts = np.flatnonzero(head)
        # (a sample no fragment covers has no span: without this guard its one "end" was k[-1] of nothing)
        ends = np.append(starts[1:], k.size) - 1 if starts.size else starts
        first = k[starts]
        rows = first // width
        parts.append((rows, np.full(starts.size, s), first % width, k[ends] % width + 1))
    rows, sample, x0, x1 = (np.concatenate([part[i] for part in parts]) for i in range(4))
    span_triangle, span_y = rows // height, rows % height
    # by triangle, then sample (each sample's spans are already by row and column)
    spans = np.argsort(span_triangle * samples + sample, kind="stable")
    return Coverage(span_triangle[spans], span_y[spans], x0[spans], x1[spans], sample=sample[spans])
