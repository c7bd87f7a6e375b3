#pragma once
/// What a rayproof::MeshCaster holds (internal to rayproof_scene and rayproof_scene_certified):
/// the vertices (a view of the user's, or a packed double copy), the BVH and the compiled method.
#include <optional>
#include <vector>

#include "rayproof/scene/mesh_caster.h"
#include "scene/accel.h"

namespace rayproof::scene::detail {

struct MeshState {
  std::vector<Vec3<double>> copy;  ///< the converted vertices, when they could not be read in place
  bool copied = false;
  std::optional<scene::Accel> accel;
  scene::SceneMethod method;
};

/// Checks the arrays (MeshInputError), converts the vertices when needed and builds the BVH for `m`.
[[nodiscard]] MeshStatePtr build_mesh_state(const VertexArray& v, const IndexArray& i, scene::SceneMethod m);

/// A scene query's answer as a MeshHit: the global primitive number as `triangle` (the scene's
/// caster uses it for scenes with other kinds too).
[[nodiscard]] MeshHit to_mesh_hit(const scene::PrimHit& h);

/// The method's state: Float and Robust in rayproof_scene, Certified in rayproof_scene_certified.
[[nodiscard]] MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Float);
[[nodiscard]] MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Robust);
[[nodiscard]] MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Certified);

}  // namespace rayproof::scene::detail

namespace rayproof {
template <class Method>
MeshCaster<Method>::MeshCaster(const VertexArray& vertices, const IndexArray& indices)
    : state_(scene::detail::make_mesh_state(vertices, indices, Method{})) {}
}  // namespace rayproof
