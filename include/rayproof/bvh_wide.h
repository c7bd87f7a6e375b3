#pragma once
/// Wide BVHs: the binary tree of bvh_build.h collapsed into nodes of up to N = 4 or 8 children
/// (one node template, one collapse, one traversal loop for both widths). This header has the
/// four-wide SSE box test (the path for CPUs without AVX2); bvh_wide8.h has the eight-wide AVX2 one. Closest hit visits children nearest first (any and all hits in slot order); the stack holds (child, entry t) so
/// closest hit drops popped children whose entry lies beyond the best t so far.
///
/// Node layout (32 N bytes: 128 for four children, two cache lines; 256 for eight): per axis the N
/// children's lo then hi planes (structure of arrays, one SSE / AVX load per plane), then per child its reference: an inner child is a
/// node index, a leaf child is a range [first, first + count) of prim_ids (count 1..255; count 0
/// marks an inner child). Unused slots have empty boxes and a clear bit in `valid`.
/// Compressed nodes (BvhWideQNode, bvh_wide_quantized.h: 128 bytes for eight children, 80 for four) hold the same
/// references with 8-bit child planes on a per-node grid; quantize_wide makes them from a full tree,
/// and the same loop and box tests traverse them (the planes decoded to floats that contain the
/// full boxes, so every guarantee below carries over). RAYPROOF_BVH_NODES=full|compressed or the
/// tree's size chooses (bvh_nodes_choice).
///
/// Box tests. The ray is given in double; the traversal runs in float when the ray is within range:
///  - standard: the slab test on the float-rounded ray (what a float kernel intersects).
///  - conservative (after Ize, "Robust BVH Ray Traversal", JCGT 2013): every box the exact double
///    segment [tmin, tmax] touches passes (for tmin >= 0; a ray with tmin < 0 takes the double test).
///    Per axis the origin is replaced by a float bound on the side that lowers the near distance
///    and raises the far one (see make_bvh4_ray), and the reciprocal by two directed floats: one
///    toward zero for the near plane, one away from zero for the far plane, each scaled by 1 -/+ 2^-22
///    so that it also covers the rounding of the plane difference. Then every node costs what the
///    plain slab test costs (difference, product, max / min, one comparison): the rounding is folded
///    into the per-ray constants. The proof is at make_bvh4_ray.
///    NaN distances (an axis with d = 0 and the origin on a slab plane: 0 * inf) are skipped, as in
///    bvh_traverse.h: `_mm_max_ps(x, t0)` returns t0 when x is NaN.
///  - Rays out of the float path's range (|o| > 2^64, or a nonzero |d| outside [2^-64, 2^64]) are
///    traversed with the scalar double box test of bvh_traverse.h on the same nodes.
#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_traverse.h"

namespace rayproof {

/// A wide node of N = 4 or 8 children (layout above; 32 N bytes). Bvh4Node / Bvh8Node name the two.
template <int N>
struct alignas(64) BvhWideNode {
  static_assert(N == 4 || N == 8, "the box tests exist for four (SSE) and eight (AVX2) lanes");
  static constexpr int kWidth = N;
  static constexpr bool kPrefetch = true;  ///< closest hit prefetches the hit inner children (wide_push)
  float lo[3][N];  ///< lo[axis][child]
  float hi[3][N];  ///< hi[axis][child]
  std::uint32_t child[N] = {};  ///< inner: node index; leaf: first prim_ids entry
  std::uint8_t count[N] = {};   ///< 0: inner child; else primitives in the leaf
  std::uint8_t valid = 0;       ///< bit i: slot i is used
  std::uint8_t pad_[3 * N - 1] = {};

  BvhWideNode() {
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < N; ++i) lo[k][i] = std::numeric_limits<float>::infinity(), hi[k][i] = -std::numeric_limits<float>::infinity();
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
using Bvh4Node = BvhWideNode<4>;
using Bvh8Node = BvhWideNode<8>;
static_assert(sizeof(Bvh4Node) == 128);
static_assert(sizeof(Bvh8Node) == 256);

/// A wide tree: Bvh4 (SSE path) and Bvh8 (AVX2 path, bvh_wide8.h).
template <int N>
struct BvhWide {
  using Node = BvhWideNode<N>;
  static constexpr int kWidth = N;
  static constexpr std::uint32_t kMaxLeaf = 255;
  std::vector<Node, AlignedAllocator<Node, 64>> nodes;  ///< nodes[0] is the root (absent when empty)
  std::vector<std::uint32_t> prim_ids;                  ///< primitive indices, leaf by leaf
  int max_depth = 0;                                    ///< nodes on the longest root-to-leaf path

  [[nodiscard]] bool empty() const { return nodes.empty(); }
  [[nodiscard]] std::size_t bytes() const { return nodes.size() * sizeof(Node) + prim_ids.size() * sizeof(std::uint32_t); }
};
using Bvh4 = BvhWide<4>;
using Bvh8 = BvhWide<8>;

namespace detail {

/// Splits a leaf range of more than kMaxLeaf primitives into a subtree of wide nodes (N chunks in
/// prim_ids order, boxes from the primitives' bounds); returns the new node's index.
template <int N>
std::uint32_t wide_chunk(BvhWide<N>& w, std::span<const BvhBox> prim_boxes, std::uint32_t first, std::uint32_t count,
                         int depth, int& max_depth) {
  const auto id = static_cast<std::uint32_t>(w.nodes.size());
  w.nodes.emplace_back();
  max_depth = std::max(max_depth, depth);
  const std::uint32_t part = (count + N - 1) / N;
  int slot = 0;
  for (std::uint32_t b = first; b < first + count; b += part, ++slot) {
    const std::uint32_t n = std::min(part, first + count - b);
    BvhBox box;
    for (std::uint32_t i = b; i < b + n; ++i) box.extend(prim_boxes[w.prim_ids[i]]);
    std::uint32_t ref = b;
    std::uint8_t cnt = static_cast<std::uint8_t>(n);
    if (n > BvhWide<N>::kMaxLeaf) ref = wide_chunk(w, prim_boxes, b, n, depth + 1, max_depth), cnt = 0;
    auto& node = w.nodes[id];
    node.set_box(slot, box);
    node.child[slot] = ref, node.count[slot] = cnt, node.valid |= std::uint8_t(1u << slot);
  }
  return id;
}

}  // namespace detail

/// Collapses a binary BVH into an N-wide one (N = 4 or 8): each wide node takes a binary node's
/// children and opens the inner child of largest surface area until it has N (or only leaves are
/// left). An inner binary node whose subtree holds at most `merge_leaf` primitives becomes one leaf
/// (its primitives are contiguous in prim_ids): fewer, fuller nodes at the bottom; 0 keeps every
/// leaf. `prim_boxes` (indexed by primitive) bound leaves of more than kMaxLeaf primitives, which
/// are split. The binary tree's prim_ids become the wide tree's (moved out of `bin`).
template <int N>
[[nodiscard]] BvhWide<N> collapse_wide(Bvh&& bin, std::span<const BvhBox> prim_boxes, std::uint32_t merge_leaf = 0) {
  using Node = BvhWideNode<N>;
  BvhWide<N> w;
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
  // A binary child taken as one leaf of the wide tree: (first, count), or count 0 (an inner node).
  auto as_leaf = [&](const BvhNode& c, std::uint32_t i) -> std::pair<std::uint32_t, std::uint32_t> {
    if (c.is_leaf()) return {c.index, c.count};
    if (merge_leaf > 0 && size[i] && size[i] <= merge_leaf) return {first[i], size[i]};
    return {0, 0};
  };
  w.prim_ids = std::move(bin.prim_ids);
  if (w.prim_ids.size() >= (std::size_t(1) << 31)) throw std::length_error("BVH: too many primitives");
  w.nodes.reserve(bin.nodes.size() / (N - 1) + 2);
  int max_depth = 1;
  struct Task {
    std::uint32_t bin, wide;
    int depth;
  };
  std::vector<Task> stack;
  w.nodes.emplace_back();
  const BvhNode& root = bin.nodes[0];
  if (root.is_leaf()) {
    // A single leaf: one slot (split when too big).
    Node& n = w.nodes[0];
    n.set_box(0, root.box), n.valid = 1;
    if (root.count > BvhWide<N>::kMaxLeaf) {
      w.nodes.clear();
      detail::wide_chunk(w, prim_boxes, root.index, root.count, 1, max_depth);
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
    std::uint32_t kids[N] = {bin.nodes[t.bin].index, bin.nodes[t.bin].index + 1};
    int nk = 2;
    while (nk < N) {
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
      if (leaf_count && leaf_count <= BvhWide<N>::kMaxLeaf) {
        ref = leaf_first, cnt = static_cast<std::uint8_t>(leaf_count);
      } else if (leaf_count) {
        ref = detail::wide_chunk(w, prim_boxes, leaf_first, leaf_count, t.depth + 1, max_depth);
      } else {
        ref = static_cast<std::uint32_t>(w.nodes.size());
        w.nodes.emplace_back();
        stack.push_back({kids[i], ref, t.depth + 1});
      }
      Node& n = w.nodes[t.wide];
      n.set_box(i, c.box);
      n.child[i] = ref, n.count[i] = cnt, n.valid |= std::uint8_t(1u << i);
    }
  }
  w.nodes.shrink_to_fit();
  w.max_depth = max_depth;
  bin = Bvh{};
  return w;
}

/// collapse_wide<4>: the tree of the SSE path.
[[nodiscard]] inline Bvh4 collapse_bvh4(Bvh&& bin, std::span<const BvhBox> prim_boxes, std::uint32_t merge_leaf = 0) {
  return collapse_wide<4>(std::move(bin), prim_boxes, merge_leaf);
}

/// collapse_wide<8>: the tree of the AVX2 path (bvh_wide8.h).
[[nodiscard]] inline Bvh8 collapse_bvh8(Bvh&& bin, std::span<const BvhBox> prim_boxes, std::uint32_t merge_leaf = 0) {
  return collapse_wide<8>(std::move(bin), prim_boxes, merge_leaf);
}

namespace detail {

/// A ray prepared for the SSE box test of four children.
struct Bvh4RayF {
  __m128 o_near[3], o_far[3];
  __m128 inv_near[3], inv_far[3];  ///< the reciprocal for the near / far plane (equal unless conservative)
  int near_off[3], far_off[3];  ///< float offsets of the near / far planes of axis k in the node
  float tmin;
};

inline float round_down_f(double x) { return bvh_float_down(x); }
inline float round_up_f(double x) { return bvh_float_up(x); }
/// Float bounds of a query's tmax and tmin without a branch (the directed roundings above compare
/// and branch, and a closest-hit query lowers tmax at data-dependent points, so that branch is
/// mispredicted about half the time). For x >= 0 (and +inf): x (1 + 2^-23) + 2^-149 in double
/// (exact but for 2^-53 relative), then rounded to the nearest float: in the normal range the
/// rounding loses at most 2^-24 relative, less than the 2^-23 added; below 2^-126 it loses at most
/// 2^-150, less than the 2^-149 added; above the float range it gives +inf. So the float is >= x.
/// Mirrored, x (1 - 2^-23) - 2^-149 gives a float <= x (for x = 0: -2^-149). NaN stays NaN.
/// A negative x (an empty range: tmax < tmin) may get a float above it in float_below and below
/// it in float_above; the box tests then only reject more, and there is nothing to find.
inline float float_above(double x) { return static_cast<float>(x * (1.0 + 0x1p-23) + 0x1p-149); }
inline float float_below(double x) { return static_cast<float>(x * (1.0 - 0x1p-23) - 0x1p-149); }

/// Prepares the float box test of the double ray; false when the ray is out of the float path's
/// range (see the header comment: NaN, |o| > 2^64, or a nonzero |d| outside [2^-64, 2^64]) and,
/// when conservative, when tmin < 0 (or NaN).
///
/// Conservative: origins. The origin bounds are o -/+ (|o| 2^-23 + 2^-148) computed in double,
/// then rounded to the nearest float. That float is <= o (resp. >= o): the offset is at least one
/// float ulp of o (ulp(o) <= |o| 2^-23 for normal floats, 2^-149 below them), and rounding to
/// nearest moves by at most half an ulp; the double operations' own roundings (2^-53 relative) are
/// far inside that. For 1/d >= 0 the near plane (lo) is paired with o_n >= o and the far plane (hi)
/// with o_f <= o; mirrored for 1/d < 0 (d = -0 included).
///
/// Conservative: directed reciprocals. With r = 1/d in double (relative error <= 2^-53),
/// inv_near = r (1 - 2^-22) and inv_far = r (1 + 2^-22), each product in double (2^-53 more) then
/// rounded to the nearest float (2^-24 more: |r| is within [2^-64, 2^64], the normal range; r = +-inf
/// stays). No directed rounding is needed (it would compare and branch per ray): the factor 2^-22
/// covers the rounding to nearest. So, with u = 2^-24,
///   |inv_near| (1 + u) <= (1/|d|) (1 - 2^-22)(1 + 2^-53)^2 (1 + 2^-24)^2 < 1/|d|,
///   |inv_far| (1 - u)  >= (1/|d|) (1 + 2^-22)(1 - 2^-53)^2 (1 - 2^-24)^2 > 1/|d|.
/// Proof that a box the exact segment touches passes (tmin >= 0). Per axis the node test computes
/// near = fl(P), P = fl(plane_n - o_n) inv_near, and far = fl(Q), Q = fl(plane_f - o_f) inv_far
/// (one rounded difference, exact below 2^-126, relative error <= u and sign kept; then the real
/// product P or Q, rounded once). Let E = (plane_n - o)/d and F = (plane_f - o)/d be the exact
/// entry and exit of the slab. For d > 0 (the other sign mirrors it):
///  - if fl(lo - o_n) >= 0: P <= (lo - o_n)(1 + u) inv_near <= (lo - o)(1 + u) inv_near <= E;
///    if fl(lo - o_n) < 0: P < 0 <= tmin, so P cannot raise max(near, tmin) above max(E, tmin);
///  - a box is touched only if F >= tmin >= 0, so hi - o >= 0 and, with o_f <= o,
///    Q >= (hi - o_f)(1 - u) inv_far >= (hi - o)(1 - u) inv_far >= F.
/// Hence, as reals, every near term (P's and the float tmin, a lower bound: float_below) is <= every far term
/// (Q's and the float tmax, an upper bound: float_above) whenever max(E, tmin) <= min(F, tmax). Rounding to
/// nearest is monotonic (overflow to inf included), so fl(P) <= fl(Q), fl(P) <= tmax_f and
/// tmin_f <= fl(Q) hold too: max over the near terms <= min over the far terms, and the box
/// passes. No widening, no clamp and no absolute term are left in the node test.
/// d = 0 on an axis: both reciprocals are +-inf; the products are +-inf (the slab excludes or
/// contains the whole line, as for the exact ray, since o_n >= o >= o_f) or NaN when the rounded
/// origin lies on the plane, which the max / min skip (the axis bounds nothing: conservative).
/// Standard: both reciprocals are r rounded to nearest, the origins o rounded to nearest.
[[gnu::always_inline]] inline bool make_bvh4_ray(const Ray<double>& r, bool conservative, double tmin, Bvh4RayF& out) {
  const __m128d sign = _mm_set1_pd(-0.0);
  const __m128d oxy = _mm_loadu_pd(&r.o.x), oz = _mm_load_sd(&r.o.z);
  const __m128d dxy = _mm_loadu_pd(&r.d.x), dz = _mm_load_sd(&r.d.z);
  const __m128d aoxy = _mm_andnot_pd(sign, oxy), aoz = _mm_andnot_pd(sign, oz);
  const __m128d adxy = _mm_andnot_pd(sign, dxy), adz = _mm_andnot_pd(sign, dz);
  const __m128d hi = _mm_set1_pd(18446744073709551616.0), lo = _mm_set1_pd(1.0 / 18446744073709551616.0);
  const __m128d zero = _mm_setzero_pd();
  // |o| <= 2^64 (false for NaN) and (d = 0 or 2^-64 <= |d| <= 2^64), per lane.
  auto ok = [&](__m128d ao, __m128d ad) {
    return _mm_and_pd(_mm_cmple_pd(ao, hi), _mm_or_pd(_mm_cmpeq_pd(ad, zero), _mm_and_pd(_mm_cmpge_pd(ad, lo), _mm_cmple_pd(ad, hi))));
  };
  if ((_mm_movemask_pd(ok(aoxy, adxy)) & 3) != 3 || (_mm_movemask_pd(ok(aoz, adz)) & 1) != 1) return false;
  if (conservative && !(tmin >= 0)) return false;
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d rxy = _mm_div_pd(one, dxy), rz = _mm_div_sd(one, dz);
  __m128 inv_near, inv_far;
  __m128 o_lo, o_hi;
  if (conservative) {
    const __m128d shrink = _mm_set1_pd(1.0 - 0x1p-22), grow = _mm_set1_pd(1.0 + 0x1p-22);
    inv_near = _mm_movelh_ps(_mm_cvtpd_ps(_mm_mul_pd(rxy, shrink)), _mm_cvtpd_ps(_mm_mul_sd(rz, shrink)));
    inv_far = _mm_movelh_ps(_mm_cvtpd_ps(_mm_mul_pd(rxy, grow)), _mm_cvtpd_ps(_mm_mul_sd(rz, grow)));
    const __m128d ulp = _mm_set1_pd(0x1p-23), tiny = _mm_set1_pd(0x1p-148);
    const __m128d exy = _mm_add_pd(_mm_mul_pd(aoxy, ulp), tiny), ez = _mm_add_pd(_mm_mul_pd(aoz, ulp), tiny);
    o_lo = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(oxy, exy)), _mm_cvtpd_ps(_mm_sub_pd(oz, ez)));
    o_hi = _mm_movelh_ps(_mm_cvtpd_ps(_mm_add_pd(oxy, exy)), _mm_cvtpd_ps(_mm_add_pd(oz, ez)));
  } else {
    inv_near = inv_far = _mm_movelh_ps(_mm_cvtpd_ps(rxy), _mm_cvtpd_ps(rz));
    o_lo = o_hi = _mm_movelh_ps(_mm_cvtpd_ps(oxy), _mm_cvtpd_ps(oz));
  }
  // 1/d < 0 (d < 0 or d = -0): the near plane is hi, and the near distance wants the lower origin.
  const __m128 neg = _mm_cmplt_ps(inv_near, _mm_setzero_ps());
  const __m128 o_near = _mm_or_ps(_mm_and_ps(neg, o_lo), _mm_andnot_ps(neg, o_hi));
  const __m128 o_far = _mm_or_ps(_mm_and_ps(neg, o_hi), _mm_andnot_ps(neg, o_lo));
  const int negs = _mm_movemask_ps(neg);
  out.o_near[0] = _mm_shuffle_ps(o_near, o_near, 0x00), out.o_far[0] = _mm_shuffle_ps(o_far, o_far, 0x00);
  out.o_near[1] = _mm_shuffle_ps(o_near, o_near, 0x55), out.o_far[1] = _mm_shuffle_ps(o_far, o_far, 0x55);
  out.o_near[2] = _mm_shuffle_ps(o_near, o_near, 0xaa), out.o_far[2] = _mm_shuffle_ps(o_far, o_far, 0xaa);
  out.inv_near[0] = _mm_shuffle_ps(inv_near, inv_near, 0x00), out.inv_far[0] = _mm_shuffle_ps(inv_far, inv_far, 0x00);
  out.inv_near[1] = _mm_shuffle_ps(inv_near, inv_near, 0x55), out.inv_far[1] = _mm_shuffle_ps(inv_far, inv_far, 0x55);
  out.inv_near[2] = _mm_shuffle_ps(inv_near, inv_near, 0xaa), out.inv_far[2] = _mm_shuffle_ps(inv_far, inv_far, 0xaa);
  for (int k = 0; k < 3; ++k) {
    // Within an axis: lo[k] at float offset 4k, hi[k] at 12 + 4k.
    const bool n = negs >> k & 1;
    out.near_off[k] = n ? 12 + 4 * k : 4 * k;
    out.far_off[k] = n ? 4 * k : 12 + 4 * k;
  }
  out.tmin = conservative ? float_below(tmin) : static_cast<float>(tmin);
  return true;
}

/// Hit mask of the four children of `n` and their entry distances: the slab test with the ray's
/// per-plane reciprocals (conservative by make_bvh4_ray's constants alone, proof there).
/// `plane(off, k)` gives the four children's planes at float offset `off` (near_off / far_off) of
/// axis k: loaded from a full node, decoded from a quantized one (BvhWideQNode); the math after it
/// is the same for both.
template <bool Conservative, class Planes>
[[gnu::always_inline]] inline int bvh4_slab_test(const Planes& plane, int valid, const Bvh4RayF& r, __m128 tmin, __m128 tmax,
                                                 __m128& t_enter) {
  __m128 t0 = tmin, t1 = tmax;
  for (int k = 0; k < 3; ++k) {
    const __m128 near = _mm_mul_ps(_mm_sub_ps(plane(r.near_off[k], k), r.o_near[k]), r.inv_near[k]);
    const __m128 far = _mm_mul_ps(_mm_sub_ps(plane(r.far_off[k], k), r.o_far[k]), r.inv_far[k]);
    t0 = _mm_max_ps(near, t0);  // NaN near: t0 (the axis bounds nothing)
    t1 = _mm_min_ps(far, t1);   // NaN far: t1
  }
  t_enter = t0;
  return _mm_movemask_ps(_mm_cmple_ps(t0, t1)) & valid;
}

template <bool Conservative>
[[gnu::always_inline]] inline int bvh4_test(const Bvh4Node& n, const Bvh4RayF& r, __m128 tmin, __m128 tmax, __m128& t_enter) {
  const float* f = &n.lo[0][0];
  return bvh4_slab_test<Conservative>([f](int off, int) { return _mm_load_ps(f + off); }, n.valid, r, tmin, tmax, t_enter);
}

/// The scalar double test of the N children of `n` (rays out of the float path's range), on the
/// node's float boxes (decoded ones for a quantized node).
template <bool Conservative, class Node>
inline int wide_test_double(const Node& n, const BvhRay<double>& r, double tmin, double tmax, double* t_enter) {
  constexpr int N = Node::kWidth;
  int mask = 0;
  for (int i = 0; i < N; ++i) {
    if (!(n.valid >> i & 1)) continue;
    t_enter[i] = r.template enter<Conservative>(n.box(i), tmin, tmax);
    if (t_enter[i] != std::numeric_limits<double>::infinity()) mask |= 1 << i;
  }
  return mask;
}

template <class T>
struct WideEntry {
  std::uint32_t ref;
  std::uint32_t count;  ///< 0: inner node
  T t;
};

/// Pushes the hit children of `n` (mask, two or more bits) on the stack: for closest hit (Sort)
/// farthest first, so the nearest is on top, and prefetching inner children's nodes (when
/// Node::kPrefetch); else in slot
/// order. On equal entry t the four-wide sort puts the later slot on top; the eight-wide pair case
/// (one comparison) puts the earlier one on top, as each did before they shared this code.
template <bool Sort, class Node, class T>
[[gnu::always_inline]] inline void wide_push(const Node& n, const Node* nodes, int mask, const T* t, WideEntry<T>* stack,
                                             int& top) {
  constexpr int N = Node::kWidth;
  if constexpr (!Sort) {
    for (; mask; mask &= mask - 1) {
      const int i = __builtin_ctz(static_cast<unsigned>(mask));
      stack[top++] = WideEntry<T>{n.child[i], n.count[i], t[i]};
    }
    return;
  }
  auto prefetch = [&](const WideEntry<T>& x) {
    if (!Node::kPrefetch || x.count) return;
    const char* p = reinterpret_cast<const char*>(nodes + x.ref);
    // Every line the node touches (an 80-byte node aligned to 16 may start late in a line).
    for (std::size_t line = 0; line < sizeof(Node) + (alignof(Node) < 64 ? 64 - alignof(Node) : 0); line += 64)
      _mm_prefetch(p + line, _MM_HINT_T0);
  };
  if constexpr (N == 8) {
    if (__builtin_popcount(static_cast<unsigned>(mask)) == 2) {  // the common case: one comparison
      const int i = __builtin_ctz(static_cast<unsigned>(mask)), j = __builtin_ctz(static_cast<unsigned>(mask & (mask - 1)));
      const WideEntry<T> a{n.child[i], n.count[i], t[i]}, b{n.child[j], n.count[j], t[j]};
      prefetch(a), prefetch(b);
      const bool a_near = a.t <= t[j];
      stack[top++] = a_near ? b : a;
      stack[top++] = a_near ? a : b;
      return;
    }
  }
  WideEntry<T> e[N];
  int m = 0;
  while (mask) {
    const int i = __builtin_ctz(static_cast<unsigned>(mask));
    mask &= mask - 1;
    WideEntry<T> x{n.child[i], n.count[i], t[i]};
    prefetch(x);
    int j = m++;
    for (; j > 0 && e[j - 1].t < x.t; --j) e[j] = e[j - 1];  // descending t
    e[j] = x;
  }
  for (int i = 0; i < m; ++i) stack[top++] = e[i];
}

// wide_traverse_loop: the traversal loop of both widths (bvh_wide_loop.h, compiled for the baseline
// here; bvh_wide8.h compiles the same source for AVX2 as wide_traverse_loop_avx2).
#define RAYPROOF_WIDE_TRAVERSE_LOOP wide_traverse_loop
#include "rayproof/bvh_wide_loop.h"
#undef RAYPROOF_WIDE_TRAVERSE_LOOP

template <bool Conservative, class Node>
struct WideBoxTestDouble {
  BvhRay<double> ray;
  double tmin;
  [[gnu::always_inline]] int operator()(const Node& n, double tmax, double* t) const {
    return wide_test_double<Conservative>(n, ray, tmin, tmax, t);
  }
};

/// A leaf callable without its type: the double path below takes its leaf through this, so that it
/// is compiled once per tree, mode and query instead of once per caller's leaf (each caller's
/// kernels and queries made it the largest part of the traversal code, for a path few rays take).
struct WideLeafRef {
  void* leaf;
  bool (*call)(void*, std::uint32_t, std::uint32_t);
  bool operator()(std::uint32_t first, std::uint32_t count) const { return call(leaf, first, count); }
};

template <class Tree, bool Conservative, BvhQuery Query>
[[gnu::noinline]] void wide_traverse_double_erased(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax,
                                                   WideLeafRef leaf) {
  const WideBoxTestDouble<Conservative, typename Tree::Node> test{
      BvhRay<double>(ray, Conservative ? BvhTraversal::conservative : BvhTraversal::standard), tmin};
  wide_traverse_loop<Tree, double, Query>(bvh, test, [&] { return tmax; }, leaf);
}

/// The loop with the double box test: rays out of the float path's range (and conservative queries
/// from tmin < 0), either width and node kind. The leaf is called through WideLeafRef (one indirect
/// call per leaf; a leaf's prefetch(first), where it has one, is not used on this path).
template <class Tree, bool Conservative, BvhQuery Query, class Leaf>
void wide_traverse_double(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, Leaf& leaf) {
  using L = std::remove_reference_t<Leaf>;
  const WideLeafRef ref{const_cast<void*>(static_cast<const void*>(&leaf)), [](void* l, std::uint32_t first, std::uint32_t count) {
                          return static_cast<bool>((*static_cast<L*>(l))(first, count));
                        }};
  wide_traverse_double_erased<Tree, Conservative, Query>(bvh, ray, tmin, tmax, ref);
}

/// tmax in float for the float box tests: an upper bound (float_above) when conservative.
template <bool Conservative>
[[gnu::always_inline]] inline float wide_tmax_float(double tmax) {
  return Conservative ? float_above(tmax) : static_cast<float>(tmax);
}

template <bool Conservative>
struct Bvh4BoxTest {
  Bvh4RayF ray;
  __m128 tmin;
  [[gnu::always_inline]] int operator()(const Bvh4Node& n, float tmax, float* t) const {
    __m128 te;
    const int mask = bvh4_test<Conservative>(n, ray, tmin, _mm_set1_ps(tmax), te);
    _mm_store_ps(t, te);
    return mask;
  }
};

/// The traversal of one tree type: run<Conservative, Query>(bvh, ray, tmin, tmax, leaf). The SSE
/// ones (four-wide, full and quantized) here, the AVX2 ones in bvh_wide8.h.
template <class Tree>
struct WideTraversal;

template <>
struct WideTraversal<Bvh4> {
  template <bool Conservative, BvhQuery Query, class Leaf>
  static void run(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, Leaf& leaf) {
    Bvh4RayF rf;
    if (!make_bvh4_ray(ray, Conservative, tmin, rf))  // out of range: the double box test
      return wide_traverse_double<Bvh4, Conservative, Query>(bvh, ray, tmin, tmax, leaf);
    const Bvh4BoxTest<Conservative> test{rf, _mm_set1_ps(rf.tmin)};
    wide_traverse_loop<Bvh4, float, Query>(bvh, test, [&] { return wide_tmax_float<Conservative>(tmax); }, leaf);
  }
};

template <class Tree, bool Conservative, class Leaf>
void wide_traverse_query(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhQuery query,
                         Leaf& leaf) {
  using Run = WideTraversal<Tree>;
  switch (query) {
    case BvhQuery::closest: return Run::template run<Conservative, BvhQuery::closest>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::any: return Run::template run<Conservative, BvhQuery::any>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::all: return Run::template run<Conservative, BvhQuery::all>(bvh, ray, tmin, tmax, leaf);
  }
}

}  // namespace detail

/// The traversal with whole leaves, either width and node kind (Bvh4, Bvh8, Bvh4Q, Bvh8Q):
/// `leaf_range(first, count)` gets the leaf-order slots [first, first + count) of one leaf and
/// returns true to stop (honoured for any hit); for closest hit it lowers `tmax` to the best t so
/// far. Any hit stops at the first leaf that returns true and does not sort children (slot order);
/// closest hit visits them nearest first. The eight-wide trees need bvh_wide8.h and AVX2: call it
/// only when cpu_has_avx2().
template <class Tree, class LeafRange>
  requires(Tree::kWidth == 4 || Tree::kWidth == 8)
void wide_traverse_leaves(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRange&& leaf_range) {
  if (bvh.empty()) return;
  // The float box test, or the double one for rays out of its range (decided per ray inside).
  if (mode == BvhTraversal::conservative) return detail::wide_traverse_query<Tree, true>(bvh, ray, tmin, tmax, query, leaf_range);
  return detail::wide_traverse_query<Tree, false>(bvh, ray, tmin, tmax, query, leaf_range);
}

/// wide_traverse_leaves one slot at a time: `leaf(j)` for each leaf-order slot j, true to stop (any
/// hit); for callers that keep their primitive data in leaf order (and may drop prim_ids).
template <class Tree, class Leaf>
void wide_traverse_slots(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                         BvhQuery query, Leaf&& leaf) {
  const bool any = query == BvhQuery::any;
  wide_traverse_leaves(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first, end = first + count; j < end; ++j)
      if (leaf(j) && any) return true;
    return false;
  });
}

/// Visits the leaves' primitives the query needs, as bvh_traverse (bvh_traverse.h) does: `leaf(prim)`
/// returns true to stop (any hit); for closest hit it lowers `tmax` to the best t so far. `ray` is
/// the ray the primitive kernel intersects, in double (for a float kernel: its float-rounded ray).
template <class Tree, class Leaf>
void wide_traverse(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                   BvhQuery query, Leaf&& leaf) {
  const std::uint32_t* ids = bvh.prim_ids.data();
  wide_traverse_slots(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t j) { return leaf(ids[j]); });
}

/// The four-wide (SSE) names of wide_traverse_leaves and wide_traverse.
template <class LeafRange>
void bvh4_traverse_leaves(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRange&& leaf_range) {
  wide_traverse_leaves(bvh, ray, tmin, tmax, mode, query, leaf_range);
}
template <class Leaf>
void bvh4_traverse(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                   BvhQuery query, Leaf&& leaf) {
  wide_traverse(bvh, ray, tmin, tmax, mode, query, leaf);
}

}  // namespace rayproof

// The compressed nodes (BvhWideQNode, quantize_wide, BvhNodes) and their SSE traversal.
#include "rayproof/bvh_wide_quantized.h"
