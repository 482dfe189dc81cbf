"""The case record: a named scene plus what is known about it exactly."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from harness.api import Scene

__all__ = ["Case"]


@dataclass(frozen=True, slots=True, eq=False)
class Case:
    """A named scene and the facts the checks may rely on.

    Parameters
    ----------
    id : str
        Stable hierarchical id, ``family/variant/detail``; the first part is the family.
    scene : Scene
    lattice : bool
        Every coordinate lies on a coarse dyadic lattice: float arithmetic is exact there,
        so no deviation from the oracle is excused as rounding.
    region : (M, 2) float64 or None
        For a planar partition, the convex outline (clockwise or not) of the union of
        its triangles, known exactly: pixels wholly inside must be hit exactly once,
        pixels wholly outside never, and no pixel twice.
    closed : bool
        The triangles form a closed mesh wholly in front of the camera: at every pixel,
        hits by clockwise triangles equal hits by counter-clockwise ones.
    refusable : tuple of int
        Triangles with finite but huge coordinates that a rasterizer may refuse by
        raising ValueError naming them (reported as skip, with its reason).
    """

    id: str
    scene: Scene
    lattice: bool = False
    region: NDArray[np.float64] | None = None
    closed: bool = False
    refusable: tuple[int, ...] = field(default=())

    @property
    def family(self) -> str:
        return self.id.split("/", 1)[0]

    @property
    def non_finite(self) -> tuple[int, ...]:
        """Triangles with a NaN or infinite coordinate."""
        bad = ~np.all(np.isfinite(self.scene.positions), axis=(1, 2))
        return tuple(int(t) for t in np.flatnonzero(bad))
