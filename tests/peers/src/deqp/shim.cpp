/* rastercheck's flat C entry points into dEQP's reference rasterizer (rrRasterizer.cpp),
 * for ctypes. Each draws primitives one at a time into a viewport (0, 0, width, height)
 * with the default RasterizationState (counter-clockwise winding, FILL_LEFT,
 * FILL_BOTTOM), as dEQP's tests drive it, and writes one row of 4 int32 per covered
 * pixel: primitive, x, y, sample mask (bit s: sample s of the pattern; bit 0 alone for
 * single-sample output). Returns the number of rows (rows beyond capacity are counted,
 * not written: call again with a larger buffer).
 */
#include "rrRasterizer.hpp"

#include <vector>

namespace
{

struct Writer
{
    int32_t *out;
    int64_t capacity;
    int64_t count;

    void put(int primitive, int x, int y, uint32_t mask)
    {
        if (count < capacity)
        {
            out[count * 4 + 0] = primitive;
            out[count * 4 + 1] = x;
            out[count * 4 + 2] = y;
            out[count * 4 + 3] = (int32_t)mask;
        }
        count++;
    }
};

enum { MAX_PACKETS = 256 };

// Drain a rasterizer's packets: each covers the 2x2 fragments at position + (fx, fy).
template <typename Rasterizer>
void drain(Rasterizer &r, int primitive, int numSamples, Writer &w)
{
    std::vector<rr::FragmentPacket> packets(MAX_PACKETS);
    int n = 0;
    do
    {
        r.rasterize(&packets[0], nullptr, MAX_PACKETS, n);
        for (int p = 0; p < n; p++)
            for (int fy = 0; fy < 2; fy++)
                for (int fx = 0; fx < 2; fx++)
                {
                    uint32_t mask = 0;
                    for (int s = 0; s < numSamples; s++)
                        if (rr::getCoverageValue(packets[p].coverage, numSamples, fx, fy, s))
                            mask |= 1u << s;
                    if (mask)
                        w.put(primitive, packets[p].position.x() + fx, packets[p].position.y() + fy, mask);
                }
    } while (n == MAX_PACKETS);
}

} // namespace

extern "C" {

/* Triangles: xy holds n * 6 floats (x0, y0, x1, y1, x2, y2 in window coordinates). */
int64_t deqp_triangles(const float *xy, int n, int width, int height, int samples, int subpixel_bits, int32_t *out,
                       int64_t capacity)
{
    Writer w = {out, capacity, 0};
    const tcu::IVec4 viewport(0, 0, width, height);
    for (int t = 0; t < n; t++)
    {
        rr::TriangleRasterizer r(viewport, samples, rr::RasterizationState(), subpixel_bits);
        const float *v = xy + 6 * t;
        r.init(tcu::Vec4(v[0], v[1], 0.0f, 1.0f), tcu::Vec4(v[2], v[3], 0.0f, 1.0f),
               tcu::Vec4(v[4], v[5], 0.0f, 1.0f));
        drain(r, t, samples, w);
    }
    return w.count;
}

/* Multisample lines: xy holds n * 4 floats (x0, y0, x1, y1); each a rectangle of the
 * given width drawn as two triangles (MultiSampleLineRasterizer). */
int64_t deqp_lines_multisample(const float *xy, int n, int width, int height, int samples, int subpixel_bits,
                               float line_width, int32_t *out, int64_t capacity)
{
    Writer w = {out, capacity, 0};
    const tcu::IVec4 viewport(0, 0, width, height);
    for (int t = 0; t < n; t++)
    {
        rr::MultiSampleLineRasterizer r(samples, viewport, subpixel_bits);
        const float *v = xy + 4 * t;
        r.init(tcu::Vec4(v[0], v[1], 0.0f, 1.0f), tcu::Vec4(v[2], v[3], 0.0f, 1.0f), line_width);
        drain(r, t, samples, w);
    }
    return w.count;
}

/* Aliased lines: xy holds n * 4 floats; the diamond-exit rule (SingleSampleLineRasterizer),
 * no stipple (factor 1, pattern 0xffff). */
int64_t deqp_lines(const float *xy, int n, int width, int height, int subpixel_bits, float line_width, int32_t *out,
                   int64_t capacity)
{
    Writer w = {out, capacity, 0};
    const tcu::IVec4 viewport(0, 0, width, height);
    for (int t = 0; t < n; t++)
    {
        rr::SingleSampleLineRasterizer r(viewport, subpixel_bits);
        const float *v = xy + 4 * t;
        r.init(tcu::Vec4(v[0], v[1], 0.0f, 1.0f), tcu::Vec4(v[2], v[3], 0.0f, 1.0f), line_width, 1, 0xffff);
        drain(r, t, 1, w);
    }
    return w.count;
}

} // extern "C"
