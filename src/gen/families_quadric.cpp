/// Sphere and ellipsoid families. Exact contacts come from Pythagorean quadruples n (integer
/// vectors of integer length r): the point c + n lies exactly on the sphere of radius r about c,
/// and a direction perpendicular to n there is an exact tangent. For the ellipsoid the sphere is
/// stretched by integers k_i along the axes: semi-axes r k_i, surface point c_i + k_i n_i, normal
/// proportional to n_i / k_i.
// No FMA contraction anywhere in the generator (the build also passes -ffp-contract=off): the same
// seed must give the same bytes on every compiler and target. GCC in ISO mode does not contract.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
#include <algorithm>
#include <cmath>
#include <numeric>

#include "gen/build.h"

namespace rayproof::gen::detail {

namespace {


/// v / gcd of its components (keeps direction and perpendicularity, shrinks the numbers).
I3 reduced(I3 v) {
  const i64 g = std::gcd(std::gcd(v[0], v[1]), v[2]);
  if (g > 1)
    for (auto& x : v) x /= g;
  return v;
}

/// An integer direction perpendicular to n (n != 0).
I3 perpendicular(Rng& r, I3 n, int bits) {
  for (;;) {
    const I3 j = reduced(cross(n, rand_ivec(r, bits)));
    if (!is_zero(j)) return j;
  }
}

/// A lattice surface point of a sphere or an ellipsoid, with the surface normal there.
struct Surface {
  LCase c;   ///< kind, centre (p[0]) and radius or semi-axes set
  I3 point;  ///< on the surface
  I3 normal; ///< outward normal at point (integer, not unit)
};

Surface sphere_surface(Rng& r, Precision p) {
  const bool f = is_float(p);
  Surface s;
  i64 len = 0;
  const I3 n = pythagorean(r, r.irange(1, f ? 7 : 20), len);
  s.c.kind = io::Kind::sphere;
  s.c.p[0] = r.chance(1, 6) ? I3{} : rand_ivec(r, r.irange(0, f ? 8 : 24));
  s.c.r = len;
  s.point = add(s.c.p[0], n);
  s.normal = n;
  return s;
}

Surface ellipsoid_surface(Rng& r, Precision p) {
  const bool f = is_float(p);
  Surface s;
  i64 len = 0;
  const I3 n = pythagorean(r, r.irange(1, f ? 5 : 14), len);
  I3 k{};
  if (r.coin()) {
    for (auto& x : k) x = r.range(1, f ? 4 : 64);
  } else {
    for (auto& x : k) x = i64{1} << r.irange(0, f ? 3 : 12);
  }
  const i64 l = std::lcm(std::lcm(k[0], k[1]), k[2]);
  s.c.kind = io::Kind::ellipsoid;
  s.c.p[0] = r.chance(1, 6) ? I3{} : rand_ivec(r, r.irange(0, f ? 8 : 24));
  s.c.s = mul(k, len);
  I3 on{}, g{};
  for (std::size_t i = 0; i < 3; ++i) {
    on[i] = k[i] * n[i];
    g[i] = n[i] * (l / k[i]);
  }
  s.point = add(s.c.p[0], on);
  s.normal = reduced(g);
  return s;
}

/// Tangent at the surface point, touched at t = s >= 0.
std::optional<io::Case> tangent_case(Rng& r, Precision p, Surface s) {
  const bool f = is_float(p);
  const I3 j = perpendicular(r, s.normal, r.irange(0, f ? 3 : 8));
  const i64 t = r.chance(1, 8) ? 0 : r.range(1, i64{1} << r.irange(0, f ? 4 : 10));
  s.c.d = j;
  s.c.o = sub(s.point, mul(j, t));
  return emit(s.c, random_place(r, p, s.c, default_opts(p)), p);
}

/// Origin on the surface, heading in (hit, T = 0), out (inside, T2 = 0) or along it (tangent).
std::optional<io::Case> on_surface_case(Rng& r, Precision p, Surface s) {
  const bool f = is_float(p);
  const int bits = r.irange(0, f ? 5 : 12);
  I3 j;
  if (r.chance(1, 4)) {
    j = perpendicular(r, s.normal, r.irange(0, f ? 3 : 8));
  } else {
    j = rand_ivec(r, bits);
    const i128 dn = dot(j, s.normal);
    const bool inward = r.coin();
    if ((dn > 0 && inward) || (dn < 0 && !inward)) j = mul(j, -1);
  }
  s.c.d = j;
  s.c.o = s.point;
  return emit(s.c, random_place(r, p, s.c, default_opts(p)), p);
}

}  // namespace

io::Case sph_generic(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  const D3 c = rand_box(r, 2);
  const double rad = r.uniform(0.05, 2);
  // The aim lies within 1.5 sqrt(3) r < 2.7 r of the centre, so the sphere is never behind.
  const double dist = r.uniform(2.7, 20);
  const D3 o = c + rand_unit(r) * (rad * dist);
  const D3 aim = c + rand_box(r, 1.5 * rad);
  io::Case k;
  k.kind = io::Kind::sphere;
  set3(k, 0, o * sc);
  set3(k, 3, normalize(aim - o));
  set3(k, 6, c * sc);
  k.v[9] = rad * sc;
  finish(k, p);
  return k;
}

io::Case sph_tangent_exact(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return tangent_case(g, q, sphere_surface(g, q)); });
}

io::Case sph_on_surface(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return on_surface_case(g, q, sphere_surface(g, q)); });
}

io::Case sph_inside_behind(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  const D3 c = rand_box(r, 2);
  const double rad = r.uniform(0.1, 3);
  D3 o, d;
  if (r.coin()) {  // inside: any direction
    const double depth = r.uniform(0, 0.9);
    o = c + rand_unit(r) * (rad * depth);
    d = rand_unit(r);
  } else {  // behind: the line passes through a point A inside, and points from A to the origin
    const double dist = r.uniform(1.5, 20);
    o = c + rand_unit(r) * (rad * dist);
    const D3 a = c + rand_box(r, 0.5 * rad);
    d = normalize(o - a);
  }
  io::Case k;
  k.kind = io::Kind::sphere;
  set3(k, 0, o * sc);
  set3(k, 3, d);
  set3(k, 6, c * sc);
  k.v[9] = rad * sc;
  finish(k, p);
  return k;
}

io::Case ell_generic(Rng& r, Precision p) {
  const double sc = r.pow2(-10, 10);
  const D3 c = rand_box(r, 2);
  const double sx = r.uniform(0.1, 3), sy = r.uniform(0.1, 3), sz = r.uniform(0.1, 3);
  const D3 s{sx, sy, sz};
  const double big = std::max({sx, sy, sz});
  const double dist = r.uniform(2.3, 10);  // beyond the aim (1.3 sqrt(3) < 2.3, scaled): never behind
  const D3 o = c + rand_unit(r) * (big * dist);
  const D3 u = rand_box(r, 1.3);
  const D3 aim = c + mul(u, s);
  io::Case k;
  k.kind = io::Kind::ellipsoid;
  set3(k, 0, o * sc);
  set3(k, 3, normalize(aim - o));
  set3(k, 6, c * sc);
  set3(k, 9, s * sc);
  finish(k, p);
  return k;
}

io::Case ell_tangent_exact(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return tangent_case(g, q, ellipsoid_surface(g, q)); });
}

io::Case ell_on_surface(Rng& r, Precision p) {
  return retry(r, p, [](Rng& g, Precision q) { return on_surface_case(g, q, ellipsoid_surface(g, q)); });
}

io::Case ell_stiff(Rng& r, Precision p) {
  const int lo = r.irange(-20, 0);
  const int spread = r.irange(10, 40);
  D3 s;
  for (std::size_t i = 0; i < 3; ++i) {
    const double m = r.chance(1, 2) ? 1.0 : r.uniform(1, 2);
    s[i] = std::ldexp(m, r.irange(lo, lo + spread));
  }
  // Make sure the full spread is present: one axis at each end.
  const std::size_t a = r.below(3);
  const std::size_t b = (a + 1 + r.below(2)) % 3;
  s[a] = std::ldexp(1.0, lo);
  s[b] = std::ldexp(1.0, lo + spread);
  const double big = std::max({s.x, s.y, s.z});
  const D3 c = rand_box(r, big);
  const double dist = r.uniform(2.1, 8);  // beyond the aim (1.2 sqrt(3) < 2.1, scaled): never behind
  const D3 o = c + rand_unit(r) * (big * dist);
  const D3 u = rand_box(r, 1.2);
  const D3 aim = c + mul(u, s);
  io::Case k;
  k.kind = io::Kind::ellipsoid;
  set3(k, 0, o);
  set3(k, 3, normalize(aim - o));
  set3(k, 6, c);
  set3(k, 9, s);
  finish(k, p);
  return k;
}

}  // namespace rayproof::gen::detail
