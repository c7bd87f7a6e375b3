// run_crossings_fuzz: ExactMesh::ray_crossings on the random closed meshes of fuzz --mesh, against the
// exact winding number at each ray's origin.
#include "verify/crossings_fuzz.h"

#include <chrono>
#include <cmath>
#include <set>
#include <utility>

#include "rayproof/scene/exact_mesh.h"

namespace rayproof::verify {

CrossingsFuzzResult run_crossings_fuzz(const MeshFuzzOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  CrossingsFuzzResult res;
  const std::size_t max_meshes = opt.max_meshes ? opt.max_meshes : (opt.seconds > 0 ? SIZE_MAX : 1);
  std::normal_distribution<double> g;
  for (std::size_t i = 0; i < max_meshes; ++i) {
    if (opt.max_meshes == 0 && opt.seconds > 0 && elapsed() >= opt.seconds) break;
    MeshShape shape;
    std::vector<Vec3<double>> interior;
    std::mt19937_64 rng;
    const mesh::Mesh m = fuzz_mesh(opt, i, shape, interior, rng);
    const ExactMesh cm(VertexArray(&m.vertices[0].x, m.vertices.size()),
                        IndexArray{m.triangles.front().data(), m.triangles.size()});
    ++res.meshes;
    res.triangles += m.triangles.size();
    // Origins: the interior points, and as many outside (beyond the bounding box).
    Vec3<double> lo = m.vertices[0], hi = lo;
    for (const auto& p : m.vertices)
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    std::vector<Vec3<double>> origins = interior;
    for (std::size_t k = 0; k < interior.size(); ++k) {
      Vec3<double> dir{g(rng), g(rng), g(rng)};
      const double len = std::sqrt(dot(dir, dir)) + 1e-300;
      const double far = 2 * std::sqrt(dot(hi - lo, hi - lo)) / len;
      origins.push_back({float((lo.x + hi.x) / 2 + far * dir.x), float((lo.y + hi.y) / 2 + far * dir.y),
                         float((lo.z + hi.z) / 2 + far * dir.z)});
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& t : m.triangles)
      for (int e = 0; e < 3; ++e) edges.insert(std::minmax(t[e], t[(e + 1) % 3]));
    for (const auto& p : origins) {
      const std::int32_t w = cm.winding(p);
      if (w == ExactMesh::kOnSurface) continue;
      std::vector<std::pair<Ray<double>, bool>> rays;  // the ray, aimed at a vertex or an edge midpoint
      for (const auto& v : m.vertices) rays.push_back({{p, v - p}, true});
      for (const auto& [a, b] : edges) rays.push_back({{p, (m.vertices[a] + m.vertices[b]) * 0.5 - p}, true});
      for (int k = 0; k < opt.parity_rays; ++k) rays.push_back({{p, {g(rng), g(rng), g(rng)}}, false});
      for (const auto& [r, aimed] : rays) {
        if (!r.valid()) continue;
        const RayCrossings c = cm.ray_crossings(r);
        ++res.rays;
        res.aimed_rays += aimed;
        res.crossings += c.crossings.size();
        res.touches += c.touches.size();
        bool ok = c.valid && c.net() == -w && (c.crossings.size() % 2) == std::size_t(std::abs(w) % 2);
        for (std::size_t k = 1; k < c.crossings.size(); ++k) ok = ok && c.crossings[k - 1].t <= c.crossings[k].t;
        if (ok) continue;
        ++res.failures;
        if (res.findings.size() < opt.keep_findings) res.findings.push_back({i, r, c.crossings.size(), c.net(), w});
      }
    }
  }
  res.seconds = elapsed();
  return res;
}

}  // namespace rayproof::verify
