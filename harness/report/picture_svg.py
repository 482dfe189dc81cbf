"""The SVG windows every crop and repro is drawn in: the pixel grid, the covered pixels,
the samples, the offending pixels outlined, and the primitives as vectors over them, each
scene kind's layer by its own drawer (:data:`_VECTORS`, keyed by the kind's name)."""

from __future__ import annotations

import base64
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from harness.checks import deviations
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene
from harness.kinds import LINES, TRIANGLES, kind_of
from harness.report.picture_kit import (
    _ALPHA,
    _DRAWN,
    _REGION,
    CROP_LEGEND,
    DIFF_LEGEND,
    SAMPLE_LEGEND,
    Samples,
    _hex,
    _svg_samples,
)
from harness.report.picture_lines import _svg_hits, _svg_lines
from harness.report.picture_paths import MAX_NUMBERED_SIDE, _svg_paths, _svg_windings

__all__ = ["svg_crop", "svg_window", "Vectors"]


def svg_crop(positions: NDArray | AnyScene, coverage: Coverage, sample: tuple[float, float],
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
    if not LINES.owns(positions):  # a line crop colours each segment's pixels against the oracle's same segment
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


def svg_window(positions: NDArray | AnyScene, covered: NDArray | None, fill: tuple[int, int, int],
               sample: tuple[float, float] | None, window: tuple[int, int, int, int], marks: list[tuple[int, int]],
               fit: int = 384, numbered: int | None = None, convention: Convention | None = None,
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


def _svg_window_text(positions: NDArray | AnyScene, covered: NDArray | None, fill: tuple[int, int, int],
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
            parts.append(f'<rect x="{mx + inset:.4f}" y="{my + inset:.4f}" width="{1 - 2 * inset:.4f}" '
                         f'height="{1 - 2 * inset:.4f}" '
                         f'fill="none" stroke="{red}" stroke-width="2" {thin}/>')
    # the kind's own vector layer (its "vectors" hook): triangles come as their positions
    kind = TRIANGLES if isinstance(positions, np.ndarray) else kind_of(positions)
    parts.extend(kind.hook("vectors")(Vectors(positions, window, scale, numbered, convention, sample, marks, hits, windings)))
    parts.append("</svg>")
    return "".join(parts)


@dataclass(frozen=True)
class Vectors:
    """What a picture's vector layer is drawn from: the primitives (``(N, 3, 2)`` triangle
    positions, a path scene or a line scene), the window and its scale (screen px per
    pixel), the path or segment numbered, the convention, the sample point, the marked
    pixels, the hit counts (lines) and whether winding numbers are written (paths)."""

    positions: Any
    window: tuple[int, int, int, int]
    scale: float
    numbered: int | None
    convention: Convention | None
    sample: tuple[float, float] | None
    marks: list[tuple[int, int]]
    hits: NDArray | None
    windings: bool


def triangle_vectors(v: Vectors) -> list[str]:
    """The triangles outlined (up to 200 near the window)."""
    x0, _, x1, _ = v.window
    positions = v.positions
    finite = np.all(np.isfinite(positions), axis=(1, 2))
    near = finite & np.any((positions[..., 0] > x0 - 64) & (positions[..., 0] < x1 + 64), axis=1)
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    thin = 'vector-effect="non-scaling-stroke"'
    parts = []
    for tri in positions[near][:200]:
        pts = " ".join(f"{vx:.6g},{vy:.6g}" for vx, vy in np.clip(tri, -1e6, 1e6))
        parts.append(f'<polygon points="{pts}" fill="none" stroke="{blue}" stroke-width="1" {thin}/>')
    return parts


def path_vectors(v: Vectors) -> list[str]:
    """The paths under their fill rule, and path ``numbered``'s winding numbers in a
    window small enough (:func:`_svg_windings`)."""
    x0, y0, x1, y1 = v.window
    parts = _svg_paths(v.positions, v.window, v.scale, v.numbered)
    if v.windings and v.numbered is not None and max(x1 - x0, y1 - y0) <= MAX_NUMBERED_SIDE and v.scale >= 10:
        chosen = v.convention if v.convention is not None else Convention(sample=v.sample or (0.5, 0.5))
        parts.extend(_svg_windings(v.positions, v.numbered, chosen, v.window, v.scale))
    return parts


def line_vectors(v: Vectors) -> list[str]:
    """The strips as polylines (:func:`_svg_lines`) and each pixel's hit count."""
    parts = _svg_lines(v.positions, v.window, v.scale, v.numbered, v.convention, v.marks)
    if v.hits is not None and v.scale >= 10:
        parts.extend(_svg_hits(v.hits, v.window, v.scale))
    return parts


def _drawn(scene: AnyScene) -> NDArray | PathScene | LineScene:
    """What a picture draws of a scene: a triangle scene's positions, any other scene itself."""
    return scene.positions if TRIANGLES.owns(scene) else cast(PathScene | LineScene, scene)
