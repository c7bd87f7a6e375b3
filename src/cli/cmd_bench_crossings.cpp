/// rayproof bench crossings [MESH...] [--rays N] [--repeat R]: every crossing along rays, side by
/// side on one thread: rayproof's ClosedMesh::ray_crossings (each crossing once, exact) and Embree 3's
/// all hits (a filter function records every hit and rejects it so traversal goes on; sorted by
/// t). Both see the mesh with its vertices rounded to float (Embree's precision) and rays whose
/// origin and direction are floats. Ray sets: random (origins in the box, uniform directions) and
/// through vertices (axis-parallel rays through a vertex: the cases where one point of the surface
/// is shared by several triangles). Embree's hits are matched to rayproof's exact contacts by t
/// (within 1e-5 of the mesh's size along the ray): a second hit at one crossing is a duplicate, a
/// hit at a touch (no crossing there) a touch, a hit at no contact unmatched; crossings with no
/// hit are missed. Printed: those counts, Mrays/s of both (thread CPU time, min-max over the
/// repeats, interleaved) and the ratio of the best runs.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/scene/contains.h"
#include "scene/compare/crossings_compare.h"

namespace rayproof::cli {

namespace {

struct BenchCrossingsOptions {
  std::vector<std::string> meshes;
  std::size_t rays = 100000;
  int repeat = 3;
};

double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

float to_float(double x) { return static_cast<float>(x); }

/// Embree's hits of one ray against rayproof's events (crossings and point touches).
struct Tally {
  std::size_t crossings = 0, touches = 0, hits = 0, right = 0, duplicates = 0, at_touches = 0, unmatched = 0,
              missed = 0, rays_exact = 0;
};

void tally_ray(const RayCrossings& r, const std::vector<scene::compare::EmbreeHit>& hits, double tol, Tally& t) {
  struct Event {
    double t;
    bool crossing;
    int seen = 0;
  };
  std::vector<Event> ev;
  for (const Crossing& c : r.crossings) ev.push_back({c.t, true});
  for (const Touch& h : r.touches)
    if (h.contact != Contact::coplanar) ev.push_back({h.t, false});
  std::sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) { return a.t < b.t; });
  t.crossings += r.crossings.size();
  t.touches += ev.size() - r.crossings.size();
  t.hits += hits.size();
  std::size_t right = 0;
  for (const auto& h : hits) {
    Event* best = nullptr;
    for (auto& e : ev)
      if (std::fabs(e.t - double(h.t)) <= tol && (!best || std::fabs(e.t - double(h.t)) < std::fabs(best->t - double(h.t)))) best = &e;
    if (!best) {
      ++t.unmatched;
    } else if (!best->crossing) {
      ++t.at_touches;
    } else if (best->seen++ == 0) {
      ++right;
    } else {
      ++t.duplicates;
    }
  }
  t.right += right;
  t.missed += r.crossings.size() - right;
  t.rays_exact += right == r.crossings.size() && hits.size() == right;
}

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
  fmt::print("rayproof bench crossings: one thread, {} rays per set, {} repeats interleaved (thread CPU time); "
             "rayproof crossings beside Embree 3 all hits\n",
             opt.rays, opt.repeat);
  std::mt19937_64 rng(31);
  for (const auto& path : meshes) {
    mesh::Mesh m;
    try {
      m = mesh::read_mesh(path);
    } catch (const mesh::MeshError& e) {
      fmt::print(stderr, "rayproof bench crossings: {}\n", e.what());
      return 2;
    }
    if (m.triangles.empty()) {
      fmt::print(stderr, "rayproof bench crossings: {}: no triangles\n", path);
      return 2;
    }
    for (auto& p : m.vertices) p = {double(to_float(p.x)), double(to_float(p.y)), double(to_float(p.z))};
    const double b0 = thread_seconds();
    std::unique_ptr<ClosedMesh> cm;
    try {
      cm = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                        IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "rayproof bench crossings: {}: {}\n", path, e.what());
      return 2;
    }
    const double build = thread_seconds() - b0;
    const auto embree = scene::compare::make_embree_all_hits(m.vertices, m.triangles);
    if (!embree.run) fmt::print("embree all hits: {} (rayproof alone)\n", embree.note);
    Vec3<double> lo = m.vertices[m.triangles[0][0]], hi = lo;
    for (const auto& t : m.triangles)
      for (auto k : t) {
        const auto& p = m.vertices[k];
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    const Vec3<double> ext = hi - lo;
    const double size = std::max({ext.x, ext.y, ext.z});
    fmt::print("\n== {} ({} triangles, {}; vertices rounded to float; rayproof's build {:.2f} s)\n",
               std::filesystem::path(path).stem().string(), m.triangles.size(), cm->closed() ? "closed" : "not closed", build);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> g;
    std::vector<Ray<double>> random(opt.rays), vertex(opt.rays);
    for (auto& r : random) {
      r.o = {to_float(lo.x - 0.1 * ext.x + 1.2 * ext.x * u(rng)), to_float(lo.y - 0.1 * ext.y + 1.2 * ext.y * u(rng)),
             to_float(lo.z - 0.1 * ext.z + 1.2 * ext.z * u(rng))};
      r.d = {to_float(g(rng)), to_float(g(rng)), to_float(g(rng))};
      if (r.d.x == 0 && r.d.y == 0 && r.d.z == 0) r.d = {1, 0, 0};
    }
    std::vector<std::uint32_t> used;
    for (const auto& t : m.triangles) used.insert(used.end(), t.begin(), t.end());
    for (auto& r : vertex) {
      const Vec3<double>& v = m.vertices[used[rng() % used.size()]];
      const int k = int(rng() % 3);
      const double sgn = (rng() & 1) ? 1.0 : -1.0;
      r.o = v;
      double* oc = reinterpret_cast<double*>(&r.o);
      oc[k] = to_float(sgn > 0 ? (&lo.x)[k] - 0.25 * size : (&hi.x)[k] + 0.25 * size);
      r.d = {0, 0, 0};
      reinterpret_cast<double*>(&r.d)[k] = sgn;
    }
    for (const auto* set : {&random, &vertex}) {
      const char* title = set == &random ? "random rays" : "rays through vertices";
      std::vector<RayCrossings> ours(set->size());
      std::vector<std::vector<scene::compare::EmbreeHit>> theirs;
      std::vector<double> rate_ours, rate_embree;
      for (int rep = 0; rep < opt.repeat; ++rep) {
        double t0 = thread_seconds();
        cm->ray_crossings(*set, ours, {}, 1);
        rate_ours.push_back(double(set->size()) / (thread_seconds() - t0) * 1e-6);
        if (embree.run) {
          t0 = thread_seconds();
          embree.run(*set, theirs);
          rate_embree.push_back(double(set->size()) / (thread_seconds() - t0) * 1e-6);
        }
      }
      Tally t;
      if (embree.run)
        for (std::size_t i = 0; i < set->size(); ++i) {
          const Ray<double>& r = (*set)[i];
          const double len = std::sqrt(r.d.x * r.d.x + r.d.y * r.d.y + r.d.z * r.d.z);
          tally_ray(ours[i], theirs[i], 1e-5 * size / len, t);
        }
      else
        for (const auto& r : ours) {
          t.crossings += r.crossings.size();
          for (const Touch& h : r.touches) t.touches += h.contact != Contact::coplanar;
        }
      auto range = [](const std::vector<double>& v) {
        return fmt::format("{:.3f}-{:.3f}", *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()));
      };
      fmt::print("\n{}: {} rays; rayproof: {} crossings, {} touches at a point\n", title, set->size(), t.crossings, t.touches);
      fmt::print("  {:<18} {:>20}\n", "method", "Mrays/s (min-max)");
      fmt::print("  {:<18} {:>20}\n", "rayproof crossings", range(rate_ours));
      if (!embree.run) continue;
      fmt::print("  {:<18} {:>20}\n", "embree all hits", range(rate_embree));
      const double best_ours = *std::max_element(rate_ours.begin(), rate_ours.end());
      const double best_embree = *std::max_element(rate_embree.begin(), rate_embree.end());
      fmt::print("  rayproof / embree (best runs): {:.3g}\n", best_ours / best_embree);
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
  auto* sub = bench.add_subcommand("crossings", "Every crossing along rays: rayproof (each once, exact) beside Embree all hits, one thread");
  sub->add_option("meshes", opt->meshes, "Meshes (default: bunny00, elephant-with-holes where extracted)");
  sub->add_option("--rays", opt->rays, "Rays per set")->capture_default_str()->check(CLI::Range(std::size_t(1), std::size_t(100000000)));
  sub->add_option("--repeat", opt->repeat, "Timed runs per method")->capture_default_str()->check(CLI::Range(1, 1000));
  return [opt] { return run_bench_crossings(*opt); };
}

}  // namespace rayproof::cli
