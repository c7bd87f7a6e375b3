#pragma once
/// Certified ray/triangle filter (certified_filter.h): the predicates of the exact method evaluated
/// with error bounds. n = (p1-p0) x (p2-p0) decides degeneracy; den = d . n decides parallel /
/// coplanar; u_i = det(d, p_j - o, p_k - o) (edges p1p2, p2p0, p0p1, summing to den) give the
/// barycentric signs; num = (p0 - o) . n the side of t = num / den. Returns the exact class and t
/// within one double ulp, or nothing (undecided: a sign the bound cannot tell, an exact zero the
/// arithmetic did not produce exactly, a coplanar range, or t not pinned to one ulp). The signs are
/// tried in double first (with an underflow term), then in Wide; t is always computed in Wide.
#include "rayproof/certified_filter.h"
#include "rayproof/hit.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified {

namespace detail {

/// The class from the signs of the predicates evaluated in W (double: the quick stage; Wide: the
/// second stage), or nothing when a sign is undecided or the ray is coplanar (a range is needed).
template <class W>
[[nodiscard]] std::optional<Contact> triangle_class(const Ray<double>& ray, const Triangle<double>& tri) {
  using B = BoundedT<W>;
  const Vec3<B> o = lift<W>(ray.o), d = lift<W>(ray.d);
  const Vec3<B> p0 = lift<W>(tri.p0), p1 = lift<W>(tri.p1), p2 = lift<W>(tri.p2);
  // Normal: degenerate only when all three components are exactly 0.
  const Vec3<B> n = cross(p1 - p0, p2 - p0);
  const auto nx = sign(n.x), ny = sign(n.y), nz = sign(n.z);
  if (nx == 0 && ny == 0 && nz == 0) return Contact::degenerate;
  if (!(nx.value_or(0) || ny.value_or(0) || nz.value_or(0))) return std::nullopt;
  // Vertices relative to the origin; num = (p0 - o) . n decides the side of t.
  const Vec3<B> a = p0 - o, b = p1 - o, c = p2 - o;
  const auto s_num = sign(dot(a, n));
  // den = d . n: zero means parallel (num != 0) or coplanar (a range: left to the exact method).
  const auto s_den = sign(dot(d, n));
  if (!s_den) return std::nullopt;
  if (*s_den == 0) {
    if (s_num && *s_num != 0) return Contact::parallel;
    return std::nullopt;
  }
  // Barycentric signs: sign(u_i) * sign(den); a decided negative one is a miss on its own.
  const auto u0 = sign(dot(d, cross(b, c)));
  const auto u1 = sign(dot(d, cross(c, a)));
  const auto u2 = sign(dot(d, cross(a, b)));
  const int sd = *s_den;
  if ((u0 && *u0 * sd < 0) || (u1 && *u1 * sd < 0) || (u2 && *u2 * sd < 0)) return Contact::miss;
  if (!u0 || !u1 || !u2 || !s_num) return std::nullopt;
  if (*s_num * sd < 0) return Contact::behind;
  const int zeros = (*u0 == 0) + (*u1 == 0) + (*u2 == 0);
  return zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
}

/// t = ((p0 - o) . n) / (d . n) in Wide, pinned to one ulp (d . n known nonzero).
[[nodiscard]] inline std::optional<double> triangle_t(const Ray<double>& ray, const Triangle<double>& tri) {
  const Vec3<Bounded> p0 = lift(tri.p0);
  const Vec3<Bounded> n = cross(lift(tri.p1) - p0, lift(tri.p2) - p0);
  const Bounded den = dot(lift(ray.d), n);
  if (!nonzero(den)) return std::nullopt;
  return pin(dot(p0 - lift(ray.o), n) / den);
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> triangle(const Ray<double>& ray, const Triangle<double>& tri) {
  using H = Hit<double>;
  if (!ray.valid() || !triangle_finite(tri)) return H{Contact::invalid};
  if constexpr (!kFilterAvailable) return std::nullopt;
  // Signs in double first (cheap, decides generic misses), then in Wide.
  auto cls = detail::triangle_class<double>(ray, tri);
  if (!cls) cls = detail::triangle_class<Wide>(ray, tri);
  if (!cls) return std::nullopt;
  if (*cls == Contact::degenerate || *cls == Contact::parallel || *cls == Contact::miss) return H{*cls};
  const auto t = detail::triangle_t(ray, tri);
  if (!t) return std::nullopt;
  return H{*cls, *t};
}

}  // namespace rayproof::certified
