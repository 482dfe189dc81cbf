"""identify's probes for line-taking rasterizers: which line rule it draws, and how.

A rasterizer that lists ``"lines"`` in its ``scene_kinds`` (:func:`harness.contract.protocol.scene_kinds_of`)
draws the segments of a :class:`~harness.contract.scenes.LineScene`. :func:`fit_lines` asks it, from
outside, the questions whose answers make up a :class:`~harness.contract.conventions.LineRule` and
the snapping in front of it, each by the exact oracle of every candidate convention
(:func:`harness.oracle.coverage.exact_coverage`) scored against what it drew -- missing plus extra
pixels, as for triangles -- the best explaining it, "identified" only when its residual is
zero and no other candidate's is:

1. *The rule* (D3D's or GL's diamond-exit, Bresenham or rectangle), with diamond-exit's and
   Bresenham's last-pixel rule, Bresenham's end point rounding (nearest-even, half-away,
   floor, toward-zero), tie direction (step, stay) and direction of travel (as given, or
   from the end point with smaller x or smaller major coordinate, as textbooks'
   ``plotLine``), and the rectangle's sample point and tie rule (the 9 usual sample points,
   and the one measured by sweeping a segment's end across a pixel,
   :func:`line_sample_sweep`, at a few dyadic precisions, as for triangles, x the 8 tie
   rules): :data:`LINE_RULES_TRIED` x those, scored
   on scenes whose end points are multiples of 1/4 px (no candidate snapping of 2 bits or
   more moves them) -- :func:`crafted_lines`, where the candidates part on purpose, and
   random lattice segments and polylines (:func:`lattice_lines`):

   * end points at pixel centres (x.5), corners (integers), diamond corners and diamond
     edges (x.25), the 20 directions of slopes 0, 1/5, 1/2, 1, 2 and infinite from each:
     Bresenham's tie (the ideal line halfway between two pixel centres) comes at every
     other step of slope 1/2, diamond-exit's corner rules on lines through diamond
     corners (a horizontal line on y = j runs through every bottom corner);
   * every segment both ways round: a drawer that walks as given breaks a tie towards the
     end it walks to and omits that end's pixel, so its two drawings differ, and a drawer
     that normalises the direction draws both alike; slope -2 segments (y-major, the
     smaller x at the larger y) part walking from the smaller x from walking from the
     smaller y;
   * segments entirely inside one pixel: in its corner (no diamond met, so diamond-exit
     draws nothing where Bresenham draws the pixel), across its diamond, inside it; and
     zero-length ones (the last-pixel rules part there);
   * end points on x = 0 or y = 0 and at negative integers: Bresenham's ``half-away``
     puts an integer coordinate p <= 0 in pixel p - 1 where ``floor`` keeps p (for p >= 1
     they agree, and ``nearest-even`` differs from both at every odd p).

2. *Snapping*: with that rule, the sub-pixel bits (none, or 2 to 16) and snap rounding
   that best explain :func:`nudged_lines` -- the same kind of end points, each coordinate
   moved by +-2**-k (k = 2 .. 20), so that a snap to 2**-b px pulls it back onto the
   decision boundary it sits next to exactly when k > b + 1 (k = b + 1 is a half step,
   where the roundings part) -- and one scene of unconstrained floats; then, with every
   coordinate a half step of the fitted grid off the lattice (:func:`half_step_lines`),
   the rounding again. Ties go to the triangles' snapping, then to none. A snapping that
   changes no pixel of any input (floor snapping in front of Bresenham's floor rounding)
   is not seen, and need not be: the two conventions draw alike.

   For rectangles, the measured sample point was swept with a snapped end, so it lies up to
   a grid step off: the grid points either side of it, on the grid found and its
   neighbours (:func:`harness.identify.triangle_probes.grid_sides`), join the candidates, and the snapping is
   fitted again with each of them.

3. The rule is then ranked again with the fitted snapping on every scene drawn (and, for
   rectangles at a sample point off the 9 usual ones, on :func:`rectangle_tie_lines`,
   whose sides and caps run through samples there, as for triangles' tie scenes): the
   runner-up (the best candidate differing in rule, last pixel, rounding, ties, direction, or for
   rectangles sample point or tie rule) and each rule's best score on the lattice scenes
   are the evidence.

4. *Wide lines* (:func:`wide_lines`): lattice segments of width 3, against the fitted
   rectangular lines (for a width-1 rule, the best rectangle of step 1, and the rule
   itself at width 1: a drawer that ignores the width; for a diamond rule, the rule
   replicated along the minor axis as GL's wide lines: a drawer doing that exactly is
   identified with ``LineRule(wide="replicate")``). Otherwise the width-1 rules have no
   other width: refusing is right for them.

Only segments as the oracle defines them are judged: a rasterizer whose answers carry
alphas or sample indices is not fitted (the line rules are aliased, single-sample).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks import FragmentCounter
from harness.contract.conventions import (
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    DIAMOND_RULES,
    LINE_DIRECTIONS,
    LINE_RULES,
    MAX_SUBPIXEL_BITS,
    SNAP_ROUNDINGS,
    TIE_RULES,
    Convention,
    LineRule,
    SnapRounding,
)
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.engine.isolation import Call, Outcome, describe
from harness.identify.triangle_probes import SAMPLES, SNAP_BITS, _fraction_bits, _sample_candidates, grid_sides
from harness.oracle.coverage import exact_coverage

__all__ = ["LINE_RULES_TRIED", "PROBE_SIZE", "WIDE", "LineDrawn", "LineRounding", "WideLines", "LineFit", "LineSampleSweep",
           "line_sample_sweep", "rectangle_tie_lines",
           "line_rules_tried", "line_candidates", "crafted_lines", "lattice_lines", "nudged_lines", "float_lines",
           "half_step_lines", "wide_lines", "fit_lines"]

# The probe viewport: every probe segment lies within 2 px of it.
PROBE_SIZE = 40
# The width of the wide-line probe.
WIDE = 3.0


def line_rules_tried() -> tuple[LineRule, ...]:
    """The line rules :func:`fit_lines` tries, rectangles aside: diamond-exit (D3D's test
    areas and GL's perturbed end points) with the last pixel omitted or drawn, and Bresenham with each rounding, tie direction, last-pixel
    rule and direction of travel (as given, or normalised as textbook plotLine does: from
    the smaller x, from the smaller major coordinate), the rule's own setting first.

    >>> len(line_rules_tried()), line_rules_tried()[0].describe()
    (52, 'diamond-exit lines, last pixel omitted')
    """
    rules = [LineRule(rule, last_pixel=last) for rule in DIAMOND_RULES for last in (False, True)]
    rules += [LineRule("bresenham", last_pixel=last, rounding=rounding, ties=ties, direction=direction)
              for direction in LINE_DIRECTIONS for rounding in BRESENHAM_ROUNDINGS for ties in BRESENHAM_TIES
              for last in (True, False)]
    return tuple(rules)


LINE_RULES_TRIED = line_rules_tried()


def line_candidates(base: Convention | None = None, measured: tuple[float, float] | None = None) -> list[Convention]:
    """Every candidate line convention, unsnapped: ``base`` (the triangle convention when
    there is one and it is single-sample; else the default) with each of
    :data:`LINE_RULES_TRIED`, then with rectangles at the 9 usual sample points, and the
    ``measured`` one (:func:`line_sample_sweep`) at a few dyadic precisions
    (:func:`harness.identify.triangle_probes._sample_candidates`, as for triangles), x the 8 tie
    rules, ``base``'s own first (a tie in the score goes to the earlier candidate). The
    rest of ``base`` (culling) plays no part in lines; keeping it makes a line convention
    that agrees with the triangles equal to the triangle convention with its line rule.

    >>> candidates = line_candidates()
    >>> len(candidates), candidates[0].line.rule, candidates[52].line.rule, candidates[52].sample
    (124, 'diamond-exit', 'rectangle', (0.5, 0.5))
    >>> len(line_candidates(measured=(0.25, 0.75))), line_candidates(measured=(0.25, 0.75))[-1].sample
    (132, (0.25, 0.75))
    """
    single = base if base is not None and base.model.single_sample else Convention()
    unsnapped = replace(single, subpixel_bits=None, snap_rounding="nearest-even")
    out = [replace(unsnapped, line=rule) for rule in LINE_RULES_TRIED]
    first = (single.sample, single.tie)
    pairs = [first] + [(s, t) for s in _sample_candidates(measured) for t in TIE_RULES if (s, t) != first]
    return out + [replace(unsnapped, sample=s, tie=t, line=LineRule("rectangle")) for s, t in pairs]


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


# --- calling a rasterizer with lines, and scoring its answers -------------------------------------


def _send(call: Call, scene: LineScene) -> Outcome:
    """``call`` on a line scene (:data:`harness.engine.isolation.Call` names triangle scenes only;
    a worker and an in-process call send whatever they are given)."""
    return call(scene)  # type: ignore[arg-type]


@dataclass(frozen=True)
class LineDrawn:
    """A line scene and the rasterizer's answer to it, scored against candidate
    conventions (missing plus extra pixels, with multiplicity; an unanswered scene says
    nothing: no pixels, no mismatches, left out of every fit and residual). The answer is seen tidied (:meth:`harness.contract.coverage.Coverage.tidy`),
    the pixels the tidying dropped counted as extra (``dropped``)."""

    scene: LineScene
    outcome: Outcome
    # the scene as the library received it (say, its coordinates rounded to float32 at the
    # GL API: the rasterizer's ``received``), which the candidates are judged on
    judged: LineScene | None = None

    @property
    def coverage(self) -> Coverage | None:
        return self.outcome.coverage

    @property
    def error(self) -> BaseException | None:
        return self.outcome.error if self.outcome.coverage is None else None

    @cached_property
    def dropped(self) -> int:
        raw, kept = self.outcome.received, self.outcome.coverage
        if raw is None or kept is None:
            return 0
        claimed = float(np.maximum(raw.x1.astype(np.float64) - raw.x0.astype(np.float64), 0.0).sum())
        return max(0, int(claimed) - kept.n_pixels)

    @property
    def pixels(self) -> int:
        return 0 if self.coverage is None else self.coverage.n_pixels + self.dropped

    @cached_property
    def _counter(self) -> FragmentCounter:
        return FragmentCounter(self.coverage or Coverage.empty(), self.scene.width, self.scene.height)

    @cached_property
    def _scores(self) -> dict[Convention, int]:
        return {}

    @cached_property
    def _still(self) -> dict[tuple[int, str], bool]:
        return {}

    def _seen_as(self, convention: Convention) -> Convention:
        """``convention`` without its snapping when that moves no end point of the scene
        (the oracle is then the same: candidates differing only there share one)."""
        bits, rounding = convention.subpixel_bits, convention.snap_rounding
        if bits is None:
            return convention
        if (bits, rounding) not in self._still:
            v = self.scene.vertices
            self._still[bits, rounding] = bool(np.array_equal(convention.snap(v), v, equal_nan=True))
        return replace(convention, subpixel_bits=None, snap_rounding="nearest-even") if self._still[bits, rounding] else convention

    def mismatches(self, convention: Convention) -> int:
        """Missing plus extra pixels against the exact oracle of ``convention`` (0 when
        unanswered: no answer is not an answer of nothing)."""
        if self.coverage is None:
            return 0
        seen = self._seen_as(convention)
        if seen not in self._scores:
            judged = self.scene if self.judged is None else self.judged
            self._scores[seen] = self._counter.mismatches(exact_coverage(judged, seen)) + self.dropped
        return self._scores[seen]


def _draw(call: Call, scene: LineScene, received: Callable[[Any], Any] | None = None) -> LineDrawn:
    judged = None
    if received is not None:
        try:
            got = received(scene)
        except Exception:  # a received() that fails judges nothing: the scene as sent
            got = None
        # isinstance: what a plugin's received() answered is checked for its class, not dispatched on
        judged = got if isinstance(got, LineScene) and got.strip_sizes.tolist() == scene.strip_sizes.tolist() else None
    return LineDrawn(scene, _send(call, scene), judged)


def _fit_score(drawn: list[LineDrawn], convention: Convention) -> int:
    """Mismatches on the answered scenes (an unanswered one never steers a fit)."""
    return sum(d.mismatches(convention) for d in drawn if d.coverage is not None)


def _snapped(convention: Convention, bits: int | None, rounding: SnapRounding) -> Convention:
    return replace(convention, subpixel_bits=bits, snap_rounding=rounding if bits is not None else "nearest-even")


# --- the records --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class LineRounding:
    """Mismatches of each snap rounding with every end point a half step of the 2**-bits
    grid off the lattice, best first; ``tied``, those as good as the best."""

    bits: int
    scores: tuple[tuple[SnapRounding, int], ...]
    tied: tuple[SnapRounding, ...]

    @property
    def text(self) -> str:
        return ("; ".join(f"{r}: {score} mismatches" for r, score in self.scores)
                + f" (every end point a half step of the 2^-{self.bits} grid)")


@dataclass(frozen=True, slots=True)
class WideLines:
    """Segments of width :data:`WIDE`: refused (``error``), or drawn (``pixels``) and
    compared with the best rectangular-line convention (``rectangle``, ``mismatches``);
    for a width-1 rule, also with that rule at width 1 (``thin``: a rasterizer that ignores
    the width)."""

    width: float
    error: str = ""
    pixels: int = 0
    rectangle: Convention | None = None
    mismatches: int = 0
    thin: int | None = None
    replicated: int | None = None

    @property
    def text(self) -> str:
        if self.error:
            return f"width {self.width:g}: refused ({self.error})"[:200]
        said = f"width {self.width:g}: {self.mismatches:,} mismatches of {self.pixels:,} pixels against "
        said += "rectangular lines" if self.rectangle is None else self.rectangle.describe_lines()
        if self.thin is not None:
            said += f"; {self.thin:,} against its rule at width 1" + (" (it ignores the width)" if self.thin == 0 else "")
        if self.replicated is not None:
            said += (f"; {self.replicated:,} against its rule replicated along the minor axis"
                     + (" (GL's wide lines)" if self.replicated == 0 else ""))
        return said


_PARTS = (("subpixel_bits", "snapping bits"), ("snap_rounding", "snap rounding"))


@dataclass(frozen=True)
class LineFit:
    """The convention that best explains the rasterizer's lines (its ``line`` the
    :class:`~harness.contract.conventions.LineRule`, its snapping, and for rectangles its sample
    point and tie rule), with its mismatches (``residual``) over ``pixels`` drawn on every
    probe scene; the runner-up (another rule, last pixel, rounding, ties, direction, or rectangle
    sample point or tie rule) and its mismatches; the snap roundings it could not tell
    apart (``ambiguous``); each rule's best score on the lattice scenes of step 1
    (``rule_scores``, unsnapped); the triangle
    convention compared (``triangles``; None when it takes none); the wide-line probe;
    ``skipped``, why no fit was made; ``sweep``, the sample point measured
    (:func:`line_sample_sweep`)."""

    convention: Convention | None
    residual: int = 0
    pixels: int = 0
    runner_up: tuple[str, int] | None = None
    ambiguous: tuple[str, ...] = ()
    rule_scores: tuple[tuple[str, int], ...] = ()
    rounding: LineRounding | None = None
    wide: WideLines | None = None
    triangles: Convention | None = None
    scenes: int = 0
    unanswered: tuple[str, ...] = ()
    skipped: str = ""
    sweep: LineSampleSweep | None = None
    drawn: tuple[LineDrawn, ...] = field(default=(), repr=False, compare=False)

    @property
    def rule(self) -> LineRule | None:
        return None if self.convention is None else self.convention.line

    @property
    def exact(self) -> bool:
        """No mismatch, a runner-up with some, no ambiguity, every probe scene answered."""
        return (self.convention is not None and self.residual == 0 and not (self.runner_up is not None and self.runner_up[1] == 0)
                and not self.ambiguous and not self.unanswered)

    @property
    def differences(self) -> tuple[str, ...]:
        """What differs from the triangle convention: snapping, and for rectangular lines
        the sample point and tie rule; each as ``part value (triangles: value)``."""
        if self.convention is None or self.triangles is None or not self.triangles.model.single_sample:
            return ()
        parts = _PARTS + ((("sample", "sample"), ("tie", "ties")) if self.convention.line.rule == "rectangle" else ())
        return tuple(f"{label} {getattr(self.convention, part)} (triangles: {getattr(self.triangles, part)})"
                     for part, label in parts if getattr(self.convention, part) != getattr(self.triangles, part))

    @property
    def same_as_triangles(self) -> bool | None:
        """Whether the line convention's snapping (and a rectangle's sample point and ties)
        are the triangle convention's; None when either is missing."""
        if self.convention is None or self.triangles is None or not self.triangles.model.single_sample:
            return None
        return not self.differences

    @property
    def text(self) -> str:
        if self.convention is None:
            return f"not fitted: {self.skipped}"
        quality = ("" if self.exact else
                   f" (best guess only: {len(self.unanswered)} probe scenes unanswered, left out of the fit)" if self.unanswered else
                   " (best guess only)" if self.residual else
                   f" (ambiguous between {' and '.join(self.ambiguous)})" if self.ambiguous else
                   " (ambiguous: the next best explains it as well)")
        said = f"{self.convention.describe_lines()}, {self.residual:,} mismatches of {self.pixels:,} pixels{quality}"
        if self.runner_up is not None:
            said += f"; next best {self.runner_up[0]} ({self.runner_up[1]:,})"
        same = self.same_as_triangles
        if same is False:
            said += f"; DIFFERS from triangles: {', '.join(self.differences)}"
        if self.unanswered:
            said += f"; {len(self.unanswered)} of {self.scenes} probe scenes unanswered (fit on the rest): {self.unanswered[0]}"
        return said

    @property
    def rules_text(self) -> str:
        """Each rule's best mismatches, as the card's "line rules" line says them."""
        return ", ".join(f"{rule}: {score:,}" for rule, score in self.rule_scores) + " mismatches at best on the lattice scenes"


# --- the probes ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class LineSampleSweep:
    """Where a rectangular line's end, swept across a pixel, stops covering it: the sample
    point, up to the snapping grid (x from a horizontal segment's start, y from a
    vertical one's); None when the pixel never flips (the rasterizer raised, draws
    nothing there, or draws no rectangles)."""

    offset: tuple[float, float] | None
    resolution: int = 20

    @property
    def text(self) -> str:
        if self.offset is None:
            return "no flip found under a segment's end swept across a pixel (not rectangular lines, or nothing drawn)"
        return (f"a segment's end swept across a pixel flips it at offset ({self.offset[0]:.6g}, {self.offset[1]:.6g}) "
                f"(bisected to 2^-{self.resolution} px; snapping moves it by up to one grid step)")


# The sweep's segments, as functions of the end's offset t into the probe pixel: a
# horizontal one on y = 30.25 and 30.75 (a width-1 rectangle holds the samples of row 30
# with y offsets in (-0.25, 0.75), (0.25, 1.25): one of them holds any), read at pixel
# (8, 30); a vertical one on x = 30.25 and 30.75, read at pixel (30, 8).
_SWEPT = ((0, 30.25), (0, 30.75), (1, 30.25), (1, 30.75))


def line_sample_sweep(call: Call, resolution: int = 20) -> LineSampleSweep:
    """The sample point of rectangular lines, measured directly as the triangles' sample
    sweep does (:func:`harness.identify.triangle_probes.sample_sweep`), anywhere on the dyadic grid: the
    start of a long horizontal (vertical) segment moved from half a pixel before pixel
    (8, 30) ((30, 8)) to half a pixel past it, bisected (every segment in one scene, one
    call per halving) to where the pixel stops being covered. Each offset is read as the
    end of its last interval with fewer fraction bits; the fit tries it at a few dyadic
    precisions besides the 9 usual points, which absorbs the snapping's error."""
    def covered(t: NDArray[np.float64]) -> NDArray[np.bool_] | None:
        a = np.array([[8.0 + t[k], line] if axis == 0 else [line, 8.0 + t[k]] for k, (axis, line) in enumerate(_SWEPT)])
        b = np.array([[40.0, line] if axis == 0 else [line, 40.0] for axis, line in _SWEPT])
        got = _send(call, LineScene.from_segments(48, 48, a, b)).coverage
        if got is None:
            return None
        k, x, y = got.pixels()
        want = np.array([[8, 30] if axis == 0 else [30, 8] for axis, _ in _SWEPT])
        return np.array([bool(np.any((k == i) & (x == want[i, 0]) & (y == want[i, 1]))) for i in range(len(_SWEPT))])

    lo, hi = np.full(len(_SWEPT), -0.5), np.full(len(_SWEPT), 1.5)
    at_lo, at_hi = covered(lo), covered(hi)
    if at_lo is None or at_hi is None:
        return LineSampleSweep(None, resolution)
    flips = at_lo & ~at_hi
    if not (flips[0] or flips[1]) or not (flips[2] or flips[3]):
        return LineSampleSweep(None, resolution)
    while hi[0] - lo[0] > 2.0**-resolution:
        mid = (lo + hi) / 2.0  # exact: dyadic
        at_mid = covered(mid)
        if at_mid is None:
            return LineSampleSweep(None, resolution)
        lo, hi = np.where(at_mid, mid, lo), np.where(at_mid, hi, mid)
    found = []
    for axis in (0, 1):
        k = 2 * axis if flips[2 * axis] else 2 * axis + 1
        low, high = float(lo[k]), float(hi[k])
        found.append(low if _fraction_bits(low) <= _fraction_bits(high) else high)
    return LineSampleSweep((found[0], found[1]), resolution)



def wide_lines(call: Call, seed: int, fitted: Convention, rectangle: Convention,
               received: Callable[[Any], Any] | None = None) -> WideLines:
    """Lattice segments of width :data:`WIDE` against ``rectangle`` (the best rectangular-line
    candidate of the fit), and for a width-1 rule (``fitted``) against that rule on the same
    segments at width 1; for a diamond rule, also against it replicated along the minor
    axis (GL's wide lines, ``LineRule(wide="replicate")``)."""
    scene = lattice_lines(seed + 3, 60).with_line_width(WIDE)
    drawn = _draw(call, scene, received)
    if drawn.coverage is None:
        return WideLines(WIDE, describe(drawn.error))
    thin = replicated = None
    if fitted.line.rule != "rectangle":
        thin = drawn._counter.mismatches(exact_coverage(scene.with_line_width(1.0), fitted)) + drawn.dropped
    if fitted.line.diamond:
        replicated = drawn.mismatches(replace(fitted, line=replace(fitted.line, wide="replicate")))
    return WideLines(WIDE, "", drawn.pixels, rectangle, drawn.mismatches(rectangle), thin, replicated)


def _aliased(drawn: list[LineDrawn]) -> str:
    """Why the answers cannot be judged as aliased single-sample lines ("" when they can)."""
    for d in drawn:
        if d.coverage is not None and d.coverage.alpha is not None:
            return "its lines carry alphas (anti-aliased); the line rules are aliased"
        if d.coverage is not None and d.coverage.sample is not None:
            return ("its lines carry sample indices (multisample): rectangles per sample, judged against the declared "
                    "rule, not fitted here")
    return ""


def fit_lines(call: Call, seed: int = 0, triangles: Convention | None = None,
              received: Callable[[Any], Any] | None = None) -> LineFit:
    """The line convention that best explains the rasterizer (see the module docstring).

    Parameters
    ----------
    call : Call
        The rasterizer, taking line scenes.
    seed : int
        Seeds the random probe scenes.
    triangles : Convention or None
        The convention identified for its triangles (or paths), compared with the line
        convention; None when it takes none. The width-1 candidates carry its sample point
        and tie rule, and rectangles at them are tried first.
    received : callable or None
        The rasterizer's ``received(scene)`` (:func:`harness.contract.protocol.received_of`): candidates
        are judged on the scene as the library received it (float32 coordinates at the GL
        API), as identify judges triangles.

    Returns
    -------
    LineFit
    """
    sweep = line_sample_sweep(call)
    candidates = line_candidates(triangles, sweep.offset)
    # 1. the rule, on end points no candidate snapping moves
    ruled = [_draw(call, s, received) for s in (crafted_lines(), lattice_lines(seed), lattice_lines(seed, 60, strips=True))]
    answered = [d for d in ruled if d.coverage is not None]
    if not answered:
        return LineFit(None, triangles=triangles, scenes=len(ruled), skipped=f"unanswered: {describe(ruled[0].error)}"[:200],
                       drawn=tuple(ruled))
    odd = _aliased(answered)
    if odd:
        return LineFit(None, triangles=triangles, scenes=len(ruled), skipped=odd, drawn=tuple(ruled))
    lattice = [_fit_score(ruled, c) for c in candidates]
    order = sorted(range(len(candidates)), key=lambda i: (lattice[i], i))
    best = candidates[order[0]]
    # 2. snapping, on end points next to decision boundaries and on floats
    floats = [_draw(call, nudged_lines(seed), received), _draw(call, float_lines(seed), received)]
    snaps: list[tuple[int | None, SnapRounding]] = [(None, "nearest-even")]
    snaps += [(b, r) for b in SNAP_BITS if b is not None for r in SNAP_ROUNDINGS]
    own = (None, "nearest-even") if triangles is None or triangles.subpixel_bits is None else (
        triangles.subpixel_bits, triangles.snap_rounding)

    def preference(bits: int | None, rounding: SnapRounding) -> int:
        # ties prefer the triangles' snapping (a snapping no line shows is theirs), then
        # none, then rounding to nearest even
        return 0 if (bits, rounding) == own else 1 if bits is None else 2 + SNAP_ROUNDINGS.index(rounding)

    scored = sorted((_fit_score(floats, _snapped(best, b, r)), preference(b, r), k) for k, (b, r) in enumerate(snaps))
    bits, rounding = snaps[scored[0][2]]
    if sweep.offset is not None and best.line.rule == "rectangle" and bits is not None:
        # a rectangle's flip, swept with a snapped end, lies up to a grid step off its
        # sample: the grid points either side of it near the grid found join the
        # candidates, and the snapping is fitted again with each of them (the lattice
        # scenes cannot tell them apart: their end points are never moved)
        near = [b for b in (bits - 1, bits, bits + 1) if 0 <= b <= MAX_SUBPIXEL_BITS]
        known = {(c.sample, c.tie) for c in candidates if c.line.rule == "rectangle"}
        extra = [replace(candidates[order[0]], sample=s, tie=t) for s in grid_sides(sweep.offset, near)
                 for t in TIE_RULES if (s, t) not in known]
        candidates += extra
        lattice += [_fit_score(ruled, c) for c in extra]
        order = sorted(range(len(candidates)), key=lambda i: (lattice[i], i))
        trials = [(best, *snaps[scored[0][2]])] + [(c, b, r) for c in extra if c.tie == best.tie
                                                   for b in near for r in SNAP_ROUNDINGS]
        _, _, _, best, bits, rounding = min(((_fit_score(floats, _snapped(c, b, r)), preference(b, r), k, c, b, r)
                                            for k, (c, b, r) in enumerate(trials)), key=lambda t: t[:3])
    rounding_fit = None
    if bits is not None:
        floats.append(_draw(call, half_step_lines(seed, bits), received))
        ranked = sorted((_fit_score(floats, _snapped(best, bits, r)), preference(bits, r), r) for r in SNAP_ROUNDINGS)
        rounding = ranked[0][2]
        rounding_fit = LineRounding(bits, tuple((r, sum(d.mismatches(_snapped(best, bits, r)) for d in floats))
                                                for _, _, r in ranked),
                                    tuple(r for score, _, r in ranked if score == ranked[0][0]))
    per_rule = {rule: min((lattice[i] for i, c in enumerate(candidates) if c.line.rule == rule), default=0) for rule in LINE_RULES}
    # 3. the rule again, with that snapping, on every scene; a candidate's score on the
    # lattice scenes bounds its total from below (no snapping of 2 bits or more moves a
    # multiple of 1/4), so one that cannot beat the runner-up so far is passed over
    drawn = ruled + floats
    if best.line.rule == "rectangle" and best.sample not in SAMPLES:
        # ties at its sample point, which the lattice scenes do not meet (as identify does for triangles)
        drawn.append(_draw(call, rectangle_tie_lines(best.sample), received))
    totals: list[tuple[int, int]] = []
    for rank, i in enumerate(order):
        candidate = _snapped(candidates[i], bits, rounding)
        if len(totals) >= 2 and lattice[i] >= totals[1][0]:
            break  # in lattice order: every later candidate's bound is as large
        totals = sorted([*totals, (_fit_score(drawn, candidate), rank)])[:2]
    best = _snapped(candidates[order[totals[0][1]]], bits, rounding)
    rectangle = best if best.line.rule == "rectangle" else _snapped(
        next(candidates[i] for i in order if candidates[i].line.rule == "rectangle"), bits, rounding)
    runner = _snapped(candidates[order[totals[1][1]]], bits, rounding)
    ambiguous = (tuple(f"{bits} bits {r}" for r in rounding_fit.tied)
                 if rounding_fit is not None and len(rounding_fit.tied) > 1 else ())
    wide = wide_lines(call, seed, best, rectangle, received)
    if wide.replicated == 0 and wide.pixels:  # it draws wide lines as GL does: part of its rule
        best = replace(best, line=replace(best.line, wide="replicate"))
    return LineFit(best, sum(d.mismatches(best) for d in drawn), sum(d.pixels for d in drawn),
                   (runner.describe_lines(), sum(d.mismatches(runner) for d in drawn)), ambiguous,
                   tuple(per_rule.items()), rounding_fit, wide, triangles, len(drawn),
                   tuple(describe(d.error) for d in drawn if d.coverage is None), sweep=sweep, drawn=tuple(drawn))
