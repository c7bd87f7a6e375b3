#pragma once
/// Möller's interval-overlap triangle/triangle test (T. Möller, "A Fast Triangle-Triangle
/// Intersection Test", JGT 2(2), 1997), as it is usually written, in plain floating point: true
/// when the closed triangles are found to share a point.
///  1. Signed distances of a's vertices to b's plane; all of one sign: no contact. The same for b.
///  2. The planes meet on a line L with direction D = n_a x n_b; project onto D's largest axis.
///  3. Each triangle meets L on an interval, from its lone vertex (the one on its own side of the
///     other plane) towards the other two: t = p_lone + (p_other - p_lone) d_lone / (d_lone - d_other).
///  4. Contact when the intervals overlap (closed). All distances exactly 0: the coplanar branch.
/// The reference code's optional epsilon (distances below 1e-6 set to 0) is not applied: every
/// comparison is against an exact 0, so what the test gets wrong is rounding alone.
#include "rayproof/tritri_coplanar.h"

namespace rayproof {

namespace tritri_detail {

/// The interval of a triangle on L: vertex projections p, signed distances d to the other plane.
/// False when all three distances are 0 (coplanar).
template <class T>
bool moller_interval(const T (&p)[3], const T (&d)[3], T& lo, T& hi) {
  int lone;
  if (d[0] * d[1] > T(0)) lone = 2;            // 0 and 1 on one side: 2 alone (or on the plane)
  else if (d[0] * d[2] > T(0)) lone = 1;
  else if (d[1] * d[2] > T(0) || d[0] != T(0)) lone = 0;
  else if (d[1] != T(0)) lone = 1;
  else if (d[2] != T(0)) lone = 2;
  else return false;
  const int i = (lone + 1) % 3, j = (lone + 2) % 3;
  const T t1 = p[lone] + (p[i] - p[lone]) * d[lone] / (d[lone] - d[i]);
  const T t2 = p[lone] + (p[j] - p[lone]) * d[lone] / (d[lone] - d[j]);
  lo = t1 < t2 ? t1 : t2;
  hi = t1 < t2 ? t2 : t1;
  return true;
}

}  // namespace tritri_detail

template <class T>
[[nodiscard]] bool tritri_moller(const Triangle<T>& a, const Triangle<T>& b) {
  const Vec3<T> nb = cross(b.p1 - b.p0, b.p2 - b.p0);
  const T db = -dot(nb, b.p0);
  const T da[3] = {dot(nb, a.p0) + db, dot(nb, a.p1) + db, dot(nb, a.p2) + db};
  if (da[0] * da[1] > T(0) && da[0] * da[2] > T(0)) return false;  // a on one side of b's plane
  const Vec3<T> na = cross(a.p1 - a.p0, a.p2 - a.p0);
  const T dn = -dot(na, a.p0);
  const T dbv[3] = {dot(na, b.p0) + dn, dot(na, b.p1) + dn, dot(na, b.p2) + dn};
  if (dbv[0] * dbv[1] > T(0) && dbv[0] * dbv[2] > T(0)) return false;
  const int k = max_abs_axis(cross(na, nb));
  const T pa[3] = {a.p0[k], a.p1[k], a.p2[k]}, pb[3] = {b.p0[k], b.p1[k], b.p2[k]};
  T lo_a, hi_a, lo_b, hi_b;
  if (!tritri_detail::moller_interval(pa, da, lo_a, hi_a)) return tritri_detail::coplanar_meet(na, a, b);
  if (!tritri_detail::moller_interval(pb, dbv, lo_b, hi_b)) return tritri_detail::coplanar_meet(na, a, b);
  return !(hi_a < lo_b || hi_b < lo_a);
}

}  // namespace rayproof
