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
                       "exact": bool, "residual": int, "pixels": int,
                       "runner_up": [str, int] | null, "facts": {str: str},
                       "ambiguous": [str]}   # alternatives it could not separate
                       | {"error": str}},   # what identify found, when it ran
      "results": [
        {"rasterizer": str, "case": str, "check": str,
         "status": "pass" | "fail" | "error" | "skip",
         "message": str,
         "metrics": {str: number},          # totals; "seconds" is the rasterize time
         "evidence": {str: ...}}            # pixels, blame, series, repro
      ]
    }

Fields may be added in a later schema 1 file; a change that removes or renames one
bumps the schema number.
"""

from __future__ import annotations

import json
import math
import time
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from dataclasses import fields
from pathlib import Path
from typing import Any

import harness
from harness.checks import Result
from harness.files import atomic_write_text

__all__ = ["SCHEMA", "results_to_json", "results_from_json", "write_json", "write_junit"]

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


def results_to_json(results: Iterable[Result], suite: str, seed: int, rasterizers: dict[str, str],
                    fingerprints: dict[str, dict[str, Any]] | None = None) -> dict[str, Any]:
    # built from the fields (no asdict: it would deep-copy a drawing's arrays only to drop them)
    rows = [_clean({name: getattr(r, name) for name in _FIELDS}) for r in results]
    return {
        "schema": SCHEMA,
        "rastercheck": harness.__version__,
        "suite": suite,
        "seed": seed,
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "rasterizers": rasterizers,
        **({"fingerprints": _clean(fingerprints)} if fingerprints else {}),
        "results": rows,
    }


def results_from_json(data: dict[str, Any]) -> list[Result]:
    """Result records back from a schema-1 document; ValueError naming what is wrong."""
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"not a rastercheck results file of schema {SCHEMA}")
    try:
        return [
            Result(r["rasterizer"], r["case"], r["check"], r["status"], r["message"],
                   r.get("metrics", {}), r.get("evidence", {}))
            for r in data["results"]
        ]
    except (KeyError, TypeError) as exc:
        raise ValueError(f"malformed results: {exc}") from None


def write_json(path: Path | str, results: Iterable[Result], suite: str, seed: int, rasterizers: dict[str, str],
               fingerprints: dict[str, dict[str, Any]] | None = None) -> Path:
    path = Path(path)
    atomic_write_text(path, json.dumps(results_to_json(results, suite, seed, rasterizers, fingerprints), indent=1))
    return path


def write_junit(path: Path | str, results: Iterable[Result]) -> Path:
    """JUnit XML: one testsuite per rasterizer, one testcase per case and check."""
    by_rasterizer: dict[str, list[Result]] = {}
    for r in results:
        by_rasterizer.setdefault(r.rasterizer, []).append(r)
    root = ET.Element("testsuites", name="rastercheck")
    for name, mine in by_rasterizer.items():
        suite = ET.SubElement(
            root, "testsuite", name=name, tests=str(len(mine)),
            failures=str(sum(r.status == "fail" for r in mine)),
            errors=str(sum(r.status == "error" for r in mine)),
            skipped=str(sum(r.status == "skip" for r in mine)),
        )
        for r in mine:
            case = ET.SubElement(suite, "testcase", classname=f"{name}.{r.check}", name=r.case,
                                 time=f"{float(r.metrics.get('seconds', 0.0)):.6f}")
            detail = r.message
            if "repro_path" in r.evidence:
                detail += f"\nminimal repro: {r.evidence['repro_path']}"
            if r.status == "fail":
                ET.SubElement(case, "failure", message=r.message).text = detail
            elif r.status == "error":
                ET.SubElement(case, "error", message=r.message).text = r.evidence.get("traceback", "") or detail
            elif r.status == "skip":
                ET.SubElement(case, "skipped", message=r.message)
    path = Path(path)
    atomic_write_text(path, ET.tostring(root, encoding="unicode", xml_declaration=True))
    return path
