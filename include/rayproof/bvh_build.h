#pragma once
/// BVH builders behind one front door, build_bvh(bounds, centers, BvhBuilder):
///  - median: the worked problems' builder. Split the node across the longest axis of its box at
///    the median primitive centroid, so both halves hold the same count (a balanced tree).
///  - sah: binned surface area heuristic (Wald 2007, "On fast construction of SAH-based BVHs"):
///    16 bins over the centroid bounds per axis (8 below 64 primitives, 4 below 16), the split of
///    least cost C = 2 + (A_l N_l + A_r N_r) / A, or a leaf when that is not cheaper than N. The
///    traversal cost 2 counts the two child box tests each inner node costs (bvh_traverse.h); it
///    also keeps leaves at 2-4 primitives, which halves the node memory of a cost of 1 (and keeps
///    the collapsed four-wide tree of bvh_wide.h within 64 bytes per triangle with its records).
/// Both work in place on one array of primitive references (bounds, center, id) partitioned node by
/// node: per SAH node one pass bins all three axes (SSE, two interleaved bin sets) and one
/// partitions, gathering both children's bounds and centroid bounds on the way (only the root and
/// median nodes take a separate bounds pass); no allocation per node. Both are iterative and never
/// produce an empty child.
/// Parallel build: the caller passes `for_each(n, f)` that may run f(0) .. f(n-1) concurrently
/// (bvh_build.h stays dependency-free; the scene layer passes TBB). The top of the tree is built
/// sequentially; subtrees below kParallelGrain primitives are built independently, then spliced.
#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <cstdint>
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

/// One primitive during the build: its bounds, split center and number.
struct PrimRef {
  BvhBox box;
  float c[3];
  std::uint32_t id;
};

struct NodeBounds {
  BvhBox box, centers;
};

struct BuildTask {
  std::uint32_t node, begin, end;
  bool have_bounds = false;  ///< `bounds` already computed (by the parent's partition)
  NodeBounds bounds{};
};

inline NodeBounds bounds_of(std::span<const PrimRef> refs) {
  NodeBounds nb;
  for (const PrimRef& r : refs) {
    nb.box.extend(r.box);
    for (int k = 0; k < 3; ++k) {
      nb.centers.lo[k] = r.c[k] < nb.centers.lo[k] ? r.c[k] : nb.centers.lo[k];
      nb.centers.hi[k] = r.c[k] > nb.centers.hi[k] ? r.c[k] : nb.centers.hi[k];
    }
  }
  return nb;
}

/// Four-lane views of a reference's box and center (lane 3 is ignored: it holds the next field).
inline __m128 ref_lo(const PrimRef& r) { return _mm_loadu_ps(r.box.lo); }
inline __m128 ref_hi(const PrimRef& r) { return _mm_loadu_ps(r.box.hi); }
inline __m128 ref_c(const PrimRef& r) { return _mm_loadu_ps(r.c); }

/// Running bounds of boxes and centers in SSE registers.
struct Bounds4 {
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity()), hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  __m128 clo = lo, chi = hi;
  void add(const PrimRef& r) {
    lo = _mm_min_ps(lo, ref_lo(r)), hi = _mm_max_ps(hi, ref_hi(r));
    const __m128 c = ref_c(r);
    clo = _mm_min_ps(clo, c), chi = _mm_max_ps(chi, c);
  }
  [[nodiscard]] NodeBounds get() const {
    alignas(16) float a[4], b[4], c[4], d[4];
    _mm_store_ps(a, lo), _mm_store_ps(b, hi), _mm_store_ps(c, clo), _mm_store_ps(d, chi);
    NodeBounds nb;
    for (int k = 0; k < 3; ++k) nb.box.lo[k] = a[k], nb.box.hi[k] = b[k], nb.centers.lo[k] = c[k], nb.centers.hi[k] = d[k];
    return nb;
  }
};

/// The binned SAH split of refs (partitioned in place): the size of the left part, or refs.size()
/// when a leaf is cheaper. When it splits by bins, the partition pass also gathers both children's
/// bounds into `left_nb` / `right_nb` and sets `have_children_bounds`.
inline std::size_t sah_split(std::span<PrimRef> refs, const NodeBounds& nb, std::uint32_t max_leaf, NodeBounds& left_nb,
                             NodeBounds& right_nb, bool& have_children_bounds) {
  constexpr int kMaxBins = 16;
  have_children_bounds = false;
  const std::size_t n = refs.size();
  // Fewer bins for small nodes (the bins' set-up and sweeps would cost more than the binning).
  const int bins = n >= 64 ? kMaxBins : (n >= 16 ? 8 : 4);
  alignas(16) float scale[4] = {0, 0, 0, 0};
  alignas(16) float origin[4] = {nb.centers.lo[0], nb.centers.lo[1], nb.centers.lo[2], 0};
  for (int k = 0; k < 3; ++k) {
    const float extent = nb.centers.hi[k] - nb.centers.lo[k];
    const float sc = extent > 0.0f ? bins / extent : 0.0f;
    scale[k] = sc <= std::numeric_limits<float>::max() ? sc : 0.0f;  // an overflowing scale: no bins
  }
  // Bin of a center per axis: (c - lo) * scale in [0, bins] up to rounding, clamped to [0, bins - 1]
  // (NaN: 0). The scalar form below computes the same float operations as the four lanes.
  const __m128 v_origin = _mm_load_ps(origin), v_scale = _mm_load_ps(scale);
  const __m128 v_zero = _mm_setzero_ps(), v_top = _mm_set1_ps(float(bins - 1));
  auto bins_of = [&](const PrimRef& r) {
    const __m128 x = _mm_mul_ps(_mm_sub_ps(ref_c(r), v_origin), v_scale);
    return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(x, v_zero), v_top));
  };
  auto bin_of = [&](const PrimRef& r, int k) {
    const float x = (r.c[k] - origin[k]) * scale[k];
    const float y = x > 0.0f ? x : 0.0f;  // NaN: 0, as _mm_max_ps(x, 0)
    return static_cast<int>(y < float(bins - 1) ? y : float(bins - 1));
  };
  // One pass bins all three axes; two sets of bins (even and odd references) halve the chains of
  // read-modify-writes on the same bin, merged afterwards.
  __m128 bin_lo[2][3][kMaxBins], bin_hi[2][3][kMaxBins];
  std::uint32_t bin_count[2][3][kMaxBins] = {};
  for (int s2 = 0; s2 < 2; ++s2)
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < bins; ++b)
        bin_lo[s2][k][b] = _mm_set1_ps(std::numeric_limits<float>::infinity()),
        bin_hi[s2][k][b] = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  auto bin_one = [&](const PrimRef& r, int set) {
    alignas(16) std::int32_t b[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(b), bins_of(r));
    const __m128 lo = ref_lo(r), hi = ref_hi(r);
    for (int k = 0; k < 3; ++k) {
      bin_lo[set][k][b[k]] = _mm_min_ps(bin_lo[set][k][b[k]], lo);
      bin_hi[set][k][b[k]] = _mm_max_ps(bin_hi[set][k][b[k]], hi);
      ++bin_count[set][k][b[k]];
    }
  };
  std::size_t ri = 0;
  for (; ri + 1 < n; ri += 2) bin_one(refs[ri], 0), bin_one(refs[ri + 1], 1);
  if (ri < n) bin_one(refs[ri], 0);
  for (int k = 0; k < 3; ++k)
    for (int b = 0; b < bins; ++b)
      bin_lo[0][k][b] = _mm_min_ps(bin_lo[0][k][b], bin_lo[1][k][b]), bin_hi[0][k][b] = _mm_max_ps(bin_hi[0][k][b], bin_hi[1][k][b]),
      bin_count[0][k][b] += bin_count[1][k][b];
  auto half_area = [](__m128 lo, __m128 hi) {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo), _mm_store_ps(h, hi);
    BvhBox bb;
    for (int k = 0; k < 3; ++k) bb.lo[k] = l[k], bb.hi[k] = h[k];
    return bb.half_area();
  };
  float best_cost = std::numeric_limits<float>::infinity();
  int best_axis = -1, best_bin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (scale[axis] == 0.0f) continue;
    // Sweep from the right to get the right-side areas, then from the left for the costs.
    std::array<float, kMaxBins> right_area{};
    std::array<std::uint32_t, kMaxBins> right_count{};
    __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity()), hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    std::uint32_t cnt = 0;
    for (int b = bins - 1; b > 0; --b) {
      lo = _mm_min_ps(lo, bin_lo[0][axis][b]), hi = _mm_max_ps(hi, bin_hi[0][axis][b]), cnt += bin_count[0][axis][b];
      right_area[b] = half_area(lo, hi), right_count[b] = cnt;
    }
    lo = _mm_set1_ps(std::numeric_limits<float>::infinity()), hi = _mm_set1_ps(-std::numeric_limits<float>::infinity()), cnt = 0;
    for (int b = 0; b < bins - 1; ++b) {
      lo = _mm_min_ps(lo, bin_lo[0][axis][b]), hi = _mm_max_ps(hi, bin_hi[0][axis][b]), cnt += bin_count[0][axis][b];
      if (cnt == 0 || right_count[b + 1] == 0) continue;
      const float cost = half_area(lo, hi) * cnt + right_area[b + 1] * right_count[b + 1];
      if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
    }
  }
  const float area = nb.box.half_area();
  const float leaf_cost = static_cast<float>(n);
  const float split_cost = area > 0.0f ? 2.0f + best_cost / area : std::numeric_limits<float>::infinity();
  if (best_axis < 0 || split_cost >= leaf_cost) {
    if (n <= 2 * max_leaf) return n;
    // Forced split (coincident centroids or a poor split on a big node): by halves.
    return n / 2;
  }
  // Partition (two pointers), gathering both sides' bounds on the way.
  Bounds4 left, right;
  std::size_t i = 0, j = n;
  for (;;) {
    while (i < j && bin_of(refs[i], best_axis) <= best_bin) left.add(refs[i++]);
    while (i < j && bin_of(refs[j - 1], best_axis) > best_bin) right.add(refs[--j]);
    if (i >= j) break;
    std::swap(refs[i], refs[j - 1]);
    left.add(refs[i++]), right.add(refs[--j]);
  }
  left_nb = left.get(), right_nb = right.get();
  have_children_bounds = true;
  return i;
}

/// Median split along the longest axis of the node's box.
inline std::size_t median_split(std::span<PrimRef> refs, const NodeBounds& nb, std::uint32_t max_leaf) {
  if (refs.size() <= max_leaf) return refs.size();
  const int axis = nb.box.longest_axis();
  const std::size_t mid = refs.size() / 2;
  std::nth_element(refs.begin(), refs.begin() + mid, refs.end(),
                   [&](const PrimRef& a, const PrimRef& b) { return a.c[axis] < b.c[axis]; });
  return mid;
}

/// Builds the subtree of refs[t.begin, t.end) into `nodes`, whose entry t.node is its (already
/// allocated) root. Pairs are appended at even indices (nodes.size() must be even). Tasks of at
/// most `defer_below` primitives other than the first are left as leaves-to-be and listed in
/// `deferred` (0: build everything here).
template <class Nodes>
void build_range(Nodes& nodes, std::span<PrimRef> refs, BuildTask root, const BvhBuildOptions& opt,
                 std::uint32_t defer_below, std::vector<BuildTask>* deferred) {
  const std::uint32_t max_leaf = std::max<std::uint32_t>(1, opt.max_leaf);
  std::vector<BuildTask> stack{root};
  while (!stack.empty()) {
    const BuildTask t = stack.back();
    stack.pop_back();
    if (deferred && t.end - t.begin <= defer_below && t.node != root.node) {
      deferred->push_back(t);
      continue;
    }
    const std::span<PrimRef> r = refs.subspan(t.begin, t.end - t.begin);
    const NodeBounds nb = t.have_bounds ? t.bounds : bounds_of(r);
    nodes[t.node].box = nb.box;
    NodeBounds left_nb, right_nb;
    bool have_children = false;
    const std::size_t left_n = opt.builder == BvhBuilder::sah ? sah_split(r, nb, max_leaf, left_nb, right_nb, have_children)
                                                              : median_split(r, nb, max_leaf);
    if (left_n == 0 || left_n == r.size()) {
      nodes[t.node].index = t.begin;
      nodes[t.node].count = t.end - t.begin;
      continue;
    }
    const auto mid = t.begin + static_cast<std::uint32_t>(left_n);
    const auto left = static_cast<std::uint32_t>(nodes.size());
    nodes[t.node].index = left;
    nodes[t.node].count = 0;
    nodes.emplace_back();
    nodes.emplace_back();
    stack.push_back({left + 1, mid, t.end, have_children, right_nb});
    stack.push_back({left, t.begin, mid, have_children, left_nb});
  }
}

/// Subtrees of fewer primitives than this are built in parallel, each into its own node array.
inline constexpr std::uint32_t kParallelGrain = 1u << 14;

struct Sequential {
  template <class F>
  void operator()(std::size_t n, F&& f) const {
    for (std::size_t i = 0; i < n; ++i) f(i);
  }
};

}  // namespace detail

/// Builds a BVH over primitives with the given bounds and centers (the builders' split keys:
/// triangle centroids for meshes). Bounds must not be empty. `for_each(n, f)` may run f(i) for
/// i < n concurrently (default: in order on this thread).
template <class ForEach = detail::Sequential>
[[nodiscard]] Bvh build_bvh(std::span<const BvhBox> bounds, std::span<const Vec3<float>> centers,
                            const BvhBuildOptions& opt = {}, ForEach&& for_each = {}) {
  using detail::BuildTask;
  using detail::PrimRef;
  Bvh bvh;
  const auto n = static_cast<std::uint32_t>(bounds.size());
  if (n == 0) return bvh;
  std::vector<PrimRef> refs(n);
  for (std::uint32_t i = 0; i < n; ++i) refs[i] = {bounds[i], {centers[i].x, centers[i].y, centers[i].z}, i};
  const std::uint32_t max_leaf = std::max<std::uint32_t>(1, opt.max_leaf);
  bvh.nodes.reserve(2 * static_cast<std::size_t>(n) / std::max<std::uint32_t>(1, max_leaf / 2) + 2);
  bvh.nodes.resize(2);  // the root, and its copy that puts the pairs at even indices
  const bool parallel = n > 2 * detail::kParallelGrain;
  std::vector<BuildTask> deferred;
  detail::build_range(bvh.nodes, refs, {0, 0, n}, opt, detail::kParallelGrain, parallel ? &deferred : nullptr);
  if (!deferred.empty()) {
    // Each deferred subtree: local root at 0, its copy at 1, pairs from 2; spliced at an even base.
    using Nodes = decltype(bvh.nodes);
    std::vector<Nodes> sub(deferred.size());
    for_each(deferred.size(), [&](std::size_t i) {
      sub[i].resize(2);
      detail::build_range(sub[i], refs, {0, deferred[i].begin, deferred[i].end, deferred[i].have_bounds, deferred[i].bounds}, opt, 0, nullptr);
    });
    for (std::size_t i = 0; i < deferred.size(); ++i) {
      const auto base = static_cast<std::uint32_t>(bvh.nodes.size()) - 2;  // local index j >= 2 lands at base + j
      BvhNode root = sub[i][0];
      if (!root.is_leaf()) root.index += base;
      bvh.nodes[deferred[i].node] = root;
      for (std::size_t j = 2; j < sub[i].size(); ++j) {
        BvhNode nd = sub[i][j];
        if (!nd.is_leaf()) nd.index += base;
        bvh.nodes.push_back(nd);
      }
      Nodes().swap(sub[i]);
    }
  }
  if (bvh.nodes[0].is_leaf()) {
    bvh.nodes.resize(1);
  } else {
    bvh.nodes[1] = bvh.nodes[0];
  }
  bvh.nodes.shrink_to_fit();
  bvh.prim_ids.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) bvh.prim_ids[i] = refs[i].id;
  bvh.max_depth = bvh.depth();
  return bvh;
}

}  // namespace rayproof
