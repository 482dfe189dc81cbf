"""A run's failing results grouped by cause, as a campaign groups its findings: the one
grouping the terminal (``rastercheck run``) and the run report (its "Failures by cause")
both show.

Each failing or erroring result of :func:`harness.run_suite` carries its signature
(evidence ``signature``: :attr:`harness.diagnose.signatures.Signature.key`), found by :func:`signed`
while the run still holds the case, the rasterizer's answer and its convention -- without
most of the trials' extra rasterizer calls (:func:`harness.diagnose.trials.with_trials`, which a
campaign can afford and a run, with many failures to classify, cannot: a run of the quick
suite would take several times as long): the signature reads the evidence the run already
has (the repro's input-format and viewport-edge trials), the answer, a few oracle calls on
the wrong primitives alone, for a failing motion check the frame it names judged alone on
the answer already drawn, and the one cheap trial that tells a tie rule from samples on
edges by chance (the tie trial).

:func:`by_cause` groups such results as the campaign page does
(:meth:`harness.campaign.state.CampaignState.causes`): on each case, the failures of the checks
that only see the effects of a wrong coverage (watertight, closed, invariance, the line
checks, ...) are counted under the cause of that case's conformance (or accuracy) failure
(:func:`attributed`, as :func:`harness.campaign.worker.attribute_causes` counts a campaign's); each signature goes under the cause most of its
results were counted under; the causes come most results first, and within each its
signatures, most results first. One bug is one cause, whichever checks and headings show it.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

from harness.checks import Result
from harness.checks.records import frame_checks, is_consequent, motion_checks, root_checks
from harness.contract.case import Case, MotionCase
from harness.contract.coverage import Coverage
from harness.contract.protocol import convention_for
from harness.diagnose.signatures import Signature, signature
from harness.diagnose.trials import frame_case, named_frames, tie_trial

Judge = Callable[[Case | MotionCase, str], list[Result]]  # the one check on a (changed) case
Answered = Callable[[Case, Coverage, str], list[Result]]  # the one check on a case, judged on a given answer

__all__ = ["SIGNATURE", "SignatureGroup", "CauseGroup", "signed", "frame_verdict", "signature_of", "by_cause", "attributed"]

SIGNATURE = "signature"  # the evidence key of a failing or erroring result's signature key
BAD = ("fail", "error")


def attributed(found: list[tuple[str, Signature]]) -> list[str]:
    """The cause each of one scene's failures (status, signature) is counted under: when
    the scene fails a root check (:attr:`Check.cause_role <harness.checks.records.Check>`
    ``root``: conformance, or accuracy for anti-aliased coverage), the failures of its
    consequent checks (``consequent``: a triangle dropped leaves a hole in watertight, a
    front-only mesh in closed, a change under flipped winding in invariance -- one cause,
    not four; and a check's ``consequent_classes``, such as hygiene's
    ``outside-primitive``) are counted under that failure's cause (the exact oracle says
    what is wrong; the others see its effects); any other keeps its own signature's cause.
    A campaign's findings (:func:`harness.campaign.worker.attribute_causes`) and a run's results
    (:func:`by_cause`) alike.

    >>> attributed([("fail", Signature("conformance", "culling", "culling")), ("fail", Signature("watertight", "hole", "none"))])
    ['culling', 'culling']
    """
    roots = root_checks()
    root = next((s.cause for status, s in found if s.check in roots and status == "fail"), None)
    return [root if root is not None and is_consequent(s.check, s.failure_class) else s.cause for _, s in found]


def signed(result: Result, case: Case | MotionCase, rasterizer: Any, judge: Judge | None = None,
           answered: Answered | None = None) -> Result:
    """``result`` with its signature (evidence ``signature``) when it fails or errs,
    judged under ``rasterizer``'s convention for ``case`` (declared or identified; for a
    motion case its convention) as a campaign judges its scenes, from what the run has: a
    failing motion check is read, given ``answered``, through a frame it names that fails
    conformance (or accuracy) judged alone on the answer already drawn
    (:func:`frame_verdict`), as the campaign's trials read it, but without calling the
    rasterizer again. Of the campaign's
    trials only the cheap one that tells the tie rule from chance runs, given ``judge``
    (the one check on a changed case, as :func:`harness.diagnose.trials.with_trials` takes it):
    a conformance failure whose wrong samples all lie exactly on edges is drawn again, its
    wrong triangles alone shifted off them (evidence ``tie_trial``: two calls per shift, at
    most six). Any other result comes back as it is. Never raises (what cannot be read is
    ``other``).

    >>> signed(Result("r", "c", "run", "error", "timeout: no answer within 2 s"), None, None).evidence
    {'signature': 'run|hang|none'}
    """
    if result.status not in BAD or SIGNATURE in result.evidence:
        return result
    try:
        convention = rasterizer.convention if isinstance(case, MotionCase) else convention_for(rasterizer, case.scene)
    except Exception:  # noqa: BLE001 - no case, or a convention that cannot be read: judged without one
        convention = None
    read = result  # what the signature reads: the result, and the facts found for it
    try:
        if isinstance(case, MotionCase) and answered is not None:
            # read, not kept: the campaign's trials (with_trials) add their own, tried, verdict
            read = frame_verdict(result, case, rasterizer, answered)
        elif judge is not None and isinstance(case, Case) and "tie_trial" not in result.evidence:
            tie = tie_trial(result, case, judge, convention)
            if tie is not None:  # kept: the trial's own fact, as a campaign's trials keep it
                result = read = replace(result, evidence={**result.evidence, "tie_trial": tie})
    except Exception:  # noqa: BLE001 - a fact that cannot be had: classified without it
        pass
    return replace(result, evidence={**result.evidence, SIGNATURE: signature(read, case, convention).key})


def frame_verdict(result: Result, case: MotionCase, rasterizer: Any, answered: Answered) -> Result:
    """A failing motion result with ``frame_failure`` (as
    :func:`harness.diagnose.trials.with_trials` adds it, untried): the first frame it names
    that fails conformance, or accuracy, judged alone (``answered``: the one check on a
    case, judged on a given answer) on the rasterizer's answer for that frame kept in its
    drawing, with that failure's signature -- a flicker of a wrong tie rule is the tie
    rule's. No rasterizer call. Any other result as it is."""
    answers = result.drawing.coverages if result.drawing is not None else ()
    if result.status != "fail" or result.check not in motion_checks() or len(answers) != len(case.frames):
        return result
    for frame in named_frames(result):
        if frame >= len(case.frames):
            continue
        still = frame_case(case, frame)
        for check in frame_checks():
            verdicts = answered(still, answers[frame], check)
            failed = [r for r in verdicts if r.status == "fail"]
            if failed:
                named = signature(failed[0], still, convention_for(rasterizer, still.scene))
                return replace(result, evidence={**result.evidence, "frame_failure": {
                    "frame": frame, "check": check, "message": failed[0].message, "signature": named.key}})
            if any(r.status == "pass" for r in verdicts):
                break  # this frame passes its verdict: try the next
    return result


def signature_of(result: Result) -> Signature:
    """The signature a result carries (:func:`signed`); one without (a record from
    elsewhere) is classified here from its drawing (read back from JSON, it has none: then
    only errors are told apart, failures are ``other``).

    >>> signature_of(Result("r", "c", "conformance", "fail", "x", evidence={"signature": "conformance|near-tie|none"}))
    Signature(check='conformance', failure_class='near-tie', convention_part='none')
    """
    key = result.evidence.get(SIGNATURE)
    if isinstance(key, str) and key.count("|") == 2:
        return Signature(*key.split("|"))
    drawing = result.drawing
    return signature(result, drawing.case if drawing is not None else None, drawing.convention if drawing is not None else None)


@dataclass(frozen=True, slots=True)
class SignatureGroup:
    """The failing (or erroring) results of one rasterizer with one signature.

    Parameters
    ----------
    signature : Signature
    status : {"fail", "error"}
    results : tuple of Result
        In run order.
    """

    signature: Signature
    status: str
    results: tuple[Result, ...]

    @property
    def count(self) -> int:
        return len(self.results)

    def describe(self) -> str:
        """The signature in one line (:meth:`harness.diagnose.signatures.Signature.describe`), whole."""
        return self.signature.describe()


@dataclass(frozen=True, slots=True)
class CauseGroup:
    """The failing (or erroring) results of one rasterizer that point at one cause.

    Parameters
    ----------
    rasterizer : str
    cause : str
        :attr:`harness.diagnose.signatures.Signature.cause` (a convention part such as ``tie-rule``,
        else a failure class such as ``hang``), as the campaign page names it.
    signatures : tuple of SignatureGroup
        Most results first: the first one's words are the cause's reason.
    """

    rasterizer: str
    cause: str
    signatures: tuple[SignatureGroup, ...]

    @property
    def results(self) -> list[Result]:
        return [r for group in self.signatures for r in group.results]

    @property
    def count(self) -> int:
        return sum(group.count for group in self.signatures)

    @property
    def checks(self) -> list[str]:
        """The checks that saw it, most results first."""
        return list(dict.fromkeys(group.signature.check for group in self.signatures))

    def reason(self) -> str:
        """One line: the words of its most frequent signature."""
        return self.signatures[0].describe()

    def repro_path(self) -> str | None:
        """A saved minimal repro of it (evidence ``repro_path``, relative to the report's
        folder, as ``rastercheck run`` writes it), of its most frequent signature first;
        None when none was saved."""
        return next((str(r.evidence["repro_path"]) for r in self.results if r.evidence.get("repro_path")), None)


def by_cause(results: Iterable[Result]) -> list[CauseGroup]:
    """The failing and erroring ``results`` grouped by rasterizer and cause, the causes
    with most results first (then by rasterizer and cause name), each with its signatures
    most results first (failures before errors, then by key). Passes and skips are left out.

    >>> bad = [Result("r", "c", "run", "error", "timeout: no answer"), Result("r", "d", "run", "error", "timeout: again"),
    ...        Result("r", "e", "run", "error", "RuntimeError: boom"), Result("r", "e", "conformance", "pass", "ok")]
    >>> [(g.cause, g.count, g.reason()) for g in by_cause(bad)]
    [('slow', 2, 'run: no answer within the time limit'), ('exception-RuntimeError', 1, 'run: raised RuntimeError')]
    """
    bad = [r for r in results if r.status in BAD]
    signatures = [signature_of(r) for r in bad]
    # each result's cause: on one case, the consequent checks' under the root check's
    by_case: dict[tuple[str, str], list[int]] = {}
    for k, r in enumerate(bad):
        by_case.setdefault((r.rasterizer, r.case), []).append(k)
    counted: list[str] = [""] * len(bad)
    for members in by_case.values():
        for k, cause in zip(members, attributed([(bad[k].status, signatures[k]) for k in members])):
            counted[k] = cause
    # each signature under the cause most of its results were counted under
    members_of: dict[tuple[str, str, str], list[int]] = {}
    for k, r in enumerate(bad):
        members_of.setdefault((r.rasterizer, signatures[k].key, r.status), []).append(k)
    causes: dict[tuple[str, str], list[SignatureGroup]] = {}
    for (rasterizer, _, status), members in members_of.items():
        tally = Counter(counted[k] for k in members)
        cause = max(sorted(tally), key=lambda c: tally[c])
        group = SignatureGroup(signatures[members[0]], status, tuple(bad[k] for k in members))
        causes.setdefault((rasterizer, cause), []).append(group)
    groups = [CauseGroup(rasterizer, cause, tuple(sorted(members, key=lambda g: (-g.count, g.status != "fail", g.signature.key))))
              for (rasterizer, cause), members in causes.items()]
    return sorted(groups, key=lambda g: (-g.count, g.rasterizer, g.cause))
