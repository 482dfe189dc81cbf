"""Line pictures: which pixels and segment a line failure points at, and the strips drawn
as polylines over the pixel grid with their joints, numbers, hit counts and the line
rule's diamonds or rectangles (the vector layer of a line crop or repro)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.checks import Result
from harness.checks.records import Drawing
from harness.contract.conventions import AREA_LINE_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.kinds import LINES
from harness.oracle.coverage import exact_coverage
from harness.report.picture_kit import _DIAMOND, _HITS, _JOINT, _NAMED_SEGMENT, _OTHER_SEGMENT, LINE_LEGEND, _focus, _hex
from harness.report.picture_paths import _clip_contour, _svg_arrows

__all__ = ["line_focus", "focus_segment", "numbered_segment", "LINE_CROP_SIDE"]


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
                if isinstance(r.get("pixels"), list):
                    named += [v for v in r["pixels"] if isinstance(v, (list, tuple))]
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
    if drawing is None or not LINES.owns(scene) or len(scene) == 0:  # a thick segment is a line picture's
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
    if convention is not None and convention.line.rule in AREA_LINE_RULES:
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
    wide = rule in AREA_LINE_RULES
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
    if wide:  # the rectangle (parallelogram) of each segment: its sides at half the width, no caps beyond the end points
        half = 0.5 * scene.line_width
        for k in shown.tolist():
            d = b[k] - a[k]
            length = float(np.hypot(*d))
            if not (length > 0 and np.isfinite(length)):
                continue
            n = np.array([-d[1], d[0]]) / length * half
            if rule == "parallelogram":  # Vulkan's non-strict lines: sides moved along the minor axis, ends parallel to it
                n = np.array([0.0, half]) if abs(d[0]) >= abs(d[1]) else np.array([half, 0.0])
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
