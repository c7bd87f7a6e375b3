#include "rayproof/plane_fma.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T> class PlaneFmaTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(PlaneFmaTest, Scalars);

TYPED_TEST(PlaneFmaTest, WorkedExamples) {
  using T = TypeParam;
  // docs/cases.md: plane 0 0 0 1 1 0 0 0 5 0 0 1 -> parallel.
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 0}, {1, 1, 0}}, Plane<T>{{0, 0, 5}, {0, 0, 1}}).contact, Contact::parallel);
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 5}, {1, 1, 0}}, Plane<T>{{0, 0, 5}, {0, 0, 1}}).contact, Contact::coplanar);
  auto h = intersect_fma(Ray<T>{{0, 0, 0}, {1, 1, 2}}, Plane<T>{{0, 0, 5}, {0, 0, 1}});
  EXPECT_EQ(h.contact, Contact::hit);
  EXPECT_EQ(h.t, T(2.5));
  h = intersect_fma(Ray<T>{{0, 0, 0}, {1, 1, -2}}, Plane<T>{{0, 0, 5}, {0, 0, 1}});
  EXPECT_EQ(h.contact, Contact::behind);
  EXPECT_EQ(h.t, T(-2.5));
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 0}, {1, 1, 2}}, Plane<T>{{0, 0, 5}, {0, 0, 0}}).contact, Contact::degenerate);
}

/// The compensated helpers of float_util.h: error-free products and sums, Dot2 accuracy.
TEST(CompensatedDot, ErrorFreeTransformations) {
  const double a = 1.0 + 0x1p-30, b = 1.0 - 0x1p-30;
  const TwoTerm<double> p = two_prod(a, b);
  EXPECT_EQ(p.hi, 1.0);  // 1 - 2^-60 rounds to 1
  EXPECT_EQ(p.lo, -0x1p-60);
  const TwoTerm<double> s = two_sum(1.0, 0x1p-60);
  EXPECT_EQ(s.hi, 1.0);
  EXPECT_EQ(s.lo, 0x1p-60);
  // (1 + 2^-30)(1 - 2^-30) - 1 = -2^-60: plain evaluation gives 0, Dot2 gives it exactly.
  EXPECT_EQ(compensated_dot3(a, b, -1.0, 1.0, 0.0, 0.0), -0x1p-60);
  EXPECT_EQ(a * b + -1.0 * 1.0, 0.0);
}

/// A direction tilted out of the plane by a few ulps: d . n cancels, the FMA form keeps its sign.
TEST(PlaneFma, NearParallelKeepsTheSign) {
  const float e = 0x1p-12f;
  const Plane<float> pl{{0, 0, 1}, {1 + e, 1 - e, 0}};
  const Ray<float> ray{{0, 0, 0}, {1 + e, -(1 - e), 1}};
  // d . n = (1+e)^2 - (1-e)^2 = 4e exactly; in plain float (1+e)^2 rounds (its e^2 bit is lost).
  EXPECT_EQ(dot_fma(ray.d, pl.normal), 4 * e);
}
