#pragma once
/// BVH traversal for the three queries: closest hit (front to back, pruned by the best t so far),
/// any hit (stops at the first primitive the callback accepts) and all hits (every leaf the ray's
/// [tmin, tmax] segment meets). The caller's leaf callback intersects one primitive.
///
/// The box test is the slab test on a precomputed reciprocal direction. In conservative mode the
/// exit distance is scaled by 1 + 2 gamma(3) (Ize, "Robust BVH Ray Traversal", JCGT 2013: each slab
/// distance has at most 3 roundings: difference, reciprocal, product), so no box the exact ray
/// segment touches is culled; robust and certified kernels need that to keep their guarantees.
/// The entry distance is widened the same way, so that closest-hit pruning against an exact t
/// (exact method) never drops a box whose exact entry equals that t.
/// An axis with d_i = 0 and the origin on a slab plane gives 0 * inf = NaN: that axis bounds
/// nothing (the origin lies in the closed slab), so NaN distances are skipped: the running
/// max / min are written `x > t0 ? x : t0`, which keeps t0 when x is NaN. With the origin off the
/// slab the distances are +-inf, exact, and are not widened (inf - inf would be NaN, skipped, and
/// the axis would then reject nothing: every box of the tree visited by an axis-aligned ray).
/// Per ray, once: the reciprocal direction and its octant (which of lo / hi is the near plane per
/// axis, from the sign bit of 1/d, so -0 picks hi). Per inner node: both children (one cache
/// line), the nearer first; the stack holds (node, entry t), so closest hit drops popped nodes
/// whose entry lies beyond the best t so far without re-testing their boxes.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/float_util.h"
#include "rayproof/ray.h"

namespace rayproof {

enum class BvhTraversal { standard, conservative };
enum class BvhQuery { closest, any, all };

/// A ray prepared for box tests: reciprocal direction, near-plane offsets and the widening of its mode.
template <class T>
struct BvhRay {
  Vec3<T> o, inv;
  T pad;           ///< 0, or 2 gamma(3): the relative widening of both slab distances (conservative)
  int near_at[3];  ///< offset of the near plane of axis k in the box's floats: k (lo) or 3 + k (hi)
  int far_at[3];   ///< the other one

  BvhRay(const Ray<T>& r, BvhTraversal mode)
      : o(r.o),
        inv{T(1) / r.d.x, T(1) / r.d.y, T(1) / r.d.z},
        pad(mode == BvhTraversal::conservative ? T(2) * gamma<T>(3) : T(0)) {
    for (int k = 0; k < 3; ++k) near_at[k] = std::signbit(inv[k]) ? 3 + k : k, far_at[k] = (near_at[k] + 3) % 6;
  }

  /// Entry distance of the box when the segment [tmin, tmax] meets it, else +inf.
  template <bool Widen = true>
  [[nodiscard]] T enter(const BvhBox& b, T tmin, T tmax) const {
    static_assert(sizeof(BvhBox) == 6 * sizeof(float));
    const float* f = b.lo;  // lo[0..2] then hi[0..2]
    T t0 = tmin, t1 = tmax;
    for (int k = 0; k < 3; ++k) {
      T near = (T(f[near_at[k]]) - o[k]) * inv[k];
      T far = (T(f[far_at[k]]) - o[k]) * inv[k];
      if constexpr (Widen) {
        // An infinite distance (d_k = 0, the origin outside the slab) is exact and stays: widening
        // it would give inf - inf = NaN, which the max / min skip, and the axis would reject no box.
        const T nw = near - pad * std::abs(near), fw = far + pad * std::abs(far);
        near = std::isinf(near) ? near : nw;
        far = std::isinf(far) ? far : fw;
      }
      t0 = near > t0 ? near : t0;  // NaN near / far: skipped
      t1 = far < t1 ? far : t1;
    }
    return t0 <= t1 ? t0 : std::numeric_limits<T>::infinity();
  }
};

namespace detail {

template <class T, bool Conservative, BvhQuery Query, class Leaf>
void bvh_traverse_impl(const Bvh& bvh, const BvhRay<T>& r, T tmin, const T& tmax, Leaf& leaf) {
  constexpr T inf = std::numeric_limits<T>::infinity();
  struct Entry {
    std::uint32_t node;
    T t;
  };
  Entry local[128];
  std::vector<Entry> heap;
  Entry* stack = local;
  if (bvh.max_depth >= 127) heap.resize(static_cast<std::size_t>(bvh.max_depth) + 2), stack = heap.data();
  int top = 0;
  if (r.template enter<Conservative>(bvh.nodes[0].box, tmin, tmax) == inf) return;
  const BvhNode* nodes = bvh.nodes.data();
  const std::uint32_t* ids = bvh.prim_ids.data();
  std::uint32_t n = 0;
  for (;;) {
    const BvhNode& node = nodes[n];
    if (node.is_leaf()) {
      for (std::uint32_t i = node.index, e = node.index + node.count; i < e; ++i)
        if (leaf(ids[i]) && Query == BvhQuery::any) return;
    } else {
      const std::uint32_t a = node.index, b = node.index + 1;
      const T ta = r.template enter<Conservative>(nodes[a].box, tmin, tmax);
      const T tb = r.template enter<Conservative>(nodes[b].box, tmin, tmax);
      if (ta != inf && tb != inf) {  // both: the nearer first (the order matters for closest hit)
        const bool a_first = ta <= tb;
        stack[top++] = a_first ? Entry{b, tb} : Entry{a, ta};
        n = a_first ? a : b;
        continue;
      }
      if (ta != inf) { n = a; continue; }
      if (tb != inf) { n = b; continue; }
    }
    // Pop; for closest hit skip entries beyond tmax (it may have dropped since the push). The entry
    // t was computed with the same widening, so this drops only what a re-test would.
    for (;;) {
      if (top == 0) return;
      const Entry e = stack[--top];
      if (Query != BvhQuery::closest || e.t <= tmax) {
        n = e.node;
        break;
      }
    }
  }
}

template <class T, bool Conservative, class Leaf>
void bvh_traverse_query(const Bvh& bvh, const BvhRay<T>& r, T tmin, const T& tmax, BvhQuery query, Leaf& leaf) {
  switch (query) {
    case BvhQuery::closest: return bvh_traverse_impl<T, Conservative, BvhQuery::closest>(bvh, r, tmin, tmax, leaf);
    case BvhQuery::any: return bvh_traverse_impl<T, Conservative, BvhQuery::any>(bvh, r, tmin, tmax, leaf);
    case BvhQuery::all: return bvh_traverse_impl<T, Conservative, BvhQuery::all>(bvh, r, tmin, tmax, leaf);
  }
}

}  // namespace detail

/// Visits the leaves' primitives the query needs. `leaf(prim)` intersects one primitive and
/// returns true to stop (any hit). For closest hit the callback lowers `tmax` (held by reference
/// here) to the best t so far, which prunes farther boxes; for all hits it leaves tmax alone.
template <class T, class Leaf>
void bvh_traverse(const Bvh& bvh, const Ray<T>& ray, T tmin, const T& tmax, BvhTraversal mode, BvhQuery query,
                  Leaf&& leaf) {
  if (bvh.empty()) return;
  const BvhRay<T> r(ray, mode);
  if (mode == BvhTraversal::conservative) {
    detail::bvh_traverse_query<T, true>(bvh, r, tmin, tmax, query, leaf);
  } else {
    detail::bvh_traverse_query<T, false>(bvh, r, tmin, tmax, query, leaf);
  }
}

}  // namespace rayproof
