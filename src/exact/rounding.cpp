/// Correct rounding of rationals to double by MPFR's IEEE-emulation idiom (MPFR manual,
/// mpfr_subnormalize): round to 53 bits with the exponent range of binary64, then re-round the
/// subnormal range using the ternary value, which avoids double rounding. And the MPFR
/// approximation of quadric roots. On GMP's mpq_t: one code for both instantiations of the exact
/// algorithm (compiled into rayproof_certified, which rayproof_verify links).
#include "exact/rounding.h"

#include <mpfr.h>

namespace rayproof::exact_algo {

namespace {

/// Restricts MPFR's exponent range to binary64's (MPFR exponents: x = 0.1b... * 2^e, so
/// DBL_MAX has e = 1024 and the least subnormal 2^-1074 has e = -1073) for its lifetime.
class Binary64ExponentRange {
 public:
  Binary64ExponentRange() : emin_(mpfr_get_emin()), emax_(mpfr_get_emax()) {
    mpfr_set_emin(-1073);
    mpfr_set_emax(1024);
  }
  ~Binary64ExponentRange() {
    mpfr_set_emin(emin_);
    mpfr_set_emax(emax_);
  }
  Binary64ExponentRange(const Binary64ExponentRange&) = delete;
  Binary64ExponentRange& operator=(const Binary64ExponentRange&) = delete;

 private:
  mpfr_exp_t emin_, emax_;
};

}  // namespace

double round_nearest(mpq_srcptr q) {
  const Binary64ExponentRange range;
  mpfr_t r;
  mpfr_init2(r, 53);
  int inexact = mpfr_set_q(r, q, MPFR_RNDN);           // correctly rounded, over/underflow in range
  inexact = mpfr_subnormalize(r, inexact, MPFR_RNDN);  // subnormal precision, no double rounding
  const double d = mpfr_get_d(r, MPFR_RNDN);           // exact: r is now a binary64 value
  mpfr_clear(r);
  return d;
}

RootPair approximate_roots(mpq_srcptr qa, mpq_srcptr qb, mpq_srcptr qc, mpq_srcptr disc) {
  constexpr mpfr_prec_t kPrec = 256;
  mpfr_t a, b, c, k, r1, r2;
  mpfr_inits2(kPrec, a, b, c, k, r1, r2, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_q(a, qa, MPFR_RNDN);
  mpfr_set_q(b, qb, MPFR_RNDN);
  mpfr_set_q(c, qc, MPFR_RNDN);
  mpfr_set_q(k, disc, MPFR_RNDN);
  mpfr_sqrt(k, k, MPFR_RNDN);
  const bool b_nonnegative = mpq_sgn(qb) >= 0;
  if (b_nonnegative) mpfr_add(k, b, k, MPFR_RNDN);
  else mpfr_sub(k, b, k, MPFR_RNDN);
  mpfr_neg(k, k, MPFR_RNDN);  // k != 0: |k| >= sqrt(disc) > 0
  mpfr_div(r1, k, a, MPFR_RNDN);
  mpfr_div(r2, c, k, MPFR_RNDN);
  const double d1 = mpfr_get_d(r1, MPFR_RNDN), d2 = mpfr_get_d(r2, MPFR_RNDN);
  mpfr_clears(a, b, c, k, r1, r2, static_cast<mpfr_ptr>(nullptr));
  // b >= 0: k < 0, so k / a is the lower root; b < 0: k > 0 and k / a is the upper one.
  return b_nonnegative ? RootPair{d1, d2} : RootPair{d2, d1};
}

}  // namespace rayproof::exact_algo
