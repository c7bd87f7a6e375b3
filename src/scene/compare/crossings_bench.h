#pragma once
/// The measuring half of `rayproof bench crossings`: the ray sets (random, and axis rays exactly
/// through vertices, rounded to float), timed interleaved runs of ClosedMesh::ray_crossings and of
/// Embree's all hits on one thread (thread CPU time), and the tally of Embree's hits against
/// rayproof's exact contacts. The tool prints what these return.
#include <random>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/ray.h"
#include "rayproof/scene/contains.h"
#include "scene/compare/crossings_compare.h"

namespace rayproof::scene::compare {

/// Embree's hits matched by t to rayproof's exact contacts (within `tol` of the contact's t): the
/// first hit at a crossing is right, another one there a duplicate, a hit at a touch (a point
/// contact that is no crossing) `at_touches`, a hit at no contact unmatched; crossings with no hit
/// are missed; `rays_exact` rays had exactly one hit per crossing and no other.
struct CrossingsTally {
  std::size_t crossings = 0, touches = 0, hits = 0, right = 0, duplicates = 0, at_touches = 0, unmatched = 0,
              missed = 0, rays_exact = 0;
};

/// Adds one ray's comparison to `t`.
void tally_ray(const RayCrossings& r, const std::vector<EmbreeHit>& hits, double tol, CrossingsTally& t);

/// The two ray sets on a mesh whose vertices are floats: `n` random rays (origins in the box grown
/// by 10% each side, normal directions) and `n` axis rays exactly through a used vertex.
struct CrossingRaySets {
  std::vector<Ray<double>> random, vertex;
  double size = 0;  ///< the box's largest extent
};
[[nodiscard]] CrossingRaySets crossing_ray_sets(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng);

/// `repeat` interleaved runs of both on `rays`; the tally when Embree ran (else only rayproof's counts).
struct CrossingsRun {
  std::vector<double> ours, embree;  ///< Mrays/s per run
  CrossingsTally tally;
};
[[nodiscard]] CrossingsRun time_crossings(const ClosedMesh& cm, const AllHitsCompetitor& embree,
                                          const std::vector<Ray<double>>& rays, double size, int repeat);

/// Thread CPU time in seconds.
[[nodiscard]] double thread_seconds();

}  // namespace rayproof::scene::compare
