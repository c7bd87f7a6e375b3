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
/// nothing (the origin lies in the closed slab), so NaN distances are skipped, not compared.
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

/// A ray prepared for box tests: reciprocal direction and the exit scaling of its mode.
template <class T>
struct BvhRay {
  Vec3<T> o, inv;
  T pad;  ///< 0, or 2 gamma(3): the relative widening of both slab distances (conservative)

  BvhRay(const Ray<T>& r, BvhTraversal mode)
      : o(r.o),
        inv{T(1) / r.d.x, T(1) / r.d.y, T(1) / r.d.z},
        pad(mode == BvhTraversal::conservative ? T(2) * gamma<T>(3) : T(0)) {}

  /// Entry distance of the box when the segment [tmin, tmax] meets it, else +inf.
  [[nodiscard]] T enter(const BvhBox& b, T tmin, T tmax) const {
    T t0 = tmin, t1 = tmax;
    for (int k = 0; k < 3; ++k) {
      const T a = (T(b.lo[k]) - o[k]) * inv[k];
      const T c = (T(b.hi[k]) - o[k]) * inv[k];
      if (a != a || c != c) continue;  // NaN: origin on a slab plane with d_k = 0 (bounds nothing)
      T near = a < c ? a : c, far = a < c ? c : a;
      near -= pad * std::abs(near);  // widen outward: entry earlier, exit later (no-op when pad = 0)
      far += pad * std::abs(far);
      t0 = near > t0 ? near : t0;
      t1 = far < t1 ? far : t1;
    }
    return t0 <= t1 ? t0 : std::numeric_limits<T>::infinity();
  }
};

/// Visits the leaves' primitives the query needs. `leaf(prim)` intersects one primitive and
/// returns true to stop (any hit). For closest hit the callback lowers `tmax` (held by reference
/// here) to the best t so far, which prunes farther boxes; for all hits it leaves tmax alone.
template <class T, class Leaf>
void bvh_traverse(const Bvh& bvh, const Ray<T>& ray, T tmin, const T& tmax, BvhTraversal mode, BvhQuery query,
                  Leaf&& leaf) {
  if (bvh.empty()) return;
  const BvhRay<T> r(ray, mode);
  std::uint32_t local[128];
  std::vector<std::uint32_t> heap;
  std::uint32_t* stack = local;
  if (bvh.max_depth >= 127) heap.resize(static_cast<std::size_t>(bvh.max_depth) + 2), stack = heap.data();
  int top = 0;
  if (r.enter(bvh.nodes[0].box, tmin, tmax) == std::numeric_limits<T>::infinity()) return;
  std::uint32_t n = 0;
  for (;;) {
    const BvhNode& node = bvh.nodes[n];
    if (node.is_leaf()) {
      for (std::uint32_t i = node.index; i < node.index + node.count; ++i)
        if (leaf(bvh.prim_ids[i]) && query == BvhQuery::any) return;
    } else {
      const std::uint32_t a = node.index, b = node.index + 1;
      const T ta = r.enter(bvh.nodes[a].box, tmin, tmax), tb = r.enter(bvh.nodes[b].box, tmin, tmax);
      constexpr T inf = std::numeric_limits<T>::infinity();
      if (ta != inf && tb != inf) {  // both: the nearer first (the order matters for closest hit)
        const bool a_first = ta <= tb;
        stack[top++] = a_first ? b : a;
        n = a_first ? a : b;
        continue;
      }
      if (ta != inf) { n = a; continue; }
      if (tb != inf) { n = b; continue; }
    }
    // Pop, re-testing the box for closest hit: tmax may have dropped since it was pushed.
    for (;;) {
      if (top == 0) return;
      n = stack[--top];
      if (query != BvhQuery::closest || r.enter(bvh.nodes[n].box, tmin, tmax) != std::numeric_limits<T>::infinity())
        break;
    }
  }
}

}  // namespace rayproof
