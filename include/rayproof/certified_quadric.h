#pragma once
/// Certified ray/sphere and ray/ellipsoid filters (certified_filter.h). With e = o - center, the ray
/// gives a t^2 + 2 b t + c = 0 and the class follows from the signs of disc = b^2 - a c, c and b, as
/// in the exact method. disc is evaluated in its cancellation-free Lagrange form (Hearn & Baker's
/// perpendicular distance): sphere disc = (d.d) r^2 - |d x e|^2; ellipsoid (scaled by P = prod s_i^2)
/// disc = P (a - sum_i s_i^2 (d_j e_k - d_k e_j)^2). The roots come from the stable pair
/// q = -(b + sign(b) sqrt(disc)), q / a and c / q (Ray Tracing Gems ch. 7), each pinned to one ulp.
/// Undecided (nothing): a tangent or an origin on the surface that the arithmetic did not make
/// exactly zero, or a root not pinned.
///
/// Stages (certified_stage.h): (1) signs in double with static error bounds and the roots in Wide
/// from a plain evaluation with the same bounds scaled by 2^-11; (2) exact signs of disc, c and b
/// with expansions: tangents (disc = 0, t = -b / a) and origins on the surface (c = 0, roots 0 and
/// -2b / a) are proven and pinned without GMP; (3) the running-error-bound filter below, for inputs
/// outside the exponent windows of stages 1 and 2.
#include "rayproof/certified_filter.h"
#include "rayproof/certified_fma.h"
#include "rayproof/certified_stage.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/sphere.h"

#include <type_traits>
#include <utility>

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


template <class W>
[[nodiscard]] inline Vec3<W> abs3(const Vec3<W>& v) {
  return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)};
}

/// a t^2 + 2 b t + c with disc = red * S^2, each value with an absolute error bound (static).
template <class W>
struct Quad {
  W a, b, c, red, ea, eb, ec, ered;
};

/// Overflow leaves a value or its bound infinite or NaN, which decides nothing (every bound contains
/// the magnitude of its value).
/// Sphere, W = double or Wide: a = d.d, b = d.e, c = e.e - r^2, red = a r^2 - |d x e|^2 (= disc), with
/// e = o - center rounded. Static bounds (gamma_k times the permanent, >= 2x slack; u = 2^-53 in
/// double, the same scaled by 2^-11 in Wide, u = 2^-64): a 3 roundings, b 4 (sum |d_i e_i|), c 6
/// (e.e + r^2). red: m_i = (d x e)_i has 3 roundings, |error| <= 2^-50 P_i with P_i = |d_j e_k| +
/// |d_k e_j|, so m_i^2 is off by <= 2 |m_i| 2^-50 P_i + (2^-50 P_i)^2, plus 6 roundings of the
/// magnitudes a r^2 + m.m + |red| (a linearised running bound: the cancellation inside m_i, a ray
/// aimed near the centre, would make the permanent bound hopeless).
template <class W>
[[nodiscard]] inline Quad<W> sphere_quad(const Ray<double>& ray, const Sphere<double>& s) {
  constexpr W k = std::is_same_v<W, double> ? W(1) : W(0x1p-11);
  const Vec3<W> d = ray.d.template cast<W>(), e = ray.o.template cast<W>() - s.center.template cast<W>();
  const W r = s.radius, a = dot(d, d), ee = dot(e, e), rr = r * r;
  const Vec3<W> m = cross(d, e), ad = abs3(d), ae = abs3(e), am = abs3(m);
  const Vec3<W> pm{ad.y * ae.z + ad.z * ae.y, ad.z * ae.x + ad.x * ae.z, ad.x * ae.y + ad.y * ae.x};
  const W pb = dot(ad, ae), mm = dot(m, m), red = a * rr - mm;
  const W ered = W(0x1p-49) * (a * rr + mm + std::fabs(red)) + W(0x1p-48) * dot(am, pm) + W(0x1p-98) * dot(pm, pm);
  // Underflow (double): at most 2^-1075 per product, amplified by at most a, r^2 or |m|: the eta terms.
  const W eta = std::is_same_v<W, double> ? W(0x1p-1000) : W(0);
  return {a, dot(d, e), ee - rr, red, k * W(0x1p-51) * a + eta, k * W(0x1p-50) * pb + eta,
          k * W(0x1p-50) * (ee + rr) + eta, k * ered + eta * (1 + a + rr + am.x + am.y + am.z)};
}

/// Ellipsoid (the equation times P = prod s_i^2, weights w_i = prod_{j != i} s_j^2): roundings per
/// path <= 7 (a), 8 (b, permanent sum w_i |d_i e_i|), 10 (c, sum w_i e_i^2 + P); red = a - sum q_i m_i^2
/// with the linearised bound of sphere_quad: 8 roundings of the magnitudes a + sum q_i m_i^2 + |red|,
/// plus q_i (2 |m_i| 2^-50 P_i + (2^-50 P_i)^2). Constants 2^-49, 2^-48, 2^-48, 2^-48 (>= 2.5x slack).
template <class W>
[[nodiscard]] inline Quad<W> ellipsoid_quad(const Ray<double>& ray, const Ellipsoid<double>& el) {
  constexpr W k = std::is_same_v<W, double> ? W(1) : W(0x1p-11);
  const Vec3<W> d = ray.d.template cast<W>(), e = ray.o.template cast<W>() - el.center.template cast<W>();
  const Vec3<W> s = el.semi_axes.template cast<W>();
  const Vec3<W> q = mul(s, s), w{q.y * q.z, q.x * q.z, q.x * q.y};
  const Vec3<W> m = cross(d, e), de = mul(d, e), ae = abs3(e), ad = abs3(d), am = abs3(m);
  const Vec3<W> pm{ad.y * ae.z + ad.z * ae.y, ad.z * ae.x + ad.x * ae.z, ad.x * ae.y + ad.y * ae.x};
  const W a = dot(w, mul(d, d)), ce = dot(w, mul(e, e)), p = q.x * w.x, qmm = dot(q, mul(m, m)), red = a - qmm;
  const W pb = dot(w, abs3(de));
  const W ered = W(0x1p-48) * (a + qmm + std::fabs(red) + dot(q, mul(am, pm))) + W(0x1p-98) * dot(q, mul(pm, pm));
  return {a, dot(w, de), ce - p, red, k * W(0x1p-49) * a, k * W(0x1p-48) * pb, k * W(0x1p-48) * (ce + p), k * ered};
}

/// The values of sphere_quad / ellipsoid_quad in Wide, with the double bounds scaled by 2^-11: the
/// permanents are the same to within a relative 2^-50, and every double constant has >= 2x slack
/// over gamma_k in Wide (for red: |m| <= |m_double| + 2^-50 P).
[[nodiscard]] inline Quad<Wide> scaled(const Quad<double>& x, Wide a, Wide b, Wide c, Wide red) {
  constexpr Wide k = 0x1p-11L;
  return {a, b, c, red, k * x.ea, k * x.eb, k * x.ec, k * x.ered};
}
[[nodiscard]] inline Quad<Wide> sphere_wide(const Ray<double>& ray, const Sphere<double>& s, const Quad<double>& x) {
  const Vec3<Wide> d = ray.d.cast<Wide>(), e = ray.o.cast<Wide>() - s.center.cast<Wide>();
  const Wide r = s.radius, a = dot(d, d);
  const Vec3<Wide> m = cross(d, e);
  return scaled(x, a, dot(d, e), dot(e, e) - r * r, a * (r * r) - dot(m, m));
}
[[nodiscard]] inline Quad<Wide> ellipsoid_wide(const Ray<double>& ray, const Ellipsoid<double>& el, const Quad<double>& x) {
  const Vec3<Wide> d = ray.d.cast<Wide>(), e = ray.o.cast<Wide>() - el.center.cast<Wide>();
  const Vec3<Wide> s = el.semi_axes.cast<Wide>();
  const Vec3<Wide> q = mul(s, s), w{q.y * q.z, q.x * q.z, q.x * q.y};
  const Vec3<Wide> m = cross(d, e);
  const Wide a = dot(w, mul(d, d));
  return scaled(x, a, dot(w, mul(d, e)), dot(w, mul(e, e)) - q.x * w.x, a - dot(q, mul(m, m)));
}

/// The two roots pinned from Wide values (red > 0, c != 0 known), sqrt(disc) = S sqrt(red) with S
/// rounded by at most 2 ulps of Wide.
[[nodiscard]] inline std::optional<Hit<double>> wide_roots(const Quad<Wide>& x, Wide S, Contact cls) {
  if (!(x.red > 2 * x.ered) || !(x.a > 2 * x.ea)) return std::nullopt;
  const Wide sq = std::sqrt(x.red);
  const Wide root = sq * S;
  const Wide eroot = (x.ered / sq + sq * 0x1p-63L) * S * (1 + 0x1p-60L) + root * 0x1p-61L;
  const bool plus = x.b >= 0;
  const Wide q = plus ? -(x.b + root) : root - x.b;
  const Wide eq = (x.eb + eroot) * (1 + 0x1p-60L) + std::fabs(q) * 0x1p-63L;
  if (!(std::fabs(q) > 2 * eq)) return std::nullopt;
  const Wide r1 = q / x.a, r2 = x.c / q;
  const Wide e1 = (eq + std::fabs(r1) * x.ea) / (x.a - x.ea) * (1 + 0x1p-40L) + std::fabs(r1) * 0x1p-63L;
  const Wide e2 = (x.ec + std::fabs(r2) * eq) / (std::fabs(q) - eq) * (1 + 0x1p-40L) + std::fabs(r2) * 0x1p-63L;
  const auto t1 = pin_wide(r1, e1), t2 = pin_wide(r2, e2);
  if (!t1 || !t2) return std::nullopt;
  // plus: q < 0 and q / a is the lower root; otherwise q > 0 and q / a the upper one.
  return plus ? Hit<double>{cls, *t1, *t2} : Hit<double>{cls, *t2, *t1};
}

/// Stage 1: the class from double signs, the roots from Wide (wide() gives the Wide Quad and S).
template <class F>
[[nodiscard]] inline std::optional<Hit<double>> solve_fast(const Quad<double>& x, F wide) {
  if (x.red < -x.ered) return Hit<double>{Contact::miss};
  if (!(x.red > x.ered)) return std::nullopt;
  const int sc = x.c > x.ec ? 1 : (x.c < -x.ec ? -1 : 0);
  const int sb = x.b > x.eb ? 1 : (x.b < -x.eb ? -1 : 0);
  if (sc == 0 || (sc > 0 && sb == 0)) return std::nullopt;
  if constexpr (!kFilterAvailable) return std::nullopt;
  const auto [qw, S] = wide();
  return wide_roots(qw, S, sc < 0 ? Contact::inside : (sb > 0 ? Contact::behind : Contact::hit));
}

/// Stage 2: exact signs (expansions a, b, c, red), as the exact method; the double root -b / a and the
/// root -2b / a of an origin on the surface pinned by the exact residual, other roots from Wide.
template <class F>
[[nodiscard]] inline std::optional<Hit<double>> solve_exact(const Expansion& a, const Expansion& b, const Expansion& c,
                                                             const Expansion& red, F wide) {
  using H = Hit<double>;
  if (a.bad || b.bad || c.bad || red.bad) return std::nullopt;
  const int sd = red.sign(), sb = b.sign(), sc = c.sign();
  if (sd < 0) return H{Contact::miss};
  if (sd == 0) {
    const auto t = pin_quotient(-b, a);
    if (!t) return std::nullopt;
    return H{sb > 0 ? Contact::behind : Contact::tangent, *t, *t};
  }
  if (sc == 0) {  // roots 0 and -2b / a, zeros signed as the exact method does
    const auto t = pin_quotient(-(b + b), a);
    if (!t) return std::nullopt;
    return sb > 0 ? H{Contact::inside, *t, -0.0} : H{Contact::hit, 0.0, *t};
  }
  if constexpr (!kFilterAvailable) return std::nullopt;
  const auto [qw, S] = wide();
  return wide_roots(qw, S, sc < 0 ? Contact::inside : (sb > 0 ? Contact::behind : Contact::hit));
}


/// A miss proven by the double stage with a bound cheaper than sphere_quad's (the ray's first test, so
/// generic misses pay little): red = a r^2 - |m|^2 (m = d x e, e = o - center rounded, as there).
/// sphere_quad's bound has 2^-48 sum |m_i| P_i + 2^-98 sum P_i^2 (P_i = |d_j e_k| + |d_k e_j|); with
/// |m_i| <= P_i (1 + 7u) and sum P_i^2 <= 2 sum_{j != k} d_j^2 e_k^2 (1 + 20u) <= 2 a (e.e) (1 + 20u),
/// both are below 2^-47 (1 + 2^-40) a (e.e), used as 2^-46 a (e.e); the other terms are sphere_quad's.
[[nodiscard, gnu::always_inline]] inline bool sphere_miss(const Ray<double>& ray, const Sphere<double>& s) {
  const Vec3<double>& d = ray.d;
  const Vec3<double> e = ray.o - s.center, m = cross(d, e);
  const double a = dot(d, d), ee = dot(e, e), rr = s.radius * s.radius, mm = dot(m, m), red = a * rr - mm;
  const double am = std::fabs(m.x) + std::fabs(m.y) + std::fabs(m.z);
  const double ered = 0x1p-49 * (a * rr + mm + std::fabs(red)) + 0x1p-46 * (a * ee) + 0x1p-1000 * (1 + a + rr + am);
  return red < -ered;
}

/// The exponent window in which the sphere's degree-4 quantities are exact as expansions (and as
/// double-double, certified_fma.h): every nonzero input in [2^-200, 2^200].
[[nodiscard]] inline bool sphere_in_window(const Ray<double>& ray, const Sphere<double>& s) {
  const Vec3<double>&o = ray.o, &d = ray.d, &c0 = s.center;
  return in_range<-200, 200>(o.x, o.y, o.z, d.x, d.y, d.z, c0.x, c0.y, c0.z, s.radius);
}

/// Stage 2 for spheres (in_range<-200, 200>, degree 4) and ellipsoids (checked by the caller), out of
/// line (expansions need a large stack frame, which the fast path should not pay for).
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> sphere_exact(const Ray<double>& ray, const Sphere<double>& s) {
  if (!sphere_in_window(ray, s)) return std::nullopt;
  auto wide = [&] { return std::pair{sphere_wide(ray, s, sphere_quad<double>(ray, s)), Wide(1)}; };
  const ExpVec3 d = exact3(ray.d), e = diff3(ray.o, s.center);
  const Expansion r(s.radius), rr = r * r, a = dot(d, d);
  const ExpVec3 m = cross(d, e);
  return solve_exact(a, dot(d, e), dot(e, e) - rr, a * rr - dot(m, m), wide);
}
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> ellipsoid_exact(const Ray<double>& ray,
                                                                              const Ellipsoid<double>& el) {
  const Vec3<double>& s = el.semi_axes;
  auto wide = [&] {
    return std::pair{ellipsoid_wide(ray, el, ellipsoid_quad<double>(ray, el)), Wide(s.x) * Wide(s.y) * Wide(s.z)};
  };
  const ExpVec3 d = exact3(ray.d), e = diff3(ray.o, el.center), sx = exact3(s);
  const ExpVec3 q{sx.x * sx.x, sx.y * sx.y, sx.z * sx.z};
  const ExpVec3 w{q.y * q.z, q.x * q.z, q.x * q.y};
  const Expansion a = dot(w, mul(d, d)), b = dot(w, mul(d, e)), c = dot(w, mul(e, e)) - q.x * w.x;
  const ExpVec3 m = cross(d, e);
  return solve_exact(a, b, c, a - dot(q, mul(m, m)), wide);
}

/// Stages 1 (double, then Wide), 2 (expansions) and 3 (running error bounds), out of line.
[[gnu::noinline]] inline std::optional<Hit<double>> sphere_rest(const Ray<double>& ray, const Sphere<double>& s) {
  const Quad<double> x = sphere_quad<double>(ray, s);
  auto wide = [&] { return std::pair{sphere_wide(ray, s, x), Wide(1)}; };
  if (auto h = solve_fast(x, wide)) return h;
  if (auto h = sphere_exact(ray, s)) return h;
  if constexpr (!kFilterAvailable) return std::nullopt;
  const Vec3<Bounded> d = lift(ray.d), e = lift(ray.o) - lift(s.center);
  const Bounded r = s.radius, rr = r * r;
  const Bounded a = dot(d, d);
  // disc = a r^2 - |d x e|^2 (Lagrange's identity applied to b^2 - a c).
  const Vec3<Bounded> m = cross(d, e);
  return solve(a, dot(d, e), dot(e, e) - rr, a * rr - dot(m, m), Bounded(1.0));
}

}  // namespace detail

/// Every result is a prvalue or a call's (copying a half-written optional cost store-forwarding stalls).
[[nodiscard]] inline std::optional<Hit<double>> sphere(const Ray<double>& ray, const Sphere<double>& s) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &d = ray.d, &c = s.center;
  if (!finite_bits(o.x, o.y, o.z, d.x, d.y, d.z, c.x, c.y, c.z, s.radius) || s.radius < 0 || is_zero(d))
    return H{Contact::invalid};
  if (s.radius == 0) return H{Contact::degenerate};
  // A miss the double stage proves costs no more; everything else goes to double-double with hardware
  // FMA first (certified_fma.h), then to the stages of sphere_rest for what that leaves.
  if (detail::sphere_miss(ray, s)) return H{Contact::miss};
#if RAYPROOF_FMA_PATH != 0
  if (dd::available() && detail::sphere_in_window(ray, s))
    return dd::sphere(ray, s, [&] { return detail::sphere_rest(ray, s); });
#endif
  return detail::sphere_rest(ray, s);
}

[[nodiscard]] inline std::optional<Hit<double>> ellipsoid(const Ray<double>& ray, const Ellipsoid<double>& el) {
  using H = Hit<double>;
  const Vec3<double>& s = el.semi_axes;
  if (!ray.valid() || !all_finite(el.center) || !all_finite(s) || s.x < 0 || s.y < 0 || s.z < 0)
    return H{Contact::invalid};
  if (s.x == 0 || s.y == 0 || s.z == 0) return H{Contact::degenerate};
  const Vec3<double>&o = ray.o, &dd = ray.d, &c0 = el.center;
  if (in_range<-110, 160>(o.x, o.y, o.z, dd.x, dd.y, dd.z, c0.x, c0.y, c0.z, s.x, s.y, s.z)) {
    const detail::Quad<double> x = detail::ellipsoid_quad<double>(ray, el);
    auto wide = [&] { return std::pair{detail::ellipsoid_wide(ray, el, x), Wide(s.x) * Wide(s.y) * Wide(s.z)}; };
    if (auto h = detail::solve_fast(x, wide)) return h;
    if (auto h = detail::ellipsoid_exact(ray, el)) return h;
  }
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
