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
#include <limits>
#include <numeric>
#include <span>
#include <vector>

#include "rayproof/bvh.h"

namespace rayproof {

enum class BvhBuilder { median, sah };

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
};

/// One group test's cost as the SAH builder uses it (1 when leaf_group is 1).
[[nodiscard]] inline float bvh_group_cost(std::uint32_t leaf_group, float group_cost) {
  if (leaf_group <= 1) return 1.0f;
  return group_cost > 0 ? group_cost : float(leaf_group);
}

namespace detail {

/// One primitive during the build: its bounds, number and split center, each 16-byte aligned.
struct alignas(16) PrimRef {
  float lo[3];
  std::uint32_t id;
  float hi[3];
  float pad_;
  float c[3];
  float pad2_;
};
static_assert(sizeof(PrimRef) == 48);

struct NodeBounds {
  BvhBox box, centers;
};

struct BuildTask {
  std::uint32_t node, begin, end;
  int depth = 1;
  NodeBounds bounds{};
};

/// Four-lane views of a reference's box and center (lane 3 is ignored).
inline __m128 ref_lo(const PrimRef& r) { return _mm_load_ps(r.lo); }
inline __m128 ref_hi(const PrimRef& r) { return _mm_load_ps(r.hi); }
inline __m128 ref_c(const PrimRef& r) { return _mm_load_ps(r.c); }

inline __m128 pos_inf4() { return _mm_set1_ps(std::numeric_limits<float>::infinity()); }
inline __m128 neg_inf4() { return _mm_set1_ps(-std::numeric_limits<float>::infinity()); }

/// Running bounds of boxes and centers in SSE registers.
struct Bounds4 {
  __m128 lo = pos_inf4(), hi = neg_inf4();
  __m128 clo = lo, chi = hi;
  void add(const PrimRef& r) { add(ref_lo(r), ref_hi(r), ref_c(r)); }
  void add(__m128 l, __m128 h, __m128 c) {
    lo = _mm_min_ps(lo, l), hi = _mm_max_ps(hi, h);
    clo = _mm_min_ps(clo, c), chi = _mm_max_ps(chi, c);
  }
  void add(const Bounds4& o) {
    lo = _mm_min_ps(lo, o.lo), hi = _mm_max_ps(hi, o.hi), clo = _mm_min_ps(clo, o.clo), chi = _mm_max_ps(chi, o.chi);
  }
  [[nodiscard]] NodeBounds get() const {
    alignas(16) float a[4], b[4], c[4], d[4];
    _mm_store_ps(a, lo), _mm_store_ps(b, hi), _mm_store_ps(c, clo), _mm_store_ps(d, chi);
    NodeBounds nb;
    for (int k = 0; k < 3; ++k) nb.box.lo[k] = a[k], nb.box.hi[k] = b[k], nb.centers.lo[k] = c[k], nb.centers.hi[k] = d[k];
    return nb;
  }
};

/// Half the surface area of the box [lo, hi] (lanes 0-2; the box must not be empty).
inline float half_area4(__m128 lo, __m128 hi) {
  const __m128 d = _mm_sub_ps(hi, lo);
  const __m128 e = _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1));  // dy dz dx
  const __m128 p = _mm_mul_ps(d, e);                               // dx dy, dy dz, dz dx
  return _mm_cvtss_f32(_mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, 1)), _mm_movehl_ps(p, p)));
}

/// The bins of one node over all three axes: bounds and counts of the references whose center
/// falls in each bin. Two interleaved sets (even and odd references) halve the chains of
/// read-modify-writes on the same bin; merge() folds in another Bins (exact: min, max, sums).
struct Bins {
  static constexpr int kMax = 16;
  int bins = kMax;
  __m128 origin, scale;   ///< bin of center c on axis k: (c - origin) * scale, clamped
  float origin_s[4], scale_s[4];
  __m128 lo[2][3][kMax], hi[2][3][kMax];
  std::uint32_t count[2][3][kMax];

  int sets = 2;  ///< one set below 64 references (its set-up would cost more than it saves)

  Bins(const NodeBounds& nb, std::size_t n) {
    // Fewer bins for small nodes (the bins' set-up and sweeps would cost more than the binning).
    bins = n >= 64 ? kMax : (n >= 16 ? 8 : 4);
    sets = n >= 64 ? 2 : 1;
    for (int k = 0; k < 3; ++k) {
      const float extent = nb.centers.hi[k] - nb.centers.lo[k];
      const float sc = extent > 0.0f ? bins / extent : 0.0f;
      scale_s[k] = sc <= std::numeric_limits<float>::max() ? sc : 0.0f;  // an overflowing scale: no bins
      origin_s[k] = nb.centers.lo[k];
    }
    scale_s[3] = origin_s[3] = 0.0f;
    origin = _mm_loadu_ps(origin_s), scale = _mm_loadu_ps(scale_s);
    for (int s = 0; s < sets; ++s)
      for (int k = 0; k < 3; ++k)
        for (int b = 0; b < bins; ++b) lo[s][k][b] = pos_inf4(), hi[s][k][b] = neg_inf4(), count[s][k][b] = 0;
  }
  /// Bin of a center per axis: (c - lo) * scale in [0, bins] up to rounding, clamped to
  /// [0, bins - 1] (NaN: 0). bin_of computes the same float operations as the four lanes.
  [[nodiscard]] __m128i bins_of(const PrimRef& r) const {
    const __m128 x = _mm_mul_ps(_mm_sub_ps(ref_c(r), origin), scale);
    return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(float(bins - 1))));
  }
  [[nodiscard]] int bin_of(const PrimRef& r, int k) const {
    const float x = (r.c[k] - origin_s[k]) * scale_s[k];
    const float y = x > 0.0f ? x : 0.0f;  // NaN: 0, as _mm_max_ps(x, 0)
    return static_cast<int>(y < float(bins - 1) ? y : float(bins - 1));
  }
  void add(const PrimRef& r, int set) {
    alignas(16) std::int32_t b[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(b), bins_of(r));
    const __m128 l = ref_lo(r), h = ref_hi(r);
    for (int k = 0; k < 3; ++k) {
      lo[set][k][b[k]] = _mm_min_ps(lo[set][k][b[k]], l);
      hi[set][k][b[k]] = _mm_max_ps(hi[set][k][b[k]], h);
      ++count[set][k][b[k]];
    }
  }
  void add(std::span<const PrimRef> refs) {
    std::size_t i = 0;
    if (sets == 2)
      for (; i + 1 < refs.size(); i += 2) add(refs[i], 0), add(refs[i + 1], 1);
    for (; i < refs.size(); ++i) add(refs[i], 0);
  }
  /// Folds set 1 into set 0 (`o` null), or `o`'s set 0 into this set 0 (both folded already).
  void merge(const Bins* o) {
    if (!o && sets == 1) return;
    const int from = o ? 0 : 1;
    if (!o) o = this;
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < bins; ++b) {
        lo[0][k][b] = _mm_min_ps(lo[0][k][b], o->lo[from][k][b]), hi[0][k][b] = _mm_max_ps(hi[0][k][b], o->hi[from][k][b]);
        count[0][k][b] += o->count[from][k][b];
      }
  }
  /// The split of least SAH cost (sum of A N over both sides, N rounded up to a multiple of
  /// `group`) after merge(): axis -1 for none.
  void best(int& best_axis, int& best_bin, float& best_cost, std::uint32_t group = 1, float group_cost = 1) const {
    const auto lanes = [group, group_cost](std::uint32_t c) { return float((c + group - 1) / group) * group_cost; };
    best_cost = std::numeric_limits<float>::infinity(), best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (scale_s[axis] == 0.0f) continue;
      // Sweep from the right to get the right-side areas, then from the left for the costs.
      std::array<float, kMax> right_area{};
      std::array<std::uint32_t, kMax> right_count{};
      __m128 l = pos_inf4(), h = neg_inf4();
      std::uint32_t cnt = 0;
      for (int b = bins - 1; b > 0; --b) {
        l = _mm_min_ps(l, lo[0][axis][b]), h = _mm_max_ps(h, hi[0][axis][b]), cnt += count[0][axis][b];
        right_area[b] = cnt ? half_area4(l, h) : 0.0f, right_count[b] = cnt;
      }
      l = pos_inf4(), h = neg_inf4(), cnt = 0;
      for (int b = 0; b < bins - 1; ++b) {
        l = _mm_min_ps(l, lo[0][axis][b]), h = _mm_max_ps(h, hi[0][axis][b]), cnt += count[0][axis][b];
        if (cnt == 0 || right_count[b + 1] == 0) continue;
        const float cost = half_area4(l, h) * lanes(cnt) + right_area[b + 1] * lanes(right_count[b + 1]);
        if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
      }
    }
  }
};

/// References per chunk when a big node's binning or bounds are split over tasks.
inline constexpr std::size_t kBinChunk = 8192;

/// Bounds of refs (over chunks with for_each when big).
template <class ForEach>
NodeBounds bounds_of(std::span<const PrimRef> refs, ForEach& for_each) {
  const std::size_t chunks = (refs.size() + kBinChunk - 1) / kBinChunk;
  if (chunks <= 1) {
    Bounds4 b;
    for (const PrimRef& r : refs) b.add(r);
    return b.get();
  }
  std::vector<Bounds4> part(chunks);
  for_each(chunks, [&](std::size_t c) {
    const std::size_t b = c * kBinChunk, e = std::min(refs.size(), b + kBinChunk);
    for (std::size_t i = b; i < e; ++i) part[c].add(refs[i]);
  });
  for (std::size_t c = 1; c < chunks; ++c) part[0].add(part[c]);
  return part[0].get();
}

/// Partitions refs in place (two pointers) into those whose center's bin on `axis` is at most
/// `split_bin` and the rest, gathering both sides' bounds; returns the size of the first part.
inline std::size_t partition_range(std::span<PrimRef> refs, const Bins& bn, int axis, int split_bin, Bounds4& left,
                                   Bounds4& right) {
  std::size_t i = 0, j = refs.size();
  for (;;) {
    while (i < j && bn.bin_of(refs[i], axis) <= split_bin) left.add(refs[i++]);
    while (i < j && bn.bin_of(refs[j - 1], axis) > split_bin) right.add(refs[--j]);
    if (i >= j) break;
    // Swap in SSE registers (std::swap's scalar stores stall the vector loads that follow).
    PrimRef& a = refs[i++];
    PrimRef& b = refs[--j];
    const __m128 al = ref_lo(a), ah = ref_hi(a), ac = ref_c(a), bl = ref_lo(b), bh = ref_hi(b), bc = ref_c(b);
    _mm_store_ps(a.lo, bl), _mm_store_ps(a.hi, bh), _mm_store_ps(a.c, bc);
    _mm_store_ps(b.lo, al), _mm_store_ps(b.hi, ah), _mm_store_ps(b.c, ac);
    left.add(bl, bh, bc), right.add(al, ah, ac);
  }
  return i;
}

/// The partition of a big node over its `chunks` fixed chunks (those of the binning), with
/// for_each: each chunk is partitioned in place on its own (partition_range), which leaves
/// [left | right] per chunk; then the right references that lie before the final boundary are
/// swapped with the left ones behind it, the k-th of one with the k-th of the other, in blocks of
/// kBinChunk pairs over for_each. The result depends on the chunks only (fixed by refs.size()),
/// not on the threads or the order the tasks run in.
template <class ForEach>
void partition_chunked(std::span<PrimRef> refs, const Bins& bn, int axis, int split_bin, std::size_t chunks,
                       NodeBounds& left_nb, NodeBounds& right_nb, ForEach& for_each, std::size_t& left_n) {
  const std::size_t n = refs.size();
  auto chunk_begin = [&](std::size_t c) { return c * kBinChunk; };
  auto chunk_end = [&](std::size_t c) { return c + 1 == chunks ? n : (c + 1) * kBinChunk; };
  std::vector<Bounds4> left(chunks), right(chunks);
  std::vector<std::size_t> lefts(chunks);
  for_each(chunks, [&](std::size_t c) {
    lefts[c] = partition_range(refs.subspan(chunk_begin(c), chunk_end(c) - chunk_begin(c)), bn, axis, split_bin,
                               left[c], right[c]);
  });
  std::size_t mid = 0;
  for (std::size_t c = 0; c < chunks; ++c) mid += lefts[c];
  for (std::size_t c = 1; c < chunks; ++c) left[0].add(left[c]), right[0].add(right[c]);
  left_nb = left[0].get(), right_nb = right[0].get();
  left_n = mid;
  // Misplaced: per chunk, its right part within [0, mid) and its left part within [mid, n), as
  // intervals in increasing order; both lists hold the same number of references.
  struct Run {
    std::size_t begin, end;
  };
  std::vector<Run> wrong_right, wrong_left;
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t b = chunk_begin(c), m = b + lefts[c], e = chunk_end(c);
    // Only non-empty runs: the swap loop below steps over one run end at a time.
    if (m < std::min(e, mid)) wrong_right.push_back({m, std::min(e, mid)});
    if (m > std::max(b, mid)) wrong_left.push_back({std::max(b, mid), m});

  }
  std::size_t pairs = 0;
  for (const Run& r : wrong_right) pairs += r.end - r.begin;
  // Position of the k-th misplaced reference in a list of runs.
  auto locate = [](const std::vector<Run>& runs, std::size_t k, std::size_t& run, std::size_t& pos) {
    run = 0;
    while (k >= runs[run].end - runs[run].begin) k -= runs[run].end - runs[run].begin, ++run;
    pos = runs[run].begin + k;
  };
  const std::size_t blocks = (pairs + kBinChunk - 1) / kBinChunk;
  for_each(blocks, [&](std::size_t blk) {
    const std::size_t k0 = blk * kBinChunk, k1 = std::min(pairs, k0 + kBinChunk);
    std::size_t ra, pa, rb, pb;
    locate(wrong_right, k0, ra, pa), locate(wrong_left, k0, rb, pb);
    for (std::size_t k = k0; k < k1; ++k) {
      if (pa == wrong_right[ra].end) pa = wrong_right[++ra].begin;
      if (pb == wrong_left[rb].end) pb = wrong_left[++rb].begin;
      PrimRef& a = refs[pa++];
      PrimRef& b = refs[pb++];
      const __m128 al = ref_lo(a), ah = ref_hi(a), ac = ref_c(a);
      _mm_store_ps(a.lo, ref_lo(b)), _mm_store_ps(a.hi, ref_hi(b)), _mm_store_ps(a.c, ref_c(b));
      _mm_store_ps(b.lo, al), _mm_store_ps(b.hi, ah), _mm_store_ps(b.c, ac);
    }
  });
}

/// Splits refs into halves by center on the centers' widest axis (ties by id; NaN centers
/// first): a total order, so the halves do not depend on the input order. Returns n / 2.
inline std::size_t forced_split(std::span<PrimRef> refs, const NodeBounds& nb) {
  const int axis = nb.centers.longest_axis();
  const std::size_t mid = refs.size() / 2;
  const auto key = [axis](const PrimRef& r) {
    return r.c[axis] == r.c[axis] ? r.c[axis] : -std::numeric_limits<float>::infinity();
  };
  std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(mid), refs.end(), [&](const PrimRef& a, const PrimRef& b) {
    const float ka = key(a), kb = key(b);
    return ka < kb || (ka == kb && a.id < b.id);
  });
  return mid;
}

/// The binned SAH split of refs (partitioned in place): the size of the left part, or refs.size()
/// when a leaf is cheaper. When it splits by bins, the partition pass also gathers both children's
/// bounds into `left_nb` / `right_nb` and sets `have_children_bounds` (a forced split leaves them
/// to the caller). Nodes of more than two chunks are binned over chunks with for_each.
template <class ForEach>
std::size_t sah_split(std::span<PrimRef> refs, const NodeBounds& nb, std::uint32_t max_leaf, std::uint32_t group,
                      float group_cost, NodeBounds& left_nb,
                      NodeBounds& right_nb, bool& have_children_bounds, ForEach& for_each) {
  have_children_bounds = false;
  const std::size_t n = refs.size();
  const std::size_t chunks = n / kBinChunk;
  std::vector<Bins> part;  // per chunk (big nodes only)
  Bins local(nb, n);
  Bins* bins = &local;
  if (chunks >= 2) {
    part.assign(chunks, local);
    for_each(chunks, [&](std::size_t c) {
      const std::size_t b = c * kBinChunk, e = c + 1 == chunks ? n : b + kBinChunk;
      part[c].add(refs.subspan(b, e - b));
      part[c].merge(nullptr);
    });
    for (std::size_t c = 1; c < chunks; ++c) part[0].merge(&part[c]);
    bins = &part[0];
  } else {
    local.add(refs);
    local.merge(nullptr);
  }
  int best_axis, best_bin;
  float best_cost;
  std::size_t i_left = 0;
  bins->best(best_axis, best_bin, best_cost, group, group_cost);
  const float area = nb.box.half_area();
  const float leaf_cost = float((n + group - 1) / group) * group_cost;
  const float split_cost = area > 0.0f ? 2.0f + best_cost / area : std::numeric_limits<float>::infinity();
  if (best_axis < 0 || split_cost >= leaf_cost) {
    if (n <= 2 * max_leaf) return n;
    // Forced split (coincident centers, or a leaf cheaper than any split but too big): the halves
    // by center on the centers' widest axis, ties by id (NaN first), so the halves do not depend
    // on the order the references arrive in (the parallel partition's order differs from the
    // sequential one's).
    return forced_split(refs, nb);
  }
  if (chunks >= 2) {
    partition_chunked(refs, *bins, best_axis, best_bin, chunks, left_nb, right_nb, for_each, i_left);
    have_children_bounds = true;
    return i_left;
  }
  Bounds4 left, right;
  const std::size_t i = partition_range(refs, *bins, best_axis, best_bin, left, right);
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
