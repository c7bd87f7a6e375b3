#pragma once
/// The closest-point tree of an ExactMesh (internal to rayproof_scene_certified): a binary BVH
/// with double boxes (exact bounds of the vertices) over the triangles, stored in leaf order, the
/// same tree collapsed to eight (AVX2) or four (SSE) children per node for the first pass
/// (distance_wide.cpp), and the exact stage's helpers (distance_exact.cpp).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_wide8.h"
#include "rayproof/scene/distance.h"
#include "rayproof/vec3.h"

namespace rayproof::scene::detail {

/// 32 bytes: the two children of a node share a cache line. The bounds are the exact double
/// bounds of the triangles rounded outwards to float (beyond the float range: +-inf).
struct alignas(32) DistanceNode {
  float lo[3], hi[3];
  std::uint32_t index = 0;  ///< inner: first child (the second follows); leaf: first slot
  std::uint32_t count = 0;  ///< 0: inner node; else the leaf's triangles
};

struct DistanceTree {
  std::vector<DistanceNode, AlignedAllocator<DistanceNode, 64>> nodes;                   ///< nodes[0] is the root (none for no triangles)
  std::vector<std::array<Vec3<double>, 3>> tris;     ///< triangles in leaf order
  std::vector<std::uint32_t> ids;                    ///< slot -> triangle index (file order)
  std::vector<std::uint8_t> degenerate;              ///< slot -> zero area, exactly (collinear vertices)
  std::vector<std::uint32_t> slot_of;                ///< triangle index -> slot
  /// The binary tree collapsed (the same leaves, slots and float boxes): wide8 on the AVX2 path
  /// (bvh_simd_path()), else wide4; the other one stays empty.
  Bvh8 wide8;
  Bvh4 wide4;
  /// For meshes far from scale 1 (largest coordinate beyond 2^+-200): the same tree over the
  /// vertices times 2^-scale_exp, when that scaling is exact for every vertex (no subnormal); the
  /// query goes there when the double filter over- or underflows and the point scales exactly.
  std::shared_ptr<const DistanceTree> scaled;
  int scale_exp = 0;
};

/// Parts of the query that `bench distance` turns off one at a time to measure each one's effect
/// (ablation; the answers are the same either way). Process-wide: set it only between queries.
enum DistanceAblation : unsigned {
  kAblateNone = 0,
  kAblateWide = 1,   ///< the first pass on the binary tree (scalar double boxes) instead of the wide one
  kAblateOrder = 2,  ///< batches in input order instead of Morton order
  kAblateHint = 4,   ///< no first bound from the previous answer
  kAblateLower = 8,  ///< the ball pass on every triangle whose box is within U (no lower bound along a direction)
  kAblateLanes = 16, ///< the wide first pass's leaves one triangle at a time instead of four in AVX2 lanes
};
void set_distance_ablation(unsigned flags);
[[nodiscard]] unsigned distance_ablation();

struct ExactMeshState;
/// The mesh's distance tree, built by the first call (thread-safe).
[[nodiscard]] const DistanceTree& distance_tree(const ExactMeshState& s);
/// The closest-point query (distance.cpp); `hint`: a slot whose triangle is likely near p (a batch's
/// previous answer; 0xffffffff for none), for the first bound only: the answer does not depend on it.
[[nodiscard]] ClosestPoint distance_query(const DistanceTree& t, const Vec3<double>& p, std::uint32_t hint);

[[nodiscard]] DistanceTree build_distance_tree(const std::vector<Vec3<double>>& v,
                                               const std::vector<std::array<std::uint32_t, 3>>& tris);

/// Among `slots`, the triangle nearest p exactly (ties: lowest id) and its result (distance
/// correctly rounded, point, barycentrics).
[[nodiscard]] ClosestPoint exact_select(const DistanceTree& t, const Vec3<double>& p, const std::uint32_t* slots,
                                        std::size_t n);
/// The exact search over the whole tree (box bounds in rationals): for inputs the filter cannot
/// handle (over- or underflow).
[[nodiscard]] ClosestPoint exact_search(const DistanceTree& t, const Vec3<double>& p);

}  // namespace rayproof::scene::detail
