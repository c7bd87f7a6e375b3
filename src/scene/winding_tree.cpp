// The generalized winding number w(p) = sum_t Omega_t(p) / 4 pi with a guaranteed bound, over a
// tree with a far-field expansion (the approach of Barill, Dickson, Schmidt, Levin and Jacobson,
// "Fast Winding Numbers for Soups and Clouds", 2018, with a truncation bound derived below instead
// of a fixed accuracy parameter). Written here rather than taken from a library: libigl's
// fast_winding_number gives no bound, and the ray BVH of rayproof_scene carries neither moments nor
// bounding balls.
//
// u = 2^-53 throughout. theta_k denotes a factor (1 + t), |t| <= gamma_k = k u / (1 - k u).
//
// 1. One triangle, directly (Van Oosterom and Strackee 1983). With A = a - p, B = b - p, C = c - p
//    and la = |A| etc.,  tan(Omega / 2) = N / D,  N = A . (B x C),
//    D = la lb lc + (A . B) lc + (B . C) la + (C . A) lb,  Omega = 2 atan2(N, D) in (-2 pi, 2 pi].
//    Rounding (no underflow or overflow: every nonzero difference in [2^-300, 2^300], else the
//    triangle is unresolved and goes to the exact stage):
//    * each difference carries theta_1; each of the six products of N carries theta_2 in the cross
//      product, theta_1 in the dot product and theta_2 in its sum, with the differences theta_8:
//      |fl(N) - N| <= gamma_8 P*, P* = sum of the six |A_i B_j C_k|. The permanent P computed the
//      same way is P* theta_8, so |fl(N) - N| <= gamma_8 / (1 - gamma_8) P <= 9u P =: en.
//    * la: the squares carry theta_3 with the differences, the sum theta_2 more, the square root
//      halves that and adds u: la = la* (1 + l), |l| <= 3.6u (1 + O(u)) < 4u.
//      la lb lc: |err| <= 14u L (L = la* lb* lc*). (A . B): |err| <= gamma_5 la* lb*, so
//      (A . B) lc: |err| <= (gamma_5 + 5u) L < 10.1u L (|A . B| <= la lb). The sum of the four
//      terms adds 3u per term (each |term| <= L (1 + 15u)). Total |fl(D) - D| <= 57u L; with the
//      computed L >= L* (1 - 15u): ed := 72u L.
//    * The true (N, D) lies within r := en + ed of the computed (n, d). When the disc of radius r
//      about (n, d) excludes the origin and the cut {N = 0, D <= 0} of atan2 (checked as
//      max(|n|, |d|) > r, and d > 0 or |n| > r), atan2 is continuous on it and changes by at most
//      asin(r / rho) <= (pi / 2) r / rho (rho = |(n, d)| >= max(|n|, |d|)). libm's atan2 is
//      within 2 ulps (of a value <= pi: 2^-50 < 1e-15). So
//      |Omega - fl(Omega)| <= 2 (1.5708 r / max(|n|, |d|) + 1e-15), rounded up by taking 1.6.
//    * Otherwise the triangle is unresolved: p is on, or within rounding of, the triangle's plane
//      and closure (or its coordinates leave the window). Exactly (winding_mpfr.cpp): N = 0 and p
//      on the closed triangle is `surface`; N = 0 elsewhere is Omega = 0 exactly; N != 0 is
//      evaluated in MPFR at increasing precision until the same test passes (it must: N != 0).
//
// 2. A node far away. The solid angle of a surface S is Omega = int_S n . K(x) dA with
//    K(x) = (x - p) / |x - p|^3 = -grad_x G, G(x) = 1 / |x - p|. About the node's centre c, with
//    R = c - p, d = |R| and y = x - c, G(c + y) = sum_l |y|^l / d^(l+1) P_l(cos g) (Legendre;
//    g the angle between y and -R) for |y| < d. Keeping l <= 2 (K to first order in y) gives
//      Omega ~ (N . R + tr M) / d^3 - 3 R^T M R / d^5,
//    N = sum of the area vectors, M_ij = int n_i y_j dA = sum_t areavec_t,i (centroid_t - c)_j
//    (exact for flat triangles). The remainder: each term h_l(y) = |y|^l P_l(cos g) is a harmonic
//    polynomial with |grad h_l| <= sqrt(l (l + 1)) |y|^(l-1) <= (l + 1) |y|^(l-1) (from
//    l^2 P_l^2 + (1 - x^2) P_l'^2 <= l (l + 1), Szego's P_l^2 + (1 - x^2) P_l'^2 / (l (l + 1)) <= 1).
//    With |y| <= r (the node's ball) and q = r / d < 1:
//      |Omega - Omega_2| <= area * sum_{l >= 3} (l + 1) q^(l-1) / d^2 = area q^2 (4 - 3q) / ((1 - q)^2 d^2)
//    (area: the sum of unsigned triangle areas). Rounding: the moments are built bottom-up (depth
//    at most 64), N with at most 72u area per component, M with at most 816u area r per entry, the
//    evaluation adds about 20u (1 + 6q) area / d^2; in all below 2^-38 (1 + q) area / d^2, added.
//    q is computed from r rounded up and d rounded down by the factors (1 +- 2^-40), which cover
//    their few ulps.
//
// 2b. A node near p. Every triangle of a node lies in its ball (c, r) (the convex hull of vertices
//    that do), so for d = |c - p| > r every point x of it has |x - p| >= d - r and
//      |Omega_t| = |int_t n . (x - p) / |x - p|^3 dA| <= int_t dA / |x - p|^2 <= area_t / (d - r)^2.
//    A node too near for the expansion (q > kQMax) but whose ball excludes p contributes 0 with
//    the bound A / (d - r)^2, A >= the sum of its triangles' exact areas (area_up below), instead
//    of being opened at once; refinement by largest error opens it only when its bound matters.
//    This is what decides most points on open meshes: the caps' tree (winding_caps.cpp) only
//    needs |w_caps| < 1/2 about, and the bound is small for every cap node not at p.
//    area_up: with e1, e2 the rounded edges (each component within u of the exact one, relative),
//    each computed cross-product component is within 5u (|e1_j e2_k| + |e1_k e2_j|) <= 5u |e1| |e2|
//    of the exact one, so the exact area is at most (|c| (1 + 8u) + 16u |e1| |e2|) / 2 with |c|
//    computed (its square root and sums err by under 4u) and |e1| |e2| <= 3 max|e1_i| max|e2_i|
//    (no squares). When |c|^2 is below 2^-1000 its squares may have underflowed (a mesh near
//    2^-300: the fuzzer's first run with this bound found areas computed as 0 there), and the area
//    is bounded by |e1| |e2| / 2 instead. 2^-1000 per triangle more covers products that
//    underflowed. Sums up the tree are scaled by (1 + 2^-50) per level.
//    Rounding of the bound: d is taken from d2 (relative error below 4u) times (1 - 2^-40), r times
//    (1 + 2^-40), the gap g = d - r times (1 - 2^-40), the quotient times (1 + 2^-40)^2, plus
//    2^-1060 in case it is subnormal. It is used only for d2 <= 2^1000 (no overflow of d2), g >=
//    2^-400 (no underflow of g^2) and a bound below 8 pi (else the node is opened: the bound would
//    not decide anything).
//
// 4. How fast w changes (CapsField, winding_field.cpp). For p off a triangle t, with r = x - p,
//    grad_p (n . r / |r|^3) = (3 (n . r^) r^ - n) / |r|^3, whose length is sqrt(1 + 3 (n . r^)^2)
//    / |r|^3 <= 2 / |r|^3. So on a ball (x0, h) that every point of t is at least g > 0 away from,
//    |grad Omega_t| <= 2 area_t / g^3, and the segment from x0 to any p of the ball crosses no
//    triangle: w is smooth along it and |w(p) - w(x0)| <= |p - x0| sum 2 area_t / (4 pi g_t^3).
//    A node of ball (c, r) is at least g = |c - x0| - r - h away; gradient_bound takes a node whole
//    where g >= r (or g > 0 at a leaf) with area_up for its area, else opens it, and at a leaf takes
//    each triangle alone: g_t the larger of its plane's and its own ball's distance less h (the
//    plane's with the rounding of the normal bounded as in triangle_reach). d is rounded down and
//    r, h up as in section 2b.
//
// 3. The sum. Recursive summation of k terms errs by at most gamma_{k-1} sum |Omega_i|; dividing by
//    the rounded 4 pi adds 2.1u |w|; every bound is scaled by (1 + 2^-40) to cover its own
//    rounding. WindingSum::value() returns w and the total.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "scene/winding_tree.h"

namespace rayproof::scene::detail {

namespace {

constexpr double kU = 0x1p-53;
constexpr double kUp = 1.0 + 0x1p-40;    // rounds a computed bound up
constexpr double kDown = 1.0 - 0x1p-40;  // rounds a computed distance down

constexpr double kLooseTriangle = kLooseSolidAngle;

/// |x| = 0 or 2^-300 <= |x| <= 2^300: products of three such differences neither underflow nor overflow.
inline bool in_window(double x) {
  const double ax = std::fabs(x);
  return ax == 0 || (ax >= 0x1p-300 && ax <= 0x1p300);
}

}  // namespace

SolidAngle solid_angle_double(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                              const Vec3<double>& p) {
  const double ax = a.x - p.x, ay = a.y - p.y, az = a.z - p.z;
  const double bx = b.x - p.x, by = b.y - p.y, bz = b.z - p.z;
  const double cx = c.x - p.x, cy = c.y - p.y, cz = c.z - p.z;
  if (!(in_window(ax) && in_window(ay) && in_window(az) && in_window(bx) && in_window(by) && in_window(bz) &&
        in_window(cx) && in_window(cy) && in_window(cz)))
    return {0, 0, 1};
  const double m1 = by * cz, m2 = bz * cy, m3 = bz * cx, m4 = bx * cz, m5 = bx * cy, m6 = by * cx;
  const double n = ax * (m1 - m2) + ay * (m3 - m4) + az * (m5 - m6);
  const double perm = std::fabs(ax) * (std::fabs(m1) + std::fabs(m2)) + std::fabs(ay) * (std::fabs(m3) + std::fabs(m4)) +
                      std::fabs(az) * (std::fabs(m5) + std::fabs(m6));
  const double la = std::sqrt(ax * ax + ay * ay + az * az);
  const double lb = std::sqrt(bx * bx + by * by + bz * bz);
  const double lc = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double l3 = la * lb * lc;
  const double d = l3 + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la +
                   (cx * ax + cy * ay + cz * az) * lb;
  const double r = 9 * kU * perm + 72 * kU * l3;
  const double an = std::fabs(n);
  const double rho = std::max(an, std::fabs(d));
  if (!(rho > r) || !(d > 0 || an > r)) return {0, 0, 1};
  const double omega = 2 * std::atan2(n, d);
  return {omega, (3.2 * r / rho + 2e-15) * kUp, 0};
}

WindingValue WindingSum::value() const {
  constexpr double kInv4Pi = 1 / (4 * std::numbers::pi);
  WindingValue v;
  v.w = sum * kInv4Pi;
  const double k = double(terms);
  // err and abs are sums of k nonnegative terms: each within a factor (1 + gamma_k) of the exact sum.
  const double e = (err + (k + 1) * 1.01 * kU * abs) * (1 + (k + 3) * 1.01 * kU);
  v.bound = (e * kInv4Pi * (1 + 4 * kU) + 2.1 * kU * std::fabs(v.w)) * kUp;
  v.surface = false;
  return v;
}

WindingTuning& winding_tuning() {
  static WindingTuning t;
  return t;
}

WindingTree::WindingTree(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t,
                         std::size_t leaf_size)
    : vertices_(v), triangles_(t), leaf_size_(leaf_size), near_bound_(winding_tuning().near_bound) {
  if (leaf_size < 1 || leaf_size > 64) throw std::invalid_argument("WindingTree: leaf size outside [1, 64]");
  if (t.empty()) return;
  std::vector<Vec3<double>> cen(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Vec3<double>&a = v[t[i][0]], &b = v[t[i][1]], &c = v[t[i][2]];
    cen[i] = {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
  }
  std::vector<std::uint32_t> ids(t.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::uint32_t(i);
  nodes_.reserve(2 * (t.size() / 4 + 1));
  tris_.reserve(t.size());
  nodes_.emplace_back();
  build(ids, 0, ids.size(), cen, 0, 0);
}

void WindingTree::build(std::vector<std::uint32_t>& ids, std::size_t lo, std::size_t hi,
                        const std::vector<Vec3<double>>& cen, std::uint32_t self, int depth) {
  // nodes_[self] was allocated by the caller (children in pairs).
  if (depth > 60) throw std::logic_error("WindingTree: depth above 60");
  auto tri = [&](std::uint32_t i) -> std::array<Vec3<double>, 3> {
    return {vertices_[triangles_[i][0]], vertices_[triangles_[i][1]], vertices_[triangles_[i][2]]};
  };
  Node nd{};
  if (hi - lo <= leaf_size_) {
    nd.first = std::uint32_t(tris_.size());
    nd.count = std::uint32_t(hi - lo);
    for (std::size_t i = lo; i < hi; ++i) tris_.push_back(tri(ids[i]));
    // Centre: area-weighted centroid (plain mean when the area is 0).
    double sa = 0, sx = 0, sy = 0, sz = 0;
    std::vector<std::array<double, 4>> av(hi - lo);  // area vector, unsigned area
    for (std::size_t i = lo; i < hi; ++i) {
      const auto& T = tris_[nd.first + (i - lo)];
      const Vec3<double> e1{T[1].x - T[0].x, T[1].y - T[0].y, T[1].z - T[0].z};
      const Vec3<double> e2{T[2].x - T[0].x, T[2].y - T[0].y, T[2].z - T[0].z};
      const double nx = 0.5 * (e1.y * e2.z - e1.z * e2.y), ny = 0.5 * (e1.z * e2.x - e1.x * e2.z),
                   nz = 0.5 * (e1.x * e2.y - e1.y * e2.x);
      const double ar = std::sqrt(nx * nx + ny * ny + nz * nz);
      av[i - lo] = {nx, ny, nz, ar};
      // The rigorous upper bound of section 2b (ar is |c| / 2; lp >= |e1| |e2| without squares).
      const double m1 = std::max({std::fabs(e1.x), std::fabs(e1.y), std::fabs(e1.z)});
      const double m2 = std::max({std::fabs(e2.x), std::fabs(e2.y), std::fabs(e2.z)});
      const double lp = 3 * m1 * m2 * (1 + 4 * kU), nn = nx * nx + ny * ny + nz * nz;
      nd.area_up += ((nn >= 0x1p-1000 ? ar * (1 + 8 * kU) + 8 * kU * lp : 0.5 * lp) + 0x1p-1000) * kUp;
      const Vec3<double>& g = cen[ids[i]];
      sa += ar, sx += ar * g.x, sy += ar * g.y, sz += ar * g.z;
    }
    if (sa > 0) {
      nd.c[0] = sx / sa, nd.c[1] = sy / sa, nd.c[2] = sz / sa;
    } else {
      double mx = 0, my = 0, mz = 0;
      for (std::size_t i = lo; i < hi; ++i) mx += cen[ids[i]].x, my += cen[ids[i]].y, mz += cen[ids[i]].z;
      const double k = double(hi - lo);
      nd.c[0] = mx / k, nd.c[1] = my / k, nd.c[2] = mz / k;
    }
    double r2 = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      const auto& T = tris_[nd.first + (i - lo)];
      for (const auto& q : T) {
        const double dx = q.x - nd.c[0], dy = q.y - nd.c[1], dz = q.z - nd.c[2];
        r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
      }
      const auto& a = av[i - lo];
      const Vec3<double>& g = cen[ids[i]];
      const double y[3] = {g.x - nd.c[0], g.y - nd.c[1], g.z - nd.c[2]};
      nd.area += a[3];
      for (int k = 0; k < 3; ++k) {
        nd.n[k] += a[k];
        for (int j = 0; j < 3; ++j) nd.m[3 * k + j] += a[k] * y[j];
      }
    }
    nd.r = std::sqrt(r2);
    nodes_[self] = nd;
    return;
  }
  // Split at the median of the centroids along the longest axis of their box.
  double lo3[3] = {1e308, 1e308, 1e308}, hi3[3] = {-1e308, -1e308, -1e308};
  for (std::size_t i = lo; i < hi; ++i) {
    const double g[3] = {cen[ids[i]].x, cen[ids[i]].y, cen[ids[i]].z};
    for (int k = 0; k < 3; ++k) lo3[k] = std::min(lo3[k], g[k]), hi3[k] = std::max(hi3[k], g[k]);
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (hi3[k] - lo3[k] > hi3[axis] - lo3[axis]) axis = k;
  const std::size_t mid = lo + (hi - lo) / 2;
  std::nth_element(ids.begin() + std::ptrdiff_t(lo), ids.begin() + std::ptrdiff_t(mid), ids.begin() + std::ptrdiff_t(hi),
                   [&](std::uint32_t x, std::uint32_t y) {
                     const double gx = reinterpret_cast<const double*>(&cen[x])[axis];
                     const double gy = reinterpret_cast<const double*>(&cen[y])[axis];
                     return gx < gy || (gx == gy && x < y);
                   });
  const std::uint32_t kid = std::uint32_t(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(ids, lo, mid, cen, kid, depth + 1);
  build(ids, mid, hi, cen, kid + 1, depth + 1);
  const Node &L = nodes_[kid], &Rn = nodes_[kid + 1];
  nd.first = kid;
  nd.count = 0;
  nd.area = L.area + Rn.area;
  nd.area_up = (L.area_up + Rn.area_up) * (1 + 0x1p-50);
  if (nd.area > 0) {
    for (int k = 0; k < 3; ++k) nd.c[k] = (L.area * L.c[k] + Rn.area * Rn.c[k]) / nd.area;
  } else {
    for (int k = 0; k < 3; ++k) nd.c[k] = 0.5 * (L.c[k] + Rn.c[k]);
  }
  double r = 0;
  for (const Node* ch : {&L, &Rn}) {
    const double dx = ch->c[0] - nd.c[0], dy = ch->c[1] - nd.c[1], dz = ch->c[2] - nd.c[2];
    r = std::max(r, std::sqrt(dx * dx + dy * dy + dz * dz) + ch->r);
    const double s[3] = {dx, dy, dz};
    for (int k = 0; k < 3; ++k) {
      nd.n[k] += ch->n[k];
      for (int j = 0; j < 3; ++j) nd.m[3 * k + j] += ch->m[3 * k + j] + ch->n[k] * s[j];
    }
  }
  // The children's balls hold every vertex; rounding of the sum is covered by kUp at use.
  nd.r = r;
  nodes_[self] = nd;
}

namespace {
/// A node's far-field term at p and its bound (section 2), when its ball is seen at r / d <= qmax.
struct FarTerm {
  bool ok = false;
  double omega = 0, err = 0;
};
template <class Node>
inline FarTerm far_expansion(const Node& nd, double rx, double ry, double rz, double d2, double qmax) {
  const double rr = nd.r * kUp;
  // The analysis of section 2 counts relative rounding only: the moments (area r), their products
  // with R (up to area r d^2) and the bound's terms (area q^2 / d^2) must neither underflow nor
  // overflow. With r and d in [2^-100, 2^100] and area >= 2^-250 (area <= 2^34 r^2 for any node)
  // every such value stays within [2^-900, 2^500], and a child's moments that underflowed err by
  // less than 2^-1000 against its parent's 816u area r. Outside that window (meshes near 2^+-300,
  // points very far away, nodes of nearly degenerate triangles) the node is opened instead: its
  // triangles are evaluated directly, with the exponent window of section 1 and the exact stage.
  if (!(rr >= 0x1p-100 && d2 >= 0x1p-200 && d2 <= 0x1p200 && nd.area >= 0x1p-250)) return {};
  // Admissible: r_up <= qmax d_down (squared: d2 has relative error below 3u + the differences').
  if (!(d2 > 0 && rr * rr <= qmax * qmax * d2 * kDown)) return {};
  const double d = std::sqrt(d2);
  const double q = rr / (d * kDown);
  const double inv_d2 = 1 / d2, inv_d3 = inv_d2 / d;
  const double* m = nd.m;
  const double tr = m[0] + m[4] + m[8];
  const double rmr = rx * (m[0] * rx + m[1] * ry + m[2] * rz) + ry * (m[3] * rx + m[4] * ry + m[5] * rz) +
                     rz * (m[6] * rx + m[7] * ry + m[8] * rz);
  const double omega = (nd.n[0] * rx + nd.n[1] * ry + nd.n[2] * rz + tr) * inv_d3 - 3 * rmr * inv_d3 * inv_d2;
  const double one_q = 1 - q;
  const double trunc = nd.area * q * q * (4 - 3 * q) / (one_q * one_q) * inv_d2;
  const double round = 0x1p-38 * (1 + q) * nd.area * inv_d2;
  return {true, omega, (trunc + round) * (1 + 8 * kU) * kUp / (kDown * kDown)};
}
template <class Node>
inline FarTerm far_term(const Node& nd, const Vec3<double>& p, double qmax) {
  const double rx = nd.c[0] - p.x, ry = nd.c[1] - p.y, rz = nd.c[2] - p.z;
  return far_expansion(nd, rx, ry, rz, rx * rx + ry * ry + rz * rz, qmax);
}
/// The term refinement starts from: the expansion where admissible (its bound is then always
/// below the near bound: 2.5 A / d^2 against 4 A / d^2 at q = 1/2), else with `near` the bound of
/// section 2b when p is outside the node's ball.
template <class Node>
inline FarTerm node_term(const Node& nd, const Vec3<double>& p, bool near) {
  const double rx = nd.c[0] - p.x, ry = nd.c[1] - p.y, rz = nd.c[2] - p.z;
  const double d2 = rx * rx + ry * ry + rz * rz;
  const FarTerm f = far_expansion(nd, rx, ry, rz, d2, WindingTree::kQMax);
  if (f.ok || !near || !(d2 <= 0x1p1000)) return f;
  const double g = (std::sqrt(d2) * kDown - nd.r * kUp) * kDown;
  if (!(g >= 0x1p-400)) return f;
  const double e = nd.area_up / (g * g) * (kUp * kUp) + 0x1p-1060;
  if (!(e < 8 * std::numbers::pi)) return f;
  return {true, 0.0, e};
}
}  // namespace

template <class Done>
WindingValue WindingTree::refine(const Vec3<double>& p, Done&& done) const {
  WindingValue v;
  if (nodes_.empty()) {
    v.w = 0, v.bound = 0;
    return v;
  }
  struct Item {
    double err, omega;
    std::uint32_t node;
    bool operator<(const Item& o) const { return err < o.err; }
  };
  thread_local std::vector<Item> heap;  // reused: no allocation per point
  heap.clear();
  WindingSum direct;
  double far_sum = 0, far_err = 0;  // running, for the stopping heuristic only
  bool surface = false;
  std::uint32_t stack[128];
  auto open = [&](std::uint32_t root) {
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
      const Node& nd = nodes_[stack[--top]];
      if (nd.count == 0) {
        for (std::uint32_t k : {nd.first, nd.first + 1}) {
          const FarTerm f = node_term(nodes_[k], p, near_bound_);
          if (f.ok) {
            heap.push_back({f.err, f.omega, k});
            std::push_heap(heap.begin(), heap.end());
            far_sum += f.omega, far_err += f.err;
          } else {
            if (top >= 127) throw std::logic_error("WindingTree: stack overflow");
            stack[top++] = k;
          }
        }
        continue;
      }
      for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
        const auto& T = tris_[i];
        SolidAngle a = solid_angle_double(T[0], T[1], T[2], p);
        if (a.status != 0 || a.err > kLooseTriangle) a = solid_angle_resolved(T[0], T[1], T[2], p);
        if (a.status == 2) return (void)(surface = true);
        direct.add(a.omega, a.err);
      }
    }
  };
  constexpr double kInv4Pi = 1 / (4 * std::numbers::pi);
  const FarTerm rootf = node_term(nodes_[0], p, near_bound_);
  if (rootf.ok) {
    heap.push_back({rootf.err, rootf.omega, 0});
    far_sum = rootf.omega, far_err = rootf.err;
  } else {
    open(0);
  }
  for (;;) {
    if (surface) {
      v.surface = true, v.bound = 0, v.w = kNaN<double>;
      return v;
    }
    const double w = (far_sum + direct.sum) * kInv4Pi, b = (far_err + direct.err) * kInv4Pi;
    if (heap.empty() || done(w, b * 1.01 + 1e-15)) {
      // The rigorous value: a fresh sum of the terms held.
      WindingSum s = direct;
      for (const Item& it : heap) s.add(it.omega, it.err);
      v = s.value();
      if (heap.empty() || done(v.w, v.bound)) return v;
    }
    std::pop_heap(heap.begin(), heap.end());
    const Item it = heap.back();
    heap.pop_back();
    far_sum -= it.omega, far_err -= it.err;
    open(it.node);
  }
}

namespace {
/// A rigorous upper bound on a triangle's area, and a lower bound g on the distance from the
/// ball (x0, h) to it (g <= 0: it may meet the ball). Section 4.
struct TriangleReach {
  double area_up, g;
};
inline TriangleReach triangle_reach(const std::array<Vec3<double>, 3>& T, const Vec3<double>& x0, double h) {
  const Vec3<double>&a = T[0], &b = T[1], &c = T[2];
  const double e1x = b.x - a.x, e1y = b.y - a.y, e1z = b.z - a.z;
  const double e2x = c.x - a.x, e2y = c.y - a.y, e2z = c.z - a.z;
  const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
  const double nn = nx * nx + ny * ny + nz * nz, ln = std::sqrt(nn);
  const double m1 = std::max({std::fabs(e1x), std::fabs(e1y), std::fabs(e1z)});
  const double m2 = std::max({std::fabs(e2x), std::fabs(e2y), std::fabs(e2z)});
  const double lp = 3 * m1 * m2 * (1 + 4 * kU);  // >= |e1| |e2| >= twice the area
  // As the leaves' area_up of section 2b, for one triangle.
  const double area_up = ((nn >= 0x1p-1000 ? 0.5 * ln * (1 + 8 * kU) + 8 * kU * lp : 0.5 * lp) + 0x1p-1000) * kUp;
  // The triangle's ball about its vertex mean.
  const double cx = (a.x + b.x + c.x) / 3, cy = (a.y + b.y + c.y) / 3, cz = (a.z + b.z + c.z) / 3;
  double r2 = 0;
  for (const Vec3<double>* v : {&a, &b, &c}) {
    const double dx = v->x - cx, dy = v->y - cy, dz = v->z - cz;
    r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
  }
  const double ox = cx - x0.x, oy = cy - x0.y, oz = cz - x0.z;
  const double g_ball = (std::sqrt(ox * ox + oy * oy + oz * oz) * kDown - std::sqrt(r2) * kUp - h) * kDown;
  // The plane: |N . (x0 - a)| / |N| with N the exact normal. Each of the computed n's components
  // is within 5u (|e1_j e2_k| + |e1_k e2_j|) <= 10u m1 m2 of N's (the edges' own rounding
  // included), v = x0 - a within u relative; so |n . v - N . v_exact| <= 64u m1 m2 mv, and
  // |N| <= |n| + 18u m1 m2.
  const double vx = x0.x - a.x, vy = x0.y - a.y, vz = x0.z - a.z;
  const double mv = std::max({std::fabs(vx), std::fabs(vy), std::fabs(vz)});
  const double dot = std::fabs(nx * vx + ny * vy + nz * vz);
  double g_plane = -1;
  if (nn >= 0x1p-1000 && std::isfinite(dot)) {
    const double num = (dot - 64 * kU * m1 * m2 * mv) * kDown;
    const double den = (ln + 18 * kU * m1 * m2) * kUp;
    g_plane = (num / den * kDown - h) * kDown;
  }
  return {area_up, std::max(g_ball, g_plane)};
}
}  // namespace

double WindingTree::gradient_bound(const Vec3<double>& x0, double h, double tau, std::vector<std::uint32_t>* near,
                                   std::size_t max_near) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double k4Pi = 4 * std::numbers::pi;
  if (nodes_.empty()) return 0;
  double sum = 0;  // of 2 area_up / g^3, each rounded up
  double terms = 0;
  // A term is taken when its share of the spread, 2 A h / (4 pi g^3), is at most tau (any share
  // without a near list); otherwise the node is opened and a leaf's triangle goes to the list.
  const double share = near ? tau * k4Pi / (2 * h) : kInf;  // 2 A h / (4 pi g^3) <= tau  <=>  A / g^3 <= share
  auto near_triangle = [&](std::uint32_t i) {
    if (!near || near->size() >= max_near) return false;
    near->push_back(i);
    return true;
  };
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    const double dx = nd.c[0] - x0.x, dy = nd.c[1] - x0.y, dz = nd.c[2] - x0.z;
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz) * kDown;
    const double g = (d - nd.r * kUp - h) * kDown;
    const bool leaf = nd.count != 0;
    if (g >= 0x1p-300 && (leaf || g >= nd.r) && nd.area_up / (g * g * g) <= share) {
      sum += 2 * nd.area_up / (g * g * g) * (kUp * kUp);
      terms += 1;
      continue;
    }
    if (!(g == g)) return kInf;
    if (leaf) {
      // Each triangle alone: its distance from the ball is at least the larger of its plane's and
      // its own ball's distance from it.
      for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
        const TriangleReach t = triangle_reach(tris_[i], x0, h);
        if (t.g >= 0x1p-300 && t.area_up / (t.g * t.g * t.g) <= share) {
          sum += 2 * t.area_up / (t.g * t.g * t.g) * (kUp * kUp);
          terms += 1;
        } else if (!near_triangle(i)) {
          return kInf;
        }
      }
      continue;
    }
    if (top + 2 > 128) throw std::logic_error("WindingTree: stack overflow");
    stack[top++] = nd.first;
    stack[top++] = nd.first + 1;
  }
  // A sum of k nonnegative terms errs by at most gamma_k relative; the division by 4 pi by 2u more.
  return sum / k4Pi * (1 + (terms + 4) * 1.01 * kU) * kUp;
}

WindingValue WindingTree::eval(const Vec3<double>& p, double beta) const {
  WindingSum s;
  if (nodes_.empty()) {
    WindingValue v;
    v.w = 0, v.bound = 0;
    return v;
  }
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (const FarTerm f = far_term(nd, p, beta); f.ok) {
      s.add(f.omega, f.err);
      continue;
    }
    if (nd.count == 0) {
      if (top + 2 > 128) throw std::logic_error("WindingTree: stack overflow");
      // Nearer child last (popped first) does not matter for a sum; keep it simple.
      stack[top++] = nd.first;
      stack[top++] = nd.first + 1;
      continue;
    }
    for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
      const auto& T = tris_[i];
      SolidAngle a = solid_angle_double(T[0], T[1], T[2], p);
      if (a.status != 0 || a.err > kLooseTriangle) a = solid_angle_resolved(T[0], T[1], T[2], p);
      if (a.status == 2) {
        WindingValue v;
        v.surface = true;
        v.bound = 0;
        return v;
      }
      s.add(a.omega, a.err);
    }
  }
  return s.value();
}

WindingValue WindingTree::value(const Vec3<double>& p, double tolerance) const {
  return refine(p, [tolerance](double, double bound) { return bound <= tolerance; });
}

WindingValue WindingTree::value_against(const Vec3<double>& p, double offset) const {
  return refine(p, [offset](double w, double bound) { return std::fabs(offset - w - 0.5) > bound; });
}

Side WindingTree::side(const Vec3<double>& p, bool* tie) const {
  if (tie) *tie = false;
  const WindingValue v = refine(p, [](double w, double bound) { return std::fabs(w - 0.5) > bound; });
  if (v.surface) return Side::surface;
  if (std::fabs(v.w - 0.5) > v.bound) return v.w > 0.5 ? Side::inside : Side::outside;
  // Every triangle directly and still within a few ulps per triangle of 1/2: every triangle and
  // the sum in MPFR.
  for (int bits : {256, 1024}) {
    int vs = 0;
    const WindingValue m = winding_mpfr(vertices_, triangles_, p, bits, &vs);
    if (m.surface) return Side::surface;
    if (vs != 0) return vs > 0 ? Side::inside : Side::outside;
  }
  if (tie) *tie = true;
  return Side::outside;
}

WindingValue winding_brute_force(std::span<const Vec3<double>> vertices,
                                 std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p) {
  WindingValue v;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return v;
  WindingSum s;
  for (const auto& t : triangles) {
    if (t[0] >= vertices.size() || t[1] >= vertices.size() || t[2] >= vertices.size())
      throw std::out_of_range("winding_brute_force: vertex index out of range");
    const Vec3<double>&a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    SolidAngle x = solid_angle_double(a, b, c, p);
    if (x.status != 0 || x.err > kLooseTriangle) x = solid_angle_resolved(a, b, c, p);
    if (x.status == 2) {
      v.surface = true, v.bound = 0;
      return v;
    }
    s.add(x.omega, x.err);
  }
  return s.value();
}

}  // namespace rayproof::scene::detail

namespace rayproof {

WindingValue winding_brute_force(std::span<const Vec3<double>> vertices,
                                 std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p) {
  return scene::detail::winding_brute_force(vertices, triangles, p);
}

double winding_plain_double(std::span<const Vec3<double>> vertices,
                            std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p) {
  double sum = 0;
  for (const auto& t : triangles) {
    const Vec3<double>&a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    const double ax = a.x - p.x, ay = a.y - p.y, az = a.z - p.z;
    const double bx = b.x - p.x, by = b.y - p.y, bz = b.z - p.z;
    const double cx = c.x - p.x, cy = c.y - p.y, cz = c.z - p.z;
    const double la = std::sqrt(ax * ax + ay * ay + az * az), lb = std::sqrt(bx * bx + by * by + bz * bz),
                 lc = std::sqrt(cx * cx + cy * cy + cz * cz);
    const double n = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
    const double d = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la +
                     (cx * ax + cy * ay + cz * az) * lb;
    sum += 2 * std::atan2(n, d);
  }
  return sum / (4 * std::numbers::pi);
}

}  // namespace rayproof
