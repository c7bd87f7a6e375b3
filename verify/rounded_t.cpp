// round_t (verify/rounded_t.h): the correctly rounded t of a ray crossing a triangle's plane.
#include "verify/rounded_t.h"

#include <bit>
#include <cmath>
#include <cstdint>

#include "rayproof/certified_expansion.h"
#include "rayproof/certified_filter.h"
#include "rayproof/float_util.h"

namespace rayproof::verify {

std::optional<double> round_t(const Ray<double>& r, const Triangle<double>& tri, double t0) {
  using certified::Bounded;
  using certified::Expansion;
  const double at = std::fabs(t0);
  if (!(at > 0x1p-200 && at < 0x1p200)) return std::nullopt;
  if (!certified::in_range<-150, 150>(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, tri.p0.x, tri.p0.y, tri.p0.z,
                                      tri.p1.x, tri.p1.y, tri.p1.z, tri.p2.x, tri.p2.y, tri.p2.z))
    return std::nullopt;
  // First in Wide with running error bounds (certified_filter.h); the expansions only where that
  // cannot tell the sign.
  const Vec3<Bounded> p0 = certified::lift(tri.p0);
  const Vec3<Bounded> nb = cross(certified::lift(tri.p1) - p0, certified::lift(tri.p2) - p0);
  const Bounded Nb = dot(p0 - certified::lift(r.o), nb), Db = dot(certified::lift(r.d), nb);
  std::optional<int> sdb = certified::kFilterAvailable ? certified::sign(Db) : std::nullopt;
  std::optional<Expansion> N, D;
  auto exact_parts = [&] {
    if (N) return;
    const certified::ExpVec3 e1 = certified::diff3(tri.p1, tri.p0), e2 = certified::diff3(tri.p2, tri.p0);
    const certified::ExpVec3 n = cross(e1, e2);
    N = dot(certified::diff3(tri.p0, r.o), n);
    D = dot(certified::exact3(r.d), n);
  };
  // side(lo, hi): sign of t - (lo + hi) / 2 for adjacent doubles lo < hi (exact t = N / D).
  auto side = [&](double lo, double hi) -> std::optional<int> {
    const double half = (hi - lo) * 0.5;  // exact: adjacent normal doubles
    if (sdb && *sdb != 0) {
      const auto sb = certified::sign(Nb - Bounded(lo) * Db - Bounded(half) * Db);
      if (sb) return *sb * *sdb;
    }
    exact_parts();
    if (N->bad || D->bad || D->n == 0) return std::nullopt;
    Expansion m(lo);
    m.grow(half);
    const Expansion sx = *N - m * *D;
    if (sx.bad) return std::nullopt;
    return sx.sign() * D->sign();
  };
  const double lo = next_down(t0), hi = next_up(t0);
  const auto up = side(t0, hi);
  if (!up) return std::nullopt;
  if (*up > 0) return hi;  // t above the midpoint to next: next (t0 is within 1 ulp)
  if (*up == 0) return (std::bit_cast<std::uint64_t>(hi) & 1) ? t0 : hi;  // tie: even
  const auto down = side(lo, t0);
  if (!down) return std::nullopt;
  if (*down < 0) return lo;
  if (*down == 0) return (std::bit_cast<std::uint64_t>(lo) & 1) ? t0 : lo;
  return t0;
}

}  // namespace rayproof::verify
