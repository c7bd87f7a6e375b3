// fuzz --mesh: random closed meshes, leak rays at every vertex and edge midpoint,
// and the crossing parity of random rays (verify/mesh_fuzz.h).
#include <fmt/core.h>
#include <fmt/format.h>

#include "cli/mesh_check_text.h"
#include "cli/mesh_modes.h"
#include "registry/registry.h"
#include "scene/accel.h"
#include "verify/mesh_check.h"
#include "verify/mesh_fuzz.h"

namespace rayproof::cli {

namespace {
/// Methods that must never leak (and, for certified, never fail parity) in mesh mode.
bool must_not_leak(const std::string& m) { return m == "robust" || m == "certified"; }

}  // namespace

int run_mesh_fuzz_cli(const FuzzCliOptions& o) {
  verify::MeshFuzzOptions opt;
  auto user = make_user_kernels("fuzz", o.user);
  if (!user) return 2;
  for (const auto& k : *user) fmt::print("# {}: {}\n", k->name, k->summary);  // GPU kernels: the device and driver
  // --methods names the mesh methods and may name your kernels (checked below, whether named or not).
  std::vector<std::string> names;
  if (o.methods.empty()) names = {"float", "double", "watertight-float", "watertight", "robust", "certified"};
  for (const auto& name : o.methods)
    if (!registry::is_user_kernel(name, *user)) names.push_back(name);
  for (const auto& name : names) {
    try {
      opt.methods.push_back(scene::find_scene_method(name, registry::all_methods()));
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof fuzz: {}\n", e.what());
      return 2;
    }
  }
  if (!o.families.empty()) {
    fmt::print(stderr, "rayproof fuzz: --families does not apply to --mesh\n");
    return 2;
  }
  if (!o.shard.empty() || !o.summary.empty()) {
    fmt::print(stderr, "rayproof fuzz: --shard and --summary apply to case campaigns, not to --mesh\n");
    return 2;
  }
  for (const auto& k : *user)
    if (!k->supports(io::Kind::triangle)) {
      fmt::print(stderr, "rayproof fuzz: --mesh needs triangle kernels; '{}' answers no triangles\n", k->name);
      return 2;
    }
  opt.seconds = o.seconds;
  opt.max_meshes = o.cases;
  if (opt.seconds <= 0 && opt.max_meshes == 0) opt.seconds = 10;
  opt.seed = o.seed;
  opt.threads = o.jobs;
  const auto res = verify::run_mesh_fuzz(opt);
  fmt::print("{:<18} {:>10} {:>8} {:>11} {:>15}\n", "method", "leak rays", "leaks", "parity rays", "parity failures");
  for (const auto& st : res.stats)
    fmt::print("{:<18} {:>10} {:>8} {:>11} {:>15}\n", st.method, st.leak_rays, st.leaks, st.parity_rays, st.parity_failures);
  // Your kernels: the leak rays of the same meshes (verify/mesh_check.h), candidates from certified.
  int user_bad = 0;
  if (!user->empty()) {
    verify::MeshCheckOptions mopt;
    mopt.finder = scene::find_scene_method("certified", registry::all_methods());
    for (const auto& k : *user) {
      std::vector<verify::MeshCheck> checks;
      for (std::size_t i = 0; i < res.meshes; ++i) checks.push_back(verify::check_mesh(*k, verify::generated_mesh(opt, i), mopt));
      std::uint64_t rays = 0, leaks = 0;
      for (const auto& c : checks) rays += c.rays, leaks += c.leaks + c.failures.size();
      fmt::print("{:<18} {:>10} {:>8}   (your kernel: leak rays only)\n", k->name, rays, leaks);
      if (leaks > 0) {
        ++user_bad;
        for (const auto& l : leak_lines(checks, mopt.finder.name)) fmt::print(stderr, "{}\n", l);
      }
    }
  }

  fmt::print("\n{} meshes ({} perturbed icospheres, {} convex hulls), {} triangles in {:.1f} s; "
             "{} parity rays with an exact edge or vertex contact set aside\n",
             res.meshes, res.star_meshes, res.hull_meshes, res.triangles, res.seconds, res.contact_rays_set_aside);
  fmt::print("reproduce: rayproof fuzz --mesh --seed {} --cases {}{}\n", o.seed, res.meshes,
             o.methods.empty() ? "" : " --methods " + fmt::format("{}", fmt::join(o.methods, ",")));
  int bad = 0;
  for (const auto& st : res.stats) {
    const bool broken = must_not_leak(st.method) && (st.leaks > 0 || (st.method == "certified" && st.parity_failures > 0));
    if (!broken) continue;
    ++bad;
    fmt::print(stderr, "rayproof fuzz: method '{}' leaked {} times and failed parity {} times\n", st.method, st.leaks,
               st.parity_failures);
    for (const auto& f : res.findings)
      if (f.method == st.method)
        fmt::print(stderr, "  mesh {} ({}): {} ray {} {} {} {} {} {}{}\n", f.mesh,
                   f.shape == verify::MeshShape::star ? "icosphere" : "hull", f.leak ? "leak" : "parity",
                   io::format_double(f.ray.o.x), io::format_double(f.ray.o.y), io::format_double(f.ray.o.z),
                   io::format_double(f.ray.d.x), io::format_double(f.ray.d.y), io::format_double(f.ray.d.z),
                   f.leak ? "" : fmt::format(" ({} crossings)", f.crossings));
  }
  if (user_bad) fmt::print(stderr, "rayproof fuzz: {} of your kernels leaked (the leaks are listed above)\n", user_bad);
  return bad ? 1 : 0;
}

}  // namespace rayproof::cli
