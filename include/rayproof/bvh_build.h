#pragma once
/// BVH builders behind one front door, build_bvh(bounds, centers, BvhBuilder):
///  - median: the worked problems' builder. Split the node across the longest axis of its box at
///    the median primitive centroid, so both halves hold the same count (a balanced tree).
///  - sah: binned surface area heuristic (Wald 2007, "On fast construction of SAH-based BVHs"):
///    16 bins over the centroid bounds per axis, the split of least cost
///    C = 2 + (A_l N_l + A_r N_r) / A, or a leaf when that is not cheaper than N. The traversal
///    cost 2 counts the two child box tests each inner node costs (bvh_traverse.h); it also keeps
///    leaves at 2-4 primitives, which halves the node memory of a cost of 1.
/// Both are iterative (no recursion depth limit) and never produce an empty child.
#include <algorithm>
#include <array>
#include <numeric>
#include <span>

#include "rayproof/bvh.h"

namespace rayproof {

enum class BvhBuilder { median, sah };

struct BvhBuildOptions {
  BvhBuilder builder = BvhBuilder::sah;
  std::uint32_t max_leaf = 4;  ///< median: split above this; sah: forced split above 2 * max_leaf
};

namespace detail {

struct BuildTask {
  std::uint32_t node, begin, end;
};

/// Finalizes `node` over prim_ids[begin, end): its bounds and, when it is a leaf, its range.
inline void make_bounds(Bvh& bvh, std::span<const BvhBox> bounds, const BuildTask& t) {
  BvhBox b;
  for (std::uint32_t i = t.begin; i < t.end; ++i) b.extend(bounds[bvh.prim_ids[i]]);
  bvh.nodes[t.node].box = b;
}

/// The binned SAH split position of prim_ids[begin, end), or end when a leaf is cheaper.
inline std::uint32_t sah_split(Bvh& bvh, std::span<const BvhBox> bounds, std::span<const Vec3<float>> centers,
                               const BuildTask& t, std::uint32_t max_leaf) {
  constexpr int kBins = 16;
  const std::uint32_t n = t.end - t.begin;
  BvhBox cb;  // centroid bounds
  for (std::uint32_t i = t.begin; i < t.end; ++i) {
    const auto& c = centers[bvh.prim_ids[i]];
    for (int k = 0; k < 3; ++k) cb.lo[k] = std::fmin(cb.lo[k], c[k]), cb.hi[k] = std::fmax(cb.hi[k], c[k]);
  }
  float best_cost = std::numeric_limits<float>::infinity();
  int best_axis = -1, best_bin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const float extent = cb.hi[axis] - cb.lo[axis];
    if (!(extent > 0.0f)) continue;
    const float scale = kBins / extent;
    std::array<BvhBox, kBins> bin_box;
    std::array<std::uint32_t, kBins> bin_count{};
    for (std::uint32_t i = t.begin; i < t.end; ++i) {
      const std::uint32_t p = bvh.prim_ids[i];
      const int b = std::min(kBins - 1, static_cast<int>((centers[p][axis] - cb.lo[axis]) * scale));
      bin_box[b].extend(bounds[p]);
      ++bin_count[b];
    }
    // Sweep from the right to get the right-side areas, then from the left for the costs.
    std::array<float, kBins> right_area{};
    std::array<std::uint32_t, kBins> right_count{};
    BvhBox acc;
    std::uint32_t cnt = 0;
    for (int b = kBins - 1; b > 0; --b) {
      acc.extend(bin_box[b]), cnt += bin_count[b];
      right_area[b] = acc.half_area(), right_count[b] = cnt;
    }
    acc = BvhBox{}, cnt = 0;
    for (int b = 0; b < kBins - 1; ++b) {
      acc.extend(bin_box[b]), cnt += bin_count[b];
      if (cnt == 0 || right_count[b + 1] == 0) continue;
      const float cost = acc.half_area() * cnt + right_area[b + 1] * right_count[b + 1];
      if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
    }
  }
  const float area = bvh.nodes[t.node].box.half_area();
  const float leaf_cost = static_cast<float>(n);
  const float split_cost = area > 0.0f ? 2.0f + best_cost / area : std::numeric_limits<float>::infinity();
  if (best_axis < 0 || split_cost >= leaf_cost) {
    if (n <= 2 * max_leaf) return t.end;
    // Forced split (coincident centroids or a poor split on a big node): by index halves.
    return t.begin + n / 2;
  }
  const float scale = kBins / (cb.hi[best_axis] - cb.lo[best_axis]);
  auto* first = bvh.prim_ids.data() + t.begin;
  auto* mid = std::partition(first, bvh.prim_ids.data() + t.end, [&](std::uint32_t p) {
    return std::min(kBins - 1, static_cast<int>((centers[p][best_axis] - cb.lo[best_axis]) * scale)) <= best_bin;
  });
  return static_cast<std::uint32_t>(mid - bvh.prim_ids.data());
}

/// Median split of prim_ids[begin, end) along the longest axis of the node's box.
inline std::uint32_t median_split(Bvh& bvh, std::span<const Vec3<float>> centers, const BuildTask& t,
                                  std::uint32_t max_leaf) {
  if (t.end - t.begin <= max_leaf) return t.end;
  const int axis = bvh.nodes[t.node].box.longest_axis();
  const std::uint32_t mid = t.begin + (t.end - t.begin) / 2;
  auto* ids = bvh.prim_ids.data();
  std::nth_element(ids + t.begin, ids + mid, ids + t.end,
                   [&](std::uint32_t a, std::uint32_t b) { return centers[a][axis] < centers[b][axis]; });
  return mid;
}

}  // namespace detail

/// Builds a BVH over primitives with the given bounds and centers (the builders' split keys:
/// triangle centroids for meshes). Bounds must not be empty.
[[nodiscard]] inline Bvh build_bvh(std::span<const BvhBox> bounds, std::span<const Vec3<float>> centers,
                                   const BvhBuildOptions& opt = {}) {
  Bvh bvh;
  const auto n = static_cast<std::uint32_t>(bounds.size());
  if (n == 0) return bvh;
  const std::uint32_t max_leaf = std::max<std::uint32_t>(1, opt.max_leaf);
  bvh.prim_ids.resize(n);
  std::iota(bvh.prim_ids.begin(), bvh.prim_ids.end(), 0u);
  bvh.nodes.reserve(2 * static_cast<std::size_t>(n) / std::max<std::uint32_t>(1, max_leaf / 2) + 1);
  bvh.nodes.emplace_back();
  std::vector<detail::BuildTask> stack{{0, 0, n}};
  while (!stack.empty()) {
    const detail::BuildTask t = stack.back();
    stack.pop_back();
    detail::make_bounds(bvh, bounds, t);
    const std::uint32_t mid = opt.builder == BvhBuilder::sah ? detail::sah_split(bvh, bounds, centers, t, max_leaf)
                                                             : detail::median_split(bvh, centers, t, max_leaf);
    if (mid == t.end || mid == t.begin) {
      bvh.nodes[t.node].index = t.begin;
      bvh.nodes[t.node].count = t.end - t.begin;
      continue;
    }
    const auto left = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes[t.node].index = left;
    bvh.nodes[t.node].count = 0;
    bvh.nodes.emplace_back();
    bvh.nodes.emplace_back();
    stack.push_back({left + 1, mid, t.end});
    stack.push_back({left, t.begin, mid});
  }
  bvh.nodes.shrink_to_fit();
  bvh.max_depth = bvh.depth();
  return bvh;
}

}  // namespace rayproof
