// ExactMesh::segment: whether the closed segment p->q meets the surface (exact orientation signs),
// the class of each contact, and the first one along the segment (t from the exact determinants,
// rounded).
#include <algorithm>
#include <cmath>
#include <limits>

#include "exact/orient_exact.h"
#include "scene/exact_mesh_state.h"

namespace rayproof {

namespace {

using certified::orient2d_exact;
using certified::orient3d_exact;
using certified::orient3d_value_exact;

inline double coord(const Vec3<double>& p, int k) { return reinterpret_cast<const double*>(&p)[k]; }

struct SegmentContact {
  bool hit = false;
  Contact contact = Contact::miss;
  double t = kNaN<double>;
};

/// Exact intersection of two closed 2D segments (p, q) and (a, b), and where along p->q (rounded).
bool segments_2d(double pu, double pv, double qu, double qv, double au, double av, double bu, double bv, double& t) {
  const int o1 = orient2d_exact(pu, pv, qu, qv, au, av), o2 = orient2d_exact(pu, pv, qu, qv, bu, bv);
  const int o3 = orient2d_exact(au, av, bu, bv, pu, pv), o4 = orient2d_exact(au, av, bu, bv, qu, qv);
  if (o1 * o2 > 0 || o3 * o4 > 0) return false;
  if (o1 == 0 && o2 == 0) {  // collinear: overlapping ranges along the line
    const bool useu = std::fabs(qu - pu) >= std::fabs(qv - pv);
    const double p0 = useu ? pu : pv, q0 = useu ? qu : qv, a0 = useu ? au : av, b0 = useu ? bu : bv;
    const double lo = std::min(a0, b0), hi = std::max(a0, b0);
    const double s0 = std::min(p0, q0), s1 = std::max(p0, q0);
    if (hi < s0 || lo > s1) return false;
    const double first = q0 >= p0 ? std::max(lo, p0) : std::min(hi, p0);
    t = q0 == p0 ? 0.0 : (first - p0) / (q0 - p0);
    return true;
  }
  // Proper or touching crossing: t from the two signed areas at a and b (rounded).
  const double da = (qu - pu) * (av - pv) - (qv - pv) * (au - pu), db = (qu - pu) * (bv - pv) - (qv - pv) * (bu - pu);
  const double s = da == db ? 0.0 : da / (da - db);  // along a->b
  const double xu = au + s * (bu - au), xv = av + s * (bv - av);
  t = std::fabs(qu - pu) >= std::fabs(qv - pv) ? (xu - pu) / (qu - pu) : (xv - pv) / (qv - pv);
  if (!(t >= 0)) t = 0;
  if (t > 1) t = 1;
  return true;
}

/// The closed segment p->q against the closed triangle abc (p != q).
SegmentContact segment_triangle(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p,
                          const Vec3<double>& q) {
  SegmentContact r;
  const int dp = orient3d_exact(a, b, c, p), dq = orient3d_exact(a, b, c, q);
  if (dp * dq > 0) return r;
  if (dp == 0 && dq == 0) {
    // Coplanar: in a projection where the triangle has area, p or q inside, or an edge crossed.
    for (int j = 0; j < 3; ++j) {
      const int u = (j + 1) % 3, v = (j + 2) % 3;
      const double au = coord(a, u), av = coord(a, v), bu = coord(b, u), bv = coord(b, v), cu = coord(c, u), cv = coord(c, v);
      const int s = orient2d_exact(au, av, bu, bv, cu, cv);
      if (s == 0) continue;
      const double pu = coord(p, u), pv = coord(p, v), qu = coord(q, u), qv = coord(q, v);
      auto inside = [&](double xu, double xv) {
        return orient2d_exact(au, av, bu, bv, xu, xv) != -s && orient2d_exact(bu, bv, cu, cv, xu, xv) != -s &&
               orient2d_exact(cu, cv, au, av, xu, xv) != -s;
      };
      r.contact = Contact::coplanar;
      if (inside(pu, pv)) return r.hit = true, r.t = 0, r;
      double best = std::numeric_limits<double>::infinity(), t = 0;
      if (segments_2d(pu, pv, qu, qv, au, av, bu, bv, t)) best = std::min(best, t);
      if (segments_2d(pu, pv, qu, qv, bu, bv, cu, cv, t)) best = std::min(best, t);
      if (segments_2d(pu, pv, qu, qv, cu, cv, au, av, t)) best = std::min(best, t);
      if (best <= 1) return r.hit = true, r.t = best, r;
      return r.contact = Contact::miss, r;
    }
    return r;  // zero-area triangle: never met
  }
  // The line pq meets the plane once, inside the closed triangle iff the three signs agree.
  const int s0 = orient3d_exact(p, q, a, b), s1 = orient3d_exact(p, q, b, c), s2 = orient3d_exact(p, q, c, a);
  if (s0 * s1 < 0 || s1 * s2 < 0 || s0 * s2 < 0) return r;
  const int zeros = (s0 == 0) + (s1 == 0) + (s2 == 0);
  if (zeros == 3) return r;  // zero-area triangle
  r.hit = true;
  r.contact = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  if (dp == 0) {
    r.t = 0;
  } else if (dq == 0) {
    r.t = 1;
  } else {
    const double vp = orient3d_value_exact(a, b, c, p), vq = orient3d_value_exact(a, b, c, q);
    r.t = std::clamp(vp / (vp - vq), 0.0, 1.0);
  }
  return r;
}

}  // namespace

SegmentHit ExactMesh::segment(const Vec3<double>& p, const Vec3<double>& q) const {
  SegmentHit out;
  out.p_side = contains(p), out.q_side = contains(q);
  if (out.p_side == Side::invalid || out.q_side == Side::invalid) return out;
  const auto& s = *s_;
  if (p.x == q.x && p.y == q.y && p.z == q.z) {  // zero length: meets the surface iff p is on it
    out.crosses = out.p_side == Side::surface;
    if (out.crosses) out.t = 0;
    return out;
  }
  auto consider = [&](std::uint32_t tri) {
    const auto& t = s.triangles[tri];
    const Vec3<double>&a = s.vertices[t[0]], &b = s.vertices[t[1]], &c = s.vertices[t[2]];
    const SegmentContact c1 = segment_triangle(a, b, c, p, q);
    if (!c1.hit) return;
    if (!out.crosses || c1.t < out.t || (c1.t == out.t && tri < out.triangle))
      out.crosses = true, out.t = c1.t, out.triangle = tri, out.contact = c1.contact;
  };
  // Candidates: the BVH along p + t (q - p), t in [0, 1], when q - p is exact in double (then the
  // conservative traversal sees every box the segment touches); otherwise every triangle whose box
  // meets the segment's box.
  const Vec3<double> d{q.x - p.x, q.y - p.y, q.z - p.z};
  const bool exact_d =
      two_sum(q.x, -p.x).lo == 0 && two_sum(q.y, -p.y).lo == 0 && two_sum(q.z, -p.z).lo == 0 && all_finite(d);
  if (exact_d) {
    const scene::LeafPrim* leaves = s.accel->leaf_prims().data();
    const double tmax = 1.0;
    s.accel->traverse_slots({p, d}, 0.0, tmax, BvhTraversal::conservative, BvhQuery::all, [&](std::uint32_t j) {
      if (leaves[j].id != scene::PrimHit::kNoPrim) consider(leaves[j].id);
      return false;
    });
  } else {
    const Vec3<double> lo{std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z)};
    const Vec3<double> hi{std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)};
    for (std::uint32_t tri = 0; tri < s.triangles.size(); ++tri) {
      const auto& t = s.triangles[tri];
      bool apart = false;
      for (int k = 0; k < 3 && !apart; ++k) {
        const double x0 = coord(s.vertices[t[0]], k), x1 = coord(s.vertices[t[1]], k), x2 = coord(s.vertices[t[2]], k);
        apart = std::max({x0, x1, x2}) < coord(lo, k) || std::min({x0, x1, x2}) > coord(hi, k);
      }
      if (!apart) consider(tri);
    }
  }
  return out;
}

}  // namespace rayproof
