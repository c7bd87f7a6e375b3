/// Exact ray/plane and ray/disk. Predicates: d . n = 0 (parallel or coplanar by (p - o) . n);
/// t = (p - o) . n / (d . n) has the sign of the product of the two signs; the disk test compares
/// |P - c|^2 with r^2 at the plane point P, scaled by (d . n)^2 so that no division is needed.
/// Construction: t rounded to nearest.
#include "verify/exact_kinds.h"
#include "verify/exact_number.h"
#include "verify/exact_rounding.h"

namespace rayproof::verify {

namespace {

/// The ray against the plane through `on` with normal n (n != 0).
struct PlaneCrossing {
  Q num, den;  ///< t = num / den; den = d . n
  [[nodiscard]] int side() const { return sign(num) * sign(den); }  ///< sign of t (den != 0)
};

PlaneCrossing cross_plane(const Point& o, const Vector& d, const Point& on, const Vector& n) {
  return {(on - o) * n, d * n};
}

/// parallel / coplanar for a ray with d . n = 0.
Hit<double> in_or_off_plane(const PlaneCrossing& x) {
  return {sign(x.num) == 0 ? Contact::coplanar : Contact::parallel};
}

}  // namespace

Hit<double> exact_plane(const Ray<double>& ray, const Plane<double>& pl) {
  const PlaneCrossing x = cross_plane(point_of(ray.o), vector_of(ray.d), point_of(pl.point), vector_of(pl.normal));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  const double t = round_nearest(x.num / x.den);
  return {x.side() < 0 ? Contact::behind : Contact::hit, t};
}

Hit<double> exact_disk(const Ray<double>& ray, const Disk<double>& dk) {
  const Point o = point_of(ray.o), center = point_of(dk.center);
  const Vector d = vector_of(ray.d);
  const PlaneCrossing x = cross_plane(o, d, center, vector_of(dk.normal));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  // den (P - center) = den (o - center) + num d, so |P - c|^2 vs r^2 <=> |that|^2 vs r^2 den^2.
  const Vector w = x.den * (o - center) + x.num * d;
  const Q r(dk.radius);
  const int outside = sign(w * w - r * r * x.den * x.den);
  if (outside > 0) return {Contact::miss};
  const double t = round_nearest(x.num / x.den);
  if (x.side() < 0) return {Contact::behind, t};
  return {outside == 0 ? Contact::rim : Contact::hit, t};
}

}  // namespace rayproof::verify
