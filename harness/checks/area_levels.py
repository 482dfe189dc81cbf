"""The area checks' reading of alphas: each (primitive, pixel)'s alpha keyed and aligned
with the model's, and what an alpha on a declared level stands for, exactly (shared by the
triangle and line checks of :mod:`harness.checks.area` and the path checks of
:mod:`harness.checks.area_paths`)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import QUANTISED_AREA
from harness.geometry.keys import union, unique_inverse

__all__ = ["AREA_COVERAGE_KINDS", "LEVEL_NOISE", "accuracy_message", "off_level", "level_values", "exact_alpha",
           "exact_tolerance"]

AREA_COVERAGE_KINDS: frozenset[str] = frozenset({"area"})
# An alpha meant as level k of L is k/(L-1) rounded to float64 (or computed as k * (1/(L-1)),
# a few units in the last place away): within about 2**-50 relative of the level. 1e-9
# relative is far beyond any such rounding and far below a level's spacing (at most 2**24
# levels: 1e-9 * 2**24 is under 0.02 of a level), so it tells "a float representation of
# a level" from "a value between levels" without deciding anything geometric.
LEVEL_NOISE = 1e-9


def _fragments(coverage: Coverage, width: int, height: int, n: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """(triangle, x, y, alpha) of every fragment inside the viewport with a valid triangle
    id; alpha NaN throughout when the coverage lacks one alpha per pixel."""
    t, x, y = coverage.pixels()
    alpha = coverage.alpha
    if alpha is None or alpha.size != t.size:
        alpha = np.full(t.size, np.nan)
    ok = (t >= 0) & (t < n) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    if ok.all():  # a tidied answer: nothing to drop
        return t, x, y, alpha
    return t[ok], x[ok], y[ok], alpha[ok]


def _keyed(coverage: Coverage, width: int, height: int, n: int) -> tuple[NDArray, NDArray]:
    """Sorted unique keys ``(t * H + y) * W + x`` and the summed alpha of each."""
    t, x, y, alpha = _fragments(coverage, width, height, n)
    keys, where = unique_inverse((t * height + y) * width + x)
    return keys, np.bincount(where, weights=alpha, minlength=keys.size)


def _aligned(keys_a: NDArray, a: NDArray, keys_b: NDArray, b: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Union of two sorted key sets and the values of each side on it (0 where absent)."""
    keys = union(keys_a, keys_b)
    out_a, out_b = np.zeros(keys.size), np.zeros(keys.size)
    out_a[np.searchsorted(keys, keys_a)] = a
    out_b[np.searchsorted(keys, keys_b)] = b
    return keys, out_a, out_b


def _model_words(convention: Convention) -> str:
    if convention.rows:
        return f"the row-sampled area ({convention.rows} rows)"
    if convention.model is QUANTISED_AREA:
        return f"the exact area's {convention.quantisation} level"
    return "the share of samples covered" if convention.samples is not None else "the exact area"


def off_level(alpha: NDArray, levels: int) -> NDArray:
    """Which alphas are no level of ``levels`` (a multiple of 1/(levels - 1)) up to float
    representation (:data:`LEVEL_NOISE`); NaN is off.

    >>> off_level(np.array([0.0, 1 / 255, 128 / 255, 0.5, np.nan]), 256).tolist()
    [False, False, False, True, True]
    """
    q = alpha * (levels - 1)
    with np.errstate(invalid="ignore"):
        off: NDArray[np.bool_] = ~(np.abs(q - np.rint(q)) <= LEVEL_NOISE * np.maximum(1.0, np.abs(q)))
    return off


def level_values(alpha: NDArray, levels: int) -> NDArray:
    """What each alpha stands for, in float: level k's value k/(levels - 1) (rounded once)
    for an alpha on a level (:func:`off_level`), the alpha itself otherwise. Within 2**-53
    relative of :func:`exact_alpha`.

    >>> level_values(np.array([142 * (1 / 255), 0.3]), 256).tolist() == [142 / 255, 0.3]
    True
    """
    q = alpha * (levels - 1)
    return np.where(off_level(alpha, levels), alpha, np.rint(q) / (levels - 1))


def exact_alpha(alpha: float, levels: int) -> Fraction:
    """The number an alpha stands for, exactly: k/(levels - 1) for an alpha on level k
    (a float representation of it, :func:`off_level`), its own value otherwise.

    >>> exact_alpha(143 / 255, 256), exact_alpha(0.3, 256) == Fraction(0.3)
    (Fraction(143, 255), True)
    """
    if off_level(np.array([alpha]), levels)[0]:
        return Fraction(alpha)
    return Fraction(round(alpha * (levels - 1)), levels - 1)


def exact_tolerance(convention: Convention) -> Fraction:
    """The declared tolerance as the number it stands for: exactly half a level when none
    is declared; a declared float that is a multiple of half a level up to float
    representation (as alphas are read as levels: :data:`LEVEL_NOISE`) that multiple
    exactly; any other float its own value.

    >>> [exact_tolerance(Convention(coverage="area", tolerance=t)) for t in (None, 1 / 255, 0.25)]
    [Fraction(1, 510), Fraction(1, 255), Fraction(1, 4)]
    >>> exact_tolerance(Convention(coverage="area", tolerance=0.5 / 255 + 2.0**-24)) == Fraction(0.5 / 255 + 2.0**-24)
    True
    """
    half = Fraction(1, 2 * (convention.levels - 1))
    if convention.tolerance is None:
        return half
    declared = float(convention.tolerance)
    q = declared * 2 * (convention.levels - 1)
    m = round(q)
    if m >= 1 and abs(q - m) <= LEVEL_NOISE * max(1.0, q):
        return m * half
    return Fraction(declared)


def accuracy_message(*, total: int, count: int, n_off: int, n_near: int, ties: str, bound: float, what: str,
                     worst: float, step: float, levels: int, strict: bool, where: str = "",
                     cause: str | None = None) -> str:
    """Accuracy's one line: every pixel within the tolerance (and the near ties excused, or
    not in strict mode), else how many are beyond it, off the levels, the cause named and the
    near ties; ``where`` qualifies "pixels" (" of the paths")."""
    if not count and not n_off:
        within = f"all {total}" if not n_near else f"{total - n_near} of {total}"
        message = f"within {bound:.3g} of {what} at {within} pixels{where} (largest error {worst:.3g}, {worst / step:.2f} levels)"
        if ties:
            message += f"; {ties}" + (", not allowed in strict mode" if strict else "")
        return message
    parts = []
    if count:
        parts.append(f"{count} of {total} pixels{where} beyond {bound:.3g} of {what} "
                     f"(largest error {worst:.3g}, {worst / step:.1f} levels)")
    if n_off:
        parts.append(f"{n_off} alphas on none of the {levels} declared levels")
    if cause:
        parts.append(cause)
    if ties:
        parts.append(ties)
    return "; ".join(parts)
