"""The pytest plugin: ``pytest --rasterizer SPEC`` runs the suite as pytest items, one per
rasterizer, case and check, with readable failure messages and minimal repro paths.

Registered through the ``pytest11`` entry point; inert unless ``--rasterizer`` is given.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from harness.checks import Result

__all__ = ["pytest_addoption", "pytest_collection_modifyitems"]


def pytest_addoption(parser: Any) -> None:
    group = parser.getgroup("rastercheck")
    group.addoption("--rasterizer", action="append", default=[], metavar="SPEC",
                    help="run the rastercheck suite on this rasterizer (repeatable)")
    group.addoption("--rastercheck-suite", default="quick", help="quick or full")
    group.addoption("--rastercheck-seed", type=int, default=0)
    group.addoption("--rastercheck-repros", default="reports/pytest-repros",
                    help="directory for minimal repros of failures")


class RastercheckFailure(Exception):
    """A failing rastercheck result."""


class RastercheckItem(pytest.Item):
    def __init__(self, *, result: Result, repro_dir: Path, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.result = result
        self.repro_dir = repro_dir

    def runtest(self) -> None:
        r = self.result
        if r.status == "skip":
            pytest.skip(r.message)
        if r.status in ("fail", "error"):
            from harness.testing import format_failures

            raise RastercheckFailure(format_failures([r], self.repro_dir))

    def repr_failure(self, excinfo: Any, style: Any = None) -> str:
        if isinstance(excinfo.value, RastercheckFailure):
            return str(excinfo.value)
        return str(super().repr_failure(excinfo))

    def reportinfo(self) -> tuple[str, int, str]:
        return "rastercheck", 0, self.name


def pytest_collection_modifyitems(session: Any, config: Any, items: list[Any]) -> None:
    specs = config.getoption("--rasterizer")
    if not specs:
        return
    from harness.registry import load
    from harness.runner import run_suite

    repro_dir = Path(config.getoption("--rastercheck-repros"))
    for spec in specs:
        try:
            rasterizer = load(spec)
        except ValueError as exc:
            raise pytest.UsageError(str(exc)) from None
        results = run_suite([rasterizer], suite=config.getoption("--rastercheck-suite"),
                            seed=config.getoption("--rastercheck-seed"))
        for r in results:
            name = f"{r.rasterizer}::{r.case}::{r.check}"
            items.append(RastercheckItem.from_parent(session, name=name, result=r, repro_dir=repro_dir))
