// Spawned rays (rayproof/spawn.h) against the primitive they leave: the error-bounded and certified
// origins never meet it again, as the method's own kernel and the certified (exact-class) method see it; no
// offset and a fixed epsilon at large magnitudes do (light/spawn_count.h).
#include <gtest/gtest.h>

#include <cmath>

#include "registry/registry.h"
#include "light/spawn_count.h"
#include "tests/cli_support.h"

namespace rayproof {
namespace {

std::vector<const Method*> methods(std::initializer_list<const char*> names) {
  std::vector<const Method*> out;
  for (const char* n : names) out.push_back(registry::all_methods().find(n));
  return out;
}

TEST(Spawn, ErrorBoundedOriginsNeverSelfIntersect) {
  const Method& exact = *registry::all_methods().find("certified");
  const auto ms = methods({"float", "double", "robust", "certified"});
  for (io::Kind kind : {io::Kind::plane, io::Kind::sphere, io::Kind::disk}) {
    for (int mag : {0, 20, 40}) {
      const auto rows = light::count_self_intersections(kind, ms, exact, 1500, 5, mag, 1e-4);
      std::uint64_t none_self = 0, none_spawned = 0;
      for (const auto& r : rows) {
        const std::string what = std::string(io::to_string(kind)) + " 2^" + std::to_string(mag) + " " +
                                 std::string(light::to_string(r.strategy)) + " " + r.method->name;
        if (r.strategy == SpawnStrategy::error_bounded) {
          EXPECT_EQ(r.self_hits, 0u) << what;
          EXPECT_EQ(r.exact_self_hits, 0u) << what;
        }
        // The certified origin is as close as the exact classifier allows: fast kernels may still
        // see their own surface there (a renderer using it classifies the primitive it leaves
        // exactly), the exact one never does.
        if (r.strategy == SpawnStrategy::certified) {
          EXPECT_EQ(r.exact_self_hits, 0u) << what;
          if (r.method->name == "certified") {
            EXPECT_EQ(r.self_hits, 0u) << what;
          }
        }
        if (r.strategy == SpawnStrategy::none) none_self += r.exact_self_hits, none_spawned += r.spawned;
        // Double methods see every primary hit; float ones lose the primitive at 2^40.
        if (r.method->precision == Precision::float64) {
          EXPECT_EQ(r.spawned, 3000u) << what;
        }
      }
      // Without an offset, about half the computed hit points lie behind the surface.
      EXPECT_GT(none_self * 5, none_spawned) << io::to_string(kind) << " 2^" << mag;
    }
  }
}

TEST(Spawn, FixedEpsilonFailsWhereItIsBelowTheUlp) {
  const Method& exact = *registry::all_methods().find("certified");
  const auto ms = methods({"float"});
  const auto rows = light::count_self_intersections(io::Kind::sphere, ms, exact, 1000, 3, 20, 1e-4);
  for (const auto& r : rows)
    if (r.strategy == SpawnStrategy::fixed_epsilon) {
      EXPECT_GT(r.exact_self_hits * 5, r.spawned);
    }
}

TEST(Spawn, NoLeaksThroughThinSlabsForErrorBoundedAndCertifiedOrigins) {
  const Method& exact = *registry::all_methods().find("certified");
  const auto ms = methods({"float", "double", "robust", "certified"});
  for (int mag : {0, 10, 20}) {
    // A slab 1e-6 of the magnitude thick: about 16 float ulps, thinner than the fixed epsilon at 2^0.
    const auto rows = light::count_slab_leaks(ms, exact, 1000, 11, mag, 1e-6 * std::ldexp(1.0, mag), 1e-4);
    for (const auto& r : rows) {
      const std::string what = "2^" + std::to_string(mag) + " " + std::string(light::to_string(r.strategy)) + " " +
                               r.method->name;
      EXPECT_EQ(r.spawned, 1000u) << what;
      if (r.strategy == SpawnStrategy::error_bounded || r.strategy == SpawnStrategy::certified) {
        EXPECT_EQ(r.self_hits, 0u) << what;
        EXPECT_EQ(r.exact_self_hits, 0u) << what;
      }
      if (r.strategy == SpawnStrategy::fixed_epsilon && mag == 0) {
        EXPECT_EQ(r.exact_self_hits, 1000u) << what;
      }
    }
  }
}

TEST(Spawn, CliPrintsCountsAndRejectsBadFlags) {
  const auto ok = testing::run_rayproof("spawn --trials 200 --kinds disk --magnitudes 0 --methods double");
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.out.find("error-bounded"), std::string::npos);
  const auto slab = testing::run_rayproof("spawn --trials 200 --slab-gap 1e-6 --magnitudes 0 --methods float");
  ASSERT_EQ(slab.status, 0) << slab.err;
  EXPECT_NE(slab.out.find("leaks (exact)"), std::string::npos);
  for (const char* bad : {"--kinds triangle", "--trials 0", "--epsilon -1", "--magnitudes 99", "--methods nosuch",
                          "--slab-gap 2", "--slab-gap nan"}) {
    const auto r = testing::run_rayproof(std::string("spawn ") + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err, "") << bad;
  }
}

}  // namespace
}  // namespace rayproof
