"""``rastercheck bench``: the throughput table against Pillow (or ``--campaign``: a campaign's
speed-up from one worker to two), from the measuring of :mod:`harness.cli.bench` (and :mod:`harness.cli.bench_campaign`).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from harness.cli.common import UsageError, _load_all

_BENCH_KINDS = ("triangles", "paths", "lines", "strokes", "identify")
# the workload kinds measured when --kinds is not given (identify only when asked: it
# identifies every built-in mode in fresh processes, a minute or two)
_DEFAULT_KINDS = ("triangles", "paths", "lines", "strokes")


def _bench_kinds(text: str) -> tuple[str, ...]:
    """``bench --kinds``: comma-separated workload kinds, each of triangles, paths, lines, strokes, identify."""
    kinds = tuple(dict.fromkeys(k.strip() for k in text.split(",") if k.strip()))
    unknown = [k for k in kinds if k not in _BENCH_KINDS]
    if unknown or not kinds:
        raise argparse.ArgumentTypeError(f"{text!r}: give workload kinds among {', '.join(_BENCH_KINDS)}")
    return kinds


def _bench_json(text: str | None) -> None:
    """``bench --json``: a file that can be written in a folder that exists, checked before
    any work; UsageError in one line naming it otherwise (a bench takes minutes: no
    traceback at its end, no folder made on a typo)."""
    from harness.results.files import prepare_file

    if not text:
        return
    path = Path(text)
    folder = path.parent if str(path.parent) else Path(".")
    if not path.is_dir() and not folder.is_dir():
        raise UsageError(f"--json {path}: its folder {folder} "
                         f"{'is a file' if folder.exists() else 'does not exist'}")
    try:
        prepare_file(path, "--json")
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def _bench(args: argparse.Namespace) -> int:
    """``bench``: the table of every contender on every workload, each measured in a
    process of its own within ``--timeout`` per call. Exit 0 when every row was measured,
    1 when a contender failed on a workload (each named with its fault, one line each)."""
    from harness.cli.bench import failures_by_contender, format_table, missing_peers, run_bench, workloads, write_json

    if args.kinds is not None and args.campaign:
        raise UsageError("--kinds chooses the workloads of bench, not of --campaign")
    _bench_json(args.json)
    if args.campaign:
        return _bench_campaign(args)
    if args.scenes is not None or args.repeats is not None:
        raise UsageError("--scenes and --repeats are for bench --campaign: give --campaign too")
    names = args.rasterizer
    if names:
        _load_all(names)  # fail early, with a usage error, on a bad spec
    started = time.perf_counter()
    kinds = args.kinds or _DEFAULT_KINDS
    if kinds == ("identify",):
        return _bench_identify(args, started)
    results = run_bench(names, scale=args.scale, budget=args.budget, timeout=args.timeout, triangles="triangles" in kinds,
                        paths="paths" in kinds, lines="lines" in kinds, strokes="strokes" in kinds,
                        progress=lambda line: print(f"[{time.perf_counter() - started:5.0f} s] {line}", file=sys.stderr,
                                                    flush=True))
    print(format_table(results, {w.name: w.description for w in workloads(args.scale)}))
    not_measured = missing_peers()
    for label, why in not_measured.items():  # a library that is not installed costs only its own rows, and says so
        print(f"not measured: {label}: {why}")
    failed = failures_by_contender(results)
    for label, why in failed.items():  # a contender that failed costs only its own rows, and says so
        print(f"failed: {label}: {why}")
    summary = None
    if "identify" in kinds:  # identify's seconds per built-in mode, in the same JSON
        identified, summary = _identify_rows(args, started)
        results += identified
        failed |= {f"identify {m.contender}": m.fault for m in identified if m.fault}
    if args.json:
        write_json(results, Path(args.json), summary=summary, not_measured=not_measured)
        print(f"json: {args.json}")
    return 1 if failed else 0


def _identify_rows(args: argparse.Namespace, started: float) -> tuple[list[Any], dict[str, Any]]:
    """``bench --kinds identify``'s measurements, its table printed: (rows, summary)."""
    from harness.cli.bench_identify import format_identify_table, identify_summary, run_identify_bench

    results = run_identify_bench(args.rasterizer or None, repeats=1 if args.budget == 0 else 2, cold=args.budget > 0,
                                 timeout=args.timeout,
                                 progress=lambda line: print(f"[{time.perf_counter() - started:5.0f} s] {line}",
                                                             file=sys.stderr, flush=True))
    print(format_identify_table(results))
    return results, {"identify": identify_summary(results)}


def _bench_identify(args: argparse.Namespace, started: float) -> int:
    """``bench --kinds identify`` alone: the table and JSON of identify's seconds per
    built-in mode (``--rasterizer``: those modes); ``--budget 0`` identifies each once and
    skips the cold figure (smoke tests). Exit 1 when a mode could not be measured."""
    from harness.cli.bench import write_json

    results, summary = _identify_rows(args, started)
    for m in results:
        if m.fault:
            print(f"failed: identify {m.contender}: {m.fault}")
    if args.json:
        write_json(results, Path(args.json), summary=summary)
        print(f"json: {args.json}")
    return 1 if any(m.fault for m in results) else 0


def _bench_campaign(args: argparse.Namespace) -> int:
    """``bench --campaign``: the same fixed scene budget on one local worker, then two;
    checked primitives per second per worker and the speed-up, as a table and JSON. Exit 1
    when the rasterizer's calls failed (every call of the warm-up: nothing measured; some
    in the campaigns: no speed-up judged)."""
    from harness.cli.bench import write_json
    from harness.cli.bench_campaign import (
        CAMPAIGN_REFERENCE,
        CAMPAIGN_REPEATS,
        CAMPAIGN_SCENES,
        NothingMeasured,
        campaign_summary,
        format_campaign_table,
        run_campaign_bench,
    )

    if args.rasterizer and len(args.rasterizer) > 1:
        raise UsageError("bench --campaign measures one rasterizer: give --rasterizer once")
    spec = args.rasterizer[0] if args.rasterizer else CAMPAIGN_REFERENCE
    _load_all([spec])  # fail early, with a usage error, on a bad spec
    started = time.perf_counter()
    try:
        results = run_campaign_bench(spec, scenes=args.scenes or CAMPAIGN_SCENES, repeats=args.repeats or CAMPAIGN_REPEATS,
                                     timeout=args.timeout,
                                     progress=lambda line: print(f"[{time.perf_counter() - started:5.0f} s] {line}",
                                                                                        file=sys.stderr, flush=True))
    except NothingMeasured as exc:
        print(f"rastercheck: bench --campaign: {exc}", file=sys.stderr)
        return 1
    print(format_campaign_table(results))
    summary = campaign_summary(results)
    if args.json:
        write_json(results, Path(args.json), summary=summary)
        print(f"json: {args.json}")
    if "not_judged" in summary or any(m.failed_calls for m in results):
        print(f"rastercheck: bench --campaign: {spec}: rasterize calls failed in the campaigns: no speed-up judged",
              file=sys.stderr)
        return 1
    return 0
