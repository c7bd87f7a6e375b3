#pragma once
/// Certified ray/triangle filter (certified_filter.h): the predicates of the exact method evaluated
/// with error bounds. n = (p1-p0) x (p2-p0) decides degeneracy; den = d . n decides parallel /
/// coplanar; u_i = det(d, p_j - o, p_k - o) (edges p1p2, p2p0, p0p1, summing to den) give the
/// barycentric signs; num = (p0 - o) . n the side of t = num / den. Returns the exact class and t
/// within one double ulp, or nothing (undecided: a sign the bound cannot tell, an exact zero the
/// arithmetic did not produce exactly, a coplanar range, or t not pinned to one ulp). The signs are
/// tried in stages (certified_stage.h): (1) double with static error bounds and t pinned from
/// double-double (certified_fma.h: compiled for FMA and AVX2, chosen at run time; the stage itself is
/// cloned for that target so t is inlined) or else from Wide; then, with FMA, the double-double
/// signs of triangle_near; (2) exact signs and t with expansions (edges, vertices, parallel rays and
/// degenerate triangles proven without GMP); (3) the running-error-bound (midpoint-radius) filters
/// below, in double then Wide, for inputs outside the exponent window of stages 1 and 2.
#include "rayproof/certified_filter.h"
#include "rayproof/certified_fma.h"
#include "rayproof/certified_stage.h"
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

/// The coplanar range (stage 2, inputs in_range<-70, 120>: the comparisons below have degree 8), as
/// the exact method clips it: edge j -> k keeps alpha + t beta >= 0 with alpha = det(e, o - p_j, n),
/// beta = det(e, d, n); bounds -alpha / beta are exact fractions p / q (q > 0), compared by
/// p1 q2 - p2 q1, and pinned by the exact residual.
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> triangle_coplanar(const Ray<double>& ray,
                                                                                const Triangle<double>& tri,
                                                                                const ExpVec3& n) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &dd = ray.d, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  if (!in_range<-70, 120>(o.x, o.y, o.z, dd.x, dd.y, dd.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z))
    return std::nullopt;
  struct Frac {
    Expansion p, q;  // q > 0
  };
  bool bad = false;  // a comparison ran out of room: its sign is unknown
  auto less = [&bad](const Frac& a, const Frac& b) {
    const Expansion z = a.p * b.q - b.p * a.q;
    bad = bad || z.bad;
    return z.sign() < 0;
  };
  const Vec3<double>* p[3] = {&tri.p0, &tri.p1, &tri.p2};
  const ExpVec3 d = exact3(ray.d);
  Frac lo{Expansion(), Expansion(1.0)};
  std::optional<Frac> hi;
  for (int j = 0; j < 3; ++j) {
    const ExpVec3 e = diff3(*p[(j + 1) % 3], *p[j]);
    const Expansion alpha = dot(e, cross(diff3(ray.o, *p[j]), n)), beta = dot(e, cross(d, n));
    if (alpha.bad || beta.bad) return std::nullopt;
    if (beta.sign() == 0) {
      if (alpha.sign() < 0) return H{Contact::coplanar};  // outside this edge's line: no range
      continue;
    }
    const Frac bound = beta.sign() > 0 ? Frac{-alpha, beta} : Frac{alpha, -beta};
    if (beta.sign() > 0) {
      if (less(lo, bound)) lo = bound;
    } else if (!hi || less(bound, *hi)) {
      hi = bound;
    }
  }
  const bool empty = !hi || less(*hi, lo);
  if (bad) return std::nullopt;
  if (empty) return H{Contact::coplanar};
  const auto t0 = pin_quotient(lo.p, lo.q), t1 = pin_quotient(hi->p, hi->q);
  if (!t0 || !t1) return std::nullopt;
  return H{Contact::coplanar, *t0, *t1};
}

/// Stage 2 (inputs in_range<-200, 200>, degree 3): the predicates of the exact method in expansions.
/// Everything but a coplanar ray (a range) and a t the residual cannot pin is decided.
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> triangle_expansion(const Ray<double>& ray, const Triangle<double>& tri) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &dd = ray.d, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  if (!in_range<-200, 200>(o.x, o.y, o.z, dd.x, dd.y, dd.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z))
    return std::nullopt;
  const ExpVec3 n = cross(diff3(tri.p1, tri.p0), diff3(tri.p2, tri.p0));
  if (any_bad(n)) return std::nullopt;
  if (is_zero(n)) return H{Contact::degenerate};
  const ExpVec3 d = exact3(ray.d), a = diff3(tri.p0, ray.o), b = diff3(tri.p1, ray.o), c = diff3(tri.p2, ray.o);
  const Expansion den = dot(d, n), num = dot(a, n);
  if (den.bad || num.bad) return std::nullopt;
  const int sd = den.sign();
  if (sd == 0) {
    if (num.sign() != 0) return H{Contact::parallel};
    return triangle_coplanar(ray, tri, n);
  }
  const Expansion u0 = dot(d, cross(b, c)), u1 = dot(d, cross(c, a));
  const Expansion u2 = den - u0 - u1;
  if (u0.bad || u1.bad || u2.bad) return std::nullopt;
  const int s0 = u0.sign() * sd, s1 = u1.sign() * sd, s2 = u2.sign() * sd;
  if (s0 < 0 || s1 < 0 || s2 < 0) return H{Contact::miss};
  const auto t = pin_quotient(num, den);
  if (!t) return std::nullopt;
  if (num.sign() * sd < 0) return H{Contact::behind, *t};
  const int zeros = (s0 == 0) + (s1 == 0) + (s2 == 0);
  return H{zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex), *t};
}

/// The stages after the double one (out of line): double-double near an edge, a vertex or the plane,
/// the expansions, the running error bounds.
[[gnu::noinline]] inline std::optional<Hit<double>> triangle_rest(const Ray<double>& ray, const Triangle<double>& tri) {
  using H = Hit<double>;
#if RAYPROOF_FMA_PATH != 0
  if (dd::available())  // near an edge, a vertex or the plane: double-double before the expansions
    if (auto h = dd::triangle_near(ray, tri)) return h;
#endif
  if (auto h = triangle_expansion(ray, tri)) return h;
  if constexpr (!kFilterAvailable) return std::nullopt;
  // Stage 3: running error bounds, in double first (cheap, decides generic misses), then in Wide.
  auto cls = triangle_class<double>(ray, tri);
  if (!cls) cls = triangle_class<Wide>(ray, tri);
  if (!cls) return std::nullopt;
  if (*cls == Contact::degenerate || *cls == Contact::parallel || *cls == Contact::miss) return H{*cls};
  const auto t = triangle_t(ray, tri);
  if (!t) return std::nullopt;
  return H{*cls, *t};
}

/// Stage 1. With a, b, c = p_i - o (rounded), the signed volumes u0 = (d x b) . c, u1 = (d x c) . a,
/// u2 = (d x a) . b have at most 7 roundings per path and a permanent <= 2 |d|_1 |b|_inf |c|_inf, so
/// |error| <= gamma_7 * that <= 2^-49 |d|_1 |b|_inf |c|_inf; underflow adds at most 2^-1075 per product,
/// amplified by |c|_inf at most: 2^-1000 (|c|_inf + 1) covers it (a normal number: subnormal
/// arithmetic would trap into microcode). Overflow leaves den or a bound not
/// finite: undecided. den = u0 + u1 + u2. Decides miss, and interior / behind with t pinned in
/// double-double (kFma: the clone compiled for FMA and AVX2) or in Wide. What it cannot decide it
/// hands to next() (the later stages), whose result is returned as is.
template <bool kFma, class Next>
[[gnu::always_inline]] inline std::optional<Hit<double>> triangle_stage1(const Ray<double>& ray, const Triangle<double>& tri,
                                                                        Next next) {
  using H = Hit<double>;
  const Vec3<double>& o = ray.o;
  const Vec3<double>& d = ray.d;
  const Vec3<double> a = tri.p0 - o, b = tri.p1 - o, c = tri.p2 - o;
  const double u0 = dot(cross(d, b), c), u1 = dot(cross(d, c), a), u2 = dot(cross(d, a), b);
  // Plain comparisons, not std::fmax (a libm call without -ffast-math); the inputs are finite.
  auto norm_inf = [](const Vec3<double>& v) {
    const double x = std::fabs(v.x), y = std::fabs(v.y), z = std::fabs(v.z), m = x > y ? x : y;
    return m > z ? m : z;
  };
  const double d1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  // k = 2^-49 |d|_1 must not underflow: at |d|_1 < 2^-1025 it became 0 and the bounds lost their
  // main term (a false interior found by fuzz_kernels, d ~ 1e-312). From 2^-960 on, k >= 2^-1009 is
  // normal and k f g loses at most 2^-1075 g to underflow, inside 2^-1000 (g + 1). Rays that short
  // go to the later stages.
  if (!(d1 >= 0x1p-960)) return next();
  const double ma = norm_inf(a), mb = norm_inf(b), mc = norm_inf(c), k = 0x1p-49 * d1;
  const double e0 = k * mb * mc + 0x1p-1000 * (mc + 1), e1 = k * mc * ma + 0x1p-1000 * (ma + 1),
               e2 = k * ma * mb + 0x1p-1000 * (mb + 1);
  const double den = u0 + u1 + u2;
  // Two more roundings: 2u of the magnitudes (with slack).
  const double eden = (e0 + e1 + e2) * (1 + 0x1p-50) + 0x1p-51 * (std::fabs(u0) + std::fabs(u1) + std::fabs(u2));
  if (!(std::fabs(den) > eden) || !(eden < 0x1p1020)) return next();  // parallel, coplanar, ...
  // den != 0, so n != 0: a barycentric of the opposite sign is a miss.
  const bool neg0 = den > 0 ? u0 < -e0 : u0 > e0, neg1 = den > 0 ? u1 < -e1 : u1 > e1,
             neg2 = den > 0 ? u2 < -e2 : u2 > e2;
  if (neg0 || neg1 || neg2) return H{Contact::miss};
  if (!(std::fabs(u0) > e0 && std::fabs(u1) > e1 && std::fabs(u2) > e2)) return next();  // maybe 0
  // Interior or behind: t = ((p0 - o) . n) / (d . n), n = (p1 - p0) x (p2 - p0).
#if RAYPROOF_FMA_PATH != 0
  if constexpr (kFma) {  // t in double-double (certified_fma.h); its sign is that of t
    const auto tt = dd::triangle_t_stage1(ray, tri);
    if (!tt) return next();
    return H{*tt < 0 ? Contact::behind : Contact::interior, *tt};
  }
#endif
  if constexpr (kFma || !kFilterAvailable) return next();
  // t plain in Wide: at most 8 roundings per path (gamma_8 = 2^-61); permanents sum_i |x_i| pn_i with
  // pn_i = |f1_j f2_k| + |f1_k f2_j| (x = p0 - o or d), used with 2^-60 (2x slack, ample for their
  // rounding in double).
  const Vec3<double> pn = cross_permanent(tri.p1 - tri.p0, tri.p2 - tri.p0);
  // (2^-1000 (|x|_1 + 1) covers underflow in these double products; Wide itself cannot underflow.)
  const double a1 = std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z);
  const Wide en = 0x1p-60 * (std::fabs(a.x) * pn.x + std::fabs(a.y) * pn.y + std::fabs(a.z) * pn.z) + 0x1p-1000 * (a1 + 1),
             ed = 0x1p-60 * (std::fabs(d.x) * pn.x + std::fabs(d.y) * pn.y + std::fabs(d.z) * pn.z) + 0x1p-1000 * (d1 + 1);
  const Vec3<Wide> P0 = tri.p0.cast<Wide>();
  const Vec3<Wide> n = cross(tri.p1.cast<Wide>() - P0, tri.p2.cast<Wide>() - P0);
  const Wide num = dot(P0 - o.cast<Wide>(), n), dn = dot(d.cast<Wide>(), n);
  // The sign of num (the side of t) and a den clear of zero, then t pinned by its residual.
  if (!(std::fabs(dn) > 2 * ed) || !(std::fabs(num) > en)) return next();  // t = 0 or unclear
  const auto tt = pin_ratio(num, dn, en, ed);
  if (!tt) return next();
  return H{(num < 0) != (dn < 0) ? Contact::behind : Contact::interior, *tt};
}

#if RAYPROOF_FMA_PATH != 0
/// Stage 1 compiled for FMA, with the double-double t inlined (no call between the class and t).
template <class Next>
[[gnu::noinline, gnu::flatten]] RAYPROOF_FMA_TARGET std::optional<Hit<double>> triangle_fast_fma(const Ray<double>& ray,
                                                                                 const Triangle<double>& tri, Next next) {
  return triangle_stage1<true>(ray, tri, next);
}
#endif

/// Stage 1: the FMA build of it when dd::available() (FMA, and AVX2 on x86), else the x87 one.
template <class Next>
[[nodiscard]] std::optional<Hit<double>> triangle_fast(const Ray<double>& ray, const Triangle<double>& tri, Next next) {
#if RAYPROOF_FMA_PATH != 0
  if (dd::available()) return triangle_fast_fma(ray, tri, next);
#endif
  return triangle_stage1<false>(ray, tri, next);
}

}  // namespace detail

/// Every result is a prvalue or a call's (copying a half-written optional cost store-forwarding stalls).
[[nodiscard]] inline std::optional<Hit<double>> triangle(const Ray<double>& ray, const Triangle<double>& tri) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &d = ray.d, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  if (!finite_bits(o.x, o.y, o.z, d.x, d.y, d.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z) || is_zero(d))
    return H{Contact::invalid};  // ray.valid() and triangle_finite() in one branch
  return detail::triangle_fast(ray, tri, [&] { return detail::triangle_rest(ray, tri); });
}

}  // namespace rayproof::certified
