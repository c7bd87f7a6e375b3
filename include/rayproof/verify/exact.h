#pragma once
/// Exact answers for one ray against one primitive, typed (no case file): the class of exact real
/// arithmetic on the given doubles (docs/cases.md), every t correctly rounded to the nearest double
/// (ties to even), and for triangles the barycentrics b1, b2 of the contact point correctly
/// rounded too. This is the ground truth: the `exact` method is these kernels on a case's fields,
/// and the certified tier (rayproof/certified/intersect.h) is judged against it.
///
/// Compiled, in the verify component: link rayproof::verify (CGAL, GMP, MPFR). The exact algorithm
/// (src/exact/algorithms.h) runs on CGAL's exact kernel (Gmpq in Simple_cartesian), with MPFR
/// for roots and roundings (verify/exact_cgal.cpp, src/exact/rounding.cpp). rayproof::certified
/// (GMP, MPFR, no CGAL) does not provide this header's functions: its exact fallback is the same
/// algorithm on gmpxx's mpq_class, checked against this one bit for bit
/// (tests/exact_crosscheck_test.cpp).
/// Cost: microseconds per call (GMP rationals; MPFR for roots and roundings), see docs/library.md.
/// Thread safety: the functions keep no state; concurrent calls from several threads are safe
/// (every CGAL number is local to the call; GMP and MPFR are reentrant; MPFR's exponent range,
/// changed during a rounding and restored, is thread-local in Debian's build).
///
/// Results (rayproof/hit.h): fields a class does not carry are NaN.
///  - invalid: a field NaN or infinite, d = 0, negative radius or semi-axis, box lo > hi.
///  - degenerate: zero normal, radius or semi-axis, collinear triangle.
///  - plane, disk: t. sphere, ellipsoid: t <= t2, the two roots (tangent: t = t2), also for
///    behind and inside. box: t = entry, t2 = exit (hit, graze, inside, behind).
///  - triangle: t for interior / edge / vertex / behind, with b1 (weight of p1) and b2 (weight of
///    p2) of the plane point rounded to nearest (a zero barycentric is exactly 0.0, a vertex's 1 is
///    exactly 1.0); coplanar: [t, t2] the range of t >= 0 on the closed triangle, or NaN, NaN.
#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"
#include "rayproof/tritri_class.h"

namespace rayproof::exact {

[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& plane);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& sphere);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& ellipsoid);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& box);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& disk);
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& triangle);

/// The exact class of two triangles (docs/tritri.md), from CGAL's do_intersect and intersection on
/// Triangle_3 with an exact kernel (verify/exact_tritri.cpp): independent of the sign-based
/// classifier of rayproof/certified/tritri.h, which is judged against it.
[[nodiscard]] TriTri tritri(const Triangle<double>& a, const Triangle<double>& b);
/// Whether the closed triangles share a point, zero-area ones included (as CGAL's Segment_3 or
/// Point_3): CGAL's do_intersect / has_on on the exact kernel. NaN or infinite: false.
[[nodiscard]] bool tritri_meets(const Triangle<double>& a, const Triangle<double>& b);

}  // namespace rayproof::exact
