#include "rayproof/disk_fma.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T> class DiskFmaTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(DiskFmaTest, Scalars);

TYPED_TEST(DiskFmaTest, WorkedExamples) {
  using T = TypeParam;
  const Disk<T> dk{{0, 0, 5}, {0, 0, 1}, 5};
  auto h = intersect_fma(Ray<T>{{0, 0, 0}, {0, 0, 1}}, dk);
  EXPECT_EQ(h.contact, Contact::hit);
  EXPECT_EQ(h.t, T(5));
  // (3, 4) on a radius-5 rim, exactly.
  h = intersect_fma(Ray<T>{{3, 4, 0}, {0, 0, 1}}, dk);
  EXPECT_EQ(h.contact, Contact::rim);
  EXPECT_EQ(intersect_fma(Ray<T>{{3, 4.5, 0}, {0, 0, 1}}, dk).contact, Contact::miss);
  EXPECT_EQ(intersect_fma(Ray<T>{{3, 4, 0}, {0, 0, -1}}, dk).contact, Contact::behind);
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 0}, {1, 0, 0}}, dk).contact, Contact::parallel);
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 5}, {1, 0, 0}}, dk).contact, Contact::coplanar);
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Disk<T>{{0, 0, 5}, {0, 0, 1}, 0}).contact, Contact::degenerate);
  EXPECT_EQ(intersect_fma(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Disk<T>{{0, 0, 5}, {0, 0, 1}, -1}).contact, Contact::invalid);
}
