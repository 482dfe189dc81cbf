"""The atlas's data: every real library in every mode, judged and fingerprinted, as one
JSON document (the page's twin, :data:`ATLAS_SCHEMA`, written atomically).

One entry per adapter (a library in one mode: ``cairo`` and ``cairo_aa``), grouped by
library; per scene kind (triangles, paths, lines) a cell: whether the adapter takes the kind
(and why not), what identify found for that kind (the convention, exact or a best guess
with its residual pixels), the quick suite's results on the kind's cases, the failing
results by cause with the run report's anchor and minimal repro of each, seconds per call,
and the other adapters that draw the same on the kind (:mod:`harness.diagnose.alike`).

Schema 1::

    {"schema": 1, "document": "rastercheck atlas", "rastercheck": str, "created": str,
     "suite": str, "seed": int, "seconds": float,
     "libraries": [{"library": str, "version": str, "adapters": [ADAPTER, ...]}],
     "missing": [{"adapter": str, "why": str}],            # registered, not installed here
     "groups": {"<kind>": [[adapter, ...], ...]},           # drawing alike, per kind
     "pairs": [{"kind", "a", "b", "scenes", "differing", "pixels"}],
     "upstream": [{"library": str, "script": str, "title": str}]}

    ADAPTER = {"adapter": str, "coverage_kind": "single" | "multisample" | "area",
               "declared": str, "page": str (the run report's page), "seconds_per_call": float | null,
               "fingerprint_error": str | null,
               "kinds": {"triangles" | "paths" | "lines": CELL}}
    CELL = {"taken": bool, "why_not": str | null,
            "identified": {"convention": str, "exact": bool, "residual": int | null, "pixels": int | null} | null,
            "fill_rules": [str] | null,                      # paths: the rules honoured
            "results": {"pass": int, "fail": int, "error": int, "skip": int},
            "causes": [{"cause": str, "count": int, "checks": [str], "link": str, "repro": str | null}],
            "seconds_per_call": float | null, "alike": [str]}
"""

from __future__ import annotations

import json
import statistics
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import harness
from harness.checks import Result
from harness.contract.case import Case, MotionCase
from harness.contract.protocol import Rasterizer, coverage_kind_of, fill_rules_of, library_of, scene_kinds_of
from harness.diagnose.alike import Pair, groups
from harness.diagnose.causes import by_cause
from harness.kinds import kind_of
from harness.report.pages import _line_identified, _path_convention, page_name
from harness.results.files import atomic_write_text

__all__ = ["ATLAS_SCHEMA", "ATLAS_KINDS", "atlas_document", "write_atlas_json", "read_atlas_json", "atlas_fault"]

ATLAS_KINDS = ("triangles", "paths", "lines")
_STATUSES = ("pass", "fail", "error", "skip")

_IDENTIFIED = {"type": ["object", "null"], "required": ["convention", "exact"],
               "properties": {"convention": {"type": "string"}, "exact": {"type": "boolean"},
                              "residual": {"type": ["integer", "null"]}, "pixels": {"type": ["integer", "null"]}}}
_CELL = {"type": "object", "required": ["taken", "why_not", "identified", "results", "causes", "alike"],
         "properties": {
             "taken": {"type": "boolean"}, "why_not": {"type": ["string", "null"]}, "identified": _IDENTIFIED,
             "fill_rules": {"type": ["array", "null"], "items": {"enum": ["nonzero", "evenodd"]}},
             "results": {"type": "object", "required": list(_STATUSES),
                         "properties": {s: {"type": "integer", "minimum": 0} for s in _STATUSES}},
             "causes": {"type": "array", "items": {
                 "type": "object", "required": ["cause", "count", "checks", "link", "repro"],
                 "properties": {"cause": {"type": "string"}, "count": {"type": "integer"},
                                "checks": {"type": "array", "items": {"type": "string"}},
                                "link": {"type": "string"}, "repro": {"type": ["string", "null"]}}}},
             "seconds_per_call": {"type": ["number", "null"]},
             "alike": {"type": "array", "items": {"type": "string"}}}}
ATLAS_SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "type": "object",
    "required": ["schema", "document", "rastercheck", "created", "suite", "seed", "seconds", "libraries", "missing",
                 "groups", "pairs", "upstream"],
    "properties": {
        "schema": {"const": 1}, "document": {"const": "rastercheck atlas"}, "rastercheck": {"type": "string"},
        "created": {"type": "string"}, "suite": {"type": "string"}, "seed": {"type": "integer"},
        "seconds": {"type": "number"},
        "libraries": {"type": "array", "items": {
            "type": "object", "required": ["library", "version", "adapters"],
            "properties": {"library": {"type": "string"}, "version": {"type": "string"},
                           "adapters": {"type": "array", "items": {
                               "type": "object",
                               "required": ["adapter", "coverage_kind", "declared", "page", "seconds_per_call", "kinds"],
                               "properties": {"adapter": {"type": "string"},
                                              "coverage_kind": {"enum": ["single", "multisample", "area"]},
                                              "declared": {"type": "string"}, "page": {"type": "string"},
                                              "seconds_per_call": {"type": ["number", "null"]},
                                              "fingerprint_error": {"type": ["string", "null"]},
                                              "kinds": {"type": "object", "required": list(ATLAS_KINDS),
                                                        "properties": {k: _CELL for k in ATLAS_KINDS}}}}}}}},
        "missing": {"type": "array", "items": {"type": "object", "required": ["adapter", "why"]}},
        "groups": {"type": "object", "additionalProperties": {"type": "array", "items": {"type": "array",
                                                                                          "items": {"type": "string"}}}},
        "pairs": {"type": "array", "items": {"type": "object",
                                             "required": ["kind", "a", "b", "scenes", "differing", "pixels"]}},
        "upstream": {"type": "array", "items": {"type": "object", "required": ["library", "script", "title"]}},
    },
}

# why an adapter does not take a kind, when it does not say (``kinds_not_taken``)
_NOT_ADAPTED = "not adapted: the library has no such mode, or this adapter does not drive it"


def _case_kinds(cases: Sequence[Case | MotionCase]) -> dict[str, str]:
    """Case id -> the kind of its scene (a motion case's first frame's)."""
    out = {}
    for case in cases:
        scene = case.scene if isinstance(case, Case) else case.frames[0] if case.frames else None
        if scene is not None:
            out[case.id] = kind_of(scene).name
    return out


def _seconds(results: Sequence[Result]) -> float | None:
    """The median seconds of one rasterize call over these results' cases (each case's
    call counted once: its checks share it)."""
    per_case: dict[str, float] = {}
    for r in results:
        seconds = r.metrics.get("seconds")
        if isinstance(seconds, (int, float)):
            per_case[r.case] = max(per_case.get(r.case, 0.0), float(seconds))
    return statistics.median(per_case.values()) if per_case else None


def _identified(kind: str, fingerprint: dict[str, Any] | None) -> dict[str, Any] | None:
    """What identify found of a kind, from a fingerprint dict (None when it found nothing)."""
    if not isinstance(fingerprint, dict) or "error" in fingerprint:
        return None
    if kind == "triangles":
        if fingerprint.get("no_answers") or not isinstance(fingerprint.get("convention"), str):
            return None
        return {"convention": fingerprint["convention"], "exact": bool(fingerprint.get("exact")),
                "residual": fingerprint.get("residual"), "pixels": fingerprint.get("pixels")}
    found = _path_convention(fingerprint) if kind == "paths" else _line_identified(fingerprint)
    if found is None:
        return None
    return {"convention": str(found["text"]), "exact": bool(found.get("exact")), "residual": found.get("residual"),
            "pixels": found.get("pixels")}


def _cell(rasterizer: Rasterizer, kind: str, mine: list[Result], case_kinds: dict[str, str],
          fingerprint: dict[str, Any] | None, cause_links: list[dict[str, Any]], alike: list[str]) -> dict[str, Any]:
    taken = kind in scene_kinds_of(rasterizer)
    inner = getattr(rasterizer, "inner", rasterizer)
    not_taken = getattr(inner, "kinds_not_taken", None) or {}
    of_kind = [r for r in mine if case_kinds.get(r.case) == kind]
    causes = [dict(c, count=n) for c in cause_links if (n := c["counts"].get(kind, 0))]
    for c in causes:
        del c["counts"]
    return {
        "taken": taken,
        "why_not": None if taken else str(not_taken.get(kind, _NOT_ADAPTED)),
        "identified": _identified(kind, fingerprint) if taken else None,
        "fill_rules": list(fill_rules_of(rasterizer)) if kind == "paths" and taken else None,
        "results": {s: sum(r.status == s for r in of_kind) for s in _STATUSES},
        "causes": causes,
        "seconds_per_call": _seconds(of_kind),
        "alike": alike,
    }


def _causes(name: str, mine: list[Result], case_kinds: dict[str, str]) -> list[dict[str, Any]]:
    """The run report's causes of one rasterizer, in its order (anchors ``cause-k`` of its
    page, as :func:`harness.report.pages.write_report` numbers them), each with its
    failing results counted per scene kind."""
    out = []
    for k, group in enumerate(by_cause(mine)):
        counts: dict[str, int] = {}
        for r in group.results:
            kind = case_kinds.get(r.case, "other")
            counts[kind] = counts.get(kind, 0) + 1
        out.append({"cause": group.cause, "checks": list(group.checks), "link": f"{page_name(name)}#cause-{k}",
                    "repro": group.repro_path(), "counts": counts})
    return out


def atlas_document(rasterizers: Sequence[Rasterizer], results: Sequence[Result], fingerprints: dict[str, dict[str, Any]],
                   cases: Sequence[Case | MotionCase], pairs: Sequence[Pair], *, missing: dict[str, str],
                   upstream: Sequence[dict[str, str]], versions: dict[str, str], suite: str, seed: int,
                   seconds: float) -> dict[str, Any]:
    """The atlas as plain data (the module docstring's schema)."""
    case_kinds = _case_kinds(cases)
    found_groups = groups(pairs)
    alike: dict[tuple[str, str], list[str]] = {}
    for kind, kind_groups in found_groups.items():
        for members in kind_groups:
            for name in members:
                alike[(kind, name)] = [m for m in members if m != name]
    libraries: dict[str, dict[str, Any]] = {}
    for r in rasterizers:
        library, version = library_of(r)
        version = versions.get(r.name) or version
        mine = [x for x in results if x.rasterizer == r.name]
        cause_links = _causes(r.name, mine, case_kinds)
        fingerprint = fingerprints.get(r.name)
        inner = getattr(r, "inner", r)
        entry = libraries.setdefault(library, {"library": library, "version": version, "adapters": []})
        entry["version"] = entry["version"] or version
        entry["adapters"].append({
            "adapter": r.name, "coverage_kind": coverage_kind_of(r),
            "declared": inner.convention.describe() if inner.convention is not None else "none declared",
            "page": page_name(r.name), "seconds_per_call": _seconds(mine),
            "fingerprint_error": fingerprint.get("error") if isinstance(fingerprint, dict) else None,
            "kinds": {kind: _cell(r, kind, mine, case_kinds, fingerprint, cause_links, alike.get((kind, r.name), []))
                      for kind in ATLAS_KINDS}})
    return {
        "schema": 1, "document": "rastercheck atlas", "rastercheck": harness.__version__,
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "suite": suite, "seed": seed, "seconds": round(seconds, 1),
        "libraries": sorted(libraries.values(), key=lambda e: e["library"].lower()),
        "missing": [{"adapter": name, "why": why} for name, why in sorted(missing.items())],
        "groups": found_groups,
        "pairs": [{"kind": p.kind, "a": p.a, "b": p.b, "scenes": p.scenes, "differing": p.differing, "pixels": p.pixels}
                  for p in pairs],
        "upstream": list(upstream),
    }


def atlas_fault(data: Any) -> str | None:
    """The first fault of an atlas document against :data:`ATLAS_SCHEMA`, or None."""
    import jsonschema

    from harness.results.schemas import schema_fault

    return schema_fault(jsonschema.Draft202012Validator(ATLAS_SCHEMA), data)


def write_atlas_json(path: Path | str, document: dict[str, Any]) -> Path:
    """Write the atlas document atomically, after checking it against its schema."""
    fault = atlas_fault(document)
    if fault is not None:
        raise ValueError(f"the atlas document breaks its schema {fault}")
    path = Path(path)
    atomic_write_text(path, json.dumps(document, indent=1))
    return path


def read_atlas_json(path: Path | str) -> dict[str, Any]:
    """An atlas document read back and checked; ValueError naming the file and the fault."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: not an atlas document ({exc})") from None
    fault = atlas_fault(data)
    if fault is not None:
        raise ValueError(f"{path}: {fault}")
    return dict(data)
