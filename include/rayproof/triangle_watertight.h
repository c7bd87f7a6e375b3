#pragma once
/// Watertight ray/triangle test: Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection",
/// JCGT 2(1), 2013. The vertices are translated to the ray origin, the axes permuted so that the
/// dominant direction component is z, and sheared so that the ray becomes the +z axis; the 2D edge
/// functions U, V, W of the sheared vertices then decide inside/outside. A shared edge is computed
/// from the same two sheared vertices by both triangles, so a ray can never pass between them.
///
/// Classes (docs/cases.md): U, V, W are the unnormalized barycentrics of p0, p1, p2 (b_i = U_i / det);
/// edge / vertex when one / two of them are exactly 0 *in the sheared coordinates* (re-evaluated in
/// double when float gives a zero, as the paper prescribes). det = U + V + W = 0: parallel or
/// coplanar, decided by the plane equation; degenerate when (p1-p0) x (p2-p0) = 0.
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include "rayproof/triangle_common.h"

namespace rayproof {

/// The per-ray part of the test (axis permutation), computed once per ray. A = the arithmetic type:
/// float follows the paper; double on float inputs keeps the products of the sheared coordinates
/// (mostly) exact, so rays through an edge or vertex of exactly representable data stay exact zeros.
template <class T, class A = T>
struct WatertightRay {
  Vec3<A> o, d;
  int kx = 0, ky = 1, kz = 2;
  /// Bounded zeros (A = double): 2^-51 D with D = |d_z| + max(|d_x|, |d_y|), the sheared
  /// coordinates' error bound per A_v (derivation at intersect_watertight); 0 for A = float.
  A edge_k = A(0);

  explicit WatertightRay(const Ray<T>& ray) : o(ray.o.template cast<A>()), d(ray.d.template cast<A>()) {
    // z: the dominant axis of d; x, y follow cyclically, swapped when d_z < 0 to keep the winding.
    kz = max_abs_axis(ray.d);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (ray.d[kz] < T(0)) std::swap(kx, ky);
    if constexpr (std::is_same_v<A, double>) {
      const double D = std::fabs(d[kz]) + std::max(std::fabs(d[kx]), std::fabs(d[ky]));
      edge_k = 0x1p-51 * D;
    }
  }
};

namespace detail {

/// Edge function a_x b_y - a_y b_x, in double when float gives exactly zero (float products are
/// exact in double, so the double sign is the exact sign for the sheared float coordinates).
template <class A>
[[nodiscard]] inline A edge_function(A ax, A ay, A bx, A by) {
  A e = ax * by - ay * bx;
  if constexpr (std::is_same_v<A, float>) {
    if (e == 0.0f) e = static_cast<float>(double(ax) * double(by) - double(ay) * double(bx));
  }
  return e;
}

}  // namespace detail

/// How the prepared test decides an edge function's zero. `exact`: the paper's, U == 0 in the
/// arithmetic type. `bounded` (the default for A = double, i.e. `robust` and `robust-double`): an
/// edge function whose magnitude is within its forward error bound counts as zero, so a ray through
/// an exact edge or vertex is never split into mixed signs by the rounding of the translation and
/// the shear (watertightness alone only guarantees that *one* of the triangles sharing the edge is
/// hit). Near-contacts then come out edge / vertex: false hits, never false misses.
enum class EdgeZeros { exact, bounded };

namespace detail {
template <class A>
inline constexpr EdgeZeros kDefaultZeros = std::is_same_v<A, double> ? EdgeZeros::bounded : EdgeZeros::exact;
}  // namespace detail

/// The watertight test with a prepared ray, for traversal: no screening of invalid or degenerate
/// input; `parallel` stands for det = 0 (parallel to the plane, in it, or a triangle too small for
/// the arithmetic; with bounded zeros: all three edge functions within their bounds, undecided --
/// the front door then reports a contact at the plane's t). The shear is applied scaled by d_z
/// (x' = d_z x - d_x z), which multiplies every edge function by d_z^2 > 0 and avoids the rounded
/// division d_x / d_z of the paper; it is still one linear map per ray, so shared edges still see
/// identical numbers.
///
/// Bounded zeros, the derivation (A = double, u = 2^-53, gamma_n = n u / (1 - n u)). Let a*, sx*,
/// U*, ... be the exact values on the (exact) inputs. The translation a = fl(p - o) errs by at most
/// u |a*|; the shear sx = fl(fl(d_z a_x) - fl(d_x a_z)) carries three roundings per term, so
/// |sx - sx*| <= gamma_3 (|d_z| |a*_x| + |d_x| |a*_z|) <= gamma_3 D A_v / (1 - u) =: e*_v, with D =
/// |d_z| + max(|d_x|, |d_y|) and A_v = max_k |a_v,k| (computed), and sy alike. The kernel's e_v =
/// fl(edge_k A_v), edge_k = fl(2^-51 fl(D)), is >= 4u (1 - 3u) D A_v >= e*_v. Write sx*_c = sx_c +
/// x1, sy*_b = sy_b + y2, ... with |x1|, |y1| <= e_c, |x2|, |y2| <= e_b; then U* = sx*_c sy*_b -
/// sy*_c sx*_b differs from the exact product difference P = sx_c sy_b - sy_c sx_b of the computed
/// coordinates by at most e_c n_b + e_b n_c + 2 e_b e_c, n_v = |sx_v| + |sy_v|, and the computed U =
/// fl(fl(sx_c sy_b) - fl(sy_c sx_b)) differs from P by at most gamma_2 (|sx_c sy_b| + |sy_c sx_b|) <=
/// gamma_2 n_b n_c. So
///   |U - U*| <= E_U = e_c (n_b + e_b) + e_b (n_c + e_c) + 2^-51 n_b n_c
/// (2^-51 >= 2 gamma_2; the 4/3 and 2 of slack in e_v and in 2^-51 cover the at most 7 roundings of
/// computing E_U). The bound scales with the sheared coordinates, not with the distance: a far,
/// small triangle (|sx| small, A large) gets E_U ~ u A D |sx|, not u A^2 D^2. Float inputs never
/// underflow or overflow here (every nonzero |a|, |d| >= 2^-149, so every nonzero computed value
/// above is >= 2^-900; |U| <= 2^517, |ts| <= 2^700). Double inputs (robust-double) add the
/// absolute error of products that underflow (<= 2^-1075 each): e_v gets + 2^-1072 and E_U +
/// 2^-1071 (overflow is not covered, nor a normal that underflows to zero in the front door:
/// robust-double promises nothing on triangles).
/// Decisions. u = 0 when |U| <= E_U, else U; likewise v, w. (1) If u, v, w have mixed strict signs,
/// then |U| > E_U >= |U - U*| gives U* the sign of U, so U*, V*, W* have mixed strict signs: the
/// line misses the triangle (a proven miss). (2) Otherwise |u - U*| <= 2 E_U in both cases (kept:
/// <= E_U; zeroed: |U*| <= |U| + E_U). If the exact answer is a contact, U*, V*, W* do not have
/// mixed signs, so det* = U* + V* + W* has the sign of every nonzero kept u, i.e. of det, and t* >
/// 0 means ts* = U* a*_z + V* b*_z + W* c*_z has the sign of den = det d_z. ts = fl(u a_z + v b_z +
/// w c_z) errs from ts* by at most sum 2 E_U |a*_z| + |u| |a_z - a*_z| + gamma_3 sum |u a_z| <= 2 (1
/// + 2u) sum E_U |a_z| + 5u sum |u a_z| < E_t = 2.001 sum E_U |a_z| + 2^-50 sum |u a_z| (computed:
/// 11 roundings, covered by the slack). So the kernel says `behind` only when ts lies beyond E_t on
/// the side opposite to den: then ts* does too, and an exact contact would be behind. When |ts| <=
/// E_t the sign is undecided and the contact is reported at t = max(0, ts / den). (3) det = u + v +
/// w = 0 only when all three are zeroed: undecided, `parallel` here.
/// No miss or behind the kernel reports can thus be an exact contact at t > 0, and the shared edge
/// of two triangles still sees the same two sheared vertices, so watertightness is kept.
template <class T, class A, EdgeZeros Z = detail::kDefaultZeros<A>>
[[nodiscard]] TriangleHit<T> intersect_watertight(const WatertightRay<T, A>& wr, const Triangle<T>& tri) {
  static_assert(Z == EdgeZeros::exact || std::is_same_v<A, double>, "bounded zeros are derived for double arithmetic");
  const int kx = wr.kx, ky = wr.ky, kz = wr.kz;
  const A dx = wr.d[kx], dy = wr.d[ky], dz = wr.d[kz];
  // Vertices relative to the ray origin.
  const Vec3<A> a = tri.p0.template cast<A>() - wr.o, b = tri.p1.template cast<A>() - wr.o,
                c = tri.p2.template cast<A>() - wr.o;
  // Shear (scaled by d_z): the ray becomes the z axis.
  const A ax = dz * a[kx] - dx * a[kz], ay = dz * a[ky] - dy * a[kz];
  const A bx = dz * b[kx] - dx * b[kz], by = dz * b[ky] - dy * b[kz];
  const A cx = dz * c[kx] - dx * c[kz], cy = dz * c[ky] - dy * c[kz];
  // Edge functions: U for edge p1 p2 (weight of p0), V for p2 p0, W for p0 p1.
  A u = detail::edge_function(cx, cy, bx, by);
  A v = detail::edge_function(ax, ay, cx, cy);
  A w = detail::edge_function(bx, by, ax, ay);
  A eu = A(0), ev = A(0), ew = A(0);
  if constexpr (Z == EdgeZeros::bounded) {
    constexpr A kUnder = std::is_same_v<T, double> ? 0x1p-1072 : 0.0;  // double inputs: underflow
    const A ea = wr.edge_k * std::max(std::max(std::fabs(a[0]), std::fabs(a[1])), std::fabs(a[2])) + kUnder;
    const A eb = wr.edge_k * std::max(std::max(std::fabs(b[0]), std::fabs(b[1])), std::fabs(b[2])) + kUnder;
    const A ec = wr.edge_k * std::max(std::max(std::fabs(c[0]), std::fabs(c[1])), std::fabs(c[2])) + kUnder;
    const A na = std::fabs(ax) + std::fabs(ay), nb = std::fabs(bx) + std::fabs(by), nc = std::fabs(cx) + std::fabs(cy);
    const A ma = na + ea, mb = nb + eb, mc = nc + ec;  // e_c n_b + e_b n_c + 2 e_b e_c = e_c m_b + e_b m_c
    eu = ec * mb + eb * mc + 0x1p-51 * (nb * nc) + 2 * kUnder;
    ev = ea * mc + ec * ma + 0x1p-51 * (nc * na) + 2 * kUnder;
    ew = eb * ma + ea * mb + 0x1p-51 * (na * nb) + 2 * kUnder;
    if (std::fabs(u) <= eu) u = A(0);
    if (std::fabs(v) <= ev) v = A(0);
    if (std::fabs(w) <= ew) w = A(0);
  }
  // Mixed signs: the ray passes outside an edge.
  if ((u < A(0) || v < A(0) || w < A(0)) && (u > A(0) || v > A(0) || w > A(0))) return {Contact::miss};
  const A det = u + v + w;
  if (det == A(0)) return {Contact::parallel};
  // Scaled hit distance: t = (U a_z + V b_z + W c_z) / (det d_z); its sign decides behind before
  // any division.
  const A t_scaled = u * a[kz] + v * b[kz] + w * c[kz];
  const A den = det * dz;
  A t_bound = A(0);
  if constexpr (Z == EdgeZeros::bounded)
    t_bound = 2.001 * (eu * std::fabs(a[kz]) + ev * std::fabs(b[kz]) + ew * std::fabs(c[kz])) +
              0x1p-50 * (std::fabs(u * a[kz]) + std::fabs(v * b[kz]) + std::fabs(w * c[kz]));
  const bool behind = den < A(0) ? t_scaled > t_bound : t_scaled < -t_bound;
  T t = static_cast<T>(t_scaled / den);
  if constexpr (Z == EdgeZeros::bounded) {
    if (!behind && !(t >= T(0))) t = T(0);  // |ts| <= E_t: undecided sign, reported at t = 0
  }
  const T b1 = static_cast<T>(v / det), b2 = static_cast<T>(w / det);
  if (behind) return {Contact::behind, t, kNaN<T>, b1, b2};
  const int zeros = (u == A(0)) + (v == A(0)) + (w == A(0));
  const Contact cls = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {cls, t, kNaN<T>, b1, b2};
}

namespace detail {
/// Bounded zeros' undecided case (all three edge functions within their bounds, d . n != 0): a
/// contact, reported as interior at the plane's t = (p0 - o) . n / (d . n), 0 when that is negative
/// or not a number (the sign of t is not decided either).
template <class T, class A>
[[nodiscard]] TriangleHit<T> undecided_contact(const Vec3<A>& o, const Vec3<A>& p0, const Vec3<A>& n, A dn) {
  const T t = static_cast<T>(dot(p0 - o, n) / dn);
  return {Contact::interior, t >= T(0) ? t : T(0), kNaN<T>, kNaN<T>, kNaN<T>};
}
}  // namespace detail

/// Front door: screens invalid and degenerate input, decides parallel / coplanar by the plane
/// equation (d . n = 0: the sign of (o - p0) . n), then the watertight test; a det = 0 that the
/// plane equation does not confirm is a miss (the paper's "no hit") with exact zeros, and an
/// undecided contact (detail::undecided_contact) with bounded zeros.
template <class T, class A = T, EdgeZeros Z = detail::kDefaultZeros<A>>
[[nodiscard]] TriangleHit<T> intersect_watertight(const Ray<T>& ray, const Triangle<T>& tri) {
  if (!ray.valid() || !triangle_finite(tri)) return {Contact::invalid};
  // Plane equation in the arithmetic type.
  const Ray<A> ra{ray.o.template cast<A>(), ray.d.template cast<A>()};
  const Triangle<A> ta{tri.p0.template cast<A>(), tri.p1.template cast<A>(), tri.p2.template cast<A>()};
  const Vec3<A> n = cross(ta.p1 - ta.p0, ta.p2 - ta.p0);
  if (is_zero(n)) return {Contact::degenerate};
  const A dn = dot(ra.d, n);
  if (dn == A(0)) {
    if (dot(ra.o - ta.p0, n) != A(0)) {
      if constexpr (Z == EdgeZeros::bounded) {
        // A rounded d . n = 0 need not be exact: unless the bounded test proves the line misses
        // (or is undecided), its contact or behind stands. Undecided stays parallel: the one case
        // the no-false-miss argument does not cover (docs/methods.md).
        const TriangleHit<T> h = intersect_watertight<T, A, Z>(WatertightRay<T, A>(ray), tri);
        if (h.contact != Contact::miss && h.contact != Contact::parallel) return h;
      }
      return {Contact::parallel};
    }
    const TriangleHit<A> c = coplanar_range(ra, ta, n);
    return {c.contact, static_cast<T>(c.t), static_cast<T>(c.t2), static_cast<T>(c.b1), static_cast<T>(c.b2)};
  }
  const TriangleHit<T> h = intersect_watertight<T, A, Z>(WatertightRay<T, A>(ray), tri);
  if (h.contact != Contact::parallel) return h;
  if constexpr (Z == EdgeZeros::bounded) return detail::undecided_contact<T>(ra.o, ta.p0, n, dn);
  return {Contact::miss};
}

}  // namespace rayproof
