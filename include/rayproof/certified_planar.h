#pragma once
/// Certified ray/plane and ray/disk filters (certified_filter.h), the predicates of the exact method
/// with error bounds: den = d . n (parallel / coplanar when exactly 0, by the sign of
/// num = (p - o) . n), t = num / den pinned to one ulp, and for the disk the sign of
/// |den (o - c) + num d|^2 - r^2 den^2, which is |P - c|^2 - r^2 scaled by den^2 (no division).
/// Undecided (nothing): a zero the arithmetic did not produce exactly, or t not pinned.
#include "rayproof/certified_filter.h"
#include "rayproof/disk.h"
#include "rayproof/plane.h"

namespace rayproof::certified {

namespace detail {

struct PlaneCrossing {
  Bounded num, den;
  std::optional<int> s_num, s_den;
};

inline PlaneCrossing cross_plane(const Ray<double>& ray, const Vec3<double>& on, const Vec3<double>& normal) {
  const Vec3<Bounded> n = lift(normal);
  PlaneCrossing x{dot(lift(on) - lift(ray.o), n), dot(lift(ray.d), n), {}, {}};
  x.s_num = sign(x.num);
  x.s_den = sign(x.den);
  return x;
}

/// parallel / coplanar when den is exactly 0; nothing when that or num's sign is undecided.
inline std::optional<Hit<double>> in_or_off_plane(const PlaneCrossing& x) {
  if (!x.s_num) return std::nullopt;
  return Hit<double>{*x.s_num == 0 ? Contact::coplanar : Contact::parallel};
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> plane(const Ray<double>& ray, const Plane<double>& pl) {
  using H = Hit<double>;
  if (!ray.valid() || !all_finite(pl.point) || !all_finite(pl.normal)) return H{Contact::invalid};
  if (is_zero(pl.normal)) return H{Contact::degenerate};
  if constexpr (!kFilterAvailable) return std::nullopt;
  const detail::PlaneCrossing x = detail::cross_plane(ray, pl.point, pl.normal);
  if (!x.s_den) return std::nullopt;
  if (*x.s_den == 0) return detail::in_or_off_plane(x);
  if (!x.s_num) return std::nullopt;
  const auto t = pin(x.num / x.den);
  if (!t) return std::nullopt;
  return H{*x.s_num * *x.s_den < 0 ? Contact::behind : Contact::hit, *t};
}

[[nodiscard]] inline std::optional<Hit<double>> disk(const Ray<double>& ray, const Disk<double>& dk) {
  using H = Hit<double>;
  if (!ray.valid() || !all_finite(dk.center) || !all_finite(dk.normal) || !std::isfinite(dk.radius) ||
      dk.radius < 0)
    return H{Contact::invalid};
  if (is_zero(dk.normal) || dk.radius == 0) return H{Contact::degenerate};
  if constexpr (!kFilterAvailable) return std::nullopt;
  const detail::PlaneCrossing x = detail::cross_plane(ray, dk.center, dk.normal);
  if (!x.s_den) return std::nullopt;
  if (*x.s_den == 0) return detail::in_or_off_plane(x);
  // den (P - c) = den (o - c) + num d; compare its square with r^2 den^2.
  const Vec3<Bounded> w = x.den * (lift(ray.o) - lift(dk.center)) + x.num * lift(ray.d);
  const Bounded r = dk.radius;
  const auto outside = sign(dot(w, w) - r * r * (x.den * x.den));
  if (!outside) return std::nullopt;
  if (*outside > 0) return H{Contact::miss};
  if (!x.s_num) return std::nullopt;
  const auto t = pin(x.num / x.den);
  if (!t) return std::nullopt;
  if (*x.s_num * *x.s_den < 0) return H{Contact::behind, *t};
  return H{*outside == 0 ? Contact::rim : Contact::hit, *t};
}

}  // namespace rayproof::certified
