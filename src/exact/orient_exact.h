#pragma once
/// The exact signs of rayproof/orient.h for every double input: the filter and the expansions
/// first, GMP when the inputs leave the expansions' exponent window (orient_exact.cpp: the signs in
/// integers, the inputs scaled by one power of two; the value in rationals).
#include "rayproof/orient.h"

namespace rayproof::certified {

[[nodiscard]] int orient2d_gmp(double au, double av, double bu, double bv, double pu, double pv);
[[nodiscard]] int orient3d_gmp(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                               const Vec3<double>& p);

/// orient3d's value as a double (GMP: truncated towards zero, so within one ulp).
[[nodiscard]] double orient3d_value_gmp(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                        const Vec3<double>& p);
[[nodiscard]] inline double orient3d_value_exact(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                                 const Vec3<double>& p) {
  const double x = orient::orient3d_value(a, b, c, p);
  return x == x ? x : orient3d_value_gmp(a, b, c, p);
}

[[nodiscard]] inline int orient2d_exact(double au, double av, double bu, double bv, double pu, double pv) {
  const int s = orient::orient2d(au, av, bu, bv, pu, pv);
  return s != orient::kUnknown ? s : orient2d_gmp(au, av, bu, bv, pu, pv);
}
[[nodiscard]] inline int orient3d_exact(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                        const Vec3<double>& p) {
  const int s = orient::orient3d(a, b, c, p);
  return s != orient::kUnknown ? s : orient3d_gmp(a, b, c, p);
}

}  // namespace rayproof::certified
