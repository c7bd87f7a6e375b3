// The measuring half of `rayproof bench crossings` (crossings_bench.h).
#include "scene/compare/crossings_bench.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "rayproof/float_util.h"
#include "scene/crossings_speedups.h"
#include "scene/watertight.h"

namespace rayproof::scene::compare {

double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void tally_ray(const RayCrossings& r, const std::vector<EmbreeHit>& hits, double tol, CrossingsTally& t) {
  struct Event {
    double t;
    bool crossing;
    int seen = 0;
  };
  std::vector<Event> ev;
  for (const Crossing& c : r.crossings) ev.push_back({c.t, true});
  for (const Touch& h : r.touches)
    if (h.contact != Contact::coplanar) ev.push_back({h.t, false});
  std::sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) { return a.t < b.t; });
  t.crossings += r.crossings.size();
  t.touches += ev.size() - r.crossings.size();
  t.hits += hits.size();
  std::size_t right = 0;
  for (const auto& h : hits) {
    Event* best = nullptr;
    for (auto& e : ev)
      if (std::fabs(e.t - double(h.t)) <= tol && (!best || std::fabs(e.t - double(h.t)) < std::fabs(best->t - double(h.t)))) best = &e;
    if (!best) {
      ++t.unmatched;
    } else if (!best->crossing) {
      ++t.at_touches;
    } else if (best->seen++ == 0) {
      ++right;
    } else {
      ++t.duplicates;
    }
  }
  t.right += right;
  t.missed += r.crossings.size() - right;
  t.rays_exact += right == r.crossings.size() && hits.size() == right;
}

CrossingRaySets crossing_ray_sets(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng) {
  auto to_float = [](double x) { return double(static_cast<float>(x)); };
  const mesh::VertexBounds b = mesh::vertex_bounds(m, true);
  const Vec3<double> lo = b.lo, hi = b.hi, ext = b.extent();
  CrossingRaySets s;
  s.size = std::max({ext.x, ext.y, ext.z});
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  s.random.resize(n), s.vertex.resize(n);
  for (auto& r : s.random) {
    r.o = {to_float(lo.x - 0.1 * ext.x + 1.2 * ext.x * u(rng)), to_float(lo.y - 0.1 * ext.y + 1.2 * ext.y * u(rng)),
           to_float(lo.z - 0.1 * ext.z + 1.2 * ext.z * u(rng))};
    r.d = {to_float(g(rng)), to_float(g(rng)), to_float(g(rng))};
    if (r.d.x == 0 && r.d.y == 0 && r.d.z == 0) r.d = {1, 0, 0};
  }
  std::vector<std::uint32_t> used;
  for (const auto& t : m.triangles) used.insert(used.end(), t.begin(), t.end());
  // An axis ray along +-e_k through p: the origin p with coordinate k moved a quarter of the size
  // outside the box (rounded to float: p_k stays on the line).
  auto axis_ray = [&](const Vec3<double>& p, int k) {
    const double sgn = (rng() & 1) ? 1.0 : -1.0;
    Ray<double> r{p, {0, 0, 0}};
    (&r.o.x)[k] = to_float(sgn > 0 ? (&lo.x)[k] - 0.25 * s.size : (&hi.x)[k] + 0.25 * s.size);
    (&r.d.x)[k] = sgn;
    return r;
  };
  for (auto& r : s.vertex) r = axis_ray(m.vertices[used[rng() % used.size()]], int(rng() % 3));
  s.edge.reserve(n);
  for (std::size_t tries = 0; s.edge.size() < n && tries < 8 * n; ++tries) {
    const auto& t = m.triangles[rng() % m.triangles.size()];
    const int e = int(rng() % 3);
    const Vec3<double>&a = m.vertices[t[e]], &b = m.vertices[t[(e + 1) % 3]];
    const Vec3<double> mid{(a.x + b.x) * 0.5, (a.y + b.y) * 0.5, (a.z + b.z) * 0.5};
    // Exact: the sums lost nothing (and halving a double above the subnormals is exact).
    if (two_sum(a.x, b.x).lo != 0 || two_sum(a.y, b.y).lo != 0 || two_sum(a.z, b.z).lo != 0) continue;
    int k = int(rng() % 3);
    const Vec3<double> ab = b - a;
    if ((&ab.x)[(k + 1) % 3] == 0 && (&ab.x)[(k + 2) % 3] == 0) continue;  // along the edge: no point contact
    s.edge.push_back(axis_ray(mid, k));
  }
  return s;
}

mesh::Mesh crossings_mesh(const std::string& path) {
  return path == "generated" ? bumpy_sphere(std::size_t(1) << 20) : mesh::read_mesh(path);
}

CrossingsRun time_crossings(const ExactMesh& cm, const AllHitsCompetitor& embree, const std::vector<Ray<double>>& rays,
                            double size, int repeat, int threads, bool ablation) {
  CrossingsRun run;
  std::vector<RayCrossings> ours(rays.size()), scratch;
  std::vector<std::vector<EmbreeHit>> theirs;
  auto now = [threads] {
    return threads == 1 ? thread_seconds()
                        : std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  };
  auto rate = [&](auto&& f) {
    const double t0 = now();
    f();
    return double(rays.size()) / (now() - t0) * 1e-6;
  };
  std::vector<std::pair<std::string, rayproof::scene::detail::CrossingsSpeedups>> off;
  if (ablation) {
    off.push_back({"without float traversal", {false, true, false}});
    off.push_back({"without lane misses", {true, false, false}});
    off.push_back({"with fan once", {true, true, true}});
    scratch.resize(rays.size());
    for (const auto& o : off) run.variants.push_back({o.first, {}, 0});
  }
  auto same = [](const RayCrossings& a, const RayCrossings& b) {
    if (a.valid != b.valid || a.crossings.size() != b.crossings.size() || a.touches.size() != b.touches.size()) return false;
    for (std::size_t i = 0; i < a.crossings.size(); ++i)
      if (a.crossings[i].t != b.crossings[i].t || a.crossings[i].triangle != b.crossings[i].triangle ||
          a.crossings[i].direction != b.crossings[i].direction)
        return false;
    for (std::size_t i = 0; i < a.touches.size(); ++i)
      if (a.touches[i].t != b.touches[i].t || a.touches[i].t2 != b.touches[i].t2 || a.touches[i].triangle != b.touches[i].triangle ||
          a.touches[i].contact != b.touches[i].contact)
        return false;
    return true;
  };
  for (int rep = 0; rep < repeat; ++rep) {
    // rayproof's variants in an order rotated each repeat (the first after Embree's run finds its
    // data evicted from the caches: measured up to 10% slower in that place).
    for (std::size_t k = 0; k <= off.size(); ++k) {
      const std::size_t v = (k + std::size_t(rep)) % (off.size() + 1);
      if (v == 0) {
        run.ours.push_back(rate([&] { cm.ray_crossings(rays, ours, {}, threads); }));
        continue;
      }
      rayproof::scene::detail::set_crossings_speedups(off[v - 1].second);
      run.variants[v - 1].ours.push_back(rate([&] { cm.ray_crossings(rays, scratch, {}, threads); }));
      rayproof::scene::detail::set_crossings_speedups({});
      if (rep == 0) {  // (the default's answers are in `ours` from repeat 0 on: it runs first there)
        std::size_t& differ = run.variants[v - 1].differing_rays;
        for (std::size_t i = 0; i < rays.size(); ++i) differ += !same(ours[i], scratch[i]);
      }
    }
    if (embree.run) run.embree.push_back(rate([&] { embree.run(rays, theirs, threads); }));
  }
  CrossingsTally& t = run.tally;
  if (embree.run)
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Ray<double>& r = rays[i];
      const double len = std::sqrt(r.d.x * r.d.x + r.d.y * r.d.y + r.d.z * r.d.z);
      tally_ray(ours[i], theirs[i], 1e-5 * size / len, t);
    }
  else
    for (const auto& r : ours) {
      t.crossings += r.crossings.size();
      for (const Touch& h : r.touches) t.touches += h.contact != Contact::coplanar;
    }
  return run;
}

}  // namespace rayproof::scene::compare
