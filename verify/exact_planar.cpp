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
io::CaseResult in_or_off_plane(const PlaneCrossing& x) {
  return {sign(x.num) == 0 ? Contact::coplanar : Contact::parallel, std::nullopt, std::nullopt};
}

}  // namespace

io::CaseResult exact_plane(const io::Case& c) {
  const PlaneCrossing x = cross_plane(point_at(c, 0), vector_at(c, 3), point_at(c, 6), vector_at(c, 9));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  const double t = round_nearest(x.num / x.den);
  return {x.side() < 0 ? Contact::behind : Contact::hit, t, std::nullopt};
}

io::CaseResult exact_disk(const io::Case& c) {
  const Point o = point_at(c, 0), center = point_at(c, 6);
  const Vector d = vector_at(c, 3);
  const PlaneCrossing x = cross_plane(o, d, center, vector_at(c, 9));
  if (sign(x.den) == 0) return in_or_off_plane(x);
  // den (P - center) = den (o - center) + num d, so |P - c|^2 vs r^2 <=> |that|^2 vs r^2 den^2.
  const Vector w = x.den * (o - center) + x.num * d;
  const Q r(c.v[12]);
  const int outside = sign(w * w - r * r * x.den * x.den);
  if (outside > 0) return {Contact::miss, std::nullopt, std::nullopt};
  const double t = round_nearest(x.num / x.den);
  if (x.side() < 0) return {Contact::behind, t, std::nullopt};
  return {outside == 0 ? Contact::rim : Contact::hit, t, std::nullopt};
}

}  // namespace rayproof::verify
