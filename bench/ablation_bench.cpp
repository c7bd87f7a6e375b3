/// One step of the traversal measured in one run: Accel with the greedy collapse and with the
/// SAH-optimal one (BvhBuildOptions::collapse; step `collapse`), or robust's leaf set-up made for
/// every ray against at the first leaf (detail::set_lazy_leaf_setup; step `lazy`, two Accels built
/// alike), beside Embree (default build: the reference of `float`) and Embree-robust (the
/// reference of `robust` and `certified`), on one thread,
/// the four interleaved in blocks of 500 rays, taken through the batch entry on one thread as the
/// reference takes them, in each of the six orders in turn, thread CPU
/// time (so a busy machine's other processes are not counted and all four see the same load).
/// Each round gives each of ours its reference's time over its own (the bench's ratio: above 1
/// is faster than Embree); the table shows the median and range over the rounds, and whether the
/// two variants answered alike (closest: the primitive; any: hit or not). RAYPROOF_SIMD and
/// RAYPROOF_BVH_NODES apply to both Accels.
/// Run: ablation_bench [mesh.off | generated[:N]] [rounds] [rays] [method] [primary | random | miss] [collapse | lazy]
/// (an empty method or ray set: all of them).
/// (default: generated 2^20 triangles, 5 rounds, 40000 rays per set, robust, certified and float).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "registry/registry.h"
#include "scene/accel.h"
#include "scene/compare/competitors.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

volatile std::uint64_t sink_value = 0;

}  // namespace

int main(int argc, char** argv) {
  const std::string mesh = argc > 1 ? argv[1] : "generated";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const int nrays = argc > 3 ? std::max(1, std::atoi(argv[3])) : 40000;
  const std::string only = argc > 4 ? argv[4] : "";
  const std::string only_set = argc > 5 ? argv[5] : "";
  // The step measured: `collapse` (greedy against SAH-optimal: two Accels) or `lazy` (robust's
  // leaf set-up in prepare() against at the first leaf: the switch set per block).
  const std::string step_name = argc > 6 ? argv[6] : "collapse";
  if (step_name != "collapse" && step_name != "lazy")
    return std::fprintf(stderr, "ablation_bench: step '%s': expected collapse or lazy\n", step_name.c_str()), 2;
  const bool collapse_step = step_name == "collapse";
  const char* label[2] = {collapse_step ? "greedy" : "eager", collapse_step ? "sah" : "lazy"};
  Scene s;
  if (mesh.rfind("generated", 0) == 0) add_mesh(s, bumpy_sphere(mesh.size() > 10 ? std::size_t(std::atoll(mesh.c_str() + 10)) : std::size_t(1) << 20));
  else s = load_scene(mesh);
  BvhBuildOptions og{BvhBuilder::sah, 4}, os{BvhBuilder::sah, 4};
  og.collapse = BvhCollapse::greedy, os.collapse = BvhCollapse::sah;
  // The first variant: the greedy tree, or for a switch step a second SAH tree built alike, so that
  // neither setting finds the other's nodes and groups in the caches.
  const Accel first(s, collapse_step ? og : os), sah(s, os);
  const Accel* accel[2] = {&first, &sah};
  auto select = [&](int which) {
    if (!collapse_step) scene::detail::set_lazy_leaf_setup(which == 1);
  };
  if (!compare::have_embree()) return std::fprintf(stderr, "ablation_bench: built without Embree\n"), 1;
  std::vector<compare::Competitor> comps = compare::make_competitors(s, "embree,embree-robust", 1);
  const compare::Competitor& embree = comps.at(0);
  const compare::Competitor& embree_r = comps.at(1);
  std::printf("%s: %zu triangles; %s path, %s nodes; build %s %.1f ms, sah %.1f ms, embree %.1f ms, embree-robust %.1f ms\n",
              mesh.c_str(), s.mesh.triangles.size(), to_string(sah.simd()), to_string(sah.nodes()),
              collapse_step ? "greedy" : "sah (first)", 1e3 * first.build_seconds(),
              1e3 * sah.build_seconds(), 1e3 * embree.build_s, 1e3 * embree_r.build_s);
  // The rays every traversal benchmark uses (bench_common.h).
  const bench::BenchRays bench_rays = bench::make_bench_rays(s.bounds(), nrays);
  const auto& primary = bench_rays.primary;
  const auto& random = bench_rays.random;
  const std::string h0 = std::string(label[0]) + ": ratio [range]", h1 = std::string(label[1]) + ": ratio [range]",
                    h2 = std::string(label[1]) + "/" + label[0] + " speed";
  std::printf("%-10s %-8s %-8s %-13s %22s %22s %22s %s\n", "method", "rays", "query", "reference", h0.c_str(), h1.c_str(),
              h2.c_str(), "answers");
  for (const char* mname : {"robust", "certified", "float"}) {
    if (!only.empty() && only != mname) continue;
    const SceneMethod m = find_scene_method(mname, registry::all_methods());
    const bool is_float = std::string(mname) == "float";
    const compare::Competitor& ref = is_float ? embree : embree_r;
    for (const char* set : {"primary", "random", "miss"}) {
      if (!only_set.empty() && only_set != set) continue;
      const auto& rays = std::string(set) == "primary" ? primary : std::string(set) == "random" ? random : bench_rays.miss;
      // certified's exact stages are slow: a quarter of the rays.
      const std::size_t n = std::string(mname) == "certified" ? std::max<std::size_t>(1, rays.size() / 4) : rays.size();
      for (const char* query : {"closest", "any"}) {
        const bool closest = std::string(query) == "closest";
        constexpr std::size_t kBlock = 500;
        std::vector<double> rg, rs, gain;
        bool same = true;
        std::vector<std::uint8_t> out(kBlock), flags;
        std::vector<PrimHit> hits;
        for (int r = 0; r < rounds; ++r) {
          double t[3] = {0, 0, 0};
          for (std::size_t b0 = 0, blk = 0; b0 < n; b0 += kBlock, ++blk) {
            const std::size_t e = std::min(n, b0 + kBlock);
            std::vector<std::uint64_t> ans[2];
            for (int step = 0; step < 3; ++step) {
              // All six orders in turn, so that each of the three follows each other one equally
              // often (a variant that ran right after a twin would find warm caches).
              static constexpr int kOrders[6][3] = {{0, 1, 2}, {1, 0, 2}, {2, 0, 1}, {2, 1, 0}, {0, 2, 1}, {1, 2, 0}};
              const int which = kOrders[(blk + std::size_t(r)) % 6][step];
              const double t0 = bench::thread_seconds();
              if (which == 2) {
                const std::span<const Ray<double>> span(rays.data() + b0, e - b0);
                if (closest) ref.closest(span, std::span(out.data(), e - b0), 1);
                else ref.any(span, std::span(out.data(), e - b0), 1);
                sink_value = sink_value + out[0];
              } else {
                select(which);
                const Accel& a = *accel[which];
                // A block through the batch entry on one thread, as the reference takes its block
                // (rayproof bench does the same): the per-call dispatch is paid once per block.
                const std::span<const Ray<double>> span(rays.data() + b0, e - b0);
                if (closest) {
                  hits.resize(e - b0);
                  a.closest_batch(span, hits, m, 1);
                  for (const PrimHit& h : hits) ans[which].push_back(h.prim);
                } else {
                  flags.resize(e - b0);
                  a.any_batch(span, flags, m, 1);
                  for (std::uint8_t f : flags) ans[which].push_back(f);
                }
              }
              t[which] += bench::thread_seconds() - t0;
            }
            same = same && ans[0] == ans[1];
          }
          rg.push_back(t[2] / t[0]), rs.push_back(t[2] / t[1]), gain.push_back(t[0] / t[1]);
        }
        auto show = [](std::vector<double> v) {
          std::sort(v.begin(), v.end());
          char buf[64];
          std::snprintf(buf, sizeof buf, "%.3f [%.3f-%.3f]", v[v.size() / 2], v.front(), v.back());
          return std::string(buf);
        };
        std::printf("%-10s %-8s %-8s %-13s %22s %22s %22s %s\n", mname, set, query, ref.name.c_str(), show(rg).c_str(),
                    show(rs).c_str(), show(gain).c_str(), same ? "same" : "DIFFER");
      }
    }
  }
  std::printf("ratio: the reference's time over ours (above 1: faster than it), median [range] over %d rounds; "
              "%s/%s speed: %s's time over %s's\n",
              rounds, label[1], label[0], label[0], label[1]);
  return 0;
}
