"""Anti-aliased lines: the area of a stroked segment ∩ pixel square, exactly and in float64.

Under an area convention with ``line=LineRule("rectangle", cap=...)`` the alpha of segment
a-b (the line scene's ``line_width`` w, h = w/2) at pixel (i, j) is the area of its stroke
inside the pixel square [i, i+1] x [j, j+1]:

* ``butt``: the rectangle {p : 0 <= (p - a).D <= |D|**2, |D x (p - a)| <= h |D|}, D = b - a;
* ``square``: the same rectangle extended by h beyond each end point
  ({-h |D| <= (p - a).D <= |D|**2 + h |D|, ...});
* ``round``: the butt rectangle plus the half disc of radius h beyond each end point (their
  interiors are disjoint, so the areas add).

A zero-length segment (a == b) has no direction: butt draws nothing, square the
axis-aligned square of side w around a, round the disc of radius h (cairo's and skia's
degenerate strokes).

Exact: butt and square caps (:func:`exact_line_area`)
    The two sides (and square caps' ends) are lines with coefficients in Q(sqrt(d)),
    d = |D|**2 rational (float input): their offsets are h |D|. The pixel square is
    clipped against the four half-planes (Sutherland-Hodgman) in the field Q(sqrt(d))
    (:class:`QSqrt`: p + q sqrt(d) with p, q rational; the sign of such a number is decided
    exactly by comparing p**2 with q**2 d), and the shoelace formula gives the area, an exact
    element of Q(sqrt(d)). Every comparison against a rational (a level, a tolerance) is
    then exact: no epsilon, no enclosure.

Rigorous enclosure: round caps
    A half disc's area inside a pixel is transcendental (arcsines). It is enclosed between
    two rational polygons: the inscribed polygon whose vertices are rational points of the
    circle (``c + h ((1 - t**2) / (1 + t**2), 2 t / (1 + t**2))``, t rational: exactly on
    the circle), and the circumscribed one whose vertices are the intersections of the
    tangents at those points (``c + h (u1 + u2) / (1 + u1.u2)``, rational). inner ⊂ disc ⊂
    outer, so after clipping both by the cap's half-plane and the pixel square (rationals),
    area(inner ∩ ...) <= area(half disc ∩ pixel) <= area(outer ∩ ...). A comparison with a
    rational is decided once the enclosure lies on one side, refining from 64 to 4,096 points
    on the circle; one still straddling then (the area within about 1e-7 h of the rational)
    is reported as equal (:meth:`LineArea.compare` returns 0; :attr:`LineArea.undecided`
    counts them) -- the only place an answer is not proven, and said so.

The float path (:func:`line_pixel_areas`)
    Each stroke becomes convex polygons in float64 (the rectangle's four corners; each
    round cap's inscribed and circumscribed polygons of K sides) and :mod:`harness.oracle.area`'s
    compiled n-gon kernels give their areas per pixel. Per segment (:func:`line_area_bound`):

        |float alpha - exact area| <= u (n (22 M + 11 G + 7) + n**2) + 10.002 n delta [+ band]

    The first term is :func:`harness.oracle.area.area_error_bound`'s for an n-gon of exact
    float vertices (its proof holds for any convex n-gon). The corners are computed in
    float, each within delta = 16 u (|a|max + w) of the exact corner (a difference, a
    hypot, a quotient and a product of numbers at most |D| and h, then a sum: a few
    roundings of quantities at most |a| + w), and moving one vertex by delta changes an
    edge term by at most 5.001 delta (step 1 of area.py's proof): 10.002 n delta.
    Round caps add their band: the true cap lies between the inner and outer polygon (up
    to the float vertices, covered by delta), whose difference inside a unit square is at
    most 4 (h / cos(pi / 2K) - h cos(pi / 2K)) (the band lies in an annulus of that width; a
    circle's arcs inside a unit square are no longer than its perimeter, 4): the float
    alpha is the mean of the two, within half of that of the cap's area, per cap. K is
    chosen per width so that band is below 2**-16.

Far segments (a coordinate or w beyond ±2**21)
    The rectangle's corners are computed in rationals (sqrt(d) to 2**-80 relative) and the
    rectangle clipped exactly to the viewport, its vertices rounded to float64 (n <= 8,
    M = G = max(W, H), as area.py does for far triangles). Round caps are drawn only when
    near (a cap reaching into the viewport from beyond 2**21 raises ValueError).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.geometry.spans import pixel_offsets
from harness.oracle.area import GUARD_LIMIT, UNIT_ROUNDOFF, _area_kernel, _shoelace, _span_kernel, _viewport

__all__ = ["QSqrt", "LineArea", "exact_line_area", "exact_line_pixel_areas", "line_pixel_areas", "line_area_bound",
           "line_area_coverage", "exact_line_model", "line_model_bound", "step_exceeds", "cap_sides", "ENCLOSURE_POINTS"]

# the rational points on a round cap's circle, refined in turn until a comparison is decided
ENCLOSURE_POINTS = (64, 256, 1024, 4096)
# the float path's round caps: the band between inner and outer polygon at most this per cap
_BAND = 2.0**-16
_MAX_CAP_SIDES = 1 << 14


# -- exact arithmetic in Q(sqrt(d)) ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class QSqrt:
    """The number ``p + q sqrt(d)``, p and q rational, d >= 0 rational and not a square
    (:func:`_root` folds a square's root into p). Exact ring operations, division by a
    nonzero element, and the exact sign.

    >>> s = QSqrt(Fraction(0), Fraction(1), Fraction(2))  # sqrt(2)
    >>> (s * s).sign(), (s - Fraction(3, 2)).sign(), (s - Fraction(1414213, 1000000)).sign()
    (1, -1, 1)
    >>> float(Fraction(1) / (s + Fraction(1)))  # sqrt(2) - 1
    0.41421356237309503
    """

    p: Fraction
    q: Fraction = Fraction(0)
    d: Fraction = Fraction(0)

    def _lift(self, other: Any) -> QSqrt:
        if isinstance(other, QSqrt):
            return other
        return QSqrt(Fraction(other), Fraction(0), self.d)

    def __add__(self, other: Any) -> QSqrt:
        o = self._lift(other)
        return QSqrt(self.p + o.p, self.q + o.q, self.d or o.d)  # a rational's d is any

    __radd__ = __add__

    def __neg__(self) -> QSqrt:
        return QSqrt(-self.p, -self.q, self.d)

    def __sub__(self, other: Any) -> QSqrt:
        return self + (-self._lift(other))

    def __rsub__(self, other: Any) -> QSqrt:
        return self._lift(other) - self

    def __mul__(self, other: Any) -> QSqrt:
        o = self._lift(other)
        d = self.d or o.d
        if not self.q and not o.q:
            return QSqrt(self.p * o.p, Fraction(0), d)
        return QSqrt(self.p * o.p + self.q * o.q * d, self.p * o.q + self.q * o.p, d)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> QSqrt:
        o = self._lift(other)
        if not o.q:
            return QSqrt(self.p / o.p, self.q / o.p, self.d or o.d)
        norm = o.p * o.p - o.q * o.q * o.d  # nonzero: d is not a square
        return self * QSqrt(o.p / norm, -o.q / norm, o.d)

    def __rtruediv__(self, other: Any) -> QSqrt:
        return self._lift(other) / self

    def sign(self) -> int:
        """The exact sign: -1, 0 or 1."""
        sp = (self.p > 0) - (self.p < 0)
        sq = (self.q > 0) - (self.q < 0)
        if not sq or sp == sq:
            return sp if sp else sq
        if not sp:
            return sq
        # opposite signs: the larger square wins
        lhs, rhs = self.p * self.p, self.q * self.q * self.d
        return sp if lhs > rhs else (sq if lhs < rhs else 0)

    def bounds(self, bits: int = 64) -> tuple[Fraction, Fraction]:
        """Rational lo <= self <= hi, sqrt(d) enclosed to about 2**-bits relative."""
        if not self.q:
            return self.p, self.p
        lo, hi = _sqrt_bounds(self.d, bits)
        a, b = self.p + self.q * lo, self.p + self.q * hi
        return min(a, b), max(a, b)

    def __float__(self) -> float:
        lo, hi = self.bounds(80)
        return float((lo + hi) / 2)


def _sqrt_bounds(d: Fraction, bits: int) -> tuple[Fraction, Fraction]:
    """Rationals lo <= sqrt(d) <= hi with hi - lo <= 2**-bits (d >= 0)."""
    scale = 1 << (2 * bits)
    # sqrt(n/m) = sqrt(n m) / m
    root = math.isqrt(d.numerator * d.denominator * scale)
    lo = Fraction(root, d.denominator << bits)
    hi = lo if root * root == d.numerator * d.denominator * scale else Fraction(root + 1, d.denominator << bits)
    return lo, hi


def _root(d: Fraction) -> QSqrt:
    """sqrt(d) as an element of Q(sqrt(d)): rational when d is a square of a rational."""
    n, m = math.isqrt(d.numerator), math.isqrt(d.denominator)
    if n * n == d.numerator and m * m == d.denominator:
        return QSqrt(Fraction(n, m), Fraction(0), Fraction(0))
    return QSqrt(Fraction(0), Fraction(1), d)


_QPoint = tuple[QSqrt, QSqrt]
_Plane = tuple[Any, Any, Any]  # a x + b y + c >= 0, coefficients rational or QSqrt


def _clip_q(polygon: list[_QPoint], plane: _Plane) -> list[_QPoint]:
    """Sutherland-Hodgman in Q(sqrt(d)): the part of a convex polygon where the plane's
    a x + b y + c >= 0 (exact signs)."""
    a, b, c = plane
    out: list[_QPoint] = []
    values = [a * x + b * y + c for x, y in polygon]
    signs = [v.sign() for v in values]
    for k, p in enumerate(polygon):
        n = (k + 1) % len(polygon)
        sp, sn = signs[k], signs[n]
        if sp >= 0:
            out.append(p)
        if sp * sn < 0:
            t = values[k] / (values[k] - values[n])
            q = polygon[n]
            out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return out


def _shoelace_q(polygon: list[_QPoint]) -> QSqrt:
    twice = QSqrt(Fraction(0))
    for k, (x, y) in enumerate(polygon):
        xn, yn = polygon[(k + 1) % len(polygon)]
        twice = twice + (x * yn - xn * y)
    return twice / 2 if twice.sign() >= 0 else -twice / 2


def _pixel_square(x: int, y: int, d: Fraction) -> list[_QPoint]:
    fx, fy = QSqrt(Fraction(x), Fraction(0), d), QSqrt(Fraction(y), Fraction(0), d)
    return [(fx, fy), (fx + 1, fy), (fx + 1, fy + 1), (fx, fy + 1)]


def _stroke_planes(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], h: Fraction, square: bool,
                   root: QSqrt) -> list[_Plane]:
    """The four half-planes of the (butt or square-capped) rectangle of a-b, |D| = root."""
    (ax, ay), (bx, by) = a, b
    dx, dy = bx - ax, by - ay
    side = h * root  # the sides' offset, h |D|, in the scaled coordinates D x (p - a)
    cross0 = dy * ax - dx * ay  # D x (p - a) = -dy px + dx py + cross0
    end = side if square else Fraction(0)
    return [(dy, -dx, side - cross0), (-dy, dx, side + cross0),
            (dx, dy, end - (dx * ax + dy * ay)), (-dx, -dy, end + (dx * bx + dy * by))]


@functools.lru_cache(maxsize=64)
def _rational_circle(c: tuple[Fraction, Fraction], r: Fraction, n: int) -> tuple[list[tuple[Fraction, Fraction]],
                                                                                 list[tuple[Fraction, Fraction]]]:
    """Inscribed and circumscribed polygons of the circle (c, r): n rational points on it
    in angular order, and the tangents' intersections between consecutive ones."""
    units = []
    for k in range(n):
        theta = -math.pi + (k + 0.5) * 2 * math.pi / n  # never pi: t stays finite
        # any rational t gives a point exactly on the circle; a small denominator keeps the
        # rationals short (the angular gaps stay within a few per cent of 2 pi / n)
        t = Fraction(round(math.tan(theta / 2) * 2**20), 2**20)
        s = 1 + t * t
        units.append(((1 - t * t) / s, 2 * t / s))
    inner = [(c[0] + r * ux, c[1] + r * uy) for ux, uy in units]
    outer = []
    for k in range(n):
        (ux, uy), (vx, vy) = units[k], units[(k + 1) % n]
        f = r / (1 + ux * vx + uy * vy)
        outer.append((c[0] + f * (ux + vx), c[1] + f * (uy + vy)))
    return inner, outer


def _rational_area(polygon: list[tuple[Fraction, Fraction]], planes: list[_Plane]) -> Fraction:
    """Area of a convex rational polygon clipped by rational half-planes (the box's last:
    the cap's plane first would keep half the circle; the box's keep a few vertices)."""
    poly = polygon
    for a, b, c in reversed(planes):
        if len(poly) < 3:
            return Fraction(0)
        out: list[tuple[Fraction, Fraction]] = []
        if b == 0 and a in (1, -1):  # the box's sides: a difference, no products
            values = [x + c if a == 1 else c - x for x, _ in poly]
        elif a == 0 and b in (1, -1):
            values = [y + c if b == 1 else c - y for _, y in poly]
        else:
            values = [a * x + b * y + c for x, y in poly]
        for k, p in enumerate(poly):
            n = k + 1 if k + 1 < len(poly) else 0
            vp, vn = values[k], values[n]
            if vp >= 0:
                out.append(p)
            if (vp > 0 > vn) or (vp < 0 < vn):
                t = vp / (vp - vn)
                q = poly[n]
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
        poly = out
    return _shoelace(poly) if len(poly) >= 3 else Fraction(0)


@dataclass(slots=True)
class LineArea:
    """The exact area of a stroke ∩ pixel: ``rect`` (exact, in Q(sqrt(d))) plus, for round
    caps, the caps' area known by rigorous rational enclosures refined on demand.

    Compares exactly with rationals (``<``, ``<=``, ``>``, ``>=``, through :meth:`compare`),
    and takes part in ``r - area`` and ``abs(...)`` as the accuracy check writes them.

    >>> area = exact_line_area([[0, 0], [2, 0]], 1.0, "butt", 0, 0)
    >>> area == Fraction(1, 2), float(area)
    (True, 0.5)
    >>> abs(Fraction(1, 3) - area) > Fraction(1, 10)
    True
    """

    rect: QSqrt
    caps: list[tuple[tuple[Fraction, Fraction], tuple[Fraction, Fraction], list[_Plane]]] = field(default_factory=list)
    scale: int = 1  # +1 or -1: the caps' enclosure enters with this sign
    shift: Fraction = Fraction(0)
    _enclosures: dict[int, tuple[Fraction, Fraction]] = field(default_factory=dict)
    undecided: int = 0

    def _caps(self, n: int) -> tuple[Fraction, Fraction]:
        """lo <= the caps' area <= hi with n points on each circle."""
        if n not in self._enclosures:
            lo = hi = Fraction(0)
            for centre, (r, _), planes in self.caps:
                inner, outer = _rational_circle(centre, r, n)
                lo += _rational_area(inner, planes)
                hi += _rational_area(outer, planes)
            self._enclosures[n] = (lo, hi)
        return self._enclosures[n]

    def compare(self, r: Any) -> int:
        """The sign of ``self - r`` for a rational r: exact without round caps; with them,
        decided by the enclosures, 0 when still open at the finest (:data:`ENCLOSURE_POINTS`)."""
        base = (self.rect * self.scale + self.shift) - Fraction(r)
        if not self.caps:
            return base.sign()
        for n in ENCLOSURE_POINTS:
            lo, hi = self._caps(n)
            if self.scale < 0:
                lo, hi = -hi, -lo
            if (base + lo).sign() > 0:
                return 1
            if (base + hi).sign() < 0:
                return -1
        self.undecided += 1
        return 0

    def bounds(self, level: int) -> tuple[Fraction, Fraction]:
        """Rational lo <= self <= hi, finer with ``level`` (0 .. len(ENCLOSURE_POINTS) - 1):
        sqrt(d) to 2**-(64 * 2**level) relative, the caps with ENCLOSURE_POINTS[level] points."""
        lo, hi = self.rect.bounds(64 << level)
        if self.caps:
            clo, chi = self._caps(ENCLOSURE_POINTS[level])
            lo, hi = lo + clo, hi + chi
        if self.scale < 0:
            lo, hi = -hi, -lo
        return lo + self.shift, hi + self.shift

    def _moved(self, scale: int, shift: Fraction) -> LineArea:
        return LineArea(self.rect, self.caps, self.scale * scale, self.shift * scale + shift, self._enclosures)

    def __neg__(self) -> LineArea:
        return self._moved(-1, Fraction(0))

    def __add__(self, other: Any) -> LineArea:
        return self._moved(1, Fraction(other))

    __radd__ = __add__

    def __sub__(self, other: Any) -> LineArea:
        return self._moved(1, -Fraction(other))

    def __rsub__(self, other: Any) -> LineArea:
        return self._moved(-1, Fraction(other))

    def __abs__(self) -> _Magnitude:
        return _Magnitude(self)

    def __lt__(self, other: Any) -> bool:
        return self.compare(other) < 0

    def __le__(self, other: Any) -> bool:
        return self.compare(other) <= 0

    def __gt__(self, other: Any) -> bool:
        return self.compare(other) > 0

    def __ge__(self, other: Any) -> bool:
        return self.compare(other) >= 0

    def __eq__(self, other: object) -> bool:
        if isinstance(other, (int, Fraction)):
            return self.compare(other) == 0
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __float__(self) -> float:
        value = float(self.rect)
        if self.caps:
            lo, hi = self._caps(ENCLOSURE_POINTS[1])
            value += float((lo + hi) / 2)
        return self.scale * value + float(self.shift)


@dataclass(frozen=True, slots=True)
class _Magnitude:
    """|x| of a :class:`LineArea`, compared with a rational bound."""

    value: LineArea

    def __gt__(self, bound: Any) -> bool:
        return self.value.compare(bound) > 0 or self.value.compare(-Fraction(bound)) < 0

    def __le__(self, bound: Any) -> bool:
        return not self > bound

    def __ge__(self, bound: Any) -> bool:
        return self.value.compare(bound) >= 0 or self.value.compare(-Fraction(bound)) <= 0

    def __lt__(self, bound: Any) -> bool:
        return not self >= bound


def step_exceeds(step: Fraction, later: LineArea, earlier: LineArea, limit: Fraction) -> bool:
    """Whether ``|step - (later - earlier)| > limit`` (popping's decision on two frames'
    exact stroke areas, which lie in different fields): decided on rational enclosures of
    both, refined until the answer is certain; one still open at the finest enclosures (the
    difference within about 2**-500, or a round cap's 1e-7 h, of the limit) is taken as
    within it (and counted in ``later.undecided``).

    >>> a = exact_line_area([[0, 0], [3, 1]], 1.0, "butt", 1, 0)
    >>> b = exact_line_area([[0, 0.25], [3, 1.25]], 1.0, "butt", 1, 0)
    >>> step_exceeds(Fraction(0), b, a, Fraction(1, 100)), step_exceeds(Fraction(0), b, a, Fraction(1, 2))
    (True, False)
    """
    for level in range(len(ENCLOSURE_POINTS)):
        lo1, hi1 = later.bounds(level)
        lo0, hi0 = earlier.bounds(level)
        low, high = lo1 - hi0, hi1 - lo0  # the exact difference lies in [low, high]
        if step - high > limit or low - step > limit:
            return True
        if step - low <= limit and high - step <= limit:
            return False
    later.undecided += 1
    return False


def _fraction_point(p: Any) -> tuple[Fraction, Fraction]:
    x, y = (float(v) for v in p)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"end point {[x, y]} has a coordinate that is not finite")
    return Fraction(x), Fraction(y)


def exact_line_area(segment: Any, line_width: float, cap: str, x: int, y: int) -> LineArea:
    """The exact area of the stroke of ``segment`` (2 x 2: a, b) ``line_width`` wide with
    ``cap`` ends inside pixel (x, y) (module docstring).

    Examples
    --------
    >>> exact_line_area([[0, 0], [3, 4]], 1.0, "butt", 1, 1) > Fraction(1, 2)
    True
    >>> exact_line_area([[0.5, 0.5], [0.5, 0.5]], 1.0, "square", 0, 0) == 1
    True
    >>> area = exact_line_area([[0.5, 0.5], [2.5, 0.5]], 1.0, "round", 0, 0)  # half a disc of radius 1/2, and 1/2
    >>> Fraction(1, 2) + Fraction(314159, 8 * 10**5) < area < Fraction(1, 2) + Fraction(314160, 8 * 10**5)
    True
    """
    seg = np.asarray(segment, dtype=np.float64)
    if seg.shape != (2, 2):
        raise ValueError(f"a segment is 2 x 2 coordinates, not shape {seg.shape}")
    a, b = _fraction_point(seg[0]), _fraction_point(seg[1])
    h = Fraction(float(line_width)) / 2
    fx, fy = Fraction(int(x)), Fraction(int(y))
    box: list[_Plane] = [(1, 0, -fx), (-1, 0, fx + 1), (0, 1, -fy), (0, -1, fy + 1)]
    if a == b:
        if cap == "butt":
            return LineArea(QSqrt(Fraction(0)))
        if cap == "square":
            square = [(a[0] - h, a[1] - h), (a[0] + h, a[1] - h), (a[0] + h, a[1] + h), (a[0] - h, a[1] + h)]
            return LineArea(QSqrt(_rational_area(square, box)))
        return LineArea(QSqrt(Fraction(0)), [(a, (h, h), box)])
    dx, dy = b[0] - a[0], b[1] - a[1]
    d = dx * dx + dy * dy
    root = _root(d)
    poly = _pixel_square(int(x), int(y), root.d)
    for plane in _stroke_planes(a, b, h, cap == "square", root):
        if len(poly) < 3:
            break
        poly = _clip_q(poly, plane)
    rect = _shoelace_q(poly) if len(poly) >= 3 else QSqrt(Fraction(0), Fraction(0), root.d)
    if cap != "round":
        return LineArea(rect)
    caps = [(a, (h, h), [(-dx, -dy, dx * a[0] + dy * a[1]), *box]),
            (b, (h, h), [(dx, dy, -(dx * b[0] + dy * b[1])), *box])]
    return LineArea(rect, caps)


def exact_line_pixel_areas(segments: Any, line_width: float, cap: str, width: int,
                           height: int) -> dict[tuple[int, int, int], LineArea]:
    """The slow reference for :func:`line_pixel_areas`: (segment, x, y) -> :class:`LineArea`
    for every viewport pixel the stroke's bounding box touches where the area is not 0.

    >>> found = exact_line_pixel_areas([[[0, 1], [2, 1]]], 1.0, "butt", 3, 2)
    >>> sorted((k, float(v)) for k, v in found.items())
    [((0, 0, 0), 0.5), ((0, 0, 1), 0.5), ((0, 1, 0), 0.5), ((0, 1, 1), 0.5)]
    """
    segs = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2)
    out: dict[tuple[int, int, int], LineArea] = {}
    reach = float(line_width) * 0.75 + 1.0  # beyond h sqrt(2) (a square cap's corner)
    for s, seg in enumerate(segs):
        if not np.all(np.isfinite(seg)):
            continue
        x0 = max(math.floor(seg[:, 0].min() - reach), 0)
        x1 = min(math.ceil(seg[:, 0].max() + reach), width)
        y0 = max(math.floor(seg[:, 1].min() - reach), 0)
        y1 = min(math.ceil(seg[:, 1].max() + reach), height)
        for j in range(y0, y1):
            for i in range(x0, x1):
                area = exact_line_area(seg, line_width, cap, i, j)
                if area.compare(0) > 0 or (area.caps and area.compare(0) == 0 and float(area) > 0):
                    out[s, i, j] = area
    return out


# -- the compiled float path ----------------------------------------------------------------------


def cap_sides(half_width: float) -> int:
    """Sides of each round cap's polygons in the float path: the band between inner and
    outer (at most 4 h sin(pi/2K)**2 / cos(pi/2K) in any pixel) below 2**-16.

    >>> cap_sides(0.5), cap_sides(2.0)
    (570, 1139)
    """
    k = math.ceil((math.pi / 2) * math.sqrt(4.0 * max(half_width, 2.0**-20) / _BAND) * 1.001)
    return int(min(max(k, 16), _MAX_CAP_SIDES))


def _band(h: float, k: int) -> float:
    half = math.pi / (2 * k) * (1 + 1e-9)
    return 4.0 * h * math.sin(half) ** 2 / math.cos(half) * (1 + 1e-12)


def _cap_polygons(c: NDArray[np.float64], start: float, h: float, k: int, full: bool) -> tuple[NDArray, NDArray]:
    """Inner and outer float polygons of the half disc (c, h) from angle ``start`` over pi
    (the whole disc when ``full``), k sides of the arc."""
    span = 2 * math.pi if full else math.pi
    step = span / k
    angles = start + step * np.arange(k + (0 if full else 1))
    inner = c + h * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    mids = start + step * (np.arange(k) + 0.5)
    far = h / math.cos(step / 2)
    outer_mid = c + far * np.stack([np.cos(mids), np.sin(mids)], axis=1)
    if full:
        outer = outer_mid
    else:
        outer = np.concatenate([inner[:1], outer_mid, inner[-1:]])
    return inner, outer


def _far_rectangle(a: NDArray, b: NDArray, h: float, square: bool, width: int, height: int) -> NDArray | None:
    """The rectangle of a far segment, corners in rationals, clipped exactly to the
    viewport and rounded (None when it misses it)."""
    from harness.oracle.area import _clip_to_box

    fa, fb = _fraction_point(a), _fraction_point(b)
    dx, dy = fb[0] - fa[0], fb[1] - fa[1]
    lo, hi = _sqrt_bounds(dx * dx + dy * dy, 80)
    length = (lo + hi) / 2
    fh = Fraction(h)
    nx, ny = -dy / length * fh, dx / length * fh
    ex, ey = (dx / length * fh, dy / length * fh) if square else (Fraction(0), Fraction(0))
    corners = [(fa[0] - ex + nx, fa[1] - ey + ny), (fb[0] + ex + nx, fb[1] + ey + ny),
               (fb[0] + ex - nx, fb[1] + ey - ny), (fa[0] - ex - nx, fa[1] - ey - ny)]
    clipped = _clip_to_box(corners, Fraction(0), Fraction(0), Fraction(width), Fraction(height))
    if not clipped:
        return None
    return np.array([(float(x), float(y)) for x, y in clipped])


@dataclass(slots=True)
class _Pieces:
    """The float polygons of a scene's strokes: each with its segment, a weight (1, or 1/2
    for each of a round cap's inner and outer polygons) and whether pixels wholly inside
    may be written as exactly 1 (not for a cap's inner polygon, measured on the outer's)."""

    polys: list[NDArray] = field(default_factory=list)
    owner: list[int] = field(default_factory=list)
    weight: list[float] = field(default_factory=list)
    paired: list[int] = field(default_factory=list)  # for an inner polygon, its outer's index; else -1

    def add(self, poly: NDArray, segment: int, weight: float = 1.0, paired: int = -1) -> int:
        self.polys.append(np.ascontiguousarray(poly, dtype=np.float64))
        self.owner.append(segment)
        self.weight.append(weight)
        self.paired.append(paired)
        return len(self.polys) - 1

    def add_all(self, polys: NDArray, segments: NDArray[np.int64]) -> None:
        """Whole-weight polygons (N, k, 2) of ``segments`` (N,), in one go."""
        self.polys.extend(np.ascontiguousarray(polys, dtype=np.float64))
        self.owner.extend(segments.tolist())
        self.weight.extend([1.0] * segments.size)
        self.paired.extend([-1] * segments.size)


def _pieces(a: NDArray, b: NDArray, line_width: float, cap: str, width: int, height: int) -> _Pieces:
    pieces = _Pieces()
    h = line_width / 2
    square = cap == "square"
    far_w = line_width > GUARD_LIMIT
    finite = np.all(np.isfinite(a), axis=1) & np.all(np.isfinite(b), axis=1)
    with np.errstate(invalid="ignore"):
        near = ~(far_w | np.any(np.abs(a) > GUARD_LIMIT, axis=1) | np.any(np.abs(b) > GUARD_LIMIT, axis=1))
    moving = np.any(a != b, axis=1)
    # the usual stroke, a near segment of nonzero length without round caps: its rectangle's
    # corners computed for all segments at once, each exactly as the loop below would
    plain = np.flatnonzero(finite & near & moving) if cap != "round" else np.zeros(0, dtype=np.int64)
    if plain.size:
        d = b[plain] - a[plain]
        length = np.hypot(d[:, 0], d[:, 1])[:, None]
        u = d / length
        n = np.stack([-u[:, 1] * h, u[:, 0] * h], axis=1)
        e = u * h if square else np.zeros_like(u)
        pa, pb = a[plain], b[plain]
        pieces.add_all(np.stack([pa - e + n, pb + e + n, pb + e - n, pa - e - n], axis=1), plain)
    done = np.zeros(a.shape[0], dtype=bool)
    done[plain] = True
    for s in np.flatnonzero(~done & finite).tolist():
        pa, pb = a[s], b[s]
        far = not near[s]
        dx, dy = float(pb[0] - pa[0]), float(pb[1] - pa[1])
        zero = bool(pa[0] == pb[0] and pa[1] == pb[1])
        if zero and cap == "butt":
            continue
        if zero and square:
            box = np.array([[pa[0] - h, pa[1] - h], [pa[0] + h, pa[1] - h], [pa[0] + h, pa[1] + h], [pa[0] - h, pa[1] + h]])
            if far:
                rect = _far_box(box, width, height)
                if rect is not None:
                    pieces.add(rect, s)
            else:
                pieces.add(box, s)
            continue
        if not zero:
            if far:
                rect = _far_rectangle(pa, pb, h, square, width, height)
                if rect is not None and len(rect) >= 3:
                    pieces.add(rect, s)
            else:
                length = math.hypot(dx, dy)
                ux, uy = dx / length, dy / length
                n = np.array([-uy * h, ux * h])
                e = np.array([ux * h, uy * h]) if square else np.zeros(2)
                pieces.add(np.stack([pa - e + n, pb + e + n, pb + e - n, pa - e - n]), s)
        if cap != "round":
            continue
        k = cap_sides(h)
        if zero:
            ends = [(pa, 0.0, True)]
            k *= 2  # the whole circle, at the same angular step
        else:
            phi = math.atan2(dy, dx)
            ends = [(pa, phi + math.pi / 2, False), (pb, phi - math.pi / 2, False)]
        for c, start, full in ends:
            if (c[0] + h < 0 or c[0] - h > width or c[1] + h < 0 or c[1] - h > height):
                continue  # the cap misses the viewport
            if np.any(np.abs(c) > GUARD_LIMIT) or h > GUARD_LIMIT:
                raise ValueError("round caps reaching the viewport from beyond 2**21 are not supported")
            inner, outer = _cap_polygons(np.asarray(c, dtype=np.float64), start, h, k, full)
            o = pieces.add(outer, s, 0.5)
            pieces.add(inner, s, 0.5, paired=o)
    return pieces


def _far_box(box: NDArray, width: int, height: int) -> NDArray | None:
    from harness.oracle.area import _clip_to_box

    clipped = _clip_to_box([(Fraction(float(x)), Fraction(float(y))) for x, y in box], Fraction(0), Fraction(0),
                           Fraction(width), Fraction(height))
    return np.array([(float(x), float(y)) for x, y in clipped]) if clipped else None


def _polygon_areas(pieces: _Pieces, width: int, height: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """(piece, x, y, area) of every pixel each piece's span holds (the inner polygon of a
    cap on its outer's pixels, never written as exactly 1)."""
    if not pieces.polys:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, empty, np.zeros(0)
    most = max(len(p) for p in pieces.polys)
    n = len(pieces.polys)
    polys = np.empty((n, most, 2))
    counts = np.empty(n, dtype=np.int64)
    for k, p in enumerate(pieces.polys):
        polys[k, : len(p)] = p
        polys[k, len(p):] = p[0]
        counts[k] = len(p)
    ys = polys[:, :, 1]
    rows = np.minimum(np.ceil(ys.max(axis=1)), height) - np.maximum(np.floor(ys.min(axis=1)), 0)
    capacity = int(np.maximum(rows, 0).sum())
    block = np.empty((6, capacity), dtype=np.int64)
    spans = _span_kernel(polys, counts, int(width), int(height), *block)
    span_p, span_y, span_x0, span_x1, span_i0, span_i1 = (np.ascontiguousarray(r[:spans]) for r in block)
    paired = np.asarray(pieces.paired, dtype=np.int64)
    own = paired[span_p] < 0  # an inner polygon's own spans are dropped: it is measured on its outer's
    span_p, span_y, span_x0, span_x1, span_i0, span_i1 = (r[own] for r in (span_p, span_y, span_x0, span_x1, span_i0,
                                                                             span_i1))
    # an inner polygon is measured on its outer's pixels (it lies inside it)
    inner_of = np.full(n, -1, dtype=np.int64)
    inner_of[paired[paired >= 0]] = np.flatnonzero(paired >= 0)
    has_inner = inner_of[span_p] >= 0
    span_p = np.concatenate([span_p, inner_of[span_p[has_inner]]])
    span_y = np.concatenate([span_y, span_y[has_inner]])
    span_x0 = np.concatenate([span_x0, span_x0[has_inner]])
    span_x1 = np.concatenate([span_x1, span_x1[has_inner]])
    zeros = np.zeros(int(has_inner.sum()), dtype=np.int64)
    span_i0 = np.concatenate([span_i0, zeros])
    span_i1 = np.concatenate([span_i1, zeros])
    lengths = span_x1 - span_x0
    area = np.empty(int(pixel_offsets(span_x0, span_x1)[-1]))
    _area_kernel(polys, counts, span_p, span_y, span_x0, span_x1, span_i0, span_i1, area)
    starts = np.repeat(span_x0 - np.concatenate([[0], np.cumsum(lengths)[:-1]]), lengths)
    x = starts + np.arange(area.size)
    return np.repeat(span_p, lengths), x, np.repeat(span_y, lengths), area


def line_pixel_areas(segments: Any, line_width: float, cap: str, width: int,
                     height: int) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The area of each stroke ∩ pixel in compiled float64, for every segment and viewport
    pixel with a nonzero float area; within :func:`line_area_bound` of :func:`exact_line_area`.

    Parameters
    ----------
    segments : (N, 2, 2) float64
    line_width : float
    cap : {"butt", "square", "round"}
    width, height : int

    Returns
    -------
    segment, x, y : (P,) int64
        Sorted by segment, row, column.
    area : (P,) float64

    Examples
    --------
    >>> s, x, y, area = line_pixel_areas(np.array([[[0, 1], [2, 1]]]), 1.0, "butt", 3, 2)
    >>> s.tolist(), x.tolist(), y.tolist(), area.tolist()
    ([0, 0, 0, 0], [0, 1, 0, 1], [0, 0, 1, 1], [0.5, 0.5, 0.5, 0.5])
    """
    _viewport(width, height)
    segs = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2)
    pieces = _pieces(segs[:, 0], segs[:, 1], float(line_width), cap, int(width), int(height))
    piece, x, y, area = _polygon_areas(pieces, int(width), int(height))
    owner = np.asarray(pieces.owner, dtype=np.int64)[piece] if piece.size else piece
    weight = np.asarray(pieces.weight)[piece] if piece.size else np.zeros(0)
    keys = (owner * height + y) * width + x
    unique, where = np.unique(keys, return_inverse=True)
    total = np.bincount(where.ravel(), weights=area * weight, minlength=unique.size)
    total = np.minimum(total, 1.0)
    keep = total > 0.0
    unique, total = unique[keep], total[keep]
    unique = unique.astype(np.int64)
    return unique // (width * height), unique % width, unique // width % height, np.asarray(total, dtype=np.float64)


def line_area_bound(segments: Any, line_width: float, cap: str, width: int, height: int) -> NDArray[np.float64]:
    """Per segment, a proven bound on ``|line_pixel_areas - exact area|`` at every pixel
    (module docstring): u (n (22 M + 11 G + 7) + n**2) + 10.002 n delta, plus for round caps
    each cap's half band; 0 for a segment with a non-finite end point.

    >>> bound = line_area_bound(np.array([[[0, 0.5], [2, 0.5]]]), 1.0, "butt", 3, 2)
    >>> bool(0 < bound[0] < 2**-40)
    True
    """
    segs = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2)
    w = float(line_width)
    h = w / 2
    out = np.zeros(segs.shape[0])
    side = float(max(width, height))
    u = UNIT_ROUNDOFF
    for s, seg in enumerate(segs):
        if not np.all(np.isfinite(seg)):
            continue
        biggest = float(np.abs(seg).max())
        far = w > GUARD_LIMIT or biggest > GUARD_LIMIT
        extent = float(max(np.ptp(seg[:, 0]), np.ptp(seg[:, 1]))) + w + 1.0
        if far:
            n, m, g, delta = 8, side, side, h * 2.0**-70
        else:
            n, m, g, delta = 4, extent, 0.0, 16 * u * (biggest + w)
        bound = u * (n * (22.0 * m + 11.0 * g + 7.0) + n * n) + 10.002 * n * delta
        if cap == "round":
            nc = 2 * cap_sides(h) + 2  # a half disc's k + 2 vertices, a whole one's 2 k
            cap_delta = 16 * u * (biggest + w) + 8 * u * h
            each = (u * (nc * (22.0 * (w + 2.0) + 7.0) + nc * nc) + 10.002 * nc * cap_delta) + _band(h, cap_sides(h)) / 2
            bound += 2 * each
        out[s] = bound * (1 + 2.0**-40)
    return out


def _snapped_segments(scene: Any, convention: Convention) -> NDArray[np.float64]:
    conv = convention.for_lines()
    a, b = scene.segments()
    return np.ascontiguousarray(np.stack([conv.snap(a), conv.snap(b)], axis=1), dtype=np.float64)


def line_area_coverage(scene: Any, convention: Convention) -> Coverage:
    """The area oracle of a line scene under an area convention with the rectangle rule:
    every (segment, pixel) with a nonzero area, its alpha the (float) area of the snapped
    segment's stroke inside the pixel (the rule's ``cap``), within :func:`line_area_bound`.

    >>> from harness.contract.conventions import LineRule
    >>> from harness.contract.scenes import LineScene
    >>> scene = LineScene.from_strips(4, 2, [[[0, 1], [4, 1]]], line_width=1.0)
    >>> cov = line_area_coverage(scene, Convention(coverage="area", line=LineRule("rectangle")))
    >>> cov.counts(4, 2).tolist(), cov.alpha.tolist()
    ([[1, 1, 1, 1], [1, 1, 1, 1]], [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
    """
    if convention.line.rule != "rectangle":
        raise ValueError(f"anti-aliased lines are rectangles (LineRule('rectangle', cap=...)), not "
                         f"{convention.line.describe()}")
    if convention.samples is not None:
        raise ValueError("anti-aliased lines are judged against their exact area; a supersampled convention's "
                         "lines are not defined")
    segs = _snapped_segments(scene, convention)
    s, x, y, area = line_pixel_areas(segs, scene.line_width, convention.line.cap, scene.width, scene.height)
    return Coverage.from_pixels(s, x, y, alpha=area)


def line_model_bound(scene: Any, convention: Convention) -> NDArray[np.float64]:
    """Per segment, :func:`line_area_bound` of the snapped segments (the accuracy check's margin)."""
    return line_area_bound(_snapped_segments(scene, convention), scene.line_width, convention.line.cap,
                           scene.width, scene.height)


def exact_line_model(scene: Any, convention: Convention, segment: int, x: int, y: int) -> LineArea:
    """The exact area of the snapped segment's stroke inside pixel (x, y) (0 for a
    segment with a non-finite end point)."""
    seg = _snapped_segments(scene, convention)[segment]
    if not np.all(np.isfinite(seg)):
        return LineArea(QSqrt(Fraction(0)))
    return exact_line_area(seg, scene.line_width, convention.line.cap, int(x), int(y))
