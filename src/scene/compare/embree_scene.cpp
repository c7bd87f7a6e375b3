// Embree 3 competitor (compiled only with RAYPROOF_HAVE_EMBREE).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <limits>

#include "scene/compare/competitors.h"

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace rayproof::scene::compare {

bool have_embree() {
#ifdef RAYPROOF_HAVE_EMBREE
  return true;
#else
  return false;
#endif
}

#ifdef RAYPROOF_HAVE_EMBREE
namespace {
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};
}  // namespace

Competitor make_embree(const Scene& s, bool robust, int build_threads) {
  const auto start = std::chrono::steady_clock::now();
  auto e = std::make_shared<EmbreeScene>();
  const std::string config = build_threads > 0 ? "threads=" + std::to_string(build_threads) : std::string();
  e->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  e->scene = rtcNewScene(e->device);
  if (robust) rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), s.mesh.vertices.size()));
  for (std::size_t i = 0; i < s.mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(s.mesh.vertices[i][k]);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), s.mesh.triangles.size()));
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = s.mesh.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(e->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e->scene);
  Competitor c;
  c.name = robust ? "embree-robust" : "embree";
  c.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.bytes_per_tri = -1;
  c.closest = [e](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& r) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
          RTCRayHit rh{};
          rh.ray.org_x = float(rays[i].o.x), rh.ray.org_y = float(rays[i].o.y), rh.ray.org_z = float(rays[i].o.z);
          rh.ray.dir_x = float(rays[i].d.x), rh.ray.dir_y = float(rays[i].d.y), rh.ray.dir_z = float(rays[i].d.z);
          rh.ray.tnear = 0.0f;
          rh.ray.tfar = std::numeric_limits<float>::infinity();
          rh.ray.mask = ~0u;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(e->scene, &ctx, &rh);
          out[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
      });
    });
  };
  return c;
}
#endif

}  // namespace rayproof::scene::compare
