// Leak counting on closed meshes (see watertight.h).
#include "scene/watertight.h"

#include <algorithm>
#include <cmath>

namespace rayproof::scene {

std::vector<Vec3<double>> leak_targets(const mesh::Mesh& m, std::size_t limit) {
  std::vector<std::uint64_t> edges;
  edges.reserve(m.triangles.size() * 3);
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
      edges.push_back(a << 32 | b);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const std::size_t n = m.vertices.size() + edges.size();
  const std::size_t stride = limit && n > limit ? (n + limit - 1) / limit : 1;
  std::vector<Vec3<double>> out;
  out.reserve(n / stride + 1);
  for (std::size_t i = 0; i < n; i += stride) {
    if (i < m.vertices.size()) {
      out.push_back(m.vertices[i]);
    } else {
      const std::uint64_t e = edges[i - m.vertices.size()];
      out.push_back((m.vertices[e >> 32] + m.vertices[e & 0xffffffffu]) * 0.5);
    }
  }
  return out;
}

std::vector<Ray<double>> leak_rays(Vec3<double> inside, const std::vector<Vec3<double>>& targets) {
  std::vector<Ray<double>> rays;
  rays.reserve(targets.size());
  for (const auto& p : targets) rays.push_back({inside, p - inside});
  return rays;
}

LeakCount count_leaks(const Accel& a, const SceneMethod& m, const std::vector<Ray<double>>& rays, int threads) {
  std::vector<PrimHit> hits(rays.size());
  a.closest_batch(rays, hits, m, threads);
  LeakCount c;
  c.rays = rays.size();
  for (const auto& h : hits) c.misses += h.prim == PrimHit::kNoPrim;
  return c;
}

Vec3<double> volume_centroid(const mesh::Mesh& m) {
  Vec3<double> acc{0, 0, 0};
  double vol = 0;
  for (const auto& t : m.triangles) {
    const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const double v = dot(a, cross(b, c));  // 6 x signed volume of (0, a, b, c)
    vol += v;
    acc = acc + v * (a + b + c);
  }
  return acc / (4 * vol);
}

mesh::Mesh bumpy_sphere(std::size_t min_triangles) {
  int sub = 0;
  while (20 * (std::size_t(1) << (2 * sub)) < min_triangles) ++sub;
  mesh::Mesh m = icosphere(sub);
  for (auto& v : m.vertices) {
    const double r = 1 + 0.08 * std::sin(7 * v.x) * std::sin(5 * v.y + 1) + 0.05 * std::cos(11 * v.z);
    v = r * v;
  }
  return m;
}

}  // namespace rayproof::scene
