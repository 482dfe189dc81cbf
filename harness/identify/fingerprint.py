"""``rastercheck identify``: fingerprint a black-box rasterizer's convention from outside.

- Sample point and tie rule: the candidate (9 sample points and the measured one x the 8
  tie rules) whose exact oracle best matches the rasterizer on lattice scenes built to
  hit ties (vertices on sample points, edges through them, and piglit's pinwheels of
  eight triangles around a sample, of which each rule draws exactly one).
- Snapping: with that sample point and tie rule, the number of sub-pixel bits (or none)
  and the rounding (nearest-even, half-away, floor) that best explain it on
  unconstrained-float scenes, where snapping shows, and on scenes whose vertices sit
  exactly on half steps of the fitted grid, where the roundings part.
- Culling, zero-area and non-finite handling, the viewport edge (the rasterizer against
  itself inside a larger screen), and watertightness on every planar partition family.

Each of these is a probe of :mod:`harness.identify.triangle_probes` giving a typed fact; :func:`identify`
composes them. It first reads the kind of coverage (:func:`harness.identify.coverage_probes.coverage_kind`):
an anti-aliaser (alphas) or a multisample rasterizer (sample indices) is fingerprinted by
the probes of :mod:`harness.identify.coverage_probes` instead -- analytic area or supersampled, the
grid and the levels (:func:`~harness.identify.area_probes.alpha_sweeps`), or the sample
pattern and its tie rule (:func:`~harness.identify.sample_probes.sample_positions`). The fit of sample point
and tie rule is :func:`harness.identify.triangle_probes.fit_ties`, the one ``compare`` uses too. Every call
of the rasterizer goes through a :data:`~harness.engine.isolation.Call`: in this process, or in a worker
process (:func:`identify_isolated`).

A path-taking rasterizer (``"paths"`` in :func:`harness.contract.protocol.scene_kinds_of`) is asked
first which fill rule it draws for each rule it declares (:func:`harness.identify.path_probes.fill_rules`),
then fingerprinted on triangles as above, then through the path interface (the triangle
probes with each triangle sent as a one-contour path, :func:`harness.identify.path_probes.fit_path_convention`):
its path convention is compared with its triangle convention, and tried on genuine paths
with ties. A triangle-only rasterizer is never sent a path scene.

A line-taking rasterizer (``"lines"`` in its scene kinds) is also asked which line rule it
draws (:func:`harness.identify.line_probes.fit_lines`: diamond-exit, Bresenham with its end point
rounding, tie direction and last pixel, or rectangular lines with their sample point and
tie rule, and the snapping in front); the rule found is put in the fingerprint's
convention (its ``line``), and the whole line convention in ``line_convention``. One that
takes only lines is fingerprinted by that alone: no triangle or path is sent to it, nor
a line to a rasterizer that does not list lines.

It prints a convention card and the :class:`Convention` that best explains the rasterizer
with the residual mismatch; it says "identified" only when the residual is zero.

identify and ``run`` agree: the probes that can see a defect (watertight, the viewport
edge, zero-area, non-finite and tiny triangles) draw the suite's own cases for the
rasterizer's scene kind (a paths-only filler's: the same triangles as one-contour paths,
:func:`cases.paths.triangle_cases_as_paths`), and each case on which a probe saw a defect
is judged as ``run`` judges it (:func:`harness.identify.triangle_defects.suite_defects`): a
:class:`~harness.identify.triangle_defects.Defect` with the check's evidence and a minimal repro
(:attr:`Fingerprint.defects`, on the card, in ``--json`` and on the fingerprint page). A
declared convention is judged by the checks of its coverage kind (:data:`VERDICT_CHECKS`)
on the probe scenes (:func:`verdict_cases`) before it is called confirmed or consistent.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import AREA_LINE_RULES, Convention, CoverageKind, LineRule
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import COVERAGE_KINDS, SINGLE, CoverageModel, model_named
from harness.contract.protocol import Rasterizer, fill_rules_of, interpolates_of, received_of, scene_kinds_of
from harness.contract.samples import STANDARD_PATTERNS
from harness.contract.scenes import AnyScene, PathScene, Scene
from harness.engine.isolation import Call, CallTally, InProcess, Outcome, TimeLimit
from harness.identify.area_probes import alpha_sweeps, rounded_up_tolerance
from harness.identify.coverage_probes import CoverageKindFact, Remembered, coverage_kind, layered
from harness.identify.input_probes import fit_input, fit_input_beside
from harness.identify.rule_probes import fit_rule_beside
from harness.identify.sample_probes import sample_positions, sample_sides
from harness.identify.triangle_defects import (
    EPSILON_CASE,
    NON_FINITE_CASES,
    REPROS,
    ZERO_AREA_CASE,
    Defect,
    Epsilon,
    NonFinite,
    Unanswered,
    ViewportEdge,
    Watertight,
    ZeroArea,
    epsilon,
    non_finite,
    suite_defects,
    unanswered,
    viewport_edge,
    watertight_partitions,
    zero_area,
)
from harness.identify.triangle_probes import Fact, fit_snapping, fit_ties, residual_lies
from harness.kinds import KINDS, LINES, PATHS, TRIANGLES, PrimitiveKind

if TYPE_CHECKING:  # the path and line probes are imported when a rasterizer taking those is identified
    from harness.contract.case import Case, MotionCase
    from harness.identify.line_probes import LineFit
    from harness.identify.path_probes import PathFit

__all__ = ["Fingerprint", "identify", "identify_isolated", "identify_all", "Identified", "VERDICT_CHECKS", "verdict_cases",
           "repro_size"]

# scenes with a defect shown on the card (--json and the fingerprint page have them all)
CARD_DEFECTS = 3

# The checks that judge a declared convention of each coverage kind, run on identify's own
# probe scenes (and the suite's scenes those checks need: partitions for seams, sub-pixel
# motion for popping) before identify calls a declaration confirmed or consistent.
# Each kind's model says which (:attr:`harness.contract.coverage_models.CoverageModel.verdict_checks`).
VERDICT_CHECKS: dict[CoverageKind, tuple[str, ...]] = {kind: model_named(kind).verdict_checks for kind in COVERAGE_KINDS}


@dataclass
class Fingerprint:
    """What identify found: the convention that best explains a rasterizer, its residual
    mismatch over ``pixels`` drawn, the runner-up (another sample point or tie rule) with
    its mismatches, the card's facts (label -> text), the snap roundings it could not tell
    apart, and the typed facts behind the card (``probes``, label -> fact).

    ``kind`` is the coverage kind seen (``single``, ``multisample``, ``area``); for the
    last two the residual counts mismatching fragments (triangle, sample, pixel) and
    (triangle, pixel)s whose alpha lies beyond the convention's tolerance of its oracle.

    For a path-taking rasterizer only (None otherwise): ``fill_rules``, each fill rule
    asked -> what it drew (``nonzero``, ``evenodd``, ``neither: ...`` or ``unanswered:
    ...``; :attr:`harness.identify.path_probes.RuleSeen.label`), and ``path_convention``, the
    convention that best explains it on paths (``path_fit`` holds the whole fit: residual,
    comparison with triangles, genuine paths).

    For a line-taking rasterizer only (None otherwise): ``line_rule``, the
    :class:`~harness.contract.conventions.LineRule` that best explains its lines (also the
    ``line`` of ``convention``), ``line_convention``, the whole convention its lines are
    judged by (the rule, the snapping seen on lines, and for rectangular lines the sample
    point and tie rule), and ``line_fit``, the fit behind them (residual, runner-up, each
    rule's score, wide lines: :class:`harness.identify.line_probes.LineFit`). For a rasterizer that
    takes only lines, ``convention``, ``residual``, ``pixels``, ``runner_up`` and
    ``ambiguous`` are the line fit's.

    ``kind_fits``: for the scene kinds it takes beyond triangles, paths and lines (points),
    each kind's own fit (its ``probes`` hook, :mod:`harness.kinds`: ``convention``,
    ``residual``, ``pixels``, ``runner_up``, ``describe()``), by kind name. For a rasterizer
    that takes only such kinds, ``convention``, ``residual``, ``pixels`` and ``runner_up`` are
    its first kind's fit.

    ``unanswered``: the fit scenes the rasterizer gave no answer for (an error, a crash, a
    call cut off twice by its time limit), left out of the fit and of the residual: a
    fingerprint with any is never exact, and its card says why. ``calls``: every call
    made, and which timed out, failed or were answered only when asked again."""

    rasterizer: str
    convention: Convention
    residual: int
    pixels: int
    runner_up: tuple[str, int] | None = None
    facts: dict[str, Any] = field(default_factory=dict)
    ambiguous: tuple[str, ...] = ()
    probes: dict[str, Fact] = field(default_factory=dict, repr=False, compare=False)
    coverage_kind: CoverageKind = "single"
    fill_rules: dict[str, str] | None = None
    path_convention: Convention | None = None
    path_fit: PathFit | None = field(default=None, repr=False, compare=False)
    line_rule: LineRule | None = None
    line_convention: Convention | None = None
    line_fit: LineFit | None = field(default=None, repr=False, compare=False)
    kind_fits: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)
    unanswered: int = 0
    calls: CallTally | None = field(default=None, repr=False, compare=False)

    @property
    def model(self) -> CoverageModel:
        """The coverage model of the kind seen (area's for alphas, analytic or not)."""
        return model_named(self.coverage_kind)

    @property
    def lines_only(self) -> bool:
        """Fingerprinted on lines alone (it takes no triangles or paths)."""
        return self.line_fit is not None and self.line_fit.triangles is None

    @property
    def honoured_fill_rules(self) -> tuple[str, ...] | None:
        """The fill rules asked that it draws as asked (None for a triangle-only rasterizer)."""
        if self.fill_rules is None:
            return None
        return tuple(rule for rule, drawn in self.fill_rules.items() if drawn == rule)

    @property
    def exact(self) -> bool:
        """No mismatch, the runner-up (another sample point or tie rule) has some, no
        other snap rounding explains it as well, and every fit scene answered: a candidate
        that only ties with another, or fits only what was answered, is never claimed."""
        return (self.residual == 0 and not (self.runner_up is not None and self.runner_up[1] == 0)
                and not self.ambiguous and not self.unanswered)

    @property
    def defects(self) -> dict[str, tuple[Defect, ...]]:
        """Probe label -> the scenes on which it saw a defect (:class:`harness.identify.triangle_defects.Defect`:
        the suite's case, the check, the evidence, a minimal repro); empty when none did."""
        return {label: tuple(found) for label, fact in self.probes.items() if (found := getattr(fact, "defects", ()))}

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON and the report."""
        out: dict[str, Any] = {
            "rasterizer": self.rasterizer,
            "convention": self.convention.describe_lines() if self.lines_only else self.convention.describe(),
            "sample": list(self.convention.sample), "tie": self.convention.tie,
            "subpixel_bits": self.convention.subpixel_bits, "snap_rounding": self.convention.snap_rounding,
            "cull": self.convention.cull, "input": self.convention.input,
            "exact": self.exact, "residual": self.residual, "pixels": self.pixels,
            "runner_up": list(self.runner_up) if self.runner_up else None, "facts": dict(self.facts),
            "ambiguous": list(self.ambiguous), "unanswered": self.unanswered}
        if self.no_answers is not None:  # nothing identified: no convention is claimed (added field)
            out.update(convention=f"none identified: no answers ({self.no_answers})", no_answers=self.no_answers)
        if self.calls is not None:  # added fields (schema 1 allows them)
            out["calls"] = self.calls.to_dict()
        if not self.model.single_sample:  # added fields (schema 1 allows them)
            samples = self.convention.samples
            out.update(kind=self.coverage_kind, samples=None if samples is None else [list(o) for o in samples],
                       levels=self.convention.levels if self.model.alphas else None,
                       tolerance=self.convention.tolerance if self.model.alphas else None)
        if self.model.rule:  # a coverage rule's declaration (added fields)
            out.update(coverage=self.convention.coverage,
                       threshold=self.convention.threshold if self.convention.coverage_uses_threshold else None)
        if self.fill_rules is not None:  # a path-taking rasterizer's (added fields)
            fit = self.path_fit
            path = self.path_convention
            out.update(fill_rules=dict(self.fill_rules), honoured_fill_rules=list(self.honoured_fill_rules or ()),
                       path_convention=None if path is None else {
                           "convention": path.describe(), "sample": list(path.sample), "tie": path.tie,
                           "subpixel_bits": path.subpixel_bits, "snap_rounding": path.snap_rounding, "cull": path.cull,
                           "exact": fit.exact if fit is not None else False,
                           "residual": fit.residual if fit is not None else None,
                           "pixels": fit.pixels if fit is not None else None,
                           "fill_rule": fit.rule if fit is not None else None,
                           "same_as_triangles": fit.same_as_triangles if fit is not None else None,
                           "differences": list(fit.differences) if fit is not None else [],
                           "genuine_paths": None if fit is None or fit.lattice is None else
                           [{"fill_rule": r, "mismatches": m, "pixels": px} for r, m, px in fit.lattice.scores]})
        if self.defects:  # each defect's scenes, evidence and minimal repro (added field)
            out["defects"] = {label: [d.to_dict() for d in found] for label, found in self.defects.items()}
        if self.line_fit is not None:  # a line-taking rasterizer's (added fields)
            out.update(line_rule=None if self.line_rule is None else self.line_rule.describe(),
                       line_convention=_line_convention_dict(self.line_fit))
        if self.kind_fits:  # the other kinds' own conventions (added field)
            out["kind_conventions"] = {name: {
                "convention": None if fit.convention is None else fit.convention.describe(), "exact": fit.exact,
                "residual": fit.residual, "pixels": fit.pixels, "runner_up": list(fit.runner_up) if fit.runner_up else None,
                "same_as_triangles": fit.convention == self.convention} for name, fit in self.kind_fits.items()}
        return out

    @property
    def no_answers(self) -> str | None:
        """Why nothing was identified, when no probe call was answered (each raised, crashed
        or timed out), or no fit scene was: then ``convention`` and ``residual`` are the
        first candidate's, chosen by nothing, and are never claimed (the card and ``identify``
        say there were no answers). None when there were answers to fit."""
        tally = self.calls
        if tally is not None and tally.calls and len(tally.failed) + len(tally.timed_out) == tally.calls:
            first = (tally.failed or tally.timed_out)[0][2]
            how = ("failed" if not tally.timed_out else "timed out (each asked twice)" if not tally.failed
                   else "failed or timed out")
            return f"every one of its {tally.calls} calls {how}, first: {first}"[:300]
        fit = self.probes.get("unanswered")
        if isinstance(fit, Unanswered) and fit.count >= fit.of:
            return f"none of its {fit.of} fit scenes was answered, first: {fit.first}"[:300]
        return None

    @property
    def pattern_missing(self) -> bool:
        """A multisample rasterizer whose pattern was not recovered: its convention is a
        stand-in (the standard pattern of its count), never a finding."""
        pattern = self.probes.get("pattern")
        return self.model.sample_ids and pattern is not None and getattr(pattern, "convention", None) is None

    def card(self) -> str:
        silence = self.no_answers
        if silence is not None:  # no fit: no convention, no residual
            head = [f"convention   none identified: no answers ({silence})", "residual     not scored: nothing was answered"]
        elif self.pattern_missing:  # nothing recovered is claimed: the card says what stands in
            head = [f"convention   NOT RECOVERED (the pattern: see below); checked against {self.convention.describe()}, "
                    "a stand-in", "residual     not scored: no pattern to score"]
        else:
            head = [f"convention   {self.convention.describe_lines() if self.lines_only else self.convention.describe()}",
                    f"             {_compact_repr(self.convention)}",
                    f"residual     {self.residual} mismatching pixels of {self.pixels}"
                    + ("  (identified exactly)" if self.exact
                       else f"  (best guess only because calls failed: {self.unanswered} fit scene"
                            f"{'' if self.unanswered == 1 else 's'} unanswered, left out of the fit and the residual; see calls)"
                       if self.unanswered
                       else f"  (ambiguous between {' and '.join(self.ambiguous)})" if self.residual == 0 and self.ambiguous
                       else "  (ambiguous: the next best explains it as well)" if self.residual == 0
                       else "  (best guess only: no candidate explains it exactly)")]
        lines = [f"rasterizer   {self.rasterizer}", *head]
        if self.runner_up and silence is None:
            lines.append(f"next best    {self.runner_up[0]} ({self.runner_up[1]} mismatches on the "
                         + ("line probes)" if self.lines_only else "tie scenes)"))
        for k, v in self.facts.items():
            lines.append(f"{k:<12} {v}")
        every = [(label, d) for label, found in self.defects.items() for d in found]
        for label, d in every[:CARD_DEFECTS]:
            repro = d.repro
            shrunk = "" if repro is None else (
                f"; minimal repro: {repro_size(repro)} of {repro.get('original_triangles')} primitives, in --json")
            lines.append(f"{'evidence':<12} {label}: {d.case}: {d.message} "
                         f"(in the suite: rastercheck run --case '{d.case}' fails {d.check}{shrunk})")
        if len(every) > CARD_DEFECTS:
            lines.append(f"{'':<12} ... {len(every) - CARD_DEFECTS} more scenes with a defect, each with its evidence, "
                         "in --json and on the fingerprint page (rastercheck run)")
        return "\n".join(lines)


def repro_size(payload: dict[str, Any]) -> int:
    """The primitives of a repro's case JSON (triangles, paths or line strips)."""
    return len(payload.get("positions") or payload.get("paths") or payload.get("lines") or [])


def _compact_repr(convention: Convention) -> str:
    """The card's ``Convention(...)`` line with a sample pattern in a few words (the JSON
    keeps its offsets): ``samples=4`` for a standard one (as it is declared), else its
    description (:func:`harness.contract.samples.describe_pattern`) in angle brackets."""
    samples = convention.samples
    if samples is None:
        return repr(convention)
    from harness.contract.samples import describe_pattern

    said = repr(samples) if len(samples) <= 2 else \
        str(len(samples)) if STANDARD_PATTERNS.get(len(samples)) == samples else f"<{describe_pattern(samples)}>"
    return repr(convention).replace(f"samples={samples!r}", f"samples={said}")


def identify(rasterizer: Rasterizer, seed: int = 0, call: Call | None = None) -> Fingerprint:
    """The convention that best explains ``rasterizer``, its residual, and other facts.

    Parameters
    ----------
    rasterizer : Rasterizer
    seed : int
        Seeds the scenes.
    call : Call or None
        How the rasterizer is called (a scene in, an outcome out); None calls it in this
        process (:class:`harness.engine.isolation.InProcess`). An outcome with an error counts as
        the rasterizer raising: each probe reports it, and nothing here raises for it.
    """
    tally = CallTally(InProcess(rasterizer) if call is None else call)
    call = tally
    kinds = scene_kinds_of(rasterizer)
    # the kinds identify composes below; any other kind brings its own fit (its probes hook)
    own = [KINDS[k] for k in kinds if k not in (TRIANGLES.name, PATHS.name, LINES.name)]
    if own and len(own) == len(kinds):
        fingerprint = _identify_own_kind_only(rasterizer.name, call, seed, own[0])
        own = own[1:]
    elif "lines" in kinds and "triangles" not in kinds and "paths" not in kinds:
        fingerprint = _identify_lines_only(rasterizer.name, call, seed, received_of(rasterizer))
    else:
        if "paths" in kinds:
            fingerprint = _identify_paths(rasterizer, call, seed)
        else:
            fingerprint = _identify_triangles(rasterizer.name, call, seed, received_of(rasterizer))
        if "lines" in kinds:
            _with_lines(fingerprint, call, seed, received_of(rasterizer))
    for kind in own:
        fit = kind.hook("probes")(call, fingerprint.convention, seed)
        fingerprint.kind_fits[kind.name] = fit
        fingerprint.facts[kind.name] = fit.describe()
    # how many calls timed out or failed, and which: the card always says
    fingerprint.calls = tally
    fingerprint.facts["calls"] = tally.text + ("; the fit is on the rest" if fingerprint.unanswered
                                               and fingerprint.no_answers is None
                                               else "")
    return fingerprint


def _identify_own_kind_only(name: str, call: Call, seed: int, kind: PrimitiveKind[Any]) -> Fingerprint:
    """:func:`identify` on a rasterizer that takes only a kind with a fit of its own
    (points): that fit is the fingerprint's convention, residual and runner-up."""
    fit = kind.hook("probes")(call, None, seed)
    convention = Convention() if fit.convention is None else fit.convention
    fingerprint = Fingerprint(name, convention, fit.residual if fit.convention is not None else max(1, fit.pixels), fit.pixels,
                              fit.runner_up, {kind.name: fit.describe()}, (), {})
    fingerprint.kind_fits[kind.name] = fit
    return fingerprint


# The suite's cases for a rasterizer's scene kind of the triangle cases a probe drew, and the
# call that draws them (a paths-only rasterizer's: the same triangles as paths).
SuiteView = Callable[[list["Case"]], tuple[list["Case"], Call]]


def _identify_triangles(name: str, call: Call, seed: int, received: Callable[[Scene], Scene] | None,
                        suite: SuiteView | None = None) -> Fingerprint:
    """:func:`identify` on triangles (``call`` takes triangle scenes). Where a probe saw a
    defect (not watertight, the viewport edge, zero-area or non-finite triangles drawn),
    the suite's cases it drew are judged as ``run`` judges them, each failure kept as
    evidence with a minimal repro (:func:`harness.identify.triangle_defects.suite_defects`); ``suite`` gives
    those cases for the rasterizer's scene kind (the triangle cases themselves unless given)."""
    from cases.degenerate import degenerate_cases
    from cases.partitions import partition_cases
    from cases.paths import viewport_cases

    def view(cases: list[Case]) -> tuple[list[Case], Call]:
        return (cases, call) if suite is None else suite(cases)

    kind = coverage_kind(call)
    if kind.model is not None and not kind.model.single_sample:
        return _identify_coverage(name, call, seed, kind)
    ties = fit_ties(call, seed)
    snapping = fit_snapping(call, seed, ties)
    inputs = fit_input(call, seed, ties, snapping)
    convention = inputs.convention
    drawn = list(inputs.drawn)
    residual = sum(d.mismatches(convention) for d in drawn)
    rule = None
    if residual:  # no sample point explains it: a coverage rule decided on the pixel's square may
        rule = fit_rule_beside(call, seed, convention, drawn)
        if rule.chosen:
            convention, drawn, residual = rule.convention, list(rule.drawn), rule.mismatches
            # the sample point's snapping and input, and what they left undecided, no longer stand
            ambiguous: tuple[str, ...] = tuple(c.describe() for c in rule.fit.ambiguous)
    # refitted beside an input that moves the lattice's vertices, the runner-up is the input fit's
    runner_up = ((ties.runner_up.describe(), ties.runner_up_mismatches) if inputs.runner_up is None
                 else (inputs.runner_up[0].describe(), inputs.runner_up[1]))
    if rule is not None and rule.chosen:  # the sample point is the runner-up of the rule that replaced it
        runner_up = (rule.before.describe(), rule.before_mismatches)
    # in the card's order; a probe that has nothing to say is None
    probes: dict[str, Fact | None] = {
        "culling": ties.culling,
        "sample sweep": ties.sweep,
        "rounding": snapping.rounding_fit,
        "input": inputs,
        "coverage rule": rule,
        "residual lies": residual_lies(ties.drawn, convention) if residual and convention.model.sample_point else None,
        "viewport edge": viewport_edge(call, seed),
        "epsilon": epsilon(call, convention, received),
        "zero area": zero_area(call),
        "non-finite": non_finite(call),
        "watertight": _watertight_of(view(partition_cases(seed)), seed, convention, name),
        "snapping": snapping,
        "vertex sweep": ties.vertex.judged(snapping.bits, snapping.rounding),
        "unanswered": unanswered(drawn),
    }
    # the suite's cases behind each defect seen, judged as run judges them
    degenerate = {c.id: c for c in degenerate_cases(seed)}
    edge, flat, nan, tiny = probes["viewport edge"], probes["zero area"], probes["non-finite"], probes["epsilon"]
    if isinstance(tiny, Epsilon) and tiny.wrong:
        # the suite holds the probe's scene at pixel centres: judged there against the convention fitted
        probes["epsilon"] = replace(tiny, defects=suite_defects(*_swap(view([degenerate[EPSILON_CASE]])), {"conformance"},
                                                                 convention, name))
    if isinstance(edge, ViewportEdge) and edge.changed:
        probes["viewport edge"] = replace(edge, defects=suite_defects(*_swap(view(viewport_cases(seed))), {"conformance"},
                                                                       convention, name))
    if isinstance(flat, ZeroArea) and flat.pixels:
        probes["zero area"] = replace(flat, defects=suite_defects(*_swap(view([degenerate[ZERO_AREA_CASE]])), {"conformance"},
                                                                   convention, name))
    if isinstance(nan, NonFinite) and nan.wrong:
        probes["non-finite"] = replace(nan, defects=suite_defects(
            *_swap(view([degenerate[c] for c in NON_FINITE_CASES.values()])), {"conformance"}, convention, name))
    found = {label: fact for label, fact in probes.items() if fact is not None}
    return Fingerprint(name, convention, residual, sum(d.pixels for d in drawn),
                       runner_up, {k: f.text for k, f in found.items()},
                       ambiguous if rule is not None and rule.chosen else
                       (() if inputs.moot_snapping else snapping.ambiguous) + tuple(f"{i} input" for i in inputs.ambiguous),
                       found, unanswered=len({id(d) for d in drawn if d.coverage is None}))


def _swap(view: tuple[list[Case], Call]) -> tuple[Call, list[Case]]:
    """(cases, call) as (call, cases), the order the probes take them in."""
    return view[1], view[0]


def _watertight_of(view: tuple[list[Case], Call], seed: int, convention: Convention, name: str) -> Watertight:
    """The watertight probe on the suite's partitions for the rasterizer's scene kind."""
    cases, call = view
    return watertight_partitions(call, seed, cases, convention, name)


def _identify_paths(rasterizer: Rasterizer, call: Call, seed: int) -> Fingerprint:
    """:func:`identify` for a path-taking rasterizer: first the fill rule drawn for each
    rule it declares, then the triangle fingerprint (through one-contour paths when it takes
    no triangles), then the convention for paths, compared with the triangle one and tried
    on genuine paths under each honoured rule. Only a single-sample rasterizer's path
    convention is fitted (the triangle probes it reuses are single-sample ones)."""
    from harness.identify.path_probes import PathFit, as_paths, fill_rules, fit_path_convention, path_fit_of, with_lattice

    rules = fill_rules(call, fill_rules_of(rasterizer))
    rule = rules.fit_rule
    received = received_of(rasterizer)
    if "triangles" in scene_kinds_of(rasterizer):
        fingerprint = _identify_triangles(rasterizer.name, call, seed, received)
        path: PathFit | None = None
        if fingerprint.model.single_sample:
            path = fit_path_convention(call, seed, rule, fingerprint.convention)
    else:
        # it takes paths only: every triangle probe goes through one-contour paths
        from cases.paths import triangle_cases_as_paths

        def as_suite(cases: list[Case]) -> tuple[list[Case], Call]:
            # the path suite's own cases of these triangles, under the rule fitted
            return triangle_cases_as_paths(cases, (rule,)), call

        fingerprint = _identify_triangles(rasterizer.name, as_paths(call, rule), seed, _received_as_triangles(received, rule),
                                          as_suite)
        path = None
        if fingerprint.model.single_sample:
            path = path_fit_of(fingerprint.convention, fingerprint.residual, fingerprint.pixels, fingerprint.runner_up,
                               fingerprint.ambiguous, None, rule, fingerprint.unanswered)
    if path is None:
        path = PathFit(None, rule=rule, skipped=f"{fingerprint.coverage_kind} coverage (the path fit is single-sample)")
    else:
        path = with_lattice(path, call, rules.honoured, seed)
    fingerprint.fill_rules = rules.drawn
    fingerprint.path_convention = path.convention
    if path.convention is None and not fingerprint.convention.model.paths:
        # identified at a library's levels (triangles only): its paths judged by the exact area, as before
        fingerprint.path_convention = _unquantised(fingerprint)
    fingerprint.path_fit = path
    fingerprint.facts["fill rules"] = rules.text
    fingerprint.facts["paths"] = path.text
    if path.lattice is not None:
        fingerprint.facts["real paths"] = path.lattice.text
    fingerprint.probes["fill rules"] = rules
    fingerprint.probes["paths"] = path
    return fingerprint


def _identify_lines_only(name: str, call: Call, seed: int, received: Callable[[Any], Any] | None = None) -> Fingerprint:
    """:func:`identify` for a rasterizer that takes only lines: the line fit is the
    fingerprint (no triangle is sent)."""
    from harness.identify.line_probes import fit_lines

    fit = fit_lines(call, seed, None, received)
    anti_aliased = _anti_aliased_line_fit(fit)
    if anti_aliased is not None:
        convention, residual, pixels, model = anti_aliased
        fingerprint = Fingerprint(name, convention, residual, pixels, None, {}, (), unanswered=len(fit.unanswered),
                                  coverage_kind="area")
        _record_lines(fingerprint, fit)
        fingerprint.line_convention, fingerprint.line_rule = None, convention.line
        fingerprint.facts["line model"] = model
        return fingerprint
    convention = fit.convention or Convention()
    runner_up: tuple[str, int] | None = fit.runner_up
    residual = fit.residual
    if fit.convention is None:  # nothing measured: never claimed
        residual, runner_up = max(1, fit.pixels), ("any line convention: " + fit.skipped, 0)
    fingerprint = Fingerprint(name, convention, residual, fit.pixels, runner_up, {}, fit.ambiguous,
                              unanswered=len(fit.unanswered))
    _record_lines(fingerprint, fit)
    return fingerprint


def _anti_aliased_line_fit(fit: Any) -> tuple[Convention, int, int, str] | None:
    """For a rasterizer taking only lines whose answers carry alphas: the one anti-aliased
    line model, the exact area of the w-wide butt-capped rectangle, within the largest
    |alpha - exact area| its probes showed (a tolerance measured on them), with the
    residual the (segment, pixel)s beyond half a level of that area; None otherwise."""
    from harness.identify.area_probes import SLACK, alpha_differences
    from harness.oracle.coverage import exact_coverage

    drawn = [d for d in fit.drawn if d.coverage is not None]
    if not drawn or all(d.coverage.alpha is None for d in drawn):
        return None
    exact = Convention(coverage="area", line=LineRule("rectangle"))
    errors: list[NDArray[np.float64]] = []
    for d in drawn:
        scene = d.judged if d.judged is not None else d.scene
        errors.append(np.abs(alpha_differences(d.coverage, exact_coverage(scene, exact), scene)))
    every = np.concatenate(errors) if errors else np.zeros(0)
    worst = float(every.max(initial=0.0))
    convention = replace(exact, tolerance=rounded_up_tolerance(worst)) if worst > exact.alpha_tolerance + SLACK else exact
    residual = int(np.sum(every > exact.alpha_tolerance + SLACK))
    model = (f"anti-aliased: the exact area of the w-wide butt-capped rectangle, |alpha - area| max {worst:.3g} over "
             f"{every.size} (segment, pixel)s")
    return convention, residual, int(every.size), model


def _with_lines(fingerprint: Fingerprint, call: Call, seed: int, received: Callable[[Any], Any] | None = None) -> None:
    """Add the line fit to a triangle (or path) fingerprint: the rule found becomes its
    convention's ``line`` (when that convention is single-sample: lines are), the whole
    line convention its ``line_convention``."""
    from harness.identify.line_probes import fit_lines

    fit = fit_lines(call, seed, _line_base(fingerprint.convention), received)
    anti_aliased: Convention | None = None
    if fit.convention is not None and fingerprint.convention.model.single_sample:
        fingerprint.convention = replace(fingerprint.convention, line=fit.convention.line)
    elif fingerprint.convention.model.alphas:
        anti_aliased = _anti_aliased_lines(fingerprint)
        levels = _unquantised(fingerprint)  # a library's levels define no lines: the exact area it was fitted to
        if levels is not None:
            anti_aliased = replace(levels, line=LineRule("rectangle"))
    _record_lines(fingerprint, fit)
    if anti_aliased is not None and anti_aliased != fingerprint.convention:
        fingerprint.line_convention = anti_aliased
        fingerprint.line_rule = anti_aliased.line


def _anti_aliased_lines(fingerprint: Fingerprint) -> Convention:
    """The convention an anti-aliaser's lines are judged by. Anti-aliased lines have one
    model, the exact area of the w-wide butt-capped rectangle (:mod:`harness.oracle.area_lines`):
    under analytic area the triangles' convention with that line rule; under a sampled
    model that defines no lines (a supersampler's grid, cairo's rows), analytic area with
    the same levels and input, within the largest |alpha - exact area| the sweeps measured
    (the triangles' own error against the exact area: the tolerance such a rasterizer's
    triangles would be judged by without its model). Sets the fact "line model"."""
    convention = fingerprint.convention
    if convention.line.rule != "rectangle":
        fingerprint.convention = convention = replace(convention, line=LineRule("rectangle"))
    said = "anti-aliased: judged against the exact area of the w-wide butt-capped rectangle"
    if convention.model.lines:
        fingerprint.facts["line model"] = said
        return convention
    sweeps = fingerprint.probes.get("sweeps")
    error = float(getattr(sweeps, "max_error", 0.0))
    lines = Convention(coverage="area", levels=convention.levels, input=convention.input,
                       subpixel_bits=convention.subpixel_bits, snap_rounding=convention.snap_rounding,
                       tolerance=rounded_up_tolerance(error), line=LineRule("rectangle"))
    fingerprint.facts["line model"] = (f"{said}, within {lines.alpha_tolerance:.3g} (the largest |alpha - exact area| "
                                       f"of its triangles: its own model, {convention.model.name}, defines no lines)")
    return lines


def _unquantised(fingerprint: Fingerprint) -> Convention | None:
    """For an anti-aliaser identified at a library's levels (``Convention.quantisation``,
    defined for triangles): the candidate before them, the exact area within its measured
    tolerance, by which its lines and paths are judged; None otherwise."""
    fit = getattr(fingerprint.probes.get("sweeps"), "quantisation", None)
    if fit is None or fit.chosen is None or fingerprint.convention.quantisation == "nearest":
        return None
    nearest: Convention | None = fit.nearest
    return nearest


def _line_base(convention: Convention) -> Convention:
    """The triangles' convention as the line fit starts from it: itself when lines are
    defined under its coverage model; under a coverage rule (which defines no lines), the
    sample point, tie rule, input and snapping beside it, one sample per pixel."""
    if convention.model.lines:
        return convention
    return Convention(sample=convention.sample, tie=convention.tie, subpixel_bits=convention.subpixel_bits,
                      cull=convention.cull, snap_rounding=convention.snap_rounding, input=convention.input)


def _record_lines(fingerprint: Fingerprint, fit: LineFit) -> None:
    """The line fit's fields, facts and probes on ``fingerprint``."""
    fingerprint.line_fit = fit
    fingerprint.line_convention = fit.convention
    fingerprint.line_rule = None if fit.convention is None else fit.convention.line
    fingerprint.facts["lines"] = fit.text
    fingerprint.probes["lines"] = fit
    if fit.rule_scores:
        fingerprint.facts["line rules"] = fit.rules_text
    if fit.rounding is not None:
        fingerprint.facts["line snap"] = fit.rounding.text
    if fit.sweep is not None and fit.rule is not None and fit.rule.rule == "rectangle":
        fingerprint.facts["line sample"] = fit.sweep.text
    if fit.wide is not None:
        fingerprint.facts["wide lines"] = fit.wide.text
        fingerprint.probes["wide lines"] = fit.wide


def _line_convention_dict(fit: LineFit) -> dict[str, Any] | None:
    """:meth:`Fingerprint.to_dict`'s ``line_convention``: the line convention in plain data
    (None when no fit was made: then ``skipped`` says why in the facts)."""
    line = fit.convention
    if line is None:
        return None
    rule = line.line
    return {"convention": line.describe_lines(), "rule": rule.rule,
            "last_pixel": None if rule.rule in AREA_LINE_RULES else rule.last_pixel,
            "rounding": rule.rounding if rule.rule == "bresenham" else None,
            "ties": rule.ties if rule.rule == "bresenham" else None,
            "direction": rule.direction if rule.rule == "bresenham" else None,
            "wide": rule.wide if rule.diamond else None,
            "cap": rule.cap if rule.rule == "rectangle" else None,
            "sample": list(line.sample) if rule.rule in AREA_LINE_RULES else None,
            "tie": line.tie if rule.rule in AREA_LINE_RULES else None,
            "subpixel_bits": line.subpixel_bits, "snap_rounding": line.snap_rounding,
            "exact": fit.exact, "residual": fit.residual, "pixels": fit.pixels,
            "runner_up": list(fit.runner_up) if fit.runner_up else None, "ambiguous": list(fit.ambiguous),
            "rule_scores": dict(fit.rule_scores), "same_as_triangles": fit.same_as_triangles,
            "differences": list(fit.differences), "wide_lines": None if fit.wide is None else fit.wide.text}


def _received_as_triangles(received: Callable[[Scene], Scene] | None, rule: str) -> Callable[[Scene], Scene] | None:
    """A paths-only rasterizer's ``received`` seen on triangle scenes: each sent as one-contour
    paths, the paths it reports receiving read back as triangles (None when that fails)."""
    from harness.identify.path_probes import triangle_paths

    if received is None:
        return None
    paths_received: Callable[[AnyScene], AnyScene] = received  # type: ignore[assignment]

    def as_triangles(scene: Scene) -> Scene:
        got = paths_received(triangle_paths(scene, rule))
        # isinstance: what a plugin's received() answered is checked for its class, not dispatched on
        if isinstance(got, PathScene):
            return Scene(got.width, got.height, got.vertices.reshape(-1, 3, 2))
        if not isinstance(got, Scene):
            raise ValueError(f"received() answered a path scene with a {got.kind} scene")
        return got

    return as_triangles


def _identify_coverage(name: str, call: Call, seed: int, kind: CoverageKindFact) -> Fingerprint:
    """identify for an anti-aliaser (the sweeps: analytic or supersampled, grid, levels)
    or a multisample rasterizer (the pattern and its tie rule, then watertightness sample
    by sample); the single-sample probes would be meaningless there. Each distinct scene
    is drawn once (the samples' probes share them)."""
    call = Remembered(call)
    probes: dict[str, Fact] = {"coverage": kind}
    lines = {"coverage": kind.text}
    if kind.model is not None and kind.model.alphas:
        sweeps = alpha_sweeps(call, seed)
        probes["sweeps"] = sweeps
        lines |= sweeps.lines()
        convention = sweeps.convention or Convention(coverage="area")
        residual, pixels, runner_up = sweeps.residual, sweeps.pixels, sweeps.runner_up
        unanswered = sum(x.coverage is None for x in sweeps.drawn)
        if sweeps.model is None:  # nothing measured: never claimed
            runner_up = ("any area convention: the sweeps were not answered", 0)
    else:
        n = max(kind.indices, default=-1) + 1
        pattern = sample_positions(call, n, seed)
        unanswered = pattern.unanswered + bool(pattern.error)
        probes["pattern"] = pattern
        lines["pattern"] = pattern.text
        # the offsets read under left and top edges, seen from the other side: a sample
        # dropped near edges is no wrong pattern
        sides = sample_sides(call, pattern.offsets, pattern.culling.cull if pattern.culling is not None else "none",
                             pattern.resolution)
        probes["sample sides"] = sides
        if sides.dropped:
            lines["pattern"] = f"{sides.text}; as read under left and top edges: {pattern.text}".replace(
                f" -- not the standard {n}x pattern", "")
        if pattern.vertex is not None:
            probes["vertex sweep"] = pattern.vertex
            lines["vertex sweep"] = pattern.vertex.text + " (sample 0)"
        # sample by sample, as the suite's watertight check judges a multisample answer
        at = [pattern.convention.at_sample(s) if pattern.convention is not None else None for s in range(n)]
        tight: list[Watertight] = []
        for s in range(n):  # repros for the first leaking sample only: the others leak on the same scenes
            leaked = any(w.defects for w in tight)
            tight.append(watertight_partitions(layered(call, s), seed, convention=at[s], name=name,
                                               repros=0 if leaked else REPROS))
        probes |= {f"watertight {s}": w for s, w in enumerate(tight)}
        leaky = [f"sample {s}: {w.text}" for s, w in enumerate(tight) if w.holes or w.doubles or w.strays or w.unanswered]
        if tight:
            lines["watertight"] = "; ".join(leaky) if leaky else f"every sample: {tight[0].text}"
        if pattern.convention is None:
            # none recovered: a stand-in for the checks, which the card names as one
            convention = Convention(samples=n) if n in STANDARD_PATTERNS else Convention()
            residual, pixels, runner_up = max(1, pattern.fragments), pattern.fragments, None
        else:
            convention = pattern.convention
            residual, pixels, runner_up = pattern.residual, pattern.fragments, pattern.runner_up
            # the input precision, at sample 0 (every sample receives the same coordinates)
            inputs = fit_input_beside(layered(call, 0), seed, convention.at_sample(0), [], [])
            probes["input"] = inputs
            lines["input"] = inputs.text + " (sample 0)"
            if inputs.input != "float64":  # the pattern's scenes judged again, as the input is received
                convention = replace(convention, input=inputs.input, subpixel_bits=inputs.convention.subpixel_bits,
                                     snap_rounding=inputs.convention.snap_rounding)
                residual = sum(d.mismatches(convention.at_sample(s)) for layers in pattern.drawn for s, d in enumerate(layers))
            residual += inputs.mismatches
            pixels += sum(d.pixels for d in inputs.drawn)
    probes |= {"zero area": zero_area(call), "non-finite": non_finite(call)}
    lines |= {"zero area": probes["zero area"].text, "non-finite": probes["non-finite"].text,
              "calls": f"{call.calls + 1} rasterizer calls"}  # and the one that read the kind
    return Fingerprint(name, convention, residual, pixels, runner_up, lines, (), probes,
                       coverage_kind=kind.coverage_kind or SINGLE.coverage_kind,
                       unanswered=unanswered)


def verdict_cases(fingerprint: Fingerprint, seed: int, scene_kinds: tuple[str, ...],
                  kind: CoverageKind) -> list[Case | MotionCase]:
    """The scenes a declared convention of coverage ``kind`` is judged on before identify
    calls it confirmed or consistent (:data:`VERDICT_CHECKS`): the probe scenes identify
    drew for that kind (the alpha sweeps, the multisample pattern's scenes) as cases
    ``identify/<probe>/<k>``, then the suite's lattice and float triangles, its planar
    partitions (seams; per-sample watertight scenes) and, for area coverage, its sub-pixel
    translations (popping); for a line drawer its line segments, for a path filler its
    path shapes (each scene kind's ``verdict_cases`` hook, :mod:`harness.kinds`). Each rasterizer is
    handed only the kinds it takes."""
    from harness.contract.case import Case

    cases: list[Case | MotionCase] = []
    drawn: dict[str, tuple[Any, ...]] = {}
    model = model_named(kind)
    sweeps, pattern = fingerprint.probes.get("sweeps"), fingerprint.probes.get("pattern")
    if model.alphas and sweeps is not None:
        drawn["sweeps"] = tuple(getattr(sweeps, "drawn", ()))
    if model.sample_ids and pattern is not None:
        drawn["pattern"] = tuple(d for group in getattr(pattern, "drawn", ()) for d in group)
    for probe, scenes in drawn.items():
        cases += [Case(f"identify/{probe}/{k}", d.scene) for k, d in enumerate(scenes) if TRIANGLES.owns(d.scene)]
    for name, primitive in KINDS.items():  # in SCENE_KINDS's order: triangles, paths, lines
        if name in scene_kinds:
            cases += primitive.hook("verdict_cases")(seed, model)
    return cases


def triangle_verdict_cases(seed: int, model: CoverageModel) -> list[Case | MotionCase]:
    """The triangles' ``verdict_cases`` hook (:func:`verdict_cases`): the suite's lattice
    and float triangles, its planar partitions (seams; per-sample watertight scenes) and,
    for area coverage, its sub-pixel translations (popping)."""
    from cases.motion import motion_cases
    from cases.partitions import partition_cases
    from cases.suites import conformance_cases

    cases: list[Case | MotionCase] = list(conformance_cases(seed))
    if not model.single_sample:
        cases += partition_cases(seed)
    if model.alphas:
        # the plain geometries' sixteenth-pixel translations (no texture, no projected mesh)
        cases += [m for m in motion_cases(seed, meshes=False) if m.id.endswith("-1/16")
                  and m.id.split("/")[1] in ("triangle", "fan-8", "grid-3x3")]
    return cases


def path_verdict_cases(seed: int, model: CoverageModel) -> list[Case | MotionCase]:
    """The paths' ``verdict_cases`` hook: the suite's path shapes (single-sample only)."""
    from cases.paths import path_cases

    return [c for c in path_cases(seed) if c.family == "paths"] if model.single_sample else []


def line_verdict_cases(seed: int, model: CoverageModel) -> list[Case | MotionCase]:
    """The lines' ``verdict_cases`` hook: the suite's line segments (single-sample only)."""
    from cases.lines import line_cases

    return [c for c in line_cases(seed) if c.family == "lines"] if model.single_sample else []


def identify_isolated(rasterizer: Rasterizer, seed: int = 0, timeout: float = 600.0,
                      call_timeout: float | TimeLimit | None = None) -> Fingerprint:
    """:func:`identify` with every rasterize call in a forked worker process (a
    :class:`harness.engine.session.Session`'s :class:`harness.engine.isolation.Worker`), so
    that a library's process-wide state (an EGL display, a crash, a hang) stays out of the
    caller: a call that crashes or hangs counts as raising, and identification goes on (the
    probes fit on the calls answered, and the card counts and names the others).

    ``timeout`` bounds the whole identification: it is checked between calls, and a call
    never runs past it (then TimeoutError, naming the rasterizer); ``call_timeout`` is the
    time-limit policy of each call (:class:`harness.engine.isolation.TimeLimit`; a number is its
    cap, ``timeout`` when None): a call cut off by its limit is asked again once with a
    longer one before it counts as a timeout.
    """
    deadline = time.monotonic() + timeout

    def expired() -> TimeoutError:
        return TimeoutError(f"identify {rasterizer.name}: no answer within {timeout:g} s")

    from harness.engine.session import Session

    with Session(rasterizer, call_timeout or timeout, deadline=deadline) as session:

        def call(scene: Scene) -> Outcome:
            if time.monotonic() >= deadline:
                raise expired()
            outcome = session.call(scene)
            if outcome.timed_out and time.monotonic() >= deadline:
                raise expired()
            return outcome

        return identify(rasterizer, seed, call)


class Identified:
    """A rasterizer that declares no convention, checked against the one identified for it."""

    def __init__(self, inner: Rasterizer, fingerprint: Fingerprint) -> None:
        self.inner = inner
        self.name = inner.name
        self.convention = fingerprint.convention
        self.interpolates = interpolates_of(inner)
        if hasattr(inner, "received"):
            self.received = inner.received
        if hasattr(inner, "input"):  # the input precision it declares (read by received_of)
            self.input = inner.input
        self.fingerprint = fingerprint
        self.scene_kinds = scene_kinds_of(inner)
        path = fingerprint.path_convention
        if path is not None and replace(path, line=self.convention.line) != fingerprint.convention:
            self.path_convention = path  # its paths are judged by what they follow (the line rule plays no part)
        if fingerprint.line_convention is not None and fingerprint.line_convention != fingerprint.convention:
            # its lines are judged by what they follow (:func:`harness.contract.protocol.convention_for` reads this)
            self.line_convention = fingerprint.line_convention
        for kind_name, fit in fingerprint.kind_fits.items():
            attribute = KINDS[kind_name].convention_attribute
            if attribute is not None and fit.convention is not None and fit.convention != fingerprint.convention:
                setattr(self, attribute, fit.convention)  # its points are judged by what they follow (convention_for)
        for attribute in ("path_convention", "line_convention"):
            declared = getattr(inner, attribute, None)
            if isinstance(declared, Convention):  # what the plugin declares for a kind beats what identify found
                setattr(self, attribute, declared)
        honoured = fingerprint.honoured_fill_rules
        if honoured is not None:
            # handed only the path scenes of the rules it was seen to draw as asked
            # (:func:`harness.contract.protocol.takes` reads this as it reads a plugin's own)
            self.fill_rules = tuple(rule for rule in fill_rules_of(inner) if rule in honoured)
        elif hasattr(inner, "fill_rules"):
            self.fill_rules = fill_rules_of(inner)

    def rasterize(self, scene: AnyScene) -> Coverage:
        return self.inner.rasterize(scene)


def identify_all(rasterizers: list[Rasterizer], seed: int = 0, *, everyone: bool = False,
                 call_timeout: float | TimeLimit = 60.0, report: Callable[[str], None] | None = None,
                 jobs: int = 1) -> tuple[list[Rasterizer], dict[str, dict[str, Any]]]:
    """Identify the rasterizers that declare no convention (all of them with
    ``everyone``), each in a process of its own, ``jobs`` of them side by side; one that
    declares none is then checked against the one identified for it (:class:`Identified`).
    A failure to identify is kept as an error entry, and that rasterizer runs without a
    convention.

    Returns
    -------
    rasterizers : the same, in the same order, undeclared ones wrapped
    fingerprints : name -> :meth:`Fingerprint.to_dict` or ``{"error": ...}``
    """
    from concurrent.futures import ThreadPoolExecutor

    fingerprints: dict[str, dict[str, Any]] = {}

    def one(r: Rasterizer) -> Rasterizer:
        if r.convention is not None and (not everyone or isinstance(r, Identified)):
            return r
        try:
            fingerprint = identify_isolated(r, seed, timeout=max(300.0, 10 * TimeLimit.of(call_timeout).cap),
                                            call_timeout=call_timeout)
        except Exception as exc:
            fingerprints[r.name] = {"error": f"{type(exc).__name__}: {exc}"}
            if report is not None:
                report(f"identify {r.name}: {type(exc).__name__}: {exc}")
            return r
        fingerprints[r.name] = fingerprint.to_dict()
        # a rasterizer that declares no convention is checked against the one identified for it
        return Identified(r, fingerprint) if r.convention is None else r

    # each identify runs in a worker process of its own: threads only wait on them
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        out = list(pool.map(one, rasterizers))
    return out, {r.name: fingerprints[r.name] for r in rasterizers if r.name in fingerprints}
