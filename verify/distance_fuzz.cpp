// fuzz --distance (verify/distance_fuzz.h).
#include "verify/distance_fuzz.h"

#include <fmt/core.h>

#include <array>
#include <chrono>
#include <cmath>
#include <random>

#include "rayproof/scene/distance.h"

namespace rayproof::verify {

namespace {

using Tri = std::array<std::uint32_t, 3>;

std::string off_text(const std::vector<Vec3<double>>& v, const std::vector<Tri>& t) {
  std::string s = fmt::format("OFF\n{} {} 0\n", v.size(), t.size());
  for (const auto& p : v) s += fmt::format("{:a} {:a} {:a}\n", p.x, p.y, p.z);
  for (const auto& f : t) s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  return s;
}

}  // namespace

DistanceFuzzResult run_distance_fuzz(const DistanceFuzzOptions& opt) {
  DistanceFuzzResult res;
  std::mt19937_64 rng(opt.seed);
  const auto t0 = std::chrono::steady_clock::now();
  const double scales[] = {1, 1, 1, 1, 0x1p600, 0x1p-600, 0x1p300, 0x1p-300, 0x1p900, 0x1p-1000};
  for (;;) {
    if (opt.max_meshes && res.meshes >= opt.max_meshes) break;
    if (!opt.max_meshes && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= opt.seconds) break;
    ++res.meshes;
    const int kind = int(rng() % 3);
    const double scale = scales[rng() % std::size(scales)];
    std::vector<Vec3<double>> v;
    std::vector<Tri> t;
    const int nv = 4 + int(rng() % 12), nt = 2 + int(rng() % 20);
    std::uniform_int_distribution<int> gi(-3, 3);
    std::uniform_real_distribution<double> gr(-3, 3);
    for (int i = 0; i < nv; ++i) {
      Vec3<double> p = kind == 1 ? Vec3<double>{gr(rng), gr(rng), gr(rng)} : Vec3<double>{double(gi(rng)), double(gi(rng)), double(gi(rng))};
      if (kind == 2) p = {p.x + gr(rng) * 0x1p-30, p.y, p.z + (rng() % 4 == 0 ? gr(rng) * 0x1p-45 : 0.0)};  // near-degenerate, near-tied
      v.push_back(p * scale);
    }
    for (int i = 0; i < nt; ++i) t.push_back({std::uint32_t(rng() % nv), std::uint32_t(rng() % nv), std::uint32_t(rng() % nv)});
    if (rng() % 3 == 0) t.push_back(t.front());  // a duplicate: an exact tie between two indices
    const ExactMesh m(VertexArray(&v[0].x, v.size()), IndexArray{t.front().data(), t.size()});
    auto tri = [&](std::size_t i) { return std::array<Vec3<double>, 3>{v[t[i][0]], v[t[i][1]], v[t[i][2]]}; };
    for (int k = 0; k < 24; ++k) {
      Vec3<double> p;
      const auto& f = t[rng() % t.size()];
      switch (k % 6) {
        case 0: p = v[rng() % v.size()]; break;                                       // a vertex
        case 1: p = (v[f[0]] + v[f[1]]) * 0.5; break;                                 // an edge midpoint
        case 2: p = v[f[0]] * 0.25 + v[f[1]] * 0.25 + v[f[2]] * 0.5; break;           // a face point
        case 3: p = Vec3<double>{gr(rng), gr(rng), gr(rng)} * (1.5 * scale); break;   // around
        case 4: p = v[rng() % v.size()] + Vec3<double>{gr(rng), gr(rng), gr(rng)} * (0x1p-40 * scale); break;  // near a vertex
        default: p = Vec3<double>{gr(rng), gr(rng), gr(rng)} * (0x1p40 * (scale > 1 ? 1.0 : scale)); break;  // far
      }
      ++res.points;
      std::size_t best = 0;
      for (std::size_t i = 1; i < t.size(); ++i)
        if (compare_triangle_distances(p, tri(i), tri(best)) < 0) best = i;
      const double want = exact_triangle_distance(p, tri(best));
      const ClosestPoint r = m.closest_point(p);
      std::string what;
      if (r.triangle != best) ++res.wrong_triangle, what = fmt::format("triangle {}, expected {} (the lowest nearest)", r.triangle, best);
      else if (!(r.distance == want)) ++res.wrong_distance, what = fmt::format("distance {:a}, expected {:a}", r.distance, want);
      else if ((r.side == Side::surface) != (want == 0)) ++res.wrong_side, what = fmt::format("side {} at distance {:a}", to_string(r.side), want);
      if (!what.empty() && res.findings.size() < 5) res.findings.push_back({what, off_text(v, t), p});
    }
  }
  return res;
}

}  // namespace rayproof::verify
