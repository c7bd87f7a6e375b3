#pragma once
/// Compressed wide BVH nodes: BvhWideQNode / BvhWideQ (8-bit child planes on a per-node grid),
/// quantize_wide that makes them from a full tree (bvh_wide.h's BvhWide), the choice between full
/// and compressed nodes (BvhNodes, RAYPROOF_BVH_NODES), and the four-wide SSE box test on decoded
/// planes. The eight-wide AVX2 test is in bvh_wide8.h. bvh_wide.h includes this header at its end,
/// so including either gives both kinds of node.
#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "rayproof/bvh_wide.h"

namespace rayproof {

/// A quantized (compressed) wide node: the children's float boxes stored as 8-bit offsets from a
/// per-node float origin in steps of a per-axis power of two (Ylitie, Karras, Laine, "Efficient
/// incoherent ray traversal on GPUs through compressed wide BVHs", HPG 2017, without the
/// float-exact reconstruction they drop). 128 bytes for eight children (two cache lines instead of
/// four), 80 for four. Child references, counts and `valid` mean what they mean in BvhWideNode.
///
/// Decoding (traversal and build alike): plane(q) = float(q) * scale[k] + origin[k], in float.
///  - float(q) is exact (q <= 255); scale[k] = 2^e with -126 <= e <= 119, so q * scale is exact
///    too (at most 8 significant bits; 255 * 2^119 < 2^127; a nonzero product is >= 2^-126,
///    normal). Only the sum rounds, once, to nearest. So decode() is one well-defined float per q
///    (an FMA contraction of the two would give the same float: the product is exact), and it is
///    monotonic in q (exact products increase with q; rounding to nearest is monotonic).
///  - Build (quantize_wide): origin[k] = the smallest lo[k] over the valid children; scale[k] =
///    the smallest power of two in range whose decode(255) >= the largest hi[k] (found by doubling
///    and checking the decoded float itself). Each child's lo is the largest q with decode(q) <= lo
///    (decode(0) = origin <= lo, so one exists), its hi the smallest q with decode(q) >= hi
///    (decode(255) >= hi, so one exists): both are found by stepping from an estimate while
///    checking the decoded float, so no estimate error or rounding can turn them inward.
///  - Hence every decoded child box contains the child's float box, which contains its primitives.
///    The box tests (bvh4_slab_test, bvh8_slab_test) then run unchanged on the decoded planes; their
///    guarantee (every box the exact double segment touches passes; bvh_wide8.h's header comment)
///    holds for any float box, so it holds for the decoded one, and a larger box only passes more.
///  - Assumes the default floating-point environment (round to nearest, no flush-to-zero or
///    denormals-are-zero), as the float box tests themselves do.
///  - Empty slots (and valid children with empty boxes, which no ray can pass) have their `valid`
///    bit clear: the tests mask every lane with `valid`, so they never pass.
///  - A node whose boxes have a non-finite plane, or whose extent does not fit 255 * 2^119 from its
///    origin, cannot be quantized: quantize_wide then returns nothing and the caller keeps the full
///    nodes (the traversal is per tree, not per node).
template <int N>
struct alignas(N == 8 ? 64 : 16) BvhWideQNode {
  static_assert(N == 4 || N == 8, "the box tests exist for four (SSE) and eight (AVX2) lanes");
  static constexpr int kWidth = N;
  /// No prefetch in wide_push: for two-line nodes it cost more than it saved. Measured with the
  /// loop compiled with and without it side by side (raw closest hit, AVX2, generated meshes of
  /// 82k (twice), 328k and 1.31M triangles): 0.955-0.993 of the time with it (medians of 7-9
  /// rounds); full nodes 0.942-1.023, mixed, so they keep it.
  static constexpr bool kPrefetch = false;
  float origin[3] = {};
  float scale[3] = {};
  std::uint8_t qlo[3][N] = {};  ///< qlo[axis][child]; same plane offsets as BvhWideNode::lo
  std::uint8_t qhi[3][N] = {};  ///< qhi[axis][child] (qlo, qhi contiguous: one array of 6 N)
  std::uint32_t child[N] = {};  ///< inner: node index; leaf: first prim_ids entry
  std::uint8_t count[N] = {};   ///< 0: inner child; else primitives in the leaf
  std::uint8_t valid = 0;       ///< bit i: slot i is used (and its box is not empty)

  /// The float plane q stands for on axis k (see above: exact product, one rounded sum).
  [[nodiscard]] static float decode(std::uint8_t q, float scale, float origin) {
    const float step = static_cast<float>(q) * scale;  // exact
    return step + origin;
  }
  /// Child i's decoded box (what the box tests use).
  [[nodiscard]] BvhBox box(int i) const {
    BvhBox b;
    for (int k = 0; k < 3; ++k) b.lo[k] = decode(qlo[k][i], scale[k], origin[k]), b.hi[k] = decode(qhi[k][i], scale[k], origin[k]);
    return b;
  }
};
using Bvh4QNode = BvhWideQNode<4>;
using Bvh8QNode = BvhWideQNode<8>;
static_assert(sizeof(Bvh4QNode) == 80);
static_assert(sizeof(Bvh8QNode) == 128);

/// A wide tree of quantized nodes (same shape, references and prim_ids as the BvhWide it came from).
template <int N>
struct BvhWideQ {
  using Node = BvhWideQNode<N>;
  static constexpr int kWidth = N;
  static constexpr std::uint32_t kMaxLeaf = 255;
  std::vector<Node, AlignedAllocator<Node, 64>> nodes;
  std::vector<std::uint32_t> prim_ids;
  int max_depth = 0;

  [[nodiscard]] bool empty() const { return nodes.empty(); }
  [[nodiscard]] std::size_t bytes() const { return nodes.size() * sizeof(Node) + prim_ids.size() * sizeof(std::uint32_t); }
};
using Bvh4Q = BvhWideQ<4>;
using Bvh8Q = BvhWideQ<8>;

namespace detail {

/// One full node quantized (see BvhWideQNode); false when it cannot be (non-finite planes, or an
/// extent beyond 255 * 2^119).
template <int N>
[[nodiscard]] bool quantize_node(const BvhWideNode<N>& in, BvhWideQNode<N>& out) {
  out = BvhWideQNode<N>{};
  for (int i = 0; i < N; ++i) out.child[i] = in.child[i], out.count[i] = in.count[i];
  int live = 0;
  for (int i = 0; i < N; ++i)
    if ((in.valid >> i & 1) && !in.box(i).empty()) live |= 1 << i;
  out.valid = static_cast<std::uint8_t>(live);
  for (int k = 0; k < 3; ++k) {
    float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
    for (int i = 0; i < N; ++i)
      if (live >> i & 1) lo = std::min(lo, in.lo[k][i]), hi = std::max(hi, in.hi[k][i]);
    for (int i = 0; i < N; ++i) out.qlo[k][i] = 255, out.qhi[k][i] = 0;  // empty slots: inverted (valid clear anyway)
    if (!live) continue;
    if (!std::isfinite(lo) || !std::isfinite(hi)) return false;
    // The smallest power of two (from an estimate, then checked on the decoded float) whose
    // decode(255) reaches hi.
    const double extent = double(hi) - double(lo);
    int e = extent > 0 ? std::ilogb(extent / 255.0) : -126;
    e = std::clamp(e, -126, 119);
    while (e > -126 && BvhWideQNode<N>::decode(255, std::ldexp(1.0f, e - 1), lo) >= hi) --e;
    while (e < 119 && BvhWideQNode<N>::decode(255, std::ldexp(1.0f, e), lo) < hi) ++e;
    const float scale = std::ldexp(1.0f, e);
    if (!(BvhWideQNode<N>::decode(255, scale, lo) >= hi)) return false;
    out.origin[k] = lo, out.scale[k] = scale;
    auto dec = [&](int q) { return BvhWideQNode<N>::decode(static_cast<std::uint8_t>(q), scale, lo); };
    for (int i = 0; i < N; ++i) {
      if (!(live >> i & 1)) continue;
      const float l = in.lo[k][i], h = in.hi[k][i];
      int ql = std::clamp(static_cast<int>(std::floor((double(l) - double(lo)) / double(scale))), 0, 255);
      while (ql > 0 && dec(ql) > l) --ql;         // decode(0) = origin <= l
      while (ql < 255 && dec(ql + 1) <= l) ++ql;  // the largest q still <= l (tightest)
      int qh = std::clamp(static_cast<int>(std::ceil((double(h) - double(lo)) / double(scale))), ql, 255);
      while (qh < 255 && dec(qh) < h) ++qh;       // decode(255) >= h
      while (qh > ql && dec(qh - 1) >= h) --qh;   // the smallest q still >= h (tightest)
      out.qlo[k][i] = static_cast<std::uint8_t>(ql), out.qhi[k][i] = static_cast<std::uint8_t>(qh);
    }
  }
  return true;
}

}  // namespace detail

/// The quantized copy of a wide tree (same nodes in the same order, same references, prim_ids
/// copied), or nothing when a node cannot be quantized (see BvhWideQNode). A separate pass after
/// collapse_wide (and after any rewrite of the leaf references, which it copies). Nodes are
/// independent: `parallel_for(n, f)` may run f(0) .. f(n - 1) on several threads (as build_bvh's;
/// the default runs them in order).
template <int N, class ParallelFor = void (*)(std::size_t, const std::function<void(std::size_t)>&)>
[[nodiscard]] std::optional<BvhWideQ<N>> quantize_wide(
    const BvhWide<N>& w, ParallelFor&& parallel_for = [](std::size_t n, const std::function<void(std::size_t)>& f) {
      for (std::size_t i = 0; i < n; ++i) f(i);
    }) {
  BvhWideQ<N> q;
  q.nodes.resize(w.nodes.size());
  constexpr std::size_t kChunk = 1024;
  std::atomic<bool> ok{true};
  parallel_for((w.nodes.size() + kChunk - 1) / kChunk, [&](std::size_t c) {
    for (std::size_t i = c * kChunk, end = std::min(w.nodes.size(), i + kChunk); i < end; ++i)
      if (!detail::quantize_node(w.nodes[i], q.nodes[i])) ok.store(false, std::memory_order_relaxed);
  });
  if (!ok.load()) return std::nullopt;
  q.prim_ids = w.prim_ids;
  q.max_depth = w.max_depth;
  return q;
}

/// Which nodes a wide tree is built with: full float boxes (BvhWideNode) or quantized ones
/// (BvhWideQNode); automatic follows RAYPROOF_BVH_NODES, then the tree's size (bvh_nodes_choice).
enum class BvhNodes { automatic, full, compressed };

/// The automatic choice takes compressed nodes when the full ones would take more than this. Measured
/// (bench/node_bench, AVX2, one thread, robust / certified / float, closest and any, medians of
/// 7-9 interleaved rounds): with 1.1-1.3 MB of full nodes (bunny00, refined_elephant) compressed
/// nodes were 0-5% slower (decoding costs more than the lines saved); with 5.9 MB (a generated mesh
/// of 328k triangles) mixed, 0.92-1.05 of the time over two runs; with 15.7 MB (1.31M triangles)
/// faster in each of three runs (robust 0.88-0.99). 8 MiB lies between the last two.
inline constexpr std::size_t kCompressedNodesAbove = std::size_t(8) << 20;

/// The RAYPROOF_BVH_NODES environment variable: unset, empty or "auto": automatic; "full";
/// "compressed". Any other value throws std::invalid_argument naming them.
[[nodiscard]] inline BvhNodes bvh_nodes_from_env() {
  const char* e = std::getenv("RAYPROOF_BVH_NODES");
  if (!e || !*e || std::strcmp(e, "auto") == 0) return BvhNodes::automatic;
  if (std::strcmp(e, "full") == 0) return BvhNodes::full;
  if (std::strcmp(e, "compressed") == 0) return BvhNodes::compressed;
  std::string msg = "RAYPROOF_BVH_NODES='";
  msg.append(e).append("': expected auto, full or compressed");
  throw std::invalid_argument(msg);
}

/// The node kind for a request and a tree whose full nodes take `full_node_bytes`: automatic
/// follows RAYPROOF_BVH_NODES, then compressed above kCompressedNodesAbove, else full. Never
/// returns automatic.
[[nodiscard]] inline BvhNodes bvh_nodes_choice(BvhNodes want = BvhNodes::automatic, std::size_t full_node_bytes = 0) {
  if (want == BvhNodes::automatic) want = bvh_nodes_from_env();
  if (want == BvhNodes::automatic) return full_node_bytes > kCompressedNodesAbove ? BvhNodes::compressed : BvhNodes::full;
  return want;
}

[[nodiscard]] inline const char* to_string(BvhNodes n) {
  switch (n) {
    case BvhNodes::automatic: return "auto";
    case BvhNodes::full: return "full";
    case BvhNodes::compressed: return "compressed";
  }
  return "?";
}

namespace detail {

/// Four quantized planes at byte offset `off` of `q` decoded to floats: each q * scale + origin
/// (u8 -> i32 -> float, exact; product, exact; one rounded sum: BvhWideQNode's decode()).
[[gnu::always_inline]] inline __m128 bvh4q_decode(const std::uint8_t* q, __m128 scale, __m128 origin) {
  std::int32_t four;
  std::memcpy(&four, q, 4);
  const __m128i zero = _mm_setzero_si128();
  const __m128i i32 = _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(four), zero), zero);
  return _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(i32), scale), origin);
}

template <bool Conservative>
struct Bvh4QBoxTest {
  Bvh4RayF ray;
  __m128 tmin;
  [[gnu::always_inline]] int operator()(const BvhWideQNode<4>& n, float tmax, float* t) const {
    const std::uint8_t* q = &n.qlo[0][0];
    auto plane = [&](int off, int k) { return bvh4q_decode(q + off, _mm_set1_ps(n.scale[k]), _mm_set1_ps(n.origin[k])); };
    __m128 te;
    const int mask = bvh4_slab_test<Conservative>(plane, n.valid, ray, tmin, _mm_set1_ps(tmax), te);
    _mm_store_ps(t, te);
    return mask;
  }
};

template <>
struct WideTraversal<Bvh4Q> {
  template <bool Conservative, BvhQuery Query, class Leaf>
  static void run(const Bvh4Q& bvh, const Ray<double>& ray, double tmin, const double& tmax, Leaf& leaf) {
    Bvh4RayF rf;
    if (!make_bvh4_ray(ray, Conservative, tmin, rf))
      return wide_traverse_double<Bvh4Q, Conservative, Query>(bvh, ray, tmin, tmax, leaf);
    const Bvh4QBoxTest<Conservative> test{rf, _mm_set1_ps(rf.tmin)};
    wide_traverse_loop<Bvh4Q, float, Query>(bvh, test, [&] { return wide_tmax_float<Conservative>(tmax); }, leaf);
  }
};

}  // namespace detail

}  // namespace rayproof
