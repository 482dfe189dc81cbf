"""Checks: pure functions from (case, coverage, oracle, tolerance) to result records.

No I/O, no plotting. Every check returns a :class:`Result` whose ``rasterizer`` the runner
fills in. Tolerances are data (:class:`Tolerance`): ``strict`` allows no deviation at all,
``default`` excuses deviations at near ties (the sample within ``near_tie`` of an edge,
relative to the coordinates' magnitude, and within ``near_tie_pixels`` absolutely: float
rounding) on non-lattice cases only. Distances are rigorous upper bounds, and exactly 0
only where the exact predicate puts the sample on an edge line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from cases.records import Case
from harness.api import Coverage, Scene
from harness.conventions import Convention
from harness.exact import orientation

__all__ = [
    "Result",
    "Tolerance",
    "NEAR_TIE",
    "CHECKS",
    "deviations",
    "FragmentCounter",
    "edge_distance",
    "near_ties",
    "hygiene",
    "conformance",
    "watertight",
    "closed_balance",
    "degenerate",
    "invariance",
    "invariance_variants",
    "blame",
    "overdraw",
]

# float64 evaluations of edge crossings err by a few units in the last place of the
# coordinates (about 2**-50 relative); 2**-40 leaves a wide berth and is still far below
# any sub-pixel lattice a rasterizer could mean (16 bits is 2**-16).
NEAR_TIE = 2.0**-40
# ... and never more than 2**-20 px, whatever the magnitude: beyond about 2**20 px a float
# rasterizer's rounding reaches whole fractions of a pixel, and it must draw exactly or
# refuse the triangle (a case's ``refusable``), not be excused.
NEAR_TIE_PIXELS = 2.0**-20
# Shewchuk's bound on the float orient2d's error, differences included; the added
# absolute term covers underflow of the products (harmless at any pixel scale).
_ORIENT_ERROR = (3.0 + 16.0 * 2.0**-53) * 2.0**-53
_UNDERFLOW = 2.0**-1000
EVIDENCE_LIMIT = 50

CHECKS = ("hygiene", "conformance", "watertight", "closed", "degenerate", "invariance", "jaggy", "texel", "perspective")


@dataclass(frozen=True, slots=True)
class Tolerance:
    """How much deviation a check lets through.

    Parameters
    ----------
    mode : {"default", "strict"}
    near_tie : float
        Relative distance of a sample from an edge below which a deviation is rounding.
    near_tie_pixels : float
        ... and the absolute distance in pixels (a cap for huge coordinates).
    work_ratio : float
        Largest allowed time ratio of an epsilon scene to its control scene.
    uv_error : float
        Largest allowed error of interpolated (u, v) against the exact values, in texels.
    """

    mode: str = "default"
    near_tie: float = NEAR_TIE
    near_tie_pixels: float = NEAR_TIE_PIXELS
    work_ratio: float = 50.0
    uv_error: float = 1e-6

    def __post_init__(self) -> None:
        if self.mode not in ("default", "strict"):
            raise ValueError(f"Tolerance.mode must be 'default' or 'strict', not {self.mode!r}")


@dataclass(frozen=True, slots=True)
class Result:
    """One check of one rasterizer on one case."""

    rasterizer: str
    case: str
    check: str
    status: str  # "pass", "fail", "error" or "skip"
    message: str
    metrics: dict[str, float] = field(default_factory=dict)
    evidence: dict[str, Any] = field(default_factory=dict)


def _result(case: Case, check: str, ok: bool, message: str, metrics: dict | None = None, evidence: dict | None = None) -> Result:
    return Result("", case.id, check, "pass" if ok else "fail", message, metrics or {}, evidence or {})


def skip(case: Case, check: str, why: str) -> Result:
    return Result("", case.id, check, "skip", why)


def _first(array: NDArray, limit: int = EVIDENCE_LIMIT) -> list:
    return np.asarray(array)[:limit].tolist()


# -- hygiene -------------------------------------------------------------------------------


def hygiene(case: Case, coverage: Coverage, interpolates: bool = True) -> Result:
    """Spans inside the viewport, valid triangle ids, ``x0 < x1``, no pixel emitted twice by
    one triangle, one attribute row per pixel (when the scene has attributes and the
    rasterizer interpolates; one that declares ``interpolates = False`` may return none)."""
    scene = case.scene
    t, y, x0, x1 = coverage.triangle, coverage.y, coverage.x0, coverage.x1
    problems: dict[str, NDArray] = {
        "outside_viewport": np.flatnonzero((y < 0) | (y >= scene.height) | (x0 < 0) | (x1 > scene.width)),
        "bad_triangle_id": np.flatnonzero((t < 0) | (t >= len(scene))),
        "empty_or_reversed": np.flatnonzero(x0 >= x1),
    }
    tri, x, yy = coverage.pixels()
    order = np.lexsort((x, yy, tri))
    same = (np.diff(tri[order]) == 0) & (np.diff(yy[order]) == 0) & (np.diff(x[order]) == 0)
    repeated = order[1:][same]
    metrics = {k: float(v.size) for k, v in problems.items()}
    metrics["repeated_pixels"] = float(repeated.size)
    evidence: dict[str, Any] = {k: _first(v) for k, v in problems.items() if v.size}
    if repeated.size:
        evidence["repeated_pixels"] = np.stack([tri[repeated], x[repeated], yy[repeated]], axis=1)[:EVIDENCE_LIMIT].tolist()
    attribute_problem = ""
    if scene.attributes is not None and (interpolates or coverage.attributes is not None):
        rows = None if coverage.attributes is None else coverage.attributes.shape[0]
        if rows != coverage.n_pixels:
            attribute_problem = f"{rows} attribute rows for {coverage.n_pixels} pixels"
        elif coverage.attributes.shape[1] != scene.n_attributes:
            attribute_problem = f"{coverage.attributes.shape[1]} attributes per pixel, the scene has {scene.n_attributes}"
    parts = [f"{int(v)} {k.replace('_', ' ')}" for k, v in metrics.items() if v]
    if attribute_problem:
        parts.append(attribute_problem)
        evidence["attributes"] = attribute_problem
    quiet = "well-formed" if interpolates or scene.attributes is None else "well-formed (interpolates no attributes, as it declares)"
    return _result(case, "hygiene", not parts, "; ".join(parts) or quiet, metrics, evidence)


# -- conformance ---------------------------------------------------------------------------


def deviations(coverage: Coverage, oracle: Coverage, width: int, height: int) -> tuple[NDArray, NDArray]:
    """Fragments (triangle, x, y) the oracle has and the coverage lacks (missing), and the
    reverse (extra), with multiplicity; fragments outside the viewport count as extra.

    Returns
    -------
    missing, extra : (3, M) int64
    """
    tri, x, y = coverage.pixels()
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (tri >= 0)
    key_got = (tri[inside] * height + y[inside]) * width + x[inside]
    o_tri, o_x, o_y = oracle.pixels()
    key_want = (o_tri * height + o_y) * width + o_x
    got_keys, got_counts = np.unique(key_got, return_counts=True)
    want_keys, want_counts = np.unique(key_want, return_counts=True)
    keys = np.union1d(got_keys, want_keys)
    delta = np.zeros(keys.size, dtype=np.int64)
    delta[np.searchsorted(keys, got_keys)] += got_counts
    delta[np.searchsorted(keys, want_keys)] -= want_counts
    triples = np.stack([keys // (width * height), keys % width, (keys // width) % height])
    missing = np.repeat(triples, np.clip(-delta, 0, None), axis=1)
    extra = np.repeat(triples, np.clip(delta, 0, None), axis=1)
    outside = np.stack([tri[~inside], x[~inside], y[~inside]])
    return missing, np.concatenate([extra, outside], axis=1)


class FragmentCounter:
    """A coverage's fragments as sorted keys, to count its deviations from many oracles
    quickly (:meth:`mismatches` equals the total size of :func:`deviations`' answer).

    Parameters
    ----------
    coverage : Coverage
    width, height : int
        The viewport; fragments outside it always count as extra.
    """

    def __init__(self, coverage: Coverage, width: int, height: int) -> None:
        tri, x, y = coverage.pixels()
        inside = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (tri >= 0)
        self.width, self.height = width, height
        self.keys, self.counts = np.unique((tri[inside] * height + y[inside]) * width + x[inside], return_counts=True)
        self.outside = int((~inside).sum())

    def mismatches(self, oracle: Coverage) -> int:
        """Missing plus extra fragments (with multiplicity) against ``oracle``."""
        tri, x, y = oracle.pixels()
        want = np.sort((tri * self.height + y) * self.width + x)
        return int(_merge_mismatches(self.keys, self.counts, want)) + self.outside


@numba.njit(cache=True)
def _merge_mismatches(got, counts, want):  # type: ignore[no-untyped-def]
    """sum |count_got(k) - count_want(k)| over all keys; both key arrays sorted, ``got``
    unique with ``counts``, ``want`` with repeats."""
    total = 0
    i = 0
    j = 0
    while i < got.size or j < want.size:
        if j >= want.size or (i < got.size and got[i] < want[j]):
            total += counts[i]
            i += 1
            continue
        key = want[j]
        n = 0
        while j < want.size and want[j] == key:
            n += 1
            j += 1
        have = 0
        if i < got.size and got[i] == key:
            have = counts[i]
            i += 1
        total += abs(have - n)
    return total


def edge_distance(positions: NDArray, fragments: NDArray, sample: tuple[float, float]) -> NDArray:
    """Distance from each fragment's sample point to the nearest edge line of its
    triangle, relative to max(1, largest |coordinate|) of that triangle.

    Never an underestimate: each edge function is evaluated in float with Shewchuk's
    rigorous error bound added, and divided by a lower bound on the edge's length. It is
    exactly 0 only when the exact predicate puts the sample on an edge line, and inf for a
    triangle with a non-finite coordinate (or an overflowing one): a float that cancels to
    zero never passes for a tie.

    Parameters
    ----------
    positions : (N, 3, 2) float64, as the convention sees them (snapped)
    fragments : (3, M) int64 rows triangle, x, y

    Returns
    -------
    (M,) float64
    """
    out = np.full(fragments.shape[1], np.inf)
    if fragments.shape[1] == 0:
        return out
    tri = fragments[0]
    ok = (tri >= 0) & (tri < positions.shape[0])
    p = positions[tri[ok]]
    px = fragments[1, ok] + sample[0]
    py = fragments[2, ok] + sample[1]
    finite = np.all(np.isfinite(p), axis=(1, 2))
    best = np.full(p.shape[0], np.inf)
    with np.errstate(all="ignore"):
        for k in range(3):
            a, b = p[:, k], p[:, (k + 1) % 3]
            left = (a[:, 0] - px) * (b[:, 1] - py)
            right = (a[:, 1] - py) * (b[:, 0] - px)
            bound = np.abs(left - right) + _ORIENT_ERROR * (np.abs(left) + np.abs(right)) + _UNDERFLOW
            length = np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]) * (1.0 - 2.0**-50)
            best = np.minimum(best, np.where(np.isfinite(bound) & (length > 0), bound / length, np.inf))
        relative = best / np.maximum(1.0, np.abs(p).max(axis=(1, 2)))
    relative[~finite] = np.inf
    samples = np.stack([px, py], axis=-1)
    for k in range(3):
        on_line = orientation(np.stack([p[:, k], p[:, (k + 1) % 3], samples], axis=1)) == 0
        relative[on_line & finite] = 0.0
    out[ok] = np.where(np.isnan(relative), np.inf, relative)
    return out


def near_ties(positions: NDArray, fragments: NDArray, sample: tuple[float, float], tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """Which fragments are near ties under ``tolerance`` (within ``near_tie`` of an edge
    relative to the coordinates and within ``near_tie_pixels`` absolutely), and their
    :func:`edge_distance`. Non-finite triangles are never near ties.

    Returns
    -------
    near : (M,) bool
    distance : (M,) float64
    """
    distance = edge_distance(positions, fragments, sample)
    tri = fragments[0]
    ok = (tri >= 0) & (tri < positions.shape[0])
    magnitude = np.full(distance.size, np.inf)
    with np.errstate(invalid="ignore"):
        magnitude[ok] = np.maximum(1.0, np.abs(positions[tri[ok]]).max(axis=(1, 2)))
        near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
    return near, distance


def conformance(case: Case, coverage: Coverage, oracle: Coverage, convention: Convention, tolerance: Tolerance = Tolerance()) -> Result:
    """Missing and extra pixels against the exact oracle of the declared convention.

    Deviations are near ties (float rounding: the sample within ``tolerance.near_tie`` of
    an edge, on a non-lattice case) or wrong. Strict mode allows none; default near ties.
    """
    scene = case.scene
    missing, extra = deviations(coverage, oracle, scene.width, scene.height)
    both = np.concatenate([missing, extra], axis=1)
    near, distance = near_ties(convention.snap(scene.positions), both, convention.sample, tolerance)
    if case.lattice:
        near[:] = False
    wrong = ~near
    allowed = distance.size == 0 if tolerance.mode == "strict" else not wrong.any()
    metrics = {
        "oracle_pixels": float(oracle.n_pixels),
        "missing": float(missing.shape[1]),
        "extra": float(extra.shape[1]),
        "near_tie": float(near.sum()),
        "wrong": float(wrong.sum()),
        "exact_ties": float((distance == 0.0).sum()),
    }
    evidence: dict[str, Any] = {}
    if both.shape[1]:
        kind = np.array(["missing"] * missing.shape[1] + ["extra"] * extra.shape[1])
        order = np.argsort(near, kind="stable")  # wrong ones first
        evidence["pixels"] = [
            {"triangle": int(both[0, i]), "x": int(both[1, i]), "y": int(both[2, i]), "kind": str(kind[i]),
             "near_tie": bool(near[i]), "distance": float(distance[i])}
            for i in order[:EVIDENCE_LIMIT]
        ]
    if not both.shape[1]:
        message = "pixel-exact"
    else:
        message = f"{missing.shape[1]} missing, {extra.shape[1]} extra; {int(near.sum())} near ties (float rounding), {int(wrong.sum())} wrong"
        if metrics["exact_ties"]:
            message += f"; {int(metrics['exact_ties'])} samples exactly on an edge"
    return _result(case, "conformance", allowed, message, metrics, evidence)


# -- watertight / no overdraw --------------------------------------------------------------


def _pixel_classes(region: NDArray, width: int, height: int) -> tuple[NDArray, NDArray]:
    """(inside, outside), (H, W) bool: pixels whose closed square lies in the open convex
    region, and pixels whose closed square misses the closed region; decided exactly."""
    m = region.shape[0]
    # the outline's winding, exactly (a float shoelace overflows for huge outlines)
    turns = orientation(np.stack([region, np.roll(region, -1, axis=0), np.roll(region, -2, axis=0)], axis=1))
    area_sign = int(turns[np.flatnonzero(turns)[0]])
    cy, cx = np.mgrid[0 : height + 1, 0 : width + 1]
    corners = np.stack([cx.ravel(), cy.ravel()], axis=-1).astype(float)
    side = np.empty((m, corners.shape[0]), dtype=np.int8)
    for k in range(m):
        a = np.broadcast_to(region[k], corners.shape)
        b = np.broadcast_to(region[(k + 1) % m], corners.shape)
        # positive: the corner lies on the region's side of edge k
        side[k] = orientation(np.stack([a, b, corners], axis=1)) * area_sign
    side = side.reshape(m, height + 1, width + 1)
    quads = np.stack([side[:, :-1, :-1], side[:, :-1, 1:], side[:, 1:, :-1], side[:, 1:, 1:]])
    inside = np.all(quads > 0, axis=(0, 1))
    outside = np.any(np.all(quads < 0, axis=0), axis=0)
    xs, ys = np.arange(width), np.arange(height)
    outside |= (region[:, 0].max() < xs)[None, :] | (region[:, 0].min() > xs + 1)[None, :]
    outside |= (region[:, 1].max() < ys)[:, None] | (region[:, 1].min() > ys + 1)[:, None]
    return inside, outside


def watertight(case: Case, coverage: Coverage) -> Result:
    """On a planar partition, convention-free: pixels wholly inside the union hit exactly
    once, pixels wholly outside never, and no pixel twice. Each hole and double hit is
    blamed on an edge and the triangles that share it."""
    if case.region is None:
        return skip(case, "watertight", "not a planar partition")
    scene = case.scene
    counts = coverage.counts(scene.width, scene.height)
    inside, outside = _pixel_classes(case.region, scene.width, scene.height)
    holes = np.argwhere(inside & (counts == 0))
    doubles = np.argwhere(counts > 1)
    strays = np.argwhere(outside & (counts > 0))
    metrics = {"holes": float(len(holes)), "double_hits": float(len(doubles)), "strays": float(len(strays)),
               "inside_pixels": float(inside.sum())}
    evidence: dict[str, Any] = {}
    if len(holes) or len(doubles):
        evidence["blame"] = blame(scene, coverage, holes[:EVIDENCE_LIMIT], doubles[:EVIDENCE_LIMIT])
    if len(strays):
        evidence["strays"] = [[int(x), int(y)] for y, x in strays[:EVIDENCE_LIMIT]]
    ok = not (len(holes) or len(doubles) or len(strays))
    message = "every inside pixel hit exactly once" if ok else f"{len(holes)} holes, {len(doubles)} double hits, {len(strays)} stray hits outside"
    if len(holes) or len(doubles):
        at_vertex = _holds_vertex(scene.positions, scene.width, scene.height)
        on_vertex = int(at_vertex[holes[:, 0], holes[:, 1]].sum() + at_vertex[doubles[:, 0], doubles[:, 1]].sum())
        metrics["at_vertex_pixels"] = float(on_vertex)
        if on_vertex == len(holes) + len(doubles):
            message += " (every one at a pixel holding a mesh vertex: the rule for samples on shared vertices)"
        else:
            message += f" ({on_vertex} at pixels holding a mesh vertex, the rest along edges)"
    return _result(case, "watertight", ok, message, metrics, evidence)


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


def overdraw(case: Case, coverage: Coverage) -> Result:
    """No pixel hit twice: for triangles that tile a region without overlapping, or any
    subset of them (the form of ``watertight`` that survives shrinking)."""
    counts = coverage.counts(case.scene.width, case.scene.height)
    doubles = np.argwhere(counts > 1)
    evidence = {"pixels": [[int(x), int(y)] for y, x in doubles[:EVIDENCE_LIMIT]]} if len(doubles) else {}
    return _result(case, "overdraw", not len(doubles), f"{len(doubles)} double hits" if len(doubles) else "no double hits",
                   {"double_hits": float(len(doubles))}, evidence)


def _shared_edges(positions: NDArray, a: int, b: int) -> list[list[list[float]]]:
    """Edges (pairs of vertices) that triangles a and b have in common."""
    va = {tuple(v) for v in positions[a].tolist()}
    common = [v for v in positions[b].tolist() if tuple(v) in va]
    return [common[:2]] if len(common) >= 2 else []


def blame(scene: Scene, coverage: Coverage, holes: NDArray, doubles: NDArray) -> list[dict[str, Any]]:
    """Attribute holes and double hits to edges. A double hit names the two triangles that
    both drew the pixel and their shared edge; a hole names the triangles whose edges pass
    closest to the pixel centre, and their shared edge.

    Parameters
    ----------
    holes, doubles : (M, 2) int, rows (y, x)
    """
    tri, x, y = coverage.pixels()
    out = []
    for yy, xx in doubles:
        hitters = sorted(set(tri[(x == xx) & (y == yy)].tolist()))
        entry: dict[str, Any] = {"pixel": [int(xx), int(yy)], "kind": "double", "triangles": hitters[:4]}
        if len(hitters) >= 2:
            entry["edge"] = (_shared_edges(scene.positions, hitters[0], hitters[1]) or [None])[0]
        out.append(entry)
    if len(holes):
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        for yy, xx in holes:
            centre = np.array([xx + 0.5, yy + 0.5])
            p = scene.positions
            dist = np.full(len(scene), np.inf)
            for k in range(3):
                a, b = p[:, k], p[:, (k + 1) % 3]
                with np.errstate(all="ignore"):
                    d = b - a  # may overflow for huge coordinates: such a triangle is then not blamed
                    t = np.clip(np.sum((centre - a) * d, axis=1) / np.sum(d * d, axis=1), 0, 1)
                    dist = np.minimum(dist, np.hypot(*(a + t[:, None] * d - centre).T))
            dist[~finite] = np.inf
            near = np.argsort(dist)[:2].tolist()
            entry = {"pixel": [int(xx), int(yy)], "kind": "hole", "triangles": near}
            entry["edge"] = (_shared_edges(p, near[0], near[1]) or [None])[0] if len(near) == 2 else None
            out.append(entry)
    return out


def closed_balance(case: Case, coverage: Coverage, convention: Convention | None) -> Result:
    """On a closed mesh in front of the camera, hits by clockwise triangles equal hits by
    counter-clockwise ones at every pixel. Orientation is taken after the declared
    snapping, if any (snapping can flip a tiny triangle)."""
    if not case.closed:
        return skip(case, "closed", "not a closed mesh")
    scene = case.scene
    sign = orientation(convention.snap(scene.positions) if convention is not None else scene.positions).astype(np.int64)
    valid = (coverage.triangle >= 0) & (coverage.triangle < len(scene))
    signed = Coverage(coverage.triangle[valid], coverage.y[valid], coverage.x0[valid], coverage.x1[valid])
    front = Coverage(*(a[sign[signed.triangle] > 0] for a in (signed.triangle, signed.y, signed.x0, signed.x1)))
    back = Coverage(*(a[sign[signed.triangle] < 0] for a in (signed.triangle, signed.y, signed.x0, signed.x1)))
    balance = front.counts(scene.width, scene.height) - back.counts(scene.width, scene.height)
    bad = np.argwhere(balance != 0)
    metrics = {"unbalanced_pixels": float(len(bad))}
    evidence = {"pixels": [[int(x), int(y), int(balance[y, x])] for y, x in bad[:EVIDENCE_LIMIT]]} if len(bad) else {}
    message = "front minus back is zero everywhere" if not len(bad) else f"{len(bad)} pixels where front minus back is not zero"
    return _result(case, "closed", not len(bad), message, metrics, evidence)


# -- degenerate ----------------------------------------------------------------------------


def control_scene(case: Case) -> Scene:
    """The work yardstick for a degenerate case: each finite triangle replaced by a plain
    right triangle over its bounding box, each side at least one pixel long."""
    p = case.scene.positions
    finite = np.all(np.isfinite(p), axis=(1, 2))
    lo = p[finite].min(axis=1)
    hi = np.maximum(p[finite].max(axis=1), lo + 1.0)
    tris = np.stack([lo, np.stack([hi[:, 0], lo[:, 1]], axis=-1), np.stack([lo[:, 0], hi[:, 1]], axis=-1)], axis=1)
    return Scene(case.scene.width, case.scene.height, tris)


def degenerate(case: Case, coverage: Coverage, convention: Convention | None,
               work: tuple[float, float] | None = None, tolerance: Tolerance = Tolerance()) -> Result:
    """Zero-area triangles (after the declared snapping) draw nothing, non-finite ones draw
    nothing, no attribute is NaN, and the work stays bounded: ``work`` is (seconds for the
    case, seconds for :func:`control_scene`), whose ratio may not exceed
    ``tolerance.work_ratio``."""
    scene = case.scene
    sign = orientation(convention.snap(scene.positions) if convention is not None else scene.positions)
    nothing = sign == 0  # zero area or non-finite
    tri = coverage.triangle
    valid = (tri >= 0) & (tri < len(scene))
    drew = np.zeros(len(scene), dtype=bool)
    drew[tri[valid][coverage.x1[valid] > coverage.x0[valid]]] = True
    offenders = np.flatnonzero(nothing & drew)
    nan_rows = 0
    if coverage.attributes is not None:
        nan_rows = int(np.isnan(coverage.attributes).any(axis=1).sum())
    metrics = {"degenerate_triangles_drawn": float(offenders.size), "nan_attribute_rows": float(nan_rows)}
    parts = []
    if offenders.size:
        parts.append(f"triangles {_first(offenders, 10)} have zero area or non-finite coordinates but drew pixels")
    if nan_rows:
        parts.append(f"{nan_rows} pixels with NaN attributes")
    if work is not None:
        ratio = work[0] / max(work[1], 1e-9)
        metrics["work_ratio"] = ratio
        if ratio > tolerance.work_ratio:
            parts.append(f"took {ratio:.0f}x the time of plain triangles with the same bounding boxes (limit {tolerance.work_ratio:g}x)")
    evidence = {"triangles": _first(offenders)} if offenders.size else {}
    return _result(case, "degenerate", not parts, "; ".join(parts) or "degenerate triangles draw nothing", metrics, evidence)


def refusal(case: Case, error: BaseException) -> Result | None:
    """A ValueError that names a triangle of the case the rasterizer may refuse: a
    non-finite one (a pass, as the contract allows) or a huge one (a skip, with its
    reason). None when the error is not such a refusal."""
    if not isinstance(error, ValueError):
        return None
    text = str(error)
    for t in case.non_finite:
        if f"triangle {t}" in text:
            return Result("", case.id, "degenerate", "pass", f"refused non-finite triangle {t}: {text}")
    for t in case.refusable:
        if f"triangle {t}" in text:
            return Result("", case.id, "degenerate", "skip", f"declined huge triangle {t}: {text}")
    return None


# -- invariance ----------------------------------------------------------------------------


def invariance_variants(case: Case, shift: tuple[int, int] = (3, 2), seed: int = 0) -> list[tuple[str, Scene, NDArray]]:
    """Transformed scenes and, for each, the scene-triangle index of each variant triangle:
    vertex order rotated, winding flipped, triangles permuted, and (when exact) translated
    by whole pixels into a viewport grown by the shift."""
    scene = case.scene
    n = len(scene)
    identity = np.arange(n)
    out = [
        ("rotate-vertices", Scene(scene.width, scene.height, scene.positions[:, [1, 2, 0]]), identity),
        ("flip-winding", Scene(scene.width, scene.height, scene.positions[:, [0, 2, 1]]), identity),
    ]
    perm = np.random.default_rng(seed).permutation(n)
    out.append(("permute-triangles", Scene(scene.width, scene.height, scene.positions[perm]), perm))
    moved = scene.positions + np.array(shift, dtype=float)
    with np.errstate(invalid="ignore"):
        exact = np.array_equal(moved - np.array(shift, dtype=float), scene.positions, equal_nan=True)
    if exact:
        out.append(("translate", Scene(scene.width + shift[0], scene.height + shift[1], moved), identity))
    return out


def invariance(case: Case, coverage: Coverage, variants: list[tuple[str, NDArray, Coverage]],
               shift: tuple[int, int] = (3, 2), tolerance: Tolerance = Tolerance(),
               sample: tuple[float, float] = (0.5, 0.5)) -> Result:
    """Each variant's coverage, mapped back (triangle ids, shift), equals the original's.
    Differences at near ties are excused on non-lattice cases in default mode.

    Parameters
    ----------
    variants : list of (name, triangle index map, coverage of the variant)
    """
    scene = case.scene
    diffs: dict[str, int] = {}
    evidence: dict[str, Any] = {}
    for name, index, cov in variants:
        t, x, y = cov.pixels()
        keep = (t >= 0) & (t < index.size)
        t, x, y = index[t[keep]], x[keep], y[keep]
        if name == "translate":
            x, y = x - shift[0], y - shift[1]
            window = (x >= 0) & (y >= 0) & (x < scene.width) & (y < scene.height)
            t, x, y = t[window], x[window], y[window]
        mapped = Coverage.from_pixels(t, x, y)
        missing, extra = deviations(mapped, coverage, scene.width, scene.height)
        both = np.concatenate([missing, extra], axis=1)
        if both.shape[1] and tolerance.mode == "default" and not case.lattice:
            distance = edge_distance(scene.positions, both, sample)
            both = both[:, distance > tolerance.near_tie]  # excused: rounding at a near tie
        if both.shape[1]:
            diffs[name] = int(both.shape[1])
            evidence[name] = both.T[:EVIDENCE_LIMIT].tolist()
    metrics = {f"{name}_differences": float(diffs.get(name, 0)) for name, _, _ in variants}
    message = "unchanged under " + ", ".join(n for n, _, _ in variants) if not diffs else "changed under " + ", ".join(f"{k} ({v} pixels)" for k, v in diffs.items())
    return _result(case, "invariance", not diffs, message, metrics, evidence)
