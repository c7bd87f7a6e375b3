#pragma once
/// The measuring half of `rayproof bench crossings`: the ray sets (random, axis rays exactly through
/// vertices and through edge midpoints), timed interleaved runs of ExactMesh::ray_crossings and of
/// Embree's all hits (one thread: thread CPU time; more: wall time), and the tally of Embree's hits
/// against rayproof's exact contacts. The tool prints what these return.
#include <random>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/ray.h"
#include "rayproof/scene/exact_mesh.h"
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

/// The mesh a `bench crossings` argument names: "generated" (the 1.31M-triangle bumpy sphere of
/// bench contains) or a mesh file (mesh::read_mesh; throws mesh::MeshError).
[[nodiscard]] mesh::Mesh crossings_mesh(const std::string& path);

/// The ray sets on a mesh whose vertices are floats: `n` random rays (origins in the box grown by
/// 10% each side, normal directions, floats), `n` axis rays exactly through a used vertex (floats),
/// and `n` axis rays exactly through the midpoint of an edge (the midpoint (a + b) / 2 exact in
/// double, the axis one not along the edge; the origin's other two coordinates are the midpoint's,
/// so these origins are doubles: Embree gets their rounding to float).
struct CrossingRaySets {
  std::vector<Ray<double>> random, vertex, edge;
  double size = 0;  ///< the box's largest extent
};
[[nodiscard]] CrossingRaySets crossing_ray_sets(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng);

/// `repeat` interleaved runs of both on `rays` on `threads` threads (1: thread CPU time; more:
/// wall time); the tally when Embree ran (else only rayproof's counts). With `ablation`, rayproof
/// also runs with each of its speed-ups (scene/crossings_speedups.h) switched from its default
/// alone, in the same interleaved loop, and its answers are compared with the default's.
struct CrossingsRun {
  std::vector<double> ours, embree;  ///< Mrays/s per run
  struct Variant {
    std::string name;  ///< e.g. "without lane misses"
    std::vector<double> ours;
    std::size_t differing_rays = 0;  ///< rays whose crossings or touches differ from the default's
  };
  std::vector<Variant> variants;
  CrossingsTally tally;
};
[[nodiscard]] CrossingsRun time_crossings(const ExactMesh& cm, const AllHitsCompetitor& embree,
                                          const std::vector<Ray<double>>& rays, double size, int repeat,
                                          int threads = 1, bool ablation = false);

/// Thread CPU time in seconds.
[[nodiscard]] double thread_seconds();

}  // namespace rayproof::scene::compare
