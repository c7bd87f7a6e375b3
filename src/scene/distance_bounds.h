#pragma once
/// Plain-double bounds of the closest-point search (internal): a rigorous lower bound of the
/// squared distance from p to a triangle's box, and a rigorous upper bound of the squared distance
/// from p to the triangle (both passes of distance.cpp and the wide first pass, distance_wide.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <immintrin.h>

#include "rayproof/vec3.h"

namespace rayproof::scene::detail {

/// Lower bound of the squared distance from p to a triangle's box (rounded down).
inline double triangle_box_lb(const std::array<Vec3<double>, 3>& tri, const Vec3<double>& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double a = tri[0][k], b = tri[1][k], c = tri[2][k];
    const double lo = std::min({a, b, c}), hi = std::max({a, b, c});
    const double g = std::max({lo - p[k], p[k] - hi, 0.0});
    s += g * g;
  }
  return std::max(0.0, s * (1 - 0x1p-49) - 0x1p-1070);
}

/// A rigorous upper bound of the squared distance from p to a triangle, in plain double: the
/// distance to a point q of the triangle (weights found by the Voronoi regions in double, clamped
/// so that they are surely nonnegative and sum to at most 1) plus a bound on the rounding of q.
/// `dir`, when given, gets p - q as computed (for lower_bound_along).
inline double upper_bound(const std::array<Vec3<double>, 3>& t, const Vec3<double>& p, Vec3<double>* dir = nullptr) {
  const Vec3<double> a = t[0], ab = t[1] - t[0], ac = t[2] - t[0], ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  const Vec3<double> bp = p - t[1], cp = p - t[2];
  const double d3 = dot(ab, bp), d4 = dot(ac, bp), d5 = dot(ab, cp), d6 = dot(ac, cp);
  double v = 0, w = 0;
  if (d1 <= 0 && d2 <= 0) v = 0, w = 0;
  else if (d3 >= 0 && d4 <= d3) v = 1, w = 0;
  else if (d6 >= 0 && d5 <= d6) v = 0, w = 1;
  else {
    const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) v = d1 / (d1 - d3);
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) w = d2 / (d2 - d6);
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) w = (d4 - d3) / ((d4 - d3) + (d5 - d6)), v = 1 - w;
    else v = vb / (va + vb + vc), w = vc / (va + vb + vc);
  }
  if (!(v >= 0)) v = 0;  // NaN too
  if (!(w >= 0)) w = 0;
  if (const double sum = v + w; sum > 1 - 0x1p-50) v *= (1 - 0x1p-49) / sum, w *= (1 - 0x1p-49) / sum;
  // q = a + v ab + w ac exactly is on the triangle; its double evaluation is within delta of it.
  double e2 = 0, delta = 0;
  for (int k = 0; k < 3; ++k) {
    const double q = a[k] + v * ab[k] + w * ac[k];
    delta += (std::abs(a[k]) + v * std::abs(ab[k]) + w * std::abs(ac[k])) * 0x1p-50;
    const double d = p[k] - q;
    if (dir) (*dir)[k] = d;
    e2 += d * d;
  }
  // 2^-520: above any underflow of the squares (it only loosens the bound below 2^-1000).
  const double r = std::sqrt(e2) * (1 + 0x1p-50) + delta * (1 + 0x1p-50) + 0x1p-520;
  return r * r * (1 + 0x1p-50);
}

/// Four triangles at once in AVX2 lanes (the wide first pass's leaves, distance_wide.cpp): lane i
/// of `box` is triangle_box_lb(*tri[i], p), of `ub` upper_bound(*tri[i], p, &dir) with dir in
/// dir[k][i], bit for bit. Every lane takes the scalar functions' operations in their order (no
/// contraction: the build has -ffp-contract=off; division and sqrt are correctly rounded in both),
/// and their branches become blends that pick what the scalar code would have computed, so both
/// bounds' proofs hold unchanged. (Lanes of the branches not taken may hold NaN or inf; they are
/// blended out. min and max give the same values as std::min/std::max up to the sign of zero, which
/// no later step can see: a gap is squared and the sum clamped at 0.)
struct Lanes4 {
  alignas(32) double box[4];
  alignas(32) double ub[4];
  alignas(32) double dir[3][4];
};

namespace lanes {
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d coord(const std::array<Vec3<double>, 3>* const tri[4], int v,
                                                                  int k) {
  return _mm256_set_pd((*tri[3])[v][k], (*tri[2])[v][k], (*tri[1])[v][k], (*tri[0])[v][k]);
}
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d le(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d ge(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d gt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
/// (a0 b0 + a1 b1) + a2 b2, as dot().
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d dot3(const __m256d a[3], const __m256d b[3]) {
  return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]));
}
}  // namespace lanes

/// The box bounds of four triangles (lane i: triangle_box_lb(*tri[i], p)); the triangles' vertices
/// are loaded into `v` (v[vertex][axis]) for upper_bounds4.
[[gnu::target("avx2")]] inline void box_bounds4(const std::array<Vec3<double>, 3>* const tri[4], const Vec3<double>& p,
                                                __m256d v[3][3], Lanes4& out) {
  using namespace lanes;
  __m256d s = _mm256_setzero_pd();
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) v[j][k] = coord(tri, j, k);
    const __m256d lo = _mm256_min_pd(_mm256_min_pd(v[0][k], v[1][k]), v[2][k]);
    const __m256d hi = _mm256_max_pd(_mm256_max_pd(v[0][k], v[1][k]), v[2][k]);
    const __m256d pk = _mm256_set1_pd(p[k]);
    const __m256d g = _mm256_max_pd(_mm256_max_pd(sub(lo, pk), sub(pk, hi)), _mm256_setzero_pd());
    s = add(s, mul(g, g));
  }
  const __m256d lb = sub(mul(s, _mm256_set1_pd(1 - 0x1p-49)), _mm256_set1_pd(0x1p-1070));
  _mm256_store_pd(out.box, _mm256_max_pd(lb, _mm256_setzero_pd()));
}

/// The upper bounds of the four triangles box_bounds4 loaded (lane i: upper_bound(*tri[i], p, &dir)).
[[gnu::target("avx2")]] inline void upper_bounds4(const __m256d v[3][3], const Vec3<double>& p, Lanes4& out) {
  using namespace lanes;
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1);
  __m256d P[3], ab[3], ac[3], ap[3], bp[3], cp[3];
  for (int k = 0; k < 3; ++k) {
    P[k] = _mm256_set1_pd(p[k]);
    ab[k] = sub(v[1][k], v[0][k]), ac[k] = sub(v[2][k], v[0][k]), ap[k] = sub(P[k], v[0][k]);
    bp[k] = sub(P[k], v[1][k]), cp[k] = sub(P[k], v[2][k]);
  }
  const __m256d d1 = dot3(ab, ap), d2 = dot3(ac, ap), d3 = dot3(ab, bp), d4 = dot3(ac, bp), d5 = dot3(ab, cp),
                d6 = dot3(ac, cp);
  const __m256d vc = sub(mul(d1, d4), mul(d3, d2)), vb = sub(mul(d5, d2), mul(d1, d6)), va = sub(mul(d3, d6), mul(d5, d4));
  const __m256d d43 = sub(d4, d3), d56 = sub(d5, d6);
  // The scalar chain of regions, last first: each earlier test that holds overrides the later ones.
  const __m256d sum3 = add(add(va, vb), vc);
  __m256d V = _mm256_div_pd(vb, sum3), W = _mm256_div_pd(vc, sum3);  // face
  const __m256d w_bc = _mm256_div_pd(d43, add(d43, d56));
  const __m256d c_bc = _mm256_and_pd(_mm256_and_pd(le(va, zero), ge(d43, zero)), ge(d56, zero));
  V = _mm256_blendv_pd(V, sub(one, w_bc), c_bc), W = _mm256_blendv_pd(W, w_bc, c_bc);
  const __m256d c_ac = _mm256_and_pd(_mm256_and_pd(le(vb, zero), ge(d2, zero)), le(d6, zero));
  V = _mm256_blendv_pd(V, zero, c_ac), W = _mm256_blendv_pd(W, _mm256_div_pd(d2, sub(d2, d6)), c_ac);
  const __m256d c_ab = _mm256_and_pd(_mm256_and_pd(le(vc, zero), ge(d1, zero)), le(d3, zero));
  V = _mm256_blendv_pd(V, _mm256_div_pd(d1, sub(d1, d3)), c_ab), W = _mm256_blendv_pd(W, zero, c_ab);
  const __m256d c_c = _mm256_and_pd(ge(d6, zero), le(d5, d6));
  V = _mm256_blendv_pd(V, zero, c_c), W = _mm256_blendv_pd(W, one, c_c);
  const __m256d c_b = _mm256_and_pd(ge(d3, zero), le(d4, d3));
  V = _mm256_blendv_pd(V, one, c_b), W = _mm256_blendv_pd(W, zero, c_b);
  const __m256d c_a = _mm256_and_pd(le(d1, zero), le(d2, zero));
  V = _mm256_blendv_pd(V, zero, c_a), W = _mm256_blendv_pd(W, zero, c_a);
  V = _mm256_and_pd(V, ge(V, zero));  // !(v >= 0): 0 (NaN too)
  W = _mm256_and_pd(W, ge(W, zero));
  const __m256d sum = add(V, W);
  const __m256d scale = _mm256_div_pd(_mm256_set1_pd(1 - 0x1p-49), sum);
  const __m256d big = gt(sum, _mm256_set1_pd(1 - 0x1p-50));
  V = _mm256_blendv_pd(V, mul(V, scale), big), W = _mm256_blendv_pd(W, mul(W, scale), big);
  const __m256d sign = _mm256_set1_pd(-0.0), ulp50 = _mm256_set1_pd(0x1p-50);
  __m256d e2 = zero, delta = zero;
  for (int k = 0; k < 3; ++k) {
    const __m256d q = add(add(v[0][k], mul(V, ab[k])), mul(W, ac[k]));
    const __m256d mag = add(add(_mm256_andnot_pd(sign, v[0][k]), mul(V, _mm256_andnot_pd(sign, ab[k]))),
                            mul(W, _mm256_andnot_pd(sign, ac[k])));
    delta = add(delta, mul(mag, ulp50));
    const __m256d d = sub(P[k], q);
    _mm256_store_pd(out.dir[k], d);
    e2 = add(e2, mul(d, d));
  }
  const __m256d up = _mm256_set1_pd(1 + 0x1p-50);
  const __m256d r = add(add(mul(_mm256_sqrt_pd(e2), up), mul(delta, up)), _mm256_set1_pd(0x1p-520));
  _mm256_store_pd(out.ub, mul(mul(r, r), up));
}

/// A rigorous lower bound of the squared distance from p to a triangle, for any direction e: every
/// point x of the triangle (convex: a combination of its vertices) has (p - x) . e >= m =
/// min_k (p - v_k) . e, so |p - x| >= m / |e| when m > 0. With e = p - q for q near the closest
/// point (upper_bound's), the bound is the distance itself up to rounding: at the exact closest
/// point q*, every vertex has (v - q*) . (p - q*) <= 0. Each dot product is computed in double and
/// lowered by a bound on its rounding (2^-50 of the sum of its terms' magnitudes: three differences
/// and three products and two sums, each 2^-53 relative, plus 2^-1060 against underflow); |e| is
/// rounded up, the quotient and the square down. 0 when m <= 0 or on overflow.
inline double lower_bound_along(const std::array<Vec3<double>, 3>& t, const Vec3<double>& p, const Vec3<double>& e) {
  double m = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double a0 = p.x - t[k].x, a1 = p.y - t[k].y, a2 = p.z - t[k].z;
    const double s = a0 * e.x + a1 * e.y + a2 * e.z;
    const double err = (std::abs(a0 * e.x) + std::abs(a1 * e.y) + std::abs(a2 * e.z)) * 0x1p-50 + 0x1p-1060;
    m = std::min(m, s - err);
  }
  if (!(m > 0)) return 0;
  const double ne = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z) * (1 + 0x1p-50) + 0x1p-1000;
  const double lb = m / ne * (1 - 0x1p-50);
  const double lb2 = lb * lb * (1 - 0x1p-50) - 0x1p-1070;
  return lb2 > 0 && lb2 < std::numeric_limits<double>::infinity() ? lb2 : 0.0;
}

}  // namespace rayproof::scene::detail
