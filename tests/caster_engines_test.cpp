// Real engines judged whole by check_caster: Embree 3 (default and RTC_SCENE_FLAG_ROBUST) and
// rayproof's own float and robust MeshCasters, on float meshes with float rays (what they take).
// The counts are printed (docs/check.md quotes them); the tests hold what each engine promises.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <limits>
#include <random>

#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/caster_check.h"
#include "verify/mesh_fuzz.h"

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace rayproof {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct TestMesh {
  mesh::Mesh m;
  std::string name;
  [[nodiscard]] verify::CasterMesh view() const { return {m.vertices, m.triangles, name}; }
};

/// Perturbed icospheres (float vertices), 320 and 1280 triangles, and a grid-point convex hull
/// (coplanar facets split into triangles).
std::vector<TestMesh> meshes() {
  std::vector<TestMesh> out;
  std::mt19937_64 rng(21);
  std::vector<Vec3<double>> interior;
  out.push_back({verify::random_star_mesh(rng, 2, 1, interior), "star320"});
  out.push_back({verify::random_star_mesh(rng, 3, 1, interior), "star1280"});
  for (int k = 0;; ++k) {
    mesh::Mesh h = verify::random_hull_mesh(rng, 40, 1, interior);
    if (k > 50 || h.triangles.size() > 30) {
      out.push_back({std::move(h), "hull"});
      break;
    }
  }
  return out;
}

verify::CasterCheckOptions float_options() {
  verify::CasterCheckOptions o;
  o.precision = verify::CasterPrecision::float32;
  o.random_rays = 2000;
  return o;
}

std::size_t set_false_miss(const verify::CasterTally& c, const std::string& set) {
  for (const auto& s : c.sets)
    if (s.set == set) return s.false_miss;
  return std::size_t(-1);
}

void print(const char* engine, const TestMesh& m, const verify::CasterTally& c) {
  std::printf("== %s on %s (%zu triangles)\n%s", engine, m.name.c_str(), m.m.triangles.size(),
              verify::summary_text(c).c_str());
}

template <class Method>
struct OwnCaster {
  MeshCaster<Method> c;
  explicit OwnCaster(const mesh::Mesh& m)
      : c(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles[0].data(), m.triangles.size()}) {}
  void operator()(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
                  std::span<std::int64_t> tri) const {
    for (std::size_t i = 0; i < o.size(); ++i) {
      const MeshHit h = c.closest({o[i], d[i]}, {std::numeric_limits<double>::denorm_min(), kInf});
      t[i] = h.hit() ? h.t : kInf;
      tri[i] = h.hit() ? std::int64_t(h.triangle) : -1;
    }
  }
  void any(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<std::uint8_t> out) const {
    for (std::size_t i = 0; i < o.size(); ++i)
      out[i] = c.any({o[i], d[i]}, {std::numeric_limits<double>::denorm_min(), kInf});
  }
};

TEST(CasterEngines, RayproofRobustCasterDoesNotLeak) {
  for (const TestMesh& m : meshes()) {
    const OwnCaster<cast::Robust> caster(m.m);
    const verify::CasterTally c = verify::check_caster(
        std::cref(caster), m.view(), float_options(),
        [&](auto o, auto d, auto out) { caster.any(o, d, out); });
    print("rayproof robust", m, c);
    EXPECT_EQ(c.false_miss + c.any_false_miss, 0u) << m.name;  // watertight: no ray that crosses slips through
    EXPECT_EQ(c.garbage + c.caster_failures + c.invalid_hit + c.invalid_failures, 0u);
  }
}

TEST(CasterEngines, RayproofFloatCasterIsJudged) {
  std::size_t findings = 0;
  for (const TestMesh& m : meshes()) {
    const OwnCaster<cast::Float> caster(m.m);
    const verify::CasterTally c = verify::check_caster(
        std::cref(caster), m.view(), float_options(),
        [&](auto o, auto d, auto out) { caster.any(o, d, out); });
    print("rayproof float", m, c);
    EXPECT_EQ(c.garbage + c.caster_failures + c.invalid_hit + c.invalid_failures, 0u);
    findings += c.findings();
  }
  EXPECT_GT(findings, 0u);  // float Möller–Trumbore is not watertight: something is found
}

#ifdef RAYPROOF_HAVE_EMBREE
struct EmbreeCaster {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  EmbreeCaster(const mesh::Mesh& m, bool robust) {
    device = rtcNewDevice("threads=1");
    scene = rtcNewScene(device);
    if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(m.vertices[i][k]);
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.triangles.size()));
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = m.triangles[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
  }
  ~EmbreeCaster() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
  static RTCRay ray_of(const Vec3<double>& o, const Vec3<double>& d) {
    RTCRay r{};
    r.org_x = float(o.x), r.org_y = float(o.y), r.org_z = float(o.z);
    r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
    r.tnear = 0.0f;
    r.tfar = std::numeric_limits<float>::infinity();
    r.mask = ~0u;
    return r;
  }
  /// Embree's ray.valid(): every coordinate of origin and direction within +-FLT_LARGE (1.844e18,
  /// so no NaN or infinity). Debian's Embree is built with assertions on and aborts on any other ray:
  /// this adapter throws instead (the ray is counted as a failure).
  static void check_range(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d) {
    for (std::size_t i = 0; i < o.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (!(std::abs(float(o[i][k])) <= 1.844e18f && std::abs(float(d[i][k])) <= 1.844e18f))
          throw std::runtime_error("outside Embree's ray range (its assertion ray.valid() would abort)");
  }
  void closest(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
               std::span<std::int64_t> tri) const {
    check_range(o, d);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = 0; i < o.size(); ++i) {
      RTCRayHit rh{};
      rh.ray = ray_of(o[i], d[i]);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      t[i] = hit ? double(rh.ray.tfar) : kInf;
      tri[i] = hit ? std::int64_t(rh.hit.primID) : -1;
    }
  }
  void any(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<std::uint8_t> out) const {
    check_range(o, d);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = 0; i < o.size(); ++i) {
      RTCRay r = ray_of(o[i], d[i]);
      rtcOccluded1(scene, &ctx, &r);
      out[i] = r.tfar < 0.0f;
    }
  }
};

void judge_embree(bool robust) {
  for (const TestMesh& m : meshes()) {
    const EmbreeCaster e(m.m, robust);
    verify::CasterCheckOptions opt = float_options();
    opt.batch = 1;  // a ray out of Embree's range fails alone
    const verify::CasterTally c = verify::check_caster(
        [&](auto o, auto d, auto t, auto tri) { e.closest(o, d, t, tri); }, m.view(), opt,
        [&](auto o, auto d, auto out) { e.any(o, d, out); });
    print(robust ? "embree robust" : "embree", m, c);
    EXPECT_EQ(c.garbage, 0u) << m.name;
    EXPECT_GT(c.hits, c.rays / 3) << m.name;
    if (robust) {
      // Watertight: no ray from inside slips out between triangles. (Grazing rays at silhouette
      // edges are another matter: float arithmetic decides those, and some miss.)
      EXPECT_EQ(set_false_miss(c, "leak"), 0u) << m.name;
    }
  }
}

TEST(CasterEngines, EmbreeDefault) { judge_embree(false); }
TEST(CasterEngines, EmbreeRobust) { judge_embree(true); }
#endif

}  // namespace
}  // namespace rayproof
