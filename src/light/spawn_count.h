#pragma once
/// Self-intersections of spawned rays on analytic primitives: primary rays hit a
/// plane, sphere or disk through a method's kernel, the hit point is computed in the method's
/// precision, a reflection ray and a shadow ray (toward a point on the incoming side) leave it by
/// each origin strategy of rayproof/spawn.h, and the spawned rays are tested against the primitive
/// they leave. Leaving to the side they came from, they cannot meet it again: every contact at
/// t > 0 is a self-intersection. Counted as the method's own kernel sees it and as an exact method
/// (certified) sees the same spawned ray. The certified strategy uses that exact method as its
/// classifier (spawn_ray_certified); its origins sit within ulps of the surface, so a renderer using
/// it must test the primitive it leaves with the exact classifier too: the exact count is the one
/// that applies, the own-kernel count shows what a fast kernel would see there instead.
#include <cstdint>
#include <span>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/spawn.h"

namespace rayproof::light {

struct SpawnCount {
  io::Kind kind = io::Kind::plane;
  int magnitude_log2 = 0;
  SpawnStrategy strategy = SpawnStrategy::none;
  const Method* method = nullptr;
  std::uint64_t spawned = 0;          ///< spawned rays (two per primary hit)
  std::uint64_t primary_misses = 0;   ///< primary rays the method's kernel did not see hit
  std::uint64_t self_hits = 0;        ///< the method's kernel finds the surface again at t > 0
  std::uint64_t exact_self_hits = 0;  ///< the exact method does, on the same spawned ray
};

[[nodiscard]] std::string_view to_string(SpawnStrategy s);

/// `trials` primary rays per method at positions of magnitude about 2^magnitude_log2; one row per
/// strategy x method. `exact` answers the spawned rays exactly (certified or exact). Throws
/// std::invalid_argument for kinds other than plane, sphere and disk or a method without the kind.
[[nodiscard]] std::vector<SpawnCount> count_self_intersections(io::Kind kind, std::span<const Method* const> methods,
                                                               const Method& exact, std::uint64_t trials,
                                                               std::uint64_t seed, int magnitude_log2, double epsilon);

/// Leaks through a thin slab: two parallel disks `gap` apart; a primary ray hits the top one from
/// above, a shadow ray leaves the hit point toward a light below the bottom disk, which must block
/// it. Rows as above, but `self_hits` / `exact_self_hits` count leaks: the bottom disk not met at
/// 0 < t <= 1 by the method's kernel / by the exact method (an origin pushed past the bottom disk).
[[nodiscard]] std::vector<SpawnCount> count_slab_leaks(std::span<const Method* const> methods, const Method& exact,
                                                       std::uint64_t trials, std::uint64_t seed, int magnitude_log2,
                                                       double gap, double epsilon);

}  // namespace rayproof::light
