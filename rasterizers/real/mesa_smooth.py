"""GL's smooth lines on Mesa (issue 34): ``GL_LINE_SMOOTH`` through moderngl's EGL backend,
judged against the exact area of the butt-capped w-wide rectangle
(:mod:`harness.oracle.area_lines`) with a tolerance derived from Mesa's own method.

What the GL specification asks (OpenGL 1.1, 3.4.2 "Other Line Segment Features",
Antialiasing; the same text in every later one, 3.5.2 up to OpenGL 4.2's compatibility
profile): an anti-aliased segment's fragments are those whose squares meet a rectangle
centred on the segment, its long edges half the line width from it on either side and its
short edges through the end points, perpendicular to it; each fragment's coverage is the
area of the rectangle's intersection with the fragment's square. That is
``LineRule("rectangle")`` (butt caps) under area coverage. The specification states no
error bound, and not every width need be supported: an implementation reports the range
of its anti-aliased widths (``GL_SMOOTH_LINE_WIDTH_RANGE``), 1.0 always among them.

What Mesa's source says (read in Mesa 23.0-devel's
``src/gallium/auxiliary/draw/draw_pipe_aaline.c`` and
``src/gallium/auxiliary/nir/nir_draw_helpers.c``): both drivers install the draw module's
anti-aliased line stage (``draw_install_aaline_stage`` in ``lp_context.c`` /
``sp_context.c``), which the pipeline runs for every line while ``line_smooth`` is on and
the framebuffer is single-sample. ``aaline_first_line`` sets the half width
``hw = w/2 + 1/2`` (``hw = 1`` when ``w <= 1``); ``aaline_line`` turns the segment a -> b of
length L (direction ``u``, normal ``n``) into a quad of two triangles, the segment
lengthened by 1/2 px at each end and widened to ``hw`` on each side, with a new varying
(d, hw, s, hl) that runs linearly from -hw to hw across the quad and from -hl to hl along
it, ``hl = L/2 + 1/2``. The fragment shader (``nir_lower_aaline_fs``) multiplies the
colour's alpha by

    ``alpha = sat(hw - |d|) * min(sat(hl - |s|), 2 hl - 1)``

at the fragment's centre, where d and s are the centre's distances from the segment's line
(across) and from its midpoint (along). For ``w >= 1`` each factor is the length of the
overlap of a unit interval centred on the coordinate with the rectangle's extent on that
axis (``[d - 1/2, d + 1/2]`` with ``[-w/2, w/2]``: ``sat(w/2 + 1/2 - |d|)``; with
``[-L/2, L/2]``: ``min(sat(L/2 + 1/2 - |s|), L)``), so Mesa's alpha is exactly

    ``alpha = area(R ∩ S_u)``,

the area of the rectangle R the specification names intersected with the unit square S_u
centred on the pixel's centre but *turned to the segment's direction* -- the specification's
fragment square is S, not turned. (:func:`turned_square_alpha` computes it; a test checks the
identity against a rational polygon clipping, and the drivers' alphas against it.)

What the drivers do, measured (Mesa 22.3.6, llvmpipe and softpipe alike, read back from a
32-bit float colour buffer): exactly that for segments at least 1 px long, but a segment
shorter than 1 px gets ``sat(hw - |d|) * sat(hl - |s|) * min(1, L / hl)`` (its along factor
scaled by ``2L / (L + 1)`` rather than capped at L); :func:`smooth_line_alpha` is this,
and the drivers' float alphas equal it within 6e-6 on random segments of widths 1 to 4 and
lengths 0 to 1.7 px (tests/rasterizers/real/test_mesa_smooth.py).

The tolerance, derived: S and S_u have the same centre and area 1, so

    ``|area(R ∩ S_u) - area(R ∩ S)| <= max(area(S_u \\ S), area(S \\ S_u)) = 1 - area(S ∩ S_u)``

for every R, and S ∩ S_u is smallest when S_u is turned by 45 degrees: a regular octagon of
area ``2 (sqrt 2 - 1)``. So the turned-square alpha is within ``3 - 2 sqrt 2`` (0.1716,
:data:`MODEL_ERROR`) of the exact area, and that bound is reached: a 1 x 1 segment at 45
degrees centred on a pixel's centre is R = S_u, alpha 1 against the octagon's 0.828. (Inside
a long segment's body only the two long edges cut the pixel, and the error is at most half
of that, 0.0858, at 45 degrees, a width-1 segment along the pixel's diagonal; the worst
cases are at the ends.) A segment shorter than 1 px is drawn fainter still: with
``t = sat(hl - |s|) <= hl``, ``min(t, L) - t L / hl`` is largest at t = L, where it is
``L (1 - L) / (1 + L)``, largest at ``L = sqrt 2 - 1``: ``3 - 2 sqrt 2`` again
(:data:`SHORT_ERROR`), and never the other way (``t L / hl <= min(t, L)``). Added to them:
the alpha is written to an 8-bit unorm colour buffer (at most 1/510 off), and the quad's
corners are snapped to llvmpipe's 1/256 px grid before its pixel centres are chosen, so a
pixel centre within 2**-8 px of the quad's edge (where the ramps give an alpha below 2**-8)
may be left out or taken in: both bounded by ``2**-8``. And ``2**-9`` for float32
arithmetic (the quad's corners and the varying's plane equations, on coordinates of at
most 2**13 px, whose float32 spacing is 2**-10: two of those). Declared:
``tolerance = 2 (3 - 2 sqrt 2) + 2**-8 + 2**-9`` (0.3490), the sum of bounds each reached
on its own; segments of 1 px and longer stay within ``3 - 2 sqrt 2 + 2**-8 + 2**-9``
(0.1774). The sum is likely not tight: maximising ``area - alpha`` and ``alpha - area`` over
segment, width and pixel (Nelder-Mead from 150 random starts each) finds ``3 - 2 sqrt 2`` on
both sides, at the two cases above (a horizontal segment ``sqrt 2 - 1`` long whose pixel
holds it whole; the 1 x 1 diagonal), and where the short-segment shortfall is largest
(``t = L``, the pixel's square holding the segment's whole length) the square turned by any
angle holds at most as much of R as the unturned one, so the two do not add there. Without
a proof for every sub-pixel segment, the sum stays declared; it costs sensitivity: the
minor-axis box drawer (tests/known_bad/aa_lines.py) errs by 0.19 at width 1, inside 0.349.

Widths: Mesa's smooth widths are [1, 255] (``GL_SMOOTH_LINE_WIDTH_RANGE``); below 1 the stage
draws a 1 px wide line (``hw = 1``), which is GL's nearest supported width but not the
rectangle the scene asks for, so narrower lines are refused (``Unsupported``), as are wider
ones than 255.

Measured (Mesa 22.3.6, llvmpipe, RGBA8): the quick suite's line cases all pass accuracy, max
``|alpha - area|`` 0.142 (width 1: sub-pixel segments around pixel centres) and 0.119 (width
2.5); random segments of widths 1, 1.5, 2.5, 4: 0.136, 0.140, 0.136, 0.158.
"""

from __future__ import annotations

import ctypes
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, Unsupported
from rasterizers.real._aa_lines import draw_each_segment_alpha
from rasterizers.real._lines import GL_LINE_SMOOTH
from rasterizers.real.adapters import _Mesa

__all__ = ["MesaSmoothLines", "MODEL_ERROR", "SHORT_ERROR", "SMOOTH_TOLERANCE", "smooth_line_alpha", "turned_square_alpha"]

# 1 - area(S ∩ S turned 45 degrees): the most Mesa's turned-square model can differ from the
# exact area (module docstring)
MODEL_ERROR = 3.0 - 2.0 * math.sqrt(2.0)
# the most a segment shorter than 1 px is drawn fainter than the turned-square alpha:
# max over L of L (1 - L) / (1 + L), at L = sqrt(2) - 1 (module docstring)
SHORT_ERROR = 3.0 - 2.0 * math.sqrt(2.0)
# + 8-bit output or a pixel centre beside the snapped quad (2**-8) + float32 arithmetic (2**-9)
SMOOTH_TOLERANCE = MODEL_ERROR + SHORT_ERROR + 2.0**-8 + 2.0**-9

_VERTEX = """#version 330
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }"""
# the aaline stage scales the colour's alpha by the coverage (nir_lower_aaline_fs): a vec4
# output whose alpha is 1, blending off, so the alpha written is the coverage
_FRAGMENT = """#version 330
out vec4 colour;
void main() { colour = vec4(1.0); }"""


def _frame(a: NDArray[np.float64], b: NDArray[np.float64], x: NDArray[np.float64],
           y: NDArray[np.float64]) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """The segment's length L and the centres' distances d (across) and s (along, from the
    midpoint)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    length = float(np.hypot(*(b - a)))
    ux, uy = (b - a) / length
    mx, my = (a + b) / 2
    px, py = np.asarray(x, dtype=np.float64) - mx, np.asarray(y, dtype=np.float64) - my
    return length, np.abs(ux * py - uy * px), np.abs(ux * px + uy * py)


def turned_square_alpha(a: NDArray[np.float64], b: NDArray[np.float64], width: float,
                        x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """What Mesa's source computes (``nir_lower_aaline_fs``) at the pixel centres (x, y) for
    the segment a -> b, ``width >= 1``: ``sat(hw - |d|) * min(sat(hl - |s|), 2 hl - 1)``
    with ``hw = w/2 + 1/2``, ``hl = L/2 + 1/2``, d and s the centre's distances across and
    along from the segment's midpoint; in float64. It is the area of the w-wide rectangle
    intersected with the unit square centred on (x, y) turned to the segment's direction.

    >>> a, b = np.array([1.0, 1.0]), np.array([5.0, 1.0])
    >>> turned_square_alpha(a, b, 1.0, np.array([0.5, 1.5, 1.5, 3.5]), np.array([1.5, 1.5, 0.5, 2.5])).tolist()
    [0.0, 0.5, 0.5, 0.0]
    """
    length, d, s = _frame(a, b, x, y)
    hw = 0.5 * max(width, 1.0) + 0.5
    hl = 0.5 * length + 0.5
    alpha: NDArray[np.float64] = np.clip(hw - d, 0.0, 1.0) * np.minimum(np.clip(hl - s, 0.0, 1.0), 2.0 * hl - 1.0)
    return alpha


def smooth_line_alpha(a: NDArray[np.float64], b: NDArray[np.float64], width: float,
                      x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """What Mesa 22.3's drivers draw (measured): :func:`turned_square_alpha` for segments
    at least 1 px long; a shorter one's along factor is ``sat(hl - |s|) * L / hl`` instead
    of ``min(sat(hl - |s|), L)``.

    >>> a, b = np.array([6.0, 6.5]), np.array([6.5, 6.5])  # 1/2 px long: hl = 3/4
    >>> smooth_line_alpha(a, b, 1.0, np.array([6.5]), np.array([6.5])).tolist()  # 1/2 * (1/2) / (3/4)
    [0.3333333333333333]
    """
    length, d, s = _frame(a, b, x, y)
    hw = 0.5 * max(width, 1.0) + 0.5
    hl = 0.5 * length + 0.5
    alpha: NDArray[np.float64] = np.clip(hw - d, 0.0, 1.0) * np.clip(hl - s, 0.0, 1.0) * min(1.0, length / hl)
    return alpha


class MesaSmoothLines(_Mesa):
    """Mesa llvmpipe's smooth lines (``GL_LINE_SMOOTH``), one segment per draw into a
    cleared, scissored box of an RGBA8 colour buffer, blending off: the alpha read back is
    the coverage Mesa's anti-aliased line stage computed (module docstring: what it computes,
    and why it is within :data:`SMOOTH_TOLERANCE` of the exact rectangle's area).

    Coordinates are mapped as in :class:`~rasterizers.real.adapters.MesaLlvmpipe` (float32
    NDC ``x / P``, viewport (-P, -P, 2P, 2P), window row y is our row y; P widened until the
    clip volume holds every end point, since Mesa clips a segment before the stage widens
    it). ``glEnable(GL_LINE_SMOOTH)`` and ``glLineWidth`` (which moderngl does not expose)
    are resolved with ``eglGetProcAddress``. Each segment is drawn alone (a polyline's
    joint comes back once per segment), so every alpha is one segment's. One Mesa adapter
    per process (the EGL display is made once: see ``_Mesa``); the runner gives each
    adapter a worker of its own."""

    name = "mesa_llvmpipe_smooth"
    driver = "llvmpipe"
    library = "Mesa llvmpipe (OpenGL)"
    coverage_kind = "area"
    scene_kinds = ("lines",)
    # llvmpipe 22.3 ignores GL_POLYGON_SMOOTH (measured: a triangle's alphas are 0 or 1)
    _NO_SMOOTH_POLYGONS = "llvmpipe ignores GL_POLYGON_SMOOTH (alphas 0 or 1)"
    kinds_not_taken = {"triangles": f"{_NO_SMOOTH_POLYGONS}: mesa_llvmpipe fills triangles",
                       "paths": f"{_NO_SMOOTH_POLYGONS}: mesa_llvmpipe fills paths"}
    fill_rules = None  # type: ignore[assignment]  # (no paths)
    convention = Convention(coverage="area", input="float32", line=LineRule("rectangle"), tolerance=SMOOTH_TOLERANCE)
    line_convention = convention
    batch = False  # no fragment list: the coverage is in the colour the stage writes
    # GL_SMOOTH_LINE_WIDTH_RANGE of llvmpipe and softpipe (PIPE_CAPF_MAX_LINE_WIDTH_AA)
    WIDTHS = (1.0, 255.0)
    # the colour buffer's type: "f1" (RGBA8, as declared); "f4" reads the unrounded alphas
    colour_dtype = "f1"

    def __init__(self) -> None:
        super().__init__()
        self._smooth_program: Any = None
        self._gl: dict[str, Any] = {}

    def _context(self) -> Any:
        fresh = self._ctx is None
        ctx = super()._context()
        if fresh or self._smooth_program is None or self._gl.get("ctx") is not ctx:
            self._smooth_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
            egl = ctypes.CDLL("libEGL.so.1")
            egl.eglGetProcAddress.restype = ctypes.c_void_p
            egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
            gl: dict[str, Any] = {"ctx": ctx}
            for name, signature in (("glEnable", ctypes.CFUNCTYPE(None, ctypes.c_uint)),
                                    ("glDisable", ctypes.CFUNCTYPE(None, ctypes.c_uint)),
                                    ("glLineWidth", ctypes.CFUNCTYPE(None, ctypes.c_float)),
                                    ("glGetError", ctypes.CFUNCTYPE(ctypes.c_uint))):
                address = egl.eglGetProcAddress(name.encode())
                if not address:
                    raise RuntimeError(f"{self.name}: EGL does not resolve {name}")
                gl[name] = signature(address)
            self._gl = gl
        return ctx

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, LineScene):
            raise ValueError(f"{self.name}: takes lines only (scene_kinds); triangles and paths: mesa_llvmpipe")
        width = float(scene.line_width)
        low, high = self.WIDTHS
        if not low <= width <= high:
            # below 1 the stage draws a 1 px wide line (draw_pipe_aaline.c: half width 1)
            raise Unsupported(f"{self.name}: draws smooth lines {low:g} to {high:g} px wide "
                              f"(GL_SMOOTH_LINE_WIDTH_RANGE), not {width:g}")
        ctx = self._context()
        side = self._guard_band(scene, self._side(scene))
        moderngl = self._moderngl
        gl = self._gl
        fbo = ctx.simple_framebuffer((side, side), components=4, dtype=self.colour_dtype)
        buffer = ctx.buffer(reserve=2 * 2 * 4)
        vao = ctx.vertex_array(self._smooth_program, [(buffer, "2f", "position")])
        fbo.use()
        ctx.viewport = (-side, -side, 2 * side, 2 * side)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND | moderngl.DEPTH_TEST)
        while gl["glGetError"]():  # an error left by an earlier call (moderngl's own) is not ours
            pass
        gl["glEnable"](GL_LINE_SMOOTH)
        gl["glLineWidth"](width)
        error = int(gl["glGetError"]())
        if error:
            raise RuntimeError(f"{self.name}: glEnable(GL_LINE_SMOOTH) / glLineWidth({width:g}) gave GL error {error:#x}")
        dtype = np.uint8 if self.colour_dtype == "f1" else np.float32
        scale = 255.0 if self.colour_dtype == "f1" else 1.0

        def draw(a: NDArray, b: NDArray, bw: int, bh: int, origin: tuple[int, int]) -> NDArray:
            x0, y0 = origin
            ndc = np.empty((2, 2), dtype=np.float32)
            ndc[0] = (a + origin) / side  # a + origin: the scene's own end point; / P exact
            ndc[1] = (b + origin) / side
            buffer.write(ndc.tobytes())
            fbo.scissor = (x0, y0, bw, bh)
            fbo.clear(0.0, 0.0, 0.0, 0.0)
            vao.render(moderngl.LINES, vertices=2)
            data = np.frombuffer(fbo.read(viewport=(x0, y0, bw, bh), components=4, alignment=1, dtype=self.colour_dtype),
                                 dtype=dtype)
            alpha: NDArray = data.reshape(bh, bw, 4)[:, :, 3].astype(np.float64) / scale
            return alpha

        try:
            # the quad reaches w/2 + 1 px beyond the segment's box on each axis
            return draw_each_segment_alpha(scene, self.name, draw, margin=2)
        finally:
            gl["glDisable"](GL_LINE_SMOOTH)
            gl["glLineWidth"](1.0)
            vao.release()
            buffer.release()
            fbo.release()
