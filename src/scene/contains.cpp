// rayproof::ExactMesh: the closure check and the exact point query (docs/contains.md).
//
// The query casts an axis-parallel ray from p (axis k, sign sigma: towards the nearest face of the
// mesh's bounding box) and counts its crossings with the triangles, as the ray from
// p' = p + eps e_k1 + eps^2 e_k2 (k1, k2 the next axes, eps -> 0+) would: every test is a sign of an
// exact orientation determinant (orient2d in the (k1, k2) projection, orient3d for the side), and
// a determinant that is exactly 0 at p is decided by its eps terms, which are signs of coordinate
// differences. Candidates come from the BVH, traversed conservatively along the unperturbed ray.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene/accel.h"
#include "scene/batch_threads.h"
#include "exact/orient_exact.h"
#include "scene/exact_mesh_state.h"

namespace rayproof {

const char* to_string(Side s) {
  switch (s) {
    case Side::outside: return "outside";
    case Side::inside: return "inside";
    case Side::surface: return "surface";
    case Side::invalid: return "invalid";
  }
  return "?";
}

const char* to_string(ContainsRule r) {
  switch (r) {
    case ContainsRule::automatic: return "automatic";
    case ContainsRule::nonzero: return "nonzero";
    case ContainsRule::parity: return "parity";
    case ContainsRule::winding: return "winding";
  }
  return "?";
}

namespace {

using certified::orient2d_exact;
using certified::orient3d_exact;

std::string str(std::size_t n) { return std::to_string(n); }
std::string str(const Vec3<double>& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", p.x, p.y, p.z);
  return buf;
}

}  // namespace

namespace scene::detail {

/// The vertices with equal coordinates (+0 and -0 alike) mapped to the first of them.
std::vector<std::uint32_t> weld(const std::vector<Vec3<double>>& v) {
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::size_t(k.x * 0x9e3779b97f4a7c15ull ^ (k.y + 0x632be59bd9b4e019ull) * 0xbf58476d1ce4e5b9ull ^ k.z * 0x94d049bb133111ebull);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> first;
  first.reserve(v.size());
  std::vector<std::uint32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Key k{std::bit_cast<std::uint64_t>(v[i].x + 0.0), std::bit_cast<std::uint64_t>(v[i].y + 0.0),
                std::bit_cast<std::uint64_t>(v[i].z + 0.0)};
    out[i] = first.try_emplace(k, std::uint32_t(i)).first->second;
  }
  return out;
}

ClosureReport check_closure(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  const std::vector<std::uint32_t> id = weld(v);
  // Every edge of nonzero length as (low, high, +1 when used low -> high, -1 otherwise), sorted.
  struct Edge {
    std::uint32_t lo, hi;
    int dir;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * tris.size());
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = id[t[k]], b = id[t[(k + 1) % 3]];
      if (a != b) edges.push_back(a < b ? Edge{a, b, 1} : Edge{b, a, -1});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi; });
  ClosureReport r;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    int uses = 0, balance = 0;
    for (; j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi; ++j) ++uses, balance += edges[j].dir;
    if (uses % 2) {
      if (r.open_edges++ == 0) r.open_example = {edges[i].lo, edges[i].hi, std::uint32_t(uses)};
    } else if (balance != 0) {
      if (r.misoriented_edges++ == 0) r.misoriented_example = {edges[i].lo, edges[i].hi, std::uint32_t(uses)};
    }
    i = j;
  }
  return r;
}

std::string edge_text(const std::vector<Vec3<double>>& v, const std::array<std::uint32_t, 3>& e) {
  return "vertex " + str(e[0]) + " " + str(v[e[0]]) + " - vertex " + str(e[1]) + " " + str(v[e[1]]) + ", used by " +
         str(e[2]) + " triangle" + (e[2] == 1 ? "" : "s");
}

}  // namespace scene::detail

namespace {

inline double coord(const Vec3<double>& p, int k) { return reinterpret_cast<const double*>(&p)[k]; }

/// Sign of orient2d(a, b, p') in the (u, v) projection when orient2d(a, b, p) = 0, for
/// p' = p + eps e_u + eps^2 e_v: the eps term -(bv - av), then the eps^2 term (bu - au).
inline int sos_edge(double au, double av, double bu, double bv) {
  if (bv != av) return av > bv ? 1 : -1;
  return bu > au ? 1 : (bu < au ? -1 : 0);
}

}  // namespace

namespace scene::detail {

/// p on the closed triangle, knowing orient3d(a, b, c, p) = 0: a projection where the triangle has
/// area, and the three edge signs there 0 or the triangle's.
bool on_closed_triangle_coplanar(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p) {
  for (int j = 0; j < 3; ++j) {
    const int u = (j + 1) % 3, v = (j + 2) % 3;
    const double au = coord(a, u), av = coord(a, v), bu = coord(b, u), bv = coord(b, v), cu = coord(c, u), cv = coord(c, v);
    const int s = orient2d_exact(au, av, bu, bv, cu, cv);
    if (s == 0) continue;
    const double pu = coord(p, u), pv = coord(p, v);
    return orient2d_exact(au, av, bu, bv, pu, pv) != -s && orient2d_exact(bu, bv, cu, cv, pu, pv) != -s &&
           orient2d_exact(cu, cv, au, av, pu, pv) != -s;
  }
  return false;  // zero area: not part of the surface
}

/// The perturbed ray's count at p (finite, inside the closed bounding box).
PointQuery query_point(const ExactMeshState& s, const Vec3<double>& p) {
  PointQuery q;
  // The nearest face of the bounding box: the shortest ray, the fewest boxes.
  int k = 0, sigma = 1;
  double best = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double lo = coord(p, a) - coord(s.lo, a), hi = coord(s.hi, a) - coord(p, a);
    if (hi < best) best = hi, k = a, sigma = 1;
    if (lo < best) best = lo, k = a, sigma = -1;
  }
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  Ray<double> ray{p, {0, 0, 0}};
  reinterpret_cast<double*>(&ray.d)[k] = sigma;
  const double pu = coord(p, u), pv = coord(p, v);
  const scene::LeafPrim* leaves = s.accel->leaf_prims().data();
  const std::array<Vec3<double>, 3>* slots = s.slots.data();
  const double tmax = std::numeric_limits<double>::infinity();
  s.accel->traverse_slots(ray, 0.0, tmax, BvhTraversal::conservative, BvhQuery::any, [&](std::uint32_t j) {
    const scene::LeafPrim& lp = leaves[j];
    if (lp.id == scene::PrimHit::kNoPrim) return false;
    const Vec3<double>&a = slots[j][0], &b = slots[j][1], &c = slots[j][2];
    const double au = coord(a, u), av = coord(a, v), bu = coord(b, u), bv = coord(b, v), cu = coord(c, u), cv = coord(c, v);
    const int e0 = orient2d_exact(au, av, bu, bv, pu, pv);
    const int e1 = orient2d_exact(bu, bv, cu, cv, pu, pv);
    if (e0 * e1 < 0) return false;  // p strictly outside the projection: neither crossed nor on it
    const int e2 = orient2d_exact(cu, cv, au, av, pu, pv);
    if (e0 * e2 < 0 || e1 * e2 < 0) return false;
    const int sk = orient2d_exact(au, av, bu, bv, cu, cv);  // sign of the normal's k component
    const int d0 = orient3d_exact(a, b, c, p);
    if (sk == 0) {
      // Parallel to the ray: never crossed by p'; only the surface test.
      if (d0 == 0 && on_closed_triangle_coplanar(a, b, c, p)) return q.surface = true;
      return false;
    }
    // p is in the closed projection (the nonzero e_i sum to orient2d(a, b, c), so they have sign sk).
    if (d0 == 0) return q.surface = true;  // on the plane and in the closed projection: on the triangle
    // p' strictly inside: each edge's sign at p, or its perturbation's when 0.
    if ((e0 ? e0 : sos_edge(au, av, bu, bv)) != sk || (e1 ? e1 : sos_edge(bu, bv, cu, cv)) != sk ||
        (e2 ? e2 : sos_edge(cu, cv, au, av)) != sk)
      return false;
    if (d0 != -sigma * sk) return false;  // the plane is behind p along the ray
    q.winding += sigma * sk;
    ++q.crossings;
    return false;
  });
  return q;
}

}  // namespace scene::detail

namespace {

bool finite(const Vec3<double>& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

ExactMesh::ExactMesh(const VertexArray& vertices, const IndexArray& indices, ContainsRule rule)
    : s_(std::make_unique<State>()) {
  scene::detail::load_exact_mesh_state(*s_, vertices, indices, rule);
}
ExactMesh::~ExactMesh() = default;
ExactMesh::ExactMesh(ExactMesh&&) noexcept = default;
ExactMesh& ExactMesh::operator=(ExactMesh&&) noexcept = default;

std::size_t ExactMesh::triangle_count() const { return s_->triangles.size(); }
bool ExactMesh::oriented() const { return s_->closure.misoriented_edges == 0 && s_->closure.open_edges == 0; }
bool ExactMesh::closed() const { return s_->closure.open_edges == 0; }
ContainsRule ExactMesh::rule() const { return s_->rule; }

Side ExactMesh::contains(const Vec3<double>& p) const {
  if (!finite(p)) return Side::invalid;
  if (s_->rule == ContainsRule::winding) return scene::detail::winding_side(*s_, p);  // w > 1/2 (winding_caps.cpp)
  if (!in_box(*s_, p)) return Side::outside;
  const scene::detail::PointQuery q = scene::detail::query_point(*s_, p);
  if (q.surface) return Side::surface;
  const bool in = s_->rule == ContainsRule::parity ? (q.crossings & 1) != 0 : q.winding != 0;
  return in ? Side::inside : Side::outside;
}

std::int32_t ExactMesh::winding(const Vec3<double>& p) const {
  if (!closed()) throw std::logic_error("ExactMesh::winding: the mesh is not closed (" + str(s_->closure.open_edges) +
                                        " open edges): its winding number is not an integer; see winding_value");
  if (!oriented()) throw std::logic_error("ExactMesh::winding: the mesh is not oriented (" +
                                          str(s_->closure.misoriented_edges) + " edges used unequally in each direction)");
  if (!finite(p) || !in_box(*s_, p)) return 0;
  const scene::detail::PointQuery q = scene::detail::query_point(*s_, p);
  return q.surface ? kOnSurface : q.winding;
}

std::uint32_t ExactMesh::crossings(const Vec3<double>& p) const {
  if (!finite(p) || !in_box(*s_, p)) return 0;
  return scene::detail::query_point(*s_, p).crossings;
}

void ExactMesh::contains(std::span<const Vec3<double>> points, std::span<Side> out, int threads) const {
  if (points.size() != out.size())
    throw MeshInputError("ExactMesh::contains: " + str(out.size()) + " results for " + str(points.size()) + " points");
  static_assert(sizeof(Side) == 1);
  contains(reinterpret_cast<const double*>(points.data()), points.size(), sizeof(Vec3<double>),
           reinterpret_cast<std::uint8_t*>(out.data()), threads);
}

void ExactMesh::contains(const double* xyz, std::size_t n, std::size_t stride, std::uint8_t* out, int threads) const {
  if (n == 0) return;
  if (!xyz || !out) throw MeshInputError("ExactMesh::contains: null pointer with a count of " + str(n));
  if (stride < 3 * sizeof(double) || stride % sizeof(double))
    throw MeshInputError("ExactMesh::contains: stride of " + str(stride) + " bytes (need a multiple of 8, at least 24)");
  const auto* base = reinterpret_cast<const std::byte*>(xyz);
  // The winding rule: batches of 4096 points or more tabulate the caps once, where their points
  // are (winding_field.cpp).
  if (s_->rule == ContainsRule::winding && n >= 4096) scene::detail::prepare_caps_field(*s_, base, n, stride);
  scene::detail::for_each_batch_range(n, threads, 2048, 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Vec3<double> p;
      std::memcpy(&p, base + i * stride, sizeof p);
      out[i] = static_cast<std::uint8_t>(contains(p));
    }
  });
}

}  // namespace rayproof
