// The orientation signs in GMP: every finite double is an integer times a power of two, so the
// inputs of one determinant, scaled by the power of two of the smallest exponent among them, are
// integers (a positive scale keeps the sign), and integer sums and products are exact, so the sign
// is exact for any exponents (no rational normalisation, whose gcds cost most of the time). The
// value (orient3d_value_gmp) and any non-finite input take rationals (mpq_set_d).
#include <gmpxx.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

#include "exact/orient_exact.h"

namespace rayproof::certified {

namespace {
int sgn_q(const mpq_class& x) { return mpq_sgn(x.get_mpq_t()); }

/// The doubles x[0..N) (finite) as integers X[k] = x[k] * 2^-E, E the least exponent of a nonzero
/// one's last mantissa bit: each x[k] = m * 2^e with m an integer of at most 53 bits.
template <int N>
bool to_integers(const double (&x)[N], mpz_class (&out)[N]) {
  std::int64_t m[N];
  int e[N], least = INT_MAX;
  for (int k = 0; k < N; ++k) {
    if (!std::isfinite(x[k])) return false;
    m[k] = 0, e[k] = 0;
    if (x[k] == 0) continue;
    int ex = 0;
    const double f = std::frexp(x[k], &ex);  // x = f 2^ex, 1/2 <= |f| < 1 (subnormals too)
    m[k] = static_cast<std::int64_t>(std::ldexp(f, 53)), e[k] = ex - 53;
    least = std::min(least, e[k]);
  }
  for (int k = 0; k < N; ++k) {
    out[k] = static_cast<long>(m[k]);
    if (m[k] != 0) mpz_mul_2exp(out[k].get_mpz_t(), out[k].get_mpz_t(), static_cast<mp_bitcnt_t>(e[k] - least));
  }
  return true;
}

int sgn_z(const mpz_class& x) {
  const int s = mpz_sgn(x.get_mpz_t());
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

int orient2d_q(double au, double av, double bu, double bv, double pu, double pv) {
  const mpq_class du = mpq_class(bu) - mpq_class(au), dv = mpq_class(bv) - mpq_class(av);
  const mpq_class eu = mpq_class(pu) - mpq_class(au), ev = mpq_class(pv) - mpq_class(av);
  const mpq_class det = du * ev - dv * eu;
  const int s = sgn_q(det);
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}
}  // namespace

int orient2d_gmp(double au, double av, double bu, double bv, double pu, double pv) {
  const double x[6] = {au, av, bu, bv, pu, pv};
  mpz_class z[6];
  if (!to_integers(x, z)) return orient2d_q(au, av, bu, bv, pu, pv);
  const mpz_class du = z[2] - z[0], dv = z[3] - z[1], eu = z[4] - z[0], ev = z[5] - z[1];
  return sgn_z(mpz_class(du * ev) - mpz_class(dv * eu));
}

namespace {
mpq_class orient3d_q(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p) {
  auto d = [](double x, double y) { return mpq_class(mpq_class(x) - mpq_class(y)); };
  const mpq_class ux = d(b.x, a.x), uy = d(b.y, a.y), uz = d(b.z, a.z);
  const mpq_class vx = d(c.x, a.x), vy = d(c.y, a.y), vz = d(c.z, a.z);
  const mpq_class wx = d(p.x, a.x), wy = d(p.y, a.y), wz = d(p.z, a.z);
  const mpq_class det = mpq_class(wx * mpq_class(uy * vz - uz * vy)) + mpq_class(wy * mpq_class(uz * vx - ux * vz)) +
                        mpq_class(wz * mpq_class(ux * vy - uy * vx));
  return det;
}
}  // namespace

int orient3d_gmp(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p) {
  const double x[12] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, p.x, p.y, p.z};
  mpz_class z[12];
  if (!to_integers(x, z)) {
    const int s = sgn_q(orient3d_q(a, b, c, p));
    return s > 0 ? 1 : (s < 0 ? -1 : 0);
  }
  const mpz_class ux = z[3] - z[0], uy = z[4] - z[1], uz = z[5] - z[2];
  const mpz_class vx = z[6] - z[0], vy = z[7] - z[1], vz = z[8] - z[2];
  const mpz_class wx = z[9] - z[0], wy = z[10] - z[1], wz = z[11] - z[2];
  const mpz_class det = mpz_class(wx * mpz_class(uy * vz - uz * vy)) + mpz_class(wy * mpz_class(uz * vx - ux * vz)) +
                        mpz_class(wz * mpz_class(ux * vy - uy * vx));
  return sgn_z(det);
}

double orient3d_value_gmp(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p) {
  return orient3d_q(a, b, c, p).get_d();
}

}  // namespace rayproof::certified
