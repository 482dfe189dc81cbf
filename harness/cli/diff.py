"""``rastercheck diff``: what changed between two runs' ``--json`` files.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from harness.cli.common import UsageError


def _diff(args: argparse.Namespace) -> int:
    """Print what changed between two runs and write diff.html; exit 1 on regressions."""
    from harness.results.diff import diff_runs, load_run, write_diff_page
    from harness.results.files import prepare_folder

    try:
        prepare_folder(args.out, "--out")
        before, after = load_run(args.before), load_run(args.after)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    diff = diff_runs(before, after, Path(args.before).name, Path(args.after).name)
    for line in diff.lines():
        print(line)
    print(f"report: {write_diff_page(args.out, diff)}")
    return 1 if diff.of("regression") else 0
