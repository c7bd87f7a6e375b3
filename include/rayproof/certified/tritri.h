#pragma once
/// The certified triangle/triangle classifier: the exact class of docs/tritri.md for two triangles
/// of doubles, decided from the signs of orient3d and orient2d alone (rayproof/certified_tritri.h).
///  - try_tritri (header-only, rayproof::core): the signs of rayproof/orient.h (Shewchuk's static
///    filter, then expansions). std::nullopt (undecided) when a sign needs the big-number fallback
///    (inputs outside the expansions' exponent window, e.g. coordinates near 2^+-600); a decided
///    answer is the exact class.
///  - tritri (compiled, link rayproof::certified: GMP, no CGAL): the same decisions on signs that
///    fall back to GMP rationals where the expansions cannot run. Always decided, exact for every
///    double input.
/// NaN or infinite coordinates: invalid. A zero-area triangle (collinear or coincident vertices):
/// degenerate, whatever the other. Both functions keep no state: concurrent calls are safe.
#include <optional>

#include "rayproof/certified_tritri.h"
#include "rayproof/orient.h"
#include "rayproof/triangle_common.h"
#include "rayproof/tritri_class.h"

namespace rayproof::certified {

/// Header-only: the exact class from the filtered signs, or std::nullopt (undecided).
[[nodiscard]] inline std::optional<TriTri> try_tritri(const Triangle<double>& a, const Triangle<double>& b) {
  auto o3 = [](const Vec3<double>& p, const Vec3<double>& q, const Vec3<double>& r, const Vec3<double>& s) {
    return orient::orient3d(p, q, r, s);
  };
  auto o2 = [](double au, double av, double bu, double bv, double pu, double pv) {
    return orient::orient2d(au, av, bu, bv, pu, pv);
  };
  tritri_detail::Signs<decltype(o3), decltype(o2)> signs{o3, o2};
  return tritri_detail::classify(signs, a, b);
}

/// Header-only: whether the closed triangles share a point, from the filtered signs, or
/// std::nullopt (undecided). Defined for zero-area triangles too (as the segment or point they
/// are); for two triangles of positive area it is meets(try_tritri(a, b)). NaN or infinite: false.
[[nodiscard]] inline std::optional<bool> try_tritri_meets(const Triangle<double>& a, const Triangle<double>& b) {
  auto o3 = [](const Vec3<double>& p, const Vec3<double>& q, const Vec3<double>& r, const Vec3<double>& s) {
    return orient::orient3d(p, q, r, s);
  };
  auto o2 = [](double au, double av, double bu, double bv, double pu, double pv) {
    return orient::orient2d(au, av, bu, bv, pu, pv);
  };
  tritri_detail::Signs<decltype(o3), decltype(o2)> signs{o3, o2};
  return tritri_detail::meets(signs, a, b);
}

/// Compiled (rayproof::certified): whether the closed triangles share a point, exact, always
/// decided; zero-area triangles included (the answer their class, degenerate, does not give).
[[nodiscard]] bool tritri_meets(const Triangle<double>& a, const Triangle<double>& b);

/// Compiled (rayproof::certified): the exact class, always decided.
[[nodiscard]] TriTri tritri(const Triangle<double>& a, const Triangle<double>& b);

/// The same for six vertices (a = (p0, p1, p2), b = (q0, q1, q2)), as mesh queries hold them.
[[nodiscard]] inline TriTri tritri(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2,
                                   const Vec3<double>& q0, const Vec3<double>& q1, const Vec3<double>& q2) {
  return tritri(Triangle<double>{p0, p1, p2}, Triangle<double>{q0, q1, q2});
}

}  // namespace rayproof::certified
