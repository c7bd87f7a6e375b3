// SIMD leaves (src/scene/leaf_simd.h): the group kernels against the
// per-primitive kernels lane by lane (class, t, b1, b2 bit for bit) on hostile triangle families,
// the leaf alignment, and whole queries (closest, any, all) through the groups against the same
// queries slot by slot, on the AVX2, SSE and scalar paths.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <set>

#include "registry/registry.h"
#include "rayproof/certified/intersect.h"
#include "scene/accel.h"
#include "scene/kernels.h"
#include "scene/leaf_simd.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;
using namespace rayproof::scene::detail;

namespace {

struct ForceSimd {
  explicit ForceSimd(LeafSimd s) { force_leaf_simd(s); }
  ~ForceSimd() { unforce_leaf_simd(); }
  ForceSimd(const ForceSimd&) = delete;
  ForceSimd& operator=(const ForceSimd&) = delete;
};

bool cpu_avx2() {
  ForceSimd f(LeafSimd::avx2);
  return leaf_simd() == LeafSimd::avx2;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

SceneMethod method(const std::string& name) { return find_scene_method(name, registry::all_methods()); }

/// Rays and triangles that hit the kernels' special cases: integer grids (rays through edges and
/// vertices exactly), degenerate, parallel and coplanar triangles, non-finite vertices, and huge,
/// tiny and random coordinates.
struct Family {
  std::mt19937 rng;
  explicit Family(unsigned seed) : rng(seed) {}
  float uni(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
  int small() { return int(rng() % 5) - 2; }

  Ray<double> ray(int kind) {
    switch (kind % 4) {
      case 0:  // integer origin and direction: exact hits on integer-grid edges and vertices
        return {{double(small()), double(small()), -4.0}, {double(small()), double(small()), double(1 + rng() % 3)}};
      case 1:  // in the plane z = 0 (coplanar with kind 3's triangles)
        return {{double(uni(-2, 2)), double(uni(-2, 2)), 0.0}, {double(uni(-1, 1)), double(uni(-1, 1)), 0.0}};
      case 2: {  // huge or tiny scale
        const double s = rng() % 2 ? 1e30 : 1e-30;
        return {{s * uni(-1, 1), s * uni(-1, 1), -s}, {uni(-1, 1), uni(-1, 1), 1.0}};
      }
      default:
        return {{uni(-3, 3), uni(-3, 3), uni(-3, 3)}, {uni(-1, 1), uni(-1, 1), uni(-1, 1)}};
    }
  }
  Triangle<float> triangle(int kind, const Ray<double>& r) {
    auto grid = [&] { return Vec3<float>{float(small()), float(small()), float(small())}; };
    auto near = [&](float s) {
      const float t = uni(0, 3);
      return Vec3<float>{float(r.o.x + t * r.d.x) + s * uni(-1, 1), float(r.o.y + t * r.d.y) + s * uni(-1, 1),
                         float(r.o.z + t * r.d.z) + s * uni(-1, 1)};
    };
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    switch (rng() % 10) {
      case 0: case 1: return {grid(), grid(), grid()};
      case 2: {  // degenerate: repeated or collinear vertices
        const Vec3<float> a = grid(), b = grid();
        return rng() % 2 ? Triangle<float>{a, b, b} : Triangle<float>{a, b, a + (b - a) * 2.0f};
      }
      case 3: {  // in z = 0 (coplanar with kind-1 rays) or z = 1 (parallel to them)
        const float z = float(rng() % 2);
        return {{uni(-2, 2), uni(-2, 2), z}, {uni(-2, 2), uni(-2, 2), z}, {uni(-2, 2), uni(-2, 2), z}};
      }
      case 4: {  // a non-finite vertex
        Triangle<float> t{grid(), grid(), grid()};
        t.p1.y = rng() % 2 ? nan : -inf;
        return t;
      }
      case 5: {  // huge or tiny, around the ray
        const float s = kind % 4 == 2 ? float(std::abs(r.o.z)) : (rng() % 2 ? 1e30f : 1e-30f);
        return {near(s), near(s), near(s)};
      }
      default: return {near(0.5f), near(0.5f), near(0.5f)};
    }
  }
};

/// A group of the triangles `t` (lanes past n are padding), tagged as the Accel tags them.
TriGroup make_group(const Triangle<float>* t, int n) {
  TriGroup g{};
  for (int i = 0; i < kLanes; ++i) {
    const Triangle<float> x = i < n ? t[i] : Triangle<float>{};
    const Vec3<float> p[3] = {x.p0, x.p1, x.p2};
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) g.p[v][a][i] = p[v][a];
    g.tag[i] = i < n ? triangle_lane_tag(x, std::uint32_t(i)) : kPadLane;
  }
  return g;
}

}  // namespace

TEST(LeafSimd, RobustLanesMatchTheScalarKernelBitForBit) {
  if (!cpu_avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const Scene empty;
  const Method* robust = registry::all_methods().find("robust");
  ASSERT_NE(robust, nullptr);
  CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0, robust};
  Family f(7);
  int hits = 0, special = 0, dead = 0, edges = 0;
  for (int r = 0; r < 10000; ++r) {
    const Ray<double> ray = f.ray(r);
    k.prepare(ray), k.leaf_ready();
    ASSERT_TRUE(k.ray_ok);
    Triangle<float> t[kLanes];
    const int n = 1 + int(f.rng() % kLanes);  // padded groups too
    for (int i = 0; i < n; ++i) t[i] = f.triangle(r, ray);
    const TriGroup g = make_group(t, n);
    unsigned live = 0;
    for (int i = 0; i < n; ++i)
      if (g.tag[i] & kDeadLane) {
        Crossing c[2];
        EXPECT_EQ(k.triangle_crossings(t[i], c), 0) << "a dead lane has a crossing, ray " << r;
        ++dead;
      } else {
        live |= 1u << i;
      }
    RobustLanes out;
    robust_group_avx2(k.lane_ray, g, live, out);
    EXPECT_EQ((out.hit | out.special) & ~live, 0u);
    EXPECT_EQ(out.hit & out.special, 0u);
    for (int i = 0; i < n; ++i) {
      if (!(live >> i & 1)) continue;
      Crossing c[2];
      const int m = k.triangle_crossings(t[i], c);
      if (out.special >> i & 1) {
        ++special;  // the scalar front door decides these lanes: d . n = 0, or bounded zeros undecided
        const Vec3<double> p0 = t[i].p0.cast<double>(), nrm = cross(t[i].p1.cast<double>() - p0, t[i].p2.cast<double>() - p0);
        EXPECT_TRUE(dot(ray.d.cast<float>().cast<double>(), nrm) == 0.0 ||
                    intersect_watertight(*k.wr_robust, t[i]).contact == Contact::parallel)
            << "ray " << r << " lane " << i;
      } else if (out.hit >> i & 1) {
        ++hits;
        ASSERT_EQ(m, 1) << "ray " << r << " lane " << i;
        EXPECT_EQ(c[0].contact, Contact(out.contact[i])) << "ray " << r << " lane " << i;
        EXPECT_TRUE(same_bits(c[0].t, double(out.t[i]))) << c[0].t << " " << out.t[i];
        EXPECT_TRUE(same_bits(c[0].b1, double(out.b1[i])) && same_bits(c[0].b2, double(out.b2[i])));
        edges += c[0].contact != Contact::interior;
      } else {
        EXPECT_EQ(m, 0) << "ray " << r << " lane " << i << ": the lanes missed a " << to_string(c[0].contact);
      }
    }
  }
  // The families reach every case.
  EXPECT_GT(hits, 400);
  EXPECT_GT(edges, 50);
  EXPECT_GT(special, 50);
  EXPECT_GT(dead, 200);
}

namespace {

/// A ray from a random origin at `scale` through a point of triangle `t` that lies on an edge
/// (or at a vertex, or just off either by a few ulps), so that one or two of the edge functions
/// are zero or nearly so and their float and double values can differ in sign.
Ray<double> grazing_ray(std::mt19937& rng, const Triangle<float>& t, double scale) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3<double> p[3] = {t.p0.cast<double>(), t.p1.cast<double>(), t.p2.cast<double>()};
  const int i = int(rng() % 3), j = (i + 1 + int(rng() % 2)) % 3;
  const double s = rng() % 3 == 0 ? double(rng() % 2) : std::uniform_real_distribution<double>(0, 1)(rng);
  Vec3<double> target = p[i] + (p[j] - p[i]) * s;
  for (int k = 0; k < 3; ++k)  // a few ulps off, or exactly on
    for (int n = int(rng() % 4); n > 0; --n) target[k] = std::nextafter(target[k], rng() % 2 ? 1e300 : -1e300);
  const Vec3<double> o = target + Vec3<double>{u(rng), u(rng), u(rng)} * scale;
  return {o, target - o};
}

}  // namespace

/// The fuzz reproducer of robust's bounded zeros (docs/methods.md): an exact vertex contact at t =
/// 7 2^36 whose double edge functions all round to 0. The scalar leaf kernel and the AVX2 lanes
/// (which hand the undecided lane to the scalar front door) must both report it, in every lane.
TEST(LeafSimd, RobustLeafKernelsKeepTheFarVertexContact) {
  const Scene empty;
  const Method* robust = registry::all_methods().find("robust");
  ASSERT_NE(robust, nullptr);
  CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0, robust};
  const Ray<double> ray{{0.0059814453125, 0.5032958984375, 0.1939697265625},
                        {-1.2434497028768806e-14, -1.0462741784067475e-12, -4.0323300254385686e-13}};
  const Triangle<float> tri{{-4.0745362639427185e-10f, 2.9103830456733704e-10f, 5.820766091346741e-11f},
                            {4.0745362639427185e-10f, 0.0f, 0.0f},
                            {0.0f, -2.3283064365386963e-10f, -1.1641532182693481e-10f}};
  k.prepare(ray), k.leaf_ready();
  ASSERT_TRUE(k.ray_ok);
  Crossing c[2];
  ASSERT_EQ(k.triangle_crossings(tri, c), 1);
  EXPECT_EQ(c[0].t, 481036337152.0);
  if (!cpu_avx2()) GTEST_SKIP() << "no AVX2 on this CPU: the scalar leaf kernel alone was checked";
  const Triangle<float> t[kLanes] = {tri, tri, tri, tri};
  const TriGroup g = make_group(t, kLanes);
  RobustLanes out;
  robust_group_avx2(k.lane_ray, g, 0xfu, out);
  EXPECT_EQ(out.hit | out.special, 0xfu) << "a lane dropped the contact";
}

TEST(LeafSimd, RobustFloatScreenDecidesOnlyTheScalarKernelsMisses) {
  // The float screen (robust_group_float_misses) against the scalar robust kernel: every lane it
  // decides has no crossing, and the double edge functions have mixed signs there (its error
  // bound's claim). Families: the hostile ones, and rays grazing an edge or a vertex at scales
  // from 2^-60 to 2^60, where float and double disagree in sign (counted: the bound is what keeps
  // the screen away from those lanes).
  const Scene empty;
  const Method* robust = registry::all_methods().find("robust");
  ASSERT_NE(robust, nullptr);
  CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0, robust};
  Family f(31);
  int decided = 0, undecided = 0, sign_traps = 0, misses = 0;
  for (int r = 0; r < 12000; ++r) {
    Triangle<float> t[kLanes];
    const int n = 1 + int(f.rng() % kLanes);
    Ray<double> ray;
    if (r % 2) {  // grazing rays, at random magnitudes (the triangle scaled with them)
      const float scale = std::ldexp(1.0f, int(f.rng() % 121) - 60);
      const Vec3<float> c{f.uni(-4, 4) * scale, f.uni(-4, 4) * scale, f.uni(-4, 4) * scale};
      for (int i = 0; i < n; ++i)
        t[i] = {c + Vec3<float>{f.uni(-1, 1), f.uni(-1, 1), f.uni(-1, 1)} * scale,
                c + Vec3<float>{f.uni(-1, 1), f.uni(-1, 1), f.uni(-1, 1)} * scale,
                c + Vec3<float>{f.uni(-1, 1), f.uni(-1, 1), f.uni(-1, 1)} * scale};
      ray = grazing_ray(f.rng, t[f.rng() % unsigned(n)], double(scale) * (f.rng() % 2 ? 1 : 1000));
    } else {
      ray = f.ray(r / 2);
      for (int i = 0; i < n; ++i) t[i] = f.triangle(r / 2, ray);
    }
    k.prepare(ray), k.leaf_ready(), finish_lane_ray(k.lane_ray);  // the screen's constants, whatever the path
    if (!k.ray_ok) continue;
    const TriGroup g = make_group(t, n);
    unsigned live = 0;
    for (int i = 0; i < n; ++i) live |= unsigned(!(g.tag[i] & kDeadLane)) << i;
    const unsigned screened = robust_group_float_misses(k.lane_ray, g, live);
    EXPECT_EQ(screened & ~live, 0u);
    for (int i = 0; i < n; ++i) {
      if (!(live >> i & 1)) continue;
      Crossing c[2];
      const int m = k.triangle_crossings(t[i], c);
      misses += m == 0;
      // The double and float edge functions, as the kernels compute them.
      const WatertightRay<float, double>& wr = *k.wr_robust;
      const Vec3<float> p[3] = {t[i].p0, t[i].p1, t[i].p2};
      double sxd[3], syd[3];
      float sxf[3], syf[3];
      for (int v = 0; v < 3; ++v) {
        const Vec3<double> q = p[v].cast<double>() - wr.o;
        sxd[v] = wr.d[wr.kz] * q[wr.kx] - wr.d[wr.kx] * q[wr.kz], syd[v] = wr.d[wr.kz] * q[wr.ky] - wr.d[wr.ky] * q[wr.kz];
        const Vec3<float> qf = p[v] - k.ray.o;
        sxf[v] = k.ray.d[wr.kz] * qf[wr.kx] - k.ray.d[wr.kx] * qf[wr.kz];
        syf[v] = k.ray.d[wr.kz] * qf[wr.ky] - k.ray.d[wr.ky] * qf[wr.kz];
      }
      const int b_of[3] = {1, 2, 0}, c_of[3] = {2, 0, 1};  // U = e(c, b) with (b, c) = (p1, p2), ...
      bool pos = false, neg = false;
      for (int e = 0; e < 3; ++e) {
        const int b = b_of[e], cc = c_of[e];
        const double ed = sxd[cc] * syd[b] - syd[cc] * sxd[b];
        const float ef = sxf[cc] * syf[b] - syf[cc] * sxf[b];
        pos |= ed > 0, neg |= ed < 0;
        sign_traps += (ef > 0 && ed < 0) || (ef < 0 && ed > 0);
      }
      if (screened >> i & 1) {
        ++decided;
        EXPECT_EQ(m, 0) << "ray " << r << " lane " << i << ": the screen decided a " << to_string(c[0].contact);
        EXPECT_TRUE(pos && neg) << "ray " << r << " lane " << i << ": the double edge functions do not have mixed signs";
      } else {
        ++undecided;
      }
    }
  }
  EXPECT_GT(decided, 8000);
  EXPECT_GT(undecided, 3000);
  EXPECT_GT(sign_traps, 300);  // float and double edge functions of opposite signs: the cases the bound exists for
  EXPECT_GT(misses, decided);
}

TEST(LeafSimd, RobustFloatScreenIsOffForRaysOutOfItsRange) {
  // D = |d_z| + max(|d_x|, |d_y|) outside [2^-20, 2^20]: no lane is decided (the double lanes are).
  const Scene empty;
  CompiledKernel<float, TriAlgo::robust> k{empty, nullptr, 0};
  const Triangle<float> t[1] = {{{5, 0, 1}, {6, 0, 1}, {5, 1, 1}}};  // missed by the rays below
  const TriGroup g = make_group(t, 1);
  for (double s : {0x1p-22, 0x1p-20, 1.0, 0x1p20, 0x1p22}) {
    k.prepare({{0, 0, 0}, {0, 0, s}}), k.leaf_ready(), finish_lane_ray(k.lane_ray);
    const bool in_range = s >= 0x1p-20 && s <= 0x1p20;
    EXPECT_EQ(robust_group_float_misses(k.lane_ray, g, 1), in_range ? 1u : 0u) << s;
  }
  // A vertex offset beyond 2^39 / D: undecided.
  const Triangle<float> far[1] = {{{0x1p40f, 0, 1}, {0x1p40f + 0x1p20f, 0, 1}, {0x1p40f, 0x1p20f, 1}}};
  k.prepare({{0, 0, 0}, {0, 0, 1}}), k.leaf_ready(), finish_lane_ray(k.lane_ray);
  EXPECT_EQ(robust_group_float_misses(k.lane_ray, make_group(far, 1), 1), 0u);
}

TEST(LeafSimd, CertifiedFloatScreenDecidesOnlyExactMisses) {
  // certified's float screen (certified_group_float_misses) on double triangles and double rays
  // that float does not represent: every lane it decides is one certified::triangle (exact class)
  // gives no crossing. Rays graze an edge or a vertex (a few ulps of double off, or on) at scales
  // from 2^-60 to 2^60, origins near or 1000 sizes away, and the hostile families.
  Family f(37);
  std::uniform_real_distribution<double> jitter(-1, 1);
  int decided = 0, undecided = 0, misses = 0, hits = 0;
  for (int r = 0; r < 12000; ++r) {
    Triangle<double> t[kLanes];
    Triangle<float> tf[kLanes];
    const int n = 1 + int(f.rng() % kLanes);
    Ray<double> ray;
    if (r % 2) {
      const double scale = std::ldexp(1.0, int(f.rng() % 121) - 60);
      const Vec3<double> c{jitter(f.rng) * 4 * scale, jitter(f.rng) * 4 * scale, jitter(f.rng) * 4 * scale};
      auto vtx = [&] { return c + Vec3<double>{jitter(f.rng), jitter(f.rng), jitter(f.rng)} * scale; };
      for (int i = 0; i < n; ++i) t[i] = {vtx(), vtx(), vtx()};
      const Triangle<double>& aim = t[f.rng() % unsigned(n)];
      const Triangle<float> aim_f{aim.p0.cast<float>(), aim.p1.cast<float>(), aim.p2.cast<float>()};
      ray = grazing_ray(f.rng, aim_f, scale * (f.rng() % 2 ? 1 : 1000));
      // Aim at the double triangle's edge instead of its float rounding's, half the time.
      if (f.rng() % 2) {
        const double s = std::uniform_real_distribution<double>(0, 1)(f.rng);
        const Vec3<double> target = aim.p0 + (aim.p1 - aim.p0) * s;
        ray.d = target - ray.o;
      }
    } else {
      ray = f.ray(r / 2);
      if (r % 4) ray.o.x += jitter(f.rng) * 1e-9;
      for (int i = 0; i < n; ++i) {
        const Triangle<float> x = f.triangle(r / 2, ray);
        t[i] = {x.p0.cast<double>(), x.p1.cast<double>(), x.p2.cast<double>()};
        if (r % 3 == 0) t[i].p2.y += jitter(f.rng) * 1e-9;
      }
    }
    for (int i = 0; i < n; ++i) tf[i] = {t[i].p0.cast<float>(), t[i].p1.cast<float>(), t[i].p2.cast<float>()};
    RobustLaneRay lr;
    certified_lane_ray(ray, lr);
    const TriGroup g = make_group(tf, n);
    const unsigned live = (1u << n) - 1;
    const unsigned screened = certified_group_float_misses(lr, g, live);
    EXPECT_EQ(screened & ~live, 0u);
    for (int i = 0; i < n; ++i) {
      const TriangleHit<double> h = certified::intersect(ray, t[i]);  // the exact class (filters, then GMP)
      Crossing c[2];
      const int m = crossings_of(h.contact, h.t, h.t2, c);
      (m ? hits : misses)++;
      if (screened >> i & 1) {
        ++decided;
        EXPECT_EQ(m, 0) << "ray " << r << " lane " << i << ": the screen decided a " << to_string(h.contact);
      } else {
        ++undecided;
      }
    }
  }
  EXPECT_GT(decided, 8000);
  EXPECT_GT(undecided, 3000);
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, decided);
}

TEST(LeafSimd, CertifiedStageOneMissesInLanesAreTheScalarStagesMisses) {
  if (!cpu_avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  Family f(9);
  std::uniform_real_distribution<double> jitter(-1e-9, 1e-9);
  int misses = 0, others = 0;
  for (int r = 0; r < 10000; ++r) {
    Ray<double> ray = f.ray(r);
    if (r % 2) ray.o.x += jitter(f.rng);  // not float-exact
    Triangle<double> t[kLanes];
    alignas(32) double p[3][3][kLanes] = {};
    const int n = 1 + int(f.rng() % kLanes);
    for (int i = 0; i < n; ++i) {
      const Triangle<float> tf = f.triangle(r, ray);
      t[i] = {tf.p0.cast<double>(), tf.p1.cast<double>(), tf.p2.cast<double>()};
      if (r % 3 == 0) t[i].p2.y += jitter(f.rng);
      const Vec3<double> q[3] = {t[i].p0, t[i].p1, t[i].p2};
      for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) p[v][a][i] = q[v][a];
    }
    const unsigned live = (1u << n) - 1;
    const unsigned miss = certified_group_misses_avx2(ray, p, live);
    EXPECT_EQ(miss & ~live, 0u);
    for (int i = 0; i < n; ++i) {
      const bool finite = triangle_finite(t[i]);
      const auto stage1 = certified::detail::triangle_fast(ray, t[i], [] { return std::optional<Hit<double>>{}; });
      const bool scalar_miss = finite && stage1 && stage1->contact == Contact::miss;
      EXPECT_EQ(bool(miss >> i & 1), scalar_miss) << "ray " << r << " lane " << i;
      if (miss >> i & 1) {
        EXPECT_EQ(certified::triangle(ray, t[i])->contact, Contact::miss);
      }
      (miss >> i & 1) ? ++misses : ++others;
    }
  }
  EXPECT_GT(misses, 1000);
  EXPECT_GT(others, 1000);
}

TEST(LeafSimd, FloatScreenLanesMatchTheScalarScreen) {
  const Scene empty;
  CompiledKernel<float, TriAlgo::moller_trumbore> k{empty, nullptr, 0};
  Family f(8);
  int survivors = 0, screened = 0;
  for (int r = 0; r < 10000; ++r) {
    const Ray<double> ray = f.ray(r);
    k.prepare(ray), k.leaf_ready();
    Triangle<float> t[kLanes];
    const int n = 1 + int(f.rng() % kLanes);
    for (int i = 0; i < n; ++i) t[i] = f.triangle(r, ray);
    const TriGroup g = make_group(t, n);
    const unsigned live = (1u << n) - 1;
    const unsigned s = mt_group_survivors(k.ray, g, live);
    EXPECT_EQ(s & ~live, 0u);
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(bool(s >> i & 1), !mt_surely_no_crossing(k.ray, t[i])) << "ray " << r << " lane " << i;
      if (!(s >> i & 1)) {
        Crossing c[2];
        EXPECT_EQ(k.triangle_crossings(t[i], c), 0);
      }
      (s >> i & 1) ? ++survivors : ++screened;
    }
  }
  EXPECT_GT(survivors, 1000);
  EXPECT_GT(screened, 1000);
}

namespace {

/// Every leaf starts on a group boundary, each primitive is in exactly one slot, and the slots
/// outside the leaves are padding (kNoPrim, kPadLane).
void expect_aligned(const Accel& a) {
  const auto& prims = a.leaf_prims();
  const auto groups = a.leaf_groups();
  ASSERT_EQ(prims.size() % kLanes, 0u);
  ASSERT_EQ(groups.size() * kLanes, prims.size());
  std::vector<char> in_leaf(prims.size(), 0);
  // The tree of the accel's path (the other one is empty): four-wide (SSE) or eight-wide (AVX2).
  auto visit = [&](const auto& nodes) {
    for (const auto& n : nodes)
      for (int i = 0; i < int(sizeof n.count); ++i) {
        if (!(n.valid >> i & 1) || !n.count[i]) continue;
        EXPECT_EQ(n.child[i] % kLanes, 0u);
        for (std::uint32_t j = n.child[i]; j < n.child[i] + n.count[i]; ++j) {
          ASSERT_LT(j, prims.size());
          EXPECT_EQ(in_leaf[j]++, 0) << "slot " << j << " in two leaves";
        }
      }
  };
  visit(a.bvh().nodes);
  visit(a.bvh8().nodes);
  visit(a.bvh4q().nodes);  // compressed nodes (RAYPROOF_BVH_NODES=compressed)
  visit(a.bvh8q().nodes);
  std::set<std::uint32_t> ids;
  for (std::size_t j = 0; j < prims.size(); ++j) {
    const std::uint32_t tag = groups[j / kLanes].tag[j % kLanes];
    if (in_leaf[j]) {
      EXPECT_TRUE(ids.insert(prims[j].id).second);
      EXPECT_EQ(tag & kLaneIdMask, prims[j].id);
    } else {
      EXPECT_EQ(prims[j].id, PrimHit::kNoPrim);
      EXPECT_EQ(tag, kPadLane);
    }
  }
  EXPECT_EQ(ids.size(), a.primitive_count());
}

bool same_hit(const PrimHit& a, const PrimHit& b) {
  return a == b && same_bits(a.t, b.t) && same_bits(a.b1, b.b1) && same_bits(a.b2, b.b2);
}

/// closest, any and all through the groups on `path`, against the slot-by-slot queries.
void expect_same_queries(const Accel& a, const std::vector<Ray<double>>& rays, LeafSimd path, int& hits) {
  hits = 0;
  for (const char* name : {"float", "robust", "certified"}) {
    const SceneMethod m = method(name);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const QueryRange q = i % 4 == 1 ? QueryRange{0.25, 1.5} : QueryRange{};
      PrimHit ref_c;
      bool ref_any;
      std::vector<PrimHit> ref_all;
      {
        ForceSimd f(LeafSimd::off);
        ref_c = a.closest(rays[i], m, q), ref_any = a.any(rays[i], m, q), ref_all = a.all(rays[i], m, q);
      }
      ForceSimd f(path);
      const PrimHit c = a.closest(rays[i], m, q);
      ASSERT_TRUE(same_hit(c, ref_c)) << name << " " << to_string(path) << " ray " << i << ": " << c << " vs " << ref_c;
      ASSERT_EQ(a.any(rays[i], m, q), ref_any) << name << " " << to_string(path) << " ray " << i;
      const auto all = a.all(rays[i], m, q);
      ASSERT_EQ(all.size(), ref_all.size()) << name << " " << to_string(path) << " ray " << i;
      for (std::size_t j = 0; j < all.size(); ++j) ASSERT_TRUE(same_hit(all[j], ref_all[j])) << name << " ray " << i;
      hits += c.prim != PrimHit::kNoPrim;
    }
  }
}

}  // namespace

TEST(LeafSimd, QueriesThroughGroupsMatchSlotBySlotOnEveryPath) {
  // A closed mesh beside analytic primitives (their lanes go to the per-primitive kernels).
  Scene s = default_scene(1);
  add_mesh(s, bumpy_sphere(3000));
  const Accel a(s);
  expect_aligned(a);
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Ray<double>> rays = leak_rays(Vec3<double>{0.01, 0.02, -0.01}, leak_targets(s.mesh, 600));
  for (int i = 0; i < 300; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  rays.push_back({{0, 0, 0}, {0, 0, 0}});  // invalid
  rays.push_back({{1e300, 0, 0}, {-1, 0, 0}});  // out of float range
  for (LeafSimd p : {LeafSimd::scalar, LeafSimd::sse, LeafSimd::avx2}) {
    if (p == LeafSimd::avx2 && !cpu_avx2()) continue;
    int hits = 0;
    expect_same_queries(a, rays, p, hits);
    EXPECT_GT(hits, 800) << to_string(p);
  }
  // The screens' other settings (their defaults flipped): robust's float screen in front of the
  // AVX2 double lanes, certified's float screen.
  set_robust_screen_avx2(!robust_screen_avx2());
  set_certified_screen(!certified_screen());
  for (LeafSimd p : {LeafSimd::sse, LeafSimd::avx2}) {
    if (p == LeafSimd::avx2 && !cpu_avx2()) continue;
    int hits = 0;
    expect_same_queries(a, rays, p, hits);
    EXPECT_GT(hits, 800) << to_string(p);
  }
  set_robust_screen_avx2(!robust_screen_avx2());
  set_certified_screen(!certified_screen());
}

TEST(LeafSimd, SceneWithoutTrianglesGoesPerPrimitive) {
  // No triangles (no vertex array): every lane is the per-primitive kernels'.
  Scene s;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int i = 0; i < 40; ++i) {
    s.spheres.push_back({{u(rng), u(rng), u(rng)}, 0.3});
    const Vec3<double> lo{u(rng), u(rng), u(rng)};
    s.boxes.push_back({lo, lo + Vec3<double>{0.4, 0.5, 0.6}});
  }
  const Accel a(s);
  expect_aligned(a);
  std::vector<Ray<double>> rays;
  for (int i = 0; i < 200; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  for (LeafSimd p : {LeafSimd::scalar, LeafSimd::sse, LeafSimd::avx2}) {
    if (p == LeafSimd::avx2 && !cpu_avx2()) continue;
    int hits = 0;
    expect_same_queries(a, rays, p, hits);
    EXPECT_GT(hits, 50) << to_string(p);
  }
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(LeafSimd, BunnyLeakRaysMatchAndRobustDoesNotLeak) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const Scene s = load_scene(path);
  const Accel a(s);
  expect_aligned(a);
  const auto rays = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 1500));
  for (LeafSimd p : {LeafSimd::sse, LeafSimd::avx2}) {
    if (p == LeafSimd::avx2 && !cpu_avx2()) continue;
    int hits = 0;
    expect_same_queries(a, rays, p, hits);
    EXPECT_GT(hits, 2000) << to_string(p);
    ForceSimd f(p);
    EXPECT_EQ(count_leaks(a, method("robust"), rays).misses, 0u) << to_string(p);
    EXPECT_EQ(count_leaks(a, method("certified"), rays).misses, 0u) << to_string(p);
  }
}
#endif

TEST(LeafSimd, GroupLeafCostFillsTheGroupsWithTheSameAnswers) {
  // The SAH with leaves costed by their groups' lanes (BvhBuildOptions::leaf_group = 4, the
  // default) against the plain SAH (leaf_group = 1) on a generated closed mesh: fuller groups
  // (fewer slots per triangle, fewer bytes), and the same answers ray by ray.
  Scene s;
  add_mesh(s, bumpy_sphere(20000));
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Ray<double>> rays = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 300));
  const std::size_t leak = rays.size();
  ASSERT_GE(leak, 100u);
  for (int i = 0; i < 200; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  ForceSimd f(cpu_avx2() ? LeafSimd::avx2 : LeafSimd::sse);
  for (BvhSimd path : {BvhSimd::sse4, BvhSimd::automatic}) {
    BvhBuildOptions plain;
    plain.leaf_group = 1;
    const Accel a1(s, plain, path), a4(s, BvhBuildOptions{}, path);
    expect_aligned(a4);
    const double n = double(s.mesh.triangles.size());
    ASSERT_EQ(a4.primitive_count(), s.mesh.triangles.size());
    const double slots1 = double(a1.leaf_prims().size()) / n, slots4 = double(a4.leaf_prims().size()) / n;
    EXPECT_LT(slots4, 1.2) << "lanes used: " << 1 / slots4;
    EXPECT_GT(slots1 - slots4, 0.15) << slots1 << " vs " << slots4;
    EXPECT_LT(a4.group_bytes_per_primitive(), a1.group_bytes_per_primitive());
    // What the queries read: float and robust the nodes and groups, certified the nodes, records
    // and double vertices (everything held).
    EXPECT_EQ(a4.bytes_read_per_primitive(method("robust")), a4.group_bytes_per_primitive());
    EXPECT_EQ(a4.bytes_read_per_primitive(method("float")), a4.group_bytes_per_primitive());
    EXPECT_EQ(a4.bytes_read_per_primitive(method("certified")), a4.bytes_per_primitive());
    EXPECT_LT(a4.group_bytes_per_primitive(), a4.bytes_per_primitive());
    int hits = 0;
    for (const char* name : {"robust", "certified"}) {
      const SceneMethod m = method(name);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const PrimHit c1 = a1.closest(rays[i], m), c4 = a4.closest(rays[i], m);
        ASSERT_TRUE(same_hit(c1, c4)) << name << " ray " << i << ": " << c1 << " vs " << c4;
        ASSERT_EQ(a1.any(rays[i], m), a4.any(rays[i], m)) << name << " ray " << i;
        const auto all1 = a1.all(rays[i], m), all4 = a4.all(rays[i], m);
        ASSERT_EQ(all1.size(), all4.size()) << name << " ray " << i;
        for (std::size_t j = 0; j < all1.size(); ++j) ASSERT_TRUE(same_hit(all1[j], all4[j])) << name << " ray " << i;
        hits += c4.prim != PrimHit::kNoPrim;
      }
    }
    EXPECT_GT(hits, int(2 * leak + 50));  // every leak ray hits the closed mesh, and some random ones
  }
}
