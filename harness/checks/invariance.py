"""invariance: vertex rotation, winding flip, triangle permutation and whole-pixel
translation change nothing but the shift (for paths: start vertex, contour reversal, contour
and path order, translation; for lines: strip order, strips split into lone segments,
translation); convention-free.

Reversing a line is no invariance (the diamond-exit rule omits the end pixel, Bresenham
breaks ties towards the end point): :mod:`harness.checks.lines` judges it against the
rule's prediction. Under area coverage it is: the w-wide stroke's area does not depend on
the direction it was drawn in, so anti-aliased lines are judged reversed too
(:func:`area_line_variants`).

Under area coverage the same scene up to orientation -- every contour reversed, one
contour of an even-odd path reversed, every segment reversed (:data:`ORIENTATION_VARIANTS`)
-- must give the same alphas exactly (issue 34: FreeType's and AGG's change by 1 to 3
levels): no rounding may follow the winding. The other variants change the order work is
done in, and may move an alpha by one level (:func:`area_invariance`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.conformance import deviations, near_ties_of
from harness.checks.fragments import same_canonical_spans
from harness.checks.records import ALL_COVERAGE_KINDS, EVIDENCE_LIMIT, Check, Result, Subject, Tolerance, register, result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.kinds import kind_of
from harness.kinds.lines import LINE_SHIFT
from harness.oracle.coverage import exact_coverage

__all__ = ["invariance_variants", "invariance", "area_invariance", "area_line_variants", "near_level_boundary",
           "shift_of", "LINE_SHIFT", "ORIENTATION_VARIANTS"]

# The variants that are the same scene up to orientation: under area coverage their alphas
# must be the original's exactly (but at a near tie, :func:`near_level_boundary`).
ORIENTATION_VARIANTS = frozenset({"reverse-every-contour", "reverse-one-contour", "reverse-segments"})



def path_variants(scene: PathScene, seed: int) -> list[tuple[str, AnyScene, NDArray]]:
    """The path scene's own variants: each contour starting at its next vertex, every
    contour reversed (the winding number negated: neither rule cares), for even-odd one
    contour per path reversed too (parity ignores orientation), contours listed in another
    order, paths numbered in another order."""
    n = len(scene)
    identity = np.arange(n)
    sizes, starts = scene.contour_sizes, scene.contour_starts
    offset = np.arange(scene.vertices.shape[0]) - np.repeat(starts, sizes)  # index within its contour
    base, size = np.repeat(starts, sizes), np.repeat(sizes, sizes)
    rotated = scene.with_coordinates(scene.vertices[base + (offset + 1) % size])
    reversed_ = scene.with_coordinates(scene.vertices[base + (size - 1 - offset)])
    out: list[tuple[str, AnyScene, NDArray]] = [("rotate-start-vertex", rotated, identity),
                                                ("reverse-every-contour", reversed_, identity)]
    if scene.fill_rule == "evenodd":
        first = np.zeros(sizes.size, dtype=bool)
        first[np.unique(scene.contour_path, return_index=True)[1]] = True
        one = np.repeat(first, sizes)
        out.append(("reverse-one-contour", scene.with_coordinates(np.where(one[:, None], reversed_.vertices, scene.vertices)),
                    identity))
    rng = np.random.default_rng(seed)
    order = rng.permutation(sizes.size)
    contours = scene.contours()
    vertices = np.concatenate([contours[c] for c in order]) if order.size else scene.vertices
    out.append(("reorder-contours", PathScene(scene.width, scene.height, vertices, sizes[order], scene.contour_path[order],
                                              scene.fill_rule), identity))
    perm = rng.permutation(n)
    out.append(("permute-paths", scene.subset(perm), perm))
    return out


def line_variants(scene: LineScene, seed: int) -> list[tuple[str, AnyScene, NDArray]]:
    """The line scene's own variants: strips listed in another order, and every strip split
    into lone segments (its joints gone). Each rule decides every segment alone, so each
    segment draws the same pixels either way."""
    first_segment = scene.strip_starts - np.arange(scene.strip_sizes.size)
    order = np.random.default_rng(seed).permutation(scene.strip_sizes.size)
    strips = scene.strips()
    index = np.concatenate([first_segment[s] + np.arange(scene.strip_sizes[s] - 1) for s in order]) if order.size \
        else np.zeros(0, dtype=np.int64)
    reordered = LineScene.from_strips(scene.width, scene.height, [strips[s] for s in order], scene.line_width)
    a, b = scene.segments()
    split = LineScene.from_segments(scene.width, scene.height, a, b, scene.line_width)
    return [("reorder-strips", reordered, index.astype(np.int64)), ("split-strips", split, np.arange(len(scene)))]


def area_line_variants(scene: LineScene) -> list[tuple[str, AnyScene, NDArray]]:
    """Anti-aliased lines' own variant beyond :func:`line_variants`: every strip drawn from
    its last vertex to its first (``reverse-segments``), each segment mapped back to its
    own number -- the stroke's area is the same whichever way it was drawn."""
    strips = scene.strips()
    first = scene.strip_starts - np.arange(scene.strip_sizes.size)  # each strip's first segment
    index = np.concatenate([first[s] + np.arange(scene.strip_sizes[s] - 2, -1, -1) for s in range(len(strips))]) \
        if strips else np.zeros(0, dtype=np.int64)
    reversed_ = LineScene.from_strips(scene.width, scene.height, [strip[::-1] for strip in strips], scene.line_width)
    return [("reverse-segments", reversed_, index.astype(np.int64))]


def shift_of(scene: AnyScene) -> tuple[int, int]:
    """The whole-pixel translation of the scene's ``translate`` variant."""
    return kind_of(scene).translate_shift


def invariance_variants(case: Case, shift: tuple[int, int] | None = None, seed: int = 0) -> list[tuple[str, AnyScene, NDArray]]:
    """Transformed scenes and, for each, the scene's primitive index of each variant
    primitive. Triangles: vertex order rotated, winding flipped, triangles permuted; paths
    (:func:`path_variants`): start vertex, contour reversal, contour order, path order;
    lines (:func:`line_variants`): strip order, strips split. All, when exact: translated
    by whole pixels (``shift``, by default :func:`shift_of`) into a viewport grown by the
    shift -- lines only when every coordinate is positive (a half-away-from-zero rounding
    of an end point at or left of 0 changes side under the shift)."""
    scene = case.scene
    kind = kind_of(scene)
    identity = np.arange(len(scene))
    shift = kind.translate_shift if shift is None else shift
    out: list[tuple[str, AnyScene, NDArray]] = kind.hook("invariance_variants")(scene, seed)
    moved = scene.coordinates + np.array(shift, dtype=float)
    with np.errstate(invalid="ignore"):
        exact = np.array_equal(moved - np.array(shift, dtype=float), scene.coordinates, equal_nan=True)
        if kind.translate_needs_positive:
            exact &= not bool((scene.coordinates <= 0).any())  # NaN compares False
    if exact:
        out.append(("translate", scene.with_coordinates(moved).with_viewport(scene.width + shift[0], scene.height + shift[1]),
                    identity))
    return out


def triangle_variants(scene: Scene, seed: int) -> list[tuple[str, AnyScene, NDArray]]:
    """The triangle scene's own variants: vertex order rotated, winding flipped, triangles
    permuted."""
    identity = np.arange(len(scene))
    out: list[tuple[str, AnyScene, NDArray]] = [
        ("rotate-vertices", Scene(scene.width, scene.height, scene.positions[:, [1, 2, 0]]), identity),
        ("flip-winding", Scene(scene.width, scene.height, scene.positions[:, [0, 2, 1]]), identity),
    ]
    perm = np.random.default_rng(seed).permutation(len(scene))
    out.append(("permute-triangles", Scene(scene.width, scene.height, scene.positions[perm]), perm))
    return out


def invariance(case: Case, coverage: Coverage, variants: list[tuple[str, NDArray, Coverage]],
               shift: tuple[int, int] | None = None, tolerance: Tolerance = Tolerance(),
               sample: tuple[float, float] = (0.5, 0.5), convention: Convention | None = None,
               own: tuple[Coverage, list[tuple[str, NDArray, Coverage]]] | None = None,
               rounding: Convention | None = None) -> Result:
    """Each variant's coverage, mapped back (triangle ids, shift), equals the original's.
    Differences at near ties are excused on non-lattice cases in default mode.

    Parameters
    ----------
    variants : list of (name, triangle index map, coverage of the variant)
    shift : (int, int) or None
        The ``translate`` variant's shift (None: :func:`shift_of` the scene).
    sample : (float, float)
        Where near ties are measured, without a ``convention``.
    convention : Convention or None
        The rasterizer's, when it declares one: near ties under its rule (for lines, its
        line rule; without one, the least distance under any rule).
    own : (Coverage, variants) or None
        The declared rule's exact answer for the scene and for each variant, when the rule
        itself is not invariant (the closed rule's crossings stepped from each edge's
        start: a reversed winding or a clip at the viewport's edge moves them): the
        differences the rule's own answers have are excused (``rule_own``).
    rounding : Convention or None
        The rasterizer's, when it declares one that moves vertices (snapping, an input grid):
        the pixels its own exact coverage changes under the ``translate`` variant are its rule,
        not a change (a rounding whose ties go one way on one side of a point and the other
        way beyond it is not translation invariant there: half away from zero at 0, piglit's
        half away from the pixel centre at 1/2).
    """
    scene = case.scene
    shift = shift_of(scene) if shift is None else shift
    judge = convention if convention is not None else (None if kind_of(scene).near_ties_by_own_rule
                                                       else Convention(sample=sample))
    diffs: dict[str, int] = {}
    evidence: dict[str, Any] = {}
    rule_own = 0
    own_variants = {name: (index, cov) for name, index, cov in own[1]} if own is not None else {}
    for name, index, cov in variants:
        both = _changed(name, index, cov, coverage, scene, shift)
        if name in own_variants and both.shape[1] and own is not None:
            theirs = _changed(name, *own_variants[name], own[0], scene, shift)
            excused = {tuple(c) for c in theirs.T.tolist()}
            mine = np.array([tuple(c) not in excused for c in both.T.tolist()], dtype=bool)
            rule_own += int((~mine).sum())
            both = both[:, mine]
        if name == "translate" and rounding is not None and both.shape[1]:
            both = both[:, ~_moved_by_rounding(scene, shift, rounding, both)]
        if both.shape[1] and tolerance.mode == "default" and not case.lattice:
            near, _ = near_ties_of(scene, judge, both, tolerance)
            both = both[:, ~near]  # excused: rounding at a near tie
        if both.shape[1]:
            diffs[name] = int(both.shape[1])
            evidence[name] = both.T[:EVIDENCE_LIMIT].tolist()
    metrics = {f"{name}_differences": float(diffs.get(name, 0)) for name, _, _ in variants}
    if own is not None:
        metrics["rule_own"] = float(rule_own)
    message = "unchanged under " + ", ".join(n for n, _, _ in variants) if not diffs \
        else "changed under " + ", ".join(f"{k} ({v} pixels)" for k, v in diffs.items())
    if rule_own:
        message += f"; {rule_own} changes excused: the rule's own (its exact answers change there too)"
    return result(case.id, "invariance", not diffs, message, metrics, evidence)


def _changed(name: str, index: NDArray, cov: Coverage, coverage: Coverage, scene: Any,
             shift: tuple[int, int]) -> NDArray:
    """The variant's coverage mapped back (triangle ids, shift) against ``coverage``: the
    missing then extra (t, x, y) columns."""
    if _unchanged_spans(name, index, cov, coverage, scene, shift):  # the usual answer: no pixel work
        return np.zeros((3, 0), dtype=np.int64)
    t, x, y = cov.pixels()
    keep = (t >= 0) & (t < index.size)
    t, x, y = index[t[keep]], x[keep], y[keep]
    if name == "translate":
        x, y = x - shift[0], y - shift[1]
        window = (x >= 0) & (y >= 0) & (x < scene.width) & (y < scene.height)
        t, x, y = t[window], x[window], y[window]
    mapped = Coverage.from_pixels(t, x, y)
    missing, extra = deviations(mapped, coverage, scene.width, scene.height)
    both: NDArray = np.concatenate([missing, extra], axis=1)
    return both


def _unchanged_spans(name: str, index: NDArray, cov: Coverage, coverage: Coverage, scene: Any,
                     shift: tuple[int, int]) -> bool:
    """True when the variant's spans, mapped back span by span as :func:`_changed` maps its
    pixels (triangle ids; the shift, cut to the viewport), are ``coverage``'s, both in
    canonical form (:func:`harness.checks.fragments.same_canonical_spans`): nothing changed.
    False says only "compare pixel by pixel"."""
    t = cov.primitive
    if t.size and (int(t.min()) < 0 or int(t.max()) >= index.size):
        return False
    t, y, x0, x1 = index[t], cov.y, cov.x0, cov.x1
    if name == "translate":
        y, x0, x1 = y - shift[1], np.maximum(x0 - shift[0], 0), np.minimum(x1 - shift[0], scene.width)
        inside = (y >= 0) & (y < scene.height) & (x0 < x1)
        t, y, x0, x1 = t[inside], y[inside], x0[inside], x1[inside]
    order = np.argsort(t, kind="stable")  # a permutation's spans back in triangle order, each's rows as drawn
    return bool(same_canonical_spans(t[order], y[order], x0[order], x1[order], coverage.primitive, coverage.y,
                                     coverage.x0, coverage.x1, scene.width, scene.height) == 1)


def _moved_by_rounding(scene: AnyScene, shift: tuple[int, int], rounding: Convention, pixels: NDArray) -> NDArray:
    """Which of ``pixels`` ((3, N): triangle, x, y) the exact coverage under ``rounding``
    itself changes when the scene is translated by ``shift`` (mapped back)."""
    moved = scene.with_coordinates(scene.coordinates + np.array(shift, dtype=float))
    t, x, y = exact_coverage(moved.with_viewport(scene.width + shift[0], scene.height + shift[1]), rounding).pixels()
    x, y = x - shift[0], y - shift[1]
    window = (x >= 0) & (y >= 0) & (x < scene.width) & (y < scene.height)
    back = Coverage.from_pixels(t[window], x[window], y[window])
    missing, extra = deviations(back, exact_coverage(scene, rounding), scene.width, scene.height)
    own = np.concatenate([missing, extra], axis=1)
    key = (pixels[0] * scene.height + pixels[2]) * scene.width + pixels[1]
    own_key = (own[0] * scene.height + own[2]) * scene.width + own[1]
    moved_by_rule: NDArray = np.isin(key, own_key)
    return moved_by_rule


def _alpha_map(coverage: Coverage, index: NDArray | None, shift: tuple[int, int], width: int,
               height: int) -> tuple[NDArray, NDArray]:
    """Sorted (triangle, y, x) keys of the pixels with nonzero alpha, mapped back through
    ``index`` and ``shift``, and their alphas (a pixel listed twice: the sum)."""
    t, x, y = coverage.pixels()
    alpha = coverage.alpha if coverage.alpha is not None and coverage.alpha.size == t.size else np.zeros(t.size)
    if index is not None:
        keep = (t >= 0) & (t < index.size)
        t, x, y, alpha = index[t[keep]], x[keep], y[keep], alpha[keep]
    x, y = x - shift[0], y - shift[1]
    window = (x >= 0) & (y >= 0) & (x < width) & (y < height) & (t >= 0) & (alpha != 0)
    keys, where = np.unique((t[window] * height + y[window]) * width + x[window], return_inverse=True)
    return keys, np.bincount(where, weights=alpha[window], minlength=keys.size)


def near_level_boundary(case: Case, oracle: Coverage, convention: Convention,
                        tolerance: Tolerance = Tolerance()) -> Callable[[NDArray], NDArray]:
    """Which (primitive, pixel) keys ``(p * H + y) * W + x`` float rounding may tip from one
    level to the next: those whose model value lies within reach of a multiple of half a
    level (a rounding boundary to nearest, or of a floor or ceiling). The reach is the
    oracle's proven bound (below 2**-24 for triangles and paths: :mod:`harness.oracle.area`,
    :mod:`harness.oracle.path_area`; a line's own, :func:`harness.oracle.area_lines.line_model_bound`)
    plus how far the area moves when the geometry moves by what conformance calls rounding
    (``tolerance.near_tie`` relative to max(1, largest |coordinate|), at most
    ``tolerance.near_tie_pixels``): :func:`harness.checks.area_paths.displaced_path_bound`
    of the primitive's edges (a stroke's boundary counted as 8 edges: two sides, and two
    caps of at most three edges' length each). On a lattice case or in strict mode only
    values on a boundary itself, within the oracle's bound (accuracy lets an area exactly
    halfway between two levels round to either way)."""
    from harness.checks.area_levels import _keyed
    from harness.checks.area_paths import displaced_path_bound
    from harness.kinds import LINES

    scene = case.scene
    width, height, n = scene.width, scene.height, len(scene)
    # on a lattice case or in strict mode only a model value on a rounding boundary itself
    # (within the oracle's bound): an area exactly halfway between two levels may round to
    # either, as accuracy allows; no geometry moved by rounding
    displaced = not case.lattice and tolerance.mode == "default"
    model_keys, model = _keyed(oracle, width, height, n)
    coordinates = convention.snap(np.asarray(scene.coordinates, dtype=np.float64))
    finite = np.where(np.isfinite(coordinates), np.abs(coordinates), 0.0)
    if isinstance(scene, PathScene):
        owner = np.repeat(scene.contour_path, scene.contour_sizes)
        edges = np.bincount(owner, minlength=n).astype(np.int64)
        magnitude = np.ones(n)
        np.maximum.at(magnitude, owner, finite.max(axis=1) if finite.size else np.zeros(0))
        oracle_bound = np.full(n, 2.0**-24)
    elif LINES.owns(scene):
        a, b = scene.segments()
        magnitude = np.maximum(1.0, np.maximum(np.abs(np.nan_to_num(a)).max(axis=1, initial=0.0),
                                               np.abs(np.nan_to_num(b)).max(axis=1, initial=0.0)))
        edges = np.full(n, 8, dtype=np.int64)
        from harness.oracle.area_lines import line_model_bound

        oracle_bound = np.maximum(line_model_bound(scene, convention), 2.0**-24)
    else:
        per = finite.reshape(n, -1)
        magnitude = np.maximum(1.0, per.max(axis=1, initial=0.0))
        edges = np.full(n, 3, dtype=np.int64)
        oracle_bound = np.full(n, 2.0**-24)
    reach = np.minimum(tolerance.near_tie * magnitude, tolerance.near_tie_pixels) if displaced else np.zeros(n)
    slack = oracle_bound + displaced_path_bound(edges, reach) + 2.0**-40
    half = 1.0 / (2 * (convention.levels - 1))

    def near(keys: NDArray) -> NDArray:
        where = np.searchsorted(model_keys, keys)
        value = np.zeros(keys.size)
        found = where < model_keys.size
        found[found] = model_keys[where[found]] == keys[found]
        value[found] = model[where[found]]
        prim = np.clip(keys // (width * height), 0, max(n - 1, 0))
        distance = np.abs(value - np.rint(value / half) * half)
        out: NDArray = distance <= slack[prim] if n else np.zeros(keys.size, dtype=bool)
        return out

    return near


def area_invariance(case: Case, coverage: Coverage, variants: list[tuple[str, NDArray, Coverage]], level_step: float,
                    shift: tuple[int, int] = (3, 2), exact: frozenset[str] = frozenset(),
                    near: Callable[[NDArray], NDArray] | None = None) -> Result:
    """Area coverage: each variant's alphas, mapped back (triangle ids, shift), equal the
    original's within one level (a rounding that lands on the other side of a level's
    midpoint is no change of method); a larger difference is a change. The variants named
    in ``exact`` (the same scene up to orientation, :data:`ORIENTATION_VARIANTS`) must
    give the same alphas exactly: a one-level difference there is a change too, but where
    ``near`` says float rounding may tip the level (:func:`near_level_boundary`; counted
    as ``near_ties``).

    Parameters
    ----------
    variants : list of (name, triangle index map, coverage of the variant)
    level_step : float
        The declared alpha quantum 1/(levels - 1).
    exact : frozenset of str
        The variants judged exactly.
    near : callable or None
        Keys ``(p * H + y) * W + x`` -> bool: a one-level difference excused there.
    """
    scene = case.scene
    keys, alpha = _alpha_map(coverage, None, (0, 0), scene.width, scene.height)
    near_ties = 0
    diffs: dict[str, int] = {}
    evidence: dict[str, Any] = {}
    for name, index, cov in variants:
        moved = shift if name == "translate" else (0, 0)
        other_keys, other_alpha = _alpha_map(cov, index, moved, scene.width, scene.height)
        union = np.union1d(keys, other_keys)
        a = np.zeros(union.size)
        b = np.zeros(union.size)
        a[np.searchsorted(union, keys)] = alpha
        b[np.searchsorted(union, other_keys)] = other_alpha
        # compared in whole levels: k/255 - (k-1)/255 need not be <= 1/255 in floats
        with np.errstate(invalid="ignore"):
            steps = np.abs(np.rint(a / level_step) - np.rint(b / level_step))
        allowed = 0 if name in exact else 1
        changed = np.flatnonzero(~(steps <= allowed))  # NaN counts as a change
        if allowed == 0 and near is not None and changed.size:
            one = changed[steps[changed] == 1]
            excused = one[near(union[one])]
            near_ties += int(excused.size)
            changed = np.setdiff1d(changed, excused)
        if changed.size:
            diffs[name] = int(changed.size)
            k = union[changed[:EVIDENCE_LIMIT]]
            evidence[name] = [[int(key // (scene.width * scene.height)), int(key % scene.width),
                               int(key // scene.width % scene.height), float(u), float(v)]
                              for key, u, v in zip(k, a[changed[:EVIDENCE_LIMIT]], b[changed[:EVIDENCE_LIMIT]])]
    metrics = {f"{name}_differences": float(diffs.get(name, 0)) for name, _, _ in variants}
    judged_exactly = [n for n, _, _ in variants if n in exact]
    if judged_exactly:
        metrics["near_ties"] = float(near_ties)
    message = ("alphas unchanged (within one level) under " + ", ".join(n for n, _, _ in variants) if not diffs else
               "alphas changed under " + ", ".join(f"{k} ({v} pixels)" for k, v in diffs.items()))
    if judged_exactly:
        message += f" (exactly under {', '.join(judged_exactly)}" + (
            f"; {near_ties} one-level differences at near ties: float rounding)" if near_ties else ")")
    if diffs:
        evidence["columns"] = ["triangle", "x", "y", "alpha", "alpha of the variant"]
    return result(case.id, "invariance", not diffs, message, metrics, evidence)


def _unanswered(s: Subject, outcome: Any) -> Result:
    """The error result of a variant the rasterizer did not answer."""
    kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
    return Result("", s.case.id, "invariance", "error", f"{kind}: {outcome.error}",
                  {"seconds": outcome.seconds}, {"traceback": outcome.traceback})


def _drawn_variants(case: Case, convention: Convention | None) -> list[tuple[str, AnyScene, NDArray]]:
    """The variants the check hands the rasterizer (:func:`invariance_variants`, and a
    stroke's reversed segments under area coverage)."""
    drawn = list(invariance_variants(case))
    if convention is not None and convention.model.alphas and isinstance(case.scene, LineScene):
        drawn += area_line_variants(case.scene)  # a stroke's area does not depend on its direction
    return drawn


def _run(s: Subject) -> Result:
    variants = []
    for label, scene, index in _drawn_variants(s.case, s.convention):
        outcome = s.call(scene)
        if outcome.coverage is None:
            return _unanswered(s, outcome)
        variants.append((label, index, outcome.coverage))
    if s.convention is not None and s.convention.model.alphas:
        built: list[Callable[[NDArray], NDArray]] = []

        def near(keys: NDArray) -> NDArray:
            """:func:`near_level_boundary`, built (the oracle drawn) only when a difference needs it."""
            assert s.convention is not None
            if not built:
                built.append(near_level_boundary(s.case, s.oracle, s.convention, s.tolerance))
            return built[0](keys)

        return area_invariance(s.case, s.coverage, variants, s.convention.level_step, shift_of(s.case.scene),
                               exact=ORIENTATION_VARIANTS, near=near)
    sample = s.convention.sample if s.convention is not None else (0.5, 0.5)
    # judged by the rasterizer's convention where the kind's near ties need its rule (lines)
    own = kind_of(s.case.scene).near_ties_by_own_rule
    rule = None
    if s.convention is not None and s.convention.model.rule and s.convention.dropout != "none":
        # the closed rule's scan conversion is not invariant itself (crossings stepped from each edge's start)
        from harness.oracle.coverage import exact_coverage

        rule = (s.oracle, [(label, index, exact_coverage(scene, s.convention))
                           for label, scene, index in invariance_variants(s.case)])
    # a declared rounding's own changes under translation are its rule (half-away at 0, piglit's at 1/2)
    rounding = s.convention if s.convention is not None and s.convention.quantizes else None
    return invariance(s.case, s.coverage, variants, tolerance=s.tolerance, sample=sample,
                      convention=s.convention if own else None, own=rule, rounding=rounding)


def _applies(case: Any) -> bool:
    if hasattr(case, "frames"):
        return False
    families = kind_of(case.scene).invariance_families
    return families is None or case.family in families


register(Check(
    "invariance", _run, _applies, shrinks=True, coverage_kinds=ALL_COVERAGE_KINDS,
    caption="vertex rotation, winding flip, triangle permutation and whole-pixel translation change nothing but the shift "
            "(paths: start vertex, contour reversal and order, path order; lines: strip order, strips split)",
    classifier="harness.diagnose.signatures:classify_invariance", cause_role="consequent", motion_role="none", figures=(),
    plans=lambda case, convention: [scene for _, scene, _ in _drawn_variants(case, convention)],
))
