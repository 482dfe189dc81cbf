"""Area (anti-aliased) coverage: accuracy against the exact area, seams on planar
partitions, and popping under sub-pixel motion.

Each check reads the answer as (triangle, pixel) -> alpha, keyed ``(triangle * H + y) * W
+ x`` (a pixel a side leaves out has alpha 0), vectorised with ``np.unique`` and
``np.bincount``; the only per-pixel Python work is the exact rational decision of the
few verdicts the float oracle's proven bound leaves open.

accuracy
    |alpha - model| per (triangle, pixel) against the declared tolerance, where the model
    is the convention's oracle (:func:`harness.oracle.coverage.exact_coverage`): the exact area
    (float, within :func:`harness.oracle.area.area_error_bound` of the rational one) or, for a
    supersampled convention, the share of samples covered (exact). A verdict the bound
    leaves open is decided with :func:`harness.oracle.area.exact_area`. Alphas off the declared
    quantisation (not a multiple of 1/(levels - 1) up to float representation) fail too.
    An alpha beyond the tolerance that float rounding explains is a near tie, counted apart
    as conformance counts its own: the rasterizer's geometry moved by at most what
    conformance calls rounding (:func:`rounding_reach`) has a model value the alpha is
    within the tolerance of -- the exact area moves by at most
    :func:`harness.oracle.area.displaced_area_bound` of it (so only an area that close to a level's
    rounding boundary can round the other way), and each sample within rounding of an
    edge (:func:`harness.checks.conformance.near_ties`) may count either way. Decided
    exactly; none on a lattice case, none allowed in strict mode. On a motion case,
    every frame is judged so (:func:`motion_accuracy`), and the failing frames named.
    A failure names its cause from facts about its errors when one holds
    (:func:`alpha_cause`): truncation, coarse levels, a bias, gamma, large coordinates, a
    sub-pixel shift, drift.
seams
    On a planar partition the exact areas (or sample shares) of the pieces in a pixel
    wholly inside the region sum to exactly 1, so the pieces' alphas, as integer levels,
    must sum to levels - 1 within what each piece's rounding may lose (the declared
    tolerance, at most one level: :func:`harness.checks.area_seams.piece_allowance`), decided exactly; outside the
    region they must sum to 0. The depth of the seam after compositing the pieces with ``over`` (the
    background left showing, prod(1 - alpha)) is reported as an artifact, never a failure.
popping
    Under a sub-pixel motion, each (triangle, pixel)'s alpha change from frame to frame
    against the declared model's change: beyond twice the tolerance the alpha jumped on
    its own. Against the exact area (even for a supersampled convention: that is what a
    viewer sees), the per-pixel change of the summed alpha is reported in 8-bit levels
    (pops).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.area_levels import (
    AREA_COVERAGE_KINDS,
    LEVEL_NOISE,
    _aligned,
    _keyed,
    _model_words,
    accuracy_message,
    exact_alpha,
    exact_tolerance,
    level_values,
    off_level,
)
from harness.checks.conformance import near_ties
from harness.checks.records import (
    EVIDENCE_LIMIT,
    Check,
    Figure,
    Result,
    Subject,
    Tolerance,
    overflow_class,
    register,
    result,
)
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import QUANTISED_AREA
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.kinds import LINES, TRIANGLES
from harness.oracle.area import area_error_bound, displaced_area_bound, exact_area
from harness.oracle.coverage import exact_samples

__all__ = ["accuracy", "motion_accuracy", "model_bound", "exact_model", "scene_model_bound", "scene_exact_model",
           "off_level", "level_values",
           "exact_alpha", "exact_tolerance", "rounding_reach", "alpha_facts", "alpha_cause", "ALPHA_CAUSES",
           "LEVEL_NOISE", "DISPLAY_LEVELS"]

# Pops are measured in the levels of an 8-bit display (1/255), whatever the convention
# declares: a 17-level supersampler's one-level step is a 16-level jump on screen.
DISPLAY_LEVELS = 255
# Rounding of the differences the checks form from floats in [0, 1] (a - b, then the
# difference of two such): a few units of 2**-53; 2**-50 per unit of magnitude is ample.
_DIFFERENCE_ROUNDING = 2.0**-50


# -- (triangle, pixel) -> alpha ---------------------------------------------------------------


# -- the declared model, in float with a bound and exactly ----------------------------------


def model_bound(positions: NDArray, convention: Convention, width: int, height: int) -> NDArray:
    """Per triangle, a proven bound on |oracle alpha - exact model| at every pixel.

    Parameters
    ----------
    positions : (N, 3, 2) float64
        The scene's positions as given (snapped here).
    convention : Convention
        An area convention.
    width, height : int

    Returns
    -------
    (N,) float64
        :func:`harness.oracle.area.area_error_bound` of the snapped triangles for the exact area;
        for a supersampled convention the share count/n is exact but for the rounding of
        the division (2**-53).

    >>> model_bound(np.array([[[0, 0], [4, 0], [0, 4]]], float), Convention(coverage="area"), 8, 8) * 2**53
    array([360.])
    """
    if convention.samples is not None or convention.model.quantum:
        return np.full(positions.shape[0], 2.0**-53)  # a share k/n, or a level k/quantum: the division's rounding
    if convention.rows:
        # row-sampled (harness.oracle.aa_models): each cross-section end is within a few
        # ulps of its coordinates; the exact fallback decides what this leaves open
        return np.full(positions.shape[0], 2.0**-30)
    if convention.model is QUANTISED_AREA:
        # a library's level (harness.oracle.analytic_models), decided exactly: level / 255 as
        # the alphas' level values are
        return np.zeros(positions.shape[0])
    return area_error_bound(convention.snap(positions), width, height)


def exact_model(positions: NDArray, convention: Convention, triangle: int, x: int, y: int, share: float = 0.0,
                surface: tuple[int, int] | None = None) -> Fraction:
    """The declared model's value at one (triangle, pixel), exactly: the area of the
    snapped triangle inside the pixel square (0 when culled or not finite), or, for a
    supersampled convention, the share of samples ``share`` (the oracle's float, count/n)
    as the rational count/n. ``surface`` (width, height): the viewport cairo's hybrid clips
    to (``full_rows``; None: unclipped).

    >>> exact_model(np.array([[[0, 0], [1, 0], [0, 3]]], float), Convention(coverage="area"), 0, 0, 0)
    Fraction(5, 6)
    """
    if convention.samples is not None:
        n = convention.n_samples
        return Fraction(int(round(share * n)), n)
    if convention.model.quantum:  # the model's own levels (skia's supersampler): the oracle's k/quantum
        return Fraction(int(round(share * convention.model.quantum)), convention.model.quantum)
    if convention.model is QUANTISED_AREA:
        # the oracle's level (``share``: level / 255) is decided exactly
        # (harness.oracle.analytic_models.quantised_area_coverage): the number it stands for
        return Fraction(int(round(share * 255)), 255)
    tri = convention.snap(positions[triangle : triangle + 1])
    if not np.all(np.isfinite(tri)):
        return Fraction(0)
    if convention.cull != "none":
        sign = int(orientation(tri)[0])
        if sign == (1 if convention.cull == "cw" else -1):
            return Fraction(0)
    if convention.rows:
        from harness.oracle.aa_models import exact_row_sampled_alpha

        return exact_row_sampled_alpha(tri[0], int(x), int(y), convention.rows, convention.full_rows, surface=surface)
    return exact_area(tri[0], int(x), int(y))


def scene_model_bound(scene: Any, convention: Convention) -> NDArray:
    """:func:`model_bound` of any scene the area checks judge: a line scene's (anti-aliased
    strokes, :func:`harness.oracle.area_lines.line_model_bound`) or a triangle scene's."""
    if LINES.owns(scene):
        from harness.oracle.area_lines import line_model_bound

        return line_model_bound(scene, convention)
    scene = TRIANGLES.narrow(scene)
    return model_bound(scene.positions, convention, scene.width, scene.height)


def scene_exact_model(scene: Any, convention: Convention, primitive: int, x: int, y: int, share: float = 0.0) -> Any:
    """:func:`exact_model` of any scene the area checks judge: for a line scene the exact
    stroke area (:class:`harness.oracle.area_lines.LineArea`, compared exactly with rationals)."""
    if LINES.owns(scene):
        from harness.oracle.area_lines import exact_line_model

        return exact_line_model(scene, convention, primitive, x, y)
    scene = TRIANGLES.narrow(scene)
    return exact_model(scene.positions, convention, primitive, x, y, share, surface=(scene.width, scene.height))


# -- near ties: float rounding ----------------------------------------------------------------


def rounding_reach(positions: NDArray, convention: Convention, tolerance: Tolerance) -> NDArray:
    """Per triangle, how far float rounding may move its geometry, in pixels: the error
    model of conformance's near ties (:func:`harness.checks.conformance.near_ties`),
    ``tolerance.near_tie`` relative to max(1, largest |coordinate|) of the snapped
    triangle, never more than ``tolerance.near_tie_pixels``; 0 for a triangle with a
    non-finite coordinate or one the convention culls (no rounding draws either).

    Parameters
    ----------
    positions : (N, 3, 2) float64
        The scene's positions as given (snapped here).
    convention : Convention
    tolerance : Tolerance

    Returns
    -------
    (N,) float64

    >>> tris = np.array([[[0, 0], [4, 0], [0, 4]], [[0, 0], [2.0**30, 0], [0, 1]], [[0, 0], [0, 4], [4, 0]]], float)
    >>> (rounding_reach(tris, Convention(coverage="area", cull="ccw"), Tolerance()) * 2**40).tolist()  # the last one culled
    [4.0, 1048576.0, 0.0]
    """
    snapped = convention.snap(positions)
    finite = np.all(np.isfinite(snapped), axis=(1, 2))
    with np.errstate(invalid="ignore"):
        magnitude = np.maximum(1.0, np.abs(np.where(finite[:, None, None], snapped, 0.0)).max(axis=(1, 2), initial=0.0))
    reach = np.where(finite, np.minimum(tolerance.near_tie * magnitude, tolerance.near_tie_pixels), 0.0)
    if convention.cull != "none":
        culled = orientation(np.where(finite[:, None, None], snapped, 0.0)) == (1 if convention.cull == "cw" else -1)
        reach[culled] = 0.0
    return reach


def _inside_samples(scene: Scene, convention: Convention, fragments: NDArray) -> NDArray:
    """(S, M) bool: which samples of each (triangle, x, y) of ``fragments`` (3, M) the
    triangle covers exactly under a supersampled convention (its oracle, on those
    triangles alone)."""
    width, height = scene.width, scene.height
    triangles = np.unique(fragments[0])
    alone = Scene(width, height, scene.positions[triangles])
    single = convention.point_sampled()
    wanted = (np.searchsorted(triangles, fragments[0]) * height + fragments[2]) * width + fragments[1]
    inside = np.zeros((convention.n_samples, fragments.shape[1]), dtype=bool)
    for s, layer in enumerate(exact_samples(alone, single, convention.samples)):
        t, x, y = layer.pixels()
        inside[s] = np.isin(wanted, (t * height + y) * width + x)
    return inside


def _near_ties(case: Case, convention: Convention, tolerance: Tolerance, triangle: NDArray, x: NDArray, y: NDArray,
               alpha: NDArray, error: NDArray, margin: NDArray, over: NDArray,
               exact_at: Callable[[int], Fraction], limit: Fraction) -> NDArray:
    """Which pixels beyond the tolerance (``over``) float rounding explains: geometry moved
    by at most :func:`rounding_reach` has a model value the alpha is within the tolerance
    of. Decided exactly (the reach is the error model's bound, not a slack of the decision).

    * Exact area: the area moves by at most :func:`harness.oracle.area.displaced_area_bound` of
      the reach, so the pixel is a near tie when ``|alpha - area| <= tolerance + that``
      (for a half-level tolerance: the area within that of a rounding boundary
      (k + 1/2) / (levels - 1)). A float rasterizer's own arithmetic on the area and its
      quantisation errs by some u M (u = 2**-53, M the largest local coordinate; the
      float oracle's bound is about 70 u M), far inside that reach of 8.5 * 2**-40 per unit
      of max(1, M) (or 8.5 * 2**-20 at the cap).
    * Share of samples: each sample within rounding of an edge (conformance's
      :func:`harness.checks.conformance.near_ties` at its offset) may count either way, the
      others as the exact oracle counts them; the pixel is a near tie when some count so
      reached is within the tolerance of the alpha.

    ``error`` is the float |level value - oracle| (:func:`level_values`) and ``margin`` a
    bound on its error (the oracle's, the differences' and the sum's roundings);
    ``exact_at(i)`` the exact model; ``limit`` the exact tolerance (:func:`exact_tolerance`);
    each alpha stands for :func:`exact_alpha`.
    No near ties on a lattice case (float arithmetic is exact there, as in conformance).
    """
    near = np.zeros(over.size, dtype=bool)
    if case.lattice or convention.model.quantum:  # a model of the library's integers has no float rounding to excuse
        return near
    scene = case.scene
    scene = TRIANGLES.narrow(scene)  # area coverage is judged on triangle scenes
    reach = rounding_reach(scene.positions, convention, tolerance)
    levels = convention.levels
    with np.errstate(invalid="ignore"):
        candidates = np.flatnonzero(over & np.isfinite(alpha) & (reach[triangle] > 0))
    if not candidates.size:
        return near
    if convention.samples is None:
        shift = displaced_area_bound(reach)[triangle[candidates]]
        allowed = float(limit) + shift  # its roundings are inside the margin
        e, m = error[candidates], margin[candidates]
        near[candidates[e + m <= allowed]] = True
        for k in np.flatnonzero((e + m > allowed) & ~(e - m > allowed)):  # open: the rationals decide
            i = int(candidates[k])
            near[i] = abs(exact_alpha(float(alpha[i]), levels) - exact_at(i)) <= limit + Fraction(float(shift[k]))
        return near
    n = convention.n_samples
    snapped = convention.snap(scene.positions)
    fragments = np.stack([triangle[candidates], x[candidates], y[candidates]])
    close = np.zeros((n, candidates.size), dtype=bool)
    for s, offset in enumerate(convention.samples):
        close[s] = near_ties(snapped, fragments, offset, tolerance)[0]
    some = np.flatnonzero(close.any(axis=0))
    if not some.size:
        return near
    inside = _inside_samples(scene, convention, fragments[:, some])
    spread = limit * n
    for column, c in enumerate(some):
        i = int(candidates[c])
        count = int(exact_at(i) * n)  # the exact share's count
        may_leave = int((close[:, c] & inside[:, column]).sum())
        may_join = int((close[:, c] & ~inside[:, column]).sum())
        level = exact_alpha(float(alpha[i]), levels) * n
        lowest = max(count - may_leave, math.ceil(level - spread))
        highest = min(count + may_join, math.floor(level + spread))
        near[i] = lowest <= highest
    return near


# -- accuracy ---------------------------------------------------------------------------------


def accuracy(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention,
             tolerance: Tolerance = Tolerance()) -> Result:
    """|alpha - model| per (triangle, pixel) against the declared tolerance; a pixel either
    side leaves out has alpha 0. Alphas off the declared levels fail too.

    Each alpha is the number it stands for, level k's k/(levels - 1) (:func:`exact_alpha`),
    and the tolerance the one declared (:func:`exact_tolerance`: exactly half a level by
    default), so an area exactly halfway between two levels is within the tolerance of
    either, and an error exactly at the tolerance is within it. The float oracle is within
    :func:`model_bound` of the model; where that bound (and the roundings of the level's
    value and of the difference) leaves the verdict open, the exact rational model decides
    (:func:`exact_model`): no epsilon decides.

    A pixel beyond the tolerance that float rounding explains -- geometry moved by at most
    what conformance calls rounding (:func:`rounding_reach`) has a model value within the
    tolerance of the alpha: the exact area within reach of a level's rounding boundary, or
    samples within rounding of an edge counted the other way (:func:`_near_ties`) -- is a
    near tie (float rounding): counted apart, not a failure in the default mode, a failure
    in strict mode (``tolerance.mode``), never on a lattice case.

    Metrics: ``max_error``, ``mean_error`` (over the (triangle, pixel)s where either side
    is nonzero, near ties left out), ``over_tolerance`` (near ties left out), ``near_tie``,
    ``near_tie_error`` (the largest error of a near tie), ``pixels``, ``off_level``,
    ``exact_decisions``. Evidence (on failure, or with near ties): ``pixels``, failures
    first, then near ties, each worst first, ``{triangle, x, y, alpha, area, error, over,
    near_tie}`` (``area``: the model's value, a share for a supersampled convention); and
    ``off_level``, ``{triangle, x, y, alpha, level}`` (level: alpha * (levels - 1)). With
    pixels beyond the tolerance, ``alpha_facts`` (:func:`alpha_facts`) and, when they name
    one, ``alpha_cause`` (:func:`alpha_cause`), whose words end the message.
    """
    scene = case.scene
    if getattr(scene, "kind", "triangles") == "paths":  # the area where the fill rule holds (issue 34)
        from harness.checks.area_paths import path_accuracy
        return path_accuracy(case, coverage, oracle, convention, tolerance)
    lines = LINES.owns(scene)  # anti-aliased strokes (harness.oracle.area_lines); else triangles
    if not lines:
        scene = TRIANGLES.narrow(scene)
    width, height, n = scene.width, scene.height, len(scene)
    keys, alpha, model = _aligned(*_keyed(coverage, width, height, n), *_keyed(oracle, width, height, n))
    present = (alpha != 0) | (model != 0)  # NaN counts as present
    keys, alpha, model = keys[present], alpha[present], model[present]
    levels = convention.levels
    with np.errstate(invalid="ignore"):
        error = np.abs(level_values(alpha, levels) - model)
    error[np.isnan(error)] = np.inf
    limit = exact_tolerance(convention)
    bound = float(limit)
    triangle = keys // (width * height)
    finite = np.isfinite(alpha)
    magnitude = np.maximum(1.0, np.abs(np.where(finite, alpha, 0.0)))
    # the exact error lies within ``margin`` of ``error``: the oracle's bound, the rounding
    # of the level's value and of the difference, and that of the tolerance's float
    margin = (scene_model_bound(scene, convention)[triangle] + _DIFFERENCE_ROUNDING * magnitude
              + _DIFFERENCE_ROUNDING * max(1.0, bound))
    # beyond the tolerance for sure, within it for sure, or open -- then the rationals
    # decide (a NaN or infinite alpha is beyond any tolerance)
    over = (error - margin > bound) | ~finite
    open_ = np.flatnonzero(~over & (error + margin > bound))
    x, y = keys % width, keys // width % height
    exact: dict[int, Fraction] = {}

    def exact_at(i: int) -> Fraction:
        """The exact model at pixel ``i`` (computed once)."""
        if i not in exact:
            exact[i] = scene_exact_model(scene, convention, int(triangle[i]), int(x[i]), int(y[i]), float(model[i]))
        return exact[i]

    for i in open_:
        over[i] = abs(exact_alpha(float(alpha[i]), levels) - exact_at(int(i))) > limit
    # near ties are measured on triangles (a stroke's rounding reach is not modelled yet)
    near = (np.zeros(over.size, dtype=bool) if lines else
            _near_ties(case, convention, tolerance, triangle, x, y, alpha, error, margin, over, exact_at, limit))
    over &= ~near
    off = off_level(alpha, convention.levels)
    count, n_off, n_near = int(over.sum()), int(off.sum()), int(near.sum())
    plain = error[~near]
    worst = float(plain.max(initial=0.0))
    worst_near = float(error[near].max(initial=0.0))
    metrics = {
        "max_error": worst,
        "mean_error": float(plain.mean()) if plain.size else 0.0,
        "over_tolerance": float(count),
        "near_tie": float(n_near),
        "near_tie_error": worst_near,
        "pixels": float(keys.size),
        "off_level": float(n_off),
        "exact_decisions": float(open_.size),
    }
    ok = not count and not n_off and not (n_near and tolerance.mode == "strict")
    step = convention.level_step
    what = _model_words(convention)
    evidence: dict[str, Any] = {}
    if not ok or n_near:
        # failures first, then near ties, each worst first
        order = np.lexsort((-error, ~over, ~(over | near)))[:EVIDENCE_LIMIT]
        evidence["pixels"] = [{"triangle": int(triangle[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                               "area": float(model[i]), "error": float(error[i]), "over": bool(over[i]),
                               "near_tie": bool(near[i])} for i in order]
        evidence["model"] = what
        evidence["tolerance"] = bound
        if n_off:
            shown = np.flatnonzero(off)[:EVIDENCE_LIMIT]
            evidence["off_level"] = [{"triangle": int(triangle[i]), "x": int(x[i]), "y": int(y[i]), "alpha": float(alpha[i]),
                                      "level": float(alpha[i] * (convention.levels - 1))} for i in shown]
    ties = ""
    if n_near:
        why = ("samples within rounding of an edge" if convention.samples is not None
               else "the area within rounding of a level's boundary")
        ties = f"{n_near} near ties (float rounding: {why}; up to {worst_near / step:.1f} levels)"
    cause = None
    if count:
        # the cause, named from facts about the errors (alpha_cause)
        facts = {} if lines else alpha_facts(case, convention, triangle, x, y, alpha, model, near, over)
        cause = alpha_cause(facts) if facts else None
        evidence["alpha_facts"] = facts
        if cause is not None:
            evidence["alpha_cause"] = cause[0]
    message = accuracy_message(total=keys.size, count=count, n_off=n_off, n_near=n_near, ties=ties, bound=bound, what=what,
                               worst=worst, step=step, levels=convention.levels, strict=tolerance.mode == "strict",
                               cause=None if cause is None else cause[1])
    return result(case.id, "accuracy", ok, message, metrics, evidence)


# -- accuracy's causes ------------------------------------------------------------------------

# The causes accuracy names from facts about its errors, first that holds (class, words):
ALPHA_CAUSES: dict[str, str] = {
    "truncated-levels": "alphas truncated to the levels, not rounded",
    "coarse-levels": "alphas on fewer levels than declared",
    "alpha-bias": "alphas biased: off by about the same number of levels everywhere",
    "gamma": "alphas a power of the area: gamma-encoded (error a function of alpha)",
    "sub-pixel-shift": "alphas of the shape moved by a sub-pixel shift",
    "drift": "alpha error growing along a row or down a triangle: stepping accumulates error",
    # where the errors lie: the classes (and words) conformance names the same facts by
    "non-finite-input": "a primitive with a NaN or infinite coordinate drawn wrongly",
    "viewport-edge": "wrong only where primitives cross the viewport's edge",
}
# a fact holds when it explains this share of the edge pixels (partially covered) at least
CAUSE_SHARE = 0.9
# coarse levels: at least this many seen, half of them in use
COARSE_LEVELS_MIN = 5
# a bias or gamma: read over edge pixels whose areas span this much at least
AREA_SPREAD = 0.5
# gamma: an exponent this far from 1 at least, its fit within a level of every edge pixel
GAMMA_MIN = 0.05
# drift: the errors' correlation with the rows (columns) stepped from the triangle's top
# (left), and how much larger the mean error of the last quarter of them is than the first's
DRIFT_CORRELATION = 0.3
DRIFT_GROWTH = 3.0
# the shifts tried: the centroids' difference rounded to these grids (px)
SHIFT_GRIDS = (1 / 16, 1 / 8, 1 / 4, 1 / 2)


def alpha_facts(case: Case, convention: Convention, triangle: NDArray, x: NDArray, y: NDArray, alpha: NDArray,
                model: NDArray, near: NDArray, over: NDArray | None = None) -> dict[str, Any]:
    """Facts about a failing accuracy verdict's errors, from which :func:`alpha_cause`
    names the cause. Over the (triangle, pixel)s either side covers ((P,) each; ``near``:
    near ties, left out), in levels of the convention: ``bias`` (the median signed error
    of the edge pixels -- the model strictly between 0 and 1 -- and ``bias_share``, the
    share of them within the tolerance plus half a level of it; ``area_spread``, the range of
    their areas, over which a bias and gamma are told apart); ``residue`` (min and max
    of model - alpha on the edge pixels: truncation leaves [0, 1), rounding [-1/2, 1/2]; and
    ``between_levels``, the share of them not a whole number of levels);
    ``levels_seen`` (the fewest levels dividing the declared ones every alpha lies on,
    ``distinct_alphas`` the values in use, ``declared_levels``);
    ``gamma`` (the exponent g of alpha = area^g fitted by least squares on logarithms,
    and ``gamma_error``, the fit's largest error); ``drift`` (the correlation of |error| with
    the rows stepped from each triangle's top and with the columns from its left, and the
    mean |error| of the first and the last quarter of those); ``magnitude`` (the
    smallest largest |coordinate| of the snapped triangles holding a pixel beyond the
    tolerance); ``shift`` (the shift of the
    scene whose oracle the alphas are within the tolerance of: the centroids' difference,
    rounded to :data:`SHIFT_GRIDS`, each tried -- an oracle call each, only when no cheaper
    fact names a cause). Where the errors are, over the pixels beyond the tolerance
    (``over``, (P,) bool): ``over_pixels``, the share of them on triangles with a NaN or
    infinite coordinate (``over_non_finite``), and the sides of the screen (``over_border``:
    ``{side: count}``) whose border row or column they lie in on a triangle crossing that
    side, with the share of them that do (``over_border_share``). Numpy on the evidence pixels."""
    from harness.oracle.coverage import exact_coverage

    scene = TRIANGLES.narrow(case.scene)
    levels = convention.levels - 1
    tolerance = float(exact_tolerance(convention)) * levels
    keep = ~near & np.isfinite(alpha)
    value = level_values(alpha, convention.levels)
    signed = (value - model) * levels
    edge = keep & (model > 0) & (model < 1)
    facts: dict[str, Any] = {"edge_pixels": int(edge.sum()), "tolerance": tolerance}
    if over is not None and over.any():
        facts.update(_where_facts(scene, triangle[over], x[over], y[over]))
    if not edge.any():
        return facts
    s = signed[edge]
    facts["area_spread"] = float(model[edge].max() - model[edge].min())
    bias = float(np.median(s))
    facts["bias"] = bias
    facts["bias_share"] = float(np.mean(np.abs(s - bias) <= tolerance + 0.5))
    residue = -s
    facts["residue"] = [float(residue.min()), float(residue.max())]
    facts["between_levels"] = float(np.mean(np.abs(residue - np.rint(residue)) > 1e-6))
    on = alpha[keep]
    facts["declared_levels"] = convention.levels
    facts["distinct_alphas"] = int(np.unique(on).size)
    small = [k for k in range(1, math.isqrt(levels) + 1) if levels % k == 0]
    for d in sorted({*small, *(levels // k for k in small)} - {levels}):  # the divisors of levels - 1 below it
        if not off_level(on, d + 1).any():
            facts["levels_seen"] = d + 1
            break
    m, a = model[edge], value[edge]
    inner = (a > 0) & (a < 1)
    if inner.sum() >= 3:
        lm, la = np.log(m[inner]), np.log(a[inner])
        g = float(np.sum(lm * la) / np.sum(lm * lm))
        facts["gamma"] = g
        facts["gamma_error"] = float(np.abs(m ** g - a).max() * levels)
    # the rows (columns) stepped from each triangle's top (left), its snapped vertices'
    positions = convention.snap(scene.positions)
    beyond = keep & (np.abs(signed) > tolerance)
    if beyond.any():  # the smallest of the largest |coordinate| of the triangles beyond the tolerance
        magnitude = np.where(np.isfinite(positions), np.abs(positions), 0.0).max(axis=(1, 2), initial=1.0)
        facts["magnitude"] = float(magnitude[np.unique(triangle[beyond])].min())
    with np.errstate(invalid="ignore"):  # NaN skipped (an all-NaN triangle's top is inf: no steps), without nanmin's warning
        unset = np.where(np.isnan(positions), np.inf, positions)
        top = np.maximum(np.floor(unset[:, :, 1].min(axis=1)), 0.0)  # stepped from the first row drawn
        left = np.maximum(np.floor(unset[:, :, 0].min(axis=1)), 0.0)
    error = np.abs(signed[edge])
    for name, steps in (("rows", y[edge] - top[triangle[edge]]), ("columns", x[edge] - left[triangle[edge]])):
        steps = steps.astype(np.float64)
        if error.size >= 8 and np.isfinite(steps).all() and steps.std() > 0 and error.std() > 0:
            span = float(steps.max() - steps.min())
            first, last = steps <= steps.min() + span / 4, steps >= steps.max() - span / 4
            facts[f"drift_{name}"] = {"correlation": float(np.corrcoef(steps, error)[0, 1]),
                                      "first": float(error[first].mean()), "last": float(error[last].mean()),
                                      "steps": int(span)}
    named = alpha_cause(facts)
    if (named is None or named[0] == "drift") and convention.cull == "none":  # a shift is named before drift
        facts.update(_shift_facts(scene, convention, triangle, x, y, value, model, keep, tolerance, exact_coverage))
    return facts


def _where_facts(scene: Scene, triangle: NDArray, x: NDArray, y: NDArray) -> dict[str, Any]:
    """Where the pixels beyond the tolerance ((K,) each) lie: ``over_pixels``,
    ``over_non_finite`` (the share on triangles with a NaN or infinite coordinate) and, of
    the others, those in a border row or column of the screen on a triangle reaching past
    that side (``over_border``, per side, and ``over_border_share``)."""
    p = scene.positions[triangle]
    finite = np.isfinite(p).all(axis=(1, 2))
    facts: dict[str, Any] = {"over_pixels": int(triangle.size), "over_non_finite": float(np.mean(~finite))}
    with np.errstate(invalid="ignore"):
        lo, hi = p.min(axis=1), p.max(axis=1)
    sides = {"top": finite & (y == 0) & (lo[:, 1] < 0), "bottom": finite & (y == scene.height - 1) & (hi[:, 1] > scene.height),
             "left": finite & (x == 0) & (lo[:, 0] < 0), "right": finite & (x == scene.width - 1) & (hi[:, 0] > scene.width)}
    border = np.zeros(triangle.size, dtype=bool)
    for name in sides:  # a corner pixel counts under the first side it lies on
        sides[name] &= ~border
        border |= sides[name]
    facts["over_border"] = {name: int(side.sum()) for name, side in sides.items() if side.any()}
    facts["over_border_share"] = float(np.mean(border))
    return facts


def _shift_facts(scene: Scene, convention: Convention, triangle: NDArray, x: NDArray, y: NDArray, value: NDArray,
                 model: NDArray, keep: NDArray, tolerance: float, oracle: Callable[..., Coverage]) -> dict[str, Any]:
    """``shift``: the move of the scene under whose oracle every alpha is within the
    tolerance, tried at the centroids' difference rounded to each of :data:`SHIFT_GRIDS`
    (alpha-weighted pixel centres against the model's, over the triangles a pixel inside
    the screen when there are some: a cut one's centroid moves otherwise); ``shift_tried``:
    those tried."""
    n, width, height = len(scene), scene.width, scene.height
    weight_a = np.bincount(triangle[keep], weights=value[keep], minlength=n)
    weight_m = np.bincount(triangle[keep], weights=model[keep], minlength=n)
    fine = (weight_a > 0) & (weight_m > 0)
    with np.errstate(invalid="ignore"):  # the triangles a pixel inside the screen: no part of them cut off
        p = scene.positions
        inside = np.isfinite(p).all(axis=(1, 2)) & (p.min(axis=(1, 2)) >= 1) & (p[:, :, 0].max(axis=1) <= width - 1) \
            & (p[:, :, 1].max(axis=1) <= height - 1)
    if (fine & inside).any():
        fine &= inside
    if not fine.any():
        return {}
    moved = []
    for c in (x, y):
        centre = c[keep] + 0.5
        a = np.bincount(triangle[keep], weights=value[keep] * centre, minlength=n)[fine] / weight_a[fine]
        b = np.bincount(triangle[keep], weights=model[keep] * centre, minlength=n)[fine] / weight_m[fine]
        moved.append(float(np.average(a - b, weights=weight_m[fine])))
    tried: list[list[float]] = []
    for grid in SHIFT_GRIDS:
        shift = [round(d / grid) * grid for d in moved]
        if shift in tried or shift == [0.0, 0.0]:
            continue
        tried.append(shift)
        other = oracle(scene.with_coordinates(scene.coordinates + np.array(shift)), convention)
        keys, got, want = _aligned(*_keyed(Coverage(triangle, y, x, x + 1, alpha=np.where(keep, value, 0.0)), width, height, n),
                                   *_keyed(other, width, height, n))
        if np.abs(got - want).max(initial=0.0) * (convention.levels - 1) <= tolerance * (1 + 1e-9) + 1e-9:
            return {"shift": shift, "shift_tried": tried}
    return {"shift_tried": tried} if tried else {}


def alpha_cause(facts: dict[str, Any]) -> tuple[str, str] | None:
    """The cause of an accuracy failure its facts (:func:`alpha_facts`) name, first that
    holds: (class of :data:`ALPHA_CAUSES`, the facts in words), else None. Errors only on
    triangles with a coordinate beyond 2**12 px, none of the level causes holding, are named
    by that magnitude as conformance names them (``overflow-2^a..2^b``), before a shift or
    drift: geometry off there is the range of the arithmetic.

    >>> alpha_cause({"edge_pixels": 9, "tolerance": 0.5, "bias": 2.0, "bias_share": 1.0, "residue": [-2.5, -1.5],
    ...              "area_spread": 0.9})
    ('alpha-bias', 'alphas 2.0 levels high on average')
    >>> alpha_cause({"edge_pixels": 9, "tolerance": 0.5, "residue": [0.0, 0.99], "between_levels": 0.9})
    ('truncated-levels', 'alphas truncated to the levels (up to 0.99 levels low), not rounded')
    """
    if facts.get("other_fill_rule"):  # a path scene's alphas, all within the tolerance under the other rule
        return "fill-rule", "every alpha within the tolerance of the other fill rule's: the fill rule drawn is not the one asked"
    tolerance = float(facts.get("tolerance", 0.5))
    # where the errors are, before what they are: every one on a non-finite triangle, or
    # in the border row or column of a screen side its triangle crosses
    if facts.get("over_pixels") and facts.get("over_non_finite") == 1.0:
        return "non-finite-input", (f"every alpha beyond the tolerance ({facts['over_pixels']}) on a triangle with a NaN "
                                    "or infinite coordinate, which covers nothing")
    border = facts.get("over_border")
    if facts.get("over_pixels") and facts.get("over_border_share") == 1.0 and isinstance(border, dict):
        rows = {"top": "top row", "bottom": "bottom row", "left": "left column", "right": "right column"}
        where = " and ".join(f"the screen's {rows[side]}" for side in border)
        return "viewport-edge", (f"every alpha beyond the tolerance ({facts['over_pixels']}) in {where}, on triangles "
                                 "reaching past that edge of the screen")
    if not facts.get("edge_pixels"):
        return None
    low, high = facts.get("residue", [0.0, 0.0])
    slack = 1e-6
    # truncation leaves the area less than a level above the alpha -- read where the areas
    # fall between levels (whole levels off are samples or levels too many, not a rounding)
    between = facts.get("between_levels", 0.0) >= 0.5
    if between and low >= -slack and high < 1.0 + slack and high > tolerance:
        return "truncated-levels", f"alphas truncated to the levels (up to {high:.2f} levels low), not rounded"
    if between and high <= slack and low > -1.0 - slack and -low > tolerance:
        return "truncated-levels", f"alphas rounded up to the levels (up to {-low:.2f} levels high), not to the nearest"
    seen, distinct = facts.get("levels_seen"), facts.get("distinct_alphas", 0)
    if isinstance(seen, int) and seen >= COARSE_LEVELS_MIN and 2 * distinct >= seen and max(abs(low), abs(high)) > tolerance:
        # many of the coarse levels in use (not a few alphas on a coarse grid by chance),
        # each within half a coarse level of the area: the area rounded to them
        coarse = (facts.get("declared_levels", 256) - 1) / (seen - 1)
        if max(abs(low), abs(high)) <= coarse / 2 + tolerance:
            return "coarse-levels", f"alphas on {seen} levels only"
    # a bias and gamma are told apart only over areas of many sizes (over half-covered
    # pixels alone a power of the area is off by one number of levels, as a bias is)
    spread = facts.get("area_spread", 0.0) >= AREA_SPREAD
    bias = facts.get("bias")
    if spread and isinstance(bias, float) and abs(bias) > tolerance and facts.get("bias_share", 0.0) >= CAUSE_SHARE:
        return "alpha-bias", f"alphas {abs(bias):.1f} levels {'high' if bias > 0 else 'low'} on average"
    g = facts.get("gamma")
    if spread and isinstance(g, float) and abs(g - 1.0) >= GAMMA_MIN and facts.get("gamma_error", math.inf) <= tolerance + 1.0:
        return "gamma", f"alphas the area to the power {g:.2f} (gamma {1 / g:.2f}): error a function of alpha"
    magnitude = facts.get("magnitude")
    if isinstance(magnitude, float) and magnitude >= 2.0**12:
        # geometry wrong only on triangles beyond 2**12 px: the range of the rasterizer's
        # arithmetic, as conformance names it (harness.checks.records.overflow_class)
        return str(overflow_class(magnitude)), (f"errors only on triangles with coordinates of magnitude {magnitude:.3g} px "
                                                "or more: precision that gives out at large coordinates")
    shift = facts.get("shift")
    if isinstance(shift, list):
        return "sub-pixel-shift", f"alphas of the shape moved by ({shift[0]:+g}, {shift[1]:+g}) px"
    for name, where in (("rows", "down the triangle"), ("columns", "along a row")):
        drift = facts.get(f"drift_{name}")
        if isinstance(drift, dict) and drift["correlation"] >= DRIFT_CORRELATION and drift["last"] > tolerance \
                and drift["last"] >= DRIFT_GROWTH * max(drift["first"], 1e-9):
            return "drift", (f"error growing {where}: {drift['first']:.1f} levels in its first {name} on average, "
                             f"{drift['last']:.1f} in its last ({drift['steps']} {name} stepped)")
    return None


def motion_accuracy(case: MotionCase, coverages: list[Coverage], oracles: list[Coverage], convention: Convention,
                    tolerance: Tolerance = Tolerance()) -> Result:
    """:func:`accuracy` on every frame of a motion sequence, each frame a still case of
    its own (no lattice claim: a frame's near ties are float rounding as on any case);
    the sequence fails when a frame does, and the result names the frames.

    Parameters
    ----------
    case : MotionCase
    coverages, oracles : list of Coverage
        One per frame: the answers and the convention's oracle (the one popping reads).
    convention : Convention
        An area convention.
    tolerance : Tolerance

    Returns
    -------
    Result
        Metrics summed over the frames (``over_tolerance``, ``off_level``, ``near_tie``,
        ``pixels``, ``exact_decisions``), the largest of ``max_error`` and
        ``near_tie_error``, ``mean_error`` over every frame's pixels, ``frames`` and
        ``failing_frames``. Evidence: the worst failing frame's accuracy evidence (each
        pixel with its ``frame``), ``frame`` (0-based), ``failing_frames`` (the first
        few) and ``series`` per frame (``over_tolerance_pixels``, ``max_error_levels``,
        ready to plot); on a pass, the series only.
    """
    verdicts = [accuracy(Case(case.id, scene), coverage, oracle, convention, tolerance)
                for scene, coverage, oracle in zip(case.frames, coverages, oracles)]
    summed = ("over_tolerance", "off_level", "near_tie", "pixels", "exact_decisions")
    metrics = {key: float(sum(r.metrics[key] for r in verdicts)) for key in summed}
    metrics["max_error"] = max((r.metrics["max_error"] for r in verdicts), default=0.0)
    metrics["near_tie_error"] = max((r.metrics["near_tie_error"] for r in verdicts), default=0.0)
    plain = [(r.metrics["pixels"] - r.metrics["near_tie"], r.metrics["mean_error"]) for r in verdicts]
    counted = sum(n for n, _ in plain)
    metrics["mean_error"] = float(sum(n * m for n, m in plain) / counted) if counted else 0.0
    failing = [f for f, r in enumerate(verdicts) if r.status == "fail"]
    metrics["frames"], metrics["failing_frames"] = float(len(verdicts)), float(len(failing))
    step = convention.level_step
    evidence: dict[str, Any] = {"series": {"over_tolerance_pixels": [r.metrics["over_tolerance"] for r in verdicts],
                                           "max_error_levels": [r.metrics["max_error"] / step for r in verdicts]}}
    if not failing:
        first = verdicts[0].message if verdicts else "no frames"
        message = f"every frame of {len(verdicts)}: {first}" if len(verdicts) == 1 else (
            f"all {len(verdicts)} frames within the tolerance (largest error {metrics['max_error']:.3g}, "
            f"{metrics['max_error'] / step:.2f} levels"
            + (f"; {int(metrics['near_tie'])} near ties" if metrics["near_tie"] else "")
            + ")")
        return result(case.id, "accuracy", True, message, metrics, evidence)
    worst = max(failing, key=lambda f: (verdicts[f].metrics["max_error"], -f))
    shown = verdicts[worst]
    evidence.update({key: value for key, value in shown.evidence.items() if key != "pixels"})
    evidence["pixels"] = [{**pixel, "frame": worst} for pixel in shown.evidence.get("pixels", [])]
    evidence["frame"] = worst
    evidence["failing_frames"] = failing[:EVIDENCE_LIMIT]
    message = (f"{len(failing)} of {len(verdicts)} frames fail (first: frame {failing[0]}); worst, frame {worst}: "
               f"{shown.message}")
    return result(case.id, "accuracy", False, message, metrics, evidence)


# -- registration -----------------------------------------------------------------------------


def _accuracy(s: Subject) -> Result:
    assert s.convention is not None
    if isinstance(s.case, MotionCase):
        return motion_accuracy(s.case, s.coverages, s.oracles, s.convention, s.tolerance)
    return accuracy(s.case, s.coverage, s.oracle, s.convention, s.tolerance)


register(Check(
    "accuracy", _accuracy, lambda case: True, needs_convention=True, shrinks=True, coverage_kinds=AREA_COVERAGE_KINDS,
    per_sample=False,
    metrics={"over_tolerance": (1.0, 0.0), "off_level": (1.0, 0.0), "max_error": (1.5, 2.0**-9)},
    caption="area coverage: every alpha within the declared tolerance of the exact area (or share of samples), "
            "on the declared levels (on every frame of a motion case)",
    # root: against the exact area, its failure names the scene's cause; the frame verdict of popping
    classifier="harness.diagnose.signatures:classify_accuracy", cause_role="root", motion_role="frame",
    figures=(Figure("max_error", "max", "largest |alpha - area|"), Figure("mean_error", "mean", "mean |alpha - area|"),
             Figure("over_tolerance", "sum", "pixels beyond the declared tolerance")),
))
