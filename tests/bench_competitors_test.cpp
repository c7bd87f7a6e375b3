// `rayproof bench`'s competitors (src/scene/compare): the names it takes, Embree on a device with
// max_isa=avx2 answering as the default device does, and the instruction sets each side reports.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "scene/accel.h"
#include "scene/compare/competitors.h"
#include "scene/compare/contains_compare.h"
#include "scene/compare/crossings_compare.h"
#include "scene/compare/distance_compare.h"
#include "scene/compare/embree_build.h"
#include "scene/compare/isa.h"
#include "registry/registry.h"
#include "scene/scene.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {
/// Rays from points inside the bounds in random directions, and from outside towards the middle.
std::vector<Ray<double>> some_rays(const Scene& s, std::size_t n) {
  const BvhBox b = s.bounds();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::vector<Ray<double>> out;
  for (std::size_t i = 0; i < n; ++i) {
    Ray<double> r;
    for (int k = 0; k < 3; ++k) r.o[k] = b.lo[k] + (double(b.hi[k]) - b.lo[k]) * (i % 2 ? u(rng) : 3 * u(rng) - 1);
    do r.d = {g(rng), g(rng), g(rng)};
    while (is_zero(r.d));
    out.push_back(r);
  }
  return out;
}
/// Certified's closest hit (triangle and t) and any hit on two trees of the same scene, ray by ray
/// (a failure names the first ray that differs); the rays that hit.
std::size_t same_certified_answers(const Accel& ours, const Accel& theirs, const std::vector<Ray<double>>& rays) {
  const SceneMethod certified = find_scene_method("certified", registry::all_methods());
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const PrimHit a = ours.closest(rays[i], certified), b = theirs.closest(rays[i], certified);
    EXPECT_EQ(a.prim, b.prim) << "ray " << i;
    if (a.prim != b.prim) return hits;
    if (a.prim != PrimHit::kNoPrim) {
      EXPECT_EQ(a.t, b.t) << "ray " << i;
    }
    EXPECT_EQ(ours.any(rays[i], certified), theirs.any(rays[i], certified)) << "ray " << i;
    hits += a.prim != PrimHit::kNoPrim;
  }
  return hits;
}
}  // namespace

TEST(BenchCompetitors, NamesAreCheckedWithTheListInTheMessage) {
  EXPECT_NO_THROW(compare::check_competitor_names("embree,embree-robust,embree-avx2,embree-robust-avx2,cgal-epick,cgal-epeck"));
  EXPECT_NO_THROW(compare::check_competitor_names("none"));
  EXPECT_NO_THROW(compare::check_competitor_names(""));
  EXPECT_NO_THROW(compare::check_competitor_names("embree,,cgal-epick"));
  try {
    compare::check_competitor_names("embree,embree-avx512");
    FAIL() << "embree-avx512 accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("unknown competitor 'embree-avx512'"), std::string::npos) << m;
    for (const auto& name : compare::competitor_names()) EXPECT_NE(m.find(name), std::string::npos) << m;
  }
  // make_competitors checks too, before building anything.
  Scene s;
  add_mesh(s, bumpy_sphere(100));
  EXPECT_THROW((void)compare::make_competitors(s, "cgal-epick,embre"), std::invalid_argument);
}

// On rays in general position. Rays aimed exactly at vertices and edges are another matter: there
// the default (Moeller) kernels of the two ISAs part in a few rays (bench's leak rays on bunny00:
// 11,172 misses capped at avx2, 11,148 with avx512), so this test keeps away from them.
TEST(BenchCompetitors, EmbreeOnAnAvx2DeviceAnswersAsTheDefaultDevice) {
  if (!compare::have_embree()) GTEST_SKIP() << "built without Embree";
  Scene s;
  add_mesh(s, bumpy_sphere(2000));
  const auto rays = some_rays(s, 4000);
  auto comps = compare::make_competitors(s, "embree,embree-robust,embree-avx2,embree-robust-avx2", 1);
  ASSERT_EQ(comps.size(), 4u);
  EXPECT_EQ(comps[2].name, "embree-avx2");
  EXPECT_EQ(comps[3].name, "embree-robust-avx2");
  EXPECT_EQ(comps[2].max_isa, "avx2");
  EXPECT_TRUE(comps[0].max_isa.empty());
  for (int pair = 0; pair < 2; ++pair) {
    const compare::Competitor &base = comps[pair], &capped = comps[2 + pair];
    for (const bool closest : {true, false}) {
      std::vector<std::uint8_t> a(rays.size()), b(rays.size());
      (closest ? base.closest : base.any)(rays, a, 1);
      (closest ? capped.closest : capped.any)(rays, b, 1);
      std::size_t hits = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(a[i] != 0, b[i] != 0) << capped.name << (closest ? " closest" : " any") << ", ray " << i;
        hits += a[i] != 0;
      }
      EXPECT_GT(hits, rays.size() / 4) << capped.name;  // the rays do reach the mesh
      EXPECT_LT(hits, rays.size()) << capped.name;
      // Packets of 8: on both devices wherever the CPU has AVX (Embree's native 8-ray width).
      for (const auto& p : capped.packets) {
        std::vector<std::uint8_t> c(rays.size());
        (closest ? p.closest : p.any)(rays, c, 1);
        for (std::size_t i = 0; i < rays.size(); ++i)
          ASSERT_EQ(a[i] != 0, c[i] != 0) << capped.name << " packet" << p.width << ", ray " << i;
      }
    }
    // No 16-ray packets on the AVX2 device: Embree runs them natively only with AVX-512.
    for (const auto& p : capped.packets) EXPECT_NE(p.width, 16) << capped.name;
  }
}

TEST(BenchCompetitors, EachSideReportsItsInstructionSet) {
  Scene s;
  add_mesh(s, bumpy_sphere(100));
  const Accel accel(s);
  const compare::OurIsa ours = compare::our_isa(accel);
  EXPECT_EQ(ours.nodes, to_string(accel.simd()));
  EXPECT_FALSE(ours.leaves.empty());
  ASSERT_EQ(ours.cpu.size(), 3u);
  EXPECT_EQ(ours.cpu[0].first, "avx2");
  EXPECT_EQ(ours.cpu[0].second, cpu_has_avx2());
  // Our eight-wide nodes run exactly when the CPU has AVX2 and nothing asks for SSE.
  if (!std::getenv("RAYPROOF_SIMD")) {
    EXPECT_EQ(ours.nodes, cpu_has_avx2() ? "avx2-8wide" : "sse-4wide");
  }
  if (!compare::have_embree()) GTEST_SKIP() << "built without Embree";
  auto comps = compare::make_competitors(s, "embree,embree-avx2,embree-robust-avx2", 1);
  ASSERT_EQ(comps.size(), 3u);
  __builtin_cpu_init();
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
                      __builtin_cpu_supports("avx512cd");
  for (const auto& c : comps) {
    ASSERT_FALSE(c.isa.empty()) << c.name << ": Embree's report had no selected intersector";
    EXPECT_EQ(c.kernel.rfind(c.isa + "::", 0), 0u) << c.kernel;
    EXPECT_FALSE(c.isa_how.empty());
  }
  // The capped devices never run above AVX2; on an AVX2 CPU they run exactly that. Embree's
  // 16-ray packets are native with its avx512 kernels only: the report and the property agree.
  for (std::size_t i = 1; i < comps.size(); ++i) {
    EXPECT_NE(comps[i].isa, "avx512") << comps[i].name;
    if (cpu_has_avx2()) {
      EXPECT_EQ(comps[i].isa, "avx2") << comps[i].name;
    }
  }
  if (avx512) {
    EXPECT_EQ(comps[0].isa, "avx512");
  }
  bool packet16 = false;
  for (const auto& p : comps[0].packets) packet16 |= p.width == 16;
  EXPECT_EQ(packet16, comps[0].isa == "avx512");
}

TEST(BenchCompetitors, SelectedKernelsFromAnEmbreeReport) {
  // As Embree 3.13 prints it with verbose=3: the created and then the selected intersectors.
  const std::string report =
      "created scene intersector\n"
      "  accels[0]\n"
      "    intersector1  = avx512::BVH8Triangle4Intersector1Moeller\n"
      "selected scene intersector\n"
      "  intersector1  = avx2::BVH8Triangle4vIntersector1Pluecker\n"
      "  intersector8  = avx2::BVH8Triangle4vIntersector8HybridPluecker\n"
      "  intersectorN = avx2::BVH8Triangle4vIntersectorStreamPluecker\n"
      "building BVH8<triangle4v> using avx::BVH8BuilderSAH ...\n";
  const auto k = compare::parse_selected_kernels(report);
  ASSERT_EQ(k.kernels.size(), 3u);
  ASSERT_NE(k.find("1"), nullptr);
  EXPECT_EQ(k.find("1")->isa, "avx2");
  EXPECT_EQ(k.find("1")->name, "avx2::BVH8Triangle4vIntersector1Pluecker");
  EXPECT_EQ(k.find("8")->name, "avx2::BVH8Triangle4vIntersector8HybridPluecker");
  EXPECT_EQ(k.find("N")->isa, "avx2");
  EXPECT_EQ(k.find("16"), nullptr);
  EXPECT_TRUE(compare::parse_selected_kernels("no report here\n").kernels.empty());
  EXPECT_TRUE(compare::parse_selected_kernels("selected scene intersector\n").kernels.empty());
}

// The mesh benches' Embree peers (bench distance, contains, crossings) live while every method is
// timed, ours included. An Embree device made with "threads=1" caps TBB's parallelism for the whole
// process (its global_control) while it lives: at --threads 2 every method then ran on one thread.
TEST(BenchCompetitors, MeshPeersLeaveTbbsThreadCountAlone) {
  if (!compare::have_embree()) GTEST_SKIP() << "built without Embree";
  const auto before = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  if (before < 2) GTEST_SKIP() << "one hardware thread here: nothing to cap";
  const mesh::Mesh m = icosphere(2);
  const auto d = compare::make_distance_competitors(m.vertices, m.triangles, "embree");
  const auto c = compare::make_contains_competitors(m.vertices, m.triangles, "embree-parity");
  const auto a = compare::make_embree_all_hits(m.vertices, m.triangles);
  ASSERT_EQ(d.size(), 1u);
  ASSERT_EQ(c.size(), 1u);
  ASSERT_TRUE(d[0].run && c[0].run && a.run);
  EXPECT_EQ(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), before);
}

// `bench --embree-tree`: Embree's rtcBuildBVH builds the binary tree that Accel collapses and
// traverses. Certified's answers are exact, so on either tree every ray gets the same triangle and
// t; robust misses nothing on either (its promise rests on the boxes holding their triangles).
TEST(BenchCompetitors, EmbreesTreeUnderOurLoopGivesTheSameAnswers) {
  std::string why;
  BvhBuildOptions eo{BvhBuilder::sah, 4};
  eo.binary = compare::embree_binary_builder(8, 4, &why);
  if (!compare::have_embree()) {
    EXPECT_FALSE(eo.binary);
    EXPECT_FALSE(why.empty());
    GTEST_SKIP() << "built without Embree";
  }
  ASSERT_TRUE(eo.binary);
  Scene s;
  add_mesh(s, bumpy_sphere(20000));
  const Accel ours(s, BvhBuildOptions{BvhBuilder::sah, 4}), theirs(s, eo);
  const auto rays = some_rays(s, 6000);
  const std::size_t hits = same_certified_answers(ours, theirs, rays);
  EXPECT_GT(hits, rays.size() / 4);
  // Every triangle lands in exactly one leaf of Embree's tree.
  std::vector<int> seen(s.mesh.triangles.size(), 0);
  for (const auto& p : theirs.leaf_prims())
    if (p.id != PrimHit::kNoPrim) {
      ASSERT_EQ(seen.at(p.id)++, 0);
    }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(seen.size()));
  // And it is Embree's tree, not ours again: the leaves hold the triangles in another order.
  std::vector<std::uint32_t> ids_ours, ids_theirs;
  for (const auto& p : ours.leaf_prims()) ids_ours.push_back(p.id);
  for (const auto& p : theirs.leaf_prims()) ids_theirs.push_back(p.id);
  EXPECT_NE(ids_ours, ids_theirs);
  // The hook is what builds it: one that throws stops the build.
  BvhBuildOptions failing;
  failing.binary = [](const std::vector<BvhBox>&, const std::vector<Vec3<float>>&) -> Bvh {
    throw std::runtime_error("binary builder called");
  };
  EXPECT_THROW(Accel(s, failing), std::runtime_error);
}

// Embree's builder with spatial splits (quality high and its splitPrimitive callback): a long
// triangle is cut into pieces, each in a leaf whose box holds only its piece. The pieces' boxes
// are rounded outwards from a double clip with a margin for its rounding, so the conservative
// traversal still finds every crossing: certified gives every ray the same triangle and t on this
// tree as on ours, including rays aimed at points of the long triangles, and every triangle sits in
// at least one leaf, some in several.
TEST(BenchCompetitors, EmbreesSpatialSplitsKeepEveryAnswer) {
  if (!compare::have_embree()) GTEST_SKIP() << "built without Embree";
  EXPECT_THROW((void)compare::embree_binary_builder(8, 4, nullptr, compare::EmbreeTreeQuality::high_splits),
               std::invalid_argument);
  // A bumpy sphere with long slivers across its box (the triangles splits are for).
  mesh::Mesh m = bumpy_sphere(4000);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<Triangle<double>> slivers;
  for (int i = 0; i < 64; ++i) {
    const Vec3<double> a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c = a + Vec3<double>{0.01 * u(rng), 0.02, 0.01};
    const auto base = std::uint32_t(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
    slivers.push_back({a, b, c});
  }
  Scene s;
  add_mesh(s, m);
  BvhBuildOptions eo{BvhBuilder::sah, 4};
  eo.binary = compare::embree_binary_builder(8, 4, nullptr, compare::EmbreeTreeQuality::high_splits,
                                             [&s](std::uint32_t i) { return s.triangle(i); });
  const Accel ours(s, BvhBuildOptions{BvhBuilder::sah, 4}), theirs(s, eo);
  std::vector<int> seen(s.mesh.triangles.size(), 0);
  for (const auto& p : theirs.leaf_prims())
    if (p.id != PrimHit::kNoPrim) ++seen.at(p.id);
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 0), 0);
  EXPECT_GT(std::count_if(seen.begin(), seen.end(), [](int n) { return n > 1; }), 8);
  std::vector<Ray<double>> rays = some_rays(s, 3000);
  std::uniform_real_distribution<double> w(0, 1);
  for (const Triangle<double>& t : slivers)
    for (int k = 0; k < 40; ++k) {
      const double a = w(rng), b = w(rng) * (1 - a);
      const Vec3<double> at = t.p0 + (t.p1 - t.p0) * a + (t.p2 - t.p0) * b;
      const Vec3<double> o{u(rng) * 3, u(rng) * 3, u(rng) * 3};
      rays.push_back({o, at - o});
    }
  const std::size_t hits = same_certified_answers(ours, theirs, rays);
  EXPECT_GT(hits, rays.size() / 3);
}
