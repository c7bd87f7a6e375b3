/// rayproof bench distance [MESH...] [--points N] [--repeat R]: closest point queries side by side
/// on one thread. Methods: rayproof (ClosedMesh::closest_points, exact; without and with the side),
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
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/scene/distance.h"
#include "scene/compare/distance_compare.h"

namespace rayproof::cli {

namespace {

using Pts = std::vector<Vec3<double>>;
using Runner = std::function<void(std::span<const Vec3<double>>, std::span<std::uint32_t>, std::span<double>)>;

struct BenchDistanceOptions {
  std::vector<std::string> meshes;
  std::size_t points = 200000;
  int repeat = 3;
};

struct Method {
  std::string name;
  Runner run;
  std::vector<double> rates;
  std::vector<std::uint32_t> tri;
  std::vector<double> dist;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double ulps(double x, double ref) {
  if (x == ref) return 0;
  if (!std::isfinite(x) || !std::isfinite(ref)) return std::numeric_limits<double>::infinity();
  const double u = std::nextafter(ref, std::numeric_limits<double>::infinity()) - ref;
  return std::abs(x - ref) / u;
}

void bench_set(const std::string& title, const mesh::Mesh& m, const ClosedMesh& cm, std::vector<Method>& ms, const Pts& pts,
               int repeat, const std::vector<std::size_t>& stage_counts_out_unused) {
  (void)stage_counts_out_unused;
  for (auto& mt : ms) mt.rates.clear(), mt.tri.assign(pts.size(), 0), mt.dist.assign(pts.size(), 0);
  for (int r = 0; r < repeat; ++r)
    for (auto& mt : ms) {
      const double t0 = now();
      mt.run(pts, mt.tri, mt.dist);
      mt.rates.push_back(double(pts.size()) / (now() - t0) * 1e-6);
    }
  // The exact reference: per point, the nearest of the methods' triangles (exact comparisons where
  // they differ) and its exact distance, correctly rounded.
  auto tri = [&](std::uint32_t t) {
    return std::array<Vec3<double>, 3>{m.vertices[m.triangles[t][0]], m.vertices[m.triangles[t][1]], m.vertices[m.triangles[t][2]]};
  };
  const std::size_t n = pts.size(), k = ms.size();
  std::vector<std::uint32_t> best(n);
  std::vector<double> ref(n);
  std::vector<std::size_t> wrong(k, 0), off(k, 0);
  std::vector<double> max_ulps(k, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t b = ms[0].tri[i];
    bool differ = false;
    for (std::size_t j = 1; j < k; ++j)
      if (ms[j].tri[i] != b && ms[j].tri[i] < m.triangles.size()) {
        differ = true;
        if (compare_triangle_distances(pts[i], tri(ms[j].tri[i]), tri(b)) < 0) b = ms[j].tri[i];
      }
    best[i] = b;
    ref[i] = differ ? exact_triangle_distance(pts[i], tri(b)) : ms[0].dist[i];
    for (std::size_t j = 0; j < k; ++j) {
      const std::uint32_t t = ms[j].tri[i];
      if (t != b && (t >= m.triangles.size() || compare_triangle_distances(pts[i], tri(t), tri(b)) > 0)) ++wrong[j];
      const double u = ulps(ms[j].dist[i], ref[i]);
      if (u > 0) ++off[j], max_ulps[j] = std::max(max_ulps[j], u);
    }
  }
  // rayproof's own distances were taken as the reference where every method agreed on the
  // triangle: check a sample of them against the exact distance of that triangle.
  std::size_t sample_bad = 0, sample = std::min<std::size_t>(n, 2000);
  for (std::size_t i = 0; i < sample; ++i) sample_bad += exact_triangle_distance(pts[i], tri(best[i])) != ref[i];
  // How often the exact stage ran.
  std::vector<ClosestPoint> res(n);
  cm.closest_points(pts, res, false, 1);
  std::size_t stages[5] = {0, 0, 0, 0, 0};
  for (const auto& r : res) ++stages[int(r.stage)];
  fmt::print("\n{}: {} points\n", title, n);
  fmt::print("  {:<16} {:>22} {:>13} {:>9} {:>10} {:>9}\n", "method", "Mpoints/s (min-max)", "rayproof/it", "wrong tri", "dist off",
             "max ulps");
  const double rp = *std::max_element(ms[0].rates.begin(), ms[0].rates.end());
  for (std::size_t j = 0; j < k; ++j) {
    const double lo = *std::min_element(ms[j].rates.begin(), ms[j].rates.end());
    const double hi = *std::max_element(ms[j].rates.begin(), ms[j].rates.end());
    fmt::print("  {:<16} {:>10.3f}-{:<11.3f} {:>12.2f}x {:>9} {:>10} {:>9.3g}\n", ms[j].name, lo, hi, rp / hi, wrong[j], off[j],
               max_ulps[j]);
  }
  fmt::print("  rayproof stages: double filter {} ({:.2f}%), rounding in rationals {}, candidates compared in rationals {}, "
             "searched in rationals {}; reference check on {} points: {} differ from the exact distance\n",
             stages[0], 100.0 * double(stages[0]) / double(std::max<std::size_t>(n, 1)), stages[1], stages[2], stages[3], sample,
             sample_bad);
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
  if (opt.points == 0 || opt.points > 100000000 || opt.repeat < 1 || opt.repeat > 100) {
    fmt::print(stderr, "{}: --points must be in [1, 1e8] and --repeat in [1, 100]\n", me);
    return 2;
  }
  fmt::print("rayproof bench distance: one thread, {} points per set, {} timed runs per method (interleaved)\n", opt.points,
             opt.repeat);
  for (const auto& path : opt.meshes) {
    mesh::Mesh m;
    try {
      m = mesh::read_mesh(path);
    } catch (const mesh::MeshError& e) {
      fmt::print(stderr, "{}: {}\n", me, e.what());
      return 2;
    }
    if (m.triangles.empty()) {
      fmt::print(stderr, "{}: {}: the mesh has no triangles\n", me, path);
      return 2;
    }
    std::unique_ptr<ClosedMesh> cm;
    try {
      cm = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                        IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "{}: {}: {}\n", me, path, e.what());
      return 2;
    }
    const double t0 = now();
    (void)cm->distance(m.vertices[m.triangles[0][0]]);  // builds the distance tree
    const double build = now() - t0;
    std::vector<Method> ms;
    auto* c = cm.get();
    ms.push_back({"rayproof", [c](std::span<const Vec3<double>> p, std::span<std::uint32_t> t, std::span<double> d) {
                    thread_local std::vector<ClosestPoint> r;
                    r.resize(p.size());
                    c->closest_points(p, r, false, 1);
                    for (std::size_t i = 0; i < p.size(); ++i) t[i] = r[i].triangle, d[i] = r[i].distance;
                  }});
    ms.push_back({"rayproof+side", [c](std::span<const Vec3<double>> p, std::span<std::uint32_t> t, std::span<double> d) {
                    thread_local std::vector<ClosestPoint> r;
                    r.resize(p.size());
                    c->closest_points(p, r, true, 1);
                    for (std::size_t i = 0; i < p.size(); ++i) t[i] = r[i].triangle, d[i] = r[i].distance;
                  }});
    const double t1 = now();
    for (auto& comp : scene::compare::make_distance_competitors(m.vertices, m.triangles)) {
      if (comp.run) ms.push_back({comp.name, comp.run});
      else fmt::print("  {}: {}\n", comp.name, comp.note);
    }
    fmt::print("\n{}: {} triangles; rayproof distance tree built in {:.3f} s; competitors built in {:.3f} s\n", path,
               m.triangles.size(), build, now() - t1);
    Vec3<double> lo = m.vertices[m.triangles[0][0]], hi = lo;
    for (const auto& t : m.triangles)
      for (auto v : t) {
        const auto& p = m.vertices[v];
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    const Vec3<double> ext = hi - lo;
    const double diag = length(ext);
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u01(0, 1), off(-1e-3, 1e-3);
    Pts uni(opt.points), near(opt.points);
    for (auto& p : uni)
      p = {lo.x - 0.1 * ext.x + 1.2 * ext.x * u01(rng), lo.y - 0.1 * ext.y + 1.2 * ext.y * u01(rng),
           lo.z - 0.1 * ext.z + 1.2 * ext.z * u01(rng)};
    for (auto& p : near) {
      const auto& t = m.triangles[rng() % m.triangles.size()];
      double a = u01(rng), b = u01(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec3<double> &A = m.vertices[t[0]], &B = m.vertices[t[1]], &C = m.vertices[t[2]];
      const Vec3<double> nrm = cross(B - A, C - A);
      const double len = length(nrm);
      const Vec3<double> q = A * (1 - a - b) + B * a + C * b;
      p = len > 0 ? q + nrm * (off(rng) * diag / len) : q;
    }
    bench_set("uniform in the box grown by 20%", m, *cm, ms, uni, opt.repeat, {});
    bench_set("near the surface (within 1e-3 of the diagonal)", m, *cm, ms, near, opt.repeat, {});
  }
  return 0;
}

}  // namespace

Run add_bench_distance(CLI::App& bench) {
  auto opt = std::make_shared<BenchDistanceOptions>();
  auto* sub = bench.add_subcommand("distance", "Closest point and distance beside CGAL AABB_tree (Epick) and Embree "
                                               "rtcPointQuery, one thread, against exact");
  sub->add_option("meshes", opt->meshes, "Meshes (default: bunny00, armadillo, refined_elephant where extracted)");
  sub->add_option("--points", opt->points, "Points per set (uniform, near the surface)")->capture_default_str();
  sub->add_option("--repeat", opt->repeat, "Timed runs per method")->capture_default_str();
  return [opt] { return run_bench_distance(*opt); };
}

}  // namespace rayproof::cli
