#pragma once
/// Exact ray/triangle (closed), on a kernel K (algo_kernel.h). Predicates: n = (p1 - p0) x
/// (p2 - p0) decides degeneracy; d . n and (p0 - o) . n decide parallel / coplanar; for a crossing
/// line, the barycentrics of the plane point are u_i / (d . n) with u_i = det(d, p_j - o, p_k - o)
/// (edges p1p2, p2p0, p0p1), which sum to d . n, so their signs and zeros are exact. Constructions:
/// t = (p0 - o) . n / (d . n) and, for a contact (interior, edge, vertex, behind), b1 = u_1 / (d .
/// n) and b2 = u_2 / (d . n), each rounded to nearest. A ray in the plane is clipped against the
/// three closed edge half-planes, exactly.
#include <optional>

#include "rayproof/hit.h"
#include "rayproof/ray.h"
#include "rayproof/triangle_common.h"
#include "exact/algo_kernel.h"

namespace rayproof::exact_algo {

/// Range of t >= 0 with o + t d in the closed triangle, for a ray lying in its plane. Edge j -> k
/// keeps the points P with det(p_k - p_j, P - p_j, n) >= 0 (the side of the third vertex, where
/// the determinant is n . n > 0); along the ray that is alpha + t beta >= 0, linear in t.
template <class K>
[[nodiscard]] TriangleHit<double> coplanar_range(const typename K::Point& o, const typename K::Vector& d,
                                                 const typename K::Point (&p)[3], const typename K::Vector& n) {
  using Q = typename K::Q;
  constexpr TriangleHit<double> kNone{Contact::coplanar};
  Q lo(0);
  std::optional<Q> hi;
  for (int j = 0; j < 3; ++j) {
    const int k = (j + 1) % 3;
    const typename K::Vector edge = p[k] - p[j];
    const Q alpha = K::det(edge, o - p[j], n);
    const Q beta = K::det(edge, d, n);
    if (K::sign(beta) == 0) {
      if (K::sign(alpha) < 0) return kNone;  // the ray runs outside this edge's line
      continue;
    }
    const Q minus_alpha = -alpha;
    const Q bound = minus_alpha / beta;
    if (K::sign(beta) > 0) {
      if (lo < bound) lo = bound;
    } else if (!hi || bound < *hi) {
      hi = bound;
    }
  }
  // d is not parallel to all three edges, and the betas sum to 0, so some beta < 0 set hi.
  if (!hi || *hi < lo) return kNone;
  return {Contact::coplanar, rounded<K>(lo), rounded<K>(*hi)};
}

template <class K>
[[nodiscard]] TriangleHit<double> triangle(const Ray<double>& ray, const Triangle<double>& tri) {
  using Q = typename K::Q;
  using Point = typename K::Point;
  const Point o = K::point(ray.o);
  const typename K::Vector d = K::vector(ray.d);
  const Point p[3] = {K::point(tri.p0), K::point(tri.p1), K::point(tri.p2)};
  const typename K::Vector n = K::cross(p[1] - p[0], p[2] - p[0]);
  if (K::is_zero(n)) return {Contact::degenerate};

  const Q den = K::dot(d, n);
  const Q num = K::dot(p[0] - o, n);
  const int s_den = K::sign(den);
  if (s_den == 0) {
    if (K::sign(num) != 0) return {Contact::parallel};
    return coplanar_range<K>(o, d, p, n);
  }

  // Barycentric i has the sign of u_i * den; u_2 follows from the sum.
  const Q u0 = K::det(d, p[1] - o, p[2] - o);
  const Q u1 = K::det(d, p[2] - o, p[0] - o);
  const Q u2 = den - u0 - u1;
  const int b[3] = {K::sign(u0) * s_den, K::sign(u1) * s_den, K::sign(u2) * s_den};
  if (b[0] < 0 || b[1] < 0 || b[2] < 0) return {Contact::miss};

  const double t = rounded_quotient<K>(num, den);
  const double b1 = rounded_quotient<K>(u1, den), b2 = rounded_quotient<K>(u2, den);
  if (K::sign(num) * s_den < 0) return {Contact::behind, t, kNaN<double>, b1, b2};
  const int zeros = (b[0] == 0) + (b[1] == 0) + (b[2] == 0);
  const Contact contact = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {contact, t, kNaN<double>, b1, b2};
}

}  // namespace rayproof::exact_algo
