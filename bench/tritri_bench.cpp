// ns per triangle pair of the triangle/triangle tests (docs/tritri.md): the classic kernels in float
// and double, the certified classifier (header-only filters alone, and always decided) and the
// CGAL ground truth, on a few pair families (4096 pairs each, or fewer for CGAL). A plain program:
// best of five passes, single thread. Usage: tritri_bench [pairs]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gen/tritri_families.h"
#include "rayproof/certified/tritri.h"
#include "rayproof/tritri.h"
#include "rayproof/verify/exact.h"

namespace {

using namespace rayproof;

template <class F>
double best_ns_per_pair(std::size_t n, int passes, F&& f) {
  double best = 1e300;
  for (int p = 0; p < passes; ++p) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n));
  }
  return best;
}

Triangle<float> to_float(const Triangle<double>& t) {
  auto f = [](Vec3<double> v) { return Vec3<float>{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; };
  return {f(t.p0), f(t.p1), f(t.p2)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 4096;
  const std::size_t n_exact = std::min<std::size_t>(n, 512);
  std::printf("%-18s %9s %9s %9s %9s %9s %9s %9s %9s\n", "family", "moller_f", "moller_d", "gd_f", "gd_d", "try_cert",
              "undecided", "certified", "exact");
  long sink = 0;
  for (const char* name : {"random", "crossing", "shared_edge", "coplanar_touching", "near_coplanar", "extreme"}) {
    const std::vector<gen::TriPair> pairs = gen::generate_tritri(*gen::find_tritri_family(name), n, 1);
    std::vector<Triangle<float>> fa, fb;
    for (const gen::TriPair& p : pairs) {
      fa.push_back(to_float(p.a));
      fb.push_back(to_float(p.b));
    }
    auto run = [&](auto&& fn) {
      return best_ns_per_pair(n, 5, [&] {
        for (std::size_t i = 0; i < n; ++i) sink += fn(i);
      });
    };
    const double mf = run([&](std::size_t i) { return tritri_moller(fa[i], fb[i]); });
    const double md = run([&](std::size_t i) { return tritri_moller(pairs[i].a, pairs[i].b); });
    const double gf = run([&](std::size_t i) { return tritri_guigue_devillers(fa[i], fb[i]); });
    const double gd = run([&](std::size_t i) { return tritri_guigue_devillers(pairs[i].a, pairs[i].b); });
    std::size_t undecided = 0;
    for (const gen::TriPair& p : pairs) undecided += !certified::try_tritri(p.a, p.b);
    const double tc = run([&](std::size_t i) {
      const auto c = certified::try_tritri(pairs[i].a, pairs[i].b);
      return c ? static_cast<int>(*c) : -1;
    });
    const double ce = run([&](std::size_t i) { return static_cast<int>(certified::tritri(pairs[i].a, pairs[i].b)); });
    const double ex = best_ns_per_pair(n_exact, 2, [&] {
      for (std::size_t i = 0; i < n_exact; ++i) sink += static_cast<int>(exact::tritri(pairs[i].a, pairs[i].b));
    });
    std::printf("%-18s %9.1f %9.1f %9.1f %9.1f %9.1f %9zu %9.1f %9.0f\n", name, mf, md, gf, gd, tc, undecided, ce, ex);
  }
  std::printf("(ns per pair, best of 5 passes over %zu pairs; exact: best of 2 over %zu; undecided: pairs try_tritri "
              "left to GMP; checksum %ld)\n", n, n_exact, sink);
  return 0;
}
