// fuzz --distance: prints the campaign's counts and its first findings (an OFF mesh and the point).
#include <fmt/core.h>

#include "cli/mesh_modes.h"
#include "verify/distance_fuzz.h"

namespace rayproof::cli {

int run_distance_fuzz_cli(const FuzzCliOptions& o) {
  if (!o.methods.empty() || !o.families.empty() || !o.shard.empty() || !o.summary.empty() || o.mesh) {
    fmt::print(stderr, "rayproof fuzz: --distance takes --seconds or --cases and --seed only\n");
    return 2;
  }
  verify::DistanceFuzzOptions opt;
  opt.seconds = o.seconds;
  opt.max_meshes = o.cases;
  if (opt.seconds <= 0 && opt.max_meshes == 0) opt.seconds = 10;
  opt.seed = o.seed;
  const auto r = verify::run_distance_fuzz(opt);
  fmt::print("{:>8} {:>8} {:>15} {:>15} {:>11}\n", "meshes", "points", "wrong triangle", "wrong distance", "wrong side");
  fmt::print("{:>8} {:>8} {:>15} {:>15} {:>11}\n", r.meshes, r.points, r.wrong_triangle, r.wrong_distance, r.wrong_side);
  for (const auto& f : r.findings)
    fmt::print("finding: {} at p = ({:a}, {:a}, {:a}) on\n{}", f.what, f.p.x, f.p.y, f.p.z, f.off);
  return r.wrong_triangle + r.wrong_distance + r.wrong_side ? 1 : 0;
}

}  // namespace rayproof::cli
