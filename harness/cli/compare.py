"""``rastercheck compare``: pixel differences between rasterizers, and the convention that
separates them.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from harness.cli.common import UsageError, _load_all
from harness.cli.run import _refuse_same_names


def _compare(args: argparse.Namespace) -> int:
    from harness.diagnose.compare import CANDIDATES, as_dict, compare
    from harness.report.pages import write_comparison
    from harness.results.files import atomic_write_text, prepare_file, prepare_folder

    if len(args.specs) < 2:
        raise UsageError("compare needs at least two rasterizers")
    try:  # the outputs, before any work (--out a file, --json a folder were tracebacks after it)
        prepare_folder(args.out, "--out")
        if args.json:
            prepare_file(args.json, "--json")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    rasterizers, _ = _load_all(args.specs, args.timeout)
    if len(rasterizers) < len(args.specs):
        raise UsageError(f"compare: {len(args.specs) - len(rasterizers)} of the rasterizers could not be loaded (see above): "
                         "nothing to compare them with")
    _refuse_same_names(rasterizers)
    explanations, comparisons = compare(rasterizers, seed=args.seed, timeout=args.timeout)
    silent = []
    for e in explanations:
        if not e.answered:  # no fit, no ranking: nothing of it was seen
            silent.append(f"{e.rasterizer}: no answers: {e.silence}")
            print(f"{e.rasterizer:<22} no answers, not ranked: {e.silence}")
            continue
        verdict = ("exactly" if e.exact else
                   f"best guess only because calls failed: {e.unanswered} of {e.scenes} fit scenes unanswered, "
                   f"{e.mismatches} mismatching pixels of {e.pixels} over the rest" if e.unanswered else
                   f"best, with {e.mismatches} mismatching pixels of {e.pixels}")
        print(f"{e.rasterizer:<22} {e.convention.describe()} ({verdict})")
    for c in comparisons:
        print(f"{c.a} vs {c.b}: {c.differing_pixels} pixels differ; {c.separation}")
    data = as_dict(explanations, comparisons)
    path = write_comparison(Path(args.out), data, max((e.candidates for e in explanations), default=len(CANDIDATES)), args.seed,
                            comparisons)
    if args.json:
        atomic_write_text(Path(args.json), json.dumps({"schema": 1, **data}, indent=1))
    print(f"report: {path}")
    for line in silent:
        print(f"rastercheck: compare {line}", file=sys.stderr)
    return 1 if silent else 0
