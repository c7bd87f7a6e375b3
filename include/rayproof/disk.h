#pragma once
/// Ray/disk: the plane test, then |p - c|^2 against r^2 at the plane point p (closed disk).
#include "rayproof/hit.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Disk {
  Vec3<T> center;
  Vec3<T> normal;  ///< need not be unit length; zero is degenerate
  T radius{};
};

template <class T>
[[nodiscard]] Hit<T> intersect(const Ray<T>& ray, const Disk<T>& dk) {
  if (!ray.valid() || !all_finite(dk.center) || !all_finite(dk.normal) || !std::isfinite(dk.radius) ||
      dk.radius < T(0))
    return {Contact::invalid};
  if (is_zero(dk.normal) || dk.radius == T(0)) return {Contact::degenerate};
  const T denom = dot(ray.d, dk.normal);
  const T num = dot(dk.center - ray.o, dk.normal);
  if (denom == T(0)) return {num == T(0) ? Contact::coplanar : Contact::parallel};
  const T t = num / denom;
  const T r2 = length_squared(ray.at(t) - dk.center);
  const T rr = dk.radius * dk.radius;
  if (!(r2 <= rr)) return {Contact::miss};
  if (t < T(0)) return {Contact::behind, t};
  return {r2 == rr ? Contact::rim : Contact::hit, t};
}

}  // namespace rayproof
