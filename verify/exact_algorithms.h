#pragma once
/// The exact ray/primitive algorithm, written once and templated on a kernel K (the number type and
/// the few point/vector operations it uses). Instantiated twice:
///  - the ground truth, rayproof::exact::intersect (exact_cgal.cpp, in rayproof_verify): K over
///    CGAL's Simple_cartesian<Gmpq> (Point_3, Vector_3, CGAL::determinant, CGAL::cross_product);
///  - the certified tier's fallback, rayproof::certified::fallback::intersect (fallback.cpp, in
///    rayproof_certified): K over gmpxx's mpq_class and a small vector of them, no CGAL.
/// The MPFR rounding (exact_rounding.h) is one shared code. So the two differ only in the number
/// type and the vector operations; exact_crosscheck_test checks that they agree bit for bit.
/// This header includes neither CGAL nor gmpxx.
///
/// Contract (CASES.md): the class of exact arithmetic on the input doubles; t, t2 and the triangle
/// barycentrics b1, b2 rounded to nearest (ties to even, signs of zeros included); NaN for fields a
/// class does not carry. Every finite double is a rational, so inputs convert exactly; NaN and
/// infinities are screened out first (`invalid`), then zero sizes (`degenerate`).
///
/// What K provides (all static; Q results may be taken by value or const reference):
///   Q, Point, Vector        types; Q(double) exact; Q + - * / Q, unary -, <, ==, +=, each
///                           convertible to Q; Point - Point and Vector + Vector -> Vector;
///                           Q * Vector -> Vector
///   point(v), vector(v)     a Vec3<double> (finite) as an exact Point / Vector
///   dot(v, w), cross(v, w), det(u, v, w) = u . (v x w), is_zero(v), coord(v, i) (i = 0, 1, 2)
///   sign(q)                 -1, 0 or +1
///   mpq(q)                  the GMP rational behind q (mpq_srcptr), for the MPFR rounding
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>

#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"
#include "rayproof/vec3.h"
#include "verify/exact_rounding.h"

namespace rayproof::exact_algo {

/// q rounded to nearest double (shared MPFR code).
template <class K>
[[nodiscard]] double rounded(const typename K::Q& q) {
  return round_nearest(K::mpq(q));
}

/// num / den (den != 0) rounded to nearest.
template <class K>
[[nodiscard]] double rounded_quotient(const typename K::Q& num, const typename K::Q& den) {
  const typename K::Q q = num / den;
  return rounded<K>(q);
}

// ---------------------------------------------------------------------------------------------
// Plane and disk. Predicates: d . n = 0 (parallel or coplanar by (p - o) . n); t = (p - o) . n /
// (d . n) has the sign of the product of the two signs; the disk test compares |P - c|^2 with r^2
// at the plane point P, scaled by (d . n)^2 so that no division is needed. Construction: t rounded.

/// The ray against the plane through `on` with normal n (n != 0).
template <class K>
struct PlaneCrossing {
  typename K::Q num, den;  ///< t = num / den; den = d . n
  [[nodiscard]] int side() const { return K::sign(num) * K::sign(den); }  ///< sign of t (den != 0)
};

template <class K>
[[nodiscard]] PlaneCrossing<K> cross_plane(const typename K::Point& o, const typename K::Vector& d,
                                           const typename K::Point& on, const typename K::Vector& n) {
  return {K::dot(on - o, n), K::dot(d, n)};
}

/// parallel / coplanar for a ray with d . n = 0.
template <class K>
[[nodiscard]] Hit<double> in_or_off_plane(const PlaneCrossing<K>& x) {
  return {K::sign(x.num) == 0 ? Contact::coplanar : Contact::parallel};
}

template <class K>
[[nodiscard]] Hit<double> plane(const Ray<double>& ray, const Plane<double>& pl) {
  const PlaneCrossing<K> x = cross_plane<K>(K::point(ray.o), K::vector(ray.d), K::point(pl.point), K::vector(pl.normal));
  if (K::sign(x.den) == 0) return in_or_off_plane(x);
  const double t = rounded_quotient<K>(x.num, x.den);
  return {x.side() < 0 ? Contact::behind : Contact::hit, t};
}

template <class K>
[[nodiscard]] Hit<double> disk(const Ray<double>& ray, const Disk<double>& dk) {
  using Q = typename K::Q;
  using Vector = typename K::Vector;
  const typename K::Point o = K::point(ray.o), center = K::point(dk.center);
  const Vector d = K::vector(ray.d);
  const PlaneCrossing<K> x = cross_plane<K>(o, d, center, K::vector(dk.normal));
  if (K::sign(x.den) == 0) return in_or_off_plane(x);
  // den (P - center) = den (o - center) + num d, so |P - c|^2 vs r^2 <=> |that|^2 vs r^2 den^2.
  const Vector w = x.den * (o - center) + x.num * d;
  const Q r(dk.radius);
  const Q excess = K::dot(w, w) - r * r * x.den * x.den;
  const int outside = K::sign(excess);
  if (outside > 0) return {Contact::miss};
  const double t = rounded_quotient<K>(x.num, x.den);
  if (x.side() < 0) return {Contact::behind, t};
  return {outside == 0 ? Contact::rim : Contact::hit, t};
}

// ---------------------------------------------------------------------------------------------
// Sphere and ellipsoid: the ray substituted into the implicit surface gives a t^2 + 2 b t + c = 0
// with rational a > 0, b, c. Predicates decide the class from the signs of the discriminant
// disc = b^2 - a c, of c (product of the roots) and of b (minus their sum), without square roots.
// Constructions: a root (-b -+ sqrt(disc)) / a is approximated with MPFR at 256 bits, then rounded
// to nearest by round_by_comparison, whose comparisons with rationals are decided exactly by
// squaring (with the signs handled first).

template <class K>
struct Quadratic {
  typename K::Q a, b, c;  ///< a t^2 + 2 b t + c, a > 0
};

/// Sign of x - m for the root x = (-b + s sqrt(disc)) / a (s = -1: lower, +1: upper), disc > 0.
/// With r = a m + b, x - m has the sign of s sqrt(disc) - r.
template <class K>
[[nodiscard]] int root_sign_vs(const Quadratic<K>& q, const typename K::Q& disc, int s, const typename K::Q& m) {
  using Q = typename K::Q;
  const Q r = q.a * m + q.b;
  const int sr = K::sign(r);
  if (s > 0) {  // sqrt(disc) - r, r >= 0: compare squares
    if (sr < 0) return 1;
    const Q diff = disc - r * r;
    return K::sign(diff);
  }
  if (sr >= 0) return -1;  // |r| - sqrt(disc), r < 0
  const Q diff = r * r - disc;
  return K::sign(diff);
}

template <class K>
[[nodiscard]] Hit<double> solve(const Quadratic<K>& q) {
  using Q = typename K::Q;
  const Q disc = q.b * q.b - q.a * q.c;
  const int sd = K::sign(disc), sb = K::sign(q.b), sc = K::sign(q.c);
  if (sd < 0) return {Contact::miss};
  if (sd == 0) {  // double root -b / a, behind when b > 0 (t = 0 when b = 0 is a tangent at 0.0)
    const Q minus_b = -q.b;
    const double t = rounded_quotient<K>(minus_b, q.a);
    return {sb > 0 ? Contact::behind : Contact::tangent, t, t};
  }
  if (sc == 0) {  // roots 0 and -2b / a (b != 0 since disc = b^2 > 0)
    const Q minus_2b = Q(-2) * q.b;
    const double other = rounded_quotient<K>(minus_2b, q.a);
    // The zero root is the upper one when b > 0; the reference computes it as c / k with k < 0,
    // which is -0.0. As the lower root (b < 0) it is c / k with k > 0: +0.0.
    if (sb > 0) return {Contact::inside, other, -0.0};
    return {Contact::hit, 0.0, other};
  }
  // Product of the roots has the sign of c, their sum the sign of -b (sb != 0 when c > 0).
  const Contact contact = sc < 0 ? Contact::inside : (sb > 0 ? Contact::behind : Contact::hit);
  const RootPair guess = approximate_roots(K::mpq(q.a), K::mpq(q.b), K::mpq(q.c), K::mpq(disc));
  const double lower = round_by_comparison<Q>(guess.lower, [&](const Q& m) { return root_sign_vs(q, disc, -1, m); });
  const double upper = round_by_comparison<Q>(guess.upper, [&](const Q& m) { return root_sign_vs(q, disc, 1, m); });
  return {contact, lower, upper};
}

template <class K>
[[nodiscard]] Hit<double> sphere(const Ray<double>& ray, const Sphere<double>& s) {
  using Q = typename K::Q;
  // |o + t d - center|^2 = r^2 with e = o - center.
  const typename K::Vector d = K::vector(ray.d);
  const typename K::Vector e = K::point(ray.o) - K::point(s.center);
  const Q r(s.radius);
  const Q c = K::dot(e, e) - r * r;
  return solve(Quadratic<K>{K::dot(d, d), K::dot(d, e), c});
}

template <class K>
[[nodiscard]] Hit<double> ellipsoid(const Ray<double>& ray, const Ellipsoid<double>& el) {
  using Q = typename K::Q;
  // sum_i (e_i + t d_i)^2 / s_i^2 = 1, times P = s_0^2 s_1^2 s_2^2 (> 0): weights w_i = P / s_i^2.
  const typename K::Vector d = K::vector(ray.d);
  const typename K::Vector e = K::point(ray.o) - K::point(el.center);
  const Q s0(el.semi_axes.x), s1(el.semi_axes.y), s2(el.semi_axes.z);
  const Q q0 = s0 * s0, q1 = s1 * s1, q2 = s2 * s2;
  const Q w[3] = {q1 * q2, q0 * q2, q0 * q1};
  const Q c0 = -(q0 * w[0]);
  Quadratic<K> q{Q(0), Q(0), c0};
  for (int i = 0; i < 3; ++i) {
    const Q di = K::coord(d, i), ei = K::coord(e, i);
    q.a += w[i] * di * di;
    q.b += w[i] * di * ei;
    q.c += w[i] * ei * ei;
  }
  return solve(q);
}

// ---------------------------------------------------------------------------------------------
// Axis-aligned box: the slab test (Kay & Kajiya) in rationals. An axis with d_i = 0 bounds nothing
// when lo_i <= o_i <= hi_i and misses otherwise; the others bound t by (lo_i - o_i) / d_i and
// (hi_i - o_i) / d_i. Entry T = the largest lower bound, exit T2 = the smallest upper bound,
// compared exactly; both rounded to nearest.

template <class K>
[[nodiscard]] Hit<double> box(const Ray<double>& ray, const Box<double>& bx) {
  using Q = typename K::Q;
  constexpr Hit<double> kMiss{Contact::miss};
  std::optional<Q> enter, exit;  // d != 0, so at least one axis sets both
  for (std::size_t i = 0; i < 3; ++i) {
    const double o = ray.o[i], d = ray.d[i], lo = bx.lo[i], hi = bx.hi[i];
    if (d == 0) {  // comparisons of doubles are exact
      if (o < lo || o > hi) return kMiss;
      continue;
    }
    const Q qo(o), qd(d);
    Q t_near = (Q(lo) - qo) / qd, t_far = (Q(hi) - qo) / qd;
    if (d < 0) std::swap(t_near, t_far);
    if (!enter || *enter < t_near) enter = t_near;
    if (!exit || t_far < *exit) exit = t_far;
  }
  if (*exit < *enter) return kMiss;
  const double t_enter = rounded<K>(*enter), t_exit = rounded<K>(*exit);
  if (K::sign(*exit) < 0) return {Contact::behind, t_enter, t_exit};
  if (K::sign(*enter) < 0) return {Contact::inside, t_enter, t_exit};
  return {*enter == *exit ? Contact::graze : Contact::hit, t_enter, t_exit};
}

// ---------------------------------------------------------------------------------------------
// Triangle (closed). Predicates: n = (p1 - p0) x (p2 - p0) decides degeneracy; d . n and
// (p0 - o) . n decide parallel / coplanar; for a crossing line, the barycentrics of the plane point
// are u_i / (d . n) with u_i = det(d, p_j - o, p_k - o) (edges p1p2, p2p0, p0p1), which sum to
// d . n, so their signs and zeros are exact. Constructions: t = (p0 - o) . n / (d . n) and, for a
// contact (interior, edge, vertex, behind), b1 = u_1 / (d . n) and b2 = u_2 / (d . n), each rounded
// to nearest. A ray in the plane is clipped against the three closed edge half-planes, exactly.

/// Range of t >= 0 with o + t d in the closed triangle, for a ray lying in its plane. Edge j -> k
/// keeps the points P with det(p_k - p_j, P - p_j, n) >= 0 (the side of the third vertex, where
/// the determinant is n . n > 0); along the ray that is alpha + t beta >= 0, linear in t.
template <class K>
[[nodiscard]] TriangleHit<double> coplanar_range(const typename K::Point& o, const typename K::Vector& d,
                                                 const typename K::Point (&p)[3], const typename K::Vector& n) {
  using Q = typename K::Q;
  constexpr TriangleHit<double> kNone{Contact::coplanar};
  Q lo(0);
  std::optional<Q> hi;
  for (int j = 0; j < 3; ++j) {
    const int k = (j + 1) % 3;
    const typename K::Vector edge = p[k] - p[j];
    const Q alpha = K::det(edge, o - p[j], n);
    const Q beta = K::det(edge, d, n);
    if (K::sign(beta) == 0) {
      if (K::sign(alpha) < 0) return kNone;  // the ray runs outside this edge's line
      continue;
    }
    const Q minus_alpha = -alpha;
    const Q bound = minus_alpha / beta;
    if (K::sign(beta) > 0) {
      if (lo < bound) lo = bound;
    } else if (!hi || bound < *hi) {
      hi = bound;
    }
  }
  // d is not parallel to all three edges, and the betas sum to 0, so some beta < 0 set hi.
  if (!hi || *hi < lo) return kNone;
  return {Contact::coplanar, rounded<K>(lo), rounded<K>(*hi)};
}

template <class K>
[[nodiscard]] TriangleHit<double> triangle(const Ray<double>& ray, const Triangle<double>& tri) {
  using Q = typename K::Q;
  using Point = typename K::Point;
  const Point o = K::point(ray.o);
  const typename K::Vector d = K::vector(ray.d);
  const Point p[3] = {K::point(tri.p0), K::point(tri.p1), K::point(tri.p2)};
  const typename K::Vector n = K::cross(p[1] - p[0], p[2] - p[0]);
  if (K::is_zero(n)) return {Contact::degenerate};

  const Q den = K::dot(d, n);
  const Q num = K::dot(p[0] - o, n);
  const int s_den = K::sign(den);
  if (s_den == 0) {
    if (K::sign(num) != 0) return {Contact::parallel};
    return coplanar_range<K>(o, d, p, n);
  }

  // Barycentric i has the sign of u_i * den; u_2 follows from the sum.
  const Q u0 = K::det(d, p[1] - o, p[2] - o);
  const Q u1 = K::det(d, p[2] - o, p[0] - o);
  const Q u2 = den - u0 - u1;
  const int b[3] = {K::sign(u0) * s_den, K::sign(u1) * s_den, K::sign(u2) * s_den};
  if (b[0] < 0 || b[1] < 0 || b[2] < 0) return {Contact::miss};

  const double t = rounded_quotient<K>(num, den);
  const double b1 = rounded_quotient<K>(u1, den), b2 = rounded_quotient<K>(u2, den);
  if (K::sign(num) * s_den < 0) return {Contact::behind, t, kNaN<double>, b1, b2};
  const int zeros = (b[0] == 0) + (b[1] == 0) + (b[2] == 0);
  const Contact contact = zeros == 0 ? Contact::interior : (zeros == 1 ? Contact::edge : Contact::vertex);
  return {contact, t, kNaN<double>, b1, b2};
}

// ---------------------------------------------------------------------------------------------
// The entry: the screening of CASES.md (invalid, then degenerate), on the doubles themselves, which
// is exact; then the algorithm of the kind. Only the triangle's degeneracy (collinear vertices)
// needs exact arithmetic and is decided by triangle<K> itself.

namespace screen {

inline bool finite_all(double x) { return std::isfinite(x); }
inline bool finite_all(const Vec3<double>& v) { return all_finite(v); }
template <class... A>
bool finite_all(const A&... a) { return (finite_all(a) && ...); }

/// NaN or infinite origin or direction, or d = 0.
inline bool bad_ray(const Ray<double>& r) { return !finite_all(r.o, r.d) || is_zero(r.d); }
inline bool any_negative(const Vec3<double>& v) { return v.x < 0 || v.y < 0 || v.z < 0; }
inline bool any_zero(const Vec3<double>& v) { return v.x == 0 || v.y == 0 || v.z == 0; }

inline constexpr Hit<double> kInvalid{Contact::invalid};
inline constexpr Hit<double> kDegenerate{Contact::degenerate};

}  // namespace screen

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Plane<double>& pl) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(pl.point, pl.normal)) return kInvalid;
  if (is_zero(pl.normal)) return kDegenerate;
  return plane<K>(ray, pl);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(s.center, s.radius) || s.radius < 0) return kInvalid;
  if (s.radius == 0) return kDegenerate;
  return sphere<K>(ray, s);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(e.center, e.semi_axes) || any_negative(e.semi_axes)) return kInvalid;
  if (any_zero(e.semi_axes)) return kDegenerate;
  return ellipsoid<K>(ray, e);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(b.lo, b.hi) || b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z) return kInvalid;
  return box<K>(ray, b);
}

template <class K>
[[nodiscard]] Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(dk.center, dk.normal, dk.radius) || dk.radius < 0) return kInvalid;
  if (is_zero(dk.normal) || dk.radius == 0) return kDegenerate;
  return disk<K>(ray, dk);
}

template <class K>
[[nodiscard]] TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) {
  using namespace screen;
  if (bad_ray(ray) || !finite_all(tri.p0, tri.p1, tri.p2)) return {Contact::invalid};
  return triangle<K>(ray, tri);  // collinear vertices: degenerate, decided exactly
}

}  // namespace rayproof::exact_algo
