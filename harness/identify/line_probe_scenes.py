"""The scenes identify's line probes draw (:mod:`harness.identify.line_probes`): crafted segments
in every octant and at every pixel landmark (:func:`crafted_lines`), lattice segments and
strips, nudged ladders that part the end point roundings, float segments, the rectangle rule's
tie segments and half-step segments for snapping; each a
:class:`~harness.contract.scenes.LineScene` within 2 px of a :data:`PROBE_SIZE` viewport.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import LineScene

__all__ = ["PROBE_SIZE", "crafted_lines", "lattice_lines", "nudged_lines", "float_lines", "rectangle_tie_lines", "half_step_lines"]

# The probe viewport: every probe segment lies within 2 px of it.
PROBE_SIZE = 40


# --- the probe scenes ---------------------------------------------------------------------------


# Directions of the crafted segments (x, y; y down): slopes 0, 1/2, 1, 2 and infinite, every
# sign, so that every octant, both majors and Bresenham's walk in both senses appear.
_DIRECTIONS = list(dict.fromkeys((dx * sx, dy * sy) for dx, dy in ((6, 3), (3, 6), (6, 0), (0, 6), (4, 4), (5, 1))
                                 for sx in (1, -1) for sy in (1, -1)))
# Where in a pixel they start: a corner, the centre, diamond corners, a diamond edge, off both.
_STARTS = ((0.0, 0.0), (0.5, 0.5), (0.5, 0.0), (0.0, 0.5), (0.25, 0.25), (0.75, 0.5))
# Segments inside one pixel (offsets in it): in a corner outside the diamond, across the
# diamond, inside it, along its diagonals, ending on its edges and corners.
_INSIDE = (((0.25, 0.0), (0.0, 0.25)), ((0.25, 0.5), (0.75, 0.5)), ((0.5, 0.25), (0.5, 0.75)), ((0.0, 0.5), (0.25, 0.5)),
           ((0.75, 0.75), (1.0, 1.0)), ((0.25, 0.25), (0.75, 0.75)), ((0.5, 0.5), (1.0, 0.5)), ((0.5, 0.5), (0.5, 1.0)),
           ((0.25, 0.75), (0.5, 0.5)), ((0.75, 0.25), (0.75, 0.0)))
# Zero-length segments: at a centre, a corner, diamond corners, diamond edges.
_POINTS = ((0.5, 0.5), (0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.25, 0.25), (0.75, 0.75), (0.25, 0.75), (1.0, 0.5))
# End points on x = 0, y = 0 and negative integers (half-away and floor part only there), and
# negative fractions (floor and toward-zero part there).
_EDGE = (((0.0, 5.25), (6.0, 8.0)), ((-1.0, 10.0), (5.0, 12.5)), ((2.25, 0.0), (5.0, 6.0)), ((3.0, -2.0), (6.0, 4.0)),
         ((0.0, 0.0), (6.0, 3.0)), ((-2.0, -1.0), (4.0, 2.0)), ((0.0, 20.0), (3.0, 26.0)), ((13.0, 0.0), (19.0, 0.0)),
         ((0.0, 30.5), (0.0, 36.5)), ((-3.0, 16.0), (2.0, 16.0)),
         # fractional negative end points: floor and toward-zero (C's cast) part here
         ((-0.75, 3.25), (5.25, 6.0)), ((4.5, -0.5), (7.25, 5.0)), ((-1.5, 22.25), (4.0, 24.0)),
         ((-0.25, -0.75), (3.0, 2.25)))


def crafted_lines() -> LineScene:
    """The segments where the candidate rules part on purpose (see the module docstring),
    each way round, in a :data:`PROBE_SIZE` square; every coordinate a multiple of 1/4.

    >>> scene = crafted_lines()
    >>> len(scene), bool(np.all(scene.vertices * 4 == np.round(scene.vertices * 4)))
    (304, True)
    """
    a: list[tuple[float, float]] = []
    b: list[tuple[float, float]] = []
    n = 0
    for d in _DIRECTIONS:
        for s in _STARTS:
            # starts 7 .. 33: a 6 px segment stays on screen whichever way it runs
            x, y = 7 + (n * 7) % 27 + s[0], 7 + (n * 11) % 27 + s[1]
            a.append((x, y))
            b.append((x + d[0], y + d[1]))
            n += 1
    for k, (p, q) in enumerate(_INSIDE):
        x, y = 4 + 3 * k, 35
        a.append((x + p[0], y + p[1]))
        b.append((x + q[0], y + q[1]))
    for k, p in enumerate(_POINTS):
        x, y = 35, 3 + 3 * k
        a.append((x + p[0], y + p[1]))
        b.append((x + p[0], y + p[1]))
    a += [p for p, _ in _EDGE]
    b += [q for _, q in _EDGE]
    start, end = np.array(a), np.array(b)
    return LineScene.from_segments(PROBE_SIZE, PROBE_SIZE, np.concatenate([start, end]), np.concatenate([end, start]))


def _lattice_points(rng: np.random.Generator, count: int) -> NDArray[np.float64]:
    """(count, 2) end points on the 1/4 px lattice in [-2, PROBE_SIZE + 2], a third on pixel
    centres and a fifth on pixel corners."""
    points = rng.integers(-8, 4 * (PROBE_SIZE + 2), size=(count, 2)) / 4.0
    on_centre = rng.random(count) < 0.33
    points[on_centre] = np.floor(points[on_centre]) + 0.5
    on_corner = rng.random(count) < 0.2
    points[on_corner] = np.floor(points[on_corner])
    return points


def _lattice_steps(rng: np.random.Generator, count: int) -> NDArray[np.float64]:
    """(count, 2) segment vectors on the 1/4 px lattice: a third short (up to 1 px each
    way), a third up to 6 px, a third up to 20 px; a quarter of them integer vectors of
    slope 1/2 or 2 (Bresenham's ties) and a tenth zero."""
    reach = np.choose(rng.integers(0, 3, size=count), [4, 24, 80])[:, None]
    steps = np.round(rng.uniform(-1.0, 1.0, size=(count, 2)) * reach) / 4.0
    halves = rng.random(count) < 0.25
    k = rng.integers(1, 5, size=count) * rng.choice([-1, 1], size=count)
    m = rng.choice([-1, 1], size=count)
    flip = rng.random(count) < 0.5
    steps[halves] = np.where(flip[:, None], np.stack([k, 2 * m * np.abs(k)], axis=1),
                             np.stack([2 * m * np.abs(k), k], axis=1))[halves]
    steps[rng.random(count) < 0.1] = 0.0
    return steps


def lattice_lines(seed: int, count: int = 150, strips: bool = False) -> LineScene:
    """``count`` random segments with end points on the 1/4 px lattice (centres and corners
    on purpose, :func:`_lattice_points`, :func:`_lattice_steps`); with ``strips``, as
    polylines of up to 6 segments instead (each vertex the last one plus a step).

    >>> len(lattice_lines(0)), len(lattice_lines(0, 40, strips=True))
    (150, 40)
    """
    rng = np.random.default_rng(seed + 61)
    if not strips:
        a = _lattice_points(rng, count)
        b = np.clip(a + _lattice_steps(rng, count), -2.0, PROBE_SIZE + 2.0)
        return LineScene.from_segments(PROBE_SIZE, PROBE_SIZE, a, b)
    pieces = []
    left = count
    while left > 0:
        n = min(left, int(rng.integers(1, 7)))
        start = _lattice_points(rng, 1)
        path = np.concatenate([start, start + np.cumsum(_lattice_steps(rng, n), axis=0)])
        pieces.append(np.clip(path, -2.0, PROBE_SIZE + 2.0))
        left -= n
    return LineScene.from_strips(PROBE_SIZE, PROBE_SIZE, pieces)


# The ladder's bases for the moved coordinate: zero (half-away and floor part there), an
# odd and an even integer (nearest-even parts from both), a pixel centre, a diamond edge.
_LADDER_BASES = (0.0, 7.0, 10.0, 12.5, 15.25)
# The rest of each ladder segment, x-major and y-major (a move along the major axis of a
# line that runs off-screen may change no pixel on screen; one across it always shows).
_LADDER_STEPS = ((6, 3), (3, -6), (5, 0), (4, 4), (1, 6), (6, -1), (2, 6))


def _ladder() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """End points (a, b), (N, 2) each: for every base of :data:`_LADDER_BASES`, k from 2
    to 20 and both signs, a segment with one end point's x (then y) at base +- 2**-k, the
    rest on the 1/4 px lattice, the moved end point the first or the last in turn: every
    snapping grid meets a move just below and just above its half step at each kind of
    decision boundary, whatever the seed. Then axis-aligned segments whose starting cap
    runs through sample points (pixel corners, pixel centres) moved likewise: the
    rectangles' decision boundaries."""
    a: list[tuple[float, float]] = []
    b: list[tuple[float, float]] = []
    n = 0
    for axis in (0, 1):
        for base in _LADDER_BASES:
            for k in range(2, 21):
                for sign in (1.0, -1.0):
                    moved = [base + sign * 2.0**-k, 2.0 + n % 33 + (0.0, 0.5, 0.25)[n % 3]]
                    step = _LADDER_STEPS[(n // 2) % len(_LADDER_STEPS)]  # both signs alike
                    other = [base + step[0], moved[1] + step[1]]
                    if axis:
                        moved, other = moved[::-1], other[::-1]
                    # the moved end point first or last: the signs opposite, alternating with k
                    first = (k % 2 == 0) == (sign > 0)
                    a.append((moved[0], moved[1]) if first else (other[0], other[1]))
                    b.append((other[0], other[1]) if first else (moved[0], moved[1]))
                    n += 1
    # caps through samples: axis-aligned segments starting at base +- 2**-k, on a row
    # (column) of samples, the cap through sample points at a pixel corner or centre
    for axis in (0, 1):
        for base, row in ((7.0, 0.0), (12.5, 0.5)):
            for k in range(2, 21):
                for sign in (1.0, -1.0):
                    j = 1.0 + k + 18.0 * (sign > 0) + row  # rows 3 .. 39.5: on screen
                    moved, other = [base + sign * 2.0**-k, j], [base + 5.0, j]
                    if axis:
                        moved, other = moved[::-1], other[::-1]
                    a.append((moved[0], moved[1]))
                    b.append((other[0], other[1]))
    return np.array(a), np.array(b)


def nudged_lines(seed: int) -> LineScene:
    """:func:`crafted_lines` and a :func:`lattice_lines` scene with three coordinates in
    four moved by +-2**-k px, k from 2 to 20, and a ladder of the same moves at each kind
    of boundary (:func:`_ladder`): a snap to 2**-b px undoes a move of k > b + 1 (rounding
    to nearest) and so puts the end point back on the decision boundary it sits next to;
    k = b + 1 is a half step of that grid."""
    rng = np.random.default_rng(seed + 67)
    crafted, lattice = crafted_lines(), lattice_lines(seed + 1)
    vertices = np.concatenate([crafted.vertices, lattice.vertices])
    moved = rng.random(vertices.shape) < 0.75
    nudge = rng.choice([-1.0, 1.0], size=vertices.shape) * 2.0 ** -rng.integers(2, 21, size=vertices.shape).astype(np.float64)
    a, b = _ladder()
    ladder = np.stack([a, b], axis=1).reshape(-1, 2)
    return LineScene(PROBE_SIZE, PROBE_SIZE, np.concatenate([vertices + np.where(moved, nudge, 0.0), ladder]),
                     np.concatenate([crafted.strip_sizes, lattice.strip_sizes, np.full(a.shape[0], 2, dtype=np.int64)]))


def float_lines(seed: int, count: int = 120) -> LineScene:
    """``count`` segments of unconstrained floats, up to 20 px long, in and around the
    probe square."""
    rng = np.random.default_rng(seed + 71)
    a = rng.uniform(-2.0, PROBE_SIZE + 2.0, size=(count, 2))
    b = np.clip(a + rng.uniform(-20.0, 20.0, size=(count, 2)) * rng.random((count, 1)), -2.0, PROBE_SIZE + 2.0)
    return LineScene.from_segments(PROBE_SIZE, PROBE_SIZE, a, b)


def rectangle_tie_lines(sample: tuple[float, float]) -> LineScene:
    """Width-1 axis-aligned segments whose sides and caps run exactly through sample points
    at ``sample`` (for rectangles at a sample point off the lattice, which no other probe
    scene meets exactly): at 25 sample points, a horizontal segment with its top side
    through the sample row and one with its bottom side through it, a vertical one with
    its left side and one with its right side through the sample column, each starting
    with its cap through the sample (a corner on it), 4 px long, and four diagonal ones
    whose starting cap (a diagonal edge) runs through the sample, each way round: the
    tie rules part there (the y-first ones on the diagonal caps, as on piglit's
    pinwheels).

    >>> len(rectangle_tie_lines((0.25, 0.75)))
    400
    """
    sx, sy = sample
    a: list[tuple[float, float]] = []
    b: list[tuple[float, float]] = []
    for i in range(2, 33, 7):
        for j in range(2, 33, 7):
            x, y = i + sx, j + sy
            for p, q in (((x, y + 0.5), (x + 4.0, y + 0.5)), ((x, y - 0.5), (x + 4.0, y - 0.5)),
                         ((x + 0.5, y), (x + 0.5, y + 4.0)), ((x - 0.5, y), (x - 0.5, y + 4.0))):
                a.append(p)
                b.append(q)
            # diagonal ones whose starting cap, a diagonal edge, runs through the sample
            for dx, dy in ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)):
                p = (x + 0.25 * dy, y - 0.25 * dx)
                a.append(p)
                b.append((p[0] + 3.0 * dx, p[1] + 3.0 * dy))
    start, end = np.array(a), np.array(b)
    return LineScene.from_segments(PROBE_SIZE, PROBE_SIZE, np.concatenate([start, end]), np.concatenate([end, start]))


def half_step_lines(seed: int, bits: int) -> LineScene:
    """:func:`crafted_lines` and a :func:`lattice_lines` scene with every coordinate moved
    by +-2**-(bits + 1): a half step of the 2**-bits grid next to a decision boundary,
    where nearest-even, half-away and floor snapping part."""
    rng = np.random.default_rng(seed + 73)
    crafted, lattice = crafted_lines(), lattice_lines(seed + 2)
    vertices = np.concatenate([crafted.vertices, lattice.vertices])
    half = rng.choice([-1.0, 1.0], size=vertices.shape) * 2.0 ** -(bits + 1)
    return LineScene(PROBE_SIZE, PROBE_SIZE, vertices + half, np.concatenate([crafted.strip_sizes, lattice.strip_sizes]))
