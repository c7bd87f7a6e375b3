#pragma once
/// Shared pieces of the staged certified filters (certified_triangle.h, certified_quadric.h,
/// certified_box.h, certified_planar.h). The stages, cheapest first:
///  1. double with a *static* error bound (Shewchuk-style): a quantity evaluated by a straight-line
///     program with at most k roundings along any path has |computed - exact| <= gamma_k P, where P is
///     the same program on absolute values (subtractions as additions); we bound P by norms of the
///     rounded inputs and use a constant with a factor >= 2 of slack. Underflow is covered by a tiny
///     absolute term (2^-1075 per product, times the largest factor it can meet later), or by an
///     in_range() check of the inputs; overflow leaves a value or its bound non-finite: undecided.
///  2. t pinned from a plain evaluation with the same static bounds scaled down: for triangles in
///     double-double with hardware FMA (certified_fma.h), else in the x87 extended format (Wide),
///     pinned by pin_wide (quadrics) or pin_ratio (a double quotient checked by its residual in Wide:
///     triangles, planes, disks, boxes); in the exact stage by an exact residual (pin_quotient).
///  3. exact signs with floating-point expansions (certified_expansion.h): exact zeros (edges,
///     vertices, tangents, rims, grazes) are proven without GMP.
/// Whatever is left returns nothing, and the caller falls back to exact arithmetic (GMP).
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "rayproof/certified_expansion.h"
#include "rayproof/certified_filter.h"

namespace rayproof::certified {

/// The neighbours of a finite double, from its bits (no libm call).
[[nodiscard]] inline double next_above(double x) {
  if (x == 0) return std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::int64_t>(x);
  return std::bit_cast<double>(x > 0 ? b + 1 : b - 1);
}
[[nodiscard]] inline double next_below(double x) { return -next_above(-x); }

/// The distance from a normal double t to the nearer of the midpoint below prev(t) and the midpoint
/// above next(t): (t - prev) + (prev - prev(prev)) / 2 and (next - t) + (next(next) - next) / 2, exact
/// (gaps of normal doubles are powers of two). A value closer to t than this rounds to t or a
/// neighbour of t.
[[nodiscard]] inline double midpoint_reach(double t) {
  const double p = next_below(t), n = next_above(t);
  const double down = (t - p) + (p - next_below(p)) / 2, up = (n - t) + (next_above(n) - n) / 2;
  return down < up ? down : up;
}

/// P_i = |x_j y_k| + |x_k y_j|: the permanent bounding the rounding errors of (x cross y)_i.
[[nodiscard]] inline Vec3<double> cross_permanent(const Vec3<double>& x, const Vec3<double>& y) {
  const Vec3<double> ax{std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)}, ay{std::fabs(y.x), std::fabs(y.y), std::fabs(y.z)};
  return {ax.y * ay.z + ax.z * ay.y, ax.z * ay.x + ax.x * ay.z, ax.x * ay.y + ax.y * ay.x};
}

/// v approximates an exact value x with |x - v| <= err. Returns t = double(v) when round(x) is
/// certainly t or a neighbour of t (the 1-ulp contract): x lies strictly between the midpoint below
/// prev(t) and the midpoint above next(t) (both exact in Wide). The term 2^-62 |v| covers the
/// rounding of v -+ err.
[[nodiscard]] inline std::optional<double> pin_wide(Wide v, Wide err) {
  const double t = static_cast<double>(v);
  if (!(std::fabs(t) < 0x1p1020) || !(err >= 0)) return std::nullopt;
  const Wide e = err + std::fabs(v) * 0x1p-62L;
  // Quick accept: within |t| 2^-53 of t, which is at most the gap to either neighbour of a normal t.
  if (std::fabs(t) > 0x1p-1000 && std::fabs(v - t) + e < std::fabs(t) * 0x1p-53L * (1 - 0x1p-60L)) return t;
  const double p = next_below(t), n = next_above(t);
  const Wide lo = (Wide(next_below(p)) + Wide(p)) / 2, hi = (Wide(n) + Wide(next_above(n))) / 2;
  if (v - e > lo && v + e < hi) return t + 0.0;  // a zero is +0.0
  return std::nullopt;
}

/// x = NUM / DEN for exact values known through Wide approximations: |NUM - num| <= en and
/// |DEN - den| <= ed, with |den| > ed. Returns a double t with round(x) equal to t or a neighbour of
/// t, or nothing. No x87 division: a quotient guess t1 = num * (1 / den) in double (SSE), one
/// correction t = t1 + (num - t1 den) / den from the residual in Wide, and then the residual of t
/// itself, R = num - t den (two Wide roundings, |error| <= 2^-63 |t den|), bounds the distance:
/// |x - t| = |NUM - t DEN| / |DEN| <= (|R| + 2^-63 |t den| + en + |t| ed) / (|den| - ed) =: B.
/// round(x) is t or a neighbour when x lies strictly between the midpoints around prev(t) and
/// next(t): accepted when B < midpoint_reach(t); the comparison carries 2^-40 of slack for the rounding of B
/// itself. A quotient outside [2^-1000, 2^1000] in magnitude (or zero) is left to the caller.
[[nodiscard]] inline std::optional<double> pin_ratio(Wide num, Wide den, Wide en, Wide ed) {
  const double inv = 1.0 / static_cast<double>(den);
  const double t1 = static_cast<double>(num) * inv;
  if (!(std::fabs(t1) < 0x1p1000 && std::fabs(t1) > 0x1p-1000)) return std::nullopt;  // also NaN
  const double t = t1 + static_cast<double>(num - Wide(t1) * den) * inv;
  const Wide R = num - Wide(t) * den, at = std::fabs(t), ad = std::fabs(den);
  const Wide lhs = (std::fabs(R) + en + at * (ed + 0x1p-63L * ad)) * (1 + 0x1p-40L);
  // Quick accept: 2^-53 |t| is at most either gap next to a normal t, and below both distances.
  if (lhs < 0x1p-53L * at * (ad - ed) && at > 0x1p-1000) return t;
  if (!(at > 0x1p-1000 && at < 0x1p1000)) return std::nullopt;
  if (lhs < Wide(midpoint_reach(t)) * (ad - ed)) return t;
  return std::nullopt;
}

/// t = N / D for exact expansions (D != 0): a candidate t1 near N / D in double, checked by the exact
/// residual R = N - t1 D: |t - t1| = |R| / |D|. Accepts t1 when that is below 1.25 times the smaller
/// gap g next to t1 (neighbouring gaps differ by at most a factor 2, so t then lies strictly between
/// the midpoints around prev(t1) and next(t1), and round(t) is within one ulp of t1); otherwise steps
/// once towards t and tries again. Each two_prod(t1, D_i) must be exact: checked at run time (no
/// product below 2^-960, none above 2^1000).
[[nodiscard]] inline std::optional<double> pin_quotient(const Expansion& N, const Expansion& D) {
  if (N.bad || D.bad || D.n == 0) return std::nullopt;
  if (N.n == 0) return 0.0;
  double t1 = N.estimate() / D.estimate();
  for (int step = 0; step < 2; ++step) {
    const double at = std::fabs(t1);
    if (!(at < 0x1p1020) || t1 == 0) return std::nullopt;  // also: NaN, infinite
    if (at * std::fabs(D.c[0]) < 0x1p-960 || at * std::fabs(D.top()) > 0x1p+1000) return std::nullopt;
    const Expansion R = N - Expansion(t1) * D;
    if (R.bad) return std::nullopt;
    if (R.n == 0) return t1;  // exact quotient
    // |R| <= |R_top| (1 + 2^-51), |D| >= |D_top| (1 - 2^-51); 2^-48 more covers this division's rounding.
    const double dist = std::fabs(R.top()) / std::fabs(D.top()) * (1 + 0x1p-48);
    const double gap = std::fmin(t1 - next_below(t1), next_above(t1) - t1);  // exact (Sterbenz)
    if (dist < 1.25 * gap * (1 - 0x1p-50)) return t1;
    t1 = (R.sign() == D.sign()) ? next_above(t1) : next_below(t1);  // t - t1 has the sign of R / D
  }
  return std::nullopt;
}

}  // namespace rayproof::certified
