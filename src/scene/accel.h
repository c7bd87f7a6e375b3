#pragma once
/// Queries over a whole scene: a BVH over every primitive and one per-primitive method, for
/// closest hit, any hit (occlusion) and all hits (every crossing, sorted), each with [tmin, tmax],
/// one ray at a time or a batch over threads (TBB).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "methods/method.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"
#include "rayproof/bvh_wide_sah.h"
#include "rayproof/scene/mesh_caster.h"
#include "scene/leaf_simd.h"
#include "scene/scene.h"

namespace rayproof::scene {

/// One crossing of a ray with a primitive: its class (docs/cases.md) and t. A miss has prim = kNoPrim.
struct PrimHit {
  static constexpr std::uint32_t kNoPrim = 0xffffffffu;
  Contact contact = Contact::miss;
  double t = kNaN<double>;
  std::uint32_t prim = kNoPrim;
  /// A triangle's barycentrics b1 (weight of p1) and b2 (of p2) where the kernel has them
  /// (compiled float, double and robust kernels), else NaN.
  double b1 = kNaN<double>, b2 = kNaN<double>;
  /// Equal classes, primitives and t (NaN t, as in a miss, equals NaN); barycentrics not compared.
  friend bool operator==(const PrimHit& a, const PrimHit& b) {
    return a.contact == b.contact && a.prim == b.prim && (a.t == b.t || (a.t != a.t && b.t != b.t));
  }
  friend std::ostream& operator<<(std::ostream& os, const PrimHit& h) {
    return os << to_string(h.contact) << ' ' << h.t << ' ' << h.prim;
  }
};

// FastKernel, the kernels compiled into the traversal, is declared with the registry's Method
// (methods/method.h): each method says there how the scene runs it. certified's exact fallback is
// the registry method (`generic`), or the typed SceneMethod::triangle_fallback when set, as
// MeshCaster<cast::Certified> does.

/// A typed exact fallback for `certified` triangles the filter cannot decide: the exact class, t
/// within 1 ulp (as the registry's certified method). Given by the layer that has exact arithmetic.
using TriangleFallback = Hit<double> (*)(const Ray<double>&, const Triangle<double>&);

/// How the scene's primitives are intersected: a compiled kernel, or any registry method through
/// its case interface (slower, used for exact, robust, certified and other methods).
struct SceneMethod {
  std::string name;
  FastKernel fast = FastKernel::none;
  const Method* generic = nullptr;
  BvhTraversal traversal = BvhTraversal::standard;
  TriangleFallback triangle_fallback = nullptr;  ///< certified: used instead of `generic` for triangles
};

/// The registry's method called `name` as the scene runs it: its compiled kernel and traversal
/// (Method::scene), else its case interface per primitive with conservative boxes. Throws
/// SceneError when the registry has no such method.
[[nodiscard]] SceneMethod find_scene_method(const std::string& name, const MethodRegistry& reg);
/// The registry's methods with compiled kernels, in its order, for messages and the bench.
[[nodiscard]] std::vector<std::string> compiled_scene_method_names(const MethodRegistry& reg);

/// A primitive in the BVH's leaf order: a triangle's vertex indices (unused for other kinds) and its
/// global number. Leaves read these contiguously instead of prim_ids -> triangles -> vertices.
struct LeafPrim {
  std::uint32_t v[3];
  std::uint32_t id;
};
static_assert(sizeof(LeafPrim) == 16);

/// A query's range of t (the public API's type: a crossing counts when tmin <= t <= tmax).
using QueryRange = TRange;

/// A triangle mesh read in place: packed double vertices (x y z, 24 bytes each) and 32-bit indices
/// `index_stride` bytes apart (the indices are read once, at build: the leaf records keep them).
struct MeshRef {
  const Vec3<double>* vertices = nullptr;
  std::size_t vertex_count = 0;
  const std::byte* indices = nullptr;
  std::size_t index_stride = 3 * sizeof(std::uint32_t);
  std::size_t triangle_count = 0;
  [[nodiscard]] std::array<std::uint32_t, 3> triangle(std::size_t i) const {
    std::array<std::uint32_t, 3> t;
    std::memcpy(t.data(), indices + i * index_stride, sizeof t);
    return t;
  }
};

/// Receives closest() results from a batch: f(context, ray number, hit).
using HitSink = void (*)(void* context, std::size_t i, const PrimHit& h);

class Accel {
 public:
  /// `simd` picks the wide tree (bvh_simd_path: automatic follows RAYPROOF_SIMD, then the CPU):
  /// eight-wide nodes with the AVX2 box test, or four-wide with SSE. `nodes` picks full float
  /// boxes or quantized ones (bvh_nodes_choice: automatic follows RAYPROOF_BVH_NODES, then the
  /// tree's size: compressed when the full nodes would exceed kCompressedNodesAbove, 8 MiB);
  /// a tree that cannot be quantized (non-finite bounds) keeps full nodes (see nodes()).
  Accel(const Scene& s, const BvhBuildOptions& opt = {}, BvhSimd simd = BvhSimd::automatic,
        BvhNodes nodes = BvhNodes::automatic);
  /// A BVH over a mesh read in place (triangles only; compiled methods only). The caller checks
  /// the input (indices in range, finite vertices) and keeps the vertex array alive.
  explicit Accel(const MeshRef& m, const BvhBuildOptions& opt = {}, BvhSimd simd = BvhSimd::automatic,
                 BvhNodes nodes = BvhNodes::automatic);

  [[nodiscard]] const Scene& scene() const { return scene_; }
  /// The path the queries take: BvhSimd::avx2 (bvh8()) or BvhSimd::sse4 (bvh()).
  [[nodiscard]] BvhSimd simd() const { return simd_; }
  /// The four-wide BVH the SSE path traverses (the SAH or median binary tree, collapsed); empty on
  /// the AVX2 path.
  [[nodiscard]] const Bvh4& bvh() const { return bvh_; }
  /// The eight-wide BVH the AVX2 path traverses; empty on the SSE path.
  [[nodiscard]] const Bvh8& bvh8() const { return bvh8_; }
  /// The node kind in use: BvhNodes::full (bvh(), bvh8()) or BvhNodes::compressed (bvh4q(), bvh8q();
  /// then bvh() and bvh8() are empty).
  [[nodiscard]] BvhNodes nodes() const { return nodes_; }
  /// The quantized trees of the compressed nodes, four-wide (SSE) and eight-wide (AVX2); empty
  /// unless nodes() is compressed and the path is theirs.
  [[nodiscard]] const Bvh4Q& bvh4q() const { return bvh4q_; }
  [[nodiscard]] const Bvh8Q& bvh8q() const { return bvh8q_; }
  /// Nodes on the longest root-to-leaf path of the tree in use.
  [[nodiscard]] int max_depth() const {
    return bvh_.max_depth + bvh8_.max_depth + bvh4q_.max_depth + bvh8q_.max_depth;  // the others are empty (0)
  }
  /// The tree in use traversed for a ray: `leaf(j)` per leaf-order slot j (leaf_prims()[j]), true
  /// to stop (any hit), as wide_traverse_slots.
  template <class Leaf>
  void traverse_slots(const Ray<double>& r, double tmin, const double& tmax, BvhTraversal mode, BvhQuery query,
                      Leaf&& leaf) const {
    with_tree([&](const auto& tree) { wide_traverse_slots(tree, r, tmin, tmax, mode, query, leaf); });
  }
  [[nodiscard]] double build_seconds() const { return build_seconds_; }
  /// BVH plus triangle data, per triangle (analytic primitives counted as triangles).
  [[nodiscard]] double bytes_per_primitive() const;
  /// Bytes of the BVH: its nodes (of the tree in use), the leaf-order primitive records and the
  /// packed leaf groups.
  [[nodiscard]] std::size_t bvh_bytes() const {
    return tree_bytes() + leaf_prims_.size() * sizeof(LeafPrim) + groups_.size() * sizeof(detail::TriGroup);
  }
  /// Bytes the `float` and `robust` queries read: the nodes and the packed leaf groups (they do
  /// not touch the leaf records or the vertex array for triangles), per primitive.
  [[nodiscard]] double group_bytes_per_primitive() const;
  /// Bytes of the structures method `m`'s queries read, per primitive, on the leaf path in use
  /// (detail::leaf_simd()): `float` and `robust` with the leaf groups: the nodes and the groups
  /// (group_bytes_per_primitive), plus the leaf records and the primitive data when the scene has
  /// other primitives than triangles (their lanes go through the records); `certified` and every
  /// other method (or RAYPROOF_SIMD=off, or no groups): the nodes, the leaf records and the
  /// triangle data (the double vertices), and for `certified` the groups too when its float
  /// screen is on (detail::set_certified_screen, off by default). bytes_per_primitive() counts
  /// everything held.
  [[nodiscard]] double bytes_read_per_primitive(const SceneMethod& m) const;
  /// The leaf-order primitive records (slot j of the BVH's leaves; every leaf starts on a multiple
  /// of detail::kLanes, the slots between leaves are padding with id = PrimHit::kNoPrim).
  [[nodiscard]] const std::vector<LeafPrim>& leaf_prims() const { return leaf_prims_; }
  /// The primitives in the BVH (the leaf records without the padding).
  [[nodiscard]] std::size_t primitive_count() const { return primitive_count_; }
  /// The packed leaf groups (leaf_simd.h): group g holds slots [g kLanes, (g + 1) kLanes); empty
  /// when the scene has too many primitives for the lane tags (then every query goes slot by slot).
  [[nodiscard]] std::span<const detail::TriGroup> leaf_groups() const { return groups_; }

  /// Closest crossing in [tmin, tmax] (ties: the lower primitive number); `invalid` for a ray
  /// with a NaN or infinite component or d = 0.
  [[nodiscard]] PrimHit closest(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;
  [[nodiscard]] bool any(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;
  /// Every crossing in [tmin, tmax], sorted by t then primitive.
  [[nodiscard]] std::vector<PrimHit> all(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;

  /// closest() for every ray, on `threads` threads (0: all hardware threads).
  void closest_batch(std::span<const Ray<double>> rays, std::span<PrimHit> out, const SceneMethod& m,
                     int threads = 0, QueryRange q = {}) const;
  void any_batch(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, const SceneMethod& m,
                 int threads = 0, QueryRange q = {}) const;
  /// The same with a range per ray (`ranges` of size 1: one for all; empty: [0, inf)), closest
  /// hits handed to `sink` (from the batch's threads, each ray once).
  void closest_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, HitSink sink,
                     void* context, const SceneMethod& m, int threads = 0) const;
  void any_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<std::uint8_t> out,
                 const SceneMethod& m, int threads = 0) const;

  /// Packets: closest() / any() for every ray, the rays taken eight at a time in the
  /// order given (a caller groups coherent rays, e.g. camera tiles of 4x2 pixels, into consecutive
  /// eights; the last packet may be partial). On the AVX2 path each eight goes through the packet
  /// traversal of rayproof/bvh_packet.h (rays out of its float range: ray by ray); on the SSE path
  /// ray by ray. `ranges`: one per ray, one for all, or empty ([0, inf)). The answers are those of
  /// closest() / any() ray by ray: identical under conservative traversal; under standard
  /// traversal closest hit may pick another crossing within float ulps of the best t (its float
  /// pruning depends on the visit order, as between the SSE and AVX2 trees).
  void closest_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<PrimHit> out,
                       const SceneMethod& m, int threads = 0) const;
  void any_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<std::uint8_t> out,
                   const SceneMethod& m, int threads = 0) const;

 private:
  /// The BVH over `boxes` and leaf records with ids (vertex indices filled by the constructor).
  void build(const std::vector<BvhBox>& boxes, const std::vector<Vec3<float>>& centers, const BvhBuildOptions& opt,
             BvhNodes nodes);
  /// Runs `f(tree)` with the wide tree the accel's path and node kind traverse.
  template <class F>
  decltype(auto) with_tree(F&& f) const {
    if (simd_ == BvhSimd::avx2) return nodes_ == BvhNodes::compressed ? f(bvh8q_) : f(bvh8_);
    return nodes_ == BvhNodes::compressed ? f(bvh4q_) : f(bvh_);
  }
  /// closest() / any() for rays [b, e): the one place the tree and kernel dispatch is expanded for
  /// each query (closest() and the batches share it; each expansion is 4 trees x 9 kernels of
  /// traversal code, most of this library's compile time).
  void closest_range(const Ray<double>* rays, std::size_t b, std::size_t e, std::span<const QueryRange> ranges,
                     HitSink sink, void* context, const SceneMethod& m) const;
  void any_range(const Ray<double>* rays, std::size_t b, std::size_t e, std::span<const QueryRange> ranges,
                 std::uint8_t* out, const SceneMethod& m) const;
  /// The body of closest_packets / any_packets over threads: `packet(leaves, kernels, first, n)`
  /// for each packet of eight rays [first, first + n) on the eight-wide trees; on the SSE path
  /// `rays(b, e)` for the rays [b, e) of each share of packets, answered ray by ray through
  /// closest_range / any_range (no second expansion of the single-ray queries). Defined in
  /// accel_packet.h, used in accel_packet.cpp and accel_packet_any.cpp only.
  template <class Packet, class Rays>
  void over_packets(std::size_t nrays, const SceneMethod& m, int threads, Packet&& packet, Rays&& rays) const;
  /// Bytes of the nodes of the tree in use (the others are empty).
  [[nodiscard]] std::size_t tree_bytes() const { return bvh_.bytes() + bvh8_.bytes() + bvh4q_.bytes() + bvh8q_.bytes(); }
  /// The packed leaf groups from the leaf records (after the vertex indices are in).
  void build_groups();
  const Scene& scene_;
  const Vec3<double>* verts_ = nullptr;  ///< the triangles' vertices
  std::uint32_t ntri_ = 0;
  std::size_t triangle_bytes_ = 0;  ///< bytes of triangle data held for the queries
  BvhSimd simd_ = BvhSimd::sse4;
  Bvh4 bvh_;   ///< SSE path: nodes only (prim_ids is folded into leaf_prims_)
  Bvh8 bvh8_;  ///< AVX2 path: the same
  BvhNodes nodes_ = BvhNodes::full;
  Bvh4Q bvh4q_;  ///< SSE path, compressed nodes (then bvh_ is empty)
  Bvh8Q bvh8q_;  ///< AVX2 path, compressed nodes (then bvh8_ is empty)
  std::vector<LeafPrim> leaf_prims_;
  std::vector<detail::TriGroup, AlignedAllocator<detail::TriGroup, 32>> groups_;
  std::size_t primitive_count_ = 0;
  double build_seconds_ = 0;
};

}  // namespace rayproof::scene
