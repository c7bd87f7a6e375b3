/// rayproof spawn: self-intersections of spawned shadow and reflection rays per origin strategy and
/// method, on planes, spheres and disks (light/spawn_count.h).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <memory>

#include "cli/commands.h"
#include "cli/mesh_modes.h"
#include "cli/tool.h"
#include "registry/registry.h"
#include "light/spawn_count.h"

namespace rayproof::cli {

namespace {



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
  const Method* exact = registry::all_methods().find("certified");
  if (!exact) {
    fmt::print(stderr, "{}: the certified method is not registered\n", kCmd);
    return 2;
  }
  if (opt.slab_gap != 0) {
    if (!(std::isfinite(opt.slab_gap) && opt.slab_gap > 0 && opt.slab_gap < 1)) {
      fmt::print(stderr, "{}: --slab-gap must be in (0, 1) (the gap over the magnitude 2^k)\n", kCmd);
      return 2;
    }
    const auto sel = registry::select_methods("spawn", opt.methods, false);
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
      for (const auto& m : registry::all_methods().all())
        if (m.name != "exact" && m.supports(*kind)) methods.push_back(&m);
    } else {
      const auto sel = registry::select_methods("spawn", opt.methods, true);
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
  auto* sub = app.add_subcommand(
      "spawn", "Self-intersections of spawned shadow and reflection rays per origin strategy and method (planes, spheres, disks)");
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
