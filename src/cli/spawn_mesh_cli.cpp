// spawn --mesh: spawned rays on triangle meshes through the mesh casters.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "cli/mesh_modes.h"
#include "cli/scene_input.h"
#include "light/spawn_count.h"
#include "light/spawn_mesh.h"
#include "mesh/mesh.h"

namespace rayproof::cli {

/// Spawned rays on a triangle mesh (light/spawn_mesh.h): the generated closed meshes (a subdivided
/// octahedron on the unit sphere and a slab 2^-16 thick beside it, moved to (2^k, 2^k, 2^k) and
/// scaled by 2^max(0, k - 10) so that float vertices still resolve it) or a file.
int run_spawn_mesh(const SpawnOptions& opt) {
  constexpr const char* kCmd = "rayproof spawn";
  std::vector<std::pair<std::string, mesh::Mesh>> meshes;
  try {
    if (opt.mesh == "generated") {
      for (int mag : opt.magnitudes)
        meshes.emplace_back(fmt::format("generated 2^{}", mag),
                            light::generated_spawn_mesh(4, std::ldexp(1.0, -16), std::ldexp(1.0, std::max(0, mag - 10)),
                                                            mag == 0 ? 0.0 : std::ldexp(1.0, mag)));
    } else {
      meshes.emplace_back(opt.mesh, mesh::read_mesh(opt.mesh));
      fmt::print(stderr, "{}: {}: {} triangles{}\n", kCmd, opt.mesh, meshes.back().second.triangles.size(),
                 reader_note(opt.mesh));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: {}\n", kCmd, e.what());
    return 2;
  }
  fmt::print("{:<20} {:<14} {:<10} {:>8} {:>7} {:>10} {:>10} {:>7} {:>9} {:>6} {:>8} {:>9} {:>11}\n", "mesh", "strategy",
             "method", "spawned", "misses", "self(own)", "self(exact)", "shadow", "false-occ", "leaks", "occ(ray)", "leaks(ray)",
             "misses(ray)");
  for (const auto& [name, m] : meshes) {
    if (m.triangles.empty()) {
      fmt::print(stderr, "{}: {} has no triangles\n", kCmd, name);
      return 2;
    }
    std::vector<light::MeshSpawnCount> rows;
    try {
      rows = light::count_mesh_spawn(m, opt.trials, opt.seed, opt.epsilon);
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: {}: {}\n", kCmd, name, e.what());
      return 2;
    }
    for (const auto& r : rows)
      fmt::print("{:<20} {:<14} {:<10} {:>8} {:>7} {:>10} {:>10} {:>7} {:>9} {:>6} {:>8} {:>9} {:>11}\n", name,
                 light::to_string(r.strategy), r.method, r.spawned, r.primary_misses, r.self_hits, r.exact_self_hits, r.shadow,
                 r.false_occlusions, r.leaks, r.false_occlusions_ray, r.leaks_ray, r.primary_misses_ray);
  }
  return 0;
}

}  // namespace rayproof::cli
