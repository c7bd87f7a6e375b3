#pragma once
// Floating-point filters of the distance judge's exact tests on answered closest points
// (verify/distance_check.cpp): each decides in x87 extended precision (long double, 64-bit
// significand) with a proven error bound, and answers "cannot tell" when the bound does not decide,
// where the judge falls back to rationals (exact_triangle_distance). They never decide otherwise
// than the exact test would. Where long double is not the x87 format (64-bit significand, 15-bit
// exponent), or at run time the rounding is not to nearest or the x87 precision control is lowered,
// they always answer "cannot tell".
#include <array>

#include "rayproof/vec3.h"

namespace rayproof::verify::detail {

/// long double is the x87 extended format the bounds below are proven for, rounding to nearest at
/// its full 64 bits.
[[nodiscard]] bool distance_filter_available();

/// True when the exact distance from x to the closed triangle t (a zero-area one: its edges) is
/// certainly at most b, so that its correct rounding is too; false when the filter cannot tell (x
/// may still be within b). x and t finite, b > 0 finite.
[[nodiscard]] bool certainly_within(const Vec3<double>& x, const std::array<Vec3<double>, 3>& t, double b);

/// The exact distance |p - x| correctly rounded to double when the filter can tell (a normal
/// double or 0), else NaN. p and x finite.
[[nodiscard]] double rounded_point_distance(const Vec3<double>& p, const Vec3<double>& x);

/// True when p is certainly at the same exact distance from the closed triangles t1 and t2 (a
/// zero-area one: its edges) because the nearest point of each is one corner they share (equal
/// coordinates), or lies on an edge they share; false when the filter cannot tell (they may still
/// tie). p finite.
[[nodiscard]] bool certainly_tied(const Vec3<double>& p, const std::array<Vec3<double>, 3>& t1,
                                  const std::array<Vec3<double>, 3>& t2);

}  // namespace rayproof::verify::detail
