#pragma once
/// The exact ray/primitive algorithm, written once and templated on a kernel K (the number type and
/// the few point/vector operations it uses). Instantiated twice:
///  - the ground truth, rayproof::exact::intersect (exact_cgal.cpp, in rayproof_verify): K over
///    CGAL's Simple_cartesian<Gmpq> (Point_3, Vector_3, CGAL::determinant, CGAL::cross_product);
///  - the certified tier's fallback, rayproof::certified::fallback::intersect (fallback.cpp, in
///    rayproof_certified): K over gmpxx's mpq_class and a small vector of them, no CGAL.
/// The MPFR rounding (rounding.h) is one shared code. So the two differ only in the number
/// type and the vector operations; exact_crosscheck_test checks that they agree bit for bit.
/// This header includes neither CGAL nor gmpxx.
///
/// Contract (docs/cases.md): the class of exact arithmetic on the input doubles; t, t2 and the triangle
/// barycentrics b1, b2 rounded to nearest (ties to even, signs of zeros included); NaN for fields a
/// class does not carry. Every finite double is a rational, so inputs convert exactly; NaN and
/// infinities are screened out first (`invalid`), then zero sizes (`degenerate`).
///
/// Parts: algo_kernel.h (what K provides, rounding helpers), algo_planar.h,
/// algo_quadric.h, algo_box.h, algo_triangle.h; here the entry.
///
/// The entry: the screening of docs/cases.md (invalid, then degenerate), on the doubles themselves, which
/// is exact; then the algorithm of the kind. Only the triangle's degeneracy (collinear vertices)
/// needs exact arithmetic and is decided by triangle<K> itself.
#include <cmath>

#include "rayproof/vec3.h"
#include "exact/algo_box.h"
#include "exact/algo_planar.h"
#include "exact/algo_quadric.h"
#include "exact/algo_triangle.h"

namespace rayproof::exact_algo {

namespace screen {

inline bool finite_all(double x) { return std::isfinite(x); }
inline bool finite_all(const Vec3<double>& v) { return all_finite(v); }
template <class... A>
bool finite_all(const A&... a) { return (finite_all(a) && ...); }

/// NaN or infinite origin or direction, or d = 0.
inline bool bad_ray(const Ray<double>& r) { return !finite_all(r.o, r.d) || is_zero(r.d); }
inline bool any_negative(const Vec3<double>& v) { return v.x < 0 || v.y < 0 || v.z < 0; }
inline bool any_zero(const Vec3<double>& v) { return v.x == 0 || v.y == 0 || v.z == 0; }

inline constexpr Hit<double> kInvalid{Contact::invalid};
inline constexpr Hit<double> kDegenerate{Contact::degenerate};

}  // namespace screen

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& pl) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(pl.point, pl.normal)) return kInvalid;
  if (is_zero(pl.normal)) return kDegenerate;
  return plane<K>(ray, pl);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(s.center, s.radius) || s.radius < 0) return kInvalid;
  if (s.radius == 0) return kDegenerate;
  return sphere<K>(ray, s);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(e.center, e.semi_axes) || any_negative(e.semi_axes)) return kInvalid;
  if (any_zero(e.semi_axes)) return kDegenerate;
  return ellipsoid<K>(ray, e);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(b.lo, b.hi) || b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z) return kInvalid;
  return box<K>(ray, b);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(dk.center, dk.normal, dk.radius) || dk.radius < 0) return kInvalid;
  if (is_zero(dk.normal) || dk.radius == 0) return kDegenerate;
  return disk<K>(ray, dk);
}

template <class K>
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(tri.p0, tri.p1, tri.p2)) return {Contact::invalid};
  return triangle<K>(ray, tri);  // collinear vertices: degenerate, decided exactly
}

}  // namespace rayproof::exact_algo
