"""Row-sampled area coverage: the anti-aliasing model of cairo's scan converter.

cairo (``src/cairo-tor-scan-converter.c``, the "tor" converter its image backend fills
with) computes a pixel's alpha neither as the exact area nor from point samples:

* ``GRID_Y 15`` sub-rows per pixel row, each sampled on its centre line: an edge's x is
  first evaluated at ``(2 * ytop + 1) / (2 * GRID_Y)`` (``polygon_add_edge``: ``tmp = (2 *
  ytop + 1) << GLITTER_INPUT_BITS``) and stepped by ``dxdy`` per sub-row (``step``), its
  ``cell`` the x rounded half up to ``GRID_X = 256`` (``GRID_X_BITS =
  CAIRO_FIXED_FRAC_BITS``); ``sub_row`` adds, for every sub-row, the covered span
  ``[xstart, xend)`` to the cells (``cell_list_add_subspan``): exact along x but for that
  rounding. An edge is active on the sub-rows ``[ytop, ybot)`` with ``ytop = floor(15 y +
  1/2)`` (``INPUT_TO_GRID_general``): the centre lines ``y_top < y_k <= y_bottom``.
* a pixel row in which no edge starts or ends and the edges keep their order
  (``can_do_full_row``) is not sampled: ``full_row`` / ``cell_list_render_edge`` add the
  area between the edges, each from its x at the row's top to its x at the bottom (stepped
  back half a sub-row from the sample positions, ``x1.quo -= edge->dxdy.quo / 2``: C's
  truncating halves), with its crossings of the pixel column boundaries at heights rounded
  down to 1/15 of the row (``y.quo = tmp / dx``).
* the cell area ``c`` in ``[0, GRID_XY]``, ``GRID_XY = 2 * 256 * 15 = 7680``, becomes an
  8-bit alpha by ``GRID_AREA_TO_ALPHA(c) = (c + (c << 4) + 256) >> 9 = floor(255 c / 7680 +
  1/2)``: the coverage rounded half up to 256 levels (``blit_a8``).

As conventions (:class:`harness.contract.conventions.Convention`):

* ``Convention(coverage="area", rows=n)``: *row-sampled* area coverage, the alpha of a
  triangle T at pixel (i, j) the mean of its n cross-sections with the pixel on the sub-row
  centre lines, exact along x::

      alpha = (1/n) * sum_{k=0}^{n-1} length(T ∩ {y = j + (k + 1/2)/n} ∩ [i, i+1] x R)

  (an edge active where ``y_top < y_k <= y_bottom``; rational for float input; decided
  exactly: each vertex is compared with each line by an exact product, :func:`_side`).
* ``Convention(coverage="area", rows=15, full_rows=True, input="fixed8")``: cairo's hybrid
  exactly, its integer procedure (full rows and sub-rows, the x rounding and the truncated
  half-steps) on its 24.8 input (the oracle rounds to 1/256 px, ties to even, as
  ``_cairo_fixed_from_double``; declare ``input="fixed8"`` to say so). Unquantised: the
  convention's ``levels`` (256) and tolerance judge the quantisation.

:func:`row_sampled_coverage` is the compiled oracle; :func:`exact_row_sampled_alpha` the
reference (rationals for the row-sampled model, cairo's integer procedure run uncompiled
for the hybrid), compared in tests/oracle/test_aa_models.py.

Measured (pycairo, cairo 1.16, A8, ``ANTIALIAS_DEFAULT``): cairo's procedure, with its
clipping to the surface and its edge list's tie order, lives in
:mod:`harness.oracle.row_sampled_paths` (a triangle is filled as the one contour it is);
every byte cairo writes equals the model's level on random triangles and polygons, those
crossing the surface's sides and those of 4e6 px included. Its failures on the quick suite
are real: the NaN triangles it draws and the sliver whose coverage of -5/255 wraps to 251.

The model is defined by coverage of a primitive along sample lines, so it extends to paths
as the winding oracle extends point samples: the cross-section of a path on a line is the
set of x where the fill rule holds (:mod:`harness.oracle.row_sampled_paths`).

The other libraries' models live beside this one: tiny-skia's supersampler exactly in
:mod:`harness.oracle.supersample_models` (skia's ``SkScan_AntiPath.cpp`` as tiny-skia runs
it), the analytic libraries' input grids and quantisations in their own modules; skia's
analytic AA has none (:data:`harness.oracle.supersample_models.SKIA_AAA_NOTE`).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.oracle.area import exact_area  # noqa: F401 (doctests)
from harness.oracle.row_sampled_paths import HYBRID_LIMIT, _cairo_spans, _side, exact_row_sampled_path_alpha

__all__ = ["CAIRO_ROWS", "row_sampled_coverage", "exact_row_sampled_alpha", "cairo_alpha_levels"]

# cairo-tor-scan-converter.c: #define GRID_Y 15
CAIRO_ROWS = 15


def cairo_alpha_levels(coverage: ArrayLike) -> NDArray[np.int64]:
    """cairo's ``GRID_AREA_TO_ALPHA`` for ``GRID_XY = 2*256*15``: the coverage in [0, 1]
    (as the cell area ``c = 7680 * coverage``) to an 8-bit level, ``(c + (c << 4) + 256) >> 9``.

    >>> cairo_alpha_levels([0.0, 0.5, 1.0, 1 / 7680]).tolist()
    [0, 128, 255, 0]
    """
    c = np.floor(np.asarray(coverage, dtype=np.float64) * 7680.0 + 0.5).astype(np.int64)
    return (c + (c << 4) + 256) >> 9


# -- the rational reference ------------------------------------------------------------------


def _cross_section(vertices: list[tuple[Fraction, Fraction]], y: Fraction) -> tuple[Fraction, Fraction] | None:
    """[xl, xr] of the triangle at height y, its edges active where y_top < y <= y_bottom,
    or None when the line misses it."""
    xs: list[Fraction] = []
    for k in range(3):
        (ax, ay), (bx, by) = vertices[k], vertices[(k + 1) % 3]
        if ay != by and min(ay, by) < y <= max(ay, by):  # cairo's sub-rows [ytop, ybot): half open
            xs.append(ax + (y - ay) * (bx - ax) / (by - ay))
    return (min(xs), max(xs)) if xs else None


def exact_row_sampled_alpha(triangle: ArrayLike, x: int, y: int, rows: int, full_rows: bool = False,
                            surface: tuple[int, int] | None = None) -> Fraction:
    """The row-sampled alpha of ``triangle`` at pixel (x, y), exactly (the reference);
    ``surface`` (width, height): the viewport cairo's hybrid clips to (None: unclipped).

    >>> exact_row_sampled_alpha([[0, 0], [1, 0], [0, 1]], 0, 0, 2)
    Fraction(1, 2)
    >>> exact_row_sampled_alpha([[0, 0], [1, 0], [0, 1]], 0, 0, 3)
    Fraction(1, 2)
    >>> exact_row_sampled_alpha([[0, 0], [4, 0], [0, 1]], 1, 0, 2)  # lengths 1 and 0 on y = 1/4, 3/4
    Fraction(1, 2)
    >>> exact_area(np.array([[0, 0], [4, 0], [0, 1.0]]), 1, 0)
    Fraction(5, 8)
    """
    points = np.asarray(triangle, dtype=np.float64)
    vertices = [(Fraction(float(px)), Fraction(float(py))) for px, py in points]
    if (vertices[1][0] - vertices[0][0]) * (vertices[2][1] - vertices[0][1]) == \
            (vertices[1][1] - vertices[0][1]) * (vertices[2][0] - vertices[0][0]):
        return Fraction(0)
    if full_rows:  # cairo's procedure, run on the triangle as the one contour it fills
        return exact_row_sampled_path_alpha([points], "nonzero", x, y, rows, full_rows=True, surface=surface)
    total = Fraction(0)
    for k in range(rows):
        section = _cross_section(vertices, y + Fraction(2 * k + 1, 2 * rows))
        if section is not None:
            total += max(Fraction(0), min(section[1], Fraction(x + 1)) - max(section[0], Fraction(x)))
    return total / rows


# -- the compiled oracle ----------------------------------------------------------------------


@numba.njit(cache=True)
def _section(tri, line, rows):  # type: ignore[no-untyped-def]
    """(xl, xr) of the triangle on the sample line y = (2 line + 1) / (2 rows), the edges
    active where y_top < y <= y_bottom, decided exactly; xl > xr when the line misses it."""
    lo = np.inf
    hi = -np.inf
    num = 2.0 * line + 1.0
    den = 2.0 * rows
    y = num / den
    for e in range(3):
        f = (e + 1) % 3
        ax, ay, bx, by = tri[e, 0], tri[e, 1], tri[f, 0], tri[f, 1]
        if ay == by:
            continue
        top = min(ay, by)
        bottom = max(ay, by)
        if _side(top, num, den) < 0 and _side(bottom, num, den) >= 0:
            x = ax + ((y - ay) / (by - ay)) * (bx - ax)
            # the line lies within the edge's y-range: keep x within its x-range
            x = min(max(x, min(ax, bx)), max(ax, bx))
            lo = min(lo, x)
            hi = max(hi, x)
    return lo, hi


@numba.njit(cache=True)
def _row_alphas(tri, j, rows, width, acc):  # type: ignore[no-untyped-def]
    """The row's alphas (its rows sample lines) into acc[i0:i1]; returns (i0, i1)."""
    lo = np.inf
    hi = -np.inf
    for k in range(rows):
        a, b = _section(tri, j * rows + k, rows)
        lo = min(lo, a)
        hi = max(hi, b)
    if not lo <= hi:
        return 0, 0
    i0 = max(int(math.floor(lo)), 0)
    i1 = min(int(math.floor(hi)) + 1, width)
    for i in range(i0, i1):
        acc[i] = 0.0
    for k in range(rows):
        a, b = _section(tri, j * rows + k, rows)
        if not a <= b:
            continue
        for i in range(max(int(math.floor(a)), i0), min(int(math.floor(b)) + 1, i1)):
            acc[i] += max(0.0, min(b, i + 1.0) - max(a, float(i))) / rows
    return i0, i1


@numba.njit(cache=True)
def _row_kernel(positions, active, width, height, rows, write,  # type: ignore[no-untyped-def]
                out_t, out_y, out_x0, out_x1, out_alpha):
    """Spans and alphas (write) or only their counts (not write): (spans, pixels)."""
    acc = np.zeros(width + 1)
    spans = 0
    pixels = 0
    for t in range(positions.shape[0]):
        if not active[t]:
            continue
        tri = positions[t]
        j0 = max(int(math.floor(min(tri[0, 1], tri[1, 1], tri[2, 1]))), 0)
        j1 = min(int(math.ceil(max(tri[0, 1], tri[1, 1], tri[2, 1]))), height)
        for j in range(j0, j1):
            i0, i1 = _row_alphas(tri, j, rows, width, acc)
            while i0 < i1 and acc[i0] <= 0.0:  # trim the zeros at both ends
                i0 += 1
            while i1 > i0 and acc[i1 - 1] <= 0.0:
                i1 -= 1
            if i0 >= i1:
                continue
            if write:
                out_t[spans] = t
                out_y[spans] = j
                out_x0[spans] = i0
                out_x1[spans] = i1
                for i in range(i0, i1):
                    out_alpha[pixels + i - i0] = min(acc[i], 1.0)
            pixels += i1 - i0
            spans += 1
    return spans, pixels


def row_sampled_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The oracle of a row-sampled area convention (``Convention(coverage="area", rows=n)``):
    per (triangle, pixel), the mean of its n cross-sections at the sub-row centre lines
    (with ``full_rows``: cairo's analytic full rows, module docstring), unquantised.

    Input precision, snapping and culling are the convention's; zero-area and non-finite
    triangles cover nothing.

    >>> c = row_sampled_coverage(Scene(4, 1, [[[0, 0], [4, 0], [0, 1]]]), Convention(coverage="area", rows=2))
    >>> c.x0.tolist(), c.x1.tolist(), c.alpha.tolist()
    ([0], [3], [1.0, 0.5, 0.5])
    """
    rows = convention.rows
    if rows <= 0:
        raise ValueError("row_sampled_coverage needs a convention with rows > 0")
    positions = np.ascontiguousarray(convention.snap(scene.positions), dtype=np.float64)
    sign = orientation(positions)
    active = sign != 0
    if convention.cull != "none":
        active &= sign != (1 if convention.cull == "cw" else -1)
    if convention.full_rows:
        # cairo's hybrid: each triangle filled as the one contour it is, by cairo's procedure
        # (harness.oracle.row_sampled_paths), on its 24.8 input, within its coordinate range
        active &= np.all(np.isfinite(positions), axis=(1, 2)) & np.all(np.abs(positions) < HYBRID_LIMIT, axis=(1, 2))
        kept = np.flatnonzero(active)
        if kept.size == 0:
            return Coverage.empty()
        edges = np.concatenate([positions[kept], np.roll(positions[kept], -1, axis=1)], axis=2).reshape(-1, 4)
        triangle, y, x0, x1, alpha, _ = _cairo_spans(edges, np.repeat(kept, 3), "nonzero", int(scene.width),
                                                     int(scene.height), int(rows))
        return Coverage(triangle, y, x0, x1, alpha=alpha)
    args = (positions, active, int(scene.width), int(scene.height), int(rows))
    empty_i, empty_f = np.empty(0, dtype=np.int64), np.empty(0)
    spans, pixels = _row_kernel(*args, False, empty_i, empty_i, empty_i, empty_i, empty_f)
    out = [np.empty(spans, dtype=np.int64) for _ in range(4)]
    alpha = np.empty(pixels)
    spans, pixels = _row_kernel(*args, True, *out, alpha)  # type: ignore[call-arg]
    triangle, y, x0, x1 = (o[:spans] for o in out)
    return Coverage(triangle, y, x0, x1, alpha=alpha[:pixels])
