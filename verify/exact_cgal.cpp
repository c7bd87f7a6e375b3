/// rayproof::exact::intersect (rayproof/verify/exact.h), the ground truth: the exact algorithm
/// (src/exact/algorithms.h) instantiated on CGAL's exact kernel, Simple_cartesian<Gmpq> (GMP rationals;
/// CGAL's Point_3, Vector_3, determinant and cross_product), with the shared MPFR rounding
/// (src/exact/rounding.h). The certified tier's fallback (src/exact/fallback.cpp) is the same algorithm on gmpxx.
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>

#include "rayproof/verify/exact.h"
#include "exact/algorithms.h"

namespace rayproof::exact {

namespace {

/// The kernel of src/exact/algorithms.h over CGAL. Every finite double is a rational, so an input
/// converts exactly (mpq_set_d); the algorithm screens NaN and infinities out first.
struct CgalKernel {
  using Q = CGAL::Gmpq;
  using Base = CGAL::Simple_cartesian<Q>;
  using Point = Base::Point_3;
  using Vector = Base::Vector_3;

  static Point point(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
  static Vector vector(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
  static Q dot(const Vector& a, const Vector& b) { return a * b; }
  static Vector cross(const Vector& a, const Vector& b) { return CGAL::cross_product(a, b); }
  static Q det(const Vector& a, const Vector& b, const Vector& c) { return CGAL::determinant(a, b, c); }
  static bool is_zero(const Vector& a) { return a == CGAL::NULL_VECTOR; }
  static Q coord(const Vector& a, int i) { return a[i]; }  // a handle copy (Gmpq is reference counted)
  static int sign(const Q& q) { return mpq_sgn(q.mpq()); }
  static mpq_srcptr mpq(const Q& q) { return q.mpq(); }
};

}  // namespace

Hit<double> intersect(const Ray<double>& ray, const Plane<double>& pl) { return exact_algo::intersect<CgalKernel>(ray, pl); }
Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) { return exact_algo::intersect<CgalKernel>(ray, s); }
Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) { return exact_algo::intersect<CgalKernel>(ray, e); }
Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) { return exact_algo::intersect<CgalKernel>(ray, b); }
Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) { return exact_algo::intersect<CgalKernel>(ray, dk); }
TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  return exact_algo::intersect<CgalKernel>(ray, tri);
}

}  // namespace rayproof::exact
