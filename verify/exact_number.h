#pragma once
/// Exact numbers of the verify layer: CGAL's Gmpq (GMP rationals) in CGAL's Simple_cartesian
/// kernel. Every finite double is a rational, so a case's fields convert exactly (mpq_set_d);
/// callers screen NaN and infinities out first (CASES.md `invalid`).
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>

#include "io/case_file.h"

namespace rayproof::verify {

using Q = CGAL::Gmpq;
using ExactKernel = CGAL::Simple_cartesian<Q>;
using Point = ExactKernel::Point_3;
using Vector = ExactKernel::Vector_3;

/// -1, 0 or +1.
[[nodiscard]] inline int sign(const Q& q) { return mpq_sgn(q.mpq()); }

/// Fields i, i+1, i+2 of a case (finite) as an exact point or vector.
[[nodiscard]] inline Point point_at(const io::Case& c, int i) {
  const auto k = static_cast<std::size_t>(i);
  return {Q(c.v[k]), Q(c.v[k + 1]), Q(c.v[k + 2])};
}
[[nodiscard]] inline Vector vector_at(const io::Case& c, int i) {
  const auto k = static_cast<std::size_t>(i);
  return {Q(c.v[k]), Q(c.v[k + 1]), Q(c.v[k + 2])};
}

}  // namespace rayproof::verify
