#pragma once
/// Ray/disk with FMA: the plane part as in plane_fma.h, then the plane point p = (o - c) + t d with
/// one FMA per component and |p - c|^2 - r^2 with a compensated dot and r^2 entering unrounded, so
/// the rim test compares the computed point with the exact r^2.
#include <cmath>

#include "rayproof/disk.h"
#include "rayproof/plane_fma.h"

namespace rayproof {

template <class T>
[[nodiscard]] Hit<T> intersect_fma(const Ray<T>& ray, const Disk<T>& dk) {
  if (!ray.valid() || !all_finite(dk.center) || !all_finite(dk.normal) || !std::isfinite(dk.radius) ||
      dk.radius < T(0))
    return {Contact::invalid};
  if (is_zero(dk.normal) || dk.radius == T(0)) return {Contact::degenerate};
  // Plane crossing, compensated.
  const T denom = dot_fma(ray.d, dk.normal);
  const T num = dot_fma(dk.center - ray.o, dk.normal);
  if (denom == T(0)) return {num == T(0) ? Contact::coplanar : Contact::parallel};
  const T t = num / denom;
  // Offset of the plane point from the centre: fma(t, d, o - c) per axis.
  const Vec3<T> oc = ray.o - dk.center;
  const Vec3<T> q{std::fma(t, ray.d.x, oc.x), std::fma(t, ray.d.y, oc.y), std::fma(t, ray.d.z, oc.z)};
  // |q|^2 - r^2: the products error-free, summed once.
  const T r2 = dot_fma(q, q);
  const T excess = std::fma(-dk.radius, dk.radius, r2);
  if (!(excess <= T(0))) return {Contact::miss};
  if (t < T(0)) return {Contact::behind, t};
  return {excess == T(0) ? Contact::rim : Contact::hit, t};
}

}  // namespace rayproof
