"""The run journal: every result of ``rastercheck run`` on disk as soon as it exists.

A run appends to ``<out>/run.journal.jsonl`` one JSON object a line, each of one key:

* ``{"header": {...}}``, the first line: the run's parameters (:func:`run_parameters`);
* ``{"result": {...}}``, one per result, the very entry of the ``--json`` file's
  ``results`` (:func:`harness.results.output.result_row`);
* ``{"complete": {"rasterizer": str, "case": str}}`` once every result of that rasterizer
  on that case is written (a case that gives no result is complete too).

Each line is written whole and flushed at once (a run killed by a signal, a plugin or the
OOM killer keeps every line before), and the file is fsync'ed at each complete pair at
most every :data:`SYNC_SECONDS` (and when the run ends), so that even a machine that
loses power keeps all but the last fraction of a second. A last line without its newline
(torn: killed mid-write) is ignored on reading; the results of a pair with no ``complete``
line are dropped, and ``run --resume`` runs that pair again.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
import threading
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from harness.checks import Result
from harness.results.files import atomic_write_text, read_input
from harness.results.output import result_from_row, result_row

__all__ = ["JOURNAL_NAME", "FORMAT", "SYNC_SECONDS", "Recorded", "JournalWriter", "journal_path", "run_parameters",
           "read_journal", "parameter_difference"]

JOURNAL_NAME = "run.journal.jsonl"
FORMAT = 1
SYNC_SECONDS = 0.5
_STATUSES = ("pass", "fail", "error", "skip")
# the header's parameters, as the command line names them (for the refusal of --resume)
_OPTIONS = {"rastercheck": "the rastercheck version", "specs": "--rasterizer", "suite": "--suite", "seed": "--seed",
            "cases": "--case", "checks": "--check", "shard": "--shard", "skip": "--skip (its entries)", "rerun": "--rerun"}


def journal_path(out: Path | str) -> Path:
    """The journal of a run whose report goes to the folder ``out``."""
    return Path(out) / JOURNAL_NAME


def run_parameters(version: str, specs: list[str] | None, suite: str, seed: int, cases: list[str] | None,
                   checks: list[str] | None, shard: tuple[int, int] | None, skip: list[tuple[str, str]],
                   rerun: int) -> dict[str, Any]:
    """The parameters that decide a run's results, as its journal's header holds them
    (JSON values, so that a header read back compares equal).

    >>> run_parameters("0.1.0", ["a"], "quick", 0, None, None, (1, 2), [], 0)["shard"]
    '1/2'
    """
    return {"rastercheck": version, "specs": list(specs) if specs else None, "suite": suite, "seed": seed,
            "cases": list(cases) if cases else None, "checks": sorted(set(checks)) if checks else None,
            "shard": f"{shard[0]}/{shard[1]}" if shard else None, "skip": [list(entry) for entry in skip], "rerun": rerun}


def parameter_difference(recorded: dict[str, Any], wanted: dict[str, Any]) -> str | None:
    """The first parameter in which a journal's header and this run differ, in words, or
    None when they agree.

    >>> parameter_difference({"seed": 0, "suite": "quick"}, {"seed": 1, "suite": "quick"})
    '--seed was 0, is now 1'
    """
    for key in (*wanted, *(k for k in recorded if k not in wanted)):
        if recorded.get(key) != wanted.get(key):
            return f"{_OPTIONS.get(key, key)} was {_said(recorded.get(key))}, is now {_said(wanted.get(key))}"
    return None


def _said(value: Any) -> str:
    if value is None:
        return "not given"
    if isinstance(value, list):
        return " ".join(" # ".join(map(str, v)) if isinstance(v, list) else str(v) for v in value) or "empty"
    return str(value)


@dataclass
class Recorded:
    """What a journal holds: its header's parameters, the results of its complete
    (rasterizer, case) pairs, in the order written, and those pairs."""

    parameters: dict[str, Any]
    results: list[Result] = field(default_factory=list)
    complete: set[tuple[str, str]] = field(default_factory=set)


def read_journal(path: Path | str) -> Recorded:
    """The journal at ``path``; ValueError in one line naming the file (and the line) for
    one that cannot be read or is malformed. A torn last line is ignored."""
    path = Path(path)
    try:
        text = read_input(path, "the run journal").decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"the run journal {path} cannot be read ({exc})") from None
    lines = text.split("\n")
    lines.pop()  # after the last newline: empty, or a line torn mid-write
    if not lines:
        raise ValueError(f"the run journal {path} is empty: no header line")
    recorded: Recorded | None = None
    pending: dict[tuple[str, str], list[Result]] = {}
    for number, line in enumerate(lines, 1):
        where = f"the run journal {path}, line {number}"
        try:
            entry = json.loads(line)
        except ValueError as exc:
            raise ValueError(f"{where}: not JSON ({exc}): malformed") from None
        if not isinstance(entry, dict) or len(entry) != 1:
            raise ValueError(f"{where}: not an object of one key (header, result or complete): malformed")
        (kind, value), = entry.items()
        if number == 1:
            if kind != "header" or not isinstance(value, dict) or value.get("journal") != FORMAT \
                    or not isinstance(value.get("parameters"), dict):
                raise ValueError(f"{where}: not a run journal header of format {FORMAT}: malformed")
            recorded = Recorded(value["parameters"])
            continue
        assert recorded is not None
        if kind == "result":
            result = _result(value, where)
            pending.setdefault((result.rasterizer, result.case), []).append(result)
        elif kind == "complete":
            if not isinstance(value, dict) or not isinstance(value.get("rasterizer"), str) \
                    or not isinstance(value.get("case"), str):
                raise ValueError(f"{where}: a complete line names no rasterizer and case: malformed")
            pair = (value["rasterizer"], value["case"])
            if pair not in recorded.complete:
                recorded.complete.add(pair)
                recorded.results += pending.pop(pair, [])
        else:
            raise ValueError(f"{where}: a line of kind {kind!r}, not result or complete: malformed")
    assert recorded is not None
    return recorded


def _result(row: Any, where: str) -> Result:
    """A result line's result; ValueError saying what is wrong with it."""
    if not isinstance(row, dict):
        raise ValueError(f"{where}: a result that is not an object: malformed")
    for name in ("rasterizer", "case", "check", "message"):
        if not isinstance(row.get(name), str):
            raise ValueError(f"{where}: a result without a text {name}: malformed")
    if row.get("status") not in _STATUSES:
        raise ValueError(f"{where}: a result of status {row.get('status')!r}, not one of {', '.join(_STATUSES)}: malformed")
    if not isinstance(row.get("metrics", {}), dict) or not isinstance(row.get("evidence", {}), dict):
        raise ValueError(f"{where}: a result whose metrics or evidence is not an object: malformed")
    return result_from_row(row)


class JournalWriter:
    """The journal of a run being written: a new file (replacing any, atomically) holding
    the header and, when resuming, what is carried over (``carried``: the complete pairs
    of the old journal); then one line per :meth:`result` and :meth:`complete`, from any
    thread."""

    def __init__(self, path: Path | str, parameters: dict[str, Any], carried: Recorded | None = None) -> None:
        self.path = Path(path)
        self._lock = threading.Lock()
        self._synced = time.monotonic()
        lines = [_line({"header": {"journal": FORMAT, "parameters": parameters}})]
        if carried is not None:
            by_pair: dict[tuple[str, str], list[Result]] = {}
            for r in carried.results:
                by_pair.setdefault((r.rasterizer, r.case), []).append(r)
            for pair in sorted(carried.complete):
                lines += [_line({"result": result_row(r)}) for r in by_pair.get(pair, [])]
                lines.append(_line({"complete": {"rasterizer": pair[0], "case": pair[1]}}))
        self._write_new("".join(lines))
        self._file: IO[str] | None = open(self.path, "a", encoding="utf-8")

    def _write_new(self, text: str) -> None:
        """``text`` as the whole journal: a temporary file beside it, synced, renamed over it."""
        atomic_write_text(self.path, text, durable=True)

    def result(self, result: Result) -> None:
        """Append one result line, flushed."""
        self._append(_line({"result": result_row(result)}), sync=False)

    def results(self, results: Iterable[Result]) -> None:
        """Append several result lines, flushed."""
        self._append("".join(_line({"result": result_row(r)}) for r in results), sync=False)

    def complete(self, rasterizer: str, case: str) -> None:
        """Append the line saying every result of ``rasterizer`` on ``case`` is written."""
        self._append(_line({"complete": {"rasterizer": rasterizer, "case": case}}), sync=True)

    def _append(self, text: str, sync: bool) -> None:
        with self._lock:
            if self._file is None or not text:
                return
            try:
                self._file.write(text)
                self._file.flush()  # in the kernel's hands: a killed process loses none of it
                if sync and time.monotonic() - self._synced >= SYNC_SECONDS:
                    os.fsync(self._file.fileno())
                    self._synced = time.monotonic()
            except OSError as exc:  # a full disk: the run goes on, its report and JSON still written at the end
                print(f"rastercheck: the run journal {self.path} cannot be written ({exc}): the results from now on "
                      "are not journaled", file=sys.stderr)
                with contextlib.suppress(OSError):
                    self._file.close()
                self._file = None

    def close(self) -> None:
        """Sync and close (idempotent)."""
        with self._lock:
            if self._file is None:
                return
            with contextlib.suppress(OSError):  # said by _append already, if the disk is full
                self._file.flush()
                os.fsync(self._file.fileno())
            with contextlib.suppress(OSError):
                self._file.close()
            self._file = None

    def __enter__(self) -> JournalWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _line(entry: dict[str, Any]) -> str:
    # one physical line: json.dumps escapes every newline inside strings
    return json.dumps(entry, separators=(",", ":")) + "\n"
