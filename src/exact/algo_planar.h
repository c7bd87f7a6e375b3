#pragma once
/// Exact ray/plane and ray/disk, on a kernel K (algo_kernel.h). Predicates: d . n = 0
/// (parallel or coplanar by (p - o) . n); t = (p - o) . n / (d . n) has the sign of the product of
/// the two signs; the disk test compares |P - c|^2 with r^2 at the plane point P, scaled by (d .
/// n)^2 so that no division is needed. Construction: t rounded.
#include "rayproof/disk.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "exact/algo_kernel.h"

namespace rayproof::exact_algo {

/// The ray against the plane through `on` with normal n (n != 0).
template <class K>
struct PlaneCrossing {
  typename K::Q num, den;  ///< t = num / den; den = d . n
  [[nodiscard]] int side() const { return K::sign(num) * K::sign(den); }  ///< sign of t (den != 0)
};

template <class K>
[[nodiscard]] PlaneCrossing<K> cross_plane(const typename K::Point& o, const typename K::Vector& d,
                                           const typename K::Point& on, const typename K::Vector& n) {
  return {K::dot(on - o, n), K::dot(d, n)};
}

/// parallel / coplanar for a ray with d . n = 0.
template <class K>
[[nodiscard]] Hit<double> in_or_off_plane(const PlaneCrossing<K>& x) {
  return {K::sign(x.num) == 0 ? Contact::coplanar : Contact::parallel};
}

template <class K>
[[nodiscard]] Hit<double> plane(const Ray<double>& ray, const Plane<double>& pl) {
  const PlaneCrossing<K> x = cross_plane<K>(K::point(ray.o), K::vector(ray.d), K::point(pl.point), K::vector(pl.normal));
  if (K::sign(x.den) == 0) return in_or_off_plane(x);
  const double t = rounded_quotient<K>(x.num, x.den);
  return {x.side() < 0 ? Contact::behind : Contact::hit, t};
}

template <class K>
[[nodiscard]] Hit<double> disk(const Ray<double>& ray, const Disk<double>& dk) {
  using Q = typename K::Q;
  using Vector = typename K::Vector;
  const typename K::Point o = K::point(ray.o), center = K::point(dk.center);
  const Vector d = K::vector(ray.d);
  const PlaneCrossing<K> x = cross_plane<K>(o, d, center, K::vector(dk.normal));
  if (K::sign(x.den) == 0) return in_or_off_plane(x);
  // den (P - center) = den (o - center) + num d, so |P - c|^2 vs r^2 <=> |that|^2 vs r^2 den^2.
  const Vector w = x.den * (o - center) + x.num * d;
  const Q r(dk.radius);
  const Q excess = K::dot(w, w) - r * r * x.den * x.den;
  const int outside = K::sign(excess);
  if (outside > 0) return {Contact::miss};
  const double t = rounded_quotient<K>(x.num, x.den);
  if (x.side() < 0) return {Contact::behind, t};
  return {outside == 0 ? Contact::rim : Contact::hit, t};
}

}  // namespace rayproof::exact_algo
