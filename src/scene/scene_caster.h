#pragma once
/// What `cast`, `render` and `bench` query. A scene of triangles only, with a method the public
/// API compiles (float, robust, certified) and the SAH builder, goes through rayproof::MeshCaster
/// (include/rayproof/scene/mesh_caster.h), the mesh's arrays read in place. Anything else (spheres,
/// boxes, disks, ellipsoids; other methods; the median builder) goes through Accel, the
/// BVH, traversal and kernels behind MeshCaster, with the method's SceneMethod.
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "rayproof/scene/mesh_caster.h"
#include "scene/accel.h"

namespace rayproof::scene {

/// A result line's crossing: MeshHit, whose `triangle` is the global primitive number (triangles
/// first, then spheres, ellipsoids, disks, boxes: scene.h) when the scene has other kinds.
using CastHit = MeshHit;

class SceneCaster {
 public:
  /// `s` must outlive the caster (its vertices are read in place).
  SceneCaster(const Scene& s, const SceneMethod& m, const BvhBuildOptions& opt = {});
  /// Queries through a scene BVH built elsewhere (it must outlive the caster).
  SceneCaster(const Accel& shared, const SceneMethod& m) : shared_(&shared), method_(m) {}
  /// Whether SceneCaster(s, m, opt) goes through the public MeshCaster.
  [[nodiscard]] static bool takes_public_api(const Scene& s, const SceneMethod& m,
                                             const BvhBuildOptions& opt = {});

  /// Whether the queries go through the public MeshCaster.
  [[nodiscard]] bool public_api() const { return mesh_.index() != 0; }
  [[nodiscard]] double build_seconds() const;
  [[nodiscard]] double bytes_per_primitive() const;
  /// Bytes per primitive the method's queries read (Accel::bytes_read_per_primitive).
  [[nodiscard]] double bytes_read_per_primitive() const;
  /// The scene BVH, when the queries go through it (else null).
  [[nodiscard]] const Accel* accel() const { return shared_; }

  void closest(std::span<const Ray<double>> rays, std::span<CastHit> out, int threads, TRange q = {}) const;
  void any(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads, TRange q = {}) const;
  [[nodiscard]] std::vector<CastHit> all(const Ray<double>& r, TRange q = {}) const;

 private:
  std::variant<std::monostate, MeshCaster<cast::Float>, MeshCaster<cast::Robust>, MeshCaster<cast::Certified>> mesh_;
  std::optional<Accel> own_;
  const Accel* shared_ = nullptr;  ///< own_, or a BVH built elsewhere
  SceneMethod method_;
};

/// MeshHit of a scene query's PrimHit.
[[nodiscard]] CastHit to_cast_hit(const PrimHit& h);

}  // namespace rayproof::scene
