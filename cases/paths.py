"""Path cases: closed contours filled under the nonzero and even-odd fill rules.

Three families, every case a :class:`~harness.contract.scenes.PathScene` carrying its fill rule, the
rule the last part of the id (``.../nonzero``, ``.../evenodd``):

- ``paths/<shape>/<detail>/<rule>``: star polygons {5/2}, {7/3}, {10/3}, bow ties, rings
  whose hole runs the same or the opposite way, overlapping contours, collinear and
  repeated vertices (zero-length edges), spikes, contours of one and two vertices, huge
  contours (1e4 .. 1e30, reaching far beyond the viewport), epsilon contours (1e-9 px),
  several paths in one scene, random contours, and deep winding (``paths/deep-winding/<N>``:
  a triangle traced N = 128, 256 or 65,536 times, where a narrow winding counter wraps).
  ``lattice`` shapes lie on a 1/4 or 1/2 px lattice (exact ties: vertices on sample rows
  and columns, edges through samples); ``float`` ones do not. Shapes that cross or
  overlap themselves come under both rules.
- ``path-partitions/<tiling>/<detail>/<rule>``: planar partitions, each cell its own
  one-contour path, under both rules (the same coverage: cells are simple): clipped
  Voronoi cells, grids of irregular quads, polygons merged from a triangulation.
  Neighbours share identical vertex floats and no vertex lies inside another cell's edge
  (no T-junctions); every partition is proven exact (:func:`partition_flaws`) before it
  is used, and its ``region`` is its exact convex outline.
  ``path-partitions/triangles/<partition>/<rule>`` are the triangle partitions of
  :func:`cases.partitions.partition_cases` with each triangle its own one-contour path
  (:func:`triangles_as_paths`): the very scenes ``identify`` sends a rasterizer that takes
  paths but no triangles when it asks whether it is watertight, so that ``run`` fails
  where ``identify`` says it is not. Likewise ``paths/triangles/bits-<b>/<rule>`` (the
  lattice triangles of its viewport-edge probe) and ``path-degenerate/triangles/...``
  (its zero-area and non-finite probes).
- ``path-degenerate/<kind>/<detail>/<rule>``: zero-area and retracing contours, figure
  eights, duplicate contours, non-finite vertices, contours of one vertex. Paths 0 and 1
  of each scene are ordinary, so that a rasterizer that mishandles the bad paths cannot
  hide it by drawing nothing at all.

Every case draws from its own generator, seeded by the suite's seed and its id, so a case
is the same in the quick and the full suite, and ids do not depend on the seed.
"""

from __future__ import annotations

import math
import zlib
from collections import Counter
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import Delaunay, Voronoi

from cases.partitions import partition_cases
from harness.contract.case import Case
from harness.contract.scenes import PathScene, Scene
from harness.geometry.exact import orientation
from harness.oracle.winding import FILL_RULES

__all__ = ["star", "rectangle", "regular", "quadratic", "glyph_o", "glyph_d", "thin_stroke", "pie",
           "is_simple", "polygon_sign", "partition_flaws", "voronoi_cells", "quad_grid",
           "merged_polygons", "shape_cases", "path_partition_cases", "triangles_as_paths", "triangle_partition_cases",
           "AS_PATHS", "path_case_id", "triangle_cases_as_paths", "viewport_cases", "VIEWPORT_CASES", "path_degenerate_cases",
           "path_cases", "PATH_FAMILIES", "wound", "deep_winding", "deep_winding_cases", "DEEP_WINDINGS"]

PATH_FAMILIES = ("paths", "path-partitions", "path-degenerate")

Contour = NDArray[np.float64]
Point = tuple[float, float]

SIZE = 32
PARTITION_SIZE = 48


# -- shapes --------------------------------------------------------------------------------


def star(n: int, k: int, centre: ArrayLike, radius: float, turn: float = 0.0) -> Contour:
    """(n, 2) float64: the star polygon {n/k}, n points on a circle each joined to the
    k-th next, as one contour (n and k coprime); the first point straight above the centre,
    turned by ``turn`` radians.

    >>> star(5, 2, (0, 0), 1).round(3)[:3]
    array([[ 0.   , -1.   ],
           [ 0.588,  0.809],
           [-0.951, -0.309]])
    """
    if math.gcd(n, k) != 1:
        raise ValueError(f"{{{n}/{k}}} is not one contour: n and k must be coprime")
    angle = turn + 2 * np.pi * ((np.arange(n) * k) % n) / n
    c = np.asarray(centre, dtype=np.float64)
    return np.stack([c[0] + radius * np.sin(angle), c[1] - radius * np.cos(angle)], axis=-1)


def rectangle(x0: float, y0: float, x1: float, y1: float) -> Contour:
    """(4, 2): the rectangle's corners, clockwise on screen (y down) for x0 < x1, y0 < y1."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)


def regular(n: int, centre: ArrayLike, radius: float, turn: float = 0.0) -> Contour:
    """(n, 2): a regular n-gon, clockwise on screen."""
    return star(n, 1, centre, radius, turn)


def quadratic(p0: ArrayLike, p1: ArrayLike, p2: ArrayLike, segments: int) -> Contour:
    """(segments, 2): the quadratic Bezier from p0 (control p1) towards p2 flattened into
    ``segments`` chords, as a TrueType outline's curves are: its points at t = k/segments,
    k = 0 .. segments - 1 (p2 starts the next piece).

    >>> quadratic([0, 0], [1, 2], [2, 0], 2).tolist()
    [[0.0, 0.0], [1.0, 1.0]]
    """
    t = (np.arange(segments, dtype=np.float64) / segments)[:, None]
    a, b, c = (np.asarray(q, dtype=np.float64) for q in (p0, p1, p2))
    points: Contour = (1 - t) ** 2 * a + 2 * (1 - t) * t * b + t**2 * c
    return points


def glyph_o(centre: ArrayLike, height: float, turn: float = 0.0) -> list[Contour]:
    """A glyph "o" crossed by a bar: a slanted oval of 64 short edges, its counter (48
    edges) wound against it, and a bar overlapping both as a variable font's contours
    overlap (nonzero: winding 2 where the bar crosses the ring, 0 in the counter's middle
    covered again by the bar at winding 1)."""
    c = np.asarray(centre, dtype=np.float64)
    outer = regular(64, c, 0.45 * height, turn) * [0.9, 1.0] + c * [0.1, 0.0]
    inner = (regular(48, c, 0.27 * height, turn) * [0.9, 1.0] + c * [0.1, 0.0])[::-1]
    bar = rectangle(c[0] - 0.5 * height, c[1] - 0.06 * height, c[0] + 0.5 * height, c[1] + 0.06 * height)
    return [outer, inner, bar]


def glyph_d(origin: ArrayLike, height: float, segments: int = 12) -> list[Contour]:
    """A glyph "D" as a TrueType outline flattens it (y down, ``origin`` its top-left, about
    0.75 ``height`` wide): a stem and a bowl of two quadratic curves, each flattened into
    ``segments`` short edges, clockwise; its counter, also of two flattened curves, wound
    the other way; and a separate stem contour overlapping the outline's stem and counter,
    wound like the outline, as variable fonts keep overlapping contours (nonzero: winding 2
    where they overlap; even-odd: a hole there).

    >>> [c.shape for c in glyph_d((0, 0), 10.0, 4)]
    [(11, 2), (11, 2), (4, 2)]
    """
    o = np.asarray(origin, dtype=np.float64)
    h, w, t = height, 0.75 * height, 0.14 * height
    outer = np.concatenate([np.array([[0.0, 0.0], [0.35 * w, 0.0]]),
                            quadratic([0.35 * w, 0.0], [w, 0.0], [w, 0.5 * h], segments),
                            quadratic([w, 0.5 * h], [w, h], [0.35 * w, h], segments),
                            np.array([[0.35 * w, h], [0.0, h]])])
    inner = np.concatenate([np.array([[t, t], [0.35 * w, t]]),
                            quadratic([0.35 * w, t], [w - t, t], [w - t, 0.5 * h], segments),
                            quadratic([w - t, 0.5 * h], [w - t, h - t], [0.35 * w, h - t], segments),
                            np.array([[0.35 * w, h - t], [t, h - t]])])[::-1]
    stem = rectangle(0.05 * h, 0.1 * h, 0.05 * h + 1.6 * t, 0.9 * h)
    return [_dedup(outer) + o, _dedup(inner) + o, stem + o]


def _dedup(contour: Contour) -> Contour:
    """The contour without a vertex equal to the one before it (a flattened curve's
    first point repeats the straight piece's last)."""
    keep = np.ones(contour.shape[0], dtype=bool)
    keep[1:] = np.any(contour[1:] != contour[:-1], axis=1)
    return contour[keep]


def thin_stroke(points: ArrayLike, width: float) -> Contour:
    """The outline of a polyline stroked ``width`` wide, as a 2D library turns a stroke
    into a path before filling it: one contour, each vertex moved by
    ``width / 2`` along its mitred normal on one side, then back along the other (a
    gentle polyline: the miters stay short).

    >>> thin_stroke([[0, 0], [4, 0]], 1.0).tolist()
    [[0.0, 0.5], [4.0, 0.5], [4.0, -0.5], [0.0, -0.5]]
    """
    p = np.asarray(points, dtype=np.float64)
    d = np.diff(p, axis=0)
    d /= np.hypot(d[:, 0], d[:, 1])[:, None]
    normal = np.stack([d[:, 1], -d[:, 0]], axis=1)
    per_vertex = np.concatenate([normal[:1], normal[:-1] + normal[1:], normal[-1:]])
    per_vertex[1:-1] /= (per_vertex[1:-1] * normal[1:]).sum(axis=1)[:, None]  # the mitre: normal . n = 1
    left, right = p - per_vertex * width / 2, p + per_vertex * width / 2
    return np.concatenate([left, right[::-1]])


def pie(slices: int, sides: int, centre: ArrayLike, radius: float, turn: float = 0.0) -> tuple[list[Contour], Contour]:
    """A regular ``sides``-gon cut from its centre into ``slices`` wedges (``sides`` a
    multiple of ``slices``): each wedge the centre and its run of the outline's vertices,
    the same floats as its neighbours'; the region, the polygon. Curved-looking pieces
    (many short outer edges) meeting at one point: a seam test for glyph-like pieces."""
    if sides % slices:
        raise ValueError("the sides must divide into the slices")
    outline = regular(sides, centre, radius, turn)
    run = sides // slices
    c = np.asarray(centre, dtype=np.float64)
    cells = [np.concatenate([c[None], outline[np.arange(k * run, k * run + run + 1) % sides]]) for k in range(slices)]
    return cells, outline


def _on_lattice(points: ArrayLike, scale: int = 4) -> Contour:
    """Points rounded to the 1/scale lattice."""
    return np.round(np.asarray(points, dtype=np.float64) * scale) / scale


def _closed(contour: Contour) -> Contour:
    """The contour with its first vertex repeated at the end (a zero-length closing edge)."""
    return np.concatenate([contour, contour[:1]])


def _retraced(polyline: Contour) -> Contour:
    """A contour along the polyline and back: p0 .. pn .. p1 (winding 0 everywhere)."""
    return np.concatenate([polyline, polyline[-2:0:-1]])


def _rng(seed: int, name: str) -> np.random.Generator:
    """The case's own generator: the same draws whatever else the suite holds."""
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


# -- exact geometry ------------------------------------------------------------------------


def _orient(a: NDArray, b: NDArray, c: NDArray) -> NDArray[np.int8]:
    """Exact sign of orient2d(a, b, c) for (N, 2) arrays: +1 clockwise on screen."""
    return orientation(np.stack([a, b, c], axis=1))


def _sign_along(o: NDArray, a: NDArray) -> NDArray[np.int64]:
    """For a on a line through o (a != o): the side of o it lies on, as +-1 along the
    line's first coordinate that varies (float comparisons: exact)."""
    use_x = a[:, 0] != o[:, 0]
    u = np.where(use_x, a[:, 0], a[:, 1])
    w = np.where(use_x, o[:, 0], o[:, 1])
    return (u > w).astype(np.int64) - (u < w).astype(np.int64)


def is_simple(contour: ArrayLike) -> bool:
    """Whether a closed contour is a simple polygon: three vertices at least, all finite,
    no zero-length edge, adjacent edges meeting only at their common vertex (no fold back
    along a line) and other edges not meeting at all. Decided exactly (orient2d signs
    and float comparisons). A simple contour has winding number +-1 inside, 0 outside.

    >>> is_simple(rectangle(0, 0, 2, 1)), is_simple(star(5, 2, (0, 0), 1)), is_simple([[0, 0], [2, 0], [1, 0]])
    (True, False, False)
    """
    v = np.asarray(contour, dtype=np.float64).reshape(-1, 2)
    k = v.shape[0]
    if k < 3 or not np.isfinite(v).all():
        return False
    nxt = np.roll(v, -1, axis=0)
    if np.any(np.all(v == nxt, axis=1)):
        return False
    i, j = np.triu_indices(k, 1)
    p1, q1, p2, q2 = v[i], nxt[i], v[j], nxt[j]
    o1, o2, o3, o4 = (x.astype(np.int64) for x in (_orient(p1, q1, p2), _orient(p1, q1, q2), _orient(p2, q2, p1),
                                                   _orient(p2, q2, q1)))
    follows = j == i + 1  # edge j starts where edge i ends (at q1)
    wraps = (i == 0) & (j == k - 1)  # edge j ends where edge i starts (at p1)
    # adjacent edges on one line overlap when the far ends lie on the same side of the
    # common vertex
    folds = follows & (o2 == 0) & (_sign_along(q1, p1) == _sign_along(q1, q2))
    folds |= wraps & (o1 == 0) & (_sign_along(p1, q1) == _sign_along(p1, p2))
    # closed segments meet: straddling both ways, or collinear with overlapping extents
    meet = (o1 * o2 <= 0) & (o3 * o4 <= 0)
    collinear = (o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0)
    lo1, hi1, lo2, hi2 = np.minimum(p1, q1), np.maximum(p1, q1), np.minimum(p2, q2), np.maximum(p2, q2)
    overlap = np.all((lo1 <= hi2) & (lo2 <= hi1), axis=1)
    meet &= ~collinear | overlap
    return not (folds.any() or (meet & ~(follows | wraps)).any())


def polygon_sign(contour: ArrayLike) -> int:
    """The orientation of a simple contour, exactly: +1 clockwise on screen (positive
    signed area, y down), -1 counter-clockwise. Read at the lowest-x (then lowest-y)
    vertex, a convex corner where the turn is never straight."""
    v = np.asarray(contour, dtype=np.float64).reshape(-1, 2)
    k = int(np.lexsort((v[:, 1], v[:, 0]))[0])
    m = v.shape[0]
    return int(_orient(v[[k - 1]], v[[k]], v[[(k + 1) % m]])[0])


def _key(p: ArrayLike) -> Point:
    x, y = np.asarray(p, dtype=np.float64)
    return float(x), float(y)


def partition_flaws(cells: Sequence[ArrayLike], region: ArrayLike) -> str | None:
    """Why ``cells`` do not tile the convex ``region`` exactly, or None when they do.

    Checked exactly: the region is strictly convex; every cell is simple
    (:func:`is_simple`); with every cell turned clockwise, each edge shared by two cells
    appears once in each direction (identical floats at both ends: no T-junction), and
    the edges left over subdivide the region's outline, each side from one corner to the
    next, in order, once. That proves the tiling: a clockwise simple cell winds once
    around the points inside it and not at all around the others; the cells' windings add
    up to that of their edges' sum, in which shared edges cancel, leaving the outline. So
    every point on no edge -- every perturbed sample of every tie rule -- lies in exactly
    one cell when it lies in the region and in none otherwise.

    >>> a, b = [[0, 0], [1, 0], [1, 2], [0, 2]], [[1, 0], [2, 0], [2, 2], [1, 2]]
    >>> partition_flaws([a, b], rectangle(0, 0, 2, 2)) is None
    True
    >>> partition_flaws([a, [[1, 0], [2, 0], [2, 2], [1, 1]]], rectangle(0, 0, 2, 2))  # a gap
    'two outline edges leave (1.0, 0.0)'
    """
    outline = np.asarray(region, dtype=np.float64).reshape(-1, 2)
    m = outline.shape[0]
    if not is_simple(outline):
        return "the region is not a simple polygon"
    turns = _orient(np.roll(outline, 1, axis=0), outline, np.roll(outline, -1, axis=0))
    if not (np.all(turns == turns[0]) and turns[0] != 0):
        return "the region is not strictly convex"
    if turns[0] < 0:
        outline = outline[::-1]
    edges: Counter[tuple[Point, Point]] = Counter()
    for n, cell in enumerate(cells):
        v = np.asarray(cell, dtype=np.float64).reshape(-1, 2)
        if not is_simple(v):
            return f"cell {n} is not a simple polygon"
        if polygon_sign(v) < 0:
            v = v[::-1]
        points = [_key(p) for p in v]
        edges.update(zip(points, points[1:] + points[:1]))
    left: dict[Point, Point] = {}
    for (a, b), count in edges.items():
        extra = count - edges.get((b, a), 0)
        if extra > 1:
            return f"edge {a} -> {b} belongs to {count} cells"
        if extra == 1:
            if a in left:
                return f"two outline edges leave {a}"
            left[a] = b
    used = 0
    for s in range(m):
        r0, r1 = outline[s], outline[(s + 1) % m]
        axis = 0 if r0[0] != r1[0] else 1
        ahead = 1.0 if r1[axis] > r0[axis] else -1.0
        p, end = _key(r0), _key(r1)
        while p != end:
            q = left.get(p)
            if q is None:
                return f"the outline breaks at {p}"
            on_side = _orient(r0[None], r1[None], np.array([q]))[0] == 0
            # strictly ahead of p, not past the corner (float comparisons: exact)
            if not (on_side and ahead * q[axis] > ahead * p[axis] and ahead * q[axis] <= ahead * end[axis]):
                return f"outline edge {p} -> {q} leaves side {s} of the region"
            used += 1
            p = q
    if used != len(left):
        return f"{len(left) - used} edges lie on no cell's neighbour and not on the outline"
    return None


# -- partitions ----------------------------------------------------------------------------


def _square(lo: float, hi: float) -> Contour:
    return rectangle(lo, lo, hi, hi)


def voronoi_cells(count: int, lo: float, hi: float, rng: np.random.Generator) -> tuple[list[Contour], Contour]:
    """The Voronoi cells of ``count`` random seeds clipped to the square [lo, hi]^2, and
    the square.

    The seeds are mirrored across the four sides: their cells in the diagram of seeds and
    mirrors are then exactly the clipped cells. Each Voronoi vertex is computed once (by
    qhull) and every cell refers to it, so neighbours share identical floats; the
    vertices qhull puts on a side to within rounding are put on it exactly.
    """
    seeds = rng.uniform(lo + 1.0, hi - 1.0, size=(count, 2))
    mirrored = [seeds]
    for axis in (0, 1):
        for side in (lo, hi):
            image = seeds.copy()
            image[:, axis] = 2 * side - image[:, axis]
            mirrored.append(image)
    diagram = Voronoi(np.concatenate(mirrored))
    vertices = diagram.vertices.copy()
    for axis in (0, 1):
        for side in (lo, hi):
            vertices[np.abs(vertices[:, axis] - side) <= 1e-9 * (hi - lo), axis] = side
    cells = []
    for i in range(count):
        index = np.array(diagram.regions[diagram.point_region[i]], dtype=np.int64)
        if index.size < 3 or np.any(index < 0):
            continue  # not a bounded cell: partition_flaws rejects the draw
        v = vertices[index]
        cells.append(v[np.argsort(np.arctan2(v[:, 1] - seeds[i, 1], v[:, 0] - seeds[i, 0]))])
    return cells, _square(lo, hi)


def quad_grid(cells: int, lo: float, hi: float, jitter: str, rng: np.random.Generator) -> tuple[list[Contour], Contour]:
    """A ``cells`` x ``cells`` grid of quads over [lo, hi]^2, and the square. Grid points are
    shared by the quads around them and moved by up to a quarter of a cell: ``"lattice"``
    in steps of 1/4 px, ``"half"`` in steps of 1/2 px, ``"float"`` uniformly, points on the
    sides only along their side, corners not at all. Each point stays in its own quarter
    cell box, so opposite edges of a quad cannot meet: every quad is simple."""
    step = (hi - lo) / cells
    lines = np.linspace(lo, hi, cells + 1)
    gx, gy = np.meshgrid(lines, lines, indexing="xy")
    v = np.stack([gx, gy], axis=-1)
    if jitter == "float":
        move = rng.uniform(-step / 4, step / 4, size=v.shape)
    else:
        unit = 4 if jitter == "lattice" else 2
        reach = int(math.floor(step / 4 * unit))
        move = rng.integers(-reach, reach + 1, size=v.shape) / unit
    move[[0, -1], :, 1] = 0.0  # the top and bottom rows stay on their sides
    move[:, [0, -1], 0] = 0.0  # and the left and right columns on theirs
    v = v + move
    quads = [np.array([v[j, i], v[j, i + 1], v[j + 1, i + 1], v[j + 1, i]]) for j in range(cells) for i in range(cells)]
    return quads, _square(lo, hi)


def _outline(triangles: NDArray[np.int64]) -> list[int] | None:
    """The vertex indices around a union of clockwise triangles (T, 3), or None when the
    edges left after cancelling shared ones are not one cycle through distinct vertices
    (a pinch or a hole)."""
    directed = {(int(t[a]), int(t[(a + 1) % 3])) for t in triangles for a in range(3)}
    rim = [(a, b) for a, b in directed if (b, a) not in directed]
    following = dict(rim)
    if len(following) != len(rim):
        return None
    start = rim[0][0]
    loop = [start]
    while (nxt := following[loop[-1]]) != start:
        loop.append(nxt)
        if len(loop) > len(rim):
            return None
    return loop if len(loop) == len(rim) else None


def merged_polygons(count: int, rng: np.random.Generator, lattice: bool,
                    size: int = PARTITION_SIZE) -> tuple[list[Contour], Contour]:
    """Polygons of one to four triangles of a Delaunay triangulation, merged across shared
    edges (convex or not, each simple), and the convex octagon they tile: ``count`` random
    points inside it (on the 1/8 lattice when ``lattice``) and its corners. Every vertex
    of the triangulation on a polygon's rim is one of its vertices: no T-junction."""
    centre, radius = size / 2, size / 2 - 4
    corners = regular(8, (centre, centre), radius, rng.uniform(0, np.pi / 4))
    if lattice:
        corners = _on_lattice(corners, 8)
    inner = rng.uniform(centre - radius, centre + radius, size=(4 * count, 2))
    if lattice:
        inner = np.unique(_on_lattice(inner, 8), axis=0)
        inner = inner[rng.permutation(inner.shape[0])]
    # strictly inside: clockwise of every side of the clockwise octagon
    turns = [_orient(np.broadcast_to(corners[s], inner.shape), np.broadcast_to(corners[(s + 1) % 8], inner.shape), inner)
             for s in range(8)]
    inner = inner[np.all(np.array(turns) > 0, axis=0)][:count]
    points = np.concatenate([corners, inner])
    triangles = Delaunay(points).simplices.astype(np.int64)
    turn = orientation(points[triangles])
    if np.any(turn == 0):
        return [], corners  # a flat triangle: partition_flaws rejects the draw
    triangles[turn < 0] = triangles[turn < 0][:, ::-1]
    sides = [[(int(min(tri[a], tri[(a + 1) % 3])), int(max(tri[a], tri[(a + 1) % 3]))) for a in range(3)] for tri in triangles]
    around: dict[tuple[int, int], list[int]] = {}
    for t, edges in enumerate(sides):
        for edge in edges:
            around.setdefault(edge, []).append(t)
    neighbours = [[u for edge in edges for u in around[edge] if u != t] for t, edges in enumerate(sides)]
    taken = np.zeros(len(triangles), dtype=bool)
    cells = []
    for t in rng.permutation(len(triangles)):
        if taken[t]:
            continue
        members = [int(t)]
        taken[t] = True
        want = int(rng.integers(1, 5))
        while len(members) < want:
            candidates = sorted({u for m in members for u in neighbours[m] if not taken[u]})
            grown = False
            for u in rng.permutation(candidates) if candidates else ():
                if _outline(triangles[members + [int(u)]]) is not None:
                    members.append(int(u))
                    taken[u] = True
                    grown = True
                    break
            if not grown:
                break
        loop = _outline(triangles[members])
        assert loop is not None
        cells.append(points[loop])
    return cells, corners


def _proven(build: Callable[[np.random.Generator], tuple[list[Contour], Contour]], rng: np.random.Generator,
            what: str, tries: int = 40) -> tuple[list[Contour], Contour]:
    """The first partition ``build`` draws that :func:`partition_flaws` proves exact."""
    for _ in range(tries):
        cells, region = build(rng)
        if cells and partition_flaws(cells, region) is None:
            return cells, region
    raise RuntimeError(f"{what}: no exact partition in {tries} draws")


def path_partition_cases(seed: int, full: bool = False) -> list[Case]:
    """``path-partitions/<tiling>/<detail>/<rule>``: each cell its own one-contour path,
    half the cells turned the other way, ``region`` the exact outline."""
    cases: list[Case] = []

    def add(name: str, build: Callable[[np.random.Generator], tuple[list[Contour], Contour]], lattice: bool,
            quick: bool) -> None:
        if not (quick or full):
            return
        rng = _rng(seed, name)
        cells, region = _proven(build, rng, name)
        flip = rng.random(len(cells)) < 0.5
        cells = [c[::-1] if f else c for c, f in zip(cells, flip)]
        for rule in FILL_RULES:
            scene = PathScene.from_paths(PARTITION_SIZE, PARTITION_SIZE, [[c] for c in cells], rule)
            cases.append(Case(f"path-partitions/{name}/{rule}", scene, lattice=lattice, region=region.copy()))

    add("voronoi-12/float", lambda r: voronoi_cells(12, 4.0, 44.0, r), False, True)
    add("voronoi-40/float", lambda r: voronoi_cells(40, 2.0, 46.0, r), False, False)
    # lines 8 px apart on whole pixels; grid points moved by quarter pixels
    add("quads-5x5/lattice", lambda r: quad_grid(5, 4.0, 44.0, "lattice", r), True, True)
    # lines through pixel centres, points moved by half pixels: vertices on samples and
    # corners, shared edges through samples
    add("quads-5x5-on-samples/lattice", lambda r: quad_grid(5, 3.5, 43.5, "half", r), True, True)
    add("quads-10x10/lattice", lambda r: quad_grid(10, 4.0, 44.0, "lattice", r), True, False)
    # lines at non-dyadic spacing, unconstrained jitter
    add("quads-6x6/float", lambda r: quad_grid(6, 4.0, 44.0, "float", r), False, False)
    add("polygons-30/float", lambda r: merged_polygons(30, r, False), False, True)
    # a 64-gon cut into 8 wedges meeting at a float centre: pieces with many short outer
    # edges (curves, as glyph pieces are), eight of them in the centre's pixel
    add("pie-8/float", lambda r: pie(8, 64, r.uniform(22, 26, 2), 19.0, r.uniform(0, 1)), False, True)
    add("pie-32/float", lambda r: pie(32, 96, r.uniform(22, 26, 2), 20.0, r.uniform(0, 1)), False, False)
    add("polygons-30/lattice", lambda r: merged_polygons(30, r, True), True, False)
    add("polygons-80/float", lambda r: merged_polygons(80, r, False), False, False)
    return cases + triangle_partition_cases(seed, full)


def triangles_as_paths(scene: Scene, fill_rule: str = "nonzero") -> PathScene:
    """The triangles of ``scene`` as a path scene: path k is triangle k, one contour of its
    three vertices in their order, so its coverage names the same primitives. A
    triangle's winding number is 0 or +-1 everywhere: both rules give it the same pixels.

    >>> tri = Scene(8, 8, [[[1, 1], [7, 1], [1, 7]], [[2, 2], [2, 6], [6, 6]]])
    >>> paths = triangles_as_paths(tri)
    >>> len(paths), paths.contour_sizes.tolist(), paths.vertices.shape
    (2, [3, 3], (6, 2))
    """
    n = len(scene)
    return PathScene(scene.width, scene.height, scene.positions.reshape(-1, 2), np.full(n, 3, dtype=np.int64),
                     np.arange(n, dtype=np.int64), fill_rule)


# the triangle families identify draws through a paths-only rasterizer's paths -> where the
# path suite holds them (``<path family>/triangles/<rest of the id>/<rule>``)
AS_PATHS = {"watertight": "path-partitions", "degenerate": "path-degenerate", "lattice": "paths"}


def path_case_id(triangle_id: str, fill_rule: str) -> str:
    """The id the path suite gives triangle case ``triangle_id`` sent as one-contour paths
    under ``fill_rule`` (:data:`AS_PATHS`).

    >>> path_case_id("watertight/fan-8/centre", "evenodd"), path_case_id("lattice/bits-2", "nonzero")
    ('path-partitions/triangles/fan-8/centre/evenodd', 'paths/triangles/bits-2/nonzero')
    """
    family, rest = triangle_id.split("/", 1)
    return f"{AS_PATHS[family]}/triangles/{rest}/{fill_rule}"


def triangle_cases_as_paths(cases: Sequence[Case], rules: Sequence[str] = FILL_RULES) -> list[Case]:
    """Triangle ``cases`` with each triangle its own one-contour path, under each of
    ``rules``, named by :func:`path_case_id`; the same region and lattice."""
    return [Case(path_case_id(case.id, rule), triangles_as_paths(case.scene, rule), lattice=case.lattice,
                 region=None if case.region is None else case.region.copy())
            for case in cases if isinstance(case.scene, Scene) for rule in rules]


def viewport_cases(seed: int) -> list[Case]:
    """The suite's lattice triangles that identify's viewport-edge probe draws
    (:func:`harness.identify.triangle_defects.viewport_edge`): ``lattice/bits-{0,2,4}``, crossing every edge."""
    from cases.conformance import conformance_cases

    return [c for c in conformance_cases(seed) if c.id in VIEWPORT_CASES]


VIEWPORT_CASES = ("lattice/bits-0", "lattice/bits-2", "lattice/bits-4")


def triangle_partition_cases(seed: int, full: bool = False) -> list[Case]:
    """``path-partitions/triangles/<partition>/<rule>``: every triangle partition of the
    suite (``watertight/<partition>``, :func:`cases.partitions.partition_cases`) with each
    triangle its own one-contour path, under both rules; the same region and lattice."""
    return triangle_cases_as_paths(partition_cases(seed, full))


# -- the shape catalogue -------------------------------------------------------------------


def _random_contours(rng: np.random.Generator, contours: int, size: int, scale: int | None) -> list[Contour]:
    """``contours`` random contours of 3..9 vertices around the viewport, on the 1/scale
    lattice (or floats when scale is None): most cross themselves, windings reach 2 and 3."""
    out = []
    for _ in range(contours):
        v = rng.uniform(-2, size + 2, size=(int(rng.integers(3, 10)), 2))
        out.append(_on_lattice(v, scale) if scale else v)
    return out


def shape_cases(seed: int, full: bool = False) -> list[Case]:
    """``paths/<shape>/<detail>/<rule>``."""
    cases: list[Case] = []
    both = FILL_RULES

    def add(name: str, paths: list[list[Contour]] | Callable[[np.random.Generator], list[list[Contour]]],
            rules: Sequence[str] = both, quick: Sequence[str] = (), lattice: bool = False,
            refusable: tuple[int, ...] = ()) -> None:
        """Case ``paths/<name>/<rule>`` for each of ``rules`` (those of ``quick`` in the quick
        suite too): ``paths``, or what it draws from the case's own generator."""
        rules = [rule for rule in rules if full or rule in quick]
        if not rules:
            return
        built = paths(_rng(seed, name)) if callable(paths) else paths
        for rule in rules:
            scene = PathScene.from_paths(SIZE, SIZE, built, rule)
            cases.append(Case(f"paths/{name}/{rule}", scene, lattice=lattice, refusable=refusable))

    def float_centre(r: np.random.Generator) -> NDArray[np.float64]:
        return r.uniform(SIZE / 2 - 2, SIZE / 2 + 2, size=2)

    def float_star(n: int, k: int) -> Callable[[np.random.Generator], list[list[Contour]]]:
        return lambda r: [[star(n, k, float_centre(r), r.uniform(10, 14), r.uniform(0, 2 * np.pi))]]

    # star polygons: winding 2 ({5/2}) or 3 ({7/3}, {10/3}) in the middle; even-odd
    # leaves out the {5/2} centre and the regions of winding 2 of the others
    for n, k in ((5, 2), (7, 3), (10, 3)):
        add(f"star-{n}-{k}/lattice", [[_on_lattice(star(n, k, (15.5, 15.5), 13.0))]], quick=both if (n, k) == (5, 2) else (),
            lattice=True)
        add(f"star-{n}-{k}/float", float_star(n, k), quick=both if (n, k) == (7, 3) else ())
    # a pentagram on the 1/2 lattice: vertices on pixel centres and corners
    add("star-5-2/half-pixels", [[_on_lattice(star(5, 2, (16.0, 16.0), 13.0, 0.1), 2)]], lattice=True)
    # bow tie: lobes of winding +1 and -1; its diagonals run through pixel centres
    # simple concave polygons whose sides run through sample points (slopes 0, 1, -1 and
    # 1/2 through pixel centres): ties on every side, for conformance and triangulation
    add("simple/arrow-on-samples/lattice", [[np.array([[2.5, 2.5], [28.5, 2.5], [28.5, 28.5], [15.5, 15.5], [2.5, 28.5]])]],
        quick=("nonzero",), lattice=True)
    add("simple/comb-on-samples/lattice", [[np.array([[3.5, 3.5], [27.5, 3.5], [27.5, 27.5], [21.5, 27.5], [21.5, 11.5],
                                                      [17.5, 15.5], [13.5, 11.5], [9.5, 27.5], [3.5, 27.5]])]],
        quick=("evenodd",), lattice=True)
    add("bow-tie/lattice", [[np.array([[4.5, 4.5], [27.5, 27.5], [27.5, 4.5], [4.5, 27.5]])]], quick=both, lattice=True)
    # corners of a rectangle moved about, taken top-left, bottom-right, top-right, bottom-left
    add("bow-tie/float", lambda r: [[np.array([[3, 3], [24, 24], [24, 3], [3, 24]]) + r.uniform(0, 5, size=(4, 2))]])
    # rings: a hole wound the same way has winding 2 (nonzero fills it), the other way 0;
    # the hole's sides run through sample rows and columns
    outer, hole = rectangle(3, 3, 29, 29), rectangle(10.5, 10.5, 21.5, 21.5)
    add("ring/hole-same/lattice", [[outer, hole]], quick=both, lattice=True)
    add("ring/hole-opposite/lattice", [[outer, hole[::-1]]], quick=both, lattice=True)

    def circle_ring(same: bool) -> Callable[[np.random.Generator], list[list[Contour]]]:
        return lambda r: [[regular(24, float_centre(r), 13.5, r.uniform(0, 1)),
                           regular(17, float_centre(r), 6.25, r.uniform(0, 1))[:: 1 if same else -1]]]

    add("ring/circle-hole-same/float", circle_ring(True))
    add("ring/circle-hole-opposite/float", circle_ring(False))
    # overlapping contours in one path: winding 2 (nonzero) or 0 where they overlap
    a, b = rectangle(3, 3, 20, 20), rectangle(11.5, 11.5, 28.5, 28.5)
    add("overlap/squares-same/lattice", [[a, b]], quick=both, lattice=True)
    add("overlap/squares-opposite/lattice", [[a, b[::-1]]], lattice=True)
    add("overlap/three-polygons/float", lambda r: [[regular(int(r.integers(3, 8)), r.uniform(10, 22, 2), r.uniform(6, 11),
                                                            r.uniform(0, 7))[:: 1 if r.random() < 0.5 else -1]
                                                    for _ in range(3)]])

    # glyph-like outlines (issue 34: what anti-aliased font renderers fill): an "o" whose
    # curves are flattened to many short edges, its counter wound against it, crossed by a
    # bar overlapping both as variable fonts' contours overlap; the same at 6 px and below
    # a pixel; and a ring a tenth of a pixel thick (a hairline sliver)
    def glyph(height: float) -> Callable[[np.random.Generator], list[list[Contour]]]:
        return lambda r: [glyph_o(float_centre(r), height, r.uniform(0, 1))]

    add("glyph/o-with-bar/float", glyph(26.0))
    add("glyph/o-with-bar-6px/float", glyph(6.0))
    add("glyph/o-with-bar-sub-pixel/float", glyph(0.8))
    # a "D" of flattened quadratic curves with a counter and an overlapping stem contour
    # (the quick suite's glyph), at text sizes, below a pixel, and a line of them
    add("glyph/d-curves/float", lambda r: [glyph_d(r.uniform(3, 5, 2), 24.0)], quick=both)
    add("glyph/d-curves-9px/float", lambda r: [glyph_d(r.uniform(10, 12, 2), 9.0, 6)])
    add("glyph/d-curves-sub-pixel/float", lambda r: [glyph_d(r.uniform(15, 16, 2), 0.7, 4)])
    add("glyph/text-line/float", lambda r: [glyph_d((1.3 + 6.1 * k + r.uniform(0, 0.5), 12.4 + r.uniform(0, 0.5)), 7.0, 5)
                                            for k in range(5)])
    # strokes as 2D libraries fill them: a wavy polyline outlined 0.25 px, 1/16 px and
    # 1/1000 px wide (the last a hairline sliver that covers next to nothing anywhere)
    wave = np.stack([np.linspace(2.0, 30.0, 40), 16.0 + 9.0 * np.sin(np.linspace(0.0, 2.5 * np.pi, 40))], axis=1)
    add("stroke/wave-0.25px/float", [[thin_stroke(wave, 0.25)]], quick=("nonzero",))
    add("stroke/wave-1/16px/float", [[thin_stroke(wave + 0.3, 1 / 16)]])
    add("stroke/wave-1e-3px/float", [[thin_stroke(wave - 0.2, 1e-3)]], quick=("evenodd",))
    # a sliver: a long needle a thousandth of a pixel wide at its base, across many pixels
    add("sliver/needle/float", [[np.array([[1.3, 2.2], [30.6, 29.1], [1.3 + 1e-3, 2.2]])]], quick=("nonzero",))
    # sub-pixel paths: a pentagram and a ring inside one pixel
    add("sub-pixel/star-0.4px/float", lambda r: [[star(5, 2, r.uniform(10, 11, 2), 0.4, r.uniform(0, 1))]])
    add("sub-pixel/ring-0.45px/float", lambda r: [[regular(24, c := r.uniform(20, 21, 2), 0.45),
                                                   regular(16, c, 0.2)[::-1]]])
    add("ring/hairline/float", lambda r: [[regular(96, c := float_centre(r), 12.0), regular(96, c, 11.9)[::-1]]])
    # collinear vertices along the sides (some on samples); a diagonal side through samples
    add("collinear/square-extra-vertices/lattice",
        [[np.array([[4, 4], [10.5, 4], [16, 4], [28, 4], [28, 15.5], [28, 28], [16, 28], [4, 28], [4, 10]])]],
        quick=("nonzero",), lattice=True)
    add("collinear/diagonal-through-samples/lattice",
        [[np.array([[2.5, 2.5], [8.5, 8.5], [17.5, 17.5], [29.5, 29.5], [2.5, 29.5]])]], lattice=True)
    # zero-length edges: every vertex doubled and the first repeated at the end (as closed
    # files write it)
    doubled = np.repeat(_on_lattice(star(7, 2, (SIZE / 2, SIZE / 2), 12.0)), 2, axis=0)
    add("zero-length-edges/doubled-vertices/lattice", [[_closed(doubled)]], quick=both, lattice=True)
    add("zero-length-edges/closed-explicitly/float", lambda r: [[_closed(regular(9, float_centre(r), 12.0, 0.3))]])
    # spikes: zero-width excursions out of the square along a sample column and into it
    # along a sample row, and a slanted one; they cover nothing
    spiked = np.array([[6, 6], [12.5, 6], [12.5, 0.5], [12.5, 6], [26, 6], [26, 16.5], [13.5, 16.5], [26, 16.5], [26, 26],
                       [6, 26]])
    add("spike/out-and-in/lattice", [[spiked]], quick=both, lattice=True)
    add("spike/slanted/float", lambda r: [[np.array([[6, 6], [26, 6], [26, 17.3], r.uniform(0, 14, size=2), [26, 17.3], [26, 26],
                                                    [6, 26]])]])
    # contours of one and two vertices (on samples) enclose nothing: in a path with a
    # square, and alone
    add("tiny-contours/one-and-two-vertices/lattice",
        [[rectangle(4, 4, 20, 20), np.array([[10.5, 10.5]]), np.array([[6.5, 12.5], [18.5, 12.5]])],
         [np.array([[24.5, 24.5]]), np.array([[22.5, 27.5], [29.5, 27.5]])]], quick=("nonzero",), lattice=True)
    # huge: a ring whose outer square reaches far beyond the viewport (its hole, on screen,
    # wound the same way), a pentagram with an inner corner on screen, a wedge from far away
    small_hole = rectangle(9.5, 9.5, 22.5, 22.5)
    for label, big in (("1e4", 1e4), ("1e6", 1e6), ("1e9", 1e9), ("1e30", 1e30)):
        add(f"huge/ring-{label}", [[rectangle(-big, -big, big, big), small_hole]], quick=both if label == "1e9" else (),
            refusable=() if big < 1e6 else (0,))
    for label, big in (("1e6", 1e6), ("1e9", 1e9)):
        # the inner corners of {5/2} lie R cos(2pi/5) / cos(pi/5) from the centre, half-way
        # between two points: one here at (16.3, 15.7)
        inner = big * math.cos(2 * math.pi / 5) / math.cos(math.pi / 5)
        centre = (16.3 - inner * math.sin(math.pi / 5), 15.7 + inner * math.cos(math.pi / 5))
        add(f"huge/star-inner-corner-{label}", [[star(5, 2, centre, big)]], refusable=(0,))
        add(f"huge/wedge-{label}", [[np.array([[-big, 6.25], [big, 9.75], [16.5, 27.0]])]], refusable=(0,))
    # beyond 2**20 px (where float32 and 24.8 fixed point give out): a band crossing the
    # screen from 2**21 px away on both sides, a glyph 2**22 px tall whose overlapping
    # stem's edge runs down the screen (both clipped to it)
    add("huge/band-2pow21", [[np.array([[-2.0**21, 9.25], [2.0**21, 19.75], [2.0**21, 23.5], [-2.0**21, 13.0]])]],
        refusable=(0,))
    add("huge/glyph-2pow22", [glyph_d((16.3 - 0.274 * 2.0**22, -2.0**21 + 16.3), 2.0**22, 8)], refusable=(0,))
    # epsilon: 1e-9 px contours on and beside pixel centres; a pentagram around a sample
    # (winding 2 there), a square with a 1e-9 px hole around one (wound the same way)
    add("epsilon/star-1e-9-on-sample", [[star(5, 2, (10.5, 12.5), 1e-9, 0.2)]], quick=both)
    add("epsilon/triangles-1e-9",
        [[np.array([[20.5 - 1e-9, 20.5 - 1e-9], [20.5 + 2e-9, 20.5], [20.5, 20.5 + 2e-9]])],  # holds a sample
         [np.array([[8.5 + 1e-9, 8.5 + 1e-9], [8.5 + 3e-9, 8.5 + 1e-9], [8.5 + 1e-9, 8.5 + 3e-9]])],  # beside one
         [np.array([[4.5, 24.5], [4.5 + 1e-9, 24.5 + 1e-9], [4.5 - 1e-9, 24.5 + 1e-9]])]])  # a corner on one
    add("epsilon/hole-1e-9", [[rectangle(4, 4, 28, 28), star(3, 1, (15.5, 15.5), 1e-9)]])
    # several paths in one scene, overlapping: each covers its own pixels
    add("several/mixed/float", lambda r: [[star(5, 2, r.uniform(8, 12, 2), r.uniform(6, 9), r.uniform(0, 7))],
                                          [regular(12, r.uniform(16, 22, 2), 9.0, 0.1),
                                           regular(7, r.uniform(16, 22, 2), 4.0, 0.2)],
                                          [r.uniform(0, 32, size=(4, 2))], _random_contours(r, 2, SIZE, None)], quick=both)
    add("several/lattice", lambda r: [[_on_lattice(star(7, 3, (12.5, 12.5), 10.0))], [outer, hole], [a, b[::-1]],
                                      _random_contours(r, 2, SIZE, 4)], lattice=True)
    for k in range(3):
        add(f"random/lattice-{k}", lambda r: _random_paths(r, 4), lattice=True)
        add(f"random/float-{k}", lambda r: _random_paths(r, None))
    cases += deep_winding_cases()
    return cases + triangle_cases_as_paths(viewport_cases(seed))  # identify's viewport-edge scenes


# -- deep winding ----------------------------------------------------------------------------

# The windings of the deep-winding cases: the first a signed 8-bit counter cannot hold, the
# first it wraps to 0, the first a 16-bit one wraps to 0.
DEEP_WINDINGS = (128, 256, 65536)
DEEP_SIZE = 16
# a triangle on the 1/4 lattice with no sample on an edge, and a square overlapping it,
# both wound alike: anticlockwise on screen, so that the crossings left of a sample count
# up (+1 each: :mod:`harness.oracle.winding`), to +N, one past the largest signed 8-bit integer
# at N = 128 (-128 is one)
DEEP_TRIANGLE = np.array([[0.75, 0.75], [1.25, 7.25], [7.25, 1.25]])
DEEP_SQUARE = rectangle(3, 3, 7, 7)[::-1]


def wound(contour: Contour, turns: int) -> Contour:
    """(K * turns, 2): ``contour`` traced ``turns`` times over as one contour -- winding
    +/- ``turns`` inside it, from K * turns vertices (a contour of K vertices per turn:
    the fewest that wind that often).

    >>> wound(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), 2).shape
    (6, 2)
    """
    return np.tile(np.asarray(contour, dtype=np.float64), (turns, 1))


def deep_winding(turns: int, fill_rule: str, size: int = DEEP_SIZE) -> PathScene:
    """One path of winding ``turns`` at most: :data:`DEEP_TRIANGLE` traced ``turns - 1``
    times and :data:`DEEP_SQUARE` once, alike wound. The samples the triangle shares with
    the square have winding ``turns``, the triangle's others ``turns - 1``, the square's
    own 1: the rules differ on both deep windings (one odd, one even), the answer is
    neither the square's nor the triangle's alone, and a winding counter that wraps (to
    0 at 256 in 8 bits, at 65,536 in 16) or saturates (at 127) shows."""
    return PathScene.from_paths(size, size, [[wound(DEEP_TRIANGLE, turns - 1), DEEP_SQUARE]], fill_rule)


def deep_winding_cases() -> list[Case]:
    """``paths/deep-winding/<turns>/<rule>`` for each of :data:`DEEP_WINDINGS`, under
    both rules (quick and full suites alike): 16 x 16 px, 3 * turns + 1 vertices."""
    return [Case(f"paths/deep-winding/{turns}/{rule}", deep_winding(turns, rule), lattice=True)
            for turns in DEEP_WINDINGS for rule in FILL_RULES]


def _random_paths(rng: np.random.Generator, scale: int | None) -> list[list[Contour]]:
    return [_random_contours(rng, int(rng.integers(1, 4)), SIZE, scale) for _ in range(int(rng.integers(1, 4)))]


# -- degenerate paths ----------------------------------------------------------------------

# Two ordinary paths that every degenerate scene carries (paths 0 and 1).
_ANCHORS = [[rectangle(1.5, 1.5, 8.0, 6.0)], [np.array([[23.0, 24.0], [30.5, 26.5], [25.25, 31.0]])]]


def path_degenerate_cases(seed: int, full: bool = False) -> list[Case]:
    """``path-degenerate/<kind>/<detail>/<rule>``: bad paths from path 2 on."""
    cases: list[Case] = []
    nan, inf = np.nan, np.inf

    def add(name: str, paths: list[list[ArrayLike]], rules: Sequence[str] = FILL_RULES, lattice: bool = False,
            quick: Sequence[str] = ()) -> None:
        for rule in rules:
            if full or rule in quick:
                scene = PathScene.from_paths(SIZE, SIZE, [*_ANCHORS, *paths], rule)
                cases.append(Case(f"path-degenerate/{name}/{rule}", scene, lattice=lattice))

    rng = _rng(seed, "path-degenerate")
    # zero area: every vertex on one line (along a sample row, a sample column, a diagonal
    # through samples) -- nothing, under either rule
    add("zero-area/collinear",
        [[[[2.5, 15.5], [12.5, 15.5], [28.5, 15.5], [7.5, 15.5]]], [[[15.5, 2.5], [15.5, 29.5], [15.5, 9.5]]],
                                [[[3.5, 3.5], [20.5, 20.5], [11.5, 11.5], [27.5, 27.5]]]], lattice=True, quick=("nonzero",))
    add("zero-area/repeated-point", [[[[10.5, 20.5]] * 4], [[[12.0, 12.0]] * 3]], lattice=True)
    # a contour retracing itself, out and back: winding 0 everywhere
    out = np.array([[4.5, 20.5], [12.5, 10.5], [20.5, 22.5], [28.5, 8.5]])
    add("retrace/out-and-back", [[_retraced(out)]], lattice=True, quick=("evenodd",))
    add("retrace/float", [[_retraced(rng.uniform(2, 30, size=(5, 2)))]])
    # a figure eight (a 1:2 Lissajous curve): lobes of winding +1 and -1, so both rules
    # cover the same pixels
    t = 2 * np.pi * np.arange(32) / 32
    eight = _on_lattice(np.stack([16 + 11 * np.sin(2 * t), 16 + 13 * np.sin(t)], axis=-1))
    add("figure-8/lattice", [[eight]], lattice=True, quick=FILL_RULES)
    # the same contour twice: winding 2 (even-odd covers nothing); with one reversed: 0
    pentagon = _on_lattice(regular(5, (15.5, 15.5), 10.0, 0.3))
    add("duplicate-contours/same", [[pentagon, pentagon.copy()]], lattice=True, quick=FILL_RULES)
    add("duplicate-contours/reversed", [[pentagon, pentagon[::-1]]], lattice=True)
    # non-finite vertices: such a path covers nothing, the others are drawn as ever
    add("non-finite/mixed",
        [[[[nan, 4.0], [20.0, 10.0], [4.0, 20.0]]], [rectangle(6, 6, 18, 18), np.array([[inf, 10], [12, 12], [10, 14]])],
                             [[[4.0, 4.0], [10.0, 10.0], [4.0, -inf]]], [[[nan, nan], [nan, nan], [nan, nan]]], [[[nan, inf]]],
                             [[[12.5, 12.5], [20.5, 12.5], [12.5, 20.5]]]], quick=("nonzero",))
    # a contour of one vertex (on a sample, on a corner) and one of two: nothing
    add("one-vertex/on-sample", [[[[10.5, 10.5]]], [[[16.0, 16.0]]], [[[6.5, 20.5], [26.5, 20.5]]]], lattice=True,
        quick=("nonzero",))
    from cases.degenerate import degenerate_cases, probe_scenes  # identify's degenerate probe scenes

    probes = {f"degenerate/{name}" for name in probe_scenes()}
    return cases + triangle_cases_as_paths([c for c in degenerate_cases(seed) if c.id in probes])


def path_cases(seed: int, full: bool = False) -> list[Case]:
    """Every path case of a suite: ``paths/...``, ``path-partitions/...``,
    ``path-degenerate/...`` (:data:`PATH_FAMILIES`)."""
    return [*shape_cases(seed, full), *path_partition_cases(seed, full), *path_degenerate_cases(seed, full)]
