#pragma once
/// Ray/triangle with a precomputed transform: Baldwin & Weber, "Fast Ray-Triangle Intersections by
/// Coordinate Transformation", JCGT 5(3), 2016. Each triangle stores the affine map that takes it to
/// the unit triangle (0,0,0), (1,0,0), (0,1,0) with its normal along z: row 2 is the plane equation
/// divided by the dominant normal component, rows 0 and 1 the barycentrics b1, b2 of the point
/// projected along that axis. A ray costs two dot products for t and two more for b1, b2.
#include "rayproof/triangle_common.h"

namespace rayproof {

/// The transform of one triangle: b1 = r0 . x + c0, b2 = r1 . x + c1, plane distance r2 . x + c2.
template <class T>
struct BaldwinWeberTriangle {
  Vec3<T> r0, r1, r2;
  T c0{}, c1{}, c2{};
  bool degenerate = true;  ///< (p1-p0) x (p2-p0) = 0: no transform
};

template <class T>
[[nodiscard]] BaldwinWeberTriangle<T> baldwin_weber_prepare(const Triangle<T>& tri) {
  const Vec3<T> e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  const Vec3<T> n = cross(e1, e2);
  BaldwinWeberTriangle<T> m;
  if (is_zero(n)) return m;
  // Project along the dominant normal axis k; (i, j, k) is a cyclic permutation of (x, y, z).
  const int k = max_abs_axis(n), i = (k + 1) % 3, j = (k + 2) % 3;
  const T inv = T(1) / n[k];
  // b1 = ((x - p0) x e2)_k / n_k and b2 = (e1 x (x - p0))_k / n_k, expanded as affine maps.
  m.r0[i] = e2[j] * inv;
  m.r0[j] = -e2[i] * inv;
  m.c0 = cross(tri.p2, tri.p0)[k] * inv;
  m.r1[i] = -e1[j] * inv;
  m.r1[j] = e1[i] * inv;
  m.c1 = -cross(tri.p1, tri.p0)[k] * inv;
  // Plane distance (x - p0) . n / n_k: 1 on axis k.
  m.r2[i] = n[i] * inv;
  m.r2[j] = n[j] * inv;
  m.r2[k] = T(1);
  m.c2 = -dot(tri.p0, n) * inv;
  m.degenerate = false;
  return m;
}

/// The test with a prepared transform. `parallel` stands for a direction in the plane (coplanar or
/// not); the front door below tells them apart.
template <class T>
[[nodiscard]] TriangleHit<T> intersect_baldwin_weber(const Ray<T>& ray, const BaldwinWeberTriangle<T>& m) {
  if (m.degenerate) return {Contact::degenerate};
  // Origin height above the plane and direction rate, in the triangle's space.
  const T oz = dot(m.r2, ray.o) + m.c2;
  const T dz = dot(m.r2, ray.d);
  if (dz == T(0)) return {Contact::parallel};
  const T t = -oz / dz;
  // Barycentrics of the plane point o + t d.
  const Vec3<T> p = ray.at(t);
  return classify_barycentric(t, dot(m.r0, p) + m.c0, dot(m.r1, p) + m.c1);
}

template <class T>
[[nodiscard]] TriangleHit<T> intersect_baldwin_weber(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  const BaldwinWeberTriangle<T> m = baldwin_weber_prepare(tri);
  const TriangleHit<T> h = intersect_baldwin_weber(ray, m);
  if (h.contact != Contact::parallel) return h;
  const Vec3<T> n = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
  if (dot(ray.o - tri.p0, n) != T(0)) return {Contact::parallel};
  return coplanar_range(ray, tri, n);
}

}  // namespace rayproof
