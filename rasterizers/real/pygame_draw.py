"""pygame's ``pygame.draw`` (SDL surfaces, no display needed): filled polygons and 1-px
lines, aliased."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, PathScene, Scene
from rasterizers.real._bases import OneAtATime, need, refuse_several_contours

__all__ = ["PygameDraw", "STALL_REPRO", "FOUND"]

# draw.polygon's rule, found from outside and read in the source (issue 33): the inclusive
# scanline fill of the vertices truncated toward zero. Not the declared ``convention``: a
# coverage rule is defined for triangles, and the adapter draws paths and lines too.
FOUND = Convention(coverage="inclusive-scanline", input="integer-toward-zero")

# the standalone repro of draw.polygon's stall on a non-finite y (issue 32, point 3)
STALL_REPRO = "rasterizers/real/upstream/pygame_polygon_inf_stall.py"


class PygameDraw(OneAtATime):
    """pygame's ``pygame.draw.polygon`` (triangles, one-contour paths) and
    ``pygame.draw.line`` (1-px lines), one call per primitive into an 8-bit surface
    around its box (``pygame.Surface((w, h), depth=8)``, no display: SDL's dummy video
    driver is selected when none is set).

    Coordinates pass unchanged: pygame's point (x, y) names pixel (x, y), the square
    [x, x+1) x [y, y+1) in our terms (its ``Rect(0, 0, 1, 1)`` is pixel (0, 0)), y down
    as ours. The mapping is proven by ``test_pygame_maps_coordinates_exactly`` in
    ``tests/rasterizers/real/test_pygame_draw.py``: a right triangle with vertices at
    integer-plus-0.25 draws exactly the pixels of its truncated integer triangle, edges
    included.

    What the library receives: whole pixels. ``draw.polygon`` and ``draw.line`` cast
    every coordinate to a C ``int`` (truncation toward zero: the pixel holding the point
    for x >= 0, pixel 0 for x in (-1, 0)). What ``draw.polygon`` does (``draw_fillpoly``
    in ``src_c/draw.c``): for each integer row y from the lowest to the highest vertex
    row, the crossings of the edges (each edge's upper end row included, its lower end
    row excluded, but every edge ending on the last row counted there) at the integer x
    ``(y - y1) * (x2 - x1) / (y2 - y1) + x1`` (C int division: truncation toward zero)
    are sorted and taken in pairs, each pair drawing the pixels between them, both ends
    included; horizontal edges on inner rows are drawn as lines. So the fill is
    inclusive (a sample on an edge or vertex is drawn by both sides) and the pairing
    of sorted crossings is the even-odd rule: a pentagram's centre is left empty, so
    ``fill_rules = ("evenodd",)`` and nonzero path scenes are refused (Unsupported).
    ``draw.polygon`` takes one point sequence: a path of several contours is refused
    (Unsupported, as for Pillow), and a contour of fewer than three vertices, which
    pygame refuses (ValueError), covers nothing.

    Lines: ``draw.line(surface, colour, a, b, 1)`` per segment, end points truncated to
    ints as above, then pygame's integer line (both end pixels drawn). Widths other than
    1 are refused (Unsupported). ``pygame.draw.aaline`` is a real anti-aliasing mode
    (Wu-style, blending two pixels across the line) but the harness has no exact area
    oracle for lines yet (issue 34), so it has no adapter.

    Known bugs. A triangle or path with a NaN or infinite **y** coordinate stalls
    ``draw.polygon`` for a minute or more (the C cast gives INT_MIN on x86-64, and the
    row loop runs from there to the polygon's last row, unclipped: about 2**31 rows; 88 s
    for one triangle in issue 32's measurement, still running after 3 s in the repro).
    Such a primitive is detected before the call and raises a RuntimeError naming the
    bug and its repro, :data:`STALL_REPRO` (refused, not drawn). A NaN or infinite
    **x** is handed over unchanged: pygame returns at once but draws the polygon with
    that vertex at x = INT_MIN, pixels along the surface's left edge (repro
    ``rasterizers/real/upstream/pygame_polygon_nan_draws.py``). Finite coordinates
    beyond +/-2**20 px are refused by the harness already; up to that, a polygon's rows
    are looped over unclipped (about 40 ms for one 2**21 rows tall).

    Found (issue 33): triangles follow the coverage rule ``inclusive-scanline`` exactly,
    :data:`FOUND` (:mod:`harness.oracle.library_rules`: each integer row from the lowest
    vertex to the highest, pixels trunc(left crossing) .. trunc(right crossing) of the
    closed triangle, both drawn; zero-area triangles draw too):
    ``python -m harness.identify.rule_probes rasterizers.real.pygame_draw:PygameDraw``
    says exact, 0 of 1,769 pixels off (the best area threshold 478 off), and 0 of 11,326
    on 400 further triangles; truncation toward zero, not floor, told apart on vertices
    left of the screen. Not declared as ``convention`` (paths and lines have no rule
    yet). Before (pygame 2.6.1, SDL 2.28.4): no declared convention; identify's best guess for
    triangles was samples at the pixel's top-left corner (0, 0), top-right ties, vertices
    snapped down to 1/4 px: 35,928 pixels off of 164,146 (best guess only: whole-pixel
    vertices and truncated crossings are no sample rule); both windings drawn; 24
    pixels for zero-area triangles; 17,435 double hits on its partitions (inclusive
    edges); NaN/inf x: 80 pixels drawn. Lines: Bresenham from the end points truncated
    toward zero, ties stay, last pixel drawn, 173 pixels off of 9,283 (best guess)."""

    name = "pygame"
    library = "pygame"
    fill_rules = ("evenodd",)

    def __init__(self) -> None:
        os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # surfaces need no window
        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        pygame = need("pygame")
        self._pygame: Any = pygame
        self.library_version = f"{pygame.version.ver} (SDL {'.'.join(map(str, pygame.get_sdl_version()))})"
        self._surfaces: dict[tuple[int, int], Any] = {}

    def _surface(self, w: int, h: int) -> Any:
        """A cleared 8-bit w x h surface, one per size, reused."""
        surface = self._surfaces.get((w, h))
        if surface is None:
            if len(self._surfaces) > 256:
                self._surfaces.clear()
            surface = self._surfaces[(w, h)] = self._pygame.Surface((w, h), depth=8)
        surface.fill(0)
        return surface

    @staticmethod
    def _read(surface: Any, w: int, h: int) -> NDArray:
        pixels = np.frombuffer(surface.get_buffer(), dtype=np.uint8).reshape(h, surface.get_pitch())[:, :w]
        mask: NDArray = pixels > 0
        return mask

    def _polygon(self, points: NDArray, w: int, h: int) -> NDArray:
        if points.shape[0] < 3:  # pygame raises ValueError below three points
            return np.zeros((h, w), dtype=bool)
        surface = self._surface(w, h)
        self._pygame.draw.polygon(surface, 255, points.tolist())
        return self._read(surface, w, h)

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return self._polygon(p, w, h)

    def _draw_path(self, contours: list[NDArray], fill_rule: str, w: int, h: int) -> NDArray:
        (contour,) = contours
        return self._polygon(contour, w, h)

    def _draw_segment(self, a: NDArray, b: NDArray, line_width: float, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        surface = self._surface(w, h)
        self._pygame.draw.line(surface, 255, (float(a[0]), float(a[1])), (float(b[0]), float(b[1])), 1)
        return self._read(surface, w, h)

    def _refuse(self, scene: PathScene) -> None:
        super()._refuse(scene)
        refuse_several_contours(self.name, scene, "pygame.draw.polygon")

    def _refuse_stalls(self, scene: Scene | PathScene) -> None:
        """RuntimeError naming the first primitive with a non-finite y coordinate: it would
        stall ``draw.polygon`` (see the class docstring)."""
        if isinstance(scene, Scene):
            bad = ~np.all(np.isfinite(scene.positions[:, :, 1]), axis=1)
            noun = "triangle"
        else:
            finite_y = np.isfinite(scene.vertices[:, 1])
            starts = scene.contour_starts
            bad = np.zeros(len(scene), dtype=bool)
            if starts.size:
                np.logical_or.at(bad, scene.contour_path, ~np.logical_and.reduceat(finite_y, starts))
            noun = "path"
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise RuntimeError(f"{self.name}: {noun} {k} has a NaN or infinite y coordinate, on which pygame "
                               f"{self.library_version} stalls (draw.polygon loops over about 2**31 rows: "
                               f"draw_fillpoly's row range is not clipped to the surface); refused, not drawn. "
                               f"Repro: {STALL_REPRO}")

    def rasterize(self, scene: AnyScene) -> Coverage:
        if isinstance(scene, PathScene):
            self._refuse(scene)  # a refused fill rule or contour count first: Unsupported, not an error
        if isinstance(scene, (Scene, PathScene)):
            self._refuse_stalls(scene)
        return super().rasterize(scene)
