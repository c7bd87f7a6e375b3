// Leak check of one kernel on closed meshes (see mesh_check.h).
#include "verify/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/core.h>

#include "scene/watertight.h"
#include "verify/differential.h"

namespace rayproof::verify {

namespace {

Vec3<double> to_float(Vec3<double> p) { return p.cast<float>().cast<double>(); }

io::Case triangle_case(const Ray<double>& r, const scene::Scene& s, std::uint32_t tri) {
  io::Case c;
  c.kind = io::Kind::triangle;
  const auto& t = s.mesh.triangles[tri];
  const Vec3<double> p[5] = {r.o, r.d, s.mesh.vertices[t[0]], s.mesh.vertices[t[1]], s.mesh.vertices[t[2]]};
  for (int i = 0; i < 5; ++i) {
    c.v[std::size_t(3 * i)] = p[i].x;
    c.v[std::size_t(3 * i + 1)] = p[i].y;
    c.v[std::size_t(3 * i + 2)] = p[i].z;
  }
  return c;
}

struct RayWork {
  Ray<double> ray;
  std::vector<scene::PrimHit> hits;  ///< the finder's crossings at t >= 0
  std::size_t first = 0;             ///< index of its first candidate case in the batch
  std::vector<std::uint32_t> prims;  ///< its candidate triangles
};

}  // namespace

std::optional<std::string> closed_mesh_problem(const mesh::Mesh& m) {
  if (m.triangles.empty()) return "it has no triangles";
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  std::size_t bad_index = 0;
  for (const auto& t : m.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++bad_index;
    for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  }
  if (bad_index) return std::to_string(bad_index) + " triangles repeat a vertex index";
  const auto open = std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second != 2; });
  if (open) return std::to_string(open) + " of its " + std::to_string(uses.size()) +
                   " edges are not shared by exactly two triangles (it is not closed)";
  return std::nullopt;
}

std::vector<Vec3<double>> interior_points(const mesh::Mesh& m, const scene::SceneMethod& finder, int count,
                                          std::uint64_t seed) {
  std::vector<Vec3<double>> out;
  if (count <= 0 || m.triangles.empty()) return out;
  scene::Scene s;
  scene::add_mesh(s, m);
  const scene::Accel accel(s);
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 17);
  auto u = [&] { return double(rng() >> 11) * 0x1p-53 * 2 - 1; };
  auto inside = [&](const Vec3<double>& p) {
    for (int k = 0; k < 3; ++k) {
      const Ray<double> r{p, Vec3<double>{u(), u(), u()}};
      const auto hits = accel.all(r, finder);
      if (hits.size() % 2 == 0) return false;
      for (const auto& h : hits)
        if (h.contact != Contact::interior) return false;
    }
    return true;
  };
  // Orientation: the signed volume tells which side of each triangle is inside.
  double vol = 0;
  for (const auto& t : m.triangles) vol += dot(m.vertices[t[0]], cross(m.vertices[t[1]], m.vertices[t[2]]));
  const double side = vol >= 0 ? -1 : 1;
  std::vector<Vec3<double>> tries{to_float(scene::volume_centroid(m))};
  const std::size_t stride = std::max<std::size_t>(1, m.triangles.size() / 64);
  for (std::size_t i = 0; i < m.triangles.size() && tries.size() < 80; i += stride) {
    const auto& t = m.triangles[(i * 7919) % m.triangles.size()];
    const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3<double> n = cross(b - a, c - a);
    const double len = std::sqrt(dot(n, n));
    if (!(len > 0)) continue;
    const double size = std::sqrt(len);  // about the triangle's edge length
    tries.push_back(to_float((a + b + c) / 3.0 + (side * 0.05 * size / len) * n));
  }
  for (const auto& p : tries) {
    if (int(out.size()) == count) break;
    if (std::find(out.begin(), out.end(), p) == out.end() && inside(p)) out.push_back(p);
  }
  return out;
}

MeshCheck check_mesh(const Method& kernel, const MeshUnderTest& mt, const MeshCheckOptions& opt) {
  MeshCheck res;
  res.mesh = mt.name;
  res.triangles = mt.mesh.triangles.size();
  // The finder sees what the kernel sees: for a float kernel, the mesh and the rays rounded to float
  // (shared vertices round alike, so the mesh stays closed), so that every candidate is a triangle
  // the kernel's own ray touches.
  const bool f32 = kernel.precision == Precision::float32;
  scene::Scene s;
  scene::add_mesh(s, mt.mesh);
  if (f32)
    for (auto& v : s.mesh.vertices) v = to_float(v);
  const scene::Accel accel(s);
  const auto targets = scene::leak_targets(s.mesh, opt.max_targets);

  std::vector<Ray<double>> rays;
  for (const auto& p : mt.interior)
    for (const auto& t : targets) {
      const Ray<double> exact{p, t - p};
      rays.push_back(f32 ? Ray<double>{to_float(exact.o), to_float(exact.d)} : exact);
      rays.push_back({p, normalize(t.cast<float>() - p.cast<float>()).cast<double>()});
    }
  res.rays = rays.size();

  // Rays in chunks: the finder's candidates, then the kernel's answers on all of them at once.
  const std::size_t chunk = 4096;
  for (std::size_t r0 = 0; r0 < rays.size(); r0 += chunk) {
    const std::size_t r1 = std::min(rays.size(), r0 + chunk);
    std::vector<RayWork> work;
    std::vector<io::Case> cases;
    for (std::size_t i = r0; i < r1; ++i) {
      RayWork w{rays[i], accel.all(rays[i], opt.finder), cases.size(), {}};
      std::erase_if(w.hits, [](const scene::PrimHit& h) { return !(h.t >= 0); });
      if (!w.hits.empty()) {
        // Candidates: every triangle in a leaf the conservative traversal reaches on the way to just
        // past the first exact crossing (boxes are tested conservatively, so none the ray touches
        // there is left out).
        const double tmax = w.hits.front().t * (1 + 0x1p-10) + 0x1p-60;
        accel.traverse_slots(rays[i], 0.0, tmax, BvhTraversal::conservative, BvhQuery::all,
                            [&](std::uint32_t j) {
                              w.prims.push_back(accel.leaf_prims()[j].id);
                              return false;
                            });
        std::sort(w.prims.begin(), w.prims.end());
        w.prims.erase(std::unique(w.prims.begin(), w.prims.end()), w.prims.end());
      }
      for (const std::uint32_t prim : w.prims) {
        const io::Case c = triangle_case(rays[i], s, prim);
        cases.push_back(f32 ? io::round_to_float(c) : c);  // already floats but for a float ray's origin
      }
      work.push_back(std::move(w));
    }
    std::vector<io::CaseResult> answers(cases.size());
    for (std::size_t b = 0; b < cases.size(); b += std::max<std::size_t>(opt.batch, 1)) {
      const std::size_t e = std::min(cases.size(), b + std::max<std::size_t>(opt.batch, 1));
      kernel.classify_many(std::span<const io::Case>(cases).subspan(b, e - b),
                           std::span<io::CaseResult>(answers).subspan(b, e - b));
      if (kernel.take_failures)
        for (auto& f : kernel.take_failures()) res.failures.push_back(std::move(f));
    }
    res.candidate_cases += cases.size();
    for (const auto& w : work) {
      if (w.prims.empty()) {
        ++res.rays_without_candidates;
        continue;
      }
      bool hit = false, failed = false;
      for (std::size_t k = 0; k < w.prims.size(); ++k) {
        hit = hit || touches(answers[w.first + k]);
        failed = failed || answers[w.first + k].contact == Contact::error;
      }
      // A ray whose kernel failed on a candidate is the failure's finding (listed in `failures`), not a leak.
      if (hit || (failed && kernel.take_failures)) continue;
      ++res.leaks;
      if (res.reproducers.size() >= opt.keep) continue;
      // The reproducer: the candidates the ray touches at its first crossing (the finder's class),
      // the triangles it slipped between.
      MeshLeak leak{w.ray, {}, w.prims.size()};
      const double t0 = w.hits.front().t;
      for (std::size_t k = 0; k < w.prims.size(); ++k)
        for (const auto& h : w.hits)
          if (h.prim == w.prims[k] && h.t <= t0 * (1 + 0x1p-10) + 0x1p-60)
            leak.candidates.push_back({cases[w.first + k], answers[w.first + k], h.contact, h.t});
      res.reproducers.push_back(std::move(leak));
    }
  }
  return res;
}

MeshUnderTest generated_mesh(const MeshFuzzOptions& opt, std::size_t i) {
  MeshUnderTest mt;
  std::mt19937_64 rng;
  MeshShape shape;
  mt.mesh = fuzz_mesh(opt, i, shape, mt.interior, rng);
  mt.name = fmt::format("generated #{} ({})", i, shape == MeshShape::star ? "icosphere" : "hull");
  return mt;
}

}  // namespace rayproof::verify
