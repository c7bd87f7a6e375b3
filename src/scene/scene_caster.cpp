// The scene commands' queries: the public MeshCaster for meshes, scene::Accel for the rest.
#include "scene/scene_caster.h"

#include "scene/mesh_caster_state.h"

namespace rayproof::scene {

CastHit to_cast_hit(const scene::PrimHit& h) { return rayproof::scene::detail::to_mesh_hit(h); }

bool SceneCaster::takes_public_api(const scene::Scene& s, const scene::SceneMethod& m, const BvhBuildOptions& opt) {
  const bool kernel = m.fast == FastKernel::mt_float || m.fast == FastKernel::robust ||
                      m.fast == FastKernel::certified;
  const BvhBuildOptions mesh_caster_build;  // MeshCaster's: SAH, leaves of 4
  return kernel && s.size() == s.mesh.triangles.size() && opt.builder == mesh_caster_build.builder &&
         opt.max_leaf == mesh_caster_build.max_leaf && opt.leaf_group == mesh_caster_build.leaf_group;
}

SceneCaster::SceneCaster(const scene::Scene& s, const scene::SceneMethod& m, const BvhBuildOptions& opt)
    : method_(m) {
  if (takes_public_api(s, m, opt)) {
    const VertexArray v(s.mesh.vertices.empty() ? nullptr : &s.mesh.vertices[0].x, s.mesh.vertices.size(),
                        sizeof(Vec3<double>));
    const IndexArray ix{s.mesh.triangles.empty() ? nullptr : s.mesh.triangles[0].data(), s.mesh.triangles.size(),
                        sizeof(s.mesh.triangles[0])};
    if (m.fast == FastKernel::mt_float) mesh_.emplace<MeshCaster<cast::Float>>(v, ix);
    if (m.fast == FastKernel::robust) mesh_.emplace<MeshCaster<cast::Robust>>(v, ix);
    if (m.fast == FastKernel::certified) mesh_.emplace<MeshCaster<cast::Certified>>(v, ix);
  }
  if (!public_api()) shared_ = &own_.emplace(s, opt);
}

double SceneCaster::build_seconds() const {
  if (shared_) return shared_->build_seconds();
  return std::visit([](const auto& c) {
    if constexpr (std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) return 0.0;
    else return c.build_seconds();
  }, mesh_);
}

double SceneCaster::bytes_per_primitive() const {
  if (shared_) return shared_->bytes_per_primitive();
  return std::visit([](const auto& c) {
    if constexpr (std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) return 0.0;
    else return c.bytes_per_triangle();
  }, mesh_);
}

double SceneCaster::bytes_read_per_primitive() const {
  if (shared_) return shared_->bytes_read_per_primitive(method_);
  return std::visit([](const auto& c) {
    if constexpr (std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) return 0.0;
    else return c.bytes_read_per_triangle();
  }, mesh_);
}

namespace {
void put_cast_hit(void* out, std::size_t i, const scene::PrimHit& h) { static_cast<CastHit*>(out)[i] = to_cast_hit(h); }
}  // namespace

void SceneCaster::closest(std::span<const Ray<double>> rays, std::span<CastHit> out, int threads, TRange q) const {
  if (shared_) return shared_->closest_batch(rays, std::span<const TRange>(&q, 1), put_cast_hit, out.data(), method_, threads);
  std::visit([&](const auto& c) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) c.closest(rays, {&q, 1}, out, threads);
  }, mesh_);
}

void SceneCaster::any(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads, TRange q) const {
  if (shared_) return shared_->any_batch(rays, out, method_, threads, q);
  std::visit([&](const auto& c) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) c.any(rays, {&q, 1}, out, threads);
  }, mesh_);
}

std::vector<CastHit> SceneCaster::all(const Ray<double>& r, TRange q) const {
  if (shared_) {
    const auto hits = shared_->all(r, method_, q);
    std::vector<CastHit> out(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) out[i] = to_cast_hit(hits[i]);
    return out;
  }
  return std::visit([&](const auto& c) {
    if constexpr (std::is_same_v<std::decay_t<decltype(c)>, std::monostate>) return std::vector<CastHit>{};
    else return c.all(r, q);
  }, mesh_);
}

}  // namespace rayproof::scene
