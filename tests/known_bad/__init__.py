"""Deliberately broken rasterizers: each check must fail on at least one of them."""

from __future__ import annotations

from collections.abc import Sequence
from typing import SupportsInt

import numpy as np

from harness.contract.coverage import Coverage


def coverage_from_parts(tris: list, xs: list, ys: list) -> Coverage:
    """One Coverage from per-triangle lists of fragment arrays (empty when there are none)."""
    if not tris:
        return Coverage.empty()
    return Coverage.from_pixels(np.concatenate(tris), np.concatenate(xs), np.concatenate(ys))


def coverage_from_spans(spans: Sequence[tuple[SupportsInt, int, int, int]]) -> Coverage:
    """One Coverage from (triangle, y, x0, x1) tuples (empty when there are none)."""
    if not spans:
        return Coverage.empty()
    t, y, x0, x1 = np.array(spans, dtype=np.int64).T
    return Coverage(t, y, x0, x1)
