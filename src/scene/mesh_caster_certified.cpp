// MeshCaster<cast::Certified>: the certified triangle filter of rayproof_scene; for the triangles
// it cannot decide, rayproof::certified::intersect (rayproof_certified: the same filter, then its
// exact fallback in GMP and MPFR; no CGAL).
#include "rayproof/certified/intersect.h"
#include "scene/mesh_caster_state.h"

namespace rayproof {
namespace scene::detail {
namespace {

/// The exact class and t (rounded to nearest) of a ray/triangle pair the filter left undecided.
Hit<double> exact_triangle(const Ray<double>& r, const Triangle<double>& t) {
  const TriangleHit<double> h = certified::intersect(r, t);
  return {h.contact, h.t, h.t2};
}

}  // namespace

MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Certified) {
  scene::SceneMethod m{"certified", FastKernel::certified, nullptr, BvhTraversal::conservative};
  m.triangle_fallback = exact_triangle;
  return build_mesh_state(v, i, std::move(m));
}

}  // namespace scene::detail

template MeshCaster<cast::Certified>::MeshCaster(const VertexArray&, const IndexArray&);

}  // namespace rayproof
