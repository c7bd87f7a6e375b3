// Mesh-level property fuzzing (see mesh_fuzz.h). CGAL builds the convex hulls and checks that the
// hulls' interior points are strictly inside (exact orientation predicates).
#include "verify/mesh_fuzz.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "scene/watertight.h"

namespace rayproof::verify {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

// Random numbers from the generator's bits only (no library distributions, no libm), so that a
// seed means the same meshes and rays with every standard library.
double u01(std::mt19937_64& r) { return double(r() >> 11) * 0x1p-53; }
double uniform(std::mt19937_64& r, double a, double b) { return a + (b - a) * u01(r); }
/// A random point in the unit ball, away from the centre (so it is also a usable direction).
Vec3<double> in_ball(std::mt19937_64& r) {
  for (;;) {
    const Vec3<double> p{uniform(r, -1, 1), uniform(r, -1, 1), uniform(r, -1, 1)};
    const double l = dot(p, p);
    if (l <= 1 && l > 1e-4) return p;
  }
}
Vec3<double> to_float(Vec3<double> p) { return p.cast<float>().cast<double>(); }

/// A random placement: scale 2^-3 .. 2^7 and a centre within a few scales of the origin.
void placement(std::mt19937_64& r, double& scale, Vec3<double>& centre) {
  scale = std::ldexp(uniform(r, 1, 2), int(r() % 11) - 3);
  centre = Vec3<double>{uniform(r, -4, 4), uniform(r, -4, 4), uniform(r, -4, 4)} * scale;
}

/// Two hits (sorted by t) are one crossing when their t are equal, or when both are edge or vertex
/// contacts within a relative 1e-5 of each other: the triangles around an edge or vertex compute
/// their t separately, so a kernel that classes the contact right may still round t differently.
bool same_crossing(const scene::PrimHit& a, const scene::PrimHit& b) {
  if (a.t == b.t) return true;
  auto on_edge = [](Contact c) { return c == Contact::edge || c == Contact::vertex; };
  return on_edge(a.contact) && on_edge(b.contact) && std::abs(b.t - a.t) <= 1e-5 * std::max(std::abs(a.t), std::abs(b.t));
}

}  // namespace

mesh::Mesh random_star_mesh(std::mt19937_64& rng, int subdivisions, int count, std::vector<Vec3<double>>& interior) {
  mesh::Mesh m = scene::icosphere(subdivisions);
  double scale;
  Vec3<double> c;
  placement(rng, scale, c);
  for (auto& v : m.vertices) v = to_float(c + (scale * uniform(rng, 0.7, 1.3)) * v);
  // The solid holds the ball of radius 0.7 cos(37.4 deg) > 0.55 (times scale) about c: every
  // triangle spans directions within 37.4 degrees of its centroid direction (the icosahedron's worst).
  interior.clear();
  for (int k = 0; k < count; ++k) interior.push_back(to_float(c + (0.25 * scale) * in_ball(rng)));
  return m;
}

mesh::Mesh random_hull_mesh(std::mt19937_64& rng, int points, int count, std::vector<Vec3<double>>& interior) {
  for (;;) {
    double scale;
    Vec3<double> c;
    placement(rng, scale, c);
    const int style = int(rng() % 3);
    std::vector<Point> pts;
    for (int i = 0; i < std::max(points, 4); ++i) {
      Vec3<double> p;
      if (style == 0) p = in_ball(rng);                // random doubles in a ball
      else if (style == 1) p = normalize(in_ball(rng));  // near a sphere: many thin triangles
      else p = Vec3<double>{double(int(rng() % 9) - 4), double(int(rng() % 9) - 4), double(int(rng() % 9) - 4)} / 4.0;  // grid: coplanar facets
      const Vec3<double> q = to_float(c + scale * p);
      pts.emplace_back(q.x, q.y, q.z);
    }
    SurfaceMesh sm;
    CGAL::convex_hull_3(pts.begin(), pts.end(), sm);
    if (sm.number_of_faces() < 4 || !CGAL::is_closed(sm)) continue;  // coplanar points: draw again
    // CGAL's hull lists vertices and faces in an order that depends on memory addresses (it keys
    // maps by handle): sort both so that the mesh, and the random numbers drawn for it, depend on
    // the seed only.
    std::vector<std::pair<std::array<double, 3>, std::uint32_t>> order;
    for (auto v : sm.vertices()) order.push_back({{sm.point(v).x(), sm.point(v).y(), sm.point(v).z()}, std::uint32_t(v)});
    std::sort(order.begin(), order.end());
    mesh::Mesh m;
    std::unordered_map<std::uint32_t, std::uint32_t> index;
    for (const auto& [p, v] : order) {
      index[v] = std::uint32_t(m.vertices.size());
      m.vertices.push_back({p[0], p[1], p[2]});
    }
    std::vector<std::uint32_t> corners;
    for (auto f : sm.faces()) {
      corners.clear();
      for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) corners.push_back(index.at(std::uint32_t(v)));
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        std::array<std::uint32_t, 3> t{corners[0], corners[k], corners[k + 1]};
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // keeps the orientation
        m.triangles.push_back(t);
      }
    }
    std::sort(m.triangles.begin(), m.triangles.end());
    // Interior points: convex combinations of every hull vertex with skewed positive weights, kept
    // only when (after rounding to float) they lie strictly on the inner side of every face.
    interior.clear();
    for (int attempt = 0; attempt < 100 * count && int(interior.size()) < count; ++attempt) {
      Vec3<double> sum{0, 0, 0};
      double wsum = 0;
      for (const auto& v : m.vertices) {
        const double u = u01(rng), w = u * u * u + 1e-3;
        sum = sum + w * v, wsum += w;
      }
      const Vec3<double> p = to_float(sum / wsum);
      const Point q(p.x, p.y, p.z);
      int sign = 0;
      bool inside = true;
      for (const auto& t : m.triangles) {
        const auto& a = m.vertices[t[0]];
        const auto& b = m.vertices[t[1]];
        const auto& d = m.vertices[t[2]];
        const int o = int(CGAL::orientation(Point(a.x, a.y, a.z), Point(b.x, b.y, b.z), Point(d.x, d.y, d.z), q));
        if (o == 0 || (sign != 0 && o != sign)) {
          inside = false;
          break;
        }
        sign = o;
      }
      if (inside) interior.push_back(p);
    }
    if (int(interior.size()) == count) return m;
  }
}

mesh::Mesh fuzz_mesh(const MeshFuzzOptions& opt, std::size_t i, MeshShape& shape, std::vector<Vec3<double>>& interior,
                     std::mt19937_64& rng) {
  rng.seed((opt.seed + 1) * 0x9E3779B97F4A7C15ull + i);
  shape = i % 2 ? MeshShape::hull : MeshShape::star;
  if (shape == MeshShape::star)
    return random_star_mesh(rng, int(rng() % std::uint64_t(opt.max_subdivisions + 1)), opt.interior_points, interior);
  const int n = 8 + int(rng() % std::uint64_t(std::max(1, opt.max_hull_points - 7)));
  return random_hull_mesh(rng, n, opt.interior_points, interior);
}

MeshFuzzResult run_mesh_fuzz(const MeshFuzzOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  MeshFuzzResult res;
  for (const auto& m : opt.methods) res.stats.push_back({m.name});
  std::vector<std::size_t> kept(opt.methods.size(), 0);
  int ref = -1;
  for (std::size_t j = 0; j < opt.methods.size(); ++j)
    if (opt.methods[j].name == opt.reference) ref = int(j);
  const std::size_t max_meshes = opt.max_meshes ? opt.max_meshes : (opt.seconds > 0 ? SIZE_MAX : 1);

  for (std::size_t i = 0; i < max_meshes; ++i) {
    if (opt.seconds > 0 && !opt.max_meshes && elapsed() >= opt.seconds) break;
    std::mt19937_64 rng;
    MeshShape shape;
    std::vector<Vec3<double>> interior;
    scene::Scene s;
    scene::add_mesh(s, fuzz_mesh(opt, i, shape, interior, rng));
    ++(shape == MeshShape::star ? res.star_meshes : res.hull_meshes);
    ++res.meshes;
    res.triangles += s.mesh.triangles.size();
    const scene::Accel accel(s);

    // Leak rays: every vertex and edge midpoint, direction exact (float minus float, in double)
    // and normalized in float.
    const auto targets = scene::leak_targets(s.mesh);
    std::vector<Ray<double>> rays;
    for (const auto& p : interior)
      for (const auto& t : targets) {
        rays.push_back({p, t - p});
        rays.push_back({p, normalize(t.cast<float>() - p.cast<float>()).cast<double>()});
      }
    std::vector<scene::PrimHit> hits(rays.size());
    for (std::size_t j = 0; j < opt.methods.size(); ++j) {
      accel.closest_batch(rays, hits, opt.methods[j], opt.threads);
      auto& st = res.stats[j];
      st.leak_rays += rays.size();
      for (std::size_t k = 0; k < rays.size(); ++k) {
        if (hits[k].prim != scene::PrimHit::kNoPrim) continue;
        ++st.leaks;
        if (kept[j] < opt.keep_findings) ++kept[j], res.findings.push_back({st.method, true, i, shape, rays[k], 0});
      }
    }

    // Parity rays: half in random directions, half aimed at a random point of a random edge (where
    // a kernel that is not watertight double-counts or misses); crossings are distinct t values.
    for (const auto& p : interior)
      for (int k = 0; k < opt.parity_rays; ++k) {
        Ray<double> r{p, in_ball(rng)};
        if (k % 2 == 1) {
          const auto& t = s.mesh.triangles[rng() % s.mesh.triangles.size()];
          const int e = int(rng() % 3);
          const Vec3<double> a = s.mesh.vertices[t[e]], b = s.mesh.vertices[t[(e + 1) % 3]];
          r.d = a + uniform(rng, 0.01, 0.99) * (b - a) - p;
        }
        std::vector<std::vector<scene::PrimHit>> all(opt.methods.size());
        for (std::size_t j = 0; j < opt.methods.size(); ++j) all[j] = accel.all(r, opt.methods[j]);
        if (ref >= 0 && std::any_of(all[std::size_t(ref)].begin(), all[std::size_t(ref)].end(),
                                    [](const scene::PrimHit& h) { return h.contact != Contact::interior; })) {
          ++res.contact_rays_set_aside;
          continue;
        }
        for (std::size_t j = 0; j < opt.methods.size(); ++j) {
          std::size_t crossings = 0;
          for (std::size_t h = 0; h < all[j].size(); ++h) crossings += h == 0 || !same_crossing(all[j][h - 1], all[j][h]);
          auto& st = res.stats[j];
          ++st.parity_rays;
          if (crossings % 2 == 1) continue;
          ++st.parity_failures;
          if (kept[j] < opt.keep_findings) ++kept[j], res.findings.push_back({st.method, false, i, shape, r, crossings});
        }
      }
  }
  res.seconds = elapsed();
  return res;
}

}  // namespace rayproof::verify
