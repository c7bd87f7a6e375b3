#pragma once
/// Watertight ray/triangle test: Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection",
/// JCGT 2(1), 2013. The vertices are translated to the ray origin, the axes permuted so that the
/// dominant direction component is z, and sheared so that the ray becomes the +z axis; the 2D edge
/// functions U, V, W of the sheared vertices then decide inside/outside. A shared edge is computed
/// from the same two sheared vertices by both triangles, so a ray can never pass between them.
///
/// Classes (CASES.md): U, V, W are the unnormalized barycentrics of p0, p1, p2 (b_i = U_i / det);
/// edge / vertex when one / two of them are exactly 0 *in the sheared coordinates* (re-evaluated in
/// double when float gives a zero, as the paper prescribes). det = U + V + W = 0: parallel or
/// coplanar, decided by the plane equation; degenerate when (p1-p0) x (p2-p0) = 0.
#include <type_traits>
#include <utility>

#include "rayproof/triangle_common.h"

namespace rayproof {

/// The per-ray part of the test (permutation and shear), computed once per ray.
template <class T>
struct WatertightRay {
  Vec3<T> o;
  int kx = 0, ky = 1, kz = 2;
  T sx{}, sy{}, sz{};

  explicit WatertightRay(const Ray<T>& ray) : o(ray.o) {
    // z: the dominant axis of d; x, y follow cyclically, swapped when d_z < 0 to keep the winding.
    kz = max_abs_axis(ray.d);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (ray.d[kz] < T(0)) std::swap(kx, ky);
    // Shear constants: the ray direction maps to (0, 0, 1).
    sx = ray.d[kx] / ray.d[kz];
    sy = ray.d[ky] / ray.d[kz];
    sz = T(1) / ray.d[kz];
  }
};

namespace detail {

/// Edge function a_x b_y - a_y b_x, in double when float gives exactly zero (float products are
/// exact in double, so the double sign is the exact sign for the sheared float coordinates).
template <class T>
[[nodiscard]] inline T edge_function(T ax, T ay, T bx, T by) {
  T e = ax * by - ay * bx;
  if constexpr (std::is_same_v<T, float>) {
    if (e == 0.0f) e = static_cast<float>(double(ax) * double(by) - double(ay) * double(bx));
  }
  return e;
}

}  // namespace detail

/// The watertight test with a prepared ray, for traversal: no screening of invalid or degenerate
/// input; `parallel` stands for det = 0 (parallel or coplanar).
template <class T>
[[nodiscard]] TriangleHit<T> intersect_watertight(const WatertightRay<T>& wr, const Triangle<T>& tri) {
  // Vertices relative to the ray origin.
  const Vec3<T> a = tri.p0 - wr.o, b = tri.p1 - wr.o, c = tri.p2 - wr.o;
  // Shear and scale to the ray's space: x, y in the plane normal to the ray.
  const T ax = a[wr.kx] - wr.sx * a[wr.kz], ay = a[wr.ky] - wr.sy * a[wr.kz];
  const T bx = b[wr.kx] - wr.sx * b[wr.kz], by = b[wr.ky] - wr.sy * b[wr.kz];
  const T cx = c[wr.kx] - wr.sx * c[wr.kz], cy = c[wr.ky] - wr.sy * c[wr.kz];
  // Edge functions: U for edge p1 p2 (weight of p0), V for p2 p0, W for p0 p1.
  const T u = detail::edge_function(cx, cy, bx, by);
  const T v = detail::edge_function(ax, ay, cx, cy);
  const T w = detail::edge_function(bx, by, ax, ay);
  // Mixed signs: the ray passes outside an edge.
  if ((u < T(0) || v < T(0) || w < T(0)) && (u > T(0) || v > T(0) || w > T(0))) return {Contact::miss};
  const T det = u + v + w;
  // det = 0: the ray is parallel to the triangle's plane or in it (the front door tells which).
  if (det == T(0)) return {Contact::parallel};
  // Scaled hit distance; its sign against det's decides behind before any division.
  const T az = wr.sz * a[wr.kz], bz = wr.sz * b[wr.kz], cz = wr.sz * c[wr.kz];
  const T t_scaled = u * az + v * bz + w * cz;
  const bool behind = det < T(0) ? t_scaled > T(0) : t_scaled < T(0);
  const T inv = T(1) / det;
  const T t = t_scaled * inv;
  if (behind) return {Contact::behind, t, kNaN<T>, v * inv, w * inv};
  const int zeros = (u == T(0)) + (v == T(0)) + (w == T(0));
  const Contact cls = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {cls, t, kNaN<T>, v * inv, w * inv};
}

/// Front door: screens invalid and degenerate input, then the watertight test; det = 0 is parallel
/// or coplanar by the sign of (o - p0) . n.
template <class T>
[[nodiscard]] TriangleHit<T> intersect_watertight(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  const Vec3<T> n = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
  if (is_zero(n)) return {Contact::degenerate};
  const TriangleHit<T> h = intersect_watertight(WatertightRay<T>(ray), tri);
  if (h.contact == Contact::parallel) {
    if (dot(ray.o - tri.p0, n) != T(0)) return {Contact::parallel};
    return coplanar_range(ray, tri, n);
  }
  return h;
}

}  // namespace rayproof
