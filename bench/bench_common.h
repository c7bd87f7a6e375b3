#pragma once
// What the traversal benchmarks share: the ray sets (primary rays from an eye outside the
// scene's bounds into them, random rays between two points inside, and rays from the eye away from
// the bounds; the same seed gives the same
// rays in every benchmark, so their numbers compare) and the clock (this thread's CPU time).
#include <time.h>

#include <random>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/ray.h"

namespace rayproof::bench {

/// This thread's CPU time in seconds: time the scheduler gives other processes on a shared machine
/// is not counted.
inline double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct BenchRays {
  std::vector<Ray<double>> primary, random;
  /// Rays from the primary rays' eye pointing away from the bounds: they miss the root box, so
  /// they time a query's fixed cost per ray (set-up, root test, the return).
  std::vector<Ray<double>> miss;
};

inline BenchRays make_bench_rays(const BvhBox& b, int nrays, unsigned seed = 9) {
  std::mt19937 rng(seed);
  auto in_box = [&] {
    Vec3<double> p;
    for (int k = 0; k < 3; ++k) p[k] = std::uniform_real_distribution<double>(b.lo[k], b.hi[k])(rng);
    return p;
  };
  Vec3<double> center, ext;
  for (int k = 0; k < 3; ++k) center[k] = 0.5 * (double(b.lo[k]) + double(b.hi[k])), ext[k] = double(b.hi[k]) - double(b.lo[k]);
  const double radius = length(ext);
  BenchRays r;
  for (int i = 0; i < nrays; ++i) {
    const Vec3<double> eye = center + Vec3<double>{0.2 * radius, 0.3 * radius, 1.5 * radius};
    r.primary.push_back({eye, in_box() - eye});
    const Vec3<double> o = in_box();
    r.random.push_back({o, in_box() - o});
    r.miss.push_back({eye, eye - in_box()});
  }
  return r;
}

}  // namespace rayproof::bench
