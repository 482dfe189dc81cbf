"""The ``rastercheck`` command's parser and dispatch: run, gate, compare, identify, replay, bench,
fuzz, diff, list (one module each: :mod:`harness.cli.run`, :mod:`~harness.cli.gate`, ...).

Exit codes: 0 everything passes, 1 a check fails or errors (for ``gate``: a regression),
2 a usage or configuration error, reported in one line without a traceback.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

from harness.cli.atlas import add_atlas_parser
from harness.cli.bench_command import _bench, _bench_kinds
from harness.cli.common import UsageError
from harness.cli.compare import _compare
from harness.cli.diff import _diff
from harness.cli.fuzz import _BUDGET_HELP, _budget, _families, _fuzz
from harness.cli.gate import _gate
from harness.cli.identify import _identify
from harness.cli.listing import _list
from harness.cli.replay import _replay
from harness.cli.run import _run, _shard

__all__ = ["main"]

# the --timeout of run, identify and fuzz
_TIMEOUT_HELP = "the most seconds one rasterize call may take (the cap of its scaled limit; see README, Reliability)"


def _positive_int(text: str) -> int:
    """A whole number >= 1 (``--jobs``), else a usage error naming the value."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, not {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, not {text!r}")
    return value


def _non_negative_int(text: str) -> int:
    """A whole number >= 0 (``--rerun``; fuzz's ``--seed``: scenes are drawn from non-negative seeds)."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, not {text!r}")
    return value


def _finite(text: str, zero_allowed: bool) -> float:
    """A finite number > 0 (>= 0 with ``zero_allowed``), else a usage error naming it."""
    wanted = ">= 0" if zero_allowed else "> 0"
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0 or (value == 0 and not zero_allowed):
        raise argparse.ArgumentTypeError(f"expected a finite number {wanted}, not {text!r}")
    return value


def _path(text: str) -> str:
    """An output or input path option: not empty (``--json ''`` wrote nothing, silently),
    no NUL (no file can be named so)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty path")
    if "\0" in text:
        raise argparse.ArgumentTypeError(f"{text!r} holds a NUL character, which no path can")
    return text


def _scheduler(text: str) -> str:
    """``--scheduler``: a Dask scheduler's tcp:// address (:func:`harness.campaign.cluster.scheduler_address`)."""
    from harness.campaign.cluster import scheduler_address

    try:
        return scheduler_address(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix(f"--scheduler {text}: ")) from None


def _positive_seconds(text: str) -> float:
    """``--timeout``, ``--scale``: a finite number > 0."""
    return _finite(text, zero_allowed=False)


def _non_negative_seconds(text: str) -> float:
    """``--budget``: a finite number >= 0 (0 measures each contender once)."""
    return _finite(text, zero_allowed=True)


def _selection(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--rasterizer", action="append", metavar="SPEC",
                        help="built-in name, module:attr or file.py:attr (repeatable; default all)")
    parser.add_argument("--suite", default="quick", help="quick or full (default quick)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--jobs", type=_positive_int, default=1, help="rasterizers checked side by side")
    parser.add_argument("--timeout", type=_positive_seconds, default=60.0, help=_TIMEOUT_HELP)
    parser.add_argument("--out", type=_path, default="reports", help="report directory (default reports/)")
    parser.add_argument("--json", type=_path, metavar="FILE", help="also write results as JSON (schema 1)")
    parser.add_argument("--junit", type=_path, metavar="FILE", help="also write JUnit XML")
    parser.add_argument("--no-fingerprints", action="store_true",
                        help="identify only rasterizers that declare no convention (faster; no side-by-side fingerprints)")
    parser.add_argument("--case", action="append", metavar="GLOB", help="only cases whose id matches (repeatable)")
    parser.add_argument("--check", action="append", metavar="NAME", help="only this check (repeatable)")
    parser.add_argument("--skip", metavar="FILE", help="a skip list: 'GLOB  # reason' per line; skipped cases are reported")
    parser.add_argument("--shard", type=_shard, metavar="K/N", help="run the K-th of N disjoint shares of the cases")
    parser.add_argument("--rerun", type=_non_negative_int, default=0, metavar="N",
                        help="rerun each failing check N times; one that changes is reported as flaky")
    parser.add_argument("--max-seconds", type=_positive_seconds, metavar="S",
                        help="a budget for the whole run: cases not started by then are errors ('not run')")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="rastercheck", description="Rasterization conformance and artifact harness.")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run the suite and write the HTML report")
    _selection(run)
    run.add_argument("--causes", type=_non_negative_int, default=8, metavar="N",
                     help="failure causes named in the terminal, the largest first (default 8; the report has all)")
    run.add_argument("--resume", action="store_true",
                     help="go on with the run whose journal is in --out (run.journal.jsonl): what it completed is not run again")
    run.set_defaults(func=_run)
    gate = sub.add_parser("gate", help="fail only on regressions against a baseline (for CI)")
    _selection(gate)
    gate.add_argument("--baseline", type=_path, required=True, metavar="FILE")
    gate.add_argument("--update-baseline", action="store_true",
                      help="write this run as the new baseline (the reasons of failures that remain are kept)")
    gate.add_argument("--allow-missing", action="store_true",
                      help="a result of the baseline missing from the run is no regression (a partial run: --case, --check, "
                           "--shard, fewer rasterizers); with --update-baseline, such entries are kept")
    gate.add_argument("--known-campaign", action="append", metavar="DIR",
                      help="a campaign's state folder (rastercheck fuzz --state): a failure it found (its case and check, "
                           "or its signature) is a known failure, not a regression (repeatable)")
    gate.set_defaults(func=_gate)
    cmp = sub.add_parser("compare", help="pixel differences between rasterizers, and the convention that separates them")
    cmp.add_argument("specs", nargs="+", metavar="SPEC")
    cmp.add_argument("--seed", type=int, default=0)
    cmp.add_argument("--out", type=_path, default="reports")
    cmp.add_argument("--json", type=_path, metavar="FILE")
    cmp.add_argument("--timeout", type=_positive_seconds, default=60.0,
                     help="the most seconds one rasterize call (and a plugin's import) may take (default 60)")
    cmp.set_defaults(func=_compare)
    ide = sub.add_parser("identify", help="fingerprint a rasterizer's convention from outside")
    ide.add_argument("spec", metavar="SPEC")
    ide.add_argument("--seed", type=int, default=0)
    ide.add_argument("--timeout", type=_positive_seconds, default=60.0, help=_TIMEOUT_HELP)
    ide.add_argument("--json", type=_path, metavar="FILE",
                     help="also write the fingerprint (and the verdict on a declared convention) as JSON")
    ide.set_defaults(func=_identify)
    rep = sub.add_parser("replay", help="run the checks of a saved case (a minimal repro) on a rasterizer")
    rep.add_argument("case", help="a case JSON file, as written under reports/repros/")
    rep.add_argument("--rasterizer", required=True, metavar="SPEC")
    rep.add_argument("--timeout", type=_positive_seconds, default=60.0)
    rep.set_defaults(func=_replay)
    bench = sub.add_parser("bench", help="throughput against Pillow, as ratios measured in one run")
    bench.add_argument("--rasterizer", action="append", metavar="SPEC")
    bench.add_argument("--json", metavar="FILE", help="write the measurements as JSON")
    bench.add_argument("--scale", type=_positive_seconds, default=1.0, help="shrink the workloads (smoke tests)")
    bench.add_argument("--budget", type=_non_negative_seconds, default=1.0, help="seconds of repeats per contender")
    bench.add_argument("--kinds", type=_bench_kinds, metavar="A,B",
                       help="only these workload kinds: triangles (W1, W2), paths (P1, P2, P3), lines (L1, L2), "
                            "anti-aliased strokes (S1, S2), identify (seconds of rastercheck identify per built-in mode); "
                            "default all but identify")
    bench.add_argument("--timeout", type=_positive_seconds, default=60.0,
                       help="the most seconds one call of a contender may take (each contender runs in a process of its own)")
    bench.add_argument("--campaign", action="store_true",
                       help="instead: a campaign of a fixed scene budget on 1, then 2 local workers (a built-in reference, "
                            "or --rasterizer): checked primitives/s per worker and the speed-up")
    bench.add_argument("--scenes", type=_positive_int, metavar="N", help="the scene budget of --campaign (default 6000)")
    bench.add_argument("--repeats", type=_positive_int, metavar="N",
                       help="rounds of --campaign over 1 and 2 workers, the fastest run of each kept (default 3)")
    bench.set_defaults(func=_bench)
    fuzz = sub.add_parser("fuzz", help="a campaign: search generated scenes for failures until a budget, grouped by cause",
                          description="Search generated scenes for failures (on a local Dask cluster, or --scheduler), group "
                                      "them by signature, shrink one repro per signature. Rerun with the same --state to "
                                      "continue; exit 1 when the campaign holds findings.")
    fuzz.add_argument("--rasterizer", metavar="SPEC", help="built-in name, module:attr or file.py:attr")
    fuzz.add_argument("--budget", type=_budget, metavar="BUDGET", help=_BUDGET_HELP)
    fuzz.add_argument("--families", type=_families, metavar="A,B", help="fuzz families (default all the rasterizer takes)")
    fuzz.add_argument("--seed", type=_non_negative_int, default=0)
    fuzz.add_argument("--state", type=_path, default=str(Path("reports") / "campaign"), metavar="DIR",
                      help="the campaign's state folder (default reports/campaign): rerun to continue")
    fuzz.add_argument("--scheduler", type=_scheduler, metavar="ADDRESS",
                      help="a Dask scheduler (tcp://host:8786); default a local cluster")
    fuzz.add_argument("--scheduler-timeout", type=_positive_seconds, default=10.0, metavar="S",
                      help="seconds the connection to --scheduler may take (default 10)")
    fuzz.add_argument("--workers", type=_positive_int, metavar="N", help="local worker processes (default one per core)")
    fuzz.add_argument("--batch", type=_positive_int, metavar="N", help="scenes per batch (default about a second of work)")
    fuzz.add_argument("--check", action="append", metavar="NAME", help="only this check (repeatable)")
    fuzz.add_argument("--timeout", type=_positive_seconds, default=60.0, help=_TIMEOUT_HELP)
    fuzz.add_argument("--json", type=_path, metavar="FILE", help="also write the campaign as JSON")
    fuzz.add_argument("--out", type=_path, default="reports", help="folder for campaign.html (default reports/)")
    fuzz.add_argument("--merge", nargs="+", metavar="DIR", help="merge these campaigns' state folders into --state")
    fuzz.set_defaults(func=_fuzz)
    dif = sub.add_parser("diff", help="what changed between two runs' --json files (regressions, fixes, new, removed, metrics)")
    dif.add_argument("before", metavar="A.json")
    dif.add_argument("after", metavar="B.json")
    dif.add_argument("--out", type=_path, default="reports", help="folder for diff.html (default reports/)")
    dif.set_defaults(func=_diff)
    add_atlas_parser(sub, _positive_int, _positive_seconds, _path)
    lst = sub.add_parser("list", help="rasterizers with their conventions, suites, checks")
    lst.set_defaults(func=_list)
    return parser


def main(argv: list[str] | None = None) -> int:
    if "" not in sys.path and os.getcwd() not in sys.path:
        sys.path.insert(0, os.getcwd())  # as `python -m` does: module:attr specs of the project at hand
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except UsageError as exc:
        print(f"rastercheck: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

