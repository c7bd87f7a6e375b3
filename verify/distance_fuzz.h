#pragma once
/// fuzz --distance: random small meshes (soups with integer and real coordinates, zero-area and
/// duplicate triangles, scaled by powers of two up to 2^+-1000) and points on and around them
/// (vertices, edge midpoints, dyadic face points, jittered, uniform, far), each query of
/// ExactMesh::closest_point checked against a brute force over every triangle in rationals: the
/// lowest nearest triangle, the correctly rounded distance, surface exactly at distance 0.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof::verify {

struct DistanceFuzzOptions {
  double seconds = 0;          ///< stop after this long (0: use max_meshes)
  std::size_t max_meshes = 0;  ///< stop after this many meshes (0: use seconds)
  std::uint64_t seed = 1;
};

struct DistanceFuzzFinding {
  std::string what;  ///< e.g. "triangle 3, expected 1"
  std::string off;   ///< the mesh as an OFF file
  Vec3<double> p;
};

struct DistanceFuzzResult {
  std::size_t meshes = 0, points = 0, wrong_triangle = 0, wrong_distance = 0, wrong_side = 0;
  std::vector<DistanceFuzzFinding> findings;  ///< the first few
};

[[nodiscard]] DistanceFuzzResult run_distance_fuzz(const DistanceFuzzOptions& opt);

}  // namespace rayproof::verify
