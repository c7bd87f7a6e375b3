/// Exact ray/plane and ray/disk. Predicates: d . n = 0 (parallel or coplanar by (p - o) . n);
/// t = (p - o) . n / (d . n) has the sign of the product of the two signs; the disk test compares
/// |P - c|^2 with r^2 at the plane point P, scaled by (d . n)^2 so that no division is needed.
/// Construction: t rounded to nearest.
#include "verify/fallback_kinds.h"
#include "verify/fallback_number.h"
#include "verify/fallback_rounding.h"

namespace rayproof::certified::fallback {

namespace {

/// The ray against the plane through `on` with normal n (n != 0).
struct PlaneCrossing {
  Q num, den;  ///< t = num / den; den = d . n
  [[nodiscard]] int side() const { return sign(num) * sign(den); }  ///< sign of t (den != 0)
};

PlaneCrossing cross_plane(const QVec& o, const QVec& d, const QVec& on, const QVec& n) {
  return {dot(on - o, n), dot(d, n)};
}

/// parallel / coplanar for a ray with d . n = 0.
Hit<double> in_or_off_plane(const PlaneCrossing& x) {
  return {sign(x.num) == 0 ? Contact::coplanar : Contact::parallel};
}

}  // namespace

Hit<double> plane_kernel(const Ray<double>& ray, const Plane<double>& pl) {
  const PlaneCrossing x = cross_plane(exact3(ray.o), exact3(ray.d), exact3(pl.point), exact3(pl.normal));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  const double t = round_nearest(Q(x.num / x.den));
  return {x.side() < 0 ? Contact::behind : Contact::hit, t};
}

Hit<double> disk_kernel(const Ray<double>& ray, const Disk<double>& dk) {
  const QVec o = exact3(ray.o), center = exact3(dk.center), d = exact3(ray.d);
  const PlaneCrossing x = cross_plane(o, d, center, exact3(dk.normal));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  // den (P - center) = den (o - center) + num d, so |P - c|^2 vs r^2 <=> |that|^2 vs r^2 den^2.
  const QVec w = x.den * (o - center) + x.num * d;
  const Q r(dk.radius);
  const int outside = sign(Q(dot(w, w) - r * r * x.den * x.den));
  if (outside > 0) return {Contact::miss};
  const double t = round_nearest(Q(x.num / x.den));
  if (x.side() < 0) return {Contact::behind, t};
  return {outside == 0 ? Contact::rim : Contact::hit, t};
}

}  // namespace rayproof::certified::fallback
