/// rayproof bench [SCENE] [--threads N] [--json]: BVH build time, bytes per triangle, Mrays/s of
/// closest hit for primary and random incoherent rays per method, next to Embree 3 (default and
/// robust) and CGAL's AABB_tree (Epick; Epeck on a subset) on the same rays, the ratio of each to
/// Embree robust, and leaks: rays from inside a closed mesh towards every vertex and edge midpoint
/// that find no hit. Without SCENE: a generated closed mesh of >= 1M triangles.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <map>
#include <random>
#include <thread>

#include "cli/commands.h"
#include "cli/scene_caster.h"
#include "cli/scene_input.h"
#include "scene/compare/competitors.h"
#include "scene/watertight.h"

namespace rayproof::cli {

namespace {
struct BenchOptions {
  std::string scene;
  int threads = 0;
  bool json = false;
  std::size_t triangles = 1 << 20, rays = 200000, slow_rays = 5000, leak_rays = 200000;
  std::string methods = "float,double,cramer-float,cramer-double,watertight-float,watertight,robust,certified";
  std::string competitors = "embree,embree-robust,cgal-epick,cgal-epeck";
  int repeat = 3;
};

struct Row {
  std::string method, rays;
  double mrays = 0, build_s = 0, bytes = -1;
  std::size_t n = 0;
  std::int64_t leaks = -1, leak_rays = 0;
};

/// At most `cap` rays (0: all), evenly strided so that a subset samples the whole image or set.
std::vector<Ray<double>> subset(const std::vector<Ray<double>>& rays, std::size_t cap) {
  if (!cap || rays.size() <= cap) return rays;
  std::vector<Ray<double>> out;
  const std::size_t stride = (rays.size() + cap - 1) / cap;
  for (std::size_t i = 0; i < rays.size(); i += stride) out.push_back(rays[i]);
  return out;
}

template <class F>
double seconds(F&& f) {
  const auto a = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

/// The least of `n` timings of f (the machine may be shared: the least is the least disturbed).
template <class F>
double best_seconds(int n, F&& f) {
  double best = seconds(f);
  for (int i = 1; i < n; ++i) best = std::min(best, seconds(f));
  return best;
}

std::vector<Ray<double>> random_rays(const BvhBox& b, std::size_t n) {
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::vector<Ray<double>> out(n);
  for (auto& r : out) {
    for (int k = 0; k < 3; ++k) r.o[k] = b.lo[k] + (double(b.hi[k]) - b.lo[k]) * u(rng);
    do r.d = {g(rng), g(rng), g(rng)};
    while (is_zero(r.d));
  }
  return out;
}

int run_bench(const BenchOptions& opt) {
  std::unique_ptr<scene::Scene> sc;
  try {
    if (opt.scene.empty()) {
      sc = std::make_unique<scene::Scene>();
      scene::add_mesh(*sc, scene::bumpy_sphere(opt.triangles));
    } else {
      sc = std::make_unique<scene::Scene>(opt.scene == "default" ? scene::default_scene() : scene::load_scene(opt.scene));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof bench: {}\n", e.what());
    return 2;
  }
  const scene::Scene& s = *sc;
  const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
  if (!opt.json) fmt::print(stderr, "scene: {} triangles, {} primitives, {} threads\n", s.mesh.triangles.size(), s.size(), threads);
  // Builds run on `threads` threads, as Embree's (its device is created with threads=N).
  tbb::task_arena build_arena(threads);
  std::optional<scene::Accel> median_a, accel_a;
  build_arena.execute([&] {
    median_a.emplace(s, BvhBuildOptions{BvhBuilder::median, 4});
    accel_a.emplace(s, BvhBuildOptions{BvhBuilder::sah, 4});
  });
  const scene::Accel& median = *median_a;
  const scene::Accel& accel = *accel_a;
  // Ray sets: primary rays of the default view, random rays inside the bounds, leak rays.
  const scene::Camera cam = s.camera ? *s.camera : scene::default_camera(s, 640, 480);
  std::map<std::string, std::vector<Ray<double>>> sets;
  for (int j = 0; j < cam.height(); ++j)
    for (int i = 0; i < cam.width(); ++i) sets["primary"].push_back(cam.generate(i, j));
  sets["random"] = random_rays(s.bounds(), opt.rays);
  std::vector<Ray<double>> leak;
  const bool closed = s.size() == s.mesh.triangles.size() && !s.mesh.triangles.empty();
  if (closed) leak = scene::leak_rays(scene::volume_centroid(s.mesh), scene::leak_targets(s.mesh, opt.leak_rays));

  std::vector<Row> rows;
  const double bytes = accel.bytes_per_primitive();
  std::string list = opt.methods;
  for (std::size_t p = 0; p <= list.size();) {
    const std::size_t q = std::min(list.find(',', p), list.size());
    const std::string name = list.substr(p, q - p);
    p = q + 1;
    if (name.empty()) continue;
    scene::SceneMethod m;
    try {
      m = scene::find_scene_method(name, all_methods());
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof bench: {}\n", e.what());
      return 2;
    }
    const std::size_t cap = m.fast == scene::FastKernel::none ? opt.slow_rays : 0;
    // float, robust and certified on a triangle mesh: through the public MeshCaster (its own BVH,
    // built as `accel`, on the same threads); the other methods through the scene BVH.
    std::optional<SceneCaster> caster;
    if (SceneCaster::takes_public_api(s, m)) build_arena.execute([&] { caster.emplace(s, m); });
    else caster.emplace(accel, m);
    const double build_s = caster->public_api() ? caster->build_seconds() : accel.build_seconds();
    for (const auto& [set, all_rays] : sets) {
      const std::vector<Ray<double>> rays = subset(all_rays, cap);
      std::vector<CastHit> hits(rays.size());
      const double t = best_seconds(cap ? 1 : opt.repeat, [&] { caster->closest(rays, hits, threads); });
      rows.push_back({name, set, rays.size() / t / 1e6, build_s, caster->bytes_per_primitive(), rays.size()});
    }
    if (closed) {
      const std::vector<Ray<double>> lr = subset(leak, cap);
      std::vector<CastHit> hits(lr.size());
      caster->closest(lr, hits, threads);
      const auto misses = std::count_if(hits.begin(), hits.end(), [](const CastHit& h) { return !h.hit(); });
      for (auto& r : rows)
        if (r.method == name) r.leaks = std::int64_t(misses), r.leak_rays = std::int64_t(lr.size());
    }
  }
  for (auto& c : scene::compare::make_competitors(s, opt.competitors, threads)) {
    for (const auto& [set, all_rays] : sets) {
      const std::vector<Ray<double>> rays = subset(all_rays, c.max_rays);
      std::vector<std::uint8_t> out(rays.size());
      const double t = best_seconds(c.max_rays ? 1 : opt.repeat, [&] { c.closest(rays, out, threads); });
      rows.push_back({c.name, set, rays.size() / t / 1e6, c.build_s, c.bytes_per_tri, rays.size()});
    }
    if (closed) {
      const std::vector<Ray<double>> lr = subset(leak, c.max_rays);
      std::vector<std::uint8_t> out(lr.size());
      c.closest(lr, out, threads);
      std::int64_t misses = 0;
      for (auto x : out) misses += !x;
      for (auto& r : rows)
        if (r.method == c.name) r.leaks = misses, r.leak_rays = std::int64_t(lr.size());
    }
  }
  std::map<std::string, double> embree_robust;
  for (const auto& r : rows)
    if (r.method == "embree-robust") embree_robust[r.rays] = r.mrays;
  if (opt.json) {
    fmt::print("[\n");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      const auto er = embree_robust.find(r.rays);
      fmt::print("  {{\"method\": \"{}\", \"rays\": \"{}\", \"ray_count\": {}, \"threads\": {}, \"mrays_per_s\": {:.4f}, "
                 "\"build_s\": {:.4f}, \"bytes_per_tri\": {}, \"ratio_to_embree_robust\": {}, \"leaks\": {}, \"leak_rays\": {}}}{}\n",
                 r.method, r.rays, r.n, threads, r.mrays, r.build_s, r.bytes < 0 ? "null" : fmt::format("{:.1f}", r.bytes),
                 er == embree_robust.end() ? "null" : fmt::format("{:.3f}", r.mrays / er->second),
                 r.leaks < 0 ? "null" : std::to_string(r.leaks), r.leak_rays, i + 1 < rows.size() ? "," : "");
    }
    fmt::print("]\n");
    return 0;
  }
  fmt::print("BVH build ({} threads, Embree's too): sah {:.3f} s, median {:.3f} s; {:.1f} bytes/triangle (BVH {:.1f} + triangles {:.1f})\n",
             threads, accel.build_seconds(), median.build_seconds(), bytes, double(accel.bvh_bytes()) / std::max<std::size_t>(1, s.size()),
             double(s.triangle_bytes()) / std::max<std::size_t>(1, s.size()));
  fmt::print("BVH traversal: {} (RAYPROOF_SIMD=sse|avx2|auto)\n", rayproof::to_string(accel.simd()));
  fmt::print("{:<18} {:<8} {:>8} {:>10} {:>9} {:>10} {:>14}\n", "method", "rays", "count", "Mrays/s", "build s", "x embree-r", "leaks");
  for (const auto& r : rows) {
    const auto er = embree_robust.find(r.rays);
    fmt::print("{:<18} {:<8} {:>8} {:>10.3f} {:>9.3f} {:>10} {:>14}\n", r.method, r.rays, r.n, r.mrays, r.build_s,
               er == embree_robust.end() ? "-" : fmt::format("{:.3f}", r.mrays / er->second),
               r.leaks < 0 ? "-" : fmt::format("{}/{}", r.leaks, r.leak_rays));
  }
  return 0;
}
}  // namespace

Run add_bench(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  auto* sub = app.add_subcommand("bench", "Throughput and leaks of every method next to Embree and CGAL");
  sub->add_option("scene", opt->scene, "Mesh file, scene JSON or 'default' (none: a generated closed mesh)");
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)");
  sub->add_flag("--json", opt->json, "Print a JSON array of results");
  sub->add_option("--triangles", opt->triangles, "Triangles of the generated mesh (at least)")->capture_default_str();
  sub->add_option("--rays", opt->rays, "Random rays")->capture_default_str();
  sub->add_option("--slow-rays", opt->slow_rays, "Rays per set for registry (non-compiled) methods")->capture_default_str();
  sub->add_option("--leak-rays", opt->leak_rays, "At most this many leak rays")->capture_default_str();
  sub->add_option("--repeat", opt->repeat, "Time each ray set this many times, report the fastest")->capture_default_str();
  sub->add_option("--methods", opt->methods, "Comma-separated methods")->capture_default_str();
  sub->add_option("--competitors", opt->competitors, "Comma-separated competitors to run (none: no competitor)")
      ->capture_default_str();
  return [opt] { return run_bench(*opt); };
}

}  // namespace rayproof::cli
