#pragma once
/// The SAH-optimal collapse of a binary BVH into an N-wide one (N = 4 or 8), by dynamic
/// programming over the binary tree (after Ylitie, Karras and Laine, "Efficient incoherent ray
/// traversal on GPUs through compressed wide BVHs", HPG 2017). collapse_wide (bvh_wide.h) opens
/// the largest child until a node has N; this one picks, over all ways of covering each binary
/// subtree by wide nodes and leaves, the one of least expected cost
///   sum over wide nodes  A(n) node_cost  +  sum over leaves  A(l) ceil(size(l) / leaf_group) group_cost,
/// A the box's half area (the probability a ray through the root reaches it, up to a constant).
/// A binary leaf stays one leaf; an inner binary node whose primitives are contiguous in prim_ids
/// may also become one leaf of at most `max_merge` primitives (the DP decides when it is cheaper).
///
/// Tables, per binary node i, for j = 1 .. N slots:
///  - slot(i): the least cost of i as one child slot of a wide node: a leaf, or a wide node of its
///    own (A(i) node_cost + dist(i's two children, N slots)).
///  - dist(i, j): the least cost of covering i's subtree by at most j slots of one wide node:
///    slot(i) for j = 1 (and always for a binary leaf); else min(slot(i), min over k of
///    dist(left, k) + dist(right, j - k)).
/// The wide tree is then read off from the root (whose wide node always opens its binary root).
/// Same references, prim_ids and leaf ranges as collapse_wide; big leaves are split by wide_chunk.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rayproof/bvh_build.h"  // BvhCollapse
#include "rayproof/bvh_wide.h"

namespace rayproof {

/// BvhCollapse (bvh_build.h) resolved: automatic follows RAYPROOF_BVH_COLLAPSE (unset, empty,
/// "auto" or "sah": sah; "greedy": greedy; anything else throws std::invalid_argument).
[[nodiscard]] inline BvhCollapse bvh_collapse_choice(BvhCollapse want = BvhCollapse::automatic) {
  if (want != BvhCollapse::automatic) return want;
  const char* e = std::getenv("RAYPROOF_BVH_COLLAPSE");
  if (!e || !*e || std::strcmp(e, "auto") == 0 || std::strcmp(e, "sah") == 0) return BvhCollapse::sah;
  if (std::strcmp(e, "greedy") == 0) return BvhCollapse::greedy;
  std::string msg = "RAYPROOF_BVH_COLLAPSE='";
  msg.append(e).append("': expected auto, sah or greedy");
  throw std::invalid_argument(msg);
}

/// The cost weights of collapse_wide_sah, in the builder's units (bvh_build.h: a binary node's
/// two box tests cost 2, a leaf group `group_cost`).
struct BvhCollapseCosts {
  float node_cost = 2;           ///< one wide node visit (N box tests in one SIMD test, the push)
  float group_cost = 2;          ///< one leaf group test
  std::uint32_t leaf_group = 4;  ///< primitives per leaf group
  std::uint32_t max_merge = 8;   ///< the largest leaf made by merging a subtree (0: no merging)
};

template <int N>
[[nodiscard]] BvhWide<N> collapse_wide_sah(Bvh&& bin, std::span<const BvhBox> prim_boxes, const BvhCollapseCosts& c = {}) {
  using Node = BvhWideNode<N>;
  const std::size_t nb = bin.nodes.size();
  if (bin.empty() || bin.nodes[0].is_leaf()) return collapse_wide<N>(std::move(bin), prim_boxes);
  const std::uint32_t g = std::max<std::uint32_t>(1, c.leaf_group);
  auto leaf_cost = [&](float area, std::uint32_t n) { return area * float((n + g - 1) / g) * c.group_cost; };
  // Post-order over the binary tree: contiguous ranges (as collapse_wide's merge_leaf) and the tables.
  std::vector<std::uint32_t> first(nb, 0), size(nb, 0);
  std::vector<std::array<float, N + 1>> dist(nb);
  std::vector<std::array<std::uint8_t, N + 1>> take(nb);  // dist(i, j): 0 = slot(i), else k for the left child
  std::vector<std::uint8_t> split(nb, 0), as_leaf(nb, 0);  // slot(i) as a wide node: k for the left child; or a leaf
  std::vector<float> slot(nb, 0);
  std::vector<std::pair<std::uint32_t, bool>> order{{0, false}};
  while (!order.empty()) {
    const auto [i, done] = order.back();
    order.pop_back();
    const BvhNode& n = bin.nodes[i];
    const float area = n.box.half_area();
    if (n.is_leaf()) {
      first[i] = n.index, size[i] = n.count;
      slot[i] = leaf_cost(area, n.count), as_leaf[i] = 1;
      dist[i].fill(slot[i]), take[i].fill(0);
      continue;
    }
    if (!done) {
      order.push_back({i, true}), order.push_back({n.index, false}), order.push_back({n.index + 1, false});
      continue;
    }
    const std::uint32_t a = n.index, b = n.index + 1;
    const bool contiguous = size[a] && size[b] && (first[a] + size[a] == first[b] || first[b] + size[b] == first[a]);
    first[i] = std::min(first[a], first[b]), size[i] = contiguous ? size[a] + size[b] : 0;
    // slot(i) as a wide node: its children over at most N slots.
    float best = std::numeric_limits<float>::infinity();
    for (int k = 1; k < N; ++k) {
      const float x = dist[a][k] + dist[b][N - k];
      if (x < best) best = x, split[i] = std::uint8_t(k);
    }
    slot[i] = area * c.node_cost + best;
    if (size[i] && size[i] <= c.max_merge && leaf_cost(area, size[i]) <= slot[i]) slot[i] = leaf_cost(area, size[i]), as_leaf[i] = 1;
    dist[i][0] = dist[i][1] = slot[i], take[i][0] = take[i][1] = 0;
    for (int j = 2; j <= N; ++j) {
      dist[i][j] = slot[i], take[i][j] = 0;
      for (int k = 1; k < j; ++k) {
        const float x = dist[a][k] + dist[b][j - k];
        if (x < dist[i][j]) dist[i][j] = x, take[i][j] = std::uint8_t(k);
      }
    }
  }
  // Reading the wide tree off the tables: each wide node's slots from its binary node's split.
  BvhWide<N> w;
  w.prim_ids = std::move(bin.prim_ids);
  if (w.prim_ids.size() >= (std::size_t(1) << 31)) throw std::length_error("BVH: too many primitives");
  w.nodes.reserve(nb / (N - 1) + 2);
  int max_depth = 1;
  struct Task {
    std::uint32_t bin, wide;
    int depth;
  };
  std::vector<Task> stack{{0, 0, 1}};
  w.nodes.emplace_back();
  std::vector<std::pair<std::uint32_t, int>> cover;  // (binary node, slots) still to split
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    max_depth = std::max(max_depth, t.depth);
    const BvhNode& root = bin.nodes[t.bin];
    std::uint32_t kids[N];
    int nk = 0;
    cover.clear();
    cover.push_back({root.index + 1, N - split[t.bin]}), cover.push_back({root.index, split[t.bin]});
    while (!cover.empty()) {
      const auto [i, j] = cover.back();
      cover.pop_back();
      const std::uint8_t k = take[i][j];
      if (k == 0) {
        kids[nk++] = i;
      } else {
        const std::uint32_t l = bin.nodes[i].index;
        cover.push_back({l + 1, j - k}), cover.push_back({l, k});
      }
    }
    for (int s = 0; s < nk; ++s) {
      const std::uint32_t i = kids[s];
      const BvhNode& cn = bin.nodes[i];
      std::uint32_t ref = 0;
      std::uint8_t cnt = 0;
      if (as_leaf[i]) {
        const std::uint32_t f = cn.is_leaf() ? cn.index : first[i], n = cn.is_leaf() ? cn.count : size[i];
        if (n <= BvhWide<N>::kMaxLeaf) {
          ref = f, cnt = static_cast<std::uint8_t>(n);
        } else {
          ref = detail::wide_chunk(w, prim_boxes, f, n, t.depth + 1, max_depth);
        }
      } else {
        ref = static_cast<std::uint32_t>(w.nodes.size());
        w.nodes.emplace_back();
        stack.push_back({i, ref, t.depth + 1});
      }
      Node& wn = w.nodes[t.wide];
      wn.set_box(s, cn.box);
      wn.child[s] = ref, wn.count[s] = cnt, wn.valid |= std::uint8_t(1u << s);
    }
  }
  w.nodes.shrink_to_fit();
  w.max_depth = max_depth;
  bin = Bvh{};
  return w;
}

/// The collapse `how` chooses (bvh_collapse_choice): collapse_wide_sah or collapse_wide.
template <int N>
[[nodiscard]] BvhWide<N> collapse_wide_as(Bvh&& bin, std::span<const BvhBox> prim_boxes, BvhCollapse how,
                                          const BvhCollapseCosts& c = {}) {
  if (bvh_collapse_choice(how) == BvhCollapse::sah) return collapse_wide_sah<N>(std::move(bin), prim_boxes, c);
  return collapse_wide<N>(std::move(bin), prim_boxes);
}

}  // namespace rayproof
