// The first pass of the closest-point query on the wide tree (distance_wide.h), through the
// traversal loop of the ray trees (bvh_wide_loop.h: nearest child first, children beyond the bound
// dropped when popped), with a box test that gives lower bounds of squared distances instead of
// entry distances.
//
// The box test, per child and in float: g_k = max(lo_k - ph_k, pl_k - hi_k, 0) for each axis k,
// with pl_k <= p_k <= ph_k the floats next to p_k (bvh_float_down / bvh_float_up), and f = (g_x^2 + g_y^2) + g_z^2.
// With u = 2^-24: lo - ph <= lo - p, and its rounding keeps the sign and errs by at most u
// relative, so g_k <= G_k (1 + u), G_k the exact gap of p to the slab; each square adds (1 + u) and
// at most 2^-150 absolute (underflow), each sum (1 + u). Overflow to +inf happens only above the
// float range, where the same bound holds in the limit. So f <= L (1 + u)^5 + 2^-147, L the exact
// squared distance of p to the box (the float box holds the exact double box: rounded outwards).
// A child is kept when f <= T, T = float_above(U (1 + 2^-20) + 2^-140) >= U (1 + 2^-20) + 2^-140:
// one dropped has L (1 + u)^5 > U (1 + 2^-20), so L > U ((1 + u)^5 < 1 + 2^-20). U = +inf keeps
// every child (float_above(x) >= x holds for x >= 0). The points are limited to |p_k| <= 2^100.
#include "scene/distance_wide.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include "scene/distance_bounds.h"

namespace rayproof::scene::detail {

using rayproof::detail::float_above;  // the header-only helpers (rayproof/float_util.h, bvh_wide_loop.h)
using rayproof::detail::wide_traverse_loop;
using rayproof::detail::wide_traverse_loop_avx2;

namespace {

/// The float bound every child is tested against for the squared-distance bound U (see above).
inline float box_threshold(double U) { return float_above(U * (1 + 0x1p-20) + 0x1p-140); }

/// The first pass's leaf visit: every triangle whose box is within U gets its upper bound and is
/// recorded with its box bound and the direction to the upper bound's point (the second pass
/// computes the lower bound along it for the triangles whose box is within the final U).
struct LeafVisit {
  const DistanceTree& t;
  const Vec3<double>& p;
  double& U;
  float& thr;
  std::vector<DistanceVisit>& visited;
  bool operator()(std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t s = first; s < first + count; ++s) {
      const double box = triangle_box_lb(t.tris[s], p);
      if (box > U) continue;
      Vec3<double> e;
      const double ub = upper_bound(t.tris[s], p, &e);
      visited.push_back({s, box, e});
      if (ub < U) U = ub, thr = box_threshold(U);
    }
    return false;
  }
  void prefetch(std::uint32_t first) const { __builtin_prefetch(&t.tris[first]); }
};

/// The same visit on the AVX2 path, four triangles at a time (distance_bounds.h, box_bounds4 and
/// upper_bounds4: each lane bit for bit the scalar bound): the box bounds of a group first, the
/// upper bounds only when one of its boxes is within U, then the lanes in slot order exactly as
/// the scalar visit takes them (U lowered by each, later lanes tested against the lowered U).
struct LeafVisitLanes : LeafVisit {
  [[gnu::target("avx2")]] bool operator()(std::uint32_t first, std::uint32_t count) {
    const std::uint32_t end = first + count;
    for (std::uint32_t s = first; s < end; s += 4) {
      const std::uint32_t n = std::min<std::uint32_t>(4, end - s);
      const std::array<Vec3<double>, 3>* tri[4];
      for (std::uint32_t i = 0; i < 4; ++i) tri[i] = &t.tris[s + std::min(i, n - 1)];  // a short group repeats its last
      __m256d v[3][3];
      Lanes4 b;
      box_bounds4(tri, p, v, b);
      const int within = _mm256_movemask_pd(_mm256_cmp_pd(_mm256_load_pd(b.box), _mm256_set1_pd(U), _CMP_LE_OQ)) &
                         ((1 << n) - 1);
      if (!within) continue;
      upper_bounds4(v, p, b);
      for (int i = 0; i < int(n); ++i) {
        if (!(b.box[i] <= U)) continue;  // U only falls: implies the lane's bit in `within` (NaN fails both)
        visited.push_back({s + std::uint32_t(i), b.box[i], {b.dir[0][i], b.dir[1][i], b.dir[2][i]}});
        if (b.ub[i] < U) U = b.ub[i], thr = box_threshold(U);
      }
    }
    return false;
  }
};

/// The SSE box test of four children (the loop's `test(node, tmax, t)`: the mask of the children
/// with f <= thr and their f).
struct Box4 {
  __m128 pl[3], ph[3];
  [[gnu::always_inline]] int operator()(const Bvh4Node& n, float thr, float* t) const {
    const __m128 zero = _mm_setzero_ps();
    __m128 s = zero;
    for (int k = 0; k < 3; ++k) {
      const __m128 g = _mm_max_ps(_mm_max_ps(_mm_sub_ps(_mm_load_ps(n.lo[k]), ph[k]), _mm_sub_ps(pl[k], _mm_load_ps(n.hi[k]))), zero);
      s = _mm_add_ps(s, _mm_mul_ps(g, g));
    }
    const int mask = _mm_movemask_ps(_mm_cmple_ps(s, _mm_set1_ps(thr))) & n.valid;
    if (mask) _mm_store_ps(t, s);
    return mask;
  }
};

/// The AVX2 box test of eight children.
struct Box8 {
  __m256 pl[3], ph[3];
  [[gnu::target("avx2"), gnu::always_inline]] int operator()(const Bvh8Node& n, float thr, float* t) const {
    const __m256 zero = _mm256_setzero_ps();
    __m256 s = zero;
    for (int k = 0; k < 3; ++k) {
      const __m256 g = _mm256_max_ps(
          _mm256_max_ps(_mm256_sub_ps(_mm256_load_ps(n.lo[k]), ph[k]), _mm256_sub_ps(pl[k], _mm256_load_ps(n.hi[k]))), zero);
      s = _mm256_add_ps(s, _mm256_mul_ps(g, g));
    }
    const int mask = _mm256_movemask_ps(_mm256_cmp_ps(s, _mm256_set1_ps(thr), _CMP_LE_OQ)) & n.valid;
    if (mask) _mm256_store_ps(t, s);
    return mask;
  }
};

/// The leaf: LeafVisitLanes, or LeafVisit (the ablation's "-leaf lanes").
template <class Leaf>
[[gnu::target("avx2")]] void run8(const Bvh8& w, const Vec3<double>& p, Leaf& leaf) {
  Box8 test;
  for (int k = 0; k < 3; ++k) test.pl[k] = _mm256_set1_ps(bvh_float_down(p[k])), test.ph[k] = _mm256_set1_ps(bvh_float_up(p[k]));
  const float& thr = leaf.thr;
  wide_traverse_loop_avx2<Bvh8, float, BvhQuery::closest>(w, test, [&] { return thr; }, leaf);
}

void run4(const Bvh4& w, const Vec3<double>& p, LeafVisit& leaf) {
  Box4 test;
  for (int k = 0; k < 3; ++k) test.pl[k] = _mm_set1_ps(bvh_float_down(p[k])), test.ph[k] = _mm_set1_ps(bvh_float_up(p[k]));
  const float& thr = leaf.thr;
  wide_traverse_loop<Bvh4, float, BvhQuery::closest>(w, test, [&] { return thr; }, leaf);
}

}  // namespace

bool wide_first_bound(const DistanceTree& t, const Vec3<double>& p, double& U, std::vector<DistanceVisit>& visited) {
  constexpr double kRange = 0x1p100;
  if (!(std::abs(p.x) <= kRange && std::abs(p.y) <= kRange && std::abs(p.z) <= kRange)) return false;
  float thr = box_threshold(U);
  LeafVisitLanes leaf{{t, p, U, thr, visited}};
  if (!t.wide8.empty() && !(distance_ablation() & kAblateLanes)) run8(t.wide8, p, leaf);
  else if (!t.wide8.empty()) run8(t.wide8, p, static_cast<LeafVisit&>(leaf));
  else if (!t.wide4.empty()) run4(t.wide4, p, leaf);
  else return false;
  return true;
}

}  // namespace rayproof::scene::detail
