"""Exact oracle of llvmpipe's rectangular lines (lavapipe's Vulkan lines), with its
reference; coverage as :func:`harness.oracle.lines.line_coverage` returns it.

llvmpipe's rectangular lines (``llvmpipe-rectangle``)
    Mesa, ``src/gallium/drivers/llvmpipe/lp_setup_line.c``, ``try_setup_line``, the
    ``setup->rectangular_lines`` branch (lavapipe sets it for Vulkan's rectangular and
    default lines): the quad whose corners are each end point snapped to the sub-pixel
    grid, plus and minus the half-width normal -- computed in float32 from the *unsnapped*
    (float32) end points as ``scale = (line_width * 0.5f) / sqrtf(dx*dx + dy*dy)``,
    ``(-dy * scale, dx * scale)`` with ``dx, dy`` = first end minus second, and snapped to
    the grid on its own (``subpixel_snap``, below) -- rasterized
    as two triangles under the triangles' sample point and tie rule. The corners lie up
    to half a grid step per coordinate off the exact rectangle's (the normal's snap and
    the ends' snaps are separate), which the ``rectangle`` rule with any snapping misses
    (lavapipe: 30 of 10,755 probe pixels, where this rule has none).

    The snapping is llvmpipe's own, whatever the convention's: ``subpixel_snap(v -
    pixel_offset)``, i.e. ``util_iround(256 * (v - 0.5f))`` in float32 (``pixel_offset`` is
    1/2 for pixel centres), and Mesa's ``util_iround`` on x86-64 is ``(int)(f + 0.5f)`` for
    f >= 0, else ``(int)(f - 0.5f)``: half away from zero *in the frame shifted by half a
    pixel* (a tie of the grid goes up when v >= 1/2, down when v < 1/2: plain half-away
    but for 0 < v < 1/2), with float32 roundings.
    So the ends snap otherwise than the triangles (nearest-even, unshifted), and the
    normal's own snap puts the corners up to 1/512 px off the exact rectangle's.

    As a convention: the convention's input precision is applied to the end points first
    (llvmpipe receives float32: declare ``input="float32"``; the rule takes float32 of
    what it receives), its ``subpixel_bits`` and ``snap_rounding`` play no part, and the
    quad's two triangles (first end - n, second end - n, second end + n; first end - n,
    second end + n, first end + n) are decided by the triangle oracle under the
    convention's sample point and tie rule: exact on the dyadic corners. Every float32
    operation is IEEE's, correctly rounded (numpy's float32 arithmetic and square root), so
    the corners are determined exactly by the input. A segment whose float32 ends coincide has no normal
    (0/0) and covers nothing; the two triangles share their diagonal, which the tie rule
    gives to one of them, so no pixel is counted twice.

:func:`llvmpipe_rectangle_corners` gives the four corners; the reference
(:func:`llvmpipe_rectangle_rational`) tests each sample of the viewport against the
quad's four edges in :class:`fractions.Fraction`, perturbed by the tie rule.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention

__all__ = ["FIXED_ORDER", "llvmpipe_rectangle_corners", "llvmpipe_rectangle_coverage", "llvmpipe_rectangle_rational"]


# llvmpipe's sub-pixel grid (lp_setup_context.h: FIXED_ORDER 8, FIXED_ONE 256)
FIXED_ORDER = 8


def _iround(f: NDArray[np.float32]) -> NDArray[np.float64]:
    """Mesa's ``util_iround`` on x86-64 (u_math.h, the portable branch): ``(int)(f + 0.5f)``
    for f >= 0, else ``(int)(f - 0.5f)``, the addition in float32 (so it may round)."""
    f = f.astype(np.float32)
    half = np.float32(0.5)
    with np.errstate(invalid="ignore"):
        moved = np.where(f >= 0, f + half, f - half).astype(np.float32)
    return np.trunc(moved.astype(np.float64))


def llvmpipe_rectangle_corners(a: NDArray[np.float64], b: NDArray[np.float64], line_width: float,
                               convention: Convention) -> NDArray[np.float64]:
    """(N, 4, 2) float64: each segment's quad corners (a - n, b - n, b + n, a + n), as
    llvmpipe computes them from the ends received at the convention's input precision
    (module docstring); NaN for a segment with no normal.

    >>> c = llvmpipe_rectangle_corners(np.array([[1.0, 1.0]]), np.array([[4.0, 2.0]]), 1.0, Convention())
    >>> (c[0] * 256).tolist()  # the normal (0.158, -0.474) snapped on its own: 40/256 and -121/256
    [[216.0, 377.0], [984.0, 633.0], [1064.0, 391.0], [296.0, 135.0]]

    An end on a tie of the grid rounds up, as its shifted coordinate (y - 1/2 > 0) does:

    >>> c = llvmpipe_rectangle_corners(np.array([[1.0, 1 + 2**-9]]), np.array([[4.0, 1 + 2**-9]]), 1.0, Convention())
    >>> (c[0, :, 1] * 256).tolist()  # y = 1 + 1/256, +- 1/2
    [385.0, 385.0, 129.0, 129.0]
    """
    f = np.float32
    one = f(2**FIXED_ORDER)
    offset = f(0.5)  # setup->pixel_offset: half_pixel_center, pixel centres at integers + 1/2
    with np.errstate(all="ignore"):
        a32 = convention.receive(np.asarray(a, dtype=np.float64)).astype(f)
        b32 = convention.receive(np.asarray(b, dtype=np.float64)).astype(f)
        dx = a32[:, 0] - b32[:, 0]
        dy = a32[:, 1] - b32[:, 1]
        scale = (f(line_width) * f(0.5)) / np.sqrt(dx * dx + dy * dy)
        # subpixel_snap(v): util_iround(FIXED_ONE * v), every product and difference in float32
        n = np.stack([_iround(one * (-dy * scale)), _iround(one * (dx * scale))], axis=1)
        sa = _iround(one * (a32 - offset))
        sb = _iround(one * (b32 - offset))
        corners = (np.stack([sa - n, sb - n, sb + n, sa + n], axis=1) / 2.0**FIXED_ORDER) + 0.5
    corners[~np.isfinite(corners).all(axis=(1, 2))] = np.nan
    return corners


def _triangles(corners: NDArray[np.float64]) -> NDArray[np.float64]:
    """(2N, 3, 2): each quad as its two triangles sharing the diagonal from corner 0 to 2."""
    first = corners[:, [0, 1, 2]]
    second = corners[:, [0, 2, 3]]
    return np.stack([first, second], axis=1).reshape(-1, 3, 2)


def llvmpipe_rectangle_coverage(scene: Any, convention: Convention) -> Any:
    """The rule's coverage of a line scene: the quads' triangles under the triangle
    oracle (sample point, tie rule; the corners already on the grid), each pixel of
    triangle 2k or 2k + 1 credited to segment k once."""
    from harness.contract.coverage import Coverage
    from harness.contract.scenes import Scene
    from harness.oracle.coverage import exact_coverage

    a, b = scene.segments()
    corners = llvmpipe_rectangle_corners(a, b, scene.line_width, convention)
    if not corners.shape[0]:
        return Coverage.from_pixels(np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.int64))
    triangles = Scene(scene.width, scene.height, _triangles(corners))
    # the corners are on the grid (or NaN): decided as given, at float64 input
    plain = Convention(sample=convention.sample, tie=convention.tie)
    primitive, x, y = exact_coverage(triangles, plain).pixels()
    return Coverage.from_pixels(primitive // 2, x, y)


def _inside(corners: list[tuple[Fraction, Fraction]], p: tuple[Fraction, Fraction], tie: tuple[int, int, bool]) -> bool:
    """Whether p lies inside the convex quad, samples on an edge decided by the tie rule's
    perturbation (x-first or y-first, signs sx, sy)."""
    sx, sy, y_first = tie
    signs = []
    for k in range(4):
        (x0, y0), (x1, y1) = corners[k], corners[(k + 1) % 4]
        e = (x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0)
        if e == 0:
            gx, gy = -(y1 - y0), (x1 - x0)  # the gradient of e
            first, second = ((gy * sy, gx * sx) if y_first else (gx * sx, gy * sy))
            e = first if first != 0 else second
        signs.append(e)
    return all(s > 0 for s in signs) or all(s < 0 for s in signs)


def llvmpipe_rectangle_rational(scene: Any, convention: Convention) -> set[tuple[int, int, int]]:
    """The reference: (segment, x, y) of every pixel whose sample lies inside the quad of
    :func:`llvmpipe_rectangle_corners`, each decided in fractions against the quad's four
    edges (not its triangles), perturbed by the tie rule."""
    a, b = scene.segments()
    corners = llvmpipe_rectangle_corners(a, b, scene.line_width, convention)
    tie = convention.tie_perturbation
    out = set()
    for k in range(corners.shape[0]):
        if not np.isfinite(corners[k]).all():
            continue
        quad = [(Fraction(float(u)), Fraction(float(v))) for u, v in corners[k]]
        area = sum(quad[i][0] * quad[(i + 1) % 4][1] - quad[(i + 1) % 4][0] * quad[i][1] for i in range(4))
        if area == 0:
            continue
        for j in range(scene.height):
            for i in range(scene.width):
                p = (i + Fraction(convention.sample[0]), j + Fraction(convention.sample[1]))
                if _inside(quad, p, tie):
                    out.add((k, i, j))
    return out
