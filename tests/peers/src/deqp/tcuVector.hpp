#ifndef _TCUVECTOR_HPP
#define _TCUVECTOR_HPP
/* rastercheck's stand-in for dEQP's tcuVector.hpp and tcuVectorUtil.hpp
 * (framework/common): a fixed-size vector with the element-wise operators, accessors,
 * dot, lengthSquared and normalize that rrRasterizer.cpp uses, each computed as the
 * original does (element by element in T; normalize multiplies by T(1) / sqrt). */
#include "deDefs.hpp"

namespace tcu
{

template <typename T, int Size>
class Vector
{
public:
    T m_data[Size];

    Vector(void) { for (int i = 0; i < Size; i++) m_data[i] = T(); }
    explicit Vector(T s) { for (int i = 0; i < Size; i++) m_data[i] = s; }
    Vector(T x, T y) { static_assert(Size == 2, "size"); m_data[0] = x; m_data[1] = y; }
    Vector(T x, T y, T z, T w) { static_assert(Size == 4, "size"); m_data[0] = x; m_data[1] = y; m_data[2] = z; m_data[3] = w; }

    T &x(void) { return m_data[0]; }
    T &y(void) { return m_data[1]; }
    T &z(void) { return m_data[2]; }
    T &w(void) { return m_data[3]; }
    const T &x(void) const { return m_data[0]; }
    const T &y(void) const { return m_data[1]; }
    const T &z(void) const { return m_data[2]; }
    const T &w(void) const { return m_data[3]; }
    T &operator[](int i) { return m_data[i]; }
    const T &operator[](int i) const { return m_data[i]; }

    Vector<T, 2> xy(void) const { return Vector<T, 2>(m_data[0], m_data[1]); }

    template <typename U>
    Vector<U, Size> cast(void) const
    {
        Vector<U, Size> r;
        for (int i = 0; i < Size; i++) r.m_data[i] = U(m_data[i]);
        return r;
    }
    Vector<float, Size> asFloat(void) const { return cast<float>(); }

    bool operator==(const Vector &o) const
    {
        for (int i = 0; i < Size; i++) if (!(m_data[i] == o.m_data[i])) return false;
        return true;
    }
    bool operator!=(const Vector &o) const { return !(*this == o); }
};

#define TCU_ELEMENTWISE(OP)                                                                            \
    template <typename T, int Size>                                                                    \
    inline Vector<T, Size> operator OP(const Vector<T, Size> &a, const Vector<T, Size> &b)            \
    {                                                                                                  \
        Vector<T, Size> r;                                                                             \
        for (int i = 0; i < Size; i++) r.m_data[i] = a.m_data[i] OP b.m_data[i];                       \
        return r;                                                                                      \
    }                                                                                                  \
    template <typename T, int Size>                                                                    \
    inline Vector<T, Size> operator OP(const Vector<T, Size> &a, T s)                                  \
    {                                                                                                  \
        Vector<T, Size> r;                                                                             \
        for (int i = 0; i < Size; i++) r.m_data[i] = a.m_data[i] OP s;                                 \
        return r;                                                                                      \
    }                                                                                                  \
    template <typename T, int Size>                                                                    \
    inline Vector<T, Size> operator OP(T s, const Vector<T, Size> &a)                                  \
    {                                                                                                  \
        Vector<T, Size> r;                                                                             \
        for (int i = 0; i < Size; i++) r.m_data[i] = s OP a.m_data[i];                                 \
        return r;                                                                                      \
    }

TCU_ELEMENTWISE(+)
TCU_ELEMENTWISE(-)
TCU_ELEMENTWISE(*)
TCU_ELEMENTWISE(/)
#undef TCU_ELEMENTWISE

template <typename T, int Size>
inline Vector<T, Size> operator-(const Vector<T, Size> &a)
{
    Vector<T, Size> r;
    for (int i = 0; i < Size; i++) r.m_data[i] = -a.m_data[i];
    return r;
}

template <typename T, int Size>
inline T dot(const Vector<T, Size> &a, const Vector<T, Size> &b)
{
    T res = T();
    for (int i = 0; i < Size; i++) res += a.m_data[i] * b.m_data[i];
    return res;
}

template <typename T, int Size>
inline T lengthSquared(const Vector<T, Size> &a)
{
    T sqSum = T();
    for (int i = 0; i < Size; i++) sqSum += a.m_data[i] * a.m_data[i];
    return sqSum;
}

template <int Size>
inline Vector<float, Size> normalize(const Vector<float, Size> &a)
{
    float ooLen = 1.0f / sqrtf(lengthSquared(a)); // deFloatSqrt is sqrtf
    Vector<float, Size> res;
    for (int i = 0; i < Size; i++) res.m_data[i] = ooLen * a.m_data[i];
    return res;
}

typedef Vector<float, 2> Vec2;
typedef Vector<float, 4> Vec4;
typedef Vector<int, 2> IVec2;
typedef Vector<int, 4> IVec4;

} // namespace tcu

#endif
