/// Box, plane, disk and invalid families.
// No FMA contraction anywhere in the generator (the build also passes -ffp-contract=off): the same
// seed must give the same bytes on every compiler and target. GCC in ISO mode does not contract.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "gen/build.h"

namespace rayproof::gen::detail {

namespace {


/// A random integer in [-2^bits, 2^bits] that is not 0.
i64 nonzero(Rng& r, int bits) { return r.signed_range(1, i64{1} << bits); }

/// A lattice box with lo < hi on every axis (each side at least `min_side`).
void rand_box_lattice(Rng& r, int cb, int sb, i64 min_side, I3& lo, I3& hi) {
  lo = rand_ivec(r, cb);
  for (std::size_t i = 0; i < 3; ++i) hi[i] = lo[i] + r.range(min_side, std::max(min_side, i64{1} << sb));
}

/// An integer direction v with v . n != 0.
I3 crossing(Rng& r, I3 n, int bits) {
  for (;;) {
    const I3 j = rand_ivec(r, bits);
    if (dot(j, n) != 0) return j;
  }
}

/// A nonzero integer vector perpendicular to n (n != 0).
I3 perp(Rng& r, I3 n, int bits) {
  for (;;) {
    I3 j = cross(n, rand_ivec(r, bits));
    const i64 g = std::gcd(std::gcd(j[0], j[1]), j[2]);
    if (g > 1)
      for (auto& x : j) x /= g;
    if (!is_zero(j)) return j;
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Boxes

io::Case box_generic(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  const D3 lo = rand_box(r, 2);
  D3 size;
  for (std::size_t i = 0; i < 3; ++i) {
    const double u = r.uniform(0.01, 3);
    size[i] = u * r.pow2(-3, 0);
  }
  const D3 hi = lo + size;
  const D3 mid = lo + size * 0.5;
  const double diag = std::sqrt(length_squared(size));
  const double dist = r.uniform(0.3, 6);
  const D3 o = mid + rand_unit(r) * (diag * dist);
  const D3 u = rand_box(r, 0.7);
  const D3 aim = mid + mul(u, size);
  io::Case c;
  c.kind = io::Kind::box;
  set3(c, 0, o * sc);
  set3(c, 3, normalize(aim - o));
  set3(c, 6, lo * sc);
  set3(c, 9, hi * sc);
  finish(c, p);
  return c;
}

io::Case box_graze(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const bool f = is_float(p);
    LCase c;
    c.kind = io::Kind::box;
    I3 lo, hi;
    const int cb = r.irange(0, f ? 8 : 24), sb = r.irange(1, f ? 8 : 24);
    rand_box_lattice(r, cb, sb, 2, lo, hi);
    std::array<int, 3> sigma{};
    for (auto& s : sigma) s = r.sign();
    I3 k{};
    for (std::size_t i = 0; i < 3; ++i) k[i] = sigma[i] > 0 ? hi[i] : lo[i];
    const bool corner = r.coin();
    // Axes i (leaving the box as t grows) and j (leaving it as t falls); the third axis is free.
    std::array<std::size_t, 3> ax{0, 1, 2};
    for (std::size_t i = 2; i > 0; --i) std::swap(ax[i], ax[r.below(i + 1)]);
    const std::size_t i = ax[0], j = ax[1], free = ax[2];
    if (!corner) k[free] = r.range(lo[free] + 1, hi[free] - 1);  // strictly inside an edge
    const int db = r.irange(0, f ? 5 : 16);
    I3 d{};
    d[i] = sigma[i] * r.range(1, i64{1} << db);
    d[j] = -sigma[j] * r.range(1, i64{1} << db);
    d[free] = r.chance(1, 3) ? 0 : r.sym_int(db);
    const i64 s = r.chance(1, 8) ? 0 : r.range(1, i64{1} << r.irange(0, f ? 5 : 12));
    c.p[0] = lo;
    c.p[1] = hi;
    c.d = d;
    c.o = sub(k, mul(d, s));
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

io::Case box_axis_parallel(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const bool f = is_float(p);
    LCase c;
    c.kind = io::Kind::box;
    I3 lo, hi;
    const int cb = r.irange(0, f ? 8 : 24), sb = r.irange(1, f ? 8 : 24);
    rand_box_lattice(r, cb, sb, 1, lo, hi);
    const int db = r.irange(0, f ? 5 : 16);
    const int zeros = r.irange(1, 2);
    std::array<std::size_t, 3> ax{0, 1, 2};
    for (std::size_t i = 2; i > 0; --i) std::swap(ax[i], ax[r.below(i + 1)]);
    I3 d{};
    I3 o{};
    const i64 reach = i64{1} << r.irange(0, f ? 8 : 24);
    for (std::size_t n = 0; n < 3; ++n) {
      const std::size_t a = ax[n];
      const bool zero = n < static_cast<std::size_t>(zeros);
      d[a] = zero ? 0 : nonzero(r, db);
      // Where the origin sits on this axis: on a slab plane, strictly inside, or outside.
      switch (r.irange(0, zero ? 5 : 6)) {
        case 0: case 1: o[a] = lo[a]; break;
        case 2: case 3: o[a] = hi[a]; break;
        case 4: o[a] = hi[a] - lo[a] >= 2 ? r.range(lo[a] + 1, hi[a] - 1) : lo[a]; break;
        case 5: o[a] = r.coin() ? lo[a] - r.range(1, reach) : hi[a] + r.range(1, reach); break;
        default: o[a] = r.range(lo[a] - reach, hi[a] + reach); break;
      }
    }
    c.p[0] = lo;
    c.p[1] = hi;
    c.d = d;
    c.o = o;
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

io::Case box_flat(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const bool f = is_float(p);
    LCase c;
    c.kind = io::Kind::box;
    I3 lo, hi;
    const int cb = r.irange(0, f ? 8 : 24), sb = r.irange(1, f ? 8 : 24);
    rand_box_lattice(r, cb, sb, 1, lo, hi);
    const std::size_t flat = r.below(3);
    const int nflat = r.chance(1, 6) ? (r.chance(1, 3) ? 3 : 2) : 1;
    for (int n = 0; n < nflat; ++n) hi[(flat + static_cast<std::size_t>(n)) % 3] = lo[(flat + static_cast<std::size_t>(n)) % 3];
    const int db = r.irange(0, f ? 5 : 16);
    I3 k{};  // a point of the flat box, sometimes on its boundary
    for (std::size_t i = 0; i < 3; ++i) k[i] = r.chance(1, 4) ? (r.coin() ? lo[i] : hi[i]) : r.range(lo[i], hi[i]);
    I3 d, o;
    switch (r.irange(0, 3)) {
      case 0:
      case 1: {  // crossing the flat box at k, at t = s (either sign)
        d = rand_ivec(r, db);
        if (d[flat] == 0) d[flat] = nonzero(r, db);
        const i64 s = r.sym_int(r.irange(0, f ? 5 : 12));
        o = sub(k, mul(d, s));
        break;
      }
      case 2: {  // travelling within the flat plane
        d = rand_ivec(r, db);
        d[flat] = 0;
        if (is_zero(d)) d[(flat + 1) % 3] = 1;
        const i64 s = r.sym_int(r.irange(0, f ? 5 : 12));
        o = sub(k, mul(d, s));
        break;
      }
      default:  // anywhere
        d = rand_ivec(r, db);
        o = add(k, rand_ivec(r, r.irange(0, f ? 8 : 20)));
        break;
    }
    c.p[0] = lo;
    c.p[1] = hi;
    c.d = d;
    c.o = o;
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

// ---------------------------------------------------------------------------------------------
// Planes

io::Case plane_generic(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  io::Case c;
  c.kind = io::Kind::plane;
  set3(c, 0, rand_box(r, 4) * sc);
  set3(c, 3, rand_unit(r));
  set3(c, 6, rand_box(r, 2) * sc);
  const double nl = r.uniform(0.1, 10);
  set3(c, 9, rand_unit(r) * nl);
  finish(c, p);
  return c;
}

io::Case plane_exact(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const bool f = is_float(p);
    const int nb = r.irange(0, f ? 4 : 12), rb = r.irange(0, f ? 4 : 12), db = r.irange(0, f ? 5 : 12);
    LCase c;
    c.kind = io::Kind::plane;
    I3 n = rand_ivec(r, nb);
    if (r.chance(1, 4)) {  // axis-aligned normal
      const std::size_t a = r.below(3);
      for (std::size_t i = 0; i < 3; ++i)
        if (i != a) n[i] = 0;
      if (n[a] == 0) n[a] = 1;
    }
    const I3 q = rand_ivec(r, r.irange(0, f ? 8 : 24));
    const I3 x = r.chance(1, 4) ? q : add(q, perp(r, n, rb));  // a point of the plane
    const i64 smax = i64{1} << r.irange(0, f ? 5 : 12);
    switch (r.irange(0, 9)) {
      case 0: case 1: case 2: case 3: {  // exact hit at t = s > 0
        c.d = crossing(r, n, db);
        c.o = sub(x, mul(c.d, r.range(1, smax)));
        break;
      }
      case 4: case 5: {  // exact behind, t = -s
        c.d = crossing(r, n, db);
        c.o = add(x, mul(c.d, r.range(1, smax)));
        break;
      }
      case 6: case 7:  // origin on the plane, crossing it: hit at t = 0
        c.d = crossing(r, n, db);
        c.o = x;
        break;
      case 8:  // origin on the plane, direction in it: coplanar
        c.d = perp(r, n, db);
        c.o = x;
        break;
      default:  // parallel, off the plane
        c.d = perp(r, n, db);
        c.o = add(x, crossing(r, n, r.irange(0, f ? 4 : 12)));
        break;
    }
    c.p[0] = q;
    c.n = n;
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

io::Case plane_near_parallel(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) -> std::optional<io::Case> {
    const bool f = is_float(p);
    LCase c;
    c.kind = io::Kind::plane;
    if (f || r.chance(2, 3)) {  // lattice plane z = 0: exact tilt in either precision
      const int db = r.irange(1, f ? 8 : 16);
      c.n = {0, 0, r.signed_range(1, 16)};
      c.p[0] = rand_ivec(r, r.irange(0, f ? 10 : 24));
      c.p[0][2] = 0;
      I3 v;
      do v = {r.sym_int(db), r.sym_int(db), 0};
      while (is_zero(v));
      const I3 x = add(c.p[0], {r.sym_int(db), r.sym_int(db), 0});
      const i64 s = r.chance(1, 5) ? -r.range(1, 64) : r.range(1, 64);
      c.tilt_axis = 2;
      c.tilt_shift = std::max(1, r.irange(20, 50) - bit_length(max_abs({v})) + 1);  // |tilt| 2^-shift ~ 2^-k |v|
      c.d = v;
      c.o = sub(x, mul(v, s));
      const i64 tilt = 2 * r.signed_range(0, 3) + 1;
      if (r.chance(1, 6)) {  // parallel, just off the plane
        c.o_tilt = tilt;
      } else {
        c.tilt = tilt;
        c.o_tilt = -s * tilt;
      }
      PlaceOpts o = default_opts(p);
      o.offset_axis = {true, true, false};
      return emit(c, random_place(r, p, c, o), p);
    }
    // General orientation (double): d = V 2^k + W, V in the plane, W not.
    const I3 n = rand_ivec(r, r.irange(1, 6));
    const I3 v = perp(r, n, 3);
    const int bv = bit_length(max_abs({v}));
    const int k = r.irange(std::max(10, 20 - bv), 44 - bv);  // relative tilt about 2^-(k + bv)
    I3 w;
    do w = rand_ivec(r, 1);
    while (dot(w, n) == 0);
    c.n = n;
    c.p[0] = rand_ivec(r, r.irange(0, 20));
    const I3 x = add(c.p[0], perp(r, n, 3));
    c.d = add(mul(v, i64{1} << k), w);
    const i64 s = r.chance(1, 5) ? -r.range(1, 16) : r.range(1, 16);
    c.o = sub(x, mul(c.d, s));
    PlaceOpts o = default_opts(p);
    o.off_lo = -1;
    return emit(c, random_place(r, p, c, o), p);
  });
}

// ---------------------------------------------------------------------------------------------
// Disks

io::Case disk_generic(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  const D3 center = rand_box(r, 2);
  const D3 n = rand_unit(r);
  const double rad = r.uniform(0.1, 2);
  const double dist = r.uniform(1.5, 10);
  const D3 o = center + rand_unit(r) * (rad * dist);
  const D3 aim = center + rand_box(r, 1.2 * rad);
  io::Case c;
  c.kind = io::Kind::disk;
  set3(c, 0, o * sc);
  set3(c, 3, normalize(aim - o));
  set3(c, 6, center * sc);
  set3(c, 9, n);
  c.v[12] = rad * sc;
  finish(c, p);
  return c;
}

io::Case disk_rim(Rng& rng, Precision prec) {
  return retry(rng, prec, [](Rng& r, Precision p) {
    const bool f = is_float(p);
    LCase c;
    c.kind = io::Kind::disk;
    i64 len = 0;
    const I3 u = pythagorean(r, r.irange(1, f ? 7 : 20), len);  // |u| = len, the radius
    I3 n;
    if (r.chance(1, 3)) {  // axis-aligned normal when u lies in a coordinate plane, else any
      n = I3{};
      std::size_t a = 3;
      for (std::size_t i = 0; i < 3; ++i)
        if (u[i] == 0) a = i;
      if (a < 3) n[a] = r.signed_range(1, 8);
      else n = perp(r, u, r.irange(0, f ? 3 : 8));
    } else {
      n = perp(r, u, r.irange(0, f ? 3 : 8));
    }
    c.p[0] = r.chance(1, 6) ? I3{} : rand_ivec(r, r.irange(0, f ? 8 : 24));
    c.n = n;
    c.r = len;
    const I3 rim = add(c.p[0], u);
    c.d = crossing(r, n, r.irange(0, f ? 5 : 12));
    const i64 s = r.chance(1, 8) ? 0 : r.range(1, i64{1} << r.irange(0, f ? 4 : 10));
    c.o = sub(rim, mul(c.d, s));
    return emit(c, random_place(r, p, c, default_opts(p)), p);
  });
}

// ---------------------------------------------------------------------------------------------
// Invalid cases over every kind

io::Case invalid_mix(Rng& r, Precision p) {
  const bool f = is_float(p);
  io::Case c;
  c.kind = io::kAllKinds[r.below(io::kAllKinds.size())];
  const auto n = static_cast<std::size_t>(io::field_count(c.kind));
  for (std::size_t i = 0; i < n; ++i) c.v[i] = static_cast<double>(r.range(-16, 16));
  // A well-formed case first: nonzero direction, positive sizes, ordered box, nonzero normal.
  if (c.v[3] == 0 && c.v[4] == 0 && c.v[5] == 0) c.v[5] = 1;
  switch (c.kind) {
    case io::Kind::sphere: c.v[9] = static_cast<double>(r.range(1, 8)); break;
    case io::Kind::ellipsoid:
      for (std::size_t i = 9; i < 12; ++i) c.v[i] = static_cast<double>(r.range(1, 8));
      break;
    case io::Kind::disk: c.v[12] = static_cast<double>(r.range(1, 8)); [[fallthrough]];
    case io::Kind::plane:
      if (c.v[9] == 0 && c.v[10] == 0 && c.v[11] == 0) c.v[11] = 1;
      break;
    case io::Kind::box:
      for (std::size_t i = 6; i < 9; ++i)
        if (c.v[i] > c.v[i + 3]) std::swap(c.v[i], c.v[i + 3]);
      break;
    case io::Kind::triangle: break;
    case io::Kind::tritri: break;  // the ray kinds only (kAllKinds)
  }
  const double tiny = f ? static_cast<double>(std::numeric_limits<float>::denorm_min())
                        : std::numeric_limits<double>::denorm_min();
  const bool has_size = c.kind == io::Kind::sphere || c.kind == io::Kind::ellipsoid || c.kind == io::Kind::disk;
  int mode = r.irange(0, 4);
  if (mode == 3 && !has_size) mode = 0;
  if (mode == 4 && c.kind != io::Kind::box) mode = 1;
  switch (mode) {
    case 0:  // NaN anywhere
      c.v[r.below(n)] = std::numeric_limits<double>::quiet_NaN();
      break;
    case 1: {  // an infinity anywhere
      const std::size_t at = r.below(n);
      c.v[at] = r.coin() ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
      break;
    }
    case 2:  // zero direction, with signed zeros
      for (std::size_t i = 3; i < 6; ++i) c.v[i] = r.coin() ? -0.0 : 0.0;
      break;
    case 3: {  // negative radius or semi-axis, down to the smallest subnormal
      std::size_t at = c.kind == io::Kind::sphere ? 9 : (c.kind == io::Kind::disk ? 12 : 9 + r.below(3));
      c.v[at] = r.chance(1, 3) ? -tiny : -static_cast<double>(r.range(1, 8));
      break;
    }
    default: {  // inverted box: lo above hi on an axis, by as little as one ulp
      const std::size_t a = r.below(3);
      const double hi = c.v[9 + a];
      double lo;
      if (r.coin()) {
        lo = f ? static_cast<double>(std::nextafter(static_cast<float>(hi), std::numeric_limits<float>::infinity()))
               : std::nextafter(hi, std::numeric_limits<double>::infinity());
      } else {
        lo = hi + static_cast<double>(r.range(1, 8));
      }
      c.v[6 + a] = lo;
      break;
    }
  }
  return c;
}

}  // namespace rayproof::gen::detail
