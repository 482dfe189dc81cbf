"""``rastercheck list``: the rasterizers with their conventions, suites and checks.
"""

from __future__ import annotations

import argparse

from harness.cli.common import _load_all


def _list(args: argparse.Namespace) -> int:
    from cases.suites import SUITES, suite
    from harness.checks import check_names

    rasterizers, problems = _load_all(None)
    print("rasterizers:")
    for r in rasterizers:
        print(f"  {r.name:<20} {r.convention.describe() if r.convention else 'declares no convention'}")
    for problem in problems:
        print(f"  skipped plugin: {problem}")
    print("suites:")
    for name in SUITES:
        print(f"  {name:<20} {len(suite(name))} cases")
    print("checks:")
    print("  " + ", ".join(check_names()))
    return 0
