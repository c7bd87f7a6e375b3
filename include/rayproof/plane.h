#pragma once
/// Ray/plane: t = ((p - o)·N) / (d·N), the worked problems' formula.
#include "rayproof/hit.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Plane {
  Vec3<T> point;   ///< any point on the plane
  Vec3<T> normal;  ///< need not be unit length; zero is degenerate
};

template <class T>
[[nodiscard]] Hit<T> intersect(const Ray<T>& ray, const Plane<T>& pl) {
  if (!ray.valid() || !all_finite(pl.point) || !all_finite(pl.normal)) return {Contact::invalid};
  if (is_zero(pl.normal)) return {Contact::degenerate};
  const T denom = dot(ray.d, pl.normal);
  const T num = dot(pl.point - ray.o, pl.normal);
  if (denom == T(0)) return {num == T(0) ? Contact::coplanar : Contact::parallel};
  const T t = num / denom;
  // A NaN t (overflow of both products) compares false and falls through to hit; it cannot arise
  // from finite inputs unless num and denom both overflow, which the verify module measures.
  return {t < T(0) ? Contact::behind : Contact::hit, t};
}

}  // namespace rayproof
