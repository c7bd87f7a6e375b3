#pragma once
// The query machinery of Accel (accel_closest / any / all.cpp: single rays and batches; accel_packet.h:
// packets of eight): the kernel dispatch, the leaf kernels (group lanes, certified's stages, slot by
// slot), the single-ray closest / any hit and the TBB batch loop. Internal to rayproof_scene.

#include <emmintrin.h>

#include <type_traits>

#include "scene/accel.h"
#include "scene/batch_threads.h"
#include "scene/kernels.h"

namespace rayproof::scene::detail {

using detail::Crossing;
using detail::TriAlgo;

/// Runs `f(kernel)` with the kernel type the method names.
template <class F>
decltype(auto) with_kernel(const Scene& s, const Vec3<double>* v, std::uint32_t n, const SceneMethod& m, F&& f) {
  using detail::CompiledKernel;
  const Method* g = m.generic;
  switch (m.fast) {
    case FastKernel::mt_float: { CompiledKernel<float, TriAlgo::moller_trumbore> k{s, v, n}; return f(k); }
    case FastKernel::mt_double: { CompiledKernel<double, TriAlgo::moller_trumbore> k{s, v, n}; return f(k); }
    case FastKernel::cramer_float: { CompiledKernel<float, TriAlgo::cramer> k{s, v, n}; return f(k); }
    case FastKernel::cramer_double: { CompiledKernel<double, TriAlgo::cramer> k{s, v, n}; return f(k); }
    case FastKernel::watertight_float: { CompiledKernel<float, TriAlgo::watertight> k{s, v, n}; return f(k); }
    case FastKernel::watertight_double: { CompiledKernel<double, TriAlgo::watertight> k{s, v, n}; return f(k); }
    case FastKernel::robust: { CompiledKernel<float, TriAlgo::robust> k{s, v, n, g}; return f(k); }
    case FastKernel::certified: {
      CompiledKernel<double, TriAlgo::certified> k{s, v, n, g, m.triangle_fallback};
      return f(k);
    }
    case FastKernel::none: break;
  }
  detail::GenericKernel k{s, *m.generic};
  return f(k);
}

/// What a query traverses: the nodes, the leaf records, the packed groups (null: none) and the
/// group kernels' path.
template <class Tree>
struct Leaves {
  const Tree& bvh;  ///< Bvh4 (SSE path) or Bvh8 (AVX2 path)
  const LeafPrim* prims;
  const detail::TriGroup* groups;
  detail::LeafSimd simd;
};

template <class Tree, class G>
Leaves<Tree> leaves_of(const Tree& bvh, const std::vector<LeafPrim>& prims, const G& groups) {
  const detail::LeafSimd simd = detail::leaf_simd();
  return {bvh, prims.data(), groups.empty() || simd == detail::LeafSimd::off ? nullptr : groups.data(), simd};
}

/// The kernels with group versions (leaf_simd.h): `float`, `robust` and `certified`.
template <class K>
constexpr bool kGroupKernel = std::is_same_v<K, detail::CompiledKernel<float, TriAlgo::moller_trumbore>> ||
                              std::is_same_v<K, detail::CompiledKernel<float, TriAlgo::robust>> ||
                              std::is_same_v<K, detail::CompiledKernel<double, TriAlgo::certified>>;

/// Lane i of group g as a float triangle.
inline Triangle<float> lane_triangle(const detail::TriGroup& g, int i) {
  auto p = [&](int v) { return Vec3<float>{g.p[v][0][i], g.p[v][1][i], g.p[v][2][i]}; };
  return {p(0), p(1), p(2)};
}

/// certified's leaves: when on (certified_screen(), off by default: it does not pay), first the
/// float screen on the group's float vertices (the roundings of the double ones); then the leaf
/// records (ids and vertex indices), the double vertices, stage 1's proven misses in lanes
/// (AVX2), the other lanes through the per-primitive kernel.
template <class K, class L_, class Emit>
bool certified_leaf(const K& k, const L_& L, std::uint32_t first, std::uint32_t count, Emit& emit) {
  using namespace detail;
  const std::uint32_t end = first + count;
  const bool screen = L.simd != LeafSimd::scalar && certified_screen();
  for (std::uint32_t g0 = first; g0 < end; g0 += kLanes) {
    unsigned in = end - g0 >= std::uint32_t(kLanes) ? (1u << kLanes) - 1 : (1u << (end - g0)) - 1;
    Crossing c[2];
    unsigned miss = 0;
    if (screen) {
      // Triangle lanes: tags without the top bit (pad and scalar lanes have it).
      const TriGroup& g = L.groups[g0 / kLanes];
      const unsigned not_tri = unsigned(_mm_movemask_ps(_mm_load_ps(reinterpret_cast<const float*>(g.tag))));
      in &= ~certified_group_float_misses(k.lane_ray, g, in & ~not_tri);
      if (!in) continue;
    }
    if (L.simd == LeafSimd::avx2) {
      alignas(32) double p[3][3][kLanes];
      unsigned tri = 0;
      for (int i = 0; i < kLanes; ++i) {
        const LeafPrim& lp = L.prims[g0 + i];
        const bool is_tri = (in >> i & 1) && lp.id < k.ntri;
        tri |= unsigned(is_tri) << i;
        for (int v = 0; v < 3; ++v) {
          const Vec3<double> x = is_tri ? k.verts[lp.v[v]] : Vec3<double>{};  // (no vertex array without triangles)
          p[v][0][i] = x.x, p[v][1][i] = x.y, p[v][2][i] = x.z;
        }
      }
      miss = certified_group_misses_avx2(k.ray_d, p, tri);
    }
    for (unsigned m = in & ~miss; m; m &= m - 1) {
      const LeafPrim& lp = L.prims[g0 + __builtin_ctz(m)];
      const int n = k.crossings(lp, c);
      if (n && emit(lp.id, c, n)) return true;
    }
  }
  return false;
}

/// One leaf's slots [first, first + count) through the group kernels (float, robust): emit(id, crossings, n) for
/// every primitive with crossings, in slot order within each group; true when emit asks to stop.
template <class K, class L_, class Emit>
bool group_leaf(const K& k, const L_& L, std::uint32_t first, std::uint32_t count, Emit& emit) {
  using namespace detail;
  constexpr bool kRobust = std::is_same_v<K, CompiledKernel<float, TriAlgo::robust>>;
  const std::uint32_t end = first + count;
  // Every line of the leaf's groups requested at once (their tags are in each group's last line,
  // read first): the misses overlap instead of following one another.
  for (std::uint32_t g0 = first; g0 < end; g0 += kLanes) {
    const char* p = reinterpret_cast<const char*>(&L.groups[g0 / kLanes]);
    for (std::size_t off = 0; off < sizeof(TriGroup); off += 64) _mm_prefetch(p + off, _MM_HINT_T0);
  }
  for (std::uint32_t g0 = first; g0 < end; g0 += kLanes) {
    const unsigned in = end - g0 >= std::uint32_t(kLanes) ? (1u << kLanes) - 1 : (1u << (end - g0)) - 1;
    Crossing c[2];
    const TriGroup& g = L.groups[g0 / kLanes];
    // The lanes' kinds from the tags' two top bits (padding lies past `in`: leaves end before it).
    static_assert(kLanes == 4 && kScalarLane == 0x80000000u && kDeadLane == 0x40000000u);
    const __m128i tags = _mm_load_si128(reinterpret_cast<const __m128i*>(g.tag));
    const unsigned bit31 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(tags)));
    const unsigned bit30 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_slli_epi32(tags, 1))));
    const unsigned scalar = in & bit31;
    const unsigned dead = in & ~bit31 & bit30, tri = in & ~bit31 & ~bit30;
    // Lanes that the per-primitive kernel finishes (in slot order with the lane results).
    unsigned finish;
    RobustLanes lanes;
    lanes.hit = 0;
    if constexpr (kRobust) {
      k.leaf_ready();
      if (!k.ray_ok) {
        finish = 0;  // the scalar kernel's `invalid`: no triangle crossing
      } else if (L.simd == LeafSimd::avx2) {
        robust_group_avx2(k.lane_ray, g, robust_screen_avx2() ? tri & ~robust_group_float_misses(k.lane_ray, g, tri) : tri,
                          lanes);
        finish = lanes.special;
      } else if (L.simd == LeafSimd::sse) {
        finish = tri & ~robust_group_float_misses(k.lane_ray, g, tri);  // the float screen's misses need no kernel
      } else {
        finish = tri;  // dead lanes: the scalar kernel reports nothing for them either
      }
    } else {
      finish = L.simd == LeafSimd::scalar ? tri | dead : mt_group_survivors(k.ray, g, tri | dead);
    }
    for (unsigned m = finish | lanes.hit | scalar; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      const std::uint32_t id = g.tag[i] & kLaneIdMask;
      int n;
      if (scalar >> i & 1) {
        n = k.crossings(L.prims[g0 + i], c);
      } else if (lanes.hit >> i & 1) {
        c[0] = {static_cast<Contact>(lanes.contact[i]), double(lanes.t[i]), double(lanes.b1[i]), double(lanes.b2[i])};
        n = 1;
      } else {
        n = k.triangle_crossings(lane_triangle(g, i), c);
      }
      if (n && emit(id, c, n)) return true;
    }
  }
  return false;
}

/// wide_traverse_leaves (rayproof/bvh_wide.h) with the query fixed at compile time. That one
/// takes the query at run time, so every leaf callable it is given instantiates the loops of all
/// three queries (each in both modes, with the float and the double box test); each caller here
/// has one query, and only its loops are built (a third of the traversal code to compile).
template <BvhQuery Query, class Tree, class LeafRange>
void traverse_leaves(const Tree& bvh, const Ray<double>& ray, double tmin, const double& tmax, BvhTraversal mode,
                     LeafRange& leaf) {
  if (bvh.empty()) return;
  using Run = rayproof::detail::WideTraversal<Tree>;
  if (mode == BvhTraversal::conservative) return Run::template run<true, Query>(bvh, ray, tmin, tmax, leaf);
  Run::template run<false, Query>(bvh, ray, tmin, tmax, leaf);
}

/// Runs the traversal with the leaf groups when the kernel has group versions and the groups
/// exist, else slot by slot: emit(id, crossings, n) as in group_leaf.
template <BvhQuery Query, class K, class L_, class Emit>
void traverse_with(const L_& L, const K& k, QueryRange q, const double& tmax, BvhTraversal mode, Emit&& emit) {
  if constexpr (kGroupKernel<K>) {
    if (L.groups) {
      auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        if constexpr (std::is_same_v<K, detail::CompiledKernel<double, TriAlgo::certified>>) {
          return certified_leaf(k, L, first, count, emit);
        } else {
          return group_leaf(k, L, first, count, emit);
        }
      };
      traverse_leaves<Query>(L.bvh, k.traversal_ray(), q.tmin, tmax, mode, leaf);
      return;
    }
  }
  auto leaf = [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first; j < first + count; ++j) {
      Crossing c[2];
      const int n = k.crossings(L.prims[j], c);
      if (n && emit(L.prims[j].id, c, n)) return true;
    }
    return false;
  };
  traverse_leaves<Query>(L.bvh, k.traversal_ray(), q.tmin, tmax, mode, leaf);
}

template <class L_, class K>
PrimHit closest_with(const L_& L, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return {Contact::invalid};
  k.prepare(r);
  PrimHit best;
  double tmax = q.tmax;
  traverse_with<BvhQuery::closest>(L, k, q, tmax, mode, [&](std::uint32_t id, const Crossing* c, int n) {
    for (int i = 0; i < n; ++i)
      if (c[i].t >= q.tmin && (c[i].t < tmax || (c[i].t == tmax && id < best.prim))) {
        tmax = c[i].t;
        best = {c[i].contact, c[i].t, id, c[i].b1, c[i].b2};
      }
    return false;
  });
  return best;
}

template <class L_, class K>
bool any_with(const L_& L, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return false;
  k.prepare(r);
  bool hit = false;
  traverse_with<BvhQuery::any>(L, k, q, q.tmax, mode, [&](std::uint32_t, const Crossing* c, int n) {
    for (int i = 0; i < n; ++i)
      if (c[i].t >= q.tmin && c[i].t <= q.tmax) return hit = true;
    return false;
  });
  return hit;
}

/// Rays [0, n) over `threads` threads in ranges of about 256 (batch_threads.h).
template <class Body>
void parallel_rays(std::size_t n, int threads, Body&& body) {
  scene::detail::for_each_batch_range(n, threads, 0, 256, body);
}

/// The HitSink that stores hit i at `out[i]` (context: a PrimHit array).
inline void store_hit(void* out, std::size_t i, const PrimHit& h) { static_cast<PrimHit*>(out)[i] = h; }

/// Ray i's range: one per ray, one for all, or the default.
inline QueryRange range_of(std::span<const QueryRange> ranges, std::size_t i) {
  return ranges.size() > 1 ? ranges[i] : ranges.empty() ? QueryRange{} : ranges[0];
}

}  // namespace rayproof::scene::detail
