/// The stiffness knobs (knobs.h). Each generator builds one case at knob value 2^k; the comment
/// above it says what exactly holds for its cases (the tests check it).
// No FMA contraction (the build passes -ffp-contract=off for the generator): same seed, same bytes.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include "gen/knobs.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "gen/build.h"
#include "gen/gen_table.h"

namespace rayproof::gen {

using namespace detail;

namespace {

using K = io::Kind;

double dbl(i64 x) { return static_cast<double>(x); }

void put_ivec(io::Case& c, std::size_t at, I3 v, int e) {
  for (std::size_t i = 0; i < 3; ++i) c.v[at + i] = std::ldexp(dbl(v[i]), e);
}

/// offset: a lattice triangle with |coordinates| <= 2^12 (the size), hit at t = s (1..8, or
/// behind, 1 in 8) at a point with barycentrics in 1/256ths (interior two times in three, else
/// outside: the origin's lattice coordinates stay below 2^15), the whole case (origin and
/// vertices) translated by +-2^(k+12) on every axis. Each
/// emitted coordinate is the double nearest to offset + lattice value (exact while k + 13 <= 53).
io::Case knob_offset(Rng& r, int k) {
  std::array<I3, 3> t;
  do t = {rand_ivec(r, 4), rand_ivec(r, 4), rand_ivec(r, 4)};
  while (collinear(t[0], t[1], t[2]));
  const I3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
  std::array<i64, 3> w{};
  if (r.chance(2, 3)) {
    const i64 a = r.range(1, 254), b = r.range(1, 255 - a);
    w = {a, b, 256 - a - b};
  } else {
    for (;;) {
      const i64 a = r.range(-256, 512), b = r.range(-256, 512);
      w = {a, b, 256 - a - b};
      if (a < 0 || b < 0 || w[2] < 0) break;
    }
  }
  const I3 x = add(add(mul(t[0], w[0]), mul(t[1], w[1])), mul(t[2], w[2]));
  I3 j;
  do j = rand_ivec(r, 3);
  while (dot(j, n) == 0);
  const i64 s = r.chance(1, 8) ? -r.range(1, 8) : r.range(1, 8);
  const I3 o = sub(x, mul(j, s));
  std::array<double, 3> off{};
  for (auto& v : off) v = std::ldexp(static_cast<double>(r.sign()), k + 12);
  io::Case c;
  c.kind = K::triangle;
  for (std::size_t i = 0; i < 3; ++i) {
    c.v[i] = off[i] + dbl(o[i]);
    c.v[3 + i] = dbl(j[i]);
    for (std::size_t q = 0; q < 3; ++q) c.v[6 + 3 * q + i] = off[i] + dbl(t[q][i] * 256);
  }
  return c;
}

/// A random integer normal n (components in [-8, 8]) with n_z != 0 and (n_x, n_y) != 0, and the
/// direction (n_y, -n_x, +-M 2^k), M = max(|n_x|, |n_y|): |d_z| / max(|d_x|, |d_y|) = 2^k exactly,
/// n . d = +-n_z M 2^k. The contact point x = (x, y, 0) on the plane n . p = n . x is reached at
/// t = s from the origin x - s d, exactly: every value is a small integer times a power of two.
struct Tilted {
  I3 n{}, x{};
  i64 s = 0, m = 0;
  int dz_sign = 1;
};
Tilted tilted(Rng& r) {
  Tilted q;
  do q.n = rand_ivec(r, 3);
  while (q.n[2] == 0 || (q.n[0] == 0 && q.n[1] == 0));
  q.m = std::max(std::abs(q.n[0]), std::abs(q.n[1]));
  q.dz_sign = r.sign();
  q.x = {r.sym_int(8), r.sym_int(8), 0};
  q.s = r.chance(1, 10) ? -r.range(1, 16) : r.range(1, 16);
  return q;
}
void put_tilted_ray(io::Case& c, const Tilted& q, int k) {
  c.v[0] = dbl(q.x[0] - q.s * q.n[1]);
  c.v[1] = dbl(q.x[1] + q.s * q.n[0]);
  c.v[2] = -std::ldexp(dbl(q.s * q.m * q.dz_sign), k);
  c.v[3] = dbl(q.n[1]);
  c.v[4] = dbl(-q.n[0]);
  c.v[5] = std::ldexp(dbl(q.m * q.dz_sign), k);
}

/// tilt_triangle: a triangle in the plane of `tilted`, its vertices x + a e1 + b e2 (e1 = (n_y,
/// -n_x, 0), e2 = n x e1, integers a, b in [-8, 8]); x strictly inside it two times in three, else
/// strictly outside.
io::Case knob_tilt_triangle(Rng& r, int k) {
  const Tilted q = tilted(r);
  const I3 e1{q.n[1], -q.n[0], 0};
  const I3 e2 = cross(q.n, e1);
  const bool want_inside = r.chance(2, 3);
  std::array<std::array<i64, 2>, 3> ab{};
  for (;;) {
    for (auto& v : ab) v = {r.sym_int(3), r.sym_int(3)};
    auto orient = [&](std::size_t i, std::size_t j) {  // sign of (ab[j] - ab[i]) x (0 - ab[i])
      return (ab[j][0] - ab[i][0]) * (-ab[i][1]) - (ab[j][1] - ab[i][1]) * (-ab[i][0]);
    };
    const i64 area = (ab[1][0] - ab[0][0]) * (ab[2][1] - ab[0][1]) - (ab[1][1] - ab[0][1]) * (ab[2][0] - ab[0][0]);
    if (area == 0) continue;
    const i64 o0 = orient(0, 1), o1 = orient(1, 2), o2 = orient(2, 0);
    if (o0 == 0 || o1 == 0 || o2 == 0) continue;  // x on an edge's line: neither strictly in nor out
    const bool inside = (o0 > 0) == (o1 > 0) && (o1 > 0) == (o2 > 0);
    if (inside == want_inside) break;
  }
  io::Case c;
  c.kind = K::triangle;
  put_tilted_ray(c, q, k);
  for (std::size_t v = 0; v < 3; ++v) put_ivec(c, 6 + 3 * v, add(q.x, add(mul(e1, ab[v][0]), mul(e2, ab[v][1]))), 0);
  return c;
}

/// tilt_plane: a plane through a lattice point x with an integer normal n (components in
/// [-8, 8]) in general position; an in-plane integer vector V = n x R; the direction
/// d = V + 2^(k+j) n, j the smallest with 2^j max|n_i| >= max|V_i|, so the sine of the angle
/// between ray and plane is 2^k within a factor 4 (it is 2^(k+j) |n| / |d|). The origin is
/// x - s d (s in 1..16, or behind, 1 in 10) and the normal n 2^g (g in [-4, 4]); d and the origin
/// are the doubles nearest to those values (exact while 2^(k+j) n needs no more bits than a double
/// has beside V), so the cancellation in n . d is left to the method (no exact integer products).
io::Case knob_tilt_plane(Rng& r, int k) {
  I3 n, v;
  do {
    n = rand_ivec(r, 3);
    v = cross(n, rand_ivec(r, 3));
  } while (is_zero(v));
  int j = -8;
  while ((static_cast<i128>(max_abs({n})) << (j + 8)) < (static_cast<i128>(max_abs({v})) << 8)) ++j;
  const I3 x = rand_ivec(r, 8);
  const double s = dbl(r.chance(1, 10) ? -r.range(1, 16) : r.range(1, 16));
  io::Case c;
  c.kind = K::plane;
  for (std::size_t i = 0; i < 3; ++i) {
    const double d = dbl(v[i]) + std::ldexp(dbl(n[i]), k + j);
    c.v[3 + i] = d;
    c.v[i] = dbl(x[i]) - s * d;
  }
  put_ivec(c, 6, x, 0);
  put_ivec(c, 9, n, r.irange(-4, 4));
  return c;
}

/// sliver: vertices p, p + 2^(k+j) A, p + u 2^(k+j) A + 2^i B with B = A x C, so B is orthogonal
/// to A and the edge from p over its altitude is 2^k (2^(j-i) |A| / |B|), in [2^k, 2^(k+1)) by the
/// choice of i, j >= 0; u in 1/256ths of [0, 1]. The ray aims at a point a little around the
/// sliver (barycentric across the thin side in [-0.5, 1.5]), from 1 to 8 altitudes away, at least
/// 0.3 out of the plane; the aim and direction are rounded to double.
io::Case knob_sliver(Rng& r, int k) {
  I3 a, b;
  do {
    a = rand_ivec(r, 3);
    b = cross(a, rand_ivec(r, 3));
  } while (is_zero(b));
  const i128 a2 = dot(a, a), b2 = dot(b, b);
  int e = 0;  // 4^e |A|^2 in [|B|^2, 4 |B|^2)
  while ((a2 << (2 * std::max(e, 0))) * (i128{1} << (2 * std::max(-e, 0))) < b2) ++e;
  while (e > -30 && (a2 << (2 * std::max(e, 0))) >= 4 * b2 * (i128{1} << (2 * std::max(-e, 0)))) --e;
  const int j = std::max(e, 0), i = std::max(-e, 0);
  const I3 p = rand_ivec(r, 4);
  const double u = std::ldexp(dbl(r.range(0, 256)), -8);
  std::array<D3, 3> v;
  const double L = std::ldexp(1.0, k + j), h = std::ldexp(1.0, i);
  for (std::size_t q = 0; q < 3; ++q) {
    v[0][q] = dbl(p[q]);
    v[1][q] = dbl(p[q]) + L * dbl(a[q]);
    v[2][q] = dbl(p[q]) + u * L * dbl(a[q]) + h * dbl(b[q]);
  }
  const D3 na = normalize(D3{dbl(a[0]), dbl(a[1]), dbl(a[2])});
  const D3 nb = normalize(D3{dbl(b[0]), dbl(b[1]), dbl(b[2])});
  const D3 normal = cross(na, nb);
  const double al = r.unit(), be = r.uniform(-0.5, 1.5);
  const D3 aim = v[0] + (v[1] - v[0]) * al + (v[2] - v[0]) * be;
  D3 d;
  do d = rand_unit(r);
  while (std::fabs(dot(d, normal)) < 0.3);
  const double dist = h * std::sqrt(static_cast<double>(b2)) * r.uniform(1, 8);
  io::Case c;
  c.kind = K::triangle;
  set3(c, 0, aim - d * dist);
  set3(c, 3, d);
  const std::size_t first = r.below(3);  // which vertex comes first
  for (std::size_t q = 0; q < 3; ++q) set3(c, 6 + 3 * q, v[(first + q) % 3]);
  return c;
}

/// far_small: a triangle whose edges are drawn from [-2^-k, 2^-k]^3 around an aim point within
/// 2^-k/2 of the axis, seen from distance 1 (the origin at z = -1, on the axis or 4 2^-k to the
/// side), aimed at a point inside it half the time; axes permuted and flipped; every value rounded
/// to float (float methods see the same case).
io::Case knob_far_small(Rng& r, int k) {
  const double size = std::ldexp(1.0, -k);
  const D3 aim{r.sym() * size / 2, r.sym() * size / 2, 0};
  const D3 e1 = rand_box(r, size), e2 = rand_box(r, size);
  double b, g;
  if (r.coin()) {
    b = r.unit();
    g = r.unit() * (1 - b);
  } else {
    b = r.uniform(-1, 2);
    g = r.uniform(-1, 2);
  }
  const D3 p = aim - e1 * b - e2 * g;
  const double lateral = r.coin() ? 0.0 : 4 * size;
  const D3 o{r.sym() * lateral, r.sym() * lateral, -1};
  const D3 d{aim.x - o.x, aim.y - o.y, 1};
  std::array<int, 3> perm{0, 1, 2};
  for (std::size_t i = 2; i > 0; --i) std::swap(perm[i], perm[r.below(i + 1)]);
  std::array<double, 3> sg{};
  for (auto& s : sg) s = r.sign();
  auto place = [&](D3 x) {
    D3 y;
    for (std::size_t i = 0; i < 3; ++i) y[i] = sg[i] * x[static_cast<std::size_t>(perm[i])];
    return y;
  };
  io::Case c;
  c.kind = K::triangle;
  set3(c, 0, place(o));
  set3(c, 3, place(d));
  const std::array<D3, 3> v{p, p + e1, p + e2};
  for (std::size_t i = 0; i < 3; ++i) set3(c, 6 + 3 * i, place(v[i]));
  finish(c, Precision::float32);
  return c;
}

/// ellipsoid: semi-axes 2^lo, 2^(lo+k) and 2^(lo+m) (m in [0, k]), in a random axis order, so the
/// largest over the smallest is 2^k exactly; centre within the largest semi-axis of 0; the origin
/// 2.1 to 8 largest semi-axes away in a random direction, aimed at a point of the semi-axes box
/// scaled by 1.2. Every value is rounded to float (float methods see the same case).
io::Case knob_ellipsoid(Rng& r, int k) {
  const int lo = r.irange(-8, 8) - k / 2;
  std::array<int, 3> ex{lo, lo + k, lo + r.irange(0, k)};
  for (std::size_t i = 2; i > 0; --i) std::swap(ex[i], ex[r.below(i + 1)]);
  const D3 s{std::ldexp(1.0, ex[0]), std::ldexp(1.0, ex[1]), std::ldexp(1.0, ex[2])};
  const double big = std::ldexp(1.0, lo + k);
  const D3 ctr = rand_box(r, big);
  const D3 o = ctr + rand_unit(r) * (big * r.uniform(2.1, 8));
  const D3 u = rand_box(r, 1.2);
  const D3 aim = ctr + D3{u.x * s.x, u.y * s.y, u.z * s.z};
  io::Case c;
  c.kind = K::ellipsoid;
  set3(c, 0, o);
  set3(c, 3, normalize(aim - o));
  set3(c, 6, ctr);
  set3(c, 9, s);
  finish(c, Precision::float32);
  return c;
}

/// magnitude_large / magnitude_small: an exact lattice case (a triangle with |coordinates| <= 2^7,
/// hit at a point in 1/8ths: strictly inside two times in three, else outside, never on an edge:
/// the knob is about range, not about edge rules; t = s in 1..8) whose
/// positions and direction are all multiplied by 2^k: every coordinate is an integer of at most 8
/// bits times 2^k, exact in double for k in [-1074, 1015] (subnormal below 2^-1022).
io::Case knob_magnitude(Rng& r, int k) {
  std::array<I3, 3> t;
  do t = {rand_ivec(r, 4), rand_ivec(r, 4), rand_ivec(r, 4)};
  while (collinear(t[0], t[1], t[2]));
  const I3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
  std::array<i64, 3> w{};
  if (r.chance(2, 3)) {
    const i64 a = r.range(1, 6), b = r.range(1, 7 - a);
    w = {a, b, 8 - a - b};
  } else {
    for (;;) {
      const i64 a = r.range(-8, 16), b = r.range(-8, 16);
      w = {a, b, 8 - a - b};
      if (a < 0 || b < 0 || w[2] < 0) break;
    }
  }
  for (std::size_t i = 2; i > 0; --i) std::swap(w[i], w[r.below(i + 1)]);
  const I3 x = add(add(mul(t[0], w[0]), mul(t[1], w[1])), mul(t[2], w[2]));
  I3 j;
  do j = rand_ivec(r, 2);
  while (dot(j, n) == 0);
  const I3 o = sub(x, mul(j, r.range(1, 8)));
  io::Case c;
  c.kind = K::triangle;
  put_ivec(c, 0, o, k);
  put_ivec(c, 3, j, k);
  for (std::size_t q = 0; q < 3; ++q) put_ivec(c, 6 + 3 * q, mul(t[q], 8), k);
  return c;
}

/// tangency: a sphere of radius R = 2^e (e in [-4, 4]) at a centre with coordinates in
/// [-8, 8] R; the ray along a random axis (either way, length 2^f), its line at distance
/// D = R (1 +- 2^k) from the centre along a second axis (+: miss, -: hit); the origin 2 to 8 radii
/// back along the ray. (D - R) / R = +-2^k exactly while the sums are exact (k >= -44); beyond,
/// each coordinate is the double nearest to it.
io::Case knob_tangency(Rng& r, int k) {
  const int e = r.irange(-4, 4);
  const double R = std::ldexp(1.0, e);
  const I3 ci = rand_ivec(r, 3);
  const D3 ctr{dbl(ci[0]) * R, dbl(ci[1]) * R, dbl(ci[2]) * R};
  const std::size_t along = r.below(3), side = (along + 1 + r.below(2)) % 3;
  const double D = r.coin() ? R + R * std::ldexp(1.0, k) : R - R * std::ldexp(1.0, k);
  const double dir = r.sign();
  D3 o = ctr, d{0, 0, 0};
  o[side] = ctr[side] + r.sign() * D;
  o[along] = ctr[along] - dir * R * dbl(r.range(2, 8));
  d[along] = std::ldexp(dir, r.irange(-4, 4));
  io::Case c;
  c.kind = K::sphere;
  set3(c, 0, o);
  set3(c, 3, d);
  set3(c, 6, ctr);
  c.v[9] = R;
  return c;
}

using KnobFn = io::Case (*)(Rng&, int);

using Table = GenTable<Knob, KnobFn>;

std::vector<int> steps(int from, int to, int by) {
  std::vector<int> v;
  for (int k = from; by > 0 ? k <= to : k >= to; k += by) v.push_back(k);
  return v;
}

const Table& table() {
  static const Table t = {
      {{"offset", K::triangle, "offset / size", "exact lattice hits translated far from the origin: cancellation in absolute positions",
        steps(0, 60, 4)},
       knob_offset},
      {{"tilt_triangle", K::triangle, "tilt (|d_z| / max(|d_x|, |d_y|), triangle in a plane with n_z != 0)",
        "rays nearly parallel to a triangle: the determinant n . d is tiny next to its terms", steps(-1, -59, -2)},
       knob_tilt_triangle},
      {{"tilt_plane", K::plane, "tilt (sine of the angle between ray and plane, within a factor 4)",
        "rays nearly parallel to a plane: n . d is tiny next to its terms", steps(-1, -59, -2)},
       knob_tilt_plane},
      {{"sliver", K::triangle, "aspect ratio (edge / its altitude, within a factor 2)",
        "needle triangles: two edges nearly parallel, their cross product cancels", steps(0, 40, 2)},
       knob_sliver},
      {{"far_small", K::triangle, "distance / size", "a tiny triangle far away: barycentrics from differences of nearly equal products",
        steps(0, 40, 2)},
       knob_far_small},
      {{"ellipsoid", K::ellipsoid, "axis ratio (largest / smallest semi-axis)",
        "badly scaled quadratic coefficients", steps(0, 40, 2)},
       knob_ellipsoid},
      {{"magnitude_large", K::triangle, "coordinate magnitude", "exact hits scaled up to 2^1000: products overflow",
        {0, 16, 32, 40, 44, 48, 56, 64, 72, 96, 128, 160, 256, 320, 344, 384, 448, 512, 520, 640, 768, 896, 1000}},
       knob_magnitude},
      {{"magnitude_small", K::triangle, "coordinate magnitude", "exact hits scaled down to the subnormals: products underflow",
        {0, -16, -32, -40, -44, -48, -56, -64, -72, -96, -128, -160, -256, -320, -344, -384, -448, -512, -520, -640, -768,
         -896, -1000, -1022, -1040, -1060, -1074}},
       knob_magnitude},
      {{"tangency", K::sphere, "distance from tangency / radius", "lines passing the sphere at R (1 +- 2^k): the discriminant cancels",
        steps(0, -60, -3)},
       knob_tangency},
  };
  return t;
}

}  // namespace

const std::vector<Knob>& knobs() { return table().items; }

const Knob* find_knob(std::string_view name) { return table().find(name); }

std::string step_name(const Knob& k, int exponent) { return k.name + "@" + std::to_string(exponent); }

std::optional<std::pair<const Knob*, int>> parse_step_name(std::string_view group) {
  const auto at = group.find('@');
  if (at == std::string_view::npos) return std::nullopt;
  const Knob* k = find_knob(group.substr(0, at));
  if (!k) return std::nullopt;
  int e = 0;
  const auto rest = group.substr(at + 1);
  const auto [ptr, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), e);
  if (ec != std::errc() || ptr != rest.data() + rest.size()) return std::nullopt;
  return std::pair<const Knob*, int>{k, e};
}

std::vector<io::Case> generate_knob(const Knob& k, int exponent, std::size_t count, std::uint64_t seed) {
  const KnobFn fn = table().fn_of(k);
  std::vector<io::Case> out;
  if (!fn) return out;
  const std::string name = step_name(k, exponent);
  Rng rng = Rng::for_family(seed, name);
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    io::Case c = fn(rng, exponent);
    c.family = name;
    out.push_back(c);
  }
  return out;
}

}  // namespace rayproof::gen
