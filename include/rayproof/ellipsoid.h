#pragma once
/// Ray/axis-aligned ellipsoid: the implicit function sum((x_i - c_i)^2 / s_i^2) - 1 with the ray
/// substituted gives A t^2 + B t + C, A = sum d_i^2/s_i^2, B = 2 sum d_i (o_i-c_i)/s_i^2,
/// C = sum (o_i-c_i)^2/s_i^2 - 1.
#include "rayproof/quadric.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Ellipsoid {
  Vec3<T> center;
  Vec3<T> semi_axes;  ///< along x, y, z
};

template <class T>
[[nodiscard]] Hit<T> intersect(const Ray<T>& ray, const Ellipsoid<T>& e) {
  const Vec3<T>& s = e.semi_axes;
  if (!ray.valid() || !all_finite(e.center) || !all_finite(s) || s.x < T(0) || s.y < T(0) || s.z < T(0))
    return {Contact::invalid};
  if (s.x == T(0) || s.y == T(0) || s.z == T(0)) return {Contact::degenerate};
  const Vec3<T> inv2{T(1) / (s.x * s.x), T(1) / (s.y * s.y), T(1) / (s.z * s.z)};
  const Vec3<T> oc = ray.o - e.center;
  const T a = dot(mul(ray.d, ray.d), inv2);
  const T b = T(2) * dot(mul(ray.d, oc), inv2);
  const T c = dot(mul(oc, oc), inv2) - T(1);
  return classify_quadratic(a, b, c);
}

}  // namespace rayproof
