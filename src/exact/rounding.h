#pragma once
/// Exact real -> double, rounded to nearest with ties to even (IEEE 754 roundTiesToEven),
/// subnormal and overflowing results included: the rounding tools of the exact algorithm
/// (exact/algorithms.h), shared by both of its instantiations (the ground truth on CGAL's
/// Gmpq, the certified fallback on gmpxx's mpq_class). The MPFR part works on GMP's mpq_t, which
/// both number types expose, and is compiled once, into rayproof_certified (rounding.cpp).
/// GMP's C header only: no CGAL, no gmpxx.
///  - round_nearest(q): a rational, rounded by MPFR (one correctly rounded conversion).
///  - approximate_roots: a starting point for the quadric roots, from MPFR at 256 bits.
///  - round_by_comparison(candidate, sign_vs): a real known only through exact comparisons with
///    rationals (a quadric root); the candidate is moved until the real lies inside its rounding
///    interval, which is then proven by those comparisons (a template over the number type).
#include <gmp.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rayproof::exact_algo {

/// q rounded to nearest double, ties to even; +-inf past the overflow threshold. Zero is +0.0.
[[nodiscard]] double round_nearest(mpq_srcptr q);

/// Approximations (about 250 bits, then rounded to double) of the two roots of a t^2 + 2 b t + c
/// with a > 0 and disc = b^2 - a c > 0, by the cancellation-free form k = -(b + sign(b) sqrt(disc)),
/// roots k / a and c / k. Only a starting point for round_by_comparison.
struct RootPair {
  double lower, upper;
};
[[nodiscard]] RootPair approximate_roots(mpq_srcptr a, mpq_srcptr b, mpq_srcptr c, mpq_srcptr disc);

/// The value a double stands for when it bounds a rounding interval: itself, and +-2^1024 for
/// +-inf (IEEE: a real of magnitude >= DBL_MAX + ulp/2 = midpoint(DBL_MAX, 2^1024) rounds to inf).
template <class Q>
[[nodiscard]] Q interval_value(double x) {
  if (!std::isinf(x)) return Q(x);
  Q two1024 = Q(std::ldexp(1.0, 1023)) * Q(2);
  if (x < 0) two1024 = -two1024;
  return two1024;
}

/// The exact midpoint of two adjacent doubles (infinities standing for +-2^1024).
template <class Q>
[[nodiscard]] Q midpoint(double a, double b) {
  return Q(interval_value<Q>(a) + interval_value<Q>(b)) / Q(2);
}

/// Of two adjacent doubles, the one with an even significand (inf counts as even, as 2^1024).
[[nodiscard]] inline double even_of(double a, double b) {
  return (std::bit_cast<std::uint64_t>(a) & 1U) == 0 ? a : b;
}

/// The double nearest to a real x, ties to even. sign_vs(m) must return the exact sign of x - m for
/// a rational m (of type Q). candidate: any double near x (a high-precision approximation); each
/// step moves it one ulp towards x and never back, so a candidate within an ulp costs at most one
/// step. Why it is correct: c is the nearest double exactly when x lies strictly between the
/// midpoints of c with its two neighbours; on a midpoint (a tie) the neighbour with the even
/// significand wins; +-inf stands for +-2^1024, so a real at or beyond midpoint(DBL_MAX, 2^1024)
/// gives inf as IEEE 754 prescribes. A zero result carries the sign of x (+0.0 when x is exactly 0).
template <class Q, class SignVs>
[[nodiscard]] double round_by_comparison(double candidate, SignVs&& sign_vs) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double c = std::isnan(candidate) ? 0.0 : candidate;
  double r = 0;
  for (;;) {
    const double below = std::nextafter(c, -inf), above = std::nextafter(c, inf);
    if (c != -inf) {  // -inf has no lower midpoint
      const int s_lo = sign_vs(midpoint<Q>(below, c));
      if (s_lo < 0) { c = below; continue; }
      if (s_lo == 0) { r = even_of(below, c); break; }
    }
    if (c != inf) {  // +inf has no upper midpoint
      const int s_hi = sign_vs(midpoint<Q>(c, above));
      if (s_hi > 0) { c = above; continue; }
      if (s_hi == 0) { r = even_of(c, above); break; }
    }
    r = c;
    break;
  }
  if (r == 0) r = sign_vs(Q(0)) < 0 ? -0.0 : 0.0;
  return r;
}

}  // namespace rayproof::exact_algo
