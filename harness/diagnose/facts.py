"""Exact facts about a failure's wrong samples, for its signature
(:mod:`harness.diagnose.signatures`): each primitive's coordinates and magnitude (its
kind's), where a wrong sample lies against its primitive's edges (exactly on one, and
which way it runs; within float rounding; near the screen's edge), which primitives
snapping leaves flat, and the hypotheses worth an oracle call on the wrong primitives
alone (another snapping rounding, the kind's own: the other fill rule, a dropped contour,
the other end pixel, reversal). Decided by the exact predicates and float comparisons of
end points, never an epsilon; measures that are tolerances by nature say so in their
names. None of these calls the rasterizer again (that is :mod:`harness.diagnose.trials`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import SNAP_ROUNDINGS, Convention, SnapRounding
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.geometry.exact import orientation
from harness.geometry.keys import unique
from harness.kinds import LINES, TRIANGLES, kind_of

__all__ = ["NEAR_PIXELS", "CLIPPER_PIXELS", "NEAR_EDGE_PIXELS", "FLOAT32_EDGE_ROUNDING", "answer_of", "judged_convention",
           "primitive_coordinates", "magnitude_of", "edge_facts", "wrong_pixels", "open_outline", "hypothesis_class",
           "flat_primitives", "on_flat_line", "dropped_near_edges", "wrong_reach_beyond", "edges_of", "ties_right_inside",
           "dropped_class", "segment_direction"]

# near-tie: |E| within float32 rounding of the edge function (about 2**-19 M**2 for an
# evaluation in float32 from float32 inputs; four times that), and at most 2**-8 px away
FLOAT32_EDGE_ROUNDING = 2.0**-17
NEAR_PIXELS = 2.0**-8
# viewport-edge: a wrong sample off every edge counts as a clipper's when it lies within
# this of an edge leaving the screen (a clipped vertex rounded to a coarse grid)
CLIPPER_PIXELS = 2.0**-4
# dropped-near-edges: a multisample layer's missing samples all this close to an edge of
# their triangle (a pixel's reach: a tolerance by nature, named as one)
NEAR_EDGE_PIXELS = 1.0


def judged_convention(result: Any, convention: Convention | None) -> Convention:
    """The single-sample convention the failing samples were judged by: the drawing's
    (a multisample result's worst layer), else the evidence's sample of ``convention``,
    else ``convention``, else the default."""
    drawing = getattr(result, "drawing", None)
    judged = getattr(drawing, "convention", None)
    if isinstance(judged, Convention) and judged.model.single_sample:
        return judged
    if isinstance(convention, Convention):
        index = result.evidence.get("sample") if isinstance(result.evidence, dict) else None
        if convention.model.sample_ids and isinstance(index, int) and 0 <= index < convention.n_samples:
            return convention.at_sample(index)
        if convention.model.single_sample or convention.model.rule:  # a coverage rule: one answer per pixel, kept
            return convention
        return convention.point_sampled()
    return Convention()


def answer_of(result: Any) -> Coverage | None:
    """The rasterizer's (tidied) answer on the still case, when the result carries it."""
    drawing = getattr(result, "drawing", None)
    coverages = getattr(drawing, "coverages", None)
    if coverages and isinstance(coverages[0], Coverage):
        return coverages[0]
    return None


def primitive_coordinates(scene: AnyScene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    """Each primitive's coordinates, (K, 2) each (a path's every contour together)."""
    return kind_of(scene).coordinates_of(scene, prims)


def magnitude_of(coordinates: list[NDArray[np.float64]]) -> float:
    """max(1, largest finite |coordinate|) of the primitives."""
    biggest = 1.0
    for c in coordinates:
        finite = np.abs(c[np.isfinite(c)])
        if finite.size:
            biggest = max(biggest, float(finite.max()))
    return biggest


def _direction(a: NDArray, b: NDArray) -> str:
    """horizontal, vertical or slanted, of the edge a -> b (float comparisons: exact)."""
    if a[1] == b[1]:
        return "horizontal"
    if a[0] == b[0]:
        return "vertical"
    return "slanted"


@dataclass
class _Sample:
    """What is known about one wrong sample."""

    tie: str | None  # "vertex", "horizontal", "vertical", "slanted" (exactly on it), else None
    near: bool  # within float rounding of an edge (and not exactly on one)
    border: bool  # the edge it lies on (or, beyond float rounding, within CLIPPER_PIXELS of) leaves the viewport


def edge_facts(edges_a: NDArray, edges_b: NDArray, sample: NDArray, magnitude: float, width: int, height: int) -> _Sample:
    """Position of ``sample`` against edges a -> b ((E, 2) each): exactly on a vertex or on
    an edge (closed; the exact orientation and float comparisons), or within float32
    rounding of one (a tolerance, named as one); and whether the edges it lies on -- or,
    off every edge and beyond float rounding, the nearest when within
    :data:`CLIPPER_PIXELS` -- reach beyond the viewport [0, width] x [0, height]."""
    if edges_a.shape[0] == 0 or not np.isfinite(sample).all():
        return _Sample(None, False, False)
    with np.errstate(invalid="ignore"):
        outside = ((np.minimum(edges_a, edges_b) < 0).any(axis=1) | (np.maximum(edges_a[:, 0], edges_b[:, 0]) > width)
                   | (np.maximum(edges_a[:, 1], edges_b[:, 1]) > height))
    at_vertex = np.all(edges_a == sample, axis=1) | np.all(edges_b == sample, axis=1)
    if at_vertex.any():
        return _Sample("vertex", False, bool(outside[at_vertex].all()))
    triple = np.stack([edges_a, edges_b, np.broadcast_to(sample, edges_a.shape)], axis=1)
    on_line = orientation(triple) == 0
    lo, hi = np.minimum(edges_a, edges_b), np.maximum(edges_a, edges_b)
    within = np.all((lo <= sample) & (sample <= hi), axis=1)
    on_edge = np.flatnonzero(on_line & within & np.any(edges_a != edges_b, axis=1))
    if on_edge.size:
        kinds = {_direction(edges_a[k], edges_b[k]) for k in on_edge}
        kind = next(k for k in ("slanted", "vertical", "horizontal") if k in kinds)
        return _Sample(kind, False, bool(outside[on_edge].all()))
    with np.errstate(all="ignore"):
        d = edges_b - edges_a
        e = d[:, 0] * (sample[1] - edges_a[:, 1]) - d[:, 1] * (sample[0] - edges_a[:, 0])
        length = np.hypot(d[:, 0], d[:, 1])
        m = max(magnitude, float(np.abs(sample).max()), 1.0)
        close = (np.abs(e) <= FLOAT32_EDGE_ROUNDING * m * m) & (np.abs(e) <= NEAR_PIXELS * length) & (length > 0)
        distance = np.where(length > 0, np.abs(e) / length, np.inf)
    distance = np.where(np.isnan(distance), np.inf, distance)
    nearest = int(np.argmin(distance))
    close &= np.isfinite(e)
    violated = _violated_edges(edges_a, edges_b, sample)
    if violated.any():
        # outside a triangle, rounding takes it in only if it rounds every edge it lies
        # outside of (one on an edge's extension past a vertex lies clearly outside another)
        near = bool(close[violated].all())
    else:  # inside, or a path: near an edge itself, not its line past its ends
        with np.errstate(all="ignore"):
            along = d[:, 0] * (sample[0] - edges_a[:, 0]) + d[:, 1] * (sample[1] - edges_a[:, 1])
            past = np.maximum(0.0, np.maximum(-along, along - length * length))  # beyond an end, times the length
        near = bool(np.any(close & (past <= NEAR_PIXELS * length)))
    # a clipper's error: beyond float rounding, yet close to an edge that leaves the screen
    border = not near and bool(outside[nearest]) and bool(distance[nearest] <= CLIPPER_PIXELS)
    return _Sample(None, near, border)


def _violated_edges(edges_a: NDArray, edges_b: NDArray, sample: NDArray) -> NDArray[np.bool_]:
    """(E,) bool: for a triangle's three edges a -> b (closed, nonzero area), those the
    sample lies strictly outside of (exact orientations); all False for anything else."""
    none = np.zeros(edges_a.shape[0], dtype=bool)
    if edges_a.shape[0] != 3 or not np.isfinite(edges_a).all() \
            or not (np.array_equal(edges_b[:2], edges_a[1:]) and np.array_equal(edges_b[2], edges_a[0])):
        return none
    winding = int(orientation(np.stack([edges_a[0], edges_a[1], edges_a[2]])[None])[0])
    if winding == 0:
        return none
    sides = orientation(np.stack([edges_a, edges_b, np.broadcast_to(sample, edges_a.shape)], axis=1))
    violated: NDArray[np.bool_] = sides == -winding
    return violated


def wrong_pixels(result: Any, noun: str, n: int) -> list[tuple[int, int, int, str, float]]:
    """(primitive, x, y, kind, distance) of the wrong deviations the evidence lists (all
    listed ones when none is marked wrong: strict mode)."""
    listed = result.evidence.get("pixels") if isinstance(result.evidence, dict) else None
    if not isinstance(listed, list):
        return []
    rows = [p for p in listed if isinstance(p, dict) and isinstance(p.get(noun), int) and 0 <= p[noun] < n]
    wrong = [p for p in rows if not p.get("near_tie")] or rows
    return [(int(p[noun]), int(p["x"]), int(p["y"]), str(p.get("kind", "")), float(p.get("distance", math.inf))) for p in wrong]


def _pixel_set(coverage: Coverage, prims: NDArray[np.int64], remap: dict[int, int], width: int,
               height: int) -> set[tuple[int, int, int]]:
    """(remapped primitive, x, y) of the coverage's fragments of ``prims`` in the viewport."""
    t, x, y = coverage.pixels()
    keep = np.isin(t, prims) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    t, x, y = t[keep], x[keep], y[keep]
    distinct = unique(t)  # remapped once each, then by lookup (a Python int per fragment was the cost)
    index = np.array([remap[v] for v in distinct.tolist()], dtype=np.int64)
    mapped = index[np.searchsorted(distinct, t)]
    return set(zip(mapped.tolist(), x.tolist(), y.tolist()))


def _same_as(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], variant: AnyScene, convention: Convention) -> bool:
    """Whether the answer's fragments of ``prims`` are exactly the oracle's of ``variant``
    (the subset scene of ``prims``, changed) under ``convention``: one oracle call."""
    from harness.oracle.coverage import exact_coverage

    remap = {int(k): i for i, k in enumerate(prims)}
    want = exact_coverage(variant, convention)
    got = _pixel_set(answer, prims, remap, scene.width, scene.height)
    expected = _pixel_set(want, np.arange(len(prims)), {i: i for i in range(len(prims))}, scene.width, scene.height)
    return got == expected


def open_outline(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], convention: Convention,
                  unlike: Callable[[set[tuple[int, int, int]]], set[tuple[int, int, int]]] | None = None) -> bool:
    """Whether the answer's fragments of ``prims`` -- some at least -- are exactly what a
    filler draws that leaves every contour open (:func:`harness.oracle.winding.open_outline_coverage`,
    under either rule for the rows that then stay inside), and not what another explanation
    draws: ``unlike`` gives that from the oracle's fragments of ``prims`` (as
    (index in ``prims``, x, y)), e.g. a culler's. Two oracle calls, a third for ``unlike``;
    single-sample triangles without culling, and paths."""
    from harness.oracle.coverage import exact_coverage
    from harness.oracle.winding import UNBALANCED_ROWS, open_outline_coverage

    # single-sample triangles without culling, and paths: a line has no outline to leave open
    if not convention.model.single_sample or (TRIANGLES.owns(scene) and convention.cull != "none") \
            or LINES.owns(scene) or not prims.size:
        return False
    subset = scene.subset(prims)
    if not np.isfinite(subset.coordinates).all():
        return False
    remap = {int(k): i for i, k in enumerate(prims)}
    identity = {i: i for i in range(len(prims))}
    got = _pixel_set(answer, prims, remap, scene.width, scene.height)
    if not got:
        return False  # dropped whole: no evidence
    for rule in UNBALANCED_ROWS:
        try:
            predicted = _pixel_set(open_outline_coverage(subset, convention, rule), np.arange(len(prims)), identity,
                                   scene.width, scene.height)
        except ValueError:  # a convention or scene it does not take
            return False
        if predicted == got:
            return unlike is None or got != unlike(_pixel_set(exact_coverage(subset, convention), np.arange(len(prims)),
                                                              identity, scene.width, scene.height))
    return False


def hypothesis_class(result: Any, scene: AnyScene, prims: NDArray[np.int64], convention: Convention,
                near: bool, exact: bool) -> tuple[str, str] | None:
    """The alternatives worth an oracle call, tested on the wrong primitives alone: the
    other roundings of the convention's snapping that move a vertex (when it snaps: the
    fewest moved first, each tried -- exact halves move under half-away as under no other,
    and floor may move fewer), the other fill rule (paths wrong away from their edges), or
    the other last-pixel choice or direction (lines wrong within rounding of the rule's
    boundary)."""
    answer = answer_of(result)
    if answer is None or not prims.size:
        return None
    subset = scene.subset(prims)
    coordinates = subset.coordinates
    if not np.isfinite(coordinates).all():
        return None
    if convention.subpixel_bits is not None:
        declared = convention.snap(coordinates)
        others: list[tuple[int, SnapRounding]] = []
        for rounding in SNAP_ROUNDINGS:
            if rounding == convention.snap_rounding:
                continue
            moved = int(np.sum(replace(convention, snap_rounding=rounding).snap(coordinates) != declared))
            if moved:
                others.append((moved, rounding))
        for _, rounding in sorted(others):
            if _same_as(answer, scene, prims, subset, replace(convention, snap_rounding=rounding)):
                return "snapping", "snapping"
    own: tuple[str, str] | None = kind_of(scene).hook("hypotheses")(answer, scene, prims, subset, convention, near, exact)
    return own


def no_hypothesis(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: AnyScene, convention: Convention,
                  near: bool, exact: bool) -> tuple[str, str] | None:
    """A kind's ``hypotheses`` hook when it has none beyond snapping (triangles)."""
    return None


def path_hypotheses(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: PathScene, convention: Convention,
                    near: bool, exact: bool) -> tuple[str, str] | None:
    """The paths' ``hypotheses`` hook: wrong away from their edges, the other fill rule or
    a contour dropped (:func:`_contours_hypothesis`)."""
    if near or exact:
        return None
    flipped = subset.with_fill_rule("evenodd" if subset.fill_rule == "nonzero" else "nonzero")
    if _same_as(answer, scene, prims, flipped, convention):
        return "fill-rule", "fill-rule"
    return _contours_hypothesis(answer, scene, prims, subset, convention)


def line_hypotheses(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: LineScene, convention: Convention,
                    near: bool, exact: bool) -> tuple[str, str] | None:
    """The lines' ``hypotheses`` hook (unsnapped lines): a decision near the rule's
    boundary drawn exactly as the rule draws it with the other last-pixel choice, or each
    segment drawn the other way: that choice, not rounding."""
    line = convention.line
    if convention.subpixel_bits is not None or not near or line is None:
        return None
    if isinstance(line.last_pixel, bool) and _same_as(answer, scene, prims, subset,
                                                      replace(convention, line=replace(line, last_pixel=not line.last_pixel))):
        return "end-pixel", "line-rule"
    if _same_reversed(answer, scene, prims, subset, convention):
        return "reversal", "line-rule"
    return None


def _contours_hypothesis(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: PathScene,
                         convention: Convention) -> tuple[str, str] | None:
    """Paths of several contours wrong away from their edges, drawn exactly as the oracle
    draws each one's first contour alone (``later-contours-dropped``), or each contour
    filled on its own, their union (``holes-ignored``) -- when the two differ (a hole
    filled within the first contour is either, or a fill counting crossings unsigned:
    none is named); else None. Two oracle calls, only for paths of several contours."""
    from harness.oracle.coverage import exact_coverage

    sizes = subset.contour_sizes
    if not (np.bincount(subset.contour_path, minlength=len(subset)) > 1).any():
        return None
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    first = np.flatnonzero(np.concatenate([[True], subset.contour_path[1:] != subset.contour_path[:-1]]))
    keep = np.concatenate([np.arange(starts[c], starts[c] + sizes[c]) for c in first])
    alone = PathScene(scene.width, scene.height, subset.vertices[keep], sizes[first], subset.contour_path[first],
                      subset.fill_rule)
    each = PathScene(scene.width, scene.height, subset.vertices, sizes, np.arange(sizes.size), subset.fill_rule)
    identity = {i: i for i in range(len(subset))}
    firsts = _pixel_set(exact_coverage(alone, convention), np.arange(len(subset)), identity, scene.width, scene.height)
    t, x, y = exact_coverage(each, convention).pixels()
    on = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
    union = set(zip(subset.contour_path[t[on]].tolist(), x[on].tolist(), y[on].tolist()))
    if firsts == union:
        return None  # every later contour within the first (a hole filled): the two cannot be told apart
    got = _pixel_set(answer, prims, {int(k): i for i, k in enumerate(prims)}, scene.width, scene.height)
    if got == firsts:
        return "later-contours-dropped", "none"
    if got == union:
        return "holes-ignored", "fill-rule"
    return None


def _same_reversed(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: LineScene,
                   convention: Convention) -> bool:
    """Whether the answer's fragments of segments ``prims`` are exactly the oracle's of
    ``subset`` (those segments) with every strip drawn backwards: one oracle call."""
    from harness.oracle.coverage import exact_coverage

    backwards, origin = subset.reversed()
    t, x, y = exact_coverage(backwards, convention).pixels()
    keep = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
    expected = set(zip(np.asarray(origin)[t[keep]].tolist(), x[keep].tolist(), y[keep].tolist()))
    remap = {int(k): i for i, k in enumerate(prims)}
    return _pixel_set(answer, prims, remap, scene.width, scene.height) == expected


def flat_primitives(scene: Any, prims: NDArray[np.int64], snapped: dict[int, NDArray[np.float64]]) -> set[int]:
    """The primitives of ``prims`` that snapping leaves without area (a triangle of zero
    orientation, a segment of zero length); none for paths."""
    return kind_of(scene).degenerate(scene, {int(k): snapped[int(k)] for k in prims})


def dropped_near_edges(wrong: list[tuple[int, int, int, str, float]], edges: dict[int, tuple[NDArray, NDArray]],
                        judged: Convention) -> bool:
    """Whether every wrong sample of a multisample layer is missing (none extra), lies
    within :data:`NEAR_EDGE_PIXELS` of an edge of its triangle, and its pixel's centre
    strictly outside the triangle (exact orientations): samples dropped where a pixel
    was rejected whole near an edge, not a pattern read wrong (which puts samples in where
    it leaves others out)."""
    if not wrong or any(kind != "missing" for _, _, _, kind, _ in wrong):
        return False
    for k, x, y, _, _ in wrong:
        a, b = edges[k]
        centre = np.array([x + 0.5, y + 0.5])
        if not _violated_edges(a, b, centre).any():
            return False
        sample = np.array([x + judged.sample[0], y + judged.sample[1]])
        with np.errstate(all="ignore"):
            d = b - a
            t = np.clip(((sample - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
            reach = np.hypot(*(a + t[:, None] * d - sample).T)
        if not (reach <= NEAR_EDGE_PIXELS).any():
            return False
    return True


def wrong_reach_beyond(result: Any, scene: AnyScene) -> bool:
    """Whether every primitive with a wrong sample reaches beyond the screen [0, width] x
    [0, height] (or has a coordinate that is not finite): only those meet its edge."""
    wrong = wrong_pixels(result, scene.noun, len(scene))
    prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
    for c in primitive_coordinates(scene, prims):
        with np.errstate(invalid="ignore"):
            inside = np.isfinite(c).all() and (c >= 0).all() \
                and (c[:, 0] <= scene.width).all() and (c[:, 1] <= scene.height).all()
        if inside:
            return False
    return bool(prims.size)


def edges_of(scene: AnyScene, judged: Convention) -> dict[int, tuple[NDArray, NDArray]]:
    """Each triangle's or path's edges a -> b as the convention sees them (snapped)."""
    start, end, owner = scene.edges()
    start, end = judged.snap(start), judged.snap(end)
    order = np.argsort(owner, kind="stable")
    bounds = np.searchsorted(owner[order], np.arange(len(scene) + 1))
    return {k: (start[order[bounds[k]:bounds[k + 1]]], end[order[bounds[k]:bounds[k + 1]]]) for k in range(len(scene))}


def ties_right_inside(scene: AnyScene, edges: dict[int, tuple[NDArray, NDArray]], judged: Convention, kinds: set[str],
                       wrong: list[tuple[int, int, int, str, float]]) -> bool:
    """Whether some sample exactly on an edge inside the viewport, of a kind in ``kinds``
    (an edge's direction, or ``vertex``), was decided right (is not among the wrong ones):
    then the rasterizer keeps that tie rule where no edge leaves the screen. Exact: each
    candidate sample's orientation decides."""
    sx, sy = judged.sample
    wrong_keys = {(k, x, y) for k, x, y, _, _ in wrong}
    bad = set(scene.non_finite())
    for k, (a, b) in edges.items():
        if k in bad or not a.shape[0]:
            continue
        if TRIANGLES.owns(scene) and orientation(np.stack([a[0], b[0], b[1]])[None])[0] == 0:
            continue  # zero area: covers nothing, no tie to decide
        for p, q in zip(a, b):
            if min(p[0], q[0]) < 0 or min(p[1], q[1]) < 0 or max(p[0], q[0]) > scene.width or max(p[1], q[1]) > scene.height:
                continue
            if "vertex" in kinds:
                x, y = p[0] - sx, p[1] - sy
                if x == math.floor(x) and y == math.floor(y) and (k, int(x), int(y)) not in wrong_keys \
                        and x < scene.width and y < scene.height:
                    return True
            kind = _direction(p, q)
            if kind not in kinds or np.array_equal(p, q):
                continue
            for x, y in _samples_on(p, q, sx, sy):
                if (k, x, y) not in wrong_keys and 0 <= x < scene.width and 0 <= y < scene.height:
                    return True
    return False


def _samples_on(p: NDArray, q: NDArray, sx: float, sy: float) -> list[tuple[int, int]]:
    """Pixels (x, y) whose sample (x + sx, y + sy) lies exactly inside the segment p-q (not at
    its ends): candidates from floats, each confirmed by the exact orientation."""
    if p[1] == q[1]:
        y = p[1] - sy
        if y != math.floor(y):
            return []
        lo, hi = min(p[0], q[0]), max(p[0], q[0])
        return [(x, int(y)) for x in range(math.floor(lo - sx) + 1, math.ceil(hi - sx)) if lo < x + sx < hi]
    lo, hi = min(p[1], q[1]), max(p[1], q[1])
    rows = np.arange(math.floor(lo - sy), math.ceil(hi - sy) + 1, dtype=np.float64)
    rows = rows[(rows + sy > lo) & (rows + sy < hi)]
    if not rows.size:
        return []
    with np.errstate(all="ignore"):
        x = p[0] + (rows + sy - p[1]) * (q[0] - p[0]) / (q[1] - p[1]) - sx
    columns = np.round(x)
    close = np.abs(x - columns) <= 1e-6 * max(1.0, float(np.abs(x).max(initial=0.0)))  # a screen: orientation decides
    if not close.any():
        return []
    samples = np.stack([columns[close] + sx, rows[close] + sy], axis=-1)
    on = orientation(np.stack([np.broadcast_to(p, samples.shape), np.broadcast_to(q, samples.shape), samples], axis=1)) == 0
    return [(int(c), int(r)) for c, r in zip(columns[close][on], rows[close][on])]


def dropped_class(result: Any, scene: AnyScene, prims: NDArray[np.int64], wrong: list[tuple[int, int, int, str, float]],
             snapped: dict[int, NDArray], snap_all: Callable[[Scene], NDArray], culls: bool = True) -> tuple[str, str] | None:
    """culling (unless ``culls`` is False: the dropped trial refuted it) or
    dropped-primitive when every wrong deviation is a missing fragment of a primitive the
    answer holds nothing of."""
    answer = answer_of(result)
    if answer is None or any(kind != "missing" for _, _, _, kind, _ in wrong):
        return None
    if np.isin(answer.pixels()[0], prims).any():
        return None
    if culls and TRIANGLES.owns(scene) and prims.size:
        # culling: every triangle of the wrong ones' winding missing, some of the other drawn
        signs = set(orientation(np.stack([snapped[int(k)] for k in prims])).tolist())
        every = orientation(snap_all(scene))
        drawn = np.unique(answer.pixels()[0])
        drawn = drawn[(drawn >= 0) & (drawn < len(scene))]
        if len(signs) == 1 and not np.isin(np.flatnonzero(every == signs.pop()), drawn).any() and drawn.size:
            return "culling", "culling"
    return "dropped-primitive", "none"


def segment_direction(a: NDArray, b: NDArray) -> str:
    if a[1] == b[1]:
        return "horizontal"
    if a[0] == b[0]:
        return "vertical"
    if abs(b[0] - a[0]) == abs(b[1] - a[1]):  # |dx| == |dy|: exact for floats that do not overflow
        return "diagonal"
    return "slanted"


def on_flat_line(positions: NDArray, samples: NDArray) -> NDArray[np.bool_]:
    """(M,) bool: which samples ((M, 2)) make all three edge functions of the zero-area
    triangle ``positions`` ((3, 2)) exactly 0 -- those on its line, or, for a triangle that
    is a point, every sample (its edge functions vanish everywhere). Exact."""
    spans = [(positions[i], positions[(i + 1) % 3]) for i in range(3)]
    a, b = max(spans, key=lambda e: float(np.abs(e[1] - e[0]).max()))
    if np.array_equal(a, b):
        return np.ones(samples.shape[0], dtype=bool)
    on_line: NDArray[np.bool_] = orientation(np.stack([np.broadcast_to(a, samples.shape), np.broadcast_to(b, samples.shape),
                                                       samples], axis=1)) == 0
    return on_line
