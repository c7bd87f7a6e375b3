// CGAL AABB_tree closest point (Epick) and Embree rtcPointQuery closest point.
#if RAYPROOF_CGAL_PEERS
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "scene/compare/competitors.h"
#include "scene/compare/distance_compare.h"

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>

#include "scene/compare/embree_mesh.h"
#endif

namespace rayproof::scene::compare {

namespace {


#if RAYPROOF_CGAL_PEERS
DistanceCompetitor make_cgal_aabb_distance(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t) {
  using K = CGAL::Epick;
  using Tri = K::Triangle_3;
  using Iter = std::vector<Tri>::const_iterator;
  using Prim = CGAL::AABB_triangle_primitive<K, Iter>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>>;
  struct Held {
    std::vector<Tri> tris;
    std::unique_ptr<Tree> tree;
  };
  auto h = std::make_shared<Held>();
  h->tris.reserve(t.size());
  auto pt = [&](std::uint32_t i) { return K::Point_3(v[i].x, v[i].y, v[i].z); };
  for (const auto& f : t) h->tris.emplace_back(pt(f[0]), pt(f[1]), pt(f[2]));
  h->tree = std::make_unique<Tree>(h->tris.cbegin(), h->tris.cend());
  h->tree->accelerate_distance_queries();
  DistanceCompetitor c{"cgal-epick", "", nullptr};
  c.run = [h](std::span<const Vec3<double>> pts, std::span<std::uint32_t> tri, std::span<double> dist) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const K::Point_3 p(pts[i].x, pts[i].y, pts[i].z);
      const auto pp = h->tree->closest_point_and_primitive(p);
      tri[i] = std::uint32_t(pp.second - h->tris.cbegin());
      dist[i] = std::sqrt(CGAL::squared_distance(p, pp.first));
    }
  };
  return c;
}
#endif

#ifdef RAYPROOF_HAVE_EMBREE
/// The closest point of a triangle in double (the Voronoi regions, as Embree's tutorial).
Vec3<double> closest_on_triangle(const Vec3<double>& p, const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c) {
  const Vec3<double> ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3<double> bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Vec3<double> cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double den = 1 / (va + vb + vc);
  return a + ab * (vb * den) + ac * (vc * den);
}

/// The Embree scene with the double mesh the callback measures against.
struct EmbreeHeld {
  std::shared_ptr<EmbreeMesh> mesh;
  std::vector<Vec3<double>> v;
  std::vector<std::array<std::uint32_t, 3>> t;
};

struct QueryResult {
  const EmbreeHeld* held;
  Vec3<double> p;
  double d2 = std::numeric_limits<double>::infinity();
  std::uint32_t prim = 0xffffffffu;
};

bool point_query_callback(RTCPointQueryFunctionArguments* args) {
  auto* r = static_cast<QueryResult*>(args->userPtr);
  const auto& f = r->held->t[args->primID];
  const Vec3<double>& a = r->held->v[f[0]];
  const Vec3<double>& b = r->held->v[f[1]];
  const Vec3<double>& c = r->held->v[f[2]];
  const Vec3<double> q = closest_on_triangle(r->p, a, b, c);
  const double d2 = length_squared(r->p - q);
  if (d2 < r->d2 || (d2 == r->d2 && args->primID < r->prim)) {
    r->d2 = d2, r->prim = args->primID;
    args->query->radius = float(std::sqrt(d2));  // the tutorial's shrink; float rounds to nearest
    return true;
  }
  return false;
}

DistanceCompetitor make_embree_point_query(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t) {
  auto e = std::make_shared<EmbreeHeld>();
  e->v = v, e->t = t;
  e->mesh = make_embree_mesh(v, t, RTC_SCENE_FLAG_NONE, point_query_callback);
  DistanceCompetitor c{"embree", "", nullptr};
  c.run = [e](std::span<const Vec3<double>> pts, std::span<std::uint32_t> tri, std::span<double> dist) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      RTCPointQuery q;
      q.x = float(pts[i].x), q.y = float(pts[i].y), q.z = float(pts[i].z);
      q.radius = std::numeric_limits<float>::infinity();
      q.time = 0.f;
      QueryResult r{e.get(), pts[i]};
      RTCPointQueryContext ctx;
      rtcInitPointQueryContext(&ctx);
      rtcPointQuery(e->mesh->scene, &q, &ctx, nullptr, &r);
      tri[i] = r.prim;
      dist[i] = std::sqrt(r.d2);
    }
  };
  return c;
}
#endif

}  // namespace

std::vector<DistanceCompetitor> make_distance_competitors(const std::vector<Vec3<double>>& vertices,
                                                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                          const std::string& names) {
  std::vector<DistanceCompetitor> out;
  if (named_in(names, "cgal-epick")) {
#if RAYPROOF_CGAL_PEERS
    out.push_back(make_cgal_aabb_distance(vertices, triangles));
#else
    out.push_back({"cgal-epick", kCgalPeersNotBuilt, nullptr});
#endif
  }
  if (named_in(names, "embree")) {
#ifdef RAYPROOF_HAVE_EMBREE
    out.push_back(make_embree_point_query(vertices, triangles));
#else
    out.push_back({"embree", "not built with Embree 3", nullptr});
#endif
  }
  return out;
}

}  // namespace rayproof::scene::compare
