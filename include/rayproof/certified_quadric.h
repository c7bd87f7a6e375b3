#pragma once
/// Certified ray/sphere and ray/ellipsoid filters (certified_filter.h). With e = o - center, the ray
/// gives a t^2 + 2 b t + c = 0 and the class follows from the signs of disc = b^2 - a c, c and b, as
/// in the exact method. disc is evaluated in its cancellation-free Lagrange form (Hearn & Baker's
/// perpendicular distance): sphere disc = (d.d) r^2 - |d x e|^2; ellipsoid (scaled by P = prod s_i^2)
/// disc = P (a - sum_i s_i^2 (d_j e_k - d_k e_j)^2). The roots come from the stable pair
/// q = -(b + sign(b) sqrt(disc)), q / a and c / q (Ray Tracing Gems ch. 7), each pinned to one ulp.
/// Undecided (nothing): a tangent or an origin on the surface that the arithmetic did not make
/// exactly zero, or a root not pinned.
#include "rayproof/certified_filter.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/sphere.h"

namespace rayproof::certified {

namespace detail {

/// Class and roots from a, b, c (a > 0) and sqrt_disc^2 = disc with sign s_disc decided by the caller.
[[nodiscard]] inline std::optional<Hit<double>> solve(Bounded a, Bounded b, Bounded c, Bounded disc,
                                                      Bounded sqrt_scale) {
  using H = Hit<double>;
  const auto s_disc = sign(disc);
  if (!s_disc) return std::nullopt;
  if (*s_disc < 0) return H{Contact::miss};
  const auto s_b = sign(b);
  if (*s_disc == 0) {  // double root -b / a: behind when b > 0
    if (!s_b) return std::nullopt;
    const auto t = pin(-b / a);
    if (!t) return std::nullopt;
    return H{*s_b > 0 ? Contact::behind : Contact::tangent, *t, *t};
  }
  // Two roots: their product has the sign of c, their sum the sign of -b.
  const auto s_c = sign(c);
  if (!s_c || *s_c == 0) return std::nullopt;  // origin on the surface: left to the exact method
  if (*s_c > 0 && !s_b) return std::nullopt;
  const Contact cls = *s_c < 0 ? Contact::inside : (*s_b > 0 ? Contact::behind : Contact::hit);
  // q = -(b + sign(b) sqrt(disc)) with no cancellation; q / a and c / q.
  const Bounded root = sqrt(disc) * sqrt_scale;
  const bool plus = b.v >= 0;
  const Bounded q = plus ? -(b + root) : root - b;
  if (!nonzero(q)) return std::nullopt;
  const auto r1 = pin(q / a), r2 = pin(c / q);
  if (!r1 || !r2) return std::nullopt;
  // plus: q < 0 and q / a is the lower root; otherwise q > 0 and q / a the upper one.
  return plus ? H{cls, *r1, *r2} : H{cls, *r2, *r1};
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> sphere(const Ray<double>& ray, const Sphere<double>& s) {
  using H = Hit<double>;
  if (!ray.valid() || !all_finite(s.center) || !std::isfinite(s.radius) || s.radius < 0) return H{Contact::invalid};
  if (s.radius == 0) return H{Contact::degenerate};
  if constexpr (!kFilterAvailable) return std::nullopt;
  const Vec3<Bounded> d = lift(ray.d), e = lift(ray.o) - lift(s.center);
  const Bounded r = s.radius, rr = r * r;
  const Bounded a = dot(d, d);
  // disc = a r^2 - |d x e|^2 (Lagrange's identity applied to b^2 - a c).
  const Vec3<Bounded> m = cross(d, e);
  return detail::solve(a, dot(d, e), dot(e, e) - rr, a * rr - dot(m, m), Bounded(1.0));
}

[[nodiscard]] inline std::optional<Hit<double>> ellipsoid(const Ray<double>& ray, const Ellipsoid<double>& el) {
  using H = Hit<double>;
  const Vec3<double>& s = el.semi_axes;
  if (!ray.valid() || !all_finite(el.center) || !all_finite(s) || s.x < 0 || s.y < 0 || s.z < 0)
    return H{Contact::invalid};
  if (s.x == 0 || s.y == 0 || s.z == 0) return H{Contact::degenerate};
  if constexpr (!kFilterAvailable) return std::nullopt;
  const Vec3<Bounded> d = lift(ray.d), e = lift(ray.o) - lift(el.center);
  // Squared semi-axes and weights w_i = prod_{j != i} s_j^2 (the equation times P = prod s_i^2).
  const Bounded q0 = Bounded(s.x) * Bounded(s.x), q1 = Bounded(s.y) * Bounded(s.y), q2 = Bounded(s.z) * Bounded(s.z);
  const Vec3<Bounded> w{q1 * q2, q0 * q2, q0 * q1};
  const Bounded a = dot(w, mul(d, d));
  const Bounded b = dot(w, mul(d, e));
  const Bounded c = dot(w, mul(e, e)) - q0 * w.x;
  // disc / P = a - sum_i s_i^2 (d x e)_i^2; sqrt(disc) = S sqrt(disc / P) with S = s0 s1 s2.
  const Vec3<Bounded> m = cross(d, e);
  const Bounded reduced = a - dot(Vec3<Bounded>{q0, q1, q2}, mul(m, m));
  const Bounded scale = Bounded(s.x) * Bounded(s.y) * Bounded(s.z);
  // The sign of disc is that of disc / P; solve uses disc only through its sign and sqrt.
  return detail::solve(a, b, c, reduced, scale);
}

}  // namespace rayproof::certified
