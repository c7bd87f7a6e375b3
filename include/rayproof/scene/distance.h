#pragma once
/// Closest point and distance on an ExactMesh (rayproof/scene/exact_mesh.h): the nearest triangle, the
/// closest point on it with its barycentrics, the distance and the side. The rule and why it is
/// exact: docs/distance.md.
///
/// Contract:
/// - distance: the exact Euclidean distance from p to the union of the triangles (each closed:
///   edges and vertices included; a zero-area triangle is its edges), rounded to the nearest double
///   (ties to even). The exact squared distance is a rational number; the double filter decides the
///   rounding when it can and GMP rationals decide it otherwise: no epsilon, every scale
///   (coordinates near 2^+-600 included; a distance beyond the double range is +inf).
/// - triangle: a triangle at that exact distance, the lowest index (file order) among exactly tied ones.
/// - point, barycentric: the closest point on that triangle and its barycentric weights of the
///   triangle's vertices 0, 1, 2 (summing to 1 up to rounding), computed in double from the exactly
///   chosen feature (face, edge or vertex), or rounded from the exact rationals when the exact stage
///   ran: within a few ulps of the coordinates, not exact (the weights lose digits on slivers).
/// - side: ExactMesh::contains(p) (exact), when asked for; Side::surface exactly when distance is 0.
/// - A point with a NaN or infinite coordinate: distance NaN, triangle kNoTriangle, side invalid.
///   A mesh without triangles: distance +inf, triangle kNoTriangle, side outside.
/// - Threads: the calls are const; the first builds the distance tree once (thread-safe).
#include <array>
#include <cstdint>

#include "rayproof/float_util.h"
#include "rayproof/scene/contains.h"
#include "rayproof/vec3.h"

namespace rayproof {

/// Which stage decided a query (for measurements: how often the exact stage runs).
enum class DistanceStage : std::uint8_t {
  filter = 0,     ///< the double filter decided the triangle and the rounding
  rounding = 1,   ///< the triangle by the filter, the rounding of the distance in rationals
  selection = 2,  ///< candidates within their error bounds of each other: compared in rationals
  extreme = 3,    ///< the double filter over- or underflowed (extreme scales): searched in rationals
  none = 4,       ///< no search (invalid point, empty mesh)
};
[[nodiscard]] const char* to_string(DistanceStage s);

struct ClosestPoint {
  static constexpr std::uint32_t kNoTriangle = 0xffffffffu;
  double distance = kNaN<double>;
  std::uint32_t triangle = kNoTriangle;
  Vec3<double> point{kNaN<double>, kNaN<double>, kNaN<double>};
  std::array<double, 3> barycentric{kNaN<double>, kNaN<double>, kNaN<double>};
  Side side = Side::invalid;  ///< Side::invalid also when the side was not asked for
  DistanceStage stage = DistanceStage::none;
  /// -distance inside, +distance outside, 0 on the surface, NaN when the side is invalid.
  [[nodiscard]] double signed_distance() const {
    switch (side) {
      case Side::inside: return -distance;
      case Side::outside: return distance;
      case Side::surface: return 0.0;
      default: return kNaN<double>;
    }
  }
};

/// The exact distance from p to one closed triangle (zero area: its edges), correctly rounded;
/// NaN for a point or vertex with a NaN or infinite coordinate. For measuring others against exact.
[[nodiscard]] double exact_triangle_distance(const Vec3<double>& p, const std::array<Vec3<double>, 3>& t);
/// The sign of D(p, t1) - D(p, t2), D the exact squared distances (rationals): -1, 0 or +1.
[[nodiscard]] int compare_triangle_distances(const Vec3<double>& p, const std::array<Vec3<double>, 3>& t1,
                                             const std::array<Vec3<double>, 3>& t2);

}  // namespace rayproof
