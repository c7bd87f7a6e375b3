// Spawned rays on triangle meshes (light/spawn_mesh.h): error-bounded and certified origins never
// meet the triangle they leave or a neighbour they cannot reach, and never leak light through the
// mesh, with the robust and certified mesh casters; no offset does self-intersect.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "gen/rng.h"
#include "light/spawn_count.h"
#include "light/spawn_mesh.h"

namespace rayproof {
namespace {

void expect_robust_strategies_clean(const mesh::Mesh& m, std::uint64_t trials, std::uint64_t seed, const std::string& what) {
  const auto rows = light::count_mesh_spawn(m, trials, seed, 1e-4);
  ASSERT_EQ(rows.size(), 12u);
  for (const auto& r : rows) {
    const std::string row = what + " " + std::string(light::to_string(r.strategy)) + " " + r.method;
    EXPECT_GT(r.spawned, trials) << row;  // up to three spawned rays per primary
    EXPECT_GT(r.shadow, 0u) << row;
    if (r.strategy == SpawnStrategy::none) {
      // The computed hit point is on either side of the surface about as often.
      EXPECT_GT(r.exact_self_hits, r.spawned / 5) << row;
      EXPECT_GT(r.false_occlusions, 0u) << row;
    }
    if (r.strategy == SpawnStrategy::error_bounded) {
      EXPECT_EQ(r.exact_self_hits, 0u) << row;
    }
    if ((r.strategy == SpawnStrategy::error_bounded || r.strategy == SpawnStrategy::certified) && r.method != "float") {
      EXPECT_EQ(r.self_hits, 0u) << row;
      EXPECT_EQ(r.exact_self_hits, 0u) << row;
      EXPECT_EQ(r.leaks, 0u) << row;
    }
    if (r.method == "certified") {
      EXPECT_EQ(r.primary_misses, 0u) << row;
    }
  }
}

TEST(SpawnMesh, GeneratedSphereAndSlab) {
  expect_robust_strategies_clean(light::generated_spawn_mesh(3, std::ldexp(1.0, -16), 1, 0), 400, 3, "2^0");
  expect_robust_strategies_clean(light::generated_spawn_mesh(3, std::ldexp(1.0, -16), 1024, std::ldexp(1.0, 20)), 400, 4,
                                 "2^20");
}

TEST(SpawnMesh, BumpySphereWithConcaveCreases) {
  // A sphere whose vertices are moved radially at random: concave and convex creases.
  mesh::Mesh m = light::generated_spawn_mesh(3, 0.01, 1, 0);
  gen::Rng rng(11);
  for (auto& v : m.vertices)
    if (v.x < 1.5) v = rng.uniform(0.75, 1.25) * v;
  expect_robust_strategies_clean(m, 400, 5, "bumpy");
}

TEST(SpawnMesh, FixedEpsilonLeaksThroughASlabThinnerThanIt) {
  // Only the slab: every back shadow ray must be blocked by its far face, 2^-16 away.
  mesh::Mesh m = light::generated_spawn_mesh(0, std::ldexp(1.0, -16), 1, 0);
  m.triangles.erase(m.triangles.begin(), m.triangles.begin() + 8);
  const auto rows = light::count_mesh_spawn(m, 400, 6, 1e-3);
  for (const auto& r : rows) {
    if (r.strategy == SpawnStrategy::fixed_epsilon) {
      EXPECT_GT(r.leaks, 0u) << r.method;
    }
    if (r.strategy != SpawnStrategy::fixed_epsilon && r.method != "float") {
      EXPECT_EQ(r.leaks, 0u) << r.method;
    }
  }
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(SpawnMesh, Bunny) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  expect_robust_strategies_clean(mesh::read_mesh(path), 300, 8, "bunny00");
}
#endif

/// The certified caster's claims on a mesh: no spawned ray of the error-bounded or certified
/// strategy meets (exactly) a triangle it cannot meet, and its shadow rays see what the reference sees.
void expect_certified_caster_clean(const mesh::Mesh& m, std::uint64_t trials, std::uint64_t seed, const std::string& what) {
  const auto rows = light::count_mesh_spawn(m, trials, seed, 1e-4);
  std::uint64_t compared = 0;
  for (const auto& r : rows) {
    const std::string row = what + " " + std::string(light::to_string(r.strategy)) + " " + r.method;
    if (r.strategy == SpawnStrategy::error_bounded || r.strategy == SpawnStrategy::certified) {
      EXPECT_EQ(r.exact_self_hits, 0u) << row;
      if (r.method == "certified") {
        EXPECT_EQ(r.leaks, 0u) << row;
        EXPECT_EQ(r.false_occlusions, 0u) << row;
        compared += r.shadow;
      }
    }
  }
  EXPECT_GT(compared, trials) << what;
}

TEST(SpawnMesh, RepeatedVerticesAreOneVertexForTheNeighbours) {
  // A mesh whose triangles repeat their corners (as STL files do, and CGAL's
  // boeing.off) had its concave creases counted as leaks of the certified caster with the
  // error-bounded origin (cow.off unshared: 104 leaks in 2000 trials), since neighbours were found
  // through shared vertex indices. The bumpy sphere, every triangle with its own three vertices:
  mesh::Mesh shared = light::generated_spawn_mesh(3, 0.01, 1, 0);
  gen::Rng rng(11);
  for (auto& v : shared.vertices)
    if (v.x < 1.5) v = rng.uniform(0.75, 1.25) * v;
  mesh::Mesh unshared;
  for (const auto& t : shared.triangles) {
    const auto base = static_cast<std::uint32_t>(unshared.vertices.size());
    for (auto v : t) unshared.vertices.push_back(shared.vertices[v]);
    unshared.triangles.push_back({base, base + 1, base + 2});
  }
  expect_certified_caster_clean(unshared, 600, 5, "bumpy, unshared");
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(SpawnMesh, BoeingWithRepeatedVertices) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/boeing.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  expect_certified_caster_clean(mesh::read_mesh(path), 3000, 1, "boeing");  // spawn --mesh's seed: 2 false occl., 3 leaks before
}
#endif

TEST(SpawnMesh, EmptyMeshIsAnError) {
  EXPECT_THROW((void)light::count_mesh_spawn(mesh::Mesh{}, 10, 1, 1e-4), std::invalid_argument);
}

}  // namespace
}  // namespace rayproof
