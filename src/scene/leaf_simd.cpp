// SIMD leaf kernels (leaf_simd.h): the robust group kernel in AVX2 double lanes (target attribute,
// chosen at run time), Möller–Trumbore's miss screen in SSE float lanes, and the path selection.
#include "scene/leaf_simd.h"

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace rayproof::scene::detail {
namespace {

bool cpu_has_avx2() {
  static const bool ok = (__builtin_cpu_init(), __builtin_cpu_supports("avx2") != 0);
  return ok;
}

LeafSimd from_environment() {
  const LeafSimd best = cpu_has_avx2() ? LeafSimd::avx2 : LeafSimd::sse;
  const char* e = std::getenv("RAYPROOF_SIMD");
  if (!e) return best;
  if (std::strcmp(e, "off") == 0) return LeafSimd::off;
  if (std::strcmp(e, "scalar") == 0) return LeafSimd::scalar;
  if (std::strcmp(e, "sse") == 0) return LeafSimd::sse;
  return best;  // "avx2" or anything else: the best the CPU has
}

// -1: not forced; else a LeafSimd.
std::atomic<int> forced{-1};

}  // namespace

LeafSimd leaf_simd() {
  const int f = forced.load(std::memory_order_relaxed);
  if (f >= 0) return static_cast<LeafSimd>(f);
  static const LeafSimd env = from_environment();
  return env;
}

void force_leaf_simd(LeafSimd s) {
  if (s == LeafSimd::avx2 && !cpu_has_avx2()) s = LeafSimd::sse;
  forced.store(int(s), std::memory_order_relaxed);
}

void unforce_leaf_simd() { forced.store(-1, std::memory_order_relaxed); }

const char* to_string(LeafSimd s) {
  switch (s) {
    case LeafSimd::off: return "off";
    case LeafSimd::scalar: return "scalar";
    case LeafSimd::sse: return "sse";
    case LeafSimd::avx2: return "avx2";
  }
  return "?";
}

// The scalar robust kernel (kernels.h, CompiledKernel<float, TriAlgo::robust>::triangle_crossings)
// after its ray-independent screens, in four lanes. Every line below is the scalar line it mirrors,
// with the same operands in the same order; each _mm256 operation is one correctly rounded IEEE
// double operation, as the scalar one is (no FMA: this function is not compiled for "fma").
__attribute__((target("avx2"))) void robust_group_avx2(const RobustLaneRay& r, const TriGroup& g, unsigned live,
                                                        RobustLanes& out) {
  out.hit = out.special = 0;
  if (!live) return;
  __m256d p[3][3];
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) p[v][k] = _mm256_cvtps_pd(_mm_load_ps(g.p[v][k]));
  const __m256d zero = _mm256_setzero_pd();
  // n = cross(p1 - p0, p2 - p0); d . n = 0 goes to the front door (parallel or coplanar).
  __m256d e1[3], e2[3];
  for (int k = 0; k < 3; ++k) e1[k] = _mm256_sub_pd(p[1][k], p[0][k]), e2[k] = _mm256_sub_pd(p[2][k], p[0][k]);
  const __m256d nx = _mm256_sub_pd(_mm256_mul_pd(e1[1], e2[2]), _mm256_mul_pd(e1[2], e2[1]));
  const __m256d ny = _mm256_sub_pd(_mm256_mul_pd(e1[2], e2[0]), _mm256_mul_pd(e1[0], e2[2]));
  const __m256d nz = _mm256_sub_pd(_mm256_mul_pd(e1[0], e2[1]), _mm256_mul_pd(e1[1], e2[0]));
  const __m256d dn = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(r.d[0]), nx), _mm256_mul_pd(_mm256_set1_pd(r.d[1]), ny)),
                                   _mm256_mul_pd(_mm256_set1_pd(r.d[2]), nz));
  const unsigned special = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(dn, zero, _CMP_EQ_OQ))) & live;
  const unsigned rest = live & ~special;
  out.special = special;
  if (!rest) return;
  // intersect_watertight(WatertightRay<float, double>, tri): vertices relative to the origin, shear.
  const int kx = r.kx, ky = r.ky, kz = r.kz;
  const __m256d dx = _mm256_set1_pd(r.d[kx]), dy = _mm256_set1_pd(r.d[ky]), dz = _mm256_set1_pd(r.d[kz]);
  const __m256d ox = _mm256_set1_pd(r.o[kx]), oy = _mm256_set1_pd(r.o[ky]), oz = _mm256_set1_pd(r.o[kz]);
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d sx[3], sy[3], sz[3], m[3];  // per vertex: sheared x, y, the relative z, and max_k |relative_k|
  for (int v = 0; v < 3; ++v) {
    const __m256d ax = _mm256_sub_pd(p[v][kx], ox), ay = _mm256_sub_pd(p[v][ky], oy), az = _mm256_sub_pd(p[v][kz], oz);
    sx[v] = _mm256_sub_pd(_mm256_mul_pd(dz, ax), _mm256_mul_pd(dx, az));
    sy[v] = _mm256_sub_pd(_mm256_mul_pd(dz, ay), _mm256_mul_pd(dy, az));
    sz[v] = az;
    // The max of three finite non-negative values: the same whatever the order of the operands.
    m[v] = _mm256_max_pd(_mm256_max_pd(_mm256_andnot_pd(sign, ax), _mm256_andnot_pd(sign, ay)), _mm256_andnot_pd(sign, az));
  }
  // u = edge(c, b), v = edge(a, c), w = edge(b, a): e(p, q) = p_x q_y - p_y q_x.
  __m256d u = _mm256_sub_pd(_mm256_mul_pd(sx[2], sy[1]), _mm256_mul_pd(sy[2], sx[1]));
  __m256d v = _mm256_sub_pd(_mm256_mul_pd(sx[0], sy[2]), _mm256_mul_pd(sy[0], sx[2]));
  __m256d w = _mm256_sub_pd(_mm256_mul_pd(sx[1], sy[0]), _mm256_mul_pd(sy[1], sx[0]));
  // Bounded zeros (triangle_watertight.h): |U| <= E_U = e_c m_b + e_b m_c + 2^-51 n_b n_c counts
  // as 0, with e_v = edge_k A_v, n_v = |sx_v| + |sy_v| and m_v = n_v + e_v.
  const __m256d k = _mm256_set1_pd(r.edge_k_double), g51 = _mm256_set1_pd(0x1p-51);
  __m256d e[3], n[3], mm[3];
  for (int i = 0; i < 3; ++i) {
    e[i] = _mm256_mul_pd(k, m[i]), n[i] = _mm256_add_pd(_mm256_andnot_pd(sign, sx[i]), _mm256_andnot_pd(sign, sy[i]));
    mm[i] = _mm256_add_pd(n[i], e[i]);
  }
  // E of the edge function e(q, p): u (q, p) = (c, b), v (a, c), w (b, a): e_q m_p + e_p m_q + g n_p n_q
  // (written out: a lambda would not inherit this function's target attribute).
  __m256d eb3[3];
  const int q_of[3] = {2, 0, 1}, p_of[3] = {1, 2, 0};
  for (int i = 0; i < 3; ++i) {
    const int q = q_of[i], pp = p_of[i];
    eb3[i] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(e[q], mm[pp]), _mm256_mul_pd(e[pp], mm[q])),
                           _mm256_mul_pd(g51, _mm256_mul_pd(n[pp], n[q])));
  }
  const __m256d eu = eb3[0], ev = eb3[1], ew = eb3[2];
  u = _mm256_blendv_pd(u, zero, _mm256_cmp_pd(_mm256_andnot_pd(sign, u), eu, _CMP_LE_OQ));
  v = _mm256_blendv_pd(v, zero, _mm256_cmp_pd(_mm256_andnot_pd(sign, v), ev, _CMP_LE_OQ));
  w = _mm256_blendv_pd(w, zero, _mm256_cmp_pd(_mm256_andnot_pd(sign, w), ew, _CMP_LE_OQ));
  const __m256d any_neg = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_LT_OQ), _mm256_cmp_pd(v, zero, _CMP_LT_OQ)),
                                       _mm256_cmp_pd(w, zero, _CMP_LT_OQ));
  const __m256d any_pos = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_GT_OQ), _mm256_cmp_pd(v, zero, _CMP_GT_OQ)),
                                       _mm256_cmp_pd(w, zero, _CMP_GT_OQ));
  const unsigned miss = unsigned(_mm256_movemask_pd(_mm256_and_pd(any_neg, any_pos)));
  const __m256d det = _mm256_add_pd(_mm256_add_pd(u, v), w);
  // det = 0: every edge function within its bound, undecided: the scalar front door's contact.
  const unsigned parallel = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(det, zero, _CMP_EQ_OQ)));
  out.special |= rest & ~miss & parallel;
  const __m256d ts = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(u, sz[0]), _mm256_mul_pd(v, sz[1])), _mm256_mul_pd(w, sz[2]));
  const __m256d den = _mm256_mul_pd(det, dz);
  // Behind needs t's error bound E_t: computed lane by lane below, only for the lanes not missed
  // (the same IEEE double operations in the same order as the scalar kernel's).
  const unsigned cand = rest & ~miss & ~parallel;
  if (!cand) return;
  alignas(32) double U[4], V[4], W[4], D[4], TS[4], DEN[4], EU[4], EV[4], EW[4], Z[3][4];
  _mm256_store_pd(U, u), _mm256_store_pd(V, v), _mm256_store_pd(W, w);
  _mm256_store_pd(D, det), _mm256_store_pd(TS, ts), _mm256_store_pd(DEN, den);
  _mm256_store_pd(EU, eu), _mm256_store_pd(EV, ev), _mm256_store_pd(EW, ew);
  for (int i = 0; i < 3; ++i) _mm256_store_pd(Z[i], sz[i]);
  unsigned hit = 0;
  for (unsigned c = cand; c; c &= c - 1) {
    const int i = __builtin_ctz(c);
    const double tb = 2.001 * (EU[i] * std::fabs(Z[0][i]) + EV[i] * std::fabs(Z[1][i]) + EW[i] * std::fabs(Z[2][i])) +
                      0x1p-50 * (std::fabs(U[i] * Z[0][i]) + std::fabs(V[i] * Z[1][i]) + std::fabs(W[i] * Z[2][i]));
    const bool behind = DEN[i] < 0.0 ? TS[i] > tb : TS[i] < -tb;
    if (behind) continue;
    hit |= 1u << i;
    const float t = static_cast<float>(TS[i] / DEN[i]);
    out.t[i] = t >= 0.0f ? t : 0.0f;  // an undecided sign of t: 0, as the scalar kernel
    out.b1[i] = static_cast<float>(V[i] / D[i]), out.b2[i] = static_cast<float>(W[i] / D[i]);
    const int zeros = (U[i] == 0.0) + (V[i] == 0.0) + (W[i] == 0.0);
    out.contact[i] = static_cast<std::uint8_t>(zeros == 0 ? Contact::interior : zeros == 1 ? Contact::edge : Contact::vertex);
  }
  out.hit = hit;
}

// triangle_stage1 (certified_triangle.h) up to `return H{Contact::miss}`, line by line in lanes:
// a = p0 - o, b = p1 - o, c = p2 - o; u0 = (d x b) . c, u1 = (d x c) . a, u2 = (d x a) . b; the
// bounds e_i and eden; a lane is a miss when |den| > eden, eden < 2^1020 and a u_i is clearly of
// the sign opposite to den. Same operations in the same order as the scalar stage (no FMA here, and
// the project compiles with -ffp-contract=off, so the scalar stage does not contract either); and
// whatever the rounding, a lane reported here is a miss proven by stage 1's error bound, so the
// exact class certified::triangle returns for it is miss.
__attribute__((target("avx2"))) unsigned certified_group_misses_avx2(const Ray<double>& ray, const double (&p)[3][3][kLanes],
                                                                    unsigned live) {
  if (!live) return 0;
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d rel[3][3];  // rel[vertex][axis] = p - o
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) rel[v][k] = _mm256_sub_pd(_mm256_loadu_pd(p[v][k]), _mm256_set1_pd(ray.o[k]));
  const __m256d dx = _mm256_set1_pd(ray.d.x), dy = _mm256_set1_pd(ray.d.y), dz = _mm256_set1_pd(ray.d.z);
  __m256d u[3], mx[3];
  // u0 from (b, c) = (rel[1], rel[2]), u1 from (c, a), u2 from (a, b): dot(cross(d, q), r).
  const int q_of[3] = {1, 2, 0}, r_of[3] = {2, 0, 1};
  for (int i = 0; i < 3; ++i) {
    const __m256d* q = rel[q_of[i]];
    const __m256d* r = rel[r_of[i]];
    const __m256d cx = _mm256_sub_pd(_mm256_mul_pd(dy, q[2]), _mm256_mul_pd(dz, q[1]));
    const __m256d cy = _mm256_sub_pd(_mm256_mul_pd(dz, q[0]), _mm256_mul_pd(dx, q[2]));
    const __m256d cz = _mm256_sub_pd(_mm256_mul_pd(dx, q[1]), _mm256_mul_pd(dy, q[0]));
    u[i] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(cx, r[0]), _mm256_mul_pd(cy, r[1])), _mm256_mul_pd(cz, r[2]));
  }
  for (int v = 0; v < 3; ++v) {  // norm_inf: m = x > y ? x : y; m > z ? m : z
    const __m256d x = _mm256_andnot_pd(sign, rel[v][0]), y = _mm256_andnot_pd(sign, rel[v][1]), z = _mm256_andnot_pd(sign, rel[v][2]);
    const __m256d m = _mm256_blendv_pd(y, x, _mm256_cmp_pd(x, y, _CMP_GT_OQ));
    mx[v] = _mm256_blendv_pd(z, m, _mm256_cmp_pd(m, z, _CMP_GT_OQ));
  }
  const double d1 = std::fabs(ray.d.x) + std::fabs(ray.d.y) + std::fabs(ray.d.z);
  if (!(d1 >= 0x1p-960)) return 0u;  // 2^-49 d1 would underflow (certified_triangle.h): decide nothing
  const __m256d k = _mm256_set1_pd(0x1p-49 * d1), tiny = _mm256_set1_pd(0x1p-1000), one = _mm256_set1_pd(1.0);
  // e0 = k mb mc + 2^-1000 (mc + 1), e1 = k mc ma + 2^-1000 (ma + 1), e2 = k ma mb + 2^-1000 (mb + 1)
  __m256d e[3];
  for (int i = 0; i < 3; ++i) {
    const __m256d f = mx[q_of[i]], g = mx[r_of[i]];
    e[i] = _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(k, f), g), _mm256_mul_pd(tiny, _mm256_add_pd(g, one)));
  }
  const __m256d den = _mm256_add_pd(_mm256_add_pd(u[0], u[1]), u[2]);
  const __m256d au = _mm256_add_pd(_mm256_add_pd(_mm256_andnot_pd(sign, u[0]), _mm256_andnot_pd(sign, u[1])),
                                   _mm256_andnot_pd(sign, u[2]));
  const __m256d eden = _mm256_add_pd(_mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(e[0], e[1]), e[2]), _mm256_set1_pd(1 + 0x1p-50)),
                                     _mm256_mul_pd(_mm256_set1_pd(0x1p-51), au));
  const __m256d decided = _mm256_and_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, den), eden, _CMP_GT_OQ),
                                        _mm256_cmp_pd(eden, _mm256_set1_pd(0x1p1020), _CMP_LT_OQ));
  const __m256d den_pos = _mm256_cmp_pd(den, _mm256_setzero_pd(), _CMP_GT_OQ);
  __m256d neg = _mm256_setzero_pd();
  for (int i = 0; i < 3; ++i) {  // den > 0 ? u < -e : u > e
    const __m256d below = _mm256_cmp_pd(u[i], _mm256_xor_pd(sign, e[i]), _CMP_LT_OQ);
    const __m256d above = _mm256_cmp_pd(u[i], e[i], _CMP_GT_OQ);
    neg = _mm256_or_pd(neg, _mm256_blendv_pd(above, below, den_pos));
  }
  return unsigned(_mm256_movemask_pd(_mm256_and_pd(decided, neg))) & live;
}

// robust's float screen. The scalar robust kernel (kernels.h) computes, in double, on the float
// vertices p and the float ray (o, d): dn = d . ((p1 - p0) x (p2 - p0)); when dn != 0, the
// watertight test's U, V, W (q = p - o, sx = d_z q_x - d_x q_z, sy = d_z q_y - d_y q_z in the
// permuted axes; U = sx_c sy_b - sy_c sx_b, V = sx_a sy_c - sy_a sx_c, W = sx_b sy_a - sy_b sx_a),
// and reports nothing when they have mixed signs. The screen computes the same U, V, W in float
// and decides a lane only when that outcome is certain:
//
// Edge functions. Let U* be the exact value on the (exact) float inputs, M_v = |d_z||q*_x| +
// |d_x||q*_z| (and with y), S = M_x,c M_y,b + M_y,c M_x,b. Each float operation errs by at most
// u = 2^-24 relatively, plus 2^-150 absolutely for a product that underflows (sums and
// differences of floats are exact when they underflow). Eight roundings lie on every path, so
// |U_float - U*| <= gamma_8 S + 2^-148 (sum of the M) + 2^-149 <= gamma_8 S + 2^-104 when every
// M <= 2^40; in double (no underflow: every value is a float-made product of at most 4 factors,
// far above 2^-1022) |U_double - U*| <= gamma_8(2^-53) S. With D = |d_z| + max(|d_x|, |d_y|) and
// A_v = max_k |q_v,k| (float, >= (1 - u) |q*|), M_v <= D A_v (1 + 2u), so S <= 2 D^2 A_b A_c
// (1 + 5u), and the two errors add up to less than B_u = 2^-19 D^2 A_b A_c + 2^-100 (factor 2 of
// slack for the float evaluation of B_u itself). When |U_float| > B_u, U* is not zero and has
// U_float's sign, and so has U_double. A lane whose float U, V, W include one > B and one < -B
// therefore has mixed double signs.
// d . n != 0. Exactly, U* + V* + W* = d_z (d . n)* up to sign (the scaled shear maps the plane
// normal to d_z d). The double dn errs by at most gamma_7(2^-53) |d|_1 8 A^2 (edges |p1 - p0| <=
// 2A) <= 2^-45.6 |d_z| A^2 (|d|_1 <= 3|d_z|, A = max A_v); the float sum det = (U + V) + W errs
// by at most the three bounds plus gamma_2 (|U| + |V| + |W|). So |det| > B_u + B_v + B_w +
// 2^-22 (|U| + |V| + |W|) + 2^-45 d_z^2 A^2 proves the double dn nonzero: the scalar kernel then
// runs the watertight test (not the coplanar front door), which reports the mixed signs' miss.
// Bounded zeros (triangle_watertight.h): the double kernel now reports a miss only when a double
// edge function exceeds its own bound E_U <= 2^-48 D^2 A_b A_c (1 + 2^-40) (e_v <= 2^-51 D A_v,
// n_v <= 2 D A_v (1 + 2^-50)). |U_float| > B_u leaves |U_double| >= B_u - (both errors) > 2^-21 D^2
// A_b A_c, far above that, with U_float's sign: the screen's decisions stand.
// Ranges. The absolute terms need M <= 2^40: a lane is decided only when every A_v <= 2^39 / D
// (false for inf and NaN); a ray is screened only when 2^-20 <= D <= 2^20, which keeps the bound
// products from overflowing and their underflow error (<= 2^-150 times a factor <= 2^21) under
// the 2^-100 of slack. Other rays and lanes go to the double kernel: slower, never different.
void finish_lane_ray(RobustLaneRay& r) {
  const int axis[3] = {r.kx, r.ky, r.kz};
  for (int i = 0; i < 3; ++i) r.so[i] = float(r.o[axis[i]]), r.sd[i] = float(r.d[axis[i]]);
  const double dz = std::fabs(r.d[r.kz]), d = dz + std::max(std::fabs(r.d[r.kx]), std::fabs(r.d[r.ky]));
  if (!(d >= 0x1p-20 && d <= 0x1p20)) {
    r.edge_k = r.dn_k = 0.0f, r.a_limit = -1.0f;  // no lane passes A_v <= -1: the screen is off
    return;
  }
  // Rounded up: float(x) >= x (1 - 2^-24), times 1 + 2^-20 > 1 + 2^-23 after rounding (x >= 2^-87:
  // no underflow, since d >= 2^-20 and d_z >= d / 2).
  r.edge_k = float(0x1p-19 * d * d) * (1.0f + 0x1p-20f);
  r.dn_k = float(0x1p-45 * dz * dz) * (1.0f + 0x1p-20f);
  r.a_limit = float(0x1p39 / d);
}

namespace {

/// The float screen's body: kRobust adds the d . n test and takes A_v = max |q|; certified takes
/// A_v = max (|p| + |o|) and its own constants (see certified_lane_ray).
template <bool kRobust>
unsigned float_screen(const RobustLaneRay& r, const TriGroup& g, unsigned live) {
  if (!live) return 0;
  const __m128 sign = _mm_set1_ps(-0.0f);
  const __m128 dx = _mm_set1_ps(r.sd[0]), dy = _mm_set1_ps(r.sd[1]), dz = _mm_set1_ps(r.sd[2]);
  const __m128 o[3] = {_mm_set1_ps(r.so[0]), _mm_set1_ps(r.so[1]), _mm_set1_ps(r.so[2])};
  const int axis[3] = {r.kx, r.ky, r.kz};
  __m128 sx[3], sy[3], a[3];
  for (int v = 0; v < 3; ++v) {
    __m128 p[3], q[3];
    for (int k = 0; k < 3; ++k) p[k] = _mm_load_ps(g.p[v][axis[k]]), q[k] = _mm_sub_ps(p[k], o[k]);
    sx[v] = _mm_sub_ps(_mm_mul_ps(dz, q[0]), _mm_mul_ps(dx, q[2]));
    sy[v] = _mm_sub_ps(_mm_mul_ps(dz, q[1]), _mm_mul_ps(dy, q[2]));
    __m128 m[3];
    for (int k = 0; k < 3; ++k)
      m[k] = kRobust ? _mm_andnot_ps(sign, q[k]) : _mm_add_ps(_mm_andnot_ps(sign, p[k]), _mm_andnot_ps(sign, o[k]));
    a[v] = _mm_max_ps(_mm_max_ps(m[0], m[1]), m[2]);
  }
  const __m128 u = _mm_sub_ps(_mm_mul_ps(sx[2], sy[1]), _mm_mul_ps(sy[2], sx[1]));
  const __m128 v = _mm_sub_ps(_mm_mul_ps(sx[0], sy[2]), _mm_mul_ps(sy[0], sx[2]));
  const __m128 w = _mm_sub_ps(_mm_mul_ps(sx[1], sy[0]), _mm_mul_ps(sy[1], sx[0]));
  const __m128 k = _mm_set1_ps(r.edge_k), slack = _mm_set1_ps(kRobust ? 0x1p-100f : 0x1p-80f);
  const __m128 bu = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(a[1], a[2]), k), slack);
  const __m128 bv = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(a[2], a[0]), k), slack);
  const __m128 bw = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(a[0], a[1]), k), slack);
  const __m128 amax = _mm_max_ps(_mm_max_ps(a[0], a[1]), a[2]);
  const __m128 in_range = _mm_cmple_ps(amax, _mm_set1_ps(r.a_limit));
  const __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, bu), _mm_cmpgt_ps(v, bv)), _mm_cmpgt_ps(w, bw));
  const __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, _mm_xor_ps(sign, bu)), _mm_cmplt_ps(v, _mm_xor_ps(sign, bv))),
                               _mm_cmplt_ps(w, _mm_xor_ps(sign, bw)));
  __m128 decided = _mm_and_ps(_mm_and_ps(pos, neg), in_range);
  if constexpr (kRobust) {
    const __m128 det = _mm_add_ps(_mm_add_ps(u, v), w);
    const __m128 sum_abs = _mm_add_ps(_mm_add_ps(_mm_andnot_ps(sign, u), _mm_andnot_ps(sign, v)), _mm_andnot_ps(sign, w));
    const __m128 det_bound = _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_add_ps(bu, bv), bw), _mm_mul_ps(_mm_set1_ps(0x1p-22f), sum_abs)),
                                        _mm_mul_ps(_mm_mul_ps(amax, amax), _mm_set1_ps(r.dn_k)));
    decided = _mm_and_ps(decided, _mm_cmpgt_ps(_mm_andnot_ps(sign, det), det_bound));
  }
  return unsigned(_mm_movemask_ps(decided)) & live;
}

}  // namespace

unsigned robust_group_float_misses(const RobustLaneRay& r, const TriGroup& g, unsigned live) {
  return float_screen<true>(r, g, live);
}

// certified's float screen: the same edge functions, but against the exact answer for the double
// triangle P and the double ray (O, D), of which the group and so, sd are the float roundings. For
// dz != 0 the scaled shear is the projection along D (times dz), so exact U*, V*, W* of mixed
// strict signs mean that the line misses the triangle: certified's exact class is then one
// without a crossing (miss, parallel, degenerate; coplanar needs U* = V* = W* = 0). Error of the
// float U against U*: the inputs carry one rounding each (relative u, or 2^-150 absolutely when
// subnormal; d is screened only when each |D_k| is 0 or >= 2^-120, so its rounding is relative),
// so |q - Q*| <= gamma_2 (|P| + |O|) + 2^-148 instead of u |Q*|: with A_v = max_k (|p_k| + |o_k|),
// |sx - SX*| <= gamma_5 D A_v (+ absolute terms), and |U - U*| <= gamma_12 2 D^2 A_b A_c + 2^-87
// (every A_v <= 2^39 / D, as for robust) < B_u = 2^-18 D^2 A_b A_c + 2^-80. No d . n test: the
// exact signs alone decide. Lanes with a non-finite or out-of-float-range vertex have A_v = inf
// and are not decided.
void certified_lane_ray(const Ray<double>& ray, RobustLaneRay& r) {
  r.kz = max_abs_axis(ray.d);
  r.kx = (r.kz + 1) % 3, r.ky = (r.kx + 1) % 3;
  if (ray.d[r.kz] < 0) std::swap(r.kx, r.ky);
  const int axis[3] = {r.kx, r.ky, r.kz};
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    r.so[i] = float(ray.o[axis[i]]), r.sd[i] = float(ray.d[axis[i]]);
    const double ad = std::fabs(ray.d[axis[i]]);
    ok = ok && (ad == 0 || ad >= 0x1p-120);
  }
  const double dz = std::fabs(ray.d[r.kz]), d = dz + std::max(std::fabs(ray.d[r.kx]), std::fabs(ray.d[r.ky]));
  r.dn_k = 0.0f;
  if (!(ok && d >= 0x1p-20 && d <= 0x1p20)) {
    r.edge_k = 0.0f, r.a_limit = -1.0f;  // off
    return;
  }
  r.edge_k = float(0x1p-18 * d * d) * (1.0f + 0x1p-20f);  // rounded up, as in finish_lane_ray
  r.a_limit = float(0x1p39 / d);
}

unsigned certified_group_float_misses(const RobustLaneRay& r, const TriGroup& g, unsigned live) {
  return float_screen<false>(r, g, live);
}

namespace {
std::atomic<bool> screen_avx2{false};
}  // namespace

void set_robust_screen_avx2(bool on) { screen_avx2.store(on, std::memory_order_relaxed); }
bool robust_screen_avx2() { return screen_avx2.load(std::memory_order_relaxed); }

namespace {
std::atomic<bool> screen_certified{false};
}  // namespace

void set_certified_screen(bool on) { screen_certified.store(on, std::memory_order_relaxed); }
bool certified_screen() { return screen_certified.load(std::memory_order_relaxed); }

namespace {
std::atomic<bool> lazy_setup{true};
}  // namespace
void set_lazy_leaf_setup(bool on) { lazy_setup.store(on, std::memory_order_relaxed); }
bool lazy_leaf_setup() { return lazy_setup.load(std::memory_order_relaxed); }

// mt_surely_no_crossing (kernels.h) in four float lanes; a lane survives unless the scalar screen
// would return true: det != 0 and (!(b1 >= 0) or !(b2 >= 0 and 1 - b1 - b2 >= 0) or t' < 0).
unsigned mt_group_survivors(const Ray<float>& ray, const TriGroup& g, unsigned live) {
  if (!live) return 0;
  __m128 p0[3], e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    p0[k] = _mm_load_ps(g.p[0][k]);
    e1[k] = _mm_sub_ps(_mm_load_ps(g.p[1][k]), p0[k]);
    e2[k] = _mm_sub_ps(_mm_load_ps(g.p[2][k]), p0[k]);
  }
  const __m128 dx = _mm_set1_ps(ray.d.x), dy = _mm_set1_ps(ray.d.y), dz = _mm_set1_ps(ray.d.z);
  // s1 = cross(d, e2), det = dot(s1, e1)
  const __m128 s1x = _mm_sub_ps(_mm_mul_ps(dy, e2[2]), _mm_mul_ps(dz, e2[1]));
  const __m128 s1y = _mm_sub_ps(_mm_mul_ps(dz, e2[0]), _mm_mul_ps(dx, e2[2]));
  const __m128 s1z = _mm_sub_ps(_mm_mul_ps(dx, e2[1]), _mm_mul_ps(dy, e2[0]));
  const __m128 det = _mm_add_ps(_mm_add_ps(_mm_mul_ps(s1x, e1[0]), _mm_mul_ps(s1y, e1[1])), _mm_mul_ps(s1z, e1[2]));
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 inv = _mm_div_ps(one, det);
  // s = o - p0; b1 = dot(s1, s) * inv
  const __m128 sx = _mm_sub_ps(_mm_set1_ps(ray.o.x), p0[0]), sy = _mm_sub_ps(_mm_set1_ps(ray.o.y), p0[1]),
               sz = _mm_sub_ps(_mm_set1_ps(ray.o.z), p0[2]);
  const __m128 b1 = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s1x, sx), _mm_mul_ps(s1y, sy)), _mm_mul_ps(s1z, sz)), inv);
  // s2 = cross(s, e1); b2 = dot(s2, d) * inv; t' = dot(s2, e2) * inv
  const __m128 s2x = _mm_sub_ps(_mm_mul_ps(sy, e1[2]), _mm_mul_ps(sz, e1[1]));
  const __m128 s2y = _mm_sub_ps(_mm_mul_ps(sz, e1[0]), _mm_mul_ps(sx, e1[2]));
  const __m128 s2z = _mm_sub_ps(_mm_mul_ps(sx, e1[1]), _mm_mul_ps(sy, e1[0]));
  const __m128 b2 = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s2x, dx), _mm_mul_ps(s2y, dy)), _mm_mul_ps(s2z, dz)), inv);
  const __m128 tt = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s2x, e2[0]), _mm_mul_ps(s2y, e2[1])), _mm_mul_ps(s2z, e2[2])), inv);
  const __m128 b0 = _mm_sub_ps(_mm_sub_ps(one, b1), b2);
  const __m128 inside = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(b1, zero), _mm_cmpge_ps(b2, zero)),
                                   _mm_and_ps(_mm_cmpge_ps(b0, zero), _mm_cmpnlt_ps(tt, zero)));
  const __m128 survive = _mm_or_ps(_mm_cmpeq_ps(det, zero), inside);
  return unsigned(_mm_movemask_ps(survive)) & live;
}

}  // namespace rayproof::scene::detail
