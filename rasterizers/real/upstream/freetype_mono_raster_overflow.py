"""FreeType: the monochrome rasterizer fails with Raster_Overflow on a valid outline whose
contour winds about 120 times or more over a 16 x 16 bitmap; the smooth rasterizer
renders the same outline.

Library: FreeType 2.13.2 (as bundled by freetype-py 2.5.1), x86-64 Linux; found by
rastercheck (its ``paths/deep-winding/128`` case).

Input: one closed contour of straight segments tracing the triangle (2, 2), (14, 2),
(8, 14) (pixels; 26.6 fixed point) 128 times over (384 on-curve points), rendered with
``FT_Outline_Get_Bitmap`` into a 16 x 16 ``FT_PIXEL_MODE_MONO`` bitmap
(``FT_OUTLINE_IGNORE_DROPOUTS``; dropout control on fails alike).

Expected: the triangle filled (nonzero winding, 128 inside), as for any valid outline:
``FT_Outline_Check`` accepts it, the coordinates are far inside FreeType's limits, and
``src/raster/ftraster.c``'s own notes say that when its render pool overflows it
"handles the situation by bisecting the job and restarting". The smooth rasterizer
(``FT_PIXEL_MODE_GRAY``) renders it.

What happens: error 0x62, Raster_Overflow. ftraster.c keeps the profiles in a fixed
16 KB pool on the stack (``FT_MAX_BLACK_POOL`` longs); every pass of the contour over a
scanline adds an upward and a downward profile, and once the profiles of a single
scanline exceed the pool, bisecting the band cannot help (``Render_Single_Pass``
returns Raster_Overflow when ``y_min == y_max``). 110 windings render; 120 fail.

Exit status: prints the evidence; exits 1 while the bug reproduces, 0 once the monochrome rasterizer
renders the outline.
"""

import ctypes
import sys

import numpy as np

RASTER_OVERFLOW = 0x62


def render(turns: int, pixel_mode: int) -> tuple[int, np.ndarray]:
    import freetype
    from freetype import raw
    from freetype.ft_structs import FT_Bitmap, FT_Outline, FT_Vector

    size = 16
    triangle = np.array([[2, 2], [14, 2], [8, 14]], dtype=np.int64) * 64  # 26.6, y up
    points = np.ascontiguousarray(np.tile(triangle, (turns, 1)))
    n = points.shape[0]
    vectors = (FT_Vector * n).from_buffer(points)
    tags = (ctypes.c_ubyte * n)(*[1] * n)  # FT_CURVE_TAG_ON: straight segments
    ends = (ctypes.c_short * 1)(n - 1)
    flags = freetype.FT_OUTLINE_IGNORE_DROPOUTS if pixel_mode == 1 else 0
    outline = FT_Outline(1, n, vectors, tags, ends, flags)
    if raw.FT_Outline_Check(ctypes.byref(outline)):
        raise SystemExit("FT_Outline_Check rejects the outline: the repro is wrong")
    pitch = 2 if pixel_mode == 1 else size
    buffer = np.zeros((size, pitch), dtype=np.uint8)
    bitmap = FT_Bitmap(size, size, pitch, buffer.ctypes.data_as(ctypes.POINTER(ctypes.c_ubyte)), 256, pixel_mode, b"\0", None)
    error = raw.FT_Outline_Get_Bitmap(freetype.get_handle(), ctypes.byref(outline), ctypes.byref(bitmap))
    return int(error), buffer


def main() -> int:
    import freetype

    print("FreeType %d.%d.%d" % freetype.version())
    turns = 128
    gray_error, gray = render(turns, 2)
    mono_error, mono = render(turns, 1)
    print(f"{turns} turns, {3 * turns} points: smooth (gray) error {gray_error:#x}, {int(np.count_nonzero(gray))} pixels; "
          f"monochrome error {mono_error:#x}, {int(np.count_nonzero(np.unpackbits(mono, axis=1)))} pixels")
    for fewer in (64, 110, 120):
        print(f"{fewer} turns: monochrome error {render(fewer, 1)[0]:#x}")
    if mono_error == RASTER_OVERFLOW:
        print("BUG: the monochrome rasterizer fails with Raster_Overflow on a valid outline the smooth one renders")
        return 1
    print("fixed: the monochrome rasterizer renders the outline")
    return 0


if __name__ == "__main__":
    sys.exit(main())
