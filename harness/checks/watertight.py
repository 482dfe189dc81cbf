"""watertight and overdraw: a planar partition covers every pixel inside it exactly once,
nothing outside, and no pixel twice; convention-free -- but for snapping: snapped to a
grid, a sliver of the partition can fold over its neighbour or vanish, and the
convention's exact answer itself then has a double hit or a hole there. Such a pixel,
hit as the oracle hits it, is the convention's own and is excused (counted apart). Likewise
under a coverage rule that does not hit a partition exactly once (conservative rasterization,
an area threshold: ``CoverageModel.exactly_once`` False), whose exact answer has double hits
and holes by definition: those are the rule's own (``rule_own``)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.checks.records import EVIDENCE_LIMIT, Check, Result, register, result, skip
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene
from harness.geometry.exact import frozen, in_safe_range, orient2d_sign, orientation
from harness.kinds import kind_of

__all__ = ["watertight", "overdraw", "holes", "blame", "pixel_classes"]


def _pixel_classes(region: NDArray, width: int, height: int) -> tuple[NDArray, NDArray]:
    """(inside, outside), (H, W) bool, read-only: pixels whose closed square lies in the
    open convex region, and pixels whose closed square misses the closed region; decided
    exactly. A case's classes are worked out once per process (every rasterizer judged on
    the case asks for them again)."""
    region = np.asarray(region, dtype=np.float64)
    if width * height > 2**18:  # (kept: at most 64 viewports of 512 x 512)
        return _classes(region, width, height)
    return _classes_of(region.tobytes(), region.shape, width, height)


@functools.lru_cache(maxsize=64)
def _classes_of(data: bytes, shape: tuple[int, ...], width: int, height: int) -> tuple[NDArray, NDArray]:
    inside, outside = _classes(np.frombuffer(data, dtype=np.float64).reshape(shape), width, height)
    inside.setflags(write=False)
    outside.setflags(write=False)
    return inside, outside


@numba.njit(cache=True)
def _sides_kernel(region, width, height, area_sign):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """(M, H + 1, W + 1) int8: the exact side of every pixel corner of edge k of the region
    (its vertices within the expansions' safe range), times ``area_sign``."""
    m = region.shape[0]
    out = np.empty((m, height + 1, width + 1), dtype=np.int8)
    for k in range(m):
        ax, ay = region[k, 0], region[k, 1]
        bx, by = region[(k + 1) % m, 0], region[(k + 1) % m, 1]
        for y in range(height + 1):
            for x in range(width + 1):
                out[k, y, x] = orient2d_sign(ax, ay, bx, by, float(x), float(y)) * area_sign
    return out


def _classes(region: NDArray, width: int, height: int) -> tuple[NDArray, NDArray]:
    m = region.shape[0]
    # the outline's winding, exactly (a float shoelace overflows for huge outlines)
    turns = orientation(np.stack([region, np.roll(region, -1, axis=0), np.roll(region, -2, axis=0)], axis=1))
    area_sign = int(turns[np.flatnonzero(turns)[0]])
    # positive: the corner lies on the region's side of edge k (every edge and corner at once)
    if bool(in_safe_range(region, axis=(0, 1))):
        sides = _sides_kernel(frozen(region), width, height, area_sign)  # exact expansions, compiled
    else:  # beyond the expansions' range: the exact rationals of orientation()
        cy, cx = np.mgrid[0 : height + 1, 0 : width + 1]
        corners = np.stack([cx.ravel(), cy.ravel()], axis=-1).astype(float)
        n = corners.shape[0]
        triangles = np.empty((m, n, 3, 2))
        triangles[:, :, 0] = region[:, None, :]
        triangles[:, :, 1] = np.roll(region, -1, axis=0)[:, None, :]
        triangles[:, :, 2] = corners[None, :, :]
        side = orientation(triangles.reshape(m * n, 3, 2)).reshape(m, n) * area_sign
        sides = side.reshape(m, height + 1, width + 1)
    quads = np.stack([sides[:, :-1, :-1], sides[:, :-1, 1:], sides[:, 1:, :-1], sides[:, 1:, 1:]])
    inside = np.all(quads > 0, axis=(0, 1))
    outside = np.any(np.all(quads < 0, axis=0), axis=0)
    xs, ys = np.arange(width), np.arange(height)
    outside |= (region[:, 0].max() < xs)[None, :] | (region[:, 0].min() > xs + 1)[None, :]
    outside |= (region[:, 1].max() < ys)[:, None] | (region[:, 1].min() > ys + 1)[:, None]
    return inside, outside


def _snapping_own(counts: NDArray, oracle: Callable[[], Coverage] | None, convention: Convention | None,
                  scene: AnyScene, width: int, height: int) -> NDArray:
    """(H, W) bool: pixels hit exactly as the convention's exact answer hits them, where
    that answer is not watertight itself -- only under snapping (a folded or vanished
    sliver, or a quantizing input), or under a coverage rule that is not exactly once;
    all False otherwise. ``oracle`` is called only then."""
    if oracle is None or convention is None or (not convention.quantizes and convention.model.exactly_once):
        return np.zeros((height, width), dtype=bool)
    low, high = _allowed_counts(oracle, convention, scene, width, height)
    own: NDArray = (counts >= low) & (counts <= high) & ((low != 1) | (high != 1))
    return own


def _allowed_counts(oracle: Callable[[], Coverage], convention: Convention, scene: AnyScene, width: int,
                    height: int) -> tuple[NDArray, NDArray]:
    """(H, W) each: the fewest and the most hits the convention allows per pixel -- its
    exact answer's, or, under a conservative rule's uncertainty region, what it must and
    what it may draw (:func:`harness.oracle.coverage_rules.uncertainty_bounds`)."""
    want = oracle()
    if not (convention.model.uncertain and convention.uncertainty):
        counts = want.counts(width, height)
        return counts, counts
    from harness.oracle.coverage_rules import uncertainty_bounds

    must, may = uncertainty_bounds(kind_of(scene).narrow(scene), convention)
    return must.counts(width, height), may.counts(width, height)


def watertight(case: Case, coverage: Coverage, convention: Convention | None = None,
               oracle: Callable[[], Coverage] | None = None) -> Result:
    """On a planar partition (of triangles, or of paths: one path per cell),
    convention-free: pixels wholly inside the union hit exactly once, pixels wholly
    outside never, and no pixel twice. Each hole and double hit is blamed on an edge and
    the primitives that share it. Under a snapping ``convention``, a hole or double hit
    that its exact answer (``oracle()``, computed only then) has too is excused
    (``snapped_own``: the snapped mesh folds there)."""
    if case.region is None:
        return skip(case, "watertight", "not a planar partition")
    scene = case.scene
    counts = coverage.counts(scene.width, scene.height)
    inside, outside = _pixel_classes(case.region, scene.width, scene.height)
    empty, twice = inside & (counts == 0), counts > 1
    own = _snapping_own(counts, oracle, convention, scene, scene.width, scene.height) if (empty | twice).any() else None
    if own is not None:
        excused = (empty | twice) & own
        empty, twice = empty & ~own, twice & ~own
    holes, doubles = np.argwhere(empty), np.argwhere(twice)
    stray = outside & (counts > 0)
    if stray.any() and oracle is not None and convention is not None and not convention.model.exactly_once \
            and (convention.quantizes or convention.uncertainty):
        # a rule that draws every square the (snapped) mesh touches: snapping moves the outline by up to half a
        # grid step (an input grid by up to one step), and a square the moved mesh touches just outside the region
        # is the rule's own (as is one its uncertainty region reaches)
        low, high = _allowed_counts(oracle, convention, scene, scene.width, scene.height)
        own_stray = stray & (counts >= low) & (counts <= high)
        excused = own_stray if own is None else excused | own_stray
        own = own_stray if own is None else own | own_stray
        stray &= ~own_stray
    strays = np.argwhere(stray)
    metrics = {"holes": float(len(holes)), "double_hits": float(len(doubles)), "strays": float(len(strays)),
               "inside_pixels": float(inside.sum())}
    own_key = "snapped_own" if convention is None or convention.model.exactly_once else "rule_own"
    if own is not None and excused.any():
        metrics[own_key] = float(excused.sum())
    evidence: dict[str, Any] = {}
    if len(holes) or len(doubles):
        evidence["blame"] = blame(scene, coverage, holes[:EVIDENCE_LIMIT], doubles[:EVIDENCE_LIMIT])
    if len(strays):
        evidence["strays"] = [[int(x), int(y)] for y, x in strays[:EVIDENCE_LIMIT]]
    ok = not (len(holes) or len(doubles) or len(strays))
    message = "every inside pixel hit exactly once" if ok \
        else f"{len(holes)} holes, {len(doubles)} double hits, {len(strays)} stray hits outside"
    if "snapped_own" in metrics:
        message += (f"; {int(metrics['snapped_own'])} holes or double hits excused: the convention's own, where snapping "
                    "folds the mesh")
    if "rule_own" in metrics:
        assert convention is not None
        message += (f"; {int(metrics['rule_own'])} holes, double hits or strays excused: the rule's own "
                    f"({convention.model.declared_as(convention)})")
    if len(holes) or len(doubles):
        at_vertex = _holds_vertex(scene.coordinates, scene.width, scene.height)
        on_vertex = int(at_vertex[holes[:, 0], holes[:, 1]].sum() + at_vertex[doubles[:, 0], doubles[:, 1]].sum())
        metrics["at_vertex_pixels"] = float(on_vertex)
        if on_vertex == len(holes) + len(doubles):
            message += " (every one at a pixel holding a mesh vertex: the rule for samples on shared vertices)"
        else:
            message += f" ({on_vertex} at pixels holding a mesh vertex, the rest along edges)"
    return result(case.id, "watertight", ok, message, metrics, evidence)


def _holds_vertex(positions: NDArray, width: int, height: int) -> NDArray:
    """(H, W) bool: pixels whose closed square holds a vertex of the scene (a vertex on a
    pixel corner or side belongs to every square that touches it)."""
    grid = np.zeros((height, width), dtype=bool)
    v = positions.reshape(-1, 2)
    v = v[np.isfinite(v).all(axis=1) & (np.abs(v) < 2.0**31).all(axis=1)]
    for dx in (0, 1):
        for dy in (0, 1):
            x = np.floor(v[:, 0]) - dx * (v[:, 0] == np.floor(v[:, 0]))
            y = np.floor(v[:, 1]) - dy * (v[:, 1] == np.floor(v[:, 1]))
            ok = (x >= 0) & (x < width) & (y >= 0) & (y < height)
            grid[y[ok].astype(np.int64), x[ok].astype(np.int64)] = True
    return grid


def overdraw(case: Case, coverage: Coverage, convention: Convention | None = None,
             oracle: Callable[[], Coverage] | None = None) -> Result:
    """No pixel hit twice: for triangles that tile a region without overlapping, or any
    subset of them (the form of ``watertight`` that survives shrinking); under snapping, a
    double hit of the convention's own excused as in :func:`watertight`."""
    width, height = case.scene.width, case.scene.height
    counts = coverage.counts(width, height)
    twice = counts > 1
    if twice.any():
        twice &= ~_snapping_own(counts, oracle, convention, case.scene, width, height)
    doubles = np.argwhere(twice)
    evidence = {"pixels": [[int(x), int(y)] for y, x in doubles[:EVIDENCE_LIMIT]]} if len(doubles) else {}
    return result(case.id, "overdraw", not len(doubles), f"{len(doubles)} double hits" if len(doubles) else "no double hits",
                   {"double_hits": float(len(doubles))}, evidence)


def holes(case: Case, coverage: Coverage) -> Result:
    """On a planar partition's pieces around a region, convention-free: every pixel whose
    closed square lies inside the (open, convex) region hit at least once -- watertight's
    holes alone, the form that survives cutting a partition down to the pieces that meet
    a small region around a hole (:func:`harness.diagnose.repro.hole_repro`): pieces that reach
    beyond that region draw there, and that is no stray."""
    if case.region is None:
        return skip(case, "holes", "no region")
    scene = case.scene
    inside, _ = _pixel_classes(case.region, scene.width, scene.height)
    empty = np.argwhere(inside & (coverage.counts(scene.width, scene.height) == 0))
    evidence = {"pixels": [[int(x), int(y)] for y, x in empty[:EVIDENCE_LIMIT]]} if len(empty) else {}
    n, of = len(empty), int(inside.sum())
    said = (f"{n} hole{'' if n == 1 else 's'} ({of} pixel{'' if of == 1 else 's'} inside the region)" if n
            else f"every one of {of} inside pixels hit")
    return result(case.id, "holes", not n, said, {"holes": float(n)}, evidence)


def _shared_edge(edges: tuple[NDArray, NDArray, NDArray], a: int, b: int) -> list[list[float]] | None:
    """An edge (pair of vertices) that primitives a and b have in common, either way round."""
    start, end, owner = edges
    of_a = {(tuple(u), tuple(v)) for u, v in zip(start[owner == a].tolist(), end[owner == a].tolist())}
    for u, v in zip(start[owner == b].tolist(), end[owner == b].tolist()):
        if (tuple(u), tuple(v)) in of_a or (tuple(v), tuple(u)) in of_a:
            return [u, v]
    return None


def blame(scene: AnyScene, coverage: Coverage, holes: NDArray, doubles: NDArray) -> list[dict[str, Any]]:
    """Attribute holes and double hits to edges. A double hit names the two primitives
    (triangles or paths) that both drew the pixel and their shared edge; a hole names the
    primitives whose edges pass closest to the pixel centre, and their shared edge.

    Parameters
    ----------
    holes, doubles : (M, 2) int, rows (y, x)
    """
    prim, x, y = coverage.pixels()
    edges = scene.edges()
    start, end, owner = edges
    key = f"{scene.noun}s"
    out = []
    for yy, xx in doubles:
        hitters = sorted(set(prim[(x == xx) & (y == yy)].tolist()))
        entry: dict[str, Any] = {"pixel": [int(xx), int(yy)], "kind": "double", key: hitters[:4]}
        if len(hitters) >= 2:
            entry["edge"] = _shared_edge(edges, hitters[0], hitters[1])
        out.append(entry)
    if len(holes):
        finite = np.zeros(len(scene), dtype=bool)
        finite[list(set(range(len(scene))) - set(scene.non_finite()))] = True
        with np.errstate(all="ignore"):
            d = end - start  # may overflow for huge coordinates: such an edge is then not blamed
            length2 = np.sum(d * d, axis=1)
        for yy, xx in holes:
            centre = np.array([xx + 0.5, yy + 0.5])
            with np.errstate(all="ignore"):
                t = np.clip(np.sum((centre - start) * d, axis=1) / length2, 0, 1)
                t = np.where(np.isfinite(t), t, 0.0)
                dist = np.hypot(*(start + t[:, None] * d - centre).T)
            dist = np.where(finite[owner] & np.isfinite(dist), dist, np.inf)
            nearest = np.full(len(scene), np.inf)
            np.minimum.at(nearest, owner, dist)
            near = [int(k) for k in np.argsort(nearest)[:2] if np.isfinite(nearest[k])]
            entry = {"pixel": [int(xx), int(yy)], "kind": "hole", key: near}
            entry["edge"] = _shared_edge(edges, near[0], near[1]) if len(near) == 2 else None
            out.append(entry)
    return out


pixel_classes = _pixel_classes

register(Check(
    "watertight", lambda s: watertight(s.case, s.coverage, s.convention, lambda: s.oracle),
    lambda case: getattr(case, "region", None) is not None,
    metrics={"holes": (1.0, 0.0), "double_hits": (1.0, 0.0), "strays": (1.0, 0.0)},
    caption="on a planar partition: inside pixels hit exactly once, outside never, no double hit",
    # consequent: a triangle dropped (conformance) leaves a hole here -- one cause, not two
    classifier="harness.diagnose.signatures:classify_watertight", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "overdraw", lambda s: overdraw(s.case, s.coverage, s.convention, lambda: s.oracle),
    # lines cross and share end pixels by rule, points' squares overlap: a double hit there is no overdraw
    lambda case: not hasattr(case, "frames") and not kind_of(case.scene).may_overlap, shrinks=True,
    metrics={"double_hits": (1.0, 0.0)}, on_request=True,
    caption="no pixel hit twice (watertight's double hits, in a form that survives shrinking)",
    classifier="harness.diagnose.signatures:classify_overdraw", cause_role="consequent", motion_role="none", figures=(),
))
register(Check(
    "holes", lambda s: holes(s.case, s.coverage), lambda case: getattr(case, "region", None) is not None,
    metrics={"holes": (1.0, 0.0)}, on_request=True,
    caption="every pixel inside the region hit (watertight's holes, in a form that survives cutting the partition down)",
    classifier="harness.diagnose.signatures:classify_holes", cause_role="own", motion_role="none", figures=(),
))
