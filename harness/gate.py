"""The CI gate: compare a run with a checked-in baseline of known results.

A baseline maps ``rasterizer|case|check`` to the status and metrics seen when it was last
updated, and, for known failures, a reason a person wrote. The gate fails only on
regressions: a check that passed (or is new) now fails or errors, or a metric got worse
beyond its tolerance. A known failure that now passes is reported as unexpectedly passing.

Baseline file (JSON)::

    {"schema": 1, "entries": {"<rasterizer>|<case>|<check>":
        {"status": "pass" | "fail" | "error" | "skip", "metrics": {...}, "reason": "..."}}}
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from harness.checks import Result, metric_tolerance
from harness.files import atomic_write_text

__all__ = ["Verdict", "compare_with_baseline", "load_baseline", "save_baseline"]

SCHEMA = 1
BAD = ("fail", "error")
# Metrics where larger is worse, with the growth the gate lets through: each check
# declares its own (harness.checks.metric_tolerance()).


def key(r: Result) -> str:
    return f"{r.rasterizer}|{r.case}|{r.check}"


@dataclass
class Verdict:
    regressions: list[str] = field(default_factory=list)
    fixed: list[str] = field(default_factory=list)
    known: list[str] = field(default_factory=list)
    new: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.regressions

    def lines(self) -> list[str]:
        out = [f"REGRESSION {line}" for line in self.regressions]
        out += [f"UNEXPECTEDLY PASSING {line}" for line in self.fixed]
        out += [f"known failure {line}" for line in self.known]
        out += [f"new {line}" for line in self.new]
        return out


def load_baseline(path: Path | str) -> dict[str, dict[str, Any]]:
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{path}: no such baseline (create one with --update-baseline)") from None
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: unreadable baseline ({exc})") from None
    if not isinstance(data, dict) or data.get("schema") != SCHEMA or not isinstance(data.get("entries"), dict):
        raise ValueError(f"{path}: not a rastercheck baseline of schema {SCHEMA}")
    return data["entries"]


def save_baseline(path: Path | str, results: list[Result], previous: dict[str, dict[str, Any]] | None = None) -> Path:
    """Write the run as the new baseline, keeping the reasons of failures that remain."""
    previous = previous or {}
    entries = {}
    gated = metric_tolerance()
    for r in results:
        k = key(r)
        entry: dict[str, Any] = {"status": r.status, "metrics": {m: v for m, v in r.metrics.items() if m in gated}}
        if r.status in BAD:
            entry["reason"] = previous.get(k, {}).get("reason", "") or f"known failure: {r.message}"
        entries[k] = entry
    path = Path(path)
    atomic_write_text(path, json.dumps({"schema": SCHEMA, "entries": entries}, indent=1, sort_keys=True))
    return path


def compare_with_baseline(results: list[Result], baseline: dict[str, dict[str, Any]]) -> Verdict:
    verdict = Verdict()
    for r in results:
        k = key(r)
        before = baseline.get(k)
        if before is None:
            (verdict.regressions if r.status in BAD else verdict.new).append(f"{k}: {r.status}: {r.message}")
            continue
        was_bad = before.get("status") in BAD
        if r.status in BAD and not was_bad:
            verdict.regressions.append(f"{k}: was {before.get('status')}, now {r.status}: {r.message}")
        elif was_bad and r.status == "pass":
            verdict.fixed.append(f"{k}: was {before.get('status')} ({before.get('reason', '')}), now passes")
        elif was_bad:
            verdict.known.append(f"{k}: {before.get('reason', '')}")
        for metric, (factor, slack) in metric_tolerance().items():
            old, new = before.get("metrics", {}).get(metric), r.metrics.get(metric)
            if isinstance(old, (int, float)) and isinstance(new, (int, float)) and new > old * factor + slack:
                verdict.regressions.append(f"{k}: {metric} worsened from {old:g} to {new:g}")
    return verdict
