"""The ``rastercheck`` command: run, bench, list."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from pathlib import Path

__all__ = ["main"]


class UsageError(Exception):
    """A usage or configuration problem: exit 2 with one line, no traceback."""


def _load_all(specs: list[str] | None):  # type: ignore[no-untyped-def]
    from harness.registry import available, load

    names = specs or available()
    loaded, problems = [], []
    for spec in names:
        try:
            loaded.append(load(spec))
        except ValueError as exc:
            if specs:  # the user named it: a configuration error
                raise UsageError(str(exc)) from None
            problems.append(str(exc))  # a broken plugin is reported and skipped
    return loaded, problems


def _run(args: argparse.Namespace) -> int:
    import time

    from harness.files import atomic_write_text
    from harness.report import write_report
    from harness.runner import run_suite

    rasterizers, problems = _load_all(args.rasterizer)
    for problem in problems:
        print(f"skipped: {problem}", file=sys.stderr)
    start = time.perf_counter()
    results = []
    for r in rasterizers:
        mine = run_suite([r], suite=args.suite, seed=args.seed, timeout=args.timeout)
        results.extend(mine)
        bad = [x for x in mine if x.status in ("fail", "error")]
        print(f"{r.name:<20} {len(mine) - len(bad)}/{len(mine)} results pass or skip" + (f", {len(bad)} failing" if bad else ""))
    seconds = time.perf_counter() - start
    written = _write_repros(Path(args.out), results)
    if written:
        print(f"repros: {written} minimal failing cases in {Path(args.out) / 'repros'}")
    conventions = {r.name: (r.convention.describe() if r.convention else "none declared") for r in rasterizers}
    path = write_report(Path(args.out), conventions, results, args.seed, args.suite, seconds)
    print(f"report: {path}")
    if args.json:
        payload = {"schema": 1, "suite": args.suite, "seed": args.seed, "results": [asdict(x) for x in results]}
        atomic_write_text(Path(args.json), json.dumps(payload, indent=2, default=str))
    return 1 if any(x.status in ("fail", "error") for x in results) else 0


def _write_repros(out: Path, results: list) -> int:  # type: ignore[type-arg]
    """Save each attached minimal repro as reports/repros/<rasterizer>/<case>--<check>.json."""
    from harness.files import atomic_write_text

    count = 0
    for r in results:
        payload = r.evidence.get("repro")
        if payload is None:
            continue
        name = f"{r.case.replace('/', '_')}--{r.check}.json"
        path = out / "repros" / r.rasterizer / name
        atomic_write_text(path, json.dumps(payload, indent=1))
        r.evidence["repro_path"] = str(path.relative_to(out))
        count += 1
    return count


def _replay(args: argparse.Namespace) -> int:
    from harness.repro import load_case
    from harness.runner import run_suite

    try:
        case = load_case(args.case)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    rasterizers, _ = _load_all([args.rasterizer])
    results = run_suite(rasterizers, cases=[case], timeout=args.timeout, repros=False)
    for r in results:
        print(f"{r.status:<6} {r.check:<12} {r.message}")
    return 1 if any(r.status in ("fail", "error") for r in results) else 0


def _bench(args: argparse.Namespace) -> int:
    from harness.bench import format_table, run_bench, workloads, write_json

    names = args.rasterizer
    if names:
        _load_all(names)  # fail early, with a usage error, on a bad spec
    results = run_bench(names, scale=args.scale, budget=args.budget)
    print(format_table(results, {w.name: w.description for w in workloads(args.scale)}))
    if args.json:
        write_json(results, Path(args.json))
        print(f"json: {args.json}")
    return 0


def _list(args: argparse.Namespace) -> int:
    rasterizers, problems = _load_all(None)
    for r in rasterizers:
        print(f"{r.name:<20} {r.convention.describe() if r.convention else 'declares no convention'}")
    for problem in problems:
        print(f"skipped: {problem}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="rastercheck", description="Rasterization conformance and artifact harness.")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run the conformance suite and write the HTML report")
    run.add_argument("--rasterizer", action="append", metavar="SPEC", help="built-in name, module:attr or file.py:attr (repeatable; default all)")
    run.add_argument("--out", default="reports", help="report directory (default reports/)")
    run.add_argument("--json", metavar="FILE", help="also write results as JSON")
    run.add_argument("--seed", type=int, default=0)
    run.add_argument("--suite", choices=["quick", "full"], default="quick")
    run.add_argument("--timeout", type=float, default=60.0, help="seconds one rasterize call may take")
    run.set_defaults(func=_run)
    bench = sub.add_parser("bench", help="throughput against Pillow, as ratios measured in one run")
    bench.add_argument("--rasterizer", action="append", metavar="SPEC")
    bench.add_argument("--json", metavar="FILE", help="write the measurements as JSON")
    bench.add_argument("--scale", type=float, default=1.0, help="shrink the workloads (smoke tests)")
    bench.add_argument("--budget", type=float, default=1.0, help="seconds of repeats per contender")
    bench.set_defaults(func=_bench)
    rep = sub.add_parser("replay", help="run the checks of a saved case (a minimal repro) on a rasterizer")
    rep.add_argument("case", help="a case JSON file, as written under reports/repros/")
    rep.add_argument("--rasterizer", required=True, metavar="SPEC")
    rep.add_argument("--timeout", type=float, default=60.0)
    rep.set_defaults(func=_replay)
    lst = sub.add_parser("list", help="registered rasterizers and their conventions")
    lst.set_defaults(func=_list)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except UsageError as exc:
        print(f"rastercheck: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
