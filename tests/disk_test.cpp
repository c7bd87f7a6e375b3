#include "rayproof/disk.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T> class DiskTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(DiskTest, Scalars);

TYPED_TEST(DiskTest, Classes) {
  using T = TypeParam;
  const Disk<T> d{{0, 0, 0}, {0, 0, 2}, 5};
  const auto hit = intersect(Ray<T>{{1, 1, 4}, {0, 0, -2}}, d);
  EXPECT_EQ(hit.contact, Contact::hit);
  EXPECT_EQ(hit.t, T(2));
  const auto rim = intersect(Ray<T>{{3, 4, 5}, {0, 0, -1}}, d);  // plane point (3,4,0), |p| = 5
  EXPECT_EQ(rim.contact, Contact::rim);
  EXPECT_EQ(rim.t, T(5));
  EXPECT_EQ(intersect(Ray<T>{{3, 5, 5}, {0, 0, -1}}, d).contact, Contact::miss);
  EXPECT_EQ(intersect(Ray<T>{{3, 5, 5}, {0, 0, 1}}, d).contact, Contact::miss);  // outside beats behind
  const auto behind = intersect(Ray<T>{{1, 1, 4}, {0, 0, 1}}, d);
  EXPECT_EQ(behind.contact, Contact::behind);
  EXPECT_EQ(behind.t, T(-4));
  EXPECT_EQ(intersect(Ray<T>{{1, 1, 4}, {1, 0, 0}}, d).contact, Contact::parallel);
  EXPECT_EQ(intersect(Ray<T>{{1, 1, 0}, {1, 0, 0}}, d).contact, Contact::coplanar);
  EXPECT_EQ(intersect(Ray<T>{{1, 1, 4}, {0, 0, 1}}, Disk<T>{{0, 0, 0}, {0, 0, 0}, 1}).contact, Contact::degenerate);
  EXPECT_EQ(intersect(Ray<T>{{1, 1, 4}, {0, 0, 1}}, Disk<T>{{0, 0, 0}, {0, 0, 1}, -1}).contact, Contact::invalid);
}
