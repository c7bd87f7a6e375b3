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
