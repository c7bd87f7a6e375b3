#pragma once
/// Packets of up to eight rays through the eight-wide tree (Bvh8, bvh_wide8.h): one AVX2 lane per
/// ray. Each node is fetched once for the packet; each of its children's boxes is tested against
/// the packet's live rays in lanes; leaves go to the caller lane by lane, so any per-ray leaf code
/// works unchanged. Meant for coherent rays (camera tiles of 4x2 pixels): the API takes any eight
/// rays, the caller groups them.
///
/// Box test. Every ray is prepared by make_bvh4_ray (bvh_wide.h), exactly as the single-ray path
/// prepares it, and its per-axis floats are transposed into lanes. The single-ray test computes,
/// per axis, near = (plane_near - o_near) * inv_near and far = (plane_far - o_far) * inv_far, where the near
/// plane is lo when 1/d >= 0 (and hi when 1/d < 0, -0 included), o_near >= o and o_far <= o (for
/// 1/d >= 0; mirrored otherwise). Hence the lo plane is always paired with the origin bound
/// make_bvh4_ray gives the lo plane (o_near and inv_near when 1/d >= 0, o_far and inv_far
/// otherwise), and the hi plane with the other ones. Here each lane computes (lo - o_lo) * inv_lo
/// and (hi - o_hi) * inv_hi with those per-ray floats and picks near and far by the ray's sign bit
/// (a blend: a selection, no arithmetic), then does the max / min from the ray's float tmin / tmax
/// and the ordered comparison of bvh8_test, in the same order with the same operands (no FMA: the
/// target is "avx2" without "fma"). When all live rays share the sign of 1/d
/// on every axis (most camera tiles), the planes are loaded as near / far directly and no blend is
/// needed: the same differences and products of the same floats. Every lane therefore computes bit for bit
/// what the single-ray test computes for that ray and that box, and the conservative guarantee of
/// bvh_wide8.h's header carries over lane by lane: under conservative traversal every box the
/// exact double segment [tmin, tmax] of a ray touches passes in that ray's lane.
///
/// Traversal. A stack entry is a child and the mask of the lanes that enter it, with their entry
/// distances. A popped entry drops (closest hit) the lanes whose entry lies beyond their own best t
/// so far, and (any hit) the lanes already done. Closest hit visits children nearest first by the
/// least entry distance among their lanes; any and all hits in slot order. A leaf is handed to
/// `leaf(lane, first, count)` for each lane of its mask; for closest hit the caller lowers
/// tmax[lane]; for any hit `true` ends that lane. Rays out of the float path's range (make_bvh4_ray
/// fails) take the single-ray double traversal of bvh_wide.h on their own.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide8.h"

namespace rayproof {

inline constexpr int kPacketWidth = 8;

namespace detail {

/// Eight rays transposed: per axis the origin bound and the reciprocal paired with the lo and with
/// the hi planes, and the sign mask (all ones: 1/d < 0, the near plane is hi).
struct Packet8RayF {
  alignas(32) float o_lo[3][8];
  alignas(32) float o_hi[3][8];
  alignas(32) float inv_lo[3][8];
  alignas(32) float inv_hi[3][8];
  alignas(32) std::int32_t neg[3][8];
  alignas(32) float tmin[8];
};

/// Lane `lane` of the packet from a prepared single ray.
inline void packet_set_lane(Packet8RayF& p, int lane, const Bvh4RayF& r) {
  for (int k = 0; k < 3; ++k) {
    const bool neg = r.near_off[k] != 4 * k;  // the near plane is hi
    const float on = _mm_cvtss_f32(r.o_near[k]), of = _mm_cvtss_f32(r.o_far[k]);
    p.o_lo[k][lane] = neg ? of : on;
    p.o_hi[k][lane] = neg ? on : of;
    const float in = _mm_cvtss_f32(r.inv_near[k]), inf_ = _mm_cvtss_f32(r.inv_far[k]);
    p.inv_lo[k][lane] = neg ? inf_ : in;
    p.inv_hi[k][lane] = neg ? in : inf_;
    p.neg[k][lane] = neg ? -1 : 0;
  }
  p.tmin[lane] = r.tmin;
}

/// The packet's registers. When every live lane has the same sign of 1/d on an axis (`uniform`:
/// the common case for a camera tile), the near and far planes of that axis are the same for all
/// lanes: o_near / o_far are then the origins paired with them and near_off / far_off their float
/// offsets in the node (lo[k] at 8k, hi[k] at 24 + 8k), and the test loads the planes it needs
/// instead of computing both and blending; each lane still computes the same difference and
/// product of the same floats.
struct Packet8Regs {
  __m256 o_lo[3], o_hi[3], inv_lo[3], inv_hi[3], neg[3], tmin;
  __m256 o_near[3], o_far[3], inv_near[3], inv_far[3];
  int near_off[3], far_off[3];
  bool uniform = false;
};

[[gnu::target("avx2"), gnu::always_inline]] inline Packet8Regs packet_regs(const Packet8RayF& p, unsigned live) {
  Packet8Regs r;
  r.uniform = true;
  for (int k = 0; k < 3; ++k) {
    r.o_lo[k] = _mm256_load_ps(p.o_lo[k]), r.o_hi[k] = _mm256_load_ps(p.o_hi[k]);
    r.inv_lo[k] = _mm256_load_ps(p.inv_lo[k]), r.inv_hi[k] = _mm256_load_ps(p.inv_hi[k]);
    r.neg[k] = _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(p.neg[k])));
    const unsigned negs = unsigned(_mm256_movemask_ps(r.neg[k])) & live;
    const bool neg = negs != 0;
    r.uniform = r.uniform && (negs == 0 || negs == live);
    r.o_near[k] = neg ? r.o_hi[k] : r.o_lo[k], r.o_far[k] = neg ? r.o_lo[k] : r.o_hi[k];
    r.inv_near[k] = neg ? r.inv_hi[k] : r.inv_lo[k], r.inv_far[k] = neg ? r.inv_lo[k] : r.inv_hi[k];
    r.near_off[k] = neg ? 24 + 8 * k : 8 * k, r.far_off[k] = neg ? 8 * k : 24 + 8 * k;
  }
  r.tmin = _mm256_load_ps(p.tmin);
  return r;
}

/// Child `c` of `n` against the eight rays: the lanes' hit bits (before any lane mask) and entry
/// distances. Per lane the operations of bvh8_test on that lane's ray (see the header comment).
/// `planes` holds the node's float planes laid out as Bvh8Node's lo[3][8] then hi[3][8] (the node
/// itself, or a compressed node's decoded planes: see node_planes).
template <bool Conservative, bool Uniform>
[[gnu::target("avx2"), gnu::always_inline]] inline int packet8_child_test(const float* planes, int c, const Packet8Regs& r,
                                                                        __m256 tmax, __m256& t_enter) {
  __m256 t0 = r.tmin, t1 = tmax;
  const float* f = planes + c;
  for (int k = 0; k < 3; ++k) {
    __m256 near, far;
    if constexpr (Uniform) {
      near = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(f + r.near_off[k]), r.o_near[k]), r.inv_near[k]);
      far = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(f + r.far_off[k]), r.o_far[k]), r.inv_far[k]);
    } else {
      const __m256 tlo = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(f + 8 * k), r.o_lo[k]), r.inv_lo[k]);
      const __m256 thi = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(f + 24 + 8 * k), r.o_hi[k]), r.inv_hi[k]);
      near = _mm256_blendv_ps(tlo, thi, r.neg[k]), far = _mm256_blendv_ps(thi, tlo, r.neg[k]);
    }
    t0 = _mm256_max_ps(near, t0);  // NaN near: t0, as in bvh8_test
    t1 = _mm256_min_ps(far, t1);
  }
  return bvh8_slab_finish(t0, t1, t_enter);
}

/// The lanes of `mask` whose entry distance is within their tmax (ordered: false for NaN).
[[gnu::target("avx2"), gnu::always_inline]] inline unsigned packet_within(__m256 t, __m256 tmax, unsigned mask) {
  return mask & unsigned(_mm256_movemask_ps(_mm256_cmp_ps(t, tmax, _CMP_LE_OQ)));
}

/// The least entry distance among the lanes of `mask` (the order key of closest hit).
[[gnu::target("avx2"), gnu::always_inline]] inline float packet_min(__m256 t, unsigned mask) {
  const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  const __m256i on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(mask)), bits), bits);
  __m256 v = _mm256_blendv_ps(_mm256_set1_ps(std::numeric_limits<float>::infinity()), t, _mm256_castsi256_ps(on));
  v = _mm256_min_ps(v, _mm256_permute2f128_ps(v, v, 1));
  v = _mm256_min_ps(v, _mm256_shuffle_ps(v, v, 0x4e));
  v = _mm256_min_ps(v, _mm256_shuffle_ps(v, v, 0xb1));
  return _mm256_cvtss_f32(v);
}

struct alignas(32) PacketEntry {
  __m256 t;            ///< the lanes' entry distances
  std::uint32_t ref;   ///< inner: node index; leaf: first slot
  std::uint32_t count; ///< 0: inner node
  std::uint32_t mask;  ///< lanes entering
};

/// The float planes of a node in Bvh8Node's layout: a full node's own; a compressed node's decoded
/// into `buf` with bvh8q_decode, the decoder of the single-ray test (the same floats, which contain
/// the full node's planes: proof at BvhWideQNode), so the lane-by-lane argument above holds for them.
[[gnu::target("avx2"), gnu::always_inline]] inline const float* node_planes(const Bvh8Node& n, float*) { return &n.lo[0][0]; }
[[gnu::target("avx2"), gnu::always_inline]] inline const float* node_planes(const Bvh8QNode& n, float* buf) {
  for (int k = 0; k < 3; ++k) {
    const __m256 scale = _mm256_broadcast_ss(&n.scale[k]), origin = _mm256_broadcast_ss(&n.origin[k]);
    _mm256_store_ps(buf + 8 * k, bvh8q_decode(&n.qlo[k][0], scale, origin));
    _mm256_store_ps(buf + 24 + 8 * k, bvh8q_decode(&n.qhi[k][0], scale, origin));
  }
  return buf;
}

template <bool Conservative, BvhQuery Query, bool Uniform, class Tree, class Leaf>
[[gnu::target("avx2")]] void packet8_run(const Tree& bvh, const Packet8Regs& r, unsigned live, const double* tmax,
                                         Leaf& leaf) {
  alignas(32) float tmax_f[8];
  for (int i = 0; i < 8; ++i) tmax_f[i] = (live >> i & 1) ? wide_tmax_float<Conservative>(tmax[i]) : 0.0f;
  __m256 tmaxv = _mm256_load_ps(tmax_f);
  constexpr std::size_t kLocal = 128;
  PacketEntry local[kLocal];
  std::vector<PacketEntry> heap;
  PacketEntry* stack = local;
  const std::size_t need = 7 * static_cast<std::size_t>(bvh.max_depth) + 8;
  if (need > kLocal) heap.resize(need), stack = heap.data();
  int top = 0;
  const auto* nodes = bvh.nodes.data();
  alignas(32) float decoded[48];  // a compressed node's planes (unused for full nodes)
  unsigned done = 0;  // any hit: lanes that found one
  PacketEntry e{_mm256_set1_ps(-std::numeric_limits<float>::infinity()), 0, 0, live};
  if constexpr (Query == BvhQuery::closest) e.mask = packet_within(e.t, tmaxv, live);  // NaN tmax: not traversed
  while (true) {
    unsigned m = e.mask & ~done;
    if constexpr (Query == BvhQuery::closest) m = packet_within(e.t, tmaxv, m);
    if (m) {
      if (e.count) {
        for (unsigned l = m; l; l &= l - 1) {
          const int lane = __builtin_ctz(l);
          if (leaf(lane, e.ref, e.count) && Query == BvhQuery::any) done |= 1u << lane;
          if constexpr (Query == BvhQuery::closest) tmax_f[lane] = wide_tmax_float<Conservative>(tmax[lane]);
        }
        if constexpr (Query == BvhQuery::closest) tmaxv = _mm256_load_ps(tmax_f);
      } else {
        const auto& n = nodes[e.ref];
        const float* planes = node_planes(n, decoded);
        PacketEntry kids[8];
        float key[8];
        int nk = 0;
        for (unsigned v = n.valid; v; v &= v - 1) {
          const int c = __builtin_ctz(v);
          __m256 t;
          const unsigned hit = unsigned(packet8_child_test<Conservative, Uniform>(planes, c, r, tmaxv, t)) & m;
          if (!hit) continue;
          kids[nk] = PacketEntry{t, n.child[c], n.count[c], hit};
          if constexpr (Query == BvhQuery::closest) key[nk] = packet_min(t, hit);
          ++nk;
        }
        if (nk == 1) {
          e = kids[0];
          continue;
        }
        if (nk > 1) {
          if constexpr (Query == BvhQuery::closest) {
            // Farthest first on the stack, the nearest visited next (insertion sort, descending key).
            int order[8];
            for (int i = 0; i < nk; ++i) {
              int j = i;
              for (; j > 0 && key[order[j - 1]] < key[i]; --j) order[j] = order[j - 1];
              order[j] = i;
            }
            for (int i = 0; i < nk - 1; ++i) stack[top++] = kids[order[i]];
            e = kids[order[nk - 1]];
          } else {
            for (int i = nk - 1; i > 0; --i) stack[top++] = kids[i];
            e = kids[0];
          }
          continue;
        }
      }
    }
    if (top == 0) return;
    e = stack[--top];
  }
}

/// The packet's registers, then the loop for its mode and sign pattern (the query fixed by the caller).
template <BvhQuery Query, class Tree, class Leaf>
[[gnu::target("avx2")]] void packet8_go(const Tree& bvh, const Packet8RayF& p, unsigned in, const double* tmax,
                                        bool conservative, Leaf& leaf) {
  const Packet8Regs r = packet_regs(p, in);
  if (conservative) {
    if (r.uniform) packet8_run<true, Query, true>(bvh, r, in, tmax, leaf);
    else packet8_run<true, Query, false>(bvh, r, in, tmax, leaf);
  } else {
    if (r.uniform) packet8_run<false, Query, true>(bvh, r, in, tmax, leaf);
    else packet8_run<false, Query, false>(bvh, r, in, tmax, leaf);
  }
}

}  // namespace detail

/// Up to eight rays through the eight-wide tree, full (Bvh8) or compressed (Bvh8Q) nodes (needs AVX2: call only when cpu_has_avx2()).
/// `rays`, `tmin`, `tmax` have eight entries; lanes outside `live` (bit i: rays[i]) are ignored.
/// `leaf(lane, first, count)` gets the leaf-order slots [first, first + count) of one leaf for one
/// lane and returns true to end that lane (honoured for any hit); for closest hit it lowers
/// tmax[lane] (read again after each leaf) to the lane's best t so far. The same rays through
/// wide_traverse_leaves visit, lane by lane, leaves whose boxes pass the same box test (the order
/// differs: see the header comment).
/// The query as a template argument: a caller that asks one kind of query compiles only its loop
/// (each loop is instantiated per mode and sign pattern, so the runtime overload below compiles three).
template <BvhQuery Query, class Tree, class LeafLane>
  requires(std::is_same_v<Tree, Bvh8> || std::is_same_v<Tree, Bvh8Q>)
void bvh8_packet_traverse_leaves(const Tree& bvh, const Ray<double>* rays, const double* tmin, const double* tmax,
                                 unsigned live, BvhTraversal mode, LeafLane&& leaf) {
  if (bvh.empty() || !(live &= 0xffu)) return;
  const bool conservative = mode == BvhTraversal::conservative;
  detail::Packet8RayF p{};
  unsigned in = 0;
  for (unsigned l = live; l; l &= l - 1) {
    const int lane = __builtin_ctz(l);
    detail::Bvh4RayF r4;
    if (detail::make_bvh4_ray(rays[lane], conservative, tmin[lane], r4)) {
      detail::packet_set_lane(p, lane, r4);
      in |= 1u << lane;
    } else {  // out of the float range: the single-ray double box test
      auto one = [&](std::uint32_t first, std::uint32_t count) { return leaf(lane, first, count); };
      if (conservative) detail::wide_traverse_double<Tree, true, Query>(bvh, rays[lane], tmin[lane], tmax[lane], one);
      else detail::wide_traverse_double<Tree, false, Query>(bvh, rays[lane], tmin[lane], tmax[lane], one);
    }
  }
  if (!in) return;
  detail::packet8_go<Query>(bvh, p, in, tmax, conservative, leaf);
}

/// The query chosen at run time.
template <class Tree, class LeafLane>
  requires(std::is_same_v<Tree, Bvh8> || std::is_same_v<Tree, Bvh8Q>)
void bvh8_packet_traverse_leaves(const Tree& bvh, const Ray<double>* rays, const double* tmin, const double* tmax,
                                 unsigned live, BvhTraversal mode, BvhQuery query, LeafLane&& leaf) {
  switch (query) {
    case BvhQuery::closest: return bvh8_packet_traverse_leaves<BvhQuery::closest>(bvh, rays, tmin, tmax, live, mode, leaf);
    case BvhQuery::any: return bvh8_packet_traverse_leaves<BvhQuery::any>(bvh, rays, tmin, tmax, live, mode, leaf);
    case BvhQuery::all: return bvh8_packet_traverse_leaves<BvhQuery::all>(bvh, rays, tmin, tmax, live, mode, leaf);
  }
}

/// Pixel numbers (j * width + i) of a width x height image in tiles of tile_w x tile_h pixels (4x2:
/// one packet of eight coherent camera rays per tile), tiles row by row, pixels row by row inside a
/// tile; tiles cut by the image's right or bottom edge hold fewer pixels. A permutation of
/// 0 .. width * height - 1 (empty for a non-positive size).
[[nodiscard]] inline std::vector<std::uint32_t> packet_tile_order(int width, int height, int tile_w = 4, int tile_h = 2) {
  std::vector<std::uint32_t> out;
  if (width <= 0 || height <= 0 || tile_w <= 0 || tile_h <= 0) return out;
  out.reserve(std::size_t(width) * std::size_t(height));
  for (int tj = 0; tj < height; tj += tile_h)
    for (int ti = 0; ti < width; ti += tile_w)
      for (int j = tj; j < std::min(tj + tile_h, height); ++j)
        for (int i = ti; i < std::min(ti + tile_w, width); ++i) out.push_back(std::uint32_t(j) * std::uint32_t(width) + std::uint32_t(i));
  return out;
}

}  // namespace rayproof
