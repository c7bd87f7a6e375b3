// The parallel binned SAH builder. The tree is valid (every primitive exactly
// once, boxes enclose children and primitives, max_depth right) and the same, node for node, for
// one thread, two threads and tasks run in reverse order; triangle bounds are rounded outward as
// BvhBox::extend rounds them. The parallel partition of big nodes is a partition (tested on a layout
// with whole chunks between misplaced ones) and the same for any threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/triangle.h"
#include "scene/scene.h"
#include "scene/watertight.h"
#include "bvh_support.h"

using namespace rayproof;

using test::Soup;

namespace {
/// n small triangles: clustered (half of them in a few tight clumps, to get coincident-looking
/// centers and forced splits) and spread over a box.
Soup soup(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10, 10), s(-0.3, 0.3), tiny(-1e-6, 1e-6);
  Soup out;
  for (std::size_t i = 0; i < n; ++i) {
    const bool clump = i % 2 == 0;
    const Vec3<double> c = clump ? Vec3<double>{double(i % 7), 0.5, -1.0} : Vec3<double>{u(rng), u(rng), u(rng)};
    auto jitter = [&] { return clump ? Vec3<double>{tiny(rng), tiny(rng), tiny(rng)} : Vec3<double>{s(rng), s(rng), s(rng)}; };
    const Triangle<double> t{c + jitter(), c + jitter(), c + jitter()};
    BvhBox b;
    Vec3<float> center;
    scene::triangle_bounds(t, b, center);
    out.tris.push_back(t);
    out.boxes.push_back(b);
    out.centers.push_back(center);
  }
  return out;
}

/// Runs f(0) .. f(n-1) on two threads (nested calls too), taking indices from a shared counter.
struct TwoThreads {
  template <class F>
  void operator()(std::size_t n, F&& f) const {
    std::atomic<std::size_t> next{0};
    auto work = [&] {
      for (std::size_t i; (i = next.fetch_add(1)) < n;) f(i);
    };
    std::thread other(work);
    work();
    other.join();
  }
};
/// Runs the tasks last to first.
struct Reversed {
  template <class F>
  void operator()(std::size_t n, F&& f) const {
    for (std::size_t i = n; i-- > 0;) f(i);
  }
};

bool same_box(const BvhBox& a, const BvhBox& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_tree(const Bvh& a, const Bvh& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(a.prim_ids, b.prim_ids);
  EXPECT_EQ(a.max_depth, b.max_depth);
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_TRUE(same_box(a.nodes[i].box, b.nodes[i].box)) << "node " << i;
    EXPECT_EQ(a.nodes[i].index, b.nodes[i].index) << "node " << i;
    EXPECT_EQ(a.nodes[i].count, b.nodes[i].count) << "node " << i;
  }
}

/// Every primitive in exactly one leaf, every node reached once from the root, boxes enclosing.
void expect_valid(const Bvh& bvh, const Soup& s) {
  const std::size_t n = s.boxes.size();
  ASSERT_EQ(bvh.prim_ids.size(), n);
  std::vector<int> seen_prim(n, 0), seen_slot(n, 0), seen_node(bvh.nodes.size(), 0);
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
  int depth = 0;
  while (!stack.empty()) {
    const auto [i, d] = stack.back();
    stack.pop_back();
    ASSERT_LT(i, bvh.nodes.size());
    ++seen_node[i];
    depth = std::max(depth, d);
    const BvhNode& node = bvh.nodes[i];
    EXPECT_FALSE(node.box.empty());
    if (node.is_leaf()) {
      ASSERT_LE(std::size_t(node.index) + node.count, n);
      for (std::uint32_t j = node.index; j < node.index + node.count; ++j) {
        ++seen_slot[j];
        const std::uint32_t p = bvh.prim_ids[j];
        ASSERT_LT(p, n);
        ++seen_prim[p];
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(node.box.lo[k] <= s.boxes[p].lo[k] && node.box.hi[k] >= s.boxes[p].hi[k]);
      }
      continue;
    }
    EXPECT_EQ(node.index % 2, 0u) << "pairs start at even indices";
    ASSERT_LT(node.index + 1, bvh.nodes.size());
    for (std::uint32_t c : {node.index, node.index + 1}) {
      for (int k = 0; k < 3; ++k)
        EXPECT_TRUE(node.box.lo[k] <= bvh.nodes[c].box.lo[k] && node.box.hi[k] >= bvh.nodes[c].box.hi[k]);
      stack.push_back({c, d + 1});
    }
  }
  EXPECT_EQ(std::count(seen_prim.begin(), seen_prim.end(), 1), std::ptrdiff_t(n));
  EXPECT_EQ(std::count(seen_slot.begin(), seen_slot.end(), 1), std::ptrdiff_t(n));
  // Every node but nodes[1] (the root's copy) is reached exactly once: no orphans, no sharing.
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) EXPECT_EQ(seen_node[i], i == 1 ? 0 : 1) << "node " << i;
  EXPECT_EQ(bvh.max_depth, depth);
  EXPECT_EQ(bvh.max_depth, bvh.depth());
}
}  // namespace

TEST(BvhBuild, ParallelTreeIsValidAndTheSameForAnyThreadsAndOrder) {
  // Above the grain and two bin chunks, so the top is split level by level over tasks.
  const std::size_t n = 5 * detail::kBinChunk + 123;
  ASSERT_GT(n, 2 * std::size_t(detail::parallel_grain(std::uint32_t(n))));
  const Soup s = soup(n, 7);
  for (BvhBuilder builder : {BvhBuilder::sah, BvhBuilder::median}) {
    SCOPED_TRACE(builder == BvhBuilder::sah ? "sah" : "median");
    const Bvh one = build_bvh(s.boxes, s.centers, {builder, 4});
    expect_valid(one, s);
    expect_same_tree(one, build_bvh(s.boxes, s.centers, {builder, 4}, TwoThreads{}));
    expect_same_tree(one, build_bvh(s.boxes, s.centers, {builder, 4}, Reversed{}));
  }
}

TEST(BvhBuild, ParallelTreeAnswersAsBruteForce) {
  // Closest and any hit through the tree built over two threads, against every triangle.
  const Soup s = soup(3 * detail::kBinChunk, 5);
  const Bvh bvh = build_bvh(s.boxes, s.centers, {}, TwoThreads{});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  int hit_rays = 0;
  for (int r = 0; r < 200; ++r) {
    // Half the rays aim at a clump or a random triangle's center, so that many of them hit.
    const Vec3<double> o{u(rng), u(rng), u(rng)};
    const Vec3<double> target = (s.tris[rng() % s.tris.size()].p0 + s.tris[rng() % s.tris.size()].p1) * 0.5;
    const Ray<double> ray{o, r % 2 ? target - o : Vec3<double>{d(rng), d(rng), d(rng)}};
    auto crosses = [&](std::uint32_t i, double& t) {
      const auto h = intersect_moller_trumbore(ray, s.tris[i]);
      t = h.t;
      return (h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex) && h.t >= 0;
    };
    double want_t = std::numeric_limits<double>::infinity();
    std::uint32_t want = ~0u;
    for (std::uint32_t i = 0; i < s.tris.size(); ++i)
      if (double t; crosses(i, t) && (t < want_t || (t == want_t && i < want))) want_t = t, want = i;
    for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative}) {
      double tmax = std::numeric_limits<double>::infinity();
      std::uint32_t got = ~0u;
      bvh_traverse(bvh, ray, 0.0, tmax, mode, BvhQuery::closest, [&](std::uint32_t i) {
        if (double t; crosses(i, t) && (t < tmax || (t == tmax && i < got))) tmax = t, got = i;
        return false;
      });
      ASSERT_EQ(got, want) << "ray " << r;
      double tm = std::numeric_limits<double>::infinity();
      bool any = false;
      bvh_traverse(bvh, ray, 0.0, tm, mode, BvhQuery::any, [&](std::uint32_t i) {
        double t;
        return any = crosses(i, t);
      });
      ASSERT_EQ(any, want != ~0u) << "ray " << r;
    }
    hit_rays += want != ~0u;
  }
  EXPECT_GT(hit_rays, 80);
}

TEST(BvhBuild, ChunkedPartitionIsAPartitionAndTheSameForAnyThreads) {
  // The parallel partition of big nodes (partition_chunked): for splits that put the boundary in
  // the first, a middle and the last chunk, every reference before it has a bin <= the split bin
  // and every one after a greater bin, no reference is lost or repeated, the children's bounds
  // are those of their references, and the order is the same on one thread, two threads and in
  // reverse order.
  const std::size_t n = 5 * detail::kBinChunk + 321;
  const Soup s = soup(n, 13);
  std::vector<detail::PrimRef> refs(n);
  detail::Bounds4 all;
  for (std::size_t i = 0; i < n; ++i) {
    const BvhBox& b = s.boxes[i];
    refs[i] = {{b.lo[0], b.lo[1], b.lo[2]}, std::uint32_t(i), {b.hi[0], b.hi[1], b.hi[2]}, 0.0f,
               {b.lo[0] * 0.5f + b.hi[0] * 0.5f, b.lo[1] * 0.5f + b.hi[1] * 0.5f, b.lo[2] * 0.5f + b.hi[2] * 0.5f}, 0.0f};
    all.add(refs[i]);
  }
  const detail::NodeBounds nb = all.get();
  const std::size_t chunks = n / detail::kBinChunk;
  // Second input: points at x = 0 or 1, laid out per chunk as alternating, left, left, right,
  // alternating; split at bin 0 on x, the boundary falls in chunk 3 and the misplaced right
  // references lie in chunks 0 and 3, with whole chunks on the left between them.
  std::vector<detail::PrimRef> layout = refs;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = std::min(i / detail::kBinChunk, chunks - 1);
    const float x = c == 1 || c == 2 ? 0.0f : c == 3 ? 1.0f : float(i % 2);
    detail::PrimRef& r = layout[i];
    r.lo[0] = r.hi[0] = r.c[0] = x;
  }
  ASSERT_EQ(chunks, 5u);
  detail::Bounds4 layout_all;
  for (const auto& r : layout) layout_all.add(r);
  const detail::NodeBounds layout_nb = layout_all.get();
  int splits = 0;
  for (const auto* input : {&refs, &layout})
  for (int axis = 0; axis < 3; ++axis)
    for (int split : {0, 3, 7, 10, 14}) {
      SCOPED_TRACE(::testing::Message() << "axis " << axis << " bin " << split << (input == &refs ? "" : " layout"));
      std::vector<std::vector<detail::PrimRef>> got;
      for (int runner = 0; runner < 3; ++runner) {
        std::vector<detail::PrimRef> r = *input;
        const detail::Bins bins(input == &refs ? nb : layout_nb, n);
        detail::NodeBounds l, h;
        std::size_t mid = 0;
        if (runner == 0) {
          detail::Sequential seq;
          detail::partition_chunked(std::span(r), bins, axis, split, chunks, l, h, seq, mid);
        } else if (runner == 1) {
          TwoThreads two;
          detail::partition_chunked(std::span(r), bins, axis, split, chunks, l, h, two, mid);
        } else {
          Reversed rev;
          detail::partition_chunked(std::span(r), bins, axis, split, chunks, l, h, rev, mid);
        }
        detail::Bounds4 want_l, want_h;
        std::vector<int> seen(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
          ASSERT_EQ(bins.bin_of(r[i], axis) <= split, i < mid) << "reference " << i << " of " << mid;
          (i < mid ? want_l : want_h).add(r[i]);
          ++seen[r[i].id];
        }
        EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(n));
        if (mid > 0 && mid < n) {
          EXPECT_TRUE(same_box(l.box, want_l.get().box) && same_box(l.centers, want_l.get().centers));
          EXPECT_TRUE(same_box(h.box, want_h.get().box) && same_box(h.centers, want_h.get().centers));
          splits += runner == 0 && mid / detail::kBinChunk > 0 && mid / detail::kBinChunk < chunks - 1;
        }
        got.push_back(std::move(r));
      }
      for (int runner = 1; runner < 3; ++runner)
        EXPECT_EQ(0, std::memcmp(got[0].data(), got[runner].data(), n * sizeof(detail::PrimRef))) << "runner " << runner;
    }
  EXPECT_GE(splits, 3);  // boundaries inside middle chunks were exercised
}

TEST(BvhBuild, SmallAndDegenerateInputs) {
  for (std::size_t n : {1u, 2u, 3u, 9u, 100u, 4097u}) {
    const Soup s = soup(n, unsigned(n));
    const Bvh bvh = build_bvh(s.boxes, s.centers, {}, TwoThreads{});
    expect_valid(bvh, s);
    expect_same_tree(bvh, build_bvh(s.boxes, s.centers));
  }
  // All centers equal: forced splits by halves keep leaves small.
  Soup same;
  for (int i = 0; i < 3000; ++i) same.boxes.push_back(BvhBox{{0, 0, 0}, {1, 1, 1}}), same.centers.push_back({0.5f, 0.5f, 0.5f});
  const Bvh bvh = build_bvh(same.boxes, same.centers, {}, TwoThreads{});
  expect_valid(bvh, same);
  for (const BvhNode& node : bvh.nodes) {
    if (node.is_leaf()) {
      EXPECT_LE(node.count, 8u);
    }
  }
}

TEST(BvhBuild, SahCostFollowsItsDefinition) {
  const Soup s = soup(3000, 3);
  const Bvh bvh = build_bvh(s.boxes, s.centers);
  // The cost from its definition: inner nodes 2 (two box tests), leaves their primitive count,
  // each weighted by its area relative to the root's.
  double expect = 0;
  const double root = bvh.nodes[0].box.half_area();
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    if (i == 1) continue;
    const BvhNode& node = bvh.nodes[i];
    expect += node.box.half_area() / root * (node.is_leaf() ? double(node.count) : 2.0);
  }
  EXPECT_NEAR(bvh_sah_cost(bvh), expect, 1e-9 * expect);
  EXPECT_GT(bvh_sah_cost(bvh), 2.0);
  EXPECT_EQ(bvh_sah_cost(Bvh{}), 0.0);
}

TEST(BvhBuild, GroupLeafCostFillsGroups) {
  // leaf_group = 4 (group_cost 2, the default): a leaf costs ceil(n / 4) 2, in the build and in
  // bvh_sah_cost(bvh, 4, 2); the leaves fill their groups more than with the plain SAH (leaf_group
  // 1), that cost is lower, and the tree is the same for any thread count.
  // A closed mesh's triangles (small, adjacent: leaves of several triangles pay).
  Soup s;
  const mesh::Mesh m = scene::bumpy_sphere(6000);
  for (const auto& f : m.triangles) {
    const Triangle<double> t{m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]};
    BvhBox b;
    Vec3<float> center;
    scene::triangle_bounds(t, b, center);
    s.tris.push_back(t), s.boxes.push_back(b), s.centers.push_back(center);
  }
  BvhBuildOptions plain, grouped;
  plain.leaf_group = 1, grouped.leaf_group = 4;
  const Bvh b1 = build_bvh(s.boxes, s.centers, plain), b4 = build_bvh(s.boxes, s.centers, grouped, TwoThreads{});
  expect_valid(b4, s);
  expect_same_tree(b4, build_bvh(s.boxes, s.centers, grouped));
  auto slots = [](const Bvh& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < b.nodes.size(); ++i)
      if (i != 1 && b.nodes[i].is_leaf()) n += (b.nodes[i].count + 3) / 4 * 4;
    return n;
  };
  EXPECT_LT(double(slots(b4)), 0.9 * double(slots(b1))) << slots(b4) << " vs " << slots(b1);
  EXPECT_EQ(grouped.group_cost, 2.0f);
  EXPECT_LT(bvh_sah_cost(b4, 4, 2), bvh_sah_cost(b1, 4, 2));
  double expect = 0;
  const double root = b4.nodes[0].box.half_area();
  for (std::size_t i = 0; i < b4.nodes.size(); ++i) {
    const BvhNode& node = b4.nodes[i];
    if (i == 1) continue;
    EXPECT_LE(node.count, 2 * grouped.max_leaf);
    expect += node.box.half_area() / root * (node.is_leaf() ? double((node.count + 3) / 4 * 2) : 2.0);
  }
  EXPECT_NEAR(bvh_sah_cost(b4, 4, 2), expect, 1e-9 * expect);
  EXPECT_NEAR(bvh_sah_cost(b4, 1, 5), bvh_sah_cost(b4), 1e-12);  // leaf_group 1: the plain count
}

TEST(TriangleBounds, RoundedOutwardAsBvhBoxExtend) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> e(-140, 140);
  const double edge[] = {0.0, -0.0, 1e-320, -1e-320, 1e-46, -1e-46, 3.4028235677973366e38, -3.4028235677973366e38,
                         1e39, -1e39, 0.1, -0.1, 1.0, -1.0, 16777217.0, -16777217.0};
  auto pick = [&](int i) { return i % 3 == 0 ? edge[std::size_t(rng() % std::size(edge))] : std::ldexp(u(rng), e(rng)); };
  for (int i = 0; i < 20000; ++i) {
    Triangle<double> t;
    for (int k = 0; k < 3; ++k) t.p0[k] = pick(i + k), t.p1[k] = pick(i + k + 1), t.p2[k] = pick(i + k + 2);
    BvhBox got, want;
    Vec3<float> c;
    scene::triangle_bounds(t, got, c);
    want.extend(t.p0), want.extend(t.p1), want.extend(t.p2);
    ASSERT_TRUE(same_box(got, want)) << "triangle " << i;
  }
  // A NaN coordinate bounds nothing on its axis (as extend leaves it).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  BvhBox got, want;
  Vec3<float> c;
  const Triangle<double> t{{nan, 0, 0}, {nan, 1, 1}, {nan, 2, 2}};
  scene::triangle_bounds(t, got, c);
  want.extend(t.p0), want.extend(t.p1), want.extend(t.p2);
  EXPECT_TRUE(same_box(got, want));
}
