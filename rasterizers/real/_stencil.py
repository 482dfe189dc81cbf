"""Paths on Mesa by stencil-then-cover: the winding number counted in the stencil buffer
by triangle fans, then a cover pass over each path's box that keeps the samples whose
count satisfies the fill rule (see :class:`rasterizers.real.adapters.MesaLlvmpipe`).

moderngl (5.x) sets no stencil state and makes no stencil attachment, so the few GL calls
needed here are resolved with ``eglGetProcAddress`` in the EGL library moderngl's context
runs on and called through ctypes; everything else (programs, buffers, vertex arrays,
read-back) stays moderngl's. moderngl's ``VertexArray.render`` binds only its program
and vertex array, so the raw state set here holds across its draws.
"""

from __future__ import annotations

import ctypes
from typing import Any, NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene
from rasterizers.real._masks import budget_batches, coverage_from_fragments, finite_within_limit, path_extents

__all__ = ["StencilPaths", "fans", "fan_indices", "cover_boxes", "layers", "CHUNK", "TILE"]

# GL enums (glcorearb.h)
GL_ZERO = 0
GL_NOTEQUAL, GL_ALWAYS = 0x0205, 0x0207
GL_FRONT, GL_BACK = 0x0404, 0x0405
GL_STENCIL_TEST, GL_SCISSOR_TEST = 0x0B90, 0x0C11
GL_KEEP, GL_INVERT = 0x1E00, 0x150A
GL_INCR_WRAP, GL_DECR_WRAP = 0x8507, 0x8508
GL_COLOR_BUFFER_BIT, GL_STENCIL_BUFFER_BIT = 0x4000, 0x0400
GL_FRAMEBUFFER, GL_RENDERBUFFER = 0x8D40, 0x8D41
GL_STENCIL_ATTACHMENT, GL_STENCIL_INDEX8 = 0x8D20, 0x8D48
GL_DEPTH_STENCIL_ATTACHMENT, GL_DEPTH24_STENCIL8 = 0x821A, 0x88F0
GL_FRAMEBUFFER_COMPLETE = 0x8CD5
GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE = 0x8217

_U, _I, _B = ctypes.c_uint, ctypes.c_int, ctypes.c_ubyte
# name: (result, argument types)
_SIGNATURES: dict[str, tuple[Any, tuple[Any, ...]]] = {
    "glEnable": (None, (_U,)),
    "glDisable": (None, (_U,)),
    "glStencilFunc": (None, (_U, _I, _U)),
    "glStencilOp": (None, (_U, _U, _U)),
    "glStencilOpSeparate": (None, (_U, _U, _U, _U)),
    "glStencilMask": (None, (_U,)),
    "glColorMask": (None, (_B, _B, _B, _B)),
    "glClearColor": (None, (ctypes.c_float,) * 4),
    "glClearStencil": (None, (_I,)),
    "glClear": (None, (_U,)),
    "glScissor": (None, (_I, _I, _I, _I)),
    "glGenRenderbuffers": (None, (_I, ctypes.POINTER(_U))),
    "glDeleteRenderbuffers": (None, (_I, ctypes.POINTER(_U))),
    "glBindRenderbuffer": (None, (_U, _U)),
    "glRenderbufferStorage": (None, (_U, _U, _I, _I)),
    "glFramebufferRenderbuffer": (None, (_U, _U, _U, _U)),
    "glCheckFramebufferStatus": (_U, (_U,)),
    "glGetFramebufferAttachmentParameteriv": (None, (_U, _U, _U, ctypes.POINTER(_I))),
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


# Contours longer than this are fanned by chunks (see fans).
CHUNK = 32


def fan_indices(contour: NDArray[np.int64], chunk: int = CHUNK) -> NDArray[np.int64]:
    """(K - 2, 3) int64: triangles over a contour's vertex indices (K >= 3) whose signed
    indicators sum to the contour's winding number off their edges.

    Up to ``chunk`` vertices, the fan from the first vertex, (v0, vi, vi+1). Longer, a fan
    of fans: the contour is cut into runs of ``chunk`` edges, each run closed by the
    chord back to its first vertex and fanned from it, and the runs' first vertices form a
    coarser contour, fanned the same way. The runs' boundaries are the contour plus each
    chord once backwards, the coarse contour is each chord once forwards, so the
    windings add up to the contour's, with as many triangles as a plain fan (K - 2) but
    short ones: a plain fan of a long outline is as many thin triangles reaching across
    it from v0, each binned into every tile it crosses.

    Examples
    --------
    >>> fan_indices(np.arange(5)).tolist()
    [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    >>> fan_indices(np.arange(7), chunk=3).tolist()  # runs 0-3, 3-6, 6-0; coarse contour 0, 3, 6
    [[0, 1, 2], [0, 2, 3], [3, 4, 5], [3, 5, 6], [0, 3, 6]]
    """
    k = contour.size
    if k <= chunk:
        return np.stack([np.full(k - 2, contour[0]), contour[1:-1], contour[2:]], axis=1)
    closed = np.append(contour, contour[0])
    inner = np.flatnonzero(np.arange(k) % chunk != 0)  # every vertex but each run's first
    runs = np.stack([closed[inner // chunk * chunk], closed[inner], closed[inner + 1]], axis=1)
    coarse = contour[::chunk]
    return runs if coarse.size < 3 else np.concatenate([runs, fan_indices(coarse, chunk)])


def fans(scene: PathScene) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """Every contour's triangle fan (:func:`fan_indices`), grouped by path.

    A contour v0 .. v(K-1) of up to :data:`CHUNK` vertices gives the K - 2 triangles (v0,
    vi, vi+1), i = 1 .. K-2 (none for K < 3, which encloses nothing). Their signed
    indicator functions sum to the contour's winding number wherever no fan edge passes:
    the boundary of the triangles is the contour plus the diagonals v0 -> vi, each walked
    once each way. A longer contour is fanned by chunks, to the same effect.

    Returns
    -------
    triangles : (T, 3, 2) float64
        The fans, path 0's first, then path 1's, ... (contours of a path in scene order).
    first, count : (P,) int64
        Path k's triangles are ``triangles[first[k] : first[k] + count[k]]``.

    Examples
    --------
    >>> scene = PathScene.from_paths(8, 8, [[[[0, 0], [4, 0], [4, 4], [0, 4]]], [[[5, 5], [6, 5]]]])
    >>> triangles, first, count = fans(scene)
    >>> triangles.tolist(), first.tolist(), count.tolist()
    ([[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]], [[0.0, 0.0], [4.0, 4.0], [0.0, 4.0]]], [0, 2], [2, 0])
    """
    sizes, starts, owner = scene.contour_sizes, scene.contour_starts, scene.contour_path
    order = np.argsort(owner, kind="stable")  # contours by path, scene order within a path
    short = order[sizes[order] <= CHUNK]
    per_contour = np.maximum(sizes[short] - 2, 0)
    pivot = np.repeat(starts[short], per_contour)
    local = np.arange(int(per_contour.sum())) - np.repeat(np.cumsum(per_contour) - per_contour, per_contour) + 1
    parts = [np.stack([pivot, pivot + local, pivot + local + 1], axis=1)]
    paths = [np.repeat(owner[short], per_contour)]
    for c in order[sizes[order] > CHUNK].tolist():  # few: long contours, one at a time
        index = fan_indices(np.arange(starts[c], starts[c] + sizes[c]), CHUNK)
        parts.append(index)
        paths.append(np.full(index.shape[0], owner[c]))
    index, path = np.concatenate(parts), np.concatenate(paths)
    grouped = np.argsort(path, kind="stable")
    count = np.bincount(path, minlength=len(scene)).astype(np.int64)
    return scene.vertices[index[grouped]], np.cumsum(count) - count, count


def cover_boxes(scene: PathScene, finite: NDArray[np.bool_]) -> NDArray[np.int64]:
    """(P, 4) int64 ``x0, y0, x1, y1``: per path the pixels its cover pass spans, the
    path's bounding box widened to whole pixels plus one on each side (a margin: the
    box already holds every sample a fan triangle can reach, the fans lying within the
    convex hull of the path's vertices and rounding to float32 and to Mesa's sub-pixel
    grid being monotone), clipped to the screen; the whole screen for a path with a
    non-finite vertex (whatever Mesa makes of it is covered, and reset)."""
    lo, hi, _ = path_extents(scene)
    size = np.array([scene.width, scene.height])
    lo = np.where(finite[:, None], lo, 0.0)
    hi = np.where(finite[:, None], hi, 0.0)
    box = np.empty((len(scene), 4), dtype=np.int64)
    box[:, 0:2] = np.where(finite[:, None], np.clip(np.floor(lo) - 1, 0, size), 0)
    box[:, 2:4] = np.where(finite[:, None], np.clip(np.ceil(hi) + 1, 0, size), size)
    return box


# The cover pass of the fragment list: each fragment that passes the stencil test appends
# (path, x, y) to storage buffer 0. early_fragment_tests: the stencil test runs before the
# shader, so fragments it rejects store nothing (else the shader's stores would happen for
# every fragment of the box). Each quad vertex carries its path's index.
_COVER_VERTEX = """#version 430
in vec2 position;
in uint path_id;
flat out uint path;
void main() { path = path_id; gl_Position = vec4(position, 0.0, 1.0); }"""
_COVER_FRAGMENT = """#version 430
layout(early_fragment_tests) in;
layout(std430, binding = 0) buffer Fragments { uint count; uint capacity; uint pad0; uint pad1; uvec4 items[]; };
flat in uint path;
out float coverage;
void main() {
    uint i = atomicAdd(count, 1u);
    if (i < capacity) items[i] = uvec4(path, uint(gl_FragCoord.x), uint(gl_FragCoord.y), 0u);
    coverage = 1.0;
}"""


class StencilPaths:
    """Stencil-then-cover on a moderngl context: :meth:`rasterize` a path scene.

    Parameters
    ----------
    ctx, moderngl : the context and the moderngl module
    program : a moderngl program drawing ``in vec2 position`` with a constant colour (the
        fan and, without the fragment list, the cover)
    listed : bool
        Whether to read coverage back through the fragment list (GL 4.3 storage buffers;
        one read-back per batch of paths) rather than one colour read-back per path.
    """

    # fragments per batch of the fragment list: 16 bytes each, so 64 MiB of storage at most
    BUDGET = 1 << 22

    def __init__(self, ctx: Any, moderngl: Any, program: Any, listed: bool) -> None:
        self.ctx, self.moderngl, self.program = ctx, moderngl, program
        self.gl = _gl_functions()
        self.cover_program = ctx.program(vertex_shader=_COVER_VERTEX, fragment_shader=_COVER_FRAGMENT) if listed else None

    # -- GL state -------------------------------------------------------------------------

    def _framebuffer(self, width: int, height: int) -> tuple[Any, Any, Any]:
        """A width x height framebuffer: moderngl's one-byte colour renderbuffer and a raw
        8-bit stencil renderbuffer (``GL_STENCIL_INDEX8``, else ``GL_DEPTH24_STENCIL8``)."""
        gl = self.gl
        colour = self.ctx.renderbuffer((width, height), components=1, dtype="f1")
        fbo = self.ctx.framebuffer(color_attachments=[colour])
        fbo.use()
        stencil = _U()
        gl["glGenRenderbuffers"](1, ctypes.byref(stencil))
        gl["glBindRenderbuffer"](GL_RENDERBUFFER, stencil)
        for storage, attachment in ((GL_STENCIL_INDEX8, GL_STENCIL_ATTACHMENT),
                                    (GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL_ATTACHMENT)):
            gl["glRenderbufferStorage"](GL_RENDERBUFFER, storage, width, height)
            gl["glFramebufferRenderbuffer"](GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, stencil)
            if gl["glCheckFramebufferStatus"](GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE:
                break
            gl["glFramebufferRenderbuffer"](GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, 0)
        else:
            self._release(fbo, colour, stencil)
            raise RuntimeError("no complete framebuffer with a stencil buffer")
        bits = _I()
        gl["glGetFramebufferAttachmentParameteriv"](GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE,
                                                    ctypes.byref(bits))
        if bits.value != 8:
            self._release(fbo, colour, stencil)
            raise RuntimeError(f"the stencil buffer has {bits.value} bits, not 8")
        return fbo, colour, stencil

    def _release(self, fbo: Any, colour: Any, stencil: Any) -> None:
        fbo.release()
        colour.release()
        self.gl["glDeleteRenderbuffers"](1, ctypes.byref(stencil))

    def _begin(self, fbo: Any, side: int, width: int, height: int) -> None:
        gl = self.gl
        fbo.use()
        self.ctx.viewport = (-side, -side, 2 * side, 2 * side)  # the triangle adapter's exact mapping
        self.ctx.disable(self.moderngl.CULL_FACE | self.moderngl.BLEND | self.moderngl.DEPTH_TEST)
        gl["glEnable"](GL_SCISSOR_TEST)
        gl["glScissor"](0, 0, width, height)
        gl["glStencilMask"](0xFF)
        gl["glClearStencil"](0)
        gl["glClearColor"](0.0, 0.0, 0.0, 0.0)
        gl["glColorMask"](1, 1, 1, 1)
        gl["glClear"](GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)
        gl["glEnable"](GL_STENCIL_TEST)

    def _end(self) -> None:
        """Back to the state the triangle draws assume (no stencil test, colour written)."""
        gl = self.gl
        gl["glDisable"](GL_STENCIL_TEST)
        gl["glDisable"](GL_SCISSOR_TEST)
        gl["glColorMask"](1, 1, 1, 1)
        gl["glStencilFunc"](GL_ALWAYS, 0, 0xFF)
        gl["glStencilOp"](GL_KEEP, GL_KEEP, GL_KEEP)

    def _count(self, fill_rule: str) -> None:
        """Stencil state of the fan pass: every fan fragment counts, colour untouched."""
        gl = self.gl
        gl["glColorMask"](0, 0, 0, 0)
        gl["glStencilFunc"](GL_ALWAYS, 0, 0xFF)
        if fill_rule == "nonzero":
            # two-sided: +1 under a front-facing fan triangle, -1 under a back-facing one (mod 256)
            gl["glStencilOpSeparate"](GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP)
            gl["glStencilOpSeparate"](GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP)
        else:
            # parity: every fan fragment flips all bits, so the value is 0 (even) or 0xFF (odd)
            gl["glStencilOp"](GL_KEEP, GL_KEEP, GL_INVERT)

    def _cover(self, fill_rule: str, colour: bool) -> None:
        """Stencil state of the cover pass: a sample passes where the fill rule holds, and
        is reset to 0 as it passes (where it fails the count is 0 already), so the next
        path starts from a clear stencil without a clear."""
        gl = self.gl
        gl["glColorMask"](*(4 * (int(colour),)))
        # nonzero: any of the 8 bits set; even-odd: bit 0 (the count's parity)
        gl["glStencilFunc"](GL_NOTEQUAL, 0, 0xFF if fill_rule == "nonzero" else 0x01)
        gl["glStencilOp"](GL_KEEP, GL_KEEP, GL_ZERO)

    # -- drawing --------------------------------------------------------------------------

    def rasterize(self, scene: PathScene, side: int, name: str) -> Coverage:
        """What each path covers: per path, its fans into the stencil buffer, then its
        cover quad under the stencil test (see the adapter's docstring). With the fragment
        list, paths whose boxes share no pixel (a layer, :func:`layers`) go in one fan draw
        and one cover draw: their stencil counts never meet."""
        finite = finite_within_limit(scene, name)
        if len(scene) == 0:
            return Coverage.empty()
        triangles, first, count = fans(scene)
        boxes = cover_boxes(scene, finite)
        area = np.maximum(boxes[:, 2] - boxes[:, 0], 0) * np.maximum(boxes[:, 3] - boxes[:, 1], 0)
        drawn = np.flatnonzero(area > 0)  # a path wholly off-screen covers nothing here
        alone = area[drawn] > self.BUDGET  # read back by colour, one at a time
        layer = layers(boxes[drawn])
        order = np.lexsort((drawn, layer, alone))  # the drawing order: by layer, the large paths last
        drawn, layer, alone = drawn[order], layer[order], alone[order]
        # the buffers in drawing order: slot s holds path drawn[s]'s fans and cover quad
        fan_count = count[drawn]
        fan_first = np.cumsum(fan_count) - fan_count
        fan_triangles = triangles[np.repeat(first[drawn] - fan_first, fan_count) + np.arange(int(fan_count.sum()))]
        x0, y0, x1, y1 = (boxes[drawn, i].astype(np.float64) for i in range(4))
        quads = np.stack([np.c_[x0, y0], np.c_[x1, y0], np.c_[x1, y1], np.c_[x0, y0], np.c_[x1, y1], np.c_[x0, y1]], axis=1)
        ctx = self.ctx
        # float32 NDC x / P: dividing by a power of two is exact (as for triangles)
        with np.errstate(over="ignore", invalid="ignore"):
            fan_buffer = ctx.buffer((fan_triangles.reshape(-1, 2) / side).astype(np.float32).tobytes() or bytes(8))
        quad_buffer = ctx.buffer((quads.reshape(-1, 2) / side).astype(np.float32).tobytes() or bytes(8))
        path_buffer = ctx.buffer(np.repeat(drawn, 6).astype(np.uint32).tobytes() or bytes(4))
        fan = ctx.vertex_array(self.program, [(fan_buffer, "2f", "position")])
        cover = ctx.vertex_array(self.program, [(quad_buffer, "2f", "position")])
        listed = None if self.cover_program is None else ctx.vertex_array(
            self.cover_program, [(quad_buffer, "2f", "position"), (path_buffer, "1u", "path_id")])
        slots = _Slots(drawn, fan_first, fan_count, fan, cover, listed)
        fbo, colour, stencil = self._framebuffer(scene.width, scene.height)
        try:
            self._begin(fbo, side, scene.width, scene.height)
            each = np.flatnonzero(alone) if listed is not None else np.arange(drawn.size)
            parts = [self._each(scene, int(s), slots, boxes, fbo) for s in each.tolist()]
            if listed is not None:
                parts += self._listed(scene, np.flatnonzero(~alone), layer, area[drawn], slots)
        finally:
            self._end()
            self._release(fbo, colour, stencil)
            for thing in (fan, cover, listed, fan_buffer, quad_buffer, path_buffer):
                if thing is not None:
                    thing.release()
        parts = [p for p in parts if len(p)]
        return Coverage.concat(parts) if parts else Coverage.empty()

    def _draw(self, rule: str, slots: _Slots, start: int, end: int, colour: bool) -> None:
        """The fans, then the cover quads, of the paths in slots ``start`` .. ``end`` - 1
        (one path, or paths whose boxes share no pixel)."""
        triangles = self.moderngl.TRIANGLES
        n_fans = int(slots.fan_first[end - 1] + slots.fan_count[end - 1] - slots.fan_first[start])
        if n_fans:
            self._count(rule)
            slots.fan.render(triangles, vertices=3 * n_fans, first=3 * int(slots.fan_first[start]))
        self._cover(rule, colour)
        (slots.cover if colour else slots.listed).render(triangles, vertices=6 * (end - start), first=6 * start)

    def _each(self, scene: PathScene, s: int, slots: _Slots, boxes: NDArray[np.int64], fbo: Any) -> Coverage:
        """The path of slot ``s``, read back as colour: its cover pass writes 1 where it
        passes."""
        k = int(slots.path[s])
        x0, y0, x1, y1 = (int(v) for v in boxes[k])
        self._draw(scene.fill_rule, slots, s, s + 1, colour=True)
        data = np.frombuffer(fbo.read(viewport=(x0, y0, x1 - x0, y1 - y0), components=1, alignment=1), dtype=np.uint8)
        mask = data.reshape(y1 - y0, x1 - x0) > 0
        gl = self.gl
        gl["glScissor"](x0, y0, x1 - x0, y1 - y0)
        gl["glColorMask"](1, 1, 1, 1)
        gl["glClear"](GL_COLOR_BUFFER_BIT)
        gl["glScissor"](0, 0, scene.width, scene.height)
        if not mask.any():
            return Coverage.empty()
        cov = Coverage.from_mask(k, mask)
        return Coverage(cov.primitive, cov.y + y0, cov.x0 + x0, cov.x1 + x0)

    def _listed(self, scene: PathScene, small: NDArray[np.int64], layer: NDArray[np.int64], area: NDArray[np.int64],
                slots: _Slots) -> list[Coverage]:
        """The paths of slots ``small`` (consecutive, in layer order) through the fragment
        list: batches of consecutive slots whose boxes fit :attr:`BUDGET` fragments
        together, each read back once; within a batch, one fan draw and one cover draw
        per layer."""
        parts = []
        for start, end in budget_batches(area[small], self.BUDGET):
            batch = small[start:end]
            capacity = int(area[batch].sum()) + 1024  # a path's cover fragments lie in its box
            storage = self.ctx.buffer(reserve=16 * (capacity + 1))
            try:
                storage.write(np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
                storage.bind_to_storage_buffer(0)
                cuts = np.flatnonzero(np.diff(layer[batch])) + 1
                for run in np.split(batch, cuts):
                    self._draw(scene.fill_rule, slots, int(run[0]), int(run[-1]) + 1, colour=False)
                self.ctx.finish()
                data = np.frombuffer(storage.read(), dtype=np.uint32)
            finally:
                storage.release()
            n = int(data[0])
            if n > capacity:  # cannot happen (fragments fit their boxes), but never truncate
                raise RuntimeError(f"{n} cover fragments for room for {capacity}")
            items = data[4:].reshape(-1, 4)[:n].astype(np.int64)
            parts.append(coverage_from_fragments(items[:, 0], items[:, 1], items[:, 2], scene.width, scene.height))
            start = end
        return parts


class _Slots(NamedTuple):
    """The draw buffers in drawing order: slot s is path ``path[s]``, its fan triangles
    ``fan_first[s] .. + fan_count[s]`` of ``fan``, its cover quad vertices 6s .. 6s + 5 of
    ``cover`` (the plain program) and ``listed`` (the appending one, or None)."""

    path: NDArray[np.int64]
    fan_first: NDArray[np.int64]
    fan_count: NDArray[np.int64]
    fan: Any
    cover: Any
    listed: Any


# Tiles of the layer assignment: two boxes that share no tile share no pixel.
TILE = 16


@numba.njit(cache=True)
def _layer_kernel(boxes, tile, tiles_x, tiles_y):  # type: ignore[no-untyped-def]
    top = np.zeros(tiles_x * tiles_y, dtype=np.int64)  # per tile: 1 + the highest layer using it
    layer = np.empty(boxes.shape[0], dtype=np.int64)
    for k in range(boxes.shape[0]):
        tx0, ty0 = boxes[k, 0] // tile, boxes[k, 1] // tile
        tx1, ty1 = (boxes[k, 2] - 1) // tile, (boxes[k, 3] - 1) // tile
        above = 0
        for ty in range(ty0, ty1 + 1):
            for tx in range(tx0, tx1 + 1):
                above = max(above, top[ty * tiles_x + tx])
        layer[k] = above
        for ty in range(ty0, ty1 + 1):
            for tx in range(tx0, tx1 + 1):
                top[ty * tiles_x + tx] = above + 1
    return layer


def layers(boxes: NDArray[np.int64], tile: int = TILE) -> NDArray[np.int64]:
    """A layer per box such that boxes of one layer share no pixel.

    Each box goes to the layer just above every earlier box it shares a ``tile`` x
    ``tile`` tile with (so boxes sharing a tile never share a layer; two boxes sharing no
    tile share no pixel).

    Parameters
    ----------
    boxes : (N, 4) int64
        ``x0, y0, x1, y1``, non-empty, non-negative.

    Returns
    -------
    (N,) int64

    Examples
    --------
    >>> layers(np.array([[0, 0, 10, 10], [40, 0, 50, 10], [5, 5, 20, 20], [0, 40, 8, 48]])).tolist()
    [0, 0, 1, 0]
    """
    boxes = np.ascontiguousarray(boxes, dtype=np.int64)
    if not boxes.shape[0]:
        return np.zeros(0, dtype=np.int64)
    tiles_x = int(boxes[:, 2].max() - 1) // tile + 1
    tiles_y = int(boxes[:, 3].max() - 1) // tile + 1
    layers: NDArray[np.int64] = _layer_kernel(boxes, tile, tiles_x, tiles_y)
    return layers
