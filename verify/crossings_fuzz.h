#pragma once
/// Fuzzing of ExactMesh::ray_crossings (`rayproof fuzz --mesh --crossings`): the random closed meshes of
/// `fuzz --mesh` (verify/mesh_fuzz.h, the same mesh i for a seed), rays from their interior points
/// and from points outside aimed exactly at every vertex, at every edge's midpoint and in random
/// directions. On a closed oriented mesh the net count of crossings (in minus out) along a ray from
/// p must be minus the exact winding number at p (ExactMesh::winding: another ray, another code
/// path), the number of crossings must have the parity of that winding number, and the listed t
/// must never decrease. A ray through a vertex or an edge is exactly where all-hits double-counts.
#include <cstdint>
#include <vector>

#include "verify/mesh_fuzz.h"

namespace rayproof::verify {

struct CrossingsFinding {
  std::size_t mesh = 0;
  Ray<double> ray;
  std::size_t crossings = 0;
  int net = 0, winding = 0;
};

struct CrossingsFuzzResult {
  std::size_t meshes = 0, triangles = 0;
  std::uint64_t rays = 0, aimed_rays = 0;  ///< aimed: at a vertex or an edge midpoint
  std::uint64_t crossings = 0, touches = 0, failures = 0;
  double seconds = 0;
  std::vector<CrossingsFinding> findings;  ///< the first opt.keep_findings
};

/// Uses opt's seed, seconds / max_meshes, mesh sizes and interior_points (parity_rays random rays per point).
[[nodiscard]] CrossingsFuzzResult run_crossings_fuzz(const MeshFuzzOptions& opt);

}  // namespace rayproof::verify
