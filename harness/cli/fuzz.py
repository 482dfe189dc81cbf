"""``rastercheck fuzz``: a campaign (:func:`harness.campaign.coordinator.run_campaign`) until a
budget, with its progress line, summary and page; ``--merge`` joins campaigns' state folders.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import threading
import time
from pathlib import Path
from typing import Any, NamedTuple

from harness.cli.common import UsageError, _quiet

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
    from harness.report.campaign_page import campaign_json, write_campaign_page
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
    from harness.report.campaign_page import campaign_run

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
