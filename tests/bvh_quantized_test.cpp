// Quantized (compressed) wide nodes (BvhWideQNode, bvh_wide.h): every decoded child box contains
// the full node's float box on soups near the origin, far from it with tiny boxes, at huge and tiny
// scales and on bunny00, both widths (and a corrupted quantization is caught); the SIMD decoders
// give the floats the build checked; the traversal of compressed trees gives the full trees'
// answers ray by ray, raw (Möller–Trumbore leaves, against brute force too) and through
// scene::Accel for every compiled method, on the AVX2 eight-wide and the SSE four-wide paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "bvh_support.h"
#include "registry/registry.h"
#include "hostile_rays.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"
#include "scene/accel.h"
#include "scene/watertight.h"

using namespace rayproof;
using test::Answers, test::answers, test::brute, test::Soup;

namespace {

/// n triangles of size ~`size` at centers `center` + uniform [-spread, spread]^3 (fixed seed);
/// with `log_mixed`, each coordinate's magnitude is 10^U(-3, 20) instead (boxes of every scale).
Soup soup_at(int n, unsigned seed, double center, double spread, double size, bool log_mixed = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), ex(-3, 20);
  Soup soup;
  for (int i = 0; i < n; ++i) {
    Vec3<double> c;
    for (int k = 0; k < 3; ++k) c[k] = log_mixed ? std::copysign(std::pow(10.0, ex(rng)), u(rng)) : center + spread * u(rng);
    const double s = log_mixed ? std::abs(c[0]) * 1e-3 : size;
    auto p = [&] { return c + Vec3<double>{s * u(rng), s * u(rng), s * u(rng)}; };
    const Triangle<double> t{p(), p(), p()};
    BvhBox b;
    b.extend(t.p0), b.extend(t.p1), b.extend(t.p2);
    soup.tris.push_back(t), soup.boxes.push_back(b), soup.centers.push_back(((t.p0 + t.p1 + t.p2) / 3.0).cast<float>());
  }
  return soup;
}

template <int N>
BvhWide<N> wide_of(const Soup& s) {
  return collapse_wide<N>(build_bvh(s.boxes, s.centers, {BvhBuilder::sah, 4}), s.boxes);
}

/// Broken promises of `q` as the quantization of `full`: a decoded plane inside the float box,
/// a valid bit that is not "used and not empty", a reference or count changed.
template <int N>
int violations(const BvhWide<N>& full, const BvhWideQ<N>& q) {
  if (q.nodes.size() != full.nodes.size()) return -1;
  int bad = 0;
  for (std::size_t i = 0; i < full.nodes.size(); ++i) {
    const BvhWideNode<N>& f = full.nodes[i];
    const BvhWideQNode<N>& c = q.nodes[i];
    for (int s = 0; s < N; ++s) {
      const bool live = (f.valid >> s & 1) && !f.box(s).empty();
      bad += bool(c.valid >> s & 1) != live;
      bad += c.child[s] != f.child[s] || c.count[s] != f.count[s];
      if (!live) continue;
      const BvhBox d = c.box(s), t = f.box(s);
      for (int k = 0; k < 3; ++k) bad += !(d.lo[k] <= t.lo[k]) + !(d.hi[k] >= t.hi[k]);
    }
  }
  return bad;
}

struct ScaleRange {
  float smallest = std::numeric_limits<float>::infinity(), largest = 0;
};
template <int N>
ScaleRange scales(const BvhWideQ<N>& q) {
  ScaleRange r;
  for (const auto& n : q.nodes)
    for (float s : n.scale)
      if (s > 0) r.smallest = std::min(r.smallest, s), r.largest = std::max(r.largest, s);
  return r;
}

template <int N>
void check_containment(const Soup& soup, const char* what, ScaleRange& range) {
  const BvhWide<N> full = wide_of<N>(soup);
  const auto q = quantize_wide(full);
  ASSERT_TRUE(q.has_value()) << what;
  EXPECT_EQ(violations(full, *q), 0) << what << ", " << N << " wide";
  EXPECT_EQ(q->max_depth, full.max_depth);
  // In chunks run in any order (Accel runs them on TBB's threads): the same nodes.
  const auto rev = quantize_wide(full, [](std::size_t n, const auto& f) {
    for (std::size_t i = n; i-- > 0;) f(i);
  });
  ASSERT_TRUE(rev.has_value());
  ASSERT_EQ(rev->nodes.size(), q->nodes.size());
  for (std::size_t i = 0; i < q->nodes.size(); ++i) {
    const auto &a = q->nodes[i], &b = rev->nodes[i];
    bool same = a.valid == b.valid && std::equal(a.origin, a.origin + 3, b.origin) && std::equal(a.scale, a.scale + 3, b.scale) &&
                std::equal(&a.qlo[0][0], &a.qlo[0][0] + 6 * N, &b.qlo[0][0]) && std::equal(a.child, a.child + N, b.child) &&
                std::equal(a.count, a.count + N, b.count);
    ASSERT_TRUE(same) << what << ": node " << i;
  }
  const ScaleRange r = scales(*q);
  range.smallest = std::min(range.smallest, r.smallest), range.largest = std::max(range.largest, r.largest);
  // The check can fail: one plane moved inward by one step (each q is the tightest, so the
  // neighbouring step crosses the float plane) is exactly one violation.
  BvhWideQ<N> bad = *q;
  for (auto& n : bad.nodes) {
    const int s = __builtin_ctz(n.valid | 0x100u);
    if (s >= N || n.qlo[1][s] == n.qhi[1][s]) continue;
    ++n.qlo[1][s];
    EXPECT_EQ(violations(full, bad), 1) << what;
    --n.qlo[1][s], --n.qhi[1][s];
    EXPECT_EQ(violations(full, bad), 1) << what;
    ++n.qhi[1][s];
    n.valid = static_cast<std::uint8_t>(n.valid & ~(1u << s));  // a live child dropped
    EXPECT_EQ(violations(full, bad), 1) << what;
    break;
  }
}

/// The AVX2 decoder of the eight-wide box test, stored (call only when cpu_has_avx2()).
[[gnu::target("avx2")]] void decode8(const std::uint8_t* q, float scale, float origin, float* out) {
  _mm256_storeu_ps(out, detail::bvh8q_decode(q, _mm256_set1_ps(scale), _mm256_set1_ps(origin)));
}

}  // namespace

TEST(BvhQuantized, NodeSizes) {
  EXPECT_EQ(sizeof(Bvh8QNode), 128u);  // half of Bvh8Node's 256
  EXPECT_EQ(sizeof(Bvh4QNode), 80u);   // Bvh4Node: 128
}

TEST(BvhQuantized, DecodedBoxesContainTheFloatBoxes) {
  struct Case {
    const char* what;
    Soup soup;
  };
  const Case cases[] = {
      {"near the origin", test::random_soup(3000, 2, true)},
      {"far (1e6) with tiny boxes", soup_at(2000, 3, 1e6, 50.0, 1e-3)},
      {"far negative (-3e7), boxes below a float ulp", soup_at(2000, 4, -3e7, 1e3, 1e-4)},
      {"huge (1e30)", soup_at(1500, 5, 0.0, 1e30, 1e28)},
      {"tiny (1e-30)", soup_at(1500, 6, 0.0, 1e-30, 1e-32)},
      {"subnormal floats (1e-39)", soup_at(800, 7, 0.0, 1e-39, 1e-41)},
      {"every scale in one tree (1e-3 .. 1e20)", soup_at(2000, 8, 0.0, 0.0, 0.0, true)},
  };
  ScaleRange range;
  for (const Case& c : cases) {
    check_containment<8>(c.soup, c.what, range);
    check_containment<4>(c.soup, c.what, range);
  }
  // Scales at both ends of their range were exercised (2^-126 and beyond 2^90).
  EXPECT_EQ(range.smallest, 0x1p-126f);
  EXPECT_GE(range.largest, 0x1p90f);
}

TEST(BvhQuantized, DecodedBoxesContainTheFloatBoxesOnBunny) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const scene::Scene s = scene::load_scene(path);
  Soup soup;
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i) {
    const Triangle<double> t = s.triangle(std::uint32_t(i));
    BvhBox b;
    b.extend(t.p0), b.extend(t.p1), b.extend(t.p2);
    soup.tris.push_back(t), soup.boxes.push_back(b), soup.centers.push_back(((t.p0 + t.p1 + t.p2) / 3.0).cast<float>());
  }
  ScaleRange range;
  check_containment<8>(soup, "bunny00", range);
  check_containment<4>(soup, "bunny00", range);
}

TEST(BvhQuantized, NonFiniteBoundsKeepFullNodes) {
  Soup soup = test::random_soup(200, 9);
  soup.tris[17].p1.x = 1e39;  // beyond the float range: the box's hi is +inf
  soup.boxes[17].extend(soup.tris[17].p1);
  ASSERT_TRUE(std::isinf(soup.boxes[17].hi[0]));
  EXPECT_FALSE(quantize_wide(wide_of<8>(soup)).has_value());
  EXPECT_FALSE(quantize_wide(wide_of<4>(soup)).has_value());
  // Accel falls back to the full nodes and says so.
  scene::Scene s;
  mesh::Mesh m;
  for (const auto& t : soup.tris) {
    const auto v = std::uint32_t(m.vertices.size());
    m.vertices.push_back(t.p0), m.vertices.push_back(t.p1), m.vertices.push_back(t.p2);
    m.triangles.push_back({v, v + 1, v + 2});
  }
  scene::add_mesh(s, m);
  const scene::Accel a(s, {}, BvhSimd::sse4, BvhNodes::compressed);
  EXPECT_EQ(a.nodes(), BvhNodes::full);
  EXPECT_FALSE(a.bvh().empty());
}

TEST(BvhQuantized, SimdDecodersGiveTheBuildsFloats) {
  const Soup soup = soup_at(1500, 10, 1e6, 50.0, 1e-3, false);
  const auto q4 = quantize_wide(wide_of<4>(soup));
  ASSERT_TRUE(q4);
  int compared = 0;
  for (const auto& n : q4->nodes)
    for (int k = 0; k < 3; ++k)
      for (int hi = 0; hi < 2; ++hi) {
        alignas(16) float out[4];
        _mm_store_ps(out, detail::bvh4q_decode(&n.qlo[0][0] + 12 * hi + 4 * k, _mm_set1_ps(n.scale[k]), _mm_set1_ps(n.origin[k])));
        for (int i = 0; i < 4; ++i, ++compared) {
          const float want = Bvh4QNode::decode(hi ? n.qhi[k][i] : n.qlo[k][i], n.scale[k], n.origin[k]);
          ASSERT_EQ(std::memcmp(&out[i], &want, 4), 0) << out[i] << " vs " << want;
        }
      }
  EXPECT_GT(compared, 1000);
  if (!cpu_has_avx2()) return;
  const auto q8 = quantize_wide(wide_of<8>(soup));
  ASSERT_TRUE(q8);
  for (const auto& n : q8->nodes)
    for (int k = 0; k < 3; ++k)
      for (int hi = 0; hi < 2; ++hi) {
        alignas(32) float out[8];
        decode8(&n.qlo[0][0] + 24 * hi + 8 * k, n.scale[k], n.origin[k], out);
        for (int i = 0; i < 8; ++i) {
          const float want = Bvh8QNode::decode(hi ? n.qhi[k][i] : n.qlo[k][i], n.scale[k], n.origin[k]);
          ASSERT_EQ(std::memcmp(&out[i], &want, 4), 0) << out[i] << " vs " << want;
        }
      }
}

namespace {
/// Raw traversals (Möller–Trumbore leaves) of full and compressed trees of one width against each
/// other and brute force, on random and hostile rays (axis-parallel, origins on slab planes, the
/// double path).
template <int N>
void check_raw(const Soup& soup, unsigned seed, int& hit_rays) {
  const BvhWide<N> full = wide_of<N>(soup);
  const BvhWideQ<N> q = *quantize_wide(full);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-12, 12), d(-1, 1);
  for (BvhTraversal mode : {BvhTraversal::standard, BvhTraversal::conservative})
    for (int r = 0; r < 500; ++r) {
      Ray<double> ray{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
      if (r % 11 == 1) ray.d = {0.0, -0.0, r % 2 ? 1.0 : -1.0};
      if (r % 11 == 4) ray.o.z = soup.tris[rng() % 600 * 5].p0.z, ray.d.z = r % 2 ? 0.0 : -0.0;
      const double s = r % 7 == 3 ? 0x1p70 : (r % 7 == 5 ? 0x1p-70 : 1.0);
      ray.d = ray.d / s;
      const double tmin = (r % 3 == 0 ? 2.0 : 0.0) * s, tmax0 = r % 5 == 0 ? 8.0 * s : 1e300;
      const Answers af = answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery qr, auto&& leaf) {
        wide_traverse(full, ray, tmin, tm, mode, qr, leaf);
      });
      const Answers aq = answers(soup, ray, tmin, tmax0, [&](double& tm, BvhQuery qr, auto&& leaf) {
        wide_traverse(q, ray, tmin, tm, mode, qr, leaf);
      });
      ASSERT_EQ(af, aq) << N << " wide, ray " << r;
      ASSERT_EQ(aq, brute(soup, ray, tmin, tmax0)) << N << " wide, ray " << r;
      hit_rays += aq.any;
    }
}
}  // namespace

TEST(BvhQuantized, RawQueriesAgreeWithFullNodesAndBruteForce) {
  const Soup soup = test::random_soup(3000, 2, true);
  int hit_rays = 0;
  check_raw<4>(soup, 3, hit_rays);
  if (cpu_has_avx2()) check_raw<8>(soup, 3, hit_rays);
  EXPECT_GT(hit_rays, 150);
}

TEST(BvhQuantized, ConservativeVisitsBoxesTouchedAtACorner) {
  // As Bvh8.ConservativeVisitsBoxesTouchedAtACornerByNonFloatOrigins on compressed trees: rays
  // through a corner of a primitive's float box exactly from a double origin that is no float.
  const Soup soup = soup_at(2000, 11, 1e3, 20.0, 0.7);  // away from the origin: coarse decoded planes
  const Bvh4Q q4 = *quantize_wide(wide_of<4>(soup));
  const Bvh8Q q8 = *quantize_wide(wide_of<8>(soup));
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  int missed = 0, total = 0;
  for (int r = 0; r < 1500; ++r) {
    const std::uint32_t p = rng() % soup.tris.size();
    const BvhBox& b = soup.boxes[p];
    const Vec3<double> corner{double(rng() & 1 ? b.hi[0] : b.lo[0]), double(rng() & 1 ? b.hi[1] : b.lo[1]),
                              double(rng() & 1 ? b.hi[2] : b.lo[2])};
    Vec3<double> d;
    for (int k = 0; k < 3; ++k) d[k] = std::ldexp(std::round(std::ldexp(u(rng), 40)), -40);
    if (r % 4 == 0) d[r / 4 % 3] = r % 8 ? 0.0 : -0.0;
    if (is_zero(d)) continue;
    const double T = r % 3 == 2 ? 1024.0 : 1.0;
    const double s = r % 10 == 7 ? 0x1p-80 : 1.0;
    const Ray<double> ray{corner - d * T, d * s};
    if (ray.o + d * T != corner) continue;
    auto visits = [&](const auto& tree, BvhQuery query, double tmin, double tmax0) {
      bool seen = false;
      double tm = tmax0;
      wide_traverse(tree, ray, tmin, tm, BvhTraversal::conservative, query, [&](std::uint32_t i) {
        seen |= i == p;
        return false;
      });
      return seen;
    };
    for (double tmin : {0.0, T / s}) {
      total += 2;
      missed += !visits(q4, BvhQuery::all, tmin, 1e300) + !visits(q4, BvhQuery::closest, tmin, T / s);
      if (cpu_has_avx2()) missed += !visits(q8, BvhQuery::all, tmin, 1e300) + !visits(q8, BvhQuery::closest, tmin, T / s);
    }
  }
  EXPECT_GT(total, 1800);
  EXPECT_EQ(missed, 0);
}

TEST(BvhQuantized, EnvironmentChoice) {
  const char* old = std::getenv("RAYPROOF_BVH_NODES");
  const std::string saved = old ? old : "";
  ::unsetenv("RAYPROOF_BVH_NODES");
  // Automatic: by the size of the full nodes.
  EXPECT_EQ(bvh_nodes_choice(), BvhNodes::full);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::automatic, kCompressedNodesAbove), BvhNodes::full);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::automatic, kCompressedNodesAbove + 1), BvhNodes::compressed);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::compressed), BvhNodes::compressed);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::full, std::size_t(1) << 30), BvhNodes::full);
  ::setenv("RAYPROOF_BVH_NODES", "compressed", 1);
  EXPECT_EQ(bvh_nodes_choice(), BvhNodes::compressed);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::full), BvhNodes::full);  // explicit wins
  ::setenv("RAYPROOF_BVH_NODES", "full", 1);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::automatic, std::size_t(1) << 30), BvhNodes::full);
  ::setenv("RAYPROOF_BVH_NODES", "auto", 1);
  EXPECT_EQ(bvh_nodes_choice(BvhNodes::automatic, std::size_t(1) << 30), BvhNodes::compressed);
  // Accel follows the variable (a small scene: automatic alone would keep full nodes).
  scene::Scene s;
  scene::add_mesh(s, scene::bumpy_sphere(500));
  ::setenv("RAYPROOF_BVH_NODES", "compressed", 1);
  EXPECT_EQ(scene::Accel(s, {}, BvhSimd::sse4).nodes(), BvhNodes::compressed);
  EXPECT_EQ(scene::Accel(s, {}, BvhSimd::sse4, BvhNodes::full).nodes(), BvhNodes::full);
  ::unsetenv("RAYPROOF_BVH_NODES");
  EXPECT_EQ(scene::Accel(s, {}, BvhSimd::sse4).nodes(), BvhNodes::full);
  ::setenv("RAYPROOF_BVH_NODES", "Compressed", 1);
  EXPECT_THROW(scene::Accel(s, {}, BvhSimd::sse4), std::invalid_argument);
  ::setenv("RAYPROOF_BVH_NODES", "quantised", 1);
  try {
    (void)bvh_nodes_choice();
    ADD_FAILURE() << "no error for RAYPROOF_BVH_NODES=quantised";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "RAYPROOF_BVH_NODES='quantised': expected auto, full or compressed");
  }
  if (old) {
    ::setenv("RAYPROOF_BVH_NODES", saved.c_str(), 1);
  } else {
    ::unsetenv("RAYPROOF_BVH_NODES");
  }
}

// ---- Through scene::Accel: every compiled method, both paths ----

namespace {
using namespace rayproof::scene;

SceneMethod method(const std::string& name) { return find_scene_method(name, registry::all_methods()); }

/// closest, any and all of every ray (a [tmin, tmax] range on a third) on `simd`'s path: the same
/// with full and compressed nodes under conservative traversal (robust, certified: every box the
/// segment touches passes either way, so both visit every leaf that can hold a crossing). Under
/// standard traversal (the textbook slab test of the float-rounded ray) the full nodes may cull a
/// leaf touched at one point that the larger decoded box lets through: all hits with compressed
/// nodes contain those with full nodes (the float box test is monotone under box inclusion) and
/// the extra ones are the kernel's own crossings; `extra` counts them. Rays from `hostile_from` on
/// are hostile (huge and tiny scales): there a float kernel's t may fall short of the box's exact
/// entry (bvh8_test), so closest hit may differ between trees whose leaf boxes differ: both must
/// be crossings of all hits, within 2^-18 relative in t.
void check_nodes(const Scene& s, const std::vector<Ray<double>>& rays, const std::vector<std::string>& names, BvhSimd simd,
                 int& crossings, int& extra, std::size_t hostile_from = std::size_t(-1)) {
  const Accel full(s, {}, simd, BvhNodes::full), comp(s, {}, simd, BvhNodes::compressed);
  ASSERT_EQ(full.nodes(), BvhNodes::full);
  ASSERT_EQ(comp.nodes(), BvhNodes::compressed);
  ASSERT_EQ(comp.simd(), simd);
  ASSERT_TRUE(comp.bvh().empty() && comp.bvh8().empty());
  ASSERT_FALSE(simd == BvhSimd::avx2 ? comp.bvh8q().empty() : comp.bvh4q().empty());
  EXPECT_EQ(comp.max_depth(), full.max_depth());
  // The bytes counted are the nodes held: 128 of 256 (eight-wide) or 80 of 128 (four-wide) per node.
  const std::size_t full_nodes = full.bvh().nodes.size() + full.bvh8().nodes.size();
  EXPECT_EQ(full.bvh_bytes() - comp.bvh_bytes(), full_nodes * (simd == BvhSimd::avx2 ? 128 : 48));
  for (const std::string& name : names) {
    const SceneMethod m = method(name);
    const bool conservative = m.traversal == BvhTraversal::conservative;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const QueryRange q = i % 3 == 1 ? QueryRange{0.25, 1.5} : QueryRange{};
      const auto all = full.all(rays[i], m, q), all_c = comp.all(rays[i], m, q);
      const PrimHit c = full.closest(rays[i], m, q), c_c = comp.closest(rays[i], m, q);
      const bool any = full.any(rays[i], m, q), any_c = comp.any(rays[i], m, q);
      crossings += int(all.size());
      auto in = [](const std::vector<PrimHit>& v, const PrimHit& h) { return std::find(v.begin(), v.end(), h) != v.end(); };
      if (conservative) {
        ASSERT_EQ(all, all_c) << name << " ray " << i;
        if (i < hostile_from) {
          ASSERT_EQ(c, c_c) << name << " ray " << i;
        } else if (c != c_c) {
          ASSERT_TRUE(in(all, c) && in(all, c_c) && std::abs(c.t - c_c.t) <= 0x1p-18 * std::abs(c.t)) << name << " ray " << i;
        }
        ASSERT_EQ(any, any_c) << name << " ray " << i;
        continue;
      }
      ASSERT_TRUE(std::includes(all_c.begin(), all_c.end(), all.begin(), all.end(), [](const PrimHit& a, const PrimHit& b) {
        return a.t < b.t || (a.t == b.t && a.prim < b.prim);
      })) << name << " ray " << i;
      extra += int(all_c.size() - all.size());
      ASSERT_TRUE(any_c || !any) << name << " ray " << i;
      // Closest: the same crossing, or (pruning with float distances that are not widened, as in
      // bvh8_test) two real crossings within 2^-18 relative; a crossing only the compressed nodes
      // see may come first.
      const bool near = in(all_c, c) && in(all_c, c_c) && std::abs(c.t - c_c.t) <= 0x1p-18 * std::abs(c.t);
      const bool only_compressed_sees = in(all_c, c_c) && !in(all, c_c) && c_c.t <= c.t;
      const bool ok = c == c_c || near || only_compressed_sees;
      ASSERT_TRUE(ok) << name << " ray " << i << ": " << c << " vs " << c_c;
    }
  }
  const SceneMethod m = method("robust");
  std::vector<PrimHit> bf(rays.size()), bc(rays.size());
  full.closest_batch(rays, bf, m, 1);
  comp.closest_batch(rays, bc, m, 2);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(bc[i], comp.closest(rays[i], m)) << i;
    if (i < hostile_from) {
      ASSERT_EQ(bf[i], bc[i]) << i;
    }
  }
}

const std::vector<std::string> kAll = {"float", "double", "cramer-float", "cramer-double", "robust",
                                       "watertight-float", "watertight", "certified"};
}  // namespace

TEST(BvhQuantizedAccel, EveryMethodAgreesWithFullNodesOnBothPaths) {
  ASSERT_EQ(compiled_scene_method_names(registry::all_methods()), kAll);  // a new compiled method joins this test
  Scene s = default_scene(2);                  // analytic primitives too
  add_mesh(s, bumpy_sphere(2000));
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Ray<double>> rays = leak_rays(Vec3<double>{0.01, 0.02, -0.01}, leak_targets(s.mesh, 250));
  for (int i = 0; i < 150; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  const std::size_t hostile_from = rays.size();
  const auto hostile = test::hostile_rays(s.mesh, 32, 200);
  rays.insert(rays.end(), hostile.begin(), hostile.end());
  int crossings = 0, extra = 0;
  check_nodes(s, rays, kAll, BvhSimd::sse4, crossings, extra, hostile_from);
  if (cpu_has_avx2()) check_nodes(s, rays, kAll, BvhSimd::avx2, crossings, extra, hostile_from);
  EXPECT_GT(crossings, 5000);
  EXPECT_LT(extra, crossings / 100);
}

TEST(BvhQuantizedAccel, BunnyLeakRaysAgreeAndDoNotLeak) {
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const Scene s = load_scene(path);
  const auto rays = leak_rays(volume_centroid(s.mesh), leak_targets(s.mesh, 800));
  const std::vector<Ray<double>> few(rays.begin(), rays.begin() + 150);
  int crossings = 0, extra = 0;
  for (BvhSimd simd : {BvhSimd::sse4, BvhSimd::avx2}) {
    if (simd == BvhSimd::avx2 && !cpu_has_avx2()) continue;
    check_nodes(s, rays, {"float", "robust"}, simd, crossings, extra);
    check_nodes(s, few, {"certified"}, simd, crossings, extra);
    const Accel comp(s, {}, simd, BvhNodes::compressed);
    EXPECT_EQ(count_leaks(comp, method("robust"), rays, 1).misses, 0u);
    EXPECT_EQ(count_leaks(comp, method("certified"), few, 1).misses, 0u);
  }
  EXPECT_GT(crossings, 1500);
  EXPECT_LT(extra, crossings / 20);
}
