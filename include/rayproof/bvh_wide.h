#pragma once
/// Four-wide BVH: the binary tree of bvh_build.h collapsed into nodes of up to four children whose
/// boxes are tested together with SSE (the path for CPUs without AVX2; bvh_wide8.h has the eight-wide
/// AVX2 one). Closest hit visits children nearest first (any and all hits in slot order); the stack holds (child, entry t) so
/// closest hit drops popped children whose entry lies beyond the best t so far.
///
/// Node layout (128 bytes, two cache lines): per axis the four children's lo then hi planes
/// (structure of arrays, one SSE load per plane), then per child its reference: an inner child is a
/// node index, a leaf child is a range [first, first + count) of prim_ids (count 1..255; count 0
/// marks an inner child). Unused slots have empty boxes and a clear bit in `valid`.
///
/// Box tests. The ray is given in double; the traversal runs in float when the ray is within range:
///  - standard: the slab test on the float-rounded ray (what a float kernel intersects).
///  - conservative (Ize, "Robust BVH Ray Traversal", JCGT 2013): every box the exact double segment
///    [tmin, tmax] touches passes. Per axis the origin is replaced by a float bound on the side that
///    lowers the near distance and raises the far one (a float >= o for the near plane when 1/d > 0,
///    <= o when 1/d < 0, and the reverse for the far plane; see make_bvh4_ray), so the rounded
///    distances bound the exact ones before any arithmetic error; the float distance then carries four roundings
///    (difference, double reciprocal, float rounding of it, product): near is scaled towards -inf
///    and far towards +inf by 2 gamma(4) (float) and moved by an absolute 2^-120 for underflow.
///    tmin is rounded down and tmax up to float.
///    NaN distances (an axis with d = 0 and the origin on a slab plane: 0 * inf) are skipped, as in
///    bvh_traverse.h: `_mm_max_ps(x, t0)` returns t0 when x is NaN.
///  - Rays out of the float path's range (|o| > 2^64, or a nonzero |d| outside [2^-64, 2^64]) are
///    traversed with the scalar double box test of bvh_traverse.h on the same nodes.
#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_traverse.h"

namespace rayproof {

struct alignas(64) Bvh4Node {
  float lo[3][4];  ///< lo[axis][child]
  float hi[3][4];  ///< hi[axis][child]
  std::uint32_t child[4] = {0, 0, 0, 0};  ///< inner: node index; leaf: first prim_ids entry
  std::uint8_t count[4] = {0, 0, 0, 0};   ///< 0: inner child; else primitives in the leaf
  std::uint8_t valid = 0;                 ///< bit i: slot i is used
  std::uint8_t pad_[11] = {};

  Bvh4Node() {
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 4; ++i) lo[k][i] = std::numeric_limits<float>::infinity(), hi[k][i] = -std::numeric_limits<float>::infinity();
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
static_assert(sizeof(Bvh4Node) == 128);

struct Bvh4 {
  static constexpr std::uint32_t kMaxLeaf = 255;
  std::vector<Bvh4Node, AlignedAllocator<Bvh4Node, 64>> nodes;  ///< nodes[0] is the root (absent when empty)
  std::vector<std::uint32_t> prim_ids;                          ///< primitive indices, leaf by leaf
  int max_depth = 0;                                            ///< nodes on the longest root-to-leaf path

  [[nodiscard]] bool empty() const { return nodes.empty(); }
  [[nodiscard]] std::size_t bytes() const {
    return nodes.size() * sizeof(Bvh4Node) + prim_ids.size() * sizeof(std::uint32_t);
  }
};

namespace detail {

/// Splits a leaf range of more than kMaxLeaf primitives into a subtree of wide nodes (chunks in
/// prim_ids order, boxes from the primitives' bounds); returns the new node's index.
inline std::uint32_t bvh4_chunk(Bvh4& w, std::span<const BvhBox> prim_boxes, std::uint32_t first, std::uint32_t count,
                                int depth, int& max_depth) {
  const auto id = static_cast<std::uint32_t>(w.nodes.size());
  w.nodes.emplace_back();
  max_depth = std::max(max_depth, depth);
  const std::uint32_t part = (count + 3) / 4;
  int slot = 0;
  for (std::uint32_t b = first; b < first + count; b += part, ++slot) {
    const std::uint32_t n = std::min(part, first + count - b);
    BvhBox box;
    for (std::uint32_t i = b; i < b + n; ++i) box.extend(prim_boxes[w.prim_ids[i]]);
    std::uint32_t ref = b;
    std::uint8_t cnt = static_cast<std::uint8_t>(n);
    if (n > Bvh4::kMaxLeaf) ref = bvh4_chunk(w, prim_boxes, b, n, depth + 1, max_depth), cnt = 0;
    Bvh4Node& node = w.nodes[id];
    node.set_box(slot, box);
    node.child[slot] = ref, node.count[slot] = cnt, node.valid |= std::uint8_t(1u << slot);
  }
  return id;
}

}  // namespace detail

/// Collapses a binary BVH into a four-wide one: each wide node takes a binary node's children and
/// opens the inner child of largest surface area until it has four (or only leaves are left).
/// `prim_boxes` (indexed by primitive) bound leaves of more than Bvh4::kMaxLeaf primitives, which
/// are split. The binary tree's prim_ids become the wide tree's (moved out of `bin`).
[[nodiscard]] inline Bvh4 collapse_bvh4(Bvh&& bin, std::span<const BvhBox> prim_boxes) {
  Bvh4 w;
  if (bin.empty()) return w;
  w.prim_ids = std::move(bin.prim_ids);
  if (w.prim_ids.size() >= (std::size_t(1) << 31)) throw std::length_error("BVH: too many primitives");
  w.nodes.reserve(bin.nodes.size() / 3 + 2);
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
    Bvh4Node& n = w.nodes[0];
    n.set_box(0, root.box), n.valid = 1;
    if (root.count > Bvh4::kMaxLeaf) {
      w.nodes.clear();
      detail::bvh4_chunk(w, prim_boxes, root.index, root.count, 1, max_depth);
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
    std::uint32_t kids[4] = {bin.nodes[t.bin].index, bin.nodes[t.bin].index + 1, 0, 0};
    int nk = 2;
    while (nk < 4) {
      int best = -1;
      float best_area = -1;
      for (int i = 0; i < nk; ++i) {
        const BvhNode& c = bin.nodes[kids[i]];
        if (!c.is_leaf() && c.box.half_area() > best_area) best = i, best_area = c.box.half_area();
      }
      if (best < 0) break;
      const std::uint32_t first = bin.nodes[kids[best]].index;
      kids[best] = first, kids[nk++] = first + 1;
    }
    for (int i = 0; i < nk; ++i) {
      const BvhNode& c = bin.nodes[kids[i]];
      std::uint32_t ref = 0;
      std::uint8_t cnt = 0;
      if (c.is_leaf() && c.count <= Bvh4::kMaxLeaf) {
        ref = c.index, cnt = static_cast<std::uint8_t>(c.count);
      } else if (c.is_leaf()) {
        ref = detail::bvh4_chunk(w, prim_boxes, c.index, c.count, t.depth + 1, max_depth);
      } else {
        ref = static_cast<std::uint32_t>(w.nodes.size());
        w.nodes.emplace_back();
        stack.push_back({kids[i], ref, t.depth + 1});
      }
      Bvh4Node& n = w.nodes[t.wide];
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

/// A ray prepared for the SSE box test of four children.
struct Bvh4RayF {
  __m128 o_near[3], o_far[3], inv[3];
  int near_off[3], far_off[3];  ///< float offsets of the near / far planes of axis k in the node
  float tmin;
};

inline float round_down_f(double x) { return bvh_float_down(x); }
inline float round_up_f(double x) { return bvh_float_up(x); }

/// Prepares the float box test of the double ray; false when the ray is out of the float path's
/// range (see the header comment: NaN, |o| > 2^64, or a nonzero |d| outside [2^-64, 2^64]).
/// Conservative: the origin bounds are o -/+ (|o| 2^-23 + 2^-148) computed in double, then rounded
/// to the nearest float. That float is <= o (resp. >= o): the offset is at least one float ulp of o
/// (ulp(o) <= |o| 2^-23 for normal floats, 2^-149 below them), and rounding to nearest moves by at
/// most half an ulp; the double operations' own roundings (2^-53 relative) are far inside that.
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
  const __m128d one = _mm_set1_pd(1.0);
  const __m128 inv = _mm_movelh_ps(_mm_cvtpd_ps(_mm_div_pd(one, dxy)), _mm_cvtpd_ps(_mm_div_sd(one, dz)));
  __m128 o_lo, o_hi;
  if (conservative) {
    const __m128d ulp = _mm_set1_pd(0x1p-23), tiny = _mm_set1_pd(0x1p-148);
    const __m128d exy = _mm_add_pd(_mm_mul_pd(aoxy, ulp), tiny), ez = _mm_add_pd(_mm_mul_pd(aoz, ulp), tiny);
    o_lo = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(oxy, exy)), _mm_cvtpd_ps(_mm_sub_pd(oz, ez)));
    o_hi = _mm_movelh_ps(_mm_cvtpd_ps(_mm_add_pd(oxy, exy)), _mm_cvtpd_ps(_mm_add_pd(oz, ez)));
  } else {
    o_lo = o_hi = _mm_movelh_ps(_mm_cvtpd_ps(oxy), _mm_cvtpd_ps(oz));
  }
  // 1/d < 0 (d < 0 or d = -0): the near plane is hi, and the near distance wants the lower origin.
  const __m128 neg = _mm_cmplt_ps(inv, _mm_setzero_ps());
  const __m128 o_near = _mm_or_ps(_mm_and_ps(neg, o_lo), _mm_andnot_ps(neg, o_hi));
  const __m128 o_far = _mm_or_ps(_mm_and_ps(neg, o_hi), _mm_andnot_ps(neg, o_lo));
  const int negs = _mm_movemask_ps(neg);
  out.o_near[0] = _mm_shuffle_ps(o_near, o_near, 0x00), out.o_far[0] = _mm_shuffle_ps(o_far, o_far, 0x00);
  out.o_near[1] = _mm_shuffle_ps(o_near, o_near, 0x55), out.o_far[1] = _mm_shuffle_ps(o_far, o_far, 0x55);
  out.o_near[2] = _mm_shuffle_ps(o_near, o_near, 0xaa), out.o_far[2] = _mm_shuffle_ps(o_far, o_far, 0xaa);
  out.inv[0] = _mm_shuffle_ps(inv, inv, 0x00), out.inv[1] = _mm_shuffle_ps(inv, inv, 0x55), out.inv[2] = _mm_shuffle_ps(inv, inv, 0xaa);
  for (int k = 0; k < 3; ++k) {
    // Within an axis: lo[k] at float offset 4k, hi[k] at 12 + 4k.
    const bool n = negs >> k & 1;
    out.near_off[k] = n ? 12 + 4 * k : 4 * k;
    out.far_off[k] = n ? 4 * k : 12 + 4 * k;
  }
  out.tmin = conservative ? round_down_f(tmin) : static_cast<float>(tmin);
  return true;
}

/// Hit mask of the four children of `n` and their entry distances.
/// Conservative widening is applied once to the largest near and the smallest far distance: the
/// widening w(x) = x * (x < 0 ? 1 + 8u : 1 - 8u) - 2^-120 (and its mirror for far) is monotonic
/// in float (rounded products by a positive constant and a rounded subtraction of a constant are
/// monotonic), so w(max_k near_k) = max_k w(near_k): the same result as widening every axis.
template <bool Conservative>
inline int bvh4_test(const Bvh4Node& n, const Bvh4RayF& r, __m128 tmin, __m128 tmax, __m128& t_enter) {
  const float* f = &n.lo[0][0];
  const __m128 ninf = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  const __m128 pinf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 t0 = Conservative ? ninf : tmin, t1 = Conservative ? pinf : tmax;
  for (int k = 0; k < 3; ++k) {
    const __m128 near = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(f + r.near_off[k]), r.o_near[k]), r.inv[k]);
    const __m128 far = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(f + r.far_off[k]), r.o_far[k]), r.inv[k]);
    t0 = _mm_max_ps(near, t0);  // NaN near: t0 (the axis bounds nothing)
    t1 = _mm_min_ps(far, t1);   // NaN far: t1
  }
  if constexpr (Conservative) {
    // 1 -/+ 2 gamma(4) (float): 1 - 8u and 1 + 8u, both exact in float (u = 2^-24); the
    // distance's own error is at most gamma(4) ~ 4u and the scaling product's rounding u more.
    // Finite stays finite, inf stays inf (no inf - inf).
    const __m128 shrink = _mm_set1_ps(1.0f - 0x1p-21f), grow = _mm_set1_ps(1.0f + 0x1p-21f);
    const __m128 tiny = _mm_set1_ps(0x1p-120f);
    const __m128 t0_neg = _mm_cmplt_ps(t0, _mm_setzero_ps()), t1_neg = _mm_cmplt_ps(t1, _mm_setzero_ps());
    t0 = _mm_sub_ps(_mm_mul_ps(t0, _mm_or_ps(_mm_and_ps(t0_neg, grow), _mm_andnot_ps(t0_neg, shrink))), tiny);
    t1 = _mm_add_ps(_mm_mul_ps(t1, _mm_or_ps(_mm_and_ps(t1_neg, shrink), _mm_andnot_ps(t1_neg, grow))), tiny);
    t0 = _mm_max_ps(t0, tmin);
    t1 = _mm_min_ps(t1, tmax);
  }
  t_enter = t0;
  return _mm_movemask_ps(_mm_cmple_ps(t0, t1)) & n.valid;
}

/// The scalar double test of the same four children (rays out of the float path's range).
template <bool Conservative>
inline int bvh4_test_double(const Bvh4Node& n, const BvhRay<double>& r, double tmin, double tmax, double t_enter[4]) {
  int mask = 0;
  for (int i = 0; i < 4; ++i) {
    if (!(n.valid >> i & 1)) continue;
    t_enter[i] = r.template enter<Conservative>(n.box(i), tmin, tmax);
    if (t_enter[i] != std::numeric_limits<double>::infinity()) mask |= 1 << i;
  }
  return mask;
}

template <class T>
struct Bvh4Entry {
  std::uint32_t ref;
  std::uint32_t count;  ///< 0: inner node
  T t;
};

/// Pushes the hit children of `n` (mask, two or more bits) on the stack, farthest first, so the
/// nearest is on top; prefetches inner children's nodes.
template <class T>
[[gnu::always_inline]] inline void bvh4_push_sorted(const Bvh4Node& n, const Bvh4Node* nodes, int mask, const T* t,
                                                    Bvh4Entry<T>* stack, int& top) {
  Bvh4Entry<T> e[4];
  int m = 0;
  while (mask) {
    const int i = __builtin_ctz(static_cast<unsigned>(mask));
    mask &= mask - 1;
    Bvh4Entry<T> x{n.child[i], n.count[i], t[i]};
    if (!x.count) {
      _mm_prefetch(reinterpret_cast<const char*>(nodes + x.ref), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(nodes + x.ref) + 64, _MM_HINT_T0);
    }
    int j = m++;
    for (; j > 0 && e[j - 1].t < x.t; --j) e[j] = e[j - 1];  // descending t
    e[j] = x;
  }
  for (int i = 0; i < m; ++i) stack[top++] = e[i];
}

/// The traversal loop, for the float (T = float) and double (T = double) box tests. `leaf(first,
/// count)` gets the leaf-order slots [first, first + count) (indices into prim_ids, or into the
/// caller's own leaf-order data) and returns true to stop (any hit).
template <class T, bool Conservative, BvhQuery Query, class Leaf>
void bvh4_traverse_impl(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, Leaf& leaf) {
  using Entry = Bvh4Entry<T>;
  Entry local[192];
  std::vector<Entry> heap;
  Entry* stack = local;
  const std::size_t need = 3 * static_cast<std::size_t>(bvh.max_depth) + 8;
  if (need > 192) heap.resize(need), stack = heap.data();
  int top = 0;
  const Bvh4Node* nodes = bvh.nodes.data();
  auto tmax_t = [&]() -> T {
    if constexpr (std::is_same_v<T, float>) {
      return Conservative ? round_up_f(tmax) : static_cast<float>(tmax);
    } else {
      return tmax;
    }
  };
  [[maybe_unused]] Bvh4RayF rf;
  [[maybe_unused]] __m128 tmin_v{};
  struct NoRay {};
  [[maybe_unused]] const std::conditional_t<std::is_same_v<T, float>, NoRay, BvhRay<double>> rd = [&] {
    if constexpr (std::is_same_v<T, float>) {
      return NoRay{};
    } else {
      return BvhRay<double>(ray, Conservative ? BvhTraversal::conservative : BvhTraversal::standard);
    }
  }();
  if constexpr (std::is_same_v<T, float>) {
    if (!make_bvh4_ray(ray, Conservative, tmin, rf)) {  // out of range: the double box test
      bvh4_traverse_impl<double, Conservative, Query>(bvh, ray, tmin, tmax, leaf);
      return;
    }
    tmin_v = _mm_set1_ps(rf.tmin);
  }
  T tmax_cur = tmax_t();
  // `e` is the child being visited (its entry already checked against tmax); a visit that ends
  // a path pops the next child whose entry is still within tmax.
  Entry e{0, 0, static_cast<T>(-std::numeric_limits<T>::infinity())};
  if (Query == BvhQuery::closest && !(e.t <= tmax_cur)) return;  // NaN tmax
  for (;;) {
    if (e.count) {
      if (leaf(e.ref, e.count) && Query == BvhQuery::any) return;
      if constexpr (Query == BvhQuery::closest) tmax_cur = tmax_t();
    } else {
      const Bvh4Node& n = nodes[e.ref];
      alignas(16) T t[4];
      int mask;
      if constexpr (std::is_same_v<T, float>) {
        __m128 te;
        mask = bvh4_test<Conservative>(n, rf, tmin_v, _mm_set1_ps(tmax_cur), te);
        _mm_store_ps(t, te);
      } else {
        mask = bvh4_test_double<Conservative>(n, rd, tmin, tmax_cur, t);
      }
      if (mask) {
        if ((mask & (mask - 1)) == 0) {  // one child: straight to it
          const int i = __builtin_ctz(static_cast<unsigned>(mask));
          e = Entry{n.child[i], n.count[i], t[i]};
        } else if constexpr (Query == BvhQuery::closest) {  // several: the nearest next, the farther ones on the stack
          bvh4_push_sorted(n, nodes, mask, t, stack, top);
          e = stack[--top];
        } else {  // any / all: no order needed, slot order
          for (int m = mask; m; m &= m - 1) {
            const int i = __builtin_ctz(static_cast<unsigned>(m));
            stack[top++] = Entry{n.child[i], n.count[i], t[i]};
          }
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

template <class T, bool Conservative, class Leaf>
void bvh4_traverse_query(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhQuery query, Leaf& leaf) {
  switch (query) {
    case BvhQuery::closest: return bvh4_traverse_impl<T, Conservative, BvhQuery::closest>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::any: return bvh4_traverse_impl<T, Conservative, BvhQuery::any>(bvh, ray, tmin, tmax, leaf);
    case BvhQuery::all: return bvh4_traverse_impl<T, Conservative, BvhQuery::all>(bvh, ray, tmin, tmax, leaf);
  }
}

}  // namespace detail

/// The traversal with whole leaves: `leaf_range(first, count)` gets the leaf-order slots
/// [first, first + count) of one leaf and returns true to stop (honoured for any hit); for closest
/// hit it lowers `tmax` to the best t so far. Any hit stops at the first leaf that returns true and
/// does not sort children (slot order); closest hit visits them nearest first.
template <class LeafRange>
void bvh4_traverse_leaves(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRange&& leaf_range) {
  if (bvh.empty()) return;
  // The float box test, or the double one for rays out of its range (decided per ray inside).
  if (mode == BvhTraversal::conservative)
    return detail::bvh4_traverse_query<float, true>(bvh, ray, tmin, tmax, query, leaf_range);
  return detail::bvh4_traverse_query<float, false>(bvh, ray, tmin, tmax, query, leaf_range);
}

/// bvh4_traverse calling `leaf(j)` with the leaf-order slot j instead of the primitive prim_ids[j]:
/// for callers that keep their primitive data in leaf order (and may drop prim_ids).
template <class Leaf>
void bvh4_traverse_slots(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                         BvhQuery query, Leaf&& leaf) {
  const bool any = query == BvhQuery::any;
  bvh4_traverse_leaves(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first, end = first + count; j < end; ++j)
      if (leaf(j) && any) return true;
    return false;
  });
}

/// bvh4_traverse_leaves under the name the leaf kernels (src/scene/leaf_simd.h) first used.
template <class LeafRangeFn>
void bvh4_traverse_ranges(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRangeFn&& leaf_range) {
  bvh4_traverse_leaves(bvh, ray, tmin, tmax, mode, query, leaf_range);
}

/// Visits the leaves' primitives the query needs, as bvh_traverse (bvh_traverse.h) does: `leaf(prim)`
/// returns true to stop (any hit); for closest hit it lowers `tmax` to the best t so far. `ray` is
/// the ray the primitive kernel intersects, in double (for a float kernel: its float-rounded ray).
template <class Leaf>
void bvh4_traverse(const Bvh4& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                   BvhQuery query, Leaf&& leaf) {
  const std::uint32_t* ids = bvh.prim_ids.data();
  bvh4_traverse_slots(bvh, ray, tmin, tmax, mode, query, [&](std::uint32_t j) { return leaf(ids[j]); });
}

}  // namespace rayproof
