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
"

The pictures are drawn by one module per drawer: :mod:`~harness.report.picture_kit` (colours,
rasters, samples), :mod:`~harness.report.picture_svg` (the SVG windows),
:mod:`~harness.report.picture_paths`, :mod:`~harness.report.picture_lines`,
:mod:`~harness.report.picture_area`, :mod:`~harness.report.picture_motion` and
:mod:`~harness.report.picture_repro`; this module draws a failure's pictures
(:func:`draw`: each scene kind's by its kind's ``still_pictures`` hook) and keeps every
picture name importable from here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.checks import EVIDENCE_LIMIT, Result, deviations, pixel_classes
from harness.checks.records import Drawing
from harness.contract.case import Case, MotionCase
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene
from harness.kinds import LINES, PATHS, kind_of
from harness.report.picture_area import _alpha_errors, _alpha_per_pixel, alpha_map
from harness.report.picture_kit import (
    _CONVENTION,
    _DIFFERS,
    _DRAWN,
    ALPHA_LEGEND,
    CROP_LEGEND,
    DIFF_LEGEND,
    HEAT_LEGEND,
    LEGEND,
    LINE_LEGEND,
    PATH_LEGEND,
    SAMPLE_LEGEND,
    Samples,
    _focus,
    _offending_rows,
    _oracles,
    _svg_samples,
    heatmap,
    oracle_diff,
    sample_hits,
    svg_pattern,
    window_around,
)
from harness.report.picture_lines import LINE_CROP_SIDE, _line_oracle, _line_sample, focus_segment, line_focus, numbered_segment
from harness.report.picture_motion import motion_animation, series_label, series_plot
from harness.report.picture_paths import (
    MAX_DRAWN_VERTICES,
    MAX_NUMBERED_SIDE,
    _numbering_convention,
    focus_path,
    numbered_path,
    rule_fills,
    winding_numbers,
)
from harness.report.picture_repro import MAX_REPRO_SIDE, MAX_REPRO_TRIANGLES, _near_segments, _repro_panels, draw_repro
from harness.report.picture_svg import _drawn, svg_crop, svg_window

__all__ = ["draw", "draw_repro", "motion_animation", "heatmap", "oracle_diff", "svg_crop", "svg_window", "series_plot",
           "series_label", "window_around", "svg_pattern", "LEGEND", "HEAT_LEGEND", "DIFF_LEGEND", "CROP_LEGEND", "ALPHA_LEGEND", "alpha_map", "MAX_REPRO_TRIANGLES",
           "MAX_REPRO_SIDE", "PATH_LEGEND", "winding_numbers", "rule_fills", "focus_path", "numbered_path", "MAX_NUMBERED_SIDE",
           "MAX_DRAWN_VERTICES", "LINE_LEGEND", "line_focus", "focus_segment", "numbered_segment",
           "LINE_CROP_SIDE", "SAMPLE_LEGEND", "Samples", "sample_hits", "fill_pictures", "line_pictures",
           # kept importable from here for the tests
           "_CONVENTION", "_DIFFERS", "_DRAWN", "_svg_samples", "_near_segments"]


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
    numbered, chosen = (numbered_path(result), _numbering_convention(drawing.convention)) if PATHS.owns(scene) else (None, None)
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
    pictures: dict[str, str] = kind_of(case.scene).hook("still_pictures")(case, drawing, result)
    return pictures


def line_pictures(case: Case, drawing: Drawing, result: Result) -> dict[str, str]:
    """The lines' ``still_pictures`` hook: :func:`_line_pictures`."""
    return _line_pictures(LINES.narrow(case.scene), drawing, result)


def fill_pictures(case: Case, drawing: Drawing, result: Result) -> dict[str, str]:
    """The triangles' and paths' ``still_pictures`` hook: heat map, oracle diff and crop
    (:func:`_still_pictures`)."""
    scene = case.scene
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
    if PATHS.owns(scene):  # a path's crop writes its winding numbers, by the convention's first sample
        convention = _numbering_convention(drawing.convention)
        numbered = numbered_path(result)
        images["crop"] = svg_crop(scene, coverage, convention.sample, crop, shown, numbered=numbered, convention=convention)
    else:
        sample = drawing.convention.sample if drawing.convention is not None else (0.5, 0.5)
        images["crop"] = svg_crop(_drawn(scene), coverage, sample, crop, shown)
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
