/// SIMD leaves (src/scene/leaf_simd.h): ns per triangle of the group kernels
/// against the per-primitive kernels on the same triangles, and ns per ray of Accel::closest and
/// Accel::any on a mesh with the groups on each path against the slot-by-slot queries
/// (RAYPROOF_SIMD=off). The variants run interleaved, round after round, and each reports its
/// fastest round (thread CPU time), so ratios taken in one run are comparable on a busy machine.
/// Run: leaf_bench [mesh.off] [rounds] [rays] [path] [method]  (default: a generated closed mesh of ~80k
/// triangles, 7 rounds, 100000 rays per set, every path; a path (off, scalar, sse, avx2) runs only
/// the queries on that path, e.g. under valgrind --tool=callgrind for instructions per ray).
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "registry/registry.h"
#include "rayproof/certified_triangle.h"
#include "scene/accel.h"
#include "scene/kernels.h"
#include "scene/leaf_simd.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;
using namespace rayproof::scene::detail;

namespace {

volatile std::uint64_t sink_value = 0;

struct Variant {
  std::string name;
  std::function<std::uint64_t()> run;  ///< returns a checksum (kept alive)
  double per = 1;                      ///< units per run (triangles or rays)
  double best = 1e30;
};

void run_rounds(std::vector<Variant>& vs, int rounds) {
  for (int r = 0; r < rounds; ++r)
    for (auto& v : vs) {
      const double t0 = bench::thread_seconds();
      sink_value = sink_value + v.run();
      v.best = std::min(v.best, bench::thread_seconds() - t0);
    }
}

void print(const char* title, const char* unit, const std::vector<Variant>& vs) {
  std::printf("%s\n", title);
  for (const auto& v : vs)
    std::printf("  %-42s %8.2f ns/%s  %5.2fx of %s\n", v.name.c_str(), 1e9 * v.best / v.per, unit, vs[0].best / v.best,
                vs[0].name.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
  const int nrays = argc > 3 ? std::max(1, std::atoi(argv[3])) : 100000;
  const std::string only = argc > 4 ? argv[4] : "";
  const std::string only_method = argc > 5 ? argv[5] : "";
  const bool avx2 = [] {
    force_leaf_simd(LeafSimd::avx2);
    const bool ok = leaf_simd() == LeafSimd::avx2;
    unforce_leaf_simd();
    return ok;
  }();

  // Kernels on groups of 4 triangles near random rays (about a third hit), 4096 rays x 4 groups.
  if (only.empty()) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1, 1);
    constexpr int kRays = 4096, kGroups = 4;
    std::vector<Ray<double>> rays(kRays);
    std::vector<TriGroup> groups(kRays * kGroups);
    std::vector<Triangle<float>> tris(kRays * kGroups * kLanes);
    for (int r = 0; r < kRays; ++r) {
      rays[r] = {{u(rng), u(rng), -3.0f}, {0.3f * u(rng), 0.3f * u(rng), 1.0f}};
      for (int g = 0; g < kGroups; ++g) {
        TriGroup& G = groups[r * kGroups + g];
        for (int i = 0; i < kLanes; ++i) {
          const float z = 3 * u(rng);
          const float cx = float(rays[r].o.x) + 0.5f * u(rng), cy = float(rays[r].o.y) + 0.5f * u(rng);
          const Triangle<float> t{{cx + 0.3f * u(rng), cy + 0.3f * u(rng), z},
                                  {cx + 0.3f * u(rng), cy + 0.3f * u(rng), z + 0.1f * u(rng)},
                                  {cx + 0.3f * u(rng), cy + 0.3f * u(rng), z + 0.1f * u(rng)}};
          tris[(r * kGroups + g) * kLanes + i] = t;
          const Vec3<float> p[3] = {t.p0, t.p1, t.p2};
          for (int v = 0; v < 3; ++v)
            for (int a = 0; a < 3; ++a) G.p[v][a][i] = p[v][a];
          G.tag[i] = triangle_lane_tag(t, std::uint32_t(i));
        }
      }
    }
    const Scene empty;
    const double n_tri = double(tris.size());
    std::vector<Variant> vs;
    // One kernel per triangle, every triangle of every group: the scalar baseline of each method.
    auto per_triangle = [&](auto kernel) {
      std::uint64_t s = 0;
      Crossing c[2];
      for (int r = 0; r < kRays; ++r) {
        kernel.prepare(rays[r]), kernel.leaf_ready();
        for (int j = 0; j < kGroups * kLanes; ++j) s += kernel.triangle_crossings(tris[r * kGroups * kLanes + j], c);
      }
      return s;
    };
    vs.push_back({"robust scalar (per triangle)",
                  [&] { return per_triangle(CompiledKernel<float, TriAlgo::robust>{empty, nullptr, 0}); }, n_tri});
    if (avx2)
      vs.push_back({"robust group (AVX2, 4 double lanes)", [&] {
                      CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0};
                      std::uint64_t s = 0;
                      RobustLanes out;
                      for (int r = 0; r < kRays; ++r) {
                        k.prepare(rays[r]), k.leaf_ready();
                        for (int g = 0; g < kGroups; ++g) {
                          robust_group_avx2(k.lane_ray, groups[r * kGroups + g], 0xf, out);
                          s += unsigned(__builtin_popcount(out.hit)) + out.special;
                        }
                      }
                      return s;
                    }, n_tri});
    vs.push_back({"robust float screen (SSE) + scalar rest", [&] {
                    CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0};
                    std::uint64_t s = 0;
                    Crossing c[2];
                    for (int r = 0; r < kRays; ++r) {
                      k.prepare(rays[r]), k.leaf_ready(), finish_lane_ray(k.lane_ray);  // the screen's constants
                      for (int g = 0; g < kGroups; ++g) {
                        const unsigned rest = 0xf & ~robust_group_float_misses(k.lane_ray, groups[r * kGroups + g], 0xf);
                        for (unsigned b = rest; b; b &= b - 1)
                          s += k.triangle_crossings(tris[(r * kGroups + g) * kLanes + __builtin_ctz(b)], c);
                      }
                    }
                    return s;
                  }, n_tri});
    if (avx2)
      vs.push_back({"robust float screen + AVX2 double rest", [&] {
                      CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0};
                      std::uint64_t s = 0;
                      RobustLanes out;
                      for (int r = 0; r < kRays; ++r) {
                        k.prepare(rays[r]), k.leaf_ready(), finish_lane_ray(k.lane_ray);
                        for (int g = 0; g < kGroups; ++g) {
                          const TriGroup& G = groups[r * kGroups + g];
                          robust_group_avx2(k.lane_ray, G, 0xf & ~robust_group_float_misses(k.lane_ray, G, 0xf), out);
                          s += unsigned(__builtin_popcount(out.hit)) + out.special;
                        }
                      }
                      return s;
                    }, n_tri});
    std::vector<Triangle<double>> tris_d(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i)
      tris_d[i] = {tris[i].p0.cast<double>(), tris[i].p1.cast<double>(), tris[i].p2.cast<double>()};
    vs.push_back({"certified scalar (certified::triangle)", [&] {
                    std::uint64_t s = 0;
                    for (int r = 0; r < kRays; ++r)
                      for (int j = 0; j < kGroups * kLanes; ++j) {
                        const auto h = certified::triangle(rays[r], tris_d[r * kGroups * kLanes + j]);
                        s += h ? unsigned(h->contact) : 99u;
                      }
                    return s;
                  }, n_tri});
    if (avx2)
      vs.push_back({"certified group (AVX2 stage-1 misses)", [&] {
                      std::uint64_t s = 0;
                      alignas(32) double p[3][3][kLanes];
                      for (int r = 0; r < kRays; ++r)
                        for (int g = 0; g < kGroups; ++g) {
                          const Triangle<double>* t = &tris_d[(r * kGroups + g) * kLanes];
                          for (int i = 0; i < kLanes; ++i) {
                            const Vec3<double> q[3] = {t[i].p0, t[i].p1, t[i].p2};
                            for (int v = 0; v < 3; ++v)
                              for (int a = 0; a < 3; ++a) p[v][a][i] = q[v][a];
                          }
                          const unsigned miss = certified_group_misses_avx2(rays[r], p, 0xf);
                          for (unsigned b = 0xf & ~miss; b; b &= b - 1) {
                            const auto h = certified::triangle(rays[r], t[__builtin_ctz(b)]);
                            s += h ? unsigned(h->contact) : 99u;
                          }
                          s += unsigned(__builtin_popcount(miss));
                        }
                      return s;
                    }, n_tri});
    vs.push_back({"float scalar (screen + kernel)",
                  [&] { return per_triangle(CompiledKernel<float, TriAlgo::moller_trumbore>{empty, nullptr, 0}); }, n_tri});
    vs.push_back({"float group (SSE screen + kernel)", [&] {
                    CompiledKernel<float, TriAlgo::moller_trumbore> k{empty, nullptr, 0};
                    std::uint64_t s = 0;
                    Crossing c[2];
                    for (int r = 0; r < kRays; ++r) {
                      k.prepare(rays[r]), k.leaf_ready();
                      for (int g = 0; g < kGroups; ++g) {
                        const unsigned m = mt_group_survivors(k.ray, groups[r * kGroups + g], 0xf);
                        for (unsigned b = m; b; b &= b - 1)
                          s += k.triangle_crossings(tris[(r * kGroups + g) * kLanes + __builtin_ctz(b)], c);
                      }
                    }
                    return s;
                  }, n_tri});
    run_rounds(vs, rounds);
    print("Triangle kernels (4096 rays x 16 triangles each, about a third hit):", "tri", vs);
  }

  // Whole queries on a mesh.
  Scene s;
  if (argc > 1 && std::string(argv[1]) != "-") {
    s = load_scene(argv[1]);
  } else {
    add_mesh(s, bumpy_sphere(80000));
  }
  const Accel a(s);
  std::printf("\nMesh: %zu triangles; bytes/triangle %.1f (all the Accel holds, with the vertex array), %.1f (nodes + "
              "groups: what float and robust read)\n",
              s.mesh.triangles.size(), a.bytes_per_primitive(), a.group_bytes_per_primitive());
  const bench::BenchRays bench_rays = bench::make_bench_rays(s.bounds(), nrays);
  const auto& primary = bench_rays.primary;
  const auto& random = bench_rays.random;
  for (const char* mname : {"robust", "certified", "float"}) {
    if (!only_method.empty() && only_method != mname) continue;
    const SceneMethod m = find_scene_method(mname, registry::all_methods());
    for (const char* set : {"primary", "random"}) {
      const auto& rays = std::string(set) == "primary" ? primary : random;
      for (const char* query : {"closest", "any"}) {
        const bool closest = std::string(query) == "closest";
        std::vector<Variant> vs;
        for (LeafSimd p : {LeafSimd::off, LeafSimd::scalar, LeafSimd::sse, LeafSimd::avx2}) {
          if ((p == LeafSimd::avx2 && !avx2) || (!only.empty() && only != to_string(p))) continue;
          // robust on AVX2 and certified on SSE and AVX2: without and with their float screens (the
          // default: without; set_robust_screen_avx2, set_certified_screen).
          const bool robust = std::string(mname) == "robust", certified = std::string(mname) == "certified";
          const bool two = (robust && p == LeafSimd::avx2) || (certified && (p == LeafSimd::avx2 || p == LeafSimd::sse));
          for (int screen = 0; screen < 1 + two; ++screen) {
            const bool on = two ? screen == 1 : (robust ? robust_screen_avx2() : certified_screen());
            const std::string name = std::string(mname) + " " + query + " " + to_string(p) + (two && on ? "+screen" : "");
            vs.push_back({name, [&, p, closest, on, robust] {
                            force_leaf_simd(p);
                            const bool before = robust ? robust_screen_avx2() : certified_screen();
                            robust ? set_robust_screen_avx2(on) : set_certified_screen(on);
                            std::uint64_t n = 0;
                            for (const auto& r : rays) n += closest ? a.closest(r, m).prim != PrimHit::kNoPrim : a.any(r, m);
                            robust ? set_robust_screen_avx2(before) : set_certified_screen(before);
                            unforce_leaf_simd();
                            return n;
                          }, double(rays.size())});
          }
        }
        run_rounds(vs, rounds);
        const std::string title = std::string("Accel ") + query + ", " + set + " rays (" + std::to_string(rays.size()) + "):";
        print(title.c_str(), "ray", vs);
      }
    }
  }
  return 0;
}
