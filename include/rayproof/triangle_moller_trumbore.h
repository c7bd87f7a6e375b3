#pragma once
/// Möller–Trumbore ray/triangle test (Möller & Trumbore, JGT 1997), as in the worked problems:
/// [t b1 b2] = 1/(S1·E1) [S2·E2, S1·S, S2·D] with E1 = p1-p0, E2 = p2-p0, S = o-p0,
/// S1 = D×E2, S2 = S×E1.
#include "rayproof/triangle_common.h"

namespace rayproof {

template <class T>
[[nodiscard]] TriangleHit<T> intersect_moller_trumbore(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  const Vec3<T> e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  const Vec3<T> n = cross(e1, e2);
  if (is_zero(n)) return {Contact::degenerate};
  const Vec3<T> s = ray.o - tri.p0;
  const Vec3<T> s1 = cross(ray.d, e2);
  const T det = dot(s1, e1);
  if (det == T(0)) {  // d in the plane (up to rounding): coplanar when o is in it too
    if (dot(s, n) != T(0)) return {Contact::parallel};
    return coplanar_range(ray, tri, n);
  }
  const Vec3<T> s2 = cross(s, e1);
  const T inv = T(1) / det;
  return classify_barycentric(dot(s2, e2) * inv, dot(s1, s) * inv, dot(s2, ray.d) * inv);
}

}  // namespace rayproof
