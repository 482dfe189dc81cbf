"""triangulation: a simple polygon covers exactly the samples of the union of any
triangulation of it, under the same convention -- the check that ties a rasterizer's path
fill to its triangle fill; convention-free.

Why it must hold: a sample not on any edge is inside the polygon exactly when it is inside
one triangle of the triangulation. A sample on the polygon's boundary is decided, for the
path and for the one triangle whose edge it lies on, by the same symbolic perturbation of
the sample (:mod:`harness.oracle.winding`, :mod:`harness.contract.conventions`); a sample on an interior
diagonal is owned by exactly one of the two triangles sharing it, the one the perturbed
sample lies in -- the polygon's own answer. (A triangulation without Steiner points has no
interior vertices, so no sample sits where three or more triangles meet inside.) So under
any tie rule, sample point and snapping, the two answers are equal pixel for pixel, and a
rasterizer that fills paths one way and triangles another shows here.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.records import EVIDENCE_LIMIT, Check, Result, Subject, register, result, skip
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.geometry.exact import orientation
from harness.kinds import PATHS

__all__ = ["simple_polygon_triangles", "triangulation"]

# Polygons up to this many vertices are triangulated (ear clipping with exact predicates
# is cubic in the worst case).
MAX_VERTICES = 64


def _orient(a: NDArray, b: NDArray, c: NDArray) -> NDArray:
    """Exact sign of orient2d for rows of points (M, 2) each."""
    return orientation(np.stack(np.broadcast_arrays(a, b, c), axis=1))


def _strictly_simple(p: NDArray) -> bool:
    """Whether the closed polygon ``p`` (K, 2) is simple in the strict sense the check
    needs: finite, at least 3 vertices, no repeated vertex, no three consecutive vertices
    collinear, and no two edges meeting anywhere but adjacent edges at their shared vertex
    (all decided exactly)."""
    k = p.shape[0]
    if k < 3 or not np.isfinite(p).all() or np.unique(p, axis=0).shape[0] != k:
        return False
    if (_orient(np.roll(p, 1, axis=0), p, np.roll(p, -1, axis=0)) == 0).any():
        return False
    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # the first and last edges are adjacent
    i, j = i[keep], j[keep]
    if not i.size:
        return True
    a, b = p[i], p[(i + 1) % k]
    c, d = p[j], p[(j + 1) % k]
    o1, o2 = _orient(a, b, c), _orient(a, b, d)
    o3, o4 = _orient(c, d, a), _orient(c, d, b)
    crossing = (o1 * o2 < 0) & (o3 * o4 < 0)

    def on(s: NDArray, t: NDArray, q: NDArray, o: NDArray) -> NDArray:
        lo, hi = np.minimum(s, t), np.maximum(s, t)
        between: NDArray = (o == 0) & (q >= lo).all(axis=1) & (q <= hi).all(axis=1)
        return between

    touching = on(a, b, c, o1) | on(a, b, d, o2) | on(c, d, a, o3) | on(c, d, b, o4)
    return not bool((crossing | touching).any())


def simple_polygon_triangles(p: NDArray) -> NDArray | None:
    """A triangulation of a strictly simple polygon by ear clipping with exact predicates,
    (K - 2, 3, 2) float64, each triangle wound as the polygon is; None when ``p`` is not
    strictly simple (see :func:`_strictly_simple`) or has more than :data:`MAX_VERTICES`.

    >>> simple_polygon_triangles(np.array([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]], dtype=float)).shape
    (3, 3, 2)
    """
    p = np.asarray(p, dtype=np.float64)
    if p.shape[0] > MAX_VERTICES or not _strictly_simple(p):
        return None
    lowest = int(np.lexsort((p[:, 1], p[:, 0]))[0])  # its corner is convex: it gives the orientation
    k = p.shape[0]
    sign = int(_orient(p[[(lowest - 1) % k]], p[[lowest]], p[[(lowest + 1) % k]])[0])
    left = list(range(k))
    out = []
    while len(left) > 3:
        m = len(left)
        for s in range(m):
            a, b, c = left[s - 1], left[s], left[(s + 1) % m]
            if int(_orient(p[[a]], p[[b]], p[[c]])[0]) != sign:
                continue  # reflex (or flat) corner: no ear
            others = [v for v in left if v not in (a, b, c)]
            q = p[others]
            o1, o2, o3 = _orient(p[a], p[b], q), _orient(p[b], p[c], q), _orient(p[c], p[a], q)
            # an ear holds no other vertex inside or on it
            if ((o1 * sign >= 0) & (o2 * sign >= 0) & (o3 * sign >= 0)).any():
                continue
            out.append(p[[a, b, c]])
            left.pop(s)
            break
        else:  # pragma: no cover - a strictly simple polygon always has an ear
            return None
    out.append(p[left])
    return np.array(out)


def _pixel_set(coverage: Coverage, index: NDArray | None = None) -> tuple[NDArray, NDArray]:
    """Unique (primitive, x, y) keys of a coverage (primitive mapped through ``index``), and
    the keys covered more than once."""
    prim, x, y = coverage.pixels()
    if index is not None:
        keep = (prim >= 0) & (prim < index.size)
        prim, x, y = index[prim[keep]], x[keep], y[keep]
    keys = np.stack([prim, x, y], axis=1)
    unique, counts = np.unique(keys, axis=0, return_counts=True)
    return unique, unique[counts > 1]


def triangulation(case: Any, coverage: Coverage, triangles_coverage: Coverage, owner: NDArray, paths: NDArray,
                  doubles_own: bool = False, own: tuple[Coverage, Coverage] | None = None) -> Result:
    """The rasterizer's coverage of each simple path in ``paths`` equals the union of its
    coverage of the path's triangulation, with no sample drawn by two of those triangles.

    Parameters
    ----------
    coverage : Coverage
        Of the path scene.
    triangles_coverage : Coverage
        Of the triangle scene holding every triangulation; triangle t belongs to path
        ``owner[t]``.
    paths : (P',) int64
        The paths judged (the strictly simple single-contour ones).
    doubles_own : bool
        The convention's rule draws a sample on a shared edge for both triangles (the
        closed rule: ``CoverageModel.exactly_once`` False): double hits are expected and
        counted (``rule_own``), not failed.
    own : (Coverage, Coverage) or None
        The declared rule's exact answers for the path scene and the triangle scene, when
        the rule does not promise a path its triangulation's samples (dropout control: a
        thin triangle of the triangulation draws a dropout pixel the path does not):
        samples drawn for the one but not the other where the rule's answers differ so
        too are excused (``rule_own``).
    """
    judged = np.zeros(len(case.scene), dtype=bool)
    judged[paths] = True
    path_keys, _ = _pixel_set(coverage)
    path_keys = path_keys[judged[path_keys[:, 0]]] if path_keys.size else path_keys
    union, doubles = _pixel_set(triangles_coverage, owner)
    view = [("p", np.int64), ("x", np.int64), ("y", np.int64)]

    def rows(a: NDArray) -> NDArray:
        return np.ascontiguousarray(a, dtype=np.int64).view(view).reshape(-1)

    only_path = np.setdiff1d(rows(path_keys), rows(union))
    only_triangles = np.setdiff1d(rows(union), rows(path_keys))
    excused = 0
    if own is not None:
        own_path, _ = _pixel_set(own[0])
        own_path = own_path[judged[own_path[:, 0]]] if own_path.size else own_path
        own_union, _ = _pixel_set(own[1], owner)
        before = only_path.size + only_triangles.size
        only_path = np.setdiff1d(only_path, np.setdiff1d(rows(own_path), rows(own_union)))
        only_triangles = np.setdiff1d(only_triangles, np.setdiff1d(rows(own_union), rows(own_path)))
        excused = before - only_path.size - only_triangles.size
    metrics = {"paths_judged": float(paths.size), "path_only": float(only_path.size),
               "triangles_only": float(only_triangles.size), "triangulation_double_hits": float(len(doubles))}
    evidence: dict[str, Any] = {}
    for name, found in (("path_only", only_path), ("triangles_only", only_triangles)):
        if found.size:
            evidence[name] = [[int(r["p"]), int(r["x"]), int(r["y"])] for r in found[:EVIDENCE_LIMIT]]
    if len(doubles):
        evidence["triangulation_double_hits"] = doubles[:EVIDENCE_LIMIT].tolist()
    if doubles_own:
        metrics["rule_own"] = metrics.pop("triangulation_double_hits")
    if excused:
        metrics["rule_own"] = metrics.get("rule_own", 0.0) + float(excused)
        evidence.pop("triangulation_double_hits", None)
    ok = not (only_path.size or only_triangles.size or (len(doubles) and not doubles_own))
    if ok:
        message = f"each of {paths.size} simple paths covers exactly its triangulation's samples"
    else:
        message = (f"{only_path.size} samples drawn for the path but not its triangles, {only_triangles.size} for the "
                   f"triangles but not the path, {len(doubles)} drawn by two triangles of one triangulation")
    if doubles_own and len(doubles):
        message += f" ({len(doubles)} samples on shared edges drawn twice: the rule's own)"
    if excused:
        message += f"; {excused} samples drawn for one but not the other excused: the rule's own (dropouts)"
    if evidence:
        evidence["columns"] = ["path", "x", "y"]
    return result(case.id, "triangulation", ok, message, metrics, evidence)


def triangulated(scene: PathScene) -> tuple[Scene, NDArray, NDArray] | None:
    """The triangle scene of every strictly simple one-contour path's triangulation, the
    path of each triangle, and the paths triangulated; None when there is none."""
    pieces, owner, paths = [], [], []
    for path in range(len(scene)):
        contours = scene.contours_of(path)
        if len(contours) != 1:
            continue
        triangles = simple_polygon_triangles(contours[0])
        if triangles is None:
            continue
        pieces.append(triangles)
        owner += [path] * len(triangles)
        paths.append(path)
    if not pieces:
        return None
    return (Scene(scene.width, scene.height, np.concatenate(pieces)), np.array(owner, dtype=np.int64),
            np.array(paths, dtype=np.int64))


def _run(s: Subject) -> Result:
    scene = s.case.scene
    scene = PATHS.narrow(scene)
    if "triangles" not in s.scene_kinds:
        return skip(s.case, "triangulation", f"{s.rasterizer} takes no triangle scenes")
    if s.convention is not None and s.convention.cull != "none":
        return skip(s.case, "triangulation", f"the convention culls {s.convention.cull} triangles: a triangulation's "
                                             "triangles are wound as the path, so some would be culled")
    made = triangulated(scene)
    if made is None:
        return skip(s.case, "triangulation", "no strictly simple one-contour path to triangulate")
    triangles, owner, paths = made
    outcome = s.call(triangles)
    if outcome.coverage is None:
        kind = "timeout" if outcome.timed_out else type(outcome.error).__name__
        return Result("", s.case.id, "triangulation", "error", f"{kind} on the triangulation: {outcome.error}",
                      {"seconds": outcome.seconds}, {"traceback": outcome.traceback})
    rule = None
    if s.convention is not None and s.convention.model.path_oracle and s.convention.dropout != "none":
        from harness.oracle.coverage import exact_coverage  # dropouts: the rule's own differences

        rule = (s.oracle, exact_coverage(triangles, s.convention))
    return triangulation(s.case, s.coverage, outcome.coverage, owner, paths,
                         doubles_own=s.convention is not None and not s.convention.model.exactly_once, own=rule)


def _applies(case: Any) -> bool:
    return PATHS.owns(getattr(case, "scene", None)) and case.family in ("paths", "path-partitions")


register(Check(
    "triangulation", _run, _applies, shrinks=True,
    metrics={"path_only": (1.0, 0.0), "triangles_only": (1.0, 0.0), "triangulation_double_hits": (1.0, 0.0)},
    caption="a simple polygon covers exactly the samples of the union of a triangulation of it (paths against triangles)",
    classifier="harness.diagnose.signatures:classify_triangulation", cause_role="consequent", motion_role="none", figures=(),
))
