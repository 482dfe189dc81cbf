"""Helpers for users' own tests."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path
from typing import Any

from harness.api import Rasterizer
from harness.checks import Result

__all__ = ["assert_conforms", "format_failures"]


def format_failures(failures: list[Result], repro_dir: Path | None = None) -> str:
    """Readable lines for failing results; minimal repros saved under ``repro_dir``."""
    lines = []
    for r in failures:
        line = f"{r.rasterizer} {r.case} [{r.check}] {r.status}: {r.message}"
        payload = r.evidence.get("repro")
        if payload is not None and repro_dir is not None:
            path = repro_dir / f"{r.rasterizer}--{r.case.replace('/', '_')}--{r.check}.json"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(payload, indent=1))
            line += f"\n    minimal repro: {path} (rastercheck replay {path} --rasterizer SPEC)"
        lines.append(line)
    return "\n".join(lines)


def assert_conforms(rasterizer: Rasterizer | str, suite: str = "quick", seed: int = 0, **options: Any) -> list[Result]:
    """Run a suite on a rasterizer and raise AssertionError listing every failure or error
    (with paths to minimal repros); return the results when all pass or skip.

    Use it in a test of your own::

        def test_my_rasterizer_conforms():
            assert_conforms("my_raster.py:MyRasterizer")
    """
    from harness.runner import run_suite

    results = run_suite([rasterizer], suite=suite, seed=seed, **options)
    failures = [r for r in results if r.status in ("fail", "error")]
    if failures:
        repro_dir = Path(tempfile.mkdtemp(prefix="rastercheck-repros-"))
        shown = format_failures(failures[:20], repro_dir)
        more = f"\n... and {len(failures) - 20} more" if len(failures) > 20 else ""
        raise AssertionError(f"{len(failures)} of {len(results)} checks failed:\n{shown}{more}")
    return results
