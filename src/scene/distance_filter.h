#pragma once
/// The double filter of the closest-point query (internal): ball arithmetic (a value and a radius
/// that bounds its distance to the exact value) in double and in double-double, the squared
/// distance of a triangle's features (vertex, edge, face) as balls, and the correct-rounding test
/// of a square root from a ball. docs/distance.md explains the bounds.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include "rayproof/certified_dd.h"
#include "rayproof/float_util.h"
#include "rayproof/vec3.h"

namespace rayproof::scene::detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
/// Relative slack for the rounding of the radius computations themselves (a few operations of
/// relative error 2^-53 each, and |hi| for |hi + lo| in double-double).
inline constexpr double kUp = 1 + 0x1p-48;
/// Absolute slack for underflow in products (far above 2^-1074; below every normal-scale radius).
inline constexpr double kEta = 0x1p-1060;

/// The double-double of the certified filters (rayproof/certified_dd.h), beside plain double in
/// the overloads below that the ball arithmetic is generic over.
using DD = certified::dd::DD;
inline DD vadd(DD a, DD b) { return certified::dd::sum(a, b); }
inline DD vsub(DD a, DD b) { return certified::dd::difference(a, b); }
inline DD vmul(DD a, DD b) { return certified::dd::product(a, b); }
inline DD vdiv(DD a, DD b) { return certified::dd::quotient(a, b); }
inline double vadd(double a, double b) { return a + b; }
inline double vsub(double a, double b) { return a - b; }
inline double vmul(double a, double b) { return a * b; }
inline double vdiv(double a, double b) { return a / b; }
inline double mag(double x) { return std::abs(x); }
inline double mag(DD x) { return std::abs(x.hi); }

/// A ball: the exact value lies within r of x. kE bounds one operation's relative rounding error
/// (double: 2^-53; double-double: 2^-100, above the published bounds of about 10 * 2^-106).
template <class V, int kLog2E>
struct Ball {
  V x{};
  double r = 0;
  static constexpr double kE = kLog2E == 53 ? 0x1p-53 : 0x1p-100;
};
using BD = Ball<double, 53>;
using BQ = Ball<DD, 100>;

inline BD dif(BD*, double a, double b) {
  const double x = a - b;
  return {x, std::abs(x) * BD::kE + kEta};
}
inline BQ dif(BQ*, double a, double b) { return {two_sum(a, -b), 0.0}; }  // exact

template <class B> B add(const B& a, const B& b) {
  const auto x = vadd(a.x, b.x);
  return {x, (a.r + b.r + mag(x) * B::kE) * kUp + kEta};
}
template <class B> B sub(const B& a, const B& b) {
  const auto x = vsub(a.x, b.x);
  return {x, (a.r + b.r + mag(x) * B::kE) * kUp + kEta};
}
template <class B> B mul(const B& a, const B& b) {
  const auto x = vmul(a.x, b.x);
  return {x, (mag(a.x) * b.r + a.r * mag(b.x) + a.r * b.r + mag(x) * B::kE) * kUp + kEta};
}
/// a / b for b > 0 surely; otherwise a ball of infinite radius.
template <class B> B div(const B& a, const B& b) {
  const double den = (mag(b.x) - b.r) * (1 - 0x1p-48);
  if (!(den > 0)) return {decltype(a.x){}, kInf};
  const auto q = vdiv(a.x, b.x);
  return {q, ((a.r + mag(q) * b.r) / den + mag(q) * B::kE) * kUp * kUp + kEta};
}
template <class B> struct BV {
  B x, y, z;
};
template <class B> BV<B> difv(const Vec3<double>& a, const Vec3<double>& b) {
  return {dif((B*)nullptr, a.x, b.x), dif((B*)nullptr, a.y, b.y), dif((B*)nullptr, a.z, b.z)};
}
template <class B> B dot(const BV<B>& a, const BV<B>& b) { return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z)); }
template <class B> BV<B> cross(const BV<B>& a, const BV<B>& b) {
  return {sub(mul(a.y, b.z), mul(a.z, b.y)), sub(mul(a.z, b.x), mul(a.x, b.z)), sub(mul(a.x, b.y), mul(a.y, b.x))};
}

/// Surely positive / surely negative.
inline bool positive(const BD& b) { return b.x > b.r; }
inline bool negative(const BD& b) { return b.x < -b.r; }

/// The interval [lo, hi] of a double ball of a nonnegative quantity, rounded outwards.
inline void interval(const BD& b, double& lo, double& hi) {
  const double m = (std::abs(b.x) + b.r) * 0x1p-51;
  lo = (b.x - b.r) - m;
  hi = (b.x + b.r) + m;
  if (!(lo > 0)) lo = 0;
}

/// The edge from vertex k to k + 1 of a triangle with its endpoints in lexicographic order, so
/// that every triangle sharing the edge computes the same bits.
inline void canonical_edge(const std::array<Vec3<double>, 3>& t, int k, Vec3<double>& u, Vec3<double>& v, bool& swapped) {
  u = t[k], v = t[(k + 1) % 3];
  swapped = v.x < u.x || (v.x == u.x && (v.y < u.y || (v.y == u.y && v.z < u.z)));
  if (swapped) std::swap(u, v);
}

enum Kind : std::uint8_t { kFace = 0, kEdge = 1, kVertex = 2 };

/// The squared distance from p to the feature's affine hull (vertex: the point, edge: its line,
/// face: its plane), as a ball in B's arithmetic.
template <class B>
B feature_value(const std::array<Vec3<double>, 3>& t, const Vec3<double>& p, Kind kind, int k) {
  if (kind == kVertex) {
    const BV<B> w = difv<B>(p, t[k]);
    return dot(w, w);
  }
  if (kind == kEdge) {
    Vec3<double> u, v;
    bool sw;
    canonical_edge(t, k, u, v, sw);
    const BV<B> d = difv<B>(v, u), w = difv<B>(p, u);
    const BV<B> c = cross(d, w);
    return div(dot(c, c), dot(d, d));
  }
  const BV<B> ab = difv<B>(t[1], t[0]), ac = difv<B>(t[2], t[0]), ap = difv<B>(p, t[0]);
  const BV<B> n = cross(ab, ac);
  const B h = dot(n, ap);
  return div(mul(h, h), dot(n, n));
}

/// sqrt(D) rounded to nearest when it is decided for every D within the ball (x, r); false
/// otherwise (or outside the exponent range where the test's terms are exact).
template <class V>
bool round_sqrt_ball(const V& x, double r, double& out) {
  double xh, xl;
  if constexpr (std::is_same_v<V, DD>) xh = x.hi, xl = x.lo;
  else xh = x, xl = 0;
  if (!(xh >= 0x1p-900 && xh <= 0x1p+1000 && r < xh * 0x1p-20)) return false;
  // sqrt(xh) or a neighbour (the low part of a double-double moves the root by a fraction of an ulp).
  const double c0 = std::sqrt(xh);
  for (const double r0 : {c0, std::nextafter(c0, kInf), std::nextafter(c0, 0.0)}) {
    const double u = std::nextafter(r0, kInf) - r0, ud = r0 - std::nextafter(r0, 0.0);
    const double P = r0 * r0, e = std::fma(r0, r0, -P);
    // Each sum of six terms is within 6 * 2^-53 of the sum of their magnitudes: below 2^-50 of it.
    {  // m+^2 - (x + r) > 0, m+ = r0 + u / 2
      const double t[6] = {P - xh, e, -xl, r0 * u, u * u * 0.25, -r};
      double s = 0, a = 0;
      for (double v : t) s += v, a += std::abs(v);
      if (!(s > a * 0x1p-50)) continue;
    }
    {  // (x - r) - m-^2 > 0, m- = r0 - ud / 2
      const double t[6] = {xh - P, xl, -e, r0 * ud, -ud * ud * 0.25, -r};
      double s = 0, a = 0;
      for (double v : t) s += v, a += std::abs(v);
      if (!(s > a * 0x1p-50)) continue;
    }
    out = r0;
    return true;
  }
  return false;
}

}  // namespace rayproof::scene::detail
