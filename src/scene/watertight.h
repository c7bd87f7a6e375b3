#pragma once
/// Watertightness at scale: from a point inside a closed mesh, cast a ray at every vertex and every
/// edge midpoint (the points where a non-watertight kernel lets rays slip between triangles) and
/// count the rays that find no hit: each is a leak.
#include <cstdint>

#include "scene/accel.h"

namespace rayproof::scene {

struct LeakCount {
  std::uint64_t rays = 0;
  std::uint64_t misses = 0;  ///< rays with no closest hit: leaks
};

/// Targets: every vertex, then the midpoint of every distinct edge (at most `limit` targets,
/// evenly strided when there are more; 0 = all).
[[nodiscard]] std::vector<Vec3<double>> leak_targets(const mesh::Mesh& m, std::size_t limit = 0);
/// Rays from `inside` towards each target.
[[nodiscard]] std::vector<Ray<double>> leak_rays(Vec3<double> inside, const std::vector<Vec3<double>>& targets);
[[nodiscard]] LeakCount count_leaks(const Accel& a, const SceneMethod& m, const std::vector<Ray<double>>& rays,
                                    int threads = 0);
/// The centroid of the solid bounded by a closed mesh (signed tetrahedron volumes); inside for
/// the star-shaped meshes the leak test uses.
[[nodiscard]] Vec3<double> volume_centroid(const mesh::Mesh& m);
/// A closed mesh with about `min_triangles` triangles or more: a subdivided icosphere, with each
/// vertex pushed radially by a fixed bumpy function so that triangles are irregular.
[[nodiscard]] mesh::Mesh bumpy_sphere(std::size_t min_triangles);

}  // namespace rayproof::scene
