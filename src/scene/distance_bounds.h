#pragma once
/// Plain-double bounds of the closest-point search (internal): a rigorous lower bound of the
/// squared distance from p to a triangle's box, and a rigorous upper bound of the squared distance
/// from p to the triangle (both passes of distance.cpp and the wide first pass, distance_wide.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "rayproof/vec3.h"

namespace rayproof::scene::detail {

/// Lower bound of the squared distance from p to a triangle's box (rounded down).
inline double triangle_box_lb(const std::array<Vec3<double>, 3>& tri, const Vec3<double>& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double a = tri[0][k], b = tri[1][k], c = tri[2][k];
    const double lo = std::min({a, b, c}), hi = std::max({a, b, c});
    const double g = std::max({lo - p[k], p[k] - hi, 0.0});
    s += g * g;
  }
  return std::max(0.0, s * (1 - 0x1p-49) - 0x1p-1070);
}

/// A rigorous upper bound of the squared distance from p to a triangle, in plain double: the
/// distance to a point q of the triangle (weights found by the Voronoi regions in double, clamped
/// so that they are surely nonnegative and sum to at most 1) plus a bound on the rounding of q.
/// `dir`, when given, gets p - q as computed (for lower_bound_along).
inline double upper_bound(const std::array<Vec3<double>, 3>& t, const Vec3<double>& p, Vec3<double>* dir = nullptr) {
  const Vec3<double> a = t[0], ab = t[1] - t[0], ac = t[2] - t[0], ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  const Vec3<double> bp = p - t[1], cp = p - t[2];
  const double d3 = dot(ab, bp), d4 = dot(ac, bp), d5 = dot(ab, cp), d6 = dot(ac, cp);
  double v = 0, w = 0;
  if (d1 <= 0 && d2 <= 0) v = 0, w = 0;
  else if (d3 >= 0 && d4 <= d3) v = 1, w = 0;
  else if (d6 >= 0 && d5 <= d6) v = 0, w = 1;
  else {
    const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) v = d1 / (d1 - d3);
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) w = d2 / (d2 - d6);
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) w = (d4 - d3) / ((d4 - d3) + (d5 - d6)), v = 1 - w;
    else v = vb / (va + vb + vc), w = vc / (va + vb + vc);
  }
  if (!(v >= 0)) v = 0;  // NaN too
  if (!(w >= 0)) w = 0;
  if (const double sum = v + w; sum > 1 - 0x1p-50) v *= (1 - 0x1p-49) / sum, w *= (1 - 0x1p-49) / sum;
  // q = a + v ab + w ac exactly is on the triangle; its double evaluation is within delta of it.
  double e2 = 0, delta = 0;
  for (int k = 0; k < 3; ++k) {
    const double q = a[k] + v * ab[k] + w * ac[k];
    delta += (std::abs(a[k]) + v * std::abs(ab[k]) + w * std::abs(ac[k])) * 0x1p-50;
    const double d = p[k] - q;
    if (dir) (*dir)[k] = d;
    e2 += d * d;
  }
  // 2^-520: above any underflow of the squares (it only loosens the bound below 2^-1000).
  const double r = std::sqrt(e2) * (1 + 0x1p-50) + delta * (1 + 0x1p-50) + 0x1p-520;
  return r * r * (1 + 0x1p-50);
}

/// A rigorous lower bound of the squared distance from p to a triangle, for any direction e: every
/// point x of the triangle (convex: a combination of its vertices) has (p - x) . e >= m =
/// min_k (p - v_k) . e, so |p - x| >= m / |e| when m > 0. With e = p - q for q near the closest
/// point (upper_bound's), the bound is the distance itself up to rounding: at the exact closest
/// point q*, every vertex has (v - q*) . (p - q*) <= 0. Each dot product is computed in double and
/// lowered by a bound on its rounding (2^-50 of the sum of its terms' magnitudes: three differences
/// and three products and two sums, each 2^-53 relative, plus 2^-1060 against underflow); |e| is
/// rounded up, the quotient and the square down. 0 when m <= 0 or on overflow.
inline double lower_bound_along(const std::array<Vec3<double>, 3>& t, const Vec3<double>& p, const Vec3<double>& e) {
  double m = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double a0 = p.x - t[k].x, a1 = p.y - t[k].y, a2 = p.z - t[k].z;
    const double s = a0 * e.x + a1 * e.y + a2 * e.z;
    const double err = (std::abs(a0 * e.x) + std::abs(a1 * e.y) + std::abs(a2 * e.z)) * 0x1p-50 + 0x1p-1060;
    m = std::min(m, s - err);
  }
  if (!(m > 0)) return 0;
  const double ne = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z) * (1 + 0x1p-50) + 0x1p-1000;
  const double lb = m / ne * (1 - 0x1p-50);
  const double lb2 = lb * lb * (1 - 0x1p-50) - 0x1p-1070;
  return lb2 > 0 && lb2 < std::numeric_limits<double>::infinity() ? lb2 : 0.0;
}

}  // namespace rayproof::scene::detail
