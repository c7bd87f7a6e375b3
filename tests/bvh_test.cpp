// BVH builders and traversal: structure invariants, and every query against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"
#include "rayproof/triangle.h"
#include "bvh_support.h"

using namespace rayproof;

using test::Soup, test::random_soup, test::hits;

namespace {
Ray<double> random_ray(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  return {{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
}
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

TEST(Bvh, AxisAlignedRaysVisitAsFewLeavesAsRandomRaysOnEveryPath) {
  // A direction component of 0 makes that axis' slab distances +-inf. The conservative double test
  // (tmin < 0, or a ray out of the float path's range) once widened them to inf - inf = NaN, which
  // the box test skips: the axis then rejected no box, and an axis-aligned ray visited every leaf
  // (bunny00's crossings ran at 1/250 of random rays' speed). Count the primitives each path
  // visits for rays along each axis (through vertices, and through nothing in particular) against
  // random rays on the same path.
  const Soup soup = random_soup(4000, 11);
  const Bvh bin = build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4});
  const Bvh4 w4 = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  const Bvh8 w8 = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-9, 9), d(-1, 1);
  struct Path {
    const char* name;
    double tmin, scale;  // scale 2^70: origin and range out of the float path's range (double test)
  };
  for (const Path path : {Path{"tmin<0", -1.0, 1.0}, Path{"tmin=0", 0.0, 1.0}, Path{"out of float range", -1.0, 0x1p70}})
    for (BvhTraversal mode : {BvhTraversal::conservative, BvhTraversal::standard})
      for (int tree = 0; tree < 3; ++tree) {
        if (tree == 2 && !cpu_has_avx2()) continue;
        auto visits = [&](const Ray<double>& ray) {
          long n = 0;
          double tmax = 1e300;
          auto leaf = [&](std::uint32_t) { return ++n, false; };
          const double tmin = path.tmin * path.scale;
          if (tree == 0) bvh_traverse(bin, ray, tmin, tmax, mode, BvhQuery::all, leaf);
          if (tree == 1) bvh4_traverse(w4, ray, tmin, tmax, mode, BvhQuery::all, leaf);
          if (tree == 2) bvh8_traverse(w8, ray, tmin, tmax, mode, BvhQuery::all, leaf);
          return n;
        };
        long axis = 0, random = 0, worst_axis = 0;
        const int rays = 60;
        for (int r = 0; r < rays; ++r) {
          // Both rays pass through p (a vertex, or a point in the soup) from 30 units away.
          const int k = r % 3;
          Vec3<double> p{u(rng), u(rng), u(rng)};
          if (r % 2) p = soup.tris[rng() % soup.tris.size()].p1;
          Vec3<double> dir{0, 0, 0};
          dir[k] = r % 4 < 2 ? 1.0 : -1.0;
          const long a = visits({(p - dir * 30.0) * path.scale, dir});
          axis += a, worst_axis = std::max(worst_axis, a);
          Vec3<double> rd{d(rng), d(rng), d(rng)};
          rd = rd / std::sqrt(dot(rd, rd));
          random += visits({(p - rd * 30.0) * path.scale, rd});
        }
        SCOPED_TRACE(std::string(path.name) + (mode == BvhTraversal::conservative ? " conservative" : " standard") +
                     " tree " + std::to_string(tree));
        // An axis ray crosses the whole soup (60 units), a random one often less: allow 4x, and
        // never a fifth of the soup for one ray (every leaf is 4000).
        EXPECT_LE(axis, 4 * random + 16 * rays) << "axis " << axis << " random " << random;
        EXPECT_LT(worst_axis, long(soup.tris.size()) / 5);
      }
}

TEST(Bvh, EmptyAndSingle) {
  const Bvh empty = build_bvh({}, {});
  EXPECT_TRUE(empty.empty());
  double tmax = 1.0;
  bvh_traverse(empty, Ray<double>{{0, 0, 0}, {1, 0, 0}}, 0.0, tmax, BvhTraversal::standard, BvhQuery::closest,
               [](std::uint32_t) { ADD_FAILURE(); return false; });
}

// ---- Four-wide BVH (bvh_wide.h) ----

TEST(Bvh4, CollapseKeepsEveryPrimitiveAndNestsBounds) {
  const Soup soup = random_soup(3000, 4);
  for (auto [builder, leaf] : {std::pair{BvhBuilder::median, 4u}, {BvhBuilder::sah, 4u}, {BvhBuilder::median, 1u << 30}}) {
    const Bvh4 w = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {builder, leaf}), soup.boxes);
    const test::WideTreeStats stats = test::check_wide_tree(w, soup);
    EXPECT_GT(stats.leaves, 0);
    if (leaf == 4u) {
      EXPECT_LT(w.nodes.size(), soup.tris.size() / 3);  // mostly four-wide
    }
  }
}

TEST(Bvh4, QueriesAgreeWithBruteForceAndTheBinaryTree) {
  const Soup soup = random_soup(3000, 2);
  std::mt19937 rng(3);
  for (BvhBuilder builder : {BvhBuilder::median, BvhBuilder::sah})
    for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative}) {
      const Bvh bin = build_bvh(soup.boxes, soup.centers, {builder, 4});
      const Bvh4 wide = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {builder, 4}), soup.boxes);
      int hit_rays = 0;
      for (int r = 0; r < 600; ++r) {
        Ray<double> ray = random_ray(rng);
        // Some rays take the double path: the same line with d scaled out of the float range.
        if (r % 7 == 3) ray.d = ray.d * 0x1p-70;
        if (r % 7 == 5) ray.d = ray.d * 0x1p+70;
        const double s = r % 7 == 3 ? 0x1p70 : (r % 7 == 5 ? 0x1p-70 : 1.0);
        const double tmin = (r % 3 == 0 ? 2.0 : 0.0) * s, tmax0 = r % 5 == 0 ? 8.0 * s : 1e300;
        // Every query on the wide tree against the binary tree and brute force.
        const test::Answers aw = test::answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery q, auto&& leaf) {
          bvh4_traverse(wide, ray, tmin, tm, mode, q, leaf);
        });
        const test::Answers ab = test::answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery q, auto&& leaf) {
          bvh_traverse(bin, ray, tmin, tm, mode, q, leaf);
        });
        ASSERT_EQ(aw, ab) << "ray " << r;
        ASSERT_EQ(aw, test::brute(soup, ray, tmin, tmax0)) << "ray " << r;
        hit_rays += aw.any;
      }
      EXPECT_GT(hit_rays, 120);
    }
}

TEST(Bvh4, ConservativeVisitsBoxesTouchedAtACornerByNonFloatOrigins) {
  // Rays through a corner of a primitive's float box exactly (o + 1 * d = corner, o a double that
  // is no float): the exact segment touches the box at one point, so conservative traversal must
  // visit the primitive, for all hits with any tmin <= 1 <= tmax and for closest hit pruned at t = 1.
  const Soup soup = random_soup(2000, 6);
  const Bvh4 wide = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  int missed = 0, total = 0;
  for (int r = 0; r < 3000; ++r) {
    const std::uint32_t p = rng() % soup.tris.size();
    const BvhBox& b = soup.boxes[p];
    const Vec3<double> corner{double(rng() & 1 ? b.hi[0] : b.lo[0]), double(rng() & 1 ? b.hi[1] : b.lo[1]),
                              double(rng() & 1 ? b.hi[2] : b.lo[2])};
    Vec3<double> d;
    for (int k = 0; k < 3; ++k) d[k] = std::ldexp(std::round(std::ldexp(u(rng), 40)), -40);  // 2^-40 grid: o exact
    if (r % 4 == 0) d[r / 4 % 3] = 0.0;  // axis-parallel: origin on the slab planes of that axis
    if (is_zero(d)) continue;
    const Ray<double> ray{corner - d, d};
    ASSERT_EQ(ray.o + ray.d, corner);
    for (double tmin : {0.0, 1.0})
      for (double tmax0 : {1.0, 1e300}) {
        ++total;
        bool seen = false;
        double tm = tmax0;
        bvh4_traverse(wide, ray, tmin, tm, BvhTraversal::conservative, BvhQuery::all, [&](std::uint32_t i) {
          seen |= i == p;
          return false;
        });
        double tc = 1.0;  // closest, with the best t so far exactly at the touch
        bool seen_closest = false;
        bvh4_traverse(wide, ray, tmin, tc, BvhTraversal::conservative, BvhQuery::closest, [&](std::uint32_t i) {
          seen_closest |= i == p;
          return false;
        });
        missed += !seen + !seen_closest;
      }
  }
  EXPECT_GT(total, 10000);
  EXPECT_EQ(missed, 0);
}

TEST(Bvh4, EmptyAndInvalidRays) {
  const Bvh4 empty = collapse_bvh4(build_bvh({}, {}), {});
  EXPECT_TRUE(empty.empty());
  double tmax = 1.0;
  bvh4_traverse(empty, Ray<double>{{0, 0, 0}, {1, 0, 0}}, 0.0, tmax, BvhTraversal::standard, BvhQuery::closest,
                [](std::uint32_t) { ADD_FAILURE(); return false; });
  // NaN and infinite rays: no crash (the double path), whatever is visited.
  const Soup soup = random_soup(100, 9);
  const Bvh4 w = collapse_bvh4(build_bvh(soup.boxes, soup.centers), soup.boxes);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const Ray<double>& r : {Ray<double>{{nan, 0, 0}, {1, 0, 0}}, Ray<double>{{0, 0, 0}, {inf, 0, 0}},
                               Ray<double>{{0, 0, 0}, {0, 0, 0}}, Ray<double>{{1e308, -1e308, 0}, {1e-308, 1, 0}}})
    for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative}) {
      double tm = inf;
      bvh4_traverse(w, r, 0.0, tm, mode, BvhQuery::closest, [](std::uint32_t) { return false; });
    }
}

// ---- One collapse for both widths (collapse_wide<N>) ----

namespace {
/// A binary tree built here, not by bvh_build.h (so the pinned results below do not move when the
/// builders change): median splits on the longest axis of the centers, ties by index; leaves of at
/// most `leaf` primitives, and at depth 4 every third subtree becomes one leaf whatever its size
/// (leaves of hundreds of primitives: the collapse splits them into chunks).
Bvh median_tree(const Soup& soup, std::uint32_t leaf) {
  Bvh bin;
  const auto n = static_cast<std::uint32_t>(soup.boxes.size());
  bin.prim_ids.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) bin.prim_ids[i] = i;
  bin.nodes.emplace_back();
  struct Task {
    std::uint32_t node, first, count;
    int depth;
  };
  std::vector<Task> stack{{0, 0, n, 1}};
  int leaf_subtrees = 0;
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    bin.max_depth = std::max(bin.max_depth, t.depth);
    BvhBox box, cbox;
    for (std::uint32_t i = t.first; i < t.first + t.count; ++i) {
      const std::uint32_t p = bin.prim_ids[i];
      box.extend(soup.boxes[p]);
      BvhBox c;
      for (int k = 0; k < 3; ++k) c.lo[k] = c.hi[k] = soup.centers[p][k];
      cbox.extend(c);
    }
    bin.nodes[t.node].box = box;
    if (t.count <= leaf || (t.depth == 4 && leaf_subtrees++ % 3 == 0)) {
      bin.nodes[t.node].index = t.first, bin.nodes[t.node].count = t.count;
      continue;
    }
    const int axis = cbox.longest_axis();
    auto* ids = bin.prim_ids.data() + t.first;
    std::sort(ids, ids + t.count, [&](std::uint32_t a, std::uint32_t b) {
      const float ca = soup.centers[a][axis], cb = soup.centers[b][axis];
      return ca < cb || (ca == cb && a < b);
    });
    const auto kids = static_cast<std::uint32_t>(bin.nodes.size());
    bin.nodes[t.node].index = kids;
    bin.nodes.emplace_back(), bin.nodes.emplace_back();
    const std::uint32_t half = t.count / 2;
    stack.push_back({kids, t.first, half, t.depth + 1});
    stack.push_back({kids + 1, t.first + half, t.count - half, t.depth + 1});
  }
  return bin;
}

/// FNV-1a over a wide tree's node bytes, prim_ids and max_depth.
template <class Tree>
std::uint64_t tree_hash(const Tree& w) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&](const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  add(w.nodes.data(), w.nodes.size() * sizeof(w.nodes[0]));
  add(w.prim_ids.data(), w.prim_ids.size() * sizeof(std::uint32_t));
  add(&w.max_depth, sizeof(w.max_depth));
  return h;
}
}  // namespace

TEST(BvhWide, CollapseIsNodeForNodeTheOneOfBeforeTheMerge) {
  // Hashes of the trees collapse_bvh4 / collapse_bvh8 built before the two widths shared one
  // collapse (commit c63722d), for these soups and trees.
  const Soup soup = random_soup(5000, 11);
  struct Pinned {
    std::uint32_t leaf;
    std::uint64_t bvh4, bvh8, bvh8_merge16;
  };
  const Pinned pinned[] = {{1, 0x88a004cf968ca847, 0x2cc93c79358a7bef, 0xaa8253d94ddc4451},
                           {4, 0x17de4fbb1c42b5d1, 0x7fe34303657ee1cb, 0x3f692f401a805465},
                           {9, 0x237e8517723b3f6b, 0xf4de8f6fd4433d77, 0xd264c351cdebd7b1}};
  for (const Pinned& p : pinned) {
    const Bvh bin = median_tree(soup, p.leaf);
    EXPECT_EQ(tree_hash(collapse_bvh4(Bvh(bin), soup.boxes)), p.bvh4) << "leaf " << p.leaf;
    EXPECT_EQ(tree_hash(collapse_wide<4>(Bvh(bin), soup.boxes)), p.bvh4) << "leaf " << p.leaf;
    EXPECT_EQ(tree_hash(collapse_bvh8(Bvh(bin), soup.boxes)), p.bvh8) << "leaf " << p.leaf;
    EXPECT_EQ(tree_hash(collapse_bvh8(Bvh(bin), soup.boxes, 16)), p.bvh8_merge16) << "leaf " << p.leaf;
  }
  // The soup has leaves above kMaxLeaf (split into chunks) and merge_leaf changes the tree.
  const Bvh8 merged = collapse_bvh8(median_tree(soup, 4), soup.boxes, 16), plain = collapse_bvh8(median_tree(soup, 4), soup.boxes);
  EXPECT_LT(merged.nodes.size(), plain.nodes.size());
}
