#pragma once
/// Ray/triangle by Plücker edge tests in the form of Embree's robust mode (Wald et al., "Embree: A
/// Kernel Framework for Efficient CPU Ray Tracing", SIGGRAPH 2014; kernels/geometry/
/// triangle_intersector_pluecker.h): with vertices v_i relative to the ray origin, the edge a -> b
/// gives d . ((b - a) x (b + a)) = 2 det(d, a, b). Reversing the edge negates that value exactly
/// (sum and difference are symmetric), so two triangles sharing an edge see the same number with
/// opposite signs and a ray cannot slip between them.
///
/// Classes: the edge values of p1p2, p2p0, p0p1 are the unnormalized barycentrics of p0, p1, p2;
/// edge / vertex when exactly zero; parallel / coplanar from the plane equation d . n = 0.
#include "rayproof/triangle_common.h"

namespace rayproof {

namespace detail {

/// d . ((b - a) x (b + a)): twice the signed volume det(d, a, b), symmetric in its rounding.
template <class T>
[[nodiscard]] inline T plucker_edge(const Vec3<T>& d, const Vec3<T>& a, const Vec3<T>& b) {
  return dot(cross(b - a, b + a), d);
}

}  // namespace detail

template <class T>
[[nodiscard]] TriangleHit<T> intersect_plucker(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  const Vec3<T> n = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
  if (is_zero(n)) return {Contact::degenerate};
  // Direction in the plane: parallel or coplanar by the plane equation.
  const T dn = dot(ray.d, n);
  if (dn == T(0)) {
    if (dot(ray.o - tri.p0, n) != T(0)) return {Contact::parallel};
    return coplanar_range(ray, tri, n);
  }
  // Vertices relative to the ray origin.
  const Vec3<T> v0 = tri.p0 - ray.o, v1 = tri.p1 - ray.o, v2 = tri.p2 - ray.o;
  // Edge values: weight of p0 from edge p1p2, of p1 from p2p0, of p2 from p0p1.
  const T u = detail::plucker_edge(ray.d, v1, v2);
  const T v = detail::plucker_edge(ray.d, v2, v0);
  const T w = detail::plucker_edge(ray.d, v0, v1);
  if ((u < T(0) || v < T(0) || w < T(0)) && (u > T(0) || v > T(0) || w > T(0))) return {Contact::miss};
  const T sum = u + v + w;
  if (sum == T(0)) return {Contact::miss};  // the edge values cancel: no hit, as in Embree
  // Hit distance from the plane equation; barycentrics from the edge values.
  const T t = dot(v0, n) / dn;
  const T inv = T(1) / sum;
  if (t < T(0)) return {Contact::behind, t, kNaN<T>, v * inv, w * inv};
  const int zeros = (u == T(0)) + (v == T(0)) + (w == T(0));
  const Contact cls = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {cls, t, kNaN<T>, v * inv, w * inv};
}

}  // namespace rayproof
