"""The check contract: result records, tolerances, what a check looks at, and the one
registry every list of checks (the runner's, the gate's, the shrinker's, the report's,
the command line's) is derived from.

A check is registered once, as a :class:`Check`: its name, the cases it applies to,
whether it needs a convention, whether its failures survive shrinking, the metrics the
gate compares (with their tolerances), a caption for people, the function from a
:class:`Subject` to a :class:`Result`, and how the rest of the harness reads its failures:
its classifier (the signature's failure class and convention part), its campaign role
(a root cause, a consequent of one, or its own), its motion role (a frame verdict, a
motion check read through frames, or neither) and the figures the report shows of it.
Adding a check touches its own module (and its known-bad test) only; a test
(``tests/checks/test_records.py``) fails when a registered check leaves any of these
undeclared.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from harness.contract.case import Case, MotionCase
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, Scene
from harness.engine import ledger

__all__ = [
    "Status", "Result", "Drawing", "Tolerance", "NEAR_TIE", "NEAR_TIE_PIXELS", "EVIDENCE_LIMIT", "result", "skip", "first",
    "Subject", "Check", "Figure", "Classifier", "CauseRole", "MotionRole", "ROLE_FIELDS", "register", "registered", "checks",
    "check_names", "metric_tolerance", "merge_samples",
    "SAMPLE_COVERAGE_KINDS", "ALL_COVERAGE_KINDS",
    "OVERFLOW_EDGES", "overflow_class", "every_check", "check_named", "root_checks", "is_consequent",
    "motion_checks", "frame_checks", "figures",
]

Status = Literal["pass", "fail", "error", "skip"]

# float64 evaluations of edge crossings err by a few units in the last place of the
# coordinates (about 2**-50 relative); 2**-40 leaves a wide berth and is still far below
# any sub-pixel lattice a rasterizer could mean (16 bits is 2**-16).
NEAR_TIE = 2.0**-40
# ... and never more than 2**-20 px, whatever the magnitude: beyond about 2**20 px a float
# rasterizer's rounding reaches whole fractions of a pixel, and it must draw exactly or
# refuse the triangle (a case's ``refusable``), not be excused.
NEAR_TIE_PIXELS = 2.0**-20
EVIDENCE_LIMIT = 50
# The coverage kinds of sample-based answers (one or several samples per pixel): what the
# checks written for single-sample coverage judge, a multisample answer sample by sample.
SAMPLE_COVERAGE_KINDS: frozenset[str] = frozenset({"single", "multisample"})
ALL_COVERAGE_KINDS: frozenset[str] = frozenset({"single", "multisample", "area"})


@dataclass(frozen=True, slots=True)
class Tolerance:
    """How much deviation a check lets through.

    Parameters
    ----------
    mode : {"default", "strict"}
    near_tie : float
        Relative distance of a sample from an edge below which a deviation is rounding.
    near_tie_pixels : float
        ... and the absolute distance in pixels (a cap for huge coordinates).
    work_ratio : float
        Largest allowed time ratio of an epsilon scene to its control scene.
    uv_error : float
        Largest allowed error of interpolated (u, v) against the exact values, in texels.
    """

    mode: str = "default"
    near_tie: float = NEAR_TIE
    near_tie_pixels: float = NEAR_TIE_PIXELS
    work_ratio: float = 50.0
    uv_error: float = 1e-6

    def __post_init__(self) -> None:
        if self.mode not in ("default", "strict"):
            raise ValueError(f"Tolerance.mode must be 'default' or 'strict', not {self.mode!r}")


@dataclass(frozen=True, slots=True)
class Result:
    """One check of one rasterizer on one case."""

    rasterizer: str
    case: str
    check: str
    status: Status
    message: str
    metrics: dict[str, float] = field(default_factory=dict)
    evidence: dict[str, Any] = field(default_factory=dict)
    # what a failure is drawn from (the report's business: see harness.report.pictures.draw); not
    # part of the verdict, not compared, not written to JSON
    drawing: Drawing | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True, slots=True, eq=False)
class Drawing:
    """What it takes to draw a failure: references to what the check looked at, no
    pictures (the report draws them from this and the evidence).

    Parameters
    ----------
    case : Case or MotionCase
    coverages : tuple of Coverage
        The rasterizer's answer (tidied): one for a still case, one per frame for a motion case.
    convention : Convention or None
    oracles : tuple of Coverage or None
        The convention's exact coverage of each scene when a check computed it already;
        None when none did (whoever draws computes it, if at all).
    whole : Drawing or None
        For a multisample answer judged sample by sample (this drawing one sample's
        layer): the drawing of the whole answer under the pattern's convention, whose
        samples the pictures show; None otherwise.
    """

    case: Case | MotionCase
    coverages: tuple[Coverage, ...]
    convention: Convention | None = None
    oracles: tuple[Coverage, ...] | None = None
    whole: Drawing | None = None

    @classmethod
    def of(cls, subject: Subject) -> Drawing:
        """References to ``subject``'s case, answers, convention and (when the checks
        needed it) oracle: no copy, no oracle computed here."""
        done = vars(subject).get("oracles")  # the cached_property's value, if it ran
        return cls(subject.case, tuple(subject.coverages), subject.convention, None if done is None else tuple(done))


def result(case_id: str, check: str, ok: bool, message: str, metrics: dict[str, float] | None = None,
           evidence: dict[str, Any] | None = None) -> Result:
    """A pass or fail record (the runner fills in the rasterizer's name)."""
    return Result("", case_id, check, "pass" if ok else "fail", message, metrics or {}, evidence or {})


def skip(case: Any, check: str, why: str) -> Result:
    """A skip record for a case (or a case id)."""
    return Result("", case if isinstance(case, str) else case.id, check, "skip", why)


def first(array: NDArray[Any] | list[Any], limit: int = EVIDENCE_LIMIT) -> list[Any]:
    """The first ``limit`` entries as plain lists, for evidence."""
    listed: list[Any] = np.asarray(array)[:limit].tolist()
    return listed


class Subject:
    """What a check looks at: one rasterizer's answer on one case, and what it may need
    besides (the convention, the oracle, a way to call the rasterizer again).

    Parameters
    ----------
    case : Case or MotionCase
    rasterizer : str
        Its name.
    convention : Convention or None
        Declared or identified; None when there is none.
    coverages : list of Coverage
        The answer: one for a static case, one per frame for a motion case.
    call : callable
        ``call(scene) -> Outcome``: the rasterizer again, isolated and time-limited.
    tolerance : Tolerance
    interpolates : bool
        False when the rasterizer says it returns coverage only.
    seconds : float
        How long the (first) call took.
    received : list of Coverage, optional
        The answers as the rasterizer gave them, when they differ from ``coverages``
        (which are tidied: see :meth:`Coverage.tidy`); the hygiene check judges these.
    scene_kinds : tuple of str
        The scene kinds the rasterizer takes (:func:`harness.contract.protocol.scene_kinds_of`): a check
        calling it on a scene of another kind must not.
    """

    def __init__(self, case: Any, rasterizer: str, convention: Convention | None, coverages: list[Coverage],
                 call: Callable[[Any], Any], tolerance: Tolerance, interpolates: bool = True, seconds: float = 0.0,
                 received: list[Coverage] | None = None, scene_kinds: tuple[str, ...] = ("triangles",)) -> None:
        self.case, self.rasterizer, self.convention = case, rasterizer, convention
        self.coverages, self.call, self.tolerance = coverages, call, tolerance
        self.interpolates, self.seconds = interpolates, seconds
        self.received = received if received is not None else coverages
        self.scene_kinds = scene_kinds

    @property
    def coverage(self) -> Coverage:
        """The answer on a static case."""
        return self.coverages[0]

    @property
    def coverage_kind(self) -> str:
        """The coverage kind judged: the convention's (``single`` without one)."""
        return "single" if self.convention is None else self.convention.coverage_kind

    def layer(self, index: int) -> Subject:
        """Sample ``index`` of a multisample subject as a single-sample subject: its
        answers' layer, the convention at that sample (:meth:`Convention.at_sample`), and
        the rasterizer again giving that layer."""
        from harness.engine.isolation import layer_of

        assert self.convention is not None
        call = self.call
        return Subject(self.case, self.rasterizer, self.convention.at_sample(index), [c.layer(index) for c in self.coverages],
                       lambda scene: layer_of(call(scene), index), self.tolerance, self.interpolates, self.seconds,
                       [c.layer(index) for c in self.received], self.scene_kinds)

    @property
    def scenes(self) -> list[AnyScene]:
        return list(self.case.frames) if hasattr(self.case, "frames") else [self.case.scene]

    @cached_property
    def oracles(self) -> list[Coverage]:
        """The exact coverage of the convention for each scene (computed once)."""
        from harness.oracle.coverage import exact_coverage

        assert self.convention is not None
        return [exact_coverage(scene, self.convention) for scene in self.scenes]

    @property
    def oracle(self) -> Coverage:
        return self.oracles[0]


# ``classify(result, case, convention) -> (failure class, convention part)``: what a failing
# result of a check is, read from its evidence (see :mod:`harness.diagnose.signatures`)
Classifier = Callable[[Any, Any, Any], tuple[str, str]]
# a check's part in naming a scene's cause (:func:`harness.diagnose.causes.attributed`): "root" -- a
# check against the exact oracle whose failure names the scene's cause; "consequent" -- a
# check whose failure on a scene that fails a root check is that failure's consequence (a
# dropped triangle leaves a hole), counted under its cause; "own" -- neither: its failures
# keep their own cause
CauseRole = Literal["root", "consequent", "own"]
# a check's part in reading motion failures (:func:`harness.diagnose.trials.with_trials`):
# "frame" -- its verdict on one frame judged alone names a motion failure's cause
# (conformance, or accuracy for anti-aliased coverage); "through-frames" -- a motion check
# whose failures are read through the frames they name; "none" -- neither
MotionRole = Literal["frame", "through-frames", "none"]
# the fields that say how the rest of the harness reads a check's failures: each built-in
# check declares every one (None is undeclared)
ROLE_FIELDS = ("classifier", "cause_role", "motion_role", "figures")


@dataclass(frozen=True, slots=True)
class Figure:
    """A figure the report shows of a check's results on a rasterizer's page: one metric,
    combined over cases.

    Parameters
    ----------
    metric : str
    how : {"max", "sum", "mean"}
        How the metric is combined over the cases that measured it.
    label : str
        What it is, for people (shown after the check's name).
    """

    metric: str
    how: Literal["max", "sum", "mean"]
    label: str


@dataclass(frozen=True)
class Check:
    """A registered check.

    Parameters
    ----------
    name : str
    run : callable
        ``run(subject) -> Result``; pure but for ``subject.call``.
    applies : callable
        ``applies(case) -> bool``: the cases (static or motion) it looks at.
    needs_convention : bool
        It compares with a convention's oracle: skipped without one, and its failures
        against a merely guessed convention say so.
    shrinks : bool
        A failure on a case still fails on some subset of its triangles: the shrinker may
        look for a minimal repro.
    metrics : mapping of str to (factor, slack)
        Metrics where larger is worse, with the growth the gate lets through.
    caption : str
        What it asserts, in one line.
    needs_attributes : bool
        It compares interpolated attributes: skipped for a coverage-only rasterizer.
    on_request : bool
        Run only when asked for by name (``overdraw``: the form of ``watertight`` that
        survives shrinking).
    timings : tuple of str
        Metrics measured in time (they differ between any two runs): never stored in a
        baseline nor compared across runs.
    kinds : frozenset of str
        The coverage kinds it judges (:attr:`Convention.coverage_kind`); a rasterizer of another
        kind is not given it.
    per_sample : bool
        A multisample rasterizer is judged sample by sample: the check runs on each
        sample's layer (:meth:`Subject.layer`) as on a single-sample rasterizer, and the
        results are merged (:func:`merge_samples`). False: the check reads every sample
        at once.
    classifier : callable or str or None
        ``classify(result, case, convention) -> (failure class, convention part)`` of a
        failing result (:func:`harness.diagnose.signatures.signature`), or its dotted name
        ``"module:function"``, imported on first use (the classifiers of the built-in
        checks live in :mod:`harness.diagnose.signatures`, which imports the check modules). None:
        undeclared -- every failure is ``other``.
    cause_role : {"root", "consequent", "own"} or None
        Its part in naming a scene's cause (:data:`CauseRole`); None: undeclared (own).
    consequent_classes : frozenset of str
        Failure classes of a check that is not ``consequent`` which still count under a
        root failure's cause (hygiene's ``outside-primitive``: coverage's fault too).
    motion_role : {"frame", "through-frames", "none"} or None
        Its part in reading motion failures (:data:`MotionRole`); None: undeclared (none).
    figures : tuple of Figure or None
        What the report shows of its results on a rasterizer's page (often none: ``()``);
        None: undeclared.
    plans : callable or None
        ``plans(case, convention) -> list of scenes``: the scenes beyond the case's own its
        run hands the rasterizer whatever the answers (invariance's variants), so that a
        campaign sends them to the rasterizer's process ahead, with the case's
        (:meth:`harness.engine.session.Session.prefetch`). None: none planned (the run may
        still ask for any scene; it is then drawn when asked).
    """

    name: str
    run: Callable[[Subject], Result]
    applies: Callable[[Any], bool]
    needs_convention: bool = False
    shrinks: bool = False
    metrics: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    caption: str = ""
    needs_attributes: bool = False
    on_request: bool = False
    timings: tuple[str, ...] = ()
    coverage_kinds: frozenset[str] = SAMPLE_COVERAGE_KINDS
    per_sample: bool = True
    classifier: Classifier | str | None = None
    cause_role: CauseRole | None = None
    consequent_classes: frozenset[str] = frozenset()
    motion_role: MotionRole | None = None
    figures: tuple[Figure, ...] | None = None
    plans: Callable[[Any, Convention | None], list[AnyScene]] | None = None

    def __post_init__(self) -> None:
        if self.cause_role not in (None, "root", "consequent", "own"):
            raise ValueError(f"check {self.name!r}: cause_role must be 'root', 'consequent' or 'own', not {self.cause_role!r}")
        if self.motion_role not in (None, "frame", "through-frames", "none"):
            raise ValueError(f"check {self.name!r}: motion_role must be 'frame', 'through-frames' or 'none', "
                             f"not {self.motion_role!r}")
        if isinstance(self.classifier, str) and self.classifier.count(":") != 1:
            raise ValueError(f"check {self.name!r}: classifier must be a function or 'module:function', not {self.classifier!r}")

    def undeclared(self) -> tuple[str, ...]:
        """The fields of :data:`ROLE_FIELDS` this check leaves undeclared (None)."""
        return tuple(name for name in ROLE_FIELDS if getattr(self, name) is None)

    def classifier_function(self) -> Classifier | None:
        """Its classifier as a function (a dotted name imported now), None without one."""
        if isinstance(self.classifier, str):
            return _imported(self.classifier)
        return self.classifier

    def verdict(self, subject: Subject) -> Result:
        """The check's result, or its skip when the subject lacks what it needs; a
        multisample subject sample by sample when the check is ``per_sample``."""
        with ledger.section("check:" + self.name):
            return self._verdict(subject)

    def _verdict(self, subject: Subject) -> Result:
        if self.needs_convention and subject.convention is None:
            return skip(subject.case, self.name, "the rasterizer declares no convention")
        if self.needs_attributes and not subject.interpolates:
            return skip(subject.case, self.name, f"{subject.rasterizer} declares interpolates = False: it returns "
                                                  "coverage only, no u, v to compare")
        if subject.coverage_kind not in self.coverage_kinds:
            judged = ", ".join(sorted(self.coverage_kinds))
            return skip(subject.case, self.name, f"judges {judged} coverage, not {subject.coverage_kind}")
        if subject.convention is not None and subject.convention.model.layered and self.per_sample:
            whole = Subject(subject.case, subject.rasterizer, subject.convention, subject.coverages,
                            _once_per_scene(subject.call),
                            subject.tolerance, subject.interpolates, subject.seconds, subject.received, subject.scene_kinds)
            layers = [whole.layer(s) for s in range(subject.convention.n_samples)]
            merged = merge_samples([(layer, self.run(layer)) for layer in layers])
            if merged.drawing is None or merged.status != "fail":
                return merged
            return replace(merged, drawing=replace(merged.drawing, whole=Drawing(subject.case, tuple(subject.coverages),
                                                                                 subject.convention)))
        return self.run(subject)


def _once_per_scene(call: Callable[[Scene], Any]) -> Callable[[Scene], Any]:
    """``call`` answering each distinct scene once: the layers of a multisample answer
    ask the rasterizer for the same variant scenes, and one answer holds every sample."""
    answers: dict[tuple[Any, ...], Any] = {}

    def once(scene: Scene) -> Any:
        # every field of the scene, whatever its kind (its pickling arguments)
        key: tuple[Any, ...] = (type(scene).__name__,
                                *(v.tobytes() if isinstance(v, np.ndarray) else v for v in scene.__reduce__()[1]))
        if key not in answers:
            answers[key] = call(scene)
        return answers[key]

    return once


def merge_samples(judged: list[tuple[Subject, Result]]) -> Result:
    """One result from a check's results on each sample layer of a multisample answer.

    An error if any layer errs, else a failure if any fails, a skip if every layer
    skips, else a pass. Metrics are summed over the layers (times: the largest);
    ``failing_samples`` counts the layers that failed. The evidence and the drawing are
    the first failing layer's, with ``sample`` (its index) and ``offset`` added, and
    ``samples`` lists each failing layer's index, offset and message.
    """
    results = [r for _, r in judged]
    first_result = results[0]
    for status in ("error", "fail"):
        bad = [(subject, r) for subject, r in judged if r.status == status]
        if bad:
            break
    else:
        if all(r.status == "skip" for r in results):
            return first_result
    times = timing_metrics()
    metrics: dict[str, float] = {}
    for r in results:
        for key, value in r.metrics.items():
            metrics[key] = max(metrics.get(key, value), value) if key in times else metrics.get(key, 0.0) + value

    def where(subject: Subject) -> str:
        assert subject.convention is not None
        x, y = subject.convention.sample
        return f"({x:g}, {y:g})"

    indexed = {id(subject): s for s, (subject, _) in enumerate(judged)}
    if not bad:
        message = f"each of {len(judged)} samples: {first_result.message}" if len({r.message for r in results}) == 1 \
            else f"{len(judged)} samples: " + "; ".join(f"sample {s}: {r.message}" for s, r in enumerate(results))
        return replace(first_result, message=message, metrics=metrics)
    metrics["failing_samples"] = float(len(bad))
    subject, worst = bad[0]
    listed = [{"sample": indexed[id(sub)], "offset": list(sub.convention.sample) if sub.convention else None,
               "message": r.message} for sub, r in bad]
    evidence = {**worst.evidence, "sample": indexed[id(subject)], "offset": listed[0]["offset"], "samples": listed}
    message = "; ".join(f"sample {indexed[id(sub)]} {where(sub)}: {r.message}" for sub, r in bad[:3])
    if len(bad) > 3:
        message += f"; and {len(bad) - 3} more samples"
    drawing = worst.drawing if worst.drawing is not None else Drawing.of(subject)
    return replace(worst, message=message, metrics=metrics, evidence=evidence, drawing=drawing)


_REGISTRY: dict[str, Check] = {}


def register(check: Check) -> Check:
    """Add a check; a second check of the same name is refused."""
    if check.name in _REGISTRY and _REGISTRY[check.name] is not check:
        raise ValueError(f"a check named {check.name!r} is registered already")
    _REGISTRY[check.name] = check
    return check


@contextmanager
def registered(check: Check) -> Iterator[Check]:
    """Register a check for the duration of a ``with`` block (tests, experiments)."""
    register(check)
    try:
        yield check
    finally:
        _REGISTRY.pop(check.name, None)


def checks(case: Any = None, only: set[str] | None = None, coverage_kind: str | None = None) -> list[Check]:
    """The registered checks in order; with ``case``, those that apply to it (on-request
    ones only when named in ``only``); with ``only``, those named; with ``coverage_kind``, those
    that judge that coverage kind."""
    out = []
    for check in _REGISTRY.values():
        if only is not None and check.name not in only:
            continue
        if coverage_kind is not None and coverage_kind not in check.coverage_kinds:
            continue
        if check.on_request and (only is None or check.name not in only):
            continue
        if case is not None and not check.applies(case):
            continue
        out.append(check)
    return out


def every_check() -> tuple[Check, ...]:
    """Every registered check in order, on-request ones too."""
    return tuple(_REGISTRY.values())


def check_named(name: str) -> Check | None:
    """The registered check of that name (on-request ones too), None when there is none."""
    return _REGISTRY.get(name)


def root_checks() -> tuple[str, ...]:
    """The checks whose failure names a scene's cause (``cause_role`` root), in order."""
    return tuple(c.name for c in _REGISTRY.values() if c.cause_role == "root")


def is_consequent(check: str, failure_class: str) -> bool:
    """Whether a failure of ``check`` of that class counts under a root failure's cause on
    the same scene: the check is ``consequent``, or the class one of its
    ``consequent_classes``. Unregistered checks (``run``, ``harness``) are not."""
    found = _REGISTRY.get(check)
    return found is not None and (found.cause_role == "consequent" or failure_class in found.consequent_classes)


def motion_checks() -> tuple[str, ...]:
    """The motion checks whose failures are read through the frames they name
    (``motion_role`` through-frames), in order."""
    return tuple(c.name for c in _REGISTRY.values() if c.motion_role == "through-frames")


def frame_checks() -> tuple[str, ...]:
    """The checks whose verdict on one frame judged alone names a motion failure's cause
    (``motion_role`` frame), in order: at most one applies to a rasterizer's coverage."""
    return tuple(c.name for c in _REGISTRY.values() if c.motion_role == "frame")


def figures() -> list[tuple[str, Figure]]:
    """Every figure the report shows, (check, figure), in registry order."""
    return [(c.name, f) for c in _REGISTRY.values() for f in c.figures or ()]


_IMPORTED: dict[str, Classifier] = {}


def _imported(dotted: str) -> Classifier:
    """The function a ``"module:function"`` name names, imported once."""
    if dotted not in _IMPORTED:
        module, _, attribute = dotted.partition(":")
        _IMPORTED[dotted] = getattr(importlib.import_module(module), attribute)
    return _IMPORTED[dotted]


def check_names() -> tuple[str, ...]:
    """Names of the registered checks (on-request ones left out)."""
    return tuple(c.name for c in _REGISTRY.values() if not c.on_request)


def timing_metrics() -> frozenset[str]:
    """Every metric measured in time: ``seconds`` (each call's) and those the checks
    declare (:attr:`Check.timings`)."""
    return frozenset({"seconds"}.union(*(check.timings for check in _REGISTRY.values())))


def metric_tolerance() -> dict[str, tuple[float, float]]:
    """Every gated metric of every registered check, with its (factor, slack)."""
    out: dict[str, tuple[float, float]] = {}
    for check in _REGISTRY.values():
        out.update(check.metrics)
    return out


# Powers of two where arithmetic gives out: 2**12 is huge beside any viewport here,
# 2**24 and 2**53 where float32 and float64 stop holding every integer, 2**31 and 2**63
# where int32 and int64 overflow, 2**128 where float32 overflows to infinity.
OVERFLOW_EDGES = (12, 24, 31, 53, 63, 128)


def overflow_class(magnitude: float) -> str | None:
    """``overflow-2^a..2^b`` for a largest |coordinate| at or beyond 2**12 (its bucket
    between :data:`OVERFLOW_EDGES`), None below.

    >>> overflow_class(100.0), overflow_class(1e6), overflow_class(2.0**53), overflow_class(1e300)
    (None, 'overflow-2^12..2^24', 'overflow-2^53..2^63', 'overflow-2^128+')
    """
    if not magnitude >= 2.0 ** OVERFLOW_EDGES[0]:  # NaN too
        return None
    exponent = math.frexp(magnitude)[1] - 1 if math.isfinite(magnitude) else 10**6  # floor(log2), exactly
    for low, high in zip(OVERFLOW_EDGES, OVERFLOW_EDGES[1:]):
        if low <= exponent < high:
            return f"overflow-2^{low}..2^{high}"
    return f"overflow-2^{OVERFLOW_EDGES[-1]}+"
