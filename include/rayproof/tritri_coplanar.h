#pragma once
/// The coplanar branch of the classic triangle/triangle tests, in plain floating point: two closed
/// triangles in one plane, projected onto the coordinate plane where the normal n has its largest
/// component (the projection keeps every incidence), meet when an edge of one crosses an edge of
/// the other or a vertex of one lies in the other (Möller 1997, section "coplanar triangles").
#include "rayproof/triangle_common.h"

namespace rayproof::tritri_detail {

/// Twice the signed area of (a, b, c) in the (u, v) plane, as the kernels write it.
template <class T>
[[nodiscard]] T orient2(T au, T av, T bu, T bv, T cu, T cv) {
  return (bu - au) * (cv - av) - (bv - av) * (cu - au);
}

/// Closed segments [a, b] and [c, d] in 2D meet: each straddles the other's line (a zero counts),
/// collinear segments by their overlap on the line.
template <class T>
[[nodiscard]] bool segments_meet(const T (&a)[2], const T (&b)[2], const T (&c)[2], const T (&d)[2]) {
  const T d1 = orient2(a[0], a[1], b[0], b[1], c[0], c[1]), d2 = orient2(a[0], a[1], b[0], b[1], d[0], d[1]);
  const T d3 = orient2(c[0], c[1], d[0], d[1], a[0], a[1]), d4 = orient2(c[0], c[1], d[0], d[1], b[0], b[1]);
  if (d1 == T(0) && d2 == T(0)) {  // collinear: overlap of the projections on both axes
    for (int k = 0; k < 2; ++k) {
      const T lo1 = a[k] < b[k] ? a[k] : b[k], hi1 = a[k] < b[k] ? b[k] : a[k];
      const T lo2 = c[k] < d[k] ? c[k] : d[k], hi2 = c[k] < d[k] ? d[k] : c[k];
      if (hi1 < lo2 || hi2 < lo1) return false;
    }
    return true;
  }
  return !(d1 * d2 > T(0)) && !(d3 * d4 > T(0));
}

/// Point p in the closed triangle (a, b, c) in 2D: the three edge signs do not disagree.
template <class T>
[[nodiscard]] bool point_in_triangle(const T (&p)[2], const T (&a)[2], const T (&b)[2], const T (&c)[2]) {
  const T s0 = orient2(a[0], a[1], b[0], b[1], p[0], p[1]);
  const T s1 = orient2(b[0], b[1], c[0], c[1], p[0], p[1]);
  const T s2 = orient2(c[0], c[1], a[0], a[1], p[0], p[1]);
  const bool neg = s0 < T(0) || s1 < T(0) || s2 < T(0), pos = s0 > T(0) || s1 > T(0) || s2 > T(0);
  return !(neg && pos);
}

/// Two coplanar triangles with (nonzero) normal n of `a`: nine edge/edge tests, then one vertex
/// of each in the other.
template <class T>
[[nodiscard]] bool coplanar_meet(Vec3<T> n, const Triangle<T>& a, const Triangle<T>& b) {
  const int k = max_abs_axis(n);
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const Vec3<T>* pa[3] = {&a.p0, &a.p1, &a.p2};
  const Vec3<T>* pb[3] = {&b.p0, &b.p1, &b.p2};
  T A[3][2], B[3][2];
  for (int i = 0; i < 3; ++i) {
    A[i][0] = (*pa[i])[u];
    A[i][1] = (*pa[i])[v];
    B[i][0] = (*pb[i])[u];
    B[i][1] = (*pb[i])[v];
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_meet(A[i], A[(i + 1) % 3], B[j], B[(j + 1) % 3])) return true;
  return point_in_triangle(A[0], B[0], B[1], B[2]) || point_in_triangle(B[0], A[0], A[1], A[2]);
}

}  // namespace rayproof::tritri_detail
