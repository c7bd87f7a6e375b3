/// Exact ray/triangle (closed triangle). Predicates: n = (p1 - p0) x (p2 - p0) decides degeneracy;
/// d . n and (p0 - o) . n decide parallel / coplanar; for a crossing line, the barycentrics of the
/// plane point are u_i / (d . n) with u_i = det(d, p_j - o, p_k - o) (edges p1p2, p2p0, p0p1),
/// which sum to d . n, so their signs and zeros are exact. Constructions: t = (p0 - o) . n / (d . n)
/// and, for a contact (interior, edge, vertex, behind), b1 = u_1 / (d . n) and b2 = u_2 / (d . n),
/// each rounded to nearest. A ray in the plane is clipped against the three closed edge
/// half-planes, exactly. CGAL's Gmpq and Simple_cartesian throughout (exact_number.h).
#include <array>
#include <cmath>
#include <optional>

#include "verify/exact.h"
#include "verify/exact_kinds.h"
#include "verify/exact_number.h"
#include "verify/exact_rounding.h"

namespace rayproof::verify {

namespace {

/// Range of t >= 0 with o + t d in the closed triangle, for a ray lying in its plane. Edge j -> k
/// keeps the points P with det(p_k - p_j, P - p_j, n) >= 0 (the side of the third vertex, where
/// the determinant is n . n > 0); along the ray that is alpha + t beta >= 0, linear in t.
TriangleHit<double> coplanar_range(const Point& o, const Vector& d, const Point (&p)[3], const Vector& n) {
  constexpr TriangleHit<double> kNone{Contact::coplanar};
  Q lo(0);
  std::optional<Q> hi;
  for (int j = 0; j < 3; ++j) {
    const int k = (j + 1) % 3;
    const Vector edge = p[k] - p[j];
    const Q alpha = CGAL::determinant(edge, o - p[j], n);
    const Q beta = CGAL::determinant(edge, d, n);
    if (sign(beta) == 0) {
      if (sign(alpha) < 0) return kNone;  // the ray runs outside this edge's line
      continue;
    }
    const Q bound = -alpha / beta;
    if (sign(beta) > 0) {
      if (lo < bound) lo = bound;
    } else if (!hi || bound < *hi) {
      hi = bound;
    }
  }
  // d is not parallel to all three edges, and the betas sum to 0, so some beta < 0 set hi.
  if (!hi || *hi < lo) return kNone;
  return {Contact::coplanar, round_nearest(lo), round_nearest(*hi)};
}

}  // namespace

TriangleHit<double> exact_triangle(const Ray<double>& ray, const Triangle<double>& tri) {
  const Point o = point_of(ray.o);
  const Vector d = vector_of(ray.d);
  const Point p[3] = {point_of(tri.p0), point_of(tri.p1), point_of(tri.p2)};
  const Vector n = CGAL::cross_product(p[1] - p[0], p[2] - p[0]);
  if (n == CGAL::NULL_VECTOR) return {Contact::degenerate};

  const Q den = d * n;
  const Q num = (p[0] - o) * n;
  const int s_den = sign(den);
  if (s_den == 0) {
    if (sign(num) != 0) return {Contact::parallel};
    return coplanar_range(o, d, p, n);
  }

  // Barycentric i has the sign of u_i * den; u_2 follows from the sum.
  const Q u0 = CGAL::determinant(d, p[1] - o, p[2] - o);
  const Q u1 = CGAL::determinant(d, p[2] - o, p[0] - o);
  const Q u2 = den - u0 - u1;
  const int b[3] = {sign(u0) * s_den, sign(u1) * s_den, sign(u2) * s_den};
  if (b[0] < 0 || b[1] < 0 || b[2] < 0) return {Contact::miss};

  const double t = round_nearest(num / den);
  const double b1 = round_nearest(u1 / den), b2 = round_nearest(u2 / den);
  if (sign(num) * s_den < 0) return {Contact::behind, t, kNaN<double>, b1, b2};
  const int zeros = (b[0] == 0) + (b[1] == 0) + (b[2] == 0);
  const Contact contact = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {contact, t, kNaN<double>, b1, b2};
}

}  // namespace rayproof::verify

namespace rayproof::verify {

std::optional<std::array<double, 2>> exact_barycentrics(const io::Case& c) {
  if (c.kind != io::Kind::triangle) return std::nullopt;
  for (int i = 0; i < 15; ++i)
    if (!std::isfinite(c.v[static_cast<std::size_t>(i)])) return std::nullopt;
  const auto field = [&](int i) { return Vec3<double>{c.v[i], c.v[i + 1], c.v[i + 2]}; };
  const Point o = point_of(field(0));
  const Vector d = vector_of(field(3));
  const Point p[3] = {point_of(field(6)), point_of(field(9)), point_of(field(12))};
  const Vector n = CGAL::cross_product(p[1] - p[0], p[2] - p[0]);
  const Q den = d * n;
  if (sign(den) == 0) return std::nullopt;  // degenerate, parallel or coplanar: no single plane point
  const Q u1 = CGAL::determinant(d, p[2] - o, p[0] - o);
  const Q u0 = CGAL::determinant(d, p[1] - o, p[2] - o);
  const Q u2 = den - u0 - u1;
  return std::array<double, 2>{round_nearest(u1 / den), round_nearest(u2 / den)};
}

}  // namespace rayproof::verify
