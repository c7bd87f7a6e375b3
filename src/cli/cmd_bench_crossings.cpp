/// rayproof bench crossings [MESH...] [--rays N] [--repeat R] [--threads T] [--ablation]: every crossing along
/// rays, side by side: rayproof's ExactMesh::ray_crossings (each crossing once, exact) and Embree
/// 3's all hits (a filter function records every hit and rejects it so traversal goes on; sorted by
/// t), both on T threads (1, the default: thread CPU time; more: wall time). MESH is a mesh file or
/// `generated` (the 1.31M-triangle bumpy sphere). Both see the mesh with its vertices rounded to
/// float (Embree's precision). Ray sets: random (origins in the box, normal directions, floats),
/// through vertices (axis-parallel rays exactly through a vertex, floats) and through edges
/// (axis-parallel rays exactly through an edge's midpoint: the origins are doubles, Embree gets
/// them rounded to float): where one point of the surface is shared by several triangles.
/// Embree's hits are matched to rayproof's exact contacts by t (within 1e-5 of the mesh's size
/// along the ray): a second hit at one crossing is a duplicate, a hit at a touch (no crossing
/// there) a touch, a hit at no contact unmatched; crossings with no hit are missed. Printed: those
/// counts, Mrays/s of both (min-max over the repeats, interleaved) and the ratio of the best runs;
/// with --ablation also rayproof with each of its speed-ups switched from its default alone, in the
/// same loop, with the number of rays whose answers differ from the default's.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "scene/compare/crossings_bench.h"

namespace rayproof::cli {

namespace {

struct BenchCrossingsOptions {
  std::vector<std::string> meshes;
  std::size_t rays = 100000;
  int repeat = 3;
  int threads = 1;
  bool ablation = false;
};

using scene::compare::thread_seconds;

int run_bench_crossings(const BenchCrossingsOptions& opt) {
  std::vector<std::string> meshes = opt.meshes;
#ifdef RAYPROOF_BENCH_MESH_DIR
  if (meshes.empty())
    for (const char* n : {"bunny00.off", "elephant-with-holes.off"})
      if (std::filesystem::exists(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n))
        meshes.push_back(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n);
#endif
  if (meshes.empty()) {
    fmt::print(stderr, "rayproof bench crossings: no mesh named and none of the default ones extracted\n");
    return 2;
  }
  const std::string threads = opt.threads == 1 ? "one thread (thread CPU time)"
                              : opt.threads == 0 ? "TBB's default threads (wall time)"
                                                 : fmt::format("{} threads (wall time)", opt.threads);
  fmt::print("rayproof bench crossings: {}, {} rays per set, {} repeats interleaved; rayproof crossings beside "
             "Embree 3 all hits\n",
             threads, opt.rays, opt.repeat);
  std::mt19937_64 rng(31);
  for (const auto& path : meshes) {
    mesh::Mesh m;
    try {
      m = scene::compare::crossings_mesh(path);
    } catch (const mesh::MeshError& e) {
      fmt::print(stderr, "rayproof bench crossings: {}\n", e.what());
      return 2;
    }
    if (m.triangles.empty()) {
      fmt::print(stderr, "rayproof bench crossings: {}: no triangles\n", path);
      return 2;
    }
    for (auto& p : m.vertices) p = {double(float(p.x)), double(float(p.y)), double(float(p.z))};
    const double b0 = thread_seconds();
    std::unique_ptr<ExactMesh> cm;
    try {
      cm = std::make_unique<ExactMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                        IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "rayproof bench crossings: {}: {}\n", path, e.what());
      return 2;
    }
    const double build = thread_seconds() - b0;
    const auto embree = scene::compare::make_embree_all_hits(m.vertices, m.triangles);
    if (!embree.run) fmt::print("embree all hits: {} (rayproof alone)\n", embree.note);
    const scene::compare::CrossingRaySets sets = scene::compare::crossing_ray_sets(m, opt.rays, rng);
    fmt::print("\n== {} ({} triangles, {}; vertices rounded to float; rayproof's build {:.2f} s)\n",
               std::filesystem::path(path).stem().string(), m.triangles.size(), cm->closed() ? "closed" : "not closed", build);
    for (const auto* set : {&sets.random, &sets.vertex, &sets.edge}) {
      const char* title = set == &sets.random ? "random rays" : (set == &sets.vertex ? "rays through vertices" : "rays through edges");
      const scene::compare::CrossingsRun run =
          scene::compare::time_crossings(*cm, embree, *set, sets.size, opt.repeat, opt.threads, opt.ablation);
      const auto& t = run.tally;
      const auto& rate_ours = run.ours;
      const auto& rate_embree = run.embree;
      auto range = [](const std::vector<double>& v) {
        return fmt::format("{:.3g}-{:.3g}", *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()));
      };
      fmt::print("\n{}: {} rays; rayproof: {} crossings, {} touches at a point\n", title, set->size(), t.crossings, t.touches);
      fmt::print("  {:<18} {:>20}\n", "method", "Mrays/s (min-max)");
      fmt::print("  {:<18} {:>20}\n", "rayproof crossings", range(rate_ours));
      if (!embree.run) continue;
      fmt::print("  {:<18} {:>20}\n", "embree all hits", range(rate_embree));
      const double best_ours = *std::max_element(rate_ours.begin(), rate_ours.end());
      const double best_embree = *std::max_element(rate_embree.begin(), rate_embree.end());
      fmt::print("  rayproof / embree (best runs): {:.3g}\n", best_ours / best_embree);
      for (const auto& w : run.variants)
        fmt::print("  rayproof {:<24} {:>12}  / embree (best runs): {:.3g}; answers differ from the default on {} rays\n",
                   w.name, range(w.ours), *std::max_element(w.ours.begin(), w.ours.end()) / best_embree, w.differing_rays);
      fmt::print("  embree's {} hits: {} at a crossing (first), {} duplicates (a crossing reported again), {} at touches, "
                 "{} at no exact contact; {} of rayproof's crossings had no embree hit matched to them; {} of {} rays with exactly "
                 "one embree hit per crossing and no other\n",
                 t.hits, t.right, t.duplicates, t.at_touches, t.unmatched, t.missed, t.rays_exact, set->size());
    }
  }
  return 0;
}

}  // namespace

Run add_bench_crossings(CLI::App& bench) {
  auto opt = std::make_shared<BenchCrossingsOptions>();
  auto* sub = bench.add_subcommand("crossings", "Every crossing along rays: rayproof (each once, exact) beside Embree all hits");
  sub->add_option("meshes", opt->meshes,
                  "Meshes, or 'generated' (the 1.31M-triangle bumpy sphere) (default: bunny00, elephant-with-holes where extracted)");
  sub->add_option("--rays", opt->rays, "Rays per set")->capture_default_str()->check(CLI::Range(std::size_t(1), std::size_t(100000000)));
  sub->add_option("--repeat", opt->repeat, "Timed runs per method")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_flag("--ablation", opt->ablation,
               "Also time rayproof with each speed-up switched alone (without float traversal, without lane misses, with fan "
               "once), interleaved, and compare its answers");
  sub->add_option("--threads", opt->threads, "Threads for both (0: TBB's default; 1: thread CPU time, else wall time)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  return [opt] { return run_bench_crossings(*opt); };
}

}  // namespace rayproof::cli
