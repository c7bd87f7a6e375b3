// ExactMesh::ray_crossings: every point where a ray passes through the surface, once, with its
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
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <atomic>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "exact/rational_vec.h"
#include "exact/rounding.h"
#include "rayproof/certified/intersect.h"
#include "rayproof/certified_expansion.h"
#include "scene/batch_threads.h"
#include "scene/exact_mesh_state.h"
#include "scene/crossings_exact_sign.h"
#include "scene/crossings_speedups.h"
#include "scene/leaf_simd.h"

namespace rayproof {

const char* to_string(CrossingDirection d) { return d == CrossingDirection::in ? "in" : "out"; }

namespace {

int sgn(const mpq_class& x) {
  const int s = mpq_sgn(x.get_mpq_t());
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

using exact_algo::QVec;
using exact_algo::rational;

/// The exact t = ((p0 - o) . n) / (d . n) (d . n != 0).
mpq_class exact_t(const Ray<double>& r, const std::array<Vec3<double>, 3>& p) {
  const QVec p0 = rational(p[0]);
  const QVec n = cross(rational(p[1]) - p0, rational(p[2]) - p0);
  return mpq_class(dot(p0 - rational(r.o), n) / dot(rational(r.d), n));
}

/// x rounded to the nearest double (ties to even), by the one correct rounding (src/exact/rounding.h).
double round_nearest(const mpq_class& x) { return exact_algo::round_nearest(x.get_mpq_t()); }

/// Sign of d . n, n = (p1 - p0) x (p2 - p0): in double when the error bound allows (every rounding
/// counted: gamma_7 of the permanent, well inside 2^-49 of it), else in GMP.
int sign_dn(const Vec3<double>& d, const std::array<Vec3<double>, 3>& p) {
  const Vec3<double> e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double dn = d.x * (e1.y * e2.z - e1.z * e2.y) + d.y * (e1.z * e2.x - e1.x * e2.z) + d.z * (e1.x * e2.y - e1.y * e2.x);
  const double perm = std::fabs(d.x) * (std::fabs(e1.y * e2.z) + std::fabs(e1.z * e2.y)) +
                      std::fabs(d.y) * (std::fabs(e1.z * e2.x) + std::fabs(e1.x * e2.z)) +
                      std::fabs(d.z) * (std::fabs(e1.x * e2.y) + std::fabs(e1.y * e2.x));
  if (perm > 0x1p-900 && perm < 0x1p1000 && std::fabs(dn) > 0x1p-49 * perm) return dn > 0 ? 1 : -1;
  const QVec q0 = rational(p[0]);
  return sgn(dot(rational(d), cross(rational(p[1]) - q0, rational(p[2]) - q0)));
}

/// Where an edge or vertex contact is: the vertex, or the edge's two ends in coordinate order
/// (contacts at the same vertex or on the same edge, as coordinates, are at the same point).
struct Where {
  int kind = 0;  ///< 0 unknown (interior), 1 edge, 2 vertex
  Vec3<double> a{0, 0, 0}, b{0, 0, 0};
  bool operator==(const Where&) const = default;
};
bool less_xyz(const Vec3<double>& p, const Vec3<double>& q) {
  return p.x != q.x ? p.x < q.x : (p.y != q.y ? p.y < q.y : p.z < q.z);
}

/// An edge or vertex contact: d . n's sign, whether the perturbed ray crosses the triangle, and
/// where the contact is.
struct Decided {
  int sdn = 0;
  bool crossed = false;
  bool met = false;  ///< no edge function of the sign opposite to d . n: the closed triangle is met
  Where where;
};

/// What one ray has proven about the points it passes exactly through, so that a vertex's or an
/// edge's fan is decided once per contact instead of once per triangle: vertices on the ray's line
/// (every edge from one has edge function exactly 0: a - o is a multiple of d), and edges whose edge
/// function is exactly 0, keyed by their ends in coordinate order, with the sign of the
/// perturbation's first nonzero coefficient for that order and, once a triangle found it, the
/// contact's t (the same exact point, so the same exact t for every triangle on the edge). Only the
/// last kRecent entries are searched: the fan's triangles are near in the BVH's leaf order, and a
/// ray along a line of many vertices does not make each lookup longer (a miss only recomputes).
struct Known {
  static constexpr std::size_t kRecent = 16;
  struct Edge {
    Vec3<double> a, b;
    int g = 0;
    Contact contact = Contact::miss;  ///< edge or behind once a triangle met there found its t
    double t = kNaN<double>;
  };
  std::vector<Vec3<double>> vertices;
  std::vector<Edge> edges;
  bool on = true;  ///< off (the ablation): nothing remembered, every triangle decided alone
  void clear() { vertices.clear(), edges.clear(); }
  [[nodiscard]] bool on_line(const Vec3<double>& v) const {
    if (!on) return false;
    for (std::size_t i = vertices.size(), e = i > kRecent ? i - kRecent : 0; i-- > e;)
      if (vertices[i] == v) return true;
    return false;
  }
  /// The entry of edge {a, b} (in coordinate order), or null.
  [[nodiscard]] Edge* edge(const Vec3<double>& a, const Vec3<double>& b) {
    if (!on) return nullptr;
    for (std::size_t i = edges.size(), e = i > kRecent ? i - kRecent : 0; i-- > e;)
      if (edges[i].a == a && edges[i].b == b) return &edges[i];
    return nullptr;
  }
};

/// From the exact signs of u_i (the edge function of edge (p_{i+1}, p_{i+2}); their sum is d . n)
/// and, where u_i = 0, of the perturbation's coefficients g_i = (p_{i+1} - p_{i+2}) x d.
Decided finish(const std::array<Vec3<double>, 3>& p, const int (&s)[3], const int (&gs)[3], int sdn) {
  Decided out;
  out.sdn = sdn;
  int zeros = 0;
  bool crossed = sdn != 0;
  for (int i = 0; i < 3; ++i) {
    zeros += s[i] == 0;
    crossed = crossed && (s[i] ? s[i] : gs[i]) == sdn;
  }
  out.crossed = crossed;
  out.met = sdn != 0 && s[0] != -sdn && s[1] != -sdn && s[2] != -sdn;
  if (zeros == 1) {
    const int i = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);
    Vec3<double> a = p[(i + 1) % 3], b = p[(i + 2) % 3];
    if (less_xyz(b, a)) std::swap(a, b);
    out.where = {1, a, b};
  } else if (zeros == 2) {
    const int m = 3 - (s[0] == 0 ? 0 : 1) - (s[2] == 0 ? 2 : 1);  // the vertex on both zero edges
    out.where = {2, p[m], p[m]};
  }
  return out;
}

/// The first nonzero sign of (x, y, z).
template <class F>
int first_sign(F&& sign_of) {
  for (int k = 0; k < 3; ++k)
    if (const int v = sign_of(k)) return v;
  return 0;
}

Decided decide_gmp(const Ray<double>& r, const std::array<Vec3<double>, 3>& p) {
  const QVec o = rational(r.o), d = rational(r.d);
  const QVec P[3] = {rational(p[0]), rational(p[1]), rational(p[2])};
  const QVec A[3] = {P[0] - o, P[1] - o, P[2] - o};
  int s[3], gs[3] = {0, 0, 0};
  mpq_class den = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const mpq_class u = dot(d, cross(A[j], A[k]));
    den += u;
    s[i] = sgn(u);
    if (s[i] == 0) {
      const QVec g = cross(P[j] - P[k], d);  // the perturbation's coefficients: eps, eps^2, eps^3
      gs[i] = first_sign([&](int c) { return sgn(c == 0 ? g.x : (c == 1 ? g.y : g.z)); });
    }
  }
  return finish(p, s, gs, sgn(den));
}

double norm_inf(const Vec3<double>& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// The same with a double filter first: u = (d x B) . C with B = a - o, C = b - o rounded, and the
/// bound of the certified filter's first stage for that expression (certified_triangle.h:
/// 2^-49 |d|_1 |B|_inf |C|_inf plus 2^-1000 (|C|_inf + 1) for underflow); g_c with the bound
/// 2^-49 (|e_j d_k| + |e_k d_j|) + 2^-1000 (e = a - b rounded: gamma_3 of the permanent, with room).
/// What a bound leaves undecided (mostly the exact zeros of an edge or vertex contact) goes to the
/// expansions, exact for inputs in the exponent window of a degree-3 polynomial; outside it, GMP.
Decided decide_perturbed(const Ray<double>& r, const std::array<Vec3<double>, 3>& p, Known& known) {
  using certified::ExpVec3;
  const Vec3<double>&o = r.o, &d = r.d, &p0 = p[0], &p1 = p[1], &p2 = p[2];
  if (!certified::in_range<-200, 200>(o.x, o.y, o.z, d.x, d.y, d.z, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y,
                                      p2.z))
    return decide_gmp(r, p);
  const double d1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  const bool filter = d1 >= 0x1p-960;
  int s[3], gs[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Vec3<double> B = p[j] - o, C = p[k] - o;
    const double u = dot(cross(d, B), C);
    const double mc = norm_inf(C), eu = 0x1p-49 * d1 * norm_inf(B) * mc + 0x1p-1000 * (mc + 1);
    if (filter && eu < 0x1p1000 && std::fabs(u) > eu) {
      s[i] = u > 0 ? 1 : -1;
      continue;
    }
    // An edge this ray already proved: u = 0 and g's sign known (negated for the other order).
    const bool ordered = !less_xyz(p[k], p[j]);
    const Vec3<double>&ea = ordered ? p[j] : p[k], &eb = ordered ? p[k] : p[j];
    if (const Known::Edge* ke = known.edge(ea, eb)) {
      s[i] = 0, gs[i] = ordered ? ke->g : -ke->g;
      continue;
    }
    if (known.on_line(p[j]) || known.on_line(p[k])) {
      s[i] = 0;
    } else if (const int small = scene::detail::u_sign_exact_small(d, o, p[j], p[k]); small != 2) {
      s[i] = small;
    } else {
      const certified::Expansion ux =
          dot(certified::exact3(d), cross(certified::diff3(p[j], o), certified::diff3(p[k], o)));
      if (ux.bad) return decide_gmp(r, p);
      s[i] = ux.sign();
    }
    if (s[i] != 0) continue;
    const Vec3<double> e = p[j] - p[k], gv = cross(e, d);
    const double eg[3] = {0x1p-49 * (std::fabs(e.y * d.z) + std::fabs(e.z * d.y)) + 0x1p-1000,
                          0x1p-49 * (std::fabs(e.z * d.x) + std::fabs(e.x * d.z)) + 0x1p-1000,
                          0x1p-49 * (std::fabs(e.x * d.y) + std::fabs(e.y * d.x)) + 0x1p-1000};
    const double gd[3] = {gv.x, gv.y, gv.z};
    // g_c = e_a d_b - e_b d_a is exactly 0 when both of its d components are (an axis ray).
    const double D[3] = {d.x, d.y, d.z};
    bool done = false;
    for (int c = 0; c < 3 && !done; ++c) {
      if (D[(c + 1) % 3] == 0 && D[(c + 2) % 3] == 0) continue;
      if (std::fabs(gd[c]) > eg[c] && eg[c] < 0x1p1000) {
        gs[i] = gd[c] > 0 ? 1 : -1;
        done = true;
      } else {
        const ExpVec3 g = cross(certified::diff3(p[j], p[k]), certified::exact3(d));
        if (certified::any_bad(g)) return decide_gmp(r, p);
        const int v = (c == 0 ? g.x : (c == 1 ? g.y : g.z)).sign();
        if (v) gs[i] = v, done = true;  // else this component is exactly 0: the next one decides
      }
    }
    if (known.on) known.edges.push_back({ea, eb, ordered ? gs[i] : -gs[i]});
  }
  const Decided out = finish(p, s, gs, sign_dn(d, p));
  // Two edge functions 0 and d . n != 0: the ray's line holds their common vertex (else it would
  // lie in the plane of the vertex and both edges, the triangle's).
  if (known.on && out.where.kind == 2 && out.sdn != 0 && !known.on_line(out.where.a)) known.vertices.push_back(out.where.a);
  return out;
}

/// The certified filter's answer for one triangle, and for a vertex contact the perturbed decision
/// made on the way. Where the filter's first stage cannot decide, a contact at a vertex (two edge
/// functions exactly 0, decided as above) gets its t from the vertex itself: the ray passes exactly
/// through v, so t = (v_c - o_c) / d_c on the axis c of the largest |d_c|, evaluated as q + (r +
/// lo) / d_c with v_c - o_c = hi + lo exactly (two_sum), q = hi / d_c rounded and r = hi - q d_c
/// exactly (fma): the correction is below an ulp of q and carries a relative error near 2^-52, so
/// t is within 0.5 ulp and a little, inside the filter's one ulp. Everything else (edges, parallel
/// and coplanar rays, degenerate triangles, t near underflow) goes to the filter's later stages.
struct Classified {
  Hit<double> h;
  bool decided = false;
  Decided dd;
};

/// What stage 1 could not decide (its `next`): the perturbed decision, and t from the vertex, the
/// edge already met, double-double or the filter's later stages. Kept out of line: stage 1 is
/// compiled with `flatten`, which would otherwise inline all of this (GMP included) into every
/// copy of it, for no speed (this path is rare) and most of this file's compile time.
[[gnu::noinline]] std::optional<Hit<double>> classify_undecided(const Ray<double>& ray, const std::array<Vec3<double>, 3>& p,
                                                                const Triangle<double>& tri, Known& known, Classified& out) {
  const Decided dd = decide_perturbed(ray, p, known);
  out.decided = true;
  out.dd = dd;
  if (dd.sdn != 0 && !dd.met) return Hit<double>{Contact::miss};
  if (dd.sdn != 0 && dd.where.kind == 2) {
    const double D[3] = {ray.d.x, ray.d.y, ray.d.z}, O[3] = {ray.o.x, ray.o.y, ray.o.z};
    const double V[3] = {dd.where.a.x, dd.where.a.y, dd.where.a.z};
    int c = 0;
    for (int k = 1; k < 3; ++k)
      if (std::fabs(D[k]) > std::fabs(D[c])) c = k;
    const TwoTerm<double> diff = two_sum(V[c], -O[c]);
    double t = 0;
    if (diff.hi != 0) {
      const double q = diff.hi / D[c];
      const double r = std::fma(-q, D[c], diff.hi);
      t = q + (r + diff.lo) / D[c];
      if (!(std::fabs(q) >= 0x1p-900 && std::fabs(q) <= 0x1p900 && std::fabs(D[c]) >= 0x1p-900)) t = kNaN<double>;
    }
    if (t == t) return Hit<double>{t < 0 ? Contact::behind : Contact::vertex, t};
  }
  // An edge contact: every triangle met on that edge is met at the same point, so the first one's
  // class (edge or behind) and t serve the others.
  Known::Edge* ke = dd.sdn != 0 && dd.where.kind == 1 ? known.edge(dd.where.a, dd.where.b) : nullptr;
  if (ke && ke->contact != Contact::miss) return Hit<double>{ke->contact, ke->t};
  std::optional<Hit<double>> h;
#if RAYPROOF_FMA_PATH != 0
  // The contact is decided (met, on one edge): only t is left, in double-double (pinned to one
  // ulp, or nothing when num is too near 0 to give its sign).
  if (dd.sdn != 0 && dd.where.kind == 1 && certified::dd::available())
    if (const std::optional<double> t = certified::dd::triangle_t(ray, tri))
      h = Hit<double>{*t < 0 ? Contact::behind : Contact::edge, *t};
#endif
  if (!h) h = certified::detail::triangle_rest(ray, tri);
  if (ke && h && (h->contact == Contact::edge || h->contact == Contact::behind)) ke->contact = h->contact, ke->t = h->t;
  return h;
}

Classified classify(const Ray<double>& ray, const std::array<Vec3<double>, 3>& p, Known& known) {
  Classified out;
  const Triangle<double> tri{p[0], p[1], p[2]};
  auto next = [&]() -> std::optional<Hit<double>> { return classify_undecided(ray, p, tri, known, out); };
  if (const auto f = certified::detail::triangle_fast(ray, tri, next)) {
    out.h = *f;
  } else {
    out.decided = false;
    const TriangleHit<double> x = certified::intersect(ray, tri);
    out.h = {x.contact, x.t, x.t2};
  }
  return out;
}

struct Candidate {
  double t;
  std::uint32_t triangle;
  std::uint32_t slot;
  Contact contact;
  int net;  ///< +1 crossed in, -1 crossed out, 0 not crossed by the perturbed ray
  Where where;
};

/// The next double above x (std::nextafter(x, inf) without the library call; NaN and +inf stay).
double next_up(double x) {
  if (!(x < std::numeric_limits<double>::infinity())) return x;
  if (x == 0) return std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::uint64_t>(x);
  return std::bit_cast<double>(x > 0 ? b + 1 : b - 1);
}
/// Two ulps above x (the rounded t of two contacts at the same exact t differ by at most that).
double two_ulps_up(double x) { return next_up(next_up(x)); }
double two_ulps_down(double x) { return -two_ulps_up(-x); }

}  // namespace

namespace {

/// Whether an exact t lies in [tmin, tmax] (either may be infinite).
bool exact_in_range(const mpq_class& t, TRange range) {
  return (!std::isfinite(range.tmin) || t >= mpq_class(range.tmin)) && (!std::isfinite(range.tmax) || t <= mpq_class(range.tmax));
}

/// Whether the exact t of a contact whose rounded t is `t` (within one ulp of it) lies in the range:
/// from t where two ulps decide, else exactly (`exact()` computes it: a ray starting on the surface).
template <class Exact>
bool contact_in_range(double t, TRange range, Exact&& exact) {
  if (t < two_ulps_down(range.tmin) || t > two_ulps_up(range.tmax)) return false;
  if (t >= two_ulps_up(range.tmin) && t <= two_ulps_down(range.tmax)) return true;
  return exact_in_range(exact(), range);
}

/// The contacts of one group [b, g) of `order` (indices into cand), at t (its exact t in the range):
/// a crossing (or, net 0, a touch).
void emit_group(const std::vector<Candidate>& cand, const std::size_t* order, std::size_t b, std::size_t g, double t,
                RayCrossings& out) {
  int net = 0;
  for (std::size_t k = b; k < g; ++k) net += cand[order[k]].net;
  // The reported triangle: the lowest-numbered one crossed in the net's direction, or (a touch)
  // the lowest-numbered one met.
  const Candidate* rep = nullptr;
  Contact worst = Contact::interior;
  for (std::size_t k = b; k < g; ++k) {
    const Candidate& c = cand[order[k]];
    if (c.contact == Contact::vertex || (c.contact == Contact::edge && worst == Contact::interior)) worst = c.contact;
    const bool fits = net == 0 || (net > 0 ? c.net > 0 : c.net < 0);
    if (fits && (!rep || c.triangle < rep->triangle)) rep = &c;
  }
  if (net == 0) {
    out.touches.push_back({t, t, rep->triangle, worst});
  } else {
    const CrossingDirection dir = net > 0 ? CrossingDirection::in : CrossingDirection::out;
    for (int m = 0; m < std::abs(net); ++m) out.crossings.push_back({t, rep->triangle, dir});
  }
}

/// The accel's tree (the one its queries use) traversed conservatively along [tmin, tmax]:
/// `leaf(first, count)` for each leaf the ray's segment may meet.
template <class LeafRange>
void traverse_leaves(const scene::Accel& a, const Ray<double>& ray, TRange range, LeafRange&& leaf) {
  auto run = [&](const auto& tree) {
    wide_traverse_leaves(tree, ray, range.tmin, range.tmax, BvhTraversal::conservative, BvhQuery::all, leaf);
  };
  const bool compressed = a.nodes() == BvhNodes::compressed;
  if (a.simd() == BvhSimd::avx2) return compressed ? run(a.bvh8q()) : run(a.bvh8());
  return compressed ? run(a.bvh4q()) : run(a.bvh());
}

/// A leaf callback with prefetch(first), which the traversal calls for each leaf child it puts on
/// its stack: the leaf's first group (four slots of triangles, 288 bytes) requested while the nearer children are visited (without it the leaves' first loads were most
/// of the leaf time: cache misses).
template <class F>
struct PrefetchingLeaf {
  F& f;
  const std::array<Vec3<double>, 3>* slots;
  const std::uint32_t* ids;
  bool operator()(std::uint32_t first, std::uint32_t count) { return f(first, count); }
  void prefetch(std::uint32_t first) const {
    const char* p = reinterpret_cast<const char*>(slots + first);
    for (int off = 0; off < 288; off += 64) _mm_prefetch(p + off, _MM_HINT_T0);
    _mm_prefetch(p + 287, _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(ids + first), _MM_HINT_T0);
  }
};

/// Per thread: the candidates of the current ray and the scratch of its runs (no allocation per ray
/// once grown).
struct Scratch {
  std::vector<Candidate> cand;
  std::vector<std::size_t> order;
  std::vector<mpq_class> exact;
  Known known;
};

}  // namespace

void ExactMesh::ray_crossings_into(const Ray<double>& ray, TRange range, RayCrossings& out) const {
  out.crossings.clear();
  out.touches.clear();
  out.valid = false;
  if (!ray.valid() || !(range.tmin <= range.tmax)) return;
  out.valid = true;
  const auto& s = *s_;
  if (s.triangles.empty()) return;
  thread_local Scratch scratch;
  std::vector<Candidate>& cand = scratch.cand;
  std::vector<std::size_t>& order = scratch.order;
  std::vector<mpq_class>& exact = scratch.exact;
  Known& known = scratch.known;
  const scene::detail::CrossingsSpeedups speedups = scene::detail::crossings_speedups();
  cand.clear();
  known.clear();
  known.on = speedups.fan_once;
  const std::uint32_t* ids = s.slot_ids.data();
  const std::array<Vec3<double>, 3>* slots = s.slots.data();
  // The traversal along the exact range (conservative: every triangle with a contact at an exact t
  // in it is visited; with tmin >= 0 on the float box test). Candidates are kept two ulps wider, so
  // that contacts at the same exact t near an end are grouped together; which groups count is
  // decided on their exact t.
  const double lo = two_ulps_down(range.tmin), hi = two_ulps_up(range.tmax);
  // Slot j of a leaf (never padding: that lies between leaves); its triangle number is read only
  // for a candidate, from slot_ids (prefetched with the leaf: read from the leaf records, a cache
  // miss each, it was a third of the leaf loop's time in perf on bunny00).
  auto slot = [&](std::uint32_t j) {
    const Classified cl = classify(ray, slots[j], known);
    const Hit<double>& h = cl.h;
    switch (h.contact) {
      case Contact::interior:
        if (h.t >= lo && h.t <= hi) cand.push_back({h.t, ids[j], j, h.contact, -sign_dn(ray.d, slots[j]), {}});
        break;
      case Contact::edge:
      case Contact::vertex:
        if (h.t >= lo && h.t <= hi) {
          const Decided dd = cl.decided ? cl.dd : decide_perturbed(ray, slots[j], known);
          cand.push_back({h.t, ids[j], j, h.contact, dd.crossed ? -dd.sdn : 0, dd.where});
        }
        break;
      case Contact::behind:  // t < 0: a contact when the range reaches behind the origin
        if (h.t >= lo && h.t <= hi) {
          const Decided dd = cl.decided ? cl.dd : decide_perturbed(ray, slots[j], known);
          const Contact c = dd.where.kind == 2 ? Contact::vertex : (dd.where.kind == 1 ? Contact::edge : Contact::interior);
          cand.push_back({h.t, ids[j], j, c, dd.crossed ? -dd.sdn : 0, dd.where});
        }
        break;
      case Contact::coplanar:
        if (h.t <= range.tmax && h.t2 >= range.tmin)  // NaN (no range on the triangle) fails both
          out.touches.push_back({std::max(h.t, range.tmin), std::min(h.t2, range.tmax), ids[j], Contact::coplanar});
        break;
      default:
        break;
    }
  };
  // Whole leaves (each starts on a multiple of kLanes: one group per four slots): stage 1's proven
  // misses in four double lanes first (the same decision as the scalar stage 1, scene/leaf_simd.h),
  // the other slots one by one.
  const bool lanes = speedups.lane_misses && scene::detail::leaf_simd() == scene::detail::LeafSimd::avx2;
  auto leaf = [&](std::uint32_t first, std::uint32_t count) {
    constexpr std::uint32_t L = scene::detail::kLanes;
    for (std::uint32_t g0 = first, end = first + count; g0 < end; g0 += L) {
      unsigned live = end - g0 >= L ? (1u << L) - 1 : (1u << (end - g0)) - 1;
      if (lanes) {
        alignas(32) double p[3][3][L];
        for (std::uint32_t i = 0; i < L; ++i)  // (slots past a leaf's end are padding or the next leaf's: in bounds)
          for (int v = 0; v < 3; ++v) {
            const Vec3<double>& x = slots[g0 + i][v];
            p[v][0][i] = x.x, p[v][1][i] = x.y, p[v][2][i] = x.z;
          }
        live &= ~scene::detail::certified_group_misses_avx2(ray, p, live);
      }
      for (; live; live &= live - 1) slot(g0 + std::uint32_t(__builtin_ctz(live)));
    }
    return false;
  };
  PrefetchingLeaf<decltype(leaf)> prefetching{leaf, slots, ids};
  traverse_leaves(*s.accel, ray, speedups.float_traversal ? range : TRange{lo, hi}, prefetching);
  std::sort(cand.begin(), cand.end(),
            [](const Candidate& a, const Candidate& b) { return a.t != b.t ? a.t < b.t : a.triangle < b.triangle; });
  // Runs whose rounded t chain within two ulps: one group when every member is at the same vertex
  // or on the same edge (as coordinates: the same point); else ordered and grouped by exact t.
  for (std::size_t i = 0; i < cand.size();) {
    std::size_t e = i + 1;
    while (e < cand.size() && cand[e].t <= two_ulps_up(cand[e - 1].t)) ++e;
    order.clear();
    for (std::size_t k = i; k < e; ++k) order.push_back(k);
    bool one_point = cand[i].where.kind != 0;
    for (std::size_t k = i + 1; k < e && one_point; ++k) one_point = cand[k].where == cand[i].where;
    if (e - i == 1 || one_point) {
      // One point: every member's t is within one ulp of its exact t; the least is taken (the runs
      // around are more than two ulps away, so the order stays), moved into the range when the
      // exact t is in it (then the range's end lies between t and the exact t).
      const double t = cand[i].t;
      if (contact_in_range(t, range, [&] { return exact_t(ray, slots[cand[i].slot]); }))
        emit_group(cand, order.data(), 0, e - i, std::clamp(t, range.tmin, range.tmax), out);
    } else {
      exact.clear();
      for (std::size_t k = i; k < e; ++k) exact.push_back(exact_t(ray, slots[cand[k].slot]));
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return exact[a - i] < exact[b - i]; });
      for (std::size_t b = 0; b < order.size();) {
        std::size_t g = b + 1;
        while (g < order.size() && exact[order[g] - i] == exact[order[b] - i]) ++g;
        // The exact t correctly rounded: monotone in the exact t, so the listed t never decrease
        // (and stay in the range when the exact t is in it).
        if (exact_in_range(exact[order[b] - i], range))
          emit_group(cand, order.data(), b, g, round_nearest(exact[order[b] - i]), out);
        b = g;
      }
    }
    i = e;
  }
  std::stable_sort(out.touches.begin(), out.touches.end(), [](const Touch& a, const Touch& b) {
    return a.t != b.t ? a.t < b.t : a.triangle < b.triangle;
  });
}

RayCrossings ExactMesh::ray_crossings(const Ray<double>& ray, TRange range) const {
  RayCrossings out;
  ray_crossings_into(ray, range, out);
  return out;
}

void ExactMesh::ray_crossings(std::span<const Ray<double>> rays, std::span<RayCrossings> out, TRange range,
                           int threads) const {
  if (rays.size() != out.size())
    throw MeshInputError("ExactMesh::ray_crossings: " + std::to_string(out.size()) + " results for " +
                         std::to_string(rays.size()) + " rays");
  scene::detail::for_each_batch_range(rays.size(), threads, 256, 64, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) ray_crossings_into(rays[i], range, out[i]);
  });
}

namespace scene::detail {
namespace {
std::atomic<unsigned> speedup_bits{3u};  // CrossingsSpeedups{}
}  // namespace
void set_crossings_speedups(const CrossingsSpeedups& s) {
  speedup_bits.store(unsigned(s.float_traversal) | unsigned(s.lane_misses) << 1 | unsigned(s.fan_once) << 2,
                     std::memory_order_relaxed);
}
CrossingsSpeedups crossings_speedups() {
  const unsigned b = speedup_bits.load(std::memory_order_relaxed);
  return {(b & 1) != 0, (b & 2) != 0, (b & 4) != 0};
}
}  // namespace scene::detail

}  // namespace rayproof
