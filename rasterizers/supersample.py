"""``supersample4``: n x n regular-grid supersampling, the box-filter anti-aliaser (issue 14).

Each pixel holds n x n samples at the offsets ((i + 0.5) / n, (j + 0.5) / n); n is a power
of two, so the offsets are dyadic and every sample point is an exact float. Each sample is
decided exactly under the tie rule by the multisample edge walk
(:func:`rasterizers.multisample.sample_run`, exact tests), and a pixel's alpha is the
share of its samples the triangle covers: ``covered / n**2``, a multiple of 1/n**2, so
``levels = n**2 + 1``. Per triangle and row, each sample's run adds +1 and -1 at its ends
into a row of cells; a prefix sum counts the samples covered in each pixel.

Convention: area coverage *supersampled* on the n x n grid (``samples`` = the grid),
``top-left`` ties at every sample, judged exactly against the share of samples
(:func:`harness.oracle.coverage.sample_shares`). How far the share strays from the true area --
up to a whole pixel's worth along an edge, in n**2 coarse steps as it moves -- is what the
popping and accuracy checks measure, not a broken promise. Triangles beyond the exact
tests' range are refused as :class:`rasterizers.multisample.MultisamplePineda` refuses
them. No attributes (``interpolates = False``).
"""

from __future__ import annotations

import numba
import numpy as np

from harness.contract.conventions import MAX_AREA_SAMPLES, TIE_RULES, Convention, TieRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from rasterizers.area_scanline import emit_row, first_capacity
from rasterizers.multisample import sample_rows, sample_run, screen_exact, triangle_edges

__all__ = ["Supersampler", "Supersampler4", "grid_pattern"]


def grid_pattern(n: int) -> tuple[tuple[float, float], ...]:
    """The n x n grid's offsets, row by row: ((i + 0.5) / n, (j + 0.5) / n).

    >>> grid_pattern(2)
    ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75))
    """
    return tuple(((i + 0.5) / n, (j + 0.5) / n) for j in range(n) for i in range(n))


@numba.njit(cache=True, error_model="numpy")
def _kernel(positions, sign, tie_x, tie_y, y_first, offsets, width, height, block, alpha):  # type: ignore[no-untyped-def]
    """Per triangle and row, each sample's exact run (the multisample edge walk) counted
    into a row of cells; the runs of covered pixels come out with their share of samples."""
    count = offsets.shape[0]
    hits = np.zeros(width + 1, dtype=np.int64)
    shares = np.zeros(width)
    edges = np.empty((3, 4))
    owned = np.empty(3, dtype=np.bool_)
    first = np.empty(count, dtype=np.int64)
    last = np.empty(count, dtype=np.int64)
    n = 0
    m = 0
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue  # zero area or non-finite: nothing, at any sample
        p = positions[t]
        triangle_edges(p, sign[t], tie_x, tie_y, y_first, edges, owned)
        xmin, xmax = min(p[0, 0], p[1, 0], p[2, 0]), max(p[0, 0], p[1, 0], p[2, 0])
        ymin, ymax = min(p[0, 1], p[1, 1], p[2, 1]), max(p[0, 1], p[1, 1], p[2, 1])
        r0, r1 = height, -1
        for s in range(count):
            first[s], last[s] = sample_rows(ymin, ymax, offsets[s, 1], height)
            if first[s] <= last[s]:
                r0, r1 = min(r0, first[s]), max(r1, last[s])
        for j in range(r0, r1 + 1):
            lo, hi = width, 0
            for s in range(count):
                if j < first[s] or j > last[s]:
                    continue
                sx = offsets[s, 0]
                c0, c1 = sample_rows(xmin, xmax, sx, width)
                left, right = sample_run(edges, owned, sx, j + offsets[s, 1], c0, c1 + 1)
                if left < right:
                    hits[left] += 1  # a difference array: +1 where a sample's run starts,
                    hits[right] -= 1  # -1 where it ends
                    lo, hi = min(lo, left), max(hi, right)
            if lo >= hi:
                continue
            covered = 0
            for c in range(lo, hi):
                covered += hits[c]
                hits[c] = 0
                shares[c] = covered / count  # exact: the count is a power of two
            hits[hi] = 0
            block, alpha, n, m = emit_row(t, j, shares, lo, hi - 1, block, alpha, n, m)
    return block, alpha, n, m


class Supersampler:
    """n x n grid supersampling with exact per-sample tests and the top-left rule.

    Parameters
    ----------
    n : int
        Samples per side, a power of two from 1 to 16 (a supersampled area convention
        holds up to :data:`harness.contract.conventions.MAX_AREA_SAMPLES` = 256; default 4: 16
        samples, 17 levels).
    tie : str
        Any of :data:`harness.contract.conventions.TIE_RULES` (default top-left).

    Examples
    --------
    >>> cov = Supersampler(2).rasterize(Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]]))
    >>> cov.x0.tolist(), cov.x1.tolist(), cov.alpha.tolist()
    ([0, 0], [2, 1], [1.0, 0.25, 0.25])
    """

    interpolates = False

    def __init__(self, n: int = 4, tie: TieRule = "top-left") -> None:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1 or n & (n - 1) or n * n > MAX_AREA_SAMPLES:
            raise ValueError(f"supersample: n must be a power of two from 1 to 16 (at most {MAX_AREA_SAMPLES} samples), "
                             f"not {n!r}")
        if tie not in TIE_RULES:
            raise ValueError(f"supersample: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        self.n = int(n)
        self.name = f"supersample{self.n}" + ("" if tie == "top-left" else f"_{tie}")
        self.convention = Convention(coverage="area", samples=grid_pattern(self.n), tie=tie, levels=self.n**2 + 1)

    def rasterize(self, scene: Scene) -> Coverage:
        sign = screen_exact(scene, self.name)
        offsets = frozen(np.array(self.convention.samples, dtype=np.float64))
        spans, pixels = first_capacity(scene.positions, sign, scene.width, scene.height)
        block, alpha = np.empty((4, spans), dtype=np.int64), np.empty(pixels)
        block, alpha, n, m = _kernel(frozen(scene.positions), sign, *self.convention.tie_perturbation, offsets,
                                     scene.width, scene.height, block, alpha)
        return Coverage(block[0, :n], block[1, :n], block[2, :n], block[3, :n], alpha=alpha[:m])


class Supersampler4(Supersampler):
    """:class:`Supersampler` on the 4 x 4 grid (entry point ``supersample4``)."""

    def __init__(self) -> None:
        super().__init__(4)
