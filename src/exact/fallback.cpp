/// rayproof::certified::fallback::intersect (exact/fallback.h): the certified tier's exact
/// fallback, the exact algorithm (algorithms.h) instantiated on gmpxx's mpq_class and its vector
/// (rational_vec.h), with the shared MPFR rounding (rounding.h). GMP and MPFR only, no CGAL:
/// rayproof_certified links without it. The ground truth (exact_cgal.cpp) is the same algorithm
/// on CGAL's kernel.
#include "exact/fallback.h"

#include <gmpxx.h>

#include "exact/algorithms.h"
#include "exact/rational_vec.h"

namespace rayproof::certified::fallback {

namespace {

using exact_algo::QVec;

/// The kernel of algorithms.h over gmpxx. Every finite double is a rational, so an input
/// converts exactly (mpq_set_d); the algorithm screens NaN and infinities out first.
struct GmpxxKernel {
  using Q = mpq_class;
  using Point = QVec;
  using Vector = QVec;

  static QVec point(const Vec3<double>& v) { return exact_algo::rational(v); }
  static QVec vector(const Vec3<double>& v) { return exact_algo::rational(v); }
  static Q dot(const QVec& a, const QVec& b) { return exact_algo::dot(a, b); }
  static QVec cross(const QVec& a, const QVec& b) { return exact_algo::cross(a, b); }
  /// det[a; b; c] = a . (b x c).
  static Q det(const QVec& a, const QVec& b, const QVec& c) { return dot(a, cross(b, c)); }
  static int sign(const Q& q) { return sgn(q); }
  static bool is_zero(const QVec& a) { return sign(a.x) == 0 && sign(a.y) == 0 && sign(a.z) == 0; }
  static const Q& coord(const QVec& a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }
  static mpq_srcptr mpq(const Q& q) { return q.get_mpq_t(); }
};

}  // namespace

template <Primitive P>
HitOf<P> intersect(const Ray<double>& ray, const P& p) {
  return exact_algo::intersect<GmpxxKernel>(ray, p);
}

template Hit<double> intersect(const Ray<double>&, const Plane<double>&);
template Hit<double> intersect(const Ray<double>&, const Sphere<double>&);
template Hit<double> intersect(const Ray<double>&, const Ellipsoid<double>&);
template Hit<double> intersect(const Ray<double>&, const Box<double>&);
template Hit<double> intersect(const Ray<double>&, const Disk<double>&);
template TriangleHit<double> intersect(const Ray<double>&, const Triangle<double>&);

}  // namespace rayproof::certified::fallback
