#pragma once
/// rayproof::ExactMesh: a triangle mesh (closed, open or a soup) copied once, with the trees that
/// answer its exact queries at BVH speed. Each family is declared with its answers and documented:
/// - inside or outside, winding numbers, segments and a ray's crossings: rayproof/scene/contains.h
///   and rayproof/scene/winding.h, docs/contains.md;
/// - closest point, distance and signed distance: rayproof/scene/distance.h, docs/distance.md.
/// The nearest hit of a ray is MeshCaster's (rayproof/scene/mesh_caster.h).
/// Link rayproof::scene_certified (its exact fallback for inputs outside the expansions' exponent
/// window uses GMP).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>

#include "rayproof/scene/contains.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/scene/winding.h"
#include "rayproof/vec3.h"

namespace rayproof {

struct ClosestPoint;  // rayproof/scene/distance.h

class ExactMesh {
 public:
  static constexpr std::int32_t kOnSurface = std::numeric_limits<std::int32_t>::min();

  /// Checks and copies the arrays, checks closure, builds the BVH. Throws MeshInputError,
  /// MeshNotClosedError; ContainsRule::nonzero on a mesh that is not oriented throws
  /// MeshNotClosedError too (its message names a misoriented edge).
  ExactMesh(const VertexArray& vertices, const IndexArray& indices, ContainsRule rule = ContainsRule::automatic);
  ~ExactMesh();
  ExactMesh(ExactMesh&&) noexcept;
  ExactMesh& operator=(ExactMesh&&) noexcept;

  // The mesh: its size, closure and orientation, and the rule contains() applies.
  [[nodiscard]] std::size_t triangle_count() const;
  /// Every edge used as often in each direction: the winding number is defined.
  [[nodiscard]] bool oriented() const;
  /// The rule contains() applies: nonzero, parity or winding.
  [[nodiscard]] ContainsRule rule() const;
  /// Every edge used by an even number of triangles.
  [[nodiscard]] bool closed() const;

  // Inside or outside and winding numbers: contains.h, winding.h; docs/contains.md.
  [[nodiscard]] Side contains(const Vec3<double>& p) const;
  /// The exact winding number at p; kOnSurface on the surface, 0 for an invalid point. Throws
  /// std::logic_error when the mesh is not closed and oriented (see winding_value).
  [[nodiscard]] std::int32_t winding(const Vec3<double>& p) const;
  /// Crossings of the perturbed parity ray (the parity rule's count; mainly for tests).
  [[nodiscard]] std::uint32_t crossings(const Vec3<double>& p) const;
  /// The generalized winding number at p with its bound (any mesh): on a closed oriented mesh the
  /// exact integer with bound 0; elsewhere a value refined until bound <= tolerance (or the bound
  /// of evaluating every triangle directly, a few ulps per triangle, if that is larger).
  [[nodiscard]] WindingValue winding_value(const Vec3<double>& p, double tolerance = 1e-6) const;
  /// winding_value of n packed points `stride` bytes apart into w[i] and bound[i] (surface: w NaN
  /// and bound 0; invalid: w NaN and bound infinite).
  void winding_values(const double* xyz, std::size_t n, std::size_t stride, double* w, double* bound,
                      double tolerance = 1e-6, int threads = 0) const;

  /// contains() of every point into `out` (same size; MeshInputError otherwise).
  void contains(std::span<const Vec3<double>> points, std::span<Side> out, int threads = 0) const;
  /// The same on packed x y z doubles `stride` bytes apart (the Python binding's arrays).
  void contains(const double* xyz, std::size_t n, std::size_t stride, std::uint8_t* out, int threads = 0) const;

  // A ray's crossings and a segment's first contact: contains.h; docs/contains.md, "Crossings", "Segments".
  /// Every point where the ray crosses the surface with tmin <= t <= tmax, once each, in exact t
  /// order, with its direction; and apart from them the touches. Exact: each triangle is crossed or
  /// not as by the ray moved sideways by an infinitesimal (o + eps e_x + eps^2 e_y + eps^3 e_z), and
  /// the triangles met at one exact point (equal exact t) form one contact whose net count decides:
  /// +k (-k): k crossings in (out), 0: a touch. Any mesh (open, a soup): triangles as given.
  [[nodiscard]] RayCrossings ray_crossings(const Ray<double>& ray, TRange range = {}) const;
  /// ray_crossings() into `out`, reusing its vectors' storage.
  void ray_crossings_into(const Ray<double>& ray, TRange range, RayCrossings& out) const;
  /// ray_crossings() of every ray into `out` (same size; MeshInputError otherwise; its vectors' storage
  /// is reused).
  void ray_crossings(std::span<const Ray<double>> rays, std::span<RayCrossings> out, TRange range = {},
                 int threads = 0) const;

  /// Whether the closed segment p->q meets the surface, and where first.
  [[nodiscard]] SegmentHit segment(const Vec3<double>& p, const Vec3<double>& q) const;

  // Closest point and distance: distance.h; docs/distance.md.
  /// Closest point, nearest triangle, distance and (with_side) side of p.
  [[nodiscard]] ClosestPoint closest_point(const Vec3<double>& p, bool with_side = true) const;
  /// closest_point() of every point into `out` (same size; MeshInputError otherwise).
  void closest_points(std::span<const Vec3<double>> points, std::span<ClosestPoint> out, bool with_side = true,
                      int threads = 0) const;
  /// The same on packed x y z doubles `stride` bytes apart.
  void closest_points(const double* xyz, std::size_t n, std::size_t stride, ClosestPoint* out, bool with_side = true,
                      int threads = 0) const;
  /// The distance alone (correctly rounded; NaN for an invalid point).
  [[nodiscard]] double distance(const Vec3<double>& p) const;
  /// The distance with the side's sign: negative inside, 0 on the surface, NaN for an invalid point.
  [[nodiscard]] double signed_distance(const Vec3<double>& p) const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// The earlier name, kept for one release: ExactMesh answers open meshes and soups too.
using ClosedMesh [[deprecated("rayproof::ClosedMesh is now rayproof::ExactMesh (rayproof/scene/exact_mesh.h)")]] =
    ExactMesh;

}  // namespace rayproof

// ClosestPoint, the distance family's answer (after the class: distance.h includes contains.h,
// which includes this header).
#include "rayproof/scene/distance.h"
