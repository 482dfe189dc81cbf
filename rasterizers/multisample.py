"""``pineda_msaa4``, ``pineda_msaa8``: Pineda edge functions at every sample of a
multisample pattern, each sample decided exactly under the tie rule (issue 14).

Sample s of pixel (i, j) is the point (i + sx_s, j + sy_s) of the pattern
(:func:`harness.contract.samples.pattern`: the D3D11 / Vulkan standard 4x and 8x locations, or any
dyadic offsets). For each triangle, sample and row, the edge walk of
:mod:`rasterizers.pineda_topleft` finds the run of columns whose sample passes all three
edge tests: along a row an edge's test is monotone in x, so each edge cuts the run from
one side, found from its float crossing and confirmed by stepping or bisecting.

Unlike ``pineda_topleft``, whose float edge functions are exact on lattice input only,
every test here is the exact sign of the edge function
(:func:`harness.geometry.exact.orient2d_sign`: a float filter, then an exact expansion). Sample
points are exact floats (offsets have at most 32 fraction bits, columns fewer than 2**20),
so each sample obeys the tie rule exactly, and the answer equals
:func:`harness.oracle.coverage.exact_coverage` on every triangle it accepts. The expansions are
exact for coordinates zero or of magnitude in [2**-450, 2**450]
(:data:`harness.geometry.exact.SAFE_MIN`, :data:`harness.geometry.exact.SAFE_MAX`); a triangle with a finite
coordinate outside that range is refused (``ValueError`` naming it), never guessed.

Spans come one per (triangle, sample, row), sorted by triangle, sample and row, each with
its sample index. Attributes are interpolated at each covered sample point (barycentric,
perspective-correct when the scene has ``w``), one row per fragment in span order.

Convention: ``Convention(samples=4)`` (or 8, or the offsets given), ``top-left`` ties (any
of the eight rules may be chosen), no snapping, no culling.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import TIE_RULES, Convention, TieRule, owns_edge
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orient2d_sign, orientation
from harness.geometry.spans import expand, pixel_offsets, span_buffers
from rasterizers._common import interpolate_barycentric

__all__ = ["MultisamplePineda", "PinedaMSAA4", "PinedaMSAA8", "screen_exact", "sample_run", "sample_rows",
           "triangle_edges"]


# -- the per-sample edge walk ----------------------------------------------------------------


@numba.njit(cache=True)
def triangle_edges(p, sign, tie_x, tie_y, y_first, edges, owned):  # type: ignore[no-untyped-def]
    """Fill ``edges`` (3, 4) with edge k's end points ``ax, ay, bx, by``, taken in the order
    that makes the signed area positive (the interior is where all three ``E_ab > 0``),
    and ``owned`` (3,) with whether the tie rule gives the edge the samples lying on it."""
    for k in range(3):
        if sign > 0:
            a, b = k, (k + 1) % 3
        else:  # walk the edges backwards: same triangle, positive orientation
            a, b = (k + 1) % 3, k
        ax, ay, bx, by = p[a, 0], p[a, 1], p[b, 0], p[b, 1]
        edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3] = ax, ay, bx, by
        # The tie rule: top-left owns top edges (horizontal, interior below) and left ones
        # (interior to the right); any other rule by its perturbation (harness.contract.conventions).
        owned[k] = owns_edge(ax, ay, bx, by, tie_x, tie_y, y_first)


@numba.njit(cache=True, inline="always")
def _passes(ax, ay, bx, by, owned, px, py):  # type: ignore[no-untyped-def]
    s = orient2d_sign(ax, ay, bx, by, px, py)
    # The tie rule, exactly per sample: a sample on the edge is inside only if the edge owns it.
    return s > 0 or (s == 0 and owned)


@numba.njit(cache=True, inline="always")
def _walk(ax, ay, bx, by, owned, sx, py, lo, hi, estimate, rising):  # type: ignore[no-untyped-def]
    """First column c in [lo, hi] where g(c) holds, g monotone false -> true and g(hi)
    taken as true: g = passes at (c + sx, py) for an edge whose function rises with x,
    not passes for one whose function falls. Starts at the estimate; steps, then bisects
    if it is far off (as :mod:`rasterizers.pineda_topleft` walks, with exact tests)."""
    c = min(max(estimate, lo), hi)
    if c < hi and (_passes(ax, ay, bx, by, owned, c + sx, py) != rising):
        c += 1
        if c >= hi or (_passes(ax, ay, bx, by, owned, c + sx, py) == rising):
            return c
        low, high = c, hi
    else:
        if c == lo or (_passes(ax, ay, bx, by, owned, c - 1 + sx, py) != rising):
            return c
        c -= 1
        if c == lo or (_passes(ax, ay, bx, by, owned, c - 1 + sx, py) != rising):
            return c
        low, high = lo - 1, c - 1
    while high - low > 1:
        mid = (low + high) // 2
        if _passes(ax, ay, bx, by, owned, mid + sx, py) == rising:
            high = mid
        else:
            low = mid
    return high


@numba.njit(cache=True)
def sample_run(edges, owned, sx, py, left, right):  # type: ignore[no-untyped-def]
    """The columns c in [left, right) whose sample point (c + sx, py) passes all three
    edge tests, as a run [left, right) (empty when left >= right)."""
    for k in range(3):
        ax, ay, bx, by = edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3]
        if ay == by:  # horizontal: the edge function is constant along the row
            if not _passes(ax, ay, bx, by, owned[k], sx, py):
                right = left
        else:
            # Float crossing of the edge line with this row, as a column estimate only.
            cross = ax + (bx - ax) * ((py - ay) / (by - ay)) - sx
            estimate = left if not cross > left else (right if cross > right else int(math.ceil(cross)))
            if by < ay:  # dE/dx = -(by - ay) > 0: the passing columns are a suffix
                left = max(left, _walk(ax, ay, bx, by, owned[k], sx, py, left, right, estimate, True))
            else:  # the function falls with x: a prefix
                right = min(right, _walk(ax, ay, bx, by, owned[k], sx, py, left, right, estimate, False))
        if left >= right:
            return left, left
    return left, right


@numba.njit(cache=True, inline="always")
def sample_rows(lo, hi, offset, size):  # type: ignore[no-untyped-def]
    """Indices c in [0, size) with lo <= c + offset <= hi, or a few more: ``ceil(fl(lo -
    offset))`` is at most the exact ceiling (rounding is monotone and integers are
    floats), likewise for the floor. Clamped as floats first: no overflow for huge input."""
    a = lo - offset
    b = hi - offset
    if b < 0.0 or a > size - 1:
        return 0, -1
    first = 0 if a < 0.0 else int(math.ceil(a))
    last = size - 1 if b > size - 1 else int(math.floor(b))
    return first, last


@numba.njit(cache=True, error_model="numpy")
def _kernel(positions, sign, tie_x, tie_y, y_first, offsets, width, height, out_t, out_s, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    edges = np.empty((3, 4))
    owned = np.empty(3, dtype=np.bool_)
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue  # zero area or non-finite: nothing, at any sample
        p = positions[t]
        triangle_edges(p, sign[t], tie_x, tie_y, y_first, edges, owned)
        xmin, xmax = min(p[0, 0], p[1, 0], p[2, 0]), max(p[0, 0], p[1, 0], p[2, 0])
        ymin, ymax = min(p[0, 1], p[1, 1], p[2, 1]), max(p[0, 1], p[1, 1], p[2, 1])
        for s in range(offsets.shape[0]):
            sx, sy = offsets[s, 0], offsets[s, 1]
            # Columns and rows whose sample lies in the triangle's box, on screen (every
            # row still tests all three edges, so the box only saves work).
            c0, c1 = sample_rows(xmin, xmax, sx, width)
            r0, r1 = sample_rows(ymin, ymax, sy, height)
            if c0 > c1:
                continue
            for j in range(r0, r1 + 1):
                left, right = sample_run(edges, owned, sx, j + sy, c0, c1 + 1)
                if left < right:
                    out_t[n] = t
                    out_s[n] = s
                    out_y[n] = j
                    out_x0[n] = left
                    out_x1[n] = right
                    n += 1
    return n


# -- shared by the supersampler ----------------------------------------------------------------


def screen_exact(scene: Scene, rasterizer: str) -> NDArray[np.int8]:
    """The exact area sign of each triangle (0: non-finite or zero area, drawn as nothing),
    after refusing the first finite triangle whose coordinates leave the exact expansions'
    range (a nonzero magnitude below 2**-450 or above 2**450) with ValueError naming it."""
    safe = np.empty(len(scene), dtype=np.bool_)
    sign = orientation(scene.positions, safe)
    finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
    beyond = np.flatnonzero(finite & ~safe)
    if beyond.size:
        t = int(beyond[0])
        raise ValueError(
            f"{rasterizer}: triangle {t} has a coordinate of magnitude outside [2**-450, 2**450] "
            f"({scene.positions[t].tolist()}); exact edge tests in float expansions do not reach it"
        )
    return sign


def row_bound(positions: NDArray[np.float64], sign: NDArray[np.int8], height: int) -> NDArray[np.int64]:
    """Per triangle, an upper bound on the rows any one sample's run may occupy (0 for
    triangles drawn as nothing); computed in floats, clamped before any integer."""
    ys = np.where(sign[:, None] != 0, positions[:, :, 1], 0.0)
    rows = np.clip(np.ceil(ys.max(axis=1)) - np.floor(ys.min(axis=1)) + 2.0, 0.0, float(height))
    return np.where(sign != 0, rows, 0.0).astype(np.int64)


def multisample_spans(scene: Scene, convention: Convention, name: str) -> tuple[NDArray[np.int64], ...]:
    """The exact runs of every (triangle, sample, row): ``triangle, sample, y, x0, x1``,
    (S,) int64 each, sorted by triangle, sample and row."""
    offsets = np.ascontiguousarray(convention.samples, dtype=np.float64).reshape(-1, 2)
    sign = screen_exact(scene, name)
    positions = frozen(scene.positions)
    capacity = int(row_bound(scene.positions, sign, scene.height).sum()) * offsets.shape[0]
    t, y, x0, x1 = span_buffers(capacity)
    sample = np.empty(capacity, dtype=np.int64)
    n = _kernel(positions, sign, *convention.tie_perturbation, frozen(offsets), scene.width, scene.height,
                t, sample, y, x0, x1)
    return t[:n], sample[:n], y[:n], x0[:n], x1[:n]


def _interpolate_samples(scene: Scene, spans: tuple[NDArray[np.int64], ...],
                         offsets: Sequence[tuple[float, float]]) -> NDArray[np.float64] | None:
    """Attributes at each fragment's sample point, one row per fragment in span order:
    the barycentric interpolation of :mod:`rasterizers._common`, one sample at a time."""
    if scene.attributes is None:
        return None
    t, sample, y, x0, x1 = spans
    starts = pixel_offsets(x0, x1)
    out = np.empty((int(starts[-1]), scene.n_attributes))
    for s, offset in enumerate(offsets):  # one pass per sample of the pattern
        mine = np.flatnonzero(sample == s)
        if not mine.size:
            continue
        part = tuple(np.ascontiguousarray(a[mine]) for a in (t, y, x0, x1))
        values = interpolate_barycentric(scene, scene.positions, part, mine.size, offset)
        assert values is not None
        out[expand(starts[mine], (x1 - x0)[mine])] = values
    return out


class MultisamplePineda:
    """Pineda edge functions at each sample of a multisample pattern, exact per sample.

    Parameters
    ----------
    samples : int or sequence of (x, y)
        A standard pattern's count (1, 2, 4, 8, 16: D3D11 / Vulkan locations) or the
        offsets themselves (:func:`harness.contract.samples.pattern`). Default 4.
    tie : str
        Any of :data:`harness.contract.conventions.TIE_RULES` (default top-left), applied at every
        sample.

    Examples
    --------
    The standard 4x pattern under the hypotenuse x + y = 2: in the pixels beside it,
    samples 0 and 2 lie inside, samples 1 and 3 outside.

    >>> cov = MultisamplePineda(4).rasterize(Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]]))
    >>> cov.sample.tolist(), cov.y.tolist(), cov.x1.tolist()
    ([0, 0, 1, 2, 2, 3], [0, 1, 0, 0, 1, 0], [2, 1, 1, 2, 1, 1])
    >>> [cov.layer(s).counts(2, 2).tolist() for s in range(4)]
    [[[1, 1], [1, 0]], [[1, 0], [0, 0]], [[1, 1], [1, 0]], [[1, 0], [0, 0]]]
    """

    def __init__(self, samples: int | Iterable[Sequence[float]] = 4, tie: TieRule = "top-left") -> None:
        if tie not in TIE_RULES:
            raise ValueError(f"pineda_msaa: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        self.convention = Convention(samples=samples, tie=tie)
        count = self.convention.n_samples
        standard = isinstance(samples, (int, np.integer)) and not isinstance(samples, bool)
        self.name = f"pineda_msaa{count}" if standard else f"pineda_msaa{count}_custom"
        if tie != "top-left":
            self.name += f"_{tie}"

    def rasterize(self, scene: Scene) -> Coverage:
        spans = multisample_spans(scene, self.convention, self.name)
        attributes = _interpolate_samples(scene, spans, self.convention.samples)
        t, sample, y, x0, x1 = spans
        return Coverage(t, y, x0, x1, attributes, sample)


class PinedaMSAA4(MultisamplePineda):
    """:class:`MultisamplePineda` with the standard 4x pattern (entry point ``pineda_msaa4``)."""

    def __init__(self) -> None:
        super().__init__(4)


class PinedaMSAA8(MultisamplePineda):
    """:class:`MultisamplePineda` with the standard 8x pattern (entry point ``pineda_msaa8``)."""

    def __init__(self) -> None:
        super().__init__(8)
