"""seams: on a planar partition under area coverage, the pieces' alphas sum to 1 inside
(within their rounding) and 0 outside; the seam compositing with over leaves, reported.
The shared parts of the area checks (the declared model, its bounds) are
:mod:`harness.checks.area`'s."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.area_levels import (
    AREA_COVERAGE_KINDS,
    _aligned,
    _fragments,
    _keyed,
    exact_tolerance,
)
from harness.checks.records import (
    EVIDENCE_LIMIT,
    Check,
    Figure,
    Result,
    register,
    result,
    skip,
)
from harness.checks.watertight import pixel_classes
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage

# -- seams ------------------------------------------------------------------------------------


def _classes(region: NDArray, convention: Convention, width: int, height: int) -> tuple[NDArray, NDArray]:
    """(inside, outside), (H, W) bool: pixels wholly inside (outside) the region both as
    given and as the convention snaps it (the pieces' vertices, the region's among them,
    move by snapping: a pixel counts only where both agree)."""
    inside, outside = pixel_classes(region, width, height)
    snapped = convention.snap(region)
    if not np.array_equal(snapped, region):
        inside_s, outside_s = pixel_classes(snapped, width, height)
        inside, outside = inside & inside_s, outside & outside_s
    return inside, outside


def piece_allowance(convention: Convention) -> Fraction:
    """How far, in levels, each piece's alpha may round off its exact area in a seam's
    sum: the declared tolerance (:func:`exact_tolerance`; half a level by default, one for
    a convention that rounds either way), but never more than one level -- no rounding to
    levels errs by a whole level, and a larger tolerance declares an approximation, whose
    errors the two sides of a shared edge must cancel (cairo's 2010 seam is two sides that
    do not). Exact.

    >>> [piece_allowance(Convention(coverage="area", tolerance=t)) for t in (None, 1 / 255, 0.375)]
    [Fraction(1, 2), Fraction(1, 1), Fraction(1, 1)]
    """
    return min(exact_tolerance(convention), Fraction(1, convention.levels - 1)) * (convention.levels - 1)


def _seam_allowance(pieces: NDArray, convention: Convention) -> NDArray:
    """Per pixel, the largest |sum of the pieces' levels - (levels - 1)| their roundings
    allow: floor(pieces * :func:`piece_allowance`), exactly (the sum is an integer)."""
    each = piece_allowance(convention)
    counts = pieces.astype(np.int64)
    out = np.zeros(counts.size)
    for k in np.unique(counts):
        out[counts == k] = math.floor(int(k) * each)
    return out


def seams(case: Case, coverage: Coverage, convention: Convention, oracle: Coverage) -> Result:
    """On a planar partition: at each pixel wholly inside the region the pieces' alphas,
    as levels ``rint(alpha * (levels - 1))``, sum to ``levels - 1`` within
    :func:`piece_allowance` per piece present there, floored (the sum is an integer; each
    piece may round by the declared tolerance -- half a level by default -- but by no
    more than one level; exact sample shares sum to exactly 1 too, so the rule is the same
    for a supersampled convention); at each pixel wholly outside, to 0 (a stray).

    A piece is present where the rasterizer gives it a nonzero alpha or the oracle a
    nonzero area: a sliver that rounds to level 0 still takes its area from the sum, and
    what it may lose must be allowed for (the float oracle's zero areas are
    below 2**-24 each, which no integer sum of levels can tell).

    Metrics: ``seam_pixels``, ``max_sum_error`` (largest |sum of alphas - 1| inside, in
    levels), ``strays``, ``inside_pixels``, and the conflation artifact ``max_over_gap``,
    ``mean_over_gap``: the background left showing, prod(1 - alpha), when the pieces are
    composited in one colour with ``over`` (never a failure by itself). Evidence (on
    failure): ``pixels``, worst first, ``{x, y, sum, levels_off, pieces, triangles,
    nonzero}`` (``sum``: of the alphas; ``levels_off``: sum of levels - (levels - 1);
    ``pieces``: present, as above; ``triangles``: those with nonzero alpha, at most 8;
    ``nonzero``: their number); ``strays``, ``[x, y]`` pairs.
    """
    if case.region is None:
        return skip(case, "seams", "not a planar partition")
    if convention.cull != "none":
        return skip(case, "seams", f"the convention culls {convention.cull} triangles: the pieces' sums mean nothing")
    scene = case.scene
    width, height = scene.width, scene.height
    t, x, y, alpha = _fragments(coverage, width, height, len(scene))
    pixel = y * width + x
    top = convention.levels - 1
    size = width * height
    with np.errstate(invalid="ignore"):
        levels = np.rint(alpha * top)
        level_sum = np.bincount(pixel, weights=levels, minlength=size)
        level_abs = np.bincount(pixel, weights=np.abs(levels), minlength=size)
        alpha_sum = np.bincount(pixel, weights=alpha, minlength=size)
        nonzero = np.bincount(pixel, weights=(alpha != 0).astype(float), minlength=size)
        # over: each piece leaves (1 - alpha) of what is below; the product, by its logarithm
        cleaned = np.clip(np.nan_to_num(alpha, nan=0.0), 0.0, 1.0)
        with np.errstate(divide="ignore"):
            gap = np.exp(np.bincount(pixel, weights=np.log1p(-cleaned), minlength=size))
    inside, outside = (c.ravel() for c in _classes(case.region, convention, width, height))
    # pieces present: nonzero alpha, or nonzero area in the oracle, per (triangle, pixel)
    keys, got, want = _aligned(*_keyed(coverage, width, height, len(scene)), *_keyed(oracle, width, height, len(scene)))
    present = keys[(got != 0) | (want != 0)] % size
    pieces = np.bincount(present, minlength=size).astype(float)
    off = level_sum - top
    allowed = _seam_allowance(pieces, convention)
    with np.errstate(invalid="ignore"):
        seam = inside & ~(np.abs(off) <= allowed)  # NaN is a seam
        stray = outside & ~(level_abs == 0)
        sum_error = np.where(np.isnan(alpha_sum), np.inf, np.abs(alpha_sum - 1.0) * top)
    n_inside = int(inside.sum())
    metrics = {
        "seam_pixels": float(seam.sum()),
        "max_sum_error": float(sum_error[inside].max(initial=0.0)),
        "strays": float(stray.sum()),
        "inside_pixels": float(n_inside),
        "max_over_gap": float(gap[inside].max(initial=0.0)),
        "mean_over_gap": float(gap[inside].mean()) if n_inside else 0.0,
    }
    ok = not seam.any() and not stray.any()
    evidence: dict[str, Any] = {}
    if not ok:
        bad = np.flatnonzero(seam)
        bad = bad[np.argsort(-np.nan_to_num(np.abs(off[bad]), nan=np.inf), kind="stable")][:EVIDENCE_LIMIT]
        evidence["pixels"] = [{"x": int(p % width), "y": int(p // width), "sum": float(alpha_sum[p]),
                               "levels_off": float(off[p]), "pieces": int(pieces[p]),
                               "triangles": sorted(set(t[(pixel == p) & (alpha != 0)].tolist()))[:8],
                               "nonzero": int(nonzero[p])} for p in bad]
        if stray.any():
            evidence["strays"] = [[int(p % width), int(p // width)] for p in np.flatnonzero(stray)[:EVIDENCE_LIMIT]]
    gaps = (f"compositing with over leaves up to {metrics['max_over_gap']:.3g} of the background showing "
            f"(mean {metrics['mean_over_gap']:.3g}: conflation)")
    if ok:
        message = (f"the pieces' alphas sum to 1 within their rounding ({float(piece_allowance(convention)):.3g} levels "
                   f"per piece) at all {n_inside} inside pixels; {gaps}")
    else:
        message = (f"{int(seam.sum())} seam pixels (the pieces' alphas off 1 by up to {metrics['max_sum_error']:.2f} levels), "
                   f"{int(stray.sum())} stray pixels outside; {gaps}")
    return result(case.id, "seams", ok, message, metrics, evidence)



register(Check(
    "seams", lambda s: seams(s.case, s.coverage, s.convention, s.oracle),  # type: ignore[arg-type]
    lambda case: not hasattr(case, "frames") and getattr(case, "region", None) is not None, needs_convention=True,
    coverage_kinds=AREA_COVERAGE_KINDS, per_sample=False, metrics={"seam_pixels": (1.0, 0.0), "strays": (1.0, 0.0)},
    caption="area coverage on a planar partition: the pieces' alphas sum to 1 inside (within their rounding), "
            "0 outside; the seam left by compositing with over reported",
    classifier="harness.diagnose.signatures:classify_seams", cause_role="consequent", motion_role="none",
    figures=(Figure("seam_pixels", "sum", "seam pixels (alphas not summing to 1)"),
             Figure("max_sum_error", "max", "largest seam (levels of its quantisation)"),
             Figure("max_over_gap", "max", "deepest seam after compositing with over")),
))
