#pragma once
/// Certified ray/plane and ray/disk filters (certified_filter.h), the predicates of the exact method
/// with error bounds: den = d . n (parallel / coplanar when exactly 0, by the sign of
/// num = (p - o) . n), t = num / den pinned to one ulp, and for the disk the sign of
/// |den (o - c) + num d|^2 - r^2 den^2, which is |P - c|^2 - r^2 scaled by den^2 (no division).
/// Undecided (nothing): a zero the arithmetic did not produce exactly, or t not pinned.
///
/// Stages (certified_stage.h): (1) num and den in double with static bounds (den: 3 roundings,
/// permanent sum |d_i n_i|; num: 4 roundings, sum |p_i - o_i| |n_i|), t in Wide with the bounds scaled
/// by 2^-11, the disk's rim sign in running-error arithmetic (BoundedT<double>) from them;
/// (2) expansions: den = 0, num = 0 (t = 0) and the rim (degree 6) decided exactly, t by the exact
/// residual; (3) the Wide running-error filter below, outside the exponent windows.
#include "rayproof/certified_filter.h"
#include "rayproof/certified_stage.h"
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


/// Stage 1 for plane and disk (in_range<-110, 160>): den and num decided nonzero, t pinned.
struct FastCrossing {
  double num, den, enum_, eden;
  double t;
};
[[nodiscard]] inline std::optional<FastCrossing> cross_fast(const Ray<double>& ray, const Vec3<double>& on,
                                                            const Vec3<double>& n) {
  const Vec3<double> a = on - ray.o;
  const double den = dot(ray.d, n), num = dot(a, n);
  const double pd = std::fabs(ray.d.x * n.x) + std::fabs(ray.d.y * n.y) + std::fabs(ray.d.z * n.z);
  const double pn = std::fabs(a.x * n.x) + std::fabs(a.y * n.y) + std::fabs(a.z * n.z);
  const double eden = 0x1p-51 * pd, enm = 0x1p-50 * pn;
  if (!(std::fabs(den) > 2 * eden) || !(std::fabs(num) > enm)) return std::nullopt;
  if constexpr (!kFilterAvailable) return std::nullopt;
  const Vec3<Wide> nw = n.cast<Wide>();
  const Wide dw = dot(ray.d.cast<Wide>(), nw), nm = dot(on.cast<Wide>() - ray.o.cast<Wide>(), nw);
  const Wide ed = Wide(eden) * 0x1p-11L, en = Wide(enm) * 0x1p-11L;
  if (!(std::fabs(dw) > 2 * ed)) return std::nullopt;
  const auto tt = pin_ratio(nm, dw, en, ed);
  if (!tt) return std::nullopt;
  return FastCrossing{num, den, enm, eden, *tt};
}

/// Stage 2: the exact crossing with expansions; t pinned when den != 0.
struct ExactCrossing {
  Expansion num, den;
  std::optional<double> t;
};
[[nodiscard]] inline ExactCrossing cross_exact(const Ray<double>& ray, const Vec3<double>& on, const Vec3<double>& n) {
  const ExpVec3 ne = exact3(n);
  ExactCrossing x{dot(diff3(on, ray.o), ne), dot(exact3(ray.d), ne), std::nullopt};
  if (!x.num.bad && !x.den.bad && x.den.n != 0) x.t = pin_quotient(x.num, x.den);
  return x;
}


/// Stage 2 for the disk, out of line: the exact crossing, and the sign of |w|^2 - r^2 den^2 (degree 6).
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> disk_exact(const Ray<double>& ray, const Disk<double>& dk) {
  using H = Hit<double>;
  const ExactCrossing x = cross_exact(ray, dk.center, dk.normal);
  if (x.num.bad || x.den.bad) return std::nullopt;
  if (x.den.n == 0) return H{x.num.n == 0 ? Contact::coplanar : Contact::parallel};
  const ExpVec3 w = x.den * diff3(ray.o, dk.center) + x.num * exact3(ray.d);
  const Expansion r(dk.radius);
  const Expansion ex = dot(w, w) - r * r * (x.den * x.den);
  if (ex.bad || any_bad(w)) return std::nullopt;
  if (ex.sign() > 0) return H{Contact::miss};
  if (!x.t) return std::nullopt;
  if (x.num.sign() * x.den.sign() < 0) return H{Contact::behind, *x.t};
  return H{ex.sign() == 0 ? Contact::rim : Contact::hit, *x.t};
}

[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> plane_exact(const Ray<double>& ray, const Plane<double>& pl) {
  using H = Hit<double>;
  const ExactCrossing x = cross_exact(ray, pl.point, pl.normal);
  if (x.num.bad || x.den.bad) return std::nullopt;
  if (x.den.n == 0) return H{x.num.n == 0 ? Contact::coplanar : Contact::parallel};
  if (!x.t) return std::nullopt;
  return H{x.num.sign() * x.den.sign() < 0 ? Contact::behind : Contact::hit, *x.t};
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> plane(const Ray<double>& ray, const Plane<double>& pl) {
  using H = Hit<double>;
  if (!ray.valid() || !all_finite(pl.point) || !all_finite(pl.normal)) return H{Contact::invalid};
  if (is_zero(pl.normal)) return H{Contact::degenerate};
  const Vec3<double>&o = ray.o, &d = ray.d, &p = pl.point, &n = pl.normal;
  if (in_range<-110, 160>(o.x, o.y, o.z, d.x, d.y, d.z, p.x, p.y, p.z, n.x, n.y, n.z)) {
    if (const auto f = detail::cross_fast(ray, p, n))
      return H{(f->num < 0) != (f->den < 0) ? Contact::behind : Contact::hit, f->t};
    if (auto h = detail::plane_exact(ray, pl)) return h;
  }
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
  const Vec3<double>&o = ray.o, &d = ray.d, &c = dk.center, &n = dk.normal;
  if (in_range<-110, 160>(o.x, o.y, o.z, d.x, d.y, d.z, c.x, c.y, c.z, n.x, n.y, n.z, dk.radius)) {
    if (const auto f = detail::cross_fast(ray, c, n)) {
      // |w|^2 - r^2 den^2, w = den (o - c) + num d, in running-error double arithmetic.
      using B = BoundedT<double>;
      const B den(f->den, f->eden), num(f->num, f->enum_), r = dk.radius;
      const Vec3<B> w = den * (lift<double>(o) - lift<double>(c)) + num * lift<double>(d);
      const auto outside = sign(dot(w, w) - r * r * (den * den));
      if (outside && *outside > 0) return H{Contact::miss};
      if (outside && *outside < 0) return H{(f->num < 0) != (f->den < 0) ? Contact::behind : Contact::hit, f->t};
    }
    if (auto h = detail::disk_exact(ray, dk)) return h;
  }
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
