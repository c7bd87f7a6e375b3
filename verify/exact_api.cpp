/// rayproof::exact::intersect (rayproof/exact.h), the ground truth: the screening of CASES.md
/// (invalid, then degenerate), on the doubles themselves, which is exact; then the exact kernel of
/// the kind (exact_*.cpp: CGAL's Gmpq and Simple_cartesian, MPFR for roundings). The certified
/// tier's fallback (fallback_*.cpp, gmpxx) is written separately and checked against this.
#include "rayproof/exact.h"

#include <cmath>

#include "verify/exact_kinds.h"

namespace rayproof::exact {

namespace {

bool finite_all(double x) { return std::isfinite(x); }
bool finite_all(const Vec3<double>& v) { return all_finite(v); }
template <class... A>
bool finite_all(const A&... a) { return (finite_all(a) && ...); }

/// NaN or infinite origin or direction, or d = 0.
bool bad_ray(const Ray<double>& r) { return !finite_all(r.o, r.d) || is_zero(r.d); }
bool any_negative(const Vec3<double>& v) { return v.x < 0 || v.y < 0 || v.z < 0; }
bool any_zero(const Vec3<double>& v) { return v.x == 0 || v.y == 0 || v.z == 0; }

constexpr Hit<double> kInvalid{Contact::invalid};
constexpr Hit<double> kDegenerate{Contact::degenerate};

}  // namespace

Hit<double> intersect(const Ray<double>& ray, const Plane<double>& pl) {
  if (bad_ray(ray) || !finite_all(pl.point, pl.normal)) return kInvalid;
  if (is_zero(pl.normal)) return kDegenerate;
  return verify::exact_plane(ray, pl);
}

Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) {
  if (bad_ray(ray) || !finite_all(s.center, s.radius) || s.radius < 0) return kInvalid;
  if (s.radius == 0) return kDegenerate;
  return verify::exact_sphere(ray, s);
}

Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  if (bad_ray(ray) || !finite_all(e.center, e.semi_axes) || any_negative(e.semi_axes)) return kInvalid;
  if (any_zero(e.semi_axes)) return kDegenerate;
  return verify::exact_ellipsoid(ray, e);
}

Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) {
  if (bad_ray(ray) || !finite_all(b.lo, b.hi) || b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z) return kInvalid;
  return verify::exact_box(ray, b);
}

Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) {
  if (bad_ray(ray) || !finite_all(dk.center, dk.normal, dk.radius) || dk.radius < 0) return kInvalid;
  if (is_zero(dk.normal) || dk.radius == 0) return kDegenerate;
  return verify::exact_disk(ray, dk);
}

TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  if (bad_ray(ray) || !finite_all(tri.p0, tri.p1, tri.p2)) return {Contact::invalid};
  return verify::exact_triangle(ray, tri);  // collinear vertices: degenerate, decided exactly
}

}  // namespace rayproof::exact
