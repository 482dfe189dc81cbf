"""``rastercheck identify``: a rasterizer's convention fingerprinted from outside, and the
verdict on the convention it declares.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable
from typing import Any

from harness.cli.common import UsageError, _load_all


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
    cases = verdict_cases(fingerprint, seed, scene_kinds_of(rasterizer), declared.coverage_kind)
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
    from harness.contract.conventions import Convention
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
    words_of: Callable[[Convention], str] = \
        Convention.describe_lines if scene_kinds_of(rasterizer) == ("lines",) else Convention.describe
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
