#pragma once
/// Exact signs of the two orientation determinants on double inputs, with a float filter:
///   orient2d(a, b, p) = (b - a) x (p - a) in a plane (u, v):  (bu - au)(pv - av) - (bv - av)(pu - au)
///   orient3d(a, b, c, p) = ((b - a) x (c - a)) . (p - a)
/// Stage 1 is Shewchuk's static filter ("Adaptive Precision Floating-Point Arithmetic and Fast Robust
/// Geometric Predicates", 1997: ccwerrboundA, o3derrboundA), valid for rounded differences and
/// products; a guard on the permanent keeps underflowed products out of it. Stage 2 is the exact sign
/// on the stack when every difference of the inputs is a double (orient3d_exact_differences), else
/// with the expansions of certified_expansion.h, when the inputs lie in their exponent window; outside
/// it the functions return kUnknown and the caller decides with a big-number fallback
/// (src/exact/orient_exact.cpp, GMP). Header-only, no dependencies.
#include <cmath>

#include "rayproof/certified_expansion.h"

namespace rayproof::orient {

/// The sign of a determinant, or kUnknown: the expansion stage could not run (inputs outside its
/// exponent window, or an overflow), the caller needs the big-number fallback.
inline constexpr int kUnknown = 2;

namespace detail {
inline constexpr double kEps = 0x1p-53;
inline constexpr double kCcwBound = (3.0 + 16.0 * kEps) * kEps;  // Shewchuk's ccwerrboundA
inline constexpr double kO3dBound = (7.0 + 56.0 * kEps) * kEps;  // Shewchuk's o3derrboundA
/// Permanents below this may hold underflowed products (absolute error 2^-1075 each): not filtered.
inline constexpr double kTiny = 0x1p-900;
}  // namespace detail

namespace detail {

using certified::grow_into;  // GROW-EXPANSION on the caller's small arrays (certified_expansion.h)

/// The sign of an expansion (nonoverlapping, increasing magnitude): that of its largest component.
inline int sign_of(const double* e, int n) { return n == 0 ? 0 : (e[n - 1] > 0 ? 1 : -1); }

/// acc += w (a b - c d), exactly: the minor as four error-free parts (two_prod) grown into a small
/// expansion (at most 4 components), each part times w error-free into acc (at most 8 more).
inline int grow_scaled_minor(double* acc, int n, double a, double b, double c, double d, double w) {
  const TwoTerm<double> p = two_prod(a, b), q = two_prod(c, d);
  double m[4];
  int k = grow_into(m, 0, p.lo);
  k = grow_into(m, k, p.hi);
  k = grow_into(m, k, -q.lo);
  k = grow_into(m, k, -q.hi);
  for (int i = 0; i < k; ++i) {
    const TwoTerm<double> r = two_prod(m[i], w);
    n = grow_into(acc, n, r.lo);
    n = grow_into(acc, n, r.hi);
  }
  return n;
}

/// True when b - a is a double exactly (its two_sum error is 0).
inline bool exact_difference(double b, double a) { return two_sum(b, -a).lo == 0; }

}  // namespace detail

/// The adaptive middle stage (Shewchuk's stage B, made exact): when every difference of the inputs
/// is itself a double, the determinant is a polynomial of degree 3 (2) in those differences, summed
/// exactly on the stack in at most 24 (4) components. That covers the exact zeros that reach this
/// far in practice (points on a face or an edge, coplanar neighbours: coordinates of a common grid
/// or close to each other, whose differences are exact by Sterbenz's lemma). Call inside the
/// expansions' exponent window only (the same argument on underflow holds: the differences are the
/// same values). Returns kUnknown when a difference is not exact.
[[nodiscard]] inline int orient2d_exact_differences(double au, double av, double bu, double bv, double pu, double pv) {
  using detail::exact_difference;
  if (!(exact_difference(bu, au) & exact_difference(pv, av) & exact_difference(bv, av) & exact_difference(pu, au)))
    return kUnknown;
  const TwoTerm<double> l = two_prod(bu - au, pv - av), r = two_prod(bv - av, pu - au);
  double e[4];
  int n = detail::grow_into(e, 0, l.lo);
  n = detail::grow_into(e, n, l.hi);
  n = detail::grow_into(e, n, -r.lo);
  n = detail::grow_into(e, n, -r.hi);
  return detail::sign_of(e, n);
}

[[nodiscard]] inline int orient3d_exact_differences(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                                    const Vec3<double>& p) {
  using detail::exact_difference;
  if (!(exact_difference(b.x, a.x) & exact_difference(b.y, a.y) & exact_difference(b.z, a.z) &
        exact_difference(c.x, a.x) & exact_difference(c.y, a.y) & exact_difference(c.z, a.z) &
        exact_difference(p.x, a.x) & exact_difference(p.y, a.y) & exact_difference(p.z, a.z)))
    return kUnknown;
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double wx = p.x - a.x, wy = p.y - a.y, wz = p.z - a.z;
  double acc[24];
  int n = detail::grow_scaled_minor(acc, 0, uy, vz, uz, vy, wx);
  n = detail::grow_scaled_minor(acc, n, uz, vx, ux, vz, wy);
  n = detail::grow_scaled_minor(acc, n, ux, vy, uy, vx, wz);
  return detail::sign_of(acc, n);
}

/// Exact sign of orient2d by expansions; kUnknown outside their window (degree 2, the window of
/// in_range for degree 3 is used for both predicates).
[[nodiscard]] inline int orient2d_expansion(double au, double av, double bu, double bv, double pu, double pv) {
  using certified::diff;
  if (!certified::in_range<-288, 336>(au, av, bu, bv, pu, pv)) return kUnknown;
  if (const int s = orient2d_exact_differences(au, av, bu, bv, pu, pv); s != kUnknown) return s;
  const certified::Expansion e = diff(bu, au) * diff(pv, av) - diff(bv, av) * diff(pu, au);
  return e.bad ? kUnknown : e.sign();
}

/// Exact sign of orient3d by expansions; kUnknown outside their window.
[[nodiscard]] inline int orient3d_expansion(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                            const Vec3<double>& p) {
  if (!certified::in_range<-288, 336>(a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, p.x, p.y, p.z)) return kUnknown;
  if (const int s = orient3d_exact_differences(a, b, c, p); s != kUnknown) return s;
  const certified::ExpVec3 u = certified::diff3(b, a), v = certified::diff3(c, a), w = certified::diff3(p, a);
  const certified::Expansion e =
      w.x * (u.y * v.z - u.z * v.y) + w.y * (u.z * v.x - u.x * v.z) + w.z * (u.x * v.y - u.y * v.x);
  return e.bad ? kUnknown : e.sign();
}

/// The filtered sign of orient2d: -1, 0, 1, or kUnknown (the filter and the expansions both gave up).
[[nodiscard]] inline int orient2d(double au, double av, double bu, double bv, double pu, double pv) {
  const double l = (bu - au) * (pv - av), r = (bv - av) * (pu - au);
  const double det = l - r, sum = std::fabs(l) + std::fabs(r);
  // NaN or infinite products fail both comparisons and go to the exact stage.
  if (sum > detail::kTiny && std::fabs(det) > detail::kCcwBound * sum) return det > 0 ? 1 : -1;
  if (l == 0 && r == 0 && (bu - au == 0 || pv - av == 0) && (bv - av == 0 || pu - au == 0))
    return 0;  // both products exactly zero: a factor is an exact zero difference
  return orient2d_expansion(au, av, bu, bv, pu, pv);
}

/// The filtered sign of orient3d: -1, 0, 1, or kUnknown.
[[nodiscard]] inline int orient3d(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                  const Vec3<double>& p) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double wx = p.x - a.x, wy = p.y - a.y, wz = p.z - a.z;
  const double m1 = uy * vz, m2 = uz * vy, m3 = uz * vx, m4 = ux * vz, m5 = ux * vy, m6 = uy * vx;
  const double det = wx * (m1 - m2) + wy * (m3 - m4) + wz * (m5 - m6);
  const double perm = (std::fabs(m1) + std::fabs(m2)) * std::fabs(wx) + (std::fabs(m3) + std::fabs(m4)) * std::fabs(wy) +
                      (std::fabs(m5) + std::fabs(m6)) * std::fabs(wz);
  // The minors' products must not underflow (their error would be multiplied by |w|): every
  // nonzero difference at least 2^-480 keeps them normal; the final products' underflow
  // (2^-1075 each) is far inside the bound once perm > kTiny.
  if (perm > detail::kTiny && std::fabs(det) > detail::kO3dBound * perm &&
      certified::in_range<-480, 1023>(ux, uy, uz, vx, vy, vz, wx, wy, wz))
    return det > 0 ? 1 : -1;
  // Every term exactly zero (points on a common axis-aligned plane, or with equal coordinates): a
  // computed difference is 0 only when it is exactly 0 (gradual underflow), so each w_k is an exact
  // zero or both products of its minor have an exact zero factor. Finite differences only (a NaN or
  // infinity goes on to the exact stage, as before).
  if (std::isfinite(ux + uy + uz + vx + vy + vz + wx + wy + wz) &&
      (wx == 0 || ((uy == 0 || vz == 0) && (uz == 0 || vy == 0))) &&
      (wy == 0 || ((uz == 0 || vx == 0) && (ux == 0 || vz == 0))) &&
      (wz == 0 || ((ux == 0 || vy == 0) && (uy == 0 || vx == 0))))
    return 0;
  return orient3d_expansion(a, b, c, p);
}

}  // namespace rayproof::orient

namespace rayproof::orient {

/// orient3d's value to within a relative 2^-52 (the expansion's largest component), or NaN when
/// the expansions cannot run (the caller's big-number fallback gives it then).
[[nodiscard]] inline double orient3d_value(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                           const Vec3<double>& p) {
  if (!certified::in_range<-288, 336>(a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, p.x, p.y, p.z)) return kNaN<double>;
  const certified::ExpVec3 u = certified::diff3(b, a), v = certified::diff3(c, a), w = certified::diff3(p, a);
  const certified::Expansion e =
      w.x * (u.y * v.z - u.z * v.y) + w.y * (u.z * v.x - u.x * v.z) + w.z * (u.x * v.y - u.y * v.x);
  return e.bad ? kNaN<double> : e.top();
}

}  // namespace rayproof::orient
