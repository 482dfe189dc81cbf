"""``rastercheck run``: the suite on every rasterizer, its cases shared by a thread pool
(:func:`_execute`, which ``gate`` runs too), the outputs written and the verdict in the
terminal.

Exit codes: 0 everything passes, 1 a check fails or errors, 2 a usage or configuration error.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ThreadPoolExecutor, TimeoutError
from pathlib import Path
from typing import Any

from harness.cli.common import UsageError, _load_all, _loaded_specs, _quiet, _skipped

# what the last _execute selected: the cases (after --case and --shard) and the registered
# plugins that failed to load (each a usage error once the others' results are written)
_selected: list[Any] = []
_broken: list[str] = []


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

    rasterizers, problems = _load_all(args.rasterizer, getattr(args, "timeout", 120.0), tolerant=getattr(args, "tolerant", False))
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
                                                 call_timeout=args.timeout, report=lambda line: print(line, file=sys.stderr),
                                                 jobs=getattr(args, "jobs", 1))
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
