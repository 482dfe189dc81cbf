/* A flat entry point into stb_truetype's version-2 anti-aliased rasterizer for ctypes:
   one polygon (here a triangle) of float vertices drawn into an 8-bit bitmap by
   stbtt__rasterize, exactly as stbtt_Rasterize does after flattening a glyph's curves.

   stb_truetype.h is included unchanged (v1.26, nothings/stb 31c1ad3). STBTT_assert is
   defined empty, as in a release build (NDEBUG): the asserts that fire on edges lying
   above the bitmap (stbtt__rasterize_sorted_edges: "z->ey >= scan_y_top") would abort. */
#define STBTT_assert(x) ((void)0)
#define STBTT_RASTERIZER_VERSION 2
#define STB_TRUETYPE_IMPLEMENTATION
#define STBTT_STATIC
#include "stb_truetype.h"

/* Draw the polygon xy[0..2n) (x, y pairs, y down) into the w x h bitmap out (row-major,
   stride w) whose pixel (0, 0) is pixel (off_x, off_y) of the vertices' space: scale 1,
   shift 0, invert 0 (y down as given), one winding. Each pixel (i, j) gets
   (int)(|coverage| * 255 + 0.5), clamped at 255. */
void stb_rasterize_polygon(const float *xy, int n, int w, int h, int off_x, int off_y, unsigned char *out)
{
   stbtt__bitmap bitmap;
   stbtt__point points[64];
   int count = n, i;
   if (n > 64) return;
   for (i = 0; i < n; ++i) {
      points[i].x = xy[2 * i];
      points[i].y = xy[2 * i + 1];
   }
   bitmap.w = w;
   bitmap.h = h;
   bitmap.stride = w;
   bitmap.pixels = out;
   stbtt__rasterize(&bitmap, points, &count, 1, 1.0f, 1.0f, 0.0f, 0.0f, off_x, off_y, 0, NULL);
}
