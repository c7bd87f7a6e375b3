#pragma once
/// What a rayproof::ExactMesh holds (internal to rayproof_scene_certified): packed copies of the
/// vertices and triangles, the closure report, the bounding box and the BVH over the copies.
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rayproof/scene/exact_mesh.h"
#include "scene/accel.h"
#include "scene/winding_tree.h"

namespace rayproof::scene::detail {

struct DistanceTree;  // scene/distance_tree.h

/// Edges of nonzero length after welding equal vertices: used an odd number of times (open), or
/// an even number but not as often in each direction (misoriented). Examples: welded vertex
/// numbers and the number of triangles using the edge.
struct ClosureReport {
  std::size_t open_edges = 0, misoriented_edges = 0;
  std::array<std::uint32_t, 3> open_example{}, misoriented_example{};
};

struct ExactMeshState {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  ClosureReport closure;
  ContainsRule rule = ContainsRule::nonzero;
  Vec3<double> lo{0, 0, 0}, hi{-1, -1, -1};  ///< the bounding box of the used vertices (empty: lo > hi)
  std::optional<scene::Accel> accel;
  /// The triangles' vertices in the BVH's leaf order (slot j: leaf_prims()[j]; padding slots
  /// zero), read contiguously by the point query instead of through the vertex indices.
  std::vector<std::array<Vec3<double>, 3>> slots;
  /// Slot j's triangle number (leaf_prims()[j].id, 4 bytes a slot: 16 slots a cache line), read
  /// for the crossings' candidates and prefetched with the leaf.
  std::vector<std::uint32_t> slot_ids;
  /// The generalized winding number's tree: built for meshes that are not closed and oriented.
  std::unique_ptr<WindingTree> tree;
  /// The winding rule's fast path (winding_caps.cpp): the mesh closed by caps over its boundary
  /// (its exact integer winding number) and a tree over the caps alone.
  std::unique_ptr<ExactMeshState> capped;
  std::unique_ptr<WindingTree> caps;
  /// The caps' winding number over an octree of capped's box (winding_field.cpp): built by the
  /// first batch of contains large enough for it to pay (prepare_caps_field), then read by every
  /// winding_side.
  bool caps_field = false;  ///< WindingTuning::caps_field when the caps were built
  mutable std::once_flag field_once;
  mutable std::unique_ptr<CapsField> field_owned;
  mutable std::atomic<const CapsField*> field{nullptr};
  /// The closest-point tree (distance.cpp), built by the first distance query.
  mutable std::once_flag distance_once;
  mutable std::shared_ptr<const DistanceTree> distance;
};

/// p in the closed bounding box of the mesh's used vertices.
[[nodiscard]] inline bool in_box(const ExactMeshState& s, const Vec3<double>& p) { return in_closed_box(s.lo, s.hi, p); }

/// The side of p through the perturbed ray: the winding number (nonzero rule) and crossing count.
struct PointQuery {
  bool surface = false;
  std::int32_t winding = 0;
  std::uint32_t crossings = 0;
};
/// The perturbed ray's count at p (finite, inside the closed bounding box; contains.cpp).
[[nodiscard]] PointQuery query_point(const ExactMeshState& s, const Vec3<double>& p);
/// Builds s.capped and s.caps when the caps close the mesh (winding_caps.cpp).
void build_caps(ExactMeshState& s);
/// Builds s.field once, for caps of 16 triangles or more, its cells spent where a batch's points
/// are (n points of 3 doubles, `stride` bytes apart; winding_caps.cpp; thread-safe).
void prepare_caps_field(const ExactMeshState& s, const std::byte* xyz, std::size_t n, std::size_t stride);
/// The winding rule's side of a finite p (winding_caps.cpp).
[[nodiscard]] Side winding_side(const ExactMeshState& s, const Vec3<double>& p);

[[nodiscard]] ClosureReport check_closure(const std::vector<Vec3<double>>& v,
                                          const std::vector<std::array<std::uint32_t, 3>>& tris);
/// "vertex A (x, y, z) - vertex B (x, y, z), used by N triangles".
/// The vertices with equal coordinates (+0 and -0 alike) mapped to the first of them.
[[nodiscard]] std::vector<std::uint32_t> weld(const std::vector<Vec3<double>>& v);

/// p on the closed triangle abc, knowing orient3d(a, b, c, p) = 0 (exact): a projection where the
/// triangle has area, and the three edge signs there 0 or the triangle's. False for zero area.
[[nodiscard]] bool on_closed_triangle_coplanar(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                               const Vec3<double>& p);

[[nodiscard]] std::string edge_text(const std::vector<Vec3<double>>& v, const std::array<std::uint32_t, 3>& e);
/// Checks and copies the arrays, checks closure (MeshNotClosedError), builds the BVH.
void load_exact_mesh_state(ExactMeshState& s, const VertexArray& v, const IndexArray& ix, ContainsRule rule);

}  // namespace rayproof::scene::detail

namespace rayproof {
struct ExactMesh::State : scene::detail::ExactMeshState {};
}  // namespace rayproof
