// Small 3-vector used by the scene records (double, host preprocessing) and the ray math (float).
#pragma once
#include <cmath>

namespace nesshi::base {

template <class T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    friend constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
    friend constexpr Vec3 operator*(Vec3 a, T s) { return {a.x * s, a.y * s, a.z * s}; }
    friend constexpr Vec3 operator*(T s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
    friend constexpr bool operator==(Vec3 a, Vec3 b) = default;
};

using Vec3d = Vec3<double>;
using Vec3f = Vec3<float>;

// Fixed evaluation order (x, then y, then z) so float results are reproducible.
template <class T>
constexpr T dot(Vec3<T> a, Vec3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
T length(Vec3<T> a) {
    return std::sqrt(dot(a, a));
}
template <class T>
Vec3<T> normalize(Vec3<T> a) {
    T l = length(a);
    return l > T(0) ? a * (T(1) / l) : a;
}
inline Vec3f to_float(Vec3d v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}
inline Vec3d to_double(Vec3f v) { return {v.x, v.y, v.z}; }

} // namespace nesshi::base
