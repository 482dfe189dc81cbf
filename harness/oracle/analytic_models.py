"""The analytic anti-aliasers' models: the exact area of the polygon as the library receives
it, then the library's own levels (issue 34).

FreeType smooth, Qt, AGG (aggdraw, matplotlib) and Blend2D compute a pixel's coverage
from the area of the outline inside it, on their input grid, and make an 8-bit level of it
their own way (:mod:`harness.contract.quantisations`, read from their sources):

* the input grid is the convention's ``input`` (``fixed6``: 26.6, FreeType and Qt;
  ``fixed8-toward-zero``: aggdraw's ``poly_coord`` and Blend2D's ``trunc_to_int`` of the
  coordinates times 256; ``fixed8-half-away``: AGG 2.4's ``iround``, matplotlib), applied
  by :meth:`Convention.snap <harness.contract.conventions.Convention.snap>` as every oracle
  applies it;
* the pixel's signed area ``S`` is the exact area of the received triangle in the pixel,
  signed by the library's orientation (:meth:`Quantisation.signed
  <harness.contract.quantisations.Quantisation.signed>`), and ``k = floor(256 S)`` --
  decided exactly: the float area (within :func:`harness.oracle.area.area_error_bound`)
  decides ``k`` unless ``256 S`` lies within that bound of a whole number, where the
  rational area (:func:`harness.oracle.area.exact_area`) does;
* the level is the quantisation's of ``k``, and alpha = level / 255.

What the model leaves out: the libraries compute the crossings of each edge with the
pixel grid in cells of 1/256 px (``ftgrays.c`` ``gray_render_line``: ``FT_UDIV``
truncates each crossing to 1/256 px; ``qgrayraster.c`` likewise; AGG
``agg_rasterizer_cells_aa.h`` ``render_hline``/``line``: ``p / dx`` per cell; Blend2D
``analyticrasterizer_p.h``: the same DDA on 24.8), so their areas are the area of a
polygon whose crossings moved by up to 1/256 px: a level off at some pixels (measured in
:mod:`harness.identify.area_probes` and in the report), beyond one at a few.

Measured (``rastercheck identify``, which fits the levels and the grid from outside:
:func:`harness.identify.area_probes.quantisation_fit`; residual = (triangle, pixel)s off the
model's level, before against the nearest level of the area with a fitted tolerance):

==================  ================  =================  ===============  ================
library             model             residual before    after            beyond one level
==================  ================  =================  ===============  ================
FreeType 2.13.2     ftgrays, 26.6     81,358             12,225 / 274,241 0 / 297,947
Qt 6.11 (PyQt6)     cells-abs, 26.6   117,110            5,442 / 274,247  38 / 297,959
aggdraw 1.4.1       cells-abs-gray8,  19,568             5,466 / 54,987   75 / 78,693
                    24.8 truncated
matplotlib 3.11.2   cells-abs         20,561             5,841 / 54,988   147 / 78,694
Blend2D 0.8.0       blend2d, 24.8     12,215             2,248 / 54,987   0 / 78,693
                    truncated
==================  ================  =================  ===============  ================

At most two levels off (aggdraw three: a cover of 254 for the model's 255 is blended to 252,
the gray-8 blend's one jump), on 92,564 random float pixels in both windings: FreeType 2
pixels two levels off, Qt 109, aggdraw 128, matplotlib 82, Blend2D 1. FreeType's are its
truncated crossings: tests/oracle/ftgrays_cells.py ports ``gray_render_line`` and draws what
FreeType draws, pixel for pixel, the two-level pixels of the quick suite included (e.g.
lattice/bits-0, triangle (48, 64), (33, 38), (63, 19), pixel (62, 19): exact area 31/60,
256 a = 132.27, model level 132; FreeType's cells hold 130.5/256: level 130). No adapter
declares its model: within one level fails a few pixels per case on the quick suite.

:func:`quantised_area_coverage` is the oracle (compiled area kernel, exact decisions);
:func:`exact_level` the reference (rationals), compared in
tests/oracle/test_analytic_models.py.
"""

from __future__ import annotations

import math
from dataclasses import fields
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.quantisations import NEAREST, Quantisation, quantisation_named
from harness.contract.scenes import Scene
from harness.geometry.exact import orient2d_sign, orientation
from harness.oracle.area import area_coverage, area_error_bound, exact_area
from harness.oracle.coverage import scene_digest

__all__ = ["levels_of", "exact_level", "quantised_area_coverage", "exact_quantised_alpha", "LEVELS"]

# the libraries' levels are bytes: alpha = level / 255
LEVELS = 256


def levels_of(quantisation: Quantisation, k: ArrayLike, fill_rule: str = "nonzero") -> NDArray[np.int64]:
    """:meth:`Quantisation.level <harness.contract.quantisations.Quantisation.level>` of every
    ``k`` (int64, two's complement as the libraries' C integers), vectorised.

    >>> from harness.contract.quantisations import QUANTISATIONS
    >>> [levels_of(q, [-256, -128, -1, 0, 1, 128, 200, 256]).tolist() for q in QUANTISATIONS.values()]
    ... # doctest: +NORMALIZE_WHITESPACE
    [[255, 127, 0, 0, 1, 128, 200, 255], [255, 128, 1, 0, 1, 128, 200, 255], [255, 127, 0, 0, 0, 127, 198, 255],
     [255, 127, 0, 0, 0, 127, 199, 255]]
    """
    k = np.asarray(k, dtype=np.int64)
    if fill_rule == "evenodd" and quantisation.evenodd == "bit8":
        out: NDArray[np.int64] = np.where(k & 0x100, ~k, k) & 0xFF
        return out
    negated = -k if quantisation.negative == "abs" else ~k
    c = np.where(k < 0, negated, k)
    if fill_rule == "evenodd":
        c = c & 511
        c = np.where(c > 256, 512 - c, c)
    if quantisation.scale == "times255":
        scaled: NDArray[np.int64] = (np.minimum(c, 256) * 255) >> 8
        return scaled
    c = np.minimum(c, 255)
    if quantisation.scale == "gray8":
        c = np.where(c == 255, 255, (255 * 255 * c) >> 16)
    return np.asarray(c, dtype=np.int64)


# -- the rational reference -------------------------------------------------------------------


def exact_level(triangle: ArrayLike, x: int, y: int, quantisation: Quantisation | str) -> int:
    """The level of pixel (x, y) for ``triangle`` (as received: snap it first), exactly:
    ``k = floor(256 S)`` of the rational signed area, then the quantisation's level.

    >>> exact_level([[0, 0], [1, 0], [0, 1]], 0, 0, "ftgrays"), exact_level([[0, 0], [0, 1], [1, 0]], 0, 0, "ftgrays")
    (128, 127)
    >>> exact_level([[0, 0], [1, 0], [0, 1]], 0, 0, "cells-abs"), exact_level([[0, 0], [0, 1], [1, 0]], 0, 0, "blend2d")
    (128, 127)
    """
    q = quantisation_named(quantisation) if isinstance(quantisation, str) else quantisation
    points = np.asarray(triangle, dtype=np.float64)
    area = exact_area(points, int(x), int(y))
    if area == 0:
        return 0
    clockwise = int(orientation(points[None])[0]) > 0
    signed = area * q.signed(clockwise)
    return q.level(math.floor(256 * signed))


def exact_quantised_alpha(positions: ArrayLike, convention: Convention, triangle: int, x: int, y: int) -> Fraction:
    """The model's alpha at one (triangle, pixel), exactly: level / 255 of the received
    (snapped) triangle; 0 when it is culled or not finite."""
    tri = convention.snap(np.asarray(positions, dtype=np.float64)[triangle : triangle + 1])
    if not np.all(np.isfinite(tri)):
        return Fraction(0)
    sign = int(orientation(tri)[0])
    if sign == 0 or (convention.cull != "none" and sign == (1 if convention.cull == "cw" else -1)):
        return Fraction(0)
    return Fraction(exact_level(tri[0], x, y, convention.quantisation), LEVELS - 1)


# -- the oracle -------------------------------------------------------------------------------

# the exact decisions made, by (triangle as received, x, y): identify scores every quantisation
# and input grid on the same probes, whose areas are whole 256ths by design (each decided once)
_DECIDED: dict[tuple[bytes, int, int], tuple[int, bool]] = {}
_DECIDED_LIMIT = 1 << 20


def _clipped(points: list[tuple[int, int, int]], axis: int, bound: int, keep: int) -> list[tuple[int, int, int]]:
    """Sutherland-Hodgman on homogeneous integer points (X, Y, D), D > 0, standing for
    (X/D, Y/D): the part where ``keep * (coordinate - bound) >= 0``. The side of a point is
    the sign of the linear form ``keep * (P[axis] - bound * D)``, so the crossing of P and
    Q is ``f(Q) P - f(P) Q`` (exact, no division; its D made positive)."""
    out: list[tuple[int, int, int]] = []
    n = len(points)
    for i in range(n):
        p, q = points[i], points[(i + 1) % n]
        fp = keep * (p[axis] - bound * p[2])
        fq = keep * (q[axis] - bound * q[2])
        if fp >= 0:
            out.append(p)
        if (fp > 0 > fq) or (fp < 0 < fq):
            c = (fq * p[0] - fp * q[0], fq * p[1] - fp * q[1], fq * p[2] - fp * q[2])
            out.append(c if c[2] > 0 else (-c[0], -c[1], -c[2]))
    return out


def _integer_area(triangle: NDArray[np.float64], x: int, y: int) -> Fraction:
    """The exact area of ``triangle`` inside pixel (x, y), as :func:`harness.oracle.area.exact_area`
    computes it, on Python integers: the dyadic coordinates over one power of two, clipped as
    homogeneous points (:func:`_clipped`), then the shoelace over one common denominator."""
    ratios = [float(v).as_integer_ratio() for v in triangle.reshape(-1)]
    shift = max(d.bit_length() - 1 for _, d in ratios)  # every denominator is a power of two
    scaled = [n << (shift - (d.bit_length() - 1)) for n, d in ratios]
    one = 1 << shift
    points = [(scaled[0], scaled[1], one), (scaled[2], scaled[3], one), (scaled[4], scaled[5], one)]
    for axis, bound, keep in ((0, x, 1), (0, x + 1, -1), (1, y, 1), (1, y + 1, -1)):
        points = _clipped(points, axis, bound, keep)
        if len(points) < 3:
            return Fraction(0)
    twice = Fraction(0)
    n = len(points)
    for i in range(n):
        (ax, ay, ad), (bx, by, bd) = points[i], points[(i + 1) % n]
        twice += Fraction(ax * by - bx * ay, ad * bd)
    return abs(twice) / 2


def _exact_256ths(triangle: NDArray[np.float64], x: int, y: int) -> tuple[int, bool]:
    """(floor(256 a), whether 256 a is a whole number) of the exact area a of ``triangle``
    in pixel (x, y), remembered."""
    key = (np.ascontiguousarray(triangle, dtype=np.float64).tobytes(), x, y)
    found = _DECIDED.get(key)
    if found is None:
        scaled = 256 * _integer_area(triangle, x, y)
        found = (math.floor(scaled), scaled.denominator == 1)
        if len(_DECIDED) >= _DECIDED_LIMIT:
            _DECIDED.clear()
        _DECIDED[key] = found
    return found


@numba.njit(cache=True)
def _whole_pixels(snapped, sign, safe, t, x, y, open_, inside):  # type: ignore[no-untyped-def]
    """``inside[j]``: whether pixel (x[i], y[i]) of triangle t[i], i = open_[j], lies wholly in
    the closed triangle (then its area is exactly 1: 256 whole 256ths). A convex triangle
    holds the unit square iff it holds its four corners, and it holds a corner iff no edge
    function has the sign opposite to the triangle's orientation: exact signs
    (:func:`harness.geometry.exact.orient2d_sign`), asked only of triangles within its safe
    range (``safe``; corners are whole pixels, always in range); the rest say False."""
    for j in range(open_.size):
        i = open_[j]
        m = t[i]
        s = sign[m]
        inside[j] = False
        if not safe[m] or s == 0:
            continue
        p = snapped[m]
        whole = True
        for corner in range(4):
            cx = float(x[i] + (corner & 1))
            cy = float(y[i] + (corner >> 1))
            for e in range(3):
                a, b = e, (e + 1) % 3
                if orient2d_sign(p[a, 0], p[a, 1], p[b, 0], p[b, 1], cx, cy) == -s:
                    whole = False
                    break
            if not whole:
                break
        inside[j] = whole


class _AreaOf:
    """A scene's area under a convention (the quantisation aside: :func:`area_coverage`), the
    received triangles' exact signs, the float area's error bound at each pixel, and the
    exact ``(floor(256 a), 256 a whole)`` of each pixel asked so far (:meth:`decided`)."""

    # (scene digest, every field of the convention but its quantisation) -> the area: identify's
    # candidates, four quantisations on each grid, share it; a few scenes at a time
    _KEPT: dict[tuple[Any, ...], _AreaOf] = {}
    _LIMIT = 64

    @classmethod
    def of(cls, scene: Scene, convention: Convention) -> _AreaOf:
        key = (scene_digest(scene), *(getattr(convention, f.name) for f in fields(Convention) if f.name != "quantisation"))
        found = cls._KEPT.get(key)
        if found is None:
            if len(cls._KEPT) >= cls._LIMIT:
                cls._KEPT.clear()
            found = cls._KEPT[key] = cls(scene, convention)
        return found

    def __init__(self, scene: Scene, convention: Convention) -> None:
        self.plain = area_coverage(scene, convention)
        self.t, self.x, self.y = self.plain.pixels()
        self.area = self.plain.alpha if self.plain.alpha is not None else np.zeros(self.t.size)
        self.snapped = convention.snap(scene.positions)
        finite = np.all(np.isfinite(self.snapped), axis=(1, 2))
        self.finite_snapped = np.where(finite[:, None, None], self.snapped, 0.0)
        safe = np.empty(self.snapped.shape[0], dtype=np.bool_)
        self.exact_sign = orientation(self.finite_snapped, safe)
        self.safe = safe & finite
        self.sign = self.exact_sign.astype(np.int64)
        self.bound = 256.0 * area_error_bound(self.finite_snapped, scene.width, scene.height)[self.t]
        n = self.t.size
        self.below = np.zeros(n, dtype=np.int64)
        self.whole = np.zeros(n, dtype=np.bool_)
        self.known = np.zeros(n, dtype=np.bool_)

    def decided(self, pixels: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
        """``(floor(256 a), 256 a whole)`` of the exact area a at each of ``pixels`` (indices
        into the area's pixels), decided once each: a pixel wholly inside its triangle by
        exact corner signs (area 1: 256 whole 256ths; most of them), the rest by rationals."""
        unknown = pixels[~self.known[pixels]]
        if unknown.size:
            # a pixel wholly inside its triangle has area exactly 1 (256 whole 256ths): told by
            # exact corner signs, no rationals (most of the pixels left open are these)
            inside = np.empty(unknown.size, dtype=np.bool_)
            _whole_pixels(self.finite_snapped, self.exact_sign, self.safe, self.t.astype(np.int64),
                          self.x.astype(np.int64), self.y.astype(np.int64), unknown.astype(np.int64), inside)
            self.below[unknown[inside]] = 256
            self.whole[unknown[inside]] = True
            for i in unknown[~inside].tolist():
                self.below[i], self.whole[i] = _exact_256ths(self.snapped[self.t[i]], int(self.x[i]), int(self.y[i]))
            self.known[unknown] = True
        return self.below[pixels], self.whole[pixels]


def quantised_area_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The oracle of ``Convention(coverage="area", quantisation=q)``: every (triangle,
    pixel) of nonzero area, its alpha the level q makes of the received triangle's signed
    area, / 255 (a level may be 0 inside a span).

    The area comes from the compiled kernel (:func:`harness.oracle.area.area_coverage`,
    within :func:`harness.oracle.area.area_error_bound` of the exact one); ``k = floor(256 S)``
    is decided by it where the bound keeps ``256 S`` off every whole number, by the
    rational area elsewhere (:func:`harness.oracle.area.exact_area`): no epsilon decides.

    >>> tri = [[[0, 0], [2, 0], [0, 2]], [[0, 0], [0, 2], [2, 0]]]
    >>> c = quantised_area_coverage(Scene(2, 2, tri), Convention(coverage="area", quantisation="ftgrays"))
    >>> (c.alpha * 255).round().astype(int).tolist()  # clockwise (first) and counter-clockwise on screen
    [255, 128, 128, 255, 127, 127]
    """
    if convention.quantisation == NEAREST:
        raise ValueError("quantised_area_coverage needs a convention with a quantisation (not 'nearest')")
    q = quantisation_named(convention.quantisation)
    # the area and its exact decisions do not depend on the quantisation: identify scores
    # every quantisation on each grid, and they share them
    seen = _AreaOf.of(scene, convention)
    plain, t = seen.plain, seen.t
    signs = np.where(seen.sign > 0, q.signed(True), q.signed(False))[t]
    # 256 S within 256 * bound of 256 * float area (exact: a power of two); widened by an
    # ulp each side for the additions' own rounding
    bound = seen.bound
    scaled = 256.0 * seen.area * signs
    lo = np.floor(np.nextafter(scaled - bound, -np.inf))
    hi = np.floor(np.nextafter(scaled + bound, np.inf))
    k = lo.astype(np.int64)
    open_ = np.flatnonzero(lo != hi)
    if open_.size:  # the rational area decides
        below, whole = seen.decided(open_)
        k[open_] = np.where(signs[open_] > 0, below, -below - (~whole).astype(np.int64))  # floor(-v) = -ceil(v)
    level = levels_of(q, k)
    return Coverage(plain.primitive, plain.y, plain.x0, plain.x1, alpha=level / float(LEVELS - 1))
