#include "light/spawn_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "gen/rng.h"
#include "rayproof/certified/intersect.h"
#include "rayproof/scene/mesh_caster.h"

namespace rayproof::light {

namespace {

using V = Vec3<double>;
constexpr double kTmin = std::numeric_limits<double>::denorm_min();  // t > 0
constexpr double kMinSine = 0.05;  ///< spawned directions leave the plane at least this steeply
constexpr std::array<SpawnStrategy, 4> kStrategies = {SpawnStrategy::none, SpawnStrategy::fixed_epsilon,
                                                      SpawnStrategy::error_bounded, SpawnStrategy::certified};

template <class T>
Vec3<T> vabs(Vec3<T> a) {
  return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)};
}

V random_unit(gen::Rng& rng) {
  for (;;) {
    const V v{rng.sym(), rng.sym(), rng.sym()};
    const double l2 = dot(v, v);
    if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
  }
}

struct Geometry {
  const mesh::Mesh& m;
  std::vector<std::uint32_t> start, list;  ///< vertex -> triangles using it (CSR)

  explicit Geometry(const mesh::Mesh& mesh) : m(mesh), start(mesh.vertices.size() + 1, 0) {
    for (const auto& t : m.triangles)
      for (auto v : t) ++start[v + 1];
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    list.resize(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < m.triangles.size(); ++i)
      for (auto v : m.triangles[i]) list[fill[v]++] = i;
  }
  [[nodiscard]] Triangle<double> tri(std::uint32_t i) const {
    const auto& t = m.triangles[i];
    return {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
  }
  /// Sign of q against the plane of triangle i (cross(e1, e2) side positive); 0 when the double
  /// evaluation cannot tell (q within the filter's bound of the plane).
  [[nodiscard]] int side_of(std::uint32_t i, V q) const {
    const Triangle<double> t = tri(i);
    const V e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, w = q - t.p0;
    const double d = dot(cross(e1, e2), w);
    const double bound = 1e-14 * length(e1) * length(e2) * length(w);
    return d > bound ? 1 : d < -bound ? -1 : 0;
  }
  /// Triangles a ray leaving triangle i to side `s` (+1: the cross(e1, e2) side) cannot meet at
  /// t > 0 from a point of triangle i: itself and the neighbours sharing an edge or vertex with
  /// every other vertex behind (or within the filter's bound of) its plane.
  [[nodiscard]] std::vector<std::uint32_t> impossible(std::uint32_t i, int s) const {
    std::vector<std::uint32_t> out{i};
    const auto& ti = m.triangles[i];
    for (auto v : ti)
      for (std::uint32_t k = start[v]; k < start[v + 1]; ++k) {
        const std::uint32_t n = list[k];
        if (std::find(out.begin(), out.end(), n) != out.end()) continue;
        bool behind = true;
        for (auto u : m.triangles[n])
          if (std::find(ti.begin(), ti.end(), u) == ti.end() && side_of(i, m.vertices[u]) * s > 0) behind = false;
        if (behind) out.push_back(n);
      }
    return out;
  }
};

bool certified_meets(const Geometry& g, const std::vector<std::uint32_t>& tris, const Ray<double>& r) {
  for (auto i : tris) {
    const TriangleHit<double> h = certified::intersect(r, g.tri(i));
    if (h.contact == Contact::coplanar) return true;
    if ((h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex) && h.t > 0)
      return true;
  }
  return false;
}

template <class Caster>
bool caster_meets(const Caster& c, const std::vector<std::uint32_t>& tris, const Ray<double>& r) {
  for (const MeshHit& h : c.all(r, {kTmin, std::numeric_limits<double>::infinity()}))
    if (std::find(tris.begin(), tris.end(), h.triangle) != tris.end()) return true;
  return false;
}

template <class T>
Ray<double> to_double(const Ray<T>& r) {
  return {V{double(r.o.x), double(r.o.y), double(r.o.z)}, V{double(r.d.x), double(r.d.y), double(r.d.z)}};
}
template <class T>
Vec3<T> as(V v) {
  return {static_cast<T>(v.x), static_cast<T>(v.y), static_cast<T>(v.z)};
}

/// pbrt-v4's triangle hit point: sum b_i v_i with error gamma(7) sum |b_i v_i| per coordinate; the
/// bound along the unit normal n is |n| . error.
template <class T>
SurfacePoint<T> triangle_point(const Triangle<double>& td, double b1d, double b2d) {
  const Vec3<T> v0 = as<T>(td.p0), v1 = as<T>(td.p1), v2 = as<T>(td.p2);
  const T b1 = static_cast<T>(b1d), b2 = static_cast<T>(b2d), b0 = T(1) - b1 - b2;
  const Vec3<T> p = b0 * v0 + b1 * v1 + b2 * v2;
  const Vec3<T> err = gamma<T>(7) * (vabs(b0 * v0) + vabs(b1 * v1) + vabs(b2 * v2));
  const Vec3<T> n = normalize(cross(v1 - v0, v2 - v0));
  // A floor at the scale of the point's largest coordinate: where the triangle lies in a
  // coordinate plane (z = 0, say) pbrt-v4's bound is 0 in that coordinate and the origin moves by a
  // denormal; a kernel whose t carries rounding at the scale of |p| (robust's watertight test,
  // which has no conservative t > 0 check as pbrt-v4's triangle test does) then finds the triangle
  // again at t ~ 1e-17.
  const T floor = gamma<T>(2) * std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  return {p, std::max(dot(vabs(n), err), floor), n};
}

struct Lights {
  V front, back;  ///< a light on the incoming side, one behind the surface
};

/// The spawned rays of one primary hit, for one method computed in T: per strategy, [reflection,
/// shadow front, shadow back] rays, the shadow rays running to their light at t = 1; `valid` says
/// which directions leave steeply enough to be counted.
template <class T>
struct Spawned {
  std::array<std::array<Ray<double>, 3>, 4> rays;
  std::array<bool, 3> valid{};
  std::array<std::vector<std::uint32_t>, 3> impossible;
};

template <class T>
Spawned<T> spawn_all(const Geometry& g, std::uint32_t tri, const SurfacePoint<T>& sp, V d_in, const Lights& L,
                     double epsilon) {
  Spawned<T> out;
  const Vec3<T> d = as<T>(d_in);
  const Vec3<T> reflect = d - (T(2) * dot(d, sp.n)) * sp.n;
  const std::array<Vec3<T>, 3> ws = {reflect, as<T>(L.front) - sp.p, as<T>(L.back) - sp.p};
  const V nd = normalize(cross(g.tri(tri).p1 - g.tri(tri).p0, g.tri(tri).p2 - g.tri(tri).p0));
  for (std::size_t j = 0; j < 3; ++j) {
    const V w{double(ws[j].x), double(ws[j].y), double(ws[j].z)};
    const double c = dot(w, nd) / length(w);
    out.valid[j] = std::isfinite(c) && std::fabs(c) >= kMinSine;
    out.impossible[j] = g.impossible(tri, c > 0 ? 1 : -1);
    for (std::size_t s = 0; s < kStrategies.size(); ++s) {
      Ray<T> r;
      if (kStrategies[s] == SpawnStrategy::certified) {
        int steps = 0;
        r = spawn_ray_certified(sp, ws[j], [&](const Ray<T>& x) { return certified_meets(g, out.impossible[j], to_double(x)); },
                                steps);
      } else {
        r = spawn_ray(sp, ws[j], kStrategies[s], static_cast<T>(epsilon));
      }
      out.rays[s][j] = to_double(r);
    }
  }
  return out;
}

}  // namespace

mesh::Mesh generated_spawn_mesh(int subdivisions, double slab_thickness, double scale, double offset) {
  if (subdivisions < 0 || subdivisions > 7) throw std::invalid_argument("subdivisions must be in 0..7");
  mesh::Mesh m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, fresh] = mid.try_emplace({key.first, key.second}, std::uint32_t(m.vertices.size()));
      if (fresh) m.vertices.push_back(normalize(m.vertices[a] + m.vertices[b]));
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({a, t[1], b});
      next.push_back({c, b, t[2]});
      next.push_back({a, b, c});
    }
    m.triangles = std::move(next);
  }
  // The slab: x in [2, 4], y in [-1, 1], z in [0, thickness], outward-facing triangles.
  const auto base = std::uint32_t(m.vertices.size());
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back({k & 1 ? 4.0 : 2.0, k & 2 ? 1.0 : -1.0, k & 4 ? slab_thickness : 0.0});
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({base + q[0], base + q[1], base + q[2]});
    m.triangles.push_back({base + q[0], base + q[2], base + q[3]});
  }
  for (auto& v : m.vertices) v = scale * v + V{offset, offset, offset};
  return m;
}

std::vector<MeshSpawnCount> count_mesh_spawn(const mesh::Mesh& input, std::uint64_t trials, std::uint64_t seed,
                                             double epsilon) {
  if (input.triangles.empty()) throw std::invalid_argument("the mesh has no triangles");
  mesh::Mesh m = input;
  for (auto& v : m.vertices) v = V{double(float(v.x)), double(float(v.y)), double(float(v.z))};
  // Neighbours (the triangles a spawned ray cannot meet, the crease at t ~ 0) are found through
  // shared vertices: vertices at one position are one vertex there, as in a mesh read from STL or
  // one whose faces repeat their corners. The casters see the mesh as given.
  mesh::Mesh welded = m;
  {
    std::map<std::array<double, 3>, std::uint32_t> first;
    std::vector<std::uint32_t> canon(m.vertices.size());
    for (std::uint32_t i = 0; i < m.vertices.size(); ++i)
      canon[i] = first.try_emplace({m.vertices[i].x, m.vertices[i].y, m.vertices[i].z}, i).first->second;
    for (auto& t : welded.triangles)
      for (auto& v : t) v = canon[v];
  }
  const Geometry g(welded);
  const VertexArray va(&m.vertices[0].x, m.vertices.size());
  const IndexArray ia{m.triangles[0].data(), m.triangles.size()};
  const MeshCaster<cast::Float> c_float(va, ia);
  const MeshCaster<cast::Robust> c_robust(va, ia);
  const MeshCaster<cast::Certified> c_cert(va, ia);
  V lo = m.vertices[0], hi = lo;
  for (const auto& v : m.vertices)
    for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
  const double size = 0.5 * length(hi - lo);

  std::vector<MeshSpawnCount> rows;
  for (const char* name : {"float", "robust", "certified"})
    for (SpawnStrategy s : kStrategies) rows.push_back({s, name});

  const double near = std::ldexp(size, -30);
  auto shares_vertex = [&](std::uint32_t a, std::uint32_t b) {
    for (auto u : welded.triangles[a])
      for (auto v : welded.triangles[b])
        if (u == v) return true;
    return false;
  };
  gen::Rng rng(seed);
  for (std::uint64_t k = 0; k < trials; ++k) {
    // A point on a random triangle (interior, on an edge or at a vertex) seen from its front.
    const auto ti = static_cast<std::uint32_t>(rng.below(m.triangles.size()));
    const Triangle<double> t = g.tri(ti);
    double b1 = rng.unit(), b2 = rng.unit();
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    const int where = static_cast<int>(rng.below(3));
    if (where == 1) b2 = 1 - b1;                      // on the edge p1 p2 (up to rounding)
    if (where == 2) b1 = 1 - 1e-6 * (0.5 + 0.5 * rng.unit()), b2 = 0;  // near the vertex p1, float-resolvable
    const V target = (1 - b1 - b2) * t.p0 + b1 * t.p1 + b2 * t.p2;
    const V nt = normalize(cross(t.p1 - t.p0, t.p2 - t.p0));
    if (!all_finite(nt)) continue;
    V tang = random_unit(rng);
    tang = tang - dot(tang, nt) * nt;
    const V origin = target + size * (rng.uniform(0.3, 1) * nt + 0.5 * tang);
    const Ray<double> primary{origin, target - origin};
    V tl = random_unit(rng), tb = random_unit(rng);
    const double up = rng.uniform(0.2, 1), down = rng.uniform(0.02, 1);

    // The reference: the certified caster's hit, its certified origins and visibility.
    const MeshHit href = c_cert.closest(primary);
    if (!href.hit()) continue;
    const Triangle<double> th = g.tri(href.triangle);
    const TriangleHit<double> bh = certified::intersect(primary, th);
    const SurfacePoint<double> sref = triangle_point<double>(th, bh.b1, bh.b2);
    const V n_in = dot(primary.d, sref.n) < 0 ? sref.n : -sref.n;
    tl = tl - dot(tl, n_in) * n_in, tb = tb - dot(tb, n_in) * n_in;
    const Lights L{sref.p + size * (up * n_in + 0.5 * tl), sref.p + size * (-down * n_in + 0.3 * tb)};
    const Spawned<double> ref = spawn_all<double>(g, href.triangle, sref, primary.d, L, epsilon);
    // A first blocker within 2^-30 of the mesh's size from the origin, sharing a vertex with the
    // triangle left, is the crease the hit point sits on (a concave neighbour met at t ~ 0):
    // whether the light is seen is not decided by the computed point there, and the shadow ray is
    // not compared (the same for the method's ray, below, unless the blocker is one it cannot meet).
    std::array<bool, 3> ref_blocked{}, ref_ambiguous{};
    for (std::size_t j = 1; j < 3; ++j) {
      const Ray<double>& r = ref.rays[3][j];
      const Ray<double> shadow{r.o, (j == 1 ? L.front : L.back) - r.o};
      const MeshHit x = c_cert.closest(shadow, {kTmin, 1});
      ref_blocked[j] = x.hit();
      ref_ambiguous[j] = x.hit() && x.t * length(shadow.d) < near && shares_vertex(x.triangle, href.triangle);
    }

    for (std::size_t mi = 0; mi < 3; ++mi) {
      MeshSpawnCount* row = &rows[mi * kStrategies.size()];
      MeshHit h;
      if (mi == 0) h = c_float.closest(primary);
      else if (mi == 1) h = c_robust.closest(primary);
      else h = href;
      if (!h.hit()) {
        const Ray<double> rounded{V{double(float(primary.o.x)), double(float(primary.o.y)), double(float(primary.o.z))},
                                  V{double(float(primary.d.x)), double(float(primary.d.y)), double(float(primary.d.z))}};
        const bool ray_misses = mi < 2 && !c_cert.closest(rounded).hit();
        for (std::size_t s = 0; s < kStrategies.size(); ++s) ++row[s].primary_misses, row[s].primary_misses_ray += ray_misses;
        continue;
      }
      std::array<std::array<Ray<double>, 3>, 4> rays;
      std::array<bool, 3> valid;
      std::array<std::vector<std::uint32_t>, 3> imp;
      if (mi < 2) {
        // float and robust see float-rounded rays: their points and origins are floats.
        const Triangle<double> tm = g.tri(h.triangle);
        const auto sp = spawn_all<float>(g, h.triangle, triangle_point<float>(tm, h.b1, h.b2), primary.d, L, epsilon);
        rays = sp.rays, valid = sp.valid, imp = sp.impossible;
      } else {
        rays = ref.rays, valid = ref.valid, imp = ref.impossible;
      }
      for (std::size_t s = 0; s < kStrategies.size(); ++s)
        for (std::size_t j = 0; j < 3; ++j) {
          if (!valid[j] || !ref.valid[j]) continue;
          const Ray<double>& r = rays[s][j];
          ++row[s].spawned;
          bool own = false;
          if (kStrategies[s] == SpawnStrategy::certified) own = certified_meets(g, imp[j], r);
          else if (mi == 0) own = caster_meets(c_float, imp[j], r);
          else if (mi == 1) own = caster_meets(c_robust, imp[j], r);
          else own = caster_meets(c_cert, imp[j], r);
          if (own) ++row[s].self_hits;
          if (caster_meets(c_cert, imp[j], r)) ++row[s].exact_self_hits;
          if (j == 0 || ref_ambiguous[j] || h.triangle != href.triangle) continue;
          const Ray<double> shadow{r.o, (j == 1 ? L.front : L.back) - r.o};
          std::vector<MeshHit> xs;
          if (mi == 0) xs = c_float.all(shadow, {kTmin, 1});
          else if (mi == 1) xs = c_robust.all(shadow, {kTmin, 1});
          else xs = c_cert.all(shadow, {kTmin, 1});
          // The certified strategy classifies the triangles it cannot meet exactly (not met, by
          // construction): the caster's answers on them are replaced by that.
          if (kStrategies[s] == SpawnStrategy::certified)
            std::erase_if(xs, [&](const MeshHit& x) { return std::find(imp[j].begin(), imp[j].end(), x.triangle) != imp[j].end(); });
          const bool blocked = !xs.empty();
          if (blocked && xs[0].t * length(shadow.d) < near && shares_vertex(xs[0].triangle, h.triangle) &&
              std::find(imp[j].begin(), imp[j].end(), xs[0].triangle) == imp[j].end())
            continue;  // a concave crease at t ~ 0
          ++row[s].shadow;
          if (blocked == ref_blocked[j]) continue;
          // The same ray through the certified caster: does it answer as the method's caster did?
          std::vector<MeshHit> cx = mi == 2 ? xs : c_cert.all(shadow, {kTmin, 1});
          if (kStrategies[s] == SpawnStrategy::certified)
            std::erase_if(cx, [&](const MeshHit& x) { return std::find(imp[j].begin(), imp[j].end(), x.triangle) != imp[j].end(); });
          const bool ray_agrees = cx.empty() != blocked;
          if (blocked) ++row[s].false_occlusions, row[s].false_occlusions_ray += ray_agrees;
          else ++row[s].leaks, row[s].leaks_ray += ray_agrees;
        }
    }
  }
  return rows;
}

}  // namespace rayproof::light
