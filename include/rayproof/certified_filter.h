#pragma once
/// Floating-point filters for the certified tier: every deciding quantity is evaluated in midpoint-
/// radius arithmetic (a value v and a radius r with |exact - v| <= r; running error bounds in the
/// sense of Wilkinson, interval arithmetic in centre form), in the x87 extended format (64-bit
/// significand, 15-bit exponent). A sign is decided when |v| > r (or v = r = 0: the computation was
/// exact); a t is certified when its interval lies within one double ulp of the double nearest v.
/// Anything else is *undecided* and the caller falls back to exact arithmetic.
///
/// Why the extended format: the quantities are polynomials of degree <= 6 in the input doubles, so
/// with a 15-bit exponent no intermediate can overflow or underflow (|x| in [2^-6444, 2^6144] for
/// nonzero products of six doubles), which removes the absolute underflow term a double filter needs,
/// and its 11 extra bits make a t certified to one double ulp in all but ill-conditioned cases.
/// Where long double is not that format, every filter answers undecided (always exact, still correct).
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include "rayproof/float_util.h"
#include "rayproof/vec3.h"

namespace rayproof::certified {

/// The working type of the filters.
using Wide = long double;

/// True when Wide is the 64-bit-significand, 15-bit-exponent format the bounds assume.
inline constexpr bool kFilterAvailable =
    std::numeric_limits<Wide>::digits >= 64 && std::numeric_limits<Wide>::max_exponent >= 16384 &&
    std::numeric_limits<Wide>::min_exponent <= -16381;

/// Factor applied to a radius before it decides anything: covers the rounding of the radius
/// computations themselves (each underestimates by at most a factor (1 - u) per operation; the
/// deepest expression here has fewer than 100 operations, and 2^-40 >> 100 * 2^-53).
inline constexpr long double kSlack = 1.0L + 1.0L / 1099511627776.0L;

/// A value with an error bound, in working type W (Wide, or double for the quick first stage): the
/// exact quantity lies in [v - r, v + r] (up to kSlack).
/// In double a product or quotient may underflow: not only its value (absolute error up to half the
/// smallest subnormal eta) but also each product or quotient inside its *radius* (|a| r_b, r_a r_b,
/// u |v|, ...), which then rounds to nearest and may lose up to eta / 2 or flush to 0 (e.g. an
/// operand that underflowed to v = 0 with r = eta, times a tiny factor: r_b |a| -> 0, and the
/// result would claim an exact zero). kSlack covers only relative rounding, so every product,
/// quotient or square root whose operands are not exact zeros (v = r = 0) adds kUnderflow = 3 eta:
/// at most five roundings with underflow, eta / 2 each. Sums never underflow (a subnormal sum is
/// exact, and for a normal sum u |v| >= half its ulp, a representable bound, is kept by rounding).
/// In Wide none of this can happen (see above) and exact zeros keep radius 0 in both.
template <class W>
struct BoundedT {
  static constexpr W kU = unit_roundoff<W>;
  static constexpr W kEta = std::is_same_v<W, double> ? std::numeric_limits<W>::denorm_min() : W(0);
  /// Absolute slack per product / quotient / square root of operands that are not exact zeros.
  static constexpr W kUnderflow = 3 * kEta;
  /// Not known to be exactly zero: an underflowed value (v = 0, r > 0) still counts.
  [[nodiscard]] bool maybe_nonzero() const { return v != 0 || r != 0; }
  W v = 0;
  W r = 0;
  BoundedT() = default;
  /// An input double: exact.
  BoundedT(double x) : v(x) {}  // NOLINT(google-explicit-constructor): inputs lift implicitly
  BoundedT(W value, W radius) : v(value), r(radius) {}
};
using Bounded = BoundedT<Wide>;

/// Sum and difference: the radii add, plus the rounding of the result (never underflows).
template <class W> inline BoundedT<W> operator+(BoundedT<W> a, BoundedT<W> b) {
  const W v = a.v + b.v;
  return {v, a.r + b.r + BoundedT<W>::kU * std::fabs(v)};
}
template <class W> inline BoundedT<W> operator-(BoundedT<W> a, BoundedT<W> b) {
  const W v = a.v - b.v;
  return {v, a.r + b.r + BoundedT<W>::kU * std::fabs(v)};
}
template <class W> inline BoundedT<W> operator-(BoundedT<W> a) { return {-a.v, a.r}; }

/// Product: |xy - ab| <= |a| r_b + |b| r_a + r_a r_b, plus the rounding of the result.
template <class W> inline BoundedT<W> operator*(BoundedT<W> a, BoundedT<W> b) {
  const W v = a.v * b.v;
  W r = std::fabs(a.v) * b.r + std::fabs(b.v) * a.r + a.r * b.r + BoundedT<W>::kU * std::fabs(v);
  // Not just a.v, b.v != 0: with a.v = 0, r_a > 0 (an earlier underflow) |b| r_a may flush to 0 too.
  if constexpr (BoundedT<W>::kEta != W(0))
    r += (a.maybe_nonzero() && b.maybe_nonzero()) ? BoundedT<W>::kUnderflow : W(0);
  return {v, r};
}

/// |b.v| > b.r: b's interval excludes 0, so a / b is bounded.
template <class W> [[nodiscard]] inline bool nonzero(BoundedT<W> b) { return std::fabs(b.v) > b.r * W(kSlack); }

/// Quotient (b must be nonzero()): |x/y - a/b| <= (r_a + |a/b| r_b) / (|b| - r_b).
template <class W> inline BoundedT<W> operator/(BoundedT<W> a, BoundedT<W> b) {
  const W v = a.v / b.v;
  const W den = std::fabs(b.v) - b.r * W(kSlack);
  W r = (a.r + std::fabs(v) * b.r) / den * W(kSlack) + BoundedT<W>::kU * std::fabs(v);
  if constexpr (BoundedT<W>::kEta != W(0)) r += a.maybe_nonzero() ? BoundedT<W>::kUnderflow : W(0);
  return {v, r};
}

/// Square root of a positive quantity (a.v > a.r): |sqrt(x) - sqrt(a)| <= r_a / sqrt(a).
template <class W> [[nodiscard]] inline BoundedT<W> sqrt(BoundedT<W> a) {
  const W v = std::sqrt(a.v);
  W r = a.r / v + BoundedT<W>::kU * v;  // r_a / v may underflow when v > 1
  if constexpr (BoundedT<W>::kEta != W(0)) r += a.r != 0 ? BoundedT<W>::kUnderflow : W(0);
  return {v, r};
}

/// Sign of the exact quantity: -1, 0 or +1, or nothing when the bound cannot tell. A NaN or infinite
/// value or radius compares false everywhere and is undecided (an infinite v has an infinite r).
template <class W> [[nodiscard]] inline std::optional<int> sign(BoundedT<W> a) {
  if (a.v == 0 && a.r == 0) return 0;
  const W r = a.r * W(kSlack);
  if (a.v > r) return 1;
  if (a.v < -r) return -1;
  return std::nullopt;
}

/// Pins an interval [lo, hi] known to contain the exact value x: round(x) lies between round(lo)
/// and round(hi), so when both are within one ulp of t = round(guess), so is round(x).
[[nodiscard]] inline std::optional<double> pin_interval(Wide lo, Wide hi, Wide guess) {
  const double t = static_cast<double>(guess);
  if (!std::isfinite(t)) return std::nullopt;
  // A zero is +0.0, as the exact method rounds it.
  if (ulp_distance(static_cast<double>(lo), t) <= 1 && ulp_distance(static_cast<double>(hi), t) <= 1) return t + 0.0;
  return std::nullopt;
}

/// The double within one ulp of the exact value of `a` (its rounding to nearest is that double or a
/// neighbour), or nothing when the interval is wider than that or not finite.
[[nodiscard]] inline std::optional<double> pin(Bounded a) {
  if (a.r == 0) {  // exact in Wide: round(a.v) is the conversion itself
    const double t = static_cast<double>(a.v);
    return std::isfinite(t) ? std::optional<double>(t + 0.0) : std::nullopt;  // a zero is +0.0
  }
  // Interval ends, widened by 2 u |v| for their own rounding.
  const Wide w = a.r * kSlack + 2 * Bounded::kU * std::fabs(a.v);
  return pin_interval(a.v - w, a.v + w, a.v);
}

/// A vector of input doubles, lifted exactly.
template <class W = Wide>
[[nodiscard]] inline Vec3<BoundedT<W>> lift(const Vec3<double>& p) {
  return {p.x, p.y, p.z};
}

}  // namespace rayproof::certified
