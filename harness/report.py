"""The HTML report, rendered on the server side with Jinja2 (autoescape on)."""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

import harness
from harness.conformance import ConformanceResult
from harness.files import atomic_write_text

__all__ = ["write_report"]


def _environment() -> Environment:
    return Environment(loader=PackageLoader("harness", "templates"), autoescape=select_autoescape(["html"]))


def write_report(
    out_dir: Path, conventions: dict[str, str], results: list[ConformanceResult], seed: int
) -> Path:
    """Write ``index.html`` into ``out_dir`` atomically; return its path."""
    summary = []
    for name, convention in conventions.items():
        mine = [r for r in results if r.rasterizer == name]
        status = "pass"
        if any(r.status == "error" for r in mine):
            status = "error"
        elif any(r.status == "fail" for r in mine):
            status = "fail"
        elif mine and all(r.status == "skip" for r in mine):
            status = "skip"
        summary.append(
            {
                "name": name,
                "convention": convention,
                "status": status,
                "cases": len(mine),
                "passed": sum(r.status == "pass" for r in mine),
                "pixels": sum(r.expected_pixels for r in mine),
                "missing": sum(r.missing for r in mine),
                "extra": sum(r.extra for r in mine),
                "double_hits": sum(r.double_hits for r in mine),
                "errors": sum(r.status == "error" for r in mine),
                "results": mine,
            }
        )
    meta = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
        "version": harness.__version__,
        "seed": seed,
        "python": platform.python_version(),
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}",
    }
    html = _environment().get_template("index.html").render(summary=summary, meta=meta)
    path = Path(out_dir) / "index.html"
    atomic_write_text(path, html)
    return path
