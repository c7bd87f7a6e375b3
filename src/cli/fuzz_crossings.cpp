// fuzz --mesh --crossings: ExactMesh::ray_crossings on random closed meshes (verify/crossings_fuzz.h).
#include <fmt/core.h>

#include "cli/mesh_modes.h"
#include "io/case_file.h"
#include "verify/crossings_fuzz.h"

namespace rayproof::cli {

int run_crossings_fuzz_cli(const FuzzCliOptions& o) {
  if (!o.methods.empty() || !o.families.empty() || !o.shard.empty() || !o.summary.empty()) {
    fmt::print(stderr, "rayproof fuzz: --mesh --crossings takes --cases, --seconds and --seed only\n");
    return 2;
  }
  verify::MeshFuzzOptions opt;
  opt.seconds = o.seconds;
  opt.max_meshes = o.cases;
  if (opt.seconds <= 0 && opt.max_meshes == 0) opt.seconds = 10;
  opt.seed = o.seed;
  const auto res = verify::run_crossings_fuzz(opt);
  fmt::print("crossings: {} meshes, {} triangles, {} rays ({} aimed at a vertex or an edge midpoint): {} crossings, "
             "{} touches; {} rays where the net count is not minus the exact winding number at the origin, the "
             "count's parity is not its parity, or t decreases; {:.1f} s\n",
             res.meshes, res.triangles, res.rays, res.aimed_rays, res.crossings, res.touches, res.failures, res.seconds);
  fmt::print("reproduce: rayproof fuzz --mesh --crossings --seed {} --cases {}\n", o.seed, res.meshes);
  for (const auto& f : res.findings)
    fmt::print(stderr, "  mesh {}: ray {} {} {} {} {} {}: {} crossings, net {}, winding {}\n", f.mesh,
               io::format_double(f.ray.o.x), io::format_double(f.ray.o.y), io::format_double(f.ray.o.z),
               io::format_double(f.ray.d.x), io::format_double(f.ray.d.y), io::format_double(f.ray.d.z), f.crossings,
               f.net, f.winding);
  return res.failures ? 1 : 0;
}

}  // namespace rayproof::cli
