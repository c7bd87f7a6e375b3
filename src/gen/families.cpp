/// The family table, seeding, and the lattice placement shared by every family (build.h).
// No FMA contraction anywhere in the generator (the build also passes -ffp-contract=off): the same
// seed must give the same bytes on every compiler and target. GCC in ISO mode does not contract.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include "gen/families.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include "gen/build.h"
#include "gen/gen_table.h"
#include "gen/tritri_families.h"

namespace rayproof::gen {

using namespace detail;

namespace {

using Table = GenTable<Family, CaseFn>;

using C = Contact;
using K = io::Kind;

const Table& table() {
  static const Table t = {
      // triangles
      {{"tri_generic", K::triangle, "random rays and triangles: ordinary hits and misses", {C::interior, C::edge, C::vertex, C::miss, C::behind}},
       tri_generic},
      {{"tri_interior_exact", K::triangle, "hits at exact dyadic barycentric points strictly inside", {C::interior}},
       tri_interior_exact},
      {{"tri_edge", K::triangle, "hits exactly on an edge (dyadic point of the edge): edge rules, watertightness", {C::edge}},
       tri_edge},
      {{"tri_vertex", K::triangle, "hits exactly on a vertex: two barycentrics exactly 0", {C::vertex}}, tri_vertex},
      {{"tri_offset_big", K::triangle, "exact interior/edge/vertex hits translated by offsets up to 2^40 times the triangle size: cancellation",
        {C::interior, C::edge, C::vertex, C::behind}},
       tri_offset_big},
      {{"tri_coplanar", K::triangle, "ray lying in the triangle's plane: through it, along an edge, from a vertex, or missing it", {C::coplanar}},
       tri_coplanar},
      {{"tri_parallel", K::triangle, "ray parallel to the plane, off it by as little as one lattice unit", {C::parallel}},
       tri_parallel},
      {{"tri_near_parallel", K::triangle, "direction tilted out of the plane by 2^-20..2^-50 relative: huge t, determinant near 0",
        {C::interior, C::edge, C::vertex, C::miss, C::behind}},
       tri_near_parallel},
      {{"tri_degenerate", K::triangle, "collinear and repeated vertices (zero-area triangles), rays through them", {C::degenerate}},
       tri_degenerate},
      {{"tri_sliver", K::triangle, "near-degenerate slivers, aspect ratio up to 1e8, never exactly collinear",
        {C::interior, C::edge, C::vertex, C::miss, C::behind}},
       tri_sliver},
      {{"tri_behind", K::triangle, "exact contacts at t < 0 through the interior, an edge or a vertex", {C::behind}},
       tri_behind},
      {{"tri_far_small", K::triangle, "tiny target far away: triangle size / distance down to 2^-30",
        {C::interior, C::edge, C::vertex, C::miss}},
       tri_far_small},
      {{"tri_extreme_scale", K::triangle, "exact hits and misses at magnitudes 1e+-30, near overflow and underflow, subnormal coordinates",
        {C::interior, C::edge, C::vertex, C::miss}},
       tri_extreme_scale},
      {{"tri_vertex_aimed_float", K::triangle, "direction = normalize(vertex - origin) in float: aimed at a vertex, up to rounding",
        {C::interior, C::edge, C::vertex, C::miss}},
       tri_vertex_aimed_float},
      // spheres and ellipsoids
      {{"sph_generic", K::sphere, "random spheres and rays aimed near them: hits and misses", {C::hit, C::miss}}, sph_generic},
      {{"sph_tangent_exact", K::sphere, "exact tangents: line at distance exactly r (Pythagorean quadruples)", {C::tangent}},
       sph_tangent_exact},
      {{"sph_on_surface", K::sphere, "origin exactly on the sphere, heading in, out or tangent", {C::hit, C::inside, C::tangent}},
       sph_on_surface},
      {{"sph_inside_behind", K::sphere, "origin inside the sphere, or the sphere entirely behind the origin", {C::inside, C::behind}},
       sph_inside_behind},
      {{"ell_generic", K::ellipsoid, "random axis-aligned ellipsoids and rays aimed near them", {C::hit, C::miss}}, ell_generic},
      {{"ell_tangent_exact", K::ellipsoid, "exact tangents to ellipsoids (scaled Pythagorean quadruples)", {C::tangent}},
       ell_tangent_exact},
      {{"ell_on_surface", K::ellipsoid, "origin exactly on the ellipsoid, heading in, out or tangent", {C::hit, C::inside, C::tangent}},
       ell_on_surface},
      {{"ell_stiff", K::ellipsoid, "axis ratios up to 2^40: badly scaled quadratic coefficients", {C::hit, C::miss}}, ell_stiff},
      // boxes
      {{"box_generic", K::box, "random boxes and rays aimed near them", {C::hit, C::miss, C::inside, C::behind, C::graze}}, box_generic},
      {{"box_graze", K::box, "rays touching exactly one corner or one edge point (entry = exit)", {C::graze}}, box_graze},
      {{"box_axis_parallel", K::box, "direction components +0 and -0, origins exactly on slab planes: 0 * inf, NaN slabs",
        {C::hit, C::miss, C::inside, C::behind, C::graze}},
       box_axis_parallel},
      {{"box_flat", K::box, "flat boxes (lo = hi on an axis): crossed at one point or travelled within",
        {C::hit, C::miss, C::inside, C::behind, C::graze}},
       box_flat},
      // planes and disks
      {{"plane_generic", K::plane, "random planes and rays", {C::hit, C::behind}}, plane_generic},
      {{"plane_exact", K::plane, "exact dyadic hits and behinds, origins on the plane, exact coplanar and parallel rays",
        {C::hit, C::behind, C::coplanar, C::parallel}},
       plane_exact},
      {{"plane_near_parallel", K::plane, "direction tilted out of the plane by 2^-20..2^-50 relative, parallel rays just off the plane",
        {C::hit, C::behind, C::parallel}},
       plane_near_parallel},
      {{"disk_generic", K::disk, "random disks and rays aimed near them", {C::hit, C::miss, C::behind}}, disk_generic},
      {{"disk_rim", K::disk, "hits exactly on the rim circle (Pythagorean triples and quadruples)", {C::rim}}, disk_rim},
      // every kind
      {{"invalid", K::triangle, "NaN, inf, zero direction, negative radius or semi-axis, inverted boxes, over every kind", {C::invalid}, true},
       invalid_mix},
      // triangle pairs (kind tritri): the pair families of tritri_families.h, named tritri_NAME, made
      // by generate_each below (no per-case function: near_coplanar's lift depends on the index)
      {{"tritri_random", K::tritri, "", {C::disjoint, C::crossing}}, nullptr},
      {{"tritri_far_apart", K::tritri, "", {C::disjoint}}, nullptr},
      {{"tritri_crossing", K::tritri, "", {C::crossing}}, nullptr},
      {{"tritri_shared_edge", K::tritri, "", {C::touching}}, nullptr},
      {{"tritri_shared_vertex", K::tritri, "", {C::touching}}, nullptr},
      {{"tritri_coplanar", K::tritri, "", {C::coplanar_overlap, C::coplanar_touching, C::disjoint}}, nullptr},
      {{"tritri_coplanar_touching", K::tritri, "", {C::coplanar_touching}}, nullptr},
      {{"tritri_coplanar_overlap", K::tritri, "", {C::coplanar_overlap}}, nullptr},
      {{"tritri_coplanar_disjoint", K::tritri, "", {C::disjoint}}, nullptr},
      {{"tritri_near_coplanar", K::tritri, "",  // in float the lift may round away: coplanar again
        {C::disjoint, C::crossing, C::touching, C::coplanar_overlap, C::coplanar_touching}}, nullptr},
      {{"tritri_edge_through_edge", K::tritri, "", {C::touching, C::crossing}}, nullptr},
      {{"tritri_vertex_on_face", K::tritri, "", {C::touching}}, nullptr},
      {{"tritri_sliver", K::tritri, "", {C::disjoint, C::crossing, C::touching, C::degenerate}}, nullptr},  // float: flat
      {{"tritri_extreme", K::tritri, "",  // in float 2^600 is inf (invalid), 2^-600 is 0 (degenerate)
        {C::crossing, C::touching, C::coplanar_touching, C::coplanar_overlap, C::disjoint, C::invalid, C::degenerate}},
       nullptr},
      {{"tritri_degenerate", K::tritri, "", {C::degenerate}}, nullptr},
      {{"tritri_degenerate_contact", K::tritri, "", {C::degenerate}}, nullptr},
  };
  return t;
}

constexpr std::string_view kPairPrefix = "tritri_";

/// The pair family behind a tritri_NAME family, or nullptr.
const TriTriFamily* pair_family(const Family& f) {
  if (f.kind != K::tritri || f.name.rfind(kPairPrefix, 0) != 0) return nullptr;
  return find_tritri_family(std::string_view(f.name).substr(kPairPrefix.size()));
}

/// The table with the pair families' descriptions filled in from tritri_families().
const std::vector<Family>& described() {
  static const std::vector<Family> v = [] {
    std::vector<Family> out = table().items;
    for (Family& f : out)
      if (const TriTriFamily* pf = pair_family(f)) f.stresses = "triangle pairs: " + pf->stresses;
    return out;
  }();
  return v;
}

}  // namespace

const std::vector<Family>& families() { return described(); }

const Family* find_family(std::string_view name) {
  for (const Family& f : described())
    if (f.name == name) return &f;
  return nullptr;
}

io::Case tritri_case(const TriPair& p) {
  io::Case c;
  c.kind = io::Kind::tritri;
  const Vec3<double> v[6] = {p.a.p0, p.a.p1, p.a.p2, p.b.p0, p.b.p1, p.b.p2};
  for (std::size_t i = 0; i < 6; ++i) {
    c.v[3 * i] = v[i].x;
    c.v[3 * i + 1] = v[i].y;
    c.v[3 * i + 2] = v[i].z;
  }
  return c;
}

std::string family_names() {
  std::string s;
  for (const auto& f : families()) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  return s;
}

void generate_each(const Family& f, std::size_t count, std::uint64_t seed, Precision p,
                   const std::function<void(const io::Case&)>& sink) {
  if (const TriTriFamily* pf = pair_family(f)) {
    // The pairs as tritri_families.h makes them; in float, every coordinate rounded to float.
    generate_tritri_each(*pf, count, seed, [&](const TriPair& pair) {
      io::Case c = tritri_case(pair);
      if (p == Precision::float32) c = io::round_to_float(c);  // 2^600 becomes inf: invalid in float
      c.family = f.name;
      c.line = 0;
      sink(c);
    });
    return;
  }
  const CaseFn fn = table().fn_of(f);
  if (!fn) return;
  Rng rng = Rng::for_family(seed, f.name);
  for (std::size_t i = 0; i < count; ++i) {
    io::Case c = fn(rng, p);
    c.family = f.name;
    c.line = 0;
    sink(c);
  }
}

std::vector<io::Case> generate(const Family& f, std::size_t count, std::uint64_t seed, Precision p) {
  std::vector<io::Case> out;
  out.reserve(count);
  generate_each(f, count, seed, p, [&](const io::Case& c) { out.push_back(c); });
  return out;
}

// ---------------------------------------------------------------------------------------------
// Lattice helpers (build.h)

namespace detail {

bool collinear(I3 a, I3 b, I3 c) {
  const I3 u = sub(b, a), v = sub(c, a);
  const i128 x = static_cast<i128>(u[1]) * v[2] - static_cast<i128>(u[2]) * v[1];
  const i128 y = static_cast<i128>(u[2]) * v[0] - static_cast<i128>(u[0]) * v[2];
  const i128 z = static_cast<i128>(u[0]) * v[1] - static_cast<i128>(u[1]) * v[0];
  return x == 0 && y == 0 && z == 0;
}

int bit_length(i64 x) {
  auto u = static_cast<std::uint64_t>(x < 0 ? -x : x);
  int n = 0;
  while (u) {
    ++n;
    u >>= 1;
  }
  return n;
}

i64 max_abs(std::initializer_list<I3> vs) {
  i64 m = 0;
  for (const I3& v : vs)
    for (i64 x : v) m = std::max(m, x < 0 ? -x : x);
  return m;
}

I3 rand_ivec(Rng& r, int bits) {
  for (;;) {
    I3 v{r.sym_int(bits), r.sym_int(bits), r.sym_int(bits)};
    if (!is_zero(v)) return v;
  }
}

I3 pythagorean(Rng& r, int bits, i64& len) {
  I3 v{};
  const int mode = r.irange(0, 5);
  if (mode == 0) {  // axis-aligned
    len = r.range(1, i64{1} << std::max(bits, 1));
    v = {len, 0, 0};
  } else if (mode <= 2) {  // Pythagorean triple (m^2 - n^2, 2mn, 0), length m^2 + n^2
    const i64 h = i64{1} << std::max((bits + 1) / 2, 1);
    const i64 m = r.range(2, h + 1), n = r.range(1, m - 1);
    v = {m * m - n * n, 2 * m * n, 0};
    len = m * m + n * n;
  } else {  // quadruple from four parameters (Lebesgue's identity)
    const int hb = std::max((bits - 1) / 2, 1);
    i64 m, n, p, q;
    do {
      m = r.sym_int(hb);
      n = r.sym_int(hb);
      p = r.sym_int(hb);
      q = r.sym_int(hb);
    } while (m == 0 && n == 0 && p == 0 && q == 0);
    v = {m * m + n * n - p * p - q * q, 2 * (m * q + n * p), 2 * (n * q - m * p)};
    len = m * m + n * n + p * p + q * q;
  }
  // Random axis order and signs keep the length.
  for (int i = 2; i > 0; --i) std::swap(v[static_cast<std::size_t>(i)], v[r.below(static_cast<std::uint64_t>(i) + 1)]);
  for (auto& x : v) x *= r.sign();
  return v;
}

PlaceOpts default_opts(Precision p) {
  PlaceOpts o;
  if (p == Precision::float32) {
    o.e_lo = -12, o.e_hi = 12, o.f_lo = -6, o.f_hi = 6, o.g_lo = -6, o.g_hi = 6;
    o.off_lo = 0, o.off_hi = 8;
  } else {
    o.e_lo = -30, o.e_hi = 30, o.f_lo = -10, o.f_hi = 10, o.g_lo = -10, o.g_hi = 10;
    o.off_lo = 0, o.off_hi = 24;
  }
  return o;
}

Place random_place(Rng& r, Precision p, const LCase& c, const PlaceOpts& o) {
  Place pl;
  if (o.permute) {
    for (int i = 2; i > 0; --i)
      std::swap(pl.perm[static_cast<std::size_t>(i)], pl.perm[r.below(static_cast<std::uint64_t>(i) + 1)]);
    for (auto& s : pl.sign) s = r.sign();
  }
  pl.e = r.irange(o.e_lo, o.e_hi);
  pl.f = r.irange(o.f_lo, o.f_hi);
  pl.g = r.irange(o.g_lo, o.g_hi);
  if (o.off_lo >= 0 && (o.always_offset || r.chance(2, 3))) {
    const i64 m = max_abs({c.o, c.p[0], c.p[1], c.p[2]});
    const int cap = mant_bits(p) - 2 - bit_length(m);
    const int hi = std::min(o.off_hi, cap);
    if (hi >= o.off_lo) {
      const int b = r.irange(o.off_lo, hi);
      for (std::size_t i = 0; i < 3; ++i)
        if (o.offset_axis[static_cast<std::size_t>(pl.perm[i])]) pl.off[i] = r.sym_int(b);
    }
  }
  for (auto& z : pl.neg_zero) z = r.coin();
  return pl;
}

std::optional<double> put(i64 m, int e, Precision p) {
  if (m == 0) return 0.0;
  if (m >= (i64{1} << 62) || m <= -(i64{1} << 62)) return std::nullopt;
  const auto x = static_cast<double>(m);
  if (static_cast<i64>(x) != m) return std::nullopt;
  const double y = std::ldexp(x, e);
  if (!std::isfinite(y) || y == 0 || std::ldexp(y, -e) != x) return std::nullopt;
  if (p == Precision::float32) {
    if (std::fabs(y) > static_cast<double>(FLT_MAX)) return std::nullopt;
    if (to_float(y) != y) return std::nullopt;
  }
  return y;
}

namespace {
/// m * 2^shift + extra, when it stays well inside 64 bits.
std::optional<i64> shifted(i64 m, int shift, i64 extra) {
  if (shift == 0) return m + extra;
  const i128 v = (static_cast<i128>(m) << shift) + extra;
  if (v >= (i128{1} << 62) || v <= -(i128{1} << 62)) return std::nullopt;
  return static_cast<i64>(v);
}
}  // namespace

std::optional<io::Case> emit(const LCase& c, const Place& pl, Precision p) {
  io::Case out;
  out.kind = c.kind;
  bool ok = true;
  auto set = [&](std::size_t at, std::optional<double> v) {
    if (!v) ok = false;
    else out.v[at] = *v;
  };
  // A position; `tilt` is its part in units of 2^-tilt_shift along lattice axis tilt_axis.
  auto pos = [&](std::size_t at, const I3& x, i64 tilt) {
    for (std::size_t i = 0; i < 3; ++i) {
      const auto a = static_cast<std::size_t>(pl.perm[i]);
      const i64 m = pl.sign[i] * x[a] + pl.off[i];
      if (tilt != 0 && static_cast<int>(a) == c.tilt_axis) {
        auto mt = shifted(m, c.tilt_shift, pl.sign[i] * tilt);
        set(at + i, mt ? put(*mt, pl.e - c.tilt_shift, p) : std::nullopt);
      } else {
        set(at + i, put(m, pl.e, p));
      }
    }
  };
  auto vec = [&](std::size_t at, const I3& x, int e, i64 tilt) {
    for (std::size_t i = 0; i < 3; ++i) {
      const auto a = static_cast<std::size_t>(pl.perm[i]);
      const i64 m = pl.sign[i] * x[a];
      if (tilt != 0 && static_cast<int>(a) == c.tilt_axis) {
        auto mt = shifted(m, c.tilt_shift, pl.sign[i] * tilt);
        set(at + i, mt ? put(*mt, e - c.tilt_shift, p) : std::nullopt);
      } else if (m == 0) {
        out.v[at + i] = pl.neg_zero[i] ? -0.0 : 0.0;
      } else {
        set(at + i, put(m, e, p));
      }
    }
  };
  pos(0, c.o, c.o_tilt);
  vec(3, c.d, pl.f, c.tilt);
  switch (c.kind) {
    case io::Kind::triangle:
      pos(6, c.p[0], 0);
      pos(9, c.p[1], 0);
      pos(12, c.p[2], 0);
      break;
    case io::Kind::sphere:
      pos(6, c.p[0], 0);
      set(9, put(c.r, pl.e, p));
      break;
    case io::Kind::ellipsoid:
      pos(6, c.p[0], 0);
      for (std::size_t i = 0; i < 3; ++i) set(9 + i, put(c.s[static_cast<std::size_t>(pl.perm[i])], pl.e, p));
      break;
    case io::Kind::box:
      for (std::size_t i = 0; i < 3; ++i) {
        const auto a = static_cast<std::size_t>(pl.perm[i]);
        const i64 u = pl.sign[i] * c.p[0][a] + pl.off[i];
        const i64 w = pl.sign[i] * c.p[1][a] + pl.off[i];
        set(6 + i, put(std::min(u, w), pl.e, p));
        set(9 + i, put(std::max(u, w), pl.e, p));
      }
      break;
    case io::Kind::plane:
      pos(6, c.p[0], 0);
      vec(9, c.n, pl.g, 0);
      break;
    case io::Kind::disk:
      pos(6, c.p[0], 0);
      vec(9, c.n, pl.g, 0);
      set(12, put(c.r, pl.e, p));
      break;
    case io::Kind::tritri: break;  // pairs are placed by tritri_families.cpp
  }
  if (!ok) return std::nullopt;
  return out;
}

double to_float(double x) {
  const volatile float f = static_cast<float>(x);
  return static_cast<double>(f);
}

void finish(io::Case& c, Precision p) {
  if (p != Precision::float32) return;
  for (double& x : c.v)
    if (std::isfinite(x) && std::fabs(x) <= static_cast<double>(FLT_MAX)) x = to_float(x);
}

D3 rand_unit(Rng& r) {
  for (;;) {
    const D3 v{r.sym(), r.sym(), r.sym()};
    const double l2 = length_squared(v);
    if (l2 > 1e-4 && l2 <= 1) return normalize(v);
  }
}

D3 rand_box(Rng& r, double h) {
  const double x = r.sym() * h, y = r.sym() * h, z = r.sym() * h;
  return {x, y, z};
}

D3 normalize(D3 v) {
  const double l = std::sqrt(length_squared(v));
  return v / l;
}

void set3(io::Case& c, std::size_t at, D3 v) {
  c.v[at] = v.x;
  c.v[at + 1] = v.y;
  c.v[at + 2] = v.z;
}

}  // namespace detail
}  // namespace rayproof::gen
