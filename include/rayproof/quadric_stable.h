#pragma once
/// Numerically stable ray/sphere and ray/ellipsoid: Haines, Günther & Akenine-Möller, "Precision
/// Improvements for Ray/Sphere Intersection", Ray Tracing Gems, ch. 7, 2019.
///  - The discriminant from the perpendicular distance of the centre to the line (Hearn & Baker):
///    with f = o - c, l = f - (f.d / d.d) d, disc/4 = (d.d) (r^2 - l.l). This avoids b^2 - 4ac,
///    which cancels catastrophically when the sphere is small and far away.
///  - The roots without cancellation: q = -(b' + sign(b') sqrt(disc')), t0 = c / q, t1 = q / a
///    (b' = f.d, disc' = disc/4).
/// An ellipsoid is scaled to the unit sphere first (x_i / s_i).
#include <cmath>
#include <utility>

#include "rayproof/ellipsoid.h"
#include "rayproof/sphere.h"

namespace rayproof {

/// Roots of a t^2 + 2 b t + c (a > 0) given disc = b^2 - a c computed by the caller in a stable way.
template <class T>
[[nodiscard]] Hit<T> classify_quadratic_stable(T a, T b, T c, T disc) {
  if (!(disc >= T(0))) return {Contact::miss};  // negative, or NaN from overflow
  if (disc == T(0)) {
    const T t = -b / a;
    return {t < T(0) ? Contact::behind : Contact::tangent, t, t};
  }
  // q has the sign of -b and no cancellation; q / a and c / q are the two roots.
  const T q = -(b + std::copysign(std::sqrt(disc), b));
  T t0 = c / q, t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  if (t1 < T(0)) return {Contact::behind, t0, t1};
  if (t0 < T(0)) return {Contact::inside, t0, t1};
  return {Contact::hit, t0, t1};
}

/// Unit-radius-scaled stable test on f = o - c and d: a = d.d, b = f.d, c = f.f - r^2.
template <class T>
[[nodiscard]] Hit<T> intersect_sphere_stable(const Vec3<T>& f, const Vec3<T>& d, T r) {
  const T a = dot(d, d);
  const T b = dot(f, d);
  // The centre's offset from its foot on the line: l = f - (b / a) d.
  const Vec3<T> l = f - (b / a) * d;
  // disc' = a (r^2 - l.l); r^2 enters through the FMA unrounded.
  const T disc = a * std::fma(r, r, -dot(l, l));
  const T c = dot(f, f) - r * r;
  return classify_quadratic_stable(a, b, c, disc);
}

template <class T>
[[nodiscard]] Hit<T> intersect_stable(const Ray<T>& ray, const Sphere<T>& s) {
  if (!ray.valid() || !all_finite(s.center) || !std::isfinite(s.radius) || s.radius < T(0))
    return {Contact::invalid};
  if (s.radius == T(0)) return {Contact::degenerate};
  return intersect_sphere_stable(ray.o - s.center, ray.d, s.radius);
}

template <class T>
[[nodiscard]] Hit<T> intersect_stable(const Ray<T>& ray, const Ellipsoid<T>& e) {
  const Vec3<T>& s = e.semi_axes;
  if (!ray.valid() || !all_finite(e.center) || !all_finite(s) || s.x < T(0) || s.y < T(0) || s.z < T(0))
    return {Contact::invalid};
  if (s.x == T(0) || s.y == T(0) || s.z == T(0)) return {Contact::degenerate};
  // Scale space so the ellipsoid becomes the unit sphere; t is unchanged.
  const Vec3<T> f = div(ray.o - e.center, s), d = div(ray.d, s);
  if (is_zero(d) || !all_finite(d)) return {Contact::miss};  // d underflowed / overflowed in scaling
  return intersect_sphere_stable(f, d, T(1));
}

}  // namespace rayproof
