"""The HTML report: an index with the summary matrix, convention cards, the rasterizers
that were skipped and why, and links to the other pages of the folder; one page per
rasterizer with its failures grouped by cause and signature as the campaign page and the
terminal group them (:func:`harness.diagnose.causes.by_cause`; a table of contents with counts, the
signatures' words whole, filters by check and status that are CSS ``:target`` rules), each with its pictures, its
minimal repro drawn, its evidence as tables and the command that replays it. Static,
self-contained (images as data URIs), rendered on the server side with Jinja2 autoescape,
without JavaScript.

The pictures are drawn here, from each failure's drawing and evidence
(:func:`harness.report.pictures.draw`), once per failure shown; results read back from JSON
carry no drawing and show none but their repro's (:func:`harness.report.pictures.draw_repro`,
without a convention).

Path scenes (:class:`harness.contract.scenes.PathScene`) are shown as triangles are, their crops and
repros drawing the paths under their fill rule with the winding number of each sample;
each rasterizer's card says which scene kinds it takes and which fill rules it honours
(and what identify saw it draw for each rule, and its path convention), and the index
lists the rasterizers that take paths in a table of polygon fillers with their failures
on path cases.

Line scenes (:class:`harness.contract.scenes.LineScene`) likewise: their crops and repros draw the
segments over the pixel grid (:mod:`harness.report.pictures`), each card says the line rule a
rasterizer declares (:meth:`harness.contract.conventions.Convention.describe_lines`) and the one
identify found, and the index lists the rasterizers that take lines in a table of line
drawers: the rule, the results on line cases, and a column per check that judges lines
(those of the registry that apply to a line case, and any with results on one) with the
failures linked, each with its minimal repro.

The campaign page is :mod:`harness.report.campaign_page`.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import re
import shlex
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypedDict

import numba
import numpy as np
from jinja2 import Environment, PackageLoader, select_autoescape

import harness
from harness.checks import EVIDENCE_LIMIT, Check, Result, check_names
from harness.checks import checks as registered_checks
from harness.checks.records import figures
from harness.contract.case import Case
from harness.contract.protocol import convention_for, fill_rules_of, scene_kinds_of
from harness.contract.scenes import LineScene, PathScene
from harness.diagnose.causes import SIGNATURE, by_cause
from harness.kinds import KINDS, LINES, PATHS, PrimitiveKind
from harness.report.pictures import (
    ALPHA_LEGEND,
    CROP_LEGEND,
    DIFF_LEGEND,
    HEAT_LEGEND,
    LEGEND,
    LINE_LEGEND,
    PATH_LEGEND,
    SAMPLE_LEGEND,
    draw,
    draw_repro,
    numbered_path,
    numbered_segment,
    svg_pattern,
)
from harness.results.files import atomic_write_text, safe_name
from harness.results.output import call_failures, call_failures_text

if TYPE_CHECKING:
    pass


__all__ = ["write_report", "write_comparison", "link_pages", "page_name", "evidence_table", "capabilities",
           "on_paths", "on_lines", "caption", "line_checks", "CAMPAIGN_PAGE"]

CAMPAIGN_PAGE = "campaign.html"  # written by harness.report.campaign_page, linked from the index

CAPTIONS = {"heatmap": "hit counts", "diff": "against the oracle", "crop": "crop: triangles over the pixel grid",
            "animation": "the sequence, offending pixels marked", "plot": "per-frame metrics",
            "alpha error": "alpha minus the oracle's, per pixel (the worst triangle there)",
            "alpha sum": "sum of the pieces' alphas minus 1, inside the partition (full colour: one level)",
            "samples": ("crop: what the rasterizer drew (left) beside what the convention says (right), offending pixels "
                        "outlined; each sample of the pattern in each pixel, a dot where covered, a ring where not, ringed "
                        "red where the two differ; anti-aliased pixels shaded by their alpha")}


def caption(key: str, r: Result) -> str:
    """The caption of picture ``key`` of failure ``r``: :data:`CAPTIONS`'s, but for a path
    scene's crop, which says the fill rule and whose winding numbers it writes, and a line
    scene's, which says the line rule and the segment drawn thick."""
    scene = getattr(r.drawing.case, "scene", None) if r.drawing is not None else None
    if key != "crop" or scene is None or scene.kind not in _CROP_CAPTIONS:
        return CAPTIONS[key]
    return _CROP_CAPTIONS[scene.kind](r, scene)


def _line_crop_caption(r: Result, scene: LineScene) -> str:
    convention = r.drawing.convention if r.drawing is not None else None
    rule = f" ({convention.describe_lines()})" if convention is not None else " (no convention known)"
    segment = numbered_segment(r)
    thick = f"; segment {segment} thick" if segment is not None else ""
    return (f"crop: the segments over the pixel grid{rule}, each pixel coloured as against the oracle, "
            f"segment by segment{thick}")


def _path_crop_caption(r: Result, scene: PathScene) -> str:
    path = numbered_path(r)
    convention = r.drawing.convention if r.drawing is not None else None
    at = ("its centre (no convention known)" if convention is None else
          "its first sample" if convention.samples is not None else "its sample")
    numbers = (f"; in each pixel the winding number of {at} around path {path} (bold where the rule fills it)"
               if path is not None else "; no path there to number")
    return f"crop: the paths over the pixel grid under the {scene.fill_rule} rule{numbers}"


# The crops whose caption says more than CAPTIONS's, per scene kind (the presentation's own
# table, keyed by harness.kinds' names).
_CROP_CAPTIONS: dict[str, Callable[[Result, Any], str]] = {"lines": _line_crop_caption, "paths": _path_crop_caption}


def _on(r: Result, kind: PrimitiveKind[Any], family_prefix: str) -> bool:
    """Whether a result is on a scene of ``kind``: its drawing's scene is one, its repro
    holds its primitives, or (read back from JSON) its case family is the kind's name or
    starts with ``family_prefix``."""
    scene = getattr(r.drawing.case, "scene", None) if r.drawing is not None else None
    if scene is not None:
        return bool(scene.kind == kind.name)
    repro = r.evidence.get("repro")
    if isinstance(repro, dict) and any(k.json_key in repro for k in KINDS.values()):
        return kind.json_key in repro
    family = r.case.split("/", 1)[0]
    return family == kind.name or family.startswith(family_prefix)


def on_paths(r: Result) -> bool:
    """Whether a result is on a path scene: its drawing's scene is one, its repro holds
    paths, or (read back from JSON) its case family is ``paths`` or ``path-...``."""
    return _on(r, PATHS, "path-")


def on_lines(r: Result) -> bool:
    """Whether a result is on a line scene: its drawing's scene is one, its repro holds
    lines, or (read back from JSON) its case family is ``lines`` or ``line-...``."""
    return _on(r, LINES, "line-")


# A line case of each form a line check may look for: a strip with joints, a closed
# polyline, a lone segment; on the 1/2 px lattice.
_LINE_PROBE = Case("lines/probe", LineScene.from_strips(8, 8, [[[0.5, 0.5], [6.5, 2.5], [6.5, 7.5]],
                                                                [[1.0, 1.0], [5.0, 1.0], [5.0, 5.0], [1.0, 1.0]],
                                                                [[0.0, 4.0], [3.0, 4.0]]]), lattice=True)


def _judges_lines(check: Check) -> bool:
    try:
        return bool(check.applies(_LINE_PROBE))
    except Exception:  # noqa: BLE001 - a check that cannot even look at a line case does not judge lines
        return False


def line_checks(results: list[Result] | None = None) -> list[str]:
    """The checks that judge lines, in registry order: those registered that apply to a
    line case (single-sample: lines have no other coverage), and any other that has a
    result on a line case among ``results`` (``run`` first, when one crashed)."""
    seen = {r.check for r in results or () if on_lines(r)}
    registered = [c.name for c in registered_checks(coverage_kind="single") if _judges_lines(c)]
    order = ["run", *check_names()]
    named = [c for c in order if c in registered or c in seen]
    return named + sorted(seen - set(named))


class Capabilities(TypedDict):
    """What :func:`capabilities` tells :func:`write_report` (and
    :func:`harness.results.output.write_json`) of each rasterizer, by name."""

    scene_kinds: dict[str, tuple[str, ...]]
    fill_rules: dict[str, tuple[str, ...]]
    line_rules: dict[str, str]
    facets: dict[str, dict[str, str]]


def capabilities(rasterizers: list[Any]) -> Capabilities:
    """What :func:`write_report` is told of each rasterizer's scene kinds, fill rules and
    line rule: ``{"scene_kinds": name -> kinds, "fill_rules": name -> rules, "line_rules":
    name -> rule}`` (the fill rules of the path-taking ones only; the line rule, in words
    (:meth:`Convention.describe_lines`), of the line-taking ones with a convention), read
    with :func:`harness.contract.protocol.scene_kinds_of`, :func:`harness.contract.protocol.fill_rules_of` and
    :func:`harness.contract.protocol.convention_for`; pass it on as ``write_report(..., **capabilities(rs))``.
    ``facets``: name -> the columns of the conventions table (:meth:`Convention.facets`) of the
    convention each one is judged by (declared, or identified), for those that have one."""
    kinds = {r.name: scene_kinds_of(r) for r in rasterizers}
    lines: dict[str, str] = {}
    for r in rasterizers:
        convention = convention_for(r, _LINE_PROBE.scene) if "lines" in kinds[r.name] else None
        if convention is not None:
            lines[r.name] = convention.describe_lines()
    return {"scene_kinds": kinds, "fill_rules": {r.name: fill_rules_of(r) for r in rasterizers if "paths" in kinds[r.name]},
            "line_rules": lines,
            "facets": {r.name: r.convention.facets() for r in rasterizers if getattr(r, "convention", None) is not None}}


def page_meta(suite: str, seed: Any, seconds: float | None = None) -> dict[str, Any]:
    """What every page's footer says: when, by which version, on what machine."""
    meta: dict[str, Any] = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "version": harness.__version__, "seed": seed, "suite": suite,
        "python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}",
    }
    if seconds is not None:
        meta["seconds"] = f"{seconds:.1f}"
    return meta


@functools.cache
def _environment() -> Environment:
    """The templates' one environment: each template is compiled once per process (every
    page of a report, every campaign page written again, rendered from the same one)."""
    return Environment(loader=PackageLoader("harness.report", "templates"), autoescape=select_autoescape(["html"]))


def page_name(rasterizer: str) -> str:
    return "rasterizer-" + safe_name(rasterizer) + ".html"


def _cell(results: list[Result]) -> dict[str, str]:
    counts = {s: sum(r.status == s for r in results) for s in ("pass", "fail", "error", "skip")}
    if not results:
        return {"status": "skip", "text": "—"}
    status = "error" if counts["error"] else "fail" if counts["fail"] else "pass" if counts["pass"] else "skip"
    return {"status": status, "text": " / ".join(str(counts[s]) for s in ("pass", "fail", "error", "skip"))}


ROWS_SHOWN = 50  # rows of a table (items of a list) shown; the rest are counted
INLINE_ITEMS = 8  # items of a list inside a table cell
HIDDEN = ("traceback", "repro", "repro_path", SIGNATURE)


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _compact(value: Any, items: int = INLINE_ITEMS) -> str:
    """A value in one line, whole: lists show their first ``items`` entries and count the
    rest, nothing is cut inside an entry."""
    value = _plain(value)
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_compact(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        shown = ", ".join(_compact(v) for v in value[:items])
        more = len(value) - items
        return "[" + shown + (f", … {more} more" if more > 0 else "") + "]"
    return str(value)


def evidence_table(value: Any, depth: int = 0) -> dict[str, Any]:
    """Evidence as nested tables for the page: a dict as key/value rows (``kind`` "pairs"),
    a list of dicts as a table with one column per key, its first :data:`ROWS_SHOWN` rows
    shown and the rest counted ("table"), anything else as one compact line ("text").
    A list of the evidence itself (``depth`` 1) as long as checks keep at most
    (:data:`~harness.checks.EVIDENCE_LIMIT`) is ``capped`` at that: there may be more.

    >>> evidence_table({"moved": 3})
    {'kind': 'pairs', 'rows': [('moved', {'kind': 'text', 'text': '3', 'capped': 0})]}
    """
    value = _plain(value)
    capped = EVIDENCE_LIMIT if depth == 1 and isinstance(value, (list, tuple)) and len(value) == EVIDENCE_LIMIT else 0
    if isinstance(value, dict):
        return {"kind": "pairs", "rows": [(str(k), evidence_table(v, depth + 1)) for k, v in value.items()]}
    if isinstance(value, (list, tuple)) and value and all(isinstance(v, dict) for v in value):
        columns = list(dict.fromkeys(str(k) for row in value for k in row))
        rows = [[_compact(row[c]) if c in row else "" for c in columns] for row in value[:ROWS_SHOWN]]
        return {"kind": "table", "columns": columns, "rows": rows, "more": len(value) - len(rows), "capped": capped}
    if isinstance(value, (list, tuple)):
        return {"kind": "text", "text": _compact(value, ROWS_SHOWN), "capped": capped}
    return {"kind": "text", "text": _compact(value), "capped": 0}


def _rows(node: dict[str, Any]) -> int:
    """How many table rows a node of :func:`evidence_table` takes."""
    if node["kind"] == "pairs":
        return sum(max(1, _rows(value)) for _, value in node["rows"])
    return len(node["rows"]) + 1 if node["kind"] == "table" else 1


def _drawn(r: Result, drawer: Any, fallback: Any, evidence: dict[str, Any], what: str) -> Any:
    """``drawer(r)``, or ``fallback`` with the reason in ``evidence`` when the picture cannot
    be drawn: a picture costs only itself, the report (and the run behind it) is written."""
    try:
        return drawer(r)
    except Exception as exc:  # noqa: BLE001 - any drawing bug: say it on the page, keep the report
        evidence[f"{what} not drawn"] = f"{type(exc).__name__}: {exc}"
        return fallback


def _problem(r: Result, index: int, spec: str) -> dict[str, Any]:
    evidence = {k: v for k, v in r.evidence.items() if k not in HIDDEN}
    images = [(caption(k, r), uri) for k, uri in _drawn(r, draw, {}, evidence, "picture").items()]  # none without a drawing
    repro = r.evidence.get("repro")
    repro = repro if isinstance(repro, dict) else {}
    path = r.evidence.get("repro_path")
    drawn = _drawn(r, draw_repro, None, evidence, "repro picture")
    table = evidence_table(evidence) if evidence else None
    lines = on_lines(r)
    if "lines" in repro:  # its segments: a strip of K vertices holds K - 1
        strips = repro["lines"]
        size = sum(len(s) - 1 for s in strips if isinstance(s, list)) if isinstance(strips, list) else 0
    else:
        shapes = repro.get("paths") if "paths" in repro else repro.get("positions")
        size = len(shapes) if isinstance(shapes, list) else 0
    paths = on_paths(r)
    return {"case": r.case, "check": r.check, "status": r.status, "message": r.message, "anchor": f"failure-{index}",
            "images": images, "evidence": table, "evidence_open": table is not None and _rows(table) <= 16,
            "evidence_keys": list(evidence), "traceback": r.evidence.get("traceback"),
            "repro_picture": drawn[0] if drawn else None, "repro_caption": drawn[1] if drawn else None,
            "repro_path": path, "repro_size": size, "repro_of": repro.get("original_triangles"),
            "noun": "path" if paths else "segment" if lines else "triangle", "paths": paths, "lines": lines,
            "replay": f"rastercheck replay {shlex.quote(str(path))} --rasterizer {shlex.quote(spec)}" if path else None}


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_-]+", "-", text).strip("-") or "x"


def _causes(results: list[Result], problems: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The failures of ``results`` (one rasterizer's; ``problems`` are their failing and
    erroring ones, in order) by cause and signature, as the terminal and the campaign page
    group them (:func:`harness.diagnose.causes.by_cause`): the largest cause first, within it each
    signature (one check, one status) with its words whole and an anchor."""
    problem_of = {id(r): p for r, p in zip((x for x in results if x.status in ("fail", "error")), problems)}
    out: list[dict[str, Any]] = []
    groups = 0
    for k, found in enumerate(by_cause(results)):
        signatures: list[dict[str, Any]] = []
        for group in found.signatures:
            signatures.append({"id": f"group-{groups}", "status": group.status, "check": group.signature.check,
                               "slug": _slug(group.signature.check), "key": group.signature.key, "describe": group.describe(),
                               "count": group.count, "problems": [problem_of[id(r)] for r in group.results]})
            groups += 1
        out.append({"id": f"cause-{k}", "cause": found.cause, "count": found.count, "signatures": signatures,
                    "checks": list(dict.fromkeys(g["slug"] for g in signatures)),
                    "statuses": sorted({g["status"] for g in signatures})})
    return out


def _failing_checks(problems: list[dict[str, Any]], order: list[str]) -> list[dict[str, Any]]:
    """The checks with failing or erroring results (in ``order``): each with its count and statuses."""
    out = []
    for check in sorted({p["check"] for p in problems}, key=lambda c: (order.index(c) if c in order else len(order), c)):
        mine = [p for p in problems if p["check"] == check]
        out.append({"check": check, "slug": _slug(check), "count": len(mine), "statuses": sorted({p["status"] for p in mine})})
    return out


def _filters(sections: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The page's filters (CSS :target rules): by check, by status, and by check and
    status where a check has failures of both statuses."""
    statuses = sorted({s for section in sections for s in section["statuses"]})
    out = [{"id": f"only-{section['slug']}", "check": section["slug"], "status": None, "label": section["check"]}
           for section in sections]
    out += [{"id": f"only-status-{s}", "check": None, "status": s, "label": s} for s in statuses]
    out += [{"id": f"only-{section['slug']}-{s}", "check": section["slug"], "status": s, "label": f"{section['check']} · {s}"}
            for section in sections if len(section["statuses"]) > 1 for s in section["statuses"]]
    return out


FACTS = ("coverage", "model", "levels", "area error", "sweeps", "pattern", "residual lies", "sample sweep", "culling",
         "zero area", "epsilon", "non-finite", "viewport edge", "watertight", "snapping", "vertex sweep",
         "fill rules", "paths", "real paths", "calls")
KIND_ORDER = {"built-in": 0, "real library": 1, "plugin": 2}


def write_report(out_dir: Path, conventions: dict[str, str], results: list[Result], seed: int,
                 suite: str = "quick", seconds: float = 0.0, *,
                 fingerprints: dict[str, dict[str, Any]] | None = None,
                 declared: dict[str, str] | None = None, kinds: dict[str, str] | None = None,
                 specs: dict[str, str] | None = None, skipped: dict[str, str] | None = None,
                 patterns: dict[str, tuple[tuple[float, float], ...]] | None = None,
                 scene_kinds: dict[str, tuple[str, ...]] | None = None,
                 fill_rules: dict[str, tuple[str, ...]] | None = None,
                 line_rules: dict[str, str] | None = None,
                 facets: dict[str, dict[str, str]] | None = None) -> Path:
    """Write ``index.html``, one page per rasterizer and, given ``fingerprints`` (name ->
    :meth:`Fingerprint.to_dict` or ``{"error": text}``), ``fingerprints.html`` with every
    rasterizer side by side, into ``out_dir`` atomically.

    ``specs`` (name -> the spec it was loaded from, as given on the command line) is what
    the replay commands quote (the name by default); ``skipped`` (spec -> why) lists on the
    index the rasterizers that could not be loaded; ``patterns`` (name -> sample offsets)
    draws the multisample pattern a rasterizer declares on its page. ``scene_kinds`` and
    ``fill_rules`` (name -> what :func:`harness.contract.protocol.scene_kinds_of` and
    :func:`harness.contract.protocol.fill_rules_of` say: :func:`capabilities`) are what the cards and
    the table of polygon fillers say a rasterizer takes; without them the scene kinds are
    read from its results (and a fingerprint that saw it fill paths or draw lines).
    ``line_rules`` (name -> the line rule in words, :func:`capabilities`) is what the cards
    and the table of line drawers say a line-taking rasterizer's lines are checked against.
    ``facets`` (name -> :meth:`Convention.facets`, :func:`capabilities`) fills the conventions
    table: each rasterizer's coverage, sample point and ties, input precision, snapping,
    culling and line rule in columns, beside what identify found."""
    fingerprints = fingerprints or {}
    out_dir = Path(out_dir)
    checks = [c for c in ("run", *check_names()) if any(r.check == c for r in results)]
    judging_lines = line_checks(results)
    meta = page_meta(suite, seed, seconds)
    env = _environment()
    calls = call_failures(results)  # the cases whose call timed out, failed or was asked again
    rows: list[dict[str, Any]] = []
    for name, convention in conventions.items():
        mine = [r for r in results if r.rasterizer == name]
        spec = (specs or {}).get(name, name)
        problems = [_problem(r, i, spec) for i, r in enumerate(x for x in mine if x.status in ("fail", "error"))]
        sections = _failing_checks(problems, checks)
        row: dict[str, Any] = {
            "name": name, "convention": convention, "total": len(mine), "problems": problems, "page": page_name(name),
            "counts": {s: sum(r.status == s for r in mine) for s in ("pass", "fail", "error", "skip")},
            "cells": [_cell([r for r in mine if r.check == c]) for c in checks],
            "fingerprint": fingerprints.get(name), "kind": (kinds or {}).get(name, ""),
            "declared": (declared or {}).get(name, convention), "sections": sections, "causes": _causes(mine, problems),
            "filters": _filters(sections),
            "figures": coverage_figures(mine),
            "pattern": svg_pattern((patterns or {})[name]) if (patterns or {}).get(name) else None,
            "calls": call_failures_text(calls[name]) if name in calls else "",
        }
        row["facets"] = (facets or {}).get(name)
        row.update(_scene_card(name, mine, problems, fingerprints.get(name), scene_kinds, fill_rules))
        row.update(_line_card(name, mine, problems, fingerprints.get(name), judging_lines, line_rules, row["declared"]))
        rows.append(row)
        html = env.get_template("rasterizer.html").render(
            row=row, meta=meta, heat_legend=HEAT_LEGEND.items(), diff_legend=DIFF_LEGEND.items(), motion_legend=LEGEND.items(),
            crop_legend=CROP_LEGEND.items(), alpha_legend=ALPHA_LEGEND.items(), path_legend=PATH_LEGEND.items(),
            line_legend=LINE_LEGEND.items(), sample_legend=SAMPLE_LEGEND.items())
        atomic_write_text(out_dir / row["page"], html)
    if fingerprints:
        for row in rows:
            row.update(_fingerprint_card(out_dir, row["name"], fingerprints.get(row["name"]), row["declared"],
                                         (patterns or {}).get(row["name"])))
        ordered = sorted(rows, key=lambda row: KIND_ORDER.get(row["kind"], 3))
        facts = [*FACTS, *sorted({k for f in fingerprints.values() if isinstance(f, dict) and isinstance(f.get("facts"), dict)
                                  for k in f["facts"] if "line" in k and k not in FACTS})]
        html = env.get_template("fingerprints.html").render(rows=ordered, checks=checks, meta=meta, facts=facts)
        atomic_write_text(out_dir / "fingerprints.html", html)
    captions = {c.name: c.caption for c in registered_checks()} | {"run": "the rasterizer answered: no crash, no hang"}
    html = env.get_template("index.html").render(rows=rows, checks=checks, captions=captions, meta=meta,
                                                 pages=_pages(out_dir, bool(fingerprints)), skipped=skipped or {},
                                                 fillers=[row for row in rows if "paths" in row["scene_kinds"]],
                                                 drawers=[row for row in rows if "lines" in row["scene_kinds"]],
                                                 line_checks=judging_lines, facet_names=FACET_NAMES)
    path = out_dir / "index.html"
    atomic_write_text(path, html)
    return path


# the conventions table's columns (:meth:`Convention.facets`), in order, with their headings
FACET_NAMES = {"coverage": "coverage", "sample": "sample point and ties", "input": "input precision",
               "snapping": "snapping", "culling": "culling", "lines": "line rule"}

PATH_LINKS = 10  # failures linked per check in the table of polygon fillers; the rest are counted


def _fingerprint_card(out_dir: Path, name: str, fingerprint: Any, declared: str,
                      pattern: tuple[tuple[float, float], ...] | None) -> dict[str, Any]:
    """The fingerprint page's fields of one rasterizer: ``defects``, every scene a probe of
    identify saw a defect on (the suite's case, the check, what is wrong, the offending
    pixels and the primitives blamed) with its minimal repro written to
    ``repros/<rasterizer>/identify--<probe>--<k>.json``; ``confirmed``, whether the declared
    convention is the one identified exactly (sample offsets compared one by one: the words
    name a pattern in short); ``offsets``, the identified sample offsets when the words do
    not spell them (an irregular pattern), for the page to list."""
    from harness.contract.samples import describe_pattern
    from harness.identify.fingerprint import repro_size

    if not isinstance(fingerprint, dict) or fingerprint.get("error"):
        return {"defects": [], "confirmed": False, "offsets": None}
    defects = []
    for label, found in (fingerprint.get("defects") or {}).items():
        for k, d in enumerate(found):
            entry = {"probe": label, "case": d["case"], "check": d["check"], "message": d["message"],
                     "pixels": [f"{b['kind']} at ({b['pixel'][0]}, {b['pixel'][1]}), "
                                f"{' and '.join(str(p) for p in b.get('paths', b.get('triangles', [])))} on one edge"
                                for b in d.get("evidence", {}).get("blame", [])][:EVIDENCE_LIMIT],
                     "repro_path": None, "repro_size": None, "repro_of": None}
            repro = d.get("repro")
            if isinstance(repro, dict):
                path = out_dir / "repros" / safe_name(name) / f"identify--{safe_name(label)}--{k}.json"
                atomic_write_text(path, json.dumps(repro, indent=1))
                entry.update(repro_path=str(path.relative_to(out_dir)), repro_size=repro_size(repro),
                             repro_of=repro.get("original_triangles"))
            defects.append(entry)
    samples = fingerprint.get("samples")
    same_samples = (pattern is None and samples is None) or (
        pattern is not None and samples is not None and [list(o) for o in pattern] == [list(o) for o in samples])
    offsets = None
    if samples and "listed in" in describe_pattern([tuple(o) for o in samples]):  # the words do not spell them
        offsets = [f"({x:g}, {y:g})" for x, y in samples]
    return {"defects": defects, "offsets": offsets,
            "confirmed": bool(declared == fingerprint.get("convention") and fingerprint.get("exact") and same_samples)}


def _fingerprint_field(fingerprint: Any, name: str) -> Any:
    """A field of a fingerprint given as :meth:`Fingerprint.to_dict`'s dict or as the
    object (None when it has no such field: identify may not record it)."""
    if isinstance(fingerprint, dict):
        return fingerprint.get(name)
    return getattr(fingerprint, name, None)


def _path_convention(fingerprint: Any) -> dict[str, Any] | None:
    """The path convention identify found, as ``{"text", "exact", "residual", "pixels",
    "same_as_triangles"}``, or None when it recorded none."""
    found = _fingerprint_field(fingerprint, "path_convention")
    if found is None:
        return None
    if isinstance(found, dict):
        return {"text": found.get("convention", "—"), "exact": bool(found.get("exact")), "residual": found.get("residual"),
                "pixels": found.get("pixels"), "same_as_triangles": found.get("same_as_triangles")}
    fit = getattr(fingerprint, "path_fit", None)
    describe = getattr(found, "describe", None)
    return {"text": describe() if callable(describe) else str(found), "exact": bool(getattr(fit, "exact", False)),
            "residual": getattr(fit, "residual", None), "pixels": getattr(fit, "pixels", None),
            "same_as_triangles": getattr(fit, "same_as_triangles", None)}


def _scene_card(name: str, mine: list[Result], problems: list[dict[str, Any]], fingerprint: Any,
                scene_kinds: dict[str, tuple[str, ...]] | None, fill_rules: dict[str, tuple[str, ...]] | None) -> dict[str, Any]:
    """What a rasterizer's card and the table of polygon fillers say of its scene kinds:
    the kinds it takes (declared, else read from its results), the fill rules it honours,
    what identify saw it draw for each rule asked and the path convention it found, and
    its failures on path cases by check (each linked, with its repro file)."""
    seen_fills = _fingerprint_field(fingerprint, "fill_rules") if fingerprint is not None else None
    if scene_kinds is not None and name in scene_kinds:
        kinds, said = list(scene_kinds[name]), "declared"
    else:
        paths = any(on_paths(r) for r in mine) or bool(seen_fills)
        lines = any(on_lines(r) for r in mine) or (fingerprint is not None and _line_identified(fingerprint) is not None)
        triangles = any(not on_paths(r) and not on_lines(r) for r in mine) or not (paths or lines)
        kinds, said = ([k for k, taken in (("triangles", triangles), ("paths", paths), ("lines", lines)) if taken],
                       "seen in its results")
    rules = list(fill_rules[name]) if fill_rules is not None and name in fill_rules else None
    on = [r for r in mine if on_paths(r)]
    by_check: dict[str, list[dict[str, Any]]] = {}
    for p in problems:
        if p["paths"]:
            by_check.setdefault(p["check"], []).append(p)
    path_checks = [{"check": check, "count": len(found), "failures": found[:PATH_LINKS], "more": len(found) - PATH_LINKS}
                   for check, found in by_check.items()]
    return {"scene_kinds": kinds, "scene_kinds_said": said, "fill_rules": rules,
            "fill_rules_seen": dict(seen_fills) if isinstance(seen_fills, dict) else None,
            "path_convention": _path_convention(fingerprint) if fingerprint is not None else None,
            "path_counts": {s: sum(r.status == s for r in on) for s in ("pass", "fail", "error", "skip")},
            "path_checks": path_checks}


LINE_LINKS = 3  # failures linked per check in the table of line drawers; the rest are counted


def _line_identified(fingerprint: Any) -> dict[str, Any] | None:
    """What identify found of a rasterizer's lines, as ``{"text", "exact", "residual",
    "pixels", "facts"}``, or None when it recorded nothing of lines. Read defensively:
    ``line_convention`` or ``line_rule`` as words, a dict (``convention``/``rule``,
    ``exact``, ``residual``, ``pixels``) or an object with ``describe_lines``/``describe``;
    every other ``line_*`` field of a fingerprint dict becomes a fact."""
    found = None
    for field in ("line_convention", "line_rule"):
        found = _fingerprint_field(fingerprint, field)
        if found is not None:
            break
    others = {k: v for k, v in fingerprint.items() if isinstance(k, str) and k.startswith("line_")
              and k not in ("line_convention", "line_rule") and v is not None} if isinstance(fingerprint, dict) else {}
    if found is None and not others:
        return None
    exact = others.pop("line_exact", None)
    residual = others.pop("line_residual", None)
    pixels = others.pop("line_pixels", None)
    facts = []
    if isinstance(found, dict):
        text = found.get("convention") or found.get("rule") or found.get("text") or _compact(found)
        exact = found.get("exact", exact)
        residual, pixels = found.get("residual", residual), found.get("pixels", pixels)
        same = found.get("same_as_triangles")
        if same is not None:
            facts.append(("the same as for triangles", "yes" if same else "no"))
        if found.get("differences"):
            facts.append(("differs from triangles in", _compact(found["differences"])))
        if found.get("wide_lines"):
            facts.append(("wide lines", str(found["wide_lines"])))
    elif found is None or isinstance(found, str):
        text = found or "—"
    else:
        describe = getattr(found, "describe_lines", None) or getattr(found, "describe", None)
        text = describe() if callable(describe) else str(found)
        fit = getattr(fingerprint, "line_fit", None)
        exact, residual, pixels = (getattr(fit, "exact", None), getattr(fit, "residual", None), getattr(fit, "pixels", None))
    facts += [(k.removeprefix("line_").replace("_", " "), _compact(v)) for k, v in others.items()]
    return {"text": str(text), "exact": None if exact is None else bool(exact), "residual": residual, "pixels": pixels,
            "facts": facts}


def _line_card(name: str, mine: list[Result], problems: list[dict[str, Any]], fingerprint: Any, judging: list[str],
               line_rules: dict[str, str] | None, declared: str) -> dict[str, Any]:
    """What a rasterizer's card and the table of line drawers say of its lines: the rule
    its lines are checked against (and whether it declared it), what identify found, its
    results on line cases, and per check that judges lines (``judging``) the counts and
    the failures, each linked, with its repro file."""
    on = [r for r in mine if on_lines(r)]
    rule = (line_rules or {}).get(name)
    cells = []
    for check in judging:
        results = [r for r in on if r.check == check]
        failures = [p for p in problems if p["lines"] and p["check"] == check]
        cell = _cell(results)
        cells.append({**cell, "check": check, "failures": failures[:LINE_LINKS], "more": len(failures) - LINE_LINKS,
                      "count": len(failures)})
    return {"line_rule": rule, "line_rule_declared": declared != "none declared",
            "line_identified": _line_identified(fingerprint) if fingerprint is not None else None,
            "line_counts": {s: sum(r.status == s for r in on) for s in ("pass", "fail", "error", "skip")},
            "line_cells": cells}


def coverage_figures(results: list[Result]) -> list[tuple[str, str]]:
    """The anti-aliasing and multisample figures of one rasterizer's results, (label,
    value) for each figure some result measured, combined over cases: the figures the
    checks declare (:attr:`Check.figures`), in registry order."""
    out = []
    for check, figure in figures():
        metric, how, label = figure.metric, figure.how, figure.label
        values = [r.metrics[metric] for r in results if r.check == check and metric in r.metrics]
        if not values:
            continue
        value = max(values) if how == "max" else sum(values) if how == "sum" else sum(values) / len(values)
        out.append((f"{check}: {label}", f"{value:.4g}" + ("" if how != "mean" else f" (over {len(values)} cases)")))
    return out


PAGES_START, PAGES_END = "<!-- pages -->", "<!-- /pages -->"


def _pages(out_dir: Path, fingerprints: bool) -> dict[str, bool]:
    """Which other pages the index links: fingerprints.html when this run wrote it,
    compare.html (``rastercheck compare``), diff.html (``rastercheck diff``) and
    campaign.html (``rastercheck fuzz``) whenever they are in the folder."""
    return {"fingerprints": fingerprints, "comparison": (out_dir / "compare.html").exists(),
            "diff": (out_dir / "diff.html").exists(), "campaign": (out_dir / CAMPAIGN_PAGE).exists()}


def link_pages(out_dir: Path) -> None:
    """Bring the links of ``out_dir/index.html`` (if there is one) up to date with the pages
    now in the folder: a comparison or diff page written after the report is linked too."""
    path = Path(out_dir) / "index.html"
    try:
        html = path.read_text(encoding="utf-8")
    except OSError:
        return
    start, end = html.find(PAGES_START), html.find(PAGES_END)
    if start < 0 or end < start:
        return  # not an index this module wrote
    old = html[start:end]
    block = _environment().get_template("pages.html").render(
        pages=_pages(Path(out_dir), 'href="fingerprints.html"' in old))
    atomic_write_text(path, html[:start] + PAGES_START + block + html[end:])


def _pair_crops(comparisons: list[Any]) -> dict[str, list[tuple[str, str]]]:
    """Per pair ``"a · b"``: an SVG crop of each side around the first pixels where they
    differ (the triangles over the pixel grid, the differing pixels outlined)."""
    from harness.report.pictures import svg_crop, window_around

    out: dict[str, list[tuple[str, str]]] = {}
    for c in comparisons:
        if c.where is None:
            continue
        scene, a, b, pixels = c.where
        x, y = pixels[0]
        window = window_around(x, y, scene.width, scene.height, 12)
        out[f"{c.a} · {c.b}"] = [(f"{name}: where they differ (outlined)",
                                  svg_crop(scene.positions, cov, (0.5, 0.5), window, pixels))
                                 for name, cov in ((c.a, a), (c.b, b))]
    return out


def write_comparison(out_dir: Path, data: dict[str, Any], candidates: int, seed: int,
                     comparisons: list[Any] | None = None) -> Path:
    """Write ``compare.html`` (the comparison page) into ``out_dir`` atomically; with the
    ``comparisons`` themselves, each pair that differs is drawn where it first does."""
    meta = page_meta("lattice", seed)
    crops = _pair_crops(comparisons or [])
    html = _environment().get_template("compare.html").render(data=data, candidates=candidates, meta=meta, crops=crops)
    path = Path(out_dir) / "compare.html"
    atomic_write_text(path, html)
    link_pages(Path(out_dir))
    return path
