"""Line cases: segments, polylines and bad lines, for the three line rules (diamond exit,
Bresenham, rectangles; :mod:`harness.oracle.lines`).

Three families, every case a :class:`~harness.contract.scenes.LineScene`:

- ``lines/<kind>/<detail>``: separate segments. Lattice fans from a pixel centre, a pixel
  corner and an edge midpoint to points of the same kind in every octant (slopes 0, +-1/2,
  +-1, +-2, vertical and between); lines through the diamonds' corners and along their
  edges (the test areas' ties); end points on the diamonds' corners and edges; random
  segments on the 1/2 and 1/8 lattices; random float segments short and long; lattice
  segments nudged by about 1e-6 px (near ties); sub-pixel segments (on the 1/16 lattice
  and float); long segments across the viewport; and rectangle-width cases,
  ``lines/wide-2.5/...`` and ``lines/wide-0.25/...`` (the diamond-exit and Bresenham
  rules draw width 1 only: a rasterizer of those raises Unsupported, a skip).
- ``line-strips/<kind>/<detail>``: polylines whose joints lie on pixel centres, pixel
  corners, the diamonds' edges, or anywhere; closed loops (last vertex equal to the first);
  spirals; zig-zags switching between x-major and y-major; star polygons.
- ``line-degenerate/<kind>``: zero-length segments (alone and inside strips), 1e-9 px
  segments, huge coordinates (1e4, 1e10, 1e200) with part of the segment on screen, NaN and
  infinite end points. Strips 0 and 1 of each scene are ordinary, so that a rasterizer that
  mishandles the bad segments cannot hide it by drawing nothing at all. Segments with a
  coordinate of 1e6 or more are ``refusable`` (a reference may decline them, naming the
  segment); non-finite ones cover nothing (:attr:`harness.contract.case.Case.non_finite`).

``lattice`` cases have every coordinate on a dyadic lattice of 1/16 px or coarser (exact
in every arithmetic, ties on purpose). Every case draws from its own generator, seeded by
the suite's seed and its id, so a case is the same in the quick and the full suite, and
ids do not depend on the seed.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.case import Case
from harness.contract.scenes import LineScene

__all__ = ["line_cases", "segment_cases", "strip_cases", "line_degenerate_cases", "fan", "spiral", "zigzag", "LINE_FAMILIES"]

LINE_FAMILIES = ("lines", "line-strips", "line-degenerate")

SIZE = 32
LARGE = 48
# |coordinate| from which a segment may be refused (ValueError naming it)
REFUSABLE_FROM = 1e6

Points = NDArray[np.float64]
Segments = tuple[Points, Points]


def _rng(seed: int, name: str) -> np.random.Generator:
    """The case's own generator: the same draws whatever else the suite holds."""
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def _on_lattice(points: ArrayLike, scale: int) -> Points:
    """Points rounded to the 1/scale lattice."""
    return np.round(np.asarray(points, dtype=np.float64) * scale) / scale


# -- geometry --------------------------------------------------------------------------------


def fan(origin: ArrayLike, reach: int, steps: Sequence[int] = (0, 3, 5, 7)) -> Segments:
    """Segments from ``origin`` to ``origin + (dx, dy)`` for every integer offset with
    ``max(|dx|, |dy|) == reach`` whose other component is 0, +-reach or +-s for s in
    ``steps`` (so end points are of the origin's kind: centre, corner or edge midpoint),
    every octant and both axes.

    >>> a, b = fan((0.5, 0.5), 4, steps=(0, 2))
    >>> d = b - a
    >>> len(d), sorted({float(y / x) + 0.0 for x, y in d if x != 0}), int((d[:, 0] == 0).sum())
    (16, [-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0], 2)
    """
    others = sorted({0, reach, -reach, *(s for s in steps if s < reach), *(-s for s in steps if s < reach)})
    offsets = {(reach * sx, o) for sx in (1, -1) for o in others} | {(o, reach * sy) for sy in (1, -1) for o in others}
    d = np.array(sorted(offsets), dtype=np.float64)
    a = np.broadcast_to(np.asarray(origin, dtype=np.float64), d.shape).copy()
    return a, a + d


def spiral(centre: ArrayLike, turns: float, points: int, radius: float) -> Points:
    """(points, 2): an Archimedean spiral from the centre out to ``radius``."""
    t = np.linspace(0.0, 1.0, points)
    angle = 2 * np.pi * turns * t
    c = np.asarray(centre, dtype=np.float64)
    return np.stack([c[0] + radius * t * np.cos(angle), c[1] + radius * t * np.sin(angle)], axis=-1)


def zigzag(start: ArrayLike, step: ArrayLike, count: int) -> Points:
    """(count + 1, 2): from ``start``, steps alternating (sx, sy) and (sx, -sy) -- or, with
    sx < 0 in ``step``, alternating in x instead: (sx, sy) then (-sx, sy)."""
    sx, sy = (float(v) for v in np.asarray(step, dtype=np.float64))
    moves = np.array([[abs(sx), sy if k % 2 == 0 else -sy] for k in range(count)]) if sx >= 0 else \
        np.array([[-sx if k % 2 == 0 else sx, abs(sy)] for k in range(count)])
    return np.concatenate([np.asarray(start, dtype=np.float64)[None],
                           np.asarray(start, dtype=np.float64) + np.cumsum(moves, axis=0)])


def _star(n: int, k: int, centre: ArrayLike, radius: float, turn: float = 0.0) -> Points:
    """(n + 1, 2): the closed star polygon {n/k} (its first vertex repeated at the end)."""
    angle = turn + 2 * np.pi * ((np.arange(n + 1) * k) % n) / n
    c = np.asarray(centre, dtype=np.float64)
    return np.stack([c[0] + radius * np.sin(angle), c[1] - radius * np.cos(angle)], axis=-1)


def _random_segments(rng: np.random.Generator, count: int, size: float, length: tuple[float, float],
                     margin: float = 2.0) -> Segments:
    """``count`` segments starting in [-margin, size + margin]^2, of lengths in ``length``,
    in random directions."""
    a = rng.uniform(-margin, size + margin, size=(count, 2))
    angle = rng.uniform(0, 2 * np.pi, size=count)
    r = rng.uniform(*length, size=count)
    return a, a + r[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def _lattice_segments(rng: np.random.Generator, count: int, size: int, reach: int, scale: int) -> Segments:
    """``count`` segments on the 1/scale lattice: starts in the viewport (and a pixel
    beyond), ends up to ``reach`` px away along each axis."""
    a = rng.integers(-scale, (size + 1) * scale, size=(count, 2)) / scale
    b = a + rng.integers(-reach * scale, reach * scale + 1, size=(count, 2)) / scale
    return a, b


def _through_diamond_corners(size: int) -> Segments:
    """Lines whose slopes and offsets put them exactly on the diamonds' corners and edges:
    horizontal at integer y (through the bottom corners of one row and the top corners of
    the next), vertical at integer x (left and right corners), slope +-1 through the left
    and right corners (along the diamonds' edges), slope 1/2 through bottom corners, slope
    2 through right corners, each way round."""
    m = float(size)
    lines = [
        ((1.0, 6.0), (m - 2.0, 6.0)),  # y = 6: bottom corners of row 5, top corners of row 6
        ((m - 1.5, 9.0), (2.5, 9.0)),  # the same, right to left, from centre-x to centre-x
        ((5.0, 1.5), (5.0, m - 2.5)),  # x = 5: right corners of column 4, left corners of 5
        ((11.0, m - 1.0), (11.0, 3.0)),  # the same, upwards
        ((1.0, 2.5), (m - 6.0, m - 4.5)),  # y = x + 1.5: through left/right corners, on edges
        ((m - 3.0, 1.5), (4.0, m - 5.5)),  # slope -1 through left/right corners
        ((2.5, 4.0), (m - 1.5, 4.0 + (m - 4.0) / 2)),  # slope 1/2 through bottom corners (x = i + 1/2, y = j + 1)
        ((m - 2.5, 20.0), (0.5, 20.0 - (m - 3.0) / 2)),  # slope 1/2, leftwards and up
        ((3.0, 0.5), (3.0 + (m - 2.0) / 2, m - 1.5)),  # slope 2 through right corners (x = i + 1, y = j + 1/2)
        ((20.0, m - 0.5), (20.0 - (m - 4.0) / 2, 3.5)),  # slope 2, up and left
        ((0.5, 0.0), (m - 0.5, m - 1.0)),  # slope 1 through top corners: along upper-right edges
        ((m, 16.5), (16.5, m)),  # slope -1 through right and bottom corners: along lower-right edges
    ]
    return np.array([p for p, _ in lines]), np.array([q for _, q in lines])


def _ends_on_diamonds(centres: Points) -> Segments:
    """Segments ending (and starting) on each diamond corner and edge midpoint around the
    given pixel centres, in x-major and y-major directions, each way round."""
    boundary = np.array([[0.0, -0.5], [0.5, 0.0], [0.0, 0.5], [-0.5, 0.0],  # top, right, bottom, left corners
                         [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25], [-0.25, -0.25]])  # edge midpoints
    directions = np.array([[5.0, 1.0], [5.0, -2.0], [1.0, 5.0], [-2.0, 5.0], [4.0, 4.0], [4.0, -4.0]])
    a, b = [], []
    for k, c in enumerate(centres):
        for m, off in enumerate(boundary):
            d = directions[(k + m) % len(directions)]
            end = c + off
            a += [end - d, end]  # ending on the boundary, starting on it
            b += [end, end + d[::-1] * [1, -1]]
    return np.array(a), np.array(b)


def _around_centres(rng: np.random.Generator, count: int, size: int) -> Segments:
    """Segments of up to 0.6 px either way around random pixel centres: short, and ending
    in the centre's diamond or just outside it."""
    centres = np.floor(rng.uniform(0, size, size=(count, 2))) + 0.5
    return centres + rng.uniform(-0.6, 0.6, size=centres.shape), centres + rng.uniform(-0.6, 0.6, size=centres.shape)


def _across(rng: np.random.Generator, count: int, size: int) -> Segments:
    """Segments with both ends outside the viewport, 1 to 2 viewports from its centre, at
    directions roughly opposite (most cross it, some pass beside it)."""
    centre = np.array([size / 2, size / 2])
    angle = rng.uniform(0, 2 * np.pi, size=count)
    other = angle + np.pi + rng.uniform(-0.6, 0.6, size=count)
    radius = rng.uniform(size, 2 * size, size=(2, count, 1))
    a = centre + radius[0] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    b = centre + radius[1] * np.stack([np.cos(other), np.sin(other)], axis=-1)
    return a, b


def _nudged(segments: Segments, rng: np.random.Generator, amount: float = 1e-6) -> Segments:
    """The segments with every coordinate moved by up to ``amount``."""
    a, b = segments
    return a + rng.uniform(-amount, amount, size=a.shape), b + rng.uniform(-amount, amount, size=b.shape)


# -- the families ---------------------------------------------------------------------------------


def segment_cases(seed: int, full: bool = False) -> list[Case]:
    """``lines/<kind>/<detail>``: separate segments."""
    cases: list[Case] = []

    def add(name: str, segments: Segments | Callable[[np.random.Generator], Segments], quick: bool = False,
            lattice: bool = False, size: int = SIZE, line_width: float = 1.0) -> None:
        if not (full or quick):
            return
        a, b = segments(_rng(seed, name)) if callable(segments) else segments
        cases.append(Case(f"lines/{name}", LineScene.from_segments(size, size, a, b, line_width), lattice=lattice))

    # fans in every octant from a pixel centre, a corner and an edge midpoint, to points of
    # the same kind: slopes 0, +-3/10, +-1/2, +-7/10, +-1, +-2, vertical
    add("octants/centres", fan((15.5, 15.5), 10, (0, 3, 5, 7)), quick=True, lattice=True)
    add("octants/corners", fan((16.0, 16.0), 10, (0, 3, 5, 7)), quick=True, lattice=True)
    add("octants/edge-midpoints", fan((16.5, 16.0), 10, (0, 3, 5, 7)), quick=True, lattice=True)
    add("octants/short-centres", fan((15.5, 15.5), 2, (0, 1)), quick=True, lattice=True)
    add("octants/long-corners", fan((24.0, 24.0), 22, (0, 5, 11, 17)), lattice=True, size=LARGE)
    # the test areas' ties: lines through diamond corners and along diamond edges
    add("ties/through-diamond-corners", _through_diamond_corners(SIZE), quick=True, lattice=True)
    add("ties/ends-on-diamonds", _ends_on_diamonds(np.array([[8.5, 8.5], [20.5, 12.5], [12.5, 22.5]])), quick=True, lattice=True)
    add("ties/ends-on-diamonds-many", _ends_on_diamonds(np.array([[x + 0.5, y + 0.5] for x in (6, 14, 22) for y in (6, 14, 22)])),
        lattice=True)
    # random segments on dyadic lattices, short and long
    add("lattice/random-1-8", lambda r: _lattice_segments(r, 200, SIZE, 4, 8), quick=True, lattice=True)
    add("lattice/random-1-2", lambda r: _lattice_segments(r, 100, SIZE, 16, 2), quick=True, lattice=True)
    add("lattice/random-1-16-long", lambda r: _lattice_segments(r, 200, LARGE, 40, 16), lattice=True, size=LARGE)
    add("lattice/sub-pixel", lambda r: _lattice_segments(r, 200, SIZE, 1, 16), quick=True, lattice=True)
    # float segments
    add("float/random-short", lambda r: _random_segments(r, 300, SIZE, (0.5, 4.0)), quick=True)
    add("float/random-long", lambda r: _random_segments(r, 60, LARGE, (10.0, 60.0)), quick=True, size=LARGE)
    add("float/random-many", lambda r: _random_segments(r, 2000, 96.0, (0.5, 12.0)), size=96)
    add("float/sub-pixel", lambda r: _random_segments(r, 200, SIZE, (0.01, 0.9)), quick=True)
    add("float/sub-pixel-around-centres", lambda r: _around_centres(r, 200, SIZE), quick=True)
    # near ties: lattice segments (1/2 and 1/4) nudged by about a micro-pixel
    add("float/near-ties-1e-6", lambda r: _nudged(_lattice_segments(r, 200, SIZE, 8, 4), r), quick=True)
    add("float/near-diamond-ties-1e-6", lambda r: _nudged(_through_diamond_corners(SIZE), r), quick=True)
    # long segments across the viewport: both ends outside, on opposite sides or not
    add("float/across-viewport", lambda r: _across(r, 40, LARGE), quick=True, size=LARGE)
    add("lattice/across-viewport", lambda r: (_on_lattice(r.uniform(-80, 130, size=(60, 2)), 4),
                                              _on_lattice(r.uniform(-80, 130, size=(60, 2)), 4)), lattice=True, size=LARGE)
    # rectangular widths (diamond-exit and Bresenham: unsupported)
    for w, label in ((2.5, "2.5"), (0.25, "0.25"), (1.5, "1.5"), (4.0, "4")):
        quick = label in ("2.5", "0.25")
        add(f"wide-{label}/octants-centres", fan((15.5, 15.5), 10, (0, 3, 5)), quick=quick, lattice=True, line_width=w)
        add(f"wide-{label}/lattice", lambda r: _lattice_segments(r, 80, SIZE, 8, 4), quick=quick, lattice=True, line_width=w)
        add(f"wide-{label}/float", lambda r: _random_segments(r, 80, SIZE, (0.5, 12.0)), quick=quick and w > 1, line_width=w)
    add("wide-2.5/ties", _through_diamond_corners(SIZE), lattice=True, line_width=2.5)
    return cases


def _walk(rng: np.random.Generator, count: int, size: int, reach: int, scale: int, offset: float) -> Points:
    """(count, 2): a random polyline on the 1/scale lattice shifted by ``offset`` (0.5:
    pixel centres when scale is 1), kept in the viewport."""
    steps = rng.integers(-reach * scale, reach * scale + 1, size=(count - 1, 2)) / scale
    start = rng.integers(size // 4, 3 * size // 4, size=2).astype(np.float64)
    points = np.concatenate([start[None], start + np.cumsum(steps, axis=0)])
    walk: Points = np.mod(points, size - 1) + offset
    return walk


def _diamond_walk(rng: np.random.Generator, count: int, size: int) -> Points:
    """(count, 2): a polyline whose vertices all lie on diamond boundaries: pixel centres
    plus a corner (+-1/2 along one axis) or an edge midpoint (+-1/4, +-1/4)."""
    centres = np.floor(rng.uniform(2, size - 2, size=(count, 2))) + 0.5
    boundary = np.array([[0.0, -0.5], [0.5, 0.0], [0.0, 0.5], [-0.5, 0.0], [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25],
                         [-0.25, -0.25]])
    walk: Points = centres + boundary[rng.integers(0, len(boundary), size=count)]
    return walk


def strip_cases(seed: int, full: bool = False) -> list[Case]:
    """``line-strips/<kind>/<detail>``: polylines sharing their end points."""
    cases: list[Case] = []

    def add(name: str, strips: Sequence[ArrayLike] | Callable[[np.random.Generator], Sequence[ArrayLike]], quick: bool = False,
            lattice: bool = False, size: int = SIZE, line_width: float = 1.0) -> None:
        if not (full or quick):
            return
        built = strips(_rng(seed, name)) if callable(strips) else strips
        cases.append(Case(f"line-strips/{name}", LineScene.from_strips(size, size, built, line_width), lattice=lattice))

    # joints on pixel centres, pixel corners, diamond boundaries, anywhere
    add("joints/centres", lambda r: [_walk(r, 12, SIZE, 8, 1, 0.5) for _ in range(4)], quick=True, lattice=True)
    add("joints/corners", lambda r: [_walk(r, 12, SIZE, 8, 1, 0.0) for _ in range(4)], quick=True, lattice=True)
    add("joints/diamond-edges", lambda r: [_diamond_walk(r, 10, SIZE) for _ in range(4)], quick=True, lattice=True)
    add("joints/lattice-1-8", lambda r: [_walk(r, 16, SIZE, 6, 8, 0.0) for _ in range(4)], lattice=True)
    add("joints/float", lambda r: [r.uniform(0, SIZE, size=(10, 2)) for _ in range(4)], quick=True)
    add("joints/float-short-steps",
        lambda r: [np.cumsum(r.uniform(-1.5, 1.5, size=(40, 2)), axis=0) + SIZE / 2 for _ in range(3)])
    # closed loops: the last vertex equals the first exactly
    square = np.array([[4.5, 4.5], [27.5, 4.5], [27.5, 27.5], [4.5, 27.5], [4.5, 4.5]])
    diamond = np.array([[16.0, 2.0], [30.0, 16.0], [16.0, 30.0], [2.0, 16.0], [16.0, 2.0]])
    add("closed/square-and-diamond", [square, diamond], quick=True, lattice=True)
    add("closed/polygons-lattice", lambda r: [_on_lattice(_star(n, 1, r.uniform(12, 20, 2), r.uniform(6, 12), r.uniform(0, 6)), 4)
                                              for n in (3, 5, 8)], lattice=True)
    add("closed/polygons-float",
        lambda r: [_star(n, 1, r.uniform(12, 20, 2), r.uniform(6, 12), r.uniform(0, 6)) for n in (4, 7, 12)], quick=True)
    # spirals: many short segments turning through every octant
    add("spiral/lattice", [_on_lattice(spiral((16, 16), 3.0, 60, 14.0), 4)], quick=True, lattice=True)
    add("spiral/float", lambda r: [spiral(r.uniform(15, 17, 2), 4.0, 90, 14.0)])
    add("spiral/tight-float", lambda r: [spiral(r.uniform(15, 17, 2), 6.0, 200, 6.0)])
    # zig-zags: slopes +-1 exactly (the x-major tie) and switching between the axes
    add("zigzag/diagonal-centres", [zigzag((2.5, 10.5), (3, 3), 9), zigzag((2.5, 20.5), (2, -2), 13)], quick=True, lattice=True)
    add("zigzag/steep-and-shallow",
        [zigzag((1.0, 4.0), (5, 2), 6), zigzag((4.0, 1.0), (-2, 5), 6), zigzag((1.5, 28.5), (3, -1), 9)],
        quick=True, lattice=True)
    add("zigzag/float", lambda r: [zigzag(r.uniform(1, 3, 2), r.uniform(1, 4, 2), 8) for _ in range(2)])
    # star polygons, closed
    add("star/lattice-5-2", [_on_lattice(_star(5, 2, (16, 16), 13.0), 4)], quick=True, lattice=True)
    add("star/float-7-3", lambda r: [_star(7, 3, r.uniform(15, 17, 2), 13.0, r.uniform(0, 6))], quick=True)
    add("star/wide-2.5", [_on_lattice(_star(5, 2, (16, 16), 13.0), 4)], quick=True, lattice=True, line_width=2.5)
    add("star/many-points", lambda r: [_star(17, 7, (24, 24), 22.0, r.uniform(0, 6))], size=LARGE)
    return cases


# Two ordinary strips that every degenerate scene carries (segments 0, 1 and 2).
_ANCHORS = [np.array([[1.5, 1.5], [9.5, 4.5], [12.0, 9.25]]), np.array([[30.5, 24.0], [22.25, 30.5]])]


def line_degenerate_cases(seed: int, full: bool = False) -> list[Case]:
    """``line-degenerate/<kind>``: bad segments after the anchors' three."""
    cases: list[Case] = []
    nan, inf = np.nan, np.inf

    def add(name: str, strips: Sequence[ArrayLike], quick: bool = False, lattice: bool = False) -> None:
        if not (full or quick):
            return
        scene = LineScene.from_strips(SIZE, SIZE, [*_ANCHORS, *strips])
        a, b = scene.segments()
        with np.errstate(invalid="ignore"):
            big = np.abs(np.concatenate([a, b], axis=1))
            refusable = np.flatnonzero(np.isfinite(big).all(axis=1) & (big >= REFUSABLE_FROM).any(axis=1))
        cases.append(Case(f"line-degenerate/{name}", scene, lattice=lattice, refusable=tuple(int(k) for k in refusable)))

    rng = _rng(seed, "line-degenerate")
    # zero length: on a pixel centre, a corner, each diamond corner, an edge midpoint, a float;
    # and inside strips (a vertex repeated)
    points = [[10.5, 10.5], [16.0, 16.0], [20.5, 6.0], [21.0, 12.5], [20.5, 19.0], [20.0, 24.5], [6.25, 20.25]]
    add("zero-length/lattice", [[p, p] for p in points] + [[[4.5, 26.5], [8.5, 26.5], [8.5, 26.5], [8.5, 29.5]]], quick=True,
        lattice=True)
    add("zero-length/float",
        [[p, p] for p in rng.uniform(0, SIZE, size=(8, 2))] + [np.repeat(rng.uniform(4, 28, size=(3, 2)), 2, axis=0)])
    # 1e-9 px segments: from a centre, from a corner, across a bottom corner, across a
    # left/right corner, from an edge midpoint along the edge, back across a right corner,
    # and a strip of two
    e = 1e-9
    add("epsilon/1e-9", [[[10.5, 10.5], [10.5 + e, 10.5 + e]], [[16.0, 16.0], [16.0 - e, 16.0]],
                         [[20.5, 7.0 - e], [20.5, 7.0 + e]], [[6.0 - e, 20.5], [6.0 + e, 20.5]],
                         [[24.25, 8.25], [24.25 + e, 8.25 - e]], [[15.0 + e, 25.5], [15.0 - e, 25.5]],
                         [[4.0, 4.0], [4.0 + e, 4.0 + 2 * e], [4.0 + 3 * e, 4.0]]], quick=True)
    # huge: crossing the viewport with ends far away on both sides, or one end on screen
    for label, big in (("1e4", 1e4), ("1e10", 1e10), ("1e200", 1e200)):
        huge = [[[-big, 10.3], [big, 20.7]],  # nearly horizontal, across
                [[15.5, 15.5], [big, big * 0.5]],  # from a centre, off screen
                [[12.25, -big], [19.75, big]],  # nearly vertical, across
                [[-big, -big], [big, big]],  # the diagonal through corners
                [[-big, big], [big, -big + 32.0]]]  # an anti-diagonal (rounded)
        add(f"huge/{label}", huge, quick=label != "1e200")
        # beyond 2**150 the oracle decides rectangles sample by sample in rationals: the
        # quick suite keeps two such segments
        if label == "1e200":
            add(f"huge/{label}-two", huge[:2], quick=True)
    add("huge/1e6-strip", [[[-1e6, 8.5], [16.5, 16.5], [1e6, 24.5], [1e6, -1e6], [16.0, 16.0]]])
    # non-finite: a segment with a NaN or infinite end covers nothing; in a strip, a bad
    # vertex spoils both its segments
    add("non-finite/mixed", [[[nan, 4.0], [20.0, 10.0]], [[4.0, 4.0], [inf, 10.0]], [[-inf, -inf], [inf, inf]],
                             [[4.5, 20.5], [10.5, 22.5], [nan, nan], [16.5, 20.5], [26.5, 14.5]], [[12.5, 12.5], [12.5, -inf]]],
        quick=True)
    return cases


def line_cases(seed: int, full: bool = False) -> list[Case]:
    """Every line case of a suite: ``lines/...``, ``line-strips/...``,
    ``line-degenerate/...`` (:data:`LINE_FAMILIES`).

    >>> cases = line_cases(0)
    >>> sorted({c.family for c in cases}), len({c.id for c in cases}) == len(cases)
    (['line-degenerate', 'line-strips', 'lines'], True)
    """
    return [*segment_cases(seed, full), *strip_cases(seed, full), *line_degenerate_cases(seed, full)]
