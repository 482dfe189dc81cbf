"""Mesa's lavapipe (Vulkan on the CPU) through PyPI ``wgpu`` (wgpu-native): triangles,
paths (stencil-then-cover) and 1-px lines single-sample (:class:`VulkanLavapipe`), and
triangles with 4x multisampling (:class:`VulkanLavapipeMSAA4`). Every fragment appends
(primitive, x, y[, sample mask]) to a storage buffer, so one draw keeps each primitive's
identity through overlaps."""

from __future__ import annotations

import glob
import json
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from rasterizers.real._bases import need, refuse_kind
from rasterizers.real._masks import (
    budget_batches,
    coverage_from_fragments,
    coverage_from_sample_masks,
    finite_within_limit,
    segment_boxes,
)
from rasterizers.real._stencil import cover_boxes, fans, layers

__all__ = ["VulkanLavapipe", "VulkanLavapipeMSAA4", "VULKAN_4X"]

# Vulkan's standard sample locations for 4 samples (Vulkan 1.3, 28.4 "Multisampling",
# table "Standard sample locations", when standardSampleLocations is VK_TRUE), in sample
# order, as offsets from the pixel's top-left corner (framebuffer y down, as ours).
VULKAN_4X = ((0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875))

_INSTALL = "apt-get install mesa-vulkan-drivers"
# where the Vulkan loader looks for Mesa's lavapipe ICD manifest
_ICD_GLOBS = ("/usr/share/vulkan/icd.d/lvp_icd*.json", "/etc/vulkan/icd.d/lvp_icd*.json",
              "/usr/local/share/vulkan/icd.d/lvp_icd*.json")

# One module for every pipeline. Vertex positions arrive as float32 NDC (x / P, -y / P);
# ``@builtin(vertex_index) / per`` names the primitive (flat: the same on all its
# vertices), ``per`` being 3 (triangle list), 2 (line list) or 6 (cover quads).
_WGSL = """
struct Fragments { count: atomic<u32>, capacity: u32, pad0: u32, pad1: u32, items: array<vec4<u32>> };
@group(0) @binding(0) var<storage, read_write> fragments: Fragments;
struct Varyings { @builtin(position) position: vec4<f32>, @location(0) @interpolate(flat) primitive: u32 };

fn varyings(position: vec2<f32>, primitive: u32) -> Varyings {
    var out: Varyings;
    out.position = vec4<f32>(position, 0.0, 1.0);
    out.primitive = primitive;
    return out;
}
@vertex fn triangles(@location(0) position: vec2<f32>, @builtin(vertex_index) index: u32) -> Varyings {
    return varyings(position, index / 3u);
}
@vertex fn lines(@location(0) position: vec2<f32>, @builtin(vertex_index) index: u32) -> Varyings {
    return varyings(position, index / 2u);
}
@vertex fn quads(@location(0) position: vec2<f32>, @builtin(vertex_index) index: u32) -> Varyings {
    return varyings(position, index / 6u);
}
fn append(primitive: u32, position: vec4<f32>, mask: u32) {
    let i = atomicAdd(&fragments.count, 1u);
    if (i < fragments.capacity) {
        fragments.items[i] = vec4<u32>(primitive, u32(position.x), u32(position.y), mask);
    }
}
@fragment fn listed(in: Varyings) -> @location(0) vec4<f32> {
    append(in.primitive, in.position, 1u);
    return vec4<f32>(1.0);
}
@fragment fn masked(in: Varyings, @builtin(sample_mask) mask: u32) -> @location(0) vec4<f32> {
    if (mask != 0u) {
        append(in.primitive, in.position, mask);
    }
    return vec4<f32>(1.0);
}
@fragment fn plain(in: Varyings) -> @location(0) vec4<f32> {
    return vec4<f32>(1.0);
}
"""
# The cover pass of paths: the stencil test must run before the shader, or the shader's
# stores would happen for every fragment of the box (SPIR-V EarlyFragmentTests).
_WGSL_COVER = """
@fragment @early_depth_test(force) fn covered(in: Varyings) -> @location(0) vec4<f32> {
    append(in.primitive, in.position, 1u);
    return vec4<f32>(1.0);
}
"""


def lavapipe_manifest() -> str | None:
    """The path of Mesa's lavapipe ICD manifest, or None (mesa-vulkan-drivers missing)."""
    override = os.environ.get("VK_ICD_FILENAMES") or os.environ.get("VK_DRIVER_FILES")
    found = [p for p in (override or "").split(os.pathsep) if "lvp" in os.path.basename(p) and os.path.exists(p)]
    for pattern in _ICD_GLOBS:
        found += sorted(glob.glob(pattern))
    return found[0] if found else None


# The process that made this module's wgpu device, if any. wgpu-native (wgpu 0.32) hangs
# in a child forked from a process that made a device: such a child is refused up front.
_MADE_IN: int | None = None


class _Device:
    """A wgpu device on lavapipe's Vulkan adapter (made lazily, once per process: a device
    made before a fork hangs in the child), its pipelines and reusable buffers."""

    def __init__(self, wgpu: Any) -> None:
        global _MADE_IN
        if _MADE_IN is not None and os.getpid() != _MADE_IN:
            raise RuntimeError(f"wgpu: this process was forked from process {_MADE_IN}, which had made a wgpu device; "
                               "wgpu-native 0.32 hangs making or using a device in such a child (make the device only "
                               "in the workers, or start them by spawn)")
        self.wgpu = wgpu
        _MADE_IN = os.getpid()
        if not os.environ.get("XDG_RUNTIME_DIR"):
            # Mesa's Vulkan loader looks for a display runtime folder and, without one, prints
            # "error: XDG_RUNTIME_DIR is invalid" on every device made (harmless: no display is
            # used); a private folder of the user's keeps the run's output clean
            import tempfile

            folder = os.path.join(tempfile.gettempdir(), f"rastercheck-xdg-{os.getuid()}")
            os.makedirs(folder, mode=0o700, exist_ok=True)
            os.environ["XDG_RUNTIME_DIR"] = folder
        adapters = [a for a in wgpu.gpu.enumerate_adapters_sync()
                    if a.info["backend_type"] == "Vulkan" and "llvmpipe" in a.info["device"]]
        if not adapters:
            raise Unavailable(f"wgpu offers no Vulkan adapter on Mesa's lavapipe: {_INSTALL}")
        adapter = adapters[0]
        self.info = dict(adapter.info)
        limit = int(adapter.limits["max-texture-dimension-2d"])
        storage = int(adapter.limits["max-storage-buffer-binding-size"])
        features = [f for f in ("shader-early-depth-test",) if f in adapter.features]
        self.device = adapter.request_device_sync(
            required_features=features,
            required_limits={"max-texture-dimension-2d": limit, "max-storage-buffer-binding-size": storage,
                             "max-buffer-size": int(adapter.limits["max-buffer-size"])})
        self.largest = limit // 2  # the viewport (-P, -P, 2P, 2P) must fit the limit
        self.max_fragments = min(storage, int(adapter.limits["max-buffer-size"])) // 16 - 1
        self.early_tests = bool(features)
        code = _WGSL + (_WGSL_COVER if self.early_tests else "")
        self.module = self.device.create_shader_module(code=code)
        self.layout = self.device.create_bind_group_layout(entries=[{
            "binding": 0, "visibility": wgpu.ShaderStage.FRAGMENT,
            "buffer": {"type": wgpu.BufferBindingType.storage}}])
        self.pipeline_layout = self.device.create_pipeline_layout(bind_group_layouts=[self.layout])
        self.pipelines: dict[tuple[Any, ...], Any] = {}
        self.targets: dict[tuple[int, int, int], Any] = {}
        self.stencils: dict[tuple[int, int], Any] = {}
        self.storage: Any = None
        self.storage_capacity = -1

    def pipeline(self, vertex: str, fragment: str, topology: str, samples: int = 1,
                 stencil: tuple[Any, ...] | None = None) -> Any:
        """A render pipeline (cached): float32x2 positions, no culling, one r8unorm target
        that is never written, optionally a stencil8 attachment with ``stencil`` =
        (front pass op, back pass op, compare, read mask)."""
        key = (vertex, fragment, topology, samples, stencil)
        if key not in self.pipelines:
            depth_stencil = None
            if stencil is not None:
                front, back, compare, read_mask = stencil
                depth_stencil = {
                    "format": "stencil8", "depth_write_enabled": False, "depth_compare": "always",
                    "stencil_front": {"compare": compare, "fail_op": "keep", "depth_fail_op": "keep", "pass_op": front},
                    "stencil_back": {"compare": compare, "fail_op": "keep", "depth_fail_op": "keep", "pass_op": back},
                    "stencil_read_mask": read_mask, "stencil_write_mask": 0xFF}
            self.pipelines[key] = self.device.create_render_pipeline(
                layout=self.pipeline_layout,
                vertex={"module": self.module, "entry_point": vertex, "buffers": [{
                    "array_stride": 8, "step_mode": "vertex",
                    "attributes": [{"format": "float32x2", "offset": 0, "shader_location": 0}]}]},
                primitive={"topology": topology, "cull_mode": "none", "front_face": "ccw"},
                depth_stencil=depth_stencil,
                multisample={"count": samples, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
                fragment={"module": self.module, "entry_point": fragment,
                          "targets": [{"format": "r8unorm", "write_mask": 0}]})
        return self.pipelines[key]

    def target(self, width: int, height: int, samples: int) -> Any:
        """The view of a width x height r8unorm render target (never written: it only sets
        the framebuffer's size and sample count)."""
        key = (width, height, samples)
        if key not in self.targets:
            texture = self.device.create_texture(size=(width, height, 1), format="r8unorm", sample_count=samples,
                                                 usage=self.wgpu.TextureUsage.RENDER_ATTACHMENT)
            self.targets[key] = texture.create_view()
        return self.targets[key]

    def stencil(self, width: int, height: int) -> Any:
        key = (width, height)
        if key not in self.stencils:
            texture = self.device.create_texture(size=(width, height, 1), format="stencil8",
                                                 usage=self.wgpu.TextureUsage.RENDER_ATTACHMENT)
            self.stencils[key] = texture.create_view()
        return self.stencils[key]

    def fragments(self, capacity: int) -> Any:
        """The storage buffer of the fragment list, room for ``capacity`` items (grown,
        never shrunk), its header (count 0, capacity) written."""
        if capacity > self.storage_capacity:
            if self.storage is not None:
                self.storage.destroy()
            size = max(capacity, 1 << 16)
            self.storage = self.device.create_buffer(
                size=16 * (size + 1), usage=self.wgpu.BufferUsage.STORAGE | self.wgpu.BufferUsage.COPY_SRC
                | self.wgpu.BufferUsage.COPY_DST)
            self.storage_capacity = size
        self.device.queue.write_buffer(self.storage, 0, np.array([0, capacity, 0, 0], dtype=np.uint32).tobytes())
        return self.storage

    def read_fragments(self) -> NDArray[np.int64]:
        """(K, 4) int64 items of the fragment list; K may exceed the capacity (then only the
        capacity's items were stored: the caller redraws)."""
        queue = self.device.queue
        count, capacity = (int(v) for v in np.frombuffer(queue.read_buffer(self.storage, 0, 8), dtype=np.uint32))
        stored = min(count, capacity)
        if count > capacity:
            return np.zeros((count, 4), dtype=np.int64)
        if stored == 0:
            return np.zeros((0, 4), dtype=np.int64)
        data = np.frombuffer(queue.read_buffer(self.storage, 16, 16 * stored), dtype=np.uint32)
        return data.reshape(-1, 4).astype(np.int64)

    def vertices(self, ndc: NDArray[np.float32]) -> Any:
        data = ndc.tobytes() or bytes(8)
        return self.device.create_buffer_with_data(data=data, usage=self.wgpu.BufferUsage.VERTEX)

    def bind_group(self) -> Any:
        return self.device.create_bind_group(layout=self.layout, entries=[
            {"binding": 0, "resource": {"buffer": self.storage, "offset": 0, "size": self.storage.size}}])


def _ndc(points: NDArray[np.float64], side: int) -> NDArray[np.float32]:
    """(..., 2) pixels to float32 NDC (x / P, -y / P): dividing by a power of two and
    negating are exact, so the float32 of each coordinate is what reaches the viewport
    transform (see :class:`VulkanLavapipe`)."""
    with np.errstate(over="ignore", invalid="ignore"):
        ndc = (points / side).astype(np.float32)
    ndc[..., 1] = -ndc[..., 1]
    return np.ascontiguousarray(ndc.reshape(-1, 2))


def bands(box: tuple[int, int, int, int], budget: int) -> list[tuple[int, int, int, int]]:
    """A box ``x0, y0, x1, y1`` cut into scissor rectangles ``x, y, width, height`` of
    whole rows, each of at most ``budget`` pixels (one row at least).

    >>> bands((2, 0, 12, 25), 100)
    [(2, 0, 10, 10), (2, 10, 10, 10), (2, 20, 10, 5)]
    """
    x0, y0, x1, y1 = box
    rows = max(1, budget // max(x1 - x0, 1))
    return [(x0, y, x1 - x0, min(rows, y1 - y)) for y in range(y0, y1, rows)]


class _Lavapipe:
    """What both modes share: the device, the exact mapping, the guard band."""

    library = "Mesa lavapipe (Vulkan)"
    library_version = ""
    coverage_kind = "single"
    convention: Convention | None = None
    interpolates = False  # coverage only: no varyings read back
    name = ""
    SAMPLES = 1
    # fragments per draw: 16 bytes each, so 64 MiB of storage at most
    BUDGET = 1 << 22

    def __init__(self) -> None:
        self._wgpu = need("wgpu")
        manifest = lavapipe_manifest()
        if manifest is None:
            raise Unavailable(f"{self.name}: Mesa's Vulkan driver lavapipe is not installed: {_INSTALL}")
        # until a device says Mesa's version (made lazily): the driver's Vulkan version
        try:
            with open(manifest) as file:
                api = str(json.load(file)["ICD"]["api_version"])
        except (OSError, ValueError, KeyError, TypeError):
            api = "?"
        self.library_version = f"lavapipe Vulkan {api}, wgpu {self._wgpu.__version__}"
        self._device: _Device | None = None
        self._pid = -1

    def _gpu(self) -> _Device:
        if self._device is None or self._pid != os.getpid():
            self._device = _Device(self._wgpu)
            self._pid = os.getpid()
            self.library_version = f"{self._device.info['description']}, wgpu {self._wgpu.__version__}"
        return self._device

    def _side(self, scene: AnyScene, gpu: _Device) -> int:
        side = 1 << max(scene.width - 1, scene.height - 1, 1).bit_length()
        if side > gpu.largest:
            raise ValueError(f"{self.name}: a {scene.width} x {scene.height} screen needs a {2 * side} px viewport; "
                             f"wgpu allows {2 * gpu.largest} (screens up to {gpu.largest} px a side)")
        return side

    def _guard_band(self, scene: AnyScene, side: int, gpu: _Device) -> int:
        """P widened (powers of two, up to the device's largest) until [-P, P]^2 holds every
        finite vertex: lavapipe clips in float, before snapping, so a primitive reaching
        past the clip volume would be moved. The mapping stays exact (x / P, P a power of
        two)."""
        coordinates = scene.coordinates
        reach = float(np.max(np.abs(coordinates), where=np.isfinite(coordinates), initial=0.0))
        while side < reach and side < gpu.largest:
            side *= 2
        return side

    # as lavapipe receives the scene: each coordinate rounded to float32 (the vertex format),
    # which the exact mapping then carries unchanged (read by received_of)
    input = "float32"

    def _draw_list(self, gpu: _Device, scene: AnyScene, ndc: NDArray[np.float32], vertex: str, fragment: str, topology: str,
                   side: int, capacity: int, scissor: tuple[int, int, int, int] | None = None) -> NDArray[np.int64]:
        """One draw of every vertex of ``ndc`` appending to the fragment list; the (K, 4)
        items inside ``scissor`` (x, y, width, height; the screen by default). Should more
        than ``capacity`` fragments arrive, redrawn with room for them (never truncated)."""
        x, y, w, h = scissor if scissor is not None else (0, 0, scene.width, scene.height)
        pipeline = gpu.pipeline(vertex, fragment, topology, self.SAMPLES)
        view = gpu.target(scene.width, scene.height, self.SAMPLES)
        vertices = gpu.vertices(ndc)
        try:
            while True:
                gpu.fragments(capacity)
                encoder = gpu.device.create_command_encoder()
                rp = encoder.begin_render_pass(color_attachments=[{
                    "view": view, "load_op": "load", "store_op": "discard"}])
                rp.set_pipeline(pipeline)
                rp.set_bind_group(0, gpu.bind_group())
                rp.set_vertex_buffer(0, vertices)
                rp.set_viewport(-side, -side, 2 * side, 2 * side, 0.0, 1.0)
                rp.set_scissor_rect(x, y, w, h)
                rp.draw(ndc.shape[0])
                rp.end()
                gpu.device.queue.submit([encoder.finish()])
                items = gpu.read_fragments()
                if items.shape[0] <= capacity:
                    break
                if items.shape[0] > gpu.max_fragments:
                    raise RuntimeError(f"{self.name}: {items.shape[0]} fragments in one draw, beyond the "
                                       f"{gpu.max_fragments} a storage buffer holds")
                capacity = items.shape[0] + 1024
        finally:
            vertices.destroy()
        # the scissor is not trusted as a filter (llvmpipe on GL runs the shader beside it with 4x MSAA)
        inside = (items[:, 1] >= x) & (items[:, 1] < x + w) & (items[:, 2] >= y) & (items[:, 2] < y + h)
        return items[inside]

    def _triangles(self, scene: Scene, fragment: str) -> NDArray[np.int64]:
        """Every triangle's fragments, (K, 4) items (triangle, x, y, mask), in batches of
        consecutive triangles whose boxes fit :attr:`BUDGET` fragments together."""
        gpu = self._gpu()
        side = self._guard_band(scene, self._side(scene, gpu), gpu)
        n = len(scene)
        finite = finite_within_limit(scene, self.name)
        if n == 0:
            return np.zeros((0, 4), dtype=np.int64)
        positions = scene.positions
        safe = np.where(finite[:, None, None], positions, 0.0)  # non-finite ones get the whole screen
        lo = np.where(finite[:, None], np.clip(np.floor(safe.min(axis=1)), 0, [scene.width, scene.height]), 0).astype(np.int64)
        hi = np.where(finite[:, None], np.clip(np.ceil(safe.max(axis=1)) + 1, 0, [scene.width, scene.height]),
                      [scene.width, scene.height]).astype(np.int64)
        boxes = np.maximum(hi - lo, 0)
        area = boxes[:, 0] * boxes[:, 1]
        parts = []
        for start, end in budget_batches(area, self.BUDGET):
            ndc = _ndc(positions[start:end], side)
            if area[start] > self.BUDGET:  # alone (end == start + 1): in bands of rows that fit the budget
                for band in bands((int(lo[start, 0]), int(lo[start, 1]), int(hi[start, 0]), int(hi[start, 1])), self.BUDGET):
                    parts.append(self._draw_list(gpu, scene, ndc, "triangles", fragment, "triangle-list", side,
                                                 band[2] * band[3] + 1024, band))
                    parts[-1][:, 0] += start
            else:
                parts.append(self._draw_list(gpu, scene, ndc, "triangles", fragment, "triangle-list", side,
                                             int(area[start:end].sum()) + 1024))
                parts[-1][:, 0] += start
        return np.concatenate(parts)


class VulkanLavapipe(_Lavapipe):
    """Mesa's lavapipe (Vulkan on the CPU, llvmpipe's rasterizer) through wgpu's
    Vulkan back end (never wgpu's GL back end: the adapter is picked by
    ``backend_type == "Vulkan"`` and an ``llvmpipe`` device), single-sample.

    Triangles: one ``triangle-list`` draw per batch (up to :attr:`BUDGET` fragments by
    the triangles' boxes); the vertex shader hands each vertex ``vertex_index / 3``, flat
    interpolated, and the fragment shader appends (triangle, x, y) to a storage buffer
    with an atomic counter (read back once per batch; should it overflow, the batch is
    drawn again with room, never truncated). No colour is written (the r8unorm target
    only sizes the framebuffer); culling off. A NaN or infinite triangle is handed over
    unchanged (what lavapipe makes of it is what the checks see).

    Coordinate mapping (exact, as for :class:`~rasterizers.real.adapters.MesaLlvmpipe`):
    the screen W x H is the render target, P is the power of two >= W, H, the viewport
    is (-P, -P, 2P, 2P) (wgpu 0.32 accepts a negative origin; its size must be within
    ``max_texture_dimension_2d`` = 16384, so screens up to 8192 px), and a vertex (x, y)
    goes to the vertex shader as float32 NDC (x / P, -y / P). wgpu flips y for Vulkan by a
    negative viewport height (VK_KHR_maintenance1): x_fb = x_ndc * P + 0 and y_fb =
    -y_ndc * P + 0, exact products by a power of two, so the float32 of each coordinate
    reaches lavapipe's rasterizer unchanged (:meth:`received`), framebuffer row y being
    our row y and pixel (i, j) our [i, i+1) x [j, j+1). The probe
    ``tests/rasterizers/real/test_vulkan.py::test_triangle_mapping_exact`` proves it (no
    half-pixel shift, flip or transposition). The clip volume is [-P, P]^2: a primitive
    reaching up to P px off-screen is not clipped (for paths and lines P is widened until
    it holds every vertex, up to 8192); lavapipe clips in float, before snapping, beyond
    that.

    What it receives: float32 vertices (:meth:`received`), snapped by lavapipe to its
    sub-pixel grid.

    Paths, both fill rules, by stencil-then-cover as
    :class:`~rasterizers.real.adapters.MesaLlvmpipe` does on GL
    (:mod:`rasterizers.real._stencil`'s fans, cover boxes and layers): per layer of paths
    whose boxes share no pixel, the contours' triangle fans into a ``stencil8``
    attachment (two-sided ``increment-wrap`` under front-facing and ``decrement-wrap``
    under back-facing fan triangles for nonzero; ``invert`` under each for even-odd),
    then a cover quad per path over its box, stencil test ``!= 0`` (read mask 0xFF, or
    0x01 for even-odd) resetting the stencil to 0 as it passes, its fragment shader
    (``@early_depth_test(force)``: the stencil test runs first) appending (path, x, y).
    The fan triangles follow lavapipe's triangle rule, so the count at a pixel centre is
    the path's winding number decided at the triangle rule's perturbed point (see
    MesaLlvmpipe's docstring), but for windings that are nonzero multiples of 256 (WebGPU
    has no stencil wider than 8 bits: the quick suite's ``paths/deep-winding/256`` and
    ``/65536`` read as 0 under nonzero). A path alone exceeding :attr:`BUDGET` pixels is
    drawn in scissored bands of rows. A path with a NaN or infinite vertex goes to
    lavapipe unchanged, its cover spanning the whole screen: lavapipe draws no fan
    triangle with a non-finite vertex (as it draws no such triangle), so the path's
    other fan triangles are counted and cover what they count (the suite's
    ``path-degenerate/non-finite/mixed``: a finite square contour beside a contour with an
    infinite vertex is drawn, where the oracle draws nothing for the path).

    Lines: width 1 only (WebGPU has no wide lines: other widths Unsupported), one
    ``line-list`` draw per batch, each segment its own vertex pair (a polyline's segments
    are separate segments to lavapipe: the draw module hands llvmpipe's line setup one
    segment at a time), the primitive ``vertex_index / 2``; a pixel two segments draw
    comes back twice; a segment with a NaN or infinite end point is not drawn and covers
    nothing. lavapipe draws Vulkan's rectangular lines (``lp_setup_line.c``, the
    ``rectangular_lines`` branch): each end point is snapped to 1/256 px by llvmpipe's
    ``subpixel_snap(v - 0.5)`` (``util_iround``: half away from zero in the frame shifted
    by half a pixel, in float32), the half-width normal ``(-dy, dx) * 0.5 / |d|`` is
    computed in float32 from the unsnapped end points and snapped on its own, and the four
    corners (snapped end +/- snapped normal) are rasterized as a quad under the triangles'
    rule. That is ``LineRule("llvmpipe-rectangle")`` (:mod:`harness.oracle.llvmpipe_lines`),
    exact: ``test_lines_are_llvmpipes_rectangle_rule`` finds 0 (segment, pixel) pairs off
    it on float segments, 1/4 px lattices and ends on ties of the 1/256 grid (Mesa 22.3.6).

    Identified (``rastercheck identify``, Mesa 22.3.6 lavapipe, LLVM 15.0.6, wgpu 0.32.0):
    triangles exactly ``Convention(tie="top-left", subpixel_bits=8)`` (pixel centres,
    top-left ties, vertices snapped to 1/256 px half to even), residual 0 of 140,770
    pixels, the viewport edge exact (the guard band), NaN and infinite triangles cover
    nothing; paths the same convention, 0 mismatches under both rules (the fill rules
    are honoured: 868 pixels of 10,756 tell them apart); lines exactly
    ``Convention(tie="top-left", subpixel_bits=8, input="float32", line="llvmpipe-rectangle")``,
    residual 0 of 8,478 pixels (the rectangle rule, its best guess before, 30 px off by the
    corner rounding). The quick suite (before the rule): triangles pass; 14 line results
    failed by that rounding (length, ends, line motion), 3 near ties and 1 snapping result
    on float lines likewise, 2 deep-winding paths (the 8-bit stencil) and the non-finite
    mixed path (above). No convention is declared (identify fingerprints it)."""

    name = "vulkan_lavapipe"
    scene_kinds: tuple[str, ...] = ("triangles", "paths", "lines")
    fill_rules: tuple[str, ...] = ("nonzero", "evenodd")
    line_widths = (1.0,)

    def rasterize(self, scene: AnyScene) -> Coverage:
        if isinstance(scene, LineScene):
            return self._lines(scene)
        if isinstance(scene, PathScene):
            return self._paths(scene)
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        items = self._triangles(scene, "listed")
        return coverage_from_fragments(items[:, 0], items[:, 1], items[:, 2], scene.width, scene.height)

    # -- lines ----------------------------------------------------------------------------

    def _lines(self, scene: LineScene) -> Coverage:
        if scene.line_width != 1.0:
            raise Unsupported(f"{self.name}: draws lines 1 px wide only (WebGPU has no wide lines), "
                              f"not {scene.line_width:g}")
        gpu = self._gpu()
        boxes, drawn = segment_boxes(scene, self.name, margin=1)
        if not drawn.size:
            return Coverage.empty()
        side = self._guard_band(scene, self._side(scene, gpu), gpu)
        a, b = scene.segments()
        extent = boxes[drawn, 2:] - boxes[drawn, :2]
        bound = extent.max(axis=1) + 1  # at most one fragment per step of the major axis, and one
        parts = []
        for start, end in budget_batches(bound, self.BUDGET):
            batch = drawn[start:end]
            pairs = np.stack([a[batch], b[batch]], axis=1)
            items = self._draw_list(gpu, scene, _ndc(pairs, side), "lines", "listed", "line-list", side,
                                    int(bound[start:end].sum()) + 1024)
            parts.append(coverage_from_fragments(batch[items[:, 0]], items[:, 1], items[:, 2], scene.width, scene.height))
        return Coverage.concat(parts)

    # -- paths ----------------------------------------------------------------------------

    def _paths(self, scene: PathScene) -> Coverage:
        if scene.fill_rule not in self.fill_rules:
            raise Unsupported(f"{self.name}: fills {' and '.join(self.fill_rules)} only, not {scene.fill_rule!r}")
        gpu = self._gpu()
        if not gpu.early_tests:
            raise Unsupported(f"{self.name}: this wgpu has no early fragment tests (shader-early-depth-test): "
                              "no stencil-then-cover with a fragment list")
        finite = finite_within_limit(scene, self.name)
        if len(scene) == 0:
            return Coverage.empty()
        side = self._guard_band(scene, self._side(scene, gpu), gpu)
        triangles, first, count = fans(scene)
        boxes = cover_boxes(scene, finite)
        area = np.maximum(boxes[:, 2] - boxes[:, 0], 0) * np.maximum(boxes[:, 3] - boxes[:, 1], 0)
        drawn = np.flatnonzero(area > 0)  # a path wholly off-screen covers nothing here
        if not drawn.size:
            return Coverage.empty()
        layer = layers(boxes[drawn])
        order = np.lexsort((drawn, layer))
        drawn, layer = drawn[order], layer[order]
        # slot s: path drawn[s]; its fan triangles fan_first[s] .. + fan_count[s]; cover quad vertices 6s .. 6s + 5
        fan_count = count[drawn]
        fan_first = np.cumsum(fan_count) - fan_count
        fan_triangles = triangles[np.repeat(first[drawn] - fan_first, fan_count) + np.arange(int(fan_count.sum()))]
        x0, y0, x1, y1 = (boxes[drawn, i].astype(np.float64) for i in range(4))
        quads = np.stack([np.c_[x0, y0], np.c_[x1, y0], np.c_[x1, y1], np.c_[x0, y0], np.c_[x1, y1], np.c_[x0, y1]], axis=1)
        nonzero = scene.fill_rule == "nonzero"
        count_state = ("increment-wrap", "decrement-wrap", "always", 0xFF) if nonzero else ("invert", "invert", "always", 0xFF)
        cover_state = ("zero", "zero", "not-equal", 0xFF if nonzero else 0x01)
        fan_pipeline = gpu.pipeline("triangles", "plain", "triangle-list", 1, count_state)
        cover_pipeline = gpu.pipeline("quads", "covered", "triangle-list", 1, cover_state)
        fan_buffer = gpu.vertices(_ndc(fan_triangles, side))
        quad_buffer = gpu.vertices(_ndc(quads, side))
        view = gpu.target(scene.width, scene.height, 1)
        stencil = gpu.stencil(scene.width, scene.height)
        screen = (0, 0, scene.width, scene.height)
        # jobs: (first slot, end slot, scissor), each one pass and one read-back: batches of
        # slots whose boxes fit the budget together; a path that alone exceeds it, in bands
        jobs: list[tuple[int, int, tuple[int, int, int, int]]] = []
        for start, end in budget_batches(area[drawn], self.BUDGET):
            if area[drawn[start]] > self.BUDGET:  # alone (end == start + 1)
                box = tuple(int(v) for v in boxes[drawn[start]])
                jobs += [(start, end, band) for band in bands((box[0], box[1], box[2], box[3]), self.BUDGET)]
            else:
                jobs.append((start, end, screen))
        parts = []
        try:
            for start, end, (x, y, w, h) in jobs:
                # cover fragments lie in their boxes (a band: in the band)
                capacity = (int(area[drawn[start:end]].sum()) if (x, y, w, h) == screen else w * h) + 1024
                gpu.fragments(capacity)
                encoder = gpu.device.create_command_encoder()
                rp = encoder.begin_render_pass(
                    color_attachments=[{"view": view, "load_op": "load", "store_op": "discard"}],
                    depth_stencil_attachment={"view": stencil, "stencil_load_op": "clear", "stencil_store_op": "discard",
                                              "stencil_clear_value": 0})
                rp.set_bind_group(0, gpu.bind_group())
                rp.set_viewport(-side, -side, 2 * side, 2 * side, 0.0, 1.0)
                rp.set_scissor_rect(x, y, w, h)
                rp.set_stencil_reference(0)
                cuts = np.flatnonzero(np.diff(layer[start:end])) + 1 + start
                for run in np.split(np.arange(start, end), cuts):
                    s, e = int(run[0]), int(run[-1]) + 1
                    n_fans = int(fan_first[e - 1] + fan_count[e - 1] - fan_first[s])
                    if n_fans:
                        rp.set_pipeline(fan_pipeline)
                        rp.set_vertex_buffer(0, fan_buffer)
                        rp.draw(3 * n_fans, 1, 3 * int(fan_first[s]), 0)
                    rp.set_pipeline(cover_pipeline)
                    rp.set_vertex_buffer(0, quad_buffer)
                    rp.draw(6 * (e - s), 1, 6 * s, 0)
                rp.end()
                gpu.device.queue.submit([encoder.finish()])
                items = gpu.read_fragments()
                if items.shape[0] > capacity:  # cannot happen (fragments fit their boxes), but never truncate
                    raise RuntimeError(f"{self.name}: {items.shape[0]} cover fragments for room for {capacity}")
                items = items[(items[:, 1] >= x) & (items[:, 1] < x + w) & (items[:, 2] >= y) & (items[:, 2] < y + h)]
                parts.append(coverage_from_fragments(drawn[items[:, 0]], items[:, 1], items[:, 2], scene.width, scene.height))
        finally:
            fan_buffer.destroy()
            quad_buffer.destroy()
        return Coverage.concat(parts)


class VulkanLavapipeMSAA4(_Lavapipe):
    """Mesa's lavapipe through wgpu's Vulkan back end with a 4x multisample framebuffer:
    which samples of each pixel each triangle covers, read from the fragment shader input
    ``@builtin(sample_mask)`` (bit s: sample s; the shader reads no per-sample input, so
    it runs once per pixel with every covered sample set), appended with the triangle
    (``vertex_index / 3``, flat) to a storage buffer, one draw per batch of triangles. A
    fragment with no sample covered stores nothing.

    Coordinates are mapped as in :class:`VulkanLavapipe` (float32 NDC (x / P, -y / P),
    viewport (-P, -P, 2P, 2P): exact; probe
    ``tests/rasterizers/real/test_vulkan.py::test_msaa_mapping_exact``). Vulkan gives
    sample positions as offsets from the pixel's top-left corner in framebuffer
    coordinates (y down, as ours); with ``standardSampleLocations`` (lavapipe: true) the
    4x pattern is :data:`VULKAN_4X` in sample order. wgpu does not expose the positions;
    the declaration is checked by identify and by the test comparing every sample with
    the multisample oracle.

    Identified (Mesa 22.3.6 lavapipe, wgpu 0.32.0): the standard 4x pattern
    :data:`VULKAN_4X` (bisected to 2^-8 px), top-left ties, vertices snapped to 1/256 px
    half to even, best guess with 1 pixel of 630,712 off: one sample of a float probe
    triangle whose vertex float32 rounding moves across a 1/512 px rounding boundary.
    On the float32 scene lavapipe receives (:meth:`received`) it is exact, but
    identify's multisample fit and the conformance verdict compare against the unrounded
    scene, so the convention (``Convention(samples=VULKAN_4X, tie="top-left",
    subpixel_bits=8)``) is not declared: declared, identify calls it contradicted (as it
    does ``mesa_llvmpipe_msaa4``'s). The test compares every sample with that oracle on
    lattice scenes (edges and vertices on samples) and on the float32-rounded float ones.

    Triangles only: paths and lines are single-sample (:class:`VulkanLavapipe`)."""

    name = "vulkan_lavapipe_msaa4"
    coverage_kind = "multisample"
    scene_kinds: tuple[str, ...] = ("triangles",)
    SAMPLES = 4
    convention: Convention | None = None

    def rasterize(self, scene: AnyScene) -> Coverage:
        if not isinstance(scene, Scene):
            refuse_kind(self.name, scene, self.scene_kinds)
        items = self._triangles(scene, "masked")
        if not items.shape[0]:
            zero = np.zeros(0, dtype=np.int64)
            return Coverage(zero, zero, zero, zero, sample=zero)
        return coverage_from_sample_masks(items[:, 0], items[:, 1], items[:, 2], items[:, 3], scene.width, self.SAMPLES)
