#include "rayproof/box.h"

#include <gtest/gtest.h>

#include <random>

using namespace rayproof;

template <class T> class BoxTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(BoxTest, Scalars);

TYPED_TEST(BoxTest, WorkedExample) {
  using T = TypeParam;
  const Ray<T> ray{{-3, 4, 5}, {1, -1, -2}};
  const auto h = intersect(ray, Box<T>{{-2, -2, -2}, {2, 2, 2}});
  ASSERT_EQ(h.contact, Contact::hit);
  EXPECT_EQ(h.t, T(2));
  EXPECT_EQ(h.t2, T(3.5));
  EXPECT_EQ(ray.at(h.t), (Vec3<T>{-1, 2, 1}));
  EXPECT_EQ(ray.at(h.t2), (Vec3<T>{0.5, 0.5, -2}));
}

TYPED_TEST(BoxTest, GrazeInsideBehindMiss) {
  using T = TypeParam;
  const Box<T> b{{0, 0, 0}, {1, 1, 1}};
  const auto corner = intersect(Ray<T>{{-1, 0, 1}, {1, 1, 0}}, b);  // touches the corner (0,1,1)
  EXPECT_EQ(corner.contact, Contact::graze);
  EXPECT_EQ(corner.t, T(1));
  EXPECT_EQ(intersect(Ray<T>{{0.5, 0.5, 0.5}, {1, 2, 3}}, b).contact, Contact::inside);
  EXPECT_EQ(intersect(Ray<T>{{2, 2, 2}, {1, 1, 1}}, b).contact, Contact::behind);
  EXPECT_EQ(intersect(Ray<T>{{2, 2, 2}, {1, 0, 0}}, b).contact, Contact::miss);
}

TYPED_TEST(BoxTest, SignedZeroDirectionOnSlabPlane) {
  using T = TypeParam;
  const Box<T> b{{0, 0, 0}, {1, 1, 1}};
  // Origin exactly on the x = 0 slab plane with d.x = +0 and -0: no 0 * inf NaN, the face is hit.
  for (T dx : {T(0), -T(0)}) {
    const auto h = intersect(Ray<T>{{0, 0.5, -1}, {dx, 0, 1}}, b);
    EXPECT_EQ(h.contact, Contact::hit);
    EXPECT_EQ(h.t, T(1));
    EXPECT_EQ(h.t2, T(2));
  }
}

TYPED_TEST(BoxTest, FlatBoxAndInvalid) {
  using T = TypeParam;
  const auto flat = intersect(Ray<T>{{0.5, 0.5, -1}, {0, 0, 1}}, Box<T>{{0, 0, 0}, {1, 1, 0}});
  EXPECT_EQ(flat.contact, Contact::graze);
  EXPECT_EQ(flat.t, T(1));
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {0, 0, 1}}, Box<T>{{1, 0, 0}, {0, 1, 1}}).contact, Contact::invalid);
}

TYPED_TEST(BoxTest, EntryNotAfterExitOnHits) {
  using T = TypeParam;
  std::mt19937 rng(3);
  std::uniform_real_distribution<T> u(-4, 4);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    Vec3<T> a{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    const Box<T> b{{std::min(a.x, c.x), std::min(a.y, c.y), std::min(a.z, c.z)},
                   {std::max(a.x, c.x), std::max(a.y, c.y), std::max(a.z, c.z)}};
    const auto h = intersect(Ray<T>{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}}, b);
    if (is_hit(h.contact) || h.contact == Contact::behind) {
      EXPECT_LE(h.t, h.t2);
      ++hits;
    }
  }
  EXPECT_GT(hits, 500);
}
