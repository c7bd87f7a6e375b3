/// Correct rounding of rationals to double by MPFR's IEEE-emulation idiom (MPFR manual,
/// mpfr_subnormalize): round to 53 bits with the exponent range of binary64, then re-round the
/// subnormal range using the ternary value, which avoids double rounding.
#include "verify/exact_rounding.h"

#include <mpfr.h>

namespace rayproof::verify {

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

double round_nearest(const Q& q) {
  const Binary64ExponentRange range;
  mpfr_t r;
  mpfr_init2(r, 53);
  int inexact = mpfr_set_q(r, q.mpq(), MPFR_RNDN);     // correctly rounded, over/underflow in range
  inexact = mpfr_subnormalize(r, inexact, MPFR_RNDN);  // subnormal precision, no double rounding
  const double d = mpfr_get_d(r, MPFR_RNDN);           // exact: r is now a binary64 value
  mpfr_clear(r);
  return d;
}

Q interval_value(double x) {
  if (!std::isinf(x)) return Q(x);
  const Q two1024 = Q(std::ldexp(1.0, 1023)) * Q(2);
  return x < 0 ? -two1024 : two1024;
}

Q midpoint(double a, double b) { return (interval_value(a) + interval_value(b)) / Q(2); }

}  // namespace rayproof::verify
