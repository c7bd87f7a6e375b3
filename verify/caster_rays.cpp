// The ray sets a whole caster is judged on (caster_rays, rayproof/verify/caster_check.h): leak rays
// through every vertex and edge of closed meshes, grazing and face rays, surface and random rays,
// extreme magnitudes and invalid rays; each set deduplicated and capped. The judging is in
// caster_check.cpp.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "rayproof/verify/caster_check.h"

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/triangle_common.h"

namespace rayproof::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct SetBuilder {
  CasterRays& out;
  std::size_t cap;
  void add(const std::string& name, std::vector<Ray<double>> rays) {
    // Each ray once (a vertex on several silhouette edges, an interior point met twice), first
    // occurrence kept, by bit pattern.
    std::set<std::array<std::uint64_t, 6>> seen;
    std::erase_if(rays, [&](const Ray<double>& r) {
      return !seen.insert({std::bit_cast<std::uint64_t>(r.o.x), std::bit_cast<std::uint64_t>(r.o.y),
                           std::bit_cast<std::uint64_t>(r.o.z), std::bit_cast<std::uint64_t>(r.d.x),
                           std::bit_cast<std::uint64_t>(r.d.y), std::bit_cast<std::uint64_t>(r.d.z)})
                  .second;
    });
    const auto id = static_cast<std::uint8_t>(out.names.size());
    out.names.push_back(name);
    const std::size_t n = rays.size();
    const std::size_t keep = std::min(n, cap);
    for (std::size_t k = 0; k < keep; ++k) {
      out.rays.push_back(rays[keep == n ? k : k * n / keep]);
      out.set.push_back(id);
    }
  }
};

bool wanted(const CasterCheckOptions& opt, const char* name) {
  return opt.sets.empty() || std::find(opt.sets.begin(), opt.sets.end(), name) != opt.sets.end();
}

Vec3<double> random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const Vec3<double> v{g(rng), g(rng), g(rng)};
    const double l = length(v);
    if (l > 1e-6) return v / l;
  }
}

}  // namespace

CasterRays caster_rays(const CasterMesh& mesh, const CasterCheckOptions& opt) {
  static const char* const kSets[] = {"leak", "graze", "face", "surface", "random", "extreme", "invalid"};
  for (const std::string& s : opt.sets)
    if (std::find_if(std::begin(kSets), std::end(kSets), [&](const char* k) { return s == k; }) == std::end(kSets))
      throw std::invalid_argument("unknown ray set '" + s + "' (leak, graze, face, surface, random, extreme, invalid)");
  CasterRays out;
  SetBuilder b{out, std::max<std::size_t>(opt.max_rays_per_set, 1)};
  std::mt19937_64 rng(opt.seed);
  const auto& V = mesh.vertices;
  const auto& F = mesh.triangles;
  for (const auto& f : F)
    for (auto i : f)
      if (i >= V.size()) throw MeshInputError(fmt::format("triangle index {} out of range ({} vertices)", i, V.size()));
  Vec3<double> lo{kInf, kInf, kInf}, hi = -lo;
  for (const auto& f : F)
    for (auto i : f)
      lo = {std::min(lo.x, V[i].x), std::min(lo.y, V[i].y), std::min(lo.z, V[i].z)},
      hi = {std::max(hi.x, V[i].x), std::max(hi.y, V[i].y), std::max(hi.z, V[i].z)};
  if (F.empty()) lo = {-1, -1, -1}, hi = {1, 1, 1};
  const Vec3<double> centre = 0.5 * (lo + hi);
  const double size = std::max(length(hi - lo), 1e-300);
  auto tri = [&](std::size_t k) { return Triangle<double>{V[F[k][0]], V[F[k][1]], V[F[k][2]]}; };

  // Edges with their triangles (for leaks and silhouettes).
  struct Edge {
    std::uint32_t a, b, t0, t1;
    int uses;
  };
  std::vector<Edge> edges;
  {
    std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> es;
    for (std::size_t k = 0; k < F.size(); ++k)
      for (int j = 0; j < 3; ++j) {
        std::uint32_t a = F[k][j], c = F[k][(j + 1) % 3];
        if (a > c) std::swap(a, c);
        es.emplace_back(a, c, static_cast<std::uint32_t>(k));
      }
    std::sort(es.begin(), es.end());
    for (std::size_t i = 0; i < es.size();) {
      std::size_t j = i;
      while (j < es.size() && std::get<0>(es[j]) == std::get<0>(es[i]) && std::get<1>(es[j]) == std::get<1>(es[i])) ++j;
      edges.push_back({std::get<0>(es[i]), std::get<1>(es[i]), std::get<2>(es[i]), std::get<2>(es[j - 1]),
                       static_cast<int>(j - i)});
      i = j;
    }
  }

  if (wanted(opt, "leak")) {
    std::vector<Ray<double>> rays;
    std::vector<Vec3<double>> inside;
    try {
      const ExactMesh closed(VertexArray(reinterpret_cast<const double*>(V.data()), V.size()),
                              IndexArray{F.empty() ? nullptr : F.data()->data(), F.size()});
      // Candidates: the box centre, then points just inside triangle centroids (both sides tried).
      std::vector<Vec3<double>> cands{centre};
      for (std::size_t k = 0; k < F.size() && cands.size() < 64; k += std::max<std::size_t>(1, F.size() / 32)) {
        const Triangle<double> t = tri(k);
        const Vec3<double> g = (t.p0 + t.p1 + t.p2) / 3.0, nn = cross(t.p1 - t.p0, t.p2 - t.p0);
        const double l = length(nn);
        if (!(l > 0)) continue;
        const double step = 1e-3 * size;
        cands.push_back(g - nn * (step / l));
        cands.push_back(g + nn * (step / l));
      }
      for (const auto& p : cands) {
        const Vec3<double> pf{double(float(p.x)), double(float(p.y)), double(float(p.z))};
        if (closed.contains(pf) == Side::inside) inside.push_back(pf);
        if (inside.size() >= 2) break;
      }
      if (inside.empty()) out.notes.push_back("leak: no interior point found; no leak rays");
    } catch (const MeshNotClosedError& e) {
      out.notes.push_back(std::string("leak: the mesh is not closed (") + e.what() + "); no leak rays");
    }
    for (const auto& p : inside) {
      std::vector<bool> used(V.size(), false);
      for (const auto& f : F)
        for (auto i : f) used[i] = true;
      for (std::size_t i = 0; i < V.size(); ++i)
        if (used[i]) rays.push_back({p, V[i] - p});
      for (const Edge& e : edges) rays.push_back({p, 0.5 * (V[e.a] + V[e.b]) - p});
    }
    b.add("leak", std::move(rays));
  }
  if (wanted(opt, "graze")) {
    std::vector<Ray<double>> rays;
    for (int view = 0; view < 8 && !F.empty(); ++view) {
      const Vec3<double> dir = random_unit(rng);
      for (const Edge& e : edges) {
        const Triangle<double> t0 = tri(e.t0), t1 = tri(e.t1);
        const double s0 = dot(cross(t0.p1 - t0.p0, t0.p2 - t0.p0), dir), s1 = dot(cross(t1.p1 - t1.p0, t1.p2 - t1.p0), dir);
        if (e.uses == 2 && (s0 > 0) == (s1 > 0)) continue;  // not a silhouette edge for this view
        const Vec3<double> m = 0.5 * (V[e.a] + V[e.b]);
        rays.push_back({m - dir * size, dir});
        rays.push_back({V[e.a] - dir * size, dir});
      }
    }
    b.add("graze", std::move(rays));
  }
  if (wanted(opt, "face")) {
    std::vector<Ray<double>> rays;
    for (std::size_t k = 0; k < F.size(); ++k) {
      const Triangle<double> t = tri(k);
      rays.push_back({t.p0 - (t.p1 - t.p0), t.p1 - t.p0});          // along an edge's line, from outside
      rays.push_back({t.p0 - (t.p2 - t.p1) * 0.5, t.p2 - t.p1});     // in the plane, across the triangle
      rays.push_back({(t.p0 + t.p1 + t.p2) / 3.0, t.p1 - t.p2});     // in the plane, from inside it
    }
    b.add("face", std::move(rays));
  }
  if (wanted(opt, "surface")) {
    std::vector<Ray<double>> rays;
    for (std::size_t k = 0; k < F.size(); ++k) {
      const Triangle<double> t = tri(k);
      const Vec3<double> nn = cross(t.p1 - t.p0, t.p2 - t.p0);
      const Vec3<double> r = random_unit(rng);
      const Vec3<double> out_dir = dot(r, nn) > 0 ? r : -r;
      rays.push_back({(t.p0 + t.p1 + t.p2) / 3.0, out_dir});
      rays.push_back({(t.p0 + t.p1 + t.p2) / 3.0, -out_dir});
      rays.push_back({t.p0, out_dir});
    }
    b.add("surface", std::move(rays));
  }
  if (wanted(opt, "random")) {
    std::vector<Ray<double>> rays;
    std::uniform_real_distribution<double> u(-1, 1);
    for (std::size_t k = 0; k < opt.random_rays; ++k) {
      const Vec3<double> o = centre + Vec3<double>{u(rng), u(rng), u(rng)} * size;
      // Half towards a random triangle point (they hit often), half in a random direction.
      Vec3<double> d = random_unit(rng);
      if (k % 2 == 0 && !F.empty()) {
        const Triangle<double> t = tri(rng() % F.size());
        std::uniform_real_distribution<double> w(0, 1);
        double a = w(rng), c = w(rng);
        if (a + c > 1) a = 1 - a, c = 1 - c;
        d = t.p0 + a * (t.p1 - t.p0) + c * (t.p2 - t.p0) - o;
      }
      rays.push_back({o, d});
    }
    b.add("random", std::move(rays));
  }
  if (wanted(opt, "extreme")) {
    std::vector<Ray<double>> rays;
    for (int k = 0; k < 64; ++k) {
      const Vec3<double> dir = random_unit(rng);
      const Vec3<double> target = F.empty() ? centre : (V[F[rng() % F.size()][k % 3]] + centre) * 0.5;
      for (double far : {1e8, 1e15, 1e30}) rays.push_back({target - dir * (far * size), dir});
      for (double scale : {1e-30, 1e-300, 1e30, 1e300}) rays.push_back({centre - dir * size, dir * scale});
      rays.push_back({target, Vec3<double>{dir.x, dir.y * 1e-300, dir.z}});
    }
    b.add("extreme", std::move(rays));
  }
  if (wanted(opt, "invalid")) {
    const double nan = kNaN<double>;
    std::vector<Ray<double>> rays{
        {centre, {0, 0, 0}},          {{nan, 0, 0}, {1, 0, 0}},   {centre, {nan, 1, 0}}, {centre, {kInf, 0, 0}},
        {{kInf, 0, 0}, {-1, 0, 0}},   {{nan, nan, nan}, {nan, nan, nan}}, {centre - Vec3<double>{size, 0, 0}, {-0.0, 0, -0.0}},
        {centre, {0, -kInf, 0}}};
    b.add("invalid", std::move(rays));
  }
  // A float caster gets float rays (what it would be given in its own precision), judged as given.
  if (opt.precision == CasterPrecision::float32)
    for (Ray<double>& r : out.rays) r = {r.o.cast<float>().cast<double>(), r.d.cast<float>().cast<double>()};
  return out;
}

}  // namespace rayproof::verify
