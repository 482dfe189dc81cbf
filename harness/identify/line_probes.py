"""identify's probes for line-taking rasterizers: which line rule it draws, and how.

A rasterizer that lists ``"lines"`` in its ``scene_kinds`` (:func:`harness.contract.protocol.scene_kinds_of`)
draws the segments of a :class:`~harness.contract.scenes.LineScene`. :func:`fit_lines` asks it, from
outside, the questions whose answers make up a :class:`~harness.contract.conventions.LineRule` and
the snapping in front of it, each by the exact oracle of every candidate convention
(:func:`harness.oracle.coverage.exact_coverage`) scored against what it drew -- missing plus extra
pixels, as for triangles -- the best explaining it, "identified" only when its residual is
zero and no other candidate's is:

1. *The rule* (D3D's or GL's diamond-exit, Bresenham, rectangle, Vulkan's non-strict
   parallelogram, or skia's hairlines or Qt's cosmetic lines read from their sources), with diamond-exit's and
   Bresenham's last-pixel rule, Bresenham's end point rounding (nearest-even, half-away,
   floor, toward-zero), tie direction (step, stay) and direction of travel (as given, or
   from the end point with smaller x or smaller major coordinate, as textbooks'
   ``plotLine``), and the rectangle's sample point and tie rule (the 9 usual sample points,
   and the one measured by sweeping a segment's end across a pixel,
   :func:`line_sample_sweep`, at a few dyadic precisions, as for triangles, x the 8 tie
   rules): :data:`LINE_RULES_TRIED` x those, scored
   on scenes whose end points are multiples of 1/4 px (no candidate snapping of 2 bits or
   more moves them) -- :func:`crafted_lines`, where the candidates part on purpose, and
   random lattice segments and polylines (:func:`lattice_lines`):

   * end points at pixel centres (x.5), corners (integers), diamond corners and diamond
     edges (x.25), the 20 directions of slopes 0, 1/5, 1/2, 1, 2 and infinite from each:
     Bresenham's tie (the ideal line halfway between two pixel centres) comes at every
     other step of slope 1/2, diamond-exit's corner rules on lines through diamond
     corners (a horizontal line on y = j runs through every bottom corner);
   * every segment both ways round: a drawer that walks as given breaks a tie towards the
     end it walks to and omits that end's pixel, so its two drawings differ, and a drawer
     that normalises the direction draws both alike; slope -2 segments (y-major, the
     smaller x at the larger y) part walking from the smaller x from walking from the
     smaller y;
   * segments entirely inside one pixel: in its corner (no diamond met, so diamond-exit
     draws nothing where Bresenham draws the pixel), across its diamond, inside it; and
     zero-length ones (the last-pixel rules part there);
   * end points on x = 0 or y = 0 and at negative integers: Bresenham's ``half-away``
     puts an integer coordinate p <= 0 in pixel p - 1 where ``floor`` keeps p (for p >= 1
     they agree, and ``nearest-even`` differs from both at every odd p).

2. *Snapping*: with that rule, the sub-pixel bits (none, or 2 to 16) and snap rounding
   that best explain :func:`nudged_lines` -- the same kind of end points, each coordinate
   moved by +-2**-k (k = 2 .. 20), so that a snap to 2**-b px pulls it back onto the
   decision boundary it sits next to exactly when k > b + 1 (k = b + 1 is a half step,
   where the roundings part) -- and one scene of unconstrained floats; then, with every
   coordinate a half step of the fitted grid off the lattice (:func:`half_step_lines`),
   the rounding again. Ties go to the triangles' snapping, then to none. A snapping that
   changes no pixel of any input (floor snapping in front of Bresenham's floor rounding)
   is not seen, and need not be: the two conventions draw alike. Lines that snap on the
   triangles' grid but round otherwise (lavapipe: half away, its triangles to even) get
   the rounding in their rule (``LineRule(snap_rounding=...)``), so that the triangle
   convention with that rule draws them.

   For rectangles, the measured sample point was swept with a snapped end, so it lies up to
   a grid step off: the grid points either side of it, on the grid found and its
   neighbours (:func:`harness.identify.triangle_probes.grid_sides`), join the candidates, and the snapping is
   fitted again with each of them.

3. The rule is then ranked again with the fitted snapping on every scene drawn (and, for
   rectangles at a sample point off the 9 usual ones, on :func:`rectangle_tie_lines`,
   whose sides and caps run through samples there, as for triangles' tie scenes): the
   runner-up (the best candidate differing in rule, last pixel, rounding, ties, direction, or for
   rectangles sample point or tie rule) and each rule's best score on the lattice scenes
   are the evidence. Steps 1 to 3 fit the general rules (diamond-exit, Bresenham,
   rectangle, parallelogram).

4. *A library's own rule*: the rules read from one library's source
   (:data:`~harness.contract.conventions.LIBRARY_LINE_RULES`: skia's hairlines, Qt's cosmetic
   lines, llvmpipe's rectangles), each with its snapping fitted as in step 2 (llvmpipe's
   rectangles snap by their own rule), replace that fit where one leaves at most
   1/:data:`LIBRARY_MARGIN` of its residual -- the general fit then being the runner-up. A
   library's rule explains that library; where it only scores a little better on another's
   lines (cairo's rectangles, say) it is no better a guess, and the general fit stands.

5. *Wide lines* (:func:`wide_lines`): lattice segments of width 3, against the fitted
   rectangular lines (for a width-1 rule, the best rectangle of step 1, and the rule
   itself at width 1: a drawer that ignores the width; for a diamond rule, the rule
   replicated along the minor axis as GL's wide lines: a drawer doing that exactly is
   identified with ``LineRule(wide="replicate")``). Otherwise the width-1 rules have no
   other width: refusing is right for them.

Only segments as the oracle defines them are judged: a rasterizer whose answers carry
alphas or sample indices is not fitted (the line rules are aliased, single-sample).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks import FragmentCounter
from harness.contract.conventions import (
    AREA_LINE_RULES,
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    DIAMOND_RULES,
    FIXED_POINT_LINE_RULES,
    LIBRARY_LINE_RULES,
    LINE_DIRECTIONS,
    LINE_RULES,
    MAX_SUBPIXEL_BITS,
    PLAIN_SNAP_ROUNDINGS,
    TIE_RULES,
    Convention,
    LineRule,
    SnapRounding,
)
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.engine.isolation import Call, Outcome, describe
from harness.identify.line_probe_scenes import (
    PROBE_SIZE,
    crafted_lines,
    float_lines,
    half_step_lines,
    lattice_lines,
    nudged_lines,
    rectangle_tie_lines,
)
from harness.identify.triangle_probes import SAMPLES, SNAP_BITS, _fraction_bits, _sample_candidates, grid_sides
from harness.oracle.coverage import exact_coverage

__all__ = ["LINE_RULES_TRIED", "PROBE_SIZE", "WIDE", "LineDrawn", "LineRounding", "WideLines", "LineFit", "LineSampleSweep",
           "line_sample_sweep", "rectangle_tie_lines",
           "line_rules_tried", "line_candidates", "crafted_lines", "lattice_lines", "nudged_lines", "float_lines",
           "half_step_lines", "wide_lines", "fit_lines"]


# The width of the wide-line probe.
WIDE = 3.0
# A rule read from one library's source is the fit only where its residual is at most this
# fraction of the general rules' best (1/10): it explains its library's lines, and is not
# a better-scoring stand-in for another library's (fit_lines, step 4)
LIBRARY_MARGIN = 10


def line_rules_tried() -> tuple[LineRule, ...]:
    """The line rules :func:`fit_lines` tries, rectangles aside: diamond-exit (D3D's test
    areas and GL's perturbed end points) with the last pixel omitted or drawn, and
    Bresenham with each rounding, tie direction, last-pixel rule and direction of travel
    (as given, or normalised as textbook plotLine does: from the smaller x, from the
    smaller major coordinate), the rule's own setting first.

    >>> len(line_rules_tried()), line_rules_tried()[0].describe()
    (52, 'diamond-exit lines, last pixel omitted')
    """
    rules = [LineRule(rule, last_pixel=last) for rule in DIAMOND_RULES for last in (False, True)]
    rules += [LineRule("bresenham", last_pixel=last, rounding=rounding, ties=ties, direction=direction)
              for direction in LINE_DIRECTIONS for rounding in BRESENHAM_ROUNDINGS for ties in BRESENHAM_TIES
              for last in (True, False)]
    return tuple(rules)


LINE_RULES_TRIED = line_rules_tried()


def line_candidates(base: Convention | None = None, measured: tuple[float, float] | None = None) -> list[Convention]:
    """Every candidate line convention, unsnapped: ``base`` (the triangle convention when
    there is one and it is single-sample; else the default) with each of
    :data:`LINE_RULES_TRIED`, then with rectangles at the 9 usual sample points, and the
    ``measured`` one (:func:`line_sample_sweep`) at a few dyadic precisions
    (:func:`harness.identify.triangle_probes._sample_candidates`, as for triangles), x the 8 tie
    rules, ``base``'s own first (a tie in the score goes to the earlier candidate); then
    parallelograms (Vulkan's non-strict lines) at ``base``'s sample point, the centre and
    the measured one, x the 8 tie rules; last, skia's hairlines and Qt's cosmetic lines
    (:data:`~harness.contract.conventions.FIXED_POINT_LINE_RULES`), and llvmpipe's
    rectangular lines at ``base``'s sample point and the centre, x the 8 tie rules. The
    rest of ``base`` (culling) plays no part in lines; keeping it makes a line convention
    that agrees with the triangles equal to the triangle convention with its line rule.

    >>> candidates = line_candidates()
    >>> len(candidates), candidates[0].line.rule, candidates[52].line.rule, candidates[52].sample
    (142, 'diamond-exit', 'rectangle', (0.5, 0.5))
    >>> candidates[124].line.rule, candidates[124].sample, candidates[124].tie
    ('parallelogram', (0.5, 0.5), 'top-left')
    >>> measured = line_candidates(measured=(0.25, 0.75))
    >>> len(measured), [c for c in measured if c.line.rule == "rectangle"][-1].sample
    (158, (0.25, 0.75))
    >>> [c.line.rule for c in candidates[-11:-8]], {c.tie for c in candidates[-8:]} == set(TIE_RULES)
    (['parallelogram', 'skia-hairline', 'qt-cosmetic'], True)
    """
    single = base if base is not None and base.model.single_sample else Convention()
    unsnapped = replace(single, subpixel_bits=None, snap_rounding="nearest-even")
    out = [replace(unsnapped, line=rule) for rule in LINE_RULES_TRIED]
    first = (single.sample, single.tie)
    pairs = [first] + [(s, t) for s in _sample_candidates(measured) for t in TIE_RULES if (s, t) != first]
    out += [replace(unsnapped, sample=s, tie=t, line=LineRule("rectangle")) for s, t in pairs]
    # Vulkan's non-strict lines: at the triangles' sample point, the centre and the measured
    # one, x the 8 tie rules (their sides decide like triangle edges)
    spots = {single.sample, (0.5, 0.5)} | ({measured} if measured is not None else set())
    out += [replace(unsnapped, sample=s, tie=t, line=LineRule("parallelogram")) for s, t in pairs if s in spots]
    # libraries' fixed-point one-pixel lines read from their sources (skia's hairlines,
    # Qt's cosmetic lines): no sample point or tie rule of theirs
    out += [replace(unsnapped, line=LineRule(rule)) for rule in FIXED_POINT_LINE_RULES]
    # llvmpipe's rectangular lines (lavapipe): at the triangles' sample point and the centre,
    # x the 8 tie rules (a measured sample off those is a rectangle's, refined on its grid)
    return out + [replace(unsnapped, sample=s, tie=t, line=LineRule("llvmpipe-rectangle")) for s, t in pairs
                  if s in (single.sample, (0.5, 0.5))]


# --- calling a rasterizer with lines, and scoring its answers -------------------------------------


def _send(call: Call, scene: LineScene) -> Outcome:
    """``call`` on a line scene (:data:`harness.engine.isolation.Call` names triangle scenes only;
    a worker and an in-process call send whatever they are given)."""
    return call(scene)  # type: ignore[arg-type]


@dataclass(frozen=True)
class LineDrawn:
    """A line scene and the rasterizer's answer to it, scored against candidate
    conventions (missing plus extra pixels, with multiplicity; an unanswered scene says
    nothing: no pixels, no mismatches, left out of every fit and residual). The answer
    is seen tidied (:meth:`harness.contract.coverage.Coverage.tidy`), the pixels the
    tidying dropped counted as extra (``dropped``)."""

    scene: LineScene
    outcome: Outcome
    # the scene as the library received it (say, its coordinates rounded to float32 at the
    # GL API: the rasterizer's ``received``), which the candidates are judged on
    judged: LineScene | None = None

    @property
    def coverage(self) -> Coverage | None:
        return self.outcome.coverage

    @property
    def error(self) -> BaseException | None:
        return self.outcome.error if self.outcome.coverage is None else None

    @cached_property
    def dropped(self) -> int:
        raw, kept = self.outcome.received, self.outcome.coverage
        if raw is None or kept is None:
            return 0
        claimed = float(np.maximum(raw.x1.astype(np.float64) - raw.x0.astype(np.float64), 0.0).sum())
        return max(0, int(claimed) - kept.n_pixels)

    @property
    def pixels(self) -> int:
        return 0 if self.coverage is None else self.coverage.n_pixels + self.dropped

    @cached_property
    def _counter(self) -> FragmentCounter:
        return FragmentCounter(self.coverage or Coverage.empty(), self.scene.width, self.scene.height)

    @cached_property
    def _scores(self) -> dict[Convention, int]:
        return {}

    @cached_property
    def _still(self) -> dict[tuple[int, str], bool]:
        return {}

    def _seen_as(self, convention: Convention) -> Convention:
        """``convention`` without its snapping when that moves no end point of the scene
        (the oracle is then the same: candidates differing only there share one)."""
        convention = convention.for_lines()
        bits, rounding = convention.subpixel_bits, convention.snap_rounding
        if bits is None:
            return convention
        if (bits, rounding) not in self._still:
            v = self.scene.vertices
            self._still[bits, rounding] = bool(np.array_equal(convention.snap(v), v, equal_nan=True))
        if not self._still[bits, rounding]:
            return convention
        return replace(convention, subpixel_bits=None, snap_rounding="nearest-even")

    def mismatches(self, convention: Convention) -> int:
        """Missing plus extra pixels against the exact oracle of ``convention`` (0 when
        unanswered: no answer is not an answer of nothing)."""
        if self.coverage is None:
            return 0
        seen = self._seen_as(convention)
        if seen not in self._scores:
            judged = self.scene if self.judged is None else self.judged
            self._scores[seen] = self._counter.mismatches(exact_coverage(judged, seen)) + self.dropped
        return self._scores[seen]


def _draw(call: Call, scene: LineScene, received: Callable[[Any], Any] | None = None) -> LineDrawn:
    judged = None
    if received is not None:
        try:
            got = received(scene)
        except Exception:  # a received() that fails judges nothing: the scene as sent
            got = None
        # isinstance: what a plugin's received() answered is checked for its class, not dispatched on
        judged = got if isinstance(got, LineScene) and got.strip_sizes.tolist() == scene.strip_sizes.tolist() else None
    return LineDrawn(scene, _send(call, scene), judged)


def _fit_score(drawn: list[LineDrawn], convention: Convention) -> int:
    """Mismatches on the answered scenes (an unanswered one never steers a fit)."""
    return sum(d.mismatches(convention) for d in drawn if d.coverage is not None)


def _snapped(convention: Convention, bits: int | None, rounding: SnapRounding) -> Convention:
    return replace(convention, subpixel_bits=bits, snap_rounding=rounding if bits is not None else "nearest-even")


# --- the records --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class LineRounding:
    """Mismatches of each snap rounding with every end point a half step of the 2**-bits
    grid off the lattice, best first; ``tied``, those as good as the best."""

    bits: int
    scores: tuple[tuple[SnapRounding, int], ...]
    tied: tuple[SnapRounding, ...]

    @property
    def text(self) -> str:
        return ("; ".join(f"{r}: {score} mismatches" for r, score in self.scores)
                + f" (every end point a half step of the 2^-{self.bits} grid)")


@dataclass(frozen=True, slots=True)
class WideLines:
    """Segments of width :data:`WIDE`: refused (``error``), or drawn (``pixels``) and
    compared with the best rectangular-line convention (``rectangle``, ``mismatches``);
    for a width-1 rule, also with that rule at width 1 (``thin``: a rasterizer that ignores
    the width)."""

    width: float
    error: str = ""
    pixels: int = 0
    rectangle: Convention | None = None
    mismatches: int = 0
    thin: int | None = None
    replicated: int | None = None

    @property
    def text(self) -> str:
        if self.error:
            return f"width {self.width:g}: refused ({self.error})"[:200]
        said = f"width {self.width:g}: {self.mismatches:,} mismatches of {self.pixels:,} pixels against "
        said += "rectangular lines" if self.rectangle is None else self.rectangle.describe_lines()
        if self.thin is not None:
            said += f"; {self.thin:,} against its rule at width 1" + (" (it ignores the width)" if self.thin == 0 else "")
        if self.replicated is not None:
            said += (f"; {self.replicated:,} against its rule replicated along the minor axis"
                     + (" (GL's wide lines)" if self.replicated == 0 else ""))
        return said


_PARTS = (("subpixel_bits", "snapping bits"), ("snap_rounding", "snap rounding"))


@dataclass(frozen=True)
class LineFit:
    """The convention that best explains the rasterizer's lines (its ``line`` the
    :class:`~harness.contract.conventions.LineRule`, its snapping, and for rectangles its sample
    point and tie rule), with its mismatches (``residual``) over ``pixels`` drawn on every
    probe scene; the runner-up (another rule, last pixel, rounding, ties, direction, or rectangle
    sample point or tie rule) and its mismatches; the snap roundings it could not tell
    apart (``ambiguous``); each rule's best score on the lattice scenes of step 1
    (``rule_scores``, unsnapped); the triangle
    convention compared (``triangles``; None when it takes none); the wide-line probe;
    ``skipped``, why no fit was made; ``sweep``, the sample point measured
    (:func:`line_sample_sweep`)."""

    convention: Convention | None
    residual: int = 0
    pixels: int = 0
    runner_up: tuple[str, int] | None = None
    ambiguous: tuple[str, ...] = ()
    rule_scores: tuple[tuple[str, int], ...] = ()
    rounding: LineRounding | None = None
    wide: WideLines | None = None
    triangles: Convention | None = None
    scenes: int = 0
    unanswered: tuple[str, ...] = ()
    skipped: str = ""
    sweep: LineSampleSweep | None = None
    drawn: tuple[LineDrawn, ...] = field(default=(), repr=False, compare=False)

    @property
    def rule(self) -> LineRule | None:
        return None if self.convention is None else self.convention.line

    @property
    def exact(self) -> bool:
        """No mismatch, a runner-up with some, no ambiguity, every probe scene answered."""
        return (self.convention is not None and self.residual == 0 and not (self.runner_up is not None and self.runner_up[1] == 0)
                and not self.ambiguous and not self.unanswered)

    @property
    def differences(self) -> tuple[str, ...]:
        """What differs from the triangle convention: snapping, and for rectangular lines
        the sample point and tie rule; each as ``part value (triangles: value)``."""
        if self.convention is None or self.triangles is None or not self.triangles.model.single_sample:
            return ()
        parts = _PARTS + ((("sample", "sample"), ("tie", "ties")) if self.convention.line.rule in AREA_LINE_RULES else ())
        return tuple(f"{label} {getattr(self.convention, part)} (triangles: {getattr(self.triangles, part)})"
                     for part, label in parts if getattr(self.convention, part) != getattr(self.triangles, part))

    @property
    def same_as_triangles(self) -> bool | None:
        """Whether the line convention's snapping (and a rectangle's sample point and ties)
        are the triangle convention's; None when either is missing."""
        if self.convention is None or self.triangles is None or not self.triangles.model.single_sample:
            return None
        return not self.differences

    @property
    def text(self) -> str:
        if self.convention is None:
            return f"not fitted: {self.skipped}"
        quality = ("" if self.exact else
                   f" (best guess only: {len(self.unanswered)} probe scenes unanswered, left out of the fit)"
                   if self.unanswered else
                   " (best guess only)" if self.residual else
                   f" (ambiguous between {' and '.join(self.ambiguous)})" if self.ambiguous else
                   " (ambiguous: the next best explains it as well)")
        said = f"{self.convention.describe_lines()}, {self.residual:,} mismatches of {self.pixels:,} pixels{quality}"
        if self.runner_up is not None:
            said += f"; next best {self.runner_up[0]} ({self.runner_up[1]:,})"
        same = self.same_as_triangles
        if same is False:
            said += f"; DIFFERS from triangles: {', '.join(self.differences)}"
        if self.unanswered:
            said += f"; {len(self.unanswered)} of {self.scenes} probe scenes unanswered (fit on the rest): {self.unanswered[0]}"
        return said

    @property
    def rules_text(self) -> str:
        """Each rule's best mismatches, as the card's "line rules" line says them."""
        return ", ".join(f"{rule}: {score:,}" for rule, score in self.rule_scores) + " mismatches at best on the lattice scenes"


# --- the probes ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class LineSampleSweep:
    """Where a rectangular line's end, swept across a pixel, stops covering it: the sample
    point, up to the snapping grid (x from a horizontal segment's start, y from a
    vertical one's); None when the pixel never flips (the rasterizer raised, draws
    nothing there, or draws no rectangles)."""

    offset: tuple[float, float] | None
    resolution: int = 20

    @property
    def text(self) -> str:
        if self.offset is None:
            return "no flip found under a segment's end swept across a pixel (not rectangular lines, or nothing drawn)"
        return (f"a segment's end swept across a pixel flips it at offset ({self.offset[0]:.6g}, {self.offset[1]:.6g}) "
                f"(bisected to 2^-{self.resolution} px; snapping moves it by up to one grid step)")


# The sweep's segments, as functions of the end's offset t into the probe pixel: a
# horizontal one on y = 30.25 and 30.75 (a width-1 rectangle holds the samples of row 30
# with y offsets in (-0.25, 0.75), (0.25, 1.25): one of them holds any), read at pixel
# (8, 30); a vertical one on x = 30.25 and 30.75, read at pixel (30, 8).
_SWEPT = ((0, 30.25), (0, 30.75), (1, 30.25), (1, 30.75))


def line_sample_sweep(call: Call, resolution: int = 20) -> LineSampleSweep:
    """The sample point of rectangular lines, measured directly as the triangles' sample
    sweep does (:func:`harness.identify.triangle_probes.sample_sweep`), anywhere on the dyadic grid: the
    start of a long horizontal (vertical) segment moved from half a pixel before pixel
    (8, 30) ((30, 8)) to half a pixel past it, bisected (every segment in one scene, one
    call per halving) to where the pixel stops being covered. Each offset is read as the
    end of its last interval with fewer fraction bits; the fit tries it at a few dyadic
    precisions besides the 9 usual points, which absorbs the snapping's error."""
    def covered(t: NDArray[np.float64]) -> NDArray[np.bool_] | None:
        a = np.array([[8.0 + t[k], line] if axis == 0 else [line, 8.0 + t[k]] for k, (axis, line) in enumerate(_SWEPT)])
        b = np.array([[40.0, line] if axis == 0 else [line, 40.0] for axis, line in _SWEPT])
        got = _send(call, LineScene.from_segments(48, 48, a, b)).coverage
        if got is None:
            return None
        k, x, y = got.pixels()
        want = np.array([[8, 30] if axis == 0 else [30, 8] for axis, _ in _SWEPT])
        return np.array([bool(np.any((k == i) & (x == want[i, 0]) & (y == want[i, 1]))) for i in range(len(_SWEPT))])

    lo, hi = np.full(len(_SWEPT), -0.5), np.full(len(_SWEPT), 1.5)
    at_lo, at_hi = covered(lo), covered(hi)
    if at_lo is None or at_hi is None:
        return LineSampleSweep(None, resolution)
    flips = at_lo & ~at_hi
    if not (flips[0] or flips[1]) or not (flips[2] or flips[3]):
        return LineSampleSweep(None, resolution)
    while hi[0] - lo[0] > 2.0**-resolution:
        mid = (lo + hi) / 2.0  # exact: dyadic
        at_mid = covered(mid)
        if at_mid is None:
            return LineSampleSweep(None, resolution)
        lo, hi = np.where(at_mid, mid, lo), np.where(at_mid, hi, mid)
    found = []
    for axis in (0, 1):
        k = 2 * axis if flips[2 * axis] else 2 * axis + 1
        low, high = float(lo[k]), float(hi[k])
        found.append(low if _fraction_bits(low) <= _fraction_bits(high) else high)
    return LineSampleSweep((found[0], found[1]), resolution)


def wide_lines(call: Call, seed: int, fitted: Convention, rectangle: Convention,
               received: Callable[[Any], Any] | None = None) -> WideLines:
    """Lattice segments of width :data:`WIDE` against ``rectangle`` (the best rectangular-line
    candidate of the fit), and for a width-1 rule (``fitted``) against that rule on the same
    segments at width 1; for a diamond rule, also against it replicated along the minor
    axis (GL's wide lines, ``LineRule(wide="replicate")``)."""
    scene = lattice_lines(seed + 3, 60).with_line_width(WIDE)
    drawn = _draw(call, scene, received)
    if drawn.coverage is None:
        return WideLines(WIDE, describe(drawn.error))
    thin = replicated = None
    if fitted.line.rule not in AREA_LINE_RULES:
        thin = drawn._counter.mismatches(exact_coverage(scene.with_line_width(1.0), fitted)) + drawn.dropped
    if fitted.line.diamond:
        replicated = drawn.mismatches(replace(fitted, line=replace(fitted.line, wide="replicate")))
    return WideLines(WIDE, "", drawn.pixels, rectangle, drawn.mismatches(rectangle), thin, replicated)


def _aliased(drawn: list[LineDrawn]) -> str:
    """Why the answers cannot be judged as aliased single-sample lines ("" when they can)."""
    for d in drawn:
        if d.coverage is not None and d.coverage.alpha is not None:
            return "its lines carry alphas (anti-aliased); the line rules are aliased"
        if d.coverage is not None and d.coverage.sample is not None:
            return ("its lines carry sample indices (multisample): rectangles per sample, judged against the declared "
                    "rule, not fitted here")
    return ""


def fit_lines(call: Call, seed: int = 0, triangles: Convention | None = None,
              received: Callable[[Any], Any] | None = None) -> LineFit:
    """The line convention that best explains the rasterizer (see the module docstring).

    Parameters
    ----------
    call : Call
        The rasterizer, taking line scenes.
    seed : int
        Seeds the random probe scenes.
    triangles : Convention or None
        The convention identified for its triangles (or paths), compared with the line
        convention; None when it takes none. The width-1 candidates carry its sample point
        and tie rule, and rectangles at them are tried first.
    received : callable or None
        The rasterizer's ``received(scene)`` (:func:`harness.contract.protocol.received_of`): candidates
        are judged on the scene as the library received it (float32 coordinates at the GL
        API), as identify judges triangles.

    Returns
    -------
    LineFit
    """
    sweep = line_sample_sweep(call)
    candidates = line_candidates(triangles, sweep.offset)
    # 1. the rule, on end points no candidate snapping moves
    ruled = [_draw(call, s, received) for s in (crafted_lines(), lattice_lines(seed), lattice_lines(seed, 60, strips=True))]
    answered = [d for d in ruled if d.coverage is not None]
    if not answered:
        return LineFit(None, triangles=triangles, scenes=len(ruled), skipped=f"unanswered: {describe(ruled[0].error)}"[:200],
                       drawn=tuple(ruled))
    odd = _aliased(answered)
    if odd:
        return LineFit(None, triangles=triangles, scenes=len(ruled), skipped=odd, drawn=tuple(ruled))
    lattice = [_fit_score(ruled, c) for c in candidates]

    def general() -> list[int]:
        # the general rules, in lattice order; the rules read from one library's source are
        # weighed against their fit afterwards (step 4)
        return sorted((i for i, c in enumerate(candidates) if c.line.rule not in LIBRARY_LINE_RULES),
                      key=lambda i: (lattice[i], i))

    order = general()
    best = candidates[order[0]]
    # 2. snapping, on end points next to decision boundaries and on floats
    floats = [_draw(call, nudged_lines(seed), received), _draw(call, float_lines(seed), received)]
    snaps: list[tuple[int | None, SnapRounding]] = [(None, "nearest-even")]
    snaps += [(b, r) for b in SNAP_BITS if b is not None for r in PLAIN_SNAP_ROUNDINGS]
    own: tuple[int | None, SnapRounding] = (None, "nearest-even") if triangles is None or triangles.subpixel_bits is None \
        else (triangles.subpixel_bits, triangles.snap_rounding)

    def preference(bits: int | None, rounding: SnapRounding) -> int:
        # ties prefer the triangles' snapping (a snapping no line shows is theirs), then
        # none, then rounding to nearest even
        return 0 if (bits, rounding) == own else 1 if bits is None else 2 + PLAIN_SNAP_ROUNDINGS.index(rounding)

    scored = sorted((_fit_score(floats, _snapped(best, b, r)), preference(b, r), k) for k, (b, r) in enumerate(snaps))
    bits, rounding = snaps[scored[0][2]]
    if sweep.offset is not None and best.line.rule == "rectangle" and bits is not None:
        # a rectangle's flip, swept with a snapped end, lies up to a grid step off its
        # sample: the grid points either side of it near the grid found join the
        # candidates, and the snapping is fitted again with each of them (the lattice
        # scenes cannot tell them apart: their end points are never moved)
        near = [b for b in (bits - 1, bits, bits + 1) if 0 <= b <= MAX_SUBPIXEL_BITS]
        known = {(c.sample, c.tie) for c in candidates if c.line.rule == "rectangle"}
        extra = [replace(candidates[order[0]], sample=s, tie=t) for s in grid_sides(sweep.offset, near)
                 for t in TIE_RULES if (s, t) not in known]
        candidates += extra
        lattice += [_fit_score(ruled, c) for c in extra]
        order = general()
        trials = [(best, *snaps[scored[0][2]])] + [(c, b, r) for c in extra if c.tie == best.tie
                                                   for b in near for r in PLAIN_SNAP_ROUNDINGS]
        _, _, _, best, bits, rounding = min(((_fit_score(floats, _snapped(c, b, r)), preference(b, r), k, c, b, r)
                                            for k, (c, b, r) in enumerate(trials)), key=lambda t: t[:3])
    rounding_fit = None
    if bits is not None:
        floats.append(_draw(call, half_step_lines(seed, bits), received))
        ranked = sorted((_fit_score(floats, _snapped(best, bits, r)), preference(bits, r), r) for r in PLAIN_SNAP_ROUNDINGS)
        rounding = ranked[0][2]
        rounding_fit = LineRounding(bits, tuple((r, sum(d.mismatches(_snapped(best, bits, r)) for d in floats))
                                                for _, _, r in ranked),
                                    tuple(r for score, _, r in ranked if score == ranked[0][0]))
    per_rule = {rule: min((lattice[i] for i, c in enumerate(candidates) if c.line.rule == rule), default=0)
                for rule in LINE_RULES}
    # 3. the rule again, with that snapping, on every scene; a candidate's score on the
    # lattice scenes bounds its total from below (no snapping of 2 bits or more moves a
    # multiple of 1/4), so one that cannot beat the runner-up so far is passed over
    drawn = ruled + floats
    if best.line.rule == "rectangle" and best.sample not in SAMPLES:
        # ties at its sample point, which the lattice scenes do not meet (as identify does for triangles)
        drawn.append(_draw(call, rectangle_tie_lines(best.sample), received))
    totals: list[tuple[int, int]] = []
    for rank, i in enumerate(order):
        candidate = _snapped(candidates[i], bits, rounding)
        if len(totals) >= 2 and lattice[i] >= totals[1][0]:
            break  # in lattice order: every later candidate's bound is as large
        totals = sorted([*totals, (_fit_score(drawn, candidate), rank)])[:2]
    best = _snapped(candidates[order[totals[0][1]]], bits, rounding)
    rectangle = best if best.line.rule in AREA_LINE_RULES else _snapped(
        next(candidates[i] for i in order if candidates[i].line.rule == "rectangle"), bits, rounding)
    runner = _snapped(candidates[order[totals[1][1]]], bits, rounding)
    # 4. a rule read from one library's source (skia's hairlines, Qt's cosmetic lines,
    # llvmpipe's rectangles), with its own snapping fit, replaces that fit only where it
    # leaves at most 1/LIBRARY_MARGIN of its residual: a library's rule explains that
    # library, and does not stand in as another's best guess
    chosen: tuple[int, Convention] | None = None
    for i in sorted((i for i, c in enumerate(candidates) if c.line.rule in LIBRARY_LINE_RULES), key=lambda i: (lattice[i], i)):
        if lattice[i] * LIBRARY_MARGIN > totals[0][0] or (chosen is not None and lattice[i] >= chosen[0]):
            break  # in lattice order: no later one can do better
        snapping = own if candidates[i].line.own_snapping else snaps[min(
            (_fit_score(floats, _snapped(candidates[i], b, r)), preference(b, r), k) for k, (b, r) in enumerate(snaps))[2]]
        candidate = _snapped(candidates[i], *snapping)
        total = _fit_score(drawn, candidate)
        # (strictly better: an exact general fit stands)
        if total * LIBRARY_MARGIN <= totals[0][0] and total < totals[0][0] and (chosen is None or total < chosen[0]):
            chosen = (total, candidate)
    if chosen is not None:
        best, runner = chosen[1], best
        bits, rounding, rounding_fit = best.subpixel_bits, best.snap_rounding, None
        if best.line.rule in AREA_LINE_RULES:
            rectangle = best
    ambiguous = (tuple(f"{bits} bits {r}" for r in rounding_fit.tied)
                 if rounding_fit is not None and len(rounding_fit.tied) > 1 else ())
    if (triangles is not None and triangles.model.single_sample and bits is not None and bits == triangles.subpixel_bits
            and rounding != triangles.snap_rounding):
        # lines snap on the triangles' grid but round otherwise (lavapipe): the rule says so,
        # and the triangle convention with this rule draws these lines
        best = replace(best, line=replace(best.line, snap_rounding=rounding))
    wide = wide_lines(call, seed, best, rectangle, received)
    if wide.replicated == 0 and wide.pixels:  # it draws wide lines as GL does: part of its rule
        best = replace(best, line=replace(best.line, wide="replicate"))
    return LineFit(best, sum(d.mismatches(best) for d in drawn), sum(d.pixels for d in drawn),
                   (runner.describe_lines(), sum(d.mismatches(runner) for d in drawn)), ambiguous,
                   tuple(per_rule.items()), rounding_fit, wide, triangles, len(drawn),
                   tuple(describe(d.error) for d in drawn if d.coverage is None), sweep=sweep, drawn=tuple(drawn))
