"""Helpers for users' own tests."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path
from typing import Any

from harness.checks import Result
from harness.contract.protocol import Rasterizer

__all__ = ["assert_conforms", "format_failures", "known_failures"]

BAD = ("fail", "error")


def format_failures(failures: list[Result], repro_dir: Path | None = None, spec: str | None = None) -> str:
    """Readable lines for failing results; minimal repros saved under ``repro_dir`` as
    ``<rasterizer>/<case>--<check>.json`` (as ``rastercheck run`` names them), each with
    the command that replays it (``spec``: the rasterizer's, when known)."""
    from harness.results.files import atomic_write_text, safe_name

    lines = []
    for r in failures:
        line = f"{r.rasterizer} {r.case} [{r.check}] {r.status}: {r.message}"
        payload = r.evidence.get("repro")
        if payload is not None and repro_dir is not None:
            path = repro_dir / safe_name(r.rasterizer) / f"{safe_name(r.case)}--{safe_name(r.check)}.json"
            atomic_write_text(path, json.dumps(payload, indent=1))
            line += f"\n    minimal repro: {path} (rastercheck replay {path} --rasterizer {spec or 'SPEC'})"
        lines.append(line)
    return "\n".join(lines)


def known_failures(results: list[Result], baseline: dict[str, dict[str, Any]]) -> list[Result]:
    """The failing or erroring results that ``baseline`` (:func:`harness.results.gate.load_baseline`)
    lists as failing or erroring already."""
    from harness.results.gate import key

    return [r for r in results if r.status in BAD and baseline.get(key(r), {}).get("status") in BAD]


def assert_conforms(rasterizer: Rasterizer | str, suite: str = "quick", seed: int = 0, *,
                    baseline: Path | str | None = None, **options: Any) -> list[Result]:
    """Run a suite on a rasterizer and raise AssertionError listing every failure or error
    (with paths to minimal repros); return the results when all pass or skip.

    Parameters
    ----------
    rasterizer : a rasterizer object or a spec (see :func:`harness.engine.registry.load`)
    suite : {"quick", "full"}
    seed : int
    baseline : path, optional
        A baseline of ``rastercheck gate --update-baseline``: the failures and errors it
        lists as such (its known failures) are let through; a known failure that passes
        now passes. Metrics are not compared (``rastercheck gate`` does that).
    **options
        Passed to :func:`harness.engine.runner.run_suite` (``cases``, ``isolate``, ``only``, ...).

    Use it in a test of your own::

        def test_my_rasterizer_conforms():
            assert_conforms("my_raster.py:MyRasterizer", baseline="rastercheck-baseline.json")
    """
    from harness.engine.runner import run_suite

    known: dict[str, dict[str, Any]] = {}
    if baseline is not None:
        from harness.results.gate import load_baseline

        known = load_baseline(baseline)  # first: a missing baseline fails before the run
    results = run_suite([rasterizer], suite=suite, seed=seed, **options)
    excused = {id(r) for r in known_failures(results, known)}
    failures = [r for r in results if r.status in BAD and id(r) not in excused]
    if failures:
        repro_dir = Path(tempfile.mkdtemp(prefix="rastercheck-repros-"))
        shown = format_failures(failures[:20], repro_dir, rasterizer if isinstance(rasterizer, str) else None)
        more = f"\n... and {len(failures) - 20} more" if len(failures) > 20 else ""
        also = f" ({len(excused)} known failures of the baseline let through)" if excused else ""
        raise AssertionError(f"{len(failures)} of {len(results)} checks failed{also}:\n{shown}{more}")
    return results
