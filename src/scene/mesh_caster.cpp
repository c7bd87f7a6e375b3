// rayproof::MeshCaster: input checks, the vertex view or copy, and the queries through scene::Accel
// (the same BVH, traversal and compiled kernels as `rayproof cast`).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "scene/mesh_caster_state.h"

namespace rayproof {
namespace scene::detail {

void MeshStateDeleter::operator()(const MeshState* s) const { delete s; }

namespace {

std::string str(std::size_t n) { return std::to_string(n); }

constexpr std::size_t kMaxElements = 0xfffffffeu;  // numbers 0 .. 2^32 - 2; 2^32 - 1 means "none"
constexpr std::size_t kMaxStride = std::size_t(1) << 16;  // bytes between elements: more is taken for a mistake

void check_array(const char* what, const void* data, std::size_t count, std::size_t stride, std::size_t elem) {
  if (count == 0) return;
  const std::string a = std::string("MeshCaster: ") + what + " array: ";
  if (!data) throw MeshInputError(a + "null pointer with a count of " + str(count));
  if (count > kMaxElements) throw MeshInputError(a + "count " + str(count) + " exceeds the limit of 2^32 - 2");
  if (stride < elem)
    throw MeshInputError(a + "stride of " + str(stride) + " bytes is smaller than one element (" + str(elem) + " bytes)");
  if (stride > kMaxStride) throw MeshInputError(a + "stride of " + str(stride) + " bytes exceeds the limit of 65536");
  // count <= 2^32 and stride <= 2^16: the byte count below cannot overflow a 64-bit size_t.
  const auto at = reinterpret_cast<std::uintptr_t>(data);
  if (at > std::numeric_limits<std::uintptr_t>::max() - ((count - 1) * stride + elem))
    throw MeshInputError(a + str(count) + " elements " + str(stride) + " bytes apart overrun the address space");
}

template <class T>
Vec3<double> read_vertex(const std::byte* base, std::size_t stride, std::size_t i) {
  T xyz[3];
  std::memcpy(xyz, base + i * stride, sizeof xyz);
  return {double(xyz[0]), double(xyz[1]), double(xyz[2])};
}

}  // namespace

MeshStatePtr build_mesh_state(const VertexArray& v, const IndexArray& ix, scene::SceneMethod m) {
  const std::size_t vsize = v.is_double ? sizeof(double) : sizeof(float);
  check_array("vertex", v.data, v.count, v.stride, 3 * vsize);
  check_array("index", ix.data, ix.triangles, ix.stride, 3 * sizeof(std::uint32_t));
  MeshStatePtr out(new MeshState);
  MeshState& s = const_cast<MeshState&>(*out);
  s.method = std::move(m);
  const auto* vb = static_cast<const std::byte*>(v.data);
  const bool in_place = v.is_double && v.stride == sizeof(Vec3<double>) &&
                        reinterpret_cast<std::uintptr_t>(v.data) % alignof(Vec3<double>) == 0;
  static_assert(sizeof(Vec3<double>) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3<double>>);
  if (!in_place && v.count) {
    s.copied = true;
    s.copy.resize(v.count);
    for (std::size_t i = 0; i < v.count; ++i)
      s.copy[i] = v.is_double ? read_vertex<double>(vb, v.stride, i) : read_vertex<float>(vb, v.stride, i);
  }
  scene::MeshRef ref;
  ref.vertices = s.copied ? s.copy.data() : static_cast<const Vec3<double>*>(v.data);
  ref.vertex_count = v.count;
  ref.indices = reinterpret_cast<const std::byte*>(ix.data);
  ref.index_stride = ix.stride;
  ref.triangle_count = ix.triangles;
  // Indices in range, the vertices they use finite: checked before the build reads them.
  for (std::size_t t = 0; t < ix.triangles; ++t) {
    const auto tri = ref.triangle(t);
    for (int k = 0; k < 3; ++k) {
      if (tri[k] >= v.count)
        throw MeshInputError("MeshCaster: triangle " + str(t) + " has vertex index " + str(tri[k]) +
                             " out of range (vertex count " + str(v.count) + ")");
      const Vec3<double>& p = ref.vertices[tri[k]];
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        throw MeshInputError("MeshCaster: vertex " + str(tri[k]) + " (used by triangle " + str(t) +
                             ") has a NaN or infinite coordinate");
    }
  }
  s.accel.emplace(ref, BvhBuildOptions{});  // the default build (binned SAH, leaves of 4), as `rayproof cast`
  return out;
}

MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Float) {
  return build_mesh_state(v, i, {"float", FastKernel::mt_float, nullptr, BvhTraversal::standard});
}
MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Robust) {
  return build_mesh_state(v, i, {"robust", FastKernel::robust, nullptr, BvhTraversal::conservative});
}

}  // namespace scene::detail

MeshHit scene::detail::to_mesh_hit(const scene::PrimHit& h) {
  MeshHit m;
  m.contact = h.contact;
  if (h.prim == scene::PrimHit::kNoPrim) return m;
  m.triangle = h.prim, m.t = h.t, m.b1 = h.b1, m.b2 = h.b2;
  return m;
}

namespace {

using scene::detail::str;
using scene::detail::to_mesh_hit;

/// The batch's spans agree: as many results as rays, and 0, 1 or one range per ray.
void check_batch(std::size_t rays, std::size_t ranges, std::size_t results) {
  if (results != rays) throw MeshInputError("MeshCaster: " + str(results) + " results for " + str(rays) + " rays");
  if (ranges > 1 && ranges != rays)
    throw MeshInputError("MeshCaster: " + str(ranges) + " ranges for " + str(rays) +
                         " rays (expected 0, 1 or one per ray)");
}
}  // namespace

template <class M>
std::size_t MeshCaster<M>::triangle_count() const {
  return state_->accel->primitive_count();
}
template <class M>
bool MeshCaster<M>::copies_vertices() const {
  return state_->copied;
}
template <class M>
double MeshCaster<M>::build_seconds() const {
  return state_->accel->build_seconds();
}
template <class M>
double MeshCaster<M>::bytes_per_triangle() const {
  return state_->accel->bytes_per_primitive();
}
template <class M>
double MeshCaster<M>::bytes_read_per_triangle() const {
  return state_->accel->bytes_read_per_primitive(state_->method);
}

template <class M>
MeshHit MeshCaster<M>::closest(const Ray<double>& ray, TRange r) const {
  return to_mesh_hit(state_->accel->closest(ray, state_->method, {r.tmin, r.tmax}));
}
template <class M>
bool MeshCaster<M>::any(const Ray<double>& ray, TRange r) const {
  return state_->accel->any(ray, state_->method, {r.tmin, r.tmax});
}
template <class M>
std::vector<MeshHit> MeshCaster<M>::all(const Ray<double>& ray, TRange r) const {
  const auto hits = state_->accel->all(ray, state_->method, {r.tmin, r.tmax});
  std::vector<MeshHit> out(hits.size());
  std::transform(hits.begin(), hits.end(), out.begin(), to_mesh_hit);
  return out;
}

template <class M>
void MeshCaster<M>::closest(std::span<const Ray<double>> rays, std::span<const TRange> ranges, std::span<MeshHit> out,
                            int threads) const {
  check_batch(rays.size(), ranges.size(), out.size());
  state_->accel->closest_batch(
      rays, ranges, [](void* c, std::size_t i, const scene::PrimHit& h) { static_cast<MeshHit*>(c)[i] = to_mesh_hit(h); },
      out.data(), state_->method, threads);
}
template <class M>
void MeshCaster<M>::any(std::span<const Ray<double>> rays, std::span<const TRange> ranges, std::span<std::uint8_t> out,
                        int threads) const {
  check_batch(rays.size(), ranges.size(), out.size());
  state_->accel->any_batch(rays, ranges, out, state_->method, threads);
}

template class MeshCaster<cast::Float>;
template class MeshCaster<cast::Robust>;
// Certified: every member but the constructor, which rayproof_scene_certified instantiates.
template std::size_t MeshCaster<cast::Certified>::triangle_count() const;
template bool MeshCaster<cast::Certified>::copies_vertices() const;
template double MeshCaster<cast::Certified>::build_seconds() const;
template double MeshCaster<cast::Certified>::bytes_per_triangle() const;
template double MeshCaster<cast::Certified>::bytes_read_per_triangle() const;
template MeshHit MeshCaster<cast::Certified>::closest(const Ray<double>&, TRange) const;
template bool MeshCaster<cast::Certified>::any(const Ray<double>&, TRange) const;
template std::vector<MeshHit> MeshCaster<cast::Certified>::all(const Ray<double>&, TRange) const;
template void MeshCaster<cast::Certified>::closest(std::span<const Ray<double>>, std::span<const TRange>,
                                                   std::span<MeshHit>, int) const;
template void MeshCaster<cast::Certified>::any(std::span<const Ray<double>>, std::span<const TRange>,
                                               std::span<std::uint8_t>, int) const;

}  // namespace rayproof
