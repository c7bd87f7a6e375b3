/// Triangle families. The exact ones put the contact point on the lattice: a vertex, a point
/// k/2^m of the way along an edge, or a barycentric combination with positive integer weights
/// summing to 2^m, all integers once the triangle is scaled by 2^m; the origin is that point minus
/// s times an integer direction that crosses the plane, so the line meets the plane there at t = s.
// No FMA contraction anywhere in the generator (the build also passes -ffp-contract=off): the same
// seed must give the same bytes on every compiler and target. GCC in ISO mode does not contract.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include <algorithm>
#include <cmath>

#include "gen/build.h"

namespace rayproof::gen::detail {

namespace {


using Tri = std::array<I3, 3>;

void shuffle_vertices(Rng& r, Tri& t) {
  for (std::size_t i = 2; i > 0; --i) std::swap(t[i], t[r.below(i + 1)]);
}

/// A random non-degenerate triangle with coordinates about [-2^cb, 2^cb]: general, in a plane
/// z = const, or right-angled along two axes.
Tri rand_triangle(Rng& r, int cb) {
  for (;;) {
    Tri t{rand_ivec(r, cb), rand_ivec(r, cb), rand_ivec(r, cb)};
    const int mode = r.irange(0, 7);
    if (mode == 0) {
      t[1][2] = t[0][2];
      t[2][2] = t[0][2];
    } else if (mode == 1) {
      t[1] = t[0];
      t[2] = t[0];
      t[1][0] += r.signed_range(1, i64{1} << cb);
      t[2][1] += r.signed_range(1, i64{1} << cb);
    }
    if (!collinear(t[0], t[1], t[2])) {
      shuffle_vertices(r, t);
      return t;
    }
  }
}

Tri scaled(const Tri& t, i64 k) { return {mul(t[0], k), mul(t[1], k), mul(t[2], k)}; }
I3 normal_of(const Tri& t) { return cross(sub(t[1], t[0]), sub(t[2], t[0])); }

enum class Spot { interior, edge, vertex, outside };

/// A point of the triangle's plane, on the lattice of the triangle scaled by 2^m: a vertex, a
/// point strictly inside an edge (m >= 1), a point strictly inside (m >= 2), or a point outside.
I3 spot_point(Rng& r, const Tri& t, int m, Spot s) {
  const i64 one = i64{1} << m;
  std::array<i64, 3> w{};
  switch (s) {
    case Spot::vertex:
      return mul(t[r.below(3)], one);
    case Spot::edge: {
      const std::size_t i = r.below(3);
      const I3 u = t[i], v = t[(i + 1) % 3];
      return add(mul(u, one), mul(sub(v, u), r.range(1, one - 1)));
    }
    case Spot::interior: {
      const i64 a = r.range(1, one - 2), b = r.range(1, one - 1 - a);
      w = {a, b, one - a - b};
      break;
    }
    case Spot::outside:
      for (;;) {
        const i64 a = r.range(-one, 2 * one), b = r.range(-one, 2 * one);
        w = {a, b, one - a - b};
        if (a < 0 || b < 0 || w[2] < 0) break;
      }
      break;
  }
  for (std::size_t i = 2; i > 0; --i) std::swap(w[i], w[r.below(i + 1)]);
  return add(add(mul(t[0], w[0]), mul(t[1], w[1])), mul(t[2], w[2]));
}

/// An integer direction crossing the plane of normal n: axis-aligned, in a coordinate plane, or
/// general.
I3 crossing_dir(Rng& r, int bits, I3 n) {
  for (;;) {
    I3 j = rand_ivec(r, bits);
    const int mode = r.irange(0, 7);
    if (mode == 0) {
      const std::size_t keep = r.below(3);
      for (std::size_t i = 0; i < 3; ++i)
        if (i != keep) j[i] = 0;
    } else if (mode == 1) {
      j[r.below(3)] = 0;
    }
    if (!is_zero(j) && dot(j, n) != 0) return j;
  }
}

struct Budget {
  int cb, m, db, sb;  ///< coordinate bits, fraction bits, direction bits, ray-parameter bits
};

Budget draw_budget(Rng& r, Precision p, bool small) {
  if (is_float(p))
    return {r.irange(2, small ? 4 : 6), r.irange(2, small ? 3 : 4), r.irange(1, small ? 3 : 5), r.irange(1, small ? 3 : 5)};
  return {r.irange(2, small ? 12 : 20), r.irange(2, small ? 8 : 16), r.irange(1, small ? 8 : 16), r.irange(1, small ? 8 : 12)};
}

/// The lattice case: contact at `spot`, reached at t = s >= 0 (side > 0; s = 0 puts the origin on
/// the contact point) or at t = s < 0 (side < 0).
LCase contact_lattice(Rng& r, const Budget& b, Spot spot, int side) {
  const Tri t = rand_triangle(r, b.cb);
  const I3 point = spot_point(r, t, b.m, spot);
  const I3 j = crossing_dir(r, b.db, normal_of(t));
  const i64 smax = i64{1} << b.sb;
  const i64 s = side > 0 ? (r.chance(1, 8) ? 0 : r.range(1, smax)) : -r.range(1, smax);
  LCase c;
  c.kind = io::Kind::triangle;
  const Tri big = scaled(t, i64{1} << b.m);
  c.p = {big[0], big[1], big[2]};
  c.d = j;
  c.o = sub(point, mul(j, s));
  return c;
}

io::Case contact_case(Rng& rng, Precision prec, Spot spot, int side) {
  return retry(rng, prec, [&](Rng& r, Precision p) {
    const LCase c = contact_lattice(r, draw_budget(r, p, false), spot, side);
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

Spot any_contact(Rng& r) {
  const int k = r.irange(0, 2);
  return k == 0 ? Spot::interior : (k == 1 ? Spot::edge : Spot::vertex);
}

/// The ray lies in the plane of a lattice triangle (coplanar), or is parallel to it, off it by an
/// integer vector that crosses the plane (parallel).
std::optional<io::Case> in_plane(Rng& r, Precision p, bool parallel) {
  const bool f = is_float(p);
  const int cb = r.irange(2, f ? 5 : 16), m = r.irange(1, f ? 3 : 10), db = r.irange(0, f ? 3 : 8);
  const Tri t = rand_triangle(r, cb);
  const i64 one = i64{1} << m;
  const Tri big = scaled(t, one);
  const I3 e1 = sub(t[1], t[0]), e2 = sub(t[2], t[0]);
  auto in_plane_dir = [&] {
    for (;;) {
      const i64 g = r.sym_int(db), h = r.sym_int(db);
      if (g != 0 || h != 0) return add(mul(e1, g), mul(e2, h));
    }
  };
  I3 o, d;
  const std::size_t vi = r.below(3);
  switch (r.irange(0, 4)) {
    case 0: {  // anywhere around the triangle, any in-plane direction
      const i64 a = r.range(-one, 2 * one), b = r.range(-one, 2 * one);
      o = add(big[0], add(mul(e1, a), mul(e2, b)));
      d = in_plane_dir();
      break;
    }
    case 1: {  // starting inside or on the boundary
      const i64 a = r.range(0, one), b = r.range(0, one - a);
      o = add(big[0], add(mul(e1, a), mul(e2, b)));
      d = in_plane_dir();
      break;
    }
    case 2: {  // along an edge's line
      const I3 u = t[vi], e = sub(t[(vi + 1) % 3], u);
      o = add(mul(u, one), mul(e, r.range(-2 * one, 3 * one)));
      i64 g = r.sym_int(db);
      if (g == 0) g = 1;
      d = mul(e, g);
      break;
    }
    case 3:  // from a vertex
      o = big[vi];
      d = in_plane_dir();
      break;
    default:  // through a vertex from outside
      d = in_plane_dir();
      o = sub(big[vi], mul(d, r.range(1, i64{1} << (f ? 3 : 8))));
      break;
  }
  if (parallel) {
    const I3 n = normal_of(t);
    I3 w;
    do w = rand_ivec(r, r.irange(0, f ? 3 : 12));
    while (dot(w, n) == 0);
    o = add(o, w);
  }
  LCase c;
  c.kind = io::Kind::triangle;
  c.p = {big[0], big[1], big[2]};
  c.o = o;
  c.d = d;
  return emit(c, random_place(r, p, c, default_opts(p)), p);
}

Spot near_parallel_spot(Rng& r) {
  const int k = r.irange(0, 7);
  return k < 4 ? Spot::interior : (k < 6 ? Spot::outside : (k == 6 ? Spot::edge : Spot::vertex));
}

/// Near-parallel, exact: the triangle lies in the lattice plane z = 0 and the direction is
/// (V, tilt * 2^-shift) with V in that plane, so every number stays exact in either precision.
std::optional<io::Case> near_parallel_axis(Rng& r, Precision p) {
  const bool f = is_float(p);
  const int cb = r.irange(2, f ? 6 : 16), m = r.irange(2, f ? 4 : 10), db = r.irange(1, f ? 4 : 10);
  Tri t;
  do {
    t = {rand_ivec(r, cb), rand_ivec(r, cb), rand_ivec(r, cb)};
    for (auto& v : t) v[2] = 0;
  } while (collinear(t[0], t[1], t[2]));
  const I3 point = spot_point(r, t, m, near_parallel_spot(r));
  I3 v;
  do v = {r.sym_int(db), r.sym_int(db), 0};
  while (is_zero(v));
  LCase c;
  c.kind = io::Kind::triangle;
  const Tri big = scaled(t, i64{1} << m);
  c.p = {big[0], big[1], big[2]};
  c.tilt_axis = 2;
  c.tilt_shift = std::max(1, r.irange(20, 50) - bit_length(max_abs({v})) + 1);  // |tilt| 2^-shift ~ 2^-k |v|
  c.tilt = 2 * r.signed_range(0, 3) + 1;
  const i64 s = r.chance(1, 10) ? -r.range(1, 16) : r.range(1, 16);
  c.d = v;
  c.o = sub(point, mul(v, s));
  c.o_tilt = -s * c.tilt;
  PlaceOpts o = default_opts(p);
  o.offset_axis = {true, true, false};
  return emit(c, random_place(r, p, c, o), p);
}

/// Near-parallel, general orientation (double only): d = V 2^k + W with V in the plane, W not.
std::optional<io::Case> near_parallel_general(Rng& r, Precision p) {
  const Tri t = rand_triangle(r, r.irange(2, 5));
  const I3 n = normal_of(t);
  const I3 v = cross(n, rand_ivec(r, 3));
  if (is_zero(v)) return std::nullopt;
  const int bv = bit_length(max_abs({v}));
  if (45 - bv < 7) return std::nullopt;
  const int k = r.irange(std::max(7, 20 - bv), 45 - bv);  // relative tilt about 2^-(k + bv)
  I3 w;
  do w = rand_ivec(r, 1);
  while (dot(w, n) == 0);
  const int m = r.irange(2, 6);
  const I3 point = spot_point(r, t, m, near_parallel_spot(r));
  LCase c;
  c.kind = io::Kind::triangle;
  const Tri big = scaled(t, i64{1} << m);
  c.p = {big[0], big[1], big[2]};
  c.d = add(mul(v, i64{1} << k), w);
  const i64 s = r.chance(1, 10) ? -r.range(1, 16) : r.range(1, 16);
  c.o = sub(point, mul(c.d, s));
  PlaceOpts o = default_opts(p);
  o.off_lo = -1;
  return emit(c, random_place(r, p, c, o), p);
}

}  // namespace

io::Case tri_generic(Rng& r, Precision p) {
  io::Case c;
  c.kind = io::Kind::triangle;
  const D3 o = rand_box(r, 3);
  const std::array<D3, 3> v{rand_box(r, 1), rand_box(r, 1), rand_box(r, 1)};
  D3 aim;
  if (r.coin()) {  // at a point of the triangle's plane inside or near it
    double u = r.uniform(-0.2, 1.2), w = r.uniform(-0.2, 1.2);
    if (u + w > 1 && r.chance(2, 3)) {  // reflected into the triangle
      u = 1 - u;
      w = 1 - w;
    }
    aim = v[0] + (v[1] - v[0]) * u + (v[2] - v[0]) * w;
  } else {
    aim = rand_box(r, 0.8);
  }
  set3(c, 0, o);
  set3(c, 3, normalize(aim - o));
  for (std::size_t i = 0; i < 3; ++i) set3(c, 6 + 3 * i, v[i]);
  finish(c, p);
  return c;
}

io::Case tri_interior_exact(Rng& r, Precision p) { return contact_case(r, p, Spot::interior, 1); }
io::Case tri_edge(Rng& r, Precision p) { return contact_case(r, p, Spot::edge, 1); }
io::Case tri_vertex(Rng& r, Precision p) { return contact_case(r, p, Spot::vertex, 1); }

io::Case tri_behind(Rng& r, Precision p) {
  const Spot s = any_contact(r);
  return contact_case(r, p, s, -1);
}

io::Case tri_offset_big(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const Spot spot = any_contact(r);
    const int side = r.chance(1, 6) ? -1 : 1;
    const LCase c = contact_lattice(r, draw_budget(r, p, true), spot, side);
    PlaceOpts o = default_opts(p);
    o.always_offset = true;
    if (is_float(p)) {
      o.off_lo = 14, o.off_hi = 21, o.e_lo = -10, o.e_hi = 10;
    } else {
      o.off_lo = 30, o.off_hi = 49, o.e_lo = -32, o.e_hi = 0;
    }
    return emit(c, random_place(r, p, c, o), p);
  });
}

io::Case tri_coplanar(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return in_plane(g, q, false); });
}

io::Case tri_parallel(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return in_plane(g, q, true); });
}

io::Case tri_near_parallel(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) {
    if (!is_float(q) && g.chance(1, 3)) return near_parallel_general(g, q);
    return near_parallel_axis(g, q);
  });
}

io::Case tri_degenerate(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) -> std::optional<io::Case> {
    const bool f = is_float(p);
    const int cb = r.irange(2, f ? 8 : 24);
    const int m = r.irange(0, 3);
    const i64 one = i64{1} << m;
    Tri t;
    t[0] = rand_ivec(r, cb);
    switch (r.irange(0, 3)) {
      case 0:
      case 1: {  // three distinct collinear points
        const I3 e = rand_ivec(r, r.irange(0, cb - 1));
        const i64 a = r.signed_range(1, 8);
        i64 b;
        do b = r.range(-8, 8);
        while (b == 0 || b == a);
        t[1] = add(t[0], mul(e, a));
        t[2] = add(t[0], mul(e, b));
        break;
      }
      case 2:  // two repeated
        t[1] = t[0];
        t[2] = rand_ivec(r, cb);
        break;
      default:  // all three the same
        t[1] = t[0];
        t[2] = t[0];
        break;
    }
    shuffle_vertices(r, t);
    if (!collinear(t[0], t[1], t[2])) return std::nullopt;
    const Tri big = scaled(t, one);
    const I3 seg = sub(t[1], t[0]);
    I3 j = rand_ivec(r, r.irange(0, f ? 6 : 16));
    if (!is_zero(seg) && r.chance(1, 5)) j = seg;  // along the segment
    I3 o;
    if (r.chance(1, 3)) {
      o = rand_ivec(r, cb + m + 1);
    } else {  // through a point of the segment, before or after the origin
      const I3 x = add(big[0], mul(seg, r.range(0, one)));
      o = sub(x, mul(j, r.sym_int(f ? 4 : 10)));
    }
    LCase c;
    c.kind = io::Kind::triangle;
    c.p = {big[0], big[1], big[2]};
    c.o = o;
    c.d = j;
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

io::Case tri_sliver(Rng& r, Precision p) {
  const bool f = is_float(p);
  const int ab = r.irange(4, f ? 10 : 20), len = r.irange(4, f ? 21 : 27);
  Tri t;
  for (;;) {
    t[0] = rand_ivec(r, ab);
    I3 d = rand_ivec(r, len - 1);
    const std::size_t axis = r.below(3);
    d[axis] = r.signed_range(i64{1} << (len - 1), i64{1} << len);
    t[1] = add(t[0], d);
    const i64 k = r.range(0, 256);
    I3 mid{};
    for (std::size_t i = 0; i < 3; ++i) mid[i] = (d[i] * k) >> 8;
    t[2] = add(add(t[0], mid), rand_ivec(r, r.irange(0, 2)));
    if (!collinear(t[0], t[1], t[2])) break;
  }
  shuffle_vertices(r, t);
  const int e = r.irange(-20, 20);
  io::Case c;
  c.kind = io::Kind::triangle;
  std::array<D3, 3> v;
  for (std::size_t i = 0; i < 3; ++i) {
    v[i] = {std::ldexp(static_cast<double>(t[i][0]), e), std::ldexp(static_cast<double>(t[i][1]), e),
            std::ldexp(static_cast<double>(t[i][2]), e)};
    set3(c, 6 + 3 * i, v[i]);
  }
  double u, w;
  if (r.coin()) {
    w = r.unit();
    u = r.unit() * (1 - w);
  } else {
    w = r.uniform(-0.5, 1.5);
    u = r.uniform(-0.2, 1.2);
  }
  const D3 aim = v[0] + (v[1] - v[0]) * u + (v[2] - v[0]) * w;
  const D3 dir = rand_unit(r);
  const double dist = std::sqrt(length_squared(v[1] - v[0])) * r.uniform(0.5, 4);
  set3(c, 0, aim - dir * dist);
  set3(c, 3, dir * r.pow2(-4, 4));
  finish(c, p);
  return c;
}

io::Case tri_far_small(Rng& r, Precision p) {
  const double size = r.pow2(-30, -8);  // the distance is 1
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
  const D3 a = aim - e1 * b - e2 * g;
  const double lateral = r.chance(1, 2) ? 0.0 : 4 * size;
  const D3 o{r.sym() * lateral, r.sym() * lateral, -1};
  const D3 d{aim.x - o.x, aim.y - o.y, 1};
  // Permute and flip axes, scale by a power of two: exact.
  std::array<int, 3> perm{0, 1, 2};
  for (std::size_t i = 2; i > 0; --i) std::swap(perm[i], perm[r.below(i + 1)]);
  std::array<double, 3> sg{};
  for (auto& s : sg) s = r.sign();
  const int e = r.irange(-20, 20);
  auto place = [&](D3 x) {
    D3 y;
    for (std::size_t i = 0; i < 3; ++i) y[i] = std::ldexp(sg[i] * x[static_cast<std::size_t>(perm[i])], e);
    return y;
  };
  io::Case c;
  c.kind = io::Kind::triangle;
  set3(c, 0, place(o));
  set3(c, 3, place(d));
  std::array<D3, 3> v{a, a + e1, a + e2};
  for (std::size_t i = 2; i > 0; --i) std::swap(v[i], v[r.below(i + 1)]);
  for (std::size_t i = 0; i < 3; ++i) set3(c, 6 + 3 * i, place(v[i]));
  finish(c, p);
  return c;
}

io::Case tri_extreme_scale(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) -> std::optional<io::Case> {
    const bool f = is_float(p);
    const Budget b = f ? Budget{r.irange(2, 5), r.irange(2, 3), r.irange(1, 4), r.irange(1, 3)}
                       : Budget{r.irange(2, 10), r.irange(2, 6), r.irange(1, 8), r.irange(1, 6)};
    const int k = r.irange(0, 9);
    const Spot spot = k < 4 ? Spot::interior : (k < 8 ? Spot::outside : (k == 8 ? Spot::edge : Spot::vertex));
    const LCase c = contact_lattice(r, b, spot, 1);
    PlaceOpts o = default_opts(p);
    o.off_lo = -1;
    Place pl = random_place(r, p, c, o);
    // Exponent of the largest magnitude: moderate, 1e+-30, near the top or bottom of the range,
    // or subnormal.
    auto extreme = [&](int mb) {
      const int min_e = f ? -149 : -1074;
      switch (r.irange(0, f ? 5 : 7)) {
        case 0: return r.irange(-5, 5) - mb;
        case 1: return r.irange(90, 110) - mb;
        case 2: return -r.irange(90, 110) - mb;
        case 3: return min_e + r.irange(0, f ? 6 : 12);  // subnormal
        case 4: return (f ? r.irange(118, 127) : r.irange(990, 1023)) - mb;
        case 5: return -(f ? r.irange(118, 126) : r.irange(1000, 1022)) - mb;
        case 6: return r.irange(480, 510) - mb;
        default: return -r.irange(480, 510) - mb;
      }
    };
    pl.e = extreme(bit_length(max_abs({c.o, c.p[0], c.p[1], c.p[2]})));
    const int db = bit_length(max_abs({c.d}));
    const int span = f ? 120 : 1000;
    do pl.f = extreme(db);
    while (pl.e - pl.f > span || pl.f - pl.e > span);
    return emit(c, pl, p);
  });
}

io::Case tri_vertex_aimed_float(Rng& r, Precision p) {
  for (;;) {
    const double sc = r.pow2(-20, 20);
    auto fl = [&](double h) {  // a random point with float coordinates (to_float: see build.h)
      const D3 v = rand_box(r, h * sc);
      return std::array<float, 3>{static_cast<float>(to_float(v.x)), static_cast<float>(to_float(v.y)),
                                  static_cast<float>(to_float(v.z))};
    };
    const auto o = fl(4);
    const std::array<std::array<float, 3>, 3> tri{fl(1), fl(1), fl(1)};
    const auto& v = tri[r.below(3)];
    // normalize(v - o), every step in float.
    const float dx = v[0] - o[0], dy = v[1] - o[1], dz = v[2] - o[2];
    float l2 = dx * dx;
    l2 += dy * dy;
    l2 += dz * dz;
    if (!(l2 > 0) || !std::isfinite(l2)) continue;
    const float l = std::sqrt(l2);
    const std::array<float, 3> d{dx / l, dy / l, dz / l};
    io::Case c;
    c.kind = io::Kind::triangle;
    for (std::size_t i = 0; i < 3; ++i) {
      c.v[i] = o[i];
      c.v[3 + i] = d[i];
      for (std::size_t k = 0; k < 3; ++k) c.v[6 + 3 * k + i] = tri[k][i];
    }
    finish(c, p);
    return c;
  }
}

}  // namespace rayproof::gen::detail
