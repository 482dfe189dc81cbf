/* rastercheck's shim around FreeType's smooth rasterizer (ftgrays.c, built standalone):
 * one outline of straight contours, in 26.6 fixed point, rendered into an 8-bit gray
 * bitmap (gray_sweep) or through direct spans (gray_sweep_direct). Not part of FreeType.
 *
 * Coordinates pass unchanged: FreeType's y grows upwards and its bitmap's rows are laid
 * out from the top when the pitch is positive; with a negative pitch row y of the buffer
 * is FreeType's row y, so a caller with y growing downwards (an image) gets its own
 * pixel (x, y) at out[y * width + x].
 *
 * Build: cc -shared -fPIC -DSTANDALONE_ -DFALL_THROUGH='(void)0' ftgrays.c freetype_shim.c
 * (add -DFT_INT64=long -DFT_Int64=long -DFT_UInt64='unsigned long' -DFT_UInt='unsigned int'
 * for the line renderer FreeType compiles on 64-bit platforms). */

#include <string.h>

#define FT_BEGIN_HEADER
#define FT_END_HEADER
#define FT_STATIC_BYTE_CAST( type, var )  (type)(unsigned char)(var)  /* as ftgrays.c, standalone */
#include "ftimage.h"
#include "ftgrays.h"

typedef struct
{
  unsigned char*  out;
  int             width;
  int             height;
} Target;


static void
gray_spans( int             y,
            int             count,
            const FT_Span*  spans,
            void*           user )
{
  Target*  target = (Target*)user;
  int      k;


  for ( k = 0; k < count; k++ )
    memset( target->out + (long)y * target->width + spans[k].x,
            spans[k].coverage,
            spans[k].len );
}


/* Render contours of straight edges into out (height x width bytes, zeroed here).
 * xy: n_points (x, y) pairs in 26.6 fixed point; ends: the index of each contour's last
 * point; evenodd: FT_OUTLINE_EVEN_ODD_FILL when nonzero; direct: spans through the
 * callback (FT_RASTER_FLAG_DIRECT, clip box = the bitmap) instead of the bitmap.
 * Returns FreeType's error code (0: success), -100 for a size it cannot take. */
int
rastercheck_ftgrays_render( const long*            xy,
                            int                    n_points,
                            const unsigned short*  ends,
                            int                    n_contours,
                            int                    evenodd,
                            int                    direct,
                            int                    width,
                            int                    height,
                            unsigned char*         out )
{
  static FT_Vector      points[65535];
  static unsigned char  tags[65535];
  static unsigned short contours[65535];

  FT_Raster         raster;
  FT_Outline        outline;
  FT_Bitmap         bitmap;
  FT_Raster_Params  params;
  Target            target;
  int               k, error;


  if ( n_points < 0 || n_points > 65535 || n_contours < 0 || n_contours > 65535 )
    return -100;
  memset( out, 0, (size_t)width * (size_t)height );

  for ( k = 0; k < n_points; k++ )
  {
    points[k].x = xy[2 * k];
    points[k].y = xy[2 * k + 1];
    tags[k]     = FT_CURVE_TAG_ON;
  }
  for ( k = 0; k < n_contours; k++ )
    contours[k] = ends[k];

  outline.n_contours = (unsigned short)n_contours;
  outline.n_points   = (unsigned short)n_points;
  outline.points     = points;
  outline.tags       = tags;
  outline.contours   = contours;
  outline.flags      = evenodd ? FT_OUTLINE_EVEN_ODD_FILL : 0;

  memset( &bitmap, 0, sizeof ( bitmap ) );
  bitmap.rows       = (unsigned int)height;
  bitmap.width      = (unsigned int)width;
  bitmap.pitch      = -width;  /* row y of the buffer is FreeType's row y */
  bitmap.buffer     = out;
  bitmap.num_grays  = 256;
  bitmap.pixel_mode = FT_PIXEL_MODE_GRAY;

  target.out    = out;
  target.width  = width;
  target.height = height;

  memset( &params, 0, sizeof ( params ) );
  params.source = &outline;
  params.flags  = FT_RASTER_FLAG_AA;
  if ( direct )
  {
    params.flags         |= FT_RASTER_FLAG_DIRECT | FT_RASTER_FLAG_CLIP;
    params.gray_spans     = gray_spans;
    params.user           = &target;
    params.clip_box.xMin  = 0;
    params.clip_box.yMin  = 0;
    params.clip_box.xMax  = width;
    params.clip_box.yMax  = height;
  }
  else
    params.target = &bitmap;

  error = ft_grays_raster.raster_new( NULL, &raster );
  if ( error )
    return error;
  error = ft_grays_raster.raster_render( raster, &params );
  ft_grays_raster.raster_done( raster );
  return error;
}
