"""identify's robustness probes on triangles, each giving one typed fact: the viewport edge
(:func:`viewport_edge`), tiny triangles (:func:`epsilon`), degenerate and non-finite input
(:func:`zero_area`, :func:`non_finite`), watertightness (:func:`watertight_partitions`), the
suite's defects judged as ``run`` judges them (:func:`suite_defects`) and the fit scenes left
unanswered (:func:`unanswered`).

Each calls the rasterizer only through a :data:`~harness.engine.isolation.Call`, as the probes
of :mod:`harness.identify.triangle_probes` do; an outcome with an error is reported, never
raised.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cases.partitions import partition_cases
from harness.checks import Result, watertight
from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import SINGLE
from harness.contract.scenes import Scene
from harness.diagnose.repro import grown_screen
from harness.engine.isolation import Call, describe
from harness.geometry.keys import unique
from harness.identify.triangle_probes import Drawn, draw, send
from harness.kinds import TRIANGLES
from harness.oracle.coverage import exact_coverage

__all__ = [
    "ViewportEdge", "Epsilon", "ZeroArea", "NonFinite", "Watertight", "Defect", "Unanswered",
    "viewport_edge", "epsilon", "zero_area", "non_finite", "watertight_partitions", "unanswered", "suite_defects",
    "ZERO_AREA_CASE", "NON_FINITE_CASES", "EPSILON_CASE",
]

# --- the viewport edge ------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ViewportEdge:
    """On-screen pixels that change when triangles cross the viewport edge, against the
    same triangles in a grown screen (pixels drawn beyond the edge count as changes too);
    ``error`` when it could not be measured."""

    changed: int
    total: int
    error: str = ""
    defects: tuple[Defect, ...] = field(default=(), compare=False)  # the suite's cases that fail for it

    @property
    def text(self) -> str:
        if self.error:
            return f"not measured: {self.error}"
        if self.changed == 0:
            return f"exact ({self.total} on-screen pixels compared)"
        return (f"{self.changed} of {self.total} on-screen pixels change when triangles cross it: "
                "it treats them differently (e.g. clips them before snapping)")


def viewport_edge(call: Call, seed: int, margin: int = 8) -> ViewportEdge:
    """Whether triangles crossing the viewport edge (the suite's ``lattice/bits-{0,2,4}``)
    cover the same on-screen pixels as when the screen is grown
    (:func:`harness.diagnose.repro.grown_screen`) so that nothing crosses it:
    convention-free, the rasterizer against itself (a clipper that moves vertices before
    snapping shows up here)."""
    from cases.paths import viewport_cases

    changed = total = 0
    for case in viewport_cases(seed):  # the suite's lattice/bits-{0,2,4}: 64 px, a power of two, as tiles often are
        crossing = TRIANGLES.narrow(case.scene)
        size = crossing.width
        grown = grown_screen(crossing, margin)
        # never for these scenes: whole-pixel moves of small dyadic numbers are exact
        if grown is None or not TRIANGLES.owns(grown):
            return ViewportEdge(0, 0, "the grown screen would round the scene")
        a, b = draw(call, crossing), draw(call, grown)
        if a.coverage is None or b.coverage is None:
            return ViewportEdge(0, 0, "the rasterizer raised")
        ta, xa, ya = a.coverage.pixels()
        tb, xb, yb = b.coverage.pixels()
        xb, yb = xb - margin, yb - margin
        keep = (xb >= 0) & (xb < size) & (yb >= 0) & (yb < size)
        base = 4 * (size + 2 * margin)  # room for any on-screen or grown-screen pixel

        def keys(t: NDArray, x: NDArray, y: NDArray, base: int = base) -> NDArray:
            return unique((t * base + (y + margin)) * base + (x + margin))

        mine, inside = keys(ta, xa, ya), keys(tb[keep], xb[keep], yb[keep])
        merged = np.sort(np.concatenate([mine, inside]), kind="stable")  # two sorted runs: linear
        common = int(np.count_nonzero(merged[1:] == merged[:-1]))  # in both (each set has no repeats)
        changed += mine.size + inside.size - 2 * common
        total += inside.size
    return ViewportEdge(changed, total)


# --- tiny triangles ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Epsilon:
    """Tiny triangles decided unlike the convention (``wrong`` of ``triangles``, of which
    ``want`` should draw); ``as_received`` whether it is exact for the coordinates as the
    library receives them (None when it does not say what it receives, or is exact)."""

    triangles: int
    want: int
    wrong: int
    as_received: bool | None = None
    error: str = ""
    defects: tuple[Defect, ...] = field(default=(), compare=False)  # the suite's cases that fail for it

    @property
    def text(self) -> str:
        if self.error:
            return f"raises {self.error}"[:120]
        if self.wrong == 0:
            return f"exact: {self.want} of {self.triangles} tiny triangles (1e-3..1e-9 px) drawn, as the convention says"
        said = (f"{self.wrong} of {self.triangles} tiny triangles (1e-3..1e-9 px) decided unlike the convention "
                f"({self.want} should draw)")
        if self.as_received:
            said += "; exact for the coordinates as the library receives them (its input format rounds them)"
        return said


def epsilon(call: Call, convention: Convention, received: Callable[[Scene], Scene] | None = None) -> Epsilon:
    """Tiny triangles (1e-3 down to 1e-9 px across) around sample points, half of them
    holding their sample strictly inside and half just missing it, against the exact
    answer of ``convention``; ``received`` is the rasterizer's own account of how its input
    format rounds a scene (:func:`harness.contract.protocol.received_of`)."""
    from cases.degenerate import epsilon_scene

    scene = epsilon_scene(convention.sample)  # at pixel centres the suite's degenerate/epsilon/probe
    triangles = scene.positions
    got = draw(call, scene)
    if got.coverage is None:
        return Epsilon(len(triangles), 0, 0, error=describe(got.error))
    wrong = got.mismatches(convention)
    want = exact_coverage(scene, convention).n_pixels
    as_received = None
    if wrong and received is not None:
        try:
            rounded = received(scene)
        except Exception:  # a plugin's own account of its input may fail like anything else of it
            rounded = None
        if rounded is not None:
            as_received = Drawn(rounded, got.outcome).mismatches(convention) == 0
    return Epsilon(len(triangles), want, wrong, as_received)


# --- degenerate and non-finite input ------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ZeroArea:
    """Pixels drawn for a line-like and a point-like triangle (None when it raised)."""

    pixels: int | None
    error: str = ""
    defects: tuple[Defect, ...] = field(default=(), compare=False)  # the suite's cases that fail for it

    @property
    def text(self) -> str:
        if self.pixels is None:
            return f"raises {self.error}"
        return "draws nothing" if self.pixels == 0 else f"draws {self.pixels} pixels"


# the suite's cases identify's degenerate probes draw (:func:`cases.degenerate.probe_scenes`)
ZERO_AREA_CASE = "degenerate/zero-area/probe"
EPSILON_CASE = "degenerate/epsilon/probe"  # the epsilon probe's scene at pixel centres
NON_FINITE_CASES = {"NaN": "degenerate/non-finite/probe-nan", "inf": "degenerate/non-finite/probe-inf"}


def _probe_scene(case_id: str) -> Scene:
    from cases.degenerate import probe_scenes

    return probe_scenes()[case_id.removeprefix("degenerate/")][0]


def zero_area(call: Call) -> ZeroArea:
    """A collinear triangle and one with two equal vertices (the suite's
    ``degenerate/zero-area/probe``): an exact rasterizer draws nothing."""
    drawn = draw(call, _probe_scene(ZERO_AREA_CASE))
    if drawn.coverage is None:
        return ZeroArea(None, type(drawn.error).__name__)
    return ZeroArea(drawn.pixels)


@dataclass(frozen=True, slots=True)
class NonFiniteAnswer:
    """A triangle with a NaN or infinite coordinate beside a finite one: the pixels drawn
    for it and whether the finite one was drawn, or the error."""

    label: str
    covered: int = 0
    rest_drawn: bool = False
    error: str = ""

    @property
    def text(self) -> str:
        if self.error:
            return f"{self.label}: raises {self.error}"[:120]
        rest = "the rest drawn" if self.rest_drawn else "the finite triangle lost too"
        return f"{self.label}: {'covers nothing' if self.covered == 0 else f'DRAWS {self.covered} pixels'}, {rest}"


@dataclass(frozen=True, slots=True)
class NonFinite:
    """What a NaN and an infinite coordinate do."""

    answers: tuple[NonFiniteAnswer, ...]
    defects: tuple[Defect, ...] = field(default=(), compare=False)  # the suite's cases that fail for it

    @property
    def text(self) -> str:
        return "; ".join(a.text for a in self.answers)

    @property
    def wrong(self) -> bool:
        """Some non-finite triangle drew pixels, or took the finite one with it."""
        return any(not a.error and (a.covered or not a.rest_drawn) for a in self.answers)


def non_finite(call: Call) -> NonFinite:
    """A triangle with a NaN (then an infinite) coordinate beside a finite triangle (the
    suite's ``degenerate/non-finite/probe-nan`` and ``-inf``)."""
    answers = []
    for label, case_id in NON_FINITE_CASES.items():
        drawn = draw(call, _probe_scene(case_id))
        cov = drawn.coverage
        if cov is None:
            answers.append(NonFiniteAnswer(label, error=describe(drawn.error)))
            continue
        covered = int(np.sum((cov.triangle == 0) * np.maximum(cov.x1 - cov.x0, 0)))
        answers.append(NonFiniteAnswer(label, covered, 1 in set(cov.triangle.tolist())))
    return NonFinite(tuple(answers))


# --- watertightness -----------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Defect:
    """One scene on which a probe saw a defect: the suite's case it is (``case``, so that
    ``rastercheck run --case`` fails there too), the check that judges it, what is wrong
    (``message``), the check's evidence (the offending pixels and the primitives blamed),
    and a minimal repro (case JSON naming the check, :func:`harness.diagnose.repro.attach_repro`;
    None when none was made)."""

    case: str
    check: str
    message: str
    evidence: dict[str, Any] = field(default_factory=dict, compare=False)
    repro: dict[str, Any] | None = field(default=None, compare=False)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON and the fingerprint page."""
        return {"case": self.case, "check": self.check, "message": self.message, "evidence": dict(self.evidence),
                "repro": self.repro}


@dataclass(frozen=True, slots=True)
class Watertight:
    """Holes and double hits over the planar partitions (``unanswered`` of them gave an
    error and were not judged); ``defects`` the partitions that leak, each with its
    evidence and, for the first few, a minimal repro."""

    holes: int
    doubles: int
    partitions: int
    unanswered: int = 0
    defects: tuple[Defect, ...] = field(default=(), compare=False)
    strays: int = 0  # pixels wholly outside the union drawn

    @property
    def text(self) -> str:
        judged = self.partitions - self.unanswered
        if judged == 0:
            return f"not measured: the rasterizer raised on all {self.partitions} partitions"
        unjudged = f" ({self.unanswered} more unanswered)" if self.unanswered else ""
        if self.holes == self.doubles == self.strays == 0:
            return f"yes (no hole, no double hit on {judged} partitions){unjudged}"
        strays = f", {self.strays} stray hits outside" if self.strays else ""
        return f"no: {self.holes} holes, {self.doubles} double hits{strays} on {judged} partitions{unjudged}"


# leaking scenes shrunk to a minimal repro per probe (each shrink redraws its scene's parts)
REPROS = 2


def watertight_partitions(call: Call, seed: int, cases: Sequence[Case] | None = None, convention: Convention | None = None,
                          name: str = "identify", repros: int = REPROS) -> Watertight:
    """Every planar partition of the suite (``cases``: :func:`cases.partitions.partition_cases`
    unless given, e.g. the same partitions as paths for a paths-only rasterizer): holes and
    double hits, judged as the suite's watertight check judges them (under ``convention``,
    a hole or double hit its own snapped answer has too is excused). The first ``repros``
    leaking partitions are shrunk to a minimal repro (:func:`harness.diagnose.repro.attach_repro`)."""
    holes = doubles = strays = unanswered = 0
    partitions = list(partition_cases(seed) if cases is None else cases)
    defects: list[Defect] = []
    for case in partitions:
        cov = send(call, case.scene).coverage
        if cov is None:
            unanswered += 1
            continue
        r = _watertight(case, cov, convention)
        holes += int(r.metrics.get("holes", 0))
        doubles += int(r.metrics.get("double_hits", 0))
        strays += int(r.metrics.get("strays", 0))
        if r.status == "fail":
            defects.append(Defect(case.id, "watertight", r.message, _evidence_of(r),
                                  _repro(r, case, call, convention, name) if len(defects) < repros else None))
    return Watertight(holes, doubles, len(partitions), unanswered, tuple(defects), strays)


def _watertight(case: Case, coverage: Coverage, convention: Convention | None) -> Result:
    """The suite's watertight verdict on ``case`` (see :func:`harness.checks.watertight`)."""
    if convention is None or not convention.model.single_sample:
        return watertight(case, coverage)
    return watertight(case, coverage, convention, lambda: exact_coverage(case.scene, convention))


class _Named:
    """The name :func:`harness.diagnose.repro.attach_repro` writes into a repro (it asks nothing else
    of the rasterizer for the watertight and overdraw checks)."""

    convention = None

    def __init__(self, name: str) -> None:
        self.name = name

    def rasterize(self, scene: Any) -> Coverage:  # never called: the probe's call draws
        raise NotImplementedError


def _judged(case: Case, coverage: Coverage, wanted: set[str], convention: Convention | None, call: Call,
            name: str) -> list[Result]:
    """The suite's checks ``wanted`` (those that apply) on ``coverage``, ``call``'s answer to ``case``."""
    from harness import checks
    from harness.checks import Subject, Tolerance

    if "watertight" in wanted:
        return [_watertight(case, coverage, convention)]
    needs = {c.name for c in checks.checks() if c.needs_convention}
    if convention is None and wanted & needs:
        return []
    subject = Subject(case, name, convention, [coverage], call, Tolerance(), False, scene_kinds=(case.scene.kind,))
    return [c.verdict(subject) for c in checks.checks(case, wanted, SINGLE.coverage_kind)]


def suite_defects(call: Call, cases: Sequence[Case], wanted: set[str], convention: Convention | None, name: str,
                  repros: int = REPROS) -> tuple[Defect, ...]:
    """The suite's cases behind a probe that saw a defect, judged as ``run`` judges them:
    each (case, check of ``wanted``) that fails is a :class:`Defect` with the check's
    evidence and, for the first ``repros``, a minimal repro. ``call`` draws the cases (a
    paths-only rasterizer's: the path versions the path suite holds)."""
    defects: list[Defect] = []
    for case in cases:
        coverage = send(call, case.scene).coverage
        if coverage is None:
            continue  # the probe reports the error itself
        for r in _judged(case, coverage, wanted, convention, call, name):
            if r.status == "fail":
                defects.append(Defect(case.id, r.check, r.message, _evidence_of(r),
                                      _repro(r, case, call, convention, name) if len(defects) < repros else None))
    return tuple(defects)


def _evidence_of(result: Result) -> dict[str, Any]:
    """The offending pixels and primitives of a check's evidence (at most EVIDENCE_LIMIT each)."""
    from harness.checks import EVIDENCE_LIMIT

    return {k: v[:EVIDENCE_LIMIT] if isinstance(v, list) else v for k, v in result.evidence.items()
            if k in ("blame", "strays", "pixels", "triangles")}


def _repro(result: Result, case: Case, call: Call, convention: Convention | None, name: str) -> dict[str, Any] | None:
    """A failing partition shrunk to a minimal repro as replayable case JSON: double hits
    shrink to the primitives that overlap (``overdraw``), a hole keeps every cell (no
    subset of a partition is one)."""
    from harness.diagnose.repro import attach_repro

    def judge(candidate: Case | MotionCase, check: str) -> list[Result]:
        if not isinstance(candidate, Case):
            return []
        cov = send(call, candidate.scene).coverage
        return [] if cov is None else _judged(candidate, cov, {check}, convention, call, name)

    try:
        shrunk = attach_repro(replace(result, rasterizer=name, case=case.id), case, judge, _Named(name), budget=40, seconds=5.0)
    except Exception:  # a repro is evidence besides the verdict: the probe's answer stands without it
        return None
    payload = shrunk.evidence.get("repro")
    return payload if isinstance(payload, dict) else None


# --- unanswered fit scenes -----------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Unanswered:
    """Fit scenes the rasterizer gave no answer for (an error, a crash, a timeout): left
    out of the fit and the residual."""

    count: int
    of: int
    first: str

    @property
    def text(self) -> str:
        return f"{self.count} of {self.of} fit scenes unanswered, left out of the fit and the residual; first: {self.first}"[:200]


def unanswered(drawn: list[Drawn]) -> Unanswered | None:
    """The fit scenes among ``drawn`` that gave an error, or None when all were answered."""
    errors = [d.error for d in drawn if d.error is not None]
    return Unanswered(len(errors), len(drawn), describe(errors[0])) if errors else None
