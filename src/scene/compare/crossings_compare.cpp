// Embree 3 all hits through a context filter function that records and rejects every hit.
#include "scene/compare/crossings_compare.h"

#include <algorithm>
#include <limits>
#include <memory>

#ifdef RAYPROOF_HAVE_EMBREE
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "scene/compare/embree_mesh.h"
#endif

namespace rayproof::scene::compare {

#ifdef RAYPROOF_HAVE_EMBREE
namespace {

/// The context with the ray's hit list (the base first: Embree hands the filter its address).
struct CollectContext {
  RTCIntersectContext base;
  std::vector<EmbreeHit>* hits;
};

void collect(const RTCFilterFunctionNArguments* args) {
  if (args->valid[0] == 0) return;
  auto* ctx = reinterpret_cast<CollectContext*>(args->context);
  ctx->hits->push_back({RTCRayN_tfar(args->ray, args->N, 0), RTCHitN_primID(args->hit, args->N, 0)});
  args->valid[0] = 0;  // reject: the traversal goes on to every other hit
}

}  // namespace

AllHitsCompetitor make_embree_all_hits(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t) {
  auto e = make_embree_mesh(v, t, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  AllHitsCompetitor c;
  c.run = [e](std::span<const Ray<double>> rays, std::vector<std::vector<EmbreeHit>>& hits, int threads) {
    hits.resize(rays.size());
    auto body = [&](std::size_t b, std::size_t end) {
      for (std::size_t i = b; i < end; ++i) {
        hits[i].clear();
        CollectContext ctx;
        rtcInitIntersectContext(&ctx.base);
        ctx.base.filter = collect;
        ctx.hits = &hits[i];
        RTCRayHit rh{};
        const Ray<double>& r = rays[i];
        rh.ray.org_x = float(r.o.x), rh.ray.org_y = float(r.o.y), rh.ray.org_z = float(r.o.z);
        rh.ray.dir_x = float(r.d.x), rh.ray.dir_y = float(r.d.y), rh.ray.dir_z = float(r.d.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e->scene, &ctx.base, &rh);
        std::sort(hits[i].begin(), hits[i].end(),
                  [](const EmbreeHit& a, const EmbreeHit& b) { return a.t != b.t ? a.t < b.t : a.prim < b.prim; });
      }
    };
    if (threads == 1) return body(0, rays.size());
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 64),
                        [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
    });
  };
  return c;
}

#else

AllHitsCompetitor make_embree_all_hits(const std::vector<Vec3<double>>&, const std::vector<std::array<std::uint32_t, 3>>&) {
  AllHitsCompetitor c;
  c.note = "not built with Embree 3";
  return c;
}

#endif

}  // namespace rayproof::scene::compare
