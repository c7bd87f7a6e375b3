#pragma once
/// BVH builders behind one front door, build_bvh(bounds, centers, BvhBuilder):
///  - median: the worked problems' builder. Split the node across the longest axis of its box at
///    the median box center, so both halves hold the same count (a balanced tree).
///  - sah: binned surface area heuristic (Wald 2007, "On fast construction of SAH-based BVHs"):
///    16 bins over the bounds of the centers per axis (8 below 64 primitives, 4 below 16), the split of
///    least cost C = 2 + (A_l L(N_l) + A_r L(N_r)) / A, or a leaf when that is not cheaper than L(N),
///    where L(N) = ceil(N / g) c counts the tests of the leaf's groups of g = leaf_group primitives
///    at c = group_cost each (the SIMD leaves test 4 triangles at once, so a leaf of 3 costs as much
///    as one of 4; g = 1: L(N) = N, the plain SAH). The traversal cost 2 counts the two child box
///    tests each inner node costs (bvh_traverse.h). With g = 4, c = 2, on bunny00 and
///    refined_elephant the leaves average 5.2-5.4 triangles (2.8-2.9 with g = 1) and the groups'
///    lanes are 91-93% full (70%).
/// Both split by the centers of the primitives' boxes (on bunny00, refined_elephant and the
/// generated 1.31M-triangle mesh that gave a 1-3% lower SAH cost than triangle centroids).
/// Both work in place on one array of primitive references (bounds, id, center: 48 bytes, three
/// aligned SSE loads) partitioned node by node: per SAH node one pass bins all three axes (two
/// interleaved bin sets from 64 references up) and one partitions, gathering both children's
/// bounds and center bounds on the way; no allocation per node. Both are iterative and never
/// produce an empty child.
///
/// Parallel build: the caller passes `for_each(n, f)` that may run f(0) .. f(n-1) concurrently
/// (bvh_build.h stays dependency-free; the scene layer passes TBB). Nodes of more than
/// parallel_grain(n) primitives (the top of the tree) are split level by level: the nodes of a level
/// concurrently, and each one's binning and partition over fixed chunks of kBinChunk references
/// concurrently (bins merge by min, max and sums: exact, in any order; the partition runs per chunk,
/// then swaps the misplaced pairs, see partition_chunked). Children are numbered in a sequential
/// pass after each level. The subtrees below the grain are then built concurrently, each into its
/// own node array, and copied behind the top at offsets from their sizes. A split the SAH finds not
/// worth it on a node too big for a leaf halves it by center on the widest center axis (ties by
/// id), independent of the references' order. Nothing depends on the
/// number of threads or the order the tasks run in: the tree (nodes, order, prim_ids) is the same
/// for one thread and for many.
#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#include <span>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_build_split.h"  // one node's split: references, bins, partitions

namespace rayproof {

enum class BvhBuilder { median, sah };

/// How a binary tree becomes a wide one (bvh_wide_sah.h): greedy (collapse_wide, bvh_wide.h: open
/// the largest child until the node is full) or the SAH-optimal collapse (collapse_wide_sah);
/// automatic: RAYPROOF_BVH_COLLAPSE, else sah.
enum class BvhCollapse { automatic, greedy, sah };

struct BvhBuildOptions {
  BvhBuilder builder = BvhBuilder::sah;
  std::uint32_t max_leaf = 4;  ///< median: split above this; sah: forced split above 2 * max_leaf
  /// sah: the primitives of a leaf group (the SIMD leaves of scene/leaf_simd.h test 4 triangles at
  /// once). A leaf of n primitives costs ceil(n / leaf_group) group tests of group_cost each, in the
  /// leaf cost and in the binned split cost (as Embree's blocks for its Triangle4 leaves), so the
  /// builder fills groups instead of leaving lanes empty. 1: every primitive costs 1 (the plain
  /// SAH; group_cost is not used).
  std::uint32_t leaf_group = 4;
  /// sah, leaf_group > 1: one group test's cost in the builder's units (an inner node costs 2: two
  /// box tests); 0: leaf_group (each lane as one primitive test). 2, a group as one inner node,
  /// gave leaves of 5.2-5.4 triangles on bunny00 and refined_elephant (4: 3.7) with 91-93% of the
  /// lanes used, 10% fewer bytes and, in `rayproof bench`, equal or better ratios to Embree-robust
  /// than 4 or 1.5.
  float group_cost = 2;
  /// The wide tree's collapse (users of build_bvh alone ignore it; Accel follows it).
  BvhCollapse collapse = BvhCollapse::automatic;
  /// Optional, for Accel: builds the binary tree instead of `builder` from the primitives' boxes
  /// (rounded outwards; a node's box must hold its primitives' boxes) and centres, as build_bvh
  /// returns it (an inner node's children at index and index + 1 after it, leaves of at most
  /// 2 * max_leaf primitives). `rayproof bench --embree-tree` passes Embree's rtcBuildBVH here.
  std::function<Bvh(const std::vector<BvhBox>&, const std::vector<Vec3<float>>&)> binary{};
};

/// One group test's cost as the SAH builder uses it (1 when leaf_group is 1).
[[nodiscard]] inline float bvh_group_cost(std::uint32_t leaf_group, float group_cost) {
  if (leaf_group <= 1) return 1.0f;
  return group_cost > 0 ? group_cost : float(leaf_group);
}

namespace detail {

struct Sequential {
  template <class F>
  void operator()(std::size_t n, F&& f) const {
    for (std::size_t i = 0; i < n; ++i) f(i);
  }
};

/// Splits one node: the size of the left part (0 or refs.size(): a leaf), children's bounds.
template <class ForEach>
std::size_t split_node(std::span<PrimRef> refs, const NodeBounds& nb, const BvhBuildOptions& opt, NodeBounds& left_nb,
                       NodeBounds& right_nb, ForEach& for_each) {
  const std::uint32_t max_leaf = std::max<std::uint32_t>(1, opt.max_leaf);
  bool have_children = false;
  const std::size_t left_n = opt.builder == BvhBuilder::sah
                                 ? sah_split(refs, nb, max_leaf, std::max<std::uint32_t>(1, opt.leaf_group),
                                             bvh_group_cost(opt.leaf_group, opt.group_cost), left_nb, right_nb,
                                             have_children, for_each)
                                 : median_split(refs, nb, max_leaf);
  if (left_n != 0 && left_n != refs.size() && !have_children) {
    left_nb = bounds_of(refs.first(left_n), for_each);
    right_nb = bounds_of(refs.subspan(left_n), for_each);
  }
  return left_n;
}

/// Builds the subtree of refs[t.begin, t.end) into `nodes`, whose entry t.node is its (already
/// allocated) root with bounds t.bounds. Pairs are appended at even indices (nodes.size() must be
/// even). Returns the depth of its deepest leaf.
template <class Nodes>
int build_range(Nodes& nodes, std::span<PrimRef> refs, const BuildTask& root, const BvhBuildOptions& opt) {
  Sequential seq;
  int max_depth = 0;
  std::vector<BuildTask> stack{root};
  while (!stack.empty()) {
    const BuildTask t = stack.back();
    stack.pop_back();
    const std::span<PrimRef> r = refs.subspan(t.begin, t.end - t.begin);
    nodes[t.node].box = t.bounds.box;
    NodeBounds left_nb, right_nb;
    const std::size_t left_n = split_node(r, t.bounds, opt, left_nb, right_nb, seq);
    if (left_n == 0 || left_n == r.size()) {
      nodes[t.node].index = t.begin;
      nodes[t.node].count = t.end - t.begin;
      max_depth = std::max(max_depth, t.depth);
      continue;
    }
    const auto mid = t.begin + static_cast<std::uint32_t>(left_n);
    const auto left = static_cast<std::uint32_t>(nodes.size());
    nodes[t.node].index = left;
    nodes[t.node].count = 0;
    nodes.emplace_back();
    nodes.emplace_back();
    stack.push_back({left + 1, mid, t.end, t.depth + 1, right_nb});
    stack.push_back({left, t.begin, mid, t.depth + 1, left_nb});
  }
  return max_depth;
}

/// Nodes of more primitives than this are split level by level with the work spread over tasks;
/// subtrees of at most this many are built as one task each.
inline constexpr std::uint32_t kParallelGrain = 1u << 14;
/// The grain for n primitives: n / 32 within [4096, kParallelGrain], so that a small mesh still
/// gives some 32 subtree tasks to balance over the threads and a big one not too many (it
/// depends on n only: the tree does not depend on the threads).
inline std::uint32_t parallel_grain(std::uint32_t n) { return std::clamp<std::uint32_t>(n / 32, 4096, kParallelGrain); }

}  // namespace detail

/// Builds a BVH over primitives with the given bounds. Bounds must not be empty. `centers` is
/// kept for source compatibility and not read (the builders split by box centers; see above). `for_each(n, f)` may run f(i) for
/// i < n concurrently (default: in order on this thread); the tree does not depend on it.
template <class ForEach = detail::Sequential>
[[nodiscard]] Bvh build_bvh(std::span<const BvhBox> bounds, [[maybe_unused]] std::span<const Vec3<float>> centers,
                            const BvhBuildOptions& opt = {}, ForEach&& for_each = {}) {
  using detail::BuildTask;
  using detail::PrimRef;
  using Nodes = decltype(Bvh::nodes);
  Bvh bvh;
  const auto n = static_cast<std::uint32_t>(bounds.size());
  if (n == 0) return bvh;
  std::vector<PrimRef> refs(n);
  const std::size_t ref_chunks = (n + detail::kBinChunk - 1) / detail::kBinChunk;
  for_each(ref_chunks, [&](std::size_t c) {
    const std::size_t e = std::min<std::size_t>(n, (c + 1) * detail::kBinChunk);
    for (std::size_t i = c * detail::kBinChunk; i < e; ++i) {
      PrimRef& r = refs[i];
      const BvhBox& b = bounds[i];
      // Halves first: no overflow near the float range's ends.
      r = {{b.lo[0], b.lo[1], b.lo[2]}, std::uint32_t(i), {b.hi[0], b.hi[1], b.hi[2]}, 0.0f,
           {b.lo[0] * 0.5f + b.hi[0] * 0.5f, b.lo[1] * 0.5f + b.hi[1] * 0.5f, b.lo[2] * 0.5f + b.hi[2] * 0.5f}, 0.0f};
    }
  });
  const std::uint32_t max_leaf = std::max<std::uint32_t>(1, opt.max_leaf);
  bvh.nodes.reserve(2 * static_cast<std::size_t>(n) / std::max<std::uint32_t>(1, max_leaf / 2) + 2);
  bvh.nodes.resize(2);  // the root, and its copy that puts the pairs at even indices
  const BuildTask root{0, 0, n, 1, detail::bounds_of(std::span<const PrimRef>(refs), for_each)};
  int max_depth = 0;
  const std::uint32_t grain = detail::parallel_grain(n);
  if (n <= grain) {
    max_depth = detail::build_range(bvh.nodes, refs, root, opt);
  } else {
    // The top, level by level: each level's nodes split concurrently, then numbered in order.
    std::vector<BuildTask> level{root}, deferred;
    struct Result {
      std::size_t left_n = 0;
      detail::NodeBounds l, r;
    };
    while (!level.empty()) {
      std::vector<Result> res(level.size());
      for_each(level.size(), [&](std::size_t i) {
        const BuildTask& t = level[i];
        res[i].left_n = detail::split_node(std::span<PrimRef>(refs).subspan(t.begin, t.end - t.begin), t.bounds, opt,
                                           res[i].l, res[i].r, for_each);
      });
      std::vector<BuildTask> next;
      for (std::size_t i = 0; i < level.size(); ++i) {
        const BuildTask& t = level[i];
        BvhNode& node = bvh.nodes[t.node];
        node.box = t.bounds.box;
        if (res[i].left_n == 0 || res[i].left_n == t.end - t.begin) {
          node.index = t.begin, node.count = t.end - t.begin;
          max_depth = std::max(max_depth, t.depth);
          continue;
        }
        const auto left = static_cast<std::uint32_t>(bvh.nodes.size());
        const auto mid = t.begin + static_cast<std::uint32_t>(res[i].left_n);
        node.index = left, node.count = 0;
        bvh.nodes.emplace_back(), bvh.nodes.emplace_back();
        for (const BuildTask& c : {BuildTask{left, t.begin, mid, t.depth + 1, res[i].l},
                                   BuildTask{left + 1, mid, t.end, t.depth + 1, res[i].r}})
          (c.end - c.begin > grain ? next : deferred).push_back(c);
      }
      level.swap(next);
    }
    // The subtrees below the grain: each into its own array (local root at 0, its copy at 1,
    // pairs from 2), then copied behind the top at offsets from their sizes.
    std::vector<Nodes> sub(deferred.size());
    std::vector<int> depth(deferred.size());
    for_each(deferred.size(), [&](std::size_t i) {
      BuildTask t = deferred[i];
      t.node = 0;
      sub[i].reserve(2 * std::size_t(t.end - t.begin) / std::max<std::uint32_t>(1, max_leaf / 2) + 2);
      sub[i].resize(2);
      depth[i] = detail::build_range(sub[i], refs, t, opt);
    });
    std::vector<std::size_t> base(deferred.size() + 1, bvh.nodes.size());
    for (std::size_t i = 0; i < deferred.size(); ++i) {
      base[i + 1] = base[i] + (sub[i].size() - 2);
      max_depth = std::max(max_depth, depth[i]);
    }
    bvh.nodes.resize(base.back());
    for_each(deferred.size(), [&](std::size_t i) {
      const auto shift = static_cast<std::uint32_t>(base[i] - 2);  // local index j >= 2 lands at base + j - 2
      BvhNode root_node = sub[i][0];
      if (!root_node.is_leaf()) root_node.index += shift;
      bvh.nodes[deferred[i].node] = root_node;
      for (std::size_t j = 2; j < sub[i].size(); ++j) {
        BvhNode nd = sub[i][j];
        if (!nd.is_leaf()) nd.index += shift;
        bvh.nodes[base[i] + j - 2] = nd;
      }
      Nodes().swap(sub[i]);
    });
  }
  if (bvh.nodes[0].is_leaf()) {
    bvh.nodes.resize(1);
  } else {
    bvh.nodes[1] = bvh.nodes[0];
  }
  bvh.nodes.shrink_to_fit();
  bvh.prim_ids.resize(n);
  for_each(ref_chunks, [&](std::size_t c) {
    const std::size_t e = std::min<std::size_t>(n, (c + 1) * detail::kBinChunk);
    for (std::size_t i = c * detail::kBinChunk; i < e; ++i) bvh.prim_ids[i] = refs[i].id;
  });
  bvh.max_depth = max_depth;
  return bvh;
}

/// The SAH cost of a binary BVH, in the builder's units: each inner node 2 (two child box tests),
/// each leaf ceil(count / leaf_group) groups of bvh_group_cost(leaf_group, group_cost) (leaf_group
/// 1: its primitive count), weighted by the node's area relative to the root's (nodes[1], the
/// root's copy, not counted). 0 for an empty tree.
[[nodiscard]] inline double bvh_sah_cost(const Bvh& bvh, std::uint32_t leaf_group = 1, float group_cost = 0) {
  if (bvh.nodes.empty()) return 0.0;
  const std::uint32_t g = std::max<std::uint32_t>(1, leaf_group);
  const double gc = bvh_group_cost(g, group_cost);
  const auto lanes = [g, gc](std::uint32_t c) { return double((c + g - 1) / g) * gc; };
  const double root = bvh.nodes[0].box.half_area();
  if (!(root > 0.0)) return bvh.nodes[0].is_leaf() ? lanes(bvh.nodes[0].count) : 0.0;
  double cost = 0.0;
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    if (i == 1) continue;
    const BvhNode& n = bvh.nodes[i];
    cost += n.box.half_area() / root * (n.is_leaf() ? lanes(n.count) : 2.0);
  }
  return cost;
}

}  // namespace rayproof
