"""Pieces the reference rasterizers share: input checks, span buffers, interpolation."""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen, orientation
from harness.oracle.coverage import interpolate_kernel as barycentric_kernel

__all__ = ["check_range", "screen_triangles", "row_capacity", "interpolate_planes", "interpolate_barycentric", "build_coverage"]


@numba.njit(cache=True)
def _first_beyond(positions, limit):  # type: ignore[no-untyped-def]
    """Index of the first finite triangle with a coordinate beyond +/-limit, or -1."""
    for t in range(positions.shape[0]):
        finite = True
        big = False
        for v in range(3):
            for c in range(2):
                value = positions[t, v, c]
                if not np.isfinite(value):
                    finite = False
                elif abs(value) > limit:
                    big = True
        if finite and big:
            return t
    return -1


def check_range(scene: Scene, limit: float, rasterizer: str, why: str) -> None:
    """Raise ValueError naming the first finite triangle with a coordinate beyond
    ``limit``: the rasterizer cannot draw it right, so it refuses rather than guesses.
    Non-finite triangles are not an error: they cover nothing."""
    t = int(_first_beyond(frozen(scene.positions), limit))
    if t >= 0:
        raise ValueError(
            f"{rasterizer}: triangle {t} has a coordinate beyond +/-{limit:g} px "
            f"({scene.positions[t].tolist()}); {why}"
        )


def screen_triangles(scene: Scene, limit: float, rasterizer: str, why: str) -> NDArray[np.int8]:
    """:func:`check_range`, then the exact area sign of each triangle (0: non-finite or
    zero area, drawn as nothing)."""
    check_range(scene, limit, rasterizer, why)
    return orientation(scene.positions)


@numba.njit(cache=True)
def row_capacity(positions, sign, height):  # type: ignore[no-untyped-def]
    """An upper bound on the spans a one-run-per-row rasterizer emits."""
    total = 0
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue
        ymin = min(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        ymax = max(positions[t, 0, 1], positions[t, 1, 1], positions[t, 2, 1])
        total += min(int(np.ceil(ymax) - np.floor(ymin)) + 2, height)
    return total


def build_coverage(scene: Scene, spans: tuple[NDArray, ...], n: int, attributes: NDArray | None) -> Coverage:
    t, y, x0, x1 = (a[:n] for a in spans)
    return Coverage(t, y, x0, x1, attributes)


def _values_and_inverse_w(scene: Scene) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    assert scene.attributes is not None
    if scene.w is None:
        return frozen(scene.attributes), frozen(np.ones((len(scene), 3))), False
    with np.errstate(divide="ignore", invalid="ignore"):
        return frozen(scene.attributes), frozen(1.0 / scene.w), True


@numba.njit(cache=True)
def _plane_kernel(positions, values, inv_w, perspective, span_t, span_y, span_x0, span_x1, span_edge_x, sx, sy, out):  # type: ignore[no-untyped-def]
    k_count = values.shape[2]
    row = 0
    q = np.empty(k_count + 1)
    dqdx = np.empty(k_count + 1)
    dqdy = np.empty(k_count + 1)
    for s in range(span_t.size):
        t = span_t[s]
        p = positions[t]
        x0, y0 = p[0, 0], p[0, 1]
        ex1, ey1 = p[1, 0] - x0, p[1, 1] - y0
        ex2, ey2 = p[2, 0] - x0, p[2, 1] - y0
        area = ex1 * ey2 - ex2 * ey1
        ys = span_y[s] + sy
        xl = span_edge_x[s]
        for k in range(k_count + 1):
            # Interpolated quantities: a/w for each attribute, and 1/w last (1 when affine).
            if k < k_count:
                v0 = values[t, 0, k] * inv_w[t, 0]
                v1 = values[t, 1, k] * inv_w[t, 1]
                v2 = values[t, 2, k] * inv_w[t, 2]
            else:
                v0, v1, v2 = inv_w[t, 0], inv_w[t, 1], inv_w[t, 2]
            dqdx[k] = ((v1 - v0) * ey2 - (v2 - v0) * ey1) / area
            dqdy[k] = ((v2 - v0) * ex1 - (v1 - v0) * ex2) / area
            # Walk the left edge to this row (the subpixel-corrected edge x), then correct
            # by the x error between the edge and the first sample (subtexel correction).
            at_edge = v0 + dqdx[k] * (xl - x0) + dqdy[k] * (ys - y0)
            q[k] = at_edge + dqdx[k] * (span_x0[s] + sx - xl)
        for _ in range(span_x0[s], span_x1[s]):
            w_here = q[k_count] if perspective else 1.0
            for k in range(k_count):
                out[row, k] = q[k] / w_here
            for k in range(k_count + 1):
                q[k] += dqdx[k]
            row += 1


def interpolate_planes(
    scene: Scene, spans: tuple[NDArray, ...], n: int, edge_x: NDArray[np.float64], sample: tuple[float, float]
) -> NDArray[np.float64] | None:
    """Scanline interpolation: plane gradients, value at the left edge, subtexel-corrected
    to the first sample, stepped by d/dx along the span (a/w and 1/w when perspective)."""
    if scene.attributes is None:
        return None
    t, y, x0, x1 = (a[:n] for a in spans)
    values, inv_w, perspective = _values_and_inverse_w(scene)
    out = np.empty((int((x1 - x0).sum()), scene.n_attributes))
    _plane_kernel(frozen(scene.positions), values, inv_w, perspective, t, y, x0, x1, edge_x[:n], sample[0], sample[1], out)
    return out


def interpolate_barycentric(
    scene: Scene, positions: NDArray[np.float64], spans: tuple[NDArray, ...], n: int, sample: tuple[float, float]
) -> NDArray[np.float64] | None:
    """Edge-function interpolation: l_i = w_i / (w0 + w1 + w2) at each sample, divided
    through by w per vertex when perspective."""
    if scene.attributes is None:
        return None
    t, y, x0, x1 = (a[:n] for a in spans)
    values, inv_w, perspective = _values_and_inverse_w(scene)
    out = np.empty((int((x1 - x0).sum()), scene.n_attributes))
    barycentric_kernel(frozen(positions), values, inv_w, perspective, t, y, x0, x1, sample[0], sample[1], out)
    return out
