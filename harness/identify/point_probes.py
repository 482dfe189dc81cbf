"""identify's probe for point-taking rasterizers: the sample point, tie rule and snapping
its point sprites follow.

A rasterizer that lists ``"points"`` in its ``scene_kinds`` is sent point scenes whose
squares' sides pass through the candidate sample points (centres on a 1/8-pixel lattice,
sizes in quarter pixels: :func:`tie_points`), beside float points a micro-pixel from such
ties (which only exact decisions draw as the oracle does). Each candidate convention --
the triangles' own first, then every sample point tried for triangles crossed with the
four ways an axis-aligned square can own its sides (top-left, top-right, bottom-left,
bottom-right: x-first and y-first rules cannot differ on a square) and the snapping
candidates -- is scored by the pixels where its oracle and the drawing differ; the best
is the fit, the runner-up its margin. A points convention that differs from the
triangles' is a finding, as for paths and lines.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from harness.contract.conventions import Convention, TieRule
from harness.engine.isolation import Outcome
from harness.kinds.points import PointScene
from harness.oracle.points import point_coverage

__all__ = ["SQUARE_TIES", "PointFit", "tie_points", "point_candidates", "fit_points", "point_verdict_cases"]

# the tie rules an axis-aligned square can tell apart (one per pair of owned sides)
SQUARE_TIES: tuple[TieRule, ...] = ("top-left", "top-right", "bottom-left", "bottom-right")
SAMPLE_POINTS = ((0.5, 0.5), (0.0, 0.0), (0.5, 0.0), (0.0, 0.5))
SIZE = 24


def tie_points(seed: int) -> list[PointScene]:
    """The probe scenes: lattice points (1/8 px) at sizes 1, 2, 1.25 and 0.75 whose
    sides pass through every candidate sample point, and float points nudged by about a
    micro-pixel off such ties."""
    rng = np.random.default_rng([seed, 7])
    scenes = []
    for size in (1.0, 2.0, 1.25, 0.75):
        centres = rng.integers(8, 8 * (SIZE - 1), size=(150, 2)) / 8.0
        scenes.append(PointScene(SIZE, SIZE, centres, point_size=size))
    lattice = rng.integers(8, 8 * (SIZE - 1), size=(150, 2)) / 8.0
    scenes.append(PointScene(SIZE, SIZE, lattice + rng.uniform(-1e-6, 1e-6, size=lattice.shape), point_size=1.5))
    return scenes


def point_candidates(triangles: Convention | None, samples: Sequence[tuple[float, float]] = SAMPLE_POINTS) -> list[Convention]:
    """The conventions tried: the triangles' own first (when known), then each sample point
    with each square tie rule, unsnapped and snapped as the triangles are."""
    base = Convention() if triangles is None else triangles.point_sampled()
    out = [base] if triangles is not None else []
    snaps = {(None, "nearest-even"), (base.subpixel_bits, base.snap_rounding)}
    for sample in dict.fromkeys([base.sample, *samples]):
        for tie in SQUARE_TIES:
            for bits, rounding in sorted(snaps, key=lambda s: (s[0] is not None, s[0] or 0)):
                candidate = replace(base, sample=sample, tie=tie, subpixel_bits=bits, snap_rounding=rounding)
                if candidate not in out:
                    out.append(candidate)
    return out


@dataclass(frozen=True)
class PointFit:
    """The convention a point-taking rasterizer's sprites follow, as seen from outside.

    Attributes
    ----------
    convention : Convention or None
        The best candidate (None when no probe scene was answered).
    residual : int
        Pixels where its oracle and the drawing differ on the probe scenes (0: an exact fit).
    pixels : int
        Pixels drawn on the probe scenes: the evidence's size.
    runner_up : tuple of (str, int) or None
        The next best candidate, in words, and its mismatches.
    errors : tuple of str
        The probe scenes the rasterizer did not answer, each with its error.
    """

    convention: Convention | None
    residual: int
    pixels: int
    runner_up: tuple[str, int] | None
    errors: tuple[str, ...] = ()

    @property
    def exact(self) -> bool:
        return self.convention is not None and self.residual == 0

    def describe(self) -> str:
        if self.convention is None:
            return "points: no probe scene answered (" + "; ".join(self.errors) + ")"
        fit = "exactly" if self.exact else f"best, {self.residual} of {self.pixels} px differ"
        margin = f"; next {self.runner_up[0]} ({self.runner_up[1]} px)" if self.runner_up else ""
        return f"points: {self.convention.describe()} ({fit}{margin})"


def _mismatches(coverage_pixels: np.ndarray, scene: PointScene, convention: Convention) -> int:
    expected = point_coverage(scene, convention).counts(scene.width, scene.height) > 0
    return int(np.count_nonzero(expected != coverage_pixels))


def fit_points(call: Callable[[PointScene], Outcome], triangles: Convention | None, seed: int = 0) -> PointFit:
    """Send :func:`tie_points` to ``call`` (scene -> :class:`harness.engine.isolation.Outcome`)
    and fit :func:`point_candidates` to what it drew (pixels drawn at least once)."""
    drawn: list[tuple[PointScene, np.ndarray]] = []
    errors: list[str] = []
    for scene in tie_points(seed):
        outcome: Outcome = call(scene)
        if outcome.coverage is None:
            errors.append(f"size {scene.point_size:g}: {outcome.error!r}")
            continue
        drawn.append((scene, outcome.coverage.counts(scene.width, scene.height) > 0))
    if not drawn:
        return PointFit(None, 0, 0, None, tuple(errors))
    scored = sorted(((sum(_mismatches(pixels, scene, c) for scene, pixels in drawn), i, c)
                     for i, c in enumerate(point_candidates(triangles))), key=lambda t: (t[0], t[1]))
    (best, _, convention), runner = scored[0], scored[1] if len(scored) > 1 else None
    pixels = sum(int(p.sum()) for _, p in drawn)
    return PointFit(convention, best, pixels, (runner[2].describe(), runner[0]) if runner else None, tuple(errors))


def point_verdict_cases(seed: int, model: Any) -> list[Any]:
    """The points' ``verdict_cases`` hook: the suite's point tilings and tie cases, for a
    sample-based coverage model (points have no area oracle)."""
    from cases.points import point_cases

    if not (model.single_sample or model.layered):
        return []
    return [c for c in point_cases(seed) if c.id.split("/")[1] in ("tiles", "ties")]
