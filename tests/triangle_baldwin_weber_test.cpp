#include "rayproof/triangle_baldwin_weber.h"

#include <gtest/gtest.h>

using namespace rayproof;

template <class T>
TriangleHit<T> bw(std::initializer_list<double> v) {
  std::vector<T> a;
  for (double x : v) a.push_back(T(x));
  return intersect_baldwin_weber(Ray<T>{{a[0], a[1], a[2]}, {a[3], a[4], a[5]}},
                                 Triangle<T>{{a[6], a[7], a[8]}, {a[9], a[10], a[11]}, {a[12], a[13], a[14]}});
}

template <class T> class BaldwinWeberTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(BaldwinWeberTest, Scalars);

TYPED_TEST(BaldwinWeberTest, WorkedExamples) {
  using T = TypeParam;
  auto h = bw<T>({0, 0, 0, 1, 1, 1, 2, 4, 2, 5, -7, -1, 0, -9, 4});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_NEAR(h.t, T(2), T(16) * std::numeric_limits<T>::epsilon());
  h = bw<T>({0, 0, 0, 0, 0, 1, -1, -1, 5, 1, -1, 5, 0, 1, 5});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_EQ(h.t, T(5));
  h = bw<T>({0.25, 0.25, 0, 0, 0, -1, 0, 0, -2, 1, 0, -2, 0, 1, -2});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_EQ(h.b1, T(0.25));
  EXPECT_EQ(h.b2, T(0.25));
  h = bw<T>({0, 0, 1, 1, 1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4});
  EXPECT_EQ(h.contact, Contact::coplanar);
  EXPECT_EQ(h.t, T(3));
  EXPECT_EQ(bw<T>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::parallel);
  EXPECT_EQ(bw<T>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 2, 0, 5}).contact, Contact::degenerate);
  EXPECT_EQ(bw<T>({0, 0, 0, 0, 0, 1, 2, 2, 5, 3, 2, 5, 2, 3, 5}).contact, Contact::miss);
  EXPECT_EQ(bw<T>({0, 0, 0, 0, 0, -1, -1, -1, 5, 1, -1, 5, 0, 1, 5}).contact, Contact::behind);
}

TYPED_TEST(BaldwinWeberTest, EveryDominantAxis) {
  using T = TypeParam;
  // The same unit triangle facing x, y and z; a ray along the normal through its centroid.
  const Vec3<T> q[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int k = 0; k < 3; ++k) {
    auto rot = [k](Vec3<T> p) { return Vec3<T>{p[(3 - k) % 3], p[(4 - k) % 3], p[(5 - k) % 3]}; };
    const Triangle<T> tri{rot(q[0]), rot(q[1]), rot(q[2])};
    const Vec3<T> n = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    const Vec3<T> centroid = (tri.p0 + tri.p1 + tri.p2) / T(3);
    const auto h = intersect_baldwin_weber(Ray<T>{centroid + T(2) * n, -n}, tri);
    EXPECT_EQ(h.contact, Contact::interior) << k;
    EXPECT_NEAR(h.t, T(2), T(4) * std::numeric_limits<T>::epsilon()) << k;
  }
}
