#include "rayproof/triangle_plucker.h"

#include <gtest/gtest.h>

#include <random>

using namespace rayproof;

template <class T>
TriangleHit<T> pl(std::initializer_list<double> v) {
  std::vector<T> a;
  for (double x : v) a.push_back(T(x));
  return intersect_plucker(Ray<T>{{a[0], a[1], a[2]}, {a[3], a[4], a[5]}},
                           Triangle<T>{{a[6], a[7], a[8]}, {a[9], a[10], a[11]}, {a[12], a[13], a[14]}});
}

template <class T> class PluckerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(PluckerTest, Scalars);

TYPED_TEST(PluckerTest, WorkedExamples) {
  using T = TypeParam;
  auto h = pl<T>({0, 0, 0, 1, 1, 1, 2, 4, 2, 5, -7, -1, 0, -9, 4});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_NEAR(h.t, T(2), T(16) * std::numeric_limits<T>::epsilon());
  h = pl<T>({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 7, -1, 0, 9, -4});
  EXPECT_EQ(h.contact, Contact::vertex);
  EXPECT_EQ(h.t, T(2));
  h = pl<T>({0, 0, 0, 0, 0, 1, -1, 0, 5, 1, 0, 5, 0, 1, 5});
  EXPECT_EQ(h.contact, Contact::edge);
  EXPECT_EQ(h.b2, T(0));
  EXPECT_EQ(pl<T>({0, 0, 1, 1, 1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4}).contact, Contact::coplanar);
  EXPECT_EQ(pl<T>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::parallel);
  EXPECT_EQ(pl<T>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 2, 0, 5}).contact, Contact::degenerate);
  EXPECT_EQ(pl<T>({0, 0, 0, 0, 0, -1, -1, -1, 5, 1, -1, 5, 0, 1, 5}).contact, Contact::behind);
}

TYPED_TEST(PluckerTest, SharedEdgeValuesAreExactNegations) {
  using T = TypeParam;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3<T> d{T(u(rng)), T(u(rng)), T(u(rng))}, a{T(u(rng)), T(u(rng)), T(u(rng))}, b{T(u(rng)), T(u(rng)), T(u(rng))};
    EXPECT_EQ(detail::plucker_edge(d, a, b), -detail::plucker_edge(d, b, a));
  }
}
