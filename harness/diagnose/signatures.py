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
``input-format``                 none                the probe found it passes as the library
                                                     receives it (evidence ``input_precision``:
                                                     :func:`with_probes`)
``viewport-edge``                none                the probe found it passes moved into a grown
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
(:func:`with_probes` finds the facts): ``input-format`` when the whole sequence passes as
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
from harness.checks.records import OVERFLOW_EDGES, check_named, frame_checks, motion_checks, overflow_class
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import SNAP_ROUNDINGS, Convention, SnapRounding
from harness.contract.coverage import Coverage
from harness.contract.protocol import convention_for
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.geometry.exact import orientation
from harness.geometry.keys import unique

__all__ = ["Signature", "signature", "CONVENTION_PARTS", "OVERFLOW_EDGES", "overflow_class", "with_probes", "frame_case"]

CONVENTION_PARTS = ("tie-rule", "sample-point", "snapping", "culling", "fill-rule", "line-rule", "none")
# failure classes of attributes missing or wrong: one cause (:attr:`Signature.cause`)
ATTRIBUTE_CLASSES = ("missing-attributes", "bad-attributes", "nan-attributes")
# near-tie: |E| within float32 rounding of the edge function (about 2**-19 M**2 for an
# evaluation in float32 from float32 inputs; four times that), and at most 2**-8 px away
FLOAT32_EDGE_ROUNDING = 2.0**-17
NEAR_PIXELS = 2.0**-8
# viewport-edge: a wrong sample off every edge counts as a clipper's when it lies within
# this of an edge leaving the screen (a clipped vertex rounded to a coarse grid)
CLIPPER_PIXELS = 2.0**-4
# dropped-near-edges: a multisample layer's missing samples all this close to an edge of
# their triangle (a pixel's reach: a tolerance by nature, named as one)
NEAR_EDGE_PIXELS = 1.0

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

    Deterministic, at most five oracle calls (hypothesis tests on the wrong primitives alone), never raises: what it cannot read is ``other``.

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


def with_probes(result: Any, case: Case | MotionCase, judge: Callable[[Case | MotionCase, str], list[Any]], rasterizer: Any) -> Any:
    """The failing ``result`` with the probes' evidence added when they apply: for
    conformance and invariance, ``viewport_edge`` (:func:`harness.diagnose.repro.viewport_edge_probe`:
    the case passes moved into a grown screen; ``viewport_edge_refuted`` when it still
    fails) and ``input_precision`` (:func:`harness.diagnose.repro.input_precision_probe`: it passes
    rounded as the library receives it), ``size_trial`` (:func:`_size_trial`: large wrong
    triangles scaled down), ``tie_trial`` (wrong only exactly on edges: do the
    wrong triangles pass shifted off them? :func:`_tie_trial`); for the motion checks
    (jaggy, texel, perspective, popping), ``input_precision`` as above for the whole
    sequence, else ``frame_failure`` (a frame the failure names, judged alone, fails
    conformance -- or accuracy, for anti-aliased coverage: that failure, probed and
    classified; :func:`_with_frame_failure`), else for texel and perspective
    ``snapping_trial`` (:func:`_snapping_trial`). Each costs a call or two of the
    rasterizer and the check; :func:`signature`
    then reads them as facts instead of guessing. Any other result comes back as it is.
    Never raises."""
    from harness.diagnose.repro import input_precision_probe, viewport_edge_trial

    try:
        if getattr(result, "status", None) == "fail" and result.check in motion_checks() and isinstance(case, MotionCase):
            return _with_frame_failure(result, case, judge, rasterizer)
        if getattr(result, "status", None) == "fail" and result.check == "seams" and isinstance(case, Case):
            return _with_order_dependence(result, case, judge)
        if getattr(result, "status", None) == "fail" and result.check == "triangulation" and isinstance(case, Case):
            return _with_triangles_failure(result, case, judge, rasterizer)
        if getattr(result, "status", None) == "fail" and result.check == "watertight" and isinstance(case, Case):
            return _with_lattice_twin(result, case, judge, convention_for(rasterizer, case.scene))
        if getattr(result, "status", None) != "fail" or result.check not in ("conformance", "invariance") or not isinstance(case, Case):
            return result
        evidence = dict(result.evidence)
        if "input_precision" not in evidence:
            found = input_precision_probe(case, result.check, judge, rasterizer)
            if found is not None:
                evidence["input_precision"] = found
        if "viewport_edge" not in evidence and "input_precision" not in evidence:
            trial = viewport_edge_trial(case, result.check, judge)
            if trial is not None:
                # it passes on a grown screen: the edge's fault; it still fails: not the edge's
                evidence["viewport_edge" if trial.pop("passes") else "viewport_edge_refuted"] = trial
        if "tie_trial" not in evidence and "input_precision" not in evidence:
            tie = _tie_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if tie is not None:
                evidence["tie_trial"] = tie
        if "size_trial" not in evidence and "input_precision" not in evidence:
            size = _size_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if size is not None:
                evidence["size_trial"] = size
        if "dropped_trial" not in evidence and "input_precision" not in evidence \
                and not evidence.get("size_trial", {}).get("passes"):
            dropped = _dropped_trial(result, case, judge, convention_for(rasterizer, case.scene))
            if dropped is not None:
                evidence["dropped_trial"] = dropped
        return replace(result, evidence=evidence)
    except Exception:
        return result


# the tie trial's shift: dyadic, well beyond float rounding, and off every line of small
# denominator through a sample (a shifted edge holding a sample again is as rare as a generic one)
TIE_SHIFT = (1 / 64 + 1 / 4096, 1 / 128 + 1 / 65536)
# under snapping to 1/2**bits px, three shifts of whole grid steps, no two parallel: a
# snapped shift runs along the edges of its own slope and keeps their samples on them, or
# moves an edge by exactly one row of samples (a (47, 7) edge under (3, -5)/256), so the
# tie stands when each wrong triangle passes both ways under one of them
TIE_GRID_SHIFTS = ((5, 3), (-3, 5), (7, -2))


def _tie_shifts(convention: Convention) -> list[tuple[float, float]]:
    """The shifts the tie trial tries (:data:`TIE_SHIFT`, or :data:`TIE_GRID_SHIFTS` in
    steps of the convention's snapping grid)."""
    if convention.subpixel_bits is None:
        return [TIE_SHIFT]
    step = 2.0 ** -convention.subpixel_bits
    return [(a * step, b * step) for a, b in TIE_GRID_SHIFTS]


def _tie_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]], convention: Convention | None
               ) -> dict[str, Any] | None:
    """Whether a conformance failure whose wrong samples all lie exactly on edges is the
    tie rule's: the wrong triangles alone, shifted one way and the other (every such
    sample then strictly inside or outside), pass strictly both times -- each triangle
    under one of :func:`_tie_shifts` at least (a shift parallel to one triangle's edge
    keeps its samples on it). A missing prestep or a dropped sliver that merely put its wrong
    samples on edges still fails. Two calls per shift; None when it does not apply
    (triangles only)."""
    scene = case.scene
    if result.check != "conformance" or convention is None:
        return None
    if isinstance(scene, PathScene):
        return _vertex_row_trial(result, case, judge, convention)
    if not isinstance(scene, Scene):
        return None
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    if not wrong or any(p.get("distance") != 0.0 or not isinstance(p.get("triangle"), int) for p in wrong):
        return None
    subset = scene.subset(np.array(sorted({int(p["triangle"]) for p in wrong}), dtype=np.int64))
    if not np.isfinite(subset.coordinates).all():
        return None
    tried = []
    unexplained = set(range(len(subset)))  # wrong triangles no shift has yet cleared
    for shift in _tie_shifts(convention):
        failing: set[int] = set()
        for sign in (1.0, -1.0):
            shifted = subset.with_coordinates(subset.coordinates + sign * np.array(shift))
            results = judge(Case(f"{case.id}/tie-shift/{'+' if sign > 0 else '-'}", shifted, lattice=True), "conformance")
            failing |= _failing_triangles(results, len(subset))
        tried.append(list(shift))
        if not failing:
            return {"shift": list(shift), "tried": tried, "passes": True}
        # a shift runs along the edges of its own slope: each triangle needs one that clears it
        unexplained &= failing
        if not unexplained:
            return {"shift": list(shift), "tried": tried, "passes": True}
    return {"shift": tried[-1], "tried": tried, "passes": False}


def _vertex_row_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                      convention: Convention) -> dict[str, Any] | None:
    """The tie trial for paths whose wrong samples all lie exactly on their edges or on rows
    through one of their path's vertices (where the crossings' count is the tie rule's):
    the wrong paths alone, shifted one way and the other by :data:`TIE_SHIFT` (no sample
    then lies on an edge or meets a vertex's row), pass both times -- else those samples
    were wrong there by chance and the fill is. Two calls; None when it does not apply
    (under snapping the shift would snap away)."""
    scene = case.scene
    if convention.subpixel_bits is not None or not isinstance(scene, PathScene):
        return None
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    if not wrong or any(not isinstance(p.get("path"), int) or not 0 <= p["path"] < len(scene) for p in wrong):
        return None
    sy = convention.sample[1]
    if not all(p.get("distance") == 0.0 or any(np.any(c[:, 1] == p["y"] + sy) for c in scene.contours_of(int(p["path"])))
               for p in wrong):
        return None  # some wrong sample neither on an edge nor on a vertex's row: no tie
    subset = scene.subset(np.array(sorted({int(p["path"]) for p in wrong}), dtype=np.int64))
    if not np.isfinite(subset.coordinates).all():
        return None
    shift = np.array(TIE_SHIFT)
    for sign in (1.0, -1.0):
        shifted = subset.with_coordinates(subset.coordinates + sign * shift)
        verdicts = judge(Case(f"{case.id}/tie-shift/{'+' if sign > 0 else '-'}", shifted, lattice=True), "conformance")
        if not verdicts or any(r.status == "fail" for r in verdicts):
            return {"shift": list(TIE_SHIFT), "tried": [list(TIE_SHIFT)], "passes": False, "vertex_rows": True}
    return {"shift": list(TIE_SHIFT), "tried": [list(TIE_SHIFT)], "passes": True, "vertex_rows": True}


def _failing_triangles(results: list[Any], n: int) -> set[int]:
    """The triangles (of n) a conformance verdict finds wrong: all n when there is no pass
    and the evidence does not list every wrong sample (or names none)."""
    if results and all(r.status in ("pass", "skip") for r in results):
        return set()
    failed = [r for r in results if r.status == "fail"]
    if len(failed) != 1:
        return set(range(n))
    pixels = [p for p in failed[0].evidence.get("pixels", []) if isinstance(p, dict) and not p.get("near_tie")]
    named = {int(p["triangle"]) for p in pixels if isinstance(p.get("triangle"), int)}
    if not named or _metric(failed[0], "wrong") > len(pixels):
        return set(range(n))
    return named


# the dropped trial's copies: each missing triangle moved by (i/4, j/4) px, i, j in 0..3
# (plus the tie trial's first shift)
DROPPED_SHIFTS = tuple((i / 4, j / 4) for j in range(4) for i in range(4))


def _dropped_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                   convention: Convention | None) -> dict[str, Any] | None:
    """Whether triangles missing whole are dropped as such, culled, or missed by another
    bug: the missing triangles, each in 16 copies moved by quarter pixels
    (:data:`DROPPED_SHIFTS`), 16 more of the other winding (two vertices swapped) and 32
    of the same winding started at its other vertices, drawn in one call. A dropper (too
    small) draws none of the copies the oracle covers; a culler draws the other winding's
    only, right; a wrong sample point or edge test that missed a sliver's only sample draws
    some of the same winding; an open outline draws some orders. Returns ``{"copies": n,
    "drawn": k, "flipped_copies": m, "flipped_drawn": j, "flipped_right": r,
    "rotated_copies": q, "rotated_drawn": i}`` (copies the oracle covers, of them those the
    rasterizer drew something of, and of the other winding's those it drew exactly right:
    a culler's), ``open_contour`` (another order drawn: all drawn exactly as with each
    triangle's closing edge left out, :func:`_open_outline`), and ``grown``
    (:func:`_grown_trial`) when none is drawn, the triangles are not culled and not so
    explained; None when it does not apply (triangles missing whole, near ties aside, finite)."""
    from harness.oracle.coverage import exact_coverage

    scene = case.scene
    answer = _answer(result)
    if result.check != "conformance" or convention is None or answer is None:
        return None
    if isinstance(scene, PathScene):
        return _path_orders_trial(result, case, judge, convention, answer)
    if not isinstance(scene, Scene):
        return None
    prims = _missing_whole(result, answer, "triangle")
    if prims is None:
        return None
    subset = scene.subset(prims)
    if not np.isfinite(subset.positions).all():
        return None
    # the same triangle as given, of the other winding, and of its winding started at its
    # second and third vertex: 16 copies each
    orders = ([0, 1, 2], [0, 2, 1], [1, 2, 0], [2, 0, 1])
    copies_of = len(DROPPED_SHIFTS) * len(subset)
    # off the quarter-pixel grid by the tie trial's shift: a sliver whose samples all lie on its
    # edges (a horizontal edge on a sample row) covers samples strictly inside in some copy
    shifts = np.repeat(np.array(DROPPED_SHIFTS) + np.array(_tie_shifts(convention)[0]), len(subset), axis=0)[:, None, :]

    def tiled(a: NDArray | None) -> NDArray | None:
        return None if a is None else np.concatenate([np.concatenate([a[:, order]] * len(DROPPED_SHIFTS)) for order in orders])
    positions = tiled(subset.positions) + np.concatenate([shifts] * len(orders))
    copies = Scene(scene.width, scene.height, positions, tiled(subset.attributes), tiled(subset.w))
    n = len(copies)
    oracle = exact_coverage(copies, convention)
    want = np.bincount(oracle.pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/dropped-copies", copies, lattice=True), "conformance")
                if r.check == "conformance"]
    if not verdicts:
        return None
    if verdicts[0].status == "pass":
        got, right = want, want
    elif (drawn := _answer(verdicts[0])) is not None:
        pixels = drawn.pixels()[0]
        got = np.bincount(pixels[(pixels >= 0) & (pixels < n)], minlength=n)[:n] > 0
        right = want & _drawn_exactly(drawn, oracle, n, scene.width, scene.height)
    else:
        return None
    same, flipped, rotated = slice(0, copies_of), slice(copies_of, 2 * copies_of), slice(2 * copies_of, n)
    found: dict[str, Any] = {"copies": int(want[same].sum()), "drawn": int((want & got)[same].sum()),
                             "flipped_copies": int(want[flipped].sum()), "flipped_drawn": int((want & got)[flipped].sum()),
                             "flipped_right": int(right[flipped].sum()),
                             "rotated_copies": int(want[rotated].sum()), "rotated_drawn": int((want & got)[rotated].sum())}
    # a culler draws the other winding right, and its own from no vertex
    culled = found["flipped_drawn"] > 0 and found["flipped_right"] == found["flipped_drawn"] and not found["rotated_drawn"]
    if (found["flipped_drawn"] or found["rotated_drawn"]) and verdicts[0].status == "fail" and drawn is not None:
        # another order drawn: as with each triangle's closing edge left out (it runs
        # between two other vertices now), and not as a culler draws it (the other winding right)?
        found["open_contour"] = _open_outline(drawn, copies, np.arange(n), convention,
                                              lambda right: {f for f in right if copies_of <= f[0] < 2 * copies_of})
    if found["copies"] and not found["drawn"] and not culled and not found.get("open_contour"):
        grown = _grown_trial(subset, case, judge, convention)
        if grown is not None:
            found["grown"] = grown
    return found


# the size trial: wrong triangles at least this long (px, their bounding box's longer
# side) and below the overflow classes (2**12) are tried scaled down under it
SIZE_TRIAL_EXTENT = 64.0


def _size_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                convention: Convention | None) -> dict[str, Any] | None:
    """Whether triangles wrong at their size are right made smaller: a range that gives out
    early -- int32 edge functions of 8-bit fixed point wrap from about 181 px, long before
    any coordinate reaches the overflow classes' 2**12 -- rather than a convention part's
    error, which shows at any size. Each wrong triangle (near ties aside) at least
    :data:`SIZE_TRIAL_EXTENT` px long and under 2**12 px from the origin is scaled by the
    power of two bringing it under that length, moved by whole pixels to the screen's
    centre, in 16 copies moved by quarter pixels (:data:`DROPPED_SHIFTS`) and 16 more made
    :data:`GROWN_THICKNESS` px thick (:func:`_thickened`: a sliver scaled down covers
    few samples), judged in one call. Returns ``{"scales": [...], "shaped": m,
    "shaped_right": j, "copies": n, "right": k, "passes": bool}`` (copies the oracle
    covers, of them those drawn exactly right, in shape and thick; passes when every one
    is right, one in shape and four thick at least -- a dropper of small areas drops the
    ones in shape); None when it does not apply."""
    from harness.oracle.coverage import exact_coverage

    scene = case.scene
    if result.check != "conformance" or convention is None or not isinstance(scene, Scene):
        return None
    wrong = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict) and isinstance(p.get("triangle"), int)
             and not p.get("near_tie")]
    if not wrong:
        return None
    prims = np.array(sorted({int(p["triangle"]) for p in wrong}), dtype=np.int64)
    subset = scene.subset(prims)
    positions = subset.positions
    if not np.isfinite(positions).all() or np.abs(positions).max(initial=0.0) >= 2.0**OVERFLOW_EDGES[0]:
        return None
    extent = (positions.max(axis=1) - positions.min(axis=1)).max(axis=1)
    if not (extent >= SIZE_TRIAL_EXTENT).all():
        return None  # a small one wrong too: not (only) its size
    scales = 2.0 ** -(np.floor(np.log2(extent / SIZE_TRIAL_EXTENT)) + 1)  # under it, by a power of two
    # about its centroid's pixel, moved by whole pixels to the screen's centre, made thick
    # as a grown copy (a sliver scaled down covers no sample)
    centroid = np.floor(positions.mean(axis=1, keepdims=True))
    centre = np.array([scene.width // 2, scene.height // 2], dtype=np.float64)
    smaller = centre + (positions - centroid) * scales[:, None, None]
    # each in its shape and made thick: a dropper of small areas drops the first, and a
    # sliver's first may cover no sample
    shifts = np.repeat(np.array(DROPPED_SHIFTS), len(subset), axis=0)[:, None, :]
    tile = lambda a: None if a is None else np.concatenate([a] * len(DROPPED_SHIFTS) * 2)  # noqa: E731
    both = np.concatenate([np.concatenate([smaller] * len(DROPPED_SHIFTS)) + shifts,
                           np.concatenate([_thickened(smaller, GROWN_THICKNESS)] * len(DROPPED_SHIFTS)) + shifts])
    copies = Scene(scene.width, scene.height, both, tile(subset.attributes), tile(subset.w))
    n = len(copies)
    oracle = exact_coverage(copies, convention)
    want = np.bincount(oracle.pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/smaller", copies, lattice=True), "conformance") if r.check == "conformance"]
    if not verdicts:
        return None
    if verdicts[0].status == "pass":
        right = want
    elif (drawn := _answer(verdicts[0])) is not None:
        right = want & _drawn_exactly(drawn, oracle, n, scene.width, scene.height)
    else:
        return None
    shaped, thick = slice(0, n // 2), slice(n // 2, n)
    found: dict[str, Any] = {"scales": scales.tolist(), "shaped": int(want[shaped].sum()), "shaped_right": int(right[shaped].sum()),
                             "copies": int(want[thick].sum()), "right": int(right[thick].sum())}
    found["passes"] = found["copies"] >= 4 and found["right"] == found["copies"] \
        and found["shaped"] >= 1 and found["shaped_right"] == found["shaped"]
    return found


def _missing_whole(result: Any, answer: Coverage, noun: str) -> NDArray[np.int64] | None:
    """The primitives (``noun``: triangle or path) a conformance failure finds wrong, when
    every wrong deviation -- near ties excused, as the classes read them -- is a missing
    fragment of a primitive the answer draws nothing of; else None."""
    listed = [p for p in result.evidence.get("pixels", []) if isinstance(p, dict)]
    wrong = [p for p in listed if not p.get("near_tie")] or listed
    if not wrong or any(p.get("kind") != "missing" or not isinstance(p.get(noun), int) for p in wrong):
        return None
    prims = np.array(sorted({int(p[noun]) for p in wrong}), dtype=np.int64)
    return None if np.isin(answer.pixels()[0], prims).any() else prims  # drawn in part: not missing whole


def _path_orders_trial(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                       convention: Convention, answer: Coverage) -> dict[str, Any] | None:
    """The dropped trial of paths missing whole (near ties aside): the same paths with
    every contour started at its second and at its third vertex, drawn in one call with
    the paths as given. A dropper draws none; an open outline (:func:`_open_outline`) draws
    some, all exactly as it predicts. Returns ``{"rotated_copies": n, "rotated_drawn": k, "open_contour": bool}``
    (copies the oracle covers, those drawn something of), None when it does not apply."""
    from harness.oracle.coverage import exact_coverage

    scene = case.scene
    prims = _missing_whole(result, answer, "path")
    if prims is None:
        return None
    subset = scene.subset(prims)
    if not isinstance(subset, PathScene) or not np.isfinite(subset.vertices).all():
        return None
    starts = np.concatenate([[0], np.cumsum(subset.contour_sizes)])
    contours = [subset.vertices[a:b] for a, b in zip(starts[:-1], starts[1:])]
    rotations = (0, 1, 2)  # with the paths as given: missing, as the hypothesis must predict too
    vertices = np.concatenate([np.roll(c, -r, axis=0) for r in rotations for c in contours])
    owner = np.concatenate([subset.contour_path + k * len(subset) for k in range(len(rotations))])
    copies = PathScene(scene.width, scene.height, vertices, np.tile(subset.contour_sizes, len(rotations)), owner,
                       subset.fill_rule)
    n = len(copies)
    want = np.bincount(exact_coverage(copies, convention).pixels()[0], minlength=n)[:n] > 0
    verdicts = [r for r in judge(Case(f"{case.id}/other-orders", copies, lattice=True), "conformance")
                if r.check == "conformance"]
    if not verdicts:
        return None
    got = None if verdicts[0].status == "pass" else _answer(verdicts[0])
    if got is None and verdicts[0].status != "pass":
        return None
    pixels = got.pixels()[0] if got is not None else np.zeros(0, dtype=np.int64)
    drawn = want if got is None else np.bincount(pixels[(pixels >= 0) & (pixels < n)], minlength=n)[:n] > 0
    rotated = slice(len(subset), n)
    found: dict[str, Any] = {"rotated_copies": int(want[rotated].sum()), "rotated_drawn": int((want & drawn)[rotated].sum())}
    found["open_contour"] = got is not None and bool(found["rotated_drawn"]) and _open_outline(got, copies, np.arange(n), convention)
    return found


def _drawn_exactly(answer: Coverage, oracle: Coverage, n: int, width: int, height: int) -> NDArray[np.bool_]:
    """(n,) bool: the primitives whose fragments in the viewport are exactly the oracle's."""
    def keys(coverage: Coverage) -> NDArray[np.int64]:
        t, x, y = coverage.pixels()
        keep = (t >= 0) & (t < n) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
        return np.unique((t[keep] * height + y[keep]) * width + x[keep])
    differ = np.setxor1d(keys(answer), keys(oracle), assume_unique=True) // (width * height)
    return np.bincount(differ, minlength=n)[:n] == 0


def _thickened(p: NDArray[np.float64], thickness: float) -> NDArray[np.float64]:
    """(N, 3, 2) triangles with each far vertex moved away from its longest edge until
    the triangle is at least ``thickness`` px thick there (its winding kept; a flat one's
    far vertex goes to the edge's left)."""
    p = p.copy()
    with np.errstate(all="ignore"):
        sides = p[:, [1, 2, 0]] - p
        rows = np.arange(len(p))
        k = np.hypot(sides[..., 0], sides[..., 1]).argmax(axis=1)
        a, b, c = p[rows, k], p[rows, (k + 1) % 3], p[rows, (k + 2) % 3]
        d = b - a
        length = np.hypot(d[:, 0], d[:, 1])
        cross = d[:, 0] * (c[:, 1] - a[:, 1]) - d[:, 1] * (c[:, 0] - a[:, 0])
        side = np.where(cross < 0, -1.0, 1.0)
        normal = np.stack([-d[:, 1], d[:, 0]], axis=-1) / length[:, None] * side[:, None]
        p[rows, (k + 2) % 3] = c + normal * np.maximum(thickness - np.abs(cross) / length, 0.0)[:, None]
    return p


# the grown trial: each never-drawn triangle made this many pixels thick and long
GROWN_THICKNESS = 3.0


def _grown_trial(subset: Scene, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                 convention: Convention) -> dict[str, Any] | None:
    """Whether triangles never drawn at any small move (the dropped trial) are dropped for
    their size or missed by the bug seen elsewhere: each grown -- scaled about its centroid
    by a power of two until its longest edge is :data:`GROWN_THICKNESS` pixels long, then
    its far vertex moved away from that edge until it is as thick -- in the same screen,
    judged once. A dropper (too small) draws the grown copies right; an edge test that
    starts spans a column late, or samples off the pixel, draws them wrong -- that failure,
    classified here, names the cause. Returns ``{"scales": [...], "drawn": k, "passes":
    bool, "signature": key}`` (the signature when it fails), None when it does not apply."""
    p = subset.positions
    if not np.isfinite(p).all() or np.abs(p).max(initial=0.0) > 2.0**20:
        return None
    with np.errstate(all="ignore"):
        sides = p[:, [1, 2, 0]] - p
        longest = np.hypot(sides[..., 0], sides[..., 1]).max(axis=1)
        if not (longest > 0).all():
            return None
        scales = 2.0 ** np.ceil(np.log2(np.maximum(GROWN_THICKNESS / longest, 1.0)))
        centroid = p.mean(axis=1, keepdims=True)
        grown = _thickened(centroid + (p - centroid) * scales[:, None, None], GROWN_THICKNESS)
    if not np.isfinite(grown).all():
        return None
    grown_case = Case(f"{case.id}/grown", subset.with_coordinates(grown))
    verdicts = [r for r in judge(grown_case, "conformance") if r.check == "conformance"]
    if not verdicts:
        return None
    found: dict[str, Any] = {"scales": scales.tolist(), "passes": verdicts[0].status == "pass"}
    answer = _answer(verdicts[0])
    drawn = answer.pixels()[0] if answer is not None else np.zeros(0, dtype=np.int64)
    found["drawn"] = len(grown) if found["passes"] else int(np.unique(drawn[(drawn >= 0) & (drawn < len(grown))]).size)
    if verdicts[0].status == "fail":
        found["signature"] = signature(verdicts[0], grown_case, convention).key
    return found


# the invariance variants that reverse the direction in which a triangle runs along its
# edges: a coverage that changes under them differs on the two sides of a shared edge
EDGE_DIRECTION_VARIANTS = ("flip-winding", "rotate-vertices")


def _with_order_dependence(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]]) -> Any:
    """A failing seams result with ``order_dependence`` added when the same case fails
    invariance under a variant of :data:`EDGE_DIRECTION_VARIANTS`: two triangles run along
    their shared edge in opposite directions, so a coverage that depends on the direction
    leaves a seam there -- the seam is that dependence, one cause with the invariance
    failure. One call."""
    evidence = dict(result.evidence)
    if "order_dependence" in evidence:
        return result
    for verdict in judge(case, "invariance"):
        if verdict.status == "fail" and verdict.check == "invariance":
            found, _ = classify_invariance(verdict, case, None)
            if found.removeprefix("changes-under-") in EDGE_DIRECTION_VARIANTS:
                evidence["order_dependence"] = found
                return replace(result, evidence=evidence)
    return result


# the lattice twin's edge: the shared edge's direction as a ratio of integers up to this
LATTICE_TWIN_DENOMINATOR = 16


def _with_lattice_twin(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                       convention: Convention | None) -> Any:
    """A failing watertight result of a float partition whose holes and double hits all lie
    exactly on shared edges, with ``lattice_twin`` added: whether the same tie, rebuilt on a
    lattice (two triangles sharing an edge of the same direction -- as a ratio of small
    integers -- through a sample, in each vertex rotation and both windings: float
    arithmetic exact there), fails too. It does: the tie rule's fault. It never does: the
    float case's rounding decided the tie (float32 edge functions), a near tie that merely
    fell exactly on the edge. Up to six calls of the rasterizer and the check."""
    evidence = dict(result.evidence)
    if case.lattice or "lattice_twin" in evidence or classify_watertight(result, case, convention)[1] != "tie-rule":
        return result
    judged = _judged_convention(result, convention)
    edges: list[Any] = [b["edge"] for b in evidence.get("blame", []) if isinstance(b, dict) and b.get("edge")]
    if not edges or isinstance(case.scene, PathScene):
        return result
    a, b = (judged.snap(np.asarray(v, dtype=np.float64)) for v in edges[0])
    step, twins = _lattice_twins(b - a, judged)
    if not twins:
        return result
    fails = False
    for twin in twins:
        verdicts = [r for r in judge(twin, "watertight") if r.check == "watertight"]
        if verdicts and verdicts[0].status == "fail":
            fails = True
            break
    evidence["lattice_twin"] = {"direction": step.tolist(), "fails": fails}
    return replace(result, evidence=evidence)


def _lattice_twins(direction: NDArray, judged: Convention) -> tuple[NDArray, list[Case]]:
    """Two triangles sharing an edge of ``direction`` (its slope as a ratio of integers up
    to :data:`LATTICE_TWIN_DENOMINATOR`, its signs kept) whose midpoint is a sample, in a
    48-pixel screen: one case per vertex rotation and winding, each a planar partition (its
    region the rhombus they make), and the edge's lattice direction. No case when the
    direction is not finite or zero, or the snapping grid cannot hold the twin."""
    from fractions import Fraction

    dx, dy = float(direction[0]), float(direction[1])
    if not (math.isfinite(dx) and math.isfinite(dy)) or dx == dy == 0.0:
        return np.zeros(2), []
    if dx == 0.0 or dy == 0.0:
        step = np.array([math.copysign(2.0, dx) if dx else 0.0, math.copysign(2.0, dy) if dy else 0.0])
    else:
        slope = Fraction(abs(dy) / abs(dx)).limit_denominator(LATTICE_TWIN_DENOMINATOR)
        if slope == 0 or slope.numerator > LATTICE_TWIN_DENOMINATOR:
            slope = Fraction(1, LATTICE_TWIN_DENOMINATOR) if slope == 0 else Fraction(LATTICE_TWIN_DENOMINATOR, 1)
        step = np.array([math.copysign(slope.denominator, dx), math.copysign(slope.numerator, dy)])
    sample = np.array([24.0 + judged.sample[0], 24.0 + judged.sample[1]])
    normal = np.array([-step[1], step[0]])
    a, b, left, right = sample - step, sample + step, sample + normal, sample - normal
    if not np.array_equal(judged.snap(np.stack([a, b, left, right])), np.stack([a, b, left, right])):
        return step, []  # the snapping grid is coarser than the sample's offset: no exact twin
    region = np.stack([a, left, b, right])
    cases = []
    for flip in (False, True):
        pair = np.array([[a, b, left], [b, a, right]])
        if flip:
            pair = pair[:, [0, 2, 1]]
        for turn in range(3):
            rotated = np.roll(pair, turn, axis=1)
            cases.append(Case(f"lattice-twin/{'flipped' if flip else 'kept'}/{turn}", Scene(48, 48, rotated),
                              lattice=True, region=region))
    return step, cases


def _with_triangles_failure(result: Any, case: Case, judge: Callable[[Case | MotionCase, str], list[Any]],
                            rasterizer: Any) -> Any:
    """A failing triangulation result with ``triangles_failure`` added when the paths'
    triangulation, drawn as triangles, fails conformance itself: the mismatch is that
    failure's (a tie rule wrong on the triangles' flat edges), probed and classified. One
    call (more for that failure's probes)."""
    from harness.checks.paths import triangulated

    evidence = dict(result.evidence)
    made = triangulated(case.scene) if isinstance(case.scene, PathScene) and "triangles_failure" not in evidence else None
    if made is None:
        return result
    triangles = Case(f"{case.id}/triangulated", made[0], lattice=True)  # strict: the check excuses no near tie
    failed = [r for r in judge(triangles, "conformance") if r.status == "fail" and r.check == "conformance"]
    if not failed:
        return result
    probed = with_probes(failed[0], triangles, judge, rasterizer)
    named = signature(probed, triangles, convention_for(rasterizer, triangles.scene))
    evidence["triangles_failure"] = {"message": probed.message, "signature": named.key}
    return replace(result, evidence=evidence)


def frame_case(case: MotionCase, frame: int) -> Case:
    """Frame ``frame`` (0-based) of a motion sequence as a still case, judged as the jaggy
    check judges frames: every deviation from the oracle counts, none excused as a near
    tie (``lattice``: conformance's strict reading)."""
    return Case(f"{case.id}/frame/{frame}", case.frames[frame], lattice=True)


# the motion checks whose failures are read through a frame's still verdict, and those
# verdicts (conformance for aliased coverage, accuracy for anti-aliased: one applies) are
# the registry's: :func:`harness.checks.records.motion_checks`, :func:`~harness.checks.records.frame_checks`
# frames judged alone per failing motion result, at most
FRAMES_TRIED = 3


def _named_frames(result: Any) -> list[int]:
    """The frames (0-based) a failing motion result names, in its evidence's order: the
    frames off the oracle (jaggy), of texel mismatches and backward steps (texel; a step
    names its frame and the one before), of the worst u, v error (perspective), of the
    worst alpha steps (popping); at most :data:`FRAMES_TRIED`."""
    evidence = result.evidence if isinstance(result.evidence, dict) else {}
    frames: list[int] = []
    if result.check == "jaggy":
        frames += [int(f) for f in evidence.get("oracle_mismatch_frames") or []][:1]
    for key, step in (("mismatches", False), ("backward_steps", True), ("steps", True)):
        for row in evidence.get(key) or []:
            if isinstance(row, dict) and isinstance(row.get("frame"), int):
                frames += [row["frame"], row["frame"] - 1] if step else [row["frame"]]
    worst = evidence.get("worst")
    if isinstance(worst, dict) and isinstance(worst.get("frame"), int):
        frames.append(worst["frame"])
    return list(dict.fromkeys(f for f in frames if f >= 0))[:FRAMES_TRIED]


def _with_frame_failure(result: Any, case: MotionCase, judge: Callable[[Case | MotionCase, str], list[Any]], rasterizer: Any) -> Any:
    """A failing motion result with ``frame_failure`` added: the first of its named frames
    (:func:`_named_frames`) that fails conformance (or accuracy) judged alone, that failure
    probed -- so a flicker, a swimming texel or a pop caused by a wrong tie rule, snapping
    or alpha is named by that cause. A call per frame tried."""
    from harness.diagnose.repro import input_precision_probe

    evidence = dict(result.evidence)
    if "frame_failure" in evidence or "input_precision" in evidence or "snapping_trial" in evidence:
        return result
    found = input_precision_probe(case, result.check, judge, rasterizer)
    if found is not None:  # the whole sequence passes as the library receives it
        evidence["input_precision"] = found
        return replace(result, evidence=evidence)
    for frame in _named_frames(result):
        if frame >= len(case.frames):
            continue
        still = frame_case(case, frame)
        for check in frame_checks():
            verdicts = judge(still, check)
            failed = [r for r in verdicts if r.status == "fail"]
            if failed:
                probed = with_probes(failed[0], still, judge, rasterizer)
                # classified here, where the frame's answer is at hand (the snapping and
                # fill-rule hypotheses compare it)
                named = signature(probed, still, convention_for(rasterizer, still.scene))
                evidence["frame_failure"] = {"frame": frame, "check": check, "message": probed.message,
                                             "signature": named.key, "metrics": dict(probed.metrics),
                                             "evidence": dict(probed.evidence)}
                return replace(result, evidence=evidence)
            if any(r.status == "pass" for r in verdicts):
                break  # this frame passes its verdict: try the next
    trial = _snapping_trial(result, case, convention_for(rasterizer, case.frames[0]))
    if trial is not None:
        evidence["snapping_trial"] = trial
        return replace(result, evidence=evidence)
    return result


def _snapping_trial(result: Any, case: MotionCase, convention: Convention | None) -> dict[str, Any] | None:
    """For a texel or perspective failure whose frames all pass conformance, under a
    snapping convention: the other roundings that move a vertex (fewest moved first), the
    check run again on the same answers against that rounding's exact oracles. The first
    under which it passes (``{"rounding": ..., "passes": True}``): the u, v came from vertices
    snapped that way -- the snapping's fault, which the coverage did not show. None when
    none passes or it does not apply. No rasterizer call: an oracle per frame per rounding."""
    from harness.checks.motion import perspective, texel_swimming
    from harness.oracle.coverage import exact_coverage

    if result.check not in ("texel", "perspective") or convention is None or convention.subpixel_bits is None:
        return None
    coverages = list(getattr(getattr(result, "drawing", None), "coverages", None) or [])
    frames = list(case.frames)
    if len(coverages) != len(frames) or not all(isinstance(f, Scene) and np.isfinite(f.positions).all() for f in frames):
        return None
    positions = np.concatenate([f.positions for f in frames])
    declared = convention.snap(positions)
    others = []
    for rounding in SNAP_ROUNDINGS:
        moved = int(np.sum(replace(convention, snap_rounding=rounding).snap(positions) != declared))
        if rounding != convention.snap_rounding and moved:
            others.append((moved, rounding))
    for _, rounding in sorted(others):
        other = replace(convention, snap_rounding=rounding)
        oracles = [exact_coverage(f, other) for f in frames]
        again = (texel_swimming(case.id, coverages, oracles, case.texels or 1) if result.check == "texel"
                 else perspective(case.id, coverages, oracles, case.texels or 1))
        if again.status == "pass":
            return {"rounding": rounding, "passes": True}
    return None


# -- errors ----------------------------------------------------------------------------------

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


# -- shared facts ----------------------------------------------------------------------------


def _judged_convention(result: Any, convention: Convention | None) -> Convention:
    """The single-sample convention the failing samples were judged by: the drawing's
    (a multisample result's worst layer), else the evidence's sample of ``convention``,
    else ``convention``, else the default."""
    drawing = getattr(result, "drawing", None)
    judged = getattr(drawing, "convention", None)
    if isinstance(judged, Convention) and judged.model.single_sample:
        return judged
    if isinstance(convention, Convention):
        index = result.evidence.get("sample") if isinstance(result.evidence, dict) else None
        if convention.model.sample_ids and isinstance(index, int) and 0 <= index < convention.n_samples:
            return convention.at_sample(index)
        if convention.model.single_sample:
            return convention
        return replace(convention, samples=None, coverage="sample", levels=256, tolerance=None)
    return Convention()


def _answer(result: Any) -> Coverage | None:
    """The rasterizer's (tidied) answer on the still case, when the result carries it."""
    drawing = getattr(result, "drawing", None)
    coverages = getattr(drawing, "coverages", None)
    if coverages and isinstance(coverages[0], Coverage):
        return coverages[0]
    return None


def _primitive_coordinates(scene: AnyScene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    """Each primitive's coordinates, (K, 2) each (a path's every contour together)."""
    if isinstance(scene, Scene):
        return [scene.positions[k] for k in prims]
    if isinstance(scene, LineScene):
        a, b = scene.segments()
        return [np.stack([a[k], b[k]]) for k in prims]
    if isinstance(scene, PathScene):
        return [np.concatenate(scene.contours_of(int(k))) for k in prims]
    return []


def _magnitude(coordinates: list[NDArray[np.float64]]) -> float:
    """max(1, largest finite |coordinate|) of the primitives."""
    biggest = 1.0
    for c in coordinates:
        finite = np.abs(c[np.isfinite(c)])
        if finite.size:
            biggest = max(biggest, float(finite.max()))
    return biggest


def _direction(a: NDArray, b: NDArray) -> str:
    """horizontal, vertical or slanted, of the edge a -> b (float comparisons: exact)."""
    if a[1] == b[1]:
        return "horizontal"
    if a[0] == b[0]:
        return "vertical"
    return "slanted"


@dataclass
class _Sample:
    """What is known about one wrong sample."""

    tie: str | None  # "vertex", "horizontal", "vertical", "slanted" (exactly on it), else None
    near: bool  # within float rounding of an edge (and not exactly on one)
    border: bool  # the edge it lies on (or, beyond float rounding, within CLIPPER_PIXELS of) leaves the viewport


def _edge_facts(edges_a: NDArray, edges_b: NDArray, sample: NDArray, magnitude: float, width: int, height: int) -> _Sample:
    """Position of ``sample`` against edges a -> b ((E, 2) each): exactly on a vertex or on
    an edge (closed; the exact orientation and float comparisons), or within float32
    rounding of one (a tolerance, named as one); and whether the edges it lies on -- or,
    off every edge and beyond float rounding, the nearest when within
    :data:`CLIPPER_PIXELS` -- reach beyond the viewport [0, width] x [0, height]."""
    if edges_a.shape[0] == 0 or not np.isfinite(sample).all():
        return _Sample(None, False, False)
    with np.errstate(invalid="ignore"):
        outside = ((np.minimum(edges_a, edges_b) < 0).any(axis=1) | (np.maximum(edges_a[:, 0], edges_b[:, 0]) > width)
                   | (np.maximum(edges_a[:, 1], edges_b[:, 1]) > height))
    at_vertex = np.all(edges_a == sample, axis=1) | np.all(edges_b == sample, axis=1)
    if at_vertex.any():
        return _Sample("vertex", False, bool(outside[at_vertex].all()))
    triple = np.stack([edges_a, edges_b, np.broadcast_to(sample, edges_a.shape)], axis=1)
    on_line = orientation(triple) == 0
    lo, hi = np.minimum(edges_a, edges_b), np.maximum(edges_a, edges_b)
    within = np.all((lo <= sample) & (sample <= hi), axis=1)
    on_edge = np.flatnonzero(on_line & within & np.any(edges_a != edges_b, axis=1))
    if on_edge.size:
        kinds = {_direction(edges_a[k], edges_b[k]) for k in on_edge}
        kind = next(k for k in ("slanted", "vertical", "horizontal") if k in kinds)
        return _Sample(kind, False, bool(outside[on_edge].all()))
    with np.errstate(all="ignore"):
        d = edges_b - edges_a
        e = d[:, 0] * (sample[1] - edges_a[:, 1]) - d[:, 1] * (sample[0] - edges_a[:, 0])
        length = np.hypot(d[:, 0], d[:, 1])
        m = max(magnitude, float(np.abs(sample).max()), 1.0)
        close = (np.abs(e) <= FLOAT32_EDGE_ROUNDING * m * m) & (np.abs(e) <= NEAR_PIXELS * length) & (length > 0)
        distance = np.where(length > 0, np.abs(e) / length, np.inf)
    distance = np.where(np.isnan(distance), np.inf, distance)
    nearest = int(np.argmin(distance))
    close &= np.isfinite(e)
    violated = _violated_edges(edges_a, edges_b, sample)
    if violated.any():
        # outside a triangle, rounding takes it in only if it rounds every edge it lies
        # outside of (one on an edge's extension past a vertex lies clearly outside another)
        near = bool(close[violated].all())
    else:  # inside, or a path: near an edge itself, not its line past its ends
        with np.errstate(all="ignore"):
            along = d[:, 0] * (sample[0] - edges_a[:, 0]) + d[:, 1] * (sample[1] - edges_a[:, 1])
            past = np.maximum(0.0, np.maximum(-along, along - length * length))  # beyond an end, times the length
        near = bool(np.any(close & (past <= NEAR_PIXELS * length)))
    # a clipper's error: beyond float rounding, yet close to an edge that leaves the screen
    border = not near and bool(outside[nearest]) and bool(distance[nearest] <= CLIPPER_PIXELS)
    return _Sample(None, near, border)


def _violated_edges(edges_a: NDArray, edges_b: NDArray, sample: NDArray) -> NDArray[np.bool_]:
    """(E,) bool: for a triangle's three edges a -> b (closed, nonzero area), those the
    sample lies strictly outside of (exact orientations); all False for anything else."""
    none = np.zeros(edges_a.shape[0], dtype=bool)
    if edges_a.shape[0] != 3 or not np.isfinite(edges_a).all() \
            or not (np.array_equal(edges_b[:2], edges_a[1:]) and np.array_equal(edges_b[2], edges_a[0])):
        return none
    winding = int(orientation(np.stack([edges_a[0], edges_a[1], edges_a[2]])[None])[0])
    if winding == 0:
        return none
    sides = orientation(np.stack([edges_a, edges_b, np.broadcast_to(sample, edges_a.shape)], axis=1))
    return sides == -winding


def _wrong_pixels(result: Any, noun: str, n: int) -> list[tuple[int, int, int, str, float]]:
    """(primitive, x, y, kind, distance) of the wrong deviations the evidence lists (all
    listed ones when none is marked wrong: strict mode)."""
    listed = result.evidence.get("pixels") if isinstance(result.evidence, dict) else None
    if not isinstance(listed, list):
        return []
    rows = [p for p in listed if isinstance(p, dict) and isinstance(p.get(noun), int) and 0 <= p[noun] < n]
    wrong = [p for p in rows if not p.get("near_tie")] or rows
    return [(int(p[noun]), int(p["x"]), int(p["y"]), str(p.get("kind", "")), float(p.get("distance", math.inf))) for p in wrong]


def _pixel_set(coverage: Coverage, prims: NDArray[np.int64], remap: dict[int, int], width: int, height: int) -> set[tuple[int, int, int]]:
    """(remapped primitive, x, y) of the coverage's fragments of ``prims`` in the viewport."""
    t, x, y = coverage.pixels()
    keep = np.isin(t, prims) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    t, x, y = t[keep], x[keep], y[keep]
    distinct = unique(t)  # remapped once each, then by lookup (a Python int per fragment was the cost)
    index = np.array([remap[v] for v in distinct.tolist()], dtype=np.int64)
    mapped = index[np.searchsorted(distinct, t)]
    return set(zip(mapped.tolist(), x.tolist(), y.tolist()))


def _same_as(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], variant: AnyScene, convention: Convention) -> bool:
    """Whether the answer's fragments of ``prims`` are exactly the oracle's of ``variant``
    (the subset scene of ``prims``, changed) under ``convention``: one oracle call."""
    from harness.oracle.coverage import exact_coverage

    remap = {int(k): i for i, k in enumerate(prims)}
    want = exact_coverage(variant, convention)
    got = _pixel_set(answer, prims, remap, scene.width, scene.height)
    expected = _pixel_set(want, np.arange(len(prims)), {i: i for i in range(len(prims))}, scene.width, scene.height)
    return got == expected


def _open_outline(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], convention: Convention,
                  unlike: Callable[[set[tuple[int, int, int]]], set[tuple[int, int, int]]] | None = None) -> bool:
    """Whether the answer's fragments of ``prims`` -- some at least -- are exactly what a
    filler draws that leaves every contour open (:func:`harness.oracle.winding.open_outline_coverage`,
    under either rule for the rows that then stay inside), and not what another explanation
    draws: ``unlike`` gives that from the oracle's fragments of ``prims`` (as
    (index in ``prims``, x, y)), e.g. a culler's. Two oracle calls, a third for ``unlike``;
    single-sample triangles without culling, and paths."""
    from harness.oracle.coverage import exact_coverage
    from harness.oracle.winding import UNBALANCED_ROWS, open_outline_coverage

    if not convention.model.single_sample or (isinstance(scene, Scene) and convention.cull != "none") \
            or not isinstance(scene, (Scene, PathScene)) or not prims.size:
        return False
    subset = scene.subset(prims)
    if not np.isfinite(subset.coordinates).all():
        return False
    remap = {int(k): i for i, k in enumerate(prims)}
    identity = {i: i for i in range(len(prims))}
    got = _pixel_set(answer, prims, remap, scene.width, scene.height)
    if not got:
        return False  # dropped whole: no evidence
    for rule in UNBALANCED_ROWS:
        try:
            predicted = _pixel_set(open_outline_coverage(subset, convention, rule), np.arange(len(prims)), identity,
                                   scene.width, scene.height)
        except ValueError:  # a convention or scene it does not take
            return False
        if predicted == got:
            return unlike is None or got != unlike(_pixel_set(exact_coverage(subset, convention), np.arange(len(prims)),
                                                              identity, scene.width, scene.height))
    return False


def _hypothesis(result: Any, scene: AnyScene, prims: NDArray[np.int64], convention: Convention,
                near: bool, exact: bool) -> tuple[str, str] | None:
    """The alternatives worth an oracle call, tested on the wrong primitives alone: the
    other roundings of the convention's snapping that move a vertex (when it snaps: the
    fewest moved first, each tried -- exact halves move under half-away as under no other,
    and floor may move fewer), the other fill rule (paths wrong away from their edges), or
    the other last-pixel choice or direction (lines wrong within rounding of the rule's
    boundary)."""
    answer = _answer(result)
    if answer is None or not prims.size:
        return None
    subset = scene.subset(prims)
    coordinates = subset.coordinates
    if not np.isfinite(coordinates).all():
        return None
    if convention.subpixel_bits is not None:
        declared = convention.snap(coordinates)
        others: list[tuple[int, SnapRounding]] = []
        for rounding in SNAP_ROUNDINGS:
            if rounding == convention.snap_rounding:
                continue
            moved = int(np.sum(replace(convention, snap_rounding=rounding).snap(coordinates) != declared))
            if moved:
                others.append((moved, rounding))
        for _, rounding in sorted(others):
            if _same_as(answer, scene, prims, subset, replace(convention, snap_rounding=rounding)):
                return "snapping", "snapping"
        if not isinstance(subset, PathScene):
            return None
    if isinstance(subset, PathScene) and not near and not exact:
        flipped = subset.with_fill_rule("evenodd" if subset.fill_rule == "nonzero" else "nonzero")
        if _same_as(answer, scene, prims, flipped, convention):
            return "fill-rule", "fill-rule"
        return _contours_hypothesis(answer, scene, prims, subset, convention)
    line = convention.line
    if isinstance(subset, LineScene) and near and line is not None:
        # a decision near the rule's boundary drawn exactly as the rule draws it with the
        # other last-pixel choice, or each segment drawn the other way: that choice, not rounding
        if isinstance(line.last_pixel, bool) and _same_as(answer, scene, prims, subset,
                                                          replace(convention, line=replace(line, last_pixel=not line.last_pixel))):
            return "end-pixel", "line-rule"
        if _same_reversed(answer, scene, prims, subset, convention):
            return "reversal", "line-rule"
    return None


def _contours_hypothesis(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: PathScene,
                         convention: Convention) -> tuple[str, str] | None:
    """Paths of several contours wrong away from their edges, drawn exactly as the oracle
    draws each one's first contour alone (``later-contours-dropped``), or each contour
    filled on its own, their union (``holes-ignored``) -- when the two differ (a hole
    filled within the first contour is either, or a fill counting crossings unsigned:
    none is named); else None. Two oracle calls, only for paths of several contours."""
    from harness.oracle.coverage import exact_coverage

    sizes = subset.contour_sizes
    if not (np.bincount(subset.contour_path, minlength=len(subset)) > 1).any():
        return None
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    first = np.flatnonzero(np.concatenate([[True], subset.contour_path[1:] != subset.contour_path[:-1]]))
    keep = np.concatenate([np.arange(starts[c], starts[c] + sizes[c]) for c in first])
    alone = PathScene(scene.width, scene.height, subset.vertices[keep], sizes[first], subset.contour_path[first], subset.fill_rule)
    each = PathScene(scene.width, scene.height, subset.vertices, sizes, np.arange(sizes.size), subset.fill_rule)
    identity = {i: i for i in range(len(subset))}
    firsts = _pixel_set(exact_coverage(alone, convention), np.arange(len(subset)), identity, scene.width, scene.height)
    t, x, y = exact_coverage(each, convention).pixels()
    on = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
    union = set(zip(subset.contour_path[t[on]].tolist(), x[on].tolist(), y[on].tolist()))
    if firsts == union:
        return None  # every later contour within the first (a hole filled): the two cannot be told apart
    got = _pixel_set(answer, prims, {int(k): i for i, k in enumerate(prims)}, scene.width, scene.height)
    if got == firsts:
        return "later-contours-dropped", "none"
    if got == union:
        return "holes-ignored", "fill-rule"
    return None


def _same_reversed(answer: Coverage, scene: AnyScene, prims: NDArray[np.int64], subset: LineScene,
                   convention: Convention) -> bool:
    """Whether the answer's fragments of segments ``prims`` are exactly the oracle's of
    ``subset`` (those segments) with every strip drawn backwards: one oracle call."""
    from harness.oracle.coverage import exact_coverage

    backwards, origin = subset.reversed()
    t, x, y = exact_coverage(backwards, convention).pixels()
    keep = (x >= 0) & (x < scene.width) & (y >= 0) & (y < scene.height)
    expected = set(zip(np.asarray(origin)[t[keep]].tolist(), x[keep].tolist(), y[keep].tolist()))
    remap = {int(k): i for i, k in enumerate(prims)}
    return _pixel_set(answer, prims, remap, scene.width, scene.height) == expected


# -- conformance -----------------------------------------------------------------------------


def _viewport_edge_class(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    """A conformance failure that passes moved into a grown screen: the viewport's edge --
    unless the answer is exactly another snap rounding's (a rounding that is not
    translation-invariant, half away from zero, rounds the moved vertices otherwise, and
    passed there by chance), or no wrong primitive reaches beyond the screen (float
    arithmetic rounds moved coordinates otherwise too, and the edge decided nothing)."""
    rest = replace(result, evidence={k: v for k, v in result.evidence.items() if k != "viewport_edge"})
    without = classify_conformance(rest, case, convention)
    if without[1] == "snapping" or without[0] == "open-contour" or not _wrong_reach_beyond(result, case.scene):
        return without
    return "viewport-edge", "none"


def _flat_primitives(scene: Any, prims: NDArray[np.int64], snapped: dict[int, NDArray[np.float64]]) -> set[int]:
    """The primitives of ``prims`` that snapping leaves without area (a triangle of zero
    orientation, a segment of zero length); none for paths."""
    if isinstance(scene, Scene):
        return {int(k) for k, sign in zip(prims, orientation(np.stack([snapped[int(k)] for k in prims]))) if sign == 0}
    if isinstance(scene, LineScene):
        return {k for k, c in snapped.items() if np.array_equal(c[0], c[1])}
    return set()


def _degenerate_class(scene: Any, wrong: list[Any], snapped: dict[int, NDArray[np.float64]],
                      judged: Convention) -> tuple[str, str]:
    """Every wrong sample a flat primitive's: drawn only where all three edge functions are
    0 is the tie rule's (an inclusive test); anything else is the degenerate case's own."""
    extra = [(k, x, y) for k, x, y, kind, _ in wrong if kind == "extra"]
    on_line = len(extra) == len(wrong) and all(
        bool(_on_flat_line(snapped[k], np.array([[x + judged.sample[0], y + judged.sample[1]]]))[0]) for k, x, y in extra)
    return "degenerate", "tie-rule" if on_line and isinstance(scene, Scene) else "none"


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
    wrong = _wrong_pixels(result, scene.noun, n)
    if not wrong:
        return "other", "none"
    complete = _metric(result, "wrong") <= len(wrong) or _metric(result, "wrong") == 0  # every wrong one listed
    judged = _judged_convention(result, convention)
    # non-finite, then zero-area primitives: their class when every wrong one is such; else
    # the others decide (a scene may show two bugs; the first kind is the one to name)
    non_finite = set(scene.non_finite())
    if all(k in non_finite for k, *_ in wrong):
        return "non-finite-input", "none"
    wrong = [w for w in wrong if w[0] not in non_finite]
    prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
    coordinates = _primitive_coordinates(scene, prims)
    snapped = {int(k): judged.snap(c) for k, c in zip(prims, coordinates)}
    flat = _flat_primitives(scene, prims, snapped)
    if all(k in flat for k, *_ in wrong):
        return _degenerate_class(scene, wrong, snapped, judged)
    if flat:
        wrong = [w for w in wrong if w[0] not in flat]
        prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
        coordinates = _primitive_coordinates(scene, prims)
    magnitude = _magnitude(coordinates)
    if isinstance(scene, LineScene):
        return _line_conformance(result, scene, wrong, prims, snapped, judged, magnitude)
    copies = evidence.get("dropped_trial")
    copies = copies if isinstance(copies, dict) else {}
    answer = _answer(result)
    if copies.get("open_contour") or (answer is not None and _open_outline(answer, scene, prims, judged)):
        # drawn exactly as with each contour's closing edge left out (missing whole: their
        # copies in other vertex orders are): the outline, at any magnitude
        return "open-contour", "none"
    edges = _edges_of(scene, judged)
    facts = [_edge_facts(*edges[k], np.array([x + judged.sample[0], y + judged.sample[1]]), _magnitude([snapped[k]]),
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
    dropped = None if exact or drawn_elsewhere else _dropped(result, scene, prims, wrong, snapped,
                                                              lambda sc: judged.snap(sc.positions), culls)
    if dropped is not None:
        return dropped
    hypothesis = _hypothesis(result, scene, prims, judged, near, exact)
    if hypothesis is not None:
        return hypothesis
    kinds = {f.tie for f in facts if f.tie is not None}
    if "viewport_edge_refuted" not in evidence and all(f.border for f in facts) \
            and (not kinds or (complete and _ties_right_inside(scene, edges, judged, kinds, wrong))):
        # every wrong sample decided by an edge that leaves the screen, and (for ties) the
        # same kind of tie decided right on an edge inside it: a clipper's work
        return "viewport-edge", "none"
    if exact:
        return _exact_tie_class(kinds)
    if near:
        return "near-tie", "none"
    if isinstance(convention, Convention) and convention.model.sample_ids and isinstance(scene, Scene) \
            and _metric(result, "extra") == 0 and _dropped_near_edges(wrong, edges, judged):
        return "dropped-near-edges", "none"
    if isinstance(scene, PathScene):
        # every wrong sample on a row through one of its path's vertices (exact: float
        # comparisons): crossings counted at the vertices -- a tie in y, not the fill
        rows = all(bool(np.any(snapped[k][:, 1] == y + judged.sample[1])) for k, _, y, _, _ in wrong)
        # (unless, shifted off those rows, the paths still fail: the fill's, on such rows by chance)
        refuted = isinstance(trial, dict) and trial.get("vertex_rows") and trial.get("passes") is False
        return ("vertex-row", "tie-rule") if rows and not refuted else ("winding", "fill-rule")
    return "far-from-edge", "sample-point"


def _dropped_near_edges(wrong: list[tuple[int, int, int, str, float]], edges: dict[int, tuple[NDArray, NDArray]],
                        judged: Convention) -> bool:
    """Whether every wrong sample of a multisample layer is missing (none extra), lies
    within :data:`NEAR_EDGE_PIXELS` of an edge of its triangle, and its pixel's centre
    strictly outside the triangle (exact orientations): samples dropped where a pixel
    was rejected whole near an edge, not a pattern read wrong (which puts samples in where
    it leaves others out)."""
    if not wrong or any(kind != "missing" for _, _, _, kind, _ in wrong):
        return False
    for k, x, y, _, _ in wrong:
        a, b = edges[k]
        centre = np.array([x + 0.5, y + 0.5])
        if not _violated_edges(a, b, centre).any():
            return False
        sample = np.array([x + judged.sample[0], y + judged.sample[1]])
        with np.errstate(all="ignore"):
            d = b - a
            t = np.clip(((sample - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
            reach = np.hypot(*(a + t[:, None] * d - sample).T)
        if not (reach <= NEAR_EDGE_PIXELS).any():
            return False
    return True


def _wrong_reach_beyond(result: Any, scene: AnyScene) -> bool:
    """Whether every primitive with a wrong sample reaches beyond the screen [0, width] x
    [0, height] (or has a coordinate that is not finite): only those meet its edge."""
    wrong = _wrong_pixels(result, scene.noun, len(scene))
    prims = np.array(sorted({w[0] for w in wrong}), dtype=np.int64)
    for c in _primitive_coordinates(scene, prims):
        with np.errstate(invalid="ignore"):
            inside = np.isfinite(c).all() and (c >= 0).all() and (c[:, 0] <= scene.width).all() and (c[:, 1] <= scene.height).all()
        if inside:
            return False
    return bool(prims.size)


def _edges_of(scene: AnyScene, judged: Convention) -> dict[int, tuple[NDArray, NDArray]]:
    """Each triangle's or path's edges a -> b as the convention sees them (snapped)."""
    start, end, owner = scene.edges()
    start, end = judged.snap(start), judged.snap(end)
    order = np.argsort(owner, kind="stable")
    bounds = np.searchsorted(owner[order], np.arange(len(scene) + 1))
    return {k: (start[order[bounds[k]:bounds[k + 1]]], end[order[bounds[k]:bounds[k + 1]]]) for k in range(len(scene))}


def _ties_right_inside(scene: AnyScene, edges: dict[int, tuple[NDArray, NDArray]], judged: Convention, kinds: set[str],
                       wrong: list[tuple[int, int, int, str, float]]) -> bool:
    """Whether some sample exactly on an edge inside the viewport, of a kind in ``kinds``
    (an edge's direction, or ``vertex``), was decided right (is not among the wrong ones):
    then the rasterizer keeps that tie rule where no edge leaves the screen. Exact: each
    candidate sample's orientation decides."""
    sx, sy = judged.sample
    wrong_keys = {(k, x, y) for k, x, y, _, _ in wrong}
    bad = set(scene.non_finite())
    for k, (a, b) in edges.items():
        if k in bad or not a.shape[0]:
            continue
        if isinstance(scene, Scene) and orientation(np.stack([a[0], b[0], b[1]])[None])[0] == 0:
            continue  # zero area: covers nothing, no tie to decide
        for p, q in zip(a, b):
            if min(p[0], q[0]) < 0 or min(p[1], q[1]) < 0 or max(p[0], q[0]) > scene.width or max(p[1], q[1]) > scene.height:
                continue
            if "vertex" in kinds:
                x, y = p[0] - sx, p[1] - sy
                if x == math.floor(x) and y == math.floor(y) and (k, int(x), int(y)) not in wrong_keys \
                        and x < scene.width and y < scene.height:
                    return True
            kind = _direction(p, q)
            if kind not in kinds or np.array_equal(p, q):
                continue
            for x, y in _samples_on(p, q, sx, sy):
                if (k, x, y) not in wrong_keys and 0 <= x < scene.width and 0 <= y < scene.height:
                    return True
    return False


def _samples_on(p: NDArray, q: NDArray, sx: float, sy: float) -> list[tuple[int, int]]:
    """Pixels (x, y) whose sample (x + sx, y + sy) lies exactly inside the segment p-q (not at
    its ends): candidates from floats, each confirmed by the exact orientation."""
    if p[1] == q[1]:
        y = p[1] - sy
        if y != math.floor(y):
            return []
        lo, hi = min(p[0], q[0]), max(p[0], q[0])
        return [(x, int(y)) for x in range(math.floor(lo - sx) + 1, math.ceil(hi - sx)) if lo < x + sx < hi]
    lo, hi = min(p[1], q[1]), max(p[1], q[1])
    rows = np.arange(math.floor(lo - sy), math.ceil(hi - sy) + 1, dtype=np.float64)
    rows = rows[(rows + sy > lo) & (rows + sy < hi)]
    if not rows.size:
        return []
    with np.errstate(all="ignore"):
        x = p[0] + (rows + sy - p[1]) * (q[0] - p[0]) / (q[1] - p[1]) - sx
    columns = np.round(x)
    close = np.abs(x - columns) <= 1e-6 * max(1.0, float(np.abs(x).max(initial=0.0)))  # a screen: orientation decides
    if not close.any():
        return []
    samples = np.stack([columns[close] + sx, rows[close] + sy], axis=-1)
    on = orientation(np.stack([np.broadcast_to(p, samples.shape), np.broadcast_to(q, samples.shape), samples], axis=1)) == 0
    return [(int(c), int(r)) for c, r in zip(columns[close][on], rows[close][on])]


def _dropped(result: Any, scene: AnyScene, prims: NDArray[np.int64], wrong: list[tuple[int, int, int, str, float]],
             snapped: dict[int, NDArray], snap_all: Callable[[Scene], NDArray], culls: bool = True) -> tuple[str, str] | None:
    """culling (unless ``culls`` is False: the dropped trial refuted it) or
    dropped-primitive when every wrong deviation is a missing fragment of a primitive the
    answer holds nothing of."""
    answer = _answer(result)
    if answer is None or any(kind != "missing" for _, _, _, kind, _ in wrong):
        return None
    if np.isin(answer.pixels()[0], prims).any():
        return None
    if culls and isinstance(scene, Scene) and prims.size:
        # culling: every triangle of the wrong ones' winding missing, some of the other drawn
        signs = set(orientation(np.stack([snapped[int(k)] for k in prims])).tolist())
        every = orientation(snap_all(scene))
        drawn = np.unique(answer.pixels()[0])
        drawn = drawn[(drawn >= 0) & (drawn < len(scene))]
        if len(signs) == 1 and not np.isin(np.flatnonzero(every == signs.pop()), drawn).any() and drawn.size:
            return "culling", "culling"
    return "dropped-primitive", "none"


def _segment_direction(a: NDArray, b: NDArray) -> str:
    if a[1] == b[1]:
        return "horizontal"
    if a[0] == b[0]:
        return "vertical"
    if abs(b[0] - a[0]) == abs(b[1] - a[1]):  # |dx| == |dy|: exact for floats that do not overflow
        return "diagonal"
    return "slanted"


def _line_conformance(result: Any, scene: LineScene, wrong: list[tuple[int, int, int, str, float]], prims: NDArray[np.int64],
                      snapped: dict[int, NDArray], judged: Convention, magnitude: float) -> tuple[str, str]:
    """A line scene's conformance failure: the check's own distances say where the rule's
    decision sits (exactly 0 only on its boundary, decided exactly)."""
    exact = all(d == 0.0 for _, _, _, _, d in wrong)
    near = all(0.0 < d <= 2.0**-16 and d * magnitude <= NEAR_PIXELS for _, _, _, _, d in wrong)
    found = _hypothesis(result, scene, prims, judged, near, exact)
    if found is not None:
        return found
    if exact:
        kinds = {_segment_direction(snapped[k][0], snapped[k][1]) for k, _, _, _, _ in wrong}
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


# -- watertight ------------------------------------------------------------------------------


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
    magnitude = _magnitude(_primitive_coordinates(scene, prims)) if prims.size else 1.0
    if case.region is not None:
        magnitude = max(magnitude, _magnitude([np.asarray(case.region, dtype=np.float64)]))
    overflow = overflow_class(magnitude)
    if overflow is not None:
        return overflow, "none"
    if kind == "stray" or not blamed:
        return kind, "none"
    judged = _judged_convention(result, convention)
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
        facts.append(_edge_facts(a, z, np.array([x + judged.sample[0], y + judged.sample[1]]), _magnitude([a, z]), scene.width, scene.height))
    twin = evidence.get("lattice_twin")
    if all(f.tie is not None for f in facts) and not (isinstance(twin, dict) and twin.get("fails") is False):
        return kind, "tie-rule"  # (unless the same tie on a lattice is decided right: rounding's)
    if all(f.near or f.tie is not None for f in facts):
        return "near-tie", "none"
    return kind, "none"


# -- the other checks ------------------------------------------------------------------------


def _metric(result: Any, name: str) -> float:
    metrics = result.metrics if isinstance(result.metrics, dict) else {}
    value = metrics.get(name, 0.0)
    return float(value) if isinstance(value, (int, float)) else 0.0


def _first_positive(result: Any, options: tuple[tuple[str, str], ...], otherwise: str) -> str:
    for metric, name in options:
        if _metric(result, metric) > 0:
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
    if not isinstance(scene, Scene) or not isinstance(named, list) or not named:
        return False
    return set(named) <= set(scene.non_finite())


def _drawn_on_own_edges(result: Any, case: Any, convention: Convention | None) -> bool:
    """Whether every zero-area triangle the degenerate check names is finite and drew only
    samples exactly on its own (snapped) line -- where its three edge functions are all 0
    (:func:`_on_flat_line`): an edge test that keeps a sample on an edge on both sides (or
    a kept horizontal edge) draws them, the tie rule's fault rather than a drawing of
    nothing."""
    answer = _answer(result)
    scene = getattr(case, "scene", None)
    named = result.evidence.get("triangles") if isinstance(result.evidence, dict) else None
    if answer is None or not isinstance(scene, Scene) or not isinstance(named, list) or not named:
        return False
    offenders = np.array([int(t) for t in named if isinstance(t, int) and 0 <= t < len(scene)], dtype=np.int64)
    if offenders.size != len(named) or np.isin(offenders, scene.non_finite()).any():
        return False
    judged = _judged_convention(result, convention)
    snapped = judged.snap(scene.positions[offenders])
    t, x, y = answer.pixels()
    for k, positions in zip(offenders, snapped):
        mine = t == k
        if not mine.any():
            return False
        samples = np.stack([x[mine] + judged.sample[0], y[mine] + judged.sample[1]], axis=-1).astype(np.float64)
        if not _on_flat_line(positions, samples).all():
            return False
    return True


def _on_flat_line(positions: NDArray, samples: NDArray) -> NDArray[np.bool_]:
    """(M,) bool: which samples ((M, 2)) make all three edge functions of the zero-area
    triangle ``positions`` ((3, 2)) exactly 0 -- those on its line, or, for a triangle that
    is a point, every sample (its edge functions vanish everywhere). Exact."""
    spans = [(positions[i], positions[(i + 1) % 3]) for i in range(3)]
    a, b = max(spans, key=lambda e: float(np.abs(e[1] - e[0]).max()))
    if np.array_equal(a, b):
        return np.ones(samples.shape[0], dtype=bool)
    return orientation(np.stack([np.broadcast_to(a, samples.shape), np.broadcast_to(b, samples.shape), samples], axis=1)) == 0


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
    return (found[0], "none") if found is not None else None


def _frame_cause(result: Any) -> tuple[str, str] | None:
    """The class and part of a motion failure read through :func:`with_probes`' facts:
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
    """The class and part of a verdict a probe classified and kept under ``key`` (a dict
    with its ``signature``) of a result's evidence (or of a probe's own dict), when it
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
    if _metric(result, "max_uv_error_texels") == math.inf:  # u, v not finite: not a perspective error
        return "nan-attributes", "none"
    return _first_positive(result, (("frames_without_attributes", "missing-attributes"),), "perspective-error"), "none"


def classify_accuracy(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    return _alpha_cause(result) or _by_metrics((("over_tolerance", "alpha-error"), ("off_level", "off-level")), "other")(
        result, case, convention)


def classify_seams(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    if isinstance(result.evidence, dict) and isinstance(result.evidence.get("order_dependence"), str):
        return str(result.evidence["order_dependence"]), "none"  # a seam of the edge direction (with_probes)
    return _first_positive(result, (("seam_pixels", "seam"), ("strays", "stray")), "other"), "none"


def classify_triangulation(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    return _sub_verdict(result, "triangles_failure") or _by_metrics(
        (("triangulation_double_hits", "triangulation-double-hit"),), "triangulation-mismatch")(result, case, convention)


def classify_joints(result: Any, case: Any, convention: Convention | None) -> tuple[str, str]:
    joints = (result.evidence or {}).get("joints", [])
    wrong_vertex = any(isinstance(r, dict) and "drawn" in r and r["drawn"] != r.get("rule") for r in joints)
    return ("joint-vertex" if wrong_vertex else "joint-overlap"), "line-rule"
