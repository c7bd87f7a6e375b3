// rayproof/scene/intersections.h: exact pairs on constructed meshes (cubes overlapping, touching
// with and without shared indices, a folded sheet, shared-vertex wedges, zero-area triangles), the
// BVH's pairs equal to a brute force over every pair, and the same output for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "intersect_meshes.h"
#include "scene/watertight.h"

namespace {

using namespace rayproof;
using namespace rayproof::testing;
using P = std::vector<TrianglePair>;

TEST(SelfIntersections, ClosedCubeHasNone) {
  EXPECT_TRUE(self_of(box({0, 0, 0}, {2, 2, 2})).empty());
  EXPECT_TRUE(self_of(scene::bumpy_sphere(500)).empty());
}

TEST(SelfIntersections, OverlappingCubes) {
  mesh::Mesh m = box({0, 0, 0}, {2, 2, 2});
  append(m, box({1, 1, 1}, {2, 2, 2}));
  const P got = self_of(m);
  EXPECT_EQ(got, brute_self(m));
  EXPECT_FALSE(got.empty());
  for (const auto& p : got) EXPECT_TRUE(p.i < 12 && p.j >= 12) << p.i << ' ' << p.j;  // each cube alone is clean
}

TEST(SelfIntersections, TouchingAtAFaceWithDifferentIndicesIntersect) {
  mesh::Mesh m = box({0, 0, 0}, {2, 2, 2});
  append(m, box({2, 0, 0}, {2, 2, 2}));  // equal coordinates on x = 2, other indices
  const P got = self_of(m);
  EXPECT_EQ(got, brute_self(m));
  // The two faces on x = 2 (triangles 10, 11 of the first, 8, 9 of the second) overlap, and the
  // side faces touch along the contact square's edges.
  for (auto [i, j] : {std::pair{10u, 20u}, {10u, 21u}, {11u, 20u}, {11u, 21u}})
    EXPECT_NE(std::find(got.begin(), got.end(), TrianglePair{i, j}), got.end()) << i << ' ' << j;
  EXPECT_GT(got.size(), 4u);
}

TEST(SelfIntersections, WeldedBoxSharingIndicesHasNone) {
  // Two unit cubes side by side sharing the four vertices of the common square (by index), the
  // square itself left out: a closed 2 x 1 x 1 box whose triangles meet only along shared indices.
  mesh::Mesh m;
  for (int k = 0; k < 12; ++k) m.vertices.push_back({double(k % 3), double((k / 3) % 2), double(k / 6)});
  const auto v = [](int x, int y, int z) { return std::uint32_t(x + 3 * y + 6 * z); };
  for (int x = 0; x < 2; ++x) {
    m.triangles.push_back({v(x, 0, 0), v(x, 1, 0), v(x + 1, 0, 0)});
    m.triangles.push_back({v(x + 1, 0, 0), v(x, 1, 0), v(x + 1, 1, 0)});
    m.triangles.push_back({v(x, 0, 1), v(x + 1, 0, 1), v(x, 1, 1)});
    m.triangles.push_back({v(x + 1, 0, 1), v(x + 1, 1, 1), v(x, 1, 1)});
    m.triangles.push_back({v(x, 0, 0), v(x + 1, 0, 0), v(x, 0, 1)});
    m.triangles.push_back({v(x + 1, 0, 0), v(x + 1, 0, 1), v(x, 0, 1)});
    m.triangles.push_back({v(x, 1, 0), v(x, 1, 1), v(x + 1, 1, 0)});
    m.triangles.push_back({v(x + 1, 1, 0), v(x, 1, 1), v(x + 1, 1, 1)});
  }
  m.triangles.push_back({v(0, 0, 0), v(0, 0, 1), v(0, 1, 0)});
  m.triangles.push_back({v(0, 1, 0), v(0, 0, 1), v(0, 1, 1)});
  m.triangles.push_back({v(2, 0, 0), v(2, 1, 0), v(2, 0, 1)});
  m.triangles.push_back({v(2, 1, 0), v(2, 1, 1), v(2, 0, 1)});
  EXPECT_TRUE(self_of(m).empty());
  EXPECT_TRUE(brute_self(m).empty());
  // The same with the middle vertices duplicated (other indices, equal coordinates): the triangles
  // of the two halves now touch along x = 1 and are reported.
  mesh::Mesh split = m;
  for (int k : {1, 4, 7, 10}) split.vertices.push_back(m.vertices[std::size_t(k)]);
  for (std::size_t t = 8; t < 16; ++t)
    for (auto& x : split.triangles[t])
      if (x % 3 == 1) x = 12 + x / 3;
  const P got = self_of(split);
  EXPECT_EQ(got, brute_self(split));
  EXPECT_FALSE(got.empty());
}

TEST(SelfIntersections, SharedEdgeCountsOnlyWhenCoplanarOverlap) {
  mesh::Mesh m;
  m.vertices = {{0, 0, 0}, {4, 0, 0}, {2, 2, 0}, {2, 1, 0}, {2, -2, 0}, {2, 1, 1}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {1, 0, 4}, {1, 0, 5}};
  // 0-1: coplanar, same side (overlap); 0-2: opposite sides (a fold line of a flat sheet); 0-3:
  // not coplanar; 1-2 opposite sides; 1-3 not coplanar; 2-3 not coplanar.
  EXPECT_EQ(self_of(m), (P{{0, 1}}));
  EXPECT_EQ(brute_self(m), (P{{0, 1}}));
  // A duplicate triangle (three shared indices) overlaps itself with positive area: reported.
  m.triangles.push_back({2, 0, 1});
  EXPECT_EQ(self_of(m), (P{{0, 1}, {0, 4}, {1, 4}}));
}

TEST(SelfIntersections, SharedVertexCountsBeyondIt) {
  mesh::Mesh m;
  m.vertices = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {2, 1, 0}, {-1, -1, 0}, {-1, -2, 0},
                {1, 1, 1}, {1, 1, -1}, {-1, 0, 1}, {-1, 1, 1}};
  m.triangles = {{0, 1, 2},    // 0
                 {0, 3, 4},    // 1: coplanar, inside 0's wedge
                 {0, 5, 6},    // 2: coplanar, only the vertex in common
                 {0, 7, 8},    // 3: pierces 0 along a segment from the shared vertex
                 {0, 9, 10}};  // 4: touches only at the shared vertex
  const P want{{0, 1}, {0, 3}, {1, 3}};
  EXPECT_EQ(self_of(m), want);
  EXPECT_EQ(brute_self(m), want);
}

TEST(SelfIntersections, FoldedSheet) {
  const mesh::Mesh m = folded_sheet(6, 3);
  const P got = self_of(m);
  EXPECT_EQ(got, brute_self(m));
  EXPECT_GT(got.size(), 36u);
}

TEST(SelfIntersections, ZeroAreaTrianglesOnlyWithThemselves) {
  mesh::Mesh m = box({0, 0, 0}, {2, 2, 2});
  m.vertices.push_back({1, 1, 1});
  m.vertices.push_back({3, 3, 3});
  m.triangles.push_back({8, 9, 9});  // a segment from the centre out through the corner (2, 2, 2)
  m.triangles.push_back({0, 7, 8});  // collinear: the cube's diagonal
  EXPECT_EQ(self_of(m), (P{{12, 12}, {13, 13}}));
  EXPECT_EQ(brute_self(m), (P{{12, 12}, {13, 13}}));
  IntersectOptions opt;
  opt.classes = true;
  for (const auto& p : self_of(m, opt)) EXPECT_EQ(p.cls, TriTri::degenerate);
}

TEST(SelfIntersections, EqualsBruteForceOnLatticeSoups) {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const mesh::Mesh m = lattice_soup(150, seed % 2 ? 40 : 400, seed);
    const P got = self_of(m);
    EXPECT_EQ(got, brute_self(m)) << "seed " << seed;
    EXPECT_GT(got.size(), 10u);
  }
}

// Fans of triangles around one shared vertex, the other vertices random: most pairs have each
// opposite edge crossing the other's plane (decided by one orient3d of the four other vertices),
// some touch only at the vertex; equal to the brute force's segment tests either way.
TEST(SelfIntersections, SharedVertexFansEqualBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t met = 0, pairs = 0;
  for (int round = 0; round < 40; ++round) {
    mesh::Mesh m;
    const Vec3<double> v = round % 2 ? Vec3<double>{u(rng), u(rng), u(rng)} : Vec3<double>{0, 0, 0};
    m.vertices.push_back(v);
    const int fan = 12;
    for (int k = 0; k < fan; ++k) {
      for (int c = 0; c < 2; ++c) {
        Vec3<double> x{u(rng), u(rng), u(rng)};
        if (round % 4 == 2) x = {std::round(4 * x.x), std::round(4 * x.y), std::round(4 * x.z)};  // ties
        m.vertices.push_back(v + x);
      }
      m.triangles.push_back({0, std::uint32_t(2 * k + 1), std::uint32_t(2 * k + 2)});
    }
    const P got = self_of(m);
    EXPECT_EQ(got, brute_self(m)) << "round " << round;
    met += got.size(), pairs += fan * (fan - 1) / 2;
  }
  EXPECT_GT(met, pairs / 10);
  EXPECT_LT(met, pairs - pairs / 10);
}

// The used vertices are copied as doubles in the tree's order whatever the input's form (floats,
// strided doubles): the pairs are those of the same coordinates as packed doubles.
TEST(SelfIntersections, FloatAndStridedVerticesGiveTheSamePairs) {
  mesh::Mesh m = scene::bumpy_sphere(1200);
  mesh::Mesh copy = m;
  for (auto& v : copy.vertices) v = v + Vec3<double>{0.5, 0.25, 0.125};
  append(m, copy);
  std::vector<float> f;
  std::vector<double> strided;
  for (auto& v : m.vertices) {
    for (int k = 0; k < 3; ++k) f.push_back(float(v[k]));
    v = {double(float(v.x)), double(float(v.y)), double(float(v.z))};
    strided.insert(strided.end(), {v.x, v.y, v.z, 7.0});
  }
  const P want = self_of(m);
  ASSERT_GT(want.size(), 10u);
  const IndexArray t{m.triangles.front().data(), m.triangles.size()};
  EXPECT_EQ(self_intersections(VertexArray(f.data(), m.vertices.size()), t), want);
  EXPECT_EQ(self_intersections(VertexArray(strided.data(), m.vertices.size(), 4 * sizeof(double)), t), want);
}

// The used vertices are copied in the tree's order and renumbered by first use: the pairs do not
// depend on the input's vertex order, on unused vertices (a NaN among them too), or on equal
// coordinates under different indices (still distinct vertices).
TEST(SelfIntersections, VertexOrderAndUnusedVerticesDoNotChangeThePairs) {
  mesh::Mesh m = folded_sheet(8, 3);
  append(m, box({0.5, 0.5, -0.5}, {1, 1, 1}));
  append(m, scene::bumpy_sphere(300));
  const P want = self_of(m);
  ASSERT_EQ(want, brute_self(m));
  ASSERT_GT(want.size(), 20u);
  // Reversed order, each used vertex followed by an unused copy of itself and an unused NaN.
  const std::size_t nv = m.vertices.size();
  mesh::Mesh r;
  for (std::size_t x = 0; x < nv; ++x) {
    r.vertices.push_back(m.vertices[nv - 1 - x]);
    r.vertices.push_back(m.vertices[nv - 1 - x]);
    r.vertices.push_back({std::numeric_limits<double>::quiet_NaN(), 0, 0});
  }
  for (const auto& t : m.triangles) {
    std::array<std::uint32_t, 3> u{};
    for (int k = 0; k < 3; ++k) u[k] = std::uint32_t(3 * (nv - 1 - t[k]));
    r.triangles.push_back(u);
  }
  EXPECT_EQ(self_of(r), want);
  // The same triangles with every index of the second triangle use moved to the unused copy:
  // the triangles that shared those vertices with it now touch there by coordinates only.
  mesh::Mesh c = r;
  for (int k = 0; k < 3; ++k) c.triangles[1][k] += 1;
  const P moved = self_of(c);
  EXPECT_EQ(moved, brute_self(c));
  EXPECT_GT(moved.size(), want.size());
}

TEST(SelfIntersections, SameOutputForEveryThreadCount) {
  mesh::Mesh m = scene::bumpy_sphere(3000);
  mesh::Mesh copy = m;
  for (auto& v : copy.vertices) v = v + Vec3<double>{0.3, 0.2, 0.1};
  append(m, copy);
  IntersectOptions one, two;
  one.threads = 1, two.threads = 2;
  one.classes = two.classes = true;
  const P a = self_of(m, one), b = self_of(m, two);
  ASSERT_EQ(a, b);
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].cls, b[k].cls);
    EXPECT_TRUE(meets(a[k].cls)) << a[k].i << ' ' << a[k].j;
  }
}

TEST(IntersectingPairs, TwoMeshesEqualBruteForce) {
  const mesh::Mesh a = box({0, 0, 0}, {2, 2, 2});
  for (const mesh::Mesh& b : {box({1, 1, 1}, {2, 2, 2}), box({2, 0, 0}, {2, 2, 2}), box({2, 2, 2}, {1, 1, 1}),
                              box({3, 0, 0}, {1, 1, 1}), lattice_soup(60, 30, 7)}) {
    const P got = intersecting_pairs(arrays_of(a), arrays_of(b));
    EXPECT_EQ(got, brute_pairs(a, b));
  }
  // Touching at one corner: the three triangles at (2, 2, 2) of a against those at b's corner.
  EXPECT_FALSE(intersecting_pairs(arrays_of(a), arrays_of(box({2, 2, 2}, {1, 1, 1}))).empty());
  EXPECT_TRUE(intersecting_pairs(arrays_of(a), arrays_of(box({2.5, 0, 0}, {1, 1, 1}))).empty());
  // A soup against itself: every triangle meets itself (no adjacency between two meshes).
  const mesh::Mesh s = lattice_soup(80, 50, 3);
  const P self_pairs = intersecting_pairs(arrays_of(s), arrays_of(s));
  EXPECT_EQ(self_pairs, brute_pairs(s, s));
}

TEST(IntersectingPairs, BadInputIsAnError) {
  mesh::Mesh a = box({0, 0, 0}, {1, 1, 1});
  mesh::Mesh bad = a;
  bad.triangles.push_back({0, 1, 99});
  EXPECT_THROW((void)intersecting_pairs(arrays_of(a), arrays_of(bad)), MeshInputError);
  EXPECT_THROW((void)self_of(bad), MeshInputError);
  bad = a;
  bad.vertices[3].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)self_of(bad), MeshInputError);
  EXPECT_TRUE(self_of(mesh::Mesh{{{0, 0, 0}}, {}}).empty());
}

}  // namespace
