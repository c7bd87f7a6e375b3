/// Compressed (quantized) wide nodes against full ones (BvhWideQNode in
/// rayproof/bvh_wide.h): ns per ray of Accel::closest and Accel::any for robust, certified and
/// float on primary and random rays, with the same tree shape in full nodes and in compressed
/// nodes, on one SIMD path. The two accels run interleaved in blocks of 500 rays (the order
/// alternating block by block), so both see the same load on a busy machine; each round gives one
/// ratio of the summed times (thread CPU time), and the table shows the median ratio over the rounds and its range.
/// Run: node_bench [mesh.off | generated[:N]] [rounds] [rays] [avx2 | sse] [method]
/// (default: generated, a closed mesh of 1.31M triangles as `rayproof bench` makes; 5 rounds;
/// 50000 rays per set; the CPU's path; robust, certified and float).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "registry/registry.h"
#include "scene/accel.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

volatile std::uint64_t sink_value = 0;

}  // namespace

int main(int argc, char** argv) {
  const std::string mesh = argc > 1 ? argv[1] : "generated";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const int nrays = argc > 3 ? std::max(1, std::atoi(argv[3])) : 50000;
  const std::string path = argc > 4 ? argv[4] : "";
  const std::string only_method = argc > 5 ? argv[5] : "";
  const BvhSimd simd = path == "sse" ? BvhSimd::sse4 : path == "avx2" ? BvhSimd::avx2 : BvhSimd::automatic;

  Scene s;
  if (mesh.rfind("generated", 0) == 0) {  // generated[:N]: at least N triangles (default 2^20: 1.31M)
    add_mesh(s, bumpy_sphere(mesh.size() > 10 ? std::size_t(std::atoll(mesh.c_str() + 10)) : std::size_t(1) << 20));
  } else {
    s = load_scene(mesh);
  }
  const BvhBuildOptions opt{BvhBuilder::sah, 4};  // as `rayproof bench`
  const Accel full(s, opt, simd, BvhNodes::full), comp(s, opt, simd, BvhNodes::compressed);
  if (comp.nodes() != BvhNodes::compressed) {
    std::fprintf(stderr, "node_bench: this scene's bounds cannot be quantized (non-finite); nothing to compare\n");
    return 1;
  }
  const std::size_t nodes = full.bvh().nodes.size() + full.bvh8().nodes.size();
  std::printf("%s: %zu triangles, %s path, %zu nodes: %zu bytes each full, %zu compressed\n", mesh.c_str(),
              s.mesh.triangles.size(), to_string(full.simd()), nodes,
              full.simd() == BvhSimd::avx2 ? sizeof(Bvh8Node) : sizeof(Bvh4Node),
              full.simd() == BvhSimd::avx2 ? sizeof(Bvh8QNode) : sizeof(Bvh4QNode));
  // The quantization pass alone (one thread), against the whole build of the full accel (TBB threads).
  double quantize = 1e30;
  for (int r = 0; r < 3; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = full.simd() == BvhSimd::avx2 ? quantize_wide(full.bvh8()).has_value() : quantize_wide(full.bvh()).has_value();
    quantize = std::min(quantize, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    sink_value = sink_value + ok;
  }
  std::printf("quantize_wide: %.1f ms (one thread; the full accel's build: %.1f ms)\n", 1e3 * quantize,
              1e3 * full.build_seconds());

  // The rays every traversal benchmark uses (bench_common.h).
  const bench::BenchRays bench_rays = bench::make_bench_rays(s.bounds(), nrays);
  const auto& primary = bench_rays.primary;
  const auto& random = bench_rays.random;

  std::printf("%-10s %-8s %-8s %12s %12s %21s %10s %10s\n", "method", "rays", "query", "full ns/ray", "comp ns/ray",
              "comp/full [range]", "B/tri full", "B/tri comp");
  for (const char* mname : {"robust", "certified", "float"}) {
    if (!only_method.empty() && only_method != mname) continue;
    const SceneMethod m = find_scene_method(mname, registry::all_methods());
    for (const char* set : {"primary", "random"}) {
      const auto& rays = std::string(set) == "primary" ? primary : random;
      // certified's exact stages are slow: a tenth of the rays.
      const std::size_t n = std::string(mname) == "certified" ? std::max<std::size_t>(1, rays.size() / 10) : rays.size();
      for (const char* query : {"closest", "any"}) {
        const bool closest = std::string(query) == "closest";
        constexpr std::size_t kBlock = 500;
        std::vector<double> ratio, sec[2];
        std::uint64_t check[2] = {0, 0};
        for (int r = 0; r < rounds; ++r) {
          double total[2] = {0, 0};
          check[0] = check[1] = 0;
          for (std::size_t b0 = 0, blk = 0; b0 < n; b0 += kBlock, ++blk)
            for (int step = 0; step < 2; ++step) {
              const int which = (step + int(blk + r)) % 2;  // alternate which goes first
              const Accel& a = which ? comp : full;
              std::uint64_t hits = 0;
              const double t0 = bench::thread_seconds();
              for (std::size_t i = b0; i < std::min(n, b0 + kBlock); ++i)
                hits += closest ? a.closest(rays[i], m).prim : a.any(rays[i], m);
              total[which] += bench::thread_seconds() - t0;
              check[which] += hits;
            }
          ratio.push_back(total[1] / total[0]);
          sec[0].push_back(total[0]), sec[1].push_back(total[1]);
        }
        sink_value = sink_value + check[0] + check[1];
        auto median = [](std::vector<double> v) {
          std::sort(v.begin(), v.end());
          return v[v.size() / 2];
        };
        std::printf("%-10s %-8s %-8s %12.1f %12.1f %7.3f [%.3f-%.3f] %10.1f %10.1f%s\n", mname, set, query,
                    1e9 * median(sec[0]) / double(n), 1e9 * median(sec[1]) / double(n), median(ratio),
                    *std::min_element(ratio.begin(), ratio.end()), *std::max_element(ratio.begin(), ratio.end()),
                    full.bytes_read_per_primitive(m), comp.bytes_read_per_primitive(m),
                    check[0] == check[1] ? "" : "  (answers differ)");
      }
    }
  }
  std::printf("comp/full: time with compressed nodes over time with full nodes (below 1: compressed faster), median "
              "and range over %d rounds; ns/ray: medians; B/tri: bytes read per triangle (Accel::bytes_read_per_primitive)\n",
              rounds);
  return 0;
}
