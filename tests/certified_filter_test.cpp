#include "rayproof/certified_filter.h"

#include <gtest/gtest.h>

using namespace rayproof;
using namespace rayproof::certified;

TEST(CertifiedFilter, WideFormatIsAvailableHere) { EXPECT_TRUE(kFilterAvailable); }

TEST(CertifiedFilter, ExactZerosAreDecided) {
  const Bounded a(3.0), b(3.0);
  EXPECT_EQ(sign((a - b) * Bounded(1e300)), 0);
  EXPECT_EQ(sign(Bounded(0.0) * Bounded(5.0) + Bounded(0.0)), 0);
}

TEST(CertifiedFilter, SignsAreDecidedOrLeftOpen) {
  // (1 + 2^-30)^2 - (1 + 2^-29) = 2^-60 > 0: 0 in double, exact in the wide format.
  const Bounded x(1.0 + 0x1p-30);
  const auto s = sign(x * x - Bounded(1.0 + 0x1p-29));
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(*s, 1);
  // A difference far below the bound stays undecided.
  const Bounded y(1.0 + 0x1p-52);
  EXPECT_FALSE(sign(y * y * y * y - (y * y) * (y * y)).has_value());
}

TEST(CertifiedFilter, RadiusEnclosesTheExactValue) {
  // 1/3 in the wide format: the exact third lies within the radius.
  const Bounded t = Bounded(1.0) / Bounded(3.0);
  EXPECT_GT(t.r, 0);
  EXPECT_LE(std::fabs(t.v * 3 - 1), 3 * t.r * kSlack);
  const auto p = pin(t);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(*p, 1.0 / 3.0);
}

TEST(CertifiedFilter, PinRefusesWideIntervals) {
  EXPECT_FALSE(pin(Bounded(Wide(1), Wide(1e-10))).has_value());
  EXPECT_TRUE(pin(Bounded(Wide(1), Wide(1e-19))).has_value());
  EXPECT_FALSE(pin(Bounded(std::numeric_limits<Wide>::max(), Wide(0))).has_value());  // beyond double
}

TEST(CertifiedFilter, NonFiniteIsUndecided) {
  const Bounded inf(std::numeric_limits<Wide>::infinity(), Wide(0));
  EXPECT_FALSE(sign(inf - inf).has_value());
  EXPECT_FALSE(pin(inf).has_value());
}

// ---- Staged filters: expansions, pinning (certified_expansion.h, certified_stage.h) ----
#include <cmath>
#include <limits>
#include <random>

#include "rayproof/certified_fma.h"
#include "rayproof/certified_stage.h"

TEST(CertifiedExpansion, ExactZerosAndTinySigns) {
  // (1 + 2^-30)^2 - (1 + 2^-29) - 2^-60 = 0 exactly; double arithmetic gives -2^-60 or so.
  const Expansion x(1.0 + 0x1p-30);
  const Expansion z = x * x - Expansion(1.0 + 0x1p-29) - Expansion(0x1p-60);
  EXPECT_FALSE(z.bad);
  EXPECT_EQ(z.sign(), 0);
  EXPECT_EQ((x * x - Expansion(1.0 + 0x1p-29)).sign(), 1);
  // A difference of inputs 2^100 apart is kept exactly.
  EXPECT_EQ((diff(0x1p100, -0x1p-100) - Expansion(0x1p100)).sign(), 1);
  EXPECT_EQ((diff(0x1p100, -0x1p-100) - Expansion(0x1p100) - Expansion(0x1p-100)).sign(), 0);
}

/// in_range (bits of |x|, integer max / min) against its definition: every value 0 or with |x| in
/// [2^lo, 2^hi]; zeros of both signs, the bounds themselves and their neighbours, subnormals, inf, NaN.
TEST(CertifiedExpansion, InRangeMatchesItsDefinition) {
  auto want = [](std::initializer_list<double> xs) {
    for (double x : xs)
      if (!(x == 0 || (std::fabs(x) >= 0x1p-200 && std::fabs(x) <= 0x1p200))) return false;
    return true;
  };
  std::mt19937_64 g(5);
  const double special[] = {0.0, -0.0, 0x1p-200, -0x1p-200, 0x1p200, -0x1p200, std::nextafter(0x1p-200, 0.0),
                            std::nextafter(0x1p200, 1e300), 4.9e-324, 1.0, -3.5, std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(), 0x1p-300, 0x1p300};
  constexpr std::size_t n = sizeof special / sizeof special[0];
  for (int i = 0; i < 20000; ++i) {
    const double a = special[g() % n], b = special[g() % n], c = special[g() % n];
    const double r = std::ldexp(1.0 + double(g() % 1000) / 1000, static_cast<int>(g() % 600) - 300);
    EXPECT_EQ((in_range<-200, 200>(a, b, c, r)), want({a, b, c, r})) << a << " " << b << " " << c << " " << r;
  }
  EXPECT_TRUE((in_range<-200, 200>(0.0, -0.0)));
  EXPECT_FALSE((in_range<-200, 200>(1.0, std::numeric_limits<double>::quiet_NaN())));
}

__extension__ typedef __int128 I128;  // exact reference for products of 31-bit integers

/// round(N / D) is t or a neighbour of t (the 1-ulp contract): N / D lies strictly between the midpoint
/// below prev(t) and the one above next(t), compared in 128-bit integers with every double scaled by
/// 2^54 (exact for the t >= 1 of the tests below, whose neighbours and midpoints lie on that grid).
static bool rounds_within_one_ulp(double t, I128 N, I128 D) {
  auto scaled = [](double m) { return static_cast<I128>(std::ldexp(m, 54)); };
  const double p = next_below(t), q = next_above(t);
  const I128 below = (scaled(next_below(p)) + scaled(p)) / 2, above = (scaled(q) + scaled(next_above(q))) / 2;
  const I128 NN = N << 54;
  return below * D < NN && NN < above * D;
}

TEST(CertifiedExpansion, SignsAgreeWithIntegerArithmetic) {
  // a b + c d - e f with 31-bit integers (exact in __int128), scaled by 2^k (sign unchanged).
  std::mt19937_64 g(7);
  std::uniform_int_distribution<std::int64_t> v(-(1LL << 31), 1LL << 31);
  std::uniform_int_distribution<int> sc(-150, 150);
  for (int i = 0; i < 20000; ++i) {
    std::int64_t a = v(g), b = v(g), c = v(g), d = v(g), e = v(g), f = v(g);
    if (i % 3 == 0) e = a, f = b + (i % 2);  // near and exact cancellations
    if (i % 5 == 0) e = c, f = d, c = a, d = -b;
    const I128 exact = I128(a) * b + I128(c) * d - I128(e) * f;
    const int want = exact > 0 ? 1 : (exact < 0 ? -1 : 0);
    const double s = std::ldexp(1.0, sc(g));
    auto X = [&](std::int64_t q) { return Expansion(double(q) * s); };
    const Expansion r = X(a) * X(b) + X(c) * X(d) - X(e) * X(f);
    ASSERT_FALSE(r.bad);
    ASSERT_EQ(r.sign(), want) << a << " " << b << " " << c << " " << d << " " << e << " " << f;
  }
}

TEST(CertifiedStage, PinsAreWithinOneUlp) {
  // Exact residual: 1/3, 2/7 and an exact quotient.
  EXPECT_EQ(pin_quotient(Expansion(1.0), Expansion(3.0)), std::optional<double>(1.0 / 3.0));
  EXPECT_EQ(pin_quotient(Expansion(2.0), Expansion(7.0)), std::optional<double>(2.0 / 7.0));
  EXPECT_EQ(pin_quotient(Expansion(6.0), Expansion(-4.0)), std::optional<double>(-1.5));
  EXPECT_EQ(pin_quotient(Expansion(0.0), Expansion(5.0)), std::optional<double>(0.0));
  // Wide: an interval inside the rounding neighbourhood pins, a wide one does not.
  EXPECT_EQ(pin_wide(Wide(1) / 3, 0x1p-70L), std::optional<double>(1.0 / 3.0));
  EXPECT_FALSE(pin_wide(Wide(1) / 3, 0x1p-50L).has_value());
  // Just below 1 (the gap below is half the gap above): still pinned to a neighbour of 1.
  const auto p = pin_wide(1 - 0x1p-60L, 0x1p-58L);
  ASSERT_TRUE(p.has_value());
  EXPECT_LE(ulp_distance(*p, 1.0), 1u);
  // Wide ratios: 1/3 pins, a bound too wide to tell does not, an exact zero numerator is the caller's.
  EXPECT_EQ(pin_ratio(Wide(1), Wide(3), 0, 0), std::optional<double>(1.0 / 3.0));
  EXPECT_EQ(pin_ratio(Wide(-7), Wide(2), 0, 0), std::optional<double>(-3.5));
  EXPECT_FALSE(pin_ratio(Wide(1), Wide(3), 0x1p-50L, 0).has_value());
  EXPECT_FALSE(pin_ratio(Wide(1), Wide(3), 0, 0x1p-50L).has_value());
  EXPECT_FALSE(pin_ratio(Wide(0), Wide(3), 0, 0).has_value());
  EXPECT_EQ(next_above(1.0), 1.0 + 0x1p-52);
  EXPECT_EQ(next_below(1.0), 1.0 - 0x1p-53);
  EXPECT_EQ(next_below(0.0), -std::numeric_limits<double>::denorm_min());
}

/// pin_ratio against exact integer arithmetic: x = N / D with N < 2^62 and D < 2^31 (both exact in
/// Wide), given to pin_ratio exactly and then perturbed within the error bounds it is told about. An
/// accepted t must have x strictly between the midpoints around prev(t) and next(t) (then round(x) is
/// t or a neighbour), checked in 128-bit integers with every midpoint scaled by 2^54 (x in [1, 2^20)).
TEST(CertifiedStage, PinRatioAgreesWithIntegerArithmetic) {
  std::mt19937_64 g(77);
  int accepted = 0, perturbed_accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t D = (g() >> 33) | 1;              // < 2^31
    const int shift = static_cast<int>(g() % 20);           // x in [2^shift, 2^(shift+1))
    const std::uint64_t lo = D << shift, N = lo + g() % lo; // N / D in [2^shift, 2^(shift+1))
    if (N >> 62) continue;
    if (const auto t = pin_ratio(Wide(N), Wide(D), 0, 0)) {
      ++accepted;
      ASSERT_TRUE(rounds_within_one_ulp(*t, N, D)) << N << " / " << D;
    }
    // Told num and den are off by up to 2^-60 of their size, and given values that are off by that.
    const Wide num = Wide(N) * (1 + 0x1p-60L * (g() % 2 ? 1 : -1)), den = Wide(D) * (1 - 0x1p-60L);
    if (const auto t = pin_ratio(num, den, Wide(N) * 0x1p-60L, Wide(D) * 0x1p-60L)) {
      ++perturbed_accepted;
      ASSERT_TRUE(rounds_within_one_ulp(*t, N, D)) << "perturbed " << N << " / " << D;
    }
  }
  EXPECT_GT(accepted, n * 95 / 100);
  EXPECT_GT(perturbed_accepted, n * 80 / 100);
}

#if RAYPROOF_FMA_PATH != 0
/// pin_dd (the double-double quotient with one correction, certified_fma.h) against 128-bit integers:
/// N in [2^69, 2^70) and D in [2^59, 2^60) given as two doubles each (hi rounded, lo the exact rest),
/// exactly and then off by 2^-90 of their size with that bound passed along. Every t returned must have
/// N / D strictly between the midpoints below prev(t) and above next(t).
TEST(CertifiedStage, PinDdAgreesWithIntegerArithmetic) {
  std::mt19937_64 g(78);
  using I = I128;
  auto split = [](I v) {
    const double hi = static_cast<double>(v);
    return certified::dd::DD{hi, static_cast<double>(v - static_cast<I>(hi))};
  };
  int accepted = 0, perturbed_accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const I N = (I(1) << 69) + static_cast<I>(g() >> 1) * (I(1) << 6) + static_cast<I>(g() % 64);
    const I D = (I(1) << 59) + static_cast<I>(g() >> 5);
    if (const auto t = certified::dd::pin_dd(split(N), split(D), 0, 0)) {
      ++accepted;
      ASSERT_TRUE(rounds_within_one_ulp(*t, N, D)) << static_cast<double>(N) << " / " << static_cast<double>(D);
    }
    certified::dd::DD num = split(N), den = split(D);
    num.lo += (g() % 2 ? 1 : -1) * std::ldexp(num.hi, -92);
    den.lo -= std::ldexp(den.hi, -92);
    if (const auto t = certified::dd::pin_dd(num, den, std::ldexp(num.hi, -90), std::ldexp(den.hi, -90))) {
      ++perturbed_accepted;
      ASSERT_TRUE(rounds_within_one_ulp(*t, N, D)) << "perturbed";
    }
  }
  EXPECT_GT(accepted, n * 99 / 100);
  EXPECT_GT(perturbed_accepted, n * 99 / 100);
}
#endif
