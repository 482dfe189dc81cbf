"""``rastercheck gate``: a run judged against a baseline (and known campaigns' findings): only a
regression fails (for CI).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from harness.cli.common import UsageError
from harness.cli.run import Interrupted, _execute, _interrupted, _write_outputs


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

