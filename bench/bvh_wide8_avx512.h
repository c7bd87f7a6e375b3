#pragma once
/// AVX-512 (F, VL, DQ) child ordering for the eight-wide traversal: closest hit
/// pushes the hit children of a node farthest first, so the nearest is on top. bvh_wide.h's
/// wide_push does that with a comparison for two children and an insertion sort for more; here
/// the hit children's entry distances become 64-bit keys (the float's bits made orderable as
/// unsigned, above the slot number; missed slots key 0) sorted by a bitonic network of six
/// compare-exchange steps in one register, with no branch on the distances. The order of equal
/// distances may differ from wide_push's; answers do not depend on it (closest hit keeps the
/// lowest primitive among equal t, bvh_wide.h). Call only when cpu_has_avx512().
///
/// A measured experiment, not the library's path: in engine_bench (bunny00, armadillo; 9 rounds,
/// interleaved with the AVX2 loop over the same SAH-collapsed tree) it gave 0.97-1.02 of the
/// AVX2 loop's speed, so the library keeps wide_push. Kept here to repeat the measurement.
#include <immintrin.h>

#include <cstdint>
#include <type_traits>

#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"

// g++ 12 warns that _mm512_undefined_epi32() inside the intrinsics "may be used uninitialized".
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace rayproof {

/// AVX-512 F, VL and DQ (the instructions used here), and the OS saving their registers.
[[nodiscard]] inline bool cpu_has_avx512() {
  static const bool ok = (__builtin_cpu_init(), __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                                    __builtin_cpu_supports("avx512dq"));
  return ok;
}

namespace detail {

/// One compare-exchange step of a descending bitonic sort over eight u64 lanes: lane i meets lane
/// i ^ J; within blocks of K (sorted descending when i & K is 0 ... ), the lane that keeps the max.
template <int K, int J>
[[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline __m512i bitonic_step(__m512i v) {
  constexpr auto max_lanes = [] {
    unsigned m = 0;
    for (int i = 0; i < 8; ++i) {
      const bool lower = (i & J) == 0;          // i < partner
      const bool desc = (i & K) == 0;           // this block sorts descending (the final pass: all)
      if (lower == desc) m |= 1u << i;          // descending: the lower lane keeps the max
    }
    return m;
  }();
  const __m512i idx = _mm512_set_epi64(7 ^ J, 6 ^ J, 5 ^ J, 4 ^ J, 3 ^ J, 2 ^ J, 1 ^ J, 0 ^ J);
  const __m512i p = _mm512_permutexvar_epi64(idx, v);
  return _mm512_mask_blend_epi64(__mmask8(max_lanes), _mm512_min_epu64(v, p), _mm512_max_epu64(v, p));
}

/// The hit children of `n` (mask, three or more bits) pushed farthest first (closest hit), entry
/// distances in t[0..8); inner children's nodes prefetched when Node::kPrefetch.
template <class Node>
[[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline void wide_push_sorted_avx512(
    const Node& n, const Node* nodes, int mask, const float* t, WideEntry<float>* stack, int& top) {
  const __m256i bits = _mm256_castps_si256(_mm256_load_ps(t));
  // Orderable: negative floats flipped whole, others with the sign bit set.
  const __m256i sign = _mm256_srai_epi32(bits, 31);
  const __m256i ord = _mm256_xor_si256(bits, _mm256_or_si256(sign, _mm256_set1_epi32(int(0x80000000u))));
  const __m512i key = _mm512_maskz_or_epi64(__mmask8(mask), _mm512_slli_epi64(_mm512_cvtepu32_epi64(ord), 32),
                                            _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
  __m512i s = key;
  s = bitonic_step<2, 1>(s);
  s = bitonic_step<4, 2>(s), s = bitonic_step<4, 1>(s);
  s = bitonic_step<8, 4>(s), s = bitonic_step<8, 2>(s), s = bitonic_step<8, 1>(s);
  alignas(64) std::uint64_t sorted[8];
  _mm512_store_si512(sorted, s);
  const int k = __builtin_popcount(static_cast<unsigned>(mask));
  for (int p = 0; p < k; ++p) {
    const int i = int(sorted[p] & 7);
    stack[top + p] = WideEntry<float>{n.child[i], n.count[i], t[i]};
    if constexpr (Node::kPrefetch) {
      if (!n.count[i]) {
        const char* q = reinterpret_cast<const char*>(nodes + n.child[i]);
        for (std::size_t line = 0; line < sizeof(Node); line += 64) _mm_prefetch(q + line, _MM_HINT_T0);
      }
    }
  }
  top += k;
}

namespace avx512 {

/// wide_push for the eight-wide nodes, found by the loop below before bvh_wide.h's (more
/// specialised): closest hit with three or more children through the sorting network, the rest
/// as wide_push does.
template <bool Sort, class T>
[[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline void wide_push(const Bvh8Node& n, const Bvh8Node* nodes,
                                                                                     int mask, const T* t,
                                                                                     WideEntry<T>* stack, int& top) {
  if constexpr (Sort && std::is_same_v<T, float>) {
    if (__builtin_popcount(static_cast<unsigned>(mask)) > 2) return wide_push_sorted_avx512(n, nodes, mask, t, stack, top);
  }
  detail::wide_push<Sort>(n, nodes, mask, t, stack, top);
}
template <bool Sort, class T>
[[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline void wide_push(const Bvh8QNode& n, const Bvh8QNode* nodes,
                                                                                     int mask, const T* t,
                                                                                     WideEntry<T>* stack, int& top) {
  if constexpr (Sort && std::is_same_v<T, float>) {
    if (__builtin_popcount(static_cast<unsigned>(mask)) > 2) return wide_push_sorted_avx512(n, nodes, mask, t, stack, top);
  }
  detail::wide_push<Sort>(n, nodes, mask, t, stack, top);
}

// The loop of bvh_wide.h compiled for AVX-512 with the pushes above: wide_traverse_loop_avx512.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")
#define RAYPROOF_WIDE_TRAVERSE_LOOP wide_traverse_loop_avx512
#include "rayproof/bvh_wide_loop.h"
#undef RAYPROOF_WIDE_TRAVERSE_LOOP
#pragma GCC pop_options

template <class Tree, template <bool> class BoxTest>
struct Traversal {
  template <bool Conservative, BvhQuery Query, class Leaf>
  [[gnu::target("avx512f,avx512vl,avx512dq")]] static void run(const Tree& bvh, const Ray<double>& ray, double tmin,
                                                               const double& tmax, Leaf& leaf) {
    Bvh4RayF r4;
    if (!make_bvh4_ray(ray, Conservative, tmin, r4)) return wide_traverse_double<Tree, Conservative, Query>(bvh, ray, tmin, tmax, leaf);
    BoxTest<Conservative> test;
    bvh8_ray(r4, test.ray);
    test.tmin = _mm256_set1_ps(r4.tmin);
    wide_traverse_loop_avx512<Tree, float, Query>(bvh, test, [&] { return wide_tmax_float<Conservative>(tmax); }, leaf);
  }
};

template <class Tree>
using TraversalOf = std::conditional_t<std::is_same_v<Tree, Bvh8>, Traversal<Bvh8, Bvh8BoxTest>, Traversal<Bvh8Q, Bvh8QBoxTest>>;

}  // namespace avx512
}  // namespace detail

/// wide_traverse_leaves (bvh_wide.h) for the eight-wide trees (Bvh8, Bvh8Q) with the AVX-512
/// child ordering: the same leaves for every query (visiting order may differ among children of
/// equal entry distance). Call only when cpu_has_avx512().
template <class Tree, class LeafRange>
  requires(std::is_same_v<Tree, Bvh8> || std::is_same_v<Tree, Bvh8Q>)
void bvh8_traverse_leaves_avx512(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                                 BvhQuery query, LeafRange&& leaf) {
  if (bvh.empty()) return;
  using Run = detail::avx512::TraversalOf<Tree>;
  auto go = [&]<bool C>() {
    switch (query) {
      case BvhQuery::closest: return Run::template run<C, BvhQuery::closest>(bvh, ray, tmin, tmax, leaf);
      case BvhQuery::any: return Run::template run<C, BvhQuery::any>(bvh, ray, tmin, tmax, leaf);
      case BvhQuery::all: return Run::template run<C, BvhQuery::all>(bvh, ray, tmin, tmax, leaf);
    }
  };
  if (mode == BvhTraversal::conservative) return go.template operator()<true>();
  go.template operator()<false>();
}

}  // namespace rayproof

#pragma GCC diagnostic pop
