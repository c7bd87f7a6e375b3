#pragma once
/// Floating-point helpers in one place: error bounds (gamma), neighbours, ulp distance,
/// difference of products. Kernels use these and never invent an epsilon.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace rayproof {

/// Unit roundoff u = eps/2 of T.
template <class T> inline constexpr T unit_roundoff = std::numeric_limits<T>::epsilon() / 2;

/// gamma(n) = n u / (1 - n u): bound on the relative error of n chained roundings (Higham 2002, §3.1;
/// pbrt-v4 uses the same bound).
template <class T> constexpr T gamma(int n) { return (n * unit_roundoff<T>) / (1 - n * unit_roundoff<T>); }

template <class T> inline constexpr T kNaN = std::numeric_limits<T>::quiet_NaN();

/// a*b - c*d with one rounding error more than a single product (Kahan's FMA trick).
template <class T> inline T difference_of_products(T a, T b, T c, T d) {
  T cd = c * d;
  T err = std::fma(-c, d, cd);
  T dop = std::fma(a, b, -cd);
  return dop + err;
}

/// Ordered integer key of a float or double: adjacent values differ by 1, -0 and +0 coincide.
template <class T> constexpr std::int64_t ordered_bits(T x) {
  if constexpr (std::is_same_v<T, float>) {
    std::int32_t i = std::bit_cast<std::int32_t>(x);
    return i < 0 ? -static_cast<std::int64_t>(i & 0x7fffffff) : i;
  } else {
    std::int64_t i = std::bit_cast<std::int64_t>(x);
    return i < 0 ? -(i & 0x7fffffffffffffffLL) : i;
  }
}

/// Number of representable T values between a and b (0 when equal, -0 == +0). Saturates; NaN and
/// mixed infinities give the maximum.
template <class T> inline std::uint64_t ulp_distance(T a, T b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::uint64_t>::max();
  if (a == b) return 0;
  std::int64_t ia = ordered_bits(a), ib = ordered_bits(b);
  // Subtract in unsigned arithmetic: the distance always fits in 64 bits, the signed difference
  // of keys of opposite sign may not.
  const auto ua = static_cast<std::uint64_t>(ia), ub = static_cast<std::uint64_t>(ib);
  return ia > ib ? ua - ub : ub - ua;
}

template <class T> inline T next_up(T x) { return std::nextafter(x, std::numeric_limits<T>::infinity()); }
template <class T> inline T next_down(T x) { return std::nextafter(x, -std::numeric_limits<T>::infinity()); }

}  // namespace rayproof

namespace rayproof {

/// An unevaluated sum hi + lo (the result of an error-free transformation).
template <class T>
struct TwoTerm {
  T hi, lo;
};

/// a*b = hi + lo exactly (FMA), unless the product overflows or underflows.
template <class T> inline TwoTerm<T> two_prod(T a, T b) {
  const T p = a * b;
  return {p, std::fma(a, b, -p)};
}

/// a+b = hi + lo exactly (Knuth's TwoSum), unless the sum overflows.
template <class T> inline TwoTerm<T> two_sum(T a, T b) {
  const T s = a + b;
  const T bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

/// a0 b0 + a1 b1 + a2 b2 as accurate as if computed in twice the precision and rounded once
/// (Dot2, Ogita, Rump & Oishi, SIAM J. Sci. Comput. 2005); the sign is right unless the sum
/// cancels to below about u^2 of its terms.
template <class T> inline T compensated_dot3(T a0, T b0, T a1, T b1, T a2, T b2) {
  const TwoTerm<T> p0 = two_prod(a0, b0), p1 = two_prod(a1, b1), p2 = two_prod(a2, b2);
  const TwoTerm<T> s1 = two_sum(p0.hi, p1.hi);
  const TwoTerm<T> s2 = two_sum(s1.hi, p2.hi);
  return s2.hi + (((p0.lo + p1.lo) + p2.lo) + (s1.lo + s2.lo));
}

}  // namespace rayproof
