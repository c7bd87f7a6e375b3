#pragma once
/// Bounding volume hierarchy: the node layout and the primitive order, shared by the builders
/// (bvh_build.h) and the traversals (bvh_traverse.h). Nodes are 32 bytes: float bounds rounded
/// outward (they contain the double primitives they bound) and one index: the first child of an
/// inner node (its sibling follows it) or the first entry of prim_ids of a leaf.
/// Siblings share one 64-byte cache line: the node array is 64-byte aligned and every pair starts
/// at an even index (nodes[1] is a copy of the root, so the root's children are nodes[2], [3]).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof {

/// The float next to f towards +inf / -inf (f not NaN): integer steps on the bits, no libm call.
inline float bvh_next_up(float f) {
  if (f == std::numeric_limits<float>::infinity()) return f;
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  u = f > 0.0f ? u + 1 : u - 1;
  std::memcpy(&f, &u, 4);
  return f;
}
inline float bvh_next_down(float f) { return -bvh_next_up(-f); }
/// x rounded to a float towards -inf / +inf (x not NaN).
inline float bvh_float_down(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? bvh_next_down(f) : f;
}
inline float bvh_float_up(double x) {
  const float f = static_cast<float>(x);
  return double(f) < x ? bvh_next_up(f) : f;
}

/// Axis-aligned bounds in float; an empty box has lo = +inf, hi = -inf.
struct BvhBox {
  float lo[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                 std::numeric_limits<float>::infinity()};
  float hi[3] = {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                 -std::numeric_limits<float>::infinity()};

  void extend(const BvhBox& b) {
    // Plain comparisons (minss / maxss), not fmin / fmax: bounds are never NaN.
    for (int k = 0; k < 3; ++k) lo[k] = b.lo[k] < lo[k] ? b.lo[k] : lo[k], hi[k] = b.hi[k] > hi[k] ? b.hi[k] : hi[k];
  }
  /// Grows the box to contain a double point: float bounds rounded down / up, never inward.
  void extend(const Vec3<double>& p) {
    for (int k = 0; k < 3; ++k) {
      const float l = bvh_float_down(p[k]), h = bvh_float_up(p[k]);
      // NaN coordinates leave the box alone (as fmin / fmax did).
      lo[k] = l < lo[k] ? l : lo[k], hi[k] = h > hi[k] ? h : hi[k];
    }
  }
  [[nodiscard]] bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  [[nodiscard]] float half_area() const {
    if (empty()) return 0.0f;
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }
  [[nodiscard]] int longest_axis() const {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx >= dy ? (dx >= dz ? 0 : 2) : (dy >= dz ? 1 : 2);
  }
};

struct BvhNode {
  BvhBox box;
  std::uint32_t index = 0;  ///< inner: first child (the second is index + 1); leaf: first prim_ids entry
  std::uint32_t count = 0;  ///< 0 for an inner node, else the number of primitives in the leaf
  [[nodiscard]] bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhNode) == 32);

/// Allocator with a fixed alignment (a cache line for the nodes).
template <class T, std::size_t Align>
struct AlignedAllocator {
  using value_type = T;
  template <class U> struct rebind { using other = AlignedAllocator<U, Align>; };
  AlignedAllocator() = default;
  template <class U> AlignedAllocator(const AlignedAllocator<U, Align>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(Align))); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(Align)); }
  template <class U> bool operator==(const AlignedAllocator<U, Align>&) const { return true; }
};

struct Bvh {
  std::vector<BvhNode, AlignedAllocator<BvhNode, 64>> nodes;  ///< nodes[0] is the root (absent for an empty BVH)
  std::vector<std::uint32_t> prim_ids;  ///< primitive indices, leaf by leaf
  int max_depth = 0;                    ///< depth(), stored by the builders for the traversal stacks

  [[nodiscard]] bool empty() const { return nodes.empty(); }
  [[nodiscard]] std::size_t bytes() const {
    return nodes.size() * sizeof(BvhNode) + prim_ids.size() * sizeof(std::uint32_t);
  }
  /// Depth of the deepest leaf (root = 1); traversal stacks must hold that many entries.
  [[nodiscard]] int depth() const {
    if (nodes.empty()) return 0;
    int best = 0;
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
    while (!stack.empty()) {
      const auto [n, d] = stack.back();
      stack.pop_back();
      if (d > best) best = d;
      if (!nodes[n].is_leaf()) stack.push_back({nodes[n].index, d + 1}), stack.push_back({nodes[n].index + 1, d + 1});
    }
    return best;
  }
};

}  // namespace rayproof
