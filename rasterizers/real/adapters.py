"""The library adapters. Each docstring says how the library's coordinates map onto ours:
pixel (i, j) is the square [i, i+1) x [j, j+1), y down."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.api import Coverage, Scene
from harness.conventions import Convention
from harness.registry import Unavailable
from rasterizers.real._masks import coverage_from_sample_masks, draw_each, draw_each_alpha, finite_within_limit

__all__ = ["PillowPolygon", "SkimagePolygon", "SkiaPath", "CairoFill", "MesaLlvmpipe", "MesaSoftpipe",
           "CairoAntialiased", "SkiaAntialiased", "MesaMultisample"]


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


def _skia_fill(skia: Any, p: NDArray, w: int, h: int, antialias: bool) -> NDArray:
    """One triangle filled by skia (a path, black paint) into a w x h alpha-8 surface: the
    (h, w) uint8 alpha."""
    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(w, h))
    canvas = surface.getCanvas()
    canvas.clear(skia.ColorTRANSPARENT)
    path = skia.Path()
    path.moveTo(float(p[0, 0]), float(p[0, 1]))
    path.lineTo(float(p[1, 0]), float(p[1, 1]))
    path.lineTo(float(p[2, 0]), float(p[2, 1]))
    path.close()
    canvas.drawPath(path, skia.Paint(AntiAlias=antialias, Color=skia.ColorBLACK))
    return np.asarray(surface.makeImageSnapshot().toarray(colorType=skia.kAlpha_8_ColorType)).reshape(h, w)


def _cairo_fill(cairo: Any, p: NDArray, w: int, h: int, antialias: Any) -> NDArray:
    """One triangle filled by cairo into a w x h A8 surface: the (h, w) uint8 alpha."""
    surface = cairo.ImageSurface(cairo.FORMAT_A8, w, h)
    ctx = cairo.Context(surface)
    ctx.set_antialias(antialias)
    ctx.move_to(float(p[0, 0]), float(p[0, 1]))
    ctx.line_to(float(p[1, 0]), float(p[1, 1]))
    ctx.line_to(float(p[2, 0]), float(p[2, 1]))
    ctx.close_path()
    ctx.fill()
    surface.flush()
    stride = surface.get_stride()
    return np.frombuffer(surface.get_data(), dtype=np.uint8).reshape(h, stride)[:, :w]


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
        return _skia_fill(self._skia, p, w, h, antialias=False) > 0


class CairoFill(_OneTriangleAtATime):
    """pycairo, ``ANTIALIAS_NONE`` fill: cairo's pixel (i, j) is our [i, i+1) x [j, j+1), so
    coordinates pass unchanged."""

    name = "cairo"

    def __init__(self) -> None:
        self._cairo = _need("cairo", "apt-get install libcairo2-dev pkg-config && pip install pycairo   (or pip install '.[real]')")

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_fill(self._cairo, p, w, h, self._cairo.ANTIALIAS_NONE) > 0


class _AlphaOneTriangleAtATime:
    """An anti-aliasing 2D library drawing one triangle at a time into an 8-bit alpha
    image (``_draw``): area coverage, alpha = pixel value / 255 per (triangle, pixel)."""

    name = ""
    convention: Convention | None = None
    interpolates = False  # coverage only: the library draws no varyings

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        raise NotImplementedError

    def rasterize(self, scene: Scene) -> Coverage:
        return draw_each_alpha(scene, self.name, self._draw)


class CairoAntialiased(_AlphaOneTriangleAtATime):
    """pycairo, ``ANTIALIAS_DEFAULT`` fill into an A8 image surface, one triangle at a
    time; cairo's pixel (i, j) is our [i, i+1) x [j, j+1), so coordinates pass unchanged.
    Alpha is the A8 value / 255. (``GRAY``, ``GOOD``, ``BEST`` and ``SUBPIXEL`` draw the
    same bytes here; ``FAST`` is a 4 x 4 supersampler, tor22, not adapted.)

    Declared convention: area coverage, 256 levels, vertices snapped to 24.8 fixed point
    (``_cairo_fixed_from_double``: round to nearest, ties to even), within
    ``1/15 + 1/256 + 1/510`` (0.0725) of the snapped triangle's area. Why: the image
    backend fills with the tor scan converter (``cairo-tor-scan-converter.c``,
    ``GRID_X`` = 256, ``GRID_Y`` = 15). Edge ends are rounded to a grid of 15 sub-rows per
    pixel and each edge's x is taken at the middle of each sub-row (in rows where no edge
    starts, ends or crosses another, the same x positions bound an exact trapezoid per
    row), so each boundary of a pixel column's covered part is displaced vertically by at
    most half a sub-row, 1/30: two boundaries per column, 1/15 of the pixel's area. Each
    sub-row's x ends are rounded to 1/256 px (at most 1/512 each side: 1/256), and the grid
    area (2 x 256 x 15 units) is rounded to 8 bits (1/510). Measured (Debian 12, cairo
    1.16): an edge swept across a pixel in 1/256 px steps takes 256 distinct alphas when
    vertical, 16 when horizontal (the 15 sub-rows), 33 at 30 degrees; the quick suite's
    static cases stay within 0.0686 of the exact area (1/15 + 1/510) but for a NaN
    triangle (drawn) and a sliver of strip-24, which gets alpha 251/255 where its area
    is ~0.001: a coverage of -5/255 wrapped to 8 bits."""

    name = "cairo_aa"
    # tor scan converter: 15 sub-rows (1/30 per boundary, two per column), x ends to 1/256,
    # 8-bit rounding of the grid area
    convention = Convention(coverage="area", levels=256, subpixel_bits=8, tolerance=1 / 15 + 1 / 256 + 1 / 510)

    def __init__(self) -> None:
        self._cairo = _need("cairo", "apt-get install libcairo2-dev pkg-config && pip install pycairo   (or pip install '.[real]')")

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _cairo_fill(self._cairo, p, w, h, self._cairo.ANTIALIAS_DEFAULT) / 255.0


class SkiaAntialiased(_AlphaOneTriangleAtATime):
    """skia-python, a path per triangle filled with anti-aliasing on into an alpha-8
    surface; skia's pixel (i, j) is our [i, i+1) x [j, j+1), so coordinates pass unchanged.
    Alpha is the alpha-8 value / 255.

    No declared convention (``identify`` fingerprints it): no tolerance follows from a
    documented method. skia's raster back end chooses per path between a supersampler
    (``SkScan_AntiPath.cpp``: 2**SUPERSAMPLE_SHIFT sub-scanlines) and analytic AA
    (``SkScan_AAAPath.cpp``, y snapped to 1/4 px, ``kDefaultAccuracy``), and neither
    states an error bound. What skia-python 144.1 does here, measured with an edge swept
    across a pixel in 1/256 px steps, triangles inside the surface: 17 distinct alphas for
    a vertical edge (x on a 1/16 px grid), 5 for a horizontal one (4 sub-scanlines), 17 at
    30 degrees, for triangles of 4 to 256 px: a 16 x 4 supersampler, 64 samples, more than
    a declared pattern may hold (:data:`harness.conventions.MAX_SAMPLES`). A path that
    leaves the surface on the right is drawn another way (256 distinct alphas for a
    vertical edge), and there shallow edges err by up to 0.08 and edges clipped at the
    left side by up to 0.31. On the quick suite's static cases the alphas are within 0.32
    of the exact area (thin tips and shallow edges of small mesh triangles), 0.0071 on
    average."""

    name = "skia_aa"
    convention = None

    def __init__(self) -> None:
        self._skia = _need("skia", "pip install skia-python   (or pip install '.[real]')")

    def _draw(self, p: NDArray, w: int, h: int, origin: tuple[int, int]) -> NDArray:
        return _skia_fill(self._skia, p, w, h, antialias=True) / 255.0


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


def _fragment_list(ctx: Any, moderngl: Any, program: Any, fbo: Any, positions: NDArray, side: int,
                   scissor: tuple[int, int, int, int], capacity: int) -> NDArray[np.int64]:
    """One draw of ``positions`` (n, 3, 2) float64 (pixels, the viewport mapping of
    :class:`_Mesa`) with ``program``, whose fragment shader appends one uvec4 per fragment
    (primitive id, x, y, ...) to storage buffer 0 (header: count, capacity); returns the
    (K, 4) int64 items of the fragments inside ``scissor`` (x, y, width, height).
    ``capacity`` bounds the fragments; should more arrive, the draw is redone with room
    for them (never truncated)."""
    n = len(positions)
    vertices = ctx.buffer((positions / side).astype(np.float32).tobytes())  # dividing by a power of two: exact
    vao = ctx.vertex_array(program, [(vertices, "2f", "position")])
    try:
        while True:
            storage = ctx.buffer(reserve=16 * (capacity + 1))
            storage.write(np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
            storage.bind_to_storage_buffer(0)
            fbo.use()
            ctx.viewport = (-side, -side, 2 * side, 2 * side)
            fbo.scissor = scissor
            ctx.disable(moderngl.CULL_FACE | moderngl.BLEND | moderngl.DEPTH_TEST)
            vao.render(moderngl.TRIANGLES, vertices=3 * n)
            ctx.finish()
            data = np.frombuffer(storage.read(), dtype=np.uint32)
            storage.release()
            count = int(data[0])
            if count <= capacity:
                break
            capacity = count + 1024  # cannot happen (fragments fit their boxes), but never truncate
        items = data[4:].reshape(-1, 4)[:count].astype(np.int64)
        # the scissor is not trusted as a filter: llvmpipe (22.3) with 4x multisampling runs
        # the shader for the row above and the column left of the rectangle, with the
        # samples past the pixel's centre
        x, y, w, h = scissor
        inside = (items[:, 1] >= x) & (items[:, 1] < x + w) & (items[:, 2] >= y) & (items[:, 2] < y + h)
        return items[inside]
    finally:
        vao.release()
        vertices.release()


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
    convention: Convention | None = None
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
        fbo = ctx.simple_framebuffer((side, side), components=1, dtype="f1")
        try:
            items = _fragment_list(ctx, self._moderngl, self._list_program, fbo, positions, side,
                                   (0, 0, scene.width, scene.height), capacity)
        finally:
            fbo.release()
        keep = (items[:, 1] < scene.width) & (items[:, 2] < scene.height)
        return Coverage.from_pixels(items[keep, 0], items[keep, 1], items[keep, 2])

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


# GL >= 4.3 with multisampling: every fragment appends (primitive id, x, y, the samples of
# the pixel the primitive covers) to a storage buffer. gl_SampleMaskIn holds every covered
# sample of the fragment (the shader reads no per-sample input, so it runs once per pixel);
# a fragment with no sample covered (a helper) stores nothing.
_FRAGMENT_SAMPLES = """#version 430
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
out float coverage;
void main() {
    uint mask = uint(gl_SampleMaskIn[0]);
    if (mask != 0u) {
        uint i = atomicAdd(count, 1u);
        if (i < capacity) items[i] = uvec4(uint(gl_PrimitiveID), uint(gl_FragCoord.x), uint(gl_FragCoord.y), mask);
    }
    coverage = 1.0;
}"""
_GL_SAMPLE_POSITION = 0x8E50
# llvmpipe's 4x sample positions: lp_sample_pos_4x in Mesa's src/gallium/drivers/llvmpipe/lp_rast.c,
# which llvmpipe_get_sample_position reports (GL_SAMPLE_POSITION) and lp_scene.c turns into the
# rasterizer's fixed-point offsets (iround(pos * FIXED_ONE), exact: multiples of 1/8): D3D11's
# standard 4x pattern.
_LLVMPIPE_4X = ((0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875))


class MesaMultisample(_Mesa):
    """Mesa's llvmpipe with a 4x multisample framebuffer, through moderngl's EGL backend:
    which samples of each pixel each triangle covers, read from the fragment shader input
    ``gl_SampleMaskIn`` (bit s: sample s) with ``gl_PrimitiveID`` naming the triangle,
    appended to a storage buffer (GL 4.3), in one draw per batch of triangles.

    Coordinates are mapped as in :class:`MesaLlvmpipe` (float32 NDC ``x / P``, viewport
    (-P, -P, 2P, 2P); GL window row y is our row y, unflipped). GL gives each sample's
    position (``glGetMultisamplefv(GL_SAMPLE_POSITION)``) as an offset from the pixel's
    corner at window (i, j), x right and window y up; window y is our y, so that corner is
    our pixel's top-left corner and GL's offsets are our y-down offsets unchanged.
    llvmpipe reports D3D11's standard 4x pattern, in GL's sample order; the first draw
    checks that the driver reports the declared positions (:meth:`sample_positions`).

    Declared convention: each sample follows llvmpipe's single-sample rule, identified
    exactly for ``mesa_llvmpipe`` (top-left ties with window row y as row y, vertices
    snapped to 1/256 px rounding half to even); a test compares every sample with the
    exact multisample oracle on lattice scenes built to put edges and vertices on samples
    (every other tie rule differs there). On the quick suite's static cases, 36 of
    1,827,799 fragments differ from the oracle, all of triangles reaching beyond the clip
    volume [-P, P]^2, which Mesa clips in float before snapping (as for
    ``mesa_llvmpipe``).

    Triangles whose boxes would overflow the storage budget (:attr:`BUDGET` fragments)
    together are drawn in several batches, and a triangle that alone would is drawn in
    horizontal bands by scissor. The scissor does not filter alone: llvmpipe 22.3 with 4x
    multisampling runs the fragment shader for the row above and the column left of the
    scissor rectangle, with the samples past the pixel's centre (masks 0b1100 and 0b1010),
    so fragments outside it are dropped after the draw."""

    name = "mesa_llvmpipe_msaa4"
    driver = "llvmpipe"
    SAMPLES = 4
    convention = Convention(samples=_LLVMPIPE_4X, tie="top-left", subpixel_bits=8)
    # fragments per draw: 16 bytes each, so 64 MiB of storage at most
    BUDGET = 1 << 22

    def __init__(self) -> None:
        super().__init__()
        self._mask_program: Any = None
        self._positions: tuple[tuple[float, float], ...] | None = None

    def _context(self) -> Any:
        fresh = self._ctx is None or self._pid != os.getpid()
        ctx = super()._context()
        if fresh or self._mask_program is None:
            if ctx.version_code < 430:
                raise Unavailable(f"{self.name}: needs GL 4.3 (storage buffers, gl_SampleMaskIn); "
                                  f"{ctx.info['GL_RENDERER']} offers {ctx.info['GL_VERSION']}")
            self._mask_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT_SAMPLES)
            self._positions = None
        return ctx

    def _framebuffer(self, ctx: Any, side: int) -> tuple[Any, Any]:
        """A side x side 4x multisample framebuffer and its colour renderbuffer."""
        colour = ctx.renderbuffer((side, side), components=1, samples=self.SAMPLES, dtype="f1")
        fbo = ctx.framebuffer(color_attachments=[colour])
        if fbo.samples != self.SAMPLES:
            fbo.release()
            colour.release()
            raise Unavailable(f"{self.name}: {ctx.info['GL_RENDERER']} gave {fbo.samples} samples, not {self.SAMPLES}")
        return fbo, colour

    def sample_positions(self) -> tuple[tuple[float, float], ...]:
        """The sample positions the driver reports for a 4x framebuffer
        (``glGetMultisamplefv(GL_SAMPLE_POSITION, s)``, which moderngl does not expose:
        resolved with ``eglGetProcAddress`` in the EGL library its context runs on), as our
        y-down offsets within the pixel, in GL's sample order."""
        if self._positions is not None and self._pid == os.getpid():
            return self._positions
        import ctypes

        ctx = self._context()
        egl = ctypes.CDLL("libEGL.so.1")
        egl.eglGetProcAddress.restype = ctypes.c_void_p
        egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
        address = egl.eglGetProcAddress(b"glGetMultisamplefv")
        if not address:
            raise Unavailable(f"{self.name}: EGL does not resolve glGetMultisamplefv")
        get = ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_uint, ctypes.POINTER(ctypes.c_float))(address)
        fbo, colour = self._framebuffer(ctx, 16)
        try:
            fbo.use()
            positions = []
            for s in range(self.SAMPLES):
                value = (ctypes.c_float * 2)()
                get(_GL_SAMPLE_POSITION, s, value)
                # window y is our y (unflipped): GL's offset up from the pixel's window corner (i, j)
                # is our offset down from its top-left corner
                positions.append((float(value[0]), float(value[1])))
        finally:
            fbo.release()
            colour.release()
        self._positions = tuple(positions)
        return self._positions

    def rasterize(self, scene: Scene) -> Coverage:
        ctx = self._context()
        side = self._side(scene)
        reported = self.sample_positions()
        declared = _LLVMPIPE_4X
        if reported != declared:
            raise RuntimeError(f"{self.name}: the driver reports sample positions {reported}, "
                               f"not the declared {declared}")
        n = len(scene)
        finite = finite_within_limit(scene, self.name)
        if n == 0:
            return Coverage.empty()
        positions = scene.positions
        safe = np.where(finite[:, None, None], positions, 0.0)  # non-finite ones get the whole screen below
        lo = np.clip(np.floor(safe.min(axis=1)), 0, [scene.width, scene.height]).astype(np.int64)
        hi = np.clip(np.ceil(safe.max(axis=1)) + 1, 0, [scene.width, scene.height]).astype(np.int64)
        lo[~finite] = 0
        hi[~finite] = [scene.width, scene.height]
        boxes = np.maximum(hi - lo, 0)
        area = boxes[:, 0] * boxes[:, 1]
        fbo, colour = self._framebuffer(ctx, side)
        parts = []
        try:
            large = np.flatnonzero(area > self.BUDGET)
            for t in large:  # alone, in bands of rows that fit the budget
                rows = max(1, self.BUDGET // int(boxes[t, 0]))
                for y0 in range(int(lo[t, 1]), int(hi[t, 1]), rows):
                    band = (int(lo[t, 0]), y0, int(boxes[t, 0]), min(rows, int(hi[t, 1]) - y0))
                    items = _fragment_list(ctx, self._moderngl, self._mask_program, fbo, positions[t:t + 1], side,
                                           band, band[2] * band[3] + 1024)
                    items[:, 0] = t
                    parts.append(items)
            small = np.where(area > self.BUDGET, 0, area)
            total = np.cumsum(small)
            start = 0
            while start < n:  # batches of consecutive triangles whose boxes fit the budget together
                before = int(total[start - 1]) if start else 0
                end = max(start + 1, int(np.searchsorted(total, before + self.BUDGET, side="right")))
                batch = positions[start:end].copy()
                batch[area[start:end] > self.BUDGET] = 0.0  # drawn above; a point draws nothing and keeps the ids in step
                items = _fragment_list(ctx, self._moderngl, self._mask_program, fbo, batch, side,
                                       (0, 0, scene.width, scene.height), int(small[start:end].sum()) + 1024)
                items[:, 0] += start
                parts.append(items)
                start = end
        finally:
            fbo.release()
            colour.release()
        items = np.concatenate(parts)
        items = items[(items[:, 1] < scene.width) & (items[:, 2] < scene.height)]
        # bit s of gl_SampleMaskIn is sample s, in GL's sample order (that of the declared pattern)
        return coverage_from_sample_masks(items[:, 0], items[:, 1], items[:, 2], items[:, 3], scene.width, self.SAMPLES)
