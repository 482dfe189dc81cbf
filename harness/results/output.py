"""Machine-readable results: JSON (schema 1) and JUnit XML, both written atomically.

JSON schema 1::

    {
      "schema": 1,
      "rastercheck": "<version>",
      "suite": "quick" | "full" | "custom",
      "seed": <int>,
      "created": "<ISO 8601 time>",
      "rasterizers": {"<name>": "<convention, in words, or 'none declared'>"},
      "fingerprints": {"<name>": {"convention": str, "sample": [x, y], "tie": str,
                       "subpixel_bits": int | null, "snap_rounding": str, "cull": str,
                       "input": str,   # the input precision (Convention.input: "float64", "float32", "fixed6", ...)
                       "exact": bool, "residual": int, "pixels": int,
                       "runner_up": [str, int] | null, "facts": {str: str},
                       "ambiguous": [str],   # alternatives it could not separate
                       "kind": "multisample" | "area",   # these four only when not "single":
                       "samples": [[x, y], ...] | null, "levels": int, "tolerance": float | null,
                       # these three only for a rasterizer that takes paths:
                       "fill_rules": {"nonzero" | "evenodd": str},   # the rule asked -> what it drew
                       "honoured_fill_rules": [str],
                       "path_convention": {"convention": str, ..., "differences": [str]} | null,
                       # and, for a rasterizer that takes lines, what identify found of them:
                       "line_...": ...}   # fields named line_* (harness.identify.line_probes)
                       | {"error": str}},   # what identify found, when it ran
      # these four only when the caller knows the rasterizers (harness.report.pages.capabilities):
      "scene_kinds": {"<name>": ["triangles" | "paths" | "lines", ...]},   # the scene kinds each takes
      "fill_rules": {"<name>": ["nonzero" | "evenodd", ...]},   # of those that take paths
      "line_rules": {"<name>": "<line rule, in words>"},   # of those that take lines: Convention.describe_lines()
      "facets": {"<name>": {"coverage": "...", "input": "...", ...}},  # the conventions table: Convention.facets()
      "results": [
        {"rasterizer": str, "case": str, "check": str,   # a path case's evidence names "path", a line case's "segment"
         "status": "pass" | "fail" | "error" | "skip",
         "message": str,
         "metrics": {str: number},          # totals; "seconds" is the rasterize time
         "evidence": {str: ...}}            # pixels, blame, series, repro; a failing or erroring one
                                            # its "signature" (harness.diagnose.causes)
      ]
    }

Fields may be added in a later schema 1 file; a change that removes or renames one
bumps the schema number.
"""

from __future__ import annotations

import json
import math
import re
import socket
import time
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from dataclasses import fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import harness
from harness.checks import Result
from harness.results.files import atomic_write_text

if TYPE_CHECKING:
    from harness.results.gate import GateFinding, Verdict

__all__ = ["SCHEMA", "results_to_json", "results_from_json", "result_row", "result_from_row", "write_json", "write_junit"]

SCHEMA = 1
# the record's fields but its drawing (references for the report's pictures, not data)
_FIELDS = tuple(f.name for f in fields(Result) if f.name != "drawing")


def _clean(value: Any) -> Any:
    """JSON-safe: non-finite floats become strings ("inf", "nan")."""
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def call_failures(results: Iterable[Result]) -> dict[str, dict[str, list[str]]]:
    """Per rasterizer, the cases whose call timed out (cut off twice by its time limit), the
    cases whose call failed (raised, crashed) and the cases whose call was answered only
    when asked again; only rasterizers with any appear.

    >>> call_failures([Result("r", "a", "run", "error", "timeout: no answer within 2 s, nor within 8 s when asked again"),
    ...                Result("r", "b", "conformance", "pass", "ok", {}, {"retried": "cut off after 2 s, answered ..."})])
    {'r': {'timed_out': ['a'], 'failed': [], 'retried': ['b']}}
    """
    out: dict[str, dict[str, list[str]]] = {}
    for r in results:
        kind = ("timed_out" if r.status == "error" and "timeout: " in r.message[:40] else
                "failed" if r.status == "error" and "traceback" in r.evidence else
                "retried" if "retried" in r.evidence else None)
        if kind is None:
            continue
        found = out.setdefault(r.rasterizer, {"timed_out": [], "failed": [], "retried": []})[kind]
        if r.case not in found:
            found.append(r.case)
    return out


def call_failures_text(found: dict[str, list[str]], most: int = 5) -> str:
    """One line of :func:`call_failures`' entry for a rasterizer."""
    said = {"timed_out": "timed out (each asked twice)", "failed": "failed (raised or crashed)",
            "retried": "answered only when asked again"}
    parts = [f"{len(cases)} call{'' if len(cases) == 1 else 's'} {said[kind]}: " + ", ".join(cases[:most])
             + (f" and {len(cases) - most} more" if len(cases) > most else "")
             for kind, cases in found.items() if cases]
    return "; ".join(parts)


def results_to_json(results: Iterable[Result], suite: str, seed: int, rasterizers: dict[str, str],
                    fingerprints: dict[str, dict[str, Any]] | None = None, *,
                    scene_kinds: dict[str, tuple[str, ...]] | None = None, fill_rules: dict[str, tuple[str, ...]] | None = None,
                    line_rules: dict[str, str] | None = None,
                    facets: dict[str, dict[str, str]] | None = None) -> dict[str, Any]:
    """The schema-1 document of a run; ``scene_kinds``, ``fill_rules``, ``line_rules`` and ``facets``
    (:func:`harness.report.pages.capabilities`: pass it on as ``**capabilities(rs)``) are written
    when given.

    >>> doc = results_to_json([], "custom", 0, {"r": "x"}, scene_kinds={"r": ("lines",)}, line_rules={"r": "rectangular lines"})
    >>> doc["scene_kinds"], doc["line_rules"], "fill_rules" in doc
    ({'r': ['lines']}, {'r': 'rectangular lines'}, False)
    """
    results = list(results)
    rows = [result_row(r) for r in results]
    failures = call_failures(results)
    known = {"scene_kinds": scene_kinds, "fill_rules": fill_rules, "line_rules": line_rules, "facets": facets}
    return {
        "schema": SCHEMA,
        "rastercheck": harness.__version__,
        "suite": suite,
        "seed": seed,
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "rasterizers": rasterizers,
        **({"fingerprints": _clean(fingerprints)} if fingerprints else {}),
        **{field: _clean(value) for field, value in known.items() if value is not None},
        # per rasterizer: cases whose call timed out, failed, was asked again
        **({"call_failures": failures} if failures else {}), "results": rows,
    }


def results_from_json(data: dict[str, Any]) -> list[Result]:
    """Result records back from a schema-1 document; ValueError naming what is wrong."""
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"not a rastercheck results file of schema {SCHEMA}")
    try:
        return [result_from_row(r) for r in data["results"]]
    except (KeyError, TypeError) as exc:
        raise ValueError(f"malformed results: {exc}") from None


def result_row(result: Result) -> dict[str, Any]:
    """One result as the schema's ``results`` entry (the run journal's result lines too).

    >>> result_row(Result("r", "a", "conformance", "pass", "ok", {"seconds": float("inf")}))["metrics"]
    {'seconds': 'inf'}
    """
    # built from the fields (no asdict: it would deep-copy a drawing's arrays only to drop them)
    row: dict[str, Any] = _clean({name: getattr(result, name) for name in _FIELDS})
    return row


def result_from_row(row: dict[str, Any]) -> Result:
    """A result back from its :func:`result_row` (no drawing); KeyError or TypeError for a
    row that is not one."""
    return Result(row["rasterizer"], row["case"], row["check"], row["status"], row["message"],
                  row.get("metrics", {}), row.get("evidence", {}))


def write_json(path: Path | str, results: Iterable[Result], suite: str, seed: int, rasterizers: dict[str, str],
               fingerprints: dict[str, dict[str, Any]] | None = None, **capabilities: Any) -> Path:
    """:func:`results_to_json` written atomically (``capabilities``: its keyword fields)."""
    path = Path(path)
    atomic_write_text(path, json.dumps(results_to_json(results, suite, seed, rasterizers, fingerprints, **capabilities),
                                       indent=1))
    return path


# Characters XML 1.0 cannot carry (a rasterizer's exception text may hold any of them).
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def _xml(text: str) -> str:
    return _NOT_XML.sub("\ufffd", text)


def _junit_seconds(r: Result) -> float:
    """A testcase's time: the result's rasterize seconds (0 when it has none)."""
    value = r.metrics.get("seconds", 0.0)
    return float(value) if isinstance(value, (int, float)) and math.isfinite(value) and value >= 0 else 0.0


def _error_type(message: str) -> str:
    """``timeout`` or the exception's name, from an error result's ``kind: text`` message."""
    head, colon, _ = message.partition(":")
    return head if colon and head.isidentifier() else "error"


def _known_failure(reason: str) -> str:
    # the default reason of earlier baselines starts so already
    return reason if reason.startswith("known failure") else f"known failure: {reason}"


def _junit_case(suite: ET.Element, r: Result, finding: GateFinding | None, notes: list[str]) -> None:
    """One testcase: its outcome from the result's status, or, under the gate, from its
    finding (a known failure is skipped, a regression fails, an unexpected pass passes
    with a note)."""
    case = ET.SubElement(suite, "testcase", classname=_xml(f"{r.rasterizer}.{r.check}"), name=_xml(r.case),
                         time=f"{_junit_seconds(r):.6f}")
    repro = f"\nminimal repro: {r.evidence['repro_path']}" if "repro_path" in r.evidence else ""
    regression = finding is not None and finding.verdict == "regression"
    message = finding.text if finding is not None and regression else r.message
    if finding is not None and finding.verdict == "known":
        ET.SubElement(case, "skipped", message=_xml(_known_failure(finding.reason)))
    elif finding is not None and finding.verdict == "fixed":
        notes.append(f"UNEXPECTEDLY PASSING {finding}")
    elif finding is not None and finding.verdict == "flaky":  # neither a pass nor a regression: said, not failed
        ET.SubElement(case, "skipped", message=_xml(f"flaky: {finding.text}"))
    elif r.status == "error":  # a crash or a timeout, new or regressed
        ET.SubElement(case, "error", type=_error_type(r.message), message=_xml(message)).text = _xml(
            str(r.evidence.get("traceback") or r.message + repro))
    elif r.status == "fail" or regression:  # a regression may be a metric of a passing check
        ET.SubElement(case, "failure", type="regression" if regression else r.check, message=_xml(message)).text = _xml(
            message + repro)
    elif r.status == "skip":
        ET.SubElement(case, "skipped", message=_xml(r.message))


def write_junit(path: Path | str, results: Iterable[Result], verdict: Verdict | None = None) -> Path:
    """JUnit XML valid against the Ant/Jenkins ``JUnit.xsd``: one testsuite per
    rasterizer, one testcase per case and check; the suites' counts are those of the
    testcases' outcomes.

    Without ``verdict``: fail is a ``<failure>``, error an ``<error>``, skip ``<skipped>``.
    With the gate's (:func:`harness.results.gate.compare_with_baseline`): a regression is a
    ``<failure>`` (an ``<error>`` when it crashed or timed out), a known failure is
    ``<skipped message="known failure: <reason>">``, an unexpected pass passes with a
    property and a line of system-out on its suite, and a missing result is a testcase
    of its own that fails.
    """
    by_rasterizer: dict[str, list[Result]] = {}
    for r in results:
        by_rasterizer.setdefault(r.rasterizer, []).append(r)
    findings: dict[str, GateFinding] = {}
    missing: dict[str, list[GateFinding]] = {}
    if verdict is not None:
        findings = verdict.by_key()
        for f in verdict.of("missing"):
            missing.setdefault(f.rasterizer, []).append(f)
            by_rasterizer.setdefault(f.rasterizer, [])
    stamp = time.strftime("%Y-%m-%dT%H:%M:%S")  # the schema's timestamp: local time, no zone
    host = socket.gethostname() or "localhost"
    root = ET.Element("testsuites")
    for number, (name, mine) in enumerate(by_rasterizer.items()):
        suite = ET.SubElement(root, "testsuite", name=_xml(name), package="rastercheck", id=str(number),
                              timestamp=stamp, hostname=_xml(host))
        properties = ET.SubElement(suite, "properties")
        notes: list[str] = []
        for r in mine:
            _junit_case(suite, r, findings.get(f"{r.rasterizer}|{r.case}|{r.check}"), notes)
        for f in missing.get(name, []):
            case = ET.SubElement(suite, "testcase", classname=_xml(f"{name}.{f.check}"), name=_xml(f.case), time="0")
            ET.SubElement(case, "failure", type="missing", message=_xml(f.text)).text = _xml(
                f"{f.text} (--allow-missing for a partial run)")
        for note in notes:
            ET.SubElement(properties, "property", name="rastercheck.gate", value=_xml(note))
        ET.SubElement(suite, "system-out").text = _xml("\n".join(notes))
        ET.SubElement(suite, "system-err")
        cases = suite.findall("testcase")
        suite.set("tests", str(len(cases)))
        for attribute, tag in (("failures", "failure"), ("errors", "error"), ("skipped", "skipped")):
            suite.set(attribute, str(sum(c.find(tag) is not None for c in cases)))
        suite.set("time", f"{sum(float(c.get('time', 0)) for c in cases):.6f}")
    path = Path(path)
    atomic_write_text(path, ET.tostring(root, encoding="unicode", xml_declaration=True))
    return path
