"""Known-bad rasterizers built from a plain, per-pixel edge-function loop (slow, small
scenes only), each with one classic bug."""

from __future__ import annotations

import numpy as np

from harness.api import Coverage, Scene
from harness.conventions import Convention

__all__ = ["EveryEdgeInclusive", "EveryEdgeExclusive", "WrongTieClaim", "Raises", "ReturnsGarbage", "DropsSmallTriangles"]


def _edge_loop(scene: Scene, accept_zero: bool, min_area: float = 0.0) -> Coverage:
    ys, xs = np.mgrid[0 : scene.height, 0 : scene.width] + 0.5
    tris, px, py = [], [], []
    for t, p in enumerate(scene.positions):
        if not np.all(np.isfinite(p)):
            continue
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if area == 0 or abs(area) / 2 < min_area:
            continue
        inside = np.ones(xs.shape, dtype=bool)
        for k in range(3):
            a, b = p[k], p[(k + 1) % 3]
            e = np.sign(area) * ((b[0] - a[0]) * (ys - a[1]) - (b[1] - a[1]) * (xs - a[0]))
            inside &= (e >= 0) if accept_zero else (e > 0)
        y, x = np.nonzero(inside)
        tris.append(np.full(x.size, t))
        px.append(x)
        py.append(y)
    if not tris:
        return Coverage.empty()
    return Coverage.from_pixels(np.concatenate(tris), np.concatenate(px), np.concatenate(py))


class EveryEdgeInclusive:
    """tinyrenderer's `alpha < 0 || beta < 0 || gamma < 0` test: every edge owns its
    samples, so shared edges are drawn twice."""

    name = "bad_every_edge_inclusive"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        return _edge_loop(scene, accept_zero=True)


class EveryEdgeExclusive:
    """No edge owns its samples: cracks along shared edges through pixel centres."""

    name = "bad_every_edge_exclusive"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        return _edge_loop(scene, accept_zero=False)


class WrongTieClaim:
    """A correct top-left rasterizer that declares bottom-right."""

    name = "bad_wrong_tie_claim"
    convention = Convention(tie="bottom-right")

    def rasterize(self, scene: Scene) -> Coverage:
        from rasterizers.centre_scanline import CentreScanline

        return CentreScanline().rasterize(scene)


class DropsSmallTriangles:
    """`if (total_area < 1) return;`: sub-pixel triangles thrown away."""

    name = "bad_drops_small_triangles"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        from rasterizers.pineda_topleft import PinedaTopLeft

        cov = PinedaTopLeft().rasterize(scene)
        p = scene.positions
        area = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
        keep = ~(area[cov.triangle] < 1.0)
        return Coverage(cov.triangle[keep], cov.y[keep], cov.x0[keep], cov.x1[keep])


class Raises:
    """Crashes on every scene."""

    name = "bad_raises"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        raise RuntimeError("rasterizer exploded")


class ReturnsGarbage:
    """Returns something that is not a Coverage."""

    name = "bad_returns_garbage"
    convention = Convention()

    def rasterize(self, scene: Scene):  # type: ignore[no-untyped-def]
        return [[1, 2, 3]]
