// `rayproof bench`'s measurements on one scene (scene_bench.h): the ray sets, every method and
// competitor timed on them, leaks, the packet paths' agreement with single rays, and the builds.
#include "scene/compare/scene_bench.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <random>

#include "rayproof/bvh_packet.h"
#include "scene/compare/competitors.h"
#include "scene/compare/embree_build.h"
#include "scene/compare/isa.h"
#include "scene/scene_caster.h"
#include "scene/watertight.h"

namespace rayproof::scene::compare {
namespace {

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

}  // namespace

void bench_scene(const SceneBenchOptions& opt, const Scene& s, const std::string& mesh_name,
                 const std::vector<std::pair<std::string, SceneMethod>>& methods, int threads, std::vector<BenchRow>& rows,
                 std::vector<BenchBuild>& builds, std::vector<std::string>& notes, BenchIsa& isa) {
  std::vector<int> counts{1};
  if (threads > 1) counts.push_back(threads);
  // Builds run on `threads` threads, as Embree's (its device is created with threads=N).
  tbb::task_arena build_arena(threads);
  std::optional<Accel> accel_a;
  build_arena.execute([&] { accel_a.emplace(s, BvhBuildOptions{BvhBuilder::sah, 4}); });
  const Accel& accel = *accel_a;
  if (isa.nodes.empty()) {
    const OurIsa ours = our_isa(accel);
    isa.nodes = ours.nodes, isa.leaves = ours.leaves, isa.cpu = ours.cpu;
  }
  // Ray sets: primary rays of the default view, random rays inside the bounds, leak rays.
  const Camera cam = s.camera ? *s.camera : default_camera(s, opt.width, opt.height);
  std::map<std::string, std::vector<Ray<double>>> sets;
  for (int j = 0; j < cam.height(); ++j)
    for (int i = 0; i < cam.width(); ++i) sets["primary"].push_back(cam.generate(i, j));
  sets["random"] = random_rays(s.bounds(), opt.rays);
  std::vector<Ray<double>> leak;
  const bool closed = s.size() == s.mesh.triangles.size() && !s.mesh.triangles.empty();
  if (closed) leak = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, opt.leak_rays));
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
        notes.push_back(what + (closest ? " closest: " : " any: ") + std::to_string(differ) + " of " +
                        std::to_string(a.size()) + " primary rays hit or miss otherwise than single rays");
    }
  };
  const std::size_t first_row = rows.size();
  auto set_leaks = [&](const std::string& name, std::int64_t misses, std::size_t n, const std::string& path = "single") {
    for (std::size_t i = first_row; i < rows.size(); ++i)
      if (rows[i].method == name && rows[i].path == path) rows[i].leaks = misses, rows[i].leak_rays = std::int64_t(n);
  };

  // One caster's row: its rays timed (at most `cap` of each set, 0: all), then its leaks.
  auto time_caster = [&](BenchRow& row, const SceneCaster& caster, std::size_t cap) {
    std::vector<CastHit> hits;
    std::vector<std::uint8_t> flags;
    measure(row, cap, true, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
      if (closest) hits.resize(rays.size()), caster.closest(rays, hits, t);
      else flags.resize(rays.size()), caster.any(rays, flags, t);
    });
    if (!closed) return;
    const std::vector<Ray<double>> lr = subset(leak, cap);
    std::vector<CastHit> lh(lr.size());
    caster.closest(lr, lh, threads);
    set_leaks(row.method, std::count_if(lh.begin(), lh.end(), [](const CastHit& h) { return !h.hit(); }), lr.size());
  };

  for (const auto& [name, m] : methods) {
    const std::size_t cap = m.fast == FastKernel::none ? opt.slow_rays : 0;
    // float, robust and certified on a triangle mesh: through the public MeshCaster (its own BVH,
    // built as `accel`, on the same threads); the other methods through the scene BVH.
    std::optional<SceneCaster> caster;
    if (SceneCaster::takes_public_api(s, m)) build_arena.execute([&] { caster.emplace(s, m); });
    else caster.emplace(accel, m);
    BenchRow row;
    row.mesh = mesh_name, row.method = name;
    row.build_s = caster->public_api() ? caster->build_seconds() : accel.build_seconds();
    row.bytes = caster->bytes_read_per_primitive(), row.bytes_held = caster->bytes_per_primitive();
    time_caster(row, *caster, cap);
    if (m.fast == FastKernel::none) continue;  // registry methods: single rays only
    std::vector<std::uint8_t> flags;
    // The packet path: eight rays at a time through the scene BVH (built as MeshCaster's).
    row.build_s = accel.build_seconds();
    std::vector<PrimHit> ph;
    measure_packets(row, "packet8", true, [&](const std::vector<Ray<double>>& rays, bool closest, int t) {
      if (closest) ph.resize(rays.size()), accel.closest_packets(rays, {}, ph, m, t);
      else flags.resize(rays.size()), accel.any_packets(rays, {}, flags, m, t);
    });
    if (closed) {
      ph.resize(leak.size());
      accel.closest_packets(leak, {}, ph, m, threads);
      set_leaks(name, std::count_if(ph.begin(), ph.end(), [](const PrimHit& h) { return h.prim == PrimHit::kNoPrim; }),
                leak.size(), "packet8");
    }
    auto hits_of = [&](bool packets, bool closest, std::vector<std::uint8_t>& out) {
      if (!closest) return packets ? accel.any_packets(tiled, {}, out, m, threads) : accel.any_batch(tiled, out, m, threads);
      std::vector<PrimHit> h(tiled.size());
      if (packets) accel.closest_packets(tiled, {}, h, m, threads);
      else accel.closest_batch(tiled, h, m, threads);
      for (std::size_t i = 0; i < h.size(); ++i) out[i] = h[i].prim != PrimHit::kNoPrim;
    };
    check_same(name + " packet8", [&](bool c, auto& out) { hits_of(false, c, out); }, [&](bool c, auto& out) { hits_of(true, c, out); });
  }
  // Our traversal on our tree and on Embree's (same collapse, leaves and loop; only the binary
  // tree's splits differ), each through the scene BVH.
  if (opt.embree_tree) {
    // Embree's builder at quality medium (its default), high, and high with spatial splits.
    std::vector<std::pair<std::string, std::unique_ptr<Accel>>> trees;
    for (const EmbreeTreeQuality q : {EmbreeTreeQuality::medium, EmbreeTreeQuality::high, EmbreeTreeQuality::high_splits}) {
      std::string why;
      BvhBuildOptions eo{BvhBuilder::sah, 4};
      eo.binary = embree_binary_builder(2 * eo.max_leaf, eo.leaf_group, &why, q,
                                        [&s](std::uint32_t i) { return s.triangle(i); });
      if (!eo.binary) {
        notes.push_back("--embree-tree: " + why);
        break;
      }
      const std::string tree = q == EmbreeTreeQuality::medium ? "embree tree" : std::string("embree ") + to_string(q);
      build_arena.execute([&] { trees.emplace_back(tree, std::make_unique<Accel>(s, eo)); });
    }
    for (const auto& [name, m] : methods) {
      if (m.fast == FastKernel::none || trees.empty()) continue;
      auto time_on = [&](const Accel& a, const std::string& tree) {
        const SceneCaster caster(a, m);
        BenchRow row;
        row.mesh = mesh_name, row.method = name + " @ " + tree;
        row.build_s = a.build_seconds();
        row.bytes = caster.bytes_read_per_primitive(), row.bytes_held = caster.bytes_per_primitive();
        time_caster(row, caster, 0);
      };
      time_on(accel, "our tree");
      for (const auto& [tree, a] : trees) time_on(*a, tree);
    }
  }
  double embree_build[2] = {-1, -1};
  if (!cgal_peers_built())
    for (const char* n : {"cgal-epick", "cgal-epeck"})
      if (named_in(opt.competitors, n)) notes.push_back(std::string(n) + ": " + kCgalPeersNotBuilt);
  for (auto& c : make_competitors(s, opt.competitors, threads)) {
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
        const Accel a(s, BvhBuildOptions{BvhBuilder::sah, 4});
        best = best < 0 ? a.build_seconds() : std::min(best, a.build_seconds());
      });
    }
    builds.push_back({mesh_name, counts[k], best, embree_build[k]});
  }
}

}  // namespace rayproof::scene::compare
