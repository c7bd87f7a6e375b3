#pragma once
/// Small 3-vector templated on the scalar type. Points and vectors share the type;
/// names in the kernels say which is which (o, d for a ray; p0.. for vertices).
#include <cmath>
#include <cstddef>

namespace rayproof {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  constexpr T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr const T& operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }

  template <class U>
  [[nodiscard]] constexpr Vec3<U> cast() const {
    return {static_cast<U>(x), static_cast<U>(y), static_cast<U>(z)};
  }
};

template <class T> constexpr Vec3<T> operator+(Vec3<T> a, Vec3<T> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> constexpr Vec3<T> operator-(Vec3<T> a, Vec3<T> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> constexpr Vec3<T> operator-(Vec3<T> a) { return {-a.x, -a.y, -a.z}; }
template <class T> constexpr Vec3<T> operator*(T s, Vec3<T> a) { return {s * a.x, s * a.y, s * a.z}; }
template <class T> constexpr Vec3<T> operator*(Vec3<T> a, T s) { return {s * a.x, s * a.y, s * a.z}; }
template <class T> constexpr Vec3<T> operator/(Vec3<T> a, T s) { return {a.x / s, a.y / s, a.z / s}; }
template <class T> constexpr bool operator==(Vec3<T> a, Vec3<T> b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/// Component-wise product and quotient (ellipsoid scaling, slab tests).
template <class T> constexpr Vec3<T> mul(Vec3<T> a, Vec3<T> b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
template <class T> constexpr Vec3<T> div(Vec3<T> a, Vec3<T> b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }

template <class T> constexpr T dot(Vec3<T> a, Vec3<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> constexpr T length_squared(Vec3<T> a) { return dot(a, a); }
template <class T> T length(Vec3<T> a) { return std::sqrt(dot(a, a)); }
template <class T> Vec3<T> normalize(Vec3<T> a) { return a / length(a); }
template <class T> constexpr bool is_zero(Vec3<T> a) { return a.x == T(0) && a.y == T(0) && a.z == T(0); }
template <class T> bool all_finite(Vec3<T> a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// Index of the component with the largest magnitude (ties: the lowest index).
template <class T> constexpr int max_abs_axis(Vec3<T> a) {
  T ax = a.x < 0 ? -a.x : a.x, ay = a.y < 0 ? -a.y : a.y, az = a.z < 0 ? -a.z : a.z;
  return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

}  // namespace rayproof
