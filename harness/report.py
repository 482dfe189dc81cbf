"""The HTML report, rendered on the server side with Jinja2 (autoescape on)."""

from __future__ import annotations

import json
import os
import platform
import time
from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

import harness
from harness.checks import CHECKS, Result
from harness.files import atomic_write_text

__all__ = ["write_report"]


def _environment() -> Environment:
    return Environment(loader=PackageLoader("harness", "templates"), autoescape=select_autoescape(["html"]))


def _cell(results: list[Result]) -> dict[str, str]:
    counts = {s: sum(r.status == s for r in results) for s in ("pass", "fail", "error", "skip")}
    if not results:
        return {"status": "skip", "text": "—"}
    status = "error" if counts["error"] else "fail" if counts["fail"] else "pass" if counts["pass"] else "skip"
    return {"status": status, "text": " / ".join(str(counts[s]) for s in ("pass", "fail", "error", "skip"))}


def write_report(out_dir: Path, conventions: dict[str, str], results: list[Result], seed: int,
                 suite: str = "quick", seconds: float = 0.0) -> Path:
    """Write ``index.html`` into ``out_dir`` atomically; return its path."""
    checks = [c for c in ("run", *CHECKS) if any(r.check == c for r in results)]
    rows = []
    for name, convention in conventions.items():
        mine = [r for r in results if r.rasterizer == name]
        problems = [
            {**{k: getattr(r, k) for k in ("case", "check", "status", "message", "evidence")},
             "repro_path": r.evidence.get("repro_path"),
             "repro_size": len(r.evidence.get("repro", {}).get("positions", [])),
             "evidence_text": json.dumps({k: v for k, v in r.evidence.items() if k not in ("traceback", "repro", "repro_path")}, default=str)[:2000]
             + ("\n" + r.evidence["traceback"] if "traceback" in r.evidence else "")}
            for r in mine if r.status != "pass"
        ]
        rows.append({
            "name": name, "convention": convention, "total": len(mine), "problems": problems,
            "cells": [_cell([r for r in mine if r.check == c]) for c in checks],
        })
    meta = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "version": harness.__version__, "seed": seed,
        "suite": suite, "seconds": f"{seconds:.1f}", "python": platform.python_version(),
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}",
    }
    html = _environment().get_template("index.html").render(rows=rows, checks=checks, meta=meta)
    path = Path(out_dir) / "index.html"
    atomic_write_text(path, html)
    return path
