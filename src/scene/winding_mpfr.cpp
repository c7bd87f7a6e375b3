// The exact and high-precision stages of the generalized winding number (winding_tree.cpp has
// the derivations). A triangle the double evaluation cannot bound is decided here:
//  * orient3d(a, b, c, p) = 0 exactly (p on the triangle's plane; N = -orient3d): p on the closed
//    triangle is `surface`; elsewhere on the plane the triangle is seen edge-on and Omega = 0
//    exactly (zero-area triangles: always 0, never surface);
//  * otherwise N != 0, and the formula of winding_tree.cpp section 1 is evaluated in MPFR at
//    128, 256, 512, ... bits. Every MPFR operation is correctly rounded (relative error at most
//    u' = 2^-bits, no underflow in MPFR's exponent range), so the same bounds hold with u' for u:
//    en = 9u' P, ed = 72u' L, and the atan2 of MPFR errs by half an ulp (at most 2u' for a value
//    <= pi). Once the precision makes en + ed smaller than |N| (N != 0 exactly, so this happens),
//    the test passes and the angle is bounded.
#include <mpfr.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "exact/orient_exact.h"
#include "scene/exact_mesh_state.h"
#include "scene/winding_tree.h"

namespace rayproof::scene::detail {

namespace {

using certified::orient2d_exact;
using certified::orient3d_exact;

inline double coord(const Vec3<double>& p, int k) { return reinterpret_cast<const double*>(&p)[k]; }

/// An mpfr_t that clears itself.
struct Mp {
  mpfr_t v;
  explicit Mp(mpfr_prec_t prec) { mpfr_init2(v, prec); }
  ~Mp() { mpfr_clear(v); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;
  operator mpfr_ptr() { return v; }
  operator mpfr_srcptr() const { return v; }
};

/// Omega and its bound (rounded up) at precision `prec`; false when unresolved at this precision.
bool solid_angle_mpfr(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p,
                      mpfr_prec_t prec, mpfr_ptr omega, mpfr_ptr err) {
  constexpr mpfr_rnd_t N = MPFR_RNDN, U = MPFR_RNDU;
  Mp A[3] = {Mp(prec), Mp(prec), Mp(prec)}, B[3] = {Mp(prec), Mp(prec), Mp(prec)}, C[3] = {Mp(prec), Mp(prec), Mp(prec)};
  for (int k = 0; k < 3; ++k) {
    mpfr_set_d(A[k], coord(a, k), N);  // exact: prec >= 53
    mpfr_sub_d(A[k], A[k], coord(p, k), N);
    mpfr_set_d(B[k], coord(b, k), N);
    mpfr_sub_d(B[k], B[k], coord(p, k), N);
    mpfr_set_d(C[k], coord(c, k), N);
    mpfr_sub_d(C[k], C[k], coord(p, k), N);
  }
  Mp m1(prec), m2(prec), t(prec), n(prec), perm(prec), s(prec), u(prec);
  mpfr_set_zero(n, 1);
  mpfr_set_zero(perm, 1);
  // N = A . (B x C), P = sum |A_i| (|B_j C_k| + |B_k C_j|), with (i, j, k) cyclic.
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    mpfr_mul(m1, B[j], C[k], N);
    mpfr_mul(m2, B[k], C[j], N);
    mpfr_sub(t, m1, m2, N);
    mpfr_mul(t, t, A[i], N);
    mpfr_add(n, n, t, N);
    mpfr_abs(m1, m1, N);
    mpfr_abs(m2, m2, N);
    mpfr_add(t, m1, m2, N);
    mpfr_abs(s, A[i], N);
    mpfr_mul(t, t, s, N);
    mpfr_add(perm, perm, t, N);
  }
  Mp la(prec), lb(prec), lc(prec), l3(prec), d(prec);
  auto norm = [&](Mp (&V)[3], mpfr_ptr out) {
    mpfr_sqr(out, V[0], N);
    mpfr_sqr(t, V[1], N);
    mpfr_add(out, out, t, N);
    mpfr_sqr(t, V[2], N);
    mpfr_add(out, out, t, N);
    mpfr_sqrt(out, out, N);
  };
  norm(A, la);
  norm(B, lb);
  norm(C, lc);
  auto dot = [&](Mp (&X)[3], Mp (&Y)[3], mpfr_ptr out) {
    mpfr_mul(out, X[0], Y[0], N);
    mpfr_mul(t, X[1], Y[1], N);
    mpfr_add(out, out, t, N);
    mpfr_mul(t, X[2], Y[2], N);
    mpfr_add(out, out, t, N);
  };
  mpfr_mul(l3, la, lb, N);
  mpfr_mul(l3, l3, lc, N);
  mpfr_set(d, l3, N);
  dot(A, B, s);
  mpfr_mul(s, s, lc, N);
  mpfr_add(d, d, s, N);
  dot(B, C, s);
  mpfr_mul(s, s, la, N);
  mpfr_add(d, d, s, N);
  dot(C, A, s);
  mpfr_mul(s, s, lb, N);
  mpfr_add(d, d, s, N);
  // r = 9u' P + 72u' L, rounded up.
  Mp r(64), rho(prec), an(prec);
  mpfr_mul_ui(r, perm, 9, U);
  mpfr_mul_ui(u, l3, 72, U);
  mpfr_add(r, r, u, U);
  mpfr_div_2si(r, r, long(prec), U);
  mpfr_abs(an, n, N);
  mpfr_abs(rho, d, N);
  if (mpfr_cmp(an, rho) > 0) mpfr_set(rho, an, N);
  if (!(mpfr_cmp(rho, r) > 0) || !(mpfr_sgn(d.v) > 0 || mpfr_cmp(an, r) > 0)) return false;
  mpfr_atan2(omega, n, d, N);
  mpfr_mul_2ui(omega, omega, 1, N);
  // err = 3.2 r / rho + 4u' (rho rounded to nearest: the factor 3.2 > pi covers it).
  mpfr_set_prec(err, 64);
  mpfr_div(err, r, rho, U);
  mpfr_mul_d(err, err, 3.2, U);
  Mp ulp4(64);
  mpfr_set_ui_2exp(ulp4, 4, -long(prec), U);
  mpfr_add(err, err, ulp4, U);
  return true;
}

/// The resolved solid angle in MPFR (status 0 or 2), omega at precision >= 128 in `omega`.
int solid_angle_exact_mpfr(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& p,
                           mpfr_ptr omega, mpfr_ptr err) {
  if (orient3d_exact(a, b, c, p) == 0) {
    if (on_closed_triangle_exact(a, b, c, p)) return 2;
    mpfr_set_zero(omega, 1);
    mpfr_set_zero(err, 1);
    return 0;
  }
  for (mpfr_prec_t prec = std::max<mpfr_prec_t>(128, mpfr_get_prec(omega)); prec <= (mpfr_prec_t(1) << 20); prec *= 2) {
    mpfr_set_prec(omega, prec);
    if (solid_angle_mpfr(a, b, c, p, prec, omega, err)) return 0;
  }
  throw std::logic_error("solid angle: unresolved at 2^20 bits although orient3d != 0");
}

}  // namespace

bool on_closed_triangle_exact(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                              const Vec3<double>& p) {
  return orient3d_exact(a, b, c, p) == 0 && on_closed_triangle_coplanar(a, b, c, p);
}

SolidAngle solid_angle_resolved(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                const Vec3<double>& p) {
  Mp omega(128), err(64);
  if (solid_angle_exact_mpfr(a, b, c, p, omega, err) == 2) return {0, 0, 2};
  // To double: the rounding of omega (at most half an ulp of a value < 2 pi + 1: 2^-51) is added.
  SolidAngle out;
  out.omega = mpfr_get_d(omega, MPFR_RNDN);
  out.err = mpfr_get_d(err, MPFR_RNDU) + 0x1p-51;
  return out;
}

WindingValue winding_mpfr(std::span<const Vec3<double>> vertices,
                          std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p, int bits,
                          int* vs_half) {
  if (vs_half) *vs_half = 0;
  WindingValue out;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return out;
  if (bits < 64 || bits > 65536) throw std::invalid_argument("winding_brute_force_mpfr: bits outside [64, 65536]");
  const mpfr_prec_t prec = bits;
  constexpr mpfr_rnd_t N = MPFR_RNDN, U = MPFR_RNDU;
  Mp sum(prec), abs(prec), errs(64), omega(prec), err(64), x(prec);
  mpfr_set_zero(sum, 1);
  mpfr_set_zero(abs, 1);
  mpfr_set_zero(errs, 1);
  std::uint64_t k = 0;
  for (const auto& t : triangles) {
    if (t[0] >= vertices.size() || t[1] >= vertices.size() || t[2] >= vertices.size())
      throw std::out_of_range("winding_brute_force_mpfr: vertex index out of range");
    const Vec3<double>&a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    mpfr_set_prec(omega, prec);
    if (!solid_angle_mpfr(a, b, c, p, prec, omega, err)) {
      if (solid_angle_exact_mpfr(a, b, c, p, omega, err) == 2) {
        out.surface = true, out.bound = 0;
        return out;
      }
    }
    mpfr_add(sum, sum, omega, N);
    mpfr_abs(x, omega, N);
    mpfr_add(abs, abs, x, U);
    mpfr_add(errs, errs, err, U);
    ++k;
  }
  // |error of the sum| <= errs + k u' abs (each addition's relative error u' on a partial sum
  // <= abs, itself an upper bound); the omegas converted from higher precision were rounded into
  // the sum at this precision: covered by the same term.
  Mp e(64), pi(prec), w(prec), h(prec), b(64);
  mpfr_mul_ui(e, abs, (unsigned long)(k + 2), U);
  mpfr_div_2si(e, e, long(prec), U);
  mpfr_add(e, e, errs, U);
  mpfr_const_pi(pi, N);
  mpfr_mul_2ui(pi, pi, 2, N);
  mpfr_div(w, sum, pi, N);
  // w = sum / (4 pi) with 4 pi and the quotient rounded: |w_exact - w| <= e / (4 pi) (1 + 4u') + 3u' |w|.
  mpfr_const_pi(b, MPFR_RNDD);
  mpfr_mul_2ui(b, b, 2, MPFR_RNDD);
  mpfr_div(b, e, b, U);
  mpfr_mul_d(b, b, 1.0 + 0x1p-40, U);
  mpfr_abs(x, w, N);
  mpfr_mul_ui(x, x, 4, U);
  mpfr_div_2si(x, x, long(prec), U);
  mpfr_add(b, b, x, U);
  // Against 1/2 in MPFR (w as a double would round away a difference below 2^-54).
  mpfr_sub_d(h, w, 0.5, N);  // exact enough: h's own rounding is below u' |h|, covered by comparing with b (1 + 2^-40)
  mpfr_abs(x, h, MPFR_RNDD);
  mpfr_mul_d(x, x, 1.0 - 0x1p-40, MPFR_RNDD);
  if (vs_half && mpfr_cmp(x, b) > 0) *vs_half = mpfr_sgn(h.v) > 0 ? 1 : -1;
  out.w = mpfr_get_d(w, N);
  // The double w: add its rounding.
  mpfr_set_d(x, out.w, N);
  mpfr_sub(x, x, w, U);
  mpfr_abs(x, x, U);
  mpfr_add(b, b, x, U);
  out.bound = mpfr_get_d(b, U);
  return out;
}

}  // namespace rayproof::scene::detail

namespace rayproof {

WindingValue winding_brute_force_mpfr(std::span<const Vec3<double>> vertices,
                                      std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p,
                                      int bits) {
  return scene::detail::winding_mpfr(vertices, triangles, p, bits, nullptr);
}

}  // namespace rayproof
