"""What the checks do differently for point scenes (:mod:`harness.kinds.points`): the
distance of a wrong sample from its point's square (conformance's near ties) and the
points' own invariance variant. Every other check judges points as it judges any scene:
conformance against :mod:`harness.oracle.points`, hygiene, whole-pixel translation,
watertightness of the tiling cases, non-finite centres drawing nothing."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from harness.checks.records import Tolerance
from harness.contract.conventions import Convention
from harness.contract.scenes import AnyScene
from harness.kinds.points import PointScene

__all__ = ["point_near_ties", "point_variants"]


def square_distance(scene: PointScene, convention: Convention, fragments: NDArray) -> NDArray:
    """(M,) float64: each fragment's sample's distance (px) from the boundary of its point's
    (snapped) square, inf for a fragment naming no point or a non-finite one.

    Parameters
    ----------
    fragments : (3, M) int64 rows point, x, y
    """
    out = np.full(fragments.shape[1], np.inf)
    point = fragments[0]
    ok = (point >= 0) & (point < len(scene))
    if not ok.any():
        return out
    centres = convention.snap(scene.vertices)[point[ok]]
    half = 0.5 * scene.point_size
    sample = np.stack([fragments[1, ok] + convention.sample[0], fragments[2, ok] + convention.sample[1]], axis=1)
    with np.errstate(invalid="ignore"):
        beyond = np.abs(sample - centres) - half  # per axis: > 0 outside the side's slab
        inside = (beyond <= 0).all(axis=1)
        out[ok] = np.where(inside, np.min(-beyond, axis=1), np.hypot(*np.maximum(beyond, 0.0).T))
    out[~np.isfinite(out)] = np.inf
    return out


def point_near_ties(scene: PointScene, convention: Convention | None, fragments: NDArray,
                    tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """The points' ``near_ties`` hook: :func:`square_distance`, relative to each point's
    magnitude (pixel centres without a convention)."""
    convention = Convention() if convention is None else convention
    distance = square_distance(scene, convention, fragments)
    point = fragments[0]
    ok = (point >= 0) & (point < len(scene))
    magnitude = np.full(distance.size, np.inf)
    with np.errstate(invalid="ignore"):
        scale = np.maximum(1.0, np.abs(scene.vertices).max(axis=1, initial=0.0) + scene.point_size)
        magnitude[ok] = scale[point[ok]]
        near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
    return near, distance


def point_variants(scene: PointScene, seed: int) -> list[tuple[str, AnyScene, NDArray]]:
    """The points' own variant: the points listed in another order (each is decided alone)."""
    order = np.random.default_rng(seed).permutation(len(scene)).astype(np.int64)
    return [("permute-points", scene.subset(order), order)]
