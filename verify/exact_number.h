#pragma once
/// Exact numbers of the ground truth (rayproof::exact, the `exact` method): CGAL's Gmpq (GMP
/// rationals) in CGAL's Simple_cartesian kernel. Every finite double is a rational, so an input
/// converts exactly (mpq_set_d); callers screen NaN and infinities out first (CASES.md `invalid`).
/// The certified tier's fallback (fallback_number.h) is a separate implementation on gmpxx.
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>

#include "rayproof/vec3.h"

namespace rayproof::verify {

using Q = CGAL::Gmpq;
using ExactKernel = CGAL::Simple_cartesian<Q>;
using Point = ExactKernel::Point_3;
using Vector = ExactKernel::Vector_3;

/// -1, 0 or +1.
[[nodiscard]] inline int sign(const Q& q) { return mpq_sgn(q.mpq()); }

/// An input (finite doubles) as an exact point or vector.
[[nodiscard]] inline Point point_of(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
[[nodiscard]] inline Vector vector_of(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }

}  // namespace rayproof::verify
