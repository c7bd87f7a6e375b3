// Scenes: JSON descriptions, the built-in scene, scene queries against brute force for every
// primitive kind, and watertightness on a closed mesh (generated, and CGAL's bunny when present).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "registry/registry.h"
#include "scene/accel.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {
std::string error_of(const std::string& json) {
  try {
    (void)parse_scene_json(json, "/nonexistent", "s.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}
SceneMethod method(const std::string& name) { return find_scene_method(name, registry::all_methods()); }
}  // namespace

TEST(SceneJson, EveryKindAndTheCamera) {
  const auto dir = std::filesystem::temp_directory_path() / ("rayproof_scene_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "tri.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const Scene s = parse_scene_json(R"({
    "camera": {"type": "orthographic", "eye": [0, 0, 5], "target": [0, 0, 0], "half_width": 2, "half_height": 1,
               "width": 40, "height": 20},
    "meshes": [{"file": "tri.off", "scale": 2, "translate": [10, 0, 0]},
               {"file": "tri.off", "matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,7],[0,0,0,1]]}],
    "spheres": [{"center": [1, 2, 3], "radius": 0.5}],
    "ellipsoids": [{"center": [0, 0, 0], "semi_axes": [1, 2, 3]}],
    "disks": [{"center": [0, 0, 0], "normal": [0, 1, 0], "radius": 4}],
    "boxes": [{"lo": [0, 0, 0], "hi": [1, 1, 1]}],
    "lights": [{"type": "disk", "center": [0, 5, 0], "normal": [0, -1, 0], "radius": 1, "emission": [2, 2, 2]}]
  })", dir.string(), "s.json");
  ASSERT_EQ(s.mesh.triangles.size(), 2u);
  EXPECT_EQ(s.mesh.vertices[1], (Vec3<double>{12, 0, 0}));
  EXPECT_EQ(s.mesh.vertices[5], (Vec3<double>{0, 1, 7}));
  EXPECT_EQ(s.size(), 6u);
  ASSERT_TRUE(s.camera);
  EXPECT_EQ(s.camera->width(), 40);
  const Ray<double> r = s.camera->generate(20, 10);
  EXPECT_EQ(r.o.z, 5.0);
  EXPECT_EQ(r.d, (Vec3<double>{0, 0, -1}));
  EXPECT_EQ(s.lights.size(), 1u);
  std::uint32_t local;
  EXPECT_EQ(s.kind_of(5, local), PrimKind::box);
  std::filesystem::remove_all(dir);
}

TEST(SceneJson, ErrorsNameTheFileAndPath) {
  EXPECT_EQ(error_of(R"({"spheres": [{"center": [0, 0, 0], "radius": "big"}]})"), "s.json: spheres[0].radius: expected a number");
  EXPECT_EQ(error_of(R"({"sphere": []})"), "s.json: (top level): unknown key 'sphere'");
  EXPECT_EQ(error_of(R"({"boxes": [{"lo": [0, 0], "hi": [1, 1, 1]}]})"), "s.json: boxes[0].lo: expected [x, y, z]");
  EXPECT_EQ(error_of(R"({"meshes": [{"file": "nope.off"}]})"), "s.json: meshes[0].file: /nonexistent/nope.off: no such file");
  EXPECT_EQ(error_of(R"({"camera": {"eye": [0, 0, 1], "target": [0, 0, 1]}})"), "s.json: camera: eye equals target");
  EXPECT_EQ(error_of("{\"spheres\": [\n"), "s.json: byte 15: invalid JSON ([json.exception.parse_error.101] parse error at line 2, column 1: syntax error while parsing value - unexpected end of input; expected '[', '{', or a literal)");
}

TEST(Scene, IcosphereIsClosed) {
  const mesh::Mesh m = icosphere(2);
  EXPECT_EQ(m.triangles.size(), 320u);
  EXPECT_EQ(m.vertices.size(), 162u);  // V - E + F = 2 with E = 3F/2
  EXPECT_NEAR(length(volume_centroid(m)), 0.0, 1e-12);
}

TEST(Accel, QueriesMatchBruteForceOnEveryKind) {
  const Scene s = default_scene(2);
  const Accel accel(s);
  const SceneMethod m = method("double");
  const auto& reg = registry::all_methods();
  const Method& dbl = *reg.find("double");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int hit_rays = 0;
  std::vector<PrimHit> batch_in;
  std::vector<Ray<double>> rays;
  for (int i = 0; i < 600; ++i) {
    const Ray<double> r = s.camera->generate(int(rng() % 320), int(rng() % 240));
    const Ray<double> ray = i % 2 ? r : Ray<double>{{3 * u(rng), 1 + u(rng), 3 * u(rng)}, {u(rng), u(rng), u(rng)}};
    rays.push_back(ray);
    // The registry's `double` through its case interface: the same kernels, reached another way.
    const SceneMethod generic{"double", FastKernel::none, &dbl, BvhTraversal::standard};
    const auto all = accel.all(ray, m);
    const auto all_generic = accel.all(ray, generic);
    ASSERT_EQ(all, all_generic) << i;  // compiled and registry kernels agree crossing by crossing
    const PrimHit c = accel.closest(ray, m);
    if (all.empty()) {
      EXPECT_EQ(c.prim, PrimHit::kNoPrim);
      EXPECT_FALSE(accel.any(ray, m));
    } else {
      ++hit_rays;
      EXPECT_EQ(c, all.front()) << i;
      EXPECT_TRUE(accel.any(ray, m));
      // The range excludes the first crossing: the next one (or none) is closest.
      const QueryRange q{std::nextafter(all.front().t, 1e300), 1e300};
      const PrimHit c2 = accel.closest(ray, m, q);
      std::size_t k = 0;
      while (k < all.size() && all[k].t <= all.front().t) ++k;
      if (k < all.size()) {
        EXPECT_EQ(c2.t, all[k].t) << i;
      } else {
        EXPECT_EQ(c2.prim, PrimHit::kNoPrim) << i;
      }
    }
  }
  EXPECT_GT(hit_rays, 300);
  std::vector<PrimHit> out(rays.size());
  accel.closest_batch(rays, out, m, 2);
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(out[i], accel.closest(rays[i], m)) << i;
}

TEST(Accel, BruteForceOverPrimitivesAgrees) {
  // A scene of many spheres and triangles: closest hit by BVH equals the minimum over all().
  const Scene s = default_scene(3);
  for (BvhBuilder b : {BvhBuilder::median, BvhBuilder::sah}) {
    const Accel accel(s, {b, 4});
    const Accel flat(s, {BvhBuilder::median, 1u << 30});  // one leaf: brute force
    ASSERT_LE(flat.max_depth(), 6);  // one leaf, split into chunks of at most 255
    const SceneMethod m = method("float");
    std::mt19937 rng(5);
    for (int i = 0; i < 400; ++i) {
      const Ray<double> r = s.camera->generate(int(rng() % 320), int(rng() % 240));
      ASSERT_EQ(accel.closest(r, m), flat.closest(r, m)) << i;
      ASSERT_EQ(accel.all(r, m), flat.all(r, m)) << i;
    }
  }
}

TEST(Watertight, GeneratedClosedMeshLeaksOnlyForNonRobustKernels) {
  Scene s;
  add_mesh(s, bumpy_sphere(20000));
  const Accel accel(s);
  const auto rays = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh));
  ASSERT_GT(rays.size(), 30000u);
  EXPECT_EQ(count_leaks(accel, method("watertight"), rays).misses, 0u);
  EXPECT_EQ(count_leaks(accel, method("watertight-float"), rays).misses, 0u);
  const auto few = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 3000));
  EXPECT_EQ(count_leaks(accel, method("robust"), few).misses, 0u);
  EXPECT_EQ(count_leaks(accel, method("certified"), few).misses, 0u);
  // Möller–Trumbore in float lets rays through at vertices and edges: the test can tell.
  EXPECT_GT(count_leaks(accel, method("float"), rays).misses, 0u);
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(Watertight, BunnyHasNoLeaksForRobustAndCertified) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const Scene s = load_scene(path);
  ASSERT_EQ(s.mesh.triangles.size(), 75408u);
  const Accel accel(s);
  const Vec3<double> inside = volume_centroid(s.mesh);
  const auto rays = leak_rays(inside, leak_targets(s.mesh));
  EXPECT_EQ(count_leaks(accel, method("watertight"), rays).misses, 0u);
  const auto few = leak_rays(inside, leak_targets(s.mesh, 4000));
  EXPECT_EQ(count_leaks(accel, method("robust"), few).misses, 0u);
  EXPECT_EQ(count_leaks(accel, method("certified"), few).misses, 0u);
}
#endif

TEST(Accel, CompiledKernelsThroughLeafRecordsMatchTheRegistryMethods) {
  // The compiled float, robust and certified kernels read triangles from the BVH's leaf-order
  // records; the registry's methods of the same names, through the case interface, read them from
  // the mesh by primitive number. Crossing by crossing they agree, on leak rays (exact vertex and
  // edge aims from inside a closed mesh), random rays, and rays with tmin / tmax, in a scene with
  // analytic primitives too.
  Scene s = default_scene(2);
  add_mesh(s, bumpy_sphere(3000));
  const Accel accel(s);
  const auto& reg = registry::all_methods();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Ray<double>> rays = leak_rays(Vec3<double>{0.01, 0.02, -0.01}, leak_targets(s.mesh, 1500));
  for (int i = 0; i < 500; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  int crossings = 0;
  for (const char* name : {"float", "robust", "certified"}) {
    const SceneMethod compiled = method(name);
    ASSERT_NE(compiled.fast, FastKernel::none) << name;
    const SceneMethod generic{name, FastKernel::none, reg.find(name), compiled.traversal};
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const QueryRange q = i % 3 == 1 ? QueryRange{0.25, 1.5} : QueryRange{};
      const auto a = accel.all(rays[i], compiled, q);
      ASSERT_EQ(a, accel.all(rays[i], generic, q)) << name << " ray " << i;
      // Closest is the first of all hits when no box the ray touches is culled (conservative
      // traversal; the textbook slab test of `float` may cull a box touched at one point).
      if (compiled.traversal == BvhTraversal::conservative) {
        ASSERT_EQ(accel.closest(rays[i], compiled, q), a.empty() ? PrimHit{} : a.front()) << name << " ray " << i;
      }
      crossings += int(a.size());
    }
  }
  EXPECT_GT(crossings, 3000);
}
