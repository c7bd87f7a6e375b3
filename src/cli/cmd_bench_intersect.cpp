/// rayproof bench intersect [MESH...] [--big] [--repeat N] [--epeck-max N] [--open3d-max N]
/// [--python PATH] [--rayproof-only]: exact self-intersections on one thread beside CGAL PMP's
/// self_intersections (Epick; Epeck on meshes up to --epeck-max triangles), Open3D's
/// get_self_intersecting_triangles (a Python child; up to --open3d-max triangles: it tests every
/// pair; it skips pairs sharing a vertex index, so it is compared with rayproof's pairs that share
/// none) and, for each mesh and a moved copy of it, contact pairs beside FCL. Default meshes: CGAL's
/// data meshes that the build extracted and generated ones with known contacts (--big: the
/// 1.31M-triangle sphere too). The measuring is in scene/compare/intersect_bench.cpp; this prints.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/mesh_input.h"
#include "scene/compare/intersect_bench.h"
#include "scene/watertight.h"

namespace rayproof::cli {

namespace {

namespace cmp = scene::compare;

struct BenchIntersectOptions {
  std::vector<std::string> meshes;
  bool big = false;
  cmp::IntersectBenchOptions run;
};

void print_row(const cmp::IntersectRow& row) {
  const std::string size = row.two ? fmt::format("{} x {}", row.triangles, row.triangles2) : std::to_string(row.triangles);
  const double per_s = row.seconds > 0 ? 1.0 / row.seconds : 0;
  fmt::print("\n== {} ({} triangles)\n", row.name, size);
  fmt::print("  {:<16} {:>9} {:>10} {:>9} {:>7} {:>10} {:>13} {:>13}\n", "method", "pairs", "compared", "missing",
             "extra", "time (s)", "/ rayproof", "");
  fmt::print("  {:<16} {:>9} {:>10} {:>9} {:>7} {:>10.4g} {:>13} {:.3g} Mtri/s, {:.3g} pairs/s\n", "rayproof", row.pairs,
             "", "", "", row.seconds, "", double(row.triangles + row.triangles2) * per_s * 1e-6,
             double(row.pairs) * per_s);
  for (const auto& p : row.peers) {
    if (!p.ran) {
      fmt::print("  {:<16} {}\n", p.peer, p.note);
      continue;
    }
    fmt::print("  {:<16} {:>9} {:>10} {:>9} {:>7} {:>10.4g} {:>13} {}\n", p.peer, p.pairs, p.reference, p.missing,
               p.extra, p.seconds, cmp::time_ratio_text(p.seconds, row.seconds),
               p.restricted ? "(pairs sharing no vertex index)" : "");
  }
  for (const auto& p : row.peers) fmt::print("  {}\n", cmp::peer_sentence(row, p));
}

int run_bench_intersect(const BenchIntersectOptions& opt) {
  const char* me = "rayproof bench intersect";
  std::vector<cmp::NamedMesh> meshes;
  for (const auto& path : opt.meshes) {
    std::optional<mesh::Mesh> m = read_mesh_file(me, path);
    if (!m) return 2;
    meshes.push_back({std::filesystem::path(path).filename().string(), std::move(*m)});
  }
  if (opt.meshes.empty()) {
#ifdef RAYPROOF_BENCH_MESH_DIR
    for (const char* n : {"bunny00.off", "armadillo.off", "refined_elephant.off", "elephant-with-holes.off", "boeing.off"}) {
      const std::string path = std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n;
      if (!std::filesystem::exists(path)) continue;
      std::optional<mesh::Mesh> m = read_mesh_file(me, path);
      if (!m) return 2;
      meshes.push_back({n, std::move(*m)});
    }
#endif
    for (auto& g : cmp::generated_intersect_meshes()) meshes.push_back(std::move(g));
  }
  if (opt.big) meshes.push_back({"bumpy sphere 1.31M", scene::bumpy_sphere(std::size_t(1) << 20)});
  fmt::print("rayproof bench intersect: one thread, thread CPU time (Open3D: the child's CPU time of the call), least time of "
             "{} timed run(s); \"compared\": rayproof's pairs in the peer's scope; missing: of those, not reported by the peer; "
             "extra: reported by the peer, not in rayproof's exact set\n",
             opt.run.repeat);
  if (!cmp::intersect_peers_built()) fmt::print("CGAL PMP and FCL: not built in this build (configure with -DRAYPROOF_BUILD_BENCH=ON)\n");
  try {
    fmt::print("\nself-intersections (one mesh)\n");
    for (const auto& m : meshes) print_row(cmp::self_intersect_row(m.name, m.mesh, opt.run));
    fmt::print("\ncontact pairs (two meshes: each mesh and its copy moved by (0.3, 0.1, 0.05) times its box's sides{})\n",
               opt.meshes.empty() ? "; a bumpy sphere and its copy moved one ulp in x" : "");
    for (const auto& m : meshes) {
      if (m.mesh.triangles.size() > 200000) {
        fmt::print("\n== {} + moved copy: skipped (over 200000 triangles)\n", m.name);
        continue;
      }
      print_row(cmp::contact_row(m.name + " + moved copy", m.mesh, cmp::shifted_copy(m.mesh), opt.run));
    }
    if (opt.meshes.empty()) {  // the default set: also contacts that float decisions get wrong
      const mesh::Mesh s = scene::bumpy_sphere(5000);
      print_row(cmp::contact_row("bumpy sphere and its copy moved one ulp", s, cmp::moved_one_ulp(s), opt.run));
    }
  } catch (const MeshInputError& e) {
    fmt::print(stderr, "{}: {}\n", me, e.what());
    return 2;
  }
  return 0;
}

}  // namespace

Run add_bench_intersect(CLI::App& bench) {
  auto opt = std::make_shared<BenchIntersectOptions>();
  auto* sub = bench.add_subcommand(
      "intersect", "Self-intersections and contact pairs: rayproof (exact) beside CGAL PMP, Open3D and FCL, one thread");
  sub->add_option("meshes", opt->meshes,
                  "Meshes (default: CGAL's bunny00, armadillo, refined_elephant, elephant-with-holes, boeing where extracted, and "
                  "generated meshes with known contacts)");
  sub->add_flag("--big", opt->big, "Also the generated 1.31M-triangle bumpy sphere");
  sub->add_option("--repeat", opt->run.repeat, "Timed runs per method (least time kept)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  sub->add_option("--epeck-max", opt->run.epeck_max, "CGAL PMP with Epeck only on meshes up to this many triangles")
      ->capture_default_str();
  sub->add_option("--open3d-max", opt->run.open3d_max,
                  "Open3D (it tests every pair of triangles) only on meshes up to this many triangles")
      ->capture_default_str();
  sub->add_option("--python", opt->run.python, "The Python interpreter with open3d (Debian's python3-open3d)")
      ->capture_default_str();
  sub->add_flag("--rayproof-only", [opt](std::int64_t) { opt->run.peers = false; }, "rayproof alone, no peers");
  return [opt] { return run_bench_intersect(*opt); };
}

}  // namespace rayproof::cli
