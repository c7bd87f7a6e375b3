#pragma once
/// The one double-double of the certified filters: a value carried as hi + lo (TwoTerm<double>, the
/// result type of float_util.h's error-free two_sum and two_prod), and its normalised arithmetic,
/// each result renormalised by fast_two_sum so that |lo| <= ulp(hi) / 2. The triangle and sphere
/// stages of certified_fma.h build their own unnormalised sums of such pairs; the closest-point
/// filter (src/scene/distance_filter.h) uses sum, difference, product and quotient below.
/// The closest-point filter bounds one operation's relative error by 2^-100, above the published
/// bounds of about 10 * 2^-106 for such sums, products and quotients. Products use std::fma (hardware
/// where the target has it, else libm's: correct, slower).
#include <cmath>

#include "rayproof/float_util.h"

namespace rayproof::certified::dd {

/// hi + lo, not necessarily normalised (certified_fma.h builds unnormalised ones).
using DD = TwoTerm<double>;

/// a + b = hi + lo exactly, when |a| >= |b| or a = 0 (Dekker's Fast2Sum).
[[nodiscard]] inline DD fast_two_sum(double a, double b) {
  const double s = a + b;
  return {s, b - (s - a)};
}

/// a + b, normalised.
[[nodiscard]] inline DD sum(DD a, DD b) {
  const DD s = two_sum(a.hi, b.hi), t = two_sum(a.lo, b.lo);
  const DD v = fast_two_sum(s.hi, s.lo + t.hi);
  return fast_two_sum(v.hi, t.lo + v.lo);
}

/// a - b, normalised.
[[nodiscard]] inline DD difference(DD a, DD b) { return sum(a, DD{-b.hi, -b.lo}); }

/// a b, normalised (the lo * lo term dropped).
[[nodiscard]] inline DD product(DD a, DD b) {
  const double p = a.hi * b.hi;
  double e = std::fma(a.hi, b.hi, -p);
  e += a.hi * b.lo + a.lo * b.hi;
  return fast_two_sum(p, e);
}

/// a / b, normalised: three quotient digits, the remainder corrected twice.
[[nodiscard]] inline DD quotient(DD a, DD b) {
  const double q1 = a.hi / b.hi;
  DD r = difference(a, product(DD{q1, 0}, b));
  const double q2 = r.hi / b.hi;
  r = difference(r, product(DD{q2, 0}, b));
  const double q3 = r.hi / b.hi;
  return sum(fast_two_sum(q1, q2), DD{q3, 0});
}

}  // namespace rayproof::certified::dd
