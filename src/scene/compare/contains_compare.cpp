// CGAL Side_of_triangle_mesh (Epick, Epeck) and Embree one-ray parity along (1, 1, 1).
#if RAYPROOF_CGAL_PEERS
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#endif

#include <array>
#include <limits>
#include <memory>

#include "scene/compare/competitors.h"
#include "scene/compare/contains_compare.h"

#ifdef RAYPROOF_HAVE_EMBREE
#include "scene/compare/embree_mesh.h"
#endif

namespace rayproof::scene::compare {

namespace {


#if RAYPROOF_CGAL_PEERS
template <class K>
ContainsCompetitor make_cgal_side_of(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t,
                             const char* name) {
  using Mesh = CGAL::Surface_mesh<typename K::Point_3>;
  struct Held {
    Mesh mesh;
    std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, K>> side;
  };
  auto h = std::make_shared<Held>();
  std::vector<typename Mesh::Vertex_index> vi;
  vi.reserve(v.size());
  for (const auto& p : v) vi.push_back(h->mesh.add_vertex(typename K::Point_3(p.x, p.y, p.z)));
  std::size_t failed = 0;
  for (const auto& f : t)
    if (h->mesh.add_face(vi[f[0]], vi[f[1]], vi[f[2]]) == Mesh::null_face()) ++failed;
  ContainsCompetitor c{name, "", nullptr};
  if (failed) {
    c.note = std::to_string(failed) + " triangles not accepted by CGAL::Surface_mesh (not a manifold)";
    return c;
  }
  h->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, K>>(h->mesh);
  c.run = [h](std::span<const Vec3<double>> pts, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const CGAL::Bounded_side b = (*h->side)(typename K::Point_3(pts[i].x, pts[i].y, pts[i].z));
      out[i] = b == CGAL::ON_BOUNDED_SIDE ? 1 : (b == CGAL::ON_BOUNDARY ? 2 : 0);
    }
  };
  return c;
}
#endif

#ifdef RAYPROOF_HAVE_EMBREE
/// The intersect context with the hits counted: distinct (geometry, primitive) pairs of one ray.
struct CountContext {
  RTCIntersectContext base;
  unsigned count = 0;
  unsigned seen[64];
};

void count_hits(const RTCFilterFunctionNArguments* args) {
  auto* ctx = reinterpret_cast<CountContext*>(args->context);
  if (args->valid[0] == 0) return;
  const unsigned prim = RTCHitN_primID(args->hit, args->N, 0);
  for (unsigned k = 0; k < ctx->count && k < 64; ++k)
    if (ctx->seen[k] == prim) {
      args->valid[0] = 0;
      return;
    }
  if (ctx->count < 64) ctx->seen[ctx->count] = prim;
  ++ctx->count;
  args->valid[0] = 0;  // reject: the traversal goes on to every other hit
}

ContainsCompetitor make_embree_parity(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t) {
  auto e = make_embree_mesh(v, t, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  ContainsCompetitor c{"embree-parity", "", nullptr};
  c.run = [e](std::span<const Vec3<double>> pts, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      CountContext ctx;
      rtcInitIntersectContext(&ctx.base);
      ctx.base.filter = count_hits;
      RTCRayHit rh{};
      rh.ray.org_x = float(pts[i].x), rh.ray.org_y = float(pts[i].y), rh.ray.org_z = float(pts[i].z);
      rh.ray.dir_x = rh.ray.dir_y = rh.ray.dir_z = 1.0f;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(e->scene, &ctx.base, &rh);
      out[i] = ctx.count & 1;
    }
  };
  return c;
}
#endif

}  // namespace

std::vector<ContainsCompetitor> make_contains_competitors(const std::vector<Vec3<double>>& vertices,
                                                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                          const std::string& names) {
  std::vector<ContainsCompetitor> out;
#if RAYPROOF_CGAL_PEERS
  if (named_in(names, "cgal-epick")) out.push_back(make_cgal_side_of<CGAL::Epick>(vertices, triangles, "cgal-epick"));
  if (named_in(names, "cgal-epeck")) out.push_back(make_cgal_side_of<CGAL::Epeck>(vertices, triangles, "cgal-epeck"));
#else
  if (named_in(names, "cgal-epick")) out.push_back({"cgal-epick", kCgalPeersNotBuilt, nullptr});
  if (named_in(names, "cgal-epeck")) out.push_back({"cgal-epeck", kCgalPeersNotBuilt, nullptr});
#endif
  if (named_in(names, "embree-parity")) {
#ifdef RAYPROOF_HAVE_EMBREE
    out.push_back(make_embree_parity(vertices, triangles));
#else
    out.push_back({"embree-parity", "not built with Embree 3", nullptr});
#endif
  }
  return out;
}

}  // namespace rayproof::scene::compare
