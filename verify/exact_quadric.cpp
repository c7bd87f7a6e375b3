/// Exact ray/sphere and ray/ellipsoid: the ray substituted into the implicit surface gives
/// a t^2 + 2 b t + c = 0 with rational a > 0, b, c. Predicates decide the class from the signs of
/// the discriminant disc = b^2 - a c, of c (product of the roots) and of b (minus their sum),
/// without square roots. Constructions: a root (-b -+ sqrt(disc)) / a is approximated with MPFR
/// at 256 bits, then rounded to nearest by round_by_comparison, whose comparisons with rationals
/// are decided exactly by squaring (with the signs handled first).
#include <mpfr.h>

#include "verify/exact_kinds.h"
#include "verify/exact_number.h"
#include "verify/exact_rounding.h"

namespace rayproof::verify {

namespace {

struct Quadratic {
  Q a, b, c;  ///< a t^2 + 2 b t + c, a > 0
};

/// Sign of x - m for the root x = (-b + s sqrt(disc)) / a (s = -1: lower, +1: upper), disc > 0.
/// With r = a m + b, x - m has the sign of s sqrt(disc) - r.
int root_sign_vs(const Quadratic& q, const Q& disc, int s, const Q& m) {
  const Q r = q.a * m + q.b;
  const int sr = sign(r);
  if (s > 0) return sr < 0 ? 1 : sign(disc - r * r);  // sqrt(disc) - r, r >= 0: compare squares
  return sr >= 0 ? -1 : sign(r * r - disc);           // |r| - sqrt(disc), r < 0
}

struct RootPair {
  double lower, upper;
};

/// Both roots to about 250 bits by the cancellation-free form: k = -(b + sign(b) sqrt(disc)),
/// roots k / a and c / k. Only a starting point for round_by_comparison.
RootPair approximate_roots(const Quadratic& q, const Q& disc) {
  constexpr mpfr_prec_t kPrec = 256;
  mpfr_t a, b, c, k, r1, r2;
  mpfr_inits2(kPrec, a, b, c, k, r1, r2, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_q(a, q.a.mpq(), MPFR_RNDN);
  mpfr_set_q(b, q.b.mpq(), MPFR_RNDN);
  mpfr_set_q(c, q.c.mpq(), MPFR_RNDN);
  mpfr_set_q(k, disc.mpq(), MPFR_RNDN);
  mpfr_sqrt(k, k, MPFR_RNDN);
  if (sign(q.b) >= 0) mpfr_add(k, b, k, MPFR_RNDN);
  else mpfr_sub(k, b, k, MPFR_RNDN);
  mpfr_neg(k, k, MPFR_RNDN);  // k != 0: |k| >= sqrt(disc) > 0
  mpfr_div(r1, k, a, MPFR_RNDN);
  mpfr_div(r2, c, k, MPFR_RNDN);
  const double d1 = mpfr_get_d(r1, MPFR_RNDN), d2 = mpfr_get_d(r2, MPFR_RNDN);
  mpfr_clears(a, b, c, k, r1, r2, static_cast<mpfr_ptr>(nullptr));
  // b >= 0: k < 0, so k / a is the lower root; b < 0: k > 0 and k / a is the upper one.
  return sign(q.b) >= 0 ? RootPair{d1, d2} : RootPair{d2, d1};
}

Hit<double> solve(const Quadratic& q) {
  const Q disc = q.b * q.b - q.a * q.c;
  const int sd = sign(disc), sb = sign(q.b), sc = sign(q.c);
  if (sd < 0) return {Contact::miss};
  if (sd == 0) {  // double root -b / a, behind when b > 0 (t = 0 when b = 0 is a tangent at 0.0)
    const double t = round_nearest(-q.b / q.a);
    return {sb > 0 ? Contact::behind : Contact::tangent, t, t};
  }
  if (sc == 0) {  // roots 0 and -2b / a (b != 0 since disc = b^2 > 0)
    const double other = round_nearest(Q(-2) * q.b / q.a);
    // The zero root is the upper one when b > 0; the reference computes it as c / k with k < 0,
    // which is -0.0. As the lower root (b < 0) it is c / k with k > 0: +0.0.
    if (sb > 0) return {Contact::inside, other, -0.0};
    return {Contact::hit, 0.0, other};
  }
  // Product of the roots has the sign of c, their sum the sign of -b (sb != 0 when c > 0).
  const Contact contact = sc < 0 ? Contact::inside : (sb > 0 ? Contact::behind : Contact::hit);
  const RootPair guess = approximate_roots(q, disc);
  const double lower = round_by_comparison(guess.lower, [&](const Q& m) { return root_sign_vs(q, disc, -1, m); });
  const double upper = round_by_comparison(guess.upper, [&](const Q& m) { return root_sign_vs(q, disc, 1, m); });
  return {contact, lower, upper};
}

}  // namespace

Hit<double> exact_sphere(const Ray<double>& ray, const Sphere<double>& s) {
  // |o + t d - center|^2 = r^2 with e = o - center.
  const Vector d = vector_of(ray.d);
  const Vector e = point_of(ray.o) - point_of(s.center);
  const Q r(s.radius);
  return solve({d * d, d * e, e * e - r * r});
}

Hit<double> exact_ellipsoid(const Ray<double>& ray, const Ellipsoid<double>& el) {
  // sum_i (e_i + t d_i)^2 / s_i^2 = 1, times P = s_0^2 s_1^2 s_2^2 (> 0): weights w_i = P / s_i^2.
  const Vector d = vector_of(ray.d);
  const Vector e = point_of(ray.o) - point_of(el.center);
  const Q s0(el.semi_axes.x), s1(el.semi_axes.y), s2(el.semi_axes.z);
  const Q q0 = s0 * s0, q1 = s1 * s1, q2 = s2 * s2;
  const Q w[3] = {q1 * q2, q0 * q2, q0 * q1};
  Quadratic q{Q(0), Q(0), -(q0 * w[0])};
  for (int i = 0; i < 3; ++i) {
    q.a += w[i] * d[i] * d[i];
    q.b += w[i] * d[i] * e[i];
    q.c += w[i] * e[i] * e[i];
  }
  return solve(q);
}

}  // namespace rayproof::verify
