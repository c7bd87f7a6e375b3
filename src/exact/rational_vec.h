#pragma once
/// The vector of rationals of the exact stages: three gmpxx mpq_class coordinates, exact for every
/// finite double (rational(v)). The certified fallback's kernel (fallback.cpp) and the scene's exact
/// stages (the closest point's, src/scene/distance_exact.cpp) compute on it. The arithmetic is spelled
/// out, each product materialized, so that no gmpxx expression template outlives its operands.
#include <gmpxx.h>

#include "rayproof/vec3.h"

namespace rayproof::exact_algo {

/// A point or vector with rational coordinates.
struct QVec {
  mpq_class x, y, z;
};

/// v exactly (v finite: a NaN or infinite coordinate is the caller's to screen out).
[[nodiscard]] inline QVec rational(const Vec3<double>& v) { return {mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)}; }

[[nodiscard]] inline QVec operator-(const QVec& a, const QVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[nodiscard]] inline QVec operator+(const QVec& a, const QVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[nodiscard]] inline QVec operator*(const mpq_class& s, const QVec& a) { return {s * a.x, s * a.y, s * a.z}; }

[[nodiscard]] inline mpq_class dot(const QVec& a, const QVec& b) {
  return mpq_class(a.x * b.x) + mpq_class(a.y * b.y) + mpq_class(a.z * b.z);
}
[[nodiscard]] inline QVec cross(const QVec& a, const QVec& b) {
  return {mpq_class(a.y * b.z) - mpq_class(a.z * b.y), mpq_class(a.z * b.x) - mpq_class(a.x * b.z),
          mpq_class(a.x * b.y) - mpq_class(a.y * b.x)};
}

}  // namespace rayproof::exact_algo
