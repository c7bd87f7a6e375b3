// The distance judge's floating-point filters (verify/distance_filter.h). Unit roundoff of long
// double u = 2^-64; every double and every product of two doubles is a normal long double (its
// exponent reaches 2^-16382), so no step below underflows or overflows on finite input.
#include "verify/distance_filter.h"

#include <cmath>
#include <limits>

namespace rayproof::verify::detail {

namespace {

using L = long double;
constexpr L kU = 0x1p-64L;  // unit roundoff of the x87 format

struct LV {
  L x, y, z;
};
LV lv(const Vec3<double>& v) { return {v.x, v.y, v.z}; }
LV sub(const LV& a, const LV& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
L dot(const LV& a, const LV& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// s + t <= 1 exactly (TwoSum: s + t = sum + err exactly).
bool sum_at_most_one(L s, L t) {
  const L sum = s + t, bv = sum - s, err = (s - (sum - bv)) + (t - bv);
  return sum < 1 || (sum == 1 && err <= 0);
}

}  // namespace

bool distance_filter_available() {
  using N = std::numeric_limits<long double>;
  return N::radix == 2 && N::digits == 64 && N::max_exponent == 16384 && N::min_exponent == -16381;
}

bool certainly_within(const Vec3<double>& xd, const std::array<Vec3<double>, 3>& t, double bd) {
  if (!distance_filter_available() || !(bd > 0) || !std::isfinite(bd)) return false;
  const LV a = lv(t[0]), b = lv(t[1]), c = lv(t[2]), x = lv(xd);
  // A point q = o + s (e - o) + r (f - o) of the triangle (o, e, f its corners, s, r >= 0,
  // s + r <= 1 exactly), near x's nearest point: the textbook Voronoi regions (Ericson, Real-Time
  // Collision Detection 5.1.5) in long double. Their rounding only moves q within the triangle;
  // the bound below holds for any such q.
  const LV* o = &a;
  const LV* e = &b;
  const LV* f = &c;
  L s = 0, r = 0;
  const LV ab = sub(b, a), ac = sub(c, a), ap = sub(x, a), bp = sub(x, b), cp = sub(x, c);
  const L d1 = dot(ab, ap), d2 = dot(ac, ap), d3 = dot(ab, bp), d4 = dot(ac, bp), d5 = dot(ab, cp), d6 = dot(ac, cp);
  const L vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (d1 <= 0 && d2 <= 0) {
  } else if (d3 >= 0 && d4 <= d3) {
    o = &b;
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    s = d1 / (d1 - d3);
  } else if (d6 >= 0 && d5 <= d6) {
    o = &c;
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    r = d2 / (d2 - d6);
  } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    o = &b, e = &c, f = &a;
    s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
  } else {
    const L den = va + vb + vc;
    s = vb / den, r = vc / den;
  }
  if (!std::isfinite(s) || !std::isfinite(r)) return false;  // a zero-area triangle's 0/0
  s = std::fmin(std::fmax(s, L(0)), L(1)), r = std::fmin(std::fmax(r, L(0)), L(1));
  for (int k = 0; !sum_at_most_one(s, r); ++k) {  // r = 1 - s rounded, then down until s + r <= 1
    if (k == 3) return false;
    r = k == 0 ? L(1) - s : std::nextafter(r, L(0));
  }
  // q~ = o + (s (e - o) + r (f - o)), six roundings per coordinate: |q~ - q| <= u |o| + (4u + 8u^2)
  // (s |e - o| + r |f - o|) <= 10 u (|o| + |e| + |f|), the terms of a zero s or r left out (both
  // zero: q~ = o exactly); err >= 10 u of their sum over the coordinates, its own rounding included.
  const auto coord = [&](const LV& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); };
  L s2 = 0, total = 0;
  for (int k = 0; k < 3; ++k) {
    const L ok = coord(*o, k);
    const L q = ok + (s * (coord(*e, k) - ok) + r * (coord(*f, k) - ok));
    const L dk = coord(x, k) - q;
    s2 += dk * dk;
    if (s != 0 || r != 0) total += std::fabs(ok);
    if (s != 0) total += std::fabs(coord(*e, k));
    if (r != 0) total += std::fabs(coord(*f, k));
  }
  const L err = 16 * kU * total;
  // |x - q~|^2 <= s2 / (1 - u)^5, so |x - q~| <= 0.75 b (1 + 3u) when s2 <= (9/16) b^2; with
  // |q~ - q| <= err <= b / 8, |x - q| < b (b^2 exact in long double: b is a double).
  const L bl = bd;
  if (!std::isfinite(s2) || !std::isfinite(err)) return false;
  return s2 <= L(0.5625) * (bl * bl) && err <= bl / 8;
}

double rounded_point_distance(const Vec3<double>& p, const Vec3<double>& x) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!distance_filter_available()) return kNaN;
  const LV d = sub(lv(p), lv(x));
  // s2 = |p - x|^2 (1 + e), |e| <= (1 + u)^5 - 1; the square root correctly rounded: D = |p - x| is
  // within D~ (1 -+ 4u), so within [lo, hi] below (each rounded, still outside that range).
  const L s2 = d.x * d.x + d.y * d.y + d.z * d.z;
  const L root = std::sqrt(s2);
  const L lo = root * (1 - 8 * kU), hi = root * (1 + 8 * kU);
  const double dl = static_cast<double>(lo), dh = static_cast<double>(hi);  // to nearest: monotone
  if (dl != dh || !std::isfinite(dh)) return kNaN;
  if (dl != 0 && dl < std::numeric_limits<double>::min()) return kNaN;  // subnormal: the exact path
  return dl;
}

}  // namespace rayproof::verify::detail
