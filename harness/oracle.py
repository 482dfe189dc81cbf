"""The exact oracle: what any declared convention says a scene must cover.

For each triangle and each row, every edge bounds the covered sample columns from one
side (a triangle is the intersection of three half-planes, so a row's covered samples
form one run). The bound is first estimated in float, then settled exactly at the
boundary pixel with :func:`harness.exact.orient2d_sign` -- a float filter with an exact
expansion fallback -- stepping or bisecting until the exact predicate agrees. No epsilon
is involved anywhere. Triangles with coordinates beyond the expansions' safe range
(|c| > 2**450, or nonzero |c| < 2**-450) take an exact rational path in Python.

Attributes are interpolated at each covered pixel's sample point from the snapped
positions: affine, or perspective-correct ``sum(l_i a_i / w_i) / sum(l_i / w_i)`` when
the scene has ``w``.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import NDArray

from harness.api import Coverage, Scene, _expand, _span_pixel_offsets
from harness.conventions import Convention, snap
from harness.exact import in_safe_range, orient2d_sign, orientation

__all__ = ["exact_coverage", "exact_coverage_python", "prepare_triangles", "PreparedTriangles"]


class PreparedTriangles:
    """Triangles after snapping, culling and orienting, ready for a coverage kernel.

    Attributes
    ----------
    index : (M,) int64
        Scene index of each surviving triangle.
    positions : (M, 3, 2) float64
        Snapped vertices, reordered so that the signed area is positive.
    vertex_order : (M, 3) int64
        Which scene vertex each row of ``positions`` came from.
    owned : (M, 3) bool
        Whether edge k (vertex k to vertex k+1) owns samples lying exactly on it.
    """

    __slots__ = ("index", "positions", "vertex_order", "owned")

    def __init__(self, scene: Scene, convention: Convention) -> None:
        snapped = snap(scene.positions, convention.subpixel_bits)
        sign = orientation(snapped)  # 0 for non-finite and zero-area triangles
        keep = sign != 0
        if convention.cull == "cw":
            keep &= sign < 0
        elif convention.cull == "ccw":
            keep &= sign > 0
        self.index = np.flatnonzero(keep).astype(np.int64)
        order = np.tile(np.arange(3, dtype=np.int64), (self.index.size, 1))
        # Orient every triangle clockwise on screen (A > 0): the interior is where all
        # three edge functions are positive.
        flip = sign[self.index] < 0
        order[flip] = (0, 2, 1)
        self.vertex_order = order
        self.positions = np.ascontiguousarray(
            np.take_along_axis(snapped[self.index], order[:, :, None], axis=1)
        )
        a = self.positions
        b = np.roll(self.positions, -1, axis=1)  # edge k: v[k] -> v[k+1]
        # With A > 0 the interior lies on the side of (-dy, dx): a horizontal edge with
        # dx > 0 has the interior below it (top edge); a non-horizontal edge with dy < 0
        # has it to its right (left edge). Comparisons, not differences: no overflow.
        horizontal = b[..., 1] == a[..., 1]
        top = horizontal & (b[..., 0] > a[..., 0])
        bottom = horizontal & (b[..., 0] < a[..., 0])
        left = b[..., 1] < a[..., 1]
        right = b[..., 1] > a[..., 1]
        vertical_owner = top if convention.owns_top else bottom
        side_owner = left if convention.owns_left else right
        self.owned = np.ascontiguousarray(vertical_owner | side_owner)


def prepare_triangles(scene: Scene, convention: Convention) -> PreparedTriangles:
    """Snap, cull, orient and classify the edges of a scene's triangles."""
    return PreparedTriangles(scene, convention)


# -- the compiled span kernel -------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _inside(ax, ay, bx, by, px, py, owned):  # type: ignore[no-untyped-def]
    s = orient2d_sign(ax, ay, bx, by, px, py)
    # A sample exactly on the edge belongs to it only when the tie rule owns the edge.
    return s > 0 or (s == 0 and owned)


@numba.njit(cache=True)
def _settle(ax, ay, bx, by, owned, sx, ys, width, estimate, lower):  # type: ignore[no-untyped-def]
    """Smallest column i in [0, width] where g(i) holds, g monotone false -> true, with
    g(i) = inside(i) for a lower bound (dy < 0) and not inside(i) for an upper bound;
    g(width) is taken as true. Starts from the float estimate, then steps or bisects."""
    c = min(max(estimate, 0), width)
    if c < width and (_inside(ax, ay, bx, by, c + sx, ys, owned) != lower):
        # g(c) is false: the answer lies right of c.
        c += 1
        if c >= width or (_inside(ax, ay, bx, by, c + sx, ys, owned) == lower):
            return c
        lo, hi = c, width
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _inside(ax, ay, bx, by, mid + sx, ys, owned) == lower:
                hi = mid
            else:
                lo = mid
        return hi
    # g(c) is true (or c == width): the answer is c or lies left of it.
    if c == 0 or (_inside(ax, ay, bx, by, c - 1 + sx, ys, owned) != lower):
        return c
    c -= 1
    if c == 0 or (_inside(ax, ay, bx, by, c - 1 + sx, ys, owned) != lower):
        return c
    lo, hi = -1, c - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _inside(ax, ay, bx, by, mid + sx, ys, owned) == lower:
            hi = mid
        else:
            lo = mid
    return hi


@numba.njit(cache=True, inline="always")
def _estimate_column(ax, ay, bx, by, sx, ys, width):  # type: ignore[no-untyped-def]
    xc = ax + (bx - ax) * ((ys - ay) / (by - ay))
    e = xc - sx
    if not e > -1.0:  # also catches NaN
        return 0
    if e > width:
        return width
    return int(math.ceil(e))


@numba.njit(cache=True)
def _row_range(ymin, ymax, sy, height):  # type: ignore[no-untyped-def]
    # floor(fl(ymin - sy)) <= the first exact row and ceil(fl(ymax - sy)) >= the last:
    # rounding is monotone and integers are representable, so the range is conservative.
    lo = ymin - sy
    hi = ymax - sy
    if hi < 0.0 or lo > height - 1:
        return 0, -1
    first = 0 if lo < 0.0 else int(math.floor(lo))
    last = height - 1 if hi > height - 1 else int(math.ceil(hi))
    return first, last


@numba.njit(cache=True)
def _capacity(positions, sy, height):  # type: ignore[no-untyped-def]
    total = 0
    for t in range(positions.shape[0]):
        p = positions[t]
        ymin = min(p[0, 1], p[1, 1], p[2, 1])
        ymax = max(p[0, 1], p[1, 1], p[2, 1])
        first, last = _row_range(ymin, ymax, sy, height)
        total += max(last - first + 1, 0)
    return total


@numba.njit(cache=True)
def _span_kernel(positions, owned, sx, sy, width, height, out_t, out_y, out_x0, out_x1):  # type: ignore[no-untyped-def]
    n = 0
    for t in range(positions.shape[0]):
        p = positions[t]
        ymin = min(p[0, 1], p[1, 1], p[2, 1])
        ymax = max(p[0, 1], p[1, 1], p[2, 1])
        first, last = _row_range(ymin, ymax, sy, height)
        for j in range(first, last + 1):
            ys = j + sy
            left = 0
            right = width
            for k in range(3):
                ax, ay = p[k, 0], p[k, 1]
                bx, by = p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
                if ay == by:
                    # Horizontal edge: E = (bx - ax) * (ys - ay), its sign from comparisons.
                    if ys == ay:
                        inside = owned[t, k]
                    else:
                        inside = (bx > ax) == (ys > ay)
                    if not inside:
                        right = 0
                        break
                    continue
                est = _estimate_column(ax, ay, bx, by, sx, ys, width)
                if by < ay:  # E grows with x: this edge bounds the run from the left
                    left = max(left, _settle(ax, ay, bx, by, owned[t, k], sx, ys, width, est, True))
                else:
                    right = min(right, _settle(ax, ay, bx, by, owned[t, k], sx, ys, width, est, False))
                if left >= right:
                    break
            if left < right:
                out_t[n] = t
                out_y[n] = j
                out_x0[n] = left
                out_x1[n] = right
                n += 1
    return n


@numba.njit(cache=True)
def interpolate_kernel(positions, values, inv_w, perspective, span_t, span_y, span_x0, span_x1, sx, sy, out):  # type: ignore[no-untyped-def]
    """Barycentric interpolation at each sample: l_i = E_i / (E_0 + E_1 + E_2)."""
    k_count = values.shape[2]
    row = 0
    for s in range(span_t.size):
        t = span_t[s]
        p = positions[t]
        ys = span_y[s] + sy
        for i in range(span_x0[s], span_x1[s]):
            xs = i + sx
            e0 = (p[2, 0] - p[1, 0]) * (ys - p[1, 1]) - (p[2, 1] - p[1, 1]) * (xs - p[1, 0])
            e1 = (p[0, 0] - p[2, 0]) * (ys - p[2, 1]) - (p[0, 1] - p[2, 1]) * (xs - p[2, 0])
            e2 = (p[1, 0] - p[0, 0]) * (ys - p[0, 1]) - (p[1, 1] - p[0, 1]) * (xs - p[0, 0])
            if perspective:
                e0 *= inv_w[t, 0]
                e1 *= inv_w[t, 1]
                e2 *= inv_w[t, 2]
            total = e0 + e1 + e2
            for k in range(k_count):
                out[row, k] = (e0 * values[t, 0, k] + e1 * values[t, 1, k] + e2 * values[t, 2, k]) / total
            row += 1


# -- the exact rational path (extreme magnitudes, and a cross-check in tests) ------------


def _rows_python(
    p: NDArray[np.float64], owned: NDArray[np.bool_], sx: float, sy: float, width: int, height: int
) -> list[tuple[int, int, int]]:
    """Exact (row, x0, x1) runs of one oriented triangle, in rational arithmetic."""
    v = [(Fraction(p[k, 0]), Fraction(p[k, 1])) for k in range(3)]
    fsx, fsy = Fraction(sx), Fraction(sy)
    ys_all = [q[1] for q in v]
    first = max(0, math.ceil(min(ys_all) - fsy))
    last = min(height - 1, math.floor(max(ys_all) - fsy))
    runs = []
    for j in range(first, last + 1):
        ys = j + fsy
        left, right = 0, width
        for k in range(3):
            (ax, ay), (bx, by) = v[k], v[(k + 1) % 3]
            if ay == by:
                inside = bool(owned[k]) if ys == ay else (bx > ax) == (ys > ay)
                if not inside:
                    right = 0
                continue
            xc = ax + (bx - ax) * (ys - ay) / (by - ay) - fsx  # crossing, in column units
            if by < ay:  # inside when i > xc (i >= xc if owned)
                left = max(left, math.ceil(xc) if owned[k] else math.floor(xc) + 1)
            else:  # inside when i < xc (i <= xc if owned)
                right = min(right, math.floor(xc) + 1 if owned[k] else math.ceil(xc))
        if left < right:
            runs.append((j, left, right))
    return runs


def _barycentric_planes(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """(3, 3) float64: l_i(x, y) = c[i,0] + c[i,1]*x + c[i,2]*y, coefficients rounded once
    from their exact rational values (no cancellation, whatever the magnitudes)."""
    v = [(Fraction(p[k, 0]), Fraction(p[k, 1])) for k in range(3)]
    area = (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[1][1] - v[0][1]) * (v[2][0] - v[0][0])
    planes = np.empty((3, 3))
    for i in range(3):
        (ax, ay), (bx, by) = v[(i + 1) % 3], v[(i + 2) % 3]
        # E_ab(x, y) = (bx-ax)*(y-ay) - (by-ay)*(x-ax), split into constant, x and y parts.
        planes[i] = [
            float((-(bx - ax) * ay + (by - ay) * ax) / area),
            float(-(by - ay) / area),
            float((bx - ax) / area),
        ]
    return planes


def _interpolate_python(
    planes: NDArray[np.float64],
    values: NDArray[np.float64],
    inv_w: NDArray[np.float64] | None,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
) -> NDArray[np.float64]:
    weights = planes[:, 0][None, :] + x[:, None] * planes[:, 1] + y[:, None] * planes[:, 2]
    if inv_w is not None:
        weights = weights * inv_w[None, :]
    return (weights @ values) / weights.sum(axis=1, keepdims=True)


# -- public entry points ------------------------------------------------------------------


def _assemble(
    scene: Scene,
    prepared: PreparedTriangles,
    local_t: NDArray[np.int64],
    y: NDArray[np.int64],
    x0: NDArray[np.int64],
    x1: NDArray[np.int64],
    attributes: NDArray[np.float64] | None,
) -> Coverage:
    triangle = prepared.index[local_t]
    order = np.argsort(triangle, kind="stable")
    if not np.array_equal(order, np.arange(order.size)):
        if attributes is not None:
            offsets = _span_pixel_offsets(x0, x1)
            attributes = attributes[_expand(offsets[order], (x1 - x0)[order])]
        triangle, y, x0, x1 = triangle[order], y[order], x0[order], x1[order]
    return Coverage(triangle, y, x0, x1, attributes)


def _vertex_values(scene: Scene, prepared: PreparedTriangles) -> tuple[NDArray, NDArray | None]:
    assert scene.attributes is not None
    values = np.take_along_axis(
        scene.attributes[prepared.index], prepared.vertex_order[:, :, None], axis=1
    )
    inv_w = None
    if scene.w is not None:
        inv_w = 1.0 / np.take_along_axis(scene.w[prepared.index], prepared.vertex_order, axis=1)
    return np.ascontiguousarray(values), inv_w


def exact_coverage(scene: Scene, convention: Convention) -> Coverage:
    """Exactly what ``convention`` says ``scene`` covers, with reference attributes.

    Parameters
    ----------
    scene : Scene
    convention : Convention

    Returns
    -------
    Coverage
        Spans sorted by triangle then row, clipped to the viewport. Non-finite,
        zero-area and culled triangles cover nothing. ``attributes`` is (P, K) when the
        scene has attributes, interpolated at each covered sample (perspective-correct
        when the scene has ``w``).

    Examples
    --------
    A right triangle whose hypotenuse runs through four pixel centres. The hypotenuse is
    a right edge (the interior lies to its left), so the top-left rule leaves those
    samples out and the bottom-right rule takes them in.

    >>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    >>> exact_coverage(scene, Convention()).counts(4, 4)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [1, 0, 0, 0],
           [0, 0, 0, 0]], dtype=int32)
    >>> exact_coverage(scene, Convention(tie="bottom-right")).counts(4, 4)
    array([[1, 1, 1, 1],
           [1, 1, 1, 0],
           [1, 1, 0, 0],
           [1, 0, 0, 0]], dtype=int32)
    """
    prepared = PreparedTriangles(scene, convention)
    sx, sy = convention.sample
    safe = in_safe_range(prepared.positions, axis=(1, 2))
    fast = np.flatnonzero(safe)
    slow = np.flatnonzero(~safe)

    pos_fast = np.ascontiguousarray(prepared.positions[fast])
    owned_fast = np.ascontiguousarray(prepared.owned[fast])
    capacity = int(_capacity(pos_fast, sy, scene.height)) if fast.size else 0
    out = [np.empty(capacity, dtype=np.int64) for _ in range(4)]
    n = int(_span_kernel(pos_fast, owned_fast, sx, sy, scene.width, scene.height, *out)) if fast.size else 0
    span_t, span_y, span_x0, span_x1 = (a[:n] for a in out)

    attributes = None
    values = inv_w = None
    if scene.attributes is not None:
        values, inv_w = _vertex_values(scene, prepared)
        attributes = np.empty((int((span_x1 - span_x0).sum()), scene.n_attributes))
        if n:
            interpolate_kernel(
                pos_fast,
                values[fast],
                inv_w[fast] if inv_w is not None else np.ones((fast.size, 3)),
                inv_w is not None,
                span_t,
                span_y,
                span_x0,
                span_x1,
                sx,
                sy,
                attributes,
            )
    local_t = fast[span_t]

    if slow.size:
        extra: list[tuple[int, int, int, int]] = []
        extra_values = []
        for m in slow:
            runs = _rows_python(prepared.positions[m], prepared.owned[m], sx, sy, scene.width, scene.height)
            extra.extend((m, j, a, b) for j, a, b in runs)
            if values is not None and runs:
                cols = np.concatenate([np.arange(a, b) for _, a, b in runs]) + sx
                rows = np.concatenate([np.full(b - a, j) for j, a, b in runs]) + sy
                planes = _barycentric_planes(prepared.positions[m])
                extra_values.append(
                    _interpolate_python(planes, values[m], None if inv_w is None else inv_w[m], cols, rows)
                )
        if extra:
            e = np.array(extra, dtype=np.int64)
            local_t = np.concatenate([local_t, e[:, 0]])
            span_y = np.concatenate([span_y, e[:, 1]])
            span_x0 = np.concatenate([span_x0, e[:, 2]])
            span_x1 = np.concatenate([span_x1, e[:, 3]])
            if attributes is not None:
                attributes = np.concatenate([attributes, *extra_values])
    return _assemble(scene, prepared, local_t, span_y, span_x0, span_x1, attributes)


def exact_coverage_python(scene: Scene, convention: Convention) -> Coverage:
    """The oracle's spans from the rational path alone, for every triangle (no attributes).

    Slow; a second, independent implementation of the same rows for tests.
    """
    prepared = PreparedTriangles(scene, convention)
    sx, sy = convention.sample
    spans = [
        (int(prepared.index[m]), j, a, b)
        for m in range(prepared.index.size)
        for j, a, b in _rows_python(
            prepared.positions[m], prepared.owned[m], sx, sy, scene.width, scene.height
        )
    ]
    if not spans:
        return Coverage.empty()
    t, y, x0, x1 = np.array(spans, dtype=np.int64).T
    return Coverage(t, y, x0, x1)
