// Mesh-level property fuzzing with a fixed seed and fixed counts (verify/mesh_fuzz.h): the random
// meshes are closed with their interior points inside, `robust` and `certified` never leak, and
// `certified` keeps the crossing parity of random rays.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "registry/registry.h"
#include "verify/mesh_fuzz.h"

using namespace rayproof;

namespace {
/// Every edge is shared by exactly two triangles, once in each direction (closed, oriented).
bool closed_and_oriented(const mesh::Mesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0 || directed.at({e.second, e.first}) != 1) return false;
  return !m.triangles.empty();
}
}  // namespace

TEST(MeshFuzz, RandomMeshesAreClosedWithInteriorPoints) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 6; ++i) {
    std::vector<Vec3<double>> inside;
    const mesh::Mesh star = verify::random_star_mesh(rng, i % 3, 3, inside);
    EXPECT_TRUE(closed_and_oriented(star)) << i;
    EXPECT_EQ(star.triangles.size(), 20u << (2 * (i % 3)));
    EXPECT_EQ(inside.size(), 3u);
    const mesh::Mesh hull = verify::random_hull_mesh(rng, 8 + 10 * i, 3, inside);
    EXPECT_TRUE(closed_and_oriented(hull)) << i;
    EXPECT_GE(hull.triangles.size(), 4u);
    EXPECT_EQ(inside.size(), 3u);
    for (const auto& p : inside) EXPECT_EQ(p, p.cast<float>().cast<double>());  // float-exact
  }
}

TEST(MeshFuzz, RobustAndCertifiedNeverLeakAndCertifiedKeepsParity) {
  verify::MeshFuzzOptions opt;
  for (const char* name : {"float", "double", "watertight-float", "watertight", "robust", "certified"})
    opt.methods.push_back(scene::find_scene_method(name, registry::all_methods()));
  opt.seed = 2024;
  opt.max_meshes = 60;
  opt.interior_points = 2;
  opt.parity_rays = 24;
  opt.threads = 2;
  const auto res = verify::run_mesh_fuzz(opt);
  EXPECT_EQ(res.meshes, 60u);
  EXPECT_EQ(res.star_meshes, 30u);
  EXPECT_EQ(res.hull_meshes, 30u);
  for (const auto& st : res.stats) {
    std::printf("%-18s leak rays %8llu  leaks %6llu  parity rays %6llu  parity failures %4llu\n", st.method.c_str(),
                (unsigned long long)st.leak_rays, (unsigned long long)st.leaks, (unsigned long long)st.parity_rays,
                (unsigned long long)st.parity_failures);
    EXPECT_GT(st.leak_rays, 5000u) << st.method;
    EXPECT_GT(st.parity_rays, 500u) << st.method;
    if (st.method == "robust" || st.method == "certified") {
      EXPECT_EQ(st.leaks, 0u) << st.method;
    }
    if (st.method == "certified") {
      EXPECT_EQ(st.parity_failures, 0u);
    }
    if (st.method == "float") {  // the checks can tell: Möller–Trumbore in float leaks and double-counts
      EXPECT_GT(st.leaks, 0u);
      EXPECT_GT(st.parity_failures, 0u);
    }
  }
  // Same seed, same campaign.
  const auto again = verify::run_mesh_fuzz(opt);
  ASSERT_EQ(again.stats.size(), res.stats.size());
  for (std::size_t j = 0; j < res.stats.size(); ++j) {
    EXPECT_EQ(again.stats[j].leaks, res.stats[j].leaks) << res.stats[j].method;
    EXPECT_EQ(again.stats[j].parity_failures, res.stats[j].parity_failures) << res.stats[j].method;
  }
  EXPECT_EQ(again.triangles, res.triangles);
}
