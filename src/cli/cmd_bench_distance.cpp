/// rayproof bench distance [MESH...] [--points N] [--repeat R] [--threads T]: closest point queries
/// side by side, on one thread by default (T > 1: every method on T threads, the points in chunks).
/// MESH `generated`: the 1.31M-triangle bumpy sphere (as bench contains). Methods: rayproof (ExactMesh::closest_points, exact; without and with the side),
/// CGAL AABB_tree closest_point_and_primitive (Epick) and Embree 3 rtcPointQuery with a
/// closest-point callback. Point sets per mesh: uniform in the bounding box grown by 20%, and near
/// the surface (a random point of a random triangle moved along its normal by up to 1e-3 of the
/// box diagonal). Against exact: a method's triangle is wrong when its exact squared distance
/// (rationals) exceeds that of another method's triangle; its distance is off by the ulps between
/// it and the exact distance of the nearest triangle, correctly rounded. Printed: Mpoints/s per
/// method (min-max over the repeats, the methods interleaved), the ratio of rayproof to each from
/// the best runs, wrong triangles, distances off and their largest ulp error, and how often
/// rayproof's exact stage ran.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/scene/distance.h"
#include "scene/compare/distance_bench.h"

namespace rayproof::cli {

namespace {

using scene::compare::DistanceMethod;
using scene::compare::DistanceSetResult;

struct BenchDistanceOptions {
  std::vector<std::string> meshes;
  std::size_t points = 200000;
  int repeat = 3;
  int threads = 1;
  bool ablation = false;
};

void print_set(const std::string& title, const std::vector<DistanceMethod>& ms, const DistanceSetResult& r) {
  const std::size_t n = r.points, k = ms.size();
  const auto& wrong = r.wrong;
  const auto& off = r.off;
  const auto& max_ulps = r.max_ulps;
  const auto& stages = r.stages;
  fmt::print("\n{}: {} points\n", title, n);
  fmt::print("  {:<24} {:>22} {:>13} {:>9} {:>10} {:>9}\n", "method", "Mpoints/s (min-max)", "rayproof/it", "wrong tri", "dist off",
             "max ulps");
  const double rp = *std::max_element(ms[0].rates.begin(), ms[0].rates.end());
  for (std::size_t j = 0; j < k; ++j) {
    const double lo = *std::min_element(ms[j].rates.begin(), ms[j].rates.end());
    const double hi = *std::max_element(ms[j].rates.begin(), ms[j].rates.end());
    fmt::print("  {:<24} {:>10.3f}-{:<11.3f} {:>12.2f}x {:>9} {:>10} {:>9.3g}\n", ms[j].name, lo, hi, rp / hi, wrong[j], off[j],
               max_ulps[j]);
  }
  fmt::print("  rayproof stages: double filter {} ({:.2f}%), rounding in rationals {}, candidates compared in rationals {}, "
             "searched in rationals {}; reference check on {} points: {} differ from the exact distance; sides that differ from "
             "contains(p): {}\n",
             stages[0], 100.0 * double(stages[0]) / double(std::max<std::size_t>(n, 1)), stages[1], stages[2], stages[3], r.sample,
             r.sample_bad, r.side_differ);
}

int run_bench_distance(BenchDistanceOptions opt) {
  const char* me = "rayproof bench distance";
  if (opt.meshes.empty()) {
    const std::string dir = RAYPROOF_BENCH_MESH_DIR;
    for (const char* nm : {"bunny00.off", "armadillo.off", "refined_elephant.off"})
      if (std::filesystem::exists(dir + "/" + nm)) opt.meshes.push_back(dir + "/" + nm);
    if (opt.meshes.empty()) {
      fmt::print(stderr, "{}: no MESH named and none of bunny00, armadillo, refined_elephant in {}\n", me, dir);
      return 2;
    }
  }
  if (opt.points == 0 || opt.points > 100000000 || opt.repeat < 1 || opt.repeat > 100 || opt.threads < 1 || opt.threads > 1024) {
    fmt::print(stderr, "{}: --points must be in [1, 1e8], --repeat in [1, 100] and --threads in [1, 1024]\n", me);
    return 2;
  }
  fmt::print("rayproof bench distance: {}, {} points per set, {} timed runs per method (interleaved)\n",
             opt.threads == 1 ? std::string("one thread") : fmt::format("{} threads for every method", opt.threads), opt.points,
             opt.repeat);
  for (const auto& path : opt.meshes) {
    mesh::Mesh m;
    std::unique_ptr<ExactMesh> cm;
    try {
      m = scene::compare::distance_bench_mesh(path);
    } catch (const mesh::MeshError& e) {  // its message names the file
      fmt::print(stderr, "{}: {}\n", me, e.what());
      return 2;
    }
    try {
      if (m.triangles.empty()) throw std::invalid_argument("the mesh has no triangles");
      cm = std::make_unique<ExactMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                        IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: {}: {}\n", me, path, e.what());
      return 2;
    }
    std::vector<std::string> notes;
    scene::compare::DistanceBuilds builds;
    std::vector<DistanceMethod> ms = scene::compare::timed_distance_methods(m, *cm, notes, opt.ablation, builds);
    for (const auto& note : notes) fmt::print("  {}\n", note);
    fmt::print("\n{}: {} triangles; rayproof distance tree built in {:.3f} s; competitors built in {:.3f} s\n", path,
               m.triangles.size(), builds.tree_s, builds.methods_s);
    std::mt19937_64 rng(2024);
    const scene::compare::DistancePointSets sets = scene::compare::distance_point_sets(m, opt.points, rng);
    print_set("uniform in the box grown by 20%", ms, scene::compare::time_distance_set(m, *cm, ms, sets.uniform, opt.repeat, opt.threads));
    print_set("near the surface (within 1e-3 of the diagonal)", ms,
              scene::compare::time_distance_set(m, *cm, ms, sets.near, opt.repeat, opt.threads));
  }
  return 0;
}

}  // namespace

Run add_bench_distance(CLI::App& bench) {
  auto opt = std::make_shared<BenchDistanceOptions>();
  auto* sub = bench.add_subcommand("distance", "Closest point and distance beside CGAL AABB_tree (Epick) and Embree "
                                               "rtcPointQuery, one thread, against exact");
  sub->add_option("meshes", opt->meshes,
                  "Meshes, or 'generated' (the 1.31M-triangle bumpy sphere) (default: bunny00, armadillo, refined_elephant "
                  "where extracted)");
  sub->add_option("--points", opt->points, "Points per set (uniform, near the surface)")->capture_default_str();
  sub->add_option("--repeat", opt->repeat, "Timed runs per method")->capture_default_str();
  sub->add_flag("--ablation", opt->ablation,
               "Also rayproof with one part off per row (wide tree, Morton order, previous hint, lower bound): "
               "rayproof/it is that part's speed-up");
  sub->add_option("--threads", opt->threads, "Threads for every method (the points split into chunks)")->capture_default_str();
  return [opt] { return run_bench_distance(*opt); };
}

}  // namespace rayproof::cli
