"""Deliberately broken rasterizers: each check must fail on at least one of them."""

from __future__ import annotations

import numpy as np

from harness.api import Coverage


def coverage_from_parts(tris: list, xs: list, ys: list) -> Coverage:  # type: ignore[type-arg]
    """One Coverage from per-triangle lists of fragment arrays (empty when there are none)."""
    if not tris:
        return Coverage.empty()
    return Coverage.from_pixels(np.concatenate(tris), np.concatenate(xs), np.concatenate(ys))
