// ClosedMesh::crossings: every point where a ray passes through the surface, once, with its
// direction, and the touches apart (docs/contains.md, "Crossings").
//
// Candidates: the BVH along the ray (conservative traversal), each triangle classified by the
// certified filter (rayproof/certified_triangle.h; its exact fallback where it cannot decide):
// the exact contact class and t within one ulp. An interior contact is a crossing of that
// triangle. An edge or vertex contact is decided by Simulation of Simplicity: the ray's origin
// moved to o + eps e_x + eps^2 e_y + eps^3 e_z (eps -> 0+) changes the edge function
// E_ab(o) = d . ((a - o) x (b - o)) into E_ab(o) + delta . ((a - b) x d), so an edge function that
// is exactly 0 takes the sign of the first nonzero component of (a - b) x d (never all zero unless
// the edge is parallel to d, and then the triangle is parallel to the ray and never crossed). The
// perturbed ray crosses the triangle iff its three edge functions have the sign of d . n. Contacts
// at the same exact t (the same point of the ray) are one contact: their net count of perturbed
// crossings (+1 in, -1 out each) is the crossing (or, 0, a touch). Equal rounded t do not say equal
// exact t, nor the reverse: contacts whose t lie within two ulps are ordered and grouped by their
// exact t in GMP rationals, and their t is then the exact t correctly rounded (MPFR), so the listed
// t never decrease.
#include <gmpxx.h>
#include <mpfr.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rayproof/certified/intersect.h"
#include "scene/contains_state.h"

namespace rayproof {

const char* to_string(CrossingDirection d) { return d == CrossingDirection::in ? "in" : "out"; }

namespace {

int sgn(const mpq_class& x) {
  const int s = mpq_sgn(x.get_mpq_t());
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

struct Q3 {
  mpq_class x, y, z;
};
Q3 q3(const Vec3<double>& p) { return {mpq_class(p.x), mpq_class(p.y), mpq_class(p.z)}; }
Q3 sub(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 cross(const Q3& a, const Q3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
mpq_class dot(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// The exact t = ((p0 - o) . n) / (d . n) (d . n != 0).
mpq_class exact_t(const Ray<double>& r, const std::array<Vec3<double>, 3>& p) {
  const Q3 p0 = q3(p[0]);
  const Q3 n = cross(sub(q3(p[1]), p0), sub(q3(p[2]), p0));
  return mpq_class(dot(sub(p0, q3(r.o)), n) / dot(q3(r.d), n));
}

/// x rounded to the nearest double (ties to even).
double round_nearest(const mpq_class& x) {
  mpfr_t r;
  mpfr_init2(r, 53);
  mpfr_set_q(r, x.get_mpq_t(), MPFR_RNDN);
  const double d = mpfr_get_d(r, MPFR_RNDN);
  mpfr_clear(r);
  return d;
}

/// Sign of d . n, n = (p1 - p0) x (p2 - p0): in double when the error bound allows (every rounding
/// counted: gamma_7 of the permanent, well inside 2^-49 of it), else in GMP.
int sign_dn(const Vec3<double>& d, const std::array<Vec3<double>, 3>& p) {
  const Vec3<double> e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double dn = d.x * (e1.y * e2.z - e1.z * e2.y) + d.y * (e1.z * e2.x - e1.x * e2.z) + d.z * (e1.x * e2.y - e1.y * e2.x);
  const double perm = std::fabs(d.x) * (std::fabs(e1.y * e2.z) + std::fabs(e1.z * e2.y)) +
                      std::fabs(d.y) * (std::fabs(e1.z * e2.x) + std::fabs(e1.x * e2.z)) +
                      std::fabs(d.z) * (std::fabs(e1.x * e2.y) + std::fabs(e1.y * e2.x));
  if (perm > 0x1p-900 && perm < 0x1p1000 && std::fabs(dn) > 0x1p-49 * perm) return dn > 0 ? 1 : -1;
  const Q3 q0 = q3(p[0]);
  return sgn(dot(q3(d), cross(sub(q3(p[1]), q0), sub(q3(p[2]), q0))));
}

/// An edge or vertex contact: d . n's sign and whether the perturbed ray crosses the triangle.
struct Decided {
  int sdn = 0;
  bool crossed = false;
};
Decided decide_perturbed(const Ray<double>& r, const std::array<Vec3<double>, 3>& p) {
  const Q3 o = q3(r.o), d = q3(r.d);
  const Q3 P[3] = {q3(p[0]), q3(p[1]), q3(p[2])};
  const Q3 A[3] = {sub(P[0], o), sub(P[1], o), sub(P[2], o)};
  // u_i: the edge function of edge (p_{i+1}, p_{i+2}); their sum is d . n.
  int s[3];
  mpq_class den = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const mpq_class u = dot(d, cross(A[j], A[k]));
    den += u;
    s[i] = sgn(u);
    if (s[i] == 0) {
      const Q3 g = cross(sub(P[j], P[k]), d);  // the perturbation's coefficients: eps, eps^2, eps^3
      s[i] = sgn(g.x) ? sgn(g.x) : (sgn(g.y) ? sgn(g.y) : sgn(g.z));
    }
  }
  Decided out;
  out.sdn = sgn(den);
  out.crossed = out.sdn != 0 && s[0] == out.sdn && s[1] == out.sdn && s[2] == out.sdn;
  return out;
}

struct Candidate {
  double t;
  std::uint32_t triangle;
  std::uint32_t slot;
  Contact contact;
  int net;  ///< +1 crossed in, -1 crossed out, 0 not crossed by the perturbed ray
};

/// Two ulps above x (the rounded t of two contacts at the same exact t differ by at most that).
double up2(double x) {
  const double inf = std::numeric_limits<double>::infinity();
  return std::nextafter(std::nextafter(x, inf), inf);
}
double down2(double x) {
  const double inf = std::numeric_limits<double>::infinity();
  return std::nextafter(std::nextafter(x, -inf), -inf);
}

}  // namespace

RayCrossings ClosedMesh::crossings(const Ray<double>& ray, TRange range) const {
  RayCrossings out;
  if (!ray.valid() || !(range.tmin <= range.tmax)) return out;
  out.valid = true;
  const auto& s = *s_;
  if (s.triangles.empty()) return out;
  const scene::LeafPrim* leaves = s.accel->leaf_prims().data();
  const std::array<Vec3<double>, 3>* slots = s.slots.data();
  const double lo = down2(range.tmin), hi = up2(range.tmax);
  std::vector<Candidate> cand;
  s.accel->traverse_slots(ray, lo, hi, BvhTraversal::conservative, BvhQuery::all, [&](std::uint32_t j) {
    const scene::LeafPrim& lp = leaves[j];
    if (lp.id == scene::PrimHit::kNoPrim) return false;
    const Triangle<double> tri{slots[j][0], slots[j][1], slots[j][2]};
    Hit<double> h;
    if (const auto f = certified::triangle(ray, tri)) {
      h = *f;
    } else {
      const TriangleHit<double> x = certified::intersect(ray, tri);
      h = {x.contact, x.t, x.t2};
    }
    switch (h.contact) {
      case Contact::interior:
        if (h.t >= lo && h.t <= hi) cand.push_back({h.t, lp.id, j, h.contact, -sign_dn(ray.d, slots[j])});
        break;
      case Contact::edge:
      case Contact::vertex:
        if (h.t >= lo && h.t <= hi) {
          const Decided dd = decide_perturbed(ray, slots[j]);
          cand.push_back({h.t, lp.id, j, h.contact, dd.crossed ? -dd.sdn : 0});
        }
        break;
      case Contact::coplanar:
        if (h.t <= range.tmax && h.t2 >= range.tmin)  // NaN (no range on the triangle) fails both
          out.touches.push_back({std::max(h.t, range.tmin), std::min(h.t2, range.tmax), lp.id, Contact::coplanar});
        break;
      default:
        break;
    }
    return false;
  });
  std::sort(cand.begin(), cand.end(),
            [](const Candidate& a, const Candidate& b) { return a.t != b.t ? a.t < b.t : a.triangle < b.triangle; });
  // Runs whose rounded t chain within two ulps: ordered and grouped by exact t.
  std::vector<mpq_class> exact;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < cand.size();) {
    std::size_t e = i + 1;
    while (e < cand.size() && cand[e].t <= up2(cand[e - 1].t)) ++e;
    // groups: [b, g) ranges of equal exact t, in exact order, as indices into cand
    std::vector<std::pair<std::size_t, std::size_t>> groups;
    order.clear();
    for (std::size_t k = i; k < e; ++k) order.push_back(k);
    if (e - i == 1) {
      groups.push_back({0, 1});
    } else {
      exact.clear();
      for (std::size_t k = i; k < e; ++k) exact.push_back(exact_t(ray, slots[cand[k].slot]));
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return exact[a - i] < exact[b - i]; });
      for (std::size_t b = 0; b < order.size();) {
        std::size_t g = b + 1;
        while (g < order.size() && exact[order[g] - i] == exact[order[b] - i]) ++g;
        groups.push_back({b, g});
        b = g;
      }
    }
    for (const auto& [b, g] : groups) {
      // In a run, the contact's t correctly rounded from its exact value: monotone in the exact t,
      // so the listed t never decrease (a lone contact keeps the filter's t, within one ulp).
      const double t = e - i == 1 ? cand[i].t : round_nearest(exact[order[b] - i]);
      int net = 0;
      for (std::size_t k = b; k < g; ++k) net += cand[order[k]].net;
      // The reported triangle: the lowest-numbered one crossed in the net's direction, or (a touch)
      // the lowest-numbered one met; its t is the contact's.
      const Candidate* rep = nullptr;
      Contact worst = Contact::interior;
      for (std::size_t k = b; k < g; ++k) {
        const Candidate& c = cand[order[k]];
        if (c.contact == Contact::vertex || (c.contact == Contact::edge && worst == Contact::interior)) worst = c.contact;
        const bool fits = net == 0 || (net > 0 ? c.net > 0 : c.net < 0);
        if (fits && (!rep || c.triangle < rep->triangle)) rep = &c;
      }
      if (!(t >= range.tmin && t <= range.tmax)) continue;
      if (net == 0) {
        out.touches.push_back({t, t, rep->triangle, worst});
      } else {
        const CrossingDirection dir = net > 0 ? CrossingDirection::in : CrossingDirection::out;
        for (int m = 0; m < std::abs(net); ++m) out.crossings.push_back({t, rep->triangle, dir});
      }
    }
    i = e;
  }
  std::stable_sort(out.touches.begin(), out.touches.end(), [](const Touch& a, const Touch& b) {
    return a.t != b.t ? a.t < b.t : a.triangle < b.triangle;
  });
  return out;
}

void ClosedMesh::crossings(std::span<const Ray<double>> rays, std::span<RayCrossings> out, TRange range,
                           int threads) const {
  if (rays.size() != out.size())
    throw MeshInputError("ClosedMesh::crossings: " + std::to_string(out.size()) + " results for " +
                         std::to_string(rays.size()) + " rays");
  auto body = [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) out[i] = crossings(rays[i], range);
  };
  if (threads == 1 || rays.size() < 256) return body(tbb::blocked_range<std::size_t>(0, rays.size()));
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 64), body); });
}

}  // namespace rayproof
