// The exact stage of the closest-point query: squared distances, closest points and barycentrics
// in GMP rationals (every finite double converts exactly), and the square root rounded correctly
// by comparing the rational against the exact squares of the midpoints between doubles.
#include <gmpxx.h>
#include <mpfr.h>

#include <cmath>
#include <limits>
#include <vector>

#include "exact/rational_vec.h"
#include "exact/rounding.h"
#include "exact/orient_exact.h"
#include "scene/distance_tree.h"

namespace rayproof::scene::detail {

namespace {

using Q = mpq_class;
using QV = exact_algo::QVec;
using exact_algo::rational;

/// The exact closest point of a triangle: squared distance and barycentrics (weights of a, b, c).
struct Exact {
  Q d2, u, v, w;
};

/// Closest point of segment a-b (weights 1 - t, t).
void segment(const QV& p, const QV& a, const QV& b, Q& d2, Q& t) {
  const QV ab = b - a, ap = p - a;
  const Q len = dot(ab, ab), s = dot(ab, ap);
  if (len == 0 || s <= 0) t = 0;
  else if (s >= len) t = 1;
  else t = s / len;
  const QV q{a.x + t * ab.x, a.y + t * ab.y, a.z + t * ab.z};
  const QV d = p - q;
  d2 = dot(d, d);
}

}  // namespace
Exact exact_triangle(const Vec3<double>& pd, const std::array<Vec3<double>, 3>& t, bool degenerate) {
  const QV p = rational(pd), a = rational(t[0]), b = rational(t[1]), c = rational(t[2]);
  Exact r;
  if (degenerate) {  // a zero-area triangle is its three edges: the nearest, the first on ties
    Q d2, s;
    segment(p, a, b, r.d2, s);
    r.u = 1 - s, r.v = s, r.w = 0;
    segment(p, b, c, d2, s);
    if (d2 < r.d2) r.d2 = d2, r.u = 0, r.v = 1 - s, r.w = s;
    segment(p, c, a, d2, s);
    if (d2 < r.d2) r.d2 = d2, r.u = s, r.v = 0, r.w = 1 - s;
    return r;
  }
  // The Voronoi regions of the vertices, edges and face, decided by exact signs.
  const QV ab = b - a, ac = c - a, ap = p - a;
  const Q d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto finish = [&](const Q& u, const Q& v, const Q& w) {
    r.u = u, r.v = v, r.w = w;
    const QV q{u * a.x + v * b.x + w * c.x, u * a.y + v * b.y + w * c.y, u * a.z + v * b.z + w * c.z};
    const QV d = p - q;
    r.d2 = dot(d, d);
    return r;
  };
  if (d1 <= 0 && d2 <= 0) return finish(1, 0, 0);
  const QV bp = p - b;
  const Q d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return finish(0, 1, 0);
  const Q vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Q v = d1 / (d1 - d3);
    return finish(1 - v, v, 0);
  }
  const QV cp = p - c;
  const Q d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return finish(0, 0, 1);
  const Q vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Q w = d2 / (d2 - d6);
    return finish(1 - w, 0, w);
  }
  const Q va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const Q w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return finish(0, 1 - w, w);
  }
  const Q den = va + vb + vc;
  const Q v = vb / den, w = vc / den;
  return finish(1 - v - w, v, w);
}

namespace {
double to_double(const Q& q) { return exact_algo::round_nearest(q.get_mpq_t()); }
}  // namespace

/// sqrt(d2) rounded to the nearest double, ties to even (d2 >= 0): a candidate from MPFR, then
/// exact comparisons of d2 with the squares of the midpoints to the neighbouring doubles
/// (exact_algo::round_by_comparison, the rounding of the exact algorithm's quadric roots).
double round_sqrt(const mpq_class& d2) {
  if (sgn(d2) == 0) return 0.0;
  mpfr_t x;
  mpfr_init2(x, 200);
  mpfr_set_q(x, d2.get_mpq_t(), MPFR_RNDN);
  mpfr_sqrt(x, x, MPFR_RNDN);
  const double candidate = mpfr_get_d(x, MPFR_RNDN);
  mpfr_clear(x);
  // sign(sqrt(d2) - m): sqrt(d2) > 0, so +1 for m <= 0; else the sign of d2 - m^2.
  return exact_algo::round_by_comparison<Q>(candidate, [&](const Q& m) { return sgn(m) <= 0 ? 1 : cmp(d2, m * m); });
}

namespace {

ClosestPoint result(const DistanceTree& t, std::uint32_t slot, const Exact& e) {
  ClosestPoint r;
  r.triangle = t.ids[slot];
  r.distance = round_sqrt(e.d2);
  r.barycentric = {to_double(e.u), to_double(e.v), to_double(e.w)};
  const auto& [a, b, c] = t.tris[slot];
  const Q qa[3] = {Q(a.x), Q(a.y), Q(a.z)}, qb[3] = {Q(b.x), Q(b.y), Q(b.z)}, qc[3] = {Q(c.x), Q(c.y), Q(c.z)};
  double pt[3];
  for (int k = 0; k < 3; ++k) pt[k] = to_double(e.u * qa[k] + e.v * qb[k] + e.w * qc[k]);
  r.point = {pt[0], pt[1], pt[2]};
  return r;
}

}  // namespace

ClosestPoint exact_select(const DistanceTree& t, const Vec3<double>& p, const std::uint32_t* slots, std::size_t n) {
  std::uint32_t best = 0;
  Exact be;
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t s = slots[i];
    Exact e = exact_triangle(p, t.tris[s], t.degenerate[s]);
    if (!any || e.d2 < be.d2 || (e.d2 == be.d2 && t.ids[s] < t.ids[best])) best = s, be = std::move(e), any = true;
  }
  return result(t, best, be);
}

ClosestPoint exact_search(const DistanceTree& t, const Vec3<double>& pd) {
  const QV p = rational(pd);
  std::vector<std::uint32_t> stack{0};
  std::uint32_t best = 0;
  Exact be;
  bool any = false;
  while (!stack.empty()) {
    const DistanceNode& nd = t.nodes[stack.back()];
    stack.pop_back();
    if (any) {
      Q lb = 0;
      const Q pc[3] = {p.x, p.y, p.z};
      for (int k = 0; k < 3; ++k) {
        Q g = 0;
        const double lo = nd.lo[k], hi = nd.hi[k];  // +-inf beyond the float range: no gap on that side
        const double x = k == 0 ? pd.x : (k == 1 ? pd.y : pd.z);
        if (x < lo && std::isfinite(lo)) g = Q(lo) - pc[k];
        else if (x > hi && std::isfinite(hi)) g = pc[k] - Q(hi);
        lb += g * g;
      }
      if (lb > be.d2) continue;
    }
    if (nd.count == 0) {
      stack.push_back(nd.index + 1);
      stack.push_back(nd.index);
      continue;
    }
    for (std::uint32_t s = nd.index; s < nd.index + nd.count; ++s) {
      Exact e = exact_triangle(pd, t.tris[s], t.degenerate[s]);
      if (!any || e.d2 < be.d2 || (e.d2 == be.d2 && t.ids[s] < t.ids[best])) best = s, be = std::move(e), any = true;
    }
  }
  return result(t, best, be);
}


}  // namespace rayproof::scene::detail

namespace rayproof {

namespace {
bool finite(const Vec3<double>& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
bool zero_area(const std::array<Vec3<double>, 3>& t) {
  using certified::orient2d_exact;
  const auto& [a, b, c] = t;
  return orient2d_exact(a.x, a.y, b.x, b.y, c.x, c.y) == 0 && orient2d_exact(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
         orient2d_exact(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
}
}  // namespace

double exact_triangle_distance(const Vec3<double>& p, const std::array<Vec3<double>, 3>& t) {
  if (!finite(p) || !finite(t[0]) || !finite(t[1]) || !finite(t[2])) return std::numeric_limits<double>::quiet_NaN();
  return scene::detail::round_sqrt(scene::detail::exact_triangle(p, t, zero_area(t)).d2);
}

int compare_triangle_distances(const Vec3<double>& p, const std::array<Vec3<double>, 3>& t1,
                               const std::array<Vec3<double>, 3>& t2) {
  const int c = cmp(scene::detail::exact_triangle(p, t1, zero_area(t1)).d2, scene::detail::exact_triangle(p, t2, zero_area(t2)).d2);
  return c < 0 ? -1 : (c > 0 ? 1 : 0);
}

}  // namespace rayproof
