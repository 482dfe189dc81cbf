"""The campaign page (:func:`write_campaign_page`, ``campaign.html``) and the campaign's JSON
(:func:`campaign_json`): a campaign's state (:class:`harness.campaign.state.CampaignState`) --
what was searched and how fast, the findings over the scenes checked (an inline SVG,
:func:`findings_chart`), and one row per signature with its counts, first and last scene,
message, repro (drawn as the main report draws a repro, :mod:`harness.report.pages`) and
example scenes, each replayable from its three numbers.

Static, self-contained, rendered with the report's Jinja2 environment (autoescape), without
JavaScript.
"""

from __future__ import annotations

import os
import shlex
from pathlib import Path
from typing import TYPE_CHECKING, Any

from harness.checks import Result
from harness.contract.protocol import convention_for
from harness.report.pages import CAMPAIGN_PAGE, _environment, _slug, link_pages, page_meta
from harness.report.pictures import (
    CROP_LEGEND,
    LINE_LEGEND,
    PATH_LEGEND,
    SAMPLE_LEGEND,
    draw_repro,
)
from harness.results.files import atomic_write_text

__all__ = ["write_campaign_page", "campaign_json", "campaign_run", "findings_chart"]

if TYPE_CHECKING:
    from harness.campaign.state import CampaignState, ProgressEvent


CAMPAIGN_EXAMPLES = 8  # example scenes shown per signature (the state keeps up to 20)


def campaign_run(event: ProgressEvent | None) -> dict[str, Any] | None:
    """This run's figures from a campaign's last :class:`~harness.campaign.state.ProgressEvent`
    (None without one): scenes, primitives, seconds, rates and workers."""
    if event is None:
        return None
    return {"scenes": event.scenes, "primitives": event.primitives, "seconds": round(event.elapsed, 3),
            "scenes_per_second": round(event.scenes_per_second, 3),
            "primitives_per_second": round(event.primitives_per_second, 3), "workers": event.workers}


def _duration(seconds: float) -> str:
    """``2 h 05 min``, ``3 min 07 s``, ``12.3 s``.

    >>> _duration(12.345), _duration(187), _duration(7500)
    ('12.3 s', '3 min 07 s', '2 h 05 min')
    """
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, secs = divmod(int(round(seconds)), 60)
    if minutes < 60:
        return f"{minutes} min {secs:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


def _point_text(point: dict[str, Any] | list[Any] | tuple[Any, ...]) -> str:
    """``family/seed/index`` of a scene point (a state's ``first``/``last`` or an example)."""
    if isinstance(point, dict):
        return f"{point.get('family')}/{point.get('seed')}/{point.get('index')}"
    return "/".join(str(p) for p in point)


def _scenes_at(history: list[list[float]], at: float) -> float:
    """The campaign's scenes when its wall clock read ``at`` seconds: those of the first
    history point at or after it (the batch that found a signature is merged, and its point
    recorded, at the same reading)."""
    for when, scenes, _ in history:
        if when >= at:
            return float(scenes)
    return float(history[-1][1]) if history else 0.0


def findings_chart(state: CampaignState, width: int = 640, height: int = 220) -> str:
    """An inline SVG of the campaign's findings against the scenes checked, from its
    ``history``: the findings (cumulative, red, left scale) and the distinct signatures (a
    step each time one is first seen, blue, right scale). Empty without history."""
    history = [[float(a), float(n), float(k)] for a, n, k in state.history]
    if not history:
        return ""
    points = [[0.0, 0.0, 0.0], *history]
    firsts = sorted(_scenes_at(history, float(entry["first"].get("at", 0.0))) for entry in state.signatures.values()
                    if isinstance(entry.get("first"), dict))
    left, right, top, bottom = 56, 44, 14, 34
    plot_w, plot_h = width - left - right, height - top - bottom
    max_scenes = max(p[1] for p in points) or 1.0
    max_findings = max(p[2] for p in points) or 1.0
    max_signatures = max(len(firsts), 1)

    def x(scenes: float) -> float:
        return left + plot_w * scenes / max_scenes

    def y(value: float, top_value: float) -> float:
        return top + plot_h * (1.0 - value / top_value)

    found = " ".join(f"{x(n):.1f},{y(k, max_findings):.1f}" for _, n, k in points)
    steps = [f"{x(0):.1f},{y(0, max_signatures):.1f}"]
    for count, scenes in enumerate(firsts, 1):
        steps += [f"{x(scenes):.1f},{y(count - 1, max_signatures):.1f}", f"{x(scenes):.1f},{y(count, max_signatures):.1f}"]
    steps.append(f"{x(max_scenes):.1f},{y(len(firsts), max_signatures):.1f}")
    red, blue, grey = "#c0392b", "#1f5fa8", "#888"
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" '
        f'role="img" aria-label="findings and distinct signatures against the scenes checked">',
        f'<rect x="{left}" y="{top}" width="{plot_w}" height="{plot_h}" fill="white" stroke="{grey}"/>',
        f'<polyline points="{found}" fill="none" stroke="{red}" stroke-width="2"/>',
        f'<polyline points="{" ".join(steps)}" fill="none" stroke="{blue}" stroke-width="2" stroke-dasharray="5 3"/>',
        f'<text x="{left - 6}" y="{top + 10}" text-anchor="end" font-size="11" fill="{red}">{max_findings:,.0f}</text>',
        f'<text x="{left - 6}" y="{top + plot_h}" text-anchor="end" font-size="11" fill="{red}">0</text>',
        f'<text x="{width - right + 6}" y="{top + 10}" font-size="11" fill="{blue}">{max_signatures}</text>',
        f'<text x="{width - right + 6}" y="{top + plot_h}" font-size="11" fill="{blue}">0</text>',
        f'<text x="{left}" y="{height - 18}" font-size="11" fill="{grey}">0</text>',
        f'<text x="{left + plot_w}" y="{height - 18}" text-anchor="end" font-size="11" fill="{grey}">{max_scenes:,.0f}</text>',
        f'<text x="{left + plot_w / 2:.0f}" y="{height - 4}" text-anchor="middle" font-size="11" fill="{grey}">scenes checked</text>',
        f'<text x="12" y="{top + plot_h / 2:.0f}" font-size="11" fill="{red}" transform="rotate(-90 12 {top + plot_h / 2:.0f})" '
        f'text-anchor="middle">findings</text>',
        f'<text x="{width - 8}" y="{top + plot_h / 2:.0f}" font-size="11" fill="{blue}" '
        f'transform="rotate(90 {width - 8} {top + plot_h / 2:.0f})" text-anchor="middle">signatures</text>',
        "</svg>",
    ]
    return "".join(parts)


def _campaign_repro(state: CampaignState, entry: dict[str, Any], page_dir: Path, rasterizer: Any | None,
                    spec: str) -> dict[str, Any]:
    """A signature's repro for the page: its link (relative to the page), its picture
    (:func:`harness.report.pictures.draw_repro`, with the pixels the rasterizer's convention covers
    when it is known), its size and the command that replays it; or why there is none."""
    import json

    from harness.checks import Drawing
    from harness.contract.case import MotionCase, case_from_json
    from harness.contract.scenes import AnyScene

    relative = entry.get("repro")
    if not relative:
        why = entry.get("repro_error")
        return {"note": f"not shrunk: {why}" if why else "no repro yet (shrunk when the campaign next runs)"}
    path = Path(state.directory) / str(relative)
    href = os.path.relpath(path.resolve(), page_dir.resolve())
    out: dict[str, Any] = {"href": Path(href).as_posix(), "file": str(path),
                           "replay": f"rastercheck replay {shlex.quote(str(path))} --rasterizer {shlex.quote(spec)}"}
    try:
        payload = json.loads(path.read_text(encoding="utf-8"))
        case = case_from_json(payload)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        return {**out, "note": f"the repro cannot be read ({exc})"}
    drawing = None
    if rasterizer is not None and not isinstance(case, MotionCase):
        try:
            scene: AnyScene = case.scene
            convention = convention_for(rasterizer, scene)
        except Exception:  # noqa: BLE001 - a convention that cannot be read: the repro is drawn without one
            convention = None
        drawing = Drawing(case, (), convention) if convention is not None else None
    probe = Result(state.rasterizer, case.id, str(payload.get("check", entry.get("check", ""))), "fail",
                   str(payload.get("message", "")), evidence={"repro": payload}, drawing=drawing)
    drawn = draw_repro(probe)
    size = len(case.frames) if isinstance(case, MotionCase) else len(case.scene)
    noun = "frame" if isinstance(case, MotionCase) else case.scene.noun
    of = payload.get("original_triangles")
    return {**out, "picture": drawn[0] if drawn else None, "caption": drawn[1] if drawn else None,
            "size": f"{size} {noun}{'' if size == 1 else 's'}" + (f" (of {of})" if of else ""),
            "message": str(payload.get("message", "")), "note": payload.get("note"), "check": payload.get("check"),
            "paths": noun == "path", "lines": noun == "segment"}


def _campaign_rows(state: CampaignState, page_dir: Path, rasterizer: Any | None) -> list[dict[str, Any]]:
    from cases.fuzz import scene_id
    from harness.diagnose.signatures import Signature

    total = max(state.findings, 1)
    rows = []
    for key, entry in sorted(state.signatures.items(), key=lambda kv: (-int(kv[1].get("count", 0)), kv[0])):
        signature = Signature(str(entry.get("check", "")), str(entry.get("failure_class", "")), str(entry.get("convention_part", "")))
        examples = []
        for point in list(entry.get("examples") or [])[:CAMPAIGN_EXAMPLES]:
            try:
                family, seed, index = point
                case_id = scene_id(family, int(seed), int(index))
            except (KeyError, TypeError, ValueError):
                continue  # not a scene point of a family this version knows: nothing to replay
            examples.append({"point": _point_text(point), "id": case_id, "call": f"generate({family!r}, {int(seed)}, {int(index)})"})
        first, last = entry.get("first") or {}, entry.get("last") or {}
        rows.append({
            "key": key, "anchor": "signature-" + _slug(key), "check": signature.check, "failure_class": signature.failure_class,
            "convention_part": signature.convention_part, "describe": signature.describe(), "count": int(entry.get("count", 0)),
            "share": f"{100.0 * int(entry.get('count', 0)) / total:.1f}%",
            "first": {"point": _point_text(first), "at": _duration(float(first.get("at", 0.0))), "when": first.get("when", "")},
            "last": {"point": _point_text(last), "at": _duration(float(last.get("at", 0.0))), "when": last.get("when", "")},
            "message": str(entry.get("message", "")), "status": entry.get("status", "fail"),
            "examples": examples, "more_examples": max(len(entry.get("examples", [])) - CAMPAIGN_EXAMPLES, 0),
            "repro": _campaign_repro(state, entry, page_dir, rasterizer, state.spec),
        })
    return rows


def write_campaign_page(out_dir: Path | str, state: CampaignState, *, rasterizer: Any | None = None,
                        run: dict[str, Any] | None = None) -> Path:
    """Write ``campaign.html`` into ``out_dir`` atomically from a campaign's state.

    Parameters
    ----------
    out_dir : path
    state : CampaignState
        What the campaign searched and found (its repros are read from its folder and
        linked relative to the page).
    rasterizer : Rasterizer, optional
        Its convention for a repro's scene (declared, or identified) draws the pixels the
        convention covers on each repro; without it the repros are drawn without them.
    run : dict, optional
        This run's figures (:func:`campaign_run`): scenes, primitives, seconds, rates,
        workers.
    """
    from markupsafe import Markup

    out_dir = Path(out_dir)
    rows = _campaign_rows(state, out_dir, rasterizer)
    wall = state.wall_seconds
    header = {
        "rasterizer": state.rasterizer, "spec": state.spec, "seed": state.seed, "families": list(state.families),
        "skipped": dict(state.skipped), "scenes": state.scenes, "primitives": state.primitives, "findings": state.findings,
        "signatures": len(state.signatures), "wall": _duration(wall), "worker_seconds": _duration(state.worker_seconds),
        "scenes_per_second": state.scenes / wall if wall > 0 else 0.0,
        "primitives_per_second": state.primitives / wall if wall > 0 else 0.0,
        "identified": state.identified, "batch_size": state.batch_size,
        "done": [{"family": f, "seed": s, "ranges": ", ".join(f"{a}..{b - 1}" for a, b in ranges), "scenes": sum(b - a for a, b in ranges)}
                 for (f, s), ranges in sorted(state.done.items())],
    }
    anchors = {row["key"]: row["anchor"] for row in rows}
    causes = [{**group, "signatures": [(key, anchors.get(key, "")) for key in group["signatures"]]} for group in state.causes()]
    header["causes"] = len(causes)
    meta = page_meta("campaign", state.seed, wall)
    chart = Markup(findings_chart(state))  # built here from numbers and fixed words only
    html = _environment().get_template("campaign.html").render(
        header=header, run=run, rows=rows, causes=causes, chart=chart, meta=meta, state_dir=str(state.directory),
        crop_legend=CROP_LEGEND.items(), path_legend=PATH_LEGEND.items(), line_legend=LINE_LEGEND.items(),
        sample_legend=SAMPLE_LEGEND.items(),
        any_paths=any(r["repro"].get("paths") for r in rows), any_lines=any(r["repro"].get("lines") for r in rows),
        resume=f"rastercheck fuzz --rasterizer {shlex.quote(state.spec)} --state {shlex.quote(str(state.directory))} --budget 10m")
    path = out_dir / CAMPAIGN_PAGE
    atomic_write_text(path, html)
    link_pages(out_dir)  # an index in the folder links the page (templates/pages.html)
    return path


def campaign_json(state: CampaignState, run: dict[str, Any] | None = None, page: Path | str | None = None) -> dict[str, Any]:
    """A campaign as JSON (schema 1): its state (:meth:`CampaignState.to_json`: spec,
    rasterizer, seed, families, done ranges, totals, signatures with their repros relative
    to ``state_dir``, history), this run's figures (``run``) and the page, plus per
    signature its one-line description and the command replaying its repro."""
    from harness.diagnose.signatures import Signature

    data = state.to_json()
    described = {}
    for key, entry in state.signatures.items():
        signature = Signature(str(entry.get("check", "")), str(entry.get("failure_class", "")), str(entry.get("convention_part", "")))
        repro = Path(state.directory) / entry["repro"] if entry.get("repro") else None
        described[key] = {"describe": signature.describe(),
                          "replay": (f"rastercheck replay {shlex.quote(str(repro))} --rasterizer {shlex.quote(state.spec)}"
                                     if repro is not None else None)}
    return {**data, "state_dir": str(state.directory), "run": run, "page": None if page is None else str(page),
            "described": described, "causes": state.causes()}
