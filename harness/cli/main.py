"""The ``rastercheck`` command: run, gate, compare, identify, replay, bench, fuzz, list.

Exit codes: 0 everything passes, 1 a check fails or errors (for ``gate``: a regression),
2 a usage or configuration error, reported in one line without a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, TimeoutError
from pathlib import Path
from typing import Any, NamedTuple

__all__ = ["main"]


class UsageError(Exception):
    """A usage or configuration problem: exit 2 with one line, no traceback."""


# what the last _load_all loaded (the spec of each rasterizer, in load order) and skipped
# (spec -> why), for the report: its replay commands quote the spec, its index lists the skipped
_loaded_specs: list[str] = []
_skipped: dict[str, str] = {}
# what the last _execute selected: the cases (after --case and --shard) and the registered
# plugins that failed to load (each a usage error once the others' results are written)
_selected: list[Any] = []
_broken: list[str] = []


def _load_all(specs: list[str] | None, timeout: float = 120.0) -> tuple[list[Any], list[str]]:
    """The rasterizers of ``specs`` (default every registered one), each given ``timeout``
    seconds to import and build, and the problems of those that could not be loaded."""
    from harness.engine.registry import Unavailable, available, load

    names = specs or available()
    loaded, problems = [], []
    _loaded_specs.clear()
    _skipped.clear()
    for spec in names:
        try:
            loaded.append(load(spec, import_timeout=timeout))
            _loaded_specs.append(spec)
        except Unavailable as exc:  # a missing library: skipped with its install hint, never fatal
            print(f"skipped {spec}: {exc}", file=sys.stderr)
            _skipped[spec] = str(exc)
        except ValueError as exc:
            if specs:  # the user named it: a configuration error
                raise UsageError(str(exc)) from None
            problems.append(str(exc))  # a broken plugin is reported and skipped
            _skipped[spec] = f"broken plugin: {exc}"
    return loaded, problems


def _quiet() -> bool:
    return bool(os.environ.get("CI")) or not sys.stderr.isatty()


def _prepare_outputs(args: argparse.Namespace) -> None:
    """Every output path checked (and its folder created) before any work starts: a
    mistyped path costs a one-line error now, not a traceback after the whole suite."""
    from harness.results.files import prepare_file, prepare_folder

    try:
        prepare_folder(args.out, "--out")
        for option in ("json", "junit"):
            if getattr(args, option, None):
                prepare_file(getattr(args, option), f"--{option}")
        if getattr(args, "baseline", None) and getattr(args, "update_baseline", False):
            prepare_file(args.baseline, "--baseline")
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def _skip_list(path: str) -> list[tuple[str, str]]:
    """A skip list: one ``GLOB  # reason`` per line (a case id glob, optionally
    ``rasterizer:case-glob``); blank lines and lines starting with # are ignored."""
    from harness.results.files import read_input

    try:
        lines = read_input(path, "the skip list").decode("utf-8").splitlines()
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise UsageError(f"--skip {path}: cannot read it ({exc})") from None
    out = []
    for number, line in enumerate(lines, 1):
        pattern, _, reason = line.partition("#")
        pattern = pattern.strip()
        if not pattern:
            continue
        if len(pattern.split()) != 1:
            raise UsageError(f"--skip {path}, line {number}: one glob per line, then '# reason' ({line.strip()!r})")
        out.append((pattern, reason.strip() or "listed in " + path))
    return out


def _select_cases(args: argparse.Namespace, cases: list[Any]) -> list[Any]:
    """The cases of ``--case`` globs and the ``--shard K/N`` share (every N-th case from
    the K-th, in suite order: the shards partition the run exactly)."""
    import fnmatch

    if getattr(args, "case", None):
        cases = [c for c in cases if any(fnmatch.fnmatchcase(c.id, g) for g in args.case)]
        if not cases:
            raise UsageError(f"--case {' '.join(args.case)}: no case of the suite matches")
    if getattr(args, "shard", None):
        k, n = args.shard
        before = len(cases)
        cases = cases[k - 1::n]
        if not cases:
            raise UsageError(f"--shard {k}/{n}: no case falls in this share of the {before} selected: nothing would be checked")
    return cases


def _refuse_same_names(rasterizers: list[Any]) -> None:
    """Two selected rasterizers of one name: a usage error naming both specs."""
    from harness.engine.registry import same_names

    clash = same_names(rasterizers, _loaded_specs)
    if clash is not None:
        raise UsageError(clash)


def _shard(text: str) -> tuple[int, int]:
    """``K/N`` with 1 <= K <= N."""
    k, _, n = text.partition("/")
    try:
        kk, nn = int(k), int(n)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected K/N (e.g. 2/4), not {text!r}") from None
    if not 1 <= kk <= nn:
        raise argparse.ArgumentTypeError(f"expected K/N with 1 <= K <= N, not {text!r}")
    return kk, nn


class Interrupted(Exception):
    """Ctrl-C during a run: what finished is kept."""

    def __init__(self, rasterizers: list[Any], results: list[Any], seconds: float, fingerprints: dict[str, Any]) -> None:
        super().__init__("interrupted")
        self.partial = (rasterizers, results, seconds, fingerprints)


def _journal_of(args: argparse.Namespace, skips: list[tuple[str, str]]) -> tuple[dict[str, Any], Any]:
    """The run's parameters as its journal's header holds them, and, under ``--resume``,
    what the journal in ``--out`` holds (:class:`harness.results.journal.Recorded`); a usage error
    in one line when there is none, it is malformed, or it is of other parameters."""
    import harness
    from harness.results.journal import journal_path, parameter_difference, read_journal, run_parameters

    parameters = run_parameters(harness.__version__, args.rasterizer, args.suite, args.seed, getattr(args, "case", None),
                                getattr(args, "check", None), getattr(args, "shard", None), skips, getattr(args, "rerun", 0))
    if not getattr(args, "resume", False):
        return parameters, None
    path = journal_path(args.out)
    if not path.exists():
        raise UsageError(f"--resume: there is no run journal {path} to resume (run without --resume)")
    try:
        recorded = read_journal(path)
    except ValueError as exc:
        raise UsageError(f"--resume: {exc}") from None
    difference = parameter_difference(recorded.parameters, parameters)
    if difference is not None:
        raise UsageError(f"--resume: the run journal {path} is of another run: {difference} (run without --resume to start over)")
    return parameters, recorded


def _selected_checks(args: argparse.Namespace) -> set[str] | None:
    """The checks ``--check`` names (``hygiene`` only when named), None for every one;
    UsageError for a name that is no check."""
    from harness.checks import check_names

    if not getattr(args, "check", None):
        return None
    unknown = sorted(set(args.check) - set(check_names()) - {"overdraw"})
    if unknown:
        raise UsageError(f"--check {', '.join(unknown)}: no such check (checks: {', '.join(check_names())})")
    return {*args.check, "hygiene"} if "hygiene" in args.check else set(args.check)


def _loaded_rasterizers(args: argparse.Namespace, loaded: Any) -> list[Any]:
    """The ``--rasterizer`` specs loaded, names made distinct; a plugin that cannot be
    loaded is said on stderr and kept in :data:`_broken` (UsageError when none loads)."""
    from harness.engine.registry import distinct_names

    rasterizers, problems = _load_all(args.rasterizer, getattr(args, "timeout", 120.0))
    if not rasterizers:
        raise UsageError("no rasterizer could be loaded: nothing was checked"
                         + (f" ({'; '.join(problems)})" if problems else ""))
    _refuse_same_names(rasterizers)
    rasterizers = distinct_names(rasterizers)
    _broken[:] = problems
    if loaded is not None:
        loaded(rasterizers)  # e.g. the gate's check that the baseline is of these rasterizers
    for problem in problems:
        print(f"skipped plugin: {problem}", file=sys.stderr)
    return rasterizers


def _run_and_skipped(cases: list[Any], skips: list[tuple[str, str]], name: str) -> tuple[list[Any], list[Any]]:
    """The cases rasterizer ``name`` runs, and a skip result for each one the skip list
    names (a glob of the case id, or of ``name:case id``)."""
    import fnmatch

    from harness.checks import Result

    keep, out = [], []
    for case in cases:
        reason = next((why for glob, why in skips
                       if fnmatch.fnmatchcase(case.id, glob) or fnmatch.fnmatchcase(f"{name}:{case.id}", glob)), None)
        if reason is None:
            keep.append(case)
        else:
            out.append(Result(name, case.id, "run", "skip", f"skipped: {reason}"))
    return keep, out


class _Collected:
    """The results of a run as they come from its threads: kept, journaled (when the run
    keeps a journal), and counted on the progress bar (on a terminal) or in a plain line
    every 30 s (in CI)."""

    def __init__(self, rasterizers: list[Any], cases: list[Any], recorder: Any, start: float) -> None:
        import threading

        self.results: list[Any] = []
        self.lock = threading.Lock()
        self.recorder = recorder
        self.start = start
        self._total = len(cases) * len(rasterizers)
        self._seen: dict[str, set[str]] = {r.name: set() for r in rasterizers}
        self._finished = threading.Event()
        self._progress = None
        if not _quiet():
            from rich.progress import Progress

            self._progress = Progress(transient=True)
            self._progress.start()
        else:
            threading.Thread(target=self._report, daemon=True).start()
        self._tasks = {r.name: self._progress.add_task(r.name, total=len(cases)) if self._progress else None
                       for r in rasterizers}

    def __call__(self, result: Any, journaled: bool = False) -> None:
        """One result: ``journaled`` when it comes from the resumed journal itself."""
        if self.recorder is not None and not journaled:
            self.recorder.result(result)
        with self.lock:
            self.results.append(result)
            seen = self._seen[result.rasterizer]
            if result.case not in seen:
                seen.add(result.case)
                task = self._tasks[result.rasterizer]
                if self._progress is not None and task is not None:
                    self._progress.advance(task)

    def _report(self) -> None:
        while not self._finished.wait(30.0):
            with self.lock:
                done = sum(len(s) for s in self._seen.values())
                failing = sum(x.status in ("fail", "error") for x in self.results)
            print(f"progress: {done}/{self._total} cases, {failing} failing results, "
                  f"{time.perf_counter() - self.start:.0f} s", file=sys.stderr, flush=True)

    def close(self) -> None:
        self._finished.set()
        if self._progress is not None:
            self._progress.stop()
        if self.recorder is not None:
            self.recorder.close()


def _journal_writer(args: argparse.Namespace, parameters: dict[str, Any], recorded: Any,
                    done: set[tuple[str, str]]) -> tuple[Any, Any]:
    """The run journal's writer, and what it carries over from the journal resumed (its
    complete pairs' results), or None for either; UsageError when it cannot be written."""
    from harness.results.journal import JournalWriter, Recorded, journal_path

    kept = Recorded(parameters, [x for x in recorded.results if (x.rasterizer, x.case) in done], done) if recorded else None
    try:
        return JournalWriter(journal_path(args.out), parameters, kept), kept
    except OSError as exc:
        raise UsageError(f"the run journal {journal_path(args.out)} cannot be written ({exc})") from None


def _execute(args: argparse.Namespace, loaded: Any = None,
             journal: bool = False) -> tuple[list[Any], list[Any], float, dict[str, dict[str, Any]]]:
    """Run the selected rasterizers over the suite, side by side with --jobs, showing
    progress (a bar on a terminal, a plain line every 30 s in CI). Ctrl-C raises
    :class:`Interrupted` carrying what finished. Returns (rasterizers, results,
    seconds, fingerprints).

    With ``journal``, each result is appended to ``<out>/run.journal.jsonl`` as it comes
    (:mod:`harness.results.journal`); under ``--resume`` the (rasterizer, case) pairs complete in
    it are not run again, and its results are among those returned."""
    import threading

    from cases.suites import suite
    from harness.engine.isolation import kill_all
    from harness.engine.runner import declared, run_session
    from harness.engine.session import Session
    from harness.identify.fingerprint import identify_all

    _prepare_outputs(args)
    only = _selected_checks(args)
    skips = _skip_list(args.skip) if getattr(args, "skip", None) else []
    try:
        cases = _select_cases(args, suite(args.suite, args.seed))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    parameters, recorded = _journal_of(args, skips) if journal else ({}, None)
    rasterizers = _loaded_rasterizers(args, loaded)
    _selected[:] = cases
    start = time.perf_counter()
    try:
        rasterizers, fingerprints = identify_all(rasterizers, args.seed, everyone=not getattr(args, "no_fingerprints", False),
                                                 call_timeout=args.timeout, report=lambda line: print(line, file=sys.stderr))
    except KeyboardInterrupt:
        kill_all()
        raise Interrupted(rasterizers, [], time.perf_counter() - start, {}) from None
    budget = getattr(args, "max_seconds", None)
    deadline = time.monotonic() + budget if budget else None
    stop = threading.Event()
    ids = {c.id: k for k, c in enumerate(cases)}
    names = {r.name for r in rasterizers}
    done = {pair for pair in recorded.complete if pair[0] in names and pair[1] in ids} if recorded is not None else set()
    recorder, kept = _journal_writer(args, parameters, recorded, done) if journal else (None, None)
    collected = _Collected(rasterizers, cases, recorder, start)
    for result in kept.results if kept is not None else []:
        collected(result, journaled=True)  # what the resumed journal holds: a result of this run, not run again

    def one(r: Any) -> None:
        mine, skips_of_r = _run_and_skipped(cases, skips, r.name)
        mine = [c for c in mine if (r.name, c.id) not in done]
        for result in skips_of_r:
            if (r.name, result.case) not in done:
                collected(result)
                if recorder is not None:
                    recorder.complete(r.name, result.case)
        with Session(declared(r), args.timeout) as session:  # its worker process, closed when its cases are done
            run_session(session, mine, on_result=collected, only=only, rerun=getattr(args, "rerun", 0), stop=stop,
                        deadline=deadline, on_case=recorder.complete if recorder is not None else None)

    pool = ThreadPoolExecutor(max_workers=args.jobs)
    try:
        for future in [pool.submit(one, r) for r in rasterizers]:
            while True:
                try:
                    future.result(timeout=0.2)
                    break
                except TimeoutError:
                    continue
    except KeyboardInterrupt:
        stop.set()
        kill_all()
        pool.shutdown(wait=True, cancel_futures=True)
        with collected.lock:
            raise Interrupted(rasterizers, list(collected.results), time.perf_counter() - start, fingerprints) from None
    finally:
        pool.shutdown(wait=False)
        collected.close()
    order = {r.name: k for k, r in enumerate(rasterizers)}
    results = sorted(collected.results, key=lambda x: order.get(x.rasterizer, len(order)))  # stable: per rasterizer, in run order
    if done:  # resumed: the journal's results and the new ones in suite order, as a run in one go gives them
        results.sort(key=lambda x: (order.get(x.rasterizer, len(order)), ids.get(x.case, len(ids))))
    return rasterizers, results, time.perf_counter() - start, fingerprints


def _kind(r: Any) -> str:
    from harness.engine.registry import builtins

    inner = getattr(r, "inner", r)
    module = type(inner).__module__
    if module.startswith("rasterizers.real"):
        return "real library"
    return "built-in" if r.name in builtins() and module.startswith("rasterizers.") else "plugin"


def _write_outputs(args: argparse.Namespace, rasterizers: list[Any], results: list[Any], seconds: float,
                   fingerprints: dict[str, dict[str, Any]], quiet: bool = False) -> None:
    from harness.contract.protocol import fingerprint_of
    from harness.report.pages import capabilities, write_report
    from harness.results.output import write_json, write_junit

    out = Path(args.out)
    written = _write_repros(out, results)
    conventions = {r.name: _convention_text(r) for r in rasterizers}
    declared = {r.name: (r.convention.describe() if r.convention is not None and fingerprint_of(r) is None
                         else "none declared") for r in rasterizers}
    kinds = {r.name: _kind(r) for r in rasterizers}
    # the rasterizers come in load order (renamed and identified ones in place): each one's spec
    specs = dict(zip([r.name for r in rasterizers], _loaded_specs)) if len(_loaded_specs) == len(rasterizers) else {}
    able = capabilities(rasterizers)
    path = write_report(out, conventions, results, args.seed, args.suite, seconds,
                        fingerprints=fingerprints, declared=declared, kinds=kinds, specs=specs, skipped=dict(_skipped),
                        patterns={r.name: r.convention.samples for r in rasterizers
                                  if r.convention is not None and r.convention.samples is not None},
                        **able)
    if not quiet:
        print(f"report: {path}" + (f"; {written} minimal repros in {out / 'repros'}" if written else ""))
    if args.json:
        write_json(args.json, results, args.suite, args.seed, conventions, fingerprints, **able)
    if args.junit:
        write_junit(args.junit, results)


def _convention_text(r: Any) -> str:
    from harness.contract.protocol import fingerprint_of

    fingerprint = fingerprint_of(r)
    if fingerprint is not None:
        if getattr(fingerprint, "pattern_missing", False):  # a stand-in, never called identified
            return (f"none declared; no multisample pattern recovered ({fingerprint.facts.get('pattern', '')}); "
                    f"checked against {r.convention.describe()}, a stand-in")
        quality = ("exactly" if fingerprint.exact else
                   f"best guess only because calls failed: {fingerprint.unanswered} fit scenes unanswered, residual "
                   f"{fingerprint.residual} pixels over the rest" if getattr(fingerprint, "unanswered", 0) else
                   f"best guess, residual {fingerprint.residual} pixels")
        return f"none declared; identified as {r.convention.describe()} ({quality}), used for the convention-bound checks"
    return r.convention.describe() if r.convention else "none declared"


def _summary(rasterizers: list[Any], results: list[Any]) -> None:
    from harness.results.output import call_failures, call_failures_text

    calls = call_failures(results)
    for r in rasterizers:
        mine = [x for x in results if x.rasterizer == r.name]
        bad = sum(x.status in ("fail", "error") for x in mine)
        if not any(x.status in ("pass", "fail") for x in mine):  # why, in one line, after the report is written
            print(f"{r.name:<22} nothing checked: {len(mine)} result{'' if len(mine) == 1 else 's'}, none a pass or a fail")
        else:
            print(f"{r.name:<22} {len(mine) - bad}/{len(mine)} pass or skip" + (f", {bad} failing" if bad else ""))
        if r.name in calls:  # calls that timed out or failed, and which, said whatever else is
            print(f"{'':<22} calls: {call_failures_text(calls[r.name])}")


SIGNATURES_SHOWN = 3  # signatures named per cause in the terminal; the rest are counted


def _failures(results: list[Any], out: Path, shown: int) -> None:
    """The failing results by cause (:func:`harness.diagnose.causes.by_cause`, as the report and the
    campaign page group them), the largest first: per cause its rasterizer, count and
    checks, its signatures' words with their counts and a minimal repro (the file ``run``
    wrote; a case without one is named); ``shown`` causes at most, the rest counted and
    sent to the report. Nothing when nothing fails."""
    from harness.diagnose.causes import by_cause

    groups = by_cause(results)
    if not groups:
        return
    failing = sum(g.count for g in groups)
    print(f"{failing} failing result{'' if failing == 1 else 's'} in {len(groups)} cause{'' if len(groups) == 1 else 's'}, "
          "most first:")
    for group in groups[:shown]:
        print(f"  {group.rasterizer}: {group.cause} -- {group.count} failing, seen by {', '.join(group.checks)}")
        for found in group.signatures[:SIGNATURES_SHOWN]:
            print(f"    {found.count:>4} {found.status} {found.describe()}")
        if len(group.signatures) > SIGNATURES_SHOWN:
            unnamed = group.signatures[SIGNATURES_SHOWN:]
            print(f"         ... {len(unnamed)} more signature{'' if len(unnamed) == 1 else 's'} "
                  f"({sum(g.count for g in unnamed)} failing)")
        repro = group.repro_path()
        print(f"    repro: {out / repro}" if repro is not None else f"    case: {group.results[0].case} (no minimal repro)")
    if len(groups) > shown:
        rest = groups[shown:]
        print(f"  ... {len(rest)} more cause{'' if len(rest) == 1 else 's'} ({sum(g.count for g in rest)} failing) "
              f"in {out / 'index.html'}")


def _interrupted(args: argparse.Namespace, stopped: Interrupted) -> int:
    """Ctrl-C: the partial report and JSON of what finished, one line, exit 130."""
    rasterizers, results, seconds, fingerprints = stopped.partial
    if results:
        _write_outputs(args, rasterizers, results, seconds, fingerprints, quiet=True)
    print(f"rastercheck: interrupted after {seconds:.0f} s; "
          + (f"the partial report of {len(results)} results is in {args.out}" if results else "nothing had finished"),
          file=sys.stderr)
    return 130


def _run(args: argparse.Namespace) -> int:
    try:
        rasterizers, results, seconds, fingerprints = _execute(args, journal=True)
    except Interrupted as stopped:
        return _interrupted(args, stopped)
    _summary(rasterizers, results)
    _refusals(results)
    _write_outputs(args, rasterizers, results, seconds, fingerprints)
    _failures(results, Path(args.out), args.causes)
    return _verdict(rasterizers, results, _selected, _broken)


def _verdict(rasterizers: list[Any], results: list[Any], cases: list[Any], broken: list[str]) -> int:
    """The exit code of a run whose outputs are written, with one line (on stderr) per
    rasterizer that nothing judged (:func:`harness.engine.runner.nothing_checked`) and per
    registered plugin that failed to load: 2 when a plugin failed to load (an input
    error), else 1 when a check failed or errored or a rasterizer was not checked at all,
    else 0."""
    from harness.engine.runner import nothing_checked

    unchecked = [why for r in rasterizers if (why := nothing_checked(r, results, cases)) is not None]
    for why in unchecked:
        print(f"rastercheck: {why}", file=sys.stderr)
    for problem in broken:
        print(f"rastercheck: not checked: a registered plugin failed to load: {problem}", file=sys.stderr)
    if broken:
        return 2
    return 1 if unchecked or any(x.status in ("fail", "error") for x in results) else 0


def _refusals(results: list[Any]) -> None:
    """One line per rasterizer and scene kind refused for answers that contradict what it
    declares (:mod:`harness.contract.declarations`): what to add, said once."""
    for x in results:
        if x.status == "error" and "refused" in x.evidence:
            print(f"{x.rasterizer}: {x.message}")


def _update_command(args: argparse.Namespace) -> str:
    """The ``rastercheck gate ... --update-baseline`` that accepts this run's selection."""
    import shlex

    parts = ["rastercheck", "gate"]
    for spec in args.rasterizer or []:
        parts += ["--rasterizer", spec]
    parts += ["--suite", args.suite, "--seed", str(args.seed)]
    for glob in args.case or []:
        parts += ["--case", glob]
    for name in args.check or []:
        parts += ["--check", name]
    if args.skip:
        parts += ["--skip", args.skip]
    if args.shard:
        parts += ["--shard", f"{args.shard[0]}/{args.shard[1]}"]
    parts += ["--baseline", args.baseline] + (["--allow-missing"] if args.allow_missing else []) + ["--update-baseline"]
    return shlex.join(parts)


def _gate(args: argparse.Namespace) -> int:
    """Run the suite, then compare with the baseline: exit 1 on a regression (a missing
    result is one, unless --allow-missing). With --update-baseline, write the run as the
    new baseline instead. A baseline that is a folder, unreadable, malformed, or of
    another rasterizer than the run's is a usage error (exit 2). --junit is written with
    the gate's verdict: known failures skipped, regressions failing."""
    from harness.results.files import prepare_file
    from harness.results.gate import compare_with_baseline, load_baseline, save_baseline
    from harness.results.output import write_junit

    baseline: dict[str, Any] = {}
    path = Path(args.baseline)
    try:
        if args.update_baseline:
            prepare_file(path, "--baseline")
        if not args.update_baseline or path.exists():
            baseline = load_baseline(path)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    campaigns = _known_campaigns(args.known_campaign or [])

    def same_rasterizers(rasterizers: list[Any]) -> None:
        """Before any work: a baseline (or a known campaign) of other rasterizers is a usage
        error now, not after the suite."""
        known = {key.split("|", 1)[0] for key in baseline}
        names = {r.name for r in rasterizers}
        if known and not args.update_baseline and not known & names:
            raise UsageError(f"{path}: the baseline is of {', '.join(sorted(known))}, this run of {', '.join(sorted(names))}: "
                             "no rasterizer in common (another --baseline, or --update-baseline to start one)")
        for campaign in campaigns:
            if campaign.rasterizer not in names:
                raise UsageError(f"--known-campaign {campaign.directory}: a campaign on {campaign.rasterizer}, and this run "
                                 f"is of {', '.join(sorted(names))}: its findings would apply to none of them")

    try:
        rasterizers, results, seconds, fingerprints = _execute(args, loaded=same_rasterizers)
    except Interrupted as stopped:  # the partial report and JSON, but no verdict (nor JUnit) on half a run
        return _interrupted(argparse.Namespace(**{**vars(args), "junit": None}), stopped)
    before: bytes | None = None
    if args.update_baseline:
        before = path.read_bytes() if path.exists() else None
        save_baseline(path, results, baseline, keep_missing=args.allow_missing)
        baseline = load_baseline(path)
    known_failure = None
    if campaigns:
        from harness.results.gate import campaign_known, result_signature

        by_name = {r.name: r for r in rasterizers}
        known_failure = campaign_known(campaigns, lambda r: result_signature(r, by_name.get(r.rasterizer)))
    try:
        verdict = compare_with_baseline(results, baseline, allow_missing=args.allow_missing, known_failure=known_failure)
    except ValueError as exc:
        raise UsageError(f"{path}: {exc}") from None
    _write_outputs(argparse.Namespace(**{**vars(args), "junit": None}), rasterizers, results, seconds, fingerprints)
    if args.junit:
        write_junit(args.junit, results, verdict)
    if args.update_baseline:
        print(f"baseline {'unchanged' if before == path.read_bytes() else 'updated'}: {path} ({len(baseline)} entries)")
        return 0
    for line in verdict.lines():
        print(line)
    fixed = verdict.of("fixed")
    if fixed:
        print(f"to accept the {len(fixed)} unexpected passes as the new baseline: {_update_command(args)}")
    absent = len(verdict.of("absent"))
    from_campaigns = sum(f.reason.startswith("known from the campaign") for f in verdict.of("known"))
    print(f"gate: {len(verdict.regressions)} regressions ({len(verdict.of('missing'))} missing), {len(fixed)} unexpectedly passing, "
          f"{len(verdict.of('known'))} known failures"
          + (f" ({from_campaigns} known from campaigns)" if campaigns else "") + f", {len(verdict.of('new'))} new"
          + (f", {absent} not run (missing allowed)" if absent else ""))
    return 0 if verdict.ok else 1


def _known_campaigns(directories: list[str]) -> list[Any]:
    """The findings of each ``--known-campaign`` folder (:class:`harness.results.gate.CampaignFindings`);
    a folder that holds no readable campaign is a usage error naming it."""
    from harness.results.gate import CampaignFindings

    out = []
    for directory in directories:
        try:
            out.append(CampaignFindings.load(directory))
        except ValueError as exc:
            raise UsageError(f"--known-campaign {directory}: {exc}") from None
    return out


def _write_repros(out: Path, results: list[Any]) -> int:
    """Save each attached minimal repro as <out>/repros/<rasterizer>/<case>--<check>.json,
    every part sanitised (no name leaves <out>)."""
    from harness.results.files import atomic_write_text, safe_name

    count = 0
    for r in results:
        payload = r.evidence.get("repro")
        if payload is None:
            continue
        path = out / "repros" / safe_name(r.rasterizer) / f"{safe_name(r.case)}--{safe_name(r.check)}.json"
        atomic_write_text(path, json.dumps(payload, indent=1))
        r.evidence["repro_path"] = str(path.relative_to(out))
        count += 1
    return count


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


def _declared_verdict(rasterizer: Any, fingerprint: Any, seed: int, timeout: float) -> tuple[str, bool]:
    """What identify says of a declared convention: (the words, contradicted?).

    Contradicted when any check of its coverage kind (:data:`harness.identify.fingerprint.VERDICT_CHECKS`:
    conformance for one sample, conformance sample by sample for multisample, accuracy,
    seams and popping for area coverage) fails against the declaration on identify's probe
    scenes and the suite's scenes of those checks (:func:`harness.identify.fingerprint.verdict_cases`),
    measured directly, so that a convention outside identify's candidates is judged fairly:
    the words name each failing check. Otherwise confirmed when identify found exactly the
    declared convention, else consistent but not pinned down. A single-sample declaration
    identified exactly is confirmed without more (its conformance on the probes is the
    residual, 0)."""
    from harness.contract.protocol import scene_kinds_of
    from harness.engine.runner import run_suite
    from harness.identify.fingerprint import verdict_cases

    declared = rasterizer.convention
    model = declared.model
    stand_in = getattr(fingerprint, "pattern_missing", False)  # its convention no finding: never compared as one
    same = declared == fingerprint.convention and fingerprint.exact and not stand_in
    if same and model.single_sample:
        return "confirmed", False
    cases = verdict_cases(fingerprint, seed, scene_kinds_of(rasterizer), declared.kind)
    names = model.verdict_checks
    results = run_suite([rasterizer], cases=cases, only=set(names), repros=False, identify=False, timeout=timeout)
    failing = [r for r in results if r.status in ("fail", "error") and r.check in (*names, "run")]
    if failing:
        judged = {check: len({r.case for r in results if r.check == check}) for check in (*names, "run")}
        counts = [f"{check} fails on {sum(r.check == check for r in failing)} of {judged[check]} cases"
                  for check in (*names, "run") if any(r.check == check for r in failing)]
        said = "; ".join(counts)
        if model.single_sample:
            pixels = sum(int(r.metrics.get("missing", 0) + r.metrics.get("extra", 0)) for r in failing)
            said = f"{len(failing)} of {len(cases)} conformance cases fail against it ({pixels} pixels)"
        return f"NOT what it does: {said}, e.g. {failing[0].case}: {failing[0].message}", True
    checked = " and ".join(names) + (" pass" if len(names) > 1 else " passes") + f" against it on {len(cases)} cases"
    if same:
        return f"confirmed ({checked})", False
    if stand_in:
        return f"consistent: {checked}, though identify recovered no pattern to compare", False
    if declared == fingerprint.convention:
        return f"consistent ({checked}; identify could not tell it from " + (
            " and ".join(fingerprint.ambiguous) or "the runner-up") + ")", False
    return f"consistent: {checked}, though identify's best fit is {fingerprint.convention.describe()}", False


def _identify(args: argparse.Namespace) -> int:
    """The fingerprint card; exit 1 when the rasterizer's declared convention is
    contradicted or a probe saw a defect the suite's checks fail on too (each with its
    evidence on the card), 2 when it cannot be loaded; ``--json`` writes the fingerprint.
    Ctrl-C: every worker killed at once, one line, exit 130 (nothing is identified from
    part of the probes)."""
    from harness.engine.isolation import kill_all

    start = time.monotonic()
    try:
        return _identify_card(args)
    except KeyboardInterrupt:
        kill_all()
        print(f"rastercheck: identify {args.spec}: interrupted after {time.monotonic() - start:.0f} s; nothing identified",
              file=sys.stderr)
        return 130


def _identify_card(args: argparse.Namespace) -> int:
    """:func:`_identify`'s work: load, probe, print the card, judge the declaration."""
    from harness.contract.protocol import scene_kinds_of
    from harness.identify.fingerprint import identify_isolated
    from harness.results.files import atomic_write_text, prepare_file

    if args.json:
        try:
            prepare_file(args.json, "--json")
        except ValueError as exc:
            raise UsageError(str(exc)) from None
    rasterizers, _ = _load_all([args.spec], args.timeout)
    if not rasterizers:
        return 2  # unavailable: reported as skipped with its install hint; nothing was identified
    rasterizer = rasterizers[0]
    try:
        fingerprint = identify_isolated(rasterizer, seed=args.seed, timeout=max(300.0, 10 * args.timeout),
                                        call_timeout=args.timeout)
    except Exception as exc:  # the rasterizer died or hung outside Python: say so, no traceback
        print(f"identify {rasterizer.name}: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    print(fingerprint.card())
    silence = fingerprint.no_answers
    if silence is not None:  # nothing to fit, nothing to judge a declaration by: no verdict but this one
        if args.json:
            atomic_write_text(args.json, json.dumps({"schema": 1, "fingerprint": fingerprint.to_dict(), "no_answers": silence,
                                                     "declared": None if rasterizer.convention is None
                                                     else rasterizer.convention.describe()}, indent=1))
        print(f"rastercheck: identify {rasterizer.name}: no answers, nothing identified: {silence}", file=sys.stderr)
        return 1
    declared = rasterizer.convention
    # a line drawer's declaration in line words
    words_of = (lambda c: c.describe_lines()) if scene_kinds_of(rasterizer) == ("lines",) else (lambda c: c.describe())
    payload: dict[str, Any] = {"schema": 1, "fingerprint": fingerprint.to_dict(),
                               "declared": words_of(declared) if declared is not None else None}
    contradicted = False
    if declared is not None:
        words, contradicted = _declared_verdict(rasterizer, fingerprint, args.seed, args.timeout)
        defects = fingerprint.defects
        if defects:  # the suite fails on these very scenes: identify says so as run does
            words += "; but " + "; ".join(f"{label} fails on {len(found)} of its scenes (evidence above)"
                                          for label, found in defects.items())
            contradicted = True
        print(f"declared     {words_of(declared)} ({words})")
        payload.update(verdict=words, contradicted=contradicted)
    if args.json:
        atomic_write_text(args.json, json.dumps(payload, indent=1))
    if contradicted:
        print(f"rastercheck: identify {rasterizer.name}: its declared convention is contradicted by what it does "
              "(the 'declared' line above)", file=sys.stderr)
    return 1 if contradicted else 0


def _replay(args: argparse.Namespace) -> int:
    from harness.contract.case import MotionCase, read_case_file
    from harness.contract.protocol import fill_rules_of, scene_kinds_of, takes
    from harness.contract.scenes import PathScene
    from harness.engine.runner import nothing_checked, replay

    try:
        read_case_file(args.case)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    rasterizers, _ = _load_all([args.rasterizer], args.timeout)
    if not rasterizers:
        return 2  # unavailable: reported as skipped with its install hint; nothing was replayed
    case, _ = read_case_file(args.case)
    scene = case.frames[0] if isinstance(case, MotionCase) else case.scene
    if not takes(rasterizers[0], scene):
        kinds = scene_kinds_of(rasterizers[0])
        rule = f" under the {scene.fill_rule} fill rule" if isinstance(scene, PathScene) and scene.kind in kinds else ""
        raise UsageError(f"replay {args.case}: a case of {scene.kind}{rule}, which {rasterizers[0].name} does not take "
                         f"(scene_kinds={kinds!r}" + (f", fill_rules={fill_rules_of(rasterizers[0])!r}" if rule else "")
                         + "): nothing to replay")
    results = replay(args.case, rasterizers[0], isolate=True, timeout=args.timeout)
    for r in results:
        print(f"{r.status:<6} {r.check:<12} {r.message}")
    why = nothing_checked(rasterizers[0], results, [case])
    if why is not None:
        print(f"rastercheck: replay {args.case}: {why}", file=sys.stderr)
        return 1
    return 1 if any(r.status in ("fail", "error") for r in results) else 0


_BENCH_KINDS = ("triangles", "paths", "lines")


def _bench_kinds(text: str) -> tuple[str, ...]:
    """``bench --kinds``: comma-separated workload kinds, each of triangles, paths, lines."""
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
    kinds = args.kinds or _BENCH_KINDS
    results = run_bench(names, scale=args.scale, budget=args.budget, timeout=args.timeout, triangles="triangles" in kinds,
                        paths="paths" in kinds, lines="lines" in kinds,
                        progress=lambda line: print(f"[{time.perf_counter() - started:5.0f} s] {line}", file=sys.stderr, flush=True))
    print(format_table(results, {w.name: w.description for w in workloads(args.scale)}))
    not_measured = missing_peers()
    for label, why in not_measured.items():  # a library that is not installed costs only its own rows, and says so
        print(f"not measured: {label}: {why}")
    failed = failures_by_contender(results)
    for label, why in failed.items():  # a contender that failed costs only its own rows, and says so
        print(f"failed: {label}: {why}")
    if args.json:
        write_json(results, Path(args.json), not_measured=not_measured)
        print(f"json: {args.json}")
    return 1 if failed else 0


def _bench_campaign(args: argparse.Namespace) -> int:
    """``bench --campaign``: the same fixed scene budget on one local worker, then two;
    checked primitives per second per worker and the speed-up, as a table and JSON. Exit 1
    when the rasterizer's calls failed (every call of the warm-up: nothing measured; some
    in the campaigns: no speed-up judged)."""
    from harness.cli.bench import (
        CAMPAIGN_REFERENCE,
        CAMPAIGN_REPEATS,
        CAMPAIGN_SCENES,
        NothingMeasured,
        campaign_summary,
        format_campaign_table,
        run_campaign_bench,
        write_json,
    )

    if args.rasterizer and len(args.rasterizer) > 1:
        raise UsageError("bench --campaign measures one rasterizer: give --rasterizer once")
    spec = args.rasterizer[0] if args.rasterizer else CAMPAIGN_REFERENCE
    _load_all([spec])  # fail early, with a usage error, on a bad spec
    started = time.perf_counter()
    try:
        results = run_campaign_bench(spec, scenes=args.scenes or CAMPAIGN_SCENES, repeats=args.repeats or CAMPAIGN_REPEATS,
                                     timeout=args.timeout, progress=lambda line: print(f"[{time.perf_counter() - started:5.0f} s] {line}",
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


# -- fuzz: campaigns ------------------------------------------------------------------------------

_DURATION = re.compile(r"(?:(?P<h>\d+(?:\.\d+)?)h)?(?:(?P<m>\d+(?:\.\d+)?)m(?:in)?)?(?:(?P<s>\d+(?:\.\d+)?)s)?")
_BUDGET_HELP = "a duration (90s, 10m, 1h, 1h30m) or a number of scenes (5000)"


class Budget(NamedTuple):
    """A campaign's budget: seconds or scenes (the other None), and as it was written."""

    seconds: float | None
    scenes: int | None
    text: str


def _budget(text: str) -> Budget:
    """``--budget``: seconds for a duration such as ``90s``, ``10m``, ``1h`` or ``1h30m``;
    scenes for a whole number; else a usage error naming it.

    >>> _budget("10m")[:2], _budget("1h30m")[:2], _budget("5000")[:2]
    ((600.0, None), (5400.0, None), (None, 5000))
    """
    value = text.strip().lower().replace(" ", "")
    if value.isdigit():
        scenes = int(value)
        if scenes < 1:
            raise argparse.ArgumentTypeError(f"expected {_BUDGET_HELP}, at least 1 scene, not {text!r}")
        return Budget(None, scenes, f"{scenes:,} scenes")
    match = _DURATION.fullmatch(value)
    if not value or match is None or not any(match.groupdict().values()):
        raise argparse.ArgumentTypeError(f"expected {_BUDGET_HELP}, not {text!r}")
    seconds = sum(float(match.group(unit) or 0) * scale for unit, scale in (("h", 3600.0), ("m", 60.0), ("s", 1.0)))
    if not (math.isfinite(seconds) and seconds > 0):
        raise argparse.ArgumentTypeError(f"expected {_BUDGET_HELP} longer than nothing, not {text!r}")
    return Budget(seconds, None, text.strip())


def _families(text: str) -> list[str]:
    """``--families a,b``: fuzz families of :data:`cases.fuzz.FAMILIES`, each named once."""
    from cases.fuzz import FAMILIES

    names = [f.strip() for f in text.split(",") if f.strip()]
    unknown = [f for f in names if f not in FAMILIES]
    if unknown or not names:
        what = f"unknown famil{'ies' if len(unknown) > 1 else 'y'} {', '.join(map(repr, unknown))}" if unknown else "no family"
        raise argparse.ArgumentTypeError(f"{what} in {text!r} (families: {','.join(FAMILIES)})")
    return list(dict.fromkeys(names))


def _clock(seconds: float | None) -> str:
    """``1:02:03``, ``4:05``, ``--`` for an unknown span."""
    if seconds is None or not math.isfinite(seconds):
        return "--"
    total = int(round(max(seconds, 0.0)))
    hours, rest = divmod(total, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


class _FuzzProgress:
    """A campaign's progress: a live table on a terminal (scenes/s, primitives/s, findings
    by signature, ETA against the budget), plain lines every ``every`` seconds otherwise
    (and one at once for each new signature)."""

    def __init__(self, budget: str, quiet: bool, every: float = 10.0) -> None:
        self.budget, self.quiet, self.every = budget, quiet, every
        self.event: Any = None
        self.started = time.monotonic()
        self.lock = threading.Lock()
        self.done = threading.Event()
        self.live: Any = None
        self.thread: threading.Thread | None = None

    def __enter__(self) -> _FuzzProgress:
        if self.quiet:
            self.thread = threading.Thread(target=self._plain_loop, name="rastercheck-fuzz-progress", daemon=True)
            self.thread.start()
        else:
            from rich.console import Console
            from rich.live import Live

            self.live = Live(self, console=Console(stderr=True), refresh_per_second=2, transient=False)
            self.live.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.done.set()
        if self.live is not None:
            self.live.stop()
        if self.thread is not None:
            self.thread.join(timeout=1.0)

    def __call__(self, event: Any) -> None:
        """The campaign's ``on_progress``: kept for the display; a new signature is said at once in plain mode."""
        with self.lock:
            self.event = event
        if self.quiet:
            for key in event.new_signatures:
                where = next((f for f in event.batch_findings if f.signature_key == key), None)
                at = f" on scene {where.family}/{where.seed}/{where.index}" if where is not None else ""
                print(f"fuzz: new signature {key}{at}", file=sys.stderr, flush=True)

    def line(self) -> str:
        with self.lock:
            event = self.event
        if event is None:
            return f"fuzz: starting the workers ({time.monotonic() - self.started:.0f} s)"
        top = sorted(event.signatures.items(), key=lambda kv: -kv[1])[:3]
        kinds = "; ".join(f"{k} {n:,}" for k, n in top) + (" ..." if len(event.signatures) > 3 else "")
        return (f"fuzz: {event.scenes:,} scenes, {event.primitives:,} primitives in {event.elapsed:.0f} s "
                f"({event.scenes_per_second:,.1f} scenes/s, {event.primitives_per_second:,.0f} primitives/s, "
                f"{event.workers} worker{'s' if event.workers != 1 else ''}); {event.findings:,} findings in "
                f"{len(event.signatures)} signature{'s' if len(event.signatures) != 1 else ''}"
                + (f" ({kinds})" if kinds else "") + f"; budget {self.budget}, ETA {_clock(event.eta)}")

    def _plain_loop(self) -> None:
        while not self.done.wait(self.every):
            print(self.line(), file=sys.stderr, flush=True)

    def __rich__(self) -> Any:
        from rich.console import Group
        from rich.table import Table
        from rich.text import Text

        with self.lock:
            event = self.event
        if event is None:
            return Text(f"fuzz: starting the workers ... {time.monotonic() - self.started:.0f} s")
        head = Text.assemble(
            ("fuzz ", "bold"), f"{event.scenes:,} scenes this run ({event.total_scenes:,} in the campaign), "
            f"{event.scenes_per_second:,.1f} scenes/s, {event.primitives_per_second:,.0f} primitives/s on {event.workers} "
            f"worker{'s' if event.workers != 1 else ''}\n",
            f"elapsed {_clock(event.elapsed)}, ETA {_clock(event.eta)} (budget {self.budget}); ",
            (f"{event.findings:,} findings in {len(event.signatures)} signature{'s' if len(event.signatures) != 1 else ''}",
             "bold red" if event.findings else "green"))
        table = Table(show_header=False, box=None, padding=(0, 1), pad_edge=False)
        table.add_column(justify="right", no_wrap=True)
        table.add_column(overflow="fold")
        ranked = sorted(event.signatures.items(), key=lambda kv: (-kv[1], kv[0]))
        for key, count in ranked[:10]:
            table.add_row(f"{count:,}", key)
        if len(ranked) > 10:
            table.add_row("", f"... {len(ranked) - 10} more")
        return Group(head, table) if ranked else head


def _fuzz_summary(state: Any, run: dict[str, Any] | None) -> None:
    """The campaign in a few lines: this run's figures, then each signature with its count,
    first scene and repro."""
    if run is not None:
        print(f"fuzz {state.rasterizer}: {run['scenes']:,} scenes ({run['primitives']:,} primitives) in {run['seconds']:.1f} s "
              f"on {run['workers']} worker{'s' if run['workers'] != 1 else ''}: {run['scenes_per_second']:,.1f} scenes/s, "
              f"{run['primitives_per_second']:,.0f} primitives/s; the campaign has checked {state.scenes:,} scenes")
    else:
        print(f"campaign {state.rasterizer}: {state.scenes:,} scenes, {state.primitives:,} primitives")
    for family, why in sorted(state.skipped.items()):
        print(f"  skipped {family}: {why}")
    if not state.signatures:
        print("no findings")
        return
    causes = state.causes()
    print(f"{state.findings:,} finding{'s' if state.findings != 1 else ''} in {len(state.signatures)} signature{'s' if len(state.signatures) != 1 else ''}"
          f" of {len(causes)} cause{'s' if len(causes) != 1 else ''}:")
    for group in causes:
        print(f"  {group['cause']}: {group['findings']:,} finding{'s' if group['findings'] != 1 else ''}, seen by {', '.join(group['checks'])}")
        for key in group["signatures"]:
            entry = state.signatures[key]
            first = entry["first"]
            repro = Path(state.directory) / entry["repro"] if entry.get("repro") else None
            print(f"    {int(entry['count']):>8,}  {key}  first {first['family']}/{first['seed']}/{first['index']}, "
                  + (f"repro {repro}" if repro is not None else "no repro yet"))


def _fuzz_outputs(args: argparse.Namespace, state: Any, run: dict[str, Any] | None) -> None:
    """The campaign page under --out and the JSON (--json), each written atomically."""
    from harness.report.pages import campaign_json, write_campaign_page
    from harness.results.files import atomic_write_text

    rasterizer = None
    try:
        from harness.engine.registry import load

        rasterizer = state.judged(load(state.spec))  # its convention draws the covered pixels on each repro
    except Exception:  # noqa: BLE001 - the page is written without them
        rasterizer = None
    page = write_campaign_page(args.out, state, rasterizer=rasterizer, run=run)
    if args.json:
        atomic_write_text(args.json, json.dumps(campaign_json(state, run, page), indent=1))
    _fuzz_summary(state, run)
    print(f"page: {page}" + (f"; json: {args.json}" if args.json else ""))
    print(f"state: {state.directory} (rerun with the same --state to continue: no scene is checked twice)")


def _fuzz(args: argparse.Namespace) -> int:
    """Run a campaign (or merge campaigns' states); exit 1 when the campaign holds findings."""
    from harness.results.files import prepare_file, prepare_folder

    if args.merge is not None:
        if args.rasterizer or args.budget:
            raise UsageError("fuzz --merge takes state folders and --state, not --rasterizer or --budget")
    elif not args.rasterizer or not args.budget:
        raise UsageError("fuzz needs --rasterizer SPEC and --budget (10m, 90s, 1h or a number of scenes); "
                         "or --merge DIR ... --state OUT")
    try:
        prepare_folder(args.out, "--out")
        if args.json:
            prepare_file(args.json, "--json")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.merge is not None:
        return _fuzz_merge(args)
    from harness.campaign.coordinator import run_campaign
    from harness.campaign.state import CampaignError
    from harness.report.pages import campaign_run

    seconds, scenes, budget_text = args.budget
    progress = _FuzzProgress(budget_text, _quiet())
    interrupted = False
    before = _saved_state(args.state)
    judged_before, scenes_before = (before.primitives, before.scenes) if before is not None else (0, 0)
    try:
        with progress:
            state = run_campaign(args.rasterizer, budget_seconds=seconds, budget_scenes=scenes, families=args.families,
                                 seed=args.seed, state_dir=args.state, scheduler=args.scheduler, workers=args.workers,
                                 scheduler_timeout=args.scheduler_timeout,
                                 batch_size=args.batch, only=args.check, timeout=args.timeout, on_progress=progress)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    except CampaignError as exc:
        print(f"rastercheck: campaign stopped: {exc}", file=sys.stderr)
        state = _saved_state(args.state)
        if state is not None:
            _fuzz_outputs(args, state, campaign_run(progress.event))
        return 2
    except KeyboardInterrupt:
        interrupted = True
        state = _saved_state(args.state)
        if state is None:
            print("rastercheck: interrupted before any batch was merged", file=sys.stderr)
            return 130
    _fuzz_outputs(args, state, campaign_run(progress.event))
    if interrupted:
        print(f"rastercheck: interrupted; the state in {args.state} keeps every batch merged: rerun to continue", file=sys.stderr)
        return 130
    if state.primitives == judged_before:  # no scene of this run had a check judge it: no verdict to give
        print(f"rastercheck: nothing checked: {_why_nothing(state, args.families, state.scenes - scenes_before)}",
              file=sys.stderr)
        return 1
    return 1 if state.signatures else 0


def _why_nothing(state: Any, families: list[str] | None, handed: int) -> str:
    """Why a campaign run that handed over ``handed`` scenes judged none, in one line."""
    asked = families or list(state.families)
    skipped = [f"{f} ({state.skipped[f]})" for f in asked if f in state.skipped]
    if len(skipped) == len(asked):
        return f"{state.rasterizer} takes no scene of the families asked: {'; '.join(skipped)}"
    if handed:
        return (f"{state.rasterizer} was handed {handed} scenes but every check skipped them (it raised Unsupported, or takes "
                "none of what they hold)" + (f"; skipped families: {'; '.join(skipped)}" if skipped else ""))
    return "the budget ended before one batch of scenes was checked: give a larger --budget"


def _saved_state(directory: str) -> Any:
    """The campaign state saved in ``directory``, or None when there is none yet."""
    from harness.campaign.state import CampaignState

    try:
        return CampaignState.load(directory)
    except ValueError:
        return None


def _fuzz_merge(args: argparse.Namespace) -> int:
    """``fuzz --merge A B ... --state OUT``: each campaign's scenes and findings added to
    OUT (created from the first when it holds none); a clash (another rasterizer, scenes
    checked twice) is a usage error naming both."""
    from harness.campaign.state import state_lock

    target = Path(args.state)
    sources = [Path(d) for d in args.merge if Path(d).resolve() != target.resolve()]
    if not sources:
        raise UsageError("fuzz --merge: name at least one state folder other than --state")
    try:
        with state_lock(target):
            return _merge_locked(args, target, sources)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def _merge_locked(args: argparse.Namespace, target: Path, sources: list[Path]) -> int:
    """:func:`_fuzz_merge` with the target state locked."""
    from harness.campaign.state import CampaignState

    try:
        states = [CampaignState.load(d) for d in sources]
        existing = _saved_state(str(target))
        if existing is None:
            first = states[0]
            existing = CampaignState.open(target, first.spec, first.rasterizer, first.seed, first.only)
            existing.identified = first.identified
            existing.batch_size = first.batch_size
        for other in states:
            existing.merge(other)
            if existing.identified is None:
                existing.identified = other.identified
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    existing.save()
    print(f"merged {', '.join(map(str, sources))} into {target}")
    _fuzz_outputs(args, existing, None)
    return 1 if existing.signatures else 0


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
    parser.add_argument("--timeout", type=_positive_seconds, default=60.0, help="the most seconds one rasterize call may take (the cap of its scaled limit; see README, Reliability)")
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
    ide.add_argument("--timeout", type=_positive_seconds, default=60.0, help="the most seconds one rasterize call may take (the cap of its scaled limit; see README, Reliability)")
    ide.add_argument("--json", type=_path, metavar="FILE", help="also write the fingerprint (and the verdict on a declared convention) as JSON")
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
                       help="only these workload kinds: triangles (W1, W2), paths (P1, P2), lines (L1, L2); default all")
    bench.add_argument("--timeout", type=_positive_seconds, default=60.0,
                       help="the most seconds one call of a contender may take (each contender runs in a process of its own)")
    bench.add_argument("--campaign", action="store_true",
                       help="instead: a campaign of a fixed scene budget on 1, then 2 local workers (a built-in reference, "
                            "or --rasterizer): checked primitives/s per worker and the speed-up")
    bench.add_argument("--scenes", type=_positive_int, metavar="N", help="the scene budget of --campaign (default 3000)")
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
    fuzz.add_argument("--timeout", type=_positive_seconds, default=60.0, help="the most seconds one rasterize call may take (the cap of its scaled limit; see README, Reliability)")
    fuzz.add_argument("--json", type=_path, metavar="FILE", help="also write the campaign as JSON")
    fuzz.add_argument("--out", type=_path, default="reports", help="folder for campaign.html (default reports/)")
    fuzz.add_argument("--merge", nargs="+", metavar="DIR", help="merge these campaigns' state folders into --state")
    fuzz.set_defaults(func=_fuzz)
    dif = sub.add_parser("diff", help="what changed between two runs' --json files (regressions, fixes, new, removed, metrics)")
    dif.add_argument("before", metavar="A.json")
    dif.add_argument("after", metavar="B.json")
    dif.add_argument("--out", type=_path, default="reports", help="folder for diff.html (default reports/)")
    dif.set_defaults(func=_diff)
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
