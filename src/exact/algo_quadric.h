#pragma once
/// Exact ray/sphere and ray/ellipsoid, on a kernel K (algo_kernel.h): the ray substituted
/// into the implicit surface gives a t^2 + 2 b t + c = 0 with rational a > 0, b, c. Predicates
/// decide the class from the signs of the discriminant disc = b^2 - a c, of c (product of the
/// roots) and of b (minus their sum), without square roots. Constructions: a root (-b -+
/// sqrt(disc)) / a is approximated with MPFR at 256 bits, then rounded to nearest by
/// round_by_comparison, whose comparisons with rationals are decided exactly by squaring (with the
/// signs handled first).
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "exact/algo_kernel.h"
#include "exact/rounding.h"

namespace rayproof::exact_algo {

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

}  // namespace rayproof::exact_algo
