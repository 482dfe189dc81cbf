"""``fixed_point``: snapped integer edge functions with the top-left bias (seed 002, GPUs).

Vertices snap to ``subpixel_bits`` fractional bits (8 by default, as D3D's 16.8; 4..16
allowed), round half to even (or half away from zero, as dEQP's reference renderer, or
down). Every edge function is then an exact int64 expression, and each row's span is
solved from it exactly: for an edge whose function grows with x the first column with
``E + bias >= 0``, for one that falls with x the last, by floor division. The tie rule
is an integer bias: ``bias = 0`` on the edges it owns and ``-1`` on the others, since
for integers ``E > 0`` and ``E - 1 >= 0`` are the same test. Any of the eight tie rules
may be chosen (top-left by default).

Overflow bound. With every fixed-point coordinate (vertices and samples) within
``|c| <= 2**30 - 1``, differences stay within 2**31, products within 2**62, and an edge
function ``E = dX*dPy - dY*dPx`` within ``8 * (2**30 - 1)**2 < 2**63``: no int64 overflow.
In pixels: ``|x|, |y| < 2**(30 - bits)`` (4,194,304 px at 8 bits, 16,384 px at 16), and
the viewport must fit too. Outside that range ``rasterize`` raises ``ValueError`` naming
the triangle -- never a wrong picture.

Convention: sample (0.5, 0.5), ``top-left`` ties (or the chosen rule), snapped to
``subpixel_bits`` with the chosen rounding.
"""

from __future__ import annotations

import numba
import numpy as np

from harness.contract.conventions import TIE_RULES, Convention, SnapRounding, TieRule, owns_edge, snap
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.spans import span_buffers
from rasterizers._common import build_coverage, check_range, interpolate_barycentric

__all__ = ["FixedPoint", "MAX_FIXED"]

MAX_FIXED = 2**30 - 1  # |fixed-point coordinate| bound: 8 * MAX_FIXED**2 < 2**63


@numba.njit(cache=True)
def _kernel(fixed, half, one, tie_x, tie_y, y_first, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    edges = np.empty((3, 5), dtype=np.int64)
    for t in range(fixed.shape[0]):
        p = fixed[t]
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if area == 0:
            continue  # zero snapped area: nothing, always
        ymin = min(p[0, 1], p[1, 1], p[2, 1])
        ymax = max(p[0, 1], p[1, 1], p[2, 1])
        # Rows whose sample height j*one + half lies within [ymin, ymax].
        first = max(-((half - ymin) // one), 0)
        last = min((ymax - half) // one, height - 1)
        # per edge (vertices taken with A > 0): start point, deltas, and the tie rule as an
        # integer bias: 0 on the edges it owns, -1 elsewhere (E > 0 and E - 1 >= 0 are the
        # same test for integers)
        for k in range(3):
            a, b = (k, (k + 1) % 3) if area > 0 else ((k + 1) % 3, k)
            ax, ay, bx, by = p[a, 0], p[a, 1], p[b, 0], p[b, 1]
            edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3] = ax, ay, bx - ax, by - ay
            edges[k, 4] = 0 if owns_edge(ax, ay, bx, by, tie_x, tie_y, y_first) else -1
        for j in range(first, last + 1):
            py = j * one + half
            left = 0
            right = width
            for k in range(3):
                ax, ay, dx, dy, bias = edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3], edges[k, 4]
                # E(i) = dx*(py - ay) - dy*(i*one + half - ax) + bias = c - dy*one*i
                c = dx * (py - ay) - dy * (half - ax) + bias
                if dy == 0:
                    if c < 0:
                        right = 0
                elif dy < 0:  # E grows with i: first i with c + slope*i >= 0
                    slope = -dy * one
                    left = max(left, -(c // slope))
                else:  # E falls with i: last i with c - slope*i >= 0
                    slope = dy * one
                    right = min(right, c // slope + 1)
            if left < right:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = left
                out_x1[n] = right
                n += 1
    return n


class FixedPoint:
    """Fixed-point rasterizer: snapped vertices, exact int64 edge functions, top-left bias.

    Parameters
    ----------
    subpixel_bits : int
        Fractional bits of the vertex grid, 4..16 (default 8: 1/256 px).
    tie : str
        Any of :data:`harness.contract.conventions.TIE_RULES` (default top-left).
    snap_rounding : {"nearest-even", "half-away", "floor"}
        How vertices round onto the grid (default nearest-even).

    Examples
    --------
    >>> FixedPoint().rasterize(Scene(4, 3, [[[0.5, 0.5], [3.5, 0.5], [0.5, 2.5]]])).counts(4, 3)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    >>> FixedPoint(16).rasterize(Scene(4, 3, [[[0, 0], [1e5, 0], [0, 1]]]))  # doctest: +NORMALIZE_WHITESPACE
    Traceback (most recent call last):
    ...
    ValueError: fixed_point_16: triangle 0 has a coordinate beyond +/-16384 px ([[0.0, 0.0], [100000.0, 0.0], [0.0, 1.0]]); 16
    sub-pixel bits keep int64 edge functions exact only within +/-2**14 px
    """

    name = "fixed_point"

    def __init__(self, subpixel_bits: int = 8, tie: TieRule = "top-left", snap_rounding: SnapRounding = "nearest-even") -> None:
        if isinstance(subpixel_bits, bool) or not isinstance(subpixel_bits, int) or not 4 <= subpixel_bits <= 16:
            raise ValueError(f"fixed_point: subpixel_bits must be an integer in 4..16, not {subpixel_bits!r}")
        if tie not in TIE_RULES:
            raise ValueError(f"fixed_point: tie must be one of {', '.join(TIE_RULES)}, not {tie!r}")
        self.subpixel_bits = subpixel_bits
        self.convention = Convention(sample=(0.5, 0.5), tie=tie, subpixel_bits=subpixel_bits, snap_rounding=snap_rounding)
        parts = [str(subpixel_bits)] if subpixel_bits != 8 else []
        parts += [tie] if tie != "top-left" else []
        parts += [snap_rounding] if snap_rounding != "nearest-even" else []
        if parts:
            self.name = "fixed_point_" + "_".join(parts)

    @property
    def max_coordinate(self) -> float:
        """Largest |coordinate| in pixels whose snapped value keeps int64 arithmetic exact."""
        return float((MAX_FIXED + 1) >> self.subpixel_bits)

    def rasterize(self, scene: Scene) -> Coverage:
        bits = self.subpixel_bits
        limit = self.max_coordinate
        if max(scene.width, scene.height) > limit:
            raise ValueError(
                f"{self.name}: a {scene.width}x{scene.height} viewport exceeds the "
                f"{limit:g} px that {bits} sub-pixel bits allow"
            )
        check_range(
            scene, limit, self.name,
            f"{bits} sub-pixel bits keep int64 edge functions exact only within +/-2**{30 - bits} px",
        )
        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))  # others draw nothing
        snapped = snap(np.where(finite[:, None, None], scene.positions, 0.0), bits, self.convention.snap_rounding)
        fixed = (snapped * 2.0**bits).astype(np.int64)  # exact: snapped values are on the grid
        rows = (fixed[..., 1].max(axis=1) - fixed[..., 1].min(axis=1)) // (1 << bits) + 2
        capacity = int(np.clip(rows, 0, scene.height).sum())
        spans = span_buffers(capacity)
        n = _kernel(fixed, 1 << (bits - 1), 1 << bits, *self.convention.tie_perturbation, scene.width, scene.height, *spans)
        attributes = interpolate_barycentric(scene, snapped, spans, n, self.convention.sample)
        return build_coverage(scene, spans, n, attributes)
