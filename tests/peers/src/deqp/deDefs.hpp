#ifndef _DEDEFS_HPP
#define _DEDEFS_HPP
/* rastercheck's stand-in for dEQP's deDefs.hpp (framework/delibs/debase): only the
 * macros and de:: helpers rrRasterizer.cpp uses, with the original's meaning. Release
 * build: DE_ASSERT checks nothing, as in dEQP without DE_DEBUG. */
#include <cstdint>
#include <cstddef>
#include <cmath>
#include <utility>

#define DE_ASSERT(X) ((void)0)
#define DE_STATIC_ASSERT(X) static_assert((X), #X)
#define DE_LENGTH_OF_ARRAY(ARRAY) ((int)(sizeof(ARRAY) / sizeof((ARRAY)[0])))
#define DE_WARN_UNUSED_TYPE

namespace de
{
template <typename T> inline T min(const T &a, const T &b) { return (a <= b) ? a : b; }
template <typename T> inline T max(const T &a, const T &b) { return (a >= b) ? a : b; }
template <typename T> inline T clamp(const T &v, const T &lo, const T &hi) { return (v < lo) ? lo : ((v > hi) ? hi : v); }
template <typename T> inline T abs(const T &a) { return (a < T(0)) ? -a : a; }
template <typename T> inline bool inRange(const T &v, const T &lo, const T &hi) { return lo <= v && v <= hi; }
template <typename T> inline bool inBounds(const T &v, const T &lo, const T &hi) { return lo <= v && v < hi; }
} // namespace de

#endif
