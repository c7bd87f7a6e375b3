// The scene layer's queries on the conservative double box test (bvh_wide.h: wide_traverse_double,
// taken for tmin < 0 and for rays out of the float path's range) with axis-aligned rays. A
// direction component of 0 gives +-inf slab distances; once they were widened into NaN, which the
// box test skips, so that axis rejected no box and an axis ray visited every leaf of the tree (ray
// crossings at 1/2000 of random rays' speed). Each query's traversal is counted through
// Accel::traverse_slots with that query's own range, mode and query kind (the call sites named
// below), on every tree the scene layer builds (four- and eight-wide, full and compressed nodes):
// axis rays through vertices, edge midpoints and nothing in particular against random rays from
// the same origins. Each case first checks that it does take the double test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rayproof/bvh_wide.h"
#include "rayproof/scene/exact_mesh.h"
#include "scene/accel.h"
#include "scene/watertight.h"

namespace {

using namespace rayproof;

struct Query {
  const char* site;  ///< the call site whose traversal this is
  BvhQuery query;
  double tmin, tmax;
  bool scaled;  ///< on the mesh scaled by 2^70 (origins beyond the float path's 2^64)
  bool segment;  ///< the ray is a segment p -> q with d = q - p, t in [0, 1]
};

constexpr double kInf = std::numeric_limits<double>::infinity();

// tmin < 0: a range that starts behind the origin (any caller's TRange); scaled: a mesh far from the
// origin, where every query takes the double test.
const Query kQueries[] = {
    {"ExactMesh::ray_crossings, range [-1, inf) (crossings.cpp)", BvhQuery::all, -1.0, kInf, false, false},
    {"ExactMesh::ray_crossings, default range (crossings.cpp)", BvhQuery::all, 0.0, kInf, true, false},
    {"ExactMesh::contains, the perturbed ray (contains.cpp: query_point)", BvhQuery::any, 0.0, kInf, true, false},
    {"ExactMesh::segment (segment.cpp)", BvhQuery::all, 0.0, 1.0, true, true},
    {"MeshCaster closest, range [-1, inf) (accel_query.h)", BvhQuery::closest, -1.0, kInf, false, false},
    {"MeshCaster any, range [-1, inf) (accel_query.h)", BvhQuery::any, -1.0, kInf, false, false},
    {"MeshCaster all, range [-1, inf) (accel_query.h)", BvhQuery::all, -1.0, kInf, false, false},
};

struct Tree {
  BvhSimd simd;
  BvhNodes nodes;
  const char* name;
};

TEST(SceneAxisRays, DoubleBoxTestVisitsAsFewLeavesAsRandomRays) {
  const mesh::Mesh base = scene::bumpy_sphere(20000);
  for (const bool scaled : {false, true}) {
    mesh::Mesh m = base;
    if (scaled)
      for (auto& v : m.vertices) v = v * 0x1p70;
    const scene::MeshRef ref{m.vertices.data(), m.vertices.size(), reinterpret_cast<const std::byte*>(m.triangles.data()),
                             3 * sizeof(std::uint32_t), m.triangles.size()};
    for (const Tree tree : {Tree{BvhSimd::sse4, BvhNodes::full, "4-wide full"}, Tree{BvhSimd::sse4, BvhNodes::compressed, "4-wide compressed"},
                            Tree{BvhSimd::avx2, BvhNodes::full, "8-wide full"}, Tree{BvhSimd::avx2, BvhNodes::compressed, "8-wide compressed"}}) {
      if (tree.simd == BvhSimd::avx2 && !cpu_has_avx2()) continue;
      const scene::Accel accel(ref, BvhBuildOptions{}, tree.simd, tree.nodes);
      const std::size_t prims = accel.primitive_count();
      for (const Query& q : kQueries) {
        if (q.scaled != scaled) continue;
        SCOPED_TRACE(std::string(q.site) + " on " + tree.name);
        auto visits = [&](const Ray<double>& r) {
          // The query's own path: the double test (the float one refuses this ray and tmin).
          detail::Bvh4RayF rf;
          EXPECT_FALSE(detail::make_bvh4_ray(r, true, q.tmin, rf));
          long n = 0;
          accel.traverse_slots(r, q.tmin, q.tmax, BvhTraversal::conservative, q.query, [&](std::uint32_t) {
            ++n;
            return false;  // every leaf the query could visit (closest and any stop earlier)
          });
          return n;
        };
        std::mt19937 rng(5);
        std::normal_distribution<double> g;
        const double size = scaled ? 0x1p70 : 1.0;  // the sphere's radius is about 1
        long axis = 0, random = 0, worst_axis = 0;
        const int rays = 90;
        for (int i = 0; i < rays; ++i) {
          const int k = i % 3;
          const auto& t = m.triangles[rng() % m.triangles.size()];
          Vec3<double> through = m.vertices[t[0]];  // a vertex, an edge's midpoint, or a point near the surface
          if (i % 3 == 1) through = (m.vertices[t[0]] + m.vertices[t[1]]) * 0.5;
          if (i % 3 == 2) through = through * 0.97;
          Vec3<double> dir{0, 0, 0};
          dir[k] = i % 2 ? 1.0 : -1.0;
          Vec3<double> o = through;
          o[k] -= dir[k] * 3 * size;  // outside the sphere, looking through it
          // The random ray: from o towards a point near `through`, so that it crosses the sphere too.
          const Vec3<double> aim = through + Vec3<double>{g(rng), g(rng), g(rng)} * (0.3 * size);
          Ray<double> a{o, dir}, r{o, aim - o};
          if (q.segment) a.d = a.d * (3 * size);  // segments: from o to `through`, and to `aim`
          const long va = visits(a);
          axis += va, worst_axis = std::max(worst_axis, va);
          random += visits(r);
        }
        // Both cross the sphere from outside (an axis ray through a vertex or an edge may meet more
        // boxes at once): 4x allowed; and never a tenth of the mesh for one ray (the regression
        // visited all of it).
        EXPECT_LE(axis, 4 * random + 16 * rays) << "axis " << axis << " random " << random;
        EXPECT_LT(worst_axis, long(prims) / 10) << "of " << prims;
        EXPECT_GT(axis, 0);  // the rays do reach the mesh
      }
    }
  }
}

TEST(SceneAxisRays, TheQueriesAnswerOnTheDoubleTest) {
  // The same paths through the public API, answers checked: an axis ray through a cube scaled far
  // beyond 2^64 crosses it twice; with the range from -1, a ray from its centre crosses it once
  // behind and once ahead.
  const double s = 0x1p70;
  std::vector<Vec3<double>> v;
  for (int i = 0; i < 8; ++i) v.push_back(Vec3<double>{double(i & 1), double(i >> 1 & 1), double(i >> 2 & 1)} * s);
  const std::vector<std::array<std::uint32_t, 3>> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                                       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  const ExactMesh cube({&v[0].x, v.size()}, {t.front().data(), t.size()});
  const RayCrossings far = cube.ray_crossings({{-s, 0.5 * s, 0.25 * s}, {1, 0, 0}});
  ASSERT_EQ(far.crossings.size(), 2u);
  EXPECT_EQ(far.crossings[0].t, s);
  EXPECT_EQ(far.crossings[1].t, 2 * s);
  EXPECT_EQ(cube.contains({0.5 * s, 0.25 * s, 0.75 * s}), Side::inside);
  EXPECT_TRUE(cube.segment({-s, 0.5 * s, 0.5 * s}, {0.5 * s, 0.5 * s, 0.5 * s}).crosses);
  const std::vector<Vec3<double>> u = [&] {
    std::vector<Vec3<double>> w;
    for (const auto& p : v) w.push_back(p * (1 / s));
    return w;
  }();
  const ExactMesh unit({&u[0].x, u.size()}, {t.front().data(), t.size()});
  const RayCrossings both = unit.ray_crossings({{0.5, 0.5, 0.25}, {0, 1, 0}}, {-1, kInf});
  ASSERT_EQ(both.crossings.size(), 2u);
  EXPECT_EQ(both.crossings[0].t, -0.5);
  EXPECT_EQ(both.crossings[0].direction, CrossingDirection::in);
  EXPECT_EQ(both.crossings[1].t, 0.5);
}

}  // namespace
