#pragma once
/// A triangle mesh in Embree 3 for the one-ray competitors of `bench contains` and
/// `bench crossings`: a one-thread device and a committed scene, the vertices rounded to float
/// (Embree's precision). Include only where RAYPROOF_HAVE_EMBREE is defined.
#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof::scene::compare {

struct EmbreeMesh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  EmbreeMesh() = default;
  EmbreeMesh(const EmbreeMesh&) = delete;
  EmbreeMesh& operator=(const EmbreeMesh&) = delete;
  ~EmbreeMesh() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

/// An Embree device that leaves TBB's thread count alone. A device made with "threads=N" caps TBB's
/// parallelism for the whole process at N (Embree's tbb::global_control) while it lives: with the
/// "threads=1" these benches used, every method of `bench distance`, `bench contains` and `bench
/// crossings` ran on one thread at --threads 2, rayproof's included. Embree's queries run on the
/// caller's thread either way; only its own build (not a judged figure here) uses TBB's threads.
inline RTCDevice new_embree_device() { return rtcNewDevice(nullptr); }

/// The mesh's triangles in one geometry (vertices rounded to float); `flags` set on the scene before
/// it is committed, and `point_query` (when given) as the geometry's point-query callback.
inline std::shared_ptr<EmbreeMesh> make_embree_mesh(const std::vector<Vec3<double>>& v,
                                                    const std::vector<std::array<std::uint32_t, 3>>& t, RTCSceneFlags flags,
                                                    RTCPointQueryFunction point_query = nullptr) {
  auto e = std::make_shared<EmbreeMesh>();
  e->device = new_embree_device();
  e->scene = rtcNewScene(e->device);
  rtcSetSceneFlags(e->scene, flags);
  RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) vb[3 * i] = float(v[i].x), vb[3 * i + 1] = float(v[i].y), vb[3 * i + 2] = float(v[i].z);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), t.size()));
  for (std::size_t i = 0; i < t.size(); ++i) ib[3 * i] = t[i][0], ib[3 * i + 1] = t[i][1], ib[3 * i + 2] = t[i][2];
  if (point_query) rtcSetGeometryPointQueryFunction(g, point_query);
  rtcCommitGeometry(g);
  rtcAttachGeometry(e->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e->scene);
  return e;
}

}  // namespace rayproof::scene::compare
