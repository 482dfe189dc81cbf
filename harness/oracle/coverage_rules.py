"""The coverage rules' exact oracles: area threshold and conservative rasterization.

Each decides a (triangle, pixel) on the pixel's closed square S = [i, i+1] x [j, j+1]
(screen space as in :mod:`harness.contract.conventions`), after the convention's snapping and
culling; a triangle of exactly zero snapped area, or with a non-finite coordinate, covers
nothing. The tie rule and the sample point mean nothing here.

``area-threshold`` (:func:`threshold_coverage`)
    Covered iff ``area(T ∩ S) >= t``. The areas come from the compiled float oracle
    :func:`harness.oracle.area.pixel_areas`, within its proven bound b
    (:func:`harness.oracle.area.area_error_bound`, below 2**-24 for every viewport) of the
    exact area; a pixel whose float area lies within ``2 b + 2**-50`` of t is decided by
    :func:`harness.oracle.area.exact_area` in rational arithmetic. A pixel the float oracle
    leaves out has an exact area at most b < 2**-24 < 2**-20 <= t: not covered. So every decision is
    the exact one; a pixel covered exactly t is drawn.

``conservative-over`` (:func:`conservative_over`)
    Covered iff S ∩ T is not empty (closed sets: touching counts). Two compact convex
    polygons are disjoint iff a line parallel to an edge of one of them separates them
    strictly, so S meets T iff their x and y extents overlap (closed intervals, exact float
    comparisons with integers) and, for each edge of T, not all four corners of S lie
    strictly outside it (exact orientation signs: :func:`harness.geometry.exact.orient2d_sign`,
    rational beyond its safe range).

``conservative-under`` (:func:`conservative_under`)
    Covered iff S ⊆ T: every corner of S on the inner side of every edge of T or on it
    (T is convex). Exact likewise. (The same pixels as ``area-threshold`` with t = 1: a
    closed triangle covers the whole square iff it contains it; the two oracles' agreement
    is tested. ``conservative-over`` is not t -> 0, though: a square the triangle only
    touches has area 0 and is drawn.)

The per-pixel work is compiled (numba, cached); triangles with coordinates outside the
expansions' safe range take the same steps in rational arithmetic. :func:`rules_reference`
is the slow, obviously correct reference in :class:`fractions.Fraction` for tests.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import CONSERVATIVE_OVER
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orient2d_fraction, orient2d_sign, orientation
from harness.oracle.area import area_error_bound, exact_area, pixel_areas

__all__ = ["threshold_coverage", "conservative_over", "conservative_under", "rules_reference", "prepared_positions",
           "on_rule_boundary", "uncertainty_bounds"]

# decided by the float areas when farther than this (plus twice the oracle's bound) from t
_FLOAT_SLACK = 2.0**-50


def prepared_positions(scene: Scene, convention: Convention) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """The triangles as the convention sees them (snapped) and their exact orientation
    sign, 0 for those that cover nothing (non-finite, zero area, culled)."""
    positions = np.ascontiguousarray(convention.snap(scene.positions))
    sign = orientation(positions).copy()
    if convention.cull != "none":
        sign[sign == (1 if convention.cull == "cw" else -1)] = 0
    return positions, sign


def _runs(triangle: NDArray[np.int64], x: NDArray[np.int64], y: NDArray[np.int64]) -> Coverage:
    """Pixels sorted by triangle, row and column as spans (consecutive columns joined)."""
    if not triangle.size:
        return Coverage.empty()
    new = np.ones(triangle.size, dtype=bool)
    new[1:] = (triangle[1:] != triangle[:-1]) | (y[1:] != y[:-1]) | (x[1:] != x[:-1] + 1)
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], triangle.size)
    return Coverage(triangle[starts], y[starts], x[starts], x[ends - 1] + 1)


def threshold_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="area-threshold"``: the
    pixels each triangle covers at least ``convention.threshold`` of (module docstring).

    >>> scene = Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]])
    >>> threshold_coverage(scene, Convention(coverage="area-threshold")).counts(2, 2).tolist()  # halves draw
    [[1, 1], [1, 0]]
    >>> threshold_coverage(scene, Convention(coverage="area-threshold", threshold=0.75)).counts(2, 2).tolist()
    [[1, 0], [0, 0]]
    """
    positions, sign = prepared_positions(scene, convention)
    positions = np.where((sign != 0)[:, None, None], positions, np.nan)  # non-finite: covers nothing
    t = convention.threshold
    triangle, x, y, area = pixel_areas(positions, scene.width, scene.height)
    margin = 2.0 * area_error_bound(positions, scene.width, scene.height)[triangle] + _FLOAT_SLACK
    covered = area - margin >= t
    unsure = np.flatnonzero(~covered & (area + margin >= t))
    exact_t = Fraction(t)
    for k in unsure:
        covered[k] = exact_area(positions[triangle[k]], int(x[k]), int(y[k])) >= exact_t
    return _runs(triangle[covered], x[covered], y[covered])


@numba.njit(cache=True)
def _outside_all(ax, ay, bx, by, s, i, j, grow):  # type: ignore[no-untyped-def]
    """Whether all four corners of pixel (i, j)'s square, grown by ``grow`` on every side,
    lie strictly outside edge a -> b of a triangle of orientation ``s``."""
    for dx in range(2):
        for dy in range(2):
            cx = float(i + dx) + (grow if dx else -grow)  # exact: grow is a multiple of 2**-16, |i| < 2**21
            cy = float(j + dy) + (grow if dy else -grow)
            if orient2d_sign(ax, ay, bx, by, cx, cy) * s >= 0:
                return False
    return True


@numba.njit(cache=True)
def _inside_all(ax, ay, bx, by, s, i, j, grow):  # type: ignore[no-untyped-def]
    """Whether all four corners of pixel (i, j)'s square, grown by ``grow``, lie inside
    edge a -> b or on it."""
    for dx in range(2):
        for dy in range(2):
            cx = float(i + dx) + (grow if dx else -grow)
            cy = float(j + dy) + (grow if dy else -grow)
            if orient2d_sign(ax, ay, bx, by, cx, cy) * s < 0:
                return False
    return True


@numba.njit(cache=True)
def _pixel_range(lo, hi, size):  # type: ignore[no-untyped-def]
    """The pixels k in 0 .. size - 1 whose closed interval [k, k+1] meets [lo, hi]:
    ceil(lo) - 1 .. floor(hi), clipped (the bounds clamped first: no integer overflow)."""
    first = int(math.ceil(max(lo, -2.0))) - 1
    last = int(math.floor(min(hi, size + 2.0)))
    return max(first, 0), min(last, size - 1)


@numba.njit(cache=True)
def _conservative_kernel(positions, sign, use, over, grow, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    """Spans of every triangle marked ``use`` (orientation ``sign``), over: squares (grown
    by ``grow``) that meet it, else squares (grown by ``grow``) inside it; one span per row
    (both sets are convex in a row)."""
    n = 0
    for t in range(positions.shape[0]):
        if not use[t]:
            continue
        p = positions[t]
        s = sign[t]
        xmin, xmax = min(p[0, 0], p[1, 0], p[2, 0]), max(p[0, 0], p[1, 0], p[2, 0])
        ymin, ymax = min(p[0, 1], p[1, 1], p[2, 1]), max(p[0, 1], p[1, 1], p[2, 1])
        i0, i1 = _pixel_range(xmin, xmax, width)
        j0, j1 = _pixel_range(ymin, ymax, height)
        if grow > 0.0:  # a grown square reaches one more pixel each way; the exact tests below decide
            i0, i1, j0, j1 = max(i0 - 1, 0), min(i1 + 1, width - 1), max(j0 - 1, 0), min(j1 + 1, height - 1)
        for j in range(j0, j1 + 1):
            first = -1
            last = -1
            for i in range(i0, i1 + 1):
                hit = True
                if over and (float(i) - grow > xmax or float(i + 1) + grow < xmin
                             or float(j) - grow > ymax or float(j + 1) + grow < ymin):
                    hit = False
                for k in range(3):
                    if not hit:
                        break
                    ax, ay = p[k, 0], p[k, 1]
                    bx, by = p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
                    if over:
                        if _outside_all(ax, ay, bx, by, s, i, j, grow):
                            hit = False
                    elif not _inside_all(ax, ay, bx, by, s, i, j, grow):
                        hit = False
                if hit:
                    if first < 0:
                        first = i
                    last = i
            if first >= 0:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = first
                out_x1[n] = last + 1
                n += 1
    return n


def _square_decision(p: list[tuple[Fraction, Fraction]], s: int, i: int, j: int, over: bool,
                     grow: Fraction = Fraction(0)) -> bool:
    """One pixel's decision in exact rational arithmetic (the reference, and triangles
    beyond the compiled kernel's safe range), its square grown by ``grow``."""
    corners = [(i + dx + (grow if dx else -grow), j + dy + (grow if dy else -grow)) for dx in (0, 1) for dy in (0, 1)]
    if over:
        xs, ys = [v[0] for v in p], [v[1] for v in p]
        if max(xs) < i - grow or min(xs) > i + 1 + grow or max(ys) < j - grow or min(ys) > j + 1 + grow:
            return False
    for k in range(3):
        (ax, ay), (bx, by) = p[k], p[(k + 1) % 3]
        sides = [s * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) for cx, cy in corners]
        if over and all(e < 0 for e in sides):
            return False
        if not over and any(e < 0 for e in sides):
            return False
    return True


def _conservative(scene: Scene, convention: Convention, over: bool, grow: float = 0.0) -> Coverage:
    positions, sign = prepared_positions(scene, convention)
    safe = np.empty(positions.shape[0], dtype=np.bool_)
    orientation(positions, safe)
    use = (sign != 0) & safe
    rows = np.zeros(positions.shape[0], dtype=np.int64)
    ys = positions[:, :, 1]
    with np.errstate(invalid="ignore"):
        lo = np.clip(np.floor(np.where(use, ys.min(axis=1), 0.0)) - 1, 0, scene.height)
        hi = np.clip(np.ceil(np.where(use, ys.max(axis=1), 0.0)) + 1, 0, scene.height)
    rows[use] = (hi - lo)[use].astype(np.int64)
    if grow > 0.0:
        rows[use] += 2
    capacity = int(rows.sum())
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    n = int(_conservative_kernel(frozen(positions), frozen(sign.astype(np.int64), np.int64), frozen(use, np.bool_), over,
                                 float(grow), scene.width, scene.height, *out))
    spans = [a[:n] for a in out]
    slow = np.flatnonzero((sign != 0) & ~safe)
    if slow.size:
        extra = [(int(t), j, i) for t in slow for j, i in _rational_pixels(positions[t], int(sign[t]), scene, over, grow)]
        if extra:
            e = np.array(extra, dtype=np.int64)
            more = _runs(e[:, 0], e[:, 2], e[:, 1])
            spans = [np.concatenate([a, getattr(more, f)]) for a, f in zip(spans, ("triangle", "y", "x0", "x1"))]
            order = np.argsort(spans[0], kind="stable")
            spans = [a[order] for a in spans]
    return Coverage(*spans)


def _rational_pixels(triangle: NDArray[np.float64], s: int, scene: Scene, over: bool,
                     grow: float = 0.0) -> list[tuple[int, int]]:
    """(row, column) of the pixels one triangle covers, sorted, decided in rationals."""
    p = [(Fraction(float(x)), Fraction(float(y))) for x, y in triangle]
    xs, ys = [v[0] for v in p], [v[1] for v in p]
    i0, i1 = max(math.ceil(min(xs)) - 2, 0), min(math.floor(max(xs)) + 1, scene.width - 1)
    j0, j1 = max(math.ceil(min(ys)) - 2, 0), min(math.floor(max(ys)) + 1, scene.height - 1)
    g = Fraction(grow)
    return [(j, i) for j in range(j0, j1 + 1) for i in range(i0, i1 + 1) if _square_decision(p, s, i, j, over, g)]


def conservative_over(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="conservative-over"``: every
    pixel whose closed square meets the closed (snapped) triangle.

    >>> conservative_over(Scene(4, 3, [[[0.5, 0.5], [2.5, 0.5], [0.5, 1.5]]]), Convention(coverage="conservative-over")
    ...                   ).counts(4, 3).tolist()
    [[1, 1, 1, 0], [1, 1, 0, 0], [0, 0, 0, 0]]
    """
    return _conservative(scene, convention, True)


def conservative_under(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="conservative-under"``: every
    pixel whose closed square lies in the closed (snapped) triangle.

    >>> conservative_under(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]), Convention(coverage="conservative-under")
    ...                    ).counts(4, 4).tolist()
    [[1, 1, 1, 0], [1, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0]]
    """
    return _conservative(scene, convention, False)


def uncertainty_bounds(scene: Scene, convention: Convention) -> tuple[Coverage, Coverage]:
    """(must, may): what a rasterizer of a conservative rule with an ``uncertainty`` region
    u must draw and may draw (D3D12's and Vulkan's uncertainty region, in pixels).
    Overestimate: it must draw every square that meets the triangle (the exact answer) and
    may draw every square that, grown by u on every side, meets it. Underestimate: it must
    draw every square that, grown by u, lies in the triangle, and may draw the exact
    answer. Both exact (u is a multiple of 2**-16: the grown corners are floats).

    A vertex 1/512 px left of pixel 2's side: pixel (2, 0) may be drawn, not must.

    >>> scene = Scene(4, 3, [[[0.5, 0.5], [2 - 2**-9, 0.5], [0.5, 1.5]]])
    >>> must, may = uncertainty_bounds(scene, Convention(coverage="conservative-over", uncertainty=2.0**-8))
    >>> must.counts(4, 3).tolist(), may.counts(4, 3).tolist()
    ([[1, 1, 0, 0], [1, 1, 0, 0], [0, 0, 0, 0]], [[1, 1, 1, 0], [1, 1, 0, 0], [0, 0, 0, 0]])
    """
    exact = convention.model.exact_triangles(scene, convention)
    grow = float(convention.uncertainty)
    if grow == 0.0:
        return exact, exact
    if convention.model is CONSERVATIVE_OVER:
        return exact, _conservative(scene, convention, True, grow)
    return _conservative(scene, convention, False, grow), exact


def rules_reference(scene: Scene, convention: Convention, grown: float = 0.0) -> Coverage:
    """The coverage rules' reference: every pixel of the viewport and every triangle decided
    in :class:`fractions.Fraction` from the definitions alone (the area by clipping the
    triangle to the square, the square tests by the corners' signs and the extents), the
    squares of the conservative rules grown by ``grown``; the rules read from libraries'
    sources by their own references (:mod:`harness.oracle.library_rules`). Slow; for tests."""
    if convention.model.input_bits is not None:
        from harness.oracle import library_rules

        reference = library_rules.agg_cover_reference if convention.model.thresholded else \
            library_rules.inclusive_scanline_reference
        return reference(scene, convention)
    positions = convention.snap(scene.positions)
    pixels: list[tuple[int, int, int]] = []
    grow = Fraction(grown)
    for t, triangle in enumerate(positions):
        if not np.all(np.isfinite(triangle)):
            continue
        s = orient2d_fraction(*(float(v) for v in triangle.ravel()))
        if s == 0 or (convention.cull == "cw" and s > 0) or (convention.cull == "ccw" and s < 0):
            continue
        p = [(Fraction(float(x)), Fraction(float(y))) for x, y in triangle]
        for j in range(scene.height):
            for i in range(scene.width):
                if convention.coverage_uses_threshold:
                    hit = exact_area(triangle, i, j) >= Fraction(convention.threshold)
                else:
                    hit = _square_decision(p, s, i, j, convention.model is CONSERVATIVE_OVER, grow)
                if hit:
                    pixels.append((t, j, i))
    if not pixels:
        return Coverage.empty()
    e = np.array(pixels, dtype=np.int64)
    return _runs(e[:, 0], e[:, 2], e[:, 1])



def on_rule_boundary(triangle: NDArray[np.float64], i: int, j: int, convention: Convention) -> bool:
    """Whether pixel (i, j) lies exactly on the boundary of the rule's decision for the
    (snapped) ``triangle``, in rationals: covered exactly ``threshold`` (area-threshold), met
    by the triangle only on its boundary (overestimate: no area, yet touching), or inside
    it with a corner on an edge (underestimate). The rule's ties: where a rasterizer that
    reads the rule with ``>`` for ``>=``, or open sets for closed ones, goes wrong.

    >>> t = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    >>> [on_rule_boundary(t, 1, 0, Convention(coverage=c)) for c in ("area-threshold", "conservative-over")]
    [True, False]
    >>> on_rule_boundary(t, 1, 1, Convention(coverage="conservative-over"))  # touched at its corner (1, 1)
    True
    """
    if convention.model.input_bits is not None:  # a rule read from a library's source: its own boundary
        from harness.oracle.library_rules import on_library_boundary

        return on_library_boundary(triangle, i, j, convention)
    snapped = convention.snap(np.asarray(triangle, dtype=np.float64).reshape(3, 2))
    if not np.all(np.isfinite(snapped)):
        return False
    s = orient2d_fraction(*(float(v) for v in snapped.ravel()))
    if s == 0:
        return False
    area = exact_area(snapped, i, j)
    if convention.coverage_uses_threshold:
        return area == Fraction(convention.threshold)
    p = [(Fraction(float(x)), Fraction(float(y))) for x, y in snapped]
    if convention.model is CONSERVATIVE_OVER:
        return area == 0 and _square_decision(p, s, i, j, True)
    corners = [(Fraction(i + dx), Fraction(j + dy)) for dx in (0, 1) for dy in (0, 1)]
    on_edge = any(s * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) == 0
                  for k, (ax, ay) in enumerate(p) for bx, by in [p[(k + 1) % 3]] for cx, cy in corners)
    return area == 1 and on_edge
