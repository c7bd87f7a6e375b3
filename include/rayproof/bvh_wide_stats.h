#pragma once
/// Shape measures of a wide tree (bvh_wide.h, bvh_wide_sah.h): the expected cost in
/// collapse_wide_sah's model and the children per node. For tests and benchmarks (tree_stats).
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide_sah.h"

namespace rayproof {

/// The expected cost of a wide tree in collapse_wide_sah's model, relative to its root's area: the
/// root's visit, then each inner child's node_cost and each leaf's groups at group_cost, weighted
/// by the child box's half area over the root's (0 for an empty tree).
template <int N>
[[nodiscard]] double wide_sah_cost(const BvhWide<N>& w, const BvhCollapseCosts& c = {}) {
  if (w.empty()) return 0;
  BvhBox all;
  for (int i = 0; i < N; ++i)
    if (w.nodes[0].valid >> i & 1) all.extend(w.nodes[0].box(i));
  const double root = all.half_area() > 0 ? double(all.half_area()) : 1.0;
  const std::uint32_t g = std::max<std::uint32_t>(1, c.leaf_group);
  double cost = c.node_cost;
  for (const auto& n : w.nodes)
    for (int i = 0; i < N; ++i) {
      if (!(n.valid >> i & 1)) continue;
      const double a = double(n.box(i).half_area()) / root;
      cost += n.count[i] ? a * double((n.count[i] + g - 1) / g) * c.group_cost : a * c.node_cost;
    }
  return cost;
}

/// Children per node of a wide tree (0 for an empty tree).
template <int N>
[[nodiscard]] double wide_fullness(const BvhWide<N>& w) {
  std::size_t used = 0;
  for (const auto& n : w.nodes) used += std::size_t(__builtin_popcount(n.valid));
  return w.nodes.empty() ? 0.0 : double(used) / double(w.nodes.size());
}

}  // namespace rayproof
