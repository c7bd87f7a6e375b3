// rayproof::verify: exact::intersect agrees with certified::intersect (same class, t within one ulp)
// on seeded random rays against every kind; verify::check (rayproof/verify/check.h) runs a user's typed
// kernel (here certified::intersect on triangles) over the built-in triangle families and its
// promises hold.
#include <rayproof/certified/intersect.h>
#include <rayproof/verify/exact.h>
#include <rayproof/float_util.h>
#include <rayproof/verify/check.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "checks.h"

namespace {

// A fixed-seed generator (splitmix64): the same cases on every machine.
struct Rng {
  std::uint64_t s;
  double next() {  // in [-4, 4)
    std::uint64_t z = (s += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1p-53 * 8 - 4;
  }
  rayproof::Vec3<double> vec() { return {next(), next(), next()}; }
  double positive() { return std::fabs(next()) + 0.25; }
};

bool within_one_ulp(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return rayproof::ulp_distance(a, b) <= 1;
}

template <class Prim>
int compare(const char* kind, const rayproof::Ray<double>& ray, const Prim& prim) {
  const auto e = rayproof::exact::intersect(ray, prim);
  const auto c = rayproof::certified::intersect(ray, prim);
  if (e.contact == c.contact && within_one_ulp(c.t, e.t) && within_one_ulp(c.t2, e.t2)) return 0;
  std::printf("verify: %s: exact %s %.17g %.17g, certified %s %.17g %.17g\n", kind, to_string(e.contact).data(), e.t,
              e.t2, to_string(c.contact).data(), c.t, c.t2);
  return 1;
}

}  // namespace

int check_verify() {
  using namespace rayproof;
  Rng rng{12};
  int failures = 0, compared = 0;
  for (int i = 0; i < 40; ++i, compared += 6) {
    const Ray<double> ray{rng.vec(), rng.vec()};
    failures += compare("plane", ray, Plane<double>{rng.vec(), rng.vec()});
    failures += compare("sphere", ray, Sphere<double>{rng.vec(), rng.positive()});
    failures += compare("ellipsoid", ray, Ellipsoid<double>{rng.vec(), {rng.positive(), rng.positive(), rng.positive()}});
    const auto a = rng.vec(), b = rng.vec();
    failures += compare("box", ray, Box<double>{{std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)},
                                                {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)}});
    failures += compare("disk", ray, Disk<double>{rng.vec(), rng.vec(), rng.positive()});
    failures += compare("triangle", ray, Triangle<double>{rng.vec(), rng.vec(), rng.vec()});
  }
  std::printf("verify: %d cases compared with exact, %d failures\n", compared, failures);

  // The checker on a user's kernel, typed: certified::intersect as a double triangle kernel.
  verify::KernelCheckOptions opt;
  opt.count = 16;
  opt.seed = 3;
  opt.exact_class = true;
  opt.max_ulps = 1;
  const auto result = verify::check(verify::TriangleKernel<double>([](const Ray<double>& r, const Triangle<double>& t) {
                                      return certified::intersect(r, t);
                                    }),
                                    opt);
  std::printf("verify: check over %zu triangle families, %zu cases, %zu class errors, promises %s\n",
              result.families.size(), result.cases(), result.class_errors(), result.promises_kept() ? "kept" : "broken");
  for (const auto& p : result.promises)
    if (!p.kept) std::printf("verify: promise %s broken on %zu cases\n", p.promise.c_str(), p.violations);
  if (result.families.empty() || result.cases() == 0 || !result.promises_kept()) ++failures;
  return failures;
}
