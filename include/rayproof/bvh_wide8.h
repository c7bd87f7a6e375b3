#pragma once
/// Eight-wide BVH: the binary tree of bvh_build.h collapsed into nodes of up to eight children whose
/// boxes are tested together in one AVX2 pass. The core is compiled for x86-64 baseline (SSE2): the
/// eight-wide traversal is compiled in functions with `__attribute__((target("avx2")))` and chosen
/// at run time (bvh_simd_path(): the CPU, or the RAYPROOF_SIMD environment variable); the four-wide
/// SSE tree of bvh_wide.h stays the path for CPUs without AVX2.
///
/// Node layout (256 bytes, four cache lines): per axis the eight children's lo then hi planes
/// (structure of arrays, one 256-bit load per plane), then `child`, `count` and `valid` with the
/// meaning they have in Bvh4Node: an inner child is a node index (count 0), a leaf child a range
/// [child, child + count) of prim_ids (count 1..255); unused slots have empty boxes and a clear bit.
///
/// Box tests. The ray is prepared by make_bvh4_ray (bvh_wide.h) and its per-axis floats broadcast
/// to eight lanes; the test then does in each lane exactly the float operations bvh4_test does in
/// each of its four (subtraction, product, max / min, widening, comparison; no FMA: the target is
/// "avx2" without "fma", so nothing is contracted). The conservative guarantee is therefore the
/// four-wide one, restated here:
///  - Per axis k with 1/d_k > 0 the near plane is lo, and its distance is computed from a float
///    o_near >= o_k (the exact origin), the far one from a float o_far <= o_k (mirrored for 1/d_k < 0,
///    including d_k = -0). So before any rounding (lo - o_near) / d_k <= (lo - o_k) / d_k and
///    (hi - o_far) / d_k >= (hi - o_k) / d_k: the exact slab interval of the double ray lies inside the
///    interval of these origins.
///  - The float distance then carries at most four roundings (the difference, the double reciprocal,
///    its rounding to float, the product): |computed - exact| <= gamma(4) |exact| (gamma(n) =
///    n u / (1 - n u), u = 2^-24), plus underflow, bounded absolutely by far less than 2^-120 for
///    the distances that matter (|d| <= 2^64, boxes and origins <= 2^64 after the range check).
///  - The largest near distance is scaled by 1 - 8u (when >= 0) or 1 + 8u (when < 0) and lowered by
///    2^-120; the smallest far distance scaled by 1 + 8u / 1 - 8u and raised by 2^-120 (the constants
///    1 -/+ 8u are exact floats). What must be covered is gamma(4) ~ 4u + 16u^2 of the distance
///    plus the rounding of the scaling product itself (u), about 5u + O(u^2) < 8u; the absolute
///    2^-120 covers underflow, as in bvh_wide.h. The widening is monotonic in float, so
///    widening max_k near_k equals max_k of the widened distances.
///  - tmin is rounded down and tmax up to float; a box passes when widened near <= widened far.
///    Hence every box the exact double segment [tmin, tmax] touches (even at one point) passes.
///  - An axis with d_k = 0 and the origin on a slab plane gives 0 * inf = NaN: vmaxps / vminps return
///    their second operand (the running bound) when either is NaN, so that axis bounds nothing, as
///    the origin lies in the closed slab; the comparison is ordered (false for NaN).
///  - Rays out of the float path's range (NaN, |o| > 2^64, or a nonzero |d| outside [2^-64, 2^64])
///    are traversed with the scalar double box test of bvh_traverse.h (BvhRay::enter) on the same
///    nodes, widened by 2 gamma(3) in double.
///
/// Traversal. Closest hit visits children nearest first (an insertion sort of the hit lanes by
/// entry t) and drops popped entries whose entry t lies beyond the best t so far. Any hit does not
/// sort: it pushes the hit children in slot order and stops at the first leaf that reports a hit.
/// All hits visits every leaf the segment meets.
///
/// Leaves are handed to the caller whole: `leaf_range(first, count)` gets a range of leaf-order
/// slots (indices into prim_ids, or the caller's own leaf-order data) and returns true to stop
/// (honoured for any hit); for closest hit it lowers `tmax` (held by reference) as the per-slot
/// callbacks do. bvh8_traverse_slots / bvh8_traverse are the per-slot and per-primitive forms.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"

namespace rayproof {

struct alignas(64) Bvh8Node {
  float lo[3][8];  ///< lo[axis][child]
  float hi[3][8];  ///< hi[axis][child]
  std::uint32_t child[8] = {};  ///< inner: node index; leaf: first prim_ids entry
  std::uint8_t count[8] = {};   ///< 0: inner child; else primitives in the leaf
  std::uint8_t valid = 0;       ///< bit i: slot i is used
  std::uint8_t pad_[23] = {};

  Bvh8Node() {
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 8; ++i) lo[k][i] = std::numeric_limits<float>::infinity(), hi[k][i] = -std::numeric_limits<float>::infinity();
  }
  [[nodiscard]] BvhBox box(int i) const {
    BvhBox b;
    for (int k = 0; k < 3; ++k) b.lo[k] = lo[k][i], b.hi[k] = hi[k][i];
    return b;
  }
  void set_box(int i, const BvhBox& b) {
    for (int k = 0; k < 3; ++k) lo[k][i] = b.lo[k], hi[k][i] = b.hi[k];
  }
};
static_assert(sizeof(Bvh8Node) == 256);

struct Bvh8 {
  static constexpr std::uint32_t kMaxLeaf = 255;
  std::vector<Bvh8Node, AlignedAllocator<Bvh8Node, 64>> nodes;  ///< nodes[0] is the root (absent when empty)
  std::vector<std::uint32_t> prim_ids;                          ///< primitive indices, leaf by leaf
  int max_depth = 0;                                            ///< nodes on the longest root-to-leaf path

  [[nodiscard]] bool empty() const { return nodes.empty(); }
  [[nodiscard]] std::size_t bytes() const {
    return nodes.size() * sizeof(Bvh8Node) + prim_ids.size() * sizeof(std::uint32_t);
  }
};

/// Which wide tree and box test the traversal uses.
enum class BvhSimd { automatic, sse4, avx2 };

/// True when the CPU runs AVX2 code.
[[nodiscard]] inline bool cpu_has_avx2() {
  static const bool ok = (__builtin_cpu_init(), __builtin_cpu_supports("avx2") != 0);
  return ok;
}

/// The RAYPROOF_SIMD environment variable: unset, empty or "auto": automatic; "sse" (and the leaf
/// kernels' "scalar" and "off"): the four-wide SSE path; "avx2": the eight-wide AVX2 path (when the
/// CPU has AVX2; else the SSE path). Any other value throws std::invalid_argument naming them.
[[nodiscard]] inline BvhSimd bvh_simd_from_env() {
  const char* e = std::getenv("RAYPROOF_SIMD");
  if (!e || !*e || std::strcmp(e, "auto") == 0) return BvhSimd::automatic;
  // "scalar" and "off" are the SIMD leaves' narrower settings (src/scene/leaf_simd.h): SSE nodes too.
  if (std::strcmp(e, "sse") == 0 || std::strcmp(e, "scalar") == 0 || std::strcmp(e, "off") == 0) return BvhSimd::sse4;
  if (std::strcmp(e, "avx2") == 0) return BvhSimd::avx2;
  std::string msg = "RAYPROOF_SIMD='";
  msg.append(e).append("': expected auto, avx2, sse, scalar or off");
  throw std::invalid_argument(msg);
}

/// The path actually taken for a request: automatic follows RAYPROOF_SIMD, then the CPU; avx2 on a
/// CPU without it falls back to sse4. Never returns automatic.
[[nodiscard]] inline BvhSimd bvh_simd_path(BvhSimd want = BvhSimd::automatic) {
  if (want == BvhSimd::automatic) want = bvh_simd_from_env();
  if (want == BvhSimd::sse4) return BvhSimd::sse4;
  return cpu_has_avx2() ? BvhSimd::avx2 : BvhSimd::sse4;
}

[[nodiscard]] inline const char* to_string(BvhSimd s) {
  switch (s) {
    case BvhSimd::automatic: return "auto";
    case BvhSimd::sse4: return "sse-4wide";
    case BvhSimd::avx2: return "avx2-8wide";
  }
  return "?";
}

namespace detail {

/// Splits a leaf range of more than kMaxLeaf primitives into a subtree of eight-wide nodes (chunks
/// in prim_ids order, boxes from the primitives' bounds); returns the new node's index.
inline std::uint32_t bvh8_chunk(Bvh8& w, std::span<const BvhBox> prim_boxes, std::uint32_t first, std::uint32_t count,
                                int depth, int& max_depth) {
  const auto id = static_cast<std::uint32_t>(w.nodes.size());
  w.nodes.emplace_back();
  max_depth = std::max(max_depth, depth);
  const std::uint32_t part = (count + 7) / 8;
  int slot = 0;
  for (std::uint32_t b = first; b < first + count; b += part, ++slot) {
    const std::uint32_t n = std::min(part, first + count - b);
    BvhBox box;
    for (std::uint32_t i = b; i < b + n; ++i) box.extend(prim_boxes[w.prim_ids[i]]);
    std::uint32_t ref = b;
    std::uint8_t cnt = static_cast<std::uint8_t>(n);
    if (n > Bvh8::kMaxLeaf) ref = bvh8_chunk(w, prim_boxes, b, n, depth + 1, max_depth), cnt = 0;
    Bvh8Node& node = w.nodes[id];
    node.set_box(slot, box);
    node.child[slot] = ref, node.count[slot] = cnt, node.valid |= std::uint8_t(1u << slot);
  }
  return id;
}

}  // namespace detail

/// Collapses a binary BVH into an eight-wide one: each wide node takes a binary node's children and
/// opens the inner child of largest surface area until it has eight (or only leaves are left).
/// An inner binary node whose subtree holds at most `merge_leaf` primitives becomes one leaf (its
/// primitives are contiguous in prim_ids): fewer, fuller nodes at the bottom; 0 keeps every leaf.
/// `prim_boxes` (indexed by primitive) bound leaves of more than Bvh8::kMaxLeaf primitives, which
/// are split. The binary tree's prim_ids become the wide tree's (moved out of `bin`).
[[nodiscard]] inline Bvh8 collapse_bvh8(Bvh&& bin, std::span<const BvhBox> prim_boxes, std::uint32_t merge_leaf = 0) {
  Bvh8 w;
  if (bin.empty()) return w;
  // Per binary node: its subtree's primitives [first, first + size) when contiguous (else size 0).
  std::vector<std::uint32_t> first, size;
  if (merge_leaf > 0) {
    first.assign(bin.nodes.size(), 0), size.assign(bin.nodes.size(), 0);
    std::vector<std::pair<std::uint32_t, bool>> order{{0, false}};  // post-order: children first
    while (!order.empty()) {
      const auto [i, done] = order.back();
      order.pop_back();
      const BvhNode& n = bin.nodes[i];
      if (n.is_leaf()) {
        first[i] = n.index, size[i] = n.count;
      } else if (!done) {
        order.push_back({i, true}), order.push_back({n.index, false}), order.push_back({n.index + 1, false});
      } else {
        const std::uint32_t a = n.index, b = n.index + 1;
        const bool contiguous = size[a] && size[b] && (first[a] + size[a] == first[b] || first[b] + size[b] == first[a]);
        first[i] = std::min(first[a], first[b]), size[i] = contiguous ? size[a] + size[b] : 0;
      }
    }
  }
  // A binary child taken as one leaf of the wide tree: (first, count), or count 0.
  auto as_leaf = [&](const BvhNode& c, std::uint32_t i) -> std::pair<std::uint32_t, std::uint32_t> {
    if (c.is_leaf()) return {c.index, c.count};
    if (merge_leaf > 0 && size[i] && size[i] <= merge_leaf) return {first[i], size[i]};
    return {0, 0};
  };
  w.prim_ids = std::move(bin.prim_ids);
  if (w.prim_ids.size() >= (std::size_t(1) << 31)) throw std::length_error("BVH: too many primitives");
  w.nodes.reserve(bin.nodes.size() / 7 + 2);
  int max_depth = 1;
  struct Task {
    std::uint32_t bin, wide;
    int depth;
  };
  std::vector<Task> stack;
  w.nodes.emplace_back();
  const BvhNode& root = bin.nodes[0];
  if (root.is_leaf()) {
    Bvh8Node& n = w.nodes[0];
    n.set_box(0, root.box), n.valid = 1;
    if (root.count > Bvh8::kMaxLeaf) {
      w.nodes.clear();
      detail::bvh8_chunk(w, prim_boxes, root.index, root.count, 1, max_depth);
    } else {
      n.child[0] = root.index, n.count[0] = static_cast<std::uint8_t>(root.count);
    }
  } else {
    stack.push_back({0, 0, 1});
  }
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    max_depth = std::max(max_depth, t.depth);
    std::uint32_t kids[8] = {bin.nodes[t.bin].index, bin.nodes[t.bin].index + 1};
    int nk = 2;
    while (nk < 8) {
      int best = -1;
      float best_area = -1;
      for (int i = 0; i < nk; ++i) {
        const BvhNode& c = bin.nodes[kids[i]];
        if (!as_leaf(c, kids[i]).second && c.box.half_area() > best_area) best = i, best_area = c.box.half_area();
      }
      if (best < 0) break;
      const std::uint32_t first_kid = bin.nodes[kids[best]].index;
      kids[best] = first_kid, kids[nk++] = first_kid + 1;
    }
    for (int i = 0; i < nk; ++i) {
      const BvhNode& c = bin.nodes[kids[i]];
      const auto [leaf_first, leaf_count] = as_leaf(c, kids[i]);
      std::uint32_t ref = 0;
      std::uint8_t cnt = 0;
      if (leaf_count && leaf_count <= Bvh8::kMaxLeaf) {
        ref = leaf_first, cnt = static_cast<std::uint8_t>(leaf_count);
      } else if (leaf_count) {
        ref = detail::bvh8_chunk(w, prim_boxes, leaf_first, leaf_count, t.depth + 1, max_depth);
      } else {
        ref = static_cast<std::uint32_t>(w.nodes.size());
        w.nodes.emplace_back();
        stack.push_back({kids[i], ref, t.depth + 1});
      }
      Bvh8Node& n = w.nodes[t.wide];
      n.set_box(i, c.box);
      n.child[i] = ref, n.count[i] = cnt, n.valid |= std::uint8_t(1u << i);
    }
  }
  w.nodes.shrink_to_fit();
  w.max_depth = max_depth;
  bin = Bvh{};
  return w;
}

namespace detail {

/// The ray of make_bvh4_ray broadcast to eight lanes; plane offsets in the eight-wide node.
struct Bvh8RayF {
  __m256 o_near[3], o_far[3], inv[3];
  int near_off[3], far_off[3];
};

[[gnu::target("avx2"), gnu::always_inline]] inline void bvh8_ray(const Bvh4RayF& r4, Bvh8RayF& r) {
  for (int k = 0; k < 3; ++k) {
    r.o_near[k] = _mm256_broadcastss_ps(r4.o_near[k]);
    r.o_far[k] = _mm256_broadcastss_ps(r4.o_far[k]);
    r.inv[k] = _mm256_broadcastss_ps(r4.inv[k]);
    // Four-wide offsets are 4k (lo) and 12 + 4k (hi); eight-wide 8k and 24 + 8k.
    r.near_off[k] = 2 * r4.near_off[k], r.far_off[k] = 2 * r4.far_off[k];
  }
}

/// Hit mask of the eight children of `n` and their entry distances: bvh4_test in eight lanes.
template <bool Conservative>
[[gnu::target("avx2"), gnu::always_inline]] inline int bvh8_test(const Bvh8Node& n, const Bvh8RayF& r, __m256 tmin,
                                                                 __m256 tmax, __m256& t_enter) {
  const float* f = &n.lo[0][0];
  const __m256 ninf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  const __m256 pinf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  __m256 t0 = Conservative ? ninf : tmin, t1 = Conservative ? pinf : tmax;
  for (int k = 0; k < 3; ++k) {
    const __m256 near = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(f + r.near_off[k]), r.o_near[k]), r.inv[k]);
    const __m256 far = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(f + r.far_off[k]), r.o_far[k]), r.inv[k]);
    t0 = _mm256_max_ps(near, t0);  // NaN near: t0 (the axis bounds nothing)
    t1 = _mm256_min_ps(far, t1);   // NaN far: t1
  }
  if constexpr (Conservative) {
    const __m256 shrink = _mm256_set1_ps(1.0f - 0x1p-21f), grow = _mm256_set1_ps(1.0f + 0x1p-21f);
    const __m256 tiny = _mm256_set1_ps(0x1p-120f), zero = _mm256_setzero_ps();
    const __m256 t0_neg = _mm256_cmp_ps(t0, zero, _CMP_LT_OQ), t1_neg = _mm256_cmp_ps(t1, zero, _CMP_LT_OQ);
    t0 = _mm256_sub_ps(_mm256_mul_ps(t0, _mm256_blendv_ps(shrink, grow, t0_neg)), tiny);
    t1 = _mm256_add_ps(_mm256_mul_ps(t1, _mm256_blendv_ps(grow, shrink, t1_neg)), tiny);
    t0 = _mm256_max_ps(t0, tmin);
    t1 = _mm256_min_ps(t1, tmax);
  }
  t_enter = t0;
  return _mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ)) & n.valid;
}

/// The scalar double test of the same eight children (rays out of the float path's range).
template <bool Conservative>
inline int bvh8_test_double(const Bvh8Node& n, const BvhRay<double>& r, double tmin, double tmax, double t_enter[8]) {
  int mask = 0;
  for (int i = 0; i < 8; ++i) {
    if (!(n.valid >> i & 1)) continue;
    t_enter[i] = r.template enter<Conservative>(n.box(i), tmin, tmax);
    if (t_enter[i] != std::numeric_limits<double>::infinity()) mask |= 1 << i;
  }
  return mask;
}

/// Pushes the hit children of `n` (mask, two or more bits) on the stack: for closest hit farthest
/// first (the nearest on top), else in slot order; prefetches inner children's nodes.
template <bool Sort, class T>
[[gnu::always_inline]] inline void bvh8_push(const Bvh8Node& n, const Bvh8Node* nodes, int mask, const T* t,
                                             Bvh4Entry<T>* stack, int& top) {
  if constexpr (!Sort) {
    while (mask) {
      const int i = __builtin_ctz(static_cast<unsigned>(mask));
      mask &= mask - 1;
      stack[top++] = Bvh4Entry<T>{n.child[i], n.count[i], t[i]};
    }
    return;
  }
  auto prefetch = [&](const Bvh4Entry<T>& x) {
    if (x.count) return;
    const char* p = reinterpret_cast<const char*>(nodes + x.ref);
    _mm_prefetch(p, _MM_HINT_T0), _mm_prefetch(p + 64, _MM_HINT_T0);
    _mm_prefetch(p + 128, _MM_HINT_T0), _mm_prefetch(p + 192, _MM_HINT_T0);
  };
  if (__builtin_popcount(static_cast<unsigned>(mask)) == 2) {  // the common case: one comparison
    const int i = __builtin_ctz(static_cast<unsigned>(mask)), j = __builtin_ctz(static_cast<unsigned>(mask & (mask - 1)));
    const Bvh4Entry<T> a{n.child[i], n.count[i], t[i]}, b{n.child[j], n.count[j], t[j]};
    prefetch(a), prefetch(b);
    const bool a_near = a.t <= t[j];
    stack[top++] = a_near ? b : a;
    stack[top++] = a_near ? a : b;
    return;
  }
  Bvh4Entry<T> e[8];
  int m = 0;
  while (mask) {
    const int i = __builtin_ctz(static_cast<unsigned>(mask));
    mask &= mask - 1;
    Bvh4Entry<T> x{n.child[i], n.count[i], t[i]};
    prefetch(x);
    int j = m++;
    for (; j > 0 && e[j - 1].t < x.t; --j) e[j] = e[j - 1];  // descending t
    e[j] = x;
  }
  for (int i = 0; i < m; ++i) stack[top++] = e[i];
}

/// The eight-wide traversal loop with the double box test (rays out of the float range).
template <bool Conservative, BvhQuery Query, class LeafRange>
[[gnu::target("avx2")]] void bvh8_traverse_double(const Bvh8& bvh, const Ray<double>& ray, double tmin,
                                                  const double& tmax, LeafRange& leaf) {
  using Entry = Bvh4Entry<double>;
  std::vector<Entry> stack(7 * static_cast<std::size_t>(bvh.max_depth) + 8);
  int top = 0;
  const Bvh8Node* nodes = bvh.nodes.data();
  const BvhRay<double> rd(ray, Conservative ? BvhTraversal::conservative : BvhTraversal::standard);
  Entry e{0, 0, -std::numeric_limits<double>::infinity()};
  if (Query == BvhQuery::closest && !(e.t <= tmax)) return;
  for (;;) {
    if (e.count) {
      if (leaf(e.ref, e.count) && Query == BvhQuery::any) return;
    } else {
      const Bvh8Node& n = nodes[e.ref];
      double t[8];
      const int mask = bvh8_test_double<Conservative>(n, rd, tmin, tmax, t);
      if (mask) {
        if ((mask & (mask - 1)) == 0) {
          const int i = __builtin_ctz(static_cast<unsigned>(mask));
          e = Entry{n.child[i], n.count[i], t[i]};
        } else {
          bvh8_push<Query == BvhQuery::closest>(n, nodes, mask, t, stack.data(), top);
          e = stack[static_cast<std::size_t>(--top)];
        }
        continue;
      }
    }
    do {
      if (top == 0) return;
      e = stack[static_cast<std::size_t>(--top)];
    } while (Query == BvhQuery::closest && !(e.t <= tmax));
  }
}

/// The eight-wide traversal loop with the AVX2 box test; hands rays out of its range to the double one.
template <bool Conservative, BvhQuery Query, class LeafRange>
[[gnu::target("avx2")]] void bvh8_traverse_impl(const Bvh8& bvh, const Ray<double>& ray, double tmin,
                                                const double& tmax, LeafRange& leaf) {
  Bvh4RayF r4;
  if (!make_bvh4_ray(ray, Conservative, tmin, r4)) return bvh8_traverse_double<Conservative, Query>(bvh, ray, tmin, tmax, leaf);
  Bvh8RayF rf;
  bvh8_ray(r4, rf);
  const __m256 tmin_v = _mm256_set1_ps(r4.tmin);
  using Entry = Bvh4Entry<float>;
  Entry local[256];
  std::vector<Entry> heap;
  Entry* stack = local;
  const std::size_t need = 7 * static_cast<std::size_t>(bvh.max_depth) + 8;
  if (need > 256) heap.resize(need), stack = heap.data();
  int top = 0;
  const Bvh8Node* nodes = bvh.nodes.data();
  auto tmax_f = [&]() -> float { return Conservative ? round_up_f(tmax) : static_cast<float>(tmax); };
  float tmax_cur = tmax_f();
  Entry e{0, 0, -std::numeric_limits<float>::infinity()};
  if (Query == BvhQuery::closest && !(e.t <= tmax_cur)) return;  // NaN tmax
  for (;;) {
    if (e.count) {
      if (leaf(e.ref, e.count) && Query == BvhQuery::any) return;
      if constexpr (Query == BvhQuery::closest) tmax_cur = tmax_f();
    } else {
      const Bvh8Node& n = nodes[e.ref];
      __m256 te;
      const int mask = bvh8_test<Conservative>(n, rf, tmin_v, _mm256_set1_ps(tmax_cur), te);
      if (mask) {
        alignas(32) float t[8];
        _mm256_store_ps(t, te);
        if ((mask & (mask - 1)) == 0) {  // one child: straight to it
          const int i = __builtin_ctz(static_cast<unsigned>(mask));
          e = Entry{n.child[i], n.count[i], t[i]};
        } else {  // several: for closest hit the nearest next, the farther ones on the stack
          bvh8_push<Query == BvhQuery::closest>(n, nodes, mask, t, stack, top);
          e = stack[--top];
        }
        continue;
      }
    }
    do {
      if (top == 0) return;
      e = stack[--top];
    } while (Query == BvhQuery::closest && !(e.t <= tmax_cur));
  }
}

template <bool Conservative, class LeafRange>
void bvh8_traverse_query(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhQuery query,
                         LeafRange& leaf) {
  switch (query) {
    case BvhQuery::closest: return bvh8_traverse_impl<Conservative, BvhQuery::closest>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::any: return bvh8_traverse_impl<Conservative, BvhQuery::any>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::all: return bvh8_traverse_impl<Conservative, BvhQuery::all>(bvh, ray, tmin, tmax, leaf);
  }
}

}  // namespace detail

/// The eight-wide traversal with whole leaves: `leaf_range(first, count)` gets the leaf-order slots
/// [first, first + count) and returns true to stop (any hit). Needs AVX2: call it only when
/// cpu_has_avx2() (bvh_simd_path() == BvhSimd::avx2).
template <class LeafRange>
void bvh8_traverse_leaves(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRange&& leaf_range) {
  if (bvh.empty()) return;
  if (mode == BvhTraversal::conservative) return detail::bvh8_traverse_query<true>(bvh, ray, tmin, tmax, query, leaf_range);
  return detail::bvh8_traverse_query<false>(bvh, ray, tmin, tmax, query, leaf_range);
}

/// bvh8_traverse_leaves one slot at a time: `leaf(j)` for each leaf-order slot j, true to stop (any hit).
template <class Leaf>
void bvh8_traverse_slots(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                         BvhQuery query, Leaf&& leaf) {
  const bool any = query == BvhQuery::any;
  bvh8_traverse_leaves(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first, end = first + count; j < end; ++j)
      if (leaf(j) && any) return true;
    return false;
  });
}

/// bvh8_traverse_slots with the primitive prim_ids[j] instead of the slot (as bvh4_traverse).
template <class Leaf>
void bvh8_traverse(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                   BvhQuery query, Leaf&& leaf) {
  const std::uint32_t* ids = bvh.prim_ids.data();
  bvh8_traverse_slots(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t j) { return leaf(ids[j]); });
}

}  // namespace rayproof
