#pragma once
/// Exact signs without GMP: Shewchuk's floating-point expansions ("Adaptive Precision Floating-Point
/// Arithmetic and Fast Robust Geometric Predicates", Discrete Comput. Geom. 18, 1997). A value is an
/// unevaluated sum of doubles, nonoverlapping and in increasing order of magnitude; sums and products
/// of input doubles are represented exactly (two_sum, and two_prod with an FMA), so the sign of a
/// polynomial in the inputs is the sign of its largest component, and an exact zero is the empty
/// expansion. Used by the certified tier between the error-bounded double stage and the GMP fallback.
///
/// Hand-written on purpose: no Debian package offers expansion arithmetic as cheap inline routines
/// for custom polynomials (Shewchuk's predicates.c ships only orient/incircle; CGAL's filtered
/// predicates cover its own kernel predicates and go through interval + Gmpq, not inline-cheap for
/// these quantities). Only GROW-EXPANSION (Theorem 10) and COMPRESS are used, both with the
/// branch-free two_sum, so no precondition on the rounding mode beyond IEEE round-to-nearest.
///
/// Exactness needs every two_prod free of underflow and overflow: callers check with in_range()
/// that all nonzero inputs have exponents in a window that makes this true for their degree (every
/// nonzero component of a degree-m polynomial in doubles >= 2^-k is a multiple of 2^(-m (k+52))).
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "rayproof/float_util.h"
#include "rayproof/vec3.h"

namespace rayproof::certified {

/// Adds b to the expansion e[0..n) in place: GROW-EXPANSION with zero elimination (Shewchuk 1997,
/// Theorem 10, valid under round-to-nearest whatever the tie rule). Writing e[k] with k <= i after
/// reading e[i] keeps it in place, so e needs room for n + 1 components. Returns the new length.
/// Expansion::grow uses it, and orient.h's stack stages on small arrays of their own.
inline int grow_into(double* e, int n, double b) {
  if (b == 0) return n;
  double q = b;
  int k = 0;
  for (int i = 0; i < n; ++i) {
    const TwoTerm<double> s = two_sum(q, e[i]);
    q = s.hi;
    if (s.lo != 0) e[k++] = s.lo;
  }
  if (q != 0) e[k++] = q;
  return k;
}

/// An expansion with room for kCap components. An operation that would need more room (possible only
/// for inputs spread over a huge exponent range) marks the result `bad`; its sign is then unknown and
/// the caller falls back to GMP.
struct Expansion {
  static constexpr int kCap = 120;
  double c[kCap];
  int n = 0;
  bool bad = false;

  Expansion() = default;
  /// One input double, exact.
  explicit Expansion(double x) {
    if (x != 0) c[n++] = x;
  }

  /// Adds one double exactly (GROW-EXPANSION with zero elimination); the result stays nonoverlapping
  /// and increasing. Compresses first when full.
  void grow(double b) {
    if (n == kCap) {
      compress();
      if (n == kCap) {
        bad = true;
        return;
      }
    }
    n = grow_into(c, n, b);
  }

  /// Shewchuk's COMPRESS (predicates.c): the same value in fewer, nonadjacent components.
  void compress() {
    if (n < 2) return;
    double g[kCap];
    int bottom = n - 1;
    double q = c[n - 1];
    for (int i = n - 2; i >= 0; --i) {
      const TwoTerm<double> s = two_sum(q, c[i]);
      if (s.lo != 0) {
        g[bottom--] = s.hi;
        q = s.lo;
      } else {
        q = s.hi;
      }
    }
    int top = 0;
    for (int i = bottom + 1; i < n; ++i) {
      const TwoTerm<double> s = two_sum(g[i], q);
      q = s.hi;
      if (s.lo != 0) c[top++] = s.lo;
    }
    if (q != 0) c[top++] = q;
    n = top;
  }

  /// Sign of the exact value: that of the largest (last) component. Meaningless when bad.
  [[nodiscard]] int sign() const { return n == 0 ? 0 : (c[n - 1] > 0 ? 1 : -1); }
  /// The largest component: the value to within a relative 2^-52.
  [[nodiscard]] double top() const { return n == 0 ? 0.0 : c[n - 1]; }
  /// The value to within a relative 2^-104 (the two largest components; the rest is below an ulp
  /// of the second).
  [[nodiscard]] double estimate() const { return n == 0 ? 0.0 : (n == 1 ? c[0] : c[n - 1] + c[n - 2]); }
};

/// Exact sum and difference of expansions.
[[nodiscard]] inline Expansion operator+(const Expansion& x, const Expansion& y) {
  Expansion h = x.n >= y.n ? x : y;
  const Expansion& o = x.n >= y.n ? y : x;
  h.bad = x.bad || y.bad;
  for (int i = 0; i < o.n; ++i) h.grow(o.c[i]);
  h.compress();
  return h;
}
[[nodiscard]] inline Expansion operator-(const Expansion& x) {
  Expansion h = x;
  for (int i = 0; i < h.n; ++i) h.c[i] = -h.c[i];
  return h;
}
[[nodiscard]] inline Expansion operator-(const Expansion& x, const Expansion& y) { return x + (-y); }

/// Exact product: every pair of components through two_prod (FMA), grown into the result.
[[nodiscard]] inline Expansion operator*(const Expansion& x, const Expansion& y) {
  Expansion h;
  h.bad = x.bad || y.bad;
  for (int i = 0; i < x.n; ++i)
    for (int j = 0; j < y.n; ++j) {
      const TwoTerm<double> p = two_prod(x.c[i], y.c[j]);
      if (p.lo != 0) h.grow(p.lo);
      h.grow(p.hi);
    }
  h.compress();
  return h;
}

/// a - b of two input doubles, exactly (two components at most).
[[nodiscard]] inline Expansion diff(double a, double b) {
  const TwoTerm<double> s = two_sum(a, -b);
  Expansion e;
  if (s.lo != 0) e.c[e.n++] = s.lo;
  if (s.hi != 0) e.c[e.n++] = s.hi;
  return e;
}

/// Vectors of expansions.
using ExpVec3 = Vec3<Expansion>;

[[nodiscard]] inline ExpVec3 diff3(const Vec3<double>& p, const Vec3<double>& q) {
  return {diff(p.x, q.x), diff(p.y, q.y), diff(p.z, q.z)};
}
[[nodiscard]] inline ExpVec3 exact3(const Vec3<double>& p) {
  return {Expansion(p.x), Expansion(p.y), Expansion(p.z)};
}
[[nodiscard]] inline bool is_zero(const ExpVec3& v) { return v.x.n == 0 && v.y.n == 0 && v.z.n == 0; }
[[nodiscard]] inline bool any_bad(const ExpVec3& v) { return v.x.bad || v.y.bad || v.z.bad; }

/// 2^e as a constant.
[[nodiscard]] constexpr double pow2(int e) {
  double r = 1;
  for (; e > 0; --e) r *= 2;
  for (; e < 0; ++e) r /= 2;
  return r;
}

/// The bits of |x|: ordered as |x| for non-negative doubles, a NaN's above every finite value's.
[[nodiscard]] inline std::uint64_t magnitude_bits(double x) {
  return std::bit_cast<std::uint64_t>(x) & ~(std::uint64_t(1) << 63);
}

/// Every value finite: the bits of |x| at most those of the largest double (integer max, no branch
/// per value, as in_range below; measured faster here than summing x - x, whose NaN would flag the same).
template <class... D>
[[nodiscard]] inline bool finite_bits(D... xs) {
  constexpr std::uint64_t top = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::max());
  std::uint64_t big = 0;
  auto step = [&](double x) {
    const std::uint64_t b = magnitude_bits(x);
    big = b > big ? b : big;
  };
  (step(xs), ...);
  return big <= top;
}

/// True when every value is 0 or has |x| in [2^lo, 2^hi] (and so is finite and normal). A caller with
/// a degree-m polynomial whose intermediate sums stay below 2^(m(hi+2)+8) picks lo, hi with
/// m (52 - lo) <= 1022 and m (hi + 2) + 8 <= 1023.
/// On the bits of |x| (monotone in |x| for non-negative doubles): the largest must not exceed those of
/// 2^hi, and the smallest of bits - 1 (a zero wraps around to the largest unsigned value and so drops
/// out) must reach those of 2^lo, minus one. A NaN's bits exceed those of any finite value. Integer
/// max / min, no branch per value: a fold over ten values of fabs and three comparisons each was ~45
/// cycles of a certified sphere test.
template <int Lo, int Hi, class... D>
[[nodiscard]] inline bool in_range(D... xs) {
  constexpr std::uint64_t lo = std::bit_cast<std::uint64_t>(pow2(Lo)), hi = std::bit_cast<std::uint64_t>(pow2(Hi));
  std::uint64_t big = 0, small = ~std::uint64_t(0);
  auto step = [&](double x) {
    const std::uint64_t b = magnitude_bits(x);
    big = b > big ? b : big;
    small = b - 1 < small ? b - 1 : small;
  };
  (step(xs), ...);
  return big <= hi && small >= lo - 1;
}

}  // namespace rayproof::certified
