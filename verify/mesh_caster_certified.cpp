// MeshCaster<cast::Certified>: the certified triangle filter of rayproof_scene with its exact
// fallback, exact_classify (GMP rationals through CGAL), for the triangles the filter cannot decide.
#include "scene/mesh_caster_state.h"
#include "verify/exact.h"

namespace rayproof {
namespace detail {
namespace {

/// The exact class and t (rounded to nearest) of one ray/triangle pair.
Hit<double> exact_triangle(const Ray<double>& r, const Triangle<double>& t) {
  io::Case c;
  c.kind = io::Kind::triangle;
  const Vec3<double> p[5] = {r.o, r.d, t.p0, t.p1, t.p2};
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 3; ++k) c.v[3 * i + k] = p[i][k];
  const io::CaseResult e = verify::exact_classify(c);
  return {e.contact, e.t.value_or(kNaN<double>), e.t2.value_or(kNaN<double>)};
}

}  // namespace

MeshStatePtr make_mesh_state(const VertexArray& v, const IndexArray& i, cast::Certified) {
  scene::SceneMethod m{"certified", scene::FastKernel::certified, nullptr, BvhTraversal::conservative};
  m.triangle_fallback = exact_triangle;
  return build_mesh_state(v, i, std::move(m));
}

}  // namespace detail

template MeshCaster<cast::Certified>::MeshCaster(const VertexArray&, const IndexArray&);

}  // namespace rayproof
