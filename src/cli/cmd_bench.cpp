/// rayproof bench [SCENE] [--threads N] [--json]: per method, Mrays/s of closest and any hit for
/// primary and random incoherent rays on one thread (and the speed-up on N threads), next to
/// Embree 3 (default and robust; rtcIntersect1 and rtcOccluded1) and CGAL's AABB_tree (Epick;
/// Epeck on a subset) on the same rays, and for primary rays the packet paths (ours: eight rays per
/// call, bvh_packet.h; Embree: rtcIntersect8 and, where native, rtcIntersect16, and the occluded
/// calls) on the same rays in 4x2 pixel tiles, the ratio of each to Embree robust, bytes per triangle,
/// leaks (rays from inside a closed mesh towards every vertex and edge midpoint that find no hit),
/// BVH build times at one and N threads beside Embree's, which instruction set each side ran, and
/// the targets with a verdict each (bench_text.h). On request (--competitors) Embree's two scenes
/// also on a device capped at max_isa=avx2, with their rates against the default device's. Without
/// SCENE: bunny00 and refined_elephant (CGAL's demo meshes, where the build extracted them) and a
/// generated closed mesh of >= 1M triangles ('generated': that one alone).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>

#include "cli/bench_text.h"
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "scene/compare/competitors.h"
#include "scene/compare/scene_bench.h"
#include "scene/watertight.h"

namespace rayproof::cli {

namespace {
struct BenchOptions {
  std::string scene;
  int threads = 0;
  bool json = false;
  std::size_t triangles = 1 << 20;
  std::string methods = "float,double,cramer-float,cramer-double,watertight-float,watertight,robust,certified";
  scene::compare::SceneBenchOptions measure;  ///< ray counts, competitors, repeats, image
};

/// The built-in mesh list for `bench` without a scene: bunny00 and refined_elephant from CGAL's
/// demo data (where the build extracted it) and the generated closed mesh.
std::vector<std::string> default_meshes() {
  std::vector<std::string> out;
#ifdef RAYPROOF_BENCH_MESH_DIR
  for (const char* m : {"bunny00.off", "refined_elephant.off"}) {
    const std::string p = std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + m;
    if (std::ifstream(p).good()) out.push_back(p);
    else fmt::print(stderr, "rayproof bench: {} not found, skipped\n", p);
  }
#endif
  out.emplace_back();  // the generated mesh
  return out;
}

/// Loads the scene at `path` (empty: the generated mesh), resolves the methods and measures them
/// with scene::compare::bench_scene. 2 on a bad scene or method name.
int bench_scene(const BenchOptions& opt, const std::string& path, int threads, std::vector<BenchRow>& rows,
                std::vector<BenchBuild>& builds, std::vector<std::string>& notes, BenchIsa& isa) {
  std::unique_ptr<scene::Scene> sc;
  std::string mesh_name;
  std::vector<std::pair<std::string, scene::SceneMethod>> methods;
  try {
    if (path.empty()) {
      sc = std::make_unique<scene::Scene>();
      scene::add_mesh(*sc, scene::bumpy_sphere(opt.triangles));
      mesh_name = fmt::format("generated-{}", sc->mesh.triangles.size());
    } else {
      sc = std::make_unique<scene::Scene>(path == "default" ? scene::default_scene() : scene::load_scene(path));
      mesh_name = std::filesystem::path(path).filename().string();
    }
    const std::string& list = opt.methods;
    for (std::size_t p = 0; p <= list.size();) {
      const std::size_t q = std::min(list.find(',', p), list.size());
      const std::string name = list.substr(p, q - p);
      p = q + 1;
      if (!name.empty()) methods.emplace_back(name, scene::find_scene_method(name, registry::all_methods()));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof bench: {}\n", e.what());
    return 2;
  }
  const scene::Scene& s = *sc;
  if (!opt.json)
    fmt::print(stderr, "{}: {} triangles, {} primitives{}; one thread{}\n", mesh_name, s.mesh.triangles.size(), s.size(),
               reader_note(path), threads > 1 ? fmt::format(" and {} threads", threads) : "");
  scene::compare::bench_scene(opt.measure, s, mesh_name, methods, threads, rows, builds, notes, isa);
  return 0;
}

int run_bench(const BenchOptions& opt) {
  const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
  std::vector<BenchRow> rows;
  std::vector<BenchBuild> builds;
  std::vector<std::string> notes;  // packet widths a competitor does not offer, and why
  BenchIsa isa;
  try {
    scene::compare::check_competitor_names(opt.measure.competitors);  // before any timing
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "rayproof bench: {}\n", e.what());
    return 2;
  }
  // "generated": the generated mesh alone (an empty path below).
  const std::vector<std::string> paths = opt.scene.empty()           ? default_meshes()
                                         : opt.scene == "generated" ? std::vector<std::string>{std::string()}
                                                                    : std::vector<std::string>{opt.scene};
  for (const std::string& path : paths)
    if (const int rc = bench_scene(opt, path, threads, rows, builds, notes, isa)) return rc;
  const std::vector<BenchTarget> targets = bench_targets(rows, builds);
  if (opt.json) {
    for (const auto& n : notes) fmt::print(stderr, "rayproof bench: {}\n", n);
    fmt::print("{}", bench_json(rows, targets, &isa));
    return 0;
  }
  fmt::print("Mrays/s on one thread; speed-up: the same on {} threads over one. Path single: one ray at a time (primary "
             "rays in scanlines); packet8 / packet16: 8 / 16 consecutive primary rays per call, the rays in tiles of 4x2 "
             "pixels (ours: Accel::closest_packets / any_packets; Embree: rtcIntersect8 / rtcOccluded8 and rtcIntersect16 / "
             "rtcOccluded16); x embree-r: against embree-robust on the same path. B/tri read: bytes per "
             "triangle of the structures the method's queries read (nodes, leaf groups or leaf records and vertices); "
             "held: all that its structures hold.\n{}",
             threads, bench_table(rows));
  for (const auto& n : notes) fmt::print("{}\n", n);
  fmt::print("\n{}", isa_lines(isa));
  if (const std::string avx2 = avx2_ratio_lines(rows); !avx2.empty())
    fmt::print("Embree on a device with max_isa=avx2 against its default device: Mrays/s on one thread, as in the table, "
               "and their ratio, per path.\n{}",
               avx2);
  fmt::print("\n");
  fmt::print("BVH build (SAH, bounds included), best of {}; Embree: the faster of its default and robust builds.\n{}\n",
             std::max(1, opt.measure.repeat), build_table(builds));
  fmt::print("Targets: speed against Embree, two-thread scaling, build time, bytes per triangle, leaks "
             "(verdicts decided on the printed values).\n{}",
             targets_table(targets));
  return 0;
}
}  // namespace

Run add_bench(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  auto* sub = app.add_subcommand("bench", "Throughput and leaks of every method next to Embree and CGAL");
  sub->add_option("scene", opt->scene,
                  "Mesh file, scene JSON, 'default' or 'generated' (the generated closed mesh alone; none: bunny00, "
                  "refined_elephant and the generated mesh)");
  sub->add_option("--threads,-j", opt->threads, "Threads for the speed-up and the second build (0: all)")
      ->check(CLI::Range(0, 1024));
  sub->add_flag("--json", opt->json, "Print a JSON array of results");
  sub->add_option("--triangles", opt->triangles, "Triangles of the generated mesh (at least)")->capture_default_str();
  sub->add_option("--rays", opt->measure.rays, "Random rays")->capture_default_str();
  sub->add_option("--slow-rays", opt->measure.slow_rays, "Rays per set for registry (non-compiled) methods")->capture_default_str();
  sub->add_option("--leak-rays", opt->measure.leak_rays, "At most this many leak rays")->capture_default_str();
  sub->add_flag("--embree-tree", opt->measure.embree_tree,
                "Also each compiled method through the scene BVH on our binary tree and on Embree's (rtcBuildBVH at "
                "quality medium, high, and high with spatial splits), all collapsed and traversed by rayproof");
  sub->add_option("--width", opt->measure.width, "Primary rays: image width (scenes without a camera)")
      ->capture_default_str()->check(CLI::Range(1, 1 << 14));
  sub->add_option("--height", opt->measure.height, "Primary rays: image height (scenes without a camera)")
      ->capture_default_str()->check(CLI::Range(1, 1 << 14));
  sub->add_option("--repeat", opt->measure.repeat, "Time each ray set and build this many times, report the fastest")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--methods", opt->methods, "Comma-separated methods")->capture_default_str();
  sub->add_option("--competitors", opt->measure.competitors,
                  "Comma-separated competitors to run, of embree, embree-robust, embree-avx2, embree-robust-avx2 (Embree's "
                  "two on a device with max_isa=avx2), cgal-epick, cgal-epeck (none: no competitor)")
      ->capture_default_str();
  return [opt] { return run_bench(*opt); };
}

}  // namespace rayproof::cli
