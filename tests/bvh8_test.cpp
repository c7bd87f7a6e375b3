// Eight-wide BVH (bvh_wide8.h) and the run-time SIMD dispatch: the AVX2 eight-wide path, the SSE
// four-wide path, the binary BVH and brute force give identical answers ray by ray, for the raw
// traversal (Möller–Trumbore leaves) and for every compiled scene method through scene::Accel, on
// generated meshes, bunny00's leak rays and hostile rays. The AVX2 tests are skipped on a CPU
// without AVX2 (the dispatch then never takes that path).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "registry/registry.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"
#include "rayproof/triangle.h"
#include "scene/accel.h"
#include "bvh_support.h"
#include "hostile_rays.h"
#include "scene/watertight.h"

using namespace rayproof;
using test::Answers, test::answers, test::brute, test::hits, test::hostile_rays, test::Soup;

namespace {
/// The soups here have every fifth triangle flat (parallel to z = 0).
test::Soup random_soup(int n, unsigned seed) { return test::random_soup(n, seed, true); }

#define REQUIRE_AVX2() \
  if (!cpu_has_avx2()) GTEST_SKIP() << "no AVX2 on this CPU: the eight-wide path is never taken"

}  // namespace

TEST(Bvh8, CollapseKeepsEveryPrimitiveAndNestsBounds) {
  const Soup soup = random_soup(3000, 4);
  struct Case {
    BvhBuilder builder;
    std::uint32_t leaf, merge;
  };
  for (auto [builder, leaf, merge] : {Case{BvhBuilder::median, 4u, 0}, {BvhBuilder::sah, 4u, 0}, {BvhBuilder::sah, 4u, 6},
                                      {BvhBuilder::median, 1u << 30, 0}, {BvhBuilder::median, 1u << 30, 300}}) {
    // The plain SAH (leaf_group 1: its leaves stay below 6 primitives here), so that merging shows.
    Bvh bin = build_bvh(soup.boxes, soup.centers, {builder, leaf, 1});
    std::uint32_t bin_largest = 0;
    for (const BvhNode& n : bin.nodes) bin_largest = std::max(bin_largest, n.count);
    const Bvh8 w = collapse_bvh8(std::move(bin), soup.boxes, merge);
    const std::uint32_t largest_leaf = test::check_wide_tree(w, soup).largest_leaf;
    if (leaf == 4u) {
      EXPECT_LT(w.nodes.size(), soup.tris.size() / 4);  // wider than the four-wide tree's bound (tris / 3)
      // Merged subtrees: at most `merge` primitives; without merging the binary tree's leaves.
      EXPECT_LE(largest_leaf, std::max(merge, bin_largest));
      if (merge) {
        EXPECT_GT(largest_leaf, bin_largest);
      } else {
        EXPECT_EQ(largest_leaf, bin_largest);
      }
    } else {
      EXPECT_LE(largest_leaf, Bvh8::kMaxLeaf);          // one big leaf: split into chunks
    }
  }
}

TEST(Bvh8, QueriesAgreeWithBvh4BinaryTreeAndBruteForce) {
  REQUIRE_AVX2();
  const Soup soup = random_soup(3000, 2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative}) {
    const Bvh bin = build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4});
    const Bvh4 w4 = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
    const Bvh8 w8 = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
    int hit_rays = 0;
    for (int r = 0; r < 700; ++r) {
      Ray<double> ray{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
      // Hostile: axis-parallel with +0 / -0 components, origins on slab planes (a vertex's z on the
      // flat triangles' planes), and directions scaled out of the float range (the double path).
      if (r % 11 == 1) ray.d = {0.0, -0.0, r % 2 ? 1.0 : -1.0};
      if (r % 11 == 2) ray.d = {-0.0, d(rng), 0.0};
      if (r % 11 == 4) ray.o.z = soup.tris[rng() % 600 * 5].p0.z, ray.d.z = r % 2 ? 0.0 : -0.0;
      const double s = r % 7 == 3 ? 0x1p70 : (r % 7 == 5 ? 0x1p-70 : 1.0);
      ray.d = ray.d / s;
      const double tmin = (r % 3 == 0 ? 2.0 : 0.0) * s, tmax0 = r % 5 == 0 ? 8.0 * s : 1e300;
      const Answers a8 = answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery q, auto&& leaf) {
        bvh8_traverse(w8, ray, tmin, tm, mode, q, leaf);
      });
      const Answers a4 = answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery q, auto&& leaf) {
        bvh4_traverse(w4, ray, tmin, tm, mode, q, leaf);
      });
      const Answers ab = answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery q, auto&& leaf) {
        bvh_traverse(bin, ray, tmin, tm, mode, q, leaf);
      });
      ASSERT_EQ(a8, a4) << "ray " << r;
      ASSERT_EQ(a8, ab) << "ray " << r;
      ASSERT_EQ(a8, brute(soup, ray, tmin, tmax0)) << "ray " << r;
      hit_rays += a8.any;
    }
    EXPECT_GT(hit_rays, 120);
  }
}

TEST(Bvh8, ConservativeVisitsBoxesTouchedAtACornerByNonFloatOrigins) {
  // As the Bvh4 test (bvh_test.cpp): rays through a corner of a primitive's float box exactly, the
  // origin a double that is no float, the exact segment touching the box at one point; huge and tiny
  // scalings of the same ray take the double path. All hits and closest hit pruned at the touch
  // must visit the primitive.
  REQUIRE_AVX2();
  const Soup soup = random_soup(2000, 6);
  const Bvh8 wide = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  int missed = 0, total = 0;
  for (int r = 0; r < 2500; ++r) {
    const std::uint32_t p = rng() % soup.tris.size();
    const BvhBox& b = soup.boxes[p];
    const Vec3<double> corner{double(rng() & 1 ? b.hi[0] : b.lo[0]), double(rng() & 1 ? b.hi[1] : b.lo[1]),
                              double(rng() & 1 ? b.hi[2] : b.lo[2])};
    Vec3<double> d;
    for (int k = 0; k < 3; ++k) d[k] = std::ldexp(std::round(std::ldexp(u(rng), 40)), -40);
    if (r % 4 == 0) d[r / 4 % 3] = r % 8 ? 0.0 : -0.0;  // axis-parallel: origin on that axis's slab planes
    if (is_zero(d)) continue;
    // The touch at t = T: T = 1024 makes distances large, so that the widening of the float
    // distances (not only the origin's bounds) is needed.
    const double T = r % 3 == 2 ? 1024.0 : 1.0;
    const double s = r % 10 == 7 ? 0x1p-80 : 1.0;  // tiny d: the double path, t scaled by 2^80
    const Ray<double> ray{corner - d * T, d * s};
    if (ray.o + d * T != corner) continue;  // o not exact: no exact touch
    for (double tmin : {0.0, T / s, -T / s})
      for (double tmax0 : {T / s, 1e300}) {
        ++total;
        bool seen = false, seen_closest = false;
        double tm = tmax0, tc = T / s;
        bvh8_traverse(wide, ray, tmin, tm, BvhTraversal::conservative, BvhQuery::all, [&](std::uint32_t i) {
          seen |= i == p;
          return false;
        });
        bvh8_traverse(wide, ray, tmin, tc, BvhTraversal::conservative, BvhQuery::closest, [&](std::uint32_t i) {
          seen_closest |= i == p;
          return false;
        });
        missed += !seen + !seen_closest;
      }
  }
  EXPECT_GT(total, 9000);
  EXPECT_EQ(missed, 0);
}

TEST(BvhWide, ConservativeVisitsBoxesTouchedAtACornerAtEveryDistance) {
  // The origin is (0, 0, 0), a float: its bounds give the node test no slack, so only the directed
  // reciprocals (make_bvh4_ray) keep a box touched at one corner from being culled by the float
  // distances' own roundings. d = corner 2^-k exactly, so the exact segment touches the corner at
  // t = 2^k; k spans tiny and huge distances. Both widths, full nodes; all hits and closest hit
  // pruned at the touch must visit the primitive. (Without the 1 -/+ 2^-22 of the reciprocals this
  // test misses hundreds of corners.)
  const Soup soup = random_soup(3000, 21);
  const Bvh bin = build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4});
  const Bvh4 w4 = collapse_bvh4(Bvh(bin), soup.boxes);
  const Bvh8 w8 = cpu_has_avx2() ? collapse_bvh8(Bvh(bin), soup.boxes) : Bvh8{};
  std::mt19937 rng(22);
  int missed4 = 0, missed8 = 0, total = 0;
  for (int r = 0; r < 6000; ++r) {
    const std::uint32_t p = rng() % soup.tris.size();
    const BvhBox& b = soup.boxes[p];
    const Vec3<double> corner{double(rng() & 1 ? b.hi[0] : b.lo[0]), double(rng() & 1 ? b.hi[1] : b.lo[1]),
                              double(rng() & 1 ? b.hi[2] : b.lo[2])};
    if (is_zero(corner)) continue;
    const int k = int(rng() % 121) - 60;  // t = 2^k, from 2^-60 to 2^60 (d within the float path's range)
    const Ray<double> ray{{0, 0, 0}, corner * std::ldexp(1.0, -k)};
    const double T = std::ldexp(1.0, k);
    for (double tmax0 : {T, 1e300}) {
      ++total;
      auto visits = [&](const auto& tree, BvhQuery q) {
        bool seen = false;
        double tm = q == BvhQuery::closest ? T : tmax0;
        wide_traverse(tree, ray, 0.0, tm, BvhTraversal::conservative, q, [&](std::uint32_t i) {
          seen |= i == p;
          return false;
        });
        return seen;
      };
      missed4 += !visits(w4, BvhQuery::all) + !visits(w4, BvhQuery::closest);
      if (cpu_has_avx2()) missed8 += !visits(w8, BvhQuery::all) + !visits(w8, BvhQuery::closest);
    }
  }
  EXPECT_GT(total, 11000);
  EXPECT_EQ(missed4, 0);
  EXPECT_EQ(missed8, 0);
}

TEST(Bvh8, LeafRangesAreWholeLeavesAndAnyStops) {
  REQUIRE_AVX2();
  const Soup soup = random_soup(1500, 12);
  const Bvh8 w8 = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  const Bvh4 w4 = collapse_bvh4(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  // Leaf ranges of the trees: every range handed to the callback is one of them.
  auto ranges = [](const auto& w) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    for (const auto& n : w.nodes)
      for (int i = 0; i < int(sizeof n.count); ++i)
        if ((n.valid >> i & 1) && n.count[i]) out.push_back({n.child[i], n.count[i]});
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto r8 = ranges(w8), r4 = ranges(w4);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  int calls = 0;
  for (int r = 0; r < 200; ++r) {
    const Ray<double> ray{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
    double tm = 1e300;
    auto check = [&](const auto& known) {
      return [&](std::uint32_t first, std::uint32_t count) {
        ++calls;
        EXPECT_TRUE(std::binary_search(known.begin(), known.end(), std::pair{first, count}));
        return false;
      };
    };
    bvh8_traverse_leaves(w8, ray, 0.0, tm, BvhTraversal::conservative, BvhQuery::all, check(r8));
    bvh4_traverse_leaves(w4, ray, 0.0, tm, BvhTraversal::conservative, BvhQuery::all, check(r4));
    // Any hit: the callback's true at the second leaf ends the traversal.
    int n8 = 0, n4 = 0;
    bvh8_traverse_leaves(w8, ray, 0.0, tm, BvhTraversal::standard, BvhQuery::any,
                         [&](std::uint32_t, std::uint32_t) { return ++n8 == 2; });
    bvh4_traverse_leaves(w4, ray, 0.0, tm, BvhTraversal::standard, BvhQuery::any,
                         [&](std::uint32_t, std::uint32_t) { return ++n4 == 2; });
    EXPECT_LE(n8, 2);
    EXPECT_LE(n4, 2);
  }
  EXPECT_GT(calls, 400);
}

TEST(Bvh8, EmptyAndInvalidRays) {
  REQUIRE_AVX2();
  const Bvh8 empty = collapse_bvh8(build_bvh({}, {}), {});
  EXPECT_TRUE(empty.empty());
  double tmax = 1.0;
  bvh8_traverse(empty, Ray<double>{{0, 0, 0}, {1, 0, 0}}, 0.0, tmax, BvhTraversal::standard, BvhQuery::closest,
                [](std::uint32_t) { ADD_FAILURE(); return false; });
  const Soup soup = random_soup(100, 9);
  const Bvh8 w = collapse_bvh8(build_bvh(soup.boxes, soup.centers), soup.boxes);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const Ray<double>& r : {Ray<double>{{nan, 0, 0}, {1, 0, 0}}, Ray<double>{{0, 0, 0}, {inf, 0, 0}},
                               Ray<double>{{0, 0, 0}, {0, 0, 0}}, Ray<double>{{1e308, -1e308, 0}, {1e-308, 1, 0}},
                               Ray<double>{{0, 0, 0}, {nan, 1, 0}}})
    for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative})
      for (double tm : {inf, nan}) {
        bvh8_traverse(w, r, 0.0, tm, mode, BvhQuery::closest, [](std::uint32_t) { return false; });
        bvh8_traverse(w, r, 0.0, tm, mode, BvhQuery::any, [](std::uint32_t) { return false; });
      }
}

TEST(BvhSimd, PathChoiceAndEnvironment) {
  EXPECT_EQ(bvh_simd_path(BvhSimd::sse4), BvhSimd::sse4);
  EXPECT_EQ(bvh_simd_path(BvhSimd::avx2), cpu_has_avx2() ? BvhSimd::avx2 : BvhSimd::sse4);
  const char* old = std::getenv("RAYPROOF_SIMD");
  const std::string saved = old ? old : "";
  ::setenv("RAYPROOF_SIMD", "sse", 1);
  EXPECT_EQ(bvh_simd_path(), BvhSimd::sse4);
  EXPECT_EQ(bvh_simd_path(BvhSimd::avx2), cpu_has_avx2() ? BvhSimd::avx2 : BvhSimd::sse4);  // explicit wins
  ::setenv("RAYPROOF_SIMD", "scalar", 1);
  EXPECT_EQ(bvh_simd_path(), BvhSimd::sse4);
  ::setenv("RAYPROOF_SIMD", "auto", 1);
  EXPECT_EQ(bvh_simd_path(), cpu_has_avx2() ? BvhSimd::avx2 : BvhSimd::sse4);
  ::setenv("RAYPROOF_SIMD", "avx512", 1);
  try {
    (void)bvh_simd_path();
    ADD_FAILURE() << "no error for RAYPROOF_SIMD=avx512";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "RAYPROOF_SIMD='avx512': expected auto, avx2, sse, scalar or off");
  }
  if (old) {
    ::setenv("RAYPROOF_SIMD", saved.c_str(), 1);
  } else {
    ::unsetenv("RAYPROOF_SIMD");
  }
}

// ---- Through scene::Accel: every compiled method ----

namespace {
using namespace rayproof::scene;

SceneMethod method(const std::string& name) { return find_scene_method(name, registry::all_methods()); }

/// closest, any and all for every ray (and a [tmin, tmax] range on a third of them) agree between
/// the AVX2 eight-wide accel, the SSE four-wide one and, for conservative traversal, `flat` (one
/// leaf split in chunks of 255: brute force over the primitives).
void check_paths(const Scene& s, const std::vector<Ray<double>>& rays, const std::vector<std::string>& names,
                 bool with_flat, bool closest_is_first, int& crossings) {
  const Accel a8(s, {}, BvhSimd::avx2), a4(s, {}, BvhSimd::sse4);
  static const Scene none;
  const Accel flat(with_flat ? s : none, {BvhBuilder::median, 1u << 30}, BvhSimd::sse4);
  ASSERT_EQ(a8.simd(), BvhSimd::avx2);
  ASSERT_EQ(a4.simd(), BvhSimd::sse4);
  ASSERT_FALSE(a8.bvh8().empty() && a8.bvh8q().empty());  // full or compressed (RAYPROOF_BVH_NODES)
  // Compressed nodes (RAYPROOF_BVH_NODES=compressed): the two widths' decoded leaf boxes differ, so
  // standard traversal (not conservative) may visit different leaves; bvh_quantized_test compares
  // compressed with full nodes. Here they are compared under conservative traversal only.
  const bool same_leaf_boxes = a8.nodes() == BvhNodes::full && a4.nodes() == BvhNodes::full;
  for (const std::string& name : names) {
    const SceneMethod m = method(name);
    ASSERT_NE(m.fast, FastKernel::none) << name;
    const bool conservative = m.traversal == BvhTraversal::conservative;
    if (!conservative && !same_leaf_boxes) continue;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const QueryRange q = i % 3 == 1 ? QueryRange{0.25, 1.5} : QueryRange{};
      const PrimHit c8 = a8.closest(rays[i], m, q);
      const auto all8 = a8.all(rays[i], m, q);
      // All hits: a box test in float is monotone under box inclusion (rounded differences and
      // products are), so every tree visits the leaves whose own box passes: the same crossings.
      ASSERT_EQ(all8, a4.all(rays[i], m, q)) << name << " ray " << i;
      // The textbook slab test (standard) may cull a leaf box touched at one point, which a chunk
      // box of `flat` around it need not: brute force is compared under conservative traversal.
      if (with_flat && conservative) {
        ASSERT_EQ(all8, flat.all(rays[i], m, q)) << name << " ray " << i;
      }
      auto same_closest = [&](const PrimHit& other, const char* what) {
        // (With compressed nodes the same holds under conservative traversal for hostile rays, whose
        // kernel t may fall short of a box's exact entry: which boxes are that near differs.)
        if ((conservative && (same_leaf_boxes || closest_is_first)) || c8 == other)
          return ::testing::AssertionResult(c8 == other) << what;
        // Standard traversal prunes closest hit with float entry distances and a float tmax, which
        // are not widened: a crossing within a few float ulps of the best t so far may be pruned,
        // so which of two such crossings is returned depends on the visit order. Both must be real
        // crossings (in all hits), within 2^-18 relative of each other.
        auto in_all = [&](const PrimHit& h) { return std::find(all8.begin(), all8.end(), h) != all8.end(); };
        const bool near = in_all(c8) && in_all(other) && std::abs(c8.t - other.t) <= 0x1p-18 * std::abs(c8.t);
        return ::testing::AssertionResult(near) << what << ": " << c8 << " vs " << other;
      };
      ASSERT_TRUE(same_closest(a4.closest(rays[i], m, q), "sse")) << name << " ray " << i;
      if (with_flat && conservative) {
        ASSERT_TRUE(same_closest(flat.closest(rays[i], m, q), "flat")) << name << " ray " << i;
      }
      const bool any8 = a8.any(rays[i], m, q);
      ASSERT_EQ(any8, a4.any(rays[i], m, q)) << name << " ray " << i;
      if (conservative) {
        ASSERT_EQ(any8, !all8.empty()) << name << " ray " << i;
      }
      // Closest is the first of all hits under conservative traversal when the kernel's t is
      // accurate enough to order crossings the way the boxes do (not for hostile scales, where a
      // float kernel's t may underflow to 0 short of a box's exact entry).
      if (conservative && closest_is_first) {
        ASSERT_EQ(c8, all8.empty() ? (rays[i].valid() ? PrimHit{} : PrimHit{Contact::invalid}) : all8.front())
            << name << " ray " << i;
      }
      crossings += int(all8.size());
    }
  }
  // The batches take the same path.
  const SceneMethod m = method("robust");
  std::vector<PrimHit> b8(rays.size()), b4(rays.size());
  a8.closest_batch(rays, b8, m, 2);
  a4.closest_batch(rays, b4, m, 1);
  for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(b8[i], b4[i]) << i;
  std::vector<std::uint8_t> y8(rays.size()), y4(rays.size());
  a8.any_batch(rays, y8, m, 2);
  a4.any_batch(rays, y4, m, 1);
  ASSERT_EQ(y8, y4);
}

const std::vector<std::string> kAll = {"float", "double", "cramer-float", "cramer-double", "robust",
                                       "watertight-float", "watertight", "certified"};
}  // namespace

TEST(Bvh8Accel, EveryMethodAgreesAcrossPathsOnGeneratedMeshes) {
  REQUIRE_AVX2();
  ASSERT_EQ(compiled_scene_method_names(registry::all_methods()), kAll);  // a new compiled method joins this test
  Scene s = default_scene(2);  // analytic primitives too (generic kernels for them)
  add_mesh(s, bumpy_sphere(2000));
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Ray<double>> rays = leak_rays(Vec3<double>{0.01, 0.02, -0.01}, leak_targets(s.mesh, 400));
  for (int i = 0; i < 200; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  int crossings = 0;
  check_paths(s, rays, kAll, true, true, crossings);
  check_paths(s, hostile_rays(s.mesh, 22, 320), kAll, false, false, crossings);  // kernels overflow here: paths only
  EXPECT_GT(crossings, 8000);
}

TEST(Bvh8Accel, BunnyLeakRaysAgreeAcrossPathsAndDoNotLeak) {
  REQUIRE_AVX2();
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const Scene s = load_scene(path);
  const auto rays = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 1200));
  int crossings = 0;
  check_paths(s, rays, {"float", "watertight-float", "robust"}, false, true, crossings);
  // certified's exact stages are slow on vertex aims: fewer rays.
  const std::vector<Ray<double>> few(rays.begin(), rays.begin() + 200);
  check_paths(s, few, {"certified"}, false, true, crossings);
  const Accel a8(s, {}, BvhSimd::avx2);
  EXPECT_EQ(count_leaks(a8, method("robust"), rays, 1).misses, 0u);
  EXPECT_EQ(count_leaks(a8, method("certified"), few, 1).misses, 0u);
  check_paths(s, hostile_rays(s.mesh, 23, 200), {"robust"}, false, false, crossings);
  EXPECT_GT(crossings, 1200);
}
