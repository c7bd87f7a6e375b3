#include "rayproof/float_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace rayproof;

TEST(FloatUtil, UlpDistanceCountsRepresentableSteps) {
  EXPECT_EQ(ulp_distance(1.0, 1.0), 0u);
  EXPECT_EQ(ulp_distance(1.0, std::nextafter(1.0, 2.0)), 1u);
  EXPECT_EQ(ulp_distance(-0.0, 0.0), 0u);
  EXPECT_EQ(ulp_distance(-std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::denorm_min()), 2u);
  EXPECT_EQ(ulp_distance(1.0f, std::nextafter(std::nextafter(1.0f, 2.0f), 2.0f)), 2u);
  EXPECT_EQ(ulp_distance(std::nan(""), 1.0), std::numeric_limits<std::uint64_t>::max());
}

TEST(FloatUtil, GammaBoundsChainedRoundings) {
  EXPECT_GT(gamma<double>(1), unit_roundoff<double>);
  EXPECT_LT(gamma<double>(3), 3.01 * unit_roundoff<double>);
  EXPECT_GT(gamma<float>(3), gamma<double>(3));
}

TEST(FloatUtil, DifferenceOfProductsIsAccurateUnderCancellation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const double a = u(rng), b = u(rng), c = a * (1 + 1e-12 * u(rng)), d = b;
    // Products of doubles are exact in binary128 (106 significant bits); the inputs are close, so
    // their difference is exact there too.
    const __float128 exact = (__float128)a * b - (__float128)c * d;
    const double got = difference_of_products(a, b, c, d);
    const __float128 err = (__float128)got - exact;
    const __float128 bound = 2 * (__float128)unit_roundoff<double> * (exact < 0 ? -exact : exact);
    EXPECT_LE((double)(err < 0 ? -err : err), (double)bound) << i;
  }
}

TEST(FloatUtil, NeighboursStepOneUlp) {
  EXPECT_EQ(ulp_distance(next_up(3.0), 3.0), 1u);
  EXPECT_EQ(ulp_distance(next_down(3.0f), 3.0f), 1u);
  EXPECT_LT(next_down(0.0), 0.0);
}

TEST(FloatUtil, UlpDistanceAcrossZeroAtExtremes) {
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(ulp_distance(-big, big), 2 * static_cast<std::uint64_t>(ordered_bits(big)));
  EXPECT_EQ(ulp_distance(big, -big), ulp_distance(-big, big));
  EXPECT_EQ(ulp_distance(-std::numeric_limits<float>::max(), std::numeric_limits<float>::max()),
            2 * static_cast<std::uint64_t>(ordered_bits(std::numeric_limits<float>::max())));
}
