// check --mesh: leak rays on closed meshes through the kernel under test.
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "cli/mesh_check_text.h"
#include "cli/mesh_modes.h"
#include "registry/registry.h"
#include "cli/scene_input.h"
#include "cli/user_kernels.h"
#include "scene/accel.h"
#include "verify/mesh_check.h"
#include "verify/mesh_fuzz.h"

namespace rayproof::cli {

/// check --mesh: leak rays on closed meshes (verify/mesh_check.h). Leaks break the promise
/// `watertight`, which --mesh states.
int run_mesh_check(const CheckCliOptions& o, const Method& kernel) {
  if (!kernel.supports(io::Kind::triangle)) {
    fmt::print(stderr, "rayproof check: --mesh needs a triangle kernel; '{}' answers no triangles\n", kernel.name);
    return 2;
  }
  for (const auto& e : o.expect)
    if (e != "watertight") {
      fmt::print(stderr, "rayproof check: --expect {} applies to the families, not to --mesh (which checks watertight)\n", e);
      return 2;
    }
  if (o.max_ulps || !o.families.empty() || !o.out.empty()) {
    fmt::print(stderr, "rayproof check: --max-ulps, --families and --out apply to the families, not to --mesh\n");
    return 2;
  }
  verify::MeshCheckOptions opt;
  opt.finder = scene::find_scene_method("certified", registry::all_methods());
  opt.max_targets = o.mesh_targets;
  opt.keep = o.reproducers;
  std::vector<verify::MeshCheck> results;
  auto run_one = [&](verify::MeshUnderTest mt) {
    fmt::print(stderr, "[mesh] {}: {} triangles, {} interior points\n", mt.name, mt.mesh.triangles.size(), mt.interior.size());
    results.push_back(verify::check_mesh(kernel, mt, opt));
  };
  for (const auto& name : o.mesh) {
    if (name == "generated") {
      verify::MeshFuzzOptions gen_opt;
      gen_opt.seed = o.seed;
      gen_opt.interior_points = o.interior;
      for (std::size_t i = 0; i < o.meshes; ++i) run_one(verify::generated_mesh(gen_opt, i));
      continue;
    }
    verify::MeshUnderTest mt;
    mt.name = name;
    try {
      mt.mesh = mesh::read_mesh(name);
      fmt::print(stderr, "rayproof check: {}: {} triangles{}\n", name, mt.mesh.triangles.size(), reader_note(name));
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}\n", e.what());
      return 2;
    }
    if (auto problem = verify::closed_mesh_problem(mt.mesh)) {
      fmt::print(stderr, "rayproof check: {}: cannot be leak-checked: {}\n", name, *problem);
      return 2;
    }
    mt.interior = verify::interior_points(mt.mesh, opt.finder, o.interior, o.seed);
    if (mt.interior.empty()) {
      fmt::print(stderr, "rayproof check: {}: found no point strictly inside it (is it closed and consistently oriented?)\n",
                 name);
      return 2;
    }
    run_one(std::move(mt));
  }
  const auto sentences = mesh_sentences(results);
  bool leaked = false;
  for (const auto& r : results) leaked = leaked || r.leaks > 0 || !r.failures.empty();
  if (o.json) {
    nlohmann::json meshes = nlohmann::json::array();
    for (const auto& r : results) {
      nlohmann::json leaks = nlohmann::json::array();
      for (const auto& l : r.reproducers) {
        nlohmann::json cands = nlohmann::json::array();
        for (const auto& c : l.candidates)
          cands.push_back({{"case", io::format_case(c.input)}, {"kernel", io::format_result(c.answer)},
                           {"finder", std::string(to_string(c.finder_contact))}, {"finder_t", c.finder_t}});
        leaks.push_back({{"origin", {l.ray.o.x, l.ray.o.y, l.ray.o.z}}, {"direction", {l.ray.d.x, l.ray.d.y, l.ray.d.z}},
                         {"candidates", cands}});
      }
      meshes.push_back({{"mesh", r.mesh}, {"triangles", r.triangles}, {"rays", r.rays}, {"candidates", r.candidate_cases},
                        {"leaks", r.leaks}, {"rays_without_candidates", r.rays_without_candidates},
                        {"failures", r.failures.size()}, {"reproducers", leaks}});
    }
    nlohmann::json j{{"method", kernel.name}, {"summary", kernel.summary}, {"finder", opt.finder.name}, {"seed", o.seed},
                     {"meshes", meshes}, {"watertight", !leaked}};
    if (is_glsl_kernel(kernel)) j["kernel"] = kernel.summary;
    fmt::print("{}\n", j.dump(1));
  } else {
    fmt::print("rayproof check --mesh: kernel '{}' ({} precision), candidates from {} (conservative BVH traversal)\n",
               kernel.name, kernel.precision == Precision::float32 ? "float" : "double", opt.finder.name);
    fmt::print("kernel '{}': {}\n\n", kernel.name, kernel.summary);
    fmt::print("{}", mesh_table(results));
    const auto lines = leak_lines(results, opt.finder.name);
    if (!lines.empty()) {
      fmt::print("\n# leaks (up to {} per mesh): each ray, then the triangles it slipped between as case lines\n",
                 o.reproducers);
      for (const auto& l : lines) fmt::print("{}\n", l);
    }
    fmt::print("\n");
    for (const auto& l : sentences) fmt::print("{}\n", l);
  }
  return leaked ? 1 : 0;
}


}  // namespace rayproof::cli
