#pragma once
/// Pieces shared by every ray/triangle method: the triangle type, validity, the barycentric
/// classification of docs/cases.md, and the coplanar range of a ray lying in the triangle's plane.
#include <algorithm>
#include <limits>

#include "rayproof/hit.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Triangle {
  Vec3<T> p0, p1, p2;
};

template <class T>
[[nodiscard]] bool triangle_finite(const Triangle<T>& tri) {
  return all_finite(tri.p0) && all_finite(tri.p1) && all_finite(tri.p2);
}

/// Classes a line/plane crossing with barycentrics (b0, b1, b2) at parameter t, as docs/cases.md orders
/// them: miss (outside the closed triangle; NaN counts as outside), behind (t < 0), then interior,
/// edge or vertex by the number of barycentrics exactly 0.
template <class T>
[[nodiscard]] TriangleHit<T> classify_barycentric(T t, T b1, T b2) {
  const T b0 = T(1) - b1 - b2;
  if (!(b0 >= T(0) && b1 >= T(0) && b2 >= T(0))) return {Contact::miss};
  if (t < T(0)) return {Contact::behind, t, kNaN<T>, b1, b2};
  const int zeros = (b0 == T(0)) + (b1 == T(0)) + (b2 == T(0));
  const Contact c = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {c, t, kNaN<T>, b1, b2};
}

/// The ray lies in the plane of a non-degenerate triangle with normal n: clip t in [0, inf) against
/// the three closed edge half-planes, in 2D after dropping the dominant axis of n.
template <class T>
[[nodiscard]] TriangleHit<T> coplanar_range(const Ray<T>& ray, const Triangle<T>& tri, Vec3<T> n) {
  const int k = max_abs_axis(n);
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const Vec3<T>* p[3] = {&tri.p0, &tri.p1, &tri.p2};
  auto orient = [&](const Vec3<T>& a, const Vec3<T>& b, T cu, T cv) {
    return (b[u] - a[u]) * (cv - a[v]) - (b[v] - a[v]) * (cu - a[u]);
  };
  T lo = T(0), hi = std::numeric_limits<T>::infinity();
  for (int e = 0; e < 3; ++e) {
    const Vec3<T>& a = *p[e];
    const Vec3<T>& b = *p[(e + 1) % 3];
    const Vec3<T>& c = *p[(e + 2) % 3];
    const T side = orient(a, b, c[u], c[v]) < T(0) ? T(-1) : T(1);
    // f(t) = f0 + t f1 must satisfy side * f(t) >= 0.
    const T f0 = side * orient(a, b, ray.o[u], ray.o[v]);
    const T f1 = side * ((b[u] - a[u]) * ray.d[v] - (b[v] - a[v]) * ray.d[u]);
    if (f1 == T(0)) {
      if (f0 < T(0)) return {Contact::coplanar};
    } else if (f1 > T(0)) {
      lo = std::max(lo, -f0 / f1);
    } else {
      hi = std::min(hi, -f0 / f1);
    }
  }
  if (!(lo <= hi)) return {Contact::coplanar};
  return {Contact::coplanar, lo, hi};
}

}  // namespace rayproof
