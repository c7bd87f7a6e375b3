#pragma once
// Test helpers shared by the BVH tests (bvh_test, bvh8_test, bvh_build_test): random triangle
// soups with their bounds, the answers of one traversal with Möller–Trumbore leaves against brute
// force, and the structure check of a collapsed wide tree (either width).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/triangle.h"

namespace rayproof::test {

struct Soup {
  std::vector<Triangle<double>> tris;
  std::vector<BvhBox> boxes;
  std::vector<Vec3<float>> centers;
};

/// n triangles of size ~0.7 at centers uniform in [-10, 10]^3 (fixed seed). With `flat_fifth`,
/// every fifth triangle is made parallel to z = 0 (flat boxes; rays along them have origins on slab
/// planes); the random sequence is the same either way.
inline Soup random_soup(int n, unsigned seed, bool flat_fifth = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10, 10), s(-0.7, 0.7);
  Soup soup;
  for (int i = 0; i < n; ++i) {
    const Vec3<double> c{u(rng), u(rng), u(rng)};
    Triangle<double> t{c + Vec3<double>{s(rng), s(rng), s(rng)}, c + Vec3<double>{s(rng), s(rng), s(rng)},
                       c + Vec3<double>{s(rng), s(rng), s(rng)}};
    if (flat_fifth && i % 5 == 0) t.p1.z = t.p2.z = t.p0.z;
    BvhBox b;
    b.extend(t.p0), b.extend(t.p1), b.extend(t.p2);
    soup.tris.push_back(t);
    soup.boxes.push_back(b);
    soup.centers.push_back(((t.p0 + t.p1 + t.p2) / 3.0).cast<float>());
  }
  return soup;
}

inline bool hits(const TriangleHit<double>& h) {
  return h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex;
}

/// The answers of one traversal (closest t and primitive, all hits sorted, any) with MT leaves.
struct Answers {
  double t = 0;
  std::uint32_t prim = ~0u;
  std::vector<std::pair<double, std::uint32_t>> all;
  bool any = false;
  friend bool operator==(const Answers&, const Answers&) = default;
};

/// `traverse(tmax, query, leaf)` runs one query of the traversal under test; closest hit breaks
/// ties in t by the lower primitive index, and any hit must stop at its first hit.
template <class Traverse>
Answers answers(const Soup& soup, const Ray<double>& ray, double tmin, double tmax0, Traverse&& traverse) {
  Answers a;
  double tmax = tmax0;
  traverse(tmax, BvhQuery::closest, [&](std::uint32_t i) {
    const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
    if (hits(h) && h.t >= tmin && (h.t < tmax || (h.t == tmax && i < a.prim))) tmax = h.t, a.prim = i;
    return false;
  });
  a.t = tmax;
  double tm = tmax0;
  traverse(tm, BvhQuery::all, [&](std::uint32_t i) {
    const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
    if (hits(h) && h.t >= tmin && h.t <= tmax0) a.all.push_back({h.t, i});
    return false;
  });
  std::sort(a.all.begin(), a.all.end());
  int visits_after_hit = 0;
  traverse(tm, BvhQuery::any, [&](std::uint32_t i) {
    visits_after_hit += a.any;
    const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
    return a.any = hits(h) && h.t >= tmin && h.t <= tmax0;
  });
  EXPECT_EQ(visits_after_hit, 0);  // any hit stops at the first hit
  return a;
}

/// The same answers by testing every triangle.
inline Answers brute(const Soup& soup, const Ray<double>& ray, double tmin, double tmax0) {
  Answers a;
  a.t = tmax0;
  for (std::uint32_t i = 0; i < soup.tris.size(); ++i) {
    const auto h = intersect_moller_trumbore(ray, soup.tris[i]);
    if (hits(h) && h.t >= tmin && h.t <= tmax0) a.all.push_back({h.t, i});
  }
  std::sort(a.all.begin(), a.all.end());
  a.any = !a.all.empty();
  if (a.any) a.t = a.all.front().first, a.prim = a.all.front().second;
  return a;
}

struct WideTreeStats {
  int leaves = 0;
  std::uint32_t largest_leaf = 0;
};

/// Checks a collapsed wide tree (Bvh4 or Bvh8) over `soup`: every primitive in exactly one leaf,
/// leaf boxes contain their primitives' boxes, inner boxes contain their children's, unused slots
/// have empty boxes, inner references are in range.
template <class Tree>
WideTreeStats check_wide_tree(const Tree& w, const Soup& soup) {
  constexpr int N = Tree::kWidth;
  WideTreeStats stats;
  std::vector<int> seen(soup.tris.size(), 0);
  for (const auto& n : w.nodes)
    for (int i = 0; i < N; ++i) {
      if (!(n.valid >> i & 1)) {
        EXPECT_GT(n.lo[0][i], n.hi[0][i]);  // unused slots: empty boxes
        continue;
      }
      const BvhBox b = n.box(i);
      if (n.count[i]) {
        ++stats.leaves;
        stats.largest_leaf = std::max<std::uint32_t>(stats.largest_leaf, n.count[i]);
        for (std::uint32_t j = n.child[i]; j < n.child[i] + n.count[i]; ++j) {
          ++seen[w.prim_ids[j]];
          for (int k = 0; k < 3; ++k) {
            EXPECT_LE(b.lo[k], soup.boxes[w.prim_ids[j]].lo[k]);
            EXPECT_GE(b.hi[k], soup.boxes[w.prim_ids[j]].hi[k]);
          }
        }
      } else {
        if (n.child[i] >= w.nodes.size()) {
          ADD_FAILURE() << "inner reference " << n.child[i] << " out of range";
          continue;
        }
        const auto& c = w.nodes[n.child[i]];
        for (int j = 0; j < N; ++j)
          if (c.valid >> j & 1)
            for (int k = 0; k < 3; ++k) {
              EXPECT_LE(b.lo[k], c.lo[k][j]);
              EXPECT_GE(b.hi[k], c.hi[k][j]);
            }
      }
    }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(seen.size())) << "primitives not in exactly one leaf";
  return stats;
}

}  // namespace rayproof::test
