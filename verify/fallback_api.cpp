/// rayproof::certified::fallback::intersect (verify/fallback.h): the certified tier's exact
/// fallback. The screening of CASES.md (invalid, then degenerate), on the doubles themselves, which
/// is exact; then the kernel of the kind (fallback_*.cpp, GMP rationals). Independent of the ground
/// truth (rayproof::exact, CGAL, exact_*.cpp), which the crosscheck test compares it with.
#include "verify/fallback.h"

#include <cmath>

#include "verify/fallback_kinds.h"

namespace rayproof::certified::fallback {

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
  return plane_kernel(ray, pl);
}

Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) {
  if (bad_ray(ray) || !finite_all(s.center, s.radius) || s.radius < 0) return kInvalid;
  if (s.radius == 0) return kDegenerate;
  return sphere_kernel(ray, s);
}

Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  if (bad_ray(ray) || !finite_all(e.center, e.semi_axes) || any_negative(e.semi_axes)) return kInvalid;
  if (any_zero(e.semi_axes)) return kDegenerate;
  return ellipsoid_kernel(ray, e);
}

Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) {
  if (bad_ray(ray) || !finite_all(b.lo, b.hi) || b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z) return kInvalid;
  return box_kernel(ray, b);
}

Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) {
  if (bad_ray(ray) || !finite_all(dk.center, dk.normal, dk.radius) || dk.radius < 0) return kInvalid;
  if (is_zero(dk.normal) || dk.radius == 0) return kDegenerate;
  return disk_kernel(ray, dk);
}

TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  if (bad_ray(ray) || !finite_all(tri.p0, tri.p1, tri.p2)) return {Contact::invalid};
  return triangle_kernel(ray, tri);  // collinear vertices: degenerate, decided exactly
}

}  // namespace rayproof::certified::fallback
