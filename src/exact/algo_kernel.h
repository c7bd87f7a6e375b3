#pragma once
/// The kernel interface of the exact algorithm (exact/algorithms.h) and its rounding
/// helpers. Includes neither CGAL nor gmpxx.
///
/// What K provides (all static; Q results may be taken by value or const reference):
///   Q, Point, Vector        types; Q(double) exact; Q + - * / Q, unary -, <, ==, +=, each
///                           convertible to Q; Point - Point and Vector + Vector -> Vector;
///                           Q * Vector -> Vector
///   point(v), vector(v)     a Vec3<double> (finite) as an exact Point / Vector
///   dot(v, w), cross(v, w), det(u, v, w) = u . (v x w), is_zero(v), coord(v, i) (i = 0, 1, 2)
///   sign(q)                 -1, 0 or +1
///   mpq(q)                  the GMP rational behind q (mpq_srcptr), for the MPFR rounding
#include "exact/rounding.h"

namespace rayproof::exact_algo {

/// q rounded to nearest double (shared MPFR code).
template <class K>
[[nodiscard]] double rounded(const typename K::Q& q) {
  return round_nearest(K::mpq(q));
}

/// num / den (den != 0) rounded to nearest.
template <class K>
[[nodiscard]] double rounded_quotient(const typename K::Q& num, const typename K::Q& den) {
  const typename K::Q q = num / den;
  return rounded<K>(q);
}

}  // namespace rayproof::exact_algo
