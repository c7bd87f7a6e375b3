// The SAH-optimal collapse (collapse_wide_sah, bvh_wide_sah.h). Its trees are
// valid wide trees (every primitive in exactly one leaf, boxes enclosing, merged leaves contiguous),
// cost no more than the greedy collapse's in the model the programme minimises and are fuller,
// and the traversal over them gives brute force's answers ray by ray; RAYPROOF_BVH_COLLAPSE picks
// the collapse and rejects other values.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <stdexcept>
#include <vector>

#include "bvh_support.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide_sah.h"
#include "rayproof/bvh_wide_stats.h"

using namespace rayproof;
using test::Answers, test::answers, test::brute, test::Soup;

namespace {

/// The traversal loop with the double box test (no SIMD needed), over whole leaves.
template <int N>
void traverse_double(const BvhWide<N>& w, const Ray<double>& ray, double tmin, double& tmax, BvhQuery q,
                     const std::function<bool(std::uint32_t)>& leaf) {
  const BvhRay<double> br(ray, BvhTraversal::conservative);
  auto test = [&](const BvhWideNode<N>& n, double tm, double* t) { return detail::wide_test_double<true>(n, br, tmin, tm, t); };
  auto range = [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first; j < first + count; ++j)
      if (leaf(w.prim_ids[j]) && q == BvhQuery::any) return true;
    return false;
  };
  auto now = [&] { return tmax; };
  switch (q) {
    case BvhQuery::closest: return detail::wide_traverse_loop<BvhWide<N>, double, BvhQuery::closest>(w, test, now, range);
    case BvhQuery::any: return detail::wide_traverse_loop<BvhWide<N>, double, BvhQuery::any>(w, test, now, range);
    case BvhQuery::all: return detail::wide_traverse_loop<BvhWide<N>, double, BvhQuery::all>(w, test, now, range);
  }
}

template <int N>
void check_width(const Soup& soup, std::uint32_t max_merge) {
  const Bvh bin = build_bvh(soup.boxes, soup.centers, BvhBuildOptions{BvhBuilder::sah, 4});
  BvhCollapseCosts c;
  c.max_merge = max_merge;
  const BvhWide<N> greedy = collapse_wide<N>(Bvh(bin), soup.boxes);
  const BvhWide<N> sah = collapse_wide_sah<N>(Bvh(bin), soup.boxes, c);
  const auto stats = test::check_wide_tree(sah, soup);
  EXPECT_LE(stats.largest_leaf, std::max<std::uint32_t>(max_merge, 8u));  // the builder's leaves are at most 8
  // The programme's optimum is at most the greedy tree's cost (a 1e-5 margin for float sums).
  EXPECT_LE(wide_sah_cost(sah, c), wide_sah_cost(greedy, c) * (1 + 1e-5));
  EXPECT_GE(wide_fullness(sah), wide_fullness(greedy));
  EXPECT_LT(sah.nodes.size(), greedy.nodes.size());
  EXPECT_GT(sah.max_depth, 0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-12, 12);
  for (int r = 0; r < 300; ++r) {
    const Ray<double> ray{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    const Answers a = answers(soup, ray, 0.0, 1e30, [&](double& tmax, BvhQuery q, auto&& leaf) {
      traverse_double<N>(sah, ray, 0.0, tmax, q, leaf);
    });
    ASSERT_EQ(a, brute(soup, ray, 0.0, 1e30)) << "ray " << r;
  }
}

}  // namespace

TEST(BvhCollapse, SahTreesAreValidCheaperAndAnswerAsBruteForce) {
  const Soup soup = test::random_soup(6000, 11);
  check_width<8>(soup, 0);
  check_width<8>(soup, 8);
  check_width<8>(soup, 16);
  check_width<4>(soup, 8);
}

TEST(BvhCollapse, MergedLeavesAreContiguousRanges) {
  // A large max_merge invites merges; check_wide_tree then sees every primitive exactly once.
  const Soup soup = test::random_soup(3000, 12);
  const Bvh bin = build_bvh(soup.boxes, soup.centers, BvhBuildOptions{BvhBuilder::sah, 4});
  BvhCollapseCosts c;
  c.max_merge = 64, c.node_cost = 16;  // nodes dear: the programme merges
  const Bvh8 w = collapse_wide_sah<8>(Bvh(bin), soup.boxes, c);
  const auto stats = test::check_wide_tree(w, soup);
  EXPECT_GT(stats.largest_leaf, 8u) << "no subtree was merged into a leaf";
  EXPECT_LE(stats.largest_leaf, 64u);
}

TEST(BvhCollapse, TinyTreesAndTheEnvironment) {
  for (int n : {1, 2, 9, 40}) {
    const Soup soup = test::random_soup(n, 13);
    const Bvh bin = build_bvh(soup.boxes, soup.centers, BvhBuildOptions{BvhBuilder::sah, 4});
    test::check_wide_tree(collapse_wide_sah<8>(Bvh(bin), soup.boxes), soup);
    test::check_wide_tree(collapse_wide_sah<4>(Bvh(bin), soup.boxes), soup);
  }
  EXPECT_TRUE(collapse_wide_sah<8>(Bvh{}, {}).empty());
  const char* old = std::getenv("RAYPROOF_BVH_COLLAPSE");
  const std::string saved = old ? old : "";
  ::setenv("RAYPROOF_BVH_COLLAPSE", "greedy", 1);
  EXPECT_EQ(bvh_collapse_choice(), BvhCollapse::greedy);
  EXPECT_EQ(bvh_collapse_choice(BvhCollapse::sah), BvhCollapse::sah);
  ::setenv("RAYPROOF_BVH_COLLAPSE", "sah", 1);
  EXPECT_EQ(bvh_collapse_choice(), BvhCollapse::sah);
  ::setenv("RAYPROOF_BVH_COLLAPSE", "", 1);
  EXPECT_EQ(bvh_collapse_choice(), BvhCollapse::sah);
  ::setenv("RAYPROOF_BVH_COLLAPSE", "optimal", 1);
  EXPECT_THROW((void)bvh_collapse_choice(), std::invalid_argument);
  if (old) ::setenv("RAYPROOF_BVH_COLLAPSE", saved.c_str(), 1);
  else ::unsetenv("RAYPROOF_BVH_COLLAPSE");
}
