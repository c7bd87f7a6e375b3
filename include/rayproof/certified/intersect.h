#pragma once
/// The certified tier, one call per query: the exact class of docs/cases.md and t (and t2) within one
/// double ulp of the exact value, for a double-precision ray against a plane, sphere, ellipsoid,
/// box, disk or triangle; for triangles also the barycentrics b1, b2 within kBarycentricError.
///
/// Two levels:
///  - try_intersect (header-only, rayproof::core): the floating-point filters of certified_*.h.
///    Where they cannot decide (a sign their error bound cannot tell, a t they cannot pin to one
///    ulp, a coplanar range, a barycentric they cannot bound), the answer is std::nullopt:
///    *undecided*. A decided answer is final: intersect returns exactly that answer.
///  - intersect (compiled, link rayproof::certified: GMP and MPFR, no CGAL): try_intersect, then
///    the certified tier's exact fallback (GMP rationals, MPFR; src/exact/fallback.cpp: the exact
///    algorithm of rayproof/verify/exact.h, src/exact/algorithms.h, on gmpxx instead of CGAL's kernel)
///    for whatever it left undecided. Always decided.
///
/// What a decided answer guarantees (fields a class does not carry are NaN, as in rayproof/hit.h):
///  - contact: the class exact arithmetic on the given doubles gives (rayproof::exact::intersect).
///  - t, t2: each within one ulp of the correctly rounded exact value (equal to it, or a
///    neighbouring double). The fallback returns them correctly rounded.
///  - triangles, classes interior, edge, vertex and behind: b1 (weight of p1) and b2 (weight of p2)
///    of the plane point, each in [0, 1] and within kBarycentricError = 2^-50 (four ulps of 1) of
///    the exact value; for edge and vertex hits a barycentric that is exactly 0 is 0.0 and a vertex
///    hit's barycentric 1 is exactly 1.0 (proofs at the detail::triangle_barycentrics_* stages).
///    Other classes: NaN.
///
/// Thread safety: try_intersect and intersect keep no shared state; concurrent calls are safe. The
/// fallback count (fallback_count) is per thread.
#include <cmath>
#include <cstdint>
#include <optional>

#include "rayproof/box.h"
#include "rayproof/certified_box.h"
#include "rayproof/certified_planar.h"
#include "rayproof/certified_quadric.h"
#include "rayproof/certified_triangle.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified {

/// Bound on |b - exact b| for the barycentrics b1, b2 of a decided triangle contact.
inline constexpr double kBarycentricError = 0x1p-50;

namespace detail {

/// The last step of every barycentric stage: w[i] approximates b_i within 2^-50 (already in [0, 1]),
/// maybe_zero[i] says that b_i may be 0 (every b_i that is 0 has it set). An edge has exactly one
/// zero barycentric and a vertex two: when exactly that many are flagged they are the zero ones
/// (0.0; a vertex's third is then exactly 1.0); when more are flagged, false (undecided). Interior
/// and behind carry no zero count: the values stand as they are.
[[nodiscard]] inline bool finish_barycentrics(Contact contact, double (&w)[3], const bool (&maybe_zero)[3], double& b1,
                                              double& b2) {
  const int zeros = contact == Contact::edge ? 1 : (contact == Contact::vertex ? 2 : 0);
  if (zeros > 0) {
    if (maybe_zero[0] + maybe_zero[1] + maybe_zero[2] != zeros) return false;
    for (int i = 0; i < 3; ++i) {
      if (maybe_zero[i]) w[i] = 0.0;
      else if (zeros == 2) w[i] = 1.0;
    }
  }
  b1 = w[1];
  b2 = w[2];
  return true;
}

/// Barycentrics, stage A without FMA: plain Wide (x87, 64-bit significand, no overflow or underflow for these
/// degree-3 polynomials of doubles) with an a-priori bound. With a = p0 - o, b = p1 - o, c = p2 - o
/// and the edges e_0 = p2 - p1, e_1 = p0 - p2, e_2 = p1 - p0, all rounded in Wide, u_0 = d . (b x c)
/// = d . (b x e_0) (b x b = 0), u_1 = d . (c x e_1), u_2 = d . (a x e_2): the edge form's permanent
/// scales with distance x size instead of distance^2. At most 7 roundings per product path (2
/// subtractions of inputs, 2 products, 1 difference, 2 sums) and a permanent <= 2 |d|_1 |y|_inf
/// |z|_inf for u = d . (y x z), so |u - u^| <= 2 gamma_7 |d|_1 |y|_inf |z|_inf < 2^-60 |d|_1 |y|_inf
/// |z|_inf = e (2 gamma_7 = 14 * 2^-64 (1 + tiny) = 2^-60.19; the 14% left covers the norms taken of
/// rounded values and the rounding of e). den = u_0 + u_1 + u_2 (= d . n
/// exactly) adds two roundings: e_den = (e_0 + e_1 + e_2)(1 + 2^-60) + 2^-62 sum |u^_i|. For
/// |den^| > e_den, |u_i / den - u^_i / den^| <= (e_i + |u^_i / den^| e_den) / (|den^| - e_den), and
/// q_i = u^_i * fl(1 / den^) (two roundings) is within 2^-63 (1 + tiny) |q_i| of u^_i / den^, so
/// |u^_i / den^| <= (1 + 2^-62) |q_i|; with 2^-62 |q_i| for the roundings and all of it times
/// (1 + 2^-50) for the rounding of the bound itself, that is err_i. Accepted when err_i <= 2^-51 and |q_i| < 2: rounding q_i to double adds at
/// most 2^-53, so the double is within 2^-51 + 2^-53 < 2^-50 of b_i. The exact b_i of a contact is
/// in [0, 1], so clamping to [0, 1] only moves towards it. b_i may be 0 when |q_i| <= err_i.
[[gnu::noinline]] inline bool triangle_barycentrics_wide(const Ray<double>& ray, const Triangle<double>& tri, Contact contact,
                                                         double& b1, double& b2) {
  if constexpr (!kFilterAvailable) {
    return false;
  } else {
    const Vec3<Wide> o = ray.o.cast<Wide>(), d = ray.d.cast<Wide>();
    const Vec3<Wide> P0 = tri.p0.cast<Wide>(), P1 = tri.p1.cast<Wide>(), P2 = tri.p2.cast<Wide>();
    const Vec3<Wide> a = P0 - o, b = P1 - o, c = P2 - o;       // vertices from the origin
    const Vec3<Wide> e0 = P2 - P1, e1 = P0 - P2, e2 = P1 - P0;  // edges
    const Wide u[3] = {dot(d, cross(b, e0)), dot(d, cross(c, e1)), dot(d, cross(a, e2))};
    auto norm_inf = [](const Vec3<Wide>& v) {
      const Wide x = std::fabs(v.x), y = std::fabs(v.y), z = std::fabs(v.z), m = x > y ? x : y;
      return m > z ? m : z;
    };
    const Wide k = 0x1p-60L * (std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z));
    const Wide ma = norm_inf(a), mb = norm_inf(b), mc = norm_inf(c);
    const Wide e[3] = {k * mb * norm_inf(e0), k * mc * norm_inf(e1), k * ma * norm_inf(e2)};
    const Wide den = u[0] + u[1] + u[2];
    const Wide eden = (e[0] + e[1] + e[2]) * (1 + 0x1p-60L) + 0x1p-62L * (std::fabs(u[0]) + std::fabs(u[1]) + std::fabs(u[2]));
    const Wide gap = std::fabs(den) - eden;
    if (!(gap > 0)) return false;  // also NaN
    const Wide inv_den = 1 / den, inv_gap = 1 / gap;  // two divisions instead of six
    double w[3];
    bool maybe_zero[3];
    for (int i = 0; i < 3; ++i) {
      const Wide q = u[i] * inv_den, aq = std::fabs(q);
      const Wide err = ((e[i] + aq * (1 + 0x1p-62L) * eden) * inv_gap + 0x1p-62L * aq) * (1 + 0x1p-50L);
      if (!(err <= 0x1p-51L) || !(aq < 2)) return false;
      const double x = static_cast<double>(q);
      w[i] = x < 0 ? 0.0 : (x > 1 ? 1.0 : x + 0.0);
      maybe_zero[i] = aq <= err;
    }
    return finish_barycentrics(contact, w, maybe_zero, b1, b2);
  }
}

#if RAYPROOF_FMA_PATH != 0
/// u = d . (Y x E) in double-double with Y = v - o, E = e1 - e0 (exact two-doubles), and its bound
/// E_u = 2^-98 P (see triangle_barycentrics_dd).
[[gnu::always_inline]] RAYPROOF_FMA_TARGET inline void barycentric_volume_dd(const Vec3<double>& v, const Vec3<double>& e1,
                                                                           const Vec3<double>& e0, const Vec3<double>& o,
                                                                           const Vec3<double>& d, double& hi, double& lo,
                                                                           double& bound) {
  using dd::DD;
  const DD Y[3] = {dd::exact_diff(v.x, o.x), dd::exact_diff(v.y, o.y), dd::exact_diff(v.z, o.z)};
  const DD E[3] = {dd::exact_diff(e1.x, e0.x), dd::exact_diff(e1.y, e0.y), dd::exact_diff(e1.z, e0.z)};
  const DD n[3] = {dd::cross_component(Y[1].hi, Y[1].lo, Y[2].hi, Y[2].lo, E[1].hi, E[1].lo, E[2].hi, E[2].lo),
                   dd::cross_component(Y[2].hi, Y[2].lo, Y[0].hi, Y[0].lo, E[2].hi, E[2].lo, E[0].hi, E[0].lo),
                   dd::cross_component(Y[0].hi, Y[0].lo, Y[1].hi, Y[1].lo, E[0].hi, E[0].lo, E[1].hi, E[1].lo)};
  const double P = std::fabs(d.x) * (std::fabs(Y[1].hi * E[2].hi) + std::fabs(Y[2].hi * E[1].hi)) +
                   std::fabs(d.y) * (std::fabs(Y[2].hi * E[0].hi) + std::fabs(Y[0].hi * E[2].hi)) +
                   std::fabs(d.z) * (std::fabs(Y[0].hi * E[1].hi) + std::fabs(Y[1].hi * E[0].hi));
  const double dv[3] = {d.x, d.y, d.z};
  const DD ud = dd::dot_d_dd(dv, n);
  hi = ud.hi;
  lo = ud.lo;
  bound = 0x1p-98 * P;
}

/// Barycentrics, stage A with hardware FMA (dd::available()): the edge form of stage A below in
/// double-double (certified_fma.h). Inputs in_range<-200, 200> (as the expansions: no product or
/// error term underflows or overflows). Y = vertex - o and E = edge are exact two-doubles
/// (exact_diff); n = Y x E by cross_component and u_i = d . n by dot_d_dd: |u_i - (hi_i + lo_i)| <=
/// 140 u^2 P_i with u = 2^-53, P_i = sum_c |d_c| M_c, M_c = |Y_j E_k| + |Y_k E_j|; E_i = 2^-98 P_i
/// (140 u^2 = 2^-98.87; the slack covers P_i taken of high parts and rounded). Then, in double:
/// U_i = fl(hi_i + lo_i), |u_i - U_i| <= r_i = E_i + u |U_i|; den = sum u_i: the high parts summed
/// exactly (two_sum), the five low terms with four roundings (<= 4u L, L the sum of their
/// magnitudes), D = fl(s + low): |den - D| <= r_D = sum E_i + 4u L + u |D| (times 1 + 2^-50).
/// q_i = fl(U_i / D): |u_i / den - q_i| <= (r_i + |U_i / D| r_D) / (|D| - r_D) + u |q_i| = err_i,
/// computed with (1 + 2^-45) for its own roundings. Accepted when err_i <= 2^-51 and |q_i| < 2: q_i
/// is the double returned (clamped to [0, 1], which moves it towards b_i), so it is within
/// 2^-51 < 2^-50. For a generic contact err_i is about 3u |q_i| <= 2^-51.4: the test rarely fails.
[[gnu::noinline]] RAYPROOF_FMA_TARGET inline bool triangle_barycentrics_dd(const Ray<double>& ray, const Triangle<double>& tri,
                                                                            Contact contact, double& b1, double& b2) {
  const Vec3<double>&o = ray.o, &d = ray.d, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  if (!in_range<-200, 200>(o.x, o.y, o.z, d.x, d.y, d.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z))
    return false;
  constexpr double u = 0x1p-53;
  double U[3], r[3], hi[3], lo[3], Ei[3];
  barycentric_volume_dd(p1, p2, p1, o, d, hi[0], lo[0], Ei[0]);
  barycentric_volume_dd(p2, p0, p2, o, d, hi[1], lo[1], Ei[1]);
  barycentric_volume_dd(p0, p1, p0, o, d, hi[2], lo[2], Ei[2]);
  for (int i = 0; i < 3; ++i) {
    U[i] = hi[i] + lo[i];
    r[i] = Ei[i] + u * std::fabs(U[i]);
  }
  const double esum = Ei[0] + Ei[1] + Ei[2];
  const TwoTerm<double> s1 = two_sum(hi[0], hi[1]), s2 = two_sum(s1.hi, hi[2]);
  const double low = ((lo[0] + lo[1]) + (lo[2] + s1.lo)) + s2.lo;
  const double L = std::fabs(lo[0]) + std::fabs(lo[1]) + std::fabs(lo[2]) + std::fabs(s1.lo) + std::fabs(s2.lo);
  const double D = s2.hi + low;
  const double rD = (esum + 4 * u * L + u * std::fabs(D)) * (1 + 0x1p-50);
  const double gap = std::fabs(D) - rD;
  if (!(gap > 0) || !std::isfinite(D)) return false;
  double w[3];
  bool maybe_zero[3];
  for (int i = 0; i < 3; ++i) {
    const double q = U[i] / D, aq = std::fabs(q);
    const double err = ((r[i] + aq * (1 + 0x1p-50) * rD) / gap + u * aq) * (1 + 0x1p-45);
    if (!(err <= 0x1p-51) || !(aq < 2)) return false;
    w[i] = q < 0 ? 0.0 : (q > 1 ? 1.0 : q + 0.0);
    maybe_zero[i] = aq <= err;
  }
  return finish_barycentrics(contact, w, maybe_zero, b1, b2);
}
#endif

/// Barycentrics, stage B: u_i and den exactly in expansions (inputs in_range<-200, 200>, degree 3, as
/// triangle_expansion), so the zeros are exact; each nonzero b_i = u_i / den pinned by pin_quotient:
/// within 1.25 times the smaller gap next to the result, at most 1.25 * 2^-52 < 2^-50 for a result
/// below 2. Anything pin_quotient cannot pin (a quotient near underflow, an expansion out of room):
/// false.
[[gnu::noinline, gnu::cold]] inline bool triangle_barycentrics_expansion(const Ray<double>& ray, const Triangle<double>& tri,
                                                                         Contact contact, double& b1, double& b2) {
  const Vec3<double>&o = ray.o, &dd = ray.d, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  if (!in_range<-200, 200>(o.x, o.y, o.z, dd.x, dd.y, dd.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z))
    return false;
  const ExpVec3 d = exact3(ray.d), a = diff3(tri.p0, ray.o), b = diff3(tri.p1, ray.o), c = diff3(tri.p2, ray.o);
  const Expansion u[3] = {dot(d, cross(b, diff3(tri.p2, tri.p1))), dot(d, cross(c, diff3(tri.p0, tri.p2))),
                          dot(d, cross(a, diff3(tri.p1, tri.p0)))};  // the edge form of stage A, exactly
  const Expansion den = u[0] + u[1] + u[2];
  if (u[0].bad || u[1].bad || u[2].bad || den.bad || den.sign() == 0) return false;
  double w[3];
  bool maybe_zero[3];
  for (int i = 0; i < 3; ++i) {
    maybe_zero[i] = u[i].sign() == 0;
    w[i] = 0.0;
    // b0 is not returned, and a vertex's barycentrics are 0 and 1 (finish_barycentrics).
    if (maybe_zero[i] || i == 0 || contact == Contact::vertex) continue;
    const std::optional<double> q = pin_quotient(u[i], den);
    if (!q || !(std::fabs(*q) < 2)) return false;
    w[i] = *q < 0 ? 0.0 : (*q > 1 ? 1.0 : *q + 0.0);
  }
  return finish_barycentrics(contact, w, maybe_zero, b1, b2);
}

/// Barycentrics of a triangle contact whose class the filter has decided (interior, edge, vertex or
/// behind; d . n != 0): stage A in double-double where dd::available(), stage A in Wide (also for
/// inputs outside the exponent window of the others), then stage B; false (undecided) when none
/// can bound them.
/// The exact barycentrics are u_i / den (certified_triangle.h), each in [0, 1] for these classes.
inline bool triangle_barycentrics(const Ray<double>& ray, const Triangle<double>& tri, Contact contact, double& b1,
                                  double& b2) {
#if RAYPROOF_FMA_PATH != 0
  if (dd::available() && triangle_barycentrics_dd(ray, tri, contact, b1, b2)) return true;
#endif
  // Wide also covers inputs outside the exponent window of the double-double and expansion stages.
  return triangle_barycentrics_wide(ray, tri, contact, b1, b2) ||
         triangle_barycentrics_expansion(ray, tri, contact, b1, b2);
}

}  // namespace detail

/// Header-only, rayproof::core: the filter's answer, or std::nullopt (undecided).
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Plane<double>& p) {
  return plane(ray, p);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Sphere<double>& s) {
  return sphere(ray, s);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  return ellipsoid(ray, e);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Box<double>& b) {
  return box(ray, b);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Disk<double>& dk) {
  return disk(ray, dk);
}
[[nodiscard]] inline std::optional<TriangleHit<double>> try_intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  const std::optional<Hit<double>> h = triangle(ray, tri);
  if (!h) return std::nullopt;
  TriangleHit<double> out{h->contact, h->t, h->t2};
  switch (h->contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex: case Contact::behind:
      if (!detail::triangle_barycentrics(ray, tri, h->contact, out.b1, out.b2)) return std::nullopt;
      break;
    default:
      break;
  }
  return out;
}

/// Compiled, rayproof::certified: always decided (the exact fallback, GMP, when the filter is not).
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& plane);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& sphere);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& ellipsoid);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& box);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& disk);
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& triangle);

/// Calls of intersect on the calling thread, since it started, that needed the exact fallback.
[[nodiscard]] std::uint64_t fallback_count();

}  // namespace rayproof::certified
