// BVH builders and traversal: structure invariants, and every query against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/triangle.h"

using namespace rayproof;

namespace {
struct Soup {
  std::vector<Triangle<double>> tris;
  std::vector<BvhBox> boxes;
  std::vector<Vec3<float>> centers;
};
Soup random_soup(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10, 10), s(-0.7, 0.7);
  Soup soup;
  for (int i = 0; i < n; ++i) {
    const Vec3<double> c{u(rng), u(rng), u(rng)};
    Triangle<double> t{c + Vec3<double>{s(rng), s(rng), s(rng)}, c + Vec3<double>{s(rng), s(rng), s(rng)},
                       c + Vec3<double>{s(rng), s(rng), s(rng)}};
    BvhBox b;
    b.extend(t.p0), b.extend(t.p1), b.extend(t.p2);
    soup.tris.push_back(t);
    soup.boxes.push_back(b);
    soup.centers.push_back(((t.p0 + t.p1 + t.p2) / 3.0).cast<float>());
  }
  return soup;
}
Ray<double> random_ray(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  return {{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
}
bool hits(const TriangleHit<double>& h) { return h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex; }
}  // namespace

TEST(BvhBox, OutwardRoundingContainsDoublePoints) {
  BvhBox b;
  b.extend(Vec3<double>{0.1, -0.1, 1e-50});
  EXPECT_LE(double(b.lo[0]), 0.1);
  EXPECT_GE(double(b.hi[0]), 0.1);
  EXPECT_LE(double(b.lo[1]), -0.1);
  EXPECT_GE(double(b.hi[1]), -0.1);
  EXPECT_LE(double(b.lo[2]), 1e-50);
  EXPECT_GT(double(b.hi[2]), 0.0);
}

TEST(Bvh, BuildersCoverEveryPrimitiveOnceAndBoundsNest) {
  const Soup soup = random_soup(2000, 1);
  for (BvhBuilder builder : {BvhBuilder::median, BvhBuilder::sah}) {
    const Bvh bvh = build_bvh(soup.boxes, soup.centers, {builder, 4});
    std::vector<std::uint32_t> ids = bvh.prim_ids;
    std::sort(ids.begin(), ids.end());
    for (std::uint32_t i = 0; i < ids.size(); ++i) ASSERT_EQ(ids[i], i);
    std::size_t in_leaves = 0;
    for (const BvhNode& n : bvh.nodes) {
      if (n.is_leaf()) {
        in_leaves += n.count;
        if (builder == BvhBuilder::median) {
          EXPECT_LE(n.count, 4u);
        }
        for (std::uint32_t i = n.index; i < n.index + n.count; ++i)
          for (int k = 0; k < 3; ++k) {
            EXPECT_LE(n.box.lo[k], soup.boxes[bvh.prim_ids[i]].lo[k]);
            EXPECT_GE(n.box.hi[k], soup.boxes[bvh.prim_ids[i]].hi[k]);
          }
      } else {
        for (std::uint32_t c : {n.index, n.index + 1})
          for (int k = 0; k < 3; ++k) {
            EXPECT_LE(n.box.lo[k], bvh.nodes[c].box.lo[k]);
            EXPECT_GE(n.box.hi[k], bvh.nodes[c].box.hi[k]);
          }
      }
    }
    EXPECT_EQ(in_leaves, soup.tris.size());
    if (builder == BvhBuilder::median) {
      EXPECT_LE(bvh.max_depth, 11);  // balanced: 1 + ceil(log2(2000 / 4)) + 1
    }
    EXPECT_LT(bvh.bytes() / double(soup.tris.size()), 40.0);  // + 24 B of indexed triangles: <= 64
  }
}

TEST(Bvh, QueriesAgreeWithBruteForce) {
  const Soup soup = random_soup(3000, 2);
  std::mt19937 rng(3);
  for (BvhBuilder builder : {BvhBuilder::median, BvhBuilder::sah})
    for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative}) {
      const Bvh bvh = build_bvh(soup.boxes, soup.centers, {builder, 4});
      int hit_rays = 0;
      for (int r = 0; r < 500; ++r) {
        const Ray<double> ray = random_ray(rng);
        const double tmin = r % 3 == 0 ? 2.0 : 0.0, tmax0 = r % 5 == 0 ? 8.0 : 1e300;
        // Brute force: every crossing in [tmin, tmax0].
        std::vector<std::pair<double, std::uint32_t>> all;
        for (std::uint32_t i = 0; i < soup.tris.size(); ++i) {
          const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
          if (hits(h) && h.t >= tmin && h.t <= tmax0) all.push_back({h.t, i});
        }
        std::sort(all.begin(), all.end());
        double tmax = tmax0;
        std::uint32_t best = ~0u;
        bvh_traverse(bvh, ray, tmin, tmax, mode, BvhQuery::closest, [&](std::uint32_t i) {
          const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
          if (hits(h) && h.t >= tmin && (h.t < tmax || (h.t == tmax && i < best))) tmax = h.t, best = i;
          return false;
        });
        std::vector<std::pair<double, std::uint32_t>> got;
        double tm = tmax0;
        bvh_traverse(bvh, ray, tmin, tm, mode, BvhQuery::all, [&](std::uint32_t i) {
          const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
          if (hits(h) && h.t >= tmin && h.t <= tm) got.push_back({h.t, i});
          return false;
        });
        std::sort(got.begin(), got.end());
        bool any = false;
        bvh_traverse(bvh, ray, tmin, tm, mode, BvhQuery::any, [&](std::uint32_t i) {
          const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
          return any = hits(h) && h.t >= tmin && h.t <= tm;
        });
        ASSERT_EQ(got, all) << "ray " << r;
        ASSERT_EQ(any, !all.empty()) << "ray " << r;
        if (all.empty()) {
          ASSERT_EQ(best, ~0u) << "ray " << r;
        } else {
          ++hit_rays;
          ASSERT_EQ(tmax, all.front().first) << "ray " << r;
        }
      }
      EXPECT_GT(hit_rays, 100);  // the soup is dense enough that the comparison means something
    }
}

TEST(Bvh, AxisParallelRayOnASlabPlaneIsNotCulled) {
  // A ray with d = (0, 0, 1) whose origin lies exactly on the boxes' x = 0 face: 0 * inf = NaN.
  Soup soup;
  const Triangle<double> t{{0, -1, 5}, {0, 1, 5}, {1, 0, 5}};
  BvhBox b;
  b.extend(t.p0), b.extend(t.p1), b.extend(t.p2);
  soup.tris = {t}, soup.boxes = {b}, soup.centers = {Vec3<float>{0.3f, 0, 5}};
  const Bvh bvh = build_bvh(soup.boxes, soup.centers);
  const Ray<double> ray{{0, 0, 0}, {0, 0, 1}};
  int visited = 0;
  double tmax = 1e300;
  bvh_traverse(bvh, ray, 0.0, tmax, BvhTraversal::standard, BvhQuery::all, [&](std::uint32_t) { return ++visited, false; });
  EXPECT_EQ(visited, 1);
  EXPECT_EQ(intersect_moller_trumbore(ray, t).contact, Contact::edge);
}

TEST(Bvh, EmptyAndSingle) {
  const Bvh empty = build_bvh({}, {});
  EXPECT_TRUE(empty.empty());
  double tmax = 1.0;
  bvh_traverse(empty, Ray<double>{{0, 0, 0}, {1, 0, 0}}, 0.0, tmax, BvhTraversal::standard, BvhQuery::closest,
               [](std::uint32_t) { ADD_FAILURE(); return false; });
}
