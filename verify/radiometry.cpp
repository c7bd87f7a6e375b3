#include "verify/radiometry.h"

#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/core.h>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace rayproof::verify {

namespace {

// ---------------------------------------------------------------------------------------------
// Interval arithmetic over MPFR: lower ends rounded down, upper ends rounded up, so every result
// encloses the exact value of the operation on any points of its operands.

constexpr mpfr_prec_t kPrec = 256;

class Iv {
 public:
  Iv() {
    mpfr_init2(lo_, kPrec);
    mpfr_init2(hi_, kPrec);
    mpfr_set_zero(lo_, 1);
    mpfr_set_zero(hi_, 1);
  }
  explicit Iv(double x) : Iv() {
    mpfr_set_d(lo_, x, MPFR_RNDN);  // exact: 256 >= 53 bits
    mpfr_set_d(hi_, x, MPFR_RNDN);
  }
  Iv(const Iv& o) : Iv() {
    mpfr_set(lo_, o.lo_, MPFR_RNDN);
    mpfr_set(hi_, o.hi_, MPFR_RNDN);
  }
  Iv& operator=(const Iv& o) {
    mpfr_set(lo_, o.lo_, MPFR_RNDN);
    mpfr_set(hi_, o.hi_, MPFR_RNDN);
    return *this;
  }
  ~Iv() {
    mpfr_clear(lo_);
    mpfr_clear(hi_);
  }

  static Iv pi() {
    Iv r;
    mpfr_const_pi(r.lo_, MPFR_RNDD);
    mpfr_const_pi(r.hi_, MPFR_RNDU);
    return r;
  }

  friend Iv operator+(const Iv& a, const Iv& b) {
    Iv r;
    mpfr_add(r.lo_, a.lo_, b.lo_, MPFR_RNDD);
    mpfr_add(r.hi_, a.hi_, b.hi_, MPFR_RNDU);
    return r;
  }
  friend Iv operator-(const Iv& a, const Iv& b) {
    Iv r;
    mpfr_sub(r.lo_, a.lo_, b.hi_, MPFR_RNDD);
    mpfr_sub(r.hi_, a.hi_, b.lo_, MPFR_RNDU);
    return r;
  }
  friend Iv operator*(const Iv& a, const Iv& b) { return corners(a, b, mpfr_mul); }
  friend Iv operator/(const Iv& a, const Iv& b) {
    if (mpfr_sgn(b.lo_) <= 0 && mpfr_sgn(b.hi_) >= 0) throw std::domain_error("interval division by an interval holding 0");
    return corners(a, b, mpfr_div);
  }
  friend Iv sqrt(const Iv& a) {
    if (mpfr_sgn(a.lo_) < 0) throw std::domain_error("interval square root of a negative");
    Iv r;
    mpfr_sqrt(r.lo_, a.lo_, MPFR_RNDD);
    mpfr_sqrt(r.hi_, a.hi_, MPFR_RNDU);
    return r;
  }
  /// cos on an interval inside [0, pi], where it decreases.
  friend Iv cos_0_pi(const Iv& a) {
    Iv r;
    mpfr_cos(r.lo_, a.hi_, MPFR_RNDD);
    mpfr_cos(r.hi_, a.lo_, MPFR_RNDU);
    return r;
  }
  /// sin on an interval inside [0, pi/2], where it increases.
  friend Iv sin_0_halfpi(const Iv& a) {
    Iv r;
    mpfr_sin(r.lo_, a.lo_, MPFR_RNDD);
    mpfr_sin(r.hi_, a.hi_, MPFR_RNDU);
    return r;
  }

  [[nodiscard]] bool positive() const { return mpfr_sgn(lo_) > 0; }
  [[nodiscard]] bool nonnegative() const { return mpfr_sgn(lo_) >= 0; }
  [[nodiscard]] bool nonpositive() const { return mpfr_sgn(hi_) <= 0; }

  /// The enclosure as doubles (rounded outward) and the double nearest the midpoint.
  [[nodiscard]] Reference to_reference(std::string how) const {
    Reference ref;
    ref.lo = mpfr_get_d(lo_, MPFR_RNDD);
    ref.hi = mpfr_get_d(hi_, MPFR_RNDU);
    mpfr_t mid;
    mpfr_init2(mid, kPrec + 1);
    mpfr_add(mid, lo_, hi_, MPFR_RNDN);  // exact with one more bit
    mpfr_div_2ui(mid, mid, 1, MPFR_RNDN);
    ref.value = mpfr_get_d(mid, MPFR_RNDN);
    mpfr_clear(mid);
    ref.proven = true;
    ref.method = std::move(how);
    return ref;
  }

 private:
  using Op = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t);
  /// min and max of op over the four corners, each rounded outward.
  static Iv corners(const Iv& a, const Iv& b, Op op) {
    Iv r;
    mpfr_t t;
    mpfr_init2(t, kPrec);
    bool first = true;
    for (mpfr_srcptr x : {a.lo_, a.hi_})
      for (mpfr_srcptr y : {b.lo_, b.hi_}) {
        op(t, x, y, MPFR_RNDD);
        if (first || mpfr_less_p(t, r.lo_)) mpfr_set(r.lo_, t, MPFR_RNDN);
        op(t, x, y, MPFR_RNDU);
        if (first || mpfr_greater_p(t, r.hi_)) mpfr_set(r.hi_, t, MPFR_RNDN);
        first = false;
      }
    mpfr_clear(t);
    return r;
  }

  mpfr_t lo_, hi_;
};

Iv degrees(double deg) { return Iv::pi() * Iv(deg) / Iv(180.0); }

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

void check_disk(double r, double h, double offset) {
  require(std::isfinite(r) && r > 0, "disk radius must be finite and > 0");
  require(std::isfinite(h) && h > 0, "height h must be finite and > 0 (the receiver is below the light)");
  require(std::isfinite(offset), "lateral offset must be finite");
}

// ---------------------------------------------------------------------------------------------
// Composite Gauss-Legendre quadrature with panel doubling.

constexpr int kGaussPoints = 16;

struct GaussRule {
  std::array<double, kGaussPoints> x{}, w{};
};

/// Nodes and weights on [-1, 1]: Newton's iteration on P_n from the Chebyshev guesses, in long double.
const GaussRule& gauss_rule() {
  static const GaussRule rule = [] {
    GaussRule g;
    const int n = kGaussPoints;
    for (int i = 0; i < n; ++i) {
      long double x = std::cos(std::numbers::pi_v<long double> * (i + 0.75L) / (n + 0.5L));
      long double dp = 0;
      for (int it = 0; it < 100; ++it) {
        long double p0 = 1, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const long double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1);
        const long double dx = p1 / dp;
        x -= dx;
        if (std::fabs(dx) < 1e-19L) break;
      }
      g.x[static_cast<std::size_t>(i)] = static_cast<double>(x);
      g.w[static_cast<std::size_t>(i)] = static_cast<double>(2 / ((1 - x * x) * dp * dp));
    }
    return g;
  }();
  return rule;
}

struct Quadrature {
  double value = 0, error = 0;
  int panels = 0;
  bool converged = false;
};

/// Integral of f over [a, b] by globally adaptive Gauss-Legendre: each panel's error is estimated
/// as |G(panel) - G(left half) - G(right half)| (16 points each), the worst panel is halved until
/// the estimates sum to <= 1e-14 of the integral's absolute mass or 20000 panels are used. The error
/// given is that sum plus a rounding allowance of 64 eps sum |w f|; `converged` says whether the
/// tolerance was met (if not, the estimate is unreliable and the caller says so).
Quadrature integrate(const std::function<double(double)>& f, double a, double b) {
  const GaussRule& g = gauss_rule();
  struct Panel {
    double lo, hi, coarse, fine, abs, err;
  };
  auto gauss = [&](double lo, double hi, double& abs_sum) {
    const double hw = (hi - lo) / 2, mid = lo + hw;
    double s = 0, sa = 0;
    for (int i = 0; i < kGaussPoints; ++i) {
      const double v = g.w[static_cast<std::size_t>(i)] * f(mid + hw * g.x[static_cast<std::size_t>(i)]);
      s += v;
      sa += std::fabs(v);
    }
    abs_sum = sa * std::fabs(hw);
    return s * hw;
  };
  auto make = [&](double lo, double hi, double coarse) {
    const double m = lo + (hi - lo) / 2;
    double a1 = 0, a2 = 0;
    const double fine = gauss(lo, m, a1) + gauss(m, hi, a2);
    return Panel{lo, hi, coarse, fine, a1 + a2, std::fabs(fine - coarse)};
  };
  auto worse = [](const Panel& x, const Panel& y) { return x.err < y.err; };
  std::vector<Panel> heap;
  constexpr int kStart = 8, kMaxPanels = 20000;
  for (int k = 0; k < kStart; ++k) {
    const double lo = a + (b - a) * k / kStart, hi = k + 1 == kStart ? b : a + (b - a) * (k + 1) / kStart;
    double ab = 0;
    heap.push_back(make(lo, hi, gauss(lo, hi, ab)));
  }
  std::make_heap(heap.begin(), heap.end(), worse);
  Quadrature q;
  for (;;) {
    double value = 0, err = 0, abs_sum = 0;
    for (const Panel& p : heap) value += p.fine, err += p.err, abs_sum += p.abs;
    q = {value, err + 64 * std::numeric_limits<double>::epsilon() * abs_sum, static_cast<int>(heap.size()), false};
    if (err <= 1e-14 * abs_sum) {
      q.converged = true;
      break;
    }
    if (static_cast<int>(heap.size()) >= kMaxPanels) break;
    std::pop_heap(heap.begin(), heap.end(), worse);
    const Panel worst = heap.back();
    heap.pop_back();
    const double m = worst.lo + (worst.hi - worst.lo) / 2;
    double ab = 0;
    const double left = gauss(worst.lo, m, ab), right = gauss(m, worst.hi, ab);
    for (const Panel& child : {make(worst.lo, m, left), make(m, worst.hi, right)}) {
      heap.push_back(child);
      std::push_heap(heap.begin(), heap.end(), worse);
    }
  }
  return q;
}

Reference from_quadrature(const Quadrature& q, double scale, const std::string& how) {
  Reference ref;
  ref.value = q.value * scale;
  const double e = q.error * std::fabs(scale);
  ref.lo = ref.value - e;
  ref.hi = ref.value + e;
  ref.proven = false;
  ref.method = fmt::format("{} (adaptive Gauss-Legendre, {} panels of 2x16 points; error estimated from each panel's "
                           "16-point rule{})",
                           how, q.panels, q.converged ? "" : "; NOT CONVERGED: the estimate is unreliable");
  return ref;
}

struct V3 {
  double x, y, z;
};
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace

Reference patch_solid_angle(double theta1_deg, double theta2_deg, double dphi_deg) {
  require(0 <= theta1_deg && theta1_deg <= theta2_deg && theta2_deg <= 180, "patch needs 0 <= theta1 <= theta2 <= 180 degrees");
  require(0 <= dphi_deg && dphi_deg <= 360, "patch needs 0 <= dphi <= 360 degrees");
  const Iv omega = (cos_0_pi(degrees(theta1_deg)) - cos_0_pi(degrees(theta2_deg))) * degrees(dphi_deg);
  return omega.to_reference("(cos theta1 - cos theta2) dphi, MPFR intervals");
}

Reference patch_solid_angle_estimate(double theta1_deg, double theta2_deg, double dphi_deg, double theta_at_deg) {
  require(0 <= theta1_deg && theta1_deg <= theta2_deg && theta2_deg <= 180, "patch needs 0 <= theta1 <= theta2 <= 180 degrees");
  require(0 <= dphi_deg && dphi_deg <= 360, "patch needs 0 <= dphi <= 360 degrees");
  require(0 <= theta_at_deg && theta_at_deg <= 90, "the estimate's theta must be in [0, 90] degrees");
  const Iv est = sin_0_halfpi(degrees(theta_at_deg)) * degrees(theta2_deg - theta1_deg) * degrees(dphi_deg);
  return est.to_reference("sin theta dtheta dphi (small-patch estimate), MPFR intervals");
}

Reference disk_solid_angle_on_axis(double r, double h) {
  check_disk(r, h, 0);
  const Iv R = sqrt(Iv(h) * Iv(h) + Iv(r) * Iv(r));
  const Iv omega = Iv(2.0) * Iv::pi() * Iv(r) * Iv(r) / (R * (R + Iv(h)));
  return omega.to_reference("2 pi r^2 / (R (R + h)), MPFR intervals");
}

Reference disk_solid_angle(double r, double h, double offset) {
  check_disk(r, h, offset);
  if (offset == 0) return disk_solid_angle_on_axis(r, h);
  // p(psi) = (a + r cos psi, r sin psi, h); (ez x p) . p' / (|p| (|p| + p_z)) = r (r + a cos psi) / (|p| (|p| + h)).
  const double a = offset;
  auto f = [=](double psi) {
    const double px = a + r * std::cos(psi), py = r * std::sin(psi);
    const double len = std::sqrt(px * px + py * py + h * h);
    return r * (r + a * std::cos(psi)) / (len * (len + h));
  };
  return from_quadrature(integrate(f, 0, 2 * std::numbers::pi), 1.0, "rim integral of the monopole potential");
}

Reference irradiance_on_axis(double r, double h, double L) {
  check_disk(r, h, 0);
  require(std::isfinite(L) && L >= 0, "radiance L must be finite and >= 0");
  const Iv r2 = Iv(r) * Iv(r);
  const Iv e = Iv::pi() * Iv(L) * r2 / (r2 + Iv(h) * Iv(h));
  return e.to_reference("pi L r^2 / (r^2 + h^2), MPFR intervals");
}

// Differential area parallel to a disk, off its axis (Hamilton & Morgan, "Radiant-interchange
// configuration factors", NACA TN 2836, 1952; J. R. Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors", differential planar element to a parallel disk):
//   F = (1 - (h^2 + a^2 - r^2) / sqrt((h^2 + a^2 + r^2)^2 - 4 a^2 r^2)) / 2,  E = pi L F.
// With B = h^2 + a^2 - r^2 the root is S = sqrt(B^2 + 4 r^2 h^2), so for B > 0
// 1 - B/S = (S^2 - B^2) / (S (S + B)) = 4 r^2 h^2 / (S (S + B)): no cancellation either way.
Reference irradiance_parallel(double r, double h, double offset, double L) {
  check_disk(r, h, offset);
  require(std::isfinite(L) && L >= 0, "radiance L must be finite and >= 0");
  const Iv r2 = Iv(r) * Iv(r), h2 = Iv(h) * Iv(h), a2 = Iv(offset) * Iv(offset);
  const Iv B = h2 + a2 - r2;
  const Iv S = sqrt(B * B + Iv(4.0) * r2 * h2);
  const Iv piL = Iv::pi() * Iv(L);
  if (B.nonnegative()) {
    const Iv e = piL * Iv(2.0) * r2 * h2 / (S * (S + B));
    return e.to_reference("pi L 2 r^2 h^2 / (S (S + B)) (Hamilton & Morgan 1952), MPFR intervals");
  }
  const Iv e = piL * (S - B) / (Iv(2.0) * S);
  return e.to_reference("pi L (S - B) / (2 S) (Hamilton & Morgan 1952), MPFR intervals");
}

double irradiance_parallel_double(double r, double h, double offset, double L) {
  const double B = h * h + offset * offset - r * r;
  const double S = std::sqrt(B * B + 4 * r * r * h * h);
  const double pi = std::numbers::pi;
  return B >= 0 ? pi * L * 2 * r * r * h * h / (S * (S + B)) : pi * L * (S - B) / (2 * S);
}

Reference irradiance_tilted(double r, double h, double offset, double tilt_rad, double L) {
  check_disk(r, h, offset);
  require(std::isfinite(L) && L >= 0, "radiance L must be finite and >= 0");
  require(std::isfinite(tilt_rad) && std::fabs(tilt_rad) <= std::numbers::pi * (1 + 1e-12), "tilt must be within [-180, 180] degrees");
  const V3 n{std::sin(tilt_rad), 0, std::cos(tilt_rad)};
  const V3 c{offset, 0, h};
  auto p = [&](double psi) { return V3{c.x + r * std::cos(psi), c.y + r * std::sin(psi), c.z}; };
  auto dp = [&](double psi) { return V3{-r * std::sin(psi), r * std::cos(psi), 0}; };
  // The integrand of n . (1/2) \oint p x p' / |p|^2 dpsi (counter-clockwise seen from +z).
  auto f = [&](double psi) {
    const V3 q = p(psi);
    return dot(n, cross(q, dp(psi))) / (2 * dot(q, q));
  };
  // Horizon: n . p(psi) = m + k cos(psi - psi0); the visible arc is cos(psi - psi0) >= -m / k.
  const double m = dot(n, c);
  const double k = r * std::hypot(n.x, n.y);
  const double psi0 = std::atan2(n.y, n.x);
  if (m >= k) {
    // Over the whole rim, the term r n.(c x u') / (2 |c|^2) integrates to 0; subtracting it removes
    // the cancellation of O(1) terms for a far disk. With u = (cos psi, sin psi, 0) and
    // 1/|p|^2 - 1/|c|^2 = -(2 r c.u + r^2) / (|p|^2 |c|^2), what remains is
    // r^2 / (2 |p|^2) (n_z - n.(c x u') (2 c.u + r) / |c|^2). Near the rim (|c| < 2 r) that bracket
    // cancels instead, so there the plain integrand is used.
    const double c2 = dot(c, c);
    if (c2 < 4 * r * r)
      return from_quadrature(integrate(f, 0, 2 * std::numbers::pi), L,
                             "Lambert's rim integral, disk wholly above the horizon");
    auto g = [&](double psi) {
      const V3 u{std::cos(psi), std::sin(psi), 0}, du{-std::sin(psi), std::cos(psi), 0};
      const V3 q = p(psi);
      return r * r / (2 * dot(q, q)) * (n.z - dot(n, cross(c, du)) * (2 * dot(c, u) + r) / c2);
    };
    return from_quadrature(integrate(g, 0, 2 * std::numbers::pi), L,
                           "Lambert's rim integral, disk wholly above the horizon");
  }
  if (m <= -k) {
    Reference ref;
    ref.proven = true;
    ref.method = "disk wholly below the receiver's horizon";
    return ref;
  }
  const double beta = std::acos(-m / k);
  Quadrature q = integrate(f, psi0 - beta, psi0 + beta);
  // The chord from p(psi0 + beta) back to p(psi0 - beta) lies in the horizon plane: it adds
  // (1/2) angle(A, B) times n . unit(A x B) = +-1.
  const V3 A = p(psi0 + beta), B = p(psi0 - beta);
  const V3 axb = cross(A, B);
  const double s = std::sqrt(dot(axb, axb));
  const double angle = std::atan2(s, dot(A, B));
  const double chord = 0.5 * angle * (dot(n, axb) >= 0 ? 1.0 : -1.0);
  q.value += chord;
  q.error += 8 * std::numeric_limits<double>::epsilon() * std::fabs(chord);
  return from_quadrature(q, L, "Lambert's rim integral over the visible arc plus the horizon chord");
}

Reference irradiance_reference(double r, double h, double offset, double tilt_rad, double L) {
  if (tilt_rad == 0) return offset == 0 ? irradiance_on_axis(r, h, L) : irradiance_parallel(r, h, offset, L);
  return irradiance_tilted(r, h, offset, tilt_rad, L);
}

}  // namespace rayproof::verify
