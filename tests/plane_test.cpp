#include "rayproof/plane.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T> class PlaneTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(PlaneTest, Scalars);

TYPED_TEST(PlaneTest, WorkedExamples) {
  using T = TypeParam;
  const Plane<T> z5{{0, 0, 5}, {0, 0, 1}};
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {1, 1, 0}}, z5).contact, Contact::parallel);
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 5}, {1, 1, 0}}, z5).contact, Contact::coplanar);
  const auto behind = intersect(Ray<T>{{0, 0, 0}, {0, 0, -1}}, z5);
  EXPECT_EQ(behind.contact, Contact::behind);
  EXPECT_EQ(behind.t, T(-5));
  const auto hit = intersect(Ray<T>{{0, 0, 0}, {0, 0, 2}}, z5);
  EXPECT_EQ(hit.contact, Contact::hit);
  EXPECT_EQ(hit.t, T(2.5));
}

TYPED_TEST(PlaneTest, BadInputIsAClassNotACrash) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {0, 0, 0}}, Plane<T>{{0, 0, 5}, {0, 0, 1}}).contact, Contact::invalid);
  EXPECT_EQ(intersect(Ray<T>{{0, nan, 0}, {0, 0, 1}}, Plane<T>{{0, 0, 5}, {0, 0, 1}}).contact, Contact::invalid);
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Plane<T>{{0, 0, 5}, {0, 0, 0}}).contact, Contact::degenerate);
}

TYPED_TEST(PlaneTest, OriginOnPlaneHitsAtZero) {
  using T = TypeParam;
  const auto h = intersect(Ray<T>{{1, 2, 5}, {0, 1, -1}}, Plane<T>{{0, 0, 5}, {0, 0, 3}});
  EXPECT_EQ(h.contact, Contact::hit);
  EXPECT_EQ(h.t, T(0));
}
