"""The CI gate: compare a run with a checked-in baseline of known results.

A baseline maps ``rasterizer|case|check`` to the status and metrics seen when it was last
updated, and, for known failures, a reason a person wrote. The gate fails only on
regressions: a check that passed (or is new) now fails or errors, a metric got worse
beyond its tolerance, or a result of the baseline is missing from the run (unless the run
is partial on purpose: ``allow_missing``). A known failure that now passes is reported as
unexpectedly passing. A run that shares no rasterizer with the baseline is not compared
at all: that is a mistake of the caller (ValueError).

Baseline file (JSON, :data:`BASELINE_SCHEMA`), written with sorted keys so that an
unchanged run rewrites it byte for byte::

    {"schema": 1, "entries": {"<rasterizer>|<case>|<check>":
        {"status": "pass" | "fail" | "error" | "skip", "metrics": {str: number}, "reason": str}}}

Only gated metrics (:func:`harness.checks.metric_tolerance`) that are not timings
(:func:`harness.checks.timing_metrics`) are stored. Fields may be added to an entry in a later schema-1 file.

A campaign's findings (``rastercheck fuzz``, :mod:`harness.campaign`) can be taken as known
failures too (:class:`CampaignFindings`, ``rastercheck gate --known-campaign DIR``): a
failing or erroring result of the campaign's rasterizer that would be a regression is
reported as known instead when its ``(check, case)`` is one the campaign saw fail (a
scene among a signature's examples, or a saved repro, by its id or the id of the case it
was shrunk from), or when its own signature (:func:`harness.diagnose.signatures.signature`) is one
the campaign found. The baseline is not changed by it: a known failure of the baseline
whose metrics worsened is a regression as before.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from harness.checks import Result, check_names, metric_tolerance, timing_metrics
from harness.results.files import atomic_write_text, read_input
from harness.results.schemas import schema_fault

__all__ = ["BASELINE_SCHEMA", "GateFinding", "Verdict", "compare_with_baseline", "gated_metrics", "key",
           "load_baseline", "save_baseline", "CampaignFindings", "campaign_known", "result_signature"]

SCHEMA = 1
BAD = ("fail", "error")

# Metrics measured with a clock (each check declares its own, Check.timings; "seconds"
# is the rasterize time the runner adds to every result) change from one run to the next
# on the same code: they never enter a baseline and the gate never compares them.

# The JSON schema of a baseline file (a JSON Schema 2020-12 document).
BASELINE_SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "type": "object",
    "required": ["schema", "entries"],
    "properties": {
        "schema": {"const": SCHEMA},
        "entries": {
            "type": "object",
            "propertyNames": {"pattern": r"^[^|]+\|.+\|[^|]+$"},  # rasterizer|case|check
            "additionalProperties": {
                "type": "object",
                "required": ["status"],
                "properties": {
                    "status": {"enum": ["pass", "fail", "error", "skip"]},
                    "metrics": {"type": "object", "additionalProperties": {"type": "number"}},
                    "reason": {"type": "string"},
                },
            },
        },
    },
}

GateVerdict = Literal["regression", "missing", "fixed", "known", "new", "absent", "flaky", "dropped"]
# How each verdict of the gate is labelled in the gate's output, and counted in a header.
_LABEL = {"regression": "REGRESSION", "missing": "MISSING", "fixed": "UNEXPECTEDLY PASSING", "flaky": "FLAKY",
          "dropped": "NOW SKIPPED"}
_SHOWN: tuple[GateVerdict, ...] = ("regression", "missing", "fixed", "flaky", "dropped")


def key(r: Result) -> str:
    return f"{r.rasterizer}|{r.case}|{r.check}"


def _parts(k: str) -> tuple[str, str, str]:
    """(rasterizer, case, check) of a baseline key."""
    rasterizer, rest = k.split("|", 1)
    case, _, check = rest.rpartition("|")
    return rasterizer, case, check


def gated_metrics() -> dict[str, tuple[float, float]]:
    """The metrics a baseline stores and the gate compares, with their (factor, slack):
    those the checks declare, but timings."""
    return {m: t for m, t in metric_tolerance().items() if m not in timing_metrics()}


@dataclass(frozen=True)
class GateFinding:
    """What the gate says of one ``rasterizer|case|check``.

    verdict : {"regression", "missing", "fixed", "known", "new", "absent", "flaky", "dropped"}
        ``missing``: in the baseline, not in the run (a regression); ``absent``: the same
        when missing results are allowed (not a regression); ``fixed``: a known failure
        that passes now; ``known``: a known failure that still fails; ``new``: not in the
        baseline, and passing or skipped; ``flaky``: it fails now, but not on every rerun
        (``--rerun``): shown, not a regression; ``dropped``: it passed, and is skipped
        now: shown (coverage lost), not a regression.
    text : str
        What changed, in one line (a status change and worse metrics together).
    reason : str
        The baseline's reason, for a known failure or a fixed one.
    """

    key: str
    verdict: GateVerdict
    text: str
    reason: str = ""

    @property
    def rasterizer(self) -> str:
        return _parts(self.key)[0]

    @property
    def case(self) -> str:
        return _parts(self.key)[1]

    @property
    def check(self) -> str:
        return _parts(self.key)[2]

    def __str__(self) -> str:
        return f"{self.key}: {self.text}"


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 or word.endswith("passing") else "s")


@dataclass
class Verdict:
    findings: list[GateFinding] = field(default_factory=list)

    def of(self, verdict: GateVerdict) -> list[GateFinding]:
        return [f for f in self.findings if f.verdict == verdict]

    def by_key(self) -> dict[str, GateFinding]:
        """The finding on each key that has one (one key has at most one)."""
        return {f.key: f for f in self.findings}

    @property
    def regressions(self) -> list[str]:
        """One line per regressed result, missing ones included."""
        return [str(f) for f in self.findings if f.verdict in ("regression", "missing")]

    @property
    def fixed(self) -> list[str]:
        return [str(f) for f in self.of("fixed")]

    @property
    def known(self) -> list[str]:
        return [str(f) for f in self.of("known")]

    @property
    def new(self) -> list[str]:
        return [str(f) for f in self.of("new")]

    @property
    def ok(self) -> bool:
        return not self.regressions

    def counts(self, findings: Iterable[GateFinding] | None = None) -> str:
        """``3 regressions, 1 unexpectedly passing, 2 known failures``: the nonzero counts."""
        mine = list(self.findings if findings is None else findings)
        n = {verdict: sum(f.verdict == verdict for f in mine)
             for verdict in ("regression", "missing", "fixed", "known", "new", "absent", "flaky", "dropped")}
        regressions = n["regression"] + n["missing"]
        parts = [_plural(regressions, "regression") + (f" ({n['missing']} missing)" if n["missing"] else "")] if regressions else []
        parts += [f"{n['fixed']} unexpectedly passing"] if n["fixed"] else []
        parts += [_plural(n["known"], "known failure")] if n["known"] else []
        parts += [f"{n['new']} new"] if n["new"] else []
        parts += [f"{n['absent']} not run (missing allowed)"] if n["absent"] else []
        parts += [f"{n['flaky']} flaky"] if n["flaky"] else []
        parts += [f"{n['dropped']} passing before, skipped now"] if n["dropped"] else []
        return ", ".join(parts)

    def lines(self) -> list[str]:
        """Grouped by check, in registry order: a header with the counts, then one line
        per regression, missing result and unexpected pass (known failures and new
        results are counted, not listed)."""
        order = {name: k for k, name in enumerate(check_names())}
        groups: dict[str, list[GateFinding]] = {}
        for f in self.findings:
            groups.setdefault(f.check, []).append(f)
        out = []
        for check in sorted(groups, key=lambda c: (order.get(c, len(order)), c)):
            mine = groups[check]
            if not any(f.verdict in _SHOWN or f.verdict == "known" for f in mine):
                continue
            out.append(f"{check}: {self.counts(mine)}")
            for verdict in _SHOWN:
                out += [f"  {_LABEL[verdict]} {f}" for f in mine if f.verdict == verdict]
        return out


def load_baseline(path: Path | str) -> dict[str, dict[str, Any]]:
    """The entries of a baseline file, checked against :data:`BASELINE_SCHEMA`;
    ValueError in one line naming the file (and the field) that is wrong."""
    import jsonschema

    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: a folder, not a baseline file")
    try:
        data = json.loads(read_input(path, "the baseline").decode("utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{path}: no such baseline (create one with --update-baseline)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise ValueError(f"{path}: unreadable baseline ({exc})") from None
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"{path}: not a rastercheck baseline of schema {SCHEMA}")
    fault = schema_fault(jsonschema.Draft202012Validator(BASELINE_SCHEMA), data, _baseline_words)
    if fault is not None:
        raise ValueError(f"{path}: malformed baseline {fault}")
    entries: dict[str, dict[str, Any]] = data["entries"]
    return entries


def _baseline_words(error: Any) -> str | None:
    if "propertyNames" in error.absolute_schema_path:
        shown = repr(error.instance)
        return f"{shown if len(shown) <= 60 else shown[:57] + '...'} is not a key of the form rasterizer|case|check"
    return None


def _entry(r: Result, previous: dict[str, dict[str, Any]], gated: dict[str, tuple[float, float]]) -> dict[str, Any]:
    metrics = {m: v for m, v in r.metrics.items() if m in gated and isinstance(v, (int, float)) and not isinstance(v, bool)}
    entry: dict[str, Any] = {"status": r.status, "metrics": metrics}
    if r.status in BAD:
        entry["reason"] = previous.get(key(r), {}).get("reason", "") or r.message
    return entry


def save_baseline(path: Path | str, results: list[Result], previous: dict[str, dict[str, Any]] | None = None,
                  keep_missing: bool = False) -> Path:
    """Write the run as the new baseline, keeping the reasons of failures that remain.

    Parameters
    ----------
    path : path
    results : list of Result
    previous : dict, optional
        The baseline's entries so far (:func:`load_baseline`): their reasons are kept.
    keep_missing : bool
        Keep the previous entries this run did not produce (a partial run: ``--case``,
        ``--check``, ``--shard``, fewer rasterizers).

    Timings are left out and keys sorted: the same results give the same bytes.
    """
    previous = previous or {}
    gated = gated_metrics()
    entries = {key(r): _entry(r, previous, gated) for r in results}
    if keep_missing:
        entries = {**{k: v for k, v in previous.items() if k not in entries}, **entries}
    path = Path(path)
    atomic_write_text(path, json.dumps({"schema": SCHEMA, "entries": entries}, indent=1, sort_keys=True) + "\n", durable=True)
    return path


def _worse(r: Result, before: dict[str, Any], gated: dict[str, tuple[float, float]]) -> list[str]:
    """``wrong worsened from 0 to 12`` for each gated metric beyond its tolerance."""
    out = []
    old_metrics = before.get("metrics", {})
    for metric, (factor, slack) in gated.items():
        old, new = old_metrics.get(metric), r.metrics.get(metric)
        if isinstance(old, (int, float)) and isinstance(new, (int, float)) and new > old * factor + slack:
            out.append(f"{metric} worsened from {old:g} to {new:g}")
    return out


def compare_with_baseline(results: list[Result], baseline: dict[str, dict[str, Any]], allow_missing: bool = False,
                          known_failure: Callable[[Result], str | None] | None = None) -> Verdict:
    """The gate's verdict on ``results`` against the baseline's entries.

    ``known_failure`` (e.g. :func:`campaign_known`) is asked about each failing or erroring
    result that would otherwise be a regression by its status (new, or passing before): a
    reason makes it a known failure instead.

    Raises ValueError (one line) when both name rasterizers and none in common: the run
    was of another rasterizer than the baseline's.
    """
    ran = {r.rasterizer for r in results}
    known = {_parts(k)[0] for k in baseline}
    if ran and known and not ran & known:
        raise ValueError(f"the baseline is of {', '.join(sorted(known))}, this run of {', '.join(sorted(ran))}: "
                         "no rasterizer in common (another --baseline, or --update-baseline to start one)")
    gated = gated_metrics()
    verdict = Verdict()
    seen = set()
    for r in results:
        k = key(r)
        seen.add(k)
        before = baseline.get(k)
        if before is None:
            if r.status in BAD and "flaky" in r.evidence:
                verdict.findings.append(GateFinding(k, "flaky", f"new, {' / '.join(r.evidence['flaky'])} on reruns: {r.message}"))
            elif r.status in BAD and (why := _known(known_failure, r)):
                verdict.findings.append(GateFinding(k, "known", f"new, {r.status}: {why}", why))
            elif r.status in BAD:
                verdict.findings.append(GateFinding(k, "regression", f"new, {r.status}: {r.message}"))
            else:
                verdict.findings.append(GateFinding(k, "new", f"new, {r.status}"))
            continue
        status, reason = before.get("status"), before.get("reason", "")
        was_bad = status in BAD
        worse = _worse(r, before, gated)
        if r.status in BAD and not was_bad and "flaky" in r.evidence:  # the reruns disagree: a flake, shown
            verdict.findings.append(GateFinding(k, "flaky", f"was {status}, now {' / '.join(r.evidence['flaky'])} on reruns: {r.message}"))
        elif r.status in BAD and not was_bad and (why := _known(known_failure, r)):
            verdict.findings.append(GateFinding(k, "known", f"was {status}, now {r.status}: {why}", why))
        elif r.status in BAD and not was_bad:
            verdict.findings.append(GateFinding(k, "regression", "; ".join([f"was {status}, now {r.status}: {r.message}", *worse])))
        elif worse:
            verdict.findings.append(GateFinding(k, "regression", "; ".join([f"{r.status} as before", *worse]), reason))
        elif was_bad and r.status == "pass":
            verdict.findings.append(GateFinding(k, "fixed", f"was {status} ({reason}), now passes", reason))
        elif was_bad and r.status in BAD:
            verdict.findings.append(GateFinding(k, "known", f"{r.status}: {reason or r.message}", reason or r.message))
        elif status == "pass" and r.status == "skip":
            verdict.findings.append(GateFinding(k, "dropped", f"was pass, now skipped: {r.message}"))
    for k in sorted(baseline.keys() - seen):
        verdict.findings.append(GateFinding(k, "absent" if allow_missing else "missing",
                                        f"in the baseline ({baseline[k].get('status')}), not in this run"))
    return verdict


def _known(known_failure: Callable[[Result], str | None] | None, r: Result) -> str | None:
    return known_failure(r) if known_failure is not None else None


# -- a campaign's findings as known failures ----------------------------------------------------


@dataclass(frozen=True)
class CampaignFindings:
    """What a campaign found (its state folder, :class:`harness.campaign.state.CampaignState`), as
    the gate reads it.

    ``signatures`` maps each signature key to its entry in the state (``count``,
    ``repro``, ...); ``cases`` maps each ``(check, case id)`` the campaign saw fail --
    every example scene of a signature (:func:`cases.fuzz.scene_id`) and every saved
    repro, by its own id and by the id of the case it was shrunk from -- to its
    signature key.
    """

    directory: Path
    rasterizer: str
    signatures: dict[str, dict[str, Any]]
    cases: dict[tuple[str, str], str]

    @classmethod
    def load(cls, directory: Path | str) -> CampaignFindings:
        """The findings of the campaign saved in ``directory``; ValueError in one line
        naming the folder (or the repro file) that cannot be read."""
        from cases.fuzz import scene_id
        from harness.campaign.state import CampaignState

        state = CampaignState.load(directory)
        cases: dict[tuple[str, str], str] = {}
        for signature_key, entry in state.signatures.items():
            if not isinstance(entry, dict) or not isinstance(entry.get("check"), str) or not isinstance(entry.get("examples", []), list):
                raise ValueError(f"{state.path}: malformed signature {signature_key!r} (its check and examples expected)")
            checks = {str(entry.get("result_check") or entry["check"]), str(entry["check"])}
            for point in entry.get("examples", []):
                try:
                    family, seed, index = point
                except (TypeError, ValueError):
                    continue  # not a scene point: nothing to match
                try:
                    case_id = scene_id(family, int(seed), int(index))
                except (KeyError, TypeError, ValueError):
                    continue  # a family this version does not know: its repro may still match
                for check in checks:
                    cases.setdefault((check, case_id), signature_key)
            if entry.get("repro"):
                path = Path(directory) / entry["repro"]
                try:
                    repro = json.loads(read_input(path, "the campaign repro").decode("utf-8"))
                except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
                    raise ValueError(f"{path}: cannot read this campaign repro ({exc})") from None
                if not isinstance(repro, dict):
                    raise ValueError(f"{path}: not a campaign repro (a JSON object expected)")
                for check in checks | {str(repro.get("check") or entry["check"])}:
                    for named in (repro.get("id"), repro.get("original_case")):
                        if isinstance(named, str):
                            cases.setdefault((check, named), signature_key)
        return cls(Path(directory), state.rasterizer, dict(state.signatures), cases)

    def reason(self, signature_key: str) -> str:
        """Why a result of this signature is known: the campaign, the signature, how often
        it was found and where its repro is."""
        entry = self.signatures[signature_key]
        count = int(entry.get("count", 0))
        repro = f"; repro {self.directory / entry['repro']}" if entry.get("repro") else ""
        return (f"known from the campaign in {self.directory}: {signature_key} "
                f"({count} finding{'' if count == 1 else 's'}{repro})")


def result_signature(result: Result, rasterizer: Any | None) -> str:
    """The signature key (:func:`harness.diagnose.signatures.signature`) of a failing or erroring
    result, judged on the case its drawing holds under ``rasterizer``'s convention for that
    case (declared or identified), as a campaign judges its scenes; its probes' evidence
    (input format, viewport edge: the runner's repro) is read as a campaign reads it."""
    from harness.contract.case import MotionCase
    from harness.contract.protocol import convention_for
    from harness.diagnose.signatures import signature

    case = result.drawing.case if result.drawing is not None else None
    convention = None
    if rasterizer is not None and case is not None:
        try:
            convention = rasterizer.convention if isinstance(case, MotionCase) else convention_for(rasterizer, case.scene)
        except Exception:  # noqa: BLE001 - a rasterizer whose convention cannot be read: judged without one
            convention = None
    return signature(result, case, convention).key


def campaign_known(campaigns: Sequence[CampaignFindings],
                   signature_of: Callable[[Result], str | None] = lambda r: result_signature(r, None)
                   ) -> Callable[[Result], str | None]:
    """A ``known_failure`` for :func:`compare_with_baseline`: the reason a failing result
    is known from one of ``campaigns`` of its rasterizer -- its ``(check, case)`` seen
    failing there, else its signature (``signature_of``, computed only for a rasterizer
    that has a campaign) found there -- or None.

    >>> found = CampaignFindings(Path("c"), "r", {"run|hang|none": {"count": 2, "repro": None}}, {})
    >>> known = campaign_known([found])
    >>> known(Result("r", "lattice/a", "run", "error", "timeout: no answer within 2 s"))
    'known from the campaign in c: run|hang|none (2 findings)'
    >>> known(Result("other", "lattice/a", "run", "error", "timeout: no answer within 2 s")) is None
    True
    """

    def known(r: Result) -> str | None:
        mine = [c for c in campaigns if c.rasterizer == r.rasterizer]
        if not mine or r.status not in BAD:
            return None
        for campaign in mine:
            found = campaign.cases.get((r.check, r.case))
            if found is not None:
                return campaign.reason(found)
        signature_key = signature_of(r)
        for campaign in mine:
            if signature_key is not None and signature_key in campaign.signatures:
                return campaign.reason(signature_key)
        return None

    return known
