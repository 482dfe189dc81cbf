"""Known-bad rasterizers that break the contract rather than a convention."""

from __future__ import annotations

import time

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from rasterizers.centre_scanline import CentreScanline
from rasterizers.pineda_topleft import PinedaTopLeft
from tests.known_bad import coverage_from_parts

__all__ = ["ClipsBeforeSnapping", "Float32Input", "DropsAttributes", "SlowOnEpsilon", "WrongTieClaim", "Raises", "ReturnsGarbage",
           "HangsOnEpsilon", "Int32FixedPoint", "NaNAttributes"]


class WrongTieClaim:
    """A correct top-left rasterizer that declares bottom-right."""

    name = "bad_wrong_tie_claim"
    convention = Convention(tie="bottom-right")

    def rasterize(self, scene: Scene) -> Coverage:
        return CentreScanline().rasterize(scene)


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

    def rasterize(self, scene: Scene):
        return [[1, 2, 3]]


class HangsOnEpsilon:
    """Loops forever on a triangle thinner than a micro-pixel (a runaway DDA)."""

    name = "bad_hangs_on_epsilon"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        p = scene.positions
        with np.errstate(all="ignore"):
            height = p[..., 1].max(axis=1) - p[..., 1].min(axis=1)
        if np.any((height > 0) & (height < 1e-6)):
            while True:
                time.sleep(0.05)
        return CentreScanline().rasterize(scene)


class Int32FixedPoint:
    """Fixed point (8 bits) whose edge functions are computed in int32: they wrap around
    for coordinates beyond a few hundred pixels."""

    interpolates = False  # coverage only: the attribute checks skip it (else its missing rows are a second finding)

    name = "bad_int32_fixed_point"
    convention = Convention(subpixel_bits=8)

    def rasterize(self, scene: Scene) -> Coverage:
        from harness.contract.conventions import snap

        finite = np.all(np.isfinite(scene.positions), axis=(1, 2))
        small = finite & np.all(np.abs(scene.positions) < 2.0**22, axis=(1, 2))
        fixed = np.zeros(scene.positions.shape, dtype=np.int64)
        fixed[small] = (snap(scene.positions[small], 8) * 256).astype(np.int64)
        tris, out_x, out_y = [], [], []
        for t in np.flatnonzero(small):
            x0 = int(np.clip(fixed[t, :, 0].min() // 256, 0, scene.width))
            x1 = int(np.clip(fixed[t, :, 0].max() // 256 + 1, 0, scene.width))
            y0 = int(np.clip(fixed[t, :, 1].min() // 256, 0, scene.height))
            y1 = int(np.clip(fixed[t, :, 1].max() // 256 + 1, 0, scene.height))
            ys, xs = np.mgrid[y0:y1, x0:x1]
            px = (xs * 256 + 128).astype(np.int32)
            py = (ys * 256 + 128).astype(np.int32)
            q = fixed[t].astype(np.int32)
            with np.errstate(over="ignore"):
                area = (q[1, 0] - q[0, 0]) * (q[2, 1] - q[0, 1]) - (q[1, 1] - q[0, 1]) * (q[2, 0] - q[0, 0])
                if area == 0:
                    continue
                if area < 0:
                    q = q[[0, 2, 1]]
                inside = np.ones(px.shape, dtype=bool)
                for k in range(3):
                    a, b = q[k], q[(k + 1) % 3]
                    dx, dy = b[0] - a[0], b[1] - a[1]
                    e = dx * (py - a[1]) - dy * (px - a[0])  # int32: wraps around
                    bias = 0 if ((dy == 0 and dx > 0) or dy < 0) else -1
                    inside &= (e + bias) >= 0
            y, x = np.nonzero(inside)
            tris.append(np.full(x.size, t))
            out_x.append(x + x0)
            out_y.append(y + y0)
        return coverage_from_parts(tris, out_x, out_y)


class NaNAttributes:
    """Correct coverage, but attributes divided by a zero area for thin triangles."""

    name = "bad_nan_attributes"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        cov = CentreScanline().rasterize(scene)
        values = np.zeros((cov.n_pixels, 1))
        p = scene.positions
        with np.errstate(all="ignore"):
            area = np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1])
                          * (p[:, 2, 0] - p[:, 0, 0]))
        tri, _, _ = cov.pixels()
        values[area[tri] < 1.0] = np.nan
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, values)


class SlowOnEpsilon:
    """Correct, but its work explodes on triangles thinner than a micro-pixel (a DDA that
    steps by the height): about 20 ms for each, where a plain triangle takes microseconds."""

    name = "bad_slow_on_epsilon"
    convention = Convention()

    def rasterize(self, scene: Scene) -> Coverage:
        p = scene.positions
        with np.errstate(all="ignore"):
            height = p[..., 1].max(axis=1) - p[..., 1].min(axis=1)
            width = p[..., 0].max(axis=1) - p[..., 0].min(axis=1)
        thin = ((height > 0) & (height < 1e-6)) | ((width > 0) & (width < 1e-6))
        time.sleep(0.02 * int(thin.sum()))
        return CentreScanline().rasterize(scene)


def _clip_to_screen(polygon: list[np.ndarray], width: int, height: int) -> list[np.ndarray]:
    """Sutherland-Hodgman against the four sides of the screen, in float (as a GL clipper)."""
    for axis, bound, keep_below in ((0, 0.0, False), (0, float(width), True), (1, 0.0, False), (1, float(height), True)):
        out: list[np.ndarray] = []
        for k in range(len(polygon)):
            a, b = polygon[k], polygon[(k + 1) % len(polygon)]
            da = (bound - a[axis]) if keep_below else (a[axis] - bound)
            db = (bound - b[axis]) if keep_below else (b[axis] - bound)
            if da >= 0:
                out.append(a)
            if (da >= 0) != (db >= 0):
                t = da / (da - db)
                out.append(a + t * (b - a))
        polygon = out
        if not polygon:
            break
    return polygon


class ClipsBeforeSnapping:
    """Mesa's behaviour at the viewport edge: a triangle with a vertex off-screen is clipped
    to the screen in float, and the clipped polygon's new vertices are then snapped to
    1/256 px, so samples on its edges can change side. Inside the screen it is exact."""

    interpolates = False  # coverage only: the attribute checks skip it (else its missing rows are a second finding)

    name = "bad_clips_before_snapping"
    convention = Convention(subpixel_bits=8)

    def rasterize(self, scene: Scene) -> Coverage:
        tris, ys, xs = [], [], []
        for t, p in enumerate(scene.positions):
            if not np.isfinite(p).all():
                continue
            inside = (p[:, 0].min() >= 0) & (p[:, 1].min() >= 0) & (p[:, 0].max() <= scene.width) \
                & (p[:, 1].max() <= scene.height)
            pieces = [p]
            if not inside:
                polygon = _clip_to_screen([v for v in p], scene.width, scene.height)
                pieces = [np.array([polygon[0], polygon[k], polygon[k + 1]]) for k in range(1, len(polygon) - 1)]
            seen: set[tuple[int, int]] = set()
            for piece in pieces:
                cov = exact_coverage(Scene(scene.width, scene.height, piece[None]), self.convention)
                _, x, y = cov.pixels()
                seen.update(zip(x.tolist(), y.tolist()))
            for column, row in sorted(seen):
                tris.append(t)
                xs.append(column)
                ys.append(row)
        if not tris:
            return Coverage.empty()
        return Coverage.from_pixels(np.array(tris), np.array(xs), np.array(ys))


class Float32Input:
    """Exact, but its API takes float32 coordinates: float scenes lose their low bits.
    With ``tell`` it says so through ``received``, as the Mesa adapters do."""

    convention = Convention()

    def __init__(self, tell: bool = True) -> None:
        self.name = "bad_float32_input" + ("" if tell else "_silent")
        if tell:
            self.received = self._received

    @staticmethod
    def _received(scene: Scene) -> Scene:
        return Scene(scene.width, scene.height, scene.positions.astype(np.float32).astype(np.float64), scene.attributes, scene.w)

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(self._received(scene), self.convention)


class DropsAttributes:
    """The centre scanline, coverage only; ``declares`` says whether it admits it
    (``interpolates = False``)."""

    convention = Convention()

    def __init__(self, declares: bool) -> None:
        self.name = "bad_drops_attributes" + ("_declared" if declares else "")
        if declares:
            self.interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        cov = CentreScanline().rasterize(scene)
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1)


class Flaky:
    """Correct on every other call, one pixel short on the others: a flake, deliberately."""

    name = "flaky"
    convention = PinedaTopLeft().convention

    def __init__(self) -> None:
        self.calls = 0

    def rasterize(self, scene: Scene) -> Coverage:
        self.calls += 1
        right = PinedaTopLeft().rasterize(scene)
        if self.calls % 2 == 0 or len(right) == 0:
            return right
        keep = np.ones(len(right), dtype=bool)
        keep[0] = False
        return Coverage(right.triangle[keep], right.y[keep], right.x0[keep], right.x1[keep])
