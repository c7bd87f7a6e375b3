// Embree 3 competitor (compiled only with RAYPROOF_HAVE_EMBREE).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <limits>
#include <string>

#include "scene/compare/competitors.h"
#include "scene/compare/isa.h"

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

/// Embree's device configuration: `threads` threads (0: all), instruction sets up to `max_isa`
/// (empty: the best the CPU and the library have).
std::string device_config(int threads, const std::string& max_isa) {
  std::string config;
  if (threads > 0) config.append("threads=").append(std::to_string(threads));
  if (!max_isa.empty()) config.append(config.empty() ? "" : ",").append("max_isa=").append(max_isa);
  return config;
}

RTCDevice new_device(const std::string& config) { return rtcNewDevice(config.empty() ? nullptr : config.c_str()); }

/// The scene of s's triangles on device e->device (vertices rounded to float, as Embree takes them).
void build_scene(EmbreeScene& e, const Scene& s, bool robust) {
  e.scene = rtcNewScene(e.device);
  if (robust) rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), s.mesh.vertices.size()));
  for (std::size_t i = 0; i < s.mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(s.mesh.vertices[i][k]);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), s.mesh.triangles.size()));
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = s.mesh.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(e.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e.scene);
}

RTCRay embree_ray(const Ray<double>& r) {
  RTCRay ray{};
  ray.org_x = float(r.o.x), ray.org_y = float(r.o.y), ray.org_z = float(r.o.z);
  ray.dir_x = float(r.d.x), ray.dir_y = float(r.d.y), ray.dir_z = float(r.d.z);
  ray.tnear = 0.0f;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.mask = ~0u;
  return ray;
}

/// Lane i of an Embree packet from a ray (as embree_ray: float origin and direction, [0, inf)).
template <class RayW>
void set_lane(RayW& p, int i, const Ray<double>& r) {
  p.org_x[i] = float(r.o.x), p.org_y[i] = float(r.o.y), p.org_z[i] = float(r.o.z);
  p.dir_x[i] = float(r.d.x), p.dir_y[i] = float(r.d.y), p.dir_z[i] = float(r.d.z);
  p.tnear[i] = 0.0f, p.time[i] = 0.0f;
  p.tfar[i] = std::numeric_limits<float>::infinity();
  p.mask[i] = ~0u, p.id[i] = 0, p.flags[i] = 0;
}

std::string fmt_not_native(const char* calls, int width, const std::string& max_isa) {
  const std::string device = max_isa.empty() ? "this Embree device" : "this Embree device, max_isa=" + max_isa + ",";
  return std::string(calls) + ": not available (" + device + " does not run " + std::to_string(width) +
         "-ray packets natively on this CPU)";
}

template <class Body>
void over_threads(std::size_t n, int threads, Body&& body) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& r) { body(r.begin(), r.end()); });
  });
}
}  // namespace

Competitor make_embree(const Scene& s, bool robust, int build_threads, const std::string& max_isa) {
  auto e = std::make_shared<EmbreeScene>();
  e->device = new_device(device_config(build_threads, max_isa));
  const auto start = std::chrono::steady_clock::now();
  build_scene(*e, s, robust);
  Competitor c;
  c.name = std::string(robust ? "embree-robust" : "embree") + (max_isa.empty() ? "" : "-" + max_isa);
  c.max_isa = max_isa;
  c.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.bytes_per_tri = -1;
  c.closest = [e](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
    over_threads(rays.size(), threads, [&](std::size_t b, std::size_t end) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      for (std::size_t i = b; i < end; ++i) {
        RTCRayHit rh{};
        rh.ray = embree_ray(rays[i]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e->scene, &ctx, &rh);
        out[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      }
    });
  };
  c.any = [e](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
    over_threads(rays.size(), threads, [&](std::size_t b, std::size_t end) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      for (std::size_t i = b; i < end; ++i) {
        RTCRay ray = embree_ray(rays[i]);
        rtcOccluded1(e->scene, &ctx, &ray);
        out[i] = ray.tfar < 0.0f;  // set to -inf on a hit
      }
    });
  };
  // Packets: 8 and 16 rays, where the device runs that width natively.
  auto add_packets = [&]<int W, class RayHitW, class RayW>(RTCDeviceProperty native, const char* calls, void (*isect)(const int*, RTCScene, RTCIntersectContext*, RayHitW*), void (*occl)(const int*, RTCScene, RTCIntersectContext*, RayW*)) {
    if (!rtcGetDeviceProperty(e->device, native)) {
      c.packet_notes.push_back(fmt_not_native(calls, W, max_isa));
      return;
    }
    Competitor::Packets p;
    p.width = W;
    p.closest = [e, isect](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
      const std::size_t packets = (rays.size() + W - 1) / W;
      over_threads(packets, threads, [&](std::size_t b, std::size_t end) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        alignas(64) int valid[W];
        alignas(64) RayHitW rh;
        for (std::size_t pk = b; pk < end; ++pk) {
          const std::size_t first = pk * W;
          for (int i = 0; i < W; ++i) {
            const bool live = first + std::size_t(i) < rays.size();
            valid[i] = live ? -1 : 0;
            set_lane(rh.ray, i, live ? rays[first + std::size_t(i)] : Ray<double>{{0, 0, 0}, {0, 0, 1}});
            rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
          }
          isect(valid, e->scene, &ctx, &rh);
          for (int i = 0; i < W && first + std::size_t(i) < rays.size(); ++i)
            out[first + std::size_t(i)] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        }
      });
    };
    p.any = [e, occl](std::span<const Ray<double>> rays, std::span<std::uint8_t> out, int threads) {
      const std::size_t packets = (rays.size() + W - 1) / W;
      over_threads(packets, threads, [&](std::size_t b, std::size_t end) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        alignas(64) int valid[W];
        alignas(64) RayW ray;
        for (std::size_t pk = b; pk < end; ++pk) {
          const std::size_t first = pk * W;
          for (int i = 0; i < W; ++i) {
            const bool live = first + std::size_t(i) < rays.size();
            valid[i] = live ? -1 : 0;
            set_lane(ray, i, live ? rays[first + std::size_t(i)] : Ray<double>{{0, 0, 0}, {0, 0, 1}});
          }
          occl(valid, e->scene, &ctx, &ray);
          for (int i = 0; i < W && first + std::size_t(i) < rays.size(); ++i)
            out[first + std::size_t(i)] = ray.tfar[i] < 0.0f;  // set to -inf on a hit
        }
      });
    };
    c.packets.push_back(std::move(p));
  };
  add_packets.template operator()<8, RTCRayHit8, RTCRay8>(RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED, "rtcIntersect8/rtcOccluded8",
                                                        rtcIntersect8, rtcOccluded8);
  add_packets.template operator()<16, RTCRayHit16, RTCRay16>(RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED,
                                                           "rtcIntersect16/rtcOccluded16", rtcIntersect16, rtcOccluded16);
  // The kernels Embree selects on this configuration (Embree 3 has no device property for it).
  const EmbreeKernels k = embree_selected_kernels(device_config(build_threads, max_isa), robust);
  if (const EmbreeKernel* one = k.find("1")) {
    c.isa = one->isa, c.kernel = one->name;
    // The packet rows run Embree's other kernels: say whether they are in the same ISA.
    std::string others;
    for (const auto& x : k.kernels)
      if (x.isa != one->isa) others += (others.empty() ? "" : ", ") + x.name;
    c.isa_how = "Embree's verbose=3 report of the kernels it selects on a one-triangle scene with the same device "
                "configuration and scene flags, " +
                (others.empty() ? std::string("its packet kernels in the ISA of") : "its packet kernels " + others + " beside") +
                " the rtcIntersect1 kernels named here";
  }
  const Scene* sp = &s;
  c.build_seconds = [sp, robust, max_isa](int threads) {
    EmbreeScene again;
    again.device = new_device(device_config(threads, max_isa));
    const auto t0 = std::chrono::steady_clock::now();
    build_scene(again, *sp, robust);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  return c;
}
#endif

}  // namespace rayproof::scene::compare
