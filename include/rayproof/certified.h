#pragma once
/// The certified tier, one call per query: the exact class of CASES.md and t (and t2) within one
/// double ulp of the exact value, for a double-precision ray against a plane, sphere, ellipsoid,
/// box, disk or triangle; for triangles also the barycentrics b1, b2 within kBarycentricError.
///
/// Two levels:
///  - try_intersect (header-only, rayproof::core): the floating-point filters of certified_*.h.
///    Where they cannot decide (a sign their error bound cannot tell, a t they cannot pin to one
///    ulp, a coplanar range, a barycentric they cannot bound), the answer is std::nullopt:
///    *undecided*. A decided answer is final: intersect returns exactly that answer.
///  - intersect (compiled, link rayproof::certified: GMP and MPFR, no CGAL): try_intersect, then
///    the exact kernels (rayproof/exact.h) for whatever it left undecided. Always decided.
///
/// What a decided answer guarantees (fields a class does not carry are NaN, as in rayproof/hit.h):
///  - contact: the class exact arithmetic on the given doubles gives (rayproof::exact::intersect).
///  - t, t2: each within one ulp of the correctly rounded exact value (equal to it, or a
///    neighbouring double). The fallback returns them correctly rounded.
///  - triangles, classes interior, edge, vertex and behind: b1 (weight of p1) and b2 (weight of p2)
///    of the plane point, each in [0, 1] and within kBarycentricError = 2^-50 (four ulps of 1) of
///    the exact value; a barycentric that is exactly 0 is 0.0, a vertex hit's barycentric 1 is
///    exactly 1.0 (see detail::triangle_barycentrics for the proof). Other classes: NaN.
///
/// Thread safety: try_intersect and intersect keep no shared state; concurrent calls are safe. The
/// fallback count (fallback_count) is per thread.
#include <cmath>
#include <cstdint>
#include <optional>

#include "rayproof/box.h"
#include "rayproof/certified_box.h"
#include "rayproof/certified_planar.h"
#include "rayproof/certified_quadric.h"
#include "rayproof/certified_triangle.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified {

/// Bound on |b - exact b| for the barycentrics b1, b2 of a decided triangle contact.
inline constexpr double kBarycentricError = 0x1p-50;

namespace detail {

/// Barycentrics of a triangle contact whose class the filter has decided (interior, edge, vertex or
/// behind; d . n != 0). With a = p0 - o, b = p1 - o, c = p2 - o, the exact barycentrics are
/// u_i / den with u_0 = d . (b x c), u_1 = d . (c x a), u_2 = d . (a x b), den = u_0 + u_1 + u_2
/// (= d . n), all in midpoint-radius arithmetic in Wide (certified_filter.h: |exact - v| <= r up
/// to kSlack; no overflow or underflow in Wide for degree-3 polynomials of doubles).
/// Proof of the bound: a quotient q = u_i / den is accepted only when r_q kSlack <= 2^-51 and
/// |v_q| < 2; rounding v_q to double adds at most half an ulp of a number below 2, 2^-53; so the
/// double is within 2^-51 + 2^-53 < 2^-50 of b_i. The exact b_i of a contact lies in [0, 1], so
/// clamping to [0, 1] moves the double towards it and keeps the bound. Zeros: an edge has exactly
/// one zero barycentric and a vertex two; the intervals of the zero ones contain 0, so when exactly
/// that many of the three intervals contain 0 they are the zero ones (set to 0.0; a vertex's third
/// is then exactly 1.0). When they do not identify the zeros, or a bound is too wide: false
/// (undecided). Behind and interior carry no zero information; their values are just clamped.
[[gnu::noinline]] inline bool triangle_barycentrics(const Ray<double>& ray, const Triangle<double>& tri, Contact contact,
                                                    double& b1, double& b2) {
  if constexpr (!kFilterAvailable) {
    return false;
  } else {
    const Vec3<Bounded> o = lift(ray.o), d = lift(ray.d);
    const Vec3<Bounded> a = lift(tri.p0) - o, b = lift(tri.p1) - o, c = lift(tri.p2) - o;
    const Bounded u[3] = {dot(d, cross(b, c)), dot(d, cross(c, a)), dot(d, cross(a, b))};
    const Bounded den = u[0] + u[1] + u[2];
    if (!nonzero(den)) return false;
    double w[3];
    bool maybe_zero[3];
    int candidates = 0;
    for (int i = 0; i < 3; ++i) {
      const Bounded q = u[i] / den;
      const Wide r = q.r * kSlack;
      if (!(r <= 0x1p-51L) || !(std::fabs(q.v) < 2)) return false;  // also catches NaN
      const double x = static_cast<double>(q.v);
      w[i] = x < 0 ? 0.0 : (x > 1 ? 1.0 : x + 0.0);
      maybe_zero[i] = std::fabs(q.v) <= r;
      candidates += maybe_zero[i];
    }
    const int zeros = contact == Contact::edge ? 1 : (contact == Contact::vertex ? 2 : 0);
    if (zeros > 0) {
      if (candidates != zeros) return false;
      for (int i = 0; i < 3; ++i)
        if (maybe_zero[i]) w[i] = 0.0;
        else if (zeros == 2) w[i] = 1.0;
    }
    b1 = w[1];
    b2 = w[2];
    return true;
  }
}

}  // namespace detail

/// Header-only, rayproof::core: the filter's answer, or std::nullopt (undecided).
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Plane<double>& p) {
  return plane(ray, p);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Sphere<double>& s) {
  return sphere(ray, s);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  return ellipsoid(ray, e);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Box<double>& b) {
  return box(ray, b);
}
[[nodiscard]] inline std::optional<Hit<double>> try_intersect(const Ray<double>& ray, const Disk<double>& dk) {
  return disk(ray, dk);
}
[[nodiscard]] inline std::optional<TriangleHit<double>> try_intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  const std::optional<Hit<double>> h = triangle(ray, tri);
  if (!h) return std::nullopt;
  TriangleHit<double> out{h->contact, h->t, h->t2};
  switch (h->contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex: case Contact::behind:
      if (!detail::triangle_barycentrics(ray, tri, h->contact, out.b1, out.b2)) return std::nullopt;
      break;
    default:
      break;
  }
  return out;
}

/// Compiled, rayproof::certified: always decided (exact fallback, GMP, when the filter is not).
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& plane);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& sphere);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& ellipsoid);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& box);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& disk);
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& triangle);

/// Calls of intersect on the calling thread, since it started, that needed the exact fallback.
[[nodiscard]] std::uint64_t fallback_count();

}  // namespace rayproof::certified
