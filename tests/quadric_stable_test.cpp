#include "rayproof/quadric_stable.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T> class QuadricStableTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(QuadricStableTest, Scalars);

TYPED_TEST(QuadricStableTest, WorkedExamples) {
  using T = TypeParam;
  const T eps = std::numeric_limits<T>::epsilon();
  // docs/cases.md: ellipsoid 0 0 0 1 1 0 2 2 0 2 1 2 -> hit 2 -+ sqrt(4/5).
  auto h = intersect_stable(Ray<T>{{0, 0, 0}, {1, 1, 0}}, Ellipsoid<T>{{2, 2, 0}, {2, 1, 2}});
  EXPECT_EQ(h.contact, Contact::hit);
  EXPECT_NEAR(h.t, T(1.105572809000084), T(4) * eps);
  EXPECT_NEAR(h.t2, T(2.8944271909999157), T(8) * eps);
  // Sphere at distance 5, radius 1: t = 4, 6; inside from the centre; behind; tangent; miss.
  h = intersect_stable(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Sphere<T>{{0, 0, 5}, 1});
  EXPECT_EQ(h.contact, Contact::hit);
  EXPECT_EQ(h.t, T(4));
  EXPECT_EQ(h.t2, T(6));
  h = intersect_stable(Ray<T>{{0, 0, 5}, {0, 0, 2}}, Sphere<T>{{0, 0, 5}, 1});
  EXPECT_EQ(h.contact, Contact::inside);
  EXPECT_EQ(h.t, T(-0.5));
  EXPECT_EQ(h.t2, T(0.5));
  EXPECT_EQ(intersect_stable(Ray<T>{{0, 0, 0}, {0, 0, -1}}, Sphere<T>{{0, 0, 5}, 1}).contact, Contact::behind);
  h = intersect_stable(Ray<T>{{1, 0, 0}, {0, 0, 1}}, Sphere<T>{{0, 0, 5}, 1});
  EXPECT_EQ(h.contact, Contact::tangent);
  EXPECT_EQ(h.t, T(5));
  EXPECT_EQ(intersect_stable(Ray<T>{{2, 0, 0}, {0, 0, 1}}, Sphere<T>{{0, 0, 5}, 1}).contact, Contact::miss);
  EXPECT_EQ(intersect_stable(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Sphere<T>{{0, 0, 5}, 0}).contact, Contact::degenerate);
  EXPECT_EQ(intersect_stable(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Sphere<T>{{0, 0, 5}, -1}).contact, Contact::invalid);
  EXPECT_EQ(intersect_stable(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Ellipsoid<T>{{0, 0, 5}, {1, 0, 1}}).contact,
            Contact::degenerate);
}

/// RT Gems ch. 7's motivating case: a small sphere far away. The textbook b^2 - 4ac loses the
/// discriminant; the stable form keeps the near root accurate.
TEST(QuadricStable, SmallFarSphereKeepsTheNearRoot) {
  const float r = 1.0f, dist = 1.0e4f;
  const auto h = intersect_stable(Ray<float>{{0, 0, 0}, {0, 0, 1}}, Sphere<float>{{0, 0.5f, dist}, r});
  ASSERT_EQ(h.contact, Contact::hit);
  const double exact = double(dist) - std::sqrt(1.0 - 0.25);
  EXPECT_NEAR(h.t, exact, 2e-3);
  EXPECT_LE(h.t, h.t2);
}
