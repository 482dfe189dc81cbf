"""Per-triangle masks drawn by a library into a small image around the triangle's box."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from harness.api import Coverage, Scene

__all__ = ["LIMIT", "draw_each", "finite_within_limit"]

# Libraries keep coordinates in float32 or fixed point: beyond this they are refused with a
# ValueError naming the triangle (a guard band), never drawn wrong.
LIMIT = 2.0**20


def finite_within_limit(scene: Scene, name: str) -> NDArray[np.bool_]:
    """(N,) bool: which triangles are finite. Raises ValueError naming the first finite
    triangle with a coordinate beyond :data:`LIMIT` (refused, never drawn wrong)."""
    positions = scene.positions
    finite = np.all(np.isfinite(positions), axis=(1, 2))
    too_big = finite & np.any(np.abs(positions) > LIMIT, axis=(1, 2))
    if too_big.any():
        t = int(np.flatnonzero(too_big)[0])
        raise ValueError(f"{name}: triangle {t} has a coordinate beyond +/-{LIMIT:g} px ({positions[t].tolist()}); "
                         "the library's coordinates would lose precision or overflow")
    return finite


def draw_each(scene: Scene, name: str, draw: Callable[[NDArray[np.float64], int, int, tuple[int, int]], NDArray[np.bool_]],
              margin: int = 2) -> Coverage:
    """Call ``draw(vertices relative to the box origin, box width, box height, origin)`` for
    each triangle; it returns the box's (h, w) bool mask. Spans come back in screen
    coordinates, clipped to the viewport. A triangle with a NaN or infinite coordinate is
    handed to the library unchanged, with the whole screen as its box, so that what the
    library does with it (draws nothing, raises, or draws garbage) is what the checks see."""
    positions = scene.positions
    finite = finite_within_limit(scene, name)
    parts = []
    for t in range(len(scene)):
        p = positions[t]
        if not finite[t]:
            x0, y0, x1, y1 = 0, 0, scene.width, scene.height
        else:
            x0 = int(np.clip(np.floor(p[:, 0].min()) - margin, 0, scene.width))
            y0 = int(np.clip(np.floor(p[:, 1].min()) - margin, 0, scene.height))
            x1 = int(np.clip(np.ceil(p[:, 0].max()) + margin, 0, scene.width))
            y1 = int(np.clip(np.ceil(p[:, 1].max()) + margin, 0, scene.height))
        if x0 >= x1 or y0 >= y1:
            continue
        try:
            mask = draw(p - np.array([x0, y0], dtype=np.float64), x1 - x0, y1 - y0, (x0, y0))
        except Exception as exc:  # name the triangle the library failed on
            raise RuntimeError(f"{name}: the library failed on triangle {int(t)} {p.tolist()}: "
                               f"{type(exc).__name__}: {exc}") from exc
        if mask.any():
            cov = Coverage.from_mask(int(t), mask)
            parts.append((cov.triangle, cov.y + y0, cov.x0 + x0, cov.x1 + x0))
    if not parts:
        return Coverage.empty()
    return Coverage(*(np.concatenate([part[i] for part in parts]) for i in range(4)))
