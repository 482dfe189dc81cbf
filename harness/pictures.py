"""Pictures for the report, drawn from results' evidence: heat maps, oracle diffs and
crops of failures on still cases, the minimal repro, animations and series plots of motion
failures, as data URIs (Pillow for the rasters, SVG by hand for the vectors, matplotlib,
imported when a plot is drawn, for the plots).

No colour means two things across the pictures: the heat map is drawn in greys and blues
(:data:`HEAT_LEGEND`), the diff against the oracle in green, red, orange and yellow
(:data:`DIFF_LEGEND`), and the animations use the diff's colours for the same meanings
(:data:`LEGEND`); the crops and repros have theirs (:data:`CROP_LEGEND`).

The engine draws nothing: a failing :class:`~harness.checks.Result` carries a
:class:`~harness.checks.records.Drawing` (references to the case, the answer, the
convention and the oracle if a check computed it), and :func:`draw` makes its pictures
when the report shows it.
"""

from __future__ import annotations

import base64
import io
import textwrap
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.api import Coverage
from harness.case import Case, MotionCase, case_from_json
from harness.checks import EVIDENCE_LIMIT, Result, pixel_classes
from harness.checks.records import Drawing
from harness.oracle import exact_coverage

__all__ = ["draw", "draw_repro", "motion_animation", "heatmap", "oracle_diff", "svg_crop", "svg_window", "series_plot",
           "series_label", "window_around", "svg_pattern", "LEGEND", "HEAT_LEGEND", "DIFF_LEGEND", "CROP_LEGEND", "ALPHA_LEGEND", "alpha_map", "MAX_REPRO_TRIANGLES",
           "MAX_REPRO_SIDE"]


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


def _alpha_per_pixel(coverage: Coverage, width: int, height: int) -> NDArray:
    """(H, W) float64: the alphas of every triangle summed per pixel (viewport only)."""
    t, x, y = coverage.pixels()
    alpha = coverage.alpha if coverage.alpha is not None and coverage.alpha.size == t.size else np.zeros(t.size)
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
    out = np.zeros(height * width)
    np.add.at(out, y[inside] * width + x[inside], alpha[inside])
    return out.reshape(height, width)


def _alpha_errors(coverage: Coverage, oracle: Coverage, width: int, height: int) -> NDArray:
    """(H, W) float64: per pixel, the signed alpha error (rasterizer minus oracle) of the
    triangle that errs most there."""
    def keyed(cov: Coverage) -> tuple[NDArray, NDArray]:
        t, x, y = cov.pixels()
        alpha = cov.alpha if cov.alpha is not None and cov.alpha.size == t.size else np.zeros(t.size)
        ok = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (t >= 0)
        keys, where = np.unique((t[ok] * height + y[ok]) * width + x[ok], return_inverse=True)
        return keys, np.bincount(where, weights=alpha[ok], minlength=keys.size)

    got_keys, got = keyed(coverage)
    want_keys, want = keyed(oracle)
    keys = np.union1d(got_keys, want_keys)
    error = np.zeros(keys.size)
    error[np.searchsorted(keys, got_keys)] += got
    error[np.searchsorted(keys, want_keys)] -= want
    pixel = keys % (width * height)
    worst = np.zeros(width * height)
    order = np.argsort(np.abs(error), kind="stable")  # the largest |error| written last wins
    worst[pixel[order]] = error[order]
    return worst.reshape(height, width)


def alpha_map(values: NDArray, scale: float, window: tuple[int, int, int, int] | None = None,
              marks: NDArray | None = None) -> str:
    """A signed per-pixel quantity as a PNG data URI on a diverging scale: white 0, red
    positive (too much alpha), blue negative (too little), full colour at ``scale`` and
    beyond; ``marks`` (H, W) bool pixels in black (ALPHA_LEGEND)."""
    level = np.clip(np.nan_to_num(values, nan=scale) / max(scale, 1e-300), -1.0, 1.0)
    rgb = np.full(values.shape + (3,), 255.0)
    for sign, colour in ((1.0, ALPHA_LEGEND["too much alpha (full red: the scale)"]),
                         (-1.0, ALPHA_LEGEND["too little alpha (full blue: the scale)"])):
        weight = np.where(level * sign > 0, np.abs(level), 0.0)[..., None]
        rgb = np.where(weight > 0, 255.0 * (1 - weight) + np.asarray(colour, dtype=float) * weight, rgb)
    rgb = rgb.astype(np.uint8)
    if marks is not None:
        rgb[marks] = ALPHA_LEGEND["stray (outside the region, alpha > 0)"]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))


def _area_pictures(case: Case, drawing: Drawing, result: Result, window: tuple[int, int, int, int]) -> dict[str, str]:
    """Area coverage: the alpha error against the oracle (scaled to the declared
    tolerance, or to the largest error when that is larger) and, on a partition, the sum
    of the pieces' alphas minus 1 (scaled to one level) with stray pixels marked."""
    scene = case.scene
    coverage = drawing.coverages[0]
    images: dict[str, str] = {}
    oracles = _oracles(drawing, [scene])
    if oracles is not None and drawing.convention is not None:
        errors = _alpha_errors(coverage, oracles[0], scene.width, scene.height)
        scale = max(drawing.convention.alpha_tolerance, float(np.abs(errors).max(initial=0.0)))
        images["alpha error"] = alpha_map(errors, scale, window)
    if case.region is not None and drawing.convention is not None:
        inside, outside = pixel_classes(case.region, scene.width, scene.height)
        total = _alpha_per_pixel(coverage, scene.width, scene.height)
        images["alpha sum"] = alpha_map(np.where(inside, total - 1.0, 0.0), drawing.convention.level_step, window,
                                        outside & (total > 0))
    return images


def _still_pictures(case: Case, drawing: Drawing, result: Result) -> dict[str, str]:
    """Heat map, oracle diff and an SVG crop around the first offending pixel (for area
    coverage: the alpha error and alpha sum maps)."""
    scene = case.scene
    coverage = drawing.coverages[0]
    marks = _focus(result)
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    window = window_around(int(fx), int(fy), scene.width, scene.height, 64)
    if drawing.convention is not None and drawing.convention.kind == "area":
        return _area_pictures(case, drawing, result, window)
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
    steps = [p for p in evidence.get("steps", []) if isinstance(p, dict)]  # popping's, dicts with frame, x, y
    marks = [*evidence.get("backward_jumps", []), *evidence.get("mismatches", []), *evidence.get("backward_steps", []), *steps]
    oracles = _oracles(drawing, list(case.frames))
    images = {"animation": motion_animation(list(drawing.coverages), list(oracles) if oracles is not None else None,
                                            first.width, first.height, marks, case.texels)}
    if evidence.get("series"):
        images["plot"] = series_plot(evidence["series"])
    return images


# -- colours: one meaning each across every picture ----------------------------------------

HEAT_LEGEND = {"not hit": (255, 255, 255), "hit once": (198, 219, 239), "hit twice or more": (8, 69, 148),
               "hole (inside, not hit)": (37, 37, 37), "stray (outside, hit)": (0, 170, 190)}
DIFF_LEGEND = {"both": (161, 217, 155), "missing (oracle only)": (215, 40, 40), "extra (rasterizer only)": (250, 140, 30),
               "near tie": (255, 225, 0)}
# the animations say "missing" and "extra" in the diff's colours
LEGEND = {
    "covered": (150, 150, 150),
    "oracle only (missing)": DIFF_LEGEND["missing (oracle only)"],
    "extra": DIFF_LEGEND["extra (rasterizer only)"],
    "flicker or backward jump": (120, 60, 220),
    "texel swim": (230, 0, 230),
}
ALPHA_LEGEND = {"exact (white)": (255, 255, 255), "too much alpha (full red: the scale)": (200, 30, 30),
                "too little alpha (full blue: the scale)": (30, 80, 200), "stray (outside the region, alpha > 0)": (0, 0, 0)}
CROP_LEGEND = {"covered by the rasterizer (crops)": (200, 200, 200), "covered by the convention (repros)": (230, 205, 140),
               "offending pixel (outlined)": (221, 0, 0), "triangle (outlined)": (0, 80, 200)}


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


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
    """Hit counts per pixel as a PNG data URI: white 0, pale blue 1, dark blue 2+, near-black
    holes, teal strays (colours in HEAT_LEGEND)."""
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
    """dEQP-style diff as a PNG data URI: both green, missing red, extra orange, near-tie
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
    t, x, y = coverage.pixels()
    inside = (x >= x0) & (x < x1) & (y >= y0) & (y < y1)
    covered = np.zeros((y1 - y0, x1 - x0), dtype=bool)
    covered[y[inside] - y0, x[inside] - x0] = True
    return svg_window(positions, covered, CROP_LEGEND["covered by the rasterizer (crops)"], sample, window, marks)


def svg_window(positions: NDArray, covered: NDArray | None, fill: tuple[int, int, int], sample: tuple[float, float] | None,
               window: tuple[int, int, int, int], marks: list[tuple[int, int]], fit: int = 384) -> str:
    """A window of the viewport as an SVG data URI, scaled to fit ``fit`` px (at most 24 px
    a pixel): the covered pixels filled, the pixel grid and the sample points when the
    pixels are drawn large enough to show them, the marked pixels outlined and the
    triangles drawn as vectors over them.

    Parameters
    ----------
    positions : (N, 3, 2) float64
    covered : (y1 - y0, x1 - x0) bool or None
        The pixels of the window to fill with ``fill``.
    sample : (float, float) or None
        The sample point in the pixel; None draws none.
    window : (x0, y0, x1, y1)
    marks : list of (x, y)
        Pixels to outline; those outside the window are left out.
    """
    x0, y0, x1, y1 = window
    cols, rows = x1 - x0, y1 - y0
    scale = min(24.0, fit / max(cols, rows, 1))  # screen px per pixel
    thin = 'vector-effect="non-scaling-stroke"'
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{round(cols * scale)}" height="{round(rows * scale)}" '
             f'viewBox="{x0} {y0} {cols} {rows}">',
             f'<rect x="{x0}" y="{y0}" width="{cols}" height="{rows}" fill="white"/>']
    if covered is not None and covered.any():
        # one rectangle per run of covered pixels in a row
        edges = np.diff(np.pad(covered.astype(np.int8), ((0, 0), (1, 1))), axis=1)
        starts, ends = np.argwhere(edges == 1), np.argwhere(edges == -1)  # row-major: pairs line up
        colour = _hex(fill)
        parts.extend(f'<rect x="{x0 + a}" y="{y0 + j}" width="{b - a}" height="1" fill="{colour}"/>'
                     for (j, a), (_, b) in zip(starts.tolist(), ends.tolist()))
    if scale >= 4:
        parts.extend(f'<line x1="{x0 + i}" y1="{y0}" x2="{x0 + i}" y2="{y1}" stroke="#999" stroke-width="0.5" {thin}/>'
                     for i in range(cols + 1))
        parts.extend(f'<line x1="{x0}" y1="{y0 + j}" x2="{x1}" y2="{y0 + j}" stroke="#999" stroke-width="0.5" {thin}/>'
                     for j in range(rows + 1))
    if sample is not None and scale >= 8:
        parts.extend(f'<circle cx="{x0 + i + sample[0]:g}" cy="{y0 + j + sample[1]:g}" r="{1.5 / scale:.4f}" fill="#333"/>'
                     for i in range(cols) for j in range(rows))
    inset = min(1.0 / scale, 0.25)
    red = _hex(CROP_LEGEND["offending pixel (outlined)"])
    for mx, my in marks:
        if x0 <= mx < x1 and y0 <= my < y1:
            parts.append(f'<rect x="{mx + inset:.4f}" y="{my + inset:.4f}" width="{1 - 2 * inset:.4f}" height="{1 - 2 * inset:.4f}" '
                         f'fill="none" stroke="{red}" stroke-width="2" {thin}/>')
    finite = np.all(np.isfinite(positions), axis=(1, 2))
    near = finite & np.any((positions[..., 0] > x0 - 64) & (positions[..., 0] < x1 + 64), axis=1)
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    for tri in positions[near][:200]:
        pts = " ".join(f"{vx:.6g},{vy:.6g}" for vx, vy in np.clip(tri, -1e6, 1e6))
        parts.append(f'<polygon points="{pts}" fill="none" stroke="{blue}" stroke-width="1" {thin}/>')
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")


def svg_pattern(offsets: tuple[tuple[float, float], ...], side: int = 160) -> str:
    """A multisample pattern as an SVG data URI: one pixel square, its 1/16 px grid, the
    centre marked, and each sample as a numbered dot (y down, as on screen).

    >>> svg_pattern(((0.375, 0.125), (0.875, 0.375))).startswith("data:image/svg+xml;base64,")
    True
    """
    thin = 'vector-effect="non-scaling-stroke"'
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{side}" height="{side}" viewBox="-0.08 -0.08 1.16 1.16">',
             '<rect x="0" y="0" width="1" height="1" fill="white" stroke="#333" stroke-width="1.5" ' + thin + '/>']
    parts.extend(f'<line x1="{k / 16:g}" y1="0" x2="{k / 16:g}" y2="1" stroke="#ddd" stroke-width="0.5" {thin}/>'
                 f'<line x1="0" y1="{k / 16:g}" x2="1" y2="{k / 16:g}" stroke="#ddd" stroke-width="0.5" {thin}/>'
                 for k in range(1, 16))
    parts.append('<circle cx="0.5" cy="0.5" r="0.012" fill="#999"/>')
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    for index, (x, y) in enumerate(offsets):
        parts.append(f'<circle cx="{x:.6g}" cy="{y:.6g}" r="0.025" fill="{blue}"/>'
                     f'<text x="{x + 0.03:.6g}" y="{y - 0.02:.6g}" font-size="0.07" font-family="sans-serif">{index}</text>')
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")


# -- the minimal repro ---------------------------------------------------------------------

MAX_REPRO_TRIANGLES = 200
MAX_REPRO_SIDE = 512  # px: larger viewports are not drawn (the report stays cheap)


def _repro_window(positions: NDArray, width: int, height: int, least: int = 8) -> tuple[int, int, int, int]:
    """The viewport's part that holds the triangles (finite ones), a pixel around them, at
    least ``least`` pixels a side where the viewport allows."""
    finite = positions[np.all(np.isfinite(positions), axis=(1, 2))].reshape(-1, 2)
    if not finite.size:
        return 0, 0, width, height
    lo = np.floor(np.clip(finite.min(axis=0), -1.0, [width + 1.0, height + 1.0])).astype(int) - 1
    hi = np.ceil(np.clip(finite.max(axis=0), -1.0, [width + 1.0, height + 1.0])).astype(int) + 1
    box = []
    for a, b, side in ((lo[0], hi[0], width), (lo[1], hi[1], height)):
        a, b = max(int(a), 0), min(int(b), side)
        if b - a < least:
            middle = (a + b) // 2
            a = int(np.clip(middle - least // 2, 0, max(side - least, 0)))
            b = min(a + least, side)
        box.append((a, b))
    (x0, x1), (y0, y1) = box
    return x0, y0, max(x1, x0 + 1), max(y1, y0 + 1)


def _near_triangles(marks: list[tuple[int, int]], positions: NDArray, reach: float = 1.5) -> list[tuple[int, int]]:
    """The marked pixels whose centre lies within ``reach`` px of one of the (finite)
    triangles: those of a whole case's evidence that can belong to its repro."""
    tris = positions[np.all(np.isfinite(positions), axis=(1, 2))]
    if not marks or not len(tris):
        return []
    centres = np.asarray(marks, dtype=float) + 0.5  # (M, 2)
    p = centres[:, None, None, :]  # (M, 1, 1, 2)
    a, b = tris[None, :, :, :], np.roll(tris, -1, axis=1)[None, :, :, :]  # (1, T, 3, 2) edges a -> b
    with np.errstate(all="ignore"):  # huge or degenerate triangles: a picture, not a verdict
        ab, ap = b - a, p - a
        t = np.clip(np.nan_to_num((ap * ab).sum(-1) / (ab * ab).sum(-1)), 0.0, 1.0)
        edge = np.hypot(*np.moveaxis(ap - t[..., None] * ab, -1, 0)).min(axis=2)  # (M, T): to the nearest edge
        cross = ab[..., 0] * ap[..., 1] - ab[..., 1] * ap[..., 0]  # (M, T, 3)
    inside = (cross >= 0).all(axis=2) | (cross <= 0).all(axis=2)
    near = (inside | (edge <= reach)).any(axis=1)
    return [m for m, ok in zip(marks, near.tolist()) if ok]


def draw_repro(result: Result) -> tuple[str | None, str] | None:
    """The failure's minimal repro (``evidence["repro"]``, case JSON) drawn, with its
    caption: its triangles over the pixel grid and, given a convention (the drawing's),
    the pixels that convention covers; the pixels the evidence names (on the whole case)
    within a pixel and a half of the repro's triangles outlined. The rasterizer's own
    answer on the repro is not known here and not drawn.

    Returns None without a repro; (None, why) when it is not drawn (a motion case, a malformed
    one, or more than :data:`MAX_REPRO_TRIANGLES` triangles or :data:`MAX_REPRO_SIDE` px).
    """
    payload = result.evidence.get("repro")
    if not isinstance(payload, dict):
        return None
    try:
        case = case_from_json(payload)
    except ValueError as exc:
        return None, f"minimal repro not drawn: {exc}"
    if isinstance(case, MotionCase):
        return None, f"minimal repro: a sequence of {len(case.frames)} frames, not drawn here"
    scene = case.scene
    n, of = len(scene), payload.get("original_triangles")
    triangles = f"{n} triangle{'' if n == 1 else 's'}" + (f" (of {of})" if of else "")
    if n > MAX_REPRO_TRIANGLES or max(scene.width, scene.height) > MAX_REPRO_SIDE:
        return None, (f"minimal repro: {triangles} on a {scene.width} x {scene.height} viewport, not drawn (pictures are "
                      f"drawn up to {MAX_REPRO_TRIANGLES} triangles and {MAX_REPRO_SIDE} px a side)")
    convention = result.drawing.convention if result.drawing is not None else None
    window = _repro_window(scene.positions, scene.width, scene.height)
    covered = None
    if convention is not None:
        x0, y0, x1, y1 = window
        covered = exact_coverage(scene, convention).counts(scene.width, scene.height)[y0:y1, x0:x1] > 0
    marks = _near_triangles(_focus(result)[:EVIDENCE_LIMIT], scene.positions)
    uri = svg_window(scene.positions, covered, CROP_LEGEND["covered by the convention (repros)"],
                     convention.sample if convention is not None else None, window, marks)
    outlined = f"; outlined: {len(marks)} of the pixels the failure names, next to these triangles" if marks else ""
    if convention is None:
        return uri, f"minimal repro: its {triangles}; no convention known, so no coverage drawn{outlined}"
    return uri, f"minimal repro: its {triangles}, the pixels the convention covers{outlined}"


# -- per-frame series ----------------------------------------------------------------------

# series name -> (what it counts, unit): the motion checks' evidence["series"]
SERIES = {
    "changed_pixels": ("pixels that changed", "pixels"),
    "oracle_changed_pixels": ("pixels the oracle changed", "pixels"),
    "backward_jumps": ("backward jumps", "span ends"),
    "mismatches": ("texel mismatches", "pixels"),
    "max_uv_error_texels": ("largest u, v error", "texels"),
    # popping: the worst pixel's alpha, exact area and declared model, frame by frame
    "alpha": ("the rasterizer's alpha", "alpha"),
    "area": ("the exact area", "alpha"),
    "oracle": ("the declared model's alpha", "alpha"),
}


def series_label(name: str) -> tuple[str, str]:
    """What a per-frame series counts and its unit; an unknown name is read from its
    suffix (``_pixels``, ``_texels``), else counted.

    >>> series_label("max_uv_error_texels"), series_label("stray_pixels"), series_label("flips")
    (('largest u, v error', 'texels'), ('stray', 'pixels'), ('flips', 'count'))
    """
    if name in SERIES:
        return SERIES[name]
    for unit in ("pixels", "texels"):
        if name.endswith("_" + unit):
            return name[: -len(unit) - 1].replace("_", " "), unit
    return name.replace("_", " "), "count"


def series_plot(series: dict[str, list[float]]) -> str:
    """Per-frame metric series as a PNG data URI (matplotlib, Agg): one panel per unit,
    frames along x, the metric and its unit along y, a legend naming each series.
    Non-finite values are left out of the line (the legend says how many). A fixed
    layout and fast PNG compression keep it near a tenth of a second."""
    from matplotlib.figure import Figure  # the presentation's own import: the engine never pays for it
    from matplotlib.ticker import MaxNLocator

    panels: dict[str, list[tuple[str, NDArray]]] = {}
    for name, values in series.items():
        label, unit = series_label(name)
        panels.setdefault(unit, []).append((label, np.asarray(values, dtype=float).ravel()))
    dpi, panel, legend, axis = 80, 110, 24, 44  # px: a panel's height, a legend's above it, the x axis's below
    height = len(panels) * (panel + legend) + axis
    figure = Figure(figsize=(512 / dpi, height / dpi), dpi=dpi)
    figure.subplots_adjust(left=90 / 512, right=1 - 12 / 512, top=1 - legend / height, bottom=axis / height,
                           hspace=legend / panel)
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (unit, lines) in zip(axes, panels.items()):
        for label, v in lines:
            finite = np.isfinite(v)
            lost = int((~finite).sum())
            ax.plot(np.arange(v.size), np.where(finite, v, np.nan), marker="." if v.size <= 40 else None,
                    linewidth=1.2, label=label + (f" ({lost} non-finite frames not drawn)" if lost else ""))
        ax.set_ylabel(textwrap.fill(lines[0][0], 16) + f"\n({unit})" if len(lines) == 1 else unit, fontsize=9)
        finite_values = np.concatenate([v[np.isfinite(v)] for _, v in lines])
        whole = bool(np.array_equal(finite_values, np.round(finite_values)))
        ax.yaxis.set_major_locator(MaxNLocator(nbins=4, integer=whole))
        if whole and (not finite_values.size or finite_values.min() >= 0):  # counts: from 0, at least to 1
            top = max(1.0, float(finite_values.max()) if finite_values.size else 1.0)
            ax.set_ylim(-0.05 * top, 1.08 * top)
        ax.tick_params(labelsize=8)
        ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=len(lines), frameon=False,
                  borderaxespad=0.1)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("frame", fontsize=9)
    axes[-1].xaxis.set_major_locator(MaxNLocator(integer=True))
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", pil_kwargs={"compress_level": 1})
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")
