#pragma once
/// Exact numbers of the certified fallback's kernels: GMP rationals (gmpxx's mpq_class) and a
/// small 3-vector of them. GMP only (no CGAL), so that the certified library's exact fallback links without CGAL.
/// Every finite double is a rational, so an input converts exactly (mpq_set_d); callers screen NaN
/// and infinities out first (CASES.md `invalid`).
#include <gmpxx.h>

#include "rayproof/vec3.h"

namespace rayproof::certified::fallback {

using Q = mpq_class;

/// -1, 0 or +1.
[[nodiscard]] inline int sign(const Q& q) { return sgn(q); }

/// A point or vector with rational coordinates. The arithmetic is spelled out (not Vec3<Q>'s
/// templates) so that no gmpxx expression template outlives its operands.
struct QVec {
  Q x, y, z;
};

/// An input vector (finite doubles), exactly.
[[nodiscard]] inline QVec exact3(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }

[[nodiscard]] inline QVec operator-(const QVec& a, const QVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[nodiscard]] inline QVec operator+(const QVec& a, const QVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[nodiscard]] inline QVec operator*(const Q& s, const QVec& a) { return {s * a.x, s * a.y, s * a.z}; }
[[nodiscard]] inline Q dot(const QVec& a, const QVec& b) { return Q(a.x * b.x) + Q(a.y * b.y) + Q(a.z * b.z); }
[[nodiscard]] inline QVec cross(const QVec& a, const QVec& b) {
  return {Q(a.y * b.z) - Q(a.z * b.y), Q(a.z * b.x) - Q(a.x * b.z), Q(a.x * b.y) - Q(a.y * b.x)};
}
/// det[a; b; c] = a . (b x c).
[[nodiscard]] inline Q det(const QVec& a, const QVec& b, const QVec& c) { return dot(a, cross(b, c)); }
[[nodiscard]] inline bool is_zero(const QVec& a) { return sign(a.x) == 0 && sign(a.y) == 0 && sign(a.z) == 0; }

}  // namespace rayproof::certified::fallback
