/// The traversal engine alone against Embree: the eight-wide AVX2 tree of the SAH-optimal collapse
/// with three node tests (the conservative one before directed reciprocals, `widened`; the
/// library's conservative one, `directed`; the plain slab test, `standard`), the greedy collapse,
/// and the SAH collapse with leaf prefetch, each walked by the
/// library's traversal (bvh_wide8.h) with one plain float Möller–Trumbore leaf test over leaf-order
/// triangles (the same for all three), beside Embree's rtcIntersect1 / rtcOccluded1 (default build)
/// on the same rays, in one process, interleaved in blocks of 1000 rays with the order rotating,
/// thread CPU time. Each round gives each variant's time over Embree's; the table shows the
/// median and range over the rounds of Embree's time over ours (the bench's "ratio": > 1 is faster
/// than Embree). It measures the engine (nodes, stack, memory) without the product's leaf kernels.
/// Run: engine_bench mesh.off [rounds] [rays]  (default 7 rounds, 40000 rays per set)
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "mesh/mesh.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"
#include "bvh_wide8_avx512.h"
#include "rayproof/bvh_wide_sah.h"
#include "rayproof/triangle.h"

using namespace rayproof;

namespace {

struct TriF {
  Vec3<float> p0, e1, e2;
};

/// Float Möller–Trumbore: t in [0, tmax] or -1.
inline float mt(const TriF& tr, const Vec3<float>& o, const Vec3<float>& d, float tmax) {
  const Vec3<float> p = cross(d, tr.e2);
  const float det = dot(tr.e1, p);
  if (det == 0) return -1;
  const float inv = 1 / det;
  const Vec3<float> s = o - tr.p0;
  const float u = dot(s, p) * inv;
  if (u < 0 || u > 1) return -1;
  const Vec3<float> q = cross(s, tr.e1);
  const float v = dot(d, q) * inv;
  if (v < 0 || u + v > 1) return -1;
  const float t = dot(tr.e2, q) * inv;
  return t >= 0 && t <= tmax ? t : -1;
}

/// How a variant walks its tree: the library's conservative traversal (directed reciprocals), the
/// conservative test as it was before them (reciprocal to nearest, the largest near and smallest
/// far distance widened by 1 -/+ 2^-21 and 2^-120, then clamped: OldConservativeTest below, kept
/// here to measure the change), or the library's standard (non-conservative) slab test.
enum class NodeTest { directed, widened, standard };

struct Variant {
  const char* name;
  Bvh8 tree;
  std::vector<TriF> tris;  ///< leaf order
  bool prefetch;
  bool avx512 = false;
  NodeTest node = NodeTest::directed;
};

/// The eight-wide conservative box test before directed reciprocals: per axis (plane - o_bound) *
/// inv with inv rounded to nearest, then the widening and clamp (the proof it relied on: the
/// distance's four roundings within 2 gamma(4), covered by 8u, plus 2^-120 for underflow).
struct OldConservativeTest {
  detail::Bvh8RayF ray;  ///< origins bounded, inv_near = inv_far = the reciprocal to nearest
  __m256 tmin;
  [[gnu::target("avx2"), gnu::always_inline]] int operator()(const Bvh8Node& n, float tmax, float* t) const {
    const float* f = &n.lo[0][0];
    __m256 t0 = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
    __m256 t1 = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    for (int k = 0; k < 3; ++k) {
      const __m256 near = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(f + ray.near_off[k]), ray.o_near[k]), ray.inv_near[k]);
      const __m256 far = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(f + ray.far_off[k]), ray.o_far[k]), ray.inv_far[k]);
      t0 = _mm256_max_ps(near, t0), t1 = _mm256_min_ps(far, t1);
    }
    const __m256 shrink = _mm256_set1_ps(1.0f - 0x1p-21f), grow = _mm256_set1_ps(1.0f + 0x1p-21f);
    const __m256 tiny = _mm256_set1_ps(0x1p-120f), zero = _mm256_setzero_ps();
    const __m256 t0_neg = _mm256_cmp_ps(t0, zero, _CMP_LT_OQ), t1_neg = _mm256_cmp_ps(t1, zero, _CMP_LT_OQ);
    t0 = _mm256_sub_ps(_mm256_mul_ps(t0, _mm256_blendv_ps(shrink, grow, t0_neg)), tiny);
    t1 = _mm256_add_ps(_mm256_mul_ps(t1, _mm256_blendv_ps(grow, shrink, t1_neg)), tiny);
    t0 = _mm256_max_ps(t0, tmin);
    t1 = _mm256_min_ps(t1, _mm256_set1_ps(tmax));
    const int mask = _mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ)) & n.valid;
    if (mask) _mm256_store_ps(t, t0);
    return mask;
  }
};

/// The old conservative traversal of `tree` (rays in the float range only; the benches' rays are).
template <BvhQuery Query, class Leaf>
[[gnu::target("avx2")]] void old_conservative_traverse(const Bvh8& tree, const Ray<double>& r, const double& tmax, Leaf& leaf) {
  detail::Bvh4RayF bounded, nearest;
  if (!detail::make_bvh4_ray(r, true, 0.0, bounded) || !detail::make_bvh4_ray(r, false, 0.0, nearest)) std::abort();
  for (int k = 0; k < 3; ++k) bounded.inv_near[k] = bounded.inv_far[k] = nearest.inv_near[k];
  OldConservativeTest test;
  detail::bvh8_ray(bounded, test.ray);
  test.tmin = _mm256_set1_ps(bounded.tmin);
  detail::wide_traverse_loop_avx2<Bvh8, float, Query>(tree, test, [&] { return detail::round_up_f(tmax); }, leaf);
}

template <class F>
struct PrefetchingLeaf {
  F& f;
  const TriF* base;
  bool operator()(std::uint32_t first, std::uint32_t count) { return f(first, count); }
  void prefetch(std::uint32_t first) const { _mm_prefetch(reinterpret_cast<const char*>(base + first), _MM_HINT_T0); }
};

volatile double sink = 0;

/// One ray through a variant: closest t (or any hit as 1), conservative box test as robust's.
double query(const Variant& v, const Ray<double>& r, bool closest) {
  const Vec3<float> o = r.o.cast<float>(), d = r.d.cast<float>();
  double tmax = std::numeric_limits<double>::infinity();
  bool hit = false;
  auto body = [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first; j < first + count; ++j) {
      const float t = mt(v.tris[j], o, d, float(tmax));
      if (t >= 0) {
        hit = true;
        if (!closest) return true;
        tmax = t;
      }
    }
    return false;
  };
  const BvhQuery q = closest ? BvhQuery::closest : BvhQuery::any;
  if (v.node == NodeTest::widened) {
    if (closest) old_conservative_traverse<BvhQuery::closest>(v.tree, r, tmax, body);
    else old_conservative_traverse<BvhQuery::any>(v.tree, r, tmax, body);
  } else if (v.node == NodeTest::standard) {
    bvh8_traverse_leaves(v.tree, r, 0.0, tmax, BvhTraversal::standard, q, body);
  } else if (v.avx512) {
    bvh8_traverse_leaves_avx512(v.tree, r, 0.0, tmax, BvhTraversal::conservative, q, body);
  } else if (v.prefetch) {
    PrefetchingLeaf<decltype(body)> leaf{body, v.tris.data()};
    bvh8_traverse_leaves(v.tree, r, 0.0, tmax, BvhTraversal::conservative, q, leaf);
  } else {
    bvh8_traverse_leaves(v.tree, r, 0.0, tmax, BvhTraversal::conservative, q, body);
  }
  return closest ? (hit ? tmax : -1) : double(hit);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return std::fprintf(stderr, "usage: engine_bench mesh.off [rounds] [rays]\n"), 2;
  if (!cpu_has_avx2()) return std::fprintf(stderr, "engine_bench: needs AVX2\n"), 1;
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
  const std::size_t nrays = argc > 3 ? std::size_t(std::max(1, std::atoi(argv[3]))) : 40000;
  const mesh::Mesh m = mesh::read_mesh(argv[1]);
  const std::size_t n = m.triangles.size();
  std::vector<Triangle<double>> tris(n);
  std::vector<BvhBox> boxes(n);
  std::vector<Vec3<float>> centers(n);
  BvhBox all;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& t = m.triangles[i];
    tris[i] = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    boxes[i].extend(tris[i].p0), boxes[i].extend(tris[i].p1), boxes[i].extend(tris[i].p2);
    centers[i] = ((tris[i].p0 + tris[i].p1 + tris[i].p2) / 3.0).cast<float>();
    all.extend(boxes[i]);
  }
  const Bvh bin = build_bvh(boxes, centers, BvhBuildOptions{BvhBuilder::sah, 4});
  std::vector<Variant> vs;
  vs.push_back({"widened", collapse_wide_sah<8>(Bvh(bin), boxes), {}, false, false, NodeTest::widened});
  vs.push_back({"directed", collapse_wide_sah<8>(Bvh(bin), boxes), {}, false});
  vs.push_back({"standard", collapse_wide_sah<8>(Bvh(bin), boxes), {}, false, false, NodeTest::standard});
  vs.push_back({"greedy", collapse_wide<8>(Bvh(bin), boxes), {}, false});
  vs.push_back({"sah+prefetch", collapse_wide_sah<8>(Bvh(bin), boxes), {}, true});
  if (cpu_has_avx512()) vs.push_back({"sah+avx512", collapse_wide_sah<8>(Bvh(bin), boxes), {}, false, true});
  for (auto& v : vs)
    for (std::uint32_t id : v.tree.prim_ids) {
      const Triangle<float> t{tris[id].p0.cast<float>(), tris[id].p1.cast<float>(), tris[id].p2.cast<float>()};
      v.tris.push_back({t.p0, t.p1 - t.p0, t.p2 - t.p0});
    }
  // Embree, default build.
  RTCDevice dev = rtcNewDevice("threads=1");
  RTCScene sc = rtcNewScene(dev);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.vertices.size()));
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = float(m.vertices[i][k]);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, n));
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = m.triangles[i][k];
  rtcCommitGeometry(g), rtcAttachGeometry(sc, g), rtcReleaseGeometry(g), rtcCommitScene(sc);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  auto embree = [&](const Ray<double>& r, bool closest) {
    RTCRayHit rh{};
    rh.ray.org_x = float(r.o.x), rh.ray.org_y = float(r.o.y), rh.ray.org_z = float(r.o.z);
    rh.ray.dir_x = float(r.d.x), rh.ray.dir_y = float(r.d.y), rh.ray.dir_z = float(r.d.z);
    rh.ray.tnear = 0, rh.ray.tfar = std::numeric_limits<float>::infinity(), rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    if (closest) return rtcIntersect1(sc, &ctx, &rh), double(rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : -1);
    return rtcOccluded1(sc, &ctx, &rh.ray), double(rh.ray.tfar < 0);
  };
  // Rays as tree_stats makes them: a pinhole grid from +z, and uniform ones in the box.
  const Vec3<double> lo{all.lo[0], all.lo[1], all.lo[2]}, hi{all.hi[0], all.hi[1], all.hi[2]};
  const Vec3<double> mid = (lo + hi) * 0.5, ext = hi - lo;
  const double rad = std::max({ext.x, ext.y, ext.z});
  std::vector<Ray<double>> primary, random;
  const int side = int(std::sqrt(double(nrays)));
  const Vec3<double> eye = mid + Vec3<double>{0.1 * rad, 0.2 * rad, 1.6 * rad};
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      primary.push_back({eye, mid + Vec3<double>{(x + 0.5) / side - 0.5, (y + 0.5) / side - 0.5, 0} * (0.8 * rad) - eye});
  std::mt19937_64 rng(20);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> nd;
  for (std::size_t i = 0; i < nrays; ++i)
    random.push_back({lo + Vec3<double>{u(rng) * ext.x, u(rng) * ext.y, u(rng) * ext.z}, Vec3<double>{nd(rng), nd(rng), nd(rng)}});
  std::printf("%s: %zu triangles, %d rounds, %zu primary / %zu random rays; Embree time over ours (median [range])\n", argv[1], n,
              rounds, primary.size(), random.size());
  for (const auto* set : {&primary, &random})
    for (bool closest : {true, false}) {
      const std::size_t nv = vs.size();
      std::vector<std::vector<double>> ratio(nv);
      for (int r = 0; r < rounds; ++r) {
        std::vector<double> t(nv + 1, 0);
        for (std::size_t b = 0, blk = 0; b < set->size(); b += 1000, ++blk)
          for (std::size_t k = 0; k <= nv; ++k) {
            const std::size_t which = (k + blk + std::size_t(r)) % (nv + 1);
            const std::size_t e = std::min(set->size(), b + 1000);
            const double t0 = bench::thread_seconds();
            double acc = 0;
            for (std::size_t i = b; i < e; ++i) acc += which == nv ? embree((*set)[i], closest) : query(vs[which], (*set)[i], closest);
            t[which] += bench::thread_seconds() - t0;
            sink = sink + acc;
          }
        for (std::size_t k = 0; k < nv; ++k) ratio[k].push_back(t[nv] / t[k]);
      }
      std::printf("  %-7s %-7s", set == &primary ? "primary" : "random", closest ? "closest" : "any");
      for (std::size_t k = 0; k < nv; ++k) {
        std::sort(ratio[k].begin(), ratio[k].end());
        std::printf(" | %s %.3f [%.3f-%.3f]", vs[k].name, ratio[k][ratio[k].size() / 2], ratio[k].front(), ratio[k].back());
      }
      std::printf("\n");
    }
  // The conservative variants answer alike (same leaves, float leaf test, every touched box
  // visited): count disagreements. `standard` may prune differently and is left out.
  std::size_t differ = 0;
  for (const auto* set : {&primary, &random})
    for (const auto& r : *set)
      for (bool closest : {true, false})
        for (std::size_t k = 1; k < vs.size(); ++k)
          if (vs[k].node != NodeTest::standard) differ += query(vs[0], r, closest) != query(vs[k], r, closest);
  std::printf("queries whose answer differs between the conservative variants: %zu\n", differ);
  rtcReleaseScene(sc), rtcReleaseDevice(dev);
  return 0;
}
