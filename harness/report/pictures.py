"""Pictures for the report, drawn from results' evidence: heat maps, oracle diffs and
crops of failures on still cases, the minimal repro, animations and series plots of motion
failures, as data URIs (Pillow for the rasters, SVG by hand for the vectors, matplotlib,
imported when a plot is drawn, for the plots).

No colour means two things across the pictures: the heat map is drawn in greys and blues
(:data:`HEAT_LEGEND`), the diff against the oracle in green, red, orange and yellow
(:data:`DIFF_LEGEND`), and the animations use the diff's colours for the same meanings
(:data:`LEGEND`); the crops and repros have theirs (:data:`CROP_LEGEND`), for path
scenes :data:`PATH_LEGEND`, for line scenes :data:`LINE_LEGEND`, and for the samples of
multisample and supersampled conventions :data:`SAMPLE_LEGEND`.

A minimal repro whose file keeps the rasterizer's answer on it (:func:`draw_repro`) is
drawn twice side by side over the same window: what the rasterizer drew, and what the
convention says, with the pixels its failure names on the repro outlined on both and its
primitives drawn over both. A multisample or supersampled failure draws each sample of
the pattern in each pixel, a dot where covered and a ring where not, ringed in red where
the rasterizer and the convention differ (:class:`Samples`); anti-aliased pixels are
shaded by their alpha, the offending ones labelled with it (``k/N`` of the samples). A
crop of a multisample failure judged sample by sample, or of an anti-aliased one, is
drawn the same way (``samples``).

A path scene's crop draws each path as one SVG ``<path>`` under the scene's fill rule
(a faint fill where the rule fills it, arrows along the edges, a ring at each contour's
start) and writes in every pixel the winding number of its sample around the path the
failure names (:func:`winding_numbers`, computed exactly: its fill-rule verdict is the
oracle's at every sample, ties included).

A line scene's crop (:class:`~harness.contract.scenes.LineScene`) draws each strip as one polyline from
end point to end point over the pixel grid, its pixels coloured as the diff against the
oracle colours them, segment by segment (drawn by both; by the oracle only; by the
rasterizer only, as a joint pixel drawn by the segment that ends there), the pixels the
failure names outlined, each segment numbered at its middle with an arrowhead
for its direction, the segment the failure names thick (:func:`numbered_segment`), every
joint (a vertex where one segment ends and the next starts) as a dot, the number of
segments that drew a pixel where more than one did, and, under the diamond-exit rule, the
diamond test area of each offending pixel with the edges and corners it includes solid
(:mod:`harness.oracle.lines`); under the rectangle rule, each segment's rectangle.

The engine draws nothing: a failing :class:`~harness.checks.Result` carries a
:class:`~harness.checks.records.Drawing` (references to the case, the answer, the
convention and the oracle if a check computed it), and :func:`draw` makes its pictures
when the report shows it.
"""

from __future__ import annotations

import base64
import io
import math
import textwrap
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.checks import EVIDENCE_LIMIT, Result, deviations, pixel_classes
from harness.checks.records import Drawing
from harness.contract.case import Case, MotionCase, case_from_json
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene
from harness.geometry.exact import orientation
from harness.oracle.coverage import exact_coverage

__all__ = ["draw", "draw_repro", "motion_animation", "heatmap", "oracle_diff", "svg_crop", "svg_window", "series_plot",
           "series_label", "window_around", "svg_pattern", "LEGEND", "HEAT_LEGEND", "DIFF_LEGEND", "CROP_LEGEND", "ALPHA_LEGEND", "alpha_map", "MAX_REPRO_TRIANGLES",
           "MAX_REPRO_SIDE", "PATH_LEGEND", "winding_numbers", "rule_fills", "focus_path", "numbered_path", "MAX_NUMBERED_SIDE",
           "MAX_DRAWN_VERTICES", "LINE_LEGEND", "line_focus", "focus_segment", "numbered_segment",
           "LINE_CROP_SIDE", "SAMPLE_LEGEND", "Samples", "sample_hits"]


def draw(result: Result) -> dict[str, str]:
    """The pictures of a failure, caption key -> data URI, in the order the report shows
    them: ``heatmap``, ``diff`` (given a convention) and ``crop`` for a still case;
    ``animation`` and, when the evidence has a series, ``plot`` for a motion case
    (and ``samples`` after them for a multisample answer judged sample by sample; area
    coverage: ``alpha error``, ``alpha sum`` and ``samples``). Nothing
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


def _offending_rows(evidence: dict[str, Any]) -> list[dict[str, Any]]:
    """The rows of ``evidence["pixels"]`` (dicts with ``x`` and ``y``) that are offending:
    all but those that say they are within tolerance (``over`` False: accuracy lists its
    worst pixels, and those of them within tolerance are not wrong); accuracy's
    ``off_level`` rows when no other is.

    >>> _offending_rows({"pixels": [{"x": 1, "y": 2, "over": True}, {"x": 3, "y": 4, "over": False}]})
    [{'x': 1, 'y': 2, 'over': True}]
    """
    rows = [p for p in evidence.get("pixels") or () if isinstance(p, dict) and "x" in p and "y" in p]
    wrong = [p for p in rows if p.get("over") is not False]
    if not wrong and rows:
        wrong = [p for p in evidence.get("off_level") or () if isinstance(p, dict) and "x" in p and "y" in p]
    return wrong


def _focus(result: Result) -> list[tuple[int, int]]:
    """The offending pixels a failure names, first the most telling."""
    e = result.evidence
    if "pixels" in e and e["pixels"] and isinstance(e["pixels"][0], dict):
        return [(int(p["x"]), int(p["y"])) for p in _offending_rows(e)]
    if "blame" in e:
        return [(int(b["pixel"][0]), int(b["pixel"][1])) for b in e["blame"]]
    for key in ("strays", "pixels"):
        if e.get(key):
            return [(int(p[0]), int(p[1])) for p in e[key]]
    for key in ("rotate-vertices", "flip-winding", "permute-triangles", "translate", *_PATH_ROWS):
        if e.get(key):
            return [(int(p[1]), int(p[2])) for p in e[key]]
    return []


# Evidence lists of [path, x, y] rows on path scenes: the triangulation check's and the
# invariance check's path variants (harness.checks.paths, harness.checks.invariance).
_PATH_ROWS = ("path_only", "triangles_only", "triangulation_double_hits", "rotate-start-vertex", "reverse-every-contour",
              "reverse-one-contour", "reorder-contours", "permute-paths")


def focus_path(result: Result) -> int | None:
    """The path a failure on a path scene names first, or None when its evidence names
    none: conformance's ``pixels[0]["path"]``, watertight's ``blame[0]["paths"][0]``,
    the first row ``[path, x, y]`` of the triangulation check's and the invariance
    check's lists.

    >>> focus_path(Result("r", "c", "conformance", "fail", "m", {}, {"pixels": [{"path": 3, "x": 1, "y": 2}]}))
    3
    """
    e = result.evidence
    pixels = e.get("pixels")
    if pixels and isinstance(pixels[0], dict) and "path" in pixels[0]:
        return int(pixels[0]["path"])
    for entry in e.get("blame", ()):
        if isinstance(entry, dict) and entry.get("paths"):
            return int(entry["paths"][0])
    on_paths = result.drawing is not None and isinstance(getattr(result.drawing.case, "scene", None), PathScene)
    translate = ("translate",) if on_paths else ()  # a name both kinds' invariance lists use
    for key in (*_PATH_ROWS, *translate):
        rows = e.get(key)
        if rows and isinstance(rows[0], (list, tuple)) and len(rows[0]) == 3:
            return int(rows[0][0])
    return None


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
    tolerance, or to the largest error when that is larger), on a partition the sum of
    the pieces' alphas minus 1 (scaled to one level) with stray pixels marked, and the
    crop of the samples (:func:`_sample_crop`)."""
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
    if oracles is not None:
        images["samples"] = _sample_crop(case, drawing, result, oracles[0])
    return images


def _sample_crop(case: Case, drawing: Drawing, result: Result, oracle: Coverage | None) -> str:
    """A multisample or anti-aliased failure's crop (12 px a side around its first
    offending pixel): what the rasterizer drew beside what the convention says
    (:func:`_repro_panels`: each sample of the pattern in each pixel, covered or not,
    ringed where the two differ; alphas as shades), the offending pixels outlined."""
    scene = case.scene
    marks = [(int(x), int(y)) for x, y in _focus(result)[:EVIDENCE_LIMIT]]
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    crop = window_around(fx, fy, scene.width, scene.height, 12)
    numbered = numbered_path(result) if isinstance(scene, PathScene) else None
    chosen = _numbering_convention(drawing.convention) if isinstance(scene, PathScene) else None
    only = _named_primitives(result, scene)
    if only is not None:  # the pixels the failure names of those primitives
        marks = [(int(p["x"]), int(p["y"])) for p in _offending_rows(result.evidence) if set(_primitives_of(p)) & set(only)]
    return _repro_panels(scene, drawing.coverages[0], oracle, drawing.convention, crop, marks, numbered, chosen, only)


def _primitives_of(row: dict[str, Any]) -> list[int]:
    """The primitives an evidence row names (``triangle``, ``path``, ``triangles``, ``paths``).

    >>> _primitives_of({"x": 1, "y": 2, "triangles": [3, 4]}), _primitives_of({"path": 2})
    ([3, 4], [2])
    """
    for key in ("triangle", "path", "triangles", "paths"):
        named = row.get(key)
        if isinstance(named, list):
            return [int(v) for v in named if isinstance(v, int)]
        if isinstance(named, int):
            return [named]
    return []


def _named_primitives(result: Result, scene: AnyScene) -> list[int] | None:
    """The primitives the first offending pixel of a failure names (``triangle``,
    ``path``, ``triangles`` or ``paths`` of its first ``pixels`` row), when its scene is no
    partition (where the pieces' sum is what counts); None otherwise: all of them."""
    pixels = result.evidence.get("pixels")
    case = result.drawing.case if result.drawing is not None else None
    if not pixels or not isinstance(pixels[0], dict) or getattr(case, "region", None) is not None:
        return None
    for key in ("triangle", "path", "triangles", "paths"):
        named = pixels[0].get(key)
        values = named if isinstance(named, list) else [named]
        if named is not None and all(isinstance(v, int) and 0 <= v < len(scene) for v in values):
            return sorted(set(values))
    return None


def _still_pictures(case: Case, drawing: Drawing, result: Result) -> dict[str, str]:
    """Heat map, oracle diff and an SVG crop around the first offending pixel (and, for one
    sample's layer of a multisample answer, the crop of all its samples,
    :func:`_sample_crop`; for area coverage: the alpha error and alpha sum maps and the
    crop of the samples)."""
    scene = case.scene
    if isinstance(scene, LineScene):
        return _line_pictures(scene, drawing, result)
    coverage = drawing.coverages[0]
    marks = _focus(result)
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    window = window_around(int(fx), int(fy), scene.width, scene.height, 64)
    if drawing.convention is not None and drawing.convention.model.alphas:
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
    shown = [(int(x), int(y)) for x, y in marks[:20]]
    if isinstance(scene, PathScene):
        convention = _numbering_convention(drawing.convention)
        numbered = numbered_path(result)
        images["crop"] = svg_crop(scene, coverage, convention.sample, crop, shown, numbered=numbered, convention=convention)
    else:
        sample = drawing.convention.sample if drawing.convention is not None else (0.5, 0.5)
        images["crop"] = svg_crop(scene.positions, coverage, sample, crop, shown)
    if drawing.whole is not None and drawing.whole.coverages:  # one sample's layer of a multisample answer: all its samples
        whole_oracles = _oracles(drawing.whole, [scene])
        images["samples"] = _sample_crop(case, drawing.whole, result, whole_oracles[0] if whole_oracles else None)
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
_DRAWN = "drawn by the rasterizer (crops, and the left picture of a repro; anti-aliased: shaded by its alpha)"
_CONVENTION = "covered by the convention (the right picture of a repro; anti-aliased: shaded by its alpha)"
CROP_LEGEND = {_DRAWN: (200, 200, 200), _CONVENTION: (230, 205, 140),
               "offending pixel (outlined)": (221, 0, 0), "triangle (outlined)": (0, 80, 200),
               "region of a partition (dotted; every pixel wholly inside it must be hit)": (0, 130, 100)}
_REGION = list(CROP_LEGEND)[-1]
# multisample and supersampled pictures: each sample of the convention's pattern in each
# pixel, over CROP_LEGEND's pixels
# The most samples one repro panel draws (a dot or ring each): 16 a pixel keep a 12 px
# crop, 64 (a 16x4 grid) a 6 px one.
SAMPLE_BUDGET = 2400

SAMPLE_LEGEND = {"sample covered (dot)": (25, 25, 25), "sample not covered (ring)": (140, 140, 140),
                 "sample where the rasterizer and the convention differ (thick ring)": (221, 0, 0),
                 "alpha of an offending pixel (anti-aliased; k/N: k of the N samples)": (0, 40, 170)}
_HIT, _MISS, _DIFFERS, _ALPHA = SAMPLE_LEGEND
# path crops and repros, over CROP_LEGEND's pixels and marks: the fill is the outline's
# colour at PATH_FILL_OPACITY (its swatch: that over white)
PATH_FILL_OPACITY = 0.16
_PATH_COLOUR: tuple[int, int, int] = (120, 40, 170)
_OTHER_PATH_COLOUR: tuple[int, int, int] = (150, 120, 60)


def _faint(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """``rgb`` at PATH_FILL_OPACITY over white."""
    r, g, b = (round(255 - PATH_FILL_OPACITY * (255 - c)) for c in rgb)
    return r, g, b


PATH_LEGEND = {
    "the numbered path (outlined; arrows: each edge's direction; ring: each contour's first vertex)": _PATH_COLOUR,
    "where its fill rule fills it (faint)": _faint(_PATH_COLOUR),
    "other paths (dashed outline; their arrows and rings likewise)": _OTHER_PATH_COLOUR,
    "where their fill rule fills them (faint)": _faint(_OTHER_PATH_COLOUR),
    "winding number of the pixel's sample: the rule fills it (bold)": (10, 10, 10),
    "winding number of the pixel's sample: the rule leaves it": (135, 135, 135),
}
_FILLED, _LEFT = list(PATH_LEGEND)[-2:]

# line crops and repros: the pixels in DIFF_LEGEND's colours (crops; without an oracle, and
# in repros, CROP_LEGEND's), the marks in CROP_LEGEND's, the vectors in these
LINE_LEGEND = {
    "the segment the failure names (thick; its number at its middle, an arrowhead for its direction; dotted: its "
    "rectangle, for rectangular lines)": (0, 100, 40),
    "other segments (a strip's segments joined; numbered and dotted likewise; a ring at each end point that is no "
    "joint)": (95, 95, 95),
    "joint: a vertex where one segment ends and the next starts": (255, 0, 150),
    "diamond test area of an offending pixel, diamond-exit rule (solid: the edges and corners it includes; dashed, "
    "hollow: those it excludes)": (160, 60, 0),
    "how many segments drew the pixel, where more than one did": (120, 0, 0),
}
_NAMED_SEGMENT, _OTHER_SEGMENT, _JOINT, _DIAMOND, _HITS = LINE_LEGEND


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


def svg_crop(positions: NDArray | PathScene | LineScene, coverage: Coverage, sample: tuple[float, float],
             window: tuple[int, int, int, int], marks: list[tuple[int, int]], numbered: int | None = None,
             convention: Convention | None = None, oracle: Coverage | None = None) -> str:
    """The pixel grid of a small window with its sample points, the covered pixels, the
    marked pixels outlined, and the triangles (or a path scene's paths, with the winding
    numbers of path ``numbered``; or a line scene's segments, segment ``numbered`` thick:
    see :func:`svg_window`) drawn as vectors over them (SVG data URI).

    For a line scene given the ``oracle``'s coverage, the pixels are coloured as the diff
    against it colours them, segment by segment (DIFF_LEGEND): extra where some segment
    drew a pixel the oracle's same segment does not (a joint drawn by both its segments),
    else missing where some segment lacks one, else both; and each pixel more than one
    segment drew shows how many did."""
    x0, y0, x1, y1 = window
    t, x, y = coverage.pixels()
    inside = (x >= x0) & (x < x1) & (y >= y0) & (y < y1)
    covered = np.zeros((y1 - y0, x1 - x0), dtype=bool)
    covered[y[inside] - y0, x[inside] - x0] = True
    if not isinstance(positions, LineScene):
        return svg_window(positions, covered, CROP_LEGEND[_DRAWN], sample, window, marks,
                          numbered=numbered, convention=convention)
    hits = np.zeros((y1 - y0, x1 - x0), dtype=np.int64)
    np.add.at(hits, (y[inside] - y0, x[inside] - x0), 1)
    fills = [(covered, CROP_LEGEND[_DRAWN])]
    if oracle is not None:
        classes = []
        for fragments in deviations(coverage, oracle, positions.width, positions.height):  # missing, then extra
            _, fx, fy = fragments
            mine = (fx >= x0) & (fx < x1) & (fy >= y0) & (fy < y1)
            mask = np.zeros_like(covered)
            mask[fy[mine] - y0, fx[mine] - x0] = True
            classes.append(mask)
        missing, extra = classes
        fills = [(covered & ~missing & ~extra, DIFF_LEGEND["both"]), (missing & ~extra, DIFF_LEGEND["missing (oracle only)"]),
                 (extra, DIFF_LEGEND["extra (rasterizer only)"])]
    return svg_window(positions, None, CROP_LEGEND[_DRAWN], sample, window, marks,
                      numbered=numbered, convention=convention, fills=fills, hits=hits)


def svg_window(positions: NDArray | PathScene | LineScene, covered: NDArray | None, fill: tuple[int, int, int],
               sample: tuple[float, float] | None, window: tuple[int, int, int, int], marks: list[tuple[int, int]], fit: int = 384,
               numbered: int | None = None, convention: Convention | None = None,
               fills: list[tuple[NDArray, tuple[int, int, int]]] | None = None, hits: NDArray | None = None) -> str:
    """A window of the viewport as an SVG data URI, scaled to fit ``fit`` px (at most 24 px
    a pixel): the covered pixels filled, the pixel grid and the sample points when the
    pixels are drawn large enough to show them, the marked pixels outlined and the
    triangles drawn as vectors over them.

    Given a path scene instead of triangles, each path is drawn as one SVG ``<path>`` of
    its contours under the scene's fill rule (:func:`_svg_paths`), and, when the window
    is at most :data:`MAX_NUMBERED_SIDE` pixels a side and drawn large enough, each
    pixel shows the winding number of its sample around path ``numbered``
    (:func:`winding_numbers`, exact), bold where the fill rule fills it (PATH_LEGEND).

    Given a line scene, each strip is drawn as a polyline from end point to end point
    (:func:`_svg_lines`): segment ``numbered`` thick, every segment numbered with an
    arrowhead, the joints as dots, and, by the convention's line rule, the diamond test
    area of each marked pixel (diamond-exit) or each segment's rectangle (rectangle)
    (LINE_LEGEND).

    Parameters
    ----------
    positions : (N, 3, 2) float64, PathScene or LineScene
    covered : (y1 - y0, x1 - x0) bool or None
        The pixels of the window to fill with ``fill``.
    sample : (float, float) or None
        The sample point in the pixel; None draws none.
    window : (x0, y0, x1, y1)
    marks : list of (x, y)
        Pixels to outline; those outside the window are left out.
    numbered : int or None
        Paths: the path whose winding numbers are written (None: none written). Lines: the
        segment drawn thick (None: none).
    convention : Convention or None
        Paths: the single-sample convention the winding numbers follow (its sample point,
        tie rule and snapping); None: ``sample`` (the centre without one), top-left ties,
        no snapping. Lines: the convention whose line rule says what to draw besides the
        segments (None: nothing).
    fills : list of ((y1 - y0, x1 - x0) bool, rgb), optional
        More pixels to fill, each mask in its colour, after ``covered``.
    hits : (y1 - y0, x1 - x0) int, optional
        Lines: how many segments drew each pixel; written where more than one did.
    """
    text = _svg_window_text(positions, covered, fill, sample, window, marks, fit, numbered, convention, fills, hits)
    return "data:image/svg+xml;base64," + base64.b64encode(text.encode()).decode("ascii")


def _svg_window_text(positions: NDArray | PathScene | LineScene, covered: NDArray | None, fill: tuple[int, int, int],
                     sample: tuple[float, float] | None, window: tuple[int, int, int, int], marks: list[tuple[int, int]],
                     fit: int = 384, numbered: int | None = None, convention: Convention | None = None,
                     fills: list[tuple[NDArray, tuple[int, int, int]]] | None = None, hits: NDArray | None = None,
                     samples: Samples | None = None, alpha: NDArray | None = None,
                     at: tuple[float, float] | None = None, windings: bool = True,
                     labels: dict[tuple[int, int], str] | None = None, region: NDArray | None = None) -> str:
    """:func:`svg_window`'s picture as SVG text (placed ``at`` (x, y) screen px in an
    enclosing SVG when given), with two layers more: ``samples`` (:class:`Samples`, drawn
    instead of ``sample``) and ``alpha`` ((rows, cols) float: each pixel filled with
    ``fill`` at that opacity, for anti-aliased coverage); ``windings`` False writes no
    winding numbers (a path scene's); ``labels`` ((x, y) -> text) writes a pixel's alpha
    in it (SAMPLE_LEGEND); ``region`` ((M, 2) float64) outlines a partition's region."""
    x0, y0, x1, y1 = window
    cols, rows = x1 - x0, y1 - y0
    scale = min(24.0, fit / max(cols, rows, 1))  # screen px per pixel
    thin = 'vector-effect="non-scaling-stroke"'
    place = "" if at is None else f'x="{at[0]:g}" y="{at[1]:g}" '
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" {place}width="{round(cols * scale)}" height="{round(rows * scale)}" '
             f'viewBox="{x0} {y0} {cols} {rows}">',
             f'<rect x="{x0}" y="{y0}" width="{cols}" height="{rows}" fill="white"/>']
    if covered is not None and covered.any():
        # one rectangle per run of covered pixels in a row
        edges = np.diff(np.pad(covered.astype(np.int8), ((0, 0), (1, 1))), axis=1)
        starts, ends = np.argwhere(edges == 1), np.argwhere(edges == -1)  # row-major: pairs line up
        colour = _hex(fill)
        parts.extend(f'<rect x="{x0 + a}" y="{y0 + j}" width="{b - a}" height="1" fill="{colour}"/>'
                     for (j, a), (_, b) in zip(starts.tolist(), ends.tolist()))
    if alpha is not None:
        colour = _hex(fill)
        parts.extend(f'<rect x="{x0 + i}" y="{y0 + j}" width="1" height="1" fill="{colour}" fill-opacity="{min(a, 1.0):.3f}">'
                     f'<title>alpha {a:.4g}</title></rect>' for (j, i), a in np.ndenumerate(alpha) if a > 0)
    for mask, rgb in fills or ():
        if mask.any():
            runs = np.diff(np.pad(mask.astype(np.int8), ((0, 0), (1, 1))), axis=1)
            parts.extend(f'<rect x="{x0 + a}" y="{y0 + j}" width="{b - a}" height="1" fill="{_hex(rgb)}"/>'
                         for (j, a), (_, b) in zip(np.argwhere(runs == 1).tolist(), np.argwhere(runs == -1).tolist()))
    if scale >= 4:
        parts.extend(f'<line x1="{x0 + i}" y1="{y0}" x2="{x0 + i}" y2="{y1}" stroke="#999" stroke-width="0.5" {thin}/>'
                     for i in range(cols + 1))
        parts.extend(f'<line x1="{x0}" y1="{y0 + j}" x2="{x1}" y2="{y0 + j}" stroke="#999" stroke-width="0.5" {thin}/>'
                     for j in range(rows + 1))
    if samples is not None and scale >= 8:
        parts.extend(_svg_samples(samples, window, scale))
    elif sample is not None and scale >= 8:
        parts.extend(f'<circle cx="{x0 + i + sample[0]:g}" cy="{y0 + j + sample[1]:g}" r="{1.5 / scale:.4f}" fill="#333"/>'
                     for i in range(cols) for j in range(rows))
    if region is not None and np.isfinite(region).all():
        points = " ".join(f"{vx:.9g},{vy:.9g}" for vx, vy in np.clip(region, -1e6, 1e6))
        parts.append(f'<polygon points="{points}" fill="none" stroke="{_hex(CROP_LEGEND[_REGION])}" stroke-width="2" '
                     f'stroke-dasharray="2 3" {thin}><title>the region of the partition</title></polygon>')
    if labels and scale >= 10:
        font = min(max(9.0 / scale, 0.22), 0.4)
        parts.extend(f'<text x="{x + 0.5:g}" y="{y + 0.08 + font * 0.75:.4f}" font-size="{font:.3f}" font-family="sans-serif" '
                     f'font-weight="bold" text-anchor="middle" fill="{_hex(SAMPLE_LEGEND[_ALPHA])}" stroke="white" '
                     f'stroke-width="2" paint-order="stroke" {thin}><title>alpha of pixel ({x}, {y})</title>{text}</text>'
                     for (x, y), text in labels.items() if x0 <= x < x1 and y0 <= y < y1)
    inset = min(1.0 / scale, 0.25)
    red = _hex(CROP_LEGEND["offending pixel (outlined)"])
    for mx, my in marks:
        if x0 <= mx < x1 and y0 <= my < y1:
            parts.append(f'<rect x="{mx + inset:.4f}" y="{my + inset:.4f}" width="{1 - 2 * inset:.4f}" height="{1 - 2 * inset:.4f}" '
                         f'fill="none" stroke="{red}" stroke-width="2" {thin}/>')
    if isinstance(positions, PathScene):
        parts.extend(_svg_paths(positions, window, scale, numbered))
        if windings and numbered is not None and max(cols, rows) <= MAX_NUMBERED_SIDE and scale >= 10:
            chosen = convention if convention is not None else Convention(sample=sample or (0.5, 0.5))
            parts.extend(_svg_windings(positions, numbered, chosen, window, scale))
        parts.append("</svg>")
        return "".join(parts)
    if isinstance(positions, LineScene):
        parts.extend(_svg_lines(positions, window, scale, numbered, convention, marks))
        if hits is not None and scale >= 10:
            parts.extend(_svg_hits(hits, window, scale))
        parts.append("</svg>")
        return "".join(parts)
    finite = np.all(np.isfinite(positions), axis=(1, 2))
    near = finite & np.any((positions[..., 0] > x0 - 64) & (positions[..., 0] < x1 + 64), axis=1)
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    for tri in positions[near][:200]:
        pts = " ".join(f"{vx:.6g},{vy:.6g}" for vx, vy in np.clip(tri, -1e6, 1e6))
        parts.append(f'<polygon points="{pts}" fill="none" stroke="{blue}" stroke-width="1" {thin}/>')
    parts.append("</svg>")
    return "".join(parts)


@dataclass(frozen=True, slots=True)
class Samples:
    """The samples of a window drawn in its pixels (SAMPLE_LEGEND).

    Parameters
    ----------
    offsets : (S, 2) float64
        The pattern: each sample's position in its pixel.
    hits : (rows, cols, S) bool
        Which samples of each pixel of the window are covered.
    differs : (rows, cols, S) bool or None
        The samples where the rasterizer and the convention disagree (ringed thick).
    """

    offsets: NDArray[np.float64]
    hits: NDArray[np.bool_]
    differs: NDArray[np.bool_] | None = None


def sample_hits(scene: AnyScene, convention: Convention, window: tuple[int, int, int, int],
                coverage: Coverage | None = None, only: list[int] | None = None) -> NDArray[np.bool_]:
    """(rows, cols, S) bool: which samples of the convention's pattern each pixel of the
    window has covered: by ``coverage`` (a multisample answer, its sample indices the
    pattern's), else by the convention itself (its exact oracle, sample by sample: for a
    supersampled area convention too); by the primitives ``only`` when given.

    >>> from harness.contract.scenes import Scene
    >>> square = Scene(2, 1, [[[0, 0], [1, 0], [0, 1]]])
    >>> sample_hits(square, Convention(samples=4), (0, 0, 2, 1))[0].astype(int).tolist()
    [[1, 0, 1, 0], [0, 0, 0, 0]]
    """
    x0, y0, x1, y1 = window
    count = convention.n_samples
    out = np.zeros((y1 - y0, x1 - x0, count), dtype=bool)
    for k in range(count):
        layer = coverage.layer(k) if coverage is not None else exact_coverage(scene, convention.at_sample(k))
        out[..., k] = _of(layer, only).counts(scene.width, scene.height)[y0:y1, x0:x1] > 0
    return out


def _of(coverage: Coverage, only: list[int] | None) -> Coverage:
    """The coverage of the primitives ``only`` (all of it for None)."""
    return coverage if only is None else coverage.take(np.flatnonzero(np.isin(coverage.primitive, only)))


def _svg_samples(samples: Samples, window: tuple[int, int, int, int], scale: float) -> list[str]:
    """Each sample of each pixel of the window: a dot where covered, a ring where not, a
    thick red ring around those where the rasterizer and the convention differ."""
    x0, y0, _, _ = window
    count = samples.offsets.shape[0]
    r = min(0.09, max(1.2 / scale, 0.35 / math.sqrt(count) / 2))
    thin = 'vector-effect="non-scaling-stroke"'
    hit, miss, red = _hex(SAMPLE_LEGEND[_HIT]), _hex(SAMPLE_LEGEND[_MISS]), _hex(SAMPLE_LEGEND[_DIFFERS])
    out = []
    for (j, i, k), covered in np.ndenumerate(samples.hits):
        cx, cy = x0 + i + float(samples.offsets[k, 0]), y0 + j + float(samples.offsets[k, 1])
        if covered:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r:.4f}" fill="{hit}"/>')
        else:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r * 0.8:.4f}" fill="none" stroke="{miss}" stroke-width="1" {thin}/>')
        if samples.differs is not None and samples.differs[j, i, k]:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r * 1.9:.4f}" fill="none" stroke="{red}" stroke-width="2" {thin}>'
                       f'<title>sample {k} of pixel ({x0 + i}, {y0 + j}): {"covered" if covered else "not covered"} here, '
                       f'the other way in the other picture</title></circle>')
    return out


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


# -- paths: winding numbers and outlines ---------------------------------------------------

MAX_NUMBERED_SIDE = 32  # px: windows up to this many pixels a side show winding numbers
MAX_DRAWN_VERTICES = 20_000  # per picture: paths beyond it (after clipping) are left out, and counted


def _numbering_convention(convention: Convention | None) -> Convention:
    """The single-sample convention a path picture's winding numbers follow: the
    drawing's (its first sample's for a multisample one); the centre, top-left ties and
    no snapping without one."""
    if convention is None:
        return Convention()
    return convention.at_sample(0) if convention.samples is not None else convention


def winding_numbers(scene: PathScene, path: int, convention: Convention, window: tuple[int, int, int, int]) -> NDArray[np.int64] | None:
    """The exact winding number of every sample of a window around one path.

    Sample ``p = (i + sx, j + sy)`` of pixel (i, j) is taken at the tie rule's perturbed
    point, exactly as the oracle does (:mod:`harness.oracle.winding`): a vertex on the sample row
    lies below it when ``vy > ys`` or ``vy == ys`` and the perturbation moves up; an edge
    crosses the row when exactly one end lies below; its crossing is right of the sample
    when the exact ``sign E_ab(p) * dir`` is positive, or, on the edge's line, when the
    tie rule says so. The number is the sum of ``dir`` (+1 for an edge running down the
    screen, -1 up) over the crossings right of the sample: +1 inside a contour running
    clockwise on screen (signed area A > 0). (The oracle counts the crossings left of the
    sample, the same number negated: neither rule cares.) So the fill rule's verdict on
    each number is the oracle's, ties included.

    Only the edges whose y extent meets the window's sample rows and whose x extent
    reaches its first sample column are looked at, so a path of 100,000 vertices costs a
    filter over its edges; where a row crosses an edge is found for all such (edge, row)
    pairs at once, by bisection over the window's columns with the exact predicate
    (:func:`harness.geometry.exact.orientation`): "right of the crossing" is monotone along a row.

    Parameters
    ----------
    scene : PathScene
    path : int
    convention : Convention
        Single-sample: its sample point, tie rule and snapping (applied to every vertex
        first) apply.
    window : (x0, y0, x1, y1)

    Returns
    -------
    (y1 - y0, x1 - x0) int64, or None when the path has a NaN or infinite vertex (after
    snapping): it covers nothing and has no winding number.

    Examples
    --------
    A pentagram, rows 3 to 5: 2 in the centre pentagon (nonzero fills it, even-odd does
    not), 1 in its points.

    >>> import math
    >>> star = [[4 + 3.6 * math.sin(k * 4 * math.pi / 5), 4 - 3.6 * math.cos(k * 4 * math.pi / 5)] for k in range(5)]
    >>> winding_numbers(PathScene.from_paths(8, 8, [[star]]), 0, Convention(), (1, 3, 7, 6))
    array([[1, 1, 2, 2, 1, 1],
           [0, 0, 2, 2, 0, 0],
           [0, 1, 1, 1, 1, 0]])
    """
    if not convention.model.single_sample:
        raise ValueError(f"winding_numbers takes a single-sample convention, not kind {convention.kind!r}")
    x0, y0, x1, y1 = window
    cols, rows = x1 - x0, y1 - y0
    out = np.zeros((rows, cols), dtype=np.int64)
    start, end, owner = scene.edges()
    mine = owner == path
    a, b = convention.snap(start[mine]), convention.snap(end[mine])
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        return None
    if rows <= 0 or cols <= 0:
        return out
    sx, sy = convention.sample
    tx, ty, y_first = convention.tie_perturbation
    xs = np.arange(x0, x1, dtype=np.float64) + sx  # exact: |i| < 2**20, sx a multiple of 2**-32
    ys = np.arange(y0, y1, dtype=np.float64) + sy
    # an edge wholly left of every sample has its crossing left of them all: it adds nothing
    keep = ((a[:, 1] != b[:, 1]) & (np.maximum(a[:, 1], b[:, 1]) >= ys[0]) & (np.minimum(a[:, 1], b[:, 1]) <= ys[-1])
            & (np.maximum(a[:, 0], b[:, 0]) >= xs[0]))
    a, b = a[keep], b[keep]
    direction = np.where(b[:, 1] > a[:, 1], 1, -1)

    def below(v: NDArray[np.float64]) -> NDArray[np.bool_]:
        # the perturbed row moves up (ty < 0): a vertex on it lies below it
        return (v[None, :] > ys[:, None]) | ((v[None, :] == ys[:, None]) & (ty < 0))

    row, edge = np.nonzero(below(a[:, 1]) != below(b[:, 1]))  # (edge, row) pairs that cross
    ea, eb, d = a[edge], b[edge], direction[edge]
    # on the edge's line the tie rule decides (harness.oracle.winding._tie_right)
    if y_first:
        tie_right = np.where(ea[:, 0] != eb[:, 0], ((eb[:, 0] > ea[:, 0]) == (eb[:, 1] > ea[:, 1])) != (ty > 0), tx > 0)
    else:
        tie_right = np.full(edge.size, tx > 0)
    # the first column whose sample is right of the crossing, in 0 .. cols: from the float
    # crossing where no sample lies within its error bound, else by bisection with the exact
    # predicate. Each of the six operations errs by at most half an ulp (2**-48 relative is
    # a wide berth) unless the product underflows (factors of at least 2**-400 cannot; the
    # absolute 2**-1000 covers an underflowing quotient); an overflow leaves no finite bound.
    with np.errstate(all="ignore"):
        rise, width = ys[row] - ea[:, 1], eb[:, 0] - ea[:, 0]
        run = rise * width / (eb[:, 1] - ea[:, 1])
        crossing = ea[:, 0] + run
        bound = 2.0**-48 * (np.abs(ea[:, 0]) + np.abs(run)) + 2.0**-1000
        guess = np.searchsorted(xs, crossing, side="right")  # samples xs < guess are <= the crossing
        left_ok = (guess == 0) | (crossing - xs[np.maximum(guess - 1, 0)] > bound)
        right_ok = (guess == cols) | (xs[np.minimum(guess, cols - 1)] - crossing > bound)
        normal = ((rise == 0) | (np.abs(rise) >= 2.0**-400)) & ((width == 0) | (np.abs(width) >= 2.0**-400))
    certain = left_ok & right_ok & normal & np.isfinite(bound)
    lo = np.where(certain, guess, np.where(np.minimum(ea[:, 0], eb[:, 0]) > xs[-1], cols, 0))  # wholly right: none is right of it
    hi = np.where(certain, guess, cols)
    while True:
        active = np.flatnonzero(lo < hi)
        if not active.size:
            break
        mid = (lo[active] + hi[active]) // 2
        p = np.stack([xs[mid], ys[row[active]]], axis=1)
        s = orientation(np.stack([ea[active], eb[active], p], axis=1)).astype(np.int64)
        right = np.where(s != 0, s * d[active] < 0, tie_right[active])
        hi[active[right]] = mid[right]
        lo[active[~right]] = mid[~right] + 1
    # each crossing adds dir to the samples left of it: columns 0 .. lo - 1 of its row
    delta = np.zeros((rows, cols + 1), dtype=np.int64)
    np.add.at(delta, (row, np.zeros_like(row)), d)
    np.add.at(delta, (row, lo), -d)
    out[:] = np.cumsum(delta, axis=1)[:, :cols]
    return out


def rule_fills(winding: NDArray[np.int64], fill_rule: str) -> NDArray[np.bool_]:
    """Where ``fill_rule`` fills: ``nonzero`` w != 0, ``evenodd`` w odd.

    >>> rule_fills(np.array([0, 1, 2, -1]), "evenodd")
    array([False,  True, False,  True])
    """
    if fill_rule == "evenodd":
        return np.asarray(winding % 2 == 1)
    if fill_rule == "nonzero":
        return np.asarray(winding != 0)
    raise ValueError(f"fill_rule must be nonzero or evenodd, not {fill_rule!r}")


def numbered_path(result: Result) -> int | None:
    """The path whose winding numbers a path failure's crop writes: the one its evidence
    names (:func:`focus_path`); else the first path the rasterizer or the oracle covers at
    the first offending pixel; else the first path whose box holds that pixel; None for a
    result without a drawing of a path scene, or a scene without paths there."""
    drawing = result.drawing
    scene = getattr(drawing.case, "scene", None) if drawing is not None else None
    if drawing is None or not isinstance(scene, PathScene) or len(scene) == 0:
        return None
    named = focus_path(result)
    if named is not None and 0 <= named < len(scene):
        return named
    marks = _focus(result)
    fx, fy = marks[0] if marks else (scene.width // 2, scene.height // 2)
    for coverage in (*drawing.coverages[:1], *(drawing.oracles or ())[:1]):
        p, x, y = coverage.pixels()
        here = p[(x == fx) & (y == fy) & (p >= 0) & (p < len(scene))]
        if here.size:
            return int(here.min())
    lo, hi, finite = scene.primitive_boxes()
    holds = finite & (lo[:, 0] <= fx + 1) & (hi[:, 0] >= fx) & (lo[:, 1] <= fy + 1) & (hi[:, 1] >= fy)
    return int(np.flatnonzero(holds)[0]) if holds.any() else None


def _clip_contour(points: NDArray[np.float64], box: tuple[float, float, float, float]) -> NDArray[np.float64]:
    """A closed contour clipped to the box (xmin, ymin, xmax, ymax), Sutherland-Hodgman:
    each excursion outside a side is replaced by the chord along it, which leaves the
    winding number of every point inside the box as it was (the excursion and the chord
    enclose only points outside). Float arithmetic: for drawing, never for a verdict.

    >>> _clip_contour(np.array([[-4.0, -4.0], [4.0, -4.0], [4.0, 4.0]]), (0.0, 0.0, 8.0, 8.0)).tolist()
    [[4.0, 0.0], [4.0, 4.0], [0.0, 0.0]]
    """
    # in units of a power of two >= the largest coordinate (exact), so no difference overflows
    magnitude = float(np.abs(points).max(initial=0.0))
    unit = 2.0 ** math.ceil(math.log2(magnitude)) if magnitude > 1.0 else 1.0
    p = points / unit
    for axis, bound, keep_above in ((0, box[0], True), (1, box[1], True), (0, box[2], False), (1, box[3], False)):
        if not p.shape[0]:
            break
        q = np.roll(p, -1, axis=0)  # each vertex's successor: edge p -> q
        edge = bound / unit
        inside = p[:, axis] >= edge if keep_above else p[:, axis] <= edge
        crossing = inside != np.roll(inside, -1)
        with np.errstate(all="ignore"):
            t = (edge - p[:, axis]) / (q[:, axis] - p[:, axis])
            cut = p + t[:, None] * (q - p)
        cut[:, axis] = edge
        # per edge: its start when inside, then the crossing point when it crosses
        p = np.stack([p, cut], axis=1)[np.stack([inside, crossing], axis=1)]
    repeated = np.all(p == np.roll(p, 1, axis=0), axis=1)  # a vertex on the side is emitted twice
    if repeated.all():
        return p[:0]
    return p[~repeated] * unit


def _svg_paths(scene: PathScene, window: tuple[int, int, int, int], scale: float, numbered: int | None) -> list[str]:
    """The SVG of the paths near the window: each path's contours, clipped to the window
    grown by 2 px, as one ``<path>`` under the scene's fill rule (faint fill, outline;
    other paths than ``numbered`` dashed), an arrowhead on each edge long enough on screen
    at the middle of its visible part, and a ring at each contour's first vertex."""
    x0, y0, x1, y1 = window
    margin = 2.0
    box = (x0 - margin, y0 - margin, x1 + margin, y1 + margin)
    thin = 'vector-effect="non-scaling-stroke"'
    rule = "evenodd" if scene.fill_rule == "evenodd" else "nonzero"
    lo, hi, finite = scene.primitive_boxes()
    near = np.flatnonzero(finite & (lo[:, 0] <= box[2]) & (hi[:, 0] >= box[0]) & (lo[:, 1] <= box[3]) & (hi[:, 1] >= box[1]))
    # the numbered path last: drawn on top of the others
    near = np.concatenate([near[near != numbered], near[near == numbered]])[-200:]
    contours = scene.contours()
    by_path: dict[int, list[int]] = {}
    for c, p in enumerate(scene.contour_path.tolist()):
        by_path.setdefault(p, []).append(c)
    parts: list[str] = []
    budget, left_out = MAX_DRAWN_VERTICES, 0
    starts: list[tuple[NDArray[np.float64], tuple[int, int, int]]] = []
    segments: list[tuple[NDArray[np.float64], NDArray[np.float64], tuple[int, int, int]]] = []
    for p in near.tolist():
        colour = _PATH_COLOUR if p == numbered else _OTHER_PATH_COLOUR
        clipped = [_clip_contour(contours[c], box) for c in by_path.get(p, [])]
        size = sum(c.shape[0] for c in clipped)
        if size > budget:
            left_out += 1
            continue
        budget -= size
        d = " ".join("M" + " L".join(f"{vx:.9g},{vy:.9g}" for vx, vy in c) + " Z" for c in clipped if c.shape[0] >= 2)
        if d:
            dash = "" if p == numbered else ' stroke-dasharray="4 3"'
            parts.append(f'<path d="{d}" fill="{_hex(colour)}" fill-opacity="{PATH_FILL_OPACITY}" fill-rule="{rule}" '
                         f'stroke="{_hex(colour)}" stroke-width="{1.5 if p == numbered else 1}"{dash} {thin}/>')
        for c in by_path.get(p, []):
            starts.append((contours[c][0], colour))
            segments.append((contours[c], np.roll(contours[c], -1, axis=0), colour))
    parts.extend(_svg_arrows(segments, window, scale))
    ring = 3.0 / scale
    for v, colour in starts:
        if x0 - ring <= v[0] <= x1 + ring and y0 - ring <= v[1] <= y1 + ring:
            parts.append(f'<circle cx="{v[0]:.9g}" cy="{v[1]:.9g}" r="{ring:.4f}" fill="none" stroke="{_hex(colour)}" '
                         f'stroke-width="1.5" {thin}/>')
    if left_out:
        parts.append(f'<text x="{x0 + 0.1:g}" y="{y1 - 0.15:g}" font-size="{11 / scale:.4f}" font-family="sans-serif" '
                     f'fill="#333">{left_out} path{"" if left_out == 1 else "s"} not drawn: more than '
                     f'{MAX_DRAWN_VERTICES} vertices in view</text>')
    return parts


def _svg_arrows(segments: list[tuple[NDArray[np.float64], NDArray[np.float64], tuple[int, int, int]]],
                window: tuple[int, int, int, int], scale: float, limit: int = 400) -> list[str]:
    """An arrowhead (7 screen px) at the middle of the visible part of each edge a -> b
    whose visible part is at least three arrowheads long on screen; at most ``limit``."""
    x0, y0, x1, y1 = window
    size = 7.0 / scale
    out: list[str] = []
    for a, b, colour in segments:
        with np.errstate(all="ignore"):
            d = b - a
            # Liang-Barsky: the parameter range [t0, t1] of a + t d inside the window
            t0, t1 = np.zeros(a.shape[0]), np.ones(a.shape[0])
            for axis, low, high in ((0, x0, x1), (1, y0, y1)):
                u = (low - a[:, axis]) / d[:, axis]
                v = (high - a[:, axis]) / d[:, axis]
                t0 = np.maximum(t0, np.where(d[:, axis] != 0, np.minimum(u, v), np.where(a[:, axis] >= low, -np.inf, np.inf)))
                t1 = np.minimum(t1, np.where(d[:, axis] != 0, np.maximum(u, v), np.where(a[:, axis] <= high, np.inf, -np.inf)))
            length = np.hypot(d[:, 0], d[:, 1])
            shown = (t1 - t0) * length
            ok = np.isfinite(shown) & (shown >= 3 * size) & np.isfinite(length) & (length > 0)
            for k in np.flatnonzero(ok)[: max(limit - len(out), 0)]:
                u_ = d[k] / length[k]
                tip = a[k] + (t0[k] + t1[k]) / 2 * d[k] + u_ * size / 2
                base = tip - u_ * size
                n = np.array([-u_[1], u_[0]]) * size / 3
                pts = " ".join(f"{px:.9g},{py:.9g}" for px, py in (tip, base + n, base - n))
                out.append(f'<polygon points="{pts}" fill="{_hex(colour)}"/>')
    return out


def _svg_windings(scene: PathScene, path: int, convention: Convention, window: tuple[int, int, int, int],
                  scale: float) -> list[str]:
    """The winding number of each pixel's sample around ``path`` as small text in the
    pixel (about 7 screen px high, 0.3 to 0.45 px), in the corner away from the sample
    point: bold near-black where the scene's fill rule fills it, grey where not (PATH_LEGEND)."""
    x0, y0, _, _ = window
    font = min(max(7.0 / scale, 0.3), 0.45)
    winding = winding_numbers(scene, path, convention, window)
    if winding is None:
        return []
    filled = rule_fills(winding, scene.fill_rule)
    sx, sy = convention.sample
    dx = 0.06 if sx >= 0.5 else 0.5  # away from the sample point
    dy = 0.06 + font if sy >= 0.5 else 0.94
    out = [f'<g font-family="sans-serif" font-size="{font:.3f}"><title>winding numbers around path {path} '
           f'({scene.fill_rule} rule)</title>']
    bold = f'font-weight="bold" fill="{_hex(PATH_LEGEND[_FILLED])}"'
    grey = f'fill="{_hex(PATH_LEGEND[_LEFT])}"'
    for (j, i), w in np.ndenumerate(winding):
        style = bold if filled[j, i] else grey
        out.append(f'<text x="{x0 + i + dx:g}" y="{y0 + j + dy:g}" {style}>{int(w)}</text>')
    out.append("</g>")
    return out


# -- lines: segments over the pixel grid, joints, diamonds ---------------------------------

LINE_CROP_SIDE = 16  # px: a line failure's crop (a longer stretch of line than a triangle's 12)
MAX_DRAWN_SEGMENTS = 400  # per picture: the segments nearest in order beyond it are left out, and counted
_NOT_PIXELS = ("repro", "repro_path", "traceback", "series", "columns", "flaky", "samples")


def _pixel_rows(rows: list[Any], columns: Any) -> list[tuple[int, int]]:
    """The pixels of an evidence list, read from its first row's form: dicts with ``x``
    and ``y``, or ``pixel``/``vertex_pixel: [x, y]`` and ``pixels: [[x, y], ...]`` (each
    row's in that order); rows named by ``columns`` (with ``x`` and ``y``); ``[x, y]``
    pairs; ``[primitive, x, y]`` triples. Nothing when it holds none."""
    head = rows[0]
    try:
        if isinstance(head, dict):
            if "x" in head and "y" in head:
                return [(int(r["x"]), int(r["y"])) for r in rows if isinstance(r, dict) and "x" in r and "y" in r]
            out: list[tuple[int, int]] = []
            for r in rows:
                if not isinstance(r, dict):
                    continue
                named = [r[k] for k in ("pixel", "vertex_pixel") if isinstance(r.get(k), (list, tuple))]
                named += [v for v in r.get("pixels", ()) if isinstance(v, (list, tuple))] if isinstance(r.get("pixels"), list) else []
                out += [(int(v[0]), int(v[1])) for v in named if len(v) == 2]
            return list(dict.fromkeys(out))
        if not isinstance(head, (list, tuple)) or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool)
                                                          for v in head):
            return []
        if isinstance(columns, list) and "x" in columns and "y" in columns:
            ix, iy = columns.index("x"), columns.index("y")
        elif len(head) in (2, 3):
            ix, iy = len(head) - 2, len(head) - 1
        else:
            return []
        return [(int(r[ix]), int(r[iy])) for r in rows if isinstance(r, (list, tuple)) and len(r) > max(ix, iy)]
    except (TypeError, ValueError, IndexError, KeyError):
        return []


def line_focus(result: Result) -> list[tuple[int, int]]:
    """The offending pixels a failure on a line scene names, first the most telling: the
    first list of its evidence (in the check's order) that holds pixels (dicts with ``x``
    and ``y`` or lists of ``pixels``, ``[x, y]`` pairs, ``[segment, x, y]`` rows or rows
    named by ``columns``), else what :func:`_focus` finds.

    >>> line_focus(Result("r", "c", "joints", "fail", "m", {}, {"count": 1, "double_hits": [{"joint": [0, 1], "x": 4, "y": 2}]}))
    [(4, 2)]
    >>> line_focus(Result("r", "c", "connectivity", "fail", "m", {}, {"gaps": [[3, 7, 1]], "columns": ["segment", "x", "y"]}))
    [(7, 1)]
    >>> line_focus(Result("r", "c", "joints", "fail", "m", {}, {"joints": [{"segments": [0, 1], "pixels": [[4, 2], [5, 2]],
    ...                                                                      "vertex_pixel": [5, 2]}]}))
    [(5, 2), (4, 2)]
    """
    e = result.evidence
    for key, value in e.items():
        if key in _NOT_PIXELS or not isinstance(value, list) or not value:
            continue
        found = _pixel_rows(value, e.get("columns"))
        if found:
            return found
    return _focus(result)


def focus_segment(result: Result) -> int | None:
    """The segment a failure on a line scene names first, or None when its evidence names
    none: the first row of an evidence list that has ``segment`` (or ``segments``, a
    joint's pair, the first of them), or whose ``columns`` name one.

    >>> focus_segment(Result("r", "c", "conformance", "fail", "m", {}, {"pixels": [{"segment": 3, "x": 1, "y": 2}]}))
    3
    >>> focus_segment(Result("r", "c", "joints", "fail", "m", {}, {"double_hits": [{"segments": [4, 5], "x": 1, "y": 2}]}))
    4
    """
    e = result.evidence
    columns = e.get("columns")
    for key, value in e.items():
        if key in _NOT_PIXELS or not isinstance(value, list) or not value:
            continue
        head = value[0]
        try:
            if isinstance(head, dict):
                for name in ("segment", "segments", "joint"):
                    named = head.get(name)
                    if isinstance(named, (list, tuple)) and named:
                        return int(named[0])
                    if isinstance(named, (int, np.integer)) and not isinstance(named, bool):
                        return int(named)
            elif isinstance(head, (list, tuple)) and isinstance(columns, list) and "segment" in columns:
                return int(head[columns.index("segment")])
        except (TypeError, ValueError, IndexError):
            continue
    return None


def numbered_segment(result: Result) -> int | None:
    """The segment a line failure's crop draws thick: the one its evidence names
    (:func:`focus_segment`); else the first segment the rasterizer or the oracle drew at
    the first offending pixel; else the first whose box holds that pixel; None for a
    result without a drawing of a line scene, or a scene without segments there."""
    drawing = result.drawing
    scene = getattr(drawing.case, "scene", None) if drawing is not None else None
    if drawing is None or not isinstance(scene, LineScene) or len(scene) == 0:
        return None
    named = focus_segment(result)
    if named is not None and 0 <= named < len(scene):
        return named
    marks = line_focus(result)
    if not marks:
        return None
    fx, fy = marks[0]
    for coverage in (*drawing.coverages[:1], *(drawing.oracles or ())[:1]):
        k, x, y = coverage.pixels()
        here = k[(x == fx) & (y == fy) & (k >= 0) & (k < len(scene))]
        if here.size:
            return int(here.min())
    return _segment_at(scene, fx, fy)


def _segment_at(scene: LineScene, x: int, y: int) -> int | None:
    """The first segment whose box (grown by half the line width) meets pixel (x, y)."""
    lo, hi, finite = scene.primitive_boxes()
    holds = finite & (lo[:, 0] <= x + 1) & (hi[:, 0] >= x) & (lo[:, 1] <= y + 1) & (hi[:, 1] >= y)
    return int(np.flatnonzero(holds)[0]) if holds.any() else None


def _line_sample(convention: Convention | None) -> tuple[float, float]:
    """The point in each pixel a line picture dots: the convention's sample for
    rectangular lines; the centre otherwise (the diamond's centre; the pixel Bresenham
    steps through)."""
    if convention is not None and convention.line.rule == "rectangle":
        return convention.sample
    return 0.5, 0.5


def _line_oracle(drawing: Drawing, scene: LineScene) -> Coverage | None:
    """The oracle's coverage of the lines: the check's, else computed now; None without a
    convention or when it has no line oracle (multisample or area coverage)."""
    if drawing.oracles is not None:
        return drawing.oracles[0]
    if drawing.convention is None:
        return None
    try:
        return exact_coverage(scene, drawing.convention)
    except ValueError:  # lines are single-sample only
        return None


def _line_pictures(scene: LineScene, drawing: Drawing, result: Result) -> dict[str, str]:
    """A failure on a line scene: the hit counts (a joint drawn by both its segments is
    hit twice), the diff against the oracle, and a crop of the segments over the pixel
    grid around the first offending pixel (:func:`svg_crop`). When the evidence names no
    pixel (a segment drawn too long, say), the pixels where the segment it names (any
    segment, when it names none) departs from the oracle are marked; failing those, the
    crop shows the named segment's middle."""
    coverage = drawing.coverages[0]
    marks = line_focus(result)
    numbered = numbered_segment(result)
    oracle = _line_oracle(drawing, scene)
    if not marks and oracle is not None:
        wrong = np.concatenate(deviations(coverage, oracle, scene.width, scene.height), axis=1)  # (3, M): segment, x, y
        if numbered is not None and (wrong[0] == numbered).any():
            wrong = wrong[:, wrong[0] == numbered]
        inside = (wrong[1] >= 0) & (wrong[1] < scene.width) & (wrong[2] >= 0) & (wrong[2] < scene.height)
        marks = list(dict.fromkeys(zip(wrong[1, inside].tolist(), wrong[2, inside].tolist())))
    if marks:
        fx, fy = marks[0]
    elif numbered is not None and numbered in np.flatnonzero(scene.primitive_boxes()[2]):
        a, b = scene.segments()
        fx, fy = (int(np.clip(np.floor(v), -1, side)) for v, side in zip((a[numbered] + b[numbered]) / 2, (scene.width, scene.height)))
    else:
        fx, fy = scene.width // 2, scene.height // 2
    counts = coverage.counts(scene.width, scene.height)
    images = {"heatmap": heatmap(counts, None, None, window_around(fx, fy, scene.width, scene.height, 64))}
    if oracle is not None:
        images["diff"] = oracle_diff(scene.width, scene.height, counts > 0, oracle.counts(scene.width, scene.height) > 0,
                                     result.evidence.get("pixels", []) if result.check == "conformance" else [],
                                     window_around(fx, fy, scene.width, scene.height, 64))
    crop = window_around(fx, fy, scene.width, scene.height, LINE_CROP_SIDE)
    images["crop"] = svg_crop(scene, coverage, _line_sample(drawing.convention), crop, marks[:20], numbered=numbered,
                              convention=drawing.convention, oracle=oracle)
    return images


def _clip_parameters(a: NDArray[np.float64], b: NDArray[np.float64],
                     box: tuple[float, float, float, float]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Liang-Barsky: the parameter range [t0, t1] of ``a + t (b - a)``, 0 <= t <= 1, inside
    the box (xmin, ymin, xmax, ymax); empty (t0 > t1) when the segment misses it. Float
    arithmetic: for drawing, never for a verdict.

    >>> t0, t1 = _clip_parameters(np.array([[-2.0, 1.0]]), np.array([[6.0, 1.0]]), (0.0, 0.0, 4.0, 4.0))
    >>> t0.tolist(), t1.tolist()
    ([0.25], [0.75])
    """
    t0, t1 = np.zeros(a.shape[0]), np.ones(a.shape[0])
    with np.errstate(all="ignore"):
        d = b - a
        for axis, low, high in ((0, box[0], box[2]), (1, box[1], box[3])):
            u = (low - a[:, axis]) / d[:, axis]
            v = (high - a[:, axis]) / d[:, axis]
            moving = d[:, axis] != 0
            still_in = (a[:, axis] >= low) & (a[:, axis] <= high)
            t0 = np.maximum(t0, np.where(moving, np.minimum(u, v), np.where(still_in, -np.inf, np.inf)))
            t1 = np.minimum(t1, np.where(moving, np.maximum(u, v), np.where(still_in, np.inf, -np.inf)))
    return t0, t1


def _point(v: NDArray[np.float64]) -> str:
    return f"{v[0]:.9g},{v[1]:.9g}"


def _svg_lines(scene: LineScene, window: tuple[int, int, int, int], scale: float, named: int | None,
               convention: Convention | None, marks: list[tuple[int, int]]) -> list[str]:
    """The SVG of the segments near the window (clipped to it grown by 2 px): under the
    diamond-exit rule the diamond test area of each marked pixel first (:func:`_svg_diamond`),
    under the rectangle rule each segment's rectangle (dotted); each strip as polylines
    from end point to end point (the runs of its segments in view, joined), segment
    ``named`` thick on top; an arrowhead and a number on each segment; every joint as a
    dot and every other end point as a ring (LINE_LEGEND)."""
    x0, y0, x1, y1 = window
    margin = 2.0
    box = (x0 - margin, y0 - margin, x1 + margin, y1 + margin)
    thin = 'vector-effect="non-scaling-stroke"'
    parts: list[str] = []
    a, b = scene.segments()
    lo, hi, finite = scene.primitive_boxes()
    t0, t1 = _clip_parameters(np.where(finite[:, None], a, 0.0), np.where(finite[:, None], b, 0.0), box)
    seen = finite & (lo[:, 0] <= box[2]) & (hi[:, 0] >= box[0]) & (lo[:, 1] <= box[3]) & (hi[:, 1] >= box[1])
    rule = convention.line.rule if convention is not None else None
    gl = convention is not None and convention.line.gl
    wide = rule == "rectangle"
    in_view = np.flatnonzero(seen & ((t0 <= t1) | wide))
    if named is not None and named in in_view:  # the named segment is drawn, whatever the budget
        in_view = np.concatenate([[named], in_view[in_view != named]])
    shown, left_out = np.sort(in_view[:MAX_DRAWN_SEGMENTS]), max(in_view.size - MAX_DRAWN_SEGMENTS, 0)
    if convention is not None and convention.line.diamond:
        d = b[named] - a[named] if named is not None and finite[named] else np.zeros(2)
        y_major = bool(abs(d[1]) > abs(d[0]))  # the y-major test area holds its right corner too
        for mx, my in [m for m in marks if x0 <= m[0] < x1 and y0 <= m[1] < y1][:8]:
            parts.extend(_svg_diamond(mx, my, y_major, thin, gl))
    colour_of = {k: _NAMED_SEGMENT if k == named else _OTHER_SEGMENT for k in shown.tolist()}
    if wide:  # the rectangle of each segment: its sides at half the width, no end caps beyond the end points
        half = 0.5 * scene.line_width
        for k in shown.tolist():
            d = b[k] - a[k]
            length = float(np.hypot(*d))
            if not (length > 0 and np.isfinite(length)):
                continue
            n = np.array([-d[1], d[0]]) / length * half
            corners = np.array([a[k] + n, b[k] + n, b[k] - n, a[k] - n])
            clipped = _clip_contour(corners, box)
            if clipped.shape[0] >= 3:
                parts.append(f'<polygon points="{" ".join(_point(v) for v in clipped)}" fill="none" '
                             f'stroke="{_hex(LINE_LEGEND[colour_of[k]])}" stroke-width="1" stroke-dasharray="1 2" {thin}/>')
    with np.errstate(all="ignore"):  # segments out of view (or not finite) give inf and nan: never drawn
        p = a + t0[:, None] * (b - a)  # the visible part of each segment, p -> q
        q = a + t1[:, None] * (b - a)
    strip = scene.segment_strip
    runs: list[list[NDArray[np.float64]]] = []
    previous = -2
    for k in shown.tolist():
        if t0[k] > t1[k]:
            previous = -2
            continue
        joined = previous == k - 1 and strip[k] == strip[previous] and t1[previous] == 1.0 and t0[k] == 0.0
        if joined:
            runs[-1].append(q[k])
        else:
            runs.append([p[k], q[k]])
        previous = k
    other = _hex(LINE_LEGEND[_OTHER_SEGMENT])
    for run in runs:
        parts.append(f'<polyline points="{" ".join(_point(v) for v in run)}" fill="none" stroke="{other}" '
                     f'stroke-width="1.5" stroke-linejoin="round" {thin}/>')
    if named is not None and named in shown and t0[named] <= t1[named]:
        parts.append(f'<line x1="{p[named][0]:.9g}" y1="{p[named][1]:.9g}" x2="{q[named][0]:.9g}" y2="{q[named][1]:.9g}" '
                     f'stroke="{_hex(LINE_LEGEND[_NAMED_SEGMENT])}" stroke-width="3" stroke-linecap="round" {thin}/>')
    for colour in (_OTHER_SEGMENT, _NAMED_SEGMENT):
        mine = [k for k in shown.tolist() if colour_of[k] == colour]
        if mine:
            parts.extend(_svg_arrows([(a[mine], b[mine], LINE_LEGEND[colour])], window, scale))
    parts.extend(_svg_end_points(scene, box, scale, set(shown.tolist()), thin))
    parts.extend(_svg_segment_numbers(scene, shown, named, window, scale))
    if left_out:
        parts.append(f'<text x="{x0 + 0.1:g}" y="{y1 - 0.15:g}" font-size="{11 / scale:.4f}" font-family="sans-serif" '
                     f'fill="#333">{left_out} segment{"" if left_out == 1 else "s"} not drawn: more than '
                     f'{MAX_DRAWN_SEGMENTS} in view</text>')
    return parts


def _svg_diamond(i: int, j: int, y_major: bool, thin: str, gl: bool = False) -> list[str]:
    """The diamond-exit rule's test area of pixel (i, j) (:mod:`harness.oracle.lines`): the diamond
    |x - xc| + |y - yc| < 1/2 with its lower-left and lower-right edges and its bottom
    corner included (solid, a filled dot), its upper edges and top and left corners
    excluded (dashed, rings), its right corner included only for a y-major segment. GL's
    (``gl``): its right edges and right corner in, the rest out, for every segment."""
    colour = _hex(LINE_LEGEND[_DIAMOND])
    top, right, bottom, left = (i + 0.5, j), (i + 1.0, j + 0.5), (i + 0.5, j + 1.0), (i, j + 0.5)

    def at(v: tuple[float, float]) -> str:
        return f"{v[0]:g},{v[1]:g}"

    def corner(v: tuple[float, float], included: bool) -> str:
        style = f'fill="{colour}"' if included else f'fill="white" stroke="{colour}" stroke-width="1" {thin}'
        return f'<circle cx="{v[0]:g}" cy="{v[1]:g}" r="0.06" {style}/>'

    if gl:
        return [f'<g><title>GL test area of pixel ({i}, {j}) (end points moved by -(eps, eps^2)): right edges and right '
                f'corner in, left edges, top, bottom and left corners out</title>',
                f'<path d="M{at(top)} L{at(right)} L{at(bottom)}" fill="none" stroke="{colour}" stroke-width="2" {thin}/>',
                f'<path d="M{at(bottom)} L{at(left)} L{at(top)}" fill="none" stroke="{colour}" stroke-width="1.5" '
                f'stroke-dasharray="3 2" {thin}/>',
                corner(right, True), corner(bottom, False), corner(top, False), corner(left, False), "</g>"]
    return [f'<g><title>diamond test area of pixel ({i}, {j}): lower edges and bottom corner in, upper edges, top and '
            f'left corners out, right corner {"in (a y-major segment)" if y_major else "out (an x-major segment)"}</title>',
            f'<path d="M{at(right)} L{at(bottom)} L{at(left)}" fill="none" stroke="{colour}" stroke-width="2" {thin}/>',
            f'<path d="M{at(left)} L{at(top)} L{at(right)}" fill="none" stroke="{colour}" stroke-width="1.5" '
            f'stroke-dasharray="3 2" {thin}/>',
            corner(bottom, True), corner(right, y_major), corner(top, False), corner(left, False), "</g>"]


def _svg_end_points(scene: LineScene, box: tuple[float, float, float, float], scale: float, shown: set[int],
                    thin: str) -> list[str]:
    """Each joint of the drawn segments (a vertex where segment k ends and m starts) as a
    dot, every other end point of theirs as a ring in its segment's colour."""
    a, b = scene.segments()
    joints = scene.joints(closed=True)
    out: list[str] = []
    shared: set[tuple[int, int]] = set()  # (segment, 0 start | 1 end) of the joints' end points
    dot, ring = 3.5 / scale, 2.5 / scale
    colour = _hex(LINE_LEGEND[_JOINT])
    for k, m in joints.tolist():
        if k not in shown and m not in shown:
            continue
        shared |= {(k, 1), (m, 0)}
        v = b[k]
        if box[0] <= v[0] <= box[2] and box[1] <= v[1] <= box[3]:
            out.append(f'<circle cx="{v[0]:.9g}" cy="{v[1]:.9g}" r="{dot:.4f}" fill="{colour}"><title>joint: segment {k} '
                       f'ends where segment {m} starts</title></circle>')
    other = _hex(LINE_LEGEND[_OTHER_SEGMENT])
    for k in sorted(shown):
        for end, v in ((0, a[k]), (1, b[k])):
            if (k, end) not in shared and box[0] <= v[0] <= box[2] and box[1] <= v[1] <= box[3]:
                out.append(f'<circle cx="{v[0]:.9g}" cy="{v[1]:.9g}" r="{ring:.4f}" fill="none" stroke="{other}" '
                           f'stroke-width="1" {thin}/>')
    return out


def _svg_segment_numbers(scene: LineScene, shown: NDArray[np.int64], named: int | None, window: tuple[int, int, int, int],
                         scale: float, limit: int = 60) -> list[str]:
    """Each drawn segment's number at the middle of its part in the window, moved off the
    line by a third of a pixel on its left (as it runs), in its colour; at most ``limit``."""
    x0, y0, x1, y1 = window
    a, b = scene.segments()
    index = shown[:limit]
    t0, t1 = _clip_parameters(a[index], b[index], (float(x0), float(y0), float(x1), float(y1)))
    font = min(max(10.0 / scale, 0.3), 0.6)
    strips = scene.segment_strip
    out = []
    for k, s, e in zip(index.tolist(), t0.tolist(), t1.tolist()):
        d = b[k] - a[k]
        length = float(np.hypot(*d))
        if s > e or not length > 0:
            continue
        middle = a[k] + (s + e) / 2 * d
        off = np.array([d[1], -d[0]]) / length * (font * 0.8)  # left of the direction of travel (y down)
        at = middle + off
        colour = _hex(LINE_LEGEND[_NAMED_SEGMENT if k == named else _OTHER_SEGMENT])
        weight = ' font-weight="bold"' if k == named else ""
        out.append(f'<text x="{at[0]:.6g}" y="{at[1] + font / 3:.6g}" font-size="{font:.3f}" font-family="sans-serif" '
                   f'text-anchor="middle" fill="{colour}"{weight}><title>segment {k} (strip {int(strips[k])})</title>{k}</text>')
    return out


def _svg_hits(hits: NDArray, window: tuple[int, int, int, int], scale: float) -> list[str]:
    """How many segments drew each pixel of the window where more than one did, small, in
    the pixel's top-left corner (away from the centre and the diamond)."""
    x0, y0, _, _ = window
    font = min(max(8.0 / scale, 0.25), 0.4)
    colour = _hex(LINE_LEGEND[_HITS])
    return [f'<text x="{x0 + i + 0.05:g}" y="{y0 + j + 0.02 + font:g}" font-size="{font:.3f}" font-family="sans-serif" '
            f'font-weight="bold" fill="{colour}"><title>drawn by {int(n)} segments</title>{int(n)}</text>'
            for (j, i), n in np.ndenumerate(hits) if n > 1]


# -- the minimal repro ---------------------------------------------------------------------

MAX_REPRO_TRIANGLES = 200  # primitives: triangles, or paths
MAX_REPRO_SIDE = 512  # px: larger viewports are not drawn (the report stays cheap)


def _repro_window(positions: NDArray, width: int, height: int, least: int = 8) -> tuple[int, int, int, int]:
    """The viewport's part that holds the triangles (finite ones), a pixel around them, at
    least ``least`` pixels a side where the viewport allows."""
    return _points_window(positions[np.all(np.isfinite(positions), axis=(1, 2))].reshape(-1, 2), width, height, least)


def _points_window(finite: NDArray, width: int, height: int, least: int = 8) -> tuple[int, int, int, int]:
    """The viewport's part that holds the (finite) points ``finite`` (M, 2), a pixel around
    them, at least ``least`` pixels a side where the viewport allows."""
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


def _near_paths(marks: list[tuple[int, int]], scene: PathScene | LineScene, reach: float = 1.5) -> list[tuple[int, int]]:
    """The marked pixels whose centre lies within ``reach`` px of the box of one of the
    (finite) paths (segments: their boxes grown by half the line width): those of a whole
    case's evidence that can belong to its repro."""
    lo, hi, finite = scene.primitive_boxes()
    if not marks or not finite.any():
        return []
    c = np.asarray(marks, dtype=float) + 0.5  # (M, 2)
    lo, hi = lo[finite] - reach, hi[finite] + reach
    inside: NDArray[np.bool_] = np.all((c[:, None, :] >= lo[None]) & (c[:, None, :] <= hi[None]), axis=2)  # (M, P)
    return [m for m, ok in zip(marks, np.any(inside, axis=1).tolist()) if ok]


def _repro_numbered(result: Result, scene: PathScene, marks: list[tuple[int, int]]) -> int | None:
    """The repro's path to number: its only path; else the one with the vertices of the
    path the failure names in the whole case; else the first whose box holds the first
    marked pixel near it; else None."""
    if len(scene) == 1:
        return 0
    named = numbered_path(result)
    whole = getattr(result.drawing.case, "scene", None) if result.drawing is not None else None
    if named is not None and isinstance(whole, PathScene):
        wanted = [c.tolist() for c in whole.contours_of(named)]
        for p in range(len(scene)):
            if [c.tolist() for c in scene.contours_of(p)] == wanted:
                return p
    if marks:
        lo, hi, finite = scene.primitive_boxes()
        fx, fy = marks[0]
        holds = finite & (lo[:, 0] <= fx + 1) & (hi[:, 0] >= fx) & (lo[:, 1] <= fy + 1) & (hi[:, 1] >= fy)
        if holds.any():
            return int(np.flatnonzero(holds)[0])
    return None


def draw_repro(result: Result) -> tuple[str | None, str] | None:
    """The failure's minimal repro (``evidence["repro"]``, case JSON) drawn, with its
    caption: its triangles (or paths) over the pixel grid and, given a convention (the
    drawing's), the pixels that convention covers.

    A repro that keeps the rasterizer's answer on it (``answer``, and the check's evidence
    on it, ``evidence``: :func:`harness.diagnose.repro.attach_repro` writes both) is drawn twice
    side by side: on the left what the rasterizer drew, on the right what the convention
    says, the pixels that evidence names outlined on both (:func:`_repro_panels`); a
    multisample or supersampled convention's samples are drawn in every pixel, covered or
    not, those where the two differ ringed. An older repro, without them, is drawn once
    with the convention's pixels, and the pixels the evidence names (on the whole case)
    within a pixel and a half of the repro's primitives outlined.

    A path repro small enough shows the winding numbers of one of its paths
    (:func:`svg_window`); a line repro draws its segments as the crops do
    (:func:`_line_repro`).

    Returns None without a repro; (None, why) when it is not drawn (a motion case, a malformed
    one, or more than :data:`MAX_REPRO_TRIANGLES` triangles (paths, segments) or
    :data:`MAX_REPRO_SIDE` px, or paths of more than :data:`MAX_DRAWN_VERTICES` vertices).
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
    noun = scene.noun
    n, of = len(scene), payload.get("original_triangles")
    triangles = f"{n} {noun}{'' if n == 1 else 's'}" + (f" (of {of})" if of else "")
    if isinstance(scene, PathScene):
        triangles += f" under the {scene.fill_rule} rule"
    if isinstance(scene, LineScene) and scene.strip_sizes.size != n:
        strips = scene.strip_sizes.size
        triangles += f" in {strips} strip{'' if strips == 1 else 's'}"
    if n > MAX_REPRO_TRIANGLES or max(scene.width, scene.height) > MAX_REPRO_SIDE:
        return None, (f"minimal repro: {triangles} on a {scene.width} x {scene.height} viewport, not drawn (pictures are "
                      f"drawn up to {MAX_REPRO_TRIANGLES} {noun}s and {MAX_REPRO_SIDE} px a side)")
    if isinstance(scene, PathScene) and scene.vertices.shape[0] > MAX_DRAWN_VERTICES:
        return None, (f"minimal repro: {triangles} of {scene.vertices.shape[0]} vertices, not drawn (pictures are drawn up to "
                      f"{MAX_DRAWN_VERTICES} vertices)")
    drawing = result.drawing.whole or result.drawing if result.drawing is not None else None  # a layer's: the pattern's
    convention = drawing.convention if drawing is not None else None
    seen = _seen_on_repro(result, case, payload, convention)
    if isinstance(scene, LineScene):
        return _line_repro(result, scene, convention, triangles, seen)
    if isinstance(scene, PathScene):
        finite_path = scene.primitive_boxes()[2]
        drawn = scene.vertices[np.repeat(finite_path[scene.contour_path], scene.contour_sizes)]  # of the finite paths
        window = _points_window(drawn, scene.width, scene.height)
    else:
        window = _repro_window(scene.positions, scene.width, scene.height)
    x0, y0, x1, y1 = window
    oracle = None
    if convention is not None:
        try:
            oracle = exact_coverage(scene, convention)
        except ValueError:  # no oracle of this kind for paths (analytic area): no coverage drawn
            oracle = None
    covered = None if oracle is None else oracle.counts(scene.width, scene.height)[y0:y1, x0:x1] > 0
    if seen is not None:
        marks = [(x, y) for x, y in _focus(seen)[:EVIDENCE_LIMIT] if x0 <= x < x1 and y0 <= y < y1]
    else:
        named = _focus(result)[:EVIDENCE_LIMIT]
        marks = _near_paths(named, scene) if isinstance(scene, PathScene) else _near_triangles(named, scene.positions)
    fill = CROP_LEGEND[_CONVENTION]
    sample = convention.sample if convention is not None else None
    numbers = ""
    numbered = chosen = None
    if isinstance(scene, PathScene):
        chosen = _numbering_convention(convention)
        numbered = _repro_numbered(result, scene, marks)
        if numbered is not None and max(x1 - x0, y1 - y0) <= MAX_NUMBERED_SIDE:
            at = ("its centre (no convention known: top-left ties)" if convention is None else
                  "its first sample" if convention.samples is not None else "its sample")
            numbers = f"; in each pixel the winding number of {at} around path {numbered}"
    if seen is not None and seen.drawing is not None and seen.drawing.coverages:
        zoom = ""
        if convention is not None and convention.samples is not None and max(x1 - x0, y1 - y0) > SAMPLES_SIDE and marks:
            window = window_around(*marks[0], scene.width, scene.height, SAMPLES_SIDE)  # samples drawn large enough to see
            zoom = f"; {SAMPLES_SIDE} px around its first offending pixel, to show the samples"
            marks = [(x, y) for x, y in marks if window[0] <= x < window[2] and window[1] <= y < window[3]]
        uri = _repro_panels(scene, seen.drawing.coverages[0], oracle, convention, window, marks, numbered, chosen,
                            region=case.region)
        triangles += zoom
        if case.region is not None:
            triangles += " (dotted: the region whose every pixel they must hit)"
        said = f"the convention ({convention.describe()})" if convention is not None and oracle is not None else ""
        where = ("; left: what the rasterizer drew, right: what " + said + " says" if said else
                 "; what the rasterizer drew (" + ("no convention known" if convention is None else "no oracle of its kind")
                 + ", so nothing beside it)")
        outlined = f"; outlined: {len(marks)} pixel{'' if len(marks) == 1 else 's'} the failure names on the repro" if marks else ""
        return uri, f"minimal repro: its {triangles}{where}{numbers if said else ''}{outlined}"
    if isinstance(scene, PathScene):
        uri = svg_window(scene, covered, fill, (chosen or Convention()).sample, window, marks, numbered=numbered, convention=chosen)
    else:
        uri = svg_window(scene.positions, covered, fill, sample, window, marks)
    outlined = f"; outlined: {len(marks)} of the pixels the failure names, next to these {noun}s" if marks else ""
    if convention is None or covered is None:
        why = "no convention known" if convention is None else "no oracle of its kind for paths"
        return uri, f"minimal repro: its {triangles}; {why}, so no coverage drawn{numbers}{outlined}"
    return uri, f"minimal repro: its {triangles}, the pixels the convention covers{numbers}{outlined}"


def _seen_on_repro(result: Result, case: Case, payload: dict[str, Any], convention: Convention | None) -> Result | None:
    """The failure on the repro itself, as its file keeps it (the check's ``evidence`` and
    the rasterizer's ``answer`` there: :func:`harness.diagnose.repro.attach_repro`), as a result
    with a drawing of the repro; None for a file without them."""
    from harness.diagnose.repro import answer_from_json

    evidence = payload.get("evidence")
    answer = answer_from_json(payload.get("answer"))
    if not isinstance(evidence, dict) or answer is None:
        return None
    return Result(result.rasterizer, case.id, str(payload.get("check", result.check)), "fail", str(payload.get("message", "")),
                  {}, evidence, Drawing(case, (answer,), convention))


PANEL_FIT = 400  # screen px: the longer side of each of a repro's two pictures
SAMPLES_SIDE = 16  # px: a repro with a sample pattern wider than this is drawn around its first offending pixel
_PANEL_GAP, _PANEL_TITLE = 16, 20  # screen px between the pictures, and above them for their titles


def _repro_panels(scene: AnyScene, answer: Coverage, oracle: Coverage | None, convention: Convention | None,
                  window: tuple[int, int, int, int], marks: list[tuple[int, int]], numbered: int | None = None,
                  chosen: Convention | None = None, only: list[int] | None = None, region: NDArray | None = None) -> str:
    """A repro drawn twice side by side as one SVG data URI: on the left the rasterizer's
    ``answer``, on the right the convention's ``oracle`` (left out when None), the same
    window of the same primitives with the same pixels outlined. Anti-aliased coverage
    shades each pixel by its alpha; a multisample or supersampled convention draws its
    samples in each pixel (:class:`Samples`: the rasterizer's own where it says which it
    covered, the convention's on the right), ringed where the two differ. A path scene's
    winding numbers (around path ``numbered``, by the ``chosen`` convention) are written
    on the right; a line scene's left picture writes how many segments drew each pixel.
    Given ``only``, the coverage of those primitives alone is drawn (their number in the
    titles): one triangle's alphas in a scene of overlapping ones, say; given a
    partition's ``region``, it is outlined."""
    w, h = scene.width, scene.height
    area = convention is not None and convention.model.alphas
    pattern = convention is not None and convention.samples is not None
    if pattern and convention is not None:
        # every sample of every pixel is drawn: a window of at most SAMPLE_BUDGET samples
        # around the first offending pixel (a 16x4 supersampler's 12 px crop was 4 MB of SVG)
        count = convention.n_samples
        x0, y0, x1, y1 = window
        if (x1 - x0) * (y1 - y0) * count > SAMPLE_BUDGET:
            fx, fy = marks[0] if marks else ((x0 + x1) // 2, (y0 + y1) // 2)
            window = window_around(fx, fy, w, h, max(2, int(math.sqrt(SAMPLE_BUDGET / count))))
    x0, y0, x1, y1 = window
    answer = _of(answer, only)
    oracle = None if oracle is None else _of(oracle, only)

    def layers(coverage: Coverage | None) -> dict[str, Any]:
        if coverage is None:
            return {}
        if area:
            got = _alpha_per_pixel(coverage, w, h)[y0:y1, x0:x1]
            return {"covered": None, "alpha": got}
        return {"covered": coverage.counts(w, h)[y0:y1, x0:x1] > 0}

    theirs, ours = layers(answer), layers(oracle)
    samples: list[Samples | None] = [None, None]
    if pattern and convention is not None:
        offsets = np.asarray(convention.samples, dtype=np.float64)
        want = sample_hits(scene, convention, window, only=only)
        got = sample_hits(scene, convention, window, answer) if convention.model.sample_ids else None
        differs = None if got is None else got != want
        samples = [None if got is None else Samples(offsets, got, differs), Samples(offsets, want, differs)]
    lines = isinstance(scene, LineScene)
    sample: tuple[float, float] | None = (_line_sample(convention) if lines else convention.sample if convention is not None
                                          else (0.5, 0.5))
    positions: NDArray | PathScene | LineScene = (scene if isinstance(scene, (PathScene, LineScene)) else
                                                  scene.positions if only is None else scene.positions[only])
    hits = answer.counts(w, h)[y0:y1, x0:x1] if lines else None
    cols, rows = x1 - x0, y1 - y0
    scale = min(24.0, PANEL_FIT / max(cols, rows, 1))
    pw, ph = round(cols * scale), round(rows * scale)
    of = "" if only is None else f" ({scene.noun}{'' if len(only) == 1 else 's'} {', '.join(map(str, only))})"
    panels = [("what the rasterizer drew" + of, theirs, CROP_LEGEND[_DRAWN], samples[0], hits, numbered)]
    if oracle is not None:
        panels.append(("what the convention says" + of, ours, CROP_LEGEND[_CONVENTION], samples[1], None, numbered))
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{len(panels) * pw + (len(panels) - 1) * _PANEL_GAP}" '
             f'height="{ph + _PANEL_TITLE}">']
    count = convention.n_samples if convention is not None else 1

    def alphas(layer: dict[str, Any]) -> dict[tuple[int, int], str] | None:
        values = layer.get("alpha")
        if values is None:
            return None
        out = {}
        for x, y in marks:
            if x0 <= x < x1 and y0 <= y < y1:
                a = float(values[y - y0, x - x0])
                k = a * count
                out[(x, y)] = f"{round(k)}/{count}" if pattern and abs(k - round(k)) < 1e-9 else f"{a:.3g}"
        return out

    for index, (title, layer, fill, shown, counts, number) in enumerate(panels):
        left = index * (pw + _PANEL_GAP)
        dot = None if (area or pattern) and shown is None else sample  # an alpha says nothing of its samples
        parts.append(f'<text x="{left}" y="{_PANEL_TITLE - 6}" font-size="13" font-family="sans-serif" fill="#222">{title}</text>')
        if isinstance(positions, LineScene):
            parts.append(_svg_window_text(positions, layer.get("covered"), fill, dot, window, marks, PANEL_FIT,
                                          numbered=number, convention=convention, hits=counts, samples=shown,
                                          alpha=layer.get("alpha"), at=(left, _PANEL_TITLE), labels=alphas(layer),
                                          region=region))
        else:
            parts.append(_svg_window_text(positions, layer.get("covered"), fill, dot, window, marks, PANEL_FIT,
                                          numbered=number if isinstance(positions, PathScene) else None, convention=chosen,
                                          samples=shown, alpha=layer.get("alpha"), at=(left, _PANEL_TITLE),
                                          windings=index == 1, labels=alphas(layer), region=region))
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")


def _repro_segment(result: Result, scene: LineScene, marks: list[tuple[int, int]]) -> int | None:
    """The repro's segment to draw thick: its only segment; else the one with the end
    points of the segment the failure names in the whole case; else the first whose box
    holds the first marked pixel near it; else None."""
    if len(scene) == 1:
        return 0
    named = numbered_segment(result)
    whole = getattr(result.drawing.case, "scene", None) if result.drawing is not None else None
    if named is not None and isinstance(whole, LineScene):
        wa, wb = whole.segments()
        a, b = scene.segments()
        same = np.flatnonzero(np.all(a == wa[named], axis=1) & np.all(b == wb[named], axis=1))
        if same.size:
            return int(same[0])
    return _segment_at(scene, *marks[0]) if marks else None


def _line_repro(result: Result, scene: LineScene, convention: Convention | None, what: str,
                seen: Result | None = None) -> tuple[str | None, str]:
    """A line repro drawn (``what``: its segments counted): its segments over the pixel
    grid as in the crops; given the failure ``seen`` on the repro itself, what the
    rasterizer drew beside what the convention draws (:func:`_repro_panels`) with the
    pixels that failure names outlined, else the pixels the convention draws (its line
    rule) with the pixels the whole case's evidence names within a pixel and a half of
    the segments outlined; one segment thick."""
    a, b = scene.segments()
    finite = scene.primitive_boxes()[2]
    window = _points_window(np.concatenate([a[finite], b[finite]]), scene.width, scene.height)
    x0, y0, x1, y1 = window
    oracle = None
    if convention is not None:
        try:
            oracle = exact_coverage(scene, convention)
        except ValueError:  # lines are single-sample only: no oracle for a multisample or area convention
            oracle = None
    covered = None if oracle is None else oracle.counts(scene.width, scene.height)[y0:y1, x0:x1] > 0
    if seen is not None:
        marks = [(x, y) for x, y in line_focus(seen)[:EVIDENCE_LIMIT] if x0 <= x < x1 and y0 <= y < y1]
        numbered = numbered_segment(seen)
        if numbered is None:
            numbered = _repro_segment(result, scene, marks)
    else:
        marks = _near_segments(line_focus(result)[:EVIDENCE_LIMIT], scene)
        numbered = _repro_segment(result, scene, marks)
    thick = f"; segment {numbered} thick" if numbered is not None and len(scene) > 1 else ""
    if seen is not None and seen.drawing is not None and seen.drawing.coverages:
        uri = _repro_panels(scene, seen.drawing.coverages[0], oracle, convention, window, marks, numbered)
        outlined = f"; outlined: {len(marks)} pixel{'' if len(marks) == 1 else 's'} the failure names on the repro" if marks else ""
        if convention is None or oracle is None:
            why = "no convention known" if convention is None else "no line oracle for its coverage kind"
            return uri, f"minimal repro: its {what}; what the rasterizer drew ({why}, so nothing beside it){thick}{outlined}"
        return uri, (f"minimal repro: its {what}; left: what the rasterizer drew, right: what the convention draws "
                     f"({convention.describe_lines()}){thick}{outlined}")
    uri = svg_window(scene, covered, CROP_LEGEND[_CONVENTION], _line_sample(convention), window, marks,
                     numbered=numbered, convention=convention)
    outlined = f"; outlined: {len(marks)} of the pixels the failure names, next to these segments" if marks else ""
    if convention is None or covered is None:
        why = "no convention known" if convention is None else "no line oracle for its coverage kind"
        return uri, f"minimal repro: its {what}; {why}, so no pixels drawn{thick}{outlined}"
    return uri, f"minimal repro: its {what}, the pixels the convention draws ({convention.describe_lines()}){thick}{outlined}"


def _near_segments(marks: list[tuple[int, int]], scene: LineScene, reach: float = 1.5) -> list[tuple[int, int]]:
    """The marked pixels whose centre lies within ``reach`` px (plus half the line width)
    of one of the (finite) segments -- not of their boxes: a diagonal segment's box holds
    pixels far from it."""
    a, b = scene.segments()
    finite = scene.primitive_boxes()[2]
    a, b = a[finite], b[finite]
    if not marks or not a.shape[0]:
        return []
    p = np.asarray(marks, dtype=float)[:, None, :] + 0.5  # (M, 1, 2)
    with np.errstate(all="ignore"):  # huge or degenerate segments: a picture, not a verdict
        d = (b - a)[None]  # (1, K, 2)
        t = np.clip(np.nan_to_num(((p - a[None]) * d).sum(-1) / (d * d).sum(-1)), 0.0, 1.0)
        distance = np.hypot(*np.moveaxis(p - a[None] - t[..., None] * d, -1, 0))  # (M, K)
    near = np.any(distance <= reach + 0.5 * scene.line_width, axis=1)
    return [m for m, ok in zip(marks, near.tolist()) if ok]


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
