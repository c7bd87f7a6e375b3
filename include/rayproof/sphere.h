#pragma once
/// Ray/sphere: |o + t d - c|^2 = r^2 as A t^2 + B t + C with A = d·d, B = 2 d·(o-c),
/// C = (o-c)·(o-c) - r^2 (the worked problems' quadratic).
#include "rayproof/quadric.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Sphere {
  Vec3<T> center;
  T radius{};
};

template <class T>
[[nodiscard]] Hit<T> intersect(const Ray<T>& ray, const Sphere<T>& s) {
  if (!ray.valid() || !all_finite(s.center) || !std::isfinite(s.radius) || s.radius < T(0))
    return {Contact::invalid};
  if (s.radius == T(0)) return {Contact::degenerate};
  const Vec3<T> oc = ray.o - s.center;
  return classify_quadratic(dot(ray.d, ray.d), T(2) * dot(ray.d, oc), dot(oc, oc) - s.radius * s.radius);
}

}  // namespace rayproof
