#pragma once
/// The correctly rounded t of a ray crossing a triangle's plane, from a t within one ulp of it
/// (the certified filter's): shared by the caster and crossings judges (caster_check.cpp,
/// crossings_check.cpp).
#include <optional>

#include "rayproof/ray.h"
#include "rayproof/triangle_common.h"

namespace rayproof::verify {

/// The exact t = ((p0 - o) . n) / (d . n) correctly rounded to the nearest double (ties to even),
/// given t0 within one ulp of it (d . n != 0): the exact signs of N - m D at the midpoints m around
/// t0, in floating-point expansions. Nothing when the inputs are outside the range where every
/// product is exact (the caller then asks exact::intersect).
[[nodiscard]] std::optional<double> round_t(const Ray<double>& r, const Triangle<double>& tri, double t0);

}  // namespace rayproof::verify
