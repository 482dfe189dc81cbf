"""Fragment diffing: the fragments (primitive, x, y) one coverage has and another lacks,
with multiplicity (:func:`deviations`), and a counter of an answer's fragments that many
oracles are compared against (:class:`FragmentCounter`), merged by compiled kernels."""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.geometry.keys import union, unique_counts

__all__ = ["deviations", "FragmentCounter", "same_canonical_spans"]


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
    got_keys, got_counts = unique_counts(key_got)
    want_keys, want_counts = unique_counts(key_want)
    keys = union(got_keys, want_keys)
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
    known = same_canonical_spans(coverage.triangle, coverage.y, coverage.x0, coverage.x1,
                                 oracle.triangle, oracle.y, oracle.x0, oracle.x1, width, height)
    if known >= 0:  # both in canonical form already (the usual answers): decided in one pass
        return bool(known)
    a, b = (Coverage(c.triangle, c.y, c.x0, c.x1).canonical() for c in (coverage, oracle))  # spans only
    if len(a) != len(b) or not all(np.array_equal(getattr(a, f), getattr(b, f)) for f in ("triangle", "y", "x0", "x1")):
        return False
    return bool(((a.triangle >= 0) & (a.y >= 0) & (a.y < height) & (a.x0 >= 0) & (a.x1 <= width)).all())


@numba.njit(cache=True)
def _canonical_form(t, y, x0, x1):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """Whether the spans are in :meth:`Coverage.canonical` form as they are: non-empty,
    sorted by (primitive, row, x0), and apart (a span of a row starts beyond the end of
    the one before it)."""
    for s in range(t.size):
        if x0[s] >= x1[s]:
            return False
        if s > 0 and (t[s] < t[s - 1] or (t[s] == t[s - 1] and (y[s] < y[s - 1] or (y[s] == y[s - 1]
                                                                                         and x0[s] <= x1[s - 1])))):
            return False
    return True


@numba.njit(cache=True)
def same_canonical_spans(t, y, x0, x1, u, v, a0, a1, width, height):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """1 when the spans (t, y, x0, x1) and (u, v, a0, a1) are both in canonical form, equal,
    and inside the viewport (the same fragments); 0 when both are canonical and differ or
    lie outside it (not the same fragments, or fragments outside: compare pixel by pixel);
    -1 when either is not in canonical form (not decided here)."""
    if not _canonical_form(t, y, x0, x1) or not _canonical_form(u, v, a0, a1):
        return -1
    if t.size != u.size:
        return 0
    for s in range(t.size):
        if t[s] != u[s] or y[s] != v[s] or x0[s] != a0[s] or x1[s] != a1[s]:
            return 0
        if t[s] < 0 or y[s] < 0 or y[s] >= height or x0[s] < 0 or x1[s] > width:
            return 0
    return 1


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
        self.keys, self.counts = unique_counts((tri[inside] * height + y[inside]) * width + x[inside])
        self.outside = int((~inside).sum())

    def mismatches(self, oracle: Coverage) -> int:
        """Missing plus extra fragments (with multiplicity) against ``oracle``.

        An oracle's spans (inside the viewport, never overlapping: what
        :func:`harness.oracle.coverage.exact_coverage` gives) are merged with the fragments span by
        span, without expanding them; any other coverage is expanded into fragments.
        """
        row = oracle.triangle * self.height + oracle.y
        start, stop = row * self.width + oracle.x0, row * self.width + oracle.x1
        order = np.argsort(start, kind="stable")
        inside = (oracle.triangle >= 0) & (oracle.y >= 0) & (oracle.y < self.height) \
            & (oracle.x0 >= 0) & (oracle.x1 <= self.width)
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
