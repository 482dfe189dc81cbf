"""Pictures of point scenes: each point's square outlined over the pixel grid, its centre
marked (the points' ``vectors`` hook, :mod:`harness.kinds.points`); the rest of a point
failure's pictures -- heat map, oracle diff, crop, repro -- are the fills' own."""

from __future__ import annotations

import numpy as np

from harness.report.picture_kit import CROP_LEGEND, _hex
from harness.report.picture_svg import Vectors

__all__ = ["point_vectors"]


def point_vectors(v: Vectors) -> list[str]:
    """The squares of the points near the window (up to 200), outlined, and their centres."""
    x0, y0, x1, y1 = v.window
    scene = v.positions
    centres = scene.vertices
    half = 0.5 * scene.point_size
    with np.errstate(invalid="ignore"):
        near = (np.isfinite(centres).all(axis=1) & (centres[:, 0] + half > x0 - 1) & (centres[:, 0] - half < x1 + 1)
                & (centres[:, 1] + half > y0 - 1) & (centres[:, 1] - half < y1 + 1))
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    thin = 'vector-effect="non-scaling-stroke"'
    parts = []
    for cx, cy in np.clip(centres[near][:200], -1e6, 1e6):
        parts.append(f'<rect x="{cx - half:.6g}" y="{cy - half:.6g}" width="{2 * half:.6g}" height="{2 * half:.6g}" '
                     f'fill="none" stroke="{blue}" stroke-width="1" {thin}/>')
        parts.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{0.06:.6g}" fill="{blue}"/>')
    return parts
