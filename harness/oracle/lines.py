"""The exact oracle of line scenes (:func:`line_coverage`): a scene's segments drawn by its
convention's line rule, one module per rule family -- :mod:`harness.oracle.diamond_lines`
(Direct3D's and GL's diamond exit, GL's wide lines), :mod:`harness.oracle.bresenham_lines`
(integer Bresenham, seed 003), :mod:`harness.oracle.rectangle_lines` (Vulkan's rectangular
lines), :mod:`harness.oracle.parallelogram_lines` (Vulkan's non-strict lines),
:mod:`harness.oracle.hairlines` (skia's hairlines and Qt's cosmetic lines),
:mod:`harness.oracle.llvmpipe_lines` (llvmpipe's rectangular lines) -- and
multisample lines here. Their public names are re-exported here.

A segment k runs from ``a[k]`` to ``b[k]`` (float64, pixels, x right, y down: the screen
space of :mod:`harness.contract.conventions`). Pixel (i, j) is the square [i, i+1) x [j, j+1) with
centre (i + 1/2, j + 1/2). Every oracle returns the covered pixels as spans
``(segment, y, x0, x1)`` -- pixels x0 <= x < x1 of row y -- sorted by segment, row and x0,
like :func:`harness.oracle.winding.path_spans`. A segment with a NaN or infinite endpoint covers
nothing. Every decision is exact on the float64 input; no epsilon appears anywhere.

Multisample lines (:func:`line_coverage` under a multisample convention)
    OpenGL 4.6, 14.5.4 "Line Multisample Rasterization" (dEQP's ``MultiSampleLineRasterizer``
    likewise): the samples inside the rectangle of the line's width centred on the segment
    (two edges parallel to it at half the width, two through the end points), i.e. the
    rectangle rule at every sample of the pattern, each decided exactly at its own offset
    under the tie rule and snapping (:meth:`harness.contract.conventions.Convention.at_sample`).
    The only line rule defined under a multisample convention.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.contract.conventions import (
    BRESENHAM_ROUNDINGS,
    BRESENHAM_TIES,
    BresenhamRounding,
    BresenhamTies,
    Convention,
)
from harness.geometry.exact import SAFE_MAX, SAFE_MIN
from harness.geometry.spans import expand
from harness.oracle.bresenham_lines import (
    BRESENHAM_MAX,
    _bresenham_far,
    _bresenham_walks,
    _walk_ends,
    bresenham_pixels,
    bresenham_spans,
    bresenham_spans_rational,
    end_point_pixels,
    walks_backwards,
)
from harness.oracle.diamond_lines import (
    _diamond_exit_kept,
    _diamond_far,
    _gl_flag,
    area_holding,
    diamond_exit_spans,
    diamond_exit_spans_rational,
    diamond_holding,
    diamond_wide_spans,
    diamond_wide_spans_rational,
    is_x_major,
)
from harness.oracle.hairlines import HAIRLINE_RULES, hairline_spans, hairline_spans_rational
from harness.oracle.line_spans import _beyond, finite_rows
from harness.oracle.llvmpipe_lines import llvmpipe_rectangle_coverage
from harness.oracle.parallelogram_lines import (
    PARA_SAFE_MAX,
    PARA_SAFE_MIN,
    parallelogram_spans,
    parallelogram_spans_rational,
)
from harness.oracle.rectangle_lines import (
    RECT_SAFE_MAX,
    RECT_SAFE_MIN,
    _rectangle_kept,
    rectangle_spans,
    rectangle_spans_rational,
)

__all__ = [
    "diamond_exit_spans",
    "diamond_exit_spans_rational",
    "bresenham_spans",
    "bresenham_spans_rational",
    "bresenham_pixels",
    "rectangle_spans",
    "rectangle_spans_rational",
    "parallelogram_spans",
    "parallelogram_spans_rational",
    "hairline_spans",
    "hairline_spans_rational",
    "line_coverage",
    "is_x_major",
    "diamond_holding",
    "area_holding",
    "diamond_wide_spans",
    "diamond_wide_spans_rational",
    "end_point_pixels",
    "walks_backwards",
    "BRESENHAM_ROUNDINGS",
    "BRESENHAM_TIES",
    "RECT_SAFE_MIN",
    "RECT_SAFE_MAX",
    "BRESENHAM_MAX",
    "BresenhamRounding",
    "BresenhamTies",
]


def _multisample_lines(scene: Any, convention: Convention) -> Any:
    """Multisample lines (OpenGL 4.6, 14.5.4 "Line Multisample Rasterization"; dEQP's
    ``MultiSampleLineRasterizer``): the samples of the convention's pattern inside the
    ``line_width``-wide rectangle around each segment, each sample decided exactly at its
    own offset under the tie rule and snapping (:meth:`Convention.at_sample`), as the
    rectangle rule decides a pixel centre. Spans carry their sample index, sorted by
    segment, sample and row (as :func:`harness.oracle.coverage.exact_multisample`)."""
    from harness.contract.coverage import Coverage

    if convention.line.rule != "rectangle":
        raise ValueError(f"multisample lines are rectangles sampled per sample (GL 14.5.4), not {convention.line.describe()}: "
                         "declare Convention(samples=..., line=LineRule('rectangle'))")
    return Coverage.from_layers([line_coverage(scene, convention.at_sample(k)) for k in range(convention.n_samples)])


def line_coverage(scene: Any, convention: Convention) -> Any:
    """The exact coverage of a line scene (:func:`harness.oracle.coverage.exact_coverage` for lines).

    The end points are snapped by the convention first (with the line rule's own
    ``snap_rounding`` when it has one: :meth:`Convention.for_lines`); then each segment is
    drawn by the convention's :class:`~harness.contract.conventions.LineRule`:
    :func:`diamond_exit_spans`, :func:`bresenham_spans` (walked in the rule's ``direction``),
    :func:`rectangle_spans` or :func:`parallelogram_spans` (the scene's ``line_width``, the
    convention's sample point and tie rule). Segments beyond the compiled kernels' range
    are decided by the rational references (Bresenham's by its closed form in Python
    integers, clipped to the viewport): exact for every finite float64.

    Parameters
    ----------
    scene : harness.contract.scenes.LineScene
    convention : harness.contract.conventions.Convention
        Single-sample, or multisample with the rectangle rule (each sample of the pattern
        at its own offset: :func:`_multisample_lines`); an area convention, or a width-1
        rule under a multisample one: ValueError.

    Returns
    -------
    harness.contract.coverage.Coverage
        Spans of segment (``primitive``), row, x0, x1 sorted by segment, row and x0; no
        attributes. Segments with a NaN or infinite end point cover nothing.

    Examples
    --------
    >>> from harness.contract.scenes import LineScene
    >>> scene = LineScene.from_strips(6, 4, [[[0.5, 0.5], [4.5, 2.5], [0.5, 3.5]]])
    >>> line_coverage(scene, Convention()).counts(6, 4)
    array([[1, 1, 0, 0, 0, 0],
           [0, 0, 1, 1, 0, 0],
           [0, 0, 1, 1, 1, 0],
           [0, 1, 0, 0, 0, 0]], dtype=int32)
    """
    from harness.contract.coverage import Coverage

    if convention.model.alphas and convention.model.lines:
        # anti-aliased lines: the area of each stroke inside the pixel (issue 34)
        from harness.oracle.area_lines import line_area_coverage

        return line_area_coverage(scene, convention)
    if convention.line.cap != "butt":
        raise ValueError(f"line caps are an area-coverage option: {convention.line.describe()} under "
                         f"{convention.coverage_kind} coverage is not defined")
    if not convention.model.lines:
        raise ValueError(f"lines are defined for single-sample and multisample conventions, "
                         f"not {convention.coverage_kind} coverage")
    if convention.model.layered:
        return _multisample_lines(scene, convention)
    convention = convention.for_lines()  # the line rule's own snap rounding, when it has one
    rule = convention.line
    if rule.rule == "llvmpipe-rectangle":  # its normal comes from the unsnapped ends: its own module
        return llvmpipe_rectangle_coverage(scene, convention)
    a, b = scene.segments()
    # input precision, then snapping: Convention.snap applies both, first, exactly
    a, b = convention.snap(a), convention.snap(b)
    n = a.shape[0]
    width, height = scene.width, scene.height
    finite = finite_rows(a, b)
    ends = np.concatenate([a, b], axis=1)
    why = rule.undefined_width(scene.line_width)
    if why:
        raise ValueError(why + ("" if not rule.diamond or rule.wide == "replicate" else
                                " (LineRule(wide='replicate') draws integer widths as GL does; the rectangle rule any width)"))
    extra: list[tuple[int, int, int, int]] = []
    if rule.diamond and scene.line_width != 1.0:
        return Coverage(*diamond_wide_spans(a, b, scene.line_width, width, height, rule.last_pixel, rule.rule))
    if rule.diamond:
        far = _beyond(ends, SAFE_MIN, SAFE_MAX) & finite
        near = finite & ~far
        spans = _diamond_exit_kept(a, b, near, width, height, rule.last_pixel, rule.rule)
        for k in np.flatnonzero(far):
            _diamond_far(int(k), a[k], b[k], width, height, rule.last_pixel, extra, _gl_flag(rule.rule))
    elif rule.rule == "bresenham":
        with np.errstate(invalid="ignore"):
            p0 = np.where(finite[:, None], end_point_pixels(np.where(finite[:, None], a, 0.0), rule.rounding), 0.0)
            p1 = np.where(finite[:, None], end_point_pixels(np.where(finite[:, None], b, 0.0), rule.rounding), 0.0)
        far = (np.abs(np.concatenate([p0, p1], axis=1)) > BRESENHAM_MAX).any(axis=1) & finite
        near = finite & ~far
        walk_0, walk_1 = _walk_ends(np.where(near[:, None], p0, 0.0), np.where(near[:, None], p1, 0.0), rule.direction)
        spans = _bresenham_walks(walk_0.astype(np.int64), walk_1.astype(np.int64), near, width, height, rule.ties,
                                 rule.last_pixel)
        for k in np.flatnonzero(far):
            # the end pixels as Python integers: the walk's direction decided exactly
            start, end = (np.array([[int(p[k, 0]), int(p[k, 1])]], dtype=object) for p in (p0, p1))
            start, end = _walk_ends(start, end, rule.direction)
            _bresenham_far(int(k), (start[0, 0], start[0, 1]), (end[0, 0], end[0, 1]), width, height, rule.ties,
                           rule.last_pixel, extra)
    elif rule.rule in HAIRLINE_RULES:
        # fixed-point DDAs: exact in integers for every finite end point (far ones in Python's)
        spans = hairline_spans(a, b, width, height, rule.rule)
    elif rule.rule == "parallelogram":
        values = np.concatenate([ends, np.full((n, 1), scene.line_width)], axis=1)
        far = _beyond(values, PARA_SAFE_MIN, PARA_SAFE_MAX) & finite
        near = finite & ~far
        kw = dict(width=width, height=height)
        spans = parallelogram_spans(np.where(near[:, None], a, np.nan), np.where(near[:, None], b, np.nan),
                                    scene.line_width, convention.sample, convention.tie, **kw)
        for k in np.flatnonzero(far):
            s, y, x0, x1 = parallelogram_spans_rational(a[k:k + 1], b[k:k + 1], scene.line_width, convention.sample,
                                                        convention.tie, **kw)
            extra.extend((int(k), int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1))
    else:
        values = np.concatenate([ends, np.full((n, 1), scene.line_width)], axis=1)
        far = _beyond(values, RECT_SAFE_MIN, RECT_SAFE_MAX) & finite
        near = finite & ~far
        kw = dict(width=width, height=height)
        spans = _rectangle_kept(a, b, np.full(n, float(scene.line_width)), near, convention, width, height)
        for k in np.flatnonzero(far):
            s, y, x0, x1 = rectangle_spans_rational(a[k:k + 1], b[k:k + 1], scene.line_width, convention.sample, convention.tie,
                                                    **kw)
            extra.extend((int(k), int(r), int(u), int(v)) for r, u, v in zip(y, x0, x1))
    p, y, x0, x1 = spans
    if extra:
        more = np.array(extra, dtype=np.int64).T
        p, y, x0, x1 = (np.concatenate([u, v]) for u, v in zip((p, y, x0, x1), more))
        order = np.lexsort((x0, y, p))
        p, y, x0, x1 = p[order], y[order], x0[order], x1[order]
        if rule.rule not in ("rectangle", "parallelogram"):  # far pixels come one by one: merge them into runs
            lengths = x1 - x0
            return Coverage.from_pixels(np.repeat(p, lengths), expand(x0, lengths), np.repeat(y, lengths))
    return Coverage(p, y, x0, x1)
