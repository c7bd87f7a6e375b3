// Packets of eight rays (rayproof/bvh_packet.h, Accel::closest_packets / any_packets): the packet
// traversal's box test is the single-ray one lane by lane, so for all hits it visits exactly the
// leaves the single-ray traversal visits, ray by ray; through scene::Accel every compiled method
// gives the single-ray answers (class, primitive, t) on generated meshes, camera tiles, incoherent
// packets, partial packets, mixed ranges, rays out of the float range and bunny00's leak rays.
// Skipped without AVX2 (the packet path is then never taken; the SSE path runs ray by ray).
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>

#include "bvh_support.h"
#include "registry/registry.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_packet.h"
#include "scene/accel.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

#define REQUIRE_AVX2() \
  if (!cpu_has_avx2()) GTEST_SKIP() << "no AVX2 on this CPU: the packet path is never taken"

using Visits = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // leaf ranges (first, count), sorted

/// All-hits leaf visits of each ray: one at a time, and in packets of eight (lane i: rays[8p + i]).
template <class Tree>
void visits(const Tree& bvh, const std::vector<Ray<double>>& rays, const std::vector<double>& tmin,
            const std::vector<double>& tmax, BvhTraversal mode, std::vector<Visits>& single, std::vector<Visits>& packet) {
  single.assign(rays.size(), {}), packet.assign(rays.size(), {});
  for (std::size_t i = 0; i < rays.size(); ++i) {
    wide_traverse_leaves(bvh, rays[i], tmin[i], tmax[i], mode, BvhQuery::all, [&](std::uint32_t f, std::uint32_t c) {
      single[i].push_back({f, c});
      return false;
    });
    std::sort(single[i].begin(), single[i].end());
  }
  for (std::size_t p = 0; p < rays.size(); p += 8) {
    const unsigned n = unsigned(std::min<std::size_t>(8, rays.size() - p));
    Ray<double> r[8];
    double t0[8] = {}, t1[8] = {};
    for (unsigned i = 0; i < n; ++i) r[i] = rays[p + i], t0[i] = tmin[p + i], t1[i] = tmax[p + i];
    bvh8_packet_traverse_leaves(bvh, r, t0, t1, (1u << n) - 1, mode, BvhQuery::all, [&](int lane, std::uint32_t f, std::uint32_t c) {
      EXPECT_LT(unsigned(lane), n);
      packet[p + std::size_t(lane)].push_back({f, c});
      return false;
    });
  }
  for (auto& v : packet) std::sort(v.begin(), v.end());
}

TEST(BvhPacket, AllHitsVisitTheSingleRayLeavesAndCornerTouches) {
  // Rays through a corner of a primitive's float box exactly (origins that are no floats; the
  // segment touches the box at one point), as bvh8_test's conservative test: under conservative
  // traversal every lane must visit that primitive's leaf, and in both modes every lane must visit
  // exactly the leaves the single-ray traversal visits. Packets mix these with random rays, huge
  // and tiny scalings (the double path) and +-0 direction components.
  REQUIRE_AVX2();
  const test::Soup soup = test::random_soup(2000, 6, true);
  const Bvh8 wide = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1), w(-12, 12);
  std::vector<Ray<double>> rays;
  std::vector<double> tmin, tmax;
  std::vector<std::uint32_t> touched;  // the primitive a ray touches, or ~0u
  for (int r = 0; r < 1600; ++r) {
    if (r % 5 == 4) {  // an incoherent ray
      rays.push_back({{w(rng), w(rng), w(rng)}, {u(rng), u(rng), u(rng)}});
      tmin.push_back(r % 3 ? 0.0 : 2.0), tmax.push_back(r % 7 ? 1e300 : 9.0), touched.push_back(~0u);
      continue;
    }
    const std::uint32_t p = rng() % soup.tris.size();
    const BvhBox& b = soup.boxes[p];
    const Vec3<double> corner{double(rng() & 1 ? b.hi[0] : b.lo[0]), double(rng() & 1 ? b.hi[1] : b.lo[1]),
                              double(rng() & 1 ? b.hi[2] : b.lo[2])};
    Vec3<double> d;
    for (int k = 0; k < 3; ++k) d[k] = std::ldexp(std::round(std::ldexp(u(rng), 40)), -40);
    if (r % 4 == 0) d[r / 4 % 3] = r % 8 ? 0.0 : -0.0;
    if (is_zero(d)) continue;
    const double T = r % 3 == 2 ? 1024.0 : 1.0;
    const double s = r % 10 == 7 ? 0x1p-80 : 1.0;  // tiny d: the double path
    const Ray<double> ray{corner - d * T, d * s};
    if (ray.o + d * T != corner) continue;
    rays.push_back(ray), touched.push_back(p);
    tmin.push_back(r % 2 ? 0.0 : T / s), tmax.push_back(r % 6 < 3 ? T / s : 1e300);
  }
  // The same rays again ordered by the signs of d (-0 counts as negative, as 1/d does), so that
  // most packets have one sign per axis: the uniform box test (bvh_packet.h, Packet8Regs).
  const std::size_t n = rays.size();
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  auto octant = [&](std::size_t i) {
    return int(std::signbit(rays[i].d.x)) | int(std::signbit(rays[i].d.y)) << 1 | int(std::signbit(rays[i].d.z)) << 2;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return octant(a) < octant(b); });
  for (std::size_t i : order) rays.push_back(rays[i]), tmin.push_back(tmin[i]), tmax.push_back(tmax[i]), touched.push_back(touched[i]);
  std::vector<Visits> single, packet;
  int missed = 0, touches = 0;
  // Full nodes, then the same tree's compressed nodes (their decoded planes; the leaves keep their
  // slots, so the touched primitive is found the same way).
  const std::optional<Bvh8Q> quantized = quantize_wide(wide);
  ASSERT_TRUE(quantized.has_value());
  for (int kind = 0; kind < 4; ++kind) {
    const BvhTraversal mode = kind % 2 ? BvhTraversal::standard : BvhTraversal::conservative;
    if (kind < 2) visits(wide, rays, tmin, tmax, mode, single, packet);
    else visits(*quantized, rays, tmin, tmax, mode, single, packet);
    std::size_t total = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(packet[i], single[i]) << "ray " << i << (mode == BvhTraversal::conservative ? " conservative" : " standard")
                                      << (kind < 2 ? " full" : " compressed");
      total += packet[i].size();
      if (mode != BvhTraversal::conservative || touched[i] == ~0u) continue;
      ++touches;
      bool seen = false;
      for (const auto& [f, c] : packet[i])
        for (std::uint32_t j = f; j < f + c; ++j) seen |= wide.prim_ids[j] == touched[i];
      missed += !seen;
    }
    EXPECT_GT(total, rays.size());  // the rays do reach leaves
  }
  EXPECT_GT(touches, 4000);
  EXPECT_EQ(missed, 0);
}

TEST(BvhPacket, AnyStopsOnlyItsLaneAndClosestReadsTmaxAgain) {
  // Any hit: a lane whose leaf returns true gets no more leaves; the other lanes go on. Closest
  // hit: lowering tmax[lane] to 0 after the first leaf ends that lane (no leaf entered beyond it).
  REQUIRE_AVX2();
  const test::Soup soup = test::random_soup(3000, 9);
  const Bvh8 wide = collapse_bvh8(build_bvh(soup.boxes, soup.centers, {BvhBuilder::sah, 4}), soup.boxes);
  Ray<double> r[8];
  double t0[8], t1[8];
  for (int i = 0; i < 8; ++i) r[i] = {{-15.0, 0.3 * i - 1.0, 0.2 * i}, {1.0, 0.01 * i, -0.02 * i}}, t0[i] = 0, t1[i] = 1e300;
  int calls[8] = {};
  bvh8_packet_traverse_leaves(wide, r, t0, t1, 0xffu, BvhTraversal::conservative, BvhQuery::any,
                              [&](int lane, std::uint32_t, std::uint32_t) { return ++calls[lane], lane % 2 == 0; });
  int all_calls[8] = {};
  bvh8_packet_traverse_leaves(wide, r, t0, t1, 0xffu, BvhTraversal::conservative, BvhQuery::all,
                              [&](int lane, std::uint32_t, std::uint32_t) { return ++all_calls[lane], false; });
  for (int i = 0; i < 8; ++i) {
    ASSERT_GT(all_calls[i], 2) << i;  // the rays cross the soup
    EXPECT_EQ(calls[i], i % 2 == 0 ? 1 : all_calls[i]) << i;
  }
  int closest_calls[8] = {};
  bvh8_packet_traverse_leaves(wide, r, t0, t1, 0x0fu, BvhTraversal::conservative, BvhQuery::closest,
                              [&](int lane, std::uint32_t, std::uint32_t) {
                                ++closest_calls[lane];
                                t1[lane] = -1.0;  // every later entry lies beyond
                                return false;
                              });
  for (int i = 0; i < 8; ++i) EXPECT_EQ(closest_calls[i], i < 4 ? 1 : 0) << i;  // lanes 4-7 not live
}

TEST(BvhPacket, TileOrderIsAPermutationInTiles) {
  const auto o = packet_tile_order(6, 3);
  const std::vector<std::uint32_t> want = {0, 1, 2, 3, 6, 7, 8, 9, 4, 5, 10, 11, 12, 13, 14, 15, 16, 17};
  EXPECT_EQ(o, want);
  EXPECT_TRUE(packet_tile_order(0, 5).empty());
  auto big = packet_tile_order(37, 11);
  std::sort(big.begin(), big.end());
  for (std::uint32_t i = 0; i < big.size(); ++i) ASSERT_EQ(big[i], i);
  EXPECT_EQ(big.size(), 37u * 11u);
}

// ---- Through scene::Accel: every compiled method ----

SceneMethod method(const std::string& name) { return find_scene_method(name, registry::all_methods()); }

/// Packets against single rays on the same accel, for every method of `names`: any hit equal;
/// closest hit equal under conservative traversal, and under standard traversal equal or another
/// real crossing within 2^-18 relative of it (float pruning depends on the visit order; see
/// Accel::closest_packets). Ranges: one per ray (`ranges`), as the packets get them.
void check_packets(const Accel& a, const std::vector<Ray<double>>& rays, const std::vector<QueryRange>& ranges,
                   const std::vector<std::string>& names, int& hits) {
  for (const std::string& name : names) {
    const SceneMethod m = method(name);
    const bool conservative = m.traversal == BvhTraversal::conservative;
    std::vector<PrimHit> c(rays.size());
    std::vector<std::uint8_t> y(rays.size(), 7);
    a.closest_packets(rays, ranges, c, m, 1);
    a.any_packets(rays, ranges, y, m, 1);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const QueryRange q = ranges.size() > 1 ? ranges[i] : ranges.empty() ? QueryRange{} : ranges[0];
      const PrimHit want = a.closest(rays[i], m, q);
      if (conservative || !(c[i] == want)) {
        if (conservative || want.prim == PrimHit::kNoPrim || c[i].prim == PrimHit::kNoPrim) {
          ASSERT_EQ(c[i], want) << name << " ray " << i;
        } else {
          const auto all = a.all(rays[i], m, q);
          auto in_all = [&](const PrimHit& h) { return std::find(all.begin(), all.end(), h) != all.end(); };
          ASSERT_TRUE(in_all(c[i]) && std::abs(c[i].t - want.t) <= 0x1p-18 * std::abs(want.t))
              << name << " ray " << i << ": " << c[i] << " vs " << want;
        }
      }
      ASSERT_EQ(y[i], std::uint8_t(a.any(rays[i], m, q))) << name << " ray " << i;
      hits += c[i].prim != PrimHit::kNoPrim;
    }
  }
}

/// Rays out of the float path's range, invalid rays and axis-parallel ones among ordinary ones.
std::vector<Ray<double>> odd_rays(const mesh::Mesh& m, unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Ray<double>> out;
  for (int i = 0; i < n; ++i) {
    const Vec3<double>& v = m.vertices[rng() % m.vertices.size()];
    Ray<double> r{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    switch (i % 6) {
      case 0: r.o = {v.x, v.y, -3.0}, r.d = {-0.0, 0.0, 1.0}; break;  // through a vertex, axis-parallel
      case 1: r.o = v * 0x1p70, r.d = (v - r.o) * 0x1p-3; break;       // huge origin: double path
      case 2: r.d = r.d * 0x1p-70; break;                              // tiny d: double path
      case 3: r.d = {std::nan(""), 1, 0}; break;                       // invalid
      default: r.d = v - r.o; break;                                   // at a vertex
    }
    out.push_back(r);
  }
  return out;
}

const std::vector<std::string> kAll = {"float", "double", "cramer-float", "cramer-double", "robust",
                                       "watertight-float", "watertight", "certified"};

TEST(BvhPacketAccel, EveryMethodGivesTheSingleRayAnswers) {
  REQUIRE_AVX2();
  ASSERT_EQ(compiled_scene_method_names(registry::all_methods()), kAll);  // a new compiled method joins this test
  Scene s = default_scene(2);  // analytic primitives too (generic kernels for them)
  add_mesh(s, bumpy_sphere(2000));
  const Accel a(s, {}, BvhSimd::avx2);
  ASSERT_EQ(a.simd(), BvhSimd::avx2);
  // Camera tiles of 4x2 (a 30x14 image: tiles cut at the right edge, so packets straddle tiles).
  const Camera cam = default_camera(s, 30, 14);
  std::vector<Ray<double>> rays;
  for (std::uint32_t p : packet_tile_order(cam.width(), cam.height()))
    rays.push_back(cam.generate(int(p % std::uint32_t(cam.width())), int(p / std::uint32_t(cam.width()))));
  // Incoherent packets: leak rays from inside (towards vertices and edge midpoints) and random rays.
  const auto leak = leak_rays(Vec3<double>{0.01, 0.02, -0.01}, leak_targets(s.mesh, 240));
  rays.insert(rays.end(), leak.begin(), leak.end());
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 160; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  const auto odd = odd_rays(s.mesh, 32, 96);
  rays.insert(rays.end(), odd.begin(), odd.end());
  rays.resize(rays.size() - 3);  // a partial last packet
  ASSERT_NE(rays.size() % 8, 0u);
  // Mixed ranges inside packets, and one range for all.
  std::vector<QueryRange> mixed(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    mixed[i] = i % 5 == 1 ? QueryRange{0.25, 1.5} : i % 5 == 3 ? QueryRange{0.0, 0.9} : QueryRange{};
  int hits = 0;
  check_packets(a, rays, mixed, kAll, hits);
  check_packets(a, rays, {}, {"float", "robust", "certified"}, hits);
  EXPECT_GT(hits, 4000);
  // The SSE path answers packets ray by ray: the same.
  const Accel a4(s, {}, BvhSimd::sse4);
  check_packets(a4, rays, mixed, {"float", "robust"}, hits);
  // A packet with fewer than eight live rays (invalid ones are not traversed).
  std::vector<Ray<double>> few(rays.begin(), rays.begin() + 8);
  for (int i : {0, 3, 4, 6}) few[std::size_t(i)].d = {0, 0, 0};
  check_packets(a, few, {}, kAll, hits);
  for (int i = 0; i < 8; ++i) few.resize(std::size_t(8 - i)), check_packets(a, few, {}, {"robust"}, hits);
  // The leaves' float screens (leaf_simd.h; off by default on AVX2) use per-ray constants that a
  // lane's kernel gets when it is prepared (at its first leaf): the same answers with them on.
  scene::detail::set_robust_screen_avx2(true), scene::detail::set_certified_screen(true);
  const std::vector<Ray<double>> some(rays.begin(), rays.begin() + 400);
  check_packets(a, some, mixed, {"robust", "certified"}, hits);
  scene::detail::set_robust_screen_avx2(false), scene::detail::set_certified_screen(false);
}

TEST(BvhPacketAccel, BunnyLeakRaysAndCameraTiles) {
  REQUIRE_AVX2();
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const Scene s = load_scene(path);
  const Accel a(s, {BvhBuilder::sah, 4}, BvhSimd::avx2);
  const auto leak = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 1200));
  int hits = 0;
  check_packets(a, leak, {}, {"float", "watertight-float", "robust"}, hits);
  const std::vector<Ray<double>> few(leak.begin(), leak.begin() + 200);  // certified's exact stages are slow here
  check_packets(a, few, {}, {"certified"}, hits);
  // No leak through packets: every leak ray from inside the closed mesh hits.
  std::vector<PrimHit> c(leak.size());
  a.closest_packets(leak, {}, c, method("robust"), 1);
  EXPECT_EQ(std::count_if(c.begin(), c.end(), [](const PrimHit& h) { return h.prim == PrimHit::kNoPrim; }), 0);
  const Camera cam = default_camera(s, 48, 32);
  std::vector<Ray<double>> tiles;
  for (std::uint32_t p : packet_tile_order(cam.width(), cam.height()))
    tiles.push_back(cam.generate(int(p % std::uint32_t(cam.width())), int(p / std::uint32_t(cam.width()))));
  check_packets(a, tiles, {}, {"float", "robust", "certified"}, hits);
  EXPECT_GT(hits, 3000);
}

}  // namespace
