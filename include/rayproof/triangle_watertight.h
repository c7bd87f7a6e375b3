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

/// The per-ray part of the test (axis permutation), computed once per ray. A = the arithmetic type:
/// float follows the paper; double on float inputs keeps the products of the sheared coordinates
/// (mostly) exact, so rays through an edge or vertex of exactly representable data stay exact zeros.
template <class T, class A = T>
struct WatertightRay {
  Vec3<A> o, d;
  int kx = 0, ky = 1, kz = 2;

  explicit WatertightRay(const Ray<T>& ray) : o(ray.o.template cast<A>()), d(ray.d.template cast<A>()) {
    // z: the dominant axis of d; x, y follow cyclically, swapped when d_z < 0 to keep the winding.
    kz = max_abs_axis(ray.d);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (ray.d[kz] < T(0)) std::swap(kx, ky);
  }
};

namespace detail {

/// Edge function a_x b_y - a_y b_x, in double when float gives exactly zero (float products are
/// exact in double, so the double sign is the exact sign for the sheared float coordinates).
template <class A>
[[nodiscard]] inline A edge_function(A ax, A ay, A bx, A by) {
  A e = ax * by - ay * bx;
  if constexpr (std::is_same_v<A, float>) {
    if (e == 0.0f) e = static_cast<float>(double(ax) * double(by) - double(ay) * double(bx));
  }
  return e;
}

}  // namespace detail

/// The watertight test with a prepared ray, for traversal: no screening of invalid or degenerate
/// input; `parallel` stands for det = 0 (parallel to the plane, in it, or a triangle too small for
/// the arithmetic). The shear is applied scaled by d_z (x' = d_z x - d_x z), which multiplies every
/// edge function by d_z^2 > 0 and avoids the rounded division d_x / d_z of the paper; it is still one
/// linear map per ray, so shared edges still see identical numbers.
template <class T, class A>
[[nodiscard]] TriangleHit<T> intersect_watertight(const WatertightRay<T, A>& wr, const Triangle<T>& tri) {
  const int kx = wr.kx, ky = wr.ky, kz = wr.kz;
  const A dx = wr.d[kx], dy = wr.d[ky], dz = wr.d[kz];
  // Vertices relative to the ray origin.
  const Vec3<A> a = tri.p0.template cast<A>() - wr.o, b = tri.p1.template cast<A>() - wr.o,
                c = tri.p2.template cast<A>() - wr.o;
  // Shear (scaled by d_z): the ray becomes the z axis.
  const A ax = dz * a[kx] - dx * a[kz], ay = dz * a[ky] - dy * a[kz];
  const A bx = dz * b[kx] - dx * b[kz], by = dz * b[ky] - dy * b[kz];
  const A cx = dz * c[kx] - dx * c[kz], cy = dz * c[ky] - dy * c[kz];
  // Edge functions: U for edge p1 p2 (weight of p0), V for p2 p0, W for p0 p1.
  const A u = detail::edge_function(cx, cy, bx, by);
  const A v = detail::edge_function(ax, ay, cx, cy);
  const A w = detail::edge_function(bx, by, ax, ay);
  // Mixed signs: the ray passes outside an edge.
  if ((u < A(0) || v < A(0) || w < A(0)) && (u > A(0) || v > A(0) || w > A(0))) return {Contact::miss};
  const A det = u + v + w;
  if (det == A(0)) return {Contact::parallel};
  // Scaled hit distance: t = (U a_z + V b_z + W c_z) / (det d_z); its sign decides behind before
  // any division.
  const A t_scaled = u * a[kz] + v * b[kz] + w * c[kz];
  const A den = det * dz;
  const bool behind = den < A(0) ? t_scaled > A(0) : t_scaled < A(0);
  const T t = static_cast<T>(t_scaled / den);
  const T b1 = static_cast<T>(v / det), b2 = static_cast<T>(w / det);
  if (behind) return {Contact::behind, t, kNaN<T>, b1, b2};
  const int zeros = (u == A(0)) + (v == A(0)) + (w == A(0));
  const Contact cls = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {cls, t, kNaN<T>, b1, b2};
}

/// Front door: screens invalid and degenerate input, decides parallel / coplanar by the plane
/// equation (d . n = 0: the sign of (o - p0) . n), then the watertight test; a det = 0 that the
/// plane equation does not confirm is a miss (the paper's "no hit").
template <class T, class A = T>
[[nodiscard]] TriangleHit<T> intersect_watertight(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  // Plane equation in the arithmetic type.
  const Ray<A> ra{ray.o.template cast<A>(), ray.d.template cast<A>()};
  const Triangle<A> ta{tri.p0.template cast<A>(), tri.p1.template cast<A>(), tri.p2.template cast<A>()};
  const Vec3<A> n = cross(ta.p1 - ta.p0, ta.p2 - ta.p0);
  if (is_zero(n)) return {Contact::degenerate};
  if (dot(ra.d, n) == A(0)) {
    if (dot(ra.o - ta.p0, n) != A(0)) return {Contact::parallel};
    const TriangleHit<A> c = coplanar_range(ra, ta, n);
    return {c.contact, static_cast<T>(c.t), static_cast<T>(c.t2), static_cast<T>(c.b1), static_cast<T>(c.b2)};
  }
  const TriangleHit<T> h = intersect_watertight(WatertightRay<T, A>(ray), tri);
  return h.contact == Contact::parallel ? TriangleHit<T>{Contact::miss} : h;
}

}  // namespace rayproof
