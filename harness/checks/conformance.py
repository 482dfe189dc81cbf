"""conformance: pixel-exact against the exact oracle; deviations at near ties (float
rounding, by a rigorous bound) excused off the lattice in default mode."""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.case import Case
from harness.api import AnyScene, Coverage, PathScene
from harness.checks.records import EVIDENCE_LIMIT, Check, Tolerance, register, result, Result
from harness.conventions import Convention
from harness.exact import orientation

__all__ = ["deviations", "FragmentCounter", "edge_distance", "path_edge_distance", "near_ties", "near_ties_of", "conformance"]

# Shewchuk's bound on the float orient2d's error, differences included; the added
# absolute term covers underflow of the products (harmless at any pixel scale).
_ORIENT_ERROR = (3.0 + 16.0 * 2.0**-53) * 2.0**-53
_UNDERFLOW = 2.0**-1000


def deviations(coverage: Coverage, oracle: Coverage, width: int, height: int) -> tuple[NDArray, NDArray]:
    """Fragments (triangle, x, y) the oracle has and the coverage lacks (missing), and the
    reverse (extra), with multiplicity; fragments outside the viewport count as extra.

    Returns
    -------
    missing, extra : (3, M) int64
    """
    if _same_fragments(coverage, oracle, width, height):  # the usual answer of a right rasterizer: no pixel work
        none = np.zeros((3, 0), dtype=np.int64)
        return none, none.copy()
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


def _same_fragments(coverage: Coverage, oracle: Coverage, width: int, height: int) -> bool:
    """True when both hold the same fragments, all inside the viewport, as equal canonical
    spans (a sufficient test, span by span; False says only "compare pixel by pixel")."""
    a, b = (Coverage(c.triangle, c.y, c.x0, c.x1).canonical() for c in (coverage, oracle))  # spans only
    if len(a) != len(b) or not all(np.array_equal(getattr(a, f), getattr(b, f)) for f in ("triangle", "y", "x0", "x1")):
        return False
    return bool(((a.triangle >= 0) & (a.y >= 0) & (a.y < height) & (a.x0 >= 0) & (a.x1 <= width)).all())


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
        """Missing plus extra fragments (with multiplicity) against ``oracle``.

        An oracle's spans (inside the viewport, never overlapping: what
        :func:`harness.oracle.exact_coverage` gives) are merged with the fragments span by
        span, without expanding them; any other coverage is expanded into fragments.
        """
        row = oracle.triangle * self.height + oracle.y
        start, stop = row * self.width + oracle.x0, row * self.width + oracle.x1
        order = np.argsort(start, kind="stable")
        inside = (oracle.triangle >= 0) & (oracle.y >= 0) & (oracle.y < self.height) & (oracle.x0 >= 0) & (oracle.x1 <= self.width)
        if inside.all():
            total = int(_merge_spans(self.keys, self.counts, start[order], stop[order]))
            if total >= 0:
                return total + self.outside
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


@numba.njit(cache=True)
def _merge_spans(got, counts, start, stop):  # type: ignore[no-untyped-def]
    """sum |count_got(k) - count_want(k)| over all keys, ``want`` given as key ranges
    [start, stop) sorted by start; -1 when two of the ranges overlap (then a key's wanted
    count may exceed 1: the caller counts fragment by fragment instead)."""
    total = 0
    i = 0
    reached = np.iinfo(np.int64).min
    for s in range(start.size):
        a = start[s]
        b = stop[s]
        if b <= a:
            continue
        if a < reached:
            return -1
        reached = b
        while i < got.size and got[i] < a:
            total += counts[i]
            i += 1
        seen = 0
        while i < got.size and got[i] < b:
            total += abs(counts[i] - 1)
            seen += 1
            i += 1
        total += (b - a) - seen
    while i < got.size:
        total += counts[i]
        i += 1
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


@numba.njit(cache=True)
def _path_distance_kernel(ax, ay, bx, by, first, last, magnitude, fragment_path, px, py, out, pairs):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """Per fragment, the least bound / length over its path's edges whose y-range holds
    the sample (the edges that decide the sample's row), relative to the path's largest
    |coordinate|; pairs (fragment, edge) whose float edge function cannot be told from 0
    are written to ``pairs`` for the exact test. Returns the number of pairs."""
    n = 0
    for f in range(fragment_path.size):
        p = fragment_path[f]
        best = np.inf
        for e in range(first[p], last[p]):
            if py[f] < min(ay[e], by[e]) or py[f] > max(ay[e], by[e]):
                continue
            left = (ax[e] - px[f]) * (by[e] - py[f])
            right = (ay[e] - py[f]) * (bx[e] - px[f])
            value = abs(left - right)
            error = _ORIENT_ERROR * (abs(left) + abs(right)) + _UNDERFLOW
            bound = value + error
            length = np.hypot(bx[e] - ax[e], by[e] - ay[e]) * (1.0 - 2.0**-50)
            if np.isfinite(bound) and length > 0:
                best = min(best, bound / length)
            if value <= error and n < pairs.shape[0]:
                pairs[n, 0] = f
                pairs[n, 1] = e
                n += 1
        out[f] = best / magnitude[p]
    return n


def path_edge_distance(scene: PathScene, convention: Convention, fragments: NDArray) -> NDArray:
    """:func:`edge_distance` for a path scene: from each fragment's sample point to the
    nearest edge of its path among those whose y-range holds the sample (the edges that
    decide it), relative to max(1, largest |coordinate|) of the path; never an
    underestimate, exactly 0 only when the exact predicate puts the sample on such an edge,
    inf for a path with a non-finite coordinate.

    Parameters
    ----------
    fragments : (3, M) int64 rows path, x, y
    """
    out = np.full(fragments.shape[1], np.inf)
    if fragments.shape[1] == 0:
        return out
    start, end, owner = scene.edges()
    start, end = convention.snap(start), convention.snap(end)
    order = np.argsort(owner, kind="stable")
    start, end, owner = start[order], end[order], owner[order]
    n = len(scene)
    first = np.searchsorted(owner, np.arange(n)).astype(np.int64)
    last = np.searchsorted(owner, np.arange(n), side="right").astype(np.int64)
    lo, hi, finite = scene.primitive_boxes()
    magnitude = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, initial=0.0)) if n else np.ones(0)
    path = fragments[0]
    ok = (path >= 0) & (path < n)
    ok[ok] &= finite[path[ok]]
    px = (fragments[1, ok] + convention.sample[0]).astype(np.float64)
    py = (fragments[2, ok] + convention.sample[1]).astype(np.float64)
    got = np.empty(px.size)
    pairs = np.empty((max(16, 8 * px.size), 2), dtype=np.int64)
    with np.errstate(all="ignore"):
        ax, ay, bx, by = (np.ascontiguousarray(c) for c in (start[:, 0], start[:, 1], end[:, 0], end[:, 1]))
        m = _path_distance_kernel(ax, ay, bx, by, first, last, magnitude, np.ascontiguousarray(path[ok]), px, py, got, pairs)
    if m:
        f, e = pairs[:m, 0], pairs[:m, 1]
        on_edge = orientation(np.stack([start[e], end[e], np.stack([px[f], py[f]], axis=-1)], axis=1)) == 0
        got[f[on_edge]] = 0.0
    out[ok] = np.where(np.isnan(got), np.inf, got)
    return out


def near_ties_of(scene: AnyScene, convention: Convention, fragments: NDArray, tolerance: Tolerance) -> tuple[NDArray, NDArray]:
    """:func:`near_ties` for a scene of any kind, as the convention sees it (snapped)."""
    if isinstance(scene, PathScene):
        distance = path_edge_distance(scene, convention, fragments)
        lo, hi, _ = scene.primitive_boxes()
        scale = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, initial=0.0)) if len(scene) else np.ones(0)
        path = fragments[0]
        ok = (path >= 0) & (path < len(scene))
        magnitude = np.full(distance.size, np.inf)
        magnitude[ok] = scale[path[ok]]
        with np.errstate(invalid="ignore"):
            near = (distance <= tolerance.near_tie) & (distance * magnitude <= tolerance.near_tie_pixels)
        return near, distance
    return near_ties(convention.snap(scene.positions), fragments, convention.sample, tolerance)


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
    near, distance = near_ties_of(scene, convention, both, tolerance)
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
            {scene.noun: int(both[0, i]), "x": int(both[1, i]), "y": int(both[2, i]), "kind": str(kind[i]),
             "near_tie": bool(near[i]), "distance": float(distance[i])}
            for i in order[:EVIDENCE_LIMIT]
        ]
    if not both.shape[1]:
        message = "pixel-exact"
    else:
        message = f"{missing.shape[1]} missing, {extra.shape[1]} extra; {int(near.sum())} near ties (float rounding), {int(wrong.sum())} wrong"
        if metrics["exact_ties"]:
            message += f"; {int(metrics['exact_ties'])} samples exactly on an edge"
    return result(case.id, "conformance", allowed, message, metrics, evidence)


register(Check(
    "conformance", lambda s: conformance(s.case, s.coverage, s.oracle, s.convention, s.tolerance),  # type: ignore[arg-type]
    lambda case: not hasattr(case, "frames"), needs_convention=True, shrinks=True, metrics={"wrong": (1.0, 0.0)},
    caption="pixel-exact against the exact oracle of the convention",
))
