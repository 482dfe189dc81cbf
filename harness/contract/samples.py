"""Multisample patterns: where inside a pixel its samples lie.

A pattern is a tuple of offsets ``(sx, sy)`` within the pixel, in pixels, y down: sample s
of pixel (i, j) -- the unit square [i, i+1) x [j, j+1) -- is the point (i + sx, j + sy).
Each offset is a dyadic float in [0, 1) x [0, 1) with at most :data:`FRACTION_BITS`
fraction bits, so that every sample point of a viewport up to
:data:`harness.contract.scenes.MAX_VIEWPORT` (2**20) is an exact float: i + sx needs at most
20 + 32 = 52 significant bits. The exact single-sample machinery then applies at each
offset unchanged.

The standard patterns (:data:`STANDARD_PATTERNS`) are D3D11's standard multisample
patterns, which Vulkan adopts as its standard sample locations. The D3D11 specification
gives them in 1/16 px from the pixel centre (x right, y down, -8 .. 7); the offset within
the pixel is ``0.5 + k / 16``. The tables below were checked against Mesa's
``src/intel/common/gen_sample_positions.c`` (``gen_sample_positions_{1,2,4,8,16}x``,
origin at the pixel's top-left corner) and a Vulkan renderer's GLSL table of the standard
locations: all five agree entry for entry, in order.
"""

from __future__ import annotations

import functools
import numbers
from collections.abc import Iterable, Sequence
from fractions import Fraction
from typing import SupportsFloat

import numpy as np

__all__ = ["FRACTION_BITS", "STANDARD_PATTERNS", "pattern", "describe_pattern", "regular_grid"]

# Offsets have at most 32 fraction bits: with i < MAX_VIEWPORT = 2**20, i + sx fits in 52 bits.
FRACTION_BITS = 32

# D3D11's standard patterns in 1/16 px from the pixel centre, x right, y down.
_SIXTEENTHS_FROM_CENTRE: dict[int, tuple[tuple[int, int], ...]] = {
    1: ((0, 0),),
    2: ((4, 4), (-4, -4)),
    4: ((-2, -6), (6, -2), (-6, 2), (2, 6)),
    8: ((1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7)),
    16: ((1, 1), (-1, -3), (-3, 2), (4, -1), (-5, -2), (2, 5), (5, 3), (3, -5),
         (-2, 6), (0, -7), (-4, -6), (-6, 4), (-8, 0), (7, -4), (6, 7), (-7, -8)),
}

# 0.5 + k/16 is exact in float64 (a multiple of 1/16 below 1).
STANDARD_PATTERNS: dict[int, tuple[tuple[float, float], ...]] = {
    count: tuple((0.5 + kx / 16, 0.5 + ky / 16) for kx, ky in table)
    for count, table in _SIXTEENTHS_FROM_CENTRE.items()
}
"""Sample count -> the D3D11 / Vulkan standard offsets within the pixel, in sample order."""


def _coordinate(value: object, offset: object) -> float:
    """One coordinate of an offset as an exact float, or ValueError naming the offset."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"sample offset {offset!r}: {value!r} is not a real number")
    try:
        exact = Fraction(value) if isinstance(value, numbers.Rational) else Fraction(float(value))
    except (ValueError, OverflowError, TypeError):
        raise ValueError(f"sample offset {offset!r}: {value!r} is not finite") from None
    if not 0 <= exact < 1:
        raise ValueError(f"sample offset {offset!r} lies outside the pixel: each coordinate must be in [0, 1)")
    denominator = exact.denominator
    # Dyadic with at most FRACTION_BITS fraction bits: the exact sample point i + s is a float.
    if denominator & (denominator - 1) or denominator > 2**FRACTION_BITS:
        raise ValueError(f"sample offset {offset!r} is not a multiple of 2**-{FRACTION_BITS}: "
                         "the sample points i + s would not be exact floats")
    return float(exact)  # exact: dyadic with few bits (and -0.0 becomes 0.0)


def pattern(spec: int | Iterable[Sequence[SupportsFloat]]) -> tuple[tuple[float, float], ...]:
    """The sample offsets of a multisample pattern, validated.

    Parameters
    ----------
    spec : int or sequence of (x, y)
        A sample count with a standard pattern (1, 2, 4, 8 or 16), or the offsets
        themselves (e.g. a (K, 2) array), each in [0, 1) x [0, 1) within the pixel, y down.

    Returns
    -------
    tuple of (float, float)
        The offsets in sample order.

    Raises
    ------
    ValueError
        For a count with no standard pattern, an empty pattern, an offset that is not a
        pair of finite reals in [0, 1), one with more than 32 fraction bits (not a
        multiple of 2**-32), or one given twice.

    Examples
    --------
    >>> pattern(4)
    ((0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875))
    >>> pattern([(0.5, 0.5), (0, 0.25)])
    ((0.5, 0.5), (0.0, 0.25))
    >>> pattern([(0.5, 0.1)])
    Traceback (most recent call last):
    ...
    ValueError: sample offset (0.5, 0.1) is not a multiple of 2**-32: the sample points i + s would not be exact floats
    >>> pattern([(0.5, 1.0)])
    Traceback (most recent call last):
    ...
    ValueError: sample offset (0.5, 1.0) lies outside the pixel: each coordinate must be in [0, 1)
    """
    if isinstance(spec, (bool, np.bool_)):
        raise ValueError(f"a sample pattern is a count or a sequence of offsets, not {spec!r}")
    if isinstance(spec, (int, np.integer)):
        count = int(spec)
        if count not in STANDARD_PATTERNS:
            raise ValueError(f"no standard pattern has {count} samples; the standard counts are "
                             f"{', '.join(map(str, STANDARD_PATTERNS))}")
        return STANDARD_PATTERNS[count]
    if isinstance(spec, tuple) and all(type(o) is tuple and len(o) == 2 and type(o[0]) is float
                                       and type(o[1]) is float for o in spec):
        return _float_pattern(spec)  # a pattern as conventions hold it: validated once
    return _validated(spec)


@functools.lru_cache(maxsize=256)
def _float_pattern(spec: tuple[tuple[float, float], ...]) -> tuple[tuple[float, float], ...]:
    return _validated(spec)


def _validated(spec: Iterable[Sequence[SupportsFloat]]) -> tuple[tuple[float, float], ...]:
    offsets: list[tuple[float, float]] = []
    first_index: dict[tuple[float, float], int] = {}
    for index, offset in enumerate(spec):
        if isinstance(offset, np.ndarray):
            items = [*offset.tolist()] if offset.ndim == 1 else [offset]
        elif isinstance(offset, (str, bytes)) or not isinstance(offset, Sequence):
            raise ValueError(f"sample offset {offset!r} is not an (x, y) pair")
        else:
            items = list(offset)
        if len(items) != 2:
            raise ValueError(f"sample offset {offset!r} is not an (x, y) pair")
        point = (_coordinate(items[0], offset), _coordinate(items[1], offset))
        if point in first_index:
            raise ValueError(f"sample offset {offset!r} (sample {index}) repeats sample {first_index[point]}")
        first_index[point] = index
        offsets.append(point)
    if not offsets:
        raise ValueError("a sample pattern needs at least one sample")
    return tuple(offsets)


def _fraction_words(value: Fraction) -> str:
    """A dyadic fraction as people write it: ``0``, ``1/8``, ``3/16``."""
    return str(value.numerator) if value.denominator == 1 else f"{value.numerator}/{value.denominator}"


def _axis_words(first: Fraction, step: Fraction, index: str) -> str:
    """``1/8 + k/4``: the first offset along an axis plus ``index`` steps."""
    steps = f"{index}/{step.denominator}" if step.numerator == 1 else f"{_fraction_words(step)} {index}"
    return steps if first == 0 else f"{_fraction_words(first)} + {steps}"


def regular_grid(offsets: Sequence[tuple[float, float]]) -> tuple[int, int, str] | None:
    """(columns, rows, where) when ``offsets`` are a regular grid listed row by row (y
    outer, x inner, as :func:`rasterizers.supersample.grid_pattern` lists them): evenly
    spaced columns and rows, every crossing a sample once; ``where`` is the offsets in
    words (``1/8 + k/4`` when both axes agree, else ``(1/32 + i/16, 1/8 + j/4)``). None
    for anything else (or a single sample).

    >>> regular_grid([(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)])
    (2, 2, '(1/4 + k/2)')
    >>> regular_grid([(0.25, 0.25), (0.25, 0.75), (0.75, 0.25), (0.75, 0.75)]) is None  # column by column
    True
    """
    grid = _grid(offsets)
    if grid is None or not grid[3]:
        return None
    return grid[:3]


def _grid(offsets: Sequence[tuple[float, float]]) -> tuple[int, int, str, bool] | None:
    """(columns, rows, where, listed row by row?) when ``offsets`` are, in some order, a
    regular grid (see :func:`regular_grid`); None otherwise."""
    if len(offsets) < 2:
        return None
    xs = sorted({Fraction(x) for x, _ in offsets})
    ys = sorted({Fraction(y) for _, y in offsets})
    if len(xs) * len(ys) != len(offsets) or len(set(offsets)) != len(offsets):
        return None
    axes = []
    for values in (xs, ys):
        steps = {b - a for a, b in zip(values, values[1:])}
        if len(steps) > 1:
            return None
        axes.append((values[0], steps.pop() if steps else None))

    def words(first: Fraction, step: Fraction | None, index: str) -> str:
        return _fraction_words(first) if step is None else _axis_words(first, step, index)  # one column (row): its offset

    if axes[0] == axes[1]:
        where = f"({words(*axes[0], 'k')})"
    else:
        where = f"({words(*axes[0], 'i')}, {words(*axes[1], 'j')})"
    row_by_row = [(Fraction(x), Fraction(y)) for x, y in offsets] == [(x, y) for y in ys for x in xs]
    return len(xs), len(ys), where, row_by_row


def describe_pattern(offsets: Sequence[tuple[float, float]]) -> str:
    """A sample pattern in a few words, never its offsets one by one: a standard pattern by
    its name, a regular grid by its size and where it lies, anything else by its count and
    where the offsets are listed (the JSON and the report keep them in full).

    >>> describe_pattern(pattern(4))
    'D3D11 4x'
    >>> describe_pattern([((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4)])
    '4x4 grid at (1/8 + k/4)'
    >>> describe_pattern([(0.25, 0.5), (0.75, 0.25), (0.5, 0.875)])
    '3 samples at irregular offsets (listed in --json and the report)'
    >>> describe_pattern([((i + 0.5) / 16, (j + 0.5) / 4) for j in range(4) for i in range(16)])
    '16x4 grid at (1/32 + i/16, 1/8 + j/4)'
    """
    offsets = tuple((float(x), float(y)) for x, y in offsets)
    if STANDARD_PATTERNS.get(len(offsets)) == offsets:
        return f"D3D11 {len(offsets)}x"
    grid = _grid(offsets)
    if grid is not None:
        columns, rows, where, row_by_row = grid
        if row_by_row:
            return f"{columns}x{rows} grid at {where}"
        # the order is the sample indices' (multisample): say that it is not row by row
        return f"{columns}x{rows} grid at {where}, samples in another order (listed in --json and the report)"
    return f"{len(offsets)} samples at irregular offsets (listed in --json and the report)"
