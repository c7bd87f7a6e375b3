// The geometry of a scene for `rayproof advise` (see analysis.h).
#include "scene/analysis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "rayproof/certified_expansion.h"
#include "rayproof/float_util.h"

namespace rayproof::scene {

std::optional<bool> collinear_exact(Vec3<double> p0, Vec3<double> p1, Vec3<double> p2) {
  // Collinearity does not change under scaling by a power of 2: bring the largest coordinate near
  // 1 (exact while no coordinate becomes subnormal). Then differences are exact in two doubles
  // (two_sum) and products of their parts exact with an FMA while every nonzero coordinate is at
  // least 2^-400 (products stay above 2^-906, far from underflow). Else: not decided here.
  double m = 0;
  for (const auto* p : {&p0, &p1, &p2}) m = std::max({m, std::fabs(p->x), std::fabs(p->y), std::fabs(p->z)});
  if (!std::isfinite(m)) return std::nullopt;
  if (m == 0) return true;
  const int e = -std::ilogb(m);
  for (auto* p : {&p0, &p1, &p2})
    for (int k = 0; k < 3; ++k) {
      const double x = std::ldexp((*p)[k], e);
      if (x != 0 && std::fabs(x) < 0x1p-400) return std::nullopt;
      (*p)[k] = x;
    }
  const Vec3<double> a = p1 - p0, b = p2 - p0;
  const Vec3<double> n = cross(a, b);
  // Filter: each component of the computed cross product is within gamma(4) of the sum of its
  // products' magnitudes from the exact one (differences, products and their difference each round
  // once). Clearly nonzero somewhere: not collinear. Else exact expansions decide.
  const double s[3] = {std::fabs(a.y * b.z) + std::fabs(a.z * b.y), std::fabs(a.z * b.x) + std::fabs(a.x * b.z),
                       std::fabs(a.x * b.y) + std::fabs(a.y * b.x)};
  for (int k = 0; k < 3; ++k)
    if (std::fabs(n[k]) > gamma<double>(4) * s[k]) return false;
  using certified::Expansion;
  const certified::ExpVec3 ea = certified::diff3(p1, p0), eb = certified::diff3(p2, p0);
  const Expansion nx = ea.y * eb.z - ea.z * eb.y, ny = ea.z * eb.x - ea.x * eb.z, nz = ea.x * eb.y - ea.y * eb.x;
  if (nx.bad || ny.bad || nz.bad) return std::nullopt;
  return nx.n == 0 && ny.n == 0 && nz.n == 0;
}

namespace {

bool is_finite(const Vec3<double>& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_float(double x) { return double(float(x)) == x || std::isnan(x); }

struct Coords {
  SceneAnalysis& a;
  void add(double x) {
    ++a.coordinates;
    const double m = std::fabs(x);
    if (!std::isfinite(m)) return;
    if (m == 0) {
      ++a.zero_coordinates;
      return;
    }
    if (a.min_abs == 0 || m < a.min_abs) a.min_abs = m;
    a.max_abs = std::max(a.max_abs, m);
  }
  bool add(const Vec3<double>& v) {
    add(v.x), add(v.y), add(v.z);
    return is_float(v.x) && is_float(v.y) && is_float(v.z);
  }
};

/// Union-find over triangles.
struct Components {
  std::vector<std::uint32_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::uint32_t x, std::uint32_t y) {
    x = find(x), y = find(y);
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
  }
};

}  // namespace

SceneAnalysis analyse_scene(const Scene& s, double sliver_aspect) {
  SceneAnalysis a;
  const auto& V = s.mesh.vertices;
  const auto& T = s.mesh.triangles;
  a.vertices = V.size(), a.triangles = T.size();
  a.spheres = s.spheres.size(), a.ellipsoids = s.ellipsoids.size(), a.disks = s.disks.size(), a.boxes = s.boxes.size();
  a.lights = s.lights.size(), a.has_camera = s.camera.has_value();
  a.sliver_aspect = sliver_aspect;

  Coords c{a};
  for (const auto& v : V) a.non_float_vertices += !c.add(v);
  auto analytic = [&](bool is_f) { a.non_float_analytic += !is_f; };
  for (const auto& x : s.spheres) c.add(x.radius), analytic(c.add(x.center) && is_float(x.radius));
  // Both points are added (no short circuit), so the counts and spread see every coordinate.
  for (const auto& x : s.ellipsoids) {
    const bool center = c.add(x.center), axes = c.add(x.semi_axes);
    analytic(center && axes);
  }
  for (const auto& x : s.disks) c.add(x.radius), analytic(c.add(x.center) && is_float(x.radius));
  for (const auto& x : s.boxes) {
    const bool lo = c.add(x.lo), hi = c.add(x.hi);
    analytic(lo && hi);
  }
  if (a.min_abs > 0) a.spread_binades = std::ilogb(a.max_abs) - std::ilogb(a.min_abs);

  // Degenerate and sliver triangles.
  for (const auto& t : T) {
    const Vec3<double> &p0 = V[t[0]], &p1 = V[t[1]], &p2 = V[t[2]];
    const std::optional<bool> line = collinear_exact(p0, p1, p2);
    if (!line) ++a.undecided;
    if (line.value_or(false)) {
      ++a.degenerate;
      continue;
    }
    if (!line) continue;
    const double l2 = std::max({length_squared(p1 - p0), length_squared(p2 - p1), length_squared(p0 - p2)});
    const double aspect = l2 / length(cross(p1 - p0, p2 - p0));
    if (aspect > sliver_aspect) ++a.slivers;
    if (aspect == aspect) a.max_aspect = std::max(a.max_aspect, aspect);
  }

  // Weld vertices at the same position (exact comparison; non-finite ones stay apart).
  std::vector<std::uint32_t> order(V.size()), weld(V.size());
  std::iota(order.begin(), order.end(), 0u);
  auto less = [&](std::uint32_t i, std::uint32_t j) {
    const auto &p = V[i], &q = V[j];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return p.z < q.z;
  };
  std::sort(order.begin(), order.end(), [&](std::uint32_t i, std::uint32_t j) {
    const bool fi = is_finite(V[i]), fj = is_finite(V[j]);
    if (fi != fj) return fi;
    if (!fi) return i < j;
    return less(i, j) || (!less(j, i) && i < j);
  });
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = order[k];
    if (k > 0 && is_finite(V[i]) && is_finite(V[order[k - 1]]) && !less(order[k - 1], i) && !less(i, order[k - 1])) {
      weld[i] = weld[order[k - 1]];
      ++a.welded;
    } else {
      weld[i] = i;
    }
  }

  // Edges: (lower, higher welded vertex) and the triangle, sorted; a run is one edge.
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t tri;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(T.size() * 3);
  for (std::uint32_t i = 0; i < T.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = weld[T[i][k]], v = weld[T[i][(k + 1) % 3]];
      if (u == v) continue;
      uses.push_back({std::uint64_t(std::min(u, v)) << 32 | std::max(u, v), i});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key || (x.key == y.key && x.tri < y.tri); });
  Components comp(T.size());
  std::vector<bool> bad_edge_tri(T.size(), false), has_edge(T.size(), false);
  for (std::size_t b = 0; b < uses.size();) {
    std::size_t e = b + 1;
    while (e < uses.size() && uses[e].key == uses[b].key) ++e;
    ++a.edges;
    const std::size_t n = e - b;
    if (n == 1) ++a.open_edges;
    if (n >= 3) ++a.non_manifold_edges;
    for (std::size_t k = b; k < e; ++k) {
      comp.join(uses[b].tri, uses[k].tri);
      has_edge[uses[k].tri] = true;
      if (n != 2) bad_edge_tri[uses[k].tri] = true;
    }
    b = e;
  }
  // Number the components in triangle order; a component is closed when it has edges and none of
  // its triangles has an edge used once or more than twice.
  a.component_of.assign(T.size(), 0);
  std::vector<std::uint32_t> number(T.size(), 0xffffffffu);
  for (std::uint32_t i = 0; i < T.size(); ++i) {
    const std::uint32_t r = comp.find(i);
    if (number[r] == 0xffffffffu) {
      number[r] = std::uint32_t(a.components++);
      a.component_closed.push_back(true);
    }
    const std::uint32_t k = a.component_of[i] = number[r];
    if (bad_edge_tri[i] || !has_edge[i]) a.component_closed[k] = false;
  }
  for (bool closed : a.component_closed) a.closed_components += closed;
  return a;
}

std::vector<mesh::Mesh> closed_component_meshes(const Scene& s, const SceneAnalysis& a, std::size_t limit) {
  // Slot of each closed component kept (or none), then every triangle appended to its slot's mesh,
  // vertices renumbered per slot through one map (a vertex belongs to one component unless the
  // mesh shares it between components: then it is copied into each).
  std::vector<std::uint32_t> slot(a.components, 0xffffffffu);
  std::size_t n = 0;
  for (std::uint32_t c = 0; c < a.components; ++c)
    if (a.component_closed[c] && (limit == 0 || n < limit)) slot[c] = std::uint32_t(n++);
  std::vector<mesh::Mesh> out(n);
  std::vector<std::uint32_t> remap_slot(s.mesh.vertices.size(), 0xffffffffu), remap(s.mesh.vertices.size(), 0);
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i) {
    const std::uint32_t k = slot[a.component_of[i]];
    if (k == 0xffffffffu) continue;
    mesh::Mesh& m = out[k];
    std::array<std::uint32_t, 3> t;
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t v = s.mesh.triangles[i][j];
      if (remap_slot[v] != k) {
        remap_slot[v] = k, remap[v] = std::uint32_t(m.vertices.size());
        m.vertices.push_back(s.mesh.vertices[v]);
      }
      t[j] = remap[v];
    }
    m.triangles.push_back(t);
  }
  return out;
}

}  // namespace rayproof::scene
