"""What "correct" means: screen space, sample points, tie rules, snapping and culling.

This module states the definitions of a convention once; everything else in
rastercheck (the oracle, the reference rasterizers, the checks) applies them.

Screen space
    x grows right, y grows down, units are pixels, row 0 is the top row. Pixel (i, j)
    -- column i, row j -- is the unit square [i, i+1) x [j, j+1). Images are numpy
    arrays indexed ``[y, x]`` with shape ``(height, width)``.

Signed area
    ``A = (x1-x0)*(y2-y0) - (y1-y0)*(x2-x0)``. With y down, A > 0 means the vertices run
    clockwise as seen on screen. Both windings draw the same unless culling asks otherwise;
    a triangle whose (snapped) area is exactly zero covers nothing, always.

Edge function
    For the edge from a to b, ``E_ab(p) = (bx-ax)*(py-ay) - (by-ay)*(px-ax)``. For a
    triangle with A > 0 the interior is where all three of E_01, E_12, E_20 are positive.

A convention is sample point + tie rule + snapping (+ culling)
    1. Sample point ``(sx, sy)``: pixel (i, j) is covered when the point (i+sx, j+sy) is
       inside the triangle. GL, D3D10+ and Vulkan use the centre (0.5, 0.5).
    2. Tie rule: who owns a sample lying exactly on an edge or vertex, defined once for
       every rule by symbolic perturbation: such a sample p is decided at p + d(eps),
       eps -> 0+, with ``d = (sx*eps, sy*eps**2)`` for the *x-first* rules and
       ``d = (sx*eps**2, sy*eps)`` for the *y-first* ones, sx, sy in {+1, -1} (y down).
       E is linear, so ``E(p + d) = E(p) + dE/dx*d_x + dE/dy*d_y``: a sample exactly on
       edge a-b (``E(p) = 0``; dE/dx = -(by-ay), dE/dy = bx-ax) is inside that edge when
       ``sign(dE/dx * sx) > 0`` if dE/dx != 0, else ``sign(dE/dy * sy) > 0`` (x-first; swap
       the roles of x and y for y-first). Each edge owns or does not own its samples, and
       a sample on a vertex is inside only if it passes every edge test -- the perturbed
       point's own test.

       =====================  ========  ===================================================
       rule                   d         owns the samples of
       =====================  ========  ===================================================
       ``top-left``           (+, +)    left edges (not horizontal, interior to the right)
                                        and top edges (horizontal, interior below): D3D10+
       ``top-right``          (-, +)    right edges and top edges
       ``bottom-left``        (+, -)    left edges and bottom edges
       ``bottom-right``       (-, -)    right edges and bottom edges (the floor scanline)
       ``top-left-y-first``   (+, +)    top edges (not vertical, interior below) and left
                                        edges (vertical, interior to the right)
       ``top-right-y-first``  (-, +)    top edges and right (vertical) edges
       ``bottom-left-y-first`` (+, -)   bottom edges (not vertical, interior above) and
                                        left (vertical) edges
       ``bottom-right-y-first`` (-, -)  bottom edges and right (vertical) edges
       =====================  ========  ===================================================

       x-first and y-first rules differ only on slanted edges: on horizontal and vertical
       ones both ask the same question.

       *Exactly once.* Two triangles sharing an edge lie on opposite sides of it, so their
       edge functions are exact negatives and the perturbed sign is positive for exactly
       one of them. More generally, for any planar partition the perturbed point p + d(eps)
       lies on no edge line for small eps > 0 (the lowest-order term of E(p + d) is
       nonzero, since an edge's gradient is not zero), so it is interior to exactly one
       piece: no crack and no double hit, at edges and at vertices where any number of
       triangles meet.

       *Who uses which.* D3D10+ mandates top-left (y down); GL and Vulkan require only
       that a shared edge's samples be produced once, and drivers pick a rule in their own
       framebuffer orientation (llvmpipe: top-left with window row y taken as row y, as
       rastercheck's Mesa adapter does). piglit's ``triangle-rasterization`` test names
       eight conventions by which of its eight sub-pixel triangles around a pixel centre
       (GL window coordinates, y up) is drawn: ``top_left``, ``top_right``,
       ``bottom_left``, ``bottom_right`` are the x-first rules and ``left_top``,
       ``right_top``, ``left_bottom``, ``right_bottom`` the y-first ones (the vertical
       edges' owner first, then the others'). Read in GL's orientation (the image shown
       with its origin at the bottom), each piglit name ``A_B`` is the rule of the same
       sides: ``left_top`` is ``top-left-y-first``, ``top_right`` is ``top-right``. With
       window y taken as rastercheck's y unflipped (row y = window row y), top and bottom
       trade places: ``top_left`` is ``bottom-left``, ``left_top`` is
       ``bottom-left-y-first`` (:data:`PIGLIT_NAMES`). piglit's own reference rasterizer
       (``rast_triangle``) biases the y-first four the other way round -- its
       ``left_bottom`` bias draws what its probe calls ``right_top`` and so on -- which
       never shows on drivers that use an x-first rule.
    3. Snapping ``subpixel_bits = n``: every coordinate c becomes ``round(c * 2**n) / 2**n``
       before anything else, rounding half to even (``nearest-even``: D3D, GL drivers),
       half away from zero (``half-away``: ``(int64)(v * 2**n +/- 0.5)``, dEQP's reference
       renderer), down (``floor``: truncating fixed-point conversion, skia), or half away
       from zero in the frame shifted by half a pixel (``half-away-shifted``: piglit's
       ``rast_triangle``, ``iround(2**n * (c - 1/2))`` with its ``iround`` half away from
       zero, the half pixel added back: a tie c*2**n = k + 1/2 rounds up when c > 1/2 and
       down when c < 1/2 -- unlike ``half-away``, which rounds the ties in (0, 1/2) up).
       ``None``: no snapping, decisions are exact on the float64 input.
    4. Culling ``none | cw | ccw``: ``cw`` removes triangles with snapped A > 0 (clockwise
       on screen), ``ccw`` those with A < 0.

Input precision ``input`` comes first, before snapping: the coordinates a rasterizer receives
    ``float64`` (the default: what the scene holds), ``float32`` (each coordinate rounded to the
    nearest float32, ties to even -- every GPU API, and the piglit and dEQP reference
    rasterizers, which compute in float32), ``fixedN`` (a fixed-point input grid of 2**-N px,
    e.g. ``fixed6`` = 26.6 as FreeType and Qt receive) or ``integer`` (whole pixels, as pygame),
    the grids with a rounding suffix ``-half-away``, ``-floor`` or ``-toward-zero`` (C's
    ``(int)`` cast; none: nearest-even). The convention's own snapping then applies to the
    received coordinates (:class:`InputPrecision`, :meth:`Convention.snap`).

A convention's coverage is one of three kinds (:attr:`Convention.coverage_kind`), each a coverage
model (:attr:`Convention.model`, :mod:`harness.contract.coverage_models`: area coverage with a
sample pattern is the supersampled area model)
    ``single``
        One sample per pixel at ``sample``: a fragment is a (triangle, pixel).
    ``multisample``
        ``samples`` is a pattern (:func:`harness.contract.samples.pattern`: D3D11/Vulkan standard
        counts 1, 2, 4, 8, 16, or any dyadic offsets): sample s of pixel (i, j) is the point
        (i + sx_s, j + sy_s), and each sample obeys the tie rule, snapping and culling on its
        own, exactly as a single-sample convention at that offset
        (:meth:`Convention.at_sample`). A fragment is a (triangle, sample, pixel).
    ``area``
        Anti-aliased: each (triangle, pixel) gets an alpha, the area of the (snapped)
        triangle inside the pixel square [i, i+1] x [j, j+1], quantised to ``levels``
        levels (alpha a multiple of 1/(levels - 1)) and within ``tolerance`` of the exact
        area. Ties and the sample point mean nothing here: an edge has no area.
        With ``samples`` too, the alpha is *supersampled*: the share of the pattern's
        samples the triangle covers (a box-filter resolve: each sample under the tie rule,
        snapping and culling), which is what a supersampling anti-aliaser computes and is
        judged against exactly; its distance from the true area is an artifact the checks
        measure (popping), not a broken promise.

    The coverage rules (``single`` kind, one (triangle, pixel) covered or not, but decided on
    the pixel's square [i, i+1] x [j, j+1] instead of at a sample point; after snapping and
    culling; a triangle of zero snapped area covers nothing; :mod:`harness.oracle.coverage_rules`)
        ``area-threshold``
            Covered iff area(T ∩ square) >= ``threshold`` (default 1/2), the area exact
            (rational); a pixel covered exactly ``threshold`` is drawn (ties are inside).
            aggdraw's aliased mode.
        ``conservative-over``
            Covered iff the closed square meets the closed triangle (touching counts): D3D12
            and Vulkan conservative rasterization, overestimate; ``uncertainty`` u (default 0)
            also allows the squares that, grown by u, meet it.
        ``conservative-under``
            Covered iff the closed square lies inside the closed triangle (a side on an edge
            counts): D3D12's underestimate (Vulkan's inner coverage); ``uncertainty`` u
            requires only the squares that, grown by u, lie inside.
        ``agg-cover``
            AGG's scanline rasterizer on 24.8 fixed point (``input="fixed8-..."``): covered
            iff the pixel's 8-bit cover, ``|V >> 9|`` capped at 255 with V the doubled signed
            area of AGG's cell polygon in the pixel, is at least ``256 * threshold``
            (aggdraw aliased: 1/2; matplotlib aliased: 1/256). :mod:`harness.oracle.library_rules`.
        ``inclusive-scanline``
            pygame's ``draw_fillpoly`` on whole pixels (``input="integer-..."``): each row
            from the lowest vertex to the highest, from the truncated left crossing of the
            closed triangle to the truncated right one, both drawn (zero area too).
        ``closed``
            Decided at ``sample`` like one sample per pixel, but a sample exactly on an
            edge is inside for every triangle sharing the edge (no tie rule): covered iff
            the sample lies in the closed triangle; a zero-area triangle covers the samples
            on its segment. FreeType's monochrome rasterizer. ``dropout`` adds TrueType's
            dropout control (:class:`Dropout`, :mod:`harness.oracle.dropout`).
        The tie rule means nothing to them, nor ``sample`` but to ``closed``. A planar partition is not hit
        exactly once: double hits (over, threshold) and holes (under, threshold) are the
        rule's own, and the checks excuse those the exact answer has.

Lines (line scenes) are drawn by the convention's :class:`LineRule`
    ``diamond-exit`` (D3D11; the last pixel omitted or drawn), ``diamond-exit-gl`` (GL's
    perturbed end points), ``bresenham`` (seed 003's
    integer algorithm, end points to pixels by a declared rounding, walked from the first
    end point or, as textbooks' ``plotLine``, from the one with smaller x or smaller major
    coordinate), ``rectangle``
    (Vulkan: the samples inside a w-wide rectangle around the segment, under the sample
    point and tie rule above) or ``parallelogram`` (Vulkan's non-strict lines: the
    segment widened by w/2 either way along its minor axis, likewise), each after snapping
    (with the rule's own snap rounding when it has one); defined in :mod:`harness.oracle.lines`. Under
    a multisample convention lines are rectangles sampled at every sample of the pattern
    (GL 14.5.4 "Line Multisample Rasterization", dEQP): ``line=LineRule("rectangle")``.

Every decision is exact: the sign of an edge function is the sign of the exact real
number (floats are dyadic rationals). No epsilon appears in any coverage decision.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass, replace
from typing import Any, Literal, cast

import numba
import numpy as np
from numpy.typing import NDArray

# the coverage models, their kinds and sample limits (re-exported: defined beside them)
from harness.contract.coverage_models import (
    COVERAGE_KINDS,
    DECLARED_COVERAGES,
    MAX_AREA_SAMPLES,
    MAX_SAMPLES,
    QUANTISED_AREA,
    SKIA_SUPERSAMPLED_AREA,
    CoverageKind,
    CoverageModel,
    model_for,
)
from harness.contract.quantisations import NEAREST, QUANTISATION_NAMES

__all__ = [
    "TIE_RULES",
    "FILL_RULES",
    "FillRule",
    "TieRule",
    "CullMode",
    "SnapRounding",
    "TIE_PERTURBATION",
    "PIGLIT_NAMES",
    "SNAP_ROUNDINGS",
    "SNAP_ROUNDING_WORDS",
    "PLAIN_SNAP_ROUNDINGS",
    "CULL_MODES",
    "MAX_SUBPIXEL_BITS",
    "SAMPLE_FRACTION_BITS",
    "MAX_SAMPLES",
    "MAX_AREA_SAMPLES",
    "COVERAGE_KINDS",
    "CoverageKind",
    "Convention",
    "snap",
    "InputPrecision",
    "INPUT_ROUNDINGS",
    "InputRounding",
    "input_precision",
    "owns_edge",
    "LineRule",
    "LineRuleName",
    "LINE_RULES",
    "DIAMOND_RULES",
    "AREA_LINE_RULES",
    "FIXED_POINT_LINE_RULES",
    "LIBRARY_LINE_RULES",
    "BRESENHAM_ROUNDINGS",
    "BRESENHAM_TIES",
    "BresenhamRounding",
    "BresenhamTies",
    "LINE_DIRECTIONS",
    "LineDirection",
    "WIDE_LINES",
    "WideLines",
    "Dropout",
    "DropoutMode",
    "DROPOUT_MODES",
    "dropout_control",
    "LINE_CAPS",
    "LineCap",
]

TieRule = Literal[
    "top-left", "top-right", "bottom-left", "bottom-right",
    "top-left-y-first", "top-right-y-first", "bottom-left-y-first", "bottom-right-y-first",
]
CullMode = Literal["none", "cw", "ccw"]
LineRuleName = Literal["diamond-exit", "diamond-exit-gl", "bresenham", "rectangle", "parallelogram", "skia-hairline",
                       "qt-cosmetic", "llvmpipe-rectangle"]
LINE_RULES: tuple[LineRuleName, ...] = ("diamond-exit", "diamond-exit-gl", "bresenham", "rectangle", "parallelogram",
                                        "skia-hairline", "qt-cosmetic", "llvmpipe-rectangle")
# The diamond rules: D3D11's test areas, and GL's open diamonds with perturbed end points.
DIAMOND_RULES: tuple[LineRuleName, ...] = ("diamond-exit", "diamond-exit-gl")
# The rules that cover the samples inside a region around the segment (any width, the
# convention's sample point and tie rule)
AREA_LINE_RULES: tuple[LineRuleName, ...] = ("rectangle", "parallelogram", "llvmpipe-rectangle")
# Libraries' one-pixel lines read from their sources: fixed-point DDAs on 26.6 end points
# (harness.oracle.hairlines: skia's SkScan::HairLineRgn, Qt's QCosmeticStroker::drawLine)
FIXED_POINT_LINE_RULES: tuple[LineRuleName, ...] = ("skia-hairline", "qt-cosmetic")
# The rules read from one library's source (those, and llvmpipe's rectangular lines):
# identify names one only where it explains that library's lines (line_probes.fit_lines)
LIBRARY_LINE_RULES: tuple[LineRuleName, ...] = FIXED_POINT_LINE_RULES + ("llvmpipe-rectangle",)
BresenhamRounding = Literal["nearest-even", "half-away", "floor", "toward-zero"]
BresenhamTies = Literal["step", "stay"]
BRESENHAM_ROUNDINGS: tuple[BresenhamRounding, ...] = ("nearest-even", "half-away", "floor", "toward-zero")
BRESENHAM_TIES: tuple[BresenhamTies, ...] = ("step", "stay")
# Where a Bresenham walk starts: at the first end point as given, or (textbook plotLine)
# at the end point with the smaller x, or with the smaller major-axis coordinate.
LineDirection = Literal["as-given", "smaller-x", "smaller-major"]
LINE_DIRECTIONS: tuple[LineDirection, ...] = ("as-given", "smaller-x", "smaller-major")
# How a diamond rule draws lines wider than 1: not at all, or (GL's wide lines) by
# replicating each fragment along the minor axis, integer widths.
WideLines = Literal["none", "replicate"]
WIDE_LINES: tuple[WideLines, ...] = ("none", "replicate")
# TrueType's dropout control (scan-conversion rules 3-6) as FreeType's ftraster.c runs it
DropoutMode = Literal["none", "simple", "smart"]
DROPOUT_MODES: tuple[DropoutMode, ...] = ("none", "simple", "smart")
# The ends of an anti-aliased rectangular line (issue 34): cut square at the end points
# (butt), the rectangle extended by w/2 at both ends (square), or half discs (round).
LineCap = Literal["butt", "square", "round"]
LINE_CAPS: tuple[LineCap, ...] = ("butt", "square", "round")
SnapRounding = Literal["nearest-even", "half-away", "floor", "half-away-shifted"]
# How a fixed-point or integer input grid rounds what it receives: the snap roundings and C's
# ``(int)`` cast (toward zero).
InputRounding = Literal["nearest-even", "half-away", "floor", "toward-zero"]
INPUT_ROUNDINGS: tuple[InputRounding, ...] = ("nearest-even", "half-away", "floor", "toward-zero")

# rule -> (sx, sy, y_first): the sample is decided as if moved by (sx*eps, sy*eps**2), or
# by (sx*eps**2, sy*eps) when y_first (y down, eps -> 0+).
TIE_PERTURBATION: dict[str, tuple[int, int, bool]] = {
    "top-left": (1, 1, False),
    "top-right": (-1, 1, False),
    "bottom-left": (1, -1, False),
    "bottom-right": (-1, -1, False),
    "top-left-y-first": (1, 1, True),
    "top-right-y-first": (-1, 1, True),
    "bottom-left-y-first": (1, -1, True),
    "bottom-right-y-first": (-1, -1, True),
}
TIE_RULES: tuple[TieRule, ...] = cast("tuple[TieRule, ...]", tuple(TIE_PERTURBATION))

# The fill rules of paths (harness.oracle.winding): a sample is inside a path when its winding
# number is nonzero, or odd.
FillRule = Literal["nonzero", "evenodd"]
FILL_RULES: tuple[FillRule, ...] = ("nonzero", "evenodd")
# piglit's eight filling conventions (GL window coordinates, y up) -> rastercheck's rule
# for that driver, with window y taken as rastercheck's y (row y = window row y).
PIGLIT_NAMES: dict[str, TieRule] = {
    "top_left": "bottom-left", "top_right": "bottom-right",
    "bottom_left": "top-left", "bottom_right": "top-right",
    "left_top": "bottom-left-y-first", "right_top": "bottom-right-y-first",
    "left_bottom": "top-left-y-first", "right_bottom": "top-right-y-first",
}
CULL_MODES: tuple[CullMode, ...] = ("none", "cw", "ccw")
# appended last: a later rounding loses every tie of identify's fits to the earlier ones
SNAP_ROUNDINGS: tuple[SnapRounding, ...] = ("nearest-even", "half-away", "floor", "half-away-shifted")
# The snap roundings that part outside the first half pixel: the probes of lines, area grids
# and coverage rules fit these (their scenes hold no half step in (0, 1/2), where alone piglit's
# shifted frame parts from half-away); the triangle snapping fit has such scenes and fits all.
PLAIN_SNAP_ROUNDINGS: tuple[SnapRounding, ...] = ("nearest-even", "half-away", "floor")
# a few words per snap rounding, for people
SNAP_ROUNDING_WORDS: dict[str, str] = {
    "nearest-even": "half to even", "half-away": "half away from zero", "floor": "rounding down",
    "half-away-shifted": "half away from the pixel centre, piglit's shifted frame"}
MAX_SUBPIXEL_BITS = 16
# A sample offset must be a multiple of 2**-32 so that i + sx is exact for every pixel
# column i of any viewport up to 2**20 pixels wide.
SAMPLE_FRACTION_BITS = 32
# At or above 2**52 every float64 is an integer, so snapping leaves it alone; below it,
# c * 2**16 < 2**68 cannot overflow and the product is exact (a power-of-two scale).
_SNAP_IDENTITY_ABOVE = 2.0**52


@dataclass(frozen=True, slots=True, repr=False)
class LineRule:
    """How a convention draws aliased lines (line scenes, :class:`harness.contract.scenes.LineScene`);
    the definitions and their sources are in :mod:`harness.oracle.lines`.

    Parameters
    ----------
    rule : {"diamond-exit", "diamond-exit-gl", "bresenham", "rectangle", "parallelogram", "skia-hairline", "qt-cosmetic", \
            "llvmpipe-rectangle"}
        ``diamond-exit``: a pixel is drawn when the segment leaves its diamond test area
        (D3D11 3.4.3: lower edges and bottom corner in, y-major lines also the right
        corner); width 1. ``diamond-exit-gl``: GL's (OpenGL 4.6 14.5.1): the segment with
        both end points moved by -(eps, eps**2) meets the open diamond and its end point
        does not lie in it (right edges and right corner in, window y taken as rows);
        width 1. ``bresenham``: seed 003's integer
        algorithm between the end points' pixels; width 1. ``rectangle``: the samples
        inside the ``line_width``-wide rectangle around the segment, under the
        convention's sample point and tie rule (Vulkan's rectangular lines); under a
        multisample convention, at each sample of its pattern (GL's multisample lines,
        the only rule defined there). ``parallelogram``: Vulkan's non-strict lines (Vulkan
        1.4, "Basic Line Segment Rasterization", ``strictLines`` false): the samples inside
        the parallelogram whose two sides are the segment moved by +-``line_width``/2 along
        its minor axis (y for an x-major segment, |dy| <= |dx|) and whose two ends are
        parallel to that axis through the end points, under the convention's sample point
        and tie rule (:mod:`harness.oracle.parallelogram_lines`). ``skia-hairline`` and
        ``qt-cosmetic``: skia's hairlines (``SkScan::HairLineRgn``) and Qt's cosmetic lines
        (``QCosmeticStroker::drawLine``, square caps), fixed-point DDAs on end points
        truncated to 26.6, read from their sources (:mod:`harness.oracle.hairlines`); width 1.
        ``llvmpipe-rectangle``: llvmpipe's (lavapipe's) rectangular lines
        (``lp_setup_line.c``): the quad of the snapped end points +- the half-width normal,
        computed in float32 from the unsnapped ends and snapped on its own, under the
        convention's sample point and tie rule (:mod:`harness.oracle.llvmpipe_lines`).
    last_pixel : bool or None
        diamond-exit and bresenham: also draw the pixel the segment ends in (a polyline's
        shared vertices are then drawn twice). None: the rule's own (diamond-exit omits
        it, seed 003's Bresenham draws both end points). Not used by ``rectangle``.
    rounding : {"nearest-even", "half-away", "floor", "toward-zero"}
        bresenham: how an end point picks its pixel (the pixel whose centre is nearest,
        halves to even or away from zero; ``floor``; or ``toward-zero``, C's ``(int)`` cast,
        as softpipe and Pillow do: pixel 0 for -1 < x < 1).
    ties : {"step", "stay"}
        bresenham: the minor coordinate on a tie of the decision variable (of the walk,
        once ``direction`` has chosen where it starts).
    direction : {"as-given", "smaller-x", "smaller-major"}
        bresenham: where the walk starts. ``as-given``: at the segment's first end point
        (seed 003, softpipe, Pillow). ``smaller-x``: at the end point whose pixel has the
        smaller x (the given order when equal), as textbooks' ``plotLine`` that swap the end
        points to always walk towards +x. ``smaller-major``: at the end point whose pixel
        has the smaller major-axis coordinate (x for x-major segments, y for y-major ones),
        as Wikipedia's ``plotLineLow``/``plotLineHigh`` and tinyrenderer's ``line`` do.
        Then the walk's ties are ``ties`` and its last pixel (the end it walks to, not
        necessarily the given one) is drawn when ``last_pixel``: a normalising drawer
        draws a segment and its reverse alike (but for the omitted end of one whose end
        pixels share their x, walked from the smaller x: it keeps its given order).
    wide : {"none", "replicate"}
        The diamond rules: ``none`` draws width 1 only (a wider scene is undefined);
        ``replicate`` draws an integer width w as GL's wide lines do (OpenGL 4.6, 14.5.2
        "Other Line Segment Features", wide lines): the segment moved by -(w - 1)/2 along
        its minor axis is drawn by the width-1 rule, and each fragment becomes w along the
        minor axis, the width-1 one first (rows y .. y + w - 1 of an x-major segment,
        columns x .. x + w - 1 of a y-major one, window y taken as rows).
    snap_rounding : {"nearest-even", "half-away", "floor"} or None
        How line end points snap, when it differs from the convention's ``snap_rounding``
        for triangles (lavapipe snaps line ends half away from zero and triangle vertices
        to nearest-even); None: the convention's. The grid is the convention's
        ``subpixel_bits`` either way.

    cap : {"butt", "square", "round"}
        ``rectangle`` under area coverage only (anti-aliased strokes,
        :mod:`harness.oracle.area_lines`): the region whose area inside a pixel is the alpha.
        ``butt``: the ``line_width``-wide rectangle between the end points; ``square``: that
        rectangle extended by ``line_width``/2 beyond each end point; ``round``: the butt
        rectangle and a half disc of diameter ``line_width`` on each end (cairo's and skia's
        ``CAP_BUTT``, ``CAP_SQUARE``, ``CAP_ROUND``). Aliased lines are butt.

    The convention's snapping (``subpixel_bits``, ``snap_rounding``, or this rule's
    ``snap_rounding``) applies to line end points first, as to triangle vertices
    (:meth:`Convention.for_lines`).

    Examples
    --------
    >>> LineRule()
    LineRule(rule='diamond-exit', last_pixel=False, rounding='nearest-even', ties='step', direction='as-given', wide='none')
    >>> LineRule("bresenham", rounding="floor").describe()
    'Bresenham lines, end points to pixels by floor, ties step, last pixel drawn'
    >>> LineRule("bresenham", ties="stay", direction="smaller-x").describe()
    'Bresenham lines walked from the end point with smaller x, end points to pixels by nearest-even, ties stay, last pixel drawn'
    >>> LineRule("parallelogram", snap_rounding="half-away").describe()
    'parallelogram lines (Vulkan non-strict), line ends snapped half away from zero'
    >>> LineRule("parallelogram", snap_rounding="half-away")  # doctest: +ELLIPSIS
    LineRule(rule='parallelogram', last_pixel=False, ..., wide='none', snap_rounding='half-away')
    >>> LineRule("rectangle", cap="square").describe()
    'rectangular lines, square caps'
    """

    rule: LineRuleName = "diamond-exit"
    last_pixel: bool | None = None
    rounding: BresenhamRounding = "nearest-even"
    ties: BresenhamTies = "step"
    direction: LineDirection = "as-given"
    wide: WideLines = "none"
    snap_rounding: SnapRounding | None = None
    cap: LineCap = "butt"

    def __repr__(self) -> str:
        # snap_rounding only when set: a rule without it reads as it always has
        fields = (f"rule={self.rule!r}, last_pixel={self.last_pixel!r}, rounding={self.rounding!r}, ties={self.ties!r}, "
                  f"direction={self.direction!r}, wide={self.wide!r}")
        if self.snap_rounding is not None:
            fields += f", snap_rounding={self.snap_rounding!r}"
        if self.cap != "butt":  # likewise the cap, only when not butt
            fields += f", cap={self.cap!r}"
        return f"LineRule({fields})"

    def __post_init__(self) -> None:
        if self.rule not in LINE_RULES:
            raise ValueError(f"LineRule.rule must be one of {', '.join(LINE_RULES)}, not {self.rule!r}")
        if self.last_pixel is None:
            object.__setattr__(self, "last_pixel", self.rule == "bresenham")
        if not isinstance(self.last_pixel, (bool, np.bool_)):
            raise ValueError(f"LineRule.last_pixel must be True, False or None, not {self.last_pixel!r}")
        object.__setattr__(self, "last_pixel", bool(self.last_pixel))
        if self.rounding not in BRESENHAM_ROUNDINGS:
            raise ValueError(f"LineRule.rounding must be one of {', '.join(BRESENHAM_ROUNDINGS)}, not {self.rounding!r}")
        if self.ties not in BRESENHAM_TIES:
            raise ValueError(f"LineRule.ties must be one of {', '.join(BRESENHAM_TIES)}, not {self.ties!r}")
        if self.direction not in LINE_DIRECTIONS:
            raise ValueError(f"LineRule.direction must be one of {', '.join(LINE_DIRECTIONS)}, not {self.direction!r}")
        if self.direction != "as-given" and self.rule != "bresenham":
            raise ValueError(f"LineRule.direction {self.direction!r} is a Bresenham option; {self.rule} lines are drawn "
                             "as given (use rule='bresenham', or leave direction='as-given')")
        if self.wide not in WIDE_LINES:
            raise ValueError(f"LineRule.wide must be one of {', '.join(WIDE_LINES)}, not {self.wide!r}")
        if self.wide != "none" and not self.diamond:
            raise ValueError(f"LineRule.wide {self.wide!r} is a diamond-exit option; {self.rule} lines "
                             + ("have their own width" if self.rule in AREA_LINE_RULES else "are 1 px wide"))
        if self.snap_rounding is not None and self.snap_rounding not in SNAP_ROUNDINGS:
            raise ValueError(f"LineRule.snap_rounding must be None or one of {', '.join(SNAP_ROUNDINGS)}, "
                             f"not {self.snap_rounding!r}")
        if self.cap not in LINE_CAPS:
            raise ValueError(f"LineRule.cap must be one of {', '.join(LINE_CAPS)}, not {self.cap!r}")
        if self.cap != "butt" and self.rule != "rectangle":
            raise ValueError(f"LineRule.cap {self.cap!r} is a rectangle option (anti-aliased strokes); "
                             f"{self.rule} lines have no caps")

    def undefined_width(self, line_width: float) -> str:
        """Why the rule draws no lines ``line_width`` wide ("" when it does): rectangles take
        any width, replicated diamond lines an integer one, the others width 1 only."""
        if self.rule in AREA_LINE_RULES or line_width == 1.0:
            return ""
        if self.wide == "replicate":
            if line_width == math.floor(line_width) and 1.0 <= line_width <= 2.0**20:
                return ""
            return (f"{self.describe()} have integer widths, not {line_width:g}: the rule does not define it "
                    "(GL rounds the width first: round it in the scene)")
        return f"{self.describe()} have width 1, not {line_width:g}: the rule does not define wider lines"

    @property
    def diamond(self) -> bool:
        """A diamond-exit rule (D3D's or GL's)."""
        return self.rule in DIAMOND_RULES

    @property
    def own_snapping(self) -> bool:
        """The rule snaps its end points itself (llvmpipe's rectangular lines: its own grid and
        rounding, :mod:`harness.oracle.llvmpipe_lines`): the convention's ``subpixel_bits`` and
        ``snap_rounding`` play no part in it."""
        return self.rule == "llvmpipe-rectangle"

    @property
    def gl(self) -> bool:
        """GL's diamond-exit rule (end points perturbed by -(eps, eps**2))."""
        return self.rule == "diamond-exit-gl"

    @property
    def walk(self) -> str:
        """Where the walk starts, for people ("" when as given)."""
        return {"as-given": "", "smaller-x": "walked from the end point with smaller x",
                "smaller-major": "walked from the end point with smaller major coordinate"}[self.direction]

    def describe(self) -> str:
        """One line for people."""
        own = {None: "", "nearest-even": ", line ends snapped to nearest-even", "half-away":
               ", line ends snapped half away from zero", "floor": ", line ends snapped down",
               "half-away-shifted": ", line ends snapped half away in piglit's shifted frame"}[self.snap_rounding]
        return self._rule_words() + own

    def _rule_words(self) -> str:
        if self.rule == "rectangle":
            return "rectangular lines" + ("" if self.cap == "butt" else f", {self.cap} caps")
        if self.rule == "parallelogram":
            return "parallelogram lines (Vulkan non-strict)"
        if self.rule == "llvmpipe-rectangle":
            return ("llvmpipe rectangular lines (ends and half-width normal each snapped to 1/256 px, half away "
                    "in the frame shifted by half a pixel)")
        if self.rule == "skia-hairline":
            return "skia hairlines (26.6 ends toward zero, 16.16 DDA)"
        if self.rule == "qt-cosmetic":
            return "Qt cosmetic lines (26.6 ends toward zero, square caps, 16.16 DDA)"
        last = "last pixel drawn" if self.last_pixel else "last pixel omitted"
        wide = ", wide lines by replication along the minor axis" if self.wide == "replicate" else ""
        if self.rule == "diamond-exit":
            return f"diamond-exit lines, {last}{wide}"
        if self.rule == "diamond-exit-gl":
            return f"GL diamond-exit lines (end points moved by -(eps, eps^2)), {last}{wide}"
        walk = f" {self.walk}" if self.walk else ""
        if walk and not self.last_pixel:
            last += " (the end walked to)"
        return f"Bresenham lines{walk}, end points to pixels by {self.rounding}, ties {self.ties}, {last}"


@dataclass(frozen=True, slots=True)
class Dropout:
    """Dropout control and scanline crossings of the ``closed`` rule: TrueType's scan
    conversion as FreeType's monochrome rasterizer (``src/raster/ftraster.c``) runs it;
    the definitions, with ftraster.c's functions, are in :mod:`harness.oracle.dropout`.

    Parameters
    ----------
    mode : {"none", "simple", "smart"}
        ``none``: no dropout control (``FT_OUTLINE_IGNORE_DROPOUTS``; SCANTYPE 2).
        Otherwise, where a scanline's span between two crossings holds no pixel centre and
        its ends lie in neighbouring pixels, one pixel is drawn anyway unless the other is
        already drawn: ``simple`` the left (lower) one (SCANTYPE 0, 1), ``smart`` the one
        whose centre is nearer the span's midpoint, ties to the left (SCANTYPE 4, 5;
        ``FT_OUTLINE_SMART_DROPOUTS``); in rows, and in columns (the second sweep).
    stubs : bool
        Whether dropouts at a contour's turning scanline (stubs) are drawn too (SCANTYPE 0
        and 4, ``FT_OUTLINE_INCLUDE_STUBS``); False (SCANTYPE 1, 5) draws a stub only where
        the outline overshoots the scanline by at least half a pixel on a span at least half
        a pixel wide.
    step_bits : None or 6
        None: crossings exact (rational). 6: crossings computed as ftraster.c's
        ``Line_Up`` does on its 1/64 px grid (FreeType's default precision): from the
        edge's start, the first rounded to nearest, then whole steps truncated toward the
        start (:func:`harness.oracle.dropout.stepped_crossing`), so the pixels depend on an
        edge's direction; needs the input on that grid (``input="fixed6"``).

    A convention keeps it as its canonical name (:attr:`name`, as ``input`` keeps its
    precision's), so that a convention's fields stay JSON values:

    >>> Dropout("smart", stubs=False).describe()
    'smart dropout control (SCANTYPE 5, stubs excluded)'
    >>> Dropout("smart", stubs=False, step_bits=6).name, dropout_control("simple-stepped6")
    ('smart-no-stubs-stepped6', Dropout(mode='simple', stubs=True, step_bits=6))
    >>> Dropout.from_json(Dropout("simple", step_bits=6).to_json()) == Dropout("simple", step_bits=6)
    True
    """

    mode: DropoutMode = "none"
    stubs: bool = True
    step_bits: int | None = None

    def __post_init__(self) -> None:
        if self.mode not in DROPOUT_MODES:
            raise ValueError(f"Dropout.mode must be one of {', '.join(DROPOUT_MODES)}, not {self.mode!r}")
        if not isinstance(self.stubs, (bool, np.bool_)):
            raise ValueError(f"Dropout.stubs must be True or False, not {self.stubs!r}")
        object.__setattr__(self, "stubs", bool(self.stubs))
        bits = self.step_bits
        if bits is not None and (isinstance(bits, bool) or not isinstance(bits, (int, np.integer)) or bits != 6):
            raise ValueError(f"Dropout.step_bits must be None (exact crossings) or 6 (ftraster.c's 1/64 px), not {bits!r}")
        if bits is not None:
            object.__setattr__(self, "step_bits", int(bits))

    @property
    def name(self) -> str:
        """Its canonical name: the mode, ``-no-stubs`` when stubs are excluded, ``-stepped6``
        when crossings are stepped (``none``, ``smart-no-stubs-stepped6``)."""
        stubs = "-no-stubs" if self.mode != "none" and not self.stubs else ""
        return self.mode + stubs + ("" if self.step_bits is None else f"-stepped{self.step_bits}")

    @property
    def active(self) -> bool:
        """Whether it changes anything (dropouts drawn, or crossings stepped)."""
        return self.mode != "none" or self.step_bits is not None

    @property
    def scantype(self) -> int:
        """TrueType's SCANTYPE (FreeType's dropout mode) for it: 0, 1, 2, 4 or 5."""
        return {"none": 2, "simple": 0, "smart": 4}[self.mode] + (0 if self.stubs or self.mode == "none" else 1)

    @classmethod
    def from_scantype(cls, mode: int, step_bits: int | None = None) -> Dropout:
        """The record of TrueType's SCANTYPE ``mode`` (3, 6 and 7 are 2's: no control)."""
        if mode not in range(8):
            raise ValueError(f"a SCANTYPE mode is 0..7, not {mode!r}")
        if mode in (0, 1, 4, 5):
            return cls("simple" if mode < 4 else "smart", stubs=mode in (0, 4), step_bits=step_bits)
        return cls("none", step_bits=step_bits)

    def describe(self) -> str:
        """A few words for people."""
        if self.mode == "none":
            said = "no dropout control"
        else:
            stubs = "stubs included" if self.stubs else "stubs excluded"
            said = f"{self.mode} dropout control (SCANTYPE {self.scantype}, {stubs})"
        if self.step_bits is not None:
            said += f", crossings stepped at 1/{2**self.step_bits} px from each edge's start"
        return said

    def to_json(self) -> dict[str, Any]:
        """Its fields as JSON values."""
        return {"mode": self.mode, "stubs": self.stubs, "step_bits": self.step_bits}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Dropout:
        """The record :meth:`to_json` gave."""
        return cls(data.get("mode", "none"), bool(data.get("stubs", True)), data.get("step_bits"))


def dropout_control(spec: Dropout | str | dict[str, Any] | None) -> Dropout:
    """A :class:`Dropout` from itself, its name (``"smart"``, ``"smart-no-stubs"``,
    ``"none-stepped6"``: :attr:`Dropout.name`), its JSON, or None (none).

    >>> dropout_control("smart-no-stubs"), dropout_control(None).active
    (Dropout(mode='smart', stubs=False, step_bits=None), False)
    """
    if spec is None:
        return Dropout()
    if isinstance(spec, Dropout):
        return spec
    if isinstance(spec, dict):
        return Dropout.from_json(spec)
    if isinstance(spec, str):
        match = re.fullmatch(r"(none|simple|smart)(-no-stubs)?(?:-stepped(\d+))?", spec)
        if match is None or (match[1] == "none" and match[2]):
            raise ValueError(f"Convention.dropout must be 'none', 'simple' or 'smart' (then optionally '-no-stubs'), "
                             f"optionally '-stepped6', or a Dropout, not {spec!r}")
        return Dropout(cast(Any, match[1]), stubs=not match[2], step_bits=None if match[3] is None else int(match[3]))
    raise ValueError(f"Convention.dropout must be a Dropout, its name or None, not {spec!r}")


@dataclass(frozen=True, slots=True, repr=False)
class Convention:
    """A fill convention: sample point, tie rule, vertex snapping and culling.

    Parameters
    ----------
    sample : (float, float)
        Offset of the sample point inside each pixel, each in [0, 1] and a multiple of
        2**-32. (0.5, 0.5) is the centre; (1, 1) is the floor scanline's bottom-right corner.
    tie : str
        Which edges own the samples lying exactly on them: one of :data:`TIE_RULES`,
        ``top-left``, ``top-right``, ``bottom-left``, ``bottom-right`` (x first) and the
        same four with ``-y-first``.
    subpixel_bits : int or None
        Snap vertices to multiples of 2**-n, 0 <= n <= 16, or None.
    cull : {"none", "cw", "ccw"}
        Remove triangles running clockwise (A > 0) or counter-clockwise on screen.
    snap_rounding : {"nearest-even", "half-away", "floor", "half-away-shifted"}
        How snapping rounds: to nearest, ties to even (D3D, GL drivers), to nearest, ties
        away from zero (dEQP's reference renderer), down (truncating fixed-point
        conversion, as skia's ``int(x * 64)``), or to nearest with ties away from zero in the
        frame shifted by half a pixel (piglit's reference rasterizer, ``iround(FIXED_ONE *
        (v - 0.5))``: ties above the line c = 1/2 round up, ties at or below it down).
    samples : int, sequence of (x, y) or None
        A multisample pattern (:func:`harness.contract.samples.pattern`): a standard count (1, 2,
        4, 8, 16) or up to :data:`MAX_SAMPLES` dyadic offsets in [0, 1)^2 (up to
        :data:`MAX_AREA_SAMPLES` for supersampled area coverage); stored as the offsets. Each
        sample then follows ``tie``, snapping and culling at its own offset, and ``sample`` is
        not used. None: one sample, at ``sample``.
    coverage : {"sample", "area", "area-threshold", "conservative-over", "conservative-under", "closed"}
        ``area``: anti-aliased coverage, an alpha per pixel equal to the area of the
        triangle inside the pixel (or, with ``samples``, the share of the samples it
        covers), quantised and within ``tolerance`` (``sample`` is not used, nor ``tie``
        without ``samples``). The last three are coverage rules (module docstring):
        aliased, decided on the pixel's square; no ``samples``.
    levels : int
        Area coverage only: alphas are multiples of 1/(levels - 1) (256: 8-bit alpha).
    tolerance : float or None
        Area coverage only: the largest |alpha - exact area| the rasterizer promises at any
        pixel; None means half a level (the exact area rounded to the nearest level).
    line : LineRule or str
        Line scenes only: how lines are drawn (:class:`LineRule`).
    input : str
        The input precision (:class:`InputPrecision`): the coordinates the rasterizer
        receives, applied first, before snapping. ``float64`` (default), ``float32``,
        ``fixedN`` (a 2**-N px grid; ``fixed6`` = 26.6) or ``integer``, a grid with an
        optional ``-half-away``, ``-floor`` or ``-toward-zero`` rounding; kept in its
        canonical spelling.
    threshold : float
        ``area-threshold`` only: the least share of a pixel's area that draws it, in
        [2**-20, 1] (default 1/2; exactly this share draws).
    uncertainty : float
        The conservative rules only: the uncertainty region D3D12 and Vulkan allow, a
        multiple of 2**-16 in [0, 1/2] (1/256 is theirs; default 0: exact). Overestimate:
        a pixel whose square grown by it meets the triangle may be drawn too;
        underestimate: one whose square so grown is not inside may be left out
        (:func:`harness.oracle.coverage_rules.uncertainty_bounds`; conformance, watertight
        and overdraw judge between the two).
    dropout : str, Dropout or None
        ``closed`` only: dropout control and how crossings are computed (:class:`Dropout`),
        kept as its canonical name (``"smart-no-stubs-stepped6"``; a Dropout or None is
        taken too; :attr:`dropout_control` gives the record); default ``"none"``, which
        changes nothing.
    rows : int
        ``area`` only, without ``samples``: row-sampled area coverage (cairo's
        ``cairo-tor-scan-converter.c``, ``GRID_Y 15``): the alpha is the mean of the
        triangle's cross-sections with the pixel on ``rows`` lines ``y = j + (k + 1/2)/rows``,
        exact along x (:mod:`harness.oracle.aa_models`); 0 (default): the analytic area.
    full_rows : bool
        With ``rows``: cairo's hybrid, its integer procedure on its 24.8 input: a pixel
        row no edge starts or ends in gets the area between its edges with their column
        crossings rounded down to 1/rows of the row (cairo's ``full_row``), the others their
        ``rows`` sample lines with x rounded to 1/256 px (:mod:`harness.oracle.aa_models`;
        declare ``input="fixed8"``).
    supersample : int
        ``area`` only, without ``samples`` or ``rows``: skia's supersampler as tiny-skia runs it
        (``src/scan/path_aa.rs``, skia's ``SkScan_AntiPath.cpp``) with ``SUPERSAMPLE_SHIFT =
        supersample`` (1..4; tiny-skia's is 2): the path scaled by 2**shift, its points (f32)
        truncated to a 2**-(shift+6) px grid, 16.16 edges stepped per sub-scanline, spans
        rounded to 1/2**shift px and summed into 8-bit levels as ``SuperBlitter::blit_h`` does
        (:mod:`harness.oracle.supersample_models`; declare ``input="float32"``). The oracle's
        alphas are the library's levels exactly. 0 (default): not this model.
    quantisation : str
        ``area`` only, without ``samples`` or ``rows``: how an analytic library turns the
        exact area into an 8-bit level (:mod:`harness.contract.quantisations`: ``ftgrays``,
        ``cells-abs``, ``cells-abs-gray8``, ``blend2d``), the oracle then giving that level
        (:mod:`harness.oracle.analytic_models`) and ``tolerance`` bounding |alpha - level|;
        ``nearest`` (default): the exact area, within ``tolerance``, as before.

    Examples
    --------
    >>> Convention()
    Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none')
    >>> Convention(sample=(1, 1), tie="bottom-right").describe()
    'sample (1, 1), bottom-right ties, no snapping, no culling'
    >>> Convention(samples=4).describe()
    'D3D11 4x, top-left ties, no snapping, no culling'
    >>> grid = [((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4)]
    >>> Convention(coverage="area", samples=grid, levels=17).describe()  # doctest: +NORMALIZE_WHITESPACE
    'area coverage, 17 levels, within 0.0312 of the share of the samples covered (4x4 grid at (1/8 + k/4)), top-left ties, no
    snapping, no culling'
    >>> Convention(coverage="area", subpixel_bits=8).describe()
    'area coverage, 256 levels, within 0.00196 of the exact area, snapped to 1/256 px (8 bits), no culling'
    >>> Convention(input="float32", subpixel_bits=8).describe()
    'sample (0.5, 0.5), top-left ties, float32 input, snapped to 1/256 px (8 bits), no culling'
    >>> Convention(coverage="area-threshold")
    Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none', coverage='area-threshold', threshold=0.5)
    >>> Convention(coverage="area-threshold", threshold=0.25).describe()
    'an area threshold (a pixel iff at least 0.25 of it is covered), no snapping, no culling'
    >>> Convention(coverage="conservative-over", subpixel_bits=8).describe()
    'conservative overestimate (a pixel iff its square meets the triangle), snapped to 1/256 px (8 bits), no culling'
    >>> Convention(tie="top-middle")  # doctest: +NORMALIZE_WHITESPACE
    Traceback (most recent call last):
    ...
    ValueError: Convention.tie must be one of top-left, top-right, bottom-left, bottom-right, top-left-y-first, top-right-y-first,
    bottom-left-y-first, bottom-right-y-first, not 'top-middle'
    """

    sample: tuple[float, float] = (0.5, 0.5)
    tie: TieRule = "top-left"
    subpixel_bits: int | None = None
    cull: CullMode = "none"
    snap_rounding: SnapRounding = "nearest-even"
    # given as a count or offsets (harness.contract.samples.pattern), kept as a tuple of (x, y) offsets
    samples: Any = None
    coverage: Literal["sample", "area", "area-threshold", "conservative-over", "conservative-under", "agg-cover",
                      "inclusive-scanline", "closed"] = "sample"
    levels: int = 256
    tolerance: float | None = None
    # line scenes only (a LineRule, or its rule's name)
    line: Any = LineRule()
    # the coordinates the rasterizer receives, before snapping (InputPrecision grammar, canonical)
    input: str = "float64"
    # coverage="area-threshold" only: the least covered share that draws a pixel
    threshold: float = 0.5
    # the conservative rules only: the uncertainty region, in pixels (D3D12/Vulkan)
    uncertainty: float = 0.0
    # coverage="closed" only: dropout control and the crossings' arithmetic (Dropout.name, canonical)
    dropout: str = "none"
    # coverage="area" only: sample each pixel row on this many lines, exact along x (0: analytic area)
    rows: int = 0
    # with rows: rows no edge starts or ends in are analytic, on cairo's grid (cairo's full_row)
    full_rows: bool = False
    # coverage="area" only: skia's supersampler with this SUPERSAMPLE_SHIFT (0: not it)
    supersample: int = 0
    # coverage="area" only: how the library maps a pixel's accumulated area to a level
    # (harness.contract.quantisations; "nearest": the area within tolerance, as before)
    quantisation: str = NEAREST

    def __repr__(self) -> str:
        extra = "" if self.snap_rounding == "nearest-even" else f", snap_rounding={self.snap_rounding!r}"
        if self.samples is not None:
            extra += f", samples={self.samples!r}"
        if self.model.rule:
            extra += f", coverage={self.coverage!r}" + (f", threshold={self.threshold!r}" if self.coverage_uses_threshold else "")
            extra += f", uncertainty={self.uncertainty!r}" if self.uncertainty else ""
            extra += f", dropout={self.dropout!r}" if self.dropout != "none" else ""
        elif self.coverage != "sample":
            extra += f", coverage={self.coverage!r}, levels={self.levels!r}, tolerance={self.tolerance!r}"
        if self.rows:
            extra += f", rows={self.rows!r}" + (", full_rows=True" if self.full_rows else "")
        if self.supersample:
            extra += f", supersample={self.supersample!r}"
        if self.quantisation != NEAREST:
            extra += f", quantisation={self.quantisation!r}"
        if self.line != LineRule():
            extra += f", line={self.line!r}"
        if self.input != "float64":
            extra += f", input={self.input!r}"
        return (f"Convention(sample={self.sample!r}, tie={self.tie!r}, subpixel_bits={self.subpixel_bits!r}, "
                f"cull={self.cull!r}{extra})")

    @property
    def model(self) -> CoverageModel:
        """Its coverage model (:mod:`harness.contract.coverage_models`), the one object the engine
        asks about its coverage: chosen from ``coverage`` and ``samples`` alone, by
        :func:`~harness.contract.coverage_models.model_for` (derived, not stored: a convention
        pickles, compares and hashes as its declaration).

        >>> Convention().model, Convention(coverage="area").model
        (CoverageModel('single'), CoverageModel('area'))
        """
        return model_for(self.coverage, self.samples is not None, self.rows, self.supersample, self.quantisation)

    @property
    def coverage_uses_threshold(self) -> bool:
        """Whether ``threshold`` means something here: an ``area-threshold`` convention
        (its model is ``thresholded``)."""
        return self.model.thresholded

    @property
    def coverage_kind(self) -> CoverageKind:
        """``single``, ``multisample`` or ``area`` (see the module docstring): its
        model's kind (:attr:`model`).

        >>> Convention().coverage_kind, Convention(samples=4).coverage_kind, Convention(coverage="area", samples=4).coverage_kind
        ('single', 'multisample', 'area')
        >>> Convention(coverage="area", samples=4).model
        CoverageModel('supersampled area')
        """
        return self.model.coverage_kind

    @property
    def n_samples(self) -> int:
        """Samples per pixel: the pattern's length, else 1."""
        return 1 if self.samples is None else len(self.samples)

    def point_sampled(self, sample: tuple[float, float] | None = None) -> Convention:
        """This convention's single-sample twin: one sample per pixel at ``sample`` (its own
        by default), with the same ties, snapping, input and culling, and none of what an
        area model adds (a pattern, rows, a supersampler's shift, a quantisation, levels):
        what a winding or a sample share is decided by.

        >>> Convention(coverage="area", rows=15, full_rows=True, input="fixed8").point_sampled((0.5, 0.5)).model
        CoverageModel('single')
        """
        return replace(self, coverage="sample", samples=None, sample=self.sample if sample is None else sample,
                       levels=256, tolerance=None, rows=0, full_rows=False, supersample=0, quantisation=NEAREST)

    def at_sample(self, index: int) -> Convention:
        """The single-sample convention that sample ``index`` of the pattern obeys: this
        one with ``sample`` moved to that offset (the same ties, snapping and culling).

        >>> Convention(samples=4).at_sample(1)
        Convention(sample=(0.875, 0.375), tie='top-left', subpixel_bits=None, cull='none')
        """
        if self.samples is None:
            if index != 0:
                raise IndexError(f"a single-sample convention has sample 0 only, not {index}")
            return self
        offsets: tuple[tuple[float, float], ...] = self.samples
        return self.point_sampled(offsets[index])

    @property
    def level_step(self) -> float:
        """Area coverage: the alpha quantum 1/(levels - 1)."""
        return 1.0 / (self.levels - 1)

    @property
    def alpha_tolerance(self) -> float:
        """Area coverage: the promised bound on |alpha - exact area| (half a level when
        none is declared)."""
        return 0.5 * self.level_step if self.tolerance is None else float(self.tolerance)

    @property
    def dropout_control(self) -> Dropout:
        """Its :attr:`dropout`, parsed (:func:`dropout_control`)."""
        return dropout_control(self.dropout)

    @property
    def input_precision(self) -> InputPrecision:
        """Its :attr:`input`, parsed (:func:`input_precision`)."""
        return input_precision(self.input)

    def receive(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """The positions as the rasterizer receives them: its input precision applied
        (:meth:`InputPrecision.apply`), before any snapping; the same array when ``float64``."""
        return input_precision(self.input).apply(positions)

    @property
    def quantizes(self) -> bool:
        """Whether vertices move before coverage is decided: snapping or an input grid."""
        return self.subpixel_bits is not None or self.input != "float64"

    def snap(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """The positions as this convention sees them: received at its input precision
        (:meth:`receive`), then snapped (see :func:`snap`). Every oracle, check and probe
        takes a scene's coordinates through here, so the input precision is applied in this
        one place, first, for every kind of scene."""
        return snap(self.receive(positions), self.subpixel_bits, self.snap_rounding)

    def __post_init__(self) -> None:
        try:
            sx, sy = (float(v) for v in self.sample)
        except (TypeError, ValueError):
            raise ValueError(
                f"Convention.sample must be a pair of numbers, not {self.sample!r}"
            ) from None
        for name, value in (("x", sx), ("y", sy)):
            if not (0.0 <= value <= 1.0) or not math.isfinite(value):
                raise ValueError(f"Convention.sample {name} must lie in [0, 1], not {value!r}")
            if (value * 2.0**SAMPLE_FRACTION_BITS) % 1.0 != 0.0:
                raise ValueError(
                    f"Convention.sample {name} must be a multiple of 2**-{SAMPLE_FRACTION_BITS}, "
                    f"not {value!r}"
                )
        object.__setattr__(self, "sample", (sx, sy))
        if self.tie not in TIE_RULES:
            raise ValueError(
                f"Convention.tie must be one of {', '.join(TIE_RULES)}, not {self.tie!r}"
            )
        bits = self.subpixel_bits
        if bits is not None and (
            isinstance(bits, bool)
            or not isinstance(bits, (int, np.integer))
            or not 0 <= bits <= MAX_SUBPIXEL_BITS
        ):
            raise ValueError(
                f"Convention.subpixel_bits must be None or an integer in 0..{MAX_SUBPIXEL_BITS}, "
                f"not {bits!r}"
            )
        if bits is not None:
            object.__setattr__(self, "subpixel_bits", int(bits))
        if self.snap_rounding not in SNAP_ROUNDINGS:
            raise ValueError(
                f"Convention.snap_rounding must be one of {', '.join(SNAP_ROUNDINGS)}, not {self.snap_rounding!r}"
            )
        if self.cull not in CULL_MODES:
            raise ValueError(
                f"Convention.cull must be one of {', '.join(CULL_MODES)}, not {self.cull!r}"
            )
        if self.samples is not None:
            from harness.contract.samples import pattern

            offsets = pattern(self.samples)
            patterned = model_for(self.coverage, True)
            if patterned.rule:
                raise ValueError(f"Convention.coverage {self.coverage!r} is a coverage rule of one answer per pixel: it "
                                 "takes no samples (leave samples=None)")
            limit = patterned.max_samples
            if len(offsets) > limit:
                raise ValueError(f"Convention.samples has {len(offsets)} samples; at most {limit} are supported"
                                 + ("" if patterned.alphas else f" ({MAX_AREA_SAMPLES} for supersampled area coverage)"))
            object.__setattr__(self, "samples", offsets)
        line = LineRule(cast(LineRuleName, self.line)) if isinstance(self.line, str) else self.line
        if not isinstance(line, LineRule):
            raise ValueError(f"Convention.line must be a LineRule or one of {', '.join(LINE_RULES)}, not {self.line!r}")
        object.__setattr__(self, "line", line)
        if not isinstance(self.input, (str, InputPrecision)):
            raise ValueError(f"Convention.input must be a string such as 'float32' or 'fixed6-floor', not {self.input!r}")
        object.__setattr__(self, "input", input_precision(self.input).name)
        if self.coverage not in DECLARED_COVERAGES:
            raise ValueError(f"Convention.coverage must be one of {', '.join(DECLARED_COVERAGES)}, not {self.coverage!r}")
        self._check_rule_fields()
        self._check_rows()
        self._check_supersample()
        self._check_quantisation()
        levels = self.levels
        if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or not 2 <= levels <= 2**24:
            raise ValueError(f"Convention.levels must be an integer in 2..2**24, not {levels!r}")
        object.__setattr__(self, "levels", int(levels))
        if self.tolerance is not None:
            try:
                tol = float(self.tolerance)
            except (TypeError, ValueError):
                raise ValueError(f"Convention.tolerance must be a number or None, not {self.tolerance!r}") from None
            if not 0.0 <= tol <= 1.0:
                raise ValueError(f"Convention.tolerance must lie in [0, 1], not {self.tolerance!r}")
            object.__setattr__(self, "tolerance", tol)

    def _check_rows(self) -> None:
        """Validate and normalise ``rows`` and ``full_rows`` (row-sampled area coverage)."""
        rows = self.rows
        if isinstance(rows, bool) or not isinstance(rows, (int, np.integer)) or not 0 <= rows <= 256:
            raise ValueError(f"Convention.rows must be an integer in 0..256, not {rows!r}")
        object.__setattr__(self, "rows", int(rows))
        if rows and (self.coverage != "area" or self.samples is not None):
            raise ValueError("Convention.rows is for area coverage without samples (coverage='area')")
        if self.full_rows and not rows:
            raise ValueError("Convention.full_rows needs rows > 0")
        object.__setattr__(self, "full_rows", bool(self.full_rows))

    def _check_supersample(self) -> None:
        """Validate and normalise ``supersample`` (skia's supersampler: its shift)."""
        shift = self.supersample
        if isinstance(shift, bool) or not isinstance(shift, (int, np.integer)) or not 0 <= shift <= 4:
            raise ValueError(f"Convention.supersample must be an integer in 0..4, not {shift!r}")
        object.__setattr__(self, "supersample", int(shift))
        if shift and model_for(self.coverage, self.samples is not None, self.rows, shift, self.quantisation) \
                is not SKIA_SUPERSAMPLED_AREA:
            raise ValueError("Convention.supersample is for area coverage without samples or rows (coverage='area')")
    def _check_quantisation(self) -> None:
        """Validate ``quantisation`` (an analytic library's levels: area coverage, no samples, no rows)."""
        if self.quantisation not in QUANTISATION_NAMES:
            raise ValueError(f"Convention.quantisation must be one of {', '.join(QUANTISATION_NAMES)}, not {self.quantisation!r}")
        if self.quantisation != NEAREST and self.model is not QUANTISED_AREA:  # area, no samples, no rows
            raise ValueError("Convention.quantisation is for analytic area coverage (coverage='area', no samples, no rows)")
        if self.quantisation != NEAREST and self.levels != 256:
            raise ValueError(f"Convention.quantisation {self.quantisation!r} makes 8-bit levels: levels=256, not {self.levels!r}")

    def _check_rule_fields(self) -> None:
        """Validate and normalise ``threshold`` and ``uncertainty`` (the coverage rules')."""
        threshold = self.threshold
        if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.integer, np.floating)) \
                or not 2.0**-20 <= float(threshold) <= 1.0:
            raise ValueError(f"Convention.threshold must be a number in [2**-20, 1], not {threshold!r}")
        object.__setattr__(self, "threshold", float(threshold))
        uncertainty = self.uncertainty
        if isinstance(uncertainty, bool) or not isinstance(uncertainty, (int, float, np.integer, np.floating)) \
                or not 0.0 <= float(uncertainty) <= 0.5 or (float(uncertainty) * 2.0**16) % 1.0 != 0.0:
            raise ValueError(f"Convention.uncertainty must be a multiple of 2**-16 in [0, 1/2], not {uncertainty!r}")
        if uncertainty and not self.model.uncertain:
            raise ValueError(f"Convention.uncertainty is a conservative rule's (coverage='conservative-over' or "
                             f"'conservative-under'), not {self.coverage!r}'s")
        object.__setattr__(self, "uncertainty", float(uncertainty))
        grid = self.model.input_bits
        if grid is not None:  # a rule defined on its library's integer grid (agg-cover, inclusive-scanline)
            received = input_precision(self.input)
            if not (received.kind == "integer" or (received.kind == "fixed" and received.bits <= grid)) \
                    or self.subpixel_bits is not None:
                raise ValueError(f"Convention.coverage {self.coverage!r} is defined on a grid of 2**-{grid} px: declare "
                                 f"input='{'integer' if grid == 0 else f'fixed{grid}'}-<rounding>' (and no subpixel_bits), "
                                 f"not input={self.input!r}")
        dropout = dropout_control(self.dropout)
        if dropout.active and self.coverage != "closed":
            raise ValueError(f"Convention.dropout is the closed rule's (coverage='closed'), not {self.coverage!r}'s")
        if dropout.step_bits is not None:
            steps_on = input_precision(self.input)
            if steps_on.kind != "fixed" or steps_on.bits > dropout.step_bits or self.subpixel_bits is not None:
                raise ValueError(f"Dropout.step_bits={dropout.step_bits} steps crossings on a 2**-{dropout.step_bits} px "
                                 f"grid: the input must lie on it (input='fixed{dropout.step_bits}' or coarser), "
                                 "without snapping")
        object.__setattr__(self, "dropout", dropout.name)

    @property
    def tie_perturbation(self) -> tuple[int, int, bool]:
        """(sx, sy, y_first): a sample on an edge is decided as if moved by
        (sx*eps, sy*eps**2), or (sx*eps**2, sy*eps) when y_first."""
        return TIE_PERTURBATION[self.tie]

    def describe_lines(self) -> str:
        """One line for people on how this convention draws lines: the line rule, with the
        sample point and ties for rectangular lines, and snapping.

        >>> Convention(subpixel_bits=8).describe_lines()
        'diamond-exit lines, last pixel omitted, snapped to 1/256 px (8 bits)'
        >>> Convention(line="rectangle").describe_lines()
        'rectangular lines, sample (0.5, 0.5), top-left ties, no snapping'
        >>> Convention(samples=4, line="rectangle").describe_lines()
        'rectangular lines, at D3D11 4x, top-left ties, no snapping'
        """
        parts = [self.for_lines().line.describe()]  # the rule's own rounding is said by the snapping
        if self.line.rule in AREA_LINE_RULES and self.samples is not None:
            parts.append(f"at {self._pattern_words()}, {self._tie_words()}")
        elif self.line.rule in AREA_LINE_RULES:
            sx, sy = (f"{v:g}" for v in self.sample)
            parts.append(f"sample ({sx}, {sy}), {self._tie_words()}")
        parts.append(self.for_lines()._snapping_words())
        return ", ".join(parts)

    def for_lines(self) -> Convention:
        """This convention as line end points see it: the line rule's own ``snap_rounding``
        in place of the convention's, when it has one (the same convention otherwise).

        >>> c = Convention(subpixel_bits=8, line=LineRule("parallelogram", snap_rounding="half-away"))
        >>> c.for_lines().snap_rounding, c.for_lines().line.snap_rounding, c.snap_rounding
        ('half-away', None, 'nearest-even')
        >>> c.describe_lines()  # doctest: +NORMALIZE_WHITESPACE
        'parallelogram lines (Vulkan non-strict), sample (0.5, 0.5), top-left ties, snapped to 1/256 px
         (8 bits, half away from zero)'
        """
        own = self.line.snap_rounding
        if own is None:
            return self
        return replace(self, snap_rounding=own, line=replace(self.line, snap_rounding=None))

    def _pattern_words(self) -> str:
        """The sample pattern for people, in a few words (``D3D11 4x``, ``4x4 grid at (1/8 +
        k/4)``: :func:`harness.contract.samples.describe_pattern`), never the offsets one by one (the
        JSON keeps them)."""
        from harness.contract.samples import describe_pattern

        return describe_pattern(self.samples)

    def _tie_words(self) -> str:
        return self.tie.removesuffix("-y-first") + " ties" + (" (y first)" if self.tie.endswith("-y-first") else "")

    def _snapping_words(self) -> str:
        received = "" if self.input == "float64" else input_precision(self.input).describe() + ", "
        if self.subpixel_bits is None:
            return received + "no snapping"
        return received + (f"snapped to 1/{2**self.subpixel_bits} px ({self.subpixel_bits} bits"
                + {"nearest-even": ")", "half-away": ", half away from zero)", "floor": ", rounding down)",
                   "half-away-shifted": ", half away in the frame shifted by half a pixel)"}[self.snap_rounding])

    def describe(self) -> str:
        """One line for people: sample point, ties, snapping, culling; a sample pattern in a
        few words (:func:`harness.contract.samples.describe_pattern`)."""
        sx, sy = (f"{v:g}" for v in self.sample)
        snapping = self._snapping_words()
        culling = "no culling" if self.cull == "none" else f"culls {self.cull}"
        tie = self._tie_words()
        where = self._pattern_words() if self.samples is not None else ""
        if self.model.rule:
            region = f", uncertainty {self.uncertainty:g} px" if self.uncertainty else ""
            return f"{self.model.declared_as(self)}{region}, {snapping}, {culling}"
        if self.model.alphas:
            what = "the exact area" if self.samples is None else f"the share of the samples covered ({where}), {tie}"
            if self.rows:
                what = f"the mean of {self.rows} cross-sections per pixel row" + (
                    ", analytic rows as cairo's full_row" if self.full_rows else "")
            if self.supersample:
                what = f"skia's supersampler ({1 << self.supersample} sub-scanlines, x in 1/{1 << self.supersample} px)"
            if self.quantisation != NEAREST:
                what = f"the exact area's {self.quantisation} level"
            return f"area coverage, {self.levels} levels, within {self.alpha_tolerance:.3g} of {what}, {snapping}, {culling}"
        if self.samples is not None:
            return f"{where}, {tie}, {snapping}, {culling}"
        return f"sample ({sx}, {sy}), {tie}, {snapping}, {culling}"


    def facets(self) -> dict[str, str]:
        """The convention in the columns of the report's conventions table, each in words:
        what decides a pixel (``coverage``: one sample, a pattern, area, or a coverage
        rule by its name), ``sample`` (the sample point and tie rule, where samples decide),
        ``input`` (the precision received, :class:`InputPrecision`), ``snapping``,
        ``culling`` and ``lines`` (the line rule, :meth:`LineRule.describe`).

        >>> Convention(coverage="area-threshold", input="fixed6").facets()["coverage"]
        'an area threshold (a pixel iff at least 0.5 of it is covered)'
        >>> Convention(input="float32", subpixel_bits=8).facets()["input"], Convention().facets()["sample"]
        ('float32 input', '(0.5, 0.5), top-left ties')
        """
        sx, sy = (f"{v:g}" for v in self.sample)
        if self.model.rule:
            coverage = self.model.declared_as(self) + (f", uncertainty {self.uncertainty:g} px" if self.uncertainty else "")
        elif self.model.alphas:
            coverage = f"area, {self.levels} levels, within {self.alpha_tolerance:.3g}" + (
                "" if self.samples is None else f" of the share of {self._pattern_words()}") + (
                f" of skia's supersampler ({1 << self.supersample} sub-scanlines)" if self.supersample else "") + (
                "" if self.quantisation == NEAREST else f" of the {self.quantisation} level")
        elif self.samples is not None:
            coverage = self._pattern_words()
        else:
            coverage = "one sample per pixel"
        if not self.model.sample_point:
            sample = "(none: the rule decides)"
        elif self.model.rule:  # closed: at the sample point, but no tie rule
            sample = f"({sx}, {sy}), no ties: a sample on an edge is inside"
        elif self.samples is not None:
            sample = self._tie_words()
        elif self.model.alphas:
            sample = "(area: no sample)"
        else:
            sample = f"({sx}, {sy}), {self._tie_words()}"
        snapping = ("none" if self.subpixel_bits is None else
                    f"1/{2**self.subpixel_bits} px" + {"nearest-even": "", "half-away": ", half away from zero",
                                                      "floor": ", rounding down"}[self.snap_rounding])
        return {"coverage": coverage, "sample": sample, "input": input_precision(self.input).describe(),
                "snapping": snapping, "culling": "none" if self.cull == "none" else self.cull,
                "lines": self.line.describe()}


def snap(positions: NDArray[np.float64], subpixel_bits: int | None, rounding: str = "nearest-even") -> NDArray[np.float64]:
    """Snap coordinates to multiples of ``2**-subpixel_bits``, rounding to nearest with
    ties to even (``"nearest-even"``), to nearest with ties away from zero
    (``"half-away"``), or down (``"floor"``); or (``"half-away-shifted"``, piglit) to
    ``(iround(2**n * (c - 1/2)) + 2**(n-1)) / 2**n`` with ``iround`` half away from zero:
    the same grid for n >= 1 (the pixel centres for n = 0), ties going away from the line
    c = 1/2 instead of from 0.

    Exact for every float64: scaling by a power of two is exact, ``np.rint`` rounds half
    to even, ``np.floor`` and ``np.trunc`` are exact, so is a float's fractional part
    ``v - trunc(v)``, and values of magnitude 2**52 or more (already integers) are left
    alone. Non-finite values pass through unchanged.

    Parameters
    ----------
    positions : (..., 2) float64
    subpixel_bits : int or None
    rounding : {"nearest-even", "half-away", "floor", "half-away-shifted"}

    Returns
    -------
    (..., 2) float64

    Examples
    --------
    >>> snap(np.array([0.125, 0.375, 1.0 / 3.0, -0.375]), 2)
    array([ 0.  ,  0.5 ,  0.25, -0.5 ])
    >>> snap(np.array([0.125, 0.375, -0.125, -0.375]), 2, "half-away")
    array([ 0.25,  0.5 , -0.25, -0.5 ])
    >>> snap(np.array([0.125, 0.375, -0.125, -0.375]), 2, "floor")
    array([ 0.  ,  0.25, -0.25, -0.5 ])
    >>> snap(np.array([0.125, 0.375, 0.625, -0.125]), 2, "half-away-shifted")
    array([ 0.  ,  0.25,  0.75, -0.25])
    """
    positions = np.asarray(positions, dtype=np.float64)
    if subpixel_bits is None:
        return positions
    if rounding not in SNAP_ROUNDINGS:
        raise ValueError(f"snap rounding must be one of {', '.join(SNAP_ROUNDINGS)}, not {rounding!r}")
    scale = 2.0**subpixel_bits
    with np.errstate(invalid="ignore"):
        small = np.abs(positions) < _SNAP_IDENTITY_ABOVE
    snapped = positions.copy()
    scaled = positions[small] * scale
    if rounding == "floor":
        rounded = np.floor(scaled)
    elif rounding == "half-away-shifted":
        rounded = _half_away_shifted(scaled, subpixel_bits)
    elif rounding == "half-away":
        # (int64)(v + 0.5) for v >= 0 and (int64)(v - 0.5) below, without the float sum's
        # rounding: truncate, then step away from zero when the dropped part is >= 1/2.
        whole = np.trunc(scaled)
        rounded = whole + np.sign(scaled) * (np.abs(scaled - whole) >= 0.5)
    else:
        rounded = np.rint(scaled)
    snapped[small] = rounded / scale
    return snapped


def _half_away_shifted(scaled: NDArray[np.float64], bits: int) -> NDArray[np.float64]:
    """``iround(s - h) + h`` for ``s = c * 2**bits`` and ``h = 2**(bits-1)``, exactly (``s - h``
    itself may round in float64): above h, ``s - h`` is positive and rounds half up, i.e.
    ``floor(s) + [frac(s) >= 1/2]`` (h is an integer); at or below h it rounds half down,
    ``ceil(s) - [ceil(s) - s >= 1/2]``. With 0 bits h = 1/2 and the result a pixel centre:
    ``floor(s) + 1/2`` above h, ``ceil(s) - 1/2`` at or below (``iround(c - 1/2) + 1/2``)."""
    half = 2.0 ** (bits - 1)
    floor, ceil = np.floor(scaled), np.ceil(scaled)
    if bits == 0:
        return np.where(scaled > half, floor + 0.5, ceil - 0.5)
    up = floor + (scaled - floor >= 0.5)
    down = ceil - (ceil - scaled >= 0.5)
    rounded: NDArray[np.float64] = np.where(scaled > half, up, down)
    return rounded


@numba.njit(cache=True, inline="always")
def owns_edge(ax, ay, bx, by, tie_x, tie_y, y_first):  # type: ignore[no-untyped-def]
    """Whether the edge a -> b of a triangle oriented with its interior where
    ``E_ab > 0`` owns the samples lying exactly on it, under the tie rule with
    perturbation ``(tie_x, tie_y, y_first)`` (:data:`TIE_PERTURBATION`).

    dE/dx = -(by - ay) and dE/dy = bx - ax; the sign of the first nonzero term of
    E(p + d) decides. Comparisons, not differences: nothing overflows.
    """
    if y_first and ax != bx:
        return (bx > ax) == (tie_y > 0)  # sign(dE/dy * sy)
    if not y_first and ay == by:
        return (bx > ax) == (tie_y > 0)  # horizontal: dE/dx = 0, sign(dE/dy * sy)
    return (by < ay) == (tie_x > 0)  # sign(dE/dx * sx)


@dataclass(frozen=True, slots=True)
class InputPrecision:
    """The coordinates a rasterizer receives, before its own snapping: a convention's
    ``input`` (:attr:`Convention.input`), applied first and exactly.

    ``float64``: as given. ``float32``: each coordinate rounded to the nearest float32, ties
    to even (IEEE 754's conversion, as every GPU API receives vertices; beyond float32's
    range it becomes infinite, as a float32 would). ``fixed`` with ``bits`` = N: to
    multiples of 2**-N px by ``rounding`` (26.6 is N = 6). ``integer``: to whole pixels by
    ``rounding`` (N = 0). Written as the strings ``float64``, ``float32``, ``fixedN`` and
    ``integer``, the grids with ``-half-away``, ``-floor`` or ``-toward-zero`` appended for
    those roundings (none: ``nearest-even``), which is its :attr:`name`.

    Examples
    --------
    >>> input_precision("fixed6-floor")
    InputPrecision(kind='fixed', bits=6, rounding='floor')
    >>> input_precision("integer-toward-zero").apply(np.array([-1.75, -0.5, 0.5, 2.99]))
    array([-1., -0.,  0.,  2.])
    >>> float(input_precision("float32").apply(np.array([0.1]))[0]) == float(np.float32(0.1))
    True
    >>> input_precision("fixed6").describe(), input_precision("integer-floor").describe()
    ('26.6 fixed-point input (1/64 px, nearest-even)', 'integer input (whole pixels, floor)')
    """

    kind: Literal["float64", "float32", "fixed", "integer"] = "float64"
    bits: int = 0
    rounding: InputRounding = "nearest-even"

    def __post_init__(self) -> None:
        if self.kind not in ("float64", "float32", "fixed", "integer"):
            raise ValueError(f"InputPrecision.kind must be float64, float32, fixed or integer, not {self.kind!r}")
        if self.rounding not in INPUT_ROUNDINGS:
            raise ValueError(f"InputPrecision.rounding must be one of {', '.join(INPUT_ROUNDINGS)}, not {self.rounding!r}")
        bits = self.bits
        if isinstance(bits, bool) or not isinstance(bits, (int, np.integer)) or not 0 <= bits <= MAX_SUBPIXEL_BITS:
            raise ValueError(f"InputPrecision.bits must be an integer in 0..{MAX_SUBPIXEL_BITS}, not {bits!r}")
        object.__setattr__(self, "bits", int(bits))
        if self.kind == "fixed" and self.bits == 0:
            object.__setattr__(self, "kind", "integer")
        if self.kind != "fixed":
            object.__setattr__(self, "bits", 0)
        if self.kind in ("float64", "float32") and self.rounding != "nearest-even":
            raise ValueError(f"{self.kind} input rounds to nearest, ties to even, not {self.rounding!r}")

    @property
    def name(self) -> str:
        """Its string (:func:`input_precision` parses it back)."""
        base = f"fixed{self.bits}" if self.kind == "fixed" else self.kind
        return base if self.rounding == "nearest-even" else f"{base}-{self.rounding}"

    def describe(self) -> str:
        """A few words for people: ``float32 input``, ``26.6 fixed-point input (1/64 px, floor)``."""
        if self.kind in ("float64", "float32"):
            return f"{self.kind} input"
        if self.kind == "integer":
            return f"integer input (whole pixels, {self.rounding})"
        return f"{32 - self.bits}.{self.bits} fixed-point input (1/{2**self.bits} px, {self.rounding})"

    def apply(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """The coordinates as received, exactly: float32's round-to-nearest-even is the
        hardware conversion (correctly rounded, subnormals included); a grid is a power-of-two
        scale (exact), an exact rounding to an integer and the scale back. Non-finite values
        pass through (float32: a finite value past its range becomes infinite)."""
        positions = np.asarray(positions, dtype=np.float64)
        if self.kind == "float64":
            return positions
        if self.kind == "float32":
            with np.errstate(over="ignore"):
                received: NDArray[np.float64] = positions.astype(np.float32).astype(np.float64)
            return received
        if self.rounding != "toward-zero":
            return snap(positions, self.bits, self.rounding)
        scale = 2.0**self.bits
        with np.errstate(invalid="ignore"):
            small = np.abs(positions) < _SNAP_IDENTITY_ABOVE
        out = positions.copy()
        out[small] = np.trunc(positions[small] * scale) / scale
        return out


_INPUT_GRAMMAR = re.compile(r"^(float64|float32|integer|fixed(\d{1,2}))(?:-(nearest-even|half-away|floor|toward-zero))?$")


@functools.lru_cache(maxsize=256)
def _parse_input(spec: str) -> InputPrecision:
    match = _INPUT_GRAMMAR.match(spec)
    if match is None:
        raise ValueError(f"Convention.input must be float64, float32, fixedN (N in 1..{MAX_SUBPIXEL_BITS}) or integer, "
                         f"a grid optionally followed by -nearest-even, -half-away, -floor or -toward-zero; not {spec!r}")
    head, bits, rounding = match.groups()
    kind = "fixed" if bits is not None else head
    if kind == "fixed" and not 1 <= int(bits) <= MAX_SUBPIXEL_BITS:
        raise ValueError(f"Convention.input fixedN needs N in 1..{MAX_SUBPIXEL_BITS} (integer for N = 0), not {spec!r}")
    return InputPrecision(cast(Any, kind), int(bits or 0), cast(Any, rounding or "nearest-even"))


def input_precision(spec: str | InputPrecision) -> InputPrecision:
    """An input precision from its string (``float32``, ``fixed6-floor``, ``integer-toward-zero``:
    :class:`InputPrecision`), or itself.

    >>> input_precision("fixed6-nearest-even").name, input_precision("integer-half-away").name
    ('fixed6', 'integer-half-away')
    """
    if isinstance(spec, InputPrecision):
        return spec
    if not isinstance(spec, str):
        raise ValueError(f"an input precision is a string such as 'float32' or 'fixed6', not {spec!r}")
    return _parse_input(spec)
