// The distance judge's floating-point filters (verify/distance_filter.h). Unit roundoff of long
// double u = 2^-64; every double and every product of two doubles is a normal long double (its
// exponent reaches 2^-16382), so no step below underflows or overflows on finite input.
#include "verify/distance_filter.h"

#include <cfenv>
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

/// A dot product of two vectors of differences of doubles (each difference rounded once): its
/// value v and the sum a of its terms' magnitudes. Five roundings per term: |v - exact| <= gamma_5
/// of the exact terms' magnitudes <= 6u a.
struct Dot {
  L v, a;
};
Dot dot_of(const LV& x, const LV& y) {
  const L t0 = x.x * y.x, t1 = x.y * y.y, t2 = x.z * y.z;
  return {t0 + t1 + t2, std::fabs(t0) + std::fabs(t1) + std::fabs(t2)};
}
/// The exact value of d is certainly <= 0 (>= 0): v + 8u a rounded keeps the sign of v + 8u a, and
/// 8u a rounded is at least 6u a.
bool at_most_zero(const Dot& d) { return d.v + 8 * kU * d.a <= 0; }
bool at_least_zero(const Dot& d) { return d.v - 8 * kU * d.a >= 0; }

bool same(const Vec3<double>& a, const Vec3<double>& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/// The nearest point of the triangle (v, e1, e2) to p is certainly its corner v: p - v has a
/// nonpositive dot product with both edges from v (the triangle lies in the cone they span).
bool corner_nearest(const LV& p, const LV& v, const LV& e1, const LV& e2) {
  const LV d = sub(p, v);
  return at_most_zero(dot_of(sub(e1, v), d)) && at_most_zero(dot_of(sub(e2, v), d));
}

/// The nearest point of the triangle (v, w, x) to p is certainly on its edge v-w (v != w): with
/// e = w - v, d = p - v, f = x - v, L = e.e and s = e.d, the projection q = v + (s/L) e of p on the
/// edge's line is on the edge (0 <= s <= L; L - s = e.(w - p)) and (p - q).(x - q) = G / L <= 0 for
/// G = L (d.f) - s (e.f), so that (p - q).(y - q) <= 0 on the whole triangle. G's error: each dot
/// within 6u of its magnitudes, the products and the difference rounded: below 14.1u (aL aP + as aQ).
bool edge_nearest(const LV& p, const LV& v, const LV& w, const LV& x) {
  const LV e = sub(w, v), d = sub(p, v), f = sub(x, v);
  const Dot s = dot_of(e, d);
  if (!at_least_zero(s) || !at_least_zero(dot_of(e, sub(w, p)))) return false;
  const Dot l = dot_of(e, e), pf = dot_of(d, f), q = dot_of(e, f);
  const L g = l.v * pf.v - s.v * q.v, bound = 16 * kU * (l.a * pf.a + s.a * q.a);
  return std::isfinite(g) && std::isfinite(bound) && g + bound <= 0;
}

}  // namespace

bool distance_filter_available() {
  using N = std::numeric_limits<long double>;
  if (!(N::radix == 2 && N::digits == 64 && N::max_exponent == 16384 && N::min_exponent == -16381)) return false;
  // At run time too: rounding to nearest, and the x87 precision control at 64 bits (not lowered to
  // double's 53 by some library): 1 + 2^-63 is then exact.
  volatile L one = 1, tiny = 0x1p-63L;
  return std::fegetround() == FE_TONEAREST && one + tiny != one;
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

bool certainly_tied(const Vec3<double>& pd, const std::array<Vec3<double>, 3>& t1, const std::array<Vec3<double>, 3>& t2) {
  if (!distance_filter_available()) return false;
  const LV p = lv(pd);
  const LV a[3] = {lv(t1[0]), lv(t1[1]), lv(t1[2])}, b[3] = {lv(t2[0]), lv(t2[1]), lv(t2[2])};
  int match[3] = {-1, -1, -1};  // t1's corner i is t2's corner match[i]
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3 && match[i] < 0; ++j)
      if (same(t1[i], t2[j])) match[i] = j;
  // A shared corner nearest on both.
  for (int i = 0; i < 3; ++i) {
    const int j = match[i];
    if (j >= 0 && corner_nearest(p, a[i], a[(i + 1) % 3], a[(i + 2) % 3]) &&
        corner_nearest(p, b[j], b[(j + 1) % 3], b[(j + 2) % 3]))
      return true;
  }
  // A shared edge (two distinct corners) nearest on both; x the third corner of each.
  for (int i = 0; i < 3; ++i) {
    const int k = (i + 1) % 3, j = match[i], m = match[k];
    if (j < 0 || m < 0 || j == m || same(t1[i], t1[k])) continue;
    if (edge_nearest(p, a[i], a[k], a[3 - i - k]) && edge_nearest(p, a[i], a[k], b[3 - j - m])) return true;
  }
  return false;
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
