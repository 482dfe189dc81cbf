"""Differences between two runs: ``rastercheck diff A.json B.json``.

Like piglit's summary pages: results are matched by (rasterizer, case, check); each
pair falls in one class -- a **regression** (it passed, was skipped or did not exist, and
now fails or errors), a **fix** (it failed or errored and now passes), another **status
change** (say, a failure that now errors), **new** or **removed** -- and metrics that moved
are listed (timings left out: they differ between any two runs). Printed as a summary and
written as one HTML page.
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from harness.checks import Result, timing_metrics
from harness.results.files import atomic_write_text

__all__ = ["Change", "RunDiff", "diff_runs", "load_run", "write_diff_page"]

BAD = ("fail", "error")
CATEGORIES = ("regression", "fix", "status change", "new", "removed")


@dataclass(frozen=True)
class Change:
    """One (rasterizer, case, check) whose status or metrics differ between the runs;
    ``category`` is its class: one of :data:`CATEGORIES`, or ``metrics`` (only metrics moved)."""

    category: str
    rasterizer: str
    case: str
    check: str
    before: str | None
    after: str | None
    message: str
    metrics: dict[str, tuple[float | None, float | None]] = field(default_factory=dict)


@dataclass
class RunDiff:
    """Everything that differs between run A and run B."""

    a: str
    b: str
    changes: list[Change] = field(default_factory=list)
    unchanged: int = 0

    def of(self, category: str) -> list[Change]:
        return [c for c in self.changes if c.category == category]

    @property
    def metric_changes(self) -> list[Change]:
        return [c for c in self.changes if c.metrics]

    def lines(self) -> list[str]:
        """The summary: counts by category, then per rasterizer and check, then each change."""
        counts = Counter(c.category for c in self.changes if c.category in CATEGORIES)
        out = [f"{self.a} -> {self.b}: " + ", ".join(f"{k}: {counts[k]}" for k in CATEGORIES)
               + f", metric changes: {len(self.metric_changes)}, unchanged: {self.unchanged}"]
        per = Counter((c.rasterizer, c.check, c.category) for c in self.changes if c.category in CATEGORIES)
        for (rasterizer, check, category), n in sorted(per.items()):
            out.append(f"  {rasterizer:<22} {check:<12} {n:>5} {category}")
        for c in self.changes:
            if c.category in CATEGORIES:
                out.append(f"{c.category.upper():<14} {c.rasterizer} {c.case} {c.check}: {c.before or '-'} -> {c.after or '-'}"
                           + (f"  {c.message}" if c.message else ""))
        for c in self.metric_changes:
            moved = ", ".join(f"{name} {old} -> {new}" for name, (old, new) in c.metrics.items())
            out.append(f"metrics        {c.rasterizer} {c.case} {c.check}: {moved}")
        return out


def _key(r: Result) -> tuple[str, str, str]:
    return (r.rasterizer, r.case, r.check)


def diff_runs(a: list[Result], b: list[Result], a_name: str = "A", b_name: str = "B") -> RunDiff:
    """Match the results of two runs and classify every difference."""
    timing = timing_metrics()
    before = {_key(r): r for r in a}
    after = {_key(r): r for r in b}
    diff = RunDiff(a_name, b_name)
    for key in sorted(before.keys() | after.keys()):
        old, new = before.get(key), after.get(key)
        if old is None and new is not None:
            category = "regression" if new.status in BAD else "new"
        elif new is None and old is not None:
            category = "removed"
        else:
            assert old is not None and new is not None
            if old.status == new.status:
                category = ""
            elif new.status in BAD and old.status not in BAD:
                category = "regression"
            elif old.status in BAD and new.status == "pass":
                category = "fix"
            else:
                category = "status change"
        metrics: dict[str, tuple[float | None, float | None]] = {}
        if old is not None and new is not None:
            for name in sorted((old.metrics.keys() | new.metrics.keys()) - timing):
                x, y = old.metrics.get(name), new.metrics.get(name)
                if x != y and not (isinstance(x, float) and isinstance(y, float) and x != x and y != y):
                    metrics[name] = (x, y)
        if not category and not metrics:
            diff.unchanged += 1
            continue
        shown = new if new is not None else old
        message = shown.message if shown is not None else ""
        diff.changes.append(Change(category or "metrics", *key, old.status if old else None, new.status if new else None,
                                   message, metrics))
    return diff


def load_run(path: Path | str) -> list[Result]:
    """The results of a ``--json`` file; ValueError naming the file and the fault."""
    from harness.results.output import results_from_json

    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise ValueError(f"{path}: cannot read the results ({exc})") from None
    try:
        return results_from_json(data)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def write_diff_page(out: Path | str, diff: RunDiff) -> Path:
    """``<out>/diff.html``: the changes by category, per rasterizer and check."""
    from harness.report.pages import _environment, link_pages, page_meta

    counts = Counter(c.category for c in diff.changes)
    per = Counter((c.rasterizer, c.check, c.category) for c in diff.changes)
    html = _environment().get_template("diff.html").render(diff=diff, categories=CATEGORIES, counts=counts, per=sorted(per.items()),
                                                           meta=page_meta("diff", "-"))
    path = Path(out) / "diff.html"
    atomic_write_text(path, html)
    link_pages(Path(out))  # index.html, when there is one, links the new page
    return path
