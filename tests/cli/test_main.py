"""``harness.cli.main``: the parser and dispatch only; each command's handler in a module of its own."""

from __future__ import annotations

import argparse

from harness.cli.main import build_parser

# command -> the module holding its handler
HOMES = {"run": "run", "gate": "gate", "compare": "compare", "identify": "identify", "replay": "replay",
         "bench": "bench_command", "fuzz": "fuzz", "diff": "diff", "list": "listing", "atlas": "atlas"}


def test_each_command_is_handled_by_its_own_module() -> None:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert set(sub.choices) == set(HOMES)
    for command, home in HOMES.items():
        handler = sub.choices[command].get_default("func")
        assert handler.__module__ == f"harness.cli.{home}", (command, handler.__module__)
