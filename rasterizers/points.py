"""Reference point rasterizer: D3D11/GL point sprites drawn by their bounds in closed form.

``point_sprites`` (:class:`PointSprites`)
    Each point's square ``[p - s/2, p + s/2]`` (per axis) covers the samples ``i + o`` of
    the indices ``first <= i < stop`` solved in rational arithmetic, once per point and
    axis, with the tie rule's choice of sides (:mod:`harness.kinds.points`): a side owned
    by the rule is a closed bound (``first = ceil(p - s/2 - o)``), a side it does not own an
    open one (``first = floor(p - s/2 - o) + 1``); likewise ``stop``. Each covered row is
    then one span, built by numpy: no loop per pixel, and none of the oracle's kernels
    (:mod:`harness.oracle.points` decides by exact float expansions and corrected
    estimates), so a test comparing the two compares two implementations.

Convention: the one given (default D3D11's: pixel centres, top-left ties, no snapping);
single-sample or multisample (each sample of the pattern at its own offset). A scene of
another kind raises :class:`harness.contract.scenes.Unsupported`.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Unsupported
from harness.kinds.points import PointScene

__all__ = ["PointSprites"]


def _bounds(p: Fraction, half: Fraction, offset: Fraction, tie: int) -> tuple[int, int]:
    """``first, stop``: the indices i whose sample ``i + offset`` lies in ``[p - half, p + half]``
    with the low side owned when ``tie > 0`` and the high side when ``tie < 0``."""
    low, high = p - half - offset, p + half - offset
    first = math.ceil(low) if tie > 0 else math.floor(low) + 1
    stop = math.ceil(high) if tie > 0 else math.floor(high) + 1
    return first, stop


class PointSprites:
    """Squares of ``point_size`` around each point, under ``convention``'s sample point,
    tie rule, snapping and sample pattern."""

    name = "point_sprites"
    scene_kinds: tuple[str, ...] = ("points",)
    interpolates = False

    def __init__(self, convention: Convention | None = None) -> None:
        self.convention = Convention() if convention is None else convention

    def rasterize(self, scene: PointScene) -> Coverage:
        if not isinstance(scene, PointScene):  # a reference drawer takes its one kind of scene
            raise Unsupported(f"{self.name} draws points, not {scene.kind}")
        if not self.convention.model.layered:
            return self._layer(scene, self.convention)
        return Coverage.from_layers([self._layer(scene, self.convention.at_sample(k)) for k in range(self.convention.n_samples)])

    def _layer(self, scene: PointScene, convention: Convention) -> Coverage:
        centres = convention.snap(scene.vertices)
        tx, ty, _ = convention.tie_perturbation
        ox, oy = (Fraction(v) for v in convention.sample)
        half = Fraction(scene.point_size) / 2
        bounds = np.zeros((len(scene), 4), dtype=np.int64)
        for k, (px, py) in enumerate(centres.tolist()):
            if not (math.isfinite(px) and math.isfinite(py)):
                continue
            first_x, stop_x = _bounds(Fraction(px), half, ox, tx)
            first_y, stop_y = _bounds(Fraction(py), half, oy, ty)
            # clipped to the viewport (a far point's bounds are huge Python integers)
            bounds[k] = (min(max(first_x, 0), scene.width), max(min(stop_x, scene.width), 0),
                         min(max(first_y, 0), scene.height), max(min(stop_y, scene.height), 0))
        return Coverage.from_boxes(*bounds.T)
