"""Path pictures: each path as one SVG ``<path>`` under its fill rule, arrows along the
edges, and the winding numbers of one path's samples (:func:`winding_numbers`, exact).

The winding numbers are computed here, not read from the oracle
(:mod:`harness.oracle.winding`): the oracle's compiled sweep yields the fill rule's verdict
per span of a row, not a sample's winding number, and this picture writes the number; both
follow the same exact predicates and tie perturbation, so the number's fill verdict is the
oracle's (pinned by ``tests/report/test_path_pictures.py``)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from harness.checks import Result
from harness.contract.conventions import Convention
from harness.contract.scenes import PathScene
from harness.geometry.exact import orientation
from harness.kinds import PATHS
from harness.report.picture_kit import (
    _FILLED,
    _LEFT,
    _OTHER_PATH_COLOUR,
    _PATH_COLOUR,
    _PATH_ROWS,
    PATH_FILL_OPACITY,
    PATH_LEGEND,
    _focus,
    _hex,
)

__all__ = ["winding_numbers", "rule_fills", "focus_path", "numbered_path", "MAX_NUMBERED_SIDE", "MAX_DRAWN_VERTICES"]


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
    on_paths = result.drawing is not None and PATHS.owns(getattr(result.drawing.case, "scene", None))
    translate = ("translate",) if on_paths else ()  # a name both kinds' invariance lists use
    for key in (*_PATH_ROWS, *translate):
        rows = e.get(key)
        if rows and isinstance(rows[0], (list, tuple)) and len(rows[0]) == 3:
            return int(rows[0][0])
    return None


MAX_NUMBERED_SIDE = 32  # px: windows up to this many pixels a side show winding numbers


MAX_DRAWN_VERTICES = 20_000  # per picture: paths beyond it (after clipping) are left out, and counted


def _numbering_convention(convention: Convention | None) -> Convention:
    """The single-sample convention a path picture's winding numbers follow: the
    drawing's (its first sample's for a multisample one); the centre, top-left ties and
    no snapping without one."""
    if convention is None:
        return Convention()
    return convention.at_sample(0) if convention.samples is not None else convention


def winding_numbers(scene: PathScene, path: int, convention: Convention,
                    window: tuple[int, int, int, int]) -> NDArray[np.int64] | None:
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
        raise ValueError(f"winding_numbers takes a single-sample convention, not kind {convention.coverage_kind!r}")
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
        under: NDArray[np.bool_] = (v[None, :] > ys[:, None]) | ((v[None, :] == ys[:, None]) & (ty < 0))
        return under

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
    if drawing is None or not PATHS.owns(scene) or len(scene) == 0:  # winding numbers are a path's
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
    corners: NDArray[np.float64] = p[~repeated] * unit
    return corners


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
    if not convention.model.single_sample:  # area or a pattern: the winding at each pixel's centre (the convention's snapping)
        convention = convention.point_sampled((0.5, 0.5))
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
