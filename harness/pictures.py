"""Pictures for the report, drawn from results' evidence: heat maps, oracle diffs and
crops of failures on still cases, animations and series plots of motion failures, as data
URIs (Pillow for the rasters, SVG by hand for the vectors).

The engine draws nothing: a failing :class:`~harness.checks.Result` carries a
:class:`~harness.checks.records.Drawing` (references to the case, the answer, the
convention and the oracle if a check computed it), and :func:`draw` makes its pictures
when the report shows it.
"""

from __future__ import annotations

import base64
import io
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.api import Coverage
from harness.case import Case, MotionCase
from harness.checks import Result, pixel_classes
from harness.checks.records import Drawing
from harness.oracle import exact_coverage

__all__ = ["draw", "motion_animation", "heatmap", "oracle_diff", "svg_crop", "series_plot", "window_around",
           "LEGEND", "HEAT_LEGEND", "DIFF_LEGEND"]


def draw(result: Result) -> dict[str, str]:
    """The pictures of a failure, caption key -> data URI, in the order the report shows
    them: ``heatmap``, ``diff`` (given a convention) and ``crop`` for a still case;
    ``animation`` and, when the evidence has a series, ``plot`` for a motion case. Nothing
    for a result without a drawing (a pass, an error, one read back from JSON)."""
    drawing = result.drawing
    if drawing is None:
        return {}
    if isinstance(drawing.case, MotionCase):
        return _motion_pictures(drawing.case, drawing, result.evidence)
    return _still_pictures(drawing.case, drawing, result)


def _oracles(drawing: Drawing, scenes: list[Any]) -> tuple[Coverage, ...] | None:
    """The oracle of each scene: the check's, when it computed one; else computed now
    (given a convention); None without a convention."""
    if drawing.oracles is not None:
        return drawing.oracles
    if drawing.convention is None:
        return None
    return tuple(exact_coverage(scene, drawing.convention) for scene in scenes)


def _focus(result: Result) -> list[tuple[int, int]]:
    """The offending pixels a failure names, first the most telling."""
    e = result.evidence
    if "pixels" in e and e["pixels"] and isinstance(e["pixels"][0], dict):
        return [(p["x"], p["y"]) for p in e["pixels"]]
    if "blame" in e:
        return [(int(b["pixel"][0]), int(b["pixel"][1])) for b in e["blame"]]
    for key in ("strays", "pixels"):
        if e.get(key):
            return [(int(p[0]), int(p[1])) for p in e[key]]
    for key in ("rotate-vertices", "flip-winding", "permute-triangles", "translate"):
        if e.get(key):
            return [(int(p[1]), int(p[2])) for p in e[key]]
    return []


def _still_pictures(case: Case, drawing: Drawing, result: Result) -> dict[str, str]:
    """Heat map, oracle diff and an SVG crop around the first offending pixel."""
    scene = case.scene
    coverage = drawing.coverages[0]
    marks = _focus(result)
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    window = window_around(int(fx), int(fy), scene.width, scene.height, 64)
    counts = coverage.counts(scene.width, scene.height)
    holes = strays = None
    if case.region is not None:
        inside, outside = pixel_classes(case.region, scene.width, scene.height)
        holes, strays = inside & (counts == 0), outside & (counts > 0)
    images = {"heatmap": heatmap(counts, holes, strays, window)}
    oracles = _oracles(drawing, [scene])
    if oracles is not None:
        images["diff"] = oracle_diff(scene.width, scene.height, counts > 0, oracles[0].counts(scene.width, scene.height) > 0,
                                     result.evidence.get("pixels", []) if result.check == "conformance" else [], window)
    crop = window_around(int(fx), int(fy), scene.width, scene.height, 12)
    sample = drawing.convention.sample if drawing.convention is not None else (0.5, 0.5)
    images["crop"] = svg_crop(scene.positions, coverage, sample, crop, [(int(x), int(y)) for x, y in marks[:20]])
    return images


def _motion_pictures(case: MotionCase, drawing: Drawing, evidence: dict[str, Any]) -> dict[str, str]:
    """The sequence as an animation with the evidence's offending pixels marked, and the
    per-frame series as a plot."""
    first = case.frames[0]
    marks = [*evidence.get("backward_jumps", []), *evidence.get("mismatches", []), *evidence.get("backward_steps", [])]
    oracles = _oracles(drawing, list(case.frames))
    images = {"animation": motion_animation(list(drawing.coverages), list(oracles) if oracles is not None else None,
                                            first.width, first.height, marks, case.texels)}
    if "series" in evidence:
        images["plot"] = series_plot(evidence["series"])
    return images

LEGEND = {
    "covered": (150, 150, 150),
    "oracle only (missing)": (90, 60, 200),
    "extra": (220, 60, 60),
    "flicker or backward jump": (255, 200, 0),
    "texel swim": (230, 0, 230),
}
MAX_FRAMES = 48
MAX_SIDE = 64  # pixels of the viewport shown: a window around the evidence


def _texel_colours(ids: NDArray) -> NDArray:
    rng = np.random.default_rng(7)
    palette = rng.integers(60, 230, size=(4096, 3))
    return palette[ids % 4096]


def motion_animation(coverages: list[Coverage], oracles: list[Coverage] | None, width: int, height: int,
                     marks: list[dict[str, Any]] | None = None, texels: int | None = None, scale: int = 6) -> str:
    """An animated GIF (data URI) of the sequence: coverage (or texel ids when textured)
    against the oracle (none without a convention), with the evidence's frames, pixels and
    rows marked.

    Frames beyond ``MAX_FRAMES`` are sampled evenly; marked frames are always kept.
    """
    marks = marks or []
    count = len(coverages)
    # a window of at most MAX_SIDE x MAX_SIDE pixels around the first mark, or the coverage
    xs = [int(m.get("x", m.get("column", 0))) for m in marks]
    ys = [int(m.get("y", m.get("row", 0))) for m in marks]
    if not xs:
        t, x, y = coverages[0].pixels()
        xs, ys = (x.tolist() or [0]), (y.tolist() or [0])
    cx = int(np.clip(xs[0], 0, width - 1)) if marks else (min(xs) + max(xs)) // 2
    cy = int(np.clip(ys[0], 0, height - 1)) if marks else (min(ys) + max(ys)) // 2
    wx0 = int(np.clip(cx - MAX_SIDE // 2, 0, max(width - MAX_SIDE, 0)))
    wy0 = int(np.clip(cy - MAX_SIDE // 2, 0, max(height - MAX_SIDE, 0)))
    wx1, wy1 = min(wx0 + MAX_SIDE, width), min(wy0 + MAX_SIDE, height)
    keep = set(np.linspace(0, count - 1, min(count, MAX_FRAMES)).astype(int).tolist())
    keep |= {int(m["frame"]) for m in marks if "frame" in m and int(m["frame"]) < count}
    images = []
    for f in sorted(keep):
        got = coverages[f].counts(width, height) > 0
        want = oracles[f].counts(width, height) > 0 if oracles is not None else got
        rgb = np.full((height, width, 3), 255, dtype=np.uint8)
        if texels and coverages[f].attributes is not None and coverages[f].attributes.shape[0] == coverages[f].n_pixels:
            t, x, y = coverages[f].pixels()
            ok = (x >= 0) & (x < width) & (y >= 0) & (y < height)
            uv = np.nan_to_num(coverages[f].attributes[ok, :2] * texels).astype(np.int64)
            rgb[y[ok], x[ok]] = _texel_colours(uv[:, 0] * 131 + uv[:, 1])
        else:
            rgb[got] = LEGEND["covered"]
        rgb[want & ~got] = LEGEND["oracle only (missing)"]
        rgb[got & ~want] = LEGEND["extra"]
        for m in marks:
            if int(m.get("frame", -1)) != f:
                continue
            if "x" in m and "y" in m:
                rgb[int(m["y"]) % height, int(m["x"]) % width] = LEGEND["texel swim" if "axis" in m or "texel" in m else "flicker or backward jump"]
            elif "row" in m and "column" in m:
                rgb[int(m["row"]) % height, min(max(int(m["column"]), 0), width - 1)] = LEGEND["flicker or backward jump"]
        crop = rgb[wy0:wy1, wx0:wx1]
        images.append(Image.fromarray(np.ascontiguousarray(crop)).resize(((wx1 - wx0) * scale, (wy1 - wy0) * scale), Image.Resampling.NEAREST))
    buffer = io.BytesIO()
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=80, loop=0)
    return "data:image/gif;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


# -- still pictures for failures of single-scene checks ------------------------------------

HEAT = {0: (255, 255, 255), 1: (190, 190, 190)}
HEAT_LEGEND = {"not hit": (255, 255, 255), "hit once": (190, 190, 190), "hit twice or more": (220, 40, 40),
               "hole (inside, not hit)": (120, 60, 220), "stray (outside, hit)": (255, 150, 0)}
DIFF_LEGEND = {"both": (190, 190, 190), "missing (oracle only)": (150, 60, 200), "extra (rasterizer only)": (220, 40, 40),
               "near tie": (255, 210, 0)}


def _png(rgb: NDArray, scale: int) -> str:
    image = Image.fromarray(np.ascontiguousarray(rgb)).resize((rgb.shape[1] * scale, rgb.shape[0] * scale), Image.Resampling.NEAREST)
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def window_around(x: int, y: int, width: int, height: int, side: int) -> tuple[int, int, int, int]:
    """A side x side window of the viewport centred near (x, y)."""
    x0 = int(np.clip(x - side // 2, 0, max(width - side, 0)))
    y0 = int(np.clip(y - side // 2, 0, max(height - side, 0)))
    return x0, y0, min(x0 + side, width), min(y0 + side, height)


def heatmap(counts: NDArray, holes: NDArray | None = None, strays: NDArray | None = None,
            window: tuple[int, int, int, int] | None = None) -> str:
    """Hit counts per pixel as a PNG data URI: white 0, grey 1, red 2+, purple holes,
    orange strays (colours in HEAT_LEGEND)."""
    rgb = np.full(counts.shape + (3,), 255, dtype=np.uint8)
    rgb[counts == 1] = HEAT_LEGEND["hit once"]
    rgb[counts >= 2] = HEAT_LEGEND["hit twice or more"]
    if holes is not None:
        rgb[holes] = HEAT_LEGEND["hole (inside, not hit)"]
    if strays is not None:
        rgb[strays] = HEAT_LEGEND["stray (outside, hit)"]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))


def oracle_diff(width: int, height: int, got: NDArray, want: NDArray, pixels: list[dict[str, Any]],
                window: tuple[int, int, int, int] | None = None) -> str:
    """dEQP-style diff as a PNG data URI: both grey, missing purple, extra red, near-tie
    yellow (colours in DIFF_LEGEND)."""
    rgb = np.full((height, width, 3), 255, dtype=np.uint8)
    rgb[got & want] = DIFF_LEGEND["both"]
    rgb[want & ~got] = DIFF_LEGEND["missing (oracle only)"]
    rgb[got & ~want] = DIFF_LEGEND["extra (rasterizer only)"]
    for p in pixels:
        x, y = int(p["x"]), int(p["y"])
        if 0 <= x < width and 0 <= y < height:
            kind = "near tie" if p.get("near_tie") else ("missing (oracle only)" if p["kind"] == "missing" else "extra (rasterizer only)")
            rgb[y, x] = DIFF_LEGEND[kind]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))


def svg_crop(positions: NDArray, coverage: Coverage, sample: tuple[float, float], window: tuple[int, int, int, int],
             marks: list[tuple[int, int]]) -> str:
    """The pixel grid of a small window with its sample points, the covered pixels, the
    marked pixels outlined, and the triangles drawn as vectors over them (SVG data URI)."""
    x0, y0, x1, y1 = window
    scale = 24
    w, h = (x1 - x0) * scale, (y1 - y0) * scale
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">',
             f'<rect width="{w}" height="{h}" fill="white"/>']
    t, x, y = coverage.pixels()
    inside = (x >= x0) & (x < x1) & (y >= y0) & (y < y1)
    for px, py in set(zip(x[inside].tolist(), y[inside].tolist())):
        parts.append(f'<rect x="{(px - x0) * scale}" y="{(py - y0) * scale}" width="{scale}" height="{scale}" fill="#c8c8c8"/>')
    for i in range(x1 - x0 + 1):
        parts.append(f'<line x1="{i * scale}" y1="0" x2="{i * scale}" y2="{h}" stroke="#999" stroke-width="0.5"/>')
    for j in range(y1 - y0 + 1):
        parts.append(f'<line x1="0" y1="{j * scale}" x2="{w}" y2="{j * scale}" stroke="#999" stroke-width="0.5"/>')
    for i in range(x1 - x0):
        for j in range(y1 - y0):
            parts.append(f'<circle cx="{(i + sample[0]) * scale:.2f}" cy="{(j + sample[1]) * scale:.2f}" r="1.5" fill="#333"/>')
    for mx, my in marks:
        if x0 <= mx < x1 and y0 <= my < y1:
            parts.append(f'<rect x="{(mx - x0) * scale + 1}" y="{(my - y0) * scale + 1}" width="{scale - 2}" height="{scale - 2}" '
                         f'fill="none" stroke="#d00" stroke-width="2"/>')
    finite = np.all(np.isfinite(positions), axis=(1, 2))
    near = finite & np.any((positions[..., 0] > x0 - 64) & (positions[..., 0] < x1 + 64), axis=1)
    for tri in positions[near][:200]:
        pts = " ".join(f"{(vx - x0) * scale:.3f},{(vy - y0) * scale:.3f}" for vx, vy in np.clip(tri, -1e6, 1e6))
        parts.append(f'<polygon points="{pts}" fill="none" stroke="#0050c8" stroke-width="1"/>')
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")


def series_plot(series: dict[str, list[float]], width: int = 480, height: int = 160) -> str:
    """Per-frame metric series as a small SVG line chart (data URI), one colour each."""
    colours = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd"]
    values = [np.nan_to_num(np.asarray(v, dtype=float), posinf=0.0) for v in series.values()]
    top = max([float(v.max()) for v in values if v.size] + [1.0])
    frames = max([v.size for v in values] + [2])
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height + 20 * len(values)}">',
             f'<rect width="{width}" height="{height}" fill="white" stroke="#999"/>']
    for k, ((name, _), v) in enumerate(zip(series.items(), values)):
        pts = " ".join(f"{i * (width - 1) / (frames - 1):.1f},{height - 1 - v[i] / top * (height - 10):.1f}" for i in range(v.size))
        colour = colours[k % len(colours)]
        parts.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        parts.append(f'<text x="4" y="{height + 15 + 20 * k}" font-size="12" fill="{colour}">{name} (max {float(v.max()) if v.size else 0:g})</text>')
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")
