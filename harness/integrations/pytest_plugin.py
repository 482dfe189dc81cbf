"""The pytest plugin: ``pytest --rasterizer SPEC`` runs the suite as pytest items, one per
rasterizer, case and check, with readable failure messages and minimal repro paths.

Registered through the ``pytest11`` entry point; inert unless ``--rasterizer`` is given.
With ``--rasterizer`` and no path on the command line, only the rastercheck items are
collected (not the project's own tests from ``testpaths`` or the current directory, which
cost seconds to import and collect before one case runs); name paths to collect them too:
``pytest tests --rasterizer X``.

Collection builds the items from the case list and the check registry alone and calls no
rasterizer: the work happens when an item runs, so ``-k`` and ``--deselect`` skip what
they leave out. The tree is ``rastercheck / <rasterizer> / <case id> / <check>``::

    rastercheck::centre_scanline::lattice/bits-0::conformance

The first item of a case runs it (the case's selected checks, one
:func:`harness.engine.runner.run_session` call); the other items of the case read its results.
Each rasterizer runs in one worker process for the whole pytest session (a
:class:`harness.engine.session.Session`, started for its first case and closed when pytest ends),
not one per case; a call cut off by its time limit leaves a fresh worker for the next.
A rasterizer that declares no convention is identified once, when its first item is set
up (so the time shows as that item's setup). With ``--rastercheck-baseline FILE``, the
baseline's known failures are expected to fail (xfail, not strict).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from harness.checks import Result
from harness.contract.case import Case, MotionCase
from harness.contract.protocol import Rasterizer

if TYPE_CHECKING:
    from harness.engine.session import Session

__all__ = ["pytest_addoption", "pytest_ignore_collect", "pytest_report_header", "pytest_collection_modifyitems",
           "pytest_collection_finish", "pytest_terminal_summary", "RastercheckFailure", "RastercheckItem"]

ROOT = "rastercheck"
BAD = ("fail", "error")
SHRINK_SECONDS = 120.0  # for minimal repros, per rasterizer and session: what `rastercheck run` allows


def pytest_addoption(parser: Any) -> None:
    group = parser.getgroup("rastercheck")
    group.addoption("--rasterizer", action="append", default=[], metavar="SPEC",
                    help="run the rastercheck suite on this rasterizer (repeatable): one item per rasterizer, case and "
                         "check, node ids rastercheck::<rasterizer>::<case>::<check>; select with -k")
    group.addoption("--rastercheck-suite", default="quick", help="quick or full")
    group.addoption("--rastercheck-seed", type=int, default=0)
    group.addoption("--rastercheck-timeout", type=_seconds, default=60.0, metavar="S",
                    help="the most seconds one rasterize call (and the plugin's import) may take, as `rastercheck run "
                         "--timeout` (default 60)")
    group.addoption("--rastercheck-repros", default="reports/pytest-repros",
                    help="directory for minimal repros of failures")
    group.addoption("--rastercheck-baseline", default=None, metavar="FILE",
                    help="a baseline of `rastercheck gate` (--update-baseline): its known failures (status fail or "
                         "error) are xfail with the baseline's reason; one that passes now is XPASS, which does not fail "
                         "the run (strict=False whatever xfail_strict says). Metrics are not compared: `rastercheck "
                         "gate` does that")


def _seconds(text: str) -> float:
    """``--rastercheck-timeout``: as ``rastercheck run --timeout`` reads it."""
    from harness.cli.main import _positive_seconds

    return _positive_seconds(text)


def _suite_only(config: pytest.Config) -> bool:
    """``--rasterizer`` given and no path named: the rastercheck items alone."""
    return bool(config.getoption("--rasterizer")) and config.args_source != pytest.Config.ArgsSource.ARGS


def pytest_ignore_collect(collection_path: Path, config: pytest.Config) -> bool | None:
    return True if _suite_only(config) else None


def pytest_report_header(config: pytest.Config) -> str | None:
    if _suite_only(config):
        return "rastercheck: the suite's items only (name paths to collect your tests too: pytest tests --rasterizer ...)"
    return None


class RastercheckFailure(Exception):
    """A failing rastercheck result (its text is the item's failure message)."""


@dataclass(frozen=True)
class _Given:
    """A ``--rasterizer SPEC`` as loaded: its distinct name and cases, or why it cannot run."""

    spec: str
    name: str
    rasterizer: Rasterizer | None
    cases: list[Case | MotionCase]
    unavailable: str = ""


_IDENTIFIED = pytest.StashKey[list[str]]()  # lines for the terminal summary


class _Root(pytest.Collector):
    """``rastercheck``: the rasterizers given with ``--rasterizer``."""

    def __init__(self, *, given: list[_Given], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.given = given

    def collect(self) -> list[pytest.Item | pytest.Collector]:
        return [_Rasterizer.from_parent(self, name=g.name, given=g) for g in self.given]


class _Rasterizer(pytest.Collector):
    """One rasterizer: its cases. Identified (when it declares no convention) at its first
    setup, once per session."""

    def __init__(self, *, given: _Given, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.given = given
        self.ready: Rasterizer | None = None  # after identification
        self.identified: dict[str, Any] | None = None
        self.shrink_seconds = SHRINK_SECONDS
        # scene kind -> the case whose answer contradicted the declaration (harness.contract.declarations):
        # said once there, and no more scenes of the kind are handed to it
        self.refused: dict[str, str] = {}
        self._rastercheck_session: Session | None = None

    def collect(self) -> list[pytest.Item | pytest.Collector]:
        if self.given.rasterizer is None:
            pytest.skip(f"{self.given.spec}: {self.given.unavailable}")
        from harness.contract.protocol import takes

        # only the scenes it takes (the runner would hand it no other)
        return [_Case.from_parent(self, name=case.id, case=case) for case in self.given.cases
                if isinstance(case, MotionCase) or takes(self.given.rasterizer, case.scene)]

    def setup(self) -> None:
        if self.ready is not None:
            return
        assert self.given.rasterizer is not None
        rasterizer = self.given.rasterizer
        if rasterizer.convention is not None:
            self.ready = rasterizer
            return
        from harness.identify.fingerprint import identify_all

        wrapped, fingerprints = identify_all([rasterizer], self.config.getoption("--rastercheck-seed"))
        self.ready = wrapped[0]
        found = self.identified = fingerprints.get(rasterizer.name, {})
        if "error" in found:
            line = f"{self.name}: identification failed, so it ran without a convention ({found['error']})"
        else:
            guess = "" if found.get("exact") else f" (a best guess: residual {found.get('residual')} px)"
            line = f"{self.name}: checked against the convention identified for it: {found.get('convention')}{guess}"
        self.config.stash.setdefault(_IDENTIFIED, []).append(line)

    def open_session(self) -> Session:
        """The rasterizer's :class:`harness.engine.session.Session` (its worker process), started
        for its first case and kept for the others: one per rasterizer and pytest session,
        closed when pytest ends. A call cut off by its time limit, or a worker that died,
        leaves a fresh worker for the next case (:class:`harness.engine.isolation.Worker` replaces
        itself). (Not ``session``: a node's ``session`` is pytest's.)"""
        if self._rastercheck_session is None:
            from harness.engine.runner import declared
            from harness.engine.session import Session

            assert self.ready is not None
            self._rastercheck_session = Session(declared(self.ready), self.config.getoption("--rastercheck-timeout"))
            self.config.add_cleanup(self._close_session)
        return self._rastercheck_session

    def _close_session(self) -> None:
        if self._rastercheck_session is not None:
            self._rastercheck_session.close()
            self._rastercheck_session = None


class _Case(pytest.Collector):
    """One case of one rasterizer: an item per applicable check. The case runs once, for
    the first of its items that runs, with the checks of its selected items; its results
    are dropped at teardown."""

    def __init__(self, *, case: Case | MotionCase, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.case = case
        self.selected: set[str] = set()  # names of this case's items left after -k and --deselect
        self.results: list[Result] | None = None

    def collect(self) -> list[pytest.Item | pytest.Collector]:
        from harness.checks import checks

        # the checks of the declared coverage kind (an undeclared rasterizer is taken as
        # single-sample until identify says otherwise; a check then skips, saying why)
        rasterizer = self.parent.given.rasterizer if isinstance(self.parent, _Rasterizer) else None
        convention = getattr(rasterizer, "convention", None)
        kind = convention.coverage_kind if convention is not None else "single"
        return [RastercheckItem.from_parent(self, name=check.name) for check in checks(self.case, coverage_kind=kind)]

    def result(self, check: str) -> Result:
        """The result of ``check``, running the case first unless a sibling did."""
        owner = self.parent
        assert isinstance(owner, _Rasterizer) and owner.ready is not None
        kind = self.case.frames[0].kind if isinstance(self.case, MotionCase) and self.case.frames else getattr(
            getattr(self.case, "scene", None), "kind", "")
        if self.results is None and kind in owner.refused:
            self.results = [Result(owner.ready.name, self.case.id, "run", "skip",
                                   f"not handed to it: its answer on {owner.refused[kind]} contradicted its declaration")]
        if self.results is None:
            from harness.engine.runner import run_session

            start = time.monotonic()
            results = run_session(owner.open_session(), [self.case], only=self.selected | {check},
                                  repro_seconds=max(0.0, owner.shrink_seconds))
            if any(r.status == "fail" for r in results):  # it shrank: the run counts against the budget
                owner.shrink_seconds -= time.monotonic() - start
            self.results = [replace(r, drawing=None) for r in results]  # no pictures here: keep no coverages
            for r in results:
                if r.status == "error" and "refused" in r.evidence:
                    owner.refused[str(r.evidence["refused"])] = self.case.id
        for r in self.results:
            if r.check == check:
                return r
        for r in self.results:
            if r.check == "run":  # the rasterizer failed on the case: that is every check's verdict
                return r
        given = "; ".join(f"{r.check} {r.status}: {r.message}" for r in self.results) or "no result"
        return Result(owner.ready.name, self.case.id, check, "skip", f"no {check} verdict on this case ({given})")

    def teardown(self) -> None:
        self.results = None


class RastercheckItem(pytest.Item):
    """One check of one rasterizer on one case."""

    def runtest(self) -> None:
        case = self.parent
        assert isinstance(case, _Case)
        r = case.result(self.name)
        if r.status == "skip":
            pytest.skip(f"{r.rasterizer} {r.case} [{r.check}]: {r.message}{_identify_note(case)}")
        if r.status in BAD:
            from harness.integrations.testing import format_failures

            owner = case.parent
            assert isinstance(owner, _Rasterizer)
            text = format_failures([r], Path(self.config.getoption("--rastercheck-repros")), spec=owner.given.spec)
            traceback = r.evidence.get("traceback")
            if r.status == "error" and traceback:
                text += "\n\nthe rasterizer's traceback:\n" + str(traceback).rstrip()
            note = _identify_note(case)
            raise RastercheckFailure(text + (f"\n{note.strip()}" if note else ""))

    def repr_failure(self, excinfo: Any, style: Any = None) -> str:
        if isinstance(excinfo.value, RastercheckFailure):
            return str(excinfo.value)
        return str(super().repr_failure(excinfo))

    def reportinfo(self) -> tuple[Path, int, str]:
        # the headline of a failure; not the node id, which pytest -v would mangle (it reads
        # a trailing domain as dotted: rotate-0.05deg would show as rotate-0::05deg)
        case = self.parent
        assert isinstance(case, _Case) and case.parent is not None
        return self.session.path / ROOT, 0, f"{case.parent.name} {case.name} [{self.name}]"


def _identify_note(case: _Case) -> str:
    owner = case.parent
    assert isinstance(owner, _Rasterizer)
    found = owner.identified
    if found and "error" in found:
        return f" (identifying its convention failed, so it ran without one: {found['error']})"
    return ""


def _key(rasterizer: str, case: str, check: str) -> str:
    from harness.results.gate import key

    return key(Result(rasterizer, case, check, "pass", ""))


def _known_failure(baseline: dict[str, dict[str, Any]], item: RastercheckItem) -> str | None:
    """The baseline's reason when the item's check (or the case's whole run) is a known
    failure; None otherwise."""
    case = item.parent
    assert isinstance(case, _Case) and case.parent is not None
    rasterizer = case.parent.name
    for check in (item.name, "run"):
        entry = baseline.get(_key(rasterizer, case.name, check))
        if entry is not None and entry.get("status") in BAD:
            reason = entry.get("reason") or f"a known {entry.get('status')} of the baseline"
            return reason if check == item.name else f"the case's run: {reason}"
    return None


def _given(config: pytest.Config) -> list[_Given]:
    from cases.suites import suite
    from harness.engine.registry import Unavailable, distinct_names, load

    try:
        cases = suite(config.getoption("--rastercheck-suite"), config.getoption("--rastercheck-seed"))
    except ValueError as exc:
        raise pytest.UsageError(f"--rastercheck-suite: {exc}") from None
    loaded: list[tuple[str, Rasterizer | str]] = []
    for text in config.getoption("--rasterizer"):
        try:
            loaded.append((text, load(text, import_timeout=config.getoption("--rastercheck-timeout"))))
        except Unavailable as exc:  # a missing library: its items are skipped with the install hint
            loaded.append((text, str(exc)))
        except ValueError as exc:
            raise pytest.UsageError(str(exc)) from None
    present = distinct_names([r for _, r in loaded if not isinstance(r, str)])
    given = []
    for text, r in loaded:
        if isinstance(r, str):
            given.append(_Given(text, text, None, [], unavailable=r))
        else:
            ready = present.pop(0)
            given.append(_Given(text, ready.name, ready, cases))
    return given


@pytest.hookimpl(tryfirst=True)  # before -k and --deselect, which then leave out the items' work
def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list[pytest.Item]) -> None:
    if not config.getoption("--rasterizer"):
        return
    baseline: dict[str, dict[str, Any]] = {}
    path = config.getoption("--rastercheck-baseline")
    if path is not None:
        from harness.results.gate import load_baseline

        try:
            baseline = load_baseline(path)
        except ValueError as exc:
            raise pytest.UsageError(f"--rastercheck-baseline: {exc}") from None
    root = _Root.from_parent(session, name=ROOT, nodeid=ROOT, given=_given(config))
    for item in session.genitems(root):
        if baseline and isinstance(item, RastercheckItem):
            reason = _known_failure(baseline, item)
            if reason is not None:
                item.add_marker(pytest.mark.xfail(reason=reason, raises=RastercheckFailure, strict=False))
        items.append(item)


def pytest_collection_finish(session: pytest.Session) -> None:
    """Tell each case which of its items are left to run (after -k and --deselect)."""
    for item in session.items:
        if isinstance(item, RastercheckItem) and isinstance(item.parent, _Case):
            item.parent.selected.add(item.name)


def pytest_terminal_summary(terminalreporter: Any, exitstatus: int, config: pytest.Config) -> None:
    """The convention each undeclared rasterizer was checked against."""
    lines = config.stash.get(_IDENTIFIED, [])
    if lines:
        terminalreporter.write_sep("-", "rastercheck: identified conventions")
        for line in lines:
            terminalreporter.write_line(line)
