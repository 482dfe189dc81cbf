"""The minimal repro's picture (:func:`draw_repro`): its primitives over the pixel grid,
what the rasterizer drew beside what the convention says (:func:`_repro_panels`); each
scene kind's repro by its kind's ``repro_picture`` hook (:mod:`harness.kinds`):
:func:`fill_repro` for triangles and paths, :func:`line_repro` for lines."""

from __future__ import annotations

import base64
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks import EVIDENCE_LIMIT, Result
from harness.checks.records import Drawing
from harness.contract.case import Case, MotionCase, case_from_json
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene
from harness.kinds import LINES, PATHS, TRIANGLES, kind_of
from harness.oracle.coverage import exact_coverage
from harness.report.picture_area import _alpha_per_pixel
from harness.report.picture_kit import (
    _CONVENTION,
    _DRAWN,
    CROP_LEGEND,
    SAMPLE_BUDGET,
    Samples,
    _focus,
    _of,
    sample_hits,
    window_around,
)
from harness.report.picture_lines import _line_sample, _segment_at, line_focus, numbered_segment
from harness.report.picture_paths import MAX_DRAWN_VERTICES, MAX_NUMBERED_SIDE, _numbering_convention, numbered_path
from harness.report.picture_svg import _drawn, _svg_window_text, svg_window

__all__ = ["draw_repro", "fill_repro", "line_repro", "MAX_REPRO_TRIANGLES", "MAX_REPRO_SIDE"]


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
    if named is not None and PATHS.owns(whole):
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
    triangles += kind_of(scene).caption_words(scene)
    if n > MAX_REPRO_TRIANGLES or max(scene.width, scene.height) > MAX_REPRO_SIDE:
        return None, (f"minimal repro: {triangles} on a {scene.width} x {scene.height} viewport, not drawn (pictures are "
                      f"drawn up to {MAX_REPRO_TRIANGLES} {noun}s and {MAX_REPRO_SIDE} px a side)")
    if PATHS.owns(scene) and scene.vertices.shape[0] > MAX_DRAWN_VERTICES:
        return None, (f"minimal repro: {triangles} of {scene.vertices.shape[0]} vertices, not drawn (pictures are drawn up to "
                      f"{MAX_DRAWN_VERTICES} vertices)")
    drawing = result.drawing.whole or result.drawing if result.drawing is not None else None  # a layer's: the pattern's
    convention = drawing.convention if drawing is not None else None
    seen = _seen_on_repro(result, case, payload, convention)
    drawn: tuple[str | None, str] = kind_of(scene).hook("repro_picture")(result, case, convention, triangles, seen)
    return drawn


def line_repro(result: Result, case: Case, convention: Convention | None, what: str, seen: Result | None
               ) -> tuple[str | None, str]:
    """The lines' ``repro_picture`` hook: :func:`_line_repro`."""
    return _line_repro(result, LINES.narrow(case.scene), convention, what, seen)


def fill_repro(result: Result, case: Case, convention: Convention | None, what: str, seen: Result | None
               ) -> tuple[str | None, str]:
    """The triangles' and paths' ``repro_picture`` hook: the repro's primitives over the
    pixel grid (:func:`draw_repro`), ``what`` its caption's start, ``seen`` the failure
    as judged on the repro (:func:`_seen_on_repro`)."""
    scene = case.scene
    noun = scene.noun
    triangles = what
    if PATHS.owns(scene):
        finite_path = scene.primitive_boxes()[2]
        drawn = scene.vertices[np.repeat(finite_path[scene.contour_path], scene.contour_sizes)]  # of the finite paths
        window = _points_window(drawn, scene.width, scene.height)
    else:
        window = _repro_window(TRIANGLES.narrow(scene).positions, scene.width, scene.height)
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
        marks = _near_paths(named, scene) if PATHS.owns(scene) else _near_triangles(named, TRIANGLES.narrow(scene).positions)
    fill = CROP_LEGEND[_CONVENTION]
    sample = convention.sample if convention is not None else None
    numbers = ""
    numbered = chosen = None
    if PATHS.owns(scene):  # a small path repro writes its winding numbers
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
        outlined = f"; outlined: {len(marks)} pixel{'' if len(marks) == 1 else 's'} the failure names on the repro" \
            if marks else ""
        return uri, f"minimal repro: its {triangles}{where}{numbers if said else ''}{outlined}"
    if PATHS.owns(scene):
        uri = svg_window(scene, covered, fill, (chosen or Convention()).sample, window, marks, numbered=numbered,
                         convention=chosen)
    else:
        uri = svg_window(_drawn(scene), covered, fill, sample, window, marks)
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
    lines = LINES.owns(scene)
    sample: tuple[float, float] | None = (_line_sample(convention) if lines else convention.sample if convention is not None
                                          else (0.5, 0.5))
    positions = _drawn(scene)
    if only is not None and isinstance(positions, np.ndarray):  # triangles: only those the failure names
        positions = positions[only]
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
        parts.append(f'<text x="{left}" y="{_PANEL_TITLE - 6}" font-size="13" font-family="sans-serif" '
                     f'fill="#222">{title}</text>')
        if lines:
            parts.append(_svg_window_text(positions, layer.get("covered"), fill, dot, window, marks, PANEL_FIT,
                                          numbered=number, convention=convention, hits=counts, samples=shown,
                                          alpha=layer.get("alpha"), at=(left, _PANEL_TITLE), labels=alphas(layer),
                                          region=region))
        else:
            parts.append(_svg_window_text(positions, layer.get("covered"), fill, dot, window, marks, PANEL_FIT,
                                          numbered=number if PATHS.owns(positions) else None, convention=chosen,
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
    if named is not None and LINES.owns(whole):
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
        outlined = f"; outlined: {len(marks)} pixel{'' if len(marks) == 1 else 's'} the failure names on the repro" \
            if marks else ""
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
