"""Near ties: how far a fragment's decision is from flipping, per scene kind.

A near tie is a fragment whose decision a tiny move of the geometry could flip; how far it
is from flipping is measured per scene kind (each kind's ``near_ties`` hook,
:mod:`harness.kinds`): for triangles (:func:`triangle_near_ties`) and paths
(:func:`path_near_ties`) the sample's distance to the nearest deciding edge line; for lines
(:func:`line_near_ties`, :func:`line_edge_distance`) the distance of the declared line
rule's decision from its boundary. Every distance is a rigorous upper bound (never an
underestimate), relative to the primitive's coordinates, and exactly 0 only where the
exact predicate sits on the boundary.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.checks.records import Tolerance
from harness.contract.conventions import FIXED_POINT_LINE_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.geometry.exact import orientation
from harness.kinds import kind_of

__all__ = ["edge_distance", "path_edge_distance", "line_edge_distance", "near_ties", "near_ties_of",
           "triangle_near_ties", "path_near_ties", "line_near_ties"]

# Shewchuk's bound on the float orient2d's error, differences included; the added
# absolute term covers underflow of the products (harmless at any pixel scale).
_ORIENT_ERROR = (3.0 + 16.0 * 2.0**-53) * 2.0**-53
_UNDERFLOW = 2.0**-1000


def edge_distance(positions: NDArray, fragments: NDArray, sample: tuple[float, float]) -> NDArray:
    """How far each fragment's sample point is from having its inside/outside decision
    flipped by rounding an edge function of its triangle, relative to max(1, largest
    |coordinate|) of that triangle: for a sample outside the triangle, the farthest of the
    edge lines it lies strictly outside of (every one must round the other way to take it
    in: a sample on an edge's extension past a vertex lies clearly outside another edge,
    unless the triangle is a sliver within rounding of it); for a sample inside, or on the
    boundary, or of a zero-area triangle, the nearest edge line.

    Never an underestimate: each edge function is evaluated in float with Shewchuk's
    rigorous error bound added, and divided by a lower bound on the edge's length; which
    edges a sample lies outside of is decided exactly. It is exactly 0 only when the exact
    predicates put the sample on the triangle's boundary (or on a zero-area triangle's
    line), and inf for a triangle with a non-finite coordinate (or an overflowing one): a
    float that cancels to zero never passes for a tie.

    Parameters
    ----------
    positions : (N, 3, 2) float64, as the convention sees them (snapped)
    fragments : (3, M) int64 rows triangle, x, y

    Returns
    -------
    (M,) float64
    """
    out = np.full(fragments.shape[1], np.inf)
    if fragments.shape[1] == 0:
        return out
    tri = fragments[0]
    ok = (tri >= 0) & (tri < positions.shape[0])
    p = positions[tri[ok]]
    px = fragments[1, ok] + sample[0]
    py = fragments[2, ok] + sample[1]
    finite = np.all(np.isfinite(p), axis=(1, 2))
    samples = np.stack([px, py], axis=-1)
    winding = np.where(finite, orientation(np.where(finite[:, None, None], p, 0.0)), 0)
    nearest = np.full(p.shape[0], np.inf)
    farthest_violated = np.full(p.shape[0], -np.inf)
    on_line = np.zeros((3, p.shape[0]), dtype=bool)
    with np.errstate(all="ignore"):
        for k in range(3):
            a, b = p[:, k], p[:, (k + 1) % 3]
            left = (a[:, 0] - px) * (b[:, 1] - py)
            right = (a[:, 1] - py) * (b[:, 0] - px)
            bound = np.abs(left - right) + _ORIENT_ERROR * (np.abs(left) + np.abs(right)) + _UNDERFLOW
            length = np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]) * (1.0 - 2.0**-50)
            distance = np.where(np.isfinite(bound) & (length > 0), bound / length, np.inf)
            side = orientation(np.stack([np.where(finite[:, None], a, 0.0), np.where(finite[:, None], b, 0.0), samples], axis=1))
            on_line[k] = side == 0
            nearest = np.minimum(nearest, distance)
            violated = (winding != 0) & (side == -winding)  # strictly outside this edge
            farthest_violated = np.where(violated, np.maximum(farthest_violated, distance), farthest_violated)
        best = np.where(farthest_violated > -np.inf, farthest_violated, nearest)
        relative = best / np.maximum(1.0, np.abs(p).max(axis=(1, 2)))
    relative[~finite] = np.inf
    # on the boundary (on an edge's line, outside none) or on a zero-area triangle's line: a tie
    relative[on_line.any(axis=0) & (farthest_violated == -np.inf) & finite] = 0.0
    out[ok] = np.where(np.isnan(relative), np.inf, relative)
    return out


@numba.njit(cache=True)
def _path_distance_kernel(ax, ay, bx, by, first, last, magnitude, fragment_path, px, py, out, pairs):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """Per fragment, the least bound / length over its path's edges whose y-range holds
    the sample (the edges that decide the sample's row), relative to the path's largest
    |coordinate|; pairs (fragment, edge) whose float edge function cannot be told from 0
    are written to ``pairs`` for the exact test. Returns the number of pairs."""
    n = 0
    for f in range(fragment_path.size):
        p = fragment_path[f]
        best = np.inf
        for e in range(first[p], last[p]):
            if py[f] < min(ay[e], by[e]) or py[f] > max(ay[e], by[e]):
                continue
            if ay[e] == by[e]:  # horizontal, on the sample's row: how far along it (exact 0 on it)
                gap = max(min(ax[e], bx[e]) - px[f], px[f] - max(ax[e], bx[e]), 0.0)
                best = min(best, gap * (1.0 + 2.0**-50))
                continue
            left = (ax[e] - px[f]) * (by[e] - py[f])
            right = (ay[e] - py[f]) * (bx[e] - px[f])
            value = abs(left - right)
            error = _ORIENT_ERROR * (abs(left) + abs(right)) + _UNDERFLOW
            bound = value + error
            length = np.hypot(bx[e] - ax[e], by[e] - ay[e]) * (1.0 - 2.0**-50)
            if np.isfinite(bound) and length > 0:
                best = min(best, bound / length)
            if value <= error and n < pairs.shape[0]:
                pairs[n, 0] = f
                pairs[n, 1] = e
                n += 1
        out[f] = best / magnitude[p]
    return n


def path_edge_distance(scene: PathScene, convention: Convention, fragments: NDArray) -> NDArray:
    """:func:`edge_distance` for a path scene: from each fragment's sample point to the
    nearest edge of its path among those whose y-range holds the sample (the edges that
    decide it; a horizontal one on the sample's row, along it: on its line past its ends is
    no tie), relative to max(1, largest |coordinate|) of the path; never an
    underestimate, exactly 0 only when the exact predicate puts the sample on such an edge,
    inf for a path with a non-finite coordinate.

    Parameters
    ----------
    fragments : (3, M) int64 rows path, x, y
    """
    out = np.full(fragments.shape[1], np.inf)
    if fragments.shape[1] == 0:
        return out
    start, end, owner = scene.edges()
    start, end = convention.snap(start), convention.snap(end)
    order = np.argsort(owner, kind="stable")
    start, end, owner = start[order], end[order], owner[order]
    n = len(scene)
    first = np.searchsorted(owner, np.arange(n)).astype(np.int64)
    last = np.searchsorted(owner, np.arange(n), side="right").astype(np.int64)
    lo, hi, finite = scene.primitive_boxes()
    magnitude = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, initial=0.0)) if n else np.ones(0)
    path = fragments[0]
    ok = (path >= 0) & (path < n)
    ok[ok] &= finite[path[ok]]
    px = (fragments[1, ok] + convention.sample[0]).astype(np.float64)
    py = (fragments[2, ok] + convention.sample[1]).astype(np.float64)
    got = np.empty(px.size)
    pairs = np.empty((max(16, 8 * px.size), 2), dtype=np.int64)
    with np.errstate(all="ignore"):
        ax, ay, bx, by = (np.ascontiguousarray(c) for c in (start[:, 0], start[:, 1], end[:, 0], end[:, 1]))
        m = _path_distance_kernel(ax, ay, bx, by, first, last, magnitude, np.ascontiguousarray(path[ok]), px, py, got, pairs)
    if m:
        f, e = pairs[:m, 0], pairs[:m, 1]
        on_edge = orientation(np.stack([start[e], end[e], np.stack([px[f], py[f]], axis=-1)], axis=1)) == 0
        got[f[on_edge]] = 0.0
    out[ok] = np.where(np.isnan(got), np.inf, got)
    return out


# -- lines ----------------------------------------------------------------------------------

# Running error bounds: an operation on floats known to within e each adds at most
# 2**-53 |result| (round to nearest); 2**-52 leaves room for the bounds' own roundings.
_ROUND = 2.0**-52
# a hypot of rounded differences is within a few ulps of the exact length
_LOW, _HIGH = 1.0 - 2.0**-50, 1.0 + 2.0**-50
_SQRT2_LOW = 1.4142135623730951 * _LOW
_SQRT2_HIGH = 1.4142135623730951 * _HIGH
_DIAGONALS = ((1, 1), (1, -1), (-1, 1), (-1, -1))


def _minus(x: NDArray, y: NDArray) -> tuple[NDArray, NDArray]:
    """x - y of exact floats, and a bound on its error."""
    z = x - y
    return z, _ROUND * np.abs(z)


def _plus(x: NDArray, ex: NDArray, y: NDArray, ey: NDArray) -> tuple[NDArray, NDArray]:
    """x + y of floats known to within ex, ey, and a bound on its error."""
    z = x + y
    return z, ex + ey + _ROUND * np.abs(z)


def _times(x: NDArray, ex: NDArray, y: NDArray, ey: NDArray) -> tuple[NDArray, NDArray]:
    """x * y of floats known to within ex, ey, and a bound on its error (underflow included)."""
    z = x * y
    return z, np.abs(x) * ey + np.abs(y) * ex + ex * ey + _ROUND * np.abs(z) + _UNDERFLOW


def _orient(ax: NDArray, ay: NDArray, bx: NDArray, by: NDArray, px: NDArray, py: NDArray) -> tuple[NDArray, NDArray]:
    """orient2d(a, b, p) = cross(b - a, p - a) in float, and Shewchuk's bound on its error."""
    left = (ax - px) * (by - py)
    right = (ay - py) * (bx - px)
    return left - right, _ORIENT_ERROR * (np.abs(left) + np.abs(right)) + _UNDERFLOW


def _q(value: float) -> Fraction:
    return Fraction(float(value))


def _diamond_touches_exactly(a: NDArray, b: NDArray, centre: tuple[float, float]) -> bool:
    """Whether the segment a-b touches the closed diamond |x - xc| + |y - yc| <= 1/2 without
    entering it: the least of its separating functions (:func:`_diamond_margins`) is 0."""
    ax, ay, bx, by = (_q(v) for v in (*a, *b))
    cx, cy = _q(centre[0]), _q(centre[1])
    half = Fraction(1, 2)
    values = [half - min(sx * (ax - cx) + sy * (ay - cy), sx * (bx - cx) + sy * (by - cy)) for sx, sy in _DIAGONALS]
    dx, dy = bx - ax, by - ay
    if dx or dy:
        values.append(max(abs(dx), abs(dy)) / 2 - abs((ax - cx) * (by - cy) - (ay - cy) * (bx - cx)))
    return min(values) == 0


def _diamond_margins(a: NDArray, b: NDArray, px: NDArray, py: NDArray, last_pixel: bool) -> NDArray:
    """How far each diamond-exit decision is from flipping, in pixels (an upper bound).

    The pixel with centre (px, py) is drawn when the segment meets its diamond D and the
    end point b is not in D (:mod:`harness.oracle.lines`). By the separating axis theorem the
    segment meets the closed diamond exactly when ``h(u) = h_D(u) + h_S(-u) >= 0`` for the
    normals u of the diamond (the four diagonals: ``1/2 - min(u.A, u.B)`` with A, B the end
    points relative to the centre) and of the segment (``max(|dx|, |dy|)/2 - |cross(d, A)|``).
    When it meets, the least h(u)/|u| is how far the segment must move to stop meeting
    (its penetration depth); when it does not, the distance between them, at most sqrt(2)
    times the largest violation (the polygon D - S has no angle below 90 degrees). The end
    point's own margin is |(|Bx| + |By|) - 1/2|, an upper bound on its distance to D's
    boundary. Every term is evaluated in float with a running error bound; the result is
    the least margin, exactly 0 where the segment touches D without entering it, or b lies
    on its boundary (decided in rational arithmetic where the float cannot tell).

    Parameters
    ----------
    a, b : (M, 2) float64
        Each fragment's segment (snapped).
    px, py : (M,) float64
        Each fragment's pixel centre.

    Returns
    -------
    (M,) float64
    """
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    big_ax, e_ax = _minus(ax, px)
    big_ay, e_ay = _minus(ay, py)
    big_bx, e_bx = _minus(bx, px)
    big_by, e_by = _minus(by, py)
    values, errors, lengths = [], [], []
    for sx, sy in _DIAGONALS:
        g_a, e_a = _plus(sx * big_ax, e_ax, sy * big_ay, e_ay)
        g_b, e_b = _plus(sx * big_bx, e_bx, sy * big_by, e_by)
        h = 0.5 - np.minimum(g_a, g_b)
        values.append(h)
        errors.append(np.maximum(e_a, e_b) + _ROUND * np.abs(h))
        lengths.append(np.full(h.shape, _SQRT2_LOW))
    dx, e_dx = _minus(bx, ax)
    dy, e_dy = _minus(by, ay)
    det, e_det = _orient(ax, ay, bx, by, px, py)
    h = 0.5 * np.maximum(np.abs(dx), np.abs(dy)) - np.abs(det)
    values.append(h)
    errors.append(0.5 * np.maximum(e_dx, e_dy) + e_det + _ROUND * np.abs(h))
    lengths.append(np.hypot(dx, dy) * _LOW)  # 0 for a zero-length segment (b - a is 0 only when b == a)
    value, error, length = np.stack(values), np.stack(errors), np.stack(lengths)
    used = length > 0
    sure_inside = np.all((value - error > 0) | ~used, axis=0)
    depth = np.min(np.where(used, (value + error) / np.where(used, length, 1.0), np.inf), axis=0) * _HIGH
    doubtful = used & (value - error <= 0)
    apart = _SQRT2_HIGH * np.max(np.where(doubtful, (np.abs(value) + error) / np.where(used, length, 1.0), 0.0), axis=0) * _HIGH
    margin: NDArray = np.where(sure_inside, depth, apart)
    unsure = ~sure_inside & np.all((value + error >= 0) | ~used, axis=0) & np.isfinite(margin)
    for k in np.flatnonzero(unsure):
        if _diamond_touches_exactly(a[k], b[k], (px[k], py[k])):
            margin[k] = 0.0
    if not last_pixel:
        s, e_s = _plus(np.abs(big_bx), e_bx, np.abs(big_by), e_by)
        excess = s - 0.5
        e_excess = e_s + _ROUND * np.abs(excess)
        end = (np.abs(excess) + e_excess) * _HIGH
        for k in np.flatnonzero((np.abs(excess) <= e_excess) & np.isfinite(end)):
            if abs(_q(bx[k]) - _q(px[k])) + abs(_q(by[k]) - _q(py[k])) == Fraction(1, 2):
                end[k] = 0.0
        margin = np.minimum(margin, end)
    return margin


def _rectangle_margins(a: NDArray, b: NDArray, px: NDArray, py: NDArray, line_width: float) -> NDArray:
    """How far each sample p is from the boundary lines of its segment's rectangle (the two
    caps through a and b, the two sides at half the width), in pixels: an upper bound,
    exactly 0 when the exact predicate puts p on a cap line or a side line; inf for a
    zero-length segment (it covers nothing).

    Parameters
    ----------
    a, b : (M, 2) float64
        Each fragment's segment (snapped).
    px, py : (M,) float64
        Each fragment's sample point.
    """
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    dx, e_dx = _minus(bx, ax)
    dy, e_dy = _minus(by, ay)
    length = np.hypot(dx, dy)
    low, high = length * _LOW, length * _HIGH
    caps = []
    for ex, ey in ((ax, ay), (bx, by)):
        rx, e_rx = _minus(px, ex)
        ry, e_ry = _minus(py, ey)
        u, e_u = _times(dx, e_dx, rx, e_rx)
        v, e_v = _times(dy, e_dy, ry, e_ry)
        dot, e_dot = _plus(u, e_u, v, e_v)
        cap = (np.abs(dot) + e_dot) / low * _HIGH
        caps.append((cap, dot, e_dot))
    det, e_det = _orient(ax, ay, bx, by, px, py)
    half = 0.5 * line_width
    q_high = (np.abs(det) + e_det) / low * _HIGH
    q_low = np.maximum(np.abs(det) - e_det, 0.0) / high * _LOW
    side = np.maximum(q_high - half, half - q_low) * _HIGH + _UNDERFLOW
    margin: NDArray = np.minimum(np.minimum(caps[0][0], caps[1][0]), side)
    margin[~(length > 0)] = np.inf
    # where the float cannot tell the sample off a boundary line, ask exactly
    doubtful = (np.abs(caps[0][1]) <= caps[0][2]) | (np.abs(caps[1][1]) <= caps[1][2]) | ((q_low <= half) & (half <= q_high))
    for k in np.flatnonzero(doubtful & np.isfinite(margin)):
        qa, qb = (_q(ax[k]), _q(ay[k])), (_q(bx[k]), _q(by[k]))
        p = (_q(px[k]), _q(py[k]))
        d = (qb[0] - qa[0], qb[1] - qa[1])
        caps_exact = [d[0] * (p[0] - e[0]) + d[1] * (p[1] - e[1]) for e in (qa, qb)]
        cross = d[0] * (p[1] - qa[1]) - d[1] * (p[0] - qa[0])
        if 0 in caps_exact or 4 * cross * cross == _q(line_width) ** 2 * (d[0] ** 2 + d[1] ** 2):
            margin[k] = 0.0
    return margin


def _parallelogram_margins(a: NDArray, b: NDArray, px: NDArray, py: NDArray, line_width: float) -> NDArray:
    """How far each sample p is from the boundary lines of its segment's parallelogram
    (Vulkan's non-strict lines: the two ends through a and b parallel to the minor axis,
    the two sides half the width away along it), measured along the axes in pixels: an
    upper bound on the move of the segment that changes the sample's decision, exactly 0
    when the exact predicate puts p on an end or a side line; inf for a zero-length segment.

    Parameters
    ----------
    a, b : (M, 2) float64
        Each fragment's segment (snapped).
    px, py : (M,) float64
        Each fragment's sample point.
    """
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    dx, e_dx = _minus(bx, ax)
    dy, e_dy = _minus(by, ay)
    x_major = np.abs(dx) >= np.abs(dy)
    major = np.where(x_major, np.abs(dx), np.abs(dy))
    e_major = np.where(x_major, e_dx, e_dy)
    ends = [np.abs(np.where(x_major, px - ex, py - ey)) * _HIGH for ex, ey in ((ax, ay), (bx, by))]
    det, e_det = _orient(ax, ay, bx, by, px, py)
    half = 0.5 * line_width
    low = np.maximum(major - e_major, 0.0) * _LOW
    high = (major + e_major) * _HIGH
    with np.errstate(divide="ignore", invalid="ignore"):
        q_high = (np.abs(det) + e_det) / low * _HIGH  # |det| / |major|: the sample's distance along the minor axis
        q_low = np.maximum(np.abs(det) - e_det, 0.0) / high * _LOW
    side = np.maximum(q_high - half, half - q_low) * _HIGH + _UNDERFLOW
    margin: NDArray = np.minimum(np.minimum(ends[0], ends[1]), side)
    margin[~(major > 0)] = np.inf
    doubtful = (q_low <= half) & (half <= q_high)
    for k in np.flatnonzero(doubtful & np.isfinite(margin)):
        qa, qb, p = (_q(ax[k]), _q(ay[k])), (_q(bx[k]), _q(by[k])), (_q(px[k]), _q(py[k]))
        d = (qb[0] - qa[0], qb[1] - qa[1])
        cross = d[0] * (p[1] - qa[1]) - d[1] * (p[0] - qa[0])
        if 2 * abs(cross) == _q(line_width) * (abs(d[0]) if x_major[k] else abs(d[1])):
            margin[k] = 0.0
    return margin


def _bresenham_margins(a: NDArray, b: NDArray, x: NDArray, y: NDArray, rule: Any, width: int, height: int) -> NDArray:
    """How far each Bresenham decision is from flipping, in pixels: the rule rounds each end
    point coordinate c to a pixel, and the pixel changes where c crosses an integer m. So
    for every set of coordinates rounded to the pixel on the other side of their nearest
    integer, the line between the changed end pixels is drawn; a fragment it draws or
    leaves differently from the rule is that far from flipping: the largest |c - m| of
    the set (exact: ``c - rint(c)`` is exact in float). inf where no such set flips it.

    Parameters
    ----------
    a, b : (M, 2) float64
        Each fragment's segment (snapped, finite).
    x, y : (M,) int64
        Each fragment's pixel (inf outside the ``width`` x ``height`` viewport).
    rule : harness.contract.conventions.LineRule
    """
    from harness.oracle.lines import BRESENHAM_MAX, bresenham_spans, end_point_pixels

    out = np.full(x.size, np.inf)
    ends = np.concatenate([a, b], axis=1)
    segments, local = np.unique(ends, axis=0, return_inverse=True)  # one row per distinct segment
    local = local.reshape(-1)
    pixel = end_point_pixels(segments, rule.rounding)
    nearest = np.rint(segments)
    away = np.abs(segments - nearest)
    other = np.where(pixel == nearest, nearest - 1.0, nearest)  # the pixel across the boundary at nearest
    if rule.rounding == "toward-zero":
        # C's cast: pixel k < 0 holds (k - 1, k], pixel 0 holds (-1, 1): a boundary at n < 0
        # parts pixels n and n + 1, and there is none at 0
        other = np.where(nearest < 0, np.where(pixel == nearest, nearest + 1.0, nearest), other)
        away = np.where(nearest == 0, np.inf, away)
    usable = (np.abs(np.concatenate([pixel, other], axis=1)) <= BRESENHAM_MAX).all(axis=1)

    def drawn(ends_px: NDArray) -> NDArray:
        """Sorted keys (segment, y, x) of the pixels the rule draws between these end pixels."""
        p0, p1 = np.where(usable[:, None], ends_px[:, :2] + 0.5, np.nan), np.where(usable[:, None], ends_px[:, 2:] + 0.5, np.nan)
        spans = bresenham_spans(p0, p1, width, height, "floor", rule.ties, rule.last_pixel, rule.direction)
        seg, px, py = Coverage(*spans).pixels()
        return np.sort((seg * height + py) * width + px)

    wanted = drawn(pixel)
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
    asked = np.where(inside, (local * height + y) * width + x, -1)
    for subset in range(1, 16):
        chosen = np.array([(subset >> c) & 1 for c in range(4)], dtype=bool)
        flipped = np.where(chosen[None, :], other, pixel)
        weight = np.max(np.where(chosen[None, :], away, 0.0), axis=1)
        changed = np.setxor1d(drawn(flipped), wanted, assume_unique=True)
        hit = np.isin(asked, changed)
        out[hit] = np.minimum(out[hit], weight[local[hit]])
    return out


def _segment_magnitude(scene: LineScene, convention: Convention | None) -> NDArray:
    """(N,) float64: max(1, largest |coordinate|) of each segment as the convention sees it
    (snapped; NaN for a non-finite one)."""
    a, b = scene.segments()
    if convention is not None:
        a, b = convention.snap(a), convention.snap(b)
    with np.errstate(invalid="ignore"):
        magnitude: NDArray = np.maximum(1.0, np.maximum(np.abs(a), np.abs(b)).max(axis=1, initial=0.0))
    return magnitude


def line_edge_distance(scene: LineScene, convention: Convention | None, fragments: NDArray) -> NDArray:
    """:func:`edge_distance` for a line scene: how far the declared line rule's decision
    on each fragment is from flipping, relative to max(1, largest |coordinate|) of its
    segment (snapped). Never an underestimate; exactly 0 only where the exact predicate sits
    on its boundary; inf for a segment with a non-finite coordinate.

    * ``diamond-exit`` (D3D's and GL's: the same diamond): the least of how far the segment is from meeting the pixel's
      diamond, or from leaving it (its penetration depth), and (last pixel omitted) how far
      the end point is from the diamond's boundary (:func:`_diamond_margins`); inf for
      replicated wide lines (no bound: none excused).
    * ``bresenham``: how far the end points of the segment are from the roundings that
      would draw or leave the fragment (:func:`_bresenham_margins`).
    * ``rectangle``: the sample's distance to the nearest boundary line of the rectangle
      (a cap or a side, :func:`_rectangle_margins`).

    Parameters
    ----------
    scene : LineScene
    convention : Convention or None
        The rule, sample point and snapping; None: the least distance under the three
        rules (end points unsnapped, pixel centres).
    fragments : (3, M) int64 rows segment, x, y

    Returns
    -------
    (M,) float64

    Examples
    --------
    Segment 0 runs along the lower-left edge of pixel (1, 0)'s diamond, touching it without
    entering: a tie (the rule owns lower edges). Segment 1 runs through the pixel centres
    of row 0: it must move 0.5 px to leave pixel (1, 0)'s diamond, relative to its largest
    coordinate, 3:

    >>> from harness.contract.conventions import LineRule
    >>> scene = LineScene.from_segments(4, 4, [[1.0, 0.5], [0.0, 0.5]], [[1.5, 1.0], [3.0, 0.5]])
    >>> line_edge_distance(scene, Convention(line=LineRule("diamond-exit", last_pixel=True)), np.array([[0, 1], [1, 1], [0, 0]]))
    array([0.        , 0.16666667])
    """
    out = np.full(fragments.shape[1], np.inf)
    n = len(scene)
    segment = fragments[0]
    ok = (segment >= 0) & (segment < n)
    if not ok.any():
        return out
    if convention is None:
        nearest: NDArray = np.minimum.reduce([line_edge_distance(scene, Convention(line=rule), fragments)
                                              for rule in ("diamond-exit", "bresenham", "rectangle")])
        return nearest
    a, b = scene.segments()
    convention = convention.for_lines()
    a, b = convention.snap(a)[segment[ok]], convention.snap(b)[segment[ok]]
    x = fragments[1, ok].astype(np.float64)
    y = fragments[2, ok].astype(np.float64)
    rule = convention.line
    with np.errstate(all="ignore"):
        if rule.rule == "bresenham":
            finite = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
            absolute = np.full(a.shape[0], np.inf)
            absolute[finite] = _bresenham_margins(a[finite], b[finite], fragments[1, ok][finite], fragments[2, ok][finite], rule,
                                                  scene.width, scene.height)
        elif rule.rule == "rectangle":
            absolute = _rectangle_margins(a, b, x + convention.sample[0], y + convention.sample[1], scene.line_width)
        elif rule.rule == "parallelogram":
            absolute = _parallelogram_margins(a, b, x + convention.sample[0], y + convention.sample[1], scene.line_width)
        elif rule.rule in FIXED_POINT_LINE_RULES or rule.own_snapping:
            # skia's hairlines, Qt's cosmetic lines, llvmpipe's rectangles: the library's own
            # arithmetic (integer DDAs on 26.6 ends; float32 corners snapped by its rule) is
            # their oracle: no float margin is theirs to excuse
            absolute = np.full(a.shape[0], np.inf)
        elif scene.line_width != 1.0:
            # replicated wide lines: a pixel inside a run stays as its base moves; no bound
            # here, so no near tie is excused
            absolute = np.full(a.shape[0], np.inf)
        else:
            absolute = _diamond_margins(a, b, x + 0.5, y + 0.5, bool(rule.last_pixel))
        relative = absolute / _segment_magnitude(scene, convention)[segment[ok]]
    finite = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
    out[ok] = np.where(finite & ~np.isnan(relative), relative, np.inf)
    return out


def near_ties_of(scene: AnyScene, convention: Convention | None, fragments: NDArray,
                 tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """:func:`near_ties` for a scene of any kind (its kind's ``near_ties`` hook), as the
    convention sees it (snapped); without a convention, pixel centres and (lines) the least
    distance under any rule.

    Returns
    -------
    near : (M,) bool
    distance : (M,) float64
    """
    answer: tuple[NDArray, NDArray] = kind_of(scene).hook("near_ties")(scene, convention, fragments, tolerance)
    return answer


def line_near_ties(scene: LineScene, convention: Convention | None, fragments: NDArray,
                   tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """:func:`near_ties_of` for a line scene: :func:`line_edge_distance`, relative to each
    segment's magnitude."""
    distance = line_edge_distance(scene, convention, fragments)
    segment = fragments[0]
    ok = (segment >= 0) & (segment < len(scene))
    magnitude = np.full(distance.size, np.inf)
    magnitude[ok] = _segment_magnitude(scene, convention)[segment[ok]]
    with np.errstate(invalid="ignore"):
        near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
    return near, distance


def path_near_ties(scene: PathScene, convention: Convention | None, fragments: NDArray,
                   tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """:func:`near_ties_of` for a path scene: :func:`path_edge_distance`, relative to each
    path's magnitude (pixel centres without a convention)."""
    if convention is None:
        convention = Convention()
    distance = path_edge_distance(scene, convention, fragments)
    lo, hi, _ = scene.primitive_boxes()
    scale = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, initial=0.0)) if len(scene) else np.ones(0)
    path = fragments[0]
    ok = (path >= 0) & (path < len(scene))
    magnitude = np.full(distance.size, np.inf)
    magnitude[ok] = scale[path[ok]]
    with np.errstate(invalid="ignore"):
        near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
    return near, distance


def triangle_near_ties(scene: Scene, convention: Convention | None, fragments: NDArray,
                       tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """:func:`near_ties_of` for a triangle scene: :func:`near_ties` of its snapped
    positions (pixel centres without a convention)."""
    if convention is None:
        convention = Convention()
    if not convention.model.sample_point:  # a coverage rule decides on the square: no near tie excused
        return np.zeros(fragments.shape[1], dtype=bool), np.full(fragments.shape[1], np.inf)
    return near_ties(convention.snap(scene.positions), fragments, convention.sample, tolerance)


def near_ties(positions: NDArray, fragments: NDArray, sample: tuple[float, float],
              tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """Which fragments are near ties under ``tolerance`` (within ``near_tie`` of an edge
    relative to the coordinates and within ``near_tie_pixels`` absolutely), and their
    :func:`edge_distance`. Non-finite triangles are never near ties.

    Returns
    -------
    near : (M,) bool
    distance : (M,) float64
    """
    distance = edge_distance(positions, fragments, sample)
    tri = fragments[0]
    ok = (tri >= 0) & (tri < positions.shape[0])
    magnitude = np.full(distance.size, np.inf)
    with np.errstate(invalid="ignore"):
        magnitude[ok] = np.maximum(1.0, np.abs(positions[tri[ok]]).max(axis=(1, 2)))
        near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
    return near, distance
