/// rayproof spawn: self-intersections of spawned shadow and reflection rays per origin strategy and
/// method, on planes, spheres and disks (light/spawn_count.h).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <memory>

#include "cli/commands.h"
#include "cli/scene_commands.h"
#include "cli/registry.h"
#include "cli/scene_input.h"
#include "light/spawn_count.h"
#include "light/spawn_mesh.h"
#include "mesh/mesh.h"

namespace rayproof::cli {

namespace {

struct SpawnOptions {
  std::vector<std::string> kinds{"plane", "sphere", "disk"};
  std::vector<std::string> methods;
  std::vector<int> magnitudes{0, 20, 40};
  std::uint64_t trials = 20000;
  std::uint64_t seed = 1;
  double epsilon = 1e-4;
  double slab_gap = 0;  ///< > 0: count leaks through a slab of this relative thickness instead
  std::string mesh;     ///< a mesh file or "generated": count on triangle meshes instead
};

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

int run_spawn(const SpawnOptions& opt) {
  constexpr const char* kCmd = "rayproof spawn";
  if (opt.trials == 0 || opt.trials > 100000000) {
    fmt::print(stderr, "{}: --trials must be in 1..1e8\n", kCmd);
    return 2;
  }
  if (!(std::isfinite(opt.epsilon) && opt.epsilon >= 0)) {
    fmt::print(stderr, "{}: --epsilon must be finite and >= 0\n", kCmd);
    return 2;
  }
  for (int m : opt.magnitudes)
    if (m < -60 || m > 60) {
      fmt::print(stderr, "{}: --magnitudes must be within -60..60 (log2 of the positions' size)\n", kCmd);
      return 2;
    }
  if (!opt.mesh.empty()) return run_spawn_mesh(opt);
  const Method* exact = all_methods().find("certified");
  if (!exact) {
    fmt::print(stderr, "{}: the certified method is not registered\n", kCmd);
    return 2;
  }
  if (opt.slab_gap != 0) {
    if (!(std::isfinite(opt.slab_gap) && opt.slab_gap > 0 && opt.slab_gap < 1)) {
      fmt::print(stderr, "{}: --slab-gap must be in (0, 1) (the gap over the magnitude 2^k)\n", kCmd);
      return 2;
    }
    const auto sel = select_methods("spawn", opt.methods, false);
    if (!sel) return 2;
    std::vector<const Method*> methods;
    for (const Method* m : *sel)
      if (m->supports(io::Kind::disk)) methods.push_back(m);
    fmt::print("{:>5} {:>10} {:<14} {:<14} {:>9} {:>9} {:>12} {:>12}\n", "2^k", "gap", "strategy", "method", "shadow",
               "misses", "leaks (own)", "leaks (exact)");
    for (int mag : opt.magnitudes) {
      const double gap = opt.slab_gap * std::ldexp(1.0, mag);
      const auto rows = light::count_slab_leaks(methods, *exact, opt.trials, opt.seed, mag, gap, opt.epsilon);
      for (const auto& r : rows)
        fmt::print("{:>5} {:>10.3g} {:<14} {:<14} {:>9} {:>9} {:>12} {:>12}\n", mag, gap, light::to_string(r.strategy),
                   r.method->name, r.spawned, r.primary_misses, r.self_hits, r.exact_self_hits);
    }
    return 0;
  }
  fmt::print("{:<7} {:>5} {:<14} {:<14} {:>9} {:>9} {:>16} {:>16}\n", "kind", "2^k", "strategy", "method", "spawned",
             "misses", "self-hits (own)", "self-hits (exact)");
  for (const auto& kind_name : opt.kinds) {
    const auto kind = io::kind_from_string(kind_name);
    if (!kind || (*kind != io::Kind::plane && *kind != io::Kind::sphere && *kind != io::Kind::disk)) {
      fmt::print(stderr, "{}: --kinds takes plane, sphere and disk, not '{}'\n", kCmd, kind_name);
      return 2;
    }
    std::vector<const Method*> methods;
    if (opt.methods.empty()) {
      for (const auto& m : all_methods().all())
        if (m.name != "exact" && m.supports(*kind)) methods.push_back(&m);
    } else {
      const auto sel = select_methods("spawn", opt.methods, true);
      if (!sel) return 2;
      for (const Method* m : *sel)
        if (!m->supports(*kind)) {
          fmt::print(stderr, "{}: method '{}' does not answer {}\n", kCmd, m->name, kind_name);
          return 2;
        }
      methods = *sel;
    }
    for (int mag : opt.magnitudes) {
      const auto rows = light::count_self_intersections(*kind, methods, *exact, opt.trials, opt.seed, mag, opt.epsilon);
      for (const auto& r : rows)
        fmt::print("{:<7} {:>5} {:<14} {:<14} {:>9} {:>9} {:>16} {:>16}\n", kind_name, mag, light::to_string(r.strategy),
                   r.method->name, r.spawned, r.primary_misses, r.self_hits, r.exact_self_hits);
    }
  }
  return 0;
}

}  // namespace

Run add_spawn(CLI::App& app) {
  auto opt = std::make_shared<SpawnOptions>();
  auto* sub = app.add_subcommand("spawn", scene_command_summary("spawn"));
  sub->add_option("--kinds", opt->kinds, "Primitive kinds: plane, sphere, disk")->delimiter(',')->capture_default_str();
  sub->add_option("--methods", opt->methods, "Methods (default: all but exact answering the kind)")->delimiter(',');
  sub->add_option("--magnitudes", opt->magnitudes, "log2 of the positions' magnitude, one run each")->delimiter(',')
      ->capture_default_str();
  sub->add_option("--trials", opt->trials, "Primary rays per kind, magnitude and method")->capture_default_str();
  sub->add_option("--seed", opt->seed, "Seed")->capture_default_str();
  sub->add_option("--epsilon", opt->epsilon, "The fixed-epsilon strategy's offset")->capture_default_str();
  sub->add_option("--slab-gap", opt->slab_gap,
                  "Count light leaks through two parallel disks this far apart (times 2^k) instead of self-intersections");
  sub->add_option("--mesh", opt->mesh,
                  "Count on a triangle mesh (a mesh file, or 'generated': a sphere and a thin slab at each magnitude) "
                  "with the float, robust and certified mesh casters");
  return [opt] { return run_spawn(*opt); };
}

}  // namespace rayproof::cli
