#pragma once
/// Point containment by other libraries, for `rayproof bench contains`: CGAL's
/// Side_of_triangle_mesh with Epick (exact predicates on the double inputs) and Epeck, and Embree 3
/// one-ray parity along (1, 1, 1) as Open3D casts it (a context filter counts every hit of
/// rtcIntersect1 and rejects it, so traversal goes on; the point and direction rounded to float).
/// CGAL and Embree stay inside this target; callers pass points and get side codes
/// (0 outside, 1 inside, 2 on the boundary: rayproof::Side's numbers).
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof::scene::compare {

struct ContainsCompetitor {
  std::string name;
  std::string note;  ///< e.g. why it was not built
  /// Side code of each point, on the calling thread.
  std::function<void(std::span<const Vec3<double>>, std::span<std::uint8_t>)> run;
};

/// Those of "cgal-epick", "cgal-epeck", "embree-parity" named in the comma-separated `names` that
/// can be built here (Embree only when compiled in; CGAL needs a mesh it can load as a
/// Surface_mesh: a competitor that cannot is returned without `run` and with a note).
[[nodiscard]] std::vector<ContainsCompetitor> make_contains_competitors(
    const std::vector<Vec3<double>>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::string& names = "cgal-epick,cgal-epeck,embree-parity");

}  // namespace rayproof::scene::compare
