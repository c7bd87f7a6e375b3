/// Triangle pair families (tritri_families.h). The constructed ones work on the integer lattice of
/// build.h: every contact (a shared edge, a vertex on a face, an edge through an edge, a sub-edge
/// shared in a plane) is an integer point, so its class holds exactly; place() then applies an
/// axis permutation with sign flips, an integer offset and a scale 2^e, each exact in double.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include "gen/tritri_families.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <utility>

#include "gen/build.h"
#include "gen/rng.h"

namespace rayproof::gen {

namespace {

using detail::add;
using detail::cross;
using detail::dot;
using detail::I3;
using detail::i64;
using detail::mul;
using detail::rand_ivec;
using detail::sub;
using LTri = std::array<I3, 3>;

struct LPair {
  LPair() = default;
  LPair(const LTri& a_, const LTri& b_, std::optional<TriTri> e, std::optional<bool> m = std::nullopt)
      : a(a_), b(b_), expected(e), expected_meets(m) {}
  LTri a{}, b{};
  std::optional<TriTri> expected;
  std::optional<bool> expected_meets;
};

bool flat(const LTri& t) { return detail::collinear(t[0], t[1], t[2]); }
/// The four points are coplanar (exact in 128 bits: components below 2^40).
bool coplanar4(I3 a, I3 b, I3 c, I3 d) { return dot(cross(sub(b, a), sub(c, a)), sub(d, a)) == 0; }
LTri scaled(const LTri& t, i64 k) { return {mul(t[0], k), mul(t[1], k), mul(t[2], k)}; }

/// A point of the plane z = alpha x + beta y + gamma (alpha, beta, gamma in `pl`).
I3 on_plane(Rng& r, const std::array<i64, 3>& pl, int bits) {
  const i64 x = r.sym_int(bits), y = r.sym_int(bits);
  return {x, y, pl[0] * x + pl[1] * y + pl[2]};
}
std::array<i64, 3> rand_plane(Rng& r) {
  const i64 al = r.range(-4, 4), be = r.range(-4, 4), ga = r.sym_int(16);
  return {al, be, ga};
}
LTri plane_triangle(Rng& r, const std::array<i64, 3>& pl, int bits) {
  for (;;) {
    const LTri t{on_plane(r, pl, bits), on_plane(r, pl, bits), on_plane(r, pl, bits)};
    if (!flat(t)) return t;
  }
}
LTri rand_triangle(Rng& r, int bits) {
  for (;;) {
    const LTri t{rand_ivec(r, bits), rand_ivec(r, bits), rand_ivec(r, bits)};
    if (!flat(t)) return t;
  }
}
/// A triangle (A, B, C) in z = 0 with A, B on the x axis (xa < xb) and C above it (y > 0).
LTri base_triangle(Rng& r, int bits) {
  const i64 xa = -r.range(1, i64{1} << bits), xb = r.range(1, i64{1} << bits);
  return {I3{xa, 0, 0}, I3{xb, 0, 0}, I3{r.sym_int(bits), r.range(1, i64{1} << bits), 0}};
}

struct Placed {
  TriPair pair;
  int z_axis = 2;  ///< the output axis that the lattice's z axis went to
};

/// Axis permutation with sign flips, an integer offset (two times in three), scale 2^e; vertex
/// order shuffled in each triangle, the two triangles swapped half the time.
Placed place(Rng& r, LPair lp, int e) {
  std::array<int, 3> perm{0, 1, 2};
  for (std::size_t i = 2; i > 0; --i) std::swap(perm[i], perm[r.below(i + 1)]);
  const std::array<int, 3> sign{r.sign(), r.sign(), r.sign()};
  const I3 off = r.chance(2, 3) ? rand_ivec(r, 20) : I3{0, 0, 0};
  for (LTri* t : {&lp.a, &lp.b})
    for (std::size_t i = 2; i > 0; --i) std::swap((*t)[i], (*t)[r.below(i + 1)]);
  if (r.coin()) std::swap(lp.a, lp.b);
  auto out = [&](const I3& v) {
    Vec3<double> o;
    for (int i = 0; i < 3; ++i) o[i] = std::ldexp(static_cast<double>(sign[i] * (v[perm[i]] + off[perm[i]])), e);
    return o;
  };
  Placed p;
  p.pair = {{out(lp.a[0]), out(lp.a[1]), out(lp.a[2])}, {out(lp.b[0]), out(lp.b[1]), out(lp.b[2])}, lp.expected,
            lp.expected_meets};
  if (!p.pair.expected_meets && p.pair.expected && *p.pair.expected != TriTri::degenerate)
    p.pair.expected_meets = meets(*p.pair.expected);
  for (int i = 0; i < 3; ++i)
    if (perm[i] == 2) p.z_axis = i;
  return p;
}

// ---- constructions on the lattice (coordinates below 2^26) ----

LPair far_apart(Rng& r) {
  LTri b = rand_triangle(r, 20);
  for (I3& v : b) v[0] += i64{1} << 22;  // a within |x| <= 2^20, b beyond 2^22 - 2^20
  return {rand_triangle(r, 20), b, TriTri::disjoint};
}

/// b's plane cuts a's interior square |x|, |y| <= 2^19 along a chord of positive length.
LPair clear_crossing(Rng& r) {
  const i64 h = i64{1} << 21;
  const LTri a{I3{-h, -h, 0}, I3{h, -h, 0}, I3{0, h, 0}};
  for (;;) {
    const LTri b{I3{r.sym_int(19), r.sym_int(19), r.range(1024, i64{1} << 20)},
                 I3{r.sym_int(19), r.sym_int(19), -r.range(1024, i64{1} << 20)},
                 I3{r.sym_int(19), r.sym_int(19), -r.range(1024, i64{1} << 20)}};
    if (!flat(b)) return {a, b, TriTri::crossing};
  }
}

LPair shared_edge(Rng& r) {
  for (;;) {
    const I3 u = rand_ivec(r, 20), v = rand_ivec(r, 20), w = rand_ivec(r, 20), x = rand_ivec(r, 20);
    const LTri a{u, v, w}, b{v, u, x};
    if (!flat(a) && !flat(b) && !coplanar4(u, v, w, x)) return {a, b, TriTri::touching};
  }
}

/// a below the plane z = u.z except at u, b above it except at u.
LPair shared_vertex(Rng& r) {
  for (;;) {
    const I3 u = rand_ivec(r, 20);
    auto off = [&](int side) { return add(u, I3{r.sym_int(20), r.sym_int(20), side * r.range(1, i64{1} << 20)}); };
    const LTri a{u, off(-1), off(-1)}, b{u, off(1), off(1)};
    if (!flat(a) && !flat(b)) return {a, b, TriTri::touching};
  }
}

LPair coplanar_random(Rng& r) {
  const auto pl = rand_plane(r);
  return {plane_triangle(r, pl, 16), plane_triangle(r, pl, 16), std::nullopt};
}

/// b shares a piece [P', Q'] of a's edge PQ from the other side (S = P' + Q' - R), or only the
/// vertex Q (b is a's point reflection through Q).
LPair coplanar_touching(Rng& r) {
  const auto pl = rand_plane(r);
  const LTri a = scaled(plane_triangle(r, pl, 16), 8);
  const I3 P = a[0], Q = a[1], R = a[2];
  if (r.chance(1, 4)) return {a, {Q, sub(mul(Q, 2), R), sub(mul(Q, 2), P)}, TriTri::coplanar_touching};
  const i64 i = r.range(0, 7), j = r.range(i + 1, 8);
  const I3 step = I3{(Q[0] - P[0]) / 8, (Q[1] - P[1]) / 8, (Q[2] - P[2]) / 8};
  const I3 P1 = add(P, mul(step, i)), Q1 = add(P, mul(step, j));
  return {a, {P1, Q1, sub(add(P1, Q1), R)}, TriTri::coplanar_touching};
}

/// b inside a: (P, (P+Q)/2, (P+R)/2) or the midpoint triangle.
LPair coplanar_overlap(Rng& r) {
  const auto pl = rand_plane(r);
  const LTri a = plane_triangle(r, pl, 16), a2 = scaled(a, 2);
  const I3 P = a[0], Q = a[1], R = a[2];
  if (r.coin()) return {a2, {mul(P, 2), add(P, Q), add(P, R)}, TriTri::coplanar_overlap};
  return {a2, {add(P, Q), add(Q, R), add(R, P)}, TriTri::coplanar_overlap};
}

/// b is a moved along the plane by 2^18 in x (a within |x| <= 2^16).
LPair coplanar_disjoint(Rng& r) {
  const auto pl = rand_plane(r);
  const LTri a = plane_triangle(r, pl, 16), b = plane_triangle(r, pl, 16);
  const i64 dx = (i64{1} << 18) * r.sign();
  const I3 shift{dx, 0, pl[0] * dx};
  return {a, {add(b[0], shift), add(b[1], shift), add(b[2], shift)}, TriTri::disjoint};
}

/// An edge of b through a point m inside a's edge AB (a in z = 0, AB on the x axis); b's plane
/// meets z = 0 on m -> q2, with q2 below the x axis (touching: only m is shared) or inside a
/// (crossing: the chord runs through both interiors).
LPair edge_through_edge(Rng& r) {
  const LTri a = scaled(base_triangle(r, 18), 4);
  const i64 xa = a[0][0], xb = a[1][0];
  const I3 m{r.range(xa + 1, xb - 1), 0, 0};
  I3 v = rand_ivec(r, 18);
  if (v[2] == 0) v[2] = 1;
  const bool crossing = r.coin();
  const I3 q2 = crossing ? I3{(a[0][0] + a[1][0] + 2 * a[2][0]) / 4, (a[0][1] + a[1][1] + 2 * a[2][1]) / 4, 0}
                         : I3{m[0] + r.sym_int(18), -r.range(1, i64{1} << 18), 0};
  return {a, {sub(m, v), add(m, v), q2}, crossing ? TriTri::crossing : TriTri::touching};
}

/// A vertex of b exactly on a (inside, on an edge, or on a vertex), the rest of b above a's plane.
LPair vertex_on_face(Rng& r) {
  const LTri a = scaled(base_triangle(r, 18), 4);
  const int where = r.irange(0, 2);
  const I3 q0 = where == 0 ? I3{(a[0][0] + a[1][0] + 2 * a[2][0]) / 4, (a[0][1] + a[1][1] + 2 * a[2][1]) / 4, 0}
                : where == 1 ? I3{(a[1][0] + a[2][0]) / 2, (a[1][1] + a[2][1]) / 2, 0}
                             : a[2];
  for (;;) {
    const LTri b{q0, add(q0, I3{r.sym_int(20), r.sym_int(20), r.range(1, i64{1} << 20)}),
                 add(q0, I3{r.sym_int(20), r.sym_int(20), r.range(1, i64{1} << 20)})};
    if (!flat(b)) return {a, b, TriTri::touching};
  }
}

LPair degenerate(Rng& r) {
  const I3 P = rand_ivec(r, 20), Q = rand_ivec(r, 20);
  LTri a;
  switch (r.irange(0, 2)) {
    case 0: a = {P, Q, add(P, mul(sub(Q, P), r.range(-2, 3)))}; break;  // collinear (maybe coincident)
    case 1: a = {P, P, Q}; break;
    default: a = {P, P, P}; break;
  }
  return {a, rand_triangle(r, 20), TriTri::degenerate};
}

/// A zero-area triangle built against a triangle b in z = 0: a point inside b, a segment through
/// b's interior, a segment in b's plane across b's edge, a segment from b's vertex away from it,
/// two segments through one point; or apart: a segment crossing b's plane one lattice step outside
/// b, two segments in one plane whose lines cross beyond one's end.
LPair degenerate_contact(Rng& r) {
  const LTri b = scaled(base_triangle(r, 18), 8);
  const I3 q{(b[0][0] + b[1][0] + 2 * b[2][0]) / 4, (b[0][1] + b[1][1] + 2 * b[2][1]) / 4, 0};  // inside b
  I3 v = rand_ivec(r, 16);
  if (v[2] == 0) v[2] = 1;
  switch (r.irange(0, 6)) {
    case 0: return {{q, q, q}, b, TriTri::degenerate, true};
    case 1: return {{sub(q, v), add(q, v), q}, b, TriTri::degenerate, true};
    case 2: {
      const I3 out{q[0] + 2 * r.sym_int(16), -r.range(2, i64{1} << 16) * 2, 0};  // below the x axis: outside b
      return {{q, out, I3{(q[0] + out[0]) / 2, (q[1] + out[1]) / 2, 0}}, b, TriTri::degenerate, true};
    }
    case 3: {
      const I3 w{r.sym_int(16), r.sym_int(16), r.range(1, i64{1} << 16)};  // upwards from b's vertex
      return {{b[2], add(b[2], w), add(b[2], mul(w, 2))}, b, TriTri::degenerate, true};
    }
    case 4: {
      I3 w = rand_ivec(r, 16);
      if (detail::collinear(I3{0, 0, 0}, v, w)) w = add(w, I3{1, 0, 0});
      return {{sub(q, v), add(q, v), q}, {sub(q, w), add(q, w), add(q, mul(w, 2))}, TriTri::degenerate, true};
    }
    case 5: {  // in one plane, b's line crosses a's line beyond a's end: apart
      I3 w = rand_ivec(r, 16);
      if (detail::collinear(I3{0, 0, 0}, v, w)) w = add(w, I3{1, 0, 0});
      const I3 c = add(q, mul(v, 3));
      return {{sub(q, v), add(q, v), q}, {sub(c, w), add(c, w), c}, TriTri::degenerate, false};
    }
    default: {
      const I3 miss{q[0], -1, 0};  // one step below b's edge on the x axis
      return {{sub(miss, v), add(miss, v), miss}, b, TriTri::degenerate, false};
    }
  }
}

// ---- families ----

Vec3<double> sym3(Rng& r) {
  const double x = r.sym(), y = r.sym(), z = r.sym();
  return {x, y, z};
}

TriPair random_pair(Rng& r) { return {{sym3(r), sym3(r), sym3(r)}, {sym3(r), sym3(r), sym3(r)}, std::nullopt, std::nullopt}; }

/// A thin triangle (P, Q, (P + Q)/2 + 2^-k w), k in [20, 50], and a triangle around its middle.
TriPair sliver(Rng& r) {
  const Vec3<double> P = sym3(r), Q = sym3(r), w = sym3(r);
  const double eps = r.pow2(-50, -20);
  const Vec3<double> M = 0.5 * (P + Q);
  const Vec3<double> C = M + eps * w;
  const Vec3<double> d0 = sym3(r), d1 = sym3(r), d2 = sym3(r);
  return {{P, Q, C}, {M + d0, M + d1, M + d2}, std::nullopt, std::nullopt};
}

int std_scale(Rng& r) { return r.irange(-30, 8); }

/// x moved k ulps away from zero (the bit pattern's magnitude plus k; from 0: k * 2^-1074).
double lift(double x, int k) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  return std::bit_cast<double>(bits + static_cast<std::uint64_t>(k));
}

TriPair near_coplanar_from(Rng& r, int k) {
  LPair lp;
  switch (r.irange(0, 3)) {
    case 0: lp = coplanar_touching(r); break;
    case 1: lp = coplanar_overlap(r); break;
    case 2: lp = coplanar_disjoint(r); break;
    default: lp = coplanar_random(r); break;
  }
  Placed p = place(r, lp, std_scale(r));
  if (k > 0) {
    Vec3<double>& v = r.coin() ? p.pair.b.p2 : p.pair.b.p0;
    v[p.z_axis] = lift(v[p.z_axis], k);
    p.pair.expected = std::nullopt;
    p.pair.expected_meets = std::nullopt;
  }
  return p.pair;
}

TriPair extreme(Rng& r) {
  LPair lp;
  switch (r.irange(0, 8)) {
    case 7: lp = far_apart(r); break;
    case 8: lp = coplanar_disjoint(r); break;
    case 0: lp = clear_crossing(r); break;
    case 1: lp = shared_edge(r); break;
    case 2: lp = shared_vertex(r); break;
    case 3: lp = edge_through_edge(r); break;
    case 4: lp = vertex_on_face(r); break;
    case 5: lp = coplanar_touching(r); break;
    default: lp = coplanar_overlap(r); break;
  }
  const int e = r.coin() ? r.irange(595, 605) : r.irange(-630, -600);
  return place(r, lp, e).pair;
}

using LFn = LPair (*)(Rng&);
using DFn = TriPair (*)(Rng&);

struct Entry {
  TriTriFamily family;
  LFn lattice = nullptr;  ///< constructed on the lattice, then placed
  DFn direct = nullptr;   ///< drawn in doubles
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {{"random", "six vertices uniform in [-1, 1]^3 (53-bit coordinates): mostly disjoint, some crossing"},
       nullptr, random_pair},
      {{"far_apart", "triangles in separate boxes: disjoint by the planes or the intervals"}, far_apart, nullptr},
      {{"crossing", "a plane through the middle of the other triangle: crossing well inside both"}, clear_crossing,
       nullptr},
      {{"shared_edge", "two triangles of a mesh sharing an edge, not coplanar: touching along it"}, shared_edge,
       nullptr},
      {{"shared_vertex", "one common vertex, the rest on opposite sides of a plane: touching at it"}, shared_vertex,
       nullptr},
      {{"coplanar", "random triangles in one plane z = ax + by + c: overlapping, touching or apart"},
       coplanar_random, nullptr},
      {{"coplanar_touching", "in one plane, sharing a piece of an edge or one vertex exactly"}, coplanar_touching,
       nullptr},
      {{"coplanar_overlap", "in one plane, one inside the other (a corner or the midpoint triangle)"},
       coplanar_overlap, nullptr},
      {{"coplanar_disjoint", "in one plane, apart"}, coplanar_disjoint, nullptr},
      {{"near_coplanar", "a coplanar pair with one vertex lifted by k ulps off the plane (k = 4^(i mod 11))"},
       nullptr, nullptr},
      {{"edge_through_edge", "an edge exactly through a point of the other's edge: touching there, or crossing"},
       edge_through_edge, nullptr},
      {{"vertex_on_face", "a vertex exactly inside the other, on its edge or on its vertex, the rest above"},
       vertex_on_face, nullptr},
      {{"sliver", "a thin triangle (height 2^-20 .. 2^-50 of its length) and one across its middle"}, nullptr,
       sliver},
      {{"extreme", "exact contacts and separations scaled by 2^600 or 2^-600 (beyond the expansions' window)"}, nullptr, extreme},
      {{"degenerate", "a zero-area triangle (collinear or coincident vertices) against a triangle"}, degenerate,
       nullptr},
      {{"degenerate_contact", "a zero-area triangle built to meet the other (a point on it, a segment through it) or to miss it by one step"},
       degenerate_contact, nullptr},
  };
  return e;
}

}  // namespace

const std::vector<TriTriFamily>& tritri_families() {
  static const std::vector<TriTriFamily> f = [] {
    std::vector<TriTriFamily> v;
    for (const Entry& e : entries()) v.push_back(e.family);
    return v;
  }();
  return f;
}

const TriTriFamily* find_tritri_family(std::string_view name) {
  for (const TriTriFamily& f : tritri_families())
    if (f.name == name) return &f;
  return nullptr;
}

TriPair near_coplanar_pair(std::uint64_t seed, std::size_t index, int k_ulps) {
  Rng r = Rng::for_family(seed ^ (0x9e3779b97f4a7c15ULL * (index + 1)), "near_coplanar");
  return near_coplanar_from(r, k_ulps);
}

void generate_tritri_each(const TriTriFamily& f, std::size_t count, std::uint64_t seed,
                          const std::function<void(const TriPair&)>& sink) {
  const Entry* entry = nullptr;
  for (const Entry& e : entries())
    if (e.family.name == f.name) entry = &e;
  if (!entry) return;
  Rng r = Rng::for_family(seed, f.name);
  for (std::size_t i = 0; i < count; ++i) {
    if (entry->lattice) sink(place(r, entry->lattice(r), std_scale(r)).pair);
    else if (entry->direct) sink(entry->direct(r));
    else sink(near_coplanar_pair(seed, i, 1 << (2 * (i % 11))));
  }
}

std::vector<TriPair> generate_tritri(const TriTriFamily& f, std::size_t count, std::uint64_t seed) {
  std::vector<TriPair> out;
  out.reserve(count);
  generate_tritri_each(f, count, seed, [&](const TriPair& p) { out.push_back(p); });
  return out;
}

}  // namespace rayproof::gen
