"""Failure signatures: what a failing or erroring result says about its cause, as a short
stable key, so that ten thousand failures of one bug make one finding and two bugs two.

A :class:`Signature` is (check, failure class, convention part). The class is read from the
evidence the checks record (:class:`harness.checks.Result`: ``evidence``, ``metrics`` and,
for a failure, the :class:`~harness.checks.Drawing` with the rasterizer's answer) and from
exact facts about the deviating samples, decided by the exact predicates
(:func:`harness.geometry.exact.orientation`), never an epsilon: whether a sample lies exactly on an
edge, and whether that edge is horizontal, vertical or slanted (float comparisons of its
end points: exact), or exactly on a vertex. Measures that are tolerances by nature
(within float rounding of an edge, how huge a coordinate is) say so in their names.

Classes of a ``conformance`` failure, first that holds (only the *wrong* deviations count,
those not excused as near ties; non-finite and zero-area primitives are named only when
every wrong one is such, else set aside):

===============================  ==================  ==============================================
class                            convention part     when
===============================  ==================  ==============================================
``input-format``                 none                the trial found it passes as the library
                                                     receives it (evidence ``input_precision``:
                                                     :func:`~harness.diagnose.trials.with_trials`)
``viewport-edge``                none                the trial found it passes moved into a grown
                                                     screen (evidence ``viewport_edge``)
``non-finite-input``             none                every wrong primitive has a NaN or infinity
``degenerate``                   none                every wrong triangle has zero area after
                                                     snapping (segment: zero length)
``open-contour``                 none                the wrong primitives are drawn exactly as with
                                                     each contour's closing edge (last vertex to
                                                     first; a triangle's third) left out, a row left
                                                     inside ending at its last crossing or at the
                                                     screen's edge, and differently from the oracle
                                                     and from nothing (:func:`harness.oracle.winding.
                                                     open_outline_coverage`); missing whole: with
                                                     their copies in other vertex orders, drawn in
                                                     part, they are so drawn (evidence
                                                     ``dropped_trial``). At any magnitude
``overflow-2^a..2^b``            none                a wrong primitive's largest |coordinate| lies in
                                                     [2^a, 2^b): 2^12, 2^24 (float32's integers),
                                                     2^31 (int32), 2^53 (float64's integers), 2^63
                                                     (int64), 2^128 (float32's range), beyond
``overflow-below-2^12``          none                (triangles) not every wrong sample on or near an
                                                     edge, and the wrong triangles, each at least
                                                     64 px long, are drawn right scaled down under
                                                     that (evidence ``size_trial``): a range that gives
                                                     out early (int32 products of fixed point)
``culling``                      culling             every wrong deviation is a missing fragment of a
                                                     primitive drawn not at all, and moved by quarter
                                                     pixels it is never drawn, its other winding is
                                                     (evidence ``dropped_trial``); or, untried, every
                                                     triangle of their winding is missing, some of
                                                     the other drawn
``dropped-primitive``            none                ... whole primitives missing otherwise -- unless
                                                     a moved copy is drawn: then missed, not dropped
                                                     (the classes below name how); or, grown three
                                                     pixels thick, they are drawn wrong: that
                                                     failure's class (evidence ``grown``)
``snapping``                     snapping            the wrong primitives are drawn exactly as the
                                                     oracle draws them under another rounding of the
                                                     same snapping (an oracle call per other
                                                     rounding that moves a vertex: two at most)
``fill-rule``                    fill-rule           (paths wrong away from their edges) ... under the
                                                     other fill rule (one oracle call)
``viewport-edge``                none                every wrong sample lies exactly on, or (beyond
                                                     float rounding) within 1/16 px of, an edge that
                                                     leaves the screen -- and, for exact ties, a tie of
                                                     the same kind on an edge inside the screen was
                                                     decided right
``exact-tie-slanted-edge``,      tie-rule            every wrong sample lies exactly on an edge of its
``-vertical-edge``,                                  primitive (or exactly on a vertex); the class
``-horizontal-edge``,                                names the first kind present in this order
``exact-tie-vertex``
``exact-tie-<dir>-segment``      line-rule           (lines) the rule's decision exactly on its
                                                     boundary; dir: slanted, diagonal, vertical,
                                                     horizontal
``near-tie``                     none                every wrong sample lies within float32 rounding of
                                                     an edge of its primitive (|E| <= 2^-17 M^2, M the
                                                     largest |coordinate|) and within 2^-8 px of it
``end-pixel``                    line-rule           (lines) every wrong pixel is next to an end point
``vertex-row``                   tie-rule            (paths) every wrong sample on a row through one of
                                                     its path's vertices: how the ray's crossings
                                                     there count is the tie rule's (the perturbed
                                                     sample's row meets no vertex), not the fill's
``later-contours-dropped``       none                (paths wrong away from their edges) drawn as
                                                     the oracle draws each one's first contour alone
``holes-ignored``                fill-rule           ... as each contour filled on its own (the union);
                                                     either only where the two differ
``winding``                      fill-rule           (paths) none of the above
``dropped-near-edges``           none                (multisample) every wrong sample missing (none
                                                     extra, of every layer: the metrics), within
                                                     a pixel of an edge, its pixel's centre outside
                                                     the triangle (exact): pixels rejected whole near
                                                     an edge
``far-from-edge``                sample-point        (triangles) none of the above
``far-from-tie``                 line-rule           (lines) none of the above
===============================  ==================  ==============================================

``watertight``: ``hole``, ``double-hit``, ``hole-and-double-hit`` or ``stray`` (tie-rule when
every hole and double hit has its sample exactly on the blamed shared edge -- on a float
partition, only if the same tie rebuilt on a lattice fails too: evidence ``lattice_twin``),
``near-tie`` when every one lies within float rounding of it, ``non-finite-input`` and
``overflow-...`` as above. ``degenerate``'s ``zero-area-drawn`` is the tie rule's when every
flat triangle drew only samples exactly on its own line, and ``non-finite-input`` when every
triangle it names has a NaN or infinite coordinate. Motion (jaggy, texel, perspective, popping), first that holds
(:func:`~harness.diagnose.trials.with_trials` finds the facts): ``input-format`` when the whole sequence passes as
the library receives it; the class and part of a frame the failure names that fails
conformance, or accuracy, judged alone (a flicker of a wrong tie rule is the tie rule's, a
pop of a biased alpha is ``alpha-error``); ``snapping`` when texel or perspective pass on
the same answers against another snap rounding's exact u, v; else ``backward-jump``,
``flicker``; ``texel-mismatch``, ``texel-backward-step``, ``perspective-error``,
``missing-attributes``, ``popping``. Lines:
``gap``, ``break``, ``double-step`` (connectivity), ``joint-vertex``, ``joint-overlap``,
``reversal``, ``last-pixel`` (a segment one pixel long or short), ``length``,
``backward-step``. Others: ``hygiene``'s flaw (``outside-viewport``, ...), ``degenerate``'s
(``zero-area-drawn``, ``nan-attributes``, ``slow``), ``invariance``'s first changed variant
(``changes-under-flip-winding``, ...), ``closed``'s ``front-only``/``back-only``/``unbalanced``,
``accuracy``'s cause named from facts about its errors, first that holds
(:func:`harness.checks.area.alpha_cause`: ``truncated-levels``, ``coarse-levels``,
``alpha-bias``, ``gamma``, ``overflow-2^a..2^b`` when only triangles beyond 2^12 err,
``sub-pixel-shift``, ``drift``), else ``alpha-error``/``off-level``;
``seam``, ``triangulation-mismatch``.

Errors: ``hang`` (a timeout), ``crash`` (the worker process died), ``not-run``,
``exception-<Type>``.

Anything else, or anything the classification cannot read, is ``other``:
:func:`signature` never raises. Its oracle calls are hypothesis tests on the wrong
primitives alone: the open outline (three: the oracle and two open fills), the other snap
roundings (two at most), or the other fill rule, the first contours alone and each contour
alone (one each).

This module is the vocabulary (:class:`Signature`, the classes above) and the
classification; the exact facts about the wrong samples and the oracle's hypothesis tests
are :mod:`harness.diagnose.facts`, the trials that call the rasterizer again on a failure
:mod:`harness.diagnose.trials`, and what differs per scene kind each kind's hooks
(:mod:`harness.kinds`: ``conformance_class``, ``hypotheses``, ``tie_trial``, ``dropped_trial``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks.area import ALPHA_CAUSES, alpha_cause
from harness.checks.records import OVERFLOW_EDGES, check_named, overflow_class
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.scenes import AnyScene, LineScene
from harness.diagnose.facts import (
    NEAR_PIXELS,
    answer_of,
    dropped_class,
    dropped_near_edges,
    edge_facts,
    edges_of,
    flat_primitives,
    hypothesis_class,
    judged_convention,
    magnitude_of,
    on_flat_line,
    open_outline,
    primitive_coordinates,
    segment_direction,
    ties_right_inside,
    wrong_pixels,
    wrong_reach_beyond,
)
from harness.kinds import PATHS, TRIANGLES, kind_of

__all__ = ["Signature", "signature", "CONVENTION_PARTS", "OVERFLOW_EDGES", "overflow_class"]

CONVENTION_PARTS = ("tie-rule", "sample-point", "snapping", "culling", "fill-rule", "line-rule", "none")


# failure classes of attributes missing or wrong: one cause (:attr:`Signature.cause`)
ATTRIBUTE_CLASSES = ("missing-attributes", "bad-attributes", "nan-attributes")


_WORDS = {
    "exact-tie-horizontal-edge": "samples exactly on a horizontal edge decided wrongly",
    "exact-tie-vertical-edge": "samples exactly on a vertical edge decided wrongly",
    "exact-tie-slanted-edge": "samples exactly on a slanted edge decided wrongly",
    "exact-tie-vertex": "samples exactly on a vertex decided wrongly",
    "near-tie": "decided wrongly within float rounding of a tie (an edge; a line rule's boundary)",
    "viewport-edge": "wrong only where primitives cross the viewport's edge",
    "input-format": "right on the input as the library receives it: the input format",
    "snapping": "right under another rounding of the same snapping",
    "fill-rule": "right under the other fill rule",
    "winding": "samples away from every edge decided wrongly: the winding or fill",
    "later-contours-dropped": "drawn as if each path had only its first contour: the contours after it dropped",
    "holes-ignored": "drawn as each contour filled on its own (their union): holes ignored",
    "vertex-row": "samples on rows through a vertex decided wrongly: crossings counted at vertices",
    "non-finite-input": "a primitive with a NaN or infinite coordinate drawn wrongly",
    "degenerate": "a zero-area triangle (zero-length segment) drawn wrongly",
    "culling": "whole primitives of one winding missing",
    "dropped-primitive": "whole primitives missing",
    "open-contour": "drawn as if each contour's closing edge were missing",
    "overflow-below-2^12": "wrong on large triangles, right made smaller (a range that gives out below 2^12)",
    "far-from-edge": "samples away from every edge decided wrongly",
    "rule-boundary": "pixels exactly on the coverage rule's boundary decided wrongly (an area of exactly the threshold, "
                     "a square the triangle only touches, or one inside it with a corner on an edge)",
    "coverage-rule": "pixels decided wrongly against the declared coverage rule, away from its boundary",
    "dropped-near-edges": "samples just inside an edge missing in pixels whose centre lies outside (none extra): "
                          "dropped near edges, not a wrong pattern",
    "far-from-tie": "pixels away from the rule's ties drawn wrongly",
    "end-pixel": "pixels at a segment's end drawn wrongly",
    "crash": "the rasterizer's process died",
    "hang": "no answer within the time limit",
    "not-run": "not run",
    "hole": "holes in a partition",
    "double-hit": "pixels hit twice in a partition",
    "hole-and-double-hit": "holes and double hits in a partition",
    "stray": "pixels hit outside a partition",
    "last-pixel": "segments drawn one pixel longer or shorter than the rule",
    "length": "segments drawn with another number of pixels than the rule",
    "reversal": "pixels that change when a segment is drawn the other way",
    "joint-vertex": "the pixel where two segments meet drawn otherwise than the rule",
    "joint-overlap": "pixels drawn by both segments of a joint otherwise than the rule",
    "gap": "steps missing along a line",
    "break": "breaks between the segments of a strip",
    "double-step": "steps drawn twice along a line",
    "alpha-error": "alphas off the exact area beyond the tolerance",
    "seam": "pixels where the alphas of a partition's pieces do not add up to 1 (a seam)",
    **ALPHA_CAUSES,
    "off-level": "alphas on none of the declared levels",
    "flicker": "pixels changing more often than the exact coverage as the scene moves",
    "backward-jump": "edges jumping backwards as the scene moves",
    "popping": "the summed alpha jumping as the scene moves",
    "zero-area-drawn": "zero-area triangles drew pixels",
    "backward-step": "a line's pixels stepping backwards as the segment moves",
    "missing-attributes": "frames answered without the attributes to interpolate",
    "nan-attributes": "interpolated attributes that are NaN or infinite",
    "perspective-error": "attributes interpolated off the perspective-correct values",
    "texel-backward-step": "texels stepping backwards as the scene moves (swimming)",
    "texel-mismatch": "texels other than the exact interpolation's",
    "triangulation-double-hit": "pixels drawn twice by the triangles a path was cut into",
    "triangulation-mismatch": "a path drawn otherwise than the triangles it was cut into",
    **{f"exact-tie-{direction}-segment": f"pixels exactly on the line rule's boundary decided wrongly ({direction} segments)"
       for direction in ("slanted", "diagonal", "vertical", "horizontal")},
    "other": "unclassified",
}


@dataclass(frozen=True, slots=True)
class Signature:
    """What a failure says about its cause.

    Parameters
    ----------
    check : str
        The check that failed (``run`` for a call that gave no answer).
    failure_class : str
        How it failed (see the module docstring).
    convention_part : str
        What of the convention is involved: one of :data:`CONVENTION_PARTS`.

    >>> s = Signature("conformance", "exact-tie-slanted-edge", "tie-rule")
    >>> s.key
    'conformance|exact-tie-slanted-edge|tie-rule'
    >>> s.describe()
    'conformance: samples exactly on a slanted edge decided wrongly (the tie rule)'
    """

    check: str
    failure_class: str
    convention_part: str

    @property
    def key(self) -> str:
        """``check|failure_class|convention_part``: the finding's identity."""
        return f"{self.check}|{self.failure_class}|{self.convention_part}"

    @property
    def cause(self) -> str:
        """The cause the signature points at, which several signatures may share: the
        convention part when one is involved (a wrong tie rule is one cause whichever check,
        edge direction or frame shows it), else the failure class -- the overflow ranges as
        one (``overflow``), the attribute failures as one (``attributes``), a call slower
        than its peers and one with no answer in time as one (``slow``: a rasterizer slow on
        some input goes past the time limit on a loaded machine).

        >>> Signature("jaggy", "exact-tie-vertex", "tie-rule").cause, Signature("watertight", "overflow-2^53..2^63", "none").cause
        ('tie-rule', 'overflow')
        >>> Signature("run", "hang", "none").cause, Signature("degenerate", "slow", "none").cause
        ('slow', 'slow')
        """
        if self.convention_part != "none":
            return self.convention_part
        if self.failure_class.startswith("overflow-"):
            return "overflow"
        if self.failure_class in ("slow", "hang"):
            return "slow"
        if self.failure_class in ATTRIBUTE_CLASSES:
            return "attributes"
        return self.failure_class

    def describe(self) -> str:
        """One line for people."""
        words = _WORDS.get(self.failure_class)
        if words is None:
            if self.failure_class.startswith("overflow-"):
                words = f"wrong with coordinates of magnitude {self.failure_class.removeprefix('overflow-')}"
            elif self.failure_class.startswith("exception-"):
                words = f"raised {self.failure_class.removeprefix('exception-')}"
            else:
                words = self.failure_class.replace("-", " ")
        part = "" if self.convention_part == "none" else f" (the {self.convention_part.replace('-', ' ')})"
        return f"{self.check}: {words}{part}"


def signature(result: Any, case: Case | MotionCase | Any, convention: Convention | None) -> Signature:
    """The signature of a failing or erroring result of ``case``, judged under
    ``convention`` (the rasterizer's, declared or identified; None without one).

    Deterministic, at most five oracle calls (hypothesis tests on the wrong primitives alone), never
    raises: what it cannot read is ``other``.

    >>> from harness.checks import Result
    >>> signature(Result("r", "c", "run", "error", "timeout: no answer within 2 s"), None, None).key
    'run|hang|none'
    >>> signature(Result("r", "c", "run", "error", "ZeroDivisionError: division by zero"), None, None).key
    'run|exception-ZeroDivisionError|none'
    """
    try:
        check = str(getattr(result, "check", "") or "unknown")
    except Exception:  # a str() that raises: still a signature
        check = "unknown"
    try:
        status = getattr(result, "status", None)
        if status == "error":
            return Signature(check, _error_class(str(getattr(result, "message", ""))), "none")
        if status != "fail":
            return Signature(check, "other", "none")
        registered = check_named(check)
        classify = registered.classifier_function() if registered is not None else None
        if classify is None:  # no such check, or one registered without a classifier
            return Signature(check, "other", "none")
        # a motion check read through its frames: the frame verdict's cause when there is one
        through = _frame_cause(result) if registered is not None and registered.motion_role == "through-frames" else None
        failure_class, part = through or classify(result, case, convention)
        return Signature(check, failure_class, part)
    except Exception:  # anything unreadable: never raise
        return Signature(check, "other", "none")


_KIND = re.compile(r"^([A-Za-z_][\w.]*)(?::| on )")


def _error_class(message: str) -> str:
    """hang, crash, not-run or exception-<Type>, from an error result's message
    (``Type: text``, ``timeout: ...``, ``Type on what: ...``, ``frame k: ...``)."""
    text = message.strip()
    text = re.sub(r"^frame \d+: ", "", text)
    if text.startswith("not run"):
        return "not-run"
    if "worker process died" in text:
        return "crash"
    match = _KIND.match(text)
    if match is None:
        return "other"
    kind = match.group(1)
    if kind.lower() in ("timeout", "timeouterror"):
        return "hang"
    return f"exception-{kind.rsplit('.', 1)[-1]}"


def _viewport_edge_class(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    """A conformance failure that passes moved into a grown screen: the viewport's edge --
    unless the answer is exactly another snap rounding's (a rounding that is not
    translation-invariant, half away from zero, rounds the moved vertices otherwise, and
    passed there by chance), or no wrong primitive reaches beyond the screen (float
    arithmetic rounds moved coordinates otherwise too, and the edge decided nothing)."""
    rest = replace(result, evidence={k: v for k, v in result.evidence.items() if k != "viewport_edge"})
    without = classify_conformance(rest, case, convention)
    if without[1] == "snapping" or without[0] == "open-contour" or not wrong_reach_beyond(result, case.scene):
        return without
    return "viewport-edge", "none"


def _degenerate_class(scene: Any, wrong: list[Any], snapped: dict[int, NDArray[np.float64]],
                      judged: Convention) -> tuple[str, str]:
    """Every wrong sample a flat primitive's: drawn only where all three edge functions are
    0 is the tie rule's (an inclusive test); anything else is the degenerate case's own."""
    extra = [(k, x, y) for k, x, y, kind, _ in wrong if kind == "extra"]
    on_line = len(extra) == len(wrong) and all(
        bool(on_flat_line(snapped[k], np.array([[x + judged.sample[0], y + judged.sample[1]]]))[0]) for k, x, y in extra)
    # all three edge functions 0 is a triangle's inclusive test; a zero-length segment has no such line
    return "degenerate", "tie-rule" if on_line and TRIANGLES.owns(scene) else "none"


def _exact_tie_class(kinds: set[str]) -> tuple[str, str]:
    """Every wrong sample exactly on an edge or a vertex: the tie rule's error, named by the
    first kind of edge among them (slanted, then vertical, then horizontal)."""
    for kind in ("slanted", "vertical", "horizontal"):
        if kind in kinds:
            return f"exact-tie-{kind}-edge", "tie-rule"
    return "exact-tie-vertex", "tie-rule"


def _dropped_by_trial(copies: dict[str, Any]) -> tuple[str, str] | None:
    """The dropped-primitive trial's class when no copy of the primitive, moved a little,
    was drawn (None otherwise): its own convention part's error when a grown copy is drawn
    wrong, culling when its other winding is drawn right, else a dropped primitive."""
    if not (int(copies.get("copies", 0)) and not int(copies.get("drawn", 0))):
        return None
    # moved a little it covers samples and is never drawn: dropped (culled, if its other
    # winding is drawn) -- whatever ties its own samples are (a sliver thinner than the
    # tie trial's shift passes that trial vacuously); unless grown thick it is drawn,
    # and wrong: the bug that draws it wrong missed it (a span started a column late)
    grown = _sub_verdict(copies, "grown")
    if grown is not None and grown[1] not in ("none", "culling") and int(copies.get("grown", {}).get("drawn", 0)):
        return grown  # a convention part's error: the sample point, the tie rule, the snapping
    # culled: its other winding is drawn, and right ("flipped_right" absent: an older
    # trial's), its own from no vertex
    flipped_drawn = int(copies.get("flipped_drawn", 0))
    culled = flipped_drawn > 0 and int(copies.get("flipped_right", flipped_drawn)) == flipped_drawn \
        and not int(copies.get("rotated_drawn", 0))
    return ("culling", "culling") if culled else ("dropped-primitive", "none")


def classify_conformance(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    if "input_precision" in evidence:
        return "input-format", "none"
    if "viewport_edge" in evidence:
        return _viewport_edge_class(result, case, convention)
    scene = case.scene
    n = len(scene)
    wrong = wrong_pixels(result, scene.noun, n)
    if not wrong:
        return "other", "none"
    complete = metric_of(result, "wrong") <= len(wrong) or metric_of(result, "wrong") == 0  # every wrong one listed
    judged = judged_convention(result, convention)
    # non-finite, then zero-area primitives: their class when every wrong one is such; else
    # the others decide (a scene may show two bugs; the first kind is the one to name)
    non_finite = set(scene.non_finite())
    if all(k in non_finite for k, *_ in wrong):
        return "non-finite-input", "none"
    wrong = [w for w in wrong if w[0] not in non_finite]
    prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
    coordinates = primitive_coordinates(scene, prims)
    snapped = {int(k): judged.snap(c) for k, c in zip(prims, coordinates)}
    flat = flat_primitives(scene, prims, snapped)
    if all(k in flat for k, *_ in wrong):
        return _degenerate_class(scene, wrong, snapped, judged)
    if flat:
        wrong = [w for w in wrong if w[0] not in flat]
        prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
        coordinates = primitive_coordinates(scene, prims)
    if judged.model.rule:  # decided on the pixel's square: no sample point, no tie rule to blame
        from harness.oracle.coverage_rules import on_rule_boundary

        boundary = all(on_rule_boundary(snapped[k], x, y, judged) for k, x, y, *_ in wrong)
        return ("rule-boundary" if boundary else "coverage-rule"), "none"
    magnitude = magnitude_of(coordinates)
    named: tuple[str, str] = kind_of(scene).hook("conformance_class")(result, convention, scene, wrong, prims, snapped, judged,
                                                                      magnitude, complete)
    return named


def fill_conformance(result: Any, convention: Convention | None, scene: AnyScene, wrong: list[tuple[int, int, int, str, float]],
                     prims: NDArray[np.int64], snapped: dict[int, NDArray], judged: Convention, magnitude: float,
                     complete: bool) -> tuple[str, str]:
    """A triangle or path scene's conformance failure (the kinds' ``conformance_class``
    hook), its non-finite and flat primitives set aside: the trials' evidence and the
    exact facts of each wrong sample against its primitive's edges."""
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    copies = evidence.get("dropped_trial")
    copies = copies if isinstance(copies, dict) else {}
    answer = answer_of(result)
    if copies.get("open_contour") or (answer is not None and open_outline(answer, scene, prims, judged)):
        # drawn exactly as with each contour's closing edge left out (missing whole: their
        # copies in other vertex orders are): the outline, at any magnitude
        return "open-contour", "none"
    edges = edges_of(scene, judged)
    facts = [edge_facts(*edges[k], np.array([x + judged.sample[0], y + judged.sample[1]]), magnitude_of([snapped[k]]),
                         scene.width, scene.height) for k, x, y, _, _ in wrong]
    trial = evidence.get("tie_trial")
    if isinstance(trial, dict) and trial.get("passes") is False:
        # shifted off the edges it is still wrong: the samples were on edges by chance
        facts = [replace(f, tie=None) for f in facts]
    exact = all(f.tie is not None for f in facts)
    near = all(f.near for f in facts)
    overflow = overflow_class(magnitude)
    if overflow is not None:
        return overflow, "none"
    size = evidence.get("size_trial")
    if isinstance(size, dict) and size.get("passes") and not exact and not near:
        # wrong at its size, right made smaller: a range that gives out below 2**12
        return "overflow-below-2^12", "none"
    # a primitive wholly missing whose only wrong samples are exact ties is a tie rule's
    # error (a sliver whose one sample lies on its edge), not a dropped primitive
    trialled = _dropped_by_trial(copies)
    if trialled is not None:
        return trialled
    drawn_elsewhere = int(copies.get("drawn", 0)) > 0  # moved a little, some copy is drawn: not dropped
    # the other winding not drawn either: not culled
    culls = not (int(copies.get("flipped_copies", 0)) and not int(copies.get("flipped_drawn", 0)))
    dropped = None if exact or drawn_elsewhere else dropped_class(result, scene, prims, wrong, snapped,
                                                              lambda sc: judged.snap(sc.positions), culls)
    if dropped is not None:
        return dropped
    hypothesis = hypothesis_class(result, scene, prims, judged, near, exact)
    if hypothesis is not None:
        return hypothesis
    kinds = {f.tie for f in facts if f.tie is not None}
    if "viewport_edge_refuted" not in evidence and all(f.border for f in facts) \
            and (not kinds or (complete and ties_right_inside(scene, edges, judged, kinds, wrong))):
        # every wrong sample decided by an edge that leaves the screen, and (for ties) the
        # same kind of tie decided right on an edge inside it: a clipper's work
        return "viewport-edge", "none"
    if exact:
        return _exact_tie_class(kinds)
    if near:
        return "near-tie", "none"
    if isinstance(convention, Convention) and convention.model.sample_ids and TRIANGLES.owns(scene) \
            and metric_of(result, "extra") == 0 and dropped_near_edges(wrong, edges, judged):
        return "dropped-near-edges", "none"
    if PATHS.owns(scene):
        # every wrong sample on a row through one of its path's vertices (exact: float
        # comparisons): crossings counted at the vertices -- a tie in y, not the fill
        rows = all(bool(np.any(snapped[k][:, 1] == y + judged.sample[1])) for k, _, y, _, _ in wrong)
        # (unless, shifted off those rows, the paths still fail: the fill's, on such rows by chance)
        refuted = isinstance(trial, dict) and trial.get("vertex_rows") and trial.get("passes") is False
        return ("vertex-row", "tie-rule") if rows and not refuted else ("winding", "fill-rule")
    return "far-from-edge", "sample-point"


def line_conformance(result: Any, convention: Convention | None, scene: LineScene, wrong: list[tuple[int, int, int, str, float]],
                     prims: NDArray[np.int64], snapped: dict[int, NDArray], judged: Convention, magnitude: float,
                     complete: bool) -> tuple[str, str]:
    """A line scene's conformance failure (the kind's ``conformance_class`` hook):
    :func:`_line_conformance`."""
    return _line_conformance(result, scene, wrong, prims, snapped, judged, magnitude)


def _line_conformance(result: Any, scene: LineScene, wrong: list[tuple[int, int, int, str, float]], prims: NDArray[np.int64],
                      snapped: dict[int, NDArray], judged: Convention, magnitude: float) -> tuple[str, str]:
    """A line scene's conformance failure: the check's own distances say where the rule's
    decision sits (exactly 0 only on its boundary, decided exactly)."""
    exact = all(d == 0.0 for _, _, _, _, d in wrong)
    near = all(0.0 < d <= 2.0**-16 and d * magnitude <= NEAR_PIXELS for _, _, _, _, d in wrong)
    found = hypothesis_class(result, scene, prims, judged, near, exact)
    if found is not None:
        return found
    if exact:
        kinds = {segment_direction(snapped[k][0], snapped[k][1]) for k, _, _, _, _ in wrong}
        for kind in ("slanted", "diagonal", "vertical", "horizontal"):
            if kind in kinds:
                return f"exact-tie-{kind}-segment", "line-rule"
    overflow = overflow_class(magnitude)
    if overflow is not None:
        return overflow, "none"
    if near:
        return "near-tie", "none"
    at_end = True
    for k, x, y, _, _ in wrong:
        centre = np.array([x + 0.5, y + 0.5])
        ends = snapped[k]
        at_end &= bool(np.any(np.abs(ends - centre).sum(axis=1) <= 1.0))
    if at_end:
        return "end-pixel", "line-rule"
    return "far-from-tie", "line-rule"


def classify_watertight(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    metrics = result.metrics if isinstance(result.metrics, dict) else {}
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    holes, doubles = metrics.get("holes", 0) > 0, metrics.get("double_hits", 0) > 0
    kind = "hole-and-double-hit" if holes and doubles else "hole" if holes else "double-hit" if doubles else "stray"
    scene = case.scene
    blamed = [b for b in evidence.get("blame", []) if isinstance(b, dict)]
    noun = f"{scene.noun}s"
    prims = np.array(sorted({int(t) for b in blamed for t in b.get(noun, []) if 0 <= int(t) < len(scene)}), dtype=np.int64)
    if set(prims.tolist()) & set(scene.non_finite()):
        return "non-finite-input", "none"
    magnitude = magnitude_of(primitive_coordinates(scene, prims)) if prims.size else 1.0
    if case.region is not None:
        magnitude = max(magnitude, magnitude_of([np.asarray(case.region, dtype=np.float64)]))
    overflow = overflow_class(magnitude)
    if overflow is not None:
        return overflow, "none"
    if kind == "stray" or not blamed:
        return kind, "none"
    judged = judged_convention(result, convention)
    start, end, owner = scene.edges()
    facts = []
    for b in blamed:
        edge = b.get("edge")
        if edge:
            a, z = (judged.snap(np.asarray(v, dtype=np.float64))[None] for v in edge)
        else:  # no edge shared by the two nearest: every edge of the primitives named
            mine = np.isin(owner, [int(t) for t in b.get(noun, [])])
            a, z = judged.snap(start[mine]), judged.snap(end[mine])
        x, y = b["pixel"]
        facts.append(edge_facts(a, z, np.array([x + judged.sample[0], y + judged.sample[1]]), magnitude_of([a, z]), scene.width,
                                scene.height))
    twin = evidence.get("lattice_twin")
    if all(f.tie is not None for f in facts) and not (isinstance(twin, dict) and twin.get("fails") is False):
        return kind, "tie-rule"  # (unless the same tie on a lattice is decided right: rounding's)
    if all(f.near or f.tie is not None for f in facts):
        return "near-tie", "none"
    return kind, "none"


def metric_of(result: Any, name: str) -> float:
    metrics = result.metrics if isinstance(result.metrics, dict) else {}
    value = metrics.get(name, 0.0)
    return float(value) if isinstance(value, (int, float)) else 0.0


def _first_positive(result: Any, options: tuple[tuple[str, str], ...], otherwise: str) -> str:
    for metric, name in options:
        if metric_of(result, metric) > 0:
            return name
    return otherwise


def classify_hygiene(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    flaws = (("outside_viewport", "outside-viewport"), ("outside_primitive", "outside-primitive"),
             ("bad_primitive_id", "bad-primitive-id"), ("empty_or_reversed", "empty-or-reversed-span"),
             ("bad_sample", "bad-sample"), ("repeated_pixels", "repeated-pixel"))
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    fallback = "malformed-coverage" if "coverage" in evidence else "bad-attributes" if "attributes" in evidence else "other"
    return _first_positive(result, flaws, fallback), "none"


def classify_degenerate(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    found = _first_positive(result, (("degenerate_triangles_drawn", "zero-area-drawn"), ("nan_attribute_rows", "nan-attributes"),
                                     ("work_ratio", "slow")), "other")
    if found == "zero-area-drawn" and _all_non_finite(result, case):
        return "non-finite-input", "none"  # as conformance and accuracy name the same drawing
    if found == "zero-area-drawn" and _drawn_on_own_edges(result, case, convention):
        return found, "tie-rule"
    return found, "none"


def _all_non_finite(result: Any, case: Any) -> bool:
    """Whether every triangle the degenerate check names has a NaN or infinite coordinate."""
    scene = getattr(case, "scene", None)
    named = result.evidence.get("triangles") if isinstance(result.evidence, dict) else None
    if not TRIANGLES.owns(scene) or not isinstance(named, list) or not named:  # degenerate cases are triangle scenes
        return False
    return set(named) <= set(scene.non_finite())


def _drawn_on_own_edges(result: Any, case: Any, convention: Convention | None) -> bool:
    """Whether every zero-area triangle the degenerate check names is finite and drew only
    samples exactly on its own (snapped) line -- where its three edge functions are all 0
    (:func:`on_flat_line`): an edge test that keeps a sample on an edge on both sides (or
    a kept horizontal edge) draws them, the tie rule's fault rather than a drawing of
    nothing."""
    answer = answer_of(result)
    scene = getattr(case, "scene", None)
    named = result.evidence.get("triangles") if isinstance(result.evidence, dict) else None
    if answer is None or not TRIANGLES.owns(scene) or not isinstance(named, list) or not named:
        return False
    offenders = np.array([int(t) for t in named if isinstance(t, int) and 0 <= t < len(scene)], dtype=np.int64)
    if offenders.size != len(named) or np.isin(offenders, scene.non_finite()).any():
        return False
    judged = judged_convention(result, convention)
    snapped = judged.snap(scene.positions[offenders])
    t, x, y = answer.pixels()
    for k, positions in zip(offenders, snapped):
        mine = t == k
        if not mine.any():
            return False
        samples = np.stack([x[mine] + judged.sample[0], y[mine] + judged.sample[1]], axis=-1).astype(np.float64)
        if not on_flat_line(positions, samples).all():
            return False
    return True


def classify_closed(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    signs = {int(np.sign(p[2])) for p in evidence.get("pixels", []) if isinstance(p, list) and len(p) == 3}
    if signs == {1}:
        return "front-only", "culling"
    if signs == {-1}:
        return "back-only", "culling"
    return "unbalanced", "none"


def classify_invariance(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    order = ("rotate-vertices", "flip-winding", "permute-triangles", "rotate-start-vertex", "reverse-every-contour",
             "reverse-one-contour", "reorder-contours", "permute-paths", "reorder-strips", "split-strips", "translate")
    for name in order:
        if name in evidence:
            return f"changes-under-{name}", "none"
    changed = sorted(k for k in evidence if isinstance(evidence[k], list))
    return (f"changes-under-{changed[0]}", "none") if changed else ("other", "none")


def _fixed(failure_class: str, part: str = "none") -> Callable[[Any, Any, Convention | None], tuple[str, str]]:
    return lambda result, case, convention: (failure_class, part)


def _by_metrics(options: tuple[tuple[str, str], ...], otherwise: str, part: str = "none"
                ) -> Callable[[Any, Any, Convention | None], tuple[str, str]]:
    return lambda result, case, convention: (_first_positive(result, options, otherwise), part)


def _alpha_cause(result: Any) -> tuple[str, str] | None:
    """An accuracy failure's cause named from the facts about its errors
    (:func:`harness.checks.area.alpha_cause`, read again from ``alpha_facts``): truncation,
    coarse levels, a bias, gamma, a sub-pixel shift or drift; None when none holds."""
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    facts = evidence.get("alpha_facts")
    found = alpha_cause(facts) if isinstance(facts, dict) else None
    if found is not None and found[0] == "fill-rule":  # a path's alphas under the other fill rule: the convention's part
        return "fill-rule", "fill-rule"
    return (found[0], "none") if found is not None else None


def _frame_cause(result: Any) -> tuple[str, str] | None:
    """The class and part of a motion failure read through :func:`~harness.diagnose.trials.with_trials`' facts:
    ``input-format`` when the sequence passes as the library receives it
    (``input_precision``), ``snapping`` when its ``snapping_trial`` passed, else its frame
    verdict's (``frame_failure``) when that reads as one; else None."""
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    if "input_precision" in evidence:
        return "input-format", "none"
    trial = evidence.get("snapping_trial")
    if isinstance(trial, dict) and trial.get("passes") is True:
        return "snapping", "snapping"
    return _sub_verdict(result, "frame_failure")


def _sub_verdict(result: Any, key: str) -> tuple[str, str] | None:
    """The class and part of a verdict a trial classified and kept under ``key`` (a dict
    with its ``signature``) of a result's evidence (or of a trial's own dict), when it
    reads as one; else None."""
    evidence = result if isinstance(result, dict) else result.evidence if isinstance(result.evidence, dict) else {}
    found = evidence.get(key)
    signature_key = found.get("signature") if isinstance(found, dict) else None
    if not isinstance(signature_key, str) or signature_key.count("|") != 2:
        return None
    _, failure_class, part = signature_key.split("|")
    return (failure_class, part) if failure_class != "other" else None


def classify_length(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    rows = evidence.get("segments", [])
    off = {int(r.get("drawn", 0)) - int(r.get("rule", 0)) for r in rows if isinstance(r, dict)}
    return ("last-pixel" if off and off <= {1, -1} else "length"), "line-rule"


# the classifiers of the other built-in checks (those above are functions of their own);
# a motion check's own is read after its frame verdict (:func:`signature`, its motion_role)
classify_overdraw = _fixed("double-hit")


classify_holes = _fixed("hole")


classify_jaggy = _by_metrics((("flicker", "flicker"), ("backward_jumps", "backward-jump")), "other")


classify_texel = _by_metrics((("frames_without_attributes", "missing-attributes"), ("swim_backward_steps", "texel-backward-step"),
                              ("texel_mismatches", "texel-mismatch")), "other")


classify_popping = _fixed("popping")


classify_connectivity = _by_metrics((("line_gaps", "gap"), ("line_breaks", "break"), ("line_doubles", "double-step")), "other",
                                    "line-rule")


classify_reversal = _fixed("reversal", "line-rule")


classify_line_motion = _fixed("backward-step", "line-rule")


def classify_perspective(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    if metric_of(result, "max_uv_error_texels") == math.inf:  # u, v not finite: not a perspective error
        return "nan-attributes", "none"
    return _first_positive(result, (("frames_without_attributes", "missing-attributes"),), "perspective-error"), "none"


def classify_accuracy(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    return _alpha_cause(result) or _by_metrics((("over_tolerance", "alpha-error"), ("off_level", "off-level")), "other")(
        result, case, convention)


def classify_seams(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    if isinstance(result.evidence, dict) and isinstance(result.evidence.get("order_dependence"), str):
        return str(result.evidence["order_dependence"]), "none"  # a seam of the edge direction (with_trials)
    return _first_positive(result, (("seam_pixels", "seam"), ("strays", "stray")), "other"), "none"


def classify_triangulation(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    return _sub_verdict(result, "triangles_failure") or _by_metrics(
        (("triangulation_double_hits", "triangulation-double-hit"),), "triangulation-mismatch")(result, case, convention)


def classify_joints(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    joints = (result.evidence or {}).get("joints", [])
    wrong_vertex = any(isinstance(r, dict) and "drawn" in r and r["drawn"] != r.get("rule") for r in joints)
    return ("joint-vertex" if wrong_vertex else "joint-overlap"), "line-rule"
