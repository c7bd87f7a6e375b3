// Which instruction sets bench's sides run (isa.h).
#include "scene/compare/isa.h"

#include <algorithm>
#include <iostream>
#include <sstream>

#include "scene/accel.h"
#include "scene/leaf_simd.h"

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace rayproof::scene::compare {

OurIsa our_isa(const Accel& a) {
  OurIsa o;
  o.nodes = to_string(a.simd());
  o.leaves = detail::to_string(detail::leaf_simd());
  __builtin_cpu_init();
  // The three that decide our paths and Embree's: AVX2 and FMA (our eight-wide nodes and leaves,
  // Embree's avx2 kernels) and AVX-512F (Embree's avx512 kernels; we have none).
  o.cpu = {{"avx2", __builtin_cpu_supports("avx2") != 0},
           {"fma", __builtin_cpu_supports("fma") != 0},
           {"avx512f", __builtin_cpu_supports("avx512f") != 0}};
  return o;
}

EmbreeKernels parse_selected_kernels(const std::string& report) {
  EmbreeKernels k;
  std::size_t p = report.rfind("selected scene intersector");  // the last commit's report
  if (p == std::string::npos) return k;
  p = report.find('\n', p);
  // Then one indented line per intersector, "  intersector1  = avx512::BVH8Triangle4Intersector1Moeller",
  // until a line of another form.
  while (p != std::string::npos && p + 1 < report.size()) {
    const std::size_t b = p + 1, e = std::min(report.find('\n', b), report.size());
    const std::string line = report.substr(b, e - b);
    p = e < report.size() ? e : std::string::npos;
    const std::size_t key = line.find_first_not_of(' '), eq = line.find(" = ");
    if (key == std::string::npos || key == 0 || line.compare(key, 11, "intersector") != 0 || eq == std::string::npos ||
        eq < key + 11)
      break;
    std::string width = line.substr(key + 11, eq - key - 11);
    width.erase(width.find_last_not_of(' ') + 1);
    std::string name = line.substr(eq + 3);
    name.erase(name.find_last_not_of(" \r") + 1);
    const std::size_t ns = name.find("::");
    if (width.empty() || ns == std::string::npos || ns == 0) break;
    k.kernels.push_back({width, name.substr(0, ns), name});
  }
  return k;
}

#ifdef RAYPROOF_HAVE_EMBREE
namespace {
/// std::cout into a string for the guard's lifetime. Embree 3 prints its verbose reports to
/// std::cout (checked: with it redirected, none of the report reaches the process's stdout), and
/// bench prints through fmt to the C stdout, so nothing of ours is caught; no other thread writes
/// to std::cout while a competitor is made.
class CaptureCout {
 public:
  CaptureCout() : old_(std::cout.rdbuf(text_.rdbuf())) {}
  ~CaptureCout() { std::cout.rdbuf(old_); }
  CaptureCout(const CaptureCout&) = delete;
  CaptureCout& operator=(const CaptureCout&) = delete;
  [[nodiscard]] std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::streambuf* old_;
};
}  // namespace

EmbreeKernels embree_selected_kernels(const std::string& config, bool robust) {
  std::string report;
  {
    CaptureCout capture;
    // The probe's own device: the same configuration (so the same ISA cap and thread count; Embree
    // sizes its task scheduler to the largest live device), verbose only here.
    const std::string verbose = config.empty() ? "verbose=3" : config + ",verbose=3";
    if (RTCDevice device = rtcNewDevice(verbose.c_str())) {
      RTCScene scene = rtcNewScene(device);
      if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vb = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3));
      const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
      std::copy(v, v + 9, vb);
      auto* ib = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 1));
      ib[0] = 0, ib[1] = 1, ib[2] = 2;
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene, g);
      rtcReleaseGeometry(g);
      rtcCommitScene(scene);
      rtcReleaseScene(scene);
      rtcReleaseDevice(device);
    }
    report = capture.text();
  }
  return parse_selected_kernels(report);
}
#else
EmbreeKernels embree_selected_kernels(const std::string&, bool) { return {}; }
#endif

}  // namespace rayproof::scene::compare
