"""The HTML report: an index with the summary matrix and convention cards, and one page
per rasterizer with each failure's pictures. Static, self-contained (images as data URIs),
rendered on the server side with Jinja2 autoescape, readable without JavaScript.

The pictures are drawn here, from each failure's drawing and evidence
(:func:`harness.pictures.draw`), once per failure shown; results read back from JSON
carry no drawing and show none."""

from __future__ import annotations

import json
import os
import platform
import time
from pathlib import Path
from typing import Any

import numba
import numpy as np
from jinja2 import Environment, PackageLoader, select_autoescape

import harness
from harness.checks import Result, check_names
from harness.checks import checks as registered_checks
from harness.files import atomic_write_text, safe_name
from harness.pictures import DIFF_LEGEND, HEAT_LEGEND, LEGEND, draw

__all__ = ["write_report", "write_comparison", "page_name"]

CAPTIONS = {"heatmap": "hit counts", "diff": "against the oracle", "crop": "crop: triangles over the pixel grid",
            "animation": "the sequence, offending pixels marked", "plot": "per-frame metrics"}


def _environment() -> Environment:
    return Environment(loader=PackageLoader("harness", "templates"), autoescape=select_autoescape(["html"]))


def page_name(rasterizer: str) -> str:
    return "rasterizer-" + safe_name(rasterizer) + ".html"


def _cell(results: list[Result]) -> dict[str, str]:
    counts = {s: sum(r.status == s for r in results) for s in ("pass", "fail", "error", "skip")}
    if not results:
        return {"status": "skip", "text": "—"}
    status = "error" if counts["error"] else "fail" if counts["fail"] else "pass" if counts["pass"] else "skip"
    return {"status": status, "text": " / ".join(str(counts[s]) for s in ("pass", "fail", "error", "skip"))}


def _problem(r: Result, index: int) -> dict[str, Any]:
    images = [(CAPTIONS[k], uri) for k, uri in draw(r).items()]  # none without a drawing
    hidden = ("traceback", "repro", "repro_path")
    text = json.dumps({k: v for k, v in r.evidence.items() if k not in hidden}, default=str)[:4000]
    if "traceback" in r.evidence:
        text += "\n" + r.evidence["traceback"]
    repro = r.evidence.get("repro", {})
    return {"case": r.case, "check": r.check, "status": r.status, "message": r.message, "anchor": f"failure-{index}",
            "images": images, "evidence_text": text if text.strip("{} \n") else "",
            "repro_path": r.evidence.get("repro_path"), "repro_size": len(repro.get("positions", [])),
            "repro_of": repro.get("original_triangles")}


FACTS = ("residual lies", "sample sweep", "culling", "zero area", "epsilon", "non-finite", "viewport edge", "watertight", "snapping", "vertex sweep")
KIND_ORDER = {"built-in": 0, "real library": 1, "plugin": 2}


def write_report(out_dir: Path, conventions: dict[str, str], results: list[Result], seed: int,
                 suite: str = "quick", seconds: float = 0.0, *,
                 fingerprints: dict[str, dict[str, Any]] | None = None,
                 declared: dict[str, str] | None = None, kinds: dict[str, str] | None = None) -> Path:
    """Write ``index.html``, one page per rasterizer and, given ``fingerprints`` (name ->
    :meth:`Fingerprint.to_dict` or ``{"error": text}``), ``fingerprints.html`` with every
    rasterizer side by side, into ``out_dir`` atomically."""
    fingerprints = fingerprints or {}
    out_dir = Path(out_dir)
    checks = [c for c in ("run", *check_names()) if any(r.check == c for r in results)]
    meta: dict[str, Any] = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "version": harness.__version__, "seed": seed,
        "suite": suite, "seconds": f"{seconds:.1f}", "python": platform.python_version(),
        "numpy": np.__version__, "numba": numba.__version__,
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}",
    }
    env = _environment()
    rows: list[dict[str, Any]] = []
    for name, convention in conventions.items():
        mine = [r for r in results if r.rasterizer == name]
        problems = [_problem(r, i) for i, r in enumerate(x for x in mine if x.status in ("fail", "error"))]
        row: dict[str, Any] = {
            "name": name, "convention": convention, "total": len(mine), "problems": problems, "page": page_name(name),
            "counts": {s: sum(r.status == s for r in mine) for s in ("pass", "fail", "error", "skip")},
            "cells": [_cell([r for r in mine if r.check == c]) for c in checks],
            "fingerprint": fingerprints.get(name), "kind": (kinds or {}).get(name, ""),
            "declared": (declared or {}).get(name, convention),
        }
        rows.append(row)
        html = env.get_template("rasterizer.html").render(
            row=row, meta=meta, heat_legend=HEAT_LEGEND.items(), diff_legend=DIFF_LEGEND.items(), motion_legend=LEGEND.items())
        atomic_write_text(out_dir / row["page"], html)
    if fingerprints:
        ordered = sorted(rows, key=lambda row: KIND_ORDER.get(row["kind"], 3))
        html = env.get_template("fingerprints.html").render(rows=ordered, checks=checks, meta=meta, facts=FACTS)
        atomic_write_text(out_dir / "fingerprints.html", html)
    captions = {c.name: c.caption for c in registered_checks()} | {"run": "the rasterizer answered: no crash, no hang"}
    html = env.get_template("index.html").render(rows=rows, checks=checks, captions=captions, meta=meta,
                                                 has_comparison=(out_dir / "compare.html").exists(),
                                                 has_fingerprints=bool(fingerprints))
    path = out_dir / "index.html"
    atomic_write_text(path, html)
    return path


def write_comparison(out_dir: Path, data: dict[str, Any], candidates: int, seed: int) -> Path:
    """Write ``compare.html`` (the comparison page) into ``out_dir`` atomically."""
    meta: dict[str, Any] = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "version": harness.__version__, "seed": seed, "suite": "lattice",
        "python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}",
    }
    html = _environment().get_template("compare.html").render(data=data, candidates=candidates, meta=meta)
    path = Path(out_dir) / "compare.html"
    atomic_write_text(path, html)
    return path
