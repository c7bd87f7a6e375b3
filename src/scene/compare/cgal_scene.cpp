// CGAL AABB_tree competitors: first_intersection with Epick (filtered predicates, inexact
// constructions) and Epeck (exact constructions; not thread-safe, so one thread).
// Built without RAYPROOF_CGAL_PEERS (the README's first command), only the names and Embree's.
#if RAYPROOF_CGAL_PEERS
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "scene/compare/competitors.h"

namespace rayproof::scene::compare {

#ifdef RAYPROOF_HAVE_EMBREE
Competitor make_embree(const Scene& s, bool robust, int build_threads, const std::string& max_isa);
#endif

#if RAYPROOF_CGAL_PEERS
namespace {

template <class K>
struct CgalTree {
  using Tri = typename K::Triangle_3;
  using Iterator = typename std::vector<Tri>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  std::vector<Tri> tris;
  Tree tree;
};

template <class K>
Competitor make_cgal(const Scene& s, const char* name, bool threaded, std::size_t max_rays) {
  const auto start = std::chrono::steady_clock::now();
  auto t = std::make_shared<CgalTree<K>>();
  using P = typename K::Point_3;
  auto pt = [](const Vec3<double>& v) { return P(v.x, v.y, v.z); };
  t->tris.reserve(s.mesh.triangles.size());
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i) {
    const auto tri = s.triangle(std::uint32_t(i));
    t->tris.emplace_back(pt(tri.p0), pt(tri.p1), pt(tri.p2));
  }
  // Degenerate triangles make CGAL's ray/triangle test assert: drop them (counted as not hit).
  t->tris.erase(std::remove_if(t->tris.begin(), t->tris.end(), [](const auto& x) { return x.is_degenerate(); }),
                t->tris.end());
  t->tree.rebuild(t->tris.cbegin(), t->tris.cend());
  t->tree.build();
  Competitor c;
  c.name = name;
  c.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.threaded = threaded;
  c.max_rays = max_rays;
  c.closest = [t, threaded, pt](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
    auto body = [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const typename K::Ray_3 ray(pt(rays[i].o), typename K::Vector_3(rays[i].d.x, rays[i].d.y, rays[i].d.z));
        out[i] = t->tree.first_intersection(ray) ? 1 : 0;
      }
    };
    if (!threaded) return body(0, rays.size());
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256),
                        [&](const auto& r) { body(r.begin(), r.end()); });
    });
  };
  c.any = [t, threaded, pt](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
    auto body = [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const typename K::Ray_3 ray(pt(rays[i].o), typename K::Vector_3(rays[i].d.x, rays[i].d.y, rays[i].d.z));
        out[i] = t->tree.do_intersect(ray) ? 1 : 0;
      }
    };
    if (!threaded) return body(0, rays.size());
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256),
                        [&](const auto& r) { body(r.begin(), r.end()); });
    });
  };
  return c;
}

}  // namespace
#endif

bool cgal_peers_built() { return RAYPROOF_CGAL_PEERS != 0; }

const std::vector<std::string>& competitor_names() {
  static const std::vector<std::string> names{"embree",     "embree-robust", "embree-avx2", "embree-robust-avx2",
                                              "cgal-epick", "cgal-epeck"};
  return names;
}

void check_competitor_names(const std::string& names) {
  for (std::size_t p = 0; p <= names.size();) {
    const std::size_t q = std::min(names.find(',', p), names.size());
    const std::string name = names.substr(p, q - p);
    p = q + 1;
    if (name.empty() || name == "none") continue;
    const auto& known = competitor_names();
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    // A misspelt name used to run nothing for it, silently: a bench without the row it was asked for.
    std::string msg = "unknown competitor '" + name + "': expected a comma-separated list of";
    for (const auto& k : known) msg += " " + k + ",";
    throw std::invalid_argument(msg + " or none");
  }
}

std::vector<Competitor> make_competitors(const Scene& s, const std::string& names, int build_threads) {
  check_competitor_names(names);
  const auto want = [&](const char* name) { return ("," + names + ",").find(std::string(",") + name + ",") != std::string::npos; };
  std::vector<Competitor> out;
#ifdef RAYPROOF_HAVE_EMBREE
  if (want("embree")) out.push_back(make_embree(s, false, build_threads, ""));
  if (want("embree-robust")) out.push_back(make_embree(s, true, build_threads, ""));
  // The same scenes on a device capped at AVX2: where the CPU has AVX-512, how much of Embree's
  // rate comes from the wider kernels its default device picks.
  if (want("embree-avx2")) out.push_back(make_embree(s, false, build_threads, "avx2"));
  if (want("embree-robust-avx2")) out.push_back(make_embree(s, true, build_threads, "avx2"));
#endif
#if RAYPROOF_CGAL_PEERS
  if (want("cgal-epick")) out.push_back(make_cgal<CGAL::Epick>(s, "cgal-epick", true, 0));
  if (want("cgal-epeck")) out.push_back(make_cgal<CGAL::Epeck>(s, "cgal-epeck", false, 2000));
#endif
  return out;
}

}  // namespace rayproof::scene::compare
