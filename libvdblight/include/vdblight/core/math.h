// Small value types shared by every module: 3-vectors, RGB, boxes.
//
// vdblight keeps its public API free of OpenVDB, Embree and Assimp types so that
// an application can link the library without those headers, and so that only a
// few translation units pay OpenVDB's compile time.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace vdblight {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvPi = 1.0 / kPi;

/// A 3-vector of T (float for storage and geometry, double for accumulation).
template <typename T>
struct Vec3T {
    T x = 0, y = 0, z = 0;

    constexpr Vec3T() = default;
    constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <typename U>
    constexpr explicit Vec3T(const Vec3T<U>& v) : x(T(v.x)), y(T(v.y)), z(T(v.z)) {}

    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3T operator-() const { return {-x, -y, -z}; }
    constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3T operator*(const Vec3T& o) const { return {x * o.x, y * o.y, z * o.z}; }
    Vec3T& operator+=(const Vec3T& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3T& operator-=(const Vec3T& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3T& o) const { return x == o.x && y == o.y && z == o.z; }
    constexpr bool operator!=(const Vec3T& o) const { return !(*this == o); }
};

template <typename T> constexpr Vec3T<T> operator*(T s, const Vec3T<T>& v) { return v * s; }
template <typename T> constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T> constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T> inline T length(const Vec3T<T>& v) { return std::sqrt(dot(v, v)); }
template <typename T> inline Vec3T<T> normalize(const Vec3T<T>& v) { return v / length(v); }
template <typename T> inline Vec3T<T> vmin(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <typename T> inline Vec3T<T> vmax(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <typename T> inline bool isFinite(const Vec3T<T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

using Vec3f = Vec3T<float>;
using Vec3d = Vec3T<double>;

/// Linear RGB. Radiance in W/(m^2 sr), irradiance in W/m^2, albedo in [0,1].
using Rgb = Vec3f;
using Rgbd = Vec3d;

inline float luminance(const Rgb& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline float maxComponent(const Rgb& c) { return std::max(c.x, std::max(c.y, c.z)); }

/// Orthonormal basis around a unit vector n (Duff et al. 2017, branchless).
inline void orthonormalBasis(const Vec3f& n, Vec3f& t, Vec3f& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float bb = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x};
    b = {bb, sign + n.y * n.y * a, -n.y};
}

/// Axis-aligned box. Empty when lo > hi on any axis.
struct Bounds {
    Vec3d lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
             std::numeric_limits<double>::max()};
    Vec3d hi{-std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
             -std::numeric_limits<double>::max()};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(const Vec3d& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    Vec3d size() const { return hi - lo; }
    Vec3d center() const { return (lo + hi) * 0.5; }
    bool contains(const Vec3d& p) const {
        return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
    }
};

}  // namespace vdblight
