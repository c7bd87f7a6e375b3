#pragma once
/// All hits along a ray by Embree 3, for `rayproof bench crossings`: an intersect-context filter
/// function records every hit of rtcIntersect1 and rejects it (valid = 0), so the traversal goes on
/// to the next; the hits of one ray are then sorted by t. This is how users collect every crossing
/// with Embree (a ray through a shared edge or vertex then reports each triangle there).
/// The ray and the vertices are rounded to float (Embree's precision). Embree stays inside this
/// target.
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayproof/ray.h"
#include "rayproof/vec3.h"

namespace rayproof::scene::compare {

struct EmbreeHit {
  float t;
  std::uint32_t prim;
};

struct AllHitsCompetitor {
  std::string name = "embree-all-hits";
  std::string note;  ///< why it is not available (then run is empty)
  /// Every hit of each ray sorted by t into hits[i] (cleared first): on the calling thread
  /// (threads = 1), else rays in chunks on a TBB arena of `threads` threads (0: TBB's default).
  std::function<void(std::span<const Ray<double>>, std::vector<std::vector<EmbreeHit>>&, int threads)> run;
};

[[nodiscard]] AllHitsCompetitor make_embree_all_hits(const std::vector<Vec3<double>>& vertices,
                                                     const std::vector<std::array<std::uint32_t, 3>>& triangles);

}  // namespace rayproof::scene::compare
