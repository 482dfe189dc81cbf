"""Known-bad path fillers (seed 002): the trapezoid fill with one classic bug each.

Each declares the reference's convention (:class:`rasterizers.trapezoid.TrapezoidFill`:
pixel centres, top-left ties) and takes triangles and paths under both fill rules, so the
conformance check judges it. Where a row crosses an edge is decided exactly (the
reference's :func:`~rasterizers.trapezoid.crossing_column`): each differs from the
oracle only through its bug. Spans are emitted between neighbouring crossings where the
winding between them satisfies the rule, as the trapezoid decomposition does: nothing
right of a row's last crossing.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, PathScene, Scene
from harness.geometry.exact import frozen
from harness.geometry.kernel_sorts import stable_argsort
from rasterizers.trapezoid import _CACHE, crossing_column, outline

__all__ = ["PathFillBug", "BUGS", "TwoFillers"]

BUGS = ("evenodd-for-nonzero", "unsigned-crossings", "horizontal-crossings", "inclusive-ends", "open-contours",
        "int8-winding", "int16-winding", "int8-saturating", "first-contour-only", "contours-apart")
(EVENODD_FOR_NONZERO, UNSIGNED_CROSSINGS, HORIZONTAL_CROSSINGS, INCLUSIVE_ENDS, OPEN_CONTOURS, INT8_WINDING, INT16_WINDING,
 INT8_SATURATING, FIRST_CONTOUR_ONLY, CONTOURS_APART) = range(10)


class PathFillBug:
    """A trapezoid (active edge list) path filler with one bug.

    bug:
      "evenodd-for-nonzero"   the parity of the crossings decides under either rule, so
                              nonzero loses every region of winding +/-2 (a pentagram's
                              centre, a hole wound like its ring)
      "unsigned-crossings"    the edge table stores every edge top to bottom and forgets
                              which way it ran: every crossing adds +1, so nonzero fills
                              from a row's first crossing to its last (a hole wound
                              against its ring, the gaps between a pentagram's points);
                              even-odd is unaffected (the parity is the same)
      "horizontal-crossings"  horizontal edges are kept in the edge table: one lying on a
                              sample row counts as a crossing there, at its left end,
                              adding +1 (``dir = 1 if dy >= 0 else -1``)
      "inclusive-ends"        an edge crosses the rows ``ylo <= ys <= yhi``, both ends
                              inclusive instead of half-open: a row through a vertex
                              where the outline passes on (one edge ending, the next
                              starting) counts it twice -- even-odd drops that row's
                              span -- and a row through a bottom edge is drawn
      "open-contours"         the edge list is built from consecutive vertex pairs only,
                              dropping each contour's closing edge (last -> first)
      "int8-winding"          the winding counter is a signed 8-bit integer and wraps:
                              a winding of 256 (or any multiple) reads as 0, so nonzero
                              leaves it out; even-odd is unaffected (a wrap keeps parity)
      "int16-winding"         the same in 16 bits: 65,536 reads as 0
      "int8-saturating"       a signed 8-bit counter that saturates (a SIMD saturating
                              add): past 127 crossings it stops counting, and the
                              crossings back down then leave it wrong -- a winding of
                              128 reads as 127 (odd), the outside right of it as below 0
      "first-contour-only"    the edge list holds each path's first contour only (a loop
                              over contours that stops after one): holes, and every
                              further contour, dropped
      "contours-apart"        each contour filled on its own and the union drawn (an edge
                              list per contour): holes ignored, whatever their winding
    """

    convention = Convention(sample=(0.5, 0.5), tie="top-left")
    scene_kinds = ("triangles", "paths")
    fill_rules = ("nonzero", "evenodd")
    interpolates = False

    def __init__(self, bug: str) -> None:
        if bug not in BUGS:
            raise ValueError(f"bug must be one of {', '.join(BUGS)}, not {bug!r}")
        self.bug = bug
        self.name = f"bad_{bug}"

    def rasterize(self, scene: Scene | PathScene) -> Coverage:  # (the kinds it takes)
        a, b, primitive = outline(scene)
        if isinstance(scene, PathScene):
            closing = np.zeros(primitive.size, dtype=bool)
            closing[np.cumsum(scene.contour_sizes) - 1] = True
        else:
            closing = np.arange(primitive.size) % 3 == 2
        keep = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
        keep &= np.isin(primitive, primitive[~keep], invert=True)  # a path with a NaN covers nothing
        bug = BUGS.index(self.bug)
        if bug == OPEN_CONTOURS:
            keep &= ~closing
        owner, n = primitive, len(scene)
        if isinstance(scene, PathScene) and bug in (FIRST_CONTOUR_ONLY, CONTOURS_APART):
            contour = np.repeat(np.arange(scene.contour_sizes.size), scene.contour_sizes)  # each edge's contour
            if bug == FIRST_CONTOUR_ONLY:  # BUG: the contours after each path's first left out
                first = np.concatenate([[True], scene.contour_path[1:] != scene.contour_path[:-1]])
                keep &= first[contour]
            else:  # BUG: each contour a primitive of its own, the union drawn
                owner, n = contour, scene.contour_sizes.size
        order = np.flatnonzero(keep)[np.argsort(owner[keep], kind="stable")]
        bounds = np.searchsorted(owner[order], np.arange(n + 1)).astype(np.int64)
        evenodd = bug == EVENODD_FOR_NONZERO or (isinstance(scene, PathScene) and scene.fill_rule == "evenodd")
        ax, ay, bx, by = (frozen(c[order]) for c in (a[:, 0], a[:, 1], b[:, 0], b[:, 1]))
        drawn = Coverage(*_spans(ax, ay, bx, by, bounds, bug, evenodd, scene.width, scene.height))
        if owner is primitive:
            return drawn
        assert isinstance(scene, PathScene)
        t, x, y = drawn.pixels()
        keys = np.unique((scene.contour_path[t] * scene.height + y) * scene.width + x)  # the union per path
        if not keys.size:
            return Coverage.empty()
        path, pixel = np.divmod(keys, scene.height * scene.width)
        return Coverage.from_pixels(path, pixel % scene.width, pixel // scene.width)


@numba.njit(cache=_CACHE, error_model="numpy")
def _spans(ax, ay, bx, by, bounds, bug, evenodd, width, height):
    """Spans (path, y, x0, x1), row by row, over each path's edges ``bounds[p]:bounds[p + 1]``."""
    # a span starts and ends at two crossings of its path's row, but the last may end at the
    # start of the next: per row and path at most crossings / 2 + 1 spans
    capacity = height * (ax.size // 2 + bounds.size)
    out_p = np.empty(capacity, dtype=np.int64)
    out_y = np.empty(capacity, dtype=np.int64)
    out_x0 = np.empty(capacity, dtype=np.int64)
    out_x1 = np.empty(capacity, dtype=np.int64)
    n = 0
    column = np.empty(ax.size, dtype=np.int64)
    winding = np.empty(ax.size, dtype=np.int64)
    order = np.empty(ax.size, dtype=np.int64)
    spare = np.empty(ax.size, dtype=np.int64)
    for p in range(bounds.size - 1):
        for j in range(height):
            ys = j + 0.5
            m = 0
            for e in range(bounds[p], bounds[p + 1]):
                if ay[e] == by[e]:
                    if bug == HORIZONTAL_CROSSINGS and ay[e] == ys:  # BUG: a horizontal edge on the row crosses it
                        column[m] = min(max(math.ceil(min(ax[e], bx[e]) - 0.5), 0), width)
                        winding[m] = 1
                        m += 1
                    continue
                if bug == INCLUSIVE_ENDS:  # BUG: [ylo, yhi] instead of [ylo, yhi)
                    crosses = min(ay[e], by[e]) <= ys <= max(ay[e], by[e])
                else:  # top-left: a vertex on the row lies above the sample
                    crosses = (ay[e] <= ys) != (by[e] <= ys)
                if not crosses:
                    continue
                # tie_right = crosses (True here): a runtime flag, not the literal True, so that the
                # built-in fill's compiled crossing_column serves (numba compiles one per literal)
                column[m] = crossing_column(ax[e], ay[e], bx[e], by[e], crosses, 0.5, ys, width)
                # BUG (unsigned-crossings): the direction is lost, every crossing adds +1
                winding[m] = 1 if bug == UNSIGNED_CROSSINGS or by[e] > ay[e] else -1
                m += 1
            stable_argsort(column, m, order, spare)  # order[:m]
            wind = 0
            start = -1
            k = 0
            while k < m:
                c = column[order[k]]
                while k < m and column[order[k]] == c:
                    wind += winding[order[k]]
                    if bug == INT8_WINDING:  # BUG: a signed 8-bit counter wraps
                        wind = ((wind + 128) & 255) - 128
                    elif bug == INT16_WINDING:  # BUG: a signed 16-bit counter wraps
                        wind = ((wind + 32768) & 65535) - 32768
                    elif bug == INT8_SATURATING:  # BUG: a signed 8-bit counter saturates
                        wind = min(max(wind, -128), 127)
                    k += 1
                inside = (wind & 1) == 1 if evenodd else wind != 0
                if inside and start < 0:
                    start = c
                elif not inside and start >= 0:
                    out_p[n] = p
                    out_y[n] = j
                    out_x0[n] = start
                    out_x1[n] = c
                    n += 1
                    start = -1
            if start >= 0 and m and column[order[m - 1]] > start:  # the last trapezoid ends at the last crossing
                out_p[n] = p
                out_y[n] = j
                out_x0[n] = start
                out_x1[n] = column[order[m - 1]]
                n += 1
    return out_p[:n], out_y[:n], out_x0[:n], out_x1[:n]


class TwoFillers:
    """Paths and triangles drawn by two separate code paths that disagree on ties (as in a
    2D library whose polygon filler and triangle filler were written apart): triangles by
    the reference with top-left ties, paths by the same algorithm with bottom-right ties.
    Convention-free, the triangulation check sees it: a simple polygon then covers other
    samples than its own triangulation does."""

    name = "bad_two_fillers"
    convention = None
    scene_kinds = ("triangles", "paths")
    interpolates = False

    def __init__(self) -> None:
        from rasterizers.trapezoid import TrapezoidFill

        self._triangles, self._paths = TrapezoidFill(), TrapezoidFill(tie="bottom-right")

    def rasterize(self, scene: AnyScene) -> Coverage:
        return (self._paths if isinstance(scene, PathScene) else self._triangles).rasterize(scene)
