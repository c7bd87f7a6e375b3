// The measuring half of `rayproof bench crossings` (crossings_bench.h).
#include "scene/compare/crossings_bench.h"

#include <time.h>

#include <algorithm>
#include <cmath>

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
  for (auto& r : s.vertex) {
    const Vec3<double>& v = m.vertices[used[rng() % used.size()]];
    const int k = int(rng() % 3);
    const double sgn = (rng() & 1) ? 1.0 : -1.0;
    r.o = v;
    double* oc = reinterpret_cast<double*>(&r.o);
    oc[k] = to_float(sgn > 0 ? (&lo.x)[k] - 0.25 * s.size : (&hi.x)[k] + 0.25 * s.size);
    r.d = {0, 0, 0};
    reinterpret_cast<double*>(&r.d)[k] = sgn;
  }
  return s;
}

CrossingsRun time_crossings(const ClosedMesh& cm, const AllHitsCompetitor& embree, const std::vector<Ray<double>>& rays,
                            double size, int repeat) {
  CrossingsRun run;
  std::vector<RayCrossings> ours(rays.size());
  std::vector<std::vector<EmbreeHit>> theirs;
  for (int rep = 0; rep < repeat; ++rep) {
    double t0 = thread_seconds();
    cm.ray_crossings(rays, ours, {}, 1);
    run.ours.push_back(double(rays.size()) / (thread_seconds() - t0) * 1e-6);
    if (embree.run) {
      t0 = thread_seconds();
      embree.run(rays, theirs);
      run.embree.push_back(double(rays.size()) / (thread_seconds() - t0) * 1e-6);
    }
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
