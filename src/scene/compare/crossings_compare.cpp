// Embree 3 all hits through a context filter function that records and rejects every hit.
#include "scene/compare/crossings_compare.h"

#include <algorithm>
#include <limits>
#include <memory>

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace rayproof::scene::compare {

#ifdef RAYPROOF_HAVE_EMBREE
namespace {

struct Held {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Held() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

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
  auto e = std::make_shared<Held>();
  e->device = rtcNewDevice("threads=1");
  e->scene = rtcNewScene(e->device);
  rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) vb[3 * i] = float(v[i].x), vb[3 * i + 1] = float(v[i].y), vb[3 * i + 2] = float(v[i].z);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), t.size()));
  for (std::size_t i = 0; i < t.size(); ++i) ib[3 * i] = t[i][0], ib[3 * i + 1] = t[i][1], ib[3 * i + 2] = t[i][2];
  rtcCommitGeometry(g);
  rtcAttachGeometry(e->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e->scene);
  AllHitsCompetitor c;
  c.run = [e](std::span<const Ray<double>> rays, std::vector<std::vector<EmbreeHit>>& hits) {
    hits.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
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
