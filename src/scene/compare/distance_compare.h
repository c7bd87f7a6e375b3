#pragma once
/// Closest points by other libraries, for `rayproof bench distance`: CGAL's AABB_tree over the
/// triangles (Epick) with closest_point_and_primitive, and Embree 3's rtcPointQuery with a
/// closest-point callback (as Embree's closest-point tutorial: the callback computes the closest
/// point on the triangle, here from the double vertices, and shrinks the query radius). CGAL and
/// Embree stay inside this target; callers pass points and get triangle indices and distances.
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof::scene::compare {

struct DistanceCompetitor {
  std::string name;
  std::string note;  ///< e.g. why it was not built
  /// The nearest triangle and the distance of each point, on the calling thread.
  std::function<void(std::span<const Vec3<double>>, std::span<std::uint32_t>, std::span<double>)> run;
};

/// Those of "cgal-epick", "embree" named in the comma-separated `names` (Embree only when compiled in).
[[nodiscard]] std::vector<DistanceCompetitor> make_distance_competitors(
    const std::vector<Vec3<double>>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::string& names = "cgal-epick,embree");

}  // namespace rayproof::scene::compare
