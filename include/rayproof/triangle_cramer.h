#pragma once
/// Ray/triangle by Cramer's rule, as in the worked problems: M x = b with M = [-D, E1, E2],
/// x = [t, b1, b2], b = S = o - p0; each unknown is det(M with a column replaced by S) / det(M),
/// the determinants expanded by cofactors along the first row.
#include "rayproof/triangle_common.h"

namespace rayproof {

/// det[c0 c1 c2] of the 3x3 matrix with columns c0, c1, c2.
template <class T>
[[nodiscard]] constexpr T det3_columns(Vec3<T> c0, Vec3<T> c1, Vec3<T> c2) {
  return c0.x * (c1.y * c2.z - c2.y * c1.z) - c1.x * (c0.y * c2.z - c2.y * c0.z) +
         c2.x * (c0.y * c1.z - c1.y * c0.z);
}

template <class T>
[[nodiscard]] TriangleHit<T> intersect_cramer(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  const Vec3<T> e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  const Vec3<T> n = cross(e1, e2);
  if (is_zero(n)) return {Contact::degenerate};
  const Vec3<T> s = ray.o - tri.p0;
  const Vec3<T> md = -ray.d;
  const T det = det3_columns(md, e1, e2);
  if (det == T(0)) {
    if (dot(s, n) != T(0)) return {Contact::parallel};
    return coplanar_range(ray, tri, n);
  }
  const T t = det3_columns(s, e1, e2) / det;
  const T b1 = det3_columns(md, s, e2) / det;
  const T b2 = det3_columns(md, e1, s) / det;
  return classify_barycentric(t, b1, b2);
}

}  // namespace rayproof
