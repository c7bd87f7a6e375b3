#pragma once
/// The certified tier's exact fallback (inside rayproof_certified: GMP rationals, MPFR roundings, no
/// CGAL): what rayproof::certified::intersect returns when the header-only filters leave a case
/// undecided. The same contract, and the same algorithm, as rayproof::exact::intersect
/// (rayproof/verify/exact.h): exact/algorithms.h, here instantiated on gmpxx's mpq_class
/// (fallback.cpp), there on CGAL's Simple_cartesian<Gmpq> (exact_cgal.cpp, in rayproof_verify).
/// Class of exact arithmetic; t, t2 and triangle barycentrics rounded to nearest (ties to even);
/// NaN for the fields a class does not carry. exact_crosscheck_test requires the two
/// instantiations to agree bit for bit.
/// Internal: not installed; users call rayproof::certified::intersect.
#include <concepts>
#include <type_traits>

#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified::fallback {

/// The six kinds (double-built).
template <class P>
concept Primitive = std::same_as<P, Plane<double>> || std::same_as<P, Sphere<double>> ||
                    std::same_as<P, Ellipsoid<double>> || std::same_as<P, Box<double>> ||
                    std::same_as<P, Disk<double>> || std::same_as<P, Triangle<double>>;

/// The answer of a kind: TriangleHit<double> (with barycentrics) for triangles, else Hit<double>.
template <Primitive P>
using HitOf = std::conditional_t<std::same_as<P, Triangle<double>>, TriangleHit<double>, Hit<double>>;

/// The exact answer for ray against p (defined in fallback.cpp for each of the six kinds).
template <Primitive P>
[[nodiscard]] HitOf<P> intersect(const Ray<double>& ray, const P& p);

}  // namespace rayproof::certified::fallback
