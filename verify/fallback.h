#pragma once
/// The certified tier's exact fallback (inside rayproof_certified: GMP rationals, MPFR roundings, no
/// CGAL): what rayproof::certified::intersect returns when the header-only filters leave a case
/// undecided. The same contract as rayproof::exact::intersect (rayproof/exact.h): class of exact
/// arithmetic, t, t2 and triangle barycentrics rounded to nearest (ties to even), NaN for the
/// fields a class does not carry. A second, independent implementation of that contract: the
/// ground truth (rayproof::exact, in rayproof_verify) uses CGAL's exact number types, and
/// exact_crosscheck_test requires the two to agree bit for bit.
/// Internal: not installed; users call rayproof::certified::intersect.
#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified::fallback {

[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& plane);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& sphere);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& ellipsoid);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& box);
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& disk);
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& triangle);

}  // namespace rayproof::certified::fallback
