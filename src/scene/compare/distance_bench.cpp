// The measuring half of `rayproof bench distance` (distance_bench.h).
#include "scene/compare/distance_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "scene/compare/distance_compare.h"
#include "scene/distance_tree.h"
#include "scene/watertight.h"

namespace rayproof::scene::compare {

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double ulps(double x, double ref) {
  if (x == ref) return 0;
  if (!std::isfinite(x) || !std::isfinite(ref)) return std::numeric_limits<double>::infinity();
  const double u = std::nextafter(ref, std::numeric_limits<double>::infinity()) - ref;
  return std::abs(x - ref) / u;
}

}  // namespace

std::vector<DistanceMethod> distance_methods(const mesh::Mesh& m, const ExactMesh& cm, std::vector<std::string>& notes,
                                             bool ablation) {
  std::vector<DistanceMethod> ms;
  const ExactMesh* c = &cm;
  // rayproof's batch call, one thread or `threads` (its own split of the batch, in Morton order).
  auto batch = [c](bool side) {
    return [c, side](std::span<const Vec3<double>> p, std::span<std::uint32_t> t, std::span<double> d, int threads) {
      thread_local std::vector<ClosestPoint> r;
      r.resize(p.size());
      c->closest_points(p, r, side, threads);
      for (std::size_t i = 0; i < p.size(); ++i) t[i] = r[i].triangle, d[i] = r[i].distance;
    };
  };
  for (const bool side : {false, true}) {
    auto b = batch(side);
    ms.push_back({side ? "rayproof+side" : "rayproof",
                  [b](std::span<const Vec3<double>> p, std::span<std::uint32_t> t, std::span<double> d) { b(p, t, d, 1); },
                  b});
  }
  if (ablation) {
    using namespace rayproof::scene::detail;
    const std::pair<const char*, unsigned> parts[] = {{"-wide tree", kAblateWide},
                                                      {"-morton order", kAblateOrder},
                                                      {"-previous hint", kAblateHint},
                                                      {"-lower bound", kAblateLower},
                                                      {"-leaf lanes", kAblateLanes}};
    for (const auto& [name, flag] : parts) {
      ms.push_back({std::string("rayproof") + name, [c, flag](std::span<const Vec3<double>> p, std::span<std::uint32_t> t,
                                                             std::span<double> d) {
                      thread_local std::vector<ClosestPoint> r;
                      r.resize(p.size());
                      set_distance_ablation(flag);
                      c->closest_points(p, r, false, 1);
                      set_distance_ablation(kAblateNone);
                      for (std::size_t i = 0; i < p.size(); ++i) t[i] = r[i].triangle, d[i] = r[i].distance;
                    }});
    }
  }
  for (auto& comp : make_distance_competitors(m.vertices, m.triangles)) {
    if (comp.run) ms.push_back({comp.name, comp.run});
    else notes.push_back(comp.name + ": " + comp.note);
  }
  return ms;
}

mesh::Mesh distance_bench_mesh(const std::string& path) {
  return path == "generated" ? bumpy_sphere(std::size_t(1) << 20) : mesh::read_mesh(path);
}

DistancePointSets distance_point_sets(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng) {
  const mesh::VertexBounds b = mesh::vertex_bounds(m, true);
  const Vec3<double> lo = b.lo, ext = b.extent();
  const double diag = length(ext);
  std::uniform_real_distribution<double> u01(0, 1), off(-1e-3, 1e-3);
  DistancePointSets s;
  s.uniform.resize(n), s.near.resize(n);
  auto& uni = s.uniform;
  auto& near = s.near;
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
  return s;
}

std::vector<DistanceMethod> timed_distance_methods(const mesh::Mesh& m, const ExactMesh& cm,
                                                   std::vector<std::string>& notes, bool ablation,
                                                   DistanceBuilds& builds) {
  const double t0 = now();
  if (!m.triangles.empty()) (void)cm.distance(m.vertices[m.triangles[0][0]]);  // builds the distance tree
  const double t1 = now();
  std::vector<DistanceMethod> ms = distance_methods(m, cm, notes, ablation);
  builds.tree_s = t1 - t0, builds.methods_s = now() - t1;
  return ms;
}

DistanceSetResult time_distance_set(const mesh::Mesh& m, const ExactMesh& cm, std::vector<DistanceMethod>& ms,
                                    const std::vector<Vec3<double>>& pts, int repeat, int threads) {
  for (auto& mt : ms) mt.rates.clear(), mt.tri.assign(pts.size(), 0), mt.dist.assign(pts.size(), 0);
  tbb::task_arena arena(std::max(threads, 1));
  auto run = [&](DistanceMethod& mt) {
    if (threads <= 1) return mt.run(pts, mt.tri, mt.dist);
    const std::span<const Vec3<double>> all(pts);
    if (mt.run_threads) return arena.execute([&] { mt.run_threads(all, mt.tri, mt.dist, threads); });
    const std::size_t chunk = std::max<std::size_t>(1024, pts.size() / (std::size_t(threads) * 8));
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pts.size(), chunk), [&](const tbb::blocked_range<std::size_t>& r) {
        const std::size_t b = r.begin(), n = r.size();
        mt.run(all.subspan(b, n), std::span(mt.tri).subspan(b, n), std::span(mt.dist).subspan(b, n));
      });
    });
  };
  for (int r = 0; r < repeat; ++r)
    for (auto& mt : ms) {
      const double t0 = now();
      run(mt);
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
  DistanceSetResult res;
  res.points = n;
  auto& wrong = res.wrong;
  auto& off = res.off;
  auto& max_ulps = res.max_ulps;
  wrong.assign(k, 0), off.assign(k, 0), max_ulps.assign(k, 0);
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
  res.sample = std::min<std::size_t>(n, 2000);
  for (std::size_t i = 0; i < res.sample; ++i) res.sample_bad += exact_triangle_distance(pts[i], tri(best[i])) != ref[i];
  // How often the exact stage ran; the batch's sides against contains(p), point by point.
  std::vector<ClosestPoint> cps(n);
  cm.closest_points(pts, cps, true, 1);
  for (std::size_t i = 0; i < n; ++i) {
    ++res.stages[std::size_t(cps[i].stage)];
    const Side want = cps[i].distance == 0 ? Side::surface : cm.contains(pts[i]);
    res.side_differ += cps[i].side != want;
  }
  return res;
}

}  // namespace rayproof::scene::compare
