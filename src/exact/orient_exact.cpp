// The orientation signs in GMP rationals: every finite double converts exactly (mpq_set_d), sums
// and products of rationals are exact, so the sign is exact for any exponents.
#include <gmpxx.h>

#include "exact/orient_exact.h"

namespace rayproof::certified {

namespace {
int sgn_q(const mpq_class& x) { return mpq_sgn(x.get_mpq_t()); }
}  // namespace

int orient2d_gmp(double au, double av, double bu, double bv, double pu, double pv) {
  const mpq_class du = mpq_class(bu) - mpq_class(au), dv = mpq_class(bv) - mpq_class(av);
  const mpq_class eu = mpq_class(pu) - mpq_class(au), ev = mpq_class(pv) - mpq_class(av);
  const mpq_class det = du * ev - dv * eu;
  const int s = sgn_q(det);
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
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
  const int s = sgn_q(orient3d_q(a, b, c, p));
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

double orient3d_value_gmp(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p) {
  return orient3d_q(a, b, c, p).get_d();
}

}  // namespace rayproof::certified
