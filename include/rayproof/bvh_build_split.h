#pragma once
/// One node's split for the BVH builders of bvh_build.h: the primitive references (PrimRef), the
/// binned SAH split (bins of all three axes in one pass, the partition, in place or over fixed
/// chunks of kBinChunk references in parallel), the forced split by center and the median split.
/// The cost model and the parallel scheme are described at bvh_build.h's top.
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

namespace rayproof::detail {

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

}  // namespace rayproof::detail
