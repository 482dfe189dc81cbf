"""The exact oracle for points (:mod:`harness.kinds.points`): the samples inside each
point's square, under the convention's sample point, tie rule and snapping.

A point's square covers sample ``c`` on an axis when ``p - s/2 <= c <= p + s/2`` with the
boundary decided by the tie rule (the module docstring of :mod:`harness.kinds.points`).
Both comparisons are the sign of ``2c - 2p +/- s``, a sum of three floats (``2c`` and
``2p`` are exact: the points beyond a 2-pixel margin of the viewport are dropped first, so
no doubling overflows), taken exactly by :func:`_sum3_sign`. Per point and axis the covered
samples are a range of pixel indices, found from a float estimate corrected by the exact
test; each covered row is then one span. Exact for every finite float64 input.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.geometry.exact import _two_sum
from harness.kinds.points import PointScene

__all__ = ["point_coverage", "point_coverage_rational"]


@numba.njit(cache=True, inline="always")
def _sum3_sign(a, b, c):  # type: ignore[no-untyped-def]
    """The exact sign of ``a + b + c`` (floats whose sums do not overflow).

    ``a + b = hi + lo`` exactly (two-sum), a nonoverlapping expansion; growing it by ``c``
    (Shewchuk's grow_expansion) gives the nonoverlapping ``e0 + e1 + q`` of increasing
    magnitude, whose sign is that of its largest nonzero component.
    """
    hi, lo = _two_sum(a, b)
    q, e0 = _two_sum(c, lo)
    q, e1 = _two_sum(q, hi)
    for part in (q, e1, e0):
        if part > 0.0:
            return 1
        if part < 0.0:
            return -1
    return 0


@numba.njit(cache=True, inline="always")
def _past_low_side(c, p, s, tie):  # type: ignore[no-untyped-def]
    """Whether sample coordinate c is inside the low side ``p - s/2``: ``2c - 2p + s > 0``,
    or ``= 0`` and the tie perturbation moves it inwards (``tie > 0``)."""
    sign = _sum3_sign(2.0 * c, -2.0 * p, s)
    return sign > 0 or (sign == 0 and tie > 0)


@numba.njit(cache=True, inline="always")
def _before_high_side(c, p, s, tie):  # type: ignore[no-untyped-def]
    """Whether sample coordinate c is inside the high side ``p + s/2``: ``2c - 2p - s < 0``,
    or ``= 0`` and the tie perturbation moves it inwards (``tie < 0``)."""
    sign = _sum3_sign(2.0 * c, -2.0 * p, -s)
    return sign < 0 or (sign == 0 and tie < 0)


@numba.njit(cache=True)
def _axis_range(p, s, offset, tie, n):  # type: ignore[no-untyped-def]
    """The pixel indices ``first <= i < stop`` (within 0..n) whose sample ``i + offset``
    lies in the side ``[p - s/2, p + s/2]`` under the tie rule: float estimates, each
    corrected by the exact tests (both are monotone in i)."""
    first = min(max(math.ceil(p - 0.5 * s - offset), -1), n + 1)
    while first > -1 and _past_low_side(first - 1 + offset, p, s, tie):
        first -= 1
    while first <= n and not _past_low_side(first + offset, p, s, tie):
        first += 1
    stop = min(max(math.ceil(p + 0.5 * s - offset), first), n + 1)
    while stop > first and not _before_high_side(stop - 1 + offset, p, s, tie):
        stop -= 1
    while stop <= n and _before_high_side(stop + offset, p, s, tie):
        stop += 1
    return max(first, 0), min(stop, n)


@numba.njit(cache=True)
def _ranges_kernel(centres, keep, s, ox, oy, tx, ty, width, height, out):  # type: ignore[no-untyped-def]
    """Per kept point its covered columns and rows: ``out[k] = x0, x1, y0, y1``."""
    for k in range(centres.shape[0]):
        if not keep[k]:
            out[k, 0] = out[k, 1] = out[k, 2] = out[k, 3] = 0
            continue
        x0, x1 = _axis_range(centres[k, 0], s, ox, tx, width)
        y0, y1 = _axis_range(centres[k, 1], s, oy, ty, height)
        out[k, 0] = x0
        out[k, 1] = x1
        out[k, 2] = y0
        out[k, 3] = y1


def _kept(centres: NDArray[np.float64], size: float, width: int, height: int) -> NDArray[np.bool_]:
    """The points worth deciding: finite, and their square within 2 px of the viewport
    (a float test with that margin misses no covering point and keeps every coordinate
    small enough that the exact tests' doublings cannot overflow)."""
    with np.errstate(invalid="ignore", over="ignore"):
        half = 0.5 * size
        finite = np.isfinite(centres).all(axis=1)
        near = ((centres[:, 0] + half > -2.0) & (centres[:, 0] - half < width + 2.0)
                & (centres[:, 1] + half > -2.0) & (centres[:, 1] - half < height + 2.0))
    return np.asarray(finite & near, dtype=np.bool_)


def _single(scene: PointScene, convention: Convention) -> Coverage:
    # input precision, then snapping: Convention.snap applies both, first, exactly
    centres = np.ascontiguousarray(convention.snap(scene.vertices), dtype=np.float64).reshape(-1, 2)
    keep = _kept(centres, scene.point_size, scene.width, scene.height)
    tx, ty, _ = convention.tie_perturbation
    ox, oy = (float(v) for v in convention.sample)
    ranges = np.zeros((centres.shape[0], 4), dtype=np.int64)
    _ranges_kernel(centres, keep, float(scene.point_size), ox, oy, tx, ty, scene.width, scene.height, ranges)
    # each covered row of point k is one span
    return Coverage.from_boxes(*ranges.T)


def point_coverage(scene: PointScene, convention: Convention) -> Coverage:
    """The exact coverage of a point scene.

    Parameters
    ----------
    scene : harness.kinds.points.PointScene
    convention : harness.contract.conventions.Convention
        Single-sample, or multisample (each sample of the pattern decided at its own
        offset, :meth:`Convention.at_sample`: GL's multisample point rasterization); area
        coverage: ValueError.

    Returns
    -------
    harness.contract.coverage.Coverage
        Spans of point (``primitive``), row, x0, x1 sorted by point and row (and by sample
        first under a multisample convention, which sets ``sample``); no attributes. Points
        with a NaN or infinite coordinate cover nothing.

    Examples
    --------
    A size-2 point at a pixel corner covers the four pixels around it (the second, at the
    viewport's left side, two); a size-1 point whose
    square's sides pass through pixel centres owns its left and top sides (top-left).

    >>> scene = PointScene(4, 3, [[2.0, 1.0], [0.0, 2.0]], point_size=2.0)
    >>> point_coverage(scene, Convention()).counts(4, 3)
    array([[0, 1, 1, 0],
           [1, 1, 1, 0],
           [1, 0, 0, 0]], dtype=int32)
    >>> point_coverage(PointScene(3, 3, [[1.0, 1.0]]), Convention()).counts(3, 3)
    array([[1, 0, 0],
           [0, 0, 0],
           [0, 0, 0]], dtype=int32)
    """
    if (not convention.model.single_sample and not convention.model.layered) or convention.model.rule:
        declared = convention.model.declared_as(convention) if convention.model.rule else f"{convention.coverage_kind} coverage"
        raise ValueError(f"points are defined for single-sample and multisample conventions, not {declared}")
    if not convention.model.layered:
        return _single(scene, convention)
    return Coverage.from_layers([_single(scene, convention.at_sample(k)) for k in range(convention.n_samples)])


def _inside_rational(c: Fraction, p: Fraction, half: Fraction, tie: int) -> bool:
    low, high = p - half, p + half
    return (low < c or (c == low and tie > 0)) and (c < high or (c == high and tie < 0))


def point_coverage_rational(scene: PointScene, convention: Convention) -> Coverage:
    """The same answer as :func:`point_coverage`, by brute force in rational arithmetic:
    every pixel of each point's clipped bounding box, every sample of the convention
    (slow; the tests' twin of the fast oracle)."""
    if convention.model.layered:
        samples = range(convention.n_samples)
        return Coverage.from_layers([point_coverage_rational(scene, convention.at_sample(k)) for k in samples])
    # input precision, then snapping: Convention.snap applies both, first, exactly
    centres = convention.snap(scene.vertices)
    tx, ty, _ = convention.tie_perturbation
    ox, oy = (Fraction(v) for v in convention.sample)
    half = Fraction(scene.point_size) / 2
    spans: list[tuple[int, int, int, int]] = []
    for k, (px, py) in enumerate(centres.tolist()):
        if not (math.isfinite(px) and math.isfinite(py)):
            continue
        p, q = Fraction(px), Fraction(py)
        columns = range(max(0, math.floor(p - half) - 1), min(scene.width, math.ceil(p + half) + 1))
        for j in range(max(0, math.floor(q - half) - 1), min(scene.height, math.ceil(q + half) + 1)):
            if not _inside_rational(j + oy, q, half, ty):
                continue
            covered = [i for i in columns if _inside_rational(i + ox, p, half, tx)]
            if covered:
                spans.append((k, j, covered[0], covered[-1] + 1))
    if not spans:
        return Coverage.empty()
    point, y, x0, x1 = (np.array(column, dtype=np.int64) for column in zip(*spans))
    return Coverage(point, y, x0, x1)
