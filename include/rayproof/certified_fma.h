#pragma once
/// Double-double evaluation with hardware FMA for the certified tier's t (certified_stage.h, stage 1).
/// The x87 extended format pins t too (certified_filter.h), but its eight-register stack spills
/// 80-bit values to memory around every product, and a triangle's t then costs about as many
/// instructions as the whole class decision. With FMA, a product of doubles is exact as two doubles
/// (p = ab rounded, e = fma(a, b, -p)), so the quantities t is a quotient of can be carried with an
/// error of order 2^-100 of their magnitude in SSE registers.
///
/// The build does not assume FMA (no -mfma): on x86 the functions here are compiled for the FMA and
/// AVX2 target (GCC / Clang `target("avx2,fma")`) and called only when the CPU has both, checked once
/// at run time (`available()`); elsewhere `available()` is false unless the compiler targets FMA
/// anyway, and the callers keep the x87 path.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

#include "rayproof/certified_dd.h"
#include "rayproof/certified_stage.h"
#include "rayproof/float_util.h"
#include "rayproof/hit.h"
#include "rayproof/sphere.h"
#include "rayproof/ray.h"
#include "rayproof/triangle_common.h"

#if defined(__FMA__) || defined(__FP_FAST_FMA)
#define RAYPROOF_FMA_TARGET
#define RAYPROOF_FMA_PATH 1
#elif defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define RAYPROOF_FMA_TARGET __attribute__((target("avx2,fma")))
#define RAYPROOF_FMA_PATH 2
#else
#define RAYPROOF_FMA_PATH 0
#endif

// On x86 the triangle's t runs three lanes at a time in AVX2 (every x86 CPU with FMA3 but the AMD
// Piledriver / Steamroller generations has AVX2; those take the x87 path, see available()).
#if RAYPROOF_FMA_PATH == 2 || (RAYPROOF_FMA_PATH == 1 && defined(__AVX2__))
#define RAYPROOF_DD_AVX2 1
#include <immintrin.h>
#else
#define RAYPROOF_DD_AVX2 0
#endif

namespace rayproof::certified::dd {

/// True when the functions below run on hardware FMA (a libm fma would be correct but slow; on x86
/// with AVX2 as well, which the triangle's t uses) and the environment variable
/// RAYPROOF_CERTIFIED_NO_FMA is unset (it selects the x87 path, for tests and for comparison). Read once.
[[nodiscard]] inline bool available() {
#if RAYPROOF_FMA_PATH == 0
  return false;
#else
#if RAYPROOF_FMA_PATH == 1
  static const bool cpu = true;
#else
  static const bool cpu = (__builtin_cpu_init(), __builtin_cpu_supports("fma") != 0 && __builtin_cpu_supports("avx2") != 0);
#endif
  static const bool ok = cpu && std::getenv("RAYPROOF_CERTIFIED_NO_FMA") == nullptr;
  return ok;
#endif
}

#if RAYPROOF_FMA_PATH != 0

// DD (certified_dd.h): hi + lo, not normalised here (lo need not be below half an ulp of hi).

/// Exact a - b as two doubles (Knuth's two-sum; no overflow assumed: an overflow shows up as a
/// non-finite value later).
[[gnu::always_inline]] inline DD exact_diff(double a, double b) {
  const TwoTerm<double> s = two_sum(a, -b);
  return {s.hi, s.lo};
}

/// One component x_j y_k - x_k y_j of the cross product of exact two-double vectors (x = xh + xl,
/// |xl| <= u |xh|, u = 2^-53). With M = |x_j y_k| + |x_k y_j|: the high products are exact
/// (p + pe, q + qe), p - q is exact as s.hi + s.lo, and lo gathers s.lo, pe - qe and the four cross
/// terms xh yl, xl yh, each at most u M (1 + u), |lo| <= 5.1 u M; its six roundings cost <= 31 u^2 M,
/// the dropped xl yl terms <= 2 u^2 M: |exact - (hi + lo)| <= 33 u^2 M.
[[gnu::always_inline]] inline DD cross_component(double xhj, double xlj, double xhk, double xlk, double yhj,
                                                 double ylj, double yhk, double ylk) {
  const double p = xhj * yhk, pe = __builtin_fma(xhj, yhk, -p);
  const double q = xhk * yhj, qe = __builtin_fma(xhk, yhj, -q);
  const TwoTerm<double> s = two_sum(p, -q);
  double lo = s.lo + (pe - qe);
  lo = __builtin_fma(xhj, ylk, lo);
  lo = __builtin_fma(xlj, yhk, lo);
  lo = __builtin_fma(-xhk, ylj, lo);
  lo = __builtin_fma(-xlk, yhj, lo);
  return {s.hi, lo};
}

/// sum_i x_i n_i for two-double x (xl = 0 for an exact double) and n from cross_component (|nl_i| <=
/// 5.1 u M_i): the three high products exact, their sum exact as NH + s1.lo + s2.lo, the rest
/// gathered in lo (eleven roundings of terms totalling <= 9.2 u P, P = sum |x_i| M_i) and the dropped
/// xl nl terms <= 5.1 u^2 P; with the 33 u^2 M_i of each n_i: |exact - (hi + lo)| <= 140 u^2 P.
[[gnu::always_inline]] inline DD dot_dd(const DD x[3], const DD n[3]) {
  const double p0 = x[0].hi * n[0].hi, p1 = x[1].hi * n[1].hi, p2 = x[2].hi * n[2].hi;
  double lo = __builtin_fma(x[0].hi, n[0].hi, -p0) + __builtin_fma(x[1].hi, n[1].hi, -p1) +
              __builtin_fma(x[2].hi, n[2].hi, -p2);
  const TwoTerm<double> s1 = two_sum(p0, p1), s2 = two_sum(s1.hi, p2);
  lo += s1.lo + s2.lo;
  for (int i = 0; i < 3; ++i) lo = __builtin_fma(x[i].hi, n[i].lo, __builtin_fma(x[i].lo, n[i].hi, lo));
  return {s2.hi, lo};
}

/// sum_i x_i y_i for doubles x and two-double y (yl = 0 allowed, then the product terms vanish):
/// high products exact, their sum exact as hi + two lows, the rest in lo (the bounds of dot_dd apply).
[[gnu::always_inline]] inline DD dot_d_dd(const double x[3], const DD y[3]) {
  const double p0 = x[0] * y[0].hi, p1 = x[1] * y[1].hi, p2 = x[2] * y[2].hi;
  double lo = __builtin_fma(x[0], y[0].hi, -p0) + __builtin_fma(x[1], y[1].hi, -p1) + __builtin_fma(x[2], y[2].hi, -p2);
  const TwoTerm<double> s1 = two_sum(p0, p1), s2 = two_sum(s1.hi, p2);
  lo += s1.lo + s2.lo;
  lo = __builtin_fma(x[0], y[0].lo, __builtin_fma(x[1], y[1].lo, __builtin_fma(x[2], y[2].lo, lo)));
  return {s2.hi, lo};
}
/// sum_i y_i^2 for two-double y: y_hi^2 exact, 2 y_hi y_lo into lo, y_lo^2 dropped (as in dot_dd).
[[gnu::always_inline]] inline DD square_sum(const DD y[3]) {
  const double p0 = y[0].hi * y[0].hi, p1 = y[1].hi * y[1].hi, p2 = y[2].hi * y[2].hi;
  double lo = __builtin_fma(y[0].hi, y[0].hi, -p0) + __builtin_fma(y[1].hi, y[1].hi, -p1) +
              __builtin_fma(y[2].hi, y[2].hi, -p2);
  const TwoTerm<double> s1 = two_sum(p0, p1), s2 = two_sum(s1.hi, p2);
  lo += s1.lo + s2.lo;
  lo = __builtin_fma(2 * y[0].hi, y[0].lo, __builtin_fma(2 * y[1].hi, y[1].lo, __builtin_fma(2 * y[2].hi, y[2].lo, lo)));
  return {s2.hi, lo};
}
/// x_j y_k - x_k y_j for doubles x and two-double y (cross_component with x exact).
[[gnu::always_inline]] inline DD cross_d_dd(double xj, double xk, const DD& yj, const DD& yk) {
  const double p = xj * yk.hi, pe = __builtin_fma(xj, yk.hi, -p);
  const double q = xk * yj.hi, qe = __builtin_fma(xk, yj.hi, -q);
  const TwoTerm<double> s = two_sum(p, -q);
  return {s.hi, __builtin_fma(xj, yk.lo, __builtin_fma(-xk, yj.lo, s.lo + (pe - qe)))};
}

/// NUM - t DEN from NUM ~ N, DEN ~ D: rho = N.hi - t D.hi by one fma, then the low parts. Returns the
/// value and the bound u (|rho| + |mid| + |R|) (1 + 2^-50) on its three roundings (each at most u
/// times its rounded result).
struct Residual {
  double r, err;
};
[[gnu::always_inline]] inline Residual residual(const DD& N, const DD& D, double t) {
  const double rho = __builtin_fma(-t, D.hi, N.hi), mid = rho + N.lo;
  const double R = __builtin_fma(-t, D.lo, mid);
  return {R, 0x1p-53 * (1 + 0x1p-50) * (std::fabs(rho) + std::fabs(mid) + std::fabs(R))};
}

/// x = NUM / DEN with |NUM - (N.hi + N.lo)| <= en and |DEN - (D.hi + D.lo)| <= ed: a double t with
/// round(x) equal to t or a neighbour, or nothing (a sign in doubt, t zero or outside
/// [2^-1000, 2^1000]). One correction and no second residual (it would lengthen the dependency chain
/// by a residual and a comparison): t1 = N.hi * inv (inv = 1 / D.hi rounded), its residual
/// r ~ NUM - t1 DEN with |R1 - r| <= err + en + |t1| ed (R1 the exact one; residual()), and
/// t = t1 + r inv rounded. Since x - t1 = R1 / DEN exactly,
///   |x - t| <= |t - (t1 + r inv)| + |R1 / DEN - r inv|
///           <= u |t| (1 + 2u) + (err + en + |t1| ed) / dmin + |r| (|D.lo| + ed) / (dmin |D.hi|) + |r| 2.0001 u / |D.hi|
/// with dmin = |D.hi| - |D.lo| - ed <= |DEN| (the middle terms: 1 / DEN - 1 / D.hi, and the roundings
/// of inv and of r inv). round(x) is t or a neighbour when |x - t| < midpoint_reach(t), which is at
/// least 1.25 u |t| for a normal t: accepted at once when the rest stays below 0.25 u |t|, else against
/// midpoint_reach itself.
[[gnu::always_inline]] inline std::optional<double> pin_dd(const DD& N, const DD& D, double en, double ed) {
  const double adh = std::fabs(D.hi), dmin = adh - std::fabs(D.lo) - ed;
  if (!(dmin > 0.5 * adh) || !(std::fabs(N.hi) > 2 * (std::fabs(N.lo) + en))) return std::nullopt;
  const double inv = 1 / D.hi, t1 = N.hi * inv;
  const Residual R = residual(N, D, t1);
  const double t = t1 + R.r * inv, at = std::fabs(t), ar = std::fabs(R.r);
  if (!(at > 0x1p-1000 && at < 0x1p1000)) return std::nullopt;  // also NaN
  // The bound times dmin |D.hi| (no division on the way). Both sides must stay normal and finite:
  // at |D| ~ 4e287 the product dmin |D.hi| overflowed, every `rest < inf` held and a t off by 1e-6
  // was accepted (fuzz_kernels). With 2^-1000 <= lhs < 2^1000 the two roundings of lhs and the
  // underflow of any term of rest (<= 2^-1074 each) stay far inside the 2^-40 slack, and an
  // overflowing rest fails the comparisons.
  const double scale = dmin * adh;
  const double lhs = 0x1p-55 * at * scale;
  if (!(lhs >= 0x1p-1000 && lhs < 0x1p1000)) return std::nullopt;
  const double rest = ((R.err + en + std::fabs(t1) * ed) * adh + ar * (std::fabs(D.lo) + ed + 2.0001 * 0x1p-53 * dmin)) *
                      (1 + 0x1p-40);
  if (rest < lhs * (1 - 0x1p-40)) return t;
  if (rest + 0x1p-53 * at * (1 + 0x1p-50) * scale < midpoint_reach(t) * scale * (1 - 0x1p-40)) return t;
  return std::nullopt;
}

/// The triangle's t = ((p0 - o) . n) / (d . n), n = (p1 - p0) x (p2 - p0), in double-double. pn =
/// cross_permanent of the rounded differences (the M_i above; slack covers their rounding). Errors: 140 u^2 times
/// sum_i |x_i| pn_i (x = p0 - o or d), used with 2^-90 (>= 3x slack), plus 2^-1000 (|x|_1 + 1) for
/// products that underflow (an fma error term below 2^-1022 is not exact: <= 2^-1075 each, amplified
/// by |x_i| at most).
RAYPROOF_FMA_TARGET inline std::optional<double> triangle_t_inline(const Ray<double>& ray, const Triangle<double>& tri) {
  const DD f1[3] = {exact_diff(tri.p1.x, tri.p0.x), exact_diff(tri.p1.y, tri.p0.y), exact_diff(tri.p1.z, tri.p0.z)};
  const DD f2[3] = {exact_diff(tri.p2.x, tri.p0.x), exact_diff(tri.p2.y, tri.p0.y), exact_diff(tri.p2.z, tri.p0.z)};
  const DD n[3] = {
      cross_component(f1[1].hi, f1[1].lo, f1[2].hi, f1[2].lo, f2[1].hi, f2[1].lo, f2[2].hi, f2[2].lo),
      cross_component(f1[2].hi, f1[2].lo, f1[0].hi, f1[0].lo, f2[2].hi, f2[2].lo, f2[0].hi, f2[0].lo),
      cross_component(f1[0].hi, f1[0].lo, f1[1].hi, f1[1].lo, f2[0].hi, f2[0].lo, f2[1].hi, f2[1].lo)};
  const DD a[3] = {exact_diff(tri.p0.x, ray.o.x), exact_diff(tri.p0.y, ray.o.y), exact_diff(tri.p0.z, ray.o.z)};
  const double d[3] = {ray.d.x, ray.d.y, ray.d.z};
  const DD num = dot_dd(a, n), den = dot_d_dd(d, n);
  const Vec3<double> pn = cross_permanent({f1[0].hi, f1[1].hi, f1[2].hi}, {f2[0].hi, f2[1].hi, f2[2].hi});
  const double a1 = std::fabs(a[0].hi) + std::fabs(a[1].hi) + std::fabs(a[2].hi);
  const double d1 = std::fabs(ray.d.x) + std::fabs(ray.d.y) + std::fabs(ray.d.z);
  const double en = 0x1p-90 * (std::fabs(a[0].hi) * pn.x + std::fabs(a[1].hi) * pn.y + std::fabs(a[2].hi) * pn.z) +
                    0x1p-1000 * (a1 + 1);
  const double ed = 0x1p-90 * (std::fabs(ray.d.x) * pn.x + std::fabs(ray.d.y) * pn.y + std::fabs(ray.d.z) * pn.z) +
                    0x1p-1000 * (d1 + 1);
  return pin_dd(num, den, en, ed);
}
/// triangle_t_inline out of line: triangle_near's t. It stays the scalar double-double on purpose, so
/// that on x86 both it and its AVX2 twin (stage 1's, triangle_t_stage1) run under the tests.
[[gnu::noinline]] RAYPROOF_FMA_TARGET inline std::optional<double> triangle_t(const Ray<double>& ray,
                                                                              const Triangle<double>& tri) {
  return triangle_t_inline(ray, tri);
}

#if RAYPROOF_DD_AVX2
/// triangle_t_inline three lanes at a time (x, y, z; the fourth lane is 0 and unused): the same
/// operations on each component in the same order (the cross product of exact two-double vectors is
/// cross_component lane by lane, with the components rotated by permutes), so its error analysis
/// holds unchanged; the dot products gather each lane's low terms first (two roundings a lane) and then
/// the lanes, fewer roundings per path than dot_dd's chain (six against eleven), within the same bound.
namespace v4 {
#define RAYPROOF_V4 [[gnu::always_inline]] RAYPROOF_FMA_TARGET inline
using V = __m256d;
struct VD {
  V hi, lo;
};
RAYPROOF_V4 V set3(const Vec3<double>& v) { return _mm256_set_pd(0.0, v.z, v.y, v.x); }
RAYPROOF_V4 V yzx(V v) { return _mm256_permute4x64_pd(v, 0xC9); }  // lanes (y, z, x, w)
RAYPROOF_V4 V zxy(V v) { return _mm256_permute4x64_pd(v, 0xD2); }  // lanes (z, x, y, w)
RAYPROOF_V4 V vabs(V v) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v); }
/// a - b exactly, as exact_diff (two-sum of a and -b).
RAYPROOF_V4 VD diff(V a, V b) {
  const V nb = _mm256_xor_pd(b, _mm256_set1_pd(-0.0));
  const V s = _mm256_add_pd(a, nb), bb = _mm256_sub_pd(s, a);
  return {s, _mm256_add_pd(_mm256_sub_pd(a, _mm256_sub_pd(s, bb)), _mm256_sub_pd(nb, bb))};
}
/// cross_component in every lane.
RAYPROOF_V4 VD cross(const VD& x, const VD& y) {
  const V xhj = yzx(x.hi), xlj = yzx(x.lo), xhk = zxy(x.hi), xlk = zxy(x.lo);
  const V yhj = yzx(y.hi), ylj = yzx(y.lo), yhk = zxy(y.hi), ylk = zxy(y.lo);
  const V p = _mm256_mul_pd(xhj, yhk), pe = _mm256_fmsub_pd(xhj, yhk, p);
  const V q = _mm256_mul_pd(xhk, yhj), qe = _mm256_fmsub_pd(xhk, yhj, q);
  const V mq = _mm256_xor_pd(q, _mm256_set1_pd(-0.0));
  const V sh = _mm256_add_pd(p, mq), bb = _mm256_sub_pd(sh, p);
  const V sl = _mm256_add_pd(_mm256_sub_pd(p, _mm256_sub_pd(sh, bb)), _mm256_sub_pd(mq, bb));
  V lo = _mm256_add_pd(sl, _mm256_sub_pd(pe, qe));
  lo = _mm256_fmadd_pd(xhj, ylk, lo);
  lo = _mm256_fmadd_pd(xlj, yhk, lo);
  lo = _mm256_fnmadd_pd(xhk, ylj, lo);
  lo = _mm256_fnmadd_pd(xlk, yhj, lo);
  return {sh, lo};
}
/// The three high products' exact sum (two-sums in dot_dd's order) plus the lanes' low terms.
RAYPROOF_V4 DD gather(V P, V T) {
  alignas(32) double p[4], t[4];
  _mm256_store_pd(p, P);
  _mm256_store_pd(t, T);
  const TwoTerm<double> s1 = two_sum(p[0], p[1]), s2 = two_sum(s1.hi, p[2]);
  return {s2.hi, ((t[0] + t[1]) + t[2]) + (s1.lo + s2.lo)};
}
/// sum_i x_i n_i for two-double x and n (dot_dd).
RAYPROOF_V4 DD dot(const VD& x, const VD& n) {
  const V P = _mm256_mul_pd(x.hi, n.hi), E = _mm256_fmsub_pd(x.hi, n.hi, P);
  return gather(P, _mm256_fmadd_pd(x.hi, n.lo, _mm256_fmadd_pd(x.lo, n.hi, E)));
}
/// sum_i x_i n_i for double x and two-double n (dot_d_dd).
RAYPROOF_V4 DD dot(V x, const VD& n) {
  const V P = _mm256_mul_pd(x, n.hi), E = _mm256_fmsub_pd(x, n.hi, P);
  return gather(P, _mm256_fmadd_pd(x, n.lo, E));
}
/// (v_0 + v_1) + v_2.
RAYPROOF_V4 double sum3(V v) {
  alignas(32) double x[4];
  _mm256_store_pd(x, v);
  return (x[0] + x[1]) + x[2];
}
#undef RAYPROOF_V4
}  // namespace v4

/// triangle_t_inline in AVX2 (see v4): the same t, the same bounds.
RAYPROOF_FMA_TARGET inline std::optional<double> triangle_t_avx2(const Ray<double>& ray, const Triangle<double>& tri) {
  using namespace v4;
  const V p0 = set3(tri.p0);
  const VD f1 = diff(set3(tri.p1), p0), f2 = diff(set3(tri.p2), p0);
  const VD n = cross(f1, f2);
  const VD a = diff(p0, set3(ray.o));
  const V d = set3(ray.d);
  const DD num = dot(a, n), den = dot(d, n);
  // cross_permanent of the rounded differences, in the same order.
  const V pn = _mm256_add_pd(_mm256_mul_pd(vabs(yzx(f1.hi)), vabs(zxy(f2.hi))),
                             _mm256_mul_pd(vabs(zxy(f1.hi)), vabs(yzx(f2.hi))));
  const V aa = vabs(a.hi), ad = vabs(d);
  const double en = 0x1p-90 * sum3(_mm256_mul_pd(aa, pn)) + 0x1p-1000 * (sum3(aa) + 1);
  const double ed = 0x1p-90 * sum3(_mm256_mul_pd(ad, pn)) + 0x1p-1000 * (sum3(ad) + 1);
  return pin_dd(num, den, en, ed);
}
#endif

/// The triangle's t for stage 1: AVX2 where available, else the scalar double-double.
RAYPROOF_FMA_TARGET inline std::optional<double> triangle_t_stage1(const Ray<double>& ray, const Triangle<double>& tri) {
#if RAYPROOF_DD_AVX2
  return triangle_t_avx2(ray, tri);
#else
  return triangle_t_inline(ray, tri);
#endif
}

/// The sign of x = hi + lo known within e: +1 or -1, or 0 when the bound cannot tell.
[[gnu::always_inline]] inline int dd_sign(const DD& x, double e) {
  const double m = (std::fabs(x.lo) + e) * (1 + 0x1p-50);
  return x.hi > m ? 1 : (x.hi < -m ? -1 : 0);
}

/// (d x y) . z for double d and two-double y, z, and its error bound (see triangle_near).
[[gnu::always_inline]] inline DD volume(const double d[3], const DD y[3], const DD z[3], double& err) {
  const DD m[3] = {cross_d_dd(d[1], d[2], y[1], y[2]), cross_d_dd(d[2], d[0], y[2], y[0]), cross_d_dd(d[0], d[1], y[0], y[1])};
  const Vec3<double> M = cross_permanent({d[0], d[1], d[2]}, {y[0].hi, y[1].hi, y[2].hi});
  const double az[3] = {std::fabs(z[0].hi), std::fabs(z[1].hi), std::fabs(z[2].hi)};
  err = 0x1p-90 * (az[0] * M.x + az[1] * M.y + az[2] * M.z) + 0x1p-1000 * (az[0] + az[1] + az[2] + 1);
  return dot_dd(z, m);
}

/// The triangle's class where the double stage could not tell (a ray near an edge, a vertex or the
/// plane), before the expansions: the signed volumes u0 = (d x b) . c, u1 = (d x c) . a,
/// u2 = (d x a) . b of certified_triangle.h's stage 1, with a, b, c = p_i - o exact as two doubles,
/// in double-double: m = d x b by cross_d_dd (x exact: within 33 u^2 M_i, M_i = |d_j b_k| + |d_k b_j|),
/// u0 = m . c by dot_dd: within 140 u^2 sum_i |c_i| M_i, used as 2^-90 (>= 3x), plus 2^-1000
/// (|c|_1 + 1) for products that underflow (as triangle_t). den = u0 + u1 + u2 adds the rounding of
/// the low parts' sum. Decides miss (a barycentric of the other sign than den), and interior or
/// behind with t from triangle_t when every sign is clear; returns nothing for what may be an exact
/// zero (an edge, a vertex, a parallel or coplanar ray): the expansions decide those.
[[gnu::noinline]] RAYPROOF_FMA_TARGET inline std::optional<Hit<double>> triangle_near(const Ray<double>& ray,
                                                                                   const Triangle<double>& tri) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &p0 = tri.p0, &p1 = tri.p1, &p2 = tri.p2;
  const DD a[3] = {exact_diff(p0.x, o.x), exact_diff(p0.y, o.y), exact_diff(p0.z, o.z)};
  const DD b[3] = {exact_diff(p1.x, o.x), exact_diff(p1.y, o.y), exact_diff(p1.z, o.z)};
  const DD c[3] = {exact_diff(p2.x, o.x), exact_diff(p2.y, o.y), exact_diff(p2.z, o.z)};
  const double d[3] = {ray.d.x, ray.d.y, ray.d.z};
  double e0, e1, e2;
  const DD u0 = volume(d, b, c, e0), u1 = volume(d, c, a, e1), u2 = volume(d, a, b, e2);
  const TwoTerm<double> s1 = two_sum(u0.hi, u1.hi), s2 = two_sum(s1.hi, u2.hi);
  const double lo = u0.lo + u1.lo + u2.lo;
  const DD den{s2.hi, (s1.lo + s2.lo) + lo};
  const double eden = (e0 + e1 + e2 + 0x1p-51 * (std::fabs(u0.lo) + std::fabs(u1.lo) + std::fabs(u2.lo) + std::fabs(lo))) *
                      (1 + 0x1p-50);
  const int sd = dd_sign(den, eden);
  if (sd == 0) return std::nullopt;  // parallel, coplanar or too close: the expansions
  const int s0 = dd_sign(u0, e0) * sd, s1s = dd_sign(u1, e1) * sd, s2s = dd_sign(u2, e2) * sd;
  if (s0 < 0 || s1s < 0 || s2s < 0) return H{Contact::miss};
  if (s0 == 0 || s1s == 0 || s2s == 0) return std::nullopt;  // maybe an edge or a vertex
  // Interior or behind: t as in stage 1.
  const auto t = triangle_t(ray, tri);
  if (!t) return std::nullopt;
  return H{*t < 0 ? Contact::behind : Contact::interior, *t};
}

/// A certified ray / sphere test in double-double, for inputs in_range<-200, 200> (checked by the
/// caller; every product is then >= 2^-1008 or zero, its fma error term exact, nothing overflows).
/// With e = o - center (exact as two doubles): a t^2 + 2 b t + c = 0 with a = d.d, b = d.e,
/// c = e.e - r^2, and disc = b^2 - a c or, when that cancels too much, a r^2 - |m|^2 with m = d x e
/// (the cancellation-free form of certified_quadric.h).
/// Error bounds (u = 2^-53), each >= 3x over the rounding count of its evaluation: a: 12 u^2 a, used
/// as 2^-100 a; b: 21 u^2 sum |d_i e_i|, as 2^-98; c: 31 u^2 (e.e + r^2), as 2^-98. disc = b^2 - a c
/// from the double-doubles b, a, c (pb = sum |d_i e_i| >= |b|, |b.lo| <= 5 u pb, |c.lo| <= 4 u (e.e +
/// r^2), |a.lo| <= 3 u a; M = pb^2 + a (e.e + r^2)): the inputs' errors carry over as 2 |b| eb + a ec +
/// |c| ea <= 2^-97 M, the six roundings of the low parts (each term <= 20 u M) add <= 120 u^2 M and
/// the dropped b.lo^2, a.lo c.lo <= 37 u^2 M: together <= 2^-96.6 M, used as 2^-95 M. Lagrange: m_i is
/// within 33 u^2 M_i (M_i = |d_j e_k| + |d_k e_j|, cross_component), |m|^2 within 16 u^2 |m|^2 +
/// 148 u^2 sum |m_i| M_i + 27 u^2 sum M_i^2, a r^2 within 30 u^2 a r^2, the difference 8 u^2 a r^2 +
/// 26 u^2 |m|^2: used as 2^-97 (a r^2 + |m|^2 + sum |m_i| M_i + sum M_i^2). Every bound also carries
/// 2^-1000 for the absolute error of an operation whose result is subnormal (2^-1075 each).
/// Decides miss, inside, behind and hit with both roots pinned (sqrt(disc) of the normalised disc
/// refined as in certified_quadric.h, |error| <= 2^-103 s + ered / sqrt(disc), used with 2^-101 s, no cancellation in
/// q = -(b + sign(b) sqrt(disc)), roots q / a and c / q by pin_dd); returns nothing for a disc, c or
/// b whose sign the bound cannot tell (tangents, origins on the surface), it returns next(): the caller's
/// exact stages, called here so that their result is returned without a copy.
template <class Next>
[[gnu::noinline]] RAYPROOF_FMA_TARGET std::optional<Hit<double>> sphere(const Ray<double>& ray, const Sphere<double>& sp,
                                                                    Next next) {
  using H = Hit<double>;
  const DD e[3] = {exact_diff(ray.o.x, sp.center.x), exact_diff(ray.o.y, sp.center.y), exact_diff(ray.o.z, sp.center.z)};
  const double dv[3] = {ray.d.x, ray.d.y, ray.d.z};
  const DD dz[3] = {{dv[0], 0}, {dv[1], 0}, {dv[2], 0}};
  const DD a = square_sum(dz);
  const double rh = sp.radius * sp.radius, rl = __builtin_fma(sp.radius, sp.radius, -rh);
  const DD b = dot_d_dd(dv, e), ee = square_sum(e);
  const TwoTerm<double> cs = two_sum(ee.hi, -rh);
  const DD c{cs.hi, cs.lo + ee.lo - rl};
  const double D[3] = {std::fabs(ray.d.x), std::fabs(ray.d.y), std::fabs(ray.d.z)};
  const double E[3] = {std::fabs(e[0].hi), std::fabs(e[1].hi), std::fabs(e[2].hi)};
  const double pb = D[0] * E[0] + D[1] * E[1] + D[2] * E[2];
  const double ea = 0x1p-100 * a.hi + 0x1p-1000, eb = 0x1p-98 * pb + 0x1p-1000, ec = 0x1p-98 * (ee.hi + rh) + 0x1p-1000;
  // disc = b^2 - a c first (cheap: b and c are needed anyway): within 2^-95 (pb^2 + a (e.e + r^2)), see
  // above. It loses (|e| / r)^2 of relative precision to cancellation (an origin far from a small
  // sphere); when that leaves it with fewer than ~62 good bits, the cancellation-free a r^2 - |d x e|^2.
  DD red;
  double ered;
  {
    const double bh2 = b.hi * b.hi, bh2e = __builtin_fma(b.hi, b.hi, -bh2);
    const double ac = a.hi * c.hi, ace = __builtin_fma(a.hi, c.hi, -ac);
    const TwoTerm<double> ds = two_sum(bh2, -ac);
    red = {ds.hi, ds.lo + (__builtin_fma(2 * b.hi, b.lo, bh2e) - __builtin_fma(a.hi, c.lo, __builtin_fma(a.lo, c.hi, ace)))};
    ered = 0x1p-95 * (pb * pb + a.hi * (ee.hi + rh)) + 0x1p-1000;
  }
  if (!(ered < 0x1p-62 * std::fabs(red.hi))) {
    const DD m[3] = {cross_d_dd(dv[1], dv[2], e[1], e[2]), cross_d_dd(dv[2], dv[0], e[2], e[0]), cross_d_dd(dv[0], dv[1], e[0], e[1])};
    const DD mm = square_sum(m);
    const double ar = a.hi * rh;
    const double arl = __builtin_fma(a.lo, rh, __builtin_fma(a.hi, rl, __builtin_fma(a.hi, rh, -ar)));
    const TwoTerm<double> rs = two_sum(ar, -mm.hi);
    red = {rs.hi, rs.lo + arl - mm.lo};
    const Vec3<double> M = cross_permanent(ray.d, {e[0].hi, e[1].hi, e[2].hi});
    ered = 0x1p-97 * (std::fabs(ar) + std::fabs(mm.hi) + std::fabs(m[0].hi) * M.x + std::fabs(m[1].hi) * M.y +
                      std::fabs(m[2].hi) * M.z + M.x * M.x + M.y * M.y + M.z * M.z) +
           0x1p-1000;
  }
  if (red.hi < -2 * (std::fabs(red.lo) + ered)) return H{Contact::miss};
  if (!(red.hi > 2 * (std::fabs(red.lo) + ered)) || !(red.hi > 0x1p-900)) return next();
  const int sc = c.hi > 2 * (std::fabs(c.lo) + ec) ? 1 : (c.hi < -2 * (std::fabs(c.lo) + ec) ? -1 : 0);
  const int sb = b.hi > 2 * (std::fabs(b.lo) + eb) ? 1 : (b.hi < -2 * (std::fabs(b.lo) + eb) ? -1 : 0);
  if (sc == 0 || (sc > 0 && sb == 0)) return next();
  const Contact cls = sc < 0 ? Contact::inside : (sb > 0 ? Contact::behind : Contact::hit);
  // sqrt(disc) = s + sl from disc normalised (exactly: rn.lo at most half an ulp of rn.hi, which the
  // refinement's error analysis needs; red.lo itself may be a sizeable fraction of red.hi after
  // cancellation), s = sqrt(rn.hi), the remainder rn.hi - s^2 exact by fma.
  const TwoTerm<double> rn = two_sum(red.hi, red.lo);
  const double s = std::sqrt(rn.hi), inv = 0.5 / s;
  const double sl = (__builtin_fma(-s, s, rn.hi) + rn.lo) * inv;
  const double esq = (0x1p-101 * s + ered * (2 * inv) * (1 + 0x1p-50)) * (1 + 0x1p-50) + 0x1p-1000;
  // q = -(b + sign(b) sqrt(disc)), no cancellation; q / a and c / q.
  const bool plus = b.hi >= 0;
  const TwoTerm<double> qs = plus ? two_sum(b.hi, s) : two_sum(s, -b.hi);
  const double ql = plus ? qs.lo + b.lo + sl : qs.lo + sl - b.lo;
  const DD q = plus ? DD{-qs.hi, -ql} : DD{qs.hi, ql};
  const double eq = (eb + esq) * (1 + 0x1p-50) + 0x1p-51 * (std::fabs(qs.lo) + std::fabs(b.lo) + std::fabs(sl));
  const auto t1 = pin_dd(q, a, eq, ea), t2 = pin_dd(c, q, ec, eq);
  if (!t1 || !t2) return next();
  // plus: q < 0 and q / a is the lower root; otherwise q > 0 and q / a the upper one.
  return plus ? H{cls, *t1, *t2} : H{cls, *t2, *t1};
}
#endif

}  // namespace rayproof::certified::dd
