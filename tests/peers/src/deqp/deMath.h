#ifndef _DEMATH_H
#define _DEMATH_H
/* rastercheck's stand-in for dEQP's deMath.h (framework/delibs/debase): the two
 * functions rrRasterizer.cpp uses, as the original defines them. */
#include <cmath>
#include <cstdint>

static inline int32_t deFloorFloatToInt32(float x) { return (int32_t)(floorf(x)); }

/* number of leading zero bits of a 64-bit value (64 for 0), as deClz64 */
static inline int deClz64(uint64_t a)
{
    if (a == 0)
        return 64;
    int n = 0;
    while (!(a & (1ull << 63))) { a <<= 1; n++; }
    return n;
}

#endif
