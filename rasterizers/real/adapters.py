"""The library adapters. Each docstring says how the library's coordinates map onto ours:
pixel (i, j) is the square [i, i+1) x [j, j+1), y down."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.api import Coverage, Scene
from harness.registry import Unavailable
from rasterizers.real._masks import draw_each, finite_within_limit

__all__ = ["PillowPolygon", "SkimagePolygon", "SkiaPath", "CairoFill", "MesaLlvmpipe", "MesaSoftpipe"]


# The pip extra that installs each adapter's module (``make`` installs each on its own
# and keeps pip's log as .venv/install-<extra>.log).
_EXTRAS = {"cairo": "cairo", "skia": "skia", "moderngl": "gl"}


def _install_failure(module: str) -> str:
    """Why ``make`` could not install the module here: the last error line of its log."""
    import sys
    from pathlib import Path

    extra = _EXTRAS.get(module)
    log = Path(sys.prefix) / f"install-{extra}.log"
    try:
        text = log.read_text(errors="replace").splitlines()
    except OSError:
        return ""
    # the build's own error (e.g. meson's "ERROR: Dependency "cairo" not found") says most
    lines = [line.strip() for line in text if "ERROR:" in line] or [line.strip() for line in text if "rror" in line]
    return f"; its install failed on this machine ({lines[0][:160]}; see {log})" if lines else ""


def _need(module: str, hint: str) -> Any:
    try:
        return __import__(module)
    except Exception as exc:
        raise Unavailable(f"{module} is not installed ({type(exc).__name__}): {hint}{_install_failure(module)}") from None


class _OneTriangleAtATime:
    """A 2D library drawing one triangle at a time into a mask (``_draw``): coverage only,
    no declared convention."""

    name = ""
    convention = None
    interpolates = False  # coverage only: the library draws no varyings

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def rasterize(self, scene: Scene) -> Coverage:
        return draw_each(scene, self.name, self._draw)


class PillowPolygon(_OneTriangleAtATime):
    """Pillow's ``ImageDraw.polygon``. Pillow puts pixel centres at integer coordinates,
    so our (x, y) is Pillow's (x - 0.5, y - 0.5)."""

    name = "pillow"

    def __init__(self) -> None:
        self._pil = _need("PIL", "pip install pillow")
        from PIL import Image, ImageDraw

        self._Image, self._Draw = Image, ImageDraw

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        image = self._Image.new("L", (w, h), 0)
        self._Draw.Draw(image).polygon([(float(x) - 0.5, float(y) - 0.5) for x, y in p], fill=255)
        return np.asarray(image) > 0


class SkimagePolygon(_OneTriangleAtATime):
    """scikit-image's ``draw.polygon(rows, cols)``: pixel centres at integers, so rows are
    y - 0.5 and columns x - 0.5."""

    name = "skimage"

    def __init__(self) -> None:
        _need("skimage", "pip install scikit-image")
        from skimage.draw import polygon

        self._polygon = polygon

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        rows, cols = self._polygon(p[:, 1] - 0.5, p[:, 0] - 0.5, shape=(h, w))
        mask = np.zeros((h, w), dtype=bool)
        mask[rows, cols] = True
        return mask


class SkiaPath(_OneTriangleAtATime):
    """skia-python, anti-aliasing off: skia's pixel (i, j) is our [i, i+1) x [j, j+1), so
    coordinates pass unchanged."""

    name = "skia"

    def __init__(self) -> None:
        self._skia = _need("skia", "pip install skia-python   (or pip install '.[real]')")

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        skia = self._skia
        surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(w, h))
        canvas = surface.getCanvas()
        canvas.clear(skia.ColorTRANSPARENT)
        path = skia.Path()
        path.moveTo(float(p[0, 0]), float(p[0, 1]))
        path.lineTo(float(p[1, 0]), float(p[1, 1]))
        path.lineTo(float(p[2, 0]), float(p[2, 1]))
        path.close()
        canvas.drawPath(path, skia.Paint(AntiAlias=False, Color=skia.ColorBLACK))
        return np.asarray(surface.makeImageSnapshot().toarray(colorType=skia.kAlpha_8_ColorType)).reshape(h, w) > 0


class CairoFill(_OneTriangleAtATime):
    """pycairo, ``ANTIALIAS_NONE`` fill: cairo's pixel (i, j) is our [i, i+1) x [j, j+1), so
    coordinates pass unchanged."""

    name = "cairo"

    def __init__(self) -> None:
        self._cairo = _need("cairo", "apt-get install libcairo2-dev pkg-config && pip install pycairo   (or pip install '.[real]')")

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        cairo = self._cairo
        surface = cairo.ImageSurface(cairo.FORMAT_A8, w, h)
        ctx = cairo.Context(surface)
        ctx.set_antialias(cairo.ANTIALIAS_NONE)
        ctx.move_to(float(p[0, 0]), float(p[0, 1]))
        ctx.line_to(float(p[1, 0]), float(p[1, 1]))
        ctx.line_to(float(p[2, 0]), float(p[2, 1]))
        ctx.close_path()
        ctx.fill()
        surface.flush()
        stride = surface.get_stride()
        data = np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(h, stride)[:, :w]
        return data > 0


_VERTEX = """#version 330
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }"""
_FRAGMENT = """#version 330
out float coverage;
void main() { coverage = 1.0; }"""
# GL >= 4.3: every fragment appends (primitive id, x, y) to a storage buffer, so one draw
# keeps each triangle's identity through overlaps (helper invocations store nothing).
_FRAGMENT_LIST = """#version 430
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
out float coverage;
void main() {
    uint i = atomicAdd(count, 1u);
    if (i < capacity) items[i] = uvec4(uint(gl_PrimitiveID), uint(gl_FragCoord.x), uint(gl_FragCoord.y), 0u);
    coverage = 1.0;
}"""


class _Mesa:
    """Mesa's OpenGL through moderngl's EGL backend (no display). Where the context offers
    GL 4.3 (llvmpipe), the small triangles are one draw whose fragment shader appends
    (gl_PrimitiveID, x, y) to a storage buffer; large ones, and all of them without GL 4.3
    (softpipe: GL 3.3), one draw per triangle into a cleared, scissored box, read back
    each time.

    The framebuffer is a power-of-two square P >= W, H; GL window row y is memory row y,
    so the read-back image is indexed [y, x] exactly as ours (flipped relative to GL's
    bottom-up display, which also flips the winding; culling is off). GL takes float32
    positions: pixel x goes to NDC as float32(x / P) and the viewport is (-P, -P, 2P, 2P),
    whose transform ndc * P + 0 brings it back exactly, so every coordinate that float32
    holds reaches Mesa unchanged (a mapping like 2x/P - 1 would lose up to 2**-19 px to
    cancellation). The clip volume is therefore [-P, P]^2, wider than the screen: a
    triangle reaching up to P px off-screen reaches the rasterizer unclipped, as with a
    hardware guard band, and Mesa's viewport clipping (which moves vertices before
    snapping) only acts beyond that. Mesa snaps vertices to its own sub-pixel grid."""

    name = ""
    driver = ""
    convention = None
    interpolates = False  # coverage only: this adapter reads back no varyings (yet)
    # GL_MAX_VIEWPORT_DIMS is 16384 in llvmpipe and softpipe: the 2P viewport must fit
    LARGEST = 8192
    batch = True  # one draw with a fragment list where GL >= 4.3
    LISTED_BOX = 2048  # px: larger boxes are drawn one at a time

    def __init__(self) -> None:
        self._moderngl = _need("moderngl", "pip install moderngl   (or pip install '.[real]'), with Mesa's EGL: apt-get install libegl1 libgl1-mesa-dri")
        self._ctx: Any = None
        self._pid = -1

    def _context(self) -> Any:
        if self._ctx is not None and self._pid == os.getpid():
            return self._ctx
        os.environ["GALLIUM_DRIVER"] = self.driver  # read when the EGL display is first made
        os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
        self._list_program = None
        try:
            ctx = self._moderngl.create_standalone_context(backend="egl", require=430)
        except Exception:
            try:
                ctx = self._moderngl.create_standalone_context(backend="egl")
            except Exception as exc:
                raise Unavailable(f"no EGL context ({exc}): apt-get install libegl1 libgl1-mesa-dri") from None
        renderer = ctx.info["GL_RENDERER"]
        if self.driver not in renderer:
            raise RuntimeError(f"{self.name}: asked Mesa for {self.driver} but got {renderer!r} "
                               "(this process already made an EGL display; run each Mesa adapter in its own worker)")
        self._ctx, self._pid = ctx, os.getpid()
        self._program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
        if ctx.version_code >= 430 and self.batch:
            self._list_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT_LIST)
        return ctx

    def _side(self, scene: Scene) -> int:
        side = 1 << max(scene.width - 1, scene.height - 1, 1).bit_length()
        if side > self.LARGEST:
            raise ValueError(f"{self.name}: a {scene.width} x {scene.height} screen needs a {2 * side} px viewport; "
                             f"Mesa allows 16384 (screens up to {self.LARGEST} px a side)")
        return side

    def received(self, scene: Scene) -> Scene:
        """The scene as Mesa receives it: each coordinate rounded to float32 (GL's vertex
        format), which the exact mapping then carries unchanged."""
        with np.errstate(invalid="ignore", over="ignore"):
            window = scene.positions.astype(np.float32).astype(np.float64)
        return Scene(scene.width, scene.height, window, scene.attributes, scene.w)

    def rasterize(self, scene: Scene) -> Coverage:
        ctx = self._context()
        side = self._side(scene)
        if self._list_program is not None:
            return self._rasterize_listed(ctx, scene, side)
        return self._rasterize_each(ctx, scene, side)

    def _rasterize_listed(self, ctx: Any, scene: Scene, side: int) -> Coverage:
        """Small triangles in one draw, the fragment list saying which triangle made each
        fragment; triangles whose box exceeds ``LISTED_BOX`` px one draw each (a fragment
        list pays an atomic per fragment: 20x faster on many small triangles, 12x slower
        on large ones, by ``rastercheck bench``'s workloads)."""
        positions = scene.positions
        n = len(scene)
        finite = finite_within_limit(scene, self.name)
        if n == 0:
            return Coverage.empty()
        safe = np.where(finite[:, None, None], positions, 0.0)  # non-finite ones get the whole screen below
        lo = np.clip(np.floor(safe.min(axis=1)), 0, [scene.width, scene.height])
        hi = np.clip(np.ceil(safe.max(axis=1)) + 1, 0, [scene.width, scene.height])
        boxes = np.where(finite[:, None], np.maximum(hi - lo, 0), [scene.width, scene.height])
        area = boxes[:, 0] * boxes[:, 1]
        large = np.flatnonzero(finite & (area > self.LISTED_BOX))
        parts = []
        if large.size:
            each = self._rasterize_each(ctx, Scene(scene.width, scene.height, positions[large]), side)
            parts.append(Coverage(large[each.triangle], each.y, each.x0, each.x1))
            positions = positions.copy()
            positions[large] = 0.0  # a point: draws nothing, and keeps the primitive ids in step
            area[large] = 0
        parts.append(self._draw_listed(ctx, scene, positions, side, int(np.sum(area)) + 1024))
        return Coverage(*(np.concatenate([getattr(c, f) for c in parts]) for f in ("triangle", "y", "x0", "x1")))

    def _draw_listed(self, ctx: Any, scene: Scene, positions: NDArray, side: int, capacity: int) -> Coverage:
        """One draw of every triangle; ``capacity`` bounds the fragments (no triangle covers
        more than its box)."""
        n = len(positions)
        fbo = ctx.simple_framebuffer((side, side), components=1, dtype="f1")
        vertices = ctx.buffer((positions / side).astype(np.float32).tobytes())  # dividing by a power of two: exact
        vao = ctx.vertex_array(self._list_program, [(vertices, "2f", "position")])
        try:
            while True:
                storage = ctx.buffer(reserve=16 * (capacity + 1))
                storage.write(np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
                storage.bind_to_storage_buffer(0)
                fbo.use()
                ctx.viewport = (-side, -side, 2 * side, 2 * side)
                fbo.scissor = (0, 0, scene.width, scene.height)
                ctx.disable(self._moderngl.CULL_FACE | self._moderngl.BLEND | self._moderngl.DEPTH_TEST)
                vao.render(self._moderngl.TRIANGLES, vertices=3 * n)
                ctx.finish()
                data = np.frombuffer(storage.read(), dtype=np.uint32)
                storage.release()
                count = int(data[0])
                if count <= capacity:
                    break
                capacity = count + 1024  # cannot happen (fragments fit their boxes), but never truncate
            items = data[4:].reshape(-1, 4)[:count].astype(np.int64)
            keep = (items[:, 1] < scene.width) & (items[:, 2] < scene.height)
            return Coverage.from_pixels(items[keep, 0], items[keep, 1], items[keep, 2])
        finally:
            vao.release()
            vertices.release()
            fbo.release()

    def _rasterize_each(self, ctx: Any, scene: Scene, side: int) -> Coverage:
        fbo = ctx.simple_framebuffer((side, side), components=1, dtype="f1")
        fbo.use()
        ctx.viewport = (-side, -side, 2 * side, 2 * side)
        ctx.disable(self._moderngl.CULL_FACE | self._moderngl.BLEND | self._moderngl.DEPTH_TEST)
        buffer = ctx.buffer(reserve=3 * 2 * 4)
        vao = ctx.vertex_array(self._program, [(buffer, "2f", "position")])

        def draw(p: NDArray, bw: int, bh: int, origin: tuple[int, int]) -> NDArray:
            x0, y0 = origin
            ndc = np.empty((3, 2), dtype=np.float32)
            ndc[:, 0] = (p[:, 0] + x0) / side  # dividing by a power of two: exact
            ndc[:, 1] = (p[:, 1] + y0) / side
            buffer.write(ndc.tobytes())
            fbo.scissor = (x0, y0, bw, bh)
            fbo.clear(0.0)
            vao.render(self._moderngl.TRIANGLES, vertices=3)
            data = np.frombuffer(fbo.read(viewport=(x0, y0, bw, bh), components=1, alignment=1), dtype=np.uint8)
            return data.reshape(bh, bw) > 0

        try:
            return draw_each(scene, self.name, draw)
        finally:
            vao.release()
            buffer.release()
            fbo.release()


class MesaLlvmpipe(_Mesa):
    __doc__ = _Mesa.__doc__
    name = "mesa_llvmpipe"
    driver = "llvmpipe"


class MesaSoftpipe(_Mesa):
    __doc__ = _Mesa.__doc__
    name = "mesa_softpipe"
    driver = "softpipe"
