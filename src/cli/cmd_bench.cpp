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

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <map>
#include <random>
#include <stdexcept>
#include <thread>

#include "cli/bench_text.h"
#include "rayproof/bvh_packet.h"
#include "cli/commands.h"
#include "scene/scene_caster.h"
#include "cli/scene_input.h"
#include "scene/compare/competitors.h"
#include "scene/compare/isa.h"
#include "scene/watertight.h"

namespace rayproof::cli {

using scene::CastHit;
using scene::SceneCaster;

namespace {
struct BenchOptions {
  std::string scene;
  int threads = 0;
  bool json = false;
  std::size_t triangles = 1 << 20, rays = 200000, slow_rays = 5000, leak_rays = 200000;
  std::string methods = "float,double,cramer-float,cramer-double,watertight-float,watertight,robust,certified";
  std::string competitors = "embree,embree-robust,cgal-epick,cgal-epeck";
  int repeat = 3;
  int width = 640, height = 480;  ///< primary rays: this image of the default view
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

/// Runs every method and competitor on one scene: rows (one thread, and `threads` for the speed-up
/// when above 1) and builds (ours and Embree's at one thread and at `threads`).
int bench_scene(const BenchOptions& opt, const std::string& path, int threads, std::vector<BenchRow>& rows,
                std::vector<BenchBuild>& builds, std::vector<std::string>& notes, BenchIsa& isa) {
  std::unique_ptr<scene::Scene> sc;
  std::string mesh_name;
  try {
    if (path.empty()) {
      sc = std::make_unique<scene::Scene>();
      scene::add_mesh(*sc, scene::bumpy_sphere(opt.triangles));
      mesh_name = fmt::format("generated-{}", sc->mesh.triangles.size());
    } else {
      sc = std::make_unique<scene::Scene>(path == "default" ? scene::default_scene() : scene::load_scene(path));
      mesh_name = std::filesystem::path(path).filename().string();
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof bench: {}\n", e.what());
    return 2;
  }
  const scene::Scene& s = *sc;
  std::vector<int> counts{1};
  if (threads > 1) counts.push_back(threads);
  if (!opt.json)
    fmt::print(stderr, "{}: {} triangles, {} primitives{}; one thread{}\n", mesh_name, s.mesh.triangles.size(), s.size(),
               reader_note(path), threads > 1 ? fmt::format(" and {} threads", threads) : "");
  // Builds run on `threads` threads, as Embree's (its device is created with threads=N).
  tbb::task_arena build_arena(threads);
  std::optional<scene::Accel> accel_a;
  build_arena.execute([&] { accel_a.emplace(s, BvhBuildOptions{BvhBuilder::sah, 4}); });
  const scene::Accel& accel = *accel_a;
  if (isa.nodes.empty()) {
    const scene::compare::OurIsa ours = scene::compare::our_isa(accel);
    isa.nodes = ours.nodes, isa.leaves = ours.leaves, isa.cpu = ours.cpu;
  }
  // Ray sets: primary rays of the default view, random rays inside the bounds, leak rays.
  const scene::Camera cam = s.camera ? *s.camera : scene::default_camera(s, opt.width, opt.height);
  std::map<std::string, std::vector<Ray<double>>> sets;
  for (int j = 0; j < cam.height(); ++j)
    for (int i = 0; i < cam.width(); ++i) sets["primary"].push_back(cam.generate(i, j));
  sets["random"] = random_rays(s.bounds(), opt.rays);
  std::vector<Ray<double>> leak;
  const bool closed = s.size() == s.mesh.triangles.size() && !s.mesh.triangles.empty();
  if (closed) leak = scene::leak_rays(scene::volume_centroid(s.mesh), scene::leak_targets(s.mesh, opt.leak_rays));
  // Packets: the primary rays in tiles of 4x2 pixels, so that each eight
  // consecutive rays (and each sixteen: two tiles side by side) are one coherent packet.
  std::vector<Ray<double>> tiled;
  for (std::uint32_t p : packet_tile_order(cam.width(), cam.height()))
    tiled.push_back(sets["primary"][p]);

  // One measurement: Mrays/s of `run(rays, threads)` at one thread and, for the speed-up, at `threads`.
  auto measure = [&](BenchRow row, std::size_t cap, bool threaded, const auto& run) {
    for (const auto& [set, all_rays] : sets) {
      const std::vector<Ray<double>> rays = subset(all_rays, cap);
      row.rays = set, row.n = rays.size();
      for (const char* query : {"closest", "any"}) {
        row.query = query;
        for (int t : counts) {
          if (t > 1 && !threaded) continue;
          const double sec = best_seconds(cap ? 1 : opt.repeat, [&] { run(rays, query[0] == 'c', t); });
          (t == 1 ? row.mrays : row.mrays_scaled) = rays.size() / std::max(sec, 1e-9) / 1e6;  // never inf
          if (t > 1) row.scaled_threads = t;
        }
        rows.push_back(row);
      }
    }
  };
  // The same on the tiled primary rays alone, for a packet path.
  auto measure_packets = [&](BenchRow row, const std::string& path, bool threaded, const auto& run) {
    row.path = path, row.rays = "primary", row.n = tiled.size();
    for (const char* query : {"closest", "any"}) {
      row.query = query;
      for (int t : counts) {
        if (t > 1 && !threaded) continue;
        const double sec = best_seconds(opt.repeat, [&] { run(tiled, query[0] == 'c', t); });
        (t == 1 ? row.mrays : row.mrays_scaled) = tiled.size() / std::max(sec, 1e-9) / 1e6;
        if (t > 1) row.scaled_threads = t;
      }
      rows.push_back(row);
    }
  };
  // A packet path's hit-or-miss answers on the tiled rays against the same caller's single rays: a
  // note when they differ (they must not: the packet paths answer each ray as a single call would).
  auto check_same = [&](const std::string& what, const auto& single, const auto& packet) {
    for (const bool closest : {true, false}) {
      std::vector<std::uint8_t> a(tiled.size()), b(tiled.size());
      single(closest, a), packet(closest, b);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < a.size(); ++i) differ += (a[i] != 0) != (b[i] != 0);
      if (differ)
        notes.push_back(fmt::format("{} {}: {} of {} primary rays hit or miss otherwise than single rays", what,
                                    closest ? "closest" : "any", differ, a.size()));
    }
  };
  const std::size_t first_row = rows.size();
  auto set_leaks = [&](const std::string& name, std::int64_t misses, std::size_t n, const std::string& path = "single") {
    for (std::size_t i = first_row; i < rows.size(); ++i)
      if (rows[i].method == name && rows[i].path == path) rows[i].leaks = misses, rows[i].leak_rays = std::int64_t(n);
  };

  std::string list = opt.methods;
  for (std::size_t p = 0; p <= list.size();) {
    const std::size_t q = std::min(list.find(',', p), list.size());
    const std::string name = list.substr(p, q - p);
    p = q + 1;
    if (name.empty()) continue;
    scene::SceneMethod m;
    try {
      m = scene::find_scene_method(name, registry::all_methods());
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
    BenchRow row;
    row.mesh = mesh_name, row.method = name;
    row.build_s = caster->public_api() ? caster->build_seconds() : accel.build_seconds();
    row.bytes = caster->bytes_read_per_primitive(), row.bytes_held = caster->bytes_per_primitive();
    std::vector<CastHit> hits;
    std::vector<std::uint8_t> flags;
    measure(row, cap, true, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
      if (closest) hits.resize(rays.size()), caster->closest(rays, hits, t);
      else flags.resize(rays.size()), caster->any(rays, flags, t);
    });
    if (closed) {
      const std::vector<Ray<double>> lr = subset(leak, cap);
      std::vector<CastHit> lh(lr.size());
      caster->closest(lr, lh, threads);
      set_leaks(name, std::count_if(lh.begin(), lh.end(), [](const CastHit& h) { return !h.hit(); }), lr.size());
    }
    if (m.fast == scene::FastKernel::none) continue;  // registry methods: single rays only
    // The packet path: eight rays at a time through the scene BVH (built as MeshCaster's).
    row.build_s = accel.build_seconds();
    std::vector<scene::PrimHit> ph;
    measure_packets(row, "packet8", true, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
      if (closest) ph.resize(rays.size()), accel.closest_packets(rays, {}, ph, m, t);
      else flags.resize(rays.size()), accel.any_packets(rays, {}, flags, m, t);
    });
    if (closed) {
      ph.resize(leak.size());
      accel.closest_packets(leak, {}, ph, m, threads);
      set_leaks(name, std::count_if(ph.begin(), ph.end(), [](const scene::PrimHit& h) { return h.prim == scene::PrimHit::kNoPrim; }),
                leak.size(), "packet8");
    }
    auto hits_of = [&](bool packets, bool closest, std::vector<std::uint8_t>& out) {
      if (!closest) return packets ? accel.any_packets(tiled, {}, out, m, threads) : accel.any_batch(tiled, out, m, threads);
      std::vector<scene::PrimHit> h(tiled.size());
      if (packets) accel.closest_packets(tiled, {}, h, m, threads);
      else accel.closest_batch(tiled, h, m, threads);
      for (std::size_t i = 0; i < h.size(); ++i) out[i] = h[i].prim != scene::PrimHit::kNoPrim;
    };
    check_same(name + " packet8", [&](bool c, auto& out) { hits_of(false, c, out); }, [&](bool c, auto& out) { hits_of(true, c, out); });
  }
  double embree_build[2] = {-1, -1};
  for (auto& c : scene::compare::make_competitors(s, opt.competitors, threads)) {
    if (!c.isa.empty() && std::none_of(isa.competitors.begin(), isa.competitors.end(),
                                       [&](const BenchIsa::Side& x) { return x.name == c.name; }))
      isa.competitors.push_back({c.name, c.isa, c.kernel, c.isa_how});
    BenchRow row;
    row.mesh = mesh_name, row.method = c.name, row.build_s = c.build_s, row.bytes = row.bytes_held = c.bytes_per_tri;
    measure(row, c.max_rays, c.threaded, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
      std::vector<std::uint8_t> out(rays.size());
      if (closest || !c.any) c.closest(rays, out, t);
      else c.any(rays, out, t);
    });
    if (!c.any)  // no any-hit query: those rows timed closest hit; drop them
      std::erase_if(rows, [&](const BenchRow& r) { return r.mesh == mesh_name && r.method == c.name && r.query == "any"; });
    if (closed) {
      const std::vector<Ray<double>> lr = subset(leak, c.max_rays);
      std::vector<std::uint8_t> out(lr.size());
      c.closest(lr, out, threads);
      set_leaks(c.name, std::count(out.begin(), out.end(), std::uint8_t(0)), lr.size());
    }
    for (const auto& p : c.packets) {
      const std::string path = "packet" + std::to_string(p.width);
      measure_packets(row, path, c.threaded, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
        std::vector<std::uint8_t> out(rays.size());
        if (closest) p.closest(rays, out, t);
        else p.any(rays, out, t);
      });
      if (closed) {
        std::vector<std::uint8_t> out(leak.size());
        p.closest(leak, out, threads);
        set_leaks(c.name, std::count(out.begin(), out.end(), std::uint8_t(0)), leak.size(), path);
      }
      if (c.any)
        check_same(c.name + " " + path, [&](bool closest, auto& out) { (closest ? c.closest : c.any)(tiled, out, threads); },
                   [&](bool closest, auto& out) { (closest ? p.closest : p.any)(tiled, out, threads); });
    }
    for (const auto& note : c.packet_notes)
      if (std::find(notes.begin(), notes.end(), c.name + ": " + note) == notes.end()) notes.push_back(c.name + ": " + note);
    // Embree's build beside ours: its default device (the -avx2 ones build with the same builder;
    // timing them too would only lengthen the run).
    if (c.build_seconds && c.name.rfind("embree", 0) == 0 && c.max_isa.empty())
      for (std::size_t k = 0; k < counts.size(); ++k) {
        // The build's own clock (its device is created before it starts), the least of `repeat`,
        // in an arena of that many threads (Embree's TBB tasks run in the caller's arena).
        tbb::task_arena arena(counts[k]);
        double best = -1;
        for (int i = 0; i < std::max(1, opt.repeat); ++i)
          arena.execute([&] {
            const double sec = c.build_seconds(counts[k]);
            best = best < 0 ? sec : std::min(best, sec);
          });
        embree_build[k] = embree_build[k] < 0 ? best : std::min(embree_build[k], best);
      }
  }
  // Our build at one thread and at `threads`, the best of `repeat`, as Embree's.
  for (std::size_t k = 0; k < counts.size(); ++k) {
    tbb::task_arena arena(counts[k]);
    double best = -1;
    for (int i = 0; i < std::max(1, opt.repeat); ++i) {
      arena.execute([&] {
        const scene::Accel a(s, BvhBuildOptions{BvhBuilder::sah, 4});
        best = best < 0 ? a.build_seconds() : std::min(best, a.build_seconds());
      });
    }
    builds.push_back({mesh_name, counts[k], best, embree_build[k]});
  }
  return 0;
}

int run_bench(const BenchOptions& opt) {
  const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
  std::vector<BenchRow> rows;
  std::vector<BenchBuild> builds;
  std::vector<std::string> notes;  // packet widths a competitor does not offer, and why
  BenchIsa isa;
  try {
    scene::compare::check_competitor_names(opt.competitors);  // before any timing
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
             std::max(1, opt.repeat), build_table(builds));
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
  sub->add_option("--rays", opt->rays, "Random rays")->capture_default_str();
  sub->add_option("--slow-rays", opt->slow_rays, "Rays per set for registry (non-compiled) methods")->capture_default_str();
  sub->add_option("--leak-rays", opt->leak_rays, "At most this many leak rays")->capture_default_str();
  sub->add_option("--width", opt->width, "Primary rays: image width (scenes without a camera)")
      ->capture_default_str()->check(CLI::Range(1, 1 << 14));
  sub->add_option("--height", opt->height, "Primary rays: image height (scenes without a camera)")
      ->capture_default_str()->check(CLI::Range(1, 1 << 14));
  sub->add_option("--repeat", opt->repeat, "Time each ray set and build this many times, report the fastest")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--methods", opt->methods, "Comma-separated methods")->capture_default_str();
  sub->add_option("--competitors", opt->competitors,
                  "Comma-separated competitors to run, of embree, embree-robust, embree-avx2, embree-robust-avx2 (Embree's "
                  "two on a device with max_isa=avx2), cgal-epick, cgal-epeck (none: no competitor)")
      ->capture_default_str();
  return [opt] { return run_bench(*opt); };
}

}  // namespace rayproof::cli
