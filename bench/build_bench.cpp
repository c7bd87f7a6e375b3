/// BVH build: the time of scene::Accel's build (bounds, binary SAH build, collapse
/// to wide nodes, leaf-group alignment, groups) beside Embree's (rtcCommitScene with its data set-up,
/// default and robust build, the faster), at one and two threads, interleaved round after round;
/// each variant reports its fastest round. Then the phases of our build at one and two threads
/// (fastest of the rounds), the binary tree's SAH cost and the wide nodes' fullness.
/// Run: build_bench [mesh.off | generated] [rounds] [triangles]  (default: generated, 5 rounds,
/// 2^20 triangles as `rayproof bench`); RAYPROOF_BUILD_BENCH_NO_EMBREE=1 leaves Embree out (ours timed
/// without Embree's devices alive); a fourth argument `profile` times build_bvh alone
/// (sequential, and in TBB arenas of one and two threads).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rayproof/bvh_build.h"
#include "rayproof/bvh_wide.h"
#include "scene/accel.h"
#include "scene/compare/competitors.h"
#include "scene/leaf_simd.h"
#include "scene/scene.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Phases {
  double bounds = 1e30, build = 1e30, collapse = 1e30, align = 1e30;
};

template <int N>
double fullness(const BvhWide<N>& w) {
  std::size_t used = 0;
  for (const auto& n : w.nodes) used += std::size_t(__builtin_popcount(n.valid));
  return w.nodes.empty() ? 0.0 : double(used) / double(w.nodes.size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "generated";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const std::size_t tris = argc > 3 ? std::size_t(std::atoll(argv[3])) : std::size_t(1) << 20;
  Scene s;
  if (path == "generated") add_mesh(s, bumpy_sphere(tris));
  else s = load_scene(path);
  std::printf("%s: %zu primitives, %d rounds (fastest shown)\n", path.c_str(), s.size(), rounds);
  const BvhBuildOptions opt{BvhBuilder::sah, 4};
  if (argc > 4 && std::string(argv[4]) == "profile") {  // build_bvh only, `rounds` times on one thread (for perf record)
    std::vector<BvhBox> boxes(s.size());
    std::vector<Vec3<float>> centers(s.size());
    for (std::uint32_t i = 0; i < s.size(); ++i) triangle_bounds(s.triangle(i), boxes[i], centers[i]);
    double best = 1e30, best_tbb = 1e30, best_two = 1e30;
    tbb::task_arena one(1), two(2);
    for (int r = 0; r < rounds; ++r) {
      double t0 = now();
      const Bvh bin = build_bvh(boxes, centers, opt);
      best = std::min(best, now() - t0);
      if (bin.nodes.empty()) return 1;
      one.execute([&] {
        t0 = now();
        const Bvh b2 = build_bvh(boxes, centers, opt, [](std::size_t n, const auto& f) {
          tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
        });
        best_tbb = std::min(best_tbb, now() - t0);
      });
      two.execute([&] {
        t0 = now();
        const Bvh b2 = build_bvh(boxes, centers, opt, [](std::size_t n, const auto& f) {
          tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
        });
        best_two = std::min(best_two, now() - t0);
      });
    }
    std::printf("build_bvh: %.1f ms sequential, %.1f ms TBB one thread, %.1f ms two threads (%.2fx)\n", 1e3 * best,
                1e3 * best_tbb, 1e3 * best_two, best_tbb / best_two);
    return 0;
  }
  auto for_each = [](std::size_t n, const auto& f) {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
  };

  const int counts[2] = {1, 2};
  double ours[2] = {1e30, 1e30}, embree[2] = {1e30, 1e30};
  Phases ph[2];
  std::vector<compare::Competitor> comps;
  // Devices of two threads: an Embree device of one thread would cap TBB at one thread (its
  // global_control) while it lives, our two-thread builds included.
  if (compare::have_embree() && !std::getenv("RAYPROOF_BUILD_BENCH_NO_EMBREE"))
    comps = compare::make_competitors(s, "embree,embree-robust", 2);
  for (int r = 0; r < rounds; ++r)
    for (int k = 0; k < 2; ++k) {
      tbb::task_arena arena(counts[k]);
      arena.execute([&] {
        const Accel a(s, opt);
        ours[k] = std::min(ours[k], a.build_seconds());
        for (auto& c : comps)
          if (c.build_seconds) embree[k] = std::min(embree[k], c.build_seconds(counts[k]));
        // Phases, as Accel builds the tree of the AVX2 path.
        double t0 = now();
        std::vector<BvhBox> boxes(s.size());
        std::vector<Vec3<float>> centers(s.size());
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(s.size()), 4096), [&](const auto& rg) {
          for (std::uint32_t i = rg.begin(); i < rg.end(); ++i) triangle_bounds(s.triangle(i), boxes[i], centers[i]);
        });
        double t1 = now();
        Bvh bin = build_bvh(boxes, centers, opt, for_each);
        double t2 = now();
        Bvh8 w = collapse_bvh8(std::move(bin), boxes);
        double t3 = now();
        const auto old_of = scene::detail::align_leaf_slots(std::span(w.nodes), scene::detail::kLanes);
        double t4 = now();
        ph[k].bounds = std::min(ph[k].bounds, t1 - t0), ph[k].build = std::min(ph[k].build, t2 - t1);
        ph[k].collapse = std::min(ph[k].collapse, t3 - t2), ph[k].align = std::min(ph[k].align, t4 - t3);
        if (old_of.empty()) std::printf("empty\n");
      });
    }
  const bool have = !comps.empty();
  for (int k = 0; k < 2; ++k)
    std::printf("threads %d: ours %.1f ms, embree %.1f ms, ours/embree %.2f | bounds %.1f  build_bvh %.1f  collapse8 %.1f  "
                "align %.1f ms\n",
                counts[k], 1e3 * ours[k], have ? 1e3 * embree[k] : 0.0, have ? ours[k] / embree[k] : 0.0, 1e3 * ph[k].bounds,
                1e3 * ph[k].build, 1e3 * ph[k].collapse, 1e3 * ph[k].align);
  std::printf("two threads over one: ours %.2fx, embree %.2fx%s\n", ours[0] / ours[1], have ? embree[0] / embree[1] : 0.0,
              have ? "" : " (no Embree: its columns are 0)");
  // Tree quality.
  std::vector<BvhBox> boxes(s.size());
  std::vector<Vec3<float>> centers(s.size());
  for (std::uint32_t i = 0; i < s.size(); ++i) triangle_bounds(s.triangle(i), boxes[i], centers[i]);
  Bvh bin = build_bvh(boxes, centers, opt, for_each);
  const double sah = bvh_sah_cost(bin, opt.leaf_group, opt.group_cost), sah1 = bvh_sah_cost(bin);
  std::size_t leaves = 0, prims = 0;
  for (std::size_t i = 0; i < bin.nodes.size(); ++i)
    if (i != 1 && bin.nodes[i].is_leaf()) ++leaves, prims += bin.nodes[i].count;
  const Bvh8 w8 = collapse_bvh8(Bvh(bin), boxes);
  const Bvh4 w4 = collapse_bvh4(Bvh(bin), boxes);
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over nodes and prim_ids: did the tree change?
  auto mix = [&hash](const void* p, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) hash = (hash ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  mix(bin.nodes.data(), bin.nodes.size() * sizeof(BvhNode)), mix(bin.prim_ids.data(), bin.prim_ids.size() * 4);
  std::printf("tree hash %016llx\n", static_cast<unsigned long long>(hash));
  std::printf("SAH cost %.4f (groups of 4 at cost 2), %.4f (plain); %zu leaves, %.2f per leaf; depth %d\n", sah, sah1,
              leaves, double(prims) / double(std::max<std::size_t>(1, leaves)), bin.max_depth);
  std::printf("8-wide: %zu nodes, %.2f of 8 children; 4-wide: %zu nodes, %.2f of 4\n", w8.nodes.size(), fullness(w8),
              w4.nodes.size(), fullness(w4));
  return 0;
}
