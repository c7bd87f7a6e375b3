#pragma once
/// Eight-wide BVH: the binary tree of bvh_build.h collapsed into nodes of up to eight children whose
/// boxes are tested together in one AVX2 pass. The core is compiled for x86-64 baseline (SSE2): the
/// eight-wide traversal is compiled in functions with `__attribute__((target("avx2")))` and chosen
/// at run time (bvh_simd_path(): the CPU, or the RAYPROOF_SIMD environment variable); the four-wide
/// SSE tree of bvh_wide.h stays the path for CPUs without AVX2.
///
/// Node layout (256 bytes, four cache lines): per axis the eight children's lo then hi planes
/// (structure of arrays, one 256-bit load per plane), then `child`, `count` and `valid` with the
/// meaning they have in Bvh4Node (both are BvhWideNode of bvh_wide.h): an inner child is a node index (count 0), a leaf child a range
/// [child, child + count) of prim_ids (count 1..255); unused slots have empty boxes and a clear bit.
/// Compressed eight-wide nodes (Bvh8QNode, 128 bytes, bvh_wide_quantized.h) run the same test on planes
/// decoded by bvh8q_decode (vpmovzxbd, vcvtdq2ps, vmulps, vaddps): floats that contain the full
/// node's planes (proof at BvhWideQNode), so the guarantee below holds for them unchanged.
///
/// Box tests. The ray is prepared by make_bvh4_ray (bvh_wide.h) and its per-axis floats broadcast
/// to eight lanes; the test then does in each lane exactly the float operations bvh4_test does in
/// each of its four (subtraction, product with the near or far reciprocal, max / min, comparison;
/// no FMA: the target is "avx2" without "fma", so nothing is contracted). The conservative
/// guarantee is therefore the four-wide one (proof at make_bvh4_ray): per-ray origin bounds and
/// directed reciprocals make every box the exact double segment [tmin, tmax] touches pass (even at
/// one point), with nothing added per node. An axis with d_k = 0 and the origin on a slab plane
/// gives 0 * inf = NaN: vmaxps / vminps return their second operand (the running bound) when either
/// is NaN, so that axis bounds nothing; the comparison is ordered (false for NaN).
///  - Rays out of the float path's range (NaN, |o| > 2^64, or a nonzero |d| outside [2^-64, 2^64])
///    are traversed with the scalar double box test of bvh_traverse.h (BvhRay::enter) on the same
///    nodes, widened by 2 gamma(3) in double.
///
/// Traversal. Closest hit visits children nearest first (an insertion sort of the hit lanes by
/// entry t) and drops popped entries whose entry t lies beyond the best t so far. Any hit does not
/// sort: it pushes the hit children in slot order and stops at the first leaf that reports a hit.
/// All hits visits every leaf the segment meets.
///
/// Leaves are handed to the caller whole: `leaf_range(first, count)` gets a range of leaf-order
/// slots (indices into prim_ids, or the caller's own leaf-order data) and returns true to stop
/// (honoured for any hit); for closest hit it lowers `tmax` (held by reference) as the per-slot
/// callbacks do. wide_traverse_slots (bvh_wide.h) and bvh8_traverse are the per-slot and per-primitive forms. The
/// loop, the stack, the child ordering and the double fallback are bvh_wide.h's (wide_traverse_loop);
/// this header adds the AVX2 box test and the AVX2-compiled entry to that loop.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"

namespace rayproof {

/// Bvh8Node, Bvh8 and collapse_bvh8 are the eight-wide instances of bvh_wide.h's templates.

/// Which wide tree and box test the traversal uses.
enum class BvhSimd { automatic, sse4, avx2 };

/// True when the CPU runs AVX2 code.
[[nodiscard]] inline bool cpu_has_avx2() {
  static const bool ok = (__builtin_cpu_init(), __builtin_cpu_supports("avx2") != 0);
  return ok;
}

/// The RAYPROOF_SIMD environment variable: unset, empty or "auto": automatic; "sse" (and the leaf
/// kernels' "scalar" and "off"): the four-wide SSE path; "avx2": the eight-wide AVX2 path (when the
/// CPU has AVX2; else the SSE path). Any other value throws std::invalid_argument naming them.
[[nodiscard]] inline BvhSimd bvh_simd_from_env() {
  const char* e = std::getenv("RAYPROOF_SIMD");
  if (!e || !*e || std::strcmp(e, "auto") == 0) return BvhSimd::automatic;
  // "scalar" and "off" are the SIMD leaves' narrower settings (src/scene/leaf_simd.h): SSE nodes too.
  if (std::strcmp(e, "sse") == 0 || std::strcmp(e, "scalar") == 0 || std::strcmp(e, "off") == 0) return BvhSimd::sse4;
  if (std::strcmp(e, "avx2") == 0) return BvhSimd::avx2;
  std::string msg = "RAYPROOF_SIMD='";
  msg.append(e).append("': expected auto, avx2, sse, scalar or off");
  throw std::invalid_argument(msg);
}

/// The path actually taken for a request: automatic follows RAYPROOF_SIMD, then the CPU; avx2 on a
/// CPU without it falls back to sse4. Never returns automatic.
[[nodiscard]] inline BvhSimd bvh_simd_path(BvhSimd want = BvhSimd::automatic) {
  if (want == BvhSimd::automatic) want = bvh_simd_from_env();
  if (want == BvhSimd::sse4) return BvhSimd::sse4;
  return cpu_has_avx2() ? BvhSimd::avx2 : BvhSimd::sse4;
}

[[nodiscard]] inline const char* to_string(BvhSimd s) {
  switch (s) {
    case BvhSimd::automatic: return "auto";
    case BvhSimd::sse4: return "sse-4wide";
    case BvhSimd::avx2: return "avx2-8wide";
  }
  return "?";
}

namespace detail {

/// The ray of make_bvh4_ray broadcast to eight lanes; plane offsets in the eight-wide node.
struct Bvh8RayF {
  __m256 o_near[3], o_far[3], inv_near[3], inv_far[3];
  int near_off[3], far_off[3];
};

[[gnu::target("avx2"), gnu::always_inline]] inline void bvh8_ray(const Bvh4RayF& r4, Bvh8RayF& r) {
  for (int k = 0; k < 3; ++k) {
    r.o_near[k] = _mm256_broadcastss_ps(r4.o_near[k]);
    r.o_far[k] = _mm256_broadcastss_ps(r4.o_far[k]);
    r.inv_near[k] = _mm256_broadcastss_ps(r4.inv_near[k]);
    r.inv_far[k] = _mm256_broadcastss_ps(r4.inv_far[k]);
    // Four-wide offsets are 4k (lo) and 12 + 4k (hi); eight-wide 8k and 24 + 8k.
    r.near_off[k] = 2 * r4.near_off[k], r.far_off[k] = 2 * r4.far_off[k];
  }
}

/// Hit mask of eight children and their entry distances: bvh4_slab_test in eight lanes.
/// `plane(off, k)` gives the eight planes at float offset `off` of axis k (loaded from a full node,
/// decoded from a quantized one: BvhWideQNode, bvh_wide_quantized.h); the math after it is the same for both.
/// bvh8_slab_finish is the end of the eight-lane slab test, from the largest near t0 and the
/// smallest far t1 of each lane (tmin and tmax already in them): the entry distances and the lanes
/// whose interval is not empty (ordered: false for NaN). Shared with the packet test of bvh_packet.h.
[[gnu::target("avx2"), gnu::always_inline]] inline int bvh8_slab_finish(__m256 t0, __m256 t1, __m256& t_enter) {
  t_enter = t0;
  return _mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ));
}

template <bool Conservative, class Planes>
[[gnu::target("avx2"), gnu::always_inline]] inline int bvh8_slab_test(const Planes& plane, int valid, const Bvh8RayF& r,
                                                                      __m256 tmin, __m256 tmax, __m256& t_enter) {
  __m256 t0 = tmin, t1 = tmax;
  for (int k = 0; k < 3; ++k) {
    const __m256 near = _mm256_mul_ps(_mm256_sub_ps(plane(r.near_off[k], k), r.o_near[k]), r.inv_near[k]);
    const __m256 far = _mm256_mul_ps(_mm256_sub_ps(plane(r.far_off[k], k), r.o_far[k]), r.inv_far[k]);
    t0 = _mm256_max_ps(near, t0);  // NaN near: t0 (the axis bounds nothing)
    t1 = _mm256_min_ps(far, t1);   // NaN far: t1
  }
  return bvh8_slab_finish(t0, t1, t_enter) & valid;
}

/// A full node's planes: loaded.
struct Bvh8Planes {
  const float* f;
  [[gnu::target("avx2"), gnu::always_inline]] __m256 operator()(int off, int) const { return _mm256_load_ps(f + off); }
};

/// Hit mask of the eight children of `n` and their entry distances: bvh4_test in eight lanes.
template <bool Conservative>
[[gnu::target("avx2"), gnu::always_inline]] inline int bvh8_test(const Bvh8Node& n, const Bvh8RayF& r, __m256 tmin,
                                                                 __m256 tmax, __m256& t_enter) {
  return bvh8_slab_test<Conservative>(Bvh8Planes{&n.lo[0][0]}, n.valid, r, tmin, tmax, t_enter);
}

/// Eight quantized planes at byte offset `off` of `q` decoded to floats: q * scale + origin
/// (u8 -> i32 -> float, exact; product, exact; one rounded sum, as BvhWideQNode::decode; no FMA:
/// the target is "avx2" without "fma", and a contraction would round the same, the product being exact).
[[gnu::target("avx2"), gnu::always_inline]] inline __m256 bvh8q_decode(const std::uint8_t* q, __m256 scale, __m256 origin) {
  const __m256i i32 = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(q)));
  return _mm256_add_ps(_mm256_mul_ps(_mm256_cvtepi32_ps(i32), scale), origin);
}

template <bool Conservative>
struct Bvh8BoxTest {
  Bvh8RayF ray;
  __m256 tmin;
  [[gnu::target("avx2"), gnu::always_inline]] int operator()(const Bvh8Node& n, float tmax, float* t) const {
    __m256 te;
    const int mask = bvh8_test<Conservative>(n, ray, tmin, _mm256_set1_ps(tmax), te);
    if (mask) _mm256_store_ps(t, te);
    return mask;
  }
};

/// A quantized node's planes: decoded.
struct Bvh8QPlanes {
  const Bvh8QNode& n;
  [[gnu::target("avx2"), gnu::always_inline]] __m256 operator()(int off, int k) const {
    return bvh8q_decode(&n.qlo[0][0] + off, _mm256_broadcast_ss(&n.scale[k]), _mm256_broadcast_ss(&n.origin[k]));
  }
};

template <bool Conservative>
struct Bvh8QBoxTest {
  Bvh8RayF ray;
  __m256 tmin;
  [[gnu::target("avx2"), gnu::always_inline]] int operator()(const Bvh8QNode& n, float tmax, float* t) const {
    __m256 te;
    const int mask = bvh8_slab_test<Conservative>(Bvh8QPlanes{n}, n.valid, ray, tmin, _mm256_set1_ps(tmax), te);
    if (mask) _mm256_store_ps(t, te);
    return mask;
  }
};

// The loop of bvh_wide.h compiled for AVX2 (see bvh_wide_loop.h): wide_traverse_loop_avx2.
// (g++: a target pragma; clang, which ignores it, applies the same attribute to every function of
// the region, the loop's lambdas included.)
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#define RAYPROOF_WIDE_TRAVERSE_LOOP wide_traverse_loop_avx2
#include "rayproof/bvh_wide_loop.h"
#undef RAYPROOF_WIDE_TRAVERSE_LOOP
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

/// The eight-wide traversal: the shared loop with the AVX2 box test, compiled for AVX2; rays out of
/// the float range take the double box test.
template <class Tree, template <bool> class BoxTest>
struct WideTraversal8 {
  template <bool Conservative, BvhQuery Query, class Leaf>
  [[gnu::target("avx2")]] static void run(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax,
                                          Leaf& leaf) {
    Bvh4RayF r4;
    if (!make_bvh4_ray(ray, Conservative, tmin, r4)) return wide_traverse_double<Tree, Conservative, Query>(bvh, ray, tmin, tmax, leaf);
    BoxTest<Conservative> test;
    bvh8_ray(r4, test.ray);
    test.tmin = _mm256_set1_ps(r4.tmin);
    wide_traverse_loop_avx2<Tree, float, Query>(bvh, test, [&] { return wide_tmax_float<Conservative>(tmax); }, leaf);
  }
};
template <>
struct WideTraversal<Bvh8> : WideTraversal8<Bvh8, Bvh8BoxTest> {};
/// The eight-wide traversal of quantized nodes: the same, with the planes decoded.
template <>
struct WideTraversal<Bvh8Q> : WideTraversal8<Bvh8Q, Bvh8QBoxTest> {};

}  // namespace detail

/// The eight-wide (AVX2) names of wide_traverse_leaves and wide_traverse (bvh_wide.h). Need
/// AVX2: call them only when cpu_has_avx2() (bvh_simd_path() == BvhSimd::avx2).
template <class LeafRange>
void bvh8_traverse_leaves(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                          BvhQuery query, LeafRange&& leaf_range) {
  wide_traverse_leaves(bvh, ray, tmin, tmax, mode, query, leaf_range);
}
template <class Leaf>
void bvh8_traverse(const Bvh8& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                   BvhQuery query, Leaf&& leaf) {
  wide_traverse(bvh, ray, tmin, tmax, mode, query, leaf);
}

}  // namespace rayproof
