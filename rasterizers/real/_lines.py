"""Line scenes on Mesa (llvmpipe, softpipe) through moderngl: separate segments as
``GL_LINES``, polylines as ``GL_LINE_STRIP``, width 1, no smoothing, single-sample, every
fragment named by its segment (see :class:`rasterizers.real.adapters.MesaLlvmpipe`).

The few GL calls moderngl does not make (line width, smoothing, primitive restart) are
resolved with ``eglGetProcAddress`` in the EGL library moderngl's context runs on, as in
:mod:`rasterizers.real._stencil`. Both drivers receive a strip from Mesa's draw module one
segment (vertex pair) at a time (``lp_setup_vbuf.c``, ``sp_prim_vbuf.c``): nothing is
carried from one segment of a strip to the next.
"""

from __future__ import annotations

import ctypes
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from rasterizers.real._masks import budget_batches, coverage_from_fragments, segment_boxes

__all__ = ["MesaLines", "LINE_FRAGMENT_LIST", "draw_lists", "RESTART"]

# GL enums (glcorearb.h)
GL_LINE_SMOOTH = 0x0B20
GL_PRIMITIVE_RESTART = 0x8F9D
# the index that ends one strip and starts the next (GL 3.1 primitive restart; moderngl
# enables restart with this index when it makes a context)
RESTART = 0xFFFFFFFF

_VERTEX = """#version 330
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }"""

_U = ctypes.c_uint
_SIGNATURES: dict[str, tuple[Any, tuple[Any, ...]]] = {
    "glEnable": (None, (_U,)),
    "glDisable": (None, (_U,)),
    "glLineWidth": (None, (ctypes.c_float,)),
    "glPrimitiveRestartIndex": (None, (_U,)),
}


def _gl_functions() -> dict[str, Any]:
    """The GL entry points of :data:`_SIGNATURES`, from ``eglGetProcAddress``."""
    egl = ctypes.CDLL("libEGL.so.1")
    egl.eglGetProcAddress.restype = ctypes.c_void_p
    egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
    functions = {}
    for name, (result, arguments) in _SIGNATURES.items():
        address = egl.eglGetProcAddress(name.encode())
        if not address:
            raise RuntimeError(f"EGL does not resolve {name}")
        functions[name] = ctypes.CFUNCTYPE(result, *arguments)(address)
    return functions


# GL >= 4.3: every fragment appends (base + gl_PrimitiveID, x, y) to a storage buffer.
# gl_PrimitiveID counts the draw's lines: GL_LINES' pairs, or a GL_LINE_STRIP's segments,
# through primitive restarts (GL 4.5, 11.1.3.9: "restarting a primitive topology using the
# primitive restart index has no effect on the primitive ID counter"). ``base`` tells the
# draws of one read-back apart.
LINE_FRAGMENT_LIST = """#version 430
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
uniform uint base;
out float coverage;
void main() {
    uint i = atomicAdd(count, 1u);
    if (i < capacity) items[i] = uvec4(base + uint(gl_PrimitiveID), uint(gl_FragCoord.x), uint(gl_FragCoord.y), 0u);
    coverage = 1.0;
}"""


def draw_lists(scene: LineScene, segments: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64],
                                                                       NDArray[np.int64]]:
    """How to draw ``segments`` (ascending scene indices): the separate ones (strips of
    two vertices) as ``GL_LINES``, the others as ``GL_LINE_STRIP`` runs.

    A run is a maximal set of consecutive listed segments of one strip; runs are
    separated by the restart index (:data:`RESTART`), so a strip with a segment left out
    (a NaN vertex) is drawn as the strips on either side of it.

    Returns
    -------
    lines : (2 L,) int64
        Vertex indices of the ``GL_LINES`` draw, two per segment.
    line_segments : (L,) int64
        The scene segment of each of its lines (its gl_PrimitiveID order).
    strip : (I,) int64
        Vertex indices of the ``GL_LINE_STRIP`` draw, runs separated by :data:`RESTART`.
    strip_segments : (M,) int64
        The scene segment of each of its segments (gl_PrimitiveID order: restarts do not
        count).

    Examples
    --------
    >>> scene = LineScene.from_strips(9, 9, [[[0, 0], [1, 1]], [[2, 2], [3, 3], [4, 4], [5, 5]], [[6, 6], [7, 7]]])
    >>> lines, line_segments, strip, strip_segments = draw_lists(scene, np.array([0, 1, 3, 4]))
    >>> lines.tolist(), line_segments.tolist()
    ([0, 1, 6, 7], [0, 4])
    >>> [int(i) if i != RESTART else -1 for i in strip], strip_segments.tolist()
    ([2, 3, -1, 4, 5, -1], [1, 3])
    """
    segments = np.asarray(segments, dtype=np.int64)
    start = scene.segment_start[segments]
    separate = scene.strip_sizes[scene.segment_strip[segments]] == 2
    line_segments = segments[separate]
    lines = np.stack([start[separate], start[separate] + 1], axis=1).reshape(-1)
    strip_segments = segments[~separate]
    first = start[~separate]
    strip_of = scene.segment_strip[strip_segments]
    # a run continues when the next listed segment is the next one of the same strip
    head = np.ones(strip_segments.size, dtype=bool)
    head[1:] = (strip_segments[1:] != strip_segments[:-1] + 1) | (strip_of[1:] != strip_of[:-1])
    run = np.cumsum(head) - 1
    # per run: its first segment's start vertex, then one vertex per segment, then RESTART
    n_runs = int(head.sum())
    run_length = np.bincount(run, minlength=n_runs)
    slot_of_run = np.cumsum(run_length + 2) - (run_length + 2)
    strip = np.full(int(np.sum(run_length + 2)), RESTART, dtype=np.int64)
    strip[slot_of_run] = first[head]
    rank = np.arange(strip_segments.size) - np.repeat(np.flatnonzero(head), run_length)
    strip[slot_of_run[run] + rank + 1] = first + 1
    return lines.astype(np.int64), line_segments, strip, strip_segments


class MesaLines:
    """Line scenes on a moderngl context: :meth:`rasterize`.

    Parameters
    ----------
    ctx, moderngl : the context and the moderngl module
    program : a moderngl program drawing ``in vec2 position`` with a constant colour
        (one segment per draw, read back by colour)
    listed : bool
        Whether to read fragments back through a storage buffer (GL 4.3: one read-back per
        batch, each fragment named by ``gl_PrimitiveID``) rather than one colour read-back
        per segment.
    """

    # fragments per batch of the fragment list: 16 bytes each, so 64 MiB of storage at most
    BUDGET = 1 << 22

    def __init__(self, ctx: Any, moderngl: Any, program: Any, listed: bool) -> None:
        self.ctx, self.moderngl, self.program = ctx, moderngl, program
        self.gl = _gl_functions()
        self.list_program = ctx.program(vertex_shader=_VERTEX, fragment_shader=LINE_FRAGMENT_LIST) if listed else None

    def _begin(self, fbo: Any, side: int) -> None:
        """Aliased lines of width 1, strips restarting at :data:`RESTART`. The framebuffer
        has one sample per pixel, so no multisample rasterization happens whatever
        ``GL_MULTISAMPLE`` says (GL 4.5, 14.3.1: it needs ``SAMPLE_BUFFERS`` = 1)."""
        gl = self.gl
        fbo.use()
        self.ctx.viewport = (-side, -side, 2 * side, 2 * side)  # the triangle adapter's exact mapping
        self.ctx.disable(self.moderngl.CULL_FACE | self.moderngl.BLEND | self.moderngl.DEPTH_TEST)
        gl["glLineWidth"](1.0)
        gl["glDisable"](GL_LINE_SMOOTH)
        gl["glEnable"](GL_PRIMITIVE_RESTART)
        gl["glPrimitiveRestartIndex"](RESTART)

    def rasterize(self, scene: LineScene, side: int, name: str) -> Coverage:
        """Every finite segment's fragments (a segment with a NaN or infinite end point is
        not drawn and covers nothing; a coordinate beyond the adapters' limit: ValueError
        naming the segment). ``side``: the power-of-two P of the mapping x -> x / P."""
        boxes, drawn = segment_boxes(scene, name, margin=1)
        if not drawn.size:
            return Coverage.empty()
        ctx = self.ctx
        # float32 NDC x / P: dividing by a power of two is exact (as for triangles)
        with np.errstate(over="ignore", invalid="ignore"):
            ndc = (np.where(np.isfinite(scene.vertices), scene.vertices, 0.0) / side).astype(np.float32)
        vertices = ctx.buffer(ndc.tobytes())
        # the screen only: the viewport (-P, -P, 2P, 2P) may reach far beyond it
        fbo = ctx.simple_framebuffer((scene.width, scene.height), components=1, dtype="f1")
        try:
            self._begin(fbo, side)
            if self.list_program is not None:
                return self._listed(scene, drawn, boxes, vertices, fbo, self.list_program)
            return self._each(scene, drawn, boxes, vertices, fbo)
        finally:
            fbo.release()
            vertices.release()

    def _each(self, scene: LineScene, drawn: NDArray[np.int64], boxes: NDArray[np.int64], vertices: Any, fbo: Any) -> Coverage:
        """One draw per segment, scissored to its box and read back by colour: a separate
        segment as ``GL_LINES``, a strip's segment as a two-vertex ``GL_LINE_STRIP`` from
        the strip's vertices (what the draw module hands the driver for that segment of
        the whole strip)."""
        moderngl = self.moderngl
        vao = self.ctx.vertex_array(self.program, [(vertices, "2f", "position")])
        start = scene.segment_start
        separate = scene.strip_sizes[scene.segment_strip] == 2
        parts = []
        try:
            for k in drawn.tolist():
                x0, y0, x1, y1 = (int(v) for v in boxes[k])
                fbo.scissor = (x0, y0, x1 - x0, y1 - y0)
                fbo.clear(0.0)
                vao.render(moderngl.LINES if separate[k] else moderngl.LINE_STRIP, vertices=2, first=int(start[k]))
                data = np.frombuffer(fbo.read(viewport=(x0, y0, x1 - x0, y1 - y0), components=1, alignment=1), dtype=np.uint8)
                mask = data.reshape(y1 - y0, x1 - x0) > 0
                if mask.any():
                    cov = Coverage.from_mask(k, mask)
                    parts.append(Coverage(cov.primitive, cov.y + y0, cov.x0 + x0, cov.x1 + x0))
        finally:
            vao.release()
        return Coverage.concat(parts) if parts else Coverage.empty()

    def _listed(self, scene: LineScene, drawn: NDArray[np.int64], boxes: NDArray[np.int64], vertices: Any,
                fbo: Any, program: Any) -> Coverage:
        """Batches of consecutive segments whose fragments fit :attr:`BUDGET`: per batch one
        ``GL_LINES`` draw and one ``GL_LINE_STRIP`` draw appending to one storage buffer,
        read back once."""
        extent = boxes[drawn, 2:] - boxes[drawn, :2]
        # a one-pixel-wide line has at most one fragment per step of its major axis (+1)
        bound = extent.max(axis=1) + 1
        parts = [self._batch(scene, drawn[start:end], vertices, fbo, program, int(bound[start:end].sum()) + 1024)
                 for start, end in budget_batches(bound, self.BUDGET)]
        return Coverage.concat(parts)

    def _batch(self, scene: LineScene, segments: NDArray[np.int64], vertices: Any, fbo: Any, program: Any,
               capacity: int) -> Coverage:
        """One read-back of ``segments``' fragments (``capacity`` bounds their number)."""
        ctx, moderngl = self.ctx, self.moderngl
        lines, line_segments, strip, strip_segments = draw_lists(scene, segments)
        owner = np.concatenate([line_segments, strip_segments])  # base + gl_PrimitiveID -> segment
        draws = [(moderngl.LINES, lines, 0), (moderngl.LINE_STRIP, strip, line_segments.size)]
        while True:
            storage = ctx.buffer(reserve=16 * (capacity + 1))
            try:
                storage.write(np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
                storage.bind_to_storage_buffer(0)
                for mode, indices, base in draws:
                    if not indices.size:
                        continue
                    index_buffer = ctx.buffer(indices.astype(np.uint32).tobytes())
                    vao = ctx.vertex_array(program, [(vertices, "2f", "position")], index_buffer=index_buffer,
                                           index_element_size=4)
                    try:
                        program["base"].value = int(base)
                        fbo.use()
                        fbo.scissor = (0, 0, scene.width, scene.height)
                        vao.render(mode)
                    finally:
                        vao.release()
                        index_buffer.release()
                ctx.finish()
                data = np.frombuffer(storage.read(), dtype=np.uint32)
            finally:
                storage.release()
            count = int(data[0])
            if count <= capacity:
                break
            capacity = count + 1024  # more fragments than the bound: redo with room, never truncate
        items = data[4:].reshape(-1, 4)[:count].astype(np.int64)
        # the framebuffer and the scissor are the screen; should a fragment fall outside, drop it
        keep = (items[:, 1] < scene.width) & (items[:, 2] < scene.height)
        items = items[keep]
        if np.any(items[:, 0] >= owner.size):
            raise RuntimeError(f"gl_PrimitiveID beyond the {owner.size} segments drawn")
        return coverage_from_fragments(owner[items[:, 0]], items[:, 1], items[:, 2], scene.width, scene.height)
