// fuzz --winding: prints the campaign's counts and its first findings (an OFF mesh and the point).
#include <fmt/core.h>

#include "cli/mesh_modes.h"
#include "verify/winding_fuzz.h"

namespace rayproof::cli {

int run_winding_fuzz_cli(const FuzzCliOptions& o) {
  if (!o.methods.empty() || !o.families.empty() || !o.shard.empty() || !o.summary.empty() || o.crossings ||
      o.distance) {
    fmt::print(stderr, "rayproof fuzz: --winding takes --seconds or --cases and --seed only\n");
    return 2;
  }
  verify::WindingFuzzOptions opt;
  opt.seconds = o.seconds;
  opt.max_meshes = o.cases;
  if (opt.seconds <= 0 && opt.max_meshes == 0) opt.seconds = 10;
  opt.seed = o.seed;
  const auto r = verify::run_winding_fuzz(opt);
  fmt::print("{:>8} {:>10} {:>8} {:>9} {:>13} {:>11} {:>14} {:>7}\n", "meshes", "points", "surface", "near 1/2",
             "bound misses", "wrong side", "wrong surface", "errors");
  fmt::print("{:>8} {:>10} {:>8} {:>9} {:>13} {:>11} {:>14} {:>7}\n", r.meshes, r.points, r.surface_points, r.near_half,
             r.bound_misses, r.wrong_sides, r.wrong_surfaces, r.errors);
  fmt::print("batches: {} meshes, {} points, {} sides that differ from the point asked alone\n", r.batch_meshes,
             r.batch_points, r.batch_differ);
  std::string kinds;
  for (std::size_t k = 0; k < verify::kWindingMeshKinds; ++k)
    kinds += fmt::format("{}{} {}", k ? ", " : "", verify::to_string(verify::WindingMeshKind(k)), r.kind_meshes[k]);
  fmt::print("meshes by kind: {} ({} triangles); near 1/2: the reference within 1e-6 of 1/2, side not judged; "
             "{:.1f} s\n",
             kinds, r.triangles, r.seconds);
  fmt::print("reproduce: rayproof fuzz --winding --seed {} --cases {}\n", o.seed, r.meshes);
  for (const auto& f : r.findings)
    fmt::print("finding: {} at p = ({:a}, {:a}, {:a}) on\n{}", f.what, f.p.x, f.p.y, f.p.z, f.off);
  return r.failures() ? 1 : 0;
}

}  // namespace rayproof::cli
