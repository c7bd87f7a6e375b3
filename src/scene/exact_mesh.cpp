// ExactMesh's construction: the input checks of MeshCaster, packed copies, closure, the BVH.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "scene/exact_mesh_state.h"

namespace rayproof::scene::detail {

namespace {

std::string str(std::size_t n) { return std::to_string(n); }

void check_array(const char* what, const void* data, std::size_t count, std::size_t stride, std::size_t elem) {
  if (count == 0) return;
  const std::string a = std::string("ExactMesh: ") + what + " array: ";
  if (!data) throw MeshInputError(a + "null pointer with a count of " + str(count));
  if (count > 0xfffffffeu) throw MeshInputError(a + "count " + str(count) + " exceeds the limit of 2^32 - 2");
  if (stride < elem)
    throw MeshInputError(a + "stride of " + str(stride) + " bytes is smaller than one element (" + str(elem) + " bytes)");
  if (stride > (std::size_t(1) << 16)) throw MeshInputError(a + "stride of " + str(stride) + " bytes exceeds the limit of 65536");
  const auto at = reinterpret_cast<std::uintptr_t>(data);
  if (at > std::numeric_limits<std::uintptr_t>::max() - ((count - 1) * stride + elem))
    throw MeshInputError(a + str(count) + " elements " + str(stride) + " bytes apart overrun the address space");
}

}  // namespace

void load_exact_mesh_state(ExactMeshState& s, const VertexArray& v, const IndexArray& ix, ContainsRule rule) {
  const std::size_t vsize = v.is_double ? sizeof(double) : sizeof(float);
  check_array("vertex", v.data, v.count, v.stride, 3 * vsize);
  check_array("index", ix.data, ix.triangles, ix.stride, 3 * sizeof(std::uint32_t));
  const auto* vb = static_cast<const std::byte*>(v.data);
  s.vertices.resize(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    if (v.is_double) {
      double xyz[3];
      std::memcpy(xyz, vb + i * v.stride, sizeof xyz);
      s.vertices[i] = {xyz[0], xyz[1], xyz[2]};
    } else {
      float xyz[3];
      std::memcpy(xyz, vb + i * v.stride, sizeof xyz);
      s.vertices[i] = {double(xyz[0]), double(xyz[1]), double(xyz[2])};
    }
  }
  const auto* ib = reinterpret_cast<const std::byte*>(ix.data);
  s.triangles.resize(ix.triangles);
  bool any = false;
  for (std::size_t t = 0; t < ix.triangles; ++t) {
    std::memcpy(s.triangles[t].data(), ib + t * ix.stride, 3 * sizeof(std::uint32_t));
    for (std::uint32_t k : s.triangles[t]) {
      if (k >= v.count)
        throw MeshInputError("ExactMesh: triangle " + str(t) + " has vertex index " + str(k) + " out of range (vertex count " +
                             str(v.count) + ")");
      const Vec3<double>& p = s.vertices[k];
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        throw MeshInputError("ExactMesh: vertex " + str(k) + " (used by triangle " + str(t) + ") has a NaN or infinite coordinate");
      if (!any) s.lo = s.hi = p, any = true;
      s.lo = {std::min(s.lo.x, p.x), std::min(s.lo.y, p.y), std::min(s.lo.z, p.z)};
      s.hi = {std::max(s.hi.x, p.x), std::max(s.hi.y, p.y), std::max(s.hi.z, p.z)};
    }
  }
  s.closure = check_closure(s.vertices, s.triangles);
  if (s.closure.open_edges && (rule == ContainsRule::nonzero || rule == ContainsRule::parity))
    throw MeshNotClosedError("the mesh is not closed: " + str(s.closure.open_edges) +
                             " edges are used by an odd number of triangles, e.g. " +
                             edge_text(s.vertices, s.closure.open_example) + " (the " + to_string(rule) +
                             " rule needs a closed surface; the winding rule answers any mesh)");
  const bool oriented = s.closure.misoriented_edges == 0 && s.closure.open_edges == 0;
  if (s.closure.open_edges) rule = ContainsRule::winding;
  if (rule == ContainsRule::winding || !oriented) s.tree = std::make_unique<WindingTree>(s.vertices, s.triangles);
  if (rule == ContainsRule::winding) build_caps(s);
  if (rule == ContainsRule::nonzero && !oriented)
    throw MeshNotClosedError("the mesh is closed but not oriented: " + str(s.closure.misoriented_edges) +
                             " edges are not used as often in each direction, e.g. " +
                             edge_text(s.vertices, s.closure.misoriented_example) +
                             " (the winding number is not defined; use the parity rule)");
  s.rule = rule == ContainsRule::automatic ? (oriented ? ContainsRule::nonzero : ContainsRule::parity) : rule;
  scene::MeshRef ref;
  ref.vertices = s.vertices.data();
  ref.vertex_count = s.vertices.size();
  ref.indices = reinterpret_cast<const std::byte*>(s.triangles.data());
  ref.index_stride = sizeof(std::array<std::uint32_t, 3>);
  ref.triangle_count = s.triangles.size();
  s.accel.emplace(ref, BvhBuildOptions{});
  const auto& leaves = s.accel->leaf_prims();
  s.slots.assign(leaves.size(), {Vec3<double>{0, 0, 0}, Vec3<double>{0, 0, 0}, Vec3<double>{0, 0, 0}});
  s.slot_ids.resize(leaves.size());
  for (std::size_t j = 0; j < leaves.size(); ++j) {
    s.slot_ids[j] = leaves[j].id;
    if (leaves[j].id != scene::PrimHit::kNoPrim)
      for (int k = 0; k < 3; ++k) s.slots[j][k] = s.vertices[leaves[j].v[k]];
  }
}

}  // namespace rayproof::scene::detail
